//! Central differences, the independent witness of the exact derivatives in the tests.

use nalgebra::DMatrix;
use vito::autodiff::VectorFunction;

/// Central-difference Jacobian of a vector function (step 1e-6·max(1, |x_j|)), one pair of
/// evaluations per column.
pub fn central_jacobian<F: VectorFunction>(f: &F, x: &[f64]) -> DMatrix<f64> {
    let (m, n) = (f.dim_out(), f.dim_in());
    let mut jac = DMatrix::zeros(m, n);
    let (mut plus, mut minus) = (vec![0.0; m], vec![0.0; m]);
    for j in 0..n {
        let step = 1e-6 * x[j].abs().max(1.0);
        let mut xp = x.to_vec();
        xp[j] += step;
        f.eval(&xp, &mut plus);
        xp[j] = x[j] - step;
        f.eval(&xp, &mut minus);
        for i in 0..m {
            jac[(i, j)] = (plus[i] - minus[i]) / (2.0 * step);
        }
    }
    jac
}
