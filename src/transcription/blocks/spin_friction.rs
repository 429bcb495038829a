//! The spin part of a rolling sphere's friction impulse in the DEL rows (its friction
//! directions are no gradient, so it is not in [`super::ContactWork`]); z = [q; c_i; β_i],
//! out length n. Generic AD.

use super::{Block, Context, Placement, RowBlock, Stage, VectorKind};
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
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // Rolling contacts' spin friction at q_{j+1} into row j, linear in [c; β].
        let Stage::ContactImpulse { j, contact } = stage else {
            return;
        };
        if !p.rolls[contact] {
            return;
        }
        let vars = p.impulse_vars(j, contact);
        let len = vars.len();
        let mut block = Block::new(
            VectorKind::SpinFriction(SpinFriction { contact }),
            vars,
            len,
            p.dynamics_targets(j),
        );
        block.linear_from = p.layout.n;
        p.vector.push(block);
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        contact::spin_friction(mech, &ctx.contact, self.contact, z, out)
    }
}
