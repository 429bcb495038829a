//! `vito regress`: solve every problem of a regression record, each in its own process (one
//! Ipopt solve per process, ARCHITECTURE.md), compare the objectives with the record, and rewrite
//! the record atomically when blessing.

pub mod independent;
pub mod reference;

use std::path::{Path, PathBuf};

use crate::files::paths::relative_path;
use crate::report::{
    DEFAULT_TOLERANCE, GoldenEntry, GoldenError, GoldenRecord, objective_matches, slack_matches,
};

/// How one problem compares with the record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Solved, objective within the recorded tolerance.
    Ok,
    /// Solved, not in the record yet.
    New,
    /// Solved, objective outside the recorded tolerance or slack above the recorded one.
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
    /// The new largest slack and iterations, if the solve wrote them.
    pub max_slack: Option<f64>,
    /// The new iteration count.
    pub iterations: Option<u64>,
    /// The new objective's terms (name, value), from `summary.json`.
    pub terms: Vec<(String, f64)>,
    /// The record's entry, if any.
    pub entry: Option<GoldenEntry>,
    /// What else a reader should know: the problem file changed since blessing, another
    /// platform blessed it.
    pub notes: Vec<String>,
    /// Where the new solution was kept (a difference or a failure).
    pub kept: Option<PathBuf>,
    /// Whether `--bless` recorded this result.
    pub blessed: bool,
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
    /// A problem could not be set up (the solve's input error, exit 2): not a regression.
    #[error("{message}")]
    Setup {
        /// The problem file.
        file: PathBuf,
        /// The solve's error message.
        message: String,
    },
    /// The scratch directory for the solves' outputs could not be made.
    #[error(
        "cannot create a scratch directory in {dir} ({source}); set TMPDIR to an existing, \
         writable directory"
    )]
    Scratch {
        /// The directory.
        dir: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
}

/// Solves `files` (relative to the working directory), or the record's problems when none
/// is named, with `vito_exe solve`, one process each, into a fresh private temporary
/// directory, and compares them with the record. A problem that differs or fails keeps its
/// solution (the row's `kept`). With `bless`, the record is rewritten (atomically) with
/// every solved result, its other entries kept; a bless that solves nothing leaves it as it
/// was (no row is `blessed`).
pub fn regress(
    vito_exe: &Path,
    record_path: &Path,
    files: &[PathBuf],
    bless: bool,
) -> Result<Vec<RegressRow>, RegressError> {
    if bless {
        GoldenRecord::check_writable(record_path)?;
    }
    let mut record = GoldenRecord::read(record_path)?;
    let base = match record_path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    };
    let mut names: Vec<String> = Vec::new();
    for f in files {
        let name = relative_path(f, &base);
        if !names.contains(&name) {
            names.push(name);
        }
    }
    if files.is_empty() {
        names = record.problem.iter().map(|e| e.file.clone()).collect();
    }
    if names.is_empty() {
        return Err(RegressError::NoProblems {
            record: record_path.to_owned(),
            missing: !record_path.exists(),
        });
    }
    let scratch = tempfile::Builder::new()
        .prefix("vito-regress-")
        .tempdir()
        .map_err(|source| RegressError::Scratch {
            dir: std::env::temp_dir(),
            source,
        })?;
    let mut rows = Vec::new();
    for name in &names {
        let out = scratch.path().join(name.replace(['/', '\\'], "_"));
        let mut row =
            solve_and_compare(vito_exe, &base.join(name), &out, name, &mut record, bless)?;
        if matches!(row.verdict, Verdict::Diff | Verdict::Fail) && out.exists() {
            row.kept = Some(out);
        } else {
            let _ = std::fs::remove_dir_all(&out);
        }
        rows.push(row);
    }
    if rows.iter().any(|r| r.kept.is_some()) {
        let _ = scratch.keep();
    }
    if bless && rows.iter().any(|r| r.blessed) {
        record.write(record_path)?;
    }
    Ok(rows)
}

/// Solves one problem in a child process and compares its `summary.json` with the record
/// (a child's exit status alone is never trusted: it must have written a result). A child
/// that exits 2 (an input error) is a setup error, not a regression.
fn solve_and_compare(
    vito_exe: &Path,
    problem: &Path,
    out: &Path,
    name: &str,
    record: &mut GoldenRecord,
    bless: bool,
) -> Result<RegressRow, RegressError> {
    let output = std::process::Command::new(vito_exe)
        .arg("solve")
        .arg(problem)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .output()
        .map_err(|source| RegressError::Spawn {
            exe: vito_exe.to_owned(),
            source,
        })?;
    let stderr = String::from_utf8_lossy(&output.stderr);
    if output.status.code() == Some(2) {
        let message = stderr
            .lines()
            .filter(|l| !l.starts_with("warning:"))
            .collect::<Vec<_>>()
            .join("\n  ");
        let message = message.strip_prefix("error: ").unwrap_or(&message);
        let shown = problem.display().to_string();
        return Err(RegressError::Setup {
            file: problem.to_owned(),
            message: if message.contains(&shown) {
                message.to_owned()
            } else {
                format!("{shown}: {message}")
            },
        });
    }
    let summary = std::fs::read_to_string(out.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok());
    let recorded = record.entry(name).cloned();
    let mut row = RegressRow {
        file: name.to_owned(),
        status: String::new(),
        objective: None,
        recorded: recorded.as_ref().map(|e| e.objective),
        max_slack: None,
        iterations: None,
        terms: Vec::new(),
        entry: recorded.clone(),
        notes: Vec::new(),
        kept: None,
        blessed: false,
        verdict: Verdict::Fail,
    };
    let Some(summary) = summary else {
        row.status = format!("no result (exit {})", output.status.code().unwrap_or(-1));
        if let Some(e) = stderr.lines().rev().find(|l| l.starts_with("error:")) {
            row.notes.push(e.to_owned());
        }
        return Ok(row);
    };
    let objective = summary["objective"].as_f64().unwrap_or(f64::NAN);
    let max_slack = summary["max_slack"].as_f64().unwrap_or(f64::NAN);
    let status_text = summary["status"].as_str().unwrap_or("?").to_owned();
    let sha256 = summary["problem_sha256"].as_str().map(str::to_owned);
    let solved = crate::report::summary_verdict(&summary).is_some_and(|v| v.is_solved());
    row.verdict = match (&recorded, solved) {
        (_, false) => Verdict::Fail,
        (None, true) => Verdict::New,
        (Some(e), true) if objective_matches(e, objective) && slack_matches(e, max_slack) => {
            Verdict::Ok
        }
        (Some(_), true) => Verdict::Diff,
    };
    let platform = crate::report::platform();
    if let Some(e) = &recorded {
        if let (Some(old), Some(new)) = (&e.problem_sha256, &sha256)
            && old != new
        {
            row.notes.push(format!(
                "{name} has changed since it was blessed (SHA-256 {}… then, {}… now)",
                &old[..old.len().min(12)],
                &new[..new.len().min(12)]
            ));
        }
        if row.verdict != Verdict::Ok
            && let Some(p) = e.platform.as_ref().filter(|p| **p != platform)
        {
            row.notes.push(format!(
                "blessed on {p}, solved here on {platform}: another MUMPS or BLAS may reach another optimum"
            ));
        }
    }
    let terms: Vec<(String, f64)> = summary["objective_terms"]
        .as_object()
        .map(|terms| {
            terms
                .iter()
                .filter_map(|(k, v)| v.as_f64().map(|x| (k.clone(), x)))
                .collect()
        })
        .unwrap_or_default();
    if bless && solved {
        row.blessed = true;
        record.upsert(GoldenEntry {
            file: name.to_owned(),
            objective,
            tolerance: recorded.as_ref().map_or(DEFAULT_TOLERANCE, |e| e.tolerance),
            status: status_text.clone(),
            iterations: summary["iterations"].as_u64().unwrap_or(0) as usize,
            max_slack,
            source: Some(format!("vito {}", env!("CARGO_PKG_VERSION"))),
            problem_sha256: sha256,
            platform: Some(platform),
            terms: terms.iter().cloned().collect(),
        });
    }
    row.status = status_text;
    row.objective = Some(objective);
    row.max_slack = Some(max_slack);
    row.iterations = summary["iterations"].as_u64();
    row.terms = terms;
    Ok(row)
}
