//! The one scalar bound of all model code: plain `f64` and every (nested) dual number of
//! `num-dual` satisfy it, so each formula is written once and differentiated by forward AD.
//!
//! Never bound model code on nalgebra's `RealField`: nested duals are not `RealField`.
//! Use `D::from(x)` to lift an `f64` constant and `x.re()` to branch on the real part.

use num_dual::DualNum;

/// A number that model code can compute with: `f64` or a (nested) `num-dual` dual number.
pub trait Scalar: DualNum<Primitive = f64> + Copy + Send + Sync {}

impl<T: DualNum<Primitive = f64> + Copy + Send + Sync> Scalar for T {}
