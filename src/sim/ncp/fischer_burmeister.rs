//! The smoothed Fischer–Burmeister function Φ_ε(a, b) = a + b − √(a² + b² + 2ε), zero exactly
//! where a, b > 0 and ab = ε, and Newton's method on a system of such equations with a
//! smoothing continuation: ε falls with the residual to a floor below the tolerance.

use super::armijo::armijo;
use super::levenberg_marquardt::levenberg_marquardt;
use super::{Limits, SmoothedSystem, StepFailure};

/// Φ_ε(a, b) and its partial derivatives, written without cancellation (far from the
/// kink, 1 − a/ρ is tiny and decides whether a variable is determined at all).
pub(in crate::sim) fn fischer_burmeister(a: f64, b: f64, eps: f64) -> (f64, f64, f64) {
    let root = (a * a + b * b + 2.0 * eps).sqrt();
    if root == 0.0 {
        let d = 1.0 - std::f64::consts::FRAC_1_SQRT_2;
        return (0.0, d, d);
    }
    // (a + b)² − ρ² = 2ab − 2ε.
    let value = if a + b > 0.0 {
        2.0 * (a * b - eps) / (a + b + root)
    } else {
        a + b - root
    };
    // 1 − x/ρ = (ρ² − x²)/(ρ(ρ + x)) for x > 0.
    let partial = |x: f64, y: f64| {
        if x > 0.0 {
            (y * y + 2.0 * eps) / (root * (root + x))
        } else {
            1.0 - x / root
        }
    };
    (value, partial(a, b), partial(b, a))
}

/// How [`newton`] continues where Newton's step is cut short.
#[derive(Debug, Clone, Copy)]
pub(in crate::sim) enum Damping {
    /// More smoothing.
    Plain,
    /// A Levenberg–Marquardt step first (momentum: the step's momentum scale).
    LevenbergMarquardt { momentum: f64 },
}

/// Newton's method on the smoothed system from x; returns the solution and the iterations,
/// or the failure and the last iterate.
pub(in crate::sim) fn newton<S: SmoothedSystem>(
    system: &S,
    mut x: Vec<f64>,
    limits: Limits,
    damping: Damping,
) -> Result<(Vec<f64>, usize), (StepFailure, Vec<f64>)> {
    let Limits {
        tolerance,
        max_iterations,
    } = limits;
    // Smoothing continuation: ε starts at the size of the residual, and falls (by 10, or
    // at once to the residual's size) whenever Newton is on the smoothed path, i.e. its
    // residual is below √(2ε); a failed or tiny line-search step raises it again.
    let eps_floor = (0.01 * tolerance).powi(2);
    let mut current = system.evaluate(&x, 0.0, false);
    let mut eps = (0.1 * current.plain).powi(2).max(eps_floor);
    current = system.evaluate(&x, eps, false);
    for iteration in 0..=max_iterations {
        if current.plain <= tolerance {
            return Ok((x, iteration));
        }
        if iteration == max_iterations {
            break;
        }
        if current.residual.amax() <= (2.0 * eps).sqrt() && eps > eps_floor {
            eps = (0.1 * eps)
                .min((0.1 * current.plain).powi(2))
                .max(eps_floor);
            current = system.evaluate(&x, eps, false);
        }
        let e = system.evaluate(&x, eps, true);
        let finite = e
            .residual
            .iter()
            .chain(e.jacobian.iter())
            .all(|v| v.is_finite());
        if !finite {
            return Err((StepFailure::NonFinite { iteration }, x));
        }
        let direction = e
            .jacobian
            .clone()
            .lu()
            .solve(&(-&e.residual))
            .ok_or(StepFailure::Singular { iteration });
        let direction = match direction {
            Ok(d) => d,
            Err(failure) => return Err((failure, x)),
        };
        let merit = 0.5 * e.residual.norm_squared();
        let mut step = armijo(system, &x, &direction, merit, eps, 30);
        let mut short = step.as_ref().is_none_or(|(_, t, _)| *t < 1e-2);
        if let (true, Damping::LevenbergMarquardt { momentum }) = (short, damping)
            && let Some(found) = levenberg_marquardt(system, &x, &e, merit, eps, momentum)
        {
            short = found.1 < 1e-2;
            step = Some(found);
        }
        if let Some((trial, _, trial_eval)) = step {
            x = trial;
            current = trial_eval;
        }
        if short {
            // Stalled on a nonsmooth valley (or jammed at an impulse's bound): smooth
            // more and go on from here.
            eps = (100.0 * eps).max((0.1 * e.plain).powi(2));
            current = system.evaluate(&x, eps, false);
        }
    }
    Err((
        StepFailure::NotConverged {
            iterations: max_iterations,
            residual: current.plain,
            tolerance,
        },
        x,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::finite_differences::central;
    use crate::sim::ncp::test_problems::{LIMITS, Mcp, close};

    #[test]
    fn smoothed_function_vanishes_exactly_on_the_smoothed_complementarity_set() {
        // Φ_0(a, 0) = 0 for a ≥ 0 and Φ_0(0, b) = 0 for b ≥ 0; Φ_0(a, b) < 0 if either is < 0.
        for (a, b) in [(3.0, 0.0), (0.0, 2.5), (0.0, 0.0)] {
            assert_eq!(fischer_burmeister(a, b, 0.0).0, 0.0, "({a}, {b})");
        }
        assert!(fischer_burmeister(-1.0, 2.0, 0.0).0 < 0.0);
        assert!(fischer_burmeister(1.0, 1.0, 0.0).0 > 0.0);
        // With ε, zero where ab = ε with both positive: (4, 0.25) at ε = 1.
        assert!(fischer_burmeister(4.0, 0.25, 1.0).0.abs() < 1e-15);
        assert!(fischer_burmeister(4.0, 0.5, 1.0).0 > 0.0);
    }

    #[test]
    fn partial_derivatives_match_central_differences() {
        for (a, b, eps) in [
            (1.5, -0.3, 0.0),
            (2.0, 3.0, 0.1),
            (-1.0, -2.0, 1e-4),
            (1e3, 1e-3, 0.0),
        ] {
            let (_, da, db) = fischer_burmeister(a, b, eps);
            let fa = central(|t| fischer_burmeister(a + t, b, eps).0, 1e-6);
            let fb = central(|t| fischer_burmeister(a, b + t, eps).0, 1e-6);
            assert!(
                (da - fa).abs() < 1e-6,
                "∂a at ({a}, {b}, {eps}): {da} vs {fa}"
            );
            assert!(
                (db - fb).abs() < 1e-6,
                "∂b at ({a}, {b}, {eps}): {db} vs {fb}"
            );
        }
    }

    #[test]
    fn newton_solves_one_dimensional_lcps_with_either_side_active() {
        // w = 2z − 4: z = 2 (w = 0); w = 2z + 3: z = 0 (w = 3).
        let (x, _) = newton(
            &Mcp::lcp(&[&[2.0]], &[-4.0]),
            vec![0.0],
            LIMITS,
            Damping::Plain,
        )
        .expect("solves");
        close(&x, &[2.0], 1e-12);
        let (x, _) = newton(
            &Mcp::lcp(&[&[2.0]], &[3.0]),
            vec![1.0],
            LIMITS,
            Damping::Plain,
        )
        .expect("solves");
        close(&x, &[0.0], 1e-12);
    }

    #[test]
    fn newton_solves_two_dimensional_lcps() {
        let m: [&[f64]; 2] = [&[2.0, 1.0], &[1.0, 2.0]];
        // Both positive: M z = −q, z = (4/3, 7/3).
        let (x, _) = newton(
            &Mcp::lcp(&m, &[-5.0, -6.0]),
            vec![0.0; 2],
            LIMITS,
            Damping::Plain,
        )
        .expect("solves");
        close(&x, &[4.0 / 3.0, 7.0 / 3.0], 1e-12);
        // One side each: z = (1/2, 0), w = (0, 7/2).
        let (x, _) = newton(
            &Mcp::lcp(&m, &[-1.0, 3.0]),
            vec![1.0; 2],
            LIMITS,
            Damping::Plain,
        )
        .expect("solves");
        close(&x, &[0.5, 0.0], 1e-12);
    }

    #[test]
    fn newton_keeps_a_box_resting_on_the_ground_and_drops_one_in_flight() {
        // At rest on the ground: the ground carries the weight over the step, c = m g h.
        let (x, _) = newton(
            &Mcp::falling_box(0.0),
            vec![0.0, 0.0],
            LIMITS,
            Damping::Plain,
        )
        .expect("solves");
        close(&x, &[0.0, 2.0 * 9.81 * 0.01], 1e-12);
        // A metre up: free fall over one step, y = 1 − g h², no impulse.
        let (x, _) = newton(
            &Mcp::falling_box(1.0),
            vec![1.0, 0.0],
            LIMITS,
            Damping::Plain,
        )
        .expect("solves");
        close(&x, &[1.0 - 9.81 * 1e-4, 0.0], 1e-12);
    }

    #[test]
    fn newton_slows_a_sliding_block_by_coulomb_friction() {
        let block = Mcp::sliding_block(1.0);
        let (x, _) = newton(&block, block.guess(), LIMITS, Damping::Plain).expect("solves");
        close(&x, &block.sliding_solution(), 1e-10);
    }
}
