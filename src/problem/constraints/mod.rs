//! Constraint kinds a problem file adds, one file per kind. A kind's file holds all of it:
//! its entry as the problem file spells it (`Entry`), the check that turns the entry into
//! the checked constraint (names resolved), and the checked constraint's
//! [`ConstraintFunction`]: the variables it reads ([`ConstraintInput`], in the order of its
//! input z), its rows (label and bounds) and their values on z. The transcription places
//! each constraint from that declaration, so a constraint's variables are written once; its
//! sparsity follows from tracing the value (`transcription/structure.rs`).
//!
//! To add a kind: a file here with its `Entry` (serde, `deny_unknown_fields`), its checked
//! type implementing [`ConstraintFunction`] and [`CheckConstraint`], and its line in the
//! `constraint_kinds!` list below. The list generates the `[[constraint]]` schema enum
//! ([`ConstraintEntry`], tagged by `type`), the checked enum ([`Constraint`]) and the
//! dispatch between them. The dynamics, contact and loop-closure rows are the model's own,
//! not problem-file constraints; they live in `transcription/blocks/`.

mod periodic;
mod periodic_momentum;

pub use periodic::{Entry as PeriodicEntry, Periodic};
pub use periodic_momentum::PeriodicMomentum;

use serde::Deserialize;

use super::schema::ProblemFile;
use super::validate::context::Context;
use super::{ProblemError, RobotInfo};
use crate::autodiff::Scalar;
use crate::discrete::{Integrator, Mechanics};

/// The list of constraint kinds: `Variant in module`. The variant's `snake_case` name is the
/// `type` of its `[[constraint]]` entry; `module::Entry` is that entry.
macro_rules! constraint_kinds {
    ($($variant:ident in $module:ident),* $(,)?) => {
        /// `[[constraint]]`: one constraint, chosen by `type`. The fields of each are its
        /// `Entry`.
        #[derive(Debug, Clone, Deserialize)]
        #[serde(tag = "type", rename_all = "snake_case")]
        pub enum ConstraintEntry {
            $(
                #[allow(missing_docs)]
                $variant($module::Entry),
            )*
        }

        /// One checked constraint.
        #[derive(Debug, Clone, PartialEq)]
        pub enum Constraint {
            $(
                #[allow(missing_docs)]
                $variant($variant),
            )*
        }

        impl ConstraintEntry {
            fn check(&self, at: &ConstraintCheck) -> Result<Constraint, ProblemError> {
                match self {
                    $(ConstraintEntry::$variant(entry) => {
                        <$variant as CheckConstraint>::check(entry, at).map(Constraint::$variant)
                    })*
                }
            }
        }

        impl Constraint {
            /// See [`ConstraintFunction::NAME`].
            pub fn name(&self) -> &'static str {
                match self {
                    $(Constraint::$variant(_) => <$variant as ConstraintFunction>::NAME,)*
                }
            }

            /// See [`ConstraintFunction::inputs`].
            pub fn inputs(&self) -> Vec<ConstraintInput> {
                match self {
                    $(Constraint::$variant(c) => c.inputs(),)*
                }
            }

            /// See [`ConstraintFunction::rows`].
            pub fn rows(&self) -> Vec<ConstraintRow> {
                match self {
                    $(Constraint::$variant(c) => c.rows(),)*
                }
            }

            /// See [`ConstraintFunction::value`].
            pub fn value<D: Scalar, M: Mechanics>(&self, mech: &M, z: &[D], out: &mut [D]) {
                match self {
                    $(Constraint::$variant(c) => c.value(mech, z, out),)*
                }
            }

            /// See [`ConstraintFunction::receives_end_momentum`].
            pub fn receives_end_momentum(&self) -> bool {
                match self {
                    $(Constraint::$variant(c) => c.receives_end_momentum(),)*
                }
            }
        }
    };
}

constraint_kinds! {
    Periodic in periodic,
    PeriodicMomentum in periodic_momentum,
}

/// A knot counted from the first (`First(0)` is q_1) or from the last (`Last(0)` is q_N).
/// Intervals are counted the same way (`Last(0)` is the last interval).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KnotRef {
    /// The k-th from the start, 0-based.
    First(usize),
    /// The k-th from the end, 0-based.
    Last(usize),
}

impl KnotRef {
    /// The 0-based index among `count` knots (or intervals), if it exists.
    pub fn resolve(self, count: usize) -> Option<usize> {
        match self {
            KnotRef::First(k) => (k < count).then_some(k),
            KnotRef::Last(k) => count.checked_sub(k + 1),
        }
    }
}

/// One piece of a constraint's input z, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConstraintInput {
    /// One coordinate q_k[c].
    Coordinate {
        /// The knot.
        knot: KnotRef,
        /// The coordinate's index.
        coordinate: usize,
    },
    /// The whole configuration q_k (n values).
    Configuration(KnotRef),
    /// The initial velocity v_0 (n values).
    InitialVelocity,
    /// The time step h_j of an interval.
    Step(KnotRef),
    /// The inputs u_j of an interval (m values).
    Inputs(KnotRef),
}

/// One row of a constraint: how it is named and its bounds lower ≤ g ≤ upper.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintRow {
    /// How `vito check --derivatives` and reports name the row.
    pub label: String,
    /// Lower bound (−∞ for none).
    pub lower: f64,
    /// Upper bound (+∞ for none).
    pub upper: f64,
}

impl ConstraintRow {
    /// An equality row g = 0.
    pub fn equality(label: String) -> ConstraintRow {
        ConstraintRow {
            label,
            lower: 0.0,
            upper: 0.0,
        }
    }
}

/// One constraint: the variables it reads, its rows and their values.
pub trait ConstraintFunction {
    /// Its kind's name (the `type` of its entry).
    const NAME: &'static str;
    /// The variables it reads, in the order of z.
    fn inputs(&self) -> Vec<ConstraintInput>;
    /// Its rows, in order.
    fn rows(&self) -> Vec<ConstraintRow>;
    /// The row values on z (layout from [`ConstraintFunction::inputs`]) into `out`.
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, z: &[D], out: &mut [D]);
    /// Whether row i also receives component i of the momentum arriving at the last knot,
    /// p_N⁻ = D2Ld(q_{N−1}, q_N, h_{N−1}) + ½Fd(q_{N−1}, q_N, u_{N−1}, h_{N−1}) (n rows). The
    /// transcription adds it from the last interval's own DEL blocks (segment and force), whose
    /// derivatives are exact and fast, instead of differentiating D2Ld again here.
    fn receives_end_momentum(&self) -> bool {
        false
    }
}

/// How a constraint is checked from its entry.
pub trait CheckConstraint: Sized {
    /// The entry as the problem file spells it.
    type Entry;
    /// The checked constraint, or the error naming the file, line and field.
    fn check(entry: &Self::Entry, at: &ConstraintCheck) -> Result<Self, ProblemError>;
}

/// What a constraint's check needs: where its entry is and the robot's names.
pub struct ConstraintCheck<'a> {
    ctx: &'a Context,
    /// `constraint[3]` or `periodic[0]`: the entry as errors name it.
    entry: String,
    robot: &'a RobotInfo,
}

impl ConstraintCheck<'_> {
    /// `entry.key`, the field named in errors.
    pub fn field(&self, key: &str) -> String {
        format!("{}.{key}", self.entry)
    }

    /// The index of coordinate `name`; an unknown name is an error naming the field and the
    /// nearest coordinate.
    pub fn coordinate(&self, key: &str, name: &str) -> Result<usize, ProblemError> {
        self.robot.coordinate_index(name).ok_or_else(|| {
            self.ctx.unknown_name(
                &self.field(key),
                "coordinate",
                name,
                &self.robot.coordinates,
            )
        })
    }

    /// The robot's coordinate names (length n).
    pub fn coordinate_names(&self) -> &[String] {
        &self.robot.coordinates
    }

    /// A finite number.
    pub fn finite(&self, key: &str, value: f64) -> Result<f64, ProblemError> {
        super::validate::values::finite(self.ctx, &self.field(key), value)
    }
}

/// Every constraint of the file, checked against the robot and the number of knots: the
/// `[[periodic]]` shorthand entries first, then `[[constraint]]`, each in file order.
pub(crate) fn check_constraints(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
    knots: usize,
) -> Result<Vec<Constraint>, ProblemError> {
    let at = |entry: String| ConstraintCheck { ctx, entry, robot };
    let periodic = raw.periodic.iter().enumerate().map(|(i, entry)| {
        let at = at(format!("periodic[{i}]"));
        let checked = <Periodic as CheckConstraint>::check(entry, &at).map(Constraint::Periodic);
        (at, checked)
    });
    let general = raw.constraint.iter().enumerate().map(|(i, entry)| {
        let at = at(format!("constraint[{i}]"));
        let checked = entry.check(&at);
        (at, checked)
    });
    periodic
        .chain(general)
        .map(|(at, checked)| {
            let constraint = checked?;
            reads_existing_knots(&constraint, &at, knots)?;
            Ok(constraint)
        })
        .collect()
}

impl Constraint {
    /// Why the constraint cannot be used with `integrator`, or `None`: the end momentum p_N⁻
    /// comes from a variational integrator's discrete Legendre transform (the midpoint rule's
    /// or a Galerkin member's), which semi-implicit Euler does not have.
    pub fn integrator_problem(&self, integrator: Integrator) -> Option<String> {
        (self.receives_end_momentum() && integrator == Integrator::Euler).then(|| {
            format!(
                "a `{}` constraint needs the momentum a variational integrator's last interval \
                 ends with; set `[solver] integrator = \"midpoint\"` (or a Galerkin member)",
                self.name()
            )
        })
    }

    /// Why the constraint cannot be placed among `knots` knots (a knot or interval it reads
    /// does not exist), or `None`.
    pub fn missing_knot(&self, knots: usize) -> Option<String> {
        self.inputs().into_iter().find_map(|input| {
            let (what, reference, count) = match input {
                ConstraintInput::Coordinate { knot, .. } | ConstraintInput::Configuration(knot) => {
                    ("knot", knot, knots)
                }
                ConstraintInput::Step(j) | ConstraintInput::Inputs(j) => {
                    ("interval", j, knots.saturating_sub(1))
                }
                ConstraintInput::InitialVelocity => return None,
            };
            reference.resolve(count).is_none().then(|| {
                format!(
                    "this `{}` constraint reads {what} {reference:?}, but the problem has \
                     {knots} knots; raise `knots`",
                    self.name()
                )
            })
        })
    }
}

/// Every knot and interval `constraint` reads exists among `knots` knots.
fn reads_existing_knots(
    constraint: &Constraint,
    at: &ConstraintCheck,
    knots: usize,
) -> Result<(), ProblemError> {
    match constraint.missing_knot(knots) {
        Some(message) => Err(at.ctx.invalid(&at.entry, message)),
        None => Ok(()),
    }
}
