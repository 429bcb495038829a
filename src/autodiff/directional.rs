//! A Jacobian together with its directional derivative, by first-order passes of
//! `DualVec<Dual64, T>` whose inner ε carries the direction.
//!
//! Applied to a gradient function g = ∇φ (for instance a hand-written reverse sweep of Ld),
//! this yields the Hessian ∇²φ and the contracted third derivative ∇²(∇φ·dir) from first-order
//! passes only, which is much cheaper than the hyper-dual route of [`super::third`].

use super::{TILE, VectorFunction, tile_count, tile_range};
use nalgebra::{Const, DMatrix};
use num_dual::{Derivative, Dual64, DualVec};

/// Values, Jacobian J = ∂f/∂z and its directional derivative Σ_k dir_k ∂J/∂z_k (both
/// `dim_out × dim_in`) of a vector function.
#[derive(Debug, Clone, PartialEq)]
pub struct JacobianDirectional {
    /// f(z), length `dim_out`.
    pub values: Vec<f64>,
    /// ∂f/∂z, `dim_out × dim_in`.
    pub jacobian: DMatrix<f64>,
    /// d/ds J(z + s·dir) at s = 0, `dim_out × dim_in`. For f = ∇φ it is ∇²(∇φ·dir).
    pub directional: DMatrix<f64>,
}

/// Jacobian of `f` at `z` and its directional derivative along `dir` (both of length `dim_in`).
pub fn jacobian_directional<F: VectorFunction>(
    f: &F,
    z: &[f64],
    dir: &[f64],
) -> JacobianDirectional {
    jacobian_directional_tiled::<TILE, F>(f, z, dir)
}

/// [`jacobian_directional`] with tile size `T`.
pub fn jacobian_directional_tiled<const T: usize, F: VectorFunction>(
    f: &F,
    z: &[f64],
    dir: &[f64],
) -> JacobianDirectional {
    let n = f.dim_in();
    let m = f.dim_out();
    assert_eq!(
        z.len(),
        n,
        "jacobian_directional: z has length {} but dim_in is {n}",
        z.len()
    );
    assert_eq!(
        dir.len(),
        n,
        "jacobian_directional: dir has length {} but dim_in is {n}",
        dir.len()
    );
    type V<const T: usize> = DualVec<Dual64, Const<T>>;
    let lift = |i: usize| V::<T>::new(Dual64::new(z[i], dir[i]), Derivative::none());
    let mut zd: Vec<V<T>> = (0..n).map(lift).collect();
    let mut out = vec![V::<T>::new(Dual64::from(0.0), Derivative::none()); m];
    let mut result = JacobianDirectional {
        values: vec![0.0; m],
        jacobian: DMatrix::zeros(m, n),
        directional: DMatrix::zeros(m, n),
    };
    for c in 0..tile_count(n, T).max(1) {
        let cols = tile_range(c, T, n);
        for (i, d) in zd.iter_mut().enumerate() {
            *d = lift(i);
            if cols.contains(&i) {
                *d = d.derivative(i - cols.start);
            }
        }
        f.eval(&zd, &mut out);
        for (r, o) in out.iter().enumerate() {
            result.values[r] = o.re.re;
            if let Some(eps) = &o.eps.0 {
                for (k, col) in cols.clone().enumerate() {
                    result.jacobian[(r, col)] = eps[k].re;
                    result.directional[(r, col)] = eps[k].eps;
                }
            }
        }
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::finite_differences::{along, central};
    use crate::autodiff::test_functions::{CoupledVector, dims, point};
    use crate::autodiff::{jacobian, weighted_hessian};

    /// J equals [`jacobian`]; the directional part equals central differences of J along dir.
    #[test]
    fn matches_jacobian_and_its_central_difference() {
        for n in dims() {
            let f = CoupledVector { n, m: 3 };
            let z = point(n, 21 + n as u64);
            let dir = point(n, 45 + n as u64);
            let r = jacobian_directional(&f, &z, &dir);
            let (values, jac) = jacobian(&f, &z);
            assert_eq!(r.values, values);
            assert!((&r.jacobian - &jac).amax() < 1e-13 * (1.0 + jac.amax()));
            let fd = central(|t| jacobian(&f, &along(&z, &dir, t)).1, 1e-6);
            let scale = 1.0 + fd.amax();
            assert!((&r.directional - &fd).amax() < 1e-6 * scale, "n={n}");
        }
    }

    /// Row-weighted, the directional derivative of J is (∇²(wᵀf))·dir.
    #[test]
    fn weighted_rows_give_hessian_times_direction() {
        let n = 11;
        let f = CoupledVector { n, m: 3 };
        let (z, dir, w) = (point(n, 1), point(n, 2), [0.3, -1.0, 2.0]);
        let r = jacobian_directional_tiled::<4, _>(&f, &z, &dir);
        let hess = weighted_hessian(&f, &z, &w);
        let expected = hess * nalgebra::DVector::from_column_slice(&dir);
        for (i, e) in expected.iter().enumerate() {
            let got: f64 = (0..3).map(|row| w[row] * r.directional[(row, i)]).sum();
            assert!((got - e).abs() < 1e-11 * (1.0 + e.abs()));
        }
    }
}
