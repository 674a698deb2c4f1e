//! The report of `certmesh mesh` (issue 20: at most 25% of the mesher's time on metrics
//! and writing), part by part, on the 256³ marching-cubes torus (pruned, 278,272
//! triangles): the mesher itself for scale, the topology analysis, the angle ranges,
//! the fidelity at each `--metrics` level, the whole report at each level, and writing
//! the mesh as binary PLY to a memory buffer. Run on 1 and 2 threads with
//! `RAYON_NUM_THREADS=1 cargo bench --bench report` (and `=2`).
use certmesh::catalog;
use certmesh::harness::compare::{fidelity_params, Metrics};
use certmesh::harness::report::{self, DomainSource};
use certmesh::io::ply::{self, PlyEncoding};
use certmesh::mesher::options::MesherOptions;
use certmesh::mesher::{self, registry, NoProgress};
use certmesh::metrics::{self, angles, fidelity};
use criterion::{black_box, criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    let e = catalog::get("torus").unwrap();
    let f = e.function();
    let o = MesherOptions {
        resolution: Some(256),
        prune: true,
        ..Default::default()
    };
    let m = registry::build("mc", 3, &o).unwrap();
    let run = mesher::run(m.as_ref(), &f, &e.domain, &NoProgress).unwrap();
    let surf = run.output.mesh.surface().unwrap().clone();
    let params = fidelity_params(&e.domain, 3);
    let mut g = c.benchmark_group("report_mc_torus_256");
    g.sample_size(20);
    g.bench_function("mesher", |b| {
        b.iter(|| mesher::run(m.as_ref(), &f, &e.domain, &NoProgress).unwrap())
    });
    g.bench_function("topology", |b| {
        b.iter(|| metrics::analyze(black_box(&surf)).unwrap())
    });
    g.bench_function("angles_full", |b| {
        b.iter(|| angles::triangle_ranges(black_box(&surf)).unwrap())
    });
    g.bench_function("angles_fast", |b| {
        b.iter(|| angles::triangle_extremes(black_box(&surf)).unwrap())
    });
    for (name, level) in [("fast", Metrics::Fast), ("full", Metrics::Full)] {
        // What `evaluate_with` asks at each level.
        let p = params
            .clone()
            .hausdorff_only(level == Metrics::Fast)
            .project_vertices(level != Metrics::Fast);
        g.bench_function(format!("fidelity_{name}"), |b| {
            b.iter(|| fidelity::surface_fidelity(black_box(&surf), &f, &p).unwrap())
        });
    }
    for (name, level) in [("fast", Metrics::Fast), ("full", Metrics::Full)] {
        g.bench_function(format!("whole_report_{name}"), |b| {
            b.iter(|| {
                report::mesh_report(
                    "torus",
                    &f,
                    &e.domain,
                    DomainSource::Catalog,
                    e.topology.as_ref(),
                    &run,
                    level,
                )
                .unwrap()
            })
        });
    }
    g.bench_function("write_ply_memory", |b| {
        b.iter(|| {
            let mut buf = Vec::with_capacity(8 << 20);
            ply::write(&mut buf, &surf, PlyEncoding::BinaryLittleEndian).unwrap();
            buf.len()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
