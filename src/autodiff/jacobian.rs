//! First derivatives: Jacobians of vector functions and gradients of scalar functions, by
//! forward passes of [`DualSVec64`] over column tiles.

use super::{ScalarFunction, TILE, VectorFunction, tile_count, tile_range};
use nalgebra::DMatrix;
use num_dual::DualSVec64;

/// Values and dense Jacobian (`dim_out × dim_in`) of `f` at `z` (length `dim_in`).
pub fn jacobian<F: VectorFunction>(f: &F, z: &[f64]) -> (Vec<f64>, DMatrix<f64>) {
    let mut values = vec![0.0; f.dim_out()];
    let mut jac = DMatrix::zeros(f.dim_out(), f.dim_in());
    jacobian_into::<TILE, F>(f, z, &mut values, &mut jac);
    (values, jac)
}

/// [`jacobian`] with tile size `T`, writing into caller buffers: `values` (length `dim_out`)
/// and `jac` (`dim_out × dim_in`), both overwritten.
pub fn jacobian_into<const T: usize, F: VectorFunction>(
    f: &F,
    z: &[f64],
    values: &mut [f64],
    jac: &mut DMatrix<f64>,
) {
    let n = f.dim_in();
    let m = f.dim_out();
    assert_eq!(
        z.len(),
        n,
        "jacobian: z has length {} but dim_in is {n}",
        z.len()
    );
    assert_eq!(
        values.len(),
        m,
        "jacobian: values buffer must have length dim_out"
    );
    assert_eq!(
        jac.shape(),
        (m, n),
        "jacobian: jac buffer must be dim_out × dim_in"
    );
    jac.fill(0.0);
    let mut zd: Vec<DualSVec64<T>> = z.iter().map(|&x| DualSVec64::from_re(x)).collect();
    let mut out = vec![DualSVec64::<T>::from_re(0.0); m];
    let passes = tile_count(n, T).max(1);
    for c in 0..passes {
        let cols = tile_range(c, T, n);
        for (i, (d, &x)) in zd.iter_mut().zip(z).enumerate() {
            *d = DualSVec64::from_re(x);
            if cols.contains(&i) {
                *d = d.derivative(i - cols.start);
            }
        }
        f.eval(&zd, &mut out);
        for (r, o) in out.iter().enumerate() {
            if c == 0 {
                values[r] = o.re;
            }
            if let Some(eps) = &o.eps.0 {
                for (k, col) in cols.clone().enumerate() {
                    jac[(r, col)] = eps[k];
                }
            }
        }
    }
}

/// Value and gradient (length `dim`) of the scalar function `f` at `z`.
pub fn gradient<F: ScalarFunction>(f: &F, z: &[f64]) -> (f64, Vec<f64>) {
    let mut grad = vec![0.0; f.dim()];
    let value = gradient_into::<TILE, F>(f, z, &mut grad);
    (value, grad)
}

/// [`gradient`] with tile size `T`, writing the gradient into `grad` (length `dim`) and
/// returning the value.
pub fn gradient_into<const T: usize, F: ScalarFunction>(f: &F, z: &[f64], grad: &mut [f64]) -> f64 {
    let n = f.dim();
    assert_eq!(
        z.len(),
        n,
        "gradient: z has length {} but dim is {n}",
        z.len()
    );
    assert_eq!(grad.len(), n, "gradient: grad buffer must have length dim");
    grad.fill(0.0);
    let mut zd: Vec<DualSVec64<T>> = z.iter().map(|&x| DualSVec64::from_re(x)).collect();
    let mut value = 0.0;
    for c in 0..tile_count(n, T).max(1) {
        let cols = tile_range(c, T, n);
        for (i, (d, &x)) in zd.iter_mut().zip(z).enumerate() {
            *d = DualSVec64::from_re(x);
            if cols.contains(&i) {
                *d = d.derivative(i - cols.start);
            }
        }
        let y = f.eval(&zd);
        value = y.re;
        if let Some(eps) = &y.eps.0 {
            for (k, i) in cols.enumerate() {
                grad[i] = eps[k];
            }
        }
    }
    value
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::finite_differences::gradient as fd_gradient;
    use crate::autodiff::test_functions::{ClosedForm, Coupled, CoupledVector, dims, point};

    /// Closed form: f(z) = z_0² z_1 + sin(z_1) has ∇f = (2 z_0 z_1, z_0² + cos z_1).
    #[test]
    fn gradient_matches_closed_form() {
        let (v, g) = gradient(&ClosedForm, &[0.7, -1.3]);
        assert!((v - (0.49 * -1.3 + (-1.3f64).sin())).abs() < 1e-14);
        assert!((g[0] - 2.0 * 0.7 * -1.3).abs() < 1e-14);
        assert!((g[1] - (0.49 + (-1.3f64).cos())).abs() < 1e-14);
    }

    #[test]
    fn gradient_matches_central_differences_for_every_tiling() {
        for n in dims() {
            let f = Coupled { n };
            let z = point(n, n as u64);
            let (v, g) = gradient(&f, &z);
            assert_eq!(v, f.eval(&z));
            let fd = fd_gradient(&|x: &[f64]| f.eval(x), &z, 1e-6);
            for i in 0..n {
                assert!(
                    (g[i] - fd[i]).abs() < 1e-7 * (1.0 + g[i].abs()),
                    "n={n} i={i}"
                );
            }
            // Other tile sizes give the same numbers.
            let mut g4 = vec![0.0; n];
            gradient_into::<3, _>(&f, &z, &mut g4);
            for i in 0..n {
                assert!((g[i] - g4[i]).abs() < 1e-13 * (1.0 + g[i].abs()));
            }
        }
    }

    #[test]
    fn jacobian_matches_central_differences_for_every_tiling() {
        for n in dims() {
            let f = CoupledVector { n, m: 3 };
            let z = point(n, 7 + n as u64);
            let (vals, jac) = jacobian(&f, &z);
            let mut direct = vec![0.0; 3];
            f.eval(&z, &mut direct);
            assert_eq!(vals, direct);
            for r in 0..3 {
                let fd = fd_gradient(
                    &|x: &[f64]| {
                        let mut o = vec![0.0; 3];
                        f.eval(x, &mut o);
                        o[r]
                    },
                    &z,
                    1e-6,
                );
                for i in 0..n {
                    let a = jac[(r, i)];
                    assert!(
                        (a - fd[i]).abs() < 1e-7 * (1.0 + a.abs()),
                        "n={n} r={r} i={i}"
                    );
                }
            }
        }
    }

    /// Closed form: a linear map has its matrix as Jacobian, whatever the tiling.
    #[test]
    fn jacobian_of_linear_map_is_its_matrix() {
        struct Lin;
        impl VectorFunction for Lin {
            fn dim_in(&self) -> usize {
                11
            }
            fn dim_out(&self) -> usize {
                2
            }
            fn eval<D: crate::autodiff::Scalar>(&self, z: &[D], out: &mut [D]) {
                out[0] = D::zero();
                out[1] = D::zero();
                for (i, &zi) in z.iter().enumerate() {
                    out[0] += zi * i as f64;
                    out[1] -= zi * (i * i) as f64;
                }
            }
        }
        let (_, jac) = jacobian(&Lin, &[0.3; 11]);
        for i in 0..11 {
            assert_eq!(jac[(0, i)], i as f64);
            assert_eq!(jac[(1, i)], -((i * i) as f64));
        }
    }
}
