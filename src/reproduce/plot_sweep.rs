//! A figure of the González-Vega–Necula sweep in the style of Fig. 1.16 of the chapter
//! "Meshing of Surfaces" (§1.4.1): the event fibres (solid) through the critical
//! points, the rational fibres between them (dotted), the output arcs, event points
//! as full circles (labelled singular, isolated or x-extreme), fibre points as open
//! circles. With a shear s the fibres are the lines x − s·y = const of the frame the
//! sweep used.
use crate::algebraic::sweep::{Label, SweepResult};
use crate::kernel::geom::Aabb;
use num_rational::BigRational;
use std::fmt::Write;

fn qf(s: &str) -> f64 {
    s.parse::<BigRational>()
        .map(|q| crate::algebraic::algnum::q_to_f64(&q))
        .unwrap_or(f64::NAN)
}

/// The legend of the sweep figures: (text, SVG of the swatch at the origin).
const LEGEND: [(&str, &str); 7] = [
    (
        "critical event fibre",
        r##"<line x1="0" y1="0" x2="40" y2="0" stroke="#d55e00" stroke-width="3"/>"##,
    ),
    (
        "other event fibre",
        r##"<line x1="0" y1="0" x2="40" y2="0" stroke="#0072b2" stroke-width="3"/>"##,
    ),
    (
        "rational fibre",
        r##"<line x1="0" y1="0" x2="40" y2="0" stroke="#888" stroke-width="3" stroke-dasharray="8 6"/>"##,
    ),
    (
        "output arc",
        r##"<line x1="0" y1="0" x2="40" y2="0" stroke="black" stroke-width="4"/>"##,
    ),
    (
        "singular point",
        r##"<circle cx="20" cy="0" r="12" fill="#d55e00" stroke="black" stroke-width="2"/>"##,
    ),
    (
        "isolated point",
        r##"<circle cx="20" cy="0" r="12" fill="#cc79a7" stroke="black" stroke-width="2"/>"##,
    ),
    (
        "x-extreme / fibre point",
        r##"<circle cx="10" cy="0" r="10" fill="black"/><circle cx="34" cy="0" r="8" fill="white" stroke="black" stroke-width="2"/>"##,
    ),
];

/// Write the sweep `r` over `domain` as `base.<ext>` in the figure formats (one column).
pub fn write_sweep(
    base: &std::path::Path,
    r: &SweepResult,
    domain: &Aabb,
    title: &str,
) -> crate::error::Result<()> {
    use crate::figure::output::{self, Meta};
    let meta = Meta {
        axes: None,
        legend: LEGEND.iter().map(|l| l.0.to_string()).collect(),
        series: LEGEND.len(),
    };
    let svg = draw_sweep_svg(r, domain, title);
    output::write_svg(
        base,
        &svg,
        crate::figure::style::Width::Column,
        &meta,
        &output::default_formats(),
    )
    .map(|_| ())
}

/// The SVG text of the sweep `r` over `domain`, in figure units (one column: 950
/// wide, 4 units to the point), legend below.
pub fn draw_sweep_svg(r: &SweepResult, domain: &Aabb, title: &str) -> String {
    let (x0, y0, x1, y1) = (domain.min[0], domain.min[1], domain.max[0], domain.max[1]);
    let w = crate::figure::style::Width::Column.units() as f64;
    let h = w * (y1 - y0) / (x1 - x0);
    let (top, rows) = (60.0, 4.0);
    let legend_h = rows * 46.0 + 16.0;
    let px = |x: f64| (x - x0) / (x1 - x0) * w;
    let py = |y: f64| h - (y - y0) / (y1 - y0) * h;
    let s = r.shear as f64;
    let mut o = String::new();
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{:.0}" viewBox="0 -{top} {w:.0} {:.0}">"#,
        h + top + legend_h,
        h + top + legend_h
    );
    let _ = writeln!(
        o,
        r#"<defs><clipPath id="dom"><rect x="0" y="0" width="{w:.1}" height="{h:.1}"/></clipPath></defs>"#
    );
    let _ = writeln!(
        o,
        r#"<text x="8" y="-18" font-family="sans-serif" font-size="29">{title} (shear s = {})</text>"#,
        r.shear
    );
    let _ = writeln!(
        o,
        r##"<rect x="0" y="0" width="{w:.1}" height="{h:.1}" fill="white" stroke="#888"/>"##
    );
    let _ = writeln!(o, r#"<g clip-path="url(#dom)">"#);
    // The fibre x − s·y = u across the domain.
    let line = |o: &mut String, u: f64, style: &str| {
        let (xa, xb) = (u + s * y0, u + s * y1);
        let _ = writeln!(
            o,
            r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" {style}/>"#,
            px(xa),
            py(y0),
            px(xb),
            py(y1)
        );
    };
    for e in &r.cert.events {
        let u = 0.5 * (qf(&e.lo) + qf(&e.hi));
        let style = if e.critical {
            r##"stroke="#d55e00" stroke-width="3""##
        } else {
            r##"stroke="#0072b2" stroke-width="3""##
        };
        line(&mut o, u, style);
    }
    for f in &r.cert.fibres {
        line(
            &mut o,
            qf(&f.q),
            r##"stroke="#888" stroke-width="3" stroke-dasharray="8 6""##,
        );
    }
    for sg in &r.curve.segments {
        let (a, b) = (
            r.curve.vertices[sg[0] as usize],
            r.curve.vertices[sg[1] as usize],
        );
        let _ = writeln!(
            o,
            r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="black" stroke-width="4"/>"#,
            px(a[0]),
            py(a[1]),
            px(b[0]),
            py(b[1])
        );
    }
    for (v, l) in r.curve.vertices.iter().zip(&r.labels) {
        let (fill, rad) = match l {
            Label::Regular => ("white", 8.0),
            Label::Boundary => ("#0072b2", 9.0),
            Label::XExtreme => ("black", 10.0),
            Label::Singular | Label::Multiple => ("#d55e00", 12.0),
            Label::Isolated => ("#cc79a7", 12.0),
        };
        let _ = writeln!(
            o,
            r#"<circle cx="{:.2}" cy="{:.2}" r="{rad}" fill="{fill}" stroke="black" stroke-width="2"/>"#,
            px(v[0]),
            py(v[1])
        );
    }
    o.push_str("</g>\n");
    for (i, (text, swatch)) in LEGEND.iter().enumerate() {
        let (cx, cy) = (
            24.0 + (i % 2) as f64 * 470.0,
            h + 40.0 + (i / 2) as f64 * 46.0,
        );
        let _ = writeln!(
            o,
            r#"<g transform="translate({cx:.0},{cy:.0})">{swatch}</g><text x="{:.0}" y="{:.0}" font-family="sans-serif" font-size="30">{text}</text>"#,
            cx + 56.0,
            cy + 10.0
        );
    }
    o.push_str("</svg>\n");
    o
}
