//! The midpoint discrete Lagrangian Ld(qa, qb, h) = h·L((qa+qb)/2, (qb−qa)/h), its slot
//! derivatives, the discrete force, the DEL residual and the discrete Legendre transforms
//! (docs/reference-problems.md, with joint damping from its extension 2).

use super::{LdBuffers, midpoint_ld_gradient};
use crate::autodiff::Scalar;
use crate::autodiff::{ScalarFunction, VectorFunction};
use crate::model::{self, Model};

/// The midpoint rule's state on an interval: configuration (qa+qb)/2 and velocity (qb−qa)/h
/// (`qa`, `qb` length n, `h` in s). Every midpoint formula (Ld, Fd, their adjoint, the costs)
/// takes its state from here.
pub fn midpoint_state<D: Scalar>(qa: &[D], qb: &[D], h: D) -> (Vec<D>, Vec<D>) {
    let (mut q_mid, mut v_mid) = (Vec::with_capacity(qa.len()), Vec::with_capacity(qa.len()));
    midpoint_state_into(qa, qb, h, &mut q_mid, &mut v_mid);
    (q_mid, v_mid)
}

/// [`midpoint_state`] into `q_mid` and `v_mid` (cleared first; their allocations reused).
pub fn midpoint_state_into<D: Scalar>(
    qa: &[D],
    qb: &[D],
    h: D,
    q_mid: &mut Vec<D>,
    v_mid: &mut Vec<D>,
) {
    q_mid.clear();
    q_mid.extend(qa.iter().zip(qb).map(|(&a, &b)| (a + b) * 0.5));
    difference_velocity_into(qa, qb, h, v_mid);
}

/// The finite-difference velocity (qb−qa)/h between two knots h apart.
pub fn difference_velocity<D: Scalar>(qa: &[D], qb: &[D], h: D) -> Vec<D> {
    let mut v = Vec::with_capacity(qa.len());
    difference_velocity_into(qa, qb, h, &mut v);
    v
}

/// [`difference_velocity`] into `v` (cleared first).
fn difference_velocity_into<D: Scalar>(qa: &[D], qb: &[D], h: D, v: &mut Vec<D>) {
    v.clear();
    v.extend(qa.iter().zip(qb).map(|(&a, &b)| (b - a) / h));
}

/// Midpoint discrete Lagrangian Ld(qa, qb, h) = h·(T − V)((qa+qb)/2, (qb−qa)/h), in J·s.
///
/// `qa`, `qb`: configurations at the two knots (length `model.nq()`); `h`: step in s.
pub fn ld<D: Scalar>(model: &Model, qa: &[D], qb: &[D], h: D) -> D {
    let (q_mid, v_mid) = midpoint_state(qa, qb, h);
    h * (model::kinetic_energy(model, &q_mid, &v_mid) - model::potential_energy(model, &q_mid))
}

/// [D1Ld, D2Ld] at (qa, qb, h) by the adjoint sweep the NLP's DEL rows use
/// ([`midpoint_ld_gradient`]), generic over `D` so that it can itself be differentiated.
fn slot_derivatives<D: Scalar>(model: &Model, qa: &[D], qb: &[D], h: D) -> (Vec<D>, Vec<D>) {
    let (mut d1, mut d2) = (vec![D::zero(); qa.len()], vec![D::zero(); qa.len()]);
    midpoint_ld_gradient(
        model,
        qa,
        qb,
        h,
        &mut d1,
        &mut d2,
        &mut LdBuffers::default(),
    );
    (d1, d2)
}

/// D1Ld(qa, qb, h) = ∂Ld/∂qa (length `nq`, N·m·s per coordinate; the negative of the momentum
/// p⁺ at qa without forcing).
pub fn d1_ld<D: Scalar>(model: &Model, qa: &[D], qb: &[D], h: D) -> Vec<D> {
    slot_derivatives(model, qa, qb, h).0
}

/// D2Ld(qa, qb, h) = ∂Ld/∂qb (length `nq`; the momentum p⁻ at qb without forcing).
pub fn d2_ld<D: Scalar>(model: &Model, qa: &[D], qb: &[D], h: D) -> Vec<D> {
    slot_derivatives(model, qa, qb, h).1
}

/// Discrete force Fd(qa, qb, u, h) = h·B((qa+qb)/2)·u − diag(d)·(qb − qa), an impulse
/// (length `nq`); `u` has one entry per input of `model.input_coordinates()`, `d` is
/// `model.damping()`. Half of it enters the DEL row of each end knot.
pub fn discrete_force<D: Scalar>(model: &Model, qa: &[D], qb: &[D], u: &[D], h: D) -> Vec<D> {
    let (q_mid, _) = midpoint_state(qa, qb, h);
    let input = model::generalized_input_force(model, &q_mid, u);
    input
        .iter()
        .zip(model.damping())
        .zip(qa.iter().zip(qb))
        .map(|((&f, &d), (&a, &b))| f * h - (b - a) * d)
        .collect()
}

/// The configurations, steps and inputs around knot k that its DEL equation involves.
#[derive(Debug, Clone, Copy)]
pub struct KnotWindow<'a, D> {
    /// q_{k−1} (length `nq`).
    pub q_prev: &'a [D],
    /// q_k (length `nq`).
    pub q_curr: &'a [D],
    /// q_{k+1} (length `nq`).
    pub q_next: &'a [D],
    /// h_{k−1} = t_k − t_{k−1}, s.
    pub h_prev: D,
    /// h_k = t_{k+1} − t_k, s.
    pub h_curr: D,
    /// u_{k−1}, held over [t_{k−1}, t_k] (one entry per input).
    pub u_prev: &'a [D],
    /// u_k, held over [t_k, t_{k+1}] (one entry per input).
    pub u_curr: &'a [D],
}

/// DEL residual at knot k (length `nq`, impulse units):
/// D2Ld(q_{k−1}, q_k, h_{k−1}) + D1Ld(q_k, q_{k+1}, h_k) + ½Fd_{k−1} + ½Fd_k.
/// Contact (`+ J(q_{k+1})ᵀλ_k`) and loop impulses (`+ Gᵀ(q_{k+1})ν_k`) are added by the caller.
pub fn del_residual<D: Scalar>(model: &Model, w: &KnotWindow<'_, D>) -> Vec<D> {
    let p_minus = momentum_after(model, w.q_prev, w.q_curr, w.u_prev, w.h_prev);
    let p_plus = momentum_before(model, w.q_curr, w.q_next, w.u_curr, w.h_curr);
    p_minus.iter().zip(&p_plus).map(|(&a, &b)| a - b).collect()
}

/// Residual of the first step (length `nq`): M(q_1)v_0 + D1Ld(q_1, q_2, h_1) + ½Fd(q_1, q_2,
/// u_1, h_1), i.e. the momentum at the start minus the discrete momentum p_1⁺.
pub fn first_step_residual<D: Scalar>(
    model: &Model,
    q1: &[D],
    v0: &[D],
    q2: &[D],
    u1: &[D],
    h1: D,
) -> Vec<D> {
    let p0 = model::generalized_momentum(model, q1, v0);
    let p_plus = momentum_before(model, q1, q2, u1, h1);
    p0.iter().zip(&p_plus).map(|(&a, &b)| a - b).collect()
}

/// Discrete Legendre transform at the start of an interval: p_k⁺ = −D1Ld(q_k, q_{k+1}, h_k)
/// − ½Fd_k (length `nq`, generalized momentum in N·s or N·m·s).
pub fn momentum_before<D: Scalar>(model: &Model, qk: &[D], qk1: &[D], u: &[D], h: D) -> Vec<D> {
    let d1 = d1_ld(model, qk, qk1, h);
    let fd = discrete_force(model, qk, qk1, u, h);
    d1.iter().zip(&fd).map(|(&a, &f)| -a - f * 0.5).collect()
}

/// Discrete Legendre transform at the end of an interval: p_{k+1}⁻ = D2Ld(q_k, q_{k+1}, h_k)
/// + ½Fd_k (length `nq`).
pub fn momentum_after<D: Scalar>(model: &Model, qk: &[D], qk1: &[D], u: &[D], h: D) -> Vec<D> {
    let d2 = d2_ld(model, qk, qk1, h);
    let fd = discrete_force(model, qk, qk1, u, h);
    d2.iter().zip(&fd).map(|(&a, &f)| a + f * 0.5).collect()
}

/// Midpoint segment Ld(qa, qb, h) as a [`ScalarFunction`] of z = [qa; qb; h] (dim 2n+1).
///
/// Its gradient holds [D1Ld; D2Ld; ∂Ld/∂h]; its Hessian gives the DEL Jacobian blocks and its
/// contracted third derivative the DEL rows' share of the Lagrangian Hessian.
#[derive(Debug, Clone, Copy)]
pub struct MidpointSegment<'a> {
    /// The robot.
    pub model: &'a Model,
}

impl ScalarFunction for MidpointSegment<'_> {
    fn dim(&self) -> usize {
        2 * self.model.nq() + 1
    }
    fn eval<D: Scalar>(&self, z: &[D]) -> D {
        let n = self.model.nq();
        ld(self.model, &z[..n], &z[n..2 * n], z[2 * n])
    }
}

/// Discrete force Fd(qa, qb, u, h) as a [`VectorFunction`] of z = [qa; qb; u; h]
/// (dim 2n + m + 1, m = number of inputs) → R^n.
#[derive(Debug, Clone, Copy)]
pub struct DiscreteForce<'a> {
    /// The robot.
    pub model: &'a Model,
}

impl VectorFunction for DiscreteForce<'_> {
    fn dim_in(&self) -> usize {
        2 * self.model.nq() + self.model.input_coordinates().len() + 1
    }
    fn dim_out(&self) -> usize {
        self.model.nq()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        let n = self.model.nq();
        let m = self.model.input_coordinates().len();
        let f = discrete_force(
            self.model,
            &z[..n],
            &z[n..2 * n],
            &z[2 * n..2 * n + m],
            z[2 * n + m],
        );
        out.copy_from_slice(&f);
    }
}

/// First-step momentum M(q_1)·v_0 as a [`VectorFunction`] of z = [q1; v0] (dim 2n) → R^n.
#[derive(Debug, Clone, Copy)]
pub struct InitialMomentum<'a> {
    /// The robot.
    pub model: &'a Model,
}

impl VectorFunction for InitialMomentum<'_> {
    fn dim_in(&self) -> usize {
        2 * self.model.nq()
    }
    fn dim_out(&self) -> usize {
        self.model.nq()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        let n = self.model.nq();
        out.copy_from_slice(&model::generalized_momentum(self.model, &z[..n], &z[n..]));
    }
}

/// The whole midpoint DEL residual at a knot as a [`VectorFunction`] → R^n of
/// z = [q_{k−1}; q_k; q_{k+1}; h_{k−1}; h_k; u_{k−1}; u_k] (dim 3n + 2 + 2m).
///
/// The NLP assembles the same Jacobian from [`MidpointSegment`] and [`DiscreteForce`] blocks;
/// this one-piece form (forward duals through the same adjoint D1Ld, D2Ld) serves tests and
/// the forward step.
#[derive(Debug, Clone, Copy)]
pub struct MidpointKnotResidual<'a> {
    /// The robot.
    pub model: &'a Model,
}

impl VectorFunction for MidpointKnotResidual<'_> {
    fn dim_in(&self) -> usize {
        3 * self.model.nq() + 2 + 2 * self.model.input_coordinates().len()
    }
    fn dim_out(&self) -> usize {
        self.model.nq()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        let n = self.model.nq();
        let m = self.model.input_coordinates().len();
        let u0 = 3 * n + 2;
        let w = KnotWindow {
            q_prev: &z[..n],
            q_curr: &z[n..2 * n],
            q_next: &z[2 * n..3 * n],
            h_prev: z[3 * n],
            h_curr: z[3 * n + 1],
            u_prev: &z[u0..u0 + m],
            u_curr: &z[u0 + m..u0 + 2 * m],
        };
        out.copy_from_slice(&del_residual(self.model, &w));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{BaseType, sample};

    /// Simple pendulum (uniform rod, 1 kg, 1 m): I about the pivot = 1/3 kg·m², V = −m g (l/2) cos q.
    fn pendulum() -> (Model, f64) {
        let model = Model::from_urdf_str(&sample::pendulum(), BaseType::Fixed).expect("loads");
        let g = -model.gravity()[2];
        (model, g)
    }

    #[test]
    fn ld_matches_closed_form_for_pendulum() {
        let (model, g) = pendulum();
        let (qa, qb, h) = (0.3, 0.37, 0.02);
        let v = (qb - qa) / h;
        let q = 0.5 * (qa + qb);
        let expected = h * (0.5 / 3.0 * v * v + 0.5 * g * f64::cos(q));
        assert!((ld(&model, &[qa], &[qb], h) - expected).abs() < 1e-12);
        // D1Ld = −(I v) − (h/2)(m g l/2) sin q, D2Ld = (I v) − (h/2)(m g l/2) sin q.
        let d1 = d1_ld(&model, &[qa], &[qb], h)[0];
        let d2 = d2_ld(&model, &[qa], &[qb], h)[0];
        let gravity = 0.5 * h * 0.5 * g * f64::sin(q);
        assert!((d1 - (-v / 3.0 - gravity)).abs() < 1e-12);
        assert!((d2 - (v / 3.0 - gravity)).abs() < 1e-12);
    }

    #[test]
    fn discrete_force_is_input_impulse_minus_damping() {
        let xml = sample::pendulum().replace(
            "<axis xyz=\"0 1 0\"/>",
            "<axis xyz=\"0 1 0\"/>\n    <dynamics damping=\"0.4\"/>",
        );
        let model = Model::from_urdf_str(&xml, BaseType::Fixed).expect("loads");
        assert_eq!(model.input_coordinates(), &[0]);
        let (qa, qb, u, h) = (0.1, 0.15, 2.0, 0.05_f64);
        let fd = discrete_force(&model, &[qa], &[qb], &[u], h)[0];
        assert!((fd - (h * u - 0.4 * (qb - qa))).abs() < 1e-15);
        // The Legendre transforms split it in halves: p⁻ − p⁺ = D2Ld + D1Ld + Fd.
        let p_plus = momentum_before(&model, &[qa], &[qb], &[u], h)[0];
        let p_minus = momentum_after(&model, &[qa], &[qb], &[u], h)[0];
        let sum = d1_ld(&model, &[qa], &[qb], h)[0] + d2_ld(&model, &[qa], &[qb], h)[0];
        assert!((p_minus - p_plus - (sum + fd)).abs() < 1e-14);
    }
}
