//! Cost terms: one file per term, each a type implementing [`CostFunction`], which declares
//! the knot-local variables the term reads ([`CostInputs`]) and its value on them. Placement
//! (`super::placement`) reads the declaration, so a term's input layout is written once.
//!
//! To add a term: a file here with its type and [`CostFunction`] impl, a variant of
//! [`CostTerm`] (`problem/spec.rs`) with its schema entry and validation arm, and one arm in
//! [`with_cost_function`].

mod configuration_difference;
mod final_state;
mod input;
mod input_rate;
mod state_tracking;
mod time;

use configuration_difference::ConfigurationDifference;
use final_state::FinalState;
use input::Input;
use input_rate::InputRate;
use state_tracking::StateTracking;
use time::Time;

use crate::problem::CostTerm;
use crate::scalar::Scalar;

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
    /// z = [q_N], the last knot, once.
    LastConfiguration,
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
    /// The first vector of the term whose length does not fit n coordinates and m inputs.
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch>;
}

/// What [`with_cost_function`] hands each term to.
pub trait CostVisitor {
    /// The result.
    type Output;
    /// Called with the term's type.
    fn visit<C: CostFunction>(self, cost: C) -> Self::Output;
}

/// Calls `visitor` with the [`CostFunction`] of `term`: the one place where the problem's
/// cost terms meet their types.
pub fn with_cost_function<V: CostVisitor>(term: &CostTerm, visitor: V) -> V::Output {
    match term {
        CostTerm::StateTracking {
            q_target,
            v_target,
            q_weights,
            v_weights,
            time_weighted,
        } => visitor.visit(StateTracking {
            q_target,
            v_target,
            q_weights,
            v_weights,
            time_weighted: *time_weighted,
        }),
        CostTerm::Input {
            weights,
            time_weighted,
        } => visitor.visit(Input {
            weights,
            time_weighted: *time_weighted,
        }),
        CostTerm::InputRate { weights } => visitor.visit(InputRate { weights }),
        CostTerm::ConfigurationDifference { weights } => {
            visitor.visit(ConfigurationDifference { weights })
        }
        CostTerm::FinalState { q_target, weights } => {
            visitor.visit(FinalState { q_target, weights })
        }
        CostTerm::Time { weight } => visitor.visit(Time { weight: *weight }),
    }
}

/// The value of one placement of `term` on z.
pub fn cost_value<D: Scalar>(term: &CostTerm, sizes: CostSizes, z: &[D]) -> D {
    struct Value<'a, D> {
        z: &'a [D],
        sizes: CostSizes,
    }
    impl<D: Scalar> CostVisitor for Value<'_, D> {
        type Output = D;
        fn visit<C: CostFunction>(self, cost: C) -> D {
            cost.value(self.z, self.sizes)
        }
    }
    with_cost_function(term, Value { z, sizes })
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
        fn visit<C: CostFunction>(self, _: C) -> CostDeclaration {
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
        fn visit<C: CostFunction>(self, cost: C) -> Option<LengthMismatch> {
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

/// `Some` mismatch when `found` differs from `expected`.
fn mismatch(field: &'static str, expected: usize, found: usize) -> Option<LengthMismatch> {
    (expected != found).then_some((field, expected, found))
}
