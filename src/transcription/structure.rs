//! Sparsity structure: which local Jacobian and Hessian entries of each block can be nonzero,
//! and their slots in the global patterns.
//!
//! The structure comes from one function, [`Transcription::probe_structure`], which today
//! evaluates every block's derivatives at seeded points around the initial guess; the slot
//! assignment ([`Transcription::assign_slots`]) reads only its masks, so a structure derived
//! from dependencies can replace the probing without touching the rest.

use nalgebra::DMatrix;

use super::Transcription;
use super::blocks::Block;
use super::evaluate::{ContactDerivatives, gather};
use super::pattern::PatternBuilder;
use crate::autodiff::{gradient_hessian, jacobian, weighted_hessian};
use crate::discrete::MechanicsDerivatives;

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

impl<M: MechanicsDerivatives> Transcription<M> {
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
    ) -> BlockMask {
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

    /// Sparsity patterns of the whole NLP: the structure of every block, placed.
    pub(super) fn build_patterns(&mut self) {
        let structure = self.probe_structure();
        self.assign_slots(&structure);
    }

    /// Which local entries of every block can be nonzero, by probing values (see
    /// [`Transcription::probe`]). The one place that decides structure.
    fn probe_structure(&self) -> Structure {
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
                    let third = self.gradient_block_third(b, z, w, ContactDerivatives::GenericAd);
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
        Structure {
            cost: cost_masks,
            gradient: gradient_masks,
            vector: vector_masks,
        }
    }

    /// Global Jacobian and Hessian slots of every block's structural nonzeros, and the
    /// inputs its generic-AD Hessian runs over.
    fn assign_slots(&mut self, structure: &Structure) {
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
        for (b, m) in self.cost_blocks.iter_mut().zip(&structure.cost) {
            place(b, m, &fixed, &mut jac, &mut hess);
        }
        for (b, m) in self.gradient_blocks.iter_mut().zip(&structure.gradient) {
            place(b, m, &fixed, &mut jac, &mut hess);
        }
        for (b, m) in self.vector_blocks.iter_mut().zip(&structure.vector) {
            place(b, m, &fixed, &mut jac, &mut hess);
        }
        self.jacobian = jac.finish();
        self.hessian = hess.finish();
    }
}
