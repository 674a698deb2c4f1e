//! The project's GradNormal tiling data, as the proof reads it.
//!
//! **Merge note.** Everything in this module mirrors `certmesh::gradnormal::tiling`
//! (and `DiagonalRule` from `certmesh::gradnormal`), written on the `gradnormal` branch
//! in parallel with this crate, with the same names, types and values. When that module is
//! merged, replace the body of this file by
//!
//! ```ignore
//! pub use certmesh::gradnormal::tiling::{
//!     Goldberg, NormalQuad, TetType, A, B, C, D, EDGE_DIRS, HELIX_OF_LABEL, K, L, LABELS, M,
//!     MIDPOINT_EDGES, MIDPOINT_NAMES, N, NORMAL_QUADS, NORMAL_TRIANGLES, P, PAPER_RATIOS, Q,
//!     SOMMERVILLE_RATIO,
//! };
//! pub use certmesh::gradnormal::DiagonalRule;
//! ```
//!
//! so the proof verifies exactly the data the mesher uses. The proof only reads
//! [`TetType::all`]`()[0].verts` (lattice coordinates of τ in label order), the label and
//! midpoint tables, the quadrilaterals with their diagonals, [`EDGE_DIRS`]`[0]` (the
//! vertical lattice edge, which fixes the paper's diagonal of the valence-four square) and
//! [`DiagonalRule`].

/// Vertex labels of the tetrahedron.
pub const LABELS: [&str; 4] = ["A", "B", "C", "D"];
/// Label index → helix index: A = v0, B = v3, C = v1, D = v2.
pub const HELIX_OF_LABEL: [usize; 4] = [0, 3, 1, 2];

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
/// rhombus is a square").
pub const SOMMERVILLE_RATIO: f64 = std::f64::consts::SQRT_2 / 4.0;

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
                    let ij = tri
                        .iter()
                        .find(|(_, c)| *c == col)
                        .map(|(ij, _)| *ij)
                        .unwrap_or([0, 0]);
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

/// How a quadrilateral (an elementary normal quadrilateral, or the square left by a
/// valence-four removal) is split into two triangles (mirror of
/// `certmesh::gradnormal::DiagonalRule`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DiagonalRule {
    /// The paper's diagonals: LMNQ → MN, KMPN → MN, KLPQ → LQ (Algorithm 1), and K K₂ for
    /// the valence-four square (Appendix A, the triangle K L K₂).
    #[default]
    Paper,
    /// The other diagonal of every quadrilateral.
    Alternate,
    /// The shorter diagonal after the projection (GradNormal) or of the midpoint
    /// quadrilateral (MidNormal, where ties go to the paper's).
    Shorter,
}

impl std::str::FromStr for DiagonalRule {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "paper" => Ok(DiagonalRule::Paper),
            "alternate" => Ok(DiagonalRule::Alternate),
            "shorter" => Ok(DiagonalRule::Shorter),
            _ => Err(format!(
                "unknown diagonal rule `{s}` (known: paper alternate shorter)"
            )),
        }
    }
}

impl DiagonalRule {
    pub fn name(&self) -> &'static str {
        match self {
            DiagonalRule::Paper => "paper",
            DiagonalRule::Alternate => "alternate",
            DiagonalRule::Shorter => "shorter",
        }
    }
}
