//! `[initial_guess]`: a linear guess towards a pose, or a previous `trajectory.csv`.

use std::path::Path;

use super::context::Context;
use super::endpoints::Endpoints;
use super::values::resolve;
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
    let text = std::fs::read_to_string(path).map_err(|e| err(format!("cannot read it: {e}")))?;
    let recorded = crate::trajectory_csv::read_trajectory(&text, &robot.coordinates, &robot.inputs)
        .map_err(err)?;
    Ok(WarmStart {
        source: path.to_owned(),
        times: recorded.times,
        q: recorded.q,
        u: recorded.u,
    })
}
