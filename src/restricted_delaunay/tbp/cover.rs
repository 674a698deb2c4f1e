//! Branch and bound over a convex Voronoi region: cover the part of the region inside
//! the domain by boxes, each accepted by a criterion proven with interval arithmetic
//! (0 ∉ □f, or 0 ∉ □(∇f·d), or the silhouette criterion of equation (1.5)), or fail at
//! the first box that cannot be decided within the budget.
//!
//! A region is given by half-spaces that contain it (a Voronoi cell V(p) lies in
//! {x : |x − p| ≤ |x − r|} for every site r), and optionally a plane it lies in (a
//! Voronoi facet lies in the bisector of its two sites). A box that misses one of
//! them, proven by interval evaluation of the affine function, holds no point of the
//! region and is dropped. Covering more than the region is harmless: every test is
//! then stronger than needed.
use crate::implicit::directed::Iv;
use crate::implicit::ops::mean_value_if;
use crate::implicit::{Dual, IBox, Implicit, Regularity};
use inari::Interval;

/// {x : a·x − b ≤ 0}, with interval coefficients enclosing the exact ones (held in the
/// evaluator's fast interval type [`Iv`], whose bounds are inari's, bit for bit).
#[derive(Clone, Copy, Debug)]
pub struct HalfSpace {
    pub a: [Iv; 3],
    pub b: Iv,
}

pub(crate) fn pt(x: f64) -> Interval {
    Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE)
}

/// [`pt`] as an [`Iv`] (the fast interval type: inari's bounds, bit for bit).
fn ipt(x: f64) -> Iv {
    Iv::from_interval(pt(x))
}

fn ivs(x: &[Interval; 3]) -> [Iv; 3] {
    x.map(Iv::from_interval)
}

impl HalfSpace {
    /// The points at least as close to `p` as to `r`: 2 x·(r − p) − (|r|² − |p|²) ≤ 0,
    /// every coefficient enclosed by outward-rounded interval arithmetic.
    pub fn closer(p: [f64; 3], r: [f64; 3]) -> Self {
        let (pi, ri) = (p.map(ipt), r.map(ipt));
        let two = Iv::point(2.0);
        let n2 = |v: [Iv; 3]| v[0].sqr() + v[1].sqr() + v[2].sqr();
        HalfSpace {
            a: [0, 1, 2].map(|k| two * (ri[k] - pi[k])),
            b: n2(ri) - n2(pi),
        }
    }
    /// An enclosure of a·x − b over the box (the box as [`Iv`]s, see [`Region::place`]).
    pub fn value(&self, x: &[Iv; 3]) -> Iv {
        // A point coefficient (the common case: 2 (r − p) is exact) takes two products.
        let term = |k: usize| {
            let a = self.a[k];
            if a.lo == a.hi {
                x[k].mul_point(a.lo)
            } else {
                a * x[k]
            }
        };
        term(0) + term(1) + term(2) - self.b
    }
}

/// Where a box lies relative to the region.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Place {
    /// Proven disjoint from the region.
    Outside,
    /// Proven inside every half-space, strictly (so inside the interior of a cell).
    Inside,
    /// Neither.
    Straddles,
}

/// A convex region: the intersection of `halfspaces`, and of the plane {value = 0} of
/// `plane` when given.
pub struct Region<'a> {
    pub halfspaces: &'a [HalfSpace],
    pub plane: Option<HalfSpace>,
}

/// The half-spaces of a [`Region`] a box still has to be placed against: bit i stands
/// for half-space i (< 64); those from 64 on are always checked.
pub type Pending = u64;

/// Every half-space pending.
pub const ALL: Pending = u64::MAX;

impl Region<'_> {
    pub fn place(&self, x: &IBox) -> Place {
        self.place_pending(x, ALL).0
    }

    /// [`Region::place`] against the `pending` half-spaces only, with those the box is
    /// proven strictly inside of cleared in the returned set. A half-space that holds
    /// strictly on a box holds on each of its sub-boxes, so a sub-box is placed against
    /// its parent's returned set: the result is the full `place`, with fewer
    /// evaluations.
    pub fn place_pending(&self, x: &IBox, pending: Pending) -> (Place, Pending) {
        let x = x.map(Iv::from_interval);
        if let Some(h) = &self.plane {
            let v = h.value(&x);
            if v.lo > 0.0 || v.hi < 0.0 {
                return (Place::Outside, pending);
            }
        }
        let mut left = pending;
        let mut beyond_inside = true; // half-spaces 64 and on
        for (i, h) in self.halfspaces.iter().enumerate() {
            if i < 64 && left & (1 << i) == 0 {
                continue;
            }
            let v = h.value(&x);
            // NaN bounds (an overflow) fail both comparisons: never Outside, never
            // proven inside.
            if v.lo > 0.0 {
                return (Place::Outside, left);
            }
            let strict = v.hi < 0.0;
            if i < 64 {
                if strict {
                    left &= !(1 << i);
                }
            } else {
                beyond_inside &= strict;
            }
        }
        let n = self.halfspaces.len().min(64);
        let low = if n == 64 { u64::MAX } else { (1u64 << n) - 1 };
        let inside = self.plane.is_none() && beyond_inside && left & low == 0;
        let place = if inside {
            Place::Inside
        } else {
            Place::Straddles
        };
        (place, left)
    }
}

/// What a criterion concluded on one box.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Accept,
    Split,
}

/// Limits of one cover.
#[derive(Clone, Copy, Debug)]
pub struct CoverBudget {
    pub max_boxes: u32,
    /// Smallest box width relative to the initial box's widest side.
    pub min_rel_width: f64,
}

impl Default for CoverBudget {
    fn default() -> Self {
        CoverBudget {
            max_boxes: 3000,
            min_rel_width: 1e-7,
        }
    }
}

/// The result of one cover.
#[derive(Clone, Copy, Debug)]
pub struct Cover {
    /// Every box of the region was accepted.
    pub ok: bool,
    pub boxes: u32,
    /// The first box that could not be decided (budget or width limit).
    pub failed: Option<IBox>,
}

fn widest(x: &IBox) -> usize {
    (0..3)
        .max_by(|&a, &b| x[a].wid().total_cmp(&x[b].wid()))
        .unwrap_or(0)
}

/// Cover `region ∩ start` by boxes accepted by `crit` (called with the box and its
/// place, never with an `Outside` box).
pub fn cover(
    start: IBox,
    region: &Region,
    budget: CoverBudget,
    mut crit: impl FnMut(&IBox, Place) -> Verdict,
) -> Cover {
    let w0 = start[widest(&start)].wid();
    let min_w = (w0 * budget.min_rel_width).max(f64::MIN_POSITIVE);
    let mut stack = vec![(start, ALL)];
    let mut boxes = 0u32;
    while let Some((x, pending)) = stack.pop() {
        let (place, pending) = region.place_pending(&x, pending);
        if place == Place::Outside {
            continue;
        }
        boxes += 1;
        if crit(&x, place) == Verdict::Accept {
            continue;
        }
        let k = widest(&x);
        if boxes >= budget.max_boxes || x[k].wid() <= min_w {
            return Cover {
                ok: false,
                boxes,
                failed: Some(x),
            };
        }
        let m = x[k].mid();
        let (mut lo, mut hi) = (x, x);
        lo[k] = Interval::try_from((x[k].inf(), m)).unwrap_or(x[k]);
        hi[k] = Interval::try_from((m, x[k].sup())).unwrap_or(x[k]);
        stack.push((hi, pending));
        stack.push((lo, pending));
    }
    Cover {
        ok: true,
        boxes,
        failed: None,
    }
}

fn idot(a: &[Iv; 3], b: &[Iv; 3]) -> Iv {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn icross(a: &[Iv; 3], b: &[Iv; 3]) -> [Iv; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn excl(i: Interval) -> bool {
    !i.is_empty() && (i.inf() > 0.0 || i.sup() < 0.0)
}

/// Enclosures already computed over a box: `dv = f.grad_interval(x)` and `fv =
/// mean_value(f, x, &dv)` ([`crate::implicit::ops::mean_value`]). The criteria given
/// them for `x` reuse them (the same values: both are functions of the box alone).
#[derive(Clone, Copy, Debug)]
pub struct Known {
    pub dv: Dual<Interval>,
    pub fv: Interval,
}

/// The criterion of tests (3) and the fast path of (4): accept a box where f has no
/// zero, or where f is proven C^∞ and ∇f·d ≠ 0 (no point of S in the box has a normal
/// perpendicular to d). `d` is an interval vector (enclosing an exact direction).
/// `smooth`: f is already proven C^∞ on a box containing `x` (regularity is
/// inclusion-monotone), so it is not asked again. `known`: [`Known`] enclosures over
/// `x` itself (the start box of a cover), used instead of evaluating them again.
pub fn no_tangency(
    f: &dyn Implicit,
    x: &IBox,
    d: &[Interval; 3],
    smooth: bool,
    known: Option<&Known>,
) -> Verdict {
    // The verdict is: Accept iff 0 ∉ □f (the natural enclosure intersected with the
    // mean-value form, [`crate::implicit::ops::enclose`]) or (f C^∞ and 0 ∉ □(∇f·d)). It is computed in the
    // cheapest order: the natural enclosure comes with the gradient and contains the
    // intersected one (excluding 0 there excludes it from the tighter one), the
    // mean-value form costs one more evaluation and, without `smooth`, a decorated one.
    let dv = match known {
        Some(k) => k.dv,
        None => f.grad_interval(x),
    };
    if excl(dv.v) {
        return Verdict::Accept;
    }
    let tangent_free = || excl(idot(&ivs(&dv.g), &ivs(d)).to_interval());
    if smooth && tangent_free() {
        return Verdict::Accept;
    }
    // `known.fv` is this value: with `smooth`, f is C^∞ on x and both continuity
    // questions (here and in `mean_value`) are answered yes; without, they are the same.
    let fv = match known {
        Some(k) => k.fv,
        None => mean_value_if(f, x, &dv, || {
            smooth || f.regularity(x) >= Regularity::Continuous
        }),
    };
    if excl(fv) {
        return Verdict::Accept;
    }
    if !smooth && tangent_free() && f.regularity(x) == Regularity::Smooth {
        return Verdict::Accept;
    }
    Verdict::Split
}

/// The criterion of test (4): as [`no_tangency`] in direction `d`; moreover, on a box
/// strictly inside the cell, accept when det(H d, d′, ∇f) ≠ 0 (equation (1.5) of the
/// chapter): the silhouette {f = 0, ∇f·d = 0} is a smooth curve there (its two
/// gradients ∇f and H d are independent) without a point critical in direction d′.
pub fn no_silhouette(
    f: &dyn Implicit,
    x: &IBox,
    place: Place,
    d: &[Interval; 3],
    d2: &[Interval; 3],
    smooth: bool,
    known: Option<&Known>,
) -> Verdict {
    if no_tangency(f, x, d, smooth, known) == Verdict::Accept {
        return Verdict::Accept;
    }
    if place != Place::Inside || !(smooth || f.regularity(x) == Regularity::Smooth) {
        return Verdict::Split;
    }
    let h = f.hessian_interval(x);
    let hm = |i: usize, j: usize| Iv::from_interval(h.h[crate::implicit::number::hidx(i, j)]);
    let d = ivs(d);
    let hd: [Iv; 3] = std::array::from_fn(|i| hm(i, 0) * d[0] + hm(i, 1) * d[1] + hm(i, 2) * d[2]);
    // det(Hd, d', g) = Hd · (d' × g)
    let det = idot(&hd, &icross(&ivs(d2), &ivs(&h.g)));
    if excl(det.to_interval()) {
        Verdict::Accept
    } else {
        Verdict::Split
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b(lo: [f64; 3], hi: [f64; 3]) -> IBox {
        std::array::from_fn(|k| Interval::try_from((lo[k], hi[k])).unwrap())
    }

    #[test]
    fn halfspace_places_boxes() {
        // Closer to the origin than to (2, 0, 0): x <= 1.
        let h = [HalfSpace::closer([0.0; 3], [2.0, 0.0, 0.0])];
        let r = Region {
            halfspaces: &h,
            plane: None,
        };
        assert_eq!(r.place(&b([1.5, 0., 0.], [2., 1., 1.])), Place::Outside);
        assert_eq!(r.place(&b([0., 0., 0.], [0.5, 1., 1.])), Place::Inside);
        assert_eq!(r.place(&b([0.5, 0., 0.], [1.5, 1., 1.])), Place::Straddles);
        // On the bisector plane x = 1 only boxes meeting it survive.
        let r2 = Region {
            halfspaces: &[],
            plane: Some(h[0]),
        };
        assert_eq!(r2.place(&b([0., 0., 0.], [0.5, 1., 1.])), Place::Outside);
        assert_eq!(r2.place(&b([0.9, 0., 0.], [1.1, 1., 1.])), Place::Straddles);
    }

    /// The criterion as it was first written (one [`enclose`], then the direction):
    /// the reference the reordered [`no_tangency`] must agree with, box for box.
    fn no_tangency_reference(
        f: &dyn Implicit,
        x: &IBox,
        d: &[Interval; 3],
        smooth: bool,
    ) -> Verdict {
        let (fv, g) = crate::implicit::ops::enclose(f, x);
        if excl(fv) {
            return Verdict::Accept;
        }
        if excl(idot(&ivs(&g), &ivs(d)).to_interval())
            && (smooth || f.regularity(x) == Regularity::Smooth)
        {
            return Verdict::Accept;
        }
        Verdict::Split
    }

    proptest::proptest! {
        /// On random sub-boxes of random boxes (f smooth, merely continuous, or with a
        /// pole), with the caller's `smooth` taken from the outer box as the covers do,
        /// the reordered criterion gives the reference verdict.
        #[test]
        fn no_tangency_equals_its_reference(
            which in 0usize..4,
            lo in proptest::array::uniform3(-1.5f64..1.4),
            w in proptest::array::uniform3(0.001f64..1.0),
            t0 in proptest::array::uniform3(0.0f64..1.0),
            t1 in proptest::array::uniform3(0.0f64..1.0),
            d in proptest::array::uniform3(-1.0f64..1.0),
        ) {
            use crate::implicit::Formula;
            let text = [
                "z^2 + 0.5*(x^2/1.44 + y^2/0.64 - 1)*((x - 0.55)^2 + y^2 - 0.09)*((x + 0.55)^2 + y^2 - 0.09)",
                "sqrt(x^2 + y^2) - 0.5 + 0.3*z",
                "abs(x) + y^2 - z^2 - 0.1",
                "1/(x - 0.2) + y + z",
            ][which];
            let f = Formula::with_dim(text, 3).unwrap();
            let outer = b(lo, std::array::from_fn(|k| lo[k] + w[k]));
            // A sub-box of the outer box (a box of the cover below its start box).
            let x: IBox = std::array::from_fn(|k| {
                let (a, c) = (t0[k].min(t1[k]), t0[k].max(t1[k]));
                Interval::try_from((lo[k] + a * w[k], lo[k] + c * w[k])).unwrap()
            });
            let smooth = f.regularity(&outer) == Regularity::Smooth;
            let di = d.map(pt);
            // The enclosures the pre-test of the start boxes hands on.
            let dv = f.grad_interval(&x);
            let known = Known { dv, fv: crate::implicit::ops::mean_value(&f, &x, &dv) };
            for s in [smooth, false] {
                let want = no_tangency_reference(&f, &x, &di, s);
                proptest::prop_assert_eq!(no_tangency(&f, &x, &di, s, None), want);
                proptest::prop_assert_eq!(no_tangency(&f, &x, &di, s, Some(&known)), want);
            }
        }
    }

    #[test]
    fn cover_fails_at_a_tangency_and_passes_without() {
        use crate::implicit::Formula;
        let f = Formula::with_dim("x^2 + y^2 + z^2 - 1", 3).unwrap();
        let r = Region {
            halfspaces: &[],
            plane: None,
        };
        let up = [pt(0.0), pt(0.0), pt(1.0)];
        // The cap z > 0.5 has normals with positive z: no tangency to d = z.
        let cap = b([-0.9, -0.9, 0.5], [0.9, 0.9, 1.2]);
        let c = cover(cap, &r, CoverBudget::default(), |x, _| {
            no_tangency(&f, x, &up, false, None)
        });
        assert!(c.ok, "{c:?}");
        // The equator z = 0 is where the normal is perpendicular to z: never accepted.
        let belt = b([-1.2, -1.2, -0.2], [1.2, 1.2, 0.2]);
        let c = cover(belt, &r, CoverBudget::default(), |x, _| {
            no_tangency(&f, x, &up, false, None)
        });
        assert!(!c.ok);
        let fb = c.failed.unwrap();
        let m = [fb[0].mid(), fb[1].mid(), fb[2].mid()];
        assert!(m[2].abs() < 0.2);
    }
}
