//! Marching cubes on a 256³-cell grid of the catalog torus (257³ vertices):
//! (a) extraction from an already sampled grid, the same work as scikit-image's
//!     `measure.marching_cubes` on a volume (compare with `benches/skimage_mc.py`);
//! (b) end to end: sampling f (the compiled formula tape) plus extraction;
//! (c) end to end with interval pruning (only the vertices of cells near the surface
//!     are evaluated).
//! Set RAYON_NUM_THREADS=1 for single-core figures (scikit-image is single-threaded).
//!
//! Measured (2 shared cores, load average ~10, so absolute figures are pessimistic):
//! (a) 73 ms (89 ms on one thread) vs scikit-image 0.26 `marching_cubes` 386–435 ms on
//! the same float64 volume, run right after (same 139136 vertices, 278272 triangles);
//! (b) 2.05 s, of which sampling 17 M points is 2.0 s; (c) 0.63 s (0.09 M interval and
//! 2.8 M point evaluations).
use certmesh::catalog;
use certmesh::lattice::grid::{Grid, Samples};
use certmesh::marching::{marching_cubes, MarchingCubes};
use certmesh::mesher::{Mesher, NoProgress};
use criterion::{criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    let e = catalog::get("torus").unwrap();
    let f = e.function();
    let grid = Grid::new(&e.domain, 256, 3).unwrap();
    let samples = Samples::sample(&f, &grid, &NoProgress).unwrap();
    let m = marching_cubes(&samples).unwrap();
    eprintln!(
        "torus 256^3: {} vertices, {} triangles",
        m.vertices.len(),
        m.triangles.len()
    );
    let mut g = c.benchmark_group("marching_cubes_torus_256");
    g.sample_size(10);
    g.bench_function("extract_from_sampled_grid", |b| {
        b.iter(|| marching_cubes(&samples).unwrap())
    });
    let mc = MarchingCubes::new().resolution(256);
    g.bench_function("end_to_end_dense", |b| {
        b.iter(|| mc.mesh(&f, &e.domain, &NoProgress).unwrap())
    });
    let mcp = mc.prune(true);
    g.bench_function("end_to_end_pruned", |b| {
        b.iter(|| mcp.mesh(&f, &e.domain, &NoProgress).unwrap())
    });
    g.bench_function("sample_only", |b| {
        b.iter(|| Samples::sample(&f, &grid, &NoProgress).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
