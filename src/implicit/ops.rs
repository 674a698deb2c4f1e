//! Locating f = 0 on a segment with a sign change: shared by every lattice mesher.
use crate::kernel::geom::lerp;
use crate::implicit::Implicit;
use crate::mesher::options::Crossing;

/// The parameter t in [0, 1] of a crossing on the segment a→b, where `fa` and `fb`
/// have opposite signs (or one is zero). `tol` is the tolerance in t; bisection
/// stops at it or when the midpoint is no longer representable.
pub fn crossing_t(
    f: &dyn Implicit,
    a: [f64; 3],
    fa: f64,
    b: [f64; 3],
    fb: f64,
    how: Crossing,
    tol: f64,
) -> f64 {
    if fa == 0.0 {
        return 0.0;
    }
    if fb == 0.0 {
        return 1.0;
    }
    let linear = (fa / (fa - fb)).clamp(0.0, 1.0);
    match how {
        Crossing::Linear => linear,
        Crossing::Bisection => {
            let (mut lo, mut hi) = (0.0f64, 1.0f64);
            let neg_at_lo = fa < 0.0;
            while hi - lo > tol {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                let fm = f.eval(lerp(a, b, mid));
                if fm == 0.0 {
                    return mid;
                }
                if (fm < 0.0) == neg_at_lo {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        }
    }
}

/// The crossing point itself (see [`crossing_t`]).
pub fn crossing(
    f: &dyn Implicit,
    a: [f64; 3],
    fa: f64,
    b: [f64; 3],
    fb: f64,
    how: Crossing,
    tol: f64,
) -> [f64; 3] {
    lerp(a, b, crossing_t(f, a, fa, b, fb, how, tol))
}
