//! ±P_i(qb)(qb − qa)/h, the nonlinear part of contact i's tangential-velocity rows; z = [qa;
//! qb; h]. Chain rule through the contact point's jet at qb (shared with the other blocks
//! there); a rolling contact's rate by generic AD ([`crate::contact::tangential_rate`]).

use nalgebra::DMatrix;

use super::place::{each, range_vec};
use super::{Block, Context, GeometryUse, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::contact::{
    self, ContactGeometry, tangential_rate_hessian, tangential_rate_hessian_in,
    tangential_rate_jacobian, tangential_rate_jacobian_in,
};
use crate::discrete::{Mechanics, MechanicsDerivatives};
use crate::problem::SlackMode;
use crate::transcription::layout::{Dims, IntervalRows, Layout};
use std::ops::Range;

/// Contact `contact`'s tangential rate.
#[derive(Debug, Clone, PartialEq)]
pub struct TangentialRate {
    /// The contact.
    pub contact: usize,
}

impl RowBlock for TangentialRate {
    const NAME: &'static str = "TangentialRate";
    fn interval_rows(dims: &Dims, _: SlackMode) -> Option<IntervalRows> {
        Some(IntervalRows {
            kind: Self::NAME,
            count: dims.nc * dims.nd,
            equality: true,
            name: |l, local, j, names| {
                let (contact, direction) = (local / l.nd, local % l.nd);
                let contact = names.contact(contact);
                format!("tangential velocity {contact} direction {direction}, interval {j}")
            },
        })
    }
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // The contact point's tangential velocity over interval j on its tangential rows.
        let Stage::ContactRows { j, contact } = stage else {
            return;
        };
        let l = p.layout;
        let mut vars = range_vec(l.q(j));
        vars.extend(l.q(j + 1));
        vars.push(l.h(j));
        p.vector.push(Block::new(
            VectorKind::TangentialRate(TangentialRate { contact }),
            vars,
            2 * l.n + 1,
            each(rows(l, j, contact)),
        ));
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        contact::tangential_rate(mech, &ctx.contact, self.contact, z, out)
    }
    /// The geometry at qb, except for a rolling contact, whose rate has no chain rule.
    fn geometry<M: Mechanics>(&self, mech: &M, n: usize) -> Option<GeometryUse> {
        (!mech.contact_rolls(self.contact)).then_some(GeometryUse {
            contact: self.contact,
            q: n..2 * n,
            order: 2,
        })
    }
    fn jacobian_in(&self, geometry: &ContactGeometry, z: &[f64]) -> Option<DMatrix<f64>> {
        Some(tangential_rate_jacobian_in(geometry, z))
    }
    fn hessian_in(&self, geometry: &ContactGeometry, z: &[f64], w: &[f64]) -> Option<DMatrix<f64>> {
        Some(tangential_rate_hessian_in(geometry, z, w))
    }
    fn jacobian<M: MechanicsDerivatives>(
        &self,
        mech: &M,
        ctx: &Context,
        z: &[f64],
    ) -> Option<DMatrix<f64>> {
        Some(tangential_rate_jacobian(
            mech,
            &ctx.contact,
            self.contact,
            z,
        ))
    }
    /// A rolling contact's rate has no chain rule: generic AD, over the block's Hessian
    /// inputs only.
    fn hessian<M: MechanicsDerivatives>(
        &self,
        mech: &M,
        ctx: &Context,
        z: &[f64],
        w: &[f64],
    ) -> Option<DMatrix<f64>> {
        (!mech.contact_rolls(self.contact))
            .then(|| tangential_rate_hessian(mech, &ctx.contact, self.contact, z, w))
    }
}

/// The tangential-velocity rows of contact i in interval j (nd rows, zero by the rate and
/// slack blocks together).
pub(super) fn rows(l: &Layout, j: usize, i: usize) -> Range<usize> {
    let a = l.rows_of(TangentialRate::NAME, j).start + i * l.nd;
    a..a + l.nd
}
