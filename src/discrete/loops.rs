//! Loop closures in the discrete equations: the residual is imposed at the new knot q_{k+1},
//! and its impulses Gᵀ(q_{k+1})ν_k (G = ∂ loop_residual / ∂q) join the momentum balance.

use crate::autodiff::Scalar;
use crate::autodiff::VectorFunction;
use crate::model::{self, Model};

/// Loop-closure residual as a [`VectorFunction`] of q (dim n) → R^{n_loop}
/// (`model.num_loop_constraints()` rows, model length units).
#[derive(Debug, Clone, Copy)]
pub struct LoopClosure<'a> {
    /// The robot.
    pub model: &'a Model,
}

impl VectorFunction for LoopClosure<'_> {
    fn dim_in(&self) -> usize {
        self.model.nq()
    }
    fn dim_out(&self) -> usize {
        self.model.num_loop_constraints()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        out.copy_from_slice(&model::loop_residual(self.model, z));
    }
}
