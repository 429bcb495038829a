//! A function restricted to some of its inputs, the others held at fixed values: its
//! derivatives are the corresponding sub-blocks of the full function's, for fewer passes.

use super::{ScalarFunction, VectorFunction};
use crate::autodiff::Scalar;

/// `f` as a function of the inputs `free` only; every other input stays at its value in `at`.
pub struct Restricted<'a, F> {
    /// The full function.
    pub f: &'a F,
    /// The point whose other inputs are held.
    pub at: &'a [f64],
    /// Indices (into `at`) of the inputs left free, in the order of the restricted inputs.
    pub free: &'a [usize],
}

impl<F> Restricted<'_, F> {
    /// The free inputs' values at `at`, the point to differentiate the restriction at.
    pub fn point(&self) -> Vec<f64> {
        self.free.iter().map(|&i| self.at[i]).collect()
    }

    fn expand<D: Scalar>(&self, z: &[D]) -> Vec<D> {
        let mut full: Vec<D> = self.at.iter().map(|&v| D::from(v)).collect();
        for (&i, &v) in self.free.iter().zip(z) {
            full[i] = v;
        }
        full
    }
}

impl<F: ScalarFunction> ScalarFunction for Restricted<'_, F> {
    fn dim(&self) -> usize {
        self.free.len()
    }
    fn eval<D: Scalar>(&self, z: &[D]) -> D {
        self.f.eval(&self.expand(z))
    }
}

impl<F: VectorFunction> VectorFunction for Restricted<'_, F> {
    fn dim_in(&self) -> usize {
        self.free.len()
    }
    fn dim_out(&self) -> usize {
        self.f.dim_out()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        self.f.eval(&self.expand(z), out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::test_functions::{Coupled, CoupledVector, point};
    use crate::autodiff::{gradient_hessian, weighted_hessian};

    /// The restriction's Hessians are the full Hessians' sub-blocks.
    #[test]
    fn hessians_are_sub_blocks() {
        let (n, m) = (11, 3);
        let z = point(n, 7);
        let free = [1, 4, 5, 9];
        let scalar = Coupled { n };
        let full = gradient_hessian(&scalar, &z).2;
        let r = Restricted {
            f: &scalar,
            at: &z,
            free: &free,
        };
        let sub = gradient_hessian(&r, &r.point()).2;
        let vector = CoupledVector { n, m };
        let w = [0.3, -1.2, 0.7];
        let full_w = weighted_hessian(&vector, &z, &w);
        let rv = Restricted {
            f: &vector,
            at: &z,
            free: &free,
        };
        let sub_w = weighted_hessian(&rv, &rv.point(), &w);
        for (a, &i) in free.iter().enumerate() {
            for (b, &j) in free.iter().enumerate() {
                assert!((sub[(a, b)] - full[(i, j)]).abs() <= 1e-12 * full[(i, j)].abs().max(1.0));
                assert!(
                    (sub_w[(a, b)] - full_w[(i, j)]).abs() <= 1e-12 * full_w[(i, j)].abs().max(1.0)
                );
                assert!(full[(i, j)] != 0.0, "the test function couples every pair");
            }
        }
    }
}
