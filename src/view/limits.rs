//! What a page or a strip draws is checked before it is drawn: every time, coordinate, link
//! and contact position and terrain height finite and within a sane range of the robot's
//! size. Beyond it a page would never finish loading (its grid has a line every quarter of
//! the robot's size across the motion) and poses would be lost to rounding.

use super::{Drawing, Motion, Scene};
use crate::files::trajectory_csv::number;
use crate::model::{CoordinateKind, frames_only};

/// Farthest a drawn point (a link, a contact point, the terrain under the motion) may be from
/// the origin, in robot sizes ([`robot_size`]).
pub const MAX_DISTANCE_IN_SIZES: f64 = 1e4;
/// Largest angle a coordinate may hold (rad, about 160,000 turns).
pub const MAX_ANGLE: f64 = 1e6;
/// Largest |time| in durations of the motion (beyond it, knot times run together).
pub const MAX_TIME_IN_DURATIONS: f64 = 1e6;
/// Longest motion drawn (seconds, about 32 years).
pub const MAX_DURATION_S: f64 = 1e9;

/// Where a refused value is.
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    /// A cell of the trajectory: its row (the header is row 1, as the CSV reader counts) and
    /// column.
    Cell {
        /// The row.
        row: usize,
        /// The column's name (without its unit).
        column: String,
    },
    /// A point the kinematics place at a row's configuration.
    Point {
        /// The row.
        row: usize,
        /// `link `name`` or `contact `name``.
        point: String,
        /// `x`, `y` or `z`.
        axis: char,
    },
    /// The terrain's height at (`x`, `y`).
    Terrain {
        /// Where along x.
        x: f64,
        /// Where along y.
        y: f64,
    },
}

/// A value a page or strip will not draw: where it is, the value, and the range it leaves.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {} {unit} is beyond {limit}", place_text(.place, .unit), number(*.value))]
pub struct Undrawable {
    /// Where it is.
    pub place: Place,
    /// The value.
    pub value: f64,
    /// Its unit.
    pub unit: String,
    /// The range it leaves, in words.
    pub limit: String,
}

fn place_text(place: &Place, unit: &str) -> String {
    match place {
        Place::Cell { row, column } => format!("row {row}, column `{column}`"),
        Place::Point { row, point, axis } => format!("row {row}: {point} at {axis}"),
        Place::Terrain { x, y } => format!(
            "the terrain's height at x = {}, y = {} {unit}",
            short(*x),
            short(*y)
        ),
    }
}

/// `x` to three significant digits, as a limit is given in words.
fn short(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || (1e-3..1e6).contains(&a) {
        let decimals = (2 - a.log10().floor() as i32).max(0) as usize;
        let text = format!("{x:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_owned()
        } else {
            text
        }
    } else {
        format!("{x:.2e}")
    }
}

/// Whether |x| ≤ bound (false for NaN).
fn within(x: f64, bound: f64) -> bool {
    x.abs() <= bound
}

/// The trajectory row of knot `k` (the header is row 1).
fn row(k: usize) -> usize {
    k + 2
}

/// The robot's size for these checks: the largest distance between its bodies' origins and
/// contact points in the first drawn pose (frames such as the world link left out, so that
/// a robot far from the origin is not that large); the drawing's size where the robot is one
/// body without contacts.
pub fn robot_size(scene: &Scene, drawing: &Drawing) -> f64 {
    let Some(first) = drawing.frames.first().and_then(|f| f.first()) else {
        return drawing.size;
    };
    let frames = frames_only(scene.mechanics.model());
    let points: Vec<[f64; 3]> = first
        .links
        .iter()
        .zip(&frames)
        .filter(|(_, frame)| !**frame)
        .map(|(link, _)| link.0)
        .chain(first.contacts.iter().copied())
        .collect();
    let size = super::largest_distance(&points);
    if size.is_finite() && size > 0.0 {
        size
    } else {
        drawing.size
    }
}

/// Checks what a page or strip of `motions` (`drawing` computed from them) draws: the times,
/// the coordinates, every drawn link origin and contact point, and the terrain under the
/// motion. Returns the first value out of range, with the index of its motion (None for the
/// terrain, which the problem gives).
pub fn check_drawable(
    scene: &Scene,
    motions: &[Motion],
    drawing: &Drawing,
) -> Result<(), (Option<usize>, Undrawable)> {
    let size = robot_size(scene, drawing);
    let length = &scene.length_unit;
    let far = MAX_DISTANCE_IN_SIZES * size;
    let far_text = format!(
        "±{} {length} ({} × the robot's size, {} {length})",
        short(far),
        short(MAX_DISTANCE_IN_SIZES),
        short(size)
    );
    for (i, (motion, frames)) in motions.iter().zip(&drawing.frames).enumerate() {
        check_motion(scene, motion, frames, far, &far_text).map_err(|e| (Some(i), e))?;
    }
    let [x0, x1, y0, y1] = super::ground_extent(drawing);
    let (xs, ys, zs) = super::terrain_grid(&scene.terrain, [x0, x1, y0, y1]);
    let points = ys
        .iter()
        .zip(&zs)
        .flat_map(|(&y, row)| xs.iter().zip(row).map(move |(&x, &z)| (x, y, z)));
    for (x, y, z) in points {
        if !within(z, far) {
            return Err((
                None,
                Undrawable {
                    place: Place::Terrain { x, y },
                    value: z,
                    unit: length.clone(),
                    limit: far_text,
                },
            ));
        }
    }
    Ok(())
}

fn check_motion(
    scene: &Scene,
    motion: &Motion,
    frames: &[super::Frame],
    far: f64,
    far_text: &str,
) -> Result<(), Undrawable> {
    let model = scene.mechanics.model();
    let (length, time) = (&scene.length_unit, &scene.time_unit);
    let seconds = crate::problem::units::seconds_per(time);
    let refuse = |place: Place, value: f64, unit: &str, limit: String| Undrawable {
        place,
        value,
        unit: unit.to_owned(),
        limit,
    };
    let cell = |k: usize, column: &str| Place::Cell {
        row: row(k),
        column: column.to_owned(),
    };
    // Times: the reader has them finite and increasing.
    if let (Some(&first), Some(&last)) = (motion.times.first(), motion.times.last()) {
        let duration = last - first;
        if !within(duration * seconds, MAX_DURATION_S) {
            return Err(refuse(
                cell(motion.times.len() - 1, "time"),
                last,
                time,
                format!(
                    "a motion of {} s from the first row's {} {time}",
                    short(MAX_DURATION_S),
                    number(first)
                ),
            ));
        }
        let latest = MAX_TIME_IN_DURATIONS * duration;
        if let Some((k, &t)) = motion
            .times
            .iter()
            .enumerate()
            .find(|(_, t)| !within(**t, latest))
        {
            return Err(refuse(
                cell(k, "time"),
                t,
                time,
                format!(
                    "±{} {time} ({} × the motion's duration, {} {time}): its times would run \
                     together",
                    short(latest),
                    short(MAX_TIME_IN_DURATIONS),
                    short(duration)
                ),
            ));
        }
    }
    let names = model.coordinate_names();
    let kinds = model.coordinate_kinds();
    for (k, q) in motion.q.iter().enumerate() {
        for ((&value, name), kind) in q.iter().zip(names).zip(&kinds) {
            let (bound, unit, limit) = match kind {
                CoordinateKind::Linear => (far, length.as_str(), far_text.to_owned()),
                CoordinateKind::Angular => (MAX_ANGLE, "rad", format!("±{} rad", short(MAX_ANGLE))),
            };
            if !within(value, bound) {
                return Err(refuse(cell(k, name), value, unit, limit));
            }
        }
    }
    let links = model.link_names();
    for frame in frames {
        let points = frame
            .links
            .iter()
            .zip(links)
            .map(|(l, name)| (l.0, format!("link `{name}`")))
            .chain(
                frame
                    .contacts
                    .iter()
                    .zip(&scene.contacts)
                    .map(|(&p, name)| (p, format!("contact `{name}`"))),
            );
        for (p, point) in points {
            if let Some(axis) = (0..3).find(|&a| !within(p[a], far)) {
                return Err(refuse(
                    Place::Point {
                        row: row(frame.knot),
                        point,
                        axis: ['x', 'y', 'z'][axis],
                    },
                    p[axis],
                    length,
                    far_text.to_owned(),
                ));
            }
        }
    }
    Ok(())
}
