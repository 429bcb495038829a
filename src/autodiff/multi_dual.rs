//! A first-order dual number carrying `K` directions at once, unboxed: one value and a
//! `[f64; K]` of directional derivatives, so that one evaluation of a generic function gives
//! its derivative along K seeds for the cost of its value once and K lanes of arithmetic.
//!
//! Each lane does exactly the floating-point operations of [`num_dual::Dual64`]'s ε part in
//! the same order, so lane k of a [`MultiDual`] evaluation is, to the bit, the `Dual64`
//! evaluation seeded along direction k. Nested in num-dual's [`num_dual::Dual`],
//! `Dual<MultiDual<K>>` is the K-direction form of `Dual<Dual64>`: the outer ε carries one
//! direction shared by all lanes (the multipliers of a contracted third derivative), the
//! inner lanes the K seeds (`crate::discrete::midpoint_derivatives` sweeps all column
//! groups of a DEL segment this way).
//!
//! Unlike num-dual's vector duals (`DualSVec`, whose derivative is an `Option` of a
//! nalgebra vector), nothing is boxed or branched on: every lane is always computed.

use std::fmt;
use std::iter::{Product, Sum};
use std::ops::{
    Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Rem, RemAssign, Sub, SubAssign,
};

use num_dual::{DualNum, DualStruct, Mappable};
use num_traits::{FromPrimitive, Inv, Num, One, Signed, Zero};

/// f64 value `re` and its derivatives `eps[k]` along K directions.
#[derive(Clone, Copy, Debug)]
pub struct MultiDual<const K: usize> {
    /// The value.
    pub re: f64,
    /// The derivative along each of the K directions.
    pub eps: [f64; K],
}

impl<const K: usize> MultiDual<K> {
    /// A value with the given derivatives.
    pub const fn new(re: f64, eps: [f64; K]) -> Self {
        MultiDual { re, eps }
    }

    /// A constant: every derivative zero.
    pub const fn constant(re: f64) -> Self {
        MultiDual { re, eps: [0.0; K] }
    }

    /// An input seeded along direction `lane` (derivative 1 there, 0 elsewhere); a constant
    /// when `lane` is `None`.
    pub fn seeded(re: f64, lane: Option<usize>) -> Self {
        let mut x = Self::constant(re);
        if let Some(k) = lane {
            x.eps[k] = 1.0;
        }
        x
    }

    /// f(self) from f's value `f0` and slope `f1` at the real part (ε·f1, as `Dual64`).
    #[inline]
    fn chain(&self, f0: f64, f1: f64) -> Self {
        MultiDual {
            re: f0,
            eps: std::array::from_fn(|k| self.eps[k] * f1),
        }
    }

    /// Lane-wise sum or difference.
    #[inline]
    fn lanes(&self, other: &Self, re: f64, op: impl Fn(f64, f64) -> f64) -> Self {
        MultiDual {
            re,
            eps: std::array::from_fn(|k| op(self.eps[k], other.eps[k])),
        }
    }

    #[inline]
    fn plus(&self, other: &Self) -> Self {
        self.lanes(other, self.re + other.re, |a, b| a + b)
    }

    #[inline]
    fn minus(&self, other: &Self) -> Self {
        self.lanes(other, self.re - other.re, |a, b| a - b)
    }

    /// Product rule, each lane as `Dual64`: ε_a·b + ε_b·a.
    #[inline]
    fn times(&self, other: &Self) -> Self {
        MultiDual {
            re: self.re * other.re,
            eps: std::array::from_fn(|k| self.eps[k] * other.re + other.eps[k] * self.re),
        }
    }

    /// Quotient rule, each lane as `Dual64`: (ε_a·b − ε_b·a)·(1/b)·(1/b).
    #[inline]
    fn over(&self, other: &Self) -> Self {
        let inv = other.re.recip();
        MultiDual {
            re: self.re * inv,
            eps: std::array::from_fn(|k| {
                (self.eps[k] * other.re - other.eps[k] * self.re) * inv * inv
            }),
        }
    }

    /// a mod b = a − b·trunc(a/b): slope 1 in a and −trunc(a/b) in b between the jumps.
    #[inline]
    fn modulo(&self, other: &Self) -> Self {
        let quotient = (self.re / other.re).trunc();
        MultiDual {
            re: self.re % other.re,
            eps: std::array::from_fn(|k| self.eps[k] - other.eps[k] * quotient),
        }
    }

    /// Adds a constant to the value (the lanes unchanged).
    #[inline]
    fn shifted(&self, c: f64) -> Self {
        MultiDual {
            re: self.re + c,
            eps: self.eps,
        }
    }

    /// Subtracts a constant from the value.
    #[inline]
    fn lowered(&self, c: f64) -> Self {
        MultiDual {
            re: self.re - c,
            eps: self.eps,
        }
    }

    /// The value mod a constant (slope 1 between the jumps).
    #[inline]
    fn wrapped(&self, c: f64) -> Self {
        MultiDual {
            re: self.re % c,
            eps: self.eps,
        }
    }

    /// Scales value and every lane by a constant.
    #[inline]
    fn scaled(&self, factor: f64) -> Self {
        MultiDual {
            re: self.re * factor,
            eps: std::array::from_fn(|k| self.eps[k] * factor),
        }
    }

    /// Divides value and every lane by a constant (as `Dual64`, not by its reciprocal).
    #[inline]
    fn divided(&self, divisor: f64) -> Self {
        MultiDual {
            re: self.re / divisor,
            eps: std::array::from_fn(|k| self.eps[k] / divisor),
        }
    }
}

impl<const K: usize> fmt::Display for MultiDual<K> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.re)?;
        for (k, e) in self.eps.iter().enumerate() {
            write!(f, " + {e}ε{k}")?;
        }
        Ok(())
    }
}

impl<const K: usize> From<f64> for MultiDual<K> {
    fn from(re: f64) -> Self {
        Self::constant(re)
    }
}

impl<const K: usize> Zero for MultiDual<K> {
    fn zero() -> Self {
        Self::constant(0.0)
    }
    fn is_zero(&self) -> bool {
        self.re.is_zero()
    }
}

impl<const K: usize> One for MultiDual<K> {
    fn one() -> Self {
        Self::constant(1.0)
    }
}

/// Comparisons look at the value only (as num-dual's).
impl<const K: usize> PartialEq for MultiDual<K> {
    fn eq(&self, other: &Self) -> bool {
        self.re == other.re
    }
}

impl<const K: usize> PartialEq<f64> for MultiDual<K> {
    fn eq(&self, other: &f64) -> bool {
        self.re == *other
    }
}

impl<const K: usize> PartialOrd for MultiDual<K> {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl<const K: usize> PartialOrd<f64> for MultiDual<K> {
    fn partial_cmp(&self, other: &f64) -> Option<std::cmp::Ordering> {
        self.re.partial_cmp(other)
    }
}

impl<const K: usize> Neg for MultiDual<K> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        MultiDual {
            re: -self.re,
            eps: self.eps.map(|e| -e),
        }
    }
}

impl<const K: usize> Neg for &MultiDual<K> {
    type Output = MultiDual<K>;
    #[inline]
    fn neg(self) -> MultiDual<K> {
        -*self
    }
}

/// The binary operator `$op` (and its assignment) between two `MultiDual`s, by value or
/// reference, through the method `$how`; and with an f64 on the right through `$with_f64`.
macro_rules! binary_ops {
    ($op:ident, $method:ident, $assign_op:ident, $assign:ident, $how:ident, $with_f64:ident) => {
        impl<const K: usize> $op for MultiDual<K> {
            type Output = Self;
            #[inline]
            fn $method(self, other: Self) -> Self {
                self.$how(&other)
            }
        }
        impl<const K: usize> $op<&MultiDual<K>> for MultiDual<K> {
            type Output = Self;
            #[inline]
            fn $method(self, other: &Self) -> Self {
                self.$how(other)
            }
        }
        impl<const K: usize> $op<&MultiDual<K>> for &MultiDual<K> {
            type Output = MultiDual<K>;
            #[inline]
            fn $method(self, other: &MultiDual<K>) -> MultiDual<K> {
                self.$how(other)
            }
        }
        impl<const K: usize> $op<MultiDual<K>> for &MultiDual<K> {
            type Output = MultiDual<K>;
            #[inline]
            fn $method(self, other: MultiDual<K>) -> MultiDual<K> {
                self.$how(&other)
            }
        }
        impl<const K: usize> $op<f64> for MultiDual<K> {
            type Output = Self;
            #[inline]
            fn $method(self, other: f64) -> Self {
                self.$with_f64(other)
            }
        }
        impl<const K: usize> $assign_op for MultiDual<K> {
            #[inline]
            fn $assign(&mut self, other: Self) {
                *self = self.$how(&other);
            }
        }
        impl<const K: usize> $assign_op<&MultiDual<K>> for MultiDual<K> {
            #[inline]
            fn $assign(&mut self, other: &Self) {
                *self = self.$how(other);
            }
        }
        impl<const K: usize> $assign_op<f64> for MultiDual<K> {
            #[inline]
            fn $assign(&mut self, other: f64) {
                *self = self.$with_f64(other);
            }
        }
    };
}

binary_ops!(Add, add, AddAssign, add_assign, plus, shifted);
binary_ops!(Sub, sub, SubAssign, sub_assign, minus, lowered);
binary_ops!(Mul, mul, MulAssign, mul_assign, times, scaled);
binary_ops!(Div, div, DivAssign, div_assign, over, divided);
binary_ops!(Rem, rem, RemAssign, rem_assign, modulo, wrapped);

impl<const K: usize> Inv for MultiDual<K> {
    type Output = Self;
    fn inv(self) -> Self {
        self.recip()
    }
}

impl<const K: usize> Sum for MultiDual<K> {
    fn sum<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::zero(), |a, b| a + b)
    }
}

impl<'a, const K: usize> Sum<&'a MultiDual<K>> for MultiDual<K> {
    fn sum<I: Iterator<Item = &'a Self>>(iter: I) -> Self {
        iter.fold(Self::zero(), |a, b| a + b)
    }
}

impl<const K: usize> Product for MultiDual<K> {
    fn product<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::one(), |a, b| a * b)
    }
}

impl<'a, const K: usize> Product<&'a MultiDual<K>> for MultiDual<K> {
    fn product<I: Iterator<Item = &'a Self>>(iter: I) -> Self {
        iter.fold(Self::one(), |a, b| a * b)
    }
}

impl<const K: usize> Num for MultiDual<K> {
    type FromStrRadixErr = <f64 as Num>::FromStrRadixErr;
    fn from_str_radix(s: &str, radix: u32) -> Result<Self, Self::FromStrRadixErr> {
        f64::from_str_radix(s, radix).map(Self::constant)
    }
}

/// Signs as num-dual's: by the value's sign bit (+0 is positive).
impl<const K: usize> Signed for MultiDual<K> {
    fn abs(&self) -> Self {
        if self.is_positive() { *self } else { -*self }
    }
    fn abs_sub(&self, other: &Self) -> Self {
        if self.re > other.re {
            self - other
        } else {
            Self::zero()
        }
    }
    fn signum(&self) -> Self {
        if self.is_positive() {
            Self::one()
        } else if self.is_zero() {
            Self::zero()
        } else {
            -Self::one()
        }
    }
    fn is_positive(&self) -> bool {
        self.re.is_sign_positive()
    }
    fn is_negative(&self) -> bool {
        self.re.is_sign_negative()
    }
}

impl<const K: usize> FromPrimitive for MultiDual<K> {
    fn from_i64(n: i64) -> Option<Self> {
        f64::from_i64(n).map(Self::constant)
    }
    fn from_u64(n: u64) -> Option<Self> {
        f64::from_u64(n).map(Self::constant)
    }
    fn from_f64(n: f64) -> Option<Self> {
        Some(Self::constant(n))
    }
}

impl<const K: usize> DualStruct for MultiDual<K> {
    type Real = f64;
    type Inner = f64;
    fn re(&self) -> f64 {
        self.re
    }
    fn from_inner(inner: &f64) -> Self {
        Self::constant(*inner)
    }
}

impl<const K: usize> Mappable<MultiDual<K>> for MultiDual<K> {
    type Output<O> = O;
    fn map_dual<M: Fn(MultiDual<K>) -> O, O>(self, f: M) -> O {
        f(self)
    }
}

impl<const K: usize> DualNum for MultiDual<K> {
    type Primitive = f64;
    const NDERIV: usize = 1;
    type InnerDual = f64;

    fn from_re(re: f64) -> Self {
        Self::constant(re)
    }
    #[inline]
    fn scale(self, factor: &f64) -> Self {
        self.scaled(*factor)
    }
    #[inline]
    fn recip(&self) -> Self {
        let rec = self.re.recip();
        self.chain(rec, -rec * rec)
    }
    fn powi(&self, n: i32) -> Self {
        match n {
            0 => Self::one(),
            1 => *self,
            2 => self * self,
            _ => {
                let pow3 = self.re.powi(n - 3);
                let f0 = pow3 * self.re * self.re * self.re;
                self.chain(f0, pow3 * self.re * self.re * f64::from(n))
            }
        }
    }
    fn powf(&self, n: f64) -> Self {
        if n == 0.0 {
            Self::one()
        } else if n == 1.0 {
            *self
        } else if (n - 2.0).abs() < f64::EPSILON {
            self * self
        } else {
            let pow3 = self.re.powf(n - 3.0);
            let f0 = pow3 * self.re * self.re * self.re;
            self.chain(f0, pow3 * self.re * self.re * n)
        }
    }
    #[inline]
    fn sqrt(&self) -> Self {
        let f0 = self.re.sqrt();
        self.chain(f0, f0 * self.re.recip() * 0.5)
    }
    fn cbrt(&self) -> Self {
        let f0 = self.re.cbrt();
        self.chain(f0, f0 * self.re.recip() * (1.0 / 3.0))
    }
    fn exp(&self) -> Self {
        let f = self.re.exp();
        self.chain(f, f)
    }
    fn exp2(&self) -> Self {
        let f0 = self.re.exp2();
        self.chain(f0, f0 * std::f64::consts::LN_2)
    }
    fn exp_m1(&self) -> Self {
        self.chain(self.re.exp_m1(), self.re.exp())
    }
    fn ln(&self) -> Self {
        self.chain(self.re.ln(), self.re.recip())
    }
    fn log(&self, base: f64) -> Self {
        self.chain(self.re.log(base), self.re.recip() / base.ln())
    }
    fn log2(&self) -> Self {
        self.chain(self.re.log2(), self.re.recip() / std::f64::consts::LN_2)
    }
    fn log10(&self) -> Self {
        self.chain(self.re.log10(), self.re.recip() / std::f64::consts::LN_10)
    }
    fn ln_1p(&self) -> Self {
        self.chain(self.re.ln_1p(), (self.re + 1.0).recip())
    }
    #[inline]
    fn sin(&self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(s, c)
    }
    #[inline]
    fn cos(&self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(c, -s)
    }
    #[inline]
    fn sin_cos(&self) -> (Self, Self) {
        let (s, c) = self.re.sin_cos();
        (self.chain(s, c), self.chain(c, -s))
    }
    fn tan(&self) -> Self {
        let (s, c) = self.sin_cos();
        s / c
    }
    fn asin(&self) -> Self {
        let rec = (1.0 - self.re * self.re).recip();
        self.chain(self.re.asin(), rec.sqrt())
    }
    fn acos(&self) -> Self {
        let rec = (1.0 - self.re * self.re).recip();
        self.chain(self.re.acos(), -rec.sqrt())
    }
    fn atan(&self) -> Self {
        self.chain(self.re.atan(), (1.0 + self.re * self.re).recip())
    }
    fn atan2(&self, other: Self) -> Self {
        let mut angle = (self / other).atan();
        angle.re = self.re.atan2(other.re);
        angle
    }
    fn sinh(&self) -> Self {
        self.chain(self.re.sinh(), self.re.cosh())
    }
    fn cosh(&self) -> Self {
        self.chain(self.re.cosh(), self.re.sinh())
    }
    fn tanh(&self) -> Self {
        self.sinh() / self.cosh()
    }
    fn asinh(&self) -> Self {
        let rec = (1.0 + self.re * self.re).recip();
        self.chain(self.re.asinh(), rec.sqrt())
    }
    fn acosh(&self) -> Self {
        let rec = (self.re * self.re - 1.0).recip();
        self.chain(self.re.acosh(), rec.sqrt())
    }
    fn atanh(&self) -> Self {
        self.chain(self.re.atanh(), (1.0 - self.re * self.re).recip())
    }
    fn sph_j0(&self) -> Self {
        if self.re.abs() < f64::EPSILON {
            Self::one() - self * self / 6.0
        } else {
            self.sin() / self
        }
    }
    fn sph_j1(&self) -> Self {
        if self.re.abs() < f64::EPSILON {
            *self / 3.0
        } else {
            let (s, c) = self.sin_cos();
            (s - self * c) / (self * self)
        }
    }
    fn sph_j2(&self) -> Self {
        if self.re.abs() < f64::EPSILON {
            self * self / 15.0
        } else {
            let (s, c) = self.sin_cos();
            let s2 = self * self;
            ((s - self * c) * 3.0 - s2 * s) / (s2 * self)
        }
    }
    #[inline]
    fn mul_add(&self, a: Self, b: Self) -> Self {
        *self * a + b
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::Scalar;
    use crate::autodiff::finite_differences::central;
    use num_dual::{Dual, Dual64};

    /// A function using every operation the model code does and most others: products,
    /// quotients, constants on either side, trigonometry, roots, powers, logarithms.
    fn f<D: Scalar>(x: &[D]) -> D {
        let (s, c) = (x[0] * x[1]).sin_cos();
        let mut acc = s * x[2] - c / (x[3] * x[3] + 2.0);
        acc += (x[1] - x[2]).cos() * 0.7 + x[0].sin() * 1.3;
        acc -= (x[2] * x[2] + 1.0).sqrt() / 3.0;
        acc *= x[3].exp() * 0.25 + 1.0;
        acc += (x[0] + 3.0).ln() + x[1].powi(3) - x[2].powf(2.5) * 0.1 + x[3].recip();
        acc += x[0].atan2(x[1]) + x[2].tanh() + x[3].cbrt() + (-x[1]).abs();
        acc + x[0].mul_add(x[1], x[2]) - x[3].sph_j1() + x[1].asinh() + (x[0] * 0.5).asin()
    }

    const X: [f64; 4] = [0.31, -0.72, 1.13, 0.64];

    /// Each lane of one evaluation equals, to the bit, the `Dual64` evaluation seeded along
    /// that lane's direction, and central differences.
    #[test]
    fn lanes_are_dual64_passes_and_match_differences() {
        const K: usize = 3;
        let dirs: [[f64; 4]; K] = [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 1.0, 0.0],
            [0.3, -0.2, 0.5, 0.9],
        ];
        let x: Vec<MultiDual<K>> = (0..4)
            .map(|i| MultiDual::new(X[i], std::array::from_fn(|k| dirs[k][i])))
            .collect();
        let y = f(&x);
        assert_eq!(y.re.to_bits(), f(&X).to_bits());
        for (k, dir) in dirs.iter().enumerate() {
            let single: Vec<Dual64> = (0..4).map(|i| Dual64::new(X[i], dir[i])).collect();
            let reference = f(&single);
            assert_eq!(y.eps[k].to_bits(), reference.eps.to_bits(), "lane {k}");
            let at = |t: f64| f(&std::array::from_fn::<f64, 4, _>(|i| X[i] + t * dir[i]));
            let fd = central(at, 1e-6);
            assert!(
                (y.eps[k] - fd).abs() <= 1e-8 * fd.abs().max(1.0),
                "lane {k}: {} against differences {fd}",
                y.eps[k]
            );
        }
    }

    /// Nested in `Dual`, the outer ε along a shared direction: lane k's mixed part is the
    /// `Dual<Dual64>` pass seeded along k, to the bit, and the second derivative along both
    /// directions by central differences of the first.
    #[test]
    fn nested_lanes_are_nested_dual64_passes() {
        const K: usize = 2;
        let seeds: [[f64; 4]; K] = [[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 0.0, 1.0]];
        let shared = [0.4, -0.6, 0.2, 0.8];
        let x: Vec<Dual<MultiDual<K>>> = (0..4)
            .map(|i| {
                Dual::new(
                    MultiDual::new(X[i], std::array::from_fn(|k| seeds[k][i])),
                    MultiDual::constant(shared[i]),
                )
            })
            .collect();
        let y = f(&x);
        for (k, seed) in seeds.iter().enumerate() {
            let single: Vec<Dual<Dual64>> = (0..4)
                .map(|i| Dual::new(Dual64::new(X[i], seed[i]), Dual64::from(shared[i])))
                .collect();
            let reference = f(&single);
            for (ours, theirs) in [
                (y.re.re, reference.re.re),
                (y.re.eps[k], reference.re.eps),
                (y.eps.re, reference.eps.re),
                (y.eps.eps[k], reference.eps.eps),
            ] {
                assert_eq!(ours.to_bits(), theirs.to_bits(), "lane {k}");
            }
            // d/dt of the seed's directional derivative at X + t·shared.
            let along = |t: f64| {
                let lifted: Vec<Dual64> = (0..4)
                    .map(|i| Dual64::new(X[i] + t * shared[i], seed[i]))
                    .collect();
                f(&lifted).eps
            };
            let fd = central(along, 1e-5);
            assert!(
                (y.eps.eps[k] - fd).abs() <= 1e-7 * fd.abs().max(1.0),
                "lane {k}: {} against differences {fd}",
                y.eps.eps[k]
            );
        }
    }

    /// Remainder, comparisons, sums and the constructors.
    #[test]
    fn remainder_comparisons_and_constructors() {
        let a = MultiDual::<2>::new(7.5, [1.0, 2.0]);
        let b = MultiDual::<2>::new(2.0, [0.5, -1.0]);
        // 7.5 mod 2 = 1.5 = a − 3b: slopes ε_a − 3 ε_b.
        let r = a % b;
        assert_eq!((r.re, r.eps), (1.5, [-0.5, 5.0]));
        assert!(b < a && a > 7.0 && a == 7.5);
        let total: MultiDual<2> = [a, b].iter().sum();
        assert_eq!((total.re, total.eps), (9.5, [1.5, 1.0]));
        let seeded = MultiDual::<3>::seeded(4.0, Some(1));
        assert_eq!((seeded.re, seeded.eps), (4.0, [0.0, 1.0, 0.0]));
        assert_eq!(MultiDual::<3>::seeded(4.0, None).eps, [0.0; 3]);
        assert_eq!((-a).abs().eps, a.eps);
    }
}
