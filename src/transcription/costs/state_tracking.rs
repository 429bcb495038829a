//! Tracking a target state at the midpoint of every interval.

use super::{CostFunction, CostInputs, CostSizes, LengthMismatch, half_weighted_square, mismatch};
use crate::discrete::midpoint_state;
use crate::scalar::Scalar;

/// Σ_k [h_k] ½ (x̄_k − x_g)ᵀ diag(w_q, w_v) (x̄_k − x_g), with the midpoint state
/// x̄_k = [(q_k+q_{k+1})/2 ; (q_{k+1}−q_k)/h_k] and target x_g = [q_target; v_target].
pub(super) struct StateTracking<'a> {
    pub q_target: &'a [f64],
    pub v_target: &'a [f64],
    pub q_weights: &'a [f64],
    pub v_weights: &'a [f64],
    pub time_weighted: bool,
}

impl CostFunction for StateTracking<'_> {
    const NAME: &'static str = "state_tracking";
    const INPUTS: CostInputs = CostInputs::IntervalWithStep;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        let n = sizes.n;
        let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
        let (mid, vel) = midpoint_state(qa, qb, h);
        let value = half_weighted_square(self.q_weights, mid.into_iter(), self.q_target)
            + half_weighted_square(self.v_weights, vel.into_iter(), self.v_target);
        if self.time_weighted { value * h } else { value }
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        let n = sizes.n;
        mismatch("q_target", n, self.q_target.len())
            .or(mismatch("v_target", n, self.v_target.len()))
            .or(mismatch("q_weights", n, self.q_weights.len()))
            .or(mismatch("v_weights", n, self.v_weights.len()))
    }
}
