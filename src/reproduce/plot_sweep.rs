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

/// The SVG text of the sweep `r` over `domain` (width 640 px).
pub fn draw_sweep_svg(r: &SweepResult, domain: &Aabb, title: &str) -> String {
    let (x0, y0, x1, y1) = (domain.min[0], domain.min[1], domain.max[0], domain.max[1]);
    let w = 640.0;
    let h = w * (y1 - y0) / (x1 - x0);
    let px = |x: f64| (x - x0) / (x1 - x0) * w;
    let py = |y: f64| h - (y - y0) / (y1 - y0) * h;
    let s = r.shear as f64;
    let mut o = String::new();
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{:.0}" viewBox="0 -24 {w:.0} {:.0}">"#,
        h + 24.0,
        h + 24.0
    );
    let _ = writeln!(
        o,
        r#"<defs><clipPath id="dom"><rect x="0" y="0" width="{w:.1}" height="{h:.1}"/></clipPath></defs>"#
    );
    let _ = writeln!(
        o,
        r#"<text x="4" y="-8" font-family="sans-serif" font-size="13">{title} (shear s = {})</text>"#,
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
            r##"stroke="#c33" stroke-width="1""##
        } else {
            r##"stroke="#39c" stroke-width="1""##
        };
        line(&mut o, u, style);
    }
    for f in &r.cert.fibres {
        line(
            &mut o,
            qf(&f.q),
            r##"stroke="#999" stroke-width="0.8" stroke-dasharray="3 3""##,
        );
    }
    for sg in &r.curve.segments {
        let (a, b) = (
            r.curve.vertices[sg[0] as usize],
            r.curve.vertices[sg[1] as usize],
        );
        let _ = writeln!(
            o,
            r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="black" stroke-width="1.6"/>"#,
            px(a[0]),
            py(a[1]),
            px(b[0]),
            py(b[1])
        );
    }
    for (v, l) in r.curve.vertices.iter().zip(&r.labels) {
        let (fill, rad) = match l {
            Label::Regular => ("white", 2.5),
            Label::Boundary => ("#39c", 3.0),
            Label::XExtreme => ("black", 3.5),
            Label::Singular | Label::Multiple => ("#c33", 4.5),
            Label::Isolated => ("#c3c", 4.5),
        };
        let _ = writeln!(
            o,
            r#"<circle cx="{:.2}" cy="{:.2}" r="{rad}" fill="{fill}" stroke="black" stroke-width="0.8"/>"#,
            px(v[0]),
            py(v[1])
        );
    }
    o.push_str("</g>\n</svg>\n");
    o
}
