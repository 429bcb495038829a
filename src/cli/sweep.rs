//! `vito sweep` and its `report` and `collect`.

use std::path::{Path, PathBuf};

use vito::problem::load;

use super::args::{SweepRunArgs, WarmStartArg, parse_overrides};
use super::error::CliError;
use super::interrupt::on_stop_request;

pub(super) fn sweep(args: SweepRunArgs) -> Result<u8, CliError> {
    use vito::sweep::{Axis, Event, Grid, Shard, SweepOptions, WarmStart};
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
    let time_limit = super::args::time_limit(args.time_limit)?;
    let jobs = super::args::jobs(args.jobs)?;
    let starts = super::args::count("--starts", args.starts, vito::transcription::MAX_STARTS)?;
    let overrides = parse_overrides(&args.set)?;
    let problem = load(&file, &overrides)?;
    vito::sweep::check_grid(&file, &overrides, &grid)?;
    let out = args.out.unwrap_or_else(|| {
        let stem = file
            .file_stem()
            .map_or("problem".into(), |s| s.to_string_lossy());
        PathBuf::from(format!("out/sweep-{stem}"))
    });
    // SIGINT, SIGTERM, SIGHUP: no new run starts; the running ones stop after their current
    // iteration and write their iterates (a rerun redoes them); a later request quits at once.
    let stop = on_stop_request(
        || {
            note!(
                "interrupted: stopping the running runs after their current iteration (interrupt again to quit now)"
            )
        },
        || {
            note!(
                "interrupted again: exiting; the running runs are killed, the table holds every run finished so far"
            );
            std::process::exit(1);
        },
    );
    let warm_start = match args.warm_start {
        WarmStartArg::None => WarmStart::None,
        WarmStartArg::Neighbour => WarmStart::Neighbour,
    };
    let warm_starts = warm_start == WarmStart::Neighbour || args.neighbour_rounds > 0;
    if let Some(absolute) = vito::sweep::out_name_without_utf8(&out, warm_starts) {
        return Err(CliError::Input(format!(
            "--out {}: the directory's name is not UTF-8, and a sweep's neighbour warm starts \
             and neighbour pass give each run the trajectory it starts from as the problem's \
             `initial_guess.warm_start`, a TOML string (UTF-8 only); choose a directory whose \
             name is UTF-8, or give --warm-start none and --neighbour-rounds 0",
            absolute.display()
        )));
    }
    let options = SweepOptions {
        exe: std::env::current_exe().map_err(|e| CliError::Internal(e.to_string()))?,
        problem: std::path::absolute(&file).map_err(|e| CliError::Internal(e.to_string()))?,
        sets: args.set.clone(),
        grid,
        shard,
        jobs,
        time_limit,
        out: out.clone(),
        warm_start,
        stop: Some(stop),
        starts,
        seed: args.seed,
        neighbour_rounds: args.neighbour_rounds,
    };
    let started = std::time::Instant::now();
    let mut display = SweepDisplay::new(started)?;
    let outcome = vito::sweep::run_sweep(&options, &problem.sha256, |event| {
        match event {
        Event::Progress(p) => display.progress(p),
        Event::Ended(row, p) => {
            display.line(&run_line(row, p));
            display.progress(p);
        }
        Event::Stopping { running } => display.line(&format!(
            "stopping: {running} running runs asked to stop after their current iteration; no new run starts"
        )),
        Event::Round { round, attempts, to_run } => display.line(&format!(
            "neighbour pass, round {round}: {attempts} re-solves from neighbours' plans ({} on disk already)",
            attempts - to_run
        )),
        Event::RoundEnded { round, improved, table } => {
            display.line(&format!(
                "neighbour pass, round {round}: {} points improved by more than {} %",
                improved.len(),
                vito::sweep::SETTLE_RATIO * 100.0
            ));
            for row in table.rows.iter().filter(|r| improved.contains(&r.index)) {
                display.line(&format!(
                    "  point {} ({}): {} from {}",
                    row.index,
                    row.point_label(),
                    row.objective.map_or("-".into(), |o| format!("objective {o:.6e}")),
                    row.start
                ));
            }
        }
    }
    })?;
    display.finish();
    let table = &outcome.table;
    print_sweep_table(table)?;
    out!(
        "{} runs: {} finished ({} of them before this sweep), {} failed, {} timed out, {} interrupted, {} not run, in {:.1} s; table in {}",
        table.rows.len(),
        table.count(vito::sweep::RunStatus::Finished),
        outcome.counts.skipped,
        table.count(vito::sweep::RunStatus::Failed),
        table.count(vito::sweep::RunStatus::Timeout),
        table.count(vito::sweep::RunStatus::Interrupted),
        table.count(vito::sweep::RunStatus::Pending),
        started.elapsed().as_secs_f64(),
        out.join(vito::sweep::TABLE_CSV).display()
    );
    if outcome.interrupted {
        out!(
            "interrupted: the table holds every run finished so far; run the same command again to do the rest"
        );
    }
    Ok(if table.all_solved() && !outcome.interrupted {
        0
    } else {
        1
    })
}

/// One line per finished run: its point, where it stands, solver status, objective, time.
fn run_line(row: &vito::sweep::Row, p: &vito::sweep::Progress) -> String {
    let point = row.point_label();
    let ended = p.done + p.failed + p.interrupted;
    let mut line = format!(
        "[{ended}/{}] point {} ({point}): {}",
        p.total,
        row.index,
        row.status.name()
    );
    if let Some(s) = &row.solver_status {
        line.push_str(&format!(" {s}"));
    }
    if let Some(o) = row.objective {
        line.push_str(&format!(", objective {o:.6e}"));
    }
    if let Some(t) = row.wall_time_s {
        line.push_str(&format!(", {t:.2} s"));
    }
    if row.status != vito::sweep::RunStatus::Finished && !row.note.is_empty() {
        line.push_str(&format!(" ({})", row.note));
    }
    line
}

/// A sweep's progress on stderr: a bar with the counts and an ETA on a terminal; plain lines
/// otherwise (a log file, a Slurm job's output).
struct SweepDisplay {
    bar: Option<indicatif::ProgressBar>,
    started: std::time::Instant,
    last: Option<vito::sweep::Progress>,
}

impl SweepDisplay {
    fn new(started: std::time::Instant) -> Result<SweepDisplay, CliError> {
        use std::io::IsTerminal;
        let bar = if std::io::stderr().is_terminal() {
            let bar = indicatif::ProgressBar::new(0);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{bar:30} {pos}/{len} runs  {msg}  elapsed {elapsed}, ETA {eta}",
                )
                .map_err(|e| CliError::Internal(e.to_string()))?,
            );
            Some(bar)
        } else {
            None
        };
        Ok(SweepDisplay {
            bar,
            started,
            last: None,
        })
    }

    fn line(&self, text: &str) {
        match &self.bar {
            Some(bar) => bar.println(vito::files::names::escape_controls(text)),
            None => note!("{text}"),
        }
    }

    fn progress(&mut self, p: &vito::sweep::Progress) {
        let counts = format!(
            "done {}, running {}, failed {}{}{}{}",
            p.done,
            p.running,
            p.failed,
            if p.interrupted > 0 {
                format!(", interrupted {}", p.interrupted)
            } else {
                String::new()
            },
            if p.skipped > 0 {
                format!(" ({} finished before)", p.skipped)
            } else {
                String::new()
            },
            if p.attempts_total > 0 {
                format!(
                    ", neighbour re-solves {}/{}",
                    p.attempts_done, p.attempts_total
                )
            } else {
                String::new()
            }
        );
        let ended = p.done + p.failed + p.interrupted + p.attempts_done;
        let total = p.total + p.attempts_total;
        match &self.bar {
            Some(bar) => {
                bar.set_length(total as u64);
                bar.set_position(ended as u64);
                bar.set_message(counts);
            }
            None => {
                // Plain lines only when a run ended (a start changes only `running`).
                let ended_before = self.last.map_or(usize::MAX, |l| {
                    l.done + l.failed + l.interrupted + l.attempts_done
                });
                if ended != ended_before {
                    let ran = ended - p.skipped;
                    let left = total - ended;
                    let eta = if ran > 0 && left > 0 {
                        let per_run = self.started.elapsed().as_secs_f64() / ran as f64;
                        format!(", ETA {:.0} s", per_run * left as f64)
                    } else {
                        String::new()
                    };
                    note!("progress: {ended}/{total} runs, {counts}{eta}");
                }
            }
        }
        self.last = Some(*p);
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
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
    // Padded by hand: a format width is limited to 65,535 characters, a cell is not.
    let line = |row: &[String]| {
        row.iter()
            .zip(&widths)
            .map(|(c, w)| format!("{c}{}", " ".repeat(w.saturating_sub(c.chars().count()))))
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
    // Exit 1 unless every point solved, as the sweep itself.
    let unsolved: Vec<String> = table
        .rows
        .iter()
        .filter(|r| vito::sweep::PointClass::of(r) != vito::sweep::PointClass::Solved)
        .map(|r| {
            format!(
                "{} ({}: {})",
                r.index,
                r.point_label(),
                vito::sweep::PointClass::of(r).name()
            )
        })
        .collect();
    if unsolved.is_empty() {
        return Ok(0);
    }
    out!(
        "not solved   {} of {} points: {}",
        unsolved.len(),
        table.rows.len(),
        unsolved.join(", ")
    );
    Ok(1)
}

pub(super) fn sweep_collect(dirs: &[PathBuf], out: &Path, partial: bool) -> Result<u8, CliError> {
    // Read the shards before making anything: a wrong directory leaves nothing behind.
    let table = vito::sweep::collect(dirs, out)?;
    vito::sweep::prepare_dir(out)?;
    table.write(out)?;
    print_sweep_table(&table)?;
    out!(
        "{} points from {} directories: {} finished, {} failed, {} timed out, {} missing; table in {}",
        table.rows.len(),
        dirs.len(),
        table.count(vito::sweep::RunStatus::Finished),
        table.count(vito::sweep::RunStatus::Failed),
        table.count(vito::sweep::RunStatus::Timeout),
        table.missing().count(),
        out.join(vito::sweep::TABLE_CSV).display()
    );
    let missing: Vec<String> = table
        .missing()
        .map(|r| format!("{} ({})", r.index, r.point_label()))
        .collect();
    if missing.is_empty() || partial {
        return Ok(0);
    }
    const SHOWN: usize = 20;
    note!(
        "error: {} of {} points have no result (a shard not run, not finished or not named): {}{}; \
         give every shard's directory, rerun the missing shards, or pass --partial to accept a partial table",
        missing.len(),
        table.rows.len(),
        missing[..missing.len().min(SHOWN)].join(", "),
        if missing.len() > SHOWN { ", …" } else { "" }
    );
    Ok(1)
}
