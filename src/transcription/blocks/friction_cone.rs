//! μ c − eᵀβ, the friction-cone row; z = [c; β]. Linear: generic AD.

use super::{Block, Context, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::contact;
use crate::discrete::Mechanics;
use crate::problem::SlackMode;
use crate::transcription::layout::{Dims, IntervalRows};

/// Contact `contact`'s friction cone.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionCone {
    /// The contact.
    pub contact: usize,
}

impl RowBlock for FrictionCone {
    const NAME: &'static str = "FrictionCone";
    fn interval_rows(dims: &Dims, _: SlackMode) -> Option<IntervalRows> {
        Some(IntervalRows {
            kind: Self::NAME,
            count: dims.nc,
            equality: false,
            name: |_, local, j, names| {
                format!("friction cone {}, interval {j}", names.contact(local))
            },
        })
    }
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // μc − eᵀβ on the cone row (linear).
        let Stage::ContactRows { j, contact } = stage else {
            return;
        };
        let l = p.layout;
        let mut vars = vec![l.c(j, contact)];
        vars.extend(l.beta(j, contact));
        p.vector.push(Block::new(
            VectorKind::FrictionCone(FrictionCone { contact }),
            vars,
            0,
            vec![vec![l.rows_of(Self::NAME, j).start + contact]],
        ));
    }
    fn value<D: Scalar, M: Mechanics>(&self, _: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        out[0] = contact::friction_cone(&ctx.contact, self.contact, z)
    }
}
