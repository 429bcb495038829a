//! Tracking a target state at the midpoint of every interval.

use nalgebra::DMatrix;
use serde::Deserialize;

use super::{
    CheckCost, CostCheck, CostFunction, CostInputs, CostSizes, LengthMismatch,
    half_weighted_square, mismatch,
};
use crate::autodiff::Scalar;
use crate::discrete::midpoint_state;
use crate::problem::ProblemError;
use crate::problem::schema::NamedVector;

/// `type = "state_tracking"`: Σ_k [h_k] ½ (x̄_k − x_g)ᵀ diag(w_q, w_v) (x̄_k − x_g), midpoint
/// state x̄_k.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Target configuration: default the final goal (`final.q`); coordinates not named keep
    /// the goal's value.
    pub q_target: Option<NamedVector>,
    /// Target velocity (default zero).
    pub v_target: Option<NamedVector>,
    /// Weights on the configuration error, per coordinate.
    pub q_weights: NamedVector,
    /// Weights on the velocity error, per coordinate (default 0).
    pub v_weights: Option<NamedVector>,
    /// Multiply each interval's term by h_k (default true).
    pub time_weighted: Option<bool>,
}

/// Σ_k [h_k] ½ (x̄_k − x_g)ᵀ diag(w_q, w_v) (x̄_k − x_g), with the midpoint state
/// x̄_k = [(q_k+q_{k+1})/2 ; (q_{k+1}−q_k)/h_k] and target x_g = [q_target; v_target].
#[derive(Debug, Clone, PartialEq)]
pub struct StateTracking {
    /// q_target, per coordinate.
    pub q_target: Vec<f64>,
    /// v_target, per coordinate.
    pub v_target: Vec<f64>,
    /// w_q, per coordinate.
    pub q_weights: Vec<f64>,
    /// w_v, per coordinate.
    pub v_weights: Vec<f64>,
    /// Whether each interval's term is multiplied by h_k.
    pub time_weighted: bool,
}

impl CheckCost for StateTracking {
    type Entry = Entry;
    fn check(entry: &Entry, at: &CostCheck) -> Result<Self, ProblemError> {
        Ok(StateTracking {
            q_target: at.configuration_target("q_target", entry.q_target.as_ref())?,
            v_target: at.velocity_target("v_target", entry.v_target.as_ref())?,
            q_weights: at.coordinate_weights("q_weights", Some(&entry.q_weights))?,
            v_weights: at.coordinate_weights("v_weights", entry.v_weights.as_ref())?,
            time_weighted: entry.time_weighted.unwrap_or(true),
        })
    }
}

impl CostFunction for StateTracking {
    const NAME: &'static str = "state_tracking";
    const INPUTS: CostInputs = CostInputs::IntervalWithStep;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        let n = sizes.n;
        let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
        let (mid, vel) = midpoint_state(qa, qb, h);
        let value = half_weighted_square(&self.q_weights, mid.into_iter(), &self.q_target)
            + half_weighted_square(&self.v_weights, vel.into_iter(), &self.v_target);
        if self.time_weighted { value * h } else { value }
    }
    /// With e = q̄ − q_target, v̄ = (qb − qa)/h, r = v̄ − v_target and φ the untimed term:
    /// φ's Hessian is diagonal per coordinate i in (qa_i, qb_i), w_q/4 ± w_v/h², with
    /// ∂²φ/∂qa_i∂h = −∂²φ/∂qb_i∂h = w_v (v̄ + r)/h² and ∂²φ/∂h² = Σ w_v (v̄² + 2 r v̄)/h²;
    /// h·φ's is h·∇²φ + ∇φ e_hᵀ + e_h ∇φᵀ: (h w_q/4 ± w_v/h), ±w_v v̄/h + w_q e/2 and
    /// Σ w_v v̄²/h.
    fn hessian(&self, z: &[f64], sizes: CostSizes) -> Option<DMatrix<f64>> {
        let n = sizes.n;
        let h = z[2 * n];
        let mut hess = DMatrix::zeros(2 * n + 1, 2 * n + 1);
        let mut hh = 0.0;
        for i in 0..n {
            let (wq, wv) = (self.q_weights[i], self.v_weights[i]);
            let (a, b) = (z[i], z[n + i]);
            let v = (b - a) / h;
            let (diagonal, cross, with_h) = if self.time_weighted {
                let e = 0.5 * (a + b) - self.q_target[i];
                hh += wv * v * v / h;
                (
                    0.25 * wq * h + wv / h,
                    0.25 * wq * h - wv / h,
                    [wv * v / h + 0.5 * wq * e, -wv * v / h + 0.5 * wq * e],
                )
            } else {
                let r = v - self.v_target[i];
                let h2 = h * h;
                hh += wv * (v * v + 2.0 * r * v) / h2;
                let t = wv * (v + r) / h2;
                (0.25 * wq + wv / h2, 0.25 * wq - wv / h2, [t, -t])
            };
            hess[(i, i)] = diagonal;
            hess[(n + i, n + i)] = diagonal;
            hess[(i, n + i)] = cross;
            hess[(n + i, i)] = cross;
            for (k, value) in [i, n + i].into_iter().zip(with_h) {
                hess[(k, 2 * n)] = value;
                hess[(2 * n, k)] = value;
            }
        }
        hess[(2 * n, 2 * n)] = hh;
        Some(hess)
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        let n = sizes.n;
        mismatch("q_target", n, self.q_target.len())
            .or(mismatch("v_target", n, self.v_target.len()))
            .or(mismatch("q_weights", n, self.q_weights.len()))
            .or(mismatch("v_weights", n, self.v_weights.len()))
    }
}
