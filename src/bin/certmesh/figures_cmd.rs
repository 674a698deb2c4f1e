//! `certmesh figures`: regenerate every figure of `papers/` in the figure style, remove
//! the stale ones, check them all, and write `papers/FIGURES.md`.
use crate::errors::*;
use crate::progress::Bar;
use certmesh::error::Error;
use certmesh::figure::{check, output};
use certmesh::mesher::Progress as _;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The figure formats of a command that writes figures (`--format`).
#[derive(clap::Args, Clone, Debug)]
pub(crate) struct FormatArg {
    /// Figure formats, comma-separated: svg (vector, text as text), png (300 dpi), pdf
    /// (vector, for LaTeX). Every figure is drawn once and converted.
    #[arg(long = "format", value_name = "LIST", default_value = "svg,png")]
    pub format: String,
}

impl FormatArg {
    /// Parse and make the process default (checked before any work: exit 2).
    pub(crate) fn apply(&self) -> CliResult<Vec<output::Format>> {
        let f = output::Format::parse_list(&self.format)?;
        output::set_default_formats(&f);
        Ok(f)
    }
}

#[derive(clap::Args)]
pub(crate) struct FiguresArgs {
    /// The papers folder to regenerate (its subfolders gradnormal, stuffing,
    /// meshing-of-surfaces) and to index in FIGURES.md.
    #[arg(long, default_value = "papers")]
    pub out: PathBuf,
    #[command(flatten)]
    pub format: FormatArg,
    /// The reduced runs of `certmesh reproduce --quick` (seconds; for tests and drafts).
    #[arg(long)]
    pub quick: bool,
    /// Only check the SVG figures already in OUT (fonts, axes, legends) and write no
    /// file; exit 1 if any figure breaks the style.
    #[arg(long, conflicts_with = "index_only")]
    pub check: bool,
    /// Regenerate nothing: check the figures in OUT and rewrite OUT/FIGURES.md (after
    /// `certmesh reproduce PAPER` or a `proofs` command redrew some of them).
    #[arg(long)]
    pub index_only: bool,
    #[arg(long)]
    pub json: bool,
}

/// Which figures a name pattern covers, what they show, and the command that makes them.
struct Kind {
    prefix: &'static str,
    what: &'static str,
    command: &'static str,
}

const KINDS: &[Kind] = &[
    Kind { prefix: "meshing-of-surfaces/fig-pv-", what: "Plantinga–Vegter subdivision of a catalog curve: leaves coloured by the criterion that certified them, true curve and output polyline (the chapter's Figs. 1.9–1.10)", command: "certmesh reproduce meshing-of-surfaces" },
    Kind { prefix: "meshing-of-surfaces/fig-snyder-", what: "Snyder subdivision of a catalog curve: leaves coloured by the criterion that certified them (global parameterizability, the chapter's Fig. 1.7)", command: "certmesh reproduce meshing-of-surfaces" },
    Kind { prefix: "meshing-of-surfaces/fig-slice-", what: "the slice z = 0 of a surface mesh against the true curve: marching cubes (MC27 / MC33) versus Plantinga–Vegter, where marching gets the topology wrong (the chapter's Fig. 1.5 in 3D)", command: "certmesh reproduce meshing-of-surfaces" },
    Kind { prefix: "meshing-of-surfaces/fig-boxes-per-depth", what: "boxes per subdivision depth of the 3D runs", command: "certmesh reproduce meshing-of-surfaces" },
    Kind { prefix: "meshing-of-surfaces/fig-gvn-", what: "the González-Vega–Necula sweep of an algebraic curve: event and rational fibres, arcs, singular and isolated points (the chapter's Fig. 1.16)", command: "certmesh reproduce meshing-of-surfaces" },
    Kind { prefix: "meshing-of-surfaces/fig-rdt2d-", what: "Boissonnat–Oudot refinement of a catalog curve (`certmesh curve NAME --algo bo`): sample points, their Voronoi edges, the crossings with the curve (curve Delaunay ball centres) and their balls, the restricted Delaunay edges and the curve, at stages of the refinement (the chapter's §1.3; restricted-delaunay-2d.md)", command: "certmesh reproduce meshing-of-surfaces" },
    Kind { prefix: "meshing-of-surfaces/fig-sweep-", what: "level sets of a Morse function across a critical value, meshed by Plantinga–Vegter (the chapter's §1.5 sweep)", command: "certmesh reproduce morse" },
    Kind { prefix: "meshing-of-surfaces/render-", what: "a rendering of a surface mesh (certmesh render)", command: "certmesh render" },
    Kind { prefix: "gradnormal/angles", what: "GradNormal and MidNormal triangle-angle distributions (the paper's Fig. 4) with the paper's claimed bounds and the certified bounds for planes as dashed lines", command: "certmesh reproduce gradnormal" },
    Kind { prefix: "gradnormal/bunny-angles", what: "angle distributions of the Stanford bunny remesh (the paper's Fig. 3)", command: "certmesh reproduce gradnormal" },
    Kind { prefix: "gradnormal/render-", what: "a rendering of a GradNormal mesh (the paper's Figs. 1–2)", command: "certmesh render" },
    Kind { prefix: "gradnormal/figures/scan-", what: "certified GradNormal angle bounds against a/e (9 values in [0.2, 0.6], tolerance 1e-4°), paper's diagonal rule", command: "cargo run --release -p proofs -- gradnormal --scan 9" },
    Kind { prefix: "gradnormal/figures/", what: "figures of the computer-assisted proof of the angle bounds (Appendix A): the projected angles along the boundary arcs of the regions of normals (Figs 14–18) and maps of the smallest and largest angle over a region", command: "cargo run --release -p proofs -- gradnormal --a sommerville --write-papers papers/gradnormal" },
    Kind { prefix: "stuffing/hist-", what: "dihedral angle histogram of a stuffed tetrahedral mesh in 2° bins, rare bins ×20 in a second colour, Table 1 bounds dashed (the paper's Fig. 1)", command: "certmesh reproduce stuffing" },
    Kind { prefix: "stuffing/render-", what: "a rendering of a stuffed tetrahedral mesh (the paper's Fig. 1 cutaway)", command: "certmesh render" },
    Kind { prefix: "stuffing/figures/pareto-", what: "the certified Pareto front of the stuffing parameters, with Table 1's rows", command: "cargo run --release -p proofs -- pareto certs/grid --out papers/stuffing/figures" },
    Kind { prefix: "stuffing/figures/", what: "the worst configuration of a Table 1 row and bound found by the proof (the paper's Fig. 5)", command: "cargo run --release -p proofs -- stuffing-figures --certs certs --out papers/stuffing/figures --bounds min_dihedral,max_dihedral,max_exposed" },
];

/// What a command needs first, by figure prefix: certificates kept out of the repository.
const NEEDS: &[(&str, &str)] = &[
    ("stuffing/figures/pareto-", "The certificates of the parameter grid first: `proofs stuffing --alpha-long A --alpha-short B --tol-deg 1e-3 -o certs/grid/p-A-B.json` for each pair of `papers/stuffing/PARETO.md` (How it was run)."),
    ("stuffing/figures/", "The row certificates first: `proofs stuffing --row ROW --json -o certs/ROW.json` for each row (`papers/stuffing/PROOF.md`)."),
];

fn kind_of(rel: &str) -> Option<&'static Kind> {
    KINDS.iter().find(|k| rel.starts_with(k.prefix))
}

fn svgs(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "svg") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

#[derive(serde::Serialize)]
struct Entry {
    file: String,
    formats: Vec<String>,
    what: String,
    command: String,
    problems: Vec<String>,
}

fn index(out: &Path) -> CliResult<Vec<Entry>> {
    let mut v = Vec::new();
    for p in svgs(out) {
        let rel = p
            .strip_prefix(out)
            .unwrap_or(&p)
            .to_string_lossy()
            .replace('\\', "/");
        let text = std::fs::read_to_string(&p).map_err(|e| CliError::from(Error::io(&p, e)))?;
        let problems = check::check_svg(&text)?.problems;
        let formats = ["svg", "png", "pdf"]
            .into_iter()
            .filter(|x| output::with_ext(&p.with_extension(""), x).exists())
            .map(String::from)
            .collect();
        let (what, command) = kind_of(&rel)
            .map(|k| (k.what.to_string(), k.command.to_string()))
            .unwrap_or_else(|| ("(not made by a known command)".into(), "–".into()));
        v.push(Entry {
            file: rel,
            formats,
            what,
            command,
            problems,
        });
    }
    Ok(v)
}

fn markdown(entries: &[Entry]) -> String {
    let mut md = String::from("# Figures of `papers/`\n\nEvery figure of the reproduction folders, what it shows and the command that made it. All are drawn once in the figure style of `certmesh::figure` (one column of 3.3 in or the full width of 7 in, fonts of at least 7 pt at that width, the Okabe–Ito palette, legends below the plot) and written as SVG (text as text) and PNG at 300 dpi, PDF on request (`--format svg,png,pdf`). `certmesh figures` regenerates those made by `certmesh` and checks every SVG here (`certmesh figures --check`: fonts, axis labels, legends); those made by the `proofs` binary need its certificates and are regenerated by the command given (`cargo run --release -p proofs -- --format svg,png,pdf ...` for PDF too).\n\nNot figures: the `.svg` curve files that `certmesh mesh` and `demo` write for planar meshes (`io::write_curve`, `meshes/*.svg` of a demo run) are a mesh output format: the polyline in its own coordinates at full precision and nothing else (no axes, no text), for other programs to read; the demo's page shows the figure of each curve instead (`renders/*.png`, axes in the curve's coordinates, in this style).\n\n");
    let mut by_kind: Vec<(String, &str, &str, Vec<&Entry>)> = Vec::new();
    for e in entries {
        let head = kind_of(&e.file)
            .map(|k| format!("{}*", k.prefix))
            .unwrap_or_else(|| e.file.clone());
        match by_kind.iter_mut().find(|k| k.0 == head) {
            Some(k) => k.3.push(e),
            None => by_kind.push((head, &e.what, &e.command, vec![e])),
        }
    }
    for (head, what, command, es) in by_kind {
        let _ = writeln!(md, "## `{head}`\n\n{what}.\n\nMade by: `{command}`\n");
        if let Some((_, n)) = NEEDS.iter().find(|(p, _)| head.starts_with(p)) {
            let _ = writeln!(md, "{n}\n");
        }
        let _ = writeln!(md, "| figure | formats | style check |\n|---|---|---|");
        for e in es {
            let _ = writeln!(
                md,
                "| [{}]({}) | {} | {} |",
                e.file,
                e.file,
                e.formats.join(", "),
                if e.problems.is_empty() {
                    "passes".to_string()
                } else {
                    format!("**{}**", e.problems.join("; "))
                }
            );
        }
        md.push('\n');
    }
    md
}

pub(crate) fn figures_cmd(a: FiguresArgs, quiet: bool) -> CliResult<()> {
    let formats = a.format.apply()?;
    if (a.check || a.index_only) && !a.out.is_dir() {
        return Err(CliError::from(Error::Param(format!(
            "--out: '{}' is not a folder of figures to check",
            a.out.display()
        ))));
    }
    if !a.check && !a.index_only {
        crate::input::check_out_dir(&a.out)?;
        let bar = Bar::new(quiet);
        let mut folders: Vec<PathBuf> = Vec::new();
        for paper in certmesh::reproduce::PAPERS {
            bar.phase(paper);
            let folder = a.out.join(
                certmesh::reproduce::default_out(paper)
                    .file_name()
                    .unwrap_or_default(),
            );
            certmesh::reproduce::reproduce(paper, &folder, a.quick).runtime()?;
            if !folders.contains(&folder) {
                folders.push(folder);
            }
        }
        bar.finish();
        // Stale figures: in a folder certmesh regenerates (not its subfolders, which
        // the proofs binary writes), in a figure format, not written by this run.
        let written = output::written();
        for f in &folders {
            let Ok(rd) = std::fs::read_dir(f) else {
                continue;
            };
            for e in rd.flatten() {
                let p = e.path();
                let fig = p
                    .extension()
                    .and_then(|x| x.to_str())
                    .is_some_and(|x| ["svg", "png", "pdf"].contains(&x));
                if fig && p.is_file() && !written.contains(&p) {
                    std::fs::remove_file(&p)
                        .map_err(|e| CliError::from(Error::io(&p, e)).runtime())?;
                }
            }
        }
    }
    let entries = index(&a.out)?;
    if !a.check {
        let p = a.out.join("FIGURES.md");
        std::fs::write(&p, markdown(&entries))
            .map_err(|e| CliError::from(Error::io(&p, e)).runtime())?;
    }
    let bad: Vec<&Entry> = entries.iter().filter(|e| !e.problems.is_empty()).collect();
    if a.json {
        print_json(&serde_json::json!({
            "figures": entries,
            "formats": formats.iter().map(|f| f.ext()).collect::<Vec<_>>(),
            "failing": bad.len(),
        }));
    } else {
        for e in &bad {
            out!("{}: {}", e.file, e.problems.join("; "));
        }
        out!(
            "{} figures in {}, {} breaking the style{}",
            entries.len(),
            a.out.display(),
            bad.len(),
            if a.check { "" } else { "; index in FIGURES.md" }
        );
    }
    if a.check && !bad.is_empty() {
        return Err(CliError::from(Error::Param(format!(
            "{} figures break the style (fonts, axis labels or legends)",
            bad.len()
        )))
        .runtime());
    }
    Ok(())
}
