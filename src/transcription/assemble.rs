//! The transcription: blocks placed on the layout, patterns built once, and the values of
//! objective, gradient, constraints, Jacobian and Lagrangian Hessian assembled from
//! per-block dense derivatives (computed in parallel, scattered serially).

use nalgebra::DMatrix;
use rayon::prelude::*;

use super::blocks::{
    Block, Context, ScalarBlockFn, ScalarKind, VectorBlockFn, VectorKind, complementarity_hessian,
    complementarity_jacobian, contact_work_gradient, contact_work_hessian, contact_work_third,
    distance_hessian, distance_jacobian, tangential_rate_hessian, tangential_rate_jacobian,
};
use super::layout::{Dims, Layout};
use super::pattern::{Pattern, PatternBuilder};
use super::{Mechanics, TranscriptionError};
use crate::autodiff::{
    Restricted, ThirdOrder, gradient, gradient_hessian, gradient_hessian_third, jacobian,
    weighted_hessian,
};
use num_dual::Dual64;

use crate::contact::FrictionBasis;
use crate::model::BaseType;
use crate::problem::{
    CostTerm, HessianMode, InitialGuess, Integrator, Interval, KnotSet, ProblemSpec, TimeSteps,
};

/// SPEC.md's values at the initial guess (no solver involved).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialGuessReport {
    /// Objective f(x₀) (problem cost + slack penalty).
    pub objective: f64,
    /// Largest constraint violation at x₀.
    pub max_constraint_violation: f64,
    /// 2-norm of the equality-constraint residuals at x₀.
    pub equality_residual_norm: f64,
}

/// The variational contact NLP of one problem (SPEC.md), ready for Ipopt.
pub struct Transcription<M> {
    mech: M,
    ctx: Context,
    layout: Layout,
    slack_weight: f64,
    hessian_mode: HessianMode,
    x_lower: Vec<f64>,
    x_upper: Vec<f64>,
    g_lower: Vec<f64>,
    g_upper: Vec<f64>,
    x_initial: Vec<f64>,
    vector_blocks: Vec<Block<VectorKind>>,
    gradient_blocks: Vec<Block<ScalarKind>>,
    cost_blocks: Vec<Block<ScalarKind>>,
    jacobian: Pattern,
    hessian: Pattern,
    parallel: bool,
    /// Contact blocks by the chain rule over q (true) or by generic AD over the block.
    contact_chain_rule: bool,
    /// See [`Transcription::set_skip_fixed_variables`].
    skip_fixed: bool,
}

fn range_vec(r: std::ops::Range<usize>) -> Vec<usize> {
    r.collect()
}

fn check_len(field: &str, expected: usize, found: usize) -> Result<(), TranscriptionError> {
    if expected == found {
        Ok(())
    } else {
        Err(TranscriptionError::Length {
            field: field.to_string(),
            expected,
            found,
        })
    }
}

fn intersect(a: Interval, b: Interval) -> Interval {
    Interval {
        lower: a.lower.max(b.lower),
        upper: a.upper.min(b.upper),
    }
}

impl<M: Mechanics> Transcription<M> {
    /// Lay out the NLP of `spec` for the robot `mech` (whose contacts are `spec.contacts`,
    /// in order) and compute its sparsity patterns.
    pub fn new(mech: M, spec: &ProblemSpec) -> Result<Self, TranscriptionError> {
        let (n, m, nl) = (mech.nq(), mech.nu(), mech.num_loop_constraints());
        let nc = spec.contacts.len();
        check_len("contacts", mech.num_contacts(), nc)?;
        check_len("q_initial", n, spec.q_initial.len())?;
        check_len("q_final", n, spec.q_final.len())?;
        check_len("input_bounds", m, spec.input_bounds.len())?;
        if let Some(v) = &spec.v_initial {
            check_len("v_initial", n, v.len())?;
        }
        if spec.knots < 2 {
            return Err(TranscriptionError::Invalid {
                field: "knots".into(),
                message: format!("{} knots; a trajectory needs at least 2", spec.knots),
            });
        }
        let basis = detect_basis(&mech, spec.robot.base, &spec.q_initial);
        let nd = basis.num_directions();
        let ctx = Context {
            n,
            m,
            nl,
            basis,
            friction: spec.contacts.iter().map(|c| c.friction).collect(),
            terrain: spec.terrain.clone(),
            integrator: spec.integrator,
            costs: spec.costs.clone(),
        };
        for (t, term) in spec.costs.iter().enumerate() {
            check_cost_lengths(t, term, n, m)?;
        }
        let equal_steps = matches!(spec.time_steps, TimeSteps::FreeEqual { .. });
        let layout = Layout::new(
            Dims { n, m, nc, nd, nl },
            spec.knots,
            spec.slack_mode,
            equal_steps,
            &spec.periodic,
        );
        let mut t = Transcription {
            ctx,
            layout,
            slack_weight: spec.slack_weight,
            hessian_mode: spec.hessian,
            x_lower: Vec::new(),
            x_upper: Vec::new(),
            g_lower: Vec::new(),
            g_upper: Vec::new(),
            x_initial: Vec::new(),
            vector_blocks: Vec::new(),
            gradient_blocks: Vec::new(),
            cost_blocks: Vec::new(),
            jacobian: Pattern::default(),
            hessian: Pattern::default(),
            parallel: true,
            contact_chain_rule: true,
            skip_fixed: false,
            mech,
        };
        // Measured (2 shared cores): rayon costs more than it saves on hopper-2d's 288
        // variables (J+H 1.6 ms serial, 6 ms parallel) and pays on brick-3d's 3532
        // (J+H 104 ms serial, 58 ms parallel, one run); see benches/transcription_evaluation.rs.
        t.parallel = t.layout.num_variables() >= 1000;
        t.place_blocks();
        t.set_bounds(spec)?;
        t.set_initial_guess(spec)?;
        // Probe with generic AD, whose structural zeros are exact; the chain-rule paths can
        // leave round-off (1e-17) where a derivative vanishes identically.
        t.contact_chain_rule = false;
        t.build_patterns();
        t.contact_chain_rule = true;
        Ok(t)
    }

    fn place_blocks(&mut self) {
        let l = &self.layout;
        let (n, nc, nl) = (l.n, l.nc, l.nl);
        let last = l.intervals();
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
                    VectorKind::EulerKnot { first_step: j == 0 },
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
                    targets.push(next_rows.as_ref().map_or(vec![], |rows| vec![rows[c]]));
                }
                targets.push(vec![]);
                let len = vars.len();
                self.gradient_blocks
                    .push(Block::new(ScalarKind::Segment, vars, len, targets));

                if self.mech.has_discrete_force() {
                    let mut vars = range_vec(l.q(j));
                    vars.extend(l.q(j + 1));
                    vars.extend(l.u(j));
                    vars.push(l.h(j));
                    let targets = (0..n)
                        .map(|c| {
                            let mut rows = vec![dyn_rows[c]];
                            rows.extend(next_rows.as_ref().map(|r| r[c]));
                            rows
                        })
                        .collect();
                    let len = vars.len();
                    self.vector_blocks
                        .push(Block::new(VectorKind::HalfForce, vars, len, targets));
                }
                if j == 0 {
                    let mut vars = range_vec(l.q(0));
                    vars.extend(l.v0());
                    let targets = dyn_rows.iter().map(|&r| vec![r]).collect();
                    self.vector_blocks.push(Block::new(
                        VectorKind::InitialMomentum,
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
                let mut block =
                    Block::new(ScalarKind::ContactWork { contact: i }, vars, len, targets);
                block.linear_from = n;
                self.gradient_blocks.push(block);
            }
            if nl > 0 {
                let mut vars = range_vec(l.q(j + 1));
                vars.extend(l.gamma(j));
                let len = vars.len();
                let targets = q_next_targets(nl);
                let mut block = Block::new(ScalarKind::LoopWork, vars, len, targets);
                block.linear_from = n;
                self.gradient_blocks.push(block);
                let targets = l.loop_rows(j).map(|r| vec![r]).collect();
                self.vector_blocks.push(Block::new(
                    VectorKind::LoopClosure,
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
                    VectorKind::TangentialRate { contact: i },
                    vars,
                    2 * n + 1,
                    tangential.clone(),
                ));
                let mut vars = vec![l.psi(j, i)];
                vars.extend(l.eta(j, i));
                self.vector_blocks.push(Block::new(
                    VectorKind::TangentialSlack,
                    vars,
                    0,
                    tangential,
                ));
                self.vector_blocks.push(Block::new(
                    VectorKind::Distance { contact: i },
                    range_vec(l.q(j + 1)),
                    n,
                    vec![vec![l.distance_row(j, i)]],
                ));
                let mut vars = vec![l.c(j, i)];
                vars.extend(l.beta(j, i));
                self.vector_blocks.push(Block::new(
                    VectorKind::FrictionCone { contact: i },
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
                        VectorKind::ContactGap { contact: i },
                        vars,
                        n + 1,
                        vec![vec![block_rows[1]]],
                    ));
                }
                let num_slacks = own.len();
                vars.extend(own);
                let targets = block_rows.iter().map(|&r| vec![r]).collect();
                self.vector_blocks.push(Block::new(
                    VectorKind::Complementarity {
                        contacts,
                        slacks: num_slacks,
                    },
                    vars,
                    nonlinear,
                    targets,
                ));
            }
        }
        if l.equal_steps {
            for j in 0..l.knots - 2 {
                self.vector_blocks.push(Block::new(
                    VectorKind::EqualStep,
                    vec![l.h(j), l.h(j + 1)],
                    0,
                    vec![vec![l.equal_step_row(j)]],
                ));
            }
        }
        if nl > 0 {
            let targets = l.first_loop_rows().map(|r| vec![r]).collect();
            self.vector_blocks.push(Block::new(
                VectorKind::LoopClosure,
                range_vec(l.q(0)),
                n,
                targets,
            ));
        }
        let last_knot = l.knots - 1;
        for (r, &(c, velocity, offset)) in l.periodic_rows.iter().enumerate() {
            let row = vec![vec![l.periodic_row(r)]];
            if velocity {
                let vars = vec![
                    l.q(0).start + c,
                    l.q(1).start + c,
                    l.h(0),
                    l.q(last_knot - 1).start + c,
                    l.q(last_knot).start + c,
                    l.h(last_knot - 1),
                ];
                self.vector_blocks
                    .push(Block::new(VectorKind::PeriodicVelocity, vars, 6, row));
            } else {
                let vars = vec![l.q(0).start + c, l.q(last_knot).start + c];
                self.vector_blocks.push(Block::new(
                    VectorKind::PeriodicPosition { offset },
                    vars,
                    0,
                    row,
                ));
            }
        }
        for (term, cost) in self.ctx.costs.iter().enumerate() {
            let kind = ScalarKind::Cost { term };
            let mut push = |vars: Vec<usize>, nonlinear: usize| {
                self.cost_blocks
                    .push(Block::new(kind.clone(), vars, nonlinear, vec![]));
            };
            match cost {
                CostTerm::StateTracking { .. } | CostTerm::ConfigurationDifference { .. } => {
                    for j in 0..l.intervals() {
                        let mut vars = range_vec(l.q(j));
                        vars.extend(l.q(j + 1));
                        if matches!(cost, CostTerm::StateTracking { .. }) {
                            vars.push(l.h(j));
                        }
                        let len = vars.len();
                        push(vars, len);
                    }
                }
                CostTerm::Input { .. } => {
                    for j in 0..l.intervals() {
                        let mut vars = range_vec(l.u(j));
                        vars.push(l.h(j));
                        let len = vars.len();
                        push(vars, len);
                    }
                }
                CostTerm::InputRate { .. } => {
                    for j in 1..l.intervals() {
                        let mut vars = range_vec(l.u(j - 1));
                        vars.extend(l.u(j));
                        let len = vars.len();
                        push(vars, len);
                    }
                }
                CostTerm::FinalState { .. } => push(range_vec(l.q(last_knot)), n),
                CostTerm::Time { .. } => {
                    for j in 0..l.intervals() {
                        push(vec![l.h(j)], 0);
                    }
                }
            }
        }
    }

    /// Points to probe structural zeros at: the initial point moved by seeded noise
    /// (steps scaled so they stay positive).
    fn probe_points(&self) -> Vec<Vec<f64>> {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut uniform = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        (0..2)
            .map(|_| {
                let mut x: Vec<f64> = self
                    .x_initial
                    .iter()
                    .map(|&v| v + 0.6 * uniform())
                    .collect();
                for j in 0..self.layout.intervals() {
                    let h = self.layout.h(j);
                    x[h] = self.x_initial[h] * (1.0 + 0.6 * uniform());
                }
                x
            })
            .collect()
    }

    /// Which local Jacobian rows × inputs and lower Hessian pairs of a block are nonzero at
    /// any probe point (with random multipliers): entries zero at every probe are
    /// structural zeros (e.g. a leg's joint in another leg's DEL row) and stay out of the
    /// patterns.
    fn probe<K>(
        &self,
        b: &Block<K>,
        points: &[Vec<f64>],
        local: impl Fn(&[f64], &[f64]) -> (Option<DMatrix<f64>>, Option<DMatrix<f64>>),
    ) -> (Vec<bool>, Vec<bool>) {
        let nv = b.vars.len();
        let mut jac = vec![false; b.targets.len() * nv];
        let mut hess = vec![false; nv * nv];
        for (p, x) in points.iter().enumerate() {
            let z = gather(x, &b.vars);
            let weights: Vec<f64> = (0..b.targets.len())
                .map(|o| {
                    if b.targets[o].is_empty() {
                        0.0
                    } else {
                        1.0 + 0.37 * ((o * 7 + p * 3) % 5) as f64
                    }
                })
                .collect();
            let (j, h) = local(&z, &weights);
            if let Some(j) = j {
                for o in 0..b.targets.len() {
                    for a in 0..nv {
                        jac[o * nv + a] |= j[(o, a)] != 0.0;
                    }
                }
            }
            if let Some(h) = h {
                for a in 0..b.nonlinear {
                    for c in 0..=a {
                        hess[a * nv + c] |= h[(a, c)] != 0.0;
                    }
                }
            }
        }
        (jac, hess)
    }

    fn build_patterns(&mut self) {
        let points = self.probe_points();
        let cost_masks: Vec<_> = self
            .cost_blocks
            .iter()
            .map(|b| {
                self.probe(b, &points, |z, _| {
                    (None, Some(gradient_hessian(&self.scalar_fn(b), z).2))
                })
            })
            .collect();
        let gradient_masks: Vec<_> = self
            .gradient_blocks
            .iter()
            .map(|b| {
                self.probe(b, &points, |z, w| {
                    let third = self.gradient_block_third(b, z, w);
                    (Some(third.hessian), Some(third.contracted))
                })
            })
            .collect();
        let vector_masks: Vec<_> = self
            .vector_blocks
            .iter()
            .map(|b| {
                self.probe(b, &points, |z, w| {
                    let f = self.vector_fn(b);
                    let h = (b.nonlinear > 0).then(|| weighted_hessian(&f, z, w));
                    (Some(jacobian(&f, z).1), h)
                })
            })
            .collect();
        let mut jac = PatternBuilder::default();
        let mut hess = PatternBuilder::default();
        let fixed: Vec<bool> = self
            .x_lower
            .iter()
            .zip(&self.x_upper)
            .map(|(lo, hi)| lo == hi)
            .collect();
        fn place<K>(
            b: &mut Block<K>,
            (jmask, hmask): &(Vec<bool>, Vec<bool>),
            fixed: &[bool],
            jac: &mut PatternBuilder,
            hess: &mut PatternBuilder,
        ) {
            let nv = b.vars.len();
            let mut slots = Vec::new();
            for (o, rows) in b.targets.iter().enumerate() {
                for &r in rows {
                    for (a, &v) in b.vars.iter().enumerate() {
                        slots.push(if jmask[o * nv + a] {
                            jac.slot(r, v)
                        } else {
                            NO_SLOT
                        });
                    }
                }
            }
            b.jacobian_slots = slots;
            let mut hslots = Vec::new();
            let mut active = vec![false; b.nonlinear];
            for a in 0..b.nonlinear {
                for c in (0..=a).filter(|&c| b.has_hessian_pair(a, c)) {
                    if !hmask[a * nv + c] {
                        hslots.push((NO_SLOT, 0.0));
                        continue;
                    }
                    active[a] = true;
                    active[c] = true;
                    let mult = if a != c && b.vars[a] == b.vars[c] {
                        2.0
                    } else {
                        1.0
                    };
                    hslots.push((hess.lower_slot(b.vars[a], b.vars[c]), mult));
                }
            }
            b.hessian_slots = hslots;
            b.hessian_inputs = (0..b.nonlinear).filter(|&a| active[a]).collect();
            b.free_input_mask = b.vars.iter().map(|&v| !fixed[v]).collect();
            b.hessian_free_inputs = b
                .hessian_inputs
                .iter()
                .copied()
                .filter(|&a| !fixed[b.vars[a]])
                .collect();
        }
        for (b, m) in self.cost_blocks.iter_mut().zip(&cost_masks) {
            place(b, m, &fixed, &mut jac, &mut hess);
        }
        for (b, m) in self.gradient_blocks.iter_mut().zip(&gradient_masks) {
            place(b, m, &fixed, &mut jac, &mut hess);
        }
        for (b, m) in self.vector_blocks.iter_mut().zip(&vector_masks) {
            place(b, m, &fixed, &mut jac, &mut hess);
        }
        self.jacobian = jac.finish();
        self.hessian = hess.finish();
    }

    fn set_bounds(&mut self, spec: &ProblemSpec) -> Result<(), TranscriptionError> {
        let l = &self.layout;
        let nv = l.num_variables();
        let mut lo = vec![f64::NEG_INFINITY; nv];
        let mut hi = vec![f64::INFINITY; nv];
        let limits = self.mech.coordinate_limits();
        let last = l.knots - 1;
        for k in 0..l.knots {
            for c in 0..l.n {
                let mut b = Interval::FREE;
                if spec.joint_limits {
                    b = intersect(b, limits[c]);
                }
                for cb in spec.bounds.iter().filter(|cb| cb.coordinate == c) {
                    let applies = match &cb.knots {
                        KnotSet::All => true,
                        KnotSet::Interior => k > 0 && k < last,
                        KnotSet::First => k == 0,
                        KnotSet::Last => k == last,
                        KnotSet::List(list) => list.contains(&k),
                    };
                    if applies {
                        b = intersect(b, cb.bound);
                    }
                }
                if k == last {
                    b = intersect(b, spec.q_final[c]);
                }
                if k == 0 {
                    b = Interval::fixed(spec.q_initial[c]);
                }
                if b.lower > b.upper {
                    return Err(TranscriptionError::EmptyBound {
                        coordinate: c,
                        knot: k,
                        lower: b.lower,
                        upper: b.upper,
                    });
                }
                lo[l.q(k).start + c] = b.lower;
                hi[l.q(k).start + c] = b.upper;
            }
        }
        if let Some(v0) = &spec.v_initial {
            for (i, &v) in l.v0().zip(v0) {
                lo[i] = v;
                hi[i] = v;
            }
        }
        let (h_lo, h_hi) = match spec.time_steps {
            TimeSteps::Fixed(h) => (h, h),
            TimeSteps::FreeEqual { t_min, t_max } => {
                let intervals = l.intervals() as f64;
                (t_min / intervals, t_max / intervals)
            }
        };
        if !(h_lo > 0.0 && h_lo <= h_hi) {
            return Err(TranscriptionError::Invalid {
                field: "time_steps".into(),
                message: format!("step bounds [{h_lo}, {h_hi}] must satisfy 0 < min ≤ max"),
            });
        }
        for j in 0..l.intervals() {
            lo[l.h(j)] = h_lo;
            hi[l.h(j)] = h_hi;
            for (i, b) in l.u(j).zip(&spec.input_bounds) {
                lo[i] = b.lower;
                hi[i] = b.upper;
            }
            for i in l.contact_vars(j) {
                lo[i] = 0.0;
            }
            if let Some(v) = spec.max_slip_speed {
                for i in 0..l.nc {
                    hi[l.psi(j, i)] = v;
                }
            }
        }
        for i in l.slacks() {
            lo[i] = 0.0;
        }
        let nr = l.num_constraints();
        let g_lower = vec![0.0; nr];
        let g_upper = (0..nr)
            .map(|r| if l.is_equality(r) { 0.0 } else { f64::INFINITY })
            .collect();
        self.x_lower = lo;
        self.x_upper = hi;
        self.g_lower = g_lower;
        self.g_upper = g_upper;
        Ok(())
    }

    fn set_initial_guess(&mut self, spec: &ProblemSpec) -> Result<(), TranscriptionError> {
        let l = &self.layout;
        let mut x = vec![0.0; l.num_variables()];
        let mut h_guess = match spec.time_steps {
            TimeSteps::Fixed(h) => h,
            TimeSteps::FreeEqual { t_max, .. } => t_max / l.intervals() as f64,
        };
        let last = l.knots - 1;
        match &spec.initial_guess {
            InitialGuess::Linear { from, to } => {
                check_len("initial_guess.from", l.n, from.len())?;
                check_len("initial_guess.to", l.n, to.len())?;
                for k in 0..l.knots {
                    let s = k as f64 / last as f64;
                    for (c, i) in l.q(k).enumerate() {
                        x[i] = from[c] + s * (to[c] - from[c]);
                    }
                }
            }
            InitialGuess::WarmStart(w) => {
                // Free steps take the previous solution's duration (within the window) and
                // resample it over the knots; fixed steps sample it at their own times.
                let duration = w.times.last().copied().unwrap_or(0.0)
                    - w.times.first().copied().unwrap_or(0.0);
                if let TimeSteps::FreeEqual { t_min, t_max } = spec.time_steps
                    && duration > 0.0
                {
                    h_guess = duration.clamp(t_min, t_max) / l.intervals() as f64;
                }
                let stretch = match spec.time_steps {
                    TimeSteps::FreeEqual { .. } if duration > 0.0 => {
                        duration / (h_guess * l.intervals() as f64)
                    }
                    _ => 1.0,
                };
                let times: Vec<f64> = (0..l.knots)
                    .map(|k| w.times.first().copied().unwrap_or(0.0) + k as f64 * h_guess * stretch)
                    .collect();
                for (k, &t) in times.iter().enumerate() {
                    let q = interpolate(&w.times, &w.q, t);
                    check_len("initial_guess.q", l.n, q.len())?;
                    for (c, i) in l.q(k).enumerate() {
                        x[i] = q[c];
                    }
                    if k < last && !w.u.is_empty() {
                        let u = interpolate(&w.times[..w.u.len()], &w.u, t);
                        check_len("initial_guess.u", l.m, u.len())?;
                        for (c, i) in l.u(k).enumerate() {
                            x[i] = u[c];
                        }
                    }
                }
            }
        }
        for j in 0..l.intervals() {
            x[l.h(j)] = h_guess;
            for i in l.contact_vars(j) {
                x[i] = 0.01;
            }
        }
        for i in l.slacks() {
            x[i] = 0.01;
        }
        // A fixed variable starts at its fixed value (SPEC.md).
        for ((xi, &lo), &hi) in x.iter_mut().zip(&self.x_lower).zip(&self.x_upper) {
            if lo == hi {
                *xi = lo;
            }
        }
        self.x_initial = x;
        Ok(())
    }

    /// Slack weight α of the objective α Σ s.
    pub fn slack_weight(&self) -> f64 {
        self.slack_weight
    }

    /// Change α (for the exact-penalty continuation).
    pub fn set_slack_weight(&mut self, weight: f64) {
        self.slack_weight = weight;
    }

    /// Start the next solve from `x` (all variables, e.g. a previous solution), clamped to the
    /// variable bounds.
    pub fn set_initial_point(&mut self, x: &[f64]) -> Result<(), TranscriptionError> {
        check_len("initial point", self.x_initial.len(), x.len())?;
        for (i, (&xi, out)) in x.iter().zip(self.x_initial.iter_mut()).enumerate() {
            *out = xi.clamp(self.x_lower[i], self.x_upper[i]);
        }
        Ok(())
    }

    /// Evaluate independent blocks on rayon's thread pool or on one thread (the default
    /// is parallel from 1000 variables on).
    pub fn set_parallel(&mut self, parallel: bool) {
        self.parallel = parallel;
    }

    /// Differentiate the contact blocks (tangential rate, contact work, signed distance, c·φ)
    /// by the chain rule through the contact point's jet, and the bilinear complementarity rows
    /// in closed form (the default), or all of them by generic forward AD over the whole block
    /// (for comparison; the sparsity pattern, probed with generic AD, is the same).
    pub fn set_contact_chain_rule(&mut self, enabled: bool) {
        self.contact_chain_rule = enabled;
    }

    /// Seconds spent on one Jacobian plus Lagrangian-Hessian evaluation per block kind
    /// (serial, at x with constraint multipliers `lambda`), named like the block kinds
    /// ("Segment", "ContactWork", "TangentialRate", …); for benchmarks.
    pub fn derivative_time_by_kind(&self, x: &[f64], lambda: &[f64]) -> Vec<(String, f64)> {
        let mut times: Vec<(String, f64)> = Vec::new();
        let mut add = |name: String, secs: f64| match times.iter_mut().find(|(n, _)| *n == name) {
            Some(entry) => entry.1 += secs,
            None => times.push((name, secs)),
        };
        let kind_name = |debug: String| debug.split([' ', '{']).next().unwrap_or("").to_string();
        let weights = |targets: &[Vec<usize>]| -> Vec<f64> {
            targets
                .iter()
                .map(|rows| rows.iter().map(|&r| lambda[r]).sum())
                .collect()
        };
        for b in &self.vector_blocks {
            let z = gather(x, &b.vars);
            let start = std::time::Instant::now();
            std::hint::black_box(self.vector_block_jacobian(b, &z));
            if b.nonlinear > 0 {
                std::hint::black_box(self.vector_block_hessian(b, &z, &weights(&b.targets)));
            }
            add(
                kind_name(format!("{:?}", b.kind)),
                start.elapsed().as_secs_f64(),
            );
        }
        for b in &self.gradient_blocks {
            let z = gather(x, &b.vars);
            let start = std::time::Instant::now();
            std::hint::black_box(self.gradient_block_hessian(b, &z));
            std::hint::black_box(self.gradient_block_third(b, &z, &weights(&b.targets)));
            add(
                kind_name(format!("{:?}", b.kind)),
                start.elapsed().as_secs_f64(),
            );
        }
        times
    }

    fn map_blocks<K: Sync, R: Send>(
        &self,
        blocks: &[Block<K>],
        f: impl Fn(&Block<K>) -> R + Sync + Send,
    ) -> Vec<R> {
        if self.parallel {
            // Batches of blocks: one task per block costs more in wake-ups than the
            // cheaper blocks take to evaluate.
            blocks.par_iter().with_min_len(32).map(f).collect()
        } else {
            blocks.iter().map(f).collect()
        }
    }

    /// The variable and row layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }
    /// The robot mechanics.
    pub fn mechanics(&self) -> &M {
        &self.mech
    }
    /// Variable bounds (lower, upper), length = number of variables.
    pub fn variable_bounds(&self) -> (&[f64], &[f64]) {
        (&self.x_lower, &self.x_upper)
    }
    /// Constraint bounds (lower, upper), length = number of rows.
    pub fn constraint_bounds(&self) -> (&[f64], &[f64]) {
        (&self.g_lower, &self.g_upper)
    }
    /// The starting point.
    pub fn initial_point(&self) -> &[f64] {
        &self.x_initial
    }
    /// Jacobian sparsity.
    pub fn jacobian_pattern(&self) -> &Pattern {
        &self.jacobian
    }
    /// Lagrangian-Hessian sparsity (lower triangle).
    pub fn hessian_pattern(&self) -> &Pattern {
        &self.hessian
    }
    /// How the Hessian is obtained.
    pub fn hessian_mode(&self) -> HessianMode {
        self.hessian_mode
    }
    /// Problem constants of the blocks.
    pub fn context(&self) -> &Context {
        &self.ctx
    }

    fn vector_fn<'a>(&'a self, b: &'a Block<VectorKind>) -> VectorBlockFn<'a, M> {
        VectorBlockFn {
            mech: &self.mech,
            ctx: &self.ctx,
            kind: &b.kind,
            dim_in: b.vars.len(),
            dim_out: b.targets.len(),
        }
    }
    /// Gradient of a gradient block at z (the DEL-row values).
    fn gradient_block_gradient(&self, b: &Block<ScalarKind>, z: &[f64]) -> Vec<f64> {
        if b.kind == ScalarKind::Segment
            && let Some(g) = self.mech.segment_gradient(z)
        {
            return g;
        }
        if let ScalarKind::ContactWork { contact } = b.kind
            && self.contact_chain_rule
        {
            return contact_work_gradient(&self.mech, &self.ctx, contact, z);
        }
        gradient(&self.scalar_fn(b), z).1
    }

    /// Hessian of a gradient block at z (the model's adjoint path for Ld when it has one).
    fn gradient_block_hessian(&self, b: &Block<ScalarKind>, z: &[f64]) -> DMatrix<f64> {
        if b.kind == ScalarKind::Segment
            && let Some((_, h)) = self.mech.segment_gradient_hessian(z)
        {
            return h;
        }
        if let ScalarKind::ContactWork { contact } = b.kind
            && self.contact_chain_rule
        {
            return contact_work_hessian(&self.mech, &self.ctx, contact, z);
        }
        gradient_hessian(&self.scalar_fn(b), z).2
    }

    /// Hessian and contracted third derivative of a gradient block at z.
    fn gradient_block_third(&self, b: &Block<ScalarKind>, z: &[f64], dir: &[f64]) -> ThirdOrder {
        if b.kind == ScalarKind::Segment
            && let Some(t) = self.mech.segment_third_order(
                z,
                dir,
                self.skip_fixed.then_some(b.free_input_mask.as_slice()),
            )
        {
            return t;
        }
        if let ScalarKind::ContactWork { contact } = b.kind
            && self.contact_chain_rule
            && let Some((hessian, contracted)) =
                contact_work_third(&self.mech, &self.ctx, contact, z, dir)
        {
            return ThirdOrder {
                value: 0.0,
                gradient: Vec::new(),
                hessian,
                contracted,
            };
        }
        gradient_hessian_third(&self.scalar_fn(b), z, dir)
    }

    /// Jacobian of a vector block at z (chain-rule assembly for the tangential rates).
    fn vector_block_jacobian(&self, b: &Block<VectorKind>, z: &[f64]) -> DMatrix<f64> {
        if self.contact_chain_rule {
            match &b.kind {
                &VectorKind::TangentialRate { contact } => {
                    return tangential_rate_jacobian(&self.mech, &self.ctx, contact, z);
                }
                VectorKind::Complementarity { contacts, slacks } => {
                    return complementarity_jacobian(&self.ctx, contacts, *slacks, z);
                }
                &VectorKind::Distance { contact } => {
                    return distance_jacobian(&self.mech, &self.ctx, contact, z, false);
                }
                &VectorKind::ContactGap { contact } => {
                    return distance_jacobian(&self.mech, &self.ctx, contact, z, true);
                }
                _ => {}
            }
        }
        jacobian(&self.vector_fn(b), z).1
    }

    /// Σ_r w_r ∇²f_r of a vector block at z (chain-rule assembly for the tangential rates).
    fn vector_block_hessian(&self, b: &Block<VectorKind>, z: &[f64], w: &[f64]) -> DMatrix<f64> {
        if self.contact_chain_rule {
            match &b.kind {
                &VectorKind::TangentialRate { contact } => {
                    return tangential_rate_hessian(&self.mech, &self.ctx, contact, z, w);
                }
                VectorKind::Complementarity { contacts, .. } => {
                    return complementarity_hessian(&self.ctx, contacts, z.len(), w);
                }
                &VectorKind::Distance { contact } => {
                    return distance_hessian(&self.mech, &self.ctx, contact, z, w[0], false);
                }
                &VectorKind::ContactGap { contact } => {
                    return distance_hessian(&self.mech, &self.ctx, contact, z, w[0], true);
                }
                _ => {}
            }
        }
        let f = self.vector_fn(b);
        let inputs = self.hessian_inputs(b);
        if inputs.len() == b.nonlinear {
            return weighted_hessian(&f, z, w);
        }
        let r = Restricted {
            f: &f,
            at: z,
            free: inputs,
        };
        expand_hessian(&weighted_hessian(&r, &r.point(), w), inputs, z.len())
    }

    /// The inputs a generic-AD Hessian of `b` runs over: those in the Hessian pattern, less
    /// the fixed variables when [`Transcription::set_skip_fixed_variables`] is on.
    fn hessian_inputs<'b, K>(&self, b: &'b Block<K>) -> &'b [usize] {
        if self.skip_fixed {
            &b.hessian_free_inputs
        } else {
            &b.hessian_inputs
        }
    }

    /// Leave the Hessian entries of variables fixed by their bounds at zero where that saves
    /// work (generic-AD blocks). Ipopt drops those entries with its default
    /// `fixed_variable_treatment make_parameter`; the solve turns this on unless that option
    /// says otherwise. Off by default, so that every entry is exact.
    pub fn set_skip_fixed_variables(&mut self, skip: bool) {
        self.skip_fixed = skip;
    }

    /// Hessian of a cost block at z, over the inputs in the Hessian pattern only.
    fn cost_block_hessian(&self, b: &Block<ScalarKind>, z: &[f64]) -> DMatrix<f64> {
        let f = self.scalar_fn(b);
        let inputs = self.hessian_inputs(b);
        if inputs.len() == b.nonlinear {
            return gradient_hessian(&f, z).2;
        }
        let r = Restricted {
            f: &f,
            at: z,
            free: inputs,
        };
        expand_hessian(&gradient_hessian(&r, &r.point()).2, inputs, z.len())
    }

    fn scalar_fn<'a>(&'a self, b: &'a Block<ScalarKind>) -> ScalarBlockFn<'a, M> {
        ScalarBlockFn {
            mech: &self.mech,
            ctx: &self.ctx,
            kind: &b.kind,
            dim: b.vars.len(),
        }
    }

    /// Objective, largest constraint violation and ‖equality residuals‖₂ at the initial
    /// point (SPEC.md's "values at the initial guess").
    pub fn initial_guess_report(&self) -> InitialGuessReport {
        let x = &self.x_initial;
        let (max_violation, eq_norm) = self.violation(x);
        InitialGuessReport {
            objective: self.objective(x),
            max_constraint_violation: max_violation,
            equality_residual_norm: eq_norm,
        }
    }

    /// Largest violation of the constraint rows (|g| for equalities, the shortfall below
    /// the lower bound for inequalities) and the 2-norm of the equality residuals at x.
    pub fn violation(&self, x: &[f64]) -> (f64, f64) {
        let mut g = vec![0.0; self.layout.num_constraints()];
        self.constraints(x, &mut g);
        let mut max = 0.0_f64;
        let mut sq = 0.0;
        for (r, &gr) in g.iter().enumerate() {
            let v = (self.g_lower[r] - gr).max(gr - self.g_upper[r]).max(0.0);
            max = max.max(v);
            if self.layout.is_equality(r) {
                sq += gr * gr;
            }
        }
        (max, sq.sqrt())
    }

    /// Problem cost per term (names as in `Solution::objective_terms`) and the slack penalty.
    pub fn objective_terms(&self, x: &[f64]) -> Vec<(String, f64)> {
        let mut terms: Vec<(String, f64)> = Vec::new();
        for b in &self.cost_blocks {
            let ScalarKind::Cost { term } = b.kind else {
                continue;
            };
            let name = super::blocks::term_name(&self.ctx.costs[term]);
            let z = gather(x, &b.vars);
            let value = crate::autodiff::ScalarFunction::eval(&self.scalar_fn(b), &z);
            match terms.iter_mut().find(|(n, _)| n == name) {
                Some(entry) => entry.1 += value,
                None => terms.push((name.to_string(), value)),
            }
        }
        let slack: f64 = x[self.layout.slacks()].iter().sum();
        terms.push(("slack_penalty".into(), self.slack_weight * slack));
        terms
    }

    /// Objective f(x) = problem cost + α Σ s.
    pub fn objective(&self, x: &[f64]) -> f64 {
        let cost: f64 = self
            .cost_blocks
            .iter()
            .map(|b| crate::autodiff::ScalarFunction::eval(&self.scalar_fn(b), &gather(x, &b.vars)))
            .sum();
        let slack: f64 = x[self.layout.slacks()].iter().sum();
        cost + self.slack_weight * slack
    }

    /// Gradient of the objective (length = variables).
    pub fn gradient(&self, x: &[f64], grad: &mut [f64]) {
        grad.fill(0.0);
        let locals = self.map_blocks(&self.cost_blocks, |b| {
            gradient(&self.scalar_fn(b), &gather(x, &b.vars)).1
        });
        for (b, g) in self.cost_blocks.iter().zip(locals) {
            for (&v, gi) in b.vars.iter().zip(g) {
                grad[v] += gi;
            }
        }
        for i in self.layout.slacks() {
            grad[i] += self.slack_weight;
        }
    }

    /// Constraint values g(x) (length = rows).
    pub fn constraints(&self, x: &[f64], g: &mut [f64]) {
        g.fill(0.0);
        let vector = self.map_blocks(&self.vector_blocks, |b| {
            let f = self.vector_fn(b);
            let mut out = vec![0.0; b.targets.len()];
            crate::autodiff::VectorFunction::eval(&f, &gather(x, &b.vars), &mut out);
            out
        });
        for (b, out) in self.vector_blocks.iter().zip(vector) {
            for (rows, o) in b.targets.iter().zip(out) {
                for &r in rows {
                    g[r] += o;
                }
            }
        }
        let gradient = self.map_blocks(&self.gradient_blocks, |b| {
            self.gradient_block_gradient(b, &gather(x, &b.vars))
        });
        for (b, out) in self.gradient_blocks.iter().zip(gradient) {
            for (rows, o) in b.targets.iter().zip(out) {
                for &r in rows {
                    g[r] += o;
                }
            }
        }
    }

    /// Jacobian values in the order of `jacobian_pattern`.
    pub fn jacobian_values(&self, x: &[f64], values: &mut [f64]) {
        values.fill(0.0);
        let vector = self.map_blocks(&self.vector_blocks, |b| {
            self.vector_block_jacobian(b, &gather(x, &b.vars))
        });
        for (b, local) in self.vector_blocks.iter().zip(vector) {
            scatter_rows(b, &local, values);
        }
        let gradient = self.map_blocks(&self.gradient_blocks, |b| {
            self.gradient_block_hessian(b, &gather(x, &b.vars))
        });
        for (b, local) in self.gradient_blocks.iter().zip(gradient) {
            scatter_rows(b, &local, values);
        }
    }

    /// Values of ∇²(σ f + Σ λ_r g_r) in the order of `hessian_pattern`.
    pub fn hessian_values(&self, x: &[f64], obj_factor: f64, lambda: &[f64], values: &mut [f64]) {
        values.fill(0.0);
        let weights = |targets: &[Vec<usize>]| -> Vec<f64> {
            targets
                .iter()
                .map(|rows| rows.iter().map(|&r| lambda[r]).sum())
                .collect()
        };
        let costs = self.map_blocks(&self.cost_blocks, |b| {
            if b.nonlinear == 0 {
                return DMatrix::zeros(0, 0);
            }
            self.cost_block_hessian(b, &gather(x, &b.vars)) * obj_factor
        });
        for (b, local) in self.cost_blocks.iter().zip(costs) {
            scatter_lower(b, &local, values);
        }
        let vector = self.map_blocks(&self.vector_blocks, |b| {
            if b.nonlinear == 0 {
                return DMatrix::zeros(0, 0);
            }
            let z = gather(x, &b.vars);
            self.vector_block_hessian(b, &z, &weights(&b.targets))
        });
        for (b, local) in self.vector_blocks.iter().zip(vector) {
            scatter_lower(b, &local, values);
        }
        let gradient = self.map_blocks(&self.gradient_blocks, |b| {
            let dir = weights(&b.targets);
            self.gradient_block_third(b, &gather(x, &b.vars), &dir)
                .contracted
        });
        for (b, local) in self.gradient_blocks.iter().zip(gradient) {
            scatter_lower(b, &local, values);
        }
    }
}

fn check_cost_lengths(
    t: usize,
    term: &CostTerm,
    n: usize,
    m: usize,
) -> Result<(), TranscriptionError> {
    let f = |name: &str| format!("costs[{t}].{name}");
    match term {
        CostTerm::StateTracking {
            q_target,
            v_target,
            q_weights,
            v_weights,
            ..
        } => {
            check_len(&f("q_target"), n, q_target.len())?;
            check_len(&f("v_target"), n, v_target.len())?;
            check_len(&f("q_weights"), n, q_weights.len())?;
            check_len(&f("v_weights"), n, v_weights.len())
        }
        CostTerm::Input { weights, .. } | CostTerm::InputRate { weights } => {
            check_len(&f("weights"), m, weights.len())
        }
        CostTerm::ConfigurationDifference { weights } => check_len(&f("weights"), n, weights.len()),
        CostTerm::FinalState { q_target, weights } => {
            check_len(&f("q_target"), n, q_target.len())?;
            check_len(&f("weights"), n, weights.len())
        }
        CostTerm::Time { .. } => Ok(()),
    }
}

/// The friction basis: planar when the base is planar, or when no contact point can move
/// along world y (a planar robot built from a fixed base and sliders, like SPEC's hopper;
/// checked by the y-rates of every contact along every coordinate at two configurations).
fn detect_basis<M: Mechanics>(mech: &M, base: BaseType, q0: &[f64]) -> FrictionBasis {
    if base == BaseType::Planar {
        return FrictionBasis::Planar;
    }
    let n = mech.nq();
    for shift in [0.0, 0.3] {
        for c in 0..n {
            let q: Vec<Dual64> = (0..n)
                .map(|k| {
                    let value = q0[k] + shift * (1.0 + k as f64 * 0.37);
                    Dual64::new(value, if k == c { 1.0 } else { 0.0 })
                })
                .collect();
            for i in 0..mech.num_contacts() {
                if mech.contact_position(i, &q)[1].eps.abs() > 1e-12 {
                    return FrictionBasis::Spatial;
                }
            }
        }
    }
    FrictionBasis::Planar
}

/// Slot marker of a local entry that is structurally zero (not in the pattern).
const NO_SLOT: usize = usize::MAX;

/// x[vars] as a dense local vector.
fn gather(x: &[f64], vars: &[usize]) -> Vec<f64> {
    vars.iter().map(|&v| x[v]).collect()
}

/// Add a block's local rows (outputs or gradient components × inputs) into the Jacobian.
fn scatter_rows<K>(b: &Block<K>, local: &DMatrix<f64>, values: &mut [f64]) {
    let mut slot = b.jacobian_slots.iter();
    for (o, rows) in b.targets.iter().enumerate() {
        for _ in rows {
            for a in 0..b.vars.len() {
                if let Some(&s) = slot.next()
                    && s != NO_SLOT
                {
                    values[s] += local[(o, a)];
                }
            }
        }
    }
}

/// A Hessian over the inputs `free` placed into a zero dim × dim Hessian.
fn expand_hessian(sub: &DMatrix<f64>, free: &[usize], dim: usize) -> DMatrix<f64> {
    let mut full = DMatrix::zeros(dim, dim);
    for (a, &i) in free.iter().enumerate() {
        for (c, &j) in free.iter().enumerate() {
            full[(i, j)] = sub[(a, c)];
        }
    }
    full
}

/// Add a block's local Hessian (lower pairs of its nonlinear inputs) into the Hessian.
fn scatter_lower<K>(b: &Block<K>, local: &DMatrix<f64>, values: &mut [f64]) {
    let mut slot = b.hessian_slots.iter();
    for a in 0..b.nonlinear {
        for c in (0..=a).filter(|&c| b.has_hessian_pair(a, c)) {
            if let Some(&(s, mult)) = slot.next()
                && s != NO_SLOT
            {
                values[s] += mult * local[(a, c)];
            }
        }
    }
}

/// Piecewise-linear interpolation of rows `values` given at `times`, clamped at the ends.
fn interpolate(times: &[f64], values: &[Vec<f64>], t: f64) -> Vec<f64> {
    if times.is_empty() || values.is_empty() {
        return Vec::new();
    }
    let last = times.len().min(values.len()) - 1;
    if t <= times[0] {
        return values[0].clone();
    }
    if t >= times[last] {
        return values[last].clone();
    }
    let k = times[..=last].partition_point(|&s| s <= t).clamp(1, last);
    let (t0, t1) = (times[k - 1], times[k]);
    let s = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
    values[k - 1]
        .iter()
        .zip(&values[k])
        .map(|(a, b)| a + s * (b - a))
        .collect()
}
