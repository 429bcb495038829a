//! Central differences in `f64`: the independent witness the unit and integration tests hold
//! the exact derivatives against. Every difference is (g(t) − g(−t)) / 2t for a function g
//! of the step t (a point moved along one coordinate or one direction).

use nalgebra::{DMatrix, DVector};

use super::VectorFunction;

/// A value whose central difference is taken entry by entry.
pub trait Differenced: Sized {
    /// (plus − minus) / (2·step), entry by entry.
    fn central(plus: Self, minus: Self, step: f64) -> Self;
}

impl Differenced for f64 {
    fn central(plus: f64, minus: f64, step: f64) -> f64 {
        (plus - minus) / (2.0 * step)
    }
}

impl Differenced for Vec<f64> {
    fn central(plus: Vec<f64>, minus: Vec<f64>, step: f64) -> Vec<f64> {
        assert_eq!(plus.len(), minus.len(), "both sides have the same length");
        plus.iter()
            .zip(&minus)
            .map(|(&p, &m)| f64::central(p, m, step))
            .collect()
    }
}

impl Differenced for DVector<f64> {
    fn central(plus: DVector<f64>, minus: DVector<f64>, step: f64) -> DVector<f64> {
        (plus - minus) / (2.0 * step)
    }
}

impl Differenced for DMatrix<f64> {
    fn central(plus: DMatrix<f64>, minus: DMatrix<f64>, step: f64) -> DMatrix<f64> {
        (plus - minus) / (2.0 * step)
    }
}

/// The central difference (g(step) − g(−step)) / (2·step) of g at 0.
pub fn central<T: Differenced>(mut g: impl FnMut(f64) -> T, step: f64) -> T {
    let plus = g(step);
    let minus = g(-step);
    T::central(plus, minus, step)
}

/// `x` with `t` added to coordinate `j`.
pub fn moved(x: &[f64], j: usize, t: f64) -> Vec<f64> {
    let mut y = x.to_vec();
    y[j] += t;
    y
}

/// x + t·dir.
pub fn along(x: &[f64], dir: &[f64], t: f64) -> Vec<f64> {
    x.iter().zip(dir).map(|(xi, di)| xi + t * di).collect()
}

/// Central differences of `f` along each coordinate of `x` in turn, with the step that
/// `step` gives for the coordinate's value: the gradient of a scalar f, the columns of a
/// vector f's Jacobian, the Hessian's columns for f a gradient.
pub fn columns<T: Differenced>(
    mut f: impl FnMut(&[f64]) -> T,
    x: &[f64],
    step: impl Fn(f64) -> f64,
) -> Vec<T> {
    (0..x.len())
        .map(|j| {
            let s = step(x[j]);
            central(|t| f(&moved(x, j, t)), s)
        })
        .collect()
}

/// Central-difference gradient of a scalar `f` at `x`, one fixed step for every coordinate.
pub fn gradient(f: impl FnMut(&[f64]) -> f64, x: &[f64], step: f64) -> Vec<f64> {
    columns(f, x, |_| step)
}

/// Central-difference Jacobian of a vector `f` at `x` (m rows), with the step that `step`
/// gives for each coordinate's value.
pub fn jacobian(
    f: impl FnMut(&[f64]) -> Vec<f64>,
    x: &[f64],
    step: impl Fn(f64) -> f64,
) -> DMatrix<f64> {
    let cols = columns(f, x, step);
    let m = cols.first().map_or(0, Vec::len);
    DMatrix::from_fn(m, x.len(), |i, j| cols[j][i])
}

/// The values of a [`VectorFunction`] at `x`, in `f64`.
pub fn values<F: VectorFunction>(f: &F, x: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; f.dim_out()];
    f.eval(x, &mut out);
    out
}

/// The step 1e-6·max(1, |x_j|): small against the coordinate's own size.
pub fn relative_step(xj: f64) -> f64 {
    1e-6 * xj.abs().max(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Known derivatives of polynomials: a central difference is exact for a quadratic
    /// (up to rounding), and its error for a cubic is step²·f'''/6.
    #[test]
    fn known_derivatives() {
        let f = |x: &[f64]| x[0] * x[0] + 3.0 * x[0] * x[1];
        let g = gradient(f, &[2.0, -1.0], 1e-3);
        assert!(
            (g[0] - 1.0).abs() < 1e-9 && (g[1] - 6.0).abs() < 1e-9,
            "{g:?}"
        );
        let cubic = central(|t| (1.0 + t).powi(3), 1e-2);
        assert!((cubic - (3.0 + 1e-4)).abs() < 1e-12, "{cubic}");
        let j = jacobian(|x| vec![x[0] * x[1], x[1]], &[2.0, 5.0], relative_step);
        let expected = DMatrix::from_row_slice(2, 2, &[5.0, 2.0, 0.0, 1.0]);
        assert!((j - expected).amax() < 1e-8);
        let d = central(|t| along(&[1.0, 2.0], &[0.5, -1.0], t), 1e-6);
        assert!(
            (d[0] - 0.5).abs() < 1e-9 && (d[1] + 1.0).abs() < 1e-9,
            "{d:?}"
        );
    }
}
