//! The floating-point filter of the exact sweep: integer polynomials with enclosing
//! `inari` intervals (outward rounding) as coefficients, evaluated by interval Horner.
//! A sign or an exclusion proven here is proven for the exact value too: every
//! conversion encloses the exact number, and interval arithmetic with outward rounding
//! encloses the exact interval evaluation of the same Horner formula, which is what the
//! certificate checker recomputes with exact rationals. When the filter cannot decide
//! (overflow, cancellation, intervals below f64 resolution) the caller falls back to
//! exact arithmetic.
use super::upoly::UPoly;
use crate::implicit::number::{next_down, next_up};
use inari::Interval;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{ToPrimitive, Zero};

/// An interval holding the integer `a`, or `None` beyond the f64 range.
pub fn int_iv(a: &BigInt) -> Option<Interval> {
    if a.is_zero() {
        return Interval::try_from((0.0, 0.0)).ok();
    }
    let f = a.to_f64()?;
    if !f.is_finite() {
        return None;
    }
    if a.bits() <= 53 {
        // Exactly representable.
        return Interval::try_from((f, f)).ok();
    }
    let (lo, hi) = (next_down(f), next_up(f));
    // Verify the enclosure exactly rather than trusting the conversion's rounding.
    let ok = BigRational::from_float(lo).is_some_and(|l| l.numer() <= a)
        && BigRational::from_float(hi).is_some_and(|h| h.numer() >= a);
    if !ok || !lo.is_finite() || !hi.is_finite() {
        return None;
    }
    Interval::try_from((lo, hi)).ok()
}

/// An interval holding the rational `x`.
pub fn q_iv(x: &BigRational) -> Option<Interval> {
    let n = int_iv(x.numer())?;
    if x.denom() == &BigInt::from(1) {
        return Some(n);
    }
    let d = int_iv(x.denom())?;
    let r = n / d;
    (r.inf().is_finite() && r.sup().is_finite()).then_some(r)
}

/// The hull of two rationals' enclosures: an interval holding \[lo, hi\].
pub fn qq_iv(lo: &BigRational, hi: &BigRational) -> Option<Interval> {
    let (a, b) = (q_iv(lo)?, q_iv(hi)?);
    Interval::try_from((a.inf(), b.sup())).ok()
}

/// The coefficients of `p` as enclosing intervals (constant term first).
pub fn poly_iv(p: &UPoly) -> Option<Vec<Interval>> {
    p.c.iter().map(int_iv).collect()
}

/// Σ c\[i\]·xⁱ by interval Horner (the formula of the exact checker).
pub fn horner(c: &[Interval], x: Interval) -> Interval {
    let mut it = c.iter().rev();
    let Some(&first) = it.next() else {
        return Interval::try_from((0.0, 0.0)).unwrap();
    };
    let mut acc = first;
    for &ci in it {
        acc = acc * x + ci;
    }
    acc
}

/// The sign of an interval when it excludes 0.
pub fn iv_sign(a: Interval) -> Option<i32> {
    if a.is_empty() {
        return None;
    }
    if a.inf() > 0.0 {
        Some(1)
    } else if a.sup() < 0.0 {
        Some(-1)
    } else {
        None
    }
}

/// A point interval (x finite).
pub fn pt(x: f64) -> Interval {
    Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE)
}
