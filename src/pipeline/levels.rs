//! Grid continuation. A problem asked for at more knots than its file gives (`--set
//! horizon.knots=…`, with `horizon.time_step` where the horizon is fixed) is solved first on
//! the file's own grid, then on grids with twice the intervals of the one before, each
//! started from the plan of the level below, up to the grid asked for: its u resampled at the
//! finer knots' times, and its contact impulses as forces (each fine interval gets the force
//! of the coarse interval holding its middle, times its own step) with q on the cubic through
//! its knots that keeps their accelerations, and the sliding speeds, their duals and the
//! slacks that meet the rows there. Such a level is solved twice from that start, relaxed and
//! with the contact modes of the level below fixed (`transcription::CarriedModes`), and keeps
//! the lower solved plan. A fine grid's relaxed NLP has far more poor local optima within
//! reach of a cold start than a coarse one's: cold, the hopper at 41 knots ended
//! `relaxed_contact` at 88.0, and at 161 knots at 30.6; started from the levels below it
//! solves at every level (BENCHMARKS.md).
//!
//! A problem whose slack is solved by a continuation (`slack.target` or `slack.homotopy`)
//! starts each level from q and u alone (q interpolated linearly), its impulses at the
//! guess's, and is solved relaxed only: from carried impulses
//! those reached worse optima, where the hopper's single relaxed solve gains from them
//! (BENCHMARKS.md: at 161 knots the median over ten seeded first levels fell from 6.669 to
//! 6.035 in a quarter of the time; Spring Flamingo's homotopy at 49 knots rose from 20.53 to
//! 24.22 over nine, LittleDog's step at 59 from 41.44 to 43.17 in one).

use crate::problem::{InitialGuess, LoadedProblem, Override, TimeSteps};
use crate::transcription::{GridLevel, Solution, SolveOptions, TranscriptionError};

/// The knots of the levels from the file's `file_knots` up to `knots`: the file's grid, its
/// intervals doubled while still below `knots`, then `knots`; just `[knots]` when `knots` is
/// not finer than the file's.
pub fn ladder(file_knots: usize, knots: usize) -> Vec<usize> {
    if file_knots < 2 || knots <= file_knots {
        return vec![knots];
    }
    let mut levels = vec![file_knots];
    let mut intervals = file_knots - 1;
    loop {
        intervals *= 2;
        if intervals + 1 >= knots {
            break;
        }
        levels.push(intervals + 1);
    }
    levels.push(knots);
    levels
}

/// The levels `target` (the problem as asked, its `--set` overrides in `parameters`) is
/// solved through: [`ladder`] from the file's own grid when `target` asks for a finer one,
/// has inputs (a problem without them is a simulation, solved directly at any grid) and is
/// not asked to start from a given plan; else None (one solve on its own grid).
pub fn levels_for(target: &LoadedProblem) -> Option<Vec<usize>> {
    let overrides = overrides_of(target);
    if !overrides.iter().any(|o| o.path == "horizon.knots")
        || target.spec.input_bounds.is_empty()
        || matches!(target.spec.initial_guess, InitialGuess::WarmStart(_))
    {
        return None;
    }
    let own: Vec<Override> = overrides
        .into_iter()
        .filter(|o| o.path != "horizon.knots" && o.path != "horizon.time_step")
        .collect();
    let file_knots = crate::pipeline::load_checked(&target.file, &own)
        .ok()?
        .spec
        .knots;
    (target.spec.knots > file_knots).then(|| ladder(file_knots, target.spec.knots))
}

/// `target`'s `--set` overrides, read back from what it records of them.
fn overrides_of(target: &LoadedProblem) -> Vec<Override> {
    target
        .parameters
        .iter()
        .filter_map(|(path, value)| Override::parse(&format!("{path}={value}")).ok())
        .collect()
}

/// The caller's `overrides` with the knots set to `knots` and, with fixed steps, the step
/// that keeps `target`'s horizon.
fn level_overrides(overrides: &[Override], target: &LoadedProblem, knots: usize) -> Vec<Override> {
    let mut out: Vec<Override> = overrides
        .iter()
        .filter(|o| o.path != "horizon.knots" && o.path != "horizon.time_step")
        .cloned()
        .collect();
    out.push(Override {
        path: "horizon.knots".into(),
        value: toml::Value::Integer(knots as i64),
    });
    if let TimeSteps::Fixed(h) = target.spec.time_steps {
        let horizon = h * (target.spec.knots - 1) as f64;
        out.push(Override {
            path: "horizon.time_step".into(),
            value: toml::Value::Float(horizon / (knots - 1) as f64),
        });
    }
    out
}

/// Solves `target` through `knots` ([`levels_for`]): `options` are the caller's (progress,
/// stop flag, deadline), and its starts (`multi_start`) explore the first level only;
/// `on_level` hears each level as it ends, with its index and the number of levels. The last level's
/// solution is returned with every level recorded in [`Solution::levels`], its iterations
/// and times their sums, and the first level's starts as its `starts` (with the best of them,
/// the one the levels above refined, as `best_start`).
pub fn solve_on_levels(
    target: &LoadedProblem,
    knots: &[usize],
    options: &mut SolveOptions,
    mut on_level: impl FnMut(&GridLevel, usize, usize),
) -> Result<Solution, TranscriptionError> {
    let overrides = overrides_of(target);
    let mut levels: Vec<GridLevel> = Vec::new();
    // The level below, its work (iterations, wall, callback and Ipopt times) summed with the
    // work of every level below it.
    let mut previous: Option<Solution> = None;
    // The first level's starts (`--starts`), which the levels above refine the best of.
    let mut explored = (Vec::new(), 0);
    for (l, &n) in knots.iter().enumerate() {
        let mut spec = if n == target.spec.knots {
            target.spec.clone()
        } else {
            crate::pipeline::load_checked(&target.file, &level_overrides(&overrides, target, n))
                .map_err(|e| TranscriptionError::Invalid {
                    field: "horizon.knots".into(),
                    message: format!("the grid continuation's level of {n} knots: {e}"),
                })?
                .spec
        };
        if let Some(p) = &previous {
            let source = format!("the grid continuation's level of {} knots", p.times.len());
            // A slack continuation starts from the guess's small impulses: from carried ones
            // it reached worse optima (module docs).
            spec.initial_guess = InitialGuess::WarmStart(if spec.slack_continuation.is_some() {
                p.warm_start(source.into())
            } else {
                p.warm_start_with_forces(source.into())
            });
        }
        let mut solution = crate::pipeline::solve(&spec, options)?;
        if l == 0 {
            options.multi_start = None;
            explored = (std::mem::take(&mut solution.starts), solution.best_start);
        }
        let level = GridLevel {
            knots: n,
            verdict: solution.verdict(),
            objective: solution.objective,
            max_slack: solution.max_slack,
            iterations: solution.iterations,
            wall_time_s: solution.wall_time_s,
            max_q_difference: previous.as_ref().map(|p| q_difference(&solution, p)),
            carried_modes_kept: solution.carried_modes.as_ref().map(|c| c.kept),
        };
        on_level(&level, l, knots.len());
        levels.push(level);
        if let Some(below) = &previous {
            solution.add_work(below);
        }
        if l + 1 == knots.len() {
            (solution.starts, solution.best_start) = explored;
            solution.levels = levels;
            return Ok(solution);
        }
        previous = Some(solution);
    }
    Err(TranscriptionError::Invalid {
        field: "horizon.knots".into(),
        message: "a grid continuation needs a level".into(),
    })
}

/// The largest |q_fine(t) − q_coarse(t)| over `coarse`'s knot times, `fine` interpolated
/// linearly between its knots.
fn q_difference(fine: &Solution, coarse: &Solution) -> f64 {
    let mut worst = 0.0_f64;
    for (t, qc) in coarse.times.iter().zip(&coarse.q) {
        let k = fine
            .times
            .partition_point(|&s| s <= *t)
            .clamp(1, fine.times.len().max(2) - 1);
        let (t0, t1) = (fine.times[k - 1], fine.times[k]);
        let w = if t1 > t0 {
            ((t - t0) / (t1 - t0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        for (c, qc) in qc.iter().enumerate() {
            let qf = fine.q[k - 1][c] * (1.0 - w) + fine.q[k][c] * w;
            worst = worst.max((qf - qc).abs());
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::ladder;

    #[test]
    fn ladders_double_the_intervals_from_the_files_grid() {
        assert_eq!(ladder(21, 21), vec![21]);
        assert_eq!(ladder(21, 11), vec![11]);
        assert_eq!(ladder(21, 41), vec![21, 41]);
        assert_eq!(ladder(21, 161), vec![21, 41, 81, 161]);
        assert_eq!(ladder(21, 50), vec![21, 41, 50]);
        assert_eq!(ladder(25, 97), vec![25, 49, 97]);
        assert_eq!(ladder(30, 59), vec![30, 59]);
    }
}
