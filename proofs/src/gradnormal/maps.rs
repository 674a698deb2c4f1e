//! Maps of the smallest and largest projected angle over the full region of plane normals
//! of a case (gnomonic chart: great-circle arcs are straight lines), full width in the
//! project's figure style (`certmesh::figure`): viridis with a colour bar in degrees per
//! panel, written in the figure formats (`--format`).
use super::cases::{Case, Ratio};
use super::sample::angles_at;
use certmesh::figure::output::{self, Meta};
use certmesh::figure::palette;
use certmesh::figure::style::{self, perr, Area, Width};
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

/// The axis labels of a map: gnomonic chart coordinates (tangents, no unit).
pub const X_LABEL: &str = "gnomonic x (tangent, no unit)";
pub const Y_LABEL: &str = "gnomonic y (tangent, no unit)";
/// The quantities of the two panels, with their unit (the colour bars' labels).
pub const BARS: [&str; 2] = [
    "smallest projected angle (degrees)",
    "largest projected angle (degrees)",
];

fn draw(area: &Area, g: &Grid, title: &str) -> certmesh::Result<()> {
    let rest = style::titled(area, title)?;
    let panels = rest.split_evenly((1, 2));
    for (pi, panel) in panels.iter().enumerate() {
        let pick = |c: &(f64, f64)| if pi == 0 { c.0 } else { c.1 };
        let (lo, hi) = g
            .cells
            .iter()
            .flatten()
            .map(pick)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        let (_, h) = panel.dim_in_pixel();
        let (plot, bar) = panel.split_vertically(h.saturating_sub(style::colour_bar_height()));
        let name = if pi == 0 { "smallest" } else { "largest" };
        let mut chart = style::chart(
            &plot,
            &format!("{name} angle over the region"),
            g.x0..g.x0 + g.step * g.n as f64,
            g.y0..g.y0 + g.step * g.n as f64,
        )?;
        style::axes(&mut chart, X_LABEL, Y_LABEL)?;
        let span = (hi - lo).max(1e-12);
        chart
            .draw_series(g.cells.iter().enumerate().filter_map(|(idx, c)| {
                c.as_ref().map(|c| {
                    let (i, j) = (idx % g.n, idx / g.n);
                    let x = g.x0 + i as f64 * g.step;
                    let y = g.y0 + j as f64 * g.step;
                    Rectangle::new(
                        [(x, y), (x + g.step, y + g.step)],
                        palette::viridis((pick(c) - lo) / span).filled(),
                    )
                })
            }))
            .map_err(perr)?;
        style::colour_bar(&bar, lo..hi, BARS[pi], palette::viridis)?;
    }
    let _ = (g.lo, g.hi);
    Ok(())
}

/// Write `map-case<i>` (figure formats) for the chosen cases.
pub fn write_maps(dir: &Path, ratio: Ratio, cases: &[Case], which: &[usize]) -> Result<(), String> {
    for &i in which {
        let Some(case) = cases.get(i) else { continue };
        let title = format!("{}: {}", case.name, case.region);
        let g = grid(ratio, case, 80);
        let meta = Meta::chart(X_LABEL, Y_LABEL, BARS.map(String::from).to_vec(), 2);
        output::figure(
            &dir.join(format!("map-case{i}")),
            Width::Full,
            0.62,
            &meta,
            |area| draw(area, &g, &title),
        )
        .map_err(|e| e.to_string())?;
    }
    Ok(())
}
