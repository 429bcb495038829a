//! Second derivatives: Hessians of scalar functions and of multiplier-weighted sums of vector
//! functions, by [`HyperDualSVec64`] passes over pairs of input tiles (lower block triangle).

use super::{ScalarFunction, TILE, VectorFunction, tile_count, tile_range};
use nalgebra::DMatrix;
use num_dual::HyperDualSVec64;

/// Seeds `zd` for the tile pair (`rows`, `cols`): ε₁ on the inputs of `rows`, ε₂ on `cols`.
fn seed_pair<const T: usize>(
    zd: &mut [HyperDualSVec64<T, T>],
    z: &[f64],
    rows: &std::ops::Range<usize>,
    cols: &std::ops::Range<usize>,
) {
    for (i, (d, &x)) in zd.iter_mut().zip(z).enumerate() {
        *d = HyperDualSVec64::from_re(x);
        if rows.contains(&i) {
            *d = d.derivative1(i - rows.start);
        }
        if cols.contains(&i) {
            *d = d.derivative2(i - cols.start);
        }
    }
}

/// Adds `weight ·` the ε₁ε₂ block of `y` into `hess` at (`rows`, `cols`) and its mirror.
fn scatter_block<const T: usize>(
    y: &HyperDualSVec64<T, T>,
    weight: f64,
    rows: &std::ops::Range<usize>,
    cols: &std::ops::Range<usize>,
    hess: &mut DMatrix<f64>,
) {
    let Some(block) = &y.eps1eps2.0 else { return };
    for (a, i) in rows.clone().enumerate() {
        for (b, j) in cols.clone().enumerate() {
            if rows == cols && j > i {
                continue;
            }
            let v = weight * block[(a, b)];
            hess[(i, j)] += v;
            if i != j {
                hess[(j, i)] += v;
            }
        }
    }
}

/// Value, gradient (length `dim`) and full symmetric Hessian (`dim × dim`) of `f` at `z`.
pub fn gradient_hessian<F: ScalarFunction>(f: &F, z: &[f64]) -> (f64, Vec<f64>, DMatrix<f64>) {
    let n = f.dim();
    let mut grad = vec![0.0; n];
    let mut hess = DMatrix::zeros(n, n);
    let value = gradient_hessian_into::<TILE, F>(f, z, &mut grad, &mut hess);
    (value, grad, hess)
}

/// [`gradient_hessian`] with tile size `T`, writing into `grad` (length `dim`) and `hess`
/// (`dim × dim`, overwritten), returning the value.
pub fn gradient_hessian_into<const T: usize, F: ScalarFunction>(
    f: &F,
    z: &[f64],
    grad: &mut [f64],
    hess: &mut DMatrix<f64>,
) -> f64 {
    let n = f.dim();
    assert_eq!(
        z.len(),
        n,
        "gradient_hessian: z has length {} but dim is {n}",
        z.len()
    );
    assert_eq!(
        grad.len(),
        n,
        "gradient_hessian: grad buffer must have length dim"
    );
    assert_eq!(
        hess.shape(),
        (n, n),
        "gradient_hessian: hess buffer must be dim × dim"
    );
    grad.fill(0.0);
    hess.fill(0.0);
    let mut zd = vec![HyperDualSVec64::<T, T>::from_re(0.0); n];
    let tiles = tile_count(n, T);
    let mut value = 0.0;
    if tiles == 0 {
        seed_pair(&mut zd, z, &(0..0), &(0..0));
        return f.eval(&zd).re;
    }
    for a in 0..tiles {
        let rows = tile_range(a, T, n);
        for b in 0..=a {
            let cols = tile_range(b, T, n);
            seed_pair(&mut zd, z, &rows, &cols);
            let y = f.eval(&zd);
            value = y.re;
            if a == b
                && let Some(eps) = &y.eps1.0
            {
                for (k, i) in rows.clone().enumerate() {
                    grad[i] = eps[k];
                }
            }
            scatter_block(&y, 1.0, &rows, &cols, hess);
        }
    }
    value
}

/// ∇²(wᵀ f(z)) (`dim_in × dim_in`, symmetric) for multipliers `w` (length `dim_out`).
pub fn weighted_hessian<F: VectorFunction>(f: &F, z: &[f64], w: &[f64]) -> DMatrix<f64> {
    let n = f.dim_in();
    let mut hess = DMatrix::zeros(n, n);
    weighted_hessian_into::<TILE, F>(f, z, w, &mut hess);
    hess
}

/// [`weighted_hessian`] with tile size `T`, writing into `hess` (`dim_in × dim_in`, overwritten).
pub fn weighted_hessian_into<const T: usize, F: VectorFunction>(
    f: &F,
    z: &[f64],
    w: &[f64],
    hess: &mut DMatrix<f64>,
) {
    let n = f.dim_in();
    let m = f.dim_out();
    assert_eq!(
        z.len(),
        n,
        "weighted_hessian: z has length {} but dim_in is {n}",
        z.len()
    );
    assert_eq!(
        w.len(),
        m,
        "weighted_hessian: w has length {} but dim_out is {m}",
        w.len()
    );
    assert_eq!(
        hess.shape(),
        (n, n),
        "weighted_hessian: hess buffer must be dim_in × dim_in"
    );
    hess.fill(0.0);
    let mut zd = vec![HyperDualSVec64::<T, T>::from_re(0.0); n];
    let mut out = vec![HyperDualSVec64::<T, T>::from_re(0.0); m];
    let tiles = tile_count(n, T);
    for a in 0..tiles {
        let rows = tile_range(a, T, n);
        for b in 0..=a {
            let cols = tile_range(b, T, n);
            seed_pair(&mut zd, z, &rows, &cols);
            f.eval(&zd, &mut out);
            for (y, &wj) in out.iter().zip(w) {
                if wj != 0.0 {
                    scatter_block(y, wj, &rows, &cols, hess);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::Scalar;
    use crate::autodiff::finite_differences::gradient as fd_gradient;
    use crate::autodiff::gradient;
    use crate::autodiff::test_functions::{ClosedForm, Coupled, CoupledVector, dims, point};

    /// Closed form: f = z_0² z_1 + sin z_1 has H = [[2 z_1, 2 z_0], [2 z_0, −sin z_1]].
    #[test]
    fn hessian_matches_closed_form() {
        let (x, y) = (0.7, -1.3);
        let (_, g, h) = gradient_hessian(&ClosedForm, &[x, y]);
        assert!((g[0] - 2.0 * x * y).abs() < 1e-14);
        assert!((h[(0, 0)] - 2.0 * y).abs() < 1e-14);
        assert!((h[(0, 1)] - 2.0 * x).abs() < 1e-14);
        assert!((h[(1, 0)] - 2.0 * x).abs() < 1e-14);
        assert!((h[(1, 1)] + f64::sin(y)).abs() < 1e-14);
    }

    /// The Hessian is the Jacobian of the (AD) gradient: compare with central differences of it.
    #[test]
    fn hessian_matches_differences_of_gradient_for_every_tiling() {
        for n in dims() {
            let f = Coupled { n };
            let z = point(n, 3 + n as u64);
            let (v, g, h) = gradient_hessian(&f, &z);
            assert_eq!(v, f.eval(&z));
            let (_, g_ref) = gradient(&f, &z);
            for i in 0..n {
                assert!((g[i] - g_ref[i]).abs() < 1e-13 * (1.0 + g[i].abs()));
                let fd = fd_gradient(&|x: &[f64]| gradient(&f, x).1[i], &z, 1e-6);
                for j in 0..n {
                    assert!(
                        (h[(i, j)] - fd[j]).abs() < 1e-7 * (1.0 + fd[j].abs()),
                        "n={n} ({i},{j})"
                    );
                    assert_eq!(h[(i, j)], h[(j, i)]);
                }
            }
        }
    }

    /// ∇²(wᵀf) equals Σ_j w_j ∇²f_j computed one output at a time.
    #[test]
    fn weighted_hessian_is_sum_of_output_hessians() {
        struct Output<'a> {
            f: &'a CoupledVector,
            j: usize,
        }
        impl ScalarFunction for Output<'_> {
            fn dim(&self) -> usize {
                self.f.n
            }
            fn eval<D: Scalar>(&self, z: &[D]) -> D {
                let mut o = vec![D::zero(); self.f.m];
                self.f.eval(z, &mut o);
                o[self.j]
            }
        }
        for n in dims() {
            let f = CoupledVector { n, m: 3 };
            let z = point(n, 11 + n as u64);
            let w = [0.5, -2.0, 0.0];
            let h = weighted_hessian(&f, &z, &w);
            let mut reference = DMatrix::zeros(n, n);
            for (j, wj) in w.iter().enumerate() {
                reference += gradient_hessian(&Output { f: &f, j }, &z).2 * *wj;
            }
            for i in 0..n {
                for k in 0..n {
                    let r = reference[(i, k)];
                    assert!((h[(i, k)] - r).abs() < 1e-12 * (1.0 + r.abs()), "n={n}");
                }
            }
            let mut h3 = DMatrix::zeros(n, n);
            weighted_hessian_into::<3, _>(&f, &z, &w, &mut h3);
            assert!((h3 - &h).amax() < 1e-12 * (1.0 + h.amax()));
        }
    }
}
