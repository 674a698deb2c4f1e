//! `certmesh stats`: the quality, topology and fidelity of a mesh file.
use crate::errors::*;
use crate::input::*;
use crate::progress::Bar;
use certmesh::catalog::{self};
use certmesh::error::Error;
use certmesh::implicit::Implicit;
use certmesh::mesher::Progress;
use certmesh::{io, metrics};
use std::io::Write;
use std::path::{Path, PathBuf};

pub(crate) struct StatsArgs {
    pub(crate) mesh: PathBuf,
    pub(crate) surface: Option<String>,
    pub(crate) formula: Option<String>,
    pub(crate) formula_file: Option<PathBuf>,
    pub(crate) histogram: Option<PathBuf>,
    pub(crate) bin: f64,
    pub(crate) emphasis: f64,
    pub(crate) json: bool,
}

/// The histogram base: a trailing .svg or .png is dropped (both files are written).
pub(crate) fn histogram_base(h: &Path) -> PathBuf {
    match h.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("svg") || e.eq_ignore_ascii_case("png") => {
            h.with_extension("")
        }
        _ => h.to_path_buf(),
    }
}

/// A measured number for text: "undefined" (NaN) and "inf" are said as such.
pub(crate) fn num(x: f64, prec: usize) -> String {
    if x.is_nan() {
        "undefined".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{x:.prec$e}")
    }
}

pub(crate) fn stats_cmd(a: StatsArgs, quiet: bool) -> CliResult<()> {
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
