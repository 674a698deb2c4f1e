//! Colours: the Okabe–Ito palette (M. Okabe, K. Ito, *Color Universal Design*, 2008),
//! safe for the common colour-vision deficiencies and in greyscale print when paired
//! with distinct markers, and viridis for continuous quantities.
use plotters::style::RGBColor;
/// An RGB colour (plotters' type, so charts and pictures share colours).
pub use plotters::style::RGBColor as Rgb;

pub const BLACK: RGBColor = RGBColor(0, 0, 0);
pub const ORANGE: RGBColor = RGBColor(230, 159, 0);
pub const SKY_BLUE: RGBColor = RGBColor(86, 180, 233);
pub const BLUISH_GREEN: RGBColor = RGBColor(0, 158, 115);
pub const YELLOW: RGBColor = RGBColor(240, 228, 66);
pub const BLUE: RGBColor = RGBColor(0, 114, 178);
pub const VERMILLION: RGBColor = RGBColor(213, 94, 0);
pub const REDDISH_PURPLE: RGBColor = RGBColor(204, 121, 167);
/// Neutral grey for reference lines and box outlines.
pub const GREY: RGBColor = RGBColor(110, 110, 110);

/// The order in which series take colours (yellow last: weak on white).
pub const SERIES: [RGBColor; 8] = [
    BLUE,
    VERMILLION,
    BLUISH_GREEN,
    REDDISH_PURPLE,
    ORANGE,
    SKY_BLUE,
    BLACK,
    YELLOW,
];

/// The colour of series `i`.
pub fn series(i: usize) -> RGBColor {
    SERIES[i % SERIES.len()]
}

/// `c` mixed with white: `t = 0` is `c`, `t = 1` is white (fills behind lines).
pub fn tint(c: RGBColor, t: f64) -> RGBColor {
    let m = |x: u8| (x as f64 + (255.0 - x as f64) * t.clamp(0.0, 1.0)).round() as u8;
    RGBColor(m(c.0), m(c.1), m(c.2))
}

/// `#rrggbb` of a colour (hand-written SVG).
pub fn hex(c: RGBColor) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

/// Viridis at `t ∈ [0, 1]` (clamped; NaN is grey), interpolated between nine stops of
/// the matplotlib map.
pub fn viridis(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    if t.is_nan() {
        return GREY;
    }
    let s = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (s.floor() as usize).min(STOPS.len() - 2);
    let f = s - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let l = |x: u8, y: u8| (x as f64 + (y as f64 - x as f64) * f).round() as u8;
    RGBColor(l(a.0, b.0), l(a.1, b.1), l(a.2, b.2))
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn viridis_ends_and_tint() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(2.0), viridis(1.0));
        assert_eq!(tint(BLUE, 1.0), RGBColor(255, 255, 255));
        assert_eq!(tint(BLUE, 0.0), BLUE);
        assert_eq!(hex(VERMILLION), "#d55e00");
    }
}
