//! Kinetic and potential energy, mass matrix and generalised momentum.

use nalgebra::DMatrix;

use super::{Model, Scalar};

/// Kinetic energy T(q, q̇) = Σ ½ m |ṗ_com|² + ½ ω_bᵀ I_c ω_b, by a recursion over the tree
/// (slices of length `nq`).
pub fn kinetic_energy<D: Scalar>(model: &Model, q: &[D], qdot: &[D]) -> D {
    let _ = (model, q, qdot);
    unimplemented!("kinetic_energy")
}

/// Potential energy V(q) = −Σ m gravity·p_com + Σ ½ k (q − rest)² (`q` of length `nq`).
pub fn potential_energy<D: Scalar>(model: &Model, q: &[D]) -> D {
    let _ = (model, q);
    unimplemented!("potential_energy")
}

/// Generalised momentum M(q)·v (length `nq`), without assembling M.
pub fn generalized_momentum<D: Scalar>(model: &Model, q: &[D], v: &[D]) -> Vec<D> {
    let _ = (model, q, v);
    unimplemented!("generalized_momentum")
}

/// The mass matrix M(q) (`nq × nq`, symmetric), from the link Jacobians.
pub fn mass_matrix(model: &Model, q: &[f64]) -> DMatrix<f64> {
    let _ = (model, q);
    unimplemented!("mass_matrix")
}
