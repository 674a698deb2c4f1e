//! The one figure style of the project, and the files a figure is written as.
//!
//! Every figure of `papers/` (and of `certmesh stats --hist`, `demo`, `render`) is
//! drawn once, as SVG in *figure units* (4 units = 1 pt), at one of two printed
//! widths ([`style::Width`]: a single column of 3.3 in or a full page width of 7 in).
//! [`output`] then writes the SVG with its physical size (text stays text), a PNG at
//! 300 dpi rasterised by `resvg`, and a PDF by `svg2pdf` — all from the same SVG, so
//! the formats never disagree.
//!
//! * [`style`]: sizes, fonts (never under 7 pt at the printed width), line widths, tick
//!   labels without spurious decimals, and the chart skeleton every plot uses;
//! * [`palette`]: the Okabe–Ito colour-blind-safe palette and a viridis colour map;
//! * [`output`]: formats (`--format svg,png,pdf`), conversion, physical size;
//! * [`check`]: reads an SVG back and reports what the style forbids (small fonts,
//!   unlabelled axes, a missing legend), for the tests and `certmesh figures --check`.
pub mod check;
pub mod labels;
pub mod output;
pub mod palette;
pub mod style;
