//! The uncertified baselines: marching cubes ([`MarchingCubes`], `"mc"`), marching
//! tetrahedra ([`MarchingTetrahedra`], `"mt"`) and marching squares
//! ([`MarchingSquares`], `"ms"`).
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

pub use cubes::{marching_cubes, MarchingCubes};
pub use squares::{marching_squares, MarchingSquares};
pub use tets::{marching_tetrahedra, MarchingTetrahedra};

use crate::error::{Error, Result};
use crate::implicit::ops::crossing_t;
use crate::implicit::{Counted, Implicit};
use crate::kernel::geom::{lerp, Aabb};
use crate::lattice::grid::{Field, Grid, Samples, SignBits};
use crate::lattice::octree;
use crate::mesh::TriMesh;
use crate::mesher::options::{Crossing, MesherOptions};
use crate::mesher::{Certificate, Mesh, MeshOutput, Progress};
use rayon::prelude::*;
use serde_json::{json, Map, Value};

/// Default cells along the longest side of the domain.
pub const DEFAULT_RESOLUTION: usize = 64;
/// Default bisection tolerance, relative to the edge length.
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// Is there a sign change between two samples? (f == 0 is positive; a NaN sample, i.e.
/// a vertex pruning skipped, never gives a crossing.)
#[inline(always)]
pub(crate) fn crosses(a: f64, b: f64) -> bool {
    (a < 0.0 && b >= 0.0) || (a >= 0.0 && b < 0.0)
}

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
pub(crate) struct Scheme {
    /// Edge directions as bit masks (1 = +x, 2 = +y, 4 = +z; sums for diagonals). A
    /// grid edge is (lower vertex, direction).
    pub dirs: Vec<u8>,
    /// The cell's local edges: (corner of the lower end, index into `dirs`). Corner `c`
    /// is at offset `(c & 1, c >> 1 & 1, c >> 2 & 1)`.
    pub edges: Vec<(u8, u8)>,
    /// Per sign case (bit `c` set when corner `c` is negative): triangles as local edge
    /// triples, oriented so that normals point toward f > 0.
    pub cases: Vec<Vec<[u8; 3]>>,
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

/// How the crossing on an edge is placed.
#[derive(Clone, Copy)]
pub(crate) enum Place<'a> {
    Linear,
    Bisection(&'a dyn Implicit, f64),
}

/// What an extraction did.
pub(crate) struct Extracted {
    pub mesh: TriMesh,
    /// Cells with a sign change.
    pub cells_visited: u64,
}

#[inline(always)]
fn corner(c: u8) -> [usize; 3] {
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
                    let t = match place {
                        Place::Linear => crossing_t_linear(a, b),
                        Place::Bisection(f, tol) => {
                            crossing_t(f, p, a, q, b, Crossing::Bisection, tol)
                        }
                    };
                    out[n] = lerp(p, q, t);
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
                            for t in &scheme.cases[case] {
                                tris.push(t.map(|e| {
                                    let (c, d) = scheme.edges[e as usize];
                                    let o = corner(c);
                                    let map = if o[2] == 0 { &ids } else { &up };
                                    map[((j + o[1]) * nx + i + o[0]) * nd + d as usize]
                                }));
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

/// The statistics every grid mesher reports.
pub(crate) fn base_stats(grid: &Grid, p: &GridParams) -> Map<String, Value> {
    let mut s = Map::new();
    s.insert("grid_cells".into(), json!(grid.cells()));
    s.insert("grid_vertices".into(), json!(grid.num_vertices()));
    s.insert("cells".into(), json!(grid.num_cells()));
    s.insert(
        "crossing".into(),
        json!(match p.crossing {
            Crossing::Linear => "linear",
            Crossing::Bisection => "bisection",
        }),
    );
    s.insert("pruned".into(), json!(p.prune));
    s
}

/// Sample (dense or pruned) and run a 3D scheme: the body of `mc` and `mt`.
pub(crate) fn mesh_3d(
    name: &str,
    scheme: &Scheme,
    p: &GridParams,
    f: &dyn Implicit,
    domain: &Aabb,
    progress: &dyn Progress,
) -> Result<MeshOutput> {
    p.check()?;
    if f.dim() != 3 {
        return Err(Error::Param(format!(
            "'{name}' meshes surfaces f(x, y, z); this function is a curve (use 'ms')"
        )));
    }
    let grid = Grid::new(domain, p.resolution, 3)?;
    check_extract_size(&grid, scheme.dirs.len())?;
    let mut stats = base_stats(&grid, p);
    let bis = Counted::new(f);
    let place = match p.crossing {
        Crossing::Linear => Place::Linear,
        Crossing::Bisection => Place::Bisection(&bis, p.tolerance),
    };
    let ex = if p.prune {
        let (s, st) = octree::sample_pruned_with(f, &grid, p.leaf, progress)?;
        stats.insert("cells_pruned".into(), json!(st.cells_pruned));
        stats.insert(
            "interval_evaluations".into(),
            json!(st.interval_evaluations),
        );
        stats.insert("point_evaluations".into(), json!(st.point_evaluations));
        stats.insert("cells_kept".into(), json!(st.cells_kept));
        stats.insert("prune_leaf".into(), json!(p.leaf));
        progress.start("extracting", 0);
        extract(&s, scheme, place)?
    } else {
        let s = Samples::sample(f, &grid, progress)?;
        stats.insert("cells_pruned".into(), json!(0));
        stats.insert("interval_evaluations".into(), json!(0));
        stats.insert("point_evaluations".into(), json!(grid.num_vertices()));
        progress.start("extracting", 0);
        extract(&s, scheme, place)?
    };
    progress.finish();
    stats.insert("cells_visited".into(), json!(ex.cells_visited));
    stats.insert("crossing_evaluations".into(), json!(bis.counts().points));
    Ok(MeshOutput {
        mesh: Mesh::Surface(ex.mesh),
        certificate: Certificate::none(format!(
            "{name} proves nothing: it reads the signs of f at grid vertices only, so \
             components, handles and gaps smaller than a cell are missed or merged"
        )),
        stats,
    })
}

/// Check the function dimension against the mesher, for `from_options` users.
pub(crate) fn check_curve(name: &str, f: &dyn Implicit) -> Result<()> {
    if f.dim() != 2 {
        return Err(Error::Param(format!(
            "'{name}' meshes curves f(x, y); this function is a surface (use 'mc' or 'mt')"
        )));
    }
    Ok(())
}
