//! Closed-form mechanics of the reference hopper-2d and brick-3d, written straight from docs/reference-problems.md
//! (not through the URDF model), so the transcription is tested on its own.

use num_dual::Dual;
use vito::autodiff::Scalar;
use vito::discrete::{Mechanics, MechanicsDerivatives};

const G: f64 = 9.81;

/// ∂T/∂v (= M(q)v for a quadratic T) by one forward dual per component.
fn momentum_of<D: Scalar>(
    kinetic: impl Fn(&[Dual<D>], &[Dual<D>]) -> Dual<D>,
    q: &[D],
    v: &[D],
    out: &mut [D],
) {
    let qd: Vec<Dual<D>> = q.iter().map(|&x| Dual::from_re(x)).collect();
    for (i, o) in out.iter_mut().enumerate().take(q.len()) {
        let vd: Vec<Dual<D>> = v
            .iter()
            .enumerate()
            .map(|(k, &x)| Dual::new(x, if k == i { D::from(1.0) } else { D::from(0.0) }))
            .collect();
        *o = kinetic(&qd, &vd).eps;
    }
}

/// Ld for the midpoint rule: h·L(q̄, (qb−qa)/h). (The Euler residual is the trait's
/// default, built from this Ld, the momentum and Fd.)
fn discrete_lagrangian<D: Scalar>(
    lagrangian: impl Fn(&[D], &[D]) -> D,
    qa: &[D],
    qb: &[D],
    h: D,
) -> D {
    let v: Vec<D> = qa.iter().zip(qb).map(|(&a, &b)| (b - a) / h).collect();
    let q: Vec<D> = qa
        .iter()
        .zip(qb)
        .map(|(&a, &b)| (a + b) * D::from(0.5))
        .collect();
    lagrangian(&q, &v) * h
}

/// The reference hopper: q = [x, z, θ, r], u = [τ, f].
pub struct Hopper;

impl Hopper {
    fn foot<D: Scalar>(q: &[D]) -> [D; 2] {
        [q[0] + q[3] * q[2].sin(), q[1] - q[3] * q[2].cos()]
    }
    fn kinetic<D: Scalar>(q: &[D], v: &[D]) -> D {
        let (s, c) = (q[2].sin(), q[2].cos());
        let px = v[0] + v[3] * s + q[3] * c * v[2];
        let pz = v[1] - v[3] * c + q[3] * s * v[2];
        (v[0] * v[0] + v[1] * v[1]) * D::from(1.5)
            + (px * px + pz * pz) * D::from(0.15)
            + v[2] * v[2] * D::from(0.5 * 0.825)
    }
    fn lagrangian<D: Scalar>(q: &[D], v: &[D]) -> D {
        Self::kinetic(q, v) - (q[1] * D::from(3.0) + Self::foot(q)[1] * D::from(0.3)) * D::from(G)
    }
}

impl Mechanics for Hopper {
    fn nq(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        2
    }
    fn num_contacts(&self) -> usize {
        1
    }
    fn coordinate_limits(&self) -> Vec<(f64, f64)> {
        let mut l = vec![(f64::NEG_INFINITY, f64::INFINITY); 4];
        l[3] = (0.3, 0.7);
        l
    }
    fn has_discrete_force(&self) -> bool {
        true
    }
    fn moves_in_xz_plane(&self) -> bool {
        // Slides along x and z, a leg turning about y: the reference planar hopper.
        true
    }
    fn discrete_lagrangian<D: Scalar>(&self, qa: &[D], qb: &[D], h: D) -> D {
        discrete_lagrangian(Self::lagrangian, qa, qb, h)
    }
    fn discrete_force<D: Scalar>(&self, _qa: &[D], _qb: &[D], u: &[D], h: D, out: &mut [D]) {
        out[0] = D::from(0.0);
        out[1] = D::from(0.0);
        out[2] = h * u[0];
        out[3] = h * u[1];
    }
    fn momentum<D: Scalar>(&self, q: &[D], v: &[D], out: &mut [D]) {
        momentum_of(Self::kinetic, q, v, out)
    }
    fn contact_position<D: Scalar>(&self, _contact: usize, q: &[D]) -> [D; 3] {
        let p = Self::foot(q);
        [p[0], D::from(0.0), p[1]]
    }
}

/// The reference brick: q = [x, y, z, roll, pitch, yaw], R = Rz·Ry·Rx, 8 corners.
pub struct Brick;

pub const BRICK_SIZE: [f64; 3] = [0.2, 0.1, 0.05];

impl Brick {
    /// Corners in the order of brick.urdf: ppp, ppm, pmp, pmm, mpp, mpm, mmp, mmm.
    pub fn corner(i: usize) -> [f64; 3] {
        let sign = |bit: usize| if i & bit == 0 { 1.0 } else { -1.0 };
        [
            sign(4) * BRICK_SIZE[0] / 2.0,
            sign(2) * BRICK_SIZE[1] / 2.0,
            sign(1) * BRICK_SIZE[2] / 2.0,
        ]
    }
    fn rotation<D: Scalar>(q: &[D]) -> [[D; 3]; 3] {
        let (sr, cr) = (q[3].sin(), q[3].cos());
        let (sp, cp) = (q[4].sin(), q[4].cos());
        let (sy, cy) = (q[5].sin(), q[5].cos());
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    }
    fn kinetic<D: Scalar>(q: &[D], v: &[D]) -> D {
        let (sr, cr) = (q[3].sin(), q[3].cos());
        let (sp, cp) = (q[4].sin(), q[4].cos());
        let w = [
            v[3] - v[5] * sp,
            v[4] * cr + v[5] * cp * sr,
            -v[4] * sr + v[5] * cp * cr,
        ];
        let [a, b, c] = BRICK_SIZE;
        let inertia = [
            (b * b + c * c) / 12.0,
            (a * a + c * c) / 12.0,
            (a * a + b * b) / 12.0,
        ];
        let mut t = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * D::from(0.5);
        for k in 0..3 {
            t += w[k] * w[k] * D::from(0.5 * inertia[k]);
        }
        t
    }
    fn lagrangian<D: Scalar>(q: &[D], v: &[D]) -> D {
        Self::kinetic(q, v) - q[2] * D::from(G)
    }
}

/// Every derivative by forward AD (the defaults).
impl MechanicsDerivatives for Hopper {}

impl Mechanics for Brick {
    fn nq(&self) -> usize {
        6
    }
    fn nu(&self) -> usize {
        0
    }
    fn num_contacts(&self) -> usize {
        8
    }
    fn has_discrete_force(&self) -> bool {
        false
    }
    fn moves_in_xz_plane(&self) -> bool {
        false
    }
    fn discrete_lagrangian<D: Scalar>(&self, qa: &[D], qb: &[D], h: D) -> D {
        discrete_lagrangian(Self::lagrangian, qa, qb, h)
    }
    fn discrete_force<D: Scalar>(&self, _: &[D], _: &[D], _: &[D], _: D, out: &mut [D]) {
        out.fill(D::from(0.0));
    }
    fn momentum<D: Scalar>(&self, q: &[D], v: &[D], out: &mut [D]) {
        momentum_of(Self::kinetic, q, v, out)
    }
    fn contact_position<D: Scalar>(&self, contact: usize, q: &[D]) -> [D; 3] {
        let r = Self::rotation(q);
        let p = Self::corner(contact);
        let mut w = [q[0], q[1], q[2]];
        for (i, wi) in w.iter_mut().enumerate() {
            for (j, &pj) in p.iter().enumerate() {
                *wi += r[i][j] * D::from(pj);
            }
        }
        w
    }
}

/// Every derivative by forward AD (the defaults).
impl MechanicsDerivatives for Brick {}
