//! SVG drawing of a planar curve: one `<polyline>` per open chain and one `<polygon>`
//! per closed chain (from [`Curve2::polylines`]), black, unfilled, and a filled dot per
//! isolated point ([`Curve2::isolated_vertices`]).
//!
//! The `viewBox` is the bounding box of the vertices with a 2% margin, and y is flipped
//! (points are written as `(x, -y)`) so that up is up, as in the curve's own coordinates.
//! Coordinates are written in full (shortest round-trip) precision; the stroke is 1.5 px
//! whatever the scale (`vector-effect="non-scaling-stroke"`); the larger side of the
//! picture is 800 px.
use super::text::{self, io_err};
use crate::error::{Error, Result};
use crate::mesh::Curve2;
use std::io::Write;

/// Write a curve as an SVG picture.
pub fn write(mut w: impl Write, curve: &Curve2) -> Result<()> {
    super::check_vertices(&curve.vertices)?;
    super::check_cells(curve.vertices.len(), &curve.segments, "segment")?;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for v in &curve.vertices {
        for k in 0..2 {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    if curve.vertices.is_empty() {
        (lo, hi) = ([0.0; 2], [1.0; 2]);
    }
    let (mut wd, mut ht) = (hi[0] - lo[0], hi[1] - lo[1]);
    // A degenerate (point or segment) picture still needs a positive size.
    let unit = wd.max(ht);
    let unit = if unit > 0.0 && unit.is_finite() {
        unit
    } else {
        1.0
    };
    let m = 0.02 * unit;
    let (x0, y0) = (lo[0] - m, -hi[1] - m);
    wd = wd.max(0.0) + 2.0 * m;
    ht = ht.max(0.0) + 2.0 * m;
    if ![x0, y0, wd, ht].iter().all(|v| v.is_finite()) {
        return Err(Error::Param(format!(
            "the curve's extent [{}, {}] x [{}, {}] overflows a double: cannot make an SVG viewBox",
            lo[0], hi[0], lo[1], hi[1]
        )));
    }
    let (pw, ph) = if wd >= ht {
        (800.0, (800.0 * ht / wd).max(1.0))
    } else {
        ((800.0 * wd / ht).max(1.0), 800.0)
    };
    writeln!(
        w,
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{pw:.0}\" height=\"{ph:.0}\" \
         viewBox=\"{} {} {} {}\">\n\
         <!-- certmesh: {} vertices, {} segments; y is flipped (points are (x, -y)) -->\n\
         <g fill=\"none\" stroke=\"black\" stroke-width=\"1.5\" stroke-linejoin=\"round\" \
         stroke-linecap=\"round\">",
        text::f(x0),
        text::f(y0),
        text::f(wd),
        text::f(ht),
        curve.vertices.len(),
        curve.segments.len()
    )
    .map_err(io_err)?;
    for (chain, closed) in curve.polylines() {
        // A closed chain repeats its first vertex at the end: a polygon closes itself.
        let pts = if closed {
            &chain[..chain.len() - 1]
        } else {
            &chain[..]
        };
        let tag = if closed { "polygon" } else { "polyline" };
        write!(w, "<{tag} vector-effect=\"non-scaling-stroke\" points=\"").map_err(io_err)?;
        for (k, &i) in pts.iter().enumerate() {
            let p = curve.vertices[i as usize];
            let sep = if k == 0 { "" } else { " " };
            write!(w, "{sep}{},{}", text::f(p[0]), text::f(-p[1])).map_err(io_err)?;
        }
        writeln!(w, "\"/>").map_err(io_err)?;
    }
    // Isolated points: filled dots of radius 0.5 % of the picture's larger side.
    for i in curve.isolated_vertices() {
        let p = curve.vertices[i as usize];
        writeln!(
            w,
            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"black\" stroke=\"none\"/>",
            text::f(p[0]),
            text::f(-p[1]),
            text::f(0.005 * unit)
        )
        .map_err(io_err)?;
    }
    writeln!(w, "</g>\n</svg>").map_err(io_err)?;
    w.flush().map_err(io_err)
}
