//! `[[periodic]]`: q_N − q_1 = offset and equal first and last velocities.

use super::context::Context;
use super::values::finite;
use crate::problem::schema::ProblemFile;
use crate::problem::{Periodicity, ProblemError, RobotInfo};

pub(super) fn check_periodic(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
) -> Result<Vec<Periodicity>, ProblemError> {
    let coords = &robot.coordinates;
    let mut periodic = Vec::new();
    for (i, p) in raw.periodic.iter().enumerate() {
        let field = format!("periodic[{i}].coordinate");
        let coordinate = robot
            .coordinate_index(&p.coordinate)
            .ok_or_else(|| ctx.unknown_name(&field, "coordinate", &p.coordinate, coords))?;
        periodic.push(Periodicity {
            coordinate,
            position: p.position.unwrap_or(true),
            offset: finite(
                ctx,
                &format!("periodic[{i}].offset"),
                p.offset.unwrap_or(0.0),
            )?,
            velocity: p.velocity.unwrap_or(false),
        });
    }
    Ok(periodic)
}
