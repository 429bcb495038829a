//! Reaching a target configuration at the last knot.

use super::{CostFunction, CostInputs, CostSizes, LengthMismatch, half_weighted_square, mismatch};
use crate::scalar::Scalar;

/// ½ (q_N − q_target)ᵀ diag(w) (q_N − q_target).
pub(super) struct FinalState<'a> {
    pub q_target: &'a [f64],
    pub weights: &'a [f64],
}

impl CostFunction for FinalState<'_> {
    const NAME: &'static str = "final_state";
    const INPUTS: CostInputs = CostInputs::LastConfiguration;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        half_weighted_square(self.weights, z[..sizes.n].iter().copied(), self.q_target)
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("q_target", sizes.n, self.q_target.len()).or(mismatch(
            "weights",
            sizes.n,
            self.weights.len(),
        ))
    }
}
