//! Reading a written SVG figure back and reporting what the style forbids: a printed
//! width that is not one of [`super::style::Width`]'s, text smaller than
//! [`super::style::MIN_FONT_PT`] at that width, axis labels declared but not drawn (or
//! empty), more than one series without a legend, legend entries not drawn.
use super::output::Meta;
use super::style::{Width, MIN_FONT_PT};
use crate::error::{Error, Result};

/// What [`check_svg`] read, and the problems it found (empty: the figure passes).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Report {
    pub width_in: f64,
    /// The smallest font in points at the printed width (infinite: no text).
    pub min_font_pt: f64,
    pub texts: Vec<String>,
    pub meta: Option<Meta>,
    pub problems: Vec<String>,
}

fn length_in(v: &str) -> Option<f64> {
    let v = v.trim();
    for (suf, per_in) in [
        ("in", 1.0),
        ("pt", 72.0),
        ("mm", 25.4),
        ("cm", 2.54),
        ("px", 96.0),
    ] {
        if let Some(n) = v.strip_suffix(suf) {
            return n.trim().parse::<f64>().ok().map(|x| x / per_in);
        }
    }
    v.parse::<f64>().ok().map(|x| x / 96.0)
}

/// Check the text of an SVG figure as written by [`super::output`].
pub fn check_svg(svg: &str) -> Result<Report> {
    let doc = roxmltree::Document::parse(svg)
        .map_err(|e| Error::Param(format!("figure check: not an SVG document: {e}")))?;
    let root = doc.root_element();
    let mut problems = Vec::new();
    let width_in = root
        .attribute("width")
        .and_then(length_in)
        .unwrap_or(f64::NAN);
    let vb_w = root
        .attribute("viewBox")
        .and_then(|v| v.split_whitespace().nth(2)?.parse::<f64>().ok())
        .unwrap_or(f64::NAN);
    if ![Width::Column, Width::Full]
        .iter()
        .any(|w| (w.inches() - width_in).abs() < 1e-6)
    {
        problems.push(format!(
            "printed width {width_in} in is neither a column (3.3 in) nor the full width (7 in)"
        ));
    }
    let pt_per_unit = width_in * 72.0 / vb_w;
    if !pt_per_unit.is_finite() {
        problems.push("no viewBox: the printed size of the text is unknown".into());
    }
    let meta: Option<Meta> = root
        .descendants()
        .find(|n| n.has_tag_name("metadata") && n.attribute("id") == Some("certmesh-figure"))
        .and_then(|n| n.text())
        .and_then(|t| serde_json::from_str(t).ok());
    if meta.is_none() {
        problems.push("no certmesh-figure metadata (not written by the figure style)".into());
    }
    let vb: Vec<f64> = root
        .attribute("viewBox")
        .map(|v| {
            v.split_whitespace()
                .filter_map(|x| x.parse().ok())
                .collect()
        })
        .unwrap_or_default();
    let mut texts = Vec::new();
    let mut min_font_pt = f64::INFINITY;
    for n in root.descendants().filter(|n| n.has_tag_name("text")) {
        let s: String = n
            .descendants()
            .filter(|d| d.is_text())
            .filter_map(|d| d.text())
            .collect::<String>()
            .trim()
            .to_string();
        let size = n
            .ancestors()
            .find_map(|a| a.attribute("font-size"))
            .and_then(|v| v.trim_end_matches("px").trim().parse::<f64>().ok());
        match size {
            Some(u) => {
                let p = u * pt_per_unit;
                min_font_pt = min_font_pt.min(p);
                if p < MIN_FONT_PT - 1e-9 && !s.trim().is_empty() {
                    problems.push(format!("text `{s}` is {p:.2} pt at the printed width"));
                }
            }
            None => problems.push(format!("text `{s}` has no font size")),
        }
        if let (Some(u), [vx, vy, vw, vh]) = (size, vb.as_slice()) {
            let num = |k: &str| n.attribute(k).and_then(|v| v.parse::<f64>().ok());
            let (Some(x), Some(y)) = (num("x"), num("y")) else {
                texts.push(s);
                continue;
            };
            // Positions inside a translated group are not checked.
            let in_group = n
                .ancestors()
                .any(|a| a.attribute("transform").is_some() && a != n);
            let w = 0.5 * u * s.chars().count() as f64;
            let (a, b) = match n.attribute("text-anchor") {
                Some("middle") => (-0.5 * w, 0.5 * w),
                Some("end") => (-w, 0.0),
                _ => (0.0, w),
            };
            let rotated = n
                .attribute("transform")
                .is_some_and(|t| t.contains("rotate"));
            let (lo, hi, min, max) = if rotated {
                (y - b, y - a, *vy, vy + vh)
            } else {
                (x + a, x + b, *vx, vx + vw)
            };
            if !in_group && (lo < min - 1.0 || hi > max + 1.0) {
                problems.push(format!("text `{s}` runs off the figure"));
            }
        }
        texts.push(s);
    }
    let drawn = |label: &str| texts.iter().any(|t| t.trim() == label.trim());
    if let Some(m) = &meta {
        if let Some(axes) = &m.axes {
            for (which, label) in ["x", "y"].iter().zip(axes) {
                if label.trim().is_empty() {
                    problems.push(format!("the {which} axis has no label"));
                } else if !drawn(label) {
                    problems.push(format!("the {which} axis label `{label}` is not drawn"));
                }
            }
        }
        if m.series > 1 && m.legend.is_empty() {
            problems.push(format!("{} series and no legend", m.series));
        }
        for l in &m.legend {
            if !drawn(l) {
                problems.push(format!("legend entry `{l}` is not drawn"));
            }
        }
    }
    Ok(Report {
        width_in,
        min_font_pt,
        texts,
        meta,
        problems,
    })
}

/// Check every `.svg` under `dir` (recursively); (file, problem) for each problem.
pub fn check_dir(dir: &std::path::Path) -> Result<Vec<(std::path::PathBuf, String)>> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).map_err(|e| Error::io(&d, e))? {
            let p = e.map_err(|e| Error::io(&d, e))?.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "svg") {
                let s = std::fs::read_to_string(&p).map_err(|e| Error::io(&p, e))?;
                for pr in check_svg(&s)?.problems {
                    out.push((p.clone(), pr));
                }
            }
        }
    }
    out.sort();
    Ok(out)
}
