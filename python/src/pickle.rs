//! Pickling of results (`Solution`, `Simulation`): the state they are pickled with, and the
//! checks a restored one passes before anything reads it. A pickle is only data: restored,
//! its problem file is loaded again (and must be the file it was, by its SHA-256), and its
//! numbers must have the names and shapes of that problem's trajectories; anything else is
//! an ordinary exception (`VitoError`, or `TypeError` for arguments of the wrong
//! type), never a panic.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyTuple;

use vito::files::names::{escape_controls, list_names};
use vito::files::trajectory_csv::Trajectory;
use vito::problem::LoadedProblem;

use crate::errors::{VitoError, vito_error};
use crate::load::reload_pickled;

/// The state a result is pickled with: its problem's file (absolute), overrides and the
/// file's SHA-256 (its fingerprint), and the result itself as TOML (which keeps NaN and
/// infinities).
pub(crate) fn pickled<'py, T: serde::Serialize>(
    py: Python<'py>,
    restore: &str,
    source: &(PathBuf, Vec<String>),
    problem: &LoadedProblem,
    value: &T,
) -> PyResult<Bound<'py, PyTuple>> {
    let text = toml::to_string(value)
        .map_err(|e| VitoError::new_err(format!("cannot pickle this result: {e}")))?;
    let path = std::path::absolute(&source.0)
        .map_err(|e| VitoError::new_err(format!("{}: {e}", source.0.display())))?;
    let restore = py.import("vito._vito")?.getattr(restore)?;
    let args = (path, source.1.clone(), text, problem.sha256.clone()).into_pyobject(py)?;
    PyTuple::new(py, [restore, args.into_any()])
}

/// The problem and value of a pickled `what` (`Solution`, `Simulation`): the value read from
/// its TOML, the problem loaded again and checked against the pickle's fingerprint `sha256`.
pub(crate) fn unpickled<T: serde::de::DeserializeOwned>(
    py: Python<'_>,
    what: &str,
    path: &std::path::Path,
    sets: &[String],
    text: &str,
    sha256: Option<&str>,
) -> PyResult<(LoadedProblem, T)> {
    let value = toml::from_str(text).map_err(|e| {
        refused(
            what,
            &format!("its state is not a pickled vito result: {}", e.message()),
        )
    })?;
    let problem = reload_pickled(py, what, path, sets, sha256)?;
    Ok((problem, value))
}

/// The error of a pickled `what` that cannot be restored, saying why.
pub(crate) fn refused(what: &str, why: &str) -> PyErr {
    VitoError::new_err(format!("cannot unpickle this vito.{what}: {why}"))
}

/// Friction directions per contact of `problem`'s trajectories (its robot's contact model).
pub(crate) fn friction_directions(problem: &LoadedProblem) -> PyResult<usize> {
    let mech = vito::pipeline::mechanics(&problem.spec).map_err(|e| vito_error(&e))?;
    Ok(problem.spec.contact_model(&mech).nd())
}

/// Names as a message lists them (control characters escaped).
fn names(list: &[String]) -> String {
    let escaped: Vec<String> = list
        .iter()
        .map(|n| escape_controls(n).into_owned())
        .collect();
    list_names(&escaped, 12)
}

/// Whether `rows` has `count` rows of `width` numbers each.
fn table(name: &str, rows: &[Vec<f64>], count: usize, width: usize) -> Result<(), String> {
    if rows.len() != count {
        return Err(format!("`{name}` has {} rows, not {count}", rows.len()));
    }
    for (k, row) in rows.iter().enumerate() {
        if row.len() != width {
            return Err(format!(
                "row {k} of `{name}` has {} values, not {width}",
                row.len()
            ));
        }
    }
    Ok(())
}

/// Whether the trajectory `t` is one of `problem`'s (with `nd` friction directions per
/// contact): its coordinates, inputs and contacts the problem's, by name and in order; at
/// least two knots at finite, increasing times; every array the shape its knots and names
/// give it (`contact_positions` may be empty). Its other numbers may be anything a result
/// holds (a diverged simulation's NaN distance).
pub(crate) fn check_trajectory(
    problem: &LoadedProblem,
    nd: usize,
    t: &Trajectory<'_>,
) -> Result<(), String> {
    let contacts: Vec<String> = problem
        .spec
        .contacts
        .iter()
        .map(|c| c.name.clone())
        .collect();
    for (what, theirs, ours) in [
        (
            "coordinates",
            t.coordinate_names,
            &problem.robot.coordinates,
        ),
        ("inputs", t.input_names, &problem.robot.inputs),
        ("contacts", t.contact_names, &contacts),
    ] {
        if theirs != ours.as_slice() {
            return Err(format!(
                "its {what} ({}) are not its problem's ({})",
                names(theirs),
                names(ours)
            ));
        }
    }
    if t.friction_directions != nd {
        return Err(format!(
            "it has {} friction directions per contact, its problem {nd}",
            t.friction_directions
        ));
    }
    let knots = t.times.len();
    if knots < 2
        || t.times.iter().any(|t| !t.is_finite())
        || t.times.windows(2).any(|w| w[1] <= w[0])
    {
        return Err("its `time` does not hold at least two finite, increasing knot times".into());
    }
    let (n, m, nc) = (
        problem.robot.coordinates.len(),
        problem.robot.inputs.len(),
        contacts.len(),
    );
    table("q", t.q, knots, n)?;
    table("v", t.v, knots, n)?;
    table("u", t.u, knots - 1, m)?;
    table("normal_impulse", t.normal_impulse, knots - 1, nc)?;
    if t.friction_impulse.len() != knots - 1 {
        return Err(format!(
            "`friction_impulse` has {} rows, not {}",
            t.friction_impulse.len(),
            knots - 1
        ));
    }
    for row in t.friction_impulse {
        table("friction_impulse", row, nc, nd)?;
    }
    table("signed_distance", t.signed_distance, knots, nc)?;
    if !t.contact_positions.is_empty()
        && (t.contact_positions.len() != knots
            || t.contact_positions.iter().any(|row| row.len() != nc))
    {
        return Err(format!(
            "`contact_positions` is not {knots} rows of {nc} points"
        ));
    }
    let width = t.slack.first().map_or(0, Vec::len);
    table("slack", t.slack, knots - 1, width)
}
