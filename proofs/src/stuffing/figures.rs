//! Figures of the worst configurations of the stuffing proof, in the manner of the
//! paper's Fig 5: the witness tetrahedron, the segments its vertices may move on (green:
//! the warped vertices' asterisk half-segments; magenta: the central parts of cut
//! edges), seen along the dihedral edge (so the dihedral angle appears at true size) or
//! perpendicular to the witness triangle (plane angles at true size). One column wide
//! in the project's figure style (`certmesh::figure`), legend below, vertex labels
//! placed clear of each other.
use super::cases::{output_cases, Kind, DEN};
use super::eval::What;
use crate::stuffing::{all_problems, Certificate, BOUNDS};
use certmesh::figure::output::{self, Meta};
use certmesh::figure::palette;
use certmesh::figure::style::{self, font, pt, stroke, Key, Width, SMALL_PT, THIN_PT};
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
            Kind::Cut => segs.push((at(r[0]), at(r[1]), palette::REDDISH_PURPLE)),
            Kind::Warp => segs.push((at(0), at(r[1]), palette::BLUISH_GREEN)),
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
    render(&fd, stem)?;
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

const FACE: RGBColor = palette::ORANGE;

fn render(f: &Fig, stem: &Path) -> Result<(), String> {
    let e = |x: certmesh::Error| x.to_string();
    let pe = |x: String| certmesh::Error::Param(x);
    let mut keys = vec![
        ("witness tetrahedron".to_string(), Key::Line(palette::BLACK)),
        (
            if f.hl.len() == 2 {
                "faces of the dihedral angle (edge-on)".to_string()
            } else {
                "the triangle of the plane angle".to_string()
            },
            Key::Box(palette::tint(FACE, 0.4)),
        ),
    ];
    let (has_warp, has_cut) = (
        f.segs.iter().any(|s| s.2 == palette::BLUISH_GREEN),
        f.segs.iter().any(|s| s.2 == palette::REDDISH_PURPLE),
    );
    if has_warp {
        keys.push((
            "W: warped vertex, its half-segment".into(),
            Key::Line(palette::BLUISH_GREEN),
        ));
    }
    if has_cut {
        keys.push((
            "C: cut point, its range on the edge".into(),
            Key::Line(palette::REDDISH_PURPLE),
        ));
    }
    // The dot marks every vertex; "F" is named only where a fixed vertex is drawn.
    keys.push((
        if f.labels.iter().any(|l| l.starts_with('F')) {
            "F: fixed lattice vertex".into()
        } else {
            "vertex of the witness".into()
        },
        Key::Dot(palette::BLACK, true),
    ));
    let meta = Meta {
        axes: None,
        legend: keys.iter().map(|k| k.0.clone()).collect(),
        series: keys.len(),
    };
    let pts = f.pts;
    output::figure(
        &stem.with_extension(""),
        Width::Column,
        1.2,
        &meta,
        |area| {
            let top = style::legend_below(area, &keys)?;
            // Equal scales: a square plotting area under the title.
            let (w, h) = top.dim_in_pixel();
            let side = w.min(h);
            let (sq, _) = top.split_horizontally(side);
            // The title in two lines (row; bound and values), so it fits one column.
            let (l1, l2) = f.title.split_once(": ").unwrap_or((&f.title, ""));
            for (i, l) in [l1, l2].iter().enumerate() {
                area.draw(&Text::new(
                    l.to_string(),
                    (
                        (w / 2) as i32,
                        (pt(4.0) + i as f64 * pt(SMALL_PT + 3.0)) as i32,
                    ),
                    font(SMALL_PT)
                        .color(&BLACK)
                        .pos(plotters::style::text_anchor::Pos::new(
                            plotters::style::text_anchor::HPos::Center,
                            plotters::style::text_anchor::VPos::Top,
                        )),
                ))
                .map_err(|x| pe(x.to_string()))?;
            }
            let (_, sq) = sq.split_vertically(pt(2.0 * SMALL_PT + 8.0) as u32);
            let mut ch = ChartBuilder::on(&sq)
                .margin(pt(6.0) as u32)
                .build_cartesian_2d(f.range.0.clone(), f.range.1.clone())
                .map_err(|x| pe(x.to_string()))?;
            let m = |x: String| pe(x);
            for t in &f.hl {
                let poly: Vec<(f64, f64)> = t.iter().map(|&k| pts[k]).collect();
                let mut ring = poly.clone();
                ring.push(poly[0]);
                ch.draw_series(std::iter::once(Polygon::new(
                    poly,
                    palette::tint(FACE, 0.4).filled(),
                )))
                .map_err(|x| m(x.to_string()))?;
                // Seen along the dihedral edge a face is a segment: outline it.
                ch.draw_series(std::iter::once(PathElement::new(
                    ring,
                    FACE.stroke_width(stroke(2.0)),
                )))
                .map_err(|x| m(x.to_string()))?;
            }
            for (a, b, c) in &f.segs {
                ch.draw_series(std::iter::once(PathElement::new(
                    vec![*a, *b],
                    c.stroke_width(stroke(1.5)),
                )))
                .map_err(|x| m(x.to_string()))?;
            }
            for i in 0..4 {
                for j in i + 1..4 {
                    ch.draw_series(std::iter::once(PathElement::new(
                        vec![pts[i], pts[j]],
                        palette::BLACK.stroke_width(stroke(THIN_PT)),
                    )))
                    .map_err(|x| m(x.to_string()))?;
                }
            }
            let r = pt(2.0);
            ch.draw_series(
                pts.iter()
                    .map(|&p| Circle::new(p, r as i32, palette::BLACK.filled())),
            )
            .map_err(|x| m(x.to_string()))?;
            // Vertices that project onto one point (the two ends of a dihedral edge seen
            // end-on) share one label, "W1, W2", instead of two crowding each other.
            let mut px: Vec<(f64, f64)> = Vec::new();
            let mut labels: Vec<String> = Vec::new();
            for (p, l) in pts.iter().zip(&f.labels) {
                let c = ch.backend_coord(p);
                let c = (c.0 as f64, c.1 as f64);
                match px.iter().position(|q| (q.0 - c.0).hypot(q.1 - c.1) <= r) {
                    Some(k) => labels[k] = format!("{}, {l}", labels[k]),
                    None => {
                        px.push(c);
                        labels.push(l.clone());
                    }
                }
            }
            let (b0, b1) = (
                ch.backend_coord(&(f.range.0.start, f.range.1.end)),
                ch.backend_coord(&(f.range.0.end, f.range.1.start)),
            );
            // Labels keep off the drawn segments and edges as well as the vertices.
            let bc = |p: &(f64, f64)| {
                let c = ch.backend_coord(p);
                (c.0 as f64, c.1 as f64)
            };
            let mut lines: Vec<((f64, f64), (f64, f64))> =
                f.segs.iter().map(|(a, b, _)| (bc(a), bc(b))).collect();
            for i in 0..4 {
                for j in i + 1..4 {
                    lines.push((bc(&pts[i]), bc(&pts[j])));
                }
            }
            let obstacles: Vec<_> = lines
                .iter()
                .flat_map(|&(a, b)| certmesh::figure::labels::along(a, b, pt(1.0), pt(2.0)))
                .collect();
            let at = certmesh::figure::labels::place_avoiding(
                &px,
                &labels,
                pt(SMALL_PT + 1.0),
                r,
                (b0.0 as f64, b0.1 as f64, b1.0 as f64, b1.1 as f64),
                &obstacles,
            );
            for (l, (x, y)) in labels.iter().zip(at) {
                area.draw(&Text::new(
                    l.clone(),
                    (x as i32, y as i32),
                    font(SMALL_PT + 1.0),
                ))
                .map_err(|x| m(x.to_string()))?;
            }
            Ok(())
        },
    )
    .map(|_| ())
    .map_err(e)
}
