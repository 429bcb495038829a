//! A dependency-tracking scalar: which inputs a value depends on, and which pairs of inputs
//! can interact in its second derivative, whatever their values.
//!
//! Run once through the same generic model code as `f64` and the dual numbers, it gives each
//! block's sparsity structure by construction: an entry is in the structure when the
//! function can depend on it *anywhere* in the domain, never because it happens to be nonzero
//! at a sample point (a smooth step's slope is exactly 0.0 in floating point far from its
//! edge). Forward duals over [`DependencyScalar`] give the structure of derivatives too: the
//! ε part of `Dual<DependencyScalar>` seeded along input a depends on the inputs of ∂f/∂a.
//!
//! Rules (conservative, exact on structural zeros): x ± y unions the dependencies and the
//! pairs; x·y adds the cross pairs D(x)×D(y); x/y adds D(x)×D(y) and D(y)×D(y); any other
//! nonlinear function f(x) adds D(x)×D(x). A constant (no dependencies) that is 0.0 is zero
//! everywhere, so multiplying by it gives a constant zero: that is how the zero ε parts of
//! forward duals, and zero entries of constant matrices, keep their structural zeros.
//!
//! A comparison of a value that depends on inputs is a branch whose other side this run does
//! not see; it is recorded ([`Trace::branched`]) and the caller must then treat the function
//! as dense.
//!
//! The tape is thread-local: a trace lives on one thread, between [`Trace::begin`] and the
//! end of the returned guard.

use std::cell::RefCell;
use std::cmp::Ordering;
use std::fmt;
use std::iter::{Product, Sum};
use std::ops::{
    Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Rem, RemAssign, Sub, SubAssign,
};

use num_dual::{DualNum, DualStruct, Mappable};
use num_traits::{FromPrimitive, Inv, Num, One, Signed, Zero};

/// Node id of a constant (depends on no input).
const CONSTANT: u32 = u32::MAX;

/// The nodes of one trace: per node, a bitset of the inputs it depends on and the symmetric
/// bit matrix of the input pairs in its second derivative.
#[derive(Default)]
struct Tape {
    inputs: usize,
    words: usize,
    nodes: usize,
    deps: Vec<u64>,
    pairs: Vec<u64>,
    branched: bool,
}

thread_local! {
    static TAPE: RefCell<Tape> = RefCell::new(Tape::default());
}

impl Tape {
    fn push(&mut self) -> usize {
        let id = self.nodes;
        self.nodes += 1;
        self.deps.resize(self.nodes * self.words, 0);
        self.pairs.resize(self.nodes * self.inputs * self.words, 0);
        id
    }

    fn dep_range(&self, node: usize) -> std::ops::Range<usize> {
        node * self.words..(node + 1) * self.words
    }

    fn pair_range(&self, node: usize) -> std::ops::Range<usize> {
        let len = self.inputs * self.words;
        node * len..(node + 1) * len
    }

    /// OR node `src`'s dependencies and pairs into node `dst`.
    fn union(&mut self, dst: usize, src: usize) {
        let (d, s) = (self.dep_range(dst), self.dep_range(src));
        for k in 0..self.words {
            self.deps[d.start + k] |= self.deps[s.start + k];
        }
        let (d, s) = (self.pair_range(dst), self.pair_range(src));
        for k in 0..d.len() {
            self.pairs[d.start + k] |= self.pairs[s.start + k];
        }
    }

    /// Add the pairs D(a)×D(b) and D(b)×D(a) to node `dst`.
    fn cross(&mut self, dst: usize, a: usize, b: usize) {
        let da: Vec<u64> = self.deps[self.dep_range(a)].to_vec();
        let db: Vec<u64> = self.deps[self.dep_range(b)].to_vec();
        let base = self.pair_range(dst).start;
        for (from, to) in [(&da, &db), (&db, &da)] {
            for i in bits(from) {
                let row = base + i * self.words;
                for (cell, word) in self.pairs[row..row + self.words].iter_mut().zip(to) {
                    *cell |= word;
                }
            }
        }
    }

    /// A new node: the union of the operands, with cross pairs between the two and squares
    /// of either as the operation requires.
    fn combine(&mut self, operands: &[u32], cross: bool, square: &[bool]) -> u32 {
        let id = self.push();
        for &o in operands {
            if o != CONSTANT {
                self.union(id, o as usize);
            }
        }
        if cross && operands.len() == 2 && !operands.contains(&CONSTANT) {
            self.cross(id, operands[0] as usize, operands[1] as usize);
        }
        for (&o, &sq) in operands.iter().zip(square) {
            if sq && o != CONSTANT {
                self.cross(id, o as usize, o as usize);
            }
        }
        u32::try_from(id).unwrap_or(CONSTANT - 1)
    }
}

/// Indices of the set bits of a bitset.
fn bits(set: &[u64]) -> impl Iterator<Item = usize> + '_ {
    set.iter().enumerate().flat_map(|(w, &word)| {
        (0..64)
            .filter(move |b| word >> b & 1 == 1)
            .map(move |b| w * 64 + b)
    })
}

fn with_tape<R>(f: impl FnOnce(&mut Tape) -> R) -> R {
    TAPE.with(|t| f(&mut t.borrow_mut()))
}

/// A value with the set of inputs it depends on (see the module documentation).
#[derive(Clone, Copy)]
pub struct DependencyScalar {
    value: f64,
    node: u32,
}

/// The guard of one dependency trace on this thread; the tape is cleared when it drops.
pub struct Trace {
    _private: (),
}

impl Trace {
    /// Start a trace over `inputs` inputs (clears any previous one on this thread).
    pub fn begin(inputs: usize) -> Trace {
        with_tape(|t| {
            *t = Tape {
                inputs,
                words: inputs.div_ceil(64).max(1),
                ..Tape::default()
            };
        });
        Trace { _private: () }
    }

    /// Input `index` with the given value.
    pub fn input(&self, index: usize, value: f64) -> DependencyScalar {
        let node = with_tape(|t| {
            let id = t.push();
            let r = t.dep_range(id);
            t.deps[r.start + index / 64] |= 1 << (index % 64);
            id
        });
        DependencyScalar {
            value,
            node: u32::try_from(node).unwrap_or(CONSTANT - 1),
        }
    }

    /// Inputs 0.. with the values `z`.
    pub fn inputs(&self, z: &[f64]) -> Vec<DependencyScalar> {
        z.iter()
            .enumerate()
            .map(|(a, &v)| self.input(a, v))
            .collect()
    }

    /// The inputs `x` depends on, as a mask over the inputs.
    pub fn dependencies(&self, x: &DependencyScalar) -> Vec<bool> {
        with_tape(|t| {
            let mut mask = vec![false; t.inputs];
            if x.node != CONSTANT {
                for i in bits(&t.deps[t.dep_range(x.node as usize)]) {
                    mask[i] = true;
                }
            }
            mask
        })
    }

    /// Add the input pairs (a, c) in the second derivative of `x` to `mask` (row-major,
    /// inputs × inputs, symmetric).
    pub fn add_pairs(&self, x: &DependencyScalar, mask: &mut [bool]) {
        with_tape(|t| {
            if x.node == CONSTANT {
                return;
            }
            let base = t.pair_range(x.node as usize).start;
            for a in 0..t.inputs {
                let row = &t.pairs[base + a * t.words..base + (a + 1) * t.words];
                for c in bits(row) {
                    mask[a * t.inputs + c] = true;
                }
            }
        })
    }

    /// Whether the traced code compared a value that depends on inputs (a branch).
    pub fn branched(&self) -> bool {
        with_tape(|t| t.branched)
    }
}

impl Drop for Trace {
    fn drop(&mut self) {
        with_tape(|t| *t = Tape::default());
    }
}

impl DependencyScalar {
    fn constant(value: f64) -> Self {
        DependencyScalar {
            value,
            node: CONSTANT,
        }
    }

    fn is_constant(&self) -> bool {
        self.node == CONSTANT
    }

    /// A function of `self` with the same dependencies and pairs (e.g. −x, x + c, c·x).
    fn linear(&self, value: f64) -> Self {
        DependencyScalar {
            value,
            node: self.node,
        }
    }

    /// A nonlinear function of `self` with value `value`.
    fn nonlinear(&self, value: f64) -> Self {
        if self.is_constant() {
            return Self::constant(value);
        }
        let node = with_tape(|t| t.combine(&[self.node], false, &[true]));
        DependencyScalar { value, node }
    }

    /// A function of two operands: `cross` when they multiply, `square` per operand when it
    /// enters nonlinearly by itself.
    fn binary(&self, other: &Self, value: f64, cross: bool, square: [bool; 2]) -> Self {
        if self.is_constant() && other.is_constant() {
            return Self::constant(value);
        }
        let node = with_tape(|t| t.combine(&[self.node, other.node], cross, &square));
        DependencyScalar { value, node }
    }

    fn is_constant_zero(&self) -> bool {
        self.is_constant() && self.value == 0.0
    }

    /// Record a branch on this value (a comparison whose outcome depends on the inputs).
    fn compared(&self) {
        if !self.is_constant() {
            with_tape(|t| t.branched = true);
        }
    }

    fn add(self, o: Self) -> Self {
        match (self.is_constant(), o.is_constant()) {
            (true, _) => o.linear(self.value + o.value),
            (_, true) => self.linear(self.value + o.value),
            _ => self.binary(&o, self.value + o.value, false, [false, false]),
        }
    }

    fn mul(self, o: Self) -> Self {
        let value = self.value * o.value;
        if self.is_constant_zero() || o.is_constant_zero() {
            return Self::constant(0.0);
        }
        match (self.is_constant(), o.is_constant()) {
            (true, _) => o.linear(value),
            (_, true) => self.linear(value),
            _ => self.binary(&o, value, true, [false, false]),
        }
    }

    fn div(self, o: Self) -> Self {
        let value = self.value / o.value;
        if self.is_constant_zero() {
            return Self::constant(0.0);
        }
        if o.is_constant() {
            return self.linear(value);
        }
        self.binary(&o, value, true, [false, true])
    }
}

impl fmt::Debug for DependencyScalar {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_constant() {
            write!(f, "{} (constant)", self.value)
        } else {
            write!(f, "{} (node {})", self.value, self.node)
        }
    }
}

impl fmt::Display for DependencyScalar {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.value)
    }
}

impl From<f64> for DependencyScalar {
    fn from(value: f64) -> Self {
        Self::constant(value)
    }
}

impl Zero for DependencyScalar {
    fn zero() -> Self {
        Self::constant(0.0)
    }
    fn is_zero(&self) -> bool {
        // Only a constant zero is zero everywhere: branching on it is exact.
        self.is_constant_zero()
    }
}

impl One for DependencyScalar {
    fn one() -> Self {
        Self::constant(1.0)
    }
}

impl PartialEq for DependencyScalar {
    fn eq(&self, other: &Self) -> bool {
        self.compared();
        other.compared();
        self.value == other.value
    }
}

impl PartialEq<f64> for DependencyScalar {
    fn eq(&self, other: &f64) -> bool {
        self.compared();
        self.value == *other
    }
}

impl PartialOrd for DependencyScalar {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        self.compared();
        other.compared();
        self.value.partial_cmp(&other.value)
    }
}

impl PartialOrd<f64> for DependencyScalar {
    fn partial_cmp(&self, other: &f64) -> Option<Ordering> {
        self.compared();
        self.value.partial_cmp(other)
    }
}

impl Neg for DependencyScalar {
    type Output = Self;
    fn neg(self) -> Self {
        self.linear(-self.value)
    }
}

impl Neg for &DependencyScalar {
    type Output = DependencyScalar;
    fn neg(self) -> DependencyScalar {
        self.linear(-self.value)
    }
}

macro_rules! binary_ops {
    ($trait:ident, $method:ident, $assign_trait:ident, $assign:ident, $f:path) => {
        impl $trait for DependencyScalar {
            type Output = Self;
            fn $method(self, o: Self) -> Self {
                $f(self, o)
            }
        }
        impl<'a> $trait<&'a DependencyScalar> for DependencyScalar {
            type Output = Self;
            fn $method(self, o: &'a Self) -> Self {
                $f(self, *o)
            }
        }
        impl<'a> $trait<&'a DependencyScalar> for &DependencyScalar {
            type Output = DependencyScalar;
            fn $method(self, o: &'a DependencyScalar) -> DependencyScalar {
                $f(*self, *o)
            }
        }
        impl $trait<DependencyScalar> for &DependencyScalar {
            type Output = DependencyScalar;
            fn $method(self, o: DependencyScalar) -> DependencyScalar {
                $f(*self, o)
            }
        }
        impl $trait<f64> for DependencyScalar {
            type Output = Self;
            fn $method(self, o: f64) -> Self {
                $f(self, DependencyScalar::constant(o))
            }
        }
        impl $trait<f64> for &DependencyScalar {
            type Output = DependencyScalar;
            fn $method(self, o: f64) -> DependencyScalar {
                $f(*self, DependencyScalar::constant(o))
            }
        }
        impl $assign_trait for DependencyScalar {
            fn $assign(&mut self, o: Self) {
                *self = $f(*self, o);
            }
        }
        impl<'a> $assign_trait<&'a DependencyScalar> for DependencyScalar {
            fn $assign(&mut self, o: &'a Self) {
                *self = $f(*self, *o);
            }
        }
        impl $assign_trait<f64> for DependencyScalar {
            fn $assign(&mut self, o: f64) {
                *self = $f(*self, DependencyScalar::constant(o));
            }
        }
    };
}

fn subtract(a: DependencyScalar, b: DependencyScalar) -> DependencyScalar {
    DependencyScalar::add(a, -b)
}

/// x mod y jumps where x/y crosses an integer: a branch.
fn remainder(a: DependencyScalar, b: DependencyScalar) -> DependencyScalar {
    a.compared();
    b.compared();
    a.binary(&b, a.value % b.value, true, [true, true])
}

binary_ops!(Add, add, AddAssign, add_assign, DependencyScalar::add);
binary_ops!(Sub, sub, SubAssign, sub_assign, subtract);
binary_ops!(Mul, mul, MulAssign, mul_assign, DependencyScalar::mul);
binary_ops!(Div, div, DivAssign, div_assign, DependencyScalar::div);
binary_ops!(Rem, rem, RemAssign, rem_assign, remainder);

impl Inv for DependencyScalar {
    type Output = Self;
    fn inv(self) -> Self {
        self.nonlinear(1.0 / self.value)
    }
}

impl Sum for DependencyScalar {
    fn sum<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::zero(), |a, b| a + b)
    }
}

impl<'a> Sum<&'a DependencyScalar> for DependencyScalar {
    fn sum<I: Iterator<Item = &'a Self>>(iter: I) -> Self {
        iter.fold(Self::zero(), |a, b| a + *b)
    }
}

impl Product for DependencyScalar {
    fn product<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::one(), |a, b| a * b)
    }
}

impl<'a> Product<&'a DependencyScalar> for DependencyScalar {
    fn product<I: Iterator<Item = &'a Self>>(iter: I) -> Self {
        iter.fold(Self::one(), |a, b| a * *b)
    }
}

impl Num for DependencyScalar {
    type FromStrRadixErr = <f64 as Num>::FromStrRadixErr;
    fn from_str_radix(s: &str, radix: u32) -> Result<Self, Self::FromStrRadixErr> {
        f64::from_str_radix(s, radix).map(Self::constant)
    }
}

impl Signed for DependencyScalar {
    fn abs(&self) -> Self {
        self.nonlinear(self.value.abs())
    }
    fn abs_sub(&self, other: &Self) -> Self {
        self.compared();
        other.compared();
        self.binary(
            other,
            (self.value - other.value).max(0.0),
            false,
            [true, true],
        )
    }
    fn signum(&self) -> Self {
        self.compared();
        Self::constant(self.value.signum())
    }
    fn is_positive(&self) -> bool {
        self.compared();
        self.value > 0.0
    }
    fn is_negative(&self) -> bool {
        self.compared();
        self.value < 0.0
    }
}

impl FromPrimitive for DependencyScalar {
    fn from_i64(n: i64) -> Option<Self> {
        Some(Self::constant(n as f64))
    }
    fn from_u64(n: u64) -> Option<Self> {
        Some(Self::constant(n as f64))
    }
    fn from_f64(n: f64) -> Option<Self> {
        Some(Self::constant(n))
    }
}

impl DualStruct for DependencyScalar {
    type Real = f64;
    type Inner = f64;
    fn re(&self) -> f64 {
        self.value
    }
    fn from_inner(inner: &f64) -> Self {
        Self::constant(*inner)
    }
}

impl Mappable<DependencyScalar> for DependencyScalar {
    type Output<O> = O;
    fn map_dual<M: Fn(DependencyScalar) -> O, O>(self, f: M) -> O {
        f(self)
    }
}

impl DualNum for DependencyScalar {
    type Primitive = f64;
    const NDERIV: usize = 0;
    type InnerDual = f64;

    fn from_re(re: f64) -> Self {
        Self::constant(re)
    }
    fn scale(self, factor: &f64) -> Self {
        self * *factor
    }
    fn recip(&self) -> Self {
        self.nonlinear(self.value.recip())
    }
    fn powi(&self, n: i32) -> Self {
        match n {
            0 => Self::constant(1.0),
            1 => *self,
            _ => self.nonlinear(self.value.powi(n)),
        }
    }
    fn powf(&self, n: f64) -> Self {
        if n == 0.0 {
            Self::constant(1.0)
        } else if n == 1.0 {
            *self
        } else {
            self.nonlinear(self.value.powf(n))
        }
    }
    fn sqrt(&self) -> Self {
        self.nonlinear(self.value.sqrt())
    }
    fn cbrt(&self) -> Self {
        self.nonlinear(self.value.cbrt())
    }
    fn exp(&self) -> Self {
        self.nonlinear(self.value.exp())
    }
    fn exp2(&self) -> Self {
        self.nonlinear(self.value.exp2())
    }
    fn exp_m1(&self) -> Self {
        self.nonlinear(self.value.exp_m1())
    }
    fn ln(&self) -> Self {
        self.nonlinear(self.value.ln())
    }
    fn log(&self, base: f64) -> Self {
        self.nonlinear(self.value.log(base))
    }
    fn log2(&self) -> Self {
        self.nonlinear(self.value.log2())
    }
    fn log10(&self) -> Self {
        self.nonlinear(self.value.log10())
    }
    fn ln_1p(&self) -> Self {
        self.nonlinear(self.value.ln_1p())
    }
    fn sin(&self) -> Self {
        self.nonlinear(self.value.sin())
    }
    fn cos(&self) -> Self {
        self.nonlinear(self.value.cos())
    }
    fn tan(&self) -> Self {
        self.nonlinear(self.value.tan())
    }
    fn sin_cos(&self) -> (Self, Self) {
        (self.sin(), self.cos())
    }
    fn asin(&self) -> Self {
        self.nonlinear(self.value.asin())
    }
    fn acos(&self) -> Self {
        self.nonlinear(self.value.acos())
    }
    fn atan(&self) -> Self {
        self.nonlinear(self.value.atan())
    }
    fn atan2(&self, other: Self) -> Self {
        self.binary(&other, self.value.atan2(other.value), true, [true, true])
    }
    fn sinh(&self) -> Self {
        self.nonlinear(self.value.sinh())
    }
    fn cosh(&self) -> Self {
        self.nonlinear(self.value.cosh())
    }
    fn tanh(&self) -> Self {
        self.nonlinear(self.value.tanh())
    }
    fn asinh(&self) -> Self {
        self.nonlinear(self.value.asinh())
    }
    fn acosh(&self) -> Self {
        self.nonlinear(self.value.acosh())
    }
    fn atanh(&self) -> Self {
        self.nonlinear(self.value.atanh())
    }
    fn sph_j0(&self) -> Self {
        self.nonlinear(self.value.sph_j0())
    }
    fn sph_j1(&self) -> Self {
        self.nonlinear(self.value.sph_j1())
    }
    fn sph_j2(&self) -> Self {
        self.nonlinear(self.value.sph_j2())
    }
    fn mul_add(&self, a: Self, b: Self) -> Self {
        *self * a + b
    }
    fn powd(&self, exp: Self) -> Self {
        self.binary(&exp, self.value.powf(exp.value), true, [true, true])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::Dual;

    fn pairs(trace: &Trace, x: &DependencyScalar, n: usize) -> Vec<(usize, usize)> {
        let mut mask = vec![false; n * n];
        trace.add_pairs(x, &mut mask);
        (0..n)
            .flat_map(|a| (0..=a).map(move |c| (a, c)))
            .filter(|&(a, c)| mask[a * n + c])
            .collect()
    }

    #[test]
    fn products_cross_sums_do_not_and_tanh_squares_whatever_its_value() {
        let trace = Trace::begin(4);
        let x: Vec<_> = (0..4).map(|i| trace.input(i, 100.0 * i as f64)).collect();
        // tanh(300) has slope exactly 0.0 in f64: the dependency stays.
        let f = x[0] * x[1] + (x[3] * 1.0).tanh() + x[2];
        assert_eq!(trace.dependencies(&f), vec![true; 4]);
        assert_eq!(pairs(&trace, &f, 4), vec![(1, 0), (3, 3)]);
        assert!(!trace.branched());
    }

    #[test]
    fn constant_zeros_stay_zero_and_division_squares_the_divisor() {
        let trace = Trace::begin(3);
        let x: Vec<_> = (0..3).map(|i| trace.input(i, 1.0 + i as f64)).collect();
        let zero = DependencyScalar::from(0.0) * x[0];
        assert!(zero.is_zero());
        let g = x[0] / x[1] + zero * x[2];
        assert_eq!(trace.dependencies(&g), vec![true, true, false]);
        assert_eq!(pairs(&trace, &g, 3), vec![(1, 0), (1, 1)]);
    }

    #[test]
    fn forward_duals_over_it_give_the_structure_of_a_gradient() {
        // f = x0² x1 + x2: ∂f/∂x0 = 2 x0 x1 depends on x0, x1 and its pairs are (1, 0).
        let trace = Trace::begin(3);
        let x: Vec<Dual<DependencyScalar>> = (0..3)
            .map(|i| {
                let eps = if i == 0 { 1.0 } else { 0.0 };
                Dual::new(trace.input(i, 0.5), DependencyScalar::from(eps))
            })
            .collect();
        let f = x[0] * x[0] * x[1] + x[2];
        assert_eq!(trace.dependencies(&f.eps), vec![true, true, false]);
        assert_eq!(pairs(&trace, &f.eps, 3), vec![(1, 0)]);
    }

    #[test]
    fn comparing_an_input_is_a_branch_comparing_a_constant_is_not() {
        let trace = Trace::begin(1);
        let x = trace.input(0, 2.0);
        let _ = DependencyScalar::from(1.0) > 0.0;
        assert!(!trace.branched());
        let _ = x > 1.0;
        assert!(trace.branched());
    }
}
