//! A Galerkin interval's discrete forces f^0 … f^s (the input held over the interval and the
//! damping, `crate::discrete::GalerkinRule::forces`): f^0 into interval j's dynamics rows,
//! f^ν into its interior-stationarity rows, f^s into the next interval's; z = [q_j; interior
//! points; q_{j+1}; u_j; h_j]. Generic AD.
//!
//! This kind owns the interior-stationarity rows ∂A/∂q^ν + f^ν = 0 (ν = 1 … s − 1, n each):
//! [`super::GalerkinSegment`] adds the action's part into them.

use super::place::range_vec;
use super::{Block, Context, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::discrete::Mechanics;
use crate::problem::SlackMode;
use crate::transcription::layout::{Dims, IntervalRows};

/// f^0 … f^s of an interval.
#[derive(Debug, Clone, PartialEq)]
pub struct GalerkinForce;

impl RowBlock for GalerkinForce {
    const NAME: &'static str = "GalerkinForce";
    fn interval_rows(dims: &Dims, _: SlackMode) -> Option<IntervalRows> {
        (dims.interior > 0).then_some(IntervalRows {
            kind: Self::NAME,
            count: dims.interior * dims.n,
            equality: true,
            name: |l, local, j, names| {
                format!(
                    "interior stationarity {}, interval {j} interior point {}",
                    names.coordinate(local % l.n),
                    local / l.n + 1
                )
            },
        })
    }
    fn place(p: &mut Placement<'_>, stage: Stage) {
        let Stage::Dynamics(j) = stage else { return };
        if p.ctx.galerkin.is_none() || !p.has_discrete_force {
            return;
        }
        let l = p.layout;
        let mut vars = range_vec(l.q(j));
        vars.extend(l.interior_points(j));
        vars.extend(l.q(j + 1));
        vars.extend(l.u(j));
        vars.push(l.h(j));
        let mut targets = p.dynamics_targets(j);
        targets.extend(l.rows_of(Self::NAME, j).map(|row| vec![row]));
        targets.extend((0..l.n).map(|c| p.after_rows(j, c)));
        let len = vars.len();
        p.vector.push(Block::new(
            VectorKind::GalerkinForce(GalerkinForce),
            vars,
            len,
            targets,
        ));
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        // Placed only with a Galerkin rule.
        let Some(rule) = &ctx.galerkin else { return };
        let points = out.len();
        let (control, rest) = z.split_at(points);
        let (u, h) = rest.split_at(rest.len() - 1);
        rule.forces(mech, control, u, h[0], out);
    }
}
