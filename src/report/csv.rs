//! The trajectory as CSV: one row per knot, one column per named quantity, units in headers.
//!
//! Columns, in order: `time [s]`; each coordinate `<name> [m|rad]`; each velocity
//! `<name>_dot [m/s|rad/s]` (v_0 on the first row, the backward difference (q_k − q_{k−1})/h
//! after); each input `u_<name> [N|N·m]`; per contact `<contact>_normal [N·s]`, its friction
//! impulses `<contact>_friction_<dir> [N·s]` (dir +x, −x in the plane; +x, +y, −x, −y in
//! space) and its signed distance `<contact>_distance [m]`; the slacks `slack` (or
//! `slack_<j>` in per-contact mode). Interval quantities (inputs, impulses, distances at the
//! interval's end knot, slacks) sit on the interval's first knot; the last row leaves them
//! empty. Units follow the robot's (`robot.units`).

use crate::transcription::Solution;

/// Unit labels for the columns.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnUnits {
    /// Time unit, e.g. `s`.
    pub time: String,
    /// Length unit, e.g. `m`.
    pub length: String,
    /// Per coordinate: `m` or `rad` (length n).
    pub coordinates: Vec<String>,
    /// Per input: `N` or `N·m` (length m).
    pub inputs: Vec<String>,
    /// Impulse unit, e.g. `N·s`.
    pub impulse: String,
}

/// The column holding input `name`.
pub fn input_column_name(name: &str) -> String {
    format!("u_{name}")
}

/// Names of the friction directions for `nd` directions per contact.
pub fn friction_direction_names(nd: usize) -> Vec<String> {
    match nd {
        2 => vec!["+x".into(), "-x".into()],
        4 => vec!["+x".into(), "+y".into(), "-x".into(), "-y".into()],
        _ => (0..nd).map(|d| format!("d{d}")).collect(),
    }
}

fn header(name: &str, unit: &str) -> String {
    if unit.is_empty() {
        name.to_owned()
    } else {
        format!("{name} [{unit}]")
    }
}

fn number(x: f64) -> String {
    // `{:e}`-free shortest round-trip representation: Rust's Display for f64 is exact.
    format!("{x}")
}

/// Renders the trajectory CSV.
pub fn trajectory_csv(solution: &Solution, units: &ColumnUnits) -> String {
    let s = solution;
    let mut names = vec![header("time", &units.time)];
    for (c, unit) in s.coordinate_names.iter().zip(&units.coordinates) {
        names.push(header(c, unit));
    }
    for (c, unit) in s.coordinate_names.iter().zip(&units.coordinates) {
        names.push(header(
            &format!("{c}_dot"),
            &format!("{unit}/{}", units.time),
        ));
    }
    for (u, unit) in s.input_names.iter().zip(&units.inputs) {
        names.push(header(&input_column_name(u), unit));
    }
    let directions = friction_direction_names(s.friction_directions);
    for c in &s.contact_names {
        names.push(header(&format!("{c}_normal"), &units.impulse));
        for d in &directions {
            names.push(header(&format!("{c}_friction_{d}"), &units.impulse));
        }
        names.push(header(&format!("{c}_distance"), &units.length));
    }
    let slacks = s.slack.first().map_or(1, Vec::len);
    if slacks == 1 {
        names.push("slack".into());
    } else {
        names.extend((0..slacks).map(|j| format!("slack_{j}")));
    }
    let mut out = names.join(",");
    out.push('\n');
    let knots = s.times.len();
    for k in 0..knots {
        let mut row: Vec<String> = vec![number(s.times[k])];
        row.extend(s.q[k].iter().map(|&x| number(x)));
        row.extend(s.v[k].iter().map(|&x| number(x)));
        let interval = k + 1 < knots;
        let cell = |x: Option<&f64>| match (interval, x) {
            (true, Some(x)) => number(*x),
            _ => String::new(),
        };
        for j in 0..s.input_names.len() {
            row.push(cell(s.u.get(k).and_then(|u| u.get(j))));
        }
        for i in 0..s.contact_names.len() {
            row.push(cell(s.normal_impulse.get(k).and_then(|c| c.get(i))));
            for d in 0..directions.len() {
                row.push(cell(
                    s.friction_impulse
                        .get(k)
                        .and_then(|b| b.get(i))
                        .and_then(|b| b.get(d)),
                ));
            }
            row.push(cell(s.signed_distance.get(k).and_then(|p| p.get(i))));
        }
        for j in 0..slacks {
            row.push(cell(s.slack.get(k).and_then(|x| x.get(j))));
        }
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}

/// A numeric CSV read back: column names without their `[unit]`, and columns of numbers
/// (empty cells are NaN).
#[derive(Debug, Clone, PartialEq)]
pub struct CsvTable {
    /// Column names, units stripped.
    pub names: Vec<String>,
    /// One vector per column (rows in order).
    pub columns: Vec<Vec<f64>>,
}

impl CsvTable {
    /// The column called `name` (units stripped), if any.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.names.iter().position(|n| n == name)?;
        Some(self.columns[i].clone())
    }
    /// Number of data rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }
}

/// Parses a numeric CSV with a header row; the message names the row and column at fault.
pub fn read_csv(text: &str) -> Result<CsvTable, String> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header = lines.next().ok_or("the file is empty")?;
    let names: Vec<String> = header
        .split(',')
        .map(|h| match h.find(" [") {
            Some(i) => h[..i].trim().to_owned(),
            None => h.trim().to_owned(),
        })
        .collect();
    let mut columns = vec![Vec::new(); names.len()];
    for (r, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        if cells.len() != names.len() {
            return Err(format!(
                "row {} has {} cells, the header has {}",
                r + 2,
                cells.len(),
                names.len()
            ));
        }
        for (c, cell) in cells.iter().enumerate() {
            let cell = cell.trim();
            let v = if cell.is_empty() {
                f64::NAN
            } else {
                cell.parse::<f64>().map_err(|_| {
                    format!(
                        "row {}, column `{}`: `{cell}` is not a number",
                        r + 2,
                        names[c]
                    )
                })?
            };
            columns[c].push(v);
        }
    }
    Ok(CsvTable { names, columns })
}
