//! A bounding volume hierarchy in flat arrays, and exact closest-point queries on
//! triangle meshes and planar polylines built on it.
//!
//! [`Bvh`] knows only boxes: it is built from one [`Aabb`] per primitive (binned SAH,
//! 16 bins, leaves of at most 4 primitives) and traversed with caller-supplied
//! primitive tests, so other queries (rays, winding numbers, signed distance) can
//! reuse it. [`TriBvh`] and [`SegBvh`] add the exact point-triangle (Ericson,
//! *Real-Time Collision Detection*, §5.1.5) and point-segment routines.
//! (Over 800 lines on purpose: one flat node layout and the traversals that depend on
//! it — closest point, winding number, segments — kept together so a change to the layout
//! is made in one file.)
use crate::error::{Error, Result};
use crate::kernel::geom::{self, Aabb};
use crate::mesh::{Curve2, TriMesh};

/// A node: `count > 0` is a leaf over `order[start..start + count]`; `count == 0` is an
/// interior node whose two children are `nodes[start]` and `nodes[start + 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub start: u32,
    pub count: u32,
}

impl Node {
    /// Squared distance from `p` to the node's box (0 inside).
    #[inline]
    pub fn dist2(&self, p: [f64; 3]) -> f64 {
        let mut d2 = 0.0;
        for k in 0..3 {
            let d = (self.min[k] - p[k]).max(p[k] - self.max[k]).max(0.0);
            d2 += d * d;
        }
        d2
    }
    /// Squared distance from `p` to the box centre.
    #[inline]
    pub fn center_dist2(&self, p: [f64; 3]) -> f64 {
        let mut d2 = 0.0;
        for k in 0..3 {
            let d = 0.5 * (self.min[k] + self.max[k]) - p[k];
            d2 += d * d;
        }
        d2
    }
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// The hierarchy: `nodes[0]` is the root (absent for no primitives), `order` lists the
/// primitive indices in leaf order.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    pub nodes: Vec<Node>,
    pub order: Vec<u32>,
}

const LEAF_SIZE: usize = 4;
const BINS: usize = 16;
/// Below this depth splits are SAH; deeper ones halve the index range, so the depth
/// stays under `SAH_DEPTH + log2(n)` and the traversal stack fits in [`STACK`].
const SAH_DEPTH: usize = 40;
const STACK: usize = 96;

fn half_area(min: [f64; 3], max: [f64; 3]) -> f64 {
    let d = geom::sub(max, min);
    // The small perimeter term keeps flat or linear boxes (curves) distinguishable.
    d[0] * d[1] + d[1] * d[2] + d[2] * d[0] + 1e-9 * (d[0] + d[1] + d[2])
}

fn grow(min: &mut [f64; 3], max: &mut [f64; 3], b: &Aabb) {
    for k in 0..3 {
        min[k] = min[k].min(b.min[k]);
        max[k] = max[k].max(b.max[k]);
    }
}

/// Ranges at least this long are split and built in parallel (rayon); their bounds
/// and bins are accumulated in parallel too. Shorter ones are built serially. The tree
/// is the same either way (the split of a range depends on its primitives only, and
/// min, max and counts are exact reductions), and so is its layout (below).
const PAR_RANGE: usize = 1 << 14;

/// Primitives per parallel task when accumulating the bounds and bins of a range.
const PAR_CHUNK: usize = 1 << 12;

/// A primitive during the build: its box and index. The build permutes these records
/// themselves (not indices into the boxes), so every pass over a range reads memory in
/// order.
#[derive(Clone, Copy)]
struct Prim {
    b: Aabb,
    id: u32,
}

impl Prim {
    /// Coordinate `k` of the box centre ([`Aabb::center`]).
    #[inline]
    fn c(&self, k: usize) -> f64 {
        0.5 * (self.b.min[k] + self.b.max[k])
    }
}

/// Bounds of a range: the union of the primitives' boxes and the box of their centroids.
#[derive(Clone, Copy)]
struct Bounds {
    min: [f64; 3],
    max: [f64; 3],
    cmin: [f64; 3],
    cmax: [f64; 3],
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
        cmin: [f64::INFINITY; 3],
        cmax: [f64::NEG_INFINITY; 3],
    };
    fn of(items: &[Prim]) -> Bounds {
        let mut acc = Bounds::EMPTY;
        for p in items {
            grow(&mut acc.min, &mut acc.max, &p.b);
            for k in 0..3 {
                acc.cmin[k] = acc.cmin[k].min(p.c(k));
                acc.cmax[k] = acc.cmax[k].max(p.c(k));
            }
        }
        acc
    }
    fn join(mut self, o: Bounds) -> Bounds {
        grow(
            &mut self.min,
            &mut self.max,
            &Aabb {
                min: o.min,
                max: o.max,
            },
        );
        grow(
            &mut self.cmin,
            &mut self.cmax,
            &Aabb {
                min: o.cmin,
                max: o.cmax,
            },
        );
        self
    }
}

/// The SAH bins of a range: count and box per bin.
#[derive(Clone, Copy)]
struct Bins {
    count: [usize; BINS],
    min: [[f64; 3]; BINS],
    max: [[f64; 3]; BINS],
}

impl Bins {
    const EMPTY: Bins = Bins {
        count: [0; BINS],
        min: [[f64::INFINITY; 3]; BINS],
        max: [[f64::NEG_INFINITY; 3]; BINS],
    };
    fn of(items: &[Prim], bin: &impl Fn(&Prim) -> usize) -> Bins {
        let mut acc = Bins::EMPTY;
        for p in items {
            let b = bin(p);
            acc.count[b] += 1;
            grow(&mut acc.min[b], &mut acc.max[b], &p.b);
        }
        acc
    }
    fn join(mut self, o: Bins) -> Bins {
        for b in 0..BINS {
            self.count[b] += o.count[b];
            grow(
                &mut self.min[b],
                &mut self.max[b],
                &Aabb {
                    min: o.min[b],
                    max: o.max[b],
                },
            );
        }
        self
    }
}

/// `of(items)`, over chunks in parallel for a long range (exact reductions: the same
/// result).
fn accumulate<A: Send>(
    items: &[Prim],
    of: impl Fn(&[Prim]) -> A + Sync,
    join: impl Fn(A, A) -> A + Sync,
) -> A {
    if items.len() >= PAR_RANGE {
        use rayon::prelude::*;
        items
            .par_chunks(PAR_CHUNK)
            .map(&of)
            .reduce_with(&join)
            .expect("a long range")
    } else {
        of(items)
    }
}

/// The box of the range `items` and where to split it (`None`: a leaf), reordering
/// `items` so the first part comes first.
fn split(items: &mut [Prim], depth: usize) -> ([f64; 3], [f64; 3], Option<usize>) {
    let Bounds {
        min,
        max,
        cmin,
        cmax,
    } = accumulate(items, Bounds::of, Bounds::join);
    let count = items.len();
    if count <= LEAF_SIZE {
        return (min, max, None);
    }
    let ext = geom::sub(cmax, cmin);
    let axis = if ext[0] >= ext[1] && ext[0] >= ext[2] {
        0
    } else if ext[1] >= ext[2] {
        1
    } else {
        2
    };
    if ext[axis] <= 0.0 || depth >= SAH_DEPTH {
        // All centroids coincide (or the tree is deep): halve the range.
        let m = count / 2;
        if ext[axis] > 0.0 {
            items.select_nth_unstable_by(m, |a, b| a.c(axis).total_cmp(&b.c(axis)));
        }
        return (min, max, Some(m));
    }
    let scale = BINS as f64 / ext[axis];
    let bin = |p: &Prim| (((p.c(axis) - cmin[axis]) * scale) as usize).min(BINS - 1);
    let Bins {
        count: bcount,
        min: bmin,
        max: bmax,
    } = accumulate(items, |c| Bins::of(c, &bin), Bins::join);
    // Sweep from the right for suffix areas, then from the left.
    let mut right_cost = [0.0; BINS];
    let (mut rmin, mut rmax, mut rc) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3], 0);
    for b in (1..BINS).rev() {
        rc += bcount[b];
        for k in 0..3 {
            rmin[k] = rmin[k].min(bmin[b][k]);
            rmax[k] = rmax[k].max(bmax[b][k]);
        }
        right_cost[b] = if rc > 0 {
            rc as f64 * half_area(rmin, rmax)
        } else {
            0.0
        };
    }
    let (mut lmin, mut lmax, mut lc) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3], 0);
    let mut best = (f64::INFINITY, 0usize);
    for b in 0..BINS - 1 {
        lc += bcount[b];
        for k in 0..3 {
            lmin[k] = lmin[k].min(bmin[b][k]);
            lmax[k] = lmax[k].max(bmax[b][k]);
        }
        if lc == 0 || lc == count {
            continue;
        }
        let cost = lc as f64 * half_area(lmin, lmax) + right_cost[b + 1];
        if cost < best.0 {
            best = (cost, b);
        }
    }
    let leaf_cost = count as f64 * half_area(min, max);
    // A traversal step costs about one primitive test.
    if count <= 2 * LEAF_SIZE && best.0 + half_area(min, max) >= leaf_cost {
        return (min, max, None);
    }
    // Partition the range so bins <= best.1 come first.
    let mut i = 0;
    let mut j = count;
    while i < j {
        if bin(&items[i]) <= best.1 {
            i += 1;
        } else {
            j -= 1;
            items.swap(i, j);
        }
    }
    (min, max, Some(i))
}

/// The subtree over `items` (slots `base..base + items.len()` of the whole order),
/// root first, children of a node adjacent, child indices local to the returned
/// vector; in the layout of a depth-first build: [root, left root, right root, the
/// rest of the left subtree, the rest of the right subtree].
fn subtree(items: &mut [Prim], base: usize, depth: usize) -> Vec<Node> {
    if items.len() < PAR_RANGE {
        return subtree_serial(items, base, depth);
    }
    let (min, max, split) = split(items, depth);
    let Some(mid) = split else {
        return vec![Node {
            min,
            max,
            start: base as u32,
            count: items.len() as u32,
        }];
    };
    let (lo, hi) = items.split_at_mut(mid);
    let (l, r) = rayon::join(
        || subtree(lo, base, depth + 1),
        || subtree(hi, base + mid, depth + 1),
    );
    // Local index i of the left subtree moves to 1 (its root) or i + 2, of the right
    // one to 2 (its root) or i + l.len() + 1: child pointers shift by 2 and l.len() + 1.
    let moved = |n: &Node, shift: usize| {
        let mut n = *n;
        if !n.is_leaf() {
            n.start += shift as u32;
        }
        n
    };
    let (lshift, rshift) = (2, l.len() + 1);
    let mut nodes = Vec::with_capacity(1 + l.len() + r.len());
    nodes.push(Node {
        min,
        max,
        start: 1,
        count: 0,
    });
    nodes.push(moved(&l[0], lshift));
    nodes.push(moved(&r[0], rshift));
    nodes.extend(l[1..].iter().map(|n| moved(n, lshift)));
    nodes.extend(r[1..].iter().map(|n| moved(n, rshift)));
    nodes
}

/// [`subtree`] serially, with an explicit stack (no recursion on deep trees).
fn subtree_serial(items: &mut [Prim], base: usize, depth0: usize) -> Vec<Node> {
    let blank = Node {
        min: [0.0; 3],
        max: [0.0; 3],
        start: 0,
        count: 0,
    };
    let mut nodes = Vec::with_capacity(2 * items.len() / LEAF_SIZE + 1);
    nodes.push(blank);
    // (node, start, end, depth)
    let mut work = vec![(0usize, 0usize, items.len(), depth0)];
    while let Some((ni, s, e, depth)) = work.pop() {
        let (min, max, split) = split(&mut items[s..e], depth);
        nodes[ni].min = min;
        nodes[ni].max = max;
        let Some(m) = split else {
            nodes[ni].start = (base + s) as u32;
            nodes[ni].count = (e - s) as u32;
            continue;
        };
        let c = nodes.len();
        nodes.push(blank);
        nodes.push(blank);
        nodes[ni].start = c as u32;
        nodes[ni].count = 0;
        work.push((c + 1, s + m, e, depth + 1));
        work.push((c, s, s + m, depth + 1));
    }
    nodes
}

impl Bvh {
    /// Build over one box per primitive. Errors on a non-finite box.
    pub fn build(boxes: &[Aabb]) -> Result<Self> {
        if boxes.len() >= u32::MAX as usize {
            return Err(Error::TooLarge(format!("{} primitives", boxes.len())));
        }
        if let Some(i) = boxes
            .iter()
            .position(|b| !(b.min.iter().chain(&b.max).all(|x| x.is_finite())))
        {
            return Err(Error::NotFinite(format!("bounding box of primitive {i}")));
        }
        if boxes.is_empty() {
            return Ok(Bvh::default());
        }
        use rayon::prelude::*;
        let mut items: Vec<Prim> = boxes
            .par_iter()
            .enumerate()
            .map(|(i, &b)| Prim { b, id: i as u32 })
            .collect();
        let nodes = subtree(&mut items, 0, 0);
        let order = items.par_iter().map(|p| p.id).collect();
        Ok(Bvh { nodes, order })
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Depth of the tree (1 for a single leaf, 0 when empty).
    pub fn depth(&self) -> usize {
        if self.nodes.is_empty() {
            return 0;
        }
        let mut best = 0;
        let mut st = vec![(0usize, 1usize)];
        while let Some((i, d)) = st.pop() {
            best = best.max(d);
            let n = &self.nodes[i];
            if !n.is_leaf() {
                st.push((n.start as usize, d + 1));
                st.push((n.start as usize + 1, d + 1));
            }
        }
        best
    }

    /// Nearest-primitive search. `test(slot, prim, best_d2)` is called for candidate
    /// primitives (`slot` indexes `order`, `prim = order[slot]`) and returns their squared
    /// distance and payload; only results below `max_d2` and the current best are kept.
    /// Children are visited nearer first, and subtrees whose box is farther than the
    /// best so far are skipped, so the result is exact when `test` is.
    #[inline]
    pub fn nearest<R>(
        &self,
        p: [f64; 3],
        max_d2: f64,
        mut test: impl FnMut(usize, u32, f64) -> Option<(f64, R)>,
    ) -> Option<(f64, R)> {
        let mut best: Option<(f64, R)> = None;
        let mut best_d2 = max_d2;
        if self.nodes.is_empty() {
            return None;
        }
        let mut stack = [(0u32, 0.0f64); STACK];
        let mut sp = 1;
        stack[0] = (0, self.nodes[0].dist2(p));
        while sp > 0 {
            sp -= 1;
            let (ni, d2) = stack[sp];
            if d2 >= best_d2 {
                continue;
            }
            let n = &self.nodes[ni as usize];
            if n.is_leaf() {
                for slot in n.start as usize..(n.start + n.count) as usize {
                    if let Some((d, r)) = test(slot, self.order[slot], best_d2) {
                        if d < best_d2 {
                            best_d2 = d;
                            best = Some((d, r));
                        }
                    }
                }
            } else {
                let a = n.start;
                let b = a + 1;
                let da = self.nodes[a as usize].dist2(p);
                let db = self.nodes[b as usize].dist2(p);
                // Inside both boxes (both 0) the box distance says nothing: descend
                // towards the nearer box centre for a good first bound.
                let a_first = if da == db {
                    self.nodes[a as usize].center_dist2(p) <= self.nodes[b as usize].center_dist2(p)
                } else {
                    da < db
                };
                let (near, dn, far, df) = if a_first {
                    (a, da, b, db)
                } else {
                    (b, db, a, da)
                };
                if df < best_d2 {
                    stack[sp] = (far, df);
                    sp += 1;
                }
                if dn < best_d2 {
                    stack[sp] = (near, dn);
                    sp += 1;
                }
            }
        }
        best
    }

    /// Visit every primitive in leaves whose box passes `keep(min, max)`: the building
    /// block for ray, segment and range queries.
    pub fn visit(
        &self,
        mut keep: impl FnMut(&[f64; 3], &[f64; 3]) -> bool,
        mut prim: impl FnMut(usize, u32),
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![0u32];
        while let Some(ni) = stack.pop() {
            let n = &self.nodes[ni as usize];
            if !keep(&n.min, &n.max) {
                continue;
            }
            if n.is_leaf() {
                for slot in n.start as usize..(n.start + n.count) as usize {
                    prim(slot, self.order[slot]);
                }
            } else {
                stack.push(n.start);
                stack.push(n.start + 1);
            }
        }
    }
}

/// Which part of a triangle the closest point lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Feature {
    /// Corner 0, 1 or 2.
    Vertex(u8),
    /// Edge k joins corners k and (k + 1) % 3.
    Edge(u8),
    Face,
}

/// The closest point on a triangle, as Ericson's routine finds it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriPoint {
    pub point: [f64; 3],
    /// Barycentric coordinates of `point` with respect to the corners.
    pub bary: [f64; 3],
}

impl TriPoint {
    /// The feature, read off the exact zeros Ericson's routine produces.
    pub fn feature(&self) -> Feature {
        let z = self.bary.map(|b| b == 0.0);
        match z {
            [false, true, true] => Feature::Vertex(0),
            [true, false, true] => Feature::Vertex(1),
            [true, true, false] => Feature::Vertex(2),
            [false, false, true] => Feature::Edge(0),
            [true, false, false] => Feature::Edge(1),
            [false, true, false] => Feature::Edge(2),
            _ => Feature::Face,
        }
    }
}

/// Closest point on segment `ab` to `p` and its parameter t in [0, 1].
#[inline]
pub fn closest_on_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> ([f64; 3], f64) {
    let ab = geom::sub(b, a);
    let l2 = geom::dot(ab, ab);
    if l2 <= 0.0 {
        return (a, 0.0);
    }
    let t = (geom::dot(geom::sub(p, a), ab) / l2).clamp(0.0, 1.0);
    (geom::add(a, geom::scale(ab, t)), t)
}

/// Closest point on triangle `abc` to `p` (Ericson 2005, §5.1.5: Voronoi regions of the
/// vertices, then the edges, then the face). Degenerate (collinear) triangles, where the
/// face-region division is 0/0, fall back to the nearest of the three edges.
#[inline]
pub fn closest_on_triangle(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> TriPoint {
    use geom::{add, dot, scale, sub};
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return TriPoint {
            point: a,
            bary: [1.0, 0.0, 0.0],
        };
    }
    let bp = sub(p, b);
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return TriPoint {
            point: b,
            bary: [0.0, 1.0, 0.0],
        };
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0 {
        let v = d1 / (d1 - d3);
        return TriPoint {
            point: add(a, scale(ab, v)),
            bary: [1.0 - v, v, 0.0],
        };
    }
    let cp = sub(p, c);
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return TriPoint {
            point: c,
            bary: [0.0, 0.0, 1.0],
        };
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0 {
        let w = d2 / (d2 - d6);
        return TriPoint {
            point: add(a, scale(ac, w)),
            bary: [1.0 - w, 0.0, w],
        };
    }
    let va = d3 * d6 - d5 * d4;
    let e1 = d4 - d3;
    let e2 = d5 - d6;
    if va <= 0.0 && e1 >= 0.0 && e2 >= 0.0 && e1 + e2 > 0.0 {
        let w = e1 / (e1 + e2);
        return TriPoint {
            point: add(b, scale(sub(c, b), w)),
            bary: [0.0, 1.0 - w, w],
        };
    }
    let den = va + vb + vc;
    if den > 0.0 && den.is_finite() {
        let v = vb / den;
        let w = vc / den;
        return TriPoint {
            point: add(a, add(scale(ab, v), scale(ac, w))),
            bary: [1.0 - v - w, v, w],
        };
    }
    // Degenerate triangle: nearest point of its three edges.
    let cands = [(a, b, 0usize), (b, c, 1), (c, a, 2)];
    let mut best = (f64::INFINITY, a, [1.0, 0.0, 0.0]);
    for (u, v, k) in cands {
        let (q, t) = closest_on_segment(p, u, v);
        let d = dot(sub(p, q), sub(p, q));
        if d < best.0 {
            let mut bary = [0.0; 3];
            bary[k] = 1.0 - t;
            bary[(k + 1) % 3] = t;
            best = (d, q, bary);
        }
    }
    TriPoint {
        point: best.1,
        bary: best.2,
    }
}

/// Result of a closest-point query on a triangle mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    pub dist2: f64,
    pub point: [f64; 3],
    /// Index into the mesh's `triangles` (or `segments` for [`SegBvh`]).
    pub index: u32,
    /// Barycentric coordinates on the triangle (for segments: `[1 - t, t, 0]`).
    pub bary: [f64; 3],
}

impl Closest {
    pub fn feature(&self) -> Feature {
        TriPoint {
            point: self.point,
            bary: self.bary,
        }
        .feature()
    }
}

fn check_indices(n: usize, what: &str, idx: impl Iterator<Item = (usize, u32)>) -> Result<()> {
    for (i, v) in idx {
        if v as usize >= n {
            return Err(Error::Param(format!(
                "{what} {i} refers to vertex {v}, but the mesh has {n} vertices"
            )));
        }
    }
    Ok(())
}

/// A BVH over the triangles of a mesh, with the corners stored in leaf order for cache
/// locality, and per node the dipole data of the fast winding number.
#[derive(Clone, Debug, Default)]
pub struct TriBvh {
    pub bvh: Bvh,
    tris: Vec<[[f64; 3]; 3]>,
    /// Built on the first winding-number query (closest-point queries never need it).
    dipoles: std::sync::OnceLock<Vec<Dipole>>,
}

/// Far-field data of a BVH node for the fast winding number (Barill, Dickson, Schmidt,
/// Levin & Jacobson, "Fast winding numbers for soups and clouds", SIGGRAPH 2018, §3.2):
/// the area-weighted normal sum of the node's triangles (order-1 dipole term), its
/// area-weighted centroid, a radius bounding every corner from that centroid, and the
/// second-order moment.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dipole {
    pub normal: [f64; 3],
    pub center: [f64; 3],
    pub radius: f64,
    /// Second-order moment M_ij = ∫ n_i (x − center)_j dA (row-major), for the
    /// order-2 term of the expansion (Barill et al. §3.2).
    pub moment: [f64; 9],
}

/// Accuracy parameter β of the fast winding number: a node whose centroid is farther
/// than β × its radius from the query point is replaced by its dipole (Barill et al.
/// use β = 2 for their reported accuracy).
pub const WINDING_BETA: f64 = 2.0;

/// The signed solid angle of triangle `abc` seen from `p` (Van Oosterom & Strackee
/// 1983): positive when the triangle is counter-clockwise seen from `p`'s far side,
/// i.e. when `p` is on the side its normal points away from.
#[inline]
pub fn solid_angle(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    use geom::{cross, dot, norm, sub};
    let (a, b, c) = (sub(a, p), sub(b, p), sub(c, p));
    let (la, lb, lc) = (norm(a), norm(b), norm(c));
    let det = dot(a, cross(b, c));
    let den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
    2.0 * det.atan2(den)
}

impl TriBvh {
    /// Errors on out-of-range indices or non-finite coordinates.
    pub fn new(mesh: &TriMesh) -> Result<Self> {
        let nv = mesh.vertices.len();
        check_indices(
            nv,
            "triangle",
            mesh.triangles
                .iter()
                .enumerate()
                .flat_map(|(i, t)| t.iter().map(move |&v| (i, v))),
        )?;
        use rayon::prelude::*;
        let boxes: Vec<Aabb> = (0..mesh.triangles.len())
            .into_par_iter()
            .map(|t| {
                let c = mesh.corners(t);
                Aabb::of_points(&c).expect("three corners")
            })
            .collect();
        let bvh = Bvh::build(&boxes)?;
        let tris: Vec<[[f64; 3]; 3]> = bvh
            .order
            .par_iter()
            .map(|&t| mesh.corners(t as usize))
            .collect();
        Ok(TriBvh {
            bvh,
            tris,
            dipoles: std::sync::OnceLock::new(),
        })
    }

    /// The corners of the triangles in leaf order (`bvh.order[slot]` is the mesh index).
    pub fn triangles(&self) -> &[[[f64; 3]; 3]] {
        &self.tris
    }

    /// The generalised winding number of the triangles around `p` (Jacobson, Kavan &
    /// Sorkine-Hornung, "Robust inside-outside segmentation using generalized winding
    /// numbers", 2013): the sum of their signed solid angles over 4π. 1 inside and 0
    /// outside a closed, outward-oriented surface; for a scan with holes it degrades
    /// smoothly, so `w > 1/2` is a robust inside test. Hierarchical evaluation (Barill et
    /// al. 2018): nodes farther than [`WINDING_BETA`] × radius contribute their dipole
    /// term, nearer triangles their exact solid angle. Not an enclosure: floating point.
    pub fn winding_number(&self, p: [f64; 3]) -> f64 {
        use geom::{dot, sub};
        let nodes = &self.bvh.nodes;
        if nodes.is_empty() {
            return 0.0;
        }
        let dipoles = self.dipoles.get_or_init(|| dipoles(&self.bvh, &self.tris));
        let mut sum = 0.0;
        let mut stack = [0u32; STACK];
        let mut sp = 1;
        let b2 = WINDING_BETA * WINDING_BETA;
        while sp > 0 {
            sp -= 1;
            let ni = stack[sp] as usize;
            let d = &dipoles[ni];
            let v = sub(d.center, p);
            let r2 = dot(v, v);
            if r2 > b2 * d.radius * d.radius {
                // Far field, Taylor expansion of F(y) = y/|y|³ about y = v = c − p
                // (Barill et al., eq. 6): order 1 is v·N/|v|³; order 2 is
                // Σ_ij J_ij M_ij with J = I/|v|³ − 3 v vᵀ/|v|⁵ the Jacobian of F.
                let r = r2.sqrt();
                let r3 = r2 * r;
                let m = &d.moment;
                let tr = m[0] + m[4] + m[8];
                let mut vmv = 0.0;
                for i in 0..3 {
                    for j in 0..3 {
                        vmv += v[i] * m[3 * i + j] * v[j];
                    }
                }
                sum += dot(v, d.normal) / r3 + tr / r3 - 3.0 * vmv / (r3 * r2);
                continue;
            }
            let n = &nodes[ni];
            if n.is_leaf() {
                for slot in n.start as usize..(n.start + n.count) as usize {
                    let [a, b, c] = self.tris[slot];
                    sum += solid_angle(p, a, b, c);
                }
            } else {
                stack[sp] = n.start;
                stack[sp + 1] = n.start + 1;
                sp += 2;
            }
        }
        sum / (4.0 * std::f64::consts::PI)
    }

    /// The exact generalised winding number (every triangle's solid angle; O(n)), the
    /// reference the hierarchical [`TriBvh::winding_number`] is tested against.
    pub fn winding_number_exact(&self, p: [f64; 3]) -> f64 {
        self.tris
            .iter()
            .map(|&[a, b, c]| solid_angle(p, a, b, c))
            .sum::<f64>()
            / (4.0 * std::f64::consts::PI)
    }
}

/// Bottom-up dipole data. Children are stored after their parent, so a reverse sweep
/// over the nodes sees both children before the parent.
fn dipoles(bvh: &Bvh, tris: &[[[f64; 3]; 3]]) -> Vec<Dipole> {
    use geom::{add, cross, dist, scale, sub};
    let mut out = vec![Dipole::default(); bvh.nodes.len()];
    let mut area = vec![0.0f64; bvh.nodes.len()];
    // Triangle centroids and area vectors of a leaf (for the moment about its centroid).
    let tri_data = |t: &[[f64; 3]; 3]| {
        let an = scale(cross(sub(t[1], t[0]), sub(t[2], t[0])), 0.5);
        (an, scale(add(add(t[0], t[1]), t[2]), 1.0 / 3.0))
    };
    for ni in (0..bvh.nodes.len()).rev() {
        let n = bvh.nodes[ni];
        let box_centre = scale(add(n.min, n.max), 0.5);
        let (mut nsum, mut csum, mut asum) = ([0.0; 3], [0.0; 3], 0.0);
        if n.is_leaf() {
            for t in &tris[n.start as usize..(n.start + n.count) as usize] {
                let an = scale(cross(sub(t[1], t[0]), sub(t[2], t[0])), 0.5);
                let a = geom::norm(an);
                nsum = add(nsum, an);
                csum = add(csum, scale(add(add(t[0], t[1]), t[2]), a / 3.0));
                asum += a;
            }
        } else {
            for ci in [n.start as usize, n.start as usize + 1] {
                nsum = add(nsum, out[ci].normal);
                csum = add(csum, scale(out[ci].center, area[ci]));
                asum += area[ci];
            }
        }
        let center = if asum > 0.0 {
            scale(csum, 1.0 / asum)
        } else {
            box_centre
        };
        // The radius bounds every corner from the centroid: exactly at leaves, through
        // the children's balls above them.
        let radius = if n.is_leaf() {
            tris[n.start as usize..(n.start + n.count) as usize]
                .iter()
                .flat_map(|t| t.iter())
                .map(|&x| dist(x, center))
                .fold(0.0, f64::max)
        } else {
            [n.start as usize, n.start as usize + 1]
                .iter()
                .map(|&ci| out[ci].radius + dist(out[ci].center, center))
                .fold(0.0, f64::max)
        };
        // M = Σ N_k (c_k − c)ᵀ over the parts k (triangles at a leaf, whose own moment
        // about their centroid vanishes; children above, plus their moments).
        let mut moment = [0.0; 9];
        let mut add_part = |nk: [f64; 3], ck: [f64; 3], mk: Option<&[f64; 9]>| {
            let dc = sub(ck, center);
            for i in 0..3 {
                for j in 0..3 {
                    moment[3 * i + j] += nk[i] * dc[j] + mk.map_or(0.0, |m| m[3 * i + j]);
                }
            }
        };
        if n.is_leaf() {
            for t in &tris[n.start as usize..(n.start + n.count) as usize] {
                let (an, ct) = tri_data(t);
                add_part(an, ct, None);
            }
        } else {
            for ci in [n.start as usize, n.start as usize + 1] {
                let ch = out[ci];
                add_part(ch.normal, ch.center, Some(&ch.moment));
            }
        }
        out[ni] = Dipole {
            normal: nsum,
            center,
            radius,
            moment,
        };
        area[ni] = asum;
    }
    out
}

impl TriBvh {
    /// The closest point of the mesh to `p` (`None` for a mesh without triangles).
    #[inline]
    pub fn closest(&self, p: [f64; 3]) -> Option<Closest> {
        self.closest_within(p, f64::INFINITY)
    }

    /// As [`TriBvh::closest`], but only points with squared distance below `max_d2`.
    #[inline]
    pub fn closest_within(&self, p: [f64; 3], max_d2: f64) -> Option<Closest> {
        self.bvh
            .nearest(p, max_d2, |slot, prim, best| {
                let [a, b, c] = self.tris[slot];
                // The triangle's own box is a cheap lower bound: skip Ericson's routine
                // for triangles that cannot beat the best so far.
                let mut lb = 0.0;
                for k in 0..3 {
                    let lo = a[k].min(b[k]).min(c[k]);
                    let hi = a[k].max(b[k]).max(c[k]);
                    let d = (lo - p[k]).max(p[k] - hi).max(0.0);
                    lb += d * d;
                }
                if lb >= best {
                    return None;
                }
                let q = closest_on_triangle(p, a, b, c);
                let d = geom::sub(p, q.point);
                Some((geom::dot(d, d), (q, prim)))
            })
            .map(|(dist2, (q, index))| Closest {
                dist2,
                point: q.point,
                index,
                bary: q.bary,
            })
    }
}

/// A BVH over the segments of a planar curve (z = 0).
#[derive(Clone, Debug, Default)]
pub struct SegBvh {
    pub bvh: Bvh,
    segs: Vec<[[f64; 3]; 2]>,
}

impl SegBvh {
    pub fn new(curve: &Curve2) -> Result<Self> {
        let nv = curve.vertices.len();
        check_indices(
            nv,
            "segment",
            curve
                .segments
                .iter()
                .enumerate()
                .flat_map(|(i, s)| s.iter().map(move |&v| (i, v))),
        )?;
        let lift = |v: u32| {
            let [x, y] = curve.vertices[v as usize];
            [x, y, 0.0]
        };
        let boxes: Vec<Aabb> = curve
            .segments
            .iter()
            .map(|s| Aabb::of_points(&s.map(lift)).expect("two points"))
            .collect();
        let bvh = Bvh::build(&boxes)?;
        let segs = bvh
            .order
            .iter()
            .map(|&s| curve.segments[s as usize].map(lift))
            .collect();
        Ok(SegBvh { bvh, segs })
    }

    /// The closest point of the curve to `p` (z ignored).
    pub fn closest(&self, p: [f64; 2]) -> Option<Closest> {
        let p3 = [p[0], p[1], 0.0];
        self.bvh
            .nearest(p3, f64::INFINITY, |slot, prim, _| {
                let [a, b] = self.segs[slot];
                let (q, t) = closest_on_segment(p3, a, b);
                let d = geom::sub(p3, q);
                Some((geom::dot(d, d), (q, t, prim)))
            })
            .map(|(dist2, (q, t, index))| Closest {
                dist2,
                point: q,
                index,
                bary: [1.0 - t, t, 0.0],
            })
    }
}
