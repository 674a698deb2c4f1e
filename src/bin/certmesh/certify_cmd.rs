//! `certmesh certify`: the topological-ball-property certificate of anyone's surface
//! mesh (the report is `certmesh::restricted_delaunay::certify::CertifyReport`; this
//! file only parses, prints and serialises).
use crate::errors::*;
use crate::input::*;
use crate::progress::Bar;
use certmesh::catalog;
use certmesh::error::Error;
use certmesh::implicit::Implicit;
use certmesh::io;
use certmesh::kernel::geom::Aabb;
use certmesh::restricted_delaunay::certify::{certify_mesh, CertifyOptions, CertifyReport};
use clap::Args;
use serde::Serialize;
use std::io::Write;
use std::path::PathBuf;

/// The arguments of `certmesh certify`.
#[derive(Args, Clone)]
pub(crate) struct CertifyArgs {
    /// The mesh file (obj off ply stl).
    pub(crate) mesh: PathBuf,
    /// The surface: a catalog name (its domain is the catalog's box).
    #[arg(long, conflicts_with_all = ["formula", "formula_file"])]
    pub(crate) surface: Option<String>,
    /// The surface: a formula f(x, y, z) (`@FILE` reads it from FILE).
    #[arg(long, short = 'f', conflicts_with = "formula_file")]
    pub(crate) formula: Option<String>,
    /// Read the formula from this file.
    #[arg(long, value_name = "FILE")]
    pub(crate) formula_file: Option<PathBuf>,
    /// The domain box x0,y0,z0,x1,y1,z1 (default: the catalog's box, [-2, 2]³ for a
    /// formula). f = 0 must stay inside it (0 ∉ □f on its faces is checked) and so
    /// must every vertex.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub(crate) domain: Vec<f64>,
    /// Write the restricted Delaunay triangulation of the mesh's vertices (oriented
    /// towards f > 0) here: obj off ply stl. It is exact when every Voronoi edge
    /// passes test (1) (the report says so).
    #[arg(short, long)]
    pub(crate) output: Option<PathBuf>,
    /// Boxes per Voronoi facet or cell check (default 3000); a face whose check runs
    /// out is reported as failing.
    #[arg(long, value_name = "N")]
    pub(crate) max_boxes: Option<u32>,
    /// Differing triangles and failing Voronoi faces listed (all are counted).
    #[arg(long, default_value_t = 20, value_name = "N")]
    pub(crate) list: usize,
    /// Stop after this many seconds (default 60): the Voronoi facets and cells not
    /// checked by then are not proven, and the verdict says so. The Delaunay
    /// triangulation and the scan of its dual segments are built whole first (their
    /// time grows with the mesh). A whole check takes about 0.3 ms per vertex on two
    /// cores (14-19 s for 54,000 vertices); a mesh whose check would need more than 16
    /// GiB (6,000 bytes per vertex) is refused before any work.
    #[arg(long, value_name = "SECONDS")]
    pub(crate) time_limit: Option<f64>,
    /// Print the report as JSON.
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Serialize)]
struct Output<'a> {
    mesh: String,
    surface: String,
    domain: Aabb,
    #[serde(flatten)]
    report: &'a CertifyReport,
    output: Option<String>,
}

pub(crate) fn certify_cmd(a: CertifyArgs, quiet: bool) -> CliResult<()> {
    let fmt = io::Format::from_path(&a.mesh)?;
    if !fmt.holds_triangles() {
        return Err(CliError::from(Error::Param(format!(
            "{}: certify reads triangle meshes (obj off ply stl), not .{}",
            a.mesh.display(),
            fmt.extension()
        ))));
    }
    if let Some(out) = &a.output {
        check_mesh_output(out, 3)?;
    }
    let formula = formula_text(a.formula.as_deref(), a.formula_file.as_deref())?;
    let (name, f, mut domain): (String, Box<dyn Implicit>, Aabb) = match (&a.surface, formula) {
        (Some(s), _) => {
            let e = catalog::get(s)?;
            if e.dim != 3 {
                return Err(CliError::from(Error::Param(format!(
                    "'{}' is a curve; certify compares a surface mesh with a surface",
                    e.name
                ))));
            }
            (e.name.to_string(), Box::new(e.function()), e.domain)
        }
        (None, Some((t, file))) => (
            t.clone(),
            Box::new(parse_formula(&t, file.as_deref(), 3)?),
            default_domain(3),
        ),
        (None, None) => {
            return Err(CliError::from(Error::Param(
                "give the surface: --surface NAME or --formula F".into(),
            )))
        }
    };
    if !a.domain.is_empty() {
        domain = domain_from(&a.domain, 3)?;
    }
    let mesh = io::read_tri(&a.mesh)?;
    let limit = a
        .time_limit
        .unwrap_or(certmesh::mesher::options::DEFAULT_TIME_LIMIT);
    certmesh::mesher::options::check_time_limit(limit)?;
    let mut o = CertifyOptions {
        max_listed: a.list,
        time_limit: Some(limit),
        ..Default::default()
    };
    if let Some(n) = a.max_boxes {
        if n == 0 {
            return Err(CliError::from(Error::Param(
                "--max-boxes must be at least 1".into(),
            )));
        }
        o.tbp.cover.max_boxes = n;
    }
    let bar = Bar::new(quiet);
    bar.phase("certify");
    let (report, rdt) = certify_mesh(&mesh, f.as_ref(), &domain, &o)?;
    drop(bar);
    if let Some(out) = &a.output {
        io::write_tri(out, &rdt).runtime()?;
    }
    let o = Output {
        mesh: a.mesh.display().to_string(),
        surface: name,
        domain,
        report: &report,
        output: a.output.as_ref().map(|p| p.display().to_string()),
    };
    if a.json {
        print_json(&o);
        return Ok(());
    }
    let r = &report;
    let t = &r.tbp;
    out!(
        "mesh          {} ({} vertices, {} triangles)",
        o.mesh,
        r.mesh_vertices,
        r.mesh_triangles
    );
    out!(
        "surface       {} in {:?}..{:?}",
        o.surface,
        domain.min,
        domain.max
    );
    out!(
        "sample        {} points ({} unreferenced and {} duplicate vertices left out, {} outside the domain)",
        r.sample_points, r.unreferenced_vertices, r.duplicate_vertices, r.vertices_outside_domain
    );
    match r.max_f_over_grad {
        Some(d) => out!("off S         max |f|/|grad f| over the vertices <= {d:.3e} (interval bound; a first-order distance estimate)"),
        None => out!("off S         max |f|/|grad f| undefined (grad f may vanish at a vertex)"),
    }
    out!(
        "(a) RDT       {} ({} restricted facets; {} mesh triangles not restricted, {} restricted facets missing)",
        if r.is_rdt { "the mesh IS the restricted Delaunay triangulation of its vertices" } else { "the mesh is NOT the restricted Delaunay triangulation of its vertices" },
        r.rdt_facets, r.mesh_triangles_not_in_rdt, r.rdt_facets_not_in_mesh
    );
    for d in &r.differing {
        out!(
            "              {} {:?}",
            if d.in_mesh {
                "in the mesh, not restricted:"
            } else {
                "restricted, not in the mesh:"
            },
            d.vertices
        );
    }
    out!(
        "(b) TBP       {} ({} Voronoi edges, {} facets, {} cells; {} boxes; failures: {} edge, {} manifold, {} facet, {} cell)",
        if t.holds { "holds" } else { "NOT proven" },
        t.voronoi_edges, t.voronoi_facets, t.voronoi_cells, t.boxes,
        t.edge_failures, t.manifold_failures, t.facet_failures, t.cell_failures
    );
    for x in &r.failures {
        out!(
            "              {:?} sites {:?} near ({:.4}, {:.4}, {:.4}): {}",
            x.test,
            x.sites,
            x.point[0],
            x.point[1],
            x.point[2],
            x.reason
        );
    }
    out!("(c) verdict   {}", r.verdict);
    out!("time          {:.3} s", r.seconds);
    if let Some(p) = &o.output {
        out!(
            "wrote         {p} (the restricted Delaunay triangulation of the vertices; {})",
            if t.edge_failures == 0 && t.far_lemma && t.delaunay_valid {
                "exact: every Voronoi edge decided by interval arithmetic"
            } else {
                "NOT proven exact: some Voronoi edges failed test (1)"
            }
        );
    }
    Ok(())
}
