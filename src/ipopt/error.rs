//! What can go wrong when setting options or running a solve (not how a solve ended: that
//! is [`super::Status`]).

/// An error from the Ipopt wrapper; each variant names what to fix.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IpoptError {
    /// Ipopt rejected an option: unknown name, wrong type or value out of range.
    #[error("Ipopt option `{name}` = {value} is invalid: {reason}")]
    InvalidOption {
        /// Option name as given.
        name: String,
        /// Value as given.
        value: String,
        /// Why it was rejected.
        reason: String,
    },
    /// An option the wrapper refuses before Ipopt sees it, because Debian's Ipopt would fail
    /// or end the process with it.
    #[error("Ipopt option `{name}` = {value} is refused: {reason}")]
    Refused {
        /// Option name as given.
        name: String,
        /// Value as given.
        value: String,
        /// Why, and what to use instead.
        reason: String,
    },
    /// A method of the problem panicked; the solve was stopped and the panic kept.
    #[error("the problem's `{callback}` panicked during the solve: {message}")]
    CallbackPanicked {
        /// Name of the `Nlp` method that panicked.
        callback: &'static str,
        /// The panic message (or a note that the payload was not a string).
        message: String,
    },
    /// The problem's sizes, bounds, starting point or sparsity cannot be handed to Ipopt.
    #[error("invalid problem for Ipopt: {what}")]
    InvalidProblem {
        /// What is wrong, with the index and values involved.
        what: String,
    },
    /// `solve` or `set_option` was called from inside a callback of a running solve on the
    /// same thread (Ipopt is not re-entrant; the global solve lock would deadlock).
    #[error("an Ipopt solve is already running on this thread (called from inside a callback?)")]
    NestedSolve,
    /// `CreateIpoptProblem` returned null.
    #[error("Ipopt could not create the problem (CreateIpoptProblem returned null)")]
    CreateFailed,
    /// `IpoptSolve` returned a code that the Ipopt built against does not define.
    #[error("Ipopt returned the unknown status code {code}")]
    UnknownStatus {
        /// The raw `ApplicationReturnStatus` value.
        code: i32,
    },
}
