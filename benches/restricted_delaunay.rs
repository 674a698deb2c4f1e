//! Boissonnat–Oudot refinement (`--algo bo`) on catalog surfaces at CGAL-style criteria
//! (angle 30°, radius 0.1 and distance 0.01 on the catalog boxes), float mode and with
//! `--certify` (interval re-derivation of the restricted triangulation and the
//! certified reach bound). `benches/cgal/` holds the kernel comparison with CGAL.
//!
//! Group `certify`: the topological-ball-property certificate of a ~10⁴-vertex mesh
//! (`certmesh certify`; target under 1 s). The mesh is CGAL's genus2 at radius 0.02,
//! distance 0.002 (13 392 vertices), shipped as `data/cgal-genus2-13392.off` (written
//! by `benches/cgal/surface_mesher genus2 30 0.02 0.002 0`); another OFF file may be
//! named by `CERTMESH_CERTIFY_OFF` with its surface in `CERTMESH_CERTIFY_SURFACE`.
//! Group `cdrr`: the Cheng–Dey–Ramos–Ray driver on the catalog.
use certmesh::catalog;
use certmesh::mesher::options::MesherOptions;
use certmesh::mesher::{Mesher, NoProgress};
use certmesh::restricted_delaunay::BoissonnatOudot;
use criterion::{criterion_group, criterion_main, Criterion};
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("bo");
    g.sample_size(10);
    g.warm_up_time(Duration::from_secs(1));
    g.measurement_time(Duration::from_secs(10));
    for name in ["sphere", "torus", "genus2"] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        for certify in [false, true] {
            let m = BoissonnatOudot::from_options(&MesherOptions {
                facet_size: Some(0.1),
                facet_distance: Some(0.01),
                certify,
                ..Default::default()
            })
            .unwrap();
            let id = format!("{name}-0.1-0.01{}", if certify { "-certify" } else { "" });
            g.bench_function(id, |b| {
                b.iter(|| m.mesh(&f, &e.domain, &NoProgress).unwrap().stats.len())
            });
        }
    }
    g.finish();
}

fn bench_certify(c: &mut Criterion) {
    use certmesh::restricted_delaunay::certify::{certify_mesh, CertifyOptions};
    let name = std::env::var("CERTMESH_CERTIFY_SURFACE").unwrap_or_else(|_| "genus2".into());
    let e = catalog::get(&name).unwrap();
    let f = e.function();
    let path = std::env::var("CERTMESH_CERTIFY_OFF").unwrap_or_else(|_| {
        concat!(env!("CARGO_MANIFEST_DIR"), "/data/cgal-genus2-13392.off").into()
    });
    let mesh = certmesh::io::read_tri(&path).unwrap();
    let mut g = c.benchmark_group("certify");
    g.sample_size(10);
    g.warm_up_time(Duration::from_secs(1));
    g.measurement_time(Duration::from_secs(15));
    let o = CertifyOptions::default();
    let id = format!("{name}-{}v", mesh.vertices.len());
    g.bench_function(id, |b| {
        b.iter(|| {
            certify_mesh(&mesh, &f, &e.domain, &o)
                .unwrap()
                .0
                .homeomorphic
        })
    });
    g.finish();
}

fn bench_cdrr(c: &mut Criterion) {
    use certmesh::restricted_delaunay::ChengDeyRamosRay;
    let mut g = c.benchmark_group("cdrr");
    g.sample_size(10);
    g.warm_up_time(Duration::from_secs(1));
    g.measurement_time(Duration::from_secs(10));
    let m = ChengDeyRamosRay::default();
    // Every smooth catalog surface but genus5 (about 14 s a run: 10 samples would take
    // minutes; its single-run time is in papers/meshing-of-surfaces/cdrr.md).
    for name in [
        "sphere",
        "ellipsoid",
        "torus",
        "two-spheres",
        "genus2",
        "tanglecube",
        "thin-torus",
        "paraboloid-cap",
        "blob",
        "superquadric",
    ] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        g.bench_function(name, |b| {
            b.iter(|| m.mesh(&f, &e.domain, &NoProgress).unwrap().stats.len())
        });
    }
    g.finish();
}

criterion_group!(benches, bench, bench_certify, bench_cdrr);
criterion_main!(benches);
