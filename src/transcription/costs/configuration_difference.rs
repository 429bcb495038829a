//! Smoothness: the change of the configuration over every interval.

use super::{CostFunction, CostInputs, CostSizes, LengthMismatch, half_weighted_change, mismatch};
use crate::scalar::Scalar;

/// Σ_{k=1}^{N−1} ½ (q_{k+1} − q_k)ᵀ diag(w) (q_{k+1} − q_k).
pub(super) struct ConfigurationDifference<'a> {
    pub weights: &'a [f64],
}

impl CostFunction for ConfigurationDifference<'_> {
    const NAME: &'static str = "configuration_difference";
    const INPUTS: CostInputs = CostInputs::IntervalConfigurations;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        half_weighted_change(self.weights, z, sizes.n)
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("weights", sizes.n, self.weights.len())
    }
}
