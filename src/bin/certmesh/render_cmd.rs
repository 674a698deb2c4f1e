//! `certmesh render`: a picture of a mesh file, or of a mesher's output with its
//! certificate (mesh and render in one step).
use crate::args::OptArgs;
use crate::errors::*;
use crate::figures_cmd::FormatArg;
use crate::input::*;
use crate::progress::Bar;
use certmesh::error::Error;
use certmesh::mesher::registry as algorithms;
use certmesh::mesher::{self, Mesh, Progress as _};
use certmesh::render::{self, ColorBy, Input, Plane, RenderOptions};
use certmesh::{catalog, io};
use std::io::Write as _;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(crate) struct RenderArgs {
    /// The mesh file (surfaces: obj off ply stl; tetrahedral: vtk mesh). Omit it to
    /// mesh --surface with --algo and render the output with its certificate.
    pub mesh: Option<PathBuf>,
    /// A catalog surface to mesh (with --algo; `certmesh surfaces` lists them).
    #[arg(long, requires = "algo")]
    pub surface: Option<String>,
    /// The mesher to run on --surface (`certmesh algos`).
    #[arg(long, requires = "surface")]
    pub algo: Option<String>,
    #[command(flatten)]
    pub opts: OptArgs,
    /// The figure to write; its extension (.png .svg .pdf) is one format, --format
    /// adds others.
    #[arg(short, long, default_value = "render.png")]
    pub output: PathBuf,
    /// Azimuth and elevation of the view in degrees (from +x about z; above xy).
    #[arg(long, default_value = "35,25", allow_hyphen_values = true)]
    pub view: String,
    /// Keep one side of a plane: x=0.1 (or y<0, z>0.2: keep that side; = keeps <=),
    /// or a,b,c,d (keep a·x + b·y + c·z <= d). On a tetrahedral mesh the faces of the
    /// tetrahedra the plane cuts are shown.
    #[arg(long, allow_hyphen_values = true)]
    pub cut: Option<String>,
    /// Colour by `quality` (smallest angle of each triangle, or smallest dihedral
    /// angle of its tetrahedron, with a colour bar), `certificate` (the mesher's typed
    /// claims and uncertified regions; needs --surface and --algo) or `none`.
    #[arg(long, default_value = "quality")]
    pub color: String,
    /// Draw the edges (hidden ones stay hidden).
    #[arg(long)]
    pub wire: bool,
    /// Gouraud (per-vertex) shading instead of flat.
    #[arg(long)]
    pub smooth: bool,
    /// Title above the picture.
    #[arg(long, default_value = "")]
    pub title: String,
    /// More formats besides the one of -o (e.g. svg,png,pdf).
    #[arg(long = "format", value_name = "LIST")]
    pub format: Option<String>,
    #[arg(long)]
    pub json: bool,
}

pub(crate) fn render_cmd(a: RenderArgs, quiet: bool) -> CliResult<()> {
    // Everything is checked before any work.
    let ext = a
        .output
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let mut formats = certmesh::figure::output::Format::parse_list(&ext).map_err(|_| {
        CliError::from(Error::Param(format!(
            "-o: '{}' must end in .png, .svg or .pdf",
            a.output.display()
        )))
    })?;
    if let Some(f) = &a.format {
        for x in (FormatArg { format: f.clone() }).apply()? {
            if !formats.contains(&x) {
                formats.push(x);
            }
        }
    }
    check_writable(&a.output)?;
    let (azimuth, elevation) = render::parse_view(&a.view)?;
    let cut = a.cut.as_deref().map(Plane::parse).transpose()?;
    let color = ColorBy::parse(&a.color)?;
    let o = RenderOptions {
        azimuth,
        elevation,
        cut,
        color,
        wire: a.wire,
        gouraud: a.smooth,
        title: a.title.clone(),
    };
    let base = a.output.with_extension("");
    let bar = Bar::new(quiet);
    let done = match (&a.mesh, &a.surface, &a.algo) {
        (Some(_), Some(_), _) => {
            return Err(CliError::from(Error::Param(
                "give a mesh file or --surface with --algo, not both".into(),
            )))
        }
        (Some(path), None, _) => {
            let fmt = io::Format::from_path(path)?;
            bar.phase("reading");
            let tets = matches!(fmt, io::Format::Vtk | io::Format::Medit)
                .then(|| io::read_tet(path))
                .transpose()?
                .filter(|m| !m.tets.is_empty());
            bar.phase("rendering");
            match tets {
                Some(m) => render::render(&base, Input::Volume(&m), None, &o, &formats),
                None => {
                    let m = io::read_tri(path)?;
                    render::render(&base, Input::Surface(&m), None, &o, &formats)
                }
            }
            .map_err(render_error)?
        }
        (None, Some(name), Some(algo)) => {
            let opts = a.opts.to_options()?;
            let m = algorithms::build(algo, 3, &opts)?;
            let e = catalog::get(name)?;
            if e.dim != 3 {
                return Err(CliError::from(Error::Param(format!(
                    "'{name}' is a curve; render draws surfaces and volumes"
                ))));
            }
            bar.phase(algo);
            let run = mesher::run(m.as_ref(), &e.function(), &e.domain, &bar)?;
            let cert = Some(&run.output.certificate);
            bar.phase("rendering");
            match &run.output.mesh {
                Mesh::Surface(t) => render::render(&base, Input::Surface(t), cert, &o, &formats),
                Mesh::Volume { tets, .. } => {
                    render::render(&base, Input::Volume(tets), cert, &o, &formats)
                }
                Mesh::Curve(_) => Err(Error::Param(format!("'{algo}' made a curve"))),
            }
            .map_err(render_error)?
        }
        _ => {
            return Err(CliError::from(Error::Param(
                "nothing to render: give a mesh file, or --surface NAME --algo NAME".into(),
            )))
        }
    };
    bar.finish();
    if a.json {
        print_json(&done);
    } else {
        let files: Vec<String> = done.files.iter().map(|p| p.display().to_string()).collect();
        out!(
            "wrote {} ({} faces{})",
            files.join(", "),
            done.faces,
            if done.cut_faces > 0 {
                format!(", {} exposed by the cut", done.cut_faces)
            } else {
                String::new()
            }
        );
        for (c, n) in &done.classes {
            out!("  {n} faces: {c}");
        }
    }
    Ok(())
}

/// A render error: a parameter the input cannot satisfy (`--color certificate` on a
/// mesh file, which carries no certificate; a mesh with no faces) is an input error
/// (exit 2), like every other bad parameter; anything else (writing the figure) is a
/// failure during the work (exit 1).
fn render_error(e: Error) -> CliError {
    match e {
        Error::Param(_) => CliError::from(e),
        e => CliError::from(e).runtime(),
    }
}
