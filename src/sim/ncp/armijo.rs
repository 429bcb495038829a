//! Armijo backtracking on the merit ½‖Φ_ε‖² of a smoothed system.

use nalgebra::DVector;

use super::{Evaluation, SmoothedSystem};

/// Armijo backtracking on ½‖Φ_ε‖² from x along `direction` (halving up to `trials`
/// times), with `merit` the value at x: the accepted point, its step length and its
/// evaluation (without Jacobian).
pub(super) fn armijo<S: SmoothedSystem>(
    system: &S,
    x: &[f64],
    direction: &DVector<f64>,
    merit: f64,
    eps: f64,
    trials: usize,
) -> Option<(Vec<f64>, f64, Evaluation)> {
    let mut t = 1.0;
    for _ in 0..trials {
        let trial: Vec<f64> = x
            .iter()
            .zip(direction.iter())
            .map(|(a, d)| a + t * d)
            .collect();
        let e = system.evaluate(&trial, eps, false);
        let value = 0.5 * e.residual.norm_squared();
        if value.is_finite() && value <= (1.0 - 1e-4 * t) * merit {
            return Some((trial, t, e));
        }
        t *= 0.5;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::ncp::test_problems::Mcp;

    /// The 1-D LCP w = 2z − 4 (solution z = 2), far from the kink at ε = 0.
    fn line() -> Mcp {
        Mcp::lcp(&[&[2.0]], &[-4.0])
    }

    fn merit(system: &Mcp, x: &[f64]) -> f64 {
        0.5 * system.evaluate(x, 0.0, false).residual.norm_squared()
    }

    #[test]
    fn takes_the_full_newton_step_where_it_decreases_the_merit_enough() {
        // From z = 3: w = 2 > 0, Φ = z + w − √(z² + w²) is linear there along the ray.
        let system = line();
        let x = [3.0];
        let (found, t, e) = armijo(
            &system,
            &x,
            &DVector::from_element(1, -1.0),
            merit(&system, &x),
            0.0,
            30,
        )
        .expect("a descent direction is accepted");
        assert_eq!(t, 1.0);
        assert_eq!(found, vec![2.0]);
        assert!(e.plain < 1e-15, "{}", e.plain);
    }

    #[test]
    fn halves_an_overshooting_step_until_the_merit_falls() {
        // A step of −8 from z = 3 lands at −5, −1 and 1 (merit up each time); halving three
        // times lands on the solution z = 2.
        let system = line();
        let x = [3.0];
        let m0 = merit(&system, &x);
        let (found, t, _) = armijo(&system, &x, &DVector::from_element(1, -8.0), m0, 0.0, 30)
            .expect("a short enough step descends");
        assert_eq!(t, 0.125);
        assert_eq!(found, vec![2.0]);
        assert!(merit(&system, &found) <= (1.0 - 1e-4 * t) * m0);
    }

    #[test]
    fn rejects_an_ascent_direction() {
        let system = line();
        let x = [3.0];
        let m0 = merit(&system, &x);
        assert!(armijo(&system, &x, &DVector::from_element(1, 1.0), m0, 0.0, 30).is_none());
    }
}
