//! Cost terms, one file per term. A term's file holds all of it: its `[[cost]]` entry as the
//! problem file spells it (`Entry`, names and all; a term that takes nothing but weights names
//! [`WeightsEntry`]), the check that turns the entry into the
//! checked term (names resolved to full-length vectors), and the checked term's
//! [`CostFunction`]: the knot-local variables it reads ([`CostInputs`]) and its value on them.
//! The transcription places each term from that declaration, so a term's variables are
//! written once.
//!
//! To add a term: a file here with its `Entry` (serde, `deny_unknown_fields`), its checked
//! type implementing [`CostFunction`] and [`CheckCost`], and its line in the
//! `cost_terms!` list below. The list generates the `[[cost]]` schema enum ([`CostEntry`],
//! tagged by `type`), the checked enum ([`CostTerm`]) and the dispatch between them.

mod configuration_difference;
mod final_state;
mod final_velocity;
mod impulse_rate;
mod input;
mod input_rate;
mod state_tracking;
mod time;
mod velocity_difference;

pub use configuration_difference::ConfigurationDifference;
pub use final_state::FinalState;
pub use final_velocity::FinalVelocity;
pub use impulse_rate::ImpulseRate;
pub use input::Input;
pub use input_rate::InputRate;
pub use state_tracking::StateTracking;
pub use time::Time;
pub use velocity_difference::VelocityDifference;

use nalgebra::DMatrix;
use serde::Deserialize;

use super::schema::{NamedVector, ProblemFile};
use super::validate::context::Context;
use super::validate::values::{nonnegative, resolve};
use super::{ProblemError, RobotInfo};
use crate::autodiff::Scalar;

/// The list of cost terms: `Variant in module`. The variant's `snake_case` name is the
/// `type` of its `[[cost]]` entry; `module::Entry` is that entry.
macro_rules! cost_terms {
    ($($variant:ident in $module:ident),* $(,)?) => {
        /// `[[cost]]`: one term, chosen by `type`. Every quadratic term carries ½:
        /// ½ (a − b)ᵀ diag(w) (a − b). The fields of each are its `Entry`.
        #[derive(Debug, Clone, Deserialize)]
        #[serde(tag = "type", rename_all = "snake_case")]
        pub enum CostEntry {
            $(
                #[allow(missing_docs)]
                $variant($module::Entry),
            )*
        }

        /// One checked cost term. Running terms are summed over intervals k = 1..N−1 (and
        /// weighted by h_k where the term says so); weight vectors have full length (n, m
        /// for inputs, nc for contacts).
        #[derive(Debug, Clone, PartialEq)]
        pub enum CostTerm {
            $(
                #[allow(missing_docs)]
                $variant($variant),
            )*
        }

        impl CostEntry {
            fn check(&self, at: &CostCheck) -> Result<CostTerm, ProblemError> {
                match self {
                    $(CostEntry::$variant(entry) => {
                        <$variant as CheckCost>::check(entry, at).map(CostTerm::$variant)
                    })*
                }
            }
        }

        /// Calls `visitor` with the [`CostFunction`] of `term`: the one place where the
        /// problem's cost terms meet their types.
        pub fn with_cost_function<V: CostVisitor>(term: &CostTerm, visitor: V) -> V::Output {
            match term {
                $(CostTerm::$variant(cost) => visitor.visit(cost),)*
            }
        }
    };
}

cost_terms! {
    StateTracking in state_tracking,
    Input in input,
    InputRate in input_rate,
    ConfigurationDifference in configuration_difference,
    FinalState in final_state,
    FinalVelocity in final_velocity,
    Time in time,
    VelocityDifference in velocity_difference,
    ImpulseRate in impulse_rate,
}

/// The `[[cost]]` entry of a term that takes nothing but its weights (per coordinate or per
/// input, as the term says).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WeightsEntry {
    /// Weights, by name or as an array.
    pub weights: NamedVector,
}

/// The knot-local variables a cost term reads, in the order of its input z, and where.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CostInputs {
    /// z = [q_j; q_{j+1}; h_j] on every interval j.
    IntervalWithStep,
    /// z = [q_j; q_{j+1}] on every interval j.
    IntervalConfigurations,
    /// z = [u_j; h_j] on every interval j.
    InputWithStep,
    /// z = [u_{j−1}; u_j] on every pair of adjacent intervals.
    AdjacentInputs,
    /// z = [c_{j−1}; c_j], the normal impulses of every contact, on every pair of adjacent
    /// intervals.
    AdjacentImpulses,
    /// z = [q_{j−1}; q_j; q_{j+1}; h_{j−1}; h_j] on every pair of adjacent intervals.
    AdjacentIntervals,
    /// z = [q_N], the last knot, once.
    LastConfiguration,
    /// z = [q_{N−1}; q_N; h_{N−1}], the last interval, once.
    LastIntervalWithStep,
    /// z = [h_j] on every interval j.
    Step,
}

/// Sizes a term's input z is split by.
#[derive(Debug, Clone, Copy)]
pub struct CostSizes {
    /// Coordinates n.
    pub n: usize,
    /// Inputs m.
    pub m: usize,
    /// Contacts nc.
    pub nc: usize,
}

/// A vector of a cost term whose length does not match the robot: (field, expected, found).
pub type LengthMismatch = (&'static str, usize, usize);

/// One cost term: which variables it reads and its value on one placement of them.
pub trait CostFunction {
    /// Its name in `Solution::objective_terms`.
    const NAME: &'static str;
    /// The variables it reads.
    const INPUTS: CostInputs;
    /// Whether it is linear in all its inputs (no Hessian entries).
    const LINEAR: bool = false;
    /// Its value on z (layout from [`CostFunction::INPUTS`]).
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D;
    /// Its Hessian on z in closed form, dim z × dim z (`None`: generic forward AD over
    /// [`CostFunction::value`]).
    fn hessian(&self, _z: &[f64], _sizes: CostSizes) -> Option<DMatrix<f64>> {
        None
    }
    /// The first vector of the term whose length does not fit n coordinates and m inputs.
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch>;
}

/// How a term is checked from its `[[cost]]` entry.
pub trait CheckCost: Sized {
    /// The entry as the problem file spells it.
    type Entry;
    /// The checked term, or the error naming the file, line and field.
    fn check(entry: &Self::Entry, at: &CostCheck) -> Result<Self, ProblemError>;
}

/// What a term's check needs: where its entry is, the robot's names, the problem's contact
/// names (in order) and the goal.
pub struct CostCheck<'a> {
    ctx: &'a Context,
    index: usize,
    robot: &'a RobotInfo,
    contacts: &'a [String],
    goal: &'a [f64],
}

impl CostCheck<'_> {
    /// `cost[i].key`, the field named in errors.
    fn field(&self, key: &str) -> String {
        format!("cost[{}].{key}", self.index)
    }

    /// A target configuration by coordinate; coordinates not named (and an absent target)
    /// keep the final goal's value.
    pub fn configuration_target(
        &self,
        key: &str,
        target: Option<&NamedVector>,
    ) -> Result<Vec<f64>, ProblemError> {
        self.coordinate_vector(key, target, self.goal)
    }

    /// A target velocity by coordinate; coordinates not named (and an absent target) are 0.
    pub fn velocity_target(
        &self,
        key: &str,
        target: Option<&NamedVector>,
    ) -> Result<Vec<f64>, ProblemError> {
        self.coordinate_vector(key, target, &vec![0.0; self.robot.coordinates.len()])
    }

    /// A vector by coordinate, `fallback` where not named.
    fn coordinate_vector(
        &self,
        key: &str,
        vector: Option<&NamedVector>,
        fallback: &[f64],
    ) -> Result<Vec<f64>, ProblemError> {
        let coordinates = &self.robot.coordinates;
        match vector {
            Some(v) => resolve(
                self.ctx,
                &self.field(key),
                "coordinate",
                coordinates,
                v,
                Some(fallback),
            ),
            None => Ok(fallback.to_vec()),
        }
    }

    /// Weights ≥ 0 by coordinate; an absent vector is all zeros.
    pub fn coordinate_weights(
        &self,
        key: &str,
        weights: Option<&NamedVector>,
    ) -> Result<Vec<f64>, ProblemError> {
        match weights {
            Some(w) => self.weights(key, &self.robot.coordinates, "coordinate", w),
            None => Ok(vec![0.0; self.robot.coordinates.len()]),
        }
    }

    /// Weights ≥ 0 by input.
    pub fn input_weights(
        &self,
        key: &str,
        weights: &NamedVector,
    ) -> Result<Vec<f64>, ProblemError> {
        self.weights(key, &self.robot.inputs, "input", weights)
    }

    /// Weights ≥ 0 by contact name.
    pub fn contact_weights(
        &self,
        key: &str,
        weights: &NamedVector,
    ) -> Result<Vec<f64>, ProblemError> {
        self.weights(key, self.contacts, "contact", weights)
    }

    /// The number of the problem's contacts.
    pub fn contact_count(&self) -> usize {
        self.contacts.len()
    }

    /// The error for `cost[i].key` with `message`.
    pub fn invalid(&self, key: &str, message: impl Into<String>) -> ProblemError {
        self.ctx.invalid(&self.field(key), message)
    }

    /// A finite number ≥ 0.
    pub fn nonnegative(&self, key: &str, value: f64) -> Result<f64, ProblemError> {
        nonnegative(self.ctx, &self.field(key), value)
    }

    fn weights(
        &self,
        key: &str,
        names: &[String],
        kind: &'static str,
        w: &NamedVector,
    ) -> Result<Vec<f64>, ProblemError> {
        let field = self.field(key);
        let values = resolve(self.ctx, &field, kind, names, w, None)?;
        if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| **v < 0.0) {
            return Err(self.ctx.invalid(
                &field,
                format!("weight of `{}` is {v}; weights must be ≥ 0", names[i]),
            ));
        }
        Ok(values)
    }
}

/// `[[cost]]`: every entry checked against the robot and the problem's contacts, in file order.
pub(super) fn check_costs(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
    contacts: &[String],
    goal: &[f64],
) -> Result<Vec<CostTerm>, ProblemError> {
    raw.cost
        .iter()
        .enumerate()
        .map(|(index, entry)| {
            entry.check(&CostCheck {
                ctx,
                index,
                robot,
                contacts,
                goal,
            })
        })
        .collect()
}

/// What [`with_cost_function`] hands each term to.
pub trait CostVisitor {
    /// The result.
    type Output;
    /// Called with the term's type.
    fn visit<C: CostFunction>(self, cost: &C) -> Self::Output;
}

/// The value of one placement of `term` on z.
pub fn cost_value<D: Scalar>(term: &CostTerm, sizes: CostSizes, z: &[D]) -> D {
    struct Value<'a, D> {
        z: &'a [D],
        sizes: CostSizes,
    }
    impl<D: Scalar> CostVisitor for Value<'_, D> {
        type Output = D;
        fn visit<C: CostFunction>(self, cost: &C) -> D {
            cost.value(self.z, self.sizes)
        }
    }
    with_cost_function(term, Value { z, sizes })
}

/// The closed-form Hessian of one placement of `term` on z, if the term has one
/// ([`CostFunction::hessian`]).
pub fn cost_hessian(term: &CostTerm, sizes: CostSizes, z: &[f64]) -> Option<DMatrix<f64>> {
    struct Hessian<'a> {
        z: &'a [f64],
        sizes: CostSizes,
    }
    impl CostVisitor for Hessian<'_> {
        type Output = Option<DMatrix<f64>>;
        fn visit<C: CostFunction>(self, cost: &C) -> Option<DMatrix<f64>> {
            cost.hessian(self.z, self.sizes)
        }
    }
    with_cost_function(term, Hessian { z, sizes })
}

/// What placement needs of a term: its name, its inputs and whether it is linear.
#[derive(Debug, Clone, Copy)]
pub struct CostDeclaration {
    /// See [`CostFunction::NAME`].
    pub name: &'static str,
    /// See [`CostFunction::INPUTS`].
    pub inputs: CostInputs,
    /// See [`CostFunction::LINEAR`].
    pub linear: bool,
}

/// The declaration of `term`.
pub fn declaration(term: &CostTerm) -> CostDeclaration {
    struct Declare;
    impl CostVisitor for Declare {
        type Output = CostDeclaration;
        fn visit<C: CostFunction>(self, _: &C) -> CostDeclaration {
            CostDeclaration {
                name: C::NAME,
                inputs: C::INPUTS,
                linear: C::LINEAR,
            }
        }
    }
    with_cost_function(term, Declare)
}

/// The first vector of `term` whose length does not fit the robot.
pub fn length_mismatch(term: &CostTerm, sizes: CostSizes) -> Option<LengthMismatch> {
    struct Check(CostSizes);
    impl CostVisitor for Check {
        type Output = Option<LengthMismatch>;
        fn visit<C: CostFunction>(self, cost: &C) -> Option<LengthMismatch> {
            cost.length_mismatch(self.0)
        }
    }
    with_cost_function(term, Check(sizes))
}

/// The name of a cost term in `Solution::objective_terms`.
pub fn term_name(term: &CostTerm) -> &'static str {
    declaration(term).name
}

/// ½ Σ w_i (a_i − b_i)² over paired slices.
fn half_weighted_square<D: Scalar>(w: &[f64], a: impl Iterator<Item = D>, b: &[f64]) -> D {
    a.zip(w.iter().zip(b))
        .fold(D::from(0.0), |acc, (ai, (&wi, &bi))| {
            let d = ai - D::from(bi);
            acc + d * d * D::from(0.5 * wi)
        })
}

/// ½ Σ w_i (b_i − a_i)² of z = [a; b], both halves of length `len`: the change of a
/// vector between two knots or intervals.
fn half_weighted_change<D: Scalar>(w: &[f64], z: &[D], len: usize) -> D {
    let zeros = vec![0.0; len];
    let diff = z[..len].iter().zip(&z[len..2 * len]).map(|(&a, &b)| b - a);
    half_weighted_square(w, diff, &zeros)
}

/// The constant Hessian of [`half_weighted_change`] over z = [a; b] (2·len): w on both
/// diagonals, −w between a_i and b_i.
fn change_hessian(w: &[f64], len: usize) -> DMatrix<f64> {
    let mut hess = DMatrix::zeros(2 * len, 2 * len);
    for (i, &wi) in w.iter().enumerate() {
        hess[(i, i)] = wi;
        hess[(len + i, len + i)] = wi;
        hess[(i, len + i)] = -wi;
        hess[(len + i, i)] = -wi;
    }
    hess
}

/// `Some` mismatch when `found` differs from `expected`.
fn mismatch(field: &'static str, expected: usize, found: usize) -> Option<LengthMismatch> {
    (expected != found).then_some((field, expected, found))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::finite_differences::jacobian as fd_jacobian;
    use crate::autodiff::{ScalarFunction, gradient, gradient_hessian};
    use crate::random::SeededRng;

    /// One placement of a term as an AD-able function.
    struct Placed<'a> {
        term: &'a CostTerm,
        sizes: CostSizes,
        dim: usize,
    }

    impl ScalarFunction for Placed<'_> {
        fn dim(&self) -> usize {
            self.dim
        }
        fn eval<D: Scalar>(&self, z: &[D]) -> D {
            cost_value(self.term, self.sizes, z)
        }
    }

    fn dim(inputs: CostInputs, s: CostSizes) -> usize {
        match inputs {
            CostInputs::IntervalWithStep | CostInputs::LastIntervalWithStep => 2 * s.n + 1,
            CostInputs::IntervalConfigurations => 2 * s.n,
            CostInputs::InputWithStep => s.m + 1,
            CostInputs::AdjacentInputs => 2 * s.m,
            CostInputs::AdjacentImpulses => 2 * s.nc,
            CostInputs::AdjacentIntervals => 3 * s.n + 2,
            CostInputs::LastConfiguration => s.n,
            CostInputs::Step => 1,
        }
    }

    /// Every closed-form cost Hessian against forward AD (to 1e-13 of the largest entry) and
    /// central differences of the AD gradient (1e-6), at random points with steps in
    /// [0.05, 0.3] and random targets, weights and both time weightings.
    #[test]
    fn closed_form_cost_hessians_match_ad_and_finite_differences() {
        let sizes = CostSizes { n: 4, m: 3, nc: 2 };
        let mut rng = SeededRng::new(7);
        let mut vector = |len: usize, lo: f64, hi: f64| -> Vec<f64> {
            (0..len).map(|_| lo + (hi - lo) * rng.unit()).collect()
        };
        let mut terms = Vec::new();
        for time_weighted in [true, false] {
            terms.push(CostTerm::StateTracking(StateTracking {
                q_target: vector(4, -1.0, 1.0),
                v_target: vector(4, -1.0, 1.0),
                q_weights: vector(4, 0.1, 2.0),
                v_weights: vector(4, 0.1, 2.0),
                time_weighted,
            }));
            terms.push(CostTerm::Input(Input {
                weights: vector(3, 0.1, 2.0),
                time_weighted,
            }));
        }
        terms.push(CostTerm::InputRate(InputRate {
            weights: vector(3, 0.1, 2.0),
        }));
        terms.push(CostTerm::FinalState(FinalState {
            q_target: vector(4, -1.0, 1.0),
            weights: vector(4, 0.1, 2.0),
        }));
        terms.push(CostTerm::VelocityDifference(VelocityDifference {
            weights: vector(4, 0.1, 2.0),
        }));
        terms.push(CostTerm::ImpulseRate(ImpulseRate {
            weights: vector(2, 0.1, 2.0),
        }));
        let mut checked = 0;
        for term in &terms {
            let declared = declaration(term);
            let dim = dim(declared.inputs, sizes);
            let f = Placed { term, sizes, dim };
            for _ in 0..3 {
                let mut z = vector(dim, -1.0, 1.0);
                let steps = match declared.inputs {
                    CostInputs::IntervalWithStep | CostInputs::InputWithStep => 1,
                    CostInputs::AdjacentIntervals => 2,
                    _ => 0,
                };
                for s in &mut z[dim - steps..] {
                    *s = 0.05 + 0.25 * s.abs();
                }
                let exact = cost_hessian(term, sizes, &z).expect("a closed form");
                let ad = gradient_hessian(&f, &z).2;
                let scale = ad.amax().max(1.0);
                assert!(
                    (&exact - &ad).amax() <= 1e-13 * scale,
                    "{}: closed form {exact} against AD {ad}",
                    declared.name
                );
                let fd_h = fd_jacobian(|x| gradient(&f, x).1, &z, |_| 1e-6);
                for c in 0..dim {
                    for r in 0..dim {
                        let fd = fd_h[(r, c)];
                        assert!(
                            (exact[(r, c)] - fd).abs() <= 1e-6 * exact[(r, c)].abs().max(1.0),
                            "{}: H[{r}, {c}] closed form {} fd {fd}",
                            declared.name,
                            exact[(r, c)]
                        );
                    }
                }
                checked += 1;
            }
        }
        assert_eq!(checked, 3 * terms.len());
    }
}
