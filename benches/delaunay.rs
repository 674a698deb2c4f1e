//! Delaunay kernel benchmarks (`kernel::delaunay`): bulk construction (BRIO + Hilbert
//! order, walk, Bowyer–Watson) of 1e5 and 1e6 uniform points in a cube and 1e5 points
//! on a sphere (every in-sphere test nearly degenerate). Throughput is in input points.
//! The targets: ≥ 6e5 points/s uniform, ≥ 3e5 on the sphere, single-threaded.
//! `benches/cgal/run.sh` times CGAL on the same point sets.
use certmesh::kernel::delaunay::{random_points, Delaunay, Sampler};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("delaunay");
    g.sample_size(10);
    g.warm_up_time(Duration::from_secs(1));
    for (name, n, on) in [
        ("uniform-1e5", 100_000usize, Sampler::Uniform),
        ("sphere-1e5", 100_000, Sampler::Sphere),
        ("uniform-1e6", 1_000_000, Sampler::Uniform),
    ] {
        let pts = random_points(n, on, 1);
        g.throughput(Throughput::Elements(n as u64));
        g.measurement_time(Duration::from_secs(if n > 100_000 { 80 } else { 10 }));
        g.bench_function(name, |b| {
            b.iter(|| Delaunay::from_points(&pts, 1).unwrap().0.num_cells())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
