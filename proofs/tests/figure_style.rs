//! Every kind of figure the `proofs` binary writes keeps certmesh's figure style: each is
//! drawn here from a small input (a shard of a stuffing row, a few GradNormal cases,
//! made-up Pareto points) and its SVG read back by `certmesh::figure::check`, which
//! rejects a printed width other than 3.3 or 7 in, text under 7 pt, missing metadata,
//! unlabelled axes, a missing legend and text running off the figure.
use certmesh::figure::check::check_svg;
use proofs::geometry::DiagonalRule;
use proofs::gradnormal::cases::{Derived, Ratio};
use proofs::stuffing::pareto::Point;
use std::path::{Path, PathBuf};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("proofs-style-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Check every SVG in `dir` (at least `n` of them) and that each has its 300 dpi PNG.
fn all_pass(dir: &Path, n: usize) {
    let mut seen = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "svg") {
            let r = check_svg(&std::fs::read_to_string(&p).unwrap()).unwrap();
            assert!(r.problems.is_empty(), "{}: {:?}", p.display(), r.problems);
            assert!(r.min_font_pt >= 7.0, "{}", p.display());
            assert!(p.with_extension("png").exists(), "{}: no PNG", p.display());
            seen += 1;
        }
    }
    assert!(
        seen >= n,
        "{seen} figures in {}, expected {n}",
        dir.display()
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn gradnormal_maps_and_arcs_keep_the_style() {
    let ratio = Ratio::parse("sommerville").unwrap();
    let cases = Derived::new(ratio).cases(DiagonalRule::Paper).unwrap();
    let d = tmp("gradnormal");
    // Case 10 has the longest name: its titles must wrap, not run off.
    proofs::gradnormal::maps::write_maps(&d, ratio, &cases, &[10]).unwrap();
    proofs::gradnormal::report::write_arcs(&d, ratio, &cases, &[10]).unwrap();
    all_pass(&d, 3);
}

#[test]
fn stuffing_witness_figures_keep_the_style() {
    let row = certmesh::stuffing::row("max-exposed-safe").unwrap();
    let mut cfg = proofs::stuffing::Config::new(row);
    cfg.shard = Some((0, 400));
    cfg.tol_deg = 5.0;
    let cert = proofs::stuffing::run(&cfg).unwrap();
    let d = tmp("witness");
    let mut n = 0;
    for b in 0..proofs::stuffing::BOUNDS.len() {
        let stem = d.join(format!("w-{b}"));
        if proofs::stuffing::figures::witness_figure(&cert, b, &stem).unwrap() {
            n += 1;
        }
    }
    assert!(n >= 2, "{n} witness figures drawn");
    all_pass(&d, n);
}

#[test]
fn pareto_plots_keep_the_style() {
    let p = |a: f64, b: f64, d: [f64; 6]| Point {
        alpha_long: a,
        alpha_short: b,
        ordered: false,
        double_sided: false,
        proven_deg: d,
        width_deg: [1e-3; 6],
        safe: "proven",
        flat_output_cases: 0,
        certificate: format!("p-{a}-{b}.json"),
        leaves: 1,
        seconds: 0.0,
    };
    let pts = vec![
        p(0.2, 0.3, [8.0, 165.0, 9.0, 155.0, 9.0, 155.0]),
        p(0.24999, 0.375, [9.3, 161.6, 7.8, 158.2, 7.8, 158.2]),
        p(0.21509, 0.359, [9.0, 163.0, 8.5, 156.0, 8.5, 156.0]),
        p(0.3, 0.5, [10.0, 164.0, 10.4, 150.0, 10.4, 150.0]),
    ];
    let d = tmp("pareto");
    let written = proofs::stuffing::pareto::plots(&pts, &d).unwrap();
    assert_eq!(written.len(), 2);
    all_pass(&d, 2);
}

/// The check can fail: a figure of the old drawing (plotters' default 1100 × 520 px,
/// no metadata, 16 px text) is rejected.
#[test]
fn an_unstyled_figure_is_rejected() {
    use plotters::prelude::*;
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, (1100, 520)).into_drawing_area();
        area.fill(&WHITE).unwrap();
        area.titled("an old figure", ("sans-serif", 16)).unwrap();
        area.present().unwrap();
    }
    let r = check_svg(&svg).unwrap();
    assert!(
        r.problems.iter().any(|p| p.contains("printed width"))
            && r.problems.iter().any(|p| p.contains("metadata")),
        "{:?}",
        r.problems
    );
}
