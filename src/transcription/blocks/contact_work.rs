//! c_i φ_i(q) + β_iᵀ P_i t_i(q), whose q-gradient is contact i's impulse J(q)ᵀλ in the DEL
//! rows (with [`super::SpinFriction`] for a rolling sphere); z = [q; c_i; β_i]. Chain rule
//! through the contact point's jet at q (shared with the other blocks there).

use nalgebra::DMatrix;

use super::{Block, Context, Eval, GeometryUse, GradientBlock, Placement, ScalarKind, Stage};
use crate::autodiff::Scalar;
use crate::autodiff::ThirdOrder;
use crate::contact::{
    self, ContactGeometry, contact_work_contracted_in, contact_work_gradient, contact_work_hessian,
    contact_work_hessian_in, contact_work_third,
};
use crate::discrete::{Mechanics, MechanicsDerivatives};

/// Contact `contact`'s work.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactWork {
    /// The contact.
    pub contact: usize,
}

impl GradientBlock for ContactWork {
    const NAME: &'static str = "ContactWork";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // The impulse's work at q_{j+1}: its q-gradient into row j, linear in [c; β].
        let Stage::ContactImpulse { j, contact } = stage else {
            return;
        };
        let vars = p.impulse_vars(j, contact);
        let len = vars.len();
        let mut targets = p.dynamics_targets(j);
        targets.extend((p.layout.n..len).map(|_| vec![]));
        let mut block = Block::new(
            ScalarKind::ContactWork(ContactWork { contact }),
            vars,
            len,
            targets,
        );
        block.linear_from = p.layout.n;
        p.gradient.push(block);
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D]) -> D {
        contact::contact_work(mech, &ctx.contact, self.contact, z)
    }
    fn geometry<M: Mechanics>(&self, _: &M, n: usize) -> Option<GeometryUse> {
        Some(GeometryUse {
            contact: self.contact,
            q: 0..n,
            order: 2,
        })
    }
    fn hessian_in(&self, geometry: &ContactGeometry, z: &[f64]) -> Option<DMatrix<f64>> {
        Some(contact_work_hessian_in(geometry, z))
    }
    fn contracted_third_in(
        &self,
        geometry: &ContactGeometry,
        z: &[f64],
        dir: &[f64],
    ) -> Option<DMatrix<f64>> {
        contact_work_contracted_in(geometry, z, dir)
    }
    fn gradient<M: MechanicsDerivatives>(&self, at: &Eval<M>, z: &[f64]) -> Option<Vec<f64>> {
        Some(contact_work_gradient(
            at.mech,
            &at.ctx.contact,
            self.contact,
            z,
        ))
    }
    fn hessian<M: MechanicsDerivatives>(&self, at: &Eval<M>, z: &[f64]) -> Option<DMatrix<f64>> {
        Some(contact_work_hessian(
            at.mech,
            &at.ctx.contact,
            self.contact,
            z,
        ))
    }
    fn third<M: MechanicsDerivatives>(
        &self,
        at: &Eval<M>,
        z: &[f64],
        dir: &[f64],
    ) -> Option<ThirdOrder> {
        let (hessian, contracted) =
            contact_work_third(at.mech, &at.ctx.contact, self.contact, z, dir)?;
        Some(ThirdOrder {
            value: 0.0,
            gradient: Vec::new(),
            hessian,
            contracted,
        })
    }
}
