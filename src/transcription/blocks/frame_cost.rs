//! The costs of the problem's frame terms (`problem::frames`): ½ w (f(z) − target)² on each
//! of a term's knots, z as in [`super::frame_row`]. Generic AD.

use super::frame_row::frame_variables;
use super::{Block, Context, GradientBlock, Placement, ScalarKind, Stage};
use crate::autodiff::Scalar;
use crate::discrete::Mechanics;

/// Frame term `term` on one knot.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameCost {
    /// Its index in the problem's frame terms.
    pub term: usize,
}

impl GradientBlock for FrameCost {
    const NAME: &'static str = "FrameCost";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        if stage != Stage::Costs {
            return;
        }
        for (term, frame) in p.ctx.frames.iter().enumerate() {
            if !frame.has_cost() {
                continue;
            }
            for &k in &frame.knots {
                let vars = frame_variables(p.layout, frame.quantity.reads(), k);
                let len = vars.len();
                let kind = ScalarKind::FrameCost(FrameCost { term });
                p.cost.push(Block::new(kind, vars, len, vec![]));
            }
        }
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D]) -> D {
        let frame = &ctx.frames[self.term];
        let d = frame.quantity.value(mech, &ctx.contact.terrain, ctx.n, z) - D::from(frame.target);
        d * d * D::from(0.5 * frame.weight)
    }
}
