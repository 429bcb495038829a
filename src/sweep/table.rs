//! The sweep's table of results (`sweep.json`, `sweep.csv`): one row per grid point, built
//! from the run directories' `summary.json` files, so a killed sweep loses no finished run.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::files::output::write_atomic;
use crate::problem::Override;
use crate::sweep::{Axis, Grid, Point, Shard, SweepError};

/// The table's JSON file.
pub const TABLE_JSON: &str = "sweep.json";
/// The table's CSV file.
pub const TABLE_CSV: &str = "sweep.csv";
/// The override a warm-started run is given (ignored when matching summaries).
pub const WARM_START_KEY: &str = "initial_guess.warm_start";
/// Where the run directories live, under the sweep directory.
pub const RUNS: &str = "runs";

/// Where a run stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// Its complete `summary.json` is on disk (the solver's own status is a column).
    Finished,
    /// The process ended without a summary (an input error, a crash, exit 0 without one).
    Failed,
    /// Stopped at the per-run time limit (its iterate kept, status `timeout`), or killed
    /// when it did not stop soon after it.
    Timeout,
    /// Stopped by a signal (its iterate is in its directory); run again on resume.
    Interrupted,
    /// Not run yet (in this shard: not started; in a collected table: no shard has it).
    Pending,
}

impl RunStatus {
    /// The name in the tables.
    pub fn name(self) -> &'static str {
        match self {
            RunStatus::Finished => "finished",
            RunStatus::Failed => "failed",
            RunStatus::Timeout => "timeout",
            RunStatus::Interrupted => "interrupted",
            RunStatus::Pending => "pending",
        }
    }
}

/// One grid point's result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// Position in the grid's order.
    pub index: usize,
    /// `(key, value)` per axis.
    pub values: Vec<(String, String)>,
    /// Where the run stands.
    pub status: RunStatus,
    /// Ipopt's status from the summary (`solve_succeeded`, …).
    pub solver_status: Option<String>,
    /// Objective value.
    pub objective: Option<f64>,
    /// Ipopt iterations.
    pub iterations: Option<u64>,
    /// Wall time of the solve [s].
    pub wall_time_s: Option<f64>,
    /// Largest complementarity slack.
    pub max_slack: Option<f64>,
    /// The summary's `metrics` (numeric leaves, nested keys joined with `.`).
    pub metrics: BTreeMap<String, f64>,
    /// The run directory, relative to the table's directory.
    pub dir: String,
    /// Why it failed, or where its warm start came from.
    pub note: String,
    /// Where the answer started: `guess` (the problem's initial guess, or the best of its
    /// starts with `--starts`), `warm <point>` (a first-pass warm start from that point's
    /// plan) or `neighbour <point>` (the neighbour pass found it from that point's plan).
    #[serde(default)]
    pub start: String,
    /// Whether the neighbour pass tried every solved neighbour's current plan from this point
    /// without improving it by more than [`crate::sweep::SETTLE_RATIO`] (None: no neighbour
    /// pass ran).
    #[serde(default)]
    pub settled: Option<bool>,
    /// With `--starts K`: the objectives of the starts that solved (the answer is the lowest).
    #[serde(default)]
    pub start_objectives: Vec<f64>,
}

impl Row {
    /// Forgets the row's result (before its point runs again, so that nothing of an earlier
    /// attempt shows); keeps its point and directory.
    pub fn clear_result(&mut self) {
        *self = Row {
            values: std::mem::take(&mut self.values),
            dir: std::mem::take(&mut self.dir),
            ..Row::pending_at(self.index)
        };
    }

    fn pending_at(index: usize) -> Row {
        Row {
            index,
            values: Vec::new(),
            status: RunStatus::Pending,
            solver_status: None,
            objective: None,
            iterations: None,
            wall_time_s: None,
            max_slack: None,
            metrics: BTreeMap::new(),
            dir: String::new(),
            note: String::new(),
            start: String::new(),
            settled: None,
            start_objectives: Vec::new(),
        }
    }

    /// A row with no result yet.
    pub fn pending(point: &Point, dir: String) -> Row {
        Row {
            values: point.values.clone(),
            dir,
            ..Row::pending_at(point.index)
        }
    }

    /// The point's values as `key=value` pairs separated by spaces.
    pub fn point_label(&self) -> String {
        crate::sweep::grid::values_label(&self.values)
    }

    /// The value of a column by name: `objective`, `iterations`, `wall_time_s`, `max_slack`
    /// or a metric (`metrics.x` or `x`).
    pub fn metric(&self, name: &str) -> Option<f64> {
        match name {
            "objective" => self.objective,
            "iterations" => self.iterations.map(|i| i as f64),
            "wall_time_s" | "time" => self.wall_time_s,
            "max_slack" => self.max_slack,
            _ => self
                .metrics
                .get(name.strip_prefix("metrics.").unwrap_or(name))
                .copied(),
        }
    }
}

/// The table of a sweep (or of several shards, collected).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Table {
    /// The problem file, as given.
    pub problem: String,
    /// SHA-256 of the problem file (a run counts only if its summary has the same).
    pub problem_sha256: String,
    /// The fixed `--set` overrides given to every run.
    pub sets: Vec<String>,
    /// The swept axes.
    pub grid: Grid,
    /// The shard this table covers (`0/1` for the whole grid).
    pub shard: Shard,
    /// One row per point of the shard, in grid order.
    pub rows: Vec<Row>,
}

/// The overrides a run's summary must list: the fixed ones, then the point's (as JSON, the
/// way `summary.json` writes `parameters`).
pub fn expected_parameters(
    sets: &[String],
    point: &Point,
) -> Result<serde_json::Map<String, Value>, SweepError> {
    let mut map = serde_json::Map::new();
    for arg in sets.iter().cloned().chain(point.set_args()) {
        let o = Override::parse(&arg).map_err(|e| SweepError::Usage(e.to_string()))?;
        let value = serde_json::to_value(&o.value).unwrap_or(Value::Null);
        map.insert(o.path, value);
    }
    Ok(map)
}

/// Solver statuses that mean the solve was stopped from outside, not finished: such a run
/// is run again.
const INTERRUPTED: &[&str] = &["user_requested_stop"];

/// What a run directory holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OnDisk {
    /// A complete `summary.json` of this problem and point.
    Finished,
    /// A complete `summary.json` of this problem and point, stopped by a signal.
    Interrupted,
    /// A complete `summary.json` of this problem and point, stopped at its time limit.
    TimedOut,
    /// No result of this problem and point.
    Nothing,
}

/// Fills `row` from `run_dir/summary.json` when that is complete, is of this problem
/// (`sha256`) and lists exactly `parameters`, and says what it found.
pub fn read_result(
    row: &mut Row,
    run_dir: &Path,
    sha256: &str,
    parameters: &serde_json::Map<String, Value>,
) -> OnDisk {
    let Ok(text) = std::fs::read_to_string(run_dir.join("summary.json")) else {
        return OnDisk::Nothing;
    };
    let Ok(summary) = serde_json::from_str::<Value>(&text) else {
        return OnDisk::Nothing;
    };
    let same_problem = summary["problem_sha256"].as_str() == Some(sha256);
    // How a run was started is not part of what it solved.
    let mut listed = summary["parameters"]
        .as_object()
        .cloned()
        .unwrap_or_default();
    listed.remove(WARM_START_KEY);
    let same_parameters = summary["parameters"].is_object() && &listed == parameters;
    let status = crate::report::summary_verdict(&summary)
        .map(|v| v.name().to_owned())
        .or_else(|| summary["status"].as_str().map(str::to_owned));
    if !same_problem || !same_parameters || status.is_none() {
        return OnDisk::Nothing;
    }
    let interrupted = status.as_deref().is_some_and(|s| INTERRUPTED.contains(&s));
    let timed_out = status.as_deref() == Some(crate::transcription::TIMEOUT);
    row.status = if interrupted {
        RunStatus::Interrupted
    } else if timed_out {
        RunStatus::Timeout
    } else {
        RunStatus::Finished
    };
    row.solver_status = status;
    row.objective = summary["objective"].as_f64();
    row.iterations = summary["iterations"].as_u64();
    row.wall_time_s = summary["wall_time_s"].as_f64();
    row.max_slack = summary["max_slack"].as_f64();
    row.metrics.clear();
    flatten_numbers(&summary["metrics"], "", &mut row.metrics);
    row.start_objectives = summary["starts"]
        .as_array()
        .map(|starts| {
            starts
                .iter()
                .filter(|s| {
                    s["status"]
                        .as_str()
                        .and_then(crate::transcription::SolveVerdict::from_name)
                        .is_some_and(|v| v.is_solved())
                })
                .filter_map(|s| s["objective"].as_f64())
                .collect()
        })
        .unwrap_or_default();
    if interrupted {
        OnDisk::Interrupted
    } else if timed_out {
        OnDisk::TimedOut
    } else {
        OnDisk::Finished
    }
}

fn flatten_numbers(value: &Value, prefix: &str, out: &mut BTreeMap<String, f64>) {
    match value {
        Value::Number(n) => {
            if let Some(x) = n.as_f64() {
                out.insert(prefix.to_owned(), x);
            }
        }
        Value::Object(map) => {
            for (k, v) in map {
                let key = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten_numbers(v, &key, out);
            }
        }
        _ => {}
    }
}

/// The table's rewrites while a sweep runs: after each run the table is rewritten only once
/// [`REWRITE_SPACING`] times the last rewrite's duration has passed since it, so that
/// rewriting a large grid's table (100,000 rows) stays a small, fixed share of the sweep's
/// time whatever the grid's size; a small grid's table (milliseconds) is still rewritten
/// after every run. The end of a pass, a stop and a round always rewrite it.
#[derive(Debug, Default)]
pub struct TableWrites {
    last: Option<(std::time::Instant, std::time::Duration)>,
}

/// Where the row of point `index` is in `rows`: found by bisection in a table's rows (in
/// grid order, so that a sweep's bookkeeping stays proportional to its points), by a scan in
/// any other order.
pub(crate) fn row_position(rows: &[Row], index: usize) -> Option<usize> {
    rows.binary_search_by_key(&index, |r| r.index)
        .ok()
        .or_else(|| rows.iter().position(|r| r.index == index))
}

/// See [`TableWrites`].
pub const REWRITE_SPACING: u32 = 10;

impl TableWrites {
    /// Writes `table` into `dir` when due, or always with `force`; whether it wrote.
    pub fn write(&mut self, table: &Table, dir: &Path, force: bool) -> Result<bool, SweepError> {
        let due = self
            .last
            .is_none_or(|(at, took)| at.elapsed() >= took * REWRITE_SPACING);
        if !(force || due) {
            return Ok(false);
        }
        let start = std::time::Instant::now();
        table.write(dir)?;
        self.last = Some((std::time::Instant::now(), start.elapsed()));
        Ok(true)
    }
}

impl Table {
    /// The row of point `index` (every point of the table has one).
    pub(crate) fn row_mut(&mut self, index: usize) -> Result<&mut Row, SweepError> {
        row_position(&self.rows, index)
            .map(|i| &mut self.rows[i])
            .ok_or_else(|| SweepError::Internal("a point without a row".into()))
    }

    /// After a stop request: every point that did not run (still pending) says so in its
    /// note (a rerun of the sweep runs it).
    pub fn mark_not_run(&mut self) {
        for row in self
            .rows
            .iter_mut()
            .filter(|r| r.status == RunStatus::Pending)
        {
            row.note = "not run: the sweep was stopped; a rerun of the sweep runs it".to_owned();
        }
    }

    /// The metric names that appear in any row.
    pub fn metric_names(&self) -> Vec<String> {
        let names: BTreeSet<&String> = self.rows.iter().flat_map(|r| r.metrics.keys()).collect();
        names.into_iter().cloned().collect()
    }

    /// Whether every row finished with a solved verdict ([`crate::transcription::SolveVerdict`]).
    pub fn all_solved(&self) -> bool {
        self.rows.iter().all(|r| {
            r.status == RunStatus::Finished
                && r.solver_status
                    .as_deref()
                    .and_then(crate::transcription::SolveVerdict::from_name)
                    .is_some_and(|v| v.is_solved())
        })
    }

    /// The rows without a result: not run (pending) or stopped by a signal (interrupted).
    pub fn missing(&self) -> impl Iterator<Item = &Row> {
        self.rows
            .iter()
            .filter(|r| matches!(r.status, RunStatus::Pending | RunStatus::Interrupted))
    }

    /// Counts of rows per status.
    pub fn count(&self, status: RunStatus) -> usize {
        self.rows.iter().filter(|r| r.status == status).count()
    }

    /// The column names of the CSV and of the printed table.
    pub fn columns(&self) -> Vec<String> {
        let mut c = vec!["index".to_owned()];
        c.extend(self.grid.axes.iter().map(|a| a.key.clone()));
        c.extend(
            [
                "status",
                "solver_status",
                "objective",
                "iterations",
                "wall_time_s",
                "max_slack",
            ]
            .map(String::from),
        );
        if self.has_starts() {
            c.extend(
                [
                    "starts_solved",
                    "objective_starts_min",
                    "objective_starts_max",
                ]
                .map(String::from),
            );
        }
        c.extend(self.metric_names().iter().map(|m| format!("metrics.{m}")));
        c.extend(["start", "settled", "dir", "note"].map(String::from));
        c
    }

    /// Whether any row lists the objectives of several starts (`--starts K`).
    pub fn has_starts(&self) -> bool {
        self.rows.iter().any(|r| !r.start_objectives.is_empty())
    }

    /// Each row's cells, in [`Table::columns`] order.
    pub fn cells(&self) -> Vec<Vec<String>> {
        let metrics = self.metric_names();
        let starts = self.has_starts();
        let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:e}"));
        self.rows
            .iter()
            .map(|r| {
                let mut c = vec![r.index.to_string()];
                c.extend(r.values.iter().map(|(_, v)| v.clone()));
                c.push(r.status.name().to_owned());
                c.push(r.solver_status.clone().unwrap_or_default());
                c.push(opt(r.objective));
                c.push(r.iterations.map_or(String::new(), |i| i.to_string()));
                c.push(r.wall_time_s.map_or(String::new(), |t| format!("{t:.3}")));
                c.push(opt(r.max_slack));
                if starts {
                    let band = r.start_objectives.iter().copied();
                    c.push(r.start_objectives.len().to_string());
                    c.push(opt(band.clone().reduce(f64::min)));
                    c.push(opt(band.reduce(f64::max)));
                }
                c.extend(metrics.iter().map(|m| opt(r.metrics.get(m).copied())));
                c.push(r.start.clone());
                c.push(r.settled.map_or(String::new(), |s| s.to_string()));
                c.push(r.dir.clone());
                c.push(r.note.clone());
                c
            })
            .collect()
    }

    /// The CSV text (RFC 4180 quoting).
    pub fn to_csv(&self) -> String {
        let line = |cells: &[String]| {
            cells
                .iter()
                .map(|c| crate::files::trajectory_csv::csv_field(c))
                .collect::<Vec<_>>()
                .join(",")
                + "\n"
        };
        let mut text = line(&self.columns());
        for row in self.cells() {
            text.push_str(&line(&row));
        }
        text
    }

    /// Writes `sweep.json` and `sweep.csv` into `dir`, each atomically.
    pub fn write(&self, dir: &Path) -> Result<(), SweepError> {
        let json =
            serde_json::to_string_pretty(self).map_err(|e| SweepError::Internal(e.to_string()))?;
        for (name, text) in [(TABLE_JSON, json + "\n"), (TABLE_CSV, self.to_csv())] {
            let path = dir.join(name);
            write_atomic(&path, text.as_bytes())
                .map_err(|source| SweepError::Io { path, source })?;
        }
        Ok(())
    }

    /// Reads `dir/sweep.json`.
    pub fn read(dir: &Path) -> Result<Table, SweepError> {
        let path = dir.join(TABLE_JSON);
        let text =
            crate::files::input::read_regular_text(&path, crate::files::input::MAX_TEXT_BYTES)
                .map_err(|source| match source.kind() {
                    std::io::ErrorKind::NotFound => SweepError::NoTable {
                        path: path.clone(),
                        dir: dir.to_owned(),
                    },
                    _ => SweepError::Io {
                        path: path.clone(),
                        source,
                    },
                })?;
        let table: Table = serde_json::from_str(&text).map_err(|e| SweepError::Table {
            path: path.clone(),
            message: e.to_string(),
        })?;
        let invalid = |e: SweepError| SweepError::Table {
            path: path.clone(),
            message: e.to_string(),
        };
        table.grid.check_size().map_err(invalid)?;
        // Its axes as `--grid` would give them: a key or value `--set` cannot take is not a
        // sweep's.
        for axis in &table.grid.axes {
            Axis::new(&axis.key, axis.values.clone()).map_err(invalid)?;
        }
        Ok(table)
    }
}

/// Merges the tables of shard directories into one table over the whole grid: each point's
/// row from the shard that has it finished (else the last shard that has it at all), its
/// `dir` relative to `out`; points no shard has are `pending`.
pub fn collect(dirs: &[PathBuf], out: &Path) -> Result<Table, SweepError> {
    let mut tables = Vec::new();
    for d in dirs {
        tables.push((d, Table::read(d)?));
    }
    let Some((first_dir, first)) = tables.first() else {
        return Err(SweepError::Usage(
            "name at least one sweep directory".into(),
        ));
    };
    for (d, t) in &tables[1..] {
        if t.grid != first.grid || t.problem_sha256 != first.problem_sha256 || t.sets != first.sets
        {
            return Err(SweepError::Usage(format!(
                "{} and {} are not shards of one sweep (problem file, --set or --grid differ)",
                first_dir.display(),
                d.display()
            )));
        }
    }
    let mut rows: Vec<Option<Row>> = vec![None; first.grid.len()];
    for (d, t) in &tables {
        for r in &t.rows {
            let Some(slot) = rows.get_mut(r.index) else {
                continue;
            };
            let better = match slot {
                None => true,
                Some(old) => old.status != RunStatus::Finished,
            };
            if better {
                let mut r = r.clone();
                r.dir = crate::files::paths::relative_path(&d.join(&r.dir), out);
                *slot = Some(r);
            }
        }
    }
    let rows = rows
        .into_iter()
        .zip(first.grid.points())
        .map(|(r, p)| r.unwrap_or_else(|| Row::pending(&p, String::new())))
        .collect();
    Ok(Table {
        problem: first.problem.clone(),
        problem_sha256: first.problem_sha256.clone(),
        sets: first.sets.clone(),
        grid: first.grid.clone(),
        shard: Shard::ALL,
        rows,
    })
}

/// A table of `rows` over `grid` for tests: the whole grid of a problem `p.toml`.
#[cfg(test)]
pub(crate) fn test_table(grid: Grid, rows: Vec<Row>) -> Table {
    Table {
        problem: "p.toml".into(),
        problem_sha256: "00".into(),
        sets: vec![],
        grid,
        shard: Shard::ALL,
        rows,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_quotes_what_needs_it_and_lists_metrics() {
        let grid = Grid::new(vec![Axis::parse("k=1,2").unwrap()]).unwrap();
        let mut rows: Vec<Row> = grid
            .points()
            .map(|p| Row::pending(&p, "x".into()))
            .collect();
        rows[0].status = RunStatus::Finished;
        rows[0].objective = Some(2.5);
        rows[0].metrics.insert("slip".into(), 0.25);
        rows[1].note = "error: a, \"b\"".into();
        let t = test_table(grid, rows);
        let csv = t.to_csv();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(
            lines[0],
            "index,k,status,solver_status,objective,iterations,wall_time_s,max_slack,metrics.slip,start,settled,dir,note"
        );
        assert_eq!(lines[1], "0,1,finished,,2.5e0,,,,2.5e-1,,,x,");
        assert_eq!(lines[2], "1,2,pending,,,,,,,,,x,\"error: a, \"\"b\"\"\"");
        assert_eq!(t.rows[0].metric("metrics.slip"), Some(0.25));
        assert_eq!(t.rows[0].metric("objective"), Some(2.5));
    }

    /// A row is found by its point's index in a shard's rows (every third point), in rows of
    /// another order, and not found when absent.
    #[test]
    fn rows_are_found_by_their_points_index() {
        let grid = Grid::new(vec![Axis::parse("k=1,2,3,4,5,6,7,8,9").unwrap()]).unwrap();
        let mut rows: Vec<Row> = grid
            .points()
            .filter(|p| p.index % 3 == 1)
            .map(|p| Row::pending(&p, "x".into()))
            .collect();
        assert_eq!(row_position(&rows, 4), Some(1));
        assert_eq!(row_position(&rows, 7), Some(2));
        assert_eq!(row_position(&rows, 3), None);
        rows.reverse();
        assert_eq!(row_position(&rows, 1), Some(2));
        assert_eq!(row_position(&rows, 7), Some(0));
    }

    /// A rewrite is due once ten times the last one's duration has passed; forced always.
    #[test]
    fn table_rewrites_are_spaced_by_their_own_cost() {
        let dir = tempfile::tempdir().unwrap();
        let grid = Grid::new(vec![Axis::parse("k=1,2").unwrap()]).unwrap();
        let rows = grid
            .points()
            .map(|p| Row::pending(&p, String::new()))
            .collect();
        let table = test_table(grid, rows);
        let json = dir.path().join(TABLE_JSON);
        let mut writes = TableWrites::default();
        assert!(writes.write(&table, dir.path(), false).unwrap());
        assert!(json.is_file());
        std::fs::remove_file(&json).unwrap();
        // The last rewrite "took" a minute: not due for ten.
        writes.last = Some((
            std::time::Instant::now(),
            std::time::Duration::from_secs(60),
        ));
        assert!(!writes.write(&table, dir.path(), false).unwrap());
        assert!(!json.exists());
        assert!(writes.write(&table, dir.path(), true).unwrap());
        assert!(json.is_file());
        // One that took nothing is due at once.
        writes.last = Some((std::time::Instant::now(), std::time::Duration::ZERO));
        assert!(writes.write(&table, dir.path(), false).unwrap());
    }
}
