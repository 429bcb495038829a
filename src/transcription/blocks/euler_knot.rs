//! The semi-implicit Euler residual at a knot (eq. 1, `Integrator::Euler`); z = [v_0; q_0;
//! q_1; h_0; u_0] at the first step, else [q_{k−1}; q_k; q_{k+1}; h_{k−1}; h_k; u_k].
//! Generic AD.

use super::place::range_vec;
use super::{Block, Context, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::discrete::Integrator;
use crate::discrete::{Mechanics, euler_knot};

/// The Euler residual at a knot.
#[derive(Debug, Clone, PartialEq)]
pub struct EulerKnot {
    /// Whether the knot is the first (v_0 instead of q_{k−1}).
    pub first_step: bool,
}

impl RowBlock for EulerKnot {
    const NAME: &'static str = "EulerKnot";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // Eq. (1) at knot j into row j: v_0 at the first step, else q_{j−1}, h_{j−1}.
        let Stage::Dynamics(j) = stage else { return };
        if p.ctx.integrator != Integrator::Euler {
            return;
        }
        let l = p.layout;
        let mut vars = if j == 0 {
            range_vec(l.v0())
        } else {
            range_vec(l.q(j - 1))
        };
        vars.extend(l.q(j));
        vars.extend(l.q(j + 1));
        if j > 0 {
            vars.push(l.h(j - 1));
        }
        vars.push(l.h(j));
        let linear_from = vars.len();
        vars.extend(l.u(j));
        let len = vars.len();
        let mut block = Block::new(
            VectorKind::EulerKnot(EulerKnot { first_step: j == 0 }),
            vars,
            len,
            p.dynamics_targets(j),
        );
        // The residual is affine in u (h·B(q_k)u): no u·u Hessian pairs.
        block.linear_from = linear_from;
        p.vector.push(block);
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Context, z: &[D], out: &mut [D]) {
        euler_knot(mech, self.first_step, z, out)
    }
}
