//! A sweep whose points are solved elsewhere (Python's `concurrent.futures` executors: a
//! process pool, Dask, Ray, Slurm through submitit): the same sweep directory, run
//! directories, resumable table and neighbour warm starts as [`crate::sweep::run_sweep`],
//! with each point handed out as a [`PointJob`] and its result recorded from its run
//! directory when the job comes back. Once every point is recorded, the rounds of the
//! neighbour pass ([`crate::sweep::neighbours`]) are handed out the same way, each attempt a
//! job of its own, and folded in as `vito sweep` folds them.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use crate::sweep::neighbours::{self, Attempt};
use crate::sweep::run::{first_pass_start, nearest_finished, own_subdir};
use crate::sweep::table::{OnDisk, TableWrites, WARM_START_KEY, expected_parameters, read_result};
use crate::sweep::{
    Grid, Point, Progress, RUNS, Row, RunStatus, Shard, SweepError, Table, WarmStart, prepare_dir,
};

/// One point to solve: the overrides to load the problem with, and the directory to write
/// (what `vito solve FILE --set ... --out RUN_DIR` would be given).
#[derive(Debug, Clone, PartialEq)]
pub struct PointJob {
    /// The point's index in the grid.
    pub index: usize,
    /// The fixed overrides, then the point's, then (with a warm start) the warm start's.
    pub sets: Vec<String>,
    /// The run directory (absolute).
    pub run_dir: PathBuf,
    /// The finished run whose trajectory it starts from, if any.
    pub warm_start: Option<PathBuf>,
    /// For a neighbour-pass attempt, its directory relative to the sweep directory
    /// (`attempts/<point>/from-p<i>-<hash>`), given back to [`JobSweep::record`]; None for a
    /// point's own run.
    pub attempt: Option<String>,
}

/// How a job came back.
#[derive(Debug, Clone, PartialEq)]
pub enum JobOutcome {
    /// The job returned: its run directory says how the solve ended.
    Returned,
    /// The job stopped its solve at the per-run time limit.
    TimedOut {
        /// The limit [s].
        limit_s: f64,
    },
    /// The job raised an error (its message).
    Failed(String),
}

/// A sweep driven from outside: hands out the points that have no finished result and
/// records each result, rewriting the table after every change.
#[derive(Debug)]
pub struct JobSweep {
    out: PathBuf,
    runs: PathBuf,
    sha256: String,
    warm_start: WarmStart,
    points: Vec<Point>,
    /// Points not handed out yet, the next one last.
    queue: Vec<Point>,
    /// Points handed out and not recorded.
    running: Vec<usize>,
    table: Table,
    writes: TableWrites,
    counts: Progress,
    /// Rounds of the neighbour pass still allowed.
    rounds_left: usize,
    /// The round handed out now (folded once its attempts are all back).
    plan: Vec<Attempt>,
    /// Attempts of that round not handed out yet, the next one last.
    attempts: Vec<Attempt>,
    /// Attempt directories handed out and not recorded.
    running_attempts: Vec<String>,
    /// Attempt directories folded in.
    tried: BTreeSet<String>,
}

impl JobSweep {
    /// Opens (or resumes) the sweep directory `out` for `problem` (its SHA-256 `sha256`)
    /// with the fixed overrides `sets` over `grid`: the table is rebuilt from the run
    /// directories, as [`crate::sweep::run_sweep`] rebuilds it, and written. After the first
    /// pass, up to `neighbour_rounds` rounds of the neighbour pass.
    pub fn open(
        problem: &Path,
        sha256: &str,
        sets: &[String],
        grid: &Grid,
        out: &Path,
        warm_start: WarmStart,
        neighbour_rounds: usize,
    ) -> Result<JobSweep, SweepError> {
        prepare_dir(out)?;
        let out = std::path::absolute(out).map_err(|source| SweepError::Io {
            path: out.to_owned(),
            source,
        })?;
        let out = out.as_path();
        let runs = own_subdir(out, RUNS)?;
        let runs = std::path::absolute(&runs).map_err(|source| SweepError::Io {
            path: runs.clone(),
            source,
        })?;
        let points: Vec<Point> = grid.points().collect();
        let mut table = Table {
            problem: problem.display().to_string(),
            problem_sha256: sha256.to_owned(),
            sets: sets.to_vec(),
            grid: grid.clone(),
            shard: Shard::ALL,
            rows: Vec::with_capacity(points.len()),
        };
        let mut queue = Vec::new();
        for p in &points {
            let name = p.run_name();
            let mut row = Row::pending(p, format!("{RUNS}/{name}"));
            let parameters = expected_parameters(sets, p)?;
            if read_result(&mut row, &runs.join(&name), sha256, &parameters) == OnDisk::Finished {
                row.start = first_pass_start(&runs.join(&name), &points);
            } else {
                queue.push(p.clone());
            }
            table.rows.push(row);
        }
        table.write(out)?;
        let skipped = points.len() - queue.len();
        queue.reverse();
        Ok(JobSweep {
            out: out.to_owned(),
            runs,
            sha256: sha256.to_owned(),
            warm_start,
            counts: Progress {
                done: skipped,
                skipped,
                total: points.len(),
                ..Progress::default()
            },
            points,
            queue,
            running: Vec::new(),
            table,
            writes: TableWrites::default(),
            rounds_left: neighbour_rounds,
            plan: Vec::new(),
            attempts: Vec::new(),
            running_attempts: Vec::new(),
            tried: BTreeSet::new(),
        })
    }

    /// The next job: a point to solve (in grid order; with neighbour warm starts from the
    /// nearest point finished so far), then, once every point is recorded, the attempts of
    /// the neighbour pass round by round. None while the jobs handed out must come back
    /// first, and when the sweep is done (nothing running either).
    pub fn next_job(&mut self) -> Result<Option<PointJob>, SweepError> {
        let Some(point) = self.queue.pop() else {
            return self.next_attempt();
        };
        let warm = match self.warm_start {
            WarmStart::None => None,
            WarmStart::Neighbour => {
                let status: Vec<(usize, RunStatus)> = self
                    .table
                    .rows
                    .iter()
                    .map(|r| (r.index, r.status))
                    .collect();
                nearest_finished(&point, &self.points, &status)
            }
        };
        let mut sets: Vec<String> = self.table.sets.clone();
        sets.extend(point.set_args());
        let warm_start = warm
            .as_ref()
            .map(|n| self.runs.join(n.run_name()).join("trajectory.csv"));
        if let Some(csv) = &warm_start {
            let value = toml::Value::String(csv.display().to_string());
            sets.push(format!("{WARM_START_KEY}={value}"));
        }
        let row = self.table.row_mut(point.index)?;
        row.note = warm
            .as_ref()
            .map(|n| format!("warm start from {}", n.run_name()))
            .unwrap_or_default();
        self.running.push(point.index);
        self.counts.running = self.running.len();
        Ok(Some(PointJob {
            index: point.index,
            sets,
            run_dir: self.runs.join(point.run_name()),
            warm_start,
            attempt: None,
        }))
    }

    /// The next attempt of the neighbour pass: when the round handed out is all back, it is
    /// folded in and the next round planned (attempts already on disk, from an earlier run
    /// of the sweep, are not handed out again).
    fn next_attempt(&mut self) -> Result<Option<PointJob>, SweepError> {
        loop {
            if let Some(attempt) = self.attempts.pop() {
                return self.attempt_job(attempt).map(Some);
            }
            if !self.running.is_empty() || !self.running_attempts.is_empty() {
                return Ok(None);
            }
            if !self.plan.is_empty() {
                let plan = std::mem::take(&mut self.plan);
                let (out, sets, sha256) = (&self.out, &self.table.sets, &self.sha256);
                let improved = neighbours::fold_round(
                    &plan,
                    &self.points,
                    &mut self.table.rows,
                    &mut self.tried,
                    |point, a| neighbours::attempt_result(out, sets, sha256, point, a),
                )?;
                self.table.write(&self.out)?;
                if improved.is_empty() {
                    self.rounds_left = 0;
                }
            }
            if self.rounds_left == 0 {
                return Ok(None);
            }
            self.rounds_left -= 1;
            let plan = neighbours::plan_round(&self.points, &self.table.rows, &self.tried);
            if plan.is_empty() {
                self.rounds_left = 0;
                neighbours::mark_settled(&self.points, &mut self.table.rows, &self.tried);
                self.table.write(&self.out)?;
                return Ok(None);
            }
            let mut to_run = Vec::new();
            for a in &plan {
                let Some(point) = self.points.iter().find(|p| p.index == a.target) else {
                    continue;
                };
                let on_disk = neighbours::attempt_result(
                    &self.out,
                    &self.table.sets,
                    &self.sha256,
                    point,
                    a,
                )?;
                if on_disk.is_none() {
                    to_run.push(a.clone());
                }
            }
            self.counts.attempts_total += to_run.len();
            to_run.reverse();
            self.attempts = to_run;
            self.plan = plan;
        }
    }

    fn attempt_job(&mut self, attempt: Attempt) -> Result<PointJob, SweepError> {
        let point = self
            .points
            .iter()
            .find(|p| p.index == attempt.target)
            .cloned()
            .ok_or_else(|| SweepError::Internal(format!("no point {}", attempt.target)))?;
        let parent = own_subdir(&self.out, neighbours::ATTEMPTS)?;
        own_subdir(&parent, &point.run_name())?;
        let mut sets: Vec<String> = self.table.sets.clone();
        sets.extend(point.set_args());
        let csv = self.out.join(&attempt.source_dir).join("trajectory.csv");
        let value = toml::Value::String(csv.display().to_string());
        sets.push(format!("{WARM_START_KEY}={value}"));
        self.running_attempts.push(attempt.dir.clone());
        self.counts.running = self.running.len() + self.running_attempts.len();
        Ok(PointJob {
            index: point.index,
            sets,
            run_dir: self.out.join(&attempt.dir),
            warm_start: Some(csv),
            attempt: Some(attempt.dir),
        })
    }

    /// Records the job of point `index` (of the neighbour-pass `attempt`, when it was one)
    /// from its run directory and rewrites the table; returns the point's row. An attempt's
    /// result is read when its round is folded in.
    pub fn record(
        &mut self,
        index: usize,
        attempt: Option<&str>,
        outcome: JobOutcome,
    ) -> Result<&Row, SweepError> {
        if let Some(dir) = attempt {
            self.running_attempts.retain(|d| d != dir);
            self.counts.running = self.running.len() + self.running_attempts.len();
            self.counts.attempts_done += 1;
            return self.table.row_mut(index).map(|r| &*r);
        }
        self.running.retain(|&i| i != index);
        self.counts.running = self.running.len() + self.running_attempts.len();
        let point = self
            .points
            .get(index)
            .cloned()
            .ok_or_else(|| SweepError::Internal(format!("no point {index}")))?;
        let parameters = expected_parameters(&self.table.sets, &point)?;
        let run_dir = self.runs.join(point.run_name());
        let sha256 = self.sha256.clone();
        let start = first_pass_start(&run_dir, &self.points);
        let row = self.table.row_mut(index)?;
        let warm_note = std::mem::take(&mut row.note);
        let on_disk = read_result(row, &run_dir, &sha256, &parameters);
        let name = point.run_name();
        match (&outcome, on_disk) {
            (JobOutcome::TimedOut { limit_s }, _) => {
                row.status = RunStatus::Timeout;
                row.note = format!("stopped at the time limit of {limit_s} s");
                self.counts.failed += 1;
            }
            (JobOutcome::Returned, OnDisk::Finished) => {
                row.note = warm_note;
                row.start = start;
                self.counts.done += 1;
            }
            (_, OnDisk::Interrupted) => {
                row.note = format!(
                    "stopped by a signal; its iterate is in {RUNS}/{name}; a rerun of the sweep runs it again"
                );
                self.counts.interrupted += 1;
            }
            (JobOutcome::Failed(message), _) => {
                row.status = RunStatus::Failed;
                row.note = message.lines().next().unwrap_or_default().to_owned();
                self.counts.failed += 1;
            }
            (JobOutcome::Returned, _) => {
                row.status = RunStatus::Failed;
                row.note =
                    format!("the job returned without a complete summary.json in {RUNS}/{name}");
                self.counts.failed += 1;
            }
        }
        // Every point back: the first pass's table in full; before, when due.
        let last = self.running.is_empty() && self.queue.is_empty();
        self.writes.write(&self.table, &self.out, last)?;
        self.table.row_mut(index).map(|r| &*r)
    }

    /// Ends the sweep early (a stop request): the points handed out and not recorded, and
    /// those never handed out, stay pending with a note (a rerun runs them); the table is
    /// written.
    pub fn stop(&mut self) -> Result<(), SweepError> {
        let unfinished: Vec<usize> = self
            .running
            .drain(..)
            .chain(self.queue.drain(..).map(|p| p.index))
            .collect();
        self.attempts.clear();
        self.running_attempts.clear();
        self.plan.clear();
        self.rounds_left = 0;
        for index in unfinished {
            self.table.row_mut(index)?.status = RunStatus::Pending;
        }
        self.table.mark_not_run();
        self.counts.running = 0;
        self.table.write(&self.out)
    }

    /// The table as it stands.
    pub fn table(&self) -> &Table {
        &self.table
    }

    /// The counts as they stand.
    pub fn counts(&self) -> Progress {
        self.counts
    }

    /// Points handed out and not recorded yet.
    pub fn running(&self) -> usize {
        self.running.len()
    }

    /// The run directories of the jobs handed out and not recorded yet (points' and
    /// neighbour-pass attempts'), as their [`PointJob::run_dir`]s named them.
    pub fn running_dirs(&self) -> Vec<PathBuf> {
        let points = self
            .running
            .iter()
            .filter_map(|&i| self.points.get(i))
            .map(|p| self.runs.join(p.run_name()));
        let attempts = self.running_attempts.iter().map(|d| self.out.join(d));
        points.chain(attempts).collect()
    }
}
