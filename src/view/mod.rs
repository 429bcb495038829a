//! Seeing the motion: `animation.html` (one self-contained page, its script and styles
//! written here, [`PAGE_TEMPLATE`]) and strips as SVG.
//!
//! All kinematics happen here, in Rust, with the model's own forward kinematics: the page
//! receives each link's pose (position and unit quaternion) per frame, the contact points'
//! positions and the contact impulses, and only interpolates between frames. A plan keeps
//! every knot; a simulation is thinned to at most [`FRAMES_PER_SECOND`] frames per second of
//! motion (or [`MIN_FRAMES`] over the whole motion, whichever is more), keeping its first and
//! last step.

#![warn(missing_docs)]

mod body;
mod limits;
mod stl;
mod svg;

pub use body::{Body, Part, base_link, body, frames_only, package_root, resolve_mesh};
pub use limits::{
    MAX_ANGLE, MAX_DISTANCE_IN_SIZES, MAX_DURATION_S, MAX_TIME_IN_DURATIONS, Place, Undrawable,
    check_drawable, robot_size,
};
pub use svg::{StripLayout, strip_svg};

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use crate::contact::{FrictionBasis, Shape, Terrain, sin_cos_degrees, world_impulse};
use crate::discrete::Mechanics;
use crate::files::names::xml_escape;
use crate::model::{LinkId, link_pose};
use crate::transcription::ModelMechanics;

/// The page's script and styles, into which the scene's data is put.
pub const PAGE_TEMPLATE: &str = include_str!("page.html");

/// Text the head of every page vito writes holds (so that `vito view` replaces only its own
/// pages, see [`is_vito_page`]).
pub const PAGE_MARK: &str = "<meta name=\"generator\" content=\"vito animation page\">";
/// Text every strip vito writes begins with.
pub const SVG_MARK: &str = "<!-- vito strip: written by vito view -->";

/// The placeholder in [`PAGE_TEMPLATE`] that the scene's JSON replaces.
const DATA_MARK: &str = "/*VITO_DATA*/null";

/// Most frames per second of motion a simulation keeps.
pub const FRAMES_PER_SECOND: f64 = 60.0;
/// Frames a simulation keeps at least (when it has that many steps), so that a short, fast
/// motion still plays smoothly when slowed down.
pub const MIN_FRAMES: usize = 121;

/// Why a view could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// A file could not be written or read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The input cannot be drawn (named file, field and fix in the message).
    #[error("{0}")]
    Input(String),
    /// A value of the motion is beyond what a page draws ([`check_drawable`]).
    #[error("{0}; the motion was not drawn (a page draws values within these ranges)")]
    Undrawable(#[from] Undrawable),
}

/// What a motion is and whether it can be used: the legend's colour and word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Standing {
    /// A plan vito calls solved.
    Solved,
    /// A plan at Ipopt's optimum whose slack breaks the contact model (`relaxed_contact`).
    Relaxed,
    /// A plan that is not solved otherwise (a failure, a stop, a time limit, an unknown
    /// status).
    Unsolved,
    /// A forward simulation.
    Simulation,
}

impl Standing {
    /// The name the page's data and the strip use (`solved`, `relaxed`, `unsolved`,
    /// `simulation`).
    pub fn name(self) -> &'static str {
        match self {
            Standing::Solved => "solved",
            Standing::Relaxed => "relaxed",
            Standing::Unsolved => "unsolved",
            Standing::Simulation => "simulation",
        }
    }

    /// The legend's text colour: amber for a relaxed plan, red for another unsolved one.
    pub fn colour(self) -> Option<&'static str> {
        match self {
            Standing::Relaxed => Some("#b35c00"),
            Standing::Unsolved => Some("#c0392b"),
            Standing::Solved | Standing::Simulation => None,
        }
    }
}

/// One motion to draw: a plan or a simulation, by knot.
#[derive(Debug, Clone)]
pub struct Motion {
    /// Legend name (the result directory, or the problem's name).
    pub name: String,
    /// Legend detail ([`legend_of`]): a plan's verdict and objective, a simulation's
    /// integrator and duration.
    pub detail: String,
    /// What the motion is and whether it can be used.
    pub standing: Standing,
    /// Knot times (problem units).
    pub times: Vec<f64>,
    /// Configurations per knot.
    pub q: Vec<Vec<f64>>,
    /// Normal impulse per interval and contact (interval k sits on knot k).
    pub normal: Vec<Vec<f64>>,
    /// Friction impulses per interval, contact and direction ([+x, −x] or [+x, +y, −x, −y]).
    pub friction: Vec<Vec<Vec<f64>>>,
}

impl Motion {
    /// A simulation (thinned to at most [`FRAMES_PER_SECOND`]) rather than a plan (every
    /// knot).
    pub fn is_simulation(&self) -> bool {
        self.standing == Standing::Simulation
    }
}

/// The robot, its terrain and its contacts: what every motion of a page shares.
pub struct Scene {
    /// The robot with its contacts, in the problem's contact order.
    pub mechanics: ModelMechanics,
    /// The terrain.
    pub terrain: Terrain,
    /// Contact names.
    pub contacts: Vec<String>,
    /// The URDF (mesh files are looked for beside it).
    pub urdf: PathBuf,
    /// Length and time unit names.
    pub length_unit: String,
    /// Time unit name.
    pub time_unit: String,
    /// Title (the problem's name).
    pub title: String,
}

/// The knots a page keeps of `times` (a simulation's steps, `seconds` per unit): every one for
/// a plan; for a simulation, those at least T / (frames − 1) after the last kept, where
/// frames = max([`FRAMES_PER_SECOND`]·T + 1, [`MIN_FRAMES`]), and always the first and last.
pub fn frame_indices(times: &[f64], simulation: bool, seconds: f64) -> Vec<usize> {
    let n = times.len();
    if n == 0 {
        return Vec::new();
    }
    let span = times[n - 1] - times[0];
    let frames = ((FRAMES_PER_SECOND * span * seconds).ceil() as usize + 1).max(MIN_FRAMES);
    if !simulation || n <= frames || span.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return (0..n).collect();
    }
    let spacing = span / (frames - 1) as f64;
    let mut kept = vec![0];
    for (k, &t) in times.iter().enumerate().take(n - 1).skip(1) {
        if t - times[kept[kept.len() - 1]] >= spacing * (1.0 - 1e-9) {
            kept.push(k);
        }
    }
    kept.push(n - 1);
    kept
}

/// A link pose as position and unit quaternion (w, x, y, z) from a rotation matrix.
fn quaternion(r: &[[f64; 3]; 3]) -> [f64; 4] {
    let trace = r[0][0] + r[1][1] + r[2][2];
    let q = if trace > 0.0 {
        let s = (trace + 1.0).sqrt() * 2.0;
        [
            0.25 * s,
            (r[2][1] - r[1][2]) / s,
            (r[0][2] - r[2][0]) / s,
            (r[1][0] - r[0][1]) / s,
        ]
    } else if r[0][0] > r[1][1] && r[0][0] > r[2][2] {
        let s = (1.0 + r[0][0] - r[1][1] - r[2][2]).sqrt() * 2.0;
        [
            (r[2][1] - r[1][2]) / s,
            0.25 * s,
            (r[0][1] + r[1][0]) / s,
            (r[0][2] + r[2][0]) / s,
        ]
    } else if r[1][1] > r[2][2] {
        let s = (1.0 + r[1][1] - r[0][0] - r[2][2]).sqrt() * 2.0;
        [
            (r[0][2] - r[2][0]) / s,
            (r[0][1] + r[1][0]) / s,
            0.25 * s,
            (r[1][2] + r[2][1]) / s,
        ]
    } else {
        let s = (1.0 + r[2][2] - r[0][0] - r[1][1]).sqrt() * 2.0;
        [
            (r[1][0] - r[0][1]) / s,
            (r[0][2] + r[2][0]) / s,
            (r[1][2] + r[2][1]) / s,
            0.25 * s,
        ]
    };
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    let q = q.map(|v| v / norm);
    // One sign per rotation: w ≥ 0.
    if q[0] < 0.0 { q.map(|v| -v) } else { q }
}

/// The rotation matrix of a unit quaternion (w, x, y, z).
pub fn rotation_of(q: &[f64; 4]) -> [[f64; 3]; 3] {
    let [w, x, y, z] = *q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// One kept frame of a motion: every link's pose, the contact points, the impulses.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Time (problem units).
    pub time: f64,
    /// The knot it is.
    pub knot: usize,
    /// Per link: (position, quaternion w x y z), by the model's forward kinematics.
    pub links: Vec<([f64; 3], [f64; 4])>,
    /// Per contact: its point in the world.
    pub contacts: Vec<[f64; 3]>,
    /// Per contact: the impulse of the interval starting here as world vectors, its normal
    /// part then its friction part ([`crate::contact::world_impulse`], in the surface's frame
    /// at the contact point of the next knot, where it acts); zero on the last knot.
    pub impulses: Vec<[[f64; 3]; 2]>,
}

/// The frames of `motion` the page keeps, with the model's kinematics at each.
pub fn frames(scene: &Scene, motion: &Motion) -> Vec<Frame> {
    let model = scene.mechanics.model();
    let nc = scene.mechanics.num_contacts();
    let basis = FrictionBasis::for_robot(scene.mechanics.moves_in_xz_plane());
    frame_indices(
        &motion.times,
        motion.is_simulation(),
        crate::problem::units::seconds_per(&scene.time_unit),
    )
    .into_iter()
    .map(|k| {
        let q = &motion.q[k];
        let links = (0..model.link_names().len())
            .map(|l| {
                let (r, p) = link_pose(model, LinkId(l), q);
                (p, quaternion(&r))
            })
            .collect();
        let contacts = (0..nc)
            .map(|c| scene.mechanics.contact_position(c, q))
            .collect();
        let acts_at = motion.q.get(k + 1).unwrap_or(q);
        let impulses = (0..nc)
            .map(|c| {
                let normal = motion.normal.get(k).and_then(|n| n.get(c)).copied();
                let beta = motion.friction.get(k).and_then(|f| f.get(c));
                let finite = |x: f64| if x.is_finite() { x } else { 0.0 };
                let friction: Vec<f64> =
                    beta.map_or(vec![], |b| b.iter().map(|&x| finite(x)).collect());
                let p = scene.mechanics.contact_position(c, acts_at);
                let normal =
                    world_impulse(basis, &scene.terrain, p, finite(normal.unwrap_or(0.0)), &[]);
                let friction = world_impulse(basis, &scene.terrain, p, 0.0, &friction);
                [normal, friction].map(|v| v.map(finite))
            })
            .collect();
        Frame {
            time: motion.times[k],
            knot: k,
            links,
            contacts,
            impulses,
        }
    })
    .collect()
}

/// The robot's extent: the largest distance between link origins and contact points at the
/// first frame (at least 1e-6 of the unit).
fn extent(frame: &Frame) -> f64 {
    let points: Vec<[f64; 3]> = frame
        .links
        .iter()
        .map(|l| l.0)
        .chain(frame.contacts.iter().copied())
        .collect();
    let size = largest_distance(&points);
    if size.is_finite() {
        size.max(1e-6)
    } else {
        1.0
    }
}

/// The largest distance between two of `points` (0 for fewer than two).
fn largest_distance(points: &[[f64; 3]]) -> f64 {
    let mut size: f64 = 0.0;
    for a in points {
        for b in points {
            let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
            size = size.max(d);
        }
    }
    size
}

/// `x` rounded to `decimals` places (so that the JSON holds short numbers).
fn round(x: f64, decimals: i32) -> f64 {
    let f = 10f64.powi(decimals);
    let r = (x * f).round() / f;
    if r.is_finite() { r } else { 0.0 }
}

/// Decimal places for lengths: 1e-5 of the robot's extent.
fn length_decimals(size: f64) -> i32 {
    (5 - size.log10().floor() as i32).clamp(0, 12)
}

/// What a page and a strip draw, computed once.
pub struct Drawing {
    /// The robot's parts.
    pub body: Body,
    /// Per motion: its frames.
    pub frames: Vec<Vec<Frame>>,
    /// The robot's extent (length units).
    pub size: f64,
}

/// Kinematics and geometry of `motions` in `scene`.
pub fn drawing(scene: &Scene, motions: &[Motion]) -> Drawing {
    let frames: Vec<Vec<Frame>> = motions.iter().map(|m| frames(scene, m)).collect();
    let size = frames.first().and_then(|f| f.first()).map_or(1.0, extent);
    let body = body(scene.mechanics.model(), &scene.urdf, size);
    Drawing { body, frames, size }
}

/// The terrain's section z = H(x, y) over x in [x0, x1] at `y`, sampled finely enough for
/// the edges that cross it.
pub(crate) fn terrain_profile(terrain: &Terrain, x0: f64, x1: f64, y: f64) -> (Vec<f64>, Vec<f64>) {
    let mut xs: Vec<f64> = (0..=200)
        .map(|i| x0 + (x1 - x0) * i as f64 / 200.0)
        .collect();
    xs.extend(terrain.edges_along(0.0));
    xs.retain(|x| *x >= x0 && *x <= x1);
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let zs = xs.iter().map(|&x| terrain.height_at(x, y)).collect();
    (xs, zs)
}

/// The terrain a page draws over [x0, x1] × [y0, y1]: the grid lines along x and y and the
/// heights on them (one row per y). Two lines along y where the heights vary along x only
/// (bilinear interpolation then draws it exactly between them).
pub(crate) fn terrain_grid(
    terrain: &Terrain,
    [x0, x1, y0, y1]: [f64; 4],
) -> (Vec<f64>, Vec<f64>, Vec<Vec<f64>>) {
    let (xs, _) = terrain_profile(terrain, x0, x1, y0);
    let along_x_only = match terrain.shape() {
        Shape::Flat | Shape::Plane(_) => true,
        Shape::Profile(h) => sin_cos_degrees(h).0 == 0.0,
        Shape::General => false,
    };
    let mut ys: Vec<f64> = if along_x_only {
        vec![y0, y1]
    } else {
        let mut ys: Vec<f64> = (0..=80).map(|i| y0 + (y1 - y0) * i as f64 / 80.0).collect();
        ys.extend(terrain.edges_along(90.0));
        ys
    };
    ys.retain(|y| *y >= y0 && *y <= y1);
    ys.sort_by(f64::total_cmp);
    ys.dedup();
    let zs = ys
        .iter()
        .map(|&y| xs.iter().map(|&x| terrain.height_at(x, y)).collect())
        .collect();
    (xs, ys, zs)
}

/// The ground a page draws, [x0, x1, y0, y1]: the frames' links and contact points with a
/// margin of 3/4 of the robot's size around them.
fn ground_extent(drawing: &Drawing) -> [f64; 4] {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for frame in drawing.frames.iter().flatten() {
        for p in frame.links.iter().map(|l| &l.0).chain(&frame.contacts) {
            if p[0].is_finite() && p[1].is_finite() {
                x0 = x0.min(p[0]);
                x1 = x1.max(p[0]);
                y0 = y0.min(p[1]);
                y1 = y1.max(p[1]);
            }
        }
    }
    if x0 > x1 {
        (x0, x1, y0, y1) = (0.0, 0.0, 0.0, 0.0);
    }
    let margin = drawing.size * 0.75;
    [x0 - margin, x1 + margin, y0 - margin, y1 + margin]
}

/// The page's data: scene, parts and every motion's frames.
pub fn page_data(scene: &Scene, motions: &[Motion], drawing: &Drawing) -> Value {
    let d = length_decimals(drawing.size);
    let v3 = |p: &[f64; 3]| json!([round(p[0], d), round(p[1], d), round(p[2], d)]);
    let parts: Vec<Value> = drawing
        .body
        .parts
        .iter()
        .map(|p| {
            json!({
                "link": p.link,
                "color": p.color.map(|c| round(f64::from(c), 3)),
                "v": p.vertices.iter().flat_map(|v| v.map(|x| round(x, d))).collect::<Vec<_>>(),
                "f": p.triangles.iter().flatten().collect::<Vec<_>>(),
                "slide": p.slide.map(|(link, first)| json!([link, first])),
            })
        })
        .collect();
    let [x0, x1, y0, y1] = ground_extent(drawing);
    let (xs, ys, zs) = terrain_grid(&scene.terrain, [x0, x1, y0, y1]);
    let max_impulse = drawing
        .frames
        .iter()
        .flatten()
        .flat_map(|f| &f.impulses)
        .map(|[n, f]| {
            let v = [n[0] + f[0], n[1] + f[1], n[2] + f[2]];
            (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
        })
        .fold(0.0, f64::max);
    let tracks: Vec<Value> = motions
        .iter()
        .zip(&drawing.frames)
        .map(|(m, frames)| {
            json!({
                "name": m.name,
                "detail": m.detail,
                "standing": m.standing.name(),
                "knots": m.times.iter().map(|&t| round(t, 9)).collect::<Vec<_>>(),
                "simulation": m.is_simulation(),
                "t": frames.iter().map(|f| round(f.time, 9)).collect::<Vec<_>>(),
                "k": frames.iter().map(|f| f.knot).collect::<Vec<_>>(),
                "poses": frames.iter().map(|f| f.links.iter().flat_map(|(p, q)| {
                    [round(p[0], d), round(p[1], d), round(p[2], d),
                     round(q[0], 6), round(q[1], 6), round(q[2], 6), round(q[3], 6)]
                }).collect::<Vec<_>>()).collect::<Vec<_>>(),
                "contacts": frames.iter().map(|f| f.contacts.iter().map(v3).collect::<Vec<_>>()).collect::<Vec<_>>(),
                "impulses": frames.iter().map(|f| f.impulses.iter().map(|v| {
                    let s = if max_impulse > 0.0 { 1.0 / max_impulse } else { 0.0 };
                    v.iter().flatten().map(|x| round(x * s, 4)).collect::<Vec<_>>()
                }).collect::<Vec<_>>()).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({
        "title": scene.title,
        "length_unit": scene.length_unit,
        "time_unit": scene.time_unit,
        "seconds_per_unit": crate::problem::units::seconds_per(&scene.time_unit),
        "size": drawing.size,
        "links": scene.mechanics.model().link_names(),
        "base": base_link(scene.mechanics.model()),
        "contacts": scene.contacts,
        "parts": parts,
        "terrain": {
            "x": xs.iter().map(|&x| round(x, d)).collect::<Vec<_>>(),
            "y": ys.iter().map(|&y| round(y, d)).collect::<Vec<_>>(),
            "z": zs.iter().map(|row| row.iter().map(|&z| round(z, d)).collect::<Vec<_>>()).collect::<Vec<_>>(),
        },
        "max_impulse": max_impulse,
        "warnings": drawing.body.warnings,
        "tracks": tracks,
    })
}

/// `value` as JSON that can stand inside an HTML `<script>` element whatever its strings
/// hold: `<`, `>` and `&` are written `\u003c`, `\u003e`, `\u0026` (so no `</script>`, `<!--`
/// or `<script` can change the HTML parser's state), U+2028 and U+2029 as `\u2028`, `\u2029`
/// (line terminators in older JavaScript). The JSON means the same: these characters occur
/// only inside strings, where the escapes stand for them.
pub fn script_json(value: &Value) -> String {
    let text = value.to_string();
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '<' => out.push_str("\\u003c"),
            '>' => out.push_str("\\u003e"),
            '&' => out.push_str("\\u0026"),
            '\u{2028}' => out.push_str("\\u2028"),
            '\u{2029}' => out.push_str("\\u2029"),
            c => out.push(c),
        }
    }
    out
}

/// The whole page of `motions`.
pub fn page(scene: &Scene, motions: &[Motion], drawing: &Drawing) -> String {
    let data = script_json(&page_data(scene, motions, drawing));
    PAGE_TEMPLATE.replacen(DATA_MARK, &data, 1)
}

/// How many bytes of an existing file [`is_vito_page`] and [`is_vito_strip`] look at.
pub const MARK_WINDOW: usize = 1024;

/// The head of pages written before [`PAGE_MARK`] existed: their first lines, exactly.
const LEGACY_PAGE_HEAD: &str = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
     <meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; script-src \
     'unsafe-inline'; style-src 'unsafe-inline'; img-src data:\">\n<title>vito animation</title>\n";
/// The start of strips written before [`SVG_MARK`] led them, and their second line's start.
const LEGACY_STRIP: (&str, &str) = (
    "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"",
    "\n<!-- vito strip --><rect ",
);

fn contains(haystack: &[u8], needle: &str) -> bool {
    haystack
        .windows(needle.len())
        .any(|w| w == needle.as_bytes())
}

/// Whether `head`, the start of an existing file, shows a page vito wrote: `<!DOCTYPE html>`
/// and [`PAGE_MARK`] within the first [`MARK_WINDOW`] bytes (or the exact head of an older
/// vito page). A user's file that merely mentions vito's markers elsewhere is not one.
pub fn is_vito_page(head: &[u8]) -> bool {
    let window = &head[..head.len().min(MARK_WINDOW)];
    (window.starts_with(b"<!DOCTYPE html>\n") && contains(window, PAGE_MARK))
        || window.starts_with(LEGACY_PAGE_HEAD.as_bytes())
}

/// Whether `head`, the start of an existing file, shows a strip vito wrote: it begins with
/// [`SVG_MARK`] (or has an older vito strip's first two lines).
pub fn is_vito_strip(head: &[u8]) -> bool {
    let window = &head[..head.len().min(MARK_WINDOW)];
    window.starts_with(SVG_MARK.as_bytes())
        || (window.starts_with(LEGACY_STRIP.0.as_bytes()) && {
            let line_end = window.iter().position(|&b| b == b'\n').unwrap_or(0);
            window[line_end..].starts_with(LEGACY_STRIP.1.as_bytes())
        })
}

/// Writes `path` atomically ([`crate::files::output::write_atomic`]: a temporary file created
/// exclusively beside it, never through a link, renamed over it).
pub fn write_atomically(path: &Path, text: &str) -> Result<(), ViewError> {
    crate::files::output::write_atomic(path, text.as_bytes()).map_err(|source| ViewError::Io {
        path: path.to_owned(),
        source,
    })
}

/// The scene of a loaded problem.
pub fn scene(problem: &crate::problem::LoadedProblem) -> Result<Scene, ViewError> {
    let mechanics = ModelMechanics::load(&problem.spec)
        .map_err(|e| ViewError::Input(format!("{}: {e}", problem.file.display())))?;
    Ok(Scene {
        mechanics,
        terrain: problem.spec.terrain.clone(),
        contacts: problem
            .spec
            .contacts
            .iter()
            .map(|c| c.name.clone())
            .collect(),
        urdf: problem.spec.robot.urdf.clone(),
        length_unit: problem.units.length.clone(),
        time_unit: problem.units.time.clone(),
        title: problem.spec.name.clone(),
    })
}

/// A motion from a trajectory file's view of a solution or simulation, with its legend.
pub fn motion(
    trajectory: &crate::files::trajectory_csv::Trajectory<'_>,
    name: &str,
    legend: Legend,
) -> Motion {
    Motion {
        name: name.to_owned(),
        detail: legend.detail,
        standing: legend.standing,
        times: trajectory.times.to_vec(),
        q: trajectory.q.to_vec(),
        normal: trajectory.normal_impulse.to_vec(),
        friction: trajectory.friction_impulse.to_vec(),
    }
}

/// A motion's legend: its detail text and standing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Legend {
    /// The text after the motion's name.
    pub detail: String,
    /// What the motion is and whether it can be used.
    pub standing: Standing,
}

/// Whether a `summary.json` is a simulation's (`vito simulate`): it says so in `kind`, or,
/// written without one, it has steps and no status. A solve's summary also names its
/// integrator, so `integrator` alone does not tell.
fn is_simulation_summary(summary: &Value) -> bool {
    match summary.get("kind").and_then(Value::as_str) {
        Some(kind) => kind == "simulation",
        None => summary.get("status").is_none() && summary.get("steps").is_some(),
    }
}

/// The legend of a result from its `summary.json`. A plan: `plan`, its verdict (a relaxed or
/// otherwise unsolved one says `not solved` and why) and objective. A simulation: its
/// integrator, duration and steps.
pub fn legend_of(summary: &Value) -> Legend {
    let number = |key: &str| summary.get(key).and_then(Value::as_f64);
    if is_simulation_summary(summary) {
        let integrator = summary
            .get("integrator")
            .and_then(Value::as_str)
            .unwrap_or("unknown integrator");
        let unit = summary["units"]["time"].as_str().unwrap_or("s");
        let mut detail = format!("simulation ({integrator})");
        if let Some(d) = number("duration") {
            detail.push_str(&format!(", {d} {unit}"));
        }
        if let Some(steps) = summary.get("steps").and_then(Value::as_u64) {
            detail.push_str(&format!(", {steps} steps"));
        }
        return Legend {
            detail,
            standing: Standing::Simulation,
        };
    }
    use crate::transcription::SolveVerdict;
    let verdict = SolveVerdict::of_summary(summary);
    let (standing, word) = match verdict {
        Some(SolveVerdict::Solved(_)) => (Standing::Solved, verdict.map(SolveVerdict::name)),
        Some(SolveVerdict::RelaxedContact) => (Standing::Relaxed, verdict.map(SolveVerdict::name)),
        Some(SolveVerdict::NotSolved(_)) => (Standing::Unsolved, verdict.map(SolveVerdict::name)),
        None => (Standing::Unsolved, None),
    };
    // Only vito's own words: a status it does not know is not repeated.
    let word = word.unwrap_or("unknown status");
    let mut detail = match standing {
        Standing::Solved => format!("plan, {word}"),
        Standing::Relaxed => match (number("max_slack"), number("slack_tolerance")) {
            (Some(s), Some(t)) => format!(
                "plan, NOT SOLVED: {word} (slack {s:.2e} above tolerance {t:e}: the contact model is broken)"
            ),
            _ => format!("plan, NOT SOLVED: {word} (the contact model is broken)"),
        },
        _ => format!("plan, NOT SOLVED: {word}"),
    };
    if let Some(o) = number("objective") {
        detail.push_str(&format!(", objective {o:.6e}"));
    }
    Legend { detail, standing }
}

/// Writes `animation.html` into `dir` for one trajectory (what `vito solve`, `vito simulate`
/// and each sweep run call); returns the drawing's warnings.
pub fn write_animation(
    dir: &Path,
    problem: &crate::problem::LoadedProblem,
    trajectory: &crate::files::trajectory_csv::Trajectory<'_>,
    summary: &Value,
) -> Result<Vec<String>, ViewError> {
    let (page, warnings) = match animation_page(problem, trajectory, summary) {
        Ok(drawn) => drawn,
        // The results are written all the same; the page says why it shows no motion.
        Err(e @ ViewError::Undrawable(_)) => (not_drawn_page(&e.to_string()), vec![e.to_string()]),
        Err(e) => return Err(e),
    };
    write_atomically(&dir.join("animation.html"), &page)?;
    Ok(warnings)
}

/// The page written in place of a motion that cannot be drawn: why, in words.
fn not_drawn_page(why: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>vito: motion not drawn</title>\
         </head><body><p>vito did not draw this motion: {}</p></body></html>\n",
        crate::files::names::xml_escape(why)
    )
}

/// The self-contained page of one trajectory (what `animation.html` holds) and the
/// drawing's warnings.
pub fn animation_page(
    problem: &crate::problem::LoadedProblem,
    trajectory: &crate::files::trajectory_csv::Trajectory<'_>,
    summary: &Value,
) -> Result<(String, Vec<String>), ViewError> {
    let scene = scene(problem)?;
    let motions = [motion(trajectory, &problem.spec.name, legend_of(summary))];
    let drawing = drawing(&scene, &motions);
    check_drawable(&scene, &motions, &drawing).map_err(|(_, e)| e)?;
    Ok((page(&scene, &motions, &drawing), drawing.body.warnings))
}

#[cfg(test)]
mod tests;
