//! MidNormal (Algorithm 1): the normal surface of the Goldberg tiling with its vertices
//! at edge midpoints, extracted only where interval arithmetic says the surface can be.
//!
//! The tiling is visited as an octree over blocks of lattice indices (i, j, m): a block
//! whose vertices' bounding box has an interval enclosure of f not containing a sign
//! change (f ≥ 0 everywhere, or f < 0 everywhere; f = 0 counts as positive, Algorithm 1
//! line 4) holds no crossing tetrahedron and is dropped, so the cost follows the surface.
//! Surviving leaf blocks evaluate f at their lattice vertices and emit, per
//! tetrahedron, the elementary normal triangle or the quadrilateral split by the
//! paper's diagonal. Mesh vertices are keyed by their lattice edge, so neighbouring
//! tetrahedra share them and the output is a closed oriented manifold away from the
//! domain boundary.
use super::tiling::{
    colour, edge_dir, edge_endpoints, edge_key, unpack_vertex, Goldberg, TetType, A, KEY_OFFSET,
    MIDPOINT_EDGES, NORMAL_QUADS, NORMAL_TRIANGLES,
};
use super::DiagonalRule;
use crate::error::{Error, Result};
use crate::implicit::ops::refuse_pole_edges;
use crate::implicit::Implicit;
use crate::kernel::geom::{add, cross, dot, scale, sub, Aabb};
use crate::mesher::Progress;
use rayon::prelude::*;

/// An oriented quadrilateral cycle (midpoint indices) and its diagonal position.
type QuadEntry = Option<([u8; 4], u8)>;

/// Per tetrahedron type and sign pattern: the oriented triangles (midpoint indices)
/// and the oriented quadrilateral cycle, if the pattern gives one.
#[derive(Clone, Debug)]
struct Table {
    /// [type][pattern] -> up to two triangles.
    tris: [[([[u8; 3]; 2], u8); 16]; 6],
    /// [type][pattern] -> oriented quadrilateral cycle and the paper's diagonal position
    /// (0: diagonal cycle[0]-cycle[2], 1: cycle[1]-cycle[3]).
    quads: [[QuadEntry; 16]; 6],
    /// [type][midpoint] -> (origin offset, direction) of the lattice edge.
    edges: [[([i64; 3], usize); 6]; 6],
}

fn centroid(pts: &[[f64; 3]]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for p in pts {
        c = add(c, *p);
    }
    scale(c, 1.0 / pts.len() as f64)
}

impl Table {
    fn new(g: &Goldberg, rule: DiagonalRule) -> Table {
        let types = TetType::all();
        let mut t = Table {
            tris: [[([[0; 3]; 2], 0); 16]; 6],
            quads: [[None; 16]; 6],
            edges: [[([0; 3], 0); 6]; 6],
        };
        for (ti, ty) in types.iter().enumerate() {
            let pos = ty.verts.map(|[i, j, m]| g.vertex(i, j, m));
            let mid = MIDPOINT_EDGES.map(|[p, q]| scale(add(pos[p], pos[q]), 0.5));
            for (k, [p, q]) in MIDPOINT_EDGES.iter().enumerate() {
                let (flip, dir) = edge_dir(ty.verts[*p], ty.verts[*q]).expect("lattice edge");
                let origin = if flip { ty.verts[*q] } else { ty.verts[*p] };
                t.edges[ti][k] = (origin, dir);
            }
            for pattern in 1..15usize {
                let positive: Vec<usize> = (0..4).filter(|k| pattern >> k & 1 == 1).collect();
                let negative: Vec<usize> = (0..4).filter(|k| pattern >> k & 1 == 0).collect();
                // Direction from the negative side to the positive side: normals point
                // towards f > 0 (the TriMesh convention).
                let towards_pos = sub(
                    centroid(&positive.iter().map(|&k| pos[k]).collect::<Vec<_>>()),
                    centroid(&negative.iter().map(|&k| pos[k]).collect::<Vec<_>>()),
                );
                let orient3 = |tri: [usize; 3]| -> [u8; 3] {
                    let n = cross(sub(mid[tri[1]], mid[tri[0]]), sub(mid[tri[2]], mid[tri[0]]));
                    if dot(n, towards_pos) >= 0.0 {
                        tri.map(|x| x as u8)
                    } else {
                        [tri[0] as u8, tri[2] as u8, tri[1] as u8]
                    }
                };
                if positive.len() == 1 || negative.len() == 1 {
                    let lone = if positive.len() == 1 {
                        positive[0]
                    } else {
                        negative[0]
                    };
                    let (_, tri) = NORMAL_TRIANGLES.iter().find(|(v, _)| *v == lone).unwrap();
                    t.tris[ti][pattern] = ([orient3(*tri), [0; 3]], 1);
                } else {
                    // Two-two split: the quadrilateral whose side holds A and A's partner.
                    let partner = if pattern & 1 == 1 {
                        positive.iter().copied().find(|&k| k != A).unwrap()
                    } else {
                        negative.iter().copied().find(|&k| k != A).unwrap()
                    };
                    let quad = NORMAL_QUADS
                        .iter()
                        .find(|q| q.side == [A, partner])
                        .unwrap();
                    let mut cyc = quad.cycle;
                    let n = cross(sub(mid[cyc[2]], mid[cyc[0]]), sub(mid[cyc[3]], mid[cyc[1]]));
                    if dot(n, towards_pos) < 0.0 {
                        cyc.swap(1, 3);
                    }
                    let diag = match rule {
                        DiagonalRule::Alternate => quad.alternate_diagonal(),
                        _ => quad.diagonal,
                    };
                    let at = if cyc[0] == diag[0] || cyc[0] == diag[1] {
                        0
                    } else {
                        1
                    };
                    let c = cyc.map(|x| x as u8);
                    t.quads[ti][pattern] = Some((c, at));
                    t.tris[ti][pattern] = (split_quad(c, at), 2);
                }
            }
        }
        t
    }
}

/// The two triangles of an oriented quadrilateral cycle split along the diagonal
/// through `cycle[at]` and `cycle[at + 2]`.
#[inline]
pub fn split_quad<T: Copy>(c: [T; 4], at: u8) -> [[T; 3]; 2] {
    if at == 0 {
        [[c[0], c[1], c[2]], [c[0], c[2], c[3]]]
    } else {
        [[c[1], c[2], c[3]], [c[1], c[3], c[0]]]
    }
}

/// A block of anchor indices [lo, hi) in (i, j, m).
#[derive(Clone, Copy, Debug)]
struct Block {
    lo: [i64; 3],
    hi: [i64; 3],
}

impl Block {
    /// Bounding box of every vertex of every tetrahedron anchored in the block.
    fn bbox(&self, g: &Goldberg) -> Aabb {
        let h = 0.866_025_403_784_438_6 * g.e;
        Aabb {
            min: [
                g.e * (self.lo[0] as f64 + 0.5 * self.lo[1] as f64),
                h * self.lo[1] as f64,
                g.a * self.lo[2] as f64,
            ],
            max: [
                g.e * (self.hi[0] as f64 + 0.5 * self.hi[1] as f64),
                h * self.hi[1] as f64,
                g.a * (self.hi[2] + 2) as f64,
            ],
        }
    }
    fn tets(&self) -> u64 {
        2 * (0..3)
            .map(|k| (self.hi[k] - self.lo[k]).max(0) as u64)
            .product::<u64>()
    }
}

fn boxes_meet(a: &Aabb, b: &Aabb) -> bool {
    (0..3).all(|k| a.min[k] <= b.max[k] && b.min[k] <= a.max[k])
}

/// What the extraction did, for the report.
#[derive(Clone, Debug, Default)]
pub struct ExtractStats {
    /// Tetrahedra of the tiling in the root block (what an unpruned run would visit).
    pub tets_total: u64,
    /// Tetrahedra in leaf blocks (visited).
    pub tets_visited: u64,
    /// Tetrahedra with a sign change.
    pub crossing_tets: u64,
    pub leaves: u64,
    pub interval_evals: u64,
    pub point_evals: u64,
}

/// The MidNormal normal surface: vertices at lattice-edge midpoints (with their edge
/// keys), triangles (quadrilaterals already split, unless `keep_quads`), and the
/// quadrilaterals kept for a later split.
#[derive(Clone, Debug, Default)]
pub struct NormalSurface {
    pub goldberg: Option<Goldberg>,
    /// Lattice edge key of each vertex (sorted, unique).
    pub keys: Vec<u64>,
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// Oriented quadrilateral cycles, when the split is deferred (rule `shorter`).
    pub quads: Vec<[u32; 4]>,
    pub stats: ExtractStats,
}

#[derive(Default)]
struct LeafOut {
    tris: Vec<[u64; 3]>,
    quads: Vec<[u64; 4]>,
    visited: u64,
    crossing: u64,
    evals: u64,
}

/// Default bound on the triangles a normal-surface extraction may produce (about
/// 100 bytes each while the surface is assembled: 5 GB).
pub const DEFAULT_MAX_TRIANGLES: u64 = 50_000_000;

/// Run Algorithm 1 over the tiling τ(g.a, g.e) on `domain`. With `keep_quads` the
/// quadrilaterals are returned unsplit (the caller splits them, e.g. by the shorter
/// diagonal after projection); otherwise they are split by `rule` (paper or alternate).
///
/// The output is bounded: the pruned blocks near the surface are
/// counted before any of them is processed, and a run that would produce more than
/// about `max_triangles` triangles is refused (measured on the sphere: one triangle
/// per ~8 tetrahedra visited; the estimate uses 1 per 10 so it errs on allowing).
#[allow(clippy::too_many_arguments)]
pub fn extract(
    f: &dyn Implicit,
    domain: &Aabb,
    g: &Goldberg,
    rule: DiagonalRule,
    keep_quads: bool,
    leaf: usize,
    prune: bool,
    max_triangles: u64,
    progress: &dyn Progress,
) -> Result<NormalSurface> {
    if !(g.e.is_finite() && g.e > 0.0 && g.a.is_finite() && g.a > 0.0) {
        return Err(Error::Param(format!(
            "Goldberg tetrahedron needs e > 0 and a > 0 (got e = {}, a = {})",
            g.e, g.a
        )));
    }
    let leaf = leaf.max(1) as i64;
    let h = 0.866_025_403_784_438_6 * g.e;
    let j0 = (domain.min[1] / h).floor() as i64 - 1;
    let j1 = (domain.max[1] / h).ceil() as i64 + 1;
    let i0 = (domain.min[0] / g.e - 0.5 * j1 as f64).floor() as i64 - 1;
    let i1 = (domain.max[0] / g.e - 0.5 * j0 as f64).ceil() as i64 + 1;
    let m0 = (domain.min[2] / g.a).floor() as i64 - 3;
    let m1 = (domain.max[2] / g.a).ceil() as i64 + 1;
    let lim = KEY_OFFSET - 8;
    for (name, v) in [
        ("i", i0),
        ("i", i1),
        ("j", j0),
        ("j", j1),
        ("m", m0),
        ("m", m1),
    ] {
        if v.abs() >= lim {
            return Err(Error::TooLarge(format!(
                "lattice index {name} = {v} exceeds ±{lim}: the scale e = {} is too small for \
                 the domain (or the domain is far from the origin)",
                g.e
            )));
        }
    }
    let root = Block {
        lo: [i0, j0, m0],
        hi: [i1, j1, m1],
    };
    let dom = domain.inflate(g.e);
    let interval_evals = std::sync::atomic::AtomicU64::new(0);
    // Phase 1: prune the octree over blocks.
    let limits = [leaf, leaf, 3 * leaf];
    #[allow(clippy::too_many_arguments)]
    fn descend(
        b: Block,
        f: &dyn Implicit,
        g: &Goldberg,
        dom: &Aabb,
        limits: [i64; 3],
        prune: bool,
        count: &std::sync::atomic::AtomicU64,
        budget: &std::sync::atomic::AtomicI64,
    ) -> Vec<Block> {
        if budget.load(std::sync::atomic::Ordering::Relaxed) < 0 {
            return Vec::new();
        }
        let bb = b.bbox(g);
        if !boxes_meet(&bb, dom) {
            return Vec::new();
        }
        if prune {
            count.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let iv = f.eval_interval(&bb.intervals());
            // f = 0 counts as positive (Algorithm 1, line 4): no sign change if f ≥ 0 or
            // f < 0 on the whole box.
            if !iv.is_empty() && (iv.inf() >= 0.0 || iv.sup() < 0.0) {
                return Vec::new();
            }
        }
        // Split the dimension that is largest relative to its leaf limit.
        let ext = [0, 1, 2].map(|k| b.hi[k] - b.lo[k]);
        let (k, r) = (0..3)
            .map(|k| (k, ext[k] as f64 / limits[k] as f64))
            .fold((0, 0.0), |acc, x| if x.1 > acc.1 { x } else { acc });
        if r <= 1.0 {
            budget.fetch_sub(b.tets() as i64, std::sync::atomic::Ordering::Relaxed);
            return vec![b];
        }
        let mid = b.lo[k] + ext[k] / 2;
        let (mut lo, mut hi) = (b, b);
        lo.hi[k] = mid;
        hi.lo[k] = mid;
        let (mut x, y) = rayon::join(
            || descend(lo, f, g, dom, limits, prune, count, budget),
            || descend(hi, f, g, dom, limits, prune, count, budget),
        );
        x.extend(y);
        x
    }
    let tets_allowed = max_triangles.saturating_mul(10).min(i64::MAX as u64) as i64;
    let budget = std::sync::atomic::AtomicI64::new(tets_allowed);
    let leaves = descend(root, f, g, &dom, limits, prune, &interval_evals, &budget);
    if budget.load(std::sync::atomic::Ordering::Relaxed) < 0 {
        return Err(Error::TooLarge(format!(
            "at e = {} the lattice has more than {tets_allowed} tetrahedra near the surface: \
             about {} triangles or more, above the limit {max_triangles} (about 100 bytes \
             each); use a larger --scale or raise the limit with --set max_triangles=N",
            g.e,
            tets_allowed / 10
        )));
    }
    let table = Table::new(g, rule);
    progress.start("midnormal: leaf blocks", leaves.len() as u64);
    let outs: Vec<Result<LeafOut>> = leaves
        .par_iter()
        .map(|b| {
            let r = process_leaf(f, g, &table, b, keep_quads);
            progress.inc(1);
            r
        })
        .collect();
    progress.finish();
    let mut stats = ExtractStats {
        tets_total: root.tets(),
        leaves: leaves.len() as u64,
        interval_evals: interval_evals.into_inner(),
        ..Default::default()
    };
    let mut outs_ok = Vec::with_capacity(outs.len());
    for o in outs {
        let o = o?;
        stats.tets_visited += o.visited;
        stats.crossing_tets += o.crossing;
        stats.point_evals += o.evals;
        outs_ok.push(o);
    }
    // One vertex per lattice edge, numbered in key order (`number_corners`).
    let n_tris: usize = outs_ok.iter().map(|o| o.tris.len()).sum();
    let n_quads: usize = outs_ok.iter().map(|o| o.quads.len()).sum();
    if 3 * n_tris + 4 * n_quads >= u32::MAX as usize {
        return Err(Error::TooLarge(format!(
            "{n_tris} triangles and {n_quads} quads: more corners than 32-bit indices can \
             number"
        )));
    }
    let (keys, triangles, quads) = number_corners(&outs_ok, n_tris, n_quads);
    let vertices: Vec<[f64; 3]> = keys
        .par_iter()
        .map(|&k| {
            let (p, q) = edge_endpoints(k);
            let a = g.vertex(p[0], p[1], p[2]);
            let b = g.vertex(q[0], q[1], q[2]);
            scale(add(a, b), 0.5)
        })
        .collect();
    // Every vertex is on a lattice edge whose ends differ in sign: a sign change across
    // a pole of f is no zero of f, and is refused with the edge named. The vertices are
    // the edges' midpoints, and no edge of `EDGE_DIRS` is longer than e + 3a (3a up,
    // or e across and at most 2a up): the midpoints' box grown by 2(e + a) holds every
    // edge.
    let near = Aabb::of_points_par(&vertices).map(|b| b.inflate(2.0 * (g.e + g.a)));
    let ends = |&k: &u64| {
        let (p, q) = edge_endpoints(k);
        (g.vertex(p[0], p[1], p[2]), g.vertex(q[0], q[1], q[2]))
    };
    let name = |&k: &u64| {
        let (p, q) = edge_endpoints(k);
        format!("lattice edge {p:?}–{q:?}")
    };
    refuse_pole_edges(f, near, &keys, ends, name)?;
    Ok(NormalSurface {
        goldberg: Some(*g),
        keys,
        vertices,
        triangles,
        quads,
        stats,
    })
}

/// The mesh vertices of an extraction: one per lattice edge that occurs, numbered in
/// key order, and every triangle's and quad's corners by number. Each corner's key is
/// mapped to a dense number over the box of the lattice coordinates that occur (i,
/// then j, then m, then the direction: the order of the keys), which fits in 32 bits
/// unless the box is huge, and radix-sorted with its corner's slot (the triangles'
/// corners, then the quads', in leaf order); one pass then numbers the distinct keys.
/// (A sort of the keys and a binary search per corner took a third of GradNormal's
/// genus 2 run; the radix sort skips the bytes every number shares.)
fn number_corners(
    outs: &[LeafOut],
    n_tris: usize,
    n_quads: usize,
) -> (Vec<u64>, Vec<[u32; 3]>, Vec<[u32; 4]>) {
    // A key is (vertex key << 3) | direction.
    let coords = |k: u64| unpack_vertex(k >> 3);
    if n_tris + n_quads == 0 {
        return (Vec::new(), Vec::new(), Vec::new());
    }
    let all = || {
        outs.par_iter()
            .flat_map_iter(|o| o.tris.iter().flatten().copied())
            .chain(
                outs.par_iter()
                    .flat_map_iter(|o| o.quads.iter().flatten().copied()),
            )
    };
    let none = || ([i64::MAX; 3], [i64::MIN; 3]);
    let (lo, hi) = all()
        .fold(none, |(mut lo, mut hi), k| {
            let c = coords(k);
            for a in 0..3 {
                lo[a] = lo[a].min(c[a]);
                hi[a] = hi[a].max(c[a]);
            }
            (lo, hi)
        })
        .reduce(none, |(l0, h0), (l1, h1)| {
            (
                [0, 1, 2].map(|a| l0[a].min(l1[a])),
                [0, 1, 2].map(|a| h0[a].max(h1[a])),
            )
        });
    // Each extent is at most 2^KEY_BITS, so a dense number has at most 3 KEY_BITS + 3
    // bits; it orders keys as they are ordered (i highest, then j, m, the direction).
    let n = [0, 1, 2].map(|a| (hi[a] - lo[a] + 1) as u64);
    let dense = |k: u64| {
        let c = coords(k);
        let c = [0, 1, 2].map(|a| (c[a] - lo[a]) as u64);
        (((c[0] * n[1] + c[1]) * n[2] + c[2]) << 3) | (k & 7)
    };
    let key = |d: u64| {
        let r = d >> 3;
        let (m, r) = ((r % n[2]) as i64 + lo[2], r / n[2]);
        let (j, i) = ((r % n[1]) as i64 + lo[1], (r / n[1]) as i64 + lo[0]);
        edge_key(i, j, m, (d & 7) as usize)
    };
    if n[0] * n[1] * n[2] <= 1 << 29 {
        numbered(
            all(),
            n_tris,
            n_quads,
            |k| dense(k) as u32,
            |d| key(d as u64),
        )
    } else {
        numbered(all(), n_tris, n_quads, dense, key)
    }
}

/// [`number_corners`] with dense numbers of type `K`: `to` maps a key to its number,
/// `from` back.
fn numbered<K: radsort::Key + PartialEq + Send>(
    corners: impl ParallelIterator<Item = u64>,
    n_tris: usize,
    n_quads: usize,
    to: impl Fn(u64) -> K + Sync + Send,
    from: impl Fn(K) -> u64,
) -> (Vec<u64>, Vec<[u32; 3]>, Vec<[u32; 4]>) {
    let mut order: Vec<(K, u32)> = corners.map(|k| (to(k), 0)).collect();
    order
        .par_iter_mut()
        .enumerate()
        .for_each(|(s, p)| p.1 = s as u32);
    radsort::sort_by_key(&mut order, |p| p.0);
    let mut tris = vec![[0u32; 3]; n_tris];
    let mut quads = vec![[0u32; 4]; n_quads];
    let mut keys: Vec<u64> = Vec::new();
    let mut last = None;
    for &(d, s) in &order {
        if last != Some(d) {
            keys.push(from(d));
            last = Some(d);
        }
        let (v, s) = ((keys.len() - 1) as u32, s as usize);
        if s < 3 * n_tris {
            tris[s / 3][s % 3] = v;
        } else {
            let q = s - 3 * n_tris;
            quads[q / 4][q % 4] = v;
        }
    }
    (keys, tris, quads)
}

fn process_leaf(
    f: &dyn Implicit,
    g: &Goldberg,
    table: &Table,
    b: &Block,
    keep_quads: bool,
) -> Result<LeafOut> {
    let [i0, j0, m0] = b.lo;
    let [i1, j1, m1] = b.hi;
    let ni = (i1 - i0 + 1) as usize;
    let nj = (j1 - j0 + 1) as usize;
    let nm = (m1 - m0 + 3) as usize;
    let mut vals = vec![f64::NAN; ni * nj * nm];
    let mut out = LeafOut::default();
    let idx = |i: i64, j: i64, m: i64| -> usize {
        ((i - i0) as usize * nj + (j - j0) as usize) * nm + (m - m0) as usize
    };
    // The leaf's lattice vertices, gathered in order and evaluated in one batch call
    // (SIMD lanes for formulas; the same values as point by point).
    let mut at = Vec::new();
    let mut ps: [Vec<f64>; 3] = Default::default();
    for i in i0..=i1 {
        for j in j0..=j1 {
            let c = colour(i, j);
            let mut m = m0 + (c - m0).rem_euclid(3);
            while m <= m1 + 2 {
                let p = g.vertex(i, j, m);
                for (a, x) in ps.iter_mut().zip(p) {
                    a.push(x);
                }
                at.push(idx(i, j, m));
                m += 3;
            }
        }
    }
    let mut vs = vec![0.0; at.len()];
    f.eval_batch([&ps[0], &ps[1], &ps[2]], &mut vs);
    for (n, (&k, &v)) in at.iter().zip(&vs).enumerate() {
        if v.is_nan() {
            return Err(Error::NotFinite(format!(
                "f is NaN at the lattice vertex ({}, {}, {})",
                ps[0][n], ps[1][n], ps[2][n]
            )));
        }
        vals[k] = v;
        out.evals += 1;
    }
    let types = TetType::all();
    for i in i0..i1 {
        for j in j0..j1 {
            let c = colour(i, j);
            for down in [false, true] {
                for m in m0..m1 {
                    let ti = TetType::index(down, (m - c).rem_euclid(3));
                    let ty = &types[ti];
                    let mut pattern = 0usize;
                    for (k, v) in ty.verts.iter().enumerate() {
                        // f = 0 counts as positive (Algorithm 1, line 4).
                        if vals[idx(i + v[0], j + v[1], m + v[2])] >= 0.0 {
                            pattern |= 1 << k;
                        }
                    }
                    out.visited += 1;
                    if pattern == 0 || pattern == 15 {
                        continue;
                    }
                    out.crossing += 1;
                    let key = |mp: u8| {
                        let (o, dir) = table.edges[ti][mp as usize];
                        edge_key(i + o[0], j + o[1], m + o[2], dir)
                    };
                    match (keep_quads, table.quads[ti][pattern]) {
                        (true, Some((cyc, _))) => out.quads.push(cyc.map(key)),
                        _ => {
                            let (tris, n) = table.tris[ti][pattern];
                            for t in &tris[..n as usize] {
                                out.tris.push(t.map(key));
                            }
                        }
                    }
                }
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// `number_corners` against a sort of the keys, their deduplication and a
        /// binary search per corner: the same keys, and every corner numbered by its
        /// key's position. Lattice coordinates in a small box (32-bit dense numbers)
        /// or spread over the whole key range (64-bit ones).
        #[test]
        fn corners_numbered_as_by_sorting_the_keys(
            leaves in prop::collection::vec(
                (
                    prop::collection::vec(prop::array::uniform3((0i64..4, 0i64..4, 0i64..4, 0usize..7)), 0..20),
                    prop::collection::vec(prop::array::uniform4((0i64..4, 0i64..4, 0i64..4, 0usize..7)), 0..6),
                ),
                1..5,
            ),
            huge in any::<bool>(),
        ) {
            let spread = if huge { (KEY_OFFSET - 1) / 3 } else { 1 };
            let key = |(i, j, m, d): (i64, i64, i64, usize)| {
                edge_key(i * spread - KEY_OFFSET / 2, (j - 2) * spread, m * spread - 3, d)
            };
            let outs: Vec<LeafOut> = leaves
                .iter()
                .map(|(t, q)| LeafOut {
                    tris: t.iter().map(|c| c.map(key)).collect(),
                    quads: q.iter().map(|c| c.map(key)).collect(),
                    ..Default::default()
                })
                .collect();
            let n_tris = outs.iter().map(|o| o.tris.len()).sum();
            let n_quads = outs.iter().map(|o| o.quads.len()).sum();
            let (keys, tris, quads) = number_corners(&outs, n_tris, n_quads);
            let mut want: Vec<u64> = outs
                .iter()
                .flat_map(|o| o.tris.iter().flatten().chain(o.quads.iter().flatten()))
                .copied()
                .collect();
            want.sort_unstable();
            want.dedup();
            prop_assert_eq!(&keys, &want);
            let at = |k: u64| want.binary_search(&k).unwrap() as u32;
            let want_tris: Vec<[u32; 3]> =
                outs.iter().flat_map(|o| o.tris.iter().map(|t| t.map(at))).collect();
            let want_quads: Vec<[u32; 4]> =
                outs.iter().flat_map(|o| o.quads.iter().map(|q| q.map(at))).collect();
            prop_assert_eq!(tris, want_tris);
            prop_assert_eq!(quads, want_quads);
        }
    }
}
