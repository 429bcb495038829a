//! Lemke's complementary pivoting method for the linear complementarity problem
//! w = M z + q, 0 ≤ z ⊥ w ≥ 0 (dense tableau, covering vector e = 1). The step solver uses it
//! on the step's linearised contact problem, where it finds the contact mode (which contacts
//! push, stick or slide) exactly, which a merit-descent Newton method cannot always do.

use nalgebra::{DMatrix, DVector};

/// Why Lemke's method stopped without a solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LemkeFailure {
    /// The entering column has no positive entry: the method ended on a secondary ray (for a
    /// copositive-plus M, the problem has no solution).
    Ray,
    /// The pivot limit was reached (cycling on a degenerate problem).
    PivotLimit,
}

/// Solves the LCP (M, q): z ≥ 0 with w = M z + q ≥ 0 and zᵀw = 0. `max_pivots` bounds the
/// work (cycling is possible on degenerate problems without lexicographic rules).
pub fn lemke(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    max_pivots: usize,
) -> Result<DVector<f64>, LemkeFailure> {
    let n = q.len();
    if q.iter().all(|&v| v >= 0.0) {
        return Ok(DVector::zeros(n));
    }
    // Columns: w (0..n), z (n..2n), the artificial z₀ (2n), the right-hand side (2n + 1):
    // I w − M z − e z₀ = q.
    let (artificial, rhs) = (2 * n, 2 * n + 1);
    let mut t = DMatrix::zeros(n, 2 * n + 2);
    for i in 0..n {
        t[(i, i)] = 1.0;
        for j in 0..n {
            t[(i, n + j)] = -m[(i, j)];
        }
        t[(i, artificial)] = -1.0;
        t[(i, rhs)] = q[i];
    }
    let mut basis: Vec<usize> = (0..n).collect();
    let scale = m.amax().max(q.amax()).max(1.0);
    let tiny = 1e-13 * scale;
    // z₀ enters at the most negative q; w of that row leaves.
    let mut row = (0..n).min_by(|&a, &b| q[a].total_cmp(&q[b])).unwrap_or(0);
    let mut entering = artificial;
    for _ in 0..max_pivots {
        pivot(&mut t, row, entering);
        let leaving = basis[row];
        basis[row] = entering;
        if leaving == artificial {
            return Ok(solution(&t, &basis, n));
        }
        // The complement of the variable that left enters.
        entering = if leaving < n {
            leaving + n
        } else {
            leaving - n
        };
        // Ratio test; among ties, z₀ leaves first (it ends the method), then the largest
        // pivot element (the most stable).
        let mut best: Option<(usize, f64)> = None;
        for i in 0..n {
            let a = t[(i, entering)];
            if a <= tiny {
                continue;
            }
            let ratio = t[(i, rhs)].max(0.0) / a;
            best = match best {
                None => Some((i, ratio)),
                Some((b, r)) => {
                    let tie = (ratio - r).abs() <= 1e-12 * r.abs().max(1e-300);
                    let prefer =
                        basis[b] != artificial && (basis[i] == artificial || a > t[(b, entering)]);
                    if ratio < r && !tie || tie && prefer {
                        Some((i, ratio))
                    } else {
                        Some((b, r))
                    }
                }
            };
        }
        let Some((next, _)) = best else {
            return Err(LemkeFailure::Ray);
        };
        row = next;
    }
    Err(LemkeFailure::PivotLimit)
}

/// Gauss–Jordan pivot of the tableau on (row, col).
fn pivot(t: &mut DMatrix<f64>, row: usize, col: usize) {
    let p = t[(row, col)];
    let width = t.ncols();
    for j in 0..width {
        t[(row, j)] /= p;
    }
    for i in 0..t.nrows() {
        if i == row {
            continue;
        }
        let f = t[(i, col)];
        if f != 0.0 {
            for j in 0..width {
                let v = t[(row, j)];
                t[(i, j)] -= f * v;
            }
        }
    }
}

/// z from the tableau's basic variables.
fn solution(t: &DMatrix<f64>, basis: &[usize], n: usize) -> DVector<f64> {
    let rhs = t.ncols() - 1;
    let mut z = DVector::zeros(n);
    for (i, &b) in basis.iter().enumerate() {
        if (n..2 * n).contains(&b) {
            z[b - n] = t[(i, rhs)].max(0.0);
        }
    }
    z
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(m: &DMatrix<f64>, q: &DVector<f64>, z: &DVector<f64>) {
        let w = m * z + q;
        for i in 0..q.len() {
            assert!(z[i] >= 0.0 && w[i] >= -1e-12, "z {z}, w {w}");
            assert!((z[i] * w[i]).abs() < 1e-12, "z {z}, w {w}");
        }
    }

    /// A positive definite M: the unique solution, with some components on each side.
    #[test]
    fn solves_a_positive_definite_problem() {
        let m = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0]);
        let q = DVector::from_row_slice(&[-2.0, 1.0, -1.0]);
        let z = lemke(&m, &q, 100).unwrap();
        check(&m, &q, &z);
        assert!(z[0] > 0.0 && z[1] == 0.0 && z[2] > 0.0, "{z}");
    }

    /// A 2D point sliding with friction (Stewart–Trinkle, one normal, two directions and ψ):
    /// the copositive LCP of the sliding mode, friction saturated against the motion.
    #[test]
    fn finds_the_sliding_mode_of_a_friction_problem() {
        // Unknowns (c, β+, β−, ψ), unit mass, h = 1, μ = 0.5: velocity after the step
        // v = v0 + β+ − β−, normal velocity −g + c.
        let mu = 0.5;
        let m = DMatrix::from_row_slice(
            4,
            4,
            &[
                1.0, 0.0, 0.0, 0.0, //
                0.0, 1.0, -1.0, 1.0, //
                0.0, -1.0, 1.0, 1.0, //
                mu, -1.0, -1.0, 0.0,
            ],
        );
        let (g, v0) = (1.0, 2.0);
        let q = DVector::from_row_slice(&[-g, v0, -v0, 0.0]);
        let z = lemke(&m, &q, 100).unwrap();
        check(&m, &q, &z);
        // c = g, β− = μc opposes the motion, ψ is the remaining speed v0 − μc.
        assert!(
            (z[0] - g).abs() < 1e-12 && (z[2] - mu * g).abs() < 1e-12,
            "{z}"
        );
        assert!((z[3] - (v0 - mu * g)).abs() < 1e-12, "{z}");
    }
}
