//! Errors of reading and checking a problem file: each names the file, line and field.

#![warn(missing_docs)]

use std::fmt;
use std::path::PathBuf;

pub use crate::files::names::list_names;

/// Where in a problem file something is: file, 1-based line (when known) and TOML path.
#[derive(Debug, Clone, PartialEq)]
pub struct Location {
    /// The problem file.
    pub file: PathBuf,
    /// 1-based line, when the field is written in the file.
    pub line: Option<usize>,
    /// TOML path such as `contacts.point[1].link`; empty for the whole file.
    pub field: String,
    /// Set when the value came from `--set` rather than the file.
    pub from_override: bool,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if !self.field.is_empty() {
            write!(f, ": field `{}`", self.field)?;
        }
        if self.from_override {
            write!(f, " (set with --set)")?;
        }
        Ok(())
    }
}

/// Formats ", did you mean `x`?" or nothing.
fn did_you_mean(s: &Option<String>) -> String {
    match s {
        Some(s) => format!(", did you mean `{s}`?"),
        None => String::new(),
    }
}

/// A problem file that cannot become a `ProblemSpec`.
#[derive(Debug, thiserror::Error)]
pub enum ProblemError {
    /// The problem file could not be read.
    #[error("cannot read problem file {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The file is not valid TOML.
    #[error("{at}: TOML syntax error: {message}")]
    Syntax {
        /// Where.
        at: Box<Location>,
        /// The TOML parser's message.
        message: String,
    },
    #[error("{at}: unknown {what} `{key}`{}; valid {what}s here: {valid}", did_you_mean(.suggestion))]
    /// A key (or a tag value such as a cost `type`) that the schema does not have.
    UnknownKey {
        /// Where.
        at: Box<Location>,
        /// `key`, or `value` for a tag such as a cost `type`.
        what: &'static str,
        /// The unknown key.
        key: String,
        /// The nearest valid key, if close.
        suggestion: Option<String>,
        /// The valid keys, listed for the message.
        valid: String,
    },
    /// A value the checks reject.
    #[error("{at}: {message}")]
    Invalid {
        /// Where.
        at: Box<Location>,
        /// What is wrong and how to fix it.
        message: String,
    },
    #[error("{at}: unknown {kind} `{name}`{}; the {kind}s are: {valid}", did_you_mean(.suggestion))]
    /// A coordinate, input, contact or link name the robot does not have.
    UnknownName {
        /// Where.
        at: Box<Location>,
        /// What kind of name (`coordinate`, `input`, ...).
        kind: &'static str,
        /// The unknown name.
        name: String,
        /// The nearest valid name, if close.
        suggestion: Option<String>,
        /// The valid names, listed for the message.
        valid: String,
    },
    #[error("{at}: {source}")]
    /// The robot's URDF could not be loaded.
    Robot {
        /// Where the URDF is named.
        at: Box<Location>,
        /// Why it failed.
        source: crate::problem::RobotError,
    },
    #[error("--set {arg}: {message}")]
    /// A `--set` argument that cannot be applied.
    Override {
        /// The argument as given.
        arg: String,
        /// What is wrong.
        message: String,
    },
    #[error("{at}: warm start {path}: {message}")]
    /// The warm-start trajectory could not be used.
    WarmStart {
        /// Where it is named.
        at: Box<Location>,
        /// The CSV file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

impl ProblemError {
    /// The location in the problem file, when the error has one.
    pub fn location(&self) -> Option<&Location> {
        match self {
            ProblemError::Syntax { at, .. }
            | ProblemError::UnknownKey { at, .. }
            | ProblemError::Invalid { at, .. }
            | ProblemError::UnknownName { at, .. }
            | ProblemError::Robot { at, .. }
            | ProblemError::WarmStart { at, .. } => Some(at.as_ref()),
            ProblemError::Io { .. } | ProblemError::Override { .. } => None,
        }
    }
}
