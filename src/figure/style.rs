//! Sizes, fonts, line widths, tick labels and the chart skeleton of every figure.
//!
//! Figures are drawn in *figure units*, [`UNITS_PER_PT`] to the printed point, at one
//! of two printed widths; [`super::output`] gives the SVG its physical size. Font sizes
//! here are in printed points, so "≥ 7 pt" holds by construction and is checked again
//! on the written SVG by [`super::check`].
use crate::error::{Error, Result};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor;
use std::ops::Range;

/// Figure units per printed point (1/72 in): 4 keeps plotters' integer coordinates
/// at a quarter point, finer than print can show.
pub const UNITS_PER_PT: f64 = 4.0;
/// The smallest font a figure may use, in points at its printed width.
pub const MIN_FONT_PT: f64 = 7.0;
/// Tick labels, legend entries and in-plot annotations.
pub const SMALL_PT: f64 = 7.5;
/// Axis labels.
pub const LABEL_PT: f64 = 8.0;
/// Figure titles.
pub const TITLE_PT: f64 = 8.5;
/// Data lines (1 pt survives printing and reduction).
pub const LINE_PT: f64 = 1.0;
/// Reference lines, outlines, mesh edges (0.5 pt: the thinnest a printer keeps).
pub const THIN_PT: f64 = 0.5;

/// The printed width of a figure.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Width {
    /// One column of a two-column paper: 3.3 in.
    Column,
    /// The full text width: 7 in.
    Full,
}

impl Width {
    /// The printed width in inches.
    pub fn inches(self) -> f64 {
        match self {
            Width::Column => 3.3,
            Width::Full => 7.0,
        }
    }
    /// The width in figure units.
    pub fn units(self) -> u32 {
        (self.inches() * 72.0 * UNITS_PER_PT).round() as u32
    }
    /// (width, height) in figure units for `aspect` = height / width.
    pub fn size(self, aspect: f64) -> (u32, u32) {
        let w = self.units();
        (w, (w as f64 * aspect).round().max(16.0) as u32)
    }
}

/// Points to figure units.
pub fn pt(x: f64) -> f64 {
    x * UNITS_PER_PT
}

/// A stroke width in figure units for a width in points.
pub fn stroke(points: f64) -> u32 {
    pt(points).round().max(1.0) as u32
}

/// plotters' SVG backend writes `font-size` as its font size / 1.24 (its sizes are
/// ascent-to-descent heights); this undoes it, so that the written size is the one asked.
pub const PLOTTERS_FONT_SCALE: f64 = 1.24;

/// The sans-serif font at `points` (printed), for plotters.
pub fn font(points: f64) -> FontDesc<'static> {
    (
        "sans-serif",
        pt(points.max(MIN_FONT_PT)) * PLOTTERS_FONT_SCALE,
    )
        .into_font()
}

/// A tick label without spurious decimals: `20`, not `20.0`; `0.25`, not `0.250000`;
/// `100 000`, not `100000.0` (thousands grouped by a space from five digits on).
pub fn tick(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    if r == r.trunc() && r.abs() < 1e15 {
        let n = r as i64;
        let digits = n.unsigned_abs().to_string();
        let body = if digits.len() >= 5 {
            let mut s = String::new();
            for (i, ch) in digits.chars().enumerate() {
                if i > 0 && (digits.len() - i) % 3 == 0 {
                    s.push(' ');
                }
                s.push(ch);
            }
            s
        } else {
            digits
        };
        if n < 0 {
            format!("-{body}")
        } else {
            body
        }
    } else {
        let t = format!("{r:.6}");
        t.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

pub fn perr(e: impl std::fmt::Display) -> Error {
    Error::Param(format!("plotting failed: {e}"))
}

/// The area every figure draws on.
pub type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
/// A chart with f64 axes on an [`Area`].
pub type Chart<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Room for the y tick labels of `range` (the widest of a few ticks) plus the axis
/// label, in figure units.
fn y_room(range: &Range<f64>) -> f64 {
    let widest = (0..=6)
        .map(|i| tick(range.start + (range.end - range.start) * i as f64 / 6.0).len())
        .max()
        .unwrap_or(3) as f64;
    pt(0.5 * SMALL_PT * widest + LABEL_PT + 6.0)
}

/// The chart skeleton: white background, a title (empty: none), margins and label areas
/// sized for the style's fonts.
pub fn chart<'a, 'b>(
    area: &'a Area<'b>,
    title: &str,
    x: Range<f64>,
    y: Range<f64>,
) -> Result<Chart<'a, 'b>> {
    area.fill(&WHITE).map_err(perr)?;
    let mut b = ChartBuilder::on(area);
    b.margin(pt(6.0) as u32)
        .x_label_area_size(pt(SMALL_PT + LABEL_PT + 9.0) as u32)
        .y_label_area_size(y_room(&y) as u32);
    let (w, _) = area.dim_in_pixel();
    let lines = wrap(title, TITLE_PT, w as f64 - pt(12.0));
    if lines.len() == 1 {
        b.caption(title, font(TITLE_PT));
    } else if lines.len() > 1 {
        // A title too long for the width: centred lines in the top margin.
        let h = title_lines(area, &lines)?;
        b.margin_top((pt(3.0) + h) as u32);
    }
    b.build_cartesian_2d(x, y).map_err(perr)
}

/// Draw `lines` centred at the top of `area` in the title font; the height they take
/// (figure units).
pub fn title_lines(area: &Area, lines: &[String]) -> Result<f64> {
    let (w, _) = area.dim_in_pixel();
    let line_h = pt(TITLE_PT + 2.5);
    for (i, l) in lines.iter().enumerate() {
        area.draw(&Text::new(
            l.clone(),
            ((w / 2) as i32, (pt(3.0) + i as f64 * line_h) as i32),
            font(TITLE_PT).color(&BLACK).pos(text_anchor::Pos::new(
                text_anchor::HPos::Center,
                text_anchor::VPos::Top,
            )),
        ))
        .map_err(perr)?;
    }
    Ok(pt(3.0) + lines.len() as f64 * line_h)
}

/// A title across the top of `area`, broken into lines that fit ([`wrap`]); returns
/// the area below it.
pub fn titled<'b>(area: &Area<'b>, title: &str) -> Result<Area<'b>> {
    area.fill(&WHITE).map_err(perr)?;
    let (w, _) = area.dim_in_pixel();
    let lines = wrap(title, TITLE_PT, w as f64 - pt(12.0));
    if lines.is_empty() {
        return Ok(area.clone());
    }
    let h = title_lines(area, &lines)?;
    Ok(area.split_vertically(h.ceil() as u32).1)
}

/// The height (figure units) of a [`colour_bar`].
pub fn colour_bar_height() -> u32 {
    pt(SMALL_PT + LABEL_PT + 9.0 + 7.0 + 12.0) as u32
}

/// A horizontal colour bar for a colour map over `range`: the map drawn in 200 steps,
/// ticks in the style's format and the quantity with its unit as the axis label.
pub fn colour_bar(
    area: &Area,
    range: Range<f64>,
    label: &str,
    map: impl Fn(f64) -> RGBColor,
) -> Result<()> {
    area.fill(&WHITE).map_err(perr)?;
    let (lo, hi) = (range.start, range.end.max(range.start + 1e-12));
    let mut ch = ChartBuilder::on(area)
        .margin(pt(6.0) as u32)
        .margin_left(pt(18.0) as u32)
        .margin_right(pt(18.0) as u32)
        .x_label_area_size(pt(SMALL_PT + LABEL_PT + 9.0) as u32)
        .build_cartesian_2d(lo..hi, 0.0..1.0)
        .map_err(perr)?;
    ch.configure_mesh()
        .disable_mesh()
        .disable_y_axis()
        .x_labels(5)
        .x_label_formatter(&|v| tick(*v))
        .x_desc(label)
        .label_style(font(SMALL_PT))
        .axis_desc_style(font(LABEL_PT))
        .axis_style(BLACK.stroke_width(stroke(THIN_PT)))
        .set_all_tick_mark_size(pt(2.5) as u32)
        .draw()
        .map_err(perr)?;
    let n = 200;
    ch.draw_series((0..n).map(|i| {
        let (a, b) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
        Rectangle::new(
            [(lo + a * (hi - lo), 0.0), (lo + b * (hi - lo), 1.0)],
            map(0.5 * (a + b)).filled(),
        )
    }))
    .map_err(perr)?;
    ch.draw_series(std::iter::once(Rectangle::new(
        [(lo, 0.0), (hi, 1.0)],
        BLACK.stroke_width(stroke(THIN_PT)),
    )))
    .map_err(perr)?;
    Ok(())
}

/// `text` broken at spaces into lines that fit `width` figure units at `points`
/// (glyphs estimated at 0.55 em, wider than [`super::check`]'s 0.5 em); empty text: no
/// line; a word longer than the width stands on its own line.
pub fn wrap(text: &str, points: f64, width: f64) -> Vec<String> {
    let per_char = 0.55 * pt(points.max(MIN_FONT_PT));
    let max = ((width / per_char).floor() as usize).max(1);
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(l) if l.chars().count() + 1 + word.chars().count() <= max => {
                l.push(' ');
                l.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// Axes with labelled ticks ([`tick`]) and axis labels (with their units), light grid.
pub fn axes<'a, 'b>(chart: &mut Chart<'a, 'b>, x_label: &str, y_label: &str) -> Result<()> {
    chart
        .configure_mesh()
        .x_labels(6)
        .y_labels(6)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style(font(SMALL_PT))
        .axis_desc_style(font(LABEL_PT))
        .axis_style(BLACK.stroke_width(stroke(THIN_PT)))
        .bold_line_style(RGBColor(225, 225, 225).stroke_width(stroke(THIN_PT)))
        .light_line_style(TRANSPARENT)
        .set_all_tick_mark_size(pt(2.5) as u32)
        .draw()
        .map_err(perr)
}

/// How a legend entry shows its series.
#[derive(Clone, Copy, Debug)]
pub enum Key {
    Line(RGBColor),
    Dashed(RGBColor),
    Box(RGBColor),
    /// A marker, filled or hollow.
    Dot(RGBColor, bool),
}

/// Split the bottom of `area` for a legend of `keys` (flowed in rows across the
/// figure's width, so it never covers data) and draw it; returns the area above.
/// No keys: the whole area, no legend.
pub fn legend_below<'b>(area: &Area<'b>, keys: &[(String, Key)]) -> Result<Area<'b>> {
    area.fill(&WHITE).map_err(perr)?;
    if keys.is_empty() {
        return Ok(area.clone());
    }
    let (w, h) = area.dim_in_pixel();
    let size = pt(SMALL_PT);
    let (sw, gap, row_h) = (pt(11.0), pt(8.0), pt(SMALL_PT + 3.5));
    let margin = pt(6.0);
    // Flow the entries into rows.
    let mut rows: Vec<Vec<usize>> = vec![vec![]];
    let mut x = margin;
    for (i, (name, _)) in keys.iter().enumerate() {
        let ew = sw + pt(3.0) + 0.55 * size * name.chars().count() as f64 + gap;
        if x + ew > w as f64 - margin && !rows.last().is_some_and(|r| r.is_empty()) {
            rows.push(vec![]);
            x = margin;
        }
        rows.last_mut().map(|r| r.push(i));
        x += ew;
    }
    let lh = (rows.len() as f64 * row_h + pt(4.0)) as u32;
    let (top, bottom) = area.split_vertically(h.saturating_sub(lh));
    for (r, row) in rows.iter().enumerate() {
        let y = (pt(2.0) + r as f64 * row_h + 0.5 * row_h) as i32;
        let mut x = margin as i32;
        for &i in row {
            let (name, key) = &keys[i];
            let (x0, x1) = (x, x + sw as i32);
            let lw = stroke(LINE_PT);
            let res = match *key {
                Key::Line(c) => bottom.draw(&PathElement::new(
                    vec![(x0, y), (x1, y)],
                    c.stroke_width(lw),
                )),
                Key::Dashed(c) => {
                    let d = (sw / 4.0) as i32;
                    bottom
                        .draw(&PathElement::new(
                            vec![(x0, y), (x0 + d, y)],
                            c.stroke_width(lw),
                        ))
                        .and_then(|_| {
                            bottom.draw(&PathElement::new(
                                vec![(x0 + 2 * d, y), (x0 + 3 * d, y)],
                                c.stroke_width(lw),
                            ))
                        })
                }
                Key::Box(c) => {
                    let hh = pt(3.0) as i32;
                    bottom.draw(&Rectangle::new([(x0, y - hh), (x1, y + hh)], c.filled()))
                }
                Key::Dot(c, filled) => {
                    let st = if filled {
                        c.filled()
                    } else {
                        c.stroke_width(stroke(THIN_PT * 2.0))
                    };
                    bottom.draw(&Circle::new(((x0 + x1) / 2, y), pt(2.2) as i32, st))
                }
            };
            res.map_err(perr)?;
            bottom
                .draw(&Text::new(
                    name.clone(),
                    (x1 + pt(3.0) as i32, y - (0.5 * size) as i32),
                    font(SMALL_PT),
                ))
                .map_err(perr)?;
            x = x1 + pt(3.0) as i32 + (0.55 * size * name.chars().count() as f64 + gap) as i32;
        }
    }
    Ok(top)
}

/// The series legend, boxed on translucent white at `pos`.
pub fn legend<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>, pos: SeriesLabelPosition) -> Result<()> {
    chart
        .configure_series_labels()
        .position(pos)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.stroke_width(stroke(THIN_PT)))
        .label_font(font(SMALL_PT))
        .margin(pt(3.0) as u32)
        .legend_area_size(pt(12.0) as u32)
        .draw()
        .map_err(perr)
}

/// A legend swatch: a short line.
pub fn swatch_line(c: RGBColor, width_pt: f64) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| {
        PathElement::new(
            vec![(x, y), (x + pt(10.0) as i32, y)],
            c.stroke_width(stroke(width_pt)),
        )
    }
}

/// A legend swatch: a filled box.
pub fn swatch_box(c: RGBColor) -> impl Fn((i32, i32)) -> Rectangle<(i32, i32)> {
    let h = pt(3.0) as i32;
    move |(x, y)| Rectangle::new([(x, y - h), (x + 3 * h, y + h)], c.filled())
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn ticks_have_no_spurious_decimals() {
        assert_eq!(tick(160.0), "160");
        assert_eq!(tick(20.0), "20");
        assert_eq!(tick(-2.0), "-2");
        assert_eq!(tick(0.25), "0.25");
        assert_eq!(tick(162.5000000001), "162.5");
        assert_eq!(tick(100000.0), "100 000");
        assert_eq!(tick(-1234567.0), "-1 234 567");
        assert_eq!(tick(2500.0), "2500");
        assert_eq!(tick(0.30000000000000004), "0.3");
    }
    #[test]
    fn widths_are_the_printed_ones() {
        assert_eq!(Width::Column.units(), 950);
        assert_eq!(Width::Full.units(), 2016);
        assert_eq!(Width::Column.size(0.5), (950, 475));
        assert!(font(5.0).get_size() >= pt(MIN_FONT_PT));
    }
    #[test]
    fn long_titles_wrap_at_spaces() {
        assert!(wrap("", TITLE_PT, 900.0).is_empty());
        assert_eq!(wrap("short title", TITLE_PT, 900.0), vec!["short title"]);
        let long =
            "mid(AB) mid(AC) mid(AB2) of the valence-4 square at AD (cut A): projected angles";
        let lines = wrap(long, TITLE_PT, 900.0);
        assert!(lines.len() >= 2, "{lines:?}");
        assert_eq!(lines.join(" "), long);
        for l in &lines {
            assert!(
                0.55 * pt(TITLE_PT) * l.chars().count() as f64 <= 900.0,
                "{l}"
            );
        }
    }
}
