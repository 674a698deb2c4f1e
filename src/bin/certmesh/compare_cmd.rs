//! `certmesh compare`, `certmesh demo`, `certmesh reproduce`.
use crate::args::*;
use crate::errors::*;
use crate::input::*;
use crate::progress::Bar;
use certmesh::catalog::{self, Entry};
use certmesh::error::Error;
use certmesh::harness::compare;
use certmesh::mesher::registry as algorithms;
use certmesh::mesher::Progress;
use std::io::Write;
use std::path::Path;

pub(crate) fn default_algos(dim: usize) -> Vec<String> {
    algorithms::list()
        .into_iter()
        .filter(|i| i.dim == dim)
        .map(|i| i.name.to_string())
        .collect()
}

/// Catalog entries of the given dimension; a name of the other kind is an error.
pub(crate) fn entries(names: &[String], dim: usize) -> CliResult<Vec<Entry>> {
    names
        .iter()
        .map(|n| {
            let e = catalog::get(n)?;
            if e.dim != dim {
                let (is, opt) = if e.dim == 2 {
                    ("a curve", "--curves")
                } else {
                    ("a surface", "--surfaces")
                };
                return Err(CliError::from(Error::Param(format!(
                    "'{n}' is {is}: give it with {opt}"
                ))));
            }
            Ok(e)
        })
        .collect()
}

/// What `compare -o FILE` writes, by extension.
#[derive(Clone, Copy)]
pub(crate) enum TableFormat {
    Markdown,
    Json,
    Csv,
}

pub(crate) fn table_format(p: &Path) -> CliResult<TableFormat> {
    let ext = p
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match ext.as_str() {
        "md" | "markdown" => Ok(TableFormat::Markdown),
        "json" => Ok(TableFormat::Json),
        "csv" => Ok(TableFormat::Csv),
        _ => Err(CliError::from(Error::Unknown {
            kind: "table format",
            name: if ext.is_empty() {
                p.display().to_string()
            } else {
                ext
            },
            known: "md json csv".into(),
        })),
    }
}

pub(crate) fn compare_cmd(mut a: CompareArgs, quiet: bool) -> CliResult<()> {
    for n in a.algos.iter_mut() {
        *n = algorithms::canonical(n).to_string();
    }
    let o = a.opts.to_options()?;
    let (mut s, c) = (a.surfaces, a.curves);
    if s.is_empty() && c.is_empty() {
        s = ["sphere", "torus", "two-spheres", "thin-torus"]
            .map(String::from)
            .to_vec();
    }
    let mut es = entries(&s, 3)?;
    es.extend(entries(&c, 2)?);
    let dims: Vec<usize> = es.iter().map(|e| e.dim).collect();
    let explicit = !a.algos.is_empty();
    let algos = if !explicit {
        let mut v = default_algos(3);
        for x in default_algos(2) {
            if !v.contains(&x) {
                v.push(x);
            }
        }
        v
    } else {
        let list = algorithms::list();
        for name in &a.algos {
            let handles: Vec<usize> = list
                .iter()
                .filter(|i| i.name == name.as_str())
                .map(|i| i.dim)
                .collect();
            if handles.is_empty() {
                return Err(CliError::from(
                    algorithms::build(name, 3, &o)
                        .err()
                        .expect("unknown algorithm"),
                ));
            }
            if !handles.iter().any(|d| dims.contains(d)) {
                let what = |d: usize| if d == 2 { "curves" } else { "surfaces" };
                return Err(CliError::from(Error::Param(format!(
                    "'{name}' meshes {} ({}D) only, and no {} were given (use {})",
                    what(handles[0]),
                    handles[0],
                    what(handles[0]),
                    if handles[0] == 2 {
                        "--curves"
                    } else {
                        "--surfaces"
                    }
                ))));
            }
        }
        a.algos
    };
    // Every algorithm option is checked once before the matrix runs: each must be
    // read by one of the meshers run, and each mesher must accept its part.
    let mut runs: Vec<(&str, usize)> = Vec::new();
    for name in &algos {
        for d in [2, 3] {
            if dims.contains(&d)
                && algorithms::list()
                    .iter()
                    .any(|i| i.name == name && i.dim == d)
            {
                runs.push((name.as_str(), d));
            }
        }
    }
    algorithms::check_used(&runs, &o)?;
    for &(name, d) in &runs {
        algorithms::build_shared(name, d, &o)?;
    }
    let fmt = match &a.output {
        Some(p) => {
            let f = table_format(p)?;
            check_writable(p)?;
            Some(f)
        }
        None => None,
    };
    let bar = Bar::new(quiet);
    let rows = compare::compare(&es, &algos, &o, &bar);
    bar.finish();
    let table = compare::markdown(&rows) + &compare::signatures_markdown(&rows);
    if let (Some(p), Some(f)) = (&a.output, fmt) {
        let text = match f {
            TableFormat::Markdown => table.clone(),
            TableFormat::Json => {
                serde_json::to_string_pretty(&rows).expect("rows serialize") + "\n"
            }
            TableFormat::Csv => compare::csv(&rows),
        };
        std::fs::write(p, text).map_err(|e| CliError::from(Error::io(p, e)).runtime())?;
    }
    // Pairs left out because the algorithm does not handle the entry's dimension.
    let skipped: Vec<String> = if explicit {
        es.iter()
            .flat_map(|e| {
                algos
                    .iter()
                    .filter(|n| {
                        !algorithms::list()
                            .iter()
                            .any(|i| i.name == n.as_str() && i.dim == e.dim)
                    })
                    .map(move |n| format!("{n} on {} ({}D)", e.name, e.dim))
            })
            .collect()
    } else {
        Vec::new()
    };
    if a.json {
        print_json(&rows);
    } else {
        out!("{}", table.trim_end());
        if !skipped.is_empty() {
            out!(
                "not run (the algorithm does not handle the dimension): {}",
                skipped.join(", ")
            );
        }
        if let Some(p) = &a.output {
            out!("wrote {}", p.display());
        }
    }
    Ok(())
}

pub(crate) fn demo_cmd(out: &Path, quick: bool, json: bool, quiet: bool) -> CliResult<()> {
    check_out_dir(out)?;
    let bar = Bar::new(quiet);
    let rep = certmesh::harness::demo::run(out, quick, &bar).runtime()?;
    bar.finish();
    if json {
        print_json(&rep.rows);
    } else {
        out!("{}", rep.table.trim_end());
        let wrong = rep
            .rows
            .iter()
            .filter(|r| r.topology_ok == Some(false))
            .count();
        let cert = rep.rows.iter().filter(|r| r.certified).count();
        out!(
            "\n{} runs: {} with the wrong topology, {} certified. Meshes, renderings, compare.md/json, angle histograms and index.html (the table beside the pictures) in {}",
            rep.rows.len(),
            wrong,
            cert,
            out.display()
        );
    }
    Ok(())
}

pub(crate) fn reproduce_cmd(
    paper: &str,
    out: Option<&Path>,
    quick: bool,
    quiet: bool,
) -> CliResult<()> {
    if !certmesh::harness::demo::PAPERS.contains(&paper) {
        return Err(CliError::from(Error::Unknown {
            kind: "paper",
            name: paper.to_string(),
            known: certmesh::harness::demo::PAPERS.join(" "),
        }));
    }
    let default = certmesh::reproduce::default_out(paper);
    check_out_dir(out.unwrap_or(&default))?;
    let bar = Bar::new(quiet);
    bar.phase(paper);
    let r = certmesh::harness::demo::reproduce(paper, out, quick).runtime();
    bar.finish();
    r
}
