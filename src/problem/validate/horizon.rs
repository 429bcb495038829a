//! `[horizon]`: the number of knots and fixed or free equal time steps.

use super::context::Context;
use super::values::positive;
use crate::problem::schema::ProblemFile;
use crate::problem::{ProblemError, TimeSteps};

/// (knots, time steps).
pub(super) fn check_horizon(
    ctx: &Context,
    raw: &ProblemFile,
) -> Result<(usize, TimeSteps), ProblemError> {
    if raw.horizon.knots < 2 {
        return Err(ctx.invalid(
            "horizon.knots",
            format!("must be at least 2, got {}", raw.horizon.knots),
        ));
    }
    let knots = raw.horizon.knots as usize;
    let time_steps = match (raw.horizon.time_step, raw.horizon.total_time) {
        (Some(h), None) => TimeSteps::Fixed(positive(ctx, "horizon.time_step", h)?),
        (None, Some([t_min, t_max])) => {
            positive(ctx, "horizon.total_time[0]", t_min)?;
            positive(ctx, "horizon.total_time[1]", t_max)?;
            if t_min > t_max {
                return Err(ctx.invalid(
                    "horizon.total_time",
                    format!("the window [{t_min}, {t_max}] is empty: give [min, max]"),
                ));
            }
            TimeSteps::FreeEqual { t_min, t_max }
        }
        (Some(_), Some(_)) => {
            return Err(ctx.invalid(
                "horizon.total_time",
                "give either `time_step` (fixed steps) or `total_time = [min, max]` (free equal steps), not both",
            ));
        }
        (None, None) => {
            return Err(ctx.invalid(
                "horizon",
                "give `time_step` (fixed steps) or `total_time = [min, max]` (free equal steps)",
            ));
        }
    };
    Ok((knots, time_steps))
}
