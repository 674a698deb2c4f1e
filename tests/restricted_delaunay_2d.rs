//! Boissonnat–Oudot refinement of curves (`certmesh curve NAME --algo bo`,
//! `restricted_delaunay::curve`): outputs checked against the catalog's topology, the
//! criteria, and an independent re-computation of the restricted Delaunay edges: a
//! fresh spade triangulation of the output's vertices *without* the far points (hull
//! edges get their true dual, a ray), every dual Voronoi edge sampled densely in f64,
//! sign changes of f compared with the output's edges.
use certmesh::catalog;
use certmesh::implicit::{Implicit, PointFn};
use certmesh::kernel::geom::Aabb;
use certmesh::mesh::Curve2;
use certmesh::mesher::options::MesherOptions;
use certmesh::mesher::registry;
use certmesh::mesher::{Claim, Mesh, MeshOutput, Mesher, NoProgress};
use certmesh::metrics::topology::analyze_curve;
use certmesh::restricted_delaunay::BoissonnatOudot2;
use certmesh::Formula;
use proptest::prelude::*;
use spade::{DelaunayTriangulation, Point2, Triangulation};
use std::collections::HashSet;

fn opts(size: Option<f64>, distance: Option<f64>, max_vertices: Option<usize>) -> MesherOptions {
    MesherOptions {
        facet_size: size,
        facet_distance: distance,
        max_vertices,
        ..Default::default()
    }
}

fn run(f: &dyn Implicit, domain: &Aabb, o: &MesherOptions) -> MeshOutput {
    let m = BoissonnatOudot2::from_options(o).unwrap();
    m.mesh(f, domain, &NoProgress).unwrap()
}

fn curve(out: &MeshOutput) -> &Curve2 {
    match &out.mesh {
        Mesh::Curve(c) => c,
        _ => panic!("bo 2D must output a curve"),
    }
}

fn stat_f64(out: &MeshOutput, k: &str) -> f64 {
    out.stats[k]
        .as_f64()
        .unwrap_or_else(|| panic!("stat {k} missing"))
}

fn complete(out: &MeshOutput) -> bool {
    out.stats["refinement_complete"].as_bool().unwrap()
}

fn rd_claim(out: &MeshOutput) -> Option<(usize, usize)> {
    out.certificate.claims_typed().iter().find_map(|c| match c {
        Claim::RestrictedDelaunayCurve {
            edges,
            isolated_sample_points,
            ..
        } => Some((*edges, *isolated_sample_points)),
        _ => None,
    })
}

/// One crossing of a dual edge found by dense sampling: the float point (bisected).
fn bisect(f: &dyn Implicit, a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let g = |t: f64| f.eval([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), 0.0]);
    let (mut lo, mut hi) = (0.0, 1.0);
    let glo = g(lo);
    for _ in 0..80 {
        let m = 0.5 * (lo + hi);
        if (g(m) < 0.0) == (glo < 0.0) {
            lo = m;
        } else {
            hi = m;
        }
    }
    let t = 0.5 * (lo + hi);
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// The crossings of f = 0 with the polyline `p0 → p1` sampled at `n` points, restricted
/// to the domain (sign changes between consecutive samples inside D).
fn sampled_crossings(
    f: &dyn Implicit,
    domain: &Aabb,
    p0: [f64; 2],
    p1: [f64; 2],
    n: usize,
) -> Vec<[f64; 2]> {
    let inside = |p: [f64; 2]| {
        p[0] >= domain.min[0]
            && p[0] <= domain.max[0]
            && p[1] >= domain.min[1]
            && p[1] <= domain.max[1]
    };
    let at = |k: usize| {
        let t = k as f64 / n as f64;
        [p0[0] + t * (p1[0] - p0[0]), p0[1] + t * (p1[1] - p0[1])]
    };
    let mut out = Vec::new();
    let mut prev = at(0);
    let mut sp = f.eval([prev[0], prev[1], 0.0]);
    for k in 1..=n {
        let q = at(k);
        let sq = f.eval([q[0], q[1], 0.0]);
        if inside(prev) && inside(q) && (sp < 0.0) != (sq < 0.0) {
            out.push(bisect(f, prev, q));
        }
        prev = q;
        sp = sq;
    }
    out
}

fn circumcentre(a: Point2<f64>, b: Point2<f64>, c: Point2<f64>) -> [f64; 2] {
    let (bx, by) = (b.x - a.x, b.y - a.y);
    let (cx, cy) = (c.x - a.x, c.y - a.y);
    let d = 2.0 * (bx * cy - by * cx);
    let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
    [a.x + (cy * b2 - by * c2) / d, a.y + (bx * c2 - cx * b2) / d]
}

/// The restricted Delaunay edges of the point set `pts` by f = 0 ∩ D, recomputed
/// independently in f64: spade's triangulation of the points alone, each edge's dual
/// (segment between circumcentres, or for a hull edge the ray from the inner
/// triangle's circumcentre away from the hull, cut at 10·diam(D)) sampled at `n`
/// points. Returns the edges (sorted index pairs) with the crossing points of each.
fn independent_restricted(
    f: &dyn Implicit,
    domain: &Aabb,
    pts: &[[f64; 2]],
    n: usize,
) -> Vec<((u32, u32), Vec<[f64; 2]>)> {
    let mut t: DelaunayTriangulation<Point2<f64>> = DelaunayTriangulation::new();
    let mut ids = Vec::new();
    for p in pts {
        let h = t.insert(Point2::new(p[0], p[1])).unwrap();
        ids.push(h.index());
    }
    // Output vertex index of each spade handle (the handles are insertion order
    // unless duplicates merged, which would be a bug).
    assert_eq!(t.num_vertices(), pts.len(), "duplicate output vertices");
    let diam = domain.diagonal();
    let mut out = Vec::new();
    for e in t.undirected_edges() {
        let d = e.as_directed();
        let [a, b] = d.vertices().map(|v| v.fix().index() as u32);
        let [pa, pb] = d.positions();
        let left = d.opposite_position();
        let right = d.rev().opposite_position();
        let (s0, s1) = match (left, right) {
            (Some(l), Some(r)) => (circumcentre(pa, pb, l), circumcentre(pb, pa, r)),
            (Some(l), None) | (None, Some(l)) => {
                let c = circumcentre(pa, pb, l);
                // Outward normal of the hull edge: away from the inner vertex l.
                let (ex, ey) = (pb.x - pa.x, pb.y - pa.y);
                let mut nrm = [-ey, ex];
                let m = [0.5 * (pa.x + pb.x), 0.5 * (pa.y + pb.y)];
                if nrm[0] * (l.x - m[0]) + nrm[1] * (l.y - m[1]) > 0.0 {
                    nrm = [ey, -ex];
                }
                let len = (nrm[0] * nrm[0] + nrm[1] * nrm[1]).sqrt();
                (
                    c,
                    [
                        c[0] + 10.0 * diam * nrm[0] / len,
                        c[1] + 10.0 * diam * nrm[1] / len,
                    ],
                )
            }
            (None, None) => continue,
        };
        let xs = sampled_crossings(f, domain, s0, s1, n);
        if !xs.is_empty() {
            out.push(((a.min(b), a.max(b)), xs));
        }
    }
    out
}

/// The independent check: the output's edges are exactly the restricted Delaunay
/// edges of its vertices (every output edge restricted, every restricted edge output),
/// and every crossing found meets the criteria. Returns the number of edges checked.
fn check_independently(
    f: &dyn Implicit,
    domain: &Aabb,
    out: &MeshOutput,
    size: f64,
    distance: f64,
) -> usize {
    let c = curve(out);
    let rd = independent_restricted(f, domain, &c.vertices, 4000);
    let mine: HashSet<(u32, u32)> = c
        .segments
        .iter()
        .map(|s| (s[0].min(s[1]), s[0].max(s[1])))
        .collect();
    let theirs: HashSet<(u32, u32)> = rd.iter().map(|x| x.0).collect();
    let missing: Vec<_> = theirs.difference(&mine).collect();
    let extra: Vec<_> = mine.difference(&theirs).collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "restricted edges differ: {} missing from the output {:?}, {} output but not restricted {:?}",
        missing.len(),
        missing,
        extra.len(),
        extra
    );
    for ((a, b), xs) in &rd {
        let pa = c.vertices[*a as usize];
        let pb = c.vertices[*b as usize];
        let m = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
        for x in xs {
            let r = ((x[0] - pa[0]).powi(2) + (x[1] - pa[1]).powi(2)).sqrt();
            let d = ((x[0] - m[0]).powi(2) + (x[1] - m[1]).powi(2)).sqrt();
            assert!(
                r <= size * (1.0 + 1e-6),
                "edge {a}-{b}: ball radius {r} > facet size {size}"
            );
            assert!(
                d <= distance * (1.0 + 1e-6) + 1e-12,
                "edge {a}-{b}: distance {d} > facet distance {distance}"
            );
        }
        assert_eq!(
            xs.len(),
            1,
            "edge {a}-{b}: its dual crosses f = 0 {} times",
            xs.len()
        );
    }
    rd.len()
}

/// Closed, one cycle per component, the catalog's component count.
fn check_topology(out: &MeshOutput, components: usize) {
    let t = analyze_curve(curve(out)).unwrap();
    assert!(t.closed, "not closed: {t:?}");
    assert_eq!(t.components, components, "{t:?}");
    assert_eq!(t.closed_components, components, "{t:?}");
    assert_eq!(t.branch_points, 0, "{t:?}");
    assert_eq!(t.open_ends, 0, "{t:?}");
    assert_eq!(t.isolated_vertices, 0, "{t:?}");
    assert_eq!(t.duplicate_segments, 0, "{t:?}");
    // One polyline per component, each a cycle.
    let p = curve(out).polylines();
    assert_eq!(p.len(), components);
    assert!(p.iter().all(|(_, closed)| *closed));
}

const SIZE: f64 = 0.15;
const DISTANCE: f64 = 0.01;

#[test]
fn catalog_curves_closed_one_cycle_per_component_and_restricted() {
    let mut checked = 0;
    for e in catalog::curves() {
        let Some(top) = e.topology else {
            continue; // singular (lemniscate): tested below
        };
        let f = e.function();
        let out = run(&f, &e.domain, &opts(Some(SIZE), Some(DISTANCE), None));
        assert!(complete(&out), "{}: {:?}", e.name, out.stats["stop_reason"]);
        check_topology(&out, top.components);
        let n = check_independently(&f, &e.domain, &out, SIZE, DISTANCE);
        assert_eq!(n, curve(&out).segments.len());
        // Certified restricted Delaunay edges, every sample point used, never isotopy.
        let (edges, isolated) =
            rd_claim(&out).unwrap_or_else(|| panic!("{}: no claim: {:?}", e.name, out.certificate));
        assert_eq!(edges, curve(&out).segments.len(), "{}", e.name);
        assert_eq!(isolated, 0, "{}", e.name);
        assert!(!out.certificate.is_certified(), "{}", e.name);
        assert!(!out.certificate.proves_topology(), "{}", e.name);
        assert!(
            !out.certificate
                .claims_typed()
                .iter()
                .any(|c| c.is_topological()),
            "{}",
            e.name
        );
        // The criteria as the mesher reports them, and its certified radius bound.
        assert!(stat_f64(&out, "max_ball_radius") <= SIZE, "{}", e.name);
        assert!(stat_f64(&out, "max_distance") <= DISTANCE, "{}", e.name);
        let rsup = stat_f64(&out, "certified_max_ball_radius");
        assert!(rsup >= stat_f64(&out, "max_ball_radius"), "{}", e.name);
        assert!(rsup <= SIZE * (1.0 + 1e-9), "{}: {rsup}", e.name);
        assert_eq!(out.stats["seeding"], "fallback-lines");
        checked += 1;
    }
    assert!(checked >= 6, "only {checked} catalog curves");
}

#[test]
fn finer_criteria_give_more_vertices_and_still_hold() {
    let e = catalog::get("cassini-2").unwrap();
    let f = e.function();
    let mut last = 0;
    for (size, distance) in [(0.3, 0.03), (0.1, 0.01), (0.03, 0.001)] {
        let out = run(&f, &e.domain, &opts(Some(size), Some(distance), None));
        assert!(complete(&out));
        check_topology(&out, 2);
        check_independently(&f, &e.domain, &out, size, distance);
        let n = curve(&out).vertices.len();
        assert!(n > last, "{n} vertices at size {size}, {last} before");
        last = n;
    }
}

#[test]
fn near_touching_circles_bridge_at_a_coarse_distance_and_separate_at_a_fine_one() {
    // Two circles 0.02 apart (lfs ~ 0.01 at the gap). With facet distance 0.05 the
    // criteria are met by a sample whose restricted Delaunay graph bridges the gap
    // (branch points): Theorem 3's hypothesis r <= 0.1 lfs fails there, the output is
    // still exactly the restricted graph, and nothing topological is claimed. With
    // facet distance 0.01 the two cycles come out.
    let e = catalog::get("near-touching").unwrap();
    let f = e.function();
    let coarse = run(&f, &e.domain, &opts(Some(0.2), Some(0.05), None));
    assert!(complete(&coarse));
    let t = analyze_curve(curve(&coarse)).unwrap();
    assert!(t.branch_points > 0 && !t.closed, "{t:?}");
    check_independently(&f, &e.domain, &coarse, 0.2, 0.05);
    assert!(rd_claim(&coarse).is_some());
    assert!(!coarse.certificate.proves_topology());
    let fine = run(&f, &e.domain, &opts(Some(0.2), Some(0.01), None));
    assert!(complete(&fine));
    check_topology(&fine, 2);
    check_independently(&f, &e.domain, &fine, 0.2, 0.01);
}

#[test]
fn manifold_phase_removes_the_bridge() {
    // The coarse run of the test above with --manifold: the sample points at the
    // bridge's branch points get their restricted edges refined until every used
    // sample point has degree 2; the output is still exactly the restricted graph.
    let e = catalog::get("near-touching").unwrap();
    let f = e.function();
    let mut o = opts(Some(0.2), Some(0.05), None);
    o.manifold = true;
    let out = run(&f, &e.domain, &o);
    assert!(complete(&out), "{:?}", out.stats["stop_reason"]);
    assert!(out.stats["manifold_rounds"].as_u64().unwrap() >= 1);
    check_topology(&out, 2);
    check_independently(&f, &e.domain, &out, 0.2, 0.05);
    assert!(rd_claim(&out).is_some());
}

#[test]
fn registered_as_bo_in_2d_with_the_3d_entry_unchanged() {
    let m = registry::build("bo", 2, &opts(Some(0.2), None, None)).unwrap();
    assert_eq!(m.dim(), 2);
    let m3 = registry::build("bo", 3, &MesherOptions::default()).unwrap();
    assert_eq!(m3.dim(), 3);
    let info = registry::list()
        .into_iter()
        .find(|i| i.name == "bo" && i.dim == 2)
        .unwrap();
    assert!(info.reads.contains(&"facet-size"));
    // The 2D bo has no angle criterion: --facet-angle is refused.
    let o = MesherOptions {
        facet_angle: Some(30.0),
        ..Default::default()
    };
    assert!(registry::build("bo", 2, &o).is_err());
    // A surface is refused.
    let e = catalog::get("sphere").unwrap();
    assert!(m.mesh(&e.function(), &e.domain, &NoProgress).is_err());
}

#[test]
fn vertex_budget_stops_the_run_and_says_so() {
    let e = catalog::get("ellipse").unwrap();
    let f = e.function();
    let out = run(&f, &e.domain, &opts(Some(0.05), None, Some(6)));
    assert!(!complete(&out));
    let why = out.stats["stop_reason"].as_str().unwrap();
    assert!(why.contains("vertex budget"), "{why}");
    assert!(out.stats["vertices"].as_u64().unwrap() <= 6);
    let reason = out.certificate.reason().unwrap();
    assert!(reason.starts_with("stopped"), "{reason}");
    // The same run without the budget completes.
    let full = run(&f, &e.domain, &opts(Some(0.05), None, None));
    assert!(complete(&full));
    assert!(curve(&full).vertices.len() > 6);
}

#[test]
fn time_limit_stops_the_run() {
    let e = catalog::get("circle").unwrap();
    let o = MesherOptions {
        facet_size: Some(1e-4),
        time_limit: Some(1e-3),
        ..Default::default()
    };
    let out = run(&e.function(), &e.domain, &o);
    assert!(!complete(&out));
    assert!(out.stats["stop_reason"]
        .as_str()
        .unwrap()
        .contains("time limit"));
}

#[test]
fn no_claim_without_a_rigorous_oracle() {
    // The unit circle as a plain point function: interval enclosures from a Lipschitz
    // bound, no derivative enclosures, not rigorous.
    let f = PointFn {
        f: |p: [f64; 3]| p[0] * p[0] + p[1] * p[1] - 1.0,
        gradient: |p: [f64; 3]| [2.0 * p[0], 2.0 * p[1], 0.0],
        lipschitz: 6.0,
        dim: 2,
        name: "circle".into(),
    };
    let e = catalog::get("circle").unwrap();
    let out = run(&f, &e.domain, &opts(Some(0.3), None, Some(200)));
    assert!(rd_claim(&out).is_none(), "{:?}", out.certificate);
}

#[test]
fn the_lemniscate_is_never_claimed_isotopic() {
    let e = catalog::get("lemniscate").unwrap();
    let out = run(&e.function(), &e.domain, &opts(None, None, Some(2000)));
    assert!(!out.certificate.proves_topology());
    assert!(!out
        .certificate
        .claims_typed()
        .iter()
        .any(|c| c.is_topological()));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, .. ProptestConfig::default() })]
    /// Random rotated ellipses strictly inside [-2, 2]²: centre in [-0.5, 0.5]², semi-
    /// axes in [0.3, 1.2], so the ellipse lies in [-1.7, 1.7]² and its extent along
    /// each axis (≥ 0.6) exceeds the spacing of the seed lines (0.5): some seed line
    /// meets it.
    #[test]
    fn random_ellipses(cx in -0.5f64..0.5, cy in -0.5f64..0.5, a in 0.3f64..1.2,
                       b in 0.3f64..1.2, th in 0.0f64..3.14159) {
        let (c, s) = (th.cos(), th.sin());
        let text = format!(
            "((x - {cx})*{c} + (y - {cy})*{s})^2/{a}^2 + ((y - {cy})*{c} - (x - {cx})*{s})^2/{b}^2 - 1"
        );
        let f = Formula::with_dim(&text, 2).unwrap();
        let domain = Aabb::rect([-2.0, -2.0], [2.0, 2.0]);
        let out = run(&f, &domain, &opts(Some(0.2), Some(0.01), None));
        prop_assert!(complete(&out));
        check_topology(&out, 1);
        check_independently(&f, &domain, &out, 0.2, 0.01);
        prop_assert!(rd_claim(&out).is_some(), "{:?}", out.certificate);
    }
}
