//! The exact algebraic machinery and the González-Vega–Necula sweep: property tests of
//! every exact primitive against independent references (Sturm counts, floating-point
//! roots, Sylvester determinants by cofactor expansion), and the sweep on curves with
//! known topology, checked against an independent count of crossings along dense
//! vertical lines (exact Sturm root counts).
use certmesh::algebraic::algnum::isolate;
use certmesh::algebraic::bipoly::{from_formula, BiPoly};
use certmesh::algebraic::check::check_curve;
use certmesh::algebraic::subres;
use certmesh::algebraic::sweep::{analyse, Label, SweepParams, SweepResult};
use certmesh::algebraic::upoly::{q, sturm_count, UPoly};
use certmesh::metrics::embedding_signature;
use certmesh::Aabb;
use num_rational::BigRational;
use num_traits::{One, ToPrimitive, Zero};
use proptest::prelude::*;

fn dom(x0: f64, y0: f64, x1: f64, y1: f64) -> Aabb {
    Aabb {
        min: [x0, y0, 0.0],
        max: [x1, y1, 0.0],
    }
}

fn run(f: &str, d: Aabb) -> SweepResult {
    let p = from_formula(f).unwrap();
    analyse(&p, &d, &SweepParams::default()).unwrap_or_else(|e| panic!("{f}: {e}"))
}

/// Components (isolated vertices count), first Betti number, degrees ≠ 2 (boundary
/// vertices excluded), number of boundary vertices.
#[derive(Debug, PartialEq)]
struct Topo {
    components: usize,
    cycles: usize,
    special_degrees: Vec<usize>,
    boundary: usize,
}

fn topo(r: &SweepResult) -> Topo {
    let n = r.curve.vertices.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut Vec<usize>, i: usize) -> usize {
        let mut i = i;
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let mut deg = vec![0usize; n];
    for s in &r.curve.segments {
        let (a, b) = (s[0] as usize, s[1] as usize);
        deg[a] += 1;
        deg[b] += 1;
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        parent[ra] = rb;
    }
    let comps = (0..n).filter(|&i| find(&mut parent, i) == i).count();
    let mut sd: Vec<usize> = (0..n)
        .filter(|&i| deg[i] != 2 && r.labels[i] != Label::Boundary)
        .map(|i| deg[i])
        .collect();
    sd.sort();
    let boundary = r.labels.iter().filter(|&&l| l == Label::Boundary).count();
    Topo {
        components: comps,
        cycles: r.curve.segments.len() + comps - n,
        special_degrees: sd,
        boundary,
    }
}

/// Independent check: along many vertical lines u = c (sheared frame), the number of
/// output segments crossing the line equals the exact number of real roots of
/// f_s(c, ·) inside the domain (Sturm count, for curves strictly inside the domain or
/// with s = 0).
fn check_crossings(f: &str, d: Aabb, r: &SweepResult) {
    let p = from_formula(f).unwrap().shear(r.shear);
    let s = r.shear as f64;
    let (ylo, yhi) = if r.shear == 0 {
        (
            BigRational::from_float(d.min[1]).unwrap(),
            BigRational::from_float(d.max[1]).unwrap(),
        )
    } else {
        (q(-1_000_000, 1), q(1_000_000, 1))
    };
    let uv: Vec<[f64; 2]> = r
        .curve
        .vertices
        .iter()
        .map(|v| [v[0] - s * v[1], v[1]])
        .collect();
    let (umin, umax) = uv
        .iter()
        .fold((f64::MAX, f64::MIN), |a, v| (a.0.min(v[0]), a.1.max(v[0])));
    if uv.is_empty() {
        return;
    }
    for t in 1..200 {
        let c = umin + (umax - umin) * (t as f64 + 0.37) / 200.0;
        if uv.iter().any(|v| (v[0] - c).abs() < 1e-12) {
            continue;
        }
        let crossings = r
            .curve
            .segments
            .iter()
            .filter(|sg| {
                let (a, b) = (uv[sg[0] as usize][0], uv[sg[1] as usize][0]);
                (a - c) * (b - c) < 0.0
            })
            .count();
        let cq = BigRational::from_float(c).unwrap();
        let exact = sturm_count(&p.at_x(&cq), &ylo, &yhi);
        assert_eq!(crossings, exact, "{f}: line u = {c}");
    }
}

/// One curve of the design note's table: the shear chosen, the number of critical
/// events (real roots of the discriminant in the domain), the embedding signature
/// (components, degrees ≠ 2, faces with dual degrees, nesting; clipped curves closed
/// by the domain frame), the certificate re-checked (also after a JSON round trip),
/// and, for compact curves or shear 0, crossings along vertical lines against exact
/// Sturm counts.
fn table(f: &str, d: Aabb, shear: i64, events: usize, signature: &str) -> SweepResult {
    let r = run(f, d);
    assert_eq!(
        r.shear, shear,
        "{f}: shear (rejected {:?})",
        r.rejected_shears
    );
    let ncrit = r.events.iter().filter(|e| e.critical).count();
    assert_eq!(ncrit, events, "{f}: critical events {:?}", r.events);
    let sig = embedding_signature(&r.curve, Some(&d)).unwrap();
    assert_eq!(sig, signature, "{f}: signature; events {:?}", r.events);
    let rep = check_curve(&r.cert).unwrap_or_else(|e| panic!("{f}: {e}"));
    assert_eq!(rep.vertices, r.curve.vertices.len());
    let json = serde_json::to_string(&r.cert).unwrap();
    let back: certmesh::algebraic::CurveCert = serde_json::from_str(&json).unwrap();
    check_curve(&back).unwrap();
    let boundary = r.labels.iter().any(|&l| l == Label::Boundary);
    if r.shear == 0 || !boundary {
        check_crossings(f, d, &r);
    }
    // A singular (or isolated) vertex has degree a_L + a_R.
    let mut deg = vec![0usize; r.curve.vertices.len()];
    for sg in &r.curve.segments {
        deg[sg[0] as usize] += 1;
        deg[sg[1] as usize] += 1;
    }
    let special = |l: Label| l == Label::Singular || l == Label::Isolated;
    let mut got: Vec<usize> = (0..deg.len())
        .filter(|&i| special(r.labels[i]))
        .map(|i| deg[i])
        .collect();
    let mut want: Vec<usize> = r
        .events
        .iter()
        .filter(|e| e.inside == Some(true) && e.label.is_some_and(special))
        .map(|e| e.branches.map_or(0, |(a, b)| a + b))
        .collect();
    got.sort();
    want.sort();
    assert_eq!(got, want, "{f}: singular vertex degrees");
    r
}

fn branches(r: &SweepResult) -> Vec<(usize, usize)> {
    let mut b: Vec<(usize, usize)> = r.events.iter().filter_map(|e| e.branches).collect();
    b.sort();
    b
}

fn sq(h: f64) -> Aabb {
    dom(-h, -h, h, h)
}

#[test]
fn table_circle() {
    let r = table("x^2 + y^2 - 1", sq(2.0), 0, 2, "C[]{O1 b1}");
    assert_eq!(branches(&r), vec![(0, 2), (2, 0)]);
    assert!(r.events.iter().all(|e| e.label != Some(Label::Singular)));
}

#[test]
fn table_lemniscate_catalog() {
    // The catalog's lemniscate, in the catalog's domain: one node of four branches.
    let e = certmesh::catalog::get("lemniscate").unwrap();
    let r = table(e.formula, e.domain, 0, 3, "C[4]{O2 b1 b1}");
    let node: Vec<_> = r
        .events
        .iter()
        .filter(|e| e.label == Some(Label::Singular))
        .collect();
    assert_eq!(node.len(), 1);
    assert_eq!(node[0].branches, Some((2, 2)));
    assert_eq!(node[0].multiplicity, Some(2));
}

#[test]
fn table_lemniscate_rotated() {
    let r = table(
        "(x^2 + y^2)^2 - 2*(y^2 - x^2)",
        sq(2.0),
        1,
        3,
        "C[4]{O2 b1 b1}",
    );
    let node = r
        .events
        .iter()
        .find(|e| e.label == Some(Label::Singular))
        .unwrap();
    assert_eq!(node.branches, Some((2, 2)));
}

#[test]
fn table_limacon() {
    let r = table(
        "(x^2 + y^2 - x)^2 - (x^2 + y^2)/4",
        sq(2.0),
        1,
        5,
        "C[4]{O1 b1 b2}",
    );
    assert_eq!(
        r.events
            .iter()
            .filter(|e| e.label == Some(Label::Singular))
            .count(),
        1
    );
}

#[test]
fn lemniscate_and_limacon_same_graph_not_isotopic() {
    let a = run("(x^2 + y^2)^2 - 2*(x^2 - y^2)", sq(2.0));
    let b = run("(x^2 + y^2 - x)^2 - (x^2 + y^2)/4", sq(2.0));
    // Same abstract graph: one vertex of degree 4, two cycles, one component.
    assert_eq!(topo(&a), topo(&b));
    assert_eq!(topo(&a).special_degrees, vec![4]);
    let (sa, sb) = (
        embedding_signature(&a.curve, None).unwrap(),
        embedding_signature(&b.curve, None).unwrap(),
    );
    assert_ne!(sa, sb);
}

#[test]
fn table_cusp() {
    let r = table("y^2 - x^3", sq(2.0), 0, 1, "F[]{O2 b2 b2}");
    assert_eq!(branches(&r), vec![(0, 2)]);
    let e = r.events.iter().find(|e| e.critical).unwrap();
    assert_eq!(e.label, Some(Label::Singular));
}

#[test]
fn table_acnode() {
    let r = table(
        "y^2 - x^2*(x - 1)",
        dom(-2.0, -3.0, 3.0, 3.0),
        0,
        2,
        "F[]{O2 b2 b2[C[0]{}]}",
    );
    assert_eq!(
        r.labels.iter().filter(|&&l| l == Label::Isolated).count(),
        1
    );
    assert_eq!(branches(&r), vec![(0, 0), (0, 2)]);
}

#[test]
fn table_crunode() {
    let r = table("y^2 - x^2*(x + 1)", sq(2.0), 0, 2, "F[4]{O2 b1 b2 b3}");
    assert_eq!(branches(&r), vec![(0, 2), (2, 2)]);
}

#[test]
fn table_point() {
    let r = table("x^2 + y^2", sq(2.0), 0, 1, "C[0]{}");
    assert_eq!(r.labels, vec![Label::Isolated]);
}

#[test]
fn table_tacnode() {
    let r = table("y^2 - x^4", sq(2.0), 0, 1, "F[4]{O4 b3 b3 b3 b3}");
    assert_eq!(branches(&r), vec![(2, 2)]);
    assert_eq!(
        r.events.iter().find(|e| e.critical).unwrap().multiplicity,
        Some(2)
    );
}

#[test]
fn table_ramphoid_cusp() {
    let r = table(
        "(y - x^2)^2 - x^5",
        dom(-1.0, -3.0, 1.5, 8.0),
        0,
        1,
        "F[]{O2 b2 b2}",
    );
    assert_eq!(branches(&r), vec![(0, 2)]);
}

#[test]
fn table_trifolium() {
    let r = table(
        "(x^2 + y^2)^2 - (x^3 - 3*x*y^2)",
        sq(2.0),
        1,
        5,
        "C[6]{O3 b1 b1 b1}",
    );
    assert!(branches(&r).contains(&(3, 3)));
}

#[test]
fn table_quadrifolium() {
    let r = table(
        "(x^2 + y^2)^3 - 4*x^2*y^2",
        sq(2.0),
        2,
        7,
        "C[8]{O4 b1 b1 b1 b1}",
    );
    assert!(branches(&r).contains(&(4, 4)));
}

#[test]
fn table_nested_circles() {
    table(
        "(x^2 + y^2 - 1)*(x^2 + y^2 - 4)",
        sq(3.0),
        0,
        4,
        "C[]{O1 b1[C[]{O1 b1}]}",
    );
}

#[test]
fn table_stacked_circles() {
    table(
        "(x^2 + y^2 - 1)*(x^2 + (y - 3)^2 - 1)",
        dom(-3.0, -2.0, 3.0, 5.0),
        1,
        4,
        "C[]{O1 b1} | C[]{O1 b1}",
    );
}

#[test]
fn table_hyperbola_clipped() {
    let r = table("x*y - 1", sq(3.0), 1, 0, "F[]{O3 b2 b2 b3}");
    assert_eq!(
        r.labels.iter().filter(|&&l| l == Label::Boundary).count(),
        4
    );
}

/// Two hyperbolas, x y = ±1/2, whose sides' crossings are rational and share sheared
/// fibres with other roots: on the fibre u = −9/4 the roots 2 (a crossing) and 2.45…
/// were isolated as [2, 2] and [2, 4], and the refinement that needed the sign at 2
/// never separated them ("locating a boundary crossing: refinement budget
/// exhausted"). Four arcs, each cutting off a corner of the square (as `x*y - 1`'s two
/// do above): four corner faces and the middle one.
#[test]
fn hyperbolas_with_rational_crossings_on_shared_fibres() {
    let r = table("x^2*y^2 - 1/4", sq(2.0), 1, 2, "F[]{O5 b2 b2 b2 b2 b5}");
    assert_eq!(
        r.labels.iter().filter(|&&l| l == Label::Boundary).count(),
        8
    );
    assert_eq!(topo(&r).components, 4);
    // On [-1, 1]² the sheared fibre u = 1/2 has the exact roots 1/2 and −1, both
    // crossings, at the centres of the root search's boxes: they stayed ends of two
    // boxes ("the 2 simple roots were not certified within the refinement budget").
    let r = table("x^2*y^2 - 1/4", sq(1.0), 1, 2, "F[]{O5 b2 b2 b2 b2 b5}");
    assert_eq!(topo(&r).components, 4);
}

#[test]
fn parabola_clipped() {
    // lc_y = 1: y-regular without a shear, and no critical x-value.
    let r = table("y - x^2", sq(2.0), 0, 0, "F[]{O2 b2 b2}");
    assert_eq!(
        r.labels.iter().filter(|&&l| l == Label::Boundary).count(),
        2
    );
    // Shear 0: the x-parabola, y-regular as it is; its vertex is an x-extreme.
    let r = table("x - y^2 + 1", sq(2.0), 0, 1, "F[]{O2 b2 b2}");
    assert_eq!(
        r.events.iter().find(|e| e.critical).unwrap().label,
        Some(Label::XExtreme)
    );
}

#[test]
fn table_cassini_two_ovals() {
    table(
        "(x^2 + y^2)^2 - 2*(x^2 - y^2) - (1/16 - 1)",
        sq(2.0),
        0,
        4,
        "C[]{O1 b1} | C[]{O1 b1}",
    );
}

#[test]
fn table_cassini_one_oval() {
    let e = certmesh::catalog::get("cassini-1").unwrap();
    // Two x-extremes; the waist has horizontal tangents only.
    table(e.formula, e.domain, 0, 2, "C[]{O1 b1}");
}

#[test]
fn table_devils_curve() {
    table(
        "y^2*(y^2 - 1) - x^2*(x^2 - 2)",
        sq(3.0),
        2,
        3,
        "F[]{O3 b2 b2 b3[C[4]{O2 b1 b1}]}",
    );
}

#[test]
fn table_point_inside_circle_phantom() {
    let r = table(
        "(x^2 + y^2 - 1)*((x - 1/5)^2 + y^2)",
        sq(3.0),
        0,
        4,
        "C[]{O1 b1[C[0]{}]}",
    );
    // The phantom event at 13/5: no real multiple root, nothing happens.
    let ph: Vec<_> = r
        .events
        .iter()
        .filter(|e| e.critical && e.generic == Some(false))
        .collect();
    assert!(
        ph.iter()
            .any(|e| e.real_multiple_roots == Some(0) && e.branches.is_none()),
        "{:?}",
        r.events
    );
}

#[test]
fn table_point_outside_circle_phantom() {
    table(
        "(x^2 + y^2 - 1)*((x - 2)^2 + y^2)",
        sq(3.0),
        0,
        4,
        "C[0]{} | C[]{O1 b1}",
    );
}

#[test]
fn table_t4_ellipses() {
    table(
        "8*x^4 - 8*x^2 + 8*y^4 - 8*y^2 + 2",
        sq(2.0),
        2,
        8,
        "C[4,4,4,4]{O4 b2 b2 b2 b2 b4}",
    );
}

#[test]
fn table_degree8_mix() {
    table(
        "((x^2 + y^2)^2 - 2*(x^2 - y^2))*(x^2 + y^2 - 4)*(x - y^2 + 1)",
        sq(3.0),
        1,
        10,
        "F[4,4,4,4,4]{O2 b1 b2 b2 b3 b3 b3 b4}",
    );
}

#[test]
fn vertical_line_component_takes_the_shear_path() {
    let r = table("x*(x^2 + y^2 - 1)", sq(2.0), 1, 4, "F[4,4]{O2 b2 b2 b3 b3}");
    assert_eq!(r.rejected_shears[0].0, 0);
}

#[test]
fn empty_curve() {
    let r = table("x^2 + y^2 + 1", sq(2.0), 0, 0, "");
    assert!(r.curve.vertices.is_empty());
}

#[test]
fn non_polynomial_rejected_naming_the_term() {
    let e = from_formula("sqrt(x^2 + y^2) - 1").unwrap_err().to_string();
    assert!(e.contains("sqrt"), "{e}");
    let e = from_formula("x/y - 1").unwrap_err().to_string();
    assert!(e.contains("non-constant"), "{e}");
}

#[test]
fn cluster_real_node_with_complex_double_roots() {
    // x = 0: y²·(y² + 1)²: three multiple roots (0, ±i), one real: the real-only test
    // keeps shear 0 and isolates the node as a cluster.
    let r = table(
        "(y^2 - x^2)*((y^2 + 1)^2 + x^2)",
        dom(-2.0, -1.5, 2.0, 1.5),
        0,
        1,
        "F[4]{O4 b3 b3 b3 b3}",
    );
    let e = r.events.iter().find(|e| e.critical).unwrap();
    assert_eq!(
        (e.k, e.generic, e.real_multiple_roots),
        (Some(3), Some(false), Some(1))
    );
    assert_eq!(e.branches, Some((2, 2)));
    assert_eq!(e.label, Some(Label::Singular));
}

// ---- Property tests of the exact primitives, against independent references. ----

/// Determinant of a rational matrix by Gaussian elimination (independent of the
/// library's fraction-free Bareiss over Z[x]).
fn det_q(mut m: Vec<Vec<BigRational>>) -> BigRational {
    let n = m.len();
    let mut det = BigRational::one();
    for k in 0..n {
        let Some(p) = (k..n).find(|&r| !m[r][k].is_zero()) else {
            return BigRational::zero();
        };
        if p != k {
            m.swap(p, k);
            det = -det;
        }
        det *= m[k][k].clone();
        for i in k + 1..n {
            let t = &m[i][k] / &m[k][k];
            for j in k..n {
                let v = &m[k][j] * &t;
                m[i][j] -= v;
            }
        }
    }
    det
}

/// det_{j,i} of two univariate rational polynomials from the Sylvester submatrix
/// (rows yᵏ·P, yᵏ·Q; columns y^(p+q−j−1) … y^(j+1) and yⁱ).
fn sub_coef_q(p: &[BigRational], q: &[BigRational], j: usize, i: usize) -> BigRational {
    let (dp, dq) = (p.len() - 1, q.len() - 1);
    let mut rows: Vec<(&[BigRational], usize)> = Vec::new();
    for r in 0..dq - j {
        rows.push((p, dq - j - 1 - r));
    }
    for r in 0..dp - j {
        rows.push((q, dp - j - 1 - r));
    }
    let mut cols: Vec<usize> = (j + 1..dp + dq - j).rev().collect();
    cols.push(i);
    let m = rows
        .iter()
        .map(|(poly, sh)| {
            cols.iter()
                .map(|&c| {
                    if c >= *sh && c - sh < poly.len() {
                        poly[c - sh].clone()
                    } else {
                        BigRational::zero()
                    }
                })
                .collect()
        })
        .collect();
    det_q(m)
}

fn bipoly_strategy(dy: usize, dx: usize) -> impl Strategy<Value = BiPoly> {
    proptest::collection::vec(proptest::collection::vec(-6i64..=6, dx + 1), dy + 1).prop_map(
        move |rows| {
            let mut c: Vec<UPoly> = rows.iter().map(|r| UPoly::from_i64(r)).collect();
            // A non-zero constant leading coefficient in y.
            c[dy] = UPoly::from_i64(&[if rows[dy][0] == 0 { 1 } else { rows[dy][0] }]);
            BiPoly::new(c)
        },
    )
}

fn upoly_strategy() -> impl Strategy<Value = UPoly> {
    proptest::collection::vec(-8i64..=8, 2..8).prop_map(|mut v| {
        let n = v.len() - 1;
        if v[n] == 0 {
            v[n] = 1;
        }
        UPoly::from_i64(&v)
    })
}

fn spec(p: &BiPoly, x: &BigRational) -> Vec<BigRational> {
    p.c.iter().map(|c| c.eval_q(x)).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Every subresultant coefficient det_{j,i}(P, Q) over Z[x], specialised at x0,
    /// equals the Sylvester-submatrix determinant of the specialised polynomials
    /// computed by rational Gaussian elimination: the subresultants are the
    /// determinants, and specialisation commutes (lc_y constant).
    #[test]
    fn subresultants_are_sylvester_determinants(p in bipoly_strategy(4, 2), x0 in -3i64..=3) {
        let qy = p.dy();
        let x = q(x0, 1);
        let (ps, qs) = (spec(&p, &x), spec(&qy, &x));
        for j in 0..qy.deg_y() as usize {
            for i in 0..=j {
                let a = subres::sub_coef(&p, &qy, j, i).eval_q(&x);
                prop_assert_eq!(a, sub_coef_q(&ps, &qs, j, i), "j = {}, i = {}", j, i);
            }
        }
    }

    /// Ducos' subresultant chain over Z[x], specialised at x0, equals the
    /// Sylvester-submatrix determinants of the specialised polynomials (rational
    /// Gaussian elimination), coefficient by coefficient, for (P, P_y), for P with an
    /// unrelated Q of degree deg P − 1, and for a non-constant leading coefficient
    /// (defective chains included).
    #[test]
    fn ducos_chain_is_sylvester_determinants(p in bipoly_strategy(5, 2), r in bipoly_strategy(3, 2), x0 in -3i64..=3) {
        let x = q(x0, 1);
        // P/y (degree 4, a constant leading coefficient) against an unrelated cubic.
        let p4 = BiPoly::new(p.c[1..].to_vec());
        // A leading coefficient x² − 1 that vanishes at some x0 (the formal degrees
        // keep the determinants polynomial in the coefficients).
        let mut c5 = p.c.clone();
        c5[5] = c5[5].mul(&UPoly::from_i64(&[-1, 0, 1]));
        let p5 = BiPoly::new(c5);
        for (a, b) in [(p.clone(), p.dy()), (p4, r), (p5.clone(), p5.dy())] {
            let (ps, qs) = (spec(&a, &x), spec(&b, &x));
            let ch = subres::chain(&a, &b);
            prop_assert_eq!(ch.len(), b.deg_y() as usize + 1);
            for j in 0..b.deg_y() as usize {
                for i in 0..=j {
                    let got = ch[j].c.get(i).map_or(BigRational::zero(), |c| c.eval_q(&x));
                    prop_assert_eq!(got, sub_coef_q(&ps, &qs, j, i), "j = {}, i = {}", j, i);
                }
                prop_assert!(ch[j].deg_y() <= j as isize);
            }
        }
    }

    /// Specialisation commutes with the resultant, and the first non-vanishing
    /// principal subresultant at x0 has the index of the degree of the gcd.
    #[test]
    fn resultant_specialises_and_gcd_degree(p in bipoly_strategy(3, 2), r in bipoly_strategy(2, 2), x0 in -3i64..=3) {
        let x = q(x0, 1);
        let res = subres::resultant(&p, &r).eval_q(&x);
        prop_assert_eq!(res, sub_coef_q(&spec(&p, &x), &spec(&r, &x), 0, 0));
        let a = p.at_x(&x);
        let b = r.at_x(&x);
        let g = a.gcd(&b);
        let pr = subres::principal(&p, &r);
        let k = (0..pr.len()).find(|&j| !pr[j].eval_q(&x).is_zero()).unwrap();
        prop_assert_eq!(k as isize, g.deg());
    }

    /// Root isolation: the count equals the Sturm count; intervals are sorted,
    /// disjoint, each holds exactly one root (Sturm) with a sign change at its ends.
    #[test]
    fn isolation_matches_sturm(p in upoly_strategy()) {
        let roots = isolate(&p).unwrap();
        let b = q(1 << 20, 1);
        prop_assert_eq!(roots.len(), sturm_count(&p, &-b.clone(), &b));
        let sq = p.squarefree();
        for (i, r) in roots.iter().enumerate() {
            if r.is_exact() {
                prop_assert_eq!(p.sign_at(&r.lo), 0);
            } else {
                prop_assert!(r.p.sign_at(&r.lo) * r.p.sign_at(&r.hi) < 0);
                prop_assert_eq!(sturm_count(&sq, &r.lo, &r.hi) - usize::from(sq.sign_at(&r.hi) == 0), 1);
            }
            if i > 0 {
                prop_assert!(roots[i - 1].hi <= r.lo);
                prop_assert!(!(roots[i - 1].is_exact() && r.is_exact() && roots[i - 1].lo == r.lo));
            }
        }
    }

    /// The Sturm–Habicht count (signed principal subresultants of f and f_y,
    /// permanences minus variations) equals the Sturm count of distinct real roots.
    #[test]
    fn sturm_habicht_count_matches_sturm(p in bipoly_strategy(5, 1), x0 in -3i64..=3) {
        let x = q(x0, 1);
        let d = p.deg_y() as usize;
        let pr = subres::principal(&p, &p.dy());
        let signs: Vec<i32> = pr.iter().map(|s| certmesh::algebraic::upoly::sign(&s.eval_hom(x.numer(), x.denom()))).collect();
        let lc = certmesh::algebraic::upoly::sign(&p.lc_y().coef(0));
        let n = subres::distinct_real_roots(d, lc, &signs);
        let b = q(1 << 30, 1);
        prop_assert_eq!(n as usize, sturm_count(&p.at_x(&x), &-b.clone(), &b));
    }

    /// The f64 filter encloses: integer coefficients up to ~190 bits and rational
    /// points and intervals convert to enclosing intervals, and interval Horner over
    /// them holds the exact value at every rational of the interval tried.
    #[test]
    fn f64_filter_encloses_exact_values(c in proptest::collection::vec((-1000i64..=1000, 0u32..190), 1..9), a in -2000i64..2000, b in 1i64..3000, w in 0i64..50) {
        use certmesh::algebraic::fint;
        let p = UPoly::new(c.iter().map(|&(m, sh)| num_bigint::BigInt::from(m) << sh as usize).collect());
        prop_assume!(!p.is_zero());
        let (lo, hi) = (q(a, b), q(a + w, b));
        let Some(cf) = fint::poly_iv(&p) else { return Ok(()); };
        let Some(x) = fint::qq_iv(&lo, &hi) else { return Ok(()); };
        let e = fint::horner(&cf, x);
        for t in [lo.clone(), hi.clone(), (&lo + &hi) / q(2, 1)] {
            let v = p.eval_q(&t);
            let inside = BigRational::from_float(e.inf()).is_none_or(|l| l <= v)
                && BigRational::from_float(e.sup()).is_none_or(|h| v <= h);
            prop_assert!(inside, "p({}) = {} outside [{}, {}]", t, v, e.inf(), e.sup());
        }
    }

    /// Refinement (quadratic interval refinement with bisection fallback) keeps an
    /// isolating interval: inside the old one, at most the asked width, a strict sign
    /// change of the square-free polynomial (or an exact root), one root inside (Sturm).
    #[test]
    fn refinement_keeps_isolating_intervals(p in upoly_strategy(), bits in 1i64..200) {
        let sq = p.squarefree();
        let w = BigRational::new(1.into(), num_bigint::BigInt::from(1) << bits as usize);
        for r in isolate(&p).unwrap() {
            let mut a = r.clone();
            a.refine_to(&w);
            prop_assert!(a.lo >= r.lo && a.hi <= r.hi && &a.hi - &a.lo <= w);
            if a.is_exact() {
                prop_assert_eq!(p.sign_at(&a.lo), 0);
            } else {
                prop_assert!(a.p.sign_at(&a.lo) * a.p.sign_at(&a.hi) < 0);
                prop_assert_eq!(sturm_count(&sq, &a.lo, &a.hi), 1);
            }
        }
    }

    /// Real algebraic numbers: the sign of q at a root agrees with the sign of q at a
    /// rational point of a tiny isolating interval, or is 0 exactly at common roots.
    #[test]
    fn sign_at_algebraic_numbers(p in upoly_strategy(), r in upoly_strategy()) {
        for mut a in isolate(&p).unwrap() {
            let s = a.sign_of(&r).unwrap();
            let common = p.gcd(&r);
            let zero = a.is_root_of(&common);
            prop_assert_eq!(s == 0, zero);
            if s != 0 {
                a.refine_to(&q(1, 1 << 30));
                let (l, h) = certmesh::algebraic::algnum::eval_interval(&r, &a.lo, &a.hi);
                let by_interval = if s > 0 { l > BigRational::zero() } else { h < BigRational::zero() };
                prop_assert!(by_interval || r.sign_at(&a.mid()) == s);
            }
        }
    }
}

// ---- The certificate checker rejects tampered certificates. ----

fn certs() -> &'static Vec<certmesh::algebraic::CurveCert> {
    static C: std::sync::OnceLock<Vec<certmesh::algebraic::CurveCert>> = std::sync::OnceLock::new();
    C.get_or_init(|| {
        [
            ("x^2 + y^2 - 1", sq(2.0)),
            ("(x^2 + y^2)^2 - 2*(x^2 - y^2)", dom(-1.7, -1.0, 1.7, 1.0)),
            ("(x^2 + y^2 - 1)*((x - 1/5)^2 + y^2)", sq(3.0)),
            ("x*y - 1", sq(3.0)),
            ("(y^2 - x^2)*((y^2 + 1)^2 + x^2)", dom(-2.0, -1.5, 2.0, 1.5)),
            ("(x^2 + y^2 - x)^2 - (x^2 + y^2)/4", sq(2.0)),
        ]
        .iter()
        .map(|(f, d)| {
            let c = run(f, *d).cert;
            check_curve(&c).unwrap();
            c
        })
        .collect()
    })
}

fn bump(s: &str, by: i64) -> String {
    let v: BigRational = s.parse().unwrap();
    (v + q(by, 1)).to_string()
}

/// Apply tampering `kind` (at a position chosen by `pick`); false if it does not
/// apply to this certificate.
fn tamper(c: &mut certmesh::algebraic::CurveCert, kind: usize, pick: usize) -> bool {
    let ne = c.events.len();
    let crit: Vec<usize> = (0..ne).filter(|&i| c.events[i].critical).collect();
    let ev = |p: usize| p % ne.max(1);
    match kind {
        0 => c.shear += 1,
        1 => {
            let rows: Vec<(usize, usize)> =
                c.f.iter()
                    .enumerate()
                    .filter(|(_, r)| !r.is_empty())
                    .map(|(j, r)| (j, r.len()))
                    .collect();
            let (j, row) = rows[pick % rows.len()];
            let i = pick % row;
            c.f[j][i] = bump(&c.f[j][i], 1);
        }
        2 if ne > 0 => {
            // Move an event past itself.
            let e = &mut c.events[ev(pick)];
            let hi = e.hi.clone();
            e.lo = bump(&hi, 1);
            e.hi = bump(&hi, 2);
        }
        3 if ne > 0 => c.events[ev(pick)].critical ^= true,
        4 if !crit.is_empty() => {
            let e = &mut c.events[crit[pick % crit.len()]];
            let j = 1 + pick % (e.signs.len() - 1).max(1);
            if j >= e.signs.len() {
                return false;
            }
            e.signs[j] = if e.signs[j] == 0 { 1 } else { -e.signs[j] };
        }
        5 if !crit.is_empty() => {
            let e = &mut c.events[crit[pick % crit.len()]];
            e.k = e.k.map(|k| k + 1);
        }
        6 if ne > 0 => c.events[ev(pick)].m += 1,
        7 if !crit.is_empty() => {
            let e = &mut c.events[crit[pick % crit.len()]];
            e.generic = e.generic.map(|g| !g);
        }
        8..=12 => {
            let roots: Vec<(usize, usize)> = (0..ne)
                .flat_map(|i| (0..c.events[i].roots.len()).map(move |r| (i, r)))
                .collect();
            if roots.is_empty() {
                return false;
            }
            let (i, r) = roots[pick % roots.len()];
            let x = &mut c.events[i].roots[r];
            match kind {
                8 => {
                    if x.lo == x.hi {
                        x.lo = bump(&x.lo, -1);
                    } else {
                        std::mem::swap(&mut x.lo, &mut x.hi);
                    }
                }
                9 => x.special ^= true,
                10 => x.boundary ^= true,
                11 => x.keep ^= true,
                _ => x.left += 1,
            }
        }
        13 => {
            let b: Vec<usize> = (0..ne)
                .filter(|&i| c.events[i].branches.is_some())
                .collect();
            if b.is_empty() {
                return false;
            }
            let e = &mut c.events[b[pick % b.len()]];
            e.branches = e.branches.map(|(l, r)| (r + 1, l));
        }
        14 => {
            let b: Vec<usize> = (0..ne).filter(|&i| c.events[i].label.is_some()).collect();
            if b.is_empty() {
                return false;
            }
            let e = &mut c.events[b[pick % b.len()]];
            e.label = Some(if e.label == Some(Label::Singular) {
                Label::Isolated
            } else {
                Label::Singular
            });
        }
        15 if !c.fibres.is_empty() => {
            // A fibre with an output vertex (moving one without is a valid certificate).
            let fs: Vec<usize> = (0..c.fibres.len())
                .filter(|&i| c.fibres[i].inside.contains(&true))
                .collect();
            if fs.is_empty() {
                return false;
            }
            let f = &mut c.fibres[fs[pick % fs.len()]];
            let v: BigRational = f.q.parse().unwrap();
            f.q = (v + q(1, 1000)).to_string();
        }
        16 | 17 => {
            let rs: Vec<(usize, usize)> = (0..c.fibres.len())
                .flat_map(|i| (0..c.fibres[i].roots.len()).map(move |r| (i, r)))
                .collect();
            if rs.is_empty() {
                return false;
            }
            let (i, r) = rs[pick % rs.len()];
            if kind == 16 {
                let x = &mut c.fibres[i].roots[r];
                if x.lo == x.hi {
                    x.lo = bump(&x.lo, -1);
                } else {
                    std::mem::swap(&mut x.lo, &mut x.hi);
                }
            } else {
                c.fibres[i].inside[r] ^= true;
            }
        }
        18 if !c.strips.is_empty() => {
            let n = c.strips.len();
            let s = &mut c.strips[pick % n];
            s.0 = Some(s.0.map_or(0, |x| x + 1));
        }
        19 if !c.segments.is_empty() => {
            let n = c.segments.len();
            if pick % 2 == 0 {
                c.segments.remove(pick % n);
            } else {
                let s = &mut c.segments[pick % n];
                s[1] = (s[1] + 1) % c.vertices.len() as u32;
                if s[1] == s[0] {
                    s[1] = (s[1] + 1) % c.vertices.len() as u32;
                }
            }
        }
        20 if !c.vertices.is_empty() => {
            c.vertices.pop();
        }
        21 => {
            // Shrink the domain to a hundredth of its width.
            let (a, b): (BigRational, BigRational) =
                (c.domain[0].parse().unwrap(), c.domain[2].parse().unwrap());
            c.domain[2] = (&a + (b - &a) / q(100, 1)).to_string();
        }
        22 => {
            let b: Vec<usize> = (0..ne)
                .filter(|&i| !c.events[i].bpoints.is_empty())
                .collect();
            if b.is_empty() {
                return false;
            }
            c.events[b[pick % b.len()]].bpoints.pop();
        }
        23 => {
            let b: Vec<usize> = (0..ne)
                .filter(|&i| !c.events[i].excluded.is_empty())
                .collect();
            if b.is_empty() {
                return false;
            }
            let e = &mut c.events[b[pick % b.len()]];
            let n = e.excluded.len();
            e.excluded.remove(pick % n);
        }
        24 => {
            let b: Vec<usize> = (0..ne)
                .filter(|&i| !c.events[i].r_signs.is_empty())
                .collect();
            if b.is_empty() {
                return false;
            }
            let e = &mut c.events[b[pick % b.len()]];
            let n = e.r_signs.len();
            let j = pick % n;
            e.r_signs[j] = if e.r_signs[j] == 0 { 1 } else { 0 };
        }
        25 => c.format.push('x'),
        _ => return false,
    }
    true
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(160))]
    #[test]
    fn checker_rejects_tampered_certificates(ci in 0usize..6, kind in 0usize..26, pick in 0usize..10_000) {
        let mut c = certs()[ci].clone();
        prop_assume!(tamper(&mut c, kind, pick));
        prop_assert!(check_curve(&c).is_err(), "tampering {} (pick {}) on certificate {} was accepted", kind, pick, ci);
    }
}

/// A bloated certificate is refused by its size before any arithmetic. The bloat here
/// keeps every claim true: an event's isolating interval is widened by 3⁻ⁿ, which still
/// isolates its root. Within the size limit (n = 3,500: about 3,400 digits) it verifies;
/// far above it (n = 100,000: 95,000 digits, over a minute of exact arithmetic before
/// the limit) it is refused at once, naming the event and the limit. Ten thousand
/// events are refused by their count.
#[test]
fn checker_refuses_bloated_certificates_by_their_size() {
    let c0 = &certs()[1]; // the lemniscate, degree 4
    let i = c0.events.iter().position(|e| e.lo != e.hi).unwrap();
    let widen = |n: u32| {
        let mut c = c0.clone();
        let lo: BigRational = c.events[i].lo.parse().unwrap();
        let three = BigRational::from_integer(3.into());
        c.events[i].lo = (lo - num_traits::pow(three, n as usize).recip()).to_string();
        c
    };
    let ok = widen(3_500);
    assert!(ok.events[i].lo.len() > 3_300);
    check_curve(&ok).unwrap();
    let big = widen(100_000);
    let e = check_curve(&big).unwrap_err().to_string();
    assert!(
        e.contains(&format!("event {i}'s interval")) && e.contains("limit"),
        "{e}"
    );
    let mut many = c0.clone();
    let e0 = many.events[0].clone();
    many.events = vec![e0; 10_000];
    let e = check_curve(&many).unwrap_err().to_string();
    assert!(e.contains("events: 10000, above the 34"), "{e}");
    // f itself: a coefficient above the checker's bits.
    let mut wide_f = c0.clone();
    wide_f.f[0][0] = "7".repeat(3_000);
    let e = check_curve(&wide_f).unwrap_err().to_string();
    assert!(e.contains("coefficient of f") && e.contains("limit"), "{e}");
}

#[test]
fn every_tampering_kind_applies_somewhere() {
    // Guard against a tamper test that silently skips: each kind changes some certificate.
    for kind in 0..26 {
        let applied = (0..certs().len()).any(|ci| {
            let mut c = certs()[ci].clone();
            (0..20).any(|p| tamper(&mut c, kind, p))
        });
        assert!(applied, "tampering kind {kind} applies to no certificate");
    }
}

// ---- The command line and the comparison harness. ----

fn certmesh_cli(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_certmesh"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn cli_gvn_certificate_written_checked_and_tampering_rejected() {
    let dir = std::env::temp_dir().join(format!("certmesh-sweep2-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cert = dir.join("lem.json");
    let svg = dir.join("lem.svg");
    let (code, out, err) = certmesh_cli(&[
        "curve",
        "lemniscate",
        "--algo",
        "gvn",
        "--certificate",
        cert.to_str().unwrap(),
        "-o",
        svg.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("certified"), "{out}");
    let (code, out, err) = certmesh_cli(&["check-curve", cert.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains("certificate verified") && out.contains("3 critical"),
        "{out}"
    );
    // Flip one sign claim of the first critical event.
    let mut c: certmesh::algebraic::CurveCert =
        serde_json::from_str(&std::fs::read_to_string(&cert).unwrap()).unwrap();
    let e = c.events.iter_mut().find(|e| e.critical).unwrap();
    e.signs[1] = -e.signs[1];
    let bad = dir.join("bad.json");
    std::fs::write(&bad, serde_json::to_string(&c).unwrap()).unwrap();
    let (code, _, err) = certmesh_cli(&["check-curve", bad.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("rejected") && err.contains("sign"), "{err}");
    // Not JSON: an input error (exit 2); a certificate asked of a non-exact mesher too.
    std::fs::write(&bad, "{").unwrap();
    assert_eq!(certmesh_cli(&["check-curve", bad.to_str().unwrap()]).0, 2);
    let (code, _, err) = certmesh_cli(&[
        "curve",
        "circle",
        "--algo",
        "pv",
        "--certificate",
        cert.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--certificate"), "{err}");
    // A non-polynomial formula: a clear error naming the term.
    let (code, _, err) =
        certmesh_cli(&["curve", "--formula", "sqrt(x^2 + y^2) - 1", "--algo", "gvn"]);
    assert_ne!(code, 0);
    assert!(
        err.contains("sqrt(") && err.contains("not a polynomial"),
        "{err}"
    );
    // Budgets beyond what the checker accepts: refused, naming the range.
    for (set, range) in [("max-degree=40", "1..=16"), ("max-bits=100000", "1..=8192")] {
        let (code, _, err) = certmesh_cli(&["curve", "circle", "--algo", "gvn", "--set", set]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(range), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `check-curve` says what it verified: the certificate's polynomial (integer
/// coefficients: 2x^2 + 8y^2 - 2 is 2(x^2 + 4y^2 - 1) with the denominators cleared)
/// and its domain, in the text (floats given as their shortest digits) and in --json
/// (the exact rationals).
#[test]
fn check_curve_names_the_polynomial_and_domain_it_verified() {
    let dir = std::env::temp_dir().join(format!("certmesh-checkpd-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cert = dir.join("ell.json");
    let (code, out, err) = certmesh_cli(&[
        "curve",
        "--formula",
        "x^2 + 4*y^2 - 1",
        "--domain=-1.5,-0.7,1.5,0.7",
        "--algo",
        "gvn",
        "--certificate",
        cert.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let c: certmesh::algebraic::CurveCert =
        serde_json::from_str(&std::fs::read_to_string(&cert).unwrap()).unwrap();
    // The polynomial as the certificate stores it, read back from its coefficients:
    // f[j][i] is the coefficient of x^i y^j.
    let coef = |i: usize, j: usize| -> i64 {
        c.f.get(j)
            .and_then(|r| r.get(i))
            .map_or(0, |a| a.parse().unwrap())
    };
    let (a, b, k) = (coef(2, 0), coef(0, 2), coef(0, 0));
    assert!(a > 0 && b == 4 * a && k == -a, "{:?}", c.f);
    let expected = if a == 1 {
        "x^2 + 4*y^2 - 1".to_string()
    } else {
        format!("{a}*x^2 + {b}*y^2 - {a}")
    };
    let (code, out, err) = certmesh_cli(&["check-curve", cert.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains(&format!("f(x, y) = {expected} = 0"))
            && out.contains("[-1.5, 1.5] × [-0.7, 0.7]")
            && out.contains("certificate verified"),
        "{out}"
    );
    let (code, out, err) = certmesh_cli(&["check-curve", cert.to_str().unwrap(), "--json"]);
    assert_eq!(code, 0, "{out}{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["polynomial"], expected.as_str(), "{out}");
    let bounds: Vec<f64> = v["domain"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            let t = t.as_str().unwrap();
            match t.split_once('/') {
                Some((n, d)) => n.parse::<f64>().unwrap() / d.parse::<f64>().unwrap(),
                None => t.parse().unwrap(),
            }
        })
        .collect();
    assert_eq!(bounds, [-1.5, -0.7, 1.5, 0.7], "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn compare_uses_signatures_for_curves() {
    use certmesh::harness::compare;
    let es = vec![
        certmesh::catalog::get("lemniscate").unwrap(),
        certmesh::catalog::get("circle").unwrap(),
    ];
    let algos = vec!["sweep".to_string(), "ms".to_string()];
    let rows = compare::compare(
        &es,
        &algos,
        &Default::default(),
        &certmesh::mesher::NoProgress,
    );
    let get = |c: &str, a: &str| rows.iter().find(|r| r.surface == c && r.algo == a).unwrap();
    let lem = get("lemniscate", "sweep");
    assert_eq!(lem.signature.as_deref(), Some("C[4]{O2 b1 b1}"));
    assert_eq!(lem.isotopy_agrees, Some(true));
    assert_eq!(
        get("circle", "sweep").signature.as_deref(),
        Some("C[]{O1 b1}")
    );
    // Marching squares is uncertified: it is judged against the sweep's signature.
    let ms = get("circle", "ms");
    assert_eq!(
        ms.isotopy_agrees,
        Some(ms.signature.as_deref() == Some("C[]{O1 b1}"))
    );
    let md = compare::signatures_markdown(&rows);
    assert!(md.contains("`C[4]{O2 b1 b1}`"), "{md}");
}

#[test]
fn sweep_figures_draw_fibres_events_and_arcs() {
    let dir = std::env::var("CERTMESH_FIG_OUT")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|_| {
            std::env::temp_dir().join(format!("certmesh-sweep2-fig-{}", std::process::id()))
        });
    std::fs::create_dir_all(&dir).unwrap();
    certmesh::reproduce::meshing_of_surfaces::sweep_figures(&dir).unwrap();
    let svg = std::fs::read_to_string(dir.join("fig-gvn-lemniscate.svg")).unwrap();
    // Inside the plot (the legend repeats each style once): three critical fibres
    // (vermillion), the dotted rational fibres, and one node (a vermillion disc).
    let plot = &svg[svg.find("<g clip-path").expect("the plot group")..];
    let plot = &plot[..plot.find("</g>").expect("its end")];
    assert_eq!(plot.matches(r##"stroke="#d55e00""##).count(), 3, "{svg}");
    assert!(plot.contains("stroke-dasharray"));
    assert_eq!(plot.matches(r##"fill="#d55e00""##).count(), 1);
    // and the legend names them
    assert!(svg.contains("critical event fibre"));
    if std::env::var("CERTMESH_FIG_OUT").is_err() {
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// The one-sided distance from the curve f = 0 (inside the domain) to the output
/// polyline, sampled densely: the real roots of f(x, ·) on 1500 vertical lines (exact
/// isolation refined to 2^-44), each point's distance to the nearest segment.
fn sampled_deviation(f: &str, d: &Aabb, c: &certmesh::mesh::Curve2) -> f64 {
    let p = from_formula(f).unwrap();
    let seg_dist = |pt: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let dd = dx * dx + dy * dy;
        let t = if dd == 0.0 {
            0.0
        } else {
            (((pt[0] - a[0]) * dx + (pt[1] - a[1]) * dy) / dd).clamp(0.0, 1.0)
        };
        ((pt[0] - a[0] - t * dx).powi(2) + (pt[1] - a[1] - t * dy).powi(2)).sqrt()
    };
    let fine = BigRational::new(1.into(), num_bigint::BigInt::from(1u64 << 44));
    let mut worst = 0.0f64;
    let n = 1500;
    for t in 0..n {
        let x = d.min[0] + (d.max[0] - d.min[0]) * (t as f64 + 0.5) / n as f64;
        let xq = BigRational::from_float(x).unwrap();
        let fx = p.at_x(&xq);
        if fx.is_zero() {
            continue;
        }
        for mut r in isolate(&fx).unwrap() {
            r.refine_to(&fine);
            let y = r.to_f64();
            if y <= d.min[1] || y >= d.max[1] {
                continue;
            }
            let pt = [x, y];
            let dist = c
                .segments
                .iter()
                .map(|s| seg_dist(pt, c.vertices[s[0] as usize], c.vertices[s[1] as usize]))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(dist);
        }
    }
    worst
}

/// `--set tolerance`: on curves with x-extremes, a node, a cusp, clipped unbounded
/// branches and a shear, the certified bound is ≤ the tolerance, every arc reaches it,
/// the densely sampled deviation of the refined polyline is ≤ the certified bound, the
/// topology (embedding signature) is the sweep's, and the sweep's own polyline
/// deviates by more than the tolerance (so the extra fibres did the work: without them
/// the sampled deviation assertion fails).
#[test]
fn extra_fibres_bound_the_deviation() {
    let t = 1e-2;
    let cases = [
        ("x^2 + y^2 - 1", dom(-2.0, -2.0, 2.0, 2.0)),
        ("(x^2 + y^2)^2 - 2*(x^2 - y^2)", dom(-2.0, -2.0, 2.0, 2.0)),
        ("y^2 - x^3", dom(-2.0, -2.0, 2.0, 2.0)),
        ("y - x^2", dom(-2.0, -2.0, 2.0, 2.0)),
        ("x*y - 1", dom(-3.0, -3.0, 3.0, 3.0)),
        (
            "(x^2 + y^2 - x)^2 - (x^2 + y^2)/4",
            dom(-2.0, -2.0, 2.0, 2.0),
        ),
    ];
    for (f, d) in cases {
        let coarse = run(f, d);
        let p = from_formula(f).unwrap();
        let params = SweepParams {
            tolerance: Some(t),
            ..SweepParams::default()
        };
        let r = analyse(&p, &d, &params).unwrap_or_else(|e| panic!("{f}: {e}"));
        let rep = r.tolerance.clone().expect("a tolerance report");
        assert!(rep.extra_fibres > 0, "{f}: no extra fibre");
        assert!(
            rep.not_reached.is_empty(),
            "{f}: not reached {:?}",
            rep.not_reached
        );
        assert_eq!(rep.arcs, rep.arcs_within_tolerance);
        assert!(
            rep.certified_bound <= t,
            "{f}: bound {}",
            rep.certified_bound
        );
        // The certificate is the sweep's, and still checks.
        assert_eq!(
            serde_json::to_string(&r.cert).unwrap(),
            serde_json::to_string(&coarse.cert).unwrap(),
            "{f}: certificate changed"
        );
        check_curve(&r.cert).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert_eq!(
            embedding_signature(&r.curve, Some(&d)).unwrap(),
            embedding_signature(&coarse.curve, Some(&d)).unwrap(),
            "{f}: topology changed"
        );
        let dev = sampled_deviation(f, &d, &r.curve);
        assert!(
            dev <= rep.certified_bound + 1e-9,
            "{f}: sampled deviation {dev} above the certified bound {}",
            rep.certified_bound
        );
        let dev0 = sampled_deviation(f, &d, &coarse.curve);
        assert!(
            dev0 > t,
            "{f}: the sweep's polyline already within {t} ({dev0})"
        );
    }
}

/// Where the budget is too small the tolerance is not claimed: with two extra fibres
/// the circle's arcs are reported not reached, and the bound reported for them (when
/// any) is still ≥ the sampled deviation.
#[test]
fn extra_fibres_report_where_the_tolerance_is_not_reached() {
    let (f, d) = ("x^2 + y^2 - 1", dom(-2.0, -2.0, 2.0, 2.0));
    let p = from_formula(f).unwrap();
    let params = SweepParams {
        tolerance: Some(1e-3),
        max_extra_fibres: 2,
        ..SweepParams::default()
    };
    let r = analyse(&p, &d, &params).unwrap();
    let rep = r.tolerance.clone().unwrap();
    assert!(rep.extra_fibres <= 2);
    assert_eq!(rep.arcs, 2);
    assert_eq!(rep.not_reached.len(), 2, "{rep:?}");
    assert_eq!(rep.arcs_within_tolerance, 0);
    // A bound reported for an arc not reached is still certified: the largest one
    // bounds the sampled deviation of the whole curve (both arcs).
    let bounds: Vec<f64> = rep.not_reached.iter().filter_map(|m| m.bound).collect();
    if bounds.len() == 2 {
        let dev = sampled_deviation(f, &d, &r.curve);
        let b = bounds.iter().cloned().fold(0.0, f64::max);
        assert!(
            b >= dev - 1e-9,
            "bound {b} below the sampled deviation {dev}"
        );
        assert!(b > 1e-3);
    }
}

// ---- Roots on the vertical sides next to exact rational roots. ----

/// f at an output vertex, exactly (its f64 coordinates as rationals).
fn f_at(p: &BiPoly, v: [f64; 2]) -> BigRational {
    let x = BigRational::from_float(v[0]).unwrap();
    let y = BigRational::from_float(v[1]).unwrap();
    spec(p, &x)
        .iter()
        .rev()
        .fold(BigRational::zero(), |acc, c| acc * &y + c)
}

/// Independent check of the vertices on the vertical sides (shear 0): on each side
/// x = c, as many vertices as f(c, ·) has distinct roots in (ymin, ymax) (Sturm), all
/// labelled Boundary, each within 1e-9 of a root (a Sturm count on a small interval
/// around it).
fn check_side_vertices(f: &str, d: Aabb, r: &SweepResult) -> Result<(), String> {
    if r.shear != 0 {
        return Ok(());
    }
    let p = from_formula(f).unwrap();
    let (ylo, yhi) = (
        BigRational::from_float(d.min[1]).unwrap(),
        BigRational::from_float(d.max[1]).unwrap(),
    );
    for x in [d.min[0], d.max[0]] {
        let px = p.at_x(&BigRational::from_float(x).unwrap());
        let want = sturm_count(&px, &ylo, &yhi) - usize::from(px.eval_q(&yhi).is_zero());
        let on: Vec<usize> = (0..r.curve.vertices.len())
            .filter(|&i| r.curve.vertices[i][0] == x)
            .collect();
        if on.len() != want {
            return Err(format!(
                "{f}: side x = {x}: {} vertices {:?}, f(x, ·) has {want} roots in ({}, {})",
                on.len(),
                on.iter().map(|&i| r.curve.vertices[i]).collect::<Vec<_>>(),
                d.min[1],
                d.max[1]
            ));
        }
        for &i in &on {
            let y = r.curve.vertices[i][1];
            let eps = 1e-9 * (1.0 + y.abs());
            let (a, b) = (
                BigRational::from_float(y - eps).unwrap(),
                BigRational::from_float(y + eps).unwrap(),
            );
            if r.labels[i] != Label::Boundary || sturm_count(&px, &a, &b) == 0 {
                return Err(format!(
                    "{f}: side vertex ({x}, {y}) ({:?}) is not on the curve: f = {}",
                    r.labels[i],
                    f_at(&p, r.curve.vertices[i])
                ));
            }
        }
    }
    Ok(())
}

/// A root on a vertical side whose isolating interval starts at an exact root of the
/// side's fibre (0, or a Descartes midpoint): the side branch rebuilt the number with
/// the fibre's full square-free polynomial, p(lo) = 0, and the comparisons with ymin
/// and ymax moved the interval onto lo. y(y − 3) on [−1, 1]² kept (±1, 0.5), off the
/// curve, as isolated points and certified it (its own checker rejected the
/// certificate); y(2y − 1) on [−1, 1] × [1/4, 1] called the side roots y = 1/2 outside
/// ("an arc inside the domain ends at a point outside"). Now: one arc from side to
/// side, every vertex on the curve, the certificates checked.
#[test]
fn side_roots_next_to_exact_roots() {
    for (f, d, y) in [
        ("y*(y-3)", sq(1.0), 0.0),
        ("(y-2)*(y-3)", dom(-1.0, -1.0, 1.0, 2.5), 2.0),
        ("y*(2*y-1)", dom(-1.0, 0.25, 1.0, 1.0), 0.5),
        ("y*(y+3)", sq(1.0), 0.0),
    ] {
        let r = table(f, d, 0, 0, "F[]{O2 b2 b2}");
        assert!(r.labels.iter().all(|&l| l != Label::Isolated), "{f}");
        assert_eq!(
            topo(&r),
            Topo {
                components: 1,
                cycles: 0,
                special_degrees: vec![],
                boundary: 2
            },
            "{f}"
        );
        // Three vertices (two sides, one sample) on the line y = c, exactly.
        assert_eq!(r.curve.vertices.len(), 3, "{f}: {:?}", r.curve.vertices);
        let p = from_formula(f).unwrap();
        for v in &r.curve.vertices {
            assert_eq!(v[1], y, "{f}: {:?}", r.curve.vertices);
            assert!(f_at(&p, *v).is_zero(), "{f}: {v:?}");
        }
        check_side_vertices(f, d, &r).unwrap();
    }
    // Degree 6: the side x = −1.7 has the exact root 0 and an interval (0, …) above
    // it; (−1.7, 1.05) was kept, f = −0.79…
    let f = "y^4*(y^2-2) + x*y + 3*x^3*y + x^3*y^2";
    let d = dom(-1.7, -1.9, 1.3, 2.1);
    let r = run(f, d);
    check_curve(&r.cert).unwrap_or_else(|e| panic!("{f}: {e}"));
    check_crossings(f, d, &r);
    check_side_vertices(f, d, &r).unwrap();
    assert!(r.labels.iter().all(|&l| l != Label::Isolated), "{f}");
    // The vertices on the rational fibres (roots refined to 2^-40) and on the sides are
    // on the curve; those of the irrational event fibres sit at the middle of their
    // certified boxes (topology only: (-1.5957.., -0.0577..) for the root y = 0).
    let p = from_formula(f).unwrap();
    let xs: Vec<f64> = [d.min[0], d.max[0]]
        .into_iter()
        .chain(r.cert.fibres.iter().map(|fb| {
            let q: BigRational = fb.q.parse().unwrap();
            q.to_f64().unwrap()
        }))
        .collect();
    let on_fibres: Vec<usize> = (0..r.curve.vertices.len())
        .filter(|&i| xs.contains(&r.curve.vertices[i][0]))
        .collect();
    assert!(on_fibres.len() >= 15, "{f}: {on_fibres:?}");
    for &i in &on_fibres {
        let v = &r.curve.vertices[i];
        let e = f_at(&p, *v).to_f64().unwrap();
        assert!(
            e.abs() < 1e-6,
            "{f}: vertex {i} {v:?} ({:?}): f = {e}",
            r.labels[i]
        );
    }
}

/// The checker names a side event's failure as an event, not as a rational fibre.
#[test]
fn checker_names_a_side_event_failure_as_an_event() {
    let mut c = run("y*(y-3)", sq(1.0)).cert;
    check_curve(&c).unwrap();
    let i = c.events.iter().position(|e| e.side).unwrap();
    let j = c.events[i].roots.iter().position(|r| r.lo != r.hi).unwrap();
    // (0, 1) holds no root of y(y − 3): the interval the side branch used to write.
    c.events[i].roots[j].lo = "0".into();
    c.events[i].roots[j].hi = "1".into();
    let e = check_curve(&c).unwrap_err().to_string();
    assert!(
        e.contains(&format!("event {i}: interval {j} does not isolate a root")),
        "{e}"
    );
}

/// Curves (y − a)(y − b)·h with exact rational roots a, b on every fibre, the vertical
/// sides included, at 0 or at small dyadics (Descartes midpoints), and h monic in y
/// (shear 0), on domains whose horizontal sides lie next to them: every certificate
/// the sweep writes passes its checker, the side vertices are the side roots inside
/// the domain (each on the curve), the arcs cross vertical lines as often as f = 0 does,
/// and a refusal is never an internal error.
fn exact_root_curve() -> impl Strategy<Value = (String, Aabb)> {
    let quarter = || (-8i64..=8).prop_map(|k| k as f64 / 4.0);
    (
        quarter(),
        quarter(),
        0usize..=2,
        proptest::collection::vec(-3i64..=3, 6),
        (-6i64..=6, 1i64..=8),
        prop_oneof![Just(1.0), Just(0.75), Just(1.25), Just(2.0)],
    )
        .prop_filter("two distinct exact roots", |(a, b, ..)| a != b)
        .prop_map(|(a, b, dh, c, (y0, h), x1)| {
            // h = y^dh + (c0 + c1 x + c2 x²) y^(dh−1) + (c3 + c4 x + c5 x²) y^(dh−2).
            let mut hs = format!("y^{dh}");
            if dh >= 1 {
                hs += &format!(" + ({} + {}*x + {}*x^2)*y^{}", c[0], c[1], c[2], dh - 1);
            }
            if dh >= 2 {
                hs += &format!(" + ({} + {}*x + {}*x^2)", c[3], c[4], c[5]);
            }
            let f = format!("(y - ({a}))*(y - ({b}))*({hs})");
            // ymin and ymax on a grid of eighths: at, next to or away from a and b.
            let ymin = y0 as f64 / 8.0 * 2.0 - 0.125;
            let ymax = ymin + h as f64 / 4.0;
            (f, dom(-x1, ymin, x1, ymax))
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]
    #[test]
    fn side_roots_of_curves_with_exact_roots((f, d) in exact_root_curve()) {
        let p = from_formula(&f).unwrap();
        match analyse(&p, &d, &SweepParams::default()) {
            Err(e) => {
                let m = e.to_string();
                prop_assert!(!m.contains("internal"), "{} on {:?}: {}", f, d, m);
            }
            Ok(r) => {
                let chk = check_curve(&r.cert);
                prop_assert!(chk.is_ok(), "{} on {:?}: certificate rejected: {}", f, d, chk.unwrap_err());
                let side = check_side_vertices(&f, d, &r);
                prop_assert!(side.is_ok(), "{}", side.unwrap_err());
                if r.shear == 0 {
                    check_crossings(&f, d, &r);
                }
            }
        }
    }
}
