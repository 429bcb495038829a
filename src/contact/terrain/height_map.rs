//! Heights on a grid, read from a file next to the problem: `[terrain.height_map]`.

use serde::Deserialize;

use super::Requirement;
use crate::autodiff::Scalar;

/// The problem file's `[terrain.height_map]` table: where the heights are and where they lie.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeightMapEntry {
    /// The heights' file, relative to the problem file: one row per grid line of constant y
    /// (the first row at the lowest y), one number per x, separated by commas or spaces;
    /// blank lines and lines starting with `#` are skipped.
    pub file: String,
    /// Grid spacing (Δx, Δy) [length], each > 0.
    pub spacing: [f64; 2],
    /// World (x, y) of the first row's first height [length] (default the origin).
    #[serde(default)]
    pub origin: [f64; 2],
}

impl HeightMapEntry {
    /// Each number of the table with what it must satisfy.
    pub fn requirements(&self) -> Vec<(&'static str, f64, Requirement)> {
        vec![
            ("spacing[0]", self.spacing[0], Requirement::Positive),
            ("spacing[1]", self.spacing[1], Requirement::Positive),
            ("origin[0]", self.origin[0], Requirement::Finite),
            ("origin[1]", self.origin[1], Requirement::Finite),
        ]
    }
}

/// Most grid lines a height map may have along each axis.
pub const MAX_HEIGHT_MAP_LINES: usize = 2000;

/// Why a height map's text was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HeightMapError {
    /// A number that does not parse or is not finite.
    #[error("line {line}, value {column}: `{text}` is not a finite number")]
    Number {
        /// 1-based line of the file.
        line: usize,
        /// 1-based position in the line.
        column: usize,
        /// What was there.
        text: String,
    },
    /// A row of another length than the first.
    #[error(
        "line {line} has {found} heights where the first row has {expected}: every row needs the same number"
    )]
    Ragged {
        /// 1-based line.
        line: usize,
        /// Its count.
        found: usize,
        /// The first row's.
        expected: usize,
    },
    /// Too few or too many grid lines.
    #[error(
        "{rows} rows of {columns} heights: a height map needs 2 to {MAX_HEIGHT_MAP_LINES} of each"
    )]
    Size {
        /// Rows read.
        rows: usize,
        /// Heights per row.
        columns: usize,
    },
}

/// Heights on a regular grid, interpolated by a bicubic spline: C², through every height of
/// the file, with natural ends (no curvature across the grid's border). Beyond the grid the
/// height is the border's (a point outside is moved onto the border, so the slope there is
/// zero): a map should reach past where the feet go.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    /// The file's entry.
    pub entry: HeightMapEntry,
    /// Grid lines along x and y (at least 2 each).
    pub nx: usize,
    /// Grid lines along y.
    pub ny: usize,
    /// The heights as read, row by row (ny rows of nx).
    pub heights: Vec<f64>,
    /// The spline's coefficients with one line of padding on each side, (ny + 2) rows of
    /// (nx + 2).
    coefficients: Vec<f64>,
}

impl HeightMap {
    /// Reads the heights of `text` (a file's contents) for `entry`.
    pub fn parse(entry: HeightMapEntry, text: &str) -> Result<HeightMap, HeightMapError> {
        let mut rows: Vec<Vec<f64>> = Vec::new();
        for (l, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let mut row = Vec::new();
            for (c, field) in line
                .split(|ch: char| ch == ',' || ch.is_whitespace())
                .filter(|f| !f.is_empty())
                .enumerate()
            {
                match field.parse::<f64>() {
                    Ok(v) if v.is_finite() => row.push(v),
                    _ => {
                        return Err(HeightMapError::Number {
                            line: l + 1,
                            column: c + 1,
                            text: field.chars().take(40).collect(),
                        });
                    }
                }
            }
            if let Some(first) = rows.first()
                && first.len() != row.len()
            {
                return Err(HeightMapError::Ragged {
                    line: l + 1,
                    found: row.len(),
                    expected: first.len(),
                });
            }
            rows.push(row);
            if rows.len() > MAX_HEIGHT_MAP_LINES {
                break;
            }
        }
        let (ny, nx) = (rows.len(), rows.first().map_or(0, Vec::len));
        let lines = 2..=MAX_HEIGHT_MAP_LINES;
        if !lines.contains(&nx) || !lines.contains(&ny) {
            return Err(HeightMapError::Size {
                rows: ny,
                columns: nx,
            });
        }
        let heights: Vec<f64> = rows.into_iter().flatten().collect();
        Ok(HeightMap {
            entry,
            nx,
            ny,
            coefficients: spline_coefficients(&heights, nx, ny),
            heights,
        })
    }

    /// The interpolated height at world (x, y) [length], C² inside the grid.
    pub fn height<D: Scalar>(&self, x: D, y: D) -> D {
        let (i, tx) = cell(x, self.entry.origin[0], self.entry.spacing[0], self.nx);
        let (j, ty) = cell(y, self.entry.origin[1], self.entry.spacing[1], self.ny);
        let (bx, by) = (basis(tx), basis(ty));
        let width = self.nx + 2;
        let mut sum = D::from(0.0);
        for (b, wy) in by.iter().enumerate() {
            let row = &self.coefficients[(j + b) * width + i..(j + b) * width + i + 4];
            let mut line = D::from(0.0);
            for (&c, wx) in row.iter().zip(&bx) {
                line += *wx * D::from(c);
            }
            sum += line * *wy;
        }
        sum
    }

    /// World x of the grid's first and last lines, and y's: [x0, x1, y0, y1].
    pub fn extent(&self) -> [f64; 4] {
        let [x0, y0] = self.entry.origin;
        let [dx, dy] = self.entry.spacing;
        [
            x0,
            x0 + dx * (self.nx - 1) as f64,
            y0,
            y0 + dy * (self.ny - 1) as f64,
        ]
    }
}

/// The cell of a coordinate and the position within it: (index of the padded coefficient
/// line before the cell, t in [0, 1]); outside the grid the border.
fn cell<D: Scalar>(v: D, origin: f64, spacing: f64, lines: usize) -> (usize, D) {
    let u = (v - D::from(origin)) / D::from(spacing);
    let last = (lines - 1) as f64;
    if u.re().is_nan() || u.re() <= 0.0 {
        return (0, D::from(0.0));
    }
    if u.re() >= last {
        return (lines - 2, D::from(1.0));
    }
    let i = (u.re().floor() as usize).min(lines - 2);
    (i, u - D::from(i as f64))
}

/// The uniform cubic B-spline's four weights at t in [0, 1].
fn basis<D: Scalar>(t: D) -> [D; 4] {
    let (t2, t3) = (t * t, t * t * t);
    let one = D::from(1.0);
    let sixth = D::from(1.0 / 6.0);
    [
        (one - t) * (one - t) * (one - t) * sixth,
        (t3 * 3.0 - t2 * 6.0 + 4.0) * sixth,
        (t3 * -3.0 + t2 * 3.0 + t * 3.0 + one) * sixth,
        t3 * sixth,
    ]
}

/// The coefficients c of the cubic spline through `values` (natural ends: c₀ = v₀,
/// c_{n−1} = v_{n−1}, c_{i−1} + 4c_i + c_{i+1} = 6v_i inside), padded with one line on each
/// side by linear extrapolation (c_{−1} = 2c₀ − c₁).
fn spline_line(values: &[f64]) -> Vec<f64> {
    let n = values.len();
    let mut c = values.to_vec();
    if n > 2 {
        // Thomas algorithm on the interior rows, the end values known.
        let m = n - 2;
        let mut diag = vec![4.0; m];
        let mut rhs: Vec<f64> = (1..n - 1).map(|i| 6.0 * values[i]).collect();
        rhs[0] -= values[0];
        rhs[m - 1] -= values[n - 1];
        for k in 1..m {
            let f = 1.0 / diag[k - 1];
            diag[k] -= f;
            rhs[k] -= f * rhs[k - 1];
        }
        c[m] = rhs[m - 1] / diag[m - 1];
        for k in (0..m - 1).rev() {
            c[k + 1] = (rhs[k] - c[k + 2]) / diag[k];
        }
        c[n - 1] = values[n - 1];
    }
    let mut padded = Vec::with_capacity(n + 2);
    padded.push(2.0 * c[0] - c[1]);
    padded.extend_from_slice(&c);
    padded.push(2.0 * c[n - 1] - c[n - 2]);
    padded
}

/// The padded tensor-product coefficients ((ny + 2) × (nx + 2)) of the bicubic spline.
fn spline_coefficients(heights: &[f64], nx: usize, ny: usize) -> Vec<f64> {
    let rows: Vec<Vec<f64>> = heights.chunks(nx).map(spline_line).collect();
    let width = nx + 2;
    let mut out = vec![0.0; (ny + 2) * width];
    for i in 0..width {
        let column: Vec<f64> = rows.iter().map(|r| r[i]).collect();
        for (j, c) in spline_line(&column).into_iter().enumerate() {
            out[j * width + i] = c;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry() -> HeightMapEntry {
        HeightMapEntry {
            file: "map.csv".into(),
            spacing: [0.1, 0.2],
            origin: [-0.1, 0.0],
        }
    }

    /// The spline passes through every height of the file, and a plane's heights give the
    /// plane everywhere inside (a natural cubic spline reproduces linear data).
    #[test]
    fn the_spline_interpolates_and_keeps_planes() {
        let mut text = String::from("# a plane z = 0.3 x − 0.2 y + 0.05\n");
        for j in 0..5 {
            let y = 0.2 * f64::from(j);
            let row: Vec<String> = (0..6)
                .map(|i| {
                    let x = -0.1 + 0.1 * f64::from(i);
                    format!("{}", 0.3 * x - 0.2 * y + 0.05)
                })
                .collect();
            text.push_str(&row.join(", "));
            text.push('\n');
        }
        let map = HeightMap::parse(entry(), &text).unwrap();
        assert_eq!((map.nx, map.ny), (6, 5));
        for (x, y) in [(-0.1, 0.0), (0.13, 0.37), (0.4, 0.8), (0.2999, 0.0001)] {
            let z = map.height::<f64>(x, y);
            assert!(
                (z - (0.3 * x - 0.2 * y + 0.05)).abs() < 1e-14,
                "{x} {y} {z}"
            );
        }
    }

    #[test]
    fn the_spline_passes_through_the_heights_and_is_smooth() {
        let text = "0 0.1 0.3 0.2\n0.05 0.4 0.1 0.0\n0.2 0.2 0.2 0.6\n";
        let map = HeightMap::parse(entry(), text).unwrap();
        for j in 0..3 {
            for i in 0..4 {
                let (x, y) = (-0.1 + 0.1 * i as f64, 0.2 * j as f64);
                let z = map.height::<f64>(x, y);
                assert!((z - map.heights[j * 4 + i]).abs() < 1e-14, "{i} {j}");
            }
        }
        // The second derivative along x is continuous across the grid line x = 0.1.
        let second = |x: f64| {
            let e = 1e-4;
            (map.height::<f64>(x + e, 0.3) - 2.0 * map.height::<f64>(x, 0.3)
                + map.height::<f64>(x - e, 0.3))
                / (e * e)
        };
        assert!((second(0.1 - 2e-4) - second(0.1 + 2e-4)).abs() < 0.5);
    }

    #[test]
    fn bad_files_are_refused_with_their_line() {
        assert_eq!(
            HeightMap::parse(entry(), "0 1\n0 nan\n"),
            Err(HeightMapError::Number {
                line: 2,
                column: 2,
                text: "nan".into()
            })
        );
        assert_eq!(
            HeightMap::parse(entry(), "0 1\n0 1 2\n"),
            Err(HeightMapError::Ragged {
                line: 2,
                found: 3,
                expected: 2
            })
        );
        assert_eq!(
            HeightMap::parse(entry(), "0 1\n"),
            Err(HeightMapError::Size {
                rows: 1,
                columns: 2
            })
        );
    }
}
