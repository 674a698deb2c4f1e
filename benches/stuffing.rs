//! Isosurface stuffing benchmarks: mesh generation *excluding* f (warping + stencils on
//! a prepared lattice, the paper's "mesh generation time"), serial and parallel, on the
//! unit sphere and on a dense domain (a Chebyshev-polynomial lattice of blobs meeting
//! about half of the BCC tetrahedra, like the paper's dense-domain test); and the total
//! time including f for a cheap polynomial.
use certmesh::stuffing::{generate, prepare, StuffingParams};
use certmesh::{Aabb, Formula};
use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};

fn bench(c: &mut Criterion) {
    let cases = [
        ("sphere", "x^2 + y^2 + z^2 - 1", Aabb::cube(1.5), 96usize),
        (
            "dense",
            "(8*x^4 - 8*x^2 + 1) + (8*y^4 - 8*y^2 + 1) + (8*z^4 - 8*z^2 + 1)",
            Aabb::cube(1.0),
            64,
        ),
    ];
    let mut g = c.benchmark_group("stuffing");
    g.sample_size(10);
    for (name, formula, dom, res) in cases {
        let f = Formula::surface(formula).unwrap();
        for parallel in [false, true] {
            let p = StuffingParams::new()
                .with_resolution(res)
                .with_parallel(parallel);
            let field = prepare(&f, &dom, &p).unwrap();
            let ntets = generate(field.clone(), &f, &p).unwrap().mesh.tets.len();
            eprintln!("{name} res {res}: {ntets} tetrahedra");
            g.throughput(Throughput::Elements(ntets as u64));
            let id = format!(
                "{name}-generate-{}",
                if parallel { "parallel" } else { "serial" }
            );
            g.bench_function(&id, |b| {
                b.iter_batched(
                    || field.clone(),
                    |fl| generate(fl, &f, &p).unwrap(),
                    BatchSize::LargeInput,
                )
            });
        }
        let p = StuffingParams::new().with_resolution(res);
        g.bench_function(format!("{name}-total-with-f"), |b| {
            b.iter(|| certmesh::stuffing::stuff(&f, &dom, &p).unwrap())
        });
    }
    g.finish();
}

/// The work after generation (issue 20: at most 30 % of the run): grouping the faces,
/// the boundary surface, the angle summary with the exact orientations, and the exact
/// conformity check, on the sphere at resolution 42 (142,704 tetrahedra, the CGAL
/// comparison's size), each on its own.
fn checks(c: &mut Criterion) {
    use certmesh::stuffing::{check_conforming_faces, quality};
    let f = Formula::surface("x^2 + y^2 + z^2 - 1").unwrap();
    let p = StuffingParams::new().with_resolution(42);
    let m = certmesh::stuffing::stuff(&f, &Aabb::cube(1.5), &p)
        .unwrap()
        .mesh;
    let faces = m.face_buckets(false);
    let boundary = m.boundary_with(&faces);
    let mut g = c.benchmark_group("stuffing_checks");
    g.sample_size(20);
    g.throughput(Throughput::Elements(m.tets.len() as u64));
    g.bench_function("face_buckets", |b| b.iter(|| m.face_buckets(false)));
    g.bench_function("boundary", |b| b.iter(|| m.boundary_with(&faces)));
    g.bench_function("summary_from_faces", |b| {
        b.iter(|| quality::summarize_faces(&m, &faces))
    });
    g.bench_function("summary_per_tetrahedron", |b| {
        b.iter(|| quality::summarize(&m, &boundary))
    });
    g.bench_function("conformity", |b| {
        b.iter(|| check_conforming_faces(&faces, &boundary).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench, checks);
criterion_main!(benches);
