//! Checks made before the work starts: output paths, formulas, domains, the target
//! surface of a run.
use crate::args::*;
use crate::errors::*;
use certmesh::catalog::{self, Entry};
use certmesh::error::{Error, Result};
use certmesh::harness::report::DomainSource;
use certmesh::implicit::{Formula, Implicit};
use certmesh::io;
use certmesh::kernel::geom::Aabb;
use std::path::{Path, PathBuf};

/// Half-width of the default domain of a formula: [-2, 2]³ for surfaces, [-2, 2]² for
/// curves (the catalog's unit-scale shapes fit in it).
pub(crate) const DEFAULT_HALF_WIDTH: f64 = 2.0;

/// Fail now, not after the work, if `path` cannot be written: its directory must
/// exist and the file must be creatable (an existing file is not truncated here).
pub(crate) fn check_writable(path: &Path) -> CliResult<()> {
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
pub(crate) fn check_mesh_output(path: &Path, dim: usize) -> CliResult<()> {
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
pub(crate) fn check_out_dir(dir: &Path) -> CliResult<()> {
    std::fs::create_dir_all(dir).map_err(|e| CliError::from(Error::io(dir, e)))?;
    let probe = dir.join(format!(".certmesh-write-test-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| CliError::from(Error::io(dir, e)))?;
    let _ = std::fs::remove_file(probe);
    Ok(())
}

/// The formula text: `--formula TEXT`, `--formula @FILE` or `--formula-file FILE`.
/// Returns the text and the file it came from.
pub(crate) fn formula_text(
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
pub(crate) fn parse_formula(text: &str, file: Option<&Path>, dim: usize) -> CliResult<Formula> {
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
pub(crate) struct Target {
    pub(crate) name: String,
    pub(crate) f: Box<dyn Implicit>,
    pub(crate) domain: Aabb,
    /// Where the domain came from: "catalog", "--domain", "default", "unit cube".
    pub(crate) domain_source: DomainSource,
    pub(crate) entry: Option<Entry>,
}

pub(crate) fn domain_from(v: &[f64], dim: usize) -> Result<Aabb> {
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
pub(crate) fn default_domain(dim: usize) -> Aabb {
    let h = DEFAULT_HALF_WIDTH;
    let z = if dim == 3 { h } else { 0.0 };
    Aabb::new([-h, -h, -z], [h, h, z]).expect("a valid box")
}

pub(crate) fn target(a: &MeshArgs, dim: usize) -> CliResult<Target> {
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
        (_, false) => (domain_from(&a.domain, dim)?, DomainSource::Given),
        (Some(e), true) => (e.domain, DomainSource::Catalog),
        (None, true) => (default_domain(dim), DomainSource::Default),
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
pub(crate) fn mesh_input_target(a: &MeshArgs, path: &Path, dim: usize) -> CliResult<Target> {
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
        (Aabb::new([0.0; 3], [1.0; 3])?, DomainSource::UnitCube)
    } else {
        (domain_from(&a.domain, 3)?, DomainSource::Given)
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
