//! Writing to standard output and standard error: control characters escaped, a broken
//! pipe the end of the output, a failed write remembered for the exit code.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

use vito::problem::RobotInfo;

use super::error::CliError;

/// A closed stdout (`vito check x | head -1`) ends the command quietly with success,
/// like ripgrep; any other write error is left to the caller.
pub(super) fn exit_quietly_on_broken_pipe(e: &std::io::Error) {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
}

/// Set when standard output or standard error could not be written.
pub(super) static OUTPUT_FAILED: AtomicBool = AtomicBool::new(false);

/// Writes one line to stderr (see [`note!`]).
pub(crate) fn write_stderr(line: &str) {
    let mut stderr = std::io::stderr().lock();
    if writeln!(stderr, "{}", vito::files::names::escape_controls(line))
        .and_then(|()| stderr.flush())
        .is_err()
    {
        OUTPUT_FAILED.store(true, Ordering::SeqCst);
    }
}

/// Writes one line to stdout (see [`out!`]).
pub(super) fn write_stdout(line: &str) -> Result<(), CliError> {
    let mut stdout = std::io::stdout().lock();
    let result = writeln!(stdout, "{}", vito::files::names::escape_controls(line))
        .and_then(|()| stdout.flush());
    result.map_err(|e| {
        exit_quietly_on_broken_pipe(&e);
        OUTPUT_FAILED.store(true, Ordering::SeqCst);
        CliError::Output(e.to_string())
    })
}

/// The URDF's warnings; with `has_contacts` (the problem gives its contacts) without the
/// advice to add sphere collisions.
pub(super) fn print_model_warnings(robot: &RobotInfo, has_contacts: bool) {
    for w in &robot.warnings {
        let w = match w.strip_suffix(vito::model::SPHERE_HINT) {
            Some(fact) if has_contacts => fact,
            _ => w,
        };
        note!("warning: {}: {w}", robot.urdf.display());
    }
}

/// The error and its chain of causes (each once), on stderr.
pub(super) fn print_error(e: &CliError) {
    let mut message = format!("error: {e}");
    let mut source = std::error::Error::source(e);
    while let Some(s) = source {
        let text = s.to_string();
        if !message.contains(&text) {
            message.push_str(&format!("\n  caused by: {text}"));
        }
        source = s.source();
    }
    write_stderr(&message);
}
