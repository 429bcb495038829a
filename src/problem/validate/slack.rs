//! `[slack]`: the penalty weight, the slack mode and the exact-penalty continuation.

use super::context::Context;
use super::values::positive;
use crate::ipopt::OptionValue;
use crate::problem::schema::ProblemFile;
use crate::problem::{ProblemError, SlackContinuation, SlackMode, SlackRestart};

/// How far below `slack.weight` a homotopy's first solve starts (`slack.homotopy`).
pub const HOMOTOPY_SPAN: f64 = 1000.0;

/// A homotopy's extra solves unless `slack.rounds` is given: three to climb back to
/// `slack.weight` at growth 10, three more above it.
const HOMOTOPY_ROUNDS: usize = 6;

/// (weight α of the first solve, mode, tolerance).
pub(super) fn check_slack_penalty(
    ctx: &Context,
    raw: &ProblemFile,
) -> Result<(f64, SlackMode, f64), ProblemError> {
    let mut slack_weight = positive(ctx, "slack.weight", raw.slack.weight)?;
    if raw.slack.homotopy == Some(true) {
        slack_weight /= HOMOTOPY_SPAN;
    }
    let slack_tolerance = match raw.slack.tolerance {
        None => crate::problem::DEFAULT_SLACK_TOLERANCE,
        Some(t) => positive(ctx, "slack.tolerance", t)?,
    };
    let slack_mode = match raw.slack.mode.as_deref() {
        None | Some("per_interval") => SlackMode::PerInterval,
        Some("per_contact") => SlackMode::PerContact,
        Some("penalty") => SlackMode::Penalty,
        Some(other) => {
            let valid = ["per_interval", "per_contact", "penalty"].map(String::from);
            return Err(ctx.unknown_name("slack.mode", "slack mode", other, &valid));
        }
    };
    Ok((slack_weight, slack_mode, slack_tolerance))
}

/// `slack.target`, `growth` and `rounds`, if a target is given (or `slack.homotopy` asks
/// for one: `target` a tenth of `tolerance`).
pub(super) fn check_slack_continuation(
    ctx: &Context,
    raw: &ProblemFile,
    tolerance: f64,
) -> Result<Option<SlackContinuation>, ProblemError> {
    let homotopy = raw.slack.homotopy == Some(true);
    let target = raw.slack.target.or(homotopy.then_some(tolerance / 10.0));
    let slack_continuation = match target {
        None => {
            for (field, given) in [
                ("slack.growth", raw.slack.growth.is_some()),
                ("slack.rounds", raw.slack.rounds.is_some()),
                ("slack.restart", raw.slack.restart.is_some()),
                (
                    "slack.tied_tolerances",
                    raw.slack.tied_tolerances == Some(true),
                ),
            ] {
                if given {
                    return Err(ctx.invalid(
                        field,
                        "has no effect without `slack.target` or `slack.homotopy = true`; give either",
                    ));
                }
            }
            None
        }
        Some(target) => {
            let growth = raw.slack.growth.unwrap_or(10.0);
            if !(growth > 1.0 && growth.is_finite()) {
                return Err(ctx.invalid(
                    "slack.growth",
                    format!(
                        "must be a number above 1 (the weight's factor per solve), got {growth}"
                    ),
                ));
            }
            let restart = match raw.slack.restart.as_deref() {
                None if homotopy => SlackRestart::PrimalDual,
                None | Some("primal") => SlackRestart::Primal,
                Some("primal_dual") => SlackRestart::PrimalDual,
                Some("initial_guess") => SlackRestart::InitialGuess,
                Some(other) => {
                    return Err(ctx.invalid(
                        "slack.restart",
                        format!(
                            "must be \"primal\", \"primal_dual\" or \"initial_guess\", got {other:?}"
                        ),
                    ));
                }
            };
            Some(SlackContinuation {
                restart,
                target: positive(ctx, "slack.target", target)?,
                growth,
                rounds: raw
                    .slack
                    .rounds
                    .unwrap_or(if homotopy { HOMOTOPY_ROUNDS } else { 3 }),
                tied_sigma: (raw.slack.tied_tolerances == Some(true))
                    .then_some(tolerance * if homotopy { HOMOTOPY_SPAN } else { 1.0 }),
            })
        }
    };
    Ok(slack_continuation)
}

/// `slack.polish` (default: on unless contact-mode blocks pair intervals): it fixes each
/// interval's own complementarity pairs, which blocks longer than one interval do not have.
pub(super) fn check_polish(
    ctx: &Context,
    raw: &ProblemFile,
    mode_block: usize,
) -> Result<bool, ProblemError> {
    match raw.slack.polish {
        Some(true) if mode_block > 1 => Err(ctx.invalid(
            "slack.polish",
            format!(
                "fixes each interval's own contact modes, but contacts.mode_block = {mode_block} \
                 pairs them across intervals; set contacts.mode_block = 1 or slack.polish = false"
            ),
        )),
        Some(polish) => Ok(polish),
        None => Ok(mode_block == 1),
    }
}

/// Penalty mode needs its products' factors ≥ 0: Ipopt's `bound_relax_factor` must be 0 (the
/// mode's default, `transcription::PENALTY_BOUND_RELAX`) if the file gives it.
pub(super) fn check_penalty_options(
    ctx: &Context,
    slack_mode: SlackMode,
    solver_options: &[(String, OptionValue)],
) -> Result<(), ProblemError> {
    if slack_mode != SlackMode::Penalty {
        return Ok(());
    }
    let relaxed = solver_options.iter().find(|(name, value)| {
        name == "bound_relax_factor"
            && !matches!(value, OptionValue::Num(v) if *v == 0.0)
            && !matches!(value, OptionValue::Int(0))
    });
    match relaxed {
        Some((_, value)) => Err(ctx.invalid(
            "solver.ipopt.bound_relax_factor",
            format!(
                "is {value}, but `slack.mode = \"penalty\"` puts the complementarity products in \
                 the objective and needs their factors >= 0: relaxed bounds let a product go \
                 below 0 without limit (the penalty runs to -1e4 and beyond); remove it (penalty \
                 mode sets 0) or use an elastic slack mode (\"per_interval\", \"per_contact\")"
            ),
        )),
        None => Ok(()),
    }
}
