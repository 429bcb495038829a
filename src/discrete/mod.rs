//! Discrete mechanics: the midpoint discrete Lagrangian (second order, the paper's method) and
//! the first-order semi-implicit Euler time stepping it is compared against, with the forward
//! step (no contact) that exercises both.
//!
//! Where things are:
//! - `mechanics`: the [`Mechanics`] trait, the physics a robot offers (Ld, Fd, momentum,
//!   contact positions, loop closures, names, limits); `derivatives`: the
//!   [`MechanicsDerivatives`] trait, its derivative fast paths with forward-AD defaults;
//!   `model_mechanics`: both for a URDF model.
//! - `midpoint`: the midpoint state, Ld, Fd, slot derivatives and Legendre transforms of a
//!   model; `midpoint_derivatives`: its adjoint gradient, Hessian and third order of Ld.
//! - `del`: the DEL equations of any mechanics: the pieces the NLP places on its rows, and the
//!   knot residual and its Jacobian in q_{k+1} for a forward step.
//! - `euler`: the semi-implicit Euler residual; `loops`: loop closures; `step`: forward steps.
//!
//! Sign convention shared by both integrators (so the NLP can swap them): every residual is a
//! momentum balance in impulse units (N·s, or N·m·s for angles), *momentum before − momentum
//! after + impulses*, so that contact impulses enter as `+ J(q_{k+1})ᵀ λ_k` and loop-closure
//! impulses as `+ G(q_{k+1})ᵀ ν_k`, with G = ∂ loop_residual / ∂q.
//!
//! Every function of configurations is generic over [`crate::autodiff::Scalar`]; the structs
//! ([`MidpointSegment`], [`DiscreteForce`], [`InitialMomentum`], [`EulerKnotResidual`],
//! [`LoopClosure`], [`MidpointKnotResidual`]) wrap them as [`crate::autodiff`] functions of one
//! flat input vector, whose layout each documents.

mod del;
mod derivatives;
mod euler;
mod loops;
mod mechanics;
mod midpoint;
mod midpoint_derivatives;
mod model_mechanics;
mod step;

pub use del::*;
pub use derivatives::*;
pub use euler::*;
pub use loops::*;
pub use mechanics::Mechanics;
pub use midpoint::*;
pub use midpoint_derivatives::*;
pub use model_mechanics::{ContactSphere, ModelMechanics};
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
