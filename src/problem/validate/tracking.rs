//! `[tracking]`: PD gains by input name for `vito simulate --track` and `vito study tracking`.

use super::context::Context;
use crate::problem::schema::ProblemFile;
use crate::problem::tracking::{GainError, TrackingGain, gains_for, merge_gains};
use crate::problem::{ProblemError, RobotInfo};

/// The file's gains, `all` first and then each named input (which overrides `all`).
pub(super) fn check_tracking(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
) -> Result<Vec<TrackingGain>, ProblemError> {
    let section = &raw.tracking.gains;
    let ordered = section
        .get_key_value("all")
        .into_iter()
        .chain(section.iter().filter(|(name, _)| name.as_str() != "all"));
    let mut gains = Vec::new();
    for (name, [kp, kd]) in ordered {
        let field = format!("tracking.gains.{name}");
        let resolved = gains_for(robot, name, *kp, *kd).map_err(|e| match e {
            GainError::Value => ctx.invalid(
                &field,
                format!("[{kp}, {kd}]: give [kp, kd], finite and ≥ 0 (input units per coordinate unit, and per coordinate rate unit)"),
            ),
            GainError::UnknownInput => {
                let mut valid = robot.inputs.clone();
                valid.push("all".into());
                ctx.unknown_name(&field, "input", name, &valid)
            }
            GainError::NoCoordinate(input) => ctx.invalid(
                &field,
                format!("input `{input}` acts on no coordinate of that name, so it has no PD reference"),
            ),
        })?;
        merge_gains(&mut gains, &resolved);
    }
    Ok(gains)
}
