//! In-process timing of the exact curve sweep (`--algo gvn`), for the side-by-side
//! run with CGAL's Curve_analysis_2 (`benches/cgal/curve_analysis.sh`): the analysis
//! only (no process start, parsing, certificate or SVG output), the median of REPS
//! runs, each with an empty gcd memo, the shear retries included.
//!
//! usage: cargo run --release --example gvn_time -- (FORMULA | dense:D:SEED) XMIN,YMIN,XMAX,YMAX REPS [CERT.json]
//!
//! Prints `shear S`, `critical_events N` and `median_ms T`; writes the certificate of
//! the first run to CERT.json when given (the script feeds its polynomial to CGAL).
//! With GVN_TOLERANCE=T set, the extra fibres of `--set tolerance=T` run too; with
//! GVN_CHECK=1, the certificate checker is timed as well (`check_median_ms`).
use certmesh::algebraic::bipoly::{from_formula, BiPoly};
use certmesh::algebraic::sweep::{analyse, SweepParams};
use certmesh::Aabb;
use std::time::Instant;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    if a.len() < 4 {
        eprintln!("usage: gvn_time (FORMULA | dense:D:SEED) XMIN,YMIN,XMAX,YMAX REPS [CERT.json]");
        std::process::exit(2);
    }
    let f = if let Some(ds) = a[1].strip_prefix("dense:") {
        let v: Vec<u64> = ds
            .split(':')
            .map(|t| t.parse().expect("dense:D:SEED"))
            .collect();
        BiPoly::dense_random(v[0] as usize, v[1])
    } else {
        from_formula(&a[1]).unwrap_or_else(|e| panic!("{e}"))
    };
    let d: Vec<f64> = a[2]
        .split(',')
        .map(|t| t.parse().expect("domain"))
        .collect();
    let dom = Aabb {
        min: [d[0], d[1], 0.0],
        max: [d[2], d[3], 0.0],
    };
    let reps: usize = a[3].parse().expect("REPS");
    // GVN_TOLERANCE=T: with the extra fibres of `--set tolerance=T` (their report is
    // printed as `tolerance …`).
    let mut p = SweepParams::default();
    if let Ok(t) = std::env::var("GVN_TOLERANCE") {
        p.tolerance = Some(t.parse().expect("GVN_TOLERANCE"));
    }
    let mut ms = Vec::new();
    let mut first = None;
    for _ in 0..reps.max(1) {
        let t = Instant::now();
        let r = analyse(&f, &dom, &p).unwrap_or_else(|e| panic!("{e}"));
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        first.get_or_insert(r);
    }
    let r = first.expect("one run");
    if let Some(path) = a.get(4) {
        std::fs::write(path, serde_json::to_string(&r.cert).expect("json")).expect("write");
    }
    ms.sort_by(f64::total_cmp);
    println!("shear {}", r.shear);
    println!(
        "critical_events {}",
        r.events.iter().filter(|e| e.critical).count()
    );
    println!("median_ms {:.3}", ms[ms.len() / 2]);
    // GVN_CHECK=1: also the median time of the certificate checker on this certificate.
    if std::env::var("GVN_CHECK").is_ok() {
        let mut cs = Vec::new();
        for _ in 0..reps.max(1) {
            let t = Instant::now();
            certmesh::algebraic::check::check_curve(&r.cert).unwrap_or_else(|e| panic!("{e}"));
            cs.push(t.elapsed().as_secs_f64() * 1e3);
        }
        cs.sort_by(f64::total_cmp);
        println!("check_median_ms {:.3}", cs[cs.len() / 2]);
    }
    if let Some(t) = &r.tolerance {
        println!("tolerance {}", serde_json::to_string(t).expect("json"));
    }
}
