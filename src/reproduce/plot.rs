//! Publication figures with plotters: every figure is written twice, as `<base>.svg`
//! and `<base>.png`, from one drawing routine (so the two never disagree).
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// One bar of a histogram: `[lo, lo + width)` with a height (count or density).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bar {
    pub lo: f64,
    pub width: f64,
    pub height: f64,
}

/// A named series of (x, y) points for line plots.
#[derive(Clone, Debug)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// A vertical marker line (e.g. a guaranteed bound) with a label.
#[derive(Clone, Debug)]
pub struct Marker {
    pub x: f64,
    pub label: String,
}

fn perr(e: impl std::fmt::Display) -> Error {
    Error::Param(format!("plotting failed: {e}"))
}

fn with_ext(base: &Path, ext: &str) -> PathBuf {
    let mut p = base.to_path_buf();
    let name = format!(
        "{}.{ext}",
        base.file_name()
            .and_then(|s| s.to_str())
            .unwrap_or("figure")
    );
    p.set_file_name(name);
    p
}

fn both(
    base: &Path,
    size: (u32, u32),
    draw: impl Fn(&DrawingArea<SVGBackend, Shift>) -> Result<()>,
    draw_png: impl Fn(&DrawingArea<BitMapBackend, Shift>) -> Result<()>,
) -> Result<()> {
    if let Some(dir) = base.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        }
    }
    let svg = with_ext(base, "svg");
    {
        let area = SVGBackend::new(&svg, size).into_drawing_area();
        draw(&area)?;
        area.present().map_err(perr)?;
    }
    let png = with_ext(base, "png");
    {
        let area = BitMapBackend::new(&png, size).into_drawing_area();
        draw_png(&area)?;
        area.present().map_err(perr)?;
    }
    Ok(())
}

/// A histogram with optional vertical markers. `emphasis > 1` also draws every bar
/// magnified by that factor in a lighter colour (the stuffing paper's ×20 view of rare
/// bins).
pub fn histogram(
    base: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    bars: &[Bar],
    markers: &[Marker],
    emphasis: f64,
) -> Result<()> {
    macro_rules! draw {
        ($area:expr) => {{
            let area = $area;
            area.fill(&WHITE).map_err(perr)?;
            let xmin = bars
                .iter()
                .map(|b| b.lo)
                .chain(markers.iter().map(|m| m.x))
                .fold(f64::INFINITY, f64::min);
            let xmax = bars
                .iter()
                .map(|b| b.lo + b.width)
                .chain(markers.iter().map(|m| m.x))
                .fold(f64::NEG_INFINITY, f64::max);
            let (xmin, xmax) = if xmin.is_finite() && xmax > xmin {
                (xmin, xmax)
            } else {
                (0.0, 180.0)
            };
            let pad = 0.03 * (xmax - xmin);
            let ymax = bars.iter().map(|b| b.height).fold(0.0, f64::max).max(1e-12) * 1.08;
            let mut chart = ChartBuilder::on(area)
                .caption(title, ("sans-serif", 22))
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(60)
                .build_cartesian_2d((xmin - pad)..(xmax + pad), 0.0..ymax)
                .map_err(perr)?;
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc(y_label)
                .disable_x_mesh()
                .draw()
                .map_err(perr)?;
            if emphasis > 1.0 {
                chart
                    .draw_series(bars.iter().map(|b| {
                        Rectangle::new(
                            [
                                (b.lo, 0.0),
                                (b.lo + b.width, (b.height * emphasis).min(ymax)),
                            ],
                            RGBColor(190, 210, 240).filled(),
                        )
                    }))
                    .map_err(perr)?
                    .label(format!("x{emphasis}"))
                    .legend(|(x, y)| {
                        Rectangle::new(
                            [(x, y - 5), (x + 10, y + 5)],
                            RGBColor(190, 210, 240).filled(),
                        )
                    });
            }
            chart
                .draw_series(bars.iter().map(|b| {
                    Rectangle::new(
                        [(b.lo, 0.0), (b.lo + b.width, b.height)],
                        RGBColor(40, 80, 160).filled(),
                    )
                }))
                .map_err(perr)?;
            for m in markers {
                chart
                    .draw_series(LineSeries::new(
                        vec![(m.x, 0.0), (m.x, ymax)],
                        RED.stroke_width(2),
                    ))
                    .map_err(perr)?;
                chart
                    .draw_series(std::iter::once(Text::new(
                        m.label.clone(),
                        (m.x, ymax * 0.97),
                        ("sans-serif", 14).into_font().color(&RED),
                    )))
                    .map_err(perr)?;
            }
            if emphasis > 1.0 {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.8))
                    .border_style(BLACK)
                    .draw()
                    .map_err(perr)?;
            }
            Ok(())
        }};
    }
    both(base, (900, 540), |a| draw!(a), |a| draw!(a))
}

/// A line plot of several series.
pub fn lines(
    base: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<()> {
    const COLORS: [RGBColor; 6] = [
        RGBColor(40, 80, 160),
        RGBColor(200, 60, 40),
        RGBColor(40, 150, 70),
        RGBColor(150, 60, 170),
        RGBColor(220, 150, 20),
        RGBColor(60, 60, 60),
    ];
    macro_rules! draw {
        ($area:expr) => {{
            let area = $area;
            area.fill(&WHITE).map_err(perr)?;
            let pts = || {
                series
                    .iter()
                    .flat_map(|s| s.points.iter().copied())
                    .filter(|(x, y)| x.is_finite() && y.is_finite())
            };
            let (mut x0, mut x1, mut y0, mut y1) = (
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            );
            for (x, y) in pts() {
                x0 = x0.min(x);
                x1 = x1.max(x);
                y0 = y0.min(y);
                y1 = y1.max(y);
            }
            if !(x1 > x0) {
                x0 -= 1.0;
                x1 += 1.0;
            }
            if !(y1 > y0) {
                y0 -= 1.0;
                y1 += 1.0;
            }
            let (px, py) = (0.03 * (x1 - x0), 0.05 * (y1 - y0));
            let mut chart = ChartBuilder::on(area)
                .caption(title, ("sans-serif", 22))
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(70)
                .build_cartesian_2d((x0 - px)..(x1 + px), (y0 - py)..(y1 + py))
                .map_err(perr)?;
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc(y_label)
                .draw()
                .map_err(perr)?;
            for (i, s) in series.iter().enumerate() {
                let c = COLORS[i % COLORS.len()];
                chart
                    .draw_series(LineSeries::new(
                        s.points
                            .iter()
                            .copied()
                            .filter(|(x, y)| x.is_finite() && y.is_finite()),
                        c.stroke_width(2),
                    ))
                    .map_err(perr)?
                    .label(s.name.clone())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2))
                    });
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(perr)?;
            Ok(())
        }};
    }
    both(base, (900, 560), |a| draw!(a), |a| draw!(a))
}

/// Bars of a histogram of `values` with bins of `width` starting at a multiple of it;
/// `normalise` makes the bar areas sum to 1 (a density, as the GradNormal paper's Fig 4).
pub fn bin(values: impl IntoIterator<Item = f64>, width: f64, normalise: bool) -> Vec<Bar> {
    let mut counts: std::collections::BTreeMap<i64, f64> = Default::default();
    let mut n = 0.0;
    for v in values {
        if v.is_finite() {
            *counts.entry((v / width).floor() as i64).or_default() += 1.0;
            n += 1.0;
        }
    }
    let scale = if normalise && n > 0.0 {
        1.0 / (n * width)
    } else {
        1.0
    };
    counts
        .into_iter()
        .map(|(k, c)| Bar {
            lo: k as f64 * width,
            width,
            height: c * scale,
        })
        .collect()
}
