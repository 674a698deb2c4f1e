//! Interval helpers: point intervals, 3-vectors, and a first-order dual number over
//! intervals (`D2`, value + gradient in two parameters) for mean-value enclosures.
//!
//! Why the mean-value form: the natural interval extension over-estimates by O(w) on a
//! box of width w, so near an interior extreme the branch and bound would keep O(1/w)
//! boxes; the mean-value form f(c) + ∇f(X)·(X − c) over-estimates by O(w²), so a fixed
//! number of boxes per level suffices to reach 1e-6 degrees.
use inari::Interval;
use std::ops::{Add, Mul, Neg, Sub};

/// The point interval [x, x] (x finite).
#[inline]
pub fn pt(x: f64) -> Interval {
    Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE)
}

/// The interval [lo, hi] (lo <= hi), or ENTIRE when malformed.
#[inline]
pub fn iv(lo: f64, hi: f64) -> Interval {
    Interval::try_from((lo, hi)).unwrap_or(Interval::ENTIRE)
}

/// An interval enclosing the exact value p/q of two small integers.
#[inline]
pub fn ratio(p: i64, q: i64) -> Interval {
    pt(p as f64) / pt(q as f64)
}

pub type IVec3 = [Interval; 3];

#[inline]
pub fn vsub(a: IVec3, b: IVec3) -> IVec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// First-order dual number over intervals: value and partial derivatives in (u, v).
#[derive(Clone, Copy, Debug)]
pub struct D2 {
    pub v: Interval,
    pub g: [Interval; 2],
}

impl D2 {
    #[inline]
    pub fn cst(v: Interval) -> Self {
        D2 {
            v,
            g: [pt(0.0), pt(0.0)],
        }
    }
    /// The k-th independent variable ranging over `v`.
    #[inline]
    pub fn var(v: Interval, k: usize) -> Self {
        let mut g = [pt(0.0), pt(0.0)];
        g[k] = pt(1.0);
        D2 { v, g }
    }
    #[inline]
    pub fn scale(self, c: Interval) -> Self {
        D2 {
            v: self.v * c,
            g: [self.g[0] * c, self.g[1] * c],
        }
    }
    #[inline]
    pub fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        let d = pt(2.0) * s;
        D2 {
            v: s,
            g: [self.g[0] / d, self.g[1] / d],
        }
    }
    #[inline]
    pub fn div(self, o: Self) -> Self {
        let q = self.v / o.v;
        D2 {
            v: q,
            g: [
                (self.g[0] - q * o.g[0]) / o.v,
                (self.g[1] - q * o.g[1]) / o.v,
            ],
        }
    }
}

impl Add for D2 {
    type Output = D2;
    #[inline]
    fn add(self, o: D2) -> D2 {
        D2 {
            v: self.v + o.v,
            g: [self.g[0] + o.g[0], self.g[1] + o.g[1]],
        }
    }
}
impl Sub for D2 {
    type Output = D2;
    #[inline]
    fn sub(self, o: D2) -> D2 {
        D2 {
            v: self.v - o.v,
            g: [self.g[0] - o.g[0], self.g[1] - o.g[1]],
        }
    }
}
impl Mul for D2 {
    type Output = D2;
    #[inline]
    fn mul(self, o: D2) -> D2 {
        D2 {
            v: self.v * o.v,
            g: [
                self.g[0] * o.v + self.v * o.g[0],
                self.g[1] * o.v + self.v * o.g[1],
            ],
        }
    }
}
impl Neg for D2 {
    type Output = D2;
    #[inline]
    fn neg(self) -> D2 {
        D2 {
            v: -self.v,
            g: [-self.g[0], -self.g[1]],
        }
    }
}

pub type DVec3 = [D2; 3];

/// m × w for a dual vector m and a constant vector w.
#[inline]
pub fn cross_c(m: &DVec3, w: &IVec3) -> DVec3 {
    [
        m[1].scale(w[2]) - m[2].scale(w[1]),
        m[2].scale(w[0]) - m[0].scale(w[2]),
        m[0].scale(w[1]) - m[1].scale(w[0]),
    ]
}

#[inline]
pub fn ddot(a: &DVec3, b: &DVec3) -> D2 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Mean-value enclosure of f over the box from the dual evaluation over the box (`over`)
/// and the value at the centre (`at_c`, a tight interval): f(c) + Σ ∂f(X)·(X_k − c_k),
/// intersected with the natural extension.
#[inline]
pub fn mean_value(over: &D2, at_c: Interval, half: [Interval; 2]) -> Interval {
    let mv = at_c + over.g[0] * half[0] + over.g[1] * half[1];
    let r = mv.intersection(over.v);
    if r.is_empty() {
        // Cannot happen for correct enclosures; keep the wider one rather than claim
        // emptiness.
        mv.convex_hull(over.v)
    } else {
        r
    }
}
