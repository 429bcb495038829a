//! Loading a problem file from Python: as the command does, and again when a pickle is
//! restored (the file checked against the fingerprint the pickle carries).

use std::path::Path;

use pyo3::prelude::*;
use vito::pipeline;
use vito::problem::{LoadedProblem, Override};

use crate::errors::{VitoError, problem_error};

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

/// Loads the problem of a pickled `what` (`Problem`, `Solution`, `Simulation`) again: the
/// file must still be where it was, with the overrides still valid (the error says so in a
/// note), and still the file it was: its SHA-256 the pickle's `sha256` (a pickle without one
/// is refused), else `VitoError`.
pub(crate) fn reload_pickled(
    py: Python<'_>,
    what: &str,
    path: &Path,
    sets: &[String],
    sha256: Option<&str>,
) -> PyResult<LoadedProblem> {
    let Some(sha256) = sha256 else {
        return Err(VitoError::new_err(format!(
            "cannot unpickle this vito.{what}: the pickle carries no fingerprint of its \
             problem file {} (it was not made by this version of vito); pickle it again",
            path.display()
        )));
    };
    let loaded = load_problem(py, path, sets).inspect_err(|e| {
        let note = format!(
            "while unpickling a vito.{what}: its problem file {} is read again from where it \
             was when pickled (the file must be reachable at that path from this process)",
            path.display()
        );
        let _ = e.value(py).call_method1("add_note", (note,));
    })?;
    let fix = match what {
        "Solution" => "load the file again and solve it",
        "Simulation" => "load the file again and simulate it",
        _ => "load the file again",
    };
    same_file(
        &loaded,
        sha256,
        &format!("cannot unpickle this vito.{what}"),
        "it was pickled",
        fix,
    )?;
    Ok(loaded)
}

/// Whether `loaded` is still the file a fingerprint (`sha256`, its SHA-256) was taken of, at
/// `since`: else a `VitoError` saying `doing` cannot go on, and `fix`.
pub(crate) fn same_file(
    loaded: &LoadedProblem,
    sha256: &str,
    doing: &str,
    since: &str,
    fix: &str,
) -> PyResult<()> {
    if loaded.sha256 == sha256 {
        return Ok(());
    }
    Err(VitoError::new_err(format!(
        "{doing}: its problem file {} has changed since {since} (SHA-256 {} then, {} now); \
         {fix}",
        loaded.file.display(),
        short(sha256),
        short(&loaded.sha256),
    )))
}

/// The start of a fingerprint, for messages (a pickle's may be any text).
fn short(sha256: &str) -> String {
    let head: String = sha256.chars().take(12).collect();
    let mut text = head.escape_debug().to_string();
    if sha256.chars().count() > 12 {
        text.push('…');
    }
    text
}
