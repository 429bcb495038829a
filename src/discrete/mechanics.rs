//! What the discrete equations need from a robot: its physics (sizes, the discrete Lagrangian
//! Ld, the discrete force Fd, the momentum, contact-point positions, loop closures, names and
//! limits), in its coordinate order.
//!
//! [`super::ModelMechanics`] implements it for a URDF [`crate::model::Model`]; tests implement
//! it in closed form for the reference hopper and brick. Every method is generic over [`Scalar`]
//! so that everything built on it is differentiated by forward AD; faster derivative paths are
//! the separate trait [`super::MechanicsDerivatives`].

use num_dual::Dual;

use super::difference_velocity;
use crate::autodiff::Scalar;

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
    /// Coordinate limits (lower, upper) from the model (URDF joint limits), length n; ±∞
    /// where none.
    fn coordinate_limits(&self) -> Vec<(f64, f64)> {
        vec![(f64::NEG_INFINITY, f64::INFINITY); self.nq()]
    }
    /// Coordinate names (length n), used in solutions.
    fn coordinate_names(&self) -> Vec<String> {
        (0..self.nq()).map(|i| format!("q{i}")).collect()
    }
    /// Input names (length m), used in solutions.
    fn input_names(&self) -> Vec<String> {
        (0..self.nu()).map(|i| format!("u{i}")).collect()
    }
    /// The robot's weight m·|g| (total mass times gravity, in the model's units), when
    /// known: the force unit of the NLP's scaling from units (`[solver] scaling`).
    fn weight(&self) -> Option<f64> {
        None
    }
    /// Whether the discrete force Fd can be nonzero (inputs or damping present).
    fn has_discrete_force(&self) -> bool;
    /// Whether every contact point stays in a plane y = const for every q, from the
    /// robot's structure (a planar model: friction along world x only).
    fn moves_in_xz_plane(&self) -> bool;

    /// Midpoint discrete Lagrangian Ld(qa, qb, h) = h·L((qa + qb)/2, (qb − qa)/h) of one
    /// interval (qa, qb length n; h > 0).
    fn discrete_lagrangian<D: Scalar>(&self, qa: &[D], qb: &[D], h: D) -> D;
    /// Midpoint discrete generalized force Fd(qa, qb, u, h) of one interval into `out`
    /// (length n): h·B(q̄)u − diag(d)(qb − qa), q̄ = (qa + qb)/2 (docs/reference-problems.md).
    fn discrete_force<D: Scalar>(&self, qa: &[D], qb: &[D], u: &[D], h: D, out: &mut [D]);
    /// Generalized momentum M(q)v into `out` (length n).
    fn momentum<D: Scalar>(&self, q: &[D], v: &[D], out: &mut [D]);
    /// World position of contact point `contact` at configuration q (length units).
    fn contact_position<D: Scalar>(&self, contact: usize, q: &[D]) -> [D; 3];
    /// World pose of link `link` (its index in the model's link order, `Model::link_names`)
    /// at configuration q: (rotation R, row-major, mapping link axes to world axes; the link
    /// origin in the world, length units). `None` for mechanics without links (closed-form
    /// test robots), the default.
    fn link_pose<D: Scalar>(&self, _link: usize, _q: &[D]) -> Option<([[D; 3]; 3], [D; 3])> {
        None
    }
    /// Whether contact `contact` is a sphere that rolls: friction acts at its lowest
    /// material point, which moves with [`Mechanics::contact_position`]'s point plus the
    /// spin term of [`Mechanics::contact_spin_columns`]. False for points (the default).
    fn contact_rolls(&self, _contact: usize) -> bool {
        false
    }
    /// Velocity of the contact's lowest material point relative to the point of
    /// [`Mechanics::contact_position`], per unit rate of the coordinates, as (coordinate,
    /// velocity) pairs to add up: r·ẑ × ∂ω/∂q̇ for a sphere of radius r on a link turning
    /// with ω (the material point at −r·ẑ from the centre moves with ω × (−r·ẑ)). Linear in
    /// q̇ but, unlike the point's velocity, not the rate of a function of q: friction along
    /// it is a generalized force Dᵀβ that is no gradient. Empty for contacts that do not roll.
    fn contact_spin_columns<D: Scalar>(&self, _contact: usize, _q: &[D]) -> Vec<(usize, [D; 3])> {
        Vec::new()
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
        let v = difference_velocity(q_k, q_next, h);
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
