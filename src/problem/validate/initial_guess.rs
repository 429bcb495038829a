//! `[initial_guess]`: a linear guess towards a pose, or a previous `trajectory.csv`.

use std::path::Path;

use super::context::Context;
use super::endpoints::Endpoints;
use super::values::{MAX_MAGNITUDE, resolve};
use crate::problem::schema::{GuessTarget, ProblemFile};
use crate::problem::{InitialGuess, ProblemError, RobotInfo, WarmStart};

pub(super) fn check_initial_guess(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
    endpoints: &Endpoints,
) -> Result<InitialGuess, ProblemError> {
    let coords = &robot.coordinates;
    let dir = ctx.file.parent().unwrap_or(Path::new(""));
    let (q_initial, goal) = (&endpoints.q_initial, &endpoints.goal);
    let initial_guess = match (&raw.initial_guess.warm_start, &raw.initial_guess.to) {
        (Some(_), Some(_)) => {
            return Err(ctx.invalid(
                "initial_guess.warm_start",
                "give either `warm_start` or `to`, not both",
            ));
        }
        (Some(csv), None) => InitialGuess::WarmStart(read_warm_start(ctx, &dir.join(csv), robot)?),
        (None, to) => InitialGuess::Linear {
            from: q_initial.clone(),
            to: match to {
                None | Some(GuessTarget::Final) => goal.clone(),
                Some(GuessTarget::Initial) => q_initial.clone(),
                Some(GuessTarget::Pose(p)) => resolve(
                    ctx,
                    "initial_guess.to",
                    "coordinate",
                    coords,
                    p,
                    Some(q_initial),
                )?,
            },
        },
    };
    Ok(initial_guess)
}

/// Reads a `trajectory.csv` written by vito: the time column, one column per coordinate
/// (by name) and, when present, one per input.
fn read_warm_start(
    ctx: &Context,
    path: &Path,
    robot: &RobotInfo,
) -> Result<WarmStart, ProblemError> {
    let field = "initial_guess.warm_start";
    let err = |message: String| ProblemError::WarmStart {
        at: ctx.at(field),
        path: path.to_owned(),
        message,
    };
    let text = crate::input::read_regular_text(path, crate::input::MAX_TEXT_BYTES)
        .map_err(|e| err(format!("cannot read it: {e}")))?;
    let recorded = crate::trajectory_csv::read_trajectory(&text, &robot.coordinates, &robot.inputs)
        .map_err(err)?;
    fn named<'a>(names: &'a [String], values: &'a [f64]) -> impl Iterator<Item = (&'a str, f64)> {
        names.iter().map(String::as_str).zip(values.iter().copied())
    }
    let rows = recorded.q.iter().zip(&recorded.times).enumerate();
    for (k, (q, t)) in rows {
        let u = recorded.u.get(k).map_or(&[][..], Vec::as_slice);
        let bad = std::iter::once(("time", *t))
            .chain(named(&robot.coordinates, q))
            .chain(named(&robot.inputs, u))
            .find(|(_, v)| !(v.is_finite() && v.abs() <= MAX_MAGNITUDE));
        if let Some((column, v)) = bad {
            return Err(err(format!(
                "data row {} has {column} = {v}; every cell must be a finite number of \
                 magnitude at most {MAX_MAGNITUDE:e}",
                k + 1
            )));
        }
    }
    Ok(WarmStart {
        source: path.to_owned(),
        times: recorded.times,
        q: recorded.q,
        u: recorded.u,
    })
}
