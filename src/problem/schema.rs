//! The problem file as written (TOML, serde): only types, no checks beyond the TOML grammar.
//!
//! Every table denies unknown keys, so a typo is an error, never a silently ignored line.
//! Units are the robot's units: SI (m, kg, s, rad, N, N·m) unless `robot.units` says
//! otherwise (HAMR: mm, g, ms, with gravity given explicitly). `validate` turns a
//! [`ProblemFile`] into a checked [`crate::problem::ProblemSpec`].

#![warn(missing_docs)]

use std::collections::BTreeMap;
use std::fmt;

use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer};

pub use super::constraints::{ConstraintEntry, PeriodicEntry};
pub use super::costs::CostEntry;
pub use super::frames::{ContactWindowEntry, FrameEntry, GaitEntry};

/// A whole problem file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProblemFile {
    /// Short name used in outputs and regression records (default: the file stem).
    pub name: Option<String>,
    /// Free text shown by `vito check`.
    pub description: Option<String>,
    /// `[robot]`.
    pub robot: RobotSection,
    /// `[contacts]`.
    #[serde(default)]
    pub contacts: ContactsSection,
    /// `[terrain]`.
    #[serde(default)]
    pub terrain: TerrainSection,
    /// `[horizon]`.
    pub horizon: HorizonSection,
    /// `[initial]`.
    pub initial: InitialSection,
    /// `[final]`.
    #[serde(rename = "final", default)]
    pub final_: FinalSection,
    /// Extra coordinate bounds, intersected with each other and with the joint limits.
    #[serde(default)]
    pub bounds: Vec<BoundEntry>,
    /// `[inputs]`.
    #[serde(default)]
    pub inputs: InputsSection,
    /// Cost terms; the slack penalty is added on top (see `slack`).
    #[serde(default)]
    pub cost: Vec<CostEntry>,
    /// `[slack]`.
    pub slack: SlackSection,
    /// `[[periodic]]` conditions (shorthand for `[[constraint]] type = "periodic"`).
    #[serde(default)]
    pub periodic: Vec<PeriodicEntry>,
    /// `[[constraint]]`: constraints of any kind, chosen by `type`.
    #[serde(default)]
    pub constraint: Vec<ConstraintEntry>,
    /// `[[frame]]`: costs and rows on a point of the robot (position, clearance,
    /// orientation, velocity) at chosen knots.
    #[serde(default)]
    pub frame: Vec<FrameEntry>,
    /// `[[contact_window]]`: a contact in flight or in stance over a time window.
    #[serde(default)]
    pub contact_window: Vec<ContactWindowEntry>,
    /// `[gait]`: contact windows from a period, a duty factor and phase offsets.
    pub gait: Option<GaitEntry>,
    /// `[initial_guess]`.
    #[serde(default)]
    pub initial_guess: InitialGuessSection,
    /// `[solver]`.
    #[serde(default)]
    pub solver: SolverSection,
    /// `[output]`.
    #[serde(default)]
    pub output: OutputSection,
    /// `[metrics]`: what the summary reports beyond the solver's numbers.
    #[serde(default)]
    pub metrics: MetricsSection,
    /// `[tracking]`: PD gains for `vito simulate --track` and `vito study tracking`.
    #[serde(default)]
    pub tracking: TrackingSection,
}

/// `[tracking]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackingSection {
    /// `NAME = [kp, kd]` per input, or `all = [kp, kd]` (a named input overrides `all`):
    /// kp in input units per coordinate unit (N·m/rad), kd per coordinate rate (N·m·s/rad).
    #[serde(default, deserialize_with = "exact_map")]
    pub gains: BTreeMap<String, [f64; 2]>,
    /// `explicit` (default) or `implicit`: PD on the step's start or end state.
    #[serde(default)]
    pub feedback: super::tracking::TrackingFeedback,
}

/// `[robot]`: the model and its environment constants.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSection {
    /// URDF path, relative to the problem file.
    pub urdf: String,
    /// `fixed`, `planar` or `floating` (coordinates: [`crate::model::BaseType::coordinate_names`]).
    #[serde(default)]
    pub base: BaseName,
    /// Gravity in world coordinates, robot units (default [0, 0, −9.81] m/s²).
    #[serde(default, deserialize_with = "exact_option")]
    pub gravity: Option<[f64; 3]>,
    /// Unit system, for the reader: `"SI"` (default) or e.g. `"mm g ms"`. Informational only:
    /// vito never converts; every number in the file is in these units.
    pub units: Option<String>,
    /// Apply the URDF joint limits on every knot (default true).
    pub joint_limits: Option<bool>,
}

/// The base joint, by name.
#[derive(Debug, Clone, Copy, Deserialize, Default, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BaseName {
    /// Root link welded to the world (default).
    #[default]
    Fixed,
    /// Coordinates [`crate::model::PLANAR_BASE_COORDINATES`].
    Planar,
    /// Coordinates [`crate::model::FLOATING_BASE_COORDINATES`].
    Floating,
}

/// `[contacts]`: which points touch the terrain.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct ContactsSection {
    /// Contacts from the URDF's collision spheres (any radius): `"all"` (default when no
    /// explicit `point` is given), `"none"`, or a list of contact names.
    pub from_urdf: Option<ContactSelection>,
    /// Coulomb friction coefficient for every contact without its own (default 1).
    pub friction: Option<f64>,
    /// Per-contact friction by contact name, overriding `friction`.
    #[serde(default)]
    pub friction_by_name: BTreeMap<String, f64>,
    /// Upper bound on ψ, the sliding-speed variable of every contact and interval (length /
    /// time units). In flight nothing bounds ψ from above, and the barrier then pushes it (and
    /// η) towards 1e6–1e8; a bound well above any real foot speed stops that drift without
    /// cutting off a physical motion. Default: none (the reference NLP).
    pub max_slip_speed: Option<f64>,
    /// Intervals per contact-mode block (default 1): each complementarity row pairs an
    /// interval's variable with the sum of its partner over the block, so that at zero slack
    /// a contact keeps one mode (in contact or not, sliding or sticking) through each block of
    /// this many consecutive intervals.
    pub mode_block: Option<i64>,
    /// Explicit contact points, after the URDF ones.
    #[serde(default)]
    pub point: Vec<ContactPointEntry>,
}

/// `"all"`, `"none"` or a list of names.
#[derive(Debug, Clone, PartialEq)]
pub enum ContactSelection {
    /// Every collision sphere of the URDF.
    All,
    /// None of them.
    None,
    /// These, by contact name, in this order.
    Names(Vec<String>),
}

impl<'de> Deserialize<'de> for ContactSelection {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct SelectionVisitor;
        impl<'de> Visitor<'de> for SelectionVisitor {
            type Value = ContactSelection;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("\"all\", \"none\" or a list of contact names")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                match v {
                    "all" => Ok(ContactSelection::All),
                    "none" => Ok(ContactSelection::None),
                    other => Err(E::invalid_value(de::Unexpected::Str(other), &self)),
                }
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut names = Vec::new();
                while let Some(name) = seq.next_element::<String>()? {
                    names.push(name);
                }
                Ok(ContactSelection::Names(names))
            }
        }
        deserializer.deserialize_any(SelectionVisitor)
    }
}

/// `[[contacts.point]]`: a point fixed on a link.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactPointEntry {
    /// Name used in outputs.
    pub name: String,
    /// URDF link name.
    pub link: String,
    /// Point in the link frame [length]: the sphere's centre when `radius` is given.
    #[serde(deserialize_with = "exact")]
    pub point: [f64; 3],
    /// Radius of a sphere around `point` [length] (default 0: a point).
    pub radius: Option<f64>,
    /// Friction coefficient (default: `contacts.friction`).
    pub friction: Option<f64>,
}

/// `[terrain]`: flat ground plus smoothed steps.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct TerrainSection {
    /// Height of the flat ground [length] (default 0).
    pub ground_height: Option<f64>,
    /// Smoothed steps H = rise·½(1 + tanh((s − edge)/width)) along a heading; heights add up.
    #[serde(default)]
    pub step: Vec<crate::contact::Step>,
    /// Flights of stairs: `count` steps `run` apart along a heading.
    #[serde(default)]
    pub stairs: Vec<crate::contact::Stairs>,
    /// Raised blocks with smoothed edges.
    #[serde(default)]
    pub block: Vec<crate::contact::Block>,
    /// Heights on a grid from a file next to the problem.
    pub height_map: Option<crate::contact::HeightMapEntry>,
    /// The ground tilted: `angle` [deg] falling along `heading` [deg] from +x towards +y.
    pub slope: Option<crate::contact::Slope>,
}

/// `[horizon]`: knots and time steps.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HorizonSection {
    /// Number of knots N ≥ 2.
    pub knots: i64,
    /// Fixed time step h [time] (exclusive with `total_time`).
    pub time_step: Option<f64>,
    /// Free, equal time steps with total time T in [min, max] [time].
    #[serde(default, deserialize_with = "exact_option")]
    pub total_time: Option<[f64; 2]>,
}

/// `[initial]`: the first knot.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSection {
    /// q_1, fixed: a table by coordinate name (optional `default` for unnamed ones) or an
    /// array of full length n in the model's coordinate order.
    pub q: NamedVector,
    /// v_0 [length/time or rad/time]: `"zero"`, `"free"`, or a vector like `q` (default zero).
    pub v: Option<VelocitySpec>,
    /// Coordinates whose q_1 is a variable (`q` is then only its guess), `"all"` or a list
    /// of names (default: none, q_1 fixed). Bounds and joint limits still apply to them.
    pub free: Option<CoordinateSelection>,
}

/// `"all"`, `"none"` or a list of coordinate names (the same three forms as contacts).
pub type CoordinateSelection = ContactSelection;

/// `[inputs] actuated`: a rule by name, or joints by name.
#[derive(Debug, Clone, PartialEq)]
pub enum ActuatedEntry {
    /// `"transmissions"` or `"all"` (checked at validation).
    Rule(String),
    /// Joint names.
    Joints(Vec<String>),
}

impl<'de> Deserialize<'de> for ActuatedEntry {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ActuatedVisitor;
        impl<'de> Visitor<'de> for ActuatedVisitor {
            type Value = ActuatedEntry;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("\"transmissions\", \"all\" or a list of joint names")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                Ok(ActuatedEntry::Rule(v.to_owned()))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut joints = Vec::new();
                while let Some(joint) = seq.next_element::<String>()? {
                    joints.push(joint);
                }
                Ok(ActuatedEntry::Joints(joints))
            }
        }
        deserializer.deserialize_any(ActuatedVisitor)
    }
}

/// `"zero"`, `"free"` or a vector.
#[derive(Debug, Clone, PartialEq)]
pub enum VelocitySpec {
    /// v_0 = 0, fixed.
    Zero,
    /// v_0 is a variable.
    Free,
    /// v_0 fixed to these values.
    Vector(NamedVector),
}

impl<'de> Deserialize<'de> for VelocitySpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct VelocityVisitor;
        impl<'de> Visitor<'de> for VelocityVisitor {
            type Value = VelocitySpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("\"zero\", \"free\", a table by coordinate name or an array")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                match v {
                    "zero" => Ok(VelocitySpec::Zero),
                    "free" => Ok(VelocitySpec::Free),
                    other => Err(E::invalid_value(de::Unexpected::Str(other), &self)),
                }
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
                NamedVectorVisitor.visit_seq(seq).map(VelocitySpec::Vector)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                NamedVectorVisitor.visit_map(map).map(VelocitySpec::Vector)
            }
        }
        deserializer.deserialize_any(VelocityVisitor)
    }
}

/// `[final]`: the last knot.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct FinalSection {
    /// Goal configuration by name; coordinates not named keep their `initial.q` value.
    /// Without `q` and without `free = true`, q_N is free.
    pub q: Option<NamedVector>,
    /// q_N within goal ± tolerance on every coordinate (default 0: fixed).
    pub tolerance: Option<f64>,
    /// Leave q_N free (the goal, if given, is still the cost and guess target).
    pub free: Option<bool>,
}

/// A fixed-length array of numbers that refuses a longer one: serde reads a `[f64; N]` as
/// its first N elements and ignores the rest (`window = [0.1, 0.2, 0.3]` would be read as
/// [0.1, 0.2]), so every fixed-length field of a problem file is read through this
/// ([`exact`], [`exact_option`], [`exact_map`]).
struct Exact<const N: usize>([f64; N]);

impl<'de, const N: usize> Deserialize<'de> for Exact<N> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ExactVisitor<const N: usize>;
        impl<'de, const N: usize> Visitor<'de> for ExactVisitor<N> {
            type Value = Exact<N>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "an array of length {N}")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut out = [0.0; N];
                for (i, slot) in out.iter_mut().enumerate() {
                    *slot = seq
                        .next_element()?
                        .ok_or_else(|| de::Error::invalid_length(i, &self))?;
                }
                let mut len = N;
                while seq.next_element::<de::IgnoredAny>()?.is_some() {
                    len += 1;
                }
                if len > N {
                    return Err(de::Error::invalid_length(len, &self));
                }
                Ok(Exact(out))
            }
        }
        deserializer.deserialize_seq(ExactVisitor::<N>)
    }
}

/// A `[f64; N]` field, exactly N numbers long ([`Exact`]).
pub(crate) fn exact<'de, D: Deserializer<'de>, const N: usize>(
    deserializer: D,
) -> Result<[f64; N], D::Error> {
    Exact::deserialize(deserializer).map(|e| e.0)
}

/// An optional `[f64; N]` field, exactly N numbers long when given ([`Exact`]).
pub(crate) fn exact_option<'de, D: Deserializer<'de>, const N: usize>(
    deserializer: D,
) -> Result<Option<[f64; N]>, D::Error> {
    Option::<Exact<N>>::deserialize(deserializer).map(|o| o.map(|e| e.0))
}

/// A table of `[f64; N]` by name, each exactly N numbers long ([`Exact`]).
pub(crate) fn exact_map<'de, D: Deserializer<'de>, const N: usize>(
    deserializer: D,
) -> Result<BTreeMap<String, [f64; N]>, D::Error> {
    BTreeMap::<String, Exact<N>>::deserialize(deserializer)
        .map(|m| m.into_iter().map(|(k, e)| (k, e.0)).collect())
}

/// A vector over coordinates, inputs or contacts: a table by name or a full-length array.
#[derive(Debug, Clone, PartialEq)]
pub enum NamedVector {
    /// `[a, b, c]` in the model's order; its length must match.
    Array(Vec<f64>),
    /// `{ name = value, ..., default = value }` in file order.
    Table(Vec<(String, f64)>),
}

struct NamedVectorVisitor;

impl<'de> Visitor<'de> for NamedVectorVisitor {
    type Value = NamedVector;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a table of numbers by name or an array of numbers")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut values = Vec::new();
        while let Some(v) = seq.next_element::<f64>()? {
            values.push(v);
        }
        Ok(NamedVector::Array(values))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let mut entries = Vec::new();
        while let Some((k, v)) = map.next_entry::<String, f64>()? {
            entries.push((k, v));
        }
        Ok(NamedVector::Table(entries))
    }
}

impl<'de> Deserialize<'de> for NamedVector {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(NamedVectorVisitor)
    }
}

/// `[[bounds]]`: bounds on one coordinate at a set of knots.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundEntry {
    /// Coordinate name.
    pub coordinate: String,
    /// `"all"` (default), `"interior"`, `"first"`, `"last"` or a list of 0-based knots.
    pub knots: Option<KnotsName>,
    /// Lower bound (default −∞).
    pub lower: Option<f64>,
    /// Upper bound (default +∞).
    pub upper: Option<f64>,
}

/// A named set of knots or an explicit list.
#[derive(Debug, Clone, PartialEq)]
pub enum KnotsName {
    /// `all`, `interior`, `first` or `last` (checked by validation).
    Named(String),
    /// 0-based knot indices.
    List(Vec<i64>),
}

impl<'de> Deserialize<'de> for KnotsName {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct KnotsVisitor;
        impl<'de> Visitor<'de> for KnotsVisitor {
            type Value = KnotsName;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("\"all\", \"interior\", \"first\", \"last\" or a list of knot indices")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                Ok(KnotsName::Named(v.to_owned()))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut knots = Vec::new();
                while let Some(k) = seq.next_element::<i64>()? {
                    knots.push(k);
                }
                Ok(KnotsName::List(knots))
            }
        }
        deserializer.deserialize_any(KnotsVisitor)
    }
}

/// `[inputs]`: bounds on the inputs.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct InputsSection {
    /// Which joints take an input: `"transmissions"` (the URDF's `<transmission>`
    /// elements), `"all"` (every movable joint) or a list of joint names. Default: the
    /// transmissions when the URDF has any, otherwise every movable joint.
    pub actuated: Option<ActuatedEntry>,
    /// Bound |u_j| ≤ URDF effort (default true; an infinite effort means no bound).
    pub effort_limits: Option<bool>,
    /// Explicit bounds by input name, `name = [lower, upper]`, replacing the effort limit.
    #[serde(default, deserialize_with = "exact_map")]
    pub bounds: BTreeMap<String, [f64; 2]>,
}

/// `[slack]`: the complementarity relaxation.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlackSection {
    /// Penalty α > 0 on Σ s.
    pub weight: f64,
    /// `"per_interval"` (default, the paper's), `"per_contact"` or `"penalty"` (no slacks:
    /// the complementarity products weighted by `weight` in the objective).
    pub mode: Option<String>,
    /// Largest slack of a solved plan (default 1e-4, problem units); a solve ending above it
    /// is `relaxed_contact`, not solved.
    pub tolerance: Option<f64>,
    /// Largest slack a solution may keep (e.g. the paper's 1e-5). When a solve ends above it,
    /// vito multiplies the weight by `growth` and solves again from that solution.
    pub target: Option<f64>,
    /// Factor on the weight per extra solve (default 10).
    pub growth: Option<f64>,
    /// Extra solves allowed (default 3).
    pub rounds: Option<usize>,
    /// Where a raised-weight solve starts after an optimum: `"primal"` (default: its x),
    /// `"primal_dual"` (its x and multipliers) or `"initial_guess"`.
    pub restart: Option<String>,
    /// A relaxation homotopy: the first solve's weight is `weight` / 1000, raised by
    /// `growth` per warm-started solve until the largest slack is below `target` (default:
    /// a tenth of `tolerance`; `rounds` default 6, `restart` default `"primal_dual"`).
    pub homotopy: Option<bool>,
    /// Each solve of the continuation only as tight as its relaxation (the practice of
    /// nosnoc's multi-Ipopt homotopy): Ipopt's `tol`, `mu_init` and `mu_target` a tenth of the
    /// relaxation σ that the solve's weight stands for (`tolerance` × `weight` / the solve's
    /// weight), monotone μ, until that reaches the file's `tol`; the polish is then the tight
    /// solve, and without it (or when it is not kept) one relaxed solve at the file's own
    /// tolerances from the last point (default false; needs `target` or `homotopy`).
    pub tied_tolerances: Option<bool>,
    /// Finish with the contact modes fixed: from the solution, fix each complementarity
    /// pair's smaller side at zero (a foot touching or free of force, sticking or sliding),
    /// solve that regular NLP without slacks from there, and keep it if it is solved and the
    /// solution it started from is not, or is no better (default true, except with
    /// `contacts.mode_block` above 1).
    pub polish: Option<bool>,
}

/// `[initial_guess]`: where Ipopt starts.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct InitialGuessSection {
    /// Linear interpolation from q_1 to this pose (default: the final goal); coordinates
    /// not named keep q_1's value. `"initial"` holds q_1 at every knot.
    pub to: Option<GuessTarget>,
    /// A previous `trajectory.csv` (relative to the problem file), resampled to the knots.
    pub warm_start: Option<String>,
    /// `[initial_guess.simulation]`: an open-loop simulation under sinusoidal inputs.
    pub simulation: Option<SimulationGuessEntry>,
}

/// `[initial_guess.simulation]`: simulate the robot from `[initial]` under the open-loop
/// inputs u_i(t) = offset_i + amplitude_i · sin(2π (t / period + phase_i)) (clipped to the
/// input bounds) for `cycles` periods at the step period / ((knots − 1) · substeps), and
/// start the solve from the last period, on the knots.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationGuessEntry {
    /// The period [time], e.g. one stride.
    pub period: f64,
    /// Periods simulated; the last is the guess (default 3: the first ones let it settle).
    pub cycles: Option<i64>,
    /// Simulation steps per knot interval (default 1: the NLP's own step). More resolve
    /// stiff transients the contact solver cannot take in one step; the guess keeps every
    /// `substeps`-th knot and the mean input of each interval.
    pub substeps: Option<i64>,
    /// Amplitude per input [input units] (a table by input name, `default` allowed).
    pub amplitude: NamedVector,
    /// Phase per input [fraction of a period] (default 0).
    pub phase: Option<NamedVector>,
    /// Constant part per input [input units] (default 0).
    pub offset: Option<NamedVector>,
}

/// `[metrics]`: quantities of a solution reported in `summary.json` under `metrics` (and
/// so in a sweep's table).
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct MetricsSection {
    /// Names from [`crate::problem::Metric`]: `"forward_per_cycle"`, `"forward_speed"`,
    /// `"slip"`, `"jump_height"`.
    #[serde(default)]
    pub report: Vec<String>,
    /// The forward coordinate (default `base_x`).
    pub forward: Option<String>,
    /// The vertical coordinate (default `base_z`).
    pub vertical: Option<String>,
}

/// `"initial"`, `"final"` or a pose.
#[derive(Debug, Clone, PartialEq)]
pub enum GuessTarget {
    /// Hold q_1 at every knot.
    Initial,
    /// Towards the final goal (default).
    Final,
    /// Towards this pose (unnamed coordinates keep q_1's value).
    Pose(NamedVector),
}

impl<'de> Deserialize<'de> for GuessTarget {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct TargetVisitor;
        impl<'de> Visitor<'de> for TargetVisitor {
            type Value = GuessTarget;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("\"initial\", \"final\" or a pose by coordinate name")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                match v {
                    "initial" => Ok(GuessTarget::Initial),
                    "final" => Ok(GuessTarget::Final),
                    other => Err(E::invalid_value(de::Unexpected::Str(other), &self)),
                }
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
                NamedVectorVisitor.visit_seq(seq).map(GuessTarget::Pose)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                NamedVectorVisitor.visit_map(map).map(GuessTarget::Pose)
            }
        }
        deserializer.deserialize_any(TargetVisitor)
    }
}

/// `[solver]`: integrator, Hessian and Ipopt options.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct SolverSection {
    /// `"midpoint"` (default) or `"euler"`.
    pub integrator: Option<String>,
    /// `"exact"` (default) or `"lbfgs"`.
    pub hessian: Option<String>,
    /// `"ipopt"` (default: Ipopt's own scaling) or `"units"`.
    pub scaling: Option<String>,
    /// Ipopt options passed through in file order (checked by the wrapper).
    #[serde(default)]
    pub ipopt: toml::Table,
}

/// `[output]`.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// Output directory, relative to the problem file (default `out/<name>` in the working
    /// directory).
    pub dir: Option<String>,
}
