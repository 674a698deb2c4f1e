//! The uncertified baselines: marching cubes ([`MarchingCubes`], `"mc"`), marching
//! tetrahedra ([`MarchingTetrahedra`], `"mt"`) and marching squares
//! ([`MarchingSquares`], `"ms"`).
//!
//! **One mesher, three tables.** The three are one type, [`Marching`], over a cell
//! [`Table`] ([`Cubes`], [`Tetrahedra`], [`Squares`]): sampling, pruning, statistics and
//! the certificate are written once; the tables differ (the cube's 256 cases derived
//! from the face rule, the six Kuhn tetrahedra's, the square's 16 from the same face
//! rule), and so do the two extraction loops (the packed-sign, layer-parallel one for a
//! cube table, a plain one for squares).
//!
//! All three sample f once per vertex of a regular [`Grid`] (or, with `prune`, only at
//! the vertices of the cells interval arithmetic could not prove empty, see
//! [`crate::lattice::octree`]) and read nothing but the signs of those samples, plus the
//! values (or bisection) to place the crossings. So they prove nothing: features
//! between grid vertices (a thin tube, a narrow gap) are missed or merged.
//!
//! **Sign convention.** A vertex is *negative* when f < 0 and *positive* otherwise:
//! f == 0 counts as positive, so a zero sample puts the crossing vertex exactly on
//! that grid vertex (and may give zero-area triangles, never a crack).
//!
//! **Watertightness.** Every crossing vertex lives on a grid edge and is shared by the
//! cells around that edge (indexed by edge, not recomputed per cell). Marching cubes
//! connects the crossings of each cell face with one rule that depends only on the
//! signs of that face, "negative corners are separated" (on a face with four crossings,
//! each negative corner is cut off by its own segment), so the two cells sharing a face
//! draw the same segments, and chains each cell's segments into closed loops. The
//! output is a closed, oriented, edge-manifold triangle mesh for every sign pattern
//! (away from the domain boundary, where the surface is cut open).
//!
//! (The asymptotic decider would pick the segments of an ambiguous face from the
//! bilinear interpolant instead; it is as consistent, but needs values, not signs, so
//! the table could not be precomputed. These are baselines: the simple rule is kept.)
//!
//! Marching tetrahedra needs no rule: its tetrahedra triangulate the grid.
//!
//! **Determinism.** Vertices are numbered in a fixed order of their grid edges (layer,
//! row, direction, column) and triangles in the order of their cells, whatever the
//! thread count: the pruned and dense runs give identical meshes (tested).
//!
//! **Speed.** The extractor packs the signs into bit sets (one pass over the samples)
//! and finds sign changes 64 vertices at a time; values are read only at crossings.
//! On the 256³ torus it extracts in about a fifth of scikit-image's time
//! (`benches/marching.rs`).
pub mod cubes;
pub mod squares;
pub mod tets;

pub use cubes::{marching_cubes, Cubes, MarchingCubes};
pub use squares::{marching_squares, MarchingSquares, Squares};
pub use tets::{marching_tetrahedra, MarchingTetrahedra, Tetrahedra};

use crate::error::{Error, Result};
use crate::implicit::ops::{
    crossing_t, discontinuity_on_segment, edges_need_pole_check, sign_change_not_a_zero,
    DISCONTINUITY_DEPTH,
};
use crate::implicit::{Counted, Implicit};
use crate::kernel::geom::{lerp, Aabb};
use crate::lattice::grid::{Field, Grid, Samples, SignBits};
use crate::lattice::octree;
use crate::mesh::TriMesh;
use crate::mesher::options::{Crossing, MesherOptions};
use crate::mesher::{Certificate, Mesh, MeshOutput, Mesher, Progress};
use rayon::prelude::*;
use std::marker::PhantomData;

/// Default cells along the longest side of the domain.
pub const DEFAULT_RESOLUTION: usize = 64;
/// Default bisection tolerance, relative to the edge length.
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// The parameters every grid mesher here shares. Defaults: resolution 64, linear
/// interpolation of crossings (the classic algorithm), bisection tolerance 1e-6 of the
/// edge, no pruning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridParams {
    /// Cells along the longest side of the domain.
    pub resolution: usize,
    /// How crossings are placed on edges with a sign change.
    pub crossing: Crossing,
    /// Bisection tolerance, as a fraction of the edge length.
    pub tolerance: f64,
    /// Prune empty space with interval arithmetic before sampling.
    pub prune: bool,
    /// Side of the leaf blocks of the pruning descent, in cells (`--set leaf=N`,
    /// default [`octree::DEFAULT_LEAF`]): smaller leaves mean more interval and fewer
    /// point evaluations. Does not change the output.
    pub leaf: usize,
}

impl Default for GridParams {
    fn default() -> Self {
        GridParams {
            resolution: DEFAULT_RESOLUTION,
            crossing: Crossing::Linear,
            tolerance: DEFAULT_TOLERANCE,
            prune: false,
            leaf: octree::DEFAULT_LEAF,
        }
    }
}

impl GridParams {
    /// Reads `resolution`, `crossing`, `tolerance`, `prune` and `--set leaf=N` (other
    /// fields of `MesherOptions` do not apply to grid meshers and are ignored); rejects
    /// other `--set` keys.
    pub fn from_options(algo: &str, o: &MesherOptions) -> Result<Self> {
        o.check_keys(algo, &["leaf"])?;
        let d = GridParams::default();
        let p = GridParams {
            resolution: o.resolution.unwrap_or(d.resolution),
            crossing: o.crossing.unwrap_or(d.crossing),
            tolerance: o.tolerance.unwrap_or(d.tolerance),
            prune: o.prune,
            leaf: o.get("leaf")?.unwrap_or(d.leaf),
        };
        p.check()?;
        Ok(p)
    }
    pub(crate) fn check(&self) -> Result<()> {
        if self.resolution == 0 {
            return Err(Error::Param("resolution must be at least 1 cell".into()));
        }
        if self.leaf == 0 {
            return Err(Error::Param(
                "leaf=0: pruning leaves have at least 1 cell".into(),
            ));
        }
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(Error::Param(format!(
                "crossing tolerance {} must lie in (0, 1) (a fraction of the edge)",
                self.tolerance
            )));
        }
        Ok(())
    }
}

/// A triangulation scheme of a grid cell: marching cubes or the Kuhn tetrahedra.
pub struct Scheme {
    /// Edge directions as bit masks (1 = +x, 2 = +y, 4 = +z; sums for diagonals). A
    /// grid edge is (lower vertex, direction).
    pub(crate) dirs: Vec<u8>,
    /// The cell's local edges: (corner of the lower end, index into `dirs`). Corner `c`
    /// is at offset `(c & 1, c >> 1 & 1, c >> 2 & 1)`.
    pub(crate) edges: Vec<(u8, u8)>,
    /// Per sign case (bit `c` set when corner `c` is negative): triangles as local edge
    /// triples, oriented so that normals point toward f > 0.
    pub(crate) cases: Vec<Vec<[u8; 3]>>,
}

impl Scheme {
    /// The local edge joining corners `a` and `b` (`a` a bit-subset of `b`), added if new.
    pub(crate) fn edge(&mut self, a: u8, b: u8) -> u8 {
        let (lo, hi) = if a & b == a { (a, b) } else { (b, a) };
        debug_assert!(lo & hi == lo && lo != hi);
        let d = hi ^ lo;
        let di = match self.dirs.iter().position(|&x| x == d) {
            Some(i) => i,
            None => {
                self.dirs.push(d);
                self.dirs.len() - 1
            }
        } as u8;
        match self.edges.iter().position(|&e| e == (lo, di)) {
            Some(i) => i as u8,
            None => {
                self.edges.push((lo, di));
                (self.edges.len() - 1) as u8
            }
        }
    }
}

/// How the crossing on an edge with a sign change is placed.
#[derive(Clone, Copy)]
pub enum Place<'a> {
    /// Linear interpolation of the two samples.
    Linear,
    /// Bisection on f, to this tolerance (a fraction of the edge).
    Bisection(&'a dyn Implicit, f64),
}

/// The face rule of marching squares and of marching cubes' faces: on a square whose
/// corners, counter-clockwise, are negative where `neg` says, walk counter-clockwise and
/// join every crossing where the sign goes from positive to negative to the next
/// crossing. Yields `(m, m2)`: the side from corner `m` to `m + 1` is joined to side
/// `m2`, in increasing `m`. On a square with four crossings this cuts each negative
/// corner off by itself ("negative corners are separated"), the negative corner lying
/// on the segment's right.
pub(crate) fn face_rule(neg: [bool; 4]) -> impl Iterator<Item = (usize, usize)> {
    let cross = [0, 1, 2, 3].map(|m| neg[m] != neg[(m + 1) % 4]);
    (0..4)
        .filter(move |&m| !neg[m] && neg[(m + 1) % 4])
        .map(move |m| {
            let m2 = (1..4).map(|o| (m + o) % 4).find(|&m2| cross[m2]).unwrap();
            (m, m2)
        })
}

/// What an extraction did.
pub(crate) struct Extracted {
    pub mesh: TriMesh,
    /// Cells with a sign change.
    pub cells_visited: u64,
}

/// The offset of cell corner `c`: `(c & 1, c >> 1 & 1, c >> 2 & 1)`.
#[inline(always)]
pub(crate) fn corner(c: u8) -> [usize; 3] {
    [
        (c & 1) as usize,
        ((c >> 1) & 1) as usize,
        ((c >> 2) & 1) as usize,
    ]
}

/// Bits `i + s .. i + s + 64` of a row bit set (`s` is 0 or 1), for word `w`.
#[inline(always)]
fn word(row: &[u64], w: usize, s: usize) -> u64 {
    if s == 0 {
        row[w]
    } else {
        (row[w] >> 1) | (row.get(w + 1).copied().unwrap_or(0) << 63)
    }
}

/// Visit the crossing edges owned by vertex layer `k` (edges whose lower vertex is in
/// the layer), in the order that numbers them: rows `j`, then direction, then `i`.
/// Sign changes are found 64 vertices at a time on the packed sign bits.
#[inline]
fn scan_layer(
    bits: &SignBits,
    dims: [usize; 3],
    dirs: &[[usize; 3]],
    k: usize,
    mut visit: impl FnMut(usize, usize, usize),
) {
    let [_, ny, nz] = dims;
    for j in 0..ny {
        let (n1, v1) = (
            bits.row(&bits.neg, ny, j, k),
            bits.row(&bits.valid, ny, j, k),
        );
        for (d, o) in dirs.iter().enumerate() {
            let (jb, kb) = (j + o[1], k + o[2]);
            if jb >= ny || kb >= nz {
                continue;
            }
            let (n2, v2) = (
                bits.row(&bits.neg, ny, jb, kb),
                bits.row(&bits.valid, ny, jb, kb),
            );
            for w in 0..bits.words {
                // Bits past the row end are zero in `valid`, so no edge leaves the grid.
                let mut m = (n1[w] ^ word(n2, w, o[0])) & v1[w] & word(v2, w, o[0]);
                while m != 0 {
                    let i = (w << 6) | m.trailing_zeros() as usize;
                    m &= m - 1;
                    visit(i, j, d);
                }
            }
        }
    }
}

/// Refuse grids whose extraction would not fit in memory (checked before sampling).
fn check_extract_size(grid: &Grid, nd: usize) -> Result<()> {
    let [nx, ny, nz] = grid.vertex_dims();
    // Two id maps per worker.
    let map_bytes = (nx * ny * nd * 4) as u64;
    if map_bytes > 1 << 30 {
        return Err(Error::TooLarge(format!(
            "a layer of {nx} x {ny} vertices needs {} MB of edge maps",
            map_bytes >> 20
        )));
    }
    // The packed signs take 2 bits per vertex (plus row padding).
    let bits_bytes = ((nx / 64 + 1) as u64) * (ny as u64) * (nz as u64) * 16;
    if bits_bytes > 2 << 30 {
        return Err(Error::TooLarge(format!(
            "the sign bits of a {nx} x {ny} x {nz} vertex grid need {} MB (at most 2048)",
            bits_bytes >> 20
        )));
    }
    Ok(())
}

/// Extract the triangle mesh of f = 0 from a sampled 3D grid with a cell scheme.
/// The signs are packed into bits first (one pass over the samples); then two passes
/// over vertex layers, both parallel: count the crossing edges of each layer (giving
/// each layer its range of vertex numbers), then per layer place its crossings and
/// triangulate the cells above it, reading the numbers of the next layer's edges by
/// rescanning its sign bits (cheap) instead of storing a global edge map. Work beyond
/// the sign pass is proportional to the number of sign changes.
pub(crate) fn extract<F: Field>(field: &F, scheme: &Scheme, place: Place) -> Result<Extracted> {
    let grid = *field.grid();
    if grid.dim() != 3 {
        return Err(Error::Param("a 3D extractor needs a 3D grid".into()));
    }
    let dims = grid.vertex_dims();
    let [nx, ny, nz] = dims;
    let nd = scheme.dirs.len();
    let dirs: Vec<[usize; 3]> = scheme.dirs.iter().map(|&d| corner(d)).collect();
    check_extract_size(&grid, nd)?;
    let bits = SignBits::of(field);
    let counts: Vec<usize> = (0..nz)
        .into_par_iter()
        .map(|k| {
            let mut n = 0;
            scan_layer(&bits, dims, &dirs, k, |_, _, _| n += 1);
            n
        })
        .collect();
    let mut offsets = Vec::with_capacity(nz + 1);
    let mut total = 0usize;
    for &c in &counts {
        offsets.push(total);
        total += c;
    }
    if total >= u32::MAX as usize {
        return Err(Error::TooLarge(format!(
            "{total} mesh vertices (at most {})",
            u32::MAX - 1
        )));
    }
    let mut vertices = vec![[0.0f64; 3]; total];
    let mut chunks = Vec::with_capacity(nz);
    let mut rest = &mut vertices[..];
    for &c in &counts {
        let (a, b) = rest.split_at_mut(c);
        chunks.push(a);
        rest = b;
    }
    let per_layer: Vec<(Vec<[u32; 3]>, u64)> = chunks
        .into_par_iter()
        .enumerate()
        .map_init(
            // Id maps, reused across layers: only entries of crossing edges are read,
            // and those are written first, so stale entries never matter.
            || (vec![u32::MAX; nx * ny * nd], vec![u32::MAX; nx * ny * nd]),
            |(ids, up), (k, out)| {
                let mut n = 0usize;
                scan_layer(&bits, dims, &dirs, k, |i, j, d| {
                    ids[(j * nx + i) * nd + d] = (offsets[k] + n) as u32;
                    let o = dirs[d];
                    let (a, b) = (
                        field.value(i, j, k),
                        field.value(i + o[0], j + o[1], k + o[2]),
                    );
                    let p = grid.point(i, j, k);
                    let q = grid.point(i + o[0], j + o[1], k + o[2]);
                    out[n] = lerp(p, q, place.t(p, a, q, b));
                    n += 1;
                });
                if k + 1 == nz {
                    return (Vec::new(), 0);
                }
                // Ids of layer k + 1's edges, numbered exactly as its own task does.
                let mut m = 0usize;
                scan_layer(&bits, dims, &dirs, k + 1, |i, j, d| {
                    up[(j * nx + i) * nd + d] = (offsets[k + 1] + m) as u32;
                    m += 1;
                });
                let mut tris = Vec::new();
                let mut visited = 0u64;
                for j in 0..ny - 1 {
                    // Rows of the cell row, indexed dy + 2 dz (corner c = dx + 2 (dy + 2 dz)).
                    let rows = [(j, k), (j + 1, k), (j, k + 1), (j + 1, k + 1)];
                    let neg = rows.map(|(a, b)| bits.row(&bits.neg, ny, a, b));
                    let val = rows.map(|(a, b)| bits.row(&bits.valid, ny, a, b));
                    for w in 0..bits.words {
                        let (mut any, mut all, mut ok) = (0u64, u64::MAX, u64::MAX);
                        for r in 0..4 {
                            for s in 0..2 {
                                let x = word(neg[r], w, s);
                                any |= x;
                                all &= x;
                                ok &= word(val[r], w, s);
                            }
                        }
                        // Cells with both signs and all corners sampled (a cell with a
                        // skipped corner was pruned: one strict sign). `ok` is zero
                        // past the last cell of the row.
                        let mut m = any & !all & ok;
                        while m != 0 {
                            let i = (w << 6) | m.trailing_zeros() as usize;
                            m &= m - 1;
                            let mut case = 0usize;
                            for c in 0..8 {
                                let r = neg[c >> 1];
                                let x = i + (c & 1);
                                case |= ((r[x >> 6] >> (x & 63) & 1) as usize) << c;
                            }
                            visited += 1;
                            // (Per corner: `t.map` left its closure out of line, a
                            // call per corner.)
                            let id = |e: u8| {
                                let (c, d) = scheme.edges[e as usize];
                                let o = corner(c);
                                let map = if o[2] == 0 { &ids } else { &up };
                                map[((j + o[1]) * nx + i + o[0]) * nd + d as usize]
                            };
                            for t in &scheme.cases[case] {
                                tris.push([id(t[0]), id(t[1]), id(t[2])]);
                            }
                        }
                    }
                }
                (tris, visited)
            },
        )
        .collect();
    let ntris = per_layer.iter().map(|(t, _)| t.len()).sum();
    let mut triangles = Vec::with_capacity(ntris);
    let mut cells_visited = 0;
    for (t, v) in per_layer {
        triangles.extend_from_slice(&t);
        cells_visited += v;
    }
    Ok(Extracted {
        mesh: TriMesh::new(vertices, triangles),
        cells_visited,
    })
}

/// Refuse a sign change of the samples that is not a zero of f: on every grid edge
/// (directions `dirs`, as in [`Scheme::dirs`]) whose two samples differ in sign (f < 0
/// against f ≥ 0, the extractors' convention), f must be proven continuous
/// ([`discontinuity_on_segment`]), else the error names the edge and the point where it
/// is not: 1/(x − a) − 1 changes sign across its pole x = a, and a marching mesher
/// would mesh the pole plane as a second surface. A pole on a grid vertex is refused by
/// the sampling (f is not finite there). One decorated evaluation on the domain answers
/// for every edge when f is continuous there (every polynomial, and rational functions
/// whose poles lie outside); only the others pay a pass over the edges.
pub(crate) fn check_crossings_continuous<F: Field>(
    f: &dyn Implicit,
    field: &F,
    dirs: &[u8],
) -> Result<()> {
    let grid = *field.grid();
    let [nx, ny, nz] = grid.vertex_dims();
    let (lo, hi) = (grid.point(0, 0, 0), grid.point(nx - 1, ny - 1, nz - 1));
    if !Aabb::of_points(&[lo, hi]).is_some_and(|b| edges_need_pole_check(f, &b)) {
        return Ok(());
    }
    let offs: Vec<[usize; 3]> = dirs.iter().map(|&d| corner(d)).collect();
    let first = (0..nz).into_par_iter().find_map_first(|k| {
        for j in 0..ny {
            for i in 0..nx {
                let a = field.value(i, j, k);
                if a.is_nan() {
                    continue;
                }
                for o in &offs {
                    let (i2, j2, k2) = (i + o[0], j + o[1], k + o[2]);
                    if i2 >= nx || j2 >= ny || k2 >= nz {
                        continue;
                    }
                    let b = field.value(i2, j2, k2);
                    if b.is_nan() || (a < 0.0) == (b < 0.0) {
                        continue;
                    }
                    let (p, q) = (grid.point(i, j, k), grid.point(i2, j2, k2));
                    if let Some(x) = discontinuity_on_segment(f, p, q, DISCONTINUITY_DEPTH) {
                        let which = format!("grid vertices {i}, {j}, {k} and {i2}, {j2}, {k2}");
                        return Some(sign_change_not_a_zero(p, a, q, b, &which, x));
                    }
                }
            }
        }
        None
    });
    first.map_or(Ok(()), Err)
}

/// The linear-interpolation crossing parameter for a sign change (f == 0 at an end puts
/// the crossing there).
#[inline(always)]
pub(crate) fn crossing_t_linear(a: f64, b: f64) -> f64 {
    if a == 0.0 {
        0.0
    } else if b == 0.0 {
        1.0
    } else {
        (a / (a - b)).clamp(0.0, 1.0)
    }
}

impl Place<'_> {
    /// The parameter in [0, 1] of the crossing on the edge from `p` (sample `a`) to `q`
    /// (sample `b`).
    #[inline(always)]
    pub(crate) fn t(&self, p: [f64; 3], a: f64, q: [f64; 3], b: f64) -> f64 {
        match *self {
            Place::Linear => crossing_t_linear(a, b),
            Place::Bisection(f, tol) => crossing_t(f, p, a, q, b, Crossing::Bisection, tol),
        }
    }
}

/// The statistics every grid mesher reports.
/// What a marching run did, serialised field by field into the report's `stats` map.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MarchingStats {
    /// Cells per axis.
    pub grid_cells: [usize; 3],
    /// Lattice vertices of the grid.
    pub grid_vertices: usize,
    /// Cells of the grid.
    pub cells: usize,
    /// Where a crossing is placed on a sign-change edge: `linear` or `bisection`.
    pub crossing: &'static str,
    /// Was empty space pruned by interval arithmetic (`--prune`)?
    pub pruned: bool,
    /// Cells proven free of f = 0 by the pruning (0 without it).
    pub cells_pruned: u64,
    /// Interval evaluations spent pruning.
    pub interval_evaluations: u64,
    /// Evaluations of f at lattice vertices.
    pub point_evaluations: u64,
    /// Cells kept by the pruning (surfaces with `--prune` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cells_kept: Option<u64>,
    /// Leaf size of the pruning octree (surfaces with `--prune` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub prune_leaf: Option<usize>,
    /// Cells the extractor visited.
    pub cells_visited: u64,
    /// Evaluations of f spent placing crossings (bisection only; 0 for linear).
    pub crossing_evaluations: u64,
}

/// What makes a grid mesher marching cubes, tetrahedra or squares: its cell table and
/// its names. The three are one type, [`Marching`], over the three tables [`Cubes`],
/// [`Tetrahedra`] and [`Squares`].
pub trait Cells: Copy + Default + PartialEq + Send + Sync + 'static {
    /// The registry name (`"mc"`).
    const ALGO: &'static str;
    /// The name in messages and certificates (`"marching cubes"`).
    const TITLE: &'static str;
    /// The name of the mesher type, for `Debug` (`"MarchingCubes"`).
    const TYPE_NAME: &'static str;
    fn table() -> Table;
}

/// A cell table: the sign cases of a cube (triangles) or of a square (segments).
#[derive(Clone, Copy)]
pub enum Table {
    /// A triangulation scheme of the grid cube (surfaces).
    Cube(&'static Scheme),
    /// Per sign case of a square (bit `m` set when corner `m`, counter-clockwise from
    /// (0, 0), is negative): the sides `(m, m2)` the face rule joins (curves).
    Square(&'static [Vec<(u8, u8)>; 16]),
}

impl Table {
    /// 3 for surfaces, 2 for curves.
    pub fn dim(&self) -> usize {
        match self {
            Table::Cube(_) => 3,
            Table::Square(_) => 2,
        }
    }
    /// What, smaller than a cell, is missed or merged (for the certificate).
    fn misses(&self) -> &'static str {
        match self {
            Table::Cube(_) => "components, handles and gaps",
            Table::Square(_) => "components and necks",
        }
    }
    /// Refuse grids whose extraction would not fit in memory (before sampling).
    fn check_size(&self, grid: &Grid) -> Result<()> {
        match self {
            Table::Cube(s) => check_extract_size(grid, s.dirs.len()),
            Table::Square(_) => Ok(()),
        }
    }
    /// Extract f = 0 from a sampled grid: the mesh and the cells with a sign change.
    /// First, a sign change of the samples across a pole of `f` is refused
    /// ([`check_crossings_continuous`]).
    fn extract<F: Field>(&self, f: &dyn Implicit, field: &F, place: Place) -> Result<(Mesh, u64)> {
        let dirs: &[u8] = match self {
            Table::Cube(s) => &s.dirs,
            Table::Square(_) => &[1, 2],
        };
        check_crossings_continuous(f, field, dirs)?;
        match self {
            Table::Cube(s) => {
                let ex = extract(field, s, place)?;
                Ok((Mesh::Surface(ex.mesh), ex.cells_visited))
            }
            Table::Square(cases) => {
                let (curve, visited) = squares::extract(field, cases, place)?;
                Ok((Mesh::Curve(curve), visited))
            }
        }
    }
}

/// A marching mesher over the cell table `C`: [`MarchingCubes`], [`MarchingTetrahedra`]
/// or [`MarchingSquares`]. Defaults ([`GridParams::default`]): 64 cells along the
/// longest side, linear interpolation, no pruning.
#[derive(Clone, Copy, Default, PartialEq)]
pub struct Marching<C> {
    pub params: GridParams,
    cells: PhantomData<C>,
}

impl<C: Cells> std::fmt::Debug for Marching<C> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct(C::TYPE_NAME)
            .field("params", &self.params)
            .finish()
    }
}

impl<C: Cells> Marching<C> {
    pub fn new() -> Self {
        Self::default()
    }
    /// Cells along the longest side of the domain (default 64).
    pub fn resolution(mut self, n: usize) -> Self {
        self.params.resolution = n;
        self
    }
    /// Linear interpolation (default) or bisection on f.
    pub fn crossing(mut self, c: Crossing) -> Self {
        self.params.crossing = c;
        self
    }
    /// Bisection tolerance, as a fraction of the edge (default 1e-6).
    pub fn tolerance(mut self, t: f64) -> Self {
        self.params.tolerance = t;
        self
    }
    /// Prune empty space with intervals (default false). Same output, fewer evaluations.
    pub fn prune(mut self, p: bool) -> Self {
        self.params.prune = p;
        self
    }
    /// Side of the pruning descent's leaf blocks, in cells (default 4).
    pub fn leaf(mut self, n: usize) -> Self {
        self.params.leaf = n;
        self
    }
    /// From `--resolution`, `--crossing`, `--tolerance`, `--prune`, `--set leaf=N`.
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Ok(Marching {
            params: GridParams::from_options(C::ALGO, o)?,
            cells: PhantomData,
        })
    }
}

impl<C: Cells> Mesher for Marching<C> {
    fn name(&self) -> &'static str {
        C::ALGO
    }
    fn dim(&self) -> usize {
        C::table().dim()
    }
    /// Sample (dense or pruned) and extract with the table.
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        let p = &self.params;
        let table = C::table();
        p.check()?;
        crate::mesher::check_input(f, domain, table.dim(), C::ALGO)?;
        let grid = Grid::new(domain, p.resolution, table.dim())?;
        table.check_size(&grid)?;
        let bis = Counted::new(f);
        let place = match p.crossing {
            Crossing::Linear => Place::Linear,
            Crossing::Bisection => Place::Bisection(&bis, p.tolerance),
        };
        // The surface extractors also report the pruning's kept cells and leaf size, and
        // extraction as a progress phase; marching squares reports neither (as before).
        let surface = table.dim() == 3;
        let mut stats = MarchingStats {
            grid_cells: grid.cells(),
            grid_vertices: grid.num_vertices(),
            cells: grid.num_cells(),
            crossing: match p.crossing {
                Crossing::Linear => "linear",
                Crossing::Bisection => "bisection",
            },
            pruned: p.prune,
            cells_pruned: 0,
            interval_evaluations: 0,
            point_evaluations: grid.num_vertices() as u64,
            cells_kept: None,
            prune_leaf: None,
            cells_visited: 0,
            crossing_evaluations: 0,
        };
        let (mesh, visited) = if p.prune {
            let (s, st) = octree::sample_pruned_with(f, &grid, p.leaf, progress)?;
            stats.cells_pruned = st.cells_pruned;
            stats.interval_evaluations = st.interval_evaluations;
            stats.point_evaluations = st.point_evaluations;
            if surface {
                stats.cells_kept = Some(st.cells_kept);
                stats.prune_leaf = Some(p.leaf);
                progress.start("extracting", 0);
            }
            table.extract(f, &s, place)?
        } else {
            let s = Samples::sample(f, &grid, progress)?;
            if surface {
                progress.start("extracting", 0);
            }
            table.extract(f, &s, place)?
        };
        if surface {
            progress.finish();
        }
        stats.cells_visited = visited;
        stats.crossing_evaluations = bis.counts().points;
        let stats = crate::mesher::stats_map(&stats);
        Ok(MeshOutput {
            mesh,
            certificate: Certificate::none(format!(
                "{} proves nothing: it reads the signs of f at grid vertices only, so {} \
                 smaller than a cell are missed or merged",
                C::TITLE,
                table.misses()
            )),
            stats,
            angles: None,
        })
    }
}
