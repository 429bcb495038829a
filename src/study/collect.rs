//! A set of gaits for figure 6: the paper tracks "a set of walking trajectories", and one
//! `vito study tracking` run is one gait (one chain of plans across K). Each gait runs as its
//! own study (in parallel, or as a cluster's array tasks, like `vito sweep`'s shards), and
//! [`collect_tracking`] reads their output directories back into one table per measure
//! whose row at (K, method) holds one run per gait: mean ± std over the set, as the paper's
//! figures.
//!
//! A plan whose simulated robot falls over (the base is unactuated, the controller drives
//! the joints alone) measures the fall, not the plan's accuracy; the set's records keep each
//! plan's largest deviation from its plan, and [`CollectedTracking::upright`] is the table
//! over the plans that stayed within a stated deviation, beside the count of those that did
//! not.

use std::path::{Path, PathBuf};

use super::tracking::{PLANS_CSV_HEADER, PlanRecord, TRACKING_MEASURES, TrackingMeasure};
use super::{METHODS, StudyError, StudyMethod, StudyTable, table_order};
use crate::discrete::Integrator;

/// Largest file read from a study's directory (bytes).
const MAX_STUDY_FILE: u64 = 64 << 20;

/// One plan of one gait, as its study recorded it.
#[derive(Debug, Clone, PartialEq)]
pub struct CollectedPlan {
    /// The gait: the name of its study's directory.
    pub gait: String,
    /// The study's record (without the trajectory, which stays in the gait's `plans/`;
    /// `max_deviation` None also for a study written before the column existed).
    pub plan: PlanRecord,
    /// Its RMS state error (None: not tracked).
    pub rms: Option<f64>,
}

/// The tables of a set of gaits.
#[derive(Debug, Clone, PartialEq)]
pub struct CollectedTracking {
    /// Per measure of [`TRACKING_MEASURES`], the table with one run per gait (that tracked
    /// the row's plan) at each row, gaits in the order given.
    pub tables: Vec<(TrackingMeasure, StudyTable)>,
    /// Every gait's plans, gaits in the order given.
    pub plans: Vec<CollectedPlan>,
}

impl CollectedTracking {
    /// The table of `stem` (one of [`TRACKING_MEASURES`]).
    pub fn table(&self, stem: &str) -> Option<&StudyTable> {
        self.tables
            .iter()
            .find(|(m, _)| m.stem == stem)
            .map(|(_, t)| t)
    }

    /// The state-error table over the tracked plans whose largest deviation is at most
    /// `max_deviation` (a plan without a recorded deviation is left out).
    pub fn upright(&self, max_deviation: f64) -> StudyTable {
        let mut table = StudyTable::default();
        for p in &self.plans {
            let (Some(rms), Some(d)) = (p.rms, p.plan.max_deviation) else {
                continue;
            };
            if d <= max_deviation {
                table.add_run(p.plan.knots, p.plan.method, rms);
            }
        }
        table.sort();
        table
    }

    /// Per (K, method): the plans tracked, those among them whose largest deviation exceeds
    /// `max_deviation`, and those without a recorded deviation.
    pub fn falls(&self, max_deviation: f64) -> Vec<FallCount> {
        let mut counts: Vec<FallCount> = Vec::new();
        for p in self
            .plans
            .iter()
            .filter(|p| p.rms.is_some())
            .map(|p| &p.plan)
        {
            let fell = p
                .max_deviation
                .is_some_and(|d| d > max_deviation || d.is_nan());
            let unknown = p.max_deviation.is_none();
            match counts
                .iter_mut()
                .find(|c| c.knots == p.knots && c.method == p.method)
            {
                Some(c) => {
                    c.tracked += 1;
                    c.fell += usize::from(fell);
                    c.unknown += usize::from(unknown);
                }
                None => counts.push(FallCount {
                    knots: p.knots,
                    method: p.method,
                    tracked: 1,
                    fell: usize::from(fell),
                    unknown: usize::from(unknown),
                }),
            }
        }
        counts.sort_by_key(|c| table_order(c.knots, c.method));
        counts
    }

    /// The set's plans as CSV: a `gait` column, a tracking study's plan columns, and each
    /// plan's RMS state error.
    pub fn plans_csv(&self) -> String {
        let mut s = format!("gait,{PLANS_CSV_HEADER},rms\n");
        for p in &self.plans {
            let rms = p.rms.map_or(String::new(), |x| format!("{x:.4e}"));
            s += &format!("{},{},{rms}\n", p.gait, p.plan.csv_cells());
        }
        s
    }
}

/// [`CollectedTracking::falls`] as CSV: `knots,method,tracked,fell,unrecorded`.
pub fn falls_csv(falls: &[FallCount]) -> String {
    let mut s = String::from("knots,method,tracked,fell,unrecorded\n");
    for f in falls {
        s += &format!(
            "{},{},{},{},{}\n",
            f.knots,
            f.method.study_name(),
            f.tracked,
            f.fell,
            f.unknown
        );
    }
    s
}

/// Tracked plans and falls at one (K, method).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FallCount {
    /// Knot count.
    pub knots: usize,
    /// Integrator.
    pub method: Integrator,
    /// Plans tracked (with an error row).
    pub tracked: usize,
    /// Those whose largest deviation exceeded the threshold.
    pub fell: usize,
    /// Those whose study did not record their deviation (written before the column).
    pub unknown: usize,
}

/// Reads the tracking studies in `dirs` (each a `vito study tracking` output directory: one
/// gait) into the set's tables. A directory holding no study, or a file that is not the
/// study's, is an [`StudyError::Invalid`] naming the file and line.
pub fn collect_tracking(dirs: &[PathBuf]) -> Result<CollectedTracking, StudyError> {
    if dirs.is_empty() {
        return Err(StudyError::Invalid {
            field: "DIRS".into(),
            message: "give the output directories of one or more `vito study tracking` runs".into(),
        });
    }
    let mut tables: Vec<(TrackingMeasure, StudyTable)> = TRACKING_MEASURES
        .iter()
        .map(|&measure| (measure, StudyTable::default()))
        .collect();
    let mut plans = Vec::new();
    let mut names: Vec<String> = Vec::new();
    for dir in dirs {
        let gait = gait_name(dir);
        if names.contains(&gait) {
            return Err(StudyError::Invalid {
                field: dir.display().to_string(),
                message: format!(
                    "a second directory named `{gait}`: each gait's directory needs its own name"
                ),
            });
        }
        names.push(gait.clone());
        for (measure, table) in &mut tables {
            let path = dir.join(format!("{}_runs.csv", measure.stem));
            for (knots, method, rms) in read_runs(&path)? {
                table.add_run(knots, method, rms);
            }
        }
        let state = read_runs(&dir.join("tracking_runs.csv"))?;
        for plan in read_plans(&dir.join("tracking_plans.csv"))? {
            let rms = state
                .iter()
                .find(|(k, m, _)| *k == plan.knots && *m == plan.method)
                .map(|r| r.2);
            plans.push(CollectedPlan {
                gait: gait.clone(),
                plan,
                rms,
            });
        }
    }
    for (_, table) in &mut tables {
        table.sort();
    }
    Ok(CollectedTracking { tables, plans })
}

/// A gait's name: its directory's last component.
fn gait_name(dir: &Path) -> String {
    dir.file_name()
        .map_or_else(
            || dir.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        )
        .replace([',', '"'], "_")
}

fn read(path: &Path) -> Result<String, StudyError> {
    crate::files::input::read_regular_text(path, MAX_STUDY_FILE).map_err(|e| StudyError::Invalid {
        field: path.display().to_string(),
        message: format!("{e}: give the output directory of a `vito study tracking` run"),
    })
}

fn bad_line(path: &Path, line: usize, message: &str) -> StudyError {
    StudyError::Invalid {
        field: format!("{}:{line}", path.display()),
        message: message.to_owned(),
    }
}

fn method_named(name: &str) -> Option<Integrator> {
    METHODS.into_iter().find(|m| m.study_name() == name)
}

/// `knots,method,run,rms` rows of a one-gait study (its single run per row).
fn read_runs(path: &Path) -> Result<Vec<(usize, Integrator, f64)>, StudyError> {
    let text = read(path)?;
    let mut lines = text.lines();
    if lines.next() != Some("knots,method,run,rms") {
        return Err(bad_line(
            path,
            1,
            "the header is not `knots,method,run,rms`: not a tracking study's runs table",
        ));
    }
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        let parsed = match cells.as_slice() {
            [k, m, _, rms] => k
                .parse::<usize>()
                .ok()
                .zip(method_named(m))
                .zip(rms.parse::<f64>().ok()),
            _ => None,
        };
        let Some(((knots, method), rms)) = parsed else {
            return Err(bad_line(
                path,
                i + 2,
                "expected `knots,method,run,rms` with a knot count, `first_order` or \
                 `variational`, a run number and an error",
            ));
        };
        if rows
            .iter()
            .any(|r: &(usize, Integrator, f64)| r.0 == knots && r.1 == method)
        {
            return Err(bad_line(
                path,
                i + 2,
                "a second run at this knot count and method: collect one-gait studies, not \
                 a collected set",
            ));
        }
        rows.push((knots, method, rms));
    }
    Ok(rows)
}

/// A study's `tracking_plans.csv` (with or without the `max_deviation` column, which studies
/// before it lack).
fn read_plans(path: &Path) -> Result<Vec<PlanRecord>, StudyError> {
    let text = read(path)?;
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default();
    let columns: Vec<&str> = header.split(',').collect();
    let with_deviation = header == PLANS_CSV_HEADER;
    if !with_deviation && header != "knots,method,objective,max_slack,iterations,start,outcome" {
        return Err(bad_line(
            path,
            1,
            &format!("the header is not `{PLANS_CSV_HEADER}`: not a tracking study's plans"),
        ));
    }
    let mut plans = Vec::new();
    for (i, line) in lines.enumerate() {
        // The outcome, last, is quoted and may hold commas.
        let cells: Vec<&str> = line.splitn(columns.len(), ',').collect();
        let bad = || bad_line(path, i + 2, "a plan line that does not fit the header");
        if cells.len() != columns.len() {
            return Err(bad());
        }
        let number = |j: usize| cells[j].parse::<f64>().map_err(|_| bad());
        let max_deviation = if with_deviation && !cells[6].is_empty() {
            Some(number(6)?)
        } else {
            None
        };
        plans.push(PlanRecord {
            knots: cells[0].parse().map_err(|_| bad())?,
            method: method_named(cells[1]).ok_or_else(bad)?,
            objective: number(2)?,
            max_slack: number(3)?,
            iterations: cells[4].parse().map_err(|_| bad())?,
            // Not in the plans table: the frontier's, written beside it.
            variables: 0,
            wall_time_s: f64::NAN,
            knot_error: None,
            start: cells[5].to_owned(),
            max_deviation,
            outcome: cells[columns.len() - 1].trim_matches('"').to_owned(),
            trajectory_csv: String::new(),
        });
    }
    Ok(plans)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn study(dir: &Path, plans: &str, runs: &str) {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join("tracking_plans.csv"), plans).unwrap();
        for measure in TRACKING_MEASURES {
            std::fs::write(dir.join(format!("{}_runs.csv", measure.stem)), runs).unwrap();
        }
    }

    /// A study written before the deviation column and one after: both read; an outcome
    /// holding commas stays whole; an unsolved plan has no error; falls count only recorded
    /// deviations; the upright table keeps the plans within the threshold.
    #[test]
    fn reads_old_and_new_plan_records() {
        let t = tempfile::tempdir().unwrap();
        let (old, new) = (t.path().join("old"), t.path().join("new"));
        study(
            &old,
            "knots,method,objective,max_slack,iterations,start,outcome\n\
             10,first_order,1e0,0e0,5,variational K=10,\"tracked\"\n\
             10,variational,2e0,0e0,7,guess,\"not solved: a, b\"\n",
            "knots,method,run,rms\n10,first_order,0,1.0e0\n",
        );
        study(
            &new,
            &format!(
                "{PLANS_CSV_HEADER}\n\
                 10,first_order,1e0,0e0,5,variational K=10,2.0e-1,\"tracked\"\n\
                 10,variational,2e0,0e0,7,guess,9.0e-1,\"tracked\"\n"
            ),
            "knots,method,run,rms\n10,first_order,0,3.0e0\n10,variational,0,5.0e0\n",
        );
        let set = collect_tracking(&[old, new]).unwrap();
        assert_eq!(set.plans.len(), 4);
        assert_eq!(set.plans[1].plan.outcome, "not solved: a, b");
        assert_eq!(set.plans[1].rms, None);
        assert_eq!(set.plans[3].plan.max_deviation, Some(0.9));
        let state = set.table("tracking").unwrap();
        assert_eq!(state.row(10, Integrator::Euler).unwrap().runs, [1.0, 3.0]);
        assert_eq!(state.row(10, Integrator::Midpoint).unwrap().runs, [5.0]);
        let falls = set.falls(0.5);
        assert_eq!(
            falls,
            [
                FallCount {
                    knots: 10,
                    method: Integrator::Euler,
                    tracked: 2,
                    fell: 0,
                    unknown: 1
                },
                FallCount {
                    knots: 10,
                    method: Integrator::Midpoint,
                    tracked: 1,
                    fell: 1,
                    unknown: 0
                }
            ]
        );
        let upright = set.upright(0.5);
        assert_eq!(upright.rows.len(), 1);
        assert_eq!(upright.rows[0].runs, [3.0]);
    }
}
