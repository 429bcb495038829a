//! Contact-mode smoothness: the change of each contact's normal impulse between adjacent
//! intervals, which a touchdown or lift-off makes large.

use nalgebra::DMatrix;
use serde::Deserialize;

use super::{
    CheckCost, CostCheck, CostFunction, CostInputs, CostSizes, LengthMismatch, change_hessian,
    half_weighted_change, mismatch,
};
use crate::autodiff::Scalar;
use crate::problem::ProblemError;
use crate::problem::schema::NamedVector;

/// `type = "impulse_rate"`: Σ_k ½ Σ_i w_i (c_{k,i} − c_{k−1,i})², c the normal impulses.
/// Exactly one of `weight` (every contact) and `weights` (by contact name).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// One weight for every contact.
    pub weight: Option<f64>,
    /// Weights per contact, by name (`default` for the others) or as an array.
    pub weights: Option<NamedVector>,
}

/// Σ_{k=2}^{N−1} ½ Σ_i w_i (c_{k,i} − c_{k−1,i})² over the problem's contacts i, with c in the
/// problem's impulse unit (mass·length/time: N·s in SI); w in cost per impulse².
#[derive(Debug, Clone, PartialEq)]
pub struct ImpulseRate {
    /// w, per contact (in the problem's contact order).
    pub weights: Vec<f64>,
}

impl CheckCost for ImpulseRate {
    type Entry = Entry;
    fn check(entry: &Entry, at: &CostCheck) -> Result<Self, ProblemError> {
        let weights = match (entry.weight, &entry.weights) {
            (Some(w), None) => vec![at.nonnegative("weight", w)?; at.contact_count()],
            (None, Some(weights)) => at.contact_weights("weights", weights)?,
            (Some(_), Some(_)) => {
                return Err(at.invalid(
                    "weights",
                    "both `weight` and `weights` are given; keep `weight` for one weight on \
                     every contact or `weights` for weights by contact name",
                ));
            }
            (None, None) => {
                return Err(at.invalid(
                    "weight",
                    "missing; give `weight = w` (every contact) or `weights = { NAME = w }`",
                ));
            }
        };
        Ok(ImpulseRate { weights })
    }
}

impl CostFunction for ImpulseRate {
    const NAME: &'static str = "impulse_rate";
    const INPUTS: CostInputs = CostInputs::AdjacentImpulses;
    fn value<D: Scalar>(&self, z: &[D], sizes: CostSizes) -> D {
        half_weighted_change(&self.weights, z, sizes.nc)
    }
    /// Constant: w on both diagonals, −w between c_{j−1} and c_j.
    fn hessian(&self, _z: &[f64], sizes: CostSizes) -> Option<DMatrix<f64>> {
        Some(change_hessian(&self.weights, sizes.nc))
    }
    fn length_mismatch(&self, sizes: CostSizes) -> Option<LengthMismatch> {
        mismatch("weights", sizes.nc, self.weights.len())
    }
}
