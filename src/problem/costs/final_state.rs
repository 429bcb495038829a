//! Reaching a target configuration at the last knot.

use nalgebra::DMatrix;
use serde::Deserialize;

use super::{
    CheckCost, CostCheck, CostFunction, CostInputs, CostSizes, LengthMismatch,
    half_weighted_square, mismatch,
};
use crate::autodiff::Scalar;
use crate::problem::ProblemError;
use crate::problem::schema::NamedVector;

/// `type = "final_state"`: ½ (q_N − q_target)ᵀ diag(w) (q_N − q_target).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Target (default: the final goal).
    pub q_target: Option<NamedVector>,
    /// Weights per coordinate.
    pub weights: NamedVector,
}

/// ½ (q_N − q_target)ᵀ diag(w) (q_N − q_target).
#[derive(Debug, Clone, PartialEq)]
pub struct FinalState {
    /// q_target, per coordinate.
    pub q_target: Vec<f64>,
    /// w, per coordinate.
    pub weights: Vec<f64>,
}

impl CheckCost for FinalState {
    type Entry = Entry;
    fn check(entry: &Entry, at: &CostCheck) -> Result<Self, ProblemError> {
        Ok(FinalState {
            q_target: at.configuration_target("q_target", entry.q_target.as_ref())?,
            weights: at.coordinate_weights("weights", Some(&entry.weights))?,
        })
    }
}

impl CostFunction for FinalState {
    const NAME: &'static str = "final_state";
    const INPUTS: CostInputs = CostInputs::LastConfiguration;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        half_weighted_square(&self.weights, z[..sizes.n].iter().copied(), &self.q_target)
    }
    /// Constant: diag(w).
    fn hessian(&self, _z: &[f64], _sizes: CostSizes) -> Option<DMatrix<f64>> {
        Some(DMatrix::from_diagonal(&self.weights.clone().into()))
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("q_target", sizes.n, self.q_target.len()).or(mismatch(
            "weights",
            sizes.n,
            self.weights.len(),
        ))
    }
}
