//! Stable-Rust "mini-fuzz": random bytes and mutations of valid files thrown at every
//! mesh reader, and random text at the formula parser. None may panic; a reader either
//! returns a valid mesh (indices in range, finite coordinates) or a `Format` error with a
//! plausible line, and the parser returns an expression or a `Parse`/`NeedsFeature`
//! error. (The coverage-guided version is the cargo-fuzz crate in `fuzz/`.)
use certmesh::io::{csv, medit, obj, off, ply, stl, vtk};
use certmesh::mesh::{Curve2, TetMesh, TriMesh};
use certmesh::{Error, Formula, Implicit};
use proptest::prelude::*;

/// Cases per property: 3000 by default (a few seconds); set `CERTMESH_FUZZ_CASES` for a
/// longer run, e.g. `CERTMESH_FUZZ_CASES=200000 cargo test --release --test fuzz_readers`.
fn cases() -> u32 {
    std::env::var("CERTMESH_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3000)
}

// ---------------------------------------------------------------- readers

fn check_error(e: Error, data: &[u8]) {
    match e {
        Error::Format { line, message, .. } => {
            let lines = data.split(|&b| b == b'\n').count();
            assert!(line <= lines + 1, "line {line} of {lines}: {message}");
            assert!(!message.is_empty());
        }
        e => panic!("a reader returned a non-format error: {e:?}"),
    }
}

fn check_cells<const K: usize>(n: usize, cells: &[[u32; K]]) {
    assert!(cells.iter().flatten().all(|&i| (i as usize) < n));
}

fn check_tri(r: certmesh::Result<TriMesh>, data: &[u8]) {
    match r {
        Ok(m) => {
            assert!(m.vertices.iter().flatten().all(|c| c.is_finite()));
            check_cells(m.vertices.len(), &m.triangles);
        }
        Err(e) => check_error(e, data),
    }
}

fn check_tet(r: certmesh::Result<TetMesh>, data: &[u8]) {
    match r {
        Ok(m) => {
            assert!(m.vertices.iter().flatten().all(|c| c.is_finite()));
            check_cells(m.vertices.len(), &m.tets);
        }
        Err(e) => check_error(e, data),
    }
}

/// Run every reader on `data`.
fn all_readers(data: &[u8]) {
    check_tri(obj::parse(data), data);
    check_tri(off::parse(data), data);
    check_tri(ply::parse(data), data);
    check_tri(stl::parse(data), data);
    match vtk::parse_cells(data) {
        Ok(m) => {
            check_tet(Ok(m.mesh.clone()), data);
            check_cells(m.mesh.vertices.len(), &m.triangles);
        }
        Err(e) => check_error(e, data),
    }
    match medit::parse(data) {
        Ok(m) => {
            check_tet(Ok(m.mesh.clone()), data);
            check_cells(m.mesh.vertices.len(), &m.triangles);
        }
        Err(e) => check_error(e, data),
    }
    match csv::parse(data) {
        Ok(c) => {
            assert!(c.vertices.iter().flatten().all(|x| x.is_finite()));
            check_cells(c.vertices.len(), &c.segments);
        }
        Err(e) => check_error(e, data),
    }
}

/// Valid files of every format (the mutation seeds).
fn seeds() -> Vec<Vec<u8>> {
    let tri = TriMesh::new(
        vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.5, 0.0],
            [0.0, 0.0, -2.25],
        ],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    );
    let tet = TetMesh {
        vertices: tri.vertices.clone(),
        tets: vec![[0, 1, 2, 3]],
    };
    let curve = Curve2 {
        vertices: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [3.0, 3.0], [4.0, 4.0]],
        segments: vec![[0, 1], [1, 2], [2, 0], [3, 4]],
    };
    let mut out = Vec::new();
    let mut push = |f: &dyn Fn(&mut Vec<u8>)| {
        let mut b = Vec::new();
        f(&mut b);
        out.push(b);
    };
    push(&|b| obj::write(b, &tri).unwrap());
    push(&|b| off::write(b, &tri).unwrap());
    for e in [
        ply::PlyEncoding::Ascii,
        ply::PlyEncoding::BinaryLittleEndian,
        ply::PlyEncoding::BinaryBigEndian,
    ] {
        push(&|b| ply::write(b, &tri, e).unwrap());
    }
    push(&|b| stl::write(b, &tri, stl::StlEncoding::Ascii).unwrap());
    push(&|b| stl::write(b, &tri, stl::StlEncoding::Binary).unwrap());
    push(&|b| vtk::write(b, &tet).unwrap());
    push(&|b| medit::write(b, &tet, true).unwrap());
    push(&|b| csv::write(b, &curve, csv::CsvLayout::Vertices).unwrap());
    // Hand-written files exercising the readers' less common paths.
    out.push(b"# c\nv 0 0 0 1\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\ng a\nf 1/1/1 2//1 3/1 -1\nf -4 -3 -2\n".to_vec());
    out.push(b"COFF 4 1 0\n0 0 0 1 1 1\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3 9 9 9\n".to_vec());
    out.push(
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty uchar r\nproperty float z\nproperty int x\n\
          property list uchar float t\nproperty double y\nelement edge 1\nproperty int a\n\
          element face 1\nproperty list ushort uint vertex_index\nend_header\n\
          1 3.5 1 2 0.5 0.25 7\n2 0 -1 0 8\n3 1 2 1 9 9\n0\n3 2 1 0\n"
            .to_vec(),
    );
    out.push(
        b"# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n0 0 0 1 0 0\n\
          0 1 0 0 0 1\nCELLS 3 7\nOFFSETS vtktypeint64\n0 4 7\nCONNECTIVITY vtktypeint64\n0 1 2 3 0 1 2\n\
          CELL_TYPES 2\n10 5\n"
            .to_vec(),
    );
    out.push(
        b"MeshVersionFormatted 1\n# c\nDimension\n3\nVertices\n4\n0 0 0 1\n1 0 0 1\n0 1 0 1\n0 0 1 1\n\
          Edges 1\n1 2 0\nCorners 1 1\nTetrahedra\n1\n1 2 3 4 7\nEnd\n"
            .to_vec(),
    );
    out
}

/// Tokens that stress counts, indices and number parsing.
const NASTY: &[&str] = &[
    "0",
    "-1",
    "-0",
    "1",
    "3",
    "255",
    "65536",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "99999999999999999999999",
    "-9223372036854775808",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e309",
    "1e-320",
    "0x10",
    "",
    "\u{0}",
    "é",
    "#",
    "/",
    "1//",
    "//1",
    "end_header",
    "End",
    "OFFSETS",
    "Vertices",
    "\n",
];

#[derive(Clone, Debug)]
enum Mutation {
    Flip(usize, u8),
    Insert(usize, Vec<u8>),
    Delete(usize, usize),
    Truncate(usize),
    Token(usize, usize),
    DupLine(usize),
    Invalid(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(p, b)| Mutation::Flip(p, b)),
        (any::<usize>(), prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(p, v)| Mutation::Insert(p, v)),
        (any::<usize>(), 1usize..16).prop_map(|(p, n)| Mutation::Delete(p, n)),
        any::<usize>().prop_map(Mutation::Truncate),
        (any::<usize>(), 0..NASTY.len()).prop_map(|(p, k)| Mutation::Token(p, k)),
        (any::<usize>(), 0..NASTY.len()).prop_map(|(p, k)| Mutation::Token(p, k)),
        any::<usize>().prop_map(Mutation::DupLine),
        any::<usize>().prop_map(Mutation::Invalid),
    ]
}

fn apply(d: &mut Vec<u8>, m: &Mutation) {
    let n = d.len();
    let at = |p: usize| if n == 0 { 0 } else { p % n };
    match m {
        Mutation::Flip(p, b) if n > 0 => d[at(*p)] ^= b | 1,
        Mutation::Insert(p, v) => {
            let p = at(*p);
            d.splice(p..p, v.iter().copied());
        }
        Mutation::Delete(p, k) if n > 0 => {
            let p = at(*p);
            d.drain(p..(p + k).min(n));
        }
        Mutation::Truncate(p) => d.truncate(at(*p)),
        Mutation::Token(p, k) if n > 0 => {
            // Replace the whitespace-delimited token around position p.
            let mut s = at(*p);
            while s > 0 && !d[s - 1].is_ascii_whitespace() {
                s -= 1;
            }
            let mut e = s;
            while e < n && !d[e].is_ascii_whitespace() {
                e += 1;
            }
            d.splice(s..e, NASTY[*k].bytes());
        }
        Mutation::DupLine(p) if n > 0 => {
            let p = at(*p);
            let s = d[..p]
                .iter()
                .rposition(|&b| b == b'\n')
                .map_or(0, |i| i + 1);
            let e = d[p..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(n, |i| p + i + 1);
            let line: Vec<u8> = d[s..e].to_vec();
            d.splice(s..s, line);
        }
        Mutation::Invalid(p) => {
            let p = at(*p);
            d.splice(p..p, [0xff, 0xc3]);
        }
        _ => {}
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn readers_survive_random_bytes(data in prop::collection::vec(any::<u8>(), 0..400)) {
        all_readers(&data);
    }

    #[test]
    fn readers_survive_random_text(s in "[0-9a-zA-Z_ ./#+\\-\\n]{0,300}") {
        all_readers(s.as_bytes());
    }

    #[test]
    fn readers_survive_mutated_files(seed in any::<prop::sample::Index>(), ms in prop::collection::vec(mutation(), 1..5)) {
        let seeds = seeds();
        let mut d = seeds[seed.index(seeds.len())].clone();
        for m in &ms {
            apply(&mut d, m);
        }
        all_readers(&d);
    }
}

#[test]
fn seeds_are_valid() {
    // The mutation seeds must themselves read (so mutations start from deep paths).
    let s = seeds();
    assert!(obj::parse(&s[0]).is_ok() && off::parse(&s[1]).is_ok());
    for d in &s[2..5] {
        assert_eq!(ply::parse(d).unwrap().triangles.len(), 4);
    }
    assert!(stl::parse(&s[5]).is_ok() && stl::parse(&s[6]).is_ok());
    assert_eq!(vtk::parse(&s[7]).unwrap().tets.len(), 1);
    assert_eq!(medit::parse(&s[8]).unwrap().triangles.len(), 4);
    assert_eq!(csv::parse(&s[9]).unwrap().segments.len(), 4);
    assert_eq!(obj::parse(&s[10]).unwrap().triangles.len(), 3);
    assert_eq!(off::parse(&s[11]).unwrap().triangles.len(), 2);
    assert_eq!(ply::parse(&s[12]).unwrap().triangles.len(), 1);
    assert_eq!(vtk::parse(&s[13]).unwrap().tets.len(), 1);
    assert_eq!(medit::parse(&s[14]).unwrap().mesh.tets.len(), 1);
}

// ---------------------------------------------------------------- formula parser

fn check_formula(s: &str) {
    for dim in [2, 3] {
        match certmesh::implicit::parse(s, dim) {
            Ok(_) => {
                // A parsed formula compiles and evaluates without panicking.
                if let Ok(f) = Formula::with_dim(s, dim) {
                    let _ = f.eval([0.5, -0.25, 0.125]);
                    let b = certmesh::Aabb::cube(1.0).intervals();
                    let _ = f.eval_interval(&b);
                    let _ = f.grad([0.5, -0.25, 0.125]);
                }
            }
            Err(Error::Parse { column, .. }) | Err(Error::NeedsFeature { column, .. }) => {
                assert!(
                    column >= 1 && column <= s.chars().count() + 1,
                    "column {column} in {s:?}"
                );
            }
            Err(e) => panic!("parse({s:?}) gave an unexpected error kind: {e:?}"),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn formula_parser_survives_arbitrary_text(s in any::<String>()) {
        check_formula(&s);
    }

    #[test]
    fn formula_parser_survives_formula_like_text(
        s in "([xyz]|[0-9]{1,3}|\\.|e|pi|sqrt|abs|min|max|sin|exp|\\^|[-+*/(),]|[0-9]+\\.[0-9]*e[-+]?[0-9]{1,4}| ){0,40}"
    ) {
        check_formula(&s);
    }

    #[test]
    fn formula_parser_survives_mutated_catalog_formulas(
        k in any::<prop::sample::Index>(),
        ms in prop::collection::vec(mutation(), 1..4),
    ) {
        let entries = certmesh::catalog::entries();
        let mut d = entries[k.index(entries.len())].formula.as_bytes().to_vec();
        for m in &ms {
            apply(&mut d, m);
        }
        check_formula(&String::from_utf8_lossy(&d));
    }
}

#[test]
fn fuzz_seed_corpus_is_valid() {
    // The seed corpus of the cargo-fuzz targets (fuzz/seeds/<target>/) must be valid
    // input, so that fuzzing starts from files that reach deep into each reader.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/seeds");
    let mut n = 0;
    for target in ["formula", "obj", "off", "ply", "stl", "vtk", "medit", "csv"] {
        let files = std::fs::read_dir(dir.join(target)).unwrap();
        for f in files {
            let path = f.unwrap().path();
            let d = std::fs::read(&path).unwrap();
            let ok = match target {
                "formula" => {
                    let s = std::str::from_utf8(&d).unwrap();
                    certmesh::implicit::parse(s, 3).is_ok()
                        || certmesh::implicit::parse(s, 2).is_ok()
                }
                "obj" => obj::parse(&d).is_ok_and(|m| !m.triangles.is_empty()),
                "off" => off::parse(&d).is_ok_and(|m| !m.triangles.is_empty()),
                "ply" => ply::parse(&d).is_ok_and(|m| !m.triangles.is_empty()),
                "stl" => {
                    stl::parse(&d).is_ok_and(|m| m.triangles.len() == 4 && m.vertices.len() == 4)
                }
                "vtk" => vtk::parse(&d).is_ok_and(|m| m.tets.len() == 1),
                "medit" => medit::parse(&d).is_ok_and(|m| m.mesh.tets.len() == 1),
                _ => csv::parse(&d).is_ok_and(|c| c.segments.len() == 4),
            };
            assert!(ok, "{} is not a valid seed", path.display());
            n += 1;
        }
    }
    assert!(n >= 20);
}
