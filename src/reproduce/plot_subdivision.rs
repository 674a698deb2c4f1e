//! Figures of 2D subdivision runs (like the chapter's Figs 1.7 and 1.9): the leaves
//! coloured by the criterion that certified them, the true curve (sign changes of f on a
//! pixel grid, red) and the output polyline (black). Written as SVG and PNG from one
//! drawing routine. No text is drawn (no font dependency); the colours are:
//! grey f ≠ 0, green SNV, blue parameterizable in y (∂f/∂x ≠ 0), orange parameterizable
//! in x (∂f/∂y ≠ 0), red uncertified.
use crate::error::{Error, Result};
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;
use crate::mesh::Curve2;
use crate::subdivision::Verdict;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

fn perr(e: impl std::fmt::Display) -> Error {
    Error::Param(format!("plotting failed: {e}"))
}

/// The fill colour of a leaf.
pub fn verdict_color(v: Verdict) -> RGBColor {
    match v {
        Verdict::Empty => RGBColor(235, 235, 235),
        Verdict::Proven { axis: None, .. } => RGBColor(190, 230, 190),
        Verdict::Proven { axis: Some(0), .. } => RGBColor(190, 210, 245),
        Verdict::Proven { .. } => RGBColor(250, 215, 170),
        Verdict::Failed(_) => RGBColor(240, 90, 90),
    }
}

fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    f: &dyn Implicit,
    domain: &Aabb,
    leaves: &[(Aabb, Verdict)],
    curve: &Curve2,
    px: (u32, u32),
) -> Result<()> {
    area.fill(&WHITE).map_err(perr)?;
    let (w, h) = (px.0 as f64, px.1 as f64);
    let sx = |x: f64| ((x - domain.min[0]) / (domain.max[0] - domain.min[0]) * (w - 1.0)) as i32;
    let sy = |y: f64| ((domain.max[1] - y) / (domain.max[1] - domain.min[1]) * (h - 1.0)) as i32;
    for (b, v) in leaves {
        let r = [(sx(b.min[0]), sy(b.max[1])), (sx(b.max[0]), sy(b.min[1]))];
        area.draw(&Rectangle::new(r, verdict_color(*v).filled()))
            .map_err(perr)?;
        area.draw(&Rectangle::new(r, RGBColor(120, 120, 120).stroke_width(1)))
            .map_err(perr)?;
    }
    // The true curve: pixels whose sign differs from the right or lower neighbour.
    let (nx, ny) = (px.0 as usize, px.1 as usize);
    let val = |i: usize, j: usize| {
        let x = domain.min[0] + (i as f64 + 0.5) / nx as f64 * (domain.max[0] - domain.min[0]);
        let y = domain.max[1] - (j as f64 + 0.5) / ny as f64 * (domain.max[1] - domain.min[1]);
        f.eval([x, y, domain.min[2]]) >= 0.0
    };
    let signs: Vec<bool> = (0..ny)
        .flat_map(|j| (0..nx).map(move |i| (i, j)))
        .map(|(i, j)| val(i, j))
        .collect();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let s = signs[j * nx + i];
            if s != signs[j * nx + i + 1] || s != signs[(j + 1) * nx + i] {
                area.draw_pixel((i as i32, j as i32), &RGBColor(220, 0, 0))
                    .map_err(perr)?;
            }
        }
    }
    for s in &curve.segments {
        let a = curve.vertices[s[0] as usize];
        let b = curve.vertices[s[1] as usize];
        area.draw(&PathElement::new(
            vec![(sx(a[0]), sy(a[1])), (sx(b[0]), sy(b[1]))],
            BLACK.stroke_width(2),
        ))
        .map_err(perr)?;
    }
    for v in &curve.vertices {
        area.draw(&Circle::new((sx(v[0]), sy(v[1])), 2, BLACK.filled()))
            .map_err(perr)?;
    }
    Ok(())
}

/// Write `<base>.svg` and `<base>.png`: the leaves of a 2D subdivision coloured by
/// criterion, the true curve f = 0 and the output polyline. `width` is the image width in
/// pixels; the height follows the domain's aspect ratio.
pub fn draw_subdivision_svg(
    base: &Path,
    f: &dyn Implicit,
    domain: &Aabb,
    leaves: &[(Aabb, Verdict)],
    curve: &Curve2,
    width: u32,
) -> Result<()> {
    let s = domain.size();
    if !(s[0] > 0.0 && s[1] > 0.0) {
        return Err(Error::Domain("a 2D figure needs a domain with area".into()));
    }
    let height = ((width as f64) * s[1] / s[0]).round().max(16.0) as u32;
    if let Some(dir) = base.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        }
    }
    let name = base
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("figure")
        .to_string();
    let svg = base.with_file_name(format!("{name}.svg"));
    let png = base.with_file_name(format!("{name}.png"));
    {
        let area = SVGBackend::new(&svg, (width, height)).into_drawing_area();
        draw(&area, f, domain, leaves, curve, (width, height))?;
        area.present().map_err(perr)?;
    }
    {
        let area = BitMapBackend::new(&png, (width, height)).into_drawing_area();
        draw(&area, f, domain, leaves, curve, (width, height))?;
        area.present().map_err(perr)?;
    }
    Ok(())
}
