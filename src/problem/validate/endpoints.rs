//! `[initial]` and `[final]`: q_1, v_0, the goal pose and the q_N box.

use super::context::Context;
use super::values::{nonnegative, resolve};
use crate::problem::schema::{ContactSelection, ProblemFile, VelocitySpec};
use crate::problem::{Interval, ProblemError, RobotInfo};

/// The checked initial and final conditions.
pub(super) struct Endpoints {
    pub(super) q_initial: Vec<f64>,
    pub(super) q_initial_free: Vec<bool>,
    pub(super) v_initial: Option<Vec<f64>>,
    /// The goal pose (the centre of the q_N box; q_1 when the file has none).
    pub(super) goal: Vec<f64>,
    pub(super) q_final: Vec<Interval>,
}

pub(super) fn check_endpoints(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
) -> Result<Endpoints, ProblemError> {
    let n = robot.coordinates.len();
    let coords = &robot.coordinates;
    let q_initial = resolve(ctx, "initial.q", "coordinate", coords, &raw.initial.q, None)?;
    let mut q_initial_free = vec![false; n];
    match &raw.initial.free {
        None | Some(ContactSelection::None) => {}
        Some(ContactSelection::All) => q_initial_free.fill(true),
        Some(ContactSelection::Names(names)) => {
            for (i, name) in names.iter().enumerate() {
                let field = format!("initial.free[{i}]");
                let c = robot
                    .coordinate_index(name)
                    .ok_or_else(|| ctx.unknown_name(&field, "coordinate", name, coords))?;
                q_initial_free[c] = true;
            }
        }
    }
    let v_initial = match &raw.initial.v {
        None | Some(VelocitySpec::Zero) => Some(vec![0.0; n]),
        Some(VelocitySpec::Free) => None,
        Some(VelocitySpec::Vector(v)) => Some(resolve(
            ctx,
            "initial.v",
            "coordinate",
            coords,
            v,
            Some(&vec![0.0; n]),
        )?),
    };
    let goal = match &raw.final_.q {
        Some(q) => resolve(ctx, "final.q", "coordinate", coords, q, Some(&q_initial))?,
        None => q_initial.clone(),
    };
    let tolerance = nonnegative(ctx, "final.tolerance", raw.final_.tolerance.unwrap_or(0.0))?;
    let q_final_free = raw.final_.free.unwrap_or(false) || raw.final_.q.is_none();
    if q_final_free && raw.final_.tolerance.is_some() {
        return Err(ctx.invalid(
            "final.tolerance",
            "applies to a goal `final.q`, but q_N is free here",
        ));
    }
    let q_final = if q_final_free {
        vec![Interval::FREE; n]
    } else {
        goal.iter()
            .map(|&g| Interval {
                lower: g - tolerance,
                upper: g + tolerance,
            })
            .collect()
    };
    Ok(Endpoints {
        q_initial,
        q_initial_free,
        v_initial,
        goal,
        q_final,
    })
}
