//! `certify`: the topological-ball-property certificate of anyone's mesh. It must never
//! certify a wrong mesh: marching cubes that merges the two spheres of `two-spheres`,
//! that loses handles of `genus5` or breaks `thin-torus`, meshes with a triangle
//! removed or added; and whenever it certifies, the restricted triangulation's
//! components and genera (computed independently, by the combinatorial topology of
//! `metrics::topology`) are the surface's.
use certmesh::catalog;
use certmesh::kernel::delaunay::Delaunay;
use certmesh::kernel::geom::Aabb;
use certmesh::marching::MarchingCubes;
use certmesh::mesh::TriMesh;
use certmesh::mesher::options::MesherOptions;
use certmesh::mesher::{Mesh, Mesher, NoProgress};
use certmesh::metrics::topology::analyze;
use certmesh::restricted_delaunay::certify::{certify_mesh, CertifyOptions};
use certmesh::restricted_delaunay::tbp::{self, TbpOptions};
use certmesh::restricted_delaunay::ChengDeyRamosRay;
use certmesh::Formula;
use proptest::prelude::*;

fn surface(out: &certmesh::mesher::MeshOutput) -> TriMesh {
    match &out.mesh {
        Mesh::Surface(s) => s.clone(),
        _ => panic!("a surface mesher"),
    }
}

fn mc(name: &str, resolution: usize) -> TriMesh {
    let e = catalog::get(name).unwrap();
    let o = MesherOptions {
        resolution: Some(resolution),
        ..Default::default()
    };
    let m = MarchingCubes::from_options(&o).unwrap();
    surface(&m.mesh(&e.function(), &e.domain, &NoProgress).unwrap())
}

fn cdrr(name: &str) -> TriMesh {
    let e = catalog::get(name).unwrap();
    let m = ChengDeyRamosRay::default();
    let out = m.mesh(&e.function(), &e.domain, &NoProgress).unwrap();
    assert!(
        out.certificate.is_certified(),
        "{name}: {:?}",
        out.certificate
    );
    surface(&out)
}

/// (components, sorted genera) of a closed orientable manifold mesh, else `None`.
fn topology(m: &TriMesh) -> Option<(usize, Vec<usize>)> {
    let t = analyze(m).unwrap();
    (t.closed && t.manifold && t.orientable).then(|| (t.components, t.genus.clone()))
}

fn expected(name: &str) -> (usize, Vec<usize>) {
    let t = catalog::get(name).unwrap().topology.unwrap();
    let mut g = t.genus.to_vec();
    g.sort_unstable();
    (t.components, g)
}

fn certify(m: &TriMesh, name: &str) -> certmesh::restricted_delaunay::certify::CertifyReport {
    let e = catalog::get(name).unwrap();
    certify_mesh(m, &e.function(), &e.domain, &CertifyOptions::default())
        .unwrap()
        .0
}

#[test]
fn wrong_marching_cubes_meshes_are_never_certified() {
    // Each of these has the wrong topology (checked here, independently of certify).
    for (name, res) in [
        ("two-spheres", 21),
        ("two-spheres", 35),
        ("genus5", 12),
        ("genus2", 8),
        ("thin-torus", 10),
    ] {
        let m = mc(name, res);
        assert_ne!(
            topology(&m),
            Some(expected(name)),
            "{name} at {res} is right"
        );
        let r = certify(&m, name);
        assert!(!r.homeomorphic, "{name} at {res}: {}", r.verdict);
        assert!(r.verdict.starts_with("not certified"), "{}", r.verdict);
        // Marching-cubes vertices are not the restricted Delaunay triangulation's.
        assert!(!r.is_rdt && r.mesh_triangles_not_in_rdt > 0);
    }
}

#[test]
fn cdrr_outputs_are_certified_and_edits_of_them_are_not() {
    for name in ["sphere", "torus", "two-spheres"] {
        let m = cdrr(name);
        assert_eq!(topology(&m), Some(expected(name)), "{name}");
        let r = certify(&m, name);
        assert!(
            r.homeomorphic && r.is_rdt && r.tbp.holds,
            "{name}: {}",
            r.verdict
        );
        assert!(r.max_f_over_grad.unwrap() < 1e-9, "{:?}", r.max_f_over_grad);
        // One triangle removed: a hole, never certified; the missing facet is named.
        let mut holed = m.clone();
        let gone = holed.triangles.pop().unwrap();
        let r = certify(&holed, name);
        assert!(!r.homeomorphic && !r.is_rdt, "{name}");
        assert_eq!(r.rdt_facets_not_in_mesh, 1);
        let mut named = r.differing[0].vertices;
        let mut g = gone;
        named.sort_unstable();
        g.sort_unstable();
        assert_eq!(named, g);
        // A triangle duplicated (with the other orientation): not the RDT.
        let mut dup = m.clone();
        let t0 = dup.triangles[0];
        dup.triangles.push([t0[0], t0[2], t0[1]]);
        assert!(!certify(&dup, name).homeomorphic, "{name}");
        // A vertex doubled (a copy at the same point) and half of its triangles moved
        // to the copy: the same triangles as point sets, but the file's surface is cut
        // open there (checked independently by the combinatorial topology), so it is
        // not certified; the report says the merged copy would be.
        let mut cut = m.clone();
        let v = cut.triangles[0][0];
        let star: Vec<usize> = (0..cut.triangles.len())
            .filter(|&t| cut.triangles[t].contains(&v))
            .collect();
        let copy = cut.vertices.len() as u32;
        cut.vertices.push(cut.vertices[v as usize]);
        for &t in &star[..star.len() / 2] {
            for w in cut.triangles[t].iter_mut().filter(|w| **w == v) {
                *w = copy;
            }
        }
        assert!(
            topology(&cut).is_none(),
            "{name}: the cut mesh is a closed manifold"
        );
        let r = certify(&cut, name);
        assert!(!r.homeomorphic, "{name}: {}", r.verdict);
        assert_eq!(r.duplicate_vertices, 1);
        assert!(r.is_rdt && r.tbp.holds, "{name}: {}", r.verdict);
        assert!(r.verdict.contains("would be certified"), "{}", r.verdict);
    }
}

#[test]
fn a_mesh_of_another_surface_is_not_certified() {
    // The torus's certified sample checked against the sphere: the vertices are far
    // from the sphere, the torus mesh is not its restricted triangulation.
    let m = cdrr("torus");
    let r = certify(&m, "sphere");
    assert!(!r.homeomorphic, "{}", r.verdict);
    // Sphere vertices against a thin torus: the torus lies inside Voronoi cells of
    // the sphere's sample, unsampled: test (4) or (1) must fail.
    let s = cdrr("sphere");
    let r = certify(&s, "thin-torus");
    assert!(!r.homeomorphic && !r.tbp.holds, "{}", r.verdict);
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let e = catalog::get("sphere").unwrap();
    let f = e.function();
    let empty = TriMesh {
        vertices: vec![[0.0; 3]; 3],
        triangles: vec![],
    };
    assert!(certify_mesh(&empty, &f, &e.domain, &CertifyOptions::default()).is_err());
    let bad = TriMesh {
        vertices: vec![[0.0; 3]; 3],
        triangles: vec![[0, 1, 7]],
    };
    let err = certify_mesh(&bad, &f, &e.domain, &CertifyOptions::default()).unwrap_err();
    assert!(err.to_string().contains("vertex 7"), "{err}");
    let nan = TriMesh {
        vertices: vec![[f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        triangles: vec![[0, 1, 2]],
    };
    assert!(certify_mesh(&nan, &f, &e.domain, &CertifyOptions::default()).is_err());
    // A vertex outside the domain: a set-up failure, not certified.
    let s = cdrr("sphere");
    let mut out = s.clone();
    out.vertices.push([5.0, 0.0, 0.0]);
    let n = out.vertices.len() as u32 - 1;
    out.triangles.push([n, 0, 1]);
    let r = certify(&out, "sphere");
    assert!(!r.homeomorphic && r.vertices_outside_domain == 1);
}

/// f of one or two ellipsoids (the product of their quadrics: two disjoint ones give a
/// surface with two sphere components).
fn ellipsoids(e: &[([f64; 3], [f64; 3])]) -> String {
    e.iter()
        .map(|(c, a)| {
            format!(
                "((x - {})^2/{} + (y - {})^2/{} + (z - {})^2/{} - 1)",
                c[0],
                a[0] * a[0],
                c[1],
                a[1] * a[1],
                c[2],
                a[2] * a[2]
            )
        })
        .collect::<Vec<_>>()
        .join("*")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40, .. ProptestConfig::default() })]
    /// Random ellipsoids (one, or two disjoint ones), random samples near them (points
    /// of the surface pushed off it by up to 5%): whenever the topological ball
    /// property is certified, the restricted triangulation is a closed manifold with
    /// the surface's components and genera (all spheres).
    #[test]
    fn certified_random_samples_have_the_right_topology(
        axes in prop::array::uniform3(0.3f64..0.9),
        axes2 in prop::array::uniform3(0.2f64..0.5),
        two in any::<bool>(),
        n in 6usize..120,
        seed in 0u64..1000,
        noise in 0.0f64..0.05,
    ) {
        let mut parts = vec![([-0.1, 0.0, 0.0], axes)];
        if two {
            parts[0].0 = [-1.0, 0.0, 0.0];
            parts.push(([0.6, 0.1, -0.1], axes2));
        }
        let f = Formula::with_dim(&ellipsoids(&parts), 3).unwrap();
        let domain = Aabb { min: [-2.2; 3], max: [2.2; 3] };
        // Points: random directions scaled onto each ellipsoid, then off it.
        let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let mut rnd = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((s >> 11) as f64) / ((1u64 << 53) as f64)
        };
        let mut pts = Vec::new();
        for k in 0..n {
            let (c, a) = parts[k % parts.len()];
            let z: f64 = 2.0 * rnd() - 1.0;
            let th = std::f64::consts::TAU * rnd();
            let r = (1.0 - z * z).sqrt();
            let u = [r * th.cos(), r * th.sin(), z];
            let scale = 1.0 + noise * (2.0 * rnd() - 1.0);
            pts.push([0, 1, 2].map(|i| c[i] + scale * a[i] * u[i]));
        }
        let (t, _) = Delaunay::from_points(&pts, seed).unwrap();
        let check = tbp::check(&t, &f, &domain, &TbpOptions::default());
        if check.report.holds {
            let tris: Vec<[u32; 3]> = check.rdt.facets.iter().map(|x| x.v).collect();
            let mesh = TriMesh { vertices: t.points().to_vec(), triangles: tris };
            let want = (parts.len(), vec![0; parts.len()]);
            prop_assert_eq!(topology(&mesh), Some(want));
        }
    }
}

/// The report as JSON without its timings (the only fields allowed to differ).
fn untimed(r: &certmesh::restricted_delaunay::certify::CertifyReport) -> serde_json::Value {
    let mut v = serde_json::to_value(r).unwrap();
    v.as_object_mut().unwrap().remove("seconds");
    v["tbp"].as_object_mut().unwrap().remove("seconds");
    v
}

fn in_pool<T: Send>(threads: usize, job: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(job)
}

/// The checks run in parallel chunks (the Voronoi-edge scan, the facet and cell
/// covers): one thread and several give the same report — the same restricted
/// triangulation, the same failures in the same order — on a certified mesh and on
/// a wrong one.
#[test]
fn parallel_and_serial_certify_agree() {
    for (m, name, certified) in [
        (cdrr("torus"), "torus", true),
        (mc("two-spheres", 21), "two-spheres", false),
    ] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        let run = |threads| {
            in_pool(threads, || {
                certify_mesh(&m, &f, &e.domain, &CertifyOptions::default()).unwrap()
            })
        };
        let (r1, rdt1) = run(1);
        let (r4, rdt4) = run(4);
        assert_eq!(r1.homeomorphic, certified, "{name}: {}", r1.verdict);
        assert_eq!(untimed(&r1), untimed(&r4), "{name}");
        assert_eq!(rdt1.vertices, rdt4.vertices, "{name}");
        assert_eq!(rdt1.triangles, rdt4.triangles, "{name}");
    }
}

/// The scan's batched one-enclosure pre-test only settles segments free of S: against
/// plain certified root isolation on every dual segment (no pre-test), every facet has
/// the same number of crossings wherever the plain isolation is complete, and a facet
/// the scan leaves undecided is undecided by the plain isolation too.
#[test]
fn the_scan_pre_test_agrees_with_plain_root_isolation() {
    use certmesh::implicit::ops::{isolate_segment, SegmentBudget};
    use certmesh::restricted_delaunay::restricted::{
        certified_circumcentres, facet_vertices, key, scan_certified,
    };
    use std::collections::HashMap;
    for (name, res) in [("two-spheres", 21), ("torus", 14)] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        let m = mc(name, res);
        let (t, _) = Delaunay::from_points(&m.vertices, 1).unwrap();
        let cc = certified_circumcentres(&t);
        let s = scan_certified(&t, &f, &e.domain, &cc, SegmentBudget::default());
        let crossings: HashMap<_, usize> = s
            .facets
            .iter()
            .map(|x| (key(x.v), x.test.crossings.len()))
            .collect();
        let undecided: Vec<_> = s.undecided.iter().map(|u| key(u.v)).collect();
        let dbox = e.domain.intervals();
        let (mut compared, mut restricted) = (0, 0);
        for (c, i, d, _) in t.facets(false) {
            let fv = facet_vertices(&t, c, i, true);
            if fv.iter().any(|&v| t.is_far(v)) {
                continue;
            }
            let k = key(fv);
            let (Some(a), Some(b)) = (cc[c as usize], cc[d as usize]) else {
                assert!(undecided.contains(&k));
                continue;
            };
            let r = isolate_segment(&f, &a, &b, Some(&dbox), SegmentBudget::default());
            if undecided.contains(&k) {
                assert!(!r.complete(), "{name}: {k:?} undecided by the scan only");
                continue;
            }
            if r.complete() {
                compared += 1;
                restricted += usize::from(!r.roots.is_empty());
                assert_eq!(
                    crossings.get(&k).copied().unwrap_or(0),
                    r.roots.len(),
                    "{name}: facet {k:?}"
                );
            }
        }
        assert!(
            compared > 1000 && restricted > 100,
            "{name}: {compared} {restricted}"
        );
        let decided = s
            .facets
            .iter()
            .filter(|x| !undecided.contains(&key(x.v)))
            .count();
        assert_eq!(restricted, decided, "{name}");
    }
}

/// A time limit cuts the check short: the faces not checked are not proven, the report
/// says the limit passed, and nothing is certified. The same mesh without a limit is
/// certified (so the cut, not the mesh, is what stops it).
#[test]
fn a_check_cut_by_its_time_limit_certifies_nothing() {
    let m = cdrr("sphere");
    let e = catalog::get("sphere").unwrap();
    let free = certify(&m, "sphere");
    assert!(free.homeomorphic && !free.tbp.timed_out, "{}", free.verdict);
    let o = CertifyOptions {
        time_limit: Some(1e-9),
        ..Default::default()
    };
    let (r, _) = certify_mesh(&m, &e.function(), &e.domain, &o).unwrap();
    assert!(r.tbp.timed_out, "{:?}", r.tbp);
    assert!(!r.tbp.holds && !r.homeomorphic);
    assert_eq!(r.tbp.boxes, 0, "no cover may run after the deadline");
    assert!(r.verdict.contains("time limit"), "{}", r.verdict);
    // The check itself: a deadline already passed leaves tests (2)-(4) not run.
    let (t, _) = Delaunay::from_points(&m.vertices, 1).unwrap();
    let o = TbpOptions {
        deadline: Some(std::time::Instant::now()),
        ..Default::default()
    };
    let c = tbp::check(&t, &e.function(), &e.domain, &o);
    assert!(c.report.timed_out && !c.report.holds);
    assert_eq!(
        c.report.skipped,
        vec![tbp::Test::Manifold, tbp::Test::Facet, tbp::Test::Cell]
    );
}

/// A mesh whose check would need more than the memory limit is refused before any
/// work, naming its size (three million vertices, one triangle each).
#[test]
fn a_mesh_too_large_to_check_is_refused_up_front() {
    use certmesh::restricted_delaunay::certify::{estimated_bytes, MAX_BYTES};
    let n = (MAX_BYTES / estimated_bytes(1)) as usize + 3;
    let n = n.div_ceil(3) * 3;
    let vertices: Vec<[f64; 3]> = (0..n).map(|i| [i as f64 * 1e-6, 0.0, 0.0]).collect();
    let triangles: Vec<[u32; 3]> = (0..n as u32 / 3)
        .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
        .collect();
    let m = TriMesh {
        vertices,
        triangles,
    };
    let e = catalog::get("sphere").unwrap();
    let err = certify_mesh(&m, &e.function(), &e.domain, &CertifyOptions::default())
        .err()
        .expect("refused");
    let msg = err.to_string();
    assert!(
        msg.contains(&format!("{n} vertices")) && msg.contains("GB limit"),
        "{msg}"
    );
}

/// cdrr's time limit bounds its checks: a run stopped by it does not go on to the
/// final check with the full cover budget (which took 30 s after a 5 s limit on two
/// touching spheres), and says why it stopped.
#[test]
fn cdrr_stops_its_checks_at_the_time_limit() {
    let f = Formula::surface("((x-0.5)^2+y^2+z^2-0.25)*((x+0.5)^2+y^2+z^2-0.25)").unwrap();
    let domain = Aabb {
        min: [-1.2; 3],
        max: [1.2; 3],
    };
    let m = ChengDeyRamosRay {
        time_limit: Some(1e-6),
        ..Default::default()
    };
    let out = m.mesh(&f, &domain, &NoProgress).unwrap();
    assert!(!out.certificate.is_certified());
    let stats = &out.stats;
    let stop = stats["stop_reason"].as_str().unwrap();
    assert!(stop.contains("time limit"), "{stop}");
    // The report is the first round's check (cut short by its failing test (1)), not
    // a final check with every test run.
    assert_eq!(stats["tbp"]["boxes"], 0, "no cover after the deadline");
    assert!(!stats["tbp"]["skipped"].as_array().unwrap().is_empty());
}
