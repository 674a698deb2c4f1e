//! CSV tables of a planar curve, with a header row.
//!
//! * [`CsvLayout::Vertices`] (the default for `.csv`): one row per vertex along each
//!   polyline of [`Curve2::polylines`], columns `polyline,closed,vertex,x,y` — the
//!   polyline's number (from 0), whether it is closed (`true`/`false`), the vertex's index
//!   in the curve, and its coordinates. A closed polyline repeats its first vertex as its
//!   last row, so plotting each polyline's rows in order draws it completely
//!   (e.g. pandas `groupby("polyline")`, gnuplot, spreadsheet charts). An isolated
//!   point of the curve (a vertex of no segment) is a polyline of one row, after the
//!   others.
//! * [`CsvLayout::Segments`]: one row per segment, columns `segment,v0,v1,x0,y0,x1,y1`.
//!
//! Coordinates are written in shortest round-trip form. [`read`] reads the vertex layout
//! back (consecutive rows of a polyline are its segments).
use super::text::{self, fmt_err, io_err, Lines};
use crate::error::Result;
use crate::mesh::Curve2;
use std::collections::HashMap;
use std::io::{BufRead, Write};

const FORMAT: &str = "CSV";
const VERTEX_HEADER: &str = "polyline,closed,vertex,x,y";

/// The row layout of a curve CSV file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CsvLayout {
    /// One row per polyline vertex: `polyline,closed,vertex,x,y`.
    Vertices,
    /// One row per segment: `segment,v0,v1,x0,y0,x1,y1`.
    Segments,
}

/// Write a curve as CSV.
pub fn write(mut w: impl Write, curve: &Curve2, layout: CsvLayout) -> Result<()> {
    super::check_vertices(&curve.vertices)?;
    super::check_cells(curve.vertices.len(), &curve.segments, "segment")?;
    match layout {
        CsvLayout::Vertices => {
            writeln!(w, "{VERTEX_HEADER}").map_err(io_err)?;
            let lines = curve.polylines();
            for (p, (chain, closed)) in lines.iter().enumerate() {
                for &i in chain {
                    let v = curve.vertices[i as usize];
                    writeln!(w, "{p},{closed},{i},{},{}", text::f(v[0]), text::f(v[1]))
                        .map_err(io_err)?;
                }
            }
            // Isolated points: a polyline of one row each (read back as a vertex of
            // no segment).
            for (k, i) in curve.isolated_vertices().into_iter().enumerate() {
                let v = curve.vertices[i as usize];
                let p = lines.len() + k;
                writeln!(w, "{p},false,{i},{},{}", text::f(v[0]), text::f(v[1])).map_err(io_err)?;
            }
        }
        CsvLayout::Segments => {
            writeln!(w, "segment,v0,v1,x0,y0,x1,y1").map_err(io_err)?;
            for (s, &[a, b]) in curve.segments.iter().enumerate() {
                let (p, q) = (curve.vertices[a as usize], curve.vertices[b as usize]);
                writeln!(
                    w,
                    "{s},{a},{b},{},{},{},{}",
                    text::f(p[0]),
                    text::f(p[1]),
                    text::f(q[0]),
                    text::f(q[1])
                )
                .map_err(io_err)?;
            }
        }
    }
    w.flush().map_err(io_err)
}

/// Read a curve written with [`CsvLayout::Vertices`]. Vertices are numbered by first
/// appearance (the file's `vertex` column identifies them; the same index must always
/// carry the same coordinates).
pub fn read(r: impl BufRead) -> Result<Curve2> {
    let data = super::slurp(r)?;
    parse(&data)
}

/// Parse the vertex layout held in memory.
pub fn parse(data: &[u8]) -> Result<Curve2> {
    let mut lines = Lines::new(FORMAT, data);
    let (n, h) = lines.expect_content(None, "the header")?;
    if h != VERTEX_HEADER {
        return Err(fmt_err(
            FORMAT,
            n,
            format!("expected the header '{VERTEX_HEADER}'"),
        ));
    }
    let mut c = Curve2::default();
    let mut ids: HashMap<u64, u32> = HashMap::new();
    let mut prev: Option<(u64, u32)> = None;
    while let Some((n, l)) = lines.next_content(None)? {
        let f: Vec<&str> = l.split(',').map(str::trim).collect();
        if f.len() != 5 {
            return Err(fmt_err(
                FORMAT,
                n,
                format!("expected 5 fields, found {}", f.len()),
            ));
        }
        let poly = text::parse_usize(FORMAT, n, f[0], "a polyline number")? as u64;
        if f[1] != "true" && f[1] != "false" {
            return Err(fmt_err(
                FORMAT,
                n,
                "the 'closed' field must be true or false",
            ));
        }
        let id = text::parse_usize(FORMAT, n, f[2], "a vertex index")? as u64;
        let p = [
            text::parse_coord(FORMAT, n, f[3])?,
            text::parse_coord(FORMAT, n, f[4])?,
        ];
        let next = c.vertices.len() as u32;
        let v = *ids.entry(id).or_insert(next);
        if v == next {
            c.vertices.push(p);
        } else if c.vertices[v as usize] != p {
            return Err(fmt_err(
                FORMAT,
                n,
                format!("vertex {id} appears with different coordinates"),
            ));
        }
        if let Some((q, u)) = prev {
            if q == poly {
                c.segments.push([u, v]);
            }
        }
        prev = Some((poly, v));
    }
    Ok(c)
}
