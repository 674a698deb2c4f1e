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

/// First-order dual number over intervals: value and partial derivatives in `N`
/// independent variables (2 for the GradNormal charts, 4 for the stuffing cases).
#[derive(Clone, Copy, Debug)]
pub struct Dual<const N: usize> {
    pub v: Interval,
    pub g: [Interval; N],
}

/// The GradNormal proof's duals: partial derivatives in the chart coordinates (u, v).
pub type D2 = Dual<2>;

impl<const N: usize> Dual<N> {
    #[inline]
    pub fn cst(v: Interval) -> Self {
        Dual { v, g: [pt(0.0); N] }
    }
    /// The k-th independent variable ranging over `v`.
    #[inline]
    pub fn var(v: Interval, k: usize) -> Self {
        let mut g = [pt(0.0); N];
        g[k] = pt(1.0);
        Dual { v, g }
    }
    #[inline]
    pub fn scale(self, c: Interval) -> Self {
        Dual {
            v: self.v * c,
            g: self.g.map(|x| x * c),
        }
    }
    #[inline]
    pub fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        let d = pt(2.0) * s;
        Dual {
            v: s,
            g: self.g.map(|x| x / d),
        }
    }
    #[inline]
    pub fn div(self, o: Self) -> Self {
        let q = self.v / o.v;
        let mut g = self.g;
        for k in 0..N {
            g[k] = (self.g[k] - q * o.g[k]) / o.v;
        }
        Dual { v: q, g }
    }
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        let mut g = self.g;
        for k in 0..N {
            g[k] = g[k] + o.g[k];
        }
        Dual { v: self.v + o.v, g }
    }
}
impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        let mut g = self.g;
        for k in 0..N {
            g[k] = g[k] - o.g[k];
        }
        Dual { v: self.v - o.v, g }
    }
}
impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let mut g = self.g;
        for k in 0..N {
            g[k] = self.g[k] * o.v + self.v * o.g[k];
        }
        Dual { v: self.v * o.v, g }
    }
}
impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Dual {
            v: -self.v,
            g: self.g.map(|x| -x),
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
