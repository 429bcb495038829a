//! Levenberg–Marquardt steps on the merit ½‖Φ_ε‖², where Newton's steps are cut short.

use super::armijo::armijo;
use super::{Evaluation, SmoothedSystem};

/// A Levenberg–Marquardt step on ½‖Φ_ε‖² from x (evaluated with its Jacobian as `e`, merit
/// `merit`): (JᵀJ + λ diag(JᵀJ)) d = −JᵀΦ with λ the residual relative to the step's momentum
/// scale `momentum` (×10 while the line search still cuts the step short, up to λ = 1).
///
/// Why: redundant contacts (the toe and heel of Spring Flamingo's flat feet, both
/// sticking) give Newton's matrix singular values of 1e-7–1e-10 against 3e4; Newton's
/// directions then run along the undetermined directions (|d| ≫ 1) and the line search
/// takes steps of 1e-6 (Spring Flamingo tracking its 30-knot plan with kd = 1 stalled at
/// step 0 with a residual of 2.4e-5). The regularised direction is a descent direction of
/// bounded length; there it reaches 3.6e-7 (the normal rows of the two feet, φ = ±1.9e-9 m
/// in opposite signs: the all-stick mode is inconsistent at second order). Used only after
/// the other attempts fail: as the first choice it led LittleDog's tracking to worse
/// stalls.
pub(super) fn levenberg_marquardt<S: SmoothedSystem>(
    system: &S,
    x: &[f64],
    e: &Evaluation,
    merit: f64,
    eps: f64,
    momentum: f64,
) -> Option<(Vec<f64>, f64, Evaluation)> {
    let normal = e.jacobian.tr_mul(&e.jacobian);
    let gradient = e.jacobian.tr_mul(&e.residual);
    let floor = normal.diagonal().amax() * f64::EPSILON;
    let mut lambda = (e.residual.amax() / momentum.max(f64::MIN_POSITIVE)).min(1.0);
    let mut best = None;
    while lambda <= 1.0 {
        let mut system_matrix = normal.clone();
        for r in 0..system_matrix.nrows() {
            system_matrix[(r, r)] += lambda * normal[(r, r)].max(floor);
        }
        let direction = system_matrix.cholesky()?.solve(&(-&gradient));
        if let Some(found) = armijo(system, x, &direction, merit, eps, 30) {
            let long = found.1 >= 1e-2;
            best = Some(found);
            if long {
                break;
            }
        }
        lambda *= 10.0;
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::ncp::fischer_burmeister::{Damping, newton};
    use crate::sim::ncp::test_problems::{LIMITS, Mcp, close};

    fn merit_at(system: &Mcp, x: &[f64], eps: f64) -> (Evaluation, f64) {
        let e = system.evaluate(x, eps, true);
        let merit = 0.5 * e.residual.norm_squared();
        (e, merit)
    }

    #[test]
    fn a_step_decreases_the_merit_of_a_two_dimensional_lcp() {
        let system = Mcp::lcp(&[&[2.0, 1.0], &[1.0, 2.0]], &[-5.0, -6.0]);
        let x = [0.0, 0.0];
        let (e, merit) = merit_at(&system, &x, 0.0);
        let (found, t, trial) =
            levenberg_marquardt(&system, &x, &e, merit, 0.0, 1.0).expect("descends");
        let value = 0.5 * trial.residual.norm_squared();
        assert!(
            t > 0.0 && value <= (1.0 - 1e-4 * t) * merit,
            "{value} vs {merit}"
        );
        // The regularised direction points towards the solution (4/3, 7/3).
        assert!(found[0] > 0.0 && found[1] > 0.0, "{found:?}");
    }

    #[test]
    fn small_regularisation_gives_newtons_step_on_a_linear_problem() {
        // Far from the kinks of the falling box's pair, Φ is nearly linear and λ ≈ 0: the
        // Levenberg–Marquardt step lands near the Newton solution of the flight mode.
        let system = Mcp::falling_box(1.0);
        let x = [1.0, 0.0];
        let (e, merit) = merit_at(&system, &x, 0.0);
        let (found, t, _) =
            levenberg_marquardt(&system, &x, &e, merit, 0.0, 1e12).expect("descends");
        assert_eq!(t, 1.0);
        close(&found, &[1.0 - 9.81e-4, 0.0], 1e-6);
    }

    #[test]
    fn newton_with_levenberg_marquardt_damping_solves_the_sliding_block() {
        let block = Mcp::sliding_block(1.0);
        let damping = Damping::LevenbergMarquardt { momentum: 1.0 };
        let (x, _) = newton(&block, block.guess(), LIMITS, damping).expect("solves");
        close(&x, &block.sliding_solution(), 1e-10);
    }
}
