//! GradNormal on the catalog genus-2 surface at the paper's tiling sizes (tetrahedra of
//! the unit cube, Sec. 5.2), and MidNormal alone: the cost should grow linearly with
//! the number of surface-crossing tetrahedra (4× per refinement), not with the tiling.
use certmesh::catalog;
use certmesh::gradnormal::tiling::{Goldberg, SOMMERVILLE_RATIO};
use certmesh::gradnormal::{GradNormal, GradNormalParams, MidNormal};
use certmesh::mesher::{Mesher, NoProgress};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

fn bench(c: &mut Criterion) {
    let entry = catalog::get("genus2").unwrap();
    let f = entry.function();
    let mut g = c.benchmark_group("gradnormal_genus2");
    g.sample_size(10);
    for n in [869_652.0, 6_748_416.0, 52_931_340.0] {
        // The catalog domain [-1.5, 1.5]^3 scaled onto the unit cube.
        let e = 3.0 * Goldberg::scale_for_count(1.0, n, SOMMERVILLE_RATIO);
        let p = GradNormalParams::new().with_scale(e);
        g.bench_with_input(BenchmarkId::new("gradnormal", n as u64), &p, |b, p| {
            b.iter(|| {
                GradNormal::new(p.clone())
                    .mesh(&f, &entry.domain, &NoProgress)
                    .unwrap()
            })
        });
        g.bench_with_input(BenchmarkId::new("midnormal", n as u64), &p, |b, p| {
            b.iter(|| {
                MidNormal::new(p.clone())
                    .mesh(&f, &entry.domain, &NoProgress)
                    .unwrap()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
