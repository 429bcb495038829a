//! The NLP read at a point for the user: row violations, the objective by term, the
//! complementarity products, the largest slack, derivative time per block kind; and the
//! derivative check.
//!
//! The derivative check (`vito check --derivatives`): the objective gradient, the constraint
//! Jacobian and the Lagrangian Hessian (seeded random multipliers) against central finite
//! differences at one point, entry by entry, including the entries the declared structure
//! leaves out.
//!
//! Tolerance rule. Variable j is stepped by δ_j = 1e-6·max(1, |x_j|) both ways. An entry
//! passes when |analytic − fd| ≤ 1e-4·max(|analytic|, |fd|) + 1e-6·max(1, |F|), where F is
//! the value of the differenced function at x (the objective, the row g_r, or the Lagrangian
//! gradient component): the relative part covers the O(δ²) truncation error, the absolute
//! part the round-off of the difference (≈ 1e-16·|F|/δ) with a wide margin. An entry
//! outside the structure has analytic value 0 and is flagged when its fd value fails.
//!
//! Cost: entries are differenced in groups of variables that share no row (Jacobian) or no
//! block (Hessian), so a check costs a few hundred evaluations, not one per variable; the
//! grouping reads the blocks' variable lists, which bound every value's dependencies
//! whatever the declared structure says. Variables fixed by their bounds are left out, as
//! Ipopt drops their entries.

use std::collections::HashMap;

use super::{InitialGuessReport, Transcription};
use crate::discrete::MechanicsDerivatives;
use crate::problem::SlackMode;
use crate::random::SeededRng;
use crate::transcription::blocks::ScalarKind;
use crate::transcription::blocks::complementarity_penalty::{
    PENALTY_TERM, interval_products, interval_slack,
};
use crate::transcription::layout::EntryNames;
use crate::transcription::structure::gather;

/// Which derivative an entry belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DerivativeKind {
    /// ∂f/∂x_col of the objective (row unused).
    Gradient,
    /// ∂g_row/∂x_col.
    Jacobian,
    /// ∂²L/∂x_row∂x_col, row ≥ col.
    Hessian,
}

/// One compared entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EntryCheck {
    /// Which derivative.
    pub kind: DerivativeKind,
    /// Constraint row (Jacobian), variable (Hessian), 0 (gradient).
    pub row: usize,
    /// Variable.
    pub col: usize,
    /// The NLP's value (0 outside the declared structure).
    pub analytic: f64,
    /// Central finite difference.
    pub finite_difference: f64,
    /// Allowed |analytic − fd| (the module's tolerance rule).
    pub allowed: f64,
    /// Whether the entry is in the declared structure (always true for the gradient).
    pub declared: bool,
}

impl EntryCheck {
    /// |analytic − fd| / allowed: above 1 fails.
    pub fn ratio(&self) -> f64 {
        (self.analytic - self.finite_difference).abs() / self.allowed
    }
    /// Whether the entry exceeds its tolerance.
    pub fn fails(&self) -> bool {
        self.ratio().is_nan() || self.ratio() > 1.0
    }
}

/// The result of a derivative check.
#[derive(Debug, Clone, Default)]
pub struct DerivativeCheck {
    /// Every compared entry whose analytic or fd value is nonzero, worst (largest ratio) first.
    pub entries: Vec<EntryCheck>,
    /// Variables left out because their bounds fix them.
    pub fixed_variables: usize,
    /// Evaluations of the NLP functions the check took (objective, constraints, gradient+Jacobian).
    pub evaluations: usize,
}

impl DerivativeCheck {
    /// Entries that exceed their tolerance.
    pub fn failures(&self) -> impl Iterator<Item = &EntryCheck> {
        self.entries.iter().filter(|e| e.fails())
    }
    /// Whether every entry is within its tolerance.
    pub fn passed(&self) -> bool {
        self.failures().next().is_none()
    }
    /// The worst entry of a kind.
    pub fn worst(&self, kind: DerivativeKind) -> Option<&EntryCheck> {
        self.entries.iter().find(|e| e.kind == kind)
    }
}

const STEP: f64 = 1e-6;
const RELATIVE: f64 = 1e-4;
const ABSOLUTE: f64 = 1e-6;

fn step(x: f64) -> f64 {
    STEP * x.abs().max(1.0)
}

fn allowed(analytic: f64, fd: f64, value: f64) -> f64 {
    RELATIVE * analytic.abs().max(fd.abs()) + ABSOLUTE * value.abs().max(1.0)
}

/// Greedy grouping of the variables `free` so that no two in a group share a set of
/// `sets_of[v]` (the rows, or the blocks, a variable enters).
fn groups(free: &[usize], sets_of: &[Vec<usize>], num_sets: usize) -> Vec<Vec<usize>> {
    let mut used: Vec<Vec<usize>> = vec![Vec::new(); num_sets];
    let mut out: Vec<Vec<usize>> = Vec::new();
    for &v in free {
        let mut forbidden: Vec<usize> = sets_of[v]
            .iter()
            .flat_map(|&s| used[s].iter().copied())
            .collect();
        forbidden.sort_unstable();
        forbidden.dedup();
        let color = (0..)
            .find(|c| forbidden.binary_search(c).is_err())
            .unwrap_or(0);
        if color == out.len() {
            out.push(Vec::new());
        }
        out[color].push(v);
        for &s in &sets_of[v] {
            used[s].push(color);
        }
    }
    out
}

/// Evaluates `f` with the variables of `group` stepped up and then down by their δ, into
/// `plus` and `minus`; `x` is restored.
fn step_group(
    x: &mut [f64],
    group: &[usize],
    plus: &mut [f64],
    minus: &mut [f64],
    mut f: impl FnMut(&[f64], &mut [f64]),
) {
    let at: Vec<f64> = group.iter().map(|&v| x[v]).collect();
    for (&v, &a) in group.iter().zip(&at) {
        x[v] = a + step(a);
    }
    f(x, plus);
    for (&v, &a) in group.iter().zip(&at) {
        x[v] = a - step(a);
    }
    f(x, minus);
    for (&v, &a) in group.iter().zip(&at) {
        x[v] = a;
    }
}

/// The entry (row, col) of `kind` with finite difference `fd`, its analytic value from
/// `declared` (0 when not declared) and the tolerance for a function of value `value`.
fn entry(
    kind: DerivativeKind,
    (row, col): (usize, usize),
    declared: &HashMap<(usize, usize), f64>,
    fd: f64,
    value: f64,
) -> EntryCheck {
    let analytic = declared.get(&(row, col)).copied();
    let a = analytic.unwrap_or(0.0);
    EntryCheck {
        kind,
        row,
        col,
        analytic: a,
        finite_difference: fd,
        allowed: allowed(a, fd, value),
        declared: analytic.is_some(),
    }
}

impl<M: MechanicsDerivatives> Transcription<M> {
    /// Every block as (its variables, the rows it adds into).
    fn block_footprints(&self) -> Vec<(&[usize], Vec<usize>)> {
        fn rows<K>(b: &crate::transcription::blocks::Block<K>) -> Vec<usize> {
            b.targets.iter().flatten().copied().collect()
        }
        let mut out: Vec<(&[usize], Vec<usize>)> = Vec::new();
        out.extend(self.vector_blocks.iter().map(|b| (&b.vars[..], rows(b))));
        out.extend(self.gradient_blocks.iter().map(|b| (&b.vars[..], rows(b))));
        out.extend(self.cost_blocks.iter().map(|b| (&b.vars[..], Vec::new())));
        out
    }

    /// Compare the gradient, Jacobian and Lagrangian Hessian (objective factor 1, multipliers
    /// uniform in [−1, 1] from `seed`) at `x` with central finite differences.
    pub fn check_derivatives(&self, x: &[f64], seed: u64) -> DerivativeCheck {
        let nv = self.layout.num_variables();
        let nr = self.layout.num_constraints();
        let free: Vec<usize> = (0..nv)
            .filter(|&v| self.x_lower[v] != self.x_upper[v])
            .collect();
        let is_free: Vec<bool> = (0..nv)
            .map(|v| self.x_lower[v] != self.x_upper[v])
            .collect();
        let mut rng = SeededRng::new(seed);
        let lambda = rng.symmetric_vec(nr, 1.0);
        let mut check = DerivativeCheck {
            fixed_variables: nv - free.len(),
            ..DerivativeCheck::default()
        };
        let footprints = self.block_footprints();

        // Objective gradient, one variable at a time (the objective is one function of all).
        let f0 = self.objective(x);
        let mut grad = vec![0.0; nv];
        self.gradient(x, &mut grad);
        let mut xp = x.to_vec();
        for &v in &free {
            let d = step(x[v]);
            xp[v] = x[v] + d;
            let fp = self.objective(&xp);
            xp[v] = x[v] - d;
            let fm = self.objective(&xp);
            xp[v] = x[v];
            check.evaluations += 2;
            let fd = (fp - fm) / (2.0 * d);
            check.entries.push(EntryCheck {
                kind: DerivativeKind::Gradient,
                row: 0,
                col: v,
                analytic: grad[v],
                finite_difference: fd,
                allowed: allowed(grad[v], fd, f0),
                declared: true,
            });
        }

        // Jacobian: which variables can reach each row, from the blocks.
        let mut row_vars: Vec<Vec<usize>> = vec![Vec::new(); nr];
        for (vars, rows) in &footprints {
            for &r in rows {
                row_vars[r].extend(vars.iter().copied());
            }
        }
        let mut rows_of: Vec<Vec<usize>> = vec![Vec::new(); nv];
        for (r, vars) in row_vars.iter_mut().enumerate() {
            vars.sort_unstable();
            vars.dedup();
            for &v in vars.iter() {
                rows_of[v].push(r);
            }
        }
        let jp = &self.jacobian;
        let mut jv = vec![0.0; jp.nnz()];
        self.jacobian_values(x, &mut jv);
        let mut declared_j: HashMap<(usize, usize), f64> = HashMap::new();
        for (k, value) in jv.iter().enumerate() {
            *declared_j.entry((jp.rows[k], jp.cols[k])).or_insert(0.0) += value;
        }
        let mut g0 = vec![0.0; nr];
        self.constraints(x, &mut g0);
        let (mut gp, mut gm) = (vec![0.0; nr], vec![0.0; nr]);
        for group in groups(&free, &rows_of, nr) {
            step_group(&mut xp, &group, &mut gp, &mut gm, |x, g| {
                self.constraints(x, g)
            });
            check.evaluations += 2;
            for &v in &group {
                let d = step(x[v]);
                for &r in &rows_of[v] {
                    let fd = (gp[r] - gm[r]) / (2.0 * d);
                    let e = entry(DerivativeKind::Jacobian, (r, v), &declared_j, fd, g0[r]);
                    check.entries.push(e);
                }
            }
        }

        // Hessian of L = f + λᵀg by differences of ∇L = ∇f + Jᵀλ: component i can depend on
        // the variables of every block i enters (its reach); a group shares no reach.
        let mut blocks_of: Vec<Vec<usize>> = vec![Vec::new(); nv];
        for (b, (vars, _)) in footprints.iter().enumerate() {
            for &v in vars.iter() {
                blocks_of[v].push(b);
            }
        }
        let reach_of: Vec<Vec<usize>> = blocks_of
            .iter()
            .map(|blocks| {
                let mut reach: Vec<usize> = blocks
                    .iter()
                    .flat_map(|&b| footprints[b].0.iter().copied())
                    .collect();
                reach.sort_unstable();
                reach.dedup();
                reach
            })
            .collect();
        let lagrangian_gradient = |x: &[f64], out: &mut [f64]| {
            self.gradient(x, out);
            let mut values = vec![0.0; jp.nnz()];
            self.jacobian_values(x, &mut values);
            for k in 0..jp.nnz() {
                out[jp.cols[k]] += lambda[jp.rows[k]] * values[k];
            }
        };
        let hp = &self.hessian;
        let mut hv = vec![0.0; hp.nnz()];
        self.hessian_values(x, 1.0, &lambda, &mut hv);
        let mut declared_h: HashMap<(usize, usize), f64> = HashMap::new();
        for (k, value) in hv.iter().enumerate() {
            *declared_h.entry((hp.rows[k], hp.cols[k])).or_insert(0.0) += value;
        }
        let mut l0 = vec![0.0; nv];
        lagrangian_gradient(x, &mut l0);
        let (mut lp, mut lm) = (vec![0.0; nv], vec![0.0; nv]);
        for group in groups(&free, &reach_of, nv) {
            step_group(&mut xp, &group, &mut lp, &mut lm, lagrangian_gradient);
            check.evaluations += 2;
            for &v in &group {
                let d = step(x[v]);
                let rows = reach_of[v]
                    .iter()
                    .copied()
                    .filter(|&i| i >= v && is_free[i]);
                for i in rows {
                    let fd = (lp[i] - lm[i]) / (2.0 * d);
                    let e = entry(DerivativeKind::Hessian, (i, v), &declared_h, fd, l0[i]);
                    check.entries.push(e);
                }
            }
        }
        check
            .entries
            .retain(|e| e.analytic != 0.0 || e.finite_difference != 0.0);
        check
            .entries
            .sort_by(|a, b| b.ratio().total_cmp(&a.ratio()));
        check
    }

    /// A one-line description of an entry, with rows and variables by name.
    pub fn describe_entry(&self, e: &EntryCheck, names: EntryNames) -> String {
        let col = self.layout.variable_name(e.col, names);
        let place = match e.kind {
            DerivativeKind::Gradient => format!("gradient  [{col}]"),
            DerivativeKind::Jacobian => format!(
                "jacobian  [{}] x [{col}]",
                self.layout.row_name(e.row, names)
            ),
            DerivativeKind::Hessian => format!(
                "hessian   [{}] x [{col}]",
                self.layout.variable_name(e.row, names)
            ),
        };
        format!(
            "{place}: analytic {:.6e}, fd {:.6e}, |diff| {:.2e} (allowed {:.1e}){}",
            e.analytic,
            e.finite_difference,
            (e.analytic - e.finite_difference).abs(),
            e.allowed,
            if e.declared {
                ""
            } else {
                "  OUTSIDE DECLARED STRUCTURE"
            }
        )
    }
}

impl<M: MechanicsDerivatives> Transcription<M> {
    /// Objective, largest constraint violation and ‖equality residuals‖₂ at the initial
    /// point (docs/reference-problems.md, "values at the initial guess").
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
        let (violations, g) = self.row_violations(x);
        let max = violations.iter().fold(0.0_f64, |a, &b| a.max(b));
        let sq: f64 = g
            .iter()
            .enumerate()
            .filter(|&(r, _)| self.layout.is_equality(r))
            .map(|(_, gr)| gr * gr)
            .sum();
        (max, sq.sqrt())
    }

    /// Each constraint row's violation at x (how far g_r lies outside [g_lower, g_upper],
    /// 0 inside), and g itself.
    pub fn row_violations(&self, x: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut g = vec![0.0; self.layout.num_constraints()];
        self.constraints(x, &mut g);
        let violations = g
            .iter()
            .enumerate()
            .map(|(r, &gr)| (self.g_lower[r] - gr).max(gr - self.g_upper[r]).max(0.0))
            .collect();
        (violations, g)
    }

    /// Problem cost per term (names as in `Solution::objective_terms`) and the slack penalty
    /// ("slack_penalty"), or in penalty mode the weighted complementarity products
    /// ("complementarity_penalty").
    pub fn objective_terms(&self, x: &[f64]) -> Vec<(String, f64)> {
        let mut terms: Vec<(String, f64)> = Vec::new();
        let mut penalty = 0.0;
        for b in &self.cost_blocks {
            let z = gather(x, &b.vars);
            let value = crate::autodiff::ScalarFunction::eval(&self.scalar_fn(b), &z);
            let name = match &b.kind {
                ScalarKind::Cost(cost) => {
                    crate::problem::costs::term_name(&self.ctx.costs[cost.term])
                }
                ScalarKind::FrameCost(cost) => self.ctx.frames[cost.term].cost_name(),
                ScalarKind::ComplementarityPenalty(_) => {
                    penalty += value;
                    continue;
                }
                _ => continue,
            };
            match terms.iter_mut().find(|(n, _)| n == name) {
                Some(entry) => entry.1 += value,
                None => terms.push((name.to_string(), value)),
            }
        }
        if self.layout.slack_mode == SlackMode::Penalty {
            terms.push((PENALTY_TERM.into(), penalty));
        } else {
            let slack: f64 = x[self.layout.slacks()].iter().sum();
            terms.push(("slack_penalty".into(), self.ctx.slack_weight * slack));
        }
        terms
    }

    /// Per interval and contact, the complementarity products at x ([`interval_products`]:
    /// η_jᵀβ, c_j·φ(q_{j+1}), ψ_j(μc_j − eᵀβ_j), summed over the partners of j's
    /// contact-mode block, factors clipped at 0).
    pub fn complementarity_products(&self, x: &[f64]) -> Vec<Vec<[f64; 3]>> {
        let l = &self.layout;
        let phi: Vec<Vec<f64>> = (0..l.knots)
            .map(|k| {
                let q = &x[l.q(k)];
                (0..l.nc)
                    .map(|i| crate::contact::distance(&self.mech, &self.ctx.contact, i, q))
                    .collect()
            })
            .collect();
        interval_products(l, &self.ctx, x, &phi)
    }

    /// The largest slack at x: of the slack variables, or in penalty mode the largest
    /// interval's [`interval_slack`] of its products (the slack the elastic form would hold).
    pub fn max_slack(&self, x: &[f64]) -> f64 {
        if self.layout.slack_mode == SlackMode::Penalty {
            return self
                .complementarity_products(x)
                .iter()
                .map(|p| interval_slack(p))
                .fold(0.0_f64, f64::max);
        }
        x[self.layout.slacks()]
            .iter()
            .fold(0.0_f64, |a, &b| a.max(b))
    }

    /// Seconds spent on one Jacobian plus Lagrangian-Hessian evaluation per block kind
    /// (serial, at x with constraint multipliers `lambda`), named like the block kinds
    /// ("Segment", "ContactWork", "TangentialRate", …, "Cost" for the cost Hessians); for
    /// benchmarks.
    pub fn derivative_time_by_kind(&self, x: &[f64], lambda: &[f64]) -> Vec<(String, f64)> {
        let mut times: Vec<(String, f64)> = Vec::new();
        let mut add = |name: String, secs: f64| match times.iter_mut().find(|(n, _)| *n == name) {
            Some(entry) => entry.1 += secs,
            None => times.push((name, secs)),
        };
        let weights = |targets: &[Vec<usize>]| -> Vec<f64> {
            targets
                .iter()
                .map(|rows| rows.iter().map(|&r| lambda[r]).sum())
                .collect()
        };
        for b in &self.vector_blocks {
            let z = gather(x, &b.vars);
            let start = std::time::Instant::now();
            std::hint::black_box(self.vector_block_jacobian(b, &z, None));
            if b.nonlinear > 0 {
                std::hint::black_box(self.vector_block_hessian(b, &z, &weights(&b.targets), None));
            }
            add(b.kind.name().into(), start.elapsed().as_secs_f64());
        }
        for b in self.cost_blocks.iter().filter(|b| b.nonlinear > 0) {
            let z = gather(x, &b.vars);
            let start = std::time::Instant::now();
            std::hint::black_box(self.cost_block_hessian(b, &z));
            add("Cost".into(), start.elapsed().as_secs_f64());
        }
        for b in &self.gradient_blocks {
            let z = gather(x, &b.vars);
            let start = std::time::Instant::now();
            std::hint::black_box(self.gradient_block_hessian(b, &z, None));
            std::hint::black_box(self.gradient_block_third(b, &z, &weights(&b.targets), None));
            add(b.kind.name().into(), start.elapsed().as_secs_f64());
        }
        times
    }
}
