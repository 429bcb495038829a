//! a(q), the loop-closure rows; z = [q]. Derivatives from the mechanics' loop jets
//! (`loops`).

use nalgebra::DMatrix;

use super::place::{each, range_vec};
use super::{
    Block, Context, Placement, RowBlock, Stage, VectorKind, loop_closure_hessian,
    loop_closure_jacobian,
};
use crate::autodiff::Scalar;
use crate::discrete::{Mechanics, MechanicsDerivatives};
use crate::problem::SlackMode;
use crate::transcription::layout::{Dims, IntervalRows};

/// a(q).
#[derive(Debug, Clone, PartialEq)]
pub struct LoopClosure;

impl RowBlock for LoopClosure {
    const NAME: &'static str = "LoopClosure";
    fn interval_rows(dims: &Dims, _: SlackMode) -> Option<IntervalRows> {
        Some(IntervalRows {
            kind: Self::NAME,
            count: dims.nl,
            equality: true,
            name: |_, local, j, _| format!("loop closure {local}, knot {}", j + 1),
        })
    }
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // a(q_{j+1}) on interval j's loop rows; a(q_0) once, after every interval.
        let l = p.layout;
        if l.nl == 0 {
            return;
        }
        let (k, rows) = match stage {
            Stage::Loops(j) => (j + 1, l.rows_of(Self::NAME, j)),
            Stage::FirstLoops => (0, l.first_loop_rows()),
            _ => return,
        };
        p.vector.push(Block::new(
            VectorKind::LoopClosure(LoopClosure),
            range_vec(l.q(k)),
            l.n,
            each(rows),
        ));
    }
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
