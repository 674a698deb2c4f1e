//! Histograms of dihedral angles (2° bins, like the paper's Figs 1, 4, 6) and the
//! `papers/stuffing/` reproduction.
use crate::error::{Error, Result};
use std::path::Path;

/// Counts of angles in 2° bins over [0°, 180°).
pub fn bins_2deg(angles: &[f64]) -> [u64; 90] {
    let mut b = [0u64; 90];
    for &a in angles {
        let i = ((a / 2.0).floor() as i64).clamp(0, 89) as usize;
        b[i] += 1;
    }
    b
}

/// Write an SVG histogram of dihedral angles in 2° bins. With `emphasis`, bins whose
/// height is under 1/20 of the tallest are also drawn ×20 in red (the paper's device).
pub fn histogram_svg(angles: &[f64], path: &Path, title: &str, emphasis: bool) -> Result<()> {
    histogram(angles, path, title, emphasis)
}

fn histogram(angles: &[f64], path: &Path, title: &str, emphasis: bool) -> Result<()> {
    use plotters::prelude::*;
    let bins = bins_2deg(angles);
    let max = *bins.iter().max().unwrap_or(&1).max(&1) as f64;
    let err = |e: String| Error::io(path, std::io::Error::other(e));
    fn draw<DB: DrawingBackend>(
        root: DrawingArea<DB, plotters::coord::Shift>,
        bins: &[u64; 90],
        max: f64,
        title: &str,
        emphasis: bool,
    ) -> std::result::Result<(), String> {
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(70)
            .build_cartesian_2d(0f64..180f64, 0f64..max * 1.05)
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc("dihedral angle (degrees)")
            .y_desc("count")
            .y_label_formatter(&|v| format!("{v:.0}"))
            .x_label_formatter(&|v| format!("{v:.0}"))
            .draw()
            .map_err(|e| e.to_string())?;
        if emphasis {
            chart
                .draw_series(
                    bins.iter()
                        .enumerate()
                        .filter(|(_, &c)| c > 0 && (c as f64) * 20.0 < max)
                        .map(|(i, &c)| {
                            Rectangle::new(
                                [
                                    (2.0 * i as f64, 0.0),
                                    (2.0 * i as f64 + 2.0, (c as f64 * 20.0).min(max)),
                                ],
                                RED.mix(0.8).filled(),
                            )
                        }),
                )
                .map_err(|e| e.to_string())?;
        }
        chart
            .draw_series(
                bins.iter()
                    .enumerate()
                    .filter(|(_, &c)| c > 0)
                    .map(|(i, &c)| {
                        Rectangle::new(
                            [(2.0 * i as f64, 0.0), (2.0 * i as f64 + 2.0, c as f64)],
                            BLUE.mix(0.7).filled(),
                        )
                    }),
            )
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
        Ok(())
    }
    if path.extension().is_some_and(|e| e == "png") {
        draw(
            BitMapBackend::new(path, (720, 400)).into_drawing_area(),
            &bins,
            max,
            title,
            emphasis,
        )
        .map_err(err)
    } else {
        draw(
            SVGBackend::new(path, (720, 400)).into_drawing_area(),
            &bins,
            max,
            title,
            emphasis,
        )
        .map_err(err)
    }
}

/// Regenerate `papers/stuffing/` (README.md with the Table 1 comparison and the
/// histograms) into `out_dir`. `quick` uses coarser lattices.
pub fn reproduce(out_dir: &Path, quick: bool) -> Result<()> {
    crate::reproduce::stuffing::run(out_dir, quick)
}
