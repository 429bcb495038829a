//! Tracking a target state at the midpoint of every interval.

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
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        let n = sizes.n;
        mismatch("q_target", n, self.q_target.len())
            .or(mismatch("v_target", n, self.v_target.len()))
            .or(mismatch("q_weights", n, self.q_weights.len()))
            .or(mismatch("v_weights", n, self.v_weights.len()))
    }
}
