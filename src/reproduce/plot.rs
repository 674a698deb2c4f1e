//! Publication charts in the project's one figure style ([`crate::figure`]): histograms,
//! line plots and labelled scatter plots, each drawn once as SVG and written in the
//! formats asked for (`--format`; SVG and PNG by default).
use crate::error::Result;
use crate::figure::labels;
use crate::figure::output::{self, Meta};
use crate::figure::palette;
use crate::figure::style::{self, font, perr, pt, stroke, Key, Width, LINE_PT, SMALL_PT, THIN_PT};
use plotters::prelude::*;
use std::path::Path;

pub use crate::figure::style::tick;

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

/// A vertical marker line (e.g. a guaranteed bound) with a label, drawn dashed and
/// listed in the legend.
#[derive(Clone, Debug)]
pub struct Marker {
    pub x: f64,
    pub label: String,
}

/// Dashed vertical marker lines across `y`, labelled beside their top and listed in the
/// legend; colours after the `first` series colour.
fn draw_markers<'a, 'b>(
    chart: &mut style::Chart<'a, 'b>,
    markers: &[Marker],
    ymax: f64,
    first: usize,
) -> Result<()> {
    for (i, m) in markers.iter().enumerate() {
        let c = marker_colour(first, i);
        chart
            .draw_series(DashedLineSeries::new(
                vec![(m.x, 0.0), (m.x, ymax)],
                pt(3.0) as u32,
                pt(2.0) as u32,
                c.stroke_width(stroke(LINE_PT)),
            ))
            .map_err(perr)?;
    }
    Ok(())
}

fn marker_colour(first: usize, i: usize) -> RGBColor {
    palette::series(first + i)
}

fn marker_keys(markers: &[Marker], first: usize) -> Vec<(String, Key)> {
    markers
        .iter()
        .enumerate()
        .map(|(i, m)| (m.label.clone(), Key::Dashed(marker_colour(first, i))))
        .collect()
}

/// Markers within `tol` of the previous one (in x order) joined into one.
fn merge_close(markers: &[Marker], tol: f64) -> Vec<Marker> {
    let mut m = markers.to_vec();
    m.sort_by(|a, b| a.x.total_cmp(&b.x));
    let mut out: Vec<Marker> = Vec::new();
    for k in m {
        match out.last_mut() {
            Some(l) if (k.x - l.x).abs() <= tol => l.label = format!("{}; {}", l.label, k.label),
            _ => out.push(k),
        }
    }
    out
}

fn x_range(bars: &[Bar], markers: &[Marker]) -> (f64, f64) {
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
    if xmin.is_finite() && xmax > xmin {
        (xmin, xmax)
    } else {
        (0.0, 180.0)
    }
}

/// A histogram (one column wide) with optional dashed markers. `emphasis > 1` also
/// draws, in a second colour behind them, the rare bars magnified by that factor (the
/// stuffing paper's ×20 view, Fig. 1): only bars whose magnified height still fits
/// the axis, so none is clipped; the legend states the factor.
pub fn histogram(
    base: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    bars: &[Bar],
    markers: &[Marker],
    emphasis: f64,
) -> Result<()> {
    let (xa, xb) = x_range(bars, markers);
    let markers = &merge_close(markers, 0.01 * (xb - xa));
    let ymax = bars.iter().map(|b| b.height).fold(0.0, f64::max).max(1e-12) * 1.1;
    let magnified: Vec<Bar> = if emphasis > 1.0 {
        bars.iter()
            .filter(|b| b.height > 0.0 && b.height * emphasis <= ymax)
            .copied()
            .collect()
    } else {
        vec![]
    };
    let mut legend = Vec::new();
    let main_name = y_label.to_string();
    if !magnified.is_empty() {
        legend.push(format!("rare bins ×{}", tick(emphasis)));
        legend.push(main_name.clone());
    }
    legend.extend(markers.iter().map(|m| m.label.clone()));
    let series = usize::from(!magnified.is_empty()) + 1 + markers.len();
    let meta = Meta::chart(x_label, y_label, legend, series);
    let (c_main, c_mag) = (palette::BLUE, palette::tint(palette::ORANGE, 0.2));
    let mut keys = Vec::new();
    if !magnified.is_empty() {
        keys.push((format!("rare bins ×{}", tick(emphasis)), Key::Box(c_mag)));
        keys.push((main_name.clone(), Key::Box(c_main)));
    }
    keys.extend(marker_keys(markers, 1));
    output::figure(base, Width::Column, 0.75, &meta, |area| {
        let top = style::legend_below(area, &keys)?;
        let (xmin, xmax) = x_range(bars, markers);
        let pad = 0.02 * (xmax - xmin);
        let mut chart = style::chart(&top, title, (xmin - pad)..(xmax + pad), 0.0..ymax)?;
        style::axes(&mut chart, x_label, y_label)?;
        if !magnified.is_empty() {
            chart
                .draw_series(magnified.iter().map(|b| {
                    Rectangle::new(
                        [(b.lo, 0.0), (b.lo + b.width, b.height * emphasis)],
                        c_mag.filled(),
                    )
                }))
                .map_err(perr)?;
        }
        chart
            .draw_series(bars.iter().map(|b| {
                Rectangle::new([(b.lo, 0.0), (b.lo + b.width, b.height)], c_main.filled())
            }))
            .map_err(perr)?;
        draw_markers(&mut chart, markers, ymax, 1)?;
        Ok(())
    })
    .map(|_| ())
}

/// A line plot of several series (one column wide), with optional dashed markers.
pub fn lines(
    base: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<()> {
    lines_marked(base, Width::Column, title, x_label, y_label, series, &[])
}

/// [`lines`] at a printed `width` with dashed vertical markers (e.g. proven bounds),
/// each in the legend; markers closer than 1% of the x range share one line and one
/// legend entry (their labels joined), so none hides another.
pub fn lines_marked(
    base: &Path,
    width: Width,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    markers: &[Marker],
) -> Result<()> {
    let (x0, x1, _, _) = extent(
        series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|(x, y)| x.is_finite() && y.is_finite()),
    );
    let markers = &merge_close(markers, 0.01 * (x1 - x0));
    let mut legend: Vec<String> = series.iter().map(|s| s.name.clone()).collect();
    legend.extend(markers.iter().map(|m| m.label.clone()));
    let n = series.len() + markers.len();
    let meta = Meta::chart(x_label, y_label, if n > 1 { legend } else { vec![] }, n);
    let mut keys: Vec<(String, Key)> = series
        .iter()
        .enumerate()
        .map(|(i, s)| (s.name.clone(), Key::Line(palette::series(i))))
        .collect();
    keys.extend(marker_keys(markers, series.len()));
    if n < 2 {
        keys.clear();
    }
    let aspect = if width == Width::Full { 0.45 } else { 0.75 };
    output::figure(base, width, aspect, &meta, |area| {
        let top = style::legend_below(area, &keys)?;
        let pts = series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .chain(markers.iter().map(|m| (m.x, 0.0)))
            .filter(|(x, y)| x.is_finite() && y.is_finite());
        let (x0, x1, y0, y1) = extent(pts);
        let (px, py) = (0.02 * (x1 - x0), 0.05 * (y1 - y0));
        let y0 = if y0 >= 0.0 {
            (y0 - py).max(0.0)
        } else {
            y0 - py
        };
        let mut chart = style::chart(&top, title, (x0 - px)..(x1 + px), y0..(y1 + 2.0 * py))?;
        style::axes(&mut chart, x_label, y_label)?;
        for (i, s) in series.iter().enumerate() {
            let c = palette::series(i);
            chart
                .draw_series(LineSeries::new(
                    s.points
                        .iter()
                        .copied()
                        .filter(|(x, y)| x.is_finite() && y.is_finite()),
                    c.stroke_width(stroke(LINE_PT)),
                ))
                .map_err(perr)?;
        }
        draw_markers(&mut chart, markers, y1 + 2.0 * py, series.len())?;
        Ok(())
    })
    .map(|_| ())
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

/// A full-width scatter plot of labelled point sets with a legend (e.g. a certified
/// Pareto front with the reference points marked). Point labels are placed so as not
/// to overlap ([`labels::place`]).
pub fn scatter(
    base: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    sets: &[PointSet],
) -> Result<()> {
    let legend: Vec<String> = sets.iter().map(|s| s.name.clone()).collect();
    let meta = Meta::chart(x_label, y_label, legend, sets.len());
    let keys: Vec<(String, Key)> = sets
        .iter()
        .enumerate()
        .map(|(i, s)| (s.name.clone(), Key::Dot(palette::series(i), s.filled)))
        .collect();
    output::figure(base, Width::Full, 0.62, &meta, |area| {
        let top = style::legend_below(area, &keys)?;
        let (x0, x1, y0, y1) = extent(
            sets.iter()
                .flat_map(|s| s.points.iter().copied())
                .filter(|(x, y)| x.is_finite() && y.is_finite()),
        );
        // Room on the right for the point labels.
        let (px, py) = (0.05 * (x1 - x0), 0.06 * (y1 - y0));
        let mut chart = style::chart(
            &top,
            title,
            (x0 - px)..(x1 + 3.0 * px),
            (y0 - py)..(y1 + py),
        )?;
        style::axes(&mut chart, x_label, y_label)?;
        let r = pt(2.2) as i32;
        let mut labelled: Vec<((i32, i32), String, RGBColor)> = Vec::new();
        for (i, s) in sets.iter().enumerate() {
            let c = palette::series(i);
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .collect();
            if s.joined {
                chart
                    .draw_series(LineSeries::new(
                        pts.clone(),
                        c.stroke_width(stroke(LINE_PT)),
                    ))
                    .map_err(perr)?;
            }
            let st = if s.filled {
                c.filled()
            } else {
                c.stroke_width(stroke(THIN_PT * 2.0))
            };
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, r, st)))
                .map_err(perr)?;
            for (p, l) in pts.iter().zip(&s.labels) {
                if !l.is_empty() {
                    labelled.push((chart.backend_coord(p), l.clone(), c));
                }
            }
        }
        let size = pt(SMALL_PT);
        let ((bx0, by0), (bx1, by1)) = (
            chart.backend_coord(&(x0 - px, y1 + py)),
            chart.backend_coord(&(x1 + 3.0 * px, y0 - py)),
        );
        let pts: Vec<(f64, f64)> = labelled
            .iter()
            .map(|(p, _, _)| (p.0 as f64, p.1 as f64))
            .collect();
        let texts: Vec<String> = labelled.iter().map(|l| l.1.clone()).collect();
        let at = labels::place(
            &pts,
            &texts,
            size,
            r as f64,
            (bx0 as f64, by0 as f64, bx1 as f64, by1 as f64),
        );
        for ((_, l, c), (x, y)) in labelled.iter().zip(at) {
            area.draw(&Text::new(
                l.clone(),
                (x as i32, y as i32),
                font(SMALL_PT).color(c),
            ))
            .map_err(perr)?;
        }
        Ok(())
    })
    .map(|_| ())
}

/// The bounding ranges (x0, x1, y0, y1) of finite points, widened to a unit range where
/// empty or degenerate.
pub fn extent(pts: impl Iterator<Item = (f64, f64)>) -> (f64, f64, f64, f64) {
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
