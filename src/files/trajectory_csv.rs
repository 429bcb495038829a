//! The trajectory CSV format, written by `report` and read back by `problem` for warm
//! starts: one row per knot, one column per named quantity, units in headers.
//!
//! Columns, in order: `time [s]`; each coordinate `<name> [m|rad]`; each velocity
//! `<name>_dot [m/s|rad/s]` (v_0 on the first row, the backward difference (q_k − q_{k−1})/h
//! after); each input `u_<name> [N|N·m]`; per contact `<contact>_normal [N·s]`, its friction
//! impulses `<contact>_friction_<dir> [N·s]` (dir +x, −x in the plane; +x, +y, −x, −y in
//! space), its signed distance `<contact>_distance [m]` and its world position
//! `<contact>_x [m]`, `<contact>_y [m]`, `<contact>_z [m]` at the row's own knot; the slacks
//! `slack` (or `slack_<j>` in per-contact mode). Interval quantities (inputs, impulses,
//! slacks) sit on the interval's first knot; the last row leaves them empty. The impulses of
//! row k are complementary to the distance of row k + 1 (c_k·φ(q_{k+1}) ≤ s_k). Units follow
//! the robot's (`robot.units`). Numbers are shortest round-trip decimals ([`number`]).
//!
//! This module knows the format only (column names, units, number text, parsing), not where
//! the numbers come from, so that both `report` (above it) and `problem` can use it.

use crate::files::names::list_names;

/// What one CSV holds, by knot (k = 0..N−1) and interval (k = 0..N−2).
#[derive(Debug, Clone, Copy)]
pub struct Trajectory<'a> {
    /// Knot times (length N).
    pub times: &'a [f64],
    /// Coordinate names (length n).
    pub coordinate_names: &'a [String],
    /// Configurations (N × n).
    pub q: &'a [Vec<f64>],
    /// Velocities (N × n).
    pub v: &'a [Vec<f64>],
    /// Input names (length m).
    pub input_names: &'a [String],
    /// Inputs per interval (N−1 × m).
    pub u: &'a [Vec<f64>],
    /// Contact names (length nc).
    pub contact_names: &'a [String],
    /// Friction directions per contact.
    pub friction_directions: usize,
    /// Normal impulses per interval (N−1 × nc).
    pub normal_impulse: &'a [Vec<f64>],
    /// Friction impulses per interval (N−1 × nc × nd).
    pub friction_impulse: &'a [Vec<Vec<f64>>],
    /// Each interval's impulse per contact as a world vector (N−1 × nc,
    /// [`crate::contact::interval_world_impulses`]; empty: unknown, the cells left empty).
    pub world_impulse: &'a [Vec<[f64; 3]>],
    /// Signed distances at every knot (N × nc).
    pub signed_distance: &'a [Vec<f64>],
    /// World positions of the contact points at every knot (N × nc; empty: unknown, the
    /// cells left empty).
    pub contact_positions: &'a [Vec<[f64; 3]>],
    /// Slacks per interval (N−1 × slacks per interval).
    pub slack: &'a [Vec<f64>],
}

/// The world axes of a contact's position columns `<contact>_x`, `_y`, `_z`.
const AXES: [&str; 3] = ["x", "y", "z"];

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

#[cfg(test)]
impl ColumnUnits {
    /// SI labels for the tests' two-coordinate sample: x in m, θ in rad, one torque input.
    pub(crate) fn x_theta_sample() -> Self {
        ColumnUnits {
            time: "s".into(),
            length: "m".into(),
            coordinates: vec!["m".into(), "rad".into()],
            inputs: vec!["N·m".into()],
            impulse: "N·s".into(),
        }
    }
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

/// A number as the file writes it: the shortest decimal that reads back to the same f64
/// (Rust's `Display` and `LowerExp` both print the fewest such digits), positional for
/// 1e-5 ≤ |x| < 1e16 (`0.15`, `2`), with an exponent otherwise (`-6.88e-14`).
pub fn number(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1e-5..1e16).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// The time of knot k after k equal steps h: the exact decimal product of k and h's
/// shortest decimal, rounded once, so that 3 steps of 0.05 end at 0.15 (k·h in floating
/// point gives 0.15000000000000002, which is what h = 0.05 written in a file means only up
/// to round-off).
pub fn knot_time(k: usize, h: f64) -> f64 {
    let fallback = k as f64 * h;
    let text = format!("{h:e}");
    let Some((mantissa, exponent)) = text.split_once('e') else {
        return fallback;
    };
    let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let (Ok(digits), Ok(exponent)) = (
        format!("{int}{frac}").parse::<i128>(),
        exponent.parse::<i32>(),
    ) else {
        return fallback;
    };
    let Some(product) = digits.checked_mul(k as i128) else {
        return fallback;
    };
    let exponent = exponent - frac.len() as i32;
    format!("{product}e{exponent}").parse().unwrap_or(fallback)
}

/// `cell` as one CSV field (RFC 4180): in double quotes, its quotes doubled, when it holds
/// a comma, a quote, a line break or leading or trailing space; as it is otherwise.
pub fn csv_field(cell: &str) -> String {
    if cell.contains([',', '"', '\n', '\r']) || cell.trim() != cell {
        format!("\"{}\"", cell.replace('"', "\"\""))
    } else {
        cell.to_owned()
    }
}

/// The fields of one CSV line as [`csv_field`] writes them: quoted fields unquoted (`""` a
/// quote), others as they are. A quote inside an unquoted field, or text after a quoted
/// field's closing quote, is an error.
pub fn split_csv_line(line: &str) -> Result<Vec<String>, String> {
    let mut fields = Vec::new();
    let mut chars = line.chars().peekable();
    loop {
        let mut field = String::new();
        if chars.peek() == Some(&'"') {
            chars.next();
            loop {
                match chars.next() {
                    Some('"') if chars.peek() == Some(&'"') => {
                        chars.next();
                        field.push('"');
                    }
                    Some('"') => break,
                    Some(c) => field.push(c),
                    None => return Err("a quoted field has no closing quote".into()),
                }
            }
            match chars.next() {
                None => {
                    fields.push(field);
                    return Ok(fields);
                }
                Some(',') => fields.push(field),
                Some(_) => return Err("text follows a quoted field's closing quote".into()),
            }
        } else {
            loop {
                match chars.next() {
                    None => {
                        fields.push(field);
                        return Ok(fields);
                    }
                    Some(',') => {
                        fields.push(field);
                        break;
                    }
                    Some('"') => return Err("a quote inside an unquoted field".into()),
                    Some(c) => field.push(c),
                }
            }
        }
    }
}

/// What gives a trajectory CSV column its name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ColumnSource {
    /// The knot time.
    Time,
    /// A coordinate (its value or its rate), by name.
    Coordinate(String),
    /// An input, by name.
    Input(String),
    /// A contact (impulses, distance, position), by name.
    Contact(String),
    /// The slacks.
    Slack,
}

impl std::fmt::Display for ColumnSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ColumnSource::Time => write!(f, "the time"),
            ColumnSource::Coordinate(name) => write!(f, "coordinate `{name}`"),
            ColumnSource::Input(name) => write!(f, "input `{name}`"),
            ColumnSource::Contact(name) => write!(f, "contact `{name}`"),
            ColumnSource::Slack => write!(f, "the slack"),
        }
    }
}

/// One column of a trajectory CSV: its name, its unit (empty: none) and what gives it its
/// name.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// The name (the header without its unit).
    pub name: String,
    /// The unit.
    pub unit: String,
    /// What the name comes from.
    pub source: ColumnSource,
}

/// The columns of a trajectory CSV, in order, for these names, friction directions per
/// contact and slacks per interval.
pub fn columns(
    coordinate_names: &[String],
    input_names: &[String],
    contact_names: &[String],
    friction_directions: usize,
    slacks: usize,
    units: &ColumnUnits,
) -> Vec<Column> {
    let column = |name: String, unit: &str, source: ColumnSource| Column {
        name,
        unit: unit.to_owned(),
        source,
    };
    let unit_of = |list: &[String], i: usize| list.get(i).cloned().unwrap_or_default();
    let mut out = vec![column("time".into(), &units.time, ColumnSource::Time)];
    for (i, c) in coordinate_names.iter().enumerate() {
        out.push(column(
            c.clone(),
            &unit_of(&units.coordinates, i),
            ColumnSource::Coordinate(c.clone()),
        ));
    }
    for (i, c) in coordinate_names.iter().enumerate() {
        let rate = format!("{}/{}", unit_of(&units.coordinates, i), units.time);
        out.push(column(
            format!("{c}_dot"),
            &rate,
            ColumnSource::Coordinate(c.clone()),
        ));
    }
    for (i, u) in input_names.iter().enumerate() {
        out.push(column(
            input_column_name(u),
            &unit_of(&units.inputs, i),
            ColumnSource::Input(u.clone()),
        ));
    }
    let directions = friction_direction_names(friction_directions);
    for c in contact_names {
        let source = || ColumnSource::Contact(c.clone());
        out.push(column(format!("{c}_normal"), &units.impulse, source()));
        for d in &directions {
            out.push(column(
                format!("{c}_friction_{d}"),
                &units.impulse,
                source(),
            ));
        }
        for axis in AXES {
            out.push(column(format!("{c}_f{axis}"), &units.impulse, source()));
        }
        out.push(column(format!("{c}_distance"), &units.length, source()));
        for axis in AXES {
            out.push(column(format!("{c}_{axis}"), &units.length, source()));
        }
    }
    if slacks == 1 {
        out.push(column("slack".into(), "", ColumnSource::Slack));
    } else {
        out.extend((0..slacks).map(|j| column(format!("slack_{j}"), "", ColumnSource::Slack)));
    }
    out
}

/// The first two columns of `columns` with one name, if any: a CSV with both could not be
/// read back (every column appears once).
pub fn repeated_column(columns: &[Column]) -> Option<(&Column, &Column)> {
    let mut seen = std::collections::HashMap::new();
    for (i, c) in columns.iter().enumerate() {
        if let Some(&first) = seen.get(c.name.as_str()) {
            return Some((&columns[first], c));
        }
        seen.insert(c.name.as_str(), i);
    }
    None
}

/// Renders the trajectory CSV.
pub fn write_trajectory(trajectory: &Trajectory<'_>, units: &ColumnUnits) -> String {
    let s = trajectory;
    let directions = friction_direction_names(s.friction_directions);
    let slacks = s.slack.first().map_or(1, Vec::len);
    let names: Vec<String> = columns(
        s.coordinate_names,
        s.input_names,
        s.contact_names,
        s.friction_directions,
        slacks,
        units,
    )
    .iter()
    .map(|c| header(&c.name, &c.unit))
    .collect();
    let mut out = names
        .iter()
        .map(|n| csv_field(n))
        .collect::<Vec<_>>()
        .join(",");
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
            for a in 0..AXES.len() {
                row.push(cell(
                    s.world_impulse.get(k).and_then(|f| f.get(i)).map(|f| &f[a]),
                ));
            }
            // A knot quantity: on every row, the last included.
            row.push(
                s.signed_distance
                    .get(k)
                    .and_then(|p| p.get(i))
                    .map_or(String::new(), |&d| number(d)),
            );
            for a in 0..AXES.len() {
                row.push(
                    s.contact_positions
                        .get(k)
                        .and_then(|p| p.get(i))
                        .map_or(String::new(), |p| number(p[a])),
                );
            }
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

/// Longest column name read (bytes), as the problem file's names.
const MAX_COLUMN_NAME: usize = 200;

/// The shape of a trajectory CSV's header, for messages.
const EXPECTED_HEADER: &str = "a trajectory CSV header (`time [s],<coordinate> [m|rad],…`, \
     as `vito solve` writes it)";

/// `cell` as a message may quote it: a short number-like cell as it is, anything else only
/// described, so that an error never shows what some other file holds.
fn quote_cell(cell: &str) -> String {
    let number_like = cell.len() <= 24
        && cell
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '+' | '-'));
    if number_like {
        format!("`{cell}`")
    } else {
        format!("a {}-byte cell that is not a number", cell.len())
    }
}

/// Parses a numeric CSV with a trajectory header row (`time` first, names of printable
/// text, each once); a file whose first line is no such header is refused before any row is
/// read. Cells are finite numbers or empty (NaN). The message names the row and column at
/// fault and the shape expected, never more of the file than a short number-like cell.
pub fn read_csv(text: &str) -> Result<CsvTable, String> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header = lines.next().ok_or("the file is empty")?;
    let not_header = || format!("its first line is not {EXPECTED_HEADER}; nothing of it was read");
    // A name may itself hold ` [` (a contact `a [b]`): the unit is the last bracket.
    let names: Vec<String> = split_csv_line(header)
        .map_err(|_| not_header())?
        .iter()
        .map(|h| {
            let h = h.trim();
            match h.rfind(" [") {
                Some(i) if h.ends_with(']') => h[..i].trim_end().to_owned(),
                _ => h.to_owned(),
            }
        })
        .collect();
    let plain = |n: &String| {
        !n.is_empty()
            && n.len() <= MAX_COLUMN_NAME
            && !n.chars().any(crate::files::names::is_hidden_char)
    };
    if names.first().map(String::as_str) != Some("time") || !names.iter().all(plain) {
        return Err(not_header());
    }
    for (c, name) in names.iter().enumerate() {
        if let Some(first) = names[..c].iter().position(|n| n == name) {
            return Err(format!(
                "columns {} and {} are both `{name}`; each column appears once",
                first + 1,
                c + 1
            ));
        }
    }
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
                match cell.parse::<f64>() {
                    Ok(v) if v.is_finite() => v,
                    _ => {
                        return Err(format!(
                            "row {}, column {} (`{}`): {} where a finite decimal number \
                             (such as 0.25 or -1e-3) or an empty cell belongs",
                            r + 2,
                            c + 1,
                            names[c],
                            quote_cell(cell)
                        ));
                    }
                }
            };
            columns[c].push(v);
        }
    }
    Ok(CsvTable { names, columns })
}

/// What a warm start takes from a trajectory CSV: knot times, configurations by coordinate
/// name, and inputs by input name when every input has a column.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedTrajectory {
    /// Knot times (at least two, increasing).
    pub times: Vec<f64>,
    /// Configurations at those times, in the order of the names asked for.
    pub q: Vec<Vec<f64>>,
    /// Inputs per interval (one fewer than times), empty when some input has no column
    /// (an empty cell on a row but the last is an error).
    pub u: Vec<Vec<f64>>,
}

/// Reads the time, coordinate and input columns of a trajectory CSV by name, in the order
/// `coordinates` and `inputs` give; the message says what is missing or wrong.
pub fn read_trajectory(
    text: &str,
    coordinates: &[String],
    inputs: &[String],
) -> Result<RecordedTrajectory, String> {
    let table = read_csv(text)?;
    let times = table.column("time").ok_or("no `time` column")?;
    if times.len() < 2 || times.iter().any(|t| t.is_nan()) || times.windows(2).any(|w| w[1] <= w[0])
    {
        return Err("the `time` column must hold at least two increasing numbers".into());
    }
    let mut q = vec![vec![0.0; coordinates.len()]; times.len()];
    for (j, name) in coordinates.iter().enumerate() {
        let column = table.column(name).ok_or_else(|| {
            format!(
                "no column for coordinate `{name}` (columns: {})",
                list_names(&table.names, 24)
            )
        })?;
        for (k, v) in column.iter().enumerate() {
            if v.is_nan() {
                return Err(format!("coordinate `{name}` has no value in row {}", k + 2));
            }
            q[k][j] = *v;
        }
    }
    let mut u = Vec::new();
    let input_columns: Vec<Option<Vec<f64>>> = inputs
        .iter()
        .map(|name| table.column(&input_column_name(name)))
        .collect();
    if !inputs.is_empty() && input_columns.iter().all(Option::is_some) {
        for k in 0..times.len() - 1 {
            let mut row = Vec::with_capacity(inputs.len());
            for (name, column) in inputs.iter().zip(&input_columns) {
                let v = column.as_ref().map_or(f64::NAN, |c| c[k]);
                if v.is_nan() {
                    return Err(format!(
                        "row {}, column `{}` is empty: every row but the last holds the \
                         inputs of its interval",
                        k + 2,
                        input_column_name(name)
                    ));
                }
                row.push(v);
            }
            u.push(row);
        }
    }
    Ok(RecordedTrajectory { times, q, u })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names with commas, quotes and brackets are quoted in the header and read back as the
    /// same names; a hand-written header with a stray quote is refused.
    #[test]
    fn names_with_commas_and_quotes_survive_the_header() {
        assert_eq!(csv_field("left,foot [N·s]"), "\"left,foot [N·s]\"");
        assert_eq!(csv_field("a\"b"), "\"a\"\"b\"");
        assert_eq!(csv_field("plain [m]"), "plain [m]");
        assert_eq!(
            split_csv_line("time [s],\"left,foot_normal [N·s]\",\"a\"\"b [m]\",x").unwrap(),
            ["time [s]", "left,foot_normal [N·s]", "a\"b [m]", "x"]
        );
        for bad in ["a\"b,c", "\"a\"b,c", "\"open,c"] {
            assert!(split_csv_line(bad).is_err(), "{bad}");
        }
        let names = ["left,foot", "a\"b", "c [d]"].map(String::from);
        let header = names
            .iter()
            .map(|n| csv_field(&format!("{n}_normal [N·s]")))
            .collect::<Vec<_>>()
            .join(",");
        let table = read_csv(&format!("time [s],{header}\n0,1,2,3\n")).unwrap();
        assert_eq!(
            table.names,
            ["time", "left,foot_normal", "a\"b_normal", "c [d]_normal"]
        );
        assert_eq!(table.column("left,foot_normal").unwrap(), [1.0]);
        assert!(read_csv("time [s],a\"b\n0,1\n").is_err());
    }

    #[test]
    fn numbers_are_shortest_round_trip_and_times_decimal() {
        for x in [
            0.15,
            0.1 + 0.2,
            -6.88338275267597e-14,
            1e-9,
            2.0,
            1e300,
            123456.789,
            0.0,
        ] {
            assert_eq!(number(x).parse::<f64>().unwrap(), x, "{}", number(x));
        }
        assert_eq!(number(-6.88338275267597e-14), "-6.88338275267597e-14");
        assert_eq!(number(2.0), "2");
        assert_eq!(number(0.15), "0.15");
        // k·h in floating point: 3·0.05 = 0.15000000000000002, 3·0.1 = 0.30000000000000004.
        assert_eq!(number(knot_time(3, 0.05)), "0.15");
        assert_eq!(number(knot_time(3, 0.1)), "0.3");
        assert_eq!(number(knot_time(29, 0.1)), "2.9");
        assert_eq!(knot_time(0, 0.1), 0.0);
        assert_eq!(knot_time(7, 0.25), 1.75);
        let h = 0.123_456_789_012_345_68;
        assert!((knot_time(11, h) - 11.0 * h).abs() <= 2.0 * f64::EPSILON * 11.0 * h);
    }

    #[test]
    fn written_trajectory_reads_back_by_name() {
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let coordinates = names(&["x", "theta"]);
        let inputs = names(&["theta"]);
        let contacts = names(&["toe"]);
        let q = vec![vec![0.0, 0.5], vec![0.25, -1.5], vec![0.5, 2.0]];
        let trajectory = Trajectory {
            times: &[0.0, 0.1, 0.3],
            coordinate_names: &coordinates,
            q: &q,
            v: &[vec![0.0; 2], vec![2.5, -20.0], vec![1.25, 17.5]],
            input_names: &inputs,
            u: &[vec![3.0], vec![-4.0]],
            contact_names: &contacts,
            friction_directions: 2,
            normal_impulse: &[vec![1.0], vec![0.0]],
            friction_impulse: &[vec![vec![0.5, 0.0]], vec![vec![0.0, 0.0]]],
            world_impulse: &[vec![[0.5, 0.0, 1.0]], vec![[0.0, 0.0, 2.0]]],
            signed_distance: &[vec![0.0], vec![0.1], vec![0.25]],
            contact_positions: &[
                vec![[0.0, 0.0, 0.0]],
                vec![[0.25, 0.0, 0.1]],
                vec![[0.5, 0.0, 0.25]],
            ],
            slack: &[vec![1e-9], vec![2e-9]],
        };
        let units = ColumnUnits::x_theta_sample();
        let text = write_trajectory(&trajectory, &units);
        assert_eq!(
            text.lines().next(),
            Some(
                "time [s],x [m],theta [rad],x_dot [m/s],theta_dot [rad/s],u_theta [N·m],\
                 toe_normal [N·s],toe_friction_+x [N·s],toe_friction_-x [N·s],\
                 toe_fx [N·s],toe_fy [N·s],toe_fz [N·s],toe_distance [m],\
                 toe_x [m],toe_y [m],toe_z [m],slack"
            )
        );
        assert_eq!(
            text.lines().nth(3),
            Some("0.3,0.5,2,1.25,17.5,,,,,,,,0.25,0.5,0,0.25,")
        );
        assert_eq!(
            text.lines().nth(1),
            Some("0,0,0.5,0,0,3,1,0.5,0,0.5,0,1,0,0,0,0,1e-9")
        );
        // Asked in another order than written.
        let back = read_trajectory(&text, &names(&["theta", "x"]), &inputs).unwrap();
        assert_eq!(back.times, [0.0, 0.1, 0.3]);
        assert_eq!(back.q[1], [-1.5, 0.25]);
        assert_eq!(back.u, vec![vec![3.0], vec![-4.0]]);
        let err = read_trajectory(&text, &names(&["z"]), &[]).unwrap_err();
        assert!(
            err.starts_with("no column for coordinate `z` (columns: `time`, `x`"),
            "{err}"
        );
        // Without a column for every input, no inputs are taken.
        let back = read_trajectory(&text, &coordinates, &names(&["theta", "r"])).unwrap();
        assert!(back.u.is_empty());
    }
}
