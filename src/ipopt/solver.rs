//! The safe solver: options, one solve at a time per process, and the solve report.

use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::Instant;

use super::callbacks::{Context, panic_message};
use super::compat::Index;
use super::handle::{Definition, Handle, Multipliers};
use super::options::{FORCED, check_allowed, default_options};
use super::{IpoptError, Nlp, OptionValue, Scaling, Status};

/// Serialises every use of Ipopt in the process: Debian's Ipopt 3.11 with sequential MUMPS
/// crashes, or exits with status 0, when two solves run at once; 3.14 with the MPI build of
/// MUMPS is no more re-entrant (see `tests/ipopt.rs`).
static SOLVE_LOCK: Mutex<()> = Mutex::new(());

/// Threads waiting for [`SOLVE_LOCK`].
static WAITING: AtomicUsize = AtomicUsize::new(0);

/// Whether a thread is waiting for this process's Ipopt lock (one solve at a time): a solve
/// that waits on something else (e.g. a caller's progress display) should go on instead,
/// since what it waits for may be that thread.
pub fn others_waiting_for_ipopt() -> bool {
    WAITING.load(Ordering::SeqCst) > 0
}

thread_local! {
    /// Whether this thread holds [`SOLVE_LOCK`] (a callback calling back into the solver
    /// would otherwise deadlock on it).
    static HOLDS_LOCK: Cell<bool> = const { Cell::new(false) };
}

/// Exclusive use of Ipopt; released on drop.
struct IpoptLock {
    _guard: MutexGuard<'static, ()>,
}

impl IpoptLock {
    /// Waits for the lock. A poisoned lock is taken over (the panic that poisoned it left no
    /// Ipopt state behind: every problem is freed by its handle's `Drop`).
    fn acquire() -> Result<IpoptLock, IpoptError> {
        if HOLDS_LOCK.get() {
            return Err(IpoptError::NestedSolve);
        }
        WAITING.fetch_add(1, Ordering::SeqCst);
        let guard = SOLVE_LOCK.lock().unwrap_or_else(PoisonError::into_inner);
        WAITING.fetch_sub(1, Ordering::SeqCst);
        HOLDS_LOCK.set(true);
        Ok(IpoptLock { _guard: guard })
    }
}

impl Drop for IpoptLock {
    fn drop(&mut self) {
        HOLDS_LOCK.set(false);
    }
}

/// The result of one solve.
///
/// `x`, `g` and the multipliers are Ipopt's final iterate, also after a stop or a failure
/// (for an error at the starting point `x` is the starting point). Multipliers follow
/// Ipopt's convention: the Lagrangian is f(x) + mult_gᵀ g(x) − mult_x_lowerᵀ(x − x_L) +
/// mult_x_upperᵀ(x − x_U), with both bound multipliers ≥ 0.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveReport {
    /// How the solve ended.
    pub status: Status,
    /// Final point (length n).
    pub x: Vec<f64>,
    /// Constraint values at `x` (length m).
    pub g: Vec<f64>,
    /// Objective at `x`; NaN when Ipopt stopped before evaluating it.
    pub objective: f64,
    /// Constraint multipliers (length m).
    pub mult_g: Vec<f64>,
    /// Multipliers of the variable lower bounds (length n).
    pub mult_x_lower: Vec<f64>,
    /// Multipliers of the variable upper bounds (length n).
    pub mult_x_upper: Vec<f64>,
    /// Iterations taken (the last intermediate callback's count).
    pub iterations: usize,
    /// Evaluations refused because the problem wrote a NaN or Inf (Ipopt then backtracks).
    pub evaluation_errors: usize,
    /// Wall time of the solve in seconds, from problem setup to Ipopt's return (waiting for
    /// another thread's solve is not included).
    pub wall_time_s: f64,
    /// Seconds spent in the problem's methods (all callbacks and the setup queries).
    pub callback_time_s: f64,
    /// Seconds spent inside Ipopt: `wall_time_s − callback_time_s`.
    pub ipopt_time_s: f64,
    /// `callback_time_s` by callback (the setup queries not included).
    pub callback_split: CallbackSplit,
}

/// Calls and seconds of one kind of callback.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CallbackStat {
    pub calls: usize,
    pub seconds: f64,
}

/// Where the callback time went: Ipopt asks f and g at every trial point of its line
/// search, ∇f, the Jacobian and the Hessian once per iteration.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CallbackSplit {
    pub objective: CallbackStat,
    pub gradient: CallbackStat,
    pub constraints: CallbackStat,
    pub jacobian: CallbackStat,
    pub hessian: CallbackStat,
}

impl CallbackSplit {
    /// The entries with their callback names (`objective`, `gradient`, `constraints`,
    /// `jacobian`, `hessian`).
    pub fn entries(&self) -> [(&'static str, CallbackStat); 5] {
        [
            ("objective", self.objective),
            ("gradient", self.gradient),
            ("constraints", self.constraints),
            ("jacobian", self.jacobian),
            ("hessian", self.hessian),
        ]
    }

    /// One line, e.g. `objective 130 × 0.020 ms, …, hessian 88 × 0.31 ms` (calls × mean).
    pub fn describe(&self) -> String {
        self.entries()
            .iter()
            .map(|(name, s)| {
                let mean_ms = if s.calls == 0 {
                    0.0
                } else {
                    1e3 * s.seconds / s.calls as f64
                };
                format!("{name} {} × {mean_ms:.3} ms", s.calls)
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The sum of two splits (the solves of a slack continuation).
    pub fn plus(&self, other: &CallbackSplit) -> CallbackSplit {
        let add = |a: CallbackStat, b: CallbackStat| CallbackStat {
            calls: a.calls + b.calls,
            seconds: a.seconds + b.seconds,
        };
        CallbackSplit {
            objective: add(self.objective, other.objective),
            gradient: add(self.gradient, other.gradient),
            constraints: add(self.constraints, other.constraints),
            jacobian: add(self.jacobian, other.jacobian),
            hessian: add(self.hessian, other.hessian),
        }
    }
}

/// Ipopt with vito's options: build one, adjust options, then solve any number of problems.
///
/// Only one solve runs at a time in a process; a second thread's `solve` waits for the
/// first. `set_option` checks the option with Ipopt at once, which also takes that lock.
#[derive(Debug, Clone)]
pub struct Solver {
    /// Options in the order they are applied; one entry per name.
    options: Vec<(String, OptionValue)>,
    cancel: Option<Arc<AtomicBool>>,
    /// The wall-clock instant after which the solve stops at its next iteration.
    deadline: Option<Instant>,
    /// Starting multipliers, read by Ipopt under `warm_start_init_point yes`.
    start_multipliers: Option<Multipliers>,
}

impl Default for Solver {
    fn default() -> Self {
        Solver::new()
    }
}

impl Solver {
    /// Solver with vito's defaults from vendor-config (embedded at compile time).
    ///
    /// The defaults are `vendor-config/ipopt-defaults.opt`: tol 1e-6, mu_strategy adaptive,
    /// max_iter 3000, linear_solver mumps, print_level 0. Every solve also sets
    /// `option_file_name ""` (no `ipopt.opt` is read from the working directory) and `sb yes`
    /// (no banner) first; both can be overridden with [`Solver::set_option`].
    pub fn new() -> Solver {
        Solver {
            options: default_options(),
            cancel: None,
            deadline: None,
            start_multipliers: None,
        }
    }

    /// Sets an Ipopt option for the following solves, replacing an earlier value.
    ///
    /// The option is checked by Ipopt right away: an unknown name, a wrong type or a value
    /// out of range is an [`IpoptError::InvalidOption`] naming it (Ipopt also prints its own
    /// reason on stdout). A `linear_solver` other than `mumps` is
    /// [`IpoptError::Refused`] before Ipopt sees it. An integer for a number option (and
    /// an integral number for an integer option) is converted.
    pub fn set_option(
        &mut self,
        name: &str,
        value: impl Into<OptionValue>,
    ) -> Result<(), IpoptError> {
        let value = value.into();
        check_allowed(name, &value)?;
        let invalid = |reason: &str| IpoptError::InvalidOption {
            name: name.to_string(),
            value: value.to_string(),
            reason: reason.to_string(),
        };
        if name.contains('\0') || matches!(&value, OptionValue::Str(s) if s.contains('\0')) {
            return Err(invalid("contains a NUL byte"));
        }
        let accepted = {
            let _lock = IpoptLock::acquire()?;
            let mut handle = Handle::create::<Unsolvable>(&Definition {
                x_lower: &[0.0],
                x_upper: &[1.0],
                g_lower: &[],
                g_upper: &[],
                jacobian_nnz: 0,
                hessian_nnz: 0,
                scaling: None,
            })
            .ok_or(IpoptError::CreateFailed)?;
            handle.set_option(name, &value)
        };
        let accepted = accepted.ok_or_else(|| {
            invalid(
                "Ipopt does not know this name, or the value has the wrong type or is out of \
                 range (Ipopt printed why above; its options are listed with \
                 `print_options_documentation yes`)",
            )
        })?;
        match self.options.iter_mut().find(|(n, _)| n == name) {
            Some(entry) => entry.1 = accepted,
            None => self.options.push((name.to_string(), accepted)),
        }
        Ok(())
    }

    /// The options the next solve applies after the forced ones, in order.
    pub fn options(&self) -> &[(String, OptionValue)] {
        &self.options
    }

    /// Multipliers for the following solves to start from. Ipopt reads them only under
    /// `warm_start_init_point yes`; multipliers of other lengths than the problem's are ignored.
    pub fn set_starting_multipliers(&mut self, multipliers: Multipliers) {
        self.start_multipliers = Some(multipliers);
    }

    /// Cancellation: when the flag becomes true the next intermediate callback stops the solve.
    ///
    /// The solve then ends with [`Status::UserRequestedStop`] and reports the current
    /// iterate. The flag is not reset by the solver.
    pub fn set_cancel_flag(&mut self, flag: Arc<AtomicBool>) {
        self.cancel = Some(flag);
    }

    /// A wall-time limit: the first intermediate callback after `deadline` stops the solve,
    /// which then ends with [`Status::MaximumWallTimeExceeded`] and reports the current
    /// iterate (as a cancel does; Ipopt 3.11 has no `max_wall_time` of its own).
    pub fn set_deadline(&mut self, deadline: Instant) {
        self.deadline = Some(deadline);
    }

    /// Solves `problem` from its initial point.
    ///
    /// Waits while another thread solves. Sizes, bounds, the starting point, the sparsity
    /// and the problem's [`Scaling`] are checked first ([`IpoptError::InvalidProblem`]); a
    /// panic in any method of `problem` stops the solve and becomes
    /// [`IpoptError::CallbackPanicked`]. Without `hessian_nnz` the solve uses
    /// `hessian_approximation limited-memory`; with [`Nlp::scaling`], `nlp_scaling_method
    /// user-scaling` unless the options set that name.
    pub fn solve<P: Nlp + ?Sized>(&mut self, problem: &mut P) -> Result<SolveReport, IpoptError> {
        let lock = IpoptLock::acquire()?;
        super::threads::pin_one_thread();
        let wall_start = Instant::now();
        let setup = catch_unwind(AssertUnwindSafe(|| Setup::query(problem)));
        let setup = match setup {
            Ok(result) => result?,
            Err(payload) => {
                return Err(IpoptError::CallbackPanicked {
                    callback: "problem setup (sizes, bounds, initial_point or structure)",
                    message: panic_message(payload.as_ref()),
                });
            }
        };
        let setup_time = wall_start.elapsed();

        let mut handle = Handle::create::<P>(&Definition {
            x_lower: &setup.x_lower,
            x_upper: &setup.x_upper,
            g_lower: &setup.g_lower,
            g_upper: &setup.g_upper,
            jacobian_nnz: setup.jacobian_rows.len(),
            hessian_nnz: setup.hessian_rows.len(),
            scaling: setup.scaling.as_ref(),
        })
        .ok_or(IpoptError::CreateFailed)?;
        let forced = FORCED
            .iter()
            .map(|&(name, value)| (name.to_string(), OptionValue::from(value)));
        let lbfgs = (!setup.has_hessian).then(|| {
            (
                "hessian_approximation".to_string(),
                OptionValue::from("limited-memory"),
            )
        });
        // The problem's own scaling is used unless the options choose a scaling method.
        let user_scaling = (setup.scaling.is_some()
            && !self.options.iter().any(|(n, _)| n == "nlp_scaling_method"))
        .then(|| {
            (
                "nlp_scaling_method".to_string(),
                OptionValue::from("user-scaling"),
            )
        });
        for (name, value) in forced
            .chain(user_scaling)
            .chain(self.options.iter().cloned())
            .chain(lbfgs)
        {
            check_allowed(&name, &value)?;
            if handle.set_option(&name, &value).is_none() {
                return Err(IpoptError::InvalidOption {
                    value: value.to_string(),
                    name,
                    reason: "Ipopt rejected it when the solve started".to_string(),
                });
            }
        }

        let m = setup.g_lower.len();
        let mut ctx = Context::new(problem, self.cancel.as_deref());
        ctx.deadline = self.deadline;
        ctx.jacobian_rows = setup.jacobian_rows;
        ctx.jacobian_cols = setup.jacobian_cols;
        ctx.hessian_rows = setup.hessian_rows;
        ctx.hessian_cols = setup.hessian_cols;
        ctx.has_hessian = setup.has_hessian;
        let n = setup.x0.len();
        let start = self
            .start_multipliers
            .as_ref()
            .filter(|w| w.g.len() == m && w.x_lower.len() == n && w.x_upper.len() == n);
        let out = handle.solve(setup.x0, m, start, &mut ctx);
        drop(handle);
        let wall_time = wall_start.elapsed();
        drop(lock);

        if let Some((callback, message)) = ctx.panic {
            return Err(IpoptError::CallbackPanicked { callback, message });
        }
        let status =
            Status::from_code(out.code).ok_or(IpoptError::UnknownStatus { code: out.code })?;
        let status = if ctx.timed_out && status == Status::UserRequestedStop {
            Status::MaximumWallTimeExceeded
        } else {
            status
        };
        let callback_time = (ctx.callback_time + setup_time).min(wall_time);
        Ok(SolveReport {
            status,
            x: out.x,
            g: out.g,
            objective: out.objective,
            mult_g: out.multipliers.g,
            mult_x_lower: out.multipliers.x_lower,
            mult_x_upper: out.multipliers.x_upper,
            iterations: ctx.iterations,
            evaluation_errors: ctx.evaluation_errors,
            wall_time_s: wall_time.as_secs_f64(),
            callback_time_s: callback_time.as_secs_f64(),
            ipopt_time_s: (wall_time - callback_time).as_secs_f64(),
            callback_split: ctx.callback_split,
        })
    }
}

/// The problem's structure and data, asked once and checked before Ipopt sees them.
struct Setup {
    x_lower: Vec<f64>,
    x_upper: Vec<f64>,
    g_lower: Vec<f64>,
    g_upper: Vec<f64>,
    x0: Vec<f64>,
    jacobian_rows: Vec<Index>,
    jacobian_cols: Vec<Index>,
    hessian_rows: Vec<Index>,
    hessian_cols: Vec<Index>,
    has_hessian: bool,
    scaling: Option<Scaling>,
}

fn invalid(what: String) -> IpoptError {
    IpoptError::InvalidProblem { what }
}

impl Setup {
    fn query<P: Nlp + ?Sized>(problem: &P) -> Result<Setup, IpoptError> {
        let n = problem.num_variables();
        let m = problem.num_constraints();
        let max = usize::try_from(Index::MAX).unwrap_or(usize::MAX);
        if n == 0 {
            return Err(invalid("the problem has no variables".to_string()));
        }
        if n > max || m > max {
            return Err(invalid(format!(
                "{n} variables and {m} constraints exceed Ipopt's indices"
            )));
        }
        let (mut x_lower, mut x_upper) = (vec![0.0; n], vec![0.0; n]);
        problem.variable_bounds(&mut x_lower, &mut x_upper);
        check_bounds("variable", &x_lower, &x_upper)?;
        let (mut g_lower, mut g_upper) = (vec![0.0; m], vec![0.0; m]);
        problem.constraint_bounds(&mut g_lower, &mut g_upper);
        check_bounds("constraint", &g_lower, &g_upper)?;
        let mut x0 = vec![0.0; n];
        problem.initial_point(&mut x0);
        if let Some(i) = x0.iter().position(|v| !v.is_finite()) {
            return Err(invalid(format!(
                "initial_point[{i}] = {} is not finite",
                x0[i]
            )));
        }

        let nnz = problem.jacobian_nnz();
        if nnz > max {
            return Err(invalid(format!(
                "{nnz} Jacobian nonzeros exceed Ipopt's indices"
            )));
        }
        let (mut rows, mut cols) = (vec![0; nnz], vec![0; nnz]);
        problem.jacobian_structure(&mut rows, &mut cols);
        let (jacobian_rows, jacobian_cols) = check_triplets("jacobian", &rows, &cols, m, n, false)?;

        let (hessian_rows, hessian_cols, has_hessian) = match problem.hessian_nnz() {
            Some(nnz) if nnz > max => {
                return Err(invalid(format!(
                    "{nnz} Hessian nonzeros exceed Ipopt's indices"
                )));
            }
            Some(nnz) => {
                let (mut rows, mut cols) = (vec![0; nnz], vec![0; nnz]);
                problem.hessian_structure(&mut rows, &mut cols);
                let (r, c) = check_triplets("hessian", &rows, &cols, n, n, true)?;
                (r, c, true)
            }
            None => (Vec::new(), Vec::new(), false),
        };
        let scaling = problem.scaling();
        if let Some(scaling) = &scaling {
            scaling.check(n, m).map_err(invalid)?;
        }
        Ok(Setup {
            x_lower,
            x_upper,
            g_lower,
            g_upper,
            x0,
            jacobian_rows,
            jacobian_cols,
            hessian_rows,
            hessian_cols,
            has_hessian,
            scaling,
        })
    }
}

/// Bounds must not be NaN and lower ≤ upper (±∞ means none).
fn check_bounds(kind: &str, lower: &[f64], upper: &[f64]) -> Result<(), IpoptError> {
    for (i, (&lo, &up)) in lower.iter().zip(upper).enumerate() {
        if lo.is_nan() || up.is_nan() || lo > up {
            return Err(invalid(format!(
                "{kind} {i} has bounds [{lo}, {up}]; need lower ≤ upper, no NaN"
            )));
        }
    }
    Ok(())
}

/// Triplet indices in range (and in the lower triangle when `lower_triangle`), as Ipopt's
/// `Index`.
fn check_triplets(
    kind: &str,
    rows: &[usize],
    cols: &[usize],
    num_rows: usize,
    num_cols: usize,
    lower_triangle: bool,
) -> Result<(Vec<Index>, Vec<Index>), IpoptError> {
    for (k, (&r, &c)) in rows.iter().zip(cols).enumerate() {
        if r >= num_rows || c >= num_cols {
            return Err(invalid(format!(
                "{kind}_structure entry {k} is ({r}, {c}), outside the {num_rows}×{num_cols} matrix"
            )));
        }
        if lower_triangle && c > r {
            return Err(invalid(format!(
                "{kind}_structure entry {k} is ({r}, {c}), above the diagonal; give the lower \
                 triangle (row ≥ col)"
            )));
        }
    }
    // In range of an Index because num_rows, num_cols ≤ Index::MAX (checked by the caller).
    let to_index = |v: &[usize]| v.iter().map(|&i| i as Index).collect();
    Ok((to_index(rows), to_index(cols)))
}

/// The one-variable problem behind the handle `set_option` creates to check an option with
/// Ipopt; it is never solved.
struct Unsolvable;

impl Nlp for Unsolvable {
    fn num_variables(&self) -> usize {
        1
    }
    fn num_constraints(&self) -> usize {
        0
    }
    fn variable_bounds(&self, _lower: &mut [f64], _upper: &mut [f64]) {}
    fn constraint_bounds(&self, _lower: &mut [f64], _upper: &mut [f64]) {}
    fn initial_point(&self, _x: &mut [f64]) {}
    fn objective(&mut self, _x: &[f64], _new_x: bool) -> f64 {
        f64::NAN
    }
    fn gradient(&mut self, _x: &[f64], _new_x: bool, _grad: &mut [f64]) {}
    fn constraints(&mut self, _x: &[f64], _new_x: bool, _g: &mut [f64]) {}
    fn jacobian_nnz(&self) -> usize {
        0
    }
    fn jacobian_structure(&self, _rows: &mut [usize], _cols: &mut [usize]) {}
    fn jacobian_values(&mut self, _x: &[f64], _new_x: bool, _values: &mut [f64]) {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipopt::sample::Quadratic;

    /// A thread that panicked while holding the lock poisons it; later solves must still run.
    #[test]
    fn poisoned_lock_does_not_block_later_solves() {
        let poisoner = std::thread::spawn(|| {
            let _guard = SOLVE_LOCK.lock();
            panic!("poisoning the solve lock on purpose");
        });
        assert!(poisoner.join().is_err());
        assert!(SOLVE_LOCK.is_poisoned());
        let report = Solver::new().solve(&mut Quadratic::default()).unwrap();
        assert_eq!(report.status, Status::SolveSucceeded);
        assert!((report.x[0] - 1.0).abs() < 1e-8, "x = {:?}", report.x);
    }

    #[test]
    fn triplets_out_of_range_name_the_entry() {
        let err = check_triplets("jacobian", &[0, 2], &[0, 0], 2, 3, false).unwrap_err();
        assert!(err.to_string().contains("entry 1 is (2, 0)"), "{err}");
        let err = check_triplets("hessian", &[1], &[1], 2, 2, true);
        assert_eq!(err.unwrap(), (vec![1], vec![1]));
        assert!(check_bounds("constraint", &[f64::NAN], &[1.0]).is_err());
        assert!(check_bounds("constraint", &[f64::NEG_INFINITY], &[f64::INFINITY]).is_ok());
    }
}
