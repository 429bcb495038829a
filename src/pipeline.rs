//! The steps `vito check`, `vito solve` and `vito bench` run on a loaded problem, in one place
//! so that what `check` reports is what `solve` builds: Ipopt's verdict on the problem's
//! options, the robot's mechanics, the solver's NLP and its size, the solve itself.

use std::path::{Path, PathBuf};

use crate::ipopt;
use crate::problem::{HessianMode, LoadedProblem, ProblemError, ProblemSpec};
use crate::transcription::{
    self, BenchRow, MechanicsDerivatives, ModelMechanics, NlpSize, Solution, SolveOptions,
    Transcription, TranscriptionError,
};

/// The robot of `spec` as the transcription sees it (URDF model, gravity, contacts).
pub fn mechanics(spec: &ProblemSpec) -> Result<ModelMechanics, TranscriptionError> {
    ModelMechanics::load(spec)
}

/// The solver's NLP for `spec`, built as [`solve`] builds it.
pub fn build_nlp(spec: &ProblemSpec) -> Result<Transcription<ModelMechanics>, TranscriptionError> {
    Transcription::new(mechanics(spec)?, spec)
}

/// The NLP's size as Ipopt sees it: variables, rows, Jacobian and lower-Hessian nonzeros
/// (none with an L-BFGS Hessian, which Ipopt then never asks for).
pub fn nlp_size<M: MechanicsDerivatives>(nlp: &Transcription<M>) -> NlpSize {
    NlpSize {
        n_variables: nlp.layout().num_variables(),
        n_constraints: nlp.layout().num_constraints(),
        nnz_jacobian: nlp.jacobian_pattern().nnz(),
        nnz_hessian: match nlp.hessian_mode() {
            HessianMode::Exact => nlp.hessian_pattern().nnz(),
            HessianMode::Lbfgs => 0,
        },
    }
}

/// Solves `spec` with the robot from its URDF.
pub fn solve(spec: &ProblemSpec, options: &SolveOptions) -> Result<Solution, TranscriptionError> {
    transcription::solve_with(mechanics(spec)?, spec, options)
}

/// The reference problems of SPEC.md, as `vito bench` runs them by default.
pub const REFERENCE_PROBLEMS: [&str; 4] = [
    "problems/hopper_2d.toml",
    "problems/brick_3d.toml",
    "problems/spring_flamingo_walk.toml",
    "problems/littledog_step.toml",
];

/// Benchmarks `spec` (sizes, one derivative evaluation, a full solve) with the robot from its
/// URDF.
pub fn bench(spec: &ProblemSpec) -> Result<BenchRow, TranscriptionError> {
    transcription::bench_with(mechanics(spec)?, spec)
}

/// Asks Ipopt whether it takes every option of the problem (name, type, range), so that a
/// typo in `[solver.ipopt]` is an input error naming its line, before any solve.
pub fn check_solver_options(problem: &LoadedProblem) -> Result<(), ProblemError> {
    for (name, value) in &problem.spec.solver_options {
        let value = ipopt::OptionValue::from(value);
        ipopt::Solver::new()
            .set_option(name, value)
            .map_err(|e| problem.field_error(&format!("solver.ipopt.{name}"), e.to_string()))?;
    }
    Ok(())
}

/// Where `vito solve` writes: `--out` if given, else the file's `output.dir`, else
/// `out/<problem name>`.
pub fn output_dir(problem: &LoadedProblem, out: Option<&Path>) -> PathBuf {
    match (out, &problem.output_dir) {
        (Some(o), _) => o.to_owned(),
        (None, Some(d)) => d.clone(),
        (None, None) => PathBuf::from("out").join(&problem.spec.name),
    }
}

/// [`output_dir`] checked before any solving against the rule of
/// [`crate::report::OutputTarget`]: only vito's own results or an empty directory are
/// replaced, and never the current directory or one holding the problem file or its robot.
pub fn checked_output_dir(
    problem: &LoadedProblem,
    out: Option<&Path>,
) -> Result<crate::report::OutputTarget, crate::report::OutputDirError> {
    let target = output_dir(problem, out);
    crate::report::OutputTarget::check(&target, &[&problem.file, &problem.spec.robot.urdf])
}
