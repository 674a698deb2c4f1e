//! An incremental 3D Delaunay triangulation kernel (Bowyer–Watson insertion).
//!
//! # Design
//!
//! * **Far box.** The triangulation starts from the 8 corners of a cube of half-width
//!   10× the bounding radius of the domain, inserted first and flagged as *far
//!   vertices* ([`Delaunay::is_far`]). Every cell is then a finite tetrahedron, every
//!   Voronoi edge dual to an interior facet is a finite segment, and insertion never
//!   meets the special cases of an infinite (ghost) vertex. We chose this over a
//!   ghost vertex because the consumer of this kernel — restricted-Delaunay refinement
//!   of a surface inside a bounded domain — wants finite Voronoi edges it can
//!   intersect with the surface, and because every predicate stays a plain exact
//!   orientation / in-sphere test. The price: cells next to the convex hull of the
//!   input may differ from those of the Delaunay triangulation of the input alone
//!   (a hull tetrahedron whose circumsphere reaches a far corner); cells with no far
//!   vertex are Delaunay for the input plus the corners. Points inserted later must
//!   lie strictly inside the box.
//! * **Flat 32-bit arrays.** A cell is 4 vertex ids and 4 neighbour codes
//!   (`cell * 4 + facet`, the facet index in the neighbour), all `u32`, 32 bytes.
//!   Facet `i` is opposite vertex `i`; cells are positively oriented. Freed cell slots
//!   go on a free list and are reused. As in HXT (Marot, Pellerin and Remacle, "One
//!   machine, one minute, three billion tetrahedra", 2019), the cavity, its boundary
//!   and the small hash table that glues the new cells are scratch arrays reused
//!   across insertions: an insertion allocates nothing once they have grown. The
//!   "visited" marks of the cavity search are two spare bits of the cell record itself
//!   (as HXT does), so testing a neighbour touches one cache line, not two.
//! * **Exact, perturbed predicates** ([`predicates`]): a static float filter in front
//!   of Shewchuk's adaptive predicates, and the symbolic perturbation of Devillers and
//!   Teillaud ("Perturbations for Delaunay and weighted Delaunay 3D triangulations",
//!   2011), so cospherical and coplanar inputs (integer grids, points on a sphere)
//!   give a valid triangulation, independent of the insertion order.
//! * **Order and location** ([`order`], [`locate`]): BRIO rounds (Amenta, Choi and Rote,
//!   "Incremental constructions con BRIO", 2003) with a Hilbert-curve order inside each
//!   round; a visibility walk with a seeded random facet order (Devillers, Pion and
//!   Teillaud, "Walking in a triangulation", 2002) so runs are reproducible.
//! * **Validity** ([`check`]): orientation, local Delaunay property of every facet
//!   (same perturbation), neighbour symmetry, Euler characteristic, each input point
//!   present once.
//!
//! Bad input (NaN, infinities) is an error naming the point, never a panic;
//! duplicates are reported and not inserted.
pub mod check;
mod insert;
pub mod locate;
pub mod order;
pub mod predicates;
mod report;

pub use check::CheckReport;
pub use report::{
    build_report, circumcentre, circumcentre_terms, random_points, tet_mesh, write_vtk,
    DelaunayReport, ReportOptions, Sampler,
};

/// Index of a vertex: 0..8 are the far corners, then the bulk input in insertion order
/// (use [`Delaunay::vertex_of_input`] / [`Delaunay::input_index`]; storing points in
/// their spatially sorted insertion order keeps coordinate reads cache-local), then
/// vertices added by [`Delaunay::insert`] in the order they were added.
pub type VertexId = u32;
/// Index of a cell slot.
pub type CellId = u32;
/// "No cell / no neighbour".
pub const NONE: u32 = u32::MAX;
/// Number of far vertices.
pub const FAR: u32 = 8;
/// Vertex ids stay below 2³⁰: the top two bits of a cell's `v[3]` are the cavity
/// search's "in the cavity" / "tested, not in conflict" flags during one insertion
/// (cleared before it returns, so no caller ever sees them).
pub const MAX_VERTICES: u32 = 1 << 30;

/// One tetrahedron: vertices (positively oriented) and neighbour codes
/// (`cell * 4 + facet`, or [`NONE`] across the far box's hull).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C, align(32))]
pub struct Cell {
    pub v: [u32; 4],
    pub n: [u32; 4],
}

const DEAD: u32 = u32::MAX;

/// Why a point was not inserted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InsertError {
    /// The point equals this existing vertex.
    Duplicate(VertexId),
    /// A coordinate is NaN or infinite.
    NonFinite,
    /// A coordinate is outside the range where the predicates are exact
    /// ([`in_exact_range`]).
    OutOfRange,
    /// The point is not strictly inside the far box.
    OutsideDomain,
    /// The triangulation already holds 2³⁰ vertices (ids keep two spare bits for the
    /// insertion's cavity flags).
    TooMany,
}

/// The smallest magnitude of a nonzero coordinate, 2⁻¹⁶²: every coordinate is then a
/// multiple of 2⁻²¹⁴ (its last bit), every product of five coordinate differences (the
/// in-sphere determinant's degree) a multiple of 2⁻¹⁰⁷⁰, which the doubles hold exactly
/// down to their subnormals, so the adaptive predicates' error-free sums and products
/// lose nothing to underflow. Below it (a surface meshed at a scale of 1e-120) they did,
/// and the kernel panicked or gave an invalid triangulation.
pub const MIN_COORDINATE: f64 = 1.0 / (1u128 << 81) as f64 / (1u128 << 81) as f64;
/// The largest magnitude of a coordinate, 2¹⁵⁰: the far box (ten bounding radii) and
/// degree-5 products stay far from overflow.
pub const MAX_COORDINATE: f64 = (1u128 << 75) as f64 * (1u128 << 75) as f64;

const RANGE_MESSAGE: &str = "a coordinate is outside the range where the exact predicates \
     hold (0, or a magnitude from 2^-162 ≈ 1.7e-49 to 2^150 ≈ 1.4e45): rescale the input";

/// `x` is 0 or of a magnitude in [[`MIN_COORDINATE`], [`MAX_COORDINATE`]].
#[inline]
pub fn in_exact_range(x: f64) -> bool {
    x == 0.0 || (MIN_COORDINATE..=MAX_COORDINATE).contains(&x.abs())
}

impl std::fmt::Display for InsertError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            InsertError::Duplicate(v) => write!(f, "duplicate of vertex {v}"),
            InsertError::NonFinite => write!(f, "coordinate is not finite"),
            InsertError::OutOfRange => write!(f, "{RANGE_MESSAGE}"),
            InsertError::OutsideDomain => write!(f, "point is outside the far box"),
            InsertError::TooMany => write!(f, "too many vertices (2^30)"),
        }
    }
}

#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Boundary {
    pub v: [u32; 4],
    pub i: u32,
    pub outer: u32,
}

#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Slot {
    pub gen: u32,
    pub a: u32,
    pub b: u32,
    pub code: u32,
}

/// The triangulation. See the module documentation.
#[derive(Clone, Debug)]
pub struct Delaunay {
    pub(crate) pts: Vec<[f64; 3]>,
    pub(crate) cells: Vec<Cell>,
    pub(crate) free: Vec<u32>,
    /// Per vertex, a live cell incident to it, or NONE when not inserted.
    pub(crate) vcell: Vec<u32>,
    pub(crate) cavity: Vec<u32>,
    pub(crate) bnd: Vec<Boundary>,
    pub(crate) table: Vec<Slot>,
    pub(crate) gen: u32,
    pub(crate) rng: u64,
    pub(crate) last: u32,
    pub(crate) live: usize,
    /// Bulk input: vertex `FAR + r` is input point `input_of[r]`.
    pub(crate) input_of: Vec<u32>,
    /// Bulk input: input point `i` is vertex `vertex_of[i]`.
    pub(crate) vertex_of: Vec<u32>,
    /// Far box: lower and upper corner.
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

/// Result of bulk construction.
#[derive(Clone, Debug, Default)]
pub struct Bulk {
    /// `(input index, input index of the earlier equal point)`.
    pub duplicates: Vec<(usize, usize)>,
}

impl Delaunay {
    /// An empty triangulation (only the far box) for points inside the axis-aligned
    /// box `lo..hi`: the far cube has half-width 10× the box's half-diagonal.
    pub fn with_domain(lo: [f64; 3], hi: [f64; 3], seed: u64) -> Result<Self, crate::error::Error> {
        if !lo.iter().chain(hi.iter()).all(|x| x.is_finite()) || (0..3).any(|k| lo[k] > hi[k]) {
            return Err(crate::error::Error::Domain(format!(
                "delaunay domain {lo:?}..{hi:?} is not a finite box"
            )));
        }
        let c: [f64; 3] = std::array::from_fn(|k| 0.5 * (lo[k] + hi[k]));
        let r = ((0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>()).sqrt() * 0.5;
        let h = if r > 0.0 {
            10.0 * r
        } else {
            1.0f64.max(c.iter().fold(0.0f64, |m, x| m.max(x.abs())) * 1e-3)
        };
        let flo = c.map(|x| x - h);
        let fhi = c.map(|x| x + h);
        if !flo.iter().chain(fhi.iter()).all(|x| x.is_finite()) {
            return Err(crate::error::Error::Domain(
                "delaunay far box overflows".into(),
            ));
        }
        if let Some(x) = lo
            .iter()
            .chain(&hi)
            .chain(&flo)
            .chain(&fhi)
            .find(|x| !in_exact_range(**x))
        {
            return Err(crate::error::Error::Domain(format!(
                "delaunay domain {lo:?}..{hi:?} (far box corner coordinate {x:e}): {RANGE_MESSAGE}"
            )));
        }
        let mut t = Delaunay {
            pts: Vec::new(),
            cells: Vec::new(),
            free: Vec::new(),
            vcell: Vec::new(),
            cavity: Vec::new(),
            bnd: Vec::new(),
            table: Vec::new(),
            gen: 0,
            rng: seed ^ 0x5DEE_CE66_D1CE_0001,
            last: 0,
            live: 0,
            input_of: Vec::new(),
            vertex_of: Vec::new(),
            lo: flo,
            hi: fhi,
        };
        for k in 0..8u32 {
            let p = std::array::from_fn(|a| if k >> a & 1 == 1 { fhi[a] } else { flo[a] });
            t.pts.push(p);
            t.vcell.push(NONE);
        }
        t.init_box();
        Ok(t)
    }

    /// Build the triangulation of `points` (BRIO + Hilbert order from `seed`). Input
    /// point `i` becomes vertex [`Delaunay::vertex_of_input`]`(i)`; duplicates are
    /// listed in [`Bulk`] and not inserted (the first occurrence is). Errors on a
    /// non-finite coordinate, naming the point.
    pub fn from_points(
        points: &[[f64; 3]],
        seed: u64,
    ) -> Result<(Self, Bulk), crate::error::Error> {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for (i, p) in points.iter().enumerate() {
            if !p.iter().all(|x| x.is_finite()) {
                return Err(crate::error::Error::NotFinite(format!(
                    "delaunay input point {i} is {p:?}"
                )));
            }
            if !p.iter().all(|&x| in_exact_range(x)) {
                return Err(crate::error::Error::Domain(format!(
                    "delaunay input point {i} is {p:?}: {RANGE_MESSAGE}"
                )));
            }
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if points.is_empty() {
            lo = [0.0; 3];
            hi = [0.0; 3];
        }
        if points.len() as u64 + FAR as u64 >= MAX_VERTICES as u64 {
            return Err(crate::error::Error::TooLarge(format!(
                "{} points",
                points.len()
            )));
        }
        let mut t = Self::with_domain(lo, hi, seed)?;
        let order = order::brio_order(points, seed);
        t.pts.reserve(points.len());
        t.pts.extend(order.iter().map(|&i| points[i as usize]));
        t.vcell.resize(t.pts.len(), NONE);
        t.vertex_of = vec![0; points.len()];
        for (r, &i) in order.iter().enumerate() {
            t.vertex_of[i as usize] = FAR + r as u32;
        }
        t.input_of = order;
        // About 6.5 cells per vertex for random points.
        t.cells.reserve(points.len() * 13 / 2 + 64);
        let mut bulk = Bulk::default();
        for r in 0..points.len() as u32 {
            let v = FAR + r;
            match t.insert_vertex(v, t.last) {
                Ok(()) => {}
                Err(InsertError::Duplicate(w)) => bulk.duplicates.push((
                    t.input_of[r as usize] as usize,
                    t.input_of[(w - FAR) as usize] as usize,
                )),
                Err(e) => unreachable!("bulk insertion of point {}: {e}", t.input_of[r as usize]),
            }
        }
        t.first_occurrence_wins(&mut bulk);
        Ok((t, bulk))
    }

    /// The insertion order is random, so a later copy of a point may have been
    /// inserted first: swap the input labels so that the smallest input index of each
    /// point is the inserted vertex and the others are reported as its duplicates.
    fn first_occurrence_wins(&mut self, bulk: &mut Bulk) {
        use std::collections::HashMap;
        let mut groups: HashMap<usize, usize> = HashMap::new(); // inserted -> min index
        for &(i, w) in &bulk.duplicates {
            let m = groups.entry(w).or_insert(w);
            *m = (*m).min(i);
        }
        for (&w, &m) in &groups {
            if m < w {
                let (vw, vm) = (self.vertex_of[w], self.vertex_of[m]);
                self.vertex_of[w] = vm;
                self.vertex_of[m] = vw;
                self.input_of[(vw - FAR) as usize] = m as u32;
                self.input_of[(vm - FAR) as usize] = w as u32;
            }
        }
        for d in bulk.duplicates.iter_mut() {
            let m = groups[&d.1];
            if d.0 == m {
                d.0 = d.1; // the one inserted first is now the duplicate
            }
            d.1 = m;
        }
        bulk.duplicates.sort_unstable();
    }

    /// Insert `p`, walking from the last created cell. Returns the new vertex, or the
    /// vertex it duplicates (nothing is inserted then).
    pub fn insert(&mut self, p: [f64; 3]) -> Result<VertexId, InsertError> {
        let start = self.last;
        self.insert_from(p, start, false)
    }

    /// Insert `p` starting the cavity from `cell_hint`, a cell whose circumsphere is
    /// known to contain `p` (e.g. `p` on the Voronoi edge dual to one of its facets):
    /// no walk. If the hint is not a live cell in conflict with `p`, falls back to a
    /// walk from the hint.
    pub fn insert_in_conflict_with(
        &mut self,
        p: [f64; 3],
        cell_hint: CellId,
    ) -> Result<VertexId, InsertError> {
        self.insert_from(p, cell_hint, true)
    }

    fn insert_from(
        &mut self,
        p: [f64; 3],
        hint: CellId,
        conflict_hint: bool,
    ) -> Result<VertexId, InsertError> {
        if !p.iter().all(|x| x.is_finite()) {
            return Err(InsertError::NonFinite);
        }
        if !p.iter().all(|&x| in_exact_range(x)) {
            return Err(InsertError::OutOfRange);
        }
        if (0..3).any(|k| !(p[k] > self.lo[k] && p[k] < self.hi[k])) {
            return Err(InsertError::OutsideDomain);
        }
        if self.pts.len() as u64 >= MAX_VERTICES as u64 {
            return Err(InsertError::TooMany);
        }
        let v = self.pts.len() as u32;
        self.pts.push(p);
        self.vcell.push(NONE);
        let hint = if (hint as usize) < self.cells.len() && self.cells[hint as usize].v[0] != DEAD {
            hint
        } else {
            self.any_cell()
        };
        let r = if conflict_hint && self.in_conflict(hint, p) && self.vertex_of(hint, p).is_none() {
            self.dig(v, hint);
            Ok(())
        } else {
            self.insert_vertex(v, hint)
        };
        match r {
            Ok(()) => Ok(v),
            Err(e) => {
                self.pts.pop();
                self.vcell.pop();
                Err(e)
            }
        }
    }

    pub(crate) fn any_cell(&self) -> u32 {
        self.cells.iter().position(|c| c.v[0] != DEAD).unwrap() as u32
    }

    pub(crate) fn vertex_of(&self, c: u32, p: [f64; 3]) -> Option<u32> {
        self.cells[c as usize]
            .v
            .into_iter()
            .find(|&w| self.pts[w as usize] == p)
    }

    /// All vertex positions (far corners first); ids of points not inserted
    /// (duplicates) are in range but have no cell ([`Delaunay::is_inserted`]).
    pub fn points(&self) -> &[[f64; 3]] {
        &self.pts
    }
    pub fn point(&self, v: VertexId) -> [f64; 3] {
        self.pts[v as usize]
    }
    /// The vertex holding bulk input point `i` (inserted, or its duplicate slot).
    pub fn vertex_of_input(&self, i: usize) -> VertexId {
        self.vertex_of[i]
    }
    /// The bulk input index of vertex `v`; `None` for far vertices and for vertices
    /// added by [`Delaunay::insert`].
    pub fn input_index(&self, v: VertexId) -> Option<usize> {
        v.checked_sub(FAR)
            .and_then(|r| self.input_of.get(r as usize))
            .map(|&i| i as usize)
    }
    /// Number of bulk input points.
    pub fn num_inputs(&self) -> usize {
        self.input_of.len()
    }
    pub fn is_far(&self, v: VertexId) -> bool {
        v < FAR
    }
    pub fn is_inserted(&self, v: VertexId) -> bool {
        self.vcell[v as usize] != NONE
    }
    /// A live cell incident to `v`, if `v` is inserted.
    pub fn incident_cell(&self, v: VertexId) -> Option<CellId> {
        let c = self.vcell[v as usize];
        (c != NONE).then_some(c)
    }
    /// Number of live cells (including those with far vertices).
    pub fn num_cells(&self) -> usize {
        self.live
    }
    /// Number of cell slots (live or free); cell ids are below it.
    pub fn cell_capacity(&self) -> usize {
        self.cells.len()
    }
    pub fn is_live(&self, c: CellId) -> bool {
        (c as usize) < self.cells.len() && self.cells[c as usize].v[0] != DEAD
    }
    /// The ids of live cells.
    pub fn cells(&self) -> impl Iterator<Item = CellId> + '_ {
        self.cells
            .iter()
            .enumerate()
            .filter(|(_, c)| c.v[0] != DEAD)
            .map(|(i, _)| i as u32)
    }
    /// Live cells with no far vertex.
    pub fn finite_cells(&self) -> impl Iterator<Item = CellId> + '_ {
        self.cells
            .iter()
            .enumerate()
            .filter(|(_, c)| c.v[0] != DEAD && c.v.iter().all(|&v| v >= FAR))
            .map(|(i, _)| i as u32)
    }
    pub fn cell_vertices(&self, c: CellId) -> [VertexId; 4] {
        self.cells[c as usize].v
    }
    /// Neighbour across facet `i` (opposite vertex `i`) and the facet index on its
    /// side, or `None` across the far box's boundary.
    pub fn neighbor(&self, c: CellId, i: usize) -> Option<(CellId, usize)> {
        let n = self.cells[c as usize].n[i];
        (n != NONE).then_some((n >> 2, (n & 3) as usize))
    }
    /// Raw cell record (vertices and neighbour codes).
    pub fn cell(&self, c: CellId) -> &Cell {
        &self.cells[c as usize]
    }
    pub fn is_far_cell(&self, c: CellId) -> bool {
        self.cells[c as usize].v.iter().any(|&v| v < FAR)
    }
    /// Circumcentre of a cell (computed in floating point, not cached).
    pub fn circumcentre(&self, c: CellId) -> [f64; 3] {
        let v = self.cells[c as usize].v;
        circumcentre(v.map(|i| self.pts[i as usize]))
    }
    /// Each interior facet once, as `(cell, facet, other cell, its facet)` with
    /// `cell < other`; `finite_only` skips facets with a far vertex.
    pub fn facets(
        &self,
        finite_only: bool,
    ) -> impl Iterator<Item = (CellId, usize, CellId, usize)> + '_ {
        self.cells().flat_map(move |c| {
            let cell = self.cells[c as usize];
            (0..4).filter_map(move |i| {
                let n = cell.n[i];
                if n == NONE || (n >> 2) < c {
                    return None;
                }
                if finite_only && (0..4).any(|k| k != i && cell.v[k] < FAR) {
                    return None;
                }
                Some((c, i, n >> 2, (n & 3) as usize))
            })
        })
    }
    /// Heap bytes a triangulation of `n` points will hold, estimated before any work
    /// (for a refusal up front): [`Self::BYTES_PER_POINT`] per point.
    pub fn estimated_bytes(n: usize) -> u64 {
        (n as u64).saturating_mul(Self::BYTES_PER_POINT)
    }
    /// Heap per point of a finished triangulation, rounded up: 482 bytes measured by
    /// [`Self::memory_bytes`] on a million uniform points (about 6.5 cells of 32 bytes
    /// per point, with the arrays' spare capacity).
    pub const BYTES_PER_POINT: u64 = 500;
    /// Estimated heap bytes held by the triangulation.
    pub fn memory_bytes(&self) -> usize {
        self.pts.capacity() * 24
            + self.cells.capacity() * std::mem::size_of::<Cell>()
            + self.vcell.capacity() * 4
            + self.free.capacity() * 4
            + self.input_of.capacity() * 4
            + self.vertex_of.capacity() * 4
            + self.cavity.capacity() * 4
            + self.bnd.capacity() * std::mem::size_of::<Boundary>()
            + self.table.capacity() * std::mem::size_of::<Slot>()
    }
    /// Validity check (exact predicates): see [`check`].
    pub fn check(&self) -> CheckReport {
        check::check(self)
    }
}
