//! `proofs`: computer-assisted proofs about certmesh's meshers, re-checked with rigorous
//! interval arithmetic (inari) and exact rational arithmetic, written as certificates
//! that can be re-verified independently.
use clap::{Parser, Subcommand};
use proofs::geometry::DiagonalRule;
use proofs::gradnormal::cases::Ratio;
use proofs::gradnormal::{self, Certificate, Config};
use proofs::stuffing;
use std::path::PathBuf;
use std::process::ExitCode;

/// Computer-assisted proofs and certificates for certmesh.
///
/// The proofs verify the project's own data (the GradNormal tiling and diagonal rules,
/// the isosurface-stuffing stencil table), read from the same code the meshers use, so
/// a certificate speaks about the meshes certmesh actually produces.
#[derive(Parser)]
#[command(name = "proofs", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Certify the GradNormal angle bounds over the full regions of plane normals
    /// (Hass & Trnkova 2020, Thm 1.1, Lemma 4.1, Appendix A) and write a certificate.
    Gradnormal {
        /// Goldberg parameter a/e: a number or `sommerville` (√2/4, the paper's Appendix).
        #[arg(long, default_value = "sommerville")]
        a: String,
        /// Diagonal rule for the quadrilaterals and the valence-four square:
        /// paper | alternate | shorter.
        #[arg(long, default_value = "paper")]
        rule: String,
        /// Certificate output path.
        #[arg(long, short, default_value = "gradnormal-cert.json")]
        out: PathBuf,
        /// Run only the cases with index ≡ i (mod N): `--shard i/N`.
        #[arg(long)]
        shard: Option<String>,
        /// Print the JSON summary (min_deg, max_deg, claims) on stdout.
        #[arg(long)]
        json: bool,
        /// Target enclosure width in degrees (default 1e-6).
        #[arg(long, default_value_t = 1e-6)]
        tol_deg: f64,
        /// Plot the certified bounds against a/e over this many values in [0.2, 0.6]
        /// (tolerance 1e-4°), into papers/gradnormal/figures/scan-RULE.svg/png.
        #[arg(long)]
        scan: Option<usize>,
        /// Write PROOF.md and the figures into this directory (runs every rule).
        #[arg(long)]
        write_papers: Option<PathBuf>,
    },
    /// Certify the isosurface-stuffing Table 1 bounds (Labelle & Shewchuk 2007, Thm 1,
    /// §4.1) on the mesher's stencil table, and the safe property, per row.
    Stuffing {
        /// A Table 1 row (the mesher's `--params` name) or `all`.
        #[arg(long, default_value = "all")]
        row: String,
        /// Print the JSON summary on stdout.
        #[arg(long)]
        json: bool,
        /// Run only the cases with index ≡ i (mod N): `--shard i/N`.
        #[arg(long)]
        shard: Option<String>,
        /// Certificate output path (with `--row all`: a directory; one file per row).
        #[arg(long, short, default_value = "stuffing-cert.json")]
        out: PathBuf,
        /// Target enclosure width in degrees.
        #[arg(long, default_value_t = 1e-4)]
        tol_deg: f64,
        /// Only print the case counts (before and after the symmetry reduction).
        #[arg(long)]
        count: bool,
        /// The graded variant's two dagger bounds (§5, max plane angle of the non-BCC
        /// background tetrahedra); `--row` then names one of the two dagger rows or `all`.
        #[arg(long)]
        graded: bool,
        /// With `--graded`: number of sample octrees of the sampled-contexts model.
        #[arg(long, default_value_t = proofs::stuffing::graded::DEFAULT_TREES)]
        trees: usize,
    },
    /// Figures of the worst configurations (like the paper's Fig 5) from stuffing
    /// certificates DIR/ROW.json, into OUT/ROW-BOUND.svg/png.
    StuffingFigures {
        #[arg(long)]
        certs: PathBuf,
        #[arg(long, default_value = "papers/stuffing/figures")]
        out: PathBuf,
        /// Comma-separated bound names.
        #[arg(long, default_value = "min_dihedral,max_dihedral")]
        bounds: String,
    },
    /// Re-verify a certificate independently of the search.
    Check { cert: PathBuf },
    /// Print the derived regions of plane normals (exact vertex rays) as markdown.
    Regions {
        #[arg(long, default_value = "sommerville")]
        a: String,
    },
    /// Merge shard certificates into one.
    Merge {
        parts: Vec<PathBuf>,
        #[arg(long, short)]
        out: PathBuf,
    },
}

fn load(p: &PathBuf) -> Result<Certificate, String> {
    let text = std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: not a certificate: {e}", p.display()))
}

fn save(p: &PathBuf, c: &Certificate) -> Result<(), String> {
    let text = serde_json::to_string(c).map_err(|e| e.to_string())?;
    std::fs::write(p, text).map_err(|e| format!("{}: {e}", p.display()))
}

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let (i, n) = s.split_once('/').ok_or("--shard expects i/N")?;
    let i: usize = i.parse().map_err(|_| "--shard expects i/N")?;
    let n: usize = n.parse().map_err(|_| "--shard expects i/N")?;
    if n == 0 || i >= n {
        return Err(format!("--shard {i}/{n}: need 0 <= i < N"));
    }
    Ok((i, n))
}

fn print_human(c: &Certificate) {
    println!(
        "GradNormal angle proof: a/e = {}, rule = {}, {} of {} cases, {:.2} s",
        c.ratio,
        c.rule,
        c.cases.len(),
        c.n_cases,
        c.seconds
    );
    if let Some(s) = &c.summary {
        println!(
            "  smallest projected angle in [{:.9}°, {:.9}°]",
            s.min_deg[0], s.min_deg[1]
        );
        println!(
            "  largest projected angle  in [{:.9}°, {:.9}°]",
            s.max_deg[0], s.max_deg[1]
        );
        println!(
            "  valence-four triangles: [{:.7}°, {:.7}°] .. [{:.7}°, {:.7}°]",
            s.v4_min_deg[0], s.v4_min_deg[1], s.v4_max_deg[0], s.v4_max_deg[1]
        );
        for cl in &c.claims {
            println!("  {:9} {}", cl.verdict.name(), cl.claim);
        }
    }
}

fn run() -> Result<(), String> {
    let cli = Cli::parse();
    match cli.cmd {
        Cmd::Gradnormal {
            a,
            rule,
            out,
            shard,
            json,
            tol_deg,
            scan,
            write_papers,
        } => {
            let ratio = Ratio::parse(&a)?;
            let rule: DiagonalRule = rule.parse().map_err(|e| format!("{e}"))?;
            if let Some(dir) = write_papers {
                return proofs::gradnormal::report::write_papers(&dir, ratio);
            }
            if let Some(n) = scan {
                let dir = PathBuf::from("papers/gradnormal/figures");
                let rows = proofs::gradnormal::report::scan(rule, n, &dir)?;
                for r in rows {
                    println!("{r}");
                }
                return Ok(());
            }
            let mut cfg = Config::new(ratio, rule);
            if !(tol_deg > 0.0) {
                return Err("--tol-deg must be positive".into());
            }
            cfg.tol_cos = 0.5 * tol_deg * std::f64::consts::PI / 180.0;
            cfg.shard = shard.as_deref().map(parse_shard).transpose()?;
            cfg.progress = !json;
            let cert = gradnormal::run(&cfg)?;
            save(&out, &cert)?;
            if json {
                let v = serde_json::json!({
                    "ratio": cert.ratio,
                    "rule": cert.rule,
                    "seconds": cert.seconds,
                    "certificate": out.display().to_string(),
                    "min_deg": cert.summary.as_ref().map(|s| s.min_deg),
                    "max_deg": cert.summary.as_ref().map(|s| s.max_deg),
                    "v4_min_deg": cert.summary.as_ref().map(|s| s.v4_min_deg),
                    "v4_max_deg": cert.summary.as_ref().map(|s| s.v4_max_deg),
                    "claims": cert.claims,
                    "cases": cert.summary.as_ref().map(|s| &s.cases),
                });
                println!(
                    "{}",
                    serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
                );
            } else {
                print_human(&cert);
                println!("  certificate: {}", out.display());
            }
            Ok(())
        }
        Cmd::Stuffing {
            row,
            json,
            shard: _,
            out,
            tol_deg,
            count: _,
            graded: true,
            trees,
        } => graded_cmd(&row, json, &out, tol_deg, trees),
        Cmd::Stuffing {
            row,
            json,
            shard,
            out,
            tol_deg,
            count,
            graded: false,
            trees: _,
        } => stuffing_cmd(&row, json, shard.as_deref(), &out, tol_deg, count),
        Cmd::StuffingFigures { certs, out, bounds } => {
            std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
            for name in stuffing::row_names() {
                let p = certs.join(format!("{name}.json"));
                if !p.exists() {
                    continue;
                }
                let c = load_stuffing(&p)?;
                for (b, (bn, _, _)) in stuffing::BOUNDS.iter().enumerate() {
                    if !bounds.split(',').any(|x| x == *bn) {
                        continue;
                    }
                    let stem = out.join(format!("{name}-{bn}"));
                    if proofs::stuffing::figures::witness_figure(&c, b, &stem)? {
                        println!("{}.svg", stem.display());
                    }
                }
            }
            Ok(())
        }
        Cmd::Check { cert } if is_stuffing(&cert)? => {
            let c = load_stuffing(&cert)?;
            let t0 = std::time::Instant::now();
            let r = stuffing::check(&c)?;
            print_check_ok(
                &format!("row {}, {} problems", c.row, r.problems),
                r.leaves,
                r.complete,
                t0,
            );
            for b in &r.bounds {
                print_bound(b);
            }
            println!(
                "  safe: {} (min volume ratio {:.6})",
                r.safe.verdict.name(),
                r.safe.min_ratio
            );
            Ok(())
        }
        Cmd::Merge { parts, out } if parts.first().map(is_stuffing).transpose()? == Some(true) => {
            let certs: Result<Vec<stuffing::Certificate>, String> =
                parts.iter().map(load_stuffing).collect();
            let m = stuffing::merge(certs?)?;
            save_json(&out, &m)?;
            print_stuffing(&m);
            Ok(())
        }
        Cmd::Check { cert } => {
            let c = load(&cert)?;
            let t0 = std::time::Instant::now();
            let r = gradnormal::check(&c)?;
            print_check_ok(&format!("{} cases", r.cases), r.leaves, r.complete, t0);
            for cl in &r.claims {
                println!("  {:9} {}", cl.verdict.name(), cl.claim);
            }
            Ok(())
        }
        Cmd::Regions { a } => {
            print!(
                "{}",
                proofs::gradnormal::report::regions_markdown(Ratio::parse(&a)?)?
            );
            Ok(())
        }
        Cmd::Merge { parts, out } => {
            let certs: Result<Vec<Certificate>, String> = parts.iter().map(load).collect();
            let m = gradnormal::merge(certs?)?;
            save(&out, &m)?;
            print_human(&m);
            Ok(())
        }
    }
}

fn is_stuffing(p: &PathBuf) -> Result<bool, String> {
    use std::io::Read;
    let mut f = std::fs::File::open(p).map_err(|e| format!("{}: {e}", p.display()))?;
    let mut head = [0u8; 200];
    let n = f
        .read(&mut head)
        .map_err(|e| format!("{}: {e}", p.display()))?;
    Ok(String::from_utf8_lossy(&head[..n]).contains(stuffing::FORMAT))
}

fn load_stuffing(p: &PathBuf) -> Result<stuffing::Certificate, String> {
    let f = std::fs::File::open(p).map_err(|e| format!("{}: {e}", p.display()))?;
    serde_json::from_reader(std::io::BufReader::new(f))
        .map_err(|e| format!("{}: not a stuffing certificate: {e}", p.display()))
}

fn save_json<T: serde::Serialize>(p: &PathBuf, c: &T) -> Result<(), String> {
    let f = std::fs::File::create(p).map_err(|e| format!("{}: {e}", p.display()))?;
    serde_json::to_writer(std::io::BufWriter::new(f), c).map_err(|e| e.to_string())
}

fn print_bound(b: &stuffing::BoundResult) {
    let paper = b
        .paper
        .map(|x| format!("{x:.4}"))
        .unwrap_or_else(|| "n/a".into());
    let deg = b
        .deg
        .map(|d| format!("[{:.6}, {:.6}]", d[0], d[1]))
        .unwrap_or_else(|| "n/a".into());
    println!(
        "  {:13} paper {:>9}  certified {:24}  {:9}  tight: {}",
        b.bound,
        paper,
        deg,
        b.verdict.map(|v| v.name()).unwrap_or("-"),
        b.tight.as_deref().unwrap_or("-")
    );
}

fn print_stuffing(c: &stuffing::Certificate) {
    println!(
        "stuffing row {}: {} -> {} cases, {} problems, {} leaves ({} unresolved), {:.1} s",
        c.row,
        c.counts.raw,
        c.counts.distinct,
        c.problems.len(),
        c.leaves,
        c.unresolved,
        c.seconds
    );
    for b in &c.bounds {
        print_bound(b);
    }
    println!(
        "  safe: {} (min volume / unwarped volume = {:.6}; {} -> {} cases){}",
        c.safe.verdict.name(),
        c.safe.min_ratio,
        c.safe.counts.raw,
        c.safe.counts.distinct,
        if c.safe.note.is_empty() {
            String::new()
        } else {
            format!("; {}", c.safe.note)
        }
    );
}

fn stuffing_cmd(
    row: &str,
    json: bool,
    shard: Option<&str>,
    out: &PathBuf,
    tol_deg: f64,
    count: bool,
) -> Result<(), String> {
    let names: Vec<&str> = if row == "all" {
        stuffing::row_names()
    } else {
        vec![
            certmesh::stuffing::row(row)
                .map_err(|e| e.to_string())?
                .name,
        ]
    };
    if !(tol_deg > 0.0) {
        return Err("--tol-deg must be positive".into());
    }
    let shard = shard.map(parse_shard).transpose()?;
    if count {
        for n in names {
            let r = certmesh::stuffing::row(n).map_err(|e| e.to_string())?;
            let a = proofs::stuffing::cases::Alphas::of(r);
            let (_, c) = proofs::stuffing::cases::output_cases(&a);
            let (_, s) = proofs::stuffing::cases::bcc_cases(&a);
            // Output-tetrahedron cases whose volume can vanish (exact corner test).
            let (cases, _) = proofs::stuffing::cases::output_cases(&a);
            let flat = cases
                .iter()
                .filter(|c| {
                    let (r, _) = proofs::stuffing::cases::volume_range(c, &a);
                    r[0] <= 0 && r[1] >= 0
                })
                .count();
            println!(
                "{n:28} output tetrahedra {:6} -> {:5} ({flat} can be flat)   BCC tetrahedra (safe) {:6} -> {:5}",
                c.raw, c.distinct, s.raw, s.distinct
            );
        }
        return Ok(());
    }
    if names.len() > 1 {
        std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    }
    let mut summaries = Vec::new();
    for n in names {
        let r = certmesh::stuffing::row(n).map_err(|e| e.to_string())?;
        let mut cfg = stuffing::Config::new(r);
        cfg.tol_deg = tol_deg;
        cfg.shard = shard;
        cfg.progress = !json;
        let path = if row == "all" {
            out.join(format!("{n}.json"))
        } else {
            out.clone()
        };
        let cert = stuffing::run(&cfg)?;
        save_json(&path, &cert)?;
        if json {
            summaries.push(stuffing::summary_json(&cert, &path.display().to_string()));
        } else {
            print_stuffing(&cert);
            println!("  certificate: {}", path.display());
        }
    }
    if json {
        let v = if summaries.len() == 1 {
            summaries.pop().unwrap_or_default()
        } else {
            serde_json::Value::Array(summaries)
        };
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
    }
    Ok(())
}

fn graded_cmd(
    row: &str,
    json: bool,
    out: &PathBuf,
    tol_deg: f64,
    trees: usize,
) -> Result<(), String> {
    use proofs::stuffing::graded as g;
    let names: Vec<&str> = if row == "all" {
        g::DAGGERS.iter().map(|d| d.0).collect()
    } else if g::DAGGERS.iter().any(|d| d.0 == row) {
        vec![g::DAGGERS
            .iter()
            .find(|d| d.0 == row)
            .map(|d| d.0)
            .unwrap_or(row)]
    } else {
        return Err(format!(
            "--graded: row '{row}' has no dagger bound; the dagger rows are {}",
            g::DAGGERS.map(|d| d.0).join(" ")
        ));
    };
    if !(tol_deg > 0.0) {
        return Err("--tol-deg must be positive".into());
    }
    if trees == 0 {
        return Err("--trees must be at least 1".into());
    }
    let mut all = Vec::new();
    for n in names {
        let r = certmesh::stuffing::row(n).map_err(|e| e.to_string())?;
        for context in [false, true] {
            let res = g::run(r, tol_deg, context, trees);
            if !json {
                println!(
                    "graded dagger, row {} ({} model): max plane angle, uniform {} -> paper {}",
                    res.row, res.model, res.uniform, res.paper
                );
                for s in &res.shapes {
                    println!(
                        "  shape {:13} level {} vertices {:?} ({} in the sample octree)",
                        s.0, s.2, s.1, s.3
                    );
                }
                println!(
                    "  faces {} -> {} distinct, {} leaves ({} unresolved), {:.1} s",
                    res.raw, res.distinct, res.leaves, res.unresolved, res.seconds
                );
                println!(
                    "  superset supremum in [{:.6}, {:.6}] deg: {}",
                    res.enclosure_deg[0], res.enclosure_deg[1], res.verdict
                );
                if let Some(w) = &res.witness {
                    println!(
                        "  witness face {:?} x {:?} positions (h units) {:?}",
                        w.0, w.1, w.2
                    );
                }
            }
            all.push(res);
        }
    }
    let v = serde_json::to_value(&all).map_err(|e| e.to_string())?;
    let text = serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?;
    std::fs::write(out, &text).map_err(|e| format!("{}: {e}", out.display()))?;
    if json {
        println!("{text}");
    }
    Ok(())
}

/// The first line of `proofs check`, for either kind of certificate.
fn print_check_ok(what: &str, leaves: usize, complete: bool, t0: std::time::Instant) {
    println!(
        "certificate OK: {what}, {leaves} leaves re-evaluated{} ({:.2} s)",
        if complete {
            ", complete"
        } else {
            " (partial: a shard)"
        },
        t0.elapsed().as_secs_f64()
    );
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
