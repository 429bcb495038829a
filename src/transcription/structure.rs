//! Sparsity structure: which local Jacobian and Hessian entries of each block can be nonzero,
//! and their slots in the global patterns.
//!
//! The structure is built by construction, never from values: every block's function runs
//! once over [`DependencyScalar`] inputs (through the same generic code that `f64` and the
//! duals run), which records which inputs each output depends on and which input pairs can
//! meet in its second derivative, anywhere in the domain. A gradient block (the DEL pieces)
//! runs over `Dual<DependencyScalar>` seeded along each input, whose ε part is that gradient
//! component. Blocks of one kind compute the same function of their local inputs, so each
//! kind is traced once. A function that branches on an input-dependent value (none does
//! today) is taken as dense, since the trace sees one side of the branch only.
//!
//! The fast derivative paths (the mechanics' segment derivatives, the contact chain rule)
//! compute the same functions' derivatives, so their nonzeros lie inside this structure;
//! what they write outside it is round-off on a structural zero, and is dropped.

use std::collections::HashMap;
use std::sync::Arc;

use num_dual::Dual;

use super::blocks::{Block, Context, PlacedBlocks, ScalarBlockFn, VectorBlockFn};
use super::pattern::{Pattern, PatternBuilder};
use crate::autodiff::dependency::{DependencyScalar, Trace};
use crate::autodiff::{ScalarFunction, SymmetricGroups, VectorFunction};
use crate::discrete::{MechanicsDerivatives, midpoint_segment_groups};

/// Slot marker of a local entry that is structurally zero (not in the pattern).
pub(super) const NO_SLOT: usize = usize::MAX;

/// One block's structural nonzeros: its local Jacobian entries (output o × input a at
/// `o * inputs + a`) and lower Hessian pairs (a, c ≤ a at `a * inputs + c`).
type BlockMask = (Vec<bool>, Vec<bool>);

/// The structure of every block, in the order of the block lists.
struct Structure {
    cost: Vec<BlockMask>,
    gradient: Vec<BlockMask>,
    vector: Vec<BlockMask>,
}

/// Which outputs of a block add into some row (the others' second derivatives carry no
/// multiplier and stay out of the Hessian).
fn live_outputs<K>(b: &Block<K>) -> Vec<bool> {
    b.targets.iter().map(|rows| !rows.is_empty()).collect()
}

/// Key of a block's traced structure: its kind, its size and which outputs are live.
fn trace_key<K: std::fmt::Debug>(b: &Block<K>) -> (String, usize, Vec<bool>) {
    (format!("{:?}", b.kind), b.vars.len(), live_outputs(b))
}

/// A dense mask: every Jacobian entry and lower Hessian pair (for a function that branched).
fn dense_mask(outputs: usize, nv: usize) -> BlockMask {
    let mut hess = vec![false; nv * nv];
    for a in 0..nv {
        for c in 0..=a {
            hess[a * nv + c] = true;
        }
    }
    (vec![true; outputs * nv], hess)
}

/// The lower triangle of a symmetric pair mask.
fn lower(mut pairs: Vec<bool>, nv: usize) -> Vec<bool> {
    for a in 0..nv {
        for c in a + 1..nv {
            pairs[a * nv + c] = false;
        }
    }
    pairs
}

/// Structure of a vector function: output o's dependencies, and the pairs of the live outputs.
fn vector_mask(f: &impl VectorFunction, z: &[f64], live: &[bool]) -> BlockMask {
    let nv = z.len();
    let trace = Trace::begin(nv);
    let input = trace.inputs(z);
    let mut out = vec![DependencyScalar::from(0.0); f.dim_out()];
    f.eval(&input, &mut out);
    if trace.branched() {
        return dense_mask(out.len(), nv);
    }
    let mut jac = Vec::with_capacity(out.len() * nv);
    let mut pairs = vec![false; nv * nv];
    for (o, y) in out.iter().enumerate() {
        jac.extend(trace.dependencies(y));
        if live[o] {
            trace.add_pairs(y, &mut pairs);
        }
    }
    (jac, lower(pairs, nv))
}

/// Structure of a cost: the pairs of its second derivative (its gradient is dense).
fn cost_mask(f: &impl ScalarFunction, z: &[f64], outputs: usize) -> BlockMask {
    let nv = z.len();
    let trace = Trace::begin(nv);
    let input = trace.inputs(z);
    let y = f.eval(&input);
    if trace.branched() {
        return dense_mask(outputs, nv);
    }
    let mut pairs = vec![false; nv * nv];
    trace.add_pairs(&y, &mut pairs);
    (vec![false; outputs * nv], lower(pairs, nv))
}

/// Structure of a gradient block (rows ∂f/∂z_a for a < outputs): row a's dependencies are the
/// nonzeros of ∂²f/∂z_a∂z, its pairs those of ∂³f/∂z_a∂z∂z, from forward duals over the
/// dependency scalar seeded along z_a.
fn gradient_mask(f: &impl ScalarFunction, z: &[f64], live: &[bool]) -> BlockMask {
    let nv = z.len();
    let outputs = live.len();
    let mut jac = Vec::with_capacity(outputs * nv);
    let mut pairs = vec![false; nv * nv];
    for (a, &row_live) in live.iter().enumerate() {
        let trace = Trace::begin(nv);
        let input: Vec<Dual<DependencyScalar>> = z
            .iter()
            .enumerate()
            .map(|(c, &v)| {
                let seed = if c == a { 1.0 } else { 0.0 };
                Dual::new(trace.input(c, v), DependencyScalar::from(seed))
            })
            .collect();
        let y = f.eval(&input);
        if trace.branched() {
            return dense_mask(outputs, nv);
        }
        jac.extend(trace.dependencies(&y.eps));
        if row_live {
            trace.add_pairs(&y.eps, &mut pairs);
        }
    }
    (jac, lower(pairs, nv))
}

/// Column groups of second-derivative patterns, computed once per distinct pattern.
#[derive(Default)]
struct GroupCache(HashMap<PatternKey, Option<Arc<SymmetricGroups>>>);

/// A pattern, the columns grouped over, and whether it is a midpoint segment's (whose qa
/// columns may be left unseeded, [`midpoint_segment_groups`]).
type PatternKey = (Vec<bool>, Vec<bool>, bool);

impl GroupCache {
    /// Groups of the symmetric `nv × nv` pattern `mask` (either triangle) over the marked
    /// columns, when they compress.
    fn over(&mut self, mask: &[bool], nv: usize, columns: &[bool]) -> Option<Arc<SymmetricGroups>> {
        self.0
            .entry((mask.to_vec(), columns.to_vec(), false))
            .or_insert_with(|| {
                let groups = SymmetricGroups::new(nv, mask, Some(columns));
                groups.compresses().then(|| Arc::new(groups))
            })
            .clone()
    }

    /// Groups of a midpoint segment's Hessian pattern `mask` ((2n + 1) × (2n + 1)) over the
    /// marked columns, with the mechanics' `translations` (length n), when they save passes.
    fn segment(
        &mut self,
        mask: &[bool],
        columns: &[bool],
        translations: &[bool],
    ) -> Option<Arc<SymmetricGroups>> {
        self.0
            .entry((mask.to_vec(), columns.to_vec(), true))
            .or_insert_with(|| {
                let groups = midpoint_segment_groups(mask, columns, translations);
                groups.compresses().then(|| Arc::new(groups))
            })
            .clone()
    }

    /// Groups of `mask` (`nv × nv`) restricted to the inputs `inputs`.
    fn restricted(
        &mut self,
        mask: &[bool],
        nv: usize,
        inputs: &[usize],
    ) -> Option<Arc<SymmetricGroups>> {
        let k = inputs.len();
        let sub: Vec<bool> = (0..k * k)
            .map(|e| mask[inputs[e / k] * nv + inputs[e % k]])
            .collect();
        self.over(&sub, k, &vec![true; k])
    }
}

/// The sparsity patterns (Jacobian, lower Hessian) of the NLP whose blocks are `blocks`: the
/// structure of every block (see the module documentation), placed. Fills each block's slots,
/// Hessian inputs and second-derivative groups; `x_lower` and `x_upper` say which variables are
/// fixed.
pub(super) fn build_patterns<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    blocks: &mut PlacedBlocks,
    x: &[f64],
    (x_lower, x_upper): (&[f64], &[f64]),
) -> (Pattern, Pattern) {
    let structure = dependency_structure(mech, ctx, blocks, x);
    let fixed: Vec<bool> = x_lower
        .iter()
        .zip(x_upper)
        .map(|(lo, hi)| lo == hi)
        .collect();
    assign_slots(blocks, &structure, &fixed, &mech.translation_coordinates())
}

/// Which local entries of every block can be nonzero anywhere, from the dependencies of its
/// function at `x`'s point (see the module documentation). The one place that decides
/// structure.
fn dependency_structure<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    blocks: &PlacedBlocks,
    x: &[f64],
) -> Structure {
    fn traced<K: std::fmt::Debug>(
        blocks: &[Block<K>],
        mut trace: impl FnMut(&Block<K>) -> BlockMask,
    ) -> Vec<BlockMask> {
        let mut cache: HashMap<(String, usize, Vec<bool>), BlockMask> = HashMap::new();
        blocks
            .iter()
            .map(|b| {
                cache
                    .entry(trace_key(b))
                    .or_insert_with(|| trace(b))
                    .clone()
            })
            .collect()
    }
    Structure {
        cost: traced(&blocks.cost, |b| {
            let f = ScalarBlockFn::new(mech, ctx, b);
            cost_mask(&f, &gather(x, &b.vars), b.targets.len())
        }),
        gradient: traced(&blocks.gradient, |b| {
            let f = ScalarBlockFn::new(mech, ctx, b);
            gradient_mask(&f, &gather(x, &b.vars), &live_outputs(b))
        }),
        vector: traced(&blocks.vector, |b| {
            let f = VectorBlockFn::new(mech, ctx, b);
            vector_mask(&f, &gather(x, &b.vars), &live_outputs(b))
        }),
    }
}

/// Global Jacobian and Hessian slots of every block's structural nonzeros, and the
/// inputs its generic-AD Hessian runs over.
fn assign_slots(
    blocks: &mut PlacedBlocks,
    structure: &Structure,
    fixed: &[bool],
    translations: &[bool],
) -> (Pattern, Pattern) {
    let mut jac = PatternBuilder::default();
    let mut hess = PatternBuilder::default();
    fn place<K>(
        b: &mut Block<K>,
        (jmask, hmask): &BlockMask,
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
    for (b, m) in blocks.cost.iter_mut().zip(&structure.cost) {
        place(b, m, fixed, &mut jac, &mut hess);
    }
    for (b, m) in blocks.gradient.iter_mut().zip(&structure.gradient) {
        place(b, m, fixed, &mut jac, &mut hess);
    }
    for (b, m) in blocks.vector.iter_mut().zip(&structure.vector) {
        place(b, m, fixed, &mut jac, &mut hess);
    }
    let mut groups = GroupCache::default();
    for (b, (_, hmask)) in blocks.cost.iter_mut().zip(&structure.cost) {
        let nv = b.vars.len();
        b.second_derivative_groups = groups.restricted(hmask, nv, &b.hessian_inputs);
        b.free_second_derivative_groups = groups.restricted(hmask, nv, &b.hessian_free_inputs);
    }
    for (b, (jmask, _)) in blocks.gradient.iter_mut().zip(&structure.gradient) {
        if b.kind.segment_groups() {
            // A segment's rows are the gradient of Ld: their Jacobian mask is the
            // pattern of the Hessian of Ld.
            let all = vec![true; b.vars.len()];
            b.second_derivative_groups = groups.segment(jmask, &all, translations);
            b.free_second_derivative_groups =
                groups.segment(jmask, &b.free_input_mask, translations);
        }
    }
    (jac.finish(), hess.finish())
}

/// x[vars] as a dense local vector.
pub(super) fn gather(x: &[f64], vars: &[usize]) -> Vec<f64> {
    vars.iter().map(|&v| x[v]).collect()
}
