//! Boissonnat–Oudot refinement (`--algo bo`) on catalog surfaces at CGAL-style criteria
//! (angle 30°, radius 0.1 and distance 0.01 on the catalog boxes), float mode and with
//! `--certify` (interval re-derivation of the restricted triangulation and the
//! certified reach bound). `benches/cgal/` holds the kernel comparison with CGAL.
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

criterion_group!(benches, bench);
criterion_main!(benches);
