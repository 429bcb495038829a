//! `vito regress`: the regression record's problems solved and compared, or blessed.

use std::path::{Path, PathBuf};

use super::error::CliError;

/// The record `vito regress` uses: `--record`, else the `golden.toml` beside the first
/// problem named, else `golden.toml` in the working directory when there is one, else
/// `problems/golden.toml` (the project's own).
pub(super) fn record_path(record: Option<&Path>, files: &[PathBuf]) -> PathBuf {
    match (record, files.first()) {
        (Some(r), _) => r.to_owned(),
        (None, Some(f)) => f.with_file_name("golden.toml"),
        (None, None) if Path::new("golden.toml").exists() => PathBuf::from("golden.toml"),
        (None, None) => PathBuf::from("problems/golden.toml"),
    }
}

pub(super) fn regress(record_path: &Path, files: &[PathBuf], bless: bool) -> Result<u8, CliError> {
    use vito::regress::Verdict;
    let exe = std::env::current_exe().map_err(|e| CliError::Internal(e.to_string()))?;
    let rows = vito::regress::regress(&exe, record_path, files, bless)?;
    out!(
        "{:<32} {:<28} {:>18} {:>18} {:>10}  result",
        "problem",
        "status",
        "objective",
        "recorded",
        "rel. diff"
    );
    let fmt = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{v:.10e}"));
    for r in &rows {
        let diff = r
            .relative_difference()
            .map_or("-".to_owned(), |d| format!("{d:.2e}"));
        out!(
            "{:<32} {:<28} {:>18} {:>18} {:>10}  {}",
            r.file,
            r.status,
            fmt(r.objective),
            fmt(r.recorded),
            diff,
            r.verdict
        );
    }
    for r in &rows {
        if !matches!(r.verdict, Verdict::Diff | Verdict::Fail) && r.notes.is_empty() {
            continue;
        }
        out!("\n{} ({}):", r.file, r.verdict);
        if r.objective.is_some() {
            let e = r.entry.as_ref();
            out!("  {:<24} {:>18} {:>18}", "", "now", "recorded");
            out!(
                "  {:<24} {:>18} {:>18}",
                "status",
                r.status,
                e.map_or("-", |e| e.status.as_str())
            );
            out!(
                "  {:<24} {:>18} {:>18}",
                "objective",
                fmt(r.objective),
                fmt(r.recorded)
            );
            for (name, value) in &r.terms {
                let recorded = e.and_then(|e| e.terms.get(name)).copied();
                out!(
                    "  {:<24} {:>18} {:>18}",
                    format!("  {name}"),
                    format!("{value:.10e}"),
                    fmt(recorded)
                );
            }
            out!(
                "  {:<24} {:>18} {:>18}",
                "iterations",
                r.iterations.map_or("-".to_owned(), |i| i.to_string()),
                e.map_or("-".to_owned(), |e| e.iterations.to_string())
            );
            out!(
                "  {:<24} {:>18} {:>18}",
                "max slack",
                r.max_slack.map_or("-".to_owned(), |x| format!("{x:.3e}")),
                e.map_or("-".to_owned(), |e| format!("{:.3e}", e.max_slack))
            );
        }
        for n in &r.notes {
            out!("  {n}");
        }
        if let Some(k) = &r.kept {
            out!("  new solution kept in {}", k.display());
        }
    }
    if bless {
        let blessed = rows.iter().filter(|r| r.blessed).count();
        if blessed == 0 {
            note!(
                "error: nothing blessed: none of the {} problem(s) solved; {} is unchanged",
                rows.len(),
                record_path.display()
            );
            return Ok(1);
        }
        out!(
            "blessed {blessed} of {} problem(s) into {}",
            rows.len(),
            record_path.display()
        );
        return Ok(if rows.iter().any(|r| r.verdict == Verdict::Fail) {
            1
        } else {
            0
        });
    }
    Ok(if rows.iter().all(|r| r.verdict == Verdict::Ok) {
        0
    } else {
        1
    })
}
