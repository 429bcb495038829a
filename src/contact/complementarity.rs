//! The complementarity products of a contact, ηᵀβ, c·φ and ψ(μc − eᵀβ), with the friction
//! cone μc − eᵀβ they share: defined once here for the NLP's complementarity rows (with their
//! closed-form derivatives, bilinear in the contact impulses), the penalty form's objective and
//! the reports of a solution and of a simulation.

use nalgebra::DMatrix;

use super::ContactModel;
use crate::autodiff::Scalar;

/// μc − eᵀβ: from μc, each β_d subtracted in direction order.
pub fn cone<D: Scalar>(mu: f64, c: D, beta: &[D]) -> D {
    beta.iter().fold(c * D::from(mu), |acc, &b| acc - b)
}

/// μ_i c − eᵀβ ([`cone`]); z = [c; β (nd)].
pub fn friction_cone<D: Scalar>(model: &ContactModel, contact: usize, z: &[D]) -> D {
    cone(model.friction[contact], z[0], &z[1..])
}

/// ηᵀβ, summed from 0 in direction order.
pub fn eta_beta<D: Scalar>(eta: &[D], beta: &[D]) -> D {
    eta.iter()
        .zip(beta)
        .fold(D::from(0.0), |acc, (&e, &b)| acc + e * b)
}

/// c·φ.
pub fn gap_product<D: Scalar>(c: D, phi: D) -> D {
    c * phi
}

/// ψ(μc − eᵀβ), of the cone's value ([`cone`]).
pub fn cone_product<D: Scalar>(psi: D, cone: D) -> D {
    psi * cone
}

/// The factors of a contact's products that belong to interval j: c_j, ψ_j and η_j (nd).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Own<'a, D> {
    /// Normal impulse c_j.
    pub c: D,
    /// ψ_j, the sliding speed (η_j = P v + ψ_j e).
    pub psi: D,
    /// η_j (nd).
    pub eta: &'a [D],
}

/// The factors complementary to [`Own`]'s, of a partner interval k of j's contact-mode block
/// (k = j without blocks, and in the simulator): φ(q_{k+1}) against c_j, β_k (nd) against
/// η_j and the cone μc_k − eᵀβ_k ([`cone`]) against ψ_j.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Partner<'a, D> {
    /// Signed distance φ(q_{k+1}).
    pub phi: D,
    /// Friction impulses β_k (nd).
    pub beta: &'a [D],
    /// μc_k − eᵀβ_k.
    pub cone: D,
}

/// A contact's three complementarity products, in the order of the complementarity rows:
/// ηᵀβ ([`eta_beta`]), c·φ ([`gap_product`]) and ψ(μc − eᵀβ) ([`cone_product`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Products<D> {
    /// η_jᵀβ_k.
    pub eta_beta: D,
    /// c_j·φ(q_{k+1}).
    pub gap: D,
    /// ψ_j(μc_k − eᵀβ_k).
    pub cone: D,
}

impl<D: Scalar> Products<D> {
    /// The raw products of `own`'s factors with `partner`'s.
    pub fn new(own: &Own<'_, D>, partner: &Partner<'_, D>) -> Self {
        Self {
            eta_beta: eta_beta(own.eta, partner.beta),
            gap: gap_product(own.c, partner.phi),
            cone: cone_product(own.psi, partner.cone),
        }
    }
}

/// A factor of a complementarity product at or below this counts as zero in the products
/// that judge a plan ([`Products::clipped`]). Ipopt's bound relaxation leaves factors that are
/// zero at about ±1e-8, and ψ and η, which nothing bounds in flight, reach 1e6 (Spring
/// Flamingo's walk): their raw products are noise of ±1e-2, which in the rows' sums over the
/// contacts can hide another contact's real product of the same size (a friction impulse of
/// 0.62 along a slip of 0.46 on LittleDog's step). 1e-6 is a hundred times the relaxation and
/// far below any impulse, distance or speed a plan uses.
pub const FACTOR_FLOOR: f64 = 1e-6;

impl Products<f64> {
    /// The products that report how far a solution is from complementarity: every factor at
    /// or below [`FACTOR_FLOOR`] counted as zero (Ipopt's bound relaxation leaves them at
    /// ±1e-8 where they are 0, and a negative factor would hide another product), the partner
    /// factors summed over `partners` (the intervals of j's contact-mode block, whose sums the
    /// rows pair with j's own factors) before the products are taken.
    pub fn clipped<'a>(
        own: &Own<'_, f64>,
        partners: impl IntoIterator<Item = Partner<'a, f64>>,
    ) -> Self {
        let pos = |v: f64| if v > FACTOR_FLOOR { v } else { 0.0 };
        let mut beta = vec![0.0; own.eta.len()];
        let (mut phi, mut cone) = (0.0, 0.0);
        for partner in partners {
            for (sum, &b) in beta.iter_mut().zip(partner.beta) {
                *sum += pos(b);
            }
            phi += pos(partner.phi);
            cone += pos(partner.cone);
        }
        let eta: Vec<f64> = own.eta.iter().map(|&e| pos(e)).collect();
        let own = Own {
            c: pos(own.c),
            psi: pos(own.psi),
            eta: &eta,
        };
        Self::new(
            &own,
            &Partner {
                phi,
                beta: &beta,
                cone,
            },
        )
    }
}

impl<D> From<Products<D>> for [D; 3] {
    fn from(p: Products<D>) -> Self {
        [p.eta_beta, p.gap, p.cone]
    }
}

/// The relaxed products s − Σ ηᵀβ, s − (Σ c·φ: added by [`super::contact_gap`] blocks),
/// s − Σ ψ(μc − eᵀβ) over the listed contacts ([`eta_beta`], [`cone_product`]); z = [(c, β,
/// ψ, η) per contact; slacks (none, 1 shared, or one per product)], out length 3. With no
/// slack the block adds only −products (another block holds s).
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
        sums[0] += eta_beta(eta, beta);
        sums[2] += cone_product(psi, cone(model.friction[i], c, beta));
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
        for d in 0..nd {
            let (beta, eta) = (z[base + 1 + d], z[base + 2 + nd + d]);
            out[(0, base + 1 + d)] = -eta;
            out[(0, base + 2 + nd + d)] = -beta;
            out[(2, base + 1 + d)] = psi;
        }
        out[(2, base)] = -psi * model.friction[i];
        out[(2, base + 1 + nd)] = -cone(model.friction[i], c, &z[base + 1..base + 1 + nd]);
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

#[cfg(test)]
mod tests {
    use num_dual::Dual64;

    use super::*;
    use crate::contact::Terrain;

    /// μ = 0.5, c = 2, ψ = 3, η = (4, 1) against φ = 0.125, β = (0.25, 0.5): the cone is
    /// 1 − 0.25 − 0.5 = 0.25, the products ηᵀβ = 1 + 0.5, c·φ = 0.25 and ψ·cone = 0.75.
    #[test]
    fn products_of_a_small_case_by_hand() {
        let beta = [0.25, 0.5];
        assert_eq!(cone(0.5, 2.0, &beta), 0.25);
        let own = Own {
            c: 2.0,
            psi: 3.0,
            eta: &[4.0, 1.0],
        };
        let partner = Partner {
            phi: 0.125,
            beta: &beta,
            cone: cone(0.5, 2.0, &beta),
        };
        let products = Products::new(&own, &partner);
        assert_eq!(<[f64; 3]>::from(products), [1.5, 0.25, 0.75]);
        // With nonnegative factors and one partner, clipping changes nothing.
        assert_eq!(Products::clipped(&own, [partner]), products);
    }

    /// The rows are s minus the same products (the c·φ row's product comes from
    /// `contact_gap` blocks), summed over the contacts.
    #[test]
    fn rows_subtract_the_products_from_the_slack() {
        let model = ContactModel::new(true, vec![0.5, 1.0], Terrain::flat());
        // Contact 0 as in `products_of_a_small_case_by_hand`; contact 1: μ = 1, c = 1,
        // β = (0.5, 0.25), ψ = 2, η = (1, 2): ηᵀβ = 1, cone 0.25, ψ·cone = 0.5.
        let z = [
            2.0, 0.25, 0.5, 3.0, 4.0, 1.0, // contact 0
            1.0, 0.5, 0.25, 2.0, 1.0, 2.0, // contact 1
            8.0, // the shared slack
        ];
        let mut out = [0.0; 3];
        complementarity(&model, &[0, 1], 1, &z, &mut out);
        assert_eq!(out, [8.0 - 2.5, 8.0, 8.0 - 1.25]);
        complementarity(&model, &[1], 0, &z[6..12], &mut out);
        assert_eq!(out, [-1.0, 0.0, -0.5]);
        assert_eq!(friction_cone(&model, 1, &z[6..9]), 0.25);
    }

    /// Each negative factor counts as 0, and the partner factors are summed over the block
    /// after clipping: a negative φ, β_d or cone of one partner does not cancel another's.
    #[test]
    fn clipping_zeroes_negative_factors_before_summing_the_partners() {
        let own = Own {
            c: 4.0,
            psi: 2.0,
            eta: &[3.0, -1e-8],
        };
        let first = Partner {
            phi: -1e-8,
            beta: &[1.0, -1e-8],
            cone: 0.75,
        };
        let second = Partner {
            phi: 0.25,
            beta: &[0.5, 2.0],
            cone: -0.5,
        };
        let clipped = Products::clipped(&own, [first, second]);
        // ηᵀβ = 3·(1 + 0.5) + 0·(0 + 2), c·φ = 4·(0 + 0.25), ψ·cone = 2·(0.75 + 0).
        assert_eq!(<[f64; 3]>::from(clipped), [4.5, 1.0, 1.5]);
        // Raw, the second partner's products are 1.5 − 2e-8, 1 and −1.
        let raw = Products::new(&own, &second);
        assert_eq!(raw.eta_beta, 1.5 - 2e-8);
        assert_eq!((raw.gap, raw.cone), (1.0, -1.0));
        assert_eq!(
            <[f64; 3]>::from(Products::clipped(&own, [second])),
            [1.5, 1.0, 0.0]
        );
        // A negative own factor zeroes its product whatever the partner's.
        let negative = Own {
            c: -1e-8,
            psi: -1e-8,
            eta: &[-1e-8, -1e-8],
        };
        assert_eq!(
            <[f64; 3]>::from(Products::clipped(&negative, [first, second])),
            [0.0, 0.0, 0.0]
        );
        // No partner: nothing to pair with.
        assert_eq!(
            <[f64; 3]>::from(Products::clipped(&own, [])),
            [0.0, 0.0, 0.0]
        );
    }

    /// Generic over the scalar: dual numbers carry the derivatives of the bilinear products
    /// (here in c, η_0 and ψ at once: φ + β_0 + cone).
    #[test]
    fn dual_numbers_carry_the_derivatives() {
        let d = |re: f64, eps: f64| Dual64::new(re, eps);
        let beta = [d(0.25, 0.0), d(0.5, 0.0)];
        let c = d(2.0, 1.0);
        let cone = cone(0.5, c, &beta);
        assert_eq!((cone.re, cone.eps), (0.25, 0.5));
        let own = Own {
            c,
            psi: d(3.0, 1.0),
            eta: &[d(4.0, 1.0), d(1.0, 0.0)],
        };
        let partner = Partner {
            phi: d(0.125, 0.0),
            beta: &beta,
            cone,
        };
        let p = Products::new(&own, &partner);
        assert_eq!((p.eta_beta.re, p.eta_beta.eps), (1.5, 0.25));
        assert_eq!((p.gap.re, p.gap.eps), (0.25, 0.125));
        // ψ·cone: ψ' cone + ψ cone' = 0.25 + 3·0.5.
        assert_eq!((p.cone.re, p.cone.eps), (0.75, 1.75));
    }
}
