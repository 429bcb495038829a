//! Duration: the total time of the trajectory.

use serde::Deserialize;

use super::{CheckCost, CostCheck, CostFunction, CostInputs, CostSizes, LengthMismatch};
use crate::autodiff::Scalar;
use crate::problem::ProblemError;

/// `type = "time"`: w · total time.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Weight per unit of time.
    pub weight: f64,
}

/// w · Σ_k h_k (total time).
#[derive(Debug, Clone, PartialEq)]
pub struct Time {
    /// w, per unit of time.
    pub weight: f64,
}

impl CheckCost for Time {
    type Entry = Entry;
    fn check(entry: &Entry, at: &CostCheck) -> Result<Self, ProblemError> {
        Ok(Time {
            weight: at.nonnegative("weight", entry.weight)?,
        })
    }
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
