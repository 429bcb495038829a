//! Effort: the inputs squared on every interval.

use super::{CostFunction, CostInputs, CostSizes, LengthMismatch, half_weighted_square, mismatch};
use crate::scalar::Scalar;

/// Σ_k [h_k] ½ u_kᵀ diag(w) u_k.
pub(super) struct Input<'a> {
    pub weights: &'a [f64],
    pub time_weighted: bool,
}

impl CostFunction for Input<'_> {
    const NAME: &'static str = "input";
    const INPUTS: CostInputs = CostInputs::InputWithStep;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        let m = sizes.m;
        let zeros = vec![0.0; m];
        let value = half_weighted_square(self.weights, z[..m].iter().copied(), &zeros);
        if self.time_weighted {
            value * z[m]
        } else {
            value
        }
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("weights", sizes.m, self.weights.len())
    }
}
