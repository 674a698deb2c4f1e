//! Wavefront OBJ: `v x y z` vertices and `f` faces.
//!
//! Reading: face corners may be `i`, `i/t`, `i/t/n` or `i//n` (texture and normal
//! indices are ignored), indices are 1-based and negative indices count back from the
//! last vertex defined so far (`-1` is the latest); positive indices may refer to vertices
//! defined later in the file. Polygons are fan-triangulated
//! (`a b c d` -> `a b c`, `a c d`), which is exact for the convex planar faces exporters
//! write. Other statements (`vt vn vp g o s usemtl mtllib l p`, comments) are ignored.
//! Extra vertex values (a `w` weight or per-vertex colours) are ignored. Vertices no face
//! uses are kept (the Stanford bunny has some).
use super::text::{self, fmt_err, io_err, Lines};
use crate::error::Result;
use crate::mesh::TriMesh;
use std::io::{BufRead, Write};

const FORMAT: &str = "OBJ";

/// Read an OBJ triangle mesh.
pub fn read(r: impl BufRead) -> Result<TriMesh> {
    let data = super::slurp(r)?;
    parse(&data)
}

/// Parse an OBJ triangle mesh held in memory.
pub fn parse(data: &[u8]) -> Result<TriMesh> {
    let mut lines = Lines::new(FORMAT, data);
    let mut mesh = TriMesh::default();
    let mut poly: Vec<u32> = Vec::new();
    // Corners referring to vertices not yet defined: (line, 0-based index).
    let mut forward: Vec<(usize, u32)> = Vec::new();
    while let Some((n, line)) = lines.next_content(Some(b'#'))? {
        let mut toks = line.split_ascii_whitespace();
        match toks.next() {
            Some("v") => {
                let mut p = [0.0; 3];
                for c in &mut p {
                    let t = toks.next().ok_or_else(|| {
                        fmt_err(FORMAT, n, "a vertex needs three coordinates 'v x y z'")
                    })?;
                    *c = text::parse_coord(FORMAT, n, t)?;
                }
                mesh.vertices.push(p);
            }
            Some("f") => {
                poly.clear();
                for t in toks {
                    let i = corner(n, t, mesh.vertices.len())?;
                    if i as usize >= mesh.vertices.len() {
                        forward.push((n, i));
                    }
                    poly.push(i);
                }
                if poly.len() < 3 {
                    return Err(fmt_err(
                        FORMAT,
                        n,
                        format!("a face needs at least 3 vertices, found {}", poly.len()),
                    ));
                }
                for k in 1..poly.len() - 1 {
                    mesh.triangles.push([poly[0], poly[k], poly[k + 1]]);
                }
            }
            _ => {}
        }
    }
    let nv = mesh.vertices.len();
    if let Some(&(n, i)) = forward.iter().find(|(_, i)| *i as usize >= nv) {
        return Err(fmt_err(
            FORMAT,
            n,
            format!(
                "vertex index {} out of range: the file has {nv} vertices",
                i as u64 + 1
            ),
        ));
    }
    Ok(mesh)
}

/// The 0-based vertex index of a face corner `i[/t[/n]]` when `nv` vertices are defined
/// so far.
fn corner(line: usize, tok: &str, nv: usize) -> Result<u32> {
    let head = tok.split('/').next().unwrap_or("");
    let i: i64 = head.parse().map_err(|_| {
        fmt_err(
            FORMAT,
            line,
            format!("expected a vertex index, found '{}'", text::clip(tok)),
        )
    })?;
    let zero_based = if i > 0 {
        (i - 1) as u64 as usize
    } else if i < 0 {
        // -1 is the last vertex defined so far.
        match usize::try_from(i.unsigned_abs()) {
            Ok(back) if back <= nv => nv - back,
            _ => {
                return Err(fmt_err(
                    FORMAT,
                    line,
                    format!(
                        "relative vertex index {i} reaches before the first vertex ({nv} defined)"
                    ),
                ))
            }
        }
    } else {
        return Err(fmt_err(
            FORMAT,
            line,
            "vertex index 0 (OBJ indices start at 1)",
        ));
    };
    // A positive index may refer to a vertex defined later in the file (checked at the
    // end, against the final count).
    u32::try_from(zero_based).map_err(|_| {
        fmt_err(
            FORMAT,
            line,
            format!("vertex index {i} exceeds the 32-bit index range"),
        )
    })
}

/// Write an OBJ file: `v` lines (shortest round-trip floats), then 1-based `f` lines.
pub fn write(mut w: impl Write, mesh: &TriMesh) -> Result<()> {
    super::check_tri(mesh)?;
    writeln!(
        w,
        "# certmesh: {} vertices, {} triangles",
        mesh.vertices.len(),
        mesh.triangles.len()
    )
    .map_err(io_err)?;
    let mut o = text::TextOut::new(&mut w);
    for v in &mesh.vertices {
        o.s("v ").fs(v).nl()?;
    }
    for t in &mesh.triangles {
        o.s("f ").ints(&t.map(|i| i as u64 + 1)).nl()?;
    }
    o.finish()?;
    w.flush().map_err(io_err)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;

    fn line_of(e: Error) -> usize {
        match e {
            Error::Format { format, line, .. } => {
                assert_eq!(format, FORMAT);
                line
            }
            e => panic!("expected a format error, got {e:?}"),
        }
    }

    #[test]
    fn corner_forms_negative_indices_and_fans() {
        let src = "# c\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ng x\nusemtl m\nvt 0 0\nvn 0 0 1\n\
                   f 1/1/1 2//1 3/1 -1\n";
        let m = parse(src.as_bytes()).unwrap();
        assert_eq!(m.vertices.len(), 4);
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        // Forward references are resolved at the end of the file.
        let m = parse(b"f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        assert_eq!(
            line_of(parse(b"v 0 0 0\nf 1 2 3\nf 1 2 9\nv 1 0 0\nv 0 1 0\n").unwrap_err()),
            3
        );
    }

    #[test]
    fn malformed_lines_are_located() {
        let cases: [(&str, usize); 7] = [
            ("v 0 0 0\nv 1 0\n", 2),
            ("v 0 0 0\nv 1 0 nan\n", 2),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", 5),
            ("v 0 0 0\nf 0 1 1\n", 2),
            ("v 0 0 0\nf -2 1 1\n", 2),
            ("v 0 0 0\nv 1 0 0\nf 1 2\n", 3),
            ("v 0 0 0\nf 1 x 1\n", 2),
        ];
        for (src, line) in cases {
            let e = parse(src.as_bytes()).unwrap_err();
            assert_eq!(line_of(e), line, "{src:?}");
        }
        assert_eq!(line_of(parse(b"v 0 0 0\r\nv 1 \xff 0\n").unwrap_err()), 2);
        // Invalid UTF-8 bytes inside a comment are fine.
        assert!(parse(b"# caf\xe9\nv 0 0 0\n").is_ok());
    }
}
