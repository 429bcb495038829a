//! Periodic velocity through the discrete Legendre transform (the paper's HAMR gaits): the
//! momentum arriving at the last knot equals the momentum the first knot starts from.

use num_dual::Dual;
use serde::Deserialize;

use super::{
    CheckConstraint, ConstraintCheck, ConstraintFunction, ConstraintInput, ConstraintRow, KnotRef,
};
use crate::discrete::Mechanics;
use crate::problem::ProblemError;
use crate::scalar::Scalar;

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

    /// z = [q_{N−1}; q_N; h_{N−1}; u_{N−1}; q_1; v_0].
    fn inputs(&self) -> Vec<ConstraintInput> {
        vec![
            ConstraintInput::Configuration(KnotRef::Last(1)),
            ConstraintInput::Configuration(KnotRef::Last(0)),
            ConstraintInput::Step(KnotRef::Last(0)),
            ConstraintInput::Inputs(KnotRef::Last(0)),
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
        let (n, m) = (mech.nq(), mech.nu());
        let (qa, rest) = z.split_at(n);
        let (qb, rest) = rest.split_at(n);
        let (h, rest) = (rest[0], &rest[1..]);
        let (u, rest) = rest.split_at(m);
        let (q_first, v_first) = rest.split_at(n);
        mech.discrete_force(qa, qb, u, h, out);
        let mut start = vec![D::from(0.0); n];
        mech.momentum(q_first, v_first, &mut start);
        let lifted = |q: &[D]| -> Vec<Dual<D>> { q.iter().map(|&x| Dual::from_re(x)).collect() };
        let (qa_dual, h_dual) = (lifted(qa), Dual::from_re(h));
        for i in 0..n {
            // D2Ld_i: the derivative along the i-th coordinate of the segment's end.
            let mut qb_dual = lifted(qb);
            qb_dual[i].eps = D::from(1.0);
            let d2 = mech.discrete_lagrangian(&qa_dual, &qb_dual, h_dual).eps;
            out[i] = d2 + out[i] * D::from(0.5) - start[i];
        }
    }
}
