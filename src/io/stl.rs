//! STL, ascii (`solid` / `facet normal` / `outer loop` / `vertex` ...) and binary
//! (80-byte header, `u32` triangle count, 50 bytes per triangle, little-endian `f32`).
//!
//! STL is a triangle soup: the reader merges vertices whose coordinates are exactly equal
//! (`-0.0` equals `0.0`), numbering them by first appearance, so that topology can be
//! computed. Stored normals are ignored (orientation comes from the vertex order);
//! written normals are the unit normals of the triangles (zero for degenerate ones).
//!
//! Binary is detected by its size (`84 + 50 n` bytes for the count `n` in the header);
//! otherwise a file starting with `solid` is ascii. The binary writer stores `f32`:
//! coordinates are rounded to the nearest `f32` (exact round trip only for `f32`-valued
//! meshes) and must fit its range. The ascii writer prints full `f64` precision. Both lose
//! vertices that no triangle uses.
use super::text::{self, fmt_err, io_err, Lines};
use crate::error::{Error, Result};
use crate::kernel::geom::{cross, norm, scale, sub};
use crate::mesh::TriMesh;
use std::collections::HashMap;
use std::io::{BufRead, Write};

const FORMAT: &str = "STL";

/// Ascii or binary STL.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StlEncoding {
    Ascii,
    Binary,
}

/// Read an STL file (ascii or binary, detected).
pub fn read(r: impl BufRead) -> Result<TriMesh> {
    let data = super::slurp(r)?;
    parse(&data)
}

/// Is this STL data binary? (`84 + 50 n` bytes, or not starting with `solid`.)
pub fn is_binary(data: &[u8]) -> bool {
    if data.len() >= 84 {
        let n = u32::from_le_bytes([data[80], data[81], data[82], data[83]]) as u64;
        if 84 + 50 * n == data.len() as u64 {
            return true;
        }
    }
    let start = data
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(data.len());
    !data[start..].starts_with(b"solid")
}

/// Parse an STL file held in memory.
pub fn parse(data: &[u8]) -> Result<TriMesh> {
    if is_binary(data) {
        parse_binary(data)
    } else {
        parse_ascii(data)
    }
}

/// Merges exactly equal vertex coordinates.
#[derive(Default)]
struct Welder {
    mesh: TriMesh,
    index: HashMap<[u64; 3], u32>,
}

impl Welder {
    fn vertex(&mut self, p: [f64; 3]) -> u32 {
        // `+ 0.0` turns -0.0 into 0.0 so that both weld together.
        let key = p.map(|c| (c + 0.0).to_bits());
        let n = self.mesh.vertices.len() as u32;
        *self.index.entry(key).or_insert_with(|| {
            self.mesh.vertices.push(p);
            n
        })
    }
}

fn parse_binary(data: &[u8]) -> Result<TriMesh> {
    if data.len() < 84 {
        return Err(fmt_err(
            FORMAT,
            0,
            format!(
                "binary STL needs at least 84 bytes (header and count), found {}",
                data.len()
            ),
        ));
    }
    let n = u32::from_le_bytes([data[80], data[81], data[82], data[83]]) as u64;
    let need = 84 + 50 * n;
    if need != data.len() as u64 {
        let at = if (data.len() as u64) < need {
            84 + 50 * ((data.len() as u64 - 84) / 50)
        } else {
            need
        };
        return Err(fmt_err(
            FORMAT,
            0,
            format!(
                "binary STL declares {n} triangles ({need} bytes) but has {} bytes (at byte offset {at})",
                data.len()
            ),
        ));
    }
    let mut w = Welder::default();
    w.mesh.triangles.reserve(n as usize);
    for (t, rec) in data[84..].chunks_exact(50).enumerate() {
        let mut tri = [0u32; 3];
        for (k, v) in tri.iter_mut().enumerate() {
            let mut p = [0.0f64; 3];
            for (c, x) in p.iter_mut().enumerate() {
                let o = 12 + 12 * k + 4 * c;
                let f = f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]);
                if !f.is_finite() {
                    return Err(fmt_err(
                        FORMAT,
                        0,
                        format!(
                            "coordinate {f} is not finite (triangle {t}, at byte offset {})",
                            84 + 50 * t + o
                        ),
                    ));
                }
                *x = f as f64;
            }
            *v = w.vertex(p);
        }
        w.mesh.triangles.push(tri);
    }
    Ok(w.mesh)
}

fn parse_ascii(data: &[u8]) -> Result<TriMesh> {
    let mut lines = Lines::new(FORMAT, data);
    let mut w = Welder::default();
    let mut poly: Vec<u32> = Vec::new();
    // States: outside a solid, in a solid, in a facet, in its loop.
    #[derive(PartialEq)]
    enum S {
        Out,
        Solid,
        Facet,
        Loop,
        LoopDone,
    }
    let mut s = S::Out;
    let mut last = 0;
    while let Some((n, l)) = lines.next_content(None)? {
        last = n;
        let mut t = l.split_ascii_whitespace();
        let key = t.next().unwrap_or("");
        let bad = |what: &str| {
            fmt_err(
                FORMAT,
                n,
                format!("expected {what}, found '{}'", text::clip(key)),
            )
        };
        match (&s, key) {
            (S::Out, "solid") => s = S::Solid,
            (S::Out, _) => return Err(bad("'solid'")),
            (S::Solid, "facet") => s = S::Facet,
            (S::Solid, "endsolid") => s = S::Out,
            (S::Solid, _) => return Err(bad("'facet' or 'endsolid'")),
            (S::Facet, "outer") => {
                poly.clear();
                s = S::Loop
            }
            (S::Facet, _) => return Err(bad("'outer loop'")),
            (S::Loop, "vertex") => {
                let mut p = [0.0; 3];
                for c in &mut p {
                    let tok = t
                        .next()
                        .ok_or_else(|| fmt_err(FORMAT, n, "a vertex needs three coordinates"))?;
                    *c = text::parse_coord(FORMAT, n, tok)?;
                }
                poly.push(w.vertex(p));
            }
            (S::Loop, "endloop") => {
                if poly.len() < 3 {
                    return Err(fmt_err(
                        FORMAT,
                        n,
                        format!("a facet needs at least 3 vertices, found {}", poly.len()),
                    ));
                }
                for k in 1..poly.len() - 1 {
                    w.mesh.triangles.push([poly[0], poly[k], poly[k + 1]]);
                }
                s = S::LoopDone
            }
            (S::Loop, _) => return Err(bad("'vertex' or 'endloop'")),
            (S::LoopDone, "endfacet") => s = S::Solid,
            (S::LoopDone, _) => return Err(bad("'endfacet'")),
        }
    }
    match s {
        S::Out => Ok(w.mesh),
        _ => Err(fmt_err(
            FORMAT,
            last + 1,
            "unexpected end of file inside a solid (missing 'endsolid')",
        )),
    }
}

/// The unit normal of a triangle, or zero when it is degenerate.
fn normal(c: [[f64; 3]; 3]) -> [f64; 3] {
    let n = cross(sub(c[1], c[0]), sub(c[2], c[0]));
    let l = norm(n);
    if l > 0.0 && l.is_finite() {
        scale(n, 1.0 / l)
    } else {
        [0.0; 3]
    }
}

/// Write an STL file.
pub fn write(mut w: impl Write, mesh: &TriMesh, encoding: StlEncoding) -> Result<()> {
    super::check_tri(mesh)?;
    match encoding {
        StlEncoding::Ascii => {
            let mut o = text::TextOut::new(&mut w);
            o.s("solid certmesh").nl()?;
            for t in 0..mesh.triangles.len() {
                let c = mesh.corners(t);
                o.s("facet normal ")
                    .fs(&normal(c))
                    .s("\n outer loop")
                    .nl()?;
                for p in c {
                    o.s("  vertex ").fs(&p).nl()?;
                }
                o.s(" endloop\nendfacet").nl()?;
            }
            o.s("endsolid certmesh").nl()?;
            o.finish()?;
        }
        StlEncoding::Binary => {
            let n = u32::try_from(mesh.triangles.len()).map_err(|_| {
                Error::TooLarge(format!(
                    "binary STL holds at most {} triangles, the mesh has {}",
                    u32::MAX,
                    mesh.triangles.len()
                ))
            })?;
            if let Some((i, v)) = mesh
                .vertices
                .iter()
                .enumerate()
                .find(|(_, v)| v.iter().any(|&c| !(c as f32).is_finite()))
            {
                return Err(Error::Param(format!(
                    "vertex {i} {v:?} is outside the float32 range of binary STL"
                )));
            }
            // The header must not start with "solid" (readers would take it for ascii).
            let mut header = [b' '; 80];
            let tag = b"certmesh binary STL";
            header[..tag.len()].copy_from_slice(tag);
            w.write_all(&header).map_err(io_err)?;
            w.write_all(&n.to_le_bytes()).map_err(io_err)?;
            let mut rec = [0u8; 50];
            for t in 0..mesh.triangles.len() {
                let c = mesh.corners(t);
                let vals = std::iter::once(normal(c)).chain(c);
                for (k, p) in vals.enumerate() {
                    for (j, x) in p.iter().enumerate() {
                        let o = 12 * k + 4 * j;
                        rec[o..o + 4].copy_from_slice(&(*x as f32).to_le_bytes());
                    }
                }
                w.write_all(&rec).map_err(io_err)?;
            }
        }
    }
    w.flush().map_err(io_err)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> TriMesh {
        TriMesh::new(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, -0.5],
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    #[test]
    fn welds_shared_vertices_in_both_encodings() {
        for enc in [StlEncoding::Ascii, StlEncoding::Binary] {
            let mut buf = Vec::new();
            write(&mut buf, &quad(), enc).unwrap();
            assert_eq!(is_binary(&buf), enc == StlEncoding::Binary);
            let m = parse(&buf).unwrap();
            assert_eq!(m, quad(), "{enc:?}");
        }
    }

    #[test]
    fn malformed_input_is_located() {
        let e = parse(
            b"solid x\nfacet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n endloop\n",
        )
        .unwrap_err();
        assert!(matches!(e, Error::Format { line: 6, .. }), "{e:?}");
        let e = parse(b"solid x\nfacet normal 0 0 1\n outer loop\n vertex 0 0\n").unwrap_err();
        assert!(matches!(e, Error::Format { line: 4, .. }), "{e:?}");
        let e = parse(b"solid x\n").unwrap_err();
        assert!(matches!(e, Error::Format { line: 2, .. }), "{e:?}");
        assert!(e.to_string().starts_with("STL file, line 2: "), "{e}");
        // Truncated binary: line 0 and the byte offset.
        let mut buf = Vec::new();
        write(&mut buf, &quad(), StlEncoding::Binary).unwrap();
        buf.truncate(buf.len() - 7);
        match parse(&buf).unwrap_err() {
            ref e @ Error::Format {
                line: 0,
                ref message,
                ..
            } => {
                assert!(message.contains("offset 134"), "{message}");
                // Binary data has no lines: the text names the offset, not "line 0".
                let text = e.to_string();
                assert!(
                    text.starts_with("STL file: ") && !text.contains("line"),
                    "{text}"
                );
            }
            e => panic!("{e:?}"),
        }
    }
}
