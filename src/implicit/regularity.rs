//! Is f defined, continuous, smooth on a box? The hypothesis every certificate needs.
//!
//! An interval enclosure alone cannot tell: over a box with y ∈ [0, 1], x/y encloses
//! to [0, +∞] and its x-derivative 1/y to [1, +∞], which "excludes 0", yet f has a pole
//! in the box and no theorem about C¹ functions applies. IEEE 1788 answers with
//! *decorations* (inari's `DecInterval`: com, dac, def, trv). [`Dec`] carries the same
//! information beside the fast kernel [`Iv`], one flag per register, with one more
//! level that IEEE 1788 does not have and the subdivision criteria need:
//!
//! * [`Regularity::Smooth`]: every operation of the tape is C^∞ on an open
//!   neighbourhood of the enclosure of its arguments (division and negative powers
//!   with the denominator's enclosure free of 0, √ and ln with a positive argument,
//!   |·| away from 0, min/max with disjoint arguments), so f is C^∞ on a neighbourhood
//!   of the closed box and the derivative enclosures are enclosures of the true
//!   derivatives;
//! * [`Regularity::Continuous`]: defined and continuous on the box (IEEE 1788 `dac`):
//!   √ on [0, b], |·|, min and max anywhere;
//! * [`Regularity::Undefined`]: possibly undefined or discontinuous somewhere on the
//!   box (`def` or `trv`): a pole, a square root or logarithm of a possibly negative
//!   number.
//!
//! The flag of a result is the meet of its arguments' flags and the operation's own
//! condition, so a tape is as regular as its least regular operation. A proptest in
//! `tests/implicit.rs` checks `Continuous` against inari's decorations and `Smooth`
//! against decorated derivative evaluation on random formulas and boxes.
use super::directed::Iv;
use super::number::{Const, Num};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// How regular f is on a box (ordered: `Undefined < Continuous < Smooth`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Regularity {
    /// Possibly undefined or discontinuous somewhere on the box.
    Undefined,
    /// Defined and continuous on the closed box (IEEE 1788 `dac` or `com`).
    Continuous,
    /// C^∞ on a neighbourhood of the closed box.
    Smooth,
}

impl Regularity {
    /// Why a box of this regularity cannot be certified by a C¹ criterion, if it cannot.
    pub fn c1_failure(self) -> Option<&'static str> {
        match self {
            Regularity::Smooth => None,
            Regularity::Continuous => {
                Some("f is not differentiable on this box (|x|, min, max or sqrt at 0)")
            }
            Regularity::Undefined => {
                Some("f is not continuous on this box (pole or domain boundary)")
            }
        }
    }
}

/// An interval with its regularity flag.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dec {
    pub x: Iv,
    pub reg: Regularity,
}

impl Dec {
    pub fn new(x: Iv, reg: Regularity) -> Dec {
        Dec { x, reg }
    }
    /// A variable ranging over `x` (smooth).
    pub fn var(x: Iv) -> Dec {
        Dec::new(x, Regularity::Smooth)
    }
    #[inline]
    fn with(self, x: Iv, cap: Regularity) -> Dec {
        Dec::new(x, self.reg.min(cap))
    }
    #[inline]
    fn with2(self, o: Dec, x: Iv, cap: Regularity) -> Dec {
        Dec::new(x, self.reg.min(o.reg).min(cap))
    }
}

/// 0 ∉ x, strictly (and x non-empty).
#[inline]
fn free_of_zero(x: Iv) -> bool {
    x.lo > 0.0 || x.hi < 0.0
}

/// The regularity of a quotient by `d`: smooth if 0 ∉ d.
#[inline]
fn denominator(d: Iv) -> Regularity {
    if free_of_zero(d) {
        Regularity::Smooth
    } else {
        Regularity::Undefined
    }
}

impl Add for Dec {
    type Output = Dec;
    fn add(self, o: Dec) -> Dec {
        self.with2(o, self.x + o.x, Regularity::Smooth)
    }
}
impl Sub for Dec {
    type Output = Dec;
    fn sub(self, o: Dec) -> Dec {
        self.with2(o, self.x - o.x, Regularity::Smooth)
    }
}
impl Mul for Dec {
    type Output = Dec;
    fn mul(self, o: Dec) -> Dec {
        self.with2(o, self.x * o.x, Regularity::Smooth)
    }
}
impl Div for Dec {
    type Output = Dec;
    fn div(self, o: Dec) -> Dec {
        self.with2(o, self.x / o.x, denominator(o.x))
    }
}
impl Neg for Dec {
    type Output = Dec;
    fn neg(self) -> Dec {
        self.with(-self.x, Regularity::Smooth)
    }
}

impl Num for Dec {
    fn cst(c: Const) -> Self {
        Dec::new(Iv::from_const(&c), Regularity::Smooth)
    }
    fn add_const(&self, c: &Const) -> Self {
        self.with(self.x.add_const(c), Regularity::Smooth)
    }
    fn sub_const(&self, c: &Const) -> Self {
        self.with(self.x.sub_const(c), Regularity::Smooth)
    }
    fn const_sub(&self, c: &Const) -> Self {
        self.with(self.x.const_sub(c), Regularity::Smooth)
    }
    fn mul_const(&self, c: &Const) -> Self {
        self.with(self.x.mul_const(c), Regularity::Smooth)
    }
    fn div_const(&self, c: &Const) -> Self {
        self.with(self.x.div_const(c), denominator(Iv::from_const(c)))
    }
    fn square(&self) -> Self {
        self.with(self.x.square(), Regularity::Smooth)
    }
    fn powi(&self, n: i32) -> Self {
        let cap = if n >= 0 {
            Regularity::Smooth
        } else {
            denominator(self.x)
        };
        self.with(Num::powi(&self.x, n), cap)
    }
    fn sqrt(&self) -> Self {
        let cap = if self.x.lo > 0.0 {
            Regularity::Smooth
        } else if self.x.lo >= 0.0 && self.x.lo <= self.x.hi {
            // √ is continuous on its closed domain [0, ∞), not differentiable at 0.
            Regularity::Continuous
        } else {
            Regularity::Undefined
        };
        self.with(Num::sqrt(&self.x), cap)
    }
    fn abs(&self) -> Self {
        let cap = if free_of_zero(self.x) {
            Regularity::Smooth
        } else {
            Regularity::Continuous
        };
        self.with(Num::abs(&self.x), cap)
    }
    fn sign(&self) -> Self {
        let cap = if free_of_zero(self.x) {
            Regularity::Smooth
        } else {
            Regularity::Undefined
        };
        self.with(self.x.sign(), cap)
    }
    fn kink(&self) -> Self {
        let cap = if free_of_zero(self.x) {
            Regularity::Smooth
        } else {
            Regularity::Undefined
        };
        self.with(self.x.kink(), cap)
    }
    fn min(&self, o: &Self) -> Self {
        let cap = if self.x.hi < o.x.lo || o.x.hi < self.x.lo {
            Regularity::Smooth
        } else {
            Regularity::Continuous
        };
        self.with2(*o, Num::min(&self.x, &o.x), cap)
    }
    fn max(&self, o: &Self) -> Self {
        let cap = if self.x.hi < o.x.lo || o.x.hi < self.x.lo {
            Regularity::Smooth
        } else {
            Regularity::Continuous
        };
        self.with2(*o, Num::max(&self.x, &o.x), cap)
    }
    fn sin(&self) -> Self {
        self.with(Num::sin(&self.x), Regularity::Smooth)
    }
    fn cos(&self) -> Self {
        self.with(Num::cos(&self.x), Regularity::Smooth)
    }
    fn exp(&self) -> Self {
        self.with(Num::exp(&self.x), Regularity::Smooth)
    }
    fn ln(&self) -> Self {
        let cap = if self.x.lo > 0.0 {
            Regularity::Smooth
        } else {
            Regularity::Undefined
        };
        self.with(Num::ln(&self.x), cap)
    }
}

/// A value computed from an empty argument (outside the domain everywhere) is
/// undefined whatever the flags say.
pub fn finish(d: Dec) -> Regularity {
    if d.x.is_empty() {
        Regularity::Undefined
    } else {
        d.reg
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iv(a: f64, b: f64) -> Dec {
        Dec::var(Iv::new(a, b))
    }

    #[test]
    fn poles_and_kinks() {
        assert_eq!((iv(1.0, 2.0) / iv(0.0, 1.0)).reg, Regularity::Undefined);
        assert_eq!((iv(1.0, 2.0) / iv(0.5, 1.0)).reg, Regularity::Smooth);
        assert_eq!(iv(0.0, 1.0).sqrt().reg, Regularity::Continuous);
        assert_eq!(iv(-1.0, 1.0).sqrt().reg, Regularity::Undefined);
        assert_eq!(iv(-1.0, 1.0).abs().reg, Regularity::Continuous);
        assert_eq!(iv(0.0, 1.0).abs().reg, Regularity::Continuous);
        assert_eq!(iv(0.1, 1.0).abs().reg, Regularity::Smooth);
        assert_eq!(iv(-1.0, 1.0).powi(-1).reg, Regularity::Undefined);
        assert_eq!(iv(0.0, 1.0).ln().reg, Regularity::Undefined);
        assert_eq!(iv(0.0, 1.0).min(&iv(2.0, 3.0)).reg, Regularity::Smooth);
        assert_eq!(iv(0.0, 2.0).max(&iv(2.0, 3.0)).reg, Regularity::Continuous);
        // The flag propagates: a smooth operation does not repair its argument.
        let bad = iv(1.0, 2.0) / iv(-1.0, 1.0);
        assert_eq!((bad * iv(0.0, 0.0)).reg, Regularity::Undefined);
    }
}
