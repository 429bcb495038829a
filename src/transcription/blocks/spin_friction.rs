//! The spin part of a rolling sphere's friction impulse in the DEL rows (its friction
//! directions are no gradient, so it is not in [`super::ContactWork`]); z = [q; c_i; β_i],
//! out length n. Generic AD.

use super::{Context, RowBlock};
use crate::autodiff::Scalar;
use crate::contact;
use crate::discrete::Mechanics;

/// Contact `contact`'s spin friction.
#[derive(Debug, Clone, PartialEq)]
pub struct SpinFriction {
    /// The contact.
    pub contact: usize,
}

impl RowBlock for SpinFriction {
    const NAME: &'static str = "SpinFriction";
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        contact::spin_friction(mech, &ctx.contact, self.contact, z, out)
    }
}
