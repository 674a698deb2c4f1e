//! `certmesh render`: a headless software renderer for publication pictures of meshes.
//!
//! Triangle meshes, and the boundary of tetrahedral meshes, are projected
//! orthographically from a view (azimuth, elevation), depth-tested per pixel in a
//! z-buffer ([`raster`]) with flat or Gouraud shading and an optional wireframe, then
//! composed with a title and a colour bar or legend as an SVG figure of one column
//! ([`crate::figure`]), written as SVG, PNG at 300 dpi and/or PDF. A cut through a plane
//! removes the tetrahedra beyond it and shows the faces of the tetrahedra it cuts (the
//! stuffing paper's Fig. 1). Colouring: by angle quality (viridis, with its scale), by
//! the mesher's certificate (only its typed claims and uncertified regions:
//! [`scene::classify`]), or none.
pub mod raster;
pub mod scene;

pub use scene::{classify, CertClass, Plane};

use crate::error::{Error, Result};
use crate::figure::output::{self, Format, Meta};
use crate::figure::palette::{self, hex, tint, viridis};
use crate::figure::style::{Width, UNITS_PER_PT};
use crate::mesh::{TetMesh, TriMesh};
use crate::mesher::Certificate;
use base64::Engine as _;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// What the faces are coloured by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorBy {
    /// Smallest angle of each triangle (or smallest dihedral of its tetrahedron).
    Quality,
    /// The certificate class of each face ([`CertClass`]).
    Certificate,
    /// One colour (cut faces in a second one).
    None,
}

impl ColorBy {
    pub fn parse(s: &str) -> Result<ColorBy> {
        match s {
            "quality" => Ok(ColorBy::Quality),
            "certificate" => Ok(ColorBy::Certificate),
            "none" => Ok(ColorBy::None),
            _ => Err(Error::Param(format!(
                "--color: unknown colouring '{s}' (known: quality certificate none)"
            ))),
        }
    }
}

/// How to render.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Degrees about the z axis, from +x.
    pub azimuth: f64,
    /// Degrees above the xy plane.
    pub elevation: f64,
    pub cut: Option<Plane>,
    pub color: ColorBy,
    pub wire: bool,
    /// Per-vertex (Gouraud) shading instead of flat.
    pub gouraud: bool,
    /// Title above the picture (empty: none).
    pub title: String,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            azimuth: 35.0,
            elevation: 25.0,
            cut: None,
            color: ColorBy::Quality,
            wire: false,
            gouraud: false,
            title: String::new(),
        }
    }
}

/// Parse `--view az,el` (degrees).
pub fn parse_view(s: &str) -> Result<(f64, f64)> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| {
            Error::Param(format!(
                "--view: '{s}' is not AZIMUTH,ELEVATION in degrees (e.g. 35,25)"
            ))
        })?;
    match v.as_slice() {
        [a, e] if a.is_finite() && (-90.0..=90.0).contains(e) => Ok((*a, *e)),
        [_, _] => Err(Error::Param(format!(
            "--view: elevation must be within [-90, 90] degrees, got '{s}'"
        ))),
        _ => Err(Error::Param(format!(
            "--view: '{s}' is not AZIMUTH,ELEVATION in degrees (e.g. 35,25)"
        ))),
    }
}

/// The mesh to render.
#[derive(Clone, Copy)]
pub enum Input<'a> {
    Surface(&'a TriMesh),
    Volume(&'a TetMesh),
}

/// What [`render`] drew.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Rendered {
    pub files: Vec<PathBuf>,
    pub faces: usize,
    /// Faces exposed by the cut.
    pub cut_faces: usize,
    /// Faces per certificate class (with `--color certificate`).
    pub classes: Vec<(String, usize)>,
    /// Range of the quality measure over the drawn faces (degrees).
    pub quality: Option<[f64; 2]>,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    if l > 0.0 {
        a.map(|x| x / l)
    } else {
        [0.0, 0.0, 1.0]
    }
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

const NO_CLAIM: palette::Rgb = palette::Rgb(190, 190, 190);

fn cert_colour(c: CertClass) -> palette::Rgb {
    match c {
        CertClass::Isotopic => tint(palette::BLUISH_GREEN, 0.25),
        CertClass::Uncertified => palette::VERMILLION,
        CertClass::NoClaim => NO_CLAIM,
    }
}

/// The longest title a rendered figure takes, in characters: one line above a column
/// figure holds about 60 at its font size; longer text belongs in the caption. (A
/// 100,000-character title took 20 s to lay out and draw.)
pub const MAX_TITLE_CHARS: usize = 200;

/// Render `input` to `base.<ext>` for each format.
pub fn render(
    base: &Path,
    input: Input,
    cert: Option<&Certificate>,
    o: &RenderOptions,
    formats: &[Format],
) -> Result<Rendered> {
    let n = o.title.chars().count();
    if n > MAX_TITLE_CHARS {
        return Err(Error::Param(format!(
            "render: the title has {n} characters, at most {MAX_TITLE_CHARS} (put longer text in the caption)"
        )));
    }
    let (faces, volume) = match input {
        Input::Surface(m) => (scene::tri_faces(m, o.cut), false),
        Input::Volume(m) => (scene::tet_faces(m, o.cut), true),
    };
    if faces.is_empty() {
        return Err(Error::Param(if o.cut.is_some() {
            "render: the cut removes every face (keep the other side: flip the inequality)".into()
        } else {
            "render: the mesh has no faces to draw".into()
        }));
    }
    let cert = match (o.color, cert) {
        (ColorBy::Certificate, None) => {
            return Err(Error::Param(
                "--color certificate needs the mesher's certificate: a mesh file carries none, so mesh and render in one step (--surface NAME --algo NAME)".into(),
            ))
        }
        (_, c) => c,
    };
    // The camera.
    let (az, el) = (o.azimuth.to_radians(), o.elevation.to_radians());
    let eye = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
    let up0 = if el.cos().abs() < 1e-6 {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    let right = unit(cross(up0, eye));
    let up = cross(eye, right);
    let view = |p: [f64; 3]| [dot(p, right), dot(p, up), dot(p, eye)];
    // Colours.
    let qmax = if volume { 70.528_779_365_509_3 } else { 60.0 };
    let mut counts: std::collections::BTreeMap<CertClass, usize> = Default::default();
    let colour = |f: &scene::Face,
                  counts: &mut std::collections::BTreeMap<CertClass, usize>|
     -> palette::Rgb {
        match o.color {
            ColorBy::Quality => viridis(f.quality / qmax),
            ColorBy::Certificate => {
                let c = cert
                    .map(|c| classify(c, &f.p))
                    .unwrap_or(CertClass::NoClaim);
                *counts.entry(c).or_default() += 1;
                cert_colour(c)
            }
            ColorBy::None => {
                if f.cut {
                    tint(palette::ORANGE, 0.35)
                } else {
                    palette::Rgb(200, 205, 215)
                }
            }
        }
    };
    // Normals: per face; Gouraud averages the faces at a vertex within 60° of this one.
    let fnorm: Vec<[f64; 3]> = faces
        .iter()
        .map(|f| {
            unit(cross(
                sub(view(f.p[1]), view(f.p[0])),
                sub(view(f.p[2]), view(f.p[0])),
            ))
        })
        .collect();
    let mut at: std::collections::HashMap<u32, Vec<usize>> = Default::default();
    if o.gouraud {
        for (i, f) in faces.iter().enumerate() {
            for v in f.v {
                at.entry(v).or_default().push(i);
            }
        }
    }
    let mut tris = Vec::with_capacity(faces.len());
    for (i, f) in faces.iter().enumerate() {
        let n = fnorm[i];
        let ns = f.v.map(|v| {
            if !o.gouraud {
                return n;
            }
            let mut s = [0.0; 3];
            for &j in at.get(&v).map(|x| x.as_slice()).unwrap_or(&[]) {
                // Orientation of the faces may differ: align with this face first.
                let m = if dot(fnorm[j], n) < 0.0 {
                    fnorm[j].map(|x| -x)
                } else {
                    fnorm[j]
                };
                if dot(m, n) > 0.5 {
                    s = [s[0] + m[0], s[1] + m[1], s[2] + m[2]];
                }
            }
            unit(s)
        });
        let c = colour(f, &mut counts);
        tris.push(raster::Tri {
            p: f.p.map(view),
            n: ns,
            rgb: [c.0, c.1, c.2],
        });
    }
    // Framing: the projected extent with a margin, aspect clamped.
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for t in &tris {
        for p in t.p {
            x0 = x0.min(p[0]);
            x1 = x1.max(p[0]);
            y0 = y0.min(p[1]);
            y1 = y1.max(p[1]);
        }
    }
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let (mut hw, mut hh) = (0.54 * (x1 - x0).max(1e-12), 0.54 * (y1 - y0).max(1e-12));
    let aspect = (hh / hw).clamp(0.45, 1.2);
    if hh / hw < aspect {
        hh = hw * aspect;
    } else {
        hw = hh / aspect;
    }
    let width = Width::Column;
    let w_units = width.units() as f64;
    let px_w = (width.inches() * output::PNG_DPI).round() as u32;
    let px_h = (px_w as f64 * aspect).round() as u32;
    let img = raster::render(
        &tris,
        (px_w, px_h),
        (cx - hw, cx + hw, cy - hh, cy + hh),
        2,
        if o.wire { 1.4 } else { 0.0 },
    );
    let png = output::encode_png(&img.rgba, img.w, img.h, output::PNG_DPI)?;
    // Composition.
    let fs = 7.5 * UNITS_PER_PT;
    let title_h = if o.title.is_empty() { 0.0 } else { fs * 1.9 };
    let img_h = w_units * aspect;
    let mut legend: Vec<(String, palette::Rgb)> = Vec::new();
    let qrange = faces
        .iter()
        .map(|f| f.quality)
        .fold([f64::INFINITY, f64::NEG_INFINITY], |a, q| {
            [a[0].min(q), a[1].max(q)]
        });
    let bar_label = if volume {
        "smallest dihedral angle of the tetrahedron (degrees)"
    } else {
        "smallest angle of the triangle (degrees)"
    };
    match o.color {
        ColorBy::Certificate => {
            for (c, n) in &counts {
                legend.push((format!("{} ({n} faces)", c.name()), cert_colour(*c)));
            }
        }
        ColorBy::None if faces.iter().any(|f| f.cut) => {
            legend.push(("boundary of the mesh".into(), palette::Rgb(200, 205, 215)));
            legend.push((
                "faces of the tetrahedra the cut exposes".into(),
                tint(palette::ORANGE, 0.35),
            ));
        }
        _ => {}
    }
    let bottom = match o.color {
        ColorBy::Quality => fs * 5.2,
        _ if legend.is_empty() => 0.0,
        _ => legend.len() as f64 * fs * 1.5 + fs * 0.8,
    };
    let total_h = title_h + img_h + bottom;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w_units}" height="{total_h:.1}" viewBox="0 0 {w_units} {total_h:.1}">"#
    );
    let _ = writeln!(
        s,
        r#"<rect x="0" y="0" width="{w_units}" height="{total_h:.1}" fill="white"/>"#
    );
    if !o.title.is_empty() {
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle" font-family="sans-serif" font-size="{:.1}">{}</text>"#,
            w_units / 2.0,
            fs * 1.3,
            8.5 * UNITS_PER_PT,
            xml(&o.title)
        );
    }
    let _ = writeln!(
        s,
        r#"<image x="0" y="{title_h:.1}" width="{w_units}" height="{img_h:.1}" preserveAspectRatio="none" href="data:image/png;base64,{}"/>"#,
        base64::engine::general_purpose::STANDARD.encode(&png)
    );
    let y = title_h + img_h;
    let meta_legend: Vec<String>;
    match o.color {
        ColorBy::Quality => {
            let (bx, bw, bh) = (w_units * 0.12, w_units * 0.76, fs * 0.9);
            let _ = writeln!(
                s,
                r#"<defs><linearGradient id="q" x1="0" x2="1" y1="0" y2="0">"#
            );
            for k in 0..=8 {
                let t = k as f64 / 8.0;
                let _ = writeln!(
                    s,
                    r#"<stop offset="{t}" stop-color="{}"/>"#,
                    hex(viridis(t))
                );
            }
            let _ = writeln!(s, "</linearGradient></defs>");
            let by = y + fs * 0.6;
            let _ = writeln!(
                s,
                r##"<rect x="{bx:.1}" y="{by:.1}" width="{bw:.1}" height="{bh:.1}" fill="url(#q)" stroke="#000" stroke-width="2"/>"##
            );
            let step = if volume { 10.0 } else { 10.0 };
            let mut t = 0.0;
            while t <= qmax + 1e-9 {
                let x = bx + bw * t / qmax;
                let _ = writeln!(
                    s,
                    r##"<line x1="{x:.1}" y1="{:.1}" x2="{x:.1}" y2="{:.1}" stroke="#000" stroke-width="2"/>"##,
                    by + bh,
                    by + bh + fs * 0.35
                );
                let _ = writeln!(
                    s,
                    r#"<text x="{x:.1}" y="{:.1}" text-anchor="middle" font-family="sans-serif" font-size="{fs}">{}</text>"#,
                    by + bh + fs * 1.35,
                    crate::figure::style::tick(t)
                );
                t += step;
            }
            let _ = writeln!(
                s,
                r#"<text x="{:.1}" y="{:.1}" text-anchor="middle" font-family="sans-serif" font-size="{fs}">{bar_label}</text>"#,
                w_units / 2.0,
                by + bh + fs * 2.75
            );
            meta_legend = vec![bar_label.to_string()];
        }
        _ => {
            for (i, (name, c)) in legend.iter().enumerate() {
                let ly = y + fs * 0.5 + i as f64 * fs * 1.5;
                let _ = writeln!(
                    s,
                    r##"<rect x="{:.1}" y="{ly:.1}" width="{:.1}" height="{:.1}" fill="{}" stroke="#000" stroke-width="1"/>"##,
                    w_units * 0.06,
                    fs * 2.0,
                    fs,
                    hex(*c)
                );
                let _ = writeln!(
                    s,
                    r#"<text x="{:.1}" y="{:.1}" font-family="sans-serif" font-size="{fs}">{}</text>"#,
                    w_units * 0.06 + fs * 2.6,
                    ly + fs * 0.85,
                    xml(name)
                );
            }
            meta_legend = legend.iter().map(|l| l.0.clone()).collect();
        }
    }
    s.push_str("</svg>\n");
    let meta = Meta {
        axes: None,
        series: meta_legend.len(),
        legend: meta_legend,
    };
    let files = output::write_svg(base, &s, width, &meta, formats)?;
    Ok(Rendered {
        files,
        faces: faces.len(),
        cut_faces: faces.iter().filter(|f| f.cut).count(),
        classes: counts
            .iter()
            .map(|(c, n)| (c.name().to_string(), *n))
            .collect(),
        quality: Some(qrange),
    })
}

fn xml(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
