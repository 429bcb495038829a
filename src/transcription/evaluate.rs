//! Values and exact derivatives of the NLP: objective, gradient, constraints, Jacobian and
//! Lagrangian Hessian, assembled from per-block dense derivatives (computed in parallel,
//! scattered serially in block order). Each block kind's derivatives come from the fastest path
//! it has (the mechanics' segment derivatives, the contact chain rule) or generic forward AD.

use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::sync::OnceLock;

use nalgebra::DMatrix;
use rayon::prelude::*;

use super::blocks::{
    Block, ScalarBlockFn, ScalarKind, VectorBlockFn, VectorKind, loop_closure_hessian,
    loop_closure_jacobian, loop_work_gradient, loop_work_hessian, loop_work_third,
};
use super::structure::NO_SLOT;
use super::{InitialGuessReport, Transcription};
use crate::autodiff::{
    Restricted, SymmetricGroups, ThirdOrder, gradient, gradient_hessian, gradient_hessian_third,
    grouped_hessian, jacobian, weighted_hessian,
};
use crate::contact::{
    ContactGeometry, complementarity_hessian, complementarity_jacobian, contact_work_gradient,
    contact_work_hessian, contact_work_hessian_in, contact_work_third, contact_work_third_in,
    distance_hessian, distance_hessian_in, distance_jacobian, distance_jacobian_in,
    tangential_rate_hessian, tangential_rate_hessian_in, tangential_rate_jacobian,
    tangential_rate_jacobian_in,
};
use crate::discrete::MechanicsDerivatives;

/// How the contact blocks (tangential rate, contact work, signed distance, c·φ,
/// complementarity) and the loop-closure blocks (residual rows, loop work) are differentiated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactDerivatives {
    /// By the chain rule through the contact point's jet and the mechanics' loop jets, and
    /// the bilinear complementarity rows in closed form (fast; the default for evaluation).
    ChainRule,
    /// By generic forward AD over the whole block: structural zeros are exact, where the
    /// chain rule can leave round-off (1e-17) on them (for comparison).
    GenericAd,
}

impl<M: MechanicsDerivatives> Transcription<M> {
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

    /// Problem cost per term (names as in `Solution::objective_terms`) and the slack penalty.
    pub fn objective_terms(&self, x: &[f64]) -> Vec<(String, f64)> {
        let mut terms: Vec<(String, f64)> = Vec::new();
        for b in &self.cost_blocks {
            let ScalarKind::Cost { term } = b.kind else {
                continue;
            };
            let name = crate::problem::costs::term_name(&self.ctx.costs[term]);
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
        let locals = self.map_blocks_serial(&self.cost_blocks, |b| {
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
        let vector = self.map_blocks_serial(&self.vector_blocks, |b| {
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
        let gradient = self.map_blocks_serial(&self.gradient_blocks, |b| {
            self.gradient_block_gradient(b, &gather(x, &b.vars), self.contact_derivatives)
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
        let shared = self.shared_geometries(Callback::Jacobian);
        let build = |key| self.contact_geometry(x, key);
        let vector = self.map_blocks(&self.vector_blocks, |b| {
            let z = gather(x, &b.vars);
            match (&b.kind, shared.get(&b.kind, &b.vars, self.ctx.n, &build)) {
                (&VectorKind::TangentialRate { contact }, Some(g))
                    if !self.mech.contact_rolls(contact) =>
                {
                    tangential_rate_jacobian_in(g, &z)
                }
                (VectorKind::Distance { .. }, Some(g)) => distance_jacobian_in(g, &z, false),
                (VectorKind::ContactGap { .. }, Some(g)) => distance_jacobian_in(g, &z, true),
                _ => self.vector_block_jacobian(b, &z, self.contact_derivatives),
            }
        });
        for (b, local) in self.vector_blocks.iter().zip(vector) {
            scatter_rows(b, &local, values);
        }
        let gradient = self.map_blocks(&self.gradient_blocks, |b| {
            let z = gather(x, &b.vars);
            match shared.get_scalar(&b.kind, &b.vars, self.ctx.n, &build) {
                Some(g) => contact_work_hessian_in(g, &z),
                None => self.gradient_block_hessian(b, &z, self.contact_derivatives),
            }
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
        let shared = self.shared_geometries(Callback::Hessian);
        let build = |key| self.contact_geometry(x, key);
        let vector = self.map_blocks(&self.vector_blocks, |b| {
            if b.nonlinear == 0 {
                return DMatrix::zeros(0, 0);
            }
            let z = gather(x, &b.vars);
            let w = weights(&b.targets);
            match (&b.kind, shared.get(&b.kind, &b.vars, self.ctx.n, &build)) {
                (&VectorKind::TangentialRate { contact }, Some(g))
                    if !self.mech.contact_rolls(contact) =>
                {
                    tangential_rate_hessian_in(g, &z, &w)
                }
                (VectorKind::Distance { .. }, Some(g)) => distance_hessian_in(g, &z, w[0], false),
                (VectorKind::ContactGap { .. }, Some(g)) => distance_hessian_in(g, &z, w[0], true),
                _ => self.vector_block_hessian(b, &z, &w, self.contact_derivatives),
            }
        });
        for (b, local) in self.vector_blocks.iter().zip(vector) {
            scatter_lower(b, &local, values);
        }
        let gradient = self.map_blocks(&self.gradient_blocks, |b| {
            let dir = weights(&b.targets);
            let z = gather(x, &b.vars);
            if let Some(g) = shared.get_scalar(&b.kind, &b.vars, self.ctx.n, &build)
                && let Some((_, contracted)) = contact_work_third_in(g, &z, &dir)
            {
                return contracted;
            }
            self.gradient_block_third(b, &z, &dir, self.contact_derivatives)
                .contracted
        });
        for (b, local) in self.gradient_blocks.iter().zip(gradient) {
            scatter_lower(b, &local, values);
        }
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
            std::hint::black_box(self.vector_block_jacobian(b, &z, self.contact_derivatives));
            if b.nonlinear > 0 {
                std::hint::black_box(self.vector_block_hessian(
                    b,
                    &z,
                    &weights(&b.targets),
                    self.contact_derivatives,
                ));
            }
            add(
                kind_name(format!("{:?}", b.kind)),
                start.elapsed().as_secs_f64(),
            );
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
            std::hint::black_box(self.gradient_block_hessian(b, &z, self.contact_derivatives));
            std::hint::black_box(self.gradient_block_third(
                b,
                &z,
                &weights(&b.targets),
                self.contact_derivatives,
            ));
            add(
                kind_name(format!("{:?}", b.kind)),
                start.elapsed().as_secs_f64(),
            );
        }
        times
    }

    /// The contact geometries of one Jacobian or Hessian call (chain-rule derivatives only),
    /// one per (contact, knot configuration), to the highest order the call's blocks there
    /// need: the tangential rate, the distance, the gap and the contact work at one knot read
    /// one point jet instead of computing it four times.
    fn shared_geometries(&self, callback: Callback) -> SharedGeometries<'_> {
        let mut shared = SharedGeometries::default();
        if self.contact_derivatives != ContactDerivatives::ChainRule {
            return shared;
        }
        let hessian = callback == Callback::Hessian;
        let mut keys: Vec<GeometryKey> = Vec::new();
        for b in &self.vector_blocks {
            if hessian && b.nonlinear == 0 {
                continue;
            }
            if let Some((contact, q, order)) =
                geometry_need(&b.kind, &b.vars, self.ctx.n, callback, |c| {
                    self.mech.contact_rolls(c)
                })
            {
                shared.add(&mut keys, contact, q, order);
            }
        }
        for b in &self.gradient_blocks {
            if let ScalarKind::ContactWork { contact } = b.kind {
                let order = if hessian { 3 } else { 2 };
                shared.add(&mut keys, contact, &b.vars[..self.ctx.n], order);
            }
        }
        shared.keys = keys;
        shared.cells = shared.keys.iter().map(|_| OnceLock::new()).collect();
        shared
    }

    /// The contact geometry at (contact, configuration variables, order) at x.
    fn contact_geometry(
        &self,
        x: &[f64],
        (contact, q, order): (usize, &[usize], usize),
    ) -> ContactGeometry<'_> {
        ContactGeometry::new(&self.mech, &self.ctx.contact, contact, &gather(x, q), order)
    }

    /// `f` over the blocks on one thread: f, ∇f and g, which Ipopt asks at every trial
    /// point, are cheap enough that handing them to rayon's pool costs more than it saves
    /// (HAMR's g: 5.7 ms serial against 10.3 ms on the pool, loaded 2-core machine).
    fn map_blocks_serial<K, R>(&self, blocks: &[Block<K>], f: impl Fn(&Block<K>) -> R) -> Vec<R> {
        blocks.iter().map(f).collect()
    }

    /// `f` over the blocks, on rayon's pool when the transcription is parallel (derivatives
    /// of large problems, see `Transcription::new`), in block order either way.
    pub(super) fn map_blocks<K: Sync, R: Send>(
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

    pub(super) fn vector_fn<'a>(&'a self, b: &'a Block<VectorKind>) -> VectorBlockFn<'a, M> {
        VectorBlockFn {
            mech: &self.mech,
            ctx: &self.ctx,
            kind: &b.kind,
            dim_in: b.vars.len(),
            dim_out: b.targets.len(),
        }
    }

    pub(super) fn scalar_fn<'a>(&'a self, b: &'a Block<ScalarKind>) -> ScalarBlockFn<'a, M> {
        ScalarBlockFn {
            mech: &self.mech,
            ctx: &self.ctx,
            kind: &b.kind,
            dim: b.vars.len(),
        }
    }

    /// Gradient of a gradient block at z (the DEL-row values).
    pub(super) fn gradient_block_gradient(
        &self,
        b: &Block<ScalarKind>,
        z: &[f64],
        contacts: ContactDerivatives,
    ) -> Vec<f64> {
        if b.kind == ScalarKind::Segment {
            return self.mech.segment_gradient(z);
        }
        if let ScalarKind::ContactWork { contact } = b.kind
            && contacts == ContactDerivatives::ChainRule
        {
            return contact_work_gradient(&self.mech, &self.ctx.contact, contact, z);
        }
        if b.kind == ScalarKind::LoopWork && contacts == ContactDerivatives::ChainRule {
            return loop_work_gradient(&self.mech, z);
        }
        gradient(&self.scalar_fn(b), z).1
    }

    /// Hessian of a gradient block at z (the model's adjoint path for Ld when it has one).
    pub(super) fn gradient_block_hessian(
        &self,
        b: &Block<ScalarKind>,
        z: &[f64],
        contacts: ContactDerivatives,
    ) -> DMatrix<f64> {
        if b.kind == ScalarKind::Segment {
            if let Some(groups) = &b.second_derivative_groups {
                return self.mech.segment_gradient_hessian_grouped(z, groups).1;
            }
            return self.mech.segment_gradient_hessian(z).1;
        }
        if let ScalarKind::ContactWork { contact } = b.kind
            && contacts == ContactDerivatives::ChainRule
        {
            return contact_work_hessian(&self.mech, &self.ctx.contact, contact, z);
        }
        if b.kind == ScalarKind::LoopWork && contacts == ContactDerivatives::ChainRule {
            return loop_work_hessian(&self.mech, z);
        }
        gradient_hessian(&self.scalar_fn(b), z).2
    }

    /// Hessian and contracted third derivative of a gradient block at z.
    pub(super) fn gradient_block_third(
        &self,
        b: &Block<ScalarKind>,
        z: &[f64],
        dir: &[f64],
        contacts: ContactDerivatives,
    ) -> ThirdOrder {
        if b.kind == ScalarKind::Segment {
            if let Some(groups) = self.second_derivative_groups(b) {
                return self.mech.segment_third_order_grouped(z, dir, groups);
            }
            let columns = self.skip_fixed.then_some(b.free_input_mask.as_slice());
            return self.mech.segment_third_order(z, dir, columns);
        }
        if let ScalarKind::ContactWork { contact } = b.kind
            && contacts == ContactDerivatives::ChainRule
            && let Some((hessian, contracted)) =
                contact_work_third(&self.mech, &self.ctx.contact, contact, z, dir)
        {
            return ThirdOrder {
                value: 0.0,
                gradient: Vec::new(),
                hessian,
                contracted,
            };
        }
        if b.kind == ScalarKind::LoopWork && contacts == ContactDerivatives::ChainRule {
            return loop_work_third(&self.mech, z, dir);
        }
        gradient_hessian_third(&self.scalar_fn(b), z, dir)
    }

    /// Jacobian of a vector block at z (chain-rule assembly for the tangential rates).
    pub(super) fn vector_block_jacobian(
        &self,
        b: &Block<VectorKind>,
        z: &[f64],
        contacts: ContactDerivatives,
    ) -> DMatrix<f64> {
        if contacts == ContactDerivatives::ChainRule {
            match &b.kind {
                &VectorKind::TangentialRate { contact } => {
                    return tangential_rate_jacobian(&self.mech, &self.ctx.contact, contact, z);
                }
                VectorKind::Complementarity { contacts, slacks } => {
                    return complementarity_jacobian(&self.ctx.contact, contacts, *slacks, z);
                }
                &VectorKind::Distance { contact } => {
                    return distance_jacobian(&self.mech, &self.ctx.contact, contact, z, false);
                }
                &VectorKind::ContactGap { contact } => {
                    return distance_jacobian(&self.mech, &self.ctx.contact, contact, z, true);
                }
                VectorKind::LoopClosure => return loop_closure_jacobian(&self.mech, z),
                _ => {}
            }
        }
        jacobian(&self.vector_fn(b), z).1
    }

    /// Σ_r w_r ∇²f_r of a vector block at z (chain-rule assembly for the tangential rates).
    pub(super) fn vector_block_hessian(
        &self,
        b: &Block<VectorKind>,
        z: &[f64],
        w: &[f64],
        contacts: ContactDerivatives,
    ) -> DMatrix<f64> {
        if contacts == ContactDerivatives::ChainRule {
            match &b.kind {
                // A rolling contact's rate has no chain rule: generic AD below, over the
                // block's Hessian inputs only.
                &VectorKind::TangentialRate { contact } if !self.mech.contact_rolls(contact) => {
                    return tangential_rate_hessian(&self.mech, &self.ctx.contact, contact, z, w);
                }
                VectorKind::Complementarity { contacts, .. } => {
                    return complementarity_hessian(&self.ctx.contact, contacts, z.len(), w);
                }
                &VectorKind::Distance { contact } => {
                    return distance_hessian(
                        &self.mech,
                        &self.ctx.contact,
                        contact,
                        z,
                        w[0],
                        false,
                    );
                }
                &VectorKind::ContactGap { contact } => {
                    return distance_hessian(&self.mech, &self.ctx.contact, contact, z, w[0], true);
                }
                VectorKind::LoopClosure => return loop_closure_hessian(&self.mech, z, w),
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
    pub(super) fn hessian_inputs<'b, K>(&self, b: &'b Block<K>) -> &'b [usize] {
        if self.skip_fixed {
            &b.hessian_free_inputs
        } else {
            &b.hessian_inputs
        }
    }

    /// The column groups of `b`'s second derivative for the inputs its Hessian runs over
    /// (the free ones when [`Transcription::set_skip_fixed_variables`] is on), if any.
    fn second_derivative_groups<'b, K>(&self, b: &'b Block<K>) -> Option<&'b SymmetricGroups> {
        if self.skip_fixed {
            b.free_second_derivative_groups.as_deref()
        } else {
            b.second_derivative_groups.as_deref()
        }
    }

    /// Hessian of a cost block at z, over the inputs in the Hessian pattern only (columns
    /// seeded by groups where its dependency pattern allows).
    pub(super) fn cost_block_hessian(&self, b: &Block<ScalarKind>, z: &[f64]) -> DMatrix<f64> {
        let f = self.scalar_fn(b);
        let inputs = self.hessian_inputs(b);
        if let Some(groups) = self.second_derivative_groups(b) {
            let r = Restricted {
                f: &f,
                at: z,
                free: inputs,
            };
            return expand_hessian(&grouped_hessian(&r, &r.point(), groups), inputs, z.len());
        }
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
}

/// x[vars] as a dense local vector.
pub(super) fn gather(x: &[f64], vars: &[usize]) -> Vec<f64> {
    vars.iter().map(|&v| x[v]).collect()
}

/// Add a block's local rows (outputs or gradient components × inputs) into the Jacobian.
pub(super) fn scatter_rows<K>(b: &Block<K>, local: &DMatrix<f64>, values: &mut [f64]) {
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
pub(super) fn expand_hessian(sub: &DMatrix<f64>, free: &[usize], dim: usize) -> DMatrix<f64> {
    let mut full = DMatrix::zeros(dim, dim);
    for (a, &i) in free.iter().enumerate() {
        for (c, &j) in free.iter().enumerate() {
            full[(i, j)] = sub[(a, c)];
        }
    }
    full
}

/// Add a block's local Hessian (lower pairs of its nonlinear inputs) into the Hessian.
pub(super) fn scatter_lower<K>(b: &Block<K>, local: &DMatrix<f64>, values: &mut [f64]) {
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

/// Which derivative callback a shared geometry is for (the orders its blocks need differ).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Callback {
    Jacobian,
    Hessian,
}

/// The (contact, configuration variables, order) a vector block's chain-rule derivatives read
/// in `callback`: the tangential rate at qb (a rolling contact's rate has no chain rule), the
/// distance and the gap at q.
fn geometry_need<'v>(
    kind: &VectorKind,
    vars: &'v [usize],
    n: usize,
    callback: Callback,
    rolls: impl Fn(usize) -> bool,
) -> Option<(usize, &'v [usize], usize)> {
    let hessian = callback == Callback::Hessian;
    let (contact, q) = geometry_site(kind, vars, n)?;
    match *kind {
        VectorKind::TangentialRate { .. } if rolls(contact) => None,
        VectorKind::TangentialRate { .. } => Some((contact, q, if hessian { 3 } else { 2 })),
        _ => Some((contact, q, if hessian { 2 } else { 1 })),
    }
}

/// The contact and the configuration variables (qb for the tangential rate, q for the
/// distance and the gap) at which a vector block of `kind` over `vars` reads a contact's
/// geometry; `None` for other blocks.
fn geometry_site<'v>(
    kind: &VectorKind,
    vars: &'v [usize],
    n: usize,
) -> Option<(usize, &'v [usize])> {
    match *kind {
        VectorKind::TangentialRate { contact } => Some((contact, &vars[n..2 * n])),
        VectorKind::Distance { contact } | VectorKind::ContactGap { contact } => {
            Some((contact, &vars[..n]))
        }
        _ => None,
    }
}

/// (contact, configuration variables, order) of a shared contact geometry.
type GeometryKey<'a> = (usize, &'a [usize], usize);

/// Contact geometries shared by the blocks of one derivative call, keyed by contact and the
/// variables of the configuration they are taken at; each is computed by the first block
/// that reads it (on whichever thread), so sharing adds no pass over the pool.
#[derive(Default)]
struct SharedGeometries<'a> {
    /// (contact, first configuration variable) → position in `keys`.
    index: HashMap<(usize, usize), usize>,
    keys: Vec<GeometryKey<'a>>,
    cells: Vec<OnceLock<ContactGeometry<'a>>>,
}

impl<'a> SharedGeometries<'a> {
    /// Registers a need; the order kept is the highest asked for. (A configuration that
    /// shares its first variable with another but not the rest is not shared: its blocks
    /// compute their own geometry.)
    fn add(
        &mut self,
        keys: &mut Vec<GeometryKey<'a>>,
        contact: usize,
        q: &'a [usize],
        order: usize,
    ) {
        match self.index.entry((contact, q[0])) {
            Entry::Occupied(e) => {
                let key = &mut keys[*e.get()];
                if key.1 == q {
                    key.2 = key.2.max(order);
                }
            }
            Entry::Vacant(e) => {
                e.insert(keys.len());
                keys.push((contact, q, order));
            }
        }
    }

    /// The shared geometry of `contact` at the configuration variables `q`, built by `build`
    /// on first use; `None` if not shared.
    fn lookup(
        &self,
        contact: usize,
        q: &[usize],
        build: &(dyn Fn(GeometryKey<'a>) -> ContactGeometry<'a> + Sync),
    ) -> Option<&ContactGeometry<'a>> {
        let &i = self.index.get(&(contact, *q.first()?))?;
        let key = self.keys[i];
        (key.1 == q).then(|| self.cells[i].get_or_init(|| build(key)))
    }

    /// The geometry a vector block of `kind` over `vars` reads, if shared.
    fn get(
        &self,
        kind: &VectorKind,
        vars: &[usize],
        n: usize,
        build: &(dyn Fn(GeometryKey<'a>) -> ContactGeometry<'a> + Sync),
    ) -> Option<&ContactGeometry<'a>> {
        let (contact, q) = geometry_site(kind, vars, n)?;
        self.lookup(contact, q, build)
    }

    /// The geometry a contact-work block over `vars` reads, if shared.
    fn get_scalar(
        &self,
        kind: &ScalarKind,
        vars: &[usize],
        n: usize,
        build: &(dyn Fn(GeometryKey<'a>) -> ContactGeometry<'a> + Sync),
    ) -> Option<&ContactGeometry<'a>> {
        let ScalarKind::ContactWork { contact } = *kind else {
            return None;
        };
        self.lookup(contact, &vars[..n], build)
    }
}
