//! `certmesh stats`: the quality, topology and fidelity of a mesh file.
use crate::args::*;
use crate::errors::*;
use crate::input::*;
use crate::progress::Bar;
use certmesh::catalog::{self};
use certmesh::error::Error;
use certmesh::harness::report;
use certmesh::implicit::Implicit;
use certmesh::mesher::Progress;
use certmesh::{io, metrics};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The histogram base: a trailing .svg or .png is dropped (both files are written).
pub(crate) fn histogram_base(h: &Path) -> PathBuf {
    match h.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("svg") || e.eq_ignore_ascii_case("png") => {
            h.with_extension("")
        }
        _ => h.to_path_buf(),
    }
}

pub(crate) fn stats_cmd(a: StatsArgs, quiet: bool) -> CliResult<()> {
    a.format.apply()?;
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
            angle_histogram(
                h,
                "dihedral angles",
                "dihedral angles per bin",
                d,
                false,
                &a,
            )?;
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
        angle_histogram(h, "triangle angles", "density (1/degree)", ang, true, &a)?;
    }
    bar.finish();
    let report = report::StatsReport::new(s, verdict);
    if a.json {
        print_json(&report);
    } else {
        for line in report.text(&a.mesh.display().to_string()) {
            out!("{line}");
        }
        if let Some(h) = &hist {
            let files: Vec<String> = certmesh::figure::output::written()
                .iter()
                .map(|p| p.display().to_string())
                .collect();
            let _ = h;
            out!("wrote {}", files.join(" and "));
        }
    }
    Ok(())
}

/// The angle histogram of `certmesh stats --histogram` (SVG and PNG).
fn angle_histogram(
    h: &Path,
    title: &str,
    y_label: &str,
    angles: Vec<f64>,
    density: bool,
    a: &StatsArgs,
) -> CliResult<()> {
    certmesh::reproduce::plot::histogram(
        h,
        title,
        "angle (degrees)",
        y_label,
        &certmesh::reproduce::plot::bin(angles, a.bin, density),
        &[],
        a.emphasis,
    )
    .runtime()
}
