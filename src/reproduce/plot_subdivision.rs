//! Figures of 2D subdivision runs (like the chapter's Figs 1.7 and 1.9): the leaves
//! coloured by the criterion that certified them (the subdivision's own verdicts, as
//! recorded in its tree: nothing is inferred here), the true curve (sign changes of f on
//! a fine grid) and the output polyline, with axes in the curve's coordinates and a
//! legend of the classes drawn. One column wide, in the figure formats.
use crate::error::{Error, Result};
use crate::figure::output::{self, Meta};
use crate::figure::palette::{self, tint};
use crate::figure::style::{self, perr, pt, stroke, Key, Width, LINE_PT, THIN_PT};
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;
use crate::mesh::Curve2;
use crate::subdivision::Verdict;
use plotters::prelude::*;
use std::path::Path;

/// The fill colour of a leaf.
pub fn verdict_color(v: Verdict) -> RGBColor {
    match v {
        Verdict::Empty => RGBColor(238, 238, 238),
        Verdict::Proven { axis: None, .. } => tint(palette::BLUISH_GREEN, 0.6),
        Verdict::Proven { axis: Some(0), .. } => tint(palette::SKY_BLUE, 0.45),
        Verdict::Proven { .. } => tint(palette::ORANGE, 0.45),
        Verdict::Failed(_) => palette::VERMILLION,
    }
}

/// The legend entry of a leaf class.
pub fn verdict_name(v: Verdict) -> &'static str {
    match v {
        Verdict::Empty => "f ≠ 0 on the box",
        Verdict::Proven { axis: None, .. } => "small normal variation",
        Verdict::Proven { axis: Some(0), .. } => "∂f/∂x ≠ 0 (a graph over y)",
        Verdict::Proven { .. } => "∂f/∂y ≠ 0 (a graph over x)",
        Verdict::Failed(_) => "uncertified",
    }
}

fn class(v: Verdict) -> u8 {
    match v {
        Verdict::Empty => 0,
        Verdict::Proven { axis: None, .. } => 1,
        Verdict::Proven { axis: Some(0), .. } => 2,
        Verdict::Proven { .. } => 3,
        Verdict::Failed(_) => 4,
    }
}

const CURVE: RGBColor = palette::REDDISH_PURPLE;

/// Write `base.<ext>`: the leaves of a 2D subdivision coloured by criterion, the true
/// curve f = 0 and the output polyline; the height follows the domain's aspect ratio.
pub fn draw_subdivision_svg(
    base: &Path,
    f: &dyn Implicit,
    domain: &Aabb,
    leaves: &[(Aabb, Verdict)],
    curve: &Curve2,
) -> Result<()> {
    let s = domain.size();
    if !(s[0] > 0.0 && s[1] > 0.0) {
        return Err(Error::Domain("a 2D figure needs a domain with area".into()));
    }
    // Legend: the leaf classes present, in a fixed order, then the two curves.
    let mut present: Vec<Verdict> = Vec::new();
    for (_, v) in leaves {
        if !present.iter().any(|p| class(*p) == class(*v)) {
            present.push(*v);
        }
    }
    present.sort_by_key(|v| class(*v));
    let mut keys: Vec<(String, Key)> = present
        .iter()
        .map(|v| (verdict_name(*v).to_string(), Key::Box(verdict_color(*v))))
        .collect();
    keys.push(("f = 0 (fine grid)".into(), Key::Line(CURVE)));
    keys.push(("output".into(), Key::Line(palette::BLACK)));
    let meta = Meta::chart(
        "x",
        "y",
        keys.iter().map(|k| k.0.clone()).collect(),
        keys.len(),
    );
    // The plot is about as tall as wide for the chapter's square domains; the legend
    // takes up to three rows below.
    let aspect = (s[1] / s[0]).clamp(0.3, 1.6) * 0.86 + 0.2;
    output::figure(base, Width::Column, aspect, &meta, |area| {
        let top = style::legend_below(area, &keys)?;
        let (x0, x1, y0, y1) = (domain.min[0], domain.max[0], domain.min[1], domain.max[1]);
        let mut chart = style::chart(&top, "", x0..x1, y0..y1)?;
        style::axes(&mut chart, "x", "y")?;
        let edge = RGBColor(120, 120, 120).stroke_width(stroke(THIN_PT * 0.5));
        for (b, v) in leaves {
            let r = [(b.min[0], b.max[1]), (b.max[0], b.min[1])];
            chart
                .draw_series([
                    Rectangle::new(r, verdict_color(*v).filled()),
                    Rectangle::new(r, edge),
                ])
                .map_err(perr)?;
        }
        // The true curve: grid cells where f changes sign, at ~4 per printed point.
        let (pw, ph) = chart.plotting_area().dim_in_pixel();
        let (nx, ny) = ((pw as usize / 2).max(2), (ph as usize / 2).max(2));
        let (dx, dy) = ((x1 - x0) / nx as f64, (y1 - y0) / ny as f64);
        let z = domain.min[2];
        let signs: Vec<bool> = (0..=ny)
            .flat_map(|j| (0..=nx).map(move |i| (i, j)))
            .map(|(i, j)| f.eval([x0 + i as f64 * dx, y0 + j as f64 * dy, z]) >= 0.0)
            .collect();
        let at = |i: usize, j: usize| signs[j * (nx + 1) + i];
        let mut cells = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let s = at(i, j);
                if s != at(i + 1, j) || s != at(i, j + 1) || s != at(i + 1, j + 1) {
                    let (cx, cy) = (x0 + i as f64 * dx, y0 + j as f64 * dy);
                    cells.push(Rectangle::new(
                        [(cx, cy), (cx + dx, cy + dy)],
                        CURVE.filled(),
                    ));
                }
            }
        }
        chart.draw_series(cells).map_err(perr)?;
        draw_polyline(&mut chart, curve)
    })
    .map(|_| ())
}

/// A curve's segments (1 pt, black) and its vertices (dots) on a chart in its own
/// coordinates.
fn draw_polyline(chart: &mut style::Chart, curve: &Curve2) -> Result<()> {
    chart
        .draw_series(curve.segments.iter().map(|s| {
            let a = curve.vertices[s[0] as usize];
            let b = curve.vertices[s[1] as usize];
            PathElement::new(
                vec![(a[0], a[1]), (b[0], b[1])],
                palette::BLACK.stroke_width(stroke(LINE_PT)),
            )
        }))
        .map_err(perr)?;
    chart
        .draw_series(
            curve
                .vertices
                .iter()
                .map(|v| Circle::new((v[0], v[1]), pt(1.0) as i32, palette::BLACK.filled())),
        )
        .map_err(perr)?;
    Ok(())
}

/// The legend entry of a curve figure's polyline.
pub const CURVE_OUTPUT: &str = "output polyline and its vertices";

/// Write `base.<ext>` in `formats`: a mesher's output curve on axes in the curve's own
/// coordinates (equal scales, one column wide), the picture of a planar mesh in the
/// figure style. (The mesh file `io::write_curve` writes as `.svg` is a mesh format,
/// full-precision coordinates and nothing else, not a figure.)
pub fn draw_curve_figure(
    base: &Path,
    title: &str,
    curve: &Curve2,
    formats: &[output::Format],
) -> Result<Vec<std::path::PathBuf>> {
    let (x0, x1, y0, y1) = crate::reproduce::plot::extent(
        curve
            .vertices
            .iter()
            .map(|v| (v[0], v[1]))
            .filter(|(x, y)| x.is_finite() && y.is_finite()),
    );
    let m = 0.05 * (x1 - x0).max(y1 - y0);
    let (x0, x1, y0, y1) = (x0 - m, x1 + m, y0 - m, y1 + m);
    let keys = vec![(CURVE_OUTPUT.to_string(), Key::Line(palette::BLACK))];
    let meta = Meta::chart("x", "y", vec![CURVE_OUTPUT.into()], 1);
    let aspect = ((y1 - y0) / (x1 - x0)).clamp(0.3, 1.6) * 0.86 + 0.2;
    output::figure_as(base, Width::Column, aspect, &meta, formats, |area| {
        let top = style::legend_below(area, &keys)?;
        let mut chart = style::chart(&top, title, x0..x1, y0..y1)?;
        style::axes(&mut chart, "x", "y")?;
        draw_polyline(&mut chart, curve)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn a_curve_figure_keeps_the_style() {
        let n = 24;
        let curve = Curve2 {
            vertices: (0..n)
                .map(|i| {
                    let t = i as f64 / n as f64 * std::f64::consts::TAU;
                    [2.0 * t.cos(), t.sin()]
                })
                .collect(),
            segments: (0..n).map(|i| [i, (i + 1) % n]).collect(),
        };
        let d = std::env::temp_dir().join(format!("certmesh-curve-fig-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let files = draw_curve_figure(
            &d.join("ellipse"),
            "ellipse, pv",
            &curve,
            &[output::Format::Svg, output::Format::Png],
        )
        .unwrap();
        assert_eq!(files.len(), 2);
        let r =
            crate::figure::check::check_svg(&std::fs::read_to_string(&files[0]).unwrap()).unwrap();
        assert!(r.problems.is_empty(), "{:?}", r.problems);
        assert!(r.texts.iter().any(|t| t == CURVE_OUTPUT), "{:?}", r.texts);
        std::fs::remove_dir_all(&d).ok();
    }
}
