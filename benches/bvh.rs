//! BVH build and closest-point queries on the Stanford bunny (69,451 faces), and the
//! topology/angle metrics on it. Run: `cargo bench --bench bvh`.
use certmesh::kernel::bvh::TriBvh;
use certmesh::mesh::TriMesh;
use certmesh::metrics;
use criterion::{black_box, criterion_group, criterion_main, Criterion};

/// Minimal OBJ reading for the bench only (`v` and `f` lines); the io module owns the
/// real reader.
fn bunny() -> Option<TriMesh> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/data/stanford-bunny.obj");
    let text = std::fs::read_to_string(path).ok()?;
    let mut m = TriMesh::default();
    for line in text.lines() {
        let mut w = line.split_whitespace();
        match w.next() {
            Some("v") => {
                let c: Vec<f64> = w.take(3).filter_map(|x| x.parse().ok()).collect();
                m.vertices.push([c[0], c[1], c[2]]);
            }
            Some("f") => {
                let idx: Vec<u32> = w
                    .filter_map(|x| x.split('/').next()?.parse::<u32>().ok())
                    .map(|i| i - 1)
                    .collect();
                for k in 1..idx.len().saturating_sub(1) {
                    m.triangles.push([idx[0], idx[k], idx[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Some(m)
}

fn bench(c: &mut Criterion) {
    let Some(m) = bunny() else {
        eprintln!("stanford-bunny.obj not found: nothing to bench");
        return;
    };
    c.bench_function("bvh build bunny", |b| {
        b.iter(|| TriBvh::new(black_box(&m)).unwrap())
    });
    let bvh = TriBvh::new(&m).unwrap();
    // Query points in and around the bunny's bounding box (deterministic).
    let bb = certmesh::Aabb::of_points(&m.vertices)
        .unwrap()
        .inflate(0.02);
    let mut s = 1u64;
    let mut rnd = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let pts: Vec<[f64; 3]> = (0..1024)
        .map(|_| [0, 1, 2].map(|k| bb.min[k] + rnd() * (bb.max[k] - bb.min[k])))
        .collect();
    let near: Vec<[f64; 3]> = m
        .vertices
        .iter()
        .step_by(37)
        .take(1024)
        .map(|p| [p[0] + 1e-3, p[1] - 5e-4, p[2] + 2e-4])
        .collect();
    c.bench_function("closest point bunny, 1024 box points", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for &p in &pts {
                acc += bvh.closest(p).unwrap().dist2;
            }
            acc
        })
    });
    c.bench_function("closest point bunny, 1024 near-surface points", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for &p in &near {
                acc += bvh.closest(p).unwrap().dist2;
            }
            acc
        })
    });
    c.bench_function("stats bunny (topology + angles)", |b| {
        b.iter(|| metrics::stats(black_box(&m), None).unwrap())
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
