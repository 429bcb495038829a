//! Contact blocks: impulses in the DEL rows, tangential velocity, non-penetration, friction
//! cone and the relaxed complementarity products (SPEC.md, "Common formulation").

use nalgebra::{DMatrix, DVector};

use super::contact_geometry::ContactGeometry;
use super::{Context, VectorBlockFn, VectorKind, tangential_rates};
use crate::autodiff::{jacobian, weighted_hessian};
use crate::contact::{signed_distance, tangential_coordinates};
use crate::discrete::{Mechanics, MechanicsDerivatives, difference_velocity};
use crate::scalar::Scalar;

/// φ_i(q); z = [q].
pub fn distance<D: Scalar, M: Mechanics>(mech: &M, ctx: &Context, contact: usize, z: &[D]) -> D {
    signed_distance(&ctx.terrain, &mech.contact_position(contact, &z[..ctx.n]))
}

/// c_i φ_i(q) + Σ_t (β⁺_it − β⁻_it) t_i(q) of one contact; z = [q; c_i; β_i (nd)].
/// Its gradient in q is contact i's share of J(q)ᵀλ = Nᵀc + Pᵀβ, P = [D; −D]; for a rolling
/// sphere, D adds the spin columns, whose share is the [`VectorKind::SpinFriction`] block.
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
    let qdot = difference_velocity(qa, qb, h);
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

/// Jacobian (nd × (2n + 1)) of [`tangential_rate`] at z = [qa; qb; h] by the chain rule:
/// with v = (qb − qa)/h and D = ∂t/∂q at qb, row d is [−D_d/h, (∂²t_d/∂q²)v + D_d/h,
/// −D_d·v/h] (rows d + nt negated).
pub fn tangential_rate_jacobian<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
) -> DMatrix<f64> {
    if mech.contact_rolls(contact) {
        return rolling_rate_derivatives(mech, ctx, contact, z, None);
    }
    let geometry = ContactGeometry::new(mech, ctx, contact, &z[ctx.n..2 * ctx.n], 2);
    tangential_rate_jacobian_in(&geometry, ctx, z)
}

/// [`tangential_rate_jacobian`] of a sliding (non-rolling) contact from its geometry at qb
/// (order ≥ 2).
pub(crate) fn tangential_rate_jacobian_in(
    geometry: &ContactGeometry,
    ctx: &Context,
    z: &[f64],
) -> DMatrix<f64> {
    let n = ctx.n;
    let nt = ctx.nd() / 2;
    let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
    let v = difference_velocity(qa, qb, h);
    let (jacobian, directional) = (geometry.jacobian(), geometry.directional(&v));
    let mut out = DMatrix::zeros(2 * nt, 2 * n + 1);
    for d in 0..nt {
        let (jac, hv) = (jacobian.row(1 + d), directional.row(1 + d));
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
/// chain rule. With a = w_d − w_{d+nt}, s(q) = aᵀt(q), G = ∇s, H = ∇²s, T = ∇²(∇s·v) at qb:
/// qb–qa −H/h, qb–qb T + 2H/h, h–qa G/h², h–qb −Hv/h − G/h², h–h 2G·v/h² (qa–qa zero).
pub fn tangential_rate_hessian<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
    w: &[f64],
) -> DMatrix<f64> {
    if mech.contact_rolls(contact) {
        return rolling_rate_derivatives(mech, ctx, contact, z, Some(w));
    }
    let geometry = ContactGeometry::new(mech, ctx, contact, &z[ctx.n..2 * ctx.n], 3);
    tangential_rate_hessian_in(&geometry, ctx, z, w)
}

/// [`tangential_rate_hessian`] of a sliding (non-rolling) contact from its geometry at qb
/// (order 3).
pub(crate) fn tangential_rate_hessian_in(
    geometry: &ContactGeometry,
    ctx: &Context,
    z: &[f64],
    w: &[f64],
) -> DMatrix<f64> {
    let n = ctx.n;
    let nt = ctx.nd() / 2;
    let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
    let v = difference_velocity(qa, qb, h);
    let mut weights = [0.0; 3];
    for d in 0..nt {
        weights[1 + d] = w[d] - w[d + nt];
    }
    let (g, hs, t) = (
        geometry.gradient(&weights),
        geometry.hessian(&weights),
        geometry.third(&weights, &v),
    );
    let hv = &hs * nalgebra::DVector::from_column_slice(&v);
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

/// Jacobian (and, with weights, Σ_r w_r ∇²(rate_r)) of a rolling contact's
/// [`tangential_rate`] by generic forward AD: its spin columns come from the kinematics
/// generic over the scalar, with no jets of their own.
fn rolling_rate_derivatives<M: Mechanics>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
    w: Option<&[f64]>,
) -> DMatrix<f64> {
    let kind = VectorKind::TangentialRate { contact };
    let f = VectorBlockFn {
        mech,
        ctx,
        kind: &kind,
        dim_in: 2 * ctx.n + 1,
        dim_out: ctx.nd(),
    };
    match w {
        Some(w) => weighted_hessian(&f, z, w),
        None => jacobian(&f, z).1,
    }
}

/// The spin part of a rolling contact's friction impulse ([`VectorKind::SpinFriction`]) and
/// its Jacobian over z = [q; c; β] (n × (n + 1 + nd)) by generic forward AD, for the
/// simulator's knot rows.
pub fn spin_friction_jacobian<M: Mechanics>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
) -> (Vec<f64>, DMatrix<f64>) {
    let kind = VectorKind::SpinFriction { contact };
    let f = VectorBlockFn {
        mech,
        ctx,
        kind: &kind,
        dim_in: ctx.n + 1 + ctx.nd(),
        dim_out: ctx.n,
    };
    jacobian(&f, z)
}

/// Gradient of [`contact_work`] over z = [q; c; β]: [Nᵀc + Pᵀβ share; φ; ±t_d], by the chain
/// rule from the point's first derivatives.
pub fn contact_work_gradient<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
) -> Vec<f64> {
    let (n, nd) = (ctx.n, ctx.nd());
    let nt = nd / 2;
    let geometry = ContactGeometry::new(mech, ctx, contact, &z[..n], 1);
    let mut out = geometry.gradient(&work_weights(ctx, z));
    let k = geometry.value();
    out.push(k[0]);
    for sign in [1.0, -1.0] {
        for d in 0..nt {
            out.push(sign * k[1 + d]);
        }
    }
    out
}

/// b = [c, β⁺ − β⁻] of contact work, the weights of K = [φ, t] in it.
fn work_weights(ctx: &Context, z: &[f64]) -> [f64; 3] {
    let n = ctx.n;
    let nt = ctx.nd() / 2;
    let mut b = [z[n], 0.0, 0.0];
    for d in 0..nt {
        b[1 + d] = z[n + 1 + d] - z[n + 1 + d + nt];
    }
    b
}

/// Hessian of [`contact_work`] over z = [q; c; β] (the Jacobian of its DEL-row gradient) by the
/// chain rule: with b = [c, β⁺ − β⁻] and K = [φ, t], the q–q block is ∇²(bᵀK), the q–c column
/// ∇φ and the q–β⁺/β⁻ columns ±∇t_d (the function is linear in c and β).
pub fn contact_work_hessian<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
) -> DMatrix<f64> {
    let geometry = ContactGeometry::new(mech, ctx, contact, &z[..ctx.n], 2);
    contact_work_derivatives(&geometry, ctx, z, None).0
}

/// [`contact_work_hessian`] from the contact's geometry at q (order ≥ 2).
pub(crate) fn contact_work_hessian_in(
    geometry: &ContactGeometry,
    ctx: &Context,
    z: &[f64],
) -> DMatrix<f64> {
    contact_work_derivatives(geometry, ctx, z, None).0
}

/// [`contact_work_hessian`] and the third derivative of [`contact_work`] contracted with `dir`
/// (the DEL-row multipliers on q; the c and β entries of `dir` must be zero, as their
/// gradient components go to no row), both (n + 1 + nd)², symmetric. Returns `None` when
/// `dir` has a nonzero c or β entry.
pub fn contact_work_third<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
    dir: &[f64],
) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    if dir[ctx.n..].iter().any(|&d| d != 0.0) {
        return None;
    }
    let geometry = ContactGeometry::new(mech, ctx, contact, &z[..ctx.n], 3);
    contact_work_third_in(&geometry, ctx, z, dir)
}

/// [`contact_work_third`] from the contact's geometry at q (order 3).
pub(crate) fn contact_work_third_in(
    geometry: &ContactGeometry,
    ctx: &Context,
    z: &[f64],
    dir: &[f64],
) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    if dir[ctx.n..].iter().any(|&d| d != 0.0) {
        return None;
    }
    let (hessian, contracted) = contact_work_derivatives(geometry, ctx, z, Some(dir));
    contracted.map(|c| (hessian, c))
}

/// The Hessian of contact work and, with `dir`, its contracted third derivative, from the
/// geometry at q (order 2, or 3 with `dir`).
fn contact_work_derivatives(
    geometry: &ContactGeometry,
    ctx: &Context,
    z: &[f64],
    dir: Option<&[f64]>,
) -> (DMatrix<f64>, Option<DMatrix<f64>>) {
    let (n, nd) = (ctx.n, ctx.nd());
    let nt = nd / 2;
    let b = work_weights(ctx, z);
    let dim = n + 1 + nd;
    let mut hessian = DMatrix::zeros(dim, dim);
    hessian
        .view_mut((0, 0), (n, n))
        .copy_from(&geometry.hessian(&b));
    let jacobian = geometry.jacobian();
    let dir_q = dir.map(|d| &d[..n]);
    let directional = dir_q.map(|d| geometry.directional(d));
    let mut contracted = dir_q.map(|d| {
        let mut c = DMatrix::zeros(dim, dim);
        c.view_mut((0, 0), (n, n)).copy_from(&geometry.third(&b, d));
        c
    });
    // q–c and q–β: columns ∇K_k (sign ± for β⁺/β⁻), and their directional derivatives.
    let mut columns = vec![(n, 0, 1.0)];
    for d in 0..nt {
        columns.push((n + 1 + d, 1 + d, 1.0));
        columns.push((n + 1 + d + nt, 1 + d, -1.0));
    }
    for (col, row_k, sign) in columns {
        for i in 0..n {
            let g = sign * jacobian[(row_k, i)];
            hessian[(i, col)] = g;
            hessian[(col, i)] = g;
            if let (Some(c), Some(dd)) = (contracted.as_mut(), directional.as_ref()) {
                let t = sign * dd[(row_k, i)];
                c[(i, col)] = t;
                c[(col, i)] = t;
            }
        }
    }
    (hessian, contracted)
}

/// Jacobian of φ_i(q) ([`distance`], 1 × n) or of −c_i φ_i(q) ([`contact_gap`], 1 × (n + 1),
/// z = [q; c_i]) by the chain rule.
pub fn distance_jacobian<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
    gap: bool,
) -> DMatrix<f64> {
    let geometry = ContactGeometry::new(mech, ctx, contact, &z[..ctx.n], 1);
    distance_jacobian_in(&geometry, ctx, z, gap)
}

/// φ_i(q) and its gradient ∇φ_i (n × 1) from one point jet: the c entry of
/// [`contact_work_gradient`] and the q–c column of [`contact_work_hessian`], to the bit,
/// without the rest of either (the simulator's contact scaling, active set and pivoting step).
pub fn distance_with_gradient<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    q: &[f64],
) -> (f64, DVector<f64>) {
    let geometry = ContactGeometry::new(mech, ctx, contact, &q[..ctx.n], 1);
    let gradient = geometry.jacobian().row(0).transpose();
    (geometry.value()[0], gradient)
}

/// [`distance_jacobian`] from the contact's geometry at q (order ≥ 1).
pub(crate) fn distance_jacobian_in(
    geometry: &ContactGeometry,
    ctx: &Context,
    z: &[f64],
    gap: bool,
) -> DMatrix<f64> {
    let n = ctx.n;
    let grad = geometry.gradient(&[1.0, 0.0, 0.0]);
    if !gap {
        return DMatrix::from_row_slice(1, n, &grad);
    }
    let c = z[n];
    let mut out = DMatrix::zeros(1, n + 1);
    for i in 0..n {
        out[(0, i)] = -c * grad[i];
    }
    out[(0, n)] = -geometry.value()[0];
    out
}

/// w·∇²φ_i (n × n) or w·∇²(−c_i φ_i) ((n + 1)²) by the chain rule; see [`distance_jacobian`].
pub fn distance_hessian<M: MechanicsDerivatives>(
    mech: &M,
    ctx: &Context,
    contact: usize,
    z: &[f64],
    w: f64,
    gap: bool,
) -> DMatrix<f64> {
    let geometry = ContactGeometry::new(mech, ctx, contact, &z[..ctx.n], 2);
    distance_hessian_in(&geometry, ctx, z, w, gap)
}

/// [`distance_hessian`] from the contact's geometry at q (order ≥ 2).
pub(crate) fn distance_hessian_in(
    geometry: &ContactGeometry,
    ctx: &Context,
    z: &[f64],
    w: f64,
    gap: bool,
) -> DMatrix<f64> {
    let n = ctx.n;
    if !gap {
        return geometry.hessian(&[w, 0.0, 0.0]);
    }
    let c = z[n];
    let mut out = DMatrix::zeros(n + 1, n + 1);
    out.view_mut((0, 0), (n, n))
        .copy_from(&geometry.hessian(&[-w * c, 0.0, 0.0]));
    let grad = geometry.gradient(&[-w, 0.0, 0.0]);
    for i in 0..n {
        out[(i, n)] = grad[i];
        out[(n, i)] = grad[i];
    }
    out
}

/// Jacobian (3 × dim) of [`complementarity`] in closed form: the rows are bilinear in the
/// contact variables (ηᵀβ, ψ(μc − eᵀβ)) and linear in the slacks. Generic AD needed three
/// tile passes for these ten inputs per contact (15 % of the brick's J + H); the FD and
/// chain-rule-against-AD tests cover this path.
pub fn complementarity_jacobian(
    ctx: &Context,
    contacts: &[usize],
    slacks: usize,
    z: &[f64],
) -> DMatrix<f64> {
    let nd = ctx.nd();
    let stride = 2 + 2 * nd;
    let mut out = DMatrix::zeros(3, z.len());
    for (l, &i) in contacts.iter().enumerate() {
        let base = l * stride;
        let (c, psi) = (z[base], z[base + 1 + nd]);
        let mut cone = c * ctx.friction[i];
        for d in 0..nd {
            let (beta, eta) = (z[base + 1 + d], z[base + 2 + nd + d]);
            out[(0, base + 1 + d)] = -eta;
            out[(0, base + 2 + nd + d)] = -beta;
            out[(2, base + 1 + d)] = psi;
            cone -= beta;
        }
        out[(2, base)] = -psi * ctx.friction[i];
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
    ctx: &Context,
    contacts: &[usize],
    dim: usize,
    w: &[f64],
) -> DMatrix<f64> {
    let nd = ctx.nd();
    let stride = 2 + 2 * nd;
    let mut out = DMatrix::zeros(dim, dim);
    let mut set = |a: usize, b: usize, v: f64| {
        out[(a, b)] = v;
        out[(b, a)] = v;
    };
    for (l, &i) in contacts.iter().enumerate() {
        let base = l * stride;
        let psi = base + 1 + nd;
        set(base, psi, -w[2] * ctx.friction[i]);
        for d in 0..nd {
            set(base + 1 + d, base + 2 + nd + d, -w[0]);
            set(base + 1 + d, psi, w[2]);
        }
    }
    out
}
