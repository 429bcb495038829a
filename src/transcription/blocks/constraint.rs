//! The rows of the problem file's constraint `index` (`problem::constraints`); z as it
//! declares. Generic AD.

use super::{Block, Context, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::discrete::Mechanics;
use crate::problem::constraints::{ConstraintInput, KnotRef};
use crate::transcription::layout::Layout;

/// The problem file's constraint `index`.
#[derive(Debug, Clone, PartialEq)]
pub struct Constraint {
    /// Its index in the problem's constraints.
    pub index: usize,
}

impl RowBlock for Constraint {
    const NAME: &'static str = "Constraint";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // After every interval, each constraint on its own rows, in the file's order.
        if stage != Stage::Constraints {
            return;
        }
        let l = p.layout;
        let mut row = l.constraint_row(0);
        for (index, constraint) in p.ctx.constraints.iter().enumerate() {
            let vars = constraint_variables(l, &constraint.inputs());
            let targets = (0..constraint.rows().len())
                .map(|r| vec![row + r])
                .collect::<Vec<_>>();
            row += targets.len();
            let len = vars.len();
            p.vector.push(Block::new(
                VectorKind::Constraint(Constraint { index }),
                vars,
                len,
                targets,
            ));
        }
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        ctx.constraints[self.index].value(mech, z, out)
    }
}

/// The variables a constraint reads, in the order it declares them. Knots and intervals
/// it names exist: `Transcription::new` refuses a constraint that reads a missing one
/// (`Constraint::missing_knot`).
fn constraint_variables(l: &Layout, inputs: &[ConstraintInput]) -> Vec<usize> {
    let knot = |k: KnotRef| k.resolve(l.knots).unwrap_or(0);
    let interval = |j: KnotRef| j.resolve(l.intervals()).unwrap_or(0);
    let mut vars = Vec::new();
    for input in inputs {
        match *input {
            ConstraintInput::Coordinate {
                knot: k,
                coordinate,
            } => vars.push(l.q(knot(k)).start + coordinate),
            ConstraintInput::Configuration(k) => vars.extend(l.q(knot(k))),
            ConstraintInput::InitialVelocity => vars.extend(l.v0()),
            ConstraintInput::Step(j) => vars.push(l.h(interval(j))),
            ConstraintInput::Inputs(j) => vars.extend(l.u(interval(j))),
        }
    }
    vars
}
