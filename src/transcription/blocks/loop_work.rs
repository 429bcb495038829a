//! γᵀa(q), whose q-gradient is the loop impulse A(q)ᵀγ in the DEL rows; z = [q; γ].
//! Derivatives from the mechanics' loop jets (`loops`).

use nalgebra::DMatrix;

use super::{Context, Eval, GradientBlock, loop_work_gradient, loop_work_hessian, loop_work_third};
use crate::autodiff::Scalar;
use crate::autodiff::ThirdOrder;
use crate::discrete::{Mechanics, MechanicsDerivatives, loop_work};

/// γᵀa(q).
#[derive(Debug, Clone, PartialEq)]
pub struct LoopWork;

impl GradientBlock for LoopWork {
    const NAME: &'static str = "LoopWork";
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Context, z: &[D]) -> D {
        loop_work(mech, z)
    }
    fn gradient<M: MechanicsDerivatives>(&self, at: &Eval<M>, z: &[f64]) -> Option<Vec<f64>> {
        Some(loop_work_gradient(at.mech, z))
    }
    fn hessian<M: MechanicsDerivatives>(&self, at: &Eval<M>, z: &[f64]) -> Option<DMatrix<f64>> {
        Some(loop_work_hessian(at.mech, z))
    }
    fn third<M: MechanicsDerivatives>(
        &self,
        at: &Eval<M>,
        z: &[f64],
        dir: &[f64],
    ) -> Option<ThirdOrder> {
        Some(loop_work_third(at.mech, z, dir))
    }
}
