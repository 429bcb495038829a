//! A sweep whose points are solved elsewhere (Python's `concurrent.futures` executors: a
//! process pool, Dask, Ray, Slurm through submitit): the same sweep directory, run
//! directories, resumable table and neighbour warm starts as [`crate::sweep::run_sweep`],
//! with each point handed out as a [`PointJob`] and its result recorded from its run
//! directory when the job comes back.

use std::path::{Path, PathBuf};

use crate::sweep::run::{nearest_finished, own_subdir};
use crate::sweep::table::{OnDisk, WARM_START_KEY, expected_parameters, read_result};
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
    counts: Progress,
}

impl JobSweep {
    /// Opens (or resumes) the sweep directory `out` for `problem` (its SHA-256 `sha256`)
    /// with the fixed overrides `sets` over `grid`: the table is rebuilt from the run
    /// directories, as [`crate::sweep::run_sweep`] rebuilds it, and written.
    pub fn open(
        problem: &Path,
        sha256: &str,
        sets: &[String],
        grid: &Grid,
        out: &Path,
        warm_start: WarmStart,
    ) -> Result<JobSweep, SweepError> {
        prepare_dir(out)?;
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
            if read_result(&mut row, &runs.join(&name), sha256, &parameters) != OnDisk::Finished {
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
        })
    }

    /// The next point to solve (in grid order), or None when every point is handed out.
    /// With neighbour warm starts, it starts from the nearest point finished so far.
    pub fn next_job(&mut self) -> Result<Option<PointJob>, SweepError> {
        let Some(point) = self.queue.pop() else {
            return Ok(None);
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
        let row = self.row_mut(point.index)?;
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
        }))
    }

    /// Records the job of point `index` from its run directory and rewrites the table;
    /// returns the point's row.
    pub fn record(&mut self, index: usize, outcome: JobOutcome) -> Result<&Row, SweepError> {
        self.running.retain(|&i| i != index);
        self.counts.running = self.running.len();
        let point = self
            .points
            .get(index)
            .cloned()
            .ok_or_else(|| SweepError::Internal(format!("no point {index}")))?;
        let parameters = expected_parameters(&self.table.sets, &point)?;
        let run_dir = self.runs.join(point.run_name());
        let sha256 = self.sha256.clone();
        let row = self.row_mut(index)?;
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
        self.table.write(&self.out)?;
        self.row_mut(index).map(|r| &*r)
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
        for index in unfinished {
            self.row_mut(index)?.status = RunStatus::Pending;
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

    fn row_mut(&mut self, index: usize) -> Result<&mut Row, SweepError> {
        self.table
            .rows
            .iter_mut()
            .find(|r| r.index == index)
            .ok_or_else(|| SweepError::Internal("a point without a row".into()))
    }
}
