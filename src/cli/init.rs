//! `vito init`: a starter problem from a URDF.

use std::io::Write;
use std::path::{Path, PathBuf};

use vito::model::BaseType;
use vito::problem::RobotInfo;
use vito::report;

use super::error::CliError;
use super::output::is_broken_pipe;

/// The regular file standard output is redirected to, if it is one (Linux's /proc).
pub(super) fn stdout_file() -> Option<PathBuf> {
    let target = std::fs::read_link("/proc/self/fd/1").ok()?;
    std::fs::metadata(&target)
        .ok()
        .filter(std::fs::Metadata::is_file)
        .map(|_| target)
}

pub(super) fn init(urdf: &Path, base: BaseType, out: Option<&Path>) -> Result<u8, CliError> {
    let robot = RobotInfo::read(urdf, base, &vito::model::Actuation::Default)
        .map_err(|e| CliError::Input(e.to_string()))?;
    let model = vito::model::Model::from_urdf_file(urdf, base)
        .map_err(|e| CliError::Input(vito::model::describe(urdf, &e)))?;
    if model.nq() == 0 {
        return Err(CliError::Input(format!(
            "{}: with a fixed base the robot has no coordinates (no moving joints); choose \
             --base floating or --base planar",
            urdf.display()
        )));
    }
    let urdf_text = match out {
        Some(_) => vito::files::paths::reference_from(urdf, out),
        // Printed: relative to the file stdout goes to, when it is one; else absolute, so
        // that the text names the URDF wherever it is saved.
        None => match stdout_file() {
            Some(file) => vito::files::paths::reference_from(urdf, Some(&file)),
            None => std::path::absolute(urdf)
                .unwrap_or_else(|_| urdf.to_owned())
                .display()
                .to_string(),
        },
    };
    let text = vito::problem::starter_problem(&model, &robot, base, &urdf_text);
    match out {
        None => {
            let mut stdout = std::io::stdout().lock();
            let written = stdout
                .write_all(vito::files::names::escape_controls(&text).as_bytes())
                .and_then(|()| stdout.flush());
            if let Err(e) = written
                && !is_broken_pipe(&e)
            {
                return Err(CliError::Output(e.to_string()));
            }
        }
        Some(path) => {
            let cannot = |e: std::io::Error| {
                CliError::Input(if e.kind() == std::io::ErrorKind::AlreadyExists {
                    format!(
                        "{} exists (a file, directory or link); vito init never overwrites or \
                         follows one (choose another --out)",
                        path.display()
                    )
                } else {
                    match path
                        .parent()
                        .filter(|d| !d.as_os_str().is_empty() && !d.exists())
                    {
                        Some(dir) => format!(
                            "cannot write {}: the directory {} does not exist (create it first: \
                             mkdir -p {})",
                            path.display(),
                            dir.display(),
                            dir.display()
                        ),
                        None => format!("cannot write {}: {e}", path.display()),
                    }
                })
            };
            let mut file = report::create_new_file(path).map_err(cannot)?;
            if let Err(e) = file.write_all(text.as_bytes()) {
                // The half-written file is the one just created.
                let _ = std::fs::remove_file(path);
                return Err(CliError::io(path)(e));
            }
            note!("wrote {}", path.display());
        }
    }
    Ok(0)
}
