//! The regression record of solved costs (`problems/golden.toml`) and its comparison.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// One problem's recorded result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GoldenEntry {
    /// Problem file, relative to the record's directory.
    pub file: String,
    /// Solved objective (problem cost + slack penalty).
    pub objective: f64,
    /// Allowed difference: |objective − recorded| ≤ tolerance · max(1, |recorded|).
    pub tolerance: f64,
    /// Ipopt status when recorded (snake case).
    pub status: String,
    /// Iterations when recorded (for information: they change with the mere order of rows).
    pub iterations: usize,
    /// Largest slack when recorded.
    pub max_slack: f64,
    /// What produced the numbers, e.g. `vito 0.1.0` or the independent CasADi implementation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// SHA-256 of the problem file blessed (`regress` says when the file has changed since).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub problem_sha256: Option<String>,
    /// The platform blessed on (operating system, architecture): another MUMPS or BLAS may
    /// reach another optimum, and `regress` says so beside a difference.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub platform: Option<String>,
    /// The objective's terms when recorded (name → value; empty in older records).
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub terms: std::collections::BTreeMap<String, f64>,
}

/// The whole record.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GoldenRecord {
    /// One entry per problem file.
    #[serde(default)]
    pub problem: Vec<GoldenEntry>,
}

/// Default relative tolerance of a blessed entry (the reference problems' objectives are compared to 1e-6).
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

const HEADER: &str = "# Regression record of solved costs, checked by `vito regress`.\n\
# Rewritten by `vito regress --bless` (do not edit by hand unless you mean it).\n\
# A check passes when the solve is solved (an Ipopt optimum with every slack within the\n\
# problem's [slack] tolerance) and |objective - recorded| <= tolerance * max(1, |recorded|);\n\
# iterations are for information only.\n\n";

/// Why the record could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum GoldenError {
    /// The record could not be read or written.
    #[error("cannot read regression record {path}: {source}")]
    Io {
        /// The record file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The record is not valid.
    #[error("regression record {path}: {message}")]
    Parse {
        /// The record file.
        path: PathBuf,
        /// The TOML parser's message.
        message: String,
    },
}

impl GoldenRecord {
    /// Reads a record; a missing file is an empty record.
    pub fn read(path: &Path) -> Result<GoldenRecord, GoldenError> {
        match crate::files::input::read_regular_text(path, crate::files::input::MAX_TEXT_BYTES) {
            Ok(text) => {
                // The parser's message and line, never its quote of the file: a record
                // named by mistake (a link to another file) is not shown.
                let record: GoldenRecord =
                    toml::from_str(&text).map_err(|e| GoldenError::Parse {
                        path: path.to_owned(),
                        message: crate::problem::toml_error_message(&text, &e),
                    })?;
                record.check().map_err(|message| GoldenError::Parse {
                    path: path.to_owned(),
                    message,
                })?;
                Ok(record)
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(GoldenRecord::default()),
            Err(source) => Err(GoldenError::Io {
                path: path.to_owned(),
                source,
            }),
        }
    }

    /// Every entry's numbers and status can be compared: a finite objective and slack, a
    /// finite tolerance ≥ 0, and a status Ipopt can return (snake case).
    fn check(&self) -> Result<(), String> {
        for (i, e) in self.problem.iter().enumerate() {
            let shown = crate::files::names::escape_controls(&e.file);
            let at = |field: &str, what: String| format!("problem[{i}].{field} ({shown}): {what}");
            if e.file.is_empty() || e.file.chars().any(crate::files::names::is_hidden_char) {
                return Err(at(
                    "file",
                    "a problem file's path is printable text, not empty and without control \
                     characters (such as a NUL byte)"
                        .into(),
                ));
            }
            if !(e.objective.is_finite() && e.objective.abs() <= 1e300) {
                return Err(at(
                    "objective",
                    format!("{} is not a finite number", e.objective),
                ));
            }
            if !(e.tolerance.is_finite() && e.tolerance >= 0.0) {
                let t = e.tolerance;
                return Err(at(
                    "tolerance",
                    format!("must be a finite number ≥ 0, got {t}"),
                ));
            }
            if !e.max_slack.is_finite() {
                let s = e.max_slack;
                return Err(at("max_slack", format!("{s} is not a finite number")));
            }
            let known = crate::ipopt::Status::ALL.map(|s| s.as_snake_case());
            if !known.contains(&e.status.as_str()) {
                return Err(at(
                    "status",
                    format!(
                        "`{}` is not an Ipopt status; one of: {}",
                        e.status,
                        known.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Writes the record atomically (a temporary file created exclusively beside it, then
    /// renamed over it). A record named through a symbolic link is refused: vito never writes
    /// through a link, and replacing the link would leave the record it names behind.
    pub fn write(&self, path: &Path) -> Result<(), GoldenError> {
        let body = toml::to_string(self).map_err(|e| GoldenError::Parse {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
        Self::check_writable(path)?;
        crate::files::output::write_atomic(path, format!("{HEADER}{body}").as_bytes()).map_err(
            |source| GoldenError::Io {
                path: path.to_owned(),
                source,
            },
        )
    }

    /// Refuses a record path that is a symbolic link (what [`GoldenRecord::write`] refuses),
    /// so that `--bless` can say so before solving anything.
    pub fn check_writable(path: &Path) -> Result<(), GoldenError> {
        if std::fs::symlink_metadata(path).is_ok_and(|m| m.is_symlink()) {
            return Err(GoldenError::Io {
                path: path.to_owned(),
                source: std::io::Error::new(
                    std::io::ErrorKind::InvalidInput,
                    "the record is a symbolic link and vito never writes through one; \
                     name the record file itself with --record",
                ),
            });
        }
        Ok(())
    }

    /// The entry for a problem file name.
    pub fn entry(&self, file: &str) -> Option<&GoldenEntry> {
        self.problem.iter().find(|e| e.file == file)
    }

    /// Inserts or replaces the entry for `entry.file`, keeping file order sorted.
    pub fn upsert(&mut self, entry: GoldenEntry) {
        self.problem.retain(|e| e.file != entry.file);
        self.problem.push(entry);
        self.problem.sort_by(|a, b| a.file.cmp(&b.file));
    }
}

/// How far a new largest slack may exceed the recorded one (problem units).
pub const SLACK_ALLOWANCE: f64 = 1e-6;

/// Whether a new largest slack is no worse than the recorded one (within
/// [`SLACK_ALLOWANCE`]).
pub fn slack_matches(entry: &GoldenEntry, max_slack: f64) -> bool {
    max_slack <= entry.max_slack.max(0.0) + SLACK_ALLOWANCE
}

/// The platform results are made on: operating system (`/etc/os-release`) and architecture.
pub fn platform() -> String {
    let os = std::fs::read_to_string("/etc/os-release")
        .ok()
        .and_then(|t| {
            t.lines()
                .find_map(|l| l.strip_prefix("PRETTY_NAME="))
                .map(|v| v.trim_matches('"').to_owned())
        })
        .unwrap_or_else(|| std::env::consts::OS.to_owned());
    format!("{os}, {}", std::env::consts::ARCH)
}

/// Whether `objective` matches the recorded one within its tolerance.
pub fn objective_matches(entry: &GoldenEntry, objective: f64) -> bool {
    (objective - entry.objective).abs() <= entry.tolerance * entry.objective.abs().max(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_compares() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("golden.toml");
        assert_eq!(GoldenRecord::read(&path).unwrap(), GoldenRecord::default());
        let mut record = GoldenRecord::default();
        let entry = GoldenEntry {
            file: "b.toml".into(),
            objective: 2.5,
            tolerance: 1e-6,
            status: "solve_succeeded".into(),
            iterations: 12,
            max_slack: 1e-9,
            source: None,
            problem_sha256: None,
            platform: None,
            terms: [
                ("input".to_owned(), 2.25),
                ("slack_penalty".to_owned(), 0.25),
            ]
            .into(),
        };
        record.upsert(entry.clone());
        record.upsert(GoldenEntry {
            file: "a.toml".into(),
            ..entry.clone()
        });
        record.write(&path).unwrap();
        let back = GoldenRecord::read(&path).unwrap();
        assert_eq!(back, record);
        assert_eq!(back.problem[0].file, "a.toml");
        assert!(objective_matches(&entry, 2.5 + 2.4e-6));
        assert!(!objective_matches(&entry, 2.5 + 2.6e-6));
    }
}
