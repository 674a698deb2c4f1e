//! The demo's single HTML page (no JavaScript): for each surface, its rows of the
//! comparison table beside one rendering per method, coloured by that run's own
//! certificate ([`crate::render::classify`]).
use crate::harness::compare::{cells, Row, COLUMNS};
use std::collections::BTreeMap;
use std::fmt::Write as _;

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Markdown emphasis of a cell (`**x**`) as `<strong>`.
fn cell(s: &str) -> String {
    match s.strip_prefix("**").and_then(|t| t.strip_suffix("**")) {
        Some(t) => format!("<strong>{}</strong>", esc(t)),
        None => match s.find("**") {
            Some(_) => esc(&s.replace("**", "")),
            None => esc(s),
        },
    }
}

const STYLE: &str = "body{font-family:sans-serif;margin:1.5em;color:#111}\
h1{font-size:1.4em}h2{font-size:1.15em;margin-top:1.6em;border-bottom:1px solid #ccc}\
.entry{display:flex;gap:1.5em;align-items:flex-start;flex-wrap:wrap}\
table{border-collapse:collapse;font-size:0.8em;max-width:46em}\
th,td{border:1px solid #bbb;padding:0.25em 0.45em;text-align:left;vertical-align:top}\
th{background:#eee}.gallery{display:flex;flex-wrap:wrap;gap:0.8em;max-width:60em}\
figure{margin:0;width:15em}figure img{width:100%;border:1px solid #ddd}\
figcaption{font-size:0.8em}";

/// The page: `renders` maps (surface, algo) to a picture path relative to the page.
pub fn html(rows: &[Row], renders: &BTreeMap<(String, String), String>, quick: bool) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>certmesh demo</title><style>{STYLE}</style></head><body>\n<h1>certmesh demo{}</h1>\n<p>Every surface and curve of the demo meshed by every method. Each picture is coloured by that run's certificate: green where the output lies inside the box of an isotopy claim of a certified run, vermillion where a face meets a region the mesher reported uncertified, grey where no claim covers it (nothing is inferred). The full table is in <a href=\"compare.md\">compare.md</a> and <a href=\"compare.json\">compare.json</a>.</p>\n",
        if quick { " (quick)" } else { "" }
    );
    let mut order: Vec<&str> = Vec::new();
    for r in rows {
        if !order.contains(&r.surface.as_str()) {
            order.push(&r.surface);
        }
    }
    for s in order {
        let _ = write!(
            h,
            "<h2 id=\"{0}\">{0}</h2>\n<div class=\"entry\">\n<table>\n<tr>",
            esc(s)
        );
        for c in &COLUMNS[1..] {
            let _ = write!(h, "<th>{}</th>", esc(c));
        }
        h.push_str("</tr>\n");
        let mine: Vec<&Row> = rows.iter().filter(|r| r.surface == s).collect();
        for r in &mine {
            h.push_str("<tr>");
            for c in &cells(r)[1..] {
                let _ = write!(h, "<td>{}</td>", cell(c));
            }
            h.push_str("</tr>\n");
        }
        h.push_str("</table>\n<div class=\"gallery\">\n");
        for r in &mine {
            if let Some(src) = renders.get(&(r.surface.clone(), r.algo.clone())) {
                let _ = write!(
                    h,
                    "<figure><img src=\"{}\" alt=\"{} meshed by {}\"><figcaption>{}: {}</figcaption></figure>\n",
                    esc(src),
                    esc(s),
                    esc(&r.algo),
                    esc(&r.algo),
                    if r.certified { "certified" } else { "uncertified" }
                );
            }
        }
        h.push_str("</div>\n</div>\n");
    }
    h.push_str("</body></html>\n");
    h
}
