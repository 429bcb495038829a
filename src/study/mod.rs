//! The paper's accuracy studies (figures 5 and 6): the first-order (semi-implicit Euler)
//! and the variational (midpoint) time-stepping methods compared at a range of knot counts.
//!
//! Where things are: `brick` (figure 5: open-loop tumbling brick against a 2 kHz first-order
//! reference), `table` (the per-knot-count table, its CSV and its SVG, and the log-log slope
//! fit), `tracking` (figure 6: plans of both methods tracked by PD control in a 2 kHz
//! first-order simulation), `collect` (figure 6 over a set of gaits: several tracking
//! studies' directories read back into one table), `frontier` (a tracking study's plans:
//! error at the knots against solve cost, per method).

pub mod brick;
pub mod collect;
pub mod frontier;
pub mod table;
pub mod tracking;

pub use table::{
    METHODS, PAPER_METHODS, StudyMethod, StudyRow, StudyTable, log_log_slope, table_order,
};

/// Why a study stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StudyError {
    /// A study option is invalid.
    #[error("{field}: {message}")]
    Invalid {
        /// The option.
        field: String,
        /// What is wrong and the fix.
        message: String,
    },
    /// The problem could not be set up.
    #[error(transparent)]
    Transcription(#[from] crate::transcription::TranscriptionError),
    /// A simulation failed.
    #[error("{what}: {source}")]
    Simulation {
        /// Which run.
        what: String,
        /// Why.
        source: crate::sim::SimulationError,
    },
    /// A plan was not solved.
    #[error("{what}: {message}")]
    Plan {
        /// Which plan.
        what: String,
        /// Why.
        message: String,
    },
    /// A table could not be written.
    #[error("{path}: {source}")]
    Write {
        /// The file.
        path: std::path::PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// A plot could not be drawn or written.
    #[error("{path}: {source}")]
    Plot {
        /// The file.
        path: std::path::PathBuf,
        /// Why.
        source: crate::report::PlotError,
    },
}

impl StudyError {
    /// The error of a table `path` that could not be written.
    pub(crate) fn write(path: &std::path::Path) -> impl FnOnce(std::io::Error) -> StudyError {
        let path = path.to_owned();
        move |source| StudyError::Write { path, source }
    }

    /// The error of a plot `path` that could not be drawn or written.
    pub(crate) fn plot(
        path: &std::path::Path,
    ) -> impl FnOnce(crate::report::PlotError) -> StudyError {
        let path = path.to_owned();
        move |source| StudyError::Plot { path, source }
    }
}
