//! Frame terms: a quantity of a point on the robot (a contact, or a point fixed on a URDF
//! link) at chosen knots, as a cost ½ w (f_k − target)² summed over the knots, as rows
//! lower ≤ f_k ≤ upper, or both. One file per quantity: its `type` name, what it reads (a
//! knot's configuration, or an interval's two configurations and step) and its value over
//! [`Scalar`], so that the transcription differentiates it exactly by forward AD.
//!
//! To add a quantity: a file here with a type implementing [`FrameFunction`], and its line
//! in the `frame_quantities!` list below, which generates [`FrameQuantity`] and its dispatch.
//! The `[[frame]]` entry, knot selection, cost and rows are shared ([`check_frames`]).
//!
//! Contact windows and gaits (`gait.rs`) expand into clearance terms of this kind plus the
//! intervals whose normal impulse is held at zero.

mod clearance;
mod gait;
mod knots;
mod orientation;
mod position;
mod velocity;

pub use clearance::Clearance;
pub(crate) use gait::check_windows;
pub use gait::{ContactWindowEntry, GaitEntry, Windows};
pub use knots::{KnotChoice, nominal_times};
pub use orientation::Orientation;
pub use position::Position;
pub use velocity::Velocity;

use serde::Deserialize;

use super::schema::{KnotsName, ProblemFile};
use super::validate::context::Context;
use super::validate::values::{finite, nonnegative};
use super::{ContactSpec, ProblemError, RobotInfo, TimeSteps};
use crate::autodiff::Scalar;
use crate::contact::Terrain;
use crate::discrete::Mechanics;

/// `[[frame]]`: one frame term as the problem file spells it.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameEntry {
    /// The quantity: `"position"`, `"clearance"`, `"orientation"` or `"velocity"`.
    #[serde(rename = "type")]
    pub kind: String,
    /// A contact of the problem (its name), or …
    pub contact: Option<String>,
    /// … a URDF link, with `point` in its frame (default its origin).
    pub link: Option<String>,
    /// The point in the link's frame [length].
    #[serde(default, deserialize_with = "crate::problem::schema::exact_option")]
    pub point: Option<[f64; 3]>,
    /// `"x"`, `"y"`, `"z"` (position, velocity) or `"roll"`, `"pitch"`, `"yaw"` (orientation).
    pub axis: Option<String>,
    /// `"all"` (default), `"interior"`, `"first"`, `"final"`, or a list of 0-based knots.
    pub knots: Option<KnotsName>,
    /// A time window [t0, t1] in seconds instead of `knots`: the knots whose nominal time
    /// lies in it.
    #[serde(default, deserialize_with = "crate::problem::schema::exact_option")]
    pub window: Option<[f64; 2]>,
    /// The cost's target value (with `weight`).
    pub target: Option<f64>,
    /// The cost's weight w ≥ 0 (with `target`).
    pub weight: Option<f64>,
    /// Lower bound of a row per knot.
    pub lower: Option<f64>,
    /// Upper bound of a row per knot.
    pub upper: Option<f64>,
}

/// A point on the robot a term follows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FramePoint {
    /// Contact i of the problem (a sphere's lowest point, as its distance row sees it).
    Contact(usize),
    /// A point fixed in a link's frame.
    Link {
        /// The link's index in the model's link order (`RobotInfo::links`).
        link: usize,
        /// The point in the link frame [length].
        point: [f64; 3],
    },
}

impl FramePoint {
    /// Its world position at q; zeros when the mechanics have no link poses (refused before
    /// a transcription is built, `Transcription::new`).
    pub fn position<D: Scalar, M: Mechanics>(&self, mech: &M, q: &[D]) -> [D; 3] {
        match *self {
            FramePoint::Contact(i) => mech.contact_position(i, q),
            FramePoint::Link { link, point } => match mech.link_pose(link, q) {
                Some((r, o)) => {
                    let mut p = o;
                    for (a, row) in p.iter_mut().zip(&r) {
                        for (rc, pc) in row.iter().zip(point) {
                            *a += *rc * D::from(pc);
                        }
                    }
                    p
                }
                None => [D::from(0.0); 3],
            },
        }
    }

    /// Whether it needs the mechanics' link poses.
    pub fn needs_link_poses(&self) -> bool {
        matches!(self, FramePoint::Link { .. })
    }
}

/// What a quantity reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameReads {
    /// z = q_k (n values) at knot k.
    Knot,
    /// z = [q_{k−1}; q_k; h_{k−1}] (2n + 1 values): the interval ending at knot k ≥ 1.
    IntervalEndingAt,
}

/// One quantity of a point: its name, what it reads, and its value.
pub trait FrameFunction: Sized {
    /// Its `type` in `[[frame]]`.
    const NAME: &'static str;
    /// The variables it reads.
    const READS: FrameReads;
    /// The `axis` names it takes (empty: no `axis`).
    const AXES: &'static [&'static str];
    /// Whether a contact names its link (orientation) rather than its point.
    const OF_LINK: bool = false;
    /// The quantity on `point`, along axis `AXES[axis]` (0 without axes).
    fn new(point: FramePoint, axis: usize) -> Self;
    /// Its value on z (layout from [`FrameFunction::READS`]; n coordinates).
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, terrain: &Terrain, n: usize, z: &[D]) -> D;
    /// The point it follows.
    fn point(&self) -> FramePoint;
}

/// The list of quantities: `Variant in module`.
macro_rules! frame_quantities {
    ($($variant:ident in $module:ident),* $(,)?) => {
        /// One checked quantity, chosen by `type`.
        #[derive(Debug, Clone, PartialEq)]
        pub enum FrameQuantity {
            $(
                #[allow(missing_docs)]
                $variant($variant),
            )*
        }

        /// The `type` names, in list order.
        pub const FRAME_TYPES: &[&str] = &[$(<$variant as FrameFunction>::NAME),*];

        impl FrameQuantity {
            /// The quantity of type `kind` on `point` (`None`: no such type).
            fn build(
                kind: &str,
                at: &FrameCheck,
                entry: &FrameEntry,
            ) -> Option<Result<FrameQuantity, ProblemError>> {
                $(if kind == <$variant as FrameFunction>::NAME {
                    return Some(at.quantity::<$variant>(entry).map(FrameQuantity::$variant));
                })*
                None
            }
            /// See [`FrameFunction::NAME`].
            pub fn name(&self) -> &'static str {
                match self {
                    $(FrameQuantity::$variant(_) => <$variant as FrameFunction>::NAME,)*
                }
            }
            /// See [`FrameFunction::READS`].
            pub fn reads(&self) -> FrameReads {
                match self {
                    $(FrameQuantity::$variant(_) => <$variant as FrameFunction>::READS,)*
                }
            }
            /// See [`FrameFunction::point`].
            pub fn point(&self) -> FramePoint {
                match self {
                    $(FrameQuantity::$variant(f) => f.point(),)*
                }
            }
            /// See [`FrameFunction::value`].
            pub fn value<D: Scalar, M: Mechanics>(
                &self,
                mech: &M,
                terrain: &Terrain,
                n: usize,
                z: &[D],
            ) -> D {
                match self {
                    $(FrameQuantity::$variant(f) => f.value(mech, terrain, n, z),)*
                }
            }
        }
    };
}

frame_quantities! {
    Position in position,
    Clearance in clearance,
    Orientation in orientation,
    Velocity in velocity,
}

/// One checked frame term: its quantity at `knots`, a cost (weight > 0) and/or rows.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameTerm {
    /// The quantity.
    pub quantity: FrameQuantity,
    /// How rows and messages name it, e.g. `frame[2] clearance front_left_foot`.
    pub label: String,
    /// The knots it applies at (0-based; a velocity's knot k ≥ 1 reads interval k − 1).
    pub knots: Vec<usize>,
    /// The cost's target.
    pub target: f64,
    /// The cost's weight (0: no cost).
    pub weight: f64,
    /// Row bounds (both infinite: no rows).
    pub lower: f64,
    /// Row bounds (both infinite: no rows).
    pub upper: f64,
}

impl FrameTerm {
    /// Whether it adds a cost.
    pub fn has_cost(&self) -> bool {
        self.weight > 0.0
    }

    /// Whether it adds one row per knot.
    pub fn has_rows(&self) -> bool {
        self.lower > f64::NEG_INFINITY || self.upper < f64::INFINITY
    }

    /// The label of its row at knot k.
    pub fn row_label(&self, k: usize) -> String {
        format!("{} at knot {k}", self.label)
    }

    /// Its name among the objective's terms: `frame_<type>`.
    pub fn cost_name(&self) -> &'static str {
        match self.quantity.name() {
            "position" => "frame_position",
            "clearance" => "frame_clearance",
            "orientation" => "frame_orientation",
            _ => "frame_velocity",
        }
    }
}

/// What every `[[frame]]`, `[[contact_window]]` and `[gait]` check shares: the robot's and
/// the problem's names and the knots.
pub(crate) struct FrameScope<'a> {
    ctx: &'a Context,
    robot: &'a RobotInfo,
    contacts: &'a [ContactSpec],
    knots: usize,
    /// The knots' nominal times.
    times: Vec<f64>,
}

impl<'a> FrameScope<'a> {
    /// The scope of a problem with these contacts, knots and steps.
    pub(crate) fn new(
        ctx: &'a Context,
        robot: &'a RobotInfo,
        contacts: &'a [ContactSpec],
        knots: usize,
        time_steps: &TimeSteps,
    ) -> Self {
        FrameScope {
            ctx,
            robot,
            contacts,
            knots,
            times: nominal_times(knots, time_steps),
        }
    }

    /// The check of entry `entry` (as errors name it).
    pub(crate) fn check(&self, entry: String) -> FrameCheck<'_> {
        FrameCheck {
            ctx: self.ctx,
            entry,
            robot: self.robot,
            contacts: self.contacts,
            knots: self.knots,
            times: &self.times,
        }
    }
}

/// What a term's check needs: where it is, the robot's and the problem's names, the knots.
pub struct FrameCheck<'a> {
    ctx: &'a Context,
    entry: String,
    robot: &'a RobotInfo,
    contacts: &'a [ContactSpec],
    knots: usize,
    times: &'a [f64],
}

impl FrameCheck<'_> {
    /// `entry.key`.
    pub(crate) fn field(&self, key: &str) -> String {
        format!("{}.{key}", self.entry)
    }

    /// The error for `entry.key`.
    pub(crate) fn invalid(&self, key: &str, message: impl Into<String>) -> ProblemError {
        self.ctx.invalid(&self.field(key), message)
    }

    /// The index of contact `name`.
    pub(crate) fn contact(&self, key: &str, name: &str) -> Result<usize, ProblemError> {
        self.contacts
            .iter()
            .position(|c| c.name == name)
            .ok_or_else(|| {
                let names: Vec<String> = self.contacts.iter().map(|c| c.name.clone()).collect();
                self.ctx
                    .unknown_name(&self.field(key), "contact", name, &names)
            })
    }

    fn link(&self, key: &str, name: &str) -> Result<usize, ProblemError> {
        self.robot
            .links
            .iter()
            .position(|l| l == name)
            .ok_or_else(|| {
                self.ctx
                    .unknown_name(&self.field(key), "link", name, &self.robot.links)
            })
    }

    /// The knots `knots` or `window` choose.
    pub(crate) fn knots(&self, choice: KnotChoice) -> Result<Vec<usize>, ProblemError> {
        choice.resolve(self, self.knots, self.times)
    }

    fn quantity<F: FrameFunction>(&self, entry: &FrameEntry) -> Result<F, ProblemError> {
        let point = match (&entry.contact, &entry.link) {
            (Some(_), Some(_)) => {
                return Err(self.invalid("link", "give `contact` or `link`, not both"));
            }
            (None, None) => {
                return Err(self.invalid(
                    "contact",
                    "name the point: `contact = \"NAME\"` (a contact of the problem) or \
                     `link = \"NAME\"` with `point = [x, y, z]` in its frame",
                ));
            }
            (Some(name), None) => {
                if entry.point.is_some() {
                    return Err(self.invalid(
                        "point",
                        "a contact's point is its own; `point` goes with `link`",
                    ));
                }
                let i = self.contact("contact", name)?;
                if F::OF_LINK {
                    let link = self.link("contact", &self.contacts[i].link)?;
                    FramePoint::Link {
                        link,
                        point: [0.0; 3],
                    }
                } else {
                    FramePoint::Contact(i)
                }
            }
            (None, Some(name)) => {
                let link = self.link("link", name)?;
                let point = entry.point.unwrap_or([0.0; 3]);
                for (i, &v) in point.iter().enumerate() {
                    finite(self.ctx, &self.field(&format!("point[{i}]")), v)?;
                }
                FramePoint::Link { link, point }
            }
        };
        let axis = match (&entry.axis, F::AXES.is_empty()) {
            (None, true) => 0,
            (Some(_), true) => {
                return Err(self.invalid(
                    "axis",
                    format!("a `{}` term has no axis; remove `axis`", F::NAME),
                ));
            }
            (None, false) => {
                return Err(
                    self.invalid("axis", format!("give `axis`, one of {}", quoted(F::AXES)))
                );
            }
            (Some(a), false) => F::AXES.iter().position(|x| x == a).ok_or_else(|| {
                let valid: Vec<String> = F::AXES.iter().map(|s| s.to_string()).collect();
                self.ctx
                    .unknown_name(&self.field("axis"), "axis", a, &valid)
            })?,
        };
        Ok(F::new(point, axis))
    }
}

/// `"a", "b"` for messages.
fn quoted(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `[[frame]]`: every entry checked, in file order.
pub(crate) fn check_frames(
    scope: &FrameScope,
    raw: &ProblemFile,
) -> Result<Vec<FrameTerm>, ProblemError> {
    raw.frame
        .iter()
        .enumerate()
        .map(|(i, entry)| check_frame(&scope.check(format!("frame[{i}]")), entry))
        .collect()
}

fn check_frame(at: &FrameCheck, entry: &FrameEntry) -> Result<FrameTerm, ProblemError> {
    let quantity = FrameQuantity::build(&entry.kind, at, entry).unwrap_or_else(|| {
        let valid: Vec<String> = FRAME_TYPES.iter().map(|s| s.to_string()).collect();
        Err(at
            .ctx
            .unknown_name(&at.field("type"), "frame term type", &entry.kind, &valid))
    })?;
    let choice = match (&entry.knots, entry.window) {
        (Some(_), Some(_)) => {
            return Err(at.invalid("window", "give `knots` or `window`, not both"));
        }
        (Some(k), None) => KnotChoice::Knots("knots", k.clone()),
        (None, Some(w)) => KnotChoice::Window("window", w),
        (None, None) => KnotChoice::Knots("knots", KnotsName::Named("all".into())),
    };
    let mut knots = at.knots(choice)?;
    if quantity.reads() == FrameReads::IntervalEndingAt {
        // A velocity at knot k is the difference over the interval ending there.
        if entry.knots.is_none() && entry.window.is_none()
            || matches!(&entry.knots, Some(KnotsName::Named(s)) if s == "all")
        {
            knots.retain(|&k| k > 0);
        }
        if knots.first() == Some(&0) {
            return Err(at.invalid(
                if entry.window.is_some() {
                    "window"
                } else {
                    "knots"
                },
                "a velocity at knot k is the difference over the interval ending at k, so \
                 knot 0 has none; start at knot 1",
            ));
        }
    }
    let (target, weight) = match (entry.target, entry.weight) {
        (Some(t), Some(w)) => (
            finite(at.ctx, &at.field("target"), t)?,
            nonnegative(at.ctx, &at.field("weight"), w)?,
        ),
        (None, None) => (0.0, 0.0),
        (Some(_), None) => return Err(at.invalid("weight", "a `target` needs a `weight` ≥ 0")),
        (None, Some(_)) => return Err(at.invalid("target", "a `weight` needs a `target`")),
    };
    let lower = match entry.lower {
        Some(v) => finite(at.ctx, &at.field("lower"), v)?,
        None => f64::NEG_INFINITY,
    };
    let upper = match entry.upper {
        Some(v) => finite(at.ctx, &at.field("upper"), v)?,
        None => f64::INFINITY,
    };
    if lower > upper {
        return Err(at.invalid(
            "upper",
            format!("lower {lower} is above upper {upper}: nothing satisfies it"),
        ));
    }
    let term = FrameTerm {
        label: label(at, entry, &quantity),
        quantity,
        knots,
        target,
        weight,
        lower,
        upper,
    };
    if !term.has_cost() && !term.has_rows() {
        return Err(at.invalid(
            "weight",
            "the term asks for nothing: give `target` and `weight` > 0 (a cost), `lower` \
             and/or `upper` (rows), or both",
        ));
    }
    Ok(term)
}

/// `frame[2] position front_left_foot z`.
fn label(at: &FrameCheck, entry: &FrameEntry, quantity: &FrameQuantity) -> String {
    let point = entry
        .contact
        .clone()
        .or_else(|| entry.link.clone())
        .unwrap_or_default();
    match &entry.axis {
        Some(axis) => format!("{} {} {point} {axis}", at.entry, quantity.name()),
        None => format!("{} {} {point}", at.entry, quantity.name()),
    }
}
