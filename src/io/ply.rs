//! Stanford PLY: `ascii`, `binary_little_endian` and `binary_big_endian`.
//!
//! Reading: the `vertex` element's `x y z` properties may come in any order among other
//! properties, of any PLY scalar type (`char uchar short ushort int uint float double`
//! or `int8 uint8 int16 uint16 int32 uint32 float32 float64`); the `face` element's
//! `vertex_indices` (or `vertex_index`) list may have any integer count and index types;
//! polygons are fan-triangulated; every other element and property is skipped (their
//! sizes are honoured in binary files). Vertex indices are checked against the declared
//! vertex count. Binary errors report line 0 and the byte offset.
//!
//! Writing: `double x y z` (exact round trip) and `list uchar int vertex_indices`.
use super::text::{self, fmt_err, io_err, Lines};
use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use std::io::{BufRead, Write};

const FORMAT: &str = "PLY";

/// The three PLY encodings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlyEncoding {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

impl PlyEncoding {
    fn name(self) -> &'static str {
        match self {
            PlyEncoding::Ascii => "ascii",
            PlyEncoding::BinaryLittleEndian => "binary_little_endian",
            PlyEncoding::BinaryBigEndian => "binary_big_endian",
        }
    }
}

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Scalar> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
    fn is_int(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
    fn range(self) -> (i64, i64) {
        match self {
            Scalar::I8 => (i8::MIN as i64, i8::MAX as i64),
            Scalar::U8 => (0, u8::MAX as i64),
            Scalar::I16 => (i16::MIN as i64, i16::MAX as i64),
            Scalar::U16 => (0, u16::MAX as i64),
            Scalar::I32 => (i32::MIN as i64, i32::MAX as i64),
            Scalar::U32 => (0, u32::MAX as i64),
            Scalar::F32 | Scalar::F64 => (i64::MIN, i64::MAX),
        }
    }
}

/// A value read from the body.
#[derive(Clone, Copy, Debug)]
enum Value {
    I(i64),
    F(f64),
}

impl Value {
    fn as_f64(self) -> f64 {
        match self {
            Value::I(i) => i as f64,
            Value::F(x) => x,
        }
    }
}

#[derive(Debug)]
enum Prop {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// What a property is used for.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Role {
    Coord(usize),
    Indices,
    Skip,
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    line: usize,
    props: Vec<(String, Prop)>,
}

impl Element {
    /// The fewest bytes one instance takes in binary.
    fn min_binary_size(&self) -> usize {
        self.props
            .iter()
            .map(|(_, p)| match p {
                Prop::Scalar(s) => s.size(),
                Prop::List { count, .. } => count.size(),
            })
            .sum()
    }
}

/// Read a PLY triangle mesh (any encoding).
pub fn read(r: impl BufRead) -> Result<TriMesh> {
    let data = super::slurp(r)?;
    parse(&data)
}

/// Parse a PLY triangle mesh held in memory.
pub fn parse(data: &[u8]) -> Result<TriMesh> {
    let mut lines = Lines::new(FORMAT, data);
    let (encoding, elements) = header(&mut lines)?;
    let nv = elements
        .iter()
        .find(|e| e.name == "vertex")
        .map_or(0, |e| e.count);
    let body_start = data.len() - lines.remaining();
    let mut mesh = TriMesh::default();
    match encoding {
        PlyEncoding::Ascii => {
            let mut src = Ascii {
                lines,
                toks: "".split_ascii_whitespace(),
                line: 0,
            };
            body(&mut src, &elements, nv, &mut mesh)?;
        }
        e => {
            let mut src = Binary {
                data,
                pos: body_start,
                at: body_start,
                big: e == PlyEncoding::BinaryBigEndian,
            };
            body(&mut src, &elements, nv, &mut mesh)?;
        }
    }
    Ok(mesh)
}

fn header(lines: &mut Lines) -> Result<(PlyEncoding, Vec<Element>)> {
    let (n, magic) = lines
        .next_raw()
        .ok_or_else(|| fmt_err(FORMAT, 1, "empty file: expected 'ply'"))?;
    if text::to_str(FORMAT, n, magic)?.trim() != "ply" {
        return Err(fmt_err(FORMAT, n, "expected 'ply' on the first line"));
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let (n, raw) = lines.next_raw().ok_or_else(|| {
            fmt_err(
                FORMAT,
                lines.line() + 1,
                "unexpected end of file in the header (no 'end_header')",
            )
        })?;
        let l = text::to_str(FORMAT, n, raw)?;
        let t: Vec<&str> = l.split_ascii_whitespace().collect();
        let err = |m: String| fmt_err(FORMAT, n, m);
        match t.first().copied() {
            None | Some("comment") | Some("obj_info") => {}
            Some("format") => {
                encoding = Some(match t.get(1).copied() {
                    Some("ascii") => PlyEncoding::Ascii,
                    Some("binary_little_endian") => PlyEncoding::BinaryLittleEndian,
                    Some("binary_big_endian") => PlyEncoding::BinaryBigEndian,
                    _ => return Err(err(format!("unknown format line '{}'", text::clip(l)))),
                });
            }
            Some("element") => {
                if t.len() != 3 {
                    return Err(err("expected 'element NAME COUNT'".into()));
                }
                let count = text::parse_usize(FORMAT, n, t[2], "an element count")?;
                elements.push(Element {
                    name: t[1].to_string(),
                    count,
                    line: n,
                    props: Vec::new(),
                });
            }
            Some("property") => {
                let e = elements
                    .last_mut()
                    .ok_or_else(|| err("a property before any element".into()))?;
                let ty = |s: &str| {
                    Scalar::parse(s)
                        .ok_or_else(|| err(format!("unknown property type '{}'", text::clip(s))))
                };
                let (name, prop) = match t.get(1).copied() {
                    Some("list") if t.len() == 5 => {
                        let (count, item) = (ty(t[2])?, ty(t[3])?);
                        if !count.is_int() {
                            return Err(err(format!("list count type '{}' is not an integer type", t[2])));
                        }
                        (t[4], Prop::List { count, item })
                    }
                    Some(s) if s != "list" && t.len() == 3 => (t[2], Prop::Scalar(ty(s)?)),
                    _ => {
                        return Err(err(
                            "expected 'property TYPE NAME' or 'property list COUNT_TYPE ITEM_TYPE NAME'"
                                .into(),
                        ))
                    }
                };
                e.props.push((name.to_string(), prop));
            }
            Some("end_header") => break,
            Some(k) => return Err(err(format!("unknown header keyword '{}'", text::clip(k)))),
        }
    }
    let encoding = encoding.ok_or_else(|| fmt_err(FORMAT, 2, "missing 'format' line"))?;
    for e in &elements {
        if e.name == "vertex" {
            for c in ["x", "y", "z"] {
                match e.props.iter().find(|(n, _)| n == c) {
                    Some((_, Prop::Scalar(_))) => {}
                    _ => {
                        return Err(fmt_err(
                            FORMAT,
                            e.line,
                            format!("the vertex element has no scalar property '{c}'"),
                        ))
                    }
                }
            }
        }
        if e.name == "face" && e.count > 0 {
            match e.props.iter().find(|(n, _)| is_index_list(n)) {
                Some((_, Prop::List { item, .. })) if item.is_int() => {}
                _ => {
                    return Err(fmt_err(
                        FORMAT,
                        e.line,
                        "the face element has no integer list property 'vertex_indices'",
                    ))
                }
            }
        }
    }
    Ok((encoding, elements))
}

fn is_index_list(name: &str) -> bool {
    name == "vertex_indices" || name == "vertex_index"
}

/// The data part of a PLY file, ascii or binary.
trait Source {
    fn begin(&mut self, what: &str) -> Result<()>;
    fn scalar(&mut self, ty: Scalar) -> Result<Value>;
    fn end(&mut self) -> Result<()>;
    fn remaining(&self) -> usize;
    fn err(&self, message: String) -> Error;
    fn binary(&self) -> bool;
}

struct Ascii<'a> {
    lines: Lines<'a>,
    toks: std::str::SplitAsciiWhitespace<'a>,
    line: usize,
}

impl Source for Ascii<'_> {
    fn begin(&mut self, what: &str) -> Result<()> {
        let (n, l) = self.lines.expect_content(None, what)?;
        self.toks = l.split_ascii_whitespace();
        self.line = n;
        Ok(())
    }
    fn scalar(&mut self, ty: Scalar) -> Result<Value> {
        let tok = self
            .toks
            .next()
            .ok_or_else(|| self.err("too few values on the line".into()))?;
        if ty.is_int() {
            let (lo, hi) = ty.range();
            match tok.parse::<i64>() {
                Ok(i) if (lo..=hi).contains(&i) => Ok(Value::I(i)),
                _ => Err(self.err(format!(
                    "expected an integer of type {ty:?}, found '{}'",
                    text::clip(tok)
                ))),
            }
        } else {
            tok.parse::<f64>()
                .map(Value::F)
                .map_err(|_| self.err(format!("expected a number, found '{}'", text::clip(tok))))
        }
    }
    fn end(&mut self) -> Result<()> {
        match self.toks.next() {
            Some(t) => Err(self.err(format!("unexpected extra value '{}'", text::clip(t)))),
            None => Ok(()),
        }
    }
    fn remaining(&self) -> usize {
        self.lines.remaining()
    }
    fn err(&self, message: String) -> Error {
        fmt_err(FORMAT, self.line, message)
    }
    fn binary(&self) -> bool {
        false
    }
}

struct Binary<'a> {
    data: &'a [u8],
    pos: usize,
    /// Offset of the value being read (for errors).
    at: usize,
    big: bool,
}

impl Source for Binary<'_> {
    fn begin(&mut self, _: &str) -> Result<()> {
        Ok(())
    }
    fn scalar(&mut self, ty: Scalar) -> Result<Value> {
        self.at = self.pos;
        let n = ty.size();
        let b = self
            .data
            .get(self.pos..self.pos + n)
            .ok_or_else(|| self.err("unexpected end of data".into()))?;
        self.pos += n;
        let mut a = [0u8; 8];
        a[..n].copy_from_slice(b);
        if self.big {
            a[..n].reverse();
        }
        Ok(match ty {
            Scalar::I8 => Value::I(a[0] as i8 as i64),
            Scalar::U8 => Value::I(a[0] as i64),
            Scalar::I16 => Value::I(i16::from_le_bytes([a[0], a[1]]) as i64),
            Scalar::U16 => Value::I(u16::from_le_bytes([a[0], a[1]]) as i64),
            Scalar::I32 => Value::I(i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as i64),
            Scalar::U32 => Value::I(u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as i64),
            Scalar::F32 => Value::F(f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64),
            Scalar::F64 => Value::F(f64::from_le_bytes(a)),
        })
    }
    fn end(&mut self) -> Result<()> {
        Ok(())
    }
    fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }
    fn err(&self, message: String) -> Error {
        fmt_err(FORMAT, 0, format!("{message} (at byte offset {})", self.at))
    }
    fn binary(&self) -> bool {
        true
    }
}

fn body(src: &mut impl Source, elements: &[Element], nv: usize, mesh: &mut TriMesh) -> Result<()> {
    let mut poly: Vec<u32> = Vec::new();
    for e in elements {
        if e.props.is_empty() {
            // Nothing to read, however large the declared count.
            continue;
        }
        let min = e.min_binary_size();
        if src.binary() && e.count.checked_mul(min).is_none_or(|b| b > src.remaining()) {
            return Err(src.err(format!(
                "element '{}' declares {} items of at least {min} bytes but only {} bytes remain",
                text::clip(&e.name),
                e.count,
                src.remaining()
            )));
        }
        let roles: Vec<Role> = e
            .props
            .iter()
            .map(|(n, _)| match (e.name.as_str(), n.as_str()) {
                ("vertex", "x") => Role::Coord(0),
                ("vertex", "y") => Role::Coord(1),
                ("vertex", "z") => Role::Coord(2),
                ("face", n) if is_index_list(n) => Role::Indices,
                _ => Role::Skip,
            })
            .collect();
        let cap = text::capacity(e.count, src.remaining(), min.max(2));
        match e.name.as_str() {
            "vertex" => mesh.vertices.reserve(cap),
            "face" => mesh.triangles.reserve(cap),
            _ => {}
        }
        // Only the first index list counts (a repeated name is skipped).
        let first_indices = roles.iter().position(|r| *r == Role::Indices);
        for _ in 0..e.count {
            src.begin(&format!("a '{}' element", e.name))?;
            let mut p = [0.0; 3];
            for (k, ((_, prop), role)) in e.props.iter().zip(&roles).enumerate() {
                match prop {
                    Prop::Scalar(ty) => {
                        let v = src.scalar(*ty)?;
                        if let Role::Coord(c) = role {
                            let x = v.as_f64();
                            if !x.is_finite() {
                                return Err(src.err(format!("coordinate {x} is not finite")));
                            }
                            p[*c] = x;
                        }
                    }
                    Prop::List { count, item } => {
                        let n = match src.scalar(*count)? {
                            Value::I(i) if i >= 0 => i as u64,
                            v => return Err(src.err(format!("invalid list length {v:?}"))),
                        };
                        if src.binary()
                            && n.saturating_mul(item.size() as u64) > src.remaining() as u64
                        {
                            return Err(src.err(format!(
                                "a list of {n} items runs past the end of the data"
                            )));
                        }
                        let is_face = Some(k) == first_indices;
                        if is_face {
                            if n < 3 {
                                return Err(
                                    src.err(format!("a face needs at least 3 vertices, found {n}"))
                                );
                            }
                            poly.clear();
                        }
                        for _ in 0..n {
                            let v = src.scalar(*item)?;
                            if is_face {
                                let i = match v {
                                    Value::I(i) if i >= 0 && (i as u64) < nv as u64 => i as usize,
                                    v => {
                                        return Err(src.err(format!(
                                            "vertex index {} out of range: {nv} vertices",
                                            v.as_f64()
                                        )))
                                    }
                                };
                                let i = u32::try_from(i).map_err(|_| {
                                    src.err(format!("vertex index {i} exceeds u32"))
                                })?;
                                poly.push(i);
                            }
                        }
                        if is_face {
                            for j in 1..poly.len() - 1 {
                                mesh.triangles.push([poly[0], poly[j], poly[j + 1]]);
                            }
                        }
                    }
                }
            }
            src.end()?;
            if e.name == "vertex" {
                mesh.vertices.push(p);
            }
        }
    }
    Ok(())
}

/// Write a PLY file in the given encoding.
pub fn write(mut w: impl Write, mesh: &TriMesh, encoding: PlyEncoding) -> Result<()> {
    super::check_tri(mesh)?;
    if mesh.vertices.len() > i32::MAX as usize {
        return Err(Error::TooLarge(format!(
            "PLY 'int' vertex indices hold at most {} vertices, the mesh has {}",
            i32::MAX,
            mesh.vertices.len()
        )));
    }
    write!(
        w,
        "ply\nformat {} 1.0\ncomment written by certmesh\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        encoding.name(),
        mesh.vertices.len(),
        mesh.triangles.len()
    )
    .map_err(io_err)?;
    match encoding {
        PlyEncoding::Ascii => {
            let mut o = text::TextOut::new(&mut w);
            for v in &mesh.vertices {
                o.fs(v).nl()?;
            }
            for t in &mesh.triangles {
                o.s("3 ").ints(t).nl()?;
            }
            o.finish()?;
        }
        e => {
            // Gathered and handed over in chunks, as the text writers do.
            let big = e == PlyEncoding::BinaryBigEndian;
            let mut o = text::TextOut::new(&mut w);
            for v in &mesh.vertices {
                for c in v {
                    o.bytes(&if big {
                        c.to_be_bytes()
                    } else {
                        c.to_le_bytes()
                    });
                }
                o.end()?;
            }
            for t in &mesh.triangles {
                o.bytes(&[3]);
                for &i in t {
                    let i = i as i32;
                    o.bytes(&if big {
                        i.to_be_bytes()
                    } else {
                        i.to_le_bytes()
                    });
                }
                o.end()?;
            }
            o.finish()?;
        }
    }
    w.flush().map_err(io_err)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn properties_in_any_order_and_types() {
        let src = "ply\nformat ascii 1.0\ncomment hi\nelement vertex 3\nproperty uchar red\n\
                   property float z\nproperty int x\nproperty list uchar float junk\nproperty double y\n\
                   element edge 1\nproperty int a\nproperty int b\n\
                   element face 1\nproperty uchar flags\nproperty list ushort uint vertex_index\n\
                   end_header\n1 3.5 1 2 0.5 0.25 7\n2 0 -1 0 8\n3 1 2 1 9 9\n0 1\n5 3 2 1 0\n";
        let m = parse(src.as_bytes()).unwrap();
        assert_eq!(
            m.vertices,
            vec![[1.0, 7.0, 3.5], [-1.0, 8.0, 0.0], [2.0, 9.0, 1.0]]
        );
        assert_eq!(m.triangles, vec![[2, 1, 0]]);
    }

    #[test]
    fn big_endian_floats_and_shorts() {
        let mut d = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\n\
                      property float y\nproperty float z\nelement face 1\n\
                      property list uchar short vertex_indices\nend_header\n"
            .to_vec();
        for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.5, 0.0]] {
            for c in v {
                d.extend(c.to_be_bytes());
            }
        }
        d.push(3);
        for i in [0i16, 1, 2] {
            d.extend(i.to_be_bytes());
        }
        let m = parse(&d).unwrap();
        assert_eq!(m.vertices[2], [0.0, 1.5, 0.0]);
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        // Truncate inside the face: line 0 and the offset of the face's list.
        let n = d.len();
        match parse(&d[..n - 1]).unwrap_err() {
            Error::Format {
                line: 0, message, ..
            } => {
                assert!(message.contains(&format!("offset {}", n - 7)), "{message}")
            }
            e => panic!("{e:?}"),
        }
    }

    #[test]
    fn malformed_headers_and_bodies_are_located() {
        let h = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                 property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
        let cases: Vec<(String, usize)> = vec![
            ("plx\n".into(), 1),
            (
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n".into(),
                3,
            ),
            (
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n".into(),
                4,
            ),
            ("ply\nformat ascii 1.0\nelement vertex 1\n".into(), 4),
            (format!("{h}0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), 13),
            (format!("{h}0 0 0\n1 0 0\n0 1 0\n2 0 1\n"), 13),
            (format!("{h}0 0 0\n1 0 0 5\n0 1 0\n3 0 1 2\n"), 11),
            (format!("{h}0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n"), 11),
            (format!("{h}0 0 0\n1 0 0\n"), 12),
            (format!("{h}0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n"), 13),
        ];
        for (src, line) in cases {
            match parse(src.as_bytes()) {
                Err(Error::Format {
                    format: "PLY",
                    line: l,
                    ..
                }) => assert_eq!(l, line, "{src:?}"),
                r => panic!("{src:?}: expected a format error, got {r:?}"),
            }
        }
        // A huge binary count is refused before any allocation.
        let src = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000000\n\
                   property double x\nproperty double y\nproperty double z\nend_header\n";
        assert!(matches!(
            parse(src.as_bytes()),
            Err(Error::Format { line: 0, .. })
        ));
    }
}
