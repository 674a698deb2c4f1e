//! The certified Morse census: the search for ∇f = 0, the height census on S, and the
//! Stander–Hart sweep against Plantinga–Vegter alone (criterion's throughput = boxes of
//! the search); BCSV against Plantinga–Vegter and Snyder.
use certmesh::catalog;
use certmesh::implicit::critical::{critical_points_of_f, euler_characteristic, Budget, Bx};
use certmesh::mesher::{registry, Mesher, NoProgress};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn census(c: &mut Criterion) {
    let mut g = c.benchmark_group("morse");
    g.sample_size(10);
    for name in ["tanglecube", "genus2", "genus5", "two-spheres"] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        let d: Bx = e.domain.into();
        let grad = Budget {
            max_depth: 30,
            ..Budget::default()
        };
        let r = critical_points_of_f(&f, d, grad);
        eprintln!(
            "{name}: grad f = 0: {} points, {} boxes",
            r.points.len(),
            r.stats.boxes
        );
        g.throughput(Throughput::Elements(r.stats.boxes as u64));
        g.bench_function(format!("gradient/{name}"), |b| {
            b.iter(|| critical_points_of_f(&f, d, grad))
        });
        let h = euler_characteristic(&f, d, None, Budget::default());
        eprintln!(
            "{name}: height: chi {:?}, {} boxes",
            h.chi, h.surface.stats.boxes
        );
        g.throughput(Throughput::Elements(h.surface.stats.boxes as u64));
        g.bench_function(format!("height/{name}"), |b| {
            b.iter(|| euler_characteristic(&f, d, None, Budget::default()))
        });
    }
    g.finish();
}

fn sweep(c: &mut Criterion) {
    let mut g = c.benchmark_group("stander-hart");
    g.sample_size(10);
    for name in ["tanglecube", "two-spheres"] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        for algo in ["stander-hart", "pv"] {
            let m: Box<dyn Mesher> = registry::build(algo, 3, &Default::default()).unwrap();
            g.bench_function(format!("{algo}/{name}"), |b| {
                b.iter(|| m.mesh(&f, &e.domain, &NoProgress).unwrap())
            });
        }
    }
    g.finish();
}

/// The census through the smooth remedy g = f·(1 + |x − b|²) on the surfaces whose f
/// is not Morse (torus, superquadric; the thin torus at depth 45), and Stander–Hart on
/// the torus with it, against the plain census that gives up.
fn remedy(c: &mut Criterion) {
    use certmesh::morse::{self, remedy::Remedy, MorseOptions};
    let mut g = c.benchmark_group("remedy");
    g.sample_size(10);
    for (name, depth) in [("torus", 30), ("thin-torus", 45), ("superquadric", 30)] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        let d: Bx = e.domain.into();
        let mut o = MorseOptions {
            remedy: Some(Remedy::parse("smooth", d).unwrap()),
            ..MorseOptions::default()
        };
        o.gradient.max_depth = depth;
        let r = morse::analyze(&f, d, &o);
        eprintln!(
            "{name}: remedy smooth: chi {:?}, {} boxes",
            r.sublevel.chi_surface, r.gradient.stats.boxes
        );
        g.bench_function(format!("census-smooth/{name}"), |b| {
            b.iter(|| morse::analyze(&f, d, &o))
        });
    }
    let e = catalog::get("torus").unwrap();
    let f = e.function();
    let mut o = certmesh::MesherOptions::default();
    o.extra.insert("remedy".into(), "smooth".into());
    let m = registry::build("stander-hart", 3, &o).unwrap();
    g.bench_function("stander-hart-smooth/torus", |b| {
        b.iter(|| m.mesh(&f, &e.domain, &NoProgress).unwrap())
    });
    g.finish();
}

/// BCSV (isotopy by Theorem B, census included) against Plantinga–Vegter and Snyder
/// on surfaces where BCSV certifies at the default resolution.
fn bcsv(c: &mut Criterion) {
    let mut g = c.benchmark_group("bcsv");
    g.sample_size(10);
    for name in ["sphere", "torus", "tanglecube"] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        for algo in ["bcsv", "pv", "snyder"] {
            // `bcsv/bcsv/*` stays the uniform version measured before the octree.
            let m: Box<dyn Mesher> = registry::build(algo, 3, &options(algo, false)).unwrap();
            g.bench_function(format!("{algo}/{name}"), |b| {
                b.iter(|| m.mesh(&f, &e.domain, &NoProgress).unwrap())
            });
        }
    }
    g.finish();
}

/// The options of `algo`: for BCSV, the adaptive octree or the uniform Kuhn grid.
fn options(algo: &str, octree: bool) -> certmesh::MesherOptions {
    let mut o = certmesh::MesherOptions::default();
    if algo == "bcsv" {
        o.extra.insert("octree".into(), octree.to_string());
    }
    o
}

/// Adaptive BCSV (the 2:1-balanced octree with conforming tetrahedra, census
/// included) on the sphere and the torus; compare with `bcsv/bcsv/*` (uniform).
fn bcsv_octree(c: &mut Criterion) {
    let mut g = c.benchmark_group("bcsv-octree");
    g.sample_size(10);
    for name in ["sphere", "torus"] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        let m: Box<dyn Mesher> = registry::build("bcsv", 3, &options("bcsv", true)).unwrap();
        g.bench_function(format!("bcsv/{name}"), |b| {
            b.iter(|| m.mesh(&f, &e.domain, &NoProgress).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, census, sweep, remedy, bcsv, bcsv_octree);
criterion_main!(benches);
