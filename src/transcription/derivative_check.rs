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

use super::Transcription;
use super::layout::EntryNames;
use crate::discrete::MechanicsDerivatives;
use crate::random::SeededRng;

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
        fn rows<K>(b: &super::blocks::Block<K>) -> Vec<usize> {
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
