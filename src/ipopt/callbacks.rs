//! The `extern "C"` trampolines Ipopt calls, one per callback, each forwarding to the
//! problem's [`Nlp`] method.
//!
//! Every body runs in [`guard`]: a panic is caught and kept (it must not unwind into C++),
//! a NaN or Inf in an output is reported to Ipopt as a failed evaluation (Ipopt backtracks,
//! or ends with `InvalidNumberDetected`), and the time spent is added up. After the first
//! panic every callback returns false at once, so Ipopt stops soon; `solve` then turns the
//! kept panic into an error.

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::compat::{Bool, FALSE, Index, Number, TRUE, is_true};
use super::sys::UserDataPtr;
use super::{IterationInfo, Nlp};

/// What `solve` shares with the trampolines through Ipopt's `user_data` pointer; it lives on
/// `solve`'s stack for the duration of `IpoptSolve` only.
pub(super) struct Context<'a, P: Nlp + ?Sized> {
    /// The problem being solved.
    pub problem: &'a mut P,
    /// Constraint Jacobian sparsity, validated, in Ipopt's index type.
    pub jacobian_rows: Vec<Index>,
    /// Columns matching `jacobian_rows`.
    pub jacobian_cols: Vec<Index>,
    /// Lower-triangle Hessian sparsity; empty when the problem has no Hessian.
    pub hessian_rows: Vec<Index>,
    /// Columns matching `hessian_rows`.
    pub hessian_cols: Vec<Index>,
    /// Whether the problem provides an exact Hessian.
    pub has_hessian: bool,
    /// Stops the solve at the next iteration when it becomes true.
    pub cancel: Option<&'a AtomicBool>,
    /// Sum of the time spent inside the trampolines.
    pub callback_time: Duration,
    /// The value callbacks' share of it, by callback.
    pub callback_split: super::CallbackSplit,
    /// Iteration count of the last intermediate callback.
    pub iterations: usize,
    /// Evaluations reported to Ipopt as failed because an output was NaN or Inf.
    pub evaluation_errors: usize,
    /// Whether the cancel flag stopped the solve.
    pub cancelled: bool,
    /// Stops the solve at the first iteration after this instant (a wall-time limit).
    pub deadline: Option<std::time::Instant>,
    /// Whether the deadline stopped the solve.
    pub timed_out: bool,
    /// The first panic: the `Nlp` method's name and the message.
    pub panic: Option<(&'static str, String)>,
}

impl<'a, P: Nlp + ?Sized> Context<'a, P> {
    /// A context with no time spent and nothing kept yet.
    pub fn new(problem: &'a mut P, cancel: Option<&'a AtomicBool>) -> Self {
        Context {
            problem,
            jacobian_rows: Vec::new(),
            jacobian_cols: Vec::new(),
            hessian_rows: Vec::new(),
            hessian_cols: Vec::new(),
            has_hessian: false,
            cancel,
            callback_time: Duration::ZERO,
            callback_split: super::CallbackSplit::default(),
            iterations: 0,
            evaluation_errors: 0,
            cancelled: false,
            deadline: None,
            timed_out: false,
            panic: None,
        }
    }
}

/// How a callback body ended.
enum Flow {
    /// Outputs written and finite.
    Continue,
    /// An output was NaN or Inf: an evaluation error for Ipopt.
    NonFinite,
    /// Ipopt's call did not match the problem (sizes); refuse it.
    Mismatch,
    /// The intermediate callback asks Ipopt to stop.
    Stop,
}

/// The panic payload as text.
pub(super) fn panic_message(payload: &(dyn Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(panic payload is not a string)".to_string())
}

/// Runs one callback body: skips it after an earlier panic, catches a panic, counts
/// non-finite outputs and adds the time spent.
fn guard<P: Nlp + ?Sized>(
    ctx: &mut Context<'_, P>,
    callback: &'static str,
    body: impl FnOnce(&mut Context<'_, P>) -> Flow,
) -> Bool {
    if ctx.panic.is_some() {
        return FALSE;
    }
    let start = Instant::now();
    let outcome = catch_unwind(AssertUnwindSafe(|| body(&mut *ctx)));
    let spent = start.elapsed();
    ctx.callback_time += spent;
    let split = &mut ctx.callback_split;
    let stat = match callback {
        "objective" => Some(&mut split.objective),
        "gradient" => Some(&mut split.gradient),
        "constraints" => Some(&mut split.constraints),
        "jacobian_values" => Some(&mut split.jacobian),
        "hessian_values" => Some(&mut split.hessian),
        _ => None,
    };
    if let Some(stat) = stat {
        stat.calls += 1;
        stat.seconds += spent.as_secs_f64();
    }
    match outcome {
        Ok(Flow::Continue) => TRUE,
        Ok(Flow::NonFinite) => {
            ctx.evaluation_errors += 1;
            FALSE
        }
        Ok(Flow::Mismatch) | Ok(Flow::Stop) => FALSE,
        Err(payload) => {
            ctx.panic = Some((callback, panic_message(payload.as_ref())));
            FALSE
        }
    }
}

fn finite_flow(values: &[f64]) -> Flow {
    if values.iter().all(|v| v.is_finite()) {
        Flow::Continue
    } else {
        Flow::NonFinite
    }
}

/// A slice over an array Ipopt passes in; empty for a null pointer or a length ≤ 0.
///
/// # Safety
/// A non-null `ptr` must point at `len` initialised values that stay valid and are not
/// written through another path while the slice lives.
unsafe fn input<'s, T>(ptr: *const T, len: Index) -> &'s [T] {
    if ptr.is_null() || len <= 0 {
        &[]
    } else {
        // SAFETY: non-null and `len` > 0; validity is the caller's promise above.
        unsafe { std::slice::from_raw_parts(ptr, len as usize) }
    }
}

/// A mutable slice over an output array Ipopt passes in; empty for null or a length ≤ 0.
///
/// # Safety
/// A non-null `ptr` must point at `len` values writable for the slice's life and not
/// reachable through any other live reference.
unsafe fn output<'s, T>(ptr: *mut T, len: Index) -> &'s mut [T] {
    if ptr.is_null() || len <= 0 {
        &mut []
    } else {
        // SAFETY: non-null and `len` > 0; exclusivity is the caller's promise above.
        unsafe { std::slice::from_raw_parts_mut(ptr, len as usize) }
    }
}

/// The context behind Ipopt's `user_data`.
///
/// # Safety
/// `user_data` must be the `*mut Context<P>` that `solve` passed to `IpoptSolve`, which
/// outlives the call and is not otherwise borrowed while a callback runs (Ipopt calls the
/// callbacks one at a time on the solving thread).
unsafe fn context<'c, 'a, P: Nlp + ?Sized>(user_data: UserDataPtr) -> &'c mut Context<'a, P> {
    // SAFETY: the caller's promise above.
    unsafe { &mut *(user_data as *mut Context<'a, P>) }
}

/// Ipopt's `eval_f`: the objective.
pub(super) extern "C" fn eval_f<P: Nlp + ?Sized>(
    n: Index,
    x: *mut Number,
    new_x: Bool,
    obj_value: *mut Number,
    user_data: UserDataPtr,
) -> Bool {
    // SAFETY: Ipopt hands back the user_data `solve` gave it (see `context`).
    let ctx = unsafe { context::<P>(user_data) };
    guard(ctx, "objective", |ctx| {
        // SAFETY: Ipopt passes the current iterate, n values, read-only during the call.
        let x = unsafe { input(x, n) };
        if obj_value.is_null() {
            return Flow::Mismatch;
        }
        let value = ctx.problem.objective(x, is_true(new_x));
        // SAFETY: obj_value is non-null (checked) and points at Ipopt's output Number.
        unsafe { *obj_value = value };
        finite_flow(&[value])
    })
}

/// Ipopt's `eval_grad_f`: the objective gradient.
pub(super) extern "C" fn eval_grad_f<P: Nlp + ?Sized>(
    n: Index,
    x: *mut Number,
    new_x: Bool,
    grad_f: *mut Number,
    user_data: UserDataPtr,
) -> Bool {
    // SAFETY: Ipopt hands back the user_data `solve` gave it (see `context`).
    let ctx = unsafe { context::<P>(user_data) };
    guard(ctx, "gradient", |ctx| {
        // SAFETY: x holds n values; grad_f is Ipopt's separate output array of n values.
        let (x, grad) = unsafe { (input(x, n), output(grad_f, n)) };
        ctx.problem.gradient(x, is_true(new_x), grad);
        finite_flow(grad)
    })
}

/// Ipopt's `eval_g`: the constraint values.
pub(super) extern "C" fn eval_g<P: Nlp + ?Sized>(
    n: Index,
    x: *mut Number,
    new_x: Bool,
    m: Index,
    g: *mut Number,
    user_data: UserDataPtr,
) -> Bool {
    // SAFETY: Ipopt hands back the user_data `solve` gave it (see `context`).
    let ctx = unsafe { context::<P>(user_data) };
    guard(ctx, "constraints", |ctx| {
        // SAFETY: x holds n values; g is Ipopt's separate output array of m values.
        let (x, g) = unsafe { (input(x, n), output(g, m)) };
        ctx.problem.constraints(x, is_true(new_x), g);
        finite_flow(g)
    })
}

/// The matrix a sparse callback serves.
#[derive(Clone, Copy)]
enum Sparse {
    /// The constraint Jacobian (`eval_jac_g`).
    Jacobian,
    /// The Lagrangian Hessian (`eval_h`).
    Hessian,
}

/// The body `eval_jac_g` and `eval_h` share. Ipopt asks either for the sparsity structure
/// (`values` null: the context's rows and columns are copied into `i_row` and `j_col`) or for
/// the values, which `fill` writes into the `nele` entries of `values`. A call whose `nele` is
/// not the structure's size, or a Hessian call for a problem without one, is refused.
///
/// # Safety
/// `user_data` is what [`context`] requires. For the structure call `i_row` and `j_col` are
/// Ipopt's two distinct output arrays of `nele` indices; for the values call `values` is its
/// output array of `nele` numbers, apart from every array `fill` reads.
unsafe fn sparse_callback<P: Nlp + ?Sized>(
    user_data: UserDataPtr,
    matrix: Sparse,
    nele: Index,
    i_row: *mut Index,
    j_col: *mut Index,
    values: *mut Number,
    fill: impl FnOnce(&mut P, &mut [Number]),
) -> Bool {
    // SAFETY: the caller's promise above.
    let ctx = unsafe { context::<P>(user_data) };
    let name = match (matrix, values.is_null()) {
        (Sparse::Jacobian, true) => "jacobian_structure",
        (Sparse::Jacobian, false) => "jacobian_values",
        (Sparse::Hessian, true) => "hessian_structure",
        (Sparse::Hessian, false) => "hessian_values",
    };
    guard(ctx, name, |ctx| {
        let (rows, cols) = match matrix {
            Sparse::Jacobian => (&ctx.jacobian_rows, &ctx.jacobian_cols),
            Sparse::Hessian if ctx.has_hessian => (&ctx.hessian_rows, &ctx.hessian_cols),
            Sparse::Hessian => return Flow::Mismatch,
        };
        if usize::try_from(nele) != Ok(rows.len()) {
            return Flow::Mismatch;
        }
        if values.is_null() {
            // SAFETY: for the structure call Ipopt passes two distinct output arrays of nele
            // indices (the caller's promise).
            let (out_rows, out_cols) = unsafe { (output(i_row, nele), output(j_col, nele)) };
            if out_rows.len() != rows.len() || out_cols.len() != cols.len() {
                return Flow::Mismatch;
            }
            out_rows.copy_from_slice(rows);
            out_cols.copy_from_slice(cols);
            return Flow::Continue;
        }
        // SAFETY: values is Ipopt's output array of nele numbers (the caller's promise).
        let values = unsafe { output(values, nele) };
        fill(&mut *ctx.problem, values);
        finite_flow(values)
    })
}

/// Ipopt's `eval_jac_g`: the Jacobian structure (when `values` is null) or its values.
pub(super) extern "C" fn eval_jac_g<P: Nlp + ?Sized>(
    n: Index,
    x: *mut Number,
    new_x: Bool,
    _m: Index,
    nele_jac: Index,
    i_row: *mut Index,
    j_col: *mut Index,
    values: *mut Number,
    user_data: UserDataPtr,
) -> Bool {
    let jacobian_values = |problem: &mut P, values: &mut [Number]| {
        // SAFETY: x holds n values, read-only during the call.
        let x = unsafe { input(x, n) };
        problem.jacobian_values(x, is_true(new_x), values);
    };
    // SAFETY: Ipopt hands back the user_data `solve` gave it (see `context`); i_row, j_col
    // and values are its output arrays of nele_jac entries, distinct from x.
    unsafe {
        sparse_callback(
            user_data,
            Sparse::Jacobian,
            nele_jac,
            i_row,
            j_col,
            values,
            jacobian_values,
        )
    }
}

/// Ipopt's `eval_h`: the Lagrangian Hessian structure (when `values` is null) or its values.
pub(super) extern "C" fn eval_h<P: Nlp + ?Sized>(
    n: Index,
    x: *mut Number,
    new_x: Bool,
    obj_factor: Number,
    m: Index,
    lambda: *mut Number,
    new_lambda: Bool,
    nele_hess: Index,
    i_row: *mut Index,
    j_col: *mut Index,
    values: *mut Number,
    user_data: UserDataPtr,
) -> Bool {
    let hessian_values = |problem: &mut P, values: &mut [Number]| {
        // SAFETY: x holds n values and lambda m values, read-only during the call.
        let (x, lambda) = unsafe { (input(x, n), input(lambda, m)) };
        problem.hessian_values(
            x,
            is_true(new_x),
            obj_factor,
            lambda,
            is_true(new_lambda),
            values,
        );
    };
    // SAFETY: Ipopt hands back the user_data `solve` gave it (see `context`); i_row, j_col
    // and values are its output arrays of nele_hess entries, distinct from x and lambda.
    unsafe {
        sparse_callback(
            user_data,
            Sparse::Hessian,
            nele_hess,
            i_row,
            j_col,
            values,
            hessian_values,
        )
    }
}

/// Ipopt's intermediate callback: counts iterations, honours the cancel flag and the deadline,
/// and calls
/// the problem's `intermediate` (progress display, its own stop rule).
pub(super) extern "C" fn intermediate<P: Nlp + ?Sized>(
    alg_mod: Index,
    iter_count: Index,
    obj_value: Number,
    inf_pr: Number,
    inf_du: Number,
    mu: Number,
    d_norm: Number,
    _regularization_size: Number,
    _alpha_du: Number,
    alpha_pr: Number,
    ls_trials: Index,
    user_data: UserDataPtr,
) -> Bool {
    // SAFETY: Ipopt hands back the user_data `solve` gave it (see `context`).
    let ctx = unsafe { context::<P>(user_data) };
    ctx.iterations = usize::try_from(iter_count).unwrap_or(0);
    if ctx.panic.is_some() {
        return FALSE;
    }
    if ctx.cancel.is_some_and(|flag| flag.load(Ordering::Relaxed)) {
        ctx.cancelled = true;
        return FALSE;
    }
    if ctx.deadline.is_some_and(|d| std::time::Instant::now() >= d) {
        ctx.timed_out = true;
        return FALSE;
    }
    let info = IterationInfo {
        iteration: ctx.iterations,
        objective: obj_value,
        inf_pr,
        inf_du,
        mu,
        d_norm,
        alpha_pr,
        ls_trials: usize::try_from(ls_trials).unwrap_or(0),
        mode: alg_mod,
    };
    guard(ctx, "intermediate", |ctx| {
        if ctx.problem.intermediate(&info) {
            Flow::Continue
        } else {
            Flow::Stop
        }
    })
}
