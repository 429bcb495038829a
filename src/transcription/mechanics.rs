//! What the transcription needs from a robot: discrete mechanics and contact-point positions.
//!
//! The NLP is written once against this trait; [`crate::transcription::solve`] implements it
//! for a URDF [`crate::model::Model`] through [`crate::discrete`], and tests implement it in
//! closed form for SPEC.md's hopper and brick. Every method is generic over
//! [`Scalar`] so that the blocks built on it are differentiated by forward AD.

use nalgebra::DMatrix;
use num_dual::Dual;

use crate::autodiff::{
    ScalarFunction, ThirdOrder, VectorFunction, gradient_hessian_third, jacobian, weighted_hessian,
};
use crate::model::PointJet;
use crate::problem::Interval;
use crate::scalar::Scalar;

/// Discrete mechanics and contact kinematics of one robot, in its coordinate order.
pub trait Mechanics: Sync {
    /// Number of generalized coordinates n.
    fn nq(&self) -> usize;
    /// Number of inputs m.
    fn nu(&self) -> usize;
    /// Number of holonomic loop-closure constraints (0 for trees).
    fn num_loop_constraints(&self) -> usize {
        0
    }
    /// Number of contact points (in the problem's contact order).
    fn num_contacts(&self) -> usize;
    /// Coordinate limits from the model (URDF joint limits), length n; ±∞ where none.
    fn coordinate_limits(&self) -> Vec<Interval> {
        vec![Interval::FREE; self.nq()]
    }
    /// Coordinate names (length n), used in solutions.
    fn coordinate_names(&self) -> Vec<String> {
        (0..self.nq()).map(|i| format!("q{i}")).collect()
    }
    /// Input names (length m), used in solutions.
    fn input_names(&self) -> Vec<String> {
        (0..self.nu()).map(|i| format!("u{i}")).collect()
    }
    /// Whether the discrete force Fd can be nonzero (inputs or damping present).
    fn has_discrete_force(&self) -> bool;

    /// Midpoint discrete Lagrangian Ld(qa, qb, h) = h·L((qa + qb)/2, (qb − qa)/h) of one
    /// interval (qa, qb length n; h > 0).
    fn discrete_lagrangian<D: Scalar>(&self, qa: &[D], qb: &[D], h: D) -> D;
    /// Midpoint discrete generalized force Fd(qa, qb, u, h) of one interval into `out`
    /// (length n): h·B(q̄)u − diag(d)(qb − qa), q̄ = (qa + qb)/2 (SPEC.md).
    fn discrete_force<D: Scalar>(&self, qa: &[D], qb: &[D], u: &[D], h: D, out: &mut [D]);
    /// Generalized momentum M(q)v into `out` (length n).
    fn momentum<D: Scalar>(&self, q: &[D], v: &[D], out: &mut [D]);
    /// World position of contact point `contact` at configuration q (length units).
    fn contact_position<D: Scalar>(&self, contact: usize, q: &[D]) -> [D; 3];
    /// World position of contact point `contact` at q and its derivatives in q up to `order`
    /// (1 to 3). The default differentiates [`Mechanics::contact_position`] by forward AD over
    /// all n coordinates ([`contact_jet_by_autodiff`]); the URDF model overrides it with the
    /// chain formulas of [`crate::model::point_jet`].
    fn contact_jet(&self, contact: usize, q: &[f64], order: usize) -> PointJet
    where
        Self: Sized,
    {
        contact_jet_by_autodiff(self, contact, q, order)
    }
    /// Gradient of Ld at z = [qa; qb; h] (length 2n + 1: D1Ld, D2Ld, ∂Ld/∂h) by a faster path
    /// than generic AD (e.g. the model's adjoint), or `None` to use forward AD.
    fn segment_gradient(&self, _z: &[f64]) -> Option<Vec<f64>> {
        None
    }
    /// Gradient and Hessian of Ld at z = [qa; qb; h] by a faster path than generic AD
    /// (e.g. the model's adjoint), or `None` to use forward AD on `discrete_lagrangian`.
    fn segment_gradient_hessian(&self, _z: &[f64]) -> Option<(Vec<f64>, DMatrix<f64>)> {
        None
    }
    /// Value, gradient, Hessian and third derivative of Ld contracted with `dir` at
    /// z = [qa; qb; h] by a faster path than generic AD, or `None`. With `columns`, only
    /// entries between marked inputs need be exact (the others belong to fixed variables).
    fn segment_third_order(
        &self,
        _z: &[f64],
        _dir: &[f64],
        _columns: Option<&[bool]>,
    ) -> Option<ThirdOrder> {
        None
    }
    /// Semi-implicit Euler residual at knot k (eq. 1 of the paper; Posa et al. 2014) into
    /// `out` (length n, impulse units, sign as the DEL rows: momentum before − momentum
    /// after + impulses): M(q_k)(v_k − v⁺) + h·(B(q_k)u − C(q_k, v⁺)v⁺ − ∂V/∂q(q_k)
    /// − diag(d)v⁺), with v⁺ = (q_next − q_k)/h. `v_k` is the velocity at knot k (v_0, or
    /// (q_k − q_{k−1})/h_{k−1}); `u` has length m.
    ///
    /// The default builds it from the other methods: with v = v⁺, the continuous
    /// Lagrangian is L(q, v) = Ld(q − hv/2, q + hv/2, h)/h exactly for the midpoint rule,
    /// h·(B(q_k)u − diag(d)v) = Fd(q_k − hv/2, q_k + hv/2, u, h), and
    /// C(q, v)v + ∂V/∂q = (∂(M(q)v)/∂q)·v − ∂L/∂q (T quadratic in v, so M(q)v = ∂L/∂v).
    fn euler_residual<D: Scalar>(
        &self,
        v_k: &[D],
        q_k: &[D],
        q_next: &[D],
        h: D,
        u: &[D],
        out: &mut [D],
    ) {
        let n = q_k.len();
        let v: Vec<D> = q_k.iter().zip(q_next).map(|(&a, &b)| (b - a) / h).collect();
        let half: Vec<D> = v.iter().map(|&vi| vi * h * D::from(0.5)).collect();
        let qa: Vec<D> = q_k.iter().zip(&half).map(|(&q, &d)| q - d).collect();
        let qb: Vec<D> = q_k.iter().zip(&half).map(|(&q, &d)| q + d).collect();
        self.discrete_force(&qa, &qb, u, h, out);
        // M(q_k)(v_k − v⁺).
        let jump: Vec<D> = v_k.iter().zip(&v).map(|(&a, &b)| a - b).collect();
        let mut momentum = vec![D::from(0.0); n];
        self.momentum(q_k, &jump, &mut momentum);
        // (∂(M(q)v)/∂q)·v: the momentum at q_k moving with v, one directional derivative.
        let q_moving: Vec<Dual<D>> = q_k
            .iter()
            .zip(&v)
            .map(|(&q, &vi)| Dual::new(q, vi))
            .collect();
        let v_dual: Vec<Dual<D>> = v.iter().map(|&vi| Dual::from_re(vi)).collect();
        let mut momentum_rate = vec![Dual::from_re(D::from(0.0)); n];
        self.momentum(&q_moving, &v_dual, &mut momentum_rate);
        let h_dual = Dual::from_re(h);
        for i in 0..n {
            // h·∂L/∂q_i = ∂Ld/∂q_i with both segment ends shifted together.
            let shift = |q: &[D]| -> Vec<Dual<D>> {
                q.iter()
                    .enumerate()
                    .map(|(k, &x)| Dual::new(x, D::from(if k == i { 1.0 } else { 0.0 })))
                    .collect()
            };
            let dl_dq = self
                .discrete_lagrangian(&shift(&qa), &shift(&qb), h_dual)
                .eps;
            out[i] += momentum[i] - momentum_rate[i].eps * h + dl_dq;
        }
    }
    /// Loop-closure residual a(q) into `out` (length `num_loop_constraints`).
    fn loop_residual<D: Scalar>(&self, _q: &[D], _out: &mut [D]) {}
}

/// The contact point's position as an AD-able function of q (all three components, or the
/// one `component`).
struct ContactPositionFn<'a, M> {
    mech: &'a M,
    contact: usize,
    component: usize,
}

impl<M: Mechanics> VectorFunction for ContactPositionFn<'_, M> {
    fn dim_in(&self) -> usize {
        self.mech.nq()
    }
    fn dim_out(&self) -> usize {
        3
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        out.copy_from_slice(&self.mech.contact_position(self.contact, z));
    }
}

impl<M: Mechanics> ScalarFunction for ContactPositionFn<'_, M> {
    fn dim(&self) -> usize {
        self.mech.nq()
    }
    fn eval<D: Scalar>(&self, z: &[D]) -> D {
        self.mech.contact_position(self.contact, z)[self.component]
    }
}

/// [`Mechanics::contact_jet`] by forward AD through [`Mechanics::contact_position`], over all
/// n coordinates (the third order costs 3n passes: meant for small closed-form mechanics and
/// as the reference the analytic jets are tested against).
pub fn contact_jet_by_autodiff<M: Mechanics + Sized>(
    mech: &M,
    contact: usize,
    q: &[f64],
    order: usize,
) -> PointJet {
    let n = q.len();
    let f = |component| ContactPositionFn {
        mech,
        contact,
        component,
    };
    let (position, jac) = jacobian(&f(0), q);
    let mut jet = PointJet {
        coords: (0..n).collect(),
        position: [position[0], position[1], position[2]],
        first: (0..n)
            .map(|a| [jac[(0, a)], jac[(1, a)], jac[(2, a)]])
            .collect(),
        second: Vec::new(),
        third: Vec::new(),
    };
    if order >= 2 {
        jet.second = vec![[0.0; 3]; n * n];
        for m in 0..3 {
            let mut w = [0.0; 3];
            w[m] = 1.0;
            let h = weighted_hessian(&f(0), q, &w);
            for (entry, value) in jet.second.iter_mut().zip(h.iter()) {
                entry[m] = *value;
            }
        }
    }
    if order >= 3 {
        jet.third = vec![[0.0; 3]; n * n * n];
        for e in 0..n {
            let mut dir = vec![0.0; n];
            dir[e] = 1.0;
            for m in 0..3 {
                let t = gradient_hessian_third(&f(m), q, &dir).contracted;
                for a in 0..n {
                    for b in 0..n {
                        jet.third[(a * n + b) * n + e][m] = t[(a, b)];
                    }
                }
            }
        }
    }
    jet
}
