//! Running a sweep: one `vito solve` process per grid point, at most `jobs` at a time, each
//! stopped at the per-run time limit; the table is rewritten (atomically) after every run.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use std::collections::BTreeSet;

use crate::sweep::neighbours;
use crate::sweep::table::{
    OnDisk, RUNS, Row, RunStatus, Table, TableWrites, WARM_START_KEY, expected_parameters,
    read_result,
};
use crate::sweep::{Grid, Point, Shard, SweepError};

/// The directory of the runs' logs (stdout and stderr of each `vito solve`).
pub const LOGS: &str = "logs";
/// Marks a directory as a sweep's (vito adds to it and rewrites its tables).
pub const SWEEP_MARKER: &str = ".vito-sweep";
/// The hidden `vito solve` option a sweep gives each run, with the sweep's process id: the
/// run dies with the sweep. (An option, not an environment variable: a user's environment
/// cannot turn it on by accident.)
pub const PARENT_FLAG: &str = "--sweep-parent";

/// Most processes run at a time (`--jobs` of `vito sweep` and of a parallel `vito solve
/// --starts`): more than any one machine runs well; a cluster spreads a sweep with `--shard`.
pub const MAX_JOBS: usize = 1024;

/// How long after its time limit a run that has not stopped by itself (a long iteration, a
/// simulated initial guess) is killed.
pub const KILL_GRACE: Duration = Duration::from_secs(30);

/// Where a run starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WarmStart {
    /// The problem file's own initial guess.
    None,
    /// The trajectory of the nearest finished point of the grid, if any.
    Neighbour,
}

/// What a sweep runs.
#[derive(Debug, Clone)]
pub struct SweepOptions {
    /// The `vito` executable (`std::env::current_exe()`).
    pub exe: PathBuf,
    /// The problem file.
    pub problem: PathBuf,
    /// Fixed `--set` overrides for every run.
    pub sets: Vec<String>,
    /// The swept axes.
    pub grid: Grid,
    /// The part of the grid this process runs.
    pub shard: Shard,
    /// Runs at a time (≥ 1).
    pub jobs: usize,
    /// Per-run wall-time limit, given to each run as `vito solve --time-limit` (it stops and
    /// keeps its iterate); a run still going [`KILL_GRACE`] after it is killed.
    pub time_limit: Option<Duration>,
    /// The sweep directory.
    pub out: PathBuf,
    /// Warm starts across the grid.
    pub warm_start: WarmStart,
    /// A stop request (a signal): no new run starts, the running ones are asked to stop
    /// after their current iteration (SIGTERM) and are waited for.
    pub stop: Option<Arc<AtomicBool>>,
    /// Starts of each point's own run (`vito solve --starts`; 1: the problem's guess only).
    pub starts: usize,
    /// Seed of those starts (`vito solve --seed`).
    pub seed: u64,
    /// Rounds of the neighbour pass (0: none): see [`crate::sweep::SETTLE_RATIO`].
    pub neighbour_rounds: usize,
}

/// Counts for a progress display.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Progress {
    /// Runs of this shard that are finished (including earlier sweeps').
    pub done: usize,
    /// Runs that failed or timed out in this sweep.
    pub failed: usize,
    /// Runs stopped by a stop request in this sweep (their iterates kept, run again on resume).
    pub interrupted: usize,
    /// Runs going now.
    pub running: usize,
    /// Runs of this shard.
    pub total: usize,
    /// Finished before this sweep started (skipped).
    pub skipped: usize,
    /// Neighbour-pass attempts run so far in this sweep.
    pub attempts_done: usize,
    /// Neighbour-pass attempts planned so far in this sweep.
    pub attempts_total: usize,
}

/// What a sweep reports while it runs.
#[derive(Debug, Clone, Copy)]
pub enum Event<'a> {
    /// The counts changed (a run started).
    Progress(&'a Progress),
    /// A run ended; its row is up to date and the counts include it.
    Ended(&'a Row, &'a Progress),
    /// A stop request arrived: `running` runs were asked to stop, no new run starts.
    Stopping {
        /// Runs asked to stop.
        running: usize,
    },
    /// A round of the neighbour pass starts.
    Round {
        /// Its number, from 1.
        round: usize,
        /// Attempts it plans.
        attempts: usize,
        /// Of them, those not already on disk from an earlier run of the sweep.
        to_run: usize,
    },
    /// A round of the neighbour pass ended; the table is up to date.
    RoundEnded {
        /// Its number, from 1.
        round: usize,
        /// The grid indices of the points whose answer it improved.
        improved: &'a [usize],
        /// The table.
        table: &'a Table,
    },
}

/// How a sweep ended.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The table (also on disk).
    pub table: Table,
    /// The final counts.
    pub counts: Progress,
    /// Whether a stop request ended it early.
    pub interrupted: bool,
}

/// Prepares `dir` as a sweep directory: creates it, or accepts it when empty or already a
/// sweep's (it holds [`SWEEP_MARKER`]); anything else is refused, so vito never mixes its
/// files into a directory it did not make.
pub fn prepare_dir(dir: &Path) -> Result<(), SweepError> {
    let io = |source| SweepError::Io {
        path: dir.to_owned(),
        source,
    };
    let marker = dir.join(SWEEP_MARKER);
    let marked = || std::fs::symlink_metadata(&marker).is_ok_and(|m| m.is_file());
    match std::fs::symlink_metadata(dir) {
        Ok(m) if m.is_dir() => {
            let empty = std::fs::read_dir(dir).map_err(io)?.next().is_none();
            if !marked() && !empty {
                return Err(SweepError::NotOurs {
                    path: dir.to_owned(),
                });
            }
        }
        Ok(_) => {
            return Err(SweepError::NotOurs {
                path: dir.to_owned(),
            });
        }
        Err(_) => std::fs::create_dir_all(dir).map_err(io)?,
    }
    if !marked() {
        let mut f = create_new_file(&marker)?;
        std::io::Write::write_all(
            &mut f,
            b"This directory holds a vito sweep; vito adds runs to it and rewrites its tables.\n",
        )
        .map_err(|source| SweepError::Io {
            path: marker.clone(),
            source,
        })?;
    }
    Ok(())
}

/// Makes `dir/sub` (one of the sweep's own subdirectories), or accepts it when it is a
/// directory; a symbolic link there is refused, never followed.
pub(crate) fn own_subdir(dir: &Path, sub: &str) -> Result<PathBuf, SweepError> {
    let path = dir.join(sub);
    match std::fs::symlink_metadata(&path) {
        Ok(m) if m.is_dir() => Ok(path),
        Ok(m) if m.is_symlink() => Err(SweepError::Link { path }),
        Ok(_) => Err(SweepError::NotOurs { path }),
        Err(_) => match std::fs::create_dir(&path) {
            Ok(()) => Ok(path),
            Err(source) => Err(SweepError::Io { path, source }),
        },
    }
}

/// Creates (or truncates) a file of the sweep's own: never through a symbolic link planted
/// at its name (refused), never anything but a regular file.
fn create_own_file(path: &Path) -> Result<std::fs::File, SweepError> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .custom_flags(rustix::fs::OFlags::NOFOLLOW.bits() as i32)
        .open(path)
        .map_err(|source| {
            if std::fs::symlink_metadata(path).is_ok_and(|m| m.is_symlink()) {
                SweepError::Link {
                    path: path.to_owned(),
                }
            } else {
                SweepError::Io {
                    path: path.to_owned(),
                    source,
                }
            }
        })
}

/// Creates a new file (never through a link, never over an existing file).
fn create_new_file(path: &Path) -> Result<std::fs::File, SweepError> {
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
        .map_err(|source| SweepError::Io {
            path: path.to_owned(),
            source,
        })
}

/// One process to run: a grid point's own run (the first pass) or a neighbour-pass attempt.
struct Job {
    point: Point,
    /// Its run directory, relative to the sweep directory.
    dir: String,
    /// Its log, relative to the sweep directory.
    log: String,
    /// The run directory (relative to the sweep directory) whose plan is its start.
    warm: Option<String>,
    /// A neighbour-pass attempt (one start), not the point's own run.
    attempt: bool,
}

struct Running {
    job: Job,
    child: Child,
    started: Instant,
}

/// A sweep in progress: the table, the counts and the caller's ear.
struct SweepRun<'a, F: FnMut(Event)> {
    options: &'a SweepOptions,
    sha256: &'a str,
    points: Vec<Point>,
    table: Table,
    writes: TableWrites,
    counts: Progress,
    stopping: bool,
    on_event: F,
}

/// The absolute name of `out` when a sweep into it cannot name its runs' warm starts, else
/// None: with neighbour warm starts or the neighbour pass (`warm_starts`) each run is given
/// the trajectory it starts from as the problem's `initial_guess.warm_start`, a TOML string,
/// so the directory's absolute name must be UTF-8.
pub fn out_name_without_utf8(out: &Path, warm_starts: bool) -> Option<PathBuf> {
    let absolute = std::path::absolute(out).unwrap_or_else(|_| out.to_path_buf());
    (warm_starts && absolute.to_str().is_none()).then_some(absolute)
}

/// Runs the shard's points that have no finished result yet, then (unless
/// `neighbour_rounds` is 0) the neighbour pass, and returns the table (also written to `out`
/// after each run) with the final counts. `on_event` hears of every run that starts or ends
/// and of a stop request.
pub fn run_sweep(
    options: &SweepOptions,
    sha256: &str,
    on_event: impl FnMut(Event),
) -> Result<Outcome, SweepError> {
    let out = &options.out;
    prepare_dir(out)?;
    let runs = own_subdir(out, RUNS)?;
    own_subdir(out, LOGS)?;
    let points: Vec<Point> = options
        .grid
        .points()
        .filter(|p| options.shard.contains(p.index))
        .collect();
    let mut table = Table {
        problem: options.problem.display().to_string(),
        problem_sha256: sha256.to_owned(),
        sets: options.sets.clone(),
        grid: options.grid.clone(),
        shard: options.shard,
        rows: Vec::new(),
    };
    // The table is rebuilt from the run directories: what is on disk is what counts.
    let mut queue = Vec::new();
    for p in &points {
        let name = p.run_name();
        let mut row = Row::pending(p, format!("{RUNS}/{name}"));
        let parameters = expected_parameters(&options.sets, p)?;
        if read_result(&mut row, &runs.join(&name), sha256, &parameters) == OnDisk::Finished {
            row.start = first_pass_start(&runs.join(&name), &points);
        } else {
            queue.push(Job {
                point: p.clone(),
                dir: format!("{RUNS}/{name}"),
                log: format!("{LOGS}/{name}.log"),
                warm: None,
                attempt: false,
            });
        }
        table.rows.push(row);
    }
    table.write(out)?;
    let counts = Progress {
        done: points.len() - queue.len(),
        total: points.len(),
        skipped: points.len() - queue.len(),
        ..Progress::default()
    };
    let mut run = SweepRun {
        options,
        sha256,
        points,
        table,
        counts,
        writes: TableWrites::default(),
        stopping: false,
        on_event,
    };
    (run.on_event)(Event::Progress(&run.counts));
    queue.reverse(); // pop() takes them in grid order
    run.run_jobs(queue)?;
    if options.neighbour_rounds > 0 && !run.stopping {
        run.neighbour_pass()?;
    }
    Ok(Outcome {
        table: run.table,
        counts: run.counts,
        interrupted: run.stopping,
    })
}

impl<F: FnMut(Event)> SweepRun<'_, F> {
    fn stop_requested(&self) -> bool {
        self.options
            .stop
            .as_ref()
            .is_some_and(|s| s.load(Ordering::SeqCst))
    }

    /// Runs `queue` (popped from the end), at most `jobs` at a time, until it is empty or a
    /// stop request arrives, and waits for the running ones.
    fn run_jobs(&mut self, mut queue: Vec<Job>) -> Result<(), SweepError> {
        let options = self.options;
        let mut running: Vec<Running> = Vec::new();
        let jobs = options.jobs.max(1);
        while (!queue.is_empty() && !self.stopping) || !running.is_empty() {
            if !self.stopping && self.stop_requested() {
                self.stopping = true;
                // Runs in the sweep's process group heard a terminal's Ctrl-C already; the
                // request counts once whoever sends it twice.
                for r in &mut running {
                    ask_to_stop(&mut r.child);
                }
                (self.on_event)(Event::Stopping {
                    running: running.len(),
                });
            }
            while running.len() < jobs && !self.stopping {
                let Some(mut job) = queue.pop() else { break };
                if !job.attempt && options.warm_start == WarmStart::Neighbour {
                    let rows = table_rows(&self.table);
                    job.warm = nearest_finished(&job.point, &self.points, &rows)
                        .map(|n| format!("{RUNS}/{}", n.run_name()));
                }
                if !job.attempt {
                    let note = job
                        .warm
                        .as_ref()
                        .map(|w| {
                            let name = w.strip_prefix(&format!("{RUNS}/")).unwrap_or(w);
                            format!("warm start from {name}")
                        })
                        .unwrap_or_default();
                    let row = self.table.row_mut(job.point.index)?;
                    row.clear_result();
                    row.note = note;
                }
                let child = spawn(options, &job)?;
                running.push(Running {
                    job,
                    child,
                    started: Instant::now(),
                });
                self.counts.running = running.len();
                (self.on_event)(Event::Progress(&self.counts));
            }
            std::thread::sleep(Duration::from_millis(20));
            let mut i = 0;
            while i < running.len() {
                let r = &mut running[i];
                let timed_out = options
                    .time_limit
                    .is_some_and(|limit| r.started.elapsed() > limit + KILL_GRACE);
                let exit = match r.child.try_wait() {
                    Ok(Some(status)) => Some((status.code(), false)),
                    Ok(None) if timed_out => {
                        let _ = r.child.kill();
                        let _ = r.child.wait();
                        Some((None, true))
                    }
                    Ok(None) => None,
                    Err(e) => {
                        let _ = r.child.kill();
                        let _ = r.child.wait();
                        return Err(SweepError::Internal(format!("waiting for a run: {e}")));
                    }
                };
                let Some((code, killed)) = exit else {
                    i += 1;
                    continue;
                };
                let r = running.swap_remove(i);
                self.counts.running = running.len();
                if r.job.attempt {
                    self.counts.attempts_done += 1;
                    (self.on_event)(Event::Progress(&self.counts));
                    continue;
                }
                match record(options, &mut self.table, &r.job, code, killed, self.sha256)? {
                    OnDisk::Finished => self.counts.done += 1,
                    OnDisk::Interrupted => self.counts.interrupted += 1,
                    OnDisk::TimedOut | OnDisk::Nothing => self.counts.failed += 1,
                }
                if let Some(w) = &r.job.warm {
                    let label = self.label_of_dir(w);
                    self.table.row_mut(r.job.point.index)?.start = format!("warm {label}");
                } else {
                    self.table.row_mut(r.job.point.index)?.start = "guess".into();
                }
                self.writes.write(&self.table, &options.out, false)?;
                let row = self
                    .table
                    .rows
                    .iter()
                    .find(|row| row.index == r.job.point.index)
                    .ok_or_else(|| SweepError::Internal("a point without a row".into()))?;
                (self.on_event)(Event::Ended(row, &self.counts));
            }
        }
        self.writes.write(&self.table, &options.out, true)?;
        Ok(())
    }

    fn label_of_dir(&self, dir: &str) -> String {
        neighbours::label_of_dir(&self.points, dir)
    }

    /// Rounds of re-solves from the neighbours' plans (see [`neighbours`]): each round plans
    /// its attempts from the answers at its start, runs those not already on disk, then folds
    /// them in, in grid order; a rerun replays the same rounds from the attempts on disk.
    fn neighbour_pass(&mut self) -> Result<(), SweepError> {
        let options = self.options;
        let mut tried = BTreeSet::new();
        for round in 1..=options.neighbour_rounds {
            let plan = neighbours::plan_round(&self.points, &self.table.rows, &tried);
            if plan.is_empty() {
                break;
            }
            let mut queue = Vec::new();
            let parent = own_subdir(&options.out, neighbours::ATTEMPTS)?;
            for a in &plan {
                let Some(point) = self.points.iter().find(|p| p.index == a.target).cloned() else {
                    continue;
                };
                if neighbours::attempt_result(&options.out, &options.sets, self.sha256, &point, a)?
                    .is_some()
                {
                    continue;
                }
                own_subdir(&parent, &point.run_name())?;
                queue.push(Job {
                    point,
                    dir: a.dir.clone(),
                    log: format!("{LOGS}/{}.log", a.dir.replace('/', "__")),
                    warm: Some(a.source_dir.clone()),
                    attempt: true,
                });
            }
            self.counts.attempts_total += queue.len();
            (self.on_event)(Event::Round {
                round,
                attempts: plan.len(),
                to_run: queue.len(),
            });
            queue.reverse();
            self.run_jobs(queue)?;
            if self.stopping {
                return Ok(());
            }
            let (out, sets, sha256) = (&options.out, &options.sets, self.sha256);
            let improved = neighbours::fold_round(
                &plan,
                &self.points,
                &mut self.table.rows,
                &mut tried,
                |point, a| neighbours::attempt_result(out, sets, sha256, point, a),
            )?;
            self.table.write(&options.out)?;
            (self.on_event)(Event::RoundEnded {
                round,
                improved: &improved,
                table: &self.table,
            });
            if improved.is_empty() {
                break;
            }
        }
        neighbours::mark_settled(&self.points, &mut self.table.rows, &tried);
        self.table.write(&options.out)
    }
}

/// `start` of a first-pass run found on disk: `warm <point>` when its summary says it was
/// warm-started from a run of this sweep, else `guess`.
pub(crate) fn first_pass_start(run_dir: &Path, points: &[Point]) -> String {
    let warm = std::fs::read_to_string(run_dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|s| s["parameters"][WARM_START_KEY].as_str().map(str::to_owned));
    let Some(path) = warm else {
        return "guess".into();
    };
    let name = Path::new(&path)
        .parent()
        .and_then(Path::file_name)
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    points
        .iter()
        .find(|p| p.run_name() == name)
        .map_or_else(|| "warm start".into(), |p| format!("warm {}", p.label()))
}

fn table_rows(table: &Table) -> Vec<(usize, RunStatus)> {
    table.rows.iter().map(|r| (r.index, r.status)).collect()
}

/// The finished point nearest to `point` in the grid (ties: the lower index).
pub(crate) fn nearest_finished(
    point: &Point,
    points: &[Point],
    status: &[(usize, RunStatus)],
) -> Option<Point> {
    points
        .iter()
        .filter(|p| {
            p.index != point.index
                && status
                    .iter()
                    .any(|(i, s)| *i == p.index && *s == RunStatus::Finished)
        })
        .min_by_key(|p| (p.distance(point), p.index))
        .cloned()
}

fn spawn(options: &SweepOptions, job: &Job) -> Result<Child, SweepError> {
    let out = &options.out;
    let log_path = out.join(&job.log);
    let log = create_own_file(&log_path)?;
    let log_err = log.try_clone().map_err(|source| SweepError::Io {
        path: log_path.clone(),
        source,
    })?;
    let mut cmd = Command::new(&options.exe);
    // Not --quiet: the log shows each iteration, so a killed or stopped run shows where it was.
    cmd.arg("solve").arg(&options.problem);
    for s in options.sets.iter().cloned().chain(job.point.set_args()) {
        cmd.arg("--set").arg(s);
    }
    if let Some(dir) = &job.warm {
        let csv = std::path::absolute(out.join(dir).join("trajectory.csv")).map_err(|source| {
            SweepError::Io {
                path: out.to_owned(),
                source,
            }
        })?;
        let value = toml::Value::String(csv.display().to_string());
        cmd.arg("--set").arg(format!("{WARM_START_KEY}={value}"));
    }
    // The point's own run takes the sweep's starts; an attempt starts from one plan.
    if !job.attempt && options.starts > 1 {
        cmd.arg("--starts")
            .arg(options.starts.to_string())
            .arg("--seed")
            .arg(options.seed.to_string())
            // The sweep's jobs are the parallelism; its runs' starts go one after another.
            .args(["--jobs", "1"]);
    }
    // Parallelism comes from the runs (processes); BLAS threads would only compete with
    // them, and one thread gives the same numbers on every run.
    if std::env::var_os("OPENBLAS_NUM_THREADS").is_none() {
        cmd.env("OPENBLAS_NUM_THREADS", "1");
    }
    if let Some(limit) = options.time_limit {
        cmd.arg("--time-limit").arg(limit.as_secs_f64().to_string());
    }
    cmd.arg("--out")
        .arg(out.join(&job.dir))
        .arg(PARENT_FLAG)
        .arg(std::process::id().to_string())
        // The pipe the sweep closes to stop the run (`ask_to_stop`).
        .stdin(Stdio::piped())
        .stdout(log)
        .stderr(log_err);
    cmd.spawn().map_err(|source| SweepError::Spawn {
        exe: options.exe.clone(),
        source,
    })
}

/// Records a run that ended; returns what it left on disk.
fn record(
    options: &SweepOptions,
    table: &mut Table,
    job: &Job,
    code: Option<i32>,
    killed: bool,
    sha256: &str,
) -> Result<OnDisk, SweepError> {
    let point = &job.point;
    let name = point.run_name();
    let parameters = expected_parameters(&options.sets, point)?;
    let row = table
        .rows
        .iter_mut()
        .find(|r| r.index == point.index)
        .ok_or_else(|| SweepError::Internal("a point without a row".into()))?;
    let warm_note = std::mem::take(&mut row.note);
    if !killed {
        match read_result(
            row,
            &options.out.join(RUNS).join(&name),
            sha256,
            &parameters,
        ) {
            OnDisk::Finished => {
                row.note = warm_note;
                return Ok(OnDisk::Finished);
            }
            OnDisk::Interrupted => {
                row.note = format!(
                    "stopped by a signal; its iterate is in {RUNS}/{name}; a rerun of the sweep runs it again"
                );
                return Ok(OnDisk::Interrupted);
            }
            OnDisk::TimedOut => {
                row.note = format!(
                    "stopped at the time limit of {} s; its iterate is in {RUNS}/{name}; a rerun of the sweep runs it again",
                    options.time_limit.map_or(0.0, |t| t.as_secs_f64())
                );
                return Ok(OnDisk::TimedOut);
            }
            OnDisk::Nothing => {}
        }
    }
    let log = std::fs::read_to_string(options.out.join(LOGS).join(format!("{name}.log")))
        .unwrap_or_default();
    let error = log
        .lines()
        .rev()
        .find(|l| l.starts_with("error:"))
        .map(str::to_owned);
    row.status = if killed {
        RunStatus::Timeout
    } else {
        RunStatus::Failed
    };
    row.note = if killed {
        format!(
            "killed {} s after the time limit of {} s; nothing of it is kept",
            KILL_GRACE.as_secs(),
            options.time_limit.map_or(0.0, |t| t.as_secs_f64())
        )
    } else {
        let exit = code.map_or("killed by a signal".to_owned(), |c| format!("exit {c}"));
        match error {
            Some(e) => format!("{exit}: {e}"),
            None => format!("{exit} without a complete summary.json (see {LOGS}/{name}.log)"),
        }
    };
    Ok(OnDisk::Nothing)
}

/// In a run started by a sweep (`parent`, the sweep's process id): asks the kernel to kill
/// this process when the sweep dies, so that killing a sweep leaves no solve running (a
/// rerun then starts from what is on disk). Returns false when the sweep has already ended.
pub fn die_with_sweep(parent: u32) -> bool {
    let _ = rustix::process::set_parent_process_death_signal(Some(rustix::process::Signal::KILL));
    // The sweep may have died before the request above took effect.
    rustix::process::getppid().is_some_and(|p| p.as_raw_nonzero().get() as u32 == parent)
}

/// In a run started by a sweep or by a parallel multi-start: sets `stop` when the parent
/// asks the run to stop, which it does by closing the run's standard input (a pipe). The
/// request waits in the pipe until it is read, so one made while the run is still starting
/// is not lost, as a signal arriving before the run's handler would be.
pub fn stop_when_the_parent_asks(stop: Arc<AtomicBool>) {
    std::thread::spawn(move || {
        use std::io::Read;
        let mut stdin = std::io::stdin().lock();
        let mut byte = [0u8; 1];
        loop {
            match stdin.read(&mut byte) {
                // Closed, or written to: either is the request.
                Ok(_) => break,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                // No pipe to listen on: only signals can stop this run.
                Err(_) => return,
            }
        }
        stop.store(true, Ordering::SeqCst);
    });
}

/// Asks a run to stop after its current iteration (see [`stop_when_the_parent_asks`]).
pub fn ask_to_stop(child: &mut Child) {
    drop(child.stdin.take());
}
