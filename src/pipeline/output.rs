//! Where `vito solve` writes, checked before any solving.

use std::path::{Path, PathBuf};

use crate::problem::LoadedProblem;

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
