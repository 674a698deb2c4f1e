//! Filtered exact predicates and the symbolic perturbation of the in-sphere test.
//!
//! Each predicate first evaluates the determinant in floating point, in exactly the
//! expression order of Shewchuk's stage A ("Adaptive Precision Floating-Point
//! Arithmetic and Fast Robust Geometric Predicates", 1997), together with his a-priori
//! error bound (a constant times the permanent of the matrix). Only when the float
//! value does not clear that bound is the exact adaptive predicate of the `robust`
//! crate called. The returned sign is always exact.
//!
//! [`insphere_sos`] never answers "on the sphere": a zero in-sphere determinant is
//! resolved by the symbolic perturbation of Devillers and Teillaud ("Perturbations for
//! Delaunay and weighted Delaunay 3D triangulations", 2011), the scheme CGAL uses in
//! `side_of_oriented_sphere`: the lifted coordinate |p|² of every point is perturbed by
//! an infinitesimal whose size is given by the lexicographic (x, y, z) order of the
//! points, and the sign of the leading non-zero term is an orientation test. Because
//! the order is by coordinates, not by insertion rank, the triangulation of a point
//! set does not depend on the insertion order.
use robust::Coord3D;

const EPS: f64 = f64::EPSILON * 0.5; // 2^-53, Shewchuk's epsilon
const O3D_BOUND: f64 = (7.0 + 56.0 * EPS) * EPS;
const ISP_BOUND: f64 = (16.0 + 224.0 * EPS) * EPS;

#[inline]
fn c3(p: [f64; 3]) -> Coord3D<f64> {
    Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

/// Positive when `(a, b, c, d)` is positively oriented (certmesh's convention, the
/// same as [`crate::kernel::predicates::orient3d`]: the unit tetrahedron 0, e1, e2, e3
/// is positive), zero when coplanar. The sign is exact; the magnitude is not.
#[inline]
pub fn orient3d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    let adx = a[0] - d[0];
    let bdx = b[0] - d[0];
    let cdx = c[0] - d[0];
    let ady = a[1] - d[1];
    let bdy = b[1] - d[1];
    let cdy = c[1] - d[1];
    let adz = a[2] - d[2];
    let bdz = b[2] - d[2];
    let cdz = c[2] - d[2];
    let bdxcdy = bdx * cdy;
    let cdxbdy = cdx * bdy;
    let cdxady = cdx * ady;
    let adxcdy = adx * cdy;
    let adxbdy = adx * bdy;
    let bdxady = bdx * ady;
    let det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    let perm = (bdxcdy.abs() + cdxbdy.abs()) * adz.abs()
        + (cdxady.abs() + adxcdy.abs()) * bdz.abs()
        + (adxbdy.abs() + bdxady.abs()) * cdz.abs();
    let bound = O3D_BOUND * perm;
    if det > bound || -det > bound {
        return -det; // Shewchuk's sign is the opposite of ours
    }
    -robust::orient3d(c3(a), c3(b), c3(c), c3(d))
}

/// Positive when `e` lies strictly inside the sphere through `a, b, c, d` for a
/// positively oriented `(a, b, c, d)`, negative outside, zero on it. Exact sign.
#[inline]
pub fn insphere(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3], e: [f64; 3]) -> f64 {
    let aex = a[0] - e[0];
    let bex = b[0] - e[0];
    let cex = c[0] - e[0];
    let dex = d[0] - e[0];
    let aey = a[1] - e[1];
    let bey = b[1] - e[1];
    let cey = c[1] - e[1];
    let dey = d[1] - e[1];
    let aez = a[2] - e[2];
    let bez = b[2] - e[2];
    let cez = c[2] - e[2];
    let dez = d[2] - e[2];

    let aexbey = aex * bey;
    let bexaey = bex * aey;
    let ab = aexbey - bexaey;
    let bexcey = bex * cey;
    let cexbey = cex * bey;
    let bc = bexcey - cexbey;
    let cexdey = cex * dey;
    let dexcey = dex * cey;
    let cd = cexdey - dexcey;
    let dexaey = dex * aey;
    let aexdey = aex * dey;
    let da = dexaey - aexdey;
    let aexcey = aex * cey;
    let cexaey = cex * aey;
    let ac = aexcey - cexaey;
    let bexdey = bex * dey;
    let dexbey = dex * bey;
    let bd = bexdey - dexbey;

    let abc = aez * bc - bez * ac + cez * ab;
    let bcd = bez * cd - cez * bd + dez * bc;
    let cda = cez * da + dez * ac + aez * cd;
    let dab = dez * ab + aez * bd + bez * da;

    let alift = aex * aex + aey * aey + aez * aez;
    let blift = bex * bex + bey * bey + bez * bez;
    let clift = cex * cex + cey * cey + cez * cez;
    let dlift = dex * dex + dey * dey + dez * dez;

    let det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);

    let aezp = aez.abs();
    let bezp = bez.abs();
    let cezp = cez.abs();
    let dezp = dez.abs();
    let aexbeyp = aexbey.abs();
    let bexaeyp = bexaey.abs();
    let bexceyp = bexcey.abs();
    let cexbeyp = cexbey.abs();
    let cexdeyp = cexdey.abs();
    let dexceyp = dexcey.abs();
    let dexaeyp = dexaey.abs();
    let aexdeyp = aexdey.abs();
    let aexceyp = aexcey.abs();
    let cexaeyp = cexaey.abs();
    let bexdeyp = bexdey.abs();
    let dexbeyp = dexbey.abs();
    let perm = ((cexdeyp + dexceyp) * bezp
        + (dexbeyp + bexdeyp) * cezp
        + (bexceyp + cexbeyp) * dezp)
        * alift
        + ((dexaeyp + aexdeyp) * cezp + (aexceyp + cexaeyp) * dezp + (cexdeyp + dexceyp) * aezp)
            * blift
        + ((aexbeyp + bexaeyp) * dezp + (bexdeyp + dexbeyp) * aezp + (dexaeyp + aexdeyp) * bezp)
            * clift
        + ((bexceyp + cexbeyp) * aezp + (cexaeyp + aexceyp) * bezp + (aexbeyp + bexaeyp) * cezp)
            * dlift;
    let bound = ISP_BOUND * perm;
    if det > bound || -det > bound {
        return -det;
    }
    insphere_stage2(a, b, c, d, e, perm)
}

// Second stage: double-double arithmetic. The differences are exact (two_diff), each
// product and sum carries a relative/absolute error of a few ε² of its operands'
// magnitudes, so the error of the whole evaluation is below a few hundred ε²·perm.
// DD_BOUND = 2^-80·perm is 2^26 ε²·perm: a margin of over 10^5. Outside the exponent
// range where that analysis holds (underflow of the low parts, overflow), and when the
// value does not clear the bound, the exact adaptive predicate decides.
const DD_BOUND: f64 = 8.271806125530277e-25; // 2^-80
const DD_MIN_PERM: f64 = 1.1830521861667747e-271; // about 2^-900
const DD_MAX_PERM: f64 = 1.0715086071862673e301; // 2^1000

#[derive(Clone, Copy)]
struct Dd(f64, f64);

#[inline(always)]
fn two_diff(a: f64, b: f64) -> Dd {
    let s = a - b;
    let bb = s - a;
    let e = (a - (s - bb)) - (b + bb);
    Dd(s, e)
}
#[inline(always)]
fn quick_two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    Dd(s, b - (s - a))
}
#[inline(always)]
fn mul(x: Dd, y: Dd) -> Dd {
    let p = x.0 * y.0;
    let e = x.0.mul_add(y.0, -p) + (x.0 * y.1 + x.1 * y.0);
    quick_two_sum(p, e)
}
#[inline(always)]
fn add(x: Dd, y: Dd) -> Dd {
    let s = x.0 + y.0;
    let bb = s - x.0;
    let e = (x.0 - (s - bb)) + (y.0 - bb) + (x.1 + y.1);
    quick_two_sum(s, e)
}
#[inline(always)]
fn sub(x: Dd, y: Dd) -> Dd {
    add(x, Dd(-y.0, -y.1))
}

#[inline(never)]
fn insphere_stage2(
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    d: [f64; 3],
    e: [f64; 3],
    perm: f64,
) -> f64 {
    if perm > DD_MIN_PERM && perm < DD_MAX_PERM {
        let aex = two_diff(a[0], e[0]);
        let bex = two_diff(b[0], e[0]);
        let cex = two_diff(c[0], e[0]);
        let dex = two_diff(d[0], e[0]);
        let aey = two_diff(a[1], e[1]);
        let bey = two_diff(b[1], e[1]);
        let cey = two_diff(c[1], e[1]);
        let dey = two_diff(d[1], e[1]);
        let aez = two_diff(a[2], e[2]);
        let bez = two_diff(b[2], e[2]);
        let cez = two_diff(c[2], e[2]);
        let dez = two_diff(d[2], e[2]);
        let ab = sub(mul(aex, bey), mul(bex, aey));
        let bc = sub(mul(bex, cey), mul(cex, bey));
        let cd = sub(mul(cex, dey), mul(dex, cey));
        let da = sub(mul(dex, aey), mul(aex, dey));
        let ac = sub(mul(aex, cey), mul(cex, aey));
        let bd = sub(mul(bex, dey), mul(dex, bey));
        let abc = add(sub(mul(aez, bc), mul(bez, ac)), mul(cez, ab));
        let bcd = add(sub(mul(bez, cd), mul(cez, bd)), mul(dez, bc));
        let cda = add(add(mul(cez, da), mul(dez, ac)), mul(aez, cd));
        let dab = add(add(mul(dez, ab), mul(aez, bd)), mul(bez, da));
        let alift = add(add(mul(aex, aex), mul(aey, aey)), mul(aez, aez));
        let blift = add(add(mul(bex, bex), mul(bey, bey)), mul(bez, bez));
        let clift = add(add(mul(cex, cex), mul(cey, cey)), mul(cez, cez));
        let dlift = add(add(mul(dex, dex), mul(dey, dey)), mul(dez, dez));
        let det = add(
            sub(mul(dlift, abc), mul(clift, dab)),
            sub(mul(blift, cda), mul(alift, bcd)),
        );
        let v = det.0 + det.1;
        let bound = DD_BOUND * perm;
        if v > bound || -v > bound {
            return -v;
        }
    }
    -robust::insphere(c3(a), c3(b), c3(c), c3(d), c3(e))
}

#[inline]
fn lex_less(p: [f64; 3], q: [f64; 3]) -> bool {
    (p[0], p[1], p[2]) < (q[0], q[1], q[2])
}

/// The perturbed in-sphere test: `+1` when `e` is inside the sphere through the
/// positively oriented `(a, b, c, d)`, `-1` when outside; never 0 for five distinct
/// points with `orient3d(a, b, c, d) > 0`. See the module documentation.
#[inline]
pub fn insphere_sos(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3], e: [f64; 3]) -> i32 {
    let s = insphere(a, b, c, d, e);
    if s > 0.0 {
        1
    } else if s < 0.0 {
        -1
    } else {
        insphere_tiebreak([a, b, c, d], e)
    }
}

#[cold]
fn insphere_tiebreak(t: [[f64; 3]; 4], e: [f64; 3]) -> i32 {
    let pts = [t[0], t[1], t[2], t[3], e];
    let mut idx = [0usize, 1, 2, 3, 4];
    // insertion sort, ascending lexicographic
    for i in 1..5 {
        let mut j = i;
        while j > 0 && lex_less(pts[idx[j]], pts[idx[j - 1]]) {
            idx.swap(j, j - 1);
            j -= 1;
        }
    }
    for k in (0..5).rev() {
        let i = idx[k];
        if i == 4 {
            return -1;
        }
        let mut q = t;
        q[i] = e;
        let o = orient3d(q[0], q[1], q[2], q[3]);
        if o > 0.0 {
            return 1;
        }
        if o < 0.0 {
            return -1;
        }
    }
    -1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filter_agrees_with_robust() {
        let mut s = 0x1234_5678_9abc_def0u64;
        let mut r = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for k in 0..20000 {
            let mut p = [[0.0; 3]; 5];
            for q in p.iter_mut() {
                *q = [r(), r(), r()];
            }
            if k % 2 == 0 {
                // near-degenerate: e close to the plane / sphere of the others
                for q in p.iter_mut() {
                    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
                    *q = q.map(|x| x / n);
                }
            }
            let o = orient3d(p[0], p[1], p[2], p[3]);
            let ro = crate::kernel::predicates::orient3d(p[0], p[1], p[2], p[3]);
            assert_eq!(o.signum(), ro.signum());
            let i = insphere(p[0], p[1], p[2], p[3], p[4]);
            let ri = crate::kernel::predicates::insphere(p[0], p[1], p[2], p[3], p[4]);
            assert_eq!(i.signum(), ri.signum());
        }
    }

    #[test]
    fn cospherical_ties_are_broken() {
        let a = [0.0, 0.0, 0.0];
        let b = [1.0, 0.0, 0.0];
        let c = [0.0, 1.0, 0.0];
        let d = [0.0, 0.0, 1.0];
        let e = [1.0, 1.0, 0.0];
        assert_eq!(insphere(a, b, c, d, e), 0.0);
        let s = insphere_sos(a, b, c, d, e);
        assert!(s == 1 || s == -1);
        // Inside and outside keep their exact answers.
        assert_eq!(insphere_sos(a, b, c, d, [0.2, 0.2, 0.2]), 1);
        assert_eq!(insphere_sos(a, b, c, d, [3.0, 3.0, 3.0]), -1);
    }
}
