//! Smoothness: the change of the configuration over every interval.

use super::{
    CheckCost, CostCheck, CostFunction, CostInputs, CostSizes, LengthMismatch,
    half_weighted_change, mismatch,
};
use crate::autodiff::Scalar;
use crate::problem::ProblemError;

/// `type = "configuration_difference"`: Σ_k ½ (q_{k+1} − q_k)ᵀ diag(w) (q_{k+1} − q_k).
///
/// Its weights are per coordinate.
pub type Entry = super::WeightsEntry;

/// Σ_{k=1}^{N−1} ½ (q_{k+1} − q_k)ᵀ diag(w) (q_{k+1} − q_k).
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigurationDifference {
    /// w, per coordinate.
    pub weights: Vec<f64>,
}

impl CheckCost for ConfigurationDifference {
    type Entry = Entry;
    fn check(entry: &Entry, at: &CostCheck) -> Result<Self, ProblemError> {
        Ok(ConfigurationDifference {
            weights: at.coordinate_weights("weights", Some(&entry.weights))?,
        })
    }
}

impl CostFunction for ConfigurationDifference {
    const NAME: &'static str = "configuration_difference";
    const INPUTS: CostInputs = CostInputs::IntervalConfigurations;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        half_weighted_change(&self.weights, z, sizes.n)
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("weights", sizes.n, self.weights.len())
    }
}
