//! Contact blocks: impulses in the DEL rows, tangential velocity, non-penetration, friction
//! cone and the relaxed complementarity products (SPEC.md, "Common formulation").

use super::{Context, tangential_rates};
use crate::contact::{signed_distance, tangential_coordinates};
use crate::model::Scalar;
use crate::transcription::Mechanics;

/// φ_i(q); z = [q].
pub fn distance<D: Scalar, M: Mechanics>(mech: &M, ctx: &Context, contact: usize, z: &[D]) -> D {
    signed_distance(&ctx.terrain, &mech.contact_position(contact, &z[..ctx.n]))
}

/// Σ_i c_i φ_i(q) + Σ_i Σ_t (β⁺_it − β⁻_it) t_i(q); z = [q; c (nc); β (nc·nd)].
/// Its gradient in q is J(q)ᵀλ = Nᵀc + Pᵀβ with P = [D; −D].
pub fn contact_work<D: Scalar, M: Mechanics>(mech: &M, ctx: &Context, z: &[D]) -> D {
    let (n, nd) = (ctx.n, ctx.nd());
    let nt = nd / 2;
    let nc = ctx.friction.len();
    let q = &z[..n];
    let c = &z[n..n + nc];
    let beta = &z[n + nc..];
    let mut work = D::from(0.0);
    for i in 0..nc {
        let p = mech.contact_position(i, q);
        work += c[i] * signed_distance(&ctx.terrain, &p);
        let mut t = [D::from(0.0); 2];
        tangential_coordinates(ctx.basis, &p, &mut t);
        let b = &beta[i * nd..(i + 1) * nd];
        for d in 0..nt {
            work += (b[d] - b[d + nt]) * t[d];
        }
    }
    work
}

/// P_i(qb)(qb − qa)/h + ψ e − η; z = [qa; qb; h; ψ; η (nd)], out length nd.
pub fn tangential_velocity<D: Scalar, M: Mechanics>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[D],
    out: &mut [D],
) {
    let (n, nd) = (ctx.n, ctx.nd());
    let nt = nd / 2;
    let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
    let psi = z[2 * n + 1];
    let eta = &z[2 * n + 2..2 * n + 2 + nd];
    let qdot: Vec<D> = qa.iter().zip(qb).map(|(&a, &b)| (b - a) / h).collect();
    let mut rate = [D::from(0.0); 2];
    tangential_rates(mech, ctx, contact, qb, &qdot, &mut rate[..nt]);
    for d in 0..nt {
        out[d] = rate[d] + psi - eta[d];
        out[d + nt] = -rate[d] + psi - eta[d + nt];
    }
}

/// μ_i c − eᵀβ; z = [c; β (nd)].
pub fn friction_cone<D: Scalar>(ctx: &Context, contact: usize, z: &[D]) -> D {
    z[1..].iter().fold(z[0] * D::from(ctx.friction[contact]), |acc, &b| acc - b)
}

/// The relaxed products s − Σ ηᵀβ, s − Σ c·φ, s − Σ ψ(μc − eᵀβ) over the listed contacts;
/// z = [q; (c, β, ψ, η) per contact; slacks (none, 1 shared, or one per product)], out
/// length 3. With no slack the block adds only −products (another block holds s).
pub fn complementarity<D: Scalar, M: Mechanics>(
    mech: &M,
    ctx: &Context,
    contacts: &[usize],
    slacks: usize,
    z: &[D],
    out: &mut [D],
) {
    let (n, nd) = (ctx.n, ctx.nd());
    let stride = 2 + 2 * nd;
    let mut sums = [D::from(0.0); 3];
    for (l, &i) in contacts.iter().enumerate() {
        let v = &z[n + l * stride..n + (l + 1) * stride];
        let (c, beta, psi, eta) = (v[0], &v[1..1 + nd], v[1 + nd], &v[2 + nd..]);
        let phi = distance(mech, ctx, i, z);
        let eta_beta = eta
            .iter()
            .zip(beta)
            .fold(D::from(0.0), |acc, (&e, &b)| acc + e * b);
        let cone = beta
            .iter()
            .fold(c * D::from(ctx.friction[i]), |acc, &b| acc - b);
        sums[0] += eta_beta;
        sums[1] += c * phi;
        sums[2] += psi * cone;
    }
    let s = &z[n + contacts.len() * stride..];
    for p in 0..3 {
        let slack = match slacks {
            0 => D::from(0.0),
            1 => s[0],
            _ => s[p],
        };
        out[p] = slack - sums[p];
    }
}
