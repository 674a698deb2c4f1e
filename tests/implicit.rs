//! The evaluator: parse errors, parse/print round trip, and the enclosure properties of
//! every evaluation mode (thousands of random expressions and boxes).
use certmesh::implicit::number::{ipow, point};
use certmesh::implicit::{parse, Dual, Formula, FromGeneric, GenericFn, Hyper, Implicit, Num};
use certmesh::Error;
use inari::Interval;
use proptest::prelude::*;

fn parse_err(text: &str) -> (String, usize) {
    match Formula::surface(text) {
        Err(Error::Parse { message, column }) => (message, column),
        other => panic!("expected a parse error for {text:?}, got {other:?}"),
    }
}

#[test]
fn parse_errors_name_the_column() {
    let (m, c) = parse_err("x^2 + * y");
    assert_eq!((m.as_str(), c), ("unexpected '*'", 7));
    assert_eq!(
        Formula::surface("x^2 + * y").unwrap_err().to_string(),
        "formula error: unexpected '*' at column 7"
    );
    assert_eq!(parse_err("x + (y").1, 7);
    assert_eq!(parse_err("x^1.5").1, 4);
    assert_eq!(parse_err("2x").1, 2);
    assert_eq!(parse_err("foo(x)").1, 1);
    assert_eq!(parse_err("").1, 1);
    assert_eq!(parse_err("x + ").1, 5);
    assert_eq!(parse_err("min(x)").1, 6);
    assert!(matches!(
        Formula::curve("x + z"),
        Err(Error::Parse { column: 5, .. })
    ));
}

#[cfg(not(feature = "mpfr"))]
#[test]
fn transcendental_functions_name_the_feature() {
    let e = Formula::surface("x + sin(y)").unwrap_err();
    assert!(matches!(e, Error::NeedsFeature { column: 5, .. }));
    assert!(e.to_string().contains("--features mpfr"), "{e}");
}

#[cfg(feature = "mpfr")]
#[test]
fn transcendental_functions_enclose() {
    let f = Formula::surface("sin(x) + cos(y) * exp(z) - ln(x + 2)").unwrap();
    let b = [
        Interval::try_from((0.1, 0.3)).unwrap(),
        point(1.0),
        Interval::try_from((-1.0, 0.5)).unwrap(),
    ];
    let r = f.eval_interval(&b);
    for i in 0..=20 {
        let x = 0.1 + 0.01 * i as f64;
        let z = -1.0 + 0.075 * i as f64;
        assert!(r.contains(f.eval([x, 1.0, z])));
    }
}

#[test]
fn tight_even_powers() {
    let x = Interval::try_from((-1.0, 2.0)).unwrap();
    assert_eq!(ipow(x, 2), Interval::try_from((0.0, 4.0)).unwrap());
    assert_eq!(ipow(x, 3), Interval::try_from((-1.0, 8.0)).unwrap());
    let f = Formula::surface("x^2").unwrap();
    let r = f.eval_interval(&[x, point(0.0), point(0.0)]);
    assert_eq!((r.inf(), r.sup()), (0.0, 4.0));
}

#[test]
fn decimal_constants_are_enclosed() {
    // 0.1 is not a float: the enclosure must strictly contain the nearest float's neighbourhood.
    let f = Formula::surface("0.1").unwrap();
    let r = f.eval_interval(&[point(0.0); 3]);
    assert!(r.inf() < 0.1 && r.sup() > 0.1);
    // 0.5 and 3 are exact.
    let g = Formula::surface("0.5 + 3").unwrap();
    let r = g.eval_interval(&[point(0.0); 3]);
    assert_eq!((r.inf(), r.sup()), (3.5, 3.5));
}

#[test]
fn generic_rust_functions_work_in_every_mode() {
    struct Torus;
    impl GenericFn for Torus {
        fn eval<T: Num>(&self, [x, y, z]: [T; 3]) -> T {
            let r2 = x.powi(2) + y.powi(2);
            (r2.clone() + z.powi(2) + T::lit(0.36 - 0.0625)).powi(2) - T::lit(4.0 * 0.36) * r2
        }
    }
    let f = FromGeneric(Torus);
    let g = certmesh::catalog::get("torus").unwrap().function();
    for p in [[0.3, 0.5, 0.1], [-0.7, 0.2, -0.2]] {
        assert!((f.eval(p) - g.eval(p)).abs() < 1e-12);
        let (a, b) = (f.hessian(p), g.hessian(p));
        for k in 0..6 {
            assert!((a.h[k] - b.h[k]).abs() < 1e-9);
        }
    }
}

/// Random formulas in the full language (without transcendental functions).
fn arb_formula() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        3 => prop_oneof![Just("x".to_string()), Just("y".to_string()), Just("z".to_string())],
        1 => (-40i32..40).prop_map(|k| format!("{}", k as f64 / 8.0)),
        1 => (1u32..30).prop_map(|k| format!("0.{k}")),
        1 => Just("pi".to_string()),
    ];
    leaf.prop_recursive(5, 40, 3, |inner| {
        prop_oneof![
            (
                inner.clone(),
                inner.clone(),
                prop_oneof![Just("+"), Just("-"), Just("*"), Just("/")]
            )
                .prop_map(|(a, b, op)| format!("({a}) {op} ({b})")),
            inner.clone().prop_map(|a| format!("-({a})")),
            (inner.clone(), 0i32..6).prop_map(|(a, n)| format!("({a})^{n}")),
            (inner.clone(), -3i32..0).prop_map(|(a, n)| format!("({a})^({n})")),
            inner.clone().prop_map(|a| format!("sqrt({a})")),
            inner.clone().prop_map(|a| format!("abs({a})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("min({a}, {b})")),
            (inner.clone(), inner).prop_map(|(a, b)| format!("max({a}, {b})")),
        ]
    })
}

fn arb_box() -> impl Strategy<Value = ([f64; 3], [f64; 3], [f64; 3])> {
    // lower corner, widths, and the relative position of a point inside
    (
        prop::array::uniform3(-2.0f64..2.0),
        prop::array::uniform3(0.0f64..1.5),
        prop::array::uniform3(0.0f64..=1.0),
    )
}

fn ibox(lo: [f64; 3], w: [f64; 3]) -> [Interval; 3] {
    [0, 1, 2].map(|k| Interval::try_from((lo[k], lo[k] + w[k])).unwrap())
}

fn inside(lo: [f64; 3], w: [f64; 3], t: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|k| (lo[k] + t[k] * w[k]).min(lo[k] + w[k]))
}

/// `small ⊆ big`, where an empty `small` (undefined at the point) is vacuous.
fn encloses(big: Interval, small: Interval) -> bool {
    small.is_empty() || small.subset(big)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    #[test]
    fn print_parse_round_trip(text in arb_formula()) {
        let e = parse(&text, 3).unwrap();
        let printed = e.to_string();
        let again = parse(&printed, 3).unwrap();
        prop_assert_eq!(&e, &again, "printed as {}", printed);
    }

    /// Inclusion: the enclosure over the box contains the enclosure at any point of it
    /// (which contains the exact value), and the f64 value lies in the point enclosure
    /// up to its own rounding.
    #[test]
    fn interval_encloses_point_values(text in arb_formula(), (lo, w, t) in arb_box()) {
        let f = Formula::surface(&text).unwrap();
        let b = ibox(lo, w);
        let p = inside(lo, w, t);
        let big = f.eval_interval(&b);
        let small = f.eval_interval(&p.map(point));
        prop_assert!(encloses(big, small), "{} over {:?}: {:?} does not contain {:?}", text, b, big, small);
        let v = f.eval(p);
        if v.is_finite() && !small.is_empty() && small.wid() < 1e-6 * (1.0 + v.abs()) {
            prop_assert!((v - small.mid()).abs() <= 1e-6 * (1.0 + v.abs()));
        }
    }

    #[test]
    fn interval_gradient_and_hessian_enclose(text in arb_formula(), (lo, w, t) in arb_box()) {
        let f = Formula::surface(&text).unwrap();
        let b = ibox(lo, w);
        let p = inside(lo, w, t);
        let gb: Dual<Interval> = f.grad_interval(&b);
        let gp: Dual<Interval> = f.grad_interval(&p.map(point));
        prop_assert!(encloses(gb.v, gp.v));
        for k in 0..3 {
            prop_assert!(encloses(gb.g[k], gp.g[k]), "d/d{}: {:?} vs {:?}", k, gb.g[k], gp.g[k]);
        }
        let hb: Hyper<Interval> = f.hessian_interval(&b);
        let hp: Hyper<Interval> = f.hessian_interval(&p.map(point));
        for k in 0..6 {
            prop_assert!(encloses(hb.h[k], hp.h[k]), "h[{}]: {:?} vs {:?}", k, hb.h[k], hp.h[k]);
        }
        // Point derivatives in f64 lie in the interval derivatives at the point.
        let h = f.hessian(p);
        for k in 0..3 {
            if h.g[k].is_finite() && !gp.g[k].is_empty() && gp.g[k].wid() < 1e-6 {
                prop_assert!((h.g[k] - gp.g[k].mid()).abs() <= 1e-6 * (1.0 + h.g[k].abs()));
            }
        }
    }

    /// The fast interval kernel (`Iv`, used by `eval_interval`, `grad_interval` and
    /// `hessian_interval`) gives exactly inari's bounds: the generic interpreter run on
    /// inari intervals is an independent second computation of the same enclosure.
    #[test]
    fn fast_interval_kernel_equals_inari(text in arb_formula(), (lo, w, _t) in arb_box()) {
        let f = Formula::surface(&text).unwrap();
        let b = ibox(lo, w);
        let same = |a: Interval, c: Interval| a == c || (a.is_empty() && c.is_empty());
        let fast = f.eval_interval(&b);
        let slow: Interval = f.tape().eval(&b, &mut Vec::new());
        prop_assert!(same(fast, slow), "{} over {:?}: {:?} vs inari {:?}", text, b, fast, slow);
        let gf = f.grad_interval(&b);
        let vars = [0, 1, 2].map(|k| Dual::var(b[k], k));
        let gs: Dual<Interval> = f.tape().eval(&vars, &mut Vec::new());
        for k in 0..3 {
            prop_assert!(same(gf.g[k], gs.g[k]), "d/d{} of {}: {:?} vs inari {:?}", k, text, gf.g[k], gs.g[k]);
        }
        let hf = f.hessian_interval(&b);
        let vars = [0, 1, 2].map(|k| Hyper::var(b[k], k));
        let hs: Hyper<Interval> = f.tape().eval(&vars, &mut Vec::new());
        for k in 0..6 {
            prop_assert!(same(hf.h[k], hs.h[k]), "h[{}] of {}: {:?} vs inari {:?}", k, text, hf.h[k], hs.h[k]);
        }
    }

    /// Point gradients agree with central differences (away from kinks and poles).
    #[test]
    fn gradient_matches_finite_differences(text in arb_formula(), (lo, w, t) in arb_box()) {
        let f = Formula::surface(&text).unwrap();
        let p = inside(lo, w, t);
        let d = f.grad(p);
        let hs = 1e-5;
        // Only test where f is smooth near p: the interval gradient over a small box is
        // bounded and abs/min/max/sqrt are not at a kink.
        let nb = p.map(|c| Interval::try_from((c - 4.0 * hs, c + 4.0 * hs)).unwrap());
        let gi = f.hessian_interval(&nb);
        let smooth = gi.v.is_common_interval() && gi.h.iter().all(|h| h.is_common_interval() && h.mag() < 1e4)
            && gi.g.iter().all(|g| g.is_common_interval());
        prop_assume!(smooth && d.v.is_finite() && d.g.iter().all(|g| g.is_finite()));
        for k in 0..3 {
            let mut a = p; a[k] += hs;
            let mut b = p; b[k] -= hs;
            let fd = (f.eval(a) - f.eval(b)) / (2.0 * hs);
            let tol = 1e-4 * (1.0 + d.g[k].abs()) + 1e-6 * (1.0 + d.v.abs()) / hs * 1e-4;
            prop_assert!((fd - d.g[k]).abs() <= tol, "d/d{} of {} at {:?}: ad {} fd {}", k, text, p, d.g[k], fd);
        }
    }
}
