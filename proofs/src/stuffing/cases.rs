//! The configuration space of the isosurface-stuffing angle proof (Labelle & Shewchuk
//! 2007, §4.1), derived from the mesher's own stencil table
//! ([`certmesh::stuffing::stencils::TABLE`]), and its reduction by symmetry.
//!
//! Every vertex of an output tetrahedron is one of (§4.1, the bulleted facts):
//! * a **fixed** lattice point (a vertex labelled + — or −, for the sign-swapped stencils
//!   of double-sided meshing, which are the same geometric tetrahedra);
//! * a **cut** point on a +/− edge, on the edge's central part `[α, 1−α]` (a cut in a
//!   peripheral part would have warped the endpoint and disappeared);
//! * a **warped** lattice point labelled 0, on one of the 14 half-segments of its
//!   asterisk: from the lattice point `p` toward the neighbour `p + d`, at parameter
//!   `t ∈ [0, α_d]` (`t = 0` is a lattice point exactly on the surface). The paper
//!   counts seven segments (each a whole line through `p`); we split each into its two
//!   halves so that the warping constraints become combinatorial:
//!   - two vertices sharing an edge cannot both warp toward each other along it;
//!   - with ordered warping, a vertex cannot warp along an edge whose other endpoint also
//!     warps (a vertex of the BCC tetrahedron labelled 0 is warped, or lies on the surface
//!     and then carries no cut point on its edges: either way no warp toward it);
//!   - with `α_short = 0.5` (§6) no cut point survives on a red edge (the midpoint
//!     violates the odd endpoint), so patterns with a red +/− edge cannot occur.
//!
//! We work in *doubled* lattice coordinates (even points have even coordinates): a
//! vertex is `p + t·d` with integer `p`, `d`; black edges have `|d| = 2`, red `|d| = √3`.
//!
//! Symmetry: angles are invariant under isometries, so two cases are the same when one
//! is mapped to the other by one of the 48 signed coordinate permutations (which preserve
//! the BCC lattice and the edge colours) followed by a translation. Sign relabelling
//! (the exterior stencils of double-sided meshing) needs no separate treatment: the
//! descriptor records only the geometry, and the sign-swapped stencil of a pattern is
//! the stencil of the negated pattern, which the enumeration visits anyway.
use certmesh::lattice::bcc::{self, NEIGHBORS};
use certmesh::stuffing::params::Row;
use certmesh::stuffing::stencils::{self, pattern_signs, EDGES, TABLE};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Kind of a vertex descriptor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Kind {
    Fixed,
    Cut,
    Warp,
}

/// One vertex of a configuration: `p + t·d` with `t` in the kind's range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Seg {
    pub kind: Kind,
    pub p: [i64; 3],
    pub d: [i64; 3],
}

impl Seg {
    pub fn fixed(p: [i64; 3]) -> Seg {
        Seg {
            kind: Kind::Fixed,
            p,
            d: [0; 3],
        }
    }
    /// A cut segment, oriented canonically (the central part is symmetric).
    pub fn cut(a: [i64; 3], b: [i64; 3]) -> Seg {
        let (p, q) = if a <= b { (a, b) } else { (b, a) };
        Seg {
            kind: Kind::Cut,
            p,
            d: sub(q, p),
        }
    }
    pub fn warp(p: [i64; 3], d: [i64; 3]) -> Seg {
        Seg {
            kind: Kind::Warp,
            p,
            d,
        }
    }
    /// Is the direction black (axis-parallel)?
    pub fn black(&self) -> bool {
        self.d.iter().filter(|&&x| x != 0).count() == 1
    }
    /// Does the vertex move (one parameter)?
    pub fn is_param(&self) -> bool {
        self.kind != Kind::Fixed
    }
    fn map(&self, g: &Sym) -> Seg {
        let s = Seg {
            kind: self.kind,
            p: g.apply(self.p),
            d: g.apply(self.d),
        };
        if s.kind == Kind::Cut {
            Seg::cut(s.p, add(s.p, s.d))
        } else {
            s
        }
    }
    fn translate(&self, m: [i64; 3]) -> Seg {
        Seg {
            kind: self.kind,
            p: sub(self.p, m),
            d: self.d,
        }
    }
}

pub fn sub(a: [i64; 3], b: [i64; 3]) -> [i64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn add(a: [i64; 3], b: [i64; 3]) -> [i64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// A signed permutation of the coordinates: `x'_k = sign_k · x_{perm_k}`.
#[derive(Clone, Copy, Debug)]
pub struct Sym {
    pub perm: [usize; 3],
    pub sign: [i64; 3],
}

impl Sym {
    pub fn apply(&self, x: [i64; 3]) -> [i64; 3] {
        [0, 1, 2].map(|k| self.sign[k] * x[self.perm[k]])
    }
    /// The 48 symmetries of the cube (they map the BCC lattice, its black and its red
    /// edges onto themselves).
    pub fn all() -> Vec<Sym> {
        let perms = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        let mut out = Vec::with_capacity(48);
        for perm in perms {
            for s in 0..8 {
                let sign = [0, 1, 2].map(|k| if s >> k & 1 == 1 { -1 } else { 1 });
                out.push(Sym { perm, sign });
            }
        }
        out
    }
}

/// The canonical form of a set of vertex descriptors under the 48 symmetries and
/// translations: the lexicographically least sorted list.
pub fn canonical(v: &[Seg], syms: &[Sym]) -> Vec<Seg> {
    let mut best: Option<Vec<Seg>> = None;
    for g in syms {
        let mut w: Vec<Seg> = v.iter().map(|s| s.map(g)).collect();
        let mut m = [i64::MAX; 3];
        for s in &w {
            for q in [s.p, add(s.p, s.d)] {
                for k in 0..3 {
                    m[k] = m[k].min(q[k]);
                }
            }
        }
        for s in &mut w {
            *s = s.translate(m);
        }
        w.sort_unstable();
        if best.as_ref().is_none_or(|b| w < *b) {
            best = Some(w);
        }
    }
    best.unwrap_or_default()
}

/// The row's parameters as exact rationals `num / DEN`.
pub const DEN: i64 = 100_000;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Alphas {
    /// α_long · DEN and α_short · DEN (Table 1 gives five decimals).
    pub long: i64,
    pub short: i64,
    pub ordered: bool,
    pub double_sided: bool,
}

impl Alphas {
    pub fn of(row: &Row) -> Alphas {
        let r = |x: f64| (x * DEN as f64).round() as i64;
        Alphas {
            long: r(row.alpha_long),
            short: r(row.alpha_short),
            ordered: row.ordered,
            double_sided: row.double_sided,
        }
    }
    /// α of a segment's edge colour (×DEN).
    pub fn alpha(&self, s: &Seg) -> i64 {
        if s.black() {
            self.long
        } else {
            self.short
        }
    }
    /// The parameter range of a vertex, `[t0, t1]` ×DEN.
    pub fn range(&self, s: &Seg) -> [i64; 2] {
        match s.kind {
            Kind::Fixed => [0, 0],
            Kind::Cut => [self.alpha(s), DEN - self.alpha(s)],
            Kind::Warp => [0, self.alpha(s)],
        }
    }
}

/// An output-tetrahedron case (canonical vertex order) with the number of raw
/// (pattern, stencil tetrahedron, warp directions) configurations it stands for.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Case {
    pub v: [Seg; 4],
    pub multiplicity: usize,
}

impl Case {
    /// The faces (vertex index triples) exposed on the boundary: no fixed vertex.
    pub fn exposed(&self, f: [usize; 3]) -> bool {
        f.iter().all(|&k| self.v[k].kind != Kind::Fixed)
    }
}

/// Counts before and after the symmetry reduction.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counts {
    pub raw: usize,
    pub distinct: usize,
}

/// Does the pattern contain a red +/− edge (impossible when α_short = 0.5, §6)?
fn red_cut(s: [i8; 4]) -> bool {
    EDGES
        .iter()
        .any(|&[u, v]| !stencils::is_black(u, v) && s[u as usize] * s[v as usize] == -1)
}

/// All admissible warp assignments of the zero-labelled vertices `zeros` (local ids of
/// the BCC tetrahedron with lattice points `pts` and signs `s`): one direction index per
/// zero vertex.
fn warp_choices(
    pts: &[[i64; 3]; 4],
    s: [i8; 4],
    zeros: &[usize],
    ordered: bool,
) -> Vec<Vec<usize>> {
    let toward = |i: usize, d: usize| -> Option<usize> {
        let q = add(pts[i], NEIGHBORS[d]);
        (0..4).find(|&w| pts[w] == q)
    };
    let mut out = Vec::new();
    let mut cur = vec![0usize; zeros.len()];
    loop {
        // Check the assignment.
        let mut ok = true;
        for (a, &i) in zeros.iter().enumerate() {
            if let Some(w) = toward(i, cur[a]) {
                if s[w] == 0 {
                    if ordered {
                        ok = false;
                    } else if let Some(b) = zeros.iter().position(|&z| z == w) {
                        if toward(w, cur[b]) == Some(i) {
                            ok = false;
                        }
                    }
                }
            }
        }
        if ok {
            out.push(cur.clone());
        }
        // Next assignment (odometer).
        let mut k = 0;
        loop {
            if k == cur.len() {
                return out;
            }
            cur[k] += 1;
            if cur[k] < 14 {
                break;
            }
            cur[k] = 0;
            k += 1;
        }
    }
}

/// The output-tetrahedron cases of a row (symmetry-reduced, sorted) and the counts.
pub fn output_cases(a: &Alphas) -> (Vec<Case>, Counts) {
    let syms = Sym::all();
    let t = &*TABLE;
    let pts: [[i64; 3]; 4] = t.reference;
    let mut map: BTreeMap<Vec<Seg>, usize> = BTreeMap::new();
    let mut raw = 0;
    for i in 0..81 {
        let s = pattern_signs(i);
        let st = &t.stencils[i];
        if st.quadruple_zero && !a.double_sided {
            continue;
        }
        if a.short == DEN / 2 && red_cut(s) {
            continue;
        }
        for tet in st.tets() {
            let zeros: Vec<usize> = tet
                .iter()
                .filter(|&&id| id < 4 && s[id as usize] == 0)
                .map(|&id| id as usize)
                .collect();
            for choice in warp_choices(&pts, s, &zeros, a.ordered) {
                let v: Vec<Seg> = tet
                    .iter()
                    .map(|&id| {
                        if id >= 4 {
                            let [u, w] = EDGES[(id - 4) as usize];
                            Seg::cut(pts[u as usize], pts[w as usize])
                        } else if s[id as usize] == 0 {
                            let k = zeros.iter().position(|&z| z == id as usize).unwrap_or(0);
                            Seg::warp(pts[id as usize], NEIGHBORS[choice[k]])
                        } else {
                            Seg::fixed(pts[id as usize])
                        }
                    })
                    .collect();
                raw += 1;
                *map.entry(canonical(&v, &syms)).or_insert(0) += 1;
            }
        }
    }
    let cases: Vec<Case> = map
        .into_iter()
        .map(|(k, m)| Case {
            v: [k[0], k[1], k[2], k[3]],
            multiplicity: m,
        })
        .collect();
    let n = cases.len();
    (cases, Counts { raw, distinct: n })
}

/// The warped-BCC-tetrahedron cases of the "safe" property (every pattern, with − and +
/// vertices fixed and 0 vertices on their asterisks), oriented so that the unwarped
/// tetrahedron has positive volume.
pub fn bcc_cases(a: &Alphas) -> (Vec<Case>, Counts) {
    let syms = Sym::all();
    let t = &*TABLE;
    let pts: [[i64; 3]; 4] = t.reference;
    let mut map: BTreeMap<Vec<Seg>, usize> = BTreeMap::new();
    let mut raw = 0;
    for i in 0..81 {
        let s = pattern_signs(i);
        if a.short == DEN / 2 && red_cut(s) {
            continue;
        }
        let zeros: Vec<usize> = (0..4).filter(|&k| s[k] == 0).collect();
        for choice in warp_choices(&pts, s, &zeros, a.ordered) {
            let v: Vec<Seg> = (0..4)
                .map(|k| match zeros.iter().position(|&z| z == k) {
                    Some(j) => Seg::warp(pts[k], NEIGHBORS[choice[j]]),
                    None => Seg::fixed(pts[k]),
                })
                .collect();
            raw += 1;
            // Canonical order loses the orientation: record it by the order of the
            // canonical list (an odd permutation of the vertices is fixed below).
            *map.entry(canonical(&v, &syms)).or_insert(0) += 1;
        }
    }
    let cases: Vec<Case> = map
        .into_iter()
        .map(|(k, m)| {
            let mut v = [k[0], k[1], k[2], k[3]];
            if bcc::orient(&v.map(|s| s.p)) < 0 {
                v.swap(0, 1);
            }
            Case { v, multiplicity: m }
        })
        .collect();
    let n = cases.len();
    (cases, Counts { raw, distinct: n })
}

/// Exact position ×DEN of a vertex at parameter `t` (×DEN).
pub fn pos_exact(s: &Seg, t: i64) -> [i128; 3] {
    [0, 1, 2].map(|k| s.p[k] as i128 * DEN as i128 + t as i128 * s.d[k] as i128)
}

/// Exact 6 × signed volume (×DEN³, doubled coordinates) of four points.
pub fn orient_exact(p: &[[i128; 3]; 4]) -> i128 {
    let u = [0, 1, 2].map(|k| p[1][k] - p[0][k]);
    let v = [0, 1, 2].map(|k| p[2][k] - p[0][k]);
    let w = [0, 1, 2].map(|k| p[3][k] - p[0][k]);
    u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0])
}

/// The minimum and maximum of the signed volume of a case over its whole parameter box,
/// exactly, with the parameters (×DEN) attaining them. The volume is affine in each
/// vertex (det(b−a, c−a, d−a) expands into determinants with at most one copy of each
/// vertex), each vertex is affine in its own parameter, so the volume is multilinear in
/// the parameters and its extremes over the box are attained at corners.
pub fn volume_range(c: &Case, a: &Alphas) -> ([i128; 2], [[i64; 4]; 2]) {
    let ranges = c.v.map(|s| a.range(&s));
    let mut lo = (i128::MAX, [0i64; 4]);
    let mut hi = (i128::MIN, [0i64; 4]);
    for m in 0..16u32 {
        let t: [i64; 4] = [0, 1, 2, 3].map(|k| ranges[k][(m >> k & 1) as usize]);
        let p = [0, 1, 2, 3].map(|k| pos_exact(&c.v[k], t[k]));
        let vol = orient_exact(&p);
        if vol < lo.0 {
            lo = (vol, t);
        }
        if vol > hi.0 {
            hi = (vol, t);
        }
    }
    ([lo.0, hi.0], [lo.1, hi.1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use certmesh::stuffing::params::TABLE1;

    #[test]
    fn symmetries_preserve_the_lattice_edges() {
        let syms = Sym::all();
        assert_eq!(syms.len(), 48);
        for g in &syms {
            for n in NEIGHBORS {
                let m = g.apply(n);
                assert!(NEIGHBORS.contains(&m));
                assert_eq!(
                    n.iter().filter(|&&x| x != 0).count(),
                    m.iter().filter(|&&x| x != 0).count()
                );
            }
        }
    }

    #[test]
    fn canonical_form_is_invariant() {
        let syms = Sym::all();
        let a = Alphas::of(&TABLE1[1]);
        let (cases, _) = output_cases(&a);
        for (i, c) in cases.iter().enumerate().step_by(37) {
            let g = syms[i % 48];
            let moved: Vec<Seg> =
                c.v.iter()
                    .rev()
                    .map(|s| s.map(&g).translate([-4, 6, 2]))
                    .collect();
            assert_eq!(canonical(&moved, &syms), c.v.to_vec());
        }
    }

    #[test]
    fn ordered_warping_and_midpoint_convention_remove_cases() {
        let un = output_cases(&Alphas::of(&TABLE1[3])).1;
        let ord = output_cases(&Alphas::of(&TABLE1[4])).1;
        let dbl = output_cases(&Alphas::of(&TABLE1[6])).1;
        assert!(ord.raw < un.raw && ord.distinct < un.distinct);
        assert!(dbl.raw > un.raw && dbl.distinct > un.distinct);
        assert!(un.distinct < un.raw / 4, "symmetry reduces {un:?}");
        let half = output_cases(&Alphas::of(&TABLE1[12])).0;
        // α_short = 0.5: no cut point on a red edge.
        assert!(half
            .iter()
            .all(|c| c.v.iter().all(|s| s.kind != Kind::Cut || s.black())));
    }

    #[test]
    fn undisturbed_bcc_tetrahedron_volume() {
        // A BCC tetrahedron (doubled coordinates): 6·volume = 4 in doubled units, i.e.
        // h³/12 ... ×DEN³.
        let c = Case {
            v: TABLE.reference.map(Seg::fixed),
            multiplicity: 1,
        };
        let a = Alphas::of(&TABLE1[0]);
        let (r, _) = volume_range(&c, &a);
        assert_eq!(r[0], r[1]);
        assert_eq!(r[0].abs(), 4 * (DEN as i128).pow(3));
    }
}
