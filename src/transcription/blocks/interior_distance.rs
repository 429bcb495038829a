//! φ_i(q_j^ν) ≥ 0 at a Galerkin interval's interior control points, so that the path between
//! two knots cannot dip into the ground there (no impulse acts at them); z = [q_j^ν]. The
//! value and derivatives are [`Distance`]'s.

use nalgebra::DMatrix;

use super::{Block, Context, Distance, GeometryUse, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::contact::ContactGeometry;
use crate::discrete::{Mechanics, MechanicsDerivatives};
use crate::problem::SlackMode;
use crate::transcription::layout::{Dims, IntervalRows};

/// Contact `contact`'s signed distance at an interior point.
#[derive(Debug, Clone, PartialEq)]
pub struct InteriorDistance(pub Distance);

impl RowBlock for InteriorDistance {
    const NAME: &'static str = "InteriorDistance";
    fn interval_rows(dims: &Dims, _: SlackMode) -> Option<IntervalRows> {
        (dims.interior > 0 && dims.nc > 0).then_some(IntervalRows {
            kind: Self::NAME,
            count: dims.interior * dims.nc,
            equality: false,
            name: |l, local, j, names| {
                format!(
                    "phi {}, interval {j} interior point {}",
                    names.contact(local % l.nc),
                    local / l.nc + 1
                )
            },
        })
    }
    fn place(p: &mut Placement<'_>, stage: Stage) {
        let Stage::ContactRows { j, contact } = stage else {
            return;
        };
        let l = p.layout;
        let rows = l.rows_of(Self::NAME, j);
        for nu in 0..l.interior {
            let distance = Distance {
                contact,
                gap: false,
            };
            p.vector.push(Block::new(
                VectorKind::InteriorDistance(InteriorDistance(distance)),
                l.interior(j, nu).collect(),
                l.n,
                vec![vec![rows.start + nu * l.nc + contact]],
            ));
        }
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        self.0.value(mech, ctx, z, out)
    }
    fn geometry<M: Mechanics>(&self, mech: &M, n: usize) -> Option<GeometryUse> {
        self.0.geometry(mech, n)
    }
    fn jacobian_in(&self, geometry: &ContactGeometry, z: &[f64]) -> Option<DMatrix<f64>> {
        self.0.jacobian_in(geometry, z)
    }
    fn hessian_in(&self, geometry: &ContactGeometry, z: &[f64], w: &[f64]) -> Option<DMatrix<f64>> {
        self.0.hessian_in(geometry, z, w)
    }
    fn jacobian<M: MechanicsDerivatives>(
        &self,
        mech: &M,
        ctx: &Context,
        z: &[f64],
    ) -> Option<DMatrix<f64>> {
        self.0.jacobian(mech, ctx, z)
    }
    fn hessian<M: MechanicsDerivatives>(
        &self,
        mech: &M,
        ctx: &Context,
        z: &[f64],
        w: &[f64],
    ) -> Option<DMatrix<f64>> {
        self.0.hessian(mech, ctx, z, w)
    }
}
