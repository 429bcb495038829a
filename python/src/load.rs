//! Loading a problem file from Python: as the command does, and again when a pickle is
//! restored.

use std::path::Path;

use pyo3::prelude::*;
use vito::pipeline;
use vito::problem::{LoadedProblem, Override};

use crate::errors::problem_error;

/// Loads `path` with `sets` as `vito solve FILE --set ...` does (`pipeline::load_checked`),
/// without the GIL (asking Ipopt about the options waits for any solve going on).
pub(crate) fn load_problem(
    py: Python<'_>,
    path: &Path,
    sets: &[String],
) -> PyResult<LoadedProblem> {
    let loaded = py.detach(|| {
        let overrides: Vec<Override> = sets
            .iter()
            .map(|s| Override::parse(s))
            .collect::<Result<_, _>>()?;
        pipeline::load_checked(path, &overrides)
    });
    loaded.map_err(|e| problem_error(py, &e))
}

/// Loads the problem of a pickled `Problem` or result again: the file must still be where it
/// was, with the overrides still valid (the error says so in a note).
pub(crate) fn reload_pickled(
    py: Python<'_>,
    path: &Path,
    sets: &[String],
) -> PyResult<LoadedProblem> {
    load_problem(py, path, sets).inspect_err(|e| {
        let note = format!(
            "while unpickling a vito object: its problem file {} is read again from where it \
             was when pickled (the file must be reachable at that path from this process)",
            path.display()
        );
        let _ = e.value(py).call_method1("add_note", (note,));
    })
}
