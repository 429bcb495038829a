//! Block placement: which constraint, gradient and cost blocks exist, which NLP variables each
//! reads (its local input z = x[vars]) and which rows each output adds into.

use super::Transcription;
use super::blocks::{
    Block, Complementarity, Constraint, ContactWork, Cost, Distance, EqualStep, EulerKnot,
    FrictionCone, HalfForce, InitialMomentum, LoopClosure, LoopWork, ScalarKind, Segment,
    SpinFriction, TangentialRate, TangentialSlack, VectorKind,
};
use super::layout::Layout;
use crate::discrete::{Integrator, MechanicsDerivatives};
use crate::problem::constraints::{ConstraintInput, KnotRef};
use crate::problem::costs::{self, CostInputs};

pub(super) fn range_vec(r: std::ops::Range<usize>) -> Vec<usize> {
    r.collect()
}

impl<M: MechanicsDerivatives> Transcription<M> {
    pub(super) fn place_blocks(&mut self) {
        let l = &self.layout;
        let (n, nc, nl) = (l.n, l.nc, l.nl);
        let last = l.intervals();
        // Rows that also receive the momentum arriving at the last knot (component c into
        // end_rows[c]): the last interval's D2Ld and second half force, which otherwise
        // target no row.
        let mut end_rows: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut row = l.constraint_row(0);
        for constraint in &self.ctx.constraints {
            let count = constraint.rows().len();
            if constraint.receives_end_momentum() {
                for (c, rows) in end_rows.iter_mut().enumerate() {
                    rows.push(row + c);
                }
            }
            row += count;
        }
        for j in 0..last {
            let dyn_rows = range_vec(l.dynamics_rows(j));
            let next_rows = (j + 1 < last).then(|| range_vec(l.dynamics_rows(j + 1)));
            if self.ctx.integrator == Integrator::Euler {
                // Eq. (1) at knot j into row j: v_0 at the first step, else q_{j−1}, h_{j−1}.
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
                let targets = dyn_rows.iter().map(|&r| vec![r]).collect();
                let len = vars.len();
                let mut block = Block::new(
                    VectorKind::EulerKnot(EulerKnot { first_step: j == 0 }),
                    vars,
                    len,
                    targets,
                );
                // The residual is affine in u (h·B(q_k)u): no u·u Hessian pairs.
                block.linear_from = linear_from;
                self.vector_blocks.push(block);
            } else {
                // Ld(q_j, q_{j+1}, h_j): D1Ld into row j, D2Ld into row j+1.
                let mut vars = range_vec(l.q(j));
                vars.extend(l.q(j + 1));
                vars.push(l.h(j));
                let mut targets: Vec<Vec<usize>> = dyn_rows.iter().map(|&r| vec![r]).collect();
                for c in 0..n {
                    targets.push(
                        next_rows
                            .as_ref()
                            .map_or_else(|| end_rows[c].clone(), |rows| vec![rows[c]]),
                    );
                }
                targets.push(vec![]);
                let len = vars.len();
                self.gradient_blocks.push(Block::new(
                    ScalarKind::Segment(Segment),
                    vars,
                    len,
                    targets,
                ));

                if self.mech.has_discrete_force() {
                    let mut vars = range_vec(l.q(j));
                    vars.extend(l.q(j + 1));
                    vars.extend(l.u(j));
                    vars.push(l.h(j));
                    let targets = (0..n)
                        .map(|c| {
                            let mut rows = vec![dyn_rows[c]];
                            match &next_rows {
                                Some(r) => rows.push(r[c]),
                                None => rows.extend(&end_rows[c]),
                            }
                            rows
                        })
                        .collect();
                    let len = vars.len();
                    self.vector_blocks.push(Block::new(
                        VectorKind::HalfForce(HalfForce),
                        vars,
                        len,
                        targets,
                    ));
                }
                if j == 0 {
                    let mut vars = range_vec(l.q(0));
                    vars.extend(l.v0());
                    let targets = dyn_rows.iter().map(|&r| vec![r]).collect();
                    self.vector_blocks.push(Block::new(
                        VectorKind::InitialMomentum(InitialMomentum),
                        vars,
                        2 * n,
                        targets,
                    ));
                }
            }
            let q_next_targets = |extra: usize| -> Vec<Vec<usize>> {
                let mut t: Vec<Vec<usize>> = dyn_rows.iter().map(|&r| vec![r]).collect();
                t.extend((0..extra).map(|_| vec![]));
                t
            };
            for i in 0..nc {
                let mut vars = range_vec(l.q(j + 1));
                vars.push(l.c(j, i));
                vars.extend(l.beta(j, i));
                let len = vars.len();
                let targets = q_next_targets(len - n);
                if self.mech.contact_rolls(i) {
                    let rows = dyn_rows.iter().map(|&r| vec![r]).collect();
                    let mut block = Block::new(
                        VectorKind::SpinFriction(SpinFriction { contact: i }),
                        vars.clone(),
                        len,
                        rows,
                    );
                    block.linear_from = n;
                    self.vector_blocks.push(block);
                }
                let mut block = Block::new(
                    ScalarKind::ContactWork(ContactWork { contact: i }),
                    vars,
                    len,
                    targets,
                );
                block.linear_from = n;
                self.gradient_blocks.push(block);
            }
            if nl > 0 {
                let mut vars = range_vec(l.q(j + 1));
                vars.extend(l.gamma(j));
                let len = vars.len();
                let targets = q_next_targets(nl);
                let mut block = Block::new(ScalarKind::LoopWork(LoopWork), vars, len, targets);
                block.linear_from = n;
                self.gradient_blocks.push(block);
                let targets = l.loop_rows(j).map(|r| vec![r]).collect();
                self.vector_blocks.push(Block::new(
                    VectorKind::LoopClosure(LoopClosure),
                    range_vec(l.q(j + 1)),
                    n,
                    targets,
                ));
            }
            for i in 0..nc {
                let mut vars = range_vec(l.q(j));
                vars.extend(l.q(j + 1));
                vars.push(l.h(j));
                let tangential: Vec<Vec<usize>> =
                    l.tangential_rows(j, i).map(|r| vec![r]).collect();
                self.vector_blocks.push(Block::new(
                    VectorKind::TangentialRate(TangentialRate { contact: i }),
                    vars,
                    2 * n + 1,
                    tangential.clone(),
                ));
                let mut vars = vec![l.psi(j, i)];
                vars.extend(l.eta(j, i));
                self.vector_blocks.push(Block::new(
                    VectorKind::TangentialSlack(TangentialSlack),
                    vars,
                    0,
                    tangential,
                ));
                self.vector_blocks.push(Block::new(
                    VectorKind::Distance(Distance {
                        contact: i,
                        gap: false,
                    }),
                    range_vec(l.q(j + 1)),
                    n,
                    vec![vec![l.distance_row(j, i)]],
                ));
                let mut vars = vec![l.c(j, i)];
                vars.extend(l.beta(j, i));
                self.vector_blocks.push(Block::new(
                    VectorKind::FrictionCone(FrictionCone { contact: i }),
                    vars,
                    0,
                    vec![vec![l.cone_row(j, i)]],
                ));
            }
            let contact_vars = |i: usize| {
                let mut v = vec![l.c(j, i)];
                v.extend(l.beta(j, i));
                v.push(l.psi(j, i));
                v.extend(l.eta(j, i));
                v
            };
            // One block per contact keeps the Hessian sparse (products of different
            // contacts never meet); in per-interval mode the shared slack rides on the
            // first block and every block adds into the same three rows.
            let rows = range_vec(l.complementarity_rows_of(j));
            let slacks = range_vec(l.slack(j));
            let shared = slacks.len() == 1;
            let groups: Vec<Vec<usize>> = if nc == 0 {
                vec![vec![]]
            } else {
                (0..nc).map(|i| vec![i]).collect()
            };
            for (g, contacts) in groups.into_iter().enumerate() {
                let mut vars = Vec::new();
                for &i in &contacts {
                    vars.extend(contact_vars(i));
                }
                let nonlinear = vars.len();
                let (own, block_rows) = if shared {
                    let own = if g == 0 { vec![slacks[0]] } else { vec![] };
                    (own, &rows[..3])
                } else {
                    (slacks[3 * g..3 * g + 3].to_vec(), &rows[3 * g..3 * g + 3])
                };
                for &i in &contacts {
                    let mut vars = range_vec(l.q(j + 1));
                    vars.push(l.c(j, i));
                    self.vector_blocks.push(Block::new(
                        VectorKind::Distance(Distance {
                            contact: i,
                            gap: true,
                        }),
                        vars,
                        n + 1,
                        vec![vec![block_rows[1]]],
                    ));
                }
                let num_slacks = own.len();
                vars.extend(own);
                let targets = block_rows.iter().map(|&r| vec![r]).collect();
                self.vector_blocks.push(Block::new(
                    VectorKind::Complementarity(Complementarity {
                        contacts,
                        slacks: num_slacks,
                    }),
                    vars,
                    nonlinear,
                    targets,
                ));
            }
        }
        if l.equal_steps {
            for j in 0..l.knots - 2 {
                self.vector_blocks.push(Block::new(
                    VectorKind::EqualStep(EqualStep),
                    vec![l.h(j), l.h(j + 1)],
                    0,
                    vec![vec![l.equal_step_row(j)]],
                ));
            }
        }
        if nl > 0 {
            let targets = l.first_loop_rows().map(|r| vec![r]).collect();
            self.vector_blocks.push(Block::new(
                VectorKind::LoopClosure(LoopClosure),
                range_vec(l.q(0)),
                n,
                targets,
            ));
        }
        let mut row = l.constraint_row(0);
        for (index, constraint) in self.ctx.constraints.iter().enumerate() {
            let vars = constraint_variables(l, &constraint.inputs());
            let targets = (0..constraint.rows().len())
                .map(|r| vec![row + r])
                .collect::<Vec<_>>();
            row += targets.len();
            let len = vars.len();
            self.vector_blocks.push(Block::new(
                VectorKind::Constraint(Constraint { index }),
                vars,
                len,
                targets,
            ));
        }
        for (term, cost) in self.ctx.costs.iter().enumerate() {
            let declared = costs::declaration(cost);
            for vars in cost_placements(l, declared.inputs) {
                let nonlinear = if declared.linear { 0 } else { vars.len() };
                let kind = ScalarKind::Cost(Cost { term });
                self.cost_blocks
                    .push(Block::new(kind, vars, nonlinear, vec![]));
            }
        }
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
