//! Everything that regenerates a folder `papers/<name>/`: one module per paper, and
//! the plotting they need. Algorithm modules never import this module.
//!
//! * [`meshing_of_surfaces`]: Boissonnat, Cohen-Steiner, Mourrain, Rote, Vegter,
//!   *Meshing of Surfaces* (2007), §1.2: Snyder and Plantinga–Vegter;
//! * [`morse`]: the same chapter, §1.5 (BCSV, the Morse census, Stander–Hart), into
//!   the same folder (`certmesh reproduce morse`);
//! * [`gradnormal`], [`gradnormal_bunny`]: Hass, Trnkova, *Approximating isosurfaces by
//!   guaranteed-quality triangular meshes* (SGP 2020): Table 1 and the bunny remesh;
//! * [`stuffing`], [`stuffing_report`]: Labelle, Shewchuk, *Isosurface Stuffing*
//!   (SIGGRAPH 2007): Table 1 on the catalog, histograms;
//! * [`plot`], [`plot_subdivision`]: line plots, histograms and subdivision pictures.
pub mod gradnormal;
pub mod gradnormal_bunny;
pub mod meshing_of_surfaces;
pub mod morse;
pub mod plot;
pub mod plot_rdt2d;
pub mod plot_subdivision;
pub mod plot_sweep;
pub mod stuffing;
pub mod stuffing_report;

use crate::error::{Error, Result};
use std::path::Path;

/// Render a mesh as `out/NAME.<ext>` (the figure formats, [`crate::render`]) and return
/// the markdown that shows it (an image line and its caption).
pub fn render_md(
    out: &Path,
    name: &str,
    input: crate::render::Input,
    cert: Option<&crate::mesher::Certificate>,
    o: &crate::render::RenderOptions,
    caption: &str,
) -> Result<String> {
    let formats = crate::figure::output::default_formats();
    crate::render::render(&out.join(name), input, cert, o, &formats)?;
    Ok(format!("\n![{name}]({name}.png)\n\n*{caption}*\n"))
}

/// The papers that can be reproduced, by the name `certmesh reproduce` takes.
pub const PAPERS: [&str; 4] = ["gradnormal", "stuffing", "meshing-of-surfaces", "morse"];

/// The folder `certmesh reproduce NAME` writes by default: `papers/NAME`, except
/// `morse`, which belongs to the meshing-of-surfaces chapter.
pub fn default_out(name: &str) -> std::path::PathBuf {
    let folder = if name == "morse" {
        "meshing-of-surfaces"
    } else {
        name
    };
    Path::new("papers").join(folder)
}

/// Regenerate `papers/<name>/` into `out` (`quick`: a reduced set, seconds).
pub fn reproduce(name: &str, out: &Path, quick: bool) -> Result<()> {
    match name {
        "gradnormal" => gradnormal::reproduce(out, quick),
        "stuffing" => stuffing_report::reproduce(out, quick),
        "meshing-of-surfaces" => meshing_of_surfaces::reproduce(out, quick),
        "morse" => morse::reproduce(out, quick),
        _ => Err(Error::Unknown {
            kind: "paper",
            name: name.into(),
            known: PAPERS.join(" "),
        }),
    }
}
