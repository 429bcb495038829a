//! φ_i(q), the non-penetration row, z = [q]; and −c_i φ_i(q), the product of the c·φ
//! complementarity row, z = [q; c_i] (`gap`). Chain rule through the contact point's jet at
//! q (shared with the other blocks there).

use nalgebra::DMatrix;

use super::place::range_vec;
use super::{Block, Context, GeometryUse, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::contact::{
    self, ContactGeometry, distance_hessian, distance_hessian_in, distance_jacobian,
    distance_jacobian_in,
};
use crate::discrete::{Mechanics, MechanicsDerivatives};
use crate::problem::SlackMode;
use crate::transcription::layout::{Dims, IntervalRows};

/// Contact `contact`'s signed distance φ, or −cφ when `gap`.
#[derive(Debug, Clone, PartialEq)]
pub struct Distance {
    /// The contact.
    pub contact: usize,
    /// Whether the row is −cφ (z = [q; c]) rather than φ.
    pub gap: bool,
}

impl RowBlock for Distance {
    const NAME: &'static str = "Distance";
    fn interval_rows(dims: &Dims, _: SlackMode) -> Option<IntervalRows> {
        Some(IntervalRows {
            kind: Self::NAME,
            count: dims.nc,
            equality: false,
            name: |_, local, j, names| format!("phi {}, knot {}", names.contact(local), j + 1),
        })
    }
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // φ(q_{j+1}) on the distance row (the −cφ rows are placed by `Complementarity`).
        let Stage::ContactRows { j, contact } = stage else {
            return;
        };
        let l = p.layout;
        p.vector.push(Block::new(
            VectorKind::Distance(Distance {
                contact,
                gap: false,
            }),
            range_vec(l.q(j + 1)),
            l.n,
            vec![vec![l.rows_of(Self::NAME, j).start + contact]],
        ));
    }
    fn name(&self) -> &'static str {
        if self.gap { "ContactGap" } else { Self::NAME }
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        out[0] = if self.gap {
            contact::contact_gap(mech, &ctx.contact, self.contact, z)
        } else {
            contact::distance(mech, &ctx.contact, self.contact, z)
        }
    }
    fn geometry<M: Mechanics>(&self, _: &M, n: usize) -> Option<GeometryUse> {
        Some(GeometryUse {
            contact: self.contact,
            q: 0..n,
            order: 1,
        })
    }
    fn jacobian_in(&self, geometry: &ContactGeometry, z: &[f64]) -> Option<DMatrix<f64>> {
        Some(distance_jacobian_in(geometry, z, self.gap))
    }
    fn hessian_in(&self, geometry: &ContactGeometry, z: &[f64], w: &[f64]) -> Option<DMatrix<f64>> {
        Some(distance_hessian_in(geometry, z, w[0], self.gap))
    }
    fn jacobian<M: MechanicsDerivatives>(
        &self,
        mech: &M,
        ctx: &Context,
        z: &[f64],
    ) -> Option<DMatrix<f64>> {
        Some(distance_jacobian(
            mech,
            &ctx.contact,
            self.contact,
            z,
            self.gap,
        ))
    }
    fn hessian<M: MechanicsDerivatives>(
        &self,
        mech: &M,
        ctx: &Context,
        z: &[f64],
        w: &[f64],
    ) -> Option<DMatrix<f64>> {
        Some(distance_hessian(
            mech,
            &ctx.contact,
            self.contact,
            z,
            w[0],
            self.gap,
        ))
    }
}
