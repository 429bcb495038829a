//! Smoothness: the change of the velocity between adjacent intervals (the c1 term of the
//! paper's eq. 36).

use nalgebra::DMatrix;

use super::{CheckCost, CostCheck, CostFunction, CostInputs, CostSizes, LengthMismatch, mismatch};
use crate::autodiff::Scalar;
use crate::problem::ProblemError;

/// `type = "velocity_difference"`: Σ_k ½ (v_k − v_{k−1})ᵀ diag(w) (v_k − v_{k−1}) with the
/// interval velocities v_k = (q_{k+1} − q_k) / h_k.
///
/// Its weights are per coordinate.
pub type Entry = super::WeightsEntry;

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
    /// Per coordinate i, d = v₂ − v₁ with v₁ = (b − a)/h₁, v₂ = (c − b)/h₂ over
    /// (a, b, c, h₁, h₂) = (q_{k−1,i}, q_{k,i}, q_{k+1,i}, h_{k−1}, h_k) adds
    /// w (∇d ∇dᵀ + d ∇²d): ∇d = (1/h₁, −1/h₁ − 1/h₂, 1/h₂, v₁/h₁, −v₂/h₂), and ∇²d has
    /// ∓1/h₁² at (a, h₁), (b, h₁), ±1/h₂² at (b, h₂), (c, h₂), −2v₁/h₁² at (h₁, h₁) and
    /// 2v₂/h₂² at (h₂, h₂).
    fn hessian(&self, z: &[f64], sizes: CostSizes) -> Option<DMatrix<f64>> {
        let n = sizes.n;
        let (h1, h2) = (z[3 * n], z[3 * n + 1]);
        let mut hess = DMatrix::zeros(3 * n + 2, 3 * n + 2);
        for (i, &w) in self.weights.iter().enumerate() {
            let v1 = (z[n + i] - z[i]) / h1;
            let v2 = (z[2 * n + i] - z[n + i]) / h2;
            let d = v2 - v1;
            let at = [i, n + i, 2 * n + i, 3 * n, 3 * n + 1];
            let grad = [1.0 / h1, -1.0 / h1 - 1.0 / h2, 1.0 / h2, v1 / h1, -v2 / h2];
            for (r, gr) in at.iter().zip(grad) {
                for (c, gc) in at.iter().zip(grad) {
                    hess[(*r, *c)] += w * gr * gc;
                }
            }
            let (s1, s2) = (w * d / (h1 * h1), w * d / (h2 * h2));
            for (r, c, value) in [
                (i, 3 * n, -s1),
                (n + i, 3 * n, s1),
                (n + i, 3 * n + 1, s2),
                (2 * n + i, 3 * n + 1, -s2),
            ] {
                hess[(r, c)] += value;
                hess[(c, r)] += value;
            }
            hess[(3 * n, 3 * n)] -= 2.0 * v1 * s1;
            hess[(3 * n + 1, 3 * n + 1)] += 2.0 * v2 * s2;
        }
        Some(hess)
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("weights", sizes.n, self.weights.len())
    }
}
