//! `vito regress`: solve every problem of a regression record, each in its own process (one
//! Ipopt solve per process, DESIGN.md), compare the objectives with the record, and rewrite
//! the record atomically when blessing.

use std::path::{Path, PathBuf};

use crate::paths::relative_path;
use crate::report::{DEFAULT_TOLERANCE, GoldenEntry, GoldenError, GoldenRecord, objective_matches};

/// How one problem compares with the record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Solved, objective within the recorded tolerance.
    Ok,
    /// Solved, not in the record yet.
    New,
    /// Solved, objective outside the recorded tolerance.
    Diff,
    /// Not solved, or no result at all.
    Fail,
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Verdict::Ok => "ok",
            Verdict::New => "NEW",
            Verdict::Diff => "DIFF",
            Verdict::Fail => "FAIL",
        })
    }
}

/// One row of the regression table.
#[derive(Debug, Clone, PartialEq)]
pub struct RegressRow {
    /// Problem file, relative to the record's directory.
    pub file: String,
    /// Ipopt's status (snake case), or why there is no result.
    pub status: String,
    /// The new objective, if the solve wrote one.
    pub objective: Option<f64>,
    /// The recorded objective, if any.
    pub recorded: Option<f64>,
    /// The comparison.
    pub verdict: Verdict,
}

impl RegressRow {
    /// |new − recorded| / max(1, |recorded|), when both exist.
    pub fn relative_difference(&self) -> Option<f64> {
        match (self.objective, self.recorded) {
            (Some(a), Some(b)) => Some((a - b).abs() / b.abs().max(1.0)),
            _ => None,
        }
    }
}

/// Why the regression could not run.
#[derive(Debug, thiserror::Error)]
pub enum RegressError {
    /// The record could not be read or written.
    #[error(transparent)]
    Record(#[from] GoldenError),
    /// Nothing to solve.
    #[error("{record} {}; name problem files to add them with --bless", if *.missing { "does not exist" } else { "lists no problems" })]
    NoProblems {
        /// The record file.
        record: PathBuf,
        /// Whether the record file is missing (rather than empty).
        missing: bool,
    },
    /// The solver process could not be started.
    #[error("cannot run {exe}: {source}")]
    Spawn {
        /// The `vito` executable.
        exe: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The scratch directory for the solves' outputs could not be made.
    #[error("cannot create {dir}: {source}")]
    Scratch {
        /// The directory.
        dir: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
}

/// Solves the record's problems plus `files` (relative to the working directory) with
/// `vito_exe solve`, one process each, and compares them with the record. With `bless`, the
/// record is rewritten (atomically) with every solved result.
pub fn regress(
    vito_exe: &Path,
    record_path: &Path,
    files: &[PathBuf],
    bless: bool,
) -> Result<Vec<RegressRow>, RegressError> {
    let mut record = GoldenRecord::read(record_path)?;
    let base = record_path.parent().unwrap_or(Path::new("")).to_owned();
    let mut names: Vec<String> = record.problem.iter().map(|e| e.file.clone()).collect();
    for f in files {
        let name = relative_path(
            f,
            if base.as_os_str().is_empty() {
                Path::new(".")
            } else {
                &base
            },
        );
        if !names.contains(&name) {
            names.push(name);
        }
    }
    if names.is_empty() {
        return Err(RegressError::NoProblems {
            record: record_path.to_owned(),
            missing: !record_path.exists(),
        });
    }
    let scratch = scratch_dir(record_path)?;
    let mut rows = Vec::new();
    for name in &names {
        let out = scratch.join(name.replace(['/', '\\'], "_"));
        let row = solve_and_compare(vito_exe, &base.join(name), &out, name, &mut record, bless);
        match row {
            Ok(row) => rows.push(row),
            Err(e) => {
                let _ = std::fs::remove_dir_all(&scratch);
                return Err(e);
            }
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    if bless {
        record.write(record_path)?;
    }
    Ok(rows)
}

/// Solves one problem in a child process and compares its `summary.json` with the record
/// (a child's exit status alone is never trusted: it must have written a result).
fn solve_and_compare(
    vito_exe: &Path,
    problem: &Path,
    out: &Path,
    name: &str,
    record: &mut GoldenRecord,
    bless: bool,
) -> Result<RegressRow, RegressError> {
    let status = std::process::Command::new(vito_exe)
        .arg("solve")
        .arg(problem)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .stdout(std::process::Stdio::null())
        .status()
        .map_err(|source| RegressError::Spawn {
            exe: vito_exe.to_owned(),
            source,
        })?;
    let summary = std::fs::read_to_string(out.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok());
    let recorded = record.entry(name).cloned();
    let Some(summary) = summary else {
        return Ok(RegressRow {
            file: name.to_owned(),
            status: format!("no result (exit {})", status.code().unwrap_or(-1)),
            objective: None,
            recorded: recorded.as_ref().map(|e| e.objective),
            verdict: Verdict::Fail,
        });
    };
    let objective = summary["objective"].as_f64().unwrap_or(f64::NAN);
    let status_text = summary["status"].as_str().unwrap_or("?").to_owned();
    let solved = crate::report::summary_verdict(&summary).is_some_and(|v| v.is_solved());
    let verdict = match (&recorded, solved) {
        (_, false) => Verdict::Fail,
        (None, true) => Verdict::New,
        (Some(e), true) if objective_matches(e, objective) => Verdict::Ok,
        (Some(_), true) => Verdict::Diff,
    };
    if bless && solved {
        record.upsert(GoldenEntry {
            file: name.to_owned(),
            objective,
            tolerance: recorded.as_ref().map_or(DEFAULT_TOLERANCE, |e| e.tolerance),
            status: status_text.clone(),
            iterations: summary["iterations"].as_u64().unwrap_or(0) as usize,
            max_slack: summary["max_slack"].as_f64().unwrap_or(f64::NAN),
            source: Some(format!("vito {}", env!("CARGO_PKG_VERSION"))),
        });
    }
    Ok(RegressRow {
        file: name.to_owned(),
        status: status_text,
        objective: Some(objective),
        recorded: recorded.as_ref().map(|e| e.objective),
        verdict,
    })
}

fn scratch_dir(record_path: &Path) -> Result<PathBuf, RegressError> {
    let dir = std::env::temp_dir().join(format!(
        "vito-regress-{}-{}",
        std::process::id(),
        record_path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    ));
    std::fs::create_dir_all(&dir).map_err(|source| RegressError::Scratch {
        dir: dir.clone(),
        source,
    })?;
    Ok(dir)
}
