//! The steps `vito check`, `vito solve` and `vito bench` run on a loaded problem, in one place
//! so that what `check` reports is what `solve` builds: Ipopt's verdict on the problem's
//! options, the robot's mechanics, the solver's NLP and its size, the solve itself.

use std::borrow::Cow;

use crate::ipopt;
use crate::problem::{InitialGuess, LoadedProblem, ProblemError, ProblemSpec};
use crate::transcription::{
    self, BenchRow, MechanicsDerivatives, ModelMechanics, Solution, SolveOptions, Transcription,
    TranscriptionError,
};

/// The robot of `spec` as the transcription sees it (URDF model, gravity, contacts).
pub fn mechanics(spec: &ProblemSpec) -> Result<ModelMechanics, TranscriptionError> {
    ModelMechanics::load(spec)
}

/// The solver's NLP for `spec`, built as [`solve`] builds it, but for a simulated initial
/// guess, which only [`solve`] and [`bench`] run (it holds q_1 here).
pub fn build_nlp(spec: &ProblemSpec) -> Result<Transcription<ModelMechanics>, TranscriptionError> {
    Transcription::new(mechanics(spec)?, spec)
}

/// Solves `spec` with the robot from its URDF: the one way a problem is solved (the CLI,
/// studies, Python and the tests all come here), its initial guess resolved first.
pub fn solve(spec: &ProblemSpec, options: &SolveOptions) -> Result<Solution, TranscriptionError> {
    solve_with(mechanics(spec)?, spec, options)
}

/// Solves `spec` as [`solve`] does, for the given mechanics (e.g. closed-form test robots).
pub fn solve_with<M: MechanicsDerivatives>(
    mech: M,
    spec: &ProblemSpec,
    options: &SolveOptions,
) -> Result<Solution, TranscriptionError> {
    let spec = resolve_initial_guess(&mech, spec)?;
    transcription::solve_with(mech, &spec, options)
}

/// `spec` with a simulated initial guess run into the warm start it stands for
/// ([`crate::sim::guess`]); every other guess as it is.
pub fn resolve_initial_guess<'a, M: MechanicsDerivatives>(
    mech: &M,
    spec: &'a ProblemSpec,
) -> Result<Cow<'a, ProblemSpec>, TranscriptionError> {
    let InitialGuess::Simulation(guess) = &spec.initial_guess else {
        return Ok(Cow::Borrowed(spec));
    };
    let start = crate::sim::guess::simulate_guess(mech, spec, guess).map_err(|e| {
        TranscriptionError::Invalid {
            field: "initial_guess.simulation".into(),
            message: format!("the simulation of the initial guess failed: {e}"),
        }
    })?;
    let mut resolved = spec.clone();
    resolved.initial_guess = InitialGuess::WarmStart(start.warm_start);
    Ok(Cow::Owned(resolved))
}

/// Benchmarks `spec` (sizes, one derivative evaluation, a full solve) with the robot from its
/// URDF.
pub fn bench(spec: &ProblemSpec) -> Result<BenchRow, TranscriptionError> {
    bench_with(mechanics(spec)?, spec)
}

/// Benchmarks `spec` as [`bench`] does, for the given mechanics.
pub fn bench_with<M: MechanicsDerivatives>(
    mech: M,
    spec: &ProblemSpec,
) -> Result<BenchRow, TranscriptionError> {
    let spec = resolve_initial_guess(&mech, spec)?;
    transcription::bench_with(mech, &spec)
}

/// Asks Ipopt whether it takes every option of the problem (name, type, range), so that a
/// typo in `[solver.ipopt]` is an input error naming its line, before any solve.
pub fn check_solver_options(problem: &LoadedProblem) -> Result<(), ProblemError> {
    for (name, value) in &problem.spec.solver_options {
        ipopt::Solver::new()
            .set_option(name, value)
            .map_err(|e| problem.field_error(&format!("solver.ipopt.{name}"), e.to_string()))?;
    }
    Ok(())
}

/// Loads `file` with `overrides` and asks Ipopt about its options: what `vito check`,
/// `vito solve` and `vito simulate` (and Python's `vito.Problem`) start with.
pub fn load_checked(
    file: &std::path::Path,
    overrides: &[crate::problem::Override],
) -> Result<LoadedProblem, ProblemError> {
    let problem = crate::problem::load(file, overrides)?;
    check_solver_options(&problem)?;
    Ok(problem)
}

/// What `vito check` reports about the NLP `solve` builds.
#[derive(Debug, Clone)]
pub struct CheckReport {
    /// Variables, constraints and nonzeros.
    pub size: transcription::NlpSize,
    /// Friction directions per contact.
    pub friction_directions: usize,
    /// Loop-closure rows per interval.
    pub loop_rows: usize,
    /// Each contact's distance to the terrain at the ends of the initial guess, and warnings.
    pub feasibility: feasibility::Feasibility,
}

/// Builds the solver's NLP for `spec` and reports its size and the initial guess's contact
/// clearances and warnings (`vito check`).
pub fn check_report(spec: &ProblemSpec) -> Result<CheckReport, TranscriptionError> {
    let nlp = build_nlp(spec)?;
    Ok(CheckReport {
        size: nlp.size(),
        friction_directions: nlp.layout().nd,
        loop_rows: nlp.layout().nl,
        feasibility: feasibility::feasibility(spec, &nlp),
    })
}

pub mod dynamics;
pub mod feasibility;
pub mod gains;
pub mod kinematics;
pub mod levels;
pub mod mujoco;
pub mod output;
pub mod simulation;
pub mod trajectory_point;
