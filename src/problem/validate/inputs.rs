//! `[inputs]`: effort limits and explicit bounds per input.

use super::context::Context;
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
        if lower.is_nan() || upper.is_nan() || lower > upper {
            return Err(ctx.invalid(&field, format!("empty bound [{lower}, {upper}]")));
        }
        input_bounds[j] = Interval {
            lower: *lower,
            upper: *upper,
        };
    }
    Ok(input_bounds)
}
