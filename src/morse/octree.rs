//! The adaptive octree of BCSV (`--algo bcsv`, the chapter "Meshing of Surfaces",
//! §1.5.2: "an octree-like subdivision of the bounding box into boxes, which are further
//! subdivided into a tetrahedral mesh T"): the refinement criterion, run by the one
//! subdivision engine ([`crate::subdivision::subdivide`]), full 2:1 balancing
//! ([`Tree::balance_with`]), and a conforming tetrahedralization of the balanced leaves.
//!
//! **Criterion** ([`criterion`]). A box with 0 ∉ □f (f continuous on it) is a leaf,
//! excluded (`Empty`), at any level. Every other box is split down to the minimum level
//! (the size condition of an attempt), and further until f is proven C^∞ on it (the
//! oracle's regularity flags) with 0 ∉ □∂f/∂x_k for some k: no critical point of f in
//! the box (`Proven { by: "no critical point", axis: k }`). A box touching ∂D is accepted
//! only with 0 ∉ □f on each of its faces on ∂D. The depth limit and the box budget leave
//! `Failed` leaves, and the attempt then certifies nothing, saying so.
//!
//! **Tetrahedra** ([`Octree::leaf_tets`]). Coordinates are integers at twice the finest
//! resolution (so leaf and face centres are grid points). The common face of two leaves
//! is cut into *pieces*: the faces of the finer of the two (a face whose neighbour
//! across is split is cut into its four quarters, recursively) — the same pieces from
//! both sides. A piece's edge is split at every leaf corner on it (found by bisection:
//! the corners on a dyadic edge are nested midpoints). A piece without such a point
//! is cut by its diagonal from its lowest to its highest corner; otherwise it is a fan
//! from its centre over the split edges. A leaf whose six faces are single pieces without
//! split points gets the six Kuhn tetrahedra (whose faces are exactly those diagonals);
//! any other leaf is a cone from its centre over the triangles of its pieces. Each
//! piece's triangles depend on the piece and the set of leaf corners only, so the two
//! leaves sharing it see the same triangles: the tetrahedra form a conforming complex
//! ([`check_conforming`] tests it: every interior triangle in exactly two tetrahedra on
//! opposite sides, every triangle on ∂D in one, all positively oriented, volumes summing
//! exactly to the domain's).
use crate::implicit::critical::linalg::{excludes_zero, sign};
use crate::implicit::{IBox, Implicit, Regularity};
use crate::kernel::geom::Aabb;
use crate::subdivision::{pkey, subdivide, Budget, Cell, Decision, Grid, Tree, Verdict};
use std::collections::{HashMap, HashSet};

/// The verdict of a box proven free of critical points of f.
pub const NO_CRITICAL: &str = "no critical point";

/// The proven sign of f on the box: f continuous there and 0 ∉ □f.
pub fn box_sign(f: &dyn Implicit, b: &IBox) -> Option<i8> {
    if f.regularity(b) < Regularity::Continuous {
        return None;
    }
    sign(crate::implicit::ops::enclose(f, b).0)
}

/// The proven sign of f on the closed box of `c`, or on its face (`axis`, `side`)
/// when `face` is given: from the box itself or from the smallest ancestor on which it
/// is proven (balancing gives children their parent's verdict without a new proof).
pub fn sign_on(f: &dyn Implicit, g: &Grid, c: Cell, face: Option<(usize, u8)>) -> Option<i8> {
    let mut a = c;
    loop {
        let (mut lo, mut hi) = g.cell_lo_hi(a);
        if let Some((ax, side)) = face {
            if side == 0 {
                hi[ax] = lo[ax];
            } else {
                lo[ax] = hi[ax];
            }
        }
        if let Some(s) = box_sign(f, &g.ibox(lo, hi)) {
            return Some(s);
        }
        a = parent(a)?;
    }
}

/// The cell containing `c` one level up (`None` for the root).
fn parent(c: Cell) -> Option<Cell> {
    (c.level > 0).then(|| Cell {
        level: c.level - 1,
        idx: c.idx.map(|x| x >> 1),
    })
}

/// The refinement criterion of adaptive BCSV (module documentation).
pub fn criterion(f: &dyn Implicit, g: &Grid, c: Cell, force: &HashSet<u64>) -> Decision {
    if (c.level as u32) < g.depth && force.contains(&c.key()) {
        return Decision::Split("refined where a previous try of the attempt failed");
    }
    let b = g.cell_ibox(c);
    if box_sign(f, &b).is_some() {
        return Decision::Leaf(Verdict::Empty);
    }
    let (lo, hi) = g.cell_lo_hi(c);
    let top = 1u32 << g.depth;
    for a in 0..3 {
        for (v, on) in [(lo[a], lo[a] == 0), (hi[a], hi[a] == top)] {
            if !on {
                continue;
            }
            let (mut p, mut q) = (lo, hi);
            p[a] = v;
            q[a] = v;
            if box_sign(f, &g.ibox(p, q)).is_none() {
                // Where two corners of the face have proven opposite signs, S does
                // cross ∂D: no refinement helps, stop here.
                let (u, w) = ((a + 1) % 3, (a + 2) % 3);
                let signs: Vec<_> = (0..4u32)
                    .map(|m| {
                        let mut x = p;
                        if m & 1 == 1 {
                            x[u] = q[u];
                        }
                        if m & 2 == 2 {
                            x[w] = q[w];
                        }
                        crate::implicit::ops::point_sign(f, g.point(x))
                    })
                    .collect();
                if f.regularity(&g.ibox(p, q)) >= Regularity::Continuous
                    && signs.iter().all(|s| s.rigorous)
                    && signs.iter().any(|s| s.pos)
                    && signs.iter().any(|s| !s.pos)
                {
                    return Decision::Leaf(Verdict::Failed("f = 0 meets the domain boundary"));
                }
                return Decision::Split("f = 0 may meet the domain boundary (0 in the enclosure of f on a boundary face)");
            }
        }
    }
    if f.regularity(&b) != Regularity::Smooth {
        return Decision::Split("f is not proven smooth on the box");
    }
    let grad = f.grad_interval(&b).g;
    match (0..3).find(|&k| excludes_zero(grad[k])) {
        Some(k) => Decision::Leaf(Verdict::Proven {
            by: NO_CRITICAL,
            axis: Some(k as u8),
        }),
        None => Decision::Split(
            "a critical point of f may lie in the box (0 in the enclosure of every partial derivative)",
        ),
    }
}

/// A piece of a leaf face (module documentation) with the leaf across it.
#[derive(Clone, Debug)]
pub struct Piece {
    /// Every vertex of the piece's triangles.
    pub verts: Vec<u32>,
    /// The leaf on the other side (`None`: the piece lies on ∂D).
    pub across: Option<usize>,
    /// The face of the leaf it lies on: axis and side (0 low, 1 high).
    pub axis: u8,
    pub side: u8,
}

/// The tetrahedra of one leaf and the pieces of its boundary.
#[derive(Clone, Debug, Default)]
pub struct LeafTets {
    pub tets: Vec<[u32; 4]>,
    pub pieces: Vec<Piece>,
}

/// The vertices of the tetrahedra: integer coordinates at twice the finest resolution.
#[derive(Clone, Debug)]
pub struct Vertices {
    ids: HashMap<u64, u32>,
    pub coords: Vec<[u32; 3]>,
    /// The grid of the doubled coordinates (depth + 1).
    pub grid: Grid,
}

impl Vertices {
    fn id(&mut self, p: [u32; 3]) -> u32 {
        let n = self.coords.len() as u32;
        *self.ids.entry(pkey(p)).or_insert_with(|| {
            self.coords.push(p);
            n
        })
    }
    /// The point of vertex `v` in space (exactly the tree's grid point where the
    /// coordinates are even).
    pub fn pos(&self, v: u32) -> [f64; 3] {
        self.grid.point(self.coords[v as usize])
    }
}

/// A balanced tree with its leaf look-up.
pub struct Octree {
    pub tree: Tree,
    leaf_of: HashMap<u64, usize>,
}

/// Splits of the per-box proofs for leaves added to W by a repair round (up to 64
/// pieces), as in the uniform version.
pub const PROOF_DEPTH: u32 = 2;

impl Octree {
    /// Subdivide the domain by [`criterion`] (every box not excluded split at least to
    /// `min_level`, at most to `max_depth`, within `max_boxes` box tests), then balance
    /// every leaf 2:1 against its face, edge and corner neighbours.
    /// The cells of `force` are split once more (local refinement where a previous try
    /// failed).
    pub fn build(
        f: &dyn Implicit,
        domain: &Aabb,
        min_level: u32,
        max_depth: u32,
        max_boxes: u64,
        time_limit: Option<f64>,
        force: &HashSet<u64>,
    ) -> Octree {
        let grid = Grid {
            domain: *domain,
            dim: 3,
            depth: max_depth,
        };
        let budget = Budget::new(max_boxes, time_limit);
        let mut tree = subdivide(grid, min_level, max_depth, &budget, &|g: &Grid, c| {
            criterion(f, g, c, force)
        });
        // Children of a split leaf: excluded if proven so, else they keep the parent's
        // verdict (interval enclosures are inclusion monotone: no critical point in a
        // box means none in its parts).
        tree.balance_with(true, &|g: &Grid, c: Cell, v: Verdict| {
            if box_sign(f, &g.cell_ibox(c)).is_some() {
                Verdict::Empty
            } else {
                v
            }
        });
        tree.collect_points();
        Octree::new(tree)
    }

    /// The look-up of a finished tree.
    pub fn new(tree: Tree) -> Octree {
        let leaf_of = tree
            .leaves
            .iter()
            .enumerate()
            .map(|(i, l)| (l.cell.key(), i))
            .collect();
        Octree { tree, leaf_of }
    }

    /// An empty vertex table for this tree.
    pub fn vertices(&self) -> Vertices {
        let mut grid = self.tree.grid;
        grid.depth += 1;
        Vertices {
            ids: HashMap::new(),
            coords: Vec::new(),
            grid,
        }
    }

    /// The leaf that is `c` or contains it.
    fn leaf_containing(&self, mut c: Cell) -> Option<usize> {
        loop {
            if let Some(&i) = self.leaf_of.get(&c.key()) {
                return Some(i);
            }
            c = parent(c)?;
        }
    }

    /// The leaves whose closed box contains the point `p` (doubled coordinates).
    pub fn leaves_at(&self, p: [u32; 3]) -> Vec<usize> {
        let d = self.tree.grid.depth + 1;
        let top = 1u32 << d;
        let mut out = Vec::new();
        for m in 0..8u32 {
            let mut q = [0u32; 3];
            let mut ok = true;
            for a in 0..3 {
                if m >> a & 1 == 1 {
                    ok &= p[a] < top;
                    q[a] = p[a];
                } else {
                    ok &= p[a] > 0;
                    q[a] = p[a].wrapping_sub(1);
                }
            }
            if !ok {
                continue;
            }
            // The finest cell of that octant, at level depth (halve the doubled units).
            let c = Cell {
                level: self.tree.grid.depth as u8,
                idx: q.map(|x| x >> 1),
            };
            if let Some(i) = self.leaf_containing(c) {
                if !out.contains(&i) {
                    out.push(i);
                }
            }
        }
        out
    }

    /// The leaf corners strictly inside the dyadic edge from `p` along axis `u` of
    /// length `s` (finest units), in order.
    fn edge_points(&self, p: [u32; 3], u: usize, s: u32, out: &mut Vec<[u32; 3]>) {
        if s < 2 {
            return;
        }
        let mut m = p;
        m[u] += s / 2;
        if !self.tree.points.contains(&pkey(m)) {
            return;
        }
        self.edge_points(p, u, s / 2, out);
        out.push(m);
        self.edge_points(m, u, s / 2, out);
    }

    /// The pieces of face (`axis`, `side`) of the cell `q` (inside leaf `li`).
    fn pieces(&self, q: Cell, axis: usize, side: u32, out: &mut Vec<(Cell, Option<usize>)>) {
        let n = 1i64 << q.level;
        let v = q.idx[axis] as i64 + if side == 1 { 1 } else { -1 };
        if v < 0 || v >= n {
            out.push((q, None));
            return;
        }
        let mut c = q;
        c.idx[axis] = v as u32;
        if self.tree.internal.contains(&c.key()) {
            for ch in q.children(3) {
                if ch.idx[axis] & 1 == side {
                    self.pieces(ch, axis, side, out);
                }
            }
        } else {
            out.push((q, self.leaf_containing(c)));
        }
    }

    /// The tetrahedra of leaf `li` (positively oriented) and the pieces of its boundary.
    pub fn leaf_tets(&self, li: usize, vs: &mut Vertices) -> LeafTets {
        let depth = self.tree.grid.depth;
        let cell = self.tree.leaves[li].cell;
        let mut out = LeafTets::default();
        // Per piece: its triangles in doubled coordinates.
        let mut tris: Vec<[[u32; 3]; 3]> = Vec::new();
        let mut simple = true;
        for axis in 0..3 {
            for side in 0..2u32 {
                let mut ps = Vec::new();
                self.pieces(cell, axis, side, &mut ps);
                simple &= ps.len() == 1;
                for (q, across) in ps {
                    let (lo, s) = q.span(depth);
                    let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
                    let mut base = lo;
                    base[axis] += side * s;
                    // The corners in cyclic order, and the split points of each edge.
                    let corner = |i: u32, j: u32| {
                        let mut c = base;
                        c[u] += i * s;
                        c[w] += j * s;
                        c
                    };
                    let cyc = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                    let mut ring: Vec<[u32; 3]> = Vec::new();
                    let mut split = false;
                    for e in 0..4 {
                        let (a, b) = (cyc[e], cyc[(e + 1) % 4]);
                        ring.push(a);
                        let ax = if a[u] != b[u] { u } else { w };
                        let mut mids = Vec::new();
                        self.edge_points(if a[ax] < b[ax] { a } else { b }, ax, s, &mut mids);
                        if a[ax] > b[ax] {
                            mids.reverse();
                        }
                        split |= !mids.is_empty();
                        ring.extend(mids);
                    }
                    simple &= !split;
                    let d = |p: [u32; 3]| p.map(|x| 2 * x);
                    let first = tris.len();
                    if split {
                        let mut c = d(base);
                        c[u] += s;
                        c[w] += s;
                        for k in 0..ring.len() {
                            tris.push([c, d(ring[k]), d(ring[(k + 1) % ring.len()])]);
                        }
                    } else {
                        // The diagonal from the lowest to the highest corner.
                        tris.push([d(cyc[0]), d(cyc[1]), d(cyc[2])]);
                        tris.push([d(cyc[0]), d(cyc[2]), d(cyc[3])]);
                    }
                    let mut verts: Vec<u32> = tris[first..]
                        .iter()
                        .flat_map(|t| t.iter().map(|&p| vs.id(p)).collect::<Vec<_>>())
                        .collect();
                    verts.sort_unstable();
                    verts.dedup();
                    out.pieces.push(Piece {
                        verts,
                        across,
                        axis: axis as u8,
                        side: side as u8,
                    });
                }
            }
        }
        let (lo, s) = cell.span(depth);
        let lo2 = lo.map(|x| 2 * x);
        let s2 = 2 * s;
        let mut push = |t: [[u32; 3]; 4], vs: &mut Vertices| {
            let mut t = t.map(|p| vs.id(p));
            if orient(&vs.coords, t) < 0 {
                t.swap(2, 3);
            }
            out.tets.push(t);
        };
        if simple {
            for k in crate::marching::tets::kuhn_tets() {
                let t = k.map(|c| [0, 1, 2].map(|a| lo2[a] + if c >> a & 1 == 1 { s2 } else { 0 }));
                push(t, vs);
            }
        } else {
            let c = lo2.map(|x| x + s);
            for t in tris {
                push([c, t[0], t[1], t[2]], vs);
            }
        }
        out
    }
}

/// Six times the signed volume of the tetrahedron (integer coordinates, exact).
pub fn orient(coords: &[[u32; 3]], t: [u32; 4]) -> i128 {
    let p = t.map(|v| coords[v as usize].map(i128::from));
    let e = [1, 2, 3].map(|q| [0, 1, 2].map(|a| p[q][a] - p[0][a]));
    e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1])
        - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0])
        + e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])
}

/// Check that `tets` (vertex coordinates `coords`, integers in `[0, top]³`) are a
/// conforming triangulation of the cube `[0, top]³`: every tetrahedron positively
/// oriented; every triangle in exactly two tetrahedra, on opposite sides of it, or in
/// one when it lies on the boundary of the cube; the volumes sum to `top³` exactly.
pub fn check_conforming(coords: &[[u32; 3]], tets: &[[u32; 4]], top: u32) -> Result<(), String> {
    let mut faces: HashMap<[u32; 3], Vec<i128>> = HashMap::new();
    let mut vol: i128 = 0;
    for (i, &t) in tets.iter().enumerate() {
        let o = orient(coords, t);
        if o <= 0 {
            return Err(format!(
                "tetrahedron {i} {t:?} is not positively oriented ({o})"
            ));
        }
        vol += o;
        for q in 0..4 {
            let mut f: Vec<u32> = (0..4).filter(|&r| r != q).map(|r| t[r]).collect();
            f.sort_unstable();
            let key = [f[0], f[1], f[2]];
            // The side of the opposite vertex, for the sorted triangle.
            let side = orient(coords, [key[0], key[1], key[2], t[q]]).signum();
            faces.entry(key).or_default().push(side);
        }
    }
    let want = 6 * i128::from(top).pow(3);
    if vol != want {
        return Err(format!("the volumes sum to {vol}/6, not {want}/6"));
    }
    for (f, sides) in &faces {
        let on_boundary = (0..3).any(|a| {
            let c = f.map(|v| coords[v as usize][a]);
            c.iter().all(|&x| x == 0) || c.iter().all(|&x| x == top)
        });
        let ok = match sides.as_slice() {
            [_] => on_boundary,
            [a, b] => !on_boundary && a * b < 0,
            _ => false,
        };
        if !ok {
            return Err(format!(
                "triangle {f:?} ({}) lies in {} tetrahedra with sides {sides:?}",
                if on_boundary {
                    "on the boundary"
                } else {
                    "interior"
                },
                sides.len()
            ));
        }
    }
    Ok(())
}
