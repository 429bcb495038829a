//! Arriving at the last knot with a target velocity (zero for an apex or a stop): the
//! velocity part of the goal state in the paper's eq. 37, which `final_state` leaves out.

use serde::Deserialize;

use super::{
    CheckCost, CostCheck, CostFunction, CostInputs, CostSizes, LengthMismatch,
    half_weighted_square, mismatch,
};
use crate::autodiff::Scalar;
use crate::discrete::difference_velocity;
use crate::problem::ProblemError;
use crate::problem::schema::NamedVector;

/// `type = "final_velocity"`: ½ (v_N − v_target)ᵀ diag(w) (v_N − v_target) with the last
/// interval's velocity v_N = (q_N − q_{N−1}) / h_{N−1}, in coordinate units per time unit.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Target velocity per coordinate (default zero; coordinates not named are zero).
    pub v_target: Option<NamedVector>,
    /// Weights per coordinate, in cost units per (coordinate unit / time unit)².
    pub weights: NamedVector,
}

/// ½ (v_N − v_target)ᵀ diag(w) (v_N − v_target), v_N = (q_N − q_{N−1}) / h_{N−1}.
#[derive(Debug, Clone, PartialEq)]
pub struct FinalVelocity {
    /// v_target, per coordinate.
    pub v_target: Vec<f64>,
    /// w, per coordinate.
    pub weights: Vec<f64>,
}

impl CheckCost for FinalVelocity {
    type Entry = Entry;
    fn check(entry: &Entry, at: &CostCheck) -> Result<Self, ProblemError> {
        Ok(FinalVelocity {
            v_target: at.velocity_target("v_target", entry.v_target.as_ref())?,
            weights: at.coordinate_weights("weights", Some(&entry.weights))?,
        })
    }
}

impl CostFunction for FinalVelocity {
    const NAME: &'static str = "final_velocity";
    const INPUTS: CostInputs = CostInputs::LastIntervalWithStep;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        let n = sizes.n;
        let velocity = difference_velocity(&z[..n], &z[n..2 * n], z[2 * n]);
        half_weighted_square(&self.weights, velocity.into_iter(), &self.v_target)
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("v_target", sizes.n, self.v_target.len()).or(mismatch(
            "weights",
            sizes.n,
            self.weights.len(),
        ))
    }
}
