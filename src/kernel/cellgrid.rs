//! Exact point-to-triangle-mesh distances through a uniform grid of cells (issue 20):
//! for a modest number of queries on a large mesh (the Hausdorff estimate's surface
//! points), building it is one linear pass (each triangle listed in every cell its
//! bounding box meets, [`Buckets`]) instead of a BVH's O(n log n) build, and a query
//! scans rings of cells around its own until no unscanned cell can hold a closer
//! point. The distance is exact in the same sense as [`TriBvh::closest`]: the minimum
//! of the same per-triangle routine over every triangle that could be nearest, so both
//! give the same value.
//!
//! [`TriBvh::closest`]: super::bvh::TriBvh::closest
use super::bvh::closest_on_triangle;
use super::geom::{self, Aabb};
use crate::error::{Error, Result};
use crate::mesh::{Buckets, TriMesh};

/// Cells of the grid's cube per triangle: a surface meets about (cells per axis)² of
/// them, so this gives about `CELLS_PER_TRIANGLE^(2/3)` triangles per occupied cell.
const CELLS_PER_TRIANGLE: f64 = 4.0;
/// Cells per axis at most (160³ cells: 16 MB of bucket offsets).
const MAX_CELLS: usize = 160;

/// The grid over a mesh: `n` cells per axis of size `h` from `min`; cell `(i, j, k)`
/// lists the triangles whose box meets it.
#[derive(Clone, Debug)]
pub struct TriGrid<'a> {
    mesh: &'a TriMesh,
    min: [f64; 3],
    h: [f64; 3],
    n: [usize; 3],
    /// Slack for rounding: triangles are listed in the cells their box grown by
    /// `slack` meets, and lower bounds are taken to cells grown by it, so a point
    /// rounded into a neighbouring cell is still accounted for.
    slack: f64,
    cells: Buckets<u32>,
}

impl<'a> TriGrid<'a> {
    /// Errors on out-of-range indices or non-finite coordinates.
    pub fn new(mesh: &'a TriMesh) -> Result<Self> {
        use rayon::prelude::*;
        crate::metrics::check_trimesh(mesh)?;
        let nf = mesh.triangles.len();
        let empty = TriGrid {
            mesh,
            min: [0.0; 3],
            h: [1.0; 3],
            n: [1; 3],
            slack: 0.0,
            cells: Buckets::default(),
        };
        // The box of all vertices (used or not: it only places the cells).
        let (Some(bb), true) = (Aabb::of_points(&mesh.vertices), nf > 0) else {
            return Ok(empty);
        };
        let ext = bb.size();
        let longest = ext.iter().copied().fold(0.0, f64::max);
        // Cubic cells, CELLS_PER_TRIANGLE per triangle along the longest side's cube.
        let per_axis =
            ((nf as f64 * CELLS_PER_TRIANGLE).cbrt().ceil() as usize).clamp(1, MAX_CELLS);
        let side = if longest > 0.0 {
            longest / per_axis as f64
        } else {
            1.0
        };
        let n = ext.map(|e| ((e / side).ceil() as usize).clamp(1, MAX_CELLS));
        let h = [0, 1, 2].map(|k| {
            if ext[k] > 0.0 {
                ext[k] / n[k] as f64
            } else {
                side
            }
        });
        let total = n[0] * n[1] * n[2];
        if total >= u32::MAX as usize {
            return Err(Error::TooLarge(format!("{total} grid cells")));
        }
        let scale = bb.max_abs();
        let mut g = TriGrid {
            mesh,
            min: bb.min,
            h,
            n,
            slack: 1e-9 * (h.iter().copied().fold(f64::INFINITY, f64::min) + scale),
            cells: Buckets::default(),
        };
        // The cells each triangle's box (grown by the slack) meets, once, in parallel.
        let ranges: Vec<([usize; 3], [usize; 3])> = (0..nf)
            .into_par_iter()
            .map(|t| {
                let b = Aabb::of_points(&mesh.corners(t))
                    .expect("three corners")
                    .inflate(g.slack);
                (g.cell(b.min), g.cell(b.max))
            })
            .collect();
        g.cells = Buckets::build(total, |emit| {
            for (t, (lo, hi)) in ranges.iter().enumerate() {
                for z in lo[2]..=hi[2] {
                    for y in lo[1]..=hi[1] {
                        for x in lo[0]..=hi[0] {
                            emit(g.index([x, y, z]) as u32, t as u32);
                        }
                    }
                }
            }
        });
        Ok(g)
    }

    /// The cell holding `p`, clamped into the grid.
    #[inline(always)]
    fn cell(&self, p: [f64; 3]) -> [usize; 3] {
        // Written per axis: `[0, 1, 2].map` was left out of line here (as
        // `array::try_map`), a call per point.
        let axis = |k: usize| clamp_cell((p[k] - self.min[k]) / self.h[k], self.n[k]);
        [axis(0), axis(1), axis(2)]
    }

    #[inline]
    fn index(&self, c: [usize; 3]) -> usize {
        flat_index(c, self.n)
    }

    /// The squared distance from `p` to the nearest triangle (`None`: no triangle).
    pub fn closest_dist2(&self, p: [f64; 3]) -> Option<f64> {
        if self.cells.is_empty() {
            return None;
        }
        let hmin = self.h.iter().copied().fold(f64::INFINITY, f64::min);
        // The squared distance from p to the slab of cells at index c along axis k,
        // the cells grown by the slack (0 inside p's own slab): the same per-axis terms
        // as the cell box bound, so a cell, a row or a plane of cells can be skipped on
        // a partial sum.
        let gap2 = |k: usize, c: i64| {
            let lo = self.min[k] + c as f64 * self.h[k] - self.slack;
            let d = (lo - p[k])
                .max(p[k] - (lo + self.h[k] + 2.0 * self.slack))
                .max(0.0);
            d * d
        };
        // Every point of a cell in ring r is at least (r - 1) cells from p along some
        // axis.
        let ring_lb2 = |r: i64| {
            let lb = ((r - 1).max(0) as f64 * hmin - 2.0 * self.slack).max(0.0);
            lb * lb
        };
        let mut best = f64::INFINITY;
        ring_search(self.cell(p), self.n, f64::INFINITY, gap2, ring_lb2, |c| {
            // The cell's box is a lower bound for what it lists (each triangle meets it).
            for &t in self.cells.bucket(self.index(c)) {
                let [a, b, c] = self.mesh.corners(t as usize);
                let q = closest_on_triangle(p, a, b, c);
                let d = geom::sub(p, q.point);
                best = best.min(geom::dot(d, d));
            }
            best
        });
        best.is_finite().then_some(best)
    }
}

/// The cell index along one axis of a grid of `n` cells, for the coordinate `t` in
/// cell units: floored, clamped into 0..n (NaN gives 0; so does n = 0). Clamped first,
/// as a float, so that the conversion is one truncation: this runs six times per
/// triangle in the report's sweeps (three instructions instead of a floor, a
/// saturating conversion and two clamps).
#[inline]
pub(crate) fn clamp_cell(t: f64, n: usize) -> usize {
    // The last index as a float, exact (at most 2⁵², beyond any grid that fits in
    // memory); `max` returns 0 for NaN.
    let last = n.saturating_sub(1).min(1 << 52) as f64;
    let c = t.max(0.0).min(last);
    // SAFETY: c is finite and in [0, 2⁵²], so its truncation fits in an i64 (a signed
    // conversion is one instruction; an unsigned one is not on x86-64); for c ≥ 0
    // truncation is the floor.
    unsafe { c.to_int_unchecked::<i64>() as usize }
}

/// The position of cell `c` in a grid of `n` cells stored x fastest.
#[inline]
pub(crate) fn flat_index(c: [usize; 3], n: [usize; 3]) -> usize {
    (c[2] * n[1] + c[1]) * n[0] + c[0]
}

/// Visit the cells of a grid of `n` cells in rings of growing Chebyshev distance from
/// cell `c0`, skipping every cell whose lower bound exceeds the current bound (a
/// squared distance, `bound` at the start): `gap2(k, c)` bounds from below the squared
/// distance along axis k to the slab of cells at index c (summed over the axes for a
/// cell, so a plane or a row is skipped on a partial sum), `ring_lb2(r)` that to any
/// cell of ring r; `visit(cell)` scans a cell and returns the new bound. Stops when a
/// whole ring is beyond the bound.
pub(crate) fn ring_search(
    c0: [usize; 3],
    n: [usize; 3],
    mut bound: f64,
    gap2: impl Fn(usize, i64) -> f64,
    ring_lb2: impl Fn(i64) -> f64,
    mut visit: impl FnMut([usize; 3]) -> f64,
) {
    let c0 = c0.map(|x| x as i64);
    let n = n.map(|x| x as i64);
    let rings = (0..3)
        .map(|k| c0[k].max(n[k] - 1 - c0[k]))
        .max()
        .unwrap_or(0);
    for r in 0..=rings {
        if ring_lb2(r) > bound {
            break;
        }
        for dz in -r..=r {
            let z = c0[2] + dz;
            if z < 0 || z >= n[2] {
                continue;
            }
            let gz = gap2(2, z);
            if gz > bound {
                continue;
            }
            for dy in -r..=r {
                let y = c0[1] + dy;
                if y < 0 || y >= n[1] {
                    continue;
                }
                let gy = gz + gap2(1, y);
                if gy > bound {
                    continue;
                }
                // Inside the shell only the two end cells of the row are in ring r.
                let shell = dz.abs() == r || dy.abs() == r;
                let mut dx = -r;
                while dx <= r {
                    let x = c0[0] + dx;
                    if x >= 0 && x < n[0] && gy + gap2(0, x) <= bound {
                        bound = visit([x as usize, y as usize, z as usize]);
                    }
                    dx += if shell || r == 0 { 1 } else { 2 * r };
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::bvh::TriBvh;
    use crate::kernel::rng::Rng;
    use proptest::prelude::*;

    /// The definition `clamp_cell` computes by a float clamp and one truncation.
    fn clamp_cell_reference(t: f64, n: usize) -> usize {
        let i = t.floor();
        if i >= 0.0 {
            (i as usize).min(n - 1)
        } else {
            0
        }
    }

    proptest! {
        /// `clamp_cell` is the floor clamped into 0..n, for every coordinate: negative,
        /// inside, on a cell boundary, past the end, huge, infinite and NaN.
        #[test]
        fn clamp_cell_is_the_clamped_floor(
            n in 1usize..5000,
            t in prop_oneof![
                -10.0f64..6000.0,
                (0usize..5001).prop_map(|k| k as f64),
                // just below a boundary
                (1usize..5001).prop_map(|k| f64::from_bits((k as f64).to_bits() - 1)),
                proptest::num::f64::ANY,
            ],
        ) {
            prop_assert_eq!(clamp_cell(t, n), clamp_cell_reference(t, n));
        }
    }

    #[test]
    fn clamp_cell_edges() {
        for n in [1, 2, 7, 1 << 20] {
            for t in [
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
                -0.0,
                0.0,
                -1e-300,
                1e300,
            ] {
                assert_eq!(clamp_cell(t, n), clamp_cell_reference(t, n), "{t} {n}");
            }
        }
    }

    /// The grid's distance equals the BVH's, bit for bit, on random soups of triangles
    /// of mixed sizes (a few long ones across many cells), at points inside and far
    /// outside the mesh's box, and on a flat mesh.
    #[test]
    fn equals_bvh_distance() {
        let mut rng = Rng::new(7);
        let mut u = move || rng.uniform();
        for case in 0..6 {
            let nv = 3 + 40 * case;
            let flat = case == 5;
            let vertices: Vec<[f64; 3]> = (0..nv)
                .map(|_| [u(), u() * 0.5, if flat { 0.25 } else { u() }])
                .collect();
            let mut m = TriMesh::new(vertices, Vec::new());
            for t in 0..(2 * nv) {
                let a = t % nv;
                let b = if t % 7 == 0 {
                    (a + nv / 2) % nv
                } else {
                    (a + 1) % nv
                };
                let c = (a + 2) % nv;
                m.triangles.push([a as u32, b as u32, c as u32]);
            }
            let grid = TriGrid::new(&m).unwrap();
            let bvh = TriBvh::new(&m).unwrap();
            for _ in 0..300 {
                let p = [3.0 * u() - 1.0, 3.0 * u() - 1.0, 3.0 * u() - 1.0];
                let want = bvh.closest(p).map(|c| c.dist2);
                assert_eq!(grid.closest_dist2(p), want, "case {case} at {p:?}");
            }
        }
        assert_eq!(
            TriGrid::new(&TriMesh::default())
                .unwrap()
                .closest_dist2([0.0; 3]),
            None
        );
    }
}
