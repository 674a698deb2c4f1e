//! The fast interval kernel `Iv` (src/implicit/directed.rs): every operation encloses
//! the exact result (checked in exact rational arithmetic, independently of inari) and
//! gives the same bounds as inari (the tightest ones), on the fast path and on the
//! fallback paths alike (huge, tiny, infinite, empty operands; division by intervals
//! containing 0; square roots of partly negative intervals). Callers moved from inari's
//! arithmetic to `Iv` (segment isolation, interval circumcentres) give the results of
//! their inari versions.
use certmesh::implicit::{Const, Formula, Implicit, Iv, Num};
use inari::Interval;
use num_rational::BigRational;
use proptest::prelude::*;

mod common;
use common::arb_f64;

fn q(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

/// Intervals, including the empty one and unbounded ones.
fn arb_iv() -> impl Strategy<Value = Iv> {
    prop_oneof![
        20 => (arb_f64(), arb_f64()).prop_filter_map("no interval", |(a, b)| {
            let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
            Interval::try_from((lo, hi)).ok().map(Iv::from_interval)
        }),
        1 => Just(Iv::from_interval(Interval::EMPTY)),
        1 => Just(Iv::from_interval(Interval::ENTIRE)),
    ]
}

fn same(a: Iv, b: Interval) -> bool {
    if b.is_empty() {
        a.is_empty()
    } else {
        // Signed zeros compare equal, as they should.
        a.lo == b.inf() && a.hi == b.sup()
    }
}

fn finite(x: Iv) -> bool {
    !x.is_empty() && x.lo.is_finite() && x.hi.is_finite()
}

/// `r` encloses every exact value in `vals` (rationals).
fn encloses_all(r: Iv, vals: &[BigRational]) -> bool {
    vals.iter().all(|v| {
        (r.lo == f64::NEG_INFINITY || q(r.lo) <= *v) && (r.hi == f64::INFINITY || *v <= q(r.hi))
    })
}

fn corners(
    a: Iv,
    b: Iv,
    f: impl Fn(&BigRational, &BigRational) -> BigRational,
) -> Vec<BigRational> {
    let mut out = Vec::new();
    for x in [a.lo, a.hi] {
        for y in [b.lo, b.hi] {
            out.push(f(&q(x), &q(y)));
        }
    }
    out
}

fn konst(c: Iv) -> Const {
    Const {
        value: c.lo,
        lo: c.lo,
        hi: c.hi,
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 20000, ..ProptestConfig::default() })]

    #[test]
    fn add_sub_match_inari_and_enclose(a in arb_iv(), b in arb_iv()) {
        let (ia, ib) = (a.to_interval(), b.to_interval());
        prop_assert!(same(a + b, ia + ib), "{:?} + {:?} = {:?}, inari {:?}", a, b, a + b, ia + ib);
        prop_assert!(same(a - b, ia - ib), "{:?} - {:?} = {:?}, inari {:?}", a, b, a - b, ia - ib);
        if finite(a) && finite(b) {
            prop_assert!(encloses_all(a + b, &corners(a, b, |x, y| x + y)));
            prop_assert!(encloses_all(a - b, &corners(a, b, |x, y| x - y)));
        }
    }

    #[test]
    fn mul_matches_inari_and_encloses(a in arb_iv(), b in arb_iv()) {
        let (ia, ib) = (a.to_interval(), b.to_interval());
        prop_assert!(same(a * b, ia * ib), "{:?} * {:?} = {:?}, inari {:?}", a, b, a * b, ia * ib);
        if finite(a) && finite(b) {
            prop_assert!(encloses_all(a * b, &corners(a, b, |x, y| x * y)));
        }
    }

    #[test]
    fn div_matches_inari_and_encloses(a in arb_iv(), b in arb_iv()) {
        let (ia, ib) = (a.to_interval(), b.to_interval());
        prop_assert!(same(a / b, ia / ib), "{:?} / {:?} = {:?}, inari {:?}", a, b, a / b, ia / ib);
        if finite(a) && finite(b) && !b.contains(0.0) {
            prop_assert!(encloses_all(a / b, &corners(a, b, |x, y| x / y)));
        }
    }

    /// Division by an interval containing 0: every quotient x / y with y ≠ 0 in the
    /// divisor is enclosed.
    #[test]
    fn div_by_zero_containing_encloses(a in arb_iv(), t in -50.0f64..50.0, w in 0.0f64..10.0, s in 0.0f64..=1.0) {
        let b = Iv::new(-w * s, w * (1.0 - s) + 1e-3);
        let r = a / b;
        prop_assert!(same(r, a.to_interval() / b.to_interval()));
        if finite(a) && a.contains(t) {
            for y in [b.lo, b.hi, 0.5 * b.hi] {
                if y != 0.0 {
                    prop_assert!(encloses_all(r, &[q(t) / q(y)]), "{:?} / {:?} misses {}/{}", a, b, t, y);
                }
            }
        }
    }

    #[test]
    fn square_and_even_powers_are_tight(a in arb_iv(), k in 1u32..5) {
        let ia = a.to_interval();
        prop_assert!(same(a.sqr(), ia.sqr()), "{:?}² = {:?}, inari {:?}", a, a.sqr(), ia.sqr());
        let n = 2 * k;
        let r = a.pown(n);
        if finite(a) && a.contains(0.0) {
            prop_assert_eq!(r.lo, 0.0, "{:?}^{} = {:?}", a, n, r);
        }
        if finite(a) && finite(r) {
            let p = |x: f64| { let mut acc = q(1.0); for _ in 0..n { acc *= q(x); } acc };
            prop_assert!(encloses_all(r, &[p(a.lo), p(a.hi)]));
            prop_assert!(r.lo >= 0.0);
        }
    }

    #[test]
    fn odd_powers_enclose(a in arb_iv(), k in 0u32..3) {
        let n = 2 * k + 1;
        let r = a.pown(n);
        if finite(a) && finite(r) {
            let p = |x: f64| { let mut acc = q(1.0); for _ in 0..n { acc *= q(x); } acc };
            prop_assert!(encloses_all(r, &[p(a.lo), p(a.hi)]), "{:?}^{} = {:?}", a, n, r);
        }
    }

    /// sqrt over the part of the interval where it is defined (partly negative input
    /// allowed): lo² ≤ max(x.lo, 0) and hi² ≥ x.hi, exactly.
    #[test]
    fn sqrt_matches_inari_and_encloses(a in arb_iv()) {
        let r = Num::sqrt(&a);
        let ia = a.to_interval();
        prop_assert!(same(r, ia.sqrt()), "sqrt {:?} = {:?}, inari {:?}", a, r, ia.sqrt());
        if finite(a) && a.hi >= 0.0 {
            let lo = q(a.lo.max(0.0));
            prop_assert!(q(r.lo) * q(r.lo) <= lo);
            prop_assert!(q(r.hi) * q(r.hi) >= q(a.hi));
        }
    }

    /// The fused constant operations against the general ones (inari) and exactly.
    #[test]
    fn const_ops_match_inari_and_enclose(
        a in arb_iv(),
        c in arb_f64().prop_map(|c| if c.abs() < f64::MAX { c } else { -2.5 }),
        wide in any::<bool>(),
    ) {
        // A point constant, or a one-ulp enclosure like that of 0.1.
        let k = if wide && c != 0.0 {
            Iv::new(certmesh::implicit::number::next_down(c), certmesh::implicit::number::next_up(c))
        } else {
            Iv::point(c)
        };
        let (ia, ik) = (a.to_interval(), k.to_interval());
        let kc = konst(k);
        prop_assert!(same(a.add_const(&kc), ia + ik));
        prop_assert!(same(a.sub_const(&kc), ia - ik));
        prop_assert!(same(a.const_sub(&kc), ik - ia));
        prop_assert!(same(a.mul_const(&kc), ia * ik), "{:?} * {:?} = {:?}, inari {:?}", a, k, a.mul_const(&kc), ia * ik);
        prop_assert!(same(a.div_const(&kc), ia / ik), "{:?} / {:?} = {:?}, inari {:?}", a, k, a.div_const(&kc), ia / ik);
        if finite(a) {
            prop_assert!(encloses_all(a.mul_const(&kc), &corners(a, k, |x, y| x * y)));
            if !k.contains(0.0) {
                prop_assert!(encloses_all(a.div_const(&kc), &corners(a, k, |x, y| x / y)));
            }
        }
    }

    #[test]
    fn abs_min_max_match_inari(a in arb_iv(), b in arb_iv()) {
        let (ia, ib) = (a.to_interval(), b.to_interval());
        prop_assert!(same(Num::abs(&a), ia.abs()));
        prop_assert!(same(Num::min(&a, &b), ia.min(ib)));
        prop_assert!(same(Num::max(&a, &b), ia.max(ib)));
        prop_assert!(same(-a, -ia));
        prop_assert!(same(Num::sign(&a), ia.sign()));
    }
}

/// The tape's interval evaluation (on `Iv`) gives the same bounds as the generic
/// interpreter on inari intervals, formula by formula.
#[test]
fn iv_tape_equals_inari_tape() {
    let formulas = [
        "z^2 + 0.5*(x^2/1.44 + y^2/0.64 - 1)*((x - 0.55)^2 + y^2 - 0.09)*((x + 0.55)^2 + y^2 - 0.09)",
        "x*x - 0.1*y + 3/(z + 2.5) - (1 - x)^3",
        "sqrt(x^2 + y^2) - 0.3 + abs(z) * min(x, y) - max(0.2, x*y)",
        "1/x + 2.7*y^(-2) - z^5",
    ];
    let boxes = [
        [(-0.3, 0.2), (0.1, 0.15), (-1.0, -0.9)],
        [(0.5, 0.51), (-2.0, 1.0), (0.0, 0.0)],
        [(-1e-3, 1e-3), (1.0, 1.0), (3.0, 4.0)],
    ];
    for text in formulas {
        let f = Formula::surface(text).unwrap();
        for b in boxes {
            let ib = b.map(|(lo, hi)| Interval::try_from((lo, hi)).unwrap());
            let fast = f.eval_interval(&ib);
            let generic: Interval = f.tape().eval(&ib, &mut Vec::new());
            assert!(
                fast == generic || (fast.is_empty() && generic.is_empty()),
                "{text} over {b:?}: {fast:?} vs {generic:?}"
            );
        }
    }
}

/// Fused constants keep rigour: 0.1 is enclosed (not rounded) inside x*0.1, x/0.1,
/// 0.1 - x and x + 0.1 — the point [1, 1] maps to an interval that strictly contains
/// the exact decimal result.
#[test]
fn fused_inexact_constants_stay_enclosed() {
    let p = [Interval::try_from((1.0, 1.0)).unwrap(); 3];
    for (text, exact_num, exact_den) in [
        ("x*0.1", 1, 10),
        ("x/0.1", 10, 1),
        ("0.1 - x", -9, 10),
        ("x + 0.1", 11, 10),
    ] {
        let f = Formula::surface(text).unwrap();
        let r = f.eval_interval(&p);
        let exact = BigRational::new(exact_num.into(), exact_den.into());
        assert!(q(r.inf()) < exact && exact < q(r.sup()), "{text}: {r:?}");
    }
}

/// Decimals that round to an integer or underflow to 0 are not exact: they must be
/// enclosed (a float shortcut once treated them as exact).
#[test]
fn inexact_decimals_that_look_exact_are_enclosed() {
    let p = [Interval::try_from((0.0, 0.0)).unwrap(); 3];
    for text in ["1.00000000000000000001", "1e-400", "9007199254740993"] {
        let r = Formula::surface(text).unwrap().eval_interval(&p);
        assert!(r.inf() < r.sup(), "{text} was treated as exact: {r:?}");
    }
    for text in ["1", "0.5", "2.5e1", "0.0", "1e3", "0.375"] {
        let r = Formula::surface(text).unwrap().eval_interval(&p);
        assert_eq!(r.inf(), r.sup(), "{text} is exact: {r:?}");
    }
}

// ---------------------------------------------------------------------------------
// Callers moved from inari's arithmetic to `Iv`: the same results as before.

/// `ops::isolate_segment` as it was written in inari's arithmetic (before it moved to
/// `Iv`): the reference the `Iv` version must agree with, piece for piece.
fn isolate_segment_inari(
    f: &dyn Implicit,
    ea: &[Interval; 3],
    eb: &[Interval; 3],
    inside: Option<&[Interval; 3]>,
    budget: certmesh::implicit::ops::SegmentBudget,
) -> (Vec<(f64, f64, bool)>, Vec<[f64; 2]>, u32) {
    use certmesh::implicit::ops::excludes_zero;
    use certmesh::implicit::Regularity;
    let sign = |t: f64| -> Option<bool> {
        let tt = Interval::try_from((t, t)).ok()?;
        let x: [Interval; 3] = [0, 1, 2].map(|k| ea[k] + tt * (eb[k] - ea[k]));
        let v = f.eval_interval(&x);
        if v.is_empty() {
            None
        } else if v.inf() > 0.0 {
            Some(true)
        } else if v.sup() < 0.0 {
            Some(false)
        } else {
            None
        }
    };
    let dir: [Interval; 3] = [0, 1, 2].map(|k| eb[k] - ea[k]);
    let at = |t: Interval| -> [Interval; 3] { [0, 1, 2].map(|k| ea[k] + t * dir[k]) };
    let pt = |t: f64| Interval::try_from((t, t)).unwrap_or(Interval::ENTIRE);
    let hull =
        |x: f64, y: f64| Interval::try_from((x.min(y), x.max(y))).unwrap_or(Interval::ENTIRE);
    let (mut roots, mut undecided, mut pieces) = (Vec::new(), Vec::new(), 0u32);
    let mut stack = vec![(0.0f64, 1.0f64, sign(0.0), sign(1.0), 0u32)];
    while let Some((t0, t1, s0, s1, depth)) = stack.pop() {
        if pieces >= budget.max_pieces {
            undecided.push([t0, t1]);
            continue;
        }
        pieces += 1;
        let tt = hull(t0, t1);
        let x = at(tt);
        let mut within = true;
        if let Some(d) = inside {
            if (0..3).any(|k| x[k].sup() < d[k].inf() || x[k].inf() > d[k].sup()) {
                continue;
            }
            within = (0..3).all(|k| d[k].inf() <= x[k].inf() && x[k].sup() <= d[k].sup());
        }
        let reg = f.regularity(&x);
        let d = f.grad_interval(&x);
        let mut enc = d.v;
        let mut dg = Interval::ENTIRE;
        if reg == Regularity::Smooth {
            dg = d.g[0] * dir[0] + d.g[1] * dir[1] + d.g[2] * dir[2];
            let m = 0.5 * (t0 + t1);
            let mv = f.eval_interval(&at(pt(m))) + dg * (tt - pt(m));
            let both = enc.intersection(mv);
            if !both.is_empty() {
                enc = both;
            }
        }
        if !enc.is_empty() && excludes_zero(enc) {
            continue;
        }
        if within && reg == Regularity::Smooth && !dg.is_empty() && excludes_zero(dg) {
            if let (Some(a), Some(b)) = (s0, s1) {
                if a != b {
                    roots.push((t0, t1, b));
                }
                continue;
            }
        }
        if depth >= budget.max_depth {
            undecided.push([t0, t1]);
            continue;
        }
        let w = t1 - t0;
        let split = [0.5, 0.375, 0.625, 0.25, 0.75]
            .iter()
            .map(|&q| t0 + q * w)
            .filter(|&tm| tm > t0 && tm < t1)
            .find_map(|tm| sign(tm).map(|s| (tm, s)));
        match split {
            Some((tm, sm)) => {
                stack.push((tm, t1, Some(sm), s1, depth + 1));
                stack.push((t0, tm, s0, Some(sm), depth + 1));
            }
            None => undecided.push([t0, t1]),
        }
    }
    (roots, undecided, pieces)
}

fn arb_end_box() -> impl Strategy<Value = [Interval; 3]> {
    (
        proptest::array::uniform3(-1.6f64..1.6),
        proptest::array::uniform3(prop_oneof![Just(0.0), 0.0f64..1e-6, 0.0f64..0.05]),
    )
        .prop_map(|(c, r)| {
            std::array::from_fn(|k| Interval::try_from((c[k] - r[k], c[k] + r[k])).unwrap())
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Segment isolation in `Iv` finds the same roots, the same undecided pieces and
    /// the same piece count as in inari's arithmetic, on the catalog's genus-2 and
    /// torus, a formula with a pole and one with a kink, with point and boxed ends.
    #[test]
    fn isolate_segment_in_iv_equals_inari(
        which in 0usize..4,
        ea in arb_end_box(),
        eb in arb_end_box(),
        clip in any::<bool>(),
    ) {
        let text = [
            "z^2 + 0.5*(x^2/1.44 + y^2/0.64 - 1)*((x - 0.55)^2 + y^2 - 0.09)*((x + 0.55)^2 + y^2 - 0.09)",
            "(x^2 + y^2 + z^2 + 0.6^2 - 0.2^2)^2 - 4*0.6^2*(x^2 + y^2)",
            "1/(x - 0.2) + y + z",
            "abs(x) + y^2 - z^2 - 0.1",
        ][which];
        let f = Formula::surface(text).unwrap();
        let dom: [Interval; 3] = [Interval::try_from((-1.0, 1.0)).unwrap(); 3];
        let inside = clip.then_some(&dom);
        let budget = certmesh::implicit::ops::SegmentBudget { max_depth: 30, max_pieces: 600 };
        let got = certmesh::implicit::ops::isolate_segment(&f, &ea, &eb, inside, budget);
        let want = isolate_segment_inari(&f, &ea, &eb, inside, budget);
        let roots: Vec<(f64, f64, bool)> = got.roots.iter().map(|r| (r.t0, r.t1, r.rising)).collect();
        prop_assert_eq!(roots, want.0);
        prop_assert_eq!(got.undecided, want.1);
        prop_assert_eq!(got.pieces, want.2);
    }

    /// Interval circumcentres in `Iv` equal the inari computation they replaced.
    #[test]
    fn circumcentre_interval_in_iv_equals_inari(
        p in proptest::array::uniform4(proptest::array::uniform3(prop_oneof![
            8 => -2.0f64..2.0,
            1 => -1e-3f64..1e-3,
            1 => Just(0.5),
        ])),
    ) {
        let point = |x: [f64; 3]| x.map(|c| Interval::try_from((c, c)).unwrap());
        let q = p.map(point);
        let d: [[Interval; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|k| q[i + 1][k] - q[0][k]));
        let (l, [c12, c20, c01], det) =
            certmesh::kernel::delaunay::circumcentre_terms(d, |x: Interval| x.sqr());
        let want = if !(det.inf() > 0.0 || det.sup() < 0.0) {
            None
        } else {
            let two = Interval::try_from((2.0, 2.0)).unwrap();
            let c: [Interval; 3] = std::array::from_fn(|k| {
                q[0][k] + (l[0] * c12[k] + l[1] * c20[k] + l[2] * c01[k]) / (two * det)
            });
            c.iter().all(|x| x.inf().is_finite() && x.sup().is_finite()).then_some(c)
        };
        let got = certmesh::restricted_delaunay::restricted::circumcentre_interval(p);
        prop_assert_eq!(got, want);
    }
}
