//! Maps of the smallest and largest projected angle over the full region of plane normals
//! of a case (gnomonic chart: great-circle arcs are straight lines), SVG and PNG.
use super::cases::{Case, Ratio};
use super::sample::angles_at;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

struct Grid {
    n: usize,
    x0: f64,
    y0: f64,
    step: f64,
    /// (min angle, max angle) per cell, None outside the region.
    cells: Vec<Option<(f64, f64)>>,
    lo: f64,
    hi: f64,
}

fn grid(ratio: Ratio, case: &Case, n: usize) -> Grid {
    let h = 3f64.sqrt() / 2.0;
    let r = ratio.f64();
    let to_m = |mu: [f64; 3]| [mu[0], mu[1] / h, mu[2] / r];
    let norm = |v: [f64; 3]| {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / l)
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let rays: Vec<[f64; 3]> = case
        .pieces
        .iter()
        .flat_map(|p| p.rays.iter())
        .map(|r| norm(to_m(r.map(|x| x as f64))))
        .collect();
    let mut c = [0.0; 3];
    for r in &rays {
        for k in 0..3 {
            c[k] += r[k];
        }
    }
    let c = norm(c);
    let t = if c[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = norm([
        t[0] - dot(t, c) * c[0],
        t[1] - dot(t, c) * c[1],
        t[2] - dot(t, c) * c[2],
    ]);
    let e2 = [
        c[1] * e1[2] - c[2] * e1[1],
        c[2] * e1[0] - c[0] * e1[2],
        c[0] * e1[1] - c[1] * e1[0],
    ];
    let chart: Vec<(f64, f64)> = rays
        .iter()
        .map(|r| (dot(*r, e1) / dot(*r, c), dot(*r, e2) / dot(*r, c)))
        .collect();
    let (mut xa, mut xb, mut ya, mut yb) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in &chart {
        xa = xa.min(x);
        xb = xb.max(x);
        ya = ya.min(y);
        yb = yb.max(y);
    }
    let span = (xb - xa).max(yb - ya).max(1e-9) * 1.04;
    let (x0, y0) = (0.5 * (xa + xb) - 0.5 * span, 0.5 * (ya + yb) - 0.5 * span);
    let step = span / n as f64;
    let mut cells = Vec::with_capacity(n * n);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (x0 + (i as f64 + 0.5) * step, y0 + (j as f64 + 0.5) * step);
            let m = [0, 1, 2].map(|k| c[k] + x * e1[k] + y * e2[k]);
            let mu = [m[0], m[1] * h, m[2] * r];
            if case
                .pieces
                .iter()
                .any(|p| !p.rays.is_empty() && p.contains(mu))
            {
                let a = angles_at(ratio, case, mu);
                let mn = a.iter().cloned().fold(f64::INFINITY, f64::min);
                let mx = a.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                lo = lo.min(mn);
                hi = hi.max(mx);
                cells.push(Some((mn, mx)));
            } else {
                cells.push(None);
            }
        }
    }
    Grid {
        n,
        x0,
        y0,
        step,
        cells,
        lo,
        hi,
    }
}

fn colour(t: f64) -> RGBColor {
    // A blue → green → yellow ramp.
    let t = t.clamp(0.0, 1.0);
    let (r, g, b) = if t < 0.5 {
        let s = t / 0.5;
        (0.2 * (1.0 - s), 0.2 + 0.5 * s, 0.6 * (1.0 - s) + 0.3 * s)
    } else {
        let s = (t - 0.5) / 0.5;
        (0.95 * s, 0.7 + 0.2 * s, 0.3 * (1.0 - s))
    };
    RGBColor((r * 255.0) as u8, (g * 255.0) as u8, (b * 255.0) as u8)
}

fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    g: &Grid,
    title: &str,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    area.fill(&WHITE).map_err(e)?;
    let panels = area.split_evenly((1, 2));
    for (pi, panel) in panels.iter().enumerate() {
        let (lo, hi) = if pi == 0 {
            let v: Vec<f64> = g.cells.iter().flatten().map(|c| c.0).collect();
            (
                v.iter().cloned().fold(f64::INFINITY, f64::min),
                v.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
            )
        } else {
            let v: Vec<f64> = g.cells.iter().flatten().map(|c| c.1).collect();
            (
                v.iter().cloned().fold(f64::INFINITY, f64::min),
                v.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
            )
        };
        let cap = format!(
            "{} angle: {:.4}° (dark) .. {:.4}° (light)",
            if pi == 0 { "smallest" } else { "largest" },
            lo,
            hi
        );
        let mut chart = ChartBuilder::on(panel)
            .caption(cap, ("sans-serif", 16))
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(40)
            .build_cartesian_2d(
                g.x0..g.x0 + g.step * g.n as f64,
                g.y0..g.y0 + g.step * g.n as f64,
            )
            .map_err(|x| x.to_string())?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("gnomonic x")
            .y_desc("gnomonic y")
            .draw()
            .map_err(|x| x.to_string())?;
        let span = (hi - lo).max(1e-12);
        chart
            .draw_series(g.cells.iter().enumerate().filter_map(|(idx, c)| {
                c.map(|(mn, mx)| {
                    let v = if pi == 0 { mn } else { mx };
                    let (i, j) = (idx % g.n, idx / g.n);
                    let x = g.x0 + i as f64 * g.step;
                    let y = g.y0 + j as f64 * g.step;
                    Rectangle::new(
                        [(x, y), (x + g.step, y + g.step)],
                        colour((v - lo) / span).filled(),
                    )
                })
            }))
            .map_err(|x| x.to_string())?;
    }
    let _ = (g.lo, g.hi, title);
    Ok(())
}

/// Write `map-case<i>.svg/.png` for the chosen cases.
pub fn write_maps(dir: &Path, ratio: Ratio, cases: &[Case], which: &[usize]) -> Result<(), String> {
    for &i in which {
        let Some(case) = cases.get(i) else { continue };
        let title = format!("{}: {}", case.name, case.region);
        let g = grid(ratio, case, 60);
        let svg = dir.join(format!("map-case{i}.svg"));
        {
            let area = SVGBackend::new(&svg, (1100, 520)).into_drawing_area();
            area.fill(&WHITE).map_err(|e| e.to_string())?;
            let (top, rest) = area.split_vertically(30);
            top.titled(&title, ("sans-serif", 16))
                .map_err(|e| e.to_string())?;
            draw(&rest, &g, &title)?;
            area.present().map_err(|e| e.to_string())?;
        }
        let g = grid(ratio, case, 300);
        let png = dir.join(format!("map-case{i}.png"));
        {
            let area = BitMapBackend::new(&png, (1100, 520)).into_drawing_area();
            area.fill(&WHITE).map_err(|e| e.to_string())?;
            let (top, rest) = area.split_vertically(30);
            top.titled(&title, ("sans-serif", 16))
                .map_err(|e| e.to_string())?;
            draw(&rest, &g, &title)?;
            area.present().map_err(|e| e.to_string())?;
        }
    }
    Ok(())
}
