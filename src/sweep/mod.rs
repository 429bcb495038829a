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
mod jobs;
mod neighbours;
mod plot;
mod run;
mod table;

use std::path::PathBuf;

pub use grid::{Axis, Grid, MAX_GRID_POINTS, Point, Shard};
pub use jobs::{JobOutcome, JobSweep, PointJob};
pub use neighbours::{ATTEMPTS, DEFAULT_ROUNDS, SETTLE_RATIO};
pub use plot::{PointClass, metric_svg, metric_svg_text};
pub use run::{
    Event, LOGS, MAX_JOBS, Outcome, PARENT_FLAG, Progress, SWEEP_MARKER, SweepOptions, WarmStart,
    ask_to_stop, die_with_sweep, out_name_without_utf8, prepare_dir, run_sweep,
    stop_when_the_parent_asks,
};
pub use table::{OnDisk, RUNS, Row, RunStatus, TABLE_CSV, TABLE_JSON, Table, collect, read_result};

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
    /// A symbolic link inside the sweep's own directories (vito never makes one there).
    #[error(
        "{path} is a symbolic link, which vito did not create: vito does not follow links \
         inside its own directories; remove it (or choose another --out)"
    )]
    Link {
        /// The link.
        path: PathBuf,
    },
    /// The sweep table a command needs does not exist.
    #[error(
        "{path} does not exist: {dir} is not a sweep directory (name the --out of a `vito sweep`)"
    )]
    NoTable {
        /// The missing table.
        path: PathBuf,
        /// The directory named.
        dir: PathBuf,
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

/// Most values of one axis that are not numbers (names, booleans, lists) [`check_grid`] loads
/// the problem with; the others are read as `--set` values, and checked by their own runs.
pub const MAX_CHECKED_OTHERS: usize = 100;

/// Checks a grid against the problem before any run, with work that does not grow with the
/// number of points and only a few loads per axis however long it is: every value of every
/// axis has been read as a `--set` value ([`Axis::new`]), and the problem `file` with
/// `overrides` is loaded with the values [`checked_values`] picks from each axis (the other
/// axes at their first values). A key the problem does not have or a value its checks reject
/// is a usage error naming the `--grid` argument (and, for a key, the full keys and
/// `[parameters]` it may have meant). A value not loaded that the problem's checks reject
/// (one between two accepted numbers that a family's expression cannot take) fails its own
/// run, with the reason in the table.
pub fn check_grid(
    file: &std::path::Path,
    overrides: &[crate::problem::Override],
    grid: &Grid,
) -> Result<(), SweepError> {
    use crate::problem::{Override, ProblemError, load};
    let usage = |e: ProblemError| SweepError::Usage(e.to_string());
    for (a, axis) in grid.axes.iter().enumerate() {
        for i in checked_values(axis) {
            // The first values of every axis together: loaded once, with the first axis.
            if i == 0 && a > 0 {
                continue;
            }
            let value = &axis.values[i];
            let mut all = overrides.to_vec();
            for (b, other) in grid.axes.iter().enumerate() {
                let v = if a == b { value } else { &other.values[0] };
                all.push(Override::parse(&format!("{}={v}", other.key)).map_err(usage)?);
            }
            let Err(e) = load(file, &all) else { continue };
            let argument = format!("--grid {}={}", axis.key, values_shown(&axis.values));
            let unknown_key = matches!(e, ProblemError::UnknownKey { .. })
                && e.to_string()
                    .contains(&format!("`{}`", last_part(&axis.key)));
            return Err(SweepError::Usage(if unknown_key {
                format!(
                    "{argument}: `{}` is not a key of {}{}\n  {e}",
                    axis.key,
                    file.display(),
                    key_hint(file, &axis.key)
                )
            } else {
                format!("{argument}: the value `{value}` is not valid here\n  {e}")
            }));
        }
    }
    Ok(())
}

/// An axis's values as a message shows them: all of a short axis, the first few of a long
/// one with their count.
fn values_shown(values: &[String]) -> String {
    const SHOWN: usize = 8;
    if values.len() <= SHOWN {
        values.join(",")
    } else {
        format!("{},… ({} values)", values[..SHOWN].join(","), values.len())
    }
}

/// The values of `axis` (indices, ascending) [`check_grid`] loads the problem with: the
/// first; of its numbers, for the integers and for the finite floats each, the smallest and
/// the largest (a problem's checks on a number are bounds), and each infinity or NaN; and
/// each other value (a name, a boolean, a list), up to [`MAX_CHECKED_OTHERS`] of them.
pub fn checked_values(axis: &Axis) -> Vec<usize> {
    use toml::Value;
    // (index, value) of the smallest and largest integer and finite float.
    let mut ints: Option<((usize, i64), (usize, i64))> = None;
    let mut floats: Option<((usize, f64), (usize, f64))> = None;
    let mut picked = vec![0];
    let mut others = 0;
    for (i, text) in axis.values.iter().enumerate() {
        let Ok(o) = crate::problem::Override::parse(&format!("{}={text}", axis.key)) else {
            picked.push(i);
            continue;
        };
        match o.value {
            Value::Integer(x) => {
                let (lo, hi) = ints.get_or_insert(((i, x), (i, x)));
                if x < lo.1 {
                    *lo = (i, x);
                }
                if x > hi.1 {
                    *hi = (i, x);
                }
            }
            Value::Float(x) if x.is_finite() => {
                let (lo, hi) = floats.get_or_insert(((i, x), (i, x)));
                if x < lo.1 {
                    *lo = (i, x);
                }
                if x > hi.1 {
                    *hi = (i, x);
                }
            }
            Value::Float(_) => picked.push(i),
            _ if others < MAX_CHECKED_OTHERS => {
                others += 1;
                picked.push(i);
            }
            _ => {}
        }
    }
    if let Some(((lo, _), (hi, _))) = ints {
        picked.extend([lo, hi]);
    }
    if let Some(((lo, _), (hi, _))) = floats {
        picked.extend([lo, hi]);
    }
    picked.sort_unstable();
    picked.dedup();
    picked
}

fn last_part(key: &str) -> &str {
    key.rsplit('.').next().unwrap_or(key)
}

/// "; did you mean …" for a swept key: the file's full key paths that end in it, and the
/// names of its `[parameters]`.
fn key_hint(file: &std::path::Path, key: &str) -> String {
    let Ok(text) =
        crate::files::input::read_regular_text(file, crate::files::input::MAX_TEXT_BYTES)
    else {
        return String::new();
    };
    let Ok(table) = toml::from_str::<toml::Table>(&text) else {
        return String::new();
    };
    let mut paths = Vec::new();
    leaf_paths(&table, "", &mut paths);
    let tail = format!(".{}", last_part(key));
    let mut hint = String::new();
    let full: Vec<String> = paths
        .iter()
        .filter(|p| p.ends_with(&tail) && !p.starts_with("parameters."))
        .map(|p| format!("`{p}`"))
        .collect();
    if !full.is_empty() {
        hint.push_str(&format!("; did you mean {}?", full.join(" or ")));
    }
    hint.push_str(" A swept key is a full key path as for --set (e.g. `contacts.friction`)");
    match table.get("parameters").and_then(toml::Value::as_table) {
        Some(p) if !p.is_empty() => hint.push_str(&format!(
            " or a name of the file's [parameters]: {}",
            p.keys()
                .map(|k| format!("`{k}`"))
                .collect::<Vec<_>>()
                .join(", ")
        )),
        _ => hint.push_str(" or a name of the file's [parameters] (it has none)"),
    }
    hint
}

fn leaf_paths(table: &toml::Table, prefix: &str, out: &mut Vec<String>) {
    for (k, v) in table {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(t) => leaf_paths(t, &path, out),
            _ => out.push(path),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 100,000-value axis is checked at a few values, not one load per value: the first,
    /// the smallest and largest integer and float, each infinity or NaN, and the names (at
    /// most [`MAX_CHECKED_OTHERS`] of them).
    #[test]
    fn a_long_axis_is_checked_at_a_few_values() {
        let mut values: Vec<String> = (0..100_000)
            .map(|i| format!("{}", 0.5 + i as f64 * 1e-6))
            .collect();
        values[7] = "0.25".into(); // the smallest float
        values[10] = "3".into(); // the only integer
        values[20] = "nan".into();
        values[30] = "-inf".into();
        values[40] = "midpoint".into();
        let axis = Axis::new("contacts.friction", values).unwrap();
        assert_eq!(checked_values(&axis), [0, 7, 10, 20, 30, 40, 99_999]);

        let names: Vec<String> = (0..1000).map(|i| format!("name{i}")).collect();
        let axis = Axis::new("name", names).unwrap();
        let checked = checked_values(&axis);
        assert_eq!(checked.len(), MAX_CHECKED_OTHERS);
        assert_eq!(checked[..3], [0, 1, 2]);

        let knots = Axis::new("horizon.knots", vec!["21".into(), "5".into(), "41".into()]);
        assert_eq!(checked_values(&knots.unwrap()), [0, 1, 2]);
    }

    /// A message names a long axis by its first values and its length, not all of them.
    #[test]
    fn a_long_axis_is_shown_short_in_messages() {
        let values: Vec<String> = (0..100_000).map(|i| i.to_string()).collect();
        assert_eq!(values_shown(&values), "0,1,2,3,4,5,6,7,… (100000 values)");
        assert_eq!(values_shown(&values[..3]), "0,1,2");
    }
}
