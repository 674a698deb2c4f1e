//! Cheng–Dey–Ramos–Ray refinement (`--algo cdrr`): on the smooth catalog surfaces a
//! closed 2-manifold with the catalog's components and genera (checked by the
//! combinatorial topology of `metrics::topology`, independently of the certificate),
//! certified `homeomorphic (topological ball property)` and never isotopic; the
//! restricted triangulation re-derived from a fresh Delaunay triangulation of the
//! output's vertices (another insertion order) by sign changes along densely sampled
//! Voronoi edges equals the output; the double cone never certified.
use certmesh::catalog;
use certmesh::kernel::delaunay::Delaunay;
use certmesh::kernel::geom::lerp;
use certmesh::mesh::TriMesh;
use certmesh::mesher::options::MesherOptions;
use certmesh::mesher::{Claim, HomeomorphismBy, Mesh, Mesher, NoProgress};
use certmesh::metrics::topology::analyze;
use certmesh::restricted_delaunay::ChengDeyRamosRay;
use std::collections::HashSet;

fn run(name: &str, m: &ChengDeyRamosRay) -> (certmesh::mesher::MeshOutput, TriMesh) {
    let e = catalog::get(name).unwrap();
    let out = m.mesh(&e.function(), &e.domain, &NoProgress).unwrap();
    let s = match &out.mesh {
        Mesh::Surface(s) => s.clone(),
        _ => panic!("cdrr makes surfaces"),
    };
    (out, s)
}

/// Restricted facets (sorted vertex triples of `verts` indices) by dense sampling of
/// each Voronoi edge of a fresh triangulation: a sign change of f along it.
fn sampled_rdt(name: &str, verts: &[[f64; 3]], n: usize) -> HashSet<[u32; 3]> {
    let e = catalog::get(name).unwrap();
    let f = e.function();
    use certmesh::implicit::Implicit;
    let (t, _) = Delaunay::from_points(verts, 7).unwrap();
    let mut out = HashSet::new();
    for (c, i, d, _) in t.facets(true) {
        let cv = t.cell_vertices(c);
        let mut k: Vec<u32> = (0..4)
            .filter(|&j| j != i)
            .map(|j| t.input_index(cv[j]).unwrap() as u32)
            .collect();
        k.sort_unstable();
        let (a, b) = (t.circumcentre(c), t.circumcentre(d));
        let mut prev = f.eval(a);
        let mut crossings = 0;
        for s in 1..=n {
            let v = f.eval(lerp(a, b, s as f64 / n as f64));
            if (v > 0.0) != (prev > 0.0) {
                crossings += 1;
            }
            prev = v;
        }
        if crossings > 0 {
            out.insert([k[0], k[1], k[2]]);
        }
    }
    out
}

fn check_surface(name: &str) {
    let (out, mesh) = run(name, &ChengDeyRamosRay::default());
    let c = &out.certificate;
    assert!(c.is_certified(), "{name}: {c:?}");
    let typed = c.claims_typed();
    assert!(typed.iter().any(|x| matches!(
        x,
        Claim::Homeomorphic {
            by: HomeomorphismBy::TopologicalBallProperty,
            ..
        }
    )));
    assert!(
        !typed.iter().any(|x| x.is_isotopy()),
        "{name}: isotopy claimed"
    );
    assert!(c.claims()[1].starts_with("homeomorphic (topological ball property)"));
    let t = analyze(&mesh).unwrap();
    let want = catalog::get(name).unwrap().topology.unwrap();
    let mut g = want.genus.to_vec();
    g.sort_unstable();
    assert!(t.closed && t.manifold && t.orientable, "{name}: {t:?}");
    assert!(t.consistently_oriented, "{name}");
    assert_eq!(
        (t.components, t.genus.clone()),
        (want.components, g),
        "{name}"
    );
    // The output is the restricted Delaunay triangulation of its vertices.
    let sampled = sampled_rdt(name, &mesh.vertices, 4000);
    let given: HashSet<[u32; 3]> = mesh
        .triangles
        .iter()
        .map(|tr| {
            let mut k = *tr;
            k.sort_unstable();
            k
        })
        .collect();
    assert_eq!(given, sampled, "{name}");
}

#[test]
fn sphere_ellipsoid_torus_two_spheres() {
    for name in ["sphere", "ellipsoid", "torus", "two-spheres"] {
        check_surface(name);
    }
}

#[test]
fn blob_superquadric_paraboloid_cap_genus2_tanglecube() {
    for name in [
        "blob",
        "superquadric",
        "paraboloid-cap",
        "genus2",
        "tanglecube",
    ] {
        check_surface(name);
    }
}

#[test]
fn thin_torus_and_genus5() {
    for name in ["thin-torus", "genus5"] {
        check_surface(name);
    }
}

#[test]
fn the_double_cone_is_never_certified() {
    let (out, _) = run("double-cone", &ChengDeyRamosRay::default());
    assert!(!out.certificate.is_certified());
    assert!(out.certificate.claims_typed().is_empty());
    let r = out.certificate.reason().unwrap();
    assert!(r.contains("domain boundary"), "{r}");
    // Inside a box where the cone does not reach the boundary (a capped cone is not
    // available, so the apex region alone): still never certified.
    let f = certmesh::Formula::with_dim("x^2 + y^2 - z^2 + 0.3*(x^2+y^2+z^2)^2 - 0.02", 3).unwrap();
    let d = certmesh::kernel::geom::Aabb {
        min: [-2.0; 3],
        max: [2.0; 3],
    };
    // A smooth surface with a pinch region: certified only with the right topology.
    let out = ChengDeyRamosRay::default()
        .mesh(&f, &d, &NoProgress)
        .unwrap();
    if out.certificate.is_certified() {
        let m = out.mesh.surface().unwrap();
        let t = analyze(m).unwrap();
        assert!(t.closed && t.manifold);
    }
}

#[test]
fn guards_stop_the_run_and_say_so() {
    let o = MesherOptions {
        max_vertices: Some(12),
        ..Default::default()
    };
    let m = ChengDeyRamosRay::from_options(&o).unwrap();
    let (out, _) = run("genus2", &m);
    assert!(!out.certificate.is_certified());
    let st = &out.stats;
    assert_eq!(st["refinement_complete"], serde_json::json!(false));
    let why = st["stop_reason"].as_str().unwrap();
    assert!(why.contains("vertex budget"), "{why}");
    assert!(out.certificate.reason().unwrap().contains("not proven"));
    // Unknown settings are errors naming the key.
    let mut o = MesherOptions::default();
    o.extra.insert("nope".into(), "1".into());
    assert!(ChengDeyRamosRay::from_options(&o).is_err());
}
