//! Assembling the mesh from the leaves: tiles on box faces, crossings paired by a
//! rule that depends only on the tile, cycles closed on each box boundary and fanned.
use super::*;
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;
use crate::mesh::{Curve2, TriMesh};
use crate::mesher::Uncertified;
use rayon::prelude::*;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

/// How the crossings on a tile are paired.
/// A face tile as a [`Pairing`] sees it: its corners, the axis normal to it and its
/// crossings.
#[derive(Clone, Copy)]
pub struct FaceTile<'a> {
    pub corners: &'a [[f64; 3]; 4],
    pub normal_axis: usize,
    pub cross: &'a [TileCrossing],
}

pub trait Pairing: Sync {
    /// `cross` lists the tile's crossings in counter-clockwise order (seen from outside,
    /// i.e. against the tile normal), each with its position, the side of the tile it
    /// lies on (0..4, sides in the same order) and the sign⁺ just after it. `corners` are
    /// the tile's corners in the same order. Returns pairs of indices into `cross`.
    fn pair(&self, f: &dyn Implicit, tile: FaceTile) -> Vec<(usize, usize)>;
}

#[derive(Clone, Copy, Debug)]
pub struct TileCrossing {
    pub pos: [f64; 3],
    pub side: usize,
    pub after_pos: bool,
}

/// The non-crossing pairing of crossings in cyclic order that cuts off the arcs of one
/// sign (`cut_negative`: each negative arc c_i → c_{i+1} becomes a chord, so the positive
/// region of the tile is joined).
pub fn cut_arcs(cross: &[TileCrossing], cut_negative: bool) -> Vec<(usize, usize)> {
    let n = cross.len();
    let mut out = Vec::with_capacity(n / 2);
    for i in 0..n {
        if cross[i].after_pos != cut_negative {
            out.push((i, (i + 1) % n));
        }
    }
    out
}

/// A crossing vertex: an elementary segment and the root's rank on it.
pub type CrossKey = (Seg, u32);

/// What a leaf produced: directed segments (2D) or boundary cycles (3D), by crossing key.
struct LeafOut {
    segs: Vec<(CrossKey, CrossKey)>,
}

/// The assembled result.
pub struct Assembled {
    pub curve: Option<Curve2>,
    pub surface: Option<TriMesh>,
    pub uncertain: Vec<Uncertified>,
    pub root_steps: u64,
    pub crossings: usize,
    pub segments: usize,
}

/// The grid points on the segment from `a` to `b` (inclusive, in order): recursively,
/// a midpoint is present iff it is a leaf corner.
fn seg_points(points: &HashSet<u64>, a: [u32; 3], b: [u32; 3], out: &mut Vec<[u32; 3]>) {
    // `out` already holds `a`.
    let k = (0..3).find(|&k| a[k] != b[k]);
    if let Some(k) = k {
        let (lo, hi) = (a[k].min(b[k]), a[k].max(b[k]));
        if hi - lo >= 2 {
            let mut m = a;
            m[k] = (lo + hi) / 2;
            if points.contains(&pkey(m)) {
                seg_points(points, a, m, out);
                seg_points(points, m, b, out);
                return;
            }
        }
    }
    out.push(b);
}

/// A tile: a square in a plane normal to `axis`, corners counter-clockwise seen from
/// outside the leaf, and its boundary points.
struct GridTile {
    corners: [[u32; 3]; 4],
    axis: usize,
}

fn leaf_tiles(tree: &Tree, c: Cell) -> Vec<GridTile> {
    let g = &tree.grid;
    let (lo, hi) = g.cell_lo_hi(c);
    if g.dim == 2 {
        return vec![GridTile {
            corners: [
                [lo[0], lo[1], 0],
                [hi[0], lo[1], 0],
                [hi[0], hi[1], 0],
                [lo[0], hi[1], 0],
            ],
            axis: 2,
        }];
    }
    let mut out = Vec::new();
    for k in 0..3 {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        for side in 0..2 {
            let w = if side == 0 { lo[k] } else { hi[k] };
            let mk = |a: u32, b: u32| {
                let mut p = [0u32; 3];
                p[k] = w;
                p[u] = a;
                p[v] = b;
                p
            };
            // CCW about +e_k is (u,v) order; the outward normal of the low face is -e_k.
            let sq = if side == 1 {
                [
                    mk(lo[u], lo[v]),
                    mk(hi[u], lo[v]),
                    mk(hi[u], hi[v]),
                    mk(lo[u], hi[v]),
                ]
            } else {
                [
                    mk(lo[u], lo[v]),
                    mk(lo[u], hi[v]),
                    mk(hi[u], hi[v]),
                    mk(hi[u], lo[v]),
                ]
            };
            split_tile(&tree.points, sq, k, &mut out);
        }
    }
    out
}

/// Split a face square where a finer neighbour has a corner at its centre.
fn split_tile(points: &HashSet<u64>, sq: [[u32; 3]; 4], axis: usize, out: &mut Vec<GridTile>) {
    let mid = |a: [u32; 3], b: [u32; 3]| [0, 1, 2].map(|k| (a[k] + b[k]) / 2);
    let c = mid(sq[0], sq[2]);
    let big = (0..3).any(|k| sq[0][k].abs_diff(sq[2][k]) >= 2);
    if big && points.contains(&pkey(c)) {
        let m01 = mid(sq[0], sq[1]);
        let m12 = mid(sq[1], sq[2]);
        let m23 = mid(sq[2], sq[3]);
        let m30 = mid(sq[3], sq[0]);
        // The four quarters keep the parent's orientation.
        split_tile(points, [sq[0], m01, c, m30], axis, out);
        split_tile(points, [m01, sq[1], m12, c], axis, out);
        split_tile(points, [c, m12, sq[2], m23], axis, out);
        split_tile(points, [m30, c, m23, sq[3]], axis, out);
    } else {
        out.push(GridTile { corners: sq, axis });
    }
}

/// Build the mesh from a finished tree. Every non-empty leaf is meshed (failed leaves
/// too, best effort: the run is then uncertified anyway).
pub fn assemble(
    f: &dyn Implicit,
    tree: &Tree,
    finder: &dyn RootFinder,
    pairing: &dyn Pairing,
) -> Assembled {
    let g = tree.grid;
    let active: Vec<Cell> = tree
        .leaves
        .iter()
        .filter(|l| l.verdict != Verdict::Empty)
        .map(|l| l.cell)
        .collect();
    // 1. Tiles and their boundary point lists.
    type TileData = (GridTile, Vec<[u32; 3]>, [usize; 4]);
    let tiles: Vec<Vec<TileData>> = active
        .par_iter()
        .map(|&c| {
            leaf_tiles(tree, c)
                .into_iter()
                .map(|t| {
                    let mut pts = vec![t.corners[0]];
                    let mut starts = [0usize; 4];
                    for s in 0..4 {
                        starts[s] = pts.len() - 1;
                        seg_points(&tree.points, t.corners[s], t.corners[(s + 1) % 4], &mut pts);
                    }
                    pts.pop(); // the closing corner repeats the first
                    (t, pts, starts)
                })
                .collect()
        })
        .collect();
    // 2. Unique points and segments.
    let mut pset: HashSet<u64> = HashSet::default();
    let mut sset: HashSet<Seg> = HashSet::default();
    for lt in &tiles {
        for (_, pts, _) in lt {
            for i in 0..pts.len() {
                let a = pkey(pts[i]);
                let b = pkey(pts[(i + 1) % pts.len()]);
                pset.insert(a);
                sset.insert(Seg {
                    a: a.min(b),
                    b: a.max(b),
                });
            }
        }
    }
    let plist: Vec<u64> = pset.into_iter().collect();
    let signs: HashMap<u64, PointSign> = plist
        .par_iter()
        .map(|&k| (k, point_sign(f, g.point(unpack(k)))))
        .collect();
    let mut uncertain: Vec<Uncertified> = Vec::new();
    for (k, s) in &signs {
        if !s.rigorous {
            let p = g.point(unpack(*k));
            uncertain.push(Uncertified::new(
                Aabb { min: p, max: p },
                "sign of f at a grid point not decided by interval arithmetic",
            ));
        }
    }
    // 3. Crossings per segment.
    let steps = AtomicU64::new(0);
    let slist: Vec<Seg> = sset.into_iter().collect();
    let roots: HashMap<Seg, SegRoots> = slist
        .par_iter()
        .map(|&s| {
            let (pa, pb) = (g.point(unpack(s.a)), g.point(unpack(s.b)));
            let e = SignedSegment {
                a: pa,
                sa: signs[&s.a],
                b: pb,
                sb: signs[&s.b],
            };
            (s, finder.roots(f, e, &steps))
        })
        .collect();
    for (s, r) in &roots {
        if !r.isolated {
            let (pa, pb) = (g.point(unpack(s.a)), g.point(unpack(s.b)));
            uncertain.push(Uncertified::new(
                Aabb::of_points(&[pa, pb]).unwrap_or(g.domain),
                "grazing intersection: roots on a box edge not isolated",
            ));
        }
    }
    let bad_tiles = AtomicU64::new(0);
    // 4. Pair the crossings on each tile and collect directed segments per leaf.
    let outs: Vec<LeafOut> = tiles
        .par_iter()
        .map(|lt| {
            let mut segs = Vec::new();
            for (t, pts, starts) in lt {
                let n = pts.len();
                let mut cross: Vec<TileCrossing> = Vec::new();
                let mut keys: Vec<CrossKey> = Vec::new();
                let mut side = 0usize;
                for i in 0..n {
                    while side < 3 && i >= starts[side + 1] {
                        side += 1;
                    }
                    let (ka, kb) = (pkey(pts[i]), pkey(pts[(i + 1) % n]));
                    let s = Seg {
                        a: ka.min(kb),
                        b: ka.max(kb),
                    };
                    let r = &roots[&s];
                    let m = r.pos.len();
                    let mut after = signs[&ka].pos;
                    for j in 0..m {
                        let (rank, pos) = if ka < kb {
                            (j, r.pos[j])
                        } else {
                            (m - 1 - j, r.pos[m - 1 - j])
                        };
                        after = !after;
                        cross.push(TileCrossing {
                            pos,
                            side,
                            after_pos: after,
                        });
                        keys.push((s, rank as u32));
                    }
                }
                if cross.is_empty() {
                    continue;
                }
                let corners = t.corners.map(|p| g.point(p));
                let pairs = pairing.pair(
                    f,
                    FaceTile {
                        corners: &corners,
                        normal_axis: t.axis,
                        cross: &cross,
                    },
                );
                // A chord must join a crossing where f turns negative to one where it
                // turns positive; otherwise the rule's premise failed on this tile.
                let consistent = pairs.len() * 2 == cross.len()
                    && pairs
                        .iter()
                        .all(|&(i, j)| cross[i].after_pos != cross[j].after_pos);
                let pairs = if consistent {
                    pairs
                } else {
                    bad_tiles.fetch_add(1, Relaxed);
                    cut_arcs(&cross, true)
                };
                for (i, j) in pairs {
                    // Direct the chord so that f > 0 lies on its left seen from outside:
                    // the region left of i→j contains the arc just after j.
                    if cross[j].after_pos {
                        segs.push((keys[i], keys[j]));
                    } else {
                        segs.push((keys[j], keys[i]));
                    }
                }
            }
            LeafOut { segs }
        })
        .collect();
    // 5. Vertex numbering.
    let mut index: HashMap<CrossKey, u32> = HashMap::default();
    let mut verts: Vec<[f64; 3]> = Vec::new();
    let mut ncross = 0;
    let mut sorted_roots: Vec<(&Seg, &SegRoots)> = roots.iter().collect();
    sorted_roots.sort_unstable_by_key(|(s, _)| **s);
    for (s, r) in sorted_roots {
        for (j, p) in r.pos.iter().enumerate() {
            index.insert((*s, j as u32), verts.len() as u32);
            verts.push(*p);
            ncross += 1;
        }
    }
    let root_steps = steps.load(Relaxed);
    let nbad = bad_tiles.load(Relaxed);
    if nbad > 0 {
        uncertain.push(Uncertified::new(
            g.domain,
            format!("{nbad} face tile(s) whose crossing pattern contradicts the connection rule"),
        ));
    }
    let nseg: usize = outs.iter().map(|o| o.segs.len()).sum();
    if g.dim == 2 {
        // Each leaf segment is a curve segment; store with f < 0 on the left
        // (counter-clockwise around the solid {f <= 0}).
        let mut segments = Vec::new();
        for o in &outs {
            for (a, b) in &o.segs {
                segments.push([index[b], index[a]]);
            }
        }
        let curve = Curve2 {
            vertices: verts.iter().map(|p| [p[0], p[1]]).collect(),
            segments,
        };
        return Assembled {
            curve: Some(curve),
            surface: None,
            uncertain,
            root_steps,
            crossings: ncross,
            segments: nseg,
        };
    }
    // 3D: close the directed segments of each leaf into cycles and fan them.
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let mut bad = 0usize;
    for (o, &c) in outs.iter().zip(&active) {
        let mut next: HashMap<u32, u32> = HashMap::default();
        let mut ok = true;
        for (a, b) in &o.segs {
            if next.insert(index[a], index[b]).is_some() {
                ok = false;
            }
        }
        let mut seen: HashSet<u32> = HashSet::default();
        let mut starts: Vec<u32> = next.keys().copied().collect();
        starts.sort_unstable();
        for s in starts {
            if seen.contains(&s) {
                continue;
            }
            let mut cyc = vec![s];
            seen.insert(s);
            let mut v = s;
            loop {
                match next.get(&v) {
                    Some(&w) if w == s => break,
                    Some(&w) if !seen.contains(&w) => {
                        seen.insert(w);
                        cyc.push(w);
                        v = w;
                    }
                    _ => {
                        ok = false;
                        break;
                    }
                }
            }
            match cyc.len() {
                0 | 1 => ok = false,
                // A two-gon (a → b on one tile, b → a on another: a cap cutting one edge
                // twice, Snyder): the disk collapses to the edge ab, which the two
                // neighbouring boxes already use in opposite directions.
                2 => {}
                3 => tris.push([cyc[0], cyc[1], cyc[2]]),
                n => {
                    let mut cen = [0.0; 3];
                    for &i in &cyc {
                        for k in 0..3 {
                            cen[k] += verts[i as usize][k] / n as f64;
                        }
                    }
                    let ci = verts.len() as u32;
                    verts.push(cen);
                    for i in 0..n {
                        tris.push([ci, cyc[i], cyc[(i + 1) % n]]);
                    }
                }
            }
        }
        if !ok {
            bad += 1;
            uncertain.push(Uncertified::new(
                g.cell_aabb(c),
                "boundary crossing pattern of the box does not close into simple cycles",
            ));
        }
    }
    let _ = bad;
    Assembled {
        curve: None,
        surface: Some(TriMesh::new(verts, tris)),
        uncertain,
        root_steps,
        crossings: ncross,
        segments: nseg,
    }
}
