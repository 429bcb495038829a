//! Discrete mechanics: the midpoint discrete Lagrangian (second order, the paper's method) and
//! the first-order semi-implicit Euler time stepping it is compared against, with the forward
//! step (no contact) that exercises both.
//!
//! Sign convention shared by both integrators (so the NLP can swap them): every residual is a
//! momentum balance in impulse units (N·s, or N·m·s for angles), *momentum before − momentum
//! after + impulses*, so that contact impulses enter as `+ J(q_{k+1})ᵀ λ_k` and loop-closure
//! impulses as `+ G(q_{k+1})ᵀ ν_k`, with G = ∂ loop_residual / ∂q.
//!
//! Every function of configurations is generic over [`crate::model::Scalar`]; the structs
//! ([`MidpointSegment`], [`DiscreteForce`], [`InitialMomentum`], [`EulerKnotResidual`],
//! [`LoopClosure`], [`MidpointKnotResidual`]) wrap them as [`crate::autodiff`] functions of one
//! flat input vector, whose layout each documents.

mod euler;
mod loops;
mod midpoint;
mod step;

pub use crate::problem::Integrator;
pub use euler::*;
pub use loops::*;
pub use midpoint::*;
pub use step::*;
