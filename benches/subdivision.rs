//! Time to a certified mesh for the subdivision meshers, and boxes processed per second
//! (criterion's throughput = boxes of the run, leaves + internal).
use certmesh::catalog;
use certmesh::mesher::{Mesher, NoProgress};
use certmesh::subdivision::plantinga_vegter::PlantingaVegter;
use certmesh::subdivision::snyder::{Snyder, SnyderParams};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("subdivision");
    g.sample_size(10);
    for name in ["genus5", "tanglecube"] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        let meshers: Vec<(&str, Box<dyn Mesher>)> = vec![
            ("pv", Box::new(PlantingaVegter::default())),
            (
                "snyder-shift-d14",
                Box::new(Snyder::new(
                    SnyderParams::new(3)
                        .with_max_depth(14)
                        .with_generic_shift(true),
                )),
            ),
        ];
        for (label, m) in meshers {
            let out = m.mesh(&f, &e.domain, &NoProgress).unwrap();
            let boxes = out.stats["boxes"].as_u64().unwrap();
            eprintln!(
                "{label} {name}: {boxes} boxes, certified = {}",
                out.certificate.is_certified()
            );
            g.throughput(Throughput::Elements(boxes));
            g.bench_function(format!("{label}/{name}"), |b| {
                b.iter(|| m.mesh(&f, &e.domain, &NoProgress).unwrap())
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
