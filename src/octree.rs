//! Interval pruning of empty space on a grid: octree descent over ranges of grid
//! cells. A block of cells is discarded when the interval enclosure of f over its box
//! excludes 0 (then f has one strict sign on the whole block, so no cell of it meets
//! f = 0); blocks that survive are split in halves along every axis longer than one
//! cell, down to single cells. Only the vertices of surviving cells are evaluated.
//!
//! Pruning never changes the output of an extractor that reads signs at vertices
//! (marching cubes, tetrahedra, squares): a pruned cell has all its vertices of one
//! strict sign, so it has no sign change, exactly as on the dense grid. (One caveat: the
//! enclosure is of the exact f, while the dense grid holds f64 evaluations. If the f64
//! evaluation of f had the wrong sign at a vertex — possible only where |f| is at the
//! level of rounding errors — the dense grid would be the wrong one.) With a
//! non-rigorous oracle ([`Implicit::is_rigorous`] false) the enclosure is only as good
//! as the oracle's bound.
use crate::error::Result;
use crate::grid::{Grid, SparseSamples};
use crate::implicit::Implicit;
use crate::mesher::Progress;
use rayon::prelude::*;
use serde::Serialize;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

/// What a pruning pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct PruneStats {
    /// Interval evaluations of f (one per visited block).
    pub interval_evaluations: u64,
    /// Point evaluations of f (one per vertex of a surviving cell).
    pub point_evaluations: u64,
    /// Cells that may meet f = 0.
    pub cells_kept: u64,
    /// Cells proven free of f = 0.
    pub cells_pruned: u64,
}

/// Blocks with more cells than this are split in parallel.
const PARALLEL_CELLS: u64 = 1 << 12;

/// An inclusive range of vertex indices per axis: the cells between them.
#[derive(Clone, Copy)]
struct Block {
    lo: [usize; 3],
    hi: [usize; 3],
}

impl Block {
    fn cells(&self) -> u64 {
        (0..3)
            .map(|a| (self.hi[a] - self.lo[a]).max(1) as u64)
            .product()
    }
    fn is_cell(&self) -> bool {
        (0..3).all(|a| self.hi[a] - self.lo[a] <= 1)
    }
    /// The (up to 8) halves: every axis longer than one cell is split at its middle.
    fn children(&self) -> Vec<Block> {
        let mut out = vec![*self];
        for a in 0..3 {
            if self.hi[a] - self.lo[a] >= 2 {
                let mid = (self.lo[a] + self.hi[a]) / 2;
                out = out
                    .into_iter()
                    .flat_map(|b| {
                        let mut l = b;
                        let mut h = b;
                        l.hi[a] = mid;
                        h.lo[a] = mid;
                        [l, h]
                    })
                    .collect();
            }
        }
        out
    }
}

/// The cells of `grid` whose box may meet f = 0, by their lowest vertex, in no
/// particular order; and the counts.
pub fn surviving_cells(f: &dyn Implicit, grid: &Grid) -> (Vec<[u32; 3]>, PruneStats) {
    let ivals = AtomicU64::new(0);
    let pruned = AtomicU64::new(0);
    let root = Block {
        lo: [0; 3],
        hi: grid.cells(),
    };
    let cells = descend(f, grid, root, &ivals, &pruned);
    let stats = PruneStats {
        interval_evaluations: ivals.load(Relaxed),
        point_evaluations: 0,
        cells_kept: cells.len() as u64,
        cells_pruned: pruned.load(Relaxed),
    };
    (cells, stats)
}

fn descend(
    f: &dyn Implicit,
    grid: &Grid,
    b: Block,
    ivals: &AtomicU64,
    pruned: &AtomicU64,
) -> Vec<[u32; 3]> {
    let bx = grid.vertex_box(b.lo, b.hi).intervals();
    let v = f.eval_interval(&bx);
    ivals.fetch_add(1, Relaxed);
    // An empty enclosure (f undefined on the whole box) is not a proof of anything:
    // keep descending so the point evaluations report where f is not finite.
    if !v.is_empty() && !v.contains(0.0) {
        pruned.fetch_add(b.cells(), Relaxed);
        return Vec::new();
    }
    if b.is_cell() {
        return vec![b.lo.map(|x| x as u32)];
    }
    let kids = b.children();
    if b.cells() > PARALLEL_CELLS {
        kids.into_par_iter()
            .map(|c| descend(f, grid, c, ivals, pruned))
            .reduce(Vec::new, |mut a, mut c| {
                a.append(&mut c);
                a
            })
    } else {
        let mut out = Vec::new();
        for c in kids {
            out.extend(descend(f, grid, c, ivals, pruned));
        }
        out
    }
}

/// Prune `grid` with intervals, then evaluate f at the vertices of the surviving
/// cells only. Errors as [`SparseSamples::evaluate`].
pub fn sample_pruned(
    f: &dyn Implicit,
    grid: &Grid,
    progress: &dyn Progress,
) -> Result<(SparseSamples, PruneStats)> {
    progress.start("pruning empty space with intervals", 0);
    let (cells, mut stats) = surviving_cells(f, grid);
    progress.finish();
    let corners: Vec<[usize; 3]> = (0..if grid.dim() == 3 { 8 } else { 4 })
        .map(|c| [c & 1, (c >> 1) & 1, (c >> 2) & 1])
        .collect();
    let vertices: Vec<u64> = cells
        .par_iter()
        .flat_map_iter(|c| {
            corners.iter().map(move |d| {
                grid.index(
                    c[0] as usize + d[0],
                    c[1] as usize + d[1],
                    c[2] as usize + d[2],
                ) as u64
            })
        })
        .collect();
    let samples = SparseSamples::evaluate(f, grid, vertices, progress)?;
    stats.point_evaluations = samples.evaluated() as u64;
    Ok((samples, stats))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Aabb;
    use crate::grid::{Field, Samples};
    use crate::implicit::Formula;
    use crate::mesher::NoProgress;

    #[test]
    fn pruning_keeps_every_sign_change_cell_and_few_others() {
        let f = Formula::surface("x^2 + y^2 + z^2 - 1").unwrap();
        let g = Grid::new(&Aabb::cube(1.5), 32, 3).unwrap();
        let dense = Samples::sample(&f, &g, &NoProgress).unwrap();
        let (sparse, st) = sample_pruned(&f, &g, &NoProgress).unwrap();
        assert_eq!(st.cells_kept + st.cells_pruned, g.num_cells() as u64);
        assert!(st.point_evaluations < g.num_vertices() as u64 / 3, "{st:?}");
        let mut changes = 0;
        for k in 0..32 {
            for j in 0..32 {
                for i in 0..32 {
                    let vals: Vec<f64> = (0..8)
                        .map(|c| dense.value(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2)))
                        .collect();
                    let neg = vals.iter().filter(|v| **v < 0.0).count();
                    if neg != 0 && neg != 8 {
                        changes += 1;
                        for c in 0..8 {
                            let s = sparse.value(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2));
                            assert_eq!(s, vals[c]);
                        }
                    }
                }
            }
        }
        assert!(changes > 0);
    }

    #[test]
    fn planar_grid_prunes_too() {
        let f = Formula::curve("x^2 + y^2 - 1").unwrap();
        let g = Grid::new(&Aabb::rect([-1.5, -1.5], [1.5, 1.5]), 64, 2).unwrap();
        let (s, st) = sample_pruned(&f, &g, &NoProgress).unwrap();
        assert!(st.cells_pruned > st.cells_kept);
        assert!(s.value(0, 32, 0).is_nan());
        assert_eq!(s.value(11, 32, 0), f.eval(g.point(11, 32, 0)));
    }
}
