//! The Goldberg tetrahedron τ(a, e) and the space-filling tiling by its copies
//! (Hass & Trnkova 2020, Sec. 4.1, Fig 6), as plain data shared with the `proofs` crate.
//!
//! Construction (Sec. 4.1): tile the xy-plane by equilateral triangles of side `e`.
//! Colour the triangular lattice points with three colours, c(i, j) = (i − j) mod 3,
//! so every triangle has one vertex of each colour. Over a lattice point of colour c
//! the tiling has vertices at the heights z = m·a with m ≡ c (mod 3). Over each
//! triangle the *helix* v_k = (vertex of colour m + k, height (m + k)·a), k = 0..3,
//! rises by `a` along each triangle edge; the tetrahedron conv(v_0..v_3) and its
//! translates by 3a fill the prism over the triangle (one tetrahedron per height step
//! `a`), and neighbouring prisms agree on their common walls because the walls'
//! zig-zag edges depend only on the colours.
//!
//! Labels (Sec. 4.2–4.3, Appendix): A = v_0, B = v_3, C = v_1, D = v_2, so that AB is
//! the vertical edge of length 3a, AD and BC are the two 90° edges (rise 2a), and the
//! triangles KLM, KNQ have edge lengths (b/2, b/2, c/2) and LNP, MPQ (3a/2, b/2, c/2)
//! as the Appendix states (b = |AC| = |CD| = |BD| rises a, c = |AD| = |BC| rises 2a).
//! The computation in `papers/gradnormal/GOLDBERG.md` checks these claims for each a.
use crate::kernel::geom::{cross, dot, norm, scale, sub};
use std::f64::consts::SQRT_2;

/// Vertex labels of the tetrahedron.
pub const LABELS: [&str; 4] = ["A", "B", "C", "D"];
/// Label index → helix index: A = v0, B = v3, C = v1, D = v2.
pub const HELIX_OF_LABEL: [usize; 4] = [0, 3, 1, 2];

/// Label indices, for readable tables.
pub const A: usize = 0;
pub const B: usize = 1;
pub const C: usize = 2;
pub const D: usize = 3;

/// Edge midpoints: K = AB, L = AC, M = AD, N = BC, P = CD, Q = BD (Fig 6(a)).
pub const MIDPOINT_NAMES: [&str; 6] = ["K", "L", "M", "N", "P", "Q"];
/// The edge (pair of labels) of each midpoint, in the order of [`MIDPOINT_NAMES`].
pub const MIDPOINT_EDGES: [[usize; 2]; 6] = [[A, B], [A, C], [A, D], [B, C], [C, D], [B, D]];
pub const K: usize = 0;
pub const L: usize = 1;
pub const M: usize = 2;
pub const N: usize = 3;
pub const P: usize = 4;
pub const Q: usize = 5;

/// The four elementary normal triangles (Sec. 4.3): the label cut off, and the
/// midpoints of its three edges.
pub const NORMAL_TRIANGLES: [(usize, [usize; 3]); 4] = [
    (A, [K, L, M]),
    (B, [K, N, Q]),
    (C, [L, N, P]),
    (D, [M, P, Q]),
];

/// An elementary normal quadrilateral and the paper's diagonal (Algorithm 1, line 6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NormalQuad {
    /// The paper's name.
    pub name: &'static str,
    /// The pair of labels on A's side (the other pair is the complement).
    pub side: [usize; 2],
    /// The four midpoints in cyclic order around the quadrilateral.
    pub cycle: [usize; 4],
    /// The paper's diagonal (two midpoints, opposite in `cycle`).
    pub diagonal: [usize; 2],
}

/// The three quadrilaterals with the paper's diagonals: LMNQ → MN, KMPN → MN, KLPQ → LQ.
pub const NORMAL_QUADS: [NormalQuad; 3] = [
    NormalQuad {
        name: "LMNQ",
        side: [A, B],
        cycle: [L, M, Q, N],
        diagonal: [M, N],
    },
    NormalQuad {
        name: "KMPN",
        side: [A, C],
        cycle: [K, M, P, N],
        diagonal: [M, N],
    },
    NormalQuad {
        name: "KLPQ",
        side: [A, D],
        cycle: [K, L, P, Q],
        diagonal: [L, Q],
    },
];

impl NormalQuad {
    /// The other diagonal.
    pub fn alternate_diagonal(&self) -> [usize; 2] {
        let i = self
            .cycle
            .iter()
            .position(|&x| x == self.diagonal[0])
            .unwrap_or(0);
        let j = (i + 1) % 4;
        [self.cycle[j], self.cycle[(j + 2) % 4]]
    }
}

/// a/e of the Sommerville (body-centred cubic) tetrahedron: √2/4 (Appendix A, "the
/// rhombus is a square"). Established by [`Goldberg::dihedral_angles`]; see GOLDBERG.md.
pub const SOMMERVILLE_RATIO: f64 = SQRT_2 / 4.0;

/// The three values of a/e the paper states: e/4 (Sec. 1), e/2 (Sec. 4.1), e·√2/4
/// (Appendix A).
pub const PAPER_RATIOS: [(&str, f64); 3] = [
    ("Sec. 1: a = e/4", 0.25),
    ("Sec. 4.1: a = e/2", 0.5),
    ("Appendix A: a = e*sqrt(2)/4", SOMMERVILLE_RATIO),
];

/// The tetrahedron τ(a, e): triangle side `e`, height step `a` (absolute lengths).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Goldberg {
    pub e: f64,
    pub a: f64,
}

/// sqrt(3)/2.
const H: f64 = 0.866_025_403_784_438_6;

impl Goldberg {
    /// The Sommerville tetrahedron of the BCC lattice at scale `e`.
    pub fn sommerville(e: f64) -> Self {
        Goldberg {
            e,
            a: e * SOMMERVILLE_RATIO,
        }
    }
    /// τ(ratio·e, e).
    pub fn with_ratio(e: f64, ratio: f64) -> Self {
        Goldberg { e, a: e * ratio }
    }
    /// Position of lattice vertex (i, j, m); valid when m ≡ i − j (mod 3).
    #[inline]
    pub fn vertex(&self, i: i64, j: i64, m: i64) -> [f64; 3] {
        [
            self.e * (i as f64 + 0.5 * j as f64),
            self.e * H * j as f64,
            self.a * m as f64,
        ]
    }
    /// The canonical tetrahedron over the triangle (0,0), (e,0), (e/2, e√3/2), in label
    /// order A, B, C, D.
    pub fn tetrahedron(&self) -> [[f64; 3]; 4] {
        let t = TetType::all()[0];
        let v = t.verts.map(|[i, j, m]| self.vertex(i, j, m));
        [v[A], v[B], v[C], v[D]]
    }
    /// Edge lengths in the order of [`MIDPOINT_EDGES`] (AB, AC, AD, BC, CD, BD).
    pub fn edge_lengths(&self) -> [f64; 6] {
        let t = self.tetrahedron();
        MIDPOINT_EDGES.map(|[p, q]| norm(sub(t[p], t[q])))
    }
    /// Interior dihedral angles (degrees) at the edges, in the order of
    /// [`MIDPOINT_EDGES`].
    pub fn dihedral_angles(&self) -> [f64; 6] {
        let t = self.tetrahedron();
        MIDPOINT_EDGES.map(|[p, q]| {
            let others: Vec<usize> = (0..4).filter(|&k| k != p && k != q).collect();
            let axis = sub(t[q], t[p]);
            // Components of the two opposite vertices orthogonal to the edge.
            let perp = |r: usize| {
                let w = sub(t[r], t[p]);
                sub(w, scale(axis, dot(w, axis) / dot(axis, axis)))
            };
            let (u, v) = (perp(others[0]), perp(others[1]));
            norm(cross(u, v)).atan2(dot(u, v)).to_degrees()
        })
    }
    /// Volume of one tetrahedron: (√3/4)e²·a (one per height step a per prism).
    pub fn tet_volume(&self) -> f64 {
        0.5 * H * self.e * self.e * self.a
    }
    /// The Sommerville scale e at which `n` tetrahedra have total volume `volume`
    /// (the paper counts tetrahedra tiling the unit cube).
    pub fn scale_for_count(volume: f64, n: f64, ratio: f64) -> f64 {
        (volume / (n * 0.5 * H * ratio)).cbrt()
    }
}

/// One of the six translation classes of tetrahedra: the anchor triangle is "up"
/// (i,j),(i+1,j),(i,j+1) or "down" (i+1,j),(i,j+1),(i+1,j+1), and the helix starts
/// at the triangle vertex whose colour is r above the anchor's colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TetType {
    pub down: bool,
    pub r: u8,
    /// Vertex offsets (di, dj, dm) from (i, j, m) in *label* order A, B, C, D.
    pub verts: [[i64; 3]; 4],
}

impl TetType {
    /// Index 0..6 = 3·down + r.
    pub fn index(down: bool, r: i64) -> usize {
        3 * down as usize + r as usize
    }
    /// All six types, indexed by [`TetType::index`].
    pub fn all() -> [TetType; 6] {
        // Triangle vertices with their colour relative to the anchor (i, j).
        let up = [([0, 0], 0), ([1, 0], 1), ([0, 1], 2)];
        let down = [([1, 0], 1), ([0, 1], 2), ([1, 1], 0)];
        let mut out = [TetType {
            down: false,
            r: 0,
            verts: [[0; 3]; 4],
        }; 6];
        for (d, tri) in [(false, up), (true, down)] {
            for r in 0..3i64 {
                // Helix: v_k has colour r + k (mod 3) and height offset k.
                let helix: [[i64; 3]; 4] = [0, 1, 2, 3].map(|k| {
                    let col = (r + k) % 3;
                    let (ij, _) = tri.iter().find(|(_, c)| *c == col).copied().unwrap();
                    [ij[0], ij[1], k]
                });
                let verts = HELIX_OF_LABEL.map(|h| helix[h]);
                out[Self::index(d, r)] = TetType {
                    down: d,
                    r: r as u8,
                    verts,
                };
            }
        }
        out
    }
}

/// Upward lattice edge directions from a vertex (di, dj, dm): the vertical edge and
/// the six neighbours in the triangular lattice (three rise a, three rise 2a).
pub const EDGE_DIRS: [[i64; 3]; 7] = [
    [0, 0, 3],
    [1, 0, 1],
    [-1, 1, 1],
    [0, -1, 1],
    [0, 1, 2],
    [-1, 0, 2],
    [1, -1, 2],
];

/// The direction index of the edge from offset `p` to offset `q` (q above p), if any.
pub fn edge_dir(p: [i64; 3], q: [i64; 3]) -> Option<(bool, usize)> {
    let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
    if let Some(k) = EDGE_DIRS.iter().position(|&x| x == d) {
        return Some((false, k));
    }
    let n = [-d[0], -d[1], -d[2]];
    EDGE_DIRS.iter().position(|&x| x == n).map(|k| (true, k))
}

/// Bits per coordinate of a packed lattice vertex key.
pub const KEY_BITS: u32 = 20;
/// Offset making coordinates non-negative in a key; coordinates must lie in
/// (−KEY_OFFSET, KEY_OFFSET).
pub const KEY_OFFSET: i64 = 1 << (KEY_BITS - 1);

/// A lattice vertex packed into 60 bits.
#[inline]
pub fn vertex_key(i: i64, j: i64, m: i64) -> u64 {
    (((i + KEY_OFFSET) as u64) << (2 * KEY_BITS))
        | (((j + KEY_OFFSET) as u64) << KEY_BITS)
        | ((m + KEY_OFFSET) as u64)
}

/// Unpack a vertex key.
#[inline]
pub fn unpack_vertex(k: u64) -> [i64; 3] {
    let mask = (1u64 << KEY_BITS) - 1;
    [
        ((k >> (2 * KEY_BITS)) & mask) as i64 - KEY_OFFSET,
        ((k >> KEY_BITS) & mask) as i64 - KEY_OFFSET,
        (k & mask) as i64 - KEY_OFFSET,
    ]
}

/// A lattice edge: its lower vertex and upward direction, packed into 63 bits. One
/// mesh vertex per lattice edge (MidNormal's vertices are edge midpoints).
#[inline]
pub fn edge_key(i: i64, j: i64, m: i64, dir: usize) -> u64 {
    (vertex_key(i, j, m) << 3) | dir as u64
}

/// The two endpoints of an edge key.
pub fn edge_endpoints(k: u64) -> ([i64; 3], [i64; 3]) {
    let p = unpack_vertex(k >> 3);
    let d = EDGE_DIRS[(k & 7) as usize];
    (p, [p[0] + d[0], p[1] + d[1], p[2] + d[2]])
}

/// Colour of a triangular-lattice point.
#[inline]
pub fn colour(i: i64, j: i64) -> i64 {
    (i - j).rem_euclid(3)
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn vertex_keys_roundtrip() {
        for &(i, j, m) in &[(0, 0, 0), (-5, 7, -300), (1000, -1000, 77)] {
            assert_eq!(unpack_vertex(vertex_key(i, j, m)), [i, j, m]);
        }
    }
    #[test]
    fn helix_types_are_lattice_tets() {
        for t in TetType::all() {
            for v in t.verts {
                // Every vertex lies on the lattice when the anchor colour is 0 and m = r.
                assert_eq!((v[2] + t.r as i64 - colour(v[0], v[1])).rem_euclid(3), 0);
            }
            for [p, q] in MIDPOINT_EDGES {
                assert!(edge_dir(t.verts[p], t.verts[q]).is_some());
            }
        }
    }
}
