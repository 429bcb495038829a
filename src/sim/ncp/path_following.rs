//! Path following on the smoothing ε: the interior-point central path of the NCP.

use super::armijo::armijo;
use super::fischer_burmeister::{Damping, newton};
use super::{Limits, SmoothedSystem, StepFailure};

/// Path following on the smoothing: ε from `momentum_scale` squared (every complementarity
/// pair far inside, ab = ε, where Φ_ε is smooth and Newton's basin wide) down to the floor,
/// Newton converging each level to within its own smoothing before ε falls by 10; a level
/// that fails restarts from the last solved one with a gentler decrease (down to 1.5).
/// Returns the solution and the iterations (at most 10 × `limits.max_iterations`).
pub(in crate::sim) fn path_following<S: SmoothedSystem>(
    system: &S,
    x0: Vec<f64>,
    limits: Limits,
    momentum_scale: f64,
) -> Result<(Vec<f64>, usize), StepFailure> {
    let Limits {
        tolerance,
        max_iterations,
    } = limits;
    let eps_floor = (0.01 * tolerance).powi(2);
    let budget = 10 * max_iterations;
    let mut eps = momentum_scale.powi(2).max(eps_floor);
    let mut factor = 0.1;
    let mut x = x0;
    let mut solved_x = x.clone();
    let mut solved_eps = f64::INFINITY;
    let mut iterations = 0;
    let mut last = f64::INFINITY;
    while iterations < budget {
        // Converge the level: smoothed residual below a small fraction of √ε (or the
        // tolerance at the floor).
        let target = if eps <= eps_floor {
            tolerance
        } else {
            (0.01 * eps.sqrt()).max(tolerance)
        };
        let mut converged = false;
        for _ in 0..max_iterations {
            let e = system.evaluate(&x, eps, true);
            let size = e.residual.amax();
            last = e.plain;
            if eps <= eps_floor && e.plain <= tolerance {
                return Ok((x, iterations));
            }
            if size <= target {
                converged = true;
                break;
            }
            if !e
                .residual
                .iter()
                .chain(e.jacobian.iter())
                .all(|v| v.is_finite())
            {
                break;
            }
            iterations += 1;
            let Some(direction) = e.jacobian.clone().lu().solve(&(-&e.residual)) else {
                break;
            };
            let merit = 0.5 * e.residual.norm_squared();
            let Some((trial, _, _)) = armijo(system, &x, &direction, merit, eps, 40) else {
                break;
            };
            x = trial;
        }
        if converged {
            solved_x.clone_from(&x);
            solved_eps = eps;
            if eps <= eps_floor {
                // Converged at the floor by the smoothed residual: polish with Newton.
                return newton(system, x, limits, Damping::Plain)
                    .map(|(x, k)| (x, iterations + k))
                    .map_err(|(failure, _)| failure);
            }
            eps = (factor * eps).max(eps_floor);
        } else if solved_eps.is_finite() && factor < 0.66 {
            factor = factor.sqrt();
            x.clone_from(&solved_x);
            eps = (factor * solved_eps).max(eps_floor);
        } else {
            break;
        }
    }
    Err(StepFailure::NotConverged {
        iterations,
        residual: last,
        tolerance,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::ncp::test_problems::{LIMITS, Mcp, close};

    #[test]
    fn follows_the_central_path_to_a_two_dimensional_lcp_with_one_side_each() {
        // z = (1/2, 0), w = (0, 7/2), from far inside at ε = 10².
        let system = Mcp::lcp(&[&[2.0, 1.0], &[1.0, 2.0]], &[-1.0, 3.0]);
        let (x, _) = path_following(&system, vec![5.0, 5.0], LIMITS, 10.0).expect("solves");
        close(&x, &[0.5, 0.0], 1e-12);
    }

    #[test]
    fn follows_the_central_path_to_the_sliding_and_the_sticking_block() {
        let block = Mcp::sliding_block(1.0);
        let (x, _) = path_following(&block, block.guess(), LIMITS, 1.0).expect("slides");
        close(&x, &block.sliding_solution(), 1e-10);
        let block = Mcp::sliding_block(0.02);
        let (x, _) = path_following(&block, block.guess(), LIMITS, 1.0).expect("sticks");
        block.assert_sticks(&x, 1e-10);
    }

    #[test]
    fn reports_the_last_residual_when_the_problem_has_no_solution() {
        // w = −z − 1 < 0 for every z ≥ 0: no solution.
        let system = Mcp::lcp(&[&[-1.0]], &[-1.0]);
        let err = path_following(&system, vec![1.0], LIMITS, 1.0).expect_err("no solution");
        let StepFailure::NotConverged {
            residual,
            tolerance,
            ..
        } = err
        else {
            panic!("{err:?}")
        };
        assert!(residual > 0.1 && tolerance == 1e-12, "{residual}");
    }
}
