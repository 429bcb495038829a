//! The semi-implicit Euler residual at a knot (eq. 1, `Integrator::Euler`); z = [v_0; q_0;
//! q_1; h_0; u_0] at the first step, else [q_{k−1}; q_k; q_{k+1}; h_{k−1}; h_k; u_k].
//! Generic AD.

use super::{Context, RowBlock};
use crate::autodiff::Scalar;
use crate::discrete::{Mechanics, euler_knot};

/// The Euler residual at a knot.
#[derive(Debug, Clone, PartialEq)]
pub struct EulerKnot {
    /// Whether the knot is the first (v_0 instead of q_{k−1}).
    pub first_step: bool,
}

impl RowBlock for EulerKnot {
    const NAME: &'static str = "EulerKnot";
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Context, z: &[D], out: &mut [D]) {
        euler_knot(mech, self.first_step, z, out)
    }
}
