//! The neighbour pass of a sweep: after every point has its own answer, each point is solved
//! again from the plans of its grid neighbours (points one step away on one axis), and a plan
//! found that way replaces the point's answer when it is better by more than [`SETTLE_RATIO`]
//! (a solved plan beats a relaxed one, which beats any other; among solved plans the lower
//! objective, among relaxed ones the smaller slack). Rounds repeat while answers change,
//! at most a given number of times.
//!
//! Every attempt is a run of its own under `attempts/<point>/from-p<neighbour>-<hash>/`, the
//! hash naming the neighbour's plan it started from (its answer's directory), so a rerun of
//! the sweep finds the attempts already made and replays the rounds to the same answers.

use std::collections::BTreeSet;
use std::path::Path;

use crate::sweep::grid::fnv1a;
use crate::sweep::table::{OnDisk, Row, RunStatus, expected_parameters, read_result, row_position};
use crate::sweep::{Point, SweepError};
use crate::transcription::SolveVerdict;

/// Where the attempts live, under the sweep directory.
pub const ATTEMPTS: &str = "attempts";

/// A neighbour's plan must improve a point's answer by more than this fraction (of its
/// objective, or of its slack for a relaxed answer) to replace it; a point none of whose
/// neighbours' plans does so is *settled*.
pub const SETTLE_RATIO: f64 = 0.01;

/// Rounds of the neighbour pass unless the user sets another number.
pub const DEFAULT_ROUNDS: usize = 5;

/// One re-solve of a point from a neighbour's plan.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Attempt {
    /// The point solved again (grid index).
    pub target: usize,
    /// The neighbour whose plan is the start (grid index).
    pub source: usize,
    /// The neighbour's answer directory (relative to the sweep directory).
    pub source_dir: String,
    /// The attempt's own run directory (relative to the sweep directory).
    pub dir: String,
}

/// How good a row's answer is: 0 solved, 1 relaxed contact, 2 any other solver verdict, 3 no
/// result.
pub fn rank(row: &Row) -> u8 {
    if row.status != RunStatus::Finished {
        return 3;
    }
    row.solver_status
        .as_deref()
        .and_then(SolveVerdict::from_name)
        .map_or(2, SolveVerdict::rank)
}

/// Whether `candidate` is better than `current` by more than [`SETTLE_RATIO`] (a better rank
/// always is).
pub fn improves(candidate: &Row, current: &Row) -> bool {
    let (a, b) = (rank(candidate), rank(current));
    if a != b {
        return a < b;
    }
    let lower = |x: Option<f64>, y: Option<f64>| match (x, y) {
        (Some(x), Some(y)) if x.is_finite() && y.is_finite() => x < y - SETTLE_RATIO * y.abs(),
        (Some(x), _) => x.is_finite(),
        _ => false,
    };
    match a {
        0 => lower(candidate.objective, current.objective),
        1 => lower(candidate.max_slack, current.max_slack),
        _ => false,
    }
}

/// The attempt directory of `target` started from the plan in `source_dir` (of point
/// `source`).
pub fn attempt_dir(target: &Point, source: usize, source_dir: &str) -> String {
    format!(
        "{ATTEMPTS}/{}/from-p{source}-{:08x}",
        target.run_name(),
        fnv1a(source_dir.as_bytes()) & 0xffff_ffff
    )
}

/// The points at grid distance 1 from `point` among `points` (in grid order).
pub fn neighbours<'a>(point: &'a Point, points: &'a [Point]) -> impl Iterator<Item = &'a Point> {
    points.iter().filter(move |p| p.distance(point) == 1)
}

/// The attempts of the next round: every point with a result tries every solved neighbour's
/// current plan it has not tried yet (`tried` holds the attempt directories already folded
/// in). In grid order of the target, then of the source.
pub fn plan_round(points: &[Point], rows: &[Row], tried: &BTreeSet<String>) -> Vec<Attempt> {
    let row_of = |index: usize| row_position(rows, index).map(|i| &rows[i]);
    let mut attempts = Vec::new();
    for p in points {
        let Some(row) = row_of(p.index) else { continue };
        if !matches!(
            row.status,
            RunStatus::Finished | RunStatus::Failed | RunStatus::Timeout
        ) {
            continue;
        }
        for n in neighbours(p, points) {
            let Some(source) = row_of(n.index) else {
                continue;
            };
            if rank(source) != 0 {
                continue;
            }
            let dir = attempt_dir(p, n.index, &source.dir);
            if !tried.contains(&dir) {
                attempts.push(Attempt {
                    target: p.index,
                    source: n.index,
                    source_dir: source.dir.clone(),
                    dir,
                });
            }
        }
    }
    attempts
}

/// Whether `row`'s point has tried the current plan of every solved neighbour.
pub fn settled(point: &Point, points: &[Point], rows: &[Row], tried: &BTreeSet<String>) -> bool {
    let row_of = |index: usize| row_position(rows, index).map(|i| &rows[i]);
    neighbours(point, points).all(|n| {
        row_of(n.index).is_none_or(|source| {
            rank(source) != 0 || tried.contains(&attempt_dir(point, n.index, &source.dir))
        })
    })
}

/// The point label of the point whose run directory `dir` is (`runs/<name>` or
/// `attempts/<name>/…`), or `dir` itself.
pub fn label_of_dir(points: &[Point], dir: &str) -> String {
    let name = dir.split('/').nth(1).unwrap_or(dir);
    points
        .iter()
        .find(|p| p.run_name() == name)
        .map_or_else(|| dir.to_owned(), |p| p.label())
}

/// The attempt's result when its run directory under the sweep directory `out` holds a
/// finished summary of this problem (`sha256`, fixed overrides `sets`) and point.
pub fn attempt_result(
    out: &Path,
    sets: &[String],
    sha256: &str,
    point: &Point,
    attempt: &Attempt,
) -> Result<Option<Row>, SweepError> {
    let mut row = Row::pending(point, attempt.dir.clone());
    let parameters = expected_parameters(sets, point)?;
    let dir = out.join(&attempt.dir);
    Ok((read_result(&mut row, &dir, sha256, &parameters) == OnDisk::Finished).then_some(row))
}

/// Folds a round's attempts into `rows` in the plan's order, adding each to `tried`: an
/// attempt whose result (`result`) improves its point's answer ([`improves`]) replaces it,
/// its `start` naming the neighbour. Returns the points improved, then marks every row
/// settled or not.
pub fn fold_round(
    plan: &[Attempt],
    points: &[Point],
    rows: &mut [Row],
    tried: &mut BTreeSet<String>,
    mut result: impl FnMut(&Point, &Attempt) -> Result<Option<Row>, SweepError>,
) -> Result<Vec<usize>, SweepError> {
    let mut improved = Vec::new();
    for a in plan {
        tried.insert(a.dir.clone());
        let Some(point) = points.iter().find(|p| p.index == a.target) else {
            continue;
        };
        let Some(candidate) = result(point, a)? else {
            continue;
        };
        let source_label = label_of_dir(points, &a.source_dir);
        let Some(row) = row_position(rows, a.target).map(|i| &mut rows[i]) else {
            continue;
        };
        if improves(&candidate, row) {
            let note = std::mem::take(&mut row.note);
            *row = Row {
                start: format!("neighbour {source_label}"),
                note,
                ..candidate
            };
            if !improved.contains(&a.target) {
                improved.push(a.target);
            }
        }
    }
    mark_settled(points, rows, tried);
    Ok(improved)
}

/// Sets every row's `settled` ([`settled`]).
pub fn mark_settled(points: &[Point], rows: &mut [Row], tried: &BTreeSet<String>) {
    let settled: Vec<bool> = rows
        .iter()
        .map(|r| {
            points
                .iter()
                .find(|p| p.index == r.index)
                .is_some_and(|p| settled(p, points, rows, tried))
        })
        .collect();
    for (row, s) in rows.iter_mut().zip(settled) {
        row.settled = Some(s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::{Axis, Grid};

    fn rows(grid: &Grid, results: &[(u8, f64)]) -> Vec<Row> {
        grid.points()
            .zip(results)
            .map(|(p, &(rank, objective))| {
                let mut r = Row::pending(&p, format!("runs/{}", p.run_name()));
                r.status = RunStatus::Finished;
                r.solver_status = Some(
                    match rank {
                        0 => "solve_succeeded",
                        1 => "relaxed_contact",
                        _ => "infeasible_problem_detected",
                    }
                    .into(),
                );
                r.objective = Some(objective);
                r.max_slack = Some(if rank == 1 { 0.5 } else { 0.0 });
                r
            })
            .collect()
    }

    #[test]
    fn a_better_verdict_or_a_lower_objective_by_more_than_one_percent_improves() {
        let grid = Grid::new(vec![Axis::parse("k=1,2,3").unwrap()]).unwrap();
        let r = rows(&grid, &[(0, 10.0), (1, 5.0), (0, 9.95)]);
        assert!(
            improves(&r[0], &r[1]),
            "solved beats relaxed whatever the objective"
        );
        assert!(!improves(&r[1], &r[0]));
        assert!(
            !improves(&r[2], &r[0]),
            "0.5 % lower is within the settle ratio"
        );
        let mut lower = r[2].clone();
        lower.objective = Some(9.8);
        assert!(improves(&lower, &r[0]), "2 % lower improves");
    }

    #[test]
    fn a_round_tries_each_solved_neighbours_plan_once() {
        // 2 x 3 grid: point 4 (middle of the second row) has neighbours 1, 3 and 5.
        let grid = Grid::new(vec![
            Axis::parse("a=1,2").unwrap(),
            Axis::parse("b=1,2,3").unwrap(),
        ])
        .unwrap();
        let points: Vec<Point> = grid.points().collect();
        let r = rows(
            &grid,
            &[(0, 1.0), (0, 1.0), (0, 1.0), (1, 9.0), (0, 2.0), (2, 3.0)],
        );
        let plan = plan_round(&points, &r, &BTreeSet::new());
        let from: Vec<(usize, usize)> = plan.iter().map(|a| (a.target, a.source)).collect();
        // Only solved plans are starts: 3 (relaxed) and 5 (not solved) are never sources.
        assert!(from.contains(&(4, 1)) && !from.contains(&(4, 3)) && !from.contains(&(4, 5)));
        assert!(from.contains(&(3, 0)) && from.contains(&(3, 4)));
        assert_eq!(from.len(), 10);
        let tried: BTreeSet<String> = plan.iter().map(|a| a.dir.clone()).collect();
        assert!(plan_round(&points, &r, &tried).is_empty());
        assert!(points.iter().all(|p| settled(p, &points, &r, &tried)));
        // A neighbour's new answer is a new plan to try.
        let mut moved = r.clone();
        moved[1].dir = "attempts/x/from-p0-0".into();
        let again = plan_round(&points, &moved, &tried);
        assert_eq!(
            again
                .iter()
                .map(|a| (a.target, a.source))
                .collect::<Vec<_>>(),
            vec![(0, 1), (2, 1), (4, 1)]
        );
        assert!(!settled(&points[4], &points, &moved, &tried));
    }
}
