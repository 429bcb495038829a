//! A level of the grid continuation starts from the plan of the level below, its contact
//! impulses carried as forces (`crate::pipeline::levels`). That plan has contact modes: which
//! contacts touch, stick or slide in each interval. With them fixed
//! ([`Transcription::fix_contact_modes`]) the finer grid's NLP is a regular one, and the start
//! nearly satisfies it, so it solves in tens of iterations (the hopper: 11 to 31 at 41 to 161
//! knots). Its plan keeps the coarse grid's contact timing, which the relaxed NLP may
//! move, and the relaxed solve from the same start may end at a worse optimum than that plan
//! (BENCHMARKS.md: the hopper's ladders over seeded first levels). Both are solved; the lower
//! solved objective is the level's plan.
//!
//! A problem whose slack is solved by a continuation (`slack.target`, `slack.homotopy`) starts
//! its levels without the impulses, loose: this solve is not made for it (Spring Flamingo's
//! 25-knot modes at 49 knots: 516 iterations to an objective of 99.7, where its homotopy found
//! 20.5).

use super::solve::{SolveOptions, set_unless_given, solve_modes_fixed};
use super::{FixedModes, MechanicsDerivatives, Solution, Transcription, TranscriptionError};
use crate::ipopt::OptionValue;
use crate::problem::{InitialGuess, ProblemSpec};

/// The solve with the contact modes of the level below fixed, as `summary.json` records it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CarriedModes {
    /// Its verdict.
    pub verdict: super::SolveVerdict,
    /// Its objective.
    pub objective: f64,
    /// Its Ipopt iterations (also counted in the solution's).
    pub iterations: usize,
    /// Its wall time [s] (also counted in the solution's).
    pub wall_time_s: f64,
    /// Whether its plan is the solution: solved, and the relaxed solve not solved or higher.
    pub kept: bool,
    /// The modes it fixed.
    pub fixed: FixedModes,
}

/// Whether `spec` starts from a plan carrying its impulses with the slack solved once, and a
/// polish that would fix modes: the case this solve is made for (module docs).
fn applies<M: MechanicsDerivatives>(t: &Transcription<M>, spec: &ProblemSpec) -> bool {
    matches!(&spec.initial_guess, InitialGuess::WarmStart(w) if !w.forces.is_empty())
        && spec.slack_continuation.is_none()
        && spec.slack_polish
        && spec.mode_block <= 1
        && t.layout().nc > 0
}

/// The NLP with the start's contact modes fixed, solved from the start (module docs); None
/// where it does not apply or a stop was requested. The solution carries its
/// [`CarriedModes`] record (`kept` is decided by [`keep_better`]).
pub(super) fn solve_with_carried_modes<M: MechanicsDerivatives>(
    t: &mut Transcription<M>,
    spec: &ProblemSpec,
    options: &SolveOptions,
) -> Result<Option<Solution>, TranscriptionError> {
    if !applies(t, spec) || options.stopped() {
        return Ok(None);
    }
    let start = t.initial_point().to_vec();
    let (report, fixed) = solve_modes_fixed(t, spec, options, &start, |solver, _| {
        // Near a solution of the modes' NLP, not on it: the resampled dynamics rows are off
        // by a fraction of an impulse.
        set_unless_given(
            solver,
            spec,
            options,
            vec![
                ("bound_push", OptionValue::Num(1e-6)),
                ("bound_frac", OptionValue::Num(1e-6)),
                ("mu_init", OptionValue::Num(1e-4)),
            ],
        )
    })?;
    let mut solution = Solution::read_off(t, spec, &report);
    solution.carried_modes = Some(CarriedModes {
        verdict: solution.verdict(),
        objective: solution.objective,
        iterations: solution.iterations,
        wall_time_s: solution.wall_time_s,
        kept: false,
        fixed,
    });
    Ok(Some(solution))
}

/// The better of the relaxed solve's `relaxed` and the carried modes' `carried`: `carried`
/// if it is solved and `relaxed` is not or is higher, else `relaxed`; either way with the
/// other's work added and the carried modes' record, `kept` set.
pub(super) fn keep_better(mut relaxed: Solution, mut carried: Solution) -> Solution {
    let keep = carried.verdict().is_solved()
        && (!relaxed.verdict().is_solved() || carried.objective < relaxed.objective);
    let mut record = carried.carried_modes.take();
    if let Some(r) = &mut record {
        r.kept = keep;
    }
    let mut kept = if keep {
        carried.add_work(&relaxed);
        carried
    } else {
        relaxed.add_work(&carried);
        relaxed
    };
    kept.carried_modes = record;
    kept
}
