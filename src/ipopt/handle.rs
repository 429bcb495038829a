//! The owning handle of one C `IpoptProblem`: creation, options, solve, and `Drop` that
//! frees it. Used only while the global solve lock is held (see `solver.rs`).

use std::ffi::{CString, c_void};
use std::ptr::NonNull;

use super::callbacks::{self, Context};
use super::compat::{self, Index, Int};
use super::options::known_integer;
use super::sys;
use super::{Nlp, OptionValue, Scaling};

/// One Ipopt problem, freed on drop. Not `Send`: it stays on the thread holding the lock.
pub(super) struct Handle {
    raw: NonNull<sys::IpoptProblemInfo>,
}

/// The bounds and sizes `CreateIpoptProblem` copies.
pub(super) struct Definition<'a> {
    /// Variable lower bounds (length n).
    pub x_lower: &'a [f64],
    /// Variable upper bounds (length n).
    pub x_upper: &'a [f64],
    /// Constraint lower bounds (length m).
    pub g_lower: &'a [f64],
    /// Constraint upper bounds (length m).
    pub g_upper: &'a [f64],
    /// Jacobian nonzeros.
    pub jacobian_nnz: usize,
    /// Hessian nonzeros (0 without a Hessian).
    pub hessian_nnz: usize,
    /// The problem's own scaling factors, checked against n and m.
    pub scaling: Option<&'a Scaling>,
}

/// What `IpoptSolve` wrote back.
pub(super) struct Outputs {
    /// Final x (the starting point if Ipopt never finalised).
    pub x: Vec<f64>,
    /// Constraint values at x.
    pub g: Vec<f64>,
    /// Objective at x (NaN if Ipopt did not write it).
    pub objective: f64,
    /// The final multipliers.
    pub multipliers: Multipliers,
    /// Ipopt's raw return code.
    pub code: i32,
}

/// `value` as Ipopt's `Index`, or `None` if it does not fit.
fn index(value: usize) -> Option<Index> {
    Index::try_from(value).ok()
}

impl Handle {
    /// Creates the C problem for `P` (its trampolines as callbacks), or `None` if a size does
    /// not fit Ipopt's 32-bit indices or Ipopt returns null.
    pub fn create<P: Nlp + ?Sized>(def: &Definition<'_>) -> Option<Handle> {
        let n = index(def.x_lower.len())?;
        let m = index(def.g_lower.len())?;
        if def.x_upper.len() != def.x_lower.len() || def.g_upper.len() != def.g_lower.len() {
            return None;
        }
        let nele_jac = index(def.jacobian_nnz)?;
        let nele_hess = index(def.hessian_nnz)?;
        // SAFETY: the four bound arrays hold n, n, m and m values (checked above); Ipopt
        // copies them and never writes through these pointers despite the `*mut` in its
        // signature. The callbacks are `extern "C"` functions with Ipopt's exact signatures.
        let raw = unsafe {
            sys::CreateIpoptProblem(
                n,
                def.x_lower.as_ptr().cast_mut(),
                def.x_upper.as_ptr().cast_mut(),
                m,
                def.g_lower.as_ptr().cast_mut(),
                def.g_upper.as_ptr().cast_mut(),
                nele_jac,
                nele_hess,
                0, // C-style (zero-based) indices
                Some(callbacks::eval_f::<P>),
                Some(callbacks::eval_g::<P>),
                Some(callbacks::eval_grad_f::<P>),
                Some(callbacks::eval_jac_g::<P>),
                Some(callbacks::eval_h::<P>),
            )
        };
        let handle = Handle {
            raw: NonNull::new(raw)?,
        };
        // SAFETY: live problem; the callback has Ipopt's exact signature.
        unsafe {
            sys::SetIntermediateCallback(handle.raw.as_ptr(), Some(callbacks::intermediate::<P>))
        };
        match def.scaling {
            Some(scaling) => handle.with_scaling(scaling, def.x_lower.len(), def.g_lower.len()),
            None => Some(handle),
        }
    }

    /// Hands the problem's scaling to Ipopt (`None` if its sizes are not n and m, or Ipopt
    /// refuses it; the handle is then dropped, which frees the problem).
    fn with_scaling(self, scaling: &Scaling, n: usize, m: usize) -> Option<Handle> {
        scaling.check(n, m).ok()?;
        // A null pointer leaves that part unscaled; so does an empty row vector (m = 0).
        let pointer = |factors: &Option<Vec<f64>>| match factors {
            Some(f) if !f.is_empty() => f.as_ptr().cast_mut(),
            _ => std::ptr::null_mut(),
        };
        // SAFETY: live problem with n variables and m rows; the factor arrays hold n and m
        // values (checked above) or are null. Ipopt (3.11 to 3.14) copies them into the
        // problem before returning and never writes through the pointers despite the
        // `*mut` in its signature.
        let ok = unsafe {
            sys::SetIpoptProblemScaling(
                self.raw.as_ptr(),
                scaling.objective,
                pointer(&scaling.variables),
                pointer(&scaling.constraints),
            )
        };
        compat::is_true(ok).then_some(self)
    }

    /// Sets one option; an integer for a number option (or an integral number for an integer
    /// option) is retried as the other type, or offered as the option's own type first when
    /// vito knows it ([`known_integer`]: then Ipopt prints no type complaint). Returns the
    /// value Ipopt accepted, or `None`.
    ///
    /// Ipopt prints its reason for a rejection on stdout (its console journal).
    pub fn set_option(&mut self, name: &str, value: &OptionValue) -> Option<OptionValue> {
        let known = known_integer(name);
        let name = CString::new(name).ok()?;
        match value {
            OptionValue::Str(s) => {
                let text = CString::new(s.as_str()).ok()?;
                // SAFETY: live problem; two NUL-terminated strings that Ipopt only reads
                // (it copies them into std::string).
                let ok = unsafe {
                    sys::AddIpoptStrOption(
                        self.raw.as_ptr(),
                        name.as_ptr().cast_mut(),
                        text.as_ptr().cast_mut(),
                    )
                };
                compat::is_true(ok).then(|| value.clone())
            }
            OptionValue::Num(x) => {
                let integral = x.fract() == 0.0 && x.abs() <= f64::from(Int::MAX);
                let as_int = || OptionValue::Int(*x as i64);
                if integral && known == Some(true) && self.add_int(&name, *x as Int) {
                    return Some(as_int());
                }
                if self.add_num(&name, *x) {
                    return Some(value.clone());
                }
                (integral && known != Some(true) && self.add_int(&name, *x as Int)).then(as_int)
            }
            OptionValue::Int(i) => {
                let as_num = OptionValue::Num(*i as f64);
                if known == Some(false) && self.add_num(&name, *i as f64) {
                    return Some(as_num);
                }
                if let Ok(small) = Int::try_from(*i)
                    && self.add_int(&name, small)
                {
                    return Some(value.clone());
                }
                (known != Some(false) && self.add_num(&name, *i as f64)).then_some(as_num)
            }
        }
    }

    fn add_num(&mut self, name: &CString, value: f64) -> bool {
        // SAFETY: live problem; a NUL-terminated name that Ipopt only reads.
        compat::is_true(unsafe {
            sys::AddIpoptNumOption(self.raw.as_ptr(), name.as_ptr().cast_mut(), value)
        })
    }

    fn add_int(&mut self, name: &CString, value: Int) -> bool {
        // SAFETY: live problem; a NUL-terminated name that Ipopt only reads.
        compat::is_true(unsafe {
            sys::AddIpoptIntOption(self.raw.as_ptr(), name.as_ptr().cast_mut(), value)
        })
    }

    /// Runs `IpoptSolve` from `x0` with `ctx` as the callbacks' user data.
    pub fn solve<P: Nlp + ?Sized>(
        &mut self,
        x0: Vec<f64>,
        m: usize,
        start: Option<&Multipliers>,
        ctx: &mut Context<'_, P>,
    ) -> Outputs {
        let n = x0.len();
        let mut out = Outputs {
            x: x0,
            g: vec![0.0; m],
            objective: f64::NAN,
            multipliers: start.cloned().unwrap_or_else(|| Multipliers {
                g: vec![0.0; m],
                x_lower: vec![0.0; n],
                x_upper: vec![0.0; n],
            }),
            code: 0,
        };
        let user_data = (ctx as *mut Context<'_, P>).cast::<c_void>();
        // SAFETY: live problem created for `P` with n variables and m constraints (the
        // caller passes the same sizes); every array has the length Ipopt writes (n or m);
        // `user_data` points at `ctx`, exclusively borrowed for the whole call, which is what
        // the trampolines cast it back to.
        let status = unsafe {
            sys::IpoptSolve(
                self.raw.as_ptr(),
                out.x.as_mut_ptr(),
                out.g.as_mut_ptr(),
                &mut out.objective,
                out.multipliers.g.as_mut_ptr(),
                out.multipliers.x_lower.as_mut_ptr(),
                out.multipliers.x_upper.as_mut_ptr(),
                user_data,
            )
        };
        out.code = status.0;
        out
    }
}

impl Drop for Handle {
    fn drop(&mut self) {
        // SAFETY: raw came from CreateIpoptProblem, is freed exactly once, here.
        unsafe { sys::FreeIpoptProblem(self.raw.as_ptr()) };
    }
}

/// Multipliers to start a solve from (Ipopt's convention, as in [`SolveReport`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Multipliers {
    /// Constraint multipliers (length m).
    pub g: Vec<f64>,
    /// Lower-bound multipliers (length n).
    pub x_lower: Vec<f64>,
    /// Upper-bound multipliers (length n).
    pub x_upper: Vec<f64>,
}
