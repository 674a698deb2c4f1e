//! Mesh file formats: round trips (proptest), malformed input, real meshes, dispatch.
use certmesh::io::{self, csv, medit, obj, off, ply, stl, svg, vtk, Format};
use certmesh::mesh::{Curve2, TetMesh, TriMesh};
use certmesh::Error;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------- strategies

/// Finite doubles of every kind: ordinary, decimal-looking, tiny, huge, subnormal, ±0.
fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e3..1e3f64,
        (-1000i32..1000).prop_map(|i| i as f64 * 0.1),
        any::<f64>().prop_filter("finite", |x| x.is_finite()),
        prop::num::f64::SUBNORMAL | prop::num::f64::NEGATIVE,
        Just(0.0),
        Just(-0.0),
    ]
}

fn point() -> impl Strategy<Value = [f64; 3]> {
    [coord(), coord(), coord()]
}

fn trimesh() -> impl Strategy<Value = TriMesh> {
    (1usize..25).prop_flat_map(|n| {
        let i = 0..n as u32;
        (
            prop::collection::vec(point(), n),
            prop::collection::vec([i.clone(), i.clone(), i], 0..30),
        )
            .prop_map(|(vertices, triangles)| TriMesh {
                vertices,
                triangles,
            })
    })
}

fn tetmesh() -> impl Strategy<Value = TetMesh> {
    (1usize..20).prop_flat_map(|n| {
        let i = 0..n as u32;
        (
            prop::collection::vec(point(), n),
            prop::collection::vec([i.clone(), i.clone(), i.clone(), i], 0..20),
        )
            .prop_map(|(vertices, tets)| TetMesh { vertices, tets })
    })
}

/// Meshes whose coordinates are `f32` values (binary STL stores `f32`).
fn trimesh_f32() -> impl Strategy<Value = TriMesh> {
    let c = prop_oneof![
        any::<f32>().prop_filter("finite", |x| x.is_finite()),
        (-50i32..50).prop_map(|i| i as f32 * 0.25),
    ];
    (1usize..25).prop_flat_map(move |n| {
        let i = 0..n as u32;
        (
            prop::collection::vec([c.clone(), c.clone(), c.clone()], n),
            prop::collection::vec([i.clone(), i.clone(), i], 0..30),
        )
            .prop_map(|(v, triangles)| TriMesh {
                vertices: v.into_iter().map(|p| p.map(|x| x as f64)).collect(),
                triangles,
            })
    })
}

fn curve() -> impl Strategy<Value = Curve2> {
    (2usize..20).prop_flat_map(|n| {
        let i = 0..n as u32;
        (
            prop::collection::vec([coord(), coord()], n),
            prop::collection::vec([i.clone(), i], 0..25),
        )
            .prop_map(|(vertices, segs)| Curve2 {
                vertices,
                segments: segs.into_iter().filter(|s| s[0] != s[1]).collect(),
            })
    })
}

// ---------------------------------------------------------------- helpers

/// Bit patterns, so that a lost sign of zero or a last-bit error is caught.
fn bits(v: &[[f64; 3]]) -> Vec<[u64; 3]> {
    v.iter().map(|p| p.map(f64::to_bits)).collect()
}

fn assert_same(a: &TriMesh, b: &TriMesh) {
    assert_eq!(bits(&a.vertices), bits(&b.vertices));
    assert_eq!(a.triangles, b.triangles);
}

/// The triangles as corner coordinates (for formats that renumber vertices).
fn soup(m: &TriMesh) -> Vec<[[f64; 3]; 3]> {
    (0..m.triangles.len()).map(|t| m.corners(t)).collect()
}

fn format_line(e: Error) -> (&'static str, usize, String) {
    match e {
        Error::Format {
            format,
            line,
            message,
        } => (format, line, message),
        e => panic!("expected a format error, got {e:?}"),
    }
}

/// A fresh folder for one test, removed when the test ends (also when it fails).
fn scratch() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("certmesh-io-test-")
        .tempdir()
        .expect("create a temporary folder")
}

// ---------------------------------------------------------------- round trips

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn obj_round_trip(m in trimesh()) {
        let mut buf = Vec::new();
        obj::write(&mut buf, &m).unwrap();
        assert_same(&obj::read(&buf[..]).unwrap(), &m);
    }

    #[test]
    fn off_round_trip(m in trimesh()) {
        let mut buf = Vec::new();
        off::write(&mut buf, &m).unwrap();
        assert_same(&off::read(&buf[..]).unwrap(), &m);
    }

    #[test]
    fn ply_round_trip_all_encodings(m in trimesh()) {
        for enc in [ply::PlyEncoding::Ascii, ply::PlyEncoding::BinaryLittleEndian, ply::PlyEncoding::BinaryBigEndian] {
            let mut buf = Vec::new();
            ply::write(&mut buf, &m, enc).unwrap();
            assert_same(&ply::read(&buf[..]).unwrap(), &m);
        }
    }

    #[test]
    fn stl_binary_round_trip(m in trimesh_f32()) {
        let mut buf = Vec::new();
        stl::write(&mut buf, &m, stl::StlEncoding::Binary).unwrap();
        prop_assert_eq!(buf.len(), 84 + 50 * m.triangles.len());
        let r = stl::read(&buf[..]).unwrap();
        prop_assert_eq!(soup(&r), soup(&m));
        // Welding: one vertex per distinct used coordinate triple.
        let mut used: Vec<[u64; 3]> = m.triangles.iter().flatten()
            .map(|&i| m.vertices[i as usize].map(|c| (c + 0.0).to_bits())).collect();
        used.sort_unstable();
        used.dedup();
        prop_assert_eq!(r.vertices.len(), used.len());
    }

    #[test]
    fn stl_ascii_round_trip(m in trimesh()) {
        let mut buf = Vec::new();
        stl::write(&mut buf, &m, stl::StlEncoding::Ascii).unwrap();
        let r = stl::read(&buf[..]).unwrap();
        prop_assert_eq!(soup(&r), soup(&m));
        let back: Vec<_> = soup(&r).iter().flatten().map(|p| p.map(f64::to_bits)).collect();
        let orig: Vec<_> = soup(&m).iter().flatten().map(|p| p.map(|c| (c + 0.0).to_bits())).collect();
        // Bit-exact up to the sign of zero (welding identifies -0.0 with 0.0).
        let back: Vec<_> = back.into_iter().map(|p| p.map(|b| (f64::from_bits(b) + 0.0).to_bits())).collect();
        prop_assert_eq!(back, orig);
    }

    #[test]
    fn vtk_round_trip(m in tetmesh()) {
        let mut buf = Vec::new();
        vtk::write(&mut buf, &m).unwrap();
        let r = vtk::read(&buf[..]).unwrap();
        prop_assert_eq!(bits(&r.vertices), bits(&m.vertices));
        prop_assert_eq!(r.tets, m.tets);
    }

    #[test]
    fn vtk_surface_round_trip(m in trimesh()) {
        let mut buf = Vec::new();
        vtk::write_surface(&mut buf, &m).unwrap();
        let r = vtk::read_cells(&buf[..]).unwrap();
        prop_assert!(r.mesh.tets.is_empty());
        assert_same(&r.surface(), &m);
    }

    #[test]
    fn medit_round_trip(m in tetmesh()) {
        let mut buf = Vec::new();
        medit::write(&mut buf, &m, true).unwrap();
        let r = medit::read(&buf[..]).unwrap();
        prop_assert_eq!(bits(&r.mesh.vertices), bits(&m.vertices));
        prop_assert_eq!(&r.mesh.tets, &m.tets);
        prop_assert_eq!(r.triangles, medit::boundary_faces(&m));
    }

    #[test]
    fn medit_surface_round_trip(m in trimesh()) {
        let mut buf = Vec::new();
        medit::write_surface(&mut buf, &m).unwrap();
        assert_same(&medit::read(&buf[..]).unwrap().surface(), &m);
    }

    #[test]
    fn csv_round_trip(c in curve()) {
        let mut buf = Vec::new();
        csv::write(&mut buf, &c, csv::CsvLayout::Vertices).unwrap();
        let r = csv::read(&buf[..]).unwrap();
        let segs = |c: &Curve2| {
            let mut s: Vec<[[u64; 2]; 2]> = c.segments.iter().map(|&[a, b]| {
                let mut e = [c.vertices[a as usize].map(f64::to_bits), c.vertices[b as usize].map(f64::to_bits)];
                e.sort_unstable();
                e
            }).collect();
            s.sort_unstable();
            s
        };
        prop_assert_eq!(segs(&r), segs(&c));
        // The segment layout has one row per segment plus the header.
        let mut buf = Vec::new();
        csv::write(&mut buf, &c, csv::CsvLayout::Segments).unwrap();
        prop_assert_eq!(String::from_utf8(buf).unwrap().lines().count(), c.segments.len() + 1);
    }

    #[test]
    fn svg_draws_every_polyline_flipped(c in curve()) {
        let mut buf = Vec::new();
        // Coordinates near the double range may leave no room for the viewBox: such a
        // curve is refused with an error, never written with "inf" in it.
        let extreme = c.vertices.iter().flatten().any(|x| x.abs() > f64::MAX / 4.0);
        match svg::write(&mut buf, &c) {
            Err(Error::Param(_)) if extreme => return Ok(()),
            r => r.unwrap(),
        }
        let s = String::from_utf8(buf).unwrap();
        let lines = c.polylines();
        let drawn: Vec<&str> = s.lines().filter(|l| l.starts_with("<polyline") || l.starts_with("<polygon")).collect();
        prop_assert_eq!(drawn.len(), lines.len());
        let vb: Vec<f64> = s.split("viewBox=\"").nth(1).unwrap().split('"').next().unwrap()
            .split(' ').map(|t| t.parse().unwrap()).collect();
        for (l, (chain, closed)) in drawn.iter().zip(&lines) {
            prop_assert_eq!(l.starts_with("<polygon"), *closed);
            let pts: Vec<[f64; 2]> = l.split("points=\"").nth(1).unwrap().split('"').next().unwrap()
                .split(' ').map(|p| {
                    let mut xy = p.split(',').map(|t| t.parse::<f64>().unwrap());
                    [xy.next().unwrap(), xy.next().unwrap()]
                }).collect();
            let n = if *closed { chain.len() - 1 } else { chain.len() };
            prop_assert_eq!(pts.len(), n);
            for (p, &i) in pts.iter().zip(chain) {
                let v = c.vertices[i as usize];
                prop_assert_eq!(p[0].to_bits(), v[0].to_bits());
                prop_assert_eq!(p[1].to_bits(), (-v[1]).to_bits());
                // Inside the viewBox (up to rounding of its huge-coordinate corners).
                let tol = 1e-9 * vb.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                prop_assert!(tol.is_finite());
                prop_assert!(p[0] >= vb[0] - tol && p[0] <= vb[0] + vb[2] + tol);
                prop_assert!(p[1] >= vb[1] - tol && p[1] <= vb[1] + vb[3] + tol);
            }
        }
    }
}

#[test]
fn empty_meshes_round_trip() {
    let m = TriMesh::default();
    for enc in [
        ply::PlyEncoding::Ascii,
        ply::PlyEncoding::BinaryLittleEndian,
    ] {
        let mut buf = Vec::new();
        ply::write(&mut buf, &m, enc).unwrap();
        assert_eq!(ply::read(&buf[..]).unwrap(), m);
    }
    for enc in [stl::StlEncoding::Ascii, stl::StlEncoding::Binary] {
        let mut buf = Vec::new();
        stl::write(&mut buf, &m, enc).unwrap();
        assert_eq!(stl::read(&buf[..]).unwrap(), m);
    }
    let mut buf = Vec::new();
    obj::write(&mut buf, &m).unwrap();
    assert_eq!(obj::read(&buf[..]).unwrap(), m);
    let mut buf = Vec::new();
    vtk::write(&mut buf, &TetMesh::default()).unwrap();
    assert_eq!(vtk::read(&buf[..]).unwrap(), TetMesh::default());
}

#[test]
fn writers_refuse_what_would_not_read_back() {
    let nan = TriMesh::new(vec![[0.0, f64::NAN, 0.0]], vec![]);
    assert!(matches!(
        obj::write(Vec::new(), &nan),
        Err(Error::NotFinite(_))
    ));
    let bad = TriMesh::new(vec![[0.0; 3]; 3], vec![[0, 1, 3]]);
    assert!(matches!(off::write(Vec::new(), &bad), Err(Error::Param(_))));
    let big = TriMesh::new(vec![[1e300, 0.0, 0.0], [0.0; 3], [1.0; 3]], vec![[0, 1, 2]]);
    assert!(matches!(
        stl::write(Vec::new(), &big, stl::StlEncoding::Binary),
        Err(Error::Param(_))
    ));
    let inf = TetMesh {
        vertices: vec![[f64::INFINITY; 3]],
        tets: vec![],
    };
    assert!(matches!(
        vtk::write(Vec::new(), &inf),
        Err(Error::NotFinite(_))
    ));
}

/// Writing over an existing file (overwritten in place, then cut to length): a
/// smaller mesh over a larger one, and a larger over a smaller, leave exactly the
/// bytes a fresh file gets, in every triangle format; a write refused for a NaN
/// vertex leaves the file empty, as a truncated file was before.
#[test]
fn writing_over_an_existing_file_leaves_only_the_new_mesh() {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    let grid = |n: u32| {
        let vertices: Vec<[f64; 3]> = (0..n * n)
            .map(|k| [(k % n) as f64 * 0.25, (k / n) as f64 * 0.5, 0.125])
            .collect();
        let triangles: Vec<[u32; 3]> = (0..n - 1)
            .flat_map(|j| (0..n - 1).map(move |i| [j * n + i, j * n + i + 1, (j + 1) * n + i]))
            .collect();
        TriMesh::new(vertices, triangles)
    };
    let (big, small) = (grid(30), grid(3));
    for ext in ["ply", "obj", "off", "stl", "vtk", "mesh"] {
        let fresh = tmp(&format!("over-fresh.{ext}"));
        let over = tmp(&format!("over.{ext}"));
        for (first, second) in [(&big, &small), (&small, &big)] {
            let _ = std::fs::remove_file(&fresh);
            io::write_tri(&fresh, second).unwrap();
            io::write_tri(&over, first).unwrap();
            io::write_tri(&over, second).unwrap();
            let (a, b) = (
                std::fs::read(&fresh).unwrap(),
                std::fs::read(&over).unwrap(),
            );
            assert_eq!(a.len(), b.len(), "{ext}: length after writing over");
            assert!(a == b, "{ext}: bytes after writing over");
            assert_eq!(
                soup(&io::read_tri(&over).unwrap()),
                soup(&io::read_tri(&fresh).unwrap())
            );
        }
        let nan = TriMesh::new(vec![[0.0, f64::NAN, 0.0]; 3], vec![[0, 1, 2]]);
        assert!(matches!(
            io::write_tri(&over, &nan),
            Err(Error::NotFinite(_))
        ));
        assert_eq!(
            std::fs::metadata(&over).unwrap().len(),
            0,
            "{ext}: after a refused write"
        );
    }
}

/// A mesh written into a FIFO reaches its reader whole (a FIFO has no length to cut
/// and no position: the writer must not ask for them).
#[cfg(unix)]
#[test]
fn writing_into_a_fifo_gives_the_reader_the_file() {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    let fifo = tmp("into.ply");
    let _ = std::fs::remove_file(&fifo);
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("mkfifo is not available: skipped");
        return;
    }
    let m = TriMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
    );
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    io::write_tri(&fifo, &m).unwrap();
    let got = reader.join().unwrap();
    let mut want = Vec::new();
    ply::write(&mut want, &m, ply::PlyEncoding::BinaryLittleEndian).unwrap();
    assert!(
        got == want,
        "{} bytes read, {} written",
        got.len(),
        want.len()
    );
    std::fs::remove_file(&fifo).unwrap();
}

// ---------------------------------------------------------------- malformed input

#[test]
fn every_reader_locates_errors() {
    // (reader, input, format, line)
    type Reader = fn(&[u8]) -> Result<(), Error>;
    let rd_obj: Reader = |d| obj::parse(d).map(|_| ());
    let rd_off: Reader = |d| off::parse(d).map(|_| ());
    let rd_ply: Reader = |d| ply::parse(d).map(|_| ());
    let rd_stl: Reader = |d| stl::parse(d).map(|_| ());
    let rd_vtk: Reader = |d| vtk::parse(d).map(|_| ());
    let rd_medit: Reader = |d| medit::parse(d).map(|_| ());
    let rd_csv: Reader = |d| csv::parse(d).map(|_| ());
    let cases: Vec<(Reader, &[u8], &str, usize)> = vec![
        (rd_obj, b"v 0 0 0\nv 0 0 0\nf 1 2 3\n", "OBJ", 3),
        (rd_obj, b"v 0 0 0\nv 0 0 NaN\n", "OBJ", 2),
        (rd_obj, b"v 0 0 0\nf 1 1 99999999999999999999999\n", "OBJ", 2),
        (rd_obj, b"v 0 0 0\nf -1 -1 -2\n", "OBJ", 2),
        (rd_obj, b"#\n\nv 0 \xc3\x28 0\n", "OBJ", 3),
        (rd_off, b"OFF\n1 1 0\n0 0 0\n3 0 0 1\n", "OFF", 4),
        (rd_off, b"OFF\n1 0 0\n0 0\n", "OFF", 3),
        (rd_off, b"OFF\n99999999999 0 0\n0 0 0\n", "OFF", 4),
        (
            rd_ply,
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 inf\n",
            "PLY",
            8,
        ),
        (rd_ply, b"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n\0\0\0\0", "PLY", 0),
        (rd_ply, b"ply\nformat ascii 2.0x\nformat lisp 1.0\n", "PLY", 3),
        (rd_stl, b"solid a\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 1 1\nvertex 1 1 nan\n", "STL", 6),
        (rd_stl, b"solid a\nendsolid a\nsolid b\nfacet\nendloop\n", "STL", 5),
        (rd_stl, &[0u8; 90], "STL", 0),
        (rd_vtk, b"# vtk DataFile Version 2.0\n\nASCII\nDATASET POLYDATA\n", "VTK", 4),
        (rd_vtk, b"# vtk DataFile Version 2.0\n\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 2 double\n0 0 0 1 1\n", "VTK", 7),
        (
            rd_vtk,
            b"# vtk DataFile Version 2.0\n\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 999999999999999999 double\n0 0 0\n",
            "VTK",
            7,
        ),
        (rd_medit, b"MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 0 0\nTetrahedra\n1\n1 1 1 2 0\n", "MEDIT", 8),
        (rd_medit, b"MeshVersionFormatted 2\nDimension 3\nVertices\n1000000000000000\n0 0 0 0\n", "MEDIT", 6),
        (rd_csv, b"polyline,closed,vertex,x,y\n0,true,1,0,0\n0,true,1,0,1\n", "CSV", 3),
    ];
    for (read, input, format, line) in cases {
        let got = format_line(read(input).expect_err(&String::from_utf8_lossy(input)));
        assert_eq!(
            (got.0, got.1),
            (format, line),
            "{:?}: {}",
            String::from_utf8_lossy(input),
            got.2
        );
        assert!(!got.2.is_empty());
    }
}

#[test]
fn truncated_binary_reports_byte_offsets() {
    let m = TriMesh::new(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    );
    let mut buf = Vec::new();
    ply::write(&mut buf, &m, ply::PlyEncoding::BinaryLittleEndian).unwrap();
    for cut in 1..(4 * 24 + 4 * 13) {
        let (f, line, msg) = format_line(ply::parse(&buf[..buf.len() - cut]).unwrap_err());
        assert_eq!((f, line), ("PLY", 0));
        assert!(msg.contains("byte offset"), "{msg}");
    }
    let mut buf = Vec::new();
    stl::write(&mut buf, &m, stl::StlEncoding::Binary).unwrap();
    for cut in 1..buf.len() - 84 {
        let (f, line, msg) = format_line(stl::parse(&buf[..buf.len() - cut]).unwrap_err());
        assert_eq!((f, line), ("STL", 0));
        assert!(msg.contains("byte offset"), "{msg}");
    }
}

// ---------------------------------------------------------------- real meshes

fn data(name: &str) -> PathBuf {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name);
    assert!(p.exists(), "test mesh {} is missing", p.display());
    p
}

/// Counts made without the OBJ reader: `v ` lines, and triangles from `f ` lines.
fn count_obj(path: &Path) -> (usize, usize) {
    let text = std::fs::read_to_string(path).unwrap();
    let v = text.lines().filter(|l| l.starts_with("v ")).count();
    let f = text
        .lines()
        .filter(|l| l.starts_with("f "))
        .map(|l| l.split_whitespace().count() - 3)
        .sum();
    (v, f)
}

#[test]
fn real_meshes_load_with_the_right_counts() {
    for (name, v, f) in [
        ("stanford-bunny.obj", 35947, 69451),
        ("spot.obj", 2930, 5856),
        ("fandisk.obj", 6475, 12946),
    ] {
        let p = data(name);
        assert_eq!(count_obj(&p), (v, f), "{name}");
        let m = io::read_tri(&p).unwrap();
        assert_eq!((m.vertices.len(), m.triangles.len()), (v, f), "{name}");
        if name == "stanford-bunny.obj" {
            // The scan has vertices no face uses.
            let mut used = vec![false; m.vertices.len()];
            m.triangles
                .iter()
                .flatten()
                .for_each(|&i| used[i as usize] = true);
            let unused = used.iter().filter(|u| !**u).count();
            // Independently: vertex numbers that no `f` line of the text mentions.
            let text = std::fs::read_to_string(&p).unwrap();
            let mut seen = std::collections::HashSet::new();
            for l in text.lines().filter(|l| l.starts_with("f ")) {
                for t in l.split_whitespace().skip(1) {
                    seen.insert(t.split('/').next().unwrap().to_string());
                }
            }
            assert_eq!(unused, v - seen.len());
            assert_eq!(unused, 1113);
        }
    }
}

#[test]
fn spot_survives_every_triangle_format() {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    let m = io::read_tri(data("spot.obj")).unwrap();
    for ext in ["obj", "OFF", "ply", "vtk", "mesh"] {
        let p = tmp(&format!("spot.{ext}"));
        io::write_tri(&p, &m).unwrap();
        assert_same(&io::read_tri(&p).unwrap(), &m);
    }
    let p = tmp("spot.stl");
    io::write_tri(&p, &m).unwrap();
    let r = io::read_tri(&p).unwrap();
    // STL renumbers vertices by first appearance and rounds to f32; spot's vertices
    // are distinct (also in f32) and all used, so the count is unchanged.
    assert_eq!(r.vertices.len(), m.vertices.len());
    let rounded: Vec<_> = soup(&m)
        .iter()
        .map(|t| t.map(|p| p.map(|c| c as f32 as f64)))
        .collect();
    assert!(
        soup(&r) == rounded,
        "STL triangles differ from spot's rounded to f32"
    );
}

// ---------------------------------------------------------------- dispatch

#[test]
fn formats_by_extension() {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    assert_eq!(Format::from_path("a/b.OBJ").unwrap(), Format::Obj);
    assert_eq!(Format::from_path("x.Mesh").unwrap(), Format::Medit);
    for f in Format::ALL {
        assert_eq!(
            Format::from_path(format!("m.{}", f.extension())).unwrap(),
            f
        );
    }
    match Format::from_path("model.3ds") {
        Err(Error::Unknown { kind, name, known }) => {
            assert_eq!((kind, name.as_str()), ("mesh format", "3ds"));
            assert!(known.contains("ply"));
        }
        r => panic!("{r:?}"),
    }
    assert!(matches!(
        io::read_tri("noext"),
        Err(Error::Unknown {
            kind: "mesh format",
            ..
        })
    ));
    assert!(matches!(
        io::write_tri(tmp("a.svg"), &TriMesh::default()),
        Err(Error::Unknown {
            kind: "triangle mesh format",
            ..
        })
    ));
    assert!(matches!(
        io::write_curve(tmp("a.obj"), &Curve2::default()),
        Err(Error::Unknown {
            kind: "curve format",
            ..
        })
    ));
    assert!(matches!(
        io::read_tri(tmp("missing.obj")),
        Err(Error::Io { .. })
    ));
}

#[test]
fn tet_and_curve_files_by_extension() {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    let t = TetMesh {
        vertices: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        tets: vec![[0, 1, 2, 3]],
    };
    for ext in ["vtk", "mesh"] {
        let p = tmp(&format!("t.{ext}"));
        io::write_tet(&p, &t).unwrap();
        assert_eq!(io::read_tet(&p).unwrap(), t);
    }
    // The .mesh file also carries the boundary, readable as a triangle mesh.
    let b = io::read_tri(tmp("t.mesh")).unwrap();
    assert_eq!(b.triangles.len(), 4);
    let c = Curve2 {
        vertices: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
        segments: vec![[0, 1], [1, 2], [2, 0]],
    };
    io::write_curve(tmp("c.svg"), &c).unwrap();
    io::write_curve(tmp("c.CSV"), &c).unwrap();
    let text = std::fs::read_to_string(tmp("c.CSV")).unwrap();
    assert_eq!(
        text.lines().count(),
        1 + 4,
        "header + closed triangle with its first vertex repeated"
    );
    assert!(std::fs::read_to_string(tmp("c.svg"))
        .unwrap()
        .contains("<polygon"));
}
