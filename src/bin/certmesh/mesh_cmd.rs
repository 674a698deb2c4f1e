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
    let m = algorithms::build(&a.algo, dim, &opts)?;
    if let Some(out) = &a.output {
        check_mesh_output(out, dim)?;
    }
    if let Some(b) = &a.boundary {
        check_mesh_output(b, 3)?;
    }
    let bar = Bar::new(quiet);
    bar.phase("preparing");
    let t = target(&a, dim)?;
    bar.phase(&a.algo);
    let run = mesher::run(m.as_ref(), t.f.as_ref(), &t.domain, &bar)?;
    bar.phase("writing");
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
    bar.phase("fidelity");
    let mut report = report::mesh_report(
        &t.name,
        t.f.as_ref(),
        &t.domain,
        t.domain_source,
        t.entry.as_ref().and_then(|e| e.topology.as_ref()),
        &run,
    )?;
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
