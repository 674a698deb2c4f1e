//! The exact González-Vega–Necula sweep (`--algo gvn`) on the design note's classical
//! curves and on dense random curves of degree 4–8 (coefficients in [−10, 10], a
//! fixed seed), and the certificate checker on the same inputs. Targets of issue 16:
//! degree ≤ 6 in < 50 ms, degree 8 in < 0.5 s per curve, shear retries included.
use certmesh::algebraic::bipoly::{from_formula, BiPoly};
use certmesh::algebraic::check::check_curve;
use certmesh::algebraic::sweep::{analyse, SweepParams};
use certmesh::Aabb;
use criterion::{criterion_group, criterion_main, Criterion};
use std::time::Duration;

fn sq(h: f64) -> Aabb {
    Aabb {
        min: [-h, -h, 0.0],
        max: [h, h, 0.0],
    }
}

fn sweep(c: &mut Criterion) {
    let mut g = c.benchmark_group("gvn");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(3));
    let classical = [
        ("lemniscate", "(x^2 + y^2)^2 - 2*(x^2 - y^2)", 2.0),
        ("limacon", "(x^2 + y^2 - x)^2 - (x^2 + y^2)/4", 2.0),
        ("trifolium", "(x^2 + y^2)^2 - (x^3 - 3*x*y^2)", 2.0),
        ("quadrifolium", "(x^2 + y^2)^3 - 4*x^2*y^2", 2.0),
        ("tacnode", "y^2 - x^4", 2.0),
        ("devil", "y^2*(y^2 - 1) - x^2*(x^2 - 2)", 3.0),
        ("t4", "8*x^4 - 8*x^2 + 8*y^4 - 8*y^2 + 2", 2.0),
        ("hyperbola", "x*y - 1", 3.0),
        (
            "degree8-mix",
            "((x^2 + y^2)^2 - 2*(x^2 - y^2))*(x^2 + y^2 - 4)*(x - y^2 + 1)",
            3.0,
        ),
    ];
    let mut inputs: Vec<(String, BiPoly, Aabb)> = classical
        .iter()
        .map(|(n, f, h)| (n.to_string(), from_formula(f).unwrap(), sq(*h)))
        .collect();
    for d in [4, 5, 6, 7, 8] {
        inputs.push((
            format!("dense-d{d}"),
            BiPoly::dense_random(d, 7 + d as u64),
            sq(2.0),
        ));
    }
    // `CERTMESH_GVN_BENCH=lemniscate,t4` restricts the inputs (the first, untimed run
    // of each input happens before criterion's own filter applies).
    if let Ok(only) = std::env::var("CERTMESH_GVN_BENCH") {
        let names: Vec<&str> = only.split(',').map(str::trim).collect();
        inputs.retain(|(n, _, _)| names.contains(&n.as_str()));
    }
    let p = SweepParams::default();
    for (name, f, dom) in &inputs {
        let t = std::time::Instant::now();
        match analyse(f, dom, &p) {
            Ok(r) => {
                eprintln!(
                    "{name}: degree {}, shear {}, {} critical events, resultant degree {}; one run {:.3} s",
                    r.degree,
                    r.shear,
                    r.events.iter().filter(|e| e.critical).count(),
                    r.resultant_degree,
                    t.elapsed().as_secs_f64()
                );
                let cert = r.cert.clone();
                g.bench_function(format!("sweep/{name}"), |b| {
                    b.iter(|| analyse(f, dom, &p).unwrap())
                });
                g.bench_function(format!("check/{name}"), |b| {
                    b.iter(|| check_curve(&cert).unwrap())
                });
            }
            Err(e) => eprintln!("{name}: {e} (after {:.3} s)", t.elapsed().as_secs_f64()),
        }
    }
    g.finish();
}

criterion_group!(benches, sweep);
criterion_main!(benches);
