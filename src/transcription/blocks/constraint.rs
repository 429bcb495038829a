//! The rows of the problem file's constraint `index` (`problem::constraints`); z as it
//! declares. Generic AD.

use super::{Context, RowBlock};
use crate::autodiff::Scalar;
use crate::discrete::Mechanics;

/// The problem file's constraint `index`.
#[derive(Debug, Clone, PartialEq)]
pub struct Constraint {
    /// Its index in the problem's constraints.
    pub index: usize,
}

impl RowBlock for Constraint {
    const NAME: &'static str = "Constraint";
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        ctx.constraints[self.index].value(mech, z, out)
    }
}
