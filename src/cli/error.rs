//! What ends a command early, and the exit codes.

use vito::problem::ProblemError;
use vito::report;

/// Exit code: solved (check, inspect, regress: passed).
pub const EXIT_OK: u8 = 0;
/// Exit code: finished but not solved.
pub const EXIT_NOT_SOLVED: u8 = 1;
/// Exit code: input or usage error (clap's usage errors are 2 as well), and a file or process
/// the operating system refuses for another reason than a full or read-only disk.
pub const EXIT_INPUT: u8 = 2;
/// Exit code: internal error (a bug, or the solver failing to start).
pub const EXIT_INTERNAL: u8 = 3;
/// Exit code: output could not be written: standard output or standard error, or a result
/// file on a full or read-only disk.
pub const EXIT_OUTPUT: u8 = 4;

/// Every exit code vito returns and what it means: the one table behind `--help` and the
/// README's.
pub const EXIT_CODE_TABLE: [(u8, &str); 5] = [
    (EXIT_OK, "solved (check, inspect, regress: passed)"),
    (
        EXIT_NOT_SOLVED,
        "finished but not solved (not optimal, relaxed_contact); stopped by a signal (Ctrl-C, SIGTERM, SIGHUP); a sweep with a run that did not solve or was stopped; sweep collect with points missing; regress: a result differs",
    ),
    (
        EXIT_INPUT,
        "input or usage error (the message names the file, line and field), found before solving; also a problem regress cannot set up, and a path or process the system refuses (a name too long, a missing directory)",
    ),
    (EXIT_INTERNAL, "internal error"),
    (
        EXIT_OUTPUT,
        "output could not be written: standard output or error (`> /dev/full`; the result files were written; a reader that goes away, as in `| head`, only ends that output), or a result file (a full disk or quota, a file-size limit, a read-only file system; the results already there are kept)",
    ),
];

/// Everything that ends a command early; the variant, and an operating-system error in its
/// chain of causes, decide the exit code ([`CliError::exit_code`]).
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    #[error(transparent)]
    Problem(#[from] ProblemError),
    #[error("{0}")]
    Input(String),
    /// A file the command reads or writes itself: the operating system's error decides.
    #[error("{what}: {source}")]
    Io {
        /// The file and what was done with it, as the message names it.
        what: String,
        source: std::io::Error,
    },
    #[error(transparent)]
    Report(#[from] report::ReportError),
    #[error(transparent)]
    Golden(#[from] report::GoldenError),
    #[error(transparent)]
    Regress(#[from] vito::regress::RegressError),
    #[error("internal error: {0}")]
    Internal(String),
    /// Nothing to write: every start of a parallel multi-start ended without a result.
    #[error("{0}")]
    NoResult(String),
    #[error("cannot write to standard output: {0}")]
    Output(String),
    #[error(transparent)]
    Sweep(#[from] vito::sweep::SweepError),
    #[error("simulation stopped: {0}")]
    Simulation(#[from] vito::sim::SimulationError),
    #[error(transparent)]
    Transcription(#[from] vito::transcription::TranscriptionError),
    #[error("study: {0}")]
    Study(#[from] vito::study::StudyError),
}

impl CliError {
    /// The error of a file `path` that could not be read or written.
    pub(super) fn io(path: &std::path::Path) -> impl FnOnce(std::io::Error) -> CliError {
        let what = path.display().to_string();
        move |source| CliError::Io { what, source }
    }

    /// The exit code: 3 only for a bug (or the solver failing to start); an operating-system
    /// error anywhere in the chain is the user's path or environment (2), or output that could
    /// not be written (4, [`io_exit_code`]); otherwise the variant's.
    pub fn exit_code(&self) -> u8 {
        use vito::study::StudyError;
        use vito::sweep::SweepError;
        use vito::transcription::TranscriptionError;
        match self {
            CliError::Internal(_)
            | CliError::Transcription(TranscriptionError::Solver(_))
            | CliError::Sweep(SweepError::Internal(_)) => return EXIT_INTERNAL,
            CliError::Output(_) => return EXIT_OUTPUT,
            CliError::Simulation(_) | CliError::NoResult(_) => return EXIT_NOT_SOLVED,
            _ => {}
        }
        if let Some(e) = io_cause(self) {
            return io_exit_code(e);
        }
        match self {
            // A plot plotters could not draw (not a file it could not write).
            CliError::Report(report::ReportError::Plot { .. })
            | CliError::Study(StudyError::Plot { .. }) => EXIT_INTERNAL,
            CliError::Study(StudyError::Simulation { .. } | StudyError::Plan { .. }) => {
                EXIT_NOT_SOLVED
            }
            _ => EXIT_INPUT,
        }
    }
}

/// The first operating-system error in the chain of `e`'s causes (`e` itself included).
fn io_cause<'a>(e: &'a (dyn std::error::Error + 'static)) -> Option<&'a std::io::Error> {
    let mut next = Some(e);
    while let Some(cause) = next {
        if let Some(io) = cause.downcast_ref::<std::io::Error>() {
            return Some(io);
        }
        next = cause.source();
    }
    None
}

/// The exit code of an operating-system error: a disk that takes no more (full, over quota or
/// a file-size limit, read-only) is unwritable output ([`EXIT_OUTPUT`]); anything else (a
/// missing or unreadable file, a name too long or holding a NUL byte, a process that cannot
/// start) is the user's path or environment ([`EXIT_INPUT`]), never a bug.
pub fn io_exit_code(e: &std::io::Error) -> u8 {
    use std::io::ErrorKind;
    match e.kind() {
        ErrorKind::StorageFull
        | ErrorKind::QuotaExceeded
        | ErrorKind::FileTooLarge
        | ErrorKind::ReadOnlyFilesystem
        | ErrorKind::WriteZero => EXIT_OUTPUT,
        _ => EXIT_INPUT,
    }
}
