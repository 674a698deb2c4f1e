//! The `certmesh` command line. Every subcommand prints a readable report, or JSON with
//! `--json`; errors name the problem and exit with status 2.
use certmesh::catalog::{self, Entry};
use certmesh::error::{Error, Result};
use certmesh::harness::compare;
use certmesh::implicit::{Formula, Implicit};
use certmesh::kernel::geom::Aabb;
use certmesh::mesher::options::{Crossing, MesherOptions};
use certmesh::mesher::registry as algorithms;
use certmesh::mesher::{self, Mesh, Progress};
use certmesh::{io, metrics};
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};

/// certmesh — certified meshing of implicit curves and surfaces.
///
/// A surface is f(x, y, z) = 0 (a curve f(x, y) = 0), given as a catalog name
/// (`certmesh surfaces`) or a formula (`--formula "x^2 + y^2 + z^2 - 1"`). Convention:
/// f < 0 inside. Every mesher returns a certificate: `certified` with what interval
/// arithmetic proved, or `uncertified` with where and why.
///
/// Formula language: numbers, x y z, + - * /, ^ with an integer exponent, unary minus,
/// parentheses, sqrt abs min max, pi; with the `mpfr` feature also sin cos exp ln.
#[derive(Parser)]
#[command(name = "certmesh", version, about, long_about, max_term_width = 100)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// List the catalog of test surfaces and curves with their known topology.
    Surfaces {
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// List the meshing algorithms (`--algo` names).
    Algos {
        #[arg(long)]
        json: bool,
    },
    /// Mesh a surface f(x, y, z) = 0 and write the mesh.
    ///
    /// Examples:
    ///   certmesh mesh torus --algo mc --resolution 64 -o torus.obj
    ///   certmesh mesh --formula "x^4 + y^4 + z^4 - 1" --domain -1.5,-1.5,-1.5,1.5,1.5,1.5 --algo mc -o s.ply --json
    #[command(verbatim_doc_comment)]
    Mesh(MeshArgs),
    /// Mesh a curve f(x, y) = 0 and write it as SVG or CSV.
    ///
    /// Example: certmesh curve cassini-2 --algo ms --resolution 32 -o c.svg
    Curve(MeshArgs),
    /// Statistics of a mesh file: counts, topology, angles; fidelity when a surface is given.
    ///
    /// Triangle meshes (obj off ply stl) and tetrahedral meshes (vtk mesh).
    Stats {
        /// The mesh file.
        mesh: PathBuf,
        /// Compare against this catalog surface (fidelity fields, topology verdict).
        #[arg(long, conflicts_with = "formula")]
        surface: Option<String>,
        /// Compare against this formula.
        #[arg(long)]
        formula: Option<String>,
        /// Write an angle histogram (BASE.svg and BASE.png).
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
        /// Also write the table (markdown) to this file.
        #[arg(short, long)]
        output: Option<PathBuf>,
        #[arg(long)]
        json: bool,
    },
    /// The main job on built-in defaults: mesh catalog entries with every algorithm,
    /// print the comparison, write the meshes and angle histograms to the output folder.
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
    Reproduce {
        /// Which paper: one of the names `certmesh reproduce --help` lists.
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
    /// A formula instead of a catalog name.
    #[arg(long, short = 'f')]
    formula: Option<String>,
    /// Remesh a triangle mesh (obj ply off stl) through its signed distance (exact
    /// distance, winding-number sign), normalised into the unit cube [0, 1]³ (the domain
    /// unless --domain is given), as GradNormal's Sec. 5.1. Never certified.
    #[arg(long, value_name = "FILE", conflicts_with = "formula")]
    mesh_input: Option<PathBuf>,
    /// With --mesh-input: margin left on each side of the unit cube.
    #[arg(long, default_value_t = 0.05, requires = "mesh_input")]
    margin: f64,
    /// With --mesh-input: close the mesh's boundary loops (holes) by fans first.
    #[arg(long, requires = "mesh_input")]
    fill_holes: bool,
    /// The domain box: x0,y0,z0,x1,y1,z1 (curves: x0,y0,x1,y1). Default: the catalog's box.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    domain: Vec<f64>,
    /// The algorithm (see `certmesh algos`).
    #[arg(long)]
    algo: String,
    #[command(flatten)]
    opts: OptArgs,
    /// Output file; the format follows the extension (obj off ply stl | vtk mesh | svg csv).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// For volume meshers: also write the boundary surface here.
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
    /// Box tests a subdivision mesher may make (default 10000000). A run that spends
    /// them stops, reports refinement_complete: false and certifies nothing.
    #[arg(long)]
    max_boxes: Option<u64>,
    /// Wall-clock limit of the subdivision, in seconds (default: none). A run stopped by
    /// it says so and certifies nothing.
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
        for kv in &self.set {
            let (k, v) = kv
                .split_once('=')
                .ok_or_else(|| Error::Param(format!("--set expects KEY=VALUE, got '{kv}'")))?;
            o.extra.insert(k.trim().to_string(), v.trim().to_string());
        }
        Ok(o)
    }
}

/// An indicatif bar on stderr (hidden when stderr is not a terminal).
struct Bar(ProgressBar);
impl Bar {
    fn new(quiet: bool) -> Self {
        let pb = if quiet {
            ProgressBar::hidden()
        } else {
            ProgressBar::new(0)
        };
        Bar(pb)
    }
}
impl Progress for Bar {
    fn start(&self, phase: &str, total: u64) {
        self.0.reset();
        self.0.set_length(total);
        let style = if total > 0 {
            ProgressStyle::with_template("{msg:>12} [{bar:40}] {pos}/{len} ({elapsed})")
                .unwrap()
                .progress_chars("=> ")
        } else {
            ProgressStyle::with_template("{msg:>12} {spinner} {pos} ({elapsed})").unwrap()
        };
        self.0.set_style(style);
        self.0.set_message(phase.to_string());
    }
    fn inc(&self, n: u64) {
        self.0.inc(n);
    }
    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

fn main() {
    let cli = Cli::parse();
    if let Err(e) = run(cli) {
        eprintln!("certmesh: error: {e}");
        std::process::exit(2);
    }
}

fn print_json(v: &impl serde::Serialize) {
    println!(
        "{}",
        serde_json::to_string_pretty(v).expect("reports serialize")
    );
}

/// The function, domain and expected topology a mesh/curve command works on.
struct Target {
    name: String,
    f: Box<dyn Implicit>,
    domain: Aabb,
    entry: Option<Entry>,
}

fn target(a: &MeshArgs, dim: usize) -> Result<Target> {
    if let Some(path) = &a.mesh_input {
        return mesh_input_target(a, path, dim);
    }
    let (name, f, entry): (String, Box<dyn Implicit>, Option<Entry>) = match (&a.name, &a.formula) {
        (Some(_), Some(_)) => {
            return Err(Error::Param(
                "give a catalog name or --formula, not both".into(),
            ))
        }
        (None, None) => {
            return Err(Error::Param(
                "give a catalog name (see `certmesh surfaces`) or --formula".into(),
            ))
        }
        (Some(n), None) => {
            let e = catalog::get(n)?;
            if e.dim != dim {
                return Err(Error::Param(format!(
                    "'{n}' is a {}; use `certmesh {}`",
                    if e.dim == 2 { "curve" } else { "surface" },
                    if e.dim == 2 { "curve" } else { "mesh" }
                )));
            }
            (n.clone(), Box::new(e.function()), Some(e))
        }
        (None, Some(t)) => (
            "formula".to_string(),
            Box::new(Formula::with_dim(t, dim)?),
            None,
        ),
    };
    let domain = match (a.domain.len(), dim) {
        (0, _) => match &entry {
            Some(e) => e.domain,
            None => {
                return Err(Error::Domain(
                    "a formula needs --domain (x0,y0,z0,x1,y1,z1; curves x0,y0,x1,y1)".into(),
                ))
            }
        },
        (6, 3) => Aabb::new(
            [a.domain[0], a.domain[1], a.domain[2]],
            [a.domain[3], a.domain[4], a.domain[5]],
        )?,
        (4, 2) => Aabb::new(
            [a.domain[0], a.domain[1], 0.0],
            [a.domain[2], a.domain[3], 0.0],
        )?,
        (n, _) => {
            return Err(Error::Domain(format!(
                "--domain needs {} numbers, got {n}",
                if dim == 3 { 6 } else { 4 }
            )))
        }
    };
    let s = domain.size();
    if (0..dim).any(|k| s[k] <= 0.0) {
        return Err(Error::Domain(format!(
            "the domain {:?}..{:?} is empty along some axis",
            domain.min, domain.max
        )));
    }
    Ok(Target {
        name,
        f,
        domain,
        entry,
    })
}

/// `--mesh-input FILE`: the signed distance to a mesh, normalised into the unit cube.
fn mesh_input_target(a: &MeshArgs, path: &Path, dim: usize) -> Result<Target> {
    if dim != 3 {
        return Err(Error::Param(
            "--mesh-input gives a surface; use `certmesh mesh`".into(),
        ));
    }
    if a.name.is_some() {
        return Err(Error::Param(
            "give a catalog name or --mesh-input, not both".into(),
        ));
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
    let domain = match a.domain.len() {
        0 => Aabb::new([0.0; 3], [1.0; 3])?,
        6 => Aabb::new(
            [a.domain[0], a.domain[1], a.domain[2]],
            [a.domain[3], a.domain[4], a.domain[5]],
        )?,
        n => return Err(Error::Domain(format!("--domain needs 6 numbers, got {n}"))),
    };
    let name = path
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".into());
    Ok(Target {
        name,
        f: Box::new(f),
        domain,
        entry: None,
    })
}

fn mesh_cmd(a: MeshArgs, dim: usize) -> Result<()> {
    let t = target(&a, dim)?;
    let opts = a.opts.to_options()?;
    let m = algorithms::build(&a.algo, dim, &opts)?;
    let bar = Bar::new(a.json);
    let run = mesher::run(m.as_ref(), t.f.as_ref(), &t.domain, &bar)?;
    bar.finish();
    if let Some(out) = &a.output {
        io::write_mesh(out, &run.output.mesh)?;
    }
    if let (Some(b), Mesh::Volume { boundary, .. }) = (&a.boundary, &run.output.mesh) {
        io::write_tri(b, boundary)?;
    }
    let row = compare::evaluate(
        &t.name,
        t.f.as_ref(),
        &t.domain,
        t.entry.as_ref().and_then(|e| e.topology.as_ref()),
        &run,
    )?;
    if a.json {
        let mut v = serde_json::to_value(&row).expect("row serializes");
        let o = v.as_object_mut().expect("object");
        o.insert(
            "uncertified_boxes".into(),
            serde_json::json!(match &run.output.certificate {
                certmesh::Certificate::Uncertified { regions, .. } => regions.len(),
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
        if let Some(out) = &a.output {
            o.insert(
                "output".into(),
                serde_json::json!(out.display().to_string()),
            );
        }
        print_json(&v);
    } else {
        println!("{}", compare::markdown(std::slice::from_ref(&row)));
        if let certmesh::Certificate::Uncertified { regions, .. } = &run.output.certificate {
            for r in regions.iter().take(10) {
                println!(
                    "uncertified region {:?}..{:?}: {}",
                    r.region.min, r.region.max, r.reason
                );
            }
            if regions.len() > 10 {
                println!(
                    "... and {} more uncertified regions (see --json)",
                    regions.len() - 10
                );
            }
        }
        for c in run.output.certificate.claims() {
            println!("proven: {c}");
        }
        if let Some(out) = &a.output {
            println!("wrote {}", out.display());
        }
    }
    Ok(())
}

fn stats_cmd(
    mesh: &Path,
    surface: Option<String>,
    formula: Option<String>,
    histogram: Option<PathBuf>,
    bin: f64,
    emphasis: f64,
    json: bool,
) -> Result<()> {
    let fmt = io::Format::from_path(mesh)?;
    let entry = surface.as_deref().map(catalog::get).transpose()?;
    let f: Option<Box<dyn Implicit>> = match (&entry, &formula) {
        (Some(e), _) => Some(Box::new(e.function())),
        (None, Some(t)) => Some(Box::new(Formula::surface(t)?)),
        _ => None,
    };
    let fref = f.as_deref();
    if !(bin.is_finite() && bin > 0.0) {
        return Err(Error::Param(format!("--bin must be positive, got {bin}")));
    }
    if !(emphasis.is_finite() && emphasis >= 1.0) {
        return Err(Error::Param(format!(
            "--emphasis must be a factor >= 1, got {emphasis}"
        )));
    }
    let params = {
        let p = metrics::FidelityParams::default();
        match &entry {
            Some(e) => p.domain(e.domain),
            None => p,
        }
    };
    // A VTK file is tetrahedral; a MEDIT file is read as tetrahedra when it has any,
    // as its triangles otherwise.
    let tets = match fmt {
        io::Format::Vtk => Some(io::read_tet(mesh)?),
        io::Format::Medit => Some(io::read_tet(mesh)?).filter(|m| !m.tets.is_empty()),
        _ => None,
    };
    if let Some(m) = tets {
        let s = metrics::tet_stats(&m, fref, &params)?;
        if let Some(h) = &histogram {
            let d: Vec<f64> = (0..m.tets.len())
                .flat_map(|t| metrics::angles::dihedral_angles(&m.corners(t)))
                .collect();
            certmesh::reproduce::plot::histogram(
                h,
                "dihedral angles",
                "degrees",
                "tetrahedra",
                &certmesh::reproduce::plot::bin(d, bin, false),
                &[],
                emphasis,
            )?;
        }
        if json {
            print_json(&s);
        } else {
            println!("{}", serde_json::to_string_pretty(&s).unwrap());
        }
        return Ok(());
    }
    let m = io::read_tri(mesh)?;
    let s = metrics::stats_with(&m, fref, &params)?;
    let verdict = match &entry {
        Some(e) => e
            .topology
            .as_ref()
            .map(|t| metrics::verdict(&metrics::analyze(&m).expect("checked"), t)),
        None => None,
    };
    if let Some(h) = &histogram {
        let a: Vec<f64> = metrics::angles::per_triangle(&m)?
            .into_iter()
            .flatten()
            .flatten()
            .collect();
        certmesh::reproduce::plot::histogram(
            h,
            "triangle angles",
            "degrees",
            "density",
            &certmesh::reproduce::plot::bin(a, bin, true),
            &[],
            emphasis,
        )?;
    }
    if json {
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
        println!(
            "{}: {} vertices ({} used, {} isolated), {} faces, {} edges, χ = {}, {}, closed: {}, manifold: {}, oriented: {}, {}, {}",
            mesh.display(),
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
        if let (Some(a), Some(b)) = (s.min_angle_deg, s.max_angle_deg) {
            println!(
                "angles: [{a:.3}°, {b:.3}°], {} degenerate triangles",
                s.degenerate_triangles
            );
        }
        if s.non_manifold_edges + s.non_manifold_vertices + s.degenerate_faces + s.duplicate_faces
            > 0
        {
            println!(
                "defects: {} non-manifold edges, {} non-manifold vertices, {} degenerate faces, {} duplicate faces",
                s.non_manifold_edges, s.non_manifold_vertices, s.degenerate_faces, s.duplicate_faces
            );
        }
        if let Some(fd) = &s.fidelity {
            println!(
                "fidelity: Hausdorff ≈ {:.3e} (mesh→surface {:.3e}, surface→mesh {:.3e}), max |f|/|∇f| = {:.3e}, normal deviation max {:.2}°",
                fd.hausdorff, fd.hausdorff_mesh_to_surface, fd.hausdorff_surface_to_mesh, fd.max_distance_estimate, fd.normal_dev_max_deg
            );
        }
        if let Some(vd) = verdict {
            println!(
                "topology: {} (expected {}, found {}) {}",
                if vd.ok { "ok" } else { "WRONG" },
                vd.expected,
                vd.found,
                vd.reason
            );
        }
    }
    Ok(())
}

fn default_algos(dim: usize) -> Vec<String> {
    algorithms::list()
        .into_iter()
        .filter(|i| i.dim == dim)
        .map(|i| i.name.to_string())
        .collect()
}

fn entries(names: &[String]) -> Result<Vec<Entry>> {
    names.iter().map(|n| catalog::get(n)).collect()
}

fn run(cli: Cli) -> Result<()> {
    match cli.cmd {
        Cmd::Surfaces { json } => {
            let all = catalog::entries();
            if json {
                print_json(&all);
            } else {
                println!("| name | kind | formula | domain | components | genus | smooth | note |\n|---|---|---|---|---|---|---|---|");
                for e in all {
                    let (c, g) = match e.topology {
                        Some(t) => (t.components.to_string(), format!("{:?}", t.genus)),
                        None => ("singular".into(), "–".into()),
                    };
                    println!(
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
                    println!(
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
        Cmd::Mesh(a) => mesh_cmd(a, 3)?,
        Cmd::Curve(a) => mesh_cmd(a, 2)?,
        Cmd::Stats {
            mesh,
            surface,
            formula,
            histogram,
            bin,
            emphasis,
            json,
        } => stats_cmd(&mesh, surface, formula, histogram, bin, emphasis, json)?,
        Cmd::Compare {
            surfaces,
            curves,
            algos,
            opts,
            output,
            json,
        } => {
            let o = opts.to_options()?;
            let (mut s, c) = (surfaces, curves);
            if s.is_empty() && c.is_empty() {
                s = ["sphere", "torus", "two-spheres", "thin-torus"]
                    .map(String::from)
                    .to_vec();
            }
            let mut es = entries(&s)?;
            es.extend(entries(&c)?);
            let algos = if algos.is_empty() {
                let mut a = default_algos(3);
                for x in default_algos(2) {
                    if !a.contains(&x) {
                        a.push(x);
                    }
                }
                a
            } else {
                for a in &algos {
                    if !algorithms::list().iter().any(|i| &i.name == a) {
                        return Err(algorithms::build(a, 3, &o)
                            .err()
                            .expect("unknown algorithm"));
                    }
                }
                algos
            };
            let bar = Bar::new(json);
            let rows = compare::compare(&es, &algos, &o, &bar);
            let table = compare::markdown(&rows);
            if let Some(p) = output {
                std::fs::write(&p, &table).map_err(|e| Error::io(&p, e))?;
            }
            if json {
                print_json(&rows);
            } else {
                print!("{table}");
            }
        }
        Cmd::Demo { out, quick, json } => {
            certmesh::harness::demo::run(&out, quick, json, &Bar::new(json))?
        }
        Cmd::Reproduce { paper, out, quick } => {
            certmesh::harness::demo::reproduce(&paper, out.as_deref(), quick)?
        }
    }
    Ok(())
}
