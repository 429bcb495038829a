//! Solvers of one step's nonlinear complementarity problem (NCP): unknowns x, equations
//! F(x) = 0 on the free unknowns, and pairs 0 ≤ z_i ⊥ w_i(x) ≥ 0 on the complementary ones,
//! each pair written as a smoothed Fischer–Burmeister equation Φ_ε(z_i, w_i(x)) = 0.
//!
//! The solvers see the problem only through [`SmoothedSystem`] (its residual and Jacobian at a
//! smoothing ε) and, for the pivoting method, [`LinearisedComplementarity`]; the contact step
//! (`super::step`) is one such problem, the unit tests' hand-solvable LCPs and blocks others.
//!
//! One file per strategy: `fischer_burmeister` (Φ_ε and Newton's method with smoothing
//! continuation), `armijo` (the backtracking line search on ½‖Φ_ε‖²), `levenberg_marquardt`
//! (regularised steps where Newton's are cut short), `path_following` (ε from far inside down
//! to the floor), `josephy_newton` (linearisations solved exactly by `lemke`).

mod armijo;
mod fischer_burmeister;
mod josephy_newton;
mod lemke;
mod levenberg_marquardt;
mod path_following;
#[cfg(test)]
mod test_problems;

pub(super) use fischer_burmeister::{Damping, fischer_burmeister, newton};
pub(super) use josephy_newton::josephy_newton;
pub(super) use path_following::path_following;

use nalgebra::{DMatrix, DVector};

/// Why a step failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum StepFailure {
    /// A value became NaN or infinite.
    #[error("non-finite residual at Newton iteration {iteration}; reduce the time step")]
    NonFinite {
        /// Newton iteration.
        iteration: usize,
    },
    /// The Newton matrix could not be factorised.
    #[error("singular Newton matrix at iteration {iteration}")]
    Singular {
        /// Newton iteration.
        iteration: usize,
    },
    /// Newton did not reach the tolerance.
    #[error(
        "the contact problem did not converge in {iterations} Newton iterations (residual {residual:.3e}, tolerance {tolerance:.3e}); reduce the time step"
    )]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// Final max-norm residual (impulse units).
        residual: f64,
        /// The tolerance.
        tolerance: f64,
    },
    /// The interior points of the Galerkin interval before the knot were not solved.
    #[error("the interior points of the interval before the step: {0}")]
    Interval(crate::discrete::StepError),
    /// The step's `before` is not what its integrator's knot equation takes: the incoming
    /// momentum for the variational integrators, v_k or the previous configuration for Euler.
    #[error(
        "the step's `before` does not match its integrator `{integrator}`: give Before::{expected}"
    )]
    IntegratorMismatch {
        /// The step's integrator.
        integrator: &'static str,
        /// The `Before` variant that integrator takes.
        expected: &'static str,
    },
}

/// The smoothed system's residual Φ_ε(x), its Jacobian, and its unsmoothed size at a point.
pub(super) struct Evaluation {
    /// Φ_ε(x).
    pub residual: DVector<f64>,
    /// ∂Φ_ε/∂x (zeros when not asked for).
    pub jacobian: DMatrix<f64>,
    /// Max-norm of the unsmoothed residual Φ_0(x): what the tolerance is on.
    pub plain: f64,
}

/// An NCP as its smoothed Fischer–Burmeister system.
pub(super) trait SmoothedSystem {
    /// Residual at x with smoothing ε; the Jacobian only when `with_jacobian` (zeros
    /// otherwise: line-search trials need values alone).
    fn evaluate(&self, x: &[f64], eps: f64, with_jacobian: bool) -> Evaluation;
}

/// An NCP whose complementary functions w(x) can be linearised around x for the pivoting
/// method ([`josephy_newton`]).
pub(super) trait LinearisedComplementarity: SmoothedSystem {
    /// The free unknowns (those of the equations F) and the complementary unknowns z (the
    /// LCP's), in the order of their rows and pairs; unknowns in neither are held.
    fn split(&self) -> (Vec<usize>, Vec<usize>);

    /// The LCP (M, q) of w linearised at x, with the free unknowns' step Δx_F = a + B z
    /// (from the linearised equations): w ≈ M z + q.
    fn linearised(
        &self,
        x: &[f64],
        a: &DVector<f64>,
        b: &DMatrix<f64>,
    ) -> (DMatrix<f64>, DVector<f64>);
}

/// What a solver stops at: the tolerance on [`Evaluation::plain`] and the iterations allowed
/// per Newton run.
#[derive(Debug, Clone, Copy)]
pub(super) struct Limits {
    /// Tolerance on the unsmoothed residual's max-norm.
    pub tolerance: f64,
    /// Newton iterations before a run fails.
    pub max_iterations: usize,
}
