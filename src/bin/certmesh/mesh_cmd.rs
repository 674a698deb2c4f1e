//! `certmesh mesh` and `certmesh curve`: run one mesher, write the mesh, print the report.
use crate::args::*;
use crate::errors::*;
use crate::input::*;
use crate::progress::Bar;
use certmesh::harness::compare;
use certmesh::io;
use certmesh::mesher::registry as algorithms;
use certmesh::mesher::{self, Certificate, Mesh, Progress};
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
    let row = compare::evaluate(
        &t.name,
        t.f.as_ref(),
        &t.domain,
        t.entry.as_ref().and_then(|e| e.topology.as_ref()),
        &run,
    )?;
    bar.finish();
    let stopped = stop_reason(&run);
    if a.json {
        let mut v = serde_json::to_value(&row).expect("row serializes");
        let o = v.as_object_mut().expect("object");
        o.insert(
            "uncertified_boxes".into(),
            serde_json::json!(match &run.output.certificate {
                Certificate::Uncertified { regions, .. } => regions.len(),
                _ => 0,
            }),
        );
        o.insert(
            "reason".into(),
            serde_json::json!(run.output.certificate.reason()),
        );
        o.insert(
            "stats".into(),
            serde_json::Value::Object(run.output.stats.clone()),
        );
        o.insert(
            "evaluation_counts".into(),
            serde_json::to_value(run.evaluations).unwrap(),
        );
        o.insert("domain".into(), serde_json::to_value(t.domain).unwrap());
        o.insert("domain_source".into(), serde_json::json!(t.domain_source));
        if let Some(rc) = run.output.stats.get("refinement_complete") {
            o.insert("refinement_complete".into(), rc.clone());
        }
        o.insert("stopped".into(), serde_json::json!(stopped));
        o.insert("notes".into(), serde_json::json!(notes));
        if let Some(out) = &a.output {
            o.insert(
                "output".into(),
                serde_json::json!(out.display().to_string()),
            );
        }
        print_json(&v);
    } else {
        out!(
            "{}",
            compare::markdown(std::slice::from_ref(&row)).trim_end()
        );
        out!(
            "domain: {}{}",
            fmt_domain(&t.domain, dim),
            match t.domain_source {
                "default" => " (the default domain of a formula; set --domain)",
                "catalog" => " (the catalog's)",
                "unit cube" => " (the unit cube of --mesh-input)",
                _ => "",
            }
        );
        if let Some(why) = &stopped {
            out!(
                "stopped before the refinement was complete: {why} (refinement_complete: false); \
                 the output is partial and nothing is certified"
            );
        }
        if let Some(n) = &row.hausdorff_note {
            out!("Hausdorff (est.): {n}");
        }
        if let Certificate::Uncertified { regions, .. } = &run.output.certificate {
            for r in regions.iter().take(10) {
                out!(
                    "uncertified region {:?}..{:?}: {}",
                    r.region.min,
                    r.region.max,
                    r.reason
                );
            }
            if regions.len() > 10 {
                out!(
                    "... and {} more uncertified regions (see --json)",
                    regions.len() - 10
                );
            }
        }
        for c in run.output.certificate.claims() {
            out!("proven: {c}");
        }
        for n in &notes {
            out!("note: {n}");
        }
        if let Some(out) = &a.output {
            out!("wrote {}", out.display());
        }
    }
    Ok(())
}
