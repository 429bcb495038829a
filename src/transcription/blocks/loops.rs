//! Derivatives of the loop-closure blocks from the mechanics' loop jets
//! ([`MechanicsDerivatives::loop_jets`]) instead of generic AD over the whole block: the
//! residual rows a(q) ([`VectorKind::LoopClosure`](super::VectorKind)) and the loop work
//! γᵀa(q) ([`ScalarKind::LoopWork`](super::ScalarKind)), z = [q; γ], whose q-gradient is the
//! impulse A(q)ᵀγ in the DEL rows. Generic AD of γᵀa over n + nl inputs to third order was
//! 85 % of HAMR's callback time (benches/hamr_callbacks.rs).

use nalgebra::DMatrix;

use crate::autodiff::ThirdOrder;
use crate::discrete::MechanicsDerivatives;
use crate::model::LoopJet;

/// Calls `f(row, a, coordinate)` for every (row, local coordinate) of the jets.
fn for_each_entry(jets: &[LoopJet], mut f: impl FnMut(&LoopJet, usize, usize)) {
    for jet in jets {
        for r in 0..jet.rows() {
            for a in 0..jet.coords.len() {
                f(jet, r, a);
            }
        }
    }
}

/// Jacobian ∂a/∂q of the loop-closure rows (nl × n).
pub(crate) fn loop_closure_jacobian<M: MechanicsDerivatives>(mech: &M, q: &[f64]) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(mech.num_loop_constraints(), q.len());
    for_each_entry(&mech.loop_jets(q, 1, &[]), |jet, r, a| {
        out[(jet.first_row + r, jet.coords[a])] = jet.first[r * jet.coords.len() + a];
    });
    out
}

/// Σ_r w_r ∇²a_r of the loop-closure rows (n × n).
pub(crate) fn loop_closure_hessian<M: MechanicsDerivatives>(
    mech: &M,
    q: &[f64],
    w: &[f64],
) -> DMatrix<f64> {
    let n = q.len();
    let mut out = DMatrix::zeros(n, n);
    for jet in mech.loop_jets(q, 2, &[]) {
        add_weighted(&mut out, &jet, &jet.second, |r| w[jet.first_row + r]);
    }
    out
}

/// out[coords[a], coords[b]] += Σ_r weight(r) · rows[(r u + a) u + b].
fn add_weighted(
    out: &mut DMatrix<f64>,
    jet: &LoopJet,
    rows: &[f64],
    weight: impl Fn(usize) -> f64,
) {
    let u = jet.coords.len();
    for r in 0..jet.rows() {
        let wr = weight(r);
        if wr == 0.0 {
            continue;
        }
        for (a, &ca) in jet.coords.iter().enumerate() {
            for (b, &cb) in jet.coords.iter().enumerate() {
                out[(ca, cb)] += wr * rows[(r * u + a) * u + b];
            }
        }
    }
}

/// Gradient of the loop work γᵀa(q) at z = [q; γ]: [A(q)ᵀγ; a(q)].
pub(crate) fn loop_work_gradient<M: MechanicsDerivatives>(mech: &M, z: &[f64]) -> Vec<f64> {
    let n = mech.nq();
    let (q, gamma) = z.split_at(n);
    let mut out = vec![0.0; z.len()];
    for jet in mech.loop_jets(q, 1, &[]) {
        let u = jet.coords.len();
        for r in 0..jet.rows() {
            out[n + jet.first_row + r] = jet.value[r];
            for (a, &ca) in jet.coords.iter().enumerate() {
                out[ca] += gamma[jet.first_row + r] * jet.first[r * u + a];
            }
        }
    }
    out
}

/// Hessian of the loop work at z = [q; γ]: Σ γ_r ∇²a_r in the q block, A(q) between q and γ.
pub(crate) fn loop_work_hessian<M: MechanicsDerivatives>(mech: &M, z: &[f64]) -> DMatrix<f64> {
    let n = mech.nq();
    let (q, gamma) = z.split_at(n);
    let mut out = DMatrix::zeros(z.len(), z.len());
    for jet in mech.loop_jets(q, 2, &[]) {
        add_weighted(&mut out, &jet, &jet.second, |r| gamma[jet.first_row + r]);
        add_loop_jacobian(&mut out, n, &jet, |r, a| {
            jet.first[r * jet.coords.len() + a]
        });
    }
    out
}

/// The q-γ blocks of a loop-work matrix: out[coords[a], n + row] = out[n + row, coords[a]]
/// = entry(r, a).
fn add_loop_jacobian(
    out: &mut DMatrix<f64>,
    n: usize,
    jet: &LoopJet,
    entry: impl Fn(usize, usize) -> f64,
) {
    for r in 0..jet.rows() {
        for (a, &ca) in jet.coords.iter().enumerate() {
            let v = entry(r, a);
            out[(ca, n + jet.first_row + r)] += v;
            out[(n + jet.first_row + r, ca)] += v;
        }
    }
}

/// Value, gradient, Hessian and third derivative contracted with `dir` (length n + nl) of
/// the loop work at z = [q; γ]. The contraction's q block is Σ γ_r ∂³a_r[dir_q] +
/// Σ dir_γr ∇²a_r, its q-γ blocks ∇²a_r·dir_q; γ enters linearly, so the γ-γ block is zero.
pub(crate) fn loop_work_third<M: MechanicsDerivatives>(
    mech: &M,
    z: &[f64],
    dir: &[f64],
) -> ThirdOrder {
    let n = mech.nq();
    let (q, gamma) = z.split_at(n);
    let (dir_q, dir_gamma) = dir.split_at(n);
    let mut out = ThirdOrder::zeros(z.len());
    for jet in mech.loop_jets(q, 3, dir_q) {
        let u = jet.coords.len();
        for r in 0..jet.rows() {
            let row = jet.first_row + r;
            out.value += gamma[row] * jet.value[r];
            out.gradient[n + row] = jet.value[r];
            for (a, &ca) in jet.coords.iter().enumerate() {
                out.gradient[ca] += gamma[row] * jet.first[r * u + a];
            }
        }
        add_weighted(&mut out.hessian, &jet, &jet.second, |r| {
            gamma[jet.first_row + r]
        });
        add_loop_jacobian(&mut out.hessian, n, &jet, |r, a| jet.first[r * u + a]);
        add_weighted(&mut out.contracted, &jet, &jet.third_along, |r| {
            gamma[jet.first_row + r]
        });
        add_weighted(&mut out.contracted, &jet, &jet.second, |r| {
            dir_gamma[jet.first_row + r]
        });
        add_loop_jacobian(&mut out.contracted, n, &jet, |r, a| {
            jet.coords
                .iter()
                .enumerate()
                .map(|(b, &cb)| jet.second[(r * u + a) * u + b] * dir_q[cb])
                .sum()
        });
    }
    out
}
