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

/// c_i φ_i(q) + Σ_t (β⁺_it − β⁻_it) t_i(q) of one contact; z = [q; c_i; β_i (nd)].
/// Its gradient in q is contact i's share of J(q)ᵀλ = Nᵀc + Pᵀβ, P = [D; −D].
pub fn contact_work<D: Scalar, M: Mechanics>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[D],
) -> D {
    let (n, nd) = (ctx.n, ctx.nd());
    let nt = nd / 2;
    let p = mech.contact_position(contact, &z[..n]);
    let (c, beta) = (z[n], &z[n + 1..n + 1 + nd]);
    let mut work = c * signed_distance(&ctx.terrain, &p);
    let mut t = [D::from(0.0); 2];
    tangential_coordinates(ctx.basis, &p, &mut t);
    for d in 0..nt {
        work += (beta[d] - beta[d + nt]) * t[d];
    }
    work
}

/// ±P_i(qb)(qb − qa)/h, the nonlinear part of the tangential-velocity rows;
/// z = [qa; qb; h], out length nd ([+D·q̇; −D·q̇]).
pub fn tangential_rate<D: Scalar, M: Mechanics>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[D],
    out: &mut [D],
) {
    let n = ctx.n;
    let nt = ctx.nd() / 2;
    let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
    let qdot: Vec<D> = qa.iter().zip(qb).map(|(&a, &b)| (b - a) / h).collect();
    let mut rate = [D::from(0.0); 2];
    tangential_rates(mech, ctx, contact, qb, &qdot, &mut rate[..nt]);
    for d in 0..nt {
        out[d] = rate[d];
        out[d + nt] = -rate[d];
    }
}

/// ψ e − η, the linear part of the tangential-velocity rows; z = [ψ; η (nd)].
pub fn tangential_slack<D: Scalar>(z: &[D], out: &mut [D]) {
    for (o, &eta) in out.iter_mut().zip(&z[1..]) {
        *o = z[0] - eta;
    }
}

/// −c_i φ_i(q), the only product of the complementarity rows that depends on q;
/// z = [q; c_i], out length 1 (added into the c·φ row).
pub fn contact_gap<D: Scalar, M: Mechanics>(mech: &M, ctx: &Context, contact: usize, z: &[D]) -> D {
    -z[ctx.n] * distance(mech, ctx, contact, z)
}

/// μ_i c − eᵀβ; z = [c; β (nd)].
pub fn friction_cone<D: Scalar>(ctx: &Context, contact: usize, z: &[D]) -> D {
    z[1..]
        .iter()
        .fold(z[0] * D::from(ctx.friction[contact]), |acc, &b| acc - b)
}

/// The relaxed products s − Σ ηᵀβ, s − (Σ c·φ: added by [`contact_gap`] blocks),
/// s − Σ ψ(μc − eᵀβ) over the listed contacts; z = [(c, β, ψ, η) per contact; slacks
/// (none, 1 shared, or one per product)], out length 3. With no slack the block adds only
/// −products (another block holds s).
pub fn complementarity<D: Scalar>(
    ctx: &Context,
    contacts: &[usize],
    slacks: usize,
    z: &[D],
    out: &mut [D],
) {
    let nd = ctx.nd();
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
            .fold(c * D::from(ctx.friction[i]), |acc, &b| acc - b);
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
