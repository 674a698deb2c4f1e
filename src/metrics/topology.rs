//! Combinatorial topology of meshes: counts, Euler characteristic, components,
//! boundary loops, manifoldness, orientability and genus; and the topology verdict
//! against a catalog entry's expected components and genera.
//!
//! Conventions (documented once, used everywhere):
//! * V counts vertices used by some face; unused ("isolated") vertices are reported
//!   separately and belong to no component.
//! * Components are the connected components of the union of the faces (two faces
//!   sharing only a vertex are connected).
//! * Degenerate faces (a repeated vertex index) count in V but not in E or F: they have
//!   no edges of their own; they make the mesh non-manifold.
//! * Boundary loops are the cycle rank E_b − V_b + C_b of the graph of boundary edges
//!   (edges in one face): the number of loops when the boundary is a disjoint union of
//!   cycles, and the number of independent loops when loops touch at a vertex.
//! * A vertex is non-manifold when its link (the opposite edges of its faces) is not a
//!   single path or cycle: a bow-tie, or a vertex on a non-manifold edge.
//! * Genus of an orientable manifold component: g = (2 − χ − b) / 2 with b its boundary
//!   loops (b = 0 for closed components, the brief's (2 − χ)/2).
use super::{check_curve, check_tetmesh, check_trimesh};
use crate::catalog::Topology;
use crate::error::Result;
use crate::mesh::{Curve2, TetMesh, TriMesh};
use rayon::prelude::*;
use serde::Serialize;

/// Union-find with path halving: union by size ([`UnionFind::union`]), or Rem's
/// splicing for many joins of mostly joined sets ([`UnionFind::join`]).
#[derive(Clone, Debug, Default)]
pub struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    pub fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }
    /// `n` singletons for [`UnionFind::join`] alone (no sizes: `union` would panic).
    pub fn for_join(n: usize) -> Self {
        UnionFind {
            parent: (0..n as u32).collect(),
            size: Vec::new(),
        }
    }
    /// Start again with `n` singletons, reusing the storage.
    pub fn reset(&mut self, n: usize) {
        self.parent.clear();
        self.parent.extend(0..n as u32);
        self.size.clear();
        self.size.resize(n, 1);
    }
    pub fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let g = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = g;
            x = g;
        }
        x
    }
    /// Join the sets of a and b, faster than [`UnionFind::union`] when they are
    /// mostly joined already (Rem's algorithm with splicing: each step points the node
    /// with the larger parent index at the other's parent, so parents only decrease
    /// and stay at most their node's index; no sizes kept). Splicing may join the two
    /// sets before the loop ends, so it cannot tell whether they were apart. Sizes are
    /// not kept: do not mix with [`UnionFind::union`] on one structure
    /// ([`UnionFind::for_join`] makes one for `join` alone).
    pub fn join(&mut self, a: u32, b: u32) {
        let p = &mut self.parent;
        let (mut x, mut y) = (a as usize, b as usize);
        while p[x] != p[y] {
            if p[x] < p[y] {
                std::mem::swap(&mut x, &mut y);
            }
            // p[x] > p[y].
            if p[x] as usize == x {
                p[x] = p[y];
                return;
            }
            let z = x;
            x = p[x] as usize;
            p[z] = p[y];
        }
    }
    /// Join the sets of a and b; true when they were different.
    pub fn union(&mut self, a: u32, b: u32) -> bool {
        let (mut a, mut b) = (self.find(a), self.find(b));
        if a == b {
            return false;
        }
        if self.size[a as usize] < self.size[b as usize] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b as usize] = a;
        self.size[a as usize] += self.size[b as usize];
        true
    }
}

/// One connected component of a triangle mesh.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ComponentReport {
    pub vertices: usize,
    pub edges: usize,
    pub faces: usize,
    pub euler_characteristic: i64,
    pub boundary_edges: usize,
    pub boundary_loops: usize,
    pub closed: bool,
    pub manifold: bool,
    /// The faces can be oriented consistently (only meaningful when manifold).
    pub orientable: bool,
    /// g = (2 − χ − b)/2 for orientable manifold components, else `None`.
    pub genus: Option<usize>,
}

/// Everything the combinatorics of a triangle mesh tells.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TopologyReport {
    /// Vertices used by faces.
    pub vertices: usize,
    pub isolated_vertices: usize,
    pub edges: usize,
    pub faces: usize,
    /// V − E + (F − degenerate faces).
    pub euler_characteristic: i64,
    pub components: usize,
    pub boundary_edges: usize,
    pub boundary_loops: usize,
    /// Edges in more than two faces.
    pub non_manifold_edges: usize,
    pub non_manifold_vertices: usize,
    /// Faces with a repeated vertex index.
    pub degenerate_faces: usize,
    /// Faces with the same vertex set as an earlier face (either orientation).
    pub duplicate_faces: usize,
    /// Manifold edges whose two faces traverse them in the same direction: the faces
    /// as given are not consistently oriented there (a flipped face gives 3).
    pub inconsistent_edges: usize,
    pub closed: bool,
    pub manifold: bool,
    /// Every component can be oriented consistently.
    pub orientable: bool,
    /// Orientable and oriented consistently as given (no inconsistent edge).
    pub consistently_oriented: bool,
    /// Genera of the closed orientable manifold components, ascending.
    pub genus: Vec<usize>,
    pub component_list: Vec<ComponentReport>,
}

/// The link edge (a, b) of corner `c` (face `c / 3`, its vertex `c % 3`: the face runs
/// v → a → b → v from that vertex v).
#[inline(always)]
fn corner_ends(c: u32, tris: &[[u32; 3]]) -> (u32, u32) {
    // By index, not by a branch on the position (which would be mispredicted).
    const NEXT: [usize; 3] = [1, 2, 0];
    let t = tris[(c / 3) as usize];
    let k = (c % 3) as usize;
    (t[NEXT[k]], t[NEXT[NEXT[k]]])
}

/// Reusable buffers of [`link_is_disk_or_sphere`] (one per rayon task, no allocation
/// per vertex).
#[derive(Default)]
struct LinkScratch {
    ends: Vec<(u32, u32)>,
    ids: Vec<u32>,
    deg: Vec<u8>,
    uf: UnionFind,
}

/// Check the link of a vertex from its corners (see [`corner_ends`]): its faces'
/// opposite edges must form one path or cycle.
fn link_is_disk_or_sphere(corners: &[u32], tris: &[[u32; 3]], s: &mut LinkScratch) -> bool {
    if corners.len() <= SMALL_LINK {
        small_link_is_disk_or_sphere(corners, tris)
    } else {
        general_link_is_disk_or_sphere(corners, tris, s)
    }
}

/// [`link_is_disk_or_sphere`] for any valence: link vertices sorted and numbered, then
/// degrees and a union-find.
fn general_link_is_disk_or_sphere(corners: &[u32], tris: &[[u32; 3]], s: &mut LinkScratch) -> bool {
    s.ends.clear();
    s.ends.extend(corners.iter().map(|&c| corner_ends(c, tris)));
    s.ids.clear();
    s.ids.extend(s.ends.iter().flat_map(|&(a, b)| [a, b]));
    s.ids.sort_unstable();
    s.ids.dedup();
    let ids = &s.ids;
    let id = |x: u32| ids.binary_search(&x).unwrap_or(0) as u32;
    s.deg.clear();
    s.deg.resize(ids.len(), 0);
    s.uf.reset(ids.len());
    let mut sets = ids.len();
    for &(a, b) in &s.ends {
        let (a, b) = (id(a), id(b));
        s.deg[a as usize] = s.deg[a as usize].saturating_add(1);
        s.deg[b as usize] = s.deg[b as usize].saturating_add(1);
        if s.uf.union(a, b) {
            sets -= 1;
        }
    }
    sets == 1 && s.deg.iter().all(|&d| d <= 2)
}

/// Links of at most this many faces are checked on the stack ([`small_link_is_disk_or_sphere`]).
const SMALL_LINK: usize = 24;

/// The common case of [`small_link_is_disk_or_sphere`], decided fast: the link
/// edges (a, b) of a consistently oriented interior vertex (each face v a b gives the
/// link edge a → b) form one directed cycle. The walk from the first edge, each step
/// to the first edge whose source is the current target, must come back to the first
/// edge after exactly n steps. Then it visited every edge once (an edge met twice
/// before returning would repeat the same loop without the first edge forever), so
/// the sources are distinct (of two edges with one source the walk only ever takes the
/// earlier, and starts at the first) and so are the targets (each the next edge's
/// source): every link vertex ends at most two edges and the link is connected, and
/// the general check would say true. Anything else (a boundary vertex, a flipped face,
/// a pinch) is left to the general check: `false` here decides nothing.
#[inline]
fn is_one_directed_cycle(ends: &[(u32, u32)]) -> bool {
    let n = ends.len();
    let (mut at, mut steps) = (0usize, 0usize);
    loop {
        let x = ends[at].1;
        match ends.iter().position(|e| e.0 == x) {
            Some(j) => {
                steps += 1;
                if j == 0 {
                    return steps == n;
                }
                if steps >= n {
                    return false;
                }
                at = j;
            }
            None => return false,
        }
    }
}

/// [`link_is_disk_or_sphere`] for a small link, without sorting or allocation: the
/// link edges must be connected (a search over edges sharing an end, quadratic in the
/// valence) and no link vertex may end more than two of them.
fn small_link_is_disk_or_sphere(corners: &[u32], tris: &[[u32; 3]]) -> bool {
    let n = corners.len();
    let mut ends = [(0u32, 0u32); SMALL_LINK];
    for (e, &c) in ends.iter_mut().zip(corners) {
        *e = corner_ends(c, tris);
    }
    let ends = &ends[..n];
    if is_one_directed_cycle(ends) {
        return true;
    }
    for &(a, b) in ends {
        for x in [a, b] {
            let d: usize = ends
                .iter()
                .map(|&(c, e)| (c == x) as usize + (e == x) as usize)
                .sum();
            if d > 2 {
                return false;
            }
        }
    }
    let mut seen = [false; SMALL_LINK];
    let mut stack = [0usize; SMALL_LINK];
    let (mut top, mut count) = (1, 1);
    seen[0] = true;
    while top > 0 {
        top -= 1;
        let (a, b) = ends[stack[top]];
        for (j, &(c, e)) in ends.iter().enumerate() {
            if !seen[j] && (c == a || c == b || e == a || e == b) {
                seen[j] = true;
                stack[top] = j;
                top += 1;
                count += 1;
            }
        }
    }
    count == n
}

/// Every vertex's corners (a counting sort by vertex: `corners[start[v]..start[v +
/// 1]]`), each 3 f + k for the vertex at position k of face f ([`corner_ends`]).
struct StarLists {
    start: Vec<u32>,
    corners: Vec<u32>,
}

impl StarLists {
    #[inline]
    fn bucket(&self, v: usize) -> &[u32] {
        &self.corners[self.start[v] as usize..self.start[v + 1] as usize]
    }
}

/// Every vertex's corners in its non-degenerate faces, in face order: the stars of
/// [`stars_of`]. A counting sort written out (count, prefix sums, fill), the two passes over the faces
/// without a closure call per incidence.
fn star_buckets(nv: usize, tris: &[[u32; 3]], degenerate: &[bool]) -> StarLists {
    assert!(
        (tris.len() as u64) * 3 < u32::MAX as u64,
        "{} faces: too many to bucket",
        tris.len()
    );
    let mut start = vec![0u32; nv + 1];
    for (t, &d) in tris.iter().zip(degenerate) {
        if !d {
            for &v in t {
                start[v as usize + 1] += 1;
            }
        }
    }
    // Each count becomes its bucket's end; the corners, placed from the last face
    // down, move every end to its bucket's start (no second array of positions) and
    // come out ascending in each bucket (a non-degenerate face has one corner at v).
    for k in 0..nv {
        start[k + 1] += start[k];
    }
    let mut corners = vec![0u32; start[nv] as usize];
    for (f, (t, &d)) in tris.iter().zip(degenerate).enumerate().rev() {
        if !d {
            for (k, &v) in t.iter().enumerate() {
                let slot = &mut start[v as usize + 1];
                *slot -= 1;
                corners[*slot as usize] = 3 * f as u32 + k as u32;
            }
        }
    }
    // Now start[v + 1] is bucket v's start: shift down by one.
    start.copy_within(1..=nv, 0);
    start[nv] = corners.len() as u32;
    StarLists { start, corners }
}

/// Vertices per task of the star pass of [`analyze`].
const STAR_CHUNK: usize = 2048;

/// What the star of one vertex v tells, about the edges {v, u} with u > v (so each
/// edge is seen once) and v's link.
#[derive(Clone, Copy, Default)]
struct StarCounts {
    edges: u32,
    boundary_edges: u32,
    non_manifold_edges: u32,
    bad_link: bool,
}

/// The stars of a range of vertices (see [`stars_of`]).
struct Stars {
    first: usize,
    at: Vec<StarCounts>,
    /// Boundary edges (v, u), ascending.
    boundary: Vec<(u32, u32)>,
    /// Manifold edges' faces (f < g) and whether they traverse the edge the same way.
    adjacent: Vec<(u32, u32, bool)>,
    inconsistent_edges: usize,
    /// Faces whose vertex set equals an earlier face's, counted at their smallest vertex.
    duplicate_faces: usize,
}

/// The star pass of [`analyze`] over `range`: for each vertex v, its faces' edges
/// {v, u} with u > v as (u, face, traversed from v to u), sorted by (u, face): one run
/// per edge, with its faces ascending (what a global sort of the half-edges by (lo, hi,
/// face) gives, edge by edge); v's link; and the vertex sets of the faces whose
/// smallest vertex is v.
#[cfg(test)]
fn stars_of(range: std::ops::Range<usize>, tris: &[[u32; 3]], vcorners: &StarLists) -> Stars {
    stars_of_with(range, tris, vcorners, false)
}

/// [`stars_of`], with `fast`: a vertex whose star is one consistently oriented disk
/// cycle of 3 to [`SMALL_LINK`] faces ([`is_one_directed_cycle`]: the common vertex of a
/// closed or bordered manifold) is settled from that cycle alone: each link vertex u
/// starts exactly one link edge (the face runs v → u) and ends exactly one (u → v),
/// so the edge {v, u} is in exactly those two faces, traversed in opposite directions
/// (manifold, not boundary, not inconsistent); v's link is a cycle; and no two faces of
/// the star have the same vertex set (with n ≥ 3 faces, v a b and v b a would close a
/// 2-cycle, and a repeated v a b a repeated start). So the counts are those of the
/// general pass; only the face pairs of [`Stars::adjacent`] are not listed (the
/// orientation search needs them only when some edge is inconsistent, and [`analyze`]
/// then runs the general pass).
fn stars_of_with(
    range: std::ops::Range<usize>,
    tris: &[[u32; 3]],
    vcorners: &StarLists,
    fast: bool,
) -> Stars {
    let mut out = Stars {
        first: range.start,
        at: vec![StarCounts::default(); range.len()],
        boundary: Vec::new(),
        adjacent: Vec::new(),
        inconsistent_edges: 0,
        duplicate_faces: 0,
    };
    let mut half: Vec<(u32, u32, bool)> = Vec::new();
    let mut sets: Vec<(u32, u32)> = Vec::new();
    let mut scratch = LinkScratch::default();
    for (k, v) in range.enumerate() {
        let cs = vcorners.bucket(v);
        if cs.is_empty() {
            continue;
        }
        let v32 = v as u32;
        if fast && cs.len() >= 3 && cs.len() <= SMALL_LINK {
            let mut ends = [(0u32, 0u32); SMALL_LINK];
            for (e, &c) in ends.iter_mut().zip(cs) {
                *e = corner_ends(c, tris);
            }
            let ends = &ends[..cs.len()];
            if is_one_directed_cycle(ends) {
                out.at[k].edges = ends.iter().filter(|e| e.0 > v32).count() as u32;
                continue;
            }
        }
        half.clear();
        sets.clear();
        for &c in cs {
            let f = c / 3;
            // The face runs v -> a and b -> v.
            let (a, b) = corner_ends(c, tris);
            if a > v32 {
                half.push((a, f, true));
            }
            if b > v32 {
                half.push((b, f, false));
            }
            if a > v32 && b > v32 {
                sets.push((a.min(b), a.max(b)));
            }
        }
        half.sort_unstable_by_key(|&(u, f, _)| (u, f));
        let at = &mut out.at[k];
        for run in half.chunk_by(|x, y| x.0 == y.0) {
            at.edges += 1;
            match run.len() {
                1 => {
                    out.boundary.push((v32, run[0].0));
                    at.boundary_edges += 1;
                }
                2 => {
                    let same = run[0].2 == run[1].2;
                    out.inconsistent_edges += same as usize;
                    if !fast {
                        out.adjacent.push((run[0].1, run[1].1, same));
                    }
                }
                _ => at.non_manifold_edges += 1,
            }
        }
        if sets.len() > 1 {
            sets.sort_unstable();
            out.duplicate_faces += sets.windows(2).filter(|w| w[0] == w[1]).count();
        }
        at.bad_link = !link_is_disk_or_sphere(cs, tris, &mut scratch);
    }
    out
}

/// [`stars_of_with`] over every vertex, in parallel chunks, in vertex order.
fn all_stars(nv: usize, tris: &[[u32; 3]], vcorners: &StarLists, fast: bool) -> Vec<Stars> {
    (0..nv.div_ceil(STAR_CHUNK))
        .into_par_iter()
        .map(|c| {
            stars_of_with(
                c * STAR_CHUNK..((c + 1) * STAR_CHUNK).min(nv),
                tris,
                vcorners,
                fast,
            )
        })
        .collect()
}

impl TopologyReport {
    /// A closed, consistently oriented 2-manifold (no boundary or non-manifold edge, no
    /// non-manifold vertex, no edge traversed twice in the same direction).
    pub fn is_closed_oriented_manifold(&self) -> bool {
        self.closed && self.manifold && self.consistently_oriented
    }
}

/// The topology of a triangle mesh. Errors only on out-of-range vertex indices.
pub fn analyze(mesh: &TriMesh) -> Result<TopologyReport> {
    check_trimesh(mesh)?;
    let nv = mesh.vertices.len();
    let tris = &mesh.triangles;
    let nf = tris.len();
    let degenerate: Vec<bool> = tris.iter().map(|&t| TriMesh::repeats_vertex(t)).collect();

    // Components (union the vertices of every face) beside the stars (every vertex's
    // corners in non-degenerate faces, in face order) and one parallel pass over them, which
    // finds every edge at its smaller vertex, the link of every vertex and the
    // duplicate faces at their smallest vertex; consistently oriented disk stars are
    // settled on the fast path of [`stars_of_with`].
    let ((used, comp_of, ncomp), (vcorners, stars)) = rayon::join(
        || {
            let mut uf = UnionFind::for_join(nv);
            let mut used = vec![false; nv];
            for t in tris {
                uf.join(t[0], t[1]);
                uf.join(t[0], t[2]);
                for &v in t {
                    used[v as usize] = true;
                }
            }
            // Every vertex's component, numbered by smallest vertex, in place of its
            // parent: parents come before their vertex (`join`), so an ascending pass
            // finds each parent already numbered; a root is its component's smallest
            // vertex. (An unused vertex is a root of its own, left unnumbered.)
            let mut comp_of = uf.parent;
            let mut ncomp = 0usize;
            for v in 0..nv {
                let p = comp_of[v] as usize;
                comp_of[v] = if p != v {
                    comp_of[p]
                } else if used[v] {
                    ncomp += 1;
                    (ncomp - 1) as u32
                } else {
                    u32::MAX
                };
            }
            (used, comp_of, ncomp)
        },
        || {
            let vcorners = star_buckets(nv, tris, &degenerate);
            let stars = all_stars(nv, tris, &vcorners, true);
            (vcorners, stars)
        },
    );
    // Some edge is traversed twice in the same direction: the orientation search needs
    // the face pairs of every manifold edge, which the general pass lists (the same
    // counts as the fast one).
    let stars = if stars.iter().any(|s| s.inconsistent_edges > 0) {
        all_stars(nv, tris, &vcorners, false)
    } else {
        stars
    };
    drop(vcorners);
    // (One component: no lookups.)
    let comp = |v: u32| {
        if ncomp == 1 {
            0
        } else {
            comp_of[v as usize] as usize
        }
    };

    let mut c_edges = vec![0usize; ncomp];
    let mut c_faces = vec![0usize; ncomp];
    let mut c_verts = vec![0usize; ncomp];
    let mut c_bedges = vec![0usize; ncomp];
    let mut c_bad = vec![false; ncomp]; // non-manifold somewhere
    let mut c_nonorientable = vec![false; ncomp];
    let mut edges = 0usize;
    let mut non_manifold_edges = 0usize;
    let mut inconsistent_edges = 0usize;
    let mut duplicate_faces = 0usize;
    let mut non_manifold_vertices = 0;
    // The stars' results, in vertex order (so the boundary edges and the face
    // adjacencies come ascending by edge, as a sort of the edges would give them).
    let mut boundary: Vec<(u32, u32)> = Vec::new();
    // Face adjacency over manifold edges: (f, g, same direction).
    let mut adj_pairs: Vec<(u32, u32, bool)> = Vec::new();
    // (A vertex without a star, unused or in degenerate faces only, counts zero. One
    // component's sums are the totals, set after the loop: no per-vertex store.)
    let mut any_bad = false;
    for st in stars {
        for (k, at) in st.at.iter().enumerate() {
            let bad = at.non_manifold_edges > 0 || at.bad_link;
            non_manifold_vertices += at.bad_link as usize;
            edges += at.edges as usize;
            non_manifold_edges += at.non_manifold_edges as usize;
            any_bad |= bad;
            if ncomp > 1 && used[st.first + k] {
                let c = comp_of[st.first + k] as usize;
                c_edges[c] += at.edges as usize;
                c_bedges[c] += at.boundary_edges as usize;
                c_bad[c] |= bad;
            }
        }
        inconsistent_edges += st.inconsistent_edges;
        duplicate_faces += st.duplicate_faces;
        boundary.extend_from_slice(&st.boundary);
        adj_pairs.extend_from_slice(&st.adjacent);
    }
    // Degenerate faces have no star: their duplicates are counted among themselves
    // (a repeated index keeps them apart from every non-degenerate face's vertex set).
    let mut degenerate_sets: Vec<[u32; 3]> = tris
        .iter()
        .zip(&degenerate)
        .filter(|(_, &d)| d)
        .map(|(t, _)| {
            let mut k = *t;
            k.sort_unstable();
            k
        })
        .collect();
    degenerate_sets.sort_unstable();
    duplicate_faces += degenerate_sets.windows(2).filter(|w| w[0] == w[1]).count();
    let vertices = used.iter().filter(|&&u| u).count();
    let degenerate_faces = degenerate.iter().filter(|&&d| d).count();
    if ncomp == 1 {
        c_edges[0] = edges;
        c_bedges[0] = boundary.len();
        c_bad[0] = any_bad || degenerate_faces > 0;
        c_faces[0] = nf - degenerate_faces;
        c_verts[0] = vertices;
    } else {
        for (f, t) in tris.iter().enumerate() {
            let c = comp(t[0]);
            if degenerate[f] {
                c_bad[c] = true;
            } else {
                c_faces[c] += 1;
            }
        }
        for v in 0..nv {
            if used[v] {
                c_verts[comp(v as u32)] += 1;
            }
        }
    }

    // Orientability (two-colour faces by "flipped or not" along manifold edges). With
    // no inconsistent edge, every pair is "not flipped": no face is flipped and there
    // is no conflict, so the search is skipped.
    let nonorientable = if inconsistent_edges == 0 {
        Vec::new()
    } else {
        let mut nonorientable = Vec::new();
        let mut start = vec![0u32; nf + 1];
        for &(f, g, _) in &adj_pairs {
            start[f as usize + 1] += 1;
            start[g as usize + 1] += 1;
        }
        for k in 0..nf {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut nbr = vec![(0u32, false); 2 * adj_pairs.len()];
        for &(f, g, s) in &adj_pairs {
            nbr[fill[f as usize] as usize] = (g, s);
            fill[f as usize] += 1;
            nbr[fill[g as usize] as usize] = (f, s);
            fill[g as usize] += 1;
        }
        let mut flip = vec![u8::MAX; nf];
        let mut queue = Vec::new();
        for f0 in 0..nf {
            if flip[f0] != u8::MAX || degenerate[f0] {
                continue;
            }
            flip[f0] = 0;
            queue.push(f0 as u32);
            while let Some(f) = queue.pop() {
                let ff = flip[f as usize];
                for &(g, same) in &nbr[start[f as usize] as usize..start[f as usize + 1] as usize] {
                    // Sharing an edge in the same direction means one of the two is flipped.
                    let want = ff ^ (same as u8);
                    if flip[g as usize] == u8::MAX {
                        flip[g as usize] = want;
                        queue.push(g);
                    } else if flip[g as usize] != want {
                        nonorientable.push(f);
                    }
                }
            }
        }
        nonorientable
    };
    for f in nonorientable {
        c_nonorientable[comp(tris[f as usize][0])] = true;
    }

    // Boundary loops: cycle rank of the boundary graph, per component (none without
    // boundary edges).
    let mut c_loops: Vec<i64> = c_bedges.iter().map(|&e| e as i64).collect();
    let (mut buf, mut on_boundary) = if boundary.is_empty() {
        (UnionFind::default(), Vec::new())
    } else {
        (UnionFind::new(nv), vec![false; nv])
    };
    for &(a, b) in &boundary {
        buf.union(a, b);
        on_boundary[a as usize] = true;
        on_boundary[b as usize] = true;
    }
    for v in 0..on_boundary.len() {
        if on_boundary[v] {
            let c = comp(v as u32);
            c_loops[c] -= 1; // − V_b
            if buf.find(v as u32) == v as u32 {
                c_loops[c] += 1; // + C_b
            }
        }
    }

    let mut component_list: Vec<ComponentReport> = (0..ncomp)
        .map(|c| {
            let chi = c_verts[c] as i64 - c_edges[c] as i64 + c_faces[c] as i64;
            let loops = c_loops[c].max(0) as usize;
            let manifold = !c_bad[c];
            let orientable = !c_nonorientable[c];
            let twice_g = 2 - chi - loops as i64;
            let genus = (manifold && orientable && twice_g >= 0 && twice_g % 2 == 0)
                .then_some((twice_g / 2) as usize);
            ComponentReport {
                vertices: c_verts[c],
                edges: c_edges[c],
                faces: c_faces[c],
                euler_characteristic: chi,
                boundary_edges: c_bedges[c],
                boundary_loops: loops,
                closed: c_bedges[c] == 0,
                manifold,
                orientable,
                genus,
            }
        })
        .collect();
    // Largest first, for readable reports.
    component_list.sort_by(|a, b| b.faces.cmp(&a.faces).then(b.vertices.cmp(&a.vertices)));
    let mut genus: Vec<usize> = component_list
        .iter()
        .filter(|c| c.closed)
        .filter_map(|c| c.genus)
        .collect();
    genus.sort_unstable();
    let orientable = component_list.iter().all(|c| c.orientable);
    let manifold = non_manifold_edges == 0 && non_manifold_vertices == 0 && degenerate_faces == 0;
    Ok(TopologyReport {
        vertices,
        isolated_vertices: nv - vertices,
        edges,
        faces: nf,
        euler_characteristic: vertices as i64 - edges as i64 + (nf - degenerate_faces) as i64,
        components: ncomp,
        boundary_edges: boundary.len(),
        boundary_loops: component_list.iter().map(|c| c.boundary_loops).sum(),
        non_manifold_edges,
        non_manifold_vertices,
        degenerate_faces,
        duplicate_faces,
        inconsistent_edges,
        closed: boundary.is_empty(),
        manifold,
        orientable,
        consistently_oriented: orientable && inconsistent_edges == 0,
        genus,
        component_list,
    })
}

/// The topology of a set of planar polylines.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CurveTopology {
    /// Vertices used by segments.
    pub vertices: usize,
    pub isolated_vertices: usize,
    pub segments: usize,
    /// Segments joining a vertex to itself (ignored otherwise).
    pub degenerate_segments: usize,
    /// Segments joining the same two vertices as an earlier segment.
    pub duplicate_segments: usize,
    /// Connected components: those of the segments, and each isolated vertex (a
    /// point component, e.g. an isolated real point of an algebraic curve, which the
    /// exact sweep keeps).
    pub components: usize,
    /// Components all of whose vertices have degree 2 (simple closed curves).
    pub closed_components: usize,
    /// Vertices of degree 1.
    pub open_ends: usize,
    /// Vertices of degree 3 or more.
    pub branch_points: usize,
    /// Every component is a simple closed curve.
    pub closed: bool,
}

pub fn analyze_curve(curve: &Curve2) -> Result<CurveTopology> {
    check_curve(curve)?;
    let nv = curve.vertices.len();
    let mut deg = vec![0u32; nv];
    let mut used = vec![false; nv];
    let mut uf = UnionFind::new(nv);
    let mut degenerate_segments = 0;
    for &[a, b] in &curve.segments {
        used[a as usize] = true;
        used[b as usize] = true;
        if a == b {
            degenerate_segments += 1;
            continue;
        }
        deg[a as usize] += 1;
        deg[b as usize] += 1;
        uf.union(a, b);
    }
    let mut keys: Vec<(u32, u32)> = curve
        .segments
        .iter()
        .map(|&[a, b]| (a.min(b), a.max(b)))
        .collect();
    keys.sort_unstable();
    let duplicate_segments = keys.windows(2).filter(|w| w[0] == w[1]).count();
    // Per root: (is a component, all degree 2).
    let mut all2 = vec![true; nv];
    let mut is_root = vec![false; nv];
    for v in 0..nv {
        if used[v] {
            let r = uf.find(v as u32) as usize;
            is_root[r] = true;
            if deg[v] != 2 {
                all2[r] = false;
            }
        }
    }
    let vertices = used.iter().filter(|&&u| u).count();
    let components = is_root.iter().filter(|&&r| r).count() + (nv - vertices);
    let closed_components = (0..nv).filter(|&r| is_root[r] && all2[r]).count();
    let open_ends = deg.iter().filter(|&&d| d == 1).count();
    let branch_points = deg.iter().filter(|&&d| d >= 3).count();
    Ok(CurveTopology {
        vertices,
        isolated_vertices: nv - vertices,
        segments: curve.segments.len(),
        degenerate_segments,
        duplicate_segments,
        components,
        closed_components,
        open_ends,
        branch_points,
        closed: closed_components == components && degenerate_segments == 0,
    })
}

/// The topology of a tetrahedral mesh and of its boundary surface.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TetTopology {
    pub vertices: usize,
    pub isolated_vertices: usize,
    pub tets: usize,
    /// Tetrahedra with a repeated vertex index (left out of the face counts).
    pub degenerate_tets: usize,
    pub components: usize,
    /// Faces in exactly one tetrahedron.
    pub boundary_faces: usize,
    /// Faces in exactly two tetrahedra.
    pub interior_faces: usize,
    /// Faces in three or more tetrahedra: the mesh is not conforming there.
    pub nonconforming_faces: usize,
    /// The boundary is a closed manifold (and the mesh conforming).
    pub boundary_closed_manifold: bool,
    pub boundary_euler_characteristic: i64,
    /// The full report of the boundary surface (outward for positively oriented tets).
    pub boundary: TopologyReport,
}

pub fn analyze_tets(mesh: &TetMesh) -> Result<TetTopology> {
    check_tetmesh(mesh)?;
    let nv = mesh.vertices.len();
    let mut used = vec![false; nv];
    let mut uf = UnionFind::new(nv);
    let mut degenerate_tets = 0;
    for t in &mesh.tets {
        for &v in t {
            used[v as usize] = true;
        }
        uf.union(t[0], t[1]);
        uf.union(t[0], t[2]);
        uf.union(t[0], t[3]);
        if (0..4).any(|i| (i + 1..4).any(|j| t[i] == t[j])) {
            degenerate_tets += 1;
        }
    }
    // Faces grouped by vertex set (linear time); boundary faces in vertex-set order.
    let faces = mesh.face_buckets(true);
    let (mut boundary_faces, mut interior_faces, mut nonconforming_faces) = (0, 0, 0);
    let mut btris = Vec::new();
    for v in 0..faces.len() {
        for run in faces.runs(v, |x| x.0) {
            match run.len() {
                1 => {
                    boundary_faces += 1;
                    btris.push(run[0].1);
                }
                2 => interior_faces += 1,
                _ => nonconforming_faces += 1,
            }
        }
    }
    drop(faces);
    let mut surf = TriMesh::new(mesh.vertices.clone(), btris);
    surf.compact();
    let boundary = analyze(&surf)?;
    // A set of used vertices has a used root (unions join tetrahedron corners only).
    let components = (0..nv as u32)
        .filter(|&v| used[v as usize] && uf.find(v) == v)
        .count();
    let vertices = used.iter().filter(|&&u| u).count();
    Ok(TetTopology {
        vertices,
        isolated_vertices: nv - vertices,
        tets: mesh.tets.len(),
        degenerate_tets,
        components,
        boundary_faces,
        interior_faces,
        nonconforming_faces,
        boundary_closed_manifold: boundary.closed && boundary.manifold && nonconforming_faces == 0,
        boundary_euler_characteristic: boundary.euler_characteristic,
        boundary,
    })
}

/// Does a mesh have the expected topology?
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Verdict {
    pub ok: bool,
    /// e.g. "1 component, genus [1]".
    pub expected: String,
    /// e.g. "2 components, genus [0, 1]".
    pub found: String,
    /// Why not, in words ("" when ok).
    pub reason: String,
}

fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// "n things" onto the problems for each count n > 0, as (n, singular, plural).
fn count(problems: &mut Vec<String>, counts: &[(usize, &str, &str)]) {
    for &(n, one, many) in counts {
        if n > 0 {
            problems.push(plural(n, one, many));
        }
    }
}

/// "n components instead of m" onto the problems when n != m.
fn component_count(problems: &mut Vec<String>, found: usize, expected: usize) {
    if found != expected {
        problems.push(format!("{} instead of {expected}", components(found)));
    }
}

fn components(n: usize) -> String {
    plural(n, "component", "components")
}

fn genus_list(g: &[usize]) -> String {
    let items: Vec<String> = g.iter().map(|g| g.to_string()).collect();
    format!("[{}]", items.join(", "))
}

fn finish(expected: String, found: String, problems: Vec<String>) -> Verdict {
    Verdict {
        ok: problems.is_empty(),
        expected,
        found,
        reason: problems.join("; "),
    }
}

/// Compare a surface mesh with the expected topology: the right number of components,
/// each closed, manifold and orientable, with the expected multiset of genera.
pub fn verdict(report: &TopologyReport, expected: &Topology) -> Verdict {
    let mut want: Vec<usize> = expected.genus.to_vec();
    want.sort_unstable();
    let exp = format!(
        "{}, genus {}",
        components(expected.components),
        genus_list(&want)
    );
    let per: Vec<String> = report
        .component_list
        .iter()
        .map(|c| match c.genus {
            Some(g) if c.closed => g.to_string(),
            _ if !c.manifold => "non-manifold".into(),
            _ if !c.orientable => "non-orientable".into(),
            _ => format!("open ({})", plural(c.boundary_loops, "hole", "holes")),
        })
        .collect();
    let found = format!(
        "{}, genus [{}]",
        components(report.components),
        per.join(", ")
    );
    let mut p = Vec::new();
    if report.faces == 0 {
        p.push("the mesh is empty".to_string());
    }
    component_count(&mut p, report.components, expected.components);
    if !report.closed {
        p.push(format!(
            "not closed: {} in {}",
            plural(report.boundary_edges, "boundary edge", "boundary edges"),
            plural(report.boundary_loops, "loop", "loops")
        ));
    }
    count(
        &mut p,
        &[
            (
                report.non_manifold_edges,
                "non-manifold edge",
                "non-manifold edges",
            ),
            (
                report.non_manifold_vertices,
                "non-manifold vertex",
                "non-manifold vertices",
            ),
            (
                report.degenerate_faces,
                "degenerate face",
                "degenerate faces",
            ),
            (report.duplicate_faces, "duplicate face", "duplicate faces"),
        ],
    );
    if !report.orientable {
        p.push("a component is not orientable".into());
    }
    if report.closed && report.manifold && report.orientable && report.genus != want {
        p.push(format!(
            "genus {} instead of {}",
            genus_list(&report.genus),
            genus_list(&want)
        ));
    }
    finish(exp, found, p)
}

/// Compare a curve with the expected topology: that many simple closed curves, with no
/// open ends or branch points.
pub fn curve_verdict(report: &CurveTopology, expected: &Topology) -> Verdict {
    let exp = plural(expected.components, "closed curve", "closed curves");
    let mut found = format!(
        "{}, {} closed",
        components(report.components),
        report.closed_components
    );
    if report.open_ends > 0 {
        found += &format!(", {}", plural(report.open_ends, "open end", "open ends"));
    }
    if report.branch_points > 0 {
        found += &format!(
            ", {}",
            plural(report.branch_points, "branch point", "branch points")
        );
    }
    let mut p = Vec::new();
    if report.segments == 0 {
        p.push("the curve is empty".to_string());
    }
    component_count(&mut p, report.components, expected.components);
    count(
        &mut p,
        &[
            (report.open_ends, "open end", "open ends"),
            (report.branch_points, "branch point", "branch points"),
        ],
    );
    if report.closed_components != report.components && report.open_ends == 0 {
        p.push("a component is not a simple closed curve".into());
    }
    count(
        &mut p,
        &[
            (
                report.degenerate_segments,
                "degenerate segment",
                "degenerate segments",
            ),
            (
                report.duplicate_segments,
                "duplicate segment",
                "duplicate segments",
            ),
        ],
    );
    finish(exp, found, p)
}

/// Compare a volume mesh's boundary with the expected topology of the surface, and
/// require the volume mesh to be conforming.
pub fn tet_verdict(report: &TetTopology, expected: &Topology) -> Verdict {
    let mut v = verdict(&report.boundary, expected);
    let mut extra = Vec::new();
    count(
        &mut extra,
        &[
            (
                report.nonconforming_faces,
                "face in 3 or more tetrahedra",
                "faces in 3 or more tetrahedra",
            ),
            (
                report.degenerate_tets,
                "degenerate tetrahedron",
                "degenerate tetrahedra",
            ),
        ],
    );
    if !extra.is_empty() {
        v.ok = false;
        if !v.reason.is_empty() {
            v.reason += "; ";
        }
        v.reason += &extra.join("; ");
    }
    v
}

#[cfg(test)]
mod tests {
    //! The linear-time incidences (buckets by the smallest vertex) against the global
    //! sorts they replaced (issue 20), on random triangle and tetrahedron soups with
    //! repeated, degenerate and non-manifold elements.
    use super::*;
    use proptest::prelude::*;

    /// Edges as the former `analyze` found them: a global sort of (edge, face, direction).
    fn edges_by_sort(tris: &[[u32; 3]], degenerate: &[bool]) -> Vec<(u32, u32, Vec<(u32, bool)>)> {
        let mut half: Vec<(u64, u32, bool)> = Vec::new();
        for (f, t) in tris.iter().enumerate() {
            if degenerate[f] {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let (lo, hi) = if a < b { (a, b) } else { (b, a) };
                half.push((((lo as u64) << 32) | hi as u64, f as u32, a < b));
            }
        }
        half.sort_unstable();
        half.chunk_by(|x, y| x.0 == y.0)
            .map(|r| {
                let k = r[0].0;
                let faces = r.iter().map(|h| (h.1, h.2)).collect();
                ((k >> 32) as u32, k as u32, faces)
            })
            .collect()
    }

    /// Tetrahedron faces as the former `analyze_tets` grouped them.
    fn tet_faces_by_sort(tets: &[[u32; 4]]) -> Vec<Vec<([u32; 3], [u32; 3])>> {
        let mut faces = Vec::new();
        for t in tets {
            if (0..4).any(|i| (i + 1..4).any(|j| t[i] == t[j])) {
                continue;
            }
            for f in crate::mesh::TET_FACES {
                let tri = f.map(|k| t[k]);
                let mut key = tri;
                key.sort_unstable();
                faces.push((key, tri));
            }
        }
        faces.sort_unstable();
        faces
            .chunk_by(|x, y| x.0 == y.0)
            .map(|r| r.to_vec())
            .collect()
    }

    /// Every field of [`analyze`]'s report, computed the plain way (issue 20: the
    /// reference of the fast paths): edges in a sorted map, links and orientations by
    /// searches over explicit lists, components by a union-find over the faces, one
    /// component at a time; nothing shared with `analyze` but [`UnionFind`].
    fn reference(nv: usize, tris: &[[u32; 3]]) -> TopologyReport {
        use std::collections::{BTreeMap, BTreeSet};
        let degenerate = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
        let mut used = vec![false; nv];
        let mut uf = UnionFind::new(nv);
        for t in tris {
            for &v in t {
                used[v as usize] = true;
            }
            uf.union(t[0], t[1]);
            uf.union(t[1], t[2]);
        }
        // Components numbered by their smallest vertex.
        let mut id = BTreeMap::new();
        for v in 0..nv as u32 {
            if used[v as usize] {
                let r = uf.find(v);
                let k = id.len();
                id.entry(r).or_insert(k);
            }
        }
        let ncomp = id.len();
        let comp = |uf: &mut UnionFind, v: u32| id[&uf.find(v)];
        // Edges: (lo, hi) -> [(face, traversed lo -> hi)].
        let mut edges: BTreeMap<(u32, u32), Vec<(usize, bool)>> = BTreeMap::new();
        for (f, t) in tris.iter().enumerate() {
            if degenerate(t) {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                edges
                    .entry((a.min(b), a.max(b)))
                    .or_default()
                    .push((f, a < b));
            }
        }
        // Links: v -> its faces' opposite edges.
        let mut link: Vec<Vec<(u32, u32)>> = vec![Vec::new(); nv];
        for t in tris.iter().filter(|t| !degenerate(t)) {
            for k in 0..3 {
                link[t[k] as usize].push((t[(k + 1) % 3], t[(k + 2) % 3]));
            }
        }
        let link_ok = |l: &Vec<(u32, u32)>| {
            if l.is_empty() {
                return true;
            }
            let mut deg: BTreeMap<u32, usize> = BTreeMap::new();
            for &(a, b) in l {
                *deg.entry(a).or_default() += 1;
                *deg.entry(b).or_default() += 1;
            }
            // Connected: grow from the first edge.
            let mut reached: BTreeSet<u32> = [l[0].0, l[0].1].into();
            loop {
                let before = reached.len();
                for &(a, b) in l {
                    if reached.contains(&a) || reached.contains(&b) {
                        reached.insert(a);
                        reached.insert(b);
                    }
                }
                if reached.len() == before {
                    break;
                }
            }
            reached.len() == deg.len() && deg.values().all(|&d| d <= 2)
        };
        let bad_vertex: Vec<bool> = (0..nv).map(|v| used[v] && !link_ok(&link[v])).collect();
        // Orientation: two-colour the faces over manifold edges, per component.
        let mut flip: Vec<Option<bool>> = vec![None; tris.len()];
        let mut nonorientable = vec![false; ncomp];
        let mut pairs: Vec<Vec<(usize, bool)>> = vec![Vec::new(); tris.len()];
        for fs in edges.values() {
            if fs.len() == 2 {
                let same = fs[0].1 == fs[1].1;
                pairs[fs[0].0].push((fs[1].0, same));
                pairs[fs[1].0].push((fs[0].0, same));
            }
        }
        for f0 in 0..tris.len() {
            if flip[f0].is_some() || degenerate(&tris[f0]) {
                continue;
            }
            flip[f0] = Some(false);
            let mut stack = vec![f0];
            while let Some(f) = stack.pop() {
                for &(g, same) in &pairs[f] {
                    let want = flip[f].unwrap() ^ same;
                    match flip[g] {
                        None => {
                            flip[g] = Some(want);
                            stack.push(g);
                        }
                        Some(x) if x != want => nonorientable[comp(&mut uf, tris[f][0])] = true,
                        _ => {}
                    }
                }
            }
        }
        // Per component.
        let mut cv = vec![0usize; ncomp];
        let mut ce = vec![0usize; ncomp];
        let mut cf = vec![0usize; ncomp];
        let mut cb = vec![0usize; ncomp];
        let mut bad = vec![false; ncomp];
        for v in 0..nv {
            if used[v] {
                let c = comp(&mut uf, v as u32);
                cv[c] += 1;
                bad[c] |= bad_vertex[v];
            }
        }
        let mut bverts: BTreeSet<u32> = BTreeSet::new();
        let mut buf = UnionFind::new(nv);
        for (&(a, _b), fs) in &edges {
            let c = comp(&mut uf, a);
            ce[c] += 1;
            if fs.len() == 1 {
                cb[c] += 1;
                bverts.insert(a);
                bverts.insert(_b);
                buf.union(a, _b);
            }
            bad[c] |= fs.len() > 2;
        }
        for t in tris {
            let c = comp(&mut uf, t[0]);
            if degenerate(t) {
                bad[c] = true;
            } else {
                cf[c] += 1;
            }
        }
        let mut loops: Vec<i64> = cb.iter().map(|&b| b as i64).collect();
        for &v in &bverts {
            let c = comp(&mut uf, v);
            loops[c] -= 1;
            if buf.find(v) == v {
                loops[c] += 1;
            }
        }
        let mut list: Vec<ComponentReport> = (0..ncomp)
            .map(|c| {
                let chi = cv[c] as i64 - ce[c] as i64 + cf[c] as i64;
                let b = loops[c].max(0) as usize;
                let twice_g = 2 - chi - b as i64;
                let (manifold, orientable) = (!bad[c], !nonorientable[c]);
                ComponentReport {
                    vertices: cv[c],
                    edges: ce[c],
                    faces: cf[c],
                    euler_characteristic: chi,
                    boundary_edges: cb[c],
                    boundary_loops: b,
                    closed: cb[c] == 0,
                    manifold,
                    orientable,
                    genus: (manifold && orientable && twice_g >= 0 && twice_g % 2 == 0)
                        .then_some((twice_g / 2) as usize),
                }
            })
            .collect();
        list.sort_by(|a, b| b.faces.cmp(&a.faces).then(b.vertices.cmp(&a.vertices)));
        let mut sets = BTreeSet::new();
        let mut duplicate_faces = 0;
        for t in tris {
            let mut k = *t;
            k.sort_unstable();
            duplicate_faces += !sets.insert(k) as usize;
        }
        let vertices = used.iter().filter(|&&u| u).count();
        let degenerate_faces = tris.iter().filter(|t| degenerate(t)).count();
        let non_manifold_edges = edges.values().filter(|f| f.len() > 2).count();
        let non_manifold_vertices = bad_vertex.iter().filter(|&&b| b).count();
        let inconsistent_edges = edges
            .values()
            .filter(|f| f.len() == 2 && f[0].1 == f[1].1)
            .count();
        let boundary_edges = edges.values().filter(|f| f.len() == 1).count();
        let mut genus: Vec<usize> = list
            .iter()
            .filter(|c| c.closed)
            .filter_map(|c| c.genus)
            .collect();
        genus.sort_unstable();
        let orientable = !nonorientable.contains(&true);
        TopologyReport {
            vertices,
            isolated_vertices: nv - vertices,
            edges: edges.len(),
            faces: tris.len(),
            euler_characteristic: vertices as i64 - edges.len() as i64
                + (tris.len() - degenerate_faces) as i64,
            components: ncomp,
            boundary_edges,
            boundary_loops: list.iter().map(|c| c.boundary_loops).sum(),
            non_manifold_edges,
            non_manifold_vertices,
            degenerate_faces,
            duplicate_faces,
            inconsistent_edges,
            closed: boundary_edges == 0,
            manifold: non_manifold_edges == 0
                && non_manifold_vertices == 0
                && degenerate_faces == 0,
            orientable,
            consistently_oriented: orientable && inconsistent_edges == 0,
            genus,
            component_list: list,
        }
    }

    /// A closed, consistently oriented torus of n × m quads (each two triangles), its
    /// vertices from `base`: every star a disk cycle of six faces (the fast path).
    fn torus_grid(n: u32, m: u32, base: u32) -> Vec<[u32; 3]> {
        let id = |i: u32, j: u32| base + (i % n) * m + (j % m);
        (0..n)
            .flat_map(|i| {
                (0..m).flat_map(move |j| {
                    [
                        [id(i, j), id(i + 1, j), id(i + 1, j + 1)],
                        [id(i, j), id(i + 1, j + 1), id(i, j + 1)],
                    ]
                })
            })
            .collect()
    }

    /// Closed oriented pieces (tetrahedra, octahedra, tori) edited by random changes
    /// (flipped, deleted, repeated, degenerate and extra faces, two pieces pinched
    /// together at a vertex), relabelled by a random permutation and shuffled: the
    /// fast paths' meshes and their near misses.
    fn edited_meshes() -> impl Strategy<Value = (usize, Vec<[u32; 3]>)> {
        let piece = prop_oneof![
            Just(0u32..0).prop_map(|_| (0u32, 0u32)),
            Just(()).prop_map(|_| (1u32, 0u32)),
            (3u32..6, 3u32..6),
        ];
        (
            prop::collection::vec(piece, 1..4),
            prop::collection::vec((0u8..6, any::<prop::sample::Index>(), 0u32..1000), 0..6),
            0usize..3,
            any::<u64>(),
        )
            .prop_map(|(pieces, edits, isolated, seed)| {
                let mut tris: Vec<[u32; 3]> = Vec::new();
                let mut nv = 0u32;
                for (a, b) in pieces {
                    let b0 = nv;
                    match (a, b) {
                        (0, 0) => {
                            // Tetrahedron, outward orientation.
                            tris.extend(
                                [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
                                    .map(|t| t.map(|x| x + b0)),
                            );
                            nv += 4;
                        }
                        (1, 0) => {
                            // Octahedron: poles 0, 5; equator 1..=4.
                            for k in 0..4u32 {
                                let (p, q) = (1 + k, 1 + (k + 1) % 4);
                                tris.push([b0, b0 + p, b0 + q]);
                                tris.push([b0 + 5, b0 + q, b0 + p]);
                            }
                            nv += 6;
                        }
                        (n, m) => {
                            tris.extend(torus_grid(n, m, b0));
                            nv += n * m;
                        }
                    }
                }
                for (kind, at, x) in edits {
                    if tris.is_empty() {
                        break;
                    }
                    let i = at.index(tris.len());
                    match kind {
                        0 => tris[i].swap(0, 1),
                        1 => {
                            tris.remove(i);
                        }
                        2 => tris.push(tris[i]),
                        3 => tris.push([tris[i][0], tris[i][0], tris[i][1]]),
                        4 => tris.push([tris[i][0], tris[i][1], x % nv]),
                        _ => {
                            // Pinch: one vertex of another face becomes this face's first.
                            let (v, w) = (tris[i][0], tris[(i + 1 + x as usize) % tris.len()][1]);
                            for t in tris.iter_mut() {
                                for c in t.iter_mut() {
                                    if *c == w {
                                        *c = v;
                                    }
                                }
                            }
                        }
                    }
                }
                let nv = nv as usize + isolated;
                // Relabel and shuffle (a small LCG from the seed).
                let mut s = seed | 1;
                let mut next = move |n: usize| {
                    s = s
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    ((s >> 33) as usize) % n.max(1)
                };
                let mut perm: Vec<u32> = (0..nv as u32).collect();
                for k in (1..nv).rev() {
                    perm.swap(k, next(k + 1));
                }
                let mut tris: Vec<[u32; 3]> =
                    tris.iter().map(|t| t.map(|v| perm[v as usize])).collect();
                for k in (1..tris.len()).rev() {
                    tris.swap(k, next(k + 1));
                }
                (nv, tris)
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]
        /// `analyze` (the fast disk-star path, the skipped orientation search and
        /// boundary union-find, the written-out star lists) equals the plain
        /// reference in every field, on edited closed meshes and on random soups.
        #[test]
        fn analyze_equals_reference_on_edited_meshes((nv, tris) in edited_meshes()) {
            let m = TriMesh { vertices: vec![[0.0; 3]; nv], triangles: tris.clone() };
            prop_assert_eq!(analyze(&m).unwrap(), reference(nv, &tris), "{:?}", tris);
        }

        #[test]
        fn analyze_equals_reference_on_soups(tris in soup::<3>(9, 30)) {
            let m = TriMesh { vertices: vec![[0.0; 3]; 9], triangles: tris.clone() };
            prop_assert_eq!(analyze(&m).unwrap(), reference(9, &tris), "{:?}", tris);
        }
    }

    /// The reference itself on known meshes: a torus grid is one closed orientable
    /// genus-1 component; two tetrahedra are two spheres.
    #[test]
    fn reference_knows_a_torus_and_two_spheres() {
        let t = torus_grid(4, 5, 0);
        let r = reference(20, &t);
        assert_eq!(
            (r.components, r.genus.clone(), r.euler_characteristic),
            (1, vec![1], 0)
        );
        assert!(r.closed && r.manifold && r.consistently_oriented);
        let mut two: Vec<[u32; 3]> = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]].to_vec();
        two.extend(two.clone().iter().map(|t| t.map(|x| x + 4)));
        let r = reference(8, &two);
        assert_eq!((r.components, r.genus.clone()), (2, vec![0, 0]));
        assert!(r.is_closed_oriented_manifold());
    }

    fn soup<const K: usize>(nv: u32, n: usize) -> impl Strategy<Value = Vec<[u32; K]>> {
        proptest::collection::vec(proptest::array::uniform(0..nv), 0..n)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// The stack check of small links agrees with the general one (sort, dedup,
        /// union-find) on random fans around vertex 0: cycles, paths, pinched and
        /// branching links, repeated faces.
        #[test]
        fn small_link_check_equals_general(
            fan in prop::collection::vec((1u32..9, 1u32..9), 1..SMALL_LINK + 1),
        ) {
            let tris: Vec<[u32; 3]> = fan.iter().map(|&(a, b)| [0, a, b]).collect();
            // Vertex 0 first in every face: corner 3 f.
            let corners: Vec<u32> = (0..tris.len() as u32).map(|f| 3 * f).collect();
            let small = small_link_is_disk_or_sphere(&corners, &tris);
            let mut s = LinkScratch::default();
            let general = general_link_is_disk_or_sphere(&corners, &tris, &mut s);
            prop_assert_eq!(small, general, "fan {:?}", fan);
        }

        /// The same on fans that are (nearly) cycles, where the directed-cycle fast
        /// path decides: a cycle of distinct link vertices, with some faces flipped,
        /// one face dropped (a path), or a second cycle through a shared vertex (a pinch) or
        /// apart from the first (a bow-tie).
        #[test]
        fn small_link_check_on_cycles_equals_general(
            ring in prop::sample::subsequence((1u32..40).collect::<Vec<_>>(), 3..12).prop_shuffle(),
            flips in prop::collection::vec(any::<bool>(), 12),
            drop_one in any::<bool>(),
            pinch in prop::option::of(prop::sample::subsequence((40u32..60).collect::<Vec<_>>(), 3..6)),
            shared in any::<bool>(),
        ) {
            let k = ring.len();
            let mut tris: Vec<[u32; 3]> = (0..k)
                .map(|i| {
                    let (a, b) = (ring[i], ring[(i + 1) % k]);
                    if flips[i % 12] && flips[(i + 5) % 12] { [0, b, a] } else { [0, a, b] }
                })
                .collect();
            if drop_one {
                tris.pop();
            }
            if let Some(p) = pinch {
                // Through ring[0] (a pinched link) or apart (a bow-tie of two cones).
                let cyc: Vec<u32> = if shared { std::iter::once(ring[0]).chain(p).collect() } else { p };
                let m = cyc.len();
                for i in 0..m {
                    tris.push([0, cyc[i], cyc[(i + 1) % m]]);
                }
            }
            tris.truncate(SMALL_LINK);
            // Vertex 0 first in every face: corner 3 f.
            let corners: Vec<u32> = (0..tris.len() as u32).map(|f| 3 * f).collect();
            let small = small_link_is_disk_or_sphere(&corners, &tris);
            let mut s = LinkScratch::default();
            let general = general_link_is_disk_or_sphere(&corners, &tris, &mut s);
            prop_assert_eq!(small, general, "fan {:?}", tris);
        }

        /// The star pass finds the edges a global sort of the half-edges finds, in the
        /// same order (boundary edges, and the faces of manifold edges with their
        /// directions), and `analyze` counts edges, boundary, non-manifold and
        /// inconsistent edges and duplicate faces as the sort does.
        #[test]
        fn star_pass_equals_sorted_edges(tris in soup::<3>(10, 40)) {
            let degenerate: Vec<bool> = tris
                .iter()
                .map(|t| t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
                .collect();
            let sorted = edges_by_sort(&tris, &degenerate);
            let vcorners = star_buckets(10, &tris, &degenerate);
            let st = stars_of(0..10, &tris, &vcorners);
            let boundary: Vec<(u32, u32)> =
                sorted.iter().filter(|e| e.2.len() == 1).map(|e| (e.0, e.1)).collect();
            let adjacent: Vec<(u32, u32, bool)> = sorted
                .iter()
                .filter(|e| e.2.len() == 2)
                .map(|e| (e.2[0].0, e.2[1].0, e.2[0].1 == e.2[1].1))
                .collect();
            prop_assert_eq!(&st.boundary, &boundary);
            prop_assert_eq!(&st.adjacent, &adjacent);
            let per_vertex: Vec<u32> = (0..10).map(|v| sorted.iter().filter(|e| e.0 == v).count() as u32).collect();
            prop_assert_eq!(st.at.iter().map(|a| a.edges).collect::<Vec<_>>(), per_vertex);
            let m = TriMesh { vertices: vec![[0.0; 3]; 10], triangles: tris.clone() };
            let r = analyze(&m).unwrap();
            prop_assert_eq!(r.edges, sorted.len());
            prop_assert_eq!(r.boundary_edges, boundary.len());
            prop_assert_eq!(r.non_manifold_edges, sorted.iter().filter(|e| e.2.len() > 2).count());
            prop_assert_eq!(r.inconsistent_edges, adjacent.iter().filter(|a| a.2).count());
            let mut keys: Vec<[u32; 3]> = tris.iter().map(|t| { let mut k = *t; k.sort_unstable(); k }).collect();
            keys.sort_unstable();
            prop_assert_eq!(r.duplicate_faces, keys.windows(2).filter(|w| w[0] == w[1]).count());
        }

        /// `join` (Rem's splicing) makes the same sets as `union` (by size), on random
        /// pair lists, also repeated and self pairs; parents never exceed their node.
        #[test]
        fn join_makes_the_sets_union_makes(pairs in prop::collection::vec((0u32..40, 0u32..40), 0..120)) {
            let (mut a, mut b) = (UnionFind::new(40), UnionFind::new(40));
            for &(x, y) in &pairs {
                a.union(x, y);
                b.join(x, y);
                prop_assert!(b.parent.iter().enumerate().all(|(i, &p)| p as usize <= i));
            }
            for x in 0..40 {
                for y in 0..40 {
                    prop_assert_eq!(a.find(x) == a.find(y), b.find(x) == b.find(y), "{} {}", x, y);
                }
            }
        }

        #[test]
        fn tet_faces_equal_sorted(tets in soup::<4>(8, 30)) {
            let m = TetMesh { vertices: vec![[0.0; 3]; 8], tets };
            let b = m.face_buckets(true);
            let got: Vec<Vec<([u32; 3], [u32; 3])>> = (0..8)
                .flat_map(|v| {
                    b.runs(v, |x| x.0)
                        .map(|r| r.iter().map(|&((mid, hi), tri)| ([v as u32, mid, hi], tri)).collect())
                        .collect::<Vec<_>>()
                })
                .collect();
            prop_assert_eq!(got, tet_faces_by_sort(&m.tets));
        }
    }
}
