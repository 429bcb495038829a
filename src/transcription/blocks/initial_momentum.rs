//! M(q_0)v_0, the initial momentum in the first-step rows (midpoint); z = [q_0; v_0].
//! Generic AD.

use super::place::range_vec;
use super::{Block, Context, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::discrete::Integrator;
use crate::discrete::{Mechanics, initial_momentum};

/// M(q_0)v_0.
#[derive(Debug, Clone, PartialEq)]
pub struct InitialMomentum;

impl RowBlock for InitialMomentum {
    const NAME: &'static str = "InitialMomentum";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // The momentum at q_0 with v_0 into the first dynamics rows.
        if stage != Stage::Dynamics(0) || p.ctx.integrator == Integrator::Euler {
            return;
        }
        let l = p.layout;
        let mut vars = range_vec(l.q(0));
        vars.extend(l.v0());
        p.vector.push(Block::new(
            VectorKind::InitialMomentum(InitialMomentum),
            vars,
            2 * l.n,
            p.dynamics_targets(0),
        ));
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Context, z: &[D], out: &mut [D]) {
        initial_momentum(mech, z, out)
    }
}
