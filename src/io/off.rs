//! Object File Format (Geomview OFF).
//!
//! `OFF` (or a `C`/`N`/`ST` variant: extra per-vertex values are ignored), then
//! `nv nf ne` (on the header line or the next one), `nv` vertex lines `x y z ...`, and
//! `nf` face lines `k i1 .. ik [colour]` with 0-based indices; polygons are
//! fan-triangulated. `#` starts a comment. 4D and n-dimensional variants are rejected.
use super::text::{self, fmt_err, io_err, Lines};
use crate::error::Result;
use crate::mesh::TriMesh;
use std::io::{BufRead, Write};

const FORMAT: &str = "OFF";

/// Read an OFF triangle mesh.
pub fn read(r: impl BufRead) -> Result<TriMesh> {
    let data = super::slurp(r)?;
    parse(&data)
}

/// Parse an OFF triangle mesh held in memory.
pub fn parse(data: &[u8]) -> Result<TriMesh> {
    let mut lines = Lines::new(FORMAT, data);
    let (n, header) = lines.expect_content(Some(b'#'), "the 'OFF' header")?;
    let mut toks = header.split_ascii_whitespace();
    let key = toks.next().unwrap_or("");
    let variant = key.strip_suffix("OFF").map(|p| {
        let p = p.strip_prefix("ST").unwrap_or(p);
        let p = p.strip_prefix('C').unwrap_or(p);
        p.strip_prefix('N').unwrap_or(p).is_empty()
    });
    if variant != Some(true) {
        return Err(fmt_err(
            FORMAT,
            n,
            format!(
                "expected the header 'OFF' (or COFF, NOFF, STOFF), found '{}'",
                text::clip(key)
            ),
        ));
    }
    // The counts may follow on the header line.
    let mut counts: Vec<&str> = toks.collect();
    let mut count_line = n;
    if counts.is_empty() {
        let (n2, l) = lines.expect_content(Some(b'#'), "the counts 'vertices faces edges'")?;
        counts = l.split_ascii_whitespace().collect();
        count_line = n2;
    }
    if counts.len() < 2 {
        return Err(fmt_err(
            FORMAT,
            count_line,
            "expected the counts 'vertices faces edges'",
        ));
    }
    let nv = text::parse_usize(FORMAT, count_line, counts[0], "a vertex count")?;
    let nf = text::parse_usize(FORMAT, count_line, counts[1], "a face count")?;

    // Each vertex line takes at least 6 bytes ("0 0 0\n"), each face 8 ("3 0 1 2\n").
    let mut mesh = TriMesh {
        vertices: Vec::with_capacity(text::capacity(nv, lines.remaining(), 6)),
        triangles: Vec::with_capacity(text::capacity(nf, lines.remaining(), 8)),
    };
    for _ in 0..nv {
        let (n, l) = lines.expect_content(Some(b'#'), "a vertex line 'x y z'")?;
        let mut t = l.split_ascii_whitespace();
        let mut p = [0.0; 3];
        for c in &mut p {
            let tok = t
                .next()
                .ok_or_else(|| fmt_err(FORMAT, n, "a vertex needs three coordinates"))?;
            *c = text::parse_coord(FORMAT, n, tok)?;
        }
        mesh.vertices.push(p);
    }
    let mut poly = Vec::new();
    for _ in 0..nf {
        let (n, l) = lines.expect_content(Some(b'#'), "a face line 'k i1 .. ik'")?;
        let mut t = l.split_ascii_whitespace();
        let k = text::parse_usize(FORMAT, n, t.next().unwrap_or(""), "a face size")?;
        if k < 3 {
            return Err(fmt_err(
                FORMAT,
                n,
                format!("a face needs at least 3 vertices, found {k}"),
            ));
        }
        poly.clear();
        for _ in 0..k {
            let tok = t.next().ok_or_else(|| {
                fmt_err(
                    FORMAT,
                    n,
                    format!("the face declares {k} vertices but lists fewer"),
                )
            })?;
            let i = text::parse_usize(FORMAT, n, tok, "a vertex index")?;
            poly.push(text::index(FORMAT, n, i, nv)?);
        }
        for j in 1..k - 1 {
            mesh.triangles.push([poly[0], poly[j], poly[j + 1]]);
        }
    }
    Ok(mesh)
}

/// Write an OFF file (shortest round-trip floats, 0-based indices, edge count 0).
pub fn write(mut w: impl Write, mesh: &TriMesh) -> Result<()> {
    super::check_tri(mesh)?;
    writeln!(w, "OFF\n{} {} 0", mesh.vertices.len(), mesh.triangles.len()).map_err(io_err)?;
    let mut o = text::TextOut::new(&mut w);
    for v in &mesh.vertices {
        o.fs(v).nl()?;
    }
    for t in &mesh.triangles {
        o.s("3 ").ints(t).nl()?;
    }
    o.finish()?;
    w.flush().map_err(io_err)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;

    #[test]
    fn reads_variants_and_polygons() {
        let m = parse(b"# hi\nOFF 4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3 255 0 0\n").unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        let m = parse(b"NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n").unwrap();
        assert_eq!(m.vertices[1], [1.0, 0.0, 0.0]);
    }

    #[test]
    fn malformed_lines_are_located() {
        let cases: [(&str, usize); 8] = [
            ("OFX\n", 1),
            ("OFF\n", 2),
            ("OFF\n3 1 0\n0 0 0\n1 0 0\n", 5),
            ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", 6),
            ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", 6),
            ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", 6),
            ("OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n", 4),
            ("OFF\n99999999999999999999 1 0\n", 2),
        ];
        for (src, line) in cases {
            match parse(src.as_bytes()) {
                Err(Error::Format {
                    format: "OFF",
                    line: l,
                    ..
                }) => assert_eq!(l, line, "{src:?}"),
                r => panic!("{src:?}: expected a format error, got {r:?}"),
            }
        }
        // A huge declared count fails at the end of the data, without allocating it.
        match parse(b"OFF\n18446744073709551615 0 0\n0 0 0\n") {
            Err(Error::Format { line: 4, .. }) => {}
            r => panic!("{r:?}"),
        }
    }
}
