//! What ends a command early, and the exit codes.

use vito::problem::ProblemError;
use vito::report;

/// Exit code: solved (check, inspect, regress: passed).
pub const EXIT_OK: u8 = 0;
/// Exit code: finished but not solved.
pub const EXIT_NOT_SOLVED: u8 = 1;
/// Exit code: input or usage error (clap's usage errors are 2 as well).
pub const EXIT_INPUT: u8 = 2;
/// Exit code: internal error (a bug, or the solver failing to start).
pub const EXIT_INTERNAL: u8 = 3;
/// Exit code: standard output or standard error could not be written.
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
        "input or usage error (the message names the file, line and field), found before solving; also a problem regress cannot set up",
    ),
    (EXIT_INTERNAL, "internal error"),
    (
        EXIT_OUTPUT,
        "standard output or error could not be written (a full disk, `> /dev/full`); the result files were written",
    ),
];

/// Everything that ends a command early; the variant decides the exit code.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    #[error(transparent)]
    Problem(#[from] ProblemError),
    #[error("{0}")]
    Input(String),
    #[error(transparent)]
    Report(#[from] report::ReportError),
    #[error(transparent)]
    Golden(#[from] report::GoldenError),
    #[error("internal error: {0}")]
    Internal(String),
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
    /// Exit code: 2 for input errors, 3 for internal ones.
    pub fn exit_code(&self) -> u8 {
        match self {
            // Like an output directory that cannot be written: the user's redirection.
            CliError::Problem(_) | CliError::Input(_) | CliError::Golden(_) => EXIT_INPUT,
            CliError::Output(_) => EXIT_OUTPUT,
            CliError::Transcription(e) => match e {
                vito::transcription::TranscriptionError::Solver(_) => 3,
                _ => 2,
            },
            // A target vito may not replace is the user's input, found before solving.
            CliError::Report(report::ReportError::Output(
                report::OutputDirError::NotOurs { .. }
                | report::OutputDirError::Protected { .. }
                | report::OutputDirError::Invalid { .. },
            )) => 2,
            CliError::Sweep(e) => match e {
                vito::sweep::SweepError::Usage(_)
                | vito::sweep::SweepError::NotOurs { .. }
                | vito::sweep::SweepError::Link { .. }
                | vito::sweep::SweepError::NoTable { .. }
                | vito::sweep::SweepError::Table { .. } => 2,
                _ => 3,
            },
            CliError::Report(_) | CliError::Internal(_) => 3,
            CliError::Simulation(_) => 1,
            CliError::Study(e) => match e {
                vito::study::StudyError::Invalid { .. }
                | vito::study::StudyError::Transcription(_) => 2,
                vito::study::StudyError::Write { .. } => 3,
                _ => 1,
            },
        }
    }
}
