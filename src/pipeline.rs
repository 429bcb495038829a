//! The steps `vito check`, `vito solve` and `vito bench` run on a loaded problem, in one place
//! so that what `check` reports is what `solve` builds: Ipopt's verdict on the problem's
//! options, the robot's mechanics, the solver's NLP and its size, the solve itself.

use std::path::{Path, PathBuf};

use crate::ipopt;
use crate::problem::{LoadedProblem, ProblemError, ProblemSpec};
use crate::transcription::{
    self, BenchRow, MechanicsDerivatives, ModelMechanics, Solution, SolveOptions, Transcription,
    TranscriptionError,
};

/// The robot of `spec` as the transcription sees it (URDF model, gravity, contacts).
pub fn mechanics(spec: &ProblemSpec) -> Result<ModelMechanics, TranscriptionError> {
    ModelMechanics::load(spec)
}

/// The solver's NLP for `spec`, built as [`solve`] builds it.
pub fn build_nlp(spec: &ProblemSpec) -> Result<Transcription<ModelMechanics>, TranscriptionError> {
    Transcription::new(mechanics(spec)?, spec)
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

/// The NLP point a trajectory CSV (as `vito solve` writes it, with one row per knot of this
/// problem) describes: q, h from the times, u, the normal and friction impulses and the
/// slacks from their columns where present; ψ, η and anything absent keep the NLP's initial
/// guess. The message names the column or the row count at fault.
pub fn point_from_trajectory<M: MechanicsDerivatives>(
    nlp: &Transcription<M>,
    robot: &crate::problem::RobotInfo,
    contacts: &[String],
    text: &str,
) -> Result<Vec<f64>, String> {
    use crate::trajectory_csv::{friction_direction_names, read_csv, read_trajectory};
    let l = nlp.layout();
    let recorded = read_trajectory(text, &robot.coordinates, &robot.inputs)?;
    if recorded.times.len() != l.knots {
        return Err(format!(
            "it has {} rows, the problem has {} knots (run the problem with `--set knots={}`, or solve it first)",
            recorded.times.len(),
            l.knots,
            recorded.times.len()
        ));
    }
    let table = read_csv(text)?;
    let mut x = nlp.initial_point().to_vec();
    for (k, q) in recorded.q.iter().enumerate() {
        for (i, v) in l.q(k).zip(q) {
            x[i] = *v;
        }
    }
    for j in 0..l.intervals() {
        x[l.h(j)] = recorded.times[j + 1] - recorded.times[j];
        if let Some(u) = recorded.u.get(j) {
            for (i, v) in l.u(j).zip(u) {
                x[i] = *v;
            }
        }
    }
    let set = |x: &mut Vec<f64>, column: &str, index: &dyn Fn(usize) -> usize| {
        if let Some(values) = table.column(column) {
            for (j, v) in values.iter().take(l.intervals()).enumerate() {
                if v.is_finite() {
                    x[index(j)] = *v;
                }
            }
        }
    };
    let directions = friction_direction_names(l.nd);
    for (i, name) in contacts.iter().enumerate() {
        set(&mut x, &format!("{name}_normal"), &|j| l.c(j, i));
        for (d, dir) in directions.iter().enumerate() {
            set(&mut x, &format!("{name}_friction_{dir}"), &|j| {
                l.beta(j, i).start + d
            });
        }
    }
    set(&mut x, "slack", &|j| l.slack(j).start);
    for s in 0..l.slacks_per_interval() {
        set(&mut x, &format!("slack_{s}"), &|j| l.slack(j).start + s);
    }
    Ok(x)
}
