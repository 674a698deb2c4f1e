//! `certmesh morse`: the certified Morse census of a surface (the report is
//! `certmesh::morse::MorseReport`; this file only parses, prints and serialises).
use crate::args::*;
use crate::errors::*;
use crate::input::*;
use crate::progress::Bar;
use certmesh::error::Error;
use certmesh::harness::report::DomainSource;
use certmesh::implicit::critical::Bx;
use certmesh::io;
use certmesh::mesher::Progress;
use certmesh::morse::{self, MorseOptions, MorseReport};
use clap::Args;
use serde::Serialize;
use std::io::Write;
use std::path::PathBuf;

/// The arguments of `certmesh morse`.
#[derive(Args, Clone)]
pub(crate) struct MorseArgs {
    /// A catalog name (see `certmesh surfaces`).
    pub(crate) name: Option<String>,
    /// A formula f(x, y, z) instead of a catalog name; `@FILE` reads it from FILE.
    #[arg(long, short = 'f', conflicts_with = "formula_file")]
    pub(crate) formula: Option<String>,
    /// Read the formula from this file (same as `--formula @FILE`).
    #[arg(long, value_name = "FILE")]
    pub(crate) formula_file: Option<PathBuf>,
    /// The domain box x0,y0,z0,x1,y1,z1. Default: the catalog's box for a catalog
    /// name, [-2, 2]³ for a formula.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub(crate) domain: Vec<f64>,
    /// The direction d of the height function <n, x> on S: dx,dy,dz (default
    /// (1/pi, 1/e, 1/sqrt 2), generic for the catalog's symmetric surfaces).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "DX,DY,DZ"
    )]
    pub(crate) height: Vec<f64>,
    /// A triangle mesh (obj ply off stl) whose Euler characteristic is printed beside
    /// the certified one.
    #[arg(long, value_name = "FILE")]
    pub(crate) mesh: Option<PathBuf>,
    /// Boxes each search may process (default 400000). A search stopped by it reports
    /// its unprocessed boxes as undecided ("budget") and certifies nothing that
    /// depends on them.
    #[arg(long, value_name = "N")]
    pub(crate) max_boxes: Option<usize>,
    /// Wall-clock limit of each search, in seconds (default 60). A search stopped by it
    /// reports its unprocessed boxes as undecided ("time-limit") and certifies nothing
    /// that depends on them; a degenerate critical set (two touching spheres, a double
    /// sphere) can otherwise spend a large --max-boxes for minutes.
    #[arg(long, value_name = "SECONDS")]
    pub(crate) time_limit: Option<f64>,
    /// Bisection depth of the search for grad f = 0 (default 30); a box still
    /// undecided there is reported (possibly degenerate, or depth limit).
    #[arg(long, value_name = "D")]
    pub(crate) max_depth: Option<u32>,
    /// Count the critical points of g = f·h instead of f, the chapter's remedy for
    /// degenerate critical points (§1.5.1), as an explicit transformation that the
    /// report states: `smooth` is h = a + |x - b|² (C^∞), `chapter` is h = a + |x - b|
    /// as the chapter writes it (not differentiable at b: nothing is certified in a
    /// box around b unless f > 0 there). a > 0 (default 1); b defaults to a fixed
    /// generic point of the domain. Since h > 0, {g <= 0} = {f <= 0} and g = 0 is S,
    /// so the certified chi is f's; the listed critical points are g's. For instance,
    /// `--remedy smooth` certifies chi(torus) = 0 from critical points (f's circle of
    /// minima becomes a minimum and a saddle of g; the thin torus, whose are nearly
    /// degenerate, also needs --max-depth 45).
    #[arg(long, value_name = "KIND[:A[:BX,BY,BZ]]")]
    pub(crate) remedy: Option<String>,
    /// Critical points listed per search in the text report (JSON lists all).
    #[arg(long, default_value_t = 30, value_name = "N")]
    pub(crate) list: usize,
    /// Print the report as JSON.
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Serialize)]
struct Output<'a> {
    surface: &'a str,
    formula: String,
    domain: Bx,
    domain_source: DomainSource,
    /// The catalog's χ, when the name is a catalog entry with a known topology.
    expected_chi: Option<i64>,
    #[serde(flatten)]
    report: &'a MorseReport,
}

pub(crate) fn morse_cmd(a: MorseArgs, quiet: bool) -> CliResult<()> {
    let mut opts = MorseOptions::default();
    if let Some(n) = a.max_boxes {
        if n == 0 {
            return Err(CliError::from(Error::Param(
                "--max-boxes must be at least 1".into(),
            )));
        }
        opts = opts.with_max_boxes(n);
    }
    let limit = a
        .time_limit
        .unwrap_or(certmesh::mesher::options::DEFAULT_TIME_LIMIT);
    certmesh::mesher::options::check_time_limit(limit)?;
    opts.gradient.time_limit = Some(limit);
    opts.surface.time_limit = Some(limit);
    if let Some(d) = a.max_depth {
        if !(1..=200).contains(&d) {
            return Err(CliError::from(Error::Param(format!(
                "--max-depth must lie in 1..=200, got {d}"
            ))));
        }
        opts.gradient.max_depth = d;
    }
    if !a.height.is_empty() {
        let h = &a.height;
        let norm = h.iter().map(|x| x * x).sum::<f64>().sqrt();
        if h.len() != 3 || !(norm.is_finite() && norm > 0.0) {
            return Err(CliError::from(Error::Param(format!(
                "--height needs a non-zero direction dx,dy,dz, got {h:?}"
            ))));
        }
        opts.direction = Some([h[0], h[1], h[2]]);
    }
    let mesh = match &a.mesh {
        Some(p) => Some(io::read_tri(p)?),
        None => None,
    };
    // The target as `certmesh mesh` resolves it (name or formula, domain).
    let mesh_args = MeshArgs {
        name: a.name.clone(),
        formula: a.formula.clone(),
        formula_file: a.formula_file.clone(),
        mesh_input: None,
        margin: 0.05,
        fill_holes: false,
        domain: a.domain.clone(),
        algo: String::new(),
        opts: OptArgs::default(),
        output: None,
        boundary: None,
        certificate: None,
        json: a.json,
        metrics: "fast".into(),
    };
    let t = target(&mesh_args, 3)?;
    let bar = Bar::new(quiet);
    bar.phase("critical points");
    let domain = Bx::from(t.domain);
    if let Some(r) = &a.remedy {
        opts.remedy = Some(morse::remedy::Remedy::parse(r, domain)?);
    }
    let mut report = morse::analyze(t.f.as_ref(), domain, &opts);
    if let (Some(m), Some(p)) = (&mesh, &a.mesh) {
        report.with_mesh(&p.display().to_string(), m)?;
    }
    bar.finish();
    let expected_chi = t.entry.as_ref().and_then(|e| e.euler_characteristic());
    let out = Output {
        surface: &t.name,
        formula: t.f.describe(),
        domain,
        domain_source: t.domain_source,
        expected_chi,
        report: &report,
    };
    if a.json {
        print_json(&out);
    } else {
        out!(
            "morse: {} in {:?}..{:?} ({})",
            t.name,
            domain.lo,
            domain.hi,
            serde_json::to_value(t.domain_source)
                .ok()
                .and_then(|v| v.as_str().map(String::from))
                .unwrap_or_default()
        );
        for line in report.text(a.list) {
            out!("{line}");
        }
        if let Some(c) = expected_chi {
            out!("catalog chi(S) = {c}");
        }
    }
    Ok(())
}
