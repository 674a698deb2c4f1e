//! Marching cubes (Lorensen & Cline 1987) with a consistent face rule instead of the
//! classic (crack-prone) 15-case table.
//!
//! The 256-case table is *derived* at first use, not typed in: for each sign case,
//! on each of the 6 cube faces, walking counter-clockwise as seen from outside the
//! cube, every crossing where the sign goes from positive to negative is joined to the
//! next crossing. On a face with two crossings that is the only segment; on an
//! ambiguous face (+ − + −) it cuts each negative corner off by itself ("negative
//! corners are separated"), a rule that depends on the face signs only, so the two
//! cells sharing the face draw the same segments: no cracks. Each segment leaves its
//! negative corner on the right (seen from outside), so the loops they chain into run
//! counter-clockwise around the normal pointing toward f > 0. Every crossing edge
//! lies on two faces of the cube and gets one segment on each, so the segments chain
//! into closed loops, which are triangulated without a diagonal between two crossings
//! of the same face (two cells sharing a face could otherwise both draw it, making an
//! edge with four triangles).
use super::{extract, mesh_3d, GridParams, Place, Scheme};
use crate::error::Result;
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;
use crate::lattice::grid::Field;
use crate::mesh::TriMesh;
use crate::mesher::options::{Crossing, MesherOptions};
use crate::mesher::{MeshOutput, Mesher, Progress};
use std::sync::OnceLock;

/// Marching cubes, `"mc"`. Defaults ([`GridParams::default`]): 64 cells along the
/// longest side, linear interpolation, no pruning.
///
/// ```
/// use certmesh::marching::MarchingCubes;
/// use certmesh::mesher::{Mesher, NoProgress};
/// use certmesh::{Aabb, Formula};
/// let f = Formula::surface("x^2 + y^2 + z^2 - 1").unwrap();
/// let out = MarchingCubes::new().resolution(16).mesh(&f, &Aabb::cube(1.5), &NoProgress).unwrap();
/// assert!(!out.certificate.is_certified());
/// assert!(out.mesh.surface().unwrap().triangles.len() > 100);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MarchingCubes {
    pub params: GridParams,
}

impl MarchingCubes {
    pub fn new() -> Self {
        Self::default()
    }
    /// Cells along the longest side of the domain (default 64).
    pub fn resolution(mut self, n: usize) -> Self {
        self.params.resolution = n;
        self
    }
    /// Linear interpolation (default) or bisection on f.
    pub fn crossing(mut self, c: Crossing) -> Self {
        self.params.crossing = c;
        self
    }
    /// Bisection tolerance, as a fraction of the edge (default 1e-6).
    pub fn tolerance(mut self, t: f64) -> Self {
        self.params.tolerance = t;
        self
    }
    /// Prune empty space with intervals (default false). Same output, fewer evaluations.
    pub fn prune(mut self, p: bool) -> Self {
        self.params.prune = p;
        self
    }
    /// Side of the pruning descent's leaf blocks, in cells (default 4).
    pub fn leaf(mut self, n: usize) -> Self {
        self.params.leaf = n;
        self
    }
    /// From `--resolution`, `--crossing`, `--tolerance`, `--prune`, `--set leaf=N`.
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Ok(MarchingCubes {
            params: GridParams::from_options("mc", o)?,
        })
    }
}

impl Mesher for MarchingCubes {
    fn name(&self) -> &'static str {
        "mc"
    }
    fn dim(&self) -> usize {
        3
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        mesh_3d("marching cubes", table(), &self.params, f, domain, progress)
    }
}

/// Marching cubes on an already sampled grid, crossings by linear interpolation.
pub fn marching_cubes<F: Field>(field: &F) -> Result<TriMesh> {
    Ok(extract(field, table(), Place::Linear)?.mesh)
}

pub(crate) fn table() -> &'static Scheme {
    static T: OnceLock<Scheme> = OnceLock::new();
    T.get_or_init(build)
}

/// The six faces, each as its four corners counter-clockwise seen from outside.
pub(crate) fn faces() -> Vec<[u8; 4]> {
    let mut out = Vec::new();
    for a in 0..3 {
        // (u, v, a) is a right-handed frame, so counter-clockwise in (u, v) is
        // counter-clockwise seen from +a; seen from -a it is the reverse.
        let (u, v) = ((a + 1) % 3, (a + 2) % 3);
        for side in 0..2u8 {
            let at = |du: u8, dv: u8| (du << u) | (dv << v) | (side << a);
            let mut q = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)];
            if side == 0 {
                q.reverse();
            }
            out.push(q);
        }
    }
    out
}

fn build() -> Scheme {
    let mut s = Scheme {
        dirs: vec![1, 2, 4],
        edges: Vec::new(),
        cases: Vec::with_capacity(256),
    };
    // The 12 cube edges, in a fixed order.
    for c in 0..8u8 {
        for d in [1u8, 2, 4] {
            if c & d == 0 {
                s.edge(c, c | d);
            }
        }
    }
    let faces = faces();
    for case in 0..256usize {
        let neg = |c: u8| case >> c & 1 == 1;
        // next[e] = the crossing the segment leaving e ends at.
        let mut next = [u8::MAX; 12];
        // For each edge, the faces (their index) it lies on.
        let mut face_of = [[u8::MAX; 2]; 12];
        for (fi, q) in faces.iter().enumerate() {
            let e: Vec<u8> = (0..4).map(|m| s.edge(q[m], q[(m + 1) % 4])).collect();
            for m in 0..4 {
                let slot = &mut face_of[e[m] as usize];
                slot[(slot[0] != u8::MAX) as usize] = fi as u8;
            }
            let cross: Vec<bool> = (0..4).map(|m| neg(q[m]) != neg(q[(m + 1) % 4])).collect();
            for m in 0..4 {
                if !neg(q[m]) && neg(q[(m + 1) % 4]) {
                    let m2 = (1..4).map(|o| (m + o) % 4).find(|&m2| cross[m2]).unwrap();
                    next[e[m] as usize] = e[m2];
                }
            }
        }
        let mut tris = Vec::new();
        let mut seen = [false; 12];
        for start in 0..12u8 {
            if next[start as usize] == u8::MAX || seen[start as usize] {
                continue;
            }
            let mut lp = vec![start];
            seen[start as usize] = true;
            let mut e = next[start as usize];
            while e != start {
                seen[e as usize] = true;
                lp.push(e);
                e = next[e as usize];
            }
            let share = |a: u8, b: u8| {
                face_of[a as usize]
                    .iter()
                    .any(|f| face_of[b as usize].contains(f))
            };
            triangulate(&lp, &share, &mut tris);
        }
        s.cases.push(tris);
    }
    s
}

/// Triangulate a closed loop of crossings (in order) so that no diagonal joins two
/// crossings on one cube face (`share`), by dynamic programming over sub-polygons
/// (loops have at most 12 crossings; this runs once per case, at table build).
fn triangulate(lp: &[u8], share: &dyn Fn(u8, u8) -> bool, out: &mut Vec<[u8; 3]>) {
    let n = lp.len();
    let ok = |i: usize, j: usize| {
        let d = (j + n - i) % n;
        d == 1 || d == n - 1 || !share(lp[i], lp[j])
    };
    // can[i][j]: the sub-polygon lp[i..=j] (closed by the chord i–j) can be triangulated.
    let mut can = vec![vec![None::<usize>; n]; n];
    for len in 2..n {
        for i in 0..n - len {
            let j = i + len;
            if !ok(i, j) {
                continue;
            }
            for k in i + 1..j {
                let left = k == i + 1 || can[i][k].is_some();
                let right = k + 1 == j || can[k][j].is_some();
                if left && right && ok(i, k) && ok(k, j) {
                    can[i][j] = Some(k);
                    break;
                }
            }
        }
    }
    fn emit(lp: &[u8], can: &[Vec<Option<usize>>], i: usize, j: usize, out: &mut Vec<[u8; 3]>) {
        if j <= i + 1 {
            return;
        }
        let k = can[i][j].expect("loop triangulable without same-face diagonals");
        out.push([lp[i], lp[k], lp[j]]);
        emit(lp, can, i, k, out);
        emit(lp, can, k, j, out);
    }
    emit(lp, &can, 0, n - 1, out);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_case_closes_and_pairs_edges() {
        let t = table();
        assert_eq!(t.edges.len(), 12);
        assert_eq!(t.cases[0].len(), 0);
        assert_eq!(t.cases[255].len(), 0);
        assert_eq!(t.cases[1].len(), 1);
        for (case, tris) in t.cases.iter().enumerate() {
            // Each crossing edge is used; the cell's patch boundary consists of one
            // directed segment per (face, crossing pair), each directed edge once.
            let mut dir = std::collections::HashMap::new();
            for tr in tris {
                for m in 0..3 {
                    *dir.entry((tr[m], tr[(m + 1) % 3])).or_insert(0) += 1;
                }
            }
            for (&(a, b), &c) in &dir {
                assert_eq!(c, 1, "case {case}: directed edge {a}->{b} twice");
            }
            let crossings = (0..12)
                .filter(|&e| {
                    let (c, d) = t.edges[e];
                    let hi = c | t.dirs[d as usize];
                    (case >> c & 1) != (case >> hi & 1)
                })
                .count();
            let used: std::collections::HashSet<u8> = tris.iter().flatten().cloned().collect();
            assert_eq!(used.len(), crossings, "case {case}");
        }
    }
}
