//! The number types one evaluator serves: `f64`, inari's `Interval`, and forward-mode
//! automatic differentiation over either (`Dual` for gradients, `Hyper` for Hessians).
//!
//! Rigour: every `Interval` operation rounds outward (inari). Constants of a formula are
//! carried as enclosing intervals ([`Const`]), so `0.1` is enclosed, not rounded.
use inari::Interval;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A constant of a formula: its nearest `f64` and a rigorous enclosure of the exact value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Const {
    pub value: f64,
    pub lo: f64,
    pub hi: f64,
}

impl Const {
    /// An exactly representable constant.
    pub fn exact(v: f64) -> Self {
        Const {
            value: v,
            lo: v,
            hi: v,
        }
    }
    /// π, enclosed.
    pub fn pi() -> Self {
        Const {
            value: std::f64::consts::PI,
            lo: Interval::PI.inf(),
            hi: Interval::PI.sup(),
        }
    }
    /// A decimal literal: exact when the parsed `f64` is an integer below 2^53 or the
    /// text is a dyadic that parses exactly; otherwise widened by one ulp each way,
    /// which encloses the decimal value (the parse is correctly rounded).
    pub fn decimal(text: &str, value: f64) -> Self {
        if is_exact_decimal(text, value) {
            Const::exact(value)
        } else {
            Const {
                value,
                lo: next_down(value),
                hi: next_up(value),
            }
        }
    }
}

/// True when `value` equals the decimal `text` (digits, optional fraction, optional
/// exponent, as the parser accepts them) exactly, decided in exact rational arithmetic.
///
/// A float-based shortcut is not safe here: `1.00000000000000000001` parses to the
/// integer 1.0 and `1e-400` to 0.0, yet neither decimal is that float; both must be
/// enclosed, not rounded. Conservative: an unreadable text or an absurd exponent says
/// false (the value is then merely widened by an ulp each way, still an enclosure).
fn is_exact_decimal(text: &str, value: f64) -> bool {
    use num_bigint::BigInt;
    use num_rational::BigRational;
    use num_traits::Zero;
    let (mant, exp) = match text.find(['e', 'E']) {
        Some(i) => (&text[..i], text[i + 1..].parse::<i64>()),
        None => (text, Ok(0)),
    };
    let Ok(exp) = exp else { return false };
    let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
    let digits = format!("{int}{frac}");
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return false;
    }
    let Some(m) = BigInt::parse_bytes(digits.as_bytes(), 10) else {
        return false;
    };
    if m.is_zero() {
        return value == 0.0;
    }
    // A non-zero decimal that parsed to 0 underflowed; one that needs more than 2000
    // decimal places or digits is not worth the big numbers (conservatively inexact).
    let e10 = exp - frac.len() as i64;
    if value == 0.0 || e10.abs() > 2000 {
        return false;
    }
    let ten = BigInt::from(10u32);
    let exact = if e10 >= 0 {
        BigRational::from_integer(m * ten.pow(e10 as u32))
    } else {
        BigRational::new(m, ten.pow((-e10) as u32))
    };
    BigRational::from_float(value) == Some(exact)
}

pub fn next_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1);
    }
    let b = x.to_bits();
    f64::from_bits(if x > 0.0 { b + 1 } else { b - 1 })
}

pub fn next_down(x: f64) -> f64 {
    -next_up(-x)
}

/// The operations the tape needs from a number type. Implemented for `f64`, `Interval`,
/// `Dual<T>` and `Hyper<T>`; user code generic over `Num` (see
/// [`crate::implicit::GenericFn`]) gets every evaluation mode for free.
pub trait Num:
    Clone
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Send
    + Sync
    + 'static
{
    /// A constant (rigorously enclosed for intervals).
    fn cst(c: Const) -> Self;
    /// An exactly representable constant.
    fn lit(v: f64) -> Self {
        Self::cst(Const::exact(v))
    }
    /// `self + c`. The tape's fused constant operations call these so that each type
    /// does the cheapest rigorous thing (derivative types leave the gradient alone,
    /// intervals multiply by a point constant with two roundings instead of four).
    #[inline]
    fn add_const(&self, c: &Const) -> Self {
        self.clone() + Self::cst(*c)
    }
    /// `self - c`.
    #[inline]
    fn sub_const(&self, c: &Const) -> Self {
        self.clone() - Self::cst(*c)
    }
    /// `c - self`.
    #[inline]
    fn const_sub(&self, c: &Const) -> Self {
        Self::cst(*c) - self.clone()
    }
    /// `self * c`.
    #[inline]
    fn mul_const(&self, c: &Const) -> Self {
        self.clone() * Self::cst(*c)
    }
    /// `self / c`.
    #[inline]
    fn div_const(&self, c: &Const) -> Self {
        self.clone() / Self::cst(*c)
    }
    /// `self²` (for intervals tight: x² over [-1, 2] is [0, 4]).
    #[inline]
    fn square(&self) -> Self {
        self.powi(2)
    }
    /// Integer power; for intervals tight on even powers (x² over [-1,2] is [0,4]).
    fn powi(&self, n: i32) -> Self;
    fn sqrt(&self) -> Self;
    fn abs(&self) -> Self;
    /// The derivative of `abs`: sign, an enclosure `[-1, 1]` for intervals containing 0.
    fn sign(&self) -> Self;
    /// The second derivative of `abs` (a Dirac mass at 0): 0 away from 0, and for an
    /// interval containing 0 the whole line, so Hessian enclosures stay honest.
    fn kink(&self) -> Self;
    fn min(&self, o: &Self) -> Self;
    fn max(&self, o: &Self) -> Self;
    fn sin(&self) -> Self;
    fn cos(&self) -> Self;
    fn exp(&self) -> Self;
    fn ln(&self) -> Self;
}

impl Num for f64 {
    #[inline]
    fn cst(c: Const) -> Self {
        c.value
    }
    #[inline]
    fn add_const(&self, c: &Const) -> Self {
        self + c.value
    }
    #[inline]
    fn sub_const(&self, c: &Const) -> Self {
        self - c.value
    }
    #[inline]
    fn const_sub(&self, c: &Const) -> Self {
        c.value - self
    }
    #[inline]
    fn mul_const(&self, c: &Const) -> Self {
        self * c.value
    }
    #[inline]
    fn div_const(&self, c: &Const) -> Self {
        self / c.value
    }
    #[inline]
    fn square(&self) -> Self {
        self * self
    }
    #[inline]
    fn powi(&self, n: i32) -> Self {
        f64::powi(*self, n)
    }
    #[inline]
    fn sqrt(&self) -> Self {
        f64::sqrt(*self)
    }
    #[inline]
    fn abs(&self) -> Self {
        f64::abs(*self)
    }
    #[inline]
    fn sign(&self) -> Self {
        if *self > 0.0 {
            1.0
        } else if *self < 0.0 {
            -1.0
        } else {
            0.0
        }
    }
    #[inline]
    fn kink(&self) -> Self {
        0.0
    }
    #[inline]
    fn min(&self, o: &Self) -> Self {
        // f64::min ignores a NaN argument; an undefined argument (√ of a negative
        // number) must make min undefined too, as in interval evaluation.
        if self.is_nan() || o.is_nan() {
            f64::NAN
        } else {
            f64::min(*self, *o)
        }
    }
    #[inline]
    fn max(&self, o: &Self) -> Self {
        if self.is_nan() || o.is_nan() {
            f64::NAN
        } else {
            f64::max(*self, *o)
        }
    }
    fn sin(&self) -> Self {
        f64::sin(*self)
    }
    fn cos(&self) -> Self {
        f64::cos(*self)
    }
    fn exp(&self) -> Self {
        f64::exp(*self)
    }
    fn ln(&self) -> Self {
        f64::ln(*self)
    }
}

/// `[x, x]` for a finite float, the whole line otherwise.
#[inline]
pub fn point(x: f64) -> Interval {
    Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE)
}

/// x^n for n >= 0 over an interval, tight up to rounding (even powers through the
/// tight square, odd powers by monotonicity): computed by the fast kernel
/// [`Iv::pown`](super::directed::Iv::pown), whose bounds equal inari's op by op.
pub fn ipow(x: Interval, n: u32) -> Interval {
    super::directed::Iv::from_interval(x).pown(n).to_interval()
}

impl Num for Interval {
    #[inline]
    fn cst(c: Const) -> Self {
        Interval::try_from((c.lo, c.hi)).unwrap_or(Interval::ENTIRE)
    }
    #[inline]
    fn square(&self) -> Self {
        self.sqr()
    }
    fn powi(&self, n: i32) -> Self {
        if n >= 0 {
            ipow(*self, n as u32)
        } else {
            ipow(*self, n.unsigned_abs()).recip()
        }
    }
    #[inline]
    fn sqrt(&self) -> Self {
        Interval::sqrt(*self)
    }
    #[inline]
    fn abs(&self) -> Self {
        Interval::abs(*self)
    }
    #[inline]
    fn sign(&self) -> Self {
        Interval::sign(*self)
    }
    fn kink(&self) -> Self {
        if self.contains(0.0) {
            Interval::ENTIRE
        } else {
            point(0.0)
        }
    }
    #[inline]
    fn min(&self, o: &Self) -> Self {
        Interval::min(*self, *o)
    }
    #[inline]
    fn max(&self, o: &Self) -> Self {
        Interval::max(*self, *o)
    }
    #[cfg(feature = "mpfr")]
    fn sin(&self) -> Self {
        Interval::sin(*self)
    }
    #[cfg(feature = "mpfr")]
    fn cos(&self) -> Self {
        Interval::cos(*self)
    }
    #[cfg(feature = "mpfr")]
    fn exp(&self) -> Self {
        Interval::exp(*self)
    }
    #[cfg(feature = "mpfr")]
    fn ln(&self) -> Self {
        Interval::ln(*self)
    }
    // Without MPFR no correctly rounded transcendental is available: return the
    // trivially valid enclosures. The formula parser rejects these functions without
    // the feature, so only hand-written `GenericFn` code can reach them.
    #[cfg(not(feature = "mpfr"))]
    fn sin(&self) -> Self {
        if self.is_empty() {
            *self
        } else {
            Interval::try_from((-1.0, 1.0)).unwrap()
        }
    }
    #[cfg(not(feature = "mpfr"))]
    fn cos(&self) -> Self {
        Num::sin(self)
    }
    #[cfg(not(feature = "mpfr"))]
    fn exp(&self) -> Self {
        if self.is_empty() {
            *self
        } else {
            Interval::try_from((0.0, f64::INFINITY)).unwrap()
        }
    }
    #[cfg(not(feature = "mpfr"))]
    fn ln(&self) -> Self {
        if self.is_empty() || self.sup() <= 0.0 {
            Interval::EMPTY
        } else {
            Interval::ENTIRE
        }
    }
}

/// The [`Num`] methods in which `Dual` and `Hyper` differ only by their derivative
/// fields (`$d`): the fused constant operations (constants have zero derivatives:
/// shifting leaves the derivatives alone, scaling scales them — no products with zero
/// derivatives, no materialised constants), `sign` and `kink` (constant almost
/// everywhere: zero derivatives), and `min`/`max`. Expands to the same code as writing
/// each out for each type.
macro_rules! derivative_ops {
    ($ty:ident { $($d:ident),+ }) => {
        #[inline]
        fn add_const(&self, c: &Const) -> Self {
            $ty {
                v: self.v.add_const(c),
                $($d: self.$d.clone(),)+
            }
        }
        #[inline]
        fn sub_const(&self, c: &Const) -> Self {
            $ty {
                v: self.v.sub_const(c),
                $($d: self.$d.clone(),)+
            }
        }
        #[inline]
        fn const_sub(&self, c: &Const) -> Self {
            $ty {
                v: self.v.const_sub(c),
                $($d: self.$d.clone().map(|x| -x),)+
            }
        }
        #[inline]
        fn mul_const(&self, c: &Const) -> Self {
            $ty {
                v: self.v.mul_const(c),
                $($d: self.$d.clone().map(|x| x.mul_const(c)),)+
            }
        }
        #[inline]
        fn div_const(&self, c: &Const) -> Self {
            $ty {
                v: self.v.div_const(c),
                $($d: self.$d.clone().map(|x| x.div_const(c)),)+
            }
        }
        fn sign(&self) -> Self {
            Self::lit(0.0).with_v(self.v.sign())
        }
        fn kink(&self) -> Self {
            Self::lit(0.0).with_v(self.v.kink())
        }
        fn min(&self, o: &Self) -> Self {
            // min(a,b) = (a + b - |a - b|)/2 gives the derivative enclosure at ties.
            let m = (self.clone() + o.clone() - (self.clone() - o.clone()).abs()) * Self::lit(0.5);
            m.with_v(self.v.min(&o.v))
        }
        fn max(&self, o: &Self) -> Self {
            let m = (self.clone() + o.clone() + (self.clone() - o.clone()).abs()) * Self::lit(0.5);
            m.with_v(self.v.max(&o.v))
        }
    };
}

/// Forward-mode first derivatives: the value and the gradient with respect to x, y, z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual<T> {
    pub v: T,
    pub g: [T; 3],
}

impl Dual<f64> {
    /// f = 0 and ∇f = 0: a placeholder for output buffers.
    pub const ZERO: Dual<f64> = Dual {
        v: 0.0,
        g: [0.0; 3],
    };
}

impl<T: Num> Dual<T> {
    /// The coordinate variable `k` (0, 1, 2) with value `v`.
    pub fn var(v: T, k: usize) -> Self {
        let mut g = [T::lit(0.0), T::lit(0.0), T::lit(0.0)];
        g[k] = T::lit(1.0);
        Dual { v, g }
    }
    fn chain(&self, v: T, d: T) -> Self {
        Dual {
            v,
            g: [
                d.clone() * self.g[0].clone(),
                d.clone() * self.g[1].clone(),
                d * self.g[2].clone(),
            ],
        }
    }
}

impl<T: Num> Add for Dual<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        let [a, b, c] = self.g;
        let [d, e, f] = o.g;
        Dual {
            v: self.v + o.v,
            g: [a + d, b + e, c + f],
        }
    }
}
impl<T: Num> Sub for Dual<T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        let [a, b, c] = self.g;
        let [d, e, f] = o.g;
        Dual {
            v: self.v - o.v,
            g: [a - d, b - e, c - f],
        }
    }
}
impl<T: Num> Neg for Dual<T> {
    type Output = Self;
    fn neg(self) -> Self {
        let [a, b, c] = self.g;
        Dual {
            v: -self.v,
            g: [-a, -b, -c],
        }
    }
}
impl<T: Num> Mul for Dual<T> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        // (Per component, as `Add` above: `[0, 1, 2].map` calls its closure through a
        // type-erased loop, left out of line for `Dual<Lanes>`: a call per component
        // in the batch gradient's loop.)
        let d = |k: usize| self.g[k].clone() * o.v.clone() + self.v.clone() * o.g[k].clone();
        let g = [d(0), d(1), d(2)];
        Dual { v: self.v * o.v, g }
    }
}
impl<T: Num> Div for Dual<T> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let q = self.v / o.v.clone();
        let d = |k: usize| (self.g[k].clone() - q.clone() * o.g[k].clone()) / o.v.clone();
        let g = [d(0), d(1), d(2)];
        Dual { v: q, g }
    }
}

impl<T: Num> Num for Dual<T> {
    fn cst(c: Const) -> Self {
        Dual {
            v: T::cst(c),
            g: [T::lit(0.0), T::lit(0.0), T::lit(0.0)],
        }
    }
    derivative_ops!(Dual { g });
    #[inline]
    fn square(&self) -> Self {
        // (u²)' = 2u u'; 2u = u + u is exact (or rounded outward for intervals).
        self.chain(self.v.square(), self.v.clone() + self.v.clone())
    }
    fn powi(&self, n: i32) -> Self {
        if n == 0 {
            return Self::lit(1.0);
        }
        let d = T::lit(n as f64) * self.v.powi(n - 1);
        self.chain(self.v.powi(n), d)
    }
    fn sqrt(&self) -> Self {
        let s = self.v.sqrt();
        let d = T::lit(0.5) / s.clone();
        self.chain(s, d)
    }
    fn abs(&self) -> Self {
        self.chain(self.v.abs(), self.v.sign())
    }
    fn sin(&self) -> Self {
        self.chain(self.v.sin(), self.v.cos())
    }
    fn cos(&self) -> Self {
        self.chain(self.v.cos(), -self.v.sin())
    }
    fn exp(&self) -> Self {
        let e = self.v.exp();
        self.chain(e.clone(), e)
    }
    fn ln(&self) -> Self {
        self.chain(self.v.ln(), T::lit(1.0) / self.v.clone())
    }
}

impl<T: Num> Dual<T> {
    fn with_v(mut self, v: T) -> Self {
        self.v = v;
        self
    }
}

/// Index of the (i, j) entry, i <= j, in the packed symmetric Hessian.
pub const fn hidx(i: usize, j: usize) -> usize {
    let (i, j) = if i <= j { (i, j) } else { (j, i) };
    match (i, j) {
        (0, 0) => 0,
        (0, 1) => 1,
        (0, 2) => 2,
        (1, 1) => 3,
        (1, 2) => 4,
        _ => 5,
    }
}
const PAIRS: [(usize, usize); 6] = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];

/// Forward-mode second derivatives: value, gradient and the packed symmetric Hessian
/// `[xx, xy, xz, yy, yz, zz]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hyper<T> {
    pub v: T,
    pub g: [T; 3],
    pub h: [T; 6],
}

impl<T: Num> Hyper<T> {
    pub fn var(v: T, k: usize) -> Self {
        let z = T::lit(0.0);
        let mut g = [z.clone(), z.clone(), z.clone()];
        g[k] = T::lit(1.0);
        Hyper {
            v,
            g,
            h: [z.clone(), z.clone(), z.clone(), z.clone(), z.clone(), z],
        }
    }
    /// Apply a scalar function with value `v`, first derivative `d1`, second `d2`.
    fn chain(&self, v: T, d1: T, d2: T) -> Self {
        let g = [0, 1, 2].map(|k| d1.clone() * self.g[k].clone());
        let h = PAIRS.map(|(i, j)| {
            d1.clone() * self.h[hidx(i, j)].clone()
                + d2.clone() * self.g[i].clone() * self.g[j].clone()
        });
        Hyper { v, g, h }
    }
    fn with_v(mut self, v: T) -> Self {
        self.v = v;
        self
    }
}

impl<T: Num> Add for Hyper<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Hyper {
            v: self.v + o.v,
            g: [0, 1, 2].map(|k| self.g[k].clone() + o.g[k].clone()),
            h: [0, 1, 2, 3, 4, 5].map(|k| self.h[k].clone() + o.h[k].clone()),
        }
    }
}
impl<T: Num> Sub for Hyper<T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Hyper {
            v: self.v - o.v,
            g: [0, 1, 2].map(|k| self.g[k].clone() - o.g[k].clone()),
            h: [0, 1, 2, 3, 4, 5].map(|k| self.h[k].clone() - o.h[k].clone()),
        }
    }
}
impl<T: Num> Neg for Hyper<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Hyper {
            v: -self.v,
            g: self.g.map(|x| -x),
            h: self.h.map(|x| -x),
        }
    }
}
impl<T: Num> Mul for Hyper<T> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let (a, b) = (&self, &o);
        let g = [0, 1, 2].map(|k| a.g[k].clone() * b.v.clone() + a.v.clone() * b.g[k].clone());
        let h = PAIRS.map(|(i, j)| {
            a.h[hidx(i, j)].clone() * b.v.clone()
                + a.v.clone() * b.h[hidx(i, j)].clone()
                + a.g[i].clone() * b.g[j].clone()
                + a.g[j].clone() * b.g[i].clone()
        });
        Hyper {
            v: a.v.clone() * b.v.clone(),
            g,
            h,
        }
    }
}
impl<T: Num> Div for Hyper<T> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        // q = u/w:  g_q = (g_u - q g_w)/w,  H_q = (H_u - q H_w - g_q g_w^T - g_w g_q^T)/w.
        let w = o.v.clone();
        let q = self.v.clone() / w.clone();
        let gq = [0, 1, 2].map(|k| (self.g[k].clone() - q.clone() * o.g[k].clone()) / w.clone());
        let h = PAIRS.map(|(i, j)| {
            (self.h[hidx(i, j)].clone()
                - q.clone() * o.h[hidx(i, j)].clone()
                - gq[i].clone() * o.g[j].clone()
                - o.g[i].clone() * gq[j].clone())
                / w.clone()
        });
        Hyper { v: q, g: gq, h }
    }
}

impl<T: Num> Num for Hyper<T> {
    fn cst(c: Const) -> Self {
        let z = T::lit(0.0);
        Hyper {
            v: T::cst(c),
            g: [z.clone(), z.clone(), z.clone()],
            h: [z.clone(), z.clone(), z.clone(), z.clone(), z.clone(), z],
        }
    }
    derivative_ops!(Hyper { g, h });
    #[inline]
    fn square(&self) -> Self {
        // (u²)' = 2u, (u²)'' = 2.
        let two_u = self.v.clone() + self.v.clone();
        self.chain(self.v.square(), two_u, T::lit(2.0))
    }
    fn powi(&self, n: i32) -> Self {
        if n == 0 {
            return Self::lit(1.0);
        }
        let nf = n as f64;
        let d1 = T::lit(nf) * self.v.powi(n - 1);
        let d2 = if n == 1 {
            T::lit(0.0)
        } else {
            T::lit(nf * (nf - 1.0)) * self.v.powi(n - 2)
        };
        self.chain(self.v.powi(n), d1, d2)
    }
    fn sqrt(&self) -> Self {
        let s = self.v.sqrt();
        let d1 = T::lit(0.5) / s.clone();
        // d2 = -1/(4 s^3)
        let d2 = -(T::lit(0.25) / (s.clone() * s.clone() * s.clone()));
        self.chain(s, d1, d2)
    }
    fn abs(&self) -> Self {
        self.chain(self.v.abs(), self.v.sign(), self.v.kink())
    }
    fn sin(&self) -> Self {
        let s = self.v.sin();
        self.chain(s.clone(), self.v.cos(), -s)
    }
    fn cos(&self) -> Self {
        let c = self.v.cos();
        self.chain(c.clone(), -self.v.sin(), -c)
    }
    fn exp(&self) -> Self {
        let e = self.v.exp();
        self.chain(e.clone(), e.clone(), e)
    }
    fn ln(&self) -> Self {
        let r = T::lit(1.0) / self.v.clone();
        self.chain(self.v.ln(), r.clone(), -(r.clone() * r))
    }
}
