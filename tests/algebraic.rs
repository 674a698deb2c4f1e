//! The exact algebraic machinery and the González-Vega–Necula sweep: property tests of
//! every exact primitive against independent references (Sturm counts, floating-point
//! roots, Sylvester determinants by cofactor expansion), and the sweep on curves with
//! known topology, checked against an independent count of crossings along dense
//! vertical lines (exact Sturm root counts).
use certmesh::algebraic::algnum::{isolate, RealAlg};
use certmesh::algebraic::bipoly::{from_formula, BiPoly};
use certmesh::algebraic::subres;
use certmesh::algebraic::check::check_curve;
use certmesh::algebraic::sweep::{analyse, Label, SweepParams, SweepResult};
use certmesh::metrics::embedding_signature;
use certmesh::algebraic::upoly::{q, sturm_count, UPoly};
use certmesh::Aabb;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};
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
        (BigRational::from_float(d.min[1]).unwrap(), BigRational::from_float(d.max[1]).unwrap())
    } else {
        (q(-1_000_000, 1), q(1_000_000, 1))
    };
    let uv: Vec<[f64; 2]> = r.curve.vertices.iter().map(|v| [v[0] - s * v[1], v[1]]).collect();
    let (umin, umax) = uv.iter().fold((f64::MAX, f64::MIN), |a, v| (a.0.min(v[0]), a.1.max(v[0])));
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

fn case(f: &str, d: Aabb, shear: i64, comps: usize, cycles: usize, degs: &[usize]) -> SweepResult {
    let r = run(f, d);
    let t = topo(&r);
    assert_eq!(r.shear, shear, "{f}: shear {:?}", r.rejected_shears);
    assert_eq!(
        (t.components, t.cycles, t.special_degrees.as_slice()),
        (comps, cycles, degs),
        "{f}: {t:?} events {:?}",
        r.events
    );
    check_crossings(f, d, &r);
    r
}


/// One curve of the design note's table: the shear chosen, the number of critical
/// events (real roots of the discriminant in the domain), the embedding signature
/// (components, degrees ≠ 2, faces with dual degrees, nesting; clipped curves closed
/// by the domain frame), the certificate re-checked (also after a JSON round trip),
/// and, for compact curves or shear 0, crossings along vertical lines against exact
/// Sturm counts.
fn table(f: &str, d: Aabb, shear: i64, events: usize, signature: &str) -> SweepResult {
    let r = run(f, d);
    assert_eq!(r.shear, shear, "{f}: shear (rejected {:?})", r.rejected_shears);
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
    // A singular vertex has degree a_L + a_R.
    let t = topo(&r);
    let _ = t;
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
    let node: Vec<_> = r.events.iter().filter(|e| e.label == Some(Label::Singular)).collect();
    assert_eq!(node.len(), 1);
    assert_eq!(node[0].branches, Some((2, 2)));
    assert_eq!(node[0].multiplicity, Some(2));
}

#[test]
fn table_lemniscate_rotated() {
    let r = table("(x^2 + y^2)^2 - 2*(y^2 - x^2)", sq(2.0), 1, 3, "C[4]{O2 b1 b1}");
    let node = r.events.iter().find(|e| e.label == Some(Label::Singular)).unwrap();
    assert_eq!(node.branches, Some((2, 2)));
}

#[test]
fn table_limacon() {
    let r = table("(x^2 + y^2 - x)^2 - (x^2 + y^2)/4", sq(2.0), 1, 5, "C[4]{O1 b1 b2}");
    assert_eq!(r.events.iter().filter(|e| e.label == Some(Label::Singular)).count(), 1);
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
    let r = table("y^2 - x^2*(x - 1)", dom(-2.0, -3.0, 3.0, 3.0), 0, 2, "F[]{O2 b2 b2[C[0]{}]}");
    assert_eq!(r.labels.iter().filter(|&&l| l == Label::Isolated).count(), 1);
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
    assert_eq!(r.events.iter().find(|e| e.critical).unwrap().multiplicity, Some(2));
}

#[test]
fn table_ramphoid_cusp() {
    let r = table("(y - x^2)^2 - x^5", dom(-1.0, -3.0, 1.5, 8.0), 0, 1, "F[]{O2 b2 b2}");
    assert_eq!(branches(&r), vec![(0, 2)]);
}

#[test]
fn table_trifolium() {
    let r = table("(x^2 + y^2)^2 - (x^3 - 3*x*y^2)", sq(2.0), 1, 5, "C[6]{O3 b1 b1 b1}");
    assert!(branches(&r).contains(&(3, 3)));
}

#[test]
fn table_quadrifolium() {
    let r = table("(x^2 + y^2)^3 - 4*x^2*y^2", sq(2.0), 2, 7, "C[8]{O4 b1 b1 b1 b1}");
    assert!(branches(&r).contains(&(4, 4)));
}

#[test]
fn table_nested_circles() {
    table("(x^2 + y^2 - 1)*(x^2 + y^2 - 4)", sq(3.0), 0, 4, "C[]{O1 b1[C[]{O1 b1}]}");
}

#[test]
fn table_stacked_circles() {
    table("(x^2 + y^2 - 1)*(x^2 + (y - 3)^2 - 1)", dom(-3.0, -2.0, 3.0, 5.0), 1, 4, "C[]{O1 b1} | C[]{O1 b1}");
}

#[test]
fn table_hyperbola_clipped() {
    let r = table("x*y - 1", sq(3.0), 1, 0, "F[]{O3 b2 b2 b3}");
    assert_eq!(r.labels.iter().filter(|&&l| l == Label::Boundary).count(), 4);
}

#[test]
fn parabola_clipped() {
    // lc_y = 1: y-regular without a shear, and no critical x-value.
    let r = table("y - x^2", sq(2.0), 0, 0, "F[]{O2 b2 b2}");
    assert_eq!(r.labels.iter().filter(|&&l| l == Label::Boundary).count(), 2);
    // Shear 0: the x-parabola, y-regular as it is; its vertex is an x-extreme.
    let r = table("x - y^2 + 1", sq(2.0), 0, 1, "F[]{O2 b2 b2}");
    assert_eq!(r.events.iter().find(|e| e.critical).unwrap().label, Some(Label::XExtreme));
}

#[test]
fn table_cassini_two_ovals() {
    table("(x^2 + y^2)^2 - 2*(x^2 - y^2) - (1/16 - 1)", sq(2.0), 0, 4, "C[]{O1 b1} | C[]{O1 b1}");
}

#[test]
fn table_cassini_one_oval() {
    let e = certmesh::catalog::get("cassini-1").unwrap();
    // Two x-extremes; the waist has horizontal tangents only.
    table(e.formula, e.domain, 0, 2, "C[]{O1 b1}");
}

#[test]
fn table_devils_curve() {
    table("y^2*(y^2 - 1) - x^2*(x^2 - 2)", sq(3.0), 2, 3, "F[]{O3 b2 b2 b3[C[4]{O2 b1 b1}]}");
}

#[test]
fn table_point_inside_circle_phantom() {
    let r = table("(x^2 + y^2 - 1)*((x - 1/5)^2 + y^2)", sq(3.0), 0, 4, "C[]{O1 b1[C[0]{}]}");
    // The phantom event at 13/5: no real multiple root, nothing happens.
    let ph: Vec<_> = r.events.iter().filter(|e| e.critical && e.generic == Some(false)).collect();
    assert!(ph.iter().any(|e| e.real_multiple_roots == Some(0) && e.branches.is_none()), "{:?}", r.events);
}

#[test]
fn table_point_outside_circle_phantom() {
    table("(x^2 + y^2 - 1)*((x - 2)^2 + y^2)", sq(3.0), 0, 4, "C[0]{} | C[]{O1 b1}");
}

#[test]
fn table_t4_ellipses() {
    table("8*x^4 - 8*x^2 + 8*y^4 - 8*y^2 + 2", sq(2.0), 2, 8, "C[4,4,4,4]{O4 b2 b2 b2 b2 b4}");
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
    let r = table("x*(x^2 + y^2 - 1)", sq(2.0), 1, 0, "F[4,4]{O2 b2 b2 b3 b3}");
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
#[ignore]
fn dbg_all() {
    let p = from_formula("(x^2 + y^2 - 1)*(x^2 + y^2 - 4)").unwrap();
    for r in isolate(&p.at_x(&q(0, 1))).unwrap() {
        eprintln!("root {} {} {:?}", r.lo, r.hi, r.p);
    }
    for (f, d) in [
        ("x^2 + y^2 - 1", sq(2.0)),
        ("x^2 + y^2", sq(2.0)),
        ("x^2 + y^2 + 1", sq(2.0)),
        ("(x^2 + y^2 - 1)*(x^2 + y^2 - 4)", sq(3.0)),
        ("x*y - 1", sq(3.0)),
    ] {
        let r = run(f, d);
        eprintln!("{f}: check {:?}", check_curve(&r.cert).err().map(|e| e.to_string()));
        eprintln!("  sig {:?}", embedding_signature(&r.curve, Some(&d)));
        eprintln!("  verts {:?}\n  segs {:?}", r.curve.vertices, r.curve.segments);
    }
}
