//! `proofs report DIR`: the result tables of `papers/stuffing/PROOF.md` (results per
//! bound, run statistics with the safe property, witness configurations, the slowest
//! cases), assembled from the row certificates `DIR/ROW.json` (or, where a certificate is
//! absent, the summaries `DIR/ROW.summary.json` written by `proofs stuffing --json`).
//! Regenerating PROOF.md needs nothing outside the repository.
use super::{row_names, summary_json, Certificate};
use serde_json::Value;
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

/// One row's inputs: its summary, and its per-case leaf counts when the certificate was read.
pub struct RowInput {
    pub name: String,
    pub summary: Value,
    pub leaves_per_case: Option<BTreeMap<usize, usize>>,
}

impl RowInput {
    pub fn from_certificate(c: &Certificate, path: &str) -> RowInput {
        let mut per = BTreeMap::new();
        for p in &c.problems {
            *per.entry(p.case).or_insert(0) += p.leaves.len();
        }
        RowInput {
            name: c.row.clone(),
            summary: summary_json(c, path),
            leaves_per_case: Some(per),
        }
    }
}

/// Read the inputs of every Table 1 row present in `dir`, in Table 1 order, with a loader
/// for certificates (the binary's, which names the file in its errors).
pub fn read_dir(
    dir: &Path,
    load: impl Fn(&Path) -> Result<Certificate, String>,
) -> Result<Vec<RowInput>, String> {
    let mut out = Vec::new();
    for r in row_names() {
        let cert = dir.join(format!("{r}.json"));
        let summ = dir.join(format!("{r}.summary.json"));
        if cert.exists() {
            let c = load(&cert)?;
            if c.row != r {
                return Err(format!(
                    "{}: the certificate of row '{}', not '{r}'",
                    cert.display(),
                    c.row
                ));
            }
            out.push(RowInput::from_certificate(&c, &cert.display().to_string()));
        } else if summ.exists() && std::fs::metadata(&summ).map(|m| m.len()).unwrap_or(0) > 0 {
            let text =
                std::fs::read_to_string(&summ).map_err(|e| format!("{}: {e}", summ.display()))?;
            let v: Value =
                serde_json::from_str(&text).map_err(|e| format!("{}: {e}", summ.display()))?;
            out.push(RowInput {
                name: r.to_string(),
                summary: v,
                leaves_per_case: None,
            });
        }
    }
    if out.is_empty() {
        return Err(format!(
            "{}: no row certificate ROW.json or summary ROW.summary.json (rows: {})",
            dir.display(),
            row_names().join(" ")
        ));
    }
    Ok(out)
}

fn f(v: &Value) -> Result<f64, String> {
    v.as_f64()
        .ok_or_else(|| format!("expected a number, found {v}"))
}
fn u(v: &Value) -> Result<u64, String> {
    v.as_u64()
        .ok_or_else(|| format!("expected a count, found {v}"))
}
fn s(v: &Value) -> String {
    match v {
        Value::String(t) => t.clone(),
        Value::Null => "-".into(),
        o => o.to_string(),
    }
}

/// The markdown of the four tables. Rows of Table 1 missing from `inputs` are listed as
/// "(not run)".
pub fn markdown(inputs: &[RowInput]) -> Result<String, String> {
    let by: BTreeMap<&str, &RowInput> = inputs.iter().map(|r| (r.name.as_str(), r)).collect();
    let mut o = String::new();
    let mut stats = String::new();
    let mut wit = String::new();
    o.push_str(
        "| row | bound | paper | certified extreme (°) | verdict | within 0.0001° of the paper |\n",
    );
    o.push_str("|---|---|---|---|---|---|\n");
    for r in row_names() {
        let Some(inp) = by.get(r) else {
            let _ = writeln!(o, "| {r} | (not run) | | | | |");
            continue;
        };
        let sm = &inp.summary;
        let ctx = |e: String| format!("row {r}: {e}");
        for b in sm["bounds"]
            .as_array()
            .ok_or_else(|| ctx("no bounds".into()))?
        {
            let bound = s(&b["bound"]);
            if b["paper"].is_null() {
                let _ = writeln!(
                    o,
                    "| {r} | {bound} | n/a | not certified (tetrahedra can be flat) | - | - |"
                );
                continue;
            }
            let lo = f(&b["certified_deg"][0]).map_err(ctx)?;
            let hi = f(&b["certified_deg"][1]).map_err(ctx)?;
            let _ = writeln!(
                o,
                "| {r} | {bound} | {:.4} | [{lo:.6}, {hi:.6}] | {} | {} |",
                f(&b["paper"]).map_err(ctx)?,
                s(&b["verdict"]),
                s(&b["tight"])
            );
            let w = &b["witness"];
            if !w.is_null() {
                let verts: Vec<String> = w["vertices_h"]
                    .as_array()
                    .ok_or_else(|| ctx("witness without vertices".into()))?
                    .iter()
                    .map(|v| -> Result<String, String> {
                        Ok(format!(
                            "({:.5}, {:.5}, {:.5})",
                            f(&v[0])?,
                            f(&v[1])?,
                            f(&v[2])?
                        ))
                    })
                    .collect::<Result<_, _>>()
                    .map_err(ctx)?;
                let kinds: Vec<String> = w["case"]
                    .as_array()
                    .map(|c| {
                        c.iter()
                            .map(|k| s(&k["kind"]).chars().take(1).collect())
                            .collect()
                    })
                    .unwrap_or_default();
                let _ = writeln!(
                    wit,
                    "| {r} | {bound} | {} | {} |",
                    kinds.join(" "),
                    verts.join("; ")
                );
            }
        }
        let sf = &sm["safe"];
        let note = s(&sf["note"]);
        let note = if sf["note"].as_str().is_some_and(|n| !n.is_empty()) {
            format!(" ({note})")
        } else {
            String::new()
        };
        let _ = writeln!(
            stats,
            "| {r} | {} -> {} | {} | {} | {} | {} | {:.0} | {} -> {} | {:.5} | {}{note} |",
            u(&sm["cases"]["raw"]).map_err(ctx)?,
            u(&sm["cases"]["distinct"]).map_err(ctx)?,
            u(&sm["unreduced_cases"]).map_err(ctx)?,
            u(&sm["problems"]).map_err(ctx)?,
            u(&sm["leaves"]).map_err(ctx)?,
            u(&sm["unresolved"]).map_err(ctx)?,
            f(&sm["seconds"]).map_err(ctx)?,
            u(&sf["counts"]["raw"]).map_err(ctx)?,
            u(&sf["counts"]["distinct"]).map_err(ctx)?,
            f(&sf["min_ratio"]).map_err(ctx)?,
            s(&sf["verdict"]),
        );
    }
    o.push_str("\n### Run statistics and the safe property\n\n");
    o.push_str("| row | output-tet cases raw -> distinct | unreduced | problems | leaves | unresolved | seconds | safe: BCC cases raw -> distinct | min volume / unwarped | safe verdict |\n");
    o.push_str("|---|---|---|---|---|---|---|---|---|---|\n");
    o.push_str(&stats);
    o.push_str("\n### Witness configurations\n\n");
    o.push_str("Vertex kinds: F fixed lattice point, C cut point, W warped lattice point. Coordinates in units of the black edge length h (lattice points at integer and half-integer coordinates).\n\n");
    o.push_str("| row | bound | kinds | vertices |\n|---|---|---|---|\n");
    o.push_str(&wit);
    o.push_str("\n### Slowest cases (most leaves)\n\n| row | case | leaves |\n|---|---|---|\n");
    for r in row_names() {
        let Some(per) = by.get(r).and_then(|i| i.leaves_per_case.as_ref()) else {
            continue;
        };
        let mut v: Vec<(usize, usize)> = per.iter().map(|(&c, &n)| (c, n)).collect();
        // Most leaves first; among equals the smaller case.
        v.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        for (case, n) in v.into_iter().take(2) {
            let _ = writeln!(o, "| {r} | {case} | {n} |");
        }
    }
    Ok(o)
}
