//! The friction cone μc − eᵀβ and the relaxed complementarity products of the NLP's
//! complementarity rows, bilinear in the contact impulses, with their closed-form derivatives.

use nalgebra::DMatrix;

use super::ContactModel;
use crate::autodiff::Scalar;

/// μ_i c − eᵀβ; z = [c; β (nd)].
pub fn friction_cone<D: Scalar>(model: &ContactModel, contact: usize, z: &[D]) -> D {
    z[1..]
        .iter()
        .fold(z[0] * D::from(model.friction[contact]), |acc, &b| acc - b)
}

/// The relaxed products s − Σ ηᵀβ, s − (Σ c·φ: added by [`super::contact_gap`] blocks),
/// s − Σ ψ(μc − eᵀβ) over the listed contacts; z = [(c, β, ψ, η) per contact; slacks
/// (none, 1 shared, or one per product)], out length 3. With no slack the block adds only
/// −products (another block holds s).
pub fn complementarity<D: Scalar>(
    model: &ContactModel,
    contacts: &[usize],
    slacks: usize,
    z: &[D],
    out: &mut [D],
) {
    let nd = model.nd();
    let stride = 2 + 2 * nd;
    let mut sums = [D::from(0.0); 3];
    for (l, &i) in contacts.iter().enumerate() {
        let v = &z[l * stride..(l + 1) * stride];
        let (c, beta, psi, eta) = (v[0], &v[1..1 + nd], v[1 + nd], &v[2 + nd..]);
        let eta_beta = eta
            .iter()
            .zip(beta)
            .fold(D::from(0.0), |acc, (&e, &b)| acc + e * b);
        let cone = beta
            .iter()
            .fold(c * D::from(model.friction[i]), |acc, &b| acc - b);
        sums[0] += eta_beta;
        sums[2] += psi * cone;
    }
    let s = &z[contacts.len() * stride..];
    for p in 0..3 {
        let slack = match slacks {
            0 => D::from(0.0),
            1 => s[0],
            _ => s[p],
        };
        out[p] = slack - sums[p];
    }
}

/// Jacobian (3 × dim) of [`complementarity`] in closed form: the rows are bilinear in the
/// contact variables (ηᵀβ, ψ(μc − eᵀβ)) and linear in the slacks. Generic AD needed three
/// tile passes for these ten inputs per contact (15 % of the brick's J + H); the FD and
/// chain-rule-against-AD tests cover this path.
pub fn complementarity_jacobian(
    model: &ContactModel,
    contacts: &[usize],
    slacks: usize,
    z: &[f64],
) -> DMatrix<f64> {
    let nd = model.nd();
    let stride = 2 + 2 * nd;
    let mut out = DMatrix::zeros(3, z.len());
    for (l, &i) in contacts.iter().enumerate() {
        let base = l * stride;
        let (c, psi) = (z[base], z[base + 1 + nd]);
        let mut cone = c * model.friction[i];
        for d in 0..nd {
            let (beta, eta) = (z[base + 1 + d], z[base + 2 + nd + d]);
            out[(0, base + 1 + d)] = -eta;
            out[(0, base + 2 + nd + d)] = -beta;
            out[(2, base + 1 + d)] = psi;
            cone -= beta;
        }
        out[(2, base)] = -psi * model.friction[i];
        out[(2, base + 1 + nd)] = -cone;
    }
    let first_slack = contacts.len() * stride;
    for p in 0..3 {
        match slacks {
            0 => {}
            1 => out[(p, first_slack)] = 1.0,
            _ => out[(p, first_slack + p)] = 1.0,
        }
    }
    out
}

/// Σ_p w_p ∇²(row p) of [`complementarity`] in closed form (constant in z): −w₀ on each
/// (β_d, η_d) pair, −w₂μ on (c, ψ) and +w₂ on each (β_d, ψ).
pub fn complementarity_hessian(
    model: &ContactModel,
    contacts: &[usize],
    dim: usize,
    w: &[f64],
) -> DMatrix<f64> {
    let nd = model.nd();
    let stride = 2 + 2 * nd;
    let mut out = DMatrix::zeros(dim, dim);
    let mut set = |a: usize, b: usize, v: f64| {
        out[(a, b)] = v;
        out[(b, a)] = v;
    };
    for (l, &i) in contacts.iter().enumerate() {
        let base = l * stride;
        let psi = base + 1 + nd;
        set(base, psi, -w[2] * model.friction[i]);
        for d in 0..nd {
            set(base + 1 + d, base + 2 + nd + d, -w[0]);
            set(base + 1 + d, psi, w[2]);
        }
    }
    out
}
