//! The rows of the problem's frame terms (`problem::frames`): lower ≤ f(z) ≤ upper, one
//! block and row per term and knot, after the problem file's constraints. z = q_k, or
//! [q_{k−1}; q_k; h_{k−1}] for a quantity read over the interval ending at knot k. Generic AD.

use super::place::range_vec;
use super::{Block, Context, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::discrete::Mechanics;
use crate::problem::frames::FrameReads;
use crate::transcription::layout::Layout;

/// Frame term `term` at knot `knot`.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameRow {
    /// Its index in the problem's frame terms.
    pub term: usize,
}

impl RowBlock for FrameRow {
    const NAME: &'static str = "FrameRow";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // After the problem file's constraints, each term's rows in knot order.
        if stage != Stage::Constraints {
            return;
        }
        let l = p.layout;
        let mut row = l.constraint_row(p.ctx.constraints.iter().map(|c| c.rows().len()).sum());
        for (term, frame) in p.ctx.frames.iter().enumerate() {
            if !frame.has_rows() {
                continue;
            }
            for &k in &frame.knots {
                let vars = frame_variables(l, frame.quantity.reads(), k);
                let len = vars.len();
                p.vector.push(Block::new(
                    VectorKind::FrameRow(FrameRow { term }),
                    vars,
                    len,
                    vec![vec![row]],
                ));
                row += 1;
            }
        }
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        let frame = &ctx.frames[self.term];
        out[0] = frame.quantity.value(mech, &ctx.contact.terrain, ctx.n, z);
    }
}

/// The variables a frame quantity reads at knot k (k ≥ 1 for an interval's).
pub(super) fn frame_variables(l: &Layout, reads: FrameReads, k: usize) -> Vec<usize> {
    match reads {
        FrameReads::Knot => range_vec(l.q(k)),
        FrameReads::IntervalEndingAt => {
            let mut vars = range_vec(l.q(k - 1));
            vars.extend(l.q(k));
            vars.push(l.h(k - 1));
            vars
        }
    }
}
