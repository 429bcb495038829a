//! Duration: the total time of the trajectory.

use super::{CostFunction, CostInputs, CostSizes, LengthMismatch};
use crate::scalar::Scalar;

/// w · Σ_k h_k (total time).
pub(super) struct Time {
    pub weight: f64,
}

impl CostFunction for Time {
    const NAME: &'static str = "time";
    const INPUTS: CostInputs = CostInputs::Step;
    const LINEAR: bool = true;
    fn value<D: Scalar>(&self, z: &[D], _: CostSizes) -> D {
        z[0] * D::from(self.weight)
    }
    fn length_mismatch(&self, _: CostSizes) -> Option<LengthMismatch> {
        None
    }
}
