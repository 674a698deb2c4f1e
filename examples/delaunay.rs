//! Delaunay kernel timing and point files for the CGAL comparison (benches/cgal/).
//!
//! `cargo run --release --example delaunay -- write N uniform|sphere|torus SEED FILE`
//! writes N points (binary: u64 count, then x y z as little-endian f64).
//! `cargo run --release --example delaunay -- run FILE [--check]` triangulates them
//! and prints one line: points, cells, seconds, points/s.
use certmesh::kernel::delaunay::{random_points, Delaunay, Sampler};
use std::io::{Read, Write};

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    match a.first().map(String::as_str) {
        Some("write") => {
            let n: usize = a[1].parse().expect("N");
            let on = match a[2].as_str() {
                "uniform" => Sampler::Uniform,
                "sphere" => Sampler::Sphere,
                "torus" => Sampler::Torus,
                s => panic!("unknown sampler {s}"),
            };
            let seed: u64 = a[3].parse().expect("SEED");
            let pts = random_points(n, on, seed);
            let mut buf = Vec::with_capacity(8 + 24 * n);
            buf.extend_from_slice(&(n as u64).to_le_bytes());
            for p in &pts {
                for x in p {
                    buf.extend_from_slice(&x.to_le_bytes());
                }
            }
            std::fs::File::create(&a[4])
                .and_then(|mut f| f.write_all(&buf))
                .expect("write");
        }
        Some("run") => {
            let mut data = Vec::new();
            std::fs::File::open(&a[1])
                .and_then(|mut f| f.read_to_end(&mut data))
                .expect("read");
            let n = u64::from_le_bytes(data[..8].try_into().unwrap()) as usize;
            let pts: Vec<[f64; 3]> = (0..n)
                .map(|i| {
                    std::array::from_fn(|k| {
                        let o = 8 + 24 * i + 8 * k;
                        f64::from_le_bytes(data[o..o + 8].try_into().unwrap())
                    })
                })
                .collect();
            let t0 = std::time::Instant::now();
            let (t, bulk) = Delaunay::from_points(&pts, 1).expect("points");
            let s = t0.elapsed().as_secs_f64();
            println!(
                "certmesh points {n} duplicates {} cells {} seconds {s:.4} points/s {:.0} memory_estimate_bytes {}",
                bulk.duplicates.len(),
                t.num_cells(),
                n as f64 / s,
                t.memory_bytes()
            );
            if a.iter().any(|x| x == "--check") {
                let r = t.check();
                println!("valid {} {:?}", r.valid, r.first_problem);
            }
        }
        _ => {
            eprintln!("usage: delaunay write N uniform|sphere|torus SEED FILE | run FILE [--check]")
        }
    }
}
