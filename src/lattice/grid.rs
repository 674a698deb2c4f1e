//! Regular sampling grids: the lattice shared by the marching meshers (and reusable by
//! any lattice method), f sampled once per grid vertex.
//!
//! * [`Grid`]: the geometry: the domain split into `n_x × n_y × n_z` near-cubic cells
//!   (`n_z = 0` for curves: one layer of vertices at z = `domain.min[2]`);
//! * [`Samples`]: f at every vertex, dense, in a flat `Vec<f64>` (x fastest), sampled in
//!   parallel;
//! * [`SparseSamples`]: f only at chosen vertices (those of the cells that interval
//!   pruning kept, see [`crate::lattice::octree`]), stored in 8×8×8 bricks;
//! * [`Field`]: what an extractor reads from either.
use crate::error::{Error, Result};
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;
use crate::mesher::Progress;
use rayon::prelude::*;

/// Largest dense sample array, in bytes (8 per vertex): 4 GiB, about 812³ vertices.
/// Larger grids must be pruned (`prune`), which stores only the vertices it evaluates.
pub const MAX_DENSE_BYTES: u64 = 4 << 30;
/// Largest number of cells along one axis.
pub const MAX_AXIS_CELLS: usize = 1 << 16;
/// Largest number of grid vertices, dense or sparse (indices are `u64`; the brick table
/// of [`SparseSamples`] has one `u32` per 512 vertices).
pub const MAX_VERTICES: u64 = 1 << 40;

/// A regular grid over a box. Vertex `(i, j, k)` sits at
/// `min + (max - min) * (i / n_x, j / n_y, k / n_z)`; the coordinate of a vertex is a
/// monotone function of its index, so the box spanned by a range of vertex indices
/// (see [`Grid::vertex_box`]) contains every vertex of the range: interval pruning relies
/// on that.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    domain: Aabb,
    cells: [usize; 3],
    dim: usize,
}

impl Grid {
    /// A grid of near-cubic cells with `resolution` cells along the longest side of
    /// `domain` (the other axes get `round(side / h)` cells, at least one). `dim` 2 gives
    /// a planar grid (for curves; z ignored), 3 a volume grid.
    pub fn new(domain: &Aabb, resolution: usize, dim: usize) -> Result<Grid> {
        if dim != 2 && dim != 3 {
            return Err(Error::Param(format!(
                "a grid has dimension 2 or 3, not {dim}"
            )));
        }
        if resolution == 0 {
            return Err(Error::Param("resolution must be at least 1 cell".into()));
        }
        let domain = Aabb::new(domain.min, domain.max)?;
        let size = domain.size();
        for (k, &s) in size.iter().enumerate().take(dim) {
            if s <= 0.0 {
                return Err(Error::Domain(format!(
                    "axis {} of the box has zero extent; a {dim}D grid needs a positive size",
                    ["x", "y", "z"][k]
                )));
            }
        }
        let longest = size[..dim].iter().cloned().fold(0.0, f64::max);
        let h = longest / resolution as f64;
        let mut cells = [0usize; 3];
        for k in 0..dim {
            let n = (size[k] / h).round();
            cells[k] = if n.is_finite() && n >= 1.0 {
                n.min(1e12) as usize
            } else {
                1
            };
        }
        Grid::with_cells(&domain, cells, dim)
    }

    /// A grid with the given cell counts (`cells[2]` must be 0 when `dim` is 2).
    pub fn with_cells(domain: &Aabb, cells: [usize; 3], dim: usize) -> Result<Grid> {
        let domain = Aabb::new(domain.min, domain.max)?;
        if dim != 2 && dim != 3 {
            return Err(Error::Param(format!(
                "a grid has dimension 2 or 3, not {dim}"
            )));
        }
        for (k, &c) in cells.iter().enumerate() {
            let active = k < dim;
            if active && c == 0 {
                return Err(Error::Param(format!(
                    "a {dim}D grid needs at least one cell along {}",
                    ["x", "y", "z"][k]
                )));
            }
            if !active && c != 0 {
                return Err(Error::Param("a 2D grid has no cells along z".into()));
            }
            if c > MAX_AXIS_CELLS {
                return Err(Error::TooLarge(format!(
                    "{c} cells along {} (at most {MAX_AXIS_CELLS})",
                    ["x", "y", "z"][k]
                )));
            }
        }
        let g = Grid { domain, cells, dim };
        if g.num_vertices_u64() > MAX_VERTICES {
            return Err(Error::TooLarge(format!(
                "a grid of {} x {} x {} cells has {} vertices (at most {MAX_VERTICES})",
                cells[0],
                cells[1],
                cells[2],
                g.num_vertices_u64()
            )));
        }
        Ok(g)
    }

    pub fn domain(&self) -> &Aabb {
        &self.domain
    }
    /// 2 (planar grid) or 3.
    pub fn dim(&self) -> usize {
        self.dim
    }
    /// Cells along each axis (z is 0 for a planar grid).
    pub fn cells(&self) -> [usize; 3] {
        self.cells
    }
    /// Vertices along each axis: `cells + 1` (1 along z for a planar grid).
    #[inline]
    pub fn vertex_dims(&self) -> [usize; 3] {
        [self.cells[0] + 1, self.cells[1] + 1, self.cells[2] + 1]
    }
    fn num_vertices_u64(&self) -> u64 {
        self.vertex_dims().iter().map(|&n| n as u64).product()
    }
    pub fn num_vertices(&self) -> usize {
        self.num_vertices_u64() as usize
    }
    /// Number of cells (squares for a planar grid).
    pub fn num_cells(&self) -> usize {
        self.cells[..self.dim].iter().product()
    }
    /// The cell edge lengths.
    pub fn spacing(&self) -> [f64; 3] {
        let s = self.domain.size();
        [0, 1, 2].map(|k| {
            if self.cells[k] == 0 {
                0.0
            } else {
                s[k] / self.cells[k] as f64
            }
        })
    }
    /// Coordinate of vertex index `i` along `axis` (monotone in `i`).
    #[inline]
    pub fn coord(&self, axis: usize, i: usize) -> f64 {
        let n = self.cells[axis];
        if n == 0 {
            return self.domain.min[axis];
        }
        let (lo, hi) = (self.domain.min[axis], self.domain.max[axis]);
        lo + (hi - lo) * (i as f64 / n as f64)
    }
    /// The position of vertex `(i, j, k)`.
    #[inline]
    pub fn point(&self, i: usize, j: usize, k: usize) -> [f64; 3] {
        [self.coord(0, i), self.coord(1, j), self.coord(2, k)]
    }
    /// Flat index of vertex `(i, j, k)` (x fastest).
    #[inline]
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        let [nx, ny, _] = self.vertex_dims();
        i + nx * (j + ny * k)
    }
    /// The vertex `(i, j, k)` of a flat index.
    #[inline]
    pub fn unindex(&self, v: usize) -> [usize; 3] {
        let [nx, ny, _] = self.vertex_dims();
        [v % nx, (v / nx) % ny, v / (nx * ny)]
    }
    /// The box spanned by the vertices `lo..=hi` (inclusive index ranges).
    pub fn vertex_box(&self, lo: [usize; 3], hi: [usize; 3]) -> Aabb {
        Aabb {
            min: [0, 1, 2].map(|a| self.coord(a, lo[a])),
            max: [0, 1, 2].map(|a| self.coord(a, hi[a])),
        }
    }
    /// The error for a non-finite value at vertex `v`.
    pub fn not_finite(&self, v: usize, value: f64) -> Error {
        let [i, j, k] = self.unindex(v);
        let p = self.point(i, j, k);
        Error::NotFinite(format!(
            "f = {value} at ({}, {}, {}) (grid vertex {i}, {j}, {k})",
            p[0], p[1], p[2]
        ))
    }
}

/// What an extractor reads: f at grid vertices. `NaN` means "not evaluated" (only
/// [`SparseSamples`] returns it, for vertices of pruned cells).
pub trait Field: Sync {
    /// True when [`Field::value`] may return `NaN` for skipped vertices.
    const SPARSE: bool;
    fn grid(&self) -> &Grid;
    fn value(&self, i: usize, j: usize, k: usize) -> f64;
    /// The signs of the row of vertices `(.., j, k)` as bit sets (bit `i` of word
    /// `i / 64`): `neg` where f < 0, `valid` where the value exists (not skipped by
    /// pruning). Both slices are zeroed by the caller and hold `nx.div_ceil(64)` words.
    fn sign_row(&self, j: usize, k: usize, neg: &mut [u64], valid: &mut [u64]) {
        let n = self.grid().vertex_dims()[0];
        for i in 0..n {
            let v = self.value(i, j, k);
            neg[i >> 6] |= ((v < 0.0) as u64) << (i & 63);
            valid[i >> 6] |= ((!v.is_nan()) as u64) << (i & 63);
        }
    }
}

/// The signs of a whole field, packed one bit per vertex (1/32 of the dense samples):
/// extractors find sign changes 64 vertices at a time and read values only there.
#[derive(Clone, Debug)]
pub struct SignBits {
    /// Words per row of vertices (each row padded with at least one zero bit).
    pub words: usize,
    /// `neg[(j + ny * k) * words + w]`: bit `i % 64` of word `i / 64` set when f < 0.
    pub neg: Vec<u64>,
    /// The same layout: set where a value exists (always, for dense samples).
    pub valid: Vec<u64>,
}

impl SignBits {
    /// Compute the bits of a field, rows in parallel.
    pub fn of<F: Field>(field: &F) -> SignBits {
        let [nx, ny, nz] = field.grid().vertex_dims();
        let words = nx / 64 + 1;
        let mut neg = vec![0u64; words * ny * nz];
        let mut valid = vec![0u64; words * ny * nz];
        neg.par_chunks_mut(words)
            .zip(valid.par_chunks_mut(words))
            .enumerate()
            .for_each(|(r, (n, v))| field.sign_row(r % ny, r / ny, n, v));
        SignBits { words, neg, valid }
    }
    /// The words of row (j, k) of `bits` (`neg` or `valid`).
    #[inline(always)]
    pub fn row<'a>(&self, bits: &'a [u64], ny: usize, j: usize, k: usize) -> &'a [u64] {
        let b = (j + ny * k) * self.words;
        &bits[b..b + self.words]
    }
}

/// f at every vertex of a grid, in a flat array (x fastest, then y, then z).
#[derive(Clone, Debug)]
pub struct Samples {
    grid: Grid,
    values: Vec<f64>,
}

/// Refuse dense arrays that would not fit in memory.
fn check_dense(grid: &Grid) -> Result<()> {
    let n = grid.num_vertices_u64();
    let bytes = n.saturating_mul(8);
    if n > u32::MAX as u64 || bytes > MAX_DENSE_BYTES {
        let [a, b, c] = grid.vertex_dims();
        return Err(Error::TooLarge(format!(
            "a dense grid of {a} x {b} x {c} vertices needs {:.1} GB (at most {} GB): \
             lower the resolution or prune empty space with intervals (--prune)",
            bytes as f64 / 1e9,
            MAX_DENSE_BYTES as f64 / 1e9
        )));
    }
    Ok(())
}

impl Samples {
    /// Evaluate f once at every vertex of `grid`, rows in parallel. Fails with
    /// [`Error::TooLarge`] when the array would not fit ([`MAX_DENSE_BYTES`]) and with
    /// [`Error::NotFinite`] naming the first vertex where f is NaN or infinite.
    pub fn sample(f: &dyn Implicit, grid: &Grid, progress: &dyn Progress) -> Result<Samples> {
        check_dense(grid)?;
        let [nx, ny, nz] = grid.vertex_dims();
        let mut values = vec![0.0f64; grid.num_vertices()];
        progress.start("sampling f on the grid", (ny * nz) as u64);
        // One task per row of x: fine enough for planar grids, coarse enough that the
        // scheduling cost vanishes next to nx evaluations. A row is one batch call
        // (SIMD lanes for formulas; the same values as `eval` point by point).
        let xs: Vec<f64> = (0..nx).map(|i| grid.coord(0, i)).collect();
        values.par_chunks_mut(nx).enumerate().for_each_init(
            || (vec![0.0; nx], vec![0.0; nx]),
            |(ys, zs), (row, out)| {
                let (j, k) = (row % ny, row / ny);
                ys.fill(grid.coord(1, j));
                zs.fill(grid.coord(2, k));
                f.eval_batch([&xs, ys, zs], out);
                progress.inc(1);
            },
        );
        progress.finish();
        Self::from_values(*grid, values)
    }

    /// Wrap values computed elsewhere (e.g. a volume read from disk), checking the
    /// length and that every value is finite.
    pub fn from_values(grid: Grid, values: Vec<f64>) -> Result<Samples> {
        check_dense(&grid)?;
        if values.len() != grid.num_vertices() {
            return Err(Error::Param(format!(
                "{} values for a grid of {} vertices",
                values.len(),
                grid.num_vertices()
            )));
        }
        if let Some(v) = crate::kernel::finite::first_non_finite(&values) {
            return Err(grid.not_finite(v, values[v]));
        }
        Ok(Samples { grid, values })
    }

    pub fn values(&self) -> &[f64] {
        &self.values
    }
    pub fn into_values(self) -> Vec<f64> {
        self.values
    }
}

impl Field for Samples {
    const SPARSE: bool = false;
    fn grid(&self) -> &Grid {
        &self.grid
    }
    #[inline(always)]
    fn value(&self, i: usize, j: usize, k: usize) -> f64 {
        self.values[self.grid.index(i, j, k)]
    }
    fn sign_row(&self, j: usize, k: usize, neg: &mut [u64], valid: &mut [u64]) {
        let n = self.grid.vertex_dims()[0];
        let b = self.grid.index(0, j, k);
        for (w, chunk) in self.values[b..b + n].chunks(64).enumerate() {
            let mut m = 0u64;
            for (t, &v) in chunk.iter().enumerate() {
                m |= ((v < 0.0) as u64) << t;
            }
            neg[w] = m;
            valid[w] = if chunk.len() == 64 {
                u64::MAX
            } else {
                (1u64 << chunk.len()) - 1
            };
        }
    }
}

/// log2 of the brick side (8 vertices).
const BRICK_SHIFT: usize = 3;

/// f at a chosen set of vertices, stored in bricks of 8×8×8 vertices (8×8 on a planar
/// grid): a brick is allocated only if one of its vertices was evaluated. Other vertices
/// read as `NaN`. Memory is one `u32` per brick of the grid plus the allocated bricks,
/// so grids far larger than [`MAX_DENSE_BYTES`] can be pruned and meshed.
#[derive(Clone, Debug)]
pub struct SparseSamples {
    grid: Grid,
    shift: [usize; 3],
    bricks: [usize; 3],
    table: Vec<u32>,
    pool: Vec<f64>,
    evaluated: usize,
}

impl SparseSamples {
    /// Evaluate f at the vertices `vertices` (flat indices, see [`Grid::index`];
    /// duplicates allowed), in parallel.
    pub fn evaluate(
        f: &dyn Implicit,
        grid: &Grid,
        vertices: &[u64],
        progress: &dyn Progress,
    ) -> Result<SparseSamples> {
        let mut s = SparseSamples::empty(grid)?;
        let mut masks = Vec::new();
        for &v in vertices {
            let [i, j, k] = grid.unindex(v as usize);
            s.mark(&mut masks, i, j, k);
        }
        s.fill(f, masks, progress)?;
        Ok(s)
    }

    /// Evaluate f at every vertex of the blocks `(lo, hi)` (inclusive vertex index
    /// ranges; overlaps allowed), in parallel.
    pub fn evaluate_blocks(
        f: &dyn Implicit,
        grid: &Grid,
        blocks: &[([usize; 3], [usize; 3])],
        progress: &dyn Progress,
    ) -> Result<SparseSamples> {
        let mut s = SparseSamples::empty(grid)?;
        let mut masks = Vec::new();
        for (lo, hi) in blocks {
            for k in lo[2]..=hi[2] {
                for j in lo[1]..=hi[1] {
                    for i in lo[0]..=hi[0] {
                        s.mark(&mut masks, i, j, k);
                    }
                }
            }
        }
        s.fill(f, masks, progress)?;
        Ok(s)
    }

    fn empty(grid: &Grid) -> Result<SparseSamples> {
        let shift = [
            BRICK_SHIFT,
            BRICK_SHIFT,
            if grid.dim() == 3 { BRICK_SHIFT } else { 0 },
        ];
        let vd = grid.vertex_dims();
        let bricks = [0, 1, 2].map(|a| (vd[a] + (1 << shift[a]) - 1) >> shift[a]);
        let nbricks = bricks.iter().map(|&b| b as u64).product::<u64>();
        if nbricks > u32::MAX as u64 / 2 {
            return Err(Error::TooLarge(format!(
                "{nbricks} bricks for a sparse grid (at most {})",
                u32::MAX / 2
            )));
        }
        Ok(SparseSamples {
            grid: *grid,
            shift,
            bricks,
            table: vec![u32::MAX; nbricks as usize],
            pool: Vec::new(),
            evaluated: 0,
        })
    }

    /// Mark vertex (i, j, k) for evaluation, allocating its brick (a 512-bit mask).
    fn mark(&mut self, masks: &mut Vec<[u64; 8]>, i: usize, j: usize, k: usize) {
        let b = self.brick(i, j, k);
        if self.table[b] == u32::MAX {
            self.table[b] = masks.len() as u32;
            masks.push([0; 8]);
        }
        let off = self.offset(i, j, k);
        masks[self.table[b] as usize][off >> 6] |= 1 << (off & 63);
    }

    /// Evaluate the marked vertices, bricks in parallel.
    fn fill(
        &mut self,
        f: &dyn Implicit,
        masks: Vec<[u64; 8]>,
        progress: &dyn Progress,
    ) -> Result<()> {
        let bsize = 1usize << (self.shift[0] + self.shift[1] + self.shift[2]);
        if masks.len() as u64 * bsize as u64 * 8 > MAX_DENSE_BYTES {
            return Err(Error::TooLarge(format!(
                "the pruned grid still needs {} bricks of {bsize} values",
                masks.len()
            )));
        }
        // Where each allocated brick sits in the grid.
        let mut origin = vec![[0usize; 3]; masks.len()];
        let [b0, b1, _] = self.bricks;
        for (b, &slot) in self.table.iter().enumerate() {
            if slot != u32::MAX {
                let (bi, bj, bk) = (b % b0, (b / b0) % b1, b / (b0 * b1));
                origin[slot as usize] = [
                    bi << self.shift[0],
                    bj << self.shift[1],
                    bk << self.shift[2],
                ];
            }
        }
        self.evaluated = masks
            .iter()
            .map(|m| m.iter().map(|w| w.count_ones() as usize).sum::<usize>())
            .sum();
        let mut pool = vec![f64::NAN; masks.len() * bsize];
        progress.start("sampling f at the kept vertices", masks.len() as u64);
        let grid = self.grid;
        let [s0, s1, _] = self.shift;
        // Per brick: gather the marked vertices' coordinates, evaluate them in one
        // batch call, scatter the values back (in offset order, as before).
        let bad = pool
            .par_chunks_mut(bsize)
            .zip(masks.par_iter().zip(origin.par_iter()))
            .map_init(
                || BrickBuf::new(bsize),
                |buf, (out, (mask, o))| {
                    buf.clear();
                    for (w, &word) in mask.iter().enumerate() {
                        let mut m = word;
                        while m != 0 {
                            let off = (w << 6) | m.trailing_zeros() as usize;
                            m &= m - 1;
                            let i = o[0] + (off & ((1 << s0) - 1));
                            let j = o[1] + ((off >> s0) & ((1 << s1) - 1));
                            let k = o[2] + (off >> (s0 + s1));
                            buf.push(off, grid.point(i, j, k));
                        }
                    }
                    let n = buf.offs.len();
                    f.eval_batch(
                        [&buf.p[0][..n], &buf.p[1][..n], &buf.p[2][..n]],
                        &mut buf.v[..n],
                    );
                    let mut bad = None;
                    for (&off, &x) in buf.offs.iter().zip(&buf.v[..n]) {
                        if !x.is_finite() && bad.is_none() {
                            let i = o[0] + (off & ((1 << s0) - 1));
                            let j = o[1] + ((off >> s0) & ((1 << s1) - 1));
                            let k = o[2] + (off >> (s0 + s1));
                            bad = Some((grid.index(i, j, k), x));
                        }
                        out[off] = x;
                    }
                    progress.inc(1);
                    bad
                },
            )
            .flatten()
            .min_by_key(|(v, _)| *v);
        progress.finish();
        if let Some((v, x)) = bad {
            return Err(grid.not_finite(v, x));
        }
        self.pool = pool;
        Ok(())
    }

    #[inline(always)]
    fn offset(&self, i: usize, j: usize, k: usize) -> usize {
        let [s0, s1, s2] = self.shift;
        let m = |s: usize| (1usize << s) - 1;
        (i & m(s0)) | ((j & m(s1)) << s0) | ((k & m(s2)) << (s0 + s1))
    }

    #[inline(always)]
    fn brick(&self, i: usize, j: usize, k: usize) -> usize {
        let [s0, s1, s2] = self.shift;
        (i >> s0) + self.bricks[0] * ((j >> s1) + self.bricks[1] * (k >> s2))
    }

    #[inline(always)]
    fn slot(&self, i: usize, j: usize, k: usize) -> Option<usize> {
        let b = self.table[self.brick(i, j, k)];
        if b == u32::MAX {
            return None;
        }
        let [s0, s1, s2] = self.shift;
        Some(((b as usize) << (s0 + s1 + s2)) | self.offset(i, j, k))
    }

    /// Number of vertices evaluated.
    pub fn evaluated(&self) -> usize {
        self.evaluated
    }
    /// Number of bricks allocated.
    pub fn bricks_allocated(&self) -> usize {
        self.pool.len() >> (self.shift[0] + self.shift[1] + self.shift[2])
    }
}

/// The marked vertices of one brick, gathered for a batch evaluation.
struct BrickBuf {
    offs: Vec<usize>,
    p: [Vec<f64>; 3],
    v: Vec<f64>,
}

impl BrickBuf {
    fn new(n: usize) -> BrickBuf {
        BrickBuf {
            offs: Vec::with_capacity(n),
            p: [0, 1, 2].map(|_| vec![0.0; n]),
            v: vec![0.0; n],
        }
    }
    fn clear(&mut self) {
        self.offs.clear();
    }
    fn push(&mut self, off: usize, q: [f64; 3]) {
        let n = self.offs.len();
        for (a, c) in self.p.iter_mut().zip(q) {
            a[n] = c;
        }
        self.offs.push(off);
    }
}

impl Field for SparseSamples {
    const SPARSE: bool = true;
    fn grid(&self) -> &Grid {
        &self.grid
    }
    fn sign_row(&self, j: usize, k: usize, neg: &mut [u64], valid: &mut [u64]) {
        let n = self.grid.vertex_dims()[0];
        let step = 1 << self.shift[0];
        // Whole bricks at a time: unallocated ones hold no values.
        for i0 in (0..n).step_by(step) {
            if self.table[self.brick(i0, j, k)] == u32::MAX {
                continue;
            }
            for i in i0..(i0 + step).min(n) {
                let v = self.value(i, j, k);
                neg[i >> 6] |= ((v < 0.0) as u64) << (i & 63);
                valid[i >> 6] |= ((!v.is_nan()) as u64) << (i & 63);
            }
        }
    }
    #[inline(always)]
    fn value(&self, i: usize, j: usize, k: usize) -> f64 {
        match self.slot(i, j, k) {
            Some(s) => self.pool[s],
            None => f64::NAN,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::implicit::Formula;
    use crate::mesher::NoProgress;

    #[test]
    fn near_cubic_cells_and_exact_corners() {
        let g = Grid::new(&Aabb::new([0.0, 0.0, 0.0], [2.0, 1.0, 0.5]).unwrap(), 8, 3).unwrap();
        assert_eq!(g.cells(), [8, 4, 2]);
        assert_eq!(g.point(8, 4, 2), [2.0, 1.0, 0.5]);
        assert_eq!(g.index(1, 2, 1), 1 + 9 * (2 + 5));
        assert_eq!(g.unindex(g.index(3, 1, 2)), [3, 1, 2]);
        let p = Grid::new(&Aabb::rect([-1.0, -1.0], [1.0, 1.0]), 4, 2).unwrap();
        assert_eq!(p.cells(), [4, 4, 0]);
        assert_eq!(p.vertex_dims(), [5, 5, 1]);
        assert!(Grid::new(&Aabb::rect([-1.0, -1.0], [1.0, 1.0]), 4, 3).is_err());
    }

    #[test]
    fn dense_sampling_and_errors() {
        let f = Formula::surface("x + 10*y + 100*z").unwrap();
        let g = Grid::new(&Aabb::new([0.0; 3], [2.0; 3]).unwrap(), 2, 3).unwrap();
        let s = Samples::sample(&f, &g, &NoProgress).unwrap();
        assert_eq!(s.value(1, 2, 1), 1.0 + 20.0 + 100.0);
        // Too large: refused before allocating.
        let big = Grid::new(&Aabb::cube(1.0), 4000, 3).unwrap();
        assert!(matches!(
            Samples::sample(&f, &big, &NoProgress),
            Err(Error::TooLarge(_))
        ));
        // Not finite: the message names the point.
        let h = Formula::surface("1/x").unwrap();
        let e = Samples::sample(&h, &g, &NoProgress).unwrap_err();
        assert!(matches!(e, Error::NotFinite(_)));
        assert!(e.to_string().contains("(0, 0, 0)"), "{e}");
    }

    #[test]
    fn sparse_reads_back_what_it_evaluated() {
        let f = Formula::surface("x + 10*y + 100*z").unwrap();
        let g = Grid::new(&Aabb::new([0.0; 3], [20.0; 3]).unwrap(), 20, 3).unwrap();
        let vs = vec![g.index(0, 0, 0) as u64, g.index(17, 9, 3) as u64];
        let s = SparseSamples::evaluate(&f, &g, &vs, &NoProgress).unwrap();
        assert_eq!(s.value(17, 9, 3), 17.0 + 90.0 + 300.0);
        assert_eq!(s.value(0, 0, 0), 0.0);
        assert!(s.value(1, 0, 0).is_nan());
        assert!(s.value(20, 20, 20).is_nan());
        assert_eq!(s.evaluated(), 2);
        assert_eq!(s.bricks_allocated(), 2);
    }
}
