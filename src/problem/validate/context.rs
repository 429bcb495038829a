//! The file being checked, and how an error names the place in it (line, field, whether an
//! override set it, the nearest valid name).

use std::path::PathBuf;

use crate::problem::error::list_names;
use crate::problem::source::{line_of_offset, line_of_path, nearest, path_at_offset};
use crate::problem::{Location, ProblemError};

/// The file being checked, for locating fields.
pub(crate) struct Context {
    /// The problem file.
    pub(crate) file: PathBuf,
    /// Its text (before overrides).
    pub(crate) text: String,
    /// The TOML paths that `--set` overrides.
    pub(crate) overridden: Vec<String>,
    /// The robot's URDF text when it comes from memory rather than from `robot.urdf`'s file
    /// (the fuzzer's [`crate::problem::load_from_str`]).
    pub(crate) urdf_text: Option<String>,
}

impl Context {
    pub(crate) fn at(&self, field: &str) -> Box<Location> {
        let from_override = self
            .overridden
            .iter()
            .any(|o| field == o || field.starts_with(&format!("{o}.")));
        Box::new(Location {
            file: self.file.clone(),
            line: if from_override {
                None
            } else {
                line_of_path(&self.text, field).or_else(|| parent_line(&self.text, field))
            },
            field: field.to_owned(),
            from_override,
        })
    }

    pub(crate) fn invalid(&self, field: &str, message: impl Into<String>) -> ProblemError {
        ProblemError::Invalid {
            at: self.at(field),
            message: message.into(),
        }
    }

    pub(crate) fn unknown_name(
        &self,
        field: &str,
        kind: &'static str,
        name: &str,
        valid: &[String],
    ) -> ProblemError {
        ProblemError::UnknownName {
            at: self.at(field),
            kind,
            name: name.to_owned(),
            suggestion: nearest(name, valid.iter().map(String::as_str)),
            valid: list_names(valid, 24),
        }
    }

    /// Turns a TOML/serde error on `parsed` (the file, or the file with overrides) into
    /// a located error; unknown keys get the nearest valid key.
    pub(crate) fn serde_error(&self, e: &toml::de::Error, parsed: &str) -> ProblemError {
        let message = plain_serde_message(e.message().trim());
        let span = e.span();
        let field = span
            .clone()
            .map(|s| path_at_offset(parsed, s.start))
            .unwrap_or_default();
        let mut at = if field.is_empty() {
            Box::new(Location {
                file: self.file.clone(),
                line: span
                    .map(|s| line_of_offset(parsed, s.start))
                    .filter(|_| parsed == self.text),
                field: String::new(),
                from_override: false,
            })
        } else {
            self.at(&field)
        };
        if at.line.is_none() && parsed == self.text {
            at.line = e.span().map(|s| line_of_offset(parsed, s.start));
        }
        for prefix in ["unknown field `", "unknown variant `"] {
            if let Some(rest) = message.strip_prefix(prefix) {
                let key = rest.split('`').next().unwrap_or_default().to_owned();
                let expected: Vec<String> = rest
                    .split_once("expected")
                    .map(|(_, list)| {
                        list.split('`')
                            .skip(1)
                            .step_by(2)
                            .map(str::to_owned)
                            .collect()
                    })
                    .unwrap_or_default();
                return ProblemError::UnknownKey {
                    at,
                    what: if prefix.contains("variant") {
                        "value"
                    } else {
                        "key"
                    },
                    suggestion: nearest(&key, expected.iter().map(String::as_str)),
                    key,
                    valid: list_names(&expected, 40),
                };
            }
        }
        if e.span().is_some() && message_is_syntax(&message) {
            return ProblemError::Syntax { at, message };
        }
        ProblemError::Invalid { at, message }
    }
}

/// serde's message in the problem file's words: a schema struct (`RobotSection`) is a table,
/// and a wrong-length 3-vector says which fields are 3-vectors.
fn plain_serde_message(message: &str) -> String {
    let mut out = message.to_owned();
    if let Some(at) = out.find("expected struct ") {
        out.replace_range(
            at..,
            "expected a table (a `[section]` or `{ key = value }`)",
        );
    }
    if out.starts_with("invalid length") && out.ends_with("expected an array of length 3") {
        out.push_str(
            " (3-vectors are `robot.gravity` and `contacts.point[].point`: give [x, y, z])",
        );
    }
    out
}

/// Errors of the TOML grammar rather than of the schema.
fn message_is_syntax(message: &str) -> bool {
    !(message.starts_with("missing field")
        || message.starts_with("invalid type")
        || message.starts_with("invalid value")
        || message.starts_with("invalid length")
        || message.starts_with("data did not match"))
}

/// Line of the nearest enclosing path that is in the file (for fields that are missing).
fn parent_line(text: &str, field: &str) -> Option<usize> {
    let mut path = field;
    while let Some(cut) = path.rfind(['.', '[']) {
        path = &path[..cut];
        if let Some(line) = line_of_path(text, path) {
            return Some(line);
        }
    }
    None
}
