//! Cost term `term` of the problem on one placement (an interval, or the last knot); z as
//! the term declares ([`crate::problem::costs::CostInputs`]). Each term's value is in its
//! own file under `crate::problem::costs`; its Hessian in closed form where the term has one
//! ([`crate::problem::costs::CostFunction::hessian`]), else by generic AD, like its gradient.

use nalgebra::DMatrix;

use super::place::range_vec;
use super::{Block, Context, Eval, GradientBlock, Placement, ScalarKind, Stage};
use crate::autodiff::Scalar;
use crate::discrete::{Mechanics, MechanicsDerivatives};
use crate::problem::costs::{self, CostInputs, CostSizes, cost_hessian, cost_value};
use crate::transcription::layout::Layout;

/// The problem's cost term `term`.
#[derive(Debug, Clone, PartialEq)]
pub struct Cost {
    /// Its index in the problem's cost terms.
    pub term: usize,
}

impl GradientBlock for Cost {
    const NAME: &'static str = "Cost";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // After every interval, each term on every placement its inputs declare.
        if stage != Stage::Costs {
            return;
        }
        for (term, cost) in p.ctx.costs.iter().enumerate() {
            let declared = costs::declaration(cost);
            for vars in cost_placements(p.layout, declared.inputs) {
                let nonlinear = if declared.linear { 0 } else { vars.len() };
                let kind = ScalarKind::Cost(Cost { term });
                p.cost.push(Block::new(kind, vars, nonlinear, vec![]));
            }
        }
    }
    fn value<D: Scalar, M: Mechanics>(&self, _: &M, ctx: &Context, z: &[D]) -> D {
        cost_value(&ctx.costs[self.term], cost_sizes(ctx), z)
    }
    fn hessian<M: MechanicsDerivatives>(&self, at: &Eval<M>, z: &[f64]) -> Option<DMatrix<f64>> {
        cost_hessian(&at.ctx.costs[self.term], cost_sizes(at.ctx), z)
    }
}

/// The sizes a cost term's input is split by, from the transcription's context.
fn cost_sizes(ctx: &Context) -> CostSizes {
    CostSizes {
        n: ctx.n,
        m: ctx.m,
        nc: ctx.nc(),
    }
}

/// The variables of every placement of a cost term that reads `inputs`, in placement order.
fn cost_placements(l: &Layout, inputs: CostInputs) -> Vec<Vec<usize>> {
    let interval = |j: usize, with_step: bool| {
        let mut vars = range_vec(l.q(j));
        vars.extend(l.q(j + 1));
        if with_step {
            vars.push(l.h(j));
        }
        vars
    };
    match inputs {
        CostInputs::IntervalWithStep => (0..l.intervals()).map(|j| interval(j, true)).collect(),
        CostInputs::IntervalConfigurations => {
            (0..l.intervals()).map(|j| interval(j, false)).collect()
        }
        CostInputs::InputWithStep => (0..l.intervals())
            .map(|j| {
                let mut vars = range_vec(l.u(j));
                vars.push(l.h(j));
                vars
            })
            .collect(),
        CostInputs::AdjacentInputs => (1..l.intervals())
            .map(|j| {
                let mut vars = range_vec(l.u(j - 1));
                vars.extend(l.u(j));
                vars
            })
            .collect(),
        CostInputs::AdjacentImpulses => (1..l.intervals())
            .map(|j| {
                let mut vars: Vec<usize> = (0..l.nc).map(|i| l.c(j - 1, i)).collect();
                vars.extend((0..l.nc).map(|i| l.c(j, i)));
                vars
            })
            .collect(),
        CostInputs::AdjacentIntervals => (1..l.intervals())
            .map(|j| {
                let mut vars = range_vec(l.q(j - 1));
                vars.extend(l.q(j));
                vars.extend(l.q(j + 1));
                vars.extend([l.h(j - 1), l.h(j)]);
                vars
            })
            .collect(),
        CostInputs::LastConfiguration => vec![range_vec(l.q(l.knots - 1))],
        CostInputs::LastIntervalWithStep => vec![interval(l.intervals() - 1, true)],
        CostInputs::Step => (0..l.intervals()).map(|j| vec![l.h(j)]).collect(),
    }
}
