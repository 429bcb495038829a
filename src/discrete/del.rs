//! The discrete Euler–Lagrange (DEL) equations of any [`Mechanics`]: the pieces the NLP places
//! on its dynamics rows, and the knot residual with its Jacobian in q_{k+1} that a forward
//! step solves, built from the same pieces.
//!
//! Midpoint DEL row of knot k (impulse units): D2Ld(q_{k−1}, q_k, h_{k−1}) + D1Ld(q_k, q_{k+1},
//! h_k) + ½Fd_{k−1} + ½Fd_k + J(q_{k+1})ᵀλ_k + G(q_{k+1})ᵀν_k, where D1Ld and D2Ld are the
//! halves of [`MechanicsDerivatives::segment_gradient`], ½Fd is [`half_force`], the contact
//! impulse J(q)ᵀλ is the q-gradient of the contact work (`crate::transcription`'s contact
//! blocks) and the loop impulse Gᵀν the q-gradient of [`loop_work`]. The first knot's row
//! starts from the momentum M(q_0)v_0 ([`initial_momentum`]) instead of D2Ld + ½Fd. The Euler
//! rows are one [`euler_knot`] residual (eq. 1 of the paper) plus the same impulses.

use nalgebra::DMatrix;

use super::{KnotWindow, Mechanics, MechanicsDerivatives, difference_velocity};
use crate::autodiff::Scalar;
use crate::autodiff::{VectorFunction, jacobian};

/// ½Fd(qa, qb, u, h) into `out` (length n); z = [qa; qb; u; h].
pub fn half_force<D: Scalar, M: Mechanics>(mech: &M, z: &[D], out: &mut [D]) {
    let (n, m) = (mech.nq(), mech.nu());
    let (qa, rest) = z.split_at(n);
    let (qb, rest) = rest.split_at(n);
    let (u, h) = rest.split_at(m);
    mech.discrete_force(qa, qb, u, h[0], out);
    for o in out.iter_mut() {
        *o *= D::from(0.5);
    }
}

/// M(q_0)v_0 into `out` (length n); z = [q_0; v_0].
pub fn initial_momentum<D: Scalar, M: Mechanics>(mech: &M, z: &[D], out: &mut [D]) {
    let n = mech.nq();
    mech.momentum(&z[..n], &z[n..2 * n], out);
}

/// Semi-implicit Euler residual at knot k into `out` (length n); z = [v_0; q_0; q_1; h_0; u_0]
/// at the first step, else [q_{k−1}; q_k; q_{k+1}; h_{k−1}; h_k; u_k] with
/// v_k = (q_k − q_{k−1})/h_{k−1}.
pub fn euler_knot<D: Scalar, M: Mechanics>(mech: &M, first_step: bool, z: &[D], out: &mut [D]) {
    let n = mech.nq();
    let (x, rest) = z.split_at(n);
    let (q_k, rest) = rest.split_at(n);
    let (q_next, rest) = rest.split_at(n);
    let (v_k, h, u) = if first_step {
        (x.to_vec(), rest[0], &rest[1..])
    } else {
        (difference_velocity(x, q_k, rest[0]), rest[1], &rest[2..])
    };
    mech.euler_residual(&v_k, q_k, q_next, h, u, out);
}

/// γᵀa(q); z = [q; γ]. Its gradient in q is the loop impulse G(q)ᵀγ.
pub fn loop_work<D: Scalar, M: Mechanics>(mech: &M, z: &[D]) -> D {
    let n = mech.nq();
    let mut a = vec![D::from(0.0); mech.num_loop_constraints()];
    mech.loop_residual(&z[..n], &mut a);
    a.iter()
        .zip(&z[n..])
        .fold(D::from(0.0), |acc, (&ai, &gi)| acc + ai * gi)
}

/// [`half_force`] as a [`VectorFunction`] of z = [qa; qb; u; h] (dim 2n + m + 1) → R^n.
#[derive(Debug, Clone, Copy)]
pub struct HalfForce<'a, M> {
    /// The robot.
    pub mech: &'a M,
}

impl<M: Mechanics> VectorFunction for HalfForce<'_, M> {
    fn dim_in(&self) -> usize {
        2 * self.mech.nq() + self.mech.nu() + 1
    }
    fn dim_out(&self) -> usize {
        self.mech.nq()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        half_force(self.mech, z, out);
    }
}

/// The segment input z = [qa; qb; h] of Ld.
fn segment(qa: &[f64], qb: &[f64], h: f64) -> Vec<f64> {
    let mut z = qa.to_vec();
    z.extend_from_slice(qb);
    z.push(h);
    z
}

/// The force input z = [qa; qb; u; h] of ½Fd.
fn force_input(qa: &[f64], qb: &[f64], u: &[f64], h: f64) -> Vec<f64> {
    let mut z = qa.to_vec();
    z.extend_from_slice(qb);
    z.extend_from_slice(u);
    z.push(h);
    z
}

/// The part of knot k's midpoint DEL row that q_{k+1} does not change (length n, impulse
/// units): D2Ld(q_{k−1}, q_k, h_{k−1}) + ½Fd(q_{k−1}, q_k, u_{k−1}, h_{k−1}), the momentum
/// p_k⁻ arriving at knot k. A forward step computes it once; the first knot's row has
/// [`initial_momentum`] here instead.
pub fn incoming_momentum<M: MechanicsDerivatives>(
    mech: &M,
    q_prev: &[f64],
    q_curr: &[f64],
    u_prev: &[f64],
    h_prev: f64,
) -> Vec<f64> {
    let n = mech.nq();
    let gradient = mech.segment_gradient(&segment(q_prev, q_curr, h_prev));
    let mut out = gradient[n..2 * n].to_vec();
    add_half_force(mech, q_prev, q_curr, u_prev, h_prev, &mut out);
    out
}

/// D1Ld(q_k, q_{k+1}, h_k) + ½Fd(q_k, q_{k+1}, u_k, h_k) = −p_k⁺ (length n), the part of knot
/// k's midpoint DEL row that depends on q_{k+1}; see [`outgoing_momentum_jacobian`].
pub fn outgoing_momentum<M: MechanicsDerivatives>(
    mech: &M,
    q_curr: &[f64],
    q_next: &[f64],
    u_curr: &[f64],
    h_curr: f64,
) -> Vec<f64> {
    let n = mech.nq();
    let mut value = mech.segment_gradient(&segment(q_curr, q_next, h_curr));
    value.truncate(n);
    add_half_force(mech, q_curr, q_next, u_curr, h_curr, &mut value);
    value
}

/// The part of knot k's midpoint DEL row that depends on q_{k+1} (length n):
/// D1Ld(q_k, q_{k+1}, h_k) + ½Fd(q_k, q_{k+1}, u_k, h_k) = −p_k⁺, and its Jacobian in q_{k+1}
/// (n × n): the qa–qb block of [`MechanicsDerivatives::segment_gradient_hessian`] plus
/// ½∂Fd/∂qb.
pub fn outgoing_momentum_jacobian<M: MechanicsDerivatives>(
    mech: &M,
    q_curr: &[f64],
    q_next: &[f64],
    u_curr: &[f64],
    h_curr: f64,
) -> (Vec<f64>, DMatrix<f64>) {
    let n = mech.nq();
    let (gradient, hessian) = mech.segment_gradient_hessian(&segment(q_curr, q_next, h_curr));
    let mut value = gradient[..n].to_vec();
    let mut jac = DMatrix::from_fn(n, n, |r, c| hessian[(r, n + c)]);
    if mech.has_discrete_force() {
        let force = force_input(q_curr, q_next, u_curr, h_curr);
        let (half, force_jacobian) = jacobian(&HalfForce { mech }, &force);
        value.iter_mut().zip(&half).for_each(|(v, f)| *v += f);
        jac += force_jacobian.columns(n, n);
    }
    (value, jac)
}

/// Adds ½Fd(qa, qb, u, h) to `out` (skipped when the mechanics has no discrete force).
fn add_half_force<M: Mechanics>(
    mech: &M,
    qa: &[f64],
    qb: &[f64],
    u: &[f64],
    h: f64,
    out: &mut [f64],
) {
    if !mech.has_discrete_force() {
        return;
    }
    let mut force = vec![0.0; mech.nq()];
    half_force(mech, &force_input(qa, qb, u, h), &mut force);
    out.iter_mut().zip(&force).for_each(|(o, f)| *o += f);
}

/// Midpoint DEL residual at knot k (length n, impulse units) of any mechanics:
/// [`incoming_momentum`] + D1Ld(q_k, q_{k+1}, h_k) + ½Fd_k + `impulse`, where `impulse`
/// (length n) is the caller's J(q_{k+1})ᵀλ_k + G(q_{k+1})ᵀν_k (zeros without contact or
/// loops). The slot derivatives are [`MechanicsDerivatives::segment_gradient`], the numbers
/// the NLP's DEL rows add up.
pub fn knot_residual<M: MechanicsDerivatives>(
    mech: &M,
    w: &KnotWindow<'_, f64>,
    impulse: &[f64],
) -> Vec<f64> {
    let mut residual = incoming_momentum(mech, w.q_prev, w.q_curr, w.u_prev, w.h_prev);
    let after = outgoing_momentum(mech, w.q_curr, w.q_next, w.u_curr, w.h_curr);
    residual.iter_mut().zip(&after).for_each(|(r, a)| *r += a);
    residual.iter_mut().zip(impulse).for_each(|(r, p)| *r += p);
    residual
}

/// Jacobian of [`knot_residual`] in q_{k+1} without the impulse (n × n): the Jacobian of
/// [`outgoing_momentum_jacobian`]. The caller adds the derivative of its impulse term.
pub fn knot_residual_jacobian_next<M: MechanicsDerivatives>(
    mech: &M,
    w: &KnotWindow<'_, f64>,
) -> DMatrix<f64> {
    outgoing_momentum_jacobian(mech, w.q_curr, w.q_next, w.u_curr, w.h_curr).1
}

/// [`euler_knot`] as a function of q_{k+1} alone (the rest fixed), for the Jacobian a forward
/// step needs: `before` is v_0 (`first_step`) or q_{k−1}, `h_prev` is ignored at the first
/// step.
#[derive(Debug, Clone, Copy)]
pub struct EulerKnotInNext<'a, M> {
    /// The robot.
    pub mech: &'a M,
    /// Whether `before` is v_0.
    pub first_step: bool,
    /// v_0 or q_{k−1} (length n).
    pub before: &'a [f64],
    /// q_k (length n).
    pub q_curr: &'a [f64],
    /// h_{k−1} (unused at the first step) and h_k, s.
    pub h_prev: f64,
    /// h_k, s.
    pub h_curr: f64,
    /// u_k (length m).
    pub u_curr: &'a [f64],
}

impl<M: Mechanics> VectorFunction for EulerKnotInNext<'_, M> {
    fn dim_in(&self) -> usize {
        self.mech.nq()
    }
    fn dim_out(&self) -> usize {
        self.mech.nq()
    }
    fn eval<D: Scalar>(&self, q_next: &[D], out: &mut [D]) {
        let lift = |x: &[f64]| x.iter().map(|&v| D::from(v)).collect::<Vec<D>>();
        self.eval_at(q_next, &lift(self.u_curr), out);
    }
}

impl<M: Mechanics> EulerKnotInNext<'_, M> {
    /// [`euler_knot`] at q_{k+1} = `q_next` and u_k = `u` (the rest from `self`).
    fn eval_at<D: Scalar>(&self, q_next: &[D], u: &[D], out: &mut [D]) {
        let lift = |x: &[f64]| x.iter().map(|&v| D::from(v)).collect::<Vec<D>>();
        let mut z = lift(self.before);
        z.extend(lift(self.q_curr));
        z.extend_from_slice(q_next);
        if !self.first_step {
            z.push(D::from(self.h_prev));
        }
        z.push(D::from(self.h_curr));
        z.extend_from_slice(u);
        euler_knot(self.mech, self.first_step, &z, out);
    }

    /// Jacobian of [`euler_knot`] in u_k at q_{k+1} = `q_next` (n × m), for an input that
    /// depends on q_{k+1} (a simulation's implicit feedback).
    pub fn input_jacobian(&self, q_next: &[f64]) -> DMatrix<f64> {
        jacobian(&EulerKnotInInput { knot: self, q_next }, self.u_curr).1
    }
}

/// [`EulerKnotInNext`] as a function of u_k alone.
struct EulerKnotInInput<'a, 'b, M> {
    knot: &'b EulerKnotInNext<'a, M>,
    q_next: &'b [f64],
}

impl<M: Mechanics> VectorFunction for EulerKnotInInput<'_, '_, M> {
    fn dim_in(&self) -> usize {
        self.knot.mech.nu()
    }
    fn dim_out(&self) -> usize {
        self.knot.mech.nq()
    }
    fn eval<D: Scalar>(&self, u: &[D], out: &mut [D]) {
        let q_next: Vec<D> = self.q_next.iter().map(|&v| D::from(v)).collect();
        self.knot.eval_at(&q_next, u, out);
    }
}

/// Jacobian of [`outgoing_momentum`] in u_k (n × m; zero without a discrete force), for an
/// input that depends on q_{k+1} (a simulation's implicit feedback).
pub fn outgoing_momentum_input_jacobian<M: MechanicsDerivatives>(
    mech: &M,
    q_curr: &[f64],
    q_next: &[f64],
    u_curr: &[f64],
    h_curr: f64,
) -> DMatrix<f64> {
    let (n, m) = (mech.nq(), mech.nu());
    if !mech.has_discrete_force() {
        return DMatrix::zeros(n, m);
    }
    let force = force_input(q_curr, q_next, u_curr, h_curr);
    jacobian(&HalfForce { mech }, &force)
        .1
        .columns(2 * n, m)
        .into_owned()
}
