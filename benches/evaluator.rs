//! Tape evaluation throughput on the catalog's genus-2 polynomial (issue 2 targets:
//! >= 20 M f64 evaluations/s and >= 5 M interval boxes/s on one core; issue 20, batch
//! evaluation: >= 100 M and >= 20 M).
//!
//! Two groups with the same benchmarks: `genus2` on criterion's wall clock, and
//! `genus2_cpu` on this thread's CPU clock (`CLOCK_THREAD_CPUTIME_ID`), which measures
//! the time the benchmark actually ran on a core: on a shared, overloaded machine the
//! wall clock mostly measures the waiting (`cargo bench --bench evaluator -- cpu`).
use certmesh::implicit::batch::BatchScratch;
use certmesh::implicit::number::point;
use certmesh::{catalog, Implicit};
use criterion::measurement::{Measurement, ValueFormatter};
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use inari::Interval;
use std::time::Duration;

/// Per-thread CPU time as a criterion measurement.
struct ThreadCpuTime;

fn thread_cpu_now() -> Duration {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: a valid clock id and a valid out-pointer.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32)
}

struct NsFormatter;

impl ValueFormatter for NsFormatter {
    fn scale_values(&self, _typical: f64, _values: &mut [f64]) -> &'static str {
        "ns (cpu)"
    }
    fn scale_throughputs(&self, _typical: f64, t: &Throughput, values: &mut [f64]) -> &'static str {
        let n = match t {
            Throughput::Elements(n) | Throughput::Bytes(n) | Throughput::BytesDecimal(n) => *n,
        } as f64;
        for v in values.iter_mut() {
            *v = n * 1e3 / *v; // elements per ns * 1e9 / 1e6
        }
        "Melem/s (cpu)"
    }
    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

impl Measurement for ThreadCpuTime {
    type Intermediate = Duration;
    type Value = Duration;
    fn start(&self) -> Duration {
        thread_cpu_now()
    }
    fn end(&self, i: Duration) -> Duration {
        thread_cpu_now() - i
    }
    fn add(&self, a: &Duration, b: &Duration) -> Duration {
        *a + *b
    }
    fn zero(&self) -> Duration {
        Duration::ZERO
    }
    fn to_f64(&self, v: &Duration) -> f64 {
        v.as_nanos() as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        &NsFormatter
    }
}

fn bench(c: &mut Criterion) {
    benches_in(c, "genus2");
}

fn bench_cpu(c: &mut Criterion<ThreadCpuTime>) {
    benches_in(c, "genus2_cpu");
}

fn benches_in<M: Measurement>(c: &mut Criterion<M>, group: &str) {
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
    let mut g = c.benchmark_group(group);
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
    g.bench_function("hessian_f64", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for p in &pts {
                s += f.hessian(black_box(*p)).h[0];
            }
            s
        })
    });
    g.bench_function("hessian_interval", |b| {
        b.iter(|| {
            let mut s = point(0.0);
            for q in &boxes {
                s = s + f.hessian_interval(black_box(q)).h[0];
            }
            s
        })
    });
    // Batch (SIMD) evaluation: the same points and boxes, `LANES` per pass of the tape
    // (src/implicit/batch.rs; issue 20 targets: >= 100 M f64 evaluations/s and >= 20 M
    // interval boxes/s on one core).
    let xs: [Vec<f64>; 3] = [0, 1, 2].map(|a| pts.iter().map(|p| p[a]).collect());
    g.bench_function("f64_batch", |b| {
        let mut out = vec![0.0; n];
        b.iter(|| {
            f.eval_batch([&xs[0], &xs[1], &xs[2]], black_box(&mut out));
            out[n - 1]
        })
    });
    g.bench_function("interval_batch", |b| {
        let mut out = vec![Interval::EMPTY; n];
        b.iter(|| {
            f.eval_interval_batch(black_box(&boxes), &mut out);
            out[n - 1]
        })
    });
    let lo: [Vec<f64>; 3] = [0, 1, 2].map(|a| boxes.iter().map(|q| q[a].inf()).collect());
    let hi: [Vec<f64>; 3] = [0, 1, 2].map(|a| boxes.iter().map(|q| q[a].sup()).collect());
    g.bench_function("interval_batch_soa", |b| {
        let (mut ol, mut oh) = (vec![0.0; n], vec![0.0; n]);
        let mut s = BatchScratch::default();
        b.iter(|| {
            f.tape().eval_iv_batch(
                [&lo[0], &lo[1], &lo[2]],
                [&hi[0], &hi[1], &hi[2]],
                black_box(&mut ol),
                &mut oh,
                &mut s,
            );
            oh[n - 1]
        })
    });
    // Reference: the same tape on inari intervals through the generic interpreter
    // (what `interval` costs without the `Iv` kernel).
    g.bench_function("interval_inari_generic", |b| {
        let mut regs = Vec::new();
        b.iter(|| {
            let mut s = point(0.0);
            for q in &boxes {
                s = s + f.tape().eval(black_box(q), &mut regs);
            }
            s
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_group! {
    name = cpu;
    config = Criterion::default().with_measurement(ThreadCpuTime);
    targets = bench_cpu
}
criterion_main!(benches, cpu);
