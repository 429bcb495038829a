//! Errors of building and solving a transcription.

use thiserror::Error;

/// Why a problem could not be transcribed or solved.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum TranscriptionError {
    /// A vector in the problem has the wrong length for the model.
    #[error("problem field `{field}` has length {found}, but the model needs {expected}")]
    Length {
        /// The problem field.
        field: String,
        /// Length the model needs.
        expected: usize,
        /// Length given.
        found: usize,
    },
    /// Bounds on one coordinate at one knot leave no feasible value.
    #[error(
        "coordinate {coordinate} at knot {knot} has empty bounds [{lower}, {upper}]: \
         check `bounds`, `q_final` and the URDF joint limits"
    )]
    EmptyBound {
        /// Coordinate index.
        coordinate: usize,
        /// Knot index (0-based).
        knot: usize,
        /// Lower bound after intersection.
        lower: f64,
        /// Upper bound after intersection.
        upper: f64,
    },
    /// A problem value is out of range.
    #[error("problem field `{field}`: {message}")]
    Invalid {
        /// The problem field.
        field: String,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// The robot model could not be loaded.
    #[error(transparent)]
    Model(#[from] crate::model::ModelError),
    /// Ipopt refused an option or failed to run.
    #[error(transparent)]
    Solver(#[from] crate::ipopt::IpoptError),
}

/// `Ok` when a given length `found` is the `expected` one, else the error naming `field`.
pub(super) fn check_len(
    field: &str,
    expected: usize,
    found: usize,
) -> Result<(), TranscriptionError> {
    if expected == found {
        Ok(())
    } else {
        Err(TranscriptionError::Length {
            field: field.to_string(),
            expected,
            found,
        })
    }
}
