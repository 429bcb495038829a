//! Small complementarity problems with known solutions, for the solvers' unit tests: linear
//! mixed complementarity problems (equations A x + f = 0 on the free unknowns, pairs
//! 0 ≤ x_p ⊥ (W x + w₀)_p ≥ 0 on the others), among them LCPs, a box on the ground and a
//! block sliding with Coulomb friction over one time step.

use nalgebra::{DMatrix, DVector};

use super::fischer_burmeister::fischer_burmeister;
use super::{Evaluation, Limits, LinearisedComplementarity, SmoothedSystem};

/// What the tests ask of every solver.
pub(super) const LIMITS: Limits = Limits {
    tolerance: 1e-12,
    max_iterations: 60,
};

/// Gravity, time step and friction coefficient of the block problems.
const G: f64 = 9.81;
const H: f64 = 0.01;
const MU: f64 = 0.5;

/// A linear mixed complementarity problem; the free unknowns come first, then the paired
/// ones, so that row i of the system belongs to unknown i (as in the contact step).
pub(super) struct Mcp {
    /// Free unknowns 0..nf.
    nf: usize,
    a: DMatrix<f64>,
    f: DVector<f64>,
    w: DMatrix<f64>,
    w0: DVector<f64>,
    /// The sliding block's initial speed (0 for the others).
    speed: f64,
}

/// Asserts |x − expected| ≤ tol (1 + |expected|) entrywise.
pub(super) fn close(x: &[f64], expected: &[f64], tol: f64) {
    assert_eq!(x.len(), expected.len());
    for (i, (a, b)) in x.iter().zip(expected).enumerate() {
        assert!(
            (a - b).abs() <= tol * (1.0 + b.abs()),
            "entry {i}: {a} vs {b} (all: {x:?} vs {expected:?})"
        );
    }
}

impl Mcp {
    /// The LCP 0 ≤ z ⊥ M z + q ≥ 0 (M by rows).
    pub(super) fn lcp(m: &[&[f64]], q: &[f64]) -> Mcp {
        let n = q.len();
        Mcp {
            nf: 0,
            a: DMatrix::zeros(0, n),
            f: DVector::zeros(0),
            w: DMatrix::from_fn(n, n, |r, c| m[r][c]),
            w0: DVector::from_column_slice(q),
            speed: 0.0,
        }
    }

    /// A box of mass 2 at rest at height `y0` over one step: unknowns [y, c], momentum
    /// m((y − y0)/h) + m g h − c = 0, and 0 ≤ c ⊥ (m/h) y ≥ 0 (the gap in impulse units).
    pub(super) fn falling_box(y0: f64) -> Mcp {
        let m = 2.0;
        Mcp {
            nf: 1,
            a: DMatrix::from_row_slice(1, 2, &[m / H, -1.0]),
            f: DVector::from_element(1, -m * y0 / H + m * G * H),
            w: DMatrix::from_row_slice(1, 2, &[m / H, 0.0]),
            w0: DVector::zeros(1),
            speed: 0.0,
        }
    }

    /// A unit mass on the ground moving along x at `speed` over one step: unknowns
    /// [x, y, c, β⁺, β⁻, ψ] with x_0 = y_0 = 0, momentum (x/h − speed) − (β⁺ − β⁻) = 0 and
    /// y/h + g h − c = 0; 0 ≤ c ⊥ y/h, 0 ≤ β^± ⊥ ±x/h + ψ, 0 ≤ ψ ⊥ μc − β⁺ − β⁻.
    pub(super) fn sliding_block(speed: f64) -> Mcp {
        let a = DMatrix::from_row_slice(
            2,
            6,
            &[
                1.0 / H,
                0.0,
                0.0,
                -1.0,
                1.0,
                0.0, //
                0.0,
                1.0 / H,
                -1.0,
                0.0,
                0.0,
                0.0,
            ],
        );
        let w = DMatrix::from_row_slice(
            4,
            6,
            &[
                0.0,
                1.0 / H,
                0.0,
                0.0,
                0.0,
                0.0, //
                1.0 / H,
                0.0,
                0.0,
                0.0,
                0.0,
                1.0, //
                -1.0 / H,
                0.0,
                0.0,
                0.0,
                0.0,
                1.0, //
                0.0,
                0.0,
                MU,
                -1.0,
                -1.0,
                0.0,
            ],
        );
        Mcp {
            nf: 2,
            a,
            f: DVector::from_column_slice(&[-speed, G * H]),
            w,
            w0: DVector::zeros(4),
            speed,
        }
    }

    /// The contact step's kind of guess: the block moved on at its speed, no impulses.
    pub(super) fn guess(&self) -> Vec<f64> {
        let mut x = vec![0.0; self.a.ncols()];
        x[0] = H * self.speed;
        x
    }

    /// The sliding block's solution while it keeps sliding (speed > μ g h): decelerated by
    /// μ g over the step, the ground carrying its weight, friction at the cone's edge.
    pub(super) fn sliding_solution(&self) -> Vec<f64> {
        let v = self.speed - MU * G * H;
        assert!(v > 0.0, "the block stops within the step");
        let c = G * H;
        vec![H * v, 0.0, c, 0.0, MU * c, v]
    }

    /// Asserts that x is a solution of the sliding block where it stops within the step
    /// (speed < μ g h): no motion, the weight on the ground, static friction taking the
    /// momentum inside the cone. The split of the friction between β⁺ and β⁻ is not unique
    /// (both rates are zero), their difference is.
    pub(super) fn assert_sticks(&self, x: &[f64], tol: f64) {
        assert!(self.speed < MU * G * H, "the block keeps sliding");
        let c = G * H;
        close(&[x[0], x[1], x[2], x[5]], &[0.0, 0.0, c, 0.0], tol);
        close(&[x[4] - x[3]], &[self.speed], tol);
        assert!(x[3] >= -tol && MU * c - x[3] - x[4] >= -tol, "{x:?}");
    }

    fn pairs(&self) -> std::ops::Range<usize> {
        self.nf..self.a.ncols()
    }
}

impl SmoothedSystem for Mcp {
    fn evaluate(&self, x: &[f64], eps: f64, with_jacobian: bool) -> Evaluation {
        let (dim, nf) = (self.a.ncols(), self.nf);
        let xv = DVector::from_column_slice(x);
        let equations = &self.a * &xv + &self.f;
        let w = &self.w * &xv + &self.w0;
        let mut residual = DVector::zeros(dim);
        let mut jacobian = DMatrix::zeros(dim, dim);
        let mut plain = equations.amax();
        residual.rows_mut(0, nf).copy_from(&equations);
        if with_jacobian {
            jacobian.rows_mut(0, nf).copy_from(&self.a);
        }
        for (k, p) in self.pairs().enumerate() {
            let (value, da, db) = fischer_burmeister(x[p], w[k], eps);
            residual[p] = value;
            plain = plain.max(fischer_burmeister(x[p], w[k], 0.0).0.abs());
            if with_jacobian {
                let mut row = jacobian.row_mut(p);
                row += self.w.row(k) * db;
                row[p] += da;
            }
        }
        Evaluation {
            residual,
            jacobian,
            plain,
        }
    }
}

impl LinearisedComplementarity for Mcp {
    fn split(&self) -> (Vec<usize>, Vec<usize>) {
        ((0..self.nf).collect(), self.pairs().collect())
    }

    fn linearised(
        &self,
        x: &[f64],
        a: &DVector<f64>,
        b: &DMatrix<f64>,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let (nf, np) = (self.nf, self.w.nrows());
        let w_f = self.w.columns(0, nf);
        let w_z = self.w.columns(nf, np);
        let z_x = DVector::from_column_slice(&x[nf..]);
        let w = &self.w * DVector::from_column_slice(x) + &self.w0;
        (w_f * b + w_z, w + w_f * a - w_z * z_x)
    }
}
