//! Discrete mechanics: the midpoint discrete Lagrangian (second order, the paper's method) and
//! the first-order semi-implicit Euler time stepping it is compared against, with the forward
//! step (no contact) that exercises both.
//!
//! Sign convention shared by both integrators (so the NLP can swap them): every residual is a
//! momentum balance in impulse units (N·s, or N·m·s for angles), *momentum before − momentum
//! after + impulses*, so that contact impulses enter as `+ J(q_{k+1})ᵀ λ_k` and loop-closure
//! impulses as `+ G(q_{k+1})ᵀ ν_k`, with G = ∂ loop_residual / ∂q.
//!
//! Every function of configurations is generic over [`crate::scalar::Scalar`]; the structs
//! ([`MidpointSegment`], [`DiscreteForce`], [`InitialMomentum`], [`EulerKnotResidual`],
//! [`LoopClosure`], [`MidpointKnotResidual`]) wrap them as [`crate::autodiff`] functions of one
//! flat input vector, whose layout each documents.

mod euler;
mod loops;
mod midpoint;
mod step;

pub use euler::*;
pub use loops::*;
pub use midpoint::*;
pub use step::*;

/// Which discrete mechanics the dynamics constraints use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Integrator {
    /// Midpoint discrete Lagrangian Ld = h·L((qa+qb)/2, (qb−qa)/h): second order, the paper's.
    #[default]
    Midpoint,
    /// First-order semi-implicit Euler time stepping (Posa et al. 2014, eq. 1 of the paper).
    Euler,
}
