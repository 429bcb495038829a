//! `[inputs]`: effort limits and explicit bounds per input.

use super::context::Context;
use super::values::bound;
use crate::problem::schema::ProblemFile;
use crate::problem::{Interval, ProblemError, RobotInfo};

pub(super) fn check_inputs(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
) -> Result<Vec<Interval>, ProblemError> {
    let m = robot.inputs.len();
    let mut input_bounds: Vec<Interval> = if raw.inputs.effort_limits.unwrap_or(true) {
        robot
            .effort_limits
            .iter()
            .map(|&e| Interval {
                lower: -e,
                upper: e,
            })
            .collect()
    } else {
        vec![Interval::FREE; m]
    };
    for (input, [lower, upper]) in &raw.inputs.bounds {
        let field = format!("inputs.bounds.{input}");
        let j = robot
            .input_index(input)
            .ok_or_else(|| ctx.unknown_name(&field, "input", input, &robot.inputs))?;
        input_bounds[j] = bound(ctx, &field, *lower, *upper)?;
    }
    Ok(input_bounds)
}
