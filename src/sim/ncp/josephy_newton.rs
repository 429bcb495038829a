//! Josephy–Newton: each linearisation of the NCP solved exactly by Lemke's pivoting method.

use nalgebra::{DMatrix, DVector};

use super::fischer_burmeister::{Damping, newton};
use super::lemke::lemke;
use super::{Limits, LinearisedComplementarity, StepFailure};

/// Josephy–Newton on the NCP, each linearisation solved exactly by Lemke's pivoting method
/// ([`lemke`]), then Newton's polish of the best iterate. At x the equations (row i of the
/// system belongs to unknown i) are linearised in the free unknowns and solved for them as
/// affine functions of the complementary ones, Δx_F = a + B z; what is left is the LCP of the
/// complementary functions ([`LinearisedComplementarity::linearised`]), whose solution is the
/// next iterate.
///
/// Why: where a contact pushes with its ψ far above its slip speed (LittleDog tracking its
/// 20-knot variational plan at 2 kHz, step 52), Φ(ψ, μc − eᵀβ) is flat in ψ and the
/// friction rows Φ(β, η) are flat in it too, so the ψ column of Newton's matrix vanishes
/// and ½‖Φ‖² has a stationary point there that is no solution; no merit-descent method
/// leaves it (the residual stayed at 1.2e-4, Levenberg–Marquardt at 2.2e-5). The LCP has
/// no such point: its pivots set the mode (stick, slide, lift) of each contact, and ψ the
/// slip speed, directly.
pub(in crate::sim) fn josephy_newton<S: LinearisedComplementarity>(
    system: &S,
    mut x: Vec<f64>,
    limits: Limits,
) -> Result<(Vec<f64>, usize), StepFailure> {
    let (free, complementary) = system.split();
    let (nf, nz) = (free.len(), complementary.len());
    let mut best = (f64::INFINITY, x.clone());
    let mut iterations = 0;
    for _ in 0..limits.max_iterations {
        let e = system.evaluate(&x, 0.0, true);
        if !e.plain.is_finite() {
            break;
        }
        if e.plain < best.0 {
            best = (e.plain, x.clone());
        }
        if e.plain <= limits.tolerance {
            return Ok((x, iterations));
        }
        iterations += 1;
        // The free rows: J_FF Δx_F + J_FZ (z − z_x) = −r_F, so Δx_F = a + B z.
        let j_ff = DMatrix::from_fn(nf, nf, |r, c| e.jacobian[(free[r], free[c])]);
        let j_fz = DMatrix::from_fn(nf, nz, |r, c| e.jacobian[(free[r], complementary[c])]);
        let z_x = DVector::from_iterator(nz, complementary.iter().map(|&i| x[i]));
        let r_f = DVector::from_iterator(nf, free.iter().map(|&r| e.residual[r]));
        let lu = j_ff.lu();
        let (Some(a), Some(b)) = (lu.solve(&(&j_fz * &z_x - r_f)), lu.solve(&(-&j_fz))) else {
            break;
        };
        let (m, q) = system.linearised(&x, &a, &b);
        let Ok(z) = lemke(&m, &q, 50 * nz.max(1)) else {
            break;
        };
        let step = a + b * &z;
        for (k, &i) in free.iter().enumerate() {
            x[i] += step[k];
        }
        for (k, &i) in complementary.iter().enumerate() {
            x[i] = z[k];
        }
    }
    // Polish the best iterate (its mode found) with Newton on the smoothed system.
    newton(system, best.1, limits, Damping::Plain)
        .map(|(x, k)| (x, iterations + k))
        .map_err(|(failure, _)| failure)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::ncp::test_problems::{LIMITS, Mcp, close};

    #[test]
    fn solves_a_linear_problem_in_one_pivoting_step() {
        // A linear problem is its own linearisation: Lemke's solution is the answer at once.
        // The box resting on the ground: y = 0, c = m g h.
        let system = Mcp::falling_box(0.0);
        let (x, iterations) = josephy_newton(&system, vec![0.0, 0.0], LIMITS).expect("solves");
        close(&x, &[0.0, 2.0 * 9.81 * 0.01], 1e-12);
        assert_eq!(iterations, 1);
    }

    #[test]
    fn finds_the_sliding_and_the_sticking_mode_of_a_block() {
        for speed in [1.0, 0.02] {
            let block = Mcp::sliding_block(speed);
            let (x, iterations) = josephy_newton(&block, block.guess(), LIMITS).expect("solves");
            if speed > 0.5 * 9.81 * 0.01 {
                close(&x, &block.sliding_solution(), 1e-10);
            } else {
                block.assert_sticks(&x, 1e-10);
            }
            assert!(iterations <= 3, "{iterations} iterations at speed {speed}");
        }
    }

    #[test]
    fn lands_a_falling_box_on_the_ground() {
        // From 5 mm up at rest, one step of free fall (g h² ≈ 1 mm) leaves it in flight.
        let (x, _) =
            josephy_newton(&Mcp::falling_box(5e-3), vec![5e-3, 1.0], LIMITS).expect("solves");
        close(&x, &[5e-3 - 9.81e-4, 0.0], 1e-12);
    }
}
