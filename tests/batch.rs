//! Batch (SIMD) evaluation of tapes (src/implicit/batch.rs) equals scalar evaluation bit
//! for bit: f64 values against `Tape::eval_f64_in`, interval bounds against the scalar
//! kernel `Iv` (`Tape::eval_iv_in`) and against inari's generic interpreter, on random
//! formulas, random points and boxes of every scale (the fallback lanes included), and
//! batches of every length (the padded last chunk included). The `Implicit` batch
//! methods of `Formula` and `Counted` agree with their scalar methods likewise. The
//! batch gradient (`Implicit::grad_batch`, on `Dual<Lanes>`) equals `Implicit::grad`
//! bit for bit, and the batch Newton projection (`ops::project_batch`) equals
//! `ops::project` point by point. The sparse interval gradient of polynomial tapes
//! (`implicit::sparse`) equals dense forward mode on `Dual<Iv>`.
use certmesh::catalog;
use certmesh::implicit::batch::{BatchScratch, LANES};
use certmesh::implicit::{ops, Counted, Dual, Formula, FromGeneric, GenericFn, Implicit, Iv, Num};
use inari::Interval;
use proptest::prelude::*;

mod common;
use common::arb_f64;
use std::mem::MaybeUninit;

/// Random formula text over x, y, z: every operation of the tape but the
/// transcendental ones (they need the `mpfr` feature), with exact and inexact
/// constants (0.1 has a non-point enclosure) and negative ones.
fn arb_formula() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        Just("x".to_string()),
        Just("y".to_string()),
        Just("z".to_string()),
        Just("0.1".to_string()),
        Just("1.44".to_string()),
        Just("2".to_string()),
        Just("(-3)".to_string()),
        Just("0".to_string()),
        Just("1e200".to_string()),
    ];
    leaf.prop_recursive(5, 48, 2, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} + {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} - {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} * {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} / {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("min({a}, {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("max({a}, {b})")),
            inner.clone().prop_map(|a| format!("({a} * 0.3)")),
            inner.clone().prop_map(|a| format!("({a} / 1.44)")),
            inner.clone().prop_map(|a| format!("({a} / (-0.7))")),
            inner.clone().prop_map(|a| format!("(0.1 - {a})")),
            inner.clone().prop_map(|a| format!("({a} + 0.1)")),
            inner.clone().prop_map(|a| format!("({a} * 0.1)")),
            inner.clone().prop_map(|a| format!("({a} * (-0.1))")),
            inner.clone().prop_map(|a| format!("(-{a})")),
            inner.clone().prop_map(|a| format!("({a})^2")),
            inner.clone().prop_map(|a| format!("({a})^3")),
            inner.clone().prop_map(|a| format!("({a})^(-2)")),
            inner.clone().prop_map(|a| format!("sqrt({a})")),
            inner.clone().prop_map(|a| format!("abs({a})")),
        ]
    })
}

/// Coordinates of every scale (those of the `Iv` tests), signed zeros, infinities and
/// NaN: the fallback lanes.
fn arb_coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        12 => -2.0f64..2.0,
        6 => arb_f64(),
        1 => Just(f64::NAN),
    ]
}

fn arb_point() -> impl Strategy<Value = [f64; 3]> {
    [arb_coord(), arb_coord(), arb_coord()]
}

/// Boxes: ordinary ones, degenerate ones, unbounded ones, and the empty interval.
fn arb_box() -> impl Strategy<Value = [Iv; 3]> {
    let iv = prop_oneof![
        12 => (-2.0f64..2.0, 0.0f64..1.0).prop_map(|(a, w)| Iv::new(a, a + w)),
        3 => (arb_coord(), arb_coord()).prop_filter_map("nan", |(a, b)| {
            let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
            Interval::try_from((lo, hi)).ok().map(Iv::from_interval)
        }),
        1 => Just(Iv::from_interval(Interval::EMPTY)),
    ];
    [iv.clone(), iv.clone(), iv]
}

/// Random polynomial formula text (the operations of the sparse gradient program,
/// `implicit::sparse`): sums, differences, products, squares, cubes, constants exact
/// and inexact, division by a constant.
fn arb_poly_formula() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        Just("x".to_string()),
        Just("y".to_string()),
        Just("z".to_string()),
        Just("0.1".to_string()),
        Just("1.44".to_string()),
        Just("(-3)".to_string()),
        Just("0".to_string()),
        Just("1e200".to_string()),
    ];
    leaf.prop_recursive(6, 64, 2, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} + {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} - {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} * {b})")),
            inner.clone().prop_map(|a| format!("({a} * 0.3)")),
            inner.clone().prop_map(|a| format!("({a} / 1.44)")),
            inner.clone().prop_map(|a| format!("({a} / (-0.7))")),
            inner.clone().prop_map(|a| format!("(0.1 - {a})")),
            inner.clone().prop_map(|a| format!("({a} - 0.55)")),
            inner.clone().prop_map(|a| format!("({a} + 0.1)")),
            inner.clone().prop_map(|a| format!("(-{a})")),
            inner.clone().prop_map(|a| format!("({a})^2")),
            inner.clone().prop_map(|a| format!("({a})^3")),
            inner.clone().prop_map(|a| format!("({a})^4")),
        ]
    })
}

/// `Implicit::grad_interval` (the sparse program on polynomial tapes) against dense
/// forward mode on `Dual<Iv>`: the same enclosures, bound for bound (signed zeros
/// compare equal, empty is empty in both).
fn check_interval_gradients(f: &Formula, boxes: &[[Iv; 3]]) -> Result<(), TestCaseError> {
    for b in boxes {
        let ib = b.map(Iv::to_interval);
        let got = f.grad_interval(&ib);
        let want = f.grad_interval_dense(&ib);
        let same = |x: Interval, y: Iv| {
            let y = y.to_interval();
            x == y || (x.is_empty() && y.is_empty())
        };
        prop_assert!(
            same(got.v, want.v) && (0..3).all(|k| same(got.g[k], want.g[k])),
            "{}: over {:?} sparse {:?} dense {:?}",
            f.text(),
            b,
            got,
            want
        );
    }
    Ok(())
}

fn scalar_f64(f: &Formula, p: [f64; 3]) -> f64 {
    let mut regs = vec![MaybeUninit::uninit(); f.tape().len()];
    f.tape().eval_f64_in(p, &mut regs)
}

fn scalar_iv(f: &Formula, b: [Iv; 3]) -> Iv {
    let mut regs = vec![MaybeUninit::uninit(); f.tape().len()];
    f.tape().eval_iv_in(b, &mut regs)
}

/// Same bits (NaN: any NaN).
fn same_f64(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// Two projections' results the same, bit for bit (both failed, or the same point).
fn same_point(a: Option<[f64; 3]>, b: Option<[f64; 3]>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => (0..3).all(|k| same_f64(a[k], b[k])),
        _ => false,
    }
}

fn check_points(f: &Formula, pts: &[[f64; 3]]) -> Result<(), TestCaseError> {
    let xs: [Vec<f64>; 3] = [0, 1, 2].map(|a| pts.iter().map(|p| p[a]).collect());
    let mut out = vec![0.0; pts.len()];
    let mut s = BatchScratch::default();
    f.tape()
        .eval_f64_batch(&xs[0], &xs[1], &xs[2], &mut out, &mut s);
    let mut via_trait = vec![0.0; pts.len()];
    f.eval_batch([&xs[0], &xs[1], &xs[2]], &mut via_trait);
    for (i, p) in pts.iter().enumerate() {
        let want = scalar_f64(f, *p);
        prop_assert!(
            same_f64(out[i], want),
            "{}: at {:?} batch {} scalar {}",
            f.text(),
            p,
            out[i],
            want
        );
        prop_assert!(same_f64(via_trait[i], want));
        prop_assert!(same_f64(f.eval(*p), want));
    }
    Ok(())
}

fn check_boxes(f: &Formula, boxes: &[[Iv; 3]]) -> Result<(), TestCaseError> {
    let lo: [Vec<f64>; 3] = [0, 1, 2].map(|a| boxes.iter().map(|b| b[a].lo).collect());
    let hi: [Vec<f64>; 3] = [0, 1, 2].map(|a| boxes.iter().map(|b| b[a].hi).collect());
    let (mut ol, mut oh) = (vec![0.0; boxes.len()], vec![0.0; boxes.len()]);
    let mut s = BatchScratch::default();
    f.tape().eval_iv_batch(
        [&lo[0], &lo[1], &lo[2]],
        [&hi[0], &hi[1], &hi[2]],
        &mut ol,
        &mut oh,
        &mut s,
    );
    let ib: Vec<[Interval; 3]> = boxes.iter().map(|b| b.map(Iv::to_interval)).collect();
    let mut via_trait = vec![Interval::EMPTY; boxes.len()];
    f.eval_interval_batch(&ib, &mut via_trait);
    let mut regs = Vec::new();
    for (i, b) in boxes.iter().enumerate() {
        let want = scalar_iv(f, *b);
        prop_assert!(
            same_f64(ol[i], want.lo) && same_f64(oh[i], want.hi),
            "{}: over {:?} batch [{}, {}] scalar [{}, {}]",
            f.text(),
            b,
            ol[i],
            oh[i],
            want.lo,
            want.hi
        );
        // inari's generic interpreter: the reference bounds (signed zeros compare
        // equal; an empty result is empty in both).
        let inari: Interval = f.tape().eval(&b.map(Iv::to_interval), &mut regs);
        let got = Iv::new(ol[i], oh[i]).to_interval();
        prop_assert!(
            got == inari || (got.is_empty() && inari.is_empty()),
            "{}: over {:?} batch {:?} inari {:?}",
            f.text(),
            b,
            got,
            inari
        );
        let t = via_trait[i];
        prop_assert!(t == f.eval_interval(&ib[i]) || (t.is_empty() && got.is_empty()));
    }
    Ok(())
}

/// `grad_batch` against `grad` (value and gradient, every bit), and `project_batch`
/// against `project`.
fn check_gradients(f: &dyn Implicit, pts: &[[f64; 3]]) -> Result<(), TestCaseError> {
    let mut out = vec![
        Dual {
            v: 0.0,
            g: [0.0; 3]
        };
        pts.len()
    ];
    f.grad_batch(pts, &mut out);
    for (p, d) in pts.iter().zip(&out) {
        let want = f.grad(*p);
        prop_assert!(
            same_f64(d.v, want.v) && (0..3).all(|k| same_f64(d.g[k], want.g[k])),
            "{}: at {:?} batch {:?} scalar {:?}",
            f.describe(),
            p,
            d,
            want
        );
    }
    for steps in [0, 1, 3] {
        let batch = ops::project_steps_batch(f, pts, steps);
        for (p, (q, ok)) in pts.iter().zip(&batch) {
            let (want, want_ok) = ops::project_steps(f, *p, steps);
            prop_assert!(
                *ok == want_ok && (0..3).all(|k| same_f64(q[k], want[k])),
                "{}: {} steps from {:?}: batch {:?} scalar {:?}",
                f.describe(),
                steps,
                p,
                (q, ok),
                (want, want_ok)
            );
        }
    }
    // Crossings: segments between consecutive points (any signs: the batch must agree
    // with `crossing_t` also where the ends do not change sign), both modes.
    let segs: Vec<ops::SignChange> = pts
        .windows(2)
        .map(|w| ops::SignChange {
            a: w[0],
            fa: f.eval(w[0]),
            b: w[1],
            fb: f.eval(w[1]),
        })
        .collect();
    for (how, tol) in [
        (ops::Crossing::Bisection, 0.0),
        (ops::Crossing::Bisection, 1e-6),
        (ops::Crossing::Linear, 0.0),
    ] {
        let ts = ops::crossing_t_batch(f, &segs, how, tol);
        for (s, t) in segs.iter().zip(&ts) {
            let want = ops::crossing_t(f, s.a, s.fa, s.b, s.fb, how, tol);
            prop_assert!(
                same_f64(*t, want),
                "{}: {:?} {:?}: batch {} scalar {}",
                f.describe(),
                how,
                s,
                t,
                want
            );
        }
    }
    // Kept where f is exactly 0 (decided by the first round's value), projected
    // elsewhere: the same as evaluating f first.
    let or_on = ops::project_batch_or_on(f, pts, 8, 1e-10);
    for (p, q) in pts.iter().zip(&or_on) {
        let want = if f.eval(*p) == 0.0 {
            Some(*p)
        } else {
            ops::project(f, *p, 8, 1e-10)
        };
        let same = same_point(*q, want);
        prop_assert!(
            same,
            "{}: projection or on S of {:?}: {:?} against {:?}",
            f.describe(),
            p,
            q,
            want
        );
    }
    // Given the first round's values and gradients (the scalar ones), the same
    // points again.
    let grads: Vec<_> = pts.iter().map(|&p| f.grad(p)).collect();
    let given = ops::project_batch_or_on_given(f, pts, &grads, 8, 1e-10);
    for ((p, q), r) in pts.iter().zip(&given).zip(&or_on) {
        let same = same_point(*q, *r);
        prop_assert!(
            same,
            "{}: projection or on S of {:?}, first gradient given: {:?} against {:?}",
            f.describe(),
            p,
            q,
            r
        );
    }
    let proj = ops::project_batch(f, pts, 8, 1e-10);
    for (p, q) in pts.iter().zip(&proj) {
        let want = ops::project(f, *p, 8, 1e-10);
        let same = same_point(*q, want);
        prop_assert!(
            same,
            "{}: projection of {:?}: batch {:?} scalar {:?}",
            f.describe(),
            p,
            q,
            want
        );
    }
    Ok(())
}

/// Generic Rust code (`FromGeneric`) has the lane gradient too.
struct Blob;
impl GenericFn for Blob {
    fn eval<T: Num>(&self, [x, y, z]: [T; 3]) -> T {
        (x.clone() * y.clone()).sin() + z.clone().exp() - (x.square() + T::lit(0.5)).sqrt()
            + y.abs().min(&z)
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn batch_gradient_and_projection_equal_scalar(
        text in arb_formula(),
        pts in prop::collection::vec(arb_point(), 1..(3 * LANES + 2)),
    ) {
        let f = Formula::surface(&text).unwrap();
        check_gradients(&f, &pts)?;
    }

    #[test]
    fn batch_gradient_on_catalog_and_generic_code(
        pick in 0usize..64,
        pts in prop::collection::vec(arb_point(), 1..(2 * LANES + 3)),
        near in prop::collection::vec(prop::array::uniform3(-2.0f64..2.0), 1..(2 * LANES + 3)),
    ) {
        let entries = catalog::surfaces();
        let e = &entries[pick % entries.len()];
        let f = e.function();
        check_gradients(&f, &pts)?;
        // Points near the surface: most projections converge.
        check_gradients(&f, &near)?;
        check_gradients(&FromGeneric(Blob), &near)?;
        let c = Counted::new(&f);
        check_gradients(&c, &near)?;
    }

    #[test]
    fn batch_f64_equals_scalar(
        text in arb_formula(),
        pts in prop::collection::vec(arb_point(), 1..(3 * LANES + 2)),
    ) {
        let f = Formula::surface(&text).unwrap();
        check_points(&f, &pts)?;
    }

    #[test]
    fn batch_intervals_equal_scalar_and_inari(
        text in arb_formula(),
        boxes in prop::collection::vec(arb_box(), 1..(3 * LANES + 2)),
    ) {
        let f = Formula::surface(&text).unwrap();
        check_boxes(&f, &boxes)?;
    }

    #[test]
    fn sparse_interval_gradient_equals_dense(
        text in arb_poly_formula(),
        boxes in prop::collection::vec(arb_box(), 1..12),
    ) {
        let f = Formula::surface(&text).unwrap();
        // Only a division of two constant subexpressions (not fused into `DivC`) takes
        // the dense path among these operations.
        let div = f.tape().ops().iter().any(|o| matches!(o, certmesh::implicit::tape::Op::Div(..)));
        prop_assert!(f.sparse_gradient().is_some() || div, "{} has no sparse program", text);
        check_interval_gradients(&f, &boxes)?;
    }

    /// Every formula: the sparse path where the tape is polynomial, the dense one
    /// otherwise; the catalog's surfaces likewise.
    #[test]
    fn interval_gradient_on_any_formula_equals_dense(
        text in arb_formula(),
        pick in 0usize..64,
        boxes in prop::collection::vec(arb_box(), 1..12),
    ) {
        let f = Formula::surface(&text).unwrap();
        check_interval_gradients(&f, &boxes)?;
        let entries = catalog::surfaces();
        let e = &entries[pick % entries.len()];
        check_interval_gradients(&Formula::surface(e.formula).unwrap(), &boxes)?;
    }

    /// The catalog's surfaces (the benchmarks' workloads among them).
    #[test]
    fn batch_on_catalog_surfaces(
        pick in 0usize..64,
        pts in prop::collection::vec(arb_point(), 1..(2 * LANES + 3)),
        boxes in prop::collection::vec(arb_box(), 1..(2 * LANES + 3)),
    ) {
        let entries = catalog::surfaces();
        let e = &entries[pick % entries.len()];
        let f = Formula::surface(e.formula).unwrap();
        check_points(&f, &pts)?;
        check_boxes(&f, &boxes)?;
    }
}

/// The smooth polynomial surfaces of the catalog (the `certify` bench's genus2 among
/// them) get the sparse interval gradient program.
#[test]
fn polynomial_catalog_surfaces_have_a_sparse_gradient() {
    for name in [
        "sphere",
        "torus",
        "genus2",
        "genus5",
        "tanglecube",
        "two-spheres",
    ] {
        let f = catalog::get(name).unwrap().function();
        let s = f
            .sparse_gradient()
            .unwrap_or_else(|| panic!("{name}: no sparse program"));
        // Fewer interval operations than dense forward mode (4 per instruction).
        assert!(s.len() < 4 * f.tape().len(), "{name}: {} ops", s.len());
    }
}

/// The counting wrapper counts one evaluation per point or box of a batch and returns
/// the inner oracle's values.
#[test]
fn counted_batches_count_each_point() {
    let f = catalog::get("genus2").unwrap().function();
    let c = Counted::new(&f);
    let xs: Vec<f64> = (0..21).map(|i| i as f64 * 0.1 - 1.0).collect();
    let mut out = vec![0.0; xs.len()];
    c.eval_batch([&xs, &xs, &xs], &mut out);
    for (i, &x) in xs.iter().enumerate() {
        assert_eq!(out[i].to_bits(), f.eval([x, x, x]).to_bits());
    }
    let boxes: Vec<[Interval; 3]> = xs
        .iter()
        .map(|&x| [Interval::try_from((x, x + 0.05)).unwrap(); 3])
        .collect();
    let mut iv = vec![Interval::EMPTY; boxes.len()];
    c.eval_interval_batch(&boxes, &mut iv);
    for (b, v) in boxes.iter().zip(&iv) {
        assert_eq!(*v, f.eval_interval(b));
    }
    let pts: Vec<[f64; 3]> = xs.iter().map(|&x| [x, x, x]).collect();
    let mut d = vec![
        Dual {
            v: 0.0,
            g: [0.0; 3]
        };
        pts.len()
    ];
    c.grad_batch(&pts, &mut d);
    let n = c.counts();
    assert_eq!((n.points, n.intervals, n.gradients), (21, 21, 21));
}

/// A batch of slices of different lengths is refused with a clear panic message.
#[test]
#[should_panic(expected = "different lengths")]
fn mismatched_batch_lengths_panic() {
    let f = Formula::surface("x + y").unwrap();
    let mut out = vec![0.0; 3];
    f.tape().eval_f64_batch(
        &[1.0, 2.0, 3.0],
        &[1.0, 2.0],
        &[0.0; 3],
        &mut out,
        &mut BatchScratch::default(),
    );
}
