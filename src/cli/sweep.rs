//! `vito sweep` and its `report` and `collect`.

use super::*;

pub(super) fn sweep(args: SweepRunArgs) -> Result<u8, CliError> {
    use vito::sweep::{Axis, Grid, Shard, SweepOptions, WarmStart};
    let file = args
        .file
        .ok_or_else(|| CliError::Input("give a problem file".into()))?;
    let grid = Grid::new(
        args.grid
            .iter()
            .map(|g| Axis::parse(g))
            .collect::<Result<_, _>>()?,
    )?;
    let shard = args
        .shard
        .as_deref()
        .map(Shard::parse)
        .transpose()?
        .unwrap_or(Shard::ALL);
    let time_limit = match args.time_limit {
        Some(t) if !(t.is_finite() && t > 0.0) => {
            return Err(CliError::Input(format!(
                "--time-limit {t}: give a positive number of seconds"
            )));
        }
        t => t.map(std::time::Duration::from_secs_f64),
    };
    if args.jobs == Some(0) {
        return Err(CliError::Input("--jobs 0: give at least 1".into()));
    }
    let overrides = parse_overrides(&args.set)?;
    let problem = load(&file, &overrides)?;
    vito::sweep::check_grid_keys(&file, &overrides, &grid)?;
    let out = args.out.unwrap_or_else(|| {
        let stem = file
            .file_stem()
            .map_or("problem".into(), |s| s.to_string_lossy());
        PathBuf::from(format!("out/sweep-{stem}"))
    });
    let options = SweepOptions {
        exe: std::env::current_exe().map_err(|e| CliError::Internal(e.to_string()))?,
        problem: std::path::absolute(&file).map_err(|e| CliError::Internal(e.to_string()))?,
        sets: args.set.clone(),
        grid,
        shard,
        jobs: args.jobs.unwrap_or_else(|| {
            std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
        }),
        time_limit,
        out: out.clone(),
        warm_start: match args.warm_start {
            WarmStartArg::None => WarmStart::None,
            WarmStartArg::Neighbour => WarmStart::Neighbour,
        },
    };
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:30} {pos}/{len} runs  {msg}  elapsed {elapsed}, ETA {eta}",
        )
        .map_err(|e| CliError::Internal(e.to_string()))?,
    );
    let started = std::time::Instant::now();
    let (table, counts) = vito::sweep::run_sweep(&options, &problem.sha256, |p| {
        bar.set_length(p.total as u64);
        bar.set_position((p.done + p.failed) as u64);
        bar.set_message(format!(
            "done {}, failed {}, running {}{}",
            p.done,
            p.failed,
            p.running,
            if p.skipped > 0 {
                format!(" ({} finished before)", p.skipped)
            } else {
                String::new()
            }
        ));
    })?;
    bar.finish_and_clear();
    print_sweep_table(&table)?;
    let solved = table.rows.iter().all(|r| {
        r.solver_status
            .as_deref()
            .and_then(vito::transcription::SolveVerdict::from_name)
            .is_some_and(|v| v.is_solved())
    });
    out!(
        "{} runs: {} finished ({} of them before this sweep), {} failed, {} timed out, in {:.1} s; table in {}",
        table.rows.len(),
        table.count(vito::sweep::RunStatus::Finished),
        counts.skipped,
        table.count(vito::sweep::RunStatus::Failed),
        table.count(vito::sweep::RunStatus::Timeout),
        started.elapsed().as_secs_f64(),
        out.join(vito::sweep::TABLE_CSV).display()
    );
    Ok(if solved { 0 } else { 1 })
}

/// Prints a sweep table with aligned columns (the CSV's columns).
pub(super) fn print_sweep_table(table: &vito::sweep::Table) -> Result<(), CliError> {
    let columns = table.columns();
    let cells = table.cells();
    let widths: Vec<usize> = columns
        .iter()
        .enumerate()
        .map(|(j, c)| {
            cells
                .iter()
                .map(|r| r[j].chars().count())
                .chain([c.chars().count()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let line = |row: &[String]| {
        row.iter()
            .zip(&widths)
            .map(|(c, w)| format!("{c:<w$}"))
            .collect::<Vec<_>>()
            .join("  ")
            .trim_end()
            .to_owned()
    };
    out!("{}", line(&columns));
    for r in &cells {
        out!("{}", line(r));
    }
    Ok(())
}

pub(super) fn sweep_report(dir: &Path, metric: &str) -> Result<u8, CliError> {
    let table = vito::sweep::Table::read(dir)?;
    print_sweep_table(&table)?;
    let known = ["objective", "iterations", "wall_time_s", "max_slack"];
    let metrics = table.metric_names();
    let bare = metric.strip_prefix("metrics.").unwrap_or(metric);
    if !known.contains(&metric) && !metrics.iter().any(|m| m == bare) {
        return Err(CliError::Input(format!(
            "--metric {metric}: not a column of {}; choose one of: {}",
            dir.join(vito::sweep::TABLE_JSON).display(),
            known
                .iter()
                .map(|s| s.to_string())
                .chain(metrics)
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    let file_name: String = bare
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let path = dir.join(format!("sweep-{file_name}.svg"));
    let plotted = vito::sweep::metric_svg(&table, metric, &path)?;
    out!("{metric} of {plotted} runs plotted in {}", path.display());
    Ok(0)
}

pub(super) fn sweep_collect(dirs: &[PathBuf], out: &Path) -> Result<u8, CliError> {
    vito::sweep::prepare_dir(out)?;
    let table = vito::sweep::collect(dirs, out)?;
    table.write(out)?;
    print_sweep_table(&table)?;
    out!(
        "{} points from {} directories: {} finished, {} failed, {} timed out, {} missing; table in {}",
        table.rows.len(),
        dirs.len(),
        table.count(vito::sweep::RunStatus::Finished),
        table.count(vito::sweep::RunStatus::Failed),
        table.count(vito::sweep::RunStatus::Timeout),
        table.count(vito::sweep::RunStatus::Pending),
        out.join(vito::sweep::TABLE_CSV).display()
    );
    Ok(0)
}
