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

/// Draw a chart's series legend: boxed, on translucent white (inside the `draw!`
/// routines, for either backend).
macro_rules! legend {
    ($chart:expr) => {
        $chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(perr)?
    };
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
                legend!(chart);
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
            let (x0, x1, y0, y1) = extent(pts());
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
            legend!(chart);
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

/// A named set of points for [`scatter`]: drawn as markers, optionally joined in order
/// (a front), each with an optional text label.
#[derive(Clone, Debug)]
pub struct PointSet {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    /// One label per point (empty: none).
    pub labels: Vec<String>,
    /// Join the points in order with a line.
    pub joined: bool,
    /// Filled markers (else hollow).
    pub filled: bool,
}

/// A scatter plot of labelled point sets with a legend (e.g. a certified Pareto front
/// with the reference points marked), as `<base>.svg` and `<base>.png`.
pub fn scatter(
    base: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    sets: &[PointSet],
) -> Result<()> {
    // Okabe–Ito, colour-blind safe.
    const COLORS: [RGBColor; 6] = [
        RGBColor(0, 114, 178),
        RGBColor(213, 94, 0),
        RGBColor(0, 158, 115),
        RGBColor(204, 121, 167),
        RGBColor(230, 159, 0),
        RGBColor(86, 180, 233),
    ];
    macro_rules! draw {
        ($area:expr) => {{
            let area = $area;
            area.fill(&WHITE).map_err(perr)?;
            let (x0, x1, y0, y1) = extent(
                sets.iter()
                    .flat_map(|s| s.points.iter().copied())
                    .filter(|(x, y)| x.is_finite() && y.is_finite()),
            );
            // Room on the right for the point labels.
            let (px, py) = (0.06 * (x1 - x0), 0.06 * (y1 - y0));
            let mut chart = ChartBuilder::on(area)
                .caption(title, ("sans-serif", 26))
                .margin(16)
                .x_label_area_size(56)
                .y_label_area_size(80)
                .build_cartesian_2d((x0 - px)..(x1 + 4.0 * px), (y0 - py)..(y1 + py))
                .map_err(perr)?;
            chart
                .configure_mesh()
                .x_label_formatter(&|v| tick(*v))
                .y_label_formatter(&|v| tick(*v))
                .x_desc(x_label)
                .y_desc(y_label)
                .label_style(("sans-serif", 18))
                .axis_desc_style(("sans-serif", 20))
                .draw()
                .map_err(perr)?;
            for (i, s) in sets.iter().enumerate() {
                let c = COLORS[i % COLORS.len()];
                let pts: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .copied()
                    .filter(|(x, y)| x.is_finite() && y.is_finite())
                    .collect();
                if s.joined {
                    chart
                        .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                        .map_err(perr)?;
                }
                let style = if s.filled {
                    c.filled()
                } else {
                    c.stroke_width(2)
                };
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 5, style)))
                    .map_err(perr)?
                    .label(s.name.clone())
                    .legend(move |(x, y)| Circle::new((x + 8, y), 5, style));
                for (p, l) in pts.iter().zip(&s.labels) {
                    if l.is_empty() {
                        continue;
                    }
                    chart
                        .draw_series(std::iter::once(Text::new(
                            l.clone(),
                            *p,
                            ("sans-serif", 15).into_font().color(&c),
                        )))
                        .map_err(perr)?;
                }
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 17))
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(perr)?;
            Ok(())
        }};
    }
    both(base, (1100, 760), |a| draw!(a), |a| draw!(a))
}

/// The bounding ranges (x0, x1, y0, y1) of finite points, widened to a unit range where
/// empty or degenerate.
fn extent(pts: impl Iterator<Item = (f64, f64)>) -> (f64, f64, f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (x, y) in pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !(x1 > x0) {
        x0 = if x0.is_finite() { x0 - 1.0 } else { -1.0 };
        x1 = x0 + 2.0;
    }
    if !(y1 > y0) {
        y0 = if y0.is_finite() { y0 - 1.0 } else { -1.0 };
        y1 = y0 + 2.0;
    }
    (x0, x1, y0, y1)
}

/// A tick label without spurious decimals: `160`, not `160.0`; `0.25`, not `0.250000`.
pub fn tick(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    if r == r.trunc() {
        format!("{}", r as i64)
    } else {
        let t = format!("{r:.6}");
        t.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn ticks_have_no_spurious_decimals() {
        assert_eq!(super::tick(160.0), "160");
        assert_eq!(super::tick(-2.0), "-2");
        assert_eq!(super::tick(0.25), "0.25");
        assert_eq!(super::tick(162.5000000001), "162.5");
    }
}
