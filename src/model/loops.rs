//! Loop-closure residuals.

use super::{Model, Scalar};

/// Loop-closure residual, length `model.num_loop_constraints()` (2 rows per loop, see
/// [`super::LoopClosure`]); zero when every loop is closed.
pub fn loop_residual<D: Scalar>(model: &Model, q: &[D]) -> Vec<D> {
    let _ = (model, q);
    unimplemented!("loop_residual")
}
