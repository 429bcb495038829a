//! `[horizon]`: the number of knots and fixed or free equal time steps.

use super::context::Context;
use super::values::{MAX_MAGNITUDE, positive};
use crate::problem::schema::ProblemFile;
use crate::problem::{ProblemError, TimeSteps};

/// The number of knots (at least 2; whether they fit is `size`'s check).
pub(super) fn check_knots(ctx: &Context, raw: &ProblemFile) -> Result<usize, ProblemError> {
    if raw.horizon.knots < 2 {
        return Err(ctx.invalid(
            "horizon.knots",
            format!("must be at least 2, got {}", raw.horizon.knots),
        ));
    }
    Ok(raw.horizon.knots as usize)
}

/// Fixed or free equal time steps over `knots` knots.
pub(super) fn check_time_steps(
    ctx: &Context,
    raw: &ProblemFile,
    knots: usize,
) -> Result<TimeSteps, ProblemError> {
    let time_steps = match (raw.horizon.time_step, raw.horizon.total_time) {
        (Some(h), None) => {
            let h = positive(ctx, "horizon.time_step", h)?;
            let total = h * (knots - 1) as f64;
            if total > MAX_MAGNITUDE {
                return Err(ctx.invalid(
                    "horizon.time_step",
                    format!(
                        "the horizon T = time_step·(knots − 1) = {total:e} exceeds \
                         {MAX_MAGNITUDE:e}: use a shorter step or fewer knots"
                    ),
                ));
            }
            TimeSteps::Fixed(h)
        }
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
    Ok(time_steps)
}
