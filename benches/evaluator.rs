//! Tape evaluation throughput on the catalog's genus-2 polynomial (issue 2 targets:
//! >= 20 M f64 evaluations/s and >= 5 M interval boxes/s on one core).
use certmesh::implicit::number::point;
use certmesh::{catalog, Implicit};
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use inari::Interval;

fn bench(c: &mut Criterion) {
    let f = catalog::get("genus2").unwrap().function();
    let n = 10_000usize;
    let pts: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            [
                1.4 * (t * 17.0).sin(),
                1.4 * (t * 23.0).cos(),
                1.4 * (2.0 * t - 1.0),
            ]
        })
        .collect();
    let boxes: Vec<[Interval; 3]> = pts
        .iter()
        .map(|p| p.map(|x| Interval::try_from((x, x + 0.01)).unwrap()))
        .collect();
    let mut g = c.benchmark_group("genus2");
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("f64", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for p in &pts {
                s += f.eval(black_box(*p));
            }
            s
        })
    });
    g.bench_function("interval", |b| {
        b.iter(|| {
            let mut s = point(0.0);
            for q in &boxes {
                s = s + f.eval_interval(black_box(q));
            }
            s
        })
    });
    g.bench_function("gradient_f64", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for p in &pts {
                s += f.grad(black_box(*p)).g[0];
            }
            s
        })
    });
    g.bench_function("gradient_interval", |b| {
        b.iter(|| {
            let mut s = point(0.0);
            for q in &boxes {
                s = s + f.grad_interval(black_box(q)).g[0];
            }
            s
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
