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
    /// Writing the table or plot failed.
    #[error("{path}: {message}")]
    Write {
        /// The file.
        path: std::path::PathBuf,
        /// Why.
        message: String,
    },
}
