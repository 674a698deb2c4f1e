//! `certmesh delaunay`: build the 3D Delaunay triangulation of random or given points
//! with the kernel (`certmesh::kernel::delaunay`), run its exact validity check, and
//! print the speed, the cell count and the memory; optionally write the tetrahedra.
use crate::errors::*;
use crate::input::check_writable;
use certmesh::error::Error;
use certmesh::io;
use certmesh::kernel::delaunay::{self, random_points, Delaunay, ReportOptions, Sampler};
use clap::Args;
use serde::Serialize;
use std::io::Write;
use std::path::PathBuf;

/// Largest `--random N` (the kernel's vertex ids are 32-bit with room for flags).
const MAX_RANDOM: usize = 1 << 28;
/// Largest estimated heap of a triangulation: 16 GiB, about 34 million points.
const MAX_BYTES: u64 = 16 << 30;

/// Refuse `n` points before generating or triangulating them when the kernel's
/// estimate of their heap ([`Delaunay::estimated_bytes`]) exceeds [`MAX_BYTES`].
fn check_memory(n: usize, what: &str) -> CliResult<()> {
    let bytes = Delaunay::estimated_bytes(n);
    if bytes > MAX_BYTES {
        return Err(CliError::from(Error::TooLarge(format!(
            "{what}: {n} points need about {:.1} GB ({} bytes per point; at most {:.1} GB)",
            bytes as f64 / 1e9,
            Delaunay::BYTES_PER_POINT,
            MAX_BYTES as f64 / 1e9
        ))));
    }
    Ok(())
}

/// The arguments of `certmesh delaunay`.
#[derive(Args, Clone)]
pub(crate) struct DelaunayArgs {
    /// A point file: one `x y z` per line (blank lines and `#` comments skipped).
    #[arg(conflicts_with = "random")]
    pub(crate) points: Option<PathBuf>,
    /// Triangulate N random points instead of a file.
    #[arg(long, value_name = "N")]
    pub(crate) random: Option<usize>,
    /// Where the random points lie: uniform (in [-1, 1]^3), sphere (the unit sphere:
    /// every in-sphere test is nearly degenerate) or torus (radii 1 and 0.35).
    #[arg(long, default_value = "uniform", requires = "random")]
    pub(crate) on: String,
    /// Seed of the random points, the insertion order and the walk.
    #[arg(long, default_value_t = 1)]
    pub(crate) seed: u64,
    /// Write the tetrahedra (those without a far-box corner) here: .vtk or .mesh.
    #[arg(short, long)]
    pub(crate) output: Option<PathBuf>,
    /// Skip the exact validity check (for timing very large inputs).
    #[arg(long)]
    pub(crate) no_check: bool,
    /// Print the report as JSON.
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Serialize)]
struct Output {
    input: String,
    seed: u64,
    #[serde(flatten)]
    report: delaunay::DelaunayReport,
    bytes_per_point: f64,
    output: Option<String>,
}

fn sampler(s: &str) -> Result<Sampler, Error> {
    match s {
        "uniform" => Ok(Sampler::Uniform),
        "sphere" => Ok(Sampler::Sphere),
        "torus" => Ok(Sampler::Torus),
        _ => Err(Error::Unknown {
            kind: "point sampler",
            name: s.into(),
            known: "uniform sphere torus".into(),
        }),
    }
}

pub(crate) fn delaunay_cmd(a: DelaunayArgs) -> CliResult<()> {
    if let Some(out) = &a.output {
        let f = io::Format::from_path(out)?;
        if !f.holds_tets() {
            return Err(CliError::from(Error::Param(format!(
                "{}: a .{} file cannot hold tetrahedra; use .vtk or .mesh",
                out.display(),
                f.extension()
            ))));
        }
        check_writable(out)?;
    }
    let (points, input) = match (&a.points, a.random) {
        (Some(p), None) => {
            let pts = io::read_points(p)?;
            check_memory(pts.len(), &p.display().to_string())?;
            (pts, p.display().to_string())
        }
        (None, Some(n)) => {
            if n > MAX_RANDOM {
                return Err(CliError::from(Error::TooLarge(format!(
                    "--random {n}: at most {MAX_RANDOM} points"
                ))));
            }
            check_memory(n, &format!("--random {n}"))?;
            let on = sampler(&a.on)?;
            (
                random_points(n, on, a.seed),
                format!("{n} random points ({})", a.on),
            )
        }
        _ => {
            return Err(CliError::from(Error::Param(
                "give a point file or --random N".into(),
            )))
        }
    };
    let (t, report) = delaunay::build_report(
        &points,
        ReportOptions {
            seed: a.seed,
            check: !a.no_check,
        },
    )?;
    if let Some(out) = &a.output {
        io::write_tet(out, &delaunay::tet_mesh(&t)).runtime()?;
    }
    let valid = report.valid;
    let first_problem = report.check.as_ref().and_then(|c| c.first_problem.clone());
    let o = Output {
        input,
        seed: a.seed,
        bytes_per_point: if report.n_points > 0 {
            report.memory_bytes as f64 / report.n_points as f64
        } else {
            0.0
        },
        report,
        output: a.output.as_ref().map(|p| p.display().to_string()),
    };
    if a.json {
        print_json(&o);
    } else {
        let r = &o.report;
        out!("input         {}", o.input);
        out!(
            "points        {} ({} inserted, {} duplicates not inserted)",
            r.n_points,
            r.n_inserted,
            r.duplicates.len()
        );
        out!(
            "cells         {} ({} without a far-box corner)",
            r.cells,
            r.finite_cells
        );
        out!(
            "time          {:.4} s, {:.3e} points/s",
            r.seconds,
            r.points_per_second
        );
        out!(
            "memory        {:.2} MB ({:.0} bytes/point, estimated heap)",
            r.memory_bytes as f64 / 1e6,
            o.bytes_per_point
        );
        match &r.check {
            None => out!("check         skipped (--no-check)"),
            Some(c) => out!(
                "check         {} ({} cells positively oriented by exact orient3d: {}; facets not locally Delaunay: {}; Euler characteristic {})",
                if c.valid { "valid" } else { "INVALID" },
                c.cells,
                c.cells - c.non_positive_cells,
                c.non_delaunay_facets,
                c.euler_characteristic
            ),
        }
        if let Some(p) = &o.output {
            out!("wrote         {p}");
        }
    }
    if valid == Some(false) {
        if a.json {
            // The report on stdout already says `"valid": false` and why: one JSON
            // document, not the report and then an error object.
            let _ = std::io::stdout().flush();
            std::process::exit(EXIT_RUNTIME);
        }
        return Err(CliError::from(Error::Param(format!(
            "the triangulation failed its validity check: {}",
            first_problem.unwrap_or_default()
        )))
        .runtime());
    }
    Ok(())
}
