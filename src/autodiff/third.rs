//! Third derivatives contracted with a direction, for the Lagrangian Hessian of constraints
//! that are themselves gradients (the DEL equations are gradients of Ld).
//!
//! Each input is a [`HyperDualVec<Dual64, Const<T>, Const<T>>`] whose inner [`Dual64`] carries the
//! direction (`re = Dual64(z_i, dir_i)`), so one pass over a tile pair yields the Hessian block
//! (real parts) and the Hessian block of the directional derivative ∇f·dir (ε parts).

use super::{ScalarFunction, TILE, tile_count, tile_range};
use nalgebra::Const;
use nalgebra::DMatrix;
use num_dual::{Dual64, HyperDualVec};

/// Value, gradient, Hessian and contracted third derivative of a scalar function at a point.
#[derive(Debug, Clone, PartialEq)]
pub struct ThirdOrder {
    /// f(z).
    pub value: f64,
    /// ∇f(z), length `dim`.
    pub gradient: Vec<f64>,
    /// ∇²f(z), `dim × dim`, symmetric.
    pub hessian: DMatrix<f64>,
    /// W = ∇²(∇f·dir)(z) = Σ_k dir_k ∂³f/∂z_k∂z_i∂z_j, `dim × dim`, symmetric.
    pub contracted: DMatrix<f64>,
}

impl ThirdOrder {
    /// All-zero result for a function of `n` inputs (a buffer for [`gradient_hessian_third_into`]).
    pub fn zeros(n: usize) -> Self {
        Self {
            value: 0.0,
            gradient: vec![0.0; n],
            hessian: DMatrix::zeros(n, n),
            contracted: DMatrix::zeros(n, n),
        }
    }
}

/// Gradient g = ∇f, Hessian H = ∇²f and W = ∇²(∇f·dir) of `f` at `z` (both of length `dim`).
pub fn gradient_hessian_third<F: ScalarFunction>(f: &F, z: &[f64], dir: &[f64]) -> ThirdOrder {
    let mut out = ThirdOrder::zeros(f.dim());
    gradient_hessian_third_into::<TILE, F>(f, z, dir, &mut out);
    out
}

/// [`gradient_hessian_third`] with tile size `T`, writing into `out` (sized by
/// [`ThirdOrder::zeros`]`(dim)`, overwritten).
pub fn gradient_hessian_third_into<const T: usize, F: ScalarFunction>(
    f: &F,
    z: &[f64],
    dir: &[f64],
    out: &mut ThirdOrder,
) {
    let n = f.dim();
    assert_eq!(
        z.len(),
        n,
        "gradient_hessian_third: z has length {} but dim is {n}",
        z.len()
    );
    assert_eq!(
        dir.len(),
        n,
        "gradient_hessian_third: dir has length {} but dim is {n}",
        dir.len()
    );
    assert_eq!(
        out.gradient.len(),
        n,
        "gradient_hessian_third: buffer from ThirdOrder::zeros(dim)"
    );
    assert_eq!(
        out.hessian.shape(),
        (n, n),
        "gradient_hessian_third: buffer from ThirdOrder::zeros(dim)"
    );
    assert_eq!(
        out.contracted.shape(),
        (n, n),
        "gradient_hessian_third: buffer from ThirdOrder::zeros(dim)"
    );
    out.gradient.fill(0.0);
    out.hessian.fill(0.0);
    out.contracted.fill(0.0);
    type H<const T: usize> = HyperDualVec<Dual64, Const<T>, Const<T>>;
    let mut zd = vec![H::<T>::from_re(Dual64::from(0.0)); n];
    let tiles = tile_count(n, T);
    if tiles == 0 {
        out.value = f.eval(&zd).re.re;
        return;
    }
    for a in 0..tiles {
        let rows = tile_range(a, T, n);
        for b in 0..=a {
            let cols = tile_range(b, T, n);
            for (i, d) in zd.iter_mut().enumerate() {
                *d = H::<T>::from_re(Dual64::new(z[i], dir[i]));
                if rows.contains(&i) {
                    *d = d.derivative1(i - rows.start);
                }
                if cols.contains(&i) {
                    *d = d.derivative2(i - cols.start);
                }
            }
            let y = f.eval(&zd);
            out.value = y.re.re;
            if a == b
                && let Some(eps) = &y.eps1.0
            {
                for (k, i) in rows.clone().enumerate() {
                    out.gradient[i] = eps[k].re;
                }
            }
            let Some(block) = &y.eps1eps2.0 else { continue };
            for (p, i) in rows.clone().enumerate() {
                for (q, j) in cols.clone().enumerate() {
                    if a == b && j > i {
                        continue;
                    }
                    let d = block[(p, q)];
                    out.hessian[(i, j)] = d.re;
                    out.hessian[(j, i)] = d.re;
                    out.contracted[(i, j)] = d.eps;
                    out.contracted[(j, i)] = d.eps;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::finite_differences::{along, central};
    use crate::autodiff::gradient_hessian;
    use crate::autodiff::test_functions::{ClosedForm, Coupled, dims, point};

    /// Closed form: f = z_0² z_1 + sin z_1. ∂³f: f_001 = 2, f_111 = −cos z_1, others 0, so
    /// W = [[2 d_1, 2 d_0], [2 d_0, −cos(z_1) d_1]].
    #[test]
    fn contracted_third_matches_closed_form() {
        let (x, y) = (0.7, -1.3);
        let dir = [0.4, -2.5];
        let t = gradient_hessian_third(&ClosedForm, &[x, y], &dir);
        assert!((t.value - (x * x * y + y.sin())).abs() < 1e-14);
        assert!((t.hessian[(0, 1)] - 2.0 * x).abs() < 1e-14);
        assert!((t.contracted[(0, 0)] - 2.0 * dir[1]).abs() < 1e-14);
        assert!((t.contracted[(0, 1)] - 2.0 * dir[0]).abs() < 1e-14);
        assert!((t.contracted[(1, 0)] - 2.0 * dir[0]).abs() < 1e-14);
        assert!((t.contracted[(1, 1)] + y.cos() * dir[1]).abs() < 1e-14);
    }

    /// W is the directional derivative of the Hessian: (H(z + s·dir) − H(z − s·dir)) / 2s.
    #[test]
    fn contracted_third_matches_differences_of_hessian_for_every_tiling() {
        for n in dims() {
            let f = Coupled { n };
            let z = point(n, 5 + n as u64);
            let dir = point(n, 99 + n as u64);
            let t = gradient_hessian_third(&f, &z, &dir);
            let (v, g, h) = gradient_hessian(&f, &z);
            assert_eq!(t.value, v);
            assert_eq!(t.gradient, g);
            assert!((&t.hessian - &h).amax() < 1e-13 * (1.0 + h.amax()));
            let fd = central(|t| gradient_hessian(&f, &along(&z, &dir, t)).2, 1e-6);
            for i in 0..n {
                for j in 0..n {
                    let r = fd[(i, j)];
                    let w = t.contracted[(i, j)];
                    assert!(
                        (w - r).abs() < 1e-6 * (1.0 + r.abs()),
                        "n={n} ({i},{j}) {w} vs {r}"
                    );
                }
            }
            let mut t3 = ThirdOrder::zeros(n);
            gradient_hessian_third_into::<3, _>(&f, &z, &dir, &mut t3);
            assert!((&t3.contracted - &t.contracted).amax() < 1e-12 * (1.0 + t.contracted.amax()));
        }
    }
}
