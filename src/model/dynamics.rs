//! Generalised forces: inputs, damping and inverse dynamics.

use super::{Model, Scalar};

/// B(q)·u: input i adds u[i] to coordinate `model.input_coordinates()[i]` (length `nq`).
pub fn generalized_input_force<D: Scalar>(model: &Model, q: &[D], u: &[D]) -> Vec<D> {
    let _ = (model, q, u);
    unimplemented!("generalized_input_force")
}

/// Viscous damping force −diag(d)·v (length `nq`).
pub fn generalized_damping_force<D: Scalar>(model: &Model, v: &[D]) -> Vec<D> {
    let _ = (model, v);
    unimplemented!("generalized_damping_force")
}

/// Inverse dynamics M(q)a + C(q, v)v + ∂V/∂q (gravity and springs; no damping, no inputs),
/// length `nq`.
pub fn inverse_dynamics<D: Scalar>(model: &Model, q: &[D], v: &[D], a: &[D]) -> Vec<D> {
    let _ = (model, q, v, a);
    unimplemented!("inverse_dynamics")
}
