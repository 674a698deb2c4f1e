//! The `certmesh` command line. Every subcommand prints a readable report, or JSON with
//! `--json`. Errors name the problem; with `--json` an error is a JSON object on stdout.
//!
//! Exit status: 0 success; 2 usage and input errors (bad option, formula, domain, file,
//! output path or format: all checked before the work starts); 1 a failure while doing
//! the work (e.g. an output that could not be written at the end).
#[macro_use]
mod errors;
mod args;
mod certify_cmd;
mod compare_cmd;
mod delaunay_cmd;
mod figures_cmd;
mod input;
mod memory;
mod mesh_cmd;
mod morse_cmd;
mod progress;
mod render_cmd;
mod stats_cmd;

use args::*;
use compare_cmd::*;
use errors::*;
use mesh_cmd::*;
use stats_cmd::*;

use certmesh::catalog::{self};
use certmesh::mesher::registry as algorithms;
use clap::{Parser, Subcommand};
use std::io::Write;
use std::path::PathBuf;

/// certmesh — certified meshing of implicit curves and surfaces.
///
/// A surface is f(x, y, z) = 0 (a curve f(x, y) = 0), given as a catalog name
/// (`certmesh surfaces`) or a formula (`--formula "x^2 + y^2 + z^2 - 1"`, or
/// `--formula @FILE` / `--formula-file FILE` for long formulas). Convention: f < 0
/// inside. Every mesher returns a certificate: `certified` with what interval arithmetic
/// proved, or `uncertified` with where and why.
///
/// Formula language: numbers, x y z, + - * /, ^ with an integer exponent, unary minus,
/// parentheses, sqrt abs min max, pi; with the `mpfr` feature also sin cos exp ln.
///
/// Exit status: 0 success, 2 usage or input error (checked before any work), 1 failure
/// during the work. With --json an error is printed on stdout as
/// {"error": MESSAGE, "kind": KIND, "position": COLUMN-or-LINE-or-null}.
#[derive(Parser)]
#[command(name = "certmesh", version, about, long_about, max_term_width = 100)]
struct Cli {
    /// No progress display on stderr (it is also off when stderr is not a terminal).
    #[arg(long, short = 'q', global = true)]
    quiet: bool,
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// List the catalog of test surfaces and curves with their known topology.
    ///
    /// Example: certmesh surfaces --json
    #[command(verbatim_doc_comment)]
    Surfaces {
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// List the meshing algorithms (`--algo` names).
    ///
    /// Example: certmesh algos
    #[command(verbatim_doc_comment)]
    Algos {
        #[arg(long)]
        json: bool,
    },
    /// Mesh a surface f(x, y, z) = 0 and write the mesh.
    ///
    /// A formula without --domain is meshed in the default domain [-2, 2]³.
    ///
    /// Examples:
    ///   certmesh mesh torus --algo mc --resolution 64 -o torus.obj
    ///   certmesh mesh --formula "x^2 + y^2 + z^2 - 1" --algo pv -o sphere.obj
    ///   certmesh mesh -f "x^4 + y^4 + z^4 - 1" --domain -1.2,-1.2,-1.2,1.2,1.2,1.2 --algo mc -o s.ply
    ///   certmesh mesh -f "(x^2 + y^2 + z^2 - 1)^2" --algo pv --max-boxes 2000 -o x.obj
    #[command(verbatim_doc_comment)]
    Mesh(MeshArgs),
    /// Mesh a curve f(x, y) = 0 and write it as SVG or CSV.
    ///
    /// A formula without --domain is meshed in the default domain [-2, 2]².
    ///
    /// Examples:
    ///   certmesh curve cassini-2 --algo ms --resolution 32 -o c.svg
    ///   certmesh curve --formula "x^2 + 4*y^2 - 1" --algo pv -o e.csv
    #[command(verbatim_doc_comment)]
    Curve(MeshArgs),
    /// Re-verify the certificate of an exact curve sweep (`certmesh curve --algo gvn
    /// --certificate CERT.json`) with exact rationals, without re-running the sweep:
    /// every sign, root count, root box, branch count and inside decision, the
    /// completeness of the events, and the output graph rebuilt from the counts.
    /// Exit status 1 when the certificate is rejected (the message says which claim).
    ///
    /// Example:
    ///   certmesh curve lemniscate --algo gvn --certificate lem.json -o lem.svg
    ///   certmesh check-curve lem.json
    #[command(verbatim_doc_comment)]
    CheckCurve {
        /// The certificate (JSON).
        file: PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// Statistics of a mesh file: counts, topology, angles; fidelity when a surface is given.
    ///
    /// Triangle meshes (obj off ply stl) and tetrahedral meshes (vtk mesh). Fidelity
    /// distances are sampled estimates ("Hausdorff (est.)"), not bounds; a quantity that
    /// could not be measured is reported as undefined (null in JSON) with the reason.
    ///
    /// Examples:
    ///   certmesh stats data/spot.obj
    ///   certmesh stats torus.obj --surface torus --histogram torus-angles
    #[command(verbatim_doc_comment)]
    Stats(StatsArgs),
    /// Run several algorithms on several catalog entries and compare them side by side.
    ///
    /// Prints a markdown table: topology verdict against the catalog, what was found,
    /// angle range, Hausdorff estimate, time, evaluations of f, certificate.
    /// Surfaces are meshed by the 3D algorithms, curves by the 2D ones; an algorithm
    /// that fits none of the entries given is an error.
    ///
    /// Example:
    ///   certmesh compare --surfaces two-spheres,thin-torus --algos mc,pv --resolution 21
    #[command(verbatim_doc_comment)]
    Compare(CompareArgs),
    /// The certified Morse census: critical points, indices, Euler characteristic.
    ///
    /// Lists the critical points of f (grad f = 0) in the domain, each in a box proven
    /// to hold exactly one, with an enclosure of its value and its Morse index from a
    /// certified Hessian inertia (interval Krawczyk); boxes where nothing could be
    /// decided are reported by reason (a degenerate or non-isolated critical set, such
    /// as the torus's circle of minima, is reported as not proven Morse, never
    /// guessed). Then chi({f <= 0}) = sum of (-1)^index over the critical points with
    /// f < 0, and chi(S) = 2 chi({f <= 0}), certified only when f > 0 is proven on
    /// the domain boundary and f is proven Morse on {f <= 0}; and the census
    /// #min - #saddle + #max of the height <n, x> on S (--height), which is chi(S)
    /// when that search is complete, every index certified and S away from the
    /// boundary. Every claim says certified or uncertified, with why. --mesh prints
    /// a mesh's chi beside the certified one. --remedy counts the critical points
    /// of g = f·(a + |x - b|^2) (or the chapter's a + |x - b|) instead: same sign as
    /// f, so the same S and {f <= 0}, and a degenerate critical set of f (the
    /// torus's circle) generically becomes isolated Morse points of g; the report
    /// states the transformation.
    ///
    /// Examples:
    ///   certmesh morse tanglecube
    ///   certmesh morse torus --remedy smooth
    ///   certmesh morse torus --max-boxes 20000 --json
    ///   certmesh morse --formula "x^2 + y^2 + z^2 - 1" --height 0,0,1
    ///   certmesh morse torus --max-boxes 20000 --mesh torus.obj
    #[command(verbatim_doc_comment)]
    Morse(morse_cmd::MorseArgs),
    /// 3D Delaunay triangulation of random or given points, with the exact check.
    ///
    /// Builds the triangulation with certmesh's kernel (BRIO + Hilbert order, filtered
    /// exact predicates with symbolic perturbation), checks it (every cell positively
    /// oriented by the exact orient3d, every facet locally Delaunay), and prints
    /// points/s, cells and memory. Duplicates are reported, not inserted.
    ///
    /// Examples:
    ///   certmesh delaunay --random 100000 --on sphere --seed 3
    ///   certmesh delaunay points.xyz -o tets.vtk --json
    #[command(verbatim_doc_comment)]
    Delaunay(delaunay_cmd::DelaunayArgs),
    /// Certify anyone's surface mesh: homeomorphic to f = 0 by the topological ball
    /// property (the chapter "Meshing of Surfaces", §1.3.2, Theorem 5).
    ///
    /// Builds the Delaunay triangulation of the mesh's vertices (exact predicates),
    /// derives the restricted Delaunay triangulation (every crossing of every Voronoi
    /// edge isolated with interval arithmetic) and checks the topological ball
    /// property on every Voronoi edge, facet and cell meeting f = 0 (the chapter's
    /// tests (1)-(4) as checks: nothing is inserted). Reports (a) whether the mesh is
    /// the restricted Delaunay triangulation of its vertices (which triangles differ),
    /// (b) whether the property holds (which Voronoi faces fail and why), (c)
    /// "certified homeomorphic" only when both hold. Homeomorphism, not isotopy
    /// (Research Problem 4). No local feature size is needed and the vertices need
    /// not lie on f = 0: the report bounds max |f|/|grad f| over them. The exit
    /// status is 0 whether or not the mesh is certified (read the verdict, or
    /// "homeomorphic" in --json).
    ///
    /// Examples:
    ///   certmesh mesh sphere --algo cdrr -o s.obj
    ///   certmesh certify s.obj --surface sphere
    ///   certmesh certify s.obj --formula "x^2 + y^2 + z^2 - 1" --json -o rdt.off
    #[command(verbatim_doc_comment)]
    Certify(certify_cmd::CertifyArgs),
    /// The main job on built-in defaults: mesh catalog entries with every algorithm,
    /// print the comparison, write the meshes, angle histograms, one rendering per
    /// surface and method (renders/, coloured by that run's certificate) and index.html
    /// (each surface's rows of the table beside its pictures; no JavaScript) to the
    /// output folder.
    ///
    /// Example: certmesh demo --quick
    #[command(verbatim_doc_comment)]
    Demo {
        #[arg(long, default_value = "out/demo")]
        out: PathBuf,
        /// A smaller run (coarser settings, fewer surfaces).
        #[arg(long)]
        quick: bool,
        #[command(flatten)]
        format: figures_cmd::FormatArg,
        #[arg(long)]
        json: bool,
    },
    /// Regenerate a paper's reproduction folder (tables and figures) under papers/.
    ///
    /// Papers: gradnormal, stuffing, meshing-of-surfaces; morse (the same chapter's
    /// §1.5: BCSV, the Morse census, Stander–Hart) writes morse.md into
    /// papers/meshing-of-surfaces.
    ///
    /// Example: certmesh reproduce meshing-of-surfaces --quick --out papers-quick/meshing-of-surfaces
    #[command(verbatim_doc_comment)]
    Reproduce {
        /// Which paper: gradnormal, stuffing, meshing-of-surfaces or morse.
        paper: String,
        /// Output folder (default: papers/<paper>; papers/meshing-of-surfaces for morse).
        #[arg(long)]
        out: Option<PathBuf>,
        /// A fast, smaller run.
        #[arg(long)]
        quick: bool,
        #[command(flatten)]
        format: figures_cmd::FormatArg,
    },
    /// Regenerate every figure of papers/ in the figure style and index them.
    ///
    /// Runs `certmesh reproduce` for each paper into OUT (tables included), removes the
    /// figures of those folders that no run writes any more, checks every SVG under OUT
    /// (fonts of at least 7 pt at the printed width, labelled axes, a legend when a
    /// figure has more than one series) and writes OUT/FIGURES.md: each figure, what it
    /// shows, the command that made it, its formats and the result of the check.
    /// Figures of the proofs binary (papers/*/figures/) are indexed and checked, not
    /// regenerated: they need its certificates (the command is listed).
    ///
    /// `certmesh figures --quick --out DIR` makes the reduced set in about a minute.
    ///
    /// Example: certmesh figures --check --out out/demo/renders
    #[command(verbatim_doc_comment)]
    Figures(figures_cmd::FiguresArgs),
    /// Render a mesh to a picture (PNG at 300 dpi, SVG or PDF), headless.
    ///
    /// A software z-buffer with flat or Gouraud shading draws a triangle mesh or the
    /// boundary of a tetrahedral mesh, seen from --view, one column (3.3 in) wide, with
    /// a colour bar (--color quality) or a legend. --cut keeps one side of a plane and,
    /// on a tetrahedral mesh, shows the faces of the tetrahedra it cuts (the stuffing
    /// paper's Fig. 1). --color certificate colours what the mesher's certificate says,
    /// and only that: faces meeting a region it reported uncertified, faces inside the
    /// box of an isotopy claim of a certified output, and the rest as making no claim;
    /// it needs the certificate, so it meshes and renders in one step (--surface with
    /// --algo).
    ///
    /// Example: certmesh render --surface sphere --algo mc --resolution 12 -o s.png --wire
    /// Example: certmesh render --surface torus --algo stuffing --cut y=0 -o t.svg
    /// Example: certmesh render --surface double-cone --algo pv --max-depth 4 --color certificate -o c.pdf
    #[command(verbatim_doc_comment)]
    Render(render_cmd::RenderArgs),
}

/// The command line, parsed. In every subcommand a negative number is an option's
/// value (`--margin -1` gets that option's range error, not "unexpected argument").
fn parse(args: &[std::ffi::OsString]) -> Result<Cli, clap::Error> {
    use clap::{CommandFactory, FromArgMatches};
    let cmd = Cli::command().mut_subcommands(|c| c.allow_negative_numbers(true));
    Cli::from_arg_matches(&cmd.try_get_matches_from(args)?)
}

fn main() {
    memory::keep_freed_memory();
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let json = wants_json(&args);
    let cli = match parse(&args) {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind;
            let informational = matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            );
            if informational || !json {
                // clap prints help/version (exit 0) and usage errors (exit 2).
                e.exit();
            }
            let text = e.render().to_string();
            // The message: clap's first paragraph on one line (a missing argument's
            // name is on the line after "were not provided:").
            let first = text
                .lines()
                .take_while(|l| !l.trim().is_empty())
                .map(str::trim)
                .collect::<Vec<_>>()
                .join(" ")
                .trim_start_matches("error: ")
                .to_string();
            report_error(
                &CliError {
                    message: first,
                    kind: "usage",
                    position: None,
                    code: EXIT_INPUT,
                },
                true,
            );
        }
    };
    let quiet = cli.quiet;
    // The command runs on one of rayon's threads, not beside them: a parallel call
    // made from outside the pool hands its work to a worker and sleeps until it is
    // done, and on one thread that costs two thread switches per call (a marching
    // mesher makes dozens; whole runs on one thread took 5-16 % longer). The workers
    // get a larger stack than the main thread's 8 MiB (reserved, not committed).
    // RAYON_NUM_THREADS sets the pool's size, as it did the global pool's.
    let pool = rayon::ThreadPoolBuilder::new()
        .stack_size(64 << 20)
        .build()
        .unwrap_or_else(|e| {
            report_error(
                &CliError {
                    message: format!("cannot start the worker threads: {e}"),
                    kind: "io",
                    position: None,
                    code: EXIT_RUNTIME,
                },
                json,
            )
        });
    if let Err(e) = pool.install(|| run(cli.cmd, quiet)) {
        report_error(&e, json);
    }
}

fn run(cmd: Cmd, quiet: bool) -> CliResult<()> {
    match cmd {
        Cmd::Surfaces { json } => {
            let all = catalog::entries();
            if json {
                print_json(&all);
            } else {
                out!("| name | kind | formula | domain | components | genus | smooth | note |\n|---|---|---|---|---|---|---|---|");
                for e in all {
                    let (c, g) = match e.topology {
                        Some(t) => (t.components.to_string(), format!("{:?}", t.genus)),
                        None => ("singular".into(), "–".into()),
                    };
                    out!(
                        "| {} | {} | `{}` | {:?}..{:?} | {} | {} | {} | {} |",
                        e.name,
                        if e.dim == 2 { "curve" } else { "surface" },
                        e.formula,
                        e.domain.min,
                        e.domain.max,
                        c,
                        g,
                        e.smooth,
                        e.note
                    );
                }
            }
        }
        Cmd::Algos { json } => {
            let l = algorithms::list();
            if json {
                print_json(&l);
            } else {
                for i in l {
                    out!(
                        "{:<12} {}D  {:<13} {}",
                        i.name,
                        i.dim,
                        if i.certifying {
                            "certifying"
                        } else {
                            "uncertified"
                        },
                        i.summary
                    );
                }
            }
        }
        Cmd::Mesh(a) => mesh_cmd(a, 3, quiet)?,
        Cmd::Curve(a) => mesh_cmd(a, 2, quiet)?,
        Cmd::Stats(a) => stats_cmd(a, quiet)?,
        Cmd::CheckCurve { file, json } => check_curve_cmd(&file, json)?,
        Cmd::Compare(a) => compare_cmd(a, quiet)?,
        Cmd::Delaunay(a) => delaunay_cmd::delaunay_cmd(a)?,
        Cmd::Certify(a) => certify_cmd::certify_cmd(a, quiet)?,
        Cmd::Morse(a) => morse_cmd::morse_cmd(a, quiet)?,
        Cmd::Demo {
            out,
            quick,
            format,
            json,
        } => {
            format.apply()?;
            demo_cmd(&out, quick, json, quiet)?
        }
        Cmd::Reproduce {
            paper,
            out,
            quick,
            format,
        } => {
            format.apply()?;
            reproduce_cmd(&paper, out.as_deref(), quick, quiet)?
        }
        Cmd::Figures(a) => figures_cmd::figures_cmd(a, quiet)?,
        Cmd::Render(a) => render_cmd::render_cmd(a, quiet)?,
    }
    Ok(())
}
