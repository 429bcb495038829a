//! Effort: the inputs squared on every interval.

use nalgebra::DMatrix;
use serde::Deserialize;

use super::{
    CheckCost, CostCheck, CostFunction, CostInputs, CostSizes, LengthMismatch,
    half_weighted_square, mismatch,
};
use crate::autodiff::Scalar;
use crate::problem::ProblemError;
use crate::problem::schema::NamedVector;

/// `type = "input"`: Σ_k [h_k] ½ u_kᵀ diag(w) u_k.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Weights per input.
    pub weights: NamedVector,
    /// Multiply by h_k (default true).
    pub time_weighted: Option<bool>,
}

/// Σ_k [h_k] ½ u_kᵀ diag(w) u_k.
#[derive(Debug, Clone, PartialEq)]
pub struct Input {
    /// w, per input.
    pub weights: Vec<f64>,
    /// Whether each interval's term is multiplied by h_k.
    pub time_weighted: bool,
}

impl CheckCost for Input {
    type Entry = Entry;
    fn check(entry: &Entry, at: &CostCheck) -> Result<Self, ProblemError> {
        Ok(Input {
            weights: at.input_weights("weights", &entry.weights)?,
            time_weighted: entry.time_weighted.unwrap_or(true),
        })
    }
}

impl CostFunction for Input {
    const NAME: &'static str = "input";
    const INPUTS: CostInputs = CostInputs::InputWithStep;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        let m = sizes.m;
        let zeros = vec![0.0; m];
        let value = half_weighted_square(&self.weights, z[..m].iter().copied(), &zeros);
        if self.time_weighted {
            value * z[m]
        } else {
            value
        }
    }
    /// w on the diagonal (times h), and w_j u_j between u_j and h when time-weighted.
    fn hessian(&self, z: &[f64], sizes: CostSizes) -> Option<DMatrix<f64>> {
        let m = sizes.m;
        let mut hess = DMatrix::zeros(m + 1, m + 1);
        for (j, &w) in self.weights.iter().enumerate() {
            if self.time_weighted {
                hess[(j, j)] = w * z[m];
                hess[(j, m)] = w * z[j];
                hess[(m, j)] = w * z[j];
            } else {
                hess[(j, j)] = w;
            }
        }
        Some(hess)
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("weights", sizes.m, self.weights.len())
    }
}
