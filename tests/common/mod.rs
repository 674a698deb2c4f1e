//! Hand-built meshes whose topology and geometry are known exactly, shared by the
//! metrics and topology tests.
#![allow(dead_code)]
use certmesh::catalog::{self, Topology};
use certmesh::kernel::geom;
use certmesh::mesh::{TetMesh, TriMesh};
use certmesh::metrics::angles;
use proptest::prelude::*;

// ---------------------------------------------------------------- hand-built meshes

pub fn tetra_surface(offset: [f64; 3]) -> TriMesh {
    let v = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let v = v.into_iter().map(|p| geom::add(p, offset)).collect();
    // Outward (counter-clockwise seen from outside).
    TriMesh::new(v, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
}

pub fn cube_surface() -> TriMesh {
    let mut v = Vec::new();
    for i in 0..8 {
        v.push([(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64]);
    }
    // Each face as a counter-clockwise quad seen from outside.
    let quads = [
        [0, 2, 3, 1], // z = 0, normal -z
        [4, 5, 7, 6], // z = 1
        [0, 1, 5, 4], // y = 0
        [2, 6, 7, 3], // y = 1
        [0, 4, 6, 2], // x = 0
        [1, 3, 7, 5], // x = 1
    ];
    let mut t = Vec::new();
    for q in quads {
        t.push([q[0], q[1], q[2]]);
        t.push([q[0], q[2], q[3]]);
    }
    TriMesh::new(v, t)
}

/// A torus (R = 1, r = 0.3) from an n × m quad grid with wrap-around indices.
pub fn torus(n: u32, m: u32) -> TriMesh {
    let mut v = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let u = i as f64 / n as f64 * std::f64::consts::TAU;
            let w = j as f64 / m as f64 * std::f64::consts::TAU;
            let rr = 1.0 + 0.3 * w.cos();
            v.push([rr * u.cos(), rr * u.sin(), 0.3 * w.sin()]);
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + (j % m);
    let mut t = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    TriMesh::new(v, t)
}

/// Icosahedron subdivided `level` times, projected on the unit sphere; outward
/// (`certmesh::mesh::icosphere`).
pub fn icosphere(level: u32) -> TriMesh {
    certmesh::mesh::icosphere(level)
}

pub fn sphere_topology() -> Topology {
    catalog::get("sphere").unwrap().topology.unwrap()
}

pub fn concat(a: &TriMesh, b: &TriMesh) -> TriMesh {
    let n = a.vertices.len() as u32;
    let mut m = a.clone();
    m.vertices.extend(&b.vertices);
    m.triangles
        .extend(b.triangles.iter().map(|t| t.map(|i| i + n)));
    m
}

pub fn polygon(n: u32, center: [f64; 2], r: f64, first: u32) -> (Vec<[f64; 2]>, Vec<[u32; 2]>) {
    let v = (0..n)
        .map(|i| {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            [center[0] + r * a.cos(), center[1] + r * a.sin()]
        })
        .collect();
    let s = (0..n).map(|i| [first + i, first + (i + 1) % n]).collect();
    (v, s)
}

pub fn cube_tets() -> TetMesh {
    let mut v = Vec::new();
    for i in 0..8 {
        v.push([(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64]);
    }
    // Six tetrahedra around the diagonal 0-7 (Kuhn triangulation).
    let paths = [[1, 3], [1, 5], [2, 3], [2, 6], [4, 5], [4, 6]];
    let tets = paths
        .iter()
        .map(|&[a, b]| {
            let t = [0u32, a, b, 7];
            let p = t.map(|i| v[i as usize]);
            if angles::signed_volume6(&p) > 0.0 {
                t
            } else {
                [0, b, a, 7]
            }
        })
        .collect();
    TetMesh { vertices: v, tets }
}

// ---------------------------------------------------------------- floats

/// Floats of every scale: ordinary, integers, tiny and huge (to reach the fallback
/// paths), signed zeros and infinities.
pub fn arb_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -100.0f64..100.0,
        2 => (-20i32..20).prop_map(|k| k as f64 / 4.0),
        2 => (1u64..(1u64 << 52), -700i32..700, any::<bool>()).prop_map(|(m, e, s)| {
            let x = (1.0 + m as f64 / (1u64 << 52) as f64) * 2f64.powi(e);
            if s { -x } else { x }
        }),
        1 => Just(0.0),
        1 => Just(-0.0),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(f64::MAX),
        1 => Just(f64::from_bits(1)),
    ]
}
