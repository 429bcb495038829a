//! `[initial_guess]`: a linear guess towards a pose, a previous `trajectory.csv`, or an
//! open-loop simulation under sinusoidal inputs.

use std::path::Path;

use super::context::Context;
use super::endpoints::Endpoints;
use super::values::{MAX_MAGNITUDE, positive, resolve};
use crate::problem::schema::{GuessTarget, ProblemFile, SimulationGuessEntry};
use crate::problem::{InitialGuess, ProblemError, RobotInfo, SimulatedGuess, WarmStart};

pub(super) fn check_initial_guess(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
    endpoints: &Endpoints,
    knots: usize,
) -> Result<InitialGuess, ProblemError> {
    let coords = &robot.coordinates;
    let dir = ctx.file.parent().unwrap_or(Path::new(""));
    let (q_initial, goal) = (&endpoints.q_initial, &endpoints.goal);
    let guess = &raw.initial_guess;
    if let Some(simulation) = &guess.simulation {
        return match (&guess.warm_start, &guess.to) {
            (None, None) => check_simulation(ctx, simulation, robot, knots),
            _ => Err(ctx.invalid(
                "initial_guess.simulation",
                "give one of `simulation`, `warm_start` or `to`",
            )),
        };
    }
    let initial_guess = match (&guess.warm_start, &guess.to) {
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

/// Simulated periods above which a guess would take longer than the solve it starts.
const MAX_CYCLES: i64 = 1000;
/// Simulation steps per knot interval, at most.
const MAX_SUBSTEPS: i64 = 1000;

fn check_simulation(
    ctx: &Context,
    entry: &SimulationGuessEntry,
    robot: &RobotInfo,
    knots: usize,
) -> Result<InitialGuess, ProblemError> {
    let field = |key: &str| format!("initial_guess.simulation.{key}");
    let period = positive(ctx, &field("period"), entry.period)?;
    let cycles = entry.cycles.unwrap_or(3);
    if !(1..=MAX_CYCLES).contains(&cycles) {
        return Err(ctx.invalid(
            &field("cycles"),
            format!("is {cycles}; simulate 1 to {MAX_CYCLES} periods"),
        ));
    }
    let substeps = entry.substeps.unwrap_or(1);
    if !(1..=MAX_SUBSTEPS).contains(&substeps) {
        return Err(ctx.invalid(
            &field("substeps"),
            format!("is {substeps}; take 1 to {MAX_SUBSTEPS} steps per knot interval"),
        ));
    }
    if knots < 2 {
        return Err(ctx.invalid("horizon.knots", "a simulated guess needs 2 knots or more"));
    }
    let inputs = &robot.inputs;
    let zeros = vec![0.0; inputs.len()];
    let per_input = |key: &str, v: Option<&crate::problem::schema::NamedVector>| match v {
        Some(v) => resolve(ctx, &field(key), "input", inputs, v, Some(&zeros)),
        None => Ok(zeros.clone()),
    };
    Ok(InitialGuess::Simulation(SimulatedGuess {
        period,
        cycles: cycles as usize,
        substeps: substeps as usize,
        amplitude: per_input("amplitude", Some(&entry.amplitude))?,
        phase: per_input("phase", entry.phase.as_ref())?,
        offset: per_input("offset", entry.offset.as_ref())?,
    }))
}

/// Reads a `trajectory.csv` written by vito: the time column, one column per coordinate
/// (by name) and, when present, one per input.
fn read_warm_start(
    ctx: &Context,
    path: &Path,
    robot: &RobotInfo,
) -> Result<WarmStart, ProblemError> {
    let err = |message: String| ProblemError::WarmStart {
        at: ctx.at("initial_guess.warm_start"),
        path: path.to_owned(),
        message,
    };
    let text = crate::files::input::read_regular_text(path, crate::files::input::MAX_TEXT_BYTES)
        .map_err(|e| err(format!("cannot read it: {e}")))?;
    let recorded = warm_start_from_text(&text, robot).map_err(err)?;
    Ok(WarmStart {
        source: path.to_owned(),
        times: recorded.times,
        q: recorded.q,
        u: recorded.u,
        forces: Vec::new(),
    })
}

/// The warm start a trajectory CSV's text holds for `robot`: its times, configurations and
/// inputs, every cell a finite number of magnitude at most [`MAX_MAGNITUDE`]; the message
/// says what is wrong (the caller names the file).
pub(crate) fn warm_start_from_text(
    text: &str,
    robot: &RobotInfo,
) -> Result<crate::files::trajectory_csv::RecordedTrajectory, String> {
    let recorded =
        crate::files::trajectory_csv::read_trajectory(text, &robot.coordinates, &robot.inputs)?;
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
            return Err(format!(
                "data row {} has {column} = {v}; every cell must be a finite number of \
                 magnitude at most {MAX_MAGNITUDE:e}",
                k + 1
            ));
        }
    }
    Ok(recorded)
}
