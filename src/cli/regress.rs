//! `vito bench` and `vito regress`: timings and the regression record.

use super::*;

/// Prints one `transcription::bench` row per problem (sizes, solve and derivative times).
pub(super) fn bench(files: &[PathBuf], set: &[String]) -> Result<u8, CliError> {
    let overrides = parse_overrides(set)?;
    let files: Vec<PathBuf> = if files.is_empty() {
        pipeline::REFERENCE_PROBLEMS
            .iter()
            .map(PathBuf::from)
            .collect()
    } else {
        files.to_vec()
    };
    let problems = files
        .iter()
        .map(|f| load(f, &overrides))
        .collect::<Result<Vec<_>, _>>()?;
    out!(
        "{:<24} {:>5} {:>6} {:>6} {:>7} {:>7} {:>28} {:>15} {:>9} {:>6} {:>9} {:>9} {:>9} {:>10}",
        "problem",
        "knots",
        "vars",
        "cons",
        "nnz J",
        "nnz H",
        "status",
        "objective",
        "max slack",
        "iter",
        "wall s",
        "callb. s",
        "ipopt s",
        "J+H eval s"
    );
    for p in &problems {
        let r = pipeline::bench(&p.spec).map_err(CliError::Transcription)?;
        out!(
            "{:<24} {:>5} {:>6} {:>6} {:>7} {:>7} {:>28} {:>15.8e} {:>9.2e} {:>6} {:>9.3} {:>9.3} {:>9.3} {:>10.2e}",
            r.name,
            p.spec.knots,
            r.size.n_variables,
            r.size.n_constraints,
            r.size.nnz_jacobian,
            r.size.nnz_hessian,
            status_name(r.status),
            r.objective,
            r.max_slack,
            r.iterations,
            r.wall_time_s,
            r.callback_time_s,
            r.ipopt_time_s,
            r.derivative_eval_s
        );
    }
    Ok(0)
}

pub(super) fn regress(record_path: &Path, files: &[PathBuf], bless: bool) -> Result<u8, CliError> {
    use vito::regress::{RegressError, Verdict};
    let exe = std::env::current_exe().map_err(|e| CliError::Internal(e.to_string()))?;
    let rows = vito::regress::regress(&exe, record_path, files, bless).map_err(|e| match e {
        RegressError::Record(e) => CliError::Golden(e),
        e @ RegressError::NoProblems { .. } => CliError::Input(e.to_string()),
        e @ (RegressError::Spawn { .. } | RegressError::Scratch { .. }) => {
            CliError::Internal(e.to_string())
        }
    })?;
    out!(
        "{:<32} {:<28} {:>18} {:>18} {:>10}  result",
        "problem",
        "status",
        "objective",
        "recorded",
        "rel. diff"
    );
    for r in &rows {
        let fmt = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{v:.10e}"));
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
    if bless {
        out!("blessed {}", record_path.display());
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
