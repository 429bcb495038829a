//! h_a − h_b, an equal-step row (free equal steps); z = [h_a; h_b]. Linear: generic AD.

use super::{Block, Context, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::discrete::Mechanics;

/// h_a − h_b.
#[derive(Debug, Clone, PartialEq)]
pub struct EqualStep;

impl RowBlock for EqualStep {
    const NAME: &'static str = "EqualStep";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // h_j − h_{j+1} = 0 for free equal steps, after every interval.
        let l = p.layout;
        if stage != Stage::EqualSteps || !l.equal_steps {
            return;
        }
        for j in 0..l.knots - 2 {
            p.vector.push(Block::new(
                VectorKind::EqualStep(EqualStep),
                vec![l.h(j), l.h(j + 1)],
                0,
                vec![vec![l.equal_step_row(j)]],
            ));
        }
    }
    fn value<D: Scalar, M: Mechanics>(&self, _: &M, _: &Context, z: &[D], out: &mut [D]) {
        out[0] = z[0] - z[1]
    }
}
