//! What the transcription needs from a robot: discrete mechanics and contact-point positions.
//!
//! The NLP is written once against this trait; [`crate::transcription::solve`] implements it
//! for a URDF [`crate::model::Model`] through [`crate::discrete`], and tests implement it in
//! closed form for SPEC.md's hopper and brick. Every method is generic over
//! [`Scalar`] so that the blocks built on it are differentiated by forward AD.

use crate::model::Scalar;
use crate::problem::{Integrator, Interval};

/// Discrete mechanics and contact kinematics of one robot, in its coordinate order.
pub trait Mechanics: Sync {
    /// Number of generalized coordinates n.
    fn nq(&self) -> usize;
    /// Number of inputs m.
    fn nu(&self) -> usize;
    /// Number of holonomic loop-closure constraints (0 for trees).
    fn num_loop_constraints(&self) -> usize {
        0
    }
    /// Number of contact points (in the problem's contact order).
    fn num_contacts(&self) -> usize;
    /// Coordinate limits from the model (URDF joint limits), length n; ±∞ where none.
    fn coordinate_limits(&self) -> Vec<Interval> {
        vec![Interval::FREE; self.nq()]
    }
    /// Coordinate names (length n), used in solutions.
    fn coordinate_names(&self) -> Vec<String> {
        (0..self.nq()).map(|i| format!("q{i}")).collect()
    }
    /// Input names (length m), used in solutions.
    fn input_names(&self) -> Vec<String> {
        (0..self.nu()).map(|i| format!("u{i}")).collect()
    }
    /// Whether the discrete force Fd can be nonzero (inputs or damping present).
    fn has_discrete_force(&self) -> bool;

    /// Discrete Lagrangian Ld(qa, qb, h) of one interval (qa, qb length n; h > 0).
    fn discrete_lagrangian<D: Scalar>(&self, integrator: Integrator, qa: &[D], qb: &[D], h: D)
    -> D;
    /// Discrete generalized force Fd(qa, qb, u, h) of one interval into `out` (length n):
    /// h·B(q̄)u − diag(d)(qb − qa) for the midpoint rule (SPEC.md).
    fn discrete_force<D: Scalar>(
        &self,
        integrator: Integrator,
        qa: &[D],
        qb: &[D],
        u: &[D],
        h: D,
        out: &mut [D],
    );
    /// Generalized momentum M(q)v into `out` (length n).
    fn momentum<D: Scalar>(&self, q: &[D], v: &[D], out: &mut [D]);
    /// World position of contact point `contact` at configuration q (length units).
    fn contact_position<D: Scalar>(&self, contact: usize, q: &[D]) -> [D; 3];
    /// Loop-closure residual a(q) into `out` (length `num_loop_constraints`).
    fn loop_residual<D: Scalar>(&self, _q: &[D], _out: &mut [D]) {}
}
