//! Histograms of dihedral angles (2° bins, like the paper's Figs 1, 4, 6) and the
//! `papers/stuffing/` reproduction.
use crate::error::Result;
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

/// Write the histogram of dihedral angles in 2° bins as `base.<ext>` (the figure
/// formats), in the manner of the paper's Fig. 1: with `emphasis`, the rare bins (those
/// whose ×20 bar still fits) are also drawn ×20 in a second colour, the scale in the
/// legend; the Table 1 bounds of `row` (when given) are dashed lines.
pub fn histogram_svg(
    angles: &[f64],
    base: &Path,
    title: &str,
    emphasis: bool,
    row: Option<&crate::stuffing::params::Row>,
) -> Result<()> {
    use crate::reproduce::plot::{self, Bar, Marker};
    let bars: Vec<Bar> = bins_2deg(angles)
        .iter()
        .enumerate()
        .filter(|(_, &c)| c > 0)
        .map(|(i, &c)| Bar {
            lo: 2.0 * i as f64,
            width: 2.0,
            height: c as f64,
        })
        .collect();
    let mut markers = Vec::new();
    if let Some(r) = row {
        for (v, what) in [
            (r.bounds.min_dihedral, "min"),
            (r.bounds.max_dihedral, "max"),
        ] {
            if let Some(x) = v {
                markers.push(Marker {
                    x,
                    label: format!("Table 1 {what} {x:.2}°"),
                });
            }
        }
    }
    plot::histogram(
        base,
        title,
        "dihedral angle (degrees)",
        "angles per 2° bin",
        &bars,
        &markers,
        if emphasis { 20.0 } else { 1.0 },
    )
}

/// Regenerate `papers/stuffing/` (README.md with the Table 1 comparison and the
/// histograms) into `out_dir`. `quick` uses coarser lattices.
pub fn reproduce(out_dir: &Path, quick: bool) -> Result<()> {
    crate::reproduce::stuffing::run(out_dir, quick)
}
