//! Contact blocks: impulses in the DEL rows, tangential velocity, non-penetration, friction
//! cone and the relaxed complementarity products (SPEC.md, "Common formulation").

use nalgebra::DMatrix;

use super::{Context, tangential_rates};
use crate::autodiff::{
    ScalarFunction, VectorFunction, gradient_hessian, gradient_hessian_third, jacobian_directional,
};
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

/// The contact point's signed distance and tangential coordinates [φ, t_1 (, t_2)] as a
/// function of q alone (length n), so that the contact blocks can be differentiated over n
/// inputs and assembled by the chain rule, instead of over their 2n + 1 (or n + 1 + nd).
struct PointCoordinates<'a, M> {
    mech: &'a M,
    ctx: &'a Context,
    contact: usize,
    /// Weights of [φ, t…] for the scalar form ([`ScalarFunction`]); unused by the vector form.
    weights: [f64; 3],
}

impl<M: Mechanics> PointCoordinates<'_, M> {
    fn coordinates<D: Scalar>(&self, q: &[D]) -> [D; 3] {
        let p = self.mech.contact_position(self.contact, q);
        let mut t = [D::from(0.0); 2];
        tangential_coordinates(self.ctx.basis, &p, &mut t);
        [signed_distance(&self.ctx.terrain, &p), t[0], t[1]]
    }
}

impl<M: Mechanics> VectorFunction for PointCoordinates<'_, M> {
    fn dim_in(&self) -> usize {
        self.ctx.n
    }
    fn dim_out(&self) -> usize {
        1 + self.ctx.nd() / 2
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        let k = self.coordinates(z);
        out.copy_from_slice(&k[..out.len()]);
    }
}

impl<M: Mechanics> ScalarFunction for PointCoordinates<'_, M> {
    fn dim(&self) -> usize {
        self.ctx.n
    }
    fn eval<D: Scalar>(&self, z: &[D]) -> D {
        let k = self.coordinates(z);
        k.iter()
            .zip(self.weights)
            .fold(D::from(0.0), |acc, (&ki, w)| acc + ki * D::from(w))
    }
}

fn point_coordinates<'a, M>(
    mech: &'a M,
    ctx: &'a Context,
    contact: usize,
    weights: [f64; 3],
) -> PointCoordinates<'a, M> {
    PointCoordinates {
        mech,
        ctx,
        contact,
        weights,
    }
}

/// Jacobian (nd × (2n + 1)) of [`tangential_rate`] at z = [qa; qb; h] by the chain rule:
/// with v = (qb − qa)/h and D = ∂t/∂q at qb, row d is [−D_d/h, (∂²t_d/∂q²)v + D_d/h,
/// −D_d·v/h] (rows d + nt negated). Only first-order passes over the n coordinates.
pub fn tangential_rate_jacobian<M: Mechanics>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
) -> DMatrix<f64> {
    let n = ctx.n;
    let nt = ctx.nd() / 2;
    let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
    let v: Vec<f64> = qa.iter().zip(qb).map(|(&a, &b)| (b - a) / h).collect();
    let k = jacobian_directional(&point_coordinates(mech, ctx, contact, [0.0; 3]), qb, &v);
    let mut out = DMatrix::zeros(2 * nt, 2 * n + 1);
    for d in 0..nt {
        let (jac, hv) = (k.jacobian.row(1 + d), k.directional.row(1 + d));
        let rate = jac.dot(&nalgebra::RowDVector::from_row_slice(&v));
        for sign_row in [(1.0, d), (-1.0, d + nt)] {
            let (sign, r) = sign_row;
            for c in 0..n {
                out[(r, c)] = -sign * jac[c] / h;
                out[(r, n + c)] = sign * (hv[c] + jac[c] / h);
            }
            out[(r, 2 * n)] = -sign * rate / h;
        }
    }
    out
}

/// Σ_r w_r ∇²(rate_r) of [`tangential_rate`] at z = [qa; qb; h] ((2n + 1)², symmetric) by the
/// chain rule. With a = w_d − w_{d+nt}, s(q) = aᵀt(q), G = ∇s, H = ∇²s, T = ∇²(∇s·v) at qb
/// (one third-order pass over the n coordinates): qb–qa −H/h, qb–qb T + 2H/h, h–qa G/h²,
/// h–qb −Hv/h − G/h², h–h 2G·v/h² (qa–qa zero).
pub fn tangential_rate_hessian<M: Mechanics>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
    w: &[f64],
) -> DMatrix<f64> {
    let n = ctx.n;
    let nt = ctx.nd() / 2;
    let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
    let v: Vec<f64> = qa.iter().zip(qb).map(|(&a, &b)| (b - a) / h).collect();
    let mut weights = [0.0; 3];
    for d in 0..nt {
        weights[1 + d] = w[d] - w[d + nt];
    }
    let s = gradient_hessian_third(&point_coordinates(mech, ctx, contact, weights), qb, &v);
    let (g, hs, t) = (&s.gradient, &s.hessian, &s.contracted);
    let hv = hs * nalgebra::DVector::from_column_slice(&v);
    let gv: f64 = g.iter().zip(&v).map(|(a, b)| a * b).sum();
    let mut out = DMatrix::zeros(2 * n + 1, 2 * n + 1);
    let (h2, ih) = (h * h, 1.0 / h);
    for i in 0..n {
        for j in 0..n {
            out[(n + i, j)] = -hs[(i, j)] * ih;
            out[(j, n + i)] = -hs[(i, j)] * ih;
            out[(n + i, n + j)] = t[(i, j)] + 2.0 * hs[(i, j)] * ih;
        }
        out[(2 * n, i)] = g[i] / h2;
        out[(i, 2 * n)] = g[i] / h2;
        let hq = -hv[i] * ih - g[i] / h2;
        out[(2 * n, n + i)] = hq;
        out[(n + i, 2 * n)] = hq;
    }
    out[(2 * n, 2 * n)] = 2.0 * gv / h2;
    out
}

/// Hessian of [`contact_work`] over z = [q; c; β] (the Jacobian of its DEL-row gradient) by the
/// chain rule: with b = [c, β⁺ − β⁻] and K = [φ, t], the q–q block is ∇²(bᵀK), the q–c column
/// ∇φ and the q–β⁺/β⁻ columns ±∇t_d (the function is linear in c and β).
pub fn contact_work_hessian<M: Mechanics>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
) -> DMatrix<f64> {
    contact_work_derivatives(mech, ctx, contact, z, None).0
}

/// [`contact_work_hessian`] and the third derivative of [`contact_work`] contracted with `dir`
/// (the DEL-row multipliers on q; the c and β entries of `dir` must be zero, as their
/// gradient components go to no row), both (n + 1 + nd)², symmetric. Returns `None` when
/// `dir` has a nonzero c or β entry.
pub fn contact_work_third<M: Mechanics>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
    dir: &[f64],
) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    if dir[ctx.n..].iter().any(|&d| d != 0.0) {
        return None;
    }
    let (hessian, contracted) = contact_work_derivatives(mech, ctx, contact, z, Some(dir));
    contracted.map(|c| (hessian, c))
}

fn contact_work_derivatives<M: Mechanics>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
    dir: Option<&[f64]>,
) -> (DMatrix<f64>, Option<DMatrix<f64>>) {
    let (n, nd) = (ctx.n, ctx.nd());
    let nt = nd / 2;
    let q = &z[..n];
    let mut b = [z[n], 0.0, 0.0];
    for d in 0..nt {
        b[1 + d] = z[n + 1 + d] - z[n + 1 + d + nt];
    }
    let dim = n + 1 + nd;
    let mut hessian = DMatrix::zeros(dim, dim);
    let zero_dir = vec![0.0; n];
    let dir_q = dir.map_or(&zero_dir[..], |d| &d[..n]);
    let work = point_coordinates(mech, ctx, contact, b);
    let k = jacobian_directional(&work, q, dir_q);
    let mut contracted = dir.map(|_| DMatrix::zeros(dim, dim));
    // q–q: ∇²(bᵀK) and, with a direction, ∇²(∇(bᵀK)·dir).
    if let Some(c) = contracted.as_mut() {
        let s = gradient_hessian_third(&work, q, dir_q);
        hessian.view_mut((0, 0), (n, n)).copy_from(&s.hessian);
        c.view_mut((0, 0), (n, n)).copy_from(&s.contracted);
    } else {
        let s = gradient_hessian(&work, q);
        hessian.view_mut((0, 0), (n, n)).copy_from(&s.2);
    }
    // q–c and q–β: columns ∇K_k (sign ± for β⁺/β⁻), and their directional derivatives.
    let mut columns = vec![(n, 0, 1.0)];
    for d in 0..nt {
        columns.push((n + 1 + d, 1 + d, 1.0));
        columns.push((n + 1 + d + nt, 1 + d, -1.0));
    }
    for (col, row_k, sign) in columns {
        for i in 0..n {
            let g = sign * k.jacobian[(row_k, i)];
            hessian[(i, col)] = g;
            hessian[(col, i)] = g;
            if let Some(c) = contracted.as_mut() {
                let t = sign * k.directional[(row_k, i)];
                c[(i, col)] = t;
                c[(col, i)] = t;
            }
        }
    }
    (hessian, contracted)
}
