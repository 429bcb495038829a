//! ½Fd(qa, qb, u, h), the discrete force's half in each of the two DEL rows of an interval
//! (midpoint); z = [qa; qb; u; h]. Derivatives from the mechanics' closed forms
//! ([`MechanicsDerivatives::half_force_jacobian`]) where it has them, else generic AD.

use nalgebra::DMatrix;

use super::place::range_vec;
use super::{Block, Context, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::discrete::Integrator;
use crate::discrete::{Mechanics, MechanicsDerivatives, half_force};

/// ½Fd(qa, qb, u, h).
#[derive(Debug, Clone, PartialEq)]
pub struct HalfForce;

impl RowBlock for HalfForce {
    const NAME: &'static str = "HalfForce";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // ½Fd(q_j, q_{j+1}, u_j, h_j) into row j and into row j+1 (or the end rows).
        let Stage::Dynamics(j) = stage else { return };
        if p.ctx.integrator != Integrator::Midpoint || !p.has_discrete_force {
            return;
        }
        let l = p.layout;
        let mut vars = range_vec(l.q(j));
        vars.extend(l.q(j + 1));
        vars.extend(l.u(j));
        vars.push(l.h(j));
        let targets = l
            .dynamics_rows(j)
            .enumerate()
            .map(|(c, row)| {
                let mut rows = vec![row];
                rows.extend(p.after_rows(j, c));
                rows
            })
            .collect();
        let len = vars.len();
        p.vector.push(Block::new(
            VectorKind::HalfForce(HalfForce),
            vars,
            len,
            targets,
        ));
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Context, z: &[D], out: &mut [D]) {
        half_force(mech, z, out)
    }
    fn jacobian<M: MechanicsDerivatives>(
        &self,
        mech: &M,
        _: &Context,
        z: &[f64],
    ) -> Option<DMatrix<f64>> {
        mech.half_force_jacobian(z)
    }
    fn hessian<M: MechanicsDerivatives>(
        &self,
        mech: &M,
        _: &Context,
        z: &[f64],
        w: &[f64],
    ) -> Option<DMatrix<f64>> {
        mech.half_force_hessian(z, w)
    }
}
