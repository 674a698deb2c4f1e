//! The options of `certmesh mesh` and `certmesh curve` (and the mesher options
//! `compare` shares), as clap parses them.
use certmesh::error::{Error, Result};
use certmesh::mesher::options::{Crossing, MesherOptions};
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Clone)]
pub(crate) struct MeshArgs {
    /// A catalog name (see `certmesh surfaces`).
    pub(crate) name: Option<String>,
    /// A formula instead of a catalog name; `@FILE` reads it from FILE (for formulas
    /// longer than the command line allows).
    /// A formula may start with a minus sign (`--formula "-x^2 - y^2 + 1"`).
    #[arg(
        long,
        short = 'f',
        conflicts_with = "formula_file",
        allow_hyphen_values = true
    )]
    pub(crate) formula: Option<String>,
    /// Read the formula from this file (same as `--formula @FILE`).
    #[arg(long, value_name = "FILE")]
    pub(crate) formula_file: Option<PathBuf>,
    /// Remesh a triangle mesh (obj ply off stl) through its signed distance (exact
    /// distance, winding-number sign), normalised into the unit cube [0, 1]³ (the domain
    /// unless --domain is given), as GradNormal's Sec. 5.1. Never certified.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["formula", "formula_file"])]
    pub(crate) mesh_input: Option<PathBuf>,
    /// With --mesh-input: margin left on each side of the unit cube.
    #[arg(long, default_value_t = 0.05, requires = "mesh_input")]
    pub(crate) margin: f64,
    /// With --mesh-input: close the mesh's boundary loops (holes) by fans first.
    #[arg(long, requires = "mesh_input")]
    pub(crate) fill_holes: bool,
    /// The domain box: x0,y0,z0,x1,y1,z1 (curves: x0,y0,x1,y1). Default: the catalog's
    /// box for a catalog name, [-2, 2]³ (curves [-2, 2]²) for a formula, the unit cube
    /// for --mesh-input. The report says which domain was used.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub(crate) domain: Vec<f64>,
    /// The algorithm (see `certmesh algos`).
    #[arg(long)]
    pub(crate) algo: String,
    #[command(flatten)]
    pub(crate) opts: OptArgs,
    /// Output file; the format follows the extension (surfaces: obj off ply stl, volume
    /// meshes also vtk mesh; curves: svg csv). Checked before the work starts.
    #[arg(short, long)]
    pub(crate) output: Option<PathBuf>,
    /// For volume meshers: also write the boundary surface here (obj off ply stl).
    #[arg(long)]
    pub(crate) boundary: Option<PathBuf>,
    /// Write the re-checkable certificate (JSON) here: the exact sweep only
    /// (`--algo gvn`, alias `sweep`); verify it with `certmesh check-curve FILE`.
    #[arg(long, value_name = "FILE")]
    pub(crate) certificate: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    pub(crate) json: bool,
    /// How much of the report to compute: `none` (sizes, time and certificate only),
    /// `fast` (every field of the report, skipping measures it does not print; the
    /// Hausdorff estimate's mesh side from 20,000 area-proportional samples, not every
    /// vertex; on a mesh under 640,000 triangles, a sample sized to it: about one mesh
    /// sample per 32 triangles, at least 513, refined on the triangles of the largest
    /// distances (their corners and all `full`'s samples on them), and surface
    /// points from a seed grid of 12 to 40 per axis, coarser for a smaller mesh:
    /// `hausdorff_kind`, `hausdorff_mesh_samples`, `hausdorff_surface_samples`) or
    /// `full` (every measure, as `certmesh compare`). The mesh file is written while the
    /// report is computed; the report's own time is `metrics_seconds` in JSON, beside
    /// the mesher's `seconds`.
    #[arg(long, default_value = "fast", value_parser = ["none", "fast", "full"])]
    pub(crate) metrics: String,
}

#[derive(Args, Clone, Default)]
pub(crate) struct OptArgs {
    /// Grid cells along the longest side of the domain (lattice meshers).
    #[arg(long)]
    pub(crate) resolution: Option<usize>,
    /// Lattice edge length (GradNormal's e, stuffing's spacing).
    #[arg(long)]
    pub(crate) scale: Option<f64>,
    /// Maximum subdivision depth (subdivision meshers).
    #[arg(long)]
    pub(crate) max_depth: Option<u32>,
    /// Minimum subdivision depth.
    #[arg(long)]
    pub(crate) min_depth: Option<u32>,
    /// Move the grid to generic position first (Snyder's remedy for grazing cases).
    #[arg(long)]
    pub(crate) generic_shift: bool,
    /// Edge crossings: linear or bisection.
    #[arg(long)]
    pub(crate) crossing: Option<String>,
    /// Crossing tolerance, relative to the edge length.
    #[arg(long)]
    pub(crate) tolerance: Option<f64>,
    /// Prune empty space with interval arithmetic (marching meshers).
    #[arg(long)]
    pub(crate) prune: bool,
    /// A named parameter set (e.g. an isosurface-stuffing Table 1 row).
    #[arg(long)]
    pub(crate) params: Option<String>,
    /// Graded variant (isosurface stuffing).
    #[arg(long)]
    pub(crate) graded: bool,
    /// Budget of box tests of the subdivision meshers (pv, snyder; default 1000000,
    /// a few seconds on a formula, minutes on --mesh-input, whose every box test is
    /// a distance query to the mesh: --time-limit stops those first). When it is spent
    /// the run stops: the boxes not yet decided are
    /// returned as uncertified regions with the reason "box budget exhausted (raise
    /// --max-boxes)", the stats say refinement_complete: false, the report says that
    /// the run stopped and why, and nothing is certified.
    #[arg(long, value_name = "N")]
    pub(crate) max_boxes: Option<u64>,
    /// Wall-clock limit of the subdivision and refinement meshers (pv, snyder,
    /// stander-hart, bcsv, bo, cdrr), in seconds (default 60). Their box and vertex budgets
    /// bound the work, but near a pole or a singular point (two touching spheres, the
    /// Whitney umbrella) reaching them can take minutes. A run stopped by the limit
    /// reports "time limit reached (raise --time-limit)", refinement_complete: false,
    /// and certifies nothing. pv and snyder stop their subdivision early enough to
    /// assemble what they found within the limit (an estimate, about 10 µs per box not
    /// proven empty), and stop at any limit once that assembly would need 16 GiB.
    /// cdrr's checks of the topological ball property stop at it too; so do the exact
    /// sweep's root searches (curves: an error naming the limit). bcsv starts no
    /// attempt after it, and its adaptive octree (--set octree=true), manifold checks
    /// and repair rounds and the build of its cut complex stop at it; its Morse census,
    /// one collapse search and its uncertified fallback (marching tetrahedra) run whole.
    #[arg(long, value_name = "SECONDS")]
    pub(crate) time_limit: Option<f64>,
    /// Smallest triangle angle in degrees (bo; CGAL's facet_angle, default 30;
    /// termination is proven up to 30).
    #[arg(long, value_name = "DEGREES")]
    pub(crate) facet_angle: Option<f64>,
    /// Largest surface Delaunay ball radius (bo; CGAL's facet_size; default the
    /// domain diagonal / 20; cdrr: geometry rounds after the topology, default none).
    #[arg(long, value_name = "R")]
    pub(crate) facet_size: Option<f64>,
    /// Largest distance from a facet's circumcentre to its surface point (bo; CGAL's
    /// facet_distance; default the domain diagonal / 200).
    #[arg(long, value_name = "D")]
    pub(crate) facet_distance: Option<f64>,
    /// Refine until the output is a closed 2-manifold (bo; CGAL's Manifold_tag).
    #[arg(long)]
    pub(crate) manifold: bool,
    /// Vertex budget of refinement meshers (bo: default 1000000; cdrr: 200000). A run stopped by
    /// it says refinement_complete: false and why.
    #[arg(long, value_name = "N")]
    pub(crate) max_vertices: Option<usize>,
    /// Run the certification pass (bo: re-derive the restricted triangulation with
    /// interval arithmetic).
    #[arg(long)]
    pub(crate) certify: bool,
    /// Algorithm-specific settings, key=value (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub(crate) set: Vec<String>,
}

impl OptArgs {
    pub(crate) fn to_options(&self) -> Result<MesherOptions> {
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
            facet_angle: self.facet_angle,
            facet_size: self.facet_size,
            facet_distance: self.facet_distance,
            manifold: self.manifold,
            max_vertices: self.max_vertices,
            certify: self.certify,
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
            certmesh::mesher::options::check_time_limit(t)?;
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

/// The arguments of `certmesh stats`.
#[derive(Args, Clone)]
pub(crate) struct StatsArgs {
    /// The mesh file.
    pub(crate) mesh: PathBuf,
    /// Compare against this catalog surface (fidelity fields, topology verdict).
    #[arg(long, conflicts_with_all = ["formula", "formula_file"])]
    pub(crate) surface: Option<String>,
    /// Compare against this formula (`@FILE` reads it from a file).
    #[arg(long, conflicts_with = "formula_file", allow_hyphen_values = true)]
    pub(crate) formula: Option<String>,
    /// Compare against the formula in this file.
    #[arg(long, value_name = "FILE")]
    pub(crate) formula_file: Option<PathBuf>,
    /// Write an angle histogram (BASE.svg and BASE.png, or the formats of --format; a
    /// .svg, .png or .pdf ending of BASE is dropped, so `h.png` writes h.svg and h.png).
    #[arg(long, value_name = "BASE")]
    pub(crate) histogram: Option<PathBuf>,
    /// Histogram bin width in degrees.
    #[arg(long, default_value_t = 2.0)]
    pub(crate) bin: f64,
    /// Draw rare bins magnified by this factor on top of the true bars (the
    /// stuffing paper's Figs 1 and 4 use 20); 1 draws the plain histogram.
    #[arg(long, default_value_t = 1.0, value_name = "K")]
    pub(crate) emphasis: f64,
    #[command(flatten)]
    pub(crate) format: crate::figures_cmd::FormatArg,
    #[arg(long)]
    pub(crate) json: bool,
}

/// The arguments of `certmesh compare`.
#[derive(Args, Clone)]
pub(crate) struct CompareArgs {
    /// Catalog surfaces (comma separated; default: a representative set).
    #[arg(long, value_delimiter = ',')]
    pub(crate) surfaces: Vec<String>,
    /// Catalog curves (comma separated).
    #[arg(long, value_delimiter = ',')]
    pub(crate) curves: Vec<String>,
    /// Algorithms (comma separated; default: all that handle the entry's dimension).
    #[arg(long, value_delimiter = ',')]
    pub(crate) algos: Vec<String>,
    #[command(flatten)]
    pub(crate) opts: OptArgs,
    /// Also write the table to this file: .md (markdown), .json (the rows as
    /// --json prints them) or .csv.
    #[arg(short, long)]
    pub(crate) output: Option<PathBuf>,
    #[arg(long)]
    pub(crate) json: bool,
}
