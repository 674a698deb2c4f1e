//! Boissonnat–Oudot restricted-Delaunay meshing (`--algo bo`) and the shared
//! restricted-triangulation machinery: outputs checked against the catalog's topology,
//! the criteria, and an independent re-computation of the restricted Delaunay
//! triangulation (a fresh kernel build of the output's vertices, every Voronoi edge
//! sampled densely in f64).
use certmesh::implicit::ops::{isolate_segment, SegmentBudget};
use certmesh::implicit::{IBox, Implicit};
use certmesh::kernel::delaunay::Delaunay;
use certmesh::kernel::geom::{dist, lerp, Aabb};
use certmesh::mesh::TriMesh;
use certmesh::mesher::options::MesherOptions;
use certmesh::mesher::{Claim, Mesh, MeshOutput, Mesher, NoProgress};
use certmesh::metrics::angles::triangle_angles;
use certmesh::metrics::topology::analyze;
use certmesh::restricted_delaunay::bo::triangle_circumcentre;
use certmesh::restricted_delaunay::restricted::test_segment;
use certmesh::restricted_delaunay::BoissonnatOudot;
use certmesh::{catalog, Formula};
use inari::Interval;
use proptest::prelude::*;
use std::collections::{HashMap, HashSet};

fn bo(
    size: f64,
    distance: f64,
    extra: &[(&str, &str)],
    tweak: impl Fn(&mut MesherOptions),
) -> BoissonnatOudot {
    let mut o = MesherOptions {
        facet_size: Some(size),
        facet_distance: Some(distance),
        certify: true,
        ..Default::default()
    };
    for (k, v) in extra {
        o.extra.insert(k.to_string(), v.to_string());
    }
    tweak(&mut o);
    BoissonnatOudot::from_options(&o).unwrap()
}

fn run(name: &str, m: &BoissonnatOudot) -> (Formula, Aabb, MeshOutput, TriMesh) {
    let e = catalog::get(name).unwrap();
    let f = e.function();
    let out = m.mesh(&f, &e.domain, &NoProgress).unwrap();
    let mesh = match &out.mesh {
        Mesh::Surface(s) => s.clone(),
        _ => panic!("bo makes surfaces"),
    };
    (f, e.domain, out, mesh)
}

fn stat<'a>(out: &'a MeshOutput, k: &str) -> &'a serde_json::Value {
    out.stats.get(k).unwrap_or_else(|| panic!("no stat {k}"))
}

/// The restricted Delaunay triangulation of `verts`, computed independently of the
/// mesher: a new kernel build (another insertion order), the facets without a far
/// corner, each Voronoi edge (between the kernel's circumcentres) clipped to the
/// domain and sampled at `n` points in f64; a facet is restricted when f changes sign
/// along it. Returns, per restricted facet (sorted mesh vertex ids), the crossing
/// points (sign changes refined by bisection).
fn sampled_rdt(
    f: &dyn Implicit,
    domain: &Aabb,
    verts: &[[f64; 3]],
    n: usize,
) -> HashMap<[u32; 3], Vec<[f64; 3]>> {
    let (t, bulk) = Delaunay::from_points(verts, 99).unwrap();
    assert!(bulk.duplicates.is_empty());
    let mut out = HashMap::new();
    for (c, i, d, _) in t.facets(true) {
        let cv = t.cell_vertices(c);
        let mut k: Vec<u32> = (0..4)
            .filter(|&j| j != i)
            .map(|j| t.input_index(cv[j]).unwrap() as u32)
            .collect();
        k.sort_unstable();
        let (a, b) = (t.circumcentre(c), t.circumcentre(d));
        // Clip to the domain (slab method).
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        for ax in 0..3 {
            let dd = b[ax] - a[ax];
            if dd == 0.0 {
                if a[ax] < domain.min[ax] || a[ax] > domain.max[ax] {
                    hi = -1.0;
                }
                continue;
            }
            let t0 = (domain.min[ax] - a[ax]) / dd;
            let t1 = (domain.max[ax] - a[ax]) / dd;
            lo = lo.max(t0.min(t1));
            hi = hi.min(t0.max(t1));
        }
        if hi <= lo {
            continue;
        }
        let mut xs = Vec::new();
        let mut prev = (lo, f.eval(lerp(a, b, lo)));
        for s in 1..=n {
            let tt = lo + (hi - lo) * s as f64 / n as f64;
            let v = f.eval(lerp(a, b, tt));
            if (v > 0.0) != (prev.1 > 0.0) {
                let (mut l, mut h) = (prev.0, tt);
                for _ in 0..60 {
                    let m = 0.5 * (l + h);
                    if (f.eval(lerp(a, b, m)) > 0.0) == (prev.1 > 0.0) {
                        l = m;
                    } else {
                        h = m;
                    }
                }
                xs.push(lerp(a, b, 0.5 * (l + h)));
            }
            prev = (tt, v);
        }
        if !xs.is_empty() {
            out.insert([k[0], k[1], k[2]], xs);
        }
    }
    out
}

/// Everything the issue asks of a refined, certified output on a smooth surface.
fn check_output(
    name: &str,
    size: f64,
    distance: f64,
    manifold: bool,
    components: usize,
    genus: &[usize],
) {
    let m = bo(size, distance, &[], |o| o.manifold = manifold);
    let (f, domain, out, mesh) = run(name, &m);
    assert_eq!(
        stat(&out, "refinement_complete"),
        true,
        "{name}: {:?}",
        out.stats
    );
    assert_eq!(stat(&out, "seeding_complete"), true);
    // Topology.
    let top = analyze(&mesh).unwrap();
    assert!(top.is_closed_oriented_manifold(), "{name}: {top:?}");
    assert_eq!(top.components, components, "{name}");
    assert_eq!(top.genus, genus, "{name}");
    let chi: i64 = genus.iter().map(|&g| 2 - 2 * g as i64).sum();
    assert_eq!(top.euler_characteristic, chi, "{name}");
    // Oriented towards f > 0 (outward, f < 0 inside): positive enclosed volume.
    let vol: f64 = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum();
    assert!(vol > 0.0, "{name}: volume {vol}");
    // Angles.
    let min_angle = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            triangle_angles(a, b, c).into_iter().fold(180.0, f64::min)
        })
        .fold(180.0, f64::min);
    assert!(min_angle >= 30.0 - 1e-9, "{name}: min angle {min_angle}");
    // Vertices on S (up to rounding of the bisection).
    for p in &mesh.vertices {
        assert!(
            f.eval(*p).abs() < 1e-9,
            "{name}: vertex {p:?} f = {}",
            f.eval(*p)
        );
    }
    // The certificate: the restricted triangulation claim, never isotopy.
    assert!(!out.certificate.is_certified() && !out.certificate.proves_topology());
    let rdt = out
        .certificate
        .claims_typed()
        .iter()
        .find_map(|c| match c {
            Claim::RestrictedDelaunay { facets, .. } => Some(*facets),
            _ => None,
        })
        .unwrap_or_else(|| {
            panic!(
                "{name}: no restricted-Delaunay claim: {:?}",
                out.certificate
            )
        });
    assert_eq!(rdt, mesh.triangles.len());
    // At CGAL-style criteria the balls exceed psi = 0.099 x the certified reach bound.
    let why = out.certificate.reason().unwrap();
    assert!(
        why.contains("isotopy")
            && (why.contains("exceed psi") || why.contains("no certified reach bound")),
        "{why}"
    );
    // Independent computation: the same facet set, and the criteria on its crossings.
    let sampled = sampled_rdt(&f, &domain, &mesh.vertices, 400);
    let ours = facet_keys(&mesh);
    let theirs: HashSet<[u32; 3]> = sampled.keys().copied().collect();
    assert_eq!(
        ours.symmetric_difference(&theirs).count(),
        0,
        "{name}: certified RDT differs from the sampled one"
    );
    for t in &mesh.triangles {
        let mut k = *t;
        k.sort_unstable();
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let cc = triangle_circumcentre(a, b, c);
        for x in &sampled[&k] {
            let r = dist(*x, a);
            assert!(r <= size * (1.0 + 1e-6), "{name}: ball radius {r} > {size}");
            let d = dist(*x, cc);
            assert!(
                d <= distance * (1.0 + 1e-6) + 1e-12,
                "{name}: distance {d} > {distance}"
            );
        }
    }
}

/// Every smooth closed surface of the catalog at bo's default criteria (facet size
/// diam/20, distance diam/200), manifold variant: the catalog's components and genus,
/// angles, criteria, the certified restricted triangulation checked against sampling.
#[test]
fn every_smooth_catalog_surface_at_default_criteria() {
    let mut done = Vec::new();
    for e in catalog::entries() {
        if e.dim != 3 || !e.smooth {
            continue;
        }
        let Some(top) = e.topology else { continue };
        let d = e.domain;
        let diam = (0..3)
            .map(|k| (d.max[k] - d.min[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        check_output(
            e.name,
            diam / 20.0,
            diam / 200.0,
            true,
            top.components,
            &top.genus,
        );
        done.push(e.name);
    }
    assert!(done.len() >= 11, "{done:?}");
}

#[test]
fn sphere_is_meshed_to_the_criteria_and_certified_restricted() {
    check_output("sphere", 0.3, 0.03, false, 1, &[0]);
}

#[test]
fn torus_is_meshed_to_the_criteria_and_certified_restricted() {
    check_output("torus", 0.12, 0.012, false, 1, &[1]);
}

/// At these criteria the plain restricted triangulation bridges the 0.02 gap
/// (non-manifold edges: the criteria are far coarser than the lfs there); the manifold
/// variant refines the bridges away.
#[test]
fn two_spheres_both_components_found() {
    check_output("two-spheres", 0.2, 0.02, true, 2, &[0, 0]);
}

/// The near-touching spheres make Voronoi edges that cross S twice with the same sign
/// at both ends: invisible to a sign-at-the-ends oracle, found by isolation.
#[test]
fn double_crossings_across_the_gap_are_found() {
    let f = catalog::get("two-spheres").unwrap().function();
    let dom = catalog::get("two-spheres").unwrap().domain.intervals();
    // From inside the left sphere to inside the right one, across the 0.02 gap:
    // f < 0 at both ends, crossings at x = ±0.01.
    let (a, b) = ([-0.6, 0.01, -0.02], [0.6, 0.0, 0.03]);
    assert!(f.eval(a) < 0.0 && f.eval(b) < 0.0);
    let t = test_segment(&f, a, b, a, &dom, SegmentBudget::default());
    assert!(t.undecided.is_empty());
    assert_eq!(t.crossings.len(), 2, "{t:?}");
    assert!(t.crossings[0].rising && !t.crossings[1].rising);
    for x in &t.crossings {
        assert!(
            x.point[0].abs() < 0.0101 && f.eval(x.point).abs() < 1e-12,
            "{x:?}"
        );
    }
    // In a coarse mesh such segments occur and are refined away.
    let m = bo(0.6, 0.2, &[], |o| {
        o.facet_angle = Some(20.0);
        o.manifold = true;
    });
    let (_, _, out, mesh) = run("two-spheres", &m);
    let by = stat(&out, "insertions_by_reason");
    assert!(by["multiple"].as_u64().unwrap_or(0) > 0, "{by}");
    let top = analyze(&mesh).unwrap();
    assert_eq!(top.components, 2);
    assert_eq!(top.genus, vec![0, 0], "{top:?}");
}

#[test]
fn double_cone_is_never_certified_and_names_the_apex() {
    let m = bo(0.2, 0.02, &[], |_| {});
    let (_, _, out, _) = run("double-cone", &m);
    assert!(!out.certificate.is_certified() && !out.certificate.proves_topology());
    let regions = match &out.certificate {
        certmesh::mesher::Certificate::Uncertified { regions, .. } => regions.clone(),
        _ => unreachable!(),
    };
    assert!(!regions.is_empty());
    assert!(
        regions.iter().any(|r| r.region.contains([0.0, 0.0, 0.0])
            || dist(r.region.center(), [0.0; 3]) < 1e-6),
        "{regions:?}"
    );
    assert_eq!(stat(&out, "seeding_complete"), false);
}

#[test]
fn guards_stop_and_say_so() {
    let m = bo(0.05, 0.005, &[], |o| o.max_vertices = Some(60));
    let (_, _, out, _) = run("sphere", &m);
    assert_eq!(stat(&out, "refinement_complete"), false);
    assert!(stat(&out, "stop_reason")
        .as_str()
        .unwrap()
        .contains("--max-vertices"));
    assert!(stat(&out, "vertices").as_u64().unwrap() <= 61);
    let m = bo(0.01, 0.001, &[], |o| o.time_limit = Some(0.05));
    let (_, _, out, _) = run("torus", &m);
    assert_eq!(stat(&out, "refinement_complete"), false);
    assert!(stat(&out, "stop_reason")
        .as_str()
        .unwrap()
        .contains("time limit"));
    // Bad parameters are errors.
    for o in [
        MesherOptions {
            facet_angle: Some(75.0),
            ..Default::default()
        },
        MesherOptions {
            facet_size: Some(-1.0),
            ..Default::default()
        },
        MesherOptions {
            max_vertices: Some(1),
            ..Default::default()
        },
    ] {
        assert!(BoissonnatOudot::from_options(&o).is_err());
    }
    let mut o = MesherOptions::default();
    o.extra.insert("no-such".into(), "1".into());
    assert!(BoissonnatOudot::from_options(&o).is_err());
}

#[test]
fn manifold_variant_gives_a_closed_manifold_at_coarse_criteria() {
    let m = bo(0.5, 0.1, &[], |o| {
        o.manifold = true;
        o.facet_angle = Some(20.0);
    });
    let (_, _, out, mesh) = run("torus", &m);
    assert_eq!(stat(&out, "refinement_complete"), true, "{:?}", out.stats);
    let top = analyze(&mesh).unwrap();
    assert!(
        top.closed && top.manifold && top.consistently_oriented,
        "{top:?}"
    );
}

fn point(x: f64) -> Interval {
    Interval::try_from((x, x)).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Segment isolation against the closed-form roots on a sphere of radius r about c:
    /// exact count, each root inside its certified piece.
    #[test]
    fn isolation_matches_closed_form_roots_on_spheres(
        c in prop::array::uniform3(-0.5f64..0.5),
        r in 0.2f64..1.0,
        a in prop::array::uniform3(-2.0f64..2.0),
        b in prop::array::uniform3(-2.0f64..2.0),
    ) {
        let f = Formula::surface(&format!(
            "(x - {:?})^2 + (y - {:?})^2 + (z - {:?})^2 - {:?}", c[0], c[1], c[2], r * r
        )).unwrap();
        let ea: IBox = a.map(point);
        let eb: IBox = b.map(point);
        let res = isolate_segment(&f, &ea, &eb, None, SegmentBudget::default());
        // |a + t d - c|² = r²: t² |d|² + 2t d·(a - c) + |a - c|² - r² = 0.
        let d: Vec<f64> = (0..3).map(|k| b[k] - a[k]).collect();
        let e: Vec<f64> = (0..3).map(|k| a[k] - c[k]).collect();
        let qa: f64 = d.iter().map(|x| x * x).sum();
        let qb: f64 = 2.0 * (0..3).map(|k| d[k] * e[k]).sum::<f64>();
        let qc: f64 = e.iter().map(|x| x * x).sum::<f64>() - r * r;
        let disc = qb * qb - 4.0 * qa * qc;
        prop_assume!(qa > 1e-6 && disc.abs() > 1e-6);
        let mut roots = Vec::new();
        if disc > 0.0 {
            for s in [-1.0, 1.0] {
                let t = (-qb + s * disc.sqrt()) / (2.0 * qa);
                if t > 1e-9 && t < 1.0 - 1e-9 { roots.push(t); }
            }
        }
        prop_assume!(roots.iter().all(|t| (t - 0.0f64).abs() > 1e-6 && (t - 1.0f64).abs() > 1e-6));
        prop_assert!(res.complete(), "{res:?}");
        prop_assert_eq!(res.roots.len(), roots.len(), "{:?} vs {:?}", res, roots);
        for (x, t) in res.roots.iter().zip(roots.iter()) {
            prop_assert!(x.t0 <= *t + 1e-12 && *t <= x.t1 + 1e-12, "{:?} {}", x, t);
        }
    }
}

/// A tangent segment is undecided, never a wrong count.
#[test]
fn tangent_segment_is_undecided() {
    let f = Formula::surface("x^2 + y^2 + z^2 - 1").unwrap();
    let res = isolate_segment(
        &f,
        &[point(-1.0), point(1.0), point(0.0)],
        &[point(1.0), point(1.0), point(0.0)],
        None,
        SegmentBudget::default(),
    );
    assert!(!res.complete());
    assert!(res.roots.is_empty());
}

/// The certified reach lower bound against the true reach: sphere radius 1, torus tube
/// radius 0.25 (both limited by curvature), two-spheres: half the 0.02 gap.
#[test]
fn reach_lower_bounds_are_below_the_true_reach() {
    use certmesh::implicit::critical::Bx;
    use certmesh::implicit::reach::{reach_lower_bound, ReachOptions};
    for (name, tau, depth) in [
        ("sphere", 1.0, 6),
        ("torus", 0.25, 6),
        ("two-spheres", 0.01, 8),
    ] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        let r = reach_lower_bound(
            &f,
            Bx::new(e.domain.min, e.domain.max),
            ReachOptions {
                max_depth: depth,
                ..Default::default()
            },
        );
        let t = r.tau.unwrap_or_else(|| panic!("{name}: {r:?}"));
        eprintln!("{name}: certified reach >= {t} (true {tau}), {r:?}");
        assert!(t <= tau && t > 0.2 * tau, "{name}: {t} vs {tau}");
    }
    // The double cone has a singular point: no bound.
    let e = catalog::get("double-cone").unwrap();
    let r = reach_lower_bound(
        &e.function(),
        Bx::new(e.domain.min, e.domain.max),
        ReachOptions::default(),
    );
    assert!(r.tau.is_none() && r.reason.is_some(), "{r:?}");
}

/// `--set size=reach`: refinement to psi = 0.099 x the certified reach bound (Theorem
/// 4's criterion); the certificate then claims the weak-sample condition, checked here
/// against the sampled crossings, and the isotopy (the sphere's samples are exactly
/// cospherical on S).
#[test]
fn sphere_weak_sample_claim_at_psi_from_the_certified_reach() {
    let mut o = MesherOptions {
        certify: true,
        ..Default::default()
    };
    o.extra.insert("size".into(), "reach".into());
    o.extra.insert("reach-depth".into(), "6".into());
    let m = BoissonnatOudot::from_options(&o).unwrap();
    let (f, domain, out, mesh) = run("sphere", &m);
    let psi = out
        .certificate
        .claims_typed()
        .iter()
        .find_map(|c| match c {
            Claim::WeakSample {
                psi,
                reach_lower_bound,
                ..
            } => {
                assert!(*reach_lower_bound <= 1.0);
                Some(*psi)
            }
            _ => None,
        })
        .unwrap_or_else(|| panic!("{:?}", out.certificate));
    assert!(psi <= 0.1);
    // Every sample of a round sphere is cospherical with every other; the certificate
    // through a point set on S accepts that exactly (restricted_delaunay::perturbed),
    // so the sphere is certified isotopic too.
    assert!(out.certificate.proves_topology(), "{:?}", out.certificate);
    let top = analyze(&mesh).unwrap();
    assert!(top.is_closed_oriented_manifold() && top.genus == vec![0]);
    let sampled = sampled_rdt(&f, &domain, &mesh.vertices, 200);
    assert_eq!(sampled.len(), mesh.triangles.len());
    for t in &mesh.triangles {
        let mut k = *t;
        k.sort_unstable();
        for x in &sampled[&k] {
            let r = dist(*x, mesh.vertices[t[0] as usize]);
            assert!(r <= psi * (1.0 + 1e-9), "ball radius {r} > psi {psi}");
        }
    }
}

/// The heavier catalog surfaces (release: `cargo test --release --test
/// restricted_delaunay -- --ignored`): genus 2 and the tanglecube (genus 5) at CGAL's
/// medium criteria, with the same checks as sphere and torus.
#[test]
#[ignore]
fn genus2_and_tanglecube_release() {
    check_output("genus2", 0.05, 0.005, true, 1, &[2]);
    check_output("tanglecube", 0.1, 0.01, true, 1, &[5]);
}

/// The triangles of `mesh` as sorted vertex triples.
fn facet_keys(mesh: &TriMesh) -> HashSet<[u32; 3]> {
    mesh.triangles
        .iter()
        .map(|t| {
            let mut k = *t;
            k.sort_unstable();
            k
        })
        .collect()
}

fn bo_reach(depth: &str) -> BoissonnatOudot {
    let mut o = MesherOptions {
        certify: true,
        manifold: true,
        ..Default::default()
    };
    o.extra.insert("size".into(), "reach".into());
    o.extra.insert("reach-depth".into(), depth.into());
    BoissonnatOudot::from_options(&o).unwrap()
}

/// Float Newton onto f = 0 (the test's own, not the library's projection).
fn newton(f: &dyn Implicit, mut p: [f64; 3]) -> [f64; 3] {
    for _ in 0..4 {
        let d = f.grad(p);
        let g2 = d.g.iter().map(|x| x * x).sum::<f64>();
        if g2 == 0.0 || d.v == 0.0 {
            break;
        }
        p = std::array::from_fn(|k| p[k] - d.v * d.g[k] / g2);
    }
    p
}

/// The isotopy certificate of `bo --certify` (Theorem 3 through a point set P* on S,
/// restricted_delaunay::perturbed), checked independently: the vertices projected onto
/// S by the test's own Newton steps move by at most the claimed offset, and a fresh
/// kernel build of the projected points, every Voronoi edge sampled in f64, has
/// exactly the output's restricted facets, with every ball within psi.
fn isotopy_through_p_star(name: &str, depth: &str, genus: &[usize]) {
    let (f, domain, out, mesh) = run(name, &bo_reach(depth));
    let c = &out.certificate;
    assert!(c.is_certified() && c.proves_topology(), "{name}: {c:?}");
    let claims = c.claims_typed();
    let has = |p: &dyn Fn(&Claim) -> bool| claims.iter().any(p);
    assert!(has(&|c| matches!(c, Claim::Isotopic { .. })), "{name}");
    assert!(
        has(&|c| matches!(c, Claim::RestrictedDelaunay { .. })),
        "{name}"
    );
    let psi = claims
        .iter()
        .find_map(|c| match c {
            Claim::WeakSample { psi, .. } => Some(*psi),
            _ => None,
        })
        .expect("weak sample claim");
    let offset = claims
        .iter()
        .find_map(|c| match c {
            Claim::PerturbedSample {
                max_offset,
                max_ball_radius,
                ..
            } => {
                assert!(*max_ball_radius <= psi, "{name}");
                Some(*max_offset)
            }
            _ => None,
        })
        .expect("perturbed-sample claim");
    assert!(offset > 0.0 && offset < 1e-10, "{name}: offset {offset}");
    let top = analyze(&mesh).unwrap();
    assert!(top.is_closed_oriented_manifold(), "{name}: {top:?}");
    assert_eq!(top.genus, genus, "{name}");
    let star: Vec<[f64; 3]> = mesh.vertices.iter().map(|&p| newton(&f, p)).collect();
    for (p, q) in mesh.vertices.iter().zip(&star) {
        assert!(
            dist(*p, *q) <= offset,
            "{name}: {p:?} moves {}",
            dist(*p, *q)
        );
    }
    let sampled = sampled_rdt(&f, &domain, &star, 200);
    let out_keys = facet_keys(&mesh);
    let star_keys: HashSet<[u32; 3]> = sampled.keys().copied().collect();
    assert_eq!(out_keys, star_keys, "{name}: restricted facets of P*");
    for (k, xs) in &sampled {
        for x in xs {
            let r = dist(*x, star[k[0] as usize]);
            assert!(r <= psi * (1.0 + 1e-9), "{name}: ball {r} > psi {psi}");
        }
    }
}

#[test]
fn sphere_blob_and_superquadric_are_certified_isotopic_through_a_point_set_on_s() {
    isotopy_through_p_star("sphere", "6", &[0]);
    isotopy_through_p_star("blob", "6", &[0]);
    isotopy_through_p_star("superquadric", "6", &[0]);
}

/// The torus at the reach bound of octree depth 8 (tau >= 0.106 of 0.25; about 36 500
/// vertices): 630 facets spanning its tube or hole have five nearly cospherical
/// samples (lifted determinant 1e-17 to 1e-14 at the float vertices); the tight vertex
/// boxes and the mean-value form of the lifted determinant decide every one.
#[test]
fn torus_is_certified_isotopic_through_a_point_set_on_s() {
    isotopy_through_p_star("torus", "8", &[1]);
}

/// The round-sphere test that lets cospherical samples pass exactly: it must hold for
/// spheres written in any form, and for nothing else (an ellipsoid, a blob or a torus
/// taken for a sphere would make a false certificate).
#[test]
fn round_sphere_is_recognised_exactly_and_nothing_else() {
    use certmesh::restricted_delaunay::perturbed::round_sphere_centre;
    let centre = |s: &str| round_sphere_centre(&Formula::surface(s).unwrap());
    let c = centre("(x - 0.5)^2 + y^2 + z^2 - 1").expect("a sphere");
    assert!(c[0].contains(0.5) && c[1].contains(0.0) && c[2].contains(0.0));
    let c = centre("2*x^2 + 2*y^2 + 2*z^2 - 4*z + 1/3 - 1").expect("a sphere");
    assert!(c[2].contains(1.0) && c[0].contains(0.0));
    assert!(centre("x^2 + y^2 + z^2 - 1").is_some());
    for s in [
        "x^2 + 4*y^2 + 16*z^2 - 1",
        "x^2 + y^2 + z^2 - 1 + 0.8*x*y*z",
        "x^2 + y^2 + z^2 - 1 + 1e-30*x*y",
        "x^2 + y^2 - z^2",
        "(x^2 + y^2 + z^2 + 0.6^2 - 0.25^2)^2 - 4*0.6^2*(x^2 + y^2)",
        "sqrt(x^2 + y^2 + z^2) - 1",
        "x^2 + y^2 + z^2 + x^3 - 1",
    ] {
        assert!(centre(s).is_none(), "{s} taken for a round sphere");
    }
}

/// A grazing crossing that only the certified scan sees (interval circumcentres): on
/// the ellipsoid at the reach bound of depth 6, with this seed radius (found by
/// search: facet_size/2.5), the float refinement ends with one dual segment the
/// certified scan cannot decide. `--certify` inserts its tangency point, refines
/// again and certifies; before, the run stopped uncertified there. (The case depends
/// on the exact refinement: if a change to it makes this assertion fail, find another
/// seed radius that triggers a certify round.)
#[test]
fn grazing_crossing_seen_only_by_the_certified_scan_is_refined_away() {
    let mut o = MesherOptions {
        certify: true,
        manifold: true,
        ..Default::default()
    };
    for (k, v) in [
        ("size", "reach"),
        ("reach-depth", "6"),
        ("seed-radius", "0.0022123553820846452"),
    ] {
        o.extra.insert(k.into(), v.into());
    }
    let (_, _, out, mesh) = run("ellipsoid", &BoissonnatOudot::from_options(&o).unwrap());
    assert!(
        stat(&out, "certify_rounds").as_u64().unwrap() >= 1,
        "{:?}",
        out.stats
    );
    assert!(
        stat(&out, "insertions_by_reason")
            .get("undecided (certify)")
            .is_some(),
        "{:?}",
        out.stats
    );
    let c = &out.certificate;
    assert!(c.is_certified() && c.proves_topology(), "{c:?}");
    assert!(c
        .claims_typed()
        .iter()
        .any(|c| matches!(c, Claim::Isotopic { .. })));
    let top = analyze(&mesh).unwrap();
    assert!(top.is_closed_oriented_manifold() && top.genus == [0]);
}

/// The unit sphere written as sqrt(x² + y² + z²) − 1 is not recognised as a round
/// sphere (not a polynomial), so its cospherical samples are not accepted exactly:
/// its interior cells are degenerate over the vertex boxes, and the isotopy claim is
/// withheld with that reason, while the restricted triangulation and the weak sample
/// are still proven.
#[test]
fn cospherical_samples_without_the_exact_sphere_test_are_reported() {
    let f = Formula::surface("sqrt(x^2 + y^2 + z^2) - 1").unwrap();
    let domain = catalog::get("sphere").unwrap().domain;
    let out = bo_reach("7").mesh(&f, &domain, &NoProgress).unwrap();
    let c = &out.certificate;
    assert!(!c.proves_topology(), "{c:?}");
    let claims = c.claims_typed();
    assert!(claims.iter().any(|c| matches!(c, Claim::WeakSample { .. })));
    assert!(claims
        .iter()
        .any(|c| matches!(c, Claim::RestrictedDelaunay { .. })));
    assert!(!claims.iter().any(|c| matches!(c, Claim::Isotopic { .. })));
    let reason = c.reason().unwrap();
    assert!(
        reason.contains("not proven strictly locally Delaunay"),
        "{reason}"
    );
}

/// Release only (`cargo test --release --test restricted_delaunay -- --ignored`): the
/// ellipsoid (about 81 000 vertices at psi), genus 2 (about 256 000 at the reach
/// bound of depth 7) and the tanglecube (about 546 000) are certified isotopic, with
/// the same independent check as in CI. About 10 minutes and 3 GB.
#[test]
#[ignore]
fn ellipsoid_genus2_and_tanglecube_isotopic_release() {
    isotopy_through_p_star("ellipsoid", "6", &[0]);
    isotopy_through_p_star("genus2", "7", &[2]);
    isotopy_through_p_star("tanglecube", "7", &[5]);
}

mod perturbed_primitives {
    use super::*;
    use certmesh::implicit::directed::Iv;
    use certmesh::kernel::delaunay::predicates::{insphere, orient3d};
    use certmesh::restricted_delaunay::perturbed::{
        even_front, lifted_centred, lifted_iv, orient_iv, vertex_boxes,
    };

    fn iv_box(p: [f64; 3], w: f64) -> [Iv; 3] {
        p.map(|x| Iv::new(x - w, x + w))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// Interval orient3d and the lifted (insphere) determinant over boxes: a sign
        /// they prove holds for the exact predicates at points drawn inside the boxes;
        /// every even permutation of the cell gives the same conclusion.
        #[test]
        fn interval_predicates_over_boxes_agree_with_exact_ones(
            pts in proptest::collection::vec(proptest::array::uniform3(-1.0f64..1.0), 5),
            far in 0usize..3,
            w in prop_oneof![Just(0.0), Just(1e-12), Just(1e-7), Just(1e-3)],
            picks in proptest::collection::vec(proptest::array::uniform3(-1.0f64..1.0), 20),
        ) {
            let mut p: Vec<[f64; 3]> = pts.clone();
            if far == 1 {
                p[0] = [25.98, -25.98, 25.98]; // a far corner in the cell
            } else if far == 2 {
                p[4] = [-25.98, 25.98, 25.98]; // a far corner as the fifth point
            }
            let boxes: Vec<[Iv; 3]> = p.iter().map(|&q| iv_box(q, w)).collect();
            let cell = [boxes[0], boxes[1], boxes[2], boxes[3]];
            let o = orient_iv(cell);
            let lifted: Vec<Iv> = (0..4).map(|k| lifted_iv(even_front(cell, k), boxes[4])).collect();
            for pick in picks.chunks(5) {
                if pick.len() < 5 { break; }
                let q: Vec<[f64; 3]> = (0..5)
                    .map(|i| std::array::from_fn(|k| p[i][k] + w * pick[i][k]))
                    .collect();
                let ex_o = orient3d(q[0], q[1], q[2], q[3]);
                if o.lo > 0.0 { prop_assert!(ex_o > 0.0); }
                if o.hi < 0.0 { prop_assert!(ex_o < 0.0); }
                if ex_o > 0.0 {
                    // insphere > 0: inside; the lifted determinant is then negative.
                    let ins = insphere(q[0], q[1], q[2], q[3], q[4]);
                    for l in &lifted {
                        if l.lo > 0.0 { prop_assert!(ins < 0.0, "lifted {l:?} insphere {ins}"); }
                        if l.hi < 0.0 { prop_assert!(ins > 0.0, "lifted {l:?} insphere {ins}"); }
                    }
                }
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]
        /// The mean-value form of the lifted determinant on five points of the unit
        /// sphere moved off it by up to `dr` (nearly cospherical: the case it exists
        /// for), boxes of half-width `w` around them: a sign it proves holds for the
        /// exact insphere at points drawn inside the boxes, for every even permutation.
        #[test]
        fn centred_lifted_determinant_is_sound_on_nearly_cospherical_points(
            dirs in proptest::collection::vec(proptest::array::uniform3(-1.0f64..1.0), 5),
            radial in proptest::collection::vec(-1.0f64..1.0, 5),
            dr in prop_oneof![Just(0.0), Just(1e-15), Just(1e-13), Just(1e-10)],
            w in prop_oneof![Just(0.0), Just(1e-16), Just(1e-14), Just(1e-12)],
            picks in proptest::collection::vec(proptest::array::uniform3(-1.0f64..1.0), 25),
        ) {
            let p: Vec<[f64; 3]> = dirs
                .iter()
                .zip(&radial)
                .map(|(d, r)| {
                    let n = d.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-3);
                    d.map(|x| x / n * (1.0 + dr * r))
                })
                .collect();
            let boxes: Vec<[Iv; 3]> = p.iter().map(|&q| iv_box(q, w)).collect();
            let cell = [boxes[0], boxes[1], boxes[2], boxes[3]];
            let centres = [p[0], p[1], p[2], p[3], p[4]];
            for k in 0..4 {
                let c4 = even_front([centres[0], centres[1], centres[2], centres[3]], k);
                let l = lifted_centred(
                    even_front(cell, k),
                    boxes[4],
                    [c4[0], c4[1], c4[2], c4[3], centres[4]],
                );
                let natural = lifted_iv(even_front(cell, k), boxes[4]);
                // Both enclose the same value set: they must overlap.
                prop_assert!(l.lo <= natural.hi && natural.lo <= l.hi, "{l:?} {natural:?}");
                for pick in picks.chunks(5) {
                    if pick.len() < 5 { break; }
                    let q: Vec<[f64; 3]> = (0..5)
                        .map(|i| std::array::from_fn(|j| p[i][j] + w * pick[i][j]))
                        .collect();
                    // Both are the 5×5 determinant of rows (q, |q|², 1), up to a
                    // positive factor and the sign (an even permutation keeps it):
                    // the lifted determinant is minus insphere.
                    let ins = insphere(q[0], q[1], q[2], q[3], q[4]);
                    if l.lo > 0.0 { prop_assert!(ins < 0.0, "{l:?} insphere {ins}"); }
                    if l.hi < 0.0 { prop_assert!(ins > 0.0, "{l:?} insphere {ins}"); }
                }
            }
        }
    }

    /// Where the mean-value form earns its place: five points of the unit sphere, the
    /// fifth moved 10⁻¹³ in or out, boxes of half-width 10⁻¹⁵. The natural enclosure
    /// of the lifted determinant straddles 0; the centred one decides, with the exact
    /// sign.
    #[test]
    fn centred_form_decides_what_the_natural_one_cannot() {
        let unit = |v: [f64; 3]| {
            let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            v.map(|x| x / n)
        };
        let base = [
            unit([0.3, 0.9, -0.2]),
            unit([-0.8, 0.1, 0.5]),
            unit([0.2, -0.7, 0.6]),
            unit([0.6, 0.2, 0.7]),
        ];
        let base = if orient3d(base[0], base[1], base[2], base[3]) > 0.0 {
            base
        } else {
            [base[1], base[0], base[2], base[3]]
        };
        let w = 1e-15;
        for sign in [-1.0, 1.0] {
            let e = unit([-0.1, -0.4, -0.9]).map(|x| x * (1.0 + sign * 1e-13));
            let cell = base.map(|p| iv_box(p, w));
            let natural = lifted_iv(cell, iv_box(e, w));
            let centred =
                lifted_centred(cell, iv_box(e, w), [base[0], base[1], base[2], base[3], e]);
            assert!(
                natural.lo <= 0.0 && natural.hi >= 0.0,
                "natural {natural:?}"
            );
            let ins = insphere(base[0], base[1], base[2], base[3], e);
            // Inside (sign −1): insphere > 0 and the lifted determinant < 0.
            assert_eq!(ins > 0.0, sign < 0.0);
            if sign < 0.0 {
                assert!(centred.hi < 0.0, "{centred:?}");
            } else {
                assert!(centred.lo > 0.0, "{centred:?}");
            }
        }
    }

    /// Boxes around points near the unit sphere each hold a point of it (checked by
    /// the closed-form range of x² + y² + z² over the box); a point 0.1 off it gets a
    /// box reaching it; a point whose box would leave the domain gets none and is named.
    #[test]
    fn vertex_boxes_hold_a_point_of_the_sphere() {
        let e = catalog::get("sphere").unwrap();
        let f = e.function();
        let mut t = Delaunay::with_domain(e.domain.min, e.domain.max, 7).unwrap();
        let mut rng = 12345u64;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..200 {
            let v = [next(), next(), next()];
            let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            t.insert(v.map(|x| x / n)).unwrap();
        }
        let vb = vertex_boxes(&t, &f, &e.domain, SegmentBudget::default());
        assert!(vb.failure.is_none(), "{:?}", vb.failure);
        assert!(vb.max_offset < 1e-12, "{}", vb.max_offset);
        let mut boxed = 0;
        for (v, b) in vb.boxes.iter().enumerate() {
            let v = v as u32;
            let Some(b) = b else { continue };
            if t.is_far(v) {
                continue;
            }
            boxed += 1;
            let p = t.point(v);
            let (mut lo, mut hi) = (0.0, 0.0);
            for k in 0..3 {
                assert!(b[k].inf() <= p[k] && p[k] <= b[k].sup());
                let (a, c) = (b[k].inf(), b[k].sup());
                let m = if a <= 0.0 && c >= 0.0 {
                    0.0
                } else {
                    a.abs().min(c.abs())
                };
                lo += m * m;
                hi += a.abs().max(c.abs()).powi(2);
            }
            assert!(
                lo <= 1.0 + 1e-15 && hi >= 1.0 - 1e-15,
                "box misses the sphere: {lo} {hi}"
            );
            // Tight: the box reaches no further from p than S is, plus a few ulps
            // (the root's bracket is narrowed on proven signs).
            let to_s = (p.iter().map(|x| x * x).sum::<f64>().sqrt() - 1.0).abs();
            let reach = (0..3)
                .map(|k| (b[k].sup() - p[k]).max(p[k] - b[k].inf()))
                .fold(0.0f64, f64::max);
            assert!(
                reach <= to_s + 2e-15,
                "box reaches {reach}, S is {to_s} away"
            );
        }
        assert_eq!(boxed, 200);
        // A point 0.1 off S: its box reaches the sphere at (0, 0, 1), and the offset
        // says how far P* may be (the robustness checks then decide).
        let off = [0.0, 0.0, 1.1];
        let v = t.insert(off).unwrap();
        let vb = vertex_boxes(&t, &f, &e.domain, SegmentBudget::default());
        assert!(vb.failure.is_none());
        let b = vb.boxes[v as usize].unwrap();
        assert!(b[2].inf() <= 1.0 && b[2].sup() >= 1.1 && vb.max_offset >= 0.1);
        // A point far inside: the search along grad f from (0, 0, 0.5) needs a
        // segment reaching past the domain, but the box is the hull of the point and
        // the root's bracket, [0.5, 1] in z, inside it.
        let mut t = Delaunay::with_domain(e.domain.min, e.domain.max, 7).unwrap();
        let inner = [0.0, 0.0, 0.5];
        let v = t.insert(inner).unwrap();
        let vb = vertex_boxes(&t, &f, &e.domain, SegmentBudget::default());
        assert!(vb.failure.is_none(), "{:?}", vb.failure);
        let b = vb.boxes[v as usize].unwrap();
        assert!(
            b[2].inf() <= 0.5 && b[2].contains(1.0) && b[2].sup() < 1.0 + 1e-12,
            "{b:?}"
        );
        assert!(vb.max_offset >= 0.5);
        // The centre, where grad f = 0, gets no box and is named.
        let mut t = Delaunay::with_domain(e.domain.min, e.domain.max, 7).unwrap();
        let centre = [0.0, 0.0, 0.0];
        t.insert(centre).unwrap();
        let vb = vertex_boxes(&t, &f, &e.domain, SegmentBudget::default());
        let (p, why) = vb.failure.expect("no box where grad f = 0");
        assert_eq!(p, centre, "{why}");
        assert!(why.contains("grad f is zero"), "{why}");
    }
}

/// A formula that says it has no rigorous interval extension (as a Python callback or
/// a mesh's distance does), with the formula's own enclosures behind it.
struct NotRigorous(Formula);

impl Implicit for NotRigorous {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn eval(&self, p: [f64; 3]) -> f64 {
        self.0.eval(p)
    }
    fn eval_interval(&self, b: &IBox) -> Interval {
        self.0.eval_interval(b)
    }
    fn grad(&self, p: [f64; 3]) -> certmesh::implicit::Dual<f64> {
        self.0.grad(p)
    }
    fn grad_interval(&self, b: &IBox) -> certmesh::implicit::Dual<Interval> {
        self.0.grad_interval(b)
    }
    fn hessian(&self, p: [f64; 3]) -> certmesh::implicit::Hyper<f64> {
        self.0.hessian(p)
    }
    fn hessian_interval(&self, b: &IBox) -> certmesh::implicit::Hyper<Interval> {
        self.0.hessian_interval(b)
    }
    fn regularity(&self, b: &IBox) -> certmesh::implicit::Regularity {
        self.0.regularity(b)
    }
    fn is_rigorous(&self) -> bool {
        false
    }
}

/// Through `mesher::run`, a function without a rigorous interval extension gets no
/// claim at all: neither the certificate nor the partial claims (restricted Delaunay,
/// weak sample) an uncertified `bo --certify` run would otherwise carry.
#[test]
fn no_claim_survives_a_non_rigorous_function() {
    let e = catalog::get("sphere").unwrap();
    let f = NotRigorous(e.function());
    let m = bo(0.3, 0.03, &[], |_| {});
    let direct = m.mesh(&f, &e.domain, &NoProgress).unwrap();
    assert!(
        !direct.certificate.claims().is_empty(),
        "the test needs a claiming run"
    );
    let r = certmesh::mesher::run(&m, &f, &e.domain, &NoProgress).unwrap();
    assert!(!r.output.certificate.is_certified());
    assert!(
        r.output.certificate.claims().is_empty(),
        "{:?}",
        r.output.certificate
    );
    assert!(r.output.certificate.claims_typed().is_empty());
    // The reach bound (and so the isotopy) refuses such a function outright.
    let err = bo_reach("6")
        .mesh(&f, &e.domain, &NoProgress)
        .unwrap_err()
        .to_string();
    assert!(err.contains("not rigorous"), "{err}");
}

/// Built from options without `--time-limit`, every mesher whose box or vertex budget
/// can take minutes to reach has the default wall-clock limit; a given limit wins.
#[test]
fn refinement_meshers_have_a_default_time_limit() {
    use certmesh::mesher::options::DEFAULT_TIME_LIMIT;
    use certmesh::restricted_delaunay::curve::BoissonnatOudot2;
    use certmesh::restricted_delaunay::{bo::BoissonnatOudot, cdrr::ChengDeyRamosRay};
    use certmesh::subdivision::engine::SubdivisionParams;
    use certmesh::subdivision::plantinga_vegter::PvCriterion;
    use certmesh::subdivision::snyder::SnyderCriterion;
    for (given, want) in [(None, DEFAULT_TIME_LIMIT), (Some(2.5), 2.5)] {
        let o = MesherOptions {
            time_limit: given,
            ..Default::default()
        };
        let got = [
            BoissonnatOudot::from_options(&o).unwrap().time_limit,
            ChengDeyRamosRay::from_options(&o).unwrap().time_limit,
            BoissonnatOudot2::from_options(&o).unwrap().time_limit,
            SubdivisionParams::<PvCriterion>::from_options(&o, 3)
                .unwrap()
                .time_limit,
            SubdivisionParams::<SnyderCriterion>::from_options(&o, 2)
                .unwrap()
                .time_limit,
        ];
        assert_eq!(got, [Some(want); 5], "given {given:?}");
    }
}

/// A facet size far beyond the surface's size still seeds a proper triangle at each
/// critical point: the seed radius (facet_size / 4) is quartered until the three
/// projected points are apart. With facet_size 1e6 on the unit sphere the three
/// projections used to land on one point and the refinement ran to its time limit
/// (185,107 vertices in 20 s), or with 1e20 no facet was seeded at all.
#[test]
fn huge_facet_sizes_still_seed_the_sphere() {
    for size in [1e6, 1e20] {
        let m = bo(size, 0.02, &[], |o| {
            o.certify = false;
            o.time_limit = Some(20.0);
        });
        let (_, _, out, mesh) = run("sphere", &m);
        assert_eq!(
            stat(&out, "refinement_complete"),
            true,
            "{size}: {:?}",
            out.stats
        );
        assert!(
            mesh.vertices.len() < 2_000,
            "{size}: {} vertices",
            mesh.vertices.len()
        );
        let t = analyze(&mesh).unwrap();
        assert!(t.closed && t.manifold && t.components == 1, "{size}: {t:?}");
        assert_eq!(t.genus, vec![0]);
    }
}
