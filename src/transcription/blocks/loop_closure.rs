//! a(q), the loop-closure rows; z = [q]. Derivatives from the mechanics' loop jets
//! (`loops`).

use nalgebra::DMatrix;

use super::{Context, RowBlock, loop_closure_hessian, loop_closure_jacobian};
use crate::autodiff::Scalar;
use crate::discrete::{Mechanics, MechanicsDerivatives};

/// a(q).
#[derive(Debug, Clone, PartialEq)]
pub struct LoopClosure;

impl RowBlock for LoopClosure {
    const NAME: &'static str = "LoopClosure";
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Context, z: &[D], out: &mut [D]) {
        mech.loop_residual(z, out)
    }
    fn jacobian<M: MechanicsDerivatives>(
        &self,
        mech: &M,
        _: &Context,
        z: &[f64],
    ) -> Option<DMatrix<f64>> {
        Some(loop_closure_jacobian(mech, z))
    }
    fn hessian<M: MechanicsDerivatives>(
        &self,
        mech: &M,
        _: &Context,
        z: &[f64],
        w: &[f64],
    ) -> Option<DMatrix<f64>> {
        Some(loop_closure_hessian(mech, z, w))
    }
}
