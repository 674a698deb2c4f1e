//! MEDIT / INRIA Gamma ASCII `.mesh` (read by Medit, mmg, TetGen, Gmsh, meshio):
//! `MeshVersionFormatted 2`, `Dimension 3`, then sections `Vertices` (`x y z ref`),
//! `Triangles` (`a b c ref`), `Tetrahedra` (`a b c d ref`) with 1-based indices, `End`.
//!
//! Reading: keywords and numbers are free-format tokens, `#` starts a comment; the
//! sections `Edges Quadrilaterals Corners Ridges Required* Normals Tangents
//! NormalAtVertices TangentAtVertices` are skipped, but `Hexahedra` and `Prisms` are an
//! error (dropping volume cells would silently change the mesh). Only `Dimension 3`.
//! Writing: references are 0; [`write()`] adds the boundary triangles of the tetrahedra
//! (outward, in the tetrahedral mesh's own vertex numbering) when asked.
use super::text::{self, fmt_err, io_err, Lines, Tokens};
use super::CellFile;
use crate::error::Result;
use crate::mesh::{TetMesh, TriMesh};
use std::io::{BufRead, Write};

const FORMAT: &str = "MEDIT";

/// Read a `.mesh` file.
pub fn read(r: impl BufRead) -> Result<CellFile> {
    let data = super::slurp(r)?;
    parse(&data)
}

/// Parse a `.mesh` file held in memory.
pub fn parse(data: &[u8]) -> Result<CellFile> {
    let mut t = Tokens::new(Lines::new(FORMAT, data), Some(b'#'));
    let mut out = CellFile::default();
    let mut have_vertices = false;
    while let Some((n, key)) = t.next()? {
        // Sections skipped with their number of values per item.
        let skip = match key {
            "End" => break,
            "MeshVersionFormatted" => {
                let (l, v) = t.usize("a version")?;
                if !(1..=4).contains(&v) {
                    return Err(fmt_err(FORMAT, l, format!("unknown version {v}")));
                }
                continue;
            }
            "Dimension" => {
                let (l, d) = t.usize("a dimension")?;
                if d != 3 {
                    return Err(fmt_err(
                        FORMAT,
                        l,
                        format!("only Dimension 3 is supported, found {d}"),
                    ));
                }
                continue;
            }
            "Vertices" => {
                let (_, nv) = t.usize("a vertex count")?;
                if have_vertices {
                    return Err(fmt_err(FORMAT, n, "a second Vertices section"));
                }
                have_vertices = true;
                let v = &mut out.mesh.vertices;
                v.reserve(text::capacity(nv, t.remaining(), 8));
                for _ in 0..nv {
                    v.push([t.coord()?, t.coord()?, t.coord()?]);
                    reference(&mut t)?;
                }
                continue;
            }
            "Triangles" => {
                let cells = cells::<3>(&mut t, n, have_vertices, out.mesh.vertices.len())?;
                out.triangles.extend(cells);
                continue;
            }
            "Tetrahedra" => {
                let cells = cells::<4>(&mut t, n, have_vertices, out.mesh.vertices.len())?;
                out.mesh.tets.extend(cells);
                continue;
            }
            "Corners" | "Ridges" | "RequiredVertices" | "RequiredEdges" | "RequiredTriangles"
            | "RequiredTetrahedra" => 1,
            "NormalAtVertices" | "TangentAtVertices" => 2,
            "Edges" | "Normals" | "Tangents" => 3,
            "Quadrilaterals" => 5,
            "Hexahedra" | "Prisms" => {
                return Err(fmt_err(
                    FORMAT,
                    n,
                    format!("{key} are not supported (only tetrahedra)"),
                ))
            }
            _ => {
                return Err(fmt_err(
                    FORMAT,
                    n,
                    format!("unknown keyword '{}'", text::clip(key)),
                ))
            }
        };
        let (_, count) = t.usize("an item count")?;
        for _ in 0..count.saturating_mul(skip) {
            t.expect("a value")?;
        }
    }
    Ok(out)
}

/// The reference number ending an item (an integer, ignored).
fn reference(t: &mut Tokens) -> Result<()> {
    let (l, r) = t.expect("a reference number")?;
    r.parse::<i64>().map(|_| ()).map_err(|_| {
        fmt_err(
            FORMAT,
            l,
            format!("expected a reference number, found '{}'", text::clip(r)),
        )
    })
}

fn cells<const K: usize>(
    t: &mut Tokens,
    line: usize,
    have_vertices: bool,
    nv: usize,
) -> Result<Vec<[u32; K]>> {
    if !have_vertices {
        return Err(fmt_err(FORMAT, line, "cells before the Vertices section"));
    }
    let (_, m) = t.usize("a cell count")?;
    let mut out = Vec::with_capacity(text::capacity(m, t.remaining(), 2 * (K + 1)));
    for _ in 0..m {
        let mut c = [0u32; K];
        for x in &mut c {
            let (l, i) = t.usize("a vertex index")?;
            if i == 0 {
                return Err(fmt_err(FORMAT, l, "vertex index 0 (indices start at 1)"));
            }
            *x = text::index(FORMAT, l, i - 1, nv)?;
        }
        reference(t)?;
        out.push(c);
    }
    Ok(out)
}

/// The boundary faces of a tetrahedral mesh (faces in exactly one tetrahedron, oriented
/// outward), in its own vertex numbering, sorted: [`TetMesh::boundary_faces`].
pub fn boundary_faces(mesh: &TetMesh) -> Vec<[u32; 3]> {
    mesh.boundary_faces()
}

fn write_parts(
    w: &mut impl Write,
    vertices: &[[f64; 3]],
    tris: &[[u32; 3]],
    tets: &[[u32; 4]],
) -> Result<()> {
    writeln!(
        w,
        "MeshVersionFormatted 2\nDimension 3\n\nVertices\n{}",
        vertices.len()
    )
    .map_err(io_err)?;
    let mut o = text::TextOut::new(&mut *w);
    for v in vertices {
        o.fs(v).s(" 0").nl()?;
    }
    if !tris.is_empty() {
        o.s("\nTriangles\n").int(tris.len()).nl()?;
        for t in tris {
            o.ints(&t.map(|i| i as u64 + 1)).s(" 0").nl()?;
        }
    }
    if !tets.is_empty() {
        o.s("\nTetrahedra\n").int(tets.len()).nl()?;
        for t in tets {
            o.ints(&t.map(|i| i as u64 + 1)).s(" 0").nl()?;
        }
    }
    o.s("\nEnd").nl()?;
    o.finish()?;
    w.flush().map_err(io_err)
}

/// Write a tetrahedral mesh, with its boundary triangles if `with_boundary`.
pub fn write(mut w: impl Write, mesh: &TetMesh, with_boundary: bool) -> Result<()> {
    super::check_tet(mesh)?;
    let tris = if with_boundary {
        boundary_faces(mesh)
    } else {
        Vec::new()
    };
    write_parts(&mut w, &mesh.vertices, &tris, &mesh.tets)
}

/// Write a triangle mesh as a surface `.mesh` file (Vertices and Triangles).
pub fn write_surface(mut w: impl Write, mesh: &TriMesh) -> Result<()> {
    super::check_tri(mesh)?;
    write_parts(&mut w, &mesh.vertices, &mesh.triangles, &[])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;

    fn tet() -> TetMesh {
        TetMesh {
            vertices: vec![
                [0.0; 3],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
            ],
            tets: vec![[0, 1, 2, 3], [1, 4, 2, 3]],
        }
    }

    #[test]
    fn round_trip_with_boundary() {
        let mut buf = Vec::new();
        write(&mut buf, &tet(), true).unwrap();
        let m = parse(&buf).unwrap();
        assert_eq!(m.mesh, tet());
        // Two tetrahedra sharing a face: 8 - 2 boundary faces, matching TetMesh::boundary.
        assert_eq!(m.triangles.len(), 6);
        let corners = |m: &TriMesh| {
            let mut c: Vec<_> = (0..m.triangles.len()).map(|t| m.corners(t)).collect();
            c.sort_by(|a, b| a.partial_cmp(b).unwrap());
            c
        };
        assert_eq!(corners(&m.surface()), corners(&tet().boundary()));
    }

    #[test]
    fn malformed_input_is_located() {
        let v = "MeshVersionFormatted 2\nDimension 3\nVertices\n2\n0 0 0 0\n1 0 0 0\n";
        let cases: Vec<(String, usize)> = vec![
            ("MeshVersionFormatted 2\nDimension 2\n".into(), 2),
            (format!("{v}Tetrahedra 1\n1 2 3 4 0\n"), 8),
            (format!("{v}Triangles 1\n1 2 0 0\n"), 8),
            (format!("{v}Hexahedra 0\n"), 7),
            (format!("{v}Bogus 0\n"), 7),
            ("Tetrahedra 1\n1 2 3 4 0\n".into(), 1),
            ("Vertices\n2\n0 0 0 0\n1 0 # comment\n".into(), 5),
            ("Vertices\n1\n0 0 1e999 0\n".into(), 3),
        ];
        for (src, line) in cases {
            match parse(src.as_bytes()) {
                Err(Error::Format {
                    format: "MEDIT",
                    line: l,
                    ..
                }) => assert_eq!(l, line, "{src:?}"),
                r => panic!("{src:?}: expected a format error, got {r:?}"),
            }
        }
    }
}
