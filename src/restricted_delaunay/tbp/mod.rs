//! The topological ball property (TBP) of a point set P with respect to S = {f = 0},
//! checked with interval arithmetic: the chapter "Meshing of Surfaces" (Boissonnat,
//! Cohen-Steiner, Mourrain, Rote and Vegter, 2007), §1.3.2, tests (1)–(4) run as
//! *checks* (nothing is inserted). When every check passes, Theorem 5 of the chapter
//! (Edelsbrunner and Shah's closed-ball property) says the Delaunay triangulation of
//! P restricted by S is **homeomorphic** to S. Not isotopic: whether the TBP implies
//! isotopy for surfaces is the chapter's open Research Problem 4 (§1.6); nothing here
//! claims it. P need not lie on S, and no local feature size is needed.
//!
//! Hypotheses, each checked (a failure names the Voronoi face and why):
//! * **Set-up.** f has rigorous interval enclosures; 0 ∉ □f on the six faces of the
//!   domain D, so S ⊂ int D and S is closed; the kernel's triangulation passes its
//!   exact check; every vertex lies in D, so the far-box corners' Voronoi cells miss D
//!   ([`super::restricted::far_lemma`]) and the Voronoi faces of P meeting S are those
//!   of P with the corners added.
//! * **(0)+(1) Voronoi vertices and edges.** Every dual segment (interval
//!   circumcentres) meets S at most once, by certified root isolation: each crossing
//!   in a piece where 0 ∉ □(∇f·e) (transversal), the end signs proven (no Voronoi
//!   vertex on S), nothing undecided.
//! * **(2) 2-manifold.** Every Delaunay edge pq is in 0 or 2 restricted facets
//!   (the Voronoi facet F_pq has 0 or 2 crossing edges) and the restricted link of
//!   every vertex is one cycle or empty. Then S ∩ ∂V(p) is one cycle or empty.
//! * **(3) Voronoi facets.** For each F = F_pq (in the bisector plane H of p, q), a
//!   cover of F ∩ D by boxes on which 0 ∉ □f, or f is C^∞ and 0 ∉ □(∇f·d) for a
//!   direction d exactly in H (d = w × (q − p) enclosed in intervals). Then S meets H
//!   transversally on F (the in-plane gradient is non-zero) and no point of S ∩ F
//!   has tangent d, so S ∩ F has no closed curve (a closed curve has a point extreme
//!   in the in-plane direction ⊥ d, where its tangent is d); each of its arcs ends
//!   on two crossings of ∂F, crossing the edges transversally (by (1)), so with 0 or
//!   2 crossings S ∩ F is empty or one arc whose boundary is S ∩ ∂F.
//! * **(4) Voronoi cells.** For each V(p), a cover of V(p) ∩ D by boxes on which 0 ∉
//!   □f, or f is C^∞ and 0 ∉ □(∇f·d) (d = ∇f(p), the chapter's choice), or — for boxes
//!   strictly inside V(p) — 0 ∉ □det(H d, d′, ∇f) (equation (1.5)). Then the
//!   silhouette Σ = {f = 0, ∇f·d = 0} misses ∂V(p), is a smooth curve inside V(p)
//!   (its gradients ∇f and H d are independent where the determinant is non-zero)
//!   and has no point critical in direction d′; a compact curve without boundary has
//!   such points, so Σ ∩ V(p) = ∅. By the Silhouette Lemma (Lemma 6), the component of
//!   M = S ∩ V(p) bounded by the cycle of (2) is a disk, and M has no closed component
//!   (a closed surface has silhouette points in every direction).
//!
//! Every point of S lies in some cell, and every box that meets S is accepted by a
//! criterion that proves ∇f ≠ 0 there, so the checks also prove S a smooth surface.
//! Degenerate (cospherical) inputs are triangulated with the kernel's symbolic
//! perturbation; the checks' strict inequalities are open conditions, so they hold
//! for the perturbed point set whose Delaunay triangulation the kernel built.
pub mod cover;

use super::restricted::{self, Scan};
use crate::implicit::critical::{boundary_clear, Bx};
use crate::implicit::ops::{mean_value, SegmentBudget};
use crate::implicit::{IBox, Implicit};
use crate::kernel::delaunay::{CellId, Delaunay, VertexId};
use crate::kernel::geom::{cross, dist, dot, Aabb};
use cover::{cover, no_silhouette, no_tangency, pt, Cover, CoverBudget, HalfSpace, Known, Region};
use inari::Interval;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::HashMap;

/// The chapter's tests, in its order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Test {
    /// The set-up hypotheses (domain boundary, Delaunay check, far corners, rigour).
    Setup,
    /// (1): a Voronoi edge meets S at most once, transversally, not at an end.
    Edge,
    /// (2): the restricted triangulation is a 2-manifold.
    Manifold,
    /// (3): a Voronoi facet meets S in ∅ or one arc.
    Facet,
    /// (4): a Voronoi cell meets S in ∅ or a disk.
    Cell,
}

/// One Voronoi face where the topological ball property was not proven.
#[derive(Clone, Debug, Serialize)]
pub struct Failure {
    pub test: Test,
    /// The dual Delaunay simplex: 3 sites for a Voronoi edge, 2 for a facet, 1 for a
    /// cell (kernel vertex ids; empty for set-up failures).
    pub sites: Vec<VertexId>,
    /// A point where it failed (a crossing, the centre of the undecided box, ...);
    /// not necessarily on S.
    pub point: [f64; 3],
    pub reason: String,
    /// Other points near the failure a refinement may try (for an undecided Voronoi
    /// edge: the float circumcentres of its two cells).
    #[serde(skip)]
    pub alternatives: Vec<[f64; 3]>,
}

/// Limits of the checks.
#[derive(Clone, Copy, Debug)]
pub struct TbpOptions {
    pub cover: CoverBudget,
    pub segment: SegmentBudget,
    /// Directions tried per Voronoi facet / cell before it is reported.
    pub directions: usize,
    /// Skip the later tests once one fails (the refinement driver's use: its next
    /// insertions come from the first failing test).
    pub stop_early: bool,
    /// Stop at this instant: the Voronoi facets and cells not yet checked are not
    /// proven, and the tests they belong to are reported as not run
    /// ([`TbpReport::timed_out`]). `None`: no time limit.
    pub deadline: Option<std::time::Instant>,
}

impl Default for TbpOptions {
    fn default() -> Self {
        TbpOptions {
            cover: CoverBudget::default(),
            segment: SegmentBudget::default(),
            directions: 3,
            stop_early: false,
            deadline: None,
        }
    }
}

/// What the checks found.
#[derive(Clone, Debug, Default, Serialize)]
pub struct TbpReport {
    /// Every check passed: the restricted triangulation is homeomorphic to S (Thm 5).
    pub holds: bool,
    pub rigorous: bool,
    pub boundary_clear: bool,
    pub delaunay_valid: bool,
    pub far_lemma: bool,
    pub voronoi_edges: usize,
    pub voronoi_facets: usize,
    pub voronoi_cells: usize,
    pub restricted_facets: usize,
    /// Failures per test (all of them; the list below is the same, possibly cut).
    pub edge_failures: usize,
    pub manifold_failures: usize,
    pub facet_failures: usize,
    pub cell_failures: usize,
    /// Boxes of the facet and cell covers.
    pub boxes: u64,
    /// Tests not run, or not run on every face: because an earlier one failed
    /// (`stop_early`), or because the deadline passed (`timed_out`).
    pub skipped: Vec<Test>,
    /// The deadline ([`TbpOptions::deadline`]) passed before every test had run on
    /// every face: the tests in `skipped` from the first cut on are incomplete.
    pub timed_out: bool,
    /// Seconds: the exact Delaunay check, (1) edges, (2) manifold, (3) facets, (4)
    /// cells. The check runs beside (1) and (2) beside (3) (unless `stop_early`): the
    /// entries of (1) and (3) are the wall time of both together.
    pub seconds: [f64; 5],
}

/// The checks' result: the report, the certified restricted triangulation (every
/// dual segment from interval circumcentres) and every failure.
pub struct Tbp {
    pub report: TbpReport,
    pub rdt: Scan,
    pub failures: Vec<Failure>,
}

/// Voronoi facets and cells already proven, keyed by their exact combinatorics (the
/// sites and the vertex sets of the dual cells, which fix the face and its vertex
/// enclosures): a refinement driver re-checks only the faces its insertions changed.
#[derive(Clone, Debug)]
pub struct TbpCache {
    proven: std::collections::HashSet<Vec<u32>>,
    /// `false`: a one-off check ([`check`]) that neither reads nor fills the cache, so
    /// the faces' keys are not built.
    keep: bool,
}

impl Default for TbpCache {
    fn default() -> Self {
        TbpCache {
            proven: Default::default(),
            keep: true,
        }
    }
}

impl TbpCache {
    fn key(&self, t: &Delaunay, sites: &[VertexId], cells: &[CellId]) -> Vec<u32> {
        if self.keep {
            face_key(t, sites, cells)
        } else {
            Vec::new()
        }
    }
    fn proven(&self, k: &[u32]) -> bool {
        self.keep && self.proven.contains(k)
    }
}

fn face_key(t: &Delaunay, sites: &[VertexId], cells: &[CellId]) -> Vec<u32> {
    let mut cs: Vec<[u32; 4]> = cells
        .iter()
        .map(|&c| {
            let mut v = t.cell_vertices(c);
            v.sort_unstable();
            v
        })
        .collect();
    cs.sort_unstable();
    let mut k = Vec::with_capacity(1 + sites.len() + 4 * cs.len());
    k.push(sites.len() as u32);
    k.extend_from_slice(sites);
    k.extend(cs.into_iter().flatten());
    k
}

/// Cells around each Delaunay edge of two non-far vertices, and the cells incident to
/// each vertex.
struct Adjacency {
    cells_of: Vec<Vec<CellId>>,
    /// The edges (a < b), sorted; the cells around edge i are
    /// `rings[start[i]..start[i + 1]]`, in the kernel's cell order.
    edges: Vec<(VertexId, VertexId)>,
    start: Vec<usize>,
    rings: Vec<CellId>,
}

impl Adjacency {
    fn ring(&self, i: usize) -> &[CellId] {
        &self.rings[self.start[i]..self.start[i + 1]]
    }
}

fn adjacency(t: &Delaunay) -> Adjacency {
    let n = t.points().len();
    let mut cells_of: Vec<Vec<CellId>> = vec![Vec::new(); n];
    let mut pairs: Vec<((VertexId, VertexId), CellId)> = Vec::new();
    for c in t.cells() {
        let v = t.cell_vertices(c);
        for &a in &v {
            cells_of[a as usize].push(c);
        }
        for i in 0..4 {
            for j in i + 1..4 {
                let (a, b) = (v[i].min(v[j]), v[i].max(v[j]));
                if !t.is_far(a) && !t.is_far(b) {
                    pairs.push(((a, b), c));
                }
            }
        }
    }
    // A stable sort by edge keeps each ring in the kernel's cell order.
    pairs.par_sort_by_key(|x| x.0);
    let mut edges = Vec::new();
    let mut start = Vec::new();
    let mut rings = Vec::with_capacity(pairs.len());
    for (k, &(e, c)) in pairs.iter().enumerate() {
        if k == 0 || pairs[k - 1].0 != e {
            edges.push(e);
            start.push(k);
        }
        rings.push(c);
    }
    start.push(rings.len());
    Adjacency {
        cells_of,
        edges,
        start,
        rings,
    }
}

fn hull(boxes: &[IBox]) -> IBox {
    std::array::from_fn(|k| {
        let lo = boxes
            .iter()
            .map(|b| b[k].inf())
            .fold(f64::INFINITY, f64::min);
        let hi = boxes
            .iter()
            .map(|b| b[k].sup())
            .fold(f64::NEG_INFINITY, f64::max);
        Interval::try_from((lo, hi)).unwrap_or(Interval::ENTIRE)
    })
}

fn clip(x: &IBox, d: &IBox) -> Option<IBox> {
    let mut out = *x;
    for k in 0..3 {
        let lo = x[k].inf().max(d[k].inf());
        let hi = x[k].sup().min(d[k].sup());
        if lo > hi {
            return None;
        }
        out[k] = Interval::try_from((lo, hi)).ok()?;
    }
    Some(out)
}

fn mid(x: &IBox) -> [f64; 3] {
    [x[0].mid(), x[1].mid(), x[2].mid()]
}

fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = dot(v, v).sqrt();
    (n > 1e-300 && n.is_finite()).then(|| v.map(|x| x / n))
}

fn icross(a: &[Interval; 3], b: &[Interval; 3]) -> [Interval; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A vector not parallel to `d`: the cross product with the axis least aligned to it.
fn transverse(d: [f64; 3]) -> [f64; 3] {
    let k = (0..3)
        .min_by(|&a, &b| d[a].abs().total_cmp(&d[b].abs()))
        .unwrap_or(0);
    let mut e = [0.0; 3];
    e[k] = 1.0;
    cross(d, e)
}

/// Vertex boxes (interval circumcentres) of the cells; `None` when one is not enclosed.
fn vertex_boxes(cc: &[Option<IBox>], cells: &[CellId]) -> Option<Vec<IBox>> {
    cells.iter().map(|&c| cc[c as usize]).collect()
}

/// The sites other than `skip` of `cells`, each once.
fn other_sites(t: &Delaunay, cells: &[CellId], skip: &[VertexId]) -> Vec<VertexId> {
    let mut s: Vec<VertexId> = cells
        .iter()
        .flat_map(|&c| t.cell_vertices(c))
        .filter(|v| !skip.contains(v))
        .collect();
    s.sort_unstable();
    s.dedup();
    s
}

struct FaceResult {
    failure: Option<Failure>,
    boxes: u64,
}

/// Fold the checked faces into the failures and the set of proven faces; returns the
/// boxes they used.
fn record(
    results: Vec<(Vec<u32>, FaceResult)>,
    failures: &mut Vec<Failure>,
    cache: &mut TbpCache,
) -> u64 {
    let mut boxes = 0;
    for (k, x) in results {
        boxes += x.boxes;
        match x.failure {
            Some(x) => failures.push(x),
            None if cache.keep => {
                cache.proven.insert(k);
            }
            None => {}
        }
    }
    boxes
}

/// Where the search over a Voronoi face (facet or cell) starts.
enum Start {
    /// The hull of its vertices' enclosures, clipped to the domain: search it. With the
    /// enclosures computed on it by the pre-test (∇f and the mean-value form of f),
    /// which the first box of each cover (the start box itself) reuses.
    Search(IBox, Option<Known>),
    /// Settled at once: the face misses the domain (0 boxes), or one enclosure over the
    /// start box excludes S (1 box; most faces are far from S).
    Settled(FaceResult),
    /// A vertex of the face (a sliver's circumcentre) could not be enclosed.
    Unenclosed,
}

/// Where the searches over many Voronoi faces start (each face given by its dual
/// cells). One batched natural enclosure of f over each clipped start box settles the
/// faces far from S; on the others the tighter mean-value enclosure ([`enclose`]) is
/// tried before the search. Both are enclosures: either proving 0 ∉ □f settles a face.
fn start_boxes(
    f: &dyn Implicit,
    cc: &[Option<IBox>],
    faces: &[&[CellId]],
    dbox: &IBox,
) -> Vec<Start> {
    let settled = |boxes| {
        Start::Settled(FaceResult {
            failure: None,
            boxes,
        })
    };
    let mut starts: Vec<Start> = faces
        .iter()
        .map(|cells| match vertex_boxes(cc, cells) {
            None => Start::Unenclosed,
            Some(vb) => match clip(&hull(&vb), dbox) {
                None => settled(0),
                Some(b) => Start::Search(b, None),
            },
        })
        .collect();
    let search: Vec<IBox> = starts
        .iter()
        .filter_map(|x| match x {
            Start::Search(b, _) => Some(*b),
            _ => None,
        })
        .collect();
    let mut natural = vec![Interval::EMPTY; search.len()];
    f.eval_interval_batch(&search, &mut natural);
    let mut k = 0;
    for x in starts.iter_mut() {
        if let Start::Search(b, known) = x {
            let n = natural[k];
            k += 1;
            if cover::excl(n) {
                *x = settled(1);
                continue;
            }
            // `enclose`, with its gradient kept for the covers.
            let dv = f.grad_interval(b);
            let fv = mean_value(f, b, &dv);
            if cover::excl(fv) {
                *x = settled(1);
            } else {
                *known = Some(Known { dv, fv });
            }
        }
    }
    starts
}

/// Try the candidate directions in turn (the first `tries` of them that normalise to
/// unit vectors, at least one) until `cover_in` covers the face for one; the boxes of
/// every cover tried are summed. `Ok(boxes)`, or `Err((boxes, centre of the last
/// failed box))` when none covers.
fn first_direction_that_covers(
    cands: Vec<[f64; 3]>,
    tries: usize,
    mut cover_in: impl FnMut([f64; 3]) -> Cover,
) -> Result<u64, (u64, Option<[f64; 3]>)> {
    let mut boxes = 0u64;
    let mut last = None;
    for d in cands.into_iter().filter_map(unit).take(tries.max(1)) {
        let c = cover_in(d);
        boxes += c.boxes as u64;
        if c.ok {
            return Ok(boxes);
        }
        last = c.failed;
    }
    Err((boxes, last.map(|x| mid(&x))))
}

/// Faces per batch of [`start_boxes`] (and per parallel task).
const CHUNK: usize = 64;

#[allow(clippy::too_many_arguments)]
fn check_facet(
    t: &Delaunay,
    f: &dyn Implicit,
    (p, q): (VertexId, VertexId),
    ring: &[CellId],
    start: Start,
    crossings: &[[f64; 3]],
    o: &TbpOptions,
) -> FaceResult {
    let fail = |point: [f64; 3], reason: String, boxes| FaceResult {
        failure: Some(Failure {
            test: Test::Facet,
            sites: vec![p, q],
            point,
            reason,
            alternatives: Vec::new(),
        }),
        boxes,
    };
    let (pp, qp) = (t.point(p), t.point(q));
    let (start, known) = match start {
        Start::Search(b, known) => (b, known),
        Start::Settled(r) => return r,
        Start::Unenclosed => {
            return fail(
                crate::kernel::geom::lerp(pp, qp, 0.5),
                "a vertex of the Voronoi facet (a sliver's circumcentre) could not be enclosed"
                    .into(),
                0,
            )
        }
    };
    let hs: Vec<HalfSpace> = other_sites(t, ring, &[p, q])
        .into_iter()
        .map(|r| HalfSpace::closer(pp, t.point(r)))
        .collect();
    let region = Region {
        halfspaces: &hs,
        plane: Some(HalfSpace::closer(pp, qp)),
    };
    let n = crate::kernel::geom::sub(qp, pp);
    let ni = [0, 1, 2].map(|k| pt(qp[k]) - pt(pp[k]));
    // Directions w x n, best first: perpendicular (in H) to the chord between the two
    // crossings of the facet's edges (an arc roughly along the chord never has its
    // tangent there), then the in-plane gradient at the crossings and at the centre.
    let mut cands = Vec::new();
    if let [a, b] = crossings {
        cands.push(crate::kernel::geom::sub(*b, *a));
    }
    for x in crossings.iter().copied().chain([mid(&start)]) {
        cands.push(cross(n, f.grad(x).g));
    }
    for k in 0..3 {
        let mut e = [0.0; 3];
        e[k] = 1.0;
        cands.push(cross(n, e));
    }
    let smooth = f.regularity(&start) == crate::implicit::Regularity::Smooth;
    // The pre-test's enclosures over the start box (a pure function of the box).
    let known_at = |x: &IBox| known.as_ref().filter(|_| *x == start);
    let tried = first_direction_that_covers(cands, o.directions, |w| {
        // d = w × (q − p) is exactly in the bisector plane; enclose it.
        let d = icross(&w.map(pt), &ni);
        cover(start, &region, o.cover, |x, _| {
            no_tangency(f, x, &d, smooth, known_at(x))
        })
    });
    match tried {
        Ok(boxes) => FaceResult {
            failure: None,
            boxes,
        },
        Err((boxes, last)) => fail(
            last.unwrap_or_else(|| mid(&start)),
            "Voronoi facet: a point of S with its tangent in every tried direction of the facet's plane (a closed curve, or S tangent to the plane) is not excluded".into(),
            boxes,
        ),
    }
}

fn check_cell(
    t: &Delaunay,
    f: &dyn Implicit,
    p: VertexId,
    cells: &[CellId],
    start: Start,
    o: &TbpOptions,
) -> FaceResult {
    let pp = t.point(p);
    let fail = |point: [f64; 3], reason: String, boxes| FaceResult {
        failure: Some(Failure {
            test: Test::Cell,
            sites: vec![p],
            point,
            reason,
            alternatives: Vec::new(),
        }),
        boxes,
    };
    let (start, known) = match start {
        Start::Search(b, known) => (b, known),
        Start::Settled(r) => return r,
        Start::Unenclosed => {
            return fail(
                pp,
                "a vertex of the Voronoi cell (a sliver's circumcentre) could not be enclosed"
                    .into(),
                0,
            )
        }
    };
    let hs: Vec<HalfSpace> = other_sites(t, cells, &[p])
        .into_iter()
        .map(|r| HalfSpace::closer(pp, t.point(r)))
        .collect();
    let region = Region {
        halfspaces: &hs,
        plane: None,
    };
    let mut cands = vec![f.grad(pp).g, f.grad(mid(&start)).g];
    cands.extend([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    let smooth = f.regularity(&start) == crate::implicit::Regularity::Smooth;
    // The pre-test's enclosures over the start box (a pure function of the box).
    let known_at = |x: &IBox| known.as_ref().filter(|_| *x == start);
    let tried = first_direction_that_covers(cands, o.directions, |d| {
        let d2 = transverse(d).map(pt);
        let di = d.map(pt);
        cover(start, &region, o.cover, |x, place| {
            no_silhouette(f, x, place, &di, &d2, smooth, known_at(x))
        })
    });
    match tried {
        Ok(boxes) => FaceResult {
            failure: None,
            boxes,
        },
        Err((boxes, last)) => fail(
            last.unwrap_or(pp),
            "Voronoi cell: a silhouette point of S (normal perpendicular to d) is not excluded in the cell: a handle, a second sheet or a small component may be there".into(),
            boxes,
        ),
    }
}

/// Run the checks on the kernel's triangulation `t` (see the module documentation).
pub fn check(t: &Delaunay, f: &dyn Implicit, domain: &Aabb, o: &TbpOptions) -> Tbp {
    let mut none = TbpCache {
        keep: false,
        ..Default::default()
    };
    check_cached(t, f, domain, o, &mut none)
}

/// [`check`], skipping the Voronoi facets and cells `cache` holds as proven and adding
/// the ones proven now.
pub fn check_cached(
    t: &Delaunay,
    f: &dyn Implicit,
    domain: &Aabb,
    o: &TbpOptions,
    cache: &mut TbpCache,
) -> Tbp {
    let dbox = domain.intervals();
    let mut r = TbpReport {
        rigorous: f.is_rigorous(),
        ..Default::default()
    };
    let mut failures: Vec<Failure> = Vec::new();
    let setup = |failures: &mut Vec<Failure>, reason: &str| {
        failures.push(Failure {
            test: Test::Setup,
            sites: Vec::new(),
            point: domain.center(),
            reason: reason.into(),
            alternatives: Vec::new(),
        })
    };
    if !r.rigorous {
        setup(&mut failures, "f has no rigorous interval extension");
    }
    r.boundary_clear = boundary_clear(f, Bx::new(domain.min, domain.max), 10, 100_000);
    if !r.boundary_clear {
        setup(
            &mut failures,
            "0 in the enclosure of f on the domain boundary: S may leave the domain",
        );
    }
    let clock = std::time::Instant::now();
    let mut lap = {
        let mut last = clock;
        move || {
            let now = std::time::Instant::now();
            let d = (now - last).as_secs_f64();
            last = now;
            d
        }
    };
    // The exact check of the triangulation and the adjacency of the Voronoi faces run
    // beside (0)+(1) (they are serial; the scan is parallel): the same results as one
    // after the other.
    let ((valid, check_seconds, adj), (cc, rdt)) = rayon::join(
        || {
            let clock = std::time::Instant::now();
            let valid = t.check().valid;
            let seconds = clock.elapsed().as_secs_f64();
            (valid, seconds, adjacency(t))
        },
        || {
            // (0)+(1): every dual segment.
            // The interval circumcentres, shared by (1) and the covers of (3) and (4).
            let cc = restricted::certified_circumcentres(t);
            let rdt = restricted::scan_certified(t, f, domain, &cc, o.segment);
            (cc, rdt)
        },
    );
    r.delaunay_valid = valid;
    if !r.delaunay_valid {
        setup(
            &mut failures,
            "the Delaunay triangulation failed its exact check",
        );
    }
    r.seconds[0] = check_seconds;
    r.far_lemma = rdt.far_lemma;
    if !rdt.far_lemma {
        setup(
            &mut failures,
            "no vertex, or a vertex outside the domain: the far-corner lemma does not apply",
        );
    }
    r.voronoi_edges = rdt.segments;
    r.restricted_facets = rdt.facets.len();
    for u in &rdt.undecided {
        let mut alternatives = vec![t.circumcentre(u.cell)];
        if let Some((d, _)) = t.neighbor(u.cell, u.facet) {
            alternatives.push(t.circumcentre(d));
        }
        failures.push(Failure {
            test: Test::Edge,
            sites: u.v.to_vec(),
            point: u.points.first().copied().unwrap_or(t.point(u.v[0])),
            reason: format!("Voronoi edge: {}", u.reason),
            alternatives,
        });
    }
    for fct in &rdt.facets {
        if fct.test.crossings.len() >= 2 {
            let p0 = t.point(fct.v[0]);
            let far = fct
                .test
                .crossings
                .iter()
                .max_by(|a, b| dist(a.point, p0).total_cmp(&dist(b.point, p0)))
                .map(|x| x.point)
                .unwrap_or(p0);
            failures.push(Failure {
                test: Test::Edge,
                sites: fct.v.to_vec(),
                point: far,
                reason: format!("Voronoi edge crosses S {} times", fct.test.crossings.len()),
                alternatives: Vec::new(),
            });
        }
    }
    let stop = |failures: &Vec<Failure>| o.stop_early && !failures.is_empty();
    r.seconds[1] = lap();
    r.voronoi_facets = adj.edges.len();
    r.voronoi_cells = (crate::kernel::delaunay::FAR..t.points().len() as u32)
        .filter(|&v| t.is_inserted(v))
        .count();
    if stop(&failures) {
        r.skipped = vec![Test::Manifold, Test::Facet, Test::Cell];
        return finish(r, rdt, failures);
    }
    let late = || o.deadline.is_some_and(|d| std::time::Instant::now() >= d);
    if late() {
        r.skipped = vec![Test::Manifold, Test::Facet, Test::Cell];
        r.timed_out = true;
        return finish(r, rdt, failures);
    }
    // Set when a task found the deadline passed and left its faces unchecked.
    let cut = std::sync::atomic::AtomicBool::new(false);
    let cut_here = || {
        let l = late();
        if l {
            cut.store(true, std::sync::atomic::Ordering::Relaxed);
        }
        l
    };
    // (2) and (3): the manifold check (serial) runs beside the covers of the Voronoi
    // facets (parallel), unless a failing (2) has to stop the checks (`stop_early`).
    // Its failures are listed before those of (3), as when run one after the other.
    let manifold = || -> (Vec<Failure>, f64) {
        let clock = std::time::Instant::now();
        let mut failures = Vec::new();
        // (2): restricted edges in 0 or 2 facets, links single cycles.
        let mut edge_count: HashMap<(VertexId, VertexId), u32> = HashMap::new();
        let mut star: HashMap<VertexId, Vec<usize>> = HashMap::new();
        for (k, fct) in rdt.facets.iter().enumerate() {
            for e in 0..3 {
                let (a, b) = (fct.v[e], fct.v[(e + 1) % 3]);
                *edge_count.entry((a.min(b), a.max(b))).or_default() += 1;
                star.entry(fct.v[e]).or_default().push(k);
            }
        }
        let farthest = |p: VertexId| -> [f64; 3] {
            let pp = t.point(p);
            star.get(&p)
                .into_iter()
                .flatten()
                .flat_map(|&k| rdt.facets[k].test.crossings.iter().map(|x| x.point))
                .max_by(|a, b| dist(*a, pp).total_cmp(&dist(*b, pp)))
                .unwrap_or(pp)
        };
        let mut bad_edges: Vec<_> = edge_count.iter().filter(|(_, &n)| n != 2).collect();
        bad_edges.sort_unstable();
        for (&(a, b), &n) in bad_edges {
            failures.push(Failure {
                test: Test::Manifold,
                sites: vec![a, b],
                point: farthest(a),
                reason: format!("restricted edge in {n} restricted facets (2 needed)"),
                alternatives: Vec::new(),
            });
        }
        let mut verts: Vec<_> = star.keys().copied().collect();
        verts.sort_unstable();
        for v in verts {
            if !super::bo::is_disk(v, &star[&v], &rdt) {
                failures.push(Failure {
                    test: Test::Manifold,
                    sites: vec![v],
                    point: farthest(v),
                    reason: "the restricted facets around the vertex do not form one disk".into(),
                    alternatives: Vec::new(),
                });
            }
        }
        (failures, clock.elapsed().as_secs_f64())
    };
    let cache_ref = &*cache;
    let facets = || -> Vec<(Vec<u32>, FaceResult)> {
        // (3): covers with interval circumcentres as the faces' vertices.
        let mut crossings: HashMap<(VertexId, VertexId), Vec<[f64; 3]>> = HashMap::new();
        for fct in &rdt.facets {
            for e in 0..3 {
                let (a, b) = (fct.v[e], fct.v[(e + 1) % 3]);
                let x = crossings.entry((a.min(b), a.max(b))).or_default();
                x.extend(fct.test.crossings.iter().map(|c| c.point));
            }
        }
        let none = Vec::new();
        let idx: Vec<usize> = (0..adj.edges.len()).collect();
        idx.par_chunks(CHUNK)
            .flat_map_iter(|chunk| {
                if cut_here() {
                    return Vec::new();
                }
                let todo: Vec<_> = chunk
                    .iter()
                    .map(|&i| {
                        let (e, ring) = (&adj.edges[i], adj.ring(i));
                        (cache_ref.key(t, &[e.0, e.1], ring), e, ring)
                    })
                    .filter(|x| !cache_ref.proven(&x.0))
                    .collect();
                let rings: Vec<&[CellId]> = todo.iter().map(|x| x.2).collect();
                let starts = start_boxes(f, &cc, &rings, &dbox);
                todo.into_iter()
                    .zip(starts)
                    .map(|((k, e, ring), start)| {
                        let xs = crossings.get(e).unwrap_or(&none);
                        (k, check_facet(t, f, *e, ring, start, xs, o))
                    })
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let ((manifold_failures, manifold_seconds), facets) = if o.stop_early {
        let m = manifold();
        if !m.0.is_empty() {
            failures.extend(m.0);
            r.seconds[2] = m.1;
            r.skipped = vec![Test::Facet, Test::Cell];
            return finish(r, rdt, failures);
        }
        (m, facets())
    } else {
        rayon::join(manifold, facets)
    };
    failures.extend(manifold_failures);
    r.seconds[2] = manifold_seconds;
    r.boxes += record(facets, &mut failures, cache);
    r.seconds[3] = lap();
    if cut.load(std::sync::atomic::Ordering::Relaxed) || late() {
        r.skipped = vec![Test::Facet, Test::Cell];
        r.timed_out = true;
        return finish(r, rdt, failures);
    }
    if stop(&failures) {
        r.skipped = vec![Test::Cell];
        return finish(r, rdt, failures);
    }
    let verts: Vec<VertexId> = (crate::kernel::delaunay::FAR..t.points().len() as u32)
        .filter(|&v| t.is_inserted(v))
        .collect();
    let cells: Vec<(Vec<u32>, FaceResult)> = verts
        .par_chunks(CHUNK)
        .flat_map_iter(|chunk| {
            if cut_here() {
                return Vec::new();
            }
            let todo: Vec<_> = chunk
                .iter()
                .map(|&p| (cache.key(t, &[p], &adj.cells_of[p as usize]), p))
                .filter(|x| !cache.proven(&x.0))
                .collect();
            let stars: Vec<&[CellId]> = todo
                .iter()
                .map(|x| adj.cells_of[x.1 as usize].as_slice())
                .collect();
            let starts = start_boxes(f, &cc, &stars, &dbox);
            todo.into_iter()
                .zip(starts)
                .map(|((k, p), start)| {
                    (k, check_cell(t, f, p, &adj.cells_of[p as usize], start, o))
                })
                .collect::<Vec<_>>()
        })
        .collect();
    r.boxes += record(cells, &mut failures, cache);
    r.seconds[4] = lap();
    if cut.load(std::sync::atomic::Ordering::Relaxed) {
        r.skipped = vec![Test::Cell];
        r.timed_out = true;
    }
    finish(r, rdt, failures)
}

fn finish(mut r: TbpReport, rdt: Scan, failures: Vec<Failure>) -> Tbp {
    let count = |k: Test| failures.iter().filter(|x| x.test == k).count();
    r.edge_failures = count(Test::Edge);
    r.manifold_failures = count(Test::Manifold);
    r.facet_failures = count(Test::Facet);
    r.cell_failures = count(Test::Cell);
    r.holds = failures.is_empty() && r.skipped.is_empty();
    Tbp {
        report: r,
        rdt,
        failures,
    }
}
