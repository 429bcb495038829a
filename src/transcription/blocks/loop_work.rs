//! γᵀa(q), whose q-gradient is the loop impulse A(q)ᵀγ in the DEL rows; z = [q; γ].
//! Derivatives from the mechanics' loop jets (`loops`).

use nalgebra::DMatrix;

use super::place::range_vec;
use super::{
    Block, Context, Eval, GradientBlock, Placement, ScalarKind, Stage, loop_work_gradient,
    loop_work_hessian, loop_work_third,
};
use crate::autodiff::Scalar;
use crate::autodiff::ThirdOrder;
use crate::discrete::{Mechanics, MechanicsDerivatives, loop_work};

/// γᵀa(q).
#[derive(Debug, Clone, PartialEq)]
pub struct LoopWork;

impl GradientBlock for LoopWork {
    const NAME: &'static str = "LoopWork";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // The loop impulses' work at q_{j+1}: its q-gradient into row j, linear in γ_j.
        let Stage::Loops(j) = stage else { return };
        let l = p.layout;
        if l.nl == 0 {
            return;
        }
        let mut vars = range_vec(l.q(j + 1));
        vars.extend(l.gamma(j));
        let len = vars.len();
        let mut targets = p.dynamics_targets(j);
        targets.extend((0..l.nl).map(|_| vec![]));
        let mut block = Block::new(ScalarKind::LoopWork(LoopWork), vars, len, targets);
        block.linear_from = l.n;
        p.gradient.push(block);
    }
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
