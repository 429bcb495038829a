//! Smoothness: the change of the velocity between adjacent intervals (the c1 term of the
//! paper's eq. 36).

use serde::Deserialize;

use super::{CheckCost, CostCheck, CostFunction, CostInputs, CostSizes, LengthMismatch, mismatch};
use crate::autodiff::Scalar;
use crate::problem::ProblemError;
use crate::problem::schema::NamedVector;

/// `type = "velocity_difference"`: Σ_k ½ (v_k − v_{k−1})ᵀ diag(w) (v_k − v_{k−1}) with the
/// interval velocities v_k = (q_{k+1} − q_k) / h_k.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Weights per coordinate.
    pub weights: NamedVector,
}

/// Σ_{k=2}^{N−1} ½ (v_k − v_{k−1})ᵀ diag(w) (v_k − v_{k−1}), v_k = (q_{k+1} − q_k) / h_k.
#[derive(Debug, Clone, PartialEq)]
pub struct VelocityDifference {
    /// w, per coordinate.
    pub weights: Vec<f64>,
}

impl CheckCost for VelocityDifference {
    type Entry = Entry;
    fn check(entry: &Entry, at: &CostCheck) -> Result<Self, ProblemError> {
        Ok(VelocityDifference {
            weights: at.coordinate_weights("weights", Some(&entry.weights))?,
        })
    }
}

impl CostFunction for VelocityDifference {
    const NAME: &'static str = "velocity_difference";
    const INPUTS: CostInputs = CostInputs::AdjacentIntervals;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        let n = sizes.n;
        let (h_before, h_after) = (z[3 * n], z[3 * n + 1]);
        (0..n).fold(D::from(0.0), |acc, c| {
            let before = (z[n + c] - z[c]) / h_before;
            let after = (z[2 * n + c] - z[n + c]) / h_after;
            let d = after - before;
            acc + d * d * D::from(0.5 * self.weights[c])
        })
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("weights", sizes.n, self.weights.len())
    }
}
