//! Cost term `term` of the problem on one placement (an interval, or the last knot); z as
//! the term declares ([`crate::problem::costs::CostInputs`]). Each term's value is in its
//! own file under `crate::problem::costs`; derivatives by generic AD.

use super::{Context, GradientBlock};
use crate::autodiff::Scalar;
use crate::discrete::Mechanics;
use crate::problem::costs::{CostSizes, cost_value};

/// The problem's cost term `term`.
#[derive(Debug, Clone, PartialEq)]
pub struct Cost {
    /// Its index in the problem's cost terms.
    pub term: usize,
}

impl GradientBlock for Cost {
    const NAME: &'static str = "Cost";
    fn value<D: Scalar, M: Mechanics>(&self, _: &M, ctx: &Context, z: &[D]) -> D {
        let sizes = CostSizes { n: ctx.n, m: ctx.m };
        cost_value(&ctx.costs[self.term], sizes, z)
    }
}
