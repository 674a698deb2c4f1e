//! Writing a figure: one SVG drawing, given its printed size, then rasterised (PNG at
//! 300 dpi, by `resvg`) and converted (PDF, by `svg2pdf`) as asked. Text stays text in
//! SVG and PDF (the PDF embeds the font subset it uses).
use super::style::{perr, Area, Width};
use crate::error::{Error, Result};
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock, RwLock};

/// PNG resolution.
pub const PNG_DPI: f64 = 300.0;

/// A file format a figure can be written as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Svg,
    Png,
    Pdf,
}

impl Format {
    pub const ALL: [Format; 3] = [Format::Svg, Format::Png, Format::Pdf];
    /// The file extension (and the name `--format` takes).
    pub fn ext(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Png => "png",
            Format::Pdf => "pdf",
        }
    }
    /// Parse a comma-separated list such as `svg,png,pdf` (no duplicates, not empty).
    pub fn parse_list(s: &str) -> Result<Vec<Format>> {
        let mut out = Vec::new();
        for part in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let f = Format::ALL
                .into_iter()
                .find(|f| f.ext().eq_ignore_ascii_case(part))
                .ok_or_else(|| {
                    Error::Param(format!(
                        "--format: unknown figure format `{part}` (known: svg, png, pdf)"
                    ))
                })?;
            if !out.contains(&f) {
                out.push(f);
            }
        }
        if out.is_empty() {
            return Err(Error::Param(
                "--format: empty list (give e.g. svg,png or pdf)".into(),
            ));
        }
        Ok(out)
    }
}

static DEFAULT: RwLock<Vec<Format>> = RwLock::new(Vec::new());
static WRITTEN: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Every figure file written by this process so far (for `certmesh figures`, which
/// removes the stale ones it no longer makes).
pub fn written() -> Vec<PathBuf> {
    WRITTEN.lock().map(|v| v.clone()).unwrap_or_default()
}

/// The formats figures are written in when a caller does not say (`--format` sets it
/// once per process; unset: SVG and PNG).
pub fn default_formats() -> Vec<Format> {
    let v = DEFAULT.read().map(|v| v.clone()).unwrap_or_default();
    if v.is_empty() {
        vec![Format::Svg, Format::Png]
    } else {
        v
    }
}

/// Set the process-wide default of [`default_formats`] (the CLI's `--format`).
pub fn set_default_formats(formats: &[Format]) {
    if let Ok(mut d) = DEFAULT.write() {
        *d = formats.to_vec();
    }
}

/// What a figure claims about itself, written into the SVG as `<metadata>` and checked
/// against what is drawn by [`super::check`].
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Meta {
    /// The x and y axis labels (None: a picture without axes).
    pub axes: Option<[String; 2]>,
    /// Legend entries as drawn (one per series, or per colour of a picture).
    pub legend: Vec<String>,
    /// How many series or colour classes the figure draws.
    pub series: usize,
}

impl Meta {
    /// A chart with labelled axes, `series` series and their legend entries.
    pub fn chart(x: &str, y: &str, legend: Vec<String>, series: usize) -> Meta {
        Meta {
            axes: Some([x.into(), y.into()]),
            legend,
            series,
        }
    }
}

fn parent_dirs(base: &Path) -> Result<()> {
    if let Some(dir) = base.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        }
    }
    Ok(())
}

/// `base` with `.ext` appended to its file name (`a/b.c` → `a/b.c.svg` is avoided:
/// the name is taken whole, so `fig-1.5` → `fig-1.5.svg`).
pub fn with_ext(base: &Path, ext: &str) -> PathBuf {
    let name = base
        .file_name()
        .and_then(|s| s.to_str())
        .unwrap_or("figure");
    let name = name
        .strip_suffix(".svg")
        .or_else(|| name.strip_suffix(".png"))
        .or_else(|| name.strip_suffix(".pdf"))
        .unwrap_or(name);
    base.with_file_name(format!("{name}.{ext}"))
}

/// Draw a figure of printed `width` and `aspect` (height / width) with `draw` and write
/// it as `base.<ext>` for each of the default formats. Returns the files written.
pub fn figure(
    base: &Path,
    width: Width,
    aspect: f64,
    meta: &Meta,
    draw: impl FnOnce(&Area) -> Result<()>,
) -> Result<Vec<PathBuf>> {
    figure_as(base, width, aspect, meta, &default_formats(), draw)
}

/// [`figure`] in the given formats.
pub fn figure_as(
    base: &Path,
    width: Width,
    aspect: f64,
    meta: &Meta,
    formats: &[Format],
    draw: impl FnOnce(&Area) -> Result<()>,
) -> Result<Vec<PathBuf>> {
    let size = width.size(aspect);
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        draw(&area)?;
        area.present().map_err(perr)?;
    }
    write_svg(base, &svg, width, meta, formats)
}

/// Give an SVG drawn in figure units (root `width`/`height` in units, with a matching
/// `viewBox`) its printed size and the figure's metadata.
pub fn physical(svg: &str, width: Width, meta: &Meta) -> Result<String> {
    let start = svg
        .find("<svg")
        .ok_or_else(|| Error::Param("figure: no <svg> element".into()))?;
    let end = start
        + svg[start..]
            .find('>')
            .ok_or_else(|| Error::Param("figure: unterminated <svg> element".into()))?;
    let head = &svg[start..end];
    let attr = |name: &str| -> Option<f64> {
        let k = head.find(&format!(" {name}=\""))? + name.len() + 3;
        let v = &head[k..];
        v[..v.find('"')?].trim().parse().ok()
    };
    let vb: Option<Vec<f64>> = head.find(" viewBox=\"").and_then(|k| {
        let v = &head[k + 10..];
        let v: Vec<f64> = v[..v.find('"')?]
            .split_whitespace()
            .filter_map(|x| x.parse().ok())
            .collect();
        (v.len() == 4 && v[2] > 0.0 && v[3] > 0.0).then_some(v)
    });
    let vb = match (vb, attr("width"), attr("height")) {
        (Some(v), _, _) => v,
        (None, Some(w), Some(h)) if w > 0.0 && h > 0.0 => vec![0.0, 0.0, w, h],
        _ => return Err(Error::Param("figure: <svg> without a numeric size".into())),
    };
    let inches = width.inches();
    let mut rest: String = head.to_string();
    for name in ["width", "height", "viewBox"] {
        if let Some(k) = rest.find(&format!(" {name}=\"")) {
            let close = rest[k + name.len() + 3..]
                .find('"')
                .map(|c| k + name.len() + 4 + c);
            if let Some(c) = close {
                rest.replace_range(k..c, "");
            }
        }
    }
    let (w, h) = (vb[2], vb[3]);
    let view = format!("{} {} {w} {h}", vb[0], vb[1]);
    let json = serde_json::to_string(meta).map_err(|e| Error::Param(e.to_string()))?;
    let json = json.replace('&', "&amp;").replace('<', "&lt;");
    Ok(format!(
        "{}{} width=\"{inches}in\" height=\"{:.4}in\" viewBox=\"{view}\">\n<metadata id=\"certmesh-figure\">{json}</metadata>{}",
        &svg[..start],
        rest,
        inches * h / w,
        &svg[end + 1..]
    ))
}

/// The fonts for rasterising and PDF: the system's, with DejaVu Sans (or Liberation
/// Sans) as `sans-serif`, the family plotters measured the text with.
pub fn fonts() -> Arc<resvg::usvg::fontdb::Database> {
    static DB: OnceLock<Arc<resvg::usvg::fontdb::Database>> = OnceLock::new();
    DB.get_or_init(|| {
        let mut db = resvg::usvg::fontdb::Database::new();
        db.load_system_fonts();
        for fam in ["DejaVu Sans", "Liberation Sans", "Noto Sans"] {
            if db.faces().any(|f| f.families.iter().any(|(n, _)| n == fam)) {
                db.set_sans_serif_family(fam);
                break;
            }
        }
        Arc::new(db)
    })
    .clone()
}

fn tree(svg: &str) -> Result<resvg::usvg::Tree> {
    let opt = resvg::usvg::Options {
        fontdb: fonts(),
        ..Default::default()
    };
    resvg::usvg::Tree::from_str(svg, &opt)
        .map_err(|e| Error::Param(format!("figure: SVG not readable: {e}")))
}

/// Rasterise a physical-size SVG at `dpi` on white; PNG bytes with the resolution
/// recorded (pHYs).
pub fn png_bytes(svg: &str, dpi: f64) -> Result<Vec<u8>> {
    let t = tree(svg)?;
    let s = (dpi / 96.0) as f32; // usvg sizes are CSS pixels, 96 to the inch
    let (w, h) = (
        (t.size().width() * s).round().max(1.0) as u32,
        (t.size().height() * s).round().max(1.0) as u32,
    );
    let mut pm = resvg::tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| Error::TooLarge(format!("figure of {w}×{h} pixels")))?;
    pm.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(
        &t,
        resvg::tiny_skia::Transform::from_scale(s, s),
        &mut pm.as_mut(),
    );
    encode_png(pm.data(), w, h, dpi)
}

/// Encode opaque RGBA8 pixels as PNG with a pHYs chunk for `dpi`.
pub fn encode_png(rgba: &[u8], w: u32, h: u32, dpi: f64) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        let ppm = (dpi / 0.0254).round() as u32;
        enc.set_pixel_dims(Some(png::PixelDimensions {
            xppu: ppm,
            yppu: ppm,
            unit: png::Unit::Meter,
        }));
        let mut wr = enc.write_header().map_err(perr)?;
        wr.write_image_data(rgba).map_err(perr)?;
    }
    Ok(out)
}

/// Convert a physical-size SVG to PDF (page = figure size).
pub fn pdf_bytes(svg: &str) -> Result<Vec<u8>> {
    let t = tree(svg)?;
    svg2pdf::to_pdf(
        &t,
        svg2pdf::ConversionOptions::default(),
        svg2pdf::PageOptions { dpi: 96.0 },
    )
    .map_err(|e| Error::Param(format!("figure: PDF conversion failed: {e}")))
}

/// Write an SVG drawn in figure units as `base.<ext>` for each format.
pub fn write_svg(
    base: &Path,
    svg: &str,
    width: Width,
    meta: &Meta,
    formats: &[Format],
) -> Result<Vec<PathBuf>> {
    parent_dirs(base)?;
    let svg = physical(svg, width, meta)?;
    let mut written = Vec::new();
    for &f in formats {
        let path = with_ext(base, f.ext());
        let bytes = match f {
            Format::Svg => svg.as_bytes().to_vec(),
            Format::Png => png_bytes(&svg, PNG_DPI)?,
            Format::Pdf => pdf_bytes(&svg)?,
        };
        std::fs::write(&path, bytes).map_err(|e| Error::io(&path, e))?;
        if let Ok(mut w) = WRITTEN.lock() {
            w.push(path.clone());
        }
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn format_lists_parse_and_reject() {
        assert_eq!(
            Format::parse_list("svg, PNG,pdf,svg").unwrap(),
            vec![Format::Svg, Format::Png, Format::Pdf]
        );
        let e = Format::parse_list("svg,jpeg").unwrap_err().to_string();
        assert!(e.contains("jpeg"), "{e}");
        assert!(Format::parse_list(",").is_err());
    }
    #[test]
    fn physical_size_replaces_units() {
        let s = physical(
            r#"<svg width="950" height="475" viewBox="0 0 950 475" xmlns="http://www.w3.org/2000/svg"><rect/></svg>"#,
            Width::Column,
            &Meta::default(),
        )
        .unwrap();
        assert!(s.contains(r#"width="3.3in""#), "{s}");
        assert!(s.contains(r#"viewBox="0 0 950 475""#), "{s}");
        assert!(s.contains("certmesh-figure"), "{s}");
        assert!(s.contains("xmlns="), "{s}");
    }
}
