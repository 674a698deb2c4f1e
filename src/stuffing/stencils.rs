//! The stencil table of §3.3, for all 81 sign patterns, *derived by code* from the
//! paper's rules (Figure 3 is not in the text we have). The table is plain data that
//! the mesher and the `proofs` crate both read.
//!
//! Local point numbering of a BCC tetrahedron in the canonical naming of
//! [`crate::lattice::bcc`]: `0 = e0, 1 = e1` (the even black edge), `2 = o0, 3 = o1` (the odd
//! black edge), and `4 + k` = the cut point on edge [`EDGES`]`[k]`.
//!
//! Derivation, for one sign pattern (+ inside, − outside, 0 on the surface):
//! 1. The output polytope is the nonnegative part of the (warped) tetrahedron: its
//!    vertices are the + and 0 vertices and the cut points on the +/− edges. Its faces
//!    are the nonnegative parts of the four tetrahedron faces (walked in order, so they
//!    keep the outward orientation) plus the *cut face*, the loop of unmatched edges.
//! 2. Quadrilateral faces are split: a truncated tetrahedron face with a truncated black
//!    edge takes the diagonal adjoining the black edge's cut point; one with a whole
//!    black edge takes the Parity-Rule diagonal ([`crate::lattice::bcc::parity_diagonal_from_a`],
//!    evaluated on the reference tetrahedron: the choice is the same for every
//!    tetrahedron in the canonical naming). The cut-face quadrilateral (pattern ++−−)
//!    is not constrained by the paper: we take the diagonal for which the polytope can
//!    be tetrahedralized without new vertices; the tests show that it is always unique.
//! 3. The polytope is coned from a vertex `v` all of whose incident faces are split
//!    through `v` (so no cone is flat): one tetrahedron per boundary triangle not at `v`.
//!
//! Output tetrahedra are positively oriented on the reference tetrahedron (cut points at
//! edge midpoints); the mirror family of lattice tetrahedra swaps two vertices.
use crate::lattice::bcc::{self, Coord};
use std::sync::LazyLock;

/// The six edges of a tetrahedron in local numbering: the two black edges first.
pub const EDGES: [[u8; 2]; 6] = [[0, 1], [2, 3], [0, 2], [0, 3], [1, 2], [1, 3]];

/// Is the local edge `{u, v}` black?
#[inline]
pub fn is_black(u: u8, v: u8) -> bool {
    let (a, b) = (u.min(v), u.max(v));
    (a, b) == (0, 1) || (a, b) == (2, 3)
}

/// The local id (4..10) of the cut point on edge `{u, v}`.
#[inline]
pub fn cut_id(u: u8, v: u8) -> u8 {
    let (a, b) = (u.min(v), u.max(v));
    4 + EDGES
        .iter()
        .position(|e| e[0] == a && e[1] == b)
        .expect("an edge") as u8
}

/// One stencil: up to three output tetrahedra over local point ids.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stencil {
    pub tets: [[u8; 4]; 3],
    pub n: u8,
    /// The all-zero pattern: the whole tetrahedron, output only by the quadruple-zero
    /// policy (§3.3).
    pub quadruple_zero: bool,
}

impl Stencil {
    pub fn tets(&self) -> &[[u8; 4]] {
        &self.tets[..self.n as usize]
    }
}

/// Signs `(e0, e1, o0, o1)` ↔ pattern index `Σ (sᵢ + 1)·3ⁱ`.
#[inline]
pub fn pattern_index(s: [i8; 4]) -> usize {
    (s[0] + 1) as usize
        + 3 * (s[1] + 1) as usize
        + 9 * (s[2] + 1) as usize
        + 27 * (s[3] + 1) as usize
}
pub fn pattern_signs(mut i: usize) -> [i8; 4] {
    let mut s = [0i8; 4];
    for v in &mut s {
        *v = (i % 3) as i8 - 1;
        i /= 3;
    }
    s
}

/// The table: 81 stencils, derived on a reference tetrahedron.
#[derive(Clone, Debug)]
pub struct StencilTable {
    /// The reference tetrahedron (doubled lattice coordinates, canonical naming).
    pub reference: [Coord; 4],
    /// Orientation sign of the reference tetrahedron in the canonical naming.
    pub reference_orientation: i8,
    pub stencils: Vec<Stencil>,
}

/// The table used by the mesher (and by `proofs`).
pub static TABLE: LazyLock<StencilTable> = LazyLock::new(|| {
    let t = bcc::TET_TEMPLATES[0];
    let reference = t.offsets;
    let stencils = (0..81)
        .map(|i| derive(&reference, pattern_signs(i)).expect("every pattern has a stencil"))
        .collect();
    StencilTable {
        reference,
        reference_orientation: t.orientation,
        stencils,
    }
});

/// Reference position of a local point (doubled coordinates ×2, so that cut points at
/// edge midpoints are integral).
pub fn reference_point(reference: &[Coord; 4], id: u8) -> [i64; 3] {
    if id < 4 {
        reference[id as usize].map(|x| 2 * x)
    } else {
        let [a, b] = EDGES[(id - 4) as usize];
        let (p, q) = (reference[a as usize], reference[b as usize]);
        [p[0] + q[0], p[1] + q[1], p[2] + q[2]]
    }
}

/// Derive the stencil of one sign pattern (see the module doc). `None` if the rules
/// leave no tetrahedralization (never happens; tested).
pub fn derive(reference: &[Coord; 4], s: [i8; 4]) -> Option<Stencil> {
    let mut st = Stencil {
        tets: [[0; 4]; 3],
        n: 0,
        quadruple_zero: false,
    };
    if s.iter().all(|&x| x == 0) {
        st.quadruple_zero = true;
        st.tets[0] = [0, 1, 2, 3];
        st.n = 1;
        if bcc::orient(reference) < 0 {
            st.tets[0].swap(0, 1);
        }
        return Some(st);
    }
    if !s.contains(&1) {
        return Some(st);
    }
    let cut = |u: u8, v: u8| s[u as usize] * s[v as usize] == -1;
    // Outward faces of the reference tetrahedron.
    let neg = bcc::orient(reference) < 0;
    let mut faces: Vec<[u8; 3]> = vec![[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
    if neg {
        for f in &mut faces {
            f.swap(1, 2);
        }
    }
    // Polygons: (vertices in order, the tetrahedron face it came from).
    let mut polys: Vec<(Vec<u8>, Option<[u8; 3]>)> = Vec::new();
    for f in &faces {
        let mut poly = Vec::new();
        for i in 0..3 {
            let (v, w) = (f[i], f[(i + 1) % 3]);
            if s[v as usize] >= 0 {
                poly.push(v);
            }
            if cut(v, w) {
                poly.push(cut_id(v, w));
            }
        }
        if poly.len() >= 3 {
            polys.push((poly, Some(*f)));
        }
    }
    // Cut face: reverse the unmatched directed edges and chain them.
    let mut dir = Vec::new();
    for (p, _) in &polys {
        for i in 0..p.len() {
            dir.push((p[i], p[(i + 1) % p.len()]));
        }
    }
    let unmatched: Vec<(u8, u8)> = dir
        .iter()
        .filter(|&&(u, v)| !dir.contains(&(v, u)))
        .map(|&(u, v)| (v, u))
        .collect();
    if !unmatched.is_empty() {
        let mut poly = vec![unmatched[0].0];
        let mut cur = unmatched[0].1;
        while cur != poly[0] {
            poly.push(cur);
            cur = unmatched.iter().find(|e| e.0 == cur)?.1;
            if poly.len() > unmatched.len() {
                return None;
            }
        }
        if poly.len() != unmatched.len() {
            return None;
        }
        polys.push((poly, None));
    }
    // Fixed diagonals of the tetrahedron-face quadrilaterals.
    let mut diag: Vec<Option<(u8, u8)>> = Vec::new();
    let mut free = Vec::new();
    for (k, (p, f)) in polys.iter().enumerate() {
        if p.len() != 4 {
            diag.push(None);
            continue;
        }
        match f {
            Some(f) => {
                let x = *f.iter().find(|&&v| s[v as usize] < 0)?;
                let ab: Vec<u8> = f.iter().copied().filter(|&v| s[v as usize] > 0).collect();
                let (a, b) = (ab[0], ab[1]);
                let d = if is_black(a, b) {
                    let r = |v: u8| reference[v as usize];
                    if bcc::parity_diagonal_from_a(r(a), r(b), r(x)) {
                        (a, cut_id(b, x))
                    } else {
                        (b, cut_id(a, x))
                    }
                } else if is_black(a, x) {
                    (cut_id(a, x), b)
                } else {
                    (cut_id(b, x), a)
                };
                diag.push(Some(d));
            }
            None => {
                diag.push(None);
                free.push(k);
            }
        }
    }
    let nfree = free.len();
    let mut found: Option<Stencil> = None;
    for choice in 0..(1usize << nfree) {
        let mut dg = diag.clone();
        for (bit, &k) in free.iter().enumerate() {
            let p = &polys[k].0;
            dg[k] = Some(if choice >> bit & 1 == 0 {
                (p[0], p[2])
            } else {
                (p[1], p[3])
            });
        }
        // Triangles per face.
        let tris: Vec<Vec<[u8; 3]>> = polys
            .iter()
            .zip(&dg)
            .map(|((p, _), d)| match p.len() {
                3 => vec![[p[0], p[1], p[2]]],
                4 => {
                    let (u, v) = d.expect("quad has a diagonal");
                    if (u == p[0] && v == p[2]) || (u == p[2] && v == p[0]) {
                        vec![[p[0], p[1], p[2]], [p[0], p[2], p[3]]]
                    } else {
                        vec![[p[1], p[2], p[3]], [p[1], p[3], p[0]]]
                    }
                }
                _ => Vec::new(),
            })
            .collect();
        let mut verts: Vec<u8> = polys.iter().flat_map(|(p, _)| p.iter().copied()).collect();
        verts.sort_unstable();
        verts.dedup();
        for &v in &verts {
            let ok = polys
                .iter()
                .zip(&tris)
                .filter(|((p, _), _)| p.contains(&v))
                .all(|(_, ts)| ts.iter().all(|t| t.contains(&v)));
            if !ok {
                continue;
            }
            let mut out = Stencil {
                tets: [[0; 4]; 3],
                n: 0,
                quadruple_zero: false,
            };
            for t in tris.iter().flatten().filter(|t| !t.contains(&v)) {
                if out.n == 3 {
                    return None;
                }
                out.tets[out.n as usize] = [t[0], t[2], t[1], v];
                out.n += 1;
            }
            match &found {
                // A second, different tetrahedralization: the rules are ambiguous.
                Some(f) if sorted(f) != sorted(&out) => return None,
                Some(_) => {}
                None => found = Some(out),
            }
            break;
        }
    }
    found
}

fn sorted(s: &Stencil) -> Vec<[u8; 4]> {
    let mut v: Vec<[u8; 4]> = s
        .tets()
        .iter()
        .map(|t| {
            let mut t = *t;
            t.sort_unstable();
            t
        })
        .collect();
    v.sort_unstable();
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vol6(r: &[Coord; 4], t: [u8; 4]) -> i64 {
        let p = t.map(|i| reference_point(r, i));
        bcc::orient(&p)
    }

    #[test]
    fn patterns_round_trip() {
        for i in 0..81 {
            assert_eq!(pattern_index(pattern_signs(i)), i);
        }
    }

    #[test]
    fn every_stencil_is_a_positive_partition() {
        let t = &*TABLE;
        let whole = bcc::orient(&t.reference.map(|c| c.map(|x| 2 * x))).abs();
        let mut classes = std::collections::HashSet::new();
        for i in 0..81 {
            let s = pattern_signs(i);
            let st = t.stencils[i];
            for &tet in st.tets() {
                assert!(vol6(&t.reference, tet) > 0, "pattern {s:?}: {tet:?}");
                // Never connect a + vertex to a − vertex (§4.2).
                for a in tet {
                    for b in tet {
                        if a < 4 && b < 4 {
                            assert!(s[a as usize] * s[b as usize] != -1);
                        }
                    }
                }
            }
            let v: i64 = st.tets().iter().map(|&q| vol6(&t.reference, q)).sum();
            if !st.quadruple_zero {
                let neg = pattern_index(s.map(|x| -x));
                let w: i64 = t.stencils[neg]
                    .tets()
                    .iter()
                    .map(|&q| vol6(&t.reference, q))
                    .sum();
                // Inside and outside stencils tile the tetrahedron.
                assert_eq!(v + w, whole, "pattern {s:?}");
            }
            classes.insert((s.iter().filter(|&&x| x > 0).count(), st.n));
        }
        assert!(t.stencils.iter().any(|s| s.n == 3));
    }

    #[test]
    fn inside_and_outside_stencils_agree_on_the_cut_face() {
        // Double-sided meshing (§3.3): swapping + and − must triangulate the
        // surface faces identically.
        let t = &*TABLE;
        let faces = |st: &Stencil, s: [i8; 4]| {
            let mut out = Vec::new();
            for &tet in st.tets() {
                for skip in 0..4 {
                    let mut f: Vec<u8> = (0..4).filter(|&k| k != skip).map(|k| tet[k]).collect();
                    if f.iter().all(|&v| v >= 4 || s[v as usize] == 0) {
                        f.sort_unstable();
                        out.push(f);
                    }
                }
            }
            out.sort();
            out
        };
        for i in 0..81 {
            let s = pattern_signs(i);
            if !s.contains(&1) || !s.contains(&-1) {
                continue;
            }
            let j = pattern_index(s.map(|x| -x));
            assert_eq!(
                faces(&t.stencils[i], s),
                faces(&t.stencils[j], s.map(|x| -x)),
                "{s:?}"
            );
        }
    }
}
