//! Periodic velocity through the discrete Legendre transform (the paper's HAMR gaits): the
//! momentum arriving at the last knot equals the momentum the first knot starts from.

use serde::Deserialize;

use super::{
    CheckConstraint, ConstraintCheck, ConstraintFunction, ConstraintInput, ConstraintRow, KnotRef,
};
use crate::autodiff::Scalar;
use crate::discrete::Mechanics;
use crate::problem::ProblemError;

/// `[[constraint]] type = "periodic_momentum"`: p_N⁻ = M(q_1)v_0 on every coordinate.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {}

/// n rows: D2Ld(q_{N−1}, q_N, h_{N−1}) + ½Fd(q_{N−1}, q_N, u_{N−1}, h_{N−1}) − M(q_1)v_0 = 0.
///
/// The left part is the discrete Legendre transform p_N⁻ of the last interval (the momentum
/// the DEL row of a next knot would start from); M(q_1)v_0 is the momentum the first knot's
/// row starts from. With q_N = q_1 up to a translation, which leaves M unchanged, equal
/// momenta are equal velocities: the state, not only the configuration, repeats. Unlike the
/// finite-difference velocity of `periodic`, this is the integrator's own velocity at the
/// knot, so the repeated gait continues with the same discrete dynamics.
///
/// The value here is −M(q_1)v_0; p_N⁻ is added by the last interval's DEL blocks
/// ([`ConstraintFunction::receives_end_momentum`]). Differentiating D2Ld inside this block
/// by generic AD cost HAMR seconds per Hessian (n dual passes of Ld under every tile pair).
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicMomentum {
    /// Coordinate names (for row labels).
    pub names: Vec<String>,
}

impl CheckConstraint for PeriodicMomentum {
    type Entry = Entry;
    fn check(_: &Entry, at: &ConstraintCheck) -> Result<Self, ProblemError> {
        Ok(PeriodicMomentum {
            names: at.coordinate_names().to_vec(),
        })
    }
}

impl ConstraintFunction for PeriodicMomentum {
    const NAME: &'static str = "periodic_momentum";

    /// z = [q_1; v_0]; the last interval's part comes from its DEL blocks.
    fn inputs(&self) -> Vec<ConstraintInput> {
        vec![
            ConstraintInput::Configuration(KnotRef::First(0)),
            ConstraintInput::InitialVelocity,
        ]
    }

    fn rows(&self) -> Vec<ConstraintRow> {
        self.names
            .iter()
            .map(|name| ConstraintRow::equality(format!("periodic momentum {name}")))
            .collect()
    }

    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, z: &[D], out: &mut [D]) {
        let (q_first, v_first) = z.split_at(mech.nq());
        mech.momentum(q_first, v_first, out);
        for o in out.iter_mut() {
            *o = -*o;
        }
    }

    fn receives_end_momentum(&self) -> bool {
        true
    }
}
