//! h_a − h_b, an equal-step row (free equal steps); z = [h_a; h_b]. Linear: generic AD.

use super::{Context, RowBlock};
use crate::autodiff::Scalar;
use crate::discrete::Mechanics;

/// h_a − h_b.
#[derive(Debug, Clone, PartialEq)]
pub struct EqualStep;

impl RowBlock for EqualStep {
    const NAME: &'static str = "EqualStep";
    fn value<D: Scalar, M: Mechanics>(&self, _: &M, _: &Context, z: &[D], out: &mut [D]) {
        out[0] = z[0] - z[1]
    }
}
