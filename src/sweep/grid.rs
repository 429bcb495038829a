//! Parameter grids: axes parsed from `--grid key=v1,v2,...`, their Cartesian product in a
//! fixed order, shards of it, and the name of each point's run directory.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::problem::Override;
use crate::sweep::SweepError;

/// One swept key and its values, as written on the command line.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// A `--set` key path or a family parameter (`contacts.friction`, `stride_hz`).
    pub key: String,
    /// The values, each a TOML value as `--set` reads it.
    pub values: Vec<String>,
}

impl Axis {
    /// Parses `key=v1,v2,...`; each value must be a valid `--set` value.
    pub fn parse(arg: &str) -> Result<Axis, SweepError> {
        let bad = |message: String| SweepError::Usage(format!("--grid {arg}: {message}"));
        let (key, list) = arg
            .split_once('=')
            .ok_or_else(|| bad("expected key=v1,v2,...".into()))?;
        let count = list.split(',').count();
        if count > MAX_GRID_POINTS {
            return Err(bad(format!(
                "{count} values; a sweep has at most {MAX_GRID_POINTS} points"
            )));
        }
        let values: Vec<String> = list.split(',').map(|v| v.trim().to_owned()).collect();
        if values.iter().any(String::is_empty) {
            return Err(bad(
                "a value is empty (values are separated by commas)".into()
            ));
        }
        Axis::new(key, values).map_err(|e| bad(e.to_string()))
    }

    /// An axis from its key and values given one by one (each a `--set` value; a value may
    /// hold a comma), checked as [`Axis::parse`] checks them.
    pub fn new(key: &str, values: Vec<String>) -> Result<Axis, SweepError> {
        let key = key.trim();
        if key.is_empty() {
            return Err(SweepError::Usage("the key is empty".into()));
        }
        // `--set` and `--grid` read `key=value` up to the first `=`: such a key could never be
        // given on the command line, and each run's `--set` would set another key.
        if key.contains('=') {
            return Err(SweepError::Usage(format!(
                "the key `{key}` holds `=`; a key ends at the first `=` (as --set and --grid \
                 read key=value): name a key without it"
            )));
        }
        if values.is_empty() {
            return Err(SweepError::Usage(format!("{key}: no values")));
        }
        if values.len() > MAX_GRID_POINTS {
            return Err(SweepError::Usage(format!(
                "{} values; a sweep has at most {MAX_GRID_POINTS} points",
                values.len()
            )));
        }
        let mut seen = std::collections::HashSet::new();
        for v in &values {
            if !seen.insert(v.as_str()) {
                return Err(SweepError::Usage(format!(
                    "the value `{v}` is listed twice"
                )));
            }
            Override::parse(&format!("{key}={v}")).map_err(|e| SweepError::Usage(e.to_string()))?;
        }
        Ok(Axis {
            key: key.to_owned(),
            values,
        })
    }
}

/// Most points a grid may have (the product of its axes' lengths), checked before anything
/// runs: each point is a solve and a row of the tables rewritten after every run.
pub const MAX_GRID_POINTS: usize = 100_000;

/// The swept axes; their product is the grid, the last axis varying fastest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Grid {
    /// The axes in command-line order.
    pub axes: Vec<Axis>,
}

/// One point of the grid: its position in the grid's order and its value per axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// 0-based position in the grid's order.
    pub index: usize,
    /// The index of its value on each axis.
    pub coordinates: Vec<usize>,
    /// `(key, value)` per axis.
    pub values: Vec<(String, String)>,
}

/// Which part of the grid a process runs: `I/N` takes the points whose index is I mod N.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// 0-based shard number.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// The whole grid.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `I/N` with 0 ≤ I < N (Slurm's `$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT`).
    pub fn parse(arg: &str) -> Result<Shard, SweepError> {
        let bad = |m: &str| SweepError::Usage(format!("--shard {arg}: {m}"));
        let (i, n) = arg
            .split_once('/')
            .ok_or_else(|| bad("expected I/N, e.g. 0/4"))?;
        let index: usize = i.trim().parse().map_err(|_| bad("I is not a number"))?;
        let count: usize = n.trim().parse().map_err(|_| bad("N is not a number"))?;
        if count == 0 || index >= count {
            return Err(bad("needs 0 <= I < N"));
        }
        Ok(Shard { index, count })
    }

    /// Whether the point with this index belongs to the shard.
    pub fn contains(&self, index: usize) -> bool {
        index % self.count == self.index
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Grid {
    /// A grid over `axes`; a key may appear on one axis only.
    pub fn new(axes: Vec<Axis>) -> Result<Grid, SweepError> {
        if axes.is_empty() {
            return Err(SweepError::Usage(
                "give at least one --grid key=v1,v2,...".into(),
            ));
        }
        for (i, a) in axes.iter().enumerate() {
            if axes[..i].iter().any(|b| b.key == a.key) {
                return Err(SweepError::Usage(format!(
                    "--grid {}: the key is swept twice; list all its values in one --grid",
                    a.key
                )));
            }
        }
        let grid = Grid { axes };
        grid.check_size()?;
        Ok(grid)
    }

    /// Refuses a grid with no point or more than [`MAX_GRID_POINTS`] (the product counted
    /// without overflow), naming the axes' lengths.
    pub fn check_size(&self) -> Result<(), SweepError> {
        let count = self
            .axes
            .iter()
            .try_fold(1usize, |n, a| n.checked_mul(a.values.len()));
        match count {
            Some(n) if n > 0 && n <= MAX_GRID_POINTS => Ok(()),
            _ => {
                let lengths: Vec<String> = self
                    .axes
                    .iter()
                    .map(|a| a.values.len().to_string())
                    .collect();
                let points = match count {
                    Some(n) => n.to_string(),
                    None => "more than 2^64".into(),
                };
                Err(SweepError::Usage(format!(
                    "the grid has {points} points ({} values per axis); a sweep has 1 to \
                     {MAX_GRID_POINTS} points: sweep fewer values, or split the sweep by a \
                     key into several sweeps",
                    lengths.join(" × ")
                )))
            }
        }
    }

    /// Number of points (saturating; a grid from [`Grid::new`] has at most
    /// [`MAX_GRID_POINTS`]).
    pub fn len(&self) -> usize {
        self.axes
            .iter()
            .try_fold(1usize, |n, a| n.checked_mul(a.values.len()))
            .unwrap_or(usize::MAX)
    }

    /// Whether the grid has no points (never, for a grid made by [`Grid::new`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The point at `index` (last axis fastest).
    pub fn point(&self, index: usize) -> Point {
        let mut rest = index;
        let mut coordinates = vec![0; self.axes.len()];
        for (c, axis) in coordinates.iter_mut().zip(&self.axes).rev() {
            *c = rest % axis.values.len();
            rest /= axis.values.len();
        }
        let values = self
            .axes
            .iter()
            .zip(&coordinates)
            .map(|(a, &c)| (a.key.clone(), a.values[c].clone()))
            .collect();
        Point {
            index,
            coordinates,
            values,
        }
    }

    /// All points in order.
    pub fn points(&self) -> impl Iterator<Item = Point> + '_ {
        (0..self.len()).map(|i| self.point(i))
    }
}

/// Values as `key=value` pairs separated by spaces (a point's label in lines and tables).
pub(crate) fn values_label(values: &[(String, String)]) -> String {
    values
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect::<Vec<_>>()
        .join(" ")
}

impl Point {
    /// The point's values as `key=value` pairs separated by spaces.
    pub fn label(&self) -> String {
        values_label(&self.values)
    }

    /// The `--set` arguments of this point.
    pub fn set_args(&self) -> Vec<String> {
        self.values
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect()
    }

    /// The run directory's name: `key-value` pairs joined by `__`, characters other than
    /// letters, digits, `.`, `-` and `+` replaced by `_`; when that changed anything (two
    /// values could then share a name) or made it long, a hash of the exact values follows.
    pub fn run_name(&self) -> String {
        let raw: Vec<String> = self
            .values
            .iter()
            .map(|(k, v)| format!("{k}-{v}"))
            .collect();
        let raw = raw.join("__");
        let clean: String = raw
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '+' | '_') {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        if clean == raw && clean.len() <= 120 && !clean.starts_with('.') {
            return clean;
        }
        let short: String = clean.chars().take(100).collect();
        format!("{short}__{:016x}", fnv1a(raw.as_bytes()))
    }

    /// Grid distance to another point: the sum over axes of the index differences.
    pub fn distance(&self, other: &Point) -> usize {
        self.coordinates
            .iter()
            .zip(&other.coordinates)
            .map(|(a, b)| a.abs_diff(*b))
            .sum()
    }
}

/// FNV-1a: a stable hash (unlike std's, the same in every build) for directory names.
pub(super) fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> Grid {
        Grid::new(vec![
            Axis::parse("stride_hz=2,10,30").unwrap(),
            Axis::parse("contacts.friction=0.29, 1.02").unwrap(),
        ])
        .unwrap()
    }

    #[test]
    fn points_run_over_the_product_last_axis_fastest() {
        let g = grid();
        assert_eq!(g.len(), 6);
        let p = g.point(3);
        assert_eq!(p.coordinates, [1, 1]);
        assert_eq!(
            p.set_args(),
            ["stride_hz=10", "contacts.friction=1.02"].map(String::from)
        );
        assert_eq!(p.run_name(), "stride_hz-10__contacts.friction-1.02");
        assert_eq!(p.distance(&g.point(0)), 2);
        let names: std::collections::BTreeSet<_> = g.points().map(|p| p.run_name()).collect();
        assert_eq!(names.len(), 6);
    }

    /// A key holding `=` (which `--grid` and `--set` never give: a key ends at the first `=`)
    /// is refused by name, as the Python package's `grid={key: values}` would give it.
    #[test]
    fn keys_holding_an_equals_sign_are_refused() {
        let err = Axis::new("contacts.friction=2", vec!["0.5".into()]).unwrap_err();
        assert!(
            err.to_string().contains("`contacts.friction=2` holds `=`"),
            "{err}"
        );
        let axis = Axis::parse("contacts.friction==0.5").unwrap();
        assert_eq!(
            (axis.key.as_str(), &axis.values[..]),
            ("contacts.friction", &["=0.5".to_owned()][..])
        );
    }

    /// Grids of 2^64 points (which a product wraps to 0) and of 10^6 points are refused
    /// when made, before any point is enumerated; an axis longer than the limit is refused
    /// before its values are checked.
    #[test]
    fn oversized_grids_are_refused_up_front() {
        let two: Vec<Axis> = (0..64)
            .map(|i| Axis::parse(&format!("k{i}=1,2")).unwrap())
            .collect();
        let err = Grid::new(two).unwrap_err().to_string();
        assert!(err.contains("more than 2^64"), "{err}");
        let ten = |i: usize| {
            Axis::parse(&format!(
                "k{i}={}",
                (0..10).map(|v| v.to_string()).collect::<Vec<_>>().join(",")
            ))
            .unwrap()
        };
        let err = Grid::new((0..6).map(ten).collect())
            .unwrap_err()
            .to_string();
        assert!(err.contains("1000000 points"), "{err}");
        assert_eq!(Grid::new((0..5).map(ten).collect()).unwrap().len(), 100_000);
        let long = format!("k={}", vec!["1"; MAX_GRID_POINTS + 1].join(","));
        assert!(
            Axis::parse(&long)
                .unwrap_err()
                .to_string()
                .contains("at most")
        );
    }

    #[test]
    fn shards_partition_the_grid() {
        let g = grid();
        let mut seen = vec![0; g.len()];
        for i in 0..4 {
            let s = Shard::parse(&format!("{i}/4")).unwrap();
            for p in g.points().filter(|p| s.contains(p.index)) {
                seen[p.index] += 1;
            }
        }
        assert!(seen.iter().all(|&n| n == 1), "{seen:?}");
        for bad in ["4/4", "1", "a/2", "0/0"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn odd_values_get_distinct_safe_names() {
        let g = Grid::new(vec![Axis::parse("output.dir=a/b,a_b,..").unwrap()]).unwrap();
        let names: Vec<String> = g.points().map(|p| p.run_name()).collect();
        assert_eq!(names[1], "output.dir-a_b");
        assert!(names[0].starts_with("output.dir-a_b__"), "{}", names[0]);
        assert!(names.iter().all(|n| !n.contains('/')));
        assert_ne!(names[0], names[1]);
        for bad in ["x", "=1,2", "k=1,,2", "k=1,1"] {
            assert!(Axis::parse(bad).is_err(), "{bad}");
        }
        assert!(
            Grid::new(vec![
                Axis::parse("k=1").unwrap(),
                Axis::parse("k=2").unwrap()
            ])
            .is_err()
        );
    }
}
