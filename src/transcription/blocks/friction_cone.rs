//! μ c − eᵀβ, the friction-cone row; z = [c; β]. Linear: generic AD.

use super::{Context, RowBlock};
use crate::autodiff::Scalar;
use crate::contact;
use crate::discrete::Mechanics;

/// Contact `contact`'s friction cone.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionCone {
    /// The contact.
    pub contact: usize,
}

impl RowBlock for FrictionCone {
    const NAME: &'static str = "FrictionCone";
    fn value<D: Scalar, M: Mechanics>(&self, _: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        out[0] = contact::friction_cone(&ctx.contact, self.contact, z)
    }
}
