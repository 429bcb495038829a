//! Errors of reading and checking a problem file: each names the file, line and field.

use std::fmt;
use std::path::PathBuf;

/// Where in a problem file something is: file, 1-based line (when known) and TOML path.
#[derive(Debug, Clone, PartialEq)]
pub struct Location {
    pub file: PathBuf,
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
    #[error("cannot read problem file {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{at}: TOML syntax error: {message}")]
    Syntax { at: Box<Location>, message: String },
    #[error("{at}: unknown {what} `{key}`{}; valid {what}s here: {valid}", did_you_mean(.suggestion))]
    UnknownKey {
        at: Box<Location>,
        /// `key`, or `value` for a tag such as a cost `type`.
        what: &'static str,
        key: String,
        suggestion: Option<String>,
        valid: String,
    },
    #[error("{at}: {message}")]
    Invalid { at: Box<Location>, message: String },
    #[error("{at}: unknown {kind} `{name}`{}; the {kind}s are: {valid}", did_you_mean(.suggestion))]
    UnknownName {
        at: Box<Location>,
        kind: &'static str,
        name: String,
        suggestion: Option<String>,
        valid: String,
    },
    #[error("{at}: {source}")]
    Robot {
        at: Box<Location>,
        source: crate::problem::RobotError,
    },
    #[error("--set {arg}: {message}")]
    Override { arg: String, message: String },
    #[error("{at}: warm start {path}: {message}")]
    WarmStart {
        at: Box<Location>,
        path: PathBuf,
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

/// Lists names for a message, at most `max` of them.
pub fn list_names<S: AsRef<str>>(names: &[S], max: usize) -> String {
    let mut out: Vec<String> = names
        .iter()
        .take(max)
        .map(|n| format!("`{}`", n.as_ref()))
        .collect();
    if names.len() > max {
        out.push(format!("… ({} in all)", names.len()));
    }
    if out.is_empty() {
        "(none)".into()
    } else {
        out.join(", ")
    }
}
