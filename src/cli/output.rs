//! Writing to standard output and standard error: control characters escaped, a broken
//! pipe the end of the output, a failed write remembered for the exit code.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

use vito::problem::RobotInfo;

use super::error::CliError;

/// Whether a write failed because its reader has gone (`vito check x | head -1`): the
/// rest of that stream's output is dropped, and the command still does its work and exits
/// with its own code (a broken pipe is neither a success nor a failure of the command).
pub(super) fn is_broken_pipe(e: &std::io::Error) -> bool {
    e.kind() == std::io::ErrorKind::BrokenPipe
}

/// Set when standard output or standard error could not be written (other than a closed
/// pipe).
pub(super) static OUTPUT_FAILED: AtomicBool = AtomicBool::new(false);

/// Set once standard output's reader has gone.
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// Writes one line to stderr (see [`note!`]).
pub(crate) fn write_stderr(line: &str) {
    let mut stderr = std::io::stderr().lock();
    if let Err(e) = writeln!(stderr, "{}", vito::files::names::escape_controls(line))
        .and_then(|()| stderr.flush())
        && !is_broken_pipe(&e)
    {
        OUTPUT_FAILED.store(true, Ordering::SeqCst);
    }
}

/// Writes one line to stdout (see [`out!`]).
pub(super) fn write_stdout(line: &str) -> Result<(), CliError> {
    if STDOUT_CLOSED.load(Ordering::SeqCst) {
        return Ok(());
    }
    let mut stdout = std::io::stdout().lock();
    let result = writeln!(stdout, "{}", vito::files::names::escape_controls(line))
        .and_then(|()| stdout.flush());
    match result {
        Ok(()) => Ok(()),
        Err(e) if is_broken_pipe(&e) => {
            STDOUT_CLOSED.store(true, Ordering::SeqCst);
            Ok(())
        }
        Err(e) => {
            OUTPUT_FAILED.store(true, Ordering::SeqCst);
            Err(CliError::Output(e.to_string()))
        }
    }
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
