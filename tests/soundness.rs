//! No false certificate on any input.
//!
//! 1. The regularity flags of the fast kernel against an independent computation:
//!    inari's IEEE 1788 decorations for continuity, and decorated forward-mode
//!    derivatives (|x|' = sign x, min/max through |a − b|) for smoothness.
//! 2. The inputs that used to be certified falsely (poles, double zeros, f ≡ 0) are
//!    not certified, in 2D and 3D, by Plantinga–Vegter and Snyder.
//! 3. Random formulas with division, sqrt, abs, min/max and squares on random boxes:
//!    every output claimed certified is checked by dense sampling that does not use
//!    the mesher (f and ∇f defined and finite near the curve, the zero set's sign
//!    changes near the mesh and the mesh near them, equal component counts).
use certmesh::implicit::expr::{BinOp, Expr, UnOp};
use certmesh::implicit::{Formula, Implicit, Regularity};
use certmesh::kernel::geom::Aabb;
use certmesh::mesh::Curve2;
use certmesh::mesher::{Mesh, MeshOutput, NoProgress};
use certmesh::subdivision::plantinga_vegter::{run_pv, PvParams};
use certmesh::subdivision::snyder::{run_snyder, SnyderParams};
use inari::{DecInterval, Decoration, Interval};
use proptest::prelude::*;

// ---------------------------------------------------------------------------------
// 1. Flags against decorations.

/// Value and gradient as decorated intervals (forward mode, no Hessian).
#[derive(Clone, Copy)]
struct DD {
    v: DecInterval,
    g: [DecInterval; 3],
}

fn dconst(lo: f64, hi: f64) -> DecInterval {
    DecInterval::new(Interval::try_from((lo, hi)).unwrap())
}

fn zero() -> DecInterval {
    dconst(0.0, 0.0)
}

fn dpow(x: DecInterval, n: u32) -> DecInterval {
    // Powers are continuous everywhere: the decoration is the argument's. The bounds are
    // the tight ones (repeated products would be wider than the evaluator's and make
    // min/max look tied where they are not); `ipow` is checked against inari elsewhere.
    match x.interval() {
        Some(i) if !i.is_empty() => DecInterval::set_dec(
            certmesh::implicit::number::ipow(i, n),
            match x.decoration() {
                Decoration::Com => Decoration::Com,
                d => d,
            },
        ),
        _ => x,
    }
}

/// The derivative of |x|: ±1 where x has a sign, and a value decorated `def`
/// (defined, not continuous) where x may be 0.
fn step(x: DecInterval) -> DecInterval {
    let i = x.interval().unwrap_or(Interval::EMPTY);
    if i.is_empty() {
        DecInterval::EMPTY
    } else if i.inf() > 0.0 {
        dconst(1.0, 1.0)
    } else if i.sup() < 0.0 {
        dconst(-1.0, -1.0)
    } else {
        DecInterval::set_dec(Interval::try_from((-1.0, 1.0)).unwrap(), Decoration::Def)
    }
}

fn eval_dd(e: &Expr, b: &[DecInterval; 3]) -> DD {
    let lift = |v: DecInterval| DD { v, g: [zero(); 3] };
    match e {
        Expr::Var(k) => {
            let mut g = [zero(); 3];
            g[*k] = dconst(1.0, 1.0);
            DD { v: b[*k], g }
        }
        Expr::Const(c, _) => lift(dconst(c.lo, c.hi)),
        Expr::Un(op, a) => {
            let a = eval_dd(a, b);
            let chain = |v: DecInterval, d: DecInterval| DD {
                v,
                g: a.g.map(|g| d * g),
            };
            match op {
                UnOp::Neg => DD {
                    v: -a.v,
                    g: a.g.map(|g| -g),
                },
                UnOp::Sqrt => {
                    let s = a.v.sqrt();
                    chain(s, dconst(1.0, 1.0) / (dconst(2.0, 2.0) * s))
                }
                UnOp::Abs => chain(a.v.abs(), step(a.v)),
                _ => panic!("transcendental functions are not generated"),
            }
        }
        Expr::Bin(op, l, r) => {
            let (x, y) = (eval_dd(l, b), eval_dd(r, b));
            match op {
                BinOp::Add => DD {
                    v: x.v + y.v,
                    g: [0, 1, 2].map(|k| x.g[k] + y.g[k]),
                },
                BinOp::Sub => DD {
                    v: x.v - y.v,
                    g: [0, 1, 2].map(|k| x.g[k] - y.g[k]),
                },
                // x·x is x² (≥ 0), as the compiled tape evaluates it; a plain product of
                // the two enclosures would straddle 0 and call sqrt(x·x) undefined.
                BinOp::Mul if l == r => DD {
                    v: x.v.sqr(),
                    g: [0, 1, 2].map(|k| dconst(2.0, 2.0) * x.v * x.g[k]),
                },
                BinOp::Mul => DD {
                    v: x.v * y.v,
                    g: [0, 1, 2].map(|k| x.g[k] * y.v + x.v * y.g[k]),
                },
                BinOp::Div => DD {
                    v: x.v / y.v,
                    g: [0, 1, 2].map(|k| (x.g[k] * y.v - x.v * y.g[k]) / y.v.sqr()),
                },
                BinOp::Min | BinOp::Max => {
                    // min(a, b) = (a + b − |a − b|)/2, max with +: the derivative goes
                    // through sign(a − b), discontinuous where a and b may be equal.
                    let s = if *op == BinOp::Min { -1.0 } else { 1.0 };
                    let half = dconst(0.5, 0.5);
                    let sg = dconst(s, s);
                    let d = x.v - y.v;
                    let v = if *op == BinOp::Min {
                        x.v.min(y.v)
                    } else {
                        x.v.max(y.v)
                    };
                    DD {
                        v,
                        g: [0, 1, 2]
                            .map(|k| half * (x.g[k] + y.g[k] + sg * step(d) * (x.g[k] - y.g[k]))),
                    }
                }
            }
        }
        Expr::Pow(a, n) => {
            let a = eval_dd(a, b);
            let m = n.unsigned_abs();
            let p = dpow(a.v, m);
            let dp = dconst(m as f64, m as f64) * dpow(a.v, m.saturating_sub(1));
            if *n >= 0 {
                DD {
                    v: p,
                    g: a.g.map(|g| dp * g),
                }
            } else {
                // x^-m = 1/x^m, derivative −m x^(m−1) / x^(2m).
                let one = dconst(1.0, 1.0);
                DD {
                    v: one / p,
                    g: a.g.map(|g| -(dp * g) / p.sqr()),
                }
            }
        }
    }
}

fn at_least_dac(d: DecInterval) -> bool {
    matches!(d.decoration(), Decoration::Com | Decoration::Dac)
}

/// Random formulas with every operation whose regularity is in question.
fn arb_formula() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        3 => prop_oneof![Just("x".to_string()), Just("y".to_string()), Just("z".to_string())],
        1 => (-12i32..12).prop_map(|k| format!("{}", k as f64 / 4.0)),
        1 => Just("0".to_string()),
    ];
    leaf.prop_recursive(4, 24, 3, |inner| {
        prop_oneof![
            (
                inner.clone(),
                inner.clone(),
                prop_oneof![Just("+"), Just("-"), Just("*"), Just("/")]
            )
                .prop_map(|(a, b, op)| format!("({a}) {op} ({b})")),
            inner.clone().prop_map(|a| format!("-({a})")),
            (inner.clone(), 0i32..5).prop_map(|(a, n)| format!("({a})^{n}")),
            (inner.clone(), -2i32..0).prop_map(|(a, n)| format!("({a})^({n})")),
            inner.clone().prop_map(|a| format!("sqrt({a})")),
            inner.clone().prop_map(|a| format!("abs({a})")),
            inner.clone().prop_map(|a| format!("(({a})^2)^2")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("min({a}, {b})")),
            (inner.clone(), inner).prop_map(|(a, b)| format!("max({a}, {b})")),
        ]
    })
}

fn arb_ibox() -> impl Strategy<Value = [Interval; 3]> {
    // Boxes with corners on a coarse grid often touch 0 exactly (poles, kinks on faces).
    (
        prop::array::uniform3(-8i32..8),
        prop::array::uniform3(0i32..8),
    )
        .prop_map(|(lo, w)| {
            [0, 1, 2].map(|k| {
                let a = lo[k] as f64 / 4.0;
                Interval::try_from((a, a + w[k] as f64 / 4.0)).unwrap()
            })
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    #[test]
    fn flags_agree_with_decorations(text in arb_formula(), b in arb_ibox()) {
        let f = Formula::surface(&text).unwrap();
        let ours = f.regularity(&b);
        let db = b.map(DecInterval::new);
        let dd = eval_dd(f.expr(), &db);
        let cont = at_least_dac(dd.v);
        // Continuity: the same verdict as IEEE 1788 (ours must never be stronger).
        prop_assert_eq!(ours >= Regularity::Continuous, cont,
            "continuity of {} on {:?}: ours {:?}, inari {:?}", text, b, ours, dd.v.decoration());
        // Smoothness: ours implies that f and its gradient are defined and continuous.
        if ours == Regularity::Smooth {
            prop_assert!(cont && dd.g.iter().all(|g| at_least_dac(*g)),
                "{} claimed smooth on {:?} but a derivative is {:?}", text, b,
                dd.g.map(|g| g.decoration()));
        }
    }
}

#[test]
fn the_flag_test_sees_every_level() {
    // The proptest above is not vacuous: the three levels all occur on simple cases.
    let b = [
        Interval::try_from((0.0, 1.0)).unwrap(),
        Interval::try_from((1.0, 2.0)).unwrap(),
        Interval::try_from((-1.0, 1.0)).unwrap(),
    ];
    let r = |t: &str| Formula::surface(t).unwrap().regularity(&b);
    assert_eq!(r("x*y + z^2"), Regularity::Smooth);
    assert_eq!(r("sqrt(x) + y"), Regularity::Continuous);
    assert_eq!(r("abs(z)"), Regularity::Continuous);
    assert_eq!(r("1/x"), Regularity::Undefined);
    assert_eq!(r("y/z"), Regularity::Undefined);
    assert_eq!(r("sqrt(z)"), Regularity::Undefined);
    assert_eq!(r("1/y + sqrt(y - 1) * 0"), Regularity::Continuous);
    // z·z is z² ≥ 0 (the case the proptest found in the test's own evaluator).
    assert_eq!(r("-(sqrt((z) * (z)))"), Regularity::Continuous);
}

// ---------------------------------------------------------------------------------
// 2. The false certificates of the past.

fn cube(dim: usize, r: f64) -> Aabb {
    if dim == 2 {
        Aabb::new([-r, -r, 0.0], [r, r, 0.0]).unwrap()
    } else {
        Aabb::new([-r; 3], [r; 3]).unwrap()
    }
}

fn pv(f: &Formula, d: &Aabb, dim: usize, depth: u32) -> MeshOutput {
    let p = PvParams::new(dim)
        .with_max_depth(depth)
        .with_max_boxes(2_000_000);
    run_pv(f, d, &p, dim, &NoProgress).unwrap().1
}

fn snyder(f: &Formula, d: &Aabb, dim: usize, depth: u32) -> MeshOutput {
    let p = SnyderParams::new(dim)
        .with_max_depth(depth)
        .with_max_boxes(2_000_000);
    run_snyder(f, d, &p, dim, &NoProgress).unwrap().1
}

#[test]
fn poles_and_double_zeros_are_never_certified() {
    let cases3 = [
        ("x/y", cube(3, 2.0)),
        ("1/x+1/y+1/z", cube(3, 2.0)),
        ("(x^2+y^2+z^2-1)^2", cube(3, 2.0)),
        ("x^2+y^2+z^2", cube(3, 2.0)),
        ("0", cube(3, 2.0)),
        ("sqrt(x^2+y^2+z^2) - 1 + 0*abs(x)", cube(3, 2.0)),
    ];
    for (t, d) in &cases3 {
        let f = Formula::surface(t).unwrap();
        for (name, out) in [("pv", pv(&f, d, 3, 5)), ("snyder", snyder(&f, d, 3, 5))] {
            if *t == "sqrt(x^2+y^2+z^2) - 1 + 0*abs(x)" {
                // abs(x) at x = 0 is not differentiable: boxes on the plane x = 0 that
                // meet the sphere are uncertified, the run as a whole too.
                assert!(!out.certificate.is_certified(), "{name} on {t}");
                continue;
            }
            assert!(
                !out.certificate.is_certified(),
                "{name} certified {t}: {:?}",
                out.certificate
            );
        }
    }
    let cases2 = ["x/y", "1/x+1/y", "(x^2+y^2-1)^2", "x^2+y^2", "0"];
    for t in cases2 {
        let f = Formula::curve(t).unwrap();
        let d = cube(2, 2.0);
        for (name, out) in [("pv", pv(&f, &d, 2, 8)), ("snyder", snyder(&f, &d, 2, 8))] {
            assert!(
                !out.certificate.is_certified(),
                "{name} certified the curve {t}: {:?}",
                out.certificate
            );
        }
    }
}

/// A pole inside boxes proven one-signed is no zero: x⁻¹ + y² + z² − 1 = 0 is the
/// regular surface x = 1/(1 − y² − z²), two sheets, with |x| ≥ 1/7.41 on the domain
/// (y² + z² ≤ 8.41). A certificate must describe exactly that, with no sheet on the
/// pole x = 0 (the mesh the old code certified had one, Hausdorff 4.09).
#[test]
fn a_pole_in_one_signed_boxes_is_no_sheet() {
    let f = Formula::surface("x^(-1)+y^2+z^2-1").unwrap();
    let d = Aabb::new([-2.0; 3], [2.0, 2.0, 2.1]).unwrap();
    for (name, out) in [("pv", pv(&f, &d, 3, 6)), ("snyder", snyder(&f, &d, 3, 6))] {
        let Mesh::Surface(m) = &out.mesh else {
            panic!()
        };
        if out.certificate.is_certified() {
            let close = m.vertices.iter().filter(|v| v[0].abs() < 0.13).count();
            assert_eq!(close, 0, "{name}: {close} vertices near the pole");
            assert_eq!(certmesh::metrics::components(m).unwrap(), 2, "{name}");
        }
        for v in &m.vertices {
            assert!(
                f.eval(*v).abs() < 1e-6 || v[0].abs() >= 0.13,
                "{name}: {v:?}"
            );
        }
    }
    // The curve analogue, checked by sampling.
    certified_curve_agrees("x^(-1)+y^2-1", [-2.0, -2.0], [4.0, 4.0], true).unwrap();
}

#[test]
fn poles_are_reported_as_discontinuities() {
    let f = Formula::surface("x/y").unwrap();
    let out = pv(&f, &cube(3, 2.0), 3, 4);
    let reasons: Vec<&str> = match &out.certificate {
        certmesh::Certificate::Uncertified { regions, .. } => {
            regions.iter().map(|r| r.reason.as_str()).collect()
        }
        c => panic!("certified {c:?}"),
    };
    assert!(
        reasons.iter().any(|r| r.contains("not continuous")),
        "{reasons:?}"
    );
}

/// A pole plane off every grid plane, at the meshers' defaults (depth limit 12, the
/// default box budget): the boxes on it stop `NONSMOOTH_MARGIN` levels early with the
/// discontinuity as their reason, so the run finishes (it spent the whole budget, 11 s,
/// and was reported as "box budget exhausted"), and the summary names the pole even
/// though other regions (f = 0 meets the domain boundary) come first in the tree.
#[test]
fn a_pole_plane_ends_the_refinement_early_and_is_named() {
    use certmesh::subdivision::engine::{NONSMOOTH_MARGIN, NONSMOOTH_MIN_LEVEL};
    let f = Formula::surface("1/(x - 0.1234) - 1").unwrap();
    let d = cube(3, 2.0);
    let pvp = PvParams::new(3);
    let (tree, pv_out) = run_pv(&f, &d, &pvp, 3, &NoProgress).unwrap();
    let sp = SnyderParams::new(3);
    let (stree, sn_out) = run_snyder(&f, &d, &sp, 3, &NoProgress).unwrap();
    for (name, tree, out, depth) in [
        ("pv", &tree, &pv_out, pvp.max_depth),
        ("snyder", &stree, &sn_out, sp.max_depth),
    ] {
        assert!(tree.refinement_complete, "{name}: the budget ran out");
        let certmesh::Certificate::Uncertified {
            reason, regions, ..
        } = &out.certificate
        else {
            panic!("{name} certified a pole plane")
        };
        assert!(reason.contains("not continuous"), "{name}: {reason}");
        // The regions on the pole are boxes of the early level that contain x = 0.1234.
        let level = (depth - NONSMOOTH_MARGIN).max(NONSMOOTH_MIN_LEVEL);
        assert!(level < depth, "{name}: the test needs a deeper default");
        let side = 4.0 / (1u64 << level) as f64;
        let pole: Vec<_> = regions
            .iter()
            .filter(|r| r.cause == certmesh::mesher::Cause::NotContinuous)
            .collect();
        assert!(!pole.is_empty(), "{name}");
        assert_eq!(regions[0].cause, certmesh::mesher::Cause::NotContinuous);
        for r in &pole {
            assert!(
                r.region.min[0] <= 0.1234 && 0.1234 <= r.region.max[0],
                "{name}"
            );
            assert!(
                (r.region.max[0] - r.region.min[0] - side).abs() < 1e-12,
                "{name}"
            );
        }
    }
}

#[test]
fn smooth_catalog_entries_still_certify() {
    for (t, dim) in [("x^2 + y^2 - 1", 2), ("x^2 + y^2 + z^2 - 1", 3)] {
        let f = Formula::with_dim(t, dim).unwrap();
        let d = cube(dim, 1.5);
        let depth = if dim == 2 { 8 } else { 6 };
        assert!(pv(&f, &d, dim, depth).certificate.is_certified(), "pv {t}");
    }
    // A pole outside the domain does not matter.
    let f = Formula::curve("x^2 + y^2 - 1 + 0.01/(x - 3)").unwrap();
    assert!(pv(&f, &cube(2, 1.5), 2, 8).certificate.is_certified());
}

#[test]
fn the_box_budget_stops_and_says_so() {
    // A double sphere: no box meeting it is ever certified, so the boxes near it are
    // split until the budget runs out.
    let f = Formula::surface("(x^2 + y^2 + z^2 - 0.25)^2").unwrap();
    let p = PvParams::new(3).with_max_depth(12).with_max_boxes(5000);
    let (tree, out) = run_pv(&f, &cube(3, 1.0), &p, 3, &NoProgress).unwrap();
    assert!(!tree.refinement_complete);
    assert_eq!(out.stats["refinement_complete"], serde_json::json!(false));
    assert!(!out.certificate.is_certified());
    match &out.certificate {
        certmesh::Certificate::Uncertified { regions, .. } => {
            assert!(regions.iter().any(|r| r.reason.contains("--max-boxes")))
        }
        c => panic!("{c:?}"),
    }
    // min_depth beyond the budget is refused before any work.
    let p = PvParams::new(3).with_max_depth(20).with_min_depth(20);
    let e = match run_pv(&f, &cube(3, 1.0), &p, 3, &NoProgress) {
        Err(e) => e,
        Ok(_) => panic!("min_depth 20 was accepted"),
    };
    assert!(e.to_string().contains("--max-boxes"), "{e}");
}

/// f ≡ 0: every box is a failure that names it, at once, instead of splitting every
/// box until the budget runs out (30 s at the defaults, with "raise --max-boxes" as
/// the reason, which could never help: found by an adversarial run).
#[test]
fn an_identically_zero_function_is_named_not_split() {
    let f = Formula::surface("0").unwrap();
    let d = cube(3, 1.0);
    let pv = PvParams::new(3).with_max_depth(12).with_max_boxes(5000);
    let sn = SnyderParams::new(3).with_max_depth(12).with_max_boxes(5000);
    for (tree, out) in [
        run_pv(&f, &d, &pv, 3, &NoProgress).unwrap(),
        run_snyder(&f, &d, &sn, 3, &NoProgress).unwrap(),
    ] {
        assert!(!out.certificate.is_certified());
        match &out.certificate {
            certmesh::Certificate::Uncertified { regions, .. } => {
                assert!(!regions.is_empty());
                assert!(
                    regions.iter().all(|r| r.reason.contains("identically 0")),
                    "{regions:?}"
                );
            }
            c => panic!("{c:?}"),
        }
        assert!(tree.refinement_complete, "stopped by the budget");
    }
}

// ---------------------------------------------------------------------------------
// 3. Random formulas: every certificate checked by sampling.

fn curve_components(c: &Curve2) -> usize {
    let n = c.vertices.len();
    let mut p: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], x: usize) -> usize {
        let mut r = x;
        while p[r] != r {
            r = p[r];
        }
        p[x] = r;
        r
    }
    for s in &c.segments {
        let (a, b) = (find(&mut p, s[0] as usize), find(&mut p, s[1] as usize));
        p[a] = b;
    }
    (0..n).filter(|&i| find(&mut p, i) == i).count()
}

/// The independent check of a certified curve: on an n×n grid over the domain, every
/// grid edge whose ends have opposite signs (both finite) lies within `tol` of a mesh
/// vertex and every mesh vertex within `tol` of such an edge; f and ∇f are finite at
/// the grid points near the curve; the sampled zero set has as many components
/// (marching-squares cells joined through shared edges) as the mesh.
fn check_certified_curve(
    f: &dyn Implicit,
    d: &Aabb,
    c: &Curve2,
    n: usize,
    leaf_diag: f64,
) -> Result<(), String> {
    let h = [
        (d.max[0] - d.min[0]) / n as f64,
        (d.max[1] - d.min[1]) / n as f64,
    ];
    let pt = |i: usize, j: usize| [d.min[0] + i as f64 * h[0], d.min[1] + j as f64 * h[1], 0.0];
    let vals: Vec<f64> = (0..=n)
        .flat_map(|j| (0..=n).map(move |i| (i, j)))
        .map(|(i, j)| f.eval(pt(i, j)))
        .collect();
    let v = |i: usize, j: usize| vals[j * (n + 1) + i];
    // The mesh is a chord of the curve inside each box: within a box diagonal of it.
    let tol = leaf_diag + 2.0 * (h[0] + h[1]);
    let seg_dist = |p: [f64; 3], a: [f64; 2], b: [f64; 2]| {
        let (ux, uy) = (b[0] - a[0], b[1] - a[1]);
        let l2 = ux * ux + uy * uy;
        let t = if l2 > 0.0 {
            (((p[0] - a[0]) * ux + (p[1] - a[1]) * uy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        ((a[0] + t * ux - p[0]).powi(2) + (a[1] + t * uy - p[1]).powi(2)).sqrt()
    };
    let near_mesh = |p: [f64; 3]| {
        c.segments
            .iter()
            .any(|s| seg_dist(p, c.vertices[s[0] as usize], c.vertices[s[1] as usize]) <= tol)
    };
    // Crossing edges, as midpoints, and marching-squares cells joined by them.
    let mut crossings = Vec::new();
    let cell = |i: usize, j: usize| j * n + i;
    let mut parent: Vec<usize> = (0..n * n).collect();
    let mut active = vec![false; n * n];
    fn find(p: &mut [usize], x: usize) -> usize {
        let mut r = x;
        while p[r] != r {
            r = p[r];
        }
        p[x] = r;
        r
    }
    for j in 0..=n {
        for i in 0..=n {
            for (di, dj) in [(1, 0), (0, 1)] {
                let (i2, j2) = (i + di, j + dj);
                if i2 > n || j2 > n {
                    continue;
                }
                let (a, b) = (v(i, j), v(i2, j2));
                if !(a.is_finite() && b.is_finite()) || (a >= 0.0) == (b >= 0.0) {
                    continue;
                }
                let (p, q) = (pt(i, j), pt(i2, j2));
                let m = [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.0];
                let g = f.grad(m);
                if !(g.g[0].is_finite() && g.g[1].is_finite()) {
                    return Err(format!("gradient not finite at {m:?} on the curve"));
                }
                crossings.push(m);
                // The edge is shared by up to two cells: join them.
                let cells: Vec<usize> = if di == 1 {
                    [j.checked_sub(1), (j < n).then_some(j)]
                        .into_iter()
                        .flatten()
                        .map(|jj| cell(i, jj))
                        .collect()
                } else {
                    [i.checked_sub(1), (i < n).then_some(i)]
                        .into_iter()
                        .flatten()
                        .map(|ii| cell(ii, j))
                        .collect()
                };
                for &k in &cells {
                    active[k] = true;
                }
                if cells.len() == 2 {
                    let (a, b) = (find(&mut parent, cells[0]), find(&mut parent, cells[1]));
                    parent[a] = b;
                }
            }
        }
    }
    for m in &crossings {
        if !near_mesh(*m) {
            return Err(format!("a sign change at {m:?} is far from the mesh"));
        }
    }
    for q in &c.vertices {
        let near = crossings
            .iter()
            .any(|m| ((q[0] - m[0]).powi(2) + (q[1] - m[1]).powi(2)).sqrt() <= tol);
        if !near {
            return Err(format!("mesh vertex {q:?} is far from every sign change"));
        }
    }
    let sampled = (0..n * n)
        .filter(|&k| active[k] && find(&mut parent, k) == k)
        .count();
    let meshed = curve_components(c);
    if sampled != meshed {
        return Err(format!("{meshed} components meshed, {sampled} sampled"));
    }
    Ok(())
}

fn arb_curve() -> impl Strategy<Value = String> {
    // Curves likely to have a zero set in [-2, 2]²: g(x, y) - c with random g.
    let leaf = prop_oneof![
        3 => prop_oneof![Just("x".to_string()), Just("y".to_string())],
        1 => (-8i32..8).prop_map(|k| format!("{}", k as f64 / 4.0)),
    ];
    let g = leaf.prop_recursive(3, 12, 2, |inner| {
        prop_oneof![
            (
                inner.clone(),
                inner.clone(),
                prop_oneof![Just("+"), Just("-"), Just("*"), Just("/")]
            )
                .prop_map(|(a, b, op)| format!("({a}) {op} ({b})")),
            (inner.clone(), 1i32..4).prop_map(|(a, n)| format!("({a})^{n}")),
            inner.clone().prop_map(|a| format!("sqrt({a})")),
            inner.clone().prop_map(|a| format!("abs({a})")),
            inner.clone().prop_map(|a| format!("(({a})^2)")),
            (inner.clone(), inner).prop_map(|(a, b)| format!("min({a}, {b})")),
        ]
    });
    (g, -4i32..4).prop_map(|(g, c)| format!("x^2 + y^2 - 2 + 0.5*({g}) - {}", c as f64 / 4.0))
}

fn certified_curve_agrees(
    text: &str,
    lo: [f64; 2],
    w: [f64; 2],
    snyder_too: bool,
) -> Result<(), String> {
    let f = Formula::curve(text).unwrap();
    let d = Aabb::new([lo[0], lo[1], 0.0], [lo[0] + w[0], lo[1] + w[1], 0.0]).unwrap();
    let budget = 2_000_000;
    let p = PvParams::new(2).with_max_depth(7).with_max_boxes(budget);
    let mut outs = vec![("pv", run_pv(&f, &d, &p, 2, &NoProgress).unwrap())];
    if snyder_too {
        let p = SnyderParams::new(2)
            .with_max_depth(7)
            .with_max_boxes(budget);
        outs.push(("snyder", run_snyder(&f, &d, &p, 2, &NoProgress).unwrap()));
    }
    for (name, (tree, out)) in outs {
        if !out.certificate.is_certified() {
            continue;
        }
        let Mesh::Curve(c) = &out.mesh else {
            return Err("not a curve".into());
        };
        let diag = certmesh::subdivision::leaf_boxes(&tree)
            .iter()
            .filter(|(_, v)| *v != certmesh::subdivision::Verdict::Empty)
            .map(|(b, _)| ((b.max[0] - b.min[0]).powi(2) + (b.max[1] - b.min[1]).powi(2)).sqrt())
            .fold(0.0, f64::max);
        check_certified_curve(&f, &d, c, 512, diag)
            .map_err(|e| format!("{name} on {text} in {d:?}: {e}"))?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2500, ..ProptestConfig::default() })]

    #[test]
    fn certified_curves_agree_with_sampling(text in arb_curve(),
            lo in prop::array::uniform2(-2.5f64..0.5), w in prop::array::uniform2(1.0f64..3.0),
            snyder_too in any::<bool>()) {
        if let Err(e) = certified_curve_agrees(&text, lo, w, snyder_too) {
            prop_assert!(false, "{}", e);
        }
    }
}

#[test]
#[ignore = "long: 50,000 random curves (cargo test --release --test soundness -- --ignored)"]
fn certified_curves_agree_with_sampling_long() {
    let mut runner = proptest::test_runner::TestRunner::new(ProptestConfig {
        cases: 50_000,
        ..ProptestConfig::default()
    });
    runner
        .run(
            &(
                arb_curve(),
                prop::array::uniform2(-2.5f64..0.5),
                prop::array::uniform2(1.0f64..3.0),
            ),
            |(t, lo, w)| {
                certified_curve_agrees(&t, lo, w, true)
                    .map_err(proptest::test_runner::TestCaseError::fail)
            },
        )
        .unwrap();
}

/// The mean-value form f(c) + □∇f·(B − c) is no enclosure across a pole: on
/// [−1, 1]² the curve x + 1/y = 0 (the hyperbola x·y = −1 through (±1, ∓1)) exists,
/// and no box containing it may be proven empty.
#[test]
fn the_mean_value_form_is_not_used_across_a_pole() {
    let f = Formula::curve("x + 1/y").unwrap();
    let d = cube(2, 1.0);
    for (name, out) in [("pv", pv(&f, &d, 2, 8)), ("snyder", snyder(&f, &d, 2, 8))] {
        assert!(!out.certificate.is_certified(), "{name}");
    }
    let f = Formula::curve("x + 1/y").unwrap();
    let d = Aabb::new([-1.5, 0.5, 0.0], [-0.5, 1.5, 0.0]).unwrap();
    certified_curve_agrees("x + 1/y", [-1.5, 0.5], [1.0, 1.0], true).unwrap();
    assert!(pv(&f, &d, 2, 8).certificate.is_certified());
}

#[test]
fn claims_are_typed_and_match_their_text() {
    use certmesh::mesher::{Cause, Claim};
    let f = Formula::surface("x^2 + y^2 + z^2 - 1").unwrap();
    let out = pv(&f, &cube(3, 1.5), 3, 6);
    let c = &out.certificate;
    assert!(c.proves_topology());
    let typed = c.claims_typed();
    assert!(matches!(typed[0], Claim::Isotopic { .. }));
    let texts: Vec<String> = typed.iter().map(|t| t.to_string()).collect();
    assert_eq!(texts, c.claims());
    let j = serde_json::to_value(c).unwrap();
    assert_eq!(j["claims_typed"][0]["kind"], "isotopic");
    assert_eq!(
        j["claims"][0],
        certmesh::subdivision::plantinga_vegter::PV_CLAIM
    );
    // Uncertified regions carry their cause.
    let f = Formula::surface("x/y").unwrap();
    let out = pv(&f, &cube(3, 2.0), 3, 4);
    match &out.certificate {
        certmesh::Certificate::Uncertified { regions, .. } => {
            assert!(regions.iter().any(|r| r.cause == Cause::NotContinuous));
            assert!(!out.certificate.proves_topology());
        }
        c => panic!("{c:?}"),
    }
}

/// A surface that leaves the domain is not certified by either subdivision mesher:
/// the case a fresh-clone CI run found in tests/subdivision.rs, where an ellipsoid of
/// semi-axis 0.986 centred at x = -0.157 crossed the face x = -1.129 and the test
/// had still demanded a certificate. The guard reports the domain boundary.
#[test]
fn a_surface_leaving_the_domain_is_not_certified() {
    use certmesh::mesher::Cause;
    let f = Formula::surface(
        "(x - (-0.15698082410445308))^2/0.9857666756195742^2 + y^2/0.3^2 + z^2/0.3^2 - 1",
    )
    .unwrap();
    let o = 0.17143818574257375;
    let d = Aabb::new([-1.3 + o, -1.25, -1.2 - o], [1.3 + o, 1.2, 1.25]).unwrap();
    for (name, out) in [("pv", pv(&f, &d, 3, 7)), ("snyder", snyder(&f, &d, 3, 7))] {
        match &out.certificate {
            certmesh::Certificate::Uncertified { regions, .. } => assert!(
                regions.iter().any(|r| r.cause == Cause::DomainBoundary),
                "{name}: {regions:?}"
            ),
            c => panic!("{name} certified a surface that leaves the domain: {c:?}"),
        }
    }
    // The same ellipsoid moved inside the domain certifies (PV).
    let f =
        Formula::surface("(x - (0.1))^2/0.9857666756195742^2 + y^2/0.3^2 + z^2/0.3^2 - 1").unwrap();
    assert!(pv(&f, &d, 3, 7).certificate.is_certified());
}

/// Snyder in generic position meshes a rotated box containing the domain; its claim
/// is isotopy to f = 0 inside the domain, with the domain as the typed `inside`. Found
/// by an adversarial test: sphere B (centre (1.08, 0, 0), r 0.02) lies outside the
/// domain [-1, 1]³ but inside the rotated box and was meshed and certified (2
/// components where f = 0 inside the domain is the one sphere A); sphere C (centre
/// (1.16, -1.16, -1.12), r 0.005) lies outside the rotated box but inside the typed
/// `inside`, which was the rotated frame's box. Either the run is uncertified, naming
/// a region at sphere B with cause `outside_domain`, or (never today) it certifies with
/// exactly the one component of sphere A and `inside` the domain. The 2D analogue
/// (a circle at (1.06, 0)) likewise. Spheres well inside the domain still certify,
/// with `inside` the domain.
#[test]
fn generic_position_claims_only_the_domain() {
    use certmesh::mesher::{Cause, Claim};
    let near = |r: &certmesh::mesher::Uncertified, p: [f64; 3], dim: usize| {
        (0..dim).all(|k| r.region.min[k] - 0.05 <= p[k] && p[k] <= r.region.max[k] + 0.05)
    };
    let a = "(x^2 + y^2 + z^2 - 0.25)";
    let b = "((x - 1.08)^2 + y^2 + z^2 - 0.0004)";
    let c = "((x - (1.16))^2 + (y - (-1.16))^2 + (z - (-1.12))^2 - 0.000025)";
    let a2 = "(x^2 + y^2 - 0.25)";
    let b2 = "((x - 1.06)^2 + y^2 - 0.0004)";
    let cases = [
        (format!("{a}*{b}*{c}"), 3, [1.08, 0.0, 0.0]),
        (format!("{a}*{b}"), 3, [1.08, 0.0, 0.0]),
        (format!("{a2}*{b2}"), 2, [1.06, 0.0, 0.0]),
    ];
    for (t, dim, outside) in &cases {
        let (t, dim) = (t.as_str(), *dim);
        let f = Formula::with_dim(t, dim).unwrap();
        let d = cube(dim, 1.0);
        let p = SnyderParams::new(dim)
            .with_max_depth(if dim == 3 { 14 } else { 16 })
            .with_max_boxes(2_000_000)
            .with_generic_shift(true);
        let out = run_snyder(&f, &d, &p, dim, &NoProgress).unwrap().1;
        match &out.certificate {
            certmesh::Certificate::Uncertified { regions, .. } => {
                assert!(
                    regions
                        .iter()
                        .any(|r| r.cause == Cause::OutsideDomain && near(r, *outside, dim)),
                    "{t}: {regions:?}"
                );
                assert!(!out.certificate.proves_topology(), "{t}");
            }
            certmesh::Certificate::Certified { claims_typed, .. } => {
                let parts = match &out.mesh {
                    Mesh::Surface(m) => certmesh::metrics::components(m).unwrap(),
                    Mesh::Curve(c) => curve_components(c),
                    _ => unreachable!(),
                };
                assert_eq!(parts, 1, "{t}: certified with {parts} components");
                for cl in claims_typed {
                    if let Claim::Isotopic { inside, .. } = cl {
                        assert_eq!(inside, &d, "{t}");
                    }
                }
            }
        }
    }
    // Zero sets well inside the domain: certified, isotopic inside the domain itself.
    for (t, dim, parts) in [
        (format!("{a}"), 3, 1),
        (format!("{a}*((x - 0.7)^2 + y^2 + z^2 - 0.0004)"), 3, 2),
        (format!("{a2}"), 2, 1),
    ] {
        let f = Formula::with_dim(&t, dim).unwrap();
        let d = cube(dim, 1.0);
        let p = SnyderParams::new(dim)
            .with_max_depth(if dim == 3 { 14 } else { 16 })
            .with_generic_shift(true);
        let out = run_snyder(&f, &d, &p, dim, &NoProgress).unwrap().1;
        assert!(
            out.certificate.proves_topology(),
            "{t}: {:?}",
            out.certificate.reason()
        );
        let found = match &out.mesh {
            Mesh::Surface(m) => certmesh::metrics::components(m).unwrap(),
            Mesh::Curve(c) => curve_components(c),
            _ => unreachable!(),
        };
        assert_eq!(found, parts, "{t}");
        let insides: Vec<&Aabb> = out
            .certificate
            .claims_typed()
            .iter()
            .filter_map(|c| match c {
                Claim::Isotopic { inside, .. } | Claim::RegularZeroSet { inside, .. } => {
                    Some(inside)
                }
                _ => None,
            })
            .collect();
        assert_eq!(insides, vec![&d, &d], "{t}");
    }
}

/// A pole plane between grid planes, where f changes sign (1/(x − a) − 1 at
/// a = 0.1234): every lattice mesher refuses it, naming a point of the pole, instead of
/// meshing the pole plane as a second surface. The point named is checked against the
/// pole itself; a pole whose sides have one sign (1/(x − a)² − 4) and a pole outside
/// the domain are no error, and their meshes have no vertex near x = a.
#[test]
fn lattice_meshers_refuse_a_sign_change_across_a_pole() {
    use certmesh::mesher::registry;
    let a = 0.1234;
    let o = certmesh::mesher::options::MesherOptions::default();
    for (algo, dim, text, ok_text) in [
        ("mc", 3, "1/(x - 0.1234) - 1", "1/(x - 0.1234)^2 - 4"),
        ("mt", 3, "1/(x - 0.1234) - 1", "1/(x - 0.1234)^2 - 4"),
        ("bcsv", 3, "1/(x - 0.1234) - 1", "1/(x - 0.1234)^2 - 4"),
        ("midnormal", 3, "1/(x - 0.1234) - 1", "1/(x - 0.1234)^2 - 4"),
        (
            "gradnormal",
            3,
            "1/(x - 0.1234) - 1",
            "1/(x - 0.1234)^2 - 4",
        ),
        ("stuffing", 3, "1/(x - 0.1234) - 1", "1/(x - 0.1234)^2 - 4"),
        ("ms", 2, "1/(x - 0.1234) - y", "1/(x - 0.1234)^2 - 4 - y"),
        (
            "midnormal",
            2,
            "1/(x - 0.1234) - y",
            "1/(x - 0.1234)^2 - 4 - y",
        ),
        (
            "gradnormal",
            2,
            "1/(x - 0.1234) - y",
            "1/(x - 0.1234)^2 - 4 - y",
        ),
    ] {
        let m = registry::build(algo, dim, &o).unwrap();
        let d = cube(dim, 2.0);
        let f = Formula::with_dim(text, dim).unwrap();
        let e = match m.mesh(&f, &d, &NoProgress) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{algo} {dim}D meshed a sign change across the pole of {text}"),
        };
        let near = e.split("continuous near [").nth(1).expect(&e);
        let x: f64 = near.split(',').next().unwrap().trim().parse().expect(&e);
        assert!((x - a).abs() < 1e-6, "{algo} {dim}D: {e}");
        let g = Formula::with_dim(ok_text, dim).unwrap();
        let out = m
            .mesh(&g, &d, &NoProgress)
            .unwrap_or_else(|e| panic!("{algo} {dim}D on {ok_text}: {e}"));
        let xs: Vec<f64> = match &out.mesh {
            Mesh::Surface(s) => s.vertices.iter().map(|v| v[0]).collect(),
            Mesh::Curve(c) => c.vertices.iter().map(|v| v[0]).collect(),
            Mesh::Volume { boundary, .. } => boundary.vertices.iter().map(|v| v[0]).collect(),
        };
        assert!(!xs.is_empty(), "{algo} {dim}D on {ok_text}");
        // Its zero set is |x − a| = 0.5: nothing lies within 0.25 of the pole.
        assert!(
            xs.iter().all(|x| (x - a).abs() > 0.25),
            "{algo} {dim}D on {ok_text}: a vertex near the pole"
        );
    }
    let far = Formula::surface("x^2 + y^2 + z^2 - 1 + 0.01/(x - 3)").unwrap();
    let m = registry::build("mc", 3, &o).unwrap();
    assert!(m.mesh(&far, &cube(3, 2.0), &NoProgress).is_ok());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    /// `discontinuity_on_segment` against the pole it is given: 1/(x − c) on a random
    /// segment is continuous there exactly when c is not between the ends' x, and the
    /// point it names then lies within the last piece (2⁻³⁰ of the segment) of x = c.
    #[test]
    fn discontinuity_on_segment_finds_the_pole(
        c in -1.0f64..1.0,
        a in prop::array::uniform3(-2.0f64..2.0),
        b in prop::array::uniform3(-2.0f64..2.0),
        k in 1u32..4,
    ) {
        use certmesh::implicit::ops::{discontinuity_on_segment, DISCONTINUITY_DEPTH};
        let f = Formula::surface(&format!("1/(x - ({c}))^{k} + y*z")).unwrap();
        let got = discontinuity_on_segment(&f, a, b, DISCONTINUITY_DEPTH);
        let (lo, hi) = (a[0].min(b[0]), a[0].max(b[0]));
        let len = (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt();
        // Margins of a few ulps and of the last piece: on the line, decide only where
        // the answer is clear.
        let piece = len * 2f64.powi(-(DISCONTINUITY_DEPTH as i32));
        if c < lo - 1e-12 || c > hi + 1e-12 {
            prop_assert!(got.is_none(), "pole {c} outside [{lo}, {hi}] but {got:?}");
        } else if c > lo + 1e-12 && c < hi - 1e-12 {
            let x = got.expect("the pole is inside the segment");
            prop_assert!((x[0] - c).abs() <= piece + 1e-12, "{x:?} against {c}");
        }
        // A polynomial is continuous on every segment.
        let p = Formula::surface(&format!("(x - ({c}))^{k} + y*z")).unwrap();
        prop_assert!(discontinuity_on_segment(&p, a, b, DISCONTINUITY_DEPTH).is_none());
    }
}
