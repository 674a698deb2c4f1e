//! Exact point-to-triangle-mesh distances for the report's `--metrics fast` (issue 20):
//! a few thousand surface points against a mesh of hundreds of thousands of triangles,
//! where building an index is most of the cost. [`closest_dist2_all`] builds none
//! when the mesh lies close to the surface: sweeps over the triangles against a small
//! grid of the points. Otherwise, and for what the sweeps leave open, the
//! [`CentroidGrid`]: each triangle is listed once, in the cell of its centroid, with
//! its bounding sphere (centroid and radius) beside it: one parallel pass over the
//! triangles and one counting sort, instead of a listing in every cell a triangle's
//! box meets ([`TriGrid`]) or a tree.
//!
//! The distance is exact in the sense of [`TriGrid::closest_dist2`]: the minimum of the
//! same per-triangle routine ([`closest_on_triangle`], the same squared distance) over
//! every triangle that could be nearest, so the two give the same value, bit for bit
//! (tested against [`TriGrid`] in this module and on the catalog meshes). A triangle is
//! skipped only on a lower bound of its true distance (its cell's box, or its sphere,
//! less its radius) that exceeds the best distance found plus a margin far above the
//! rounding of both (see [`SLACK_REL`]).
//!
//! Triangles larger than a cell (radius above the cell size) are kept apart and tested
//! for every query, so that one long sliver cannot widen the search around every query;
//! when there are many, the cells are made coarser.
//!
//! [`TriGrid`]: crate::kernel::cellgrid::TriGrid
//! [`TriGrid::closest_dist2`]: crate::kernel::cellgrid::TriGrid::closest_dist2
use crate::kernel::bvh::closest_on_triangle;
use crate::kernel::cellgrid::{clamp_cell, flat_index, ring_search};
use crate::kernel::geom::{self, Aabb};
use crate::mesh::{Buckets, TriMesh};
use rayon::prelude::*;

/// Cells of the grid's cube per triangle (fewer than [`TriGrid`]'s: a triangle is
/// listed once, and the sphere test makes a fuller cell cheap to scan).
///
/// [`TriGrid`]: crate::kernel::cellgrid::TriGrid
const CELLS_PER_TRIANGLE: f64 = 2.0;
/// Cells per axis at most.
const MAX_CELLS: usize = 128;
/// The margin of every skip test, relative to the size of the coordinates: rounding
/// makes a computed centroid, radius or distance differ from the true one by a few
/// units in the last place (about 1e-16 of the coordinates), and a skip needs the
/// lower bound to exceed the best distance by more than 2 × `SLACK_REL` of them.
const SLACK_REL: f64 = 1e-9;

/// A triangle's bounding sphere and index, in cell order.
#[derive(Clone, Copy, Debug)]
struct Item {
    centre: [f64; 3],
    radius: f64,
    tri: u32,
}

/// The box of all vertices of a mesh that has a triangle (used or not).
fn vertex_box(mesh: &TriMesh) -> Aabb {
    Aabb::of_points_par(&mesh.vertices).expect("a triangle's corners are vertices")
}

/// Triangle `t`'s centroid and the largest squared distance to a corner.
#[inline(always)]
fn centre_r2(mesh: &TriMesh, t: usize) -> ([f64; 3], f64) {
    let [a, b, c] = mesh.corners(t);
    let centre = [0, 1, 2].map(|k| (a[k] + b[k] + c[k]) * (1.0 / 3.0));
    let r2 = [a, b, c]
        .iter()
        .map(|&p| {
            let d = geom::sub(p, centre);
            geom::dot(d, d)
        })
        .fold(0.0, f64::max);
    (centre, r2)
}

/// Triangle `t`'s bounding sphere: its centroid and the largest distance to a corner
/// (up to rounding, which the skip tests' margin covers).
#[inline(always)]
fn sphere(mesh: &TriMesh, t: usize) -> Item {
    let (centre, r2) = centre_r2(mesh, t);
    Item {
        centre,
        radius: r2.sqrt(),
        tri: t as u32,
    }
}

/// The grid (see the module documentation).
#[derive(Clone, Debug)]
pub struct CentroidGrid<'a> {
    mesh: &'a TriMesh,
    min: [f64; 3],
    /// Cell size (cubic cells) and its inverse.
    size: f64,
    inv: f64,
    n: [usize; 3],
    /// Cell `k` holds `items[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    items: Vec<Item>,
    /// Triangles of radius above the cell size, tested for every query.
    big: Vec<Item>,
    /// The largest radius of a triangle in the cells (at most `size`).
    rmax: f64,
    /// The margin of the skip tests (absolute).
    slack: f64,
}

impl<'a> CentroidGrid<'a> {
    /// The grid over every triangle of `mesh` (whose indices and coordinates the
    /// caller has checked: [`super::check_trimesh`]).
    pub fn new(mesh: &'a TriMesh) -> Self {
        let nf = mesh.triangles.len();
        let mut g = CentroidGrid {
            mesh,
            min: [0.0; 3],
            size: 1.0,
            inv: 1.0,
            n: [1; 3],
            start: vec![0, 0],
            items: Vec::new(),
            big: Vec::new(),
            rmax: 0.0,
            slack: 0.0,
        };
        if nf == 0 {
            return g;
        }
        // The box of all vertices (used or not: it only places the cells; centroids
        // lie in it).
        let vbox = vertex_box(mesh);
        let Aabb { min: lo, max: hi } = vbox;
        let ext = [0, 1, 2].map(|k| hi[k] - lo[k]);
        let longest = ext.iter().copied().fold(0.0, f64::max);
        let scale = vbox.max_abs();
        let per_axis =
            ((nf as f64 * CELLS_PER_TRIANGLE).cbrt().ceil() as usize).clamp(1, MAX_CELLS);
        let size = if longest > 0.0 {
            longest / per_axis as f64
        } else {
            1.0
        };
        g.min = lo;
        g.size = size;
        g.inv = 1.0 / size;
        g.n = ext.map(|e| ((e * g.inv).floor() as usize + 1).clamp(1, MAX_CELLS + 1));
        // (The largest coordinate bounds every centroid and radius's size too.)
        g.slack = SLACK_REL * (size + scale);
        let cells = g.n[0] * g.n[1] * g.n[2];
        // Each triangle's cell (u32::MAX: larger than a cell, kept apart), in
        // parallel; the cells' counts and starts (the one serial pass, over 4-byte
        // cells); then the spheres computed in triangle order and placed at their
        // cells' slots, in parallel: each task owns a run of cells (about as many
        // spheres each) and scans the cells of every triangle for its own. No list of
        // triangle indices in cell order, and no gather of corners in that order.
        let cells_of: Vec<u32> = (0..nf)
            .into_par_iter()
            .with_min_len(4096)
            .map(|t| {
                let (centre, r2) = centre_r2(mesh, t);
                if r2 > size * size {
                    u32::MAX
                } else {
                    g.index(g.cell(centre)) as u32
                }
            })
            .collect();
        let mut start = vec![0u32; cells + 1];
        for (t, &c) in cells_of.iter().enumerate() {
            if c == u32::MAX {
                g.big.push(sphere(mesh, t));
            } else {
                start[c as usize + 1] += 1;
            }
        }
        for k in 0..cells {
            start[k + 1] += start[k];
        }
        let total = start[cells] as usize;
        // (One task on one thread: every task scans all the triangles' cells.)
        let tasks = if total < 8192 {
            1
        } else {
            let n = rayon::current_num_threads();
            if n == 1 {
                1
            } else {
                2 * n
            }
        };
        // Task j's cells: from the first cell whose start reaches j/tasks of the spheres.
        let bounds: Vec<usize> = (0..=tasks)
            .map(|j| {
                if j == tasks {
                    cells
                } else {
                    start
                        .partition_point(|&s| (s as usize) < j * total / tasks)
                        .min(cells)
                }
            })
            .collect();
        let mut items: Vec<Item> = Vec::with_capacity(total);
        let mut parts = Vec::with_capacity(tasks);
        let mut rest = &mut items.spare_capacity_mut()[..total];
        for w in bounds.windows(2) {
            let (lo, hi) = (w[0], w[1].max(w[0]));
            let (mine, tail) = rest.split_at_mut((start[hi] - start[lo]) as usize);
            parts.push((lo, hi, mine));
            rest = tail;
        }
        let (written, rmax) = parts
            .into_par_iter()
            .map(|(lo, hi, out)| {
                let base = start[lo];
                let mut fill: Vec<u32> = start[lo..hi].iter().map(|&s| s - base).collect();
                let (mut written, mut rmax) = (0usize, 0.0f64);
                for (t, &c) in cells_of.iter().enumerate() {
                    let c = c as usize;
                    if c >= lo && c < hi {
                        let slot = &mut fill[c - lo];
                        let it = sphere(mesh, t);
                        rmax = rmax.max(it.radius);
                        out[*slot as usize].write(it);
                        *slot += 1;
                        written += 1;
                    }
                }
                (written, rmax)
            })
            .reduce(|| (0, 0.0), |a, b| (a.0 + b.0, a.1.max(b.1)));
        drop(cells_of);
        // Every slot was written: each task's cells hold as many triangles as it
        // wrote, into distinct slots of its own part (each cell's slots run from its
        // start up, and its count came from the same cells).
        assert_eq!(
            written, total,
            "the centroid grid's placement left a slot empty"
        );
        // SAFETY: the `total` items were initialised above (the assertion).
        unsafe { items.set_len(total) };
        g.rmax = rmax;
        g.start = start;
        g.items = items;
        g
    }

    /// The cell holding `p`, clamped into the grid.
    #[inline(always)]
    fn cell(&self, p: [f64; 3]) -> [usize; 3] {
        // Written per axis: `[0, 1, 2].map` was left out of line (as
        // `array::try_map`), a call per triangle of the build.
        let axis = |k: usize| clamp_cell((p[k] - self.min[k]) * self.inv, self.n[k]);
        [axis(0), axis(1), axis(2)]
    }

    #[inline]
    fn index(&self, c: [usize; 3]) -> usize {
        flat_index(c, self.n)
    }

    /// Test one triangle against the best squared distance so far, `best`, whose
    /// square root (rounded up by 1e-12 relative) is `sb`: skipped when its sphere is
    /// farther than `sb` by more than twice the slack, tested as squares (no square
    /// root per triangle). The computed squares are within a few ulps (relative) of the
    /// true ones, far inside the 1e-12 and the slack.
    #[inline]
    fn offer(&self, p: [f64; 3], it: &Item, best: &mut f64, sb: &mut f64) {
        let d = geom::sub(p, it.centre);
        let reach = *sb + it.radius + 2.0 * self.slack;
        if geom::dot(d, d) > reach * reach {
            return;
        }
        let [a, b, c] = self.mesh.corners(it.tri as usize);
        let q = closest_on_triangle(p, a, b, c);
        let e = geom::sub(p, q.point);
        let d2 = geom::dot(e, e);
        if d2 < *best {
            *best = d2;
            *sb = d2.sqrt() * (1.0 + 1e-12);
        }
    }

    /// The squared distance from `p` to the nearest triangle (`None`: no triangle).
    pub fn closest_dist2(&self, p: [f64; 3]) -> Option<f64> {
        if self.items.is_empty() && self.big.is_empty() {
            return None;
        }
        let (mut best, mut sb) = (f64::INFINITY, f64::INFINITY);
        for it in &self.big {
            self.offer(p, it, &mut best, &mut sb);
        }
        if self.items.is_empty() {
            return Some(best);
        }
        // How far a listed triangle can reach beyond its cell, with the margin.
        let reach = self.rmax + 2.0 * self.slack;
        // p's own cell first; then, when it held a triangle, every cell that can hold
        // the centroid of a closer one: within sb + reach of p along each axis (the
        // box's corners rounded outwards by another slack; `cell` is monotonic, so
        // such a centroid's cell is in the range).
        let c0 = self.cell(p);
        let k0 = self.index(c0);
        let own = &self.items[self.start[k0] as usize..self.start[k0 + 1] as usize];
        // The triangle whose centre is nearest first (a tight bound early skips most
        // of the others on their spheres), then the rest.
        let first = own
            .iter()
            .enumerate()
            .map(|(i, it)| {
                let d = geom::sub(p, it.centre);
                (geom::dot(d, d), i)
            })
            .fold(
                (f64::INFINITY, usize::MAX),
                |a, b| if b.0 < a.0 { b } else { a },
            )
            .1;
        if first != usize::MAX {
            self.offer(p, &own[first], &mut best, &mut sb);
        }
        for (i, it) in own.iter().enumerate() {
            if i != first {
                self.offer(p, it, &mut best, &mut sb);
            }
        }
        if sb.is_finite() {
            let r = sb + reach + self.slack;
            let lo = self.cell([0, 1, 2].map(|k| p[k] - r));
            let hi = self.cell([0, 1, 2].map(|k| p[k] + r));
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    for x in lo[0]..=hi[0] {
                        let k = self.index([x, y, z]);
                        if k == k0 {
                            continue;
                        }
                        for it in &self.items[self.start[k] as usize..self.start[k + 1] as usize] {
                            self.offer(p, it, &mut best, &mut sb);
                        }
                    }
                }
            }
            return Some(best);
        }
        // Nothing in p's cell: rings of cells around it.
        // The distance from p to the slab of cells at index c along axis k (0 inside).
        let gap2 = |k: usize, c: i64| {
            let lo = self.min[k] + c as f64 * self.size;
            let d = (lo - p[k]).max(p[k] - (lo + self.size)).max(0.0);
            d * d
        };
        // A point of a cell at Chebyshev index distance r from p's cell (p clamped into
        // the grid: projecting onto the box shortens every distance to it) is at least
        // (r - 1) cells away from p along some axis.
        let ring_lb2 = |r: i64| {
            let lb = ((r - 1) as f64 * self.size - 2.0 * self.slack).max(0.0);
            lb * lb
        };
        // Cells farther than this (squared) hold nothing closer than `best`.
        let within = |sb: f64| {
            let r = sb + reach;
            r * r
        };
        ring_search(c0, self.n, within(sb), gap2, ring_lb2, |c| {
            let k = self.index(c);
            let (s, e) = (self.start[k] as usize, self.start[k + 1] as usize);
            for it in &self.items[s..e] {
                self.offer(p, it, &mut best, &mut sb);
            }
            within(sb)
        });
        Some(best)
    }
}

/// The first reach of [`closest_dist2_all`]'s sweeps without a hint, in mean bounding
/// radii of the mesh's triangles.
const SWEEP_REACH: f64 = 0.25;
/// The first reach with a hint h (a typical distance from the mesh to the surface):
/// this many times h, but at least [`SWEEP_MIN_REACH`] mean radii.
const SWEEP_HINT_FACTOR: f64 = 2.0;
const SWEEP_MIN_REACH: f64 = 1.0 / 16.0;
/// The farthest a sweep reaches, in mean radii: its cost grows with the square of the
/// reach, and beyond this a [`CentroidGrid`] is cheaper (measured on the catalog).
const SWEEP_MAX_REACH: f64 = 1.0;
/// Each further sweep reaches this many times farther, for the points the one before
/// left open.
const SWEEP_GROWTH: f64 = 4.0;
/// Sweeps at most.
const SWEEP_PASSES: usize = 3;
/// Cell size of a sweep's grid of points: this many mean radii, plus twice the reach.
const SWEEP_CELL: f64 = 2.0;
/// Triangles per parallel run of a sweep.
const SWEEP_RUN: usize = 4096;
/// Triangles sampled (evenly spread) for the mean bounding radius.
const SWEEP_RADIUS_SAMPLE: usize = 1024;
/// A sweep's mask (see [`Sweep::offer`]) holds, at each cell, the points near the
/// block of cells from it to this many further along each axis.
const SWEEP_MASK_SPAN: usize = 2;
/// The mask's cells are sized so that this fraction of the triangles (evenly spread,
/// [`SWEEP_RADIUS_SAMPLE`] of them) meet at most [`SWEEP_MASK_SPAN`] + 1 cells along
/// each axis: their boxes' largest extent at this quantile, over the span.
const SWEEP_MASK_QUANTILE: f64 = 0.95;
/// The mask's cells at most (1 MiB of bits).
const SWEEP_MASK_BITS: usize = 1 << 23;
/// Cells of a sweep's grid per point at most (or 4,096 cells in all).
const SWEEP_CELLS_PER_POINT: usize = 8;

/// The squared distance from each query point to the nearest triangle of `mesh` (`None`
/// for every point when there is no triangle): the same values as
/// [`CentroidGrid::closest_dist2`], bit for bit, found by sweeps over the triangles
/// against a small grid of the points, with no index of the triangles when the mesh
/// lies close to the surface, which is the common case. (A triangle index's memory,
/// first touched in a short run, costs more than the search it saves:
/// `papers/bench-report.md`.)
///
/// A sweep of reach R tests each triangle against the points within R of its box,
/// skipping a point on the distance to the box whenever that exceeds the best distance
/// found for the point (with the margin of [`CentroidGrid`]'s skip tests). Most
/// triangles have no point within R: a bit mask over a finer grid, set near the
/// points, skips them from their corners' cells alone (see `Sweep::new`). A point
/// whose best distance is at most R has its exact minimum: a triangle nearer than
/// that has its box within R of the point, and was tested.
///
/// `hint` is a typical distance from the mesh to the surface (the report passes its
/// mesh → surface estimate; NaN when there is none): the first sweep reaches twice it,
/// but at least 1/16 of the triangles' mean bounding radius (without a hint, 1/4 of
/// it). The points it leaves open go to a sweep 4 times farther, up to 3 sweeps and a
/// reach of one mean radius; the rest (a mesh far from the surface for its triangles'
/// size, or one that misses part of it) to a [`CentroidGrid`]. The hint changes only
/// the time, never a value.
///
/// The coordinates of the mesh and of the queries must be finite (the report checks
/// the mesh with [`super::check_trimesh`]; its queries are projections kept inside a
/// box).
pub fn closest_dist2_all(mesh: &TriMesh, queries: &[[f64; 3]], hint: f64) -> Vec<Option<f64>> {
    sweeps(mesh, queries, hint).0
}

/// [`closest_dist2_all`], and how many points the [`CentroidGrid`] answered.
fn sweeps(mesh: &TriMesh, queries: &[[f64; 3]], hint: f64) -> (Vec<Option<f64>>, usize) {
    let nf = mesh.triangles.len();
    if nf == 0 {
        return (vec![None; queries.len()], 0);
    }
    let mut out = vec![None; queries.len()];
    if queries.is_empty() {
        return (out, 0);
    }
    // Evenly spread triangles (the middle of each run of `step`): their mean bounding
    // radius, and their largest box extents.
    let step = nf.div_ceil(SWEEP_RADIUS_SAMPLE).max(1);
    let mut sum = 0.0;
    let mut extents: Vec<f64> = (step / 2..nf)
        .step_by(step)
        .map(|t| {
            sum += centre_r2(mesh, t).1.sqrt();
            let [a, b, c] = mesh.corners(t);
            (0..3)
                .map(|k| mx(mx(a[k], b[k]), c[k]) - mn(mn(a[k], b[k]), c[k]))
                .fold(0.0, mx)
        })
        .collect();
    let mean_radius = sum / extents.len().max(1) as f64;
    // The 95th percentile of the extents.
    let q = ((extents.len() as f64 * SWEEP_MASK_QUANTILE) as usize).min(extents.len() - 1);
    let extent = *extents.select_nth_unstable_by(q, f64::total_cmp).1;
    let mut r = if hint.is_finite() && hint >= 0.0 {
        (SWEEP_HINT_FACTOR * hint).max(SWEEP_MIN_REACH * mean_radius)
    } else {
        SWEEP_REACH * mean_radius
    };
    let mut open: Vec<u32> = (0..queries.len() as u32).collect();
    // (Triangles that are all points have no radius: the grid at once.)
    if mean_radius > 0.0 && r <= SWEEP_MAX_REACH * mean_radius {
        // The size of the coordinates (vertices and points), for the margin.
        let scale = vertex_box(mesh)
            .max_abs()
            .max(queries.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs())));
        for pass in 0..SWEEP_PASSES {
            if pass > 0 && (r > SWEEP_MAX_REACH * mean_radius || open.is_empty()) {
                break;
            }
            let sweep = Sweep::new(mesh, queries, open, r, mean_radius, extent, scale);
            let best = sweep.run();
            open = Vec::new();
            for (&(_, j), &(d2, _)) in sweep.cells.items().iter().zip(&best) {
                if d2 <= sweep.r2 {
                    out[j as usize] = Some(d2);
                } else {
                    open.push(j);
                }
            }
            open.sort_unstable();
            r *= SWEEP_GROWTH;
        }
    }
    let by_grid = open.len();
    if !open.is_empty() {
        let g = CentroidGrid::new(mesh);
        let far: Vec<Option<f64>> = open
            .par_iter()
            .map(|&j| g.closest_dist2(queries[j as usize]))
            .collect();
        for (j, d) in open.into_iter().zip(far) {
            out[j as usize] = d;
        }
    }
    (out, by_grid)
}

/// The larger of two finite numbers, in one instruction (`f64::max` also handles NaN,
/// which costs a compare and a blend; the sweeps' coordinates are finite).
#[inline(always)]
fn mx(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// The smaller of two finite numbers (see [`mx`]).
#[inline(always)]
fn mn(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

/// Set bits `a..=b` of `mask` (a ≤ b), a word at a time.
#[inline]
fn set_bits(mask: &mut [u64], a: usize, b: usize) {
    let (wa, wb) = (a / 64, b / 64);
    // The bits from a's position up, and those up to b's position.
    let (from, upto) = (u64::MAX << (a % 64), u64::MAX >> (63 - b % 64));
    if wa == wb {
        mask[wa] |= from & upto;
    } else {
        mask[wa] |= from;
        mask[wa + 1..wb].fill(u64::MAX);
        mask[wb] |= upto;
    }
}

/// One pass of [`closest_dist2_all`]: the open query points sorted into a grid, and
/// the reach.
struct Sweep<'a> {
    mesh: &'a TriMesh,
    /// The points by cell, each with its index among the queries.
    cells: Buckets<([f64; 3], u32)>,
    min: [f64; 3],
    max: [f64; 3],
    inv: f64,
    n: [usize; 3],
    /// The reach R plus the margin: how far from its box a triangle is tested.
    reach: f64,
    /// R², the largest squared distance the pass answers.
    r2: f64,
    /// The margin of the skip tests (absolute).
    slack: f64,
    /// The mask's grid: finer cells from `min`, `fine_n` of them along each axis
    /// (at most 2¹⁶).
    fine_n: [usize; 3],
    /// Each vertex's cell of the mask's grid, packed: x, y and z in 16 bits each.
    vertex_cells: Vec<u64>,
    /// The mask: one bit per cell of its grid (x fastest); see [`Sweep::new`].
    mask: Vec<u64>,
}

impl<'a> Sweep<'a> {
    /// The pass of reach `r` over the points `open` (indices into `queries`, not
    /// empty), for a mesh of triangles of mean bounding radius `mean_radius` and
    /// coordinates at most `scale` in size.
    fn new(
        mesh: &'a TriMesh,
        queries: &[[f64; 3]],
        open: Vec<u32>,
        r: f64,
        mean_radius: f64,
        extent: f64,
        scale: f64,
    ) -> Self {
        let at = |j: u32| queries[j as usize];
        let (mut min, mut max) = (at(open[0]), at(open[0]));
        for &j in &open {
            let p = at(j);
            for k in 0..3 {
                min[k] = min[k].min(p[k]);
                max[k] = max[k].max(p[k]);
            }
        }
        let slack = SLACK_REL * (r + scale);
        // Cells about as wide as a triangle's box with its reach on both sides (so a
        // triangle meets a block of at most 2 × 2 × 2 cells, and the points it scans
        // are about the ones within its reach), but no more than
        // SWEEP_CELLS_PER_POINT cells per point.
        let ext = [0, 1, 2].map(|k| max[k] - min[k]);
        let cells_at = |h: f64| -> f64 { ext.iter().map(|&e| (e / h).floor() + 1.0).product() };
        let cap = (SWEEP_CELLS_PER_POINT * open.len()).max(4096) as f64;
        let longest = ext.iter().copied().fold(0.0, f64::max);
        let mut size = (SWEEP_CELL * mean_radius + 2.0 * r).max(longest / 1024.0);
        if size.is_nan() || size <= 0.0 {
            size = 1.0;
        }
        while cells_at(size) > cap {
            size *= 1.25;
        }
        let inv = 1.0 / size;
        let n = ext.map(|e| (e * inv).floor() as usize + 1);
        let cell = |p: [f64; 3]| {
            flat_index(
                [0, 1, 2].map(|k| clamp_cell((p[k] - min[k]) * inv, n[k])),
                n,
            ) as u32
        };
        let cells = Buckets::build(n[0] * n[1] * n[2], |emit| {
            for &j in &open {
                emit(cell(at(j)), (at(j), j));
            }
        });
        let reach = r + slack;
        // The mask, which lets most triangles far from every point be skipped from
        // their corners' cells alone (`Sweep::offer`). Its cells: `extent` (the
        // triangles' largest box extent at SWEEP_MASK_QUANTILE) over SWEEP_MASK_SPAN, so
        // that most boxes meet at most SWEEP_MASK_SPAN + 1 cells along each axis; at
        // most 65,000 along an axis (a cell index fits in 16 bits) and SWEEP_MASK_BITS
        // in all.
        let mut fsize = (extent / SWEEP_MASK_SPAN as f64).max(longest / 65_000.0);
        if fsize.is_nan() || fsize <= 0.0 {
            fsize = 1.0;
        }
        while cells_at(fsize) > SWEEP_MASK_BITS as f64 {
            fsize *= 1.25;
        }
        let fine_inv = 1.0 / fsize;
        let fine_n = ext.map(|e| ((e * fine_inv).floor() as usize + 1).min(1 << 16));
        let fine = |x: f64, k: usize| clamp_cell((x - min[k]) * fine_inv, fine_n[k]);
        let vertex_cells: Vec<u64> = mesh
            .vertices
            .par_iter()
            .with_min_len(8192)
            .map(|v| {
                fine(v[0], 0) as u64 | (fine(v[1], 1) as u64) << 16 | (fine(v[2], 2) as u64) << 32
            })
            .collect();
        // Bit c is set when some point p has, along every axis k,
        // cell(p_k - d) - span <= c_k <= cell(p_k + d), with d the reach plus another
        // margin. Why that suffices: a triangle whose box is within the reach of p
        // (a Euclidean distance, so along every axis too) has along each axis a
        // coordinate x of its box (p_k clamped into the box: a corner's coordinate or
        // p_k itself) within the reach of p_k, so fl(p_k - d) <= x <= fl(p_k + d) (the
        // margin exceeds their rounding). The cell of a coordinate is monotonic in it,
        // so cell(x) lies in cell(p_k - d)..=cell(p_k + d) and in l..=h, the smallest
        // and the largest of the corners' cells along k. When h <= l + span,
        // cell(p_k - d) - span <= cell(x) - span <= l <= cell(x) <= cell(p_k + d):
        // the triangle's l is a cell whose bit p set. (Clamping into the grid keeps
        // the cells monotonic, so this holds for triangles beyond the points' box too.)
        let mut mask = vec![0u64; (fine_n[0] * fine_n[1] * fine_n[2]).div_ceil(64)];
        let d = reach + slack;
        let k = SWEEP_MASK_SPAN;
        for &j in &open {
            let p = at(j);
            let lo = [0, 1, 2].map(|a| fine(p[a] - d, a).saturating_sub(k));
            let hi = [0, 1, 2].map(|a| fine(p[a] + d, a));
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    let row = (z * fine_n[1] + y) * fine_n[0];
                    set_bits(&mut mask, row + lo[0], row + hi[0]);
                }
            }
        }
        Sweep {
            mesh,
            cells,
            min,
            max,
            inv,
            n,
            reach,
            r2: r * r,
            slack,
            fine_n,
            vertex_cells,
            mask,
        }
    }

    /// The best (squared distance, its square root rounded up by 1e-12 relative) of
    /// each point in cell order, over the triangles within reach (infinite when none
    /// was): the triangles in parallel runs, each with its own bests, the runs' bests
    /// merged by the minimum (so the same values however the runs fall).
    fn run(&self) -> Vec<(f64, f64)> {
        let np = self.cells.items().len();
        let none = || vec![(f64::INFINITY, f64::INFINITY); np];
        let nf = self.mesh.triangles.len();
        let runs = nf.div_ceil(SWEEP_RUN);
        (0..runs)
            .into_par_iter()
            .map(|r| {
                let mut best = none();
                for t in r * SWEEP_RUN..((r + 1) * SWEEP_RUN).min(nf) {
                    self.offer(t, &mut best);
                }
                best
            })
            .reduce_with(|mut a, b| {
                for (x, y) in a.iter_mut().zip(b) {
                    if y.0 < x.0 {
                        *x = y;
                    }
                }
                a
            })
            .unwrap_or_else(none)
    }

    /// Test triangle `t` against every point within reach of its box. (Written out
    /// per axis: this runs once per triangle of the mesh.)
    #[inline(always)]
    fn offer(&self, t: usize, best: &mut [(f64, f64)]) {
        let [ia, ib, ic] = self.mesh.triangles[t];
        // The mask first, from the corners' cells alone (no coordinates loaded): along
        // each axis, the smallest corner cell l and the largest h. When h ≤ l + span
        // on every axis and l's bit is clear, no point is within the reach of the box
        // (see `Sweep::new`), and the triangle is skipped.
        let (ca, cb, cc) = (
            self.vertex_cells[ia as usize],
            self.vertex_cells[ib as usize],
            self.vertex_cells[ic as usize],
        );
        let (mut fits, mut bit) = (true, 0usize);
        for axis in [2, 1, 0] {
            let lane = |w: u64| (w >> (16 * axis)) & 0xffff;
            let (x, y, z) = (lane(ca), lane(cb), lane(cc));
            let l = x.min(y).min(z);
            fits &= x.max(y).max(z) - l <= SWEEP_MASK_SPAN as u64;
            bit = bit * self.fine_n[axis] + l as usize;
        }
        if fits && self.mask[bit / 64] & (1 << (bit % 64)) == 0 {
            return;
        }
        let v = &self.mesh.vertices;
        let (a, b, c) = (v[ia as usize], v[ib as usize], v[ic as usize]);
        let lo = [
            mn(mn(a[0], b[0]), c[0]),
            mn(mn(a[1], b[1]), c[1]),
            mn(mn(a[2], b[2]), c[2]),
        ];
        let hi = [
            mx(mx(a[0], b[0]), c[0]),
            mx(mx(a[1], b[1]), c[1]),
            mx(mx(a[2], b[2]), c[2]),
        ];
        let reach = self.reach;
        let (min, max, inv, n) = (self.min, self.max, self.inv, self.n);
        if hi[0] + reach < min[0]
            || hi[1] + reach < min[1]
            || hi[2] + reach < min[2]
            || lo[0] - reach > max[0]
            || lo[1] - reach > max[1]
            || lo[2] - reach > max[2]
        {
            return;
        }
        let cell = |x: f64, k: usize| clamp_cell((x - min[k]) * inv, n[k]);
        let (x0, x1) = (cell(lo[0] - reach, 0), cell(hi[0] + reach, 0));
        let (y0, y1) = (cell(lo[1] - reach, 1), cell(hi[1] + reach, 1));
        let (z0, z1) = (cell(lo[2] - reach, 2), cell(hi[2] + reach, 2));
        let slack2 = 2.0 * self.slack;
        for z in z0..=z1 {
            for y in y0..=y1 {
                // The row's cells are consecutive (x fastest).
                let row = (z * n[1] + y) * n[0];
                let span = self.cells.span(row + x0, row + x1 + 1);
                let pts = &self.cells.items()[span.clone()];
                for (&(p, _), (d2, sb)) in pts.iter().zip(&mut best[span]) {
                    // The distance from p to the box: beyond the reach, the triangle
                    // is not tested; beyond the best so far (with the margin), it
                    // cannot be nearer.
                    let gx = mx(mx(lo[0] - p[0], p[0] - hi[0]), 0.0);
                    let gy = mx(mx(lo[1] - p[1], p[1] - hi[1]), 0.0);
                    let gz = mx(mx(lo[2] - p[2], p[2] - hi[2]), 0.0);
                    let lim = mn(*sb + slack2, reach);
                    if gx * gx + gy * gy + gz * gz > lim * lim {
                        continue;
                    }
                    let q = closest_on_triangle(p, a, b, c);
                    let e = geom::sub(p, q.point);
                    let e2 = geom::dot(e, e);
                    if e2 < *d2 {
                        *d2 = e2;
                        *sb = e2.sqrt() * (1.0 + 1e-12);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::cellgrid::TriGrid;
    use proptest::prelude::*;

    fn check(m: &TriMesh, queries: &[[f64; 3]]) -> std::result::Result<(), TestCaseError> {
        check_hint(m, queries, f64::NAN)
    }

    /// [`CentroidGrid::closest_dist2`] and [`closest_dist2_all`] (with `hint`) against
    /// [`TriGrid::closest_dist2`], bit for bit.
    fn check_hint(
        m: &TriMesh,
        queries: &[[f64; 3]],
        hint: f64,
    ) -> std::result::Result<(), TestCaseError> {
        let grid = TriGrid::new(m).unwrap();
        let cg = CentroidGrid::new(m);
        let all = closest_dist2_all(m, queries, hint);
        prop_assert_eq!(all.len(), queries.len());
        for (&p, s) in queries.iter().zip(all) {
            let a = grid.closest_dist2(p);
            prop_assert_eq!(
                a.map(f64::to_bits),
                s.map(f64::to_bits),
                "sweep at {:?}: {:?} vs {:?}",
                p,
                a,
                s
            );
        }
        for &p in queries {
            let (a, b) = (grid.closest_dist2(p), cg.closest_dist2(p));
            prop_assert_eq!(
                a.map(f64::to_bits),
                b.map(f64::to_bits),
                "at {:?}: {:?} vs {:?}",
                p,
                a,
                b
            );
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]
        /// The same squared distances as the cell grid of the full report, bit for
        /// bit: random soups of small triangles with a few long slivers and repeated
        /// or collinear corners, at points among them and far outside, at several
        /// scales.
        #[test]
        fn equals_trigrid(
            pts in prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), 3..60),
            tris in prop::collection::vec((0usize..1000, 0usize..1000, 0usize..1000), 1..200),
            queries in prop::collection::vec(prop::array::uniform3(-3.0f64..3.0), 1..30),
            small in 0.001f64..0.3,
            scale in prop::sample::select(vec![1.0, 1e-6, 1e6]),
            offset in prop::sample::select(vec![0.0, 1e4]),
            // The sweeps' hint (relative to the scale): none, 0, small (several
            // sweeps), large (the grid at once).
            hint in prop::sample::select(vec![f64::NAN, 0.0, 1e-4, 1e-2, 10.0]),
        ) {
            let nv = pts.len();
            // Small triangles: a vertex and two near copies of others, except every
            // tenth (a long sliver across the mesh).
            let mut vertices: Vec<[f64; 3]> = pts.clone();
            let mut triangles = Vec::new();
            for (i, &(a, b, c)) in tris.iter().enumerate() {
                let a = a % nv;
                if i % 10 == 0 {
                    triangles.push([a as u32, (b % nv) as u32, (c % nv) as u32]);
                } else {
                    let base = vertices[a];
                    let off = |s: usize, k: usize| ((s * 7 + k * 13) % 17) as f64 / 17.0 - 0.5;
                    let v1 = [0, 1, 2].map(|k| base[k] + small * off(b, k));
                    let v2 = [0, 1, 2].map(|k| base[k] + small * off(c, k + 1));
                    vertices.push(v1);
                    vertices.push(v2);
                    let n = vertices.len() as u32;
                    triangles.push([a as u32, n - 2, n - 1]);
                }
            }
            // (Also far from the origin, where the coordinates' rounding is larger
            // than a small triangle.)
            let m = TriMesh::new(
                vertices.iter().map(|p| p.map(|x| x * scale + offset)).collect(),
                triangles,
            );
            let q: Vec<[f64; 3]> = queries
                .iter()
                .map(|p| p.map(|x| x * scale + offset))
                .chain(m.vertices.iter().take(20).map(|p| p.map(|x| x + 1e-3 * scale)))
                .collect();
            check_hint(&m, &q, hint * scale)?;
        }
    }

    /// The height of the test sheet over (x, y).
    fn sheet(x: f64, y: f64) -> f64 {
        0.3 * (3.0 * x).sin() * (2.0 * y).cos()
    }

    /// A sheet over [-1, 1]² of 121 × 121 vertices, 28,800 triangles (radius ~0.01).
    fn sine_sheet() -> TriMesh {
        let n = 121;
        let vertices: Vec<[f64; 3]> = (0..n * n)
            .map(|i| {
                let (x, y) = ((i % n) as f64 / 60.0 - 1.0, (i / n) as f64 / 60.0 - 1.0);
                [x, y, sheet(x, y)]
            })
            .collect();
        let n = n as u32;
        let triangles: Vec<[u32; 3]> = (0..n * (n - 1))
            .filter(|i| i % n != n - 1)
            .flat_map(|i| [[i, i + 1, i + n], [i + 1, i + n + 1, i + n]])
            .collect();
        TriMesh::new(vertices, triangles)
    }

    /// A mesh large enough for the parallel placement (several tasks): every listed
    /// triangle sits in its centroid's cell, the cells in order and each cell's
    /// triangles ascending (what a stable sort by cell gives), and the distances are
    /// the cell grid's.
    #[test]
    fn parallel_placement_is_a_stable_sort_by_cell() {
        let m = sine_sheet();
        let g = CentroidGrid::new(&m);
        assert!(g.items.len() > 16_384 && g.big.is_empty());
        let mut want: Vec<(usize, u32)> = (0..m.triangles.len())
            .map(|t| (g.index(g.cell(centre_r2(&m, t).0)), t as u32))
            .collect();
        want.sort_by_key(|&(c, _)| c);
        let got: Vec<u32> = g.items.iter().map(|it| it.tri).collect();
        assert_eq!(got, want.iter().map(|&(_, t)| t).collect::<Vec<_>>());
        for (k, w) in g.start.windows(2).enumerate() {
            for it in &g.items[w[0] as usize..w[1] as usize] {
                assert_eq!(g.index(g.cell(it.centre)), k);
            }
        }
        let q: Vec<[f64; 3]> = (0..200)
            .map(|i| {
                let (u, v) = ((i % 20) as f64 / 10.0 - 1.0, (i / 20) as f64 / 5.0 - 1.0);
                [u, v, 0.1 * (i % 7) as f64 - 0.3]
            })
            .collect();
        check(&m, &q).unwrap();
    }

    /// On a mesh close to its surface (points at small offsets from a sine sheet of
    /// 28,800 triangles, several parallel runs), the sweeps answer every point, with
    /// the cell grid's distances: with no hint, a hint of 0 (a second and third sweep
    /// for the farther points) and a good hint; a hint as large as the triangles
    /// leaves them all to the centroid grid.
    #[test]
    fn sweeps_answer_points_near_the_mesh() {
        let m = sine_sheet();
        // Points on the sheet and up to 1e-3 off it (triangles of radius ~0.01).
        let q: Vec<[f64; 3]> = (0..900)
            .map(|i| {
                let (u, v) = ((i % 30) as f64 / 15.5 - 0.95, (i / 30) as f64 / 15.5 - 0.95);
                [u, v, sheet(u, v) + 1e-3 * ((i % 7) as f64 / 6.0 - 0.5)]
            })
            .collect();
        for hint in [f64::NAN, 0.0, 5e-4] {
            let (_, by_grid) = sweeps(&m, &q, hint);
            assert_eq!(by_grid, 0, "hint {hint}");
            check_hint(&m, &q, hint).unwrap();
        }
        let (_, by_grid) = sweeps(&m, &q, 1.0);
        assert_eq!(by_grid, q.len());
    }

    /// A triangle much longer than the others (beyond the span of the sweeps' mask) is
    /// tested from its box, not skipped from its corners' cells: a sliver 1.8 long, 1e-3
    /// above the sheet's line z = 0 at x = 0, its lowest corner far from the points
    /// just under it, which are nearer to it (1e-5) than to the sheet (under 1e-3, within
    /// the first sweep's reach). Skipping it on the mask alone would answer them with
    /// the sheet's distance.
    #[test]
    fn sweeps_test_triangles_longer_than_the_mask_span() {
        let mut m = sine_sheet();
        let base = m.vertices.len() as u32;
        m.vertices
            .extend([[0.0, -0.9, 1e-3], [0.0, 0.9, 1e-3], [1e-4, 0.0, 1e-3]]);
        m.triangles.push([base, base + 1, base + 2]);
        // (Two points on the sheet's far corners widen the points' box, so that the
        // sliver's lowest corner cell is far from every point.)
        let mut q: Vec<[f64; 3]> = (0..51)
            .map(|i| [0.0, i as f64 / 100.0, 1e-3 - 1e-5])
            .collect();
        q.extend([-0.95, 0.95].map(|c| [c, c, sheet(c, c)]));
        for hint in [f64::NAN, 0.0, 5e-4] {
            check_hint(&m, &q, hint).unwrap();
            let d = closest_dist2_all(&m, &q, hint);
            assert!(
                d[..51].iter().all(|d| d.unwrap() <= 1.0001e-10),
                "hint {hint}"
            );
        }
    }

    proptest! {
        /// `set_bits` sets exactly the bits of `a..=b` and keeps the others, as one bit
        /// at a time does: ranges within a word, across one boundary and several, on
        /// words already partly set.
        #[test]
        fn set_bits_sets_the_range(
            a in 0usize..400,
            len in 0usize..200,
            init in proptest::collection::vec(any::<u64>(), 10),
        ) {
            let b = a + len;
            let mut got = init.clone();
            set_bits(&mut got, a, b);
            let mut want = init;
            for bit in a..=b {
                want[bit / 64] |= 1 << (bit % 64);
            }
            prop_assert_eq!(got, want);
        }
    }

    #[test]
    fn empty_and_flat_meshes() {
        let m = TriMesh::new(vec![[0.0; 3]; 3], vec![]);
        assert_eq!(CentroidGrid::new(&m).closest_dist2([1.0, 0.0, 0.0]), None);
        // One point-like triangle, and a flat mesh in z = 0.
        let m = TriMesh::new(vec![[0.5; 3]; 3], vec![[0, 1, 2]]);
        check(&m, &[[0.0; 3], [0.5; 3]]).unwrap();
        let vertices: Vec<[f64; 3]> = (0..30)
            .map(|i| [(i % 6) as f64 * 0.2, (i / 6) as f64 * 0.2, 0.0])
            .collect();
        let triangles = (0..24u32)
            .filter(|i| i % 6 != 5)
            .flat_map(|i| [[i, i + 1, i + 6], [i + 1, i + 7, i + 6]])
            .collect();
        let m = TriMesh::new(vertices, triangles);
        check(&m, &[[0.3, 0.3, 0.1], [-1.0, 2.0, -0.5], [0.55, 0.41, 0.0]]).unwrap();
    }
}
