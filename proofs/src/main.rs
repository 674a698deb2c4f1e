//! `proofs`: computer-assisted proofs about certmesh's meshers, re-checked with rigorous
//! interval arithmetic (inari) and exact rational arithmetic, written as certificates
//! that can be re-verified independently.
use clap::{Parser, Subcommand};
use proofs::bnb::Budget;
mod cli;
use cli::fail::{report, Fail, Kind};
use cli::files::*;
use cli::print::*;
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
///
/// Every run has a work budget (--max-boxes, --time-limit): a run that reaches it stops,
/// says so and writes no certificate. A shard (--shard i/N) is a partial result with no
/// verdict until `proofs merge` has all N shards.
///
/// Exit codes: 0 success (a certificate written or accepted, whatever its verdicts);
/// 1 a certificate rejected by `check`, or a run stopped by its budget; 2 a usage or
/// input error. With --json, an error is {"error": ..., "kind": ..., "position": ...}
/// on stdout.
#[derive(Parser)]
#[command(name = "proofs", version, about, long_about)]
struct Cli {
    /// Machine-readable output: results as JSON on stdout, and an error as a JSON
    /// object `{"error": ..., "kind": ..., "position": ...}` on stdout.
    #[arg(long, global = true)]
    json: bool,
    /// Figure formats, comma-separated, for the commands that draw figures: svg (vector,
    /// text as text), png (300 dpi), pdf (vector, for LaTeX). Each figure is drawn once
    /// in certmesh's figure style and converted.
    #[arg(
        long = "format",
        global = true,
        value_name = "LIST",
        default_value = "svg,png"
    )]
    format: String,
    #[command(subcommand)]
    cmd: Cmd,
}

/// The work budget options of a run.
#[derive(clap::Args, Clone, Copy, Debug)]
struct BudgetArgs {
    /// Work budget: the most boxes (interval evaluations) the run may use; a run that
    /// reaches it stops, says so and writes no certificate.
    #[arg(long, default_value_t = proofs::bnb::DEFAULT_MAX_BOXES)]
    max_boxes: u64,
    /// Wall-clock limit in seconds (default: none); a run that reaches it stops, says
    /// so and writes no certificate.
    #[arg(long, value_name = "SECONDS")]
    time_limit: Option<f64>,
}

impl BudgetArgs {
    fn budget(&self) -> Result<Budget, Fail> {
        if let Some(t) = self.time_limit {
            if !(t > 0.0 && t.is_finite()) {
                return Err(Fail::input(format!(
                    "--time-limit {t}: must be a positive number of seconds"
                )));
            }
        }
        if self.max_boxes == 0 {
            return Err(Fail::input("--max-boxes must be at least 1"));
        }
        Ok(Budget::new(self.max_boxes, self.time_limit))
    }
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
        #[command(flatten)]
        budget: BudgetArgs,
    },
    /// Certify the isosurface-stuffing Table 1 bounds (Labelle & Shewchuk 2007, Thm 1,
    /// §4.1) on the mesher's stencil table, and the safe property, per row.
    Stuffing {
        /// A Table 1 row (the mesher's `--params` name) or `all` (the default).
        #[arg(long, conflicts_with_all = ["alpha_long", "alpha_short"])]
        row: Option<String>,
        /// Audit any parameter pair instead of a Table 1 row: α_long (black, long
        /// lattice edges), a decimal in (0, 0.5) with at most five decimals. Needs
        /// `--alpha-short`. The six extremes are certified as enclosures with witnesses;
        /// there is no paper value, so no verdict. Example (Unreal Engine's
        /// TIsosurfaceStuffing): `proofs stuffing --alpha-long 0.21509 --alpha-short 0.359`.
        #[arg(long, requires = "alpha_short", value_name = "A")]
        alpha_long: Option<String>,
        /// α_short (red, short lattice edges), a decimal in (0, 0.5]. Needs `--alpha-long`.
        #[arg(long, requires = "alpha_long", value_name = "B")]
        alpha_short: Option<String>,
        /// With `--alpha-long`: ordered warping (§3.2) instead of arbitrary order.
        #[arg(long, requires = "alpha_long")]
        ordered: bool,
        /// With `--alpha-long`: `one` (bounds over the tetrahedra of one side, as Table
        /// 1's one-sided rows) or `both` (double-sided: quadruple-zero tetrahedra too).
        #[arg(long, requires = "alpha_long", value_parser = ["one", "both"], default_value = "one")]
        side: String,
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
        /// With `--graded`: the all-contexts model enumerates the non-BCC tetrahedra of
        /// octree levels 0..=K at their real coordinates (K = this) and covers the
        /// coarser levels by the free model with the warps shrunk by 2^-K.
        #[arg(long, default_value_t = proofs::stuffing::graded::DEFAULT_LEVELS)]
        levels: u32,
        /// With `--graded`: which configuration spaces to search: `free`,
        /// `sampled-contexts`, `all-contexts` (comma-separated), or `every` (all three).
        #[arg(long, default_value = "every")]
        model: String,
        /// With `--graded`: write one certificate per row and model into this folder
        /// (`graded-ROW-MODEL.json`, with every leaf of the search), for `proofs check`.
        #[arg(long)]
        certificates: Option<PathBuf>,
        #[command(flatten)]
        budget: BudgetArgs,
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
    /// The result tables of papers/stuffing/PROOF.md (results per bound, run statistics
    /// and the safe property, witness configurations, slowest cases) from the row
    /// certificates DIR/ROW.json (or the summaries DIR/ROW.summary.json), as markdown.
    /// Example: `proofs report certs > tables.md`.
    Report {
        dir: PathBuf,
        /// Write the markdown here instead of stdout.
        #[arg(long, short)]
        out: Option<PathBuf>,
    },
    /// Recompute the witness configurations of stuffing summaries (`proofs stuffing
    /// --json` output) or certificates independently in floating point, from their vertex
    /// coordinates alone, and compare with the certified enclosures. Exit 1 when one
    /// disagrees. Example: `proofs witness certs/*.summary.json`.
    Witness {
        /// Summary files (ROW.summary.json), certificates (ROW.json) or folders of them.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Rounding slack of the float recomputation, in degrees.
        #[arg(long, default_value_t = 1e-6)]
        slack_deg: f64,
    },
    /// The certified Pareto front of isosurface stuffing: every audited parameter pair's
    /// certificate in DIR (`proofs stuffing --alpha-long A --alpha-short B -o DIR/x.json`,
    /// one job per pair) is re-checked, then the non-dominated pairs per criterion
    /// (dihedral, plane angle) are listed with the Table 1 rows they beat, and plotted
    /// (OUT/pareto-dihedral.svg/png, OUT/pareto-plane.svg/png).
    /// Example: `proofs pareto certs/grid --out papers/stuffing/figures --md papers/stuffing/PARETO-table.md`.
    Pareto {
        dir: PathBuf,
        /// Folder for the plots.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write the markdown table here (default: stdout).
        #[arg(long)]
        md: Option<PathBuf>,
    },
    /// Merge shard certificates into one.
    Merge {
        parts: Vec<PathBuf>,
        #[arg(long, short)]
        out: PathBuf,
    },
}

fn run(cli: Cli) -> Result<(), Fail> {
    let json = cli.json;
    let formats = certmesh::figure::output::Format::parse_list(&cli.format)
        .map_err(|e| Fail::input(e.to_string()))?;
    certmesh::figure::output::set_default_formats(&formats);
    match cli.cmd {
        Cmd::Gradnormal {
            a,
            rule,
            out,
            shard,
            tol_deg,
            scan,
            write_papers,
            budget,
        } => {
            let ratio = Ratio::parse(&a).map_err(|e| Fail::input(format!("--a: {e}")))?;
            let rule: DiagonalRule = rule
                .parse()
                .map_err(|e| Fail::input(format!("--rule: {e}")))?;
            let budget = budget.budget()?;
            if let Some(dir) = write_papers {
                gradnormal::check_theorem_range(ratio)?;
                return proofs::gradnormal::report::write_papers(&dir, ratio, &budget)
                    .map_err(|e| Fail::run(e, &budget));
            }
            if let Some(n) = scan {
                let dir = PathBuf::from("papers/gradnormal/figures");
                let rows = proofs::gradnormal::report::scan(rule, n, &dir, &budget)
                    .map_err(|e| Fail::run(e, &budget))?;
                for r in rows {
                    println!("{r}");
                }
                return Ok(());
            }
            check_tol_deg(tol_deg)?;
            gradnormal::check_theorem_range(ratio)?;
            check_out_path(&out)?;
            let mut cfg = Config::new(ratio, rule);
            cfg.tol_cos = 0.5 * tol_deg * std::f64::consts::PI / 180.0;
            cfg.shard = shard.as_deref().map(parse_shard).transpose()?;
            cfg.progress = !json;
            cfg.budget = budget.clone();
            let cert = gradnormal::run(&cfg).map_err(|e| Fail::run(e, &budget))?;
            save_json(&out, &cert)?;
            if json {
                print_json(&gradnormal_json(&cert, &out))?;
            } else {
                print_human(&cert);
                println!("  certificate: {}", out.display());
            }
            Ok(())
        }
        Cmd::Stuffing {
            row,
            alpha_long,
            out,
            tol_deg,
            graded: true,
            trees,
            levels,
            model,
            certificates,
            budget,
            ..
        } => {
            if alpha_long.is_some() {
                return Err(Fail::input(
                    "--alpha-long/--alpha-short audit the uniform mesher; --graded proves the §5 daggers of Table 1 rows only",
                ));
            }
            graded_cmd(
                row.as_deref().unwrap_or("all"),
                json,
                &out,
                tol_deg,
                trees,
                levels,
                &model,
                certificates.as_deref(),
                budget.budget()?,
            )
        }
        Cmd::Stuffing {
            row,
            alpha_long,
            alpha_short,
            ordered,
            side,
            shard,
            out,
            tol_deg,
            count,
            graded: false,
            trees: _,
            levels: _,
            model: _,
            certificates: _,
            budget,
        } => stuffing_cmd(
            &stuffing_row_arg(row, alpha_long, alpha_short, ordered, &side)?,
            json,
            shard.as_deref(),
            &out,
            tol_deg,
            count,
            budget.budget()?,
        ),
        Cmd::StuffingFigures { certs, out, bounds } => {
            // Everything is checked before anything is written: unknown bound names, a
            // missing folder, a file that is not a certificate, no certificate at all.
            let known: Vec<&str> = stuffing::BOUNDS.iter().map(|(n, _, _)| *n).collect();
            let wanted: Vec<&str> = bounds.split(',').map(str::trim).collect();
            if let Some(bad) = wanted.iter().find(|w| !known.contains(w)) {
                return Err(Fail::input(format!(
                    "unknown bound '{bad}' in --bounds; known: {}",
                    known.join(" ")
                )));
            }
            // --certs is a folder of ROW.json certificates, or one certificate file.
            let certs_found: Vec<(String, stuffing::Certificate)> = if certs.is_file() {
                let c = load_stuffing(&certs)?;
                vec![(c.row.clone(), c)]
            } else if certs.is_dir() {
                let mut v = Vec::new();
                for name in stuffing::row_names() {
                    let p = certs.join(format!("{name}.json"));
                    if p.exists() {
                        v.push((name.to_string(), load_stuffing(&p)?));
                    }
                }
                if v.is_empty() {
                    return Err(Fail::input(format!(
                        "{}: no stuffing certificate ROW.json in this folder (rows: {})",
                        certs.display(),
                        stuffing::row_names().join(" ")
                    )));
                }
                v
            } else {
                return Err(Fail::input(format!(
                    "{}: no such certificate file or folder",
                    certs.display()
                )));
            };
            std::fs::create_dir_all(&out)
                .map_err(|e| Fail::input(format!("{}: {e}", out.display())))?;
            let mut written = 0;
            for (name, c) in &certs_found {
                for (b, (bn, _, _)) in stuffing::BOUNDS.iter().enumerate() {
                    if !wanted.contains(bn) {
                        continue;
                    }
                    let stem = out.join(format!("{name}-{bn}"));
                    if proofs::stuffing::figures::witness_figure(c, b, &stem)? {
                        println!("{}.svg", stem.display());
                        written += 1;
                    }
                }
            }
            if written == 0 {
                return Err(Fail::input(format!(
                    "no figure written: the {} certificate(s) read have no witness for {}",
                    certs_found.len(),
                    wanted.join(", ")
                )));
            }
            Ok(())
        }
        Cmd::Check { cert } if is_graded(&cert)? => {
            let c: stuffing::graded::DaggerCertificate =
                read_json(&cert, "graded dagger certificate")?;
            let t0 = std::time::Instant::now();
            let r = stuffing::graded::check_dagger(&c).map_err(Fail::check)?;
            if json {
                return print_json(&serde_json::json!({
                    "ok": true,
                    "kind": "graded-dagger",
                    "row": r.row,
                    "model": r.model,
                    "levels": r.levels,
                    "leaves": r.leaves,
                    "unresolved": r.unresolved,
                    "enclosure_deg": r.enclosure_deg,
                    "paper": r.paper,
                    "verdict": r.verdict,
                    "seconds": t0.elapsed().as_secs_f64(),
                }));
            }
            print_check_ok(
                &format!(
                    "graded dagger, row {} ({} model), {} problems",
                    r.row, r.model, r.distinct
                ),
                r.leaves,
                r.verdict != "undecided" && !r.verdict.starts_with("incomplete"),
                t0,
            );
            println!(
                "  max plane angle: superset supremum in [{:.6}, {:.6}] deg (paper {}): {}",
                r.enclosure_deg[0], r.enclosure_deg[1], r.paper, r.verdict
            );
            Ok(())
        }
        Cmd::Check { cert } if is_stuffing(&cert)? => {
            let c = load_stuffing(&cert)?;
            let t0 = std::time::Instant::now();
            let r = stuffing::check(&c).map_err(Fail::check)?;
            if json {
                return print_json(&serde_json::json!({
                    "ok": true,
                    "kind": "stuffing",
                    "row": c.row,
                    "complete": r.complete,
                    "partial": !r.complete,
                    "shard": c.shard.map(|s| format!("{}/{}", s[0], s[1])),
                    "problems": r.problems,
                    "leaves": r.leaves,
                    "bounds": r.bounds,
                    "safe": r.safe,
                    "seconds": t0.elapsed().as_secs_f64(),
                }));
            }
            print_check_ok(
                &format!("row {}, {} problems", c.row, r.problems),
                r.leaves,
                r.complete,
                t0,
            );
            if let Some(s) = c.shard {
                println!("  {}", shard_line(s, "the row"));
            }
            for b in &r.bounds {
                print_bound(b, c.partial);
            }
            println!(
                "  safe: {} (min volume ratio {:.6})",
                r.safe.verdict.name(),
                r.safe.min_ratio
            );
            Ok(())
        }
        Cmd::Merge { parts, out } if parts.first().map(is_stuffing).transpose()? == Some(true) => {
            check_out_path(&out)?;
            let certs: Result<Vec<stuffing::Certificate>, Fail> =
                parts.iter().map(load_stuffing).collect();
            let m = stuffing::merge(certs?)?;
            save_json(&out, &m)?;
            if json {
                return print_json(&stuffing::summary_json(&m, &out.display().to_string()));
            }
            print_stuffing(&m);
            Ok(())
        }
        Cmd::Check { cert } => {
            let c = load(&cert)?;
            let t0 = std::time::Instant::now();
            let r = gradnormal::check(&c).map_err(Fail::check)?;
            if json {
                return print_json(&serde_json::json!({
                    "ok": true,
                    "kind": "gradnormal",
                    "complete": r.complete,
                    "partial": !r.complete,
                    "shard": c.shard.map(|s| format!("{}/{}", s[0], s[1])),
                    "cases": r.cases,
                    "leaves": r.leaves,
                    "claims": r.claims,
                    "seconds": t0.elapsed().as_secs_f64(),
                }));
            }
            print_check_ok(&format!("{} cases", r.cases), r.leaves, r.complete, t0);
            if let Some(s) = c.shard {
                println!("  {}", shard_line(s, "the claims"));
            }
            for cl in &r.claims {
                println!("  {:9} {}", cl.verdict.name(), cl.claim);
            }
            Ok(())
        }
        Cmd::Pareto { dir, out, md } => {
            if !dir.is_dir() {
                return Err(Fail::input(format!(
                    "{}: not a folder of certificates",
                    dir.display()
                )));
            }
            let pts = stuffing::pareto::read_dir(
                &dir,
                |p| load_stuffing(&p.to_path_buf()).map_err(|f| f.msg),
                !json,
            )
            .map_err(Fail::input)?;
            let text = stuffing::pareto::markdown(&pts);
            let mut plots = Vec::new();
            if let Some(o) = &out {
                std::fs::create_dir_all(o)
                    .map_err(|e| Fail::input(format!("{}: {e}", o.display())))?;
                plots = stuffing::pareto::plots(&pts, o).map_err(Fail::input)?;
            }
            if let Some(m) = &md {
                check_out_path(m)?;
                std::fs::write(m, &text)
                    .map_err(|e| Fail::input(format!("{}: {e}", m.display())))?;
            }
            if json {
                let fronts: Vec<serde_json::Value> = stuffing::pareto::CRITERIA
                    .iter()
                    .flat_map(|&(c, lo, hi)| {
                        let pts = &pts;
                        [(false, false), (true, false), (false, true), (true, true)]
                            .into_iter()
                            .map(move |fam| {
                                serde_json::json!({
                                    "criterion": c,
                                    "family": stuffing::pareto::Point::family_name(fam.0, fam.1),
                                    "points": stuffing::pareto::front(pts, fam, lo, hi),
                                })
                            })
                    })
                    .filter(|v| !v["points"].as_array().is_some_and(|a| a.is_empty()))
                    .collect();
                print_json(&serde_json::json!({
                    "points": pts,
                    "fronts": fronts,
                    "findings": stuffing::pareto::findings(&pts),
                    "plots": plots,
                }))?;
            } else if md.is_none() {
                print!("{text}");
            } else {
                println!("{} pairs checked; table written", pts.len());
            }
            for p in plots {
                if !json {
                    println!("{}", p.display());
                }
            }
            Ok(())
        }
        Cmd::Report { dir, out } => {
            if !dir.is_dir() {
                return Err(Fail::input(format!(
                    "{}: not a folder of certificates",
                    dir.display()
                )));
            }
            let rows = stuffing::tables::read_dir(&dir, |p| {
                load_stuffing(&p.to_path_buf()).map_err(|f| f.msg)
            })
            .map_err(Fail::input)?;
            let md = stuffing::tables::markdown(&rows).map_err(Fail::input)?;
            match out {
                Some(o) => {
                    check_out_path(&o)?;
                    std::fs::write(&o, md)
                        .map_err(|e| Fail::input(format!("{}: {e}", o.display())))?;
                    println!("{}: tables of {} rows", o.display(), rows.len());
                }
                None => print!("{md}"),
            }
            Ok(())
        }
        Cmd::Witness { files, slack_deg } => {
            if !(slack_deg >= 0.0 && slack_deg.is_finite()) {
                return Err(Fail::input("--slack-deg must be a non-negative number"));
            }
            let mut paths = Vec::new();
            for f in files {
                if f.is_dir() {
                    let mut v: Vec<PathBuf> = std::fs::read_dir(&f)
                        .map_err(|e| Fail::input(format!("{}: {e}", f.display())))?
                        .filter_map(|e| e.ok().map(|e| e.path()))
                        .filter(|p| p.to_string_lossy().ends_with(".summary.json"))
                        .collect();
                    v.sort();
                    paths.extend(v);
                } else {
                    paths.push(f);
                }
            }
            if paths.is_empty() {
                return Err(Fail::input("no summary file (ROW.summary.json) found"));
            }
            let mut all = Vec::new();
            for p in &paths {
                let text = std::fs::read_to_string(p)
                    .map_err(|e| Fail::input(format!("{}: {e}", p.display())))?;
                let v: serde_json::Value = serde_json::from_str(&text)
                    .map_err(|e| Fail::input(format!("{}: {e}", p.display())))?;
                // A certificate (it has problems as a list): summarise it first.
                let v = if v["problems"].is_array() {
                    let c: stuffing::Certificate = serde_json::from_value(v)
                        .map_err(|e| Fail::input(format!("{}: {e}", p.display())))?;
                    stuffing::summary_json(&c, &p.display().to_string())
                } else {
                    v
                };
                all.extend(
                    proofs::witness_check::recompute(&v, slack_deg)
                        .map_err(|e| Fail::input(format!("{}: {e}", p.display())))?,
                );
            }
            let bad = all.iter().filter(|r| !r.agrees).count();
            if json {
                print_json(&serde_json::json!({"ok": bad == 0, "witnesses": all}))?;
            } else {
                for r in &all {
                    println!(
                        "{:28} {:12} paper {:>9}  float {:.6}  certified [{:.6}, {:.6}]  {}",
                        r.row,
                        r.bound,
                        r.paper
                            .map(|p| format!("{p:.4}"))
                            .unwrap_or_else(|| "n/a".into()),
                        r.float_deg,
                        r.certified_deg[0],
                        r.certified_deg[1],
                        if r.agrees { "agrees" } else { "DISAGREES" }
                    );
                }
            }
            if bad > 0 {
                return Err(Fail::check(format!(
                    "{bad} of {} witnesses disagree with their certified enclosures",
                    all.len()
                )));
            }
            Ok(())
        }
        Cmd::Regions { a } => {
            let ratio = Ratio::parse(&a).map_err(|e| Fail::input(format!("--a: {e}")))?;
            print!("{}", proofs::gradnormal::report::regions_markdown(ratio)?);
            Ok(())
        }
        Cmd::Merge { parts, out } => {
            check_out_path(&out)?;
            let certs: Result<Vec<Certificate>, Fail> = parts.iter().map(load).collect();
            let m = gradnormal::merge(certs?)?;
            save_json(&out, &m)?;
            if json {
                return print_json(&gradnormal_json(&m, &out));
            }
            print_human(&m);
            Ok(())
        }
    }
}

/// The `--row` of `proofs stuffing`, or the encoded name of a custom pair.
fn stuffing_row_arg(
    row: Option<String>,
    alpha_long: Option<String>,
    alpha_short: Option<String>,
    ordered: bool,
    side: &str,
) -> Result<String, Fail> {
    use proofs::stuffing::custom::Params;
    match (alpha_long, alpha_short) {
        (Some(l), Some(s)) => {
            let p = Params::new(
                Params::alpha(&l, "--alpha-long").map_err(Fail::input)?,
                Params::alpha(&s, "--alpha-short").map_err(Fail::input)?,
                ordered,
                side == "both",
            )
            .map_err(Fail::input)?;
            Ok(p.name())
        }
        _ => Ok(row.unwrap_or_else(|| "all".into())),
    }
}

fn stuffing_cmd(
    row: &str,
    json: bool,
    shard: Option<&str>,
    out: &PathBuf,
    tol_deg: f64,
    count: bool,
    budget: Budget,
) -> Result<(), Fail> {
    let names: Vec<&str> = if row == "all" {
        stuffing::row_names()
    } else {
        vec![
            stuffing::custom::resolve(row)
                .map_err(|e| Fail::input(format!("--row: {e}")))?
                .name,
        ]
    };
    check_tol_deg(tol_deg)?;
    let shard = shard.map(parse_shard).transpose()?;
    if count {
        for n in names {
            let r = stuffing::custom::resolve(n)?;
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
        if out.exists() && !out.is_dir() {
            return Err(Fail::input(format!(
                "{}: --row all writes one file per row into a directory",
                out.display()
            )));
        }
        std::fs::create_dir_all(out).map_err(|e| Fail::input(format!("{}: {e}", out.display())))?;
    } else {
        check_out_path(out)?;
    }
    let mut summaries = Vec::new();
    for n in names {
        let r = stuffing::custom::resolve(n)?;
        let mut cfg = stuffing::Config::new(r);
        cfg.tol_deg = tol_deg;
        cfg.shard = shard;
        cfg.progress = !json;
        // One budget per row.
        cfg.budget = budget.fresh();
        let path = if row == "all" {
            out.join(format!("{n}.json"))
        } else {
            out.clone()
        };
        let cert =
            stuffing::run(&cfg).map_err(|e| Fail::run(format!("row {n}: {e}"), &cfg.budget))?;
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
        print_json(&v)?;
    }
    Ok(())
}

/// The work estimate of one sample octree of the graded proof's sampled-context model
/// (about 3.3 million face configurations for the 96 default trees).
const GRADED_FACES_PER_TREE: u64 = 35_000;

fn graded_cmd(
    row: &str,
    json: bool,
    out: &PathBuf,
    tol_deg: f64,
    trees: usize,
    levels: u32,
    model: &str,
    certificates: Option<&std::path::Path>,
    budget: Budget,
) -> Result<(), Fail> {
    use proofs::stuffing::graded as g;
    if !(1..=6).contains(&levels) {
        return Err(Fail::input(format!(
            "--levels {levels}: the all-contexts model enumerates octree levels 0..=K for K in 1..=6"
        )));
    }
    let names: Vec<&str> = if row == "all" {
        g::DAGGERS.iter().map(|d| d.0).collect()
    } else if g::DAGGERS.iter().any(|d| d.0 == row) {
        vec![g::DAGGERS
            .iter()
            .find(|d| d.0 == row)
            .map(|d| d.0)
            .unwrap_or(row)]
    } else {
        return Err(Fail::input(format!(
            "--graded: row '{row}' has no dagger bound; the dagger rows are {}",
            g::DAGGERS.map(|d| d.0).join(" ")
        )));
    };
    let mut models = Vec::new();
    for m in model.split(',') {
        match m.trim() {
            "every" => models.extend([
                g::Model::Free,
                g::Model::Sampled(trees),
                g::Model::AllContexts(levels),
            ]),
            "free" => models.push(g::Model::Free),
            "sampled-contexts" => models.push(g::Model::Sampled(trees)),
            "all-contexts" => models.push(g::Model::AllContexts(levels)),
            other => {
                return Err(Fail::input(format!(
                    "--model {other}: expected free, sampled-contexts, all-contexts or every"
                )))
            }
        }
    }
    check_tol_deg(tol_deg)?;
    if trees == 0 {
        return Err(Fail::input("--trees must be at least 1"));
    }
    let estimate = trees as u64 * GRADED_FACES_PER_TREE;
    if estimate > budget.max_boxes() {
        return Err(Fail::input(format!(
            "--trees {trees}: about {GRADED_FACES_PER_TREE} face configurations per sample octree, {estimate} in all, above the work budget of {} (--max-boxes N raises it; or lower --trees)",
            budget.max_boxes()
        )));
    }
    check_out_path(out)?;
    if let Some(dir) = certificates {
        if !dir.is_dir() {
            return Err(Fail::input(format!(
                "--certificates {}: not a folder",
                dir.display()
            )));
        }
    }
    let mut all = Vec::new();
    for &n in &names {
        let r = certmesh::stuffing::row(n).map_err(|e| e.to_string())?;
        for &model in &models {
            let cert = g::certify_model(r, tol_deg, model, &budget);
            let res = cert.result.clone();
            if res.verdict.starts_with("incomplete") {
                return Err(Fail {
                    kind: Kind::Budget,
                    msg: format!("graded row {n}: {}", res.verdict),
                    position: None,
                });
            }
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
            if let Some(dir) = certificates {
                let path = dir.join(format!("graded-{}-{}.json", res.row, res.model));
                save_json(&path, &cert)?;
                if !json {
                    println!("  certificate: {}", path.display());
                }
            }
            all.push(res);
        }
    }
    // The safe property of the non-BCC tetrahedra, over the all-contexts model.
    let mut safe = Vec::new();
    if models.iter().any(|m| matches!(m, g::Model::AllContexts(_))) {
        for n in &names {
            let r = certmesh::stuffing::row(n).map_err(|e| e.to_string())?;
            let a = proofs::stuffing::cases::Alphas::of(r);
            let t0 = std::time::Instant::now();
            let sres = proofs::stuffing::contexts::safe_non_bcc(&a, levels);
            if !json {
                println!(
                    "non-BCC safe property, row {n} (all-contexts, levels 0..={levels}): {} ({} configurations, min volume ratio {:.6} at a {} tetrahedron, {:.1} s)",
                    sres.verdict,
                    sres.configurations,
                    sres.min_ratio,
                    sres.witness.0,
                    t0.elapsed().as_secs_f64()
                );
            }
            safe.push(serde_json::json!({"row": n, "result": sres}));
        }
    }
    let v = serde_json::json!({ "daggers": all, "non_bcc_safe": safe });
    let text = serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?;
    std::fs::write(out, &text).map_err(|e| Fail::input(format!("{}: {e}", out.display())))?;
    if json {
        println!("{text}");
    }
    Ok(())
}

fn main() -> ExitCode {
    let json = std::env::args_os().any(|a| a == "--json");
    // In every subcommand a negative number is an option's value (`--a -1` gets that
    // option's range error, not "unexpected argument").
    let parsed = {
        use clap::{CommandFactory, FromArgMatches};
        Cli::command()
            .mut_subcommands(|c| c.allow_negative_numbers(true))
            .try_get_matches()
            .and_then(|m| Cli::from_arg_matches(&m))
    };
    let cli = match parsed {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind;
            let info = matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            );
            if json && !info {
                let f = Fail {
                    kind: Kind::Usage,
                    // clap's first paragraph on one line (a missing argument's name
                    // is on the line after "were not provided:").
                    msg: e
                        .to_string()
                        .lines()
                        .take_while(|l| !l.trim().is_empty())
                        .map(str::trim)
                        .collect::<Vec<_>>()
                        .join(" ")
                        .trim_start_matches("error: ")
                        .to_string(),
                    position: None,
                };
                return report(&f, true);
            }
            e.exit()
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => report(&f, json),
    }
}
