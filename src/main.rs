//! The `certmesh` command line. Every subcommand prints a readable report, or JSON with
//! `--json`. Errors name the problem; with `--json` an error is a JSON object on stdout.
//!
//! Exit status: 0 success; 2 usage and input errors (bad option, formula, domain, file,
//! output path or format: all checked before the work starts); 1 a failure while doing
//! the work (e.g. an output that could not be written at the end).
mod progress;

use certmesh::catalog::{self, Entry};
use certmesh::error::{Error, Result};
use certmesh::harness::compare;
use certmesh::implicit::{Formula, Implicit};
use certmesh::kernel::geom::Aabb;
use certmesh::mesher::options::{Crossing, MesherOptions};
use certmesh::mesher::registry as algorithms;
use certmesh::mesher::{self, Certificate, Mesh, Progress};
use certmesh::{io, metrics};
use clap::{Args, Parser, Subcommand};
use progress::Bar;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Half-width of the default domain of a formula: [-2, 2]³ for surfaces, [-2, 2]² for
/// curves (the catalog's unit-scale shapes fit in it).
const DEFAULT_HALF_WIDTH: f64 = 2.0;

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
    ///   certmesh mesh --formula 0 --domain -1,-1,-1,1,1,1 --algo pv --max-boxes 2000 -o x.obj
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
    Stats {
        /// The mesh file.
        mesh: PathBuf,
        /// Compare against this catalog surface (fidelity fields, topology verdict).
        #[arg(long, conflicts_with_all = ["formula", "formula_file"])]
        surface: Option<String>,
        /// Compare against this formula (`@FILE` reads it from a file).
        #[arg(long, conflicts_with = "formula_file")]
        formula: Option<String>,
        /// Compare against the formula in this file.
        #[arg(long, value_name = "FILE")]
        formula_file: Option<PathBuf>,
        /// Write an angle histogram (BASE.svg and BASE.png; a .svg or .png ending of
        /// BASE is dropped, so `h.png` writes h.svg and h.png).
        #[arg(long, value_name = "BASE")]
        histogram: Option<PathBuf>,
        /// Histogram bin width in degrees.
        #[arg(long, default_value_t = 2.0)]
        bin: f64,
        /// Draw rare bins magnified by this factor on top of the true bars (the
        /// stuffing paper's Figs 1 and 4 use 20); 1 draws the plain histogram.
        #[arg(long, default_value_t = 1.0, value_name = "K")]
        emphasis: f64,
        #[arg(long)]
        json: bool,
    },
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
    Compare {
        /// Catalog surfaces (comma separated; default: a representative set).
        #[arg(long, value_delimiter = ',')]
        surfaces: Vec<String>,
        /// Catalog curves (comma separated).
        #[arg(long, value_delimiter = ',')]
        curves: Vec<String>,
        /// Algorithms (comma separated; default: all that handle the entry's dimension).
        #[arg(long, value_delimiter = ',')]
        algos: Vec<String>,
        #[command(flatten)]
        opts: OptArgs,
        /// Also write the table to this file: .md (markdown), .json (the rows as
        /// --json prints them) or .csv.
        #[arg(short, long)]
        output: Option<PathBuf>,
        #[arg(long)]
        json: bool,
    },
    /// The main job on built-in defaults: mesh catalog entries with every algorithm,
    /// print the comparison, write the meshes and angle histograms to the output folder.
    ///
    /// Example: certmesh demo --quick
    #[command(verbatim_doc_comment)]
    Demo {
        #[arg(long, default_value = "out/demo")]
        out: PathBuf,
        /// A smaller run (coarser settings, fewer surfaces).
        #[arg(long)]
        quick: bool,
        #[arg(long)]
        json: bool,
    },
    /// Regenerate a paper's reproduction folder (tables and figures) under papers/.
    ///
    /// Papers: gradnormal, stuffing, meshing-of-surfaces.
    ///
    /// Example: certmesh reproduce meshing-of-surfaces --quick --out papers-quick/meshing-of-surfaces
    #[command(verbatim_doc_comment)]
    Reproduce {
        /// Which paper: gradnormal, stuffing or meshing-of-surfaces.
        paper: String,
        /// Output folder (default: papers/<paper>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// A fast, smaller run.
        #[arg(long)]
        quick: bool,
    },
}

#[derive(Args, Clone)]
struct MeshArgs {
    /// A catalog name (see `certmesh surfaces`).
    name: Option<String>,
    /// A formula instead of a catalog name; `@FILE` reads it from FILE (for formulas
    /// longer than the command line allows).
    #[arg(long, short = 'f', conflicts_with = "formula_file")]
    formula: Option<String>,
    /// Read the formula from this file (same as `--formula @FILE`).
    #[arg(long, value_name = "FILE")]
    formula_file: Option<PathBuf>,
    /// Remesh a triangle mesh (obj ply off stl) through its signed distance (exact
    /// distance, winding-number sign), normalised into the unit cube [0, 1]³ (the domain
    /// unless --domain is given), as GradNormal's Sec. 5.1. Never certified.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["formula", "formula_file"])]
    mesh_input: Option<PathBuf>,
    /// With --mesh-input: margin left on each side of the unit cube.
    #[arg(long, default_value_t = 0.05, requires = "mesh_input")]
    margin: f64,
    /// With --mesh-input: close the mesh's boundary loops (holes) by fans first.
    #[arg(long, requires = "mesh_input")]
    fill_holes: bool,
    /// The domain box: x0,y0,z0,x1,y1,z1 (curves: x0,y0,x1,y1). Default: the catalog's
    /// box for a catalog name, [-2, 2]³ (curves [-2, 2]²) for a formula, the unit cube
    /// for --mesh-input. The report says which domain was used.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    domain: Vec<f64>,
    /// The algorithm (see `certmesh algos`).
    #[arg(long)]
    algo: String,
    #[command(flatten)]
    opts: OptArgs,
    /// Output file; the format follows the extension (surfaces: obj off ply stl, volume
    /// meshes also vtk mesh; curves: svg csv). Checked before the work starts.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// For volume meshers: also write the boundary surface here (obj off ply stl).
    #[arg(long)]
    boundary: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Args, Clone, Default)]
struct OptArgs {
    /// Grid cells along the longest side of the domain (lattice meshers).
    #[arg(long)]
    resolution: Option<usize>,
    /// Lattice edge length (GradNormal's e, stuffing's spacing).
    #[arg(long)]
    scale: Option<f64>,
    /// Maximum subdivision depth (subdivision meshers).
    #[arg(long)]
    max_depth: Option<u32>,
    /// Minimum subdivision depth.
    #[arg(long)]
    min_depth: Option<u32>,
    /// Move the grid to generic position first (Snyder's remedy for grazing cases).
    #[arg(long)]
    generic_shift: bool,
    /// Edge crossings: linear or bisection.
    #[arg(long)]
    crossing: Option<String>,
    /// Crossing tolerance, relative to the edge length.
    #[arg(long)]
    tolerance: Option<f64>,
    /// Prune empty space with interval arithmetic (marching meshers).
    #[arg(long)]
    prune: bool,
    /// A named parameter set (e.g. an isosurface-stuffing Table 1 row).
    #[arg(long)]
    params: Option<String>,
    /// Graded variant (isosurface stuffing).
    #[arg(long)]
    graded: bool,
    /// Budget of box tests of the subdivision meshers (pv, snyder; default 1000000,
    /// a few seconds). When it is spent the run stops: the boxes not yet decided are
    /// returned as uncertified regions with the reason "box budget exhausted (raise
    /// --max-boxes)", the stats say refinement_complete: false, the report says that
    /// the run stopped and why, and nothing is certified.
    #[arg(long, value_name = "N")]
    max_boxes: Option<u64>,
    /// Wall-clock limit of the subdivision meshers (pv, snyder), in seconds (default:
    /// none). A run stopped by it reports "time limit reached (raise --time-limit)",
    /// refinement_complete: false, and certifies nothing.
    #[arg(long, value_name = "SECONDS")]
    time_limit: Option<f64>,
    /// Algorithm-specific settings, key=value (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

impl OptArgs {
    fn to_options(&self) -> Result<MesherOptions> {
        let mut o = MesherOptions {
            resolution: self.resolution,
            scale: self.scale,
            max_depth: self.max_depth,
            min_depth: self.min_depth,
            generic_shift: self.generic_shift,
            crossing: self
                .crossing
                .as_deref()
                .map(|s| s.parse::<Crossing>())
                .transpose()?,
            tolerance: self.tolerance,
            prune: self.prune,
            max_boxes: self.max_boxes,
            time_limit: self.time_limit,
            params: self.params.clone(),
            graded: self.graded,
            extra: Default::default(),
        };
        if let Some(r) = o.resolution {
            if r == 0 {
                return Err(Error::Param("--resolution must be at least 1".into()));
            }
        }
        if let Some(s) = o.scale {
            if !(s.is_finite() && s > 0.0) {
                return Err(Error::Param(format!(
                    "--scale must be a positive number, got {s}"
                )));
            }
        }
        if o.max_boxes == Some(0) {
            return Err(Error::Param("--max-boxes must be at least 1".into()));
        }
        if let Some(t) = o.time_limit {
            if !(t.is_finite() && t > 0.0) {
                return Err(Error::Param(format!(
                    "--time-limit must be a positive number of seconds, got {t}"
                )));
            }
        }
        for kv in &self.set {
            let (k, v) = kv
                .split_once('=')
                .ok_or_else(|| Error::Param(format!("--set expects KEY=VALUE, got '{kv}'")))?;
            o.extra.insert(k.trim().to_string(), v.trim().to_string());
        }
        Ok(o)
    }
}

// ---------------------------------------------------------------------------------
// Errors and exit codes

/// An error as the command line reports it: the message, a kind, a position (formula
/// column or file line) and the exit code.
struct CliError {
    message: String,
    kind: &'static str,
    position: Option<usize>,
    code: i32,
}

/// Exit code of usage and input errors.
const EXIT_INPUT: i32 = 2;
/// Exit code of a failure while doing the work.
const EXIT_RUNTIME: i32 = 1;

impl From<Error> for CliError {
    fn from(e: Error) -> Self {
        let (kind, position) = match &e {
            Error::Parse { column, .. } | Error::NeedsFeature { column, .. } => {
                ("formula", Some(*column))
            }
            Error::Format { line, .. } => ("file", (*line > 0).then_some(*line)),
            Error::Param(_) => ("parameter", None),
            Error::Domain(_) => ("domain", None),
            Error::TooLarge(_) => ("too-large", None),
            Error::NotFinite(_) => ("not-finite", None),
            Error::Unknown { .. } => ("unknown-name", None),
            Error::Io { .. } => ("io", None),
        };
        CliError {
            message: e.to_string(),
            kind,
            position,
            code: EXIT_INPUT,
        }
    }
}

impl CliError {
    /// The same error, as a failure during the work (exit 1).
    fn runtime(mut self) -> Self {
        self.code = EXIT_RUNTIME;
        self
    }
    fn with_prefix(mut self, p: &str) -> Self {
        self.message = format!("{p}: {}", self.message);
        self
    }
}

type CliResult<T> = std::result::Result<T, CliError>;

/// `result.runtime()`: a library error met while doing the work (exit 1).
trait Runtime<T> {
    fn runtime(self) -> CliResult<T>;
}
impl<T> Runtime<T> for Result<T> {
    fn runtime(self) -> CliResult<T> {
        self.map_err(|e| CliError::from(e).runtime())
    }
}

/// Print a line on stdout; a closed pipe (`certmesh ... | head`) is not an error.
macro_rules! out {
    ($($t:tt)*) => {{
        let _ = writeln!(std::io::stdout().lock(), $($t)*);
    }};
}

fn print_json(v: &impl serde::Serialize) {
    out!(
        "{}",
        serde_json::to_string_pretty(v).expect("reports serialize")
    );
}

/// Does the command line ask for JSON output? (Used for errors clap reports before the
/// arguments are parsed.)
fn wants_json(args: &[std::ffi::OsString]) -> bool {
    args.iter().skip(1).any(|a| a == "--json")
}

fn report_error(e: &CliError, json: bool) -> ! {
    if json {
        print_json(&serde_json::json!({
            "error": e.message,
            "kind": e.kind,
            "position": e.position,
        }));
    } else {
        eprintln!("certmesh: error: {}", e.message);
    }
    std::process::exit(e.code);
}

fn main() {
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let json = wants_json(&args);
    let cli = match Cli::try_parse_from(&args) {
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
            let first = text
                .lines()
                .next()
                .unwrap_or("")
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
    if let Err(e) = run(cli.cmd, quiet) {
        report_error(&e, json);
    }
}

// ---------------------------------------------------------------------------------
// Checks made before the work starts

/// Fail now, not after the work, if `path` cannot be written: its directory must
/// exist and the file must be creatable (an existing file is not truncated here).
fn check_writable(path: &Path) -> CliResult<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(CliError::from(Error::io(
            path,
            std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!("the directory {} does not exist", dir.display()),
            ),
        )));
    }
    if path.is_dir() {
        return Err(CliError::from(Error::io(
            path,
            std::io::Error::other("is a directory, not a file"),
        )));
    }
    let existed = path.exists();
    std::fs::OpenOptions::new()
        .append(true)
        .create(true)
        .open(path)
        .map_err(|e| CliError::from(Error::io(path, e)))?;
    if !existed {
        let _ = std::fs::remove_file(path);
    }
    Ok(())
}

/// Check an output mesh path: known extension, a format that holds what the command
/// produces, writable.
fn check_mesh_output(path: &Path, dim: usize) -> CliResult<()> {
    let f = io::Format::from_path(path)?;
    let ok = if dim == 2 {
        f.holds_curves()
    } else {
        f.holds_triangles()
    };
    if !ok {
        return Err(CliError::from(Error::Param(format!(
            "{}: a .{} file cannot hold {}; use {}",
            path.display(),
            f.extension(),
            if dim == 2 {
                "a curve"
            } else {
                "a surface or volume mesh"
            },
            if dim == 2 {
                ".svg or .csv"
            } else {
                ".obj .off .ply .stl (surfaces), .vtk .mesh (volume meshes)"
            }
        ))));
    }
    check_writable(path)
}

/// Create (if needed) an output folder and check it is writable, before the work.
fn check_out_dir(dir: &Path) -> CliResult<()> {
    std::fs::create_dir_all(dir).map_err(|e| CliError::from(Error::io(dir, e)))?;
    let probe = dir.join(format!(".certmesh-write-test-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| CliError::from(Error::io(dir, e)))?;
    let _ = std::fs::remove_file(probe);
    Ok(())
}

/// The formula text: `--formula TEXT`, `--formula @FILE` or `--formula-file FILE`.
/// Returns the text and the file it came from.
fn formula_text(
    formula: Option<&str>,
    file: Option<&Path>,
) -> CliResult<Option<(String, Option<PathBuf>)>> {
    let path = match (formula, file) {
        (Some(t), None) => match t.strip_prefix('@') {
            Some(p) => PathBuf::from(p),
            None => return Ok(Some((t.to_string(), None))),
        },
        (None, Some(p)) => p.to_path_buf(),
        (None, None) => return Ok(None),
        (Some(_), Some(_)) => {
            return Err(CliError::from(Error::Param(
                "give --formula or --formula-file, not both".into(),
            )))
        }
    };
    let text = std::fs::read_to_string(&path).map_err(|e| CliError::from(Error::io(&path, e)))?;
    Ok(Some((text.trim_end().to_string(), Some(path))))
}

/// Parse a formula, naming its file in the error.
fn parse_formula(text: &str, file: Option<&Path>, dim: usize) -> CliResult<Formula> {
    Formula::with_dim(text, dim).map_err(|e| {
        let e = CliError::from(e);
        match file {
            Some(p) => e.with_prefix(&p.display().to_string()),
            None => e,
        }
    })
}

// ---------------------------------------------------------------------------------
// mesh / curve

/// The function, domain and expected topology a mesh/curve command works on.
struct Target {
    name: String,
    f: Box<dyn Implicit>,
    domain: Aabb,
    /// Where the domain came from: "catalog", "--domain", "default", "unit cube".
    domain_source: &'static str,
    entry: Option<Entry>,
}

fn domain_from(v: &[f64], dim: usize) -> Result<Aabb> {
    match (v.len(), dim) {
        (6, 3) => Aabb::new([v[0], v[1], v[2]], [v[3], v[4], v[5]]),
        (4, 2) => Aabb::new([v[0], v[1], 0.0], [v[2], v[3], 0.0]),
        (n, _) => Err(Error::Domain(format!(
            "--domain needs {} numbers ({}), got {n}",
            if dim == 3 { 6 } else { 4 },
            if dim == 3 {
                "x0,y0,z0,x1,y1,z1"
            } else {
                "x0,y0,x1,y1"
            }
        ))),
    }
}

/// The default domain of a formula: [-2, 2]³, or [-2, 2]² for a curve.
fn default_domain(dim: usize) -> Aabb {
    let h = DEFAULT_HALF_WIDTH;
    let z = if dim == 3 { h } else { 0.0 };
    Aabb::new([-h, -h, -z], [h, h, z]).expect("a valid box")
}

fn target(a: &MeshArgs, dim: usize) -> CliResult<Target> {
    if let Some(path) = &a.mesh_input {
        return mesh_input_target(a, path, dim);
    }
    let formula = formula_text(a.formula.as_deref(), a.formula_file.as_deref())?;
    let (name, f, entry): (String, Box<dyn Implicit>, Option<Entry>) = match (&a.name, formula) {
        (Some(_), Some(_)) => {
            return Err(CliError::from(Error::Param(
                "give a catalog name or --formula, not both".into(),
            )))
        }
        (None, None) => {
            return Err(CliError::from(Error::Param(
                "give a catalog name (see `certmesh surfaces`) or --formula".into(),
            )))
        }
        (Some(n), None) => {
            let e = catalog::get(n)?;
            if e.dim != dim {
                return Err(CliError::from(Error::Param(format!(
                    "'{n}' is a {}; use `certmesh {}`",
                    if e.dim == 2 { "curve" } else { "surface" },
                    if e.dim == 2 { "curve" } else { "mesh" }
                ))));
            }
            (n.clone(), Box::new(e.function()), Some(e))
        }
        (None, Some((t, file))) => (
            "formula".to_string(),
            Box::new(parse_formula(&t, file.as_deref(), dim)?),
            None,
        ),
    };
    let (domain, domain_source) = match (&entry, a.domain.is_empty()) {
        (_, false) => (domain_from(&a.domain, dim)?, "--domain"),
        (Some(e), true) => (e.domain, "catalog"),
        (None, true) => (default_domain(dim), "default"),
    };
    let s = domain.size();
    if (0..dim).any(|k| s[k] <= 0.0) {
        return Err(CliError::from(Error::Domain(format!(
            "the domain {:?}..{:?} is empty along some axis",
            domain.min, domain.max
        ))));
    }
    Ok(Target {
        name,
        f,
        domain,
        domain_source,
        entry,
    })
}

/// `--mesh-input FILE`: the signed distance to a mesh, normalised into the unit cube.
fn mesh_input_target(a: &MeshArgs, path: &Path, dim: usize) -> CliResult<Target> {
    if dim != 3 {
        return Err(CliError::from(Error::Param(
            "--mesh-input gives a surface; use `certmesh mesh`".into(),
        )));
    }
    if a.name.is_some() {
        return Err(CliError::from(Error::Param(
            "give a catalog name or --mesh-input, not both".into(),
        )));
    }
    let (f, holes) = certmesh::implicit::sdf::from_file(path, a.margin, a.fill_holes)?;
    if a.fill_holes && !a.json {
        eprintln!(
            "{}: closed {} boundary loops ({} boundary edges left open)",
            path.display(),
            holes.filled,
            holes.open_edges
        );
    }
    let (domain, domain_source) = if a.domain.is_empty() {
        (Aabb::new([0.0; 3], [1.0; 3])?, "unit cube")
    } else {
        (domain_from(&a.domain, 3)?, "--domain")
    };
    let name = path
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".into());
    Ok(Target {
        name,
        f: Box::new(f),
        domain,
        domain_source,
        entry: None,
    })
}

/// "[-2, 2] × [-2, 2] × [-2, 2]".
fn fmt_domain(d: &Aabb, dim: usize) -> String {
    (0..dim)
        .map(|k| format!("[{}, {}]", d.min[k], d.max[k]))
        .collect::<Vec<_>>()
        .join(" × ")
}

/// Why a run stopped before its refinement was complete (a budget), if it did.
fn stop_reason(run: &mesher::Run) -> Option<String> {
    let complete = run
        .output
        .stats
        .get("refinement_complete")
        .and_then(|v| v.as_bool());
    if complete != Some(false) {
        return None;
    }
    let budget = [
        certmesh::subdivision::BOX_BUDGET_REASON,
        certmesh::subdivision::TIME_LIMIT_REASON,
    ];
    let from_regions = match &run.output.certificate {
        Certificate::Uncertified { regions, .. } => budget
            .iter()
            .find(|b| regions.iter().any(|r| r.reason == **b))
            .map(|b| b.to_string()),
        _ => None,
    };
    Some(from_regions.unwrap_or_else(|| "a work budget was spent".into()))
}

fn mesh_cmd(a: MeshArgs, dim: usize, quiet: bool) -> CliResult<()> {
    // Everything the user gave is checked before any work.
    let opts = a.opts.to_options()?;
    let m = algorithms::build(&a.algo, dim, &opts)?;
    if let Some(out) = &a.output {
        check_mesh_output(out, dim)?;
    }
    if let Some(b) = &a.boundary {
        check_mesh_output(b, 3)?;
    }
    let bar = Bar::new(quiet);
    bar.phase("preparing");
    let t = target(&a, dim)?;
    bar.phase(&a.algo);
    let run = mesher::run(m.as_ref(), t.f.as_ref(), &t.domain, &bar)?;
    bar.phase("writing");
    if let Some(out) = &a.output {
        io::write_mesh(out, &run.output.mesh).runtime()?;
    }
    let mut notes = Vec::new();
    match (&a.boundary, &run.output.mesh) {
        (Some(b), Mesh::Volume { boundary, .. }) => io::write_tri(b, boundary).runtime()?,
        (Some(_), _) => notes.push(format!(
            "--boundary ignored: '{}' produces no volume mesh",
            a.algo
        )),
        _ => {}
    }
    bar.phase("fidelity");
    let row = compare::evaluate(
        &t.name,
        t.f.as_ref(),
        &t.domain,
        t.entry.as_ref().and_then(|e| e.topology.as_ref()),
        &run,
    )?;
    bar.finish();
    let stopped = stop_reason(&run);
    if a.json {
        let mut v = serde_json::to_value(&row).expect("row serializes");
        let o = v.as_object_mut().expect("object");
        o.insert(
            "uncertified_boxes".into(),
            serde_json::json!(match &run.output.certificate {
                Certificate::Uncertified { regions, .. } => regions.len(),
                _ => 0,
            }),
        );
        o.insert(
            "reason".into(),
            serde_json::json!(run.output.certificate.reason()),
        );
        o.insert(
            "stats".into(),
            serde_json::Value::Object(run.output.stats.clone()),
        );
        o.insert(
            "evaluation_counts".into(),
            serde_json::to_value(run.evaluations).unwrap(),
        );
        o.insert("domain".into(), serde_json::to_value(t.domain).unwrap());
        o.insert("domain_source".into(), serde_json::json!(t.domain_source));
        if let Some(rc) = run.output.stats.get("refinement_complete") {
            o.insert("refinement_complete".into(), rc.clone());
        }
        o.insert("stopped".into(), serde_json::json!(stopped));
        o.insert("notes".into(), serde_json::json!(notes));
        if let Some(out) = &a.output {
            o.insert(
                "output".into(),
                serde_json::json!(out.display().to_string()),
            );
        }
        print_json(&v);
    } else {
        out!(
            "{}",
            compare::markdown(std::slice::from_ref(&row)).trim_end()
        );
        out!(
            "domain: {}{}",
            fmt_domain(&t.domain, dim),
            match t.domain_source {
                "default" => " (the default domain of a formula; set --domain)",
                "catalog" => " (the catalog's)",
                "unit cube" => " (the unit cube of --mesh-input)",
                _ => "",
            }
        );
        if let Some(why) = &stopped {
            out!(
                "stopped before the refinement was complete: {why} (refinement_complete: false); \
                 the output is partial and nothing is certified"
            );
        }
        if let Some(n) = &row.hausdorff_note {
            out!("Hausdorff (est.): {n}");
        }
        if let Certificate::Uncertified { regions, .. } = &run.output.certificate {
            for r in regions.iter().take(10) {
                out!(
                    "uncertified region {:?}..{:?}: {}",
                    r.region.min,
                    r.region.max,
                    r.reason
                );
            }
            if regions.len() > 10 {
                out!(
                    "... and {} more uncertified regions (see --json)",
                    regions.len() - 10
                );
            }
        }
        for c in run.output.certificate.claims() {
            out!("proven: {c}");
        }
        for n in &notes {
            out!("note: {n}");
        }
        if let Some(out) = &a.output {
            out!("wrote {}", out.display());
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------
// stats

struct StatsArgs {
    mesh: PathBuf,
    surface: Option<String>,
    formula: Option<String>,
    formula_file: Option<PathBuf>,
    histogram: Option<PathBuf>,
    bin: f64,
    emphasis: f64,
    json: bool,
}

/// The histogram base: a trailing .svg or .png is dropped (both files are written).
fn histogram_base(h: &Path) -> PathBuf {
    match h.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("svg") || e.eq_ignore_ascii_case("png") => {
            h.with_extension("")
        }
        _ => h.to_path_buf(),
    }
}

/// A measured number for text: "undefined" (NaN) and "inf" are said as such.
fn num(x: f64, prec: usize) -> String {
    if x.is_nan() {
        "undefined".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{x:.prec$e}")
    }
}

fn stats_cmd(a: StatsArgs, quiet: bool) -> CliResult<()> {
    let fmt = io::Format::from_path(&a.mesh)?;
    let entry = a.surface.as_deref().map(catalog::get).transpose()?;
    if let Some(e) = &entry {
        if e.dim != 3 {
            return Err(CliError::from(Error::Param(format!(
                "'{}' is a curve; stats compares a mesh file with a surface",
                e.name
            ))));
        }
    }
    let formula = formula_text(a.formula.as_deref(), a.formula_file.as_deref())?;
    let f: Option<Box<dyn Implicit>> = match (&entry, formula) {
        (Some(e), _) => Some(Box::new(e.function())),
        (None, Some((t, file))) => Some(Box::new(parse_formula(&t, file.as_deref(), 3)?)),
        _ => None,
    };
    let fref = f.as_deref();
    if !(a.bin.is_finite() && a.bin > 0.0) {
        return Err(CliError::from(Error::Param(format!(
            "--bin must be positive, got {}",
            a.bin
        ))));
    }
    if !(a.emphasis.is_finite() && a.emphasis >= 1.0) {
        return Err(CliError::from(Error::Param(format!(
            "--emphasis must be a factor >= 1, got {}",
            a.emphasis
        ))));
    }
    let hist = a.histogram.as_deref().map(histogram_base);
    if let Some(h) = &hist {
        for ext in ["svg", "png"] {
            let mut name = h.file_name().unwrap_or_default().to_os_string();
            name.push(format!(".{ext}"));
            check_writable(&h.with_file_name(name))?;
        }
    }
    let params = {
        let p = metrics::FidelityParams::default();
        match &entry {
            Some(e) => p.domain(e.domain),
            None => p,
        }
    };
    let bar = Bar::new(quiet);
    bar.phase("reading");
    // A VTK file is tetrahedral; a MEDIT file is read as tetrahedra when it has any,
    // as its triangles otherwise.
    let tets = match fmt {
        io::Format::Vtk => Some(io::read_tet(&a.mesh)?),
        io::Format::Medit => Some(io::read_tet(&a.mesh)?).filter(|m| !m.tets.is_empty()),
        _ => None,
    };
    if let Some(m) = tets {
        bar.phase("measuring");
        let s = metrics::tet_stats(&m, fref, &params)?;
        if let Some(h) = &hist {
            bar.phase("histogram");
            let d: Vec<f64> = (0..m.tets.len())
                .flat_map(|t| metrics::angles::dihedral_angles(&m.corners(t)))
                .collect();
            certmesh::reproduce::plot::histogram(
                h,
                "dihedral angles",
                "degrees",
                "tetrahedra",
                &certmesh::reproduce::plot::bin(d, a.bin, false),
                &[],
                a.emphasis,
            )
            .runtime()?;
        }
        bar.finish();
        print_json(&s);
        return Ok(());
    }
    let m = io::read_tri(&a.mesh)?;
    bar.phase(if fref.is_some() {
        "fidelity"
    } else {
        "measuring"
    });
    let s = metrics::stats_with(&m, fref, &params)?;
    let verdict = match &entry {
        Some(e) => e
            .topology
            .as_ref()
            .map(|t| metrics::verdict(&metrics::analyze(&m).expect("checked"), t)),
        None => None,
    };
    if let Some(h) = &hist {
        bar.phase("histogram");
        let ang: Vec<f64> = metrics::angles::per_triangle(&m)?
            .into_iter()
            .flatten()
            .flatten()
            .collect();
        certmesh::reproduce::plot::histogram(
            h,
            "triangle angles",
            "degrees",
            "density",
            &certmesh::reproduce::plot::bin(ang, a.bin, true),
            &[],
            a.emphasis,
        )
        .runtime()?;
    }
    bar.finish();
    if a.json {
        let mut v = serde_json::to_value(&s).unwrap();
        if let Some(vd) = &verdict {
            v.as_object_mut()
                .unwrap()
                .insert("topology_verdict".into(), serde_json::to_value(vd).unwrap());
        }
        print_json(&v);
    } else {
        let plural =
            |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
        let genus = if s.genus.is_empty() {
            "genus: n/a (no closed orientable component)".to_string()
        } else {
            format!("genus per closed component: {:?}", s.genus)
        };
        out!(
            "{}: {} vertices ({} used, {} isolated), {} faces, {} edges, χ = {}, {}, closed: {}, manifold: {}, oriented: {}, {}, {}",
            a.mesh.display(),
            s.vertices + s.isolated_vertices,
            s.vertices,
            s.isolated_vertices,
            s.faces,
            s.edges,
            s.euler_characteristic,
            plural(s.components, "component", "components"),
            s.closed,
            s.manifold,
            s.consistently_oriented,
            plural(s.boundary_loops, "boundary loop", "boundary loops"),
            genus
        );
        if let (Some(x), Some(y)) = (s.min_angle_deg, s.max_angle_deg) {
            out!(
                "angles: [{x:.3}°, {y:.3}°], {} degenerate triangles",
                s.degenerate_triangles
            );
        }
        if s.non_manifold_edges + s.non_manifold_vertices + s.degenerate_faces + s.duplicate_faces
            > 0
        {
            out!(
                "defects: {} non-manifold edges, {} non-manifold vertices, {} degenerate faces, {} duplicate faces",
                s.non_manifold_edges, s.non_manifold_vertices, s.degenerate_faces, s.duplicate_faces
            );
        }
        if let Some(fd) = &s.fidelity {
            out!(
                "fidelity: Hausdorff (est.) ≈ {} (mesh→surface {}, surface→mesh {}), max |f|/|∇f| = {}, normal deviation max {}",
                num(fd.hausdorff, 3),
                num(fd.hausdorff_mesh_to_surface, 3),
                num(fd.hausdorff_surface_to_mesh, 3),
                num(fd.max_distance_estimate, 3),
                if fd.normal_dev_max_deg.is_finite() {
                    format!("{:.2}°", fd.normal_dev_max_deg)
                } else {
                    num(fd.normal_dev_max_deg, 2)
                }
            );
            // The reasons of the measured fields (the means and the two-sided maximum
            // repeat them; --json has every field).
            for (field, why) in &fd.fidelity_undefined {
                if field != "hausdorff"
                    && !field.starts_with("mean_")
                    && !field.ends_with("mean_deg")
                {
                    out!("  {field}: {why}");
                }
            }
        }
        if let Some(vd) = verdict {
            out!(
                "topology: {} (expected {}, found {}) {}",
                if vd.ok { "ok" } else { "WRONG" },
                vd.expected,
                vd.found,
                vd.reason
            );
        }
        if let Some(h) = &hist {
            out!("wrote {}.svg and {}.png", h.display(), h.display());
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------
// compare, demo, reproduce

fn default_algos(dim: usize) -> Vec<String> {
    algorithms::list()
        .into_iter()
        .filter(|i| i.dim == dim)
        .map(|i| i.name.to_string())
        .collect()
}

/// Catalog entries of the given dimension; a name of the other kind is an error.
fn entries(names: &[String], dim: usize) -> CliResult<Vec<Entry>> {
    names
        .iter()
        .map(|n| {
            let e = catalog::get(n)?;
            if e.dim != dim {
                let (is, opt) = if e.dim == 2 {
                    ("a curve", "--curves")
                } else {
                    ("a surface", "--surfaces")
                };
                return Err(CliError::from(Error::Param(format!(
                    "'{n}' is {is}: give it with {opt}"
                ))));
            }
            Ok(e)
        })
        .collect()
}

/// What `compare -o FILE` writes, by extension.
#[derive(Clone, Copy)]
enum TableFormat {
    Markdown,
    Json,
    Csv,
}

fn table_format(p: &Path) -> CliResult<TableFormat> {
    let ext = p
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match ext.as_str() {
        "md" | "markdown" => Ok(TableFormat::Markdown),
        "json" => Ok(TableFormat::Json),
        "csv" => Ok(TableFormat::Csv),
        _ => Err(CliError::from(Error::Unknown {
            kind: "table format",
            name: if ext.is_empty() {
                p.display().to_string()
            } else {
                ext
            },
            known: "md json csv".into(),
        })),
    }
}

struct CompareArgs {
    surfaces: Vec<String>,
    curves: Vec<String>,
    algos: Vec<String>,
    opts: OptArgs,
    output: Option<PathBuf>,
    json: bool,
}

fn compare_cmd(a: CompareArgs, quiet: bool) -> CliResult<()> {
    let o = a.opts.to_options()?;
    let (mut s, c) = (a.surfaces, a.curves);
    if s.is_empty() && c.is_empty() {
        s = ["sphere", "torus", "two-spheres", "thin-torus"]
            .map(String::from)
            .to_vec();
    }
    let mut es = entries(&s, 3)?;
    es.extend(entries(&c, 2)?);
    let dims: Vec<usize> = es.iter().map(|e| e.dim).collect();
    let explicit = !a.algos.is_empty();
    let algos = if !explicit {
        let mut v = default_algos(3);
        for x in default_algos(2) {
            if !v.contains(&x) {
                v.push(x);
            }
        }
        v
    } else {
        let list = algorithms::list();
        for name in &a.algos {
            let handles: Vec<usize> = list
                .iter()
                .filter(|i| i.name == name.as_str())
                .map(|i| i.dim)
                .collect();
            if handles.is_empty() {
                return Err(CliError::from(
                    algorithms::build(name, 3, &o)
                        .err()
                        .expect("unknown algorithm"),
                ));
            }
            if !handles.iter().any(|d| dims.contains(d)) {
                let what = |d: usize| if d == 2 { "curves" } else { "surfaces" };
                return Err(CliError::from(Error::Param(format!(
                    "'{name}' meshes {} ({}D) only, and no {} were given (use {})",
                    what(handles[0]),
                    handles[0],
                    what(handles[0]),
                    if handles[0] == 2 {
                        "--curves"
                    } else {
                        "--surfaces"
                    }
                ))));
            }
        }
        a.algos
    };
    // Every algorithm option is checked once before the matrix runs.
    for name in &algos {
        for d in [2, 3] {
            if dims.contains(&d)
                && algorithms::list()
                    .iter()
                    .any(|i| i.name == name && i.dim == d)
            {
                algorithms::build(name, d, &o)?;
            }
        }
    }
    let fmt = match &a.output {
        Some(p) => {
            let f = table_format(p)?;
            check_writable(p)?;
            Some(f)
        }
        None => None,
    };
    let bar = Bar::new(quiet);
    let rows = compare::compare(&es, &algos, &o, &bar);
    bar.finish();
    let table = compare::markdown(&rows);
    if let (Some(p), Some(f)) = (&a.output, fmt) {
        let text = match f {
            TableFormat::Markdown => table.clone(),
            TableFormat::Json => {
                serde_json::to_string_pretty(&rows).expect("rows serialize") + "\n"
            }
            TableFormat::Csv => compare::csv(&rows),
        };
        std::fs::write(p, text).map_err(|e| CliError::from(Error::io(p, e)).runtime())?;
    }
    // Pairs left out because the algorithm does not handle the entry's dimension.
    let skipped: Vec<String> = if explicit {
        es.iter()
            .flat_map(|e| {
                algos
                    .iter()
                    .filter(|n| {
                        !algorithms::list()
                            .iter()
                            .any(|i| i.name == n.as_str() && i.dim == e.dim)
                    })
                    .map(move |n| format!("{n} on {} ({}D)", e.name, e.dim))
            })
            .collect()
    } else {
        Vec::new()
    };
    if a.json {
        print_json(&rows);
    } else {
        out!("{}", table.trim_end());
        if !skipped.is_empty() {
            out!(
                "not run (the algorithm does not handle the dimension): {}",
                skipped.join(", ")
            );
        }
        if let Some(p) = &a.output {
            out!("wrote {}", p.display());
        }
    }
    Ok(())
}

fn demo_cmd(out: &Path, quick: bool, json: bool, quiet: bool) -> CliResult<()> {
    check_out_dir(out)?;
    let bar = Bar::new(quiet);
    let rep = certmesh::harness::demo::run(out, quick, &bar).runtime()?;
    bar.finish();
    if json {
        print_json(&rep.rows);
    } else {
        out!("{}", rep.table.trim_end());
        let wrong = rep
            .rows
            .iter()
            .filter(|r| r.topology_ok == Some(false))
            .count();
        let cert = rep.rows.iter().filter(|r| r.certified).count();
        out!(
            "\n{} runs: {} with the wrong topology, {} certified. Meshes, compare.md/json and angle histograms in {}",
            rep.rows.len(),
            wrong,
            cert,
            out.display()
        );
    }
    Ok(())
}

fn reproduce_cmd(paper: &str, out: Option<&Path>, quick: bool, quiet: bool) -> CliResult<()> {
    if !certmesh::harness::demo::PAPERS.contains(&paper) {
        return Err(CliError::from(Error::Unknown {
            kind: "paper",
            name: paper.to_string(),
            known: certmesh::harness::demo::PAPERS.join(" "),
        }));
    }
    let default = Path::new("papers").join(paper);
    check_out_dir(out.unwrap_or(&default))?;
    let bar = Bar::new(quiet);
    bar.phase(paper);
    let r = certmesh::harness::demo::reproduce(paper, out, quick).runtime();
    bar.finish();
    r
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
        Cmd::Stats {
            mesh,
            surface,
            formula,
            formula_file,
            histogram,
            bin,
            emphasis,
            json,
        } => stats_cmd(
            StatsArgs {
                mesh,
                surface,
                formula,
                formula_file,
                histogram,
                bin,
                emphasis,
                json,
            },
            quiet,
        )?,
        Cmd::Compare {
            surfaces,
            curves,
            algos,
            opts,
            output,
            json,
        } => compare_cmd(
            CompareArgs {
                surfaces,
                curves,
                algos,
                opts,
                output,
                json,
            },
            quiet,
        )?,
        Cmd::Demo { out, quick, json } => demo_cmd(&out, quick, json, quiet)?,
        Cmd::Reproduce { paper, out, quick } => {
            reproduce_cmd(&paper, out.as_deref(), quick, quiet)?
        }
    }
    Ok(())
}
