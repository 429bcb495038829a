//! Dense local derivatives of small functions that are generic over the scalar type.
//!
//! Every NLP block depends on a handful of variables (at most 2n + 1 = 77 for the
//! 38-coordinate robot). Its derivatives are taken by *tiled* forward mode with one static
//! tile size [`TILE`], so that any input dimension works with one monomorphisation:
//! - Jacobians by [`num_dual::DualSVec64<TILE>`] passes over column chunks of `TILE` inputs;
//! - Hessians by [`num_dual::HyperDualSVec64<TILE, TILE>`] passes over pairs of chunks
//!   (the lower block triangle only, mirrored);
//! - the third derivative contracted with a direction by nesting a [`num_dual::Dual64`]
//!   inside, whose inner ε of every input carries the direction: one pass yields the Hessian
//!   (real parts) and the Hessian of the directional derivative (ε parts).
//!
//! - [`jacobian_directional`]: a Jacobian and its directional derivative by first-order passes
//!   of `DualVec<Dual64, T>`; applied to a gradient function (an adjoint sweep) it gives the
//!   Hessian and the contracted third derivative without hyper-duals.
//!
//! Unseeded derivative parts of `num-dual` are `None` and cost nothing, so a pass only pays for
//! the inputs of its chunks.

mod coloring;
pub mod dependency;
mod directional;
pub mod finite_differences;
mod hessian;
mod jacobian;
mod multi_dual;
mod restrict;
mod scalar;
mod third;

pub use coloring::{SymmetricGroups, grouped_hessian};
pub use directional::*;
pub use hessian::*;
pub use jacobian::*;
pub use multi_dual::MultiDual;
pub use restrict::Restricted;
pub use scalar::Scalar;
pub use third::*;

/// Tile size (inputs per forward pass) of the public drivers.
///
/// Per pass, work grows like T² while the number of passes falls like (n/T)²/2; the
/// `_into` variants take any tile size for comparison (see `benches/derivatives.rs`).
pub const TILE: usize = 8;

/// A scalar function of `dim()` inputs, written once for every scalar type.
pub trait ScalarFunction {
    /// Number of inputs (the length of `z` in [`ScalarFunction::eval`]).
    fn dim(&self) -> usize;
    /// Value at `z` (length `dim()`).
    fn eval<D: Scalar>(&self, z: &[D]) -> D;
}

/// A vector function R^`dim_in()` → R^`dim_out()`, written once for every scalar type.
pub trait VectorFunction {
    /// Number of inputs (the length of `z`).
    fn dim_in(&self) -> usize;
    /// Number of outputs (the length of `out`).
    fn dim_out(&self) -> usize;
    /// Writes the values at `z` (length `dim_in()`) into `out` (length `dim_out()`, every entry
    /// overwritten).
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]);
}

/// Number of tiles of size `tile` needed to cover `n` inputs.
fn tile_count(n: usize, tile: usize) -> usize {
    n.div_ceil(tile)
}

/// Index range of tile `c` of size `tile` within `n` inputs.
fn tile_range(c: usize, tile: usize, n: usize) -> std::ops::Range<usize> {
    let start = c * tile;
    start..(start + tile).min(n)
}

#[cfg(test)]
pub(crate) mod test_functions {
    //! Closed-form test functions shared by the unit tests of this module.
    use super::{ScalarFunction, VectorFunction};
    use crate::autodiff::Scalar;

    /// f(z) = Σ_i c_i z_i³ + (Σ_i z_i)·sin(Σ_i i·z_i) + exp(z_0 z_{n−1}): every pair of inputs
    /// couples and every third derivative is nonzero.
    pub struct Coupled {
        pub n: usize,
    }

    impl ScalarFunction for Coupled {
        fn dim(&self) -> usize {
            self.n
        }
        fn eval<D: Scalar>(&self, z: &[D]) -> D {
            let mut cubic = D::zero();
            let mut sum = D::zero();
            let mut weighted = D::zero();
            for (i, &zi) in z.iter().enumerate() {
                cubic += zi * zi * zi * (0.5 + 0.1 * i as f64);
                sum += zi;
                weighted += zi * (i as f64 + 1.0) * 0.3;
            }
            cubic + sum * weighted.sin() + (z[0] * z[self.n - 1]).exp()
        }
    }

    /// f(z) = z_0² z_1 + sin z_1: two inputs, with ∇f, ∇²f and ∂³f in closed form.
    pub struct ClosedForm;

    impl ScalarFunction for ClosedForm {
        fn dim(&self) -> usize {
            2
        }
        fn eval<D: Scalar>(&self, z: &[D]) -> D {
            z[0] * z[0] * z[1] + z[1].sin()
        }
    }

    /// g(z)_j = Coupled restricted to a rotation of z, times (j + 1): m outputs.
    pub struct CoupledVector {
        pub n: usize,
        pub m: usize,
    }

    impl VectorFunction for CoupledVector {
        fn dim_in(&self) -> usize {
            self.n
        }
        fn dim_out(&self) -> usize {
            self.m
        }
        fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
            let base = Coupled { n: self.n };
            let mut rotated = z.to_vec();
            for (j, o) in out.iter_mut().enumerate() {
                *o = base.eval(&rotated) * (j as f64 + 1.0);
                rotated.rotate_left(1);
            }
        }
    }

    /// Deterministic pseudo-random point in (−0.5, 0.5)^n.
    pub fn point(n: usize, seed: u64) -> Vec<f64> {
        let mut rng = crate::random::SeededRng::new(seed);
        rng.next_u64(); // mixes the seed, as the points the tests were written against did
        (0..n).map(|_| rng.unit() - 0.5).collect()
    }

    /// The dimensions every driver is tested on: 1, T−1, T, T+1 and 2T+3.
    pub fn dims() -> [usize; 5] {
        let t = super::TILE;
        [1, t - 1, t, t + 1, 2 * t + 3]
    }
}
