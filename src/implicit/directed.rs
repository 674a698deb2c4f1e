//! [`Iv`]: a small interval type for the evaluator's hot path, rounding outward with
//! error-free transformations instead of switching the FPU rounding mode.
//!
//! Every arithmetic result is first computed in round-to-nearest; its exact rounding
//! error is then recovered (TwoSum for sums, an FMA for products, quotients and square
//! roots), and the bound is moved one ulp outward only when the error points outward.
//! Since a round-to-nearest result is within half an ulp of the exact value, the
//! neighbouring float on the error's side is the directed rounding of the exact value:
//! `Iv` bounds are the *same* as inari's (the tightest ones), a property the tests
//! check op by op against inari and against exact rationals.
//!
//! The error-free transformations are exact only away from overflow and underflow, so
//! each operation checks that its operands are moderate (zero or of magnitude in
//! [2^-500, 2^500], finite, non-empty) and otherwise falls back to inari; division by
//! an interval containing 0, square roots of partly negative intervals and every
//! transcendental function take the inari path too. Rigour never depends on the fast
//! path being taken.
use super::number::{Const, Num};
use inari::Interval;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A closed interval `[lo, hi]`; empty when `lo > hi` (inari's `inf`/`sup` of the
/// empty interval are `+inf`, `-inf`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iv {
    pub lo: f64,
    pub hi: f64,
}

/// Magnitudes outside [TINY, HUGE] (other than 0) take the inari path: products and
/// quotients of moderate numbers neither overflow nor underflow, so the FMA-recovered
/// error terms are exact (Boldo–Muller, "Exact and approximated error of the FMA").
const TINY: f64 = 3.054936363499605e-151; // 2^-500
const HUGE: f64 = 3.273390607896142e150; // 2^500

#[inline(always)]
pub(crate) fn moderate(x: f64) -> bool {
    let a = x.abs();
    // NaN and ±inf fail both comparisons' conjunction.
    a == 0.0 || (a >= TINY && a <= HUGE)
}

/// For sums only overflow matters (TwoSum is exact whenever no intermediate overflows).
#[inline(always)]
pub(crate) fn bounded(x: f64) -> bool {
    x.abs() <= HUGE
}

/// The float below `x` when `cond`, else `x`. Requires `x != 0` when `cond` (an inexact
/// result of a moderate operation is never 0).
#[inline(always)]
fn down_if(x: f64, cond: bool) -> f64 {
    let b = x.to_bits() as i64;
    // +1 for positive x, -1 for negative x: moving the bit pattern towards 0 by one
    // steps down for positive and up for negative numbers.
    let sgn = (b >> 63) | 1;
    f64::from_bits((b - if cond { sgn } else { 0 }) as u64)
}

/// The float above `x` when `cond`, else `x` (same requirement as [`down_if`]).
#[inline(always)]
fn up_if(x: f64, cond: bool) -> f64 {
    let b = x.to_bits() as i64;
    let sgn = (b >> 63) | 1;
    f64::from_bits((b + if cond { sgn } else { 0 }) as u64)
}

/// Knuth's TwoSum: `s + e == a + b` exactly, `s = fl(a + b)`.
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// Round-down of the exact a + b.
#[inline(always)]
pub(crate) fn add_dn(a: f64, b: f64) -> f64 {
    let (s, e) = two_sum(a, b);
    down_if(s, e < 0.0)
}
#[inline(always)]
pub(crate) fn add_up(a: f64, b: f64) -> f64 {
    let (s, e) = two_sum(a, b);
    up_if(s, e > 0.0)
}

/// Round-down / round-up of the exact a·b: `fma(a, b, -p)` is the exact error of
/// `p = fl(a·b)` for moderate operands.
#[inline(always)]
pub(crate) fn mul_dn(a: f64, b: f64) -> f64 {
    let p = a * b;
    down_if(p, a.mul_add(b, -p) < 0.0)
}
#[inline(always)]
pub(crate) fn mul_up(a: f64, b: f64) -> f64 {
    let p = a * b;
    up_if(p, a.mul_add(b, -p) > 0.0)
}

/// Round-down / round-up of the exact a/b (b ≠ 0): the remainder `a - q·b` is exact
/// (for moderate operands) and has the sign of `a/b - q` times the sign of `b`.
#[inline(always)]
fn div_dn(a: f64, b: f64) -> f64 {
    let q = a / b;
    let r = (-q).mul_add(b, a);
    down_if(q, (r < 0.0) != (b < 0.0) && r != 0.0)
}
#[inline(always)]
fn div_up(a: f64, b: f64) -> f64 {
    let q = a / b;
    let r = (-q).mul_add(b, a);
    up_if(q, (r > 0.0) != (b < 0.0) && r != 0.0)
}

/// [`div_dn`] and [`div_up`] for a positive divisor: the remainder's sign alone says
/// on which side of the exact quotient `q` lies.
#[inline(always)]
pub(crate) fn div_dn_pos(a: f64, b: f64) -> f64 {
    let q = a / b;
    down_if(q, (-q).mul_add(b, a) < 0.0)
}
#[inline(always)]
pub(crate) fn div_up_pos(a: f64, b: f64) -> f64 {
    let q = a / b;
    up_if(q, (-q).mul_add(b, a) > 0.0)
}

impl Iv {
    pub const fn new(lo: f64, hi: f64) -> Iv {
        Iv { lo, hi }
    }
    pub const fn point(x: f64) -> Iv {
        Iv { lo: x, hi: x }
    }
    #[inline]
    pub fn from_interval(x: Interval) -> Iv {
        Iv {
            lo: x.inf(),
            hi: x.sup(),
        }
    }
    #[inline]
    pub fn from_const(c: &Const) -> Iv {
        Iv { lo: c.lo, hi: c.hi }
    }
    #[inline]
    pub fn to_interval(self) -> Interval {
        if self.lo <= self.hi {
            Interval::try_from((self.lo, self.hi)).unwrap_or(Interval::ENTIRE)
        } else {
            Interval::EMPTY
        }
    }
    pub fn is_empty(self) -> bool {
        !(self.lo <= self.hi)
    }
    pub fn contains(self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }
    #[inline]
    fn is_point(self) -> bool {
        self.lo == self.hi
    }

    /// The inari path for anything outside the fast path's preconditions.
    #[cold]
    #[inline(never)]
    fn slow2(self, o: Iv, f: fn(Interval, Interval) -> Interval) -> Iv {
        Iv::from_interval(f(self.to_interval(), o.to_interval()))
    }
    #[cold]
    #[inline(never)]
    fn slow1(self, f: fn(Interval) -> Interval) -> Iv {
        Iv::from_interval(f(self.to_interval()))
    }

    /// x², tight (x² over [-1, 2] is [0, 4]).
    #[inline]
    pub fn sqr(self) -> Iv {
        if !(moderate(self.lo) & moderate(self.hi) & (self.lo <= self.hi)) {
            return self.slow1(Interval::sqr);
        }
        if self.lo >= 0.0 {
            Iv::new(mul_dn(self.lo, self.lo), mul_up(self.hi, self.hi))
        } else if self.hi <= 0.0 {
            Iv::new(mul_dn(self.hi, self.hi), mul_up(self.lo, self.lo))
        } else {
            let m = (-self.lo).max(self.hi);
            Iv::new(0.0, mul_up(m, m))
        }
    }

    /// x · c for a point c (two products instead of four).
    #[inline]
    pub fn mul_point(self, c: f64) -> Iv {
        if !(moderate(self.lo) & moderate(self.hi) & moderate(c) & (self.lo <= self.hi)) {
            return self.slow2(Iv::point(c), |a, b| a * b);
        }
        if c >= 0.0 {
            Iv::new(mul_dn(self.lo, c), mul_up(self.hi, c))
        } else {
            Iv::new(mul_dn(self.hi, c), mul_up(self.lo, c))
        }
    }

    /// x / c for a constant enclosure c = [cl, ch] not containing 0: each bound of the
    /// quotient comes from one endpoint of c chosen by signs (two divisions).
    #[inline]
    fn div_const_iv(self, c: Iv) -> Iv {
        let ok = moderate(self.lo)
            & moderate(self.hi)
            & moderate(c.lo)
            & moderate(c.hi)
            & (self.lo <= self.hi)
            & ((c.lo > 0.0) | (c.hi < 0.0));
        if !ok {
            return self.slow2(c, |a, b| a / b);
        }
        if c.lo > 0.0 {
            // Dividing by a positive number: lo/ch is smallest when lo >= 0, lo/cl otherwise.
            let dl = if self.lo >= 0.0 { c.hi } else { c.lo };
            let dh = if self.hi >= 0.0 { c.lo } else { c.hi };
            Iv::new(div_dn_pos(self.lo, dl), div_up_pos(self.hi, dh))
        } else {
            let dl = if self.hi >= 0.0 { c.hi } else { c.lo };
            let dh = if self.lo >= 0.0 { c.lo } else { c.hi };
            Iv::new(div_dn(self.hi, dl), div_up(self.lo, dh))
        }
    }

    /// 1 / x (inari semantics when x contains 0).
    pub fn recip(self) -> Iv {
        Iv::point(1.0) / self
    }

    /// x^n, n >= 0: tight for even n (via the tight square), monotone for odd n.
    pub fn pown(self, n: u32) -> Iv {
        match n {
            0 => {
                if self.is_empty() {
                    self
                } else {
                    Iv::point(1.0)
                }
            }
            1 => self,
            2 => self.sqr(),
            _ if n % 2 == 0 => {
                let s = self.sqr();
                let mut acc = s;
                for _ in 1..n / 2 {
                    acc = acc * s;
                }
                acc
            }
            _ => {
                if self.is_empty() {
                    return self;
                }
                // Odd powers are increasing: enclose the endpoints' powers.
                let lo = pow_point(self.lo, n).lo;
                let hi = pow_point(self.hi, n).hi;
                Iv::new(lo, hi)
            }
        }
    }
}

/// x^n for a point x, enclosed by repeated outward-rounded multiplication.
fn pow_point(x: f64, n: u32) -> Iv {
    let mut acc = Iv::point(1.0);
    let mut base = Iv::point(x);
    let mut e = n;
    while e > 0 {
        if e & 1 == 1 {
            acc = acc * base;
        }
        e >>= 1;
        if e > 0 {
            base = base * base;
        }
    }
    acc
}

impl From<Interval> for Iv {
    fn from(x: Interval) -> Iv {
        Iv::from_interval(x)
    }
}
impl From<Iv> for Interval {
    fn from(x: Iv) -> Interval {
        x.to_interval()
    }
}

impl Add for Iv {
    type Output = Iv;
    #[inline(always)]
    fn add(self, o: Iv) -> Iv {
        if !(bounded(self.lo) & bounded(self.hi) & bounded(o.lo) & bounded(o.hi)) {
            return self.slow2(o, |a, b| a + b);
        }
        Iv::new(add_dn(self.lo, o.lo), add_up(self.hi, o.hi))
    }
}
impl Sub for Iv {
    type Output = Iv;
    #[inline(always)]
    fn sub(self, o: Iv) -> Iv {
        if !(bounded(self.lo) & bounded(self.hi) & bounded(o.lo) & bounded(o.hi)) {
            return self.slow2(o, |a, b| a - b);
        }
        Iv::new(add_dn(self.lo, -o.hi), add_up(self.hi, -o.lo))
    }
}
impl Neg for Iv {
    type Output = Iv;
    #[inline]
    fn neg(self) -> Iv {
        Iv::new(-self.hi, -self.lo)
    }
}
impl Mul for Iv {
    type Output = Iv;
    #[inline(always)]
    fn mul(self, o: Iv) -> Iv {
        let ok = moderate(self.lo)
            & moderate(self.hi)
            & moderate(o.lo)
            & moderate(o.hi)
            & (self.lo <= self.hi)
            & (o.lo <= o.hi);
        if !ok {
            return self.slow2(o, |a, b| a * b);
        }
        // The four endpoint products, each rounded both ways (branch-free; the min and
        // max pick the extreme ones).
        let (a, b, c, d) = (self.lo, self.hi, o.lo, o.hi);
        if (a >= 0.0) & (c >= 0.0) {
            // Both non-negative (common in sums of squares): two products.
            return Iv::new(mul_dn(a, c), mul_up(b, d));
        }
        let lo = mul_dn(a, c)
            .min(mul_dn(a, d))
            .min(mul_dn(b, c))
            .min(mul_dn(b, d));
        let hi = mul_up(a, c)
            .max(mul_up(a, d))
            .max(mul_up(b, c))
            .max(mul_up(b, d));
        Iv::new(lo, hi)
    }
}
impl Div for Iv {
    type Output = Iv;
    #[inline(always)]
    fn div(self, o: Iv) -> Iv {
        // Division by an interval that does not contain 0; otherwise inari decides
        // (the result is then unbounded, or empty for [0, 0]).
        let ok = moderate(self.lo)
            & moderate(self.hi)
            & moderate(o.lo)
            & moderate(o.hi)
            & (self.lo <= self.hi)
            & ((o.lo > 0.0) | (o.hi < 0.0))
            & (o.lo <= o.hi);
        if !ok {
            return self.slow2(o, |a, b| a / b);
        }
        let (a, b, c, d) = (self.lo, self.hi, o.lo, o.hi);
        let lo = div_dn(a, c)
            .min(div_dn(a, d))
            .min(div_dn(b, c))
            .min(div_dn(b, d));
        let hi = div_up(a, c)
            .max(div_up(a, d))
            .max(div_up(b, c))
            .max(div_up(b, d));
        Iv::new(lo, hi)
    }
}

/// sqrt over the part of x where it is defined (inari's convention: [-1, 4] ↦ [0, 2],
/// empty when x < 0 entirely). The remainder x - s² is exact for moderate x.
fn sqrt_dn(x: f64) -> f64 {
    let s = x.sqrt();
    // s too large when s² > x.
    down_if(s, (-s).mul_add(s, x) < 0.0)
}
fn sqrt_up(x: f64) -> f64 {
    let s = x.sqrt();
    up_if(s, (-s).mul_add(s, x) > 0.0)
}

impl Num for Iv {
    #[inline]
    fn cst(c: Const) -> Self {
        Iv::from_const(&c)
    }
    #[inline]
    fn add_const(&self, c: &Const) -> Self {
        *self + Iv::from_const(c)
    }
    #[inline]
    fn sub_const(&self, c: &Const) -> Self {
        *self - Iv::from_const(c)
    }
    #[inline]
    fn const_sub(&self, c: &Const) -> Self {
        Iv::from_const(c) - *self
    }
    #[inline]
    fn mul_const(&self, c: &Const) -> Self {
        let k = Iv::from_const(c);
        if k.is_point() {
            self.mul_point(k.lo)
        } else if k.lo > 0.0 || k.hi < 0.0 {
            // A positive (negative) enclosure: each bound uses one endpoint of k chosen
            // by the sign of the bound it multiplies (two products).
            let ok = moderate(self.lo)
                & moderate(self.hi)
                & moderate(k.lo)
                & moderate(k.hi)
                & (self.lo <= self.hi);
            if !ok {
                return self.slow2(k, |a, b| a * b);
            }
            if k.lo > 0.0 {
                let ml = if self.lo >= 0.0 { k.lo } else { k.hi };
                let mh = if self.hi >= 0.0 { k.hi } else { k.lo };
                Iv::new(mul_dn(self.lo, ml), mul_up(self.hi, mh))
            } else {
                let ml = if self.hi >= 0.0 { k.lo } else { k.hi };
                let mh = if self.lo >= 0.0 { k.hi } else { k.lo };
                Iv::new(mul_dn(self.hi, ml), mul_up(self.lo, mh))
            }
        } else {
            *self * k
        }
    }
    #[inline]
    fn div_const(&self, c: &Const) -> Self {
        let k = Iv::from_const(c);
        self.div_const_iv(k)
    }
    fn powi(&self, n: i32) -> Self {
        if n >= 0 {
            self.pown(n as u32)
        } else {
            self.pown(n.unsigned_abs()).recip()
        }
    }
    #[inline]
    fn square(&self) -> Self {
        self.sqr()
    }
    fn sqrt(&self) -> Self {
        if !(moderate(self.lo) & moderate(self.hi) & (self.lo >= 0.0) & (self.lo <= self.hi)) {
            return self.slow1(Interval::sqrt);
        }
        Iv::new(sqrt_dn(self.lo), sqrt_up(self.hi))
    }
    #[inline]
    fn abs(&self) -> Self {
        if self.is_empty() {
            *self
        } else if self.lo >= 0.0 {
            *self
        } else if self.hi <= 0.0 {
            -*self
        } else {
            Iv::new(0.0, (-self.lo).max(self.hi))
        }
    }
    fn sign(&self) -> Self {
        self.slow1(Interval::sign)
    }
    fn kink(&self) -> Self {
        Iv::from_interval(Num::kink(&self.to_interval()))
    }
    #[inline]
    fn min(&self, o: &Self) -> Self {
        if self.is_empty() || o.is_empty() {
            return self.slow2(*o, Interval::min);
        }
        Iv::new(self.lo.min(o.lo), self.hi.min(o.hi))
    }
    #[inline]
    fn max(&self, o: &Self) -> Self {
        if self.is_empty() || o.is_empty() {
            return self.slow2(*o, Interval::max);
        }
        Iv::new(self.lo.max(o.lo), self.hi.max(o.hi))
    }
    fn sin(&self) -> Self {
        Iv::from_interval(Num::sin(&self.to_interval()))
    }
    fn cos(&self) -> Self {
        Iv::from_interval(Num::cos(&self.to_interval()))
    }
    fn exp(&self) -> Self {
        Iv::from_interval(Num::exp(&self.to_interval()))
    }
    fn ln(&self) -> Self {
        Iv::from_interval(Num::ln(&self.to_interval()))
    }
}
