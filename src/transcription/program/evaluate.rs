//! Values and exact derivatives of the NLP: objective, gradient, constraints, Jacobian and
//! Lagrangian Hessian, assembled from per-block dense derivatives (computed in parallel,
//! scattered serially in block order). Each block kind's derivatives come from the fastest path
//! it has (the mechanics' segment derivatives, the contact chain rule) or generic forward AD.

use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::sync::{Mutex, OnceLock};

use nalgebra::DMatrix;
use rayon::prelude::*;

use super::Transcription;
use crate::autodiff::{
    Restricted, ThirdOrder, gradient, gradient_hessian, gradient_hessian_third, grouped_hessian,
    jacobian, weighted_hessian,
};
use crate::contact::ContactGeometry;
use crate::discrete::MechanicsDerivatives;
use crate::model::PointJet;
use crate::transcription::blocks::{
    Block, Eval, GeometryUse, ScalarBlockFn, ScalarKind, VectorBlockFn, VectorKind,
};
use crate::transcription::structure::{NO_SLOT, gather};

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
    /// Objective f(x) = problem cost + α Σ s.
    pub fn objective(&self, x: &[f64]) -> f64 {
        let cost: f64 = self
            .cost_blocks
            .iter()
            .map(|b| crate::autodiff::ScalarFunction::eval(&self.scalar_fn(b), &gather(x, &b.vars)))
            .sum();
        let slack: f64 = x[self.layout.slacks()].iter().sum();
        cost + self.ctx.slack_weight * slack
    }

    /// Gradient of the objective (length = variables).
    pub fn gradient(&self, x: &[f64], grad: &mut [f64]) {
        grad.fill(0.0);
        // Cost terms by generic AD; penalty-mode products by their closed forms.
        let locals = self.map_blocks_serial(&self.cost_blocks, |b| {
            self.gradient_block_gradient(b, &gather(x, &b.vars))
        });
        for (b, g) in self.cost_blocks.iter().zip(locals) {
            for (&v, gi) in b.vars.iter().zip(g) {
                grad[v] += gi;
            }
        }
        for i in self.layout.slacks() {
            grad[i] += self.ctx.slack_weight;
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
        let shared = self.shared_geometries(Callback::Jacobian);
        let build = |key, jet| self.contact_geometry(x, key, jet);
        let vector = self.map_blocks(&self.vector_blocks, |scratch, b| {
            let z = scratch.point(x, &b.vars);
            let geometry = shared.get(b.kind.geometry(&self.mech, self.ctx.n), &b.vars, &build);
            self.vector_block_jacobian(b, z, geometry)
        });
        for (b, local) in self.vector_blocks.iter().zip(vector) {
            scatter_rows(b, &local, values);
        }
        let gradient = self.map_blocks(&self.gradient_blocks, |scratch, b| {
            let z = scratch.point(x, &b.vars);
            let geometry = shared.get(b.kind.geometry(&self.mech, self.ctx.n), &b.vars, &build);
            self.gradient_block_hessian(b, z, geometry)
        });
        for (b, local) in self.gradient_blocks.iter().zip(gradient) {
            scatter_rows(b, &local, values);
        }
        shared.recycle();
    }

    /// Values of ∇²(σ f + Σ λ_r g_r) in the order of `hessian_pattern`.
    pub fn hessian_values(&self, x: &[f64], obj_factor: f64, lambda: &[f64], values: &mut [f64]) {
        values.fill(0.0);
        let costs = self.map_blocks(&self.cost_blocks, |scratch, b| {
            if b.nonlinear == 0 {
                return DMatrix::zeros(0, 0);
            }
            self.cost_block_hessian(b, scratch.point(x, &b.vars)) * obj_factor
        });
        for (b, local) in self.cost_blocks.iter().zip(costs) {
            scatter_lower(b, &local, values);
        }
        let shared = self.shared_geometries(Callback::Hessian);
        let build = |key, jet| self.contact_geometry(x, key, jet);
        let vector = self.map_blocks(&self.vector_blocks, |scratch, b| {
            if b.nonlinear == 0 {
                return DMatrix::zeros(0, 0);
            }
            let (z, w) = scratch.point_and_weights(x, &b.vars, lambda, &b.targets);
            let geometry = shared.get(b.kind.geometry(&self.mech, self.ctx.n), &b.vars, &build);
            self.vector_block_hessian(b, z, w, geometry)
        });
        for (b, local) in self.vector_blocks.iter().zip(vector) {
            scatter_lower(b, &local, values);
        }
        let gradient = self.map_blocks(&self.gradient_blocks, |scratch, b| {
            let (z, dir) = scratch.point_and_weights(x, &b.vars, lambda, &b.targets);
            let geometry = shared.get(b.kind.geometry(&self.mech, self.ctx.n), &b.vars, &build);
            self.gradient_block_third(b, z, dir, geometry)
        });
        for (b, local) in self.gradient_blocks.iter().zip(gradient) {
            scatter_lower(b, &local, values);
        }
        shared.recycle();
    }

    /// The contact geometries of one Jacobian or Hessian call (chain-rule derivatives only),
    /// one per (contact, knot configuration), to the highest order the call's blocks there
    /// need: the tangential rate, the distance, the gap and the contact work at one knot read
    /// one point jet instead of computing it four times.
    fn shared_geometries(&self, callback: Callback) -> SharedGeometries<'_> {
        let hessian = callback == Callback::Hessian;
        let mut shared = SharedGeometries {
            jets: Some(if hessian {
                &self.jets.hessian
            } else {
                &self.jets.jacobian
            }),
            ..SharedGeometries::default()
        };
        if self.contact_derivatives != ContactDerivatives::ChainRule {
            return shared;
        }
        let extra = usize::from(hessian);
        let mut keys: Vec<GeometryKey> = Vec::new();
        for b in &self.vector_blocks {
            if hessian && b.nonlinear == 0 {
                continue;
            }
            if let Some(u) = b.kind.geometry(&self.mech, self.ctx.n) {
                shared.add(&mut keys, u.contact, &b.vars[u.q], u.order + extra);
            }
        }
        for b in &self.gradient_blocks {
            if let Some(u) = b.kind.geometry(&self.mech, self.ctx.n) {
                shared.add(&mut keys, u.contact, &b.vars[u.q], u.order + extra);
            }
        }
        shared.keys = keys;
        shared.cells = shared.keys.iter().map(|_| OnceLock::new()).collect();
        shared
    }

    /// The contact geometry at (contact, configuration variables, order) at x, its point jet
    /// in `jet`'s storage.
    fn contact_geometry(
        &self,
        x: &[f64],
        (contact, q, order): (usize, &[usize], usize),
        jet: PointJet,
    ) -> ContactGeometry<'_> {
        ContactGeometry::with_jet(
            &self.mech,
            &self.ctx.contact,
            contact,
            &gather(x, q),
            order,
            jet,
        )
    }

    /// `f` over the blocks on one thread: f, ∇f and g, which Ipopt asks at every trial
    /// point, are cheap enough that handing them to rayon's pool costs more than it saves
    /// (HAMR's g: 5.7 ms serial against 10.3 ms on the pool, loaded 2-core machine).
    fn map_blocks_serial<K, R>(&self, blocks: &[Block<K>], f: impl Fn(&Block<K>) -> R) -> Vec<R> {
        blocks.iter().map(f).collect()
    }

    /// `f` over the blocks, on rayon's pool when the transcription is parallel (derivatives
    /// of large problems, see `Transcription::new`), in block order either way; each task
    /// (the serial loop, or one per batch of the pool) lends `f` one [`BlockScratch`].
    pub(super) fn map_blocks<K: Sync, R: Send>(
        &self,
        blocks: &[Block<K>],
        f: impl Fn(&mut BlockScratch, &Block<K>) -> R + Sync + Send,
    ) -> Vec<R> {
        if self.parallel {
            // Batches of blocks: one task per block costs more in wake-ups than the
            // cheaper blocks take to evaluate.
            blocks
                .par_iter()
                .with_min_len(32)
                .map_init(BlockScratch::default, |scratch, b| f(scratch, b))
                .collect()
        } else {
            let mut scratch = BlockScratch::default();
            blocks.iter().map(|b| f(&mut scratch, b)).collect()
        }
    }

    fn vector_fn<'a>(&'a self, b: &'a Block<VectorKind>) -> VectorBlockFn<'a, M> {
        VectorBlockFn::new(&self.mech, &self.ctx, b)
    }

    pub(super) fn scalar_fn<'a>(&'a self, b: &'a Block<ScalarKind>) -> ScalarBlockFn<'a, M> {
        ScalarBlockFn::new(&self.mech, &self.ctx, b)
    }

    /// Whether `b`'s closed-form derivatives are used (`set_contact_chain_rule(false)` asks
    /// for generic AD except where the kind says otherwise).
    fn closed_form(&self, b: &Block<ScalarKind>) -> bool {
        self.contact_derivatives == ContactDerivatives::ChainRule || b.kind.always_closed_form()
    }

    fn eval_at<'a>(&'a self, b: &'a Block<ScalarKind>) -> Eval<'a, M> {
        Eval {
            mech: &self.mech,
            ctx: &self.ctx,
            block: b,
            skip_fixed: self.skip_fixed,
        }
    }

    /// Gradient of a gradient block at z (the DEL-row values).
    pub(super) fn gradient_block_gradient(&self, b: &Block<ScalarKind>, z: &[f64]) -> Vec<f64> {
        if self.closed_form(b)
            && let Some(g) = b.kind.gradient(&self.eval_at(b), z)
        {
            return g;
        }
        gradient(&self.scalar_fn(b), z).1
    }

    /// Hessian of a gradient block at z (the Jacobian of its rows), from a shared contact
    /// geometry when given.
    pub(super) fn gradient_block_hessian(
        &self,
        b: &Block<ScalarKind>,
        z: &[f64],
        geometry: Option<&ContactGeometry>,
    ) -> DMatrix<f64> {
        if let Some(h) = geometry.and_then(|g| b.kind.hessian_in(g, z)) {
            return h;
        }
        if self.closed_form(b)
            && let Some(h) = b.kind.hessian(&self.eval_at(b), z)
        {
            return h;
        }
        gradient_hessian(&self.scalar_fn(b), z).2
    }

    /// Third derivative of a gradient block at z contracted with `dir` (the Hessian of its
    /// rows weighted by `dir`), from a shared contact geometry when given.
    pub(super) fn gradient_block_third(
        &self,
        b: &Block<ScalarKind>,
        z: &[f64],
        dir: &[f64],
        geometry: Option<&ContactGeometry>,
    ) -> DMatrix<f64> {
        if let Some(w) = geometry.and_then(|g| b.kind.contracted_third_in(g, z, dir)) {
            return w;
        }
        if self.closed_form(b)
            && let Some(third) = b.kind.third(&self.eval_at(b), z, dir)
        {
            return third.contracted;
        }
        let third: ThirdOrder = gradient_hessian_third(&self.scalar_fn(b), z, dir);
        third.contracted
    }

    /// Jacobian of a vector block at z, from a shared contact geometry when given.
    pub(super) fn vector_block_jacobian(
        &self,
        b: &Block<VectorKind>,
        z: &[f64],
        geometry: Option<&ContactGeometry>,
    ) -> DMatrix<f64> {
        if let Some(j) = geometry.and_then(|g| b.kind.jacobian_in(g, z)) {
            return j;
        }
        if self.contact_derivatives == ContactDerivatives::ChainRule
            && let Some(j) = b.kind.jacobian(&self.mech, &self.ctx, z)
        {
            return j;
        }
        jacobian(&self.vector_fn(b), z).1
    }

    /// Σ_r w_r ∇²f_r of a vector block at z, from a shared contact geometry when given.
    pub(super) fn vector_block_hessian(
        &self,
        b: &Block<VectorKind>,
        z: &[f64],
        w: &[f64],
        geometry: Option<&ContactGeometry>,
    ) -> DMatrix<f64> {
        if let Some(h) = geometry.and_then(|g| b.kind.hessian_in(g, z, w)) {
            return h;
        }
        if self.contact_derivatives == ContactDerivatives::ChainRule
            && let Some(h) = b.kind.hessian(&self.mech, &self.ctx, z, w)
        {
            return h;
        }
        let f = self.vector_fn(b);
        let inputs = b.hessian_inputs_for(self.skip_fixed);
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

    /// Hessian of a cost block at z, over the inputs in the Hessian pattern only: in closed
    /// form where the term has one, else by generic AD (columns seeded by groups where its
    /// dependency pattern allows).
    pub(super) fn cost_block_hessian(&self, b: &Block<ScalarKind>, z: &[f64]) -> DMatrix<f64> {
        let inputs = b.hessian_inputs_for(self.skip_fixed);
        if self.closed_form(b)
            && let Some(mut h) = b.kind.hessian(&self.eval_at(b), z)
        {
            if inputs.len() < z.len() {
                keep_only(&mut h, inputs);
            }
            return h;
        }
        let f = self.scalar_fn(b);
        if let Some(groups) = b.groups_for(self.skip_fixed) {
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

/// Storage a derivative call's task reuses from block to block: the block's local point and
/// the summed multipliers of its outputs (no allocation per block once grown).
#[derive(Debug, Default)]
pub(super) struct BlockScratch {
    z: Vec<f64>,
    w: Vec<f64>,
}

impl BlockScratch {
    /// x[vars] (as [`gather`]).
    fn point(&mut self, x: &[f64], vars: &[usize]) -> &[f64] {
        self.gather_point(x, vars);
        &self.z
    }

    /// x[vars] and, per output, the sum of the multipliers of the rows it is added into.
    fn point_and_weights(
        &mut self,
        x: &[f64],
        vars: &[usize],
        lambda: &[f64],
        targets: &[Vec<usize>],
    ) -> (&[f64], &[f64]) {
        self.gather_point(x, vars);
        self.w.clear();
        self.w.extend(
            targets
                .iter()
                .map(|rows| rows.iter().map(|&r| lambda[r]).sum::<f64>()),
        );
        (&self.z, &self.w)
    }

    /// x[vars] into the point's storage.
    fn gather_point(&mut self, x: &[f64], vars: &[usize]) {
        self.z.clear();
        self.z.extend(vars.iter().map(|&v| x[v]));
    }
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

/// Zeroes the rows and columns of a square matrix outside `kept` (ascending), as
/// [`expand_hessian`] leaves them.
fn keep_only(m: &mut DMatrix<f64>, kept: &[usize]) {
    let dim = m.nrows();
    let mut keep = vec![false; dim];
    for &i in kept {
        keep[i] = true;
    }
    for i in (0..dim).filter(|&i| !keep[i]) {
        m.row_mut(i).fill(0.0);
        m.column_mut(i).fill(0.0);
    }
}

/// Add a block's local Hessian (lower pairs of its nonlinear inputs) into the Hessian.
pub(super) fn scatter_lower<K>(b: &Block<K>, local: &DMatrix<f64>, values: &mut [f64]) {
    // The pairs (a, c ≤ a) with c < linear_from (`Block::has_hessian_pair`), in slot order.
    let mut slot = b.hessian_slots.iter();
    for a in 0..b.nonlinear {
        let row = local.row(a);
        for (c, &(s, mult)) in (0..(a + 1).min(b.linear_from)).zip(slot.by_ref()) {
            if s != NO_SLOT {
                values[s] += mult * row[c];
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

/// (contact, configuration variables, order) of a shared contact geometry.
type GeometryKey<'a> = (usize, &'a [usize], usize);

/// The point jets of the last derivative calls' shared contact geometries, one pool per
/// callback (the Jacobian's geometries are of a lower order than the Hessian's), lent to the
/// next call's geometries so that their jets are written into storage of the right size:
/// no allocation and no zero-filling of ∂²p and ∂³p per call.
#[derive(Debug, Default)]
pub(super) struct JetPools {
    jacobian: Mutex<Vec<PointJet>>,
    hessian: Mutex<Vec<PointJet>>,
}

/// Contact geometries shared by the blocks of one derivative call, keyed by contact and the
/// variables of the configuration they are taken at; each is computed by the first block
/// that reads it (on whichever thread), so sharing adds no pass over the pool.
#[derive(Default)]
struct SharedGeometries<'a> {
    /// (contact, first configuration variable) → position in `keys`.
    index: HashMap<(usize, usize), usize>,
    keys: Vec<GeometryKey<'a>>,
    cells: Vec<OnceLock<ContactGeometry<'a>>>,
    /// Where the geometries' jets come from and go back to.
    jets: Option<&'a Mutex<Vec<PointJet>>>,
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
        build: &(dyn Fn(GeometryKey<'a>, PointJet) -> ContactGeometry<'a> + Sync),
    ) -> Option<&ContactGeometry<'a>> {
        let &i = self.index.get(&(contact, *q.first()?))?;
        let key = self.keys[i];
        (key.1 == q).then(|| self.cells[i].get_or_init(|| build(key, self.take_jet())))
    }

    /// A jet from the pool (a new one when it is empty).
    fn take_jet(&self) -> PointJet {
        self.jets
            .and_then(|pool| pool.lock().ok()?.pop())
            .unwrap_or_default()
    }

    /// Gives the jets of the geometries built back to the pool.
    fn recycle(self) {
        let Some(pool) = self.jets else { return };
        let jets = self
            .cells
            .into_iter()
            .filter_map(|cell| cell.into_inner().map(ContactGeometry::into_jet));
        if let Ok(mut pool) = pool.lock() {
            pool.extend(jets);
        }
    }

    /// The shared geometry a block over `vars` reads where it declares `geometry`, if any.
    fn get(
        &self,
        geometry: Option<GeometryUse>,
        vars: &[usize],
        build: &(dyn Fn(GeometryKey<'a>, PointJet) -> ContactGeometry<'a> + Sync),
    ) -> Option<&ContactGeometry<'a>> {
        let u = geometry?;
        self.lookup(u.contact, &vars[u.q], build)
    }
}

#[cfg(test)]
mod tests {
    use crate::autodiff::finite_differences::{central, moved};
    use crate::random::SeededRng;
    use crate::transcription::fixture::hopper;

    /// A point off the guess: every variable moved by up to 0.05, within its bounds.
    fn point(t: &crate::transcription::Transcription<crate::discrete::ModelMechanics>) -> Vec<f64> {
        let mut rng = SeededRng::new(7);
        let (lo, hi) = t.variable_bounds();
        t.initial_point()
            .iter()
            .enumerate()
            .map(|(i, &x)| (x + rng.symmetric(0.05)).clamp(lo[i], hi[i]))
            .collect()
    }

    /// The dense Jacobian column j from the sparse values.
    fn jacobian_column(
        t: &crate::transcription::Transcription<crate::discrete::ModelMechanics>,
        x: &[f64],
        j: usize,
    ) -> Vec<f64> {
        let pattern = t.jacobian_pattern();
        let mut values = vec![0.0; pattern.nnz()];
        t.jacobian_values(x, &mut values);
        let mut column = vec![0.0; t.layout().num_constraints()];
        for ((&r, &c), v) in pattern.rows.iter().zip(&pattern.cols).zip(&values) {
            if c == j {
                column[r] += v;
            }
        }
        column
    }

    #[test]
    fn the_objective_is_the_sum_of_its_terms() {
        let t = hopper(&[]);
        let x = point(&t);
        let terms: f64 = t.objective_terms(&x).iter().map(|(_, v)| v).sum();
        let f = t.objective(&x);
        assert!(f > 0.0);
        assert!(
            (f - terms).abs() <= 1e-12 * f,
            "{f} against the terms' {terms}"
        );
    }

    #[test]
    fn gradient_and_jacobian_agree_with_central_differences() {
        let t = hopper(&[]);
        let x = point(&t);
        let mut grad = vec![0.0; x.len()];
        t.gradient(&x, &mut grad);
        let rows = t.layout().num_constraints();
        let g = |y: &[f64]| {
            let mut out = vec![0.0; rows];
            t.constraints(y, &mut out);
            out
        };
        // Every fifth variable: knots, inputs, steps, impulses and slacks all among them.
        for j in (0..x.len()).step_by(5) {
            let fd = central(|s| t.objective(&moved(&x, j, s)), 1e-6);
            assert!(
                (grad[j] - fd).abs() <= 1e-6 * (1.0 + fd.abs()),
                "∂f/∂x{j}: {} against {fd}",
                grad[j]
            );
            let fd = central(|s| g(&moved(&x, j, s)), 1e-6);
            for (r, (a, d)) in jacobian_column(&t, &x, j).iter().zip(&fd).enumerate() {
                assert!(
                    (a - d).abs() <= 1e-5 * (1.0 + d.abs()),
                    "∂g{r}/∂x{j}: {a} against {d}"
                );
            }
        }
    }

    #[test]
    fn the_hessian_is_the_lagrangians_second_derivative() {
        let t = hopper(&[]);
        let x = point(&t);
        let rows = t.layout().num_constraints();
        let mut rng = SeededRng::new(11);
        let lambda = rng.symmetric_vec(rows, 1.0);
        let obj_factor = 0.7;
        // ∇L = obj_factor ∇f + Jᵀλ, densely.
        let grad_lagrangian = |y: &[f64]| -> Vec<f64> {
            let mut out = vec![0.0; y.len()];
            t.gradient(y, &mut out);
            out.iter_mut().for_each(|v| *v *= obj_factor);
            let pattern = t.jacobian_pattern();
            let mut values = vec![0.0; pattern.nnz()];
            t.jacobian_values(y, &mut values);
            for ((&r, &c), v) in pattern.rows.iter().zip(&pattern.cols).zip(&values) {
                out[c] += lambda[r] * v;
            }
            out
        };
        let pattern = t.hessian_pattern();
        let mut values = vec![0.0; pattern.nnz()];
        t.hessian_values(&x, obj_factor, &lambda, &mut values);
        let n = x.len();
        let mut dense = vec![0.0; n * n];
        for ((&r, &c), v) in pattern.rows.iter().zip(&pattern.cols).zip(&values) {
            dense[r * n + c] += v;
            if r != c {
                dense[c * n + r] += v;
            }
        }
        for j in (0..n).step_by(7) {
            let fd = central(|s| grad_lagrangian(&moved(&x, j, s)), 1e-5);
            for (i, d) in fd.iter().enumerate() {
                let a = dense[i * n + j];
                assert!(
                    (a - d).abs() <= 1e-4 * (1.0 + d.abs()),
                    "∂²L/∂x{i}∂x{j}: {a} against {d}"
                );
            }
        }
    }

    #[test]
    fn the_pool_and_one_thread_evaluate_the_same_bits() {
        let mut t = hopper(&[]);
        let x = point(&t);
        let lambda = SeededRng::new(3).symmetric_vec(t.layout().num_constraints(), 1.0);
        let mut run = |parallel: bool| {
            t.set_parallel(parallel);
            let mut jac = vec![0.0; t.jacobian_pattern().nnz()];
            t.jacobian_values(&x, &mut jac);
            let mut hess = vec![0.0; t.hessian_pattern().nnz()];
            t.hessian_values(&x, 1.0, &lambda, &mut hess);
            (jac, hess)
        };
        let (serial, pooled) = (run(false), run(true));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
        assert_eq!(bits(&serial.0), bits(&pooled.0));
        assert_eq!(bits(&serial.1), bits(&pooled.1));
    }
}
