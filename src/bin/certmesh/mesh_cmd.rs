//! `certmesh mesh` and `certmesh curve`: run one mesher, write the mesh, print the report.
use crate::args::*;
use crate::errors::*;
use crate::input::*;
use crate::progress::Bar;
use certmesh::harness::report;
use certmesh::io;
use certmesh::mesher::registry as algorithms;
use certmesh::mesher::{self, Mesh, Progress};
use std::io::Write;

pub(crate) fn mesh_cmd(a: MeshArgs, dim: usize, quiet: bool) -> CliResult<()> {
    // Everything the user gave is checked before any work.
    let opts = a.opts.to_options()?;
    let metrics = report::Metrics::parse(&a.metrics)?;
    let m = algorithms::build(&a.algo, dim, &opts)?;
    if let Some(out) = &a.output {
        check_mesh_output(out, dim)?;
    }
    if let Some(b) = &a.boundary {
        check_mesh_output(b, 3)?;
    }
    if let Some(c) = &a.certificate {
        if algorithms::canonical(&a.algo) != "sweep" {
            return Err(CliError::from(certmesh::error::Error::Param(format!(
                "--certificate: '{}' writes no re-checkable certificate (only gvn/sweep does)",
                a.algo
            ))));
        }
        check_writable(c)?;
    }
    let bar = Bar::new(quiet);
    bar.phase("preparing");
    let t = target(&a, dim)?;
    bar.phase(&a.algo);
    let mut run = mesher::run(m.as_ref(), t.f.as_ref(), &t.domain, &bar)?;
    // The sweep's re-checkable certificate travels in its stats; it is written to its
    // own file, not printed with the report.
    let recheck = run
        .output
        .stats
        .remove(certmesh::algebraic::sweep::CERT_STATS_KEY);
    if let (Some(path), Some(cert)) = (&a.certificate, &recheck) {
        let text = serde_json::to_string(cert).expect("certificate serializes") + "\n";
        std::fs::write(path, text)
            .map_err(|e| CliError::from(certmesh::error::Error::io(path, e)).runtime())?;
    }
    if let Some(e) = empty_result(&run, &t.domain, dim, t.domain_source) {
        bar.finish();
        return Err(e);
    }
    bar.phase("writing and measuring");
    // The mesh is written while the report is computed (side by side on rayon's
    // threads; one after the other on one thread).
    let write = || -> CliResult<Vec<String>> {
        if let Some(out) = &a.output {
            io::write_mesh(out, &run.output.mesh).runtime()?;
        }
        let mut notes = Vec::new();
        match (&a.boundary, &run.output.mesh) {
            (Some(b), Mesh::Volume { boundary, .. }) => io::write_tri(b, boundary).runtime()?,
            (Some(_), _) => notes.push(format!(
                "--boundary ignored: '{}' produces no volume mesh",
                a.algo
            )),
            _ => {}
        }
        Ok(notes)
    };
    let measure = || {
        report::mesh_report(
            &t.name,
            t.f.as_ref(),
            &t.domain,
            t.domain_source,
            t.entry.as_ref().and_then(|e| e.topology.as_ref()),
            &run,
            metrics,
        )
    };
    let (notes, report) = rayon::join(write, measure);
    let (notes, mut report) = (notes?, report?);
    bar.finish();
    report.notes = notes;
    report.output = a.output.as_ref().map(|o| o.display().to_string());
    if a.json {
        print_json(&report);
    } else {
        for line in report.text(10) {
            out!("{line}");
        }
    }
    Ok(())
}

/// A run whose output is empty is an error (exit 2, kind `empty-zero-set`): f = 0 does
/// not meet the domain, or the mesher found no point of it. The message says which:
/// proven by the mesher's certificate (every certifying mesher's first claim is
/// topological: its output, here empty, is isotopic or homeomorphic to f = 0 in the
/// domain), or only not seen (a lattice mesher met one sign at
/// every point it read), and no mesh file is written. A run stopped by a budget is not
/// this case: its partial, perhaps empty, output is written and its report says why it
/// stopped.
fn empty_result(
    run: &mesher::Run,
    domain: &certmesh::Aabb,
    dim: usize,
    source: certmesh::harness::report::DomainSource,
) -> Option<CliError> {
    use certmesh::harness::report::DomainSource;
    use certmesh::mesher::Certificate;
    let empty = match &run.output.mesh {
        Mesh::Surface(m) => m.triangles.is_empty(),
        Mesh::Volume { tets, .. } => tets.tets.is_empty(),
        // (An isolated point is a vertex of no segment: not empty.)
        Mesh::Curve(c) => c.segments.is_empty() && c.vertices.is_empty(),
    };
    // A run stopped by a budget is partial and says so in its report (exit 0).
    if !empty || report::stop_reason(run).is_some() {
        return None;
    }
    let dom = report::domain_text(domain, dim);
    let hint = match source {
        DomainSource::Default => {
            "check the formula, or set --domain (this is the default domain of a formula)"
        }
        _ => "check the formula and --domain",
    };
    let what = if dim == 2 { "curve" } else { "surface" };
    let message = match &run.output.certificate {
        Certificate::Certified { claims, .. } => format!(
            "f = 0 does not meet the domain {dom}: proven by '{}', whose empty output is certified ({}), so there is no {what} to mesh; no mesh written; {hint}",
            run.algo,
            claims.first().map_or("", |c| c.as_str())
        ),
        Certificate::Uncertified { .. } => format!(
            "'{}' found no point of f = 0 in the domain {dom}, so it produced no {what}; not proven empty (f had one sign at every point the mesher read, and a component between those points would be missed); no mesh written; {hint}, or mesh with pv or snyder, which prove a domain empty",
            run.algo
        ),
    };
    Some(CliError {
        message,
        kind: "empty-zero-set",
        position: None,
        code: EXIT_INPUT,
    })
}

/// `certmesh check-curve CERT.json`: re-verify a sweep certificate with exact
/// rationals, without re-running the sweep.
pub(crate) fn check_curve_cmd(path: &std::path::Path, json: bool) -> CliResult<()> {
    use certmesh::error::Error;
    let text = std::fs::read_to_string(path).map_err(|e| CliError::from(Error::io(path, e)))?;
    let cert: certmesh::algebraic::CurveCert = serde_json::from_str(&text).map_err(|e| {
        CliError::from(Error::Format {
            format: "certificate",
            line: e.line(),
            message: e.to_string(),
        })
    })?;
    let rep = certmesh::algebraic::check_curve(&cert).map_err(|e| CliError::from(e).runtime())?;
    if json {
        print_json(&rep);
    } else {
        out!(
            "certificate verified for f(x, y) = {} = 0 in the domain {}: shear {}, degree {}, {} events ({} critical), {} rational fibres, {} vertices, {} segments; {} claims re-checked with exact rationals",
            rep.polynomial,
            rep.domain_text(),
            rep.shear,
            rep.degree,
            rep.events,
            rep.critical_events,
            rep.fibres,
            rep.vertices,
            rep.segments,
            rep.claims
        );
    }
    Ok(())
}
