//! Sweeps: a problem solved over a grid of `--set` values, each run in its own `vito solve`
//! process (a crash or hang of one run leaves the others intact), resumable from the run
//! directories, shardable over the tasks of a cluster array job.
//!
//! A sweep directory holds `runs/<point>/` (each run's own output directory, written by
//! `vito solve` with its output-directory safety), `logs/<point>.log`, and the table
//! `sweep.json`/`sweep.csv`, rewritten atomically after every run. A run counts as finished
//! only when its complete `summary.json`, of the same problem file and overrides, is on disk.

#![warn(missing_docs)]

mod grid;
mod plot;
mod run;
mod table;

use std::path::PathBuf;

pub use grid::{Axis, Grid, Point, Shard};
pub use plot::metric_svg;
pub use run::{
    LOGS, PARENT_ENV, Progress, SWEEP_MARKER, SweepOptions, WarmStart, die_with_sweep, prepare_dir,
    run_sweep,
};
pub use table::{RUNS, Row, RunStatus, TABLE_CSV, TABLE_JSON, Table, collect};

/// Why a sweep could not run.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// A bad argument (grid, shard, directories).
    #[error("{0}")]
    Usage(String),
    /// The sweep directory holds things vito did not write.
    #[error(
        "sweep directory {path} is not empty and holds no `{SWEEP_MARKER}`: vito adds runs only \
         to a directory a sweep made (or an empty one); choose another --out"
    )]
    NotOurs {
        /// The directory.
        path: PathBuf,
    },
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// A table file is not a sweep table.
    #[error("{path}: not a sweep table: {message}")]
    Table {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A run could not be started.
    #[error("cannot run {exe}: {source}")]
    Spawn {
        /// The executable.
        exe: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// A plot could not be drawn.
    #[error("cannot draw {path}: {message}")]
    Plot {
        /// The plot file.
        path: PathBuf,
        /// plotters' message.
        message: String,
    },
    /// A bug.
    #[error("internal error: {0}")]
    Internal(String),
}

/// Loads the problem `file` with `overrides` at every point of `grid`, before any run. Keys
/// that do not exist (a typo in an axis or a `--set`) are usage errors, returned once here;
/// values the checks reject are results of the sweep (that point's run fails), so they pass.
pub fn check_grid_keys(
    file: &std::path::Path,
    overrides: &[crate::problem::Override],
    grid: &Grid,
) -> Result<(), crate::problem::ProblemError> {
    use crate::problem::{Override, ProblemError, load};
    for point in grid.points() {
        let mut all = overrides.to_vec();
        for arg in point.set_args() {
            all.push(Override::parse(&arg)?);
        }
        if let Err(e @ (ProblemError::UnknownKey { .. } | ProblemError::Override { .. })) =
            load(file, &all)
        {
            return Err(e);
        }
    }
    Ok(())
}
