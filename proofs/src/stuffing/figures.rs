//! Figures of the worst configurations of the stuffing proof, in the manner of the
//! paper's Fig 5: the witness tetrahedron, the segments its vertices may move on (green:
//! the warped vertices' asterisk half-segments; magenta: the central parts of cut
//! edges), seen along the dihedral edge (so the dihedral angle appears at true size) or
//! perpendicular to the witness triangle (plane angles at true size). SVG and PNG.
use super::cases::{output_cases, Kind, DEN};
use super::eval::What;
use crate::stuffing::{all_problems, Certificate, BOUNDS};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

type P3 = [f64; 3];

fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: P3) -> P3 {
    let l = dot(a, a).sqrt().max(1e-300);
    a.map(|x| x / l)
}

/// Draw the witness of bound `b` of a certificate into `stem.svg` and `stem.png`.
pub fn witness_figure(cert: &Certificate, b: usize, stem: &Path) -> Result<bool, String> {
    let Some(w) = cert.witnesses.get(b).cloned().flatten() else {
        return Ok(false);
    };
    let res = &cert.bounds[b];
    let Some(deg) = res.deg else {
        return Ok(false);
    };
    let row = super::custom::resolve(&cert.row)?;
    let (cases, _) = output_cases(&cert.alphas);
    let (probs, _) = all_problems(row, &cases);
    let case = &cases[w.case];
    let pr = &probs[w.case][w.problem];
    let pts: [P3; 4] = pr.config(case, &cert.alphas, &w.x);
    // View direction and the highlighted elements.
    let (view, hl): (P3, Vec<[usize; 3]>) = match pr.what {
        What::Dihedral => {
            let v = pr.verts.clone();
            (
                unit(sub(pts[v[1]], pts[v[0]])),
                vec![[v[0], v[1], v[2]], [v[0], v[1], v[3]]],
            )
        }
        What::Face { .. } => {
            let v = pr.verts.clone();
            (
                unit(cross(sub(pts[v[1]], pts[v[0]]), sub(pts[v[2]], pts[v[0]]))),
                vec![[v[0], v[1], v[2]]],
            )
        }
    };
    let t = if view[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = unit(cross(view, t));
    let e2 = cross(view, e1);
    let proj = |p: P3| (dot(p, e1), dot(p, e2));
    // Segments of the moving vertices (units of h).
    let mut segs = Vec::new();
    for s in &case.v {
        let r = cert.alphas.range(s);
        let at = |t: i64| -> P3 {
            [0, 1, 2].map(|k| 0.5 * (s.p[k] as f64 + t as f64 / DEN as f64 * s.d[k] as f64))
        };
        match s.kind {
            Kind::Fixed => {}
            Kind::Cut => segs.push((at(r[0]), at(r[1]), MAGENTA)),
            Kind::Warp => segs.push((at(0), at(r[1]), GREEN)),
        }
    }
    let mut all: Vec<(f64, f64)> = pts.iter().map(|&p| proj(p)).collect();
    let segs: Vec<((f64, f64), (f64, f64), RGBColor)> = segs
        .iter()
        .map(|(a, b2, c)| (proj(*a), proj(*b2), *c))
        .collect();
    for (a, b2, _) in &segs {
        all.push(*a);
        all.push(*b2);
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in &all {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let span = (x1 - x0).max(y1 - y0) * 1.15 + 1e-9;
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let range = (
        cx - 0.5 * span..cx + 0.5 * span,
        cy - 0.5 * span..cy + 0.5 * span,
    );
    let title = format!(
        "{}: {} = {:.4}° (paper {})",
        cert.row,
        BOUNDS[b].0,
        0.5 * (deg[0] + deg[1]),
        res.paper
            .map(|p| format!("{p:.4}°"))
            .unwrap_or_else(|| "n/a".into())
    );
    let fd = Fig {
        title,
        range,
        hl,
        segs,
        pts: pts.map(proj),
        labels: [0, 1, 2, 3].map(|k| match case.v[k].kind {
            Kind::Fixed => format!("F{k}"),
            Kind::Cut => format!("C{k}"),
            Kind::Warp => format!("W{k}"),
        }),
    };
    let svg = stem.with_extension("svg");
    render(SVGBackend::new(&svg, (520, 520)).into_drawing_area(), &fd)?;
    let png = stem.with_extension("png");
    render(
        BitMapBackend::new(&png, (520, 520)).into_drawing_area(),
        &fd,
    )?;
    Ok(true)
}

struct Fig {
    title: String,
    range: (std::ops::Range<f64>, std::ops::Range<f64>),
    hl: Vec<[usize; 3]>,
    segs: Vec<((f64, f64), (f64, f64), RGBColor)>,
    pts: [(f64, f64); 4],
    labels: [String; 4],
}

fn render<DB: DrawingBackend>(area: DrawingArea<DB, Shift>, f: &Fig) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    area.fill(&WHITE).map_err(e)?;
    let mut ch = ChartBuilder::on(&area)
        .caption(&f.title, ("sans-serif", 16))
        .margin(10)
        .build_cartesian_2d(f.range.0.clone(), f.range.1.clone())
        .map_err(e)?;
    for t in &f.hl {
        let poly: Vec<(f64, f64)> = t.iter().map(|&k| f.pts[k]).collect();
        let mut ring = poly.clone();
        ring.push(poly[0]);
        ch.draw_series(std::iter::once(Polygon::new(
            poly,
            RGBColor(255, 230, 80).mix(0.6).filled(),
        )))
        .map_err(e)?;
        // Seen along the dihedral edge a face is a segment: outline it.
        ch.draw_series(std::iter::once(PathElement::new(
            ring,
            RGBColor(240, 170, 0).stroke_width(7),
        )))
        .map_err(e)?;
    }
    for (a, b, c) in &f.segs {
        ch.draw_series(std::iter::once(PathElement::new(
            vec![*a, *b],
            c.stroke_width(4),
        )))
        .map_err(e)?;
    }
    for i in 0..4 {
        for j in i + 1..4 {
            ch.draw_series(std::iter::once(PathElement::new(
                vec![f.pts[i], f.pts[j]],
                BLACK.stroke_width(1),
            )))
            .map_err(e)?;
        }
    }
    for k in 0..4 {
        ch.draw_series(std::iter::once(Circle::new(f.pts[k], 4, BLACK.filled())))
            .map_err(e)?;
        ch.draw_series(std::iter::once(Text::new(
            f.labels[k].clone(),
            f.pts[k],
            ("sans-serif", 14),
        )))
        .map_err(e)?;
    }
    area.present().map_err(e)
}
