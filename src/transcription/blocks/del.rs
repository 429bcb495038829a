//! Dynamics blocks: discrete Lagrangian segments, discrete forces, the initial momentum,
//! semi-implicit Euler knots and loop-closure impulses. The midpoint DEL rows are the sums
//! D2Ld + D1Ld + ½Fd + ½Fd + J(q)ᵀλ + A(q)ᵀγ; the Euler rows are one knot residual
//! (eq. 1 of the paper) + J(q)ᵀλ + A(q)ᵀγ.

use super::Context;
use crate::scalar::Scalar;
use crate::transcription::Mechanics;

/// Ld(qa, qb, h); z = [qa; qb; h].
pub fn segment<D: Scalar, M: Mechanics>(mech: &M, ctx: &Context, z: &[D]) -> D {
    let n = ctx.n;
    mech.discrete_lagrangian(&z[..n], &z[n..2 * n], z[2 * n])
}

/// ½Fd(qa, qb, u, h); z = [qa; qb; u; h].
pub fn half_force<D: Scalar, M: Mechanics>(mech: &M, ctx: &Context, z: &[D], out: &mut [D]) {
    let (n, m) = (ctx.n, ctx.m);
    let (qa, rest) = z.split_at(n);
    let (qb, rest) = rest.split_at(n);
    let (u, h) = rest.split_at(m);
    mech.discrete_force(qa, qb, u, h[0], out);
    for o in out.iter_mut() {
        *o *= D::from(0.5);
    }
}

/// M(q_0)v_0; z = [q_0; v_0].
pub fn initial_momentum<D: Scalar, M: Mechanics>(mech: &M, ctx: &Context, z: &[D], out: &mut [D]) {
    mech.momentum(&z[..ctx.n], &z[ctx.n..2 * ctx.n], out);
}

/// Semi-implicit Euler residual at knot k; z = [v_0; q_0; q_1; h_0; u_0] at the first step,
/// else [q_{k−1}; q_k; q_{k+1}; h_{k−1}; h_k; u_k] with v_k = (q_k − q_{k−1})/h_{k−1}.
pub fn euler_knot<D: Scalar, M: Mechanics>(
    mech: &M,
    ctx: &Context,
    first_step: bool,
    z: &[D],
    out: &mut [D],
) {
    let n = ctx.n;
    let (x, rest) = z.split_at(n);
    let (q_k, rest) = rest.split_at(n);
    let (q_next, rest) = rest.split_at(n);
    let (v_k, h, u) = if first_step {
        (x.to_vec(), rest[0], &rest[1..])
    } else {
        let h_prev = rest[0];
        let v: Vec<D> = x.iter().zip(q_k).map(|(&a, &b)| (b - a) / h_prev).collect();
        (v, rest[1], &rest[2..])
    };
    mech.euler_residual(&v_k, q_k, q_next, h, u, out);
}

/// γᵀa(q); z = [q; γ]. Its gradient in q is the loop impulse A(q)ᵀγ.
pub fn loop_work<D: Scalar, M: Mechanics>(mech: &M, ctx: &Context, z: &[D]) -> D {
    let mut a = vec![D::from(0.0); ctx.nl];
    mech.loop_residual(&z[..ctx.n], &mut a);
    a.iter()
        .zip(&z[ctx.n..])
        .fold(D::from(0.0), |acc, (&ai, &gi)| acc + ai * gi)
}
