//! Smoothness: the change of the inputs between adjacent intervals.

use nalgebra::DMatrix;

use super::{
    CheckCost, CostCheck, CostFunction, CostInputs, CostSizes, LengthMismatch, change_hessian,
    half_weighted_change, mismatch,
};
use crate::autodiff::Scalar;
use crate::problem::ProblemError;

/// `type = "input_rate"`: Σ_k ½ (u_k − u_{k−1})ᵀ diag(w) (u_k − u_{k−1}).
///
/// Its weights are per input.
pub type Entry = super::WeightsEntry;

/// Σ_{k=2}^{N−1} ½ (u_k − u_{k−1})ᵀ diag(w) (u_k − u_{k−1}).
#[derive(Debug, Clone, PartialEq)]
pub struct InputRate {
    /// w, per input.
    pub weights: Vec<f64>,
}

impl CheckCost for InputRate {
    type Entry = Entry;
    fn check(entry: &Entry, at: &CostCheck) -> Result<Self, ProblemError> {
        Ok(InputRate {
            weights: at.input_weights("weights", &entry.weights)?,
        })
    }
}

impl CostFunction for InputRate {
    const NAME: &'static str = "input_rate";
    const INPUTS: CostInputs = CostInputs::AdjacentInputs;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        half_weighted_change(&self.weights, z, sizes.m)
    }
    /// Constant: w on both diagonals, −w between u_{j−1} and u_j.
    fn hessian(&self, _z: &[f64], sizes: CostSizes) -> Option<DMatrix<f64>> {
        Some(change_hessian(&self.weights, sizes.m))
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("weights", sizes.m, self.weights.len())
    }
}
