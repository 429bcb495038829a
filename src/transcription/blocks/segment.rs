//! Midpoint Ld(qa, qb, h), whose gradient is D1Ld into one interval's DEL rows and D2Ld into
//! the next's; z = [qa; qb; h]. Derivatives by the mechanics' own segment derivatives
//! ([`MechanicsDerivatives::segment_gradient`] and the rest), columns grouped as a midpoint
//! segment's.

use nalgebra::DMatrix;

use super::place::range_vec;
use super::{Block, Context, Eval, GradientBlock, Placement, ScalarKind, Stage};
use crate::autodiff::Scalar;
use crate::autodiff::ThirdOrder;
use crate::discrete::Integrator;
use crate::discrete::{Mechanics, MechanicsDerivatives, SegmentLagrangian};

/// Ld(qa, qb, h).
#[derive(Debug, Clone, PartialEq)]
pub struct Segment;

impl GradientBlock for Segment {
    const NAME: &'static str = "Segment";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // Ld(q_j, q_{j+1}, h_j): D1Ld into row j, D2Ld into row j+1 (or the end rows).
        let Stage::Dynamics(j) = stage else { return };
        if p.ctx.integrator != Integrator::Midpoint {
            return;
        }
        let l = p.layout;
        let mut vars = range_vec(l.q(j));
        vars.extend(l.q(j + 1));
        vars.push(l.h(j));
        let mut targets = p.dynamics_targets(j);
        targets.extend((0..l.n).map(|c| p.after_rows(j, c)));
        targets.push(vec![]);
        let len = vars.len();
        p.gradient
            .push(Block::new(ScalarKind::Segment(Segment), vars, len, targets));
    }
    const ALWAYS_CLOSED_FORM: bool = true;
    const SEGMENT_GROUPS: bool = true;
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Context, z: &[D]) -> D {
        crate::autodiff::ScalarFunction::eval(&SegmentLagrangian { mech }, z)
    }
    fn gradient<M: MechanicsDerivatives>(&self, at: &Eval<M>, z: &[f64]) -> Option<Vec<f64>> {
        Some(at.mech.segment_gradient(z))
    }
    /// The model's adjoint path for Ld when it has one.
    fn hessian<M: MechanicsDerivatives>(&self, at: &Eval<M>, z: &[f64]) -> Option<DMatrix<f64>> {
        Some(match &at.block.second_derivative_groups {
            Some(groups) => at.mech.segment_gradient_hessian_grouped(z, groups).1,
            None => at.mech.segment_gradient_hessian(z).1,
        })
    }
    fn third<M: MechanicsDerivatives>(
        &self,
        at: &Eval<M>,
        z: &[f64],
        dir: &[f64],
    ) -> Option<ThirdOrder> {
        if let Some(groups) = at.block.groups_for(at.skip_fixed) {
            return Some(at.mech.segment_third_order_grouped(z, dir, groups));
        }
        let columns = at.skip_fixed.then_some(at.block.free_input_mask.as_slice());
        Some(at.mech.segment_third_order(z, dir, columns))
    }
}
