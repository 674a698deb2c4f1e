//! End to end, one group per workload of issue 20: evaluation + mesh + report (the
//! default `--metrics fast`, and `none`) + writing the mesh to a memory buffer, as
//! `certmesh mesh` does minus the process start and the file system. The anchors
//! (scikit-image, the paper's Python) are timed by `scripts/bench.sh`, which writes
//! papers/BENCH.md.
use certmesh::catalog;
use certmesh::gradnormal::tiling::{Goldberg, SOMMERVILLE_RATIO};
use certmesh::harness::report::{self, DomainSource, Metrics};
use certmesh::io::ply::{self, PlyEncoding};
use certmesh::mesher::options::MesherOptions;
use certmesh::mesher::{self, registry, NoProgress};
use criterion::{criterion_group, criterion_main, Criterion};

/// Mesh, report at `level`, write the boundary surface as binary PLY into memory.
fn whole_run(name: &str, algo: &str, o: &MesherOptions, level: Metrics) -> usize {
    let e = catalog::get(name).unwrap();
    let f = e.function();
    let m = registry::build(algo, 3, o).unwrap();
    let run = mesher::run(m.as_ref(), &f, &e.domain, &NoProgress).unwrap();
    let rep = report::mesh_report(
        name,
        &f,
        &e.domain,
        DomainSource::Catalog,
        e.topology.as_ref(),
        &run,
        level,
    )
    .unwrap();
    let mut buf = Vec::new();
    ply::write(
        &mut buf,
        run.output.mesh.surface().unwrap(),
        PlyEncoding::BinaryLittleEndian,
    )
    .unwrap();
    buf.len() + rep.row.faces
}

fn bench(c: &mut Criterion) {
    // Each run on one of rayon's threads, as `certmesh` runs its command.
    let pool = rayon::ThreadPoolBuilder::new().build().unwrap();
    let workloads = [
        (
            "mc_torus_256_pruned",
            "torus",
            "mc",
            MesherOptions {
                resolution: Some(256),
                prune: true,
                ..Default::default()
            },
        ),
        (
            "gradnormal_genus2_52.9M",
            "genus2",
            "gradnormal",
            MesherOptions {
                scale: Some(3.0 * Goldberg::scale_for_count(1.0, 52_931_340.0, SOMMERVILLE_RATIO)),
                ..Default::default()
            },
        ),
        (
            "stuffing_sphere",
            "sphere",
            "stuffing",
            MesherOptions::default(),
        ),
    ];
    for (id, name, algo, o) in workloads {
        let mut g = c.benchmark_group(format!("end_to_end_{id}"));
        g.sample_size(10);
        for (lname, level) in [("fast", Metrics::Fast), ("none", Metrics::None)] {
            g.bench_function(format!("metrics_{lname}"), |b| {
                b.iter(|| pool.install(|| whole_run(name, algo, &o, level)))
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
