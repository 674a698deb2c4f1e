//! Legacy VTK, ASCII `UNSTRUCTURED_GRID` of linear tetrahedra (cell type 10) and
//! triangles (cell type 5), which ParaView and meshio read. VTK's tetrahedron orientation (points 0 1 2 counter-clockwise
//! seen from point 3) is certmesh's positive volume, so cells are written unchanged.
//!
//! Reading accepts the classic `CELLS m size` layout (`4 a b c d` per cell) and the 5.1
//! layout (`OFFSETS` / `CONNECTIVITY` arrays). Triangles are kept ([`parse_cells`]);
//! other lower-dimensional cells (vertices, lines, quads, ...) are skipped; other volume cells (hexahedra, wedges, quadratic
//! tetrahedra, ...) are an error rather than being dropped silently. Sections after
//! `CELL_TYPES` (point and cell data) are ignored. BINARY files are not supported.
use super::text::{self, fmt_err, io_err, Lines, Tokens};
use super::CellFile;
use crate::error::Result;
use crate::mesh::{TetMesh, TriMesh};
use std::io::{BufRead, Write};

const FORMAT: &str = "VTK";
const TETRA: usize = 10;
const TRIANGLE: usize = 5;

/// Read a legacy VTK tetrahedral mesh (its triangles are dropped).
pub fn read(r: impl BufRead) -> Result<TetMesh> {
    read_cells(r).map(|c| c.mesh)
}

/// Parse a legacy VTK tetrahedral mesh held in memory (its triangles are dropped).
pub fn parse(data: &[u8]) -> Result<TetMesh> {
    parse_cells(data).map(|c| c.mesh)
}

/// Read a legacy VTK file's tetrahedra and triangles.
pub fn read_cells(r: impl BufRead) -> Result<CellFile> {
    let data = super::slurp(r)?;
    parse_cells(&data)
}

/// Parse a legacy VTK file's tetrahedra and triangles held in memory.
pub fn parse_cells(data: &[u8]) -> Result<CellFile> {
    let mut lines = Lines::new(FORMAT, data);
    let (n, l) = lines
        .next_raw()
        .ok_or_else(|| fmt_err(FORMAT, 1, "empty file: expected '# vtk DataFile Version'"))?;
    if !text::to_str(FORMAT, n, l)?.starts_with("# vtk DataFile") {
        return Err(fmt_err(FORMAT, n, "expected '# vtk DataFile Version x.y'"));
    }
    // The title line may hold anything.
    lines
        .next_raw()
        .ok_or_else(|| fmt_err(FORMAT, 2, "unexpected end of file: expected a title line"))?;
    let (n, l) = lines.expect_content(None, "ASCII")?;
    if l != "ASCII" {
        return Err(fmt_err(
            FORMAT,
            n,
            format!(
                "expected 'ASCII' (BINARY files are not supported), found '{}'",
                text::clip(l)
            ),
        ));
    }
    let mut t = Tokens::new(lines, None);
    let (n, k) = t.expect("DATASET")?;
    let (n2, kind) = t.expect("a dataset type")?;
    if k != "DATASET" || kind != "UNSTRUCTURED_GRID" {
        return Err(fmt_err(
            FORMAT,
            n.max(n2),
            "expected 'DATASET UNSTRUCTURED_GRID'",
        ));
    }
    let mut vertices: Option<Vec<[f64; 3]>> = None;
    // Cells as (line, first point, number of points) into `conn`.
    let mut cells: Option<Vec<(usize, usize, usize)>> = None;
    let mut conn: Vec<usize> = Vec::new();
    let mut tets = Vec::new();
    let mut triangles = Vec::new();
    loop {
        let (n, key) = t.expect("a section: POINTS, CELLS or CELL_TYPES")?;
        match key {
            "POINTS" => {
                let (_, np) = t.usize("a point count")?;
                let (n3, ty) = t.expect("a point data type")?;
                if !matches!(
                    ty,
                    "float"
                        | "double"
                        | "int"
                        | "unsigned_int"
                        | "long"
                        | "unsigned_long"
                        | "short"
                        | "unsigned_short"
                        | "char"
                        | "unsigned_char"
                        | "vtktypeint64"
                ) {
                    return Err(fmt_err(
                        FORMAT,
                        n3,
                        format!("unknown data type '{}'", text::clip(ty)),
                    ));
                }
                let mut v = Vec::with_capacity(text::capacity(np, t.remaining(), 6));
                for _ in 0..np {
                    v.push([t.coord()?, t.coord()?, t.coord()?]);
                }
                vertices = Some(v);
            }
            "CELLS" => {
                let nv = vertices
                    .as_ref()
                    .ok_or_else(|| fmt_err(FORMAT, n, "CELLS before POINTS"))?
                    .len();
                let (_, m) = t.usize("a cell count")?;
                let (_, size) = t.usize("a cell list size")?;
                let mut cs = Vec::with_capacity(text::capacity(m, t.remaining(), 2));
                conn = Vec::with_capacity(text::capacity(size, t.remaining(), 2));
                let check =
                    |line: usize, i: usize| text::index(FORMAT, line, i, nv).map(|i| i as usize);
                let first = if m == 0 {
                    None
                } else {
                    Some(t.expect("the cells")?)
                };
                match first {
                    None => {
                        if size != 0 {
                            return Err(fmt_err(FORMAT, n, "no cells but a non-zero list size"));
                        }
                    }
                    Some((n, "OFFSETS")) => {
                        // VTK 5.1: `CELLS m+1 size`, OFFSETS and CONNECTIVITY arrays.
                        t.expect("the offsets type")?;
                        let mut offs = Vec::with_capacity(text::capacity(m, t.remaining(), 2));
                        for _ in 0..m {
                            offs.push(t.usize("an offset")?);
                        }
                        let (n2, k) = t.expect("CONNECTIVITY")?;
                        if k != "CONNECTIVITY" {
                            return Err(fmt_err(FORMAT, n2, "expected 'CONNECTIVITY'"));
                        }
                        t.expect("the connectivity type")?;
                        for _ in 0..size {
                            let (l, i) = t.usize("a point index")?;
                            conn.push(check(l, i)?);
                        }
                        for w in offs.windows(2) {
                            let ((l, a), (_, b)) = (w[0], w[1]);
                            if a > b || b > size {
                                return Err(fmt_err(
                                    FORMAT,
                                    l,
                                    format!("invalid offsets {a}, {b}"),
                                ));
                            }
                            cs.push((l, a, b - a));
                        }
                        if m == 0 {
                            return Err(fmt_err(
                                FORMAT,
                                n,
                                "the 5.1 layout needs at least one offset",
                            ));
                        }
                    }
                    Some((l, tok)) => {
                        // Classic: m cells `k i1 .. ik`, size = sum of (k + 1).
                        let mut k = text::parse_usize(FORMAT, l, tok, "a cell size")?;
                        let mut line = l;
                        let mut used = 0usize;
                        for c in 0..m {
                            if c > 0 {
                                (line, k) = t.usize("a cell size")?;
                            }
                            used = used.saturating_add(k.saturating_add(1));
                            if used > size {
                                return Err(fmt_err(
                                    FORMAT,
                                    line,
                                    format!("the cells exceed the declared list size {size}"),
                                ));
                            }
                            cs.push((line, conn.len(), k));
                            for _ in 0..k {
                                let (l, i) = t.usize("a point index")?;
                                conn.push(check(l, i)?);
                            }
                        }
                        if used != size {
                            return Err(fmt_err(
                                FORMAT,
                                line,
                                format!("the cells use {used} list entries, CELLS declared {size}"),
                            ));
                        }
                    }
                }
                cells = Some(cs);
            }
            "CELL_TYPES" => {
                let cs = cells
                    .as_ref()
                    .ok_or_else(|| fmt_err(FORMAT, n, "CELL_TYPES before CELLS"))?;
                let (l, m) = t.usize("a cell count")?;
                if m != cs.len() {
                    return Err(fmt_err(
                        FORMAT,
                        l,
                        format!("CELL_TYPES declares {m} cells, CELLS declared {}", cs.len()),
                    ));
                }
                for &(cl, first, k) in cs {
                    let (l, ty) = t.usize("a cell type")?;
                    match ty {
                        TETRA if k == 4 => tets.push([0, 1, 2, 3].map(|j| conn[first + j] as u32)),
                        TRIANGLE if k == 3 => {
                            triangles.push([0, 1, 2].map(|j| conn[first + j] as u32))
                        }
                        TETRA | TRIANGLE => {
                            return Err(fmt_err(
                                FORMAT,
                                cl,
                                format!("a cell of type {ty} with {k} points"),
                            ))
                        }
                        // Vertices, lines, polylines, strips, polygons, pixels, quads and
                        // quadratic versions: decoration of the mesh, skipped.
                        1..=4 | 6..=9 | 21 | 22 | 23 | 28 | 30 => {}
                        _ => {
                            return Err(fmt_err(
                                FORMAT,
                                l,
                                format!(
                                "unsupported cell type {ty} (only tetrahedra, type 10, and triangles, type 5, are read)"
                            ),
                            ))
                        }
                    }
                }
                break;
            }
            _ => {
                return Err(fmt_err(
                    FORMAT,
                    n,
                    format!(
                        "unexpected '{}': expected POINTS, CELLS or CELL_TYPES",
                        text::clip(key)
                    ),
                ))
            }
        }
    }
    Ok(CellFile {
        mesh: TetMesh {
            vertices: vertices.unwrap_or_default(),
            tets,
        },
        triangles,
    })
}

/// Write a legacy VTK ASCII unstructured grid of tetrahedra (shortest round-trip floats).
pub fn write(mut w: impl Write, mesh: &TetMesh) -> Result<()> {
    super::check_tet(mesh)?;
    write_cells(&mut w, &mesh.vertices, &mesh.tets, TETRA, "tetrahedral")
}

/// Write a triangle mesh as a legacy VTK unstructured grid of triangles (type 5).
pub fn write_surface(mut w: impl Write, mesh: &TriMesh) -> Result<()> {
    super::check_tri(mesh)?;
    write_cells(
        &mut w,
        &mesh.vertices,
        &mesh.triangles,
        TRIANGLE,
        "triangle",
    )
}

fn write_cells<const K: usize>(
    w: &mut impl Write,
    vertices: &[[f64; 3]],
    cells: &[[u32; K]],
    ty: usize,
    what: &str,
) -> Result<()> {
    let m = cells.len();
    write!(
        w,
        "# vtk DataFile Version 3.0\ncertmesh {what} mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n\
         POINTS {} double\n",
        vertices.len()
    )
    .map_err(io_err)?;
    let mut o = text::TextOut::new(&mut *w);
    for v in vertices {
        o.fs(v).nl()?;
    }
    o.s("CELLS ").int(m).s(" ").int((K + 1) * m).nl()?;
    for c in cells {
        o.int(K).s(" ").ints(c).nl()?;
    }
    o.s("CELL_TYPES ").int(m).nl()?;
    for _ in 0..m {
        o.int(ty).nl()?;
    }
    o.finish()?;
    w.flush().map_err(io_err)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;

    const HEAD: &str = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n\
                        POINTS 4 float\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";

    #[test]
    fn reads_classic_and_5_1_layouts_skipping_triangles() {
        let classic =
            format!("{HEAD}CELLS 2 9\n4 0 1 2 3\n3 0 1 2\nCELL_TYPES 2\n10\n5\nPOINT_DATA 4\n");
        let m = parse(classic.as_bytes()).unwrap();
        assert_eq!(m.tets, vec![[0, 1, 2, 3]]);
        assert_eq!(
            parse_cells(classic.as_bytes()).unwrap().triangles,
            vec![[0, 1, 2]]
        );
        let v51 = format!(
            "{HEAD}CELLS 3 7\nOFFSETS vtktypeint64\n0 4 7\nCONNECTIVITY vtktypeint64\n0 1 2 3 0 1 2\n\
             CELL_TYPES 2\n10 5\n"
        );
        assert_eq!(parse(v51.as_bytes()).unwrap(), m);
    }

    #[test]
    fn malformed_input_is_located() {
        let cases: Vec<(String, usize)> = vec![
            ("# vtk DataFile Version 3.0\nt\nBINARY\n".into(), 3),
            (format!("{HEAD}CELLS 1 5\n4 0 1 2 4\nCELL_TYPES 1\n10\n"), 11),
            (format!("{HEAD}CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n12\n"), 13),
            (format!("{HEAD}CELLS 1 6\n5 0 1 2 3 3\nCELL_TYPES 1\n10\n"), 11),
            (format!("{HEAD}CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 2\n10\n"), 12),
            (format!("{HEAD}CELLS 1 5\n4 0 1 2 3\n"), 12),
            ("# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 1 float\n0 nan 0\n".into(), 6),
        ];
        for (src, line) in cases {
            match parse(src.as_bytes()) {
                Err(Error::Format {
                    format: "VTK",
                    line: l,
                    ..
                }) => assert_eq!(l, line, "{src:?}"),
                r => panic!("{src:?}: expected a format error, got {r:?}"),
            }
        }
    }
}
