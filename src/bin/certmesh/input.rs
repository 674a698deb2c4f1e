//! Checks made before the work starts: output paths, formulas, domains, the target
//! surface of a run.
use crate::args::*;
use crate::errors::*;
use certmesh::error::Error;
use certmesh::harness::report::DomainSource;
pub(crate) use certmesh::harness::target::Target;
use certmesh::harness::target::{self, Source};
pub(crate) use certmesh::harness::target::{default_domain, domain_from};
use certmesh::implicit::Formula;
use certmesh::io;
use certmesh::kernel::geom::Aabb;
use std::path::{Path, PathBuf};

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
    // What is at the path now, if anything (one look serves the three questions).
    let meta = std::fs::metadata(path).ok();
    if meta.as_ref().is_some_and(|m| m.is_dir()) {
        return Err(CliError::from(Error::io(
            path,
            std::io::Error::other("is a directory, not a file"),
        )));
    }
    // An existing FIFO or device is not opened here: opening a FIFO for writing
    // waits for a reader, and closing it again would end the reader's input before
    // the mesh is written. Its open when the mesh is written reports any error.
    if meta.as_ref().is_some_and(|m| !m.is_file()) {
        return Ok(());
    }
    let existed = meta.is_some();
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

/// The function, domain and expected topology a mesh/curve command works on
/// ([`certmesh::harness::target::resolve`]).
pub(crate) fn target(a: &MeshArgs, dim: usize) -> CliResult<Target> {
    if let Some(path) = &a.mesh_input {
        return mesh_input_target(a, path, dim);
    }
    let formula = formula_text(a.formula.as_deref(), a.formula_file.as_deref())?;
    let source = match (&a.name, formula) {
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
        (Some(n), None) => Source::Catalog(n),
        (None, Some((t, file))) => Source::Function {
            name: "formula".to_string(),
            f: Box::new(parse_formula(&t, file.as_deref(), dim)?),
        },
    };
    Ok(target::resolve(source, &a.domain, dim)?)
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
