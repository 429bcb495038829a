//! The relaxed products ηᵀβ and ψ(μc − eᵀβ) of the listed contacts with the slacks; z = [(c,
//! β, ψ, η) per contact; slacks (0: added by another block, 1 shared, or 3)]. Bilinear:
//! closed-form Jacobian and Hessian.

use nalgebra::DMatrix;

use super::{Context, RowBlock};
use crate::autodiff::Scalar;
use crate::contact::{self, complementarity_hessian, complementarity_jacobian};
use crate::discrete::{Mechanics, MechanicsDerivatives};

/// The complementarity products of `contacts` with `slacks` slacks.
#[derive(Debug, Clone, PartialEq)]
pub struct Complementarity {
    /// The contacts, in z order.
    pub contacts: Vec<usize>,
    /// Slacks at the end of z.
    pub slacks: usize,
}

impl RowBlock for Complementarity {
    const NAME: &'static str = "Complementarity";
    fn value<D: Scalar, M: Mechanics>(&self, _: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        contact::complementarity(&ctx.contact, &self.contacts, self.slacks, z, out)
    }
    fn jacobian<M: MechanicsDerivatives>(
        &self,
        _: &M,
        ctx: &Context,
        z: &[f64],
    ) -> Option<DMatrix<f64>> {
        Some(complementarity_jacobian(
            &ctx.contact,
            &self.contacts,
            self.slacks,
            z,
        ))
    }
    fn hessian<M: MechanicsDerivatives>(
        &self,
        _: &M,
        ctx: &Context,
        z: &[f64],
        w: &[f64],
    ) -> Option<DMatrix<f64>> {
        Some(complementarity_hessian(
            &ctx.contact,
            &self.contacts,
            z.len(),
            w,
        ))
    }
}
