//! Smoothness: the change of the inputs between adjacent intervals.

use super::{CostFunction, CostInputs, CostSizes, LengthMismatch, half_weighted_change, mismatch};
use crate::scalar::Scalar;

/// Σ_{k=2}^{N−1} ½ (u_k − u_{k−1})ᵀ diag(w) (u_k − u_{k−1}).
pub(super) struct InputRate<'a> {
    pub weights: &'a [f64],
}

impl CostFunction for InputRate<'_> {
    const NAME: &'static str = "input_rate";
    const INPUTS: CostInputs = CostInputs::AdjacentInputs;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        half_weighted_change(self.weights, z, sizes.m)
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("weights", sizes.m, self.weights.len())
    }
}
