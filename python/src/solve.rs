//! A solve from Python: `pipeline::solve` (the command's; a grid finer than the file's
//! through `pipeline::levels`) on its own thread, with progress to a Python callable, Ctrl-C
//! and an optional deadline as stop requests.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use vito::pipeline;
use vito::problem::LoadedProblem;
use vito::transcription::{MultiStart, Progress, SolveOptions};

use crate::errors::vito_error;
use crate::watch::run_watched;

/// An iteration as the `progress` callable hears of it.
struct Iteration {
    iteration: usize,
    objective: f64,
    inf_pr: f64,
    inf_du: f64,
    max_slack: f64,
}

/// How a solve from Python ended.
pub(crate) struct Solved {
    pub(crate) solution: vito::transcription::Solution,
    /// The exception that stopped it (Ctrl-C, or raised by `progress`), to raise once the
    /// iterate is kept.
    pub(crate) error: Option<PyErr>,
    /// Whether the deadline stopped it.
    pub(crate) timed_out: bool,
}

/// Solves `problem` as `vito solve` does: `starts`/`seed` the command's `--starts`/`--seed`,
/// `progress` called with a dict at each iteration, stopped after the current iteration by
/// Ctrl-C, an exception of `progress`, the `deadline`, or `cancel` set by another thread.
pub(crate) fn solve_loaded(
    py: Python<'_>,
    problem: &LoadedProblem,
    multi_start: MultiStart,
    progress: Option<Py<PyAny>>,
    deadline: Option<Instant>,
    cancel: Arc<AtomicBool>,
) -> PyResult<Solved> {
    let timed_out = Arc::new(AtomicBool::new(false));
    let wants_progress = progress.is_some();
    let (result, error) = run_watched(
        py,
        &cancel,
        |messages| {
            let (stop, late) = (cancel.clone(), timed_out.clone());
            let mut options = SolveOptions {
                progress: Some(Box::new(move |p: &Progress| {
                    if deadline.is_some_and(|d| Instant::now() >= d) {
                        late.store(true, Ordering::SeqCst);
                        stop.store(true, Ordering::SeqCst);
                    }
                    if wants_progress {
                        messages.send_and_wait(Iteration {
                            iteration: p.iteration,
                            objective: p.objective,
                            inf_pr: p.inf_pr,
                            inf_du: p.inf_du,
                            max_slack: p.max_slack,
                        });
                    }
                })),
                cancel: Some(cancel.clone()),
                ipopt_options: Vec::new(),
                multi_start: Some(multi_start),
                deadline: None,
            };
            // A grid finer than the file's goes through the file's grid, as `vito solve`.
            match pipeline::levels::levels_for(problem) {
                Some(knots) => {
                    pipeline::levels::solve_on_levels(problem, &knots, &mut options, |_, _, _| {})
                }
                None => pipeline::solve(&problem.spec, &options),
            }
        },
        |py, it: Iteration| {
            let Some(callable) = &progress else {
                return Ok(());
            };
            let info = PyDict::new(py);
            info.set_item("iteration", it.iteration)?;
            info.set_item("objective", it.objective)?;
            info.set_item("inf_pr", it.inf_pr)?;
            info.set_item("inf_du", it.inf_du)?;
            info.set_item("max_slack", it.max_slack)?;
            callable.call1(py, (info,)).map(drop)
        },
    );
    let solution = match result {
        Ok(s) => s,
        // A stop request that came before the solve could start is the request's error.
        Err(e) => return Err(error.unwrap_or_else(|| vito_error(&e))),
    };
    Ok(Solved {
        solution,
        error,
        timed_out: timed_out.load(Ordering::SeqCst),
    })
}
