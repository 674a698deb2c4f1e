//! `certmesh demo` (the main job on built-in defaults) and `certmesh reproduce PAPER`.
use crate::catalog::{self, Entry};
use crate::error::{Error, Result};
use crate::figure::output::Format;
use crate::harness::compare;
use crate::mesher::options::MesherOptions;
use crate::mesher::registry as algorithms;
use crate::mesher::{Mesh, Progress, Run};
use crate::render;
use crate::reproduce::plot;
use crate::{io, metrics};
use std::path::Path;

/// The demo's surfaces and curves.
fn demo_entries(quick: bool) -> Vec<Entry> {
    let names: &[&str] = if quick {
        &[
            "sphere",
            "torus",
            "two-spheres",
            "thin-torus",
            "circle",
            "protrusion",
            "near-touching",
        ]
    } else {
        &[
            "sphere",
            "torus",
            "genus2",
            "tanglecube",
            "two-spheres",
            "thin-torus",
            "paraboloid-cap",
            "double-cone",
            "blob",
            "circle",
            "cassini-2",
            "protrusion",
            "near-touching",
            "lemniscate",
        ]
    };
    names
        .iter()
        .map(|n| catalog::get(n).expect("demo entries are in the catalog"))
        .collect()
}

/// What a demo run produced (the caller prints it; the library does not print).
#[derive(Clone, Debug)]
pub struct DemoReport {
    /// One row per (entry, algorithm) run.
    pub rows: Vec<compare::Row>,
    /// The rows as a markdown table (also written to `out/compare.md`).
    pub table: String,
}

/// Mesh the demo entries with every registered algorithm and write meshes, the
/// comparison table (markdown and JSON), angle histograms, one rendering per surface
/// and method (`renders/`, coloured by the run's certificate) and `index.html`, the
/// table beside the pictures, into `out`.
pub fn run(out: &Path, quick: bool, progress: &dyn Progress) -> Result<DemoReport> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let mesh_dir = out.join("meshes");
    std::fs::create_dir_all(&mesh_dir).map_err(|e| Error::io(&mesh_dir, e))?;
    let entries = demo_entries(quick);
    let mut algos: Vec<String> = Vec::new();
    for i in algorithms::list() {
        if !algos.iter().any(|a| a == i.name) {
            algos.push(i.name.to_string());
        }
    }
    let opts = MesherOptions {
        resolution: Some(if quick { 32 } else { 64 }),
        ..Default::default()
    };
    // Angles of every surface run, per algorithm, for the histograms.
    let mut angles: std::collections::BTreeMap<String, Vec<f64>> = Default::default();
    let render_dir = out.join("renders");
    std::fs::create_dir_all(&render_dir).map_err(|e| Error::io(&render_dir, e))?;
    let mut renders: std::collections::BTreeMap<(String, String), String> = Default::default();
    let mut write = |e: &Entry, r: &Run| -> Result<()> {
        let base = mesh_dir.join(format!("{}-{}", e.name, r.algo));
        let name = format!("{}-{}", e.name, r.algo);
        let input = match &r.output.mesh {
            Mesh::Surface(m) => Some(render::Input::Surface(m)),
            Mesh::Volume { tets, .. } => Some(render::Input::Volume(tets)),
            Mesh::Curve(_) => None,
        };
        if let Some(input) = input {
            let o = render::RenderOptions {
                color: render::ColorBy::Certificate,
                title: format!("{}, {}", e.name, r.algo),
                ..Default::default()
            };
            // A run that drew nothing (an empty mesh) has no picture.
            if render::render(
                &render_dir.join(&name),
                input,
                Some(&r.output.certificate),
                &o,
                &[Format::Png],
            )
            .is_ok()
            {
                renders.insert(
                    (e.name.to_string(), r.algo.clone()),
                    format!("renders/{name}.png"),
                );
            }
        } else if let Mesh::Curve(c) = &r.output.mesh {
            // The mesh file meshes/NAME.svg holds the curve's coordinates only; the
            // page shows its figure (axes in the curve's coordinates, the style's fonts).
            if !c.vertices.is_empty()
                && crate::reproduce::plot_subdivision::draw_curve_figure(
                    &render_dir.join(&name),
                    &format!("{}, {}", e.name, r.algo),
                    c,
                    &[Format::Svg, Format::Png],
                )
                .is_ok()
            {
                renders.insert(
                    (e.name.to_string(), r.algo.clone()),
                    format!("renders/{name}.png"),
                );
            }
        }
        match &r.output.mesh {
            Mesh::Surface(m) => {
                io::write_tri(base.with_extension("obj"), m)?;
                angles.entry(r.algo.clone()).or_default().extend(
                    metrics::angles::per_triangle(m)?
                        .into_iter()
                        .flatten()
                        .flatten(),
                );
            }
            Mesh::Volume { tets, boundary } => {
                io::write_tet(base.with_extension("vtk"), tets)?;
                io::write_tri(base.with_extension("obj"), boundary)?;
                angles.entry(r.algo.clone()).or_default().extend(
                    metrics::angles::per_triangle(boundary)?
                        .into_iter()
                        .flatten()
                        .flatten(),
                );
            }
            Mesh::Curve(c) => io::write_curve(base.with_extension("svg"), c)?,
        }
        Ok(())
    };
    let rows = compare::compare_with(&entries, &algos, &opts, progress, &mut write);
    let table = compare::markdown(&rows);
    let page = out.join("index.html");
    std::fs::write(
        &page,
        crate::harness::demo_page::html(&rows, &renders, quick),
    )
    .map_err(|e| Error::io(&page, e))?;
    let md = out.join("compare.md");
    std::fs::write(&md, &table).map_err(|e| Error::io(&md, e))?;
    let js = out.join("compare.json");
    std::fs::write(
        &js,
        serde_json::to_string_pretty(&rows).expect("rows serialize"),
    )
    .map_err(|e| Error::io(&js, e))?;
    for (algo, a) in &angles {
        plot::histogram(
            &out.join(format!("angles-{algo}")),
            &format!("triangle angles, {algo} (all demo surfaces)"),
            "angle (degrees)",
            "density",
            &plot::bin(a.iter().copied(), 2.0, true),
            &[],
            1.0,
        )?;
    }
    Ok(DemoReport { rows, table })
}

/// The papers `certmesh reproduce` knows.
pub const PAPERS: &[&str] = &crate::reproduce::PAPERS;

/// Regenerate a paper's reproduction folder.
pub fn reproduce(paper: &str, out: Option<&Path>, quick: bool) -> Result<()> {
    let default = crate::reproduce::default_out(paper);
    let out = out.unwrap_or(&default);
    crate::reproduce::reproduce(paper, out, quick)
}
