//! The report of `certmesh mesh` (issue 20: at most 25% of the mesher's time on metrics
//! and writing), part by part, on four workloads: the 256³ marching-cubes torus
//! (pruned, 278,272 triangles), and the marching-cubes torus, the marching-tetrahedra
//! torus, the GradNormal and the MidNormal genus-2 surfaces at their default settings
//! (16,912, 52,896, 28,364 and 30,008 triangles; MidNormal's mesh lies farther from
//! the surface than its triangles are wide, so its surface → mesh side falls to the
//! centroid grid). Each group times the mesher itself for scale, the topology
//! analysis, the angle ranges, the fidelity at each `--metrics` level, the whole report
//! at each level, and writing the mesh as binary PLY and as OBJ to a memory buffer; and
//! floors: what any report that looks at every triangle once would pay beside the
//! topology and the angles (one gradient of f per triangle, the cheapest first-order
//! distance estimate; one Newton projection per triangle, the cheapest mesh → surface
//! distance), and the floors of the topology and the angle range themselves (star lists
//! and edge count; signed squared cosines); and the surface → mesh distances of
//! `--metrics fast` by the sweeps the report uses and by the centroid grid. Run on 1
//! and 2 threads with `RAYON_NUM_THREADS=1 cargo bench --bench report` (and `=2`).
use certmesh::catalog;
use certmesh::harness::compare::{fidelity_params, level_fidelity_params, Metrics};
use certmesh::harness::report::{self, DomainSource};
use certmesh::implicit::{ops, Dual, Implicit};
use certmesh::io::obj;
use certmesh::io::ply::{self, PlyEncoding};
use certmesh::mesher::options::MesherOptions;
use certmesh::mesher::{self, registry, NoProgress};
use certmesh::metrics::{self, angles, fidelity, nearest};
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rayon::prelude::*;

/// One workload's group: `name` of the catalog, `algo` at `opts`.
fn workload(c: &mut Criterion, group: &str, name: &str, algo: &str, opts: &MesherOptions) {
    let e = catalog::get(name).unwrap();
    let f = e.function();
    let m = registry::build(algo, 3, opts).unwrap();
    let run = mesher::run(m.as_ref(), &f, &e.domain, &NoProgress).unwrap();
    let surf = run.output.mesh.surface().unwrap().clone();
    let params = fidelity_params(&e.domain, 3);
    // Each iteration on one of rayon's threads, as `certmesh` runs its command (a
    // parallel call from outside the pool costs two thread switches; the floors are
    // serial and run where they are).
    let pool = rayon::ThreadPoolBuilder::new().build().unwrap();
    let mut g = c.benchmark_group(group);
    g.sample_size(20);
    g.bench_function("mesher", |b| {
        b.iter(|| pool.install(|| mesher::run(m.as_ref(), &f, &e.domain, &NoProgress).unwrap()))
    });
    g.bench_function("topology", |b| {
        b.iter(|| pool.install(|| metrics::analyze(black_box(&surf)).unwrap()))
    });
    g.bench_function("angles_full", |b| {
        b.iter(|| pool.install(|| angles::triangle_ranges(black_box(&surf)).unwrap()))
    });
    g.bench_function("angles_fast", |b| {
        b.iter(|| pool.install(|| angles::triangle_extremes(black_box(&surf)).unwrap()))
    });
    for (level_name, level) in [("fast", Metrics::Fast), ("full", Metrics::Full)] {
        // What `evaluate_with` asks at each level (`fast`: sized to the mesh).
        let p = level_fidelity_params(level, &e.domain, 3, surf.triangles.len());
        g.bench_function(format!("fidelity_{level_name}"), |b| {
            b.iter(|| {
                pool.install(|| fidelity::surface_fidelity(black_box(&surf), &f, &p).unwrap())
            })
        });
    }
    for (level_name, level) in [("fast", Metrics::Fast), ("full", Metrics::Full)] {
        g.bench_function(format!("whole_report_{level_name}"), |b| {
            b.iter(|| {
                pool.install(|| {
                    report::mesh_report(
                        name,
                        &f,
                        &e.domain,
                        DomainSource::Catalog,
                        e.topology.as_ref(),
                        &run,
                        level,
                    )
                    .unwrap()
                })
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
    g.bench_function("write_obj_memory", |b| {
        b.iter(|| {
            let mut buf = Vec::with_capacity(16 << 20);
            obj::write(&mut buf, &surf).unwrap();
            buf.len()
        })
    });
    // The floors: f and ∇f once at every triangle's centroid (batch gradient, one
    // thread: the floor of the work, not of its spreading), and one Newton projection
    // of every centroid with the report's own steps and tolerance.
    let centroids: Vec<[f64; 3]> = (0..surf.triangles.len())
        .map(|t| {
            let [a, b, c] = surf.corners(t);
            [0, 1, 2].map(|k| (a[k] + b[k] + c[k]) / 3.0)
        })
        .collect();
    let mut d = vec![Dual::ZERO; centroids.len()];
    g.bench_function("floor_one_gradient_per_triangle", |b| {
        b.iter(|| {
            f.grad_batch(black_box(&centroids), &mut d);
            d[0].v
        })
    });
    let tol = 1e-10 * e.domain.diagonal();
    g.bench_function("floor_one_projection_per_triangle", |b| {
        b.iter(|| ops::project_batch(&f, black_box(&centroids), params.newton_steps, tol).len())
    });
    // The surface → mesh distances of `--metrics fast` (its surface points, the mesh
    // → surface estimate as the hint), by the sweeps (what the report does) and by the
    // centroid grid over every triangle (what it did before, and does when the sweeps
    // leave points open): the same distances, bit for bit.
    let fast = level_fidelity_params(Metrics::Fast, &e.domain, 3, surf.triangles.len());
    let (spts, _) =
        fidelity::surface_points_counted(&f, &e.domain, fast.seed_grid, fast.newton_steps, tol);
    let hint = fidelity::surface_fidelity(&surf, &f, &fast)
        .unwrap()
        .hausdorff_mesh_to_surface;
    g.bench_function("surface_to_mesh_sweeps", |b| {
        b.iter(|| pool.install(|| nearest::closest_dist2_all(black_box(&surf), &spts, hint)))
    });
    g.bench_function("surface_to_mesh_centroid_grid", |b| {
        b.iter(|| {
            pool.install(|| {
                let grid = nearest::CentroidGrid::new(black_box(&surf));
                spts.par_iter()
                    .map(|&p| grid.closest_dist2(p))
                    .collect::<Vec<_>>()
            })
        })
    });
    // The floors of the topology and the angle range, one thread each: what any
    // topology that finds every edge pays (every vertex's faces by a counting sort,
    // then every edge counted once, at its smaller vertex), and what any angle range
    // pays (every triangle's corners read, three dot products and three squared
    // lengths, compared as signed squared cosines: no square root, no atan2).
    g.bench_function("floor_star_lists_and_edges", |b| {
        b.iter(|| star_lists_and_edges(surf.vertices.len(), black_box(&surf.triangles)))
    });
    g.bench_function("floor_angle_comparisons", |b| {
        b.iter(|| angle_comparisons(black_box(&surf)))
    });
    g.finish();
}

/// The topology floor: every vertex's faces (count, prefix sums, fill), then the
/// distinct larger neighbours of every vertex (the edges, each once).
fn star_lists_and_edges(nv: usize, tris: &[[u32; 3]]) -> usize {
    let mut start = vec![0u32; nv + 1];
    for t in tris {
        for &v in t {
            start[v as usize + 1] += 1;
        }
    }
    for k in 0..nv {
        start[k + 1] += start[k];
    }
    let mut fill = start[..nv].to_vec();
    let mut faces = vec![0u32; 3 * tris.len()];
    for (f, t) in tris.iter().enumerate() {
        for &v in t {
            let s = &mut fill[v as usize];
            faces[*s as usize] = f as u32;
            *s += 1;
        }
    }
    let mut edges = 0;
    let mut nb = [0u32; 64];
    for v in 0..nv {
        let mut n = 0;
        for &f in &faces[start[v] as usize..start[v + 1] as usize] {
            for w in tris[f as usize] {
                if w > v as u32 && n < nb.len() && !nb[..n].contains(&w) {
                    nb[n] = w;
                    n += 1;
                }
            }
        }
        edges += n;
    }
    edges
}

/// The angle-range floor: the extremes of the signed squared cosines of every angle.
fn angle_comparisons(m: &certmesh::mesh::TriMesh) -> (f64, f64) {
    use certmesh::kernel::geom::{dot, sub};
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| m.vertices[i as usize]);
        let (ab, bc, ca) = (sub(b, a), sub(c, b), sub(a, c));
        let (l0, l1, l2) = (dot(ab, ab), dot(bc, bc), dot(ca, ca));
        for (x, l) in [
            (-dot(ca, ab), l2 * l0),
            (-dot(ab, bc), l0 * l1),
            (-dot(bc, ca), l1 * l2),
        ] {
            let q = x * x.abs() / l;
            lo = lo.min(q);
            hi = hi.max(q);
        }
    }
    (lo, hi)
}

fn bench(c: &mut Criterion) {
    let mc256 = MesherOptions {
        resolution: Some(256),
        prune: true,
        ..Default::default()
    };
    workload(c, "report_mc_torus_256", "torus", "mc", &mc256);
    let defaults = MesherOptions::default();
    workload(c, "report_mc_torus_default", "torus", "mc", &defaults);
    workload(c, "report_mt_torus_default", "torus", "mt", &defaults);
    workload(
        c,
        "report_gradnormal_genus2_default",
        "genus2",
        "gradnormal",
        &defaults,
    );
    workload(
        c,
        "report_midnormal_genus2_default",
        "genus2",
        "midnormal",
        &defaults,
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
