//! Boissonnat–Oudot refinement for a curve f(x, y) = 0 (`certmesh curve NAME --algo
//! bo`): the chapter "Meshing of Surfaces" (Boissonnat, Cohen-Steiner, Mourrain, Rote
//! and Vegter, 2007), §1.3 and §1.3.1, one dimension down, on the `spade` crate's 2D
//! Delaunay triangulation (exact predicates).
//!
//! **Restricted Delaunay edges.** A Delaunay edge pq is *restricted* iff its dual
//! Voronoi edge meets C = {f = 0} ∩ D; a crossing x is the centre of a *curve Delaunay
//! ball* (a disk through p and q, centred on C, empty of sample points), of radius
//! |x − p|. The output is the set of restricted edges (a polygon when the sample is
//! good).
//!
//! **Far points and the far lemma.** Four far points, the corners of a square centred
//! on D at distance > diam(D) from D, are inserted first (the 2D analogue of the 3D
//! kernel's far corners). Then every sample point lies strictly inside their convex
//! hull, so every Delaunay edge with two sample end points has two finite triangles and
//! its dual Voronoi edge is the *segment* between their circumcentres (never a ray).
//! Lemma ([`far_lemma_2d`], checked with outward-rounded intervals): if every sample
//! point lies in D (and there is one) and every far point q has dist(q, D) > diam(D),
//! then no edge with a far end point is restricted. Proof: a point x ∈ D has
//! |x − p| ≤ diam(D) < |x − q| for a sample point p ∈ D, so x is not in the closed
//! Voronoi cell of q; a Voronoi edge dual to an edge with end point q lies in that
//! cell, hence misses D, hence misses C. (We prefer the far square to spade's
//! unbounded outer Voronoi rays: the rays would need clipping against D, a second
//! code path for hull edges; with the square every tested dual is a finite segment
//! and the lemma disposes of the rest.) The far points do not change the answer: as
//! no point of D lies in a far point's cell, Vor(P ∪ F) ∩ D = Vor(P) ∩ D, so an edge
//! pq of P has a Voronoi edge meeting C ∩ D in one diagram iff in the other (a point
//! x ∈ C ∩ D equidistant from p and q and closer to them than to the rest of P is
//! also closer to them than to F).
//!
//! **Crossings.** Every crossing of a dual segment with C is isolated by
//! [`isolate_segment`] (interval arithmetic; the 2D function is evaluated with z = 0,
//! the segment lies in the plane z = 0 and the domain box has z = [0, 0]), not by the
//! signs at its ends: a Voronoi edge can cross C twice (near-touching components, a
//! thin neck). A piece where neither exclusion nor uniqueness is proven (tangent or
//! grazing crossing) is *undecided*.
//!
//! **Refinement** (worst first, a binary heap with stale entries dropped): a
//! restricted edge is bad when its dual has an undecided crossing (the projected
//! point is inserted, a bounded number of times), when it crosses C more than once,
//! when a curve Delaunay ball has radius > `facet_size`, or when the distance from the
//! edge's midpoint (its circumcentre) to a crossing exceeds `facet_distance`; there is
//! no angle criterion for curves. The point inserted is the crossing with the largest
//! ball, as in §1.3.1. Guards: `--max-vertices`, `--time-limit`, a minimum separation
//! (a ball of radius < 1e-9·diam(D) is not refined), a cap on insertions for undecided
//! crossings; a run stopped by one says `refinement_complete: false` and why.
//! `--manifold` adds CGAL's `Manifold_tag` phase one dimension down: while a sample
//! point has restricted degree other than 2, its restricted edges are refined.
//!
//! **Seeds.** The project's certified critical points of a height
//! ([`crate::implicit::critical`]) are implemented for surfaces only (curves are
//! `Unsupported`), so the seeds are the crossings of a fixed family of lines with C
//! (every crossing isolated by interval arithmetic): horizontal and vertical lines
//! across D at generic offsets and two slanted ones. A component that none of them
//! meets is missed; the report says `seeding: "fallback-lines"` and the certificate's
//! reason says that the seeding is not certified.
//!
//! **Certificate.** After the refinement the restricted edges are re-derived with
//! interval circumcentres (each circumcentre enclosed in outward-rounded arithmetic,
//! every crossing isolated on the segment between *any* points of the two enclosures),
//! the triangulation is checked with the exact incircle predicate, and the far lemma is
//! checked, and the oracle must be rigorous. When all of that holds and no dual
//! segment is undecided, the output is claimed to be exactly the restricted Delaunay
//! graph of the sample ([`Claim::RestrictedDelaunayCurve`], which also counts the
//! sample points on no restricted edge: they are not output vertices). Isotopy is **not** claimed: Theorem 3 is stated
//! for surfaces and samples *on* S; for curves it would need (i) a certified lower
//! bound ψ ≤ ε·lfs (the project's reach bound is for surfaces), (ii) vertices exactly
//! on C (ours are floats within ~1e-16 of it), and (iii) a certified seed on every
//! component (ours come from fallback lines).
use super::restricted::{test_segment, DualTest, FacetCrossing};
use crate::error::{Error, Result};
use crate::implicit::ops::{
    isolate_segment, project, segment_root_point, segment_sign, SegmentBudget, SegmentRoot,
};
use crate::implicit::{IBox, Implicit};
use crate::kernel::geom::{dist, lerp, Aabb};
use crate::mesh::Curve2;
use crate::mesher::options::MesherOptions;
use crate::mesher::{
    check_input, stats_map, Certificate, Claim, Mesh, MeshOutput, Mesher, Progress, Uncertified,
};
use inari::Interval;
use serde::Serialize;
use spade::handles::FixedVertexHandle;
use spade::{DelaunayTriangulation, Point2, Triangulation};
use std::collections::{BinaryHeap, HashMap, HashSet};

/// The `--set` keys of the 2D `bo`.
pub const SETTINGS: &[&str] = &["seed-lines", "undecided-insertions"];

/// Number of far points (inserted first; vertex handles 0..FAR).
pub const FAR: usize = 4;

/// Boissonnat–Oudot refinement of a curve; see the module documentation.
#[derive(Clone, Debug)]
pub struct BoissonnatOudot2 {
    /// Largest curve Delaunay ball radius (`--facet-size`; default diam(D)/20).
    pub facet_size: f64,
    /// Largest distance from an edge's midpoint to a crossing of its dual
    /// (`--facet-distance`; default diam(D)/200).
    pub facet_distance: Option<f64>,
    pub max_vertices: usize,
    pub time_limit: Option<f64>,
    /// Seed lines per axis (and two slanted ones).
    pub seed_lines: usize,
    /// Insertions allowed for undecided crossings before they are reported.
    pub max_undecided_insertions: usize,
    /// `--manifold` (CGAL's `Manifold_tag`, one dimension down): when the queue is
    /// empty, refine every restricted edge at a sample point of restricted degree
    /// other than 2 (a branch point or an open end), until every used sample point has
    /// degree 2 or `max_manifold_rounds` rounds have run.
    pub manifold: bool,
    pub max_manifold_rounds: usize,
}

impl Default for BoissonnatOudot2 {
    fn default() -> Self {
        BoissonnatOudot2 {
            facet_size: f64::NAN,
            facet_distance: None,
            max_vertices: 1_000_000,
            time_limit: None,
            seed_lines: 8,
            max_undecided_insertions: 200,
            manifold: false,
            max_manifold_rounds: 50,
        }
    }
}

impl BoissonnatOudot2 {
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        o.check_keys("bo", SETTINGS)?;
        let mut m = BoissonnatOudot2::default();
        let pos = |name: &str, v: Option<f64>| -> Result<Option<f64>> {
            match v {
                Some(x) if !(x.is_finite() && x > 0.0) => Err(Error::Param(format!(
                    "--{name} must be a positive number, got {x}"
                ))),
                v => Ok(v),
            }
        };
        if let Some(s) = pos("facet-size", o.facet_size)? {
            m.facet_size = s;
        }
        m.facet_distance = pos("facet-distance", o.facet_distance)?;
        if let Some(n) = o.max_vertices {
            if n < 2 {
                return Err(Error::Param(
                    "--max-vertices must be at least 2 for curves".into(),
                ));
            }
            m.max_vertices = n;
        }
        let t = o.time_limit_or_default();
        crate::mesher::options::check_time_limit(t)?;
        m.time_limit = Some(t);
        if let Some(n) = o.get::<usize>("seed-lines")? {
            m.seed_lines = n.clamp(1, 1000);
        }
        if let Some(n) = o.get::<usize>("undecided-insertions")? {
            m.max_undecided_insertions = n;
        }
        m.manifold = o.manifold;
        Ok(m)
    }
}

/// Why an edge is bad, in refinement order (lower first).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
enum Bad {
    Undecided = 0,
    Multiple = 1,
    Size = 2,
    Distance = 3,
    Manifold = 4,
}

impl Bad {
    fn name(self) -> &'static str {
        match self {
            Bad::Undecided => "undecided",
            Bad::Multiple => "multiple",
            Bad::Size => "size",
            Bad::Distance => "distance",
            Bad::Manifold => "manifold",
        }
    }
}

struct Entry {
    class: Bad,
    badness: f64,
    /// The edge (a, b) and its two opposite vertices when it was tested.
    a: usize,
    b: usize,
    left: usize,
    right: usize,
    point: [f64; 3],
    radius: f64,
}

super::restricted::worst_first_order!(Entry);

/// Statistics of a run (the report's `stats`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Bo2Stats {
    pub facet_size: f64,
    pub facet_distance: Option<f64>,
    /// Sample points (far points not counted).
    pub vertices: usize,
    /// Restricted edges output.
    pub edges: usize,
    /// How the seeds were found: always "fallback-lines" for curves (the certified
    /// critical-point search of `implicit::critical` does not handle curves).
    pub seeding: String,
    pub seeding_note: String,
    pub seed_lines: usize,
    pub seed_vertices: usize,
    /// Seed vertices incident to no restricted edge at the end.
    pub seeds_not_incident: usize,
    pub insertions: usize,
    pub insertions_by_reason: HashMap<String, usize>,
    /// Refinement points refused: too close to the edge's end points, outside D, or a
    /// duplicate.
    pub refused: usize,
    pub undecided_insertions: usize,
    pub manifold: bool,
    /// Manifold-phase rounds run.
    pub manifold_rounds: usize,
    pub dual_tests: usize,
    pub multiple_crossing_segments: usize,
    pub refinement_complete: bool,
    pub stop_reason: Option<String>,
    /// Largest curve Delaunay ball of the output (float).
    pub max_ball_radius: Option<f64>,
    /// Largest distance from an output edge's midpoint to a crossing of its dual.
    pub max_distance: Option<f64>,
    /// The certified re-derivation.
    pub certified_segments: usize,
    pub certified_undecided: usize,
    /// Edges in the float scan and not the certified one, or the reverse.
    pub certified_mismatches: usize,
    /// Every interior edge locally Delaunay by the exact incircle predicate.
    pub delaunay_valid: bool,
    pub far_lemma: bool,
    /// Upper bound of every curve Delaunay ball radius over its certified piece.
    pub certified_max_ball_radius: Option<f64>,
    pub seconds_refine: f64,
    pub seconds_certify: f64,
}

type Dt = DelaunayTriangulation<Point2<f64>>;

fn p3(p: Point2<f64>) -> [f64; 3] {
    [p.x, p.y, 0.0]
}

/// One restricted edge of a scan.
#[derive(Clone, Debug, Serialize)]
pub struct RestrictedEdge {
    /// Vertex handles (indices), oriented so that f > 0 lies to the right of a → b
    /// at the largest-ball crossing (counter-clockwise around {f < 0}).
    pub v: [usize; 2],
    pub test: DualTest,
}

/// The restricted edges of a triangulation, and what could not be decided.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Scan2 {
    pub edges: Vec<RestrictedEdge>,
    /// Edges whose dual could not be decided, with a point near each undecided piece.
    pub undecided: Vec<([usize; 2], Vec<[f64; 3]>, &'static str)>,
    /// Dual segments tested (edges between two sample points).
    pub segments: usize,
    pub multiple_crossings: usize,
    pub far_lemma: bool,
}

/// The far lemma (module doc), checked with outward-rounded intervals: every vertex
/// but the far points lies in D, there is at least one, and each far point is farther
/// than diam(D) from D.
pub fn far_lemma_2d(t: &Dt, domain: &Aabb) -> bool {
    let mut any = false;
    for v in t.vertices().skip(FAR) {
        if !domain.contains(p3(v.position())) {
            return false;
        }
        any = true;
    }
    if !any || t.num_vertices() < FAR {
        return false;
    }
    let iv = |x: f64| Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE);
    let zero = iv(0.0);
    let w: [Interval; 2] = [0, 1].map(|k| iv(domain.max[k]) - iv(domain.min[k]));
    let diam2 = w[0].sqr() + w[1].sqr();
    t.vertices().take(FAR).all(|q| {
        let p = [q.position().x, q.position().y];
        let gap: [Interval; 2] = [0, 1].map(|k| {
            if p[k] < domain.min[k] {
                iv(domain.min[k]) - iv(p[k])
            } else if p[k] > domain.max[k] {
                iv(p[k]) - iv(domain.max[k])
            } else {
                zero
            }
        });
        let g2 = gap[0].sqr() + gap[1].sqr();
        g2.inf() > diam2.sup()
    })
}

/// The four far points: corners of the square centred on D with half-side
/// max half-extent + 2·diam(D), so each is ≥ 2·diam(D) > diam(D) from D.
pub fn far_points(domain: &Aabb) -> [[f64; 2]; 4] {
    let c = domain.center();
    let s = domain.size();
    let diam = (s[0] * s[0] + s[1] * s[1]).sqrt();
    let l = 0.5 * s[0].max(s[1]) + 2.0 * diam;
    [
        [c[0] - l, c[1] - l],
        [c[0] + l, c[1] - l],
        [c[0] + l, c[1] + l],
        [c[0] - l, c[1] + l],
    ]
}

/// An interval enclosure of the circumcentre of the triangle (a, b, c) (floats), in
/// outward-rounded arithmetic, or `None` when the enclosure of the determinant
/// contains 0. Returned as a box with z = [0, 0].
pub fn circumcentre_interval_2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Option<IBox> {
    let iv = |x: f64| Interval::try_from((x, x)).ok();
    let (ax, ay) = (iv(a[0])?, iv(a[1])?);
    let (bx, by) = (iv(b[0])? - ax, iv(b[1])? - ay);
    let (cx, cy) = (iv(c[0])? - ax, iv(c[1])? - ay);
    let d = iv(2.0)? * (bx * cy - by * cx);
    if !(d.inf() > 0.0 || d.sup() < 0.0) {
        return None;
    }
    let b2 = bx.sqr() + by.sqr();
    let c2 = cx.sqr() + cy.sqr();
    let ux = (cy * b2 - by * c2) / d;
    let uy = (bx * c2 - cx * b2) / d;
    let out = [ax + ux, ay + uy, iv(0.0)?];
    out.iter()
        .all(|x| x.inf().is_finite() && x.sup().is_finite())
        .then_some(out)
}

/// The two triangles of edge a → b (left, right) as their vertex handles, and the
/// opposite vertices; `None` for a hull edge or a missing edge.
fn edge_faces(t: &Dt, a: usize, b: usize) -> Option<([usize; 3], [usize; 3], usize, usize)> {
    let e = t.get_edge_from_neighbors(
        FixedVertexHandle::from_index(a),
        FixedVertexHandle::from_index(b),
    )?;
    let l = e.opposite_vertex()?;
    let r = e.rev().opposite_vertex()?;
    Some((
        [a, b, l.fix().index()],
        [b, a, r.fix().index()],
        l.fix().index(),
        r.fix().index(),
    ))
}

fn pos(t: &Dt, v: usize) -> [f64; 2] {
    let p = t.vertex(FixedVertexHandle::from_index(v)).position();
    [p.x, p.y]
}

/// The float circumcentre of a triangle given by vertex handles (the formula of
/// [`circumcentre_interval_2d`] in floats; the centroid for a flat triangle).
fn cc_float(t: &Dt, tri: [usize; 3]) -> [f64; 3] {
    let [a, b, c] = tri.map(|v| pos(t, v));
    let (bx, by) = (b[0] - a[0], b[1] - a[1]);
    let (cx, cy) = (c[0] - a[0], c[1] - a[1]);
    let d = 2.0 * (bx * cy - by * cx);
    if d == 0.0 {
        return [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0, 0.0];
    }
    let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
    [
        a[0] + (cy * b2 - by * c2) / d,
        a[1] + (bx * c2 - cx * b2) / d,
        0.0,
    ]
}

/// The float dual segment of the sample edge (a, b) (left circumcentre → right one)
/// with the opposite vertices, or `None` (hull edge: impossible once the far points
/// are in; a missing edge).
fn dual_float(t: &Dt, a: usize, b: usize) -> Option<([f64; 3], [f64; 3], usize, usize)> {
    let (lt, rt, l, r) = edge_faces(t, a, b)?;
    Some((cc_float(t, lt), cc_float(t, rt), l, r))
}

/// Every crossing of C with the segment between any points of the boxes `ea`, `eb`
/// (interval circumcentres); a float point of each on the segment of the midpoints,
/// its radius, and an upper bound of the radius over the certified piece.
fn certified_dual(
    f: &dyn Implicit,
    ea: &IBox,
    eb: &IBox,
    v0: [f64; 3],
    dbox: &IBox,
    budget: SegmentBudget,
) -> DualTest {
    let r = isolate_segment(f, ea, eb, Some(dbox), budget);
    let am = ea.map(|x| x.mid());
    let bm = eb.map(|x| x.mid());
    let v = v0.map(|x| Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE));
    DualTest {
        crossings: r
            .roots
            .iter()
            .map(|root| {
                let (p, tp) = segment_root_point(f, am, bm, root, 1e-12);
                let [t0, t1] = narrow(f, ea, eb, root, tp);
                let tt = Interval::try_from((t0, t1)).unwrap_or(Interval::ENTIRE);
                let d2 = (0..2)
                    .map(|k| (ea[k] + tt * (eb[k] - ea[k]) - v[k]).sqr())
                    .fold(Interval::try_from((0.0, 0.0)).unwrap(), |s, x| s + x);
                FacetCrossing {
                    point: p,
                    radius: dist(p, v0),
                    radius_sup: d2.sup().sqrt() * (1.0 + 4.0 * f64::EPSILON),
                    rising: root.rising,
                    piece: [root.t0, root.t1],
                }
            })
            .collect(),
        undecided: r
            .undecided
            .iter()
            .map(|u| lerp(am, bm, 0.5 * (u[0] + u[1])))
            .collect(),
        pieces: r.pieces,
    }
}

/// A sub-piece [t0, t1] of a certified root's piece that still holds the root: the
/// signs at t − δ and t + δ around the float root t proven opposite (for every segment
/// between the two boxes), δ growing from 1e-12; the whole piece if that fails. The
/// root is unique in its piece, so it lies in any sub-piece with opposite end signs.
fn narrow(f: &dyn Implicit, ea: &IBox, eb: &IBox, root: &SegmentRoot, t: f64) -> [f64; 2] {
    let sign = |t: f64| segment_sign(f, ea, eb, t);
    let mut d = 1e-12;
    while d < 1e-2 {
        let (l, h) = ((t - d).max(root.t0), (t + d).min(root.t1));
        if l < h && sign(l) == Some(!root.rising) && sign(h) == Some(root.rising) {
            return [l, h];
        }
        d *= 16.0;
    }
    [root.t0, root.t1]
}

/// The sample edges (both end points not far), each once, as (a, b) with a < b.
fn sample_edges(t: &Dt) -> Vec<(usize, usize)> {
    t.undirected_edges()
        .map(|e| {
            let [a, b] = e.vertices().map(|v| v.fix().index());
            (a.min(b), a.max(b))
        })
        .filter(|&(a, _)| a >= FAR)
        .collect()
}

/// The restricted edges of the current triangulation: `certified` with interval
/// circumcentres (the certificate's view), else with the float ones (the
/// refinement's view).
pub fn scan(
    t: &Dt,
    f: &dyn Implicit,
    domain: &Aabb,
    certified: bool,
    budget: SegmentBudget,
) -> Scan2 {
    let dbox = domain.intervals();
    let mut s = Scan2 {
        far_lemma: far_lemma_2d(t, domain),
        ..Default::default()
    };
    for (a, b) in sample_edges(t) {
        s.segments += 1;
        let Some((lt, rt, _, _)) = edge_faces(t, a, b) else {
            s.undecided
                .push(([a, b], Vec::new(), "hull edge between sample points"));
            continue;
        };
        let v0 = p3(Point2::new(pos(t, a)[0], pos(t, a)[1]));
        let test = if certified {
            let enc = |tri: [usize; 3]| {
                let [x, y, z] = tri.map(|v| pos(t, v));
                circumcentre_interval_2d(x, y, z)
            };
            match (enc(lt), enc(rt)) {
                (Some(ea), Some(eb)) => certified_dual(f, &ea, &eb, v0, &dbox, budget),
                _ => {
                    let m = lerp(cc_float(t, lt), cc_float(t, rt), 0.5);
                    s.undecided.push((
                        [a, b],
                        vec![m],
                        "circumcentre not enclosed (a flat triangle)",
                    ));
                    continue;
                }
            }
        } else {
            test_segment(f, cc_float(t, lt), cc_float(t, rt), v0, &dbox, budget)
        };
        if !test.undecided.is_empty() {
            s.undecided.push((
                [a, b],
                test.undecided.clone(),
                "grazing: tangent or grazing crossing of a dual Voronoi edge (roots not isolated)",
            ));
        }
        if test.crossings.len() >= 2 {
            s.multiple_crossings += 1;
        }
        if let Some(x) = test.largest() {
            // The dual runs from the left triangle to the right one: a rising crossing
            // puts f > 0 on the right of a → b.
            let v = if x.rising { [a, b] } else { [b, a] };
            s.edges.push(RestrictedEdge { v, test });
        }
    }
    s
}

/// Is every interior edge of `t` locally Delaunay by the exact incircle predicate
/// (the opposite vertex of one triangle not strictly inside the circumcircle of the
/// other), and every inner triangle counter-clockwise by exact orient2d?
pub fn delaunay_check(t: &Dt) -> bool {
    let c = |p: Point2<f64>| robust::Coord { x: p.x, y: p.y };
    for face in t.inner_faces() {
        let [a, b, d] = face.positions();
        if robust::orient2d(c(a), c(b), c(d)) <= 0.0 {
            return false;
        }
    }
    for e in t.directed_edges() {
        let (Some(l), Some(r)) = (e.opposite_vertex(), e.rev().opposite_vertex()) else {
            continue;
        };
        let [a, b] = e.positions();
        if robust::incircle(c(a), c(b), c(l.position()), c(r.position())) > 0.0 {
            return false;
        }
    }
    true
}

/// The state of a refinement (public for the figures).
pub struct Refinement {
    pub t: Dt,
    pub stats: Bo2Stats,
    pub seeds: Vec<usize>,
    pub regions: Vec<Uncertified>,
}

struct Run<'a> {
    f: &'a dyn Implicit,
    domain: Aabb,
    dbox: IBox,
    p: &'a BoissonnatOudot2,
    t: Dt,
    heap: BinaryHeap<Entry>,
    stats: Bo2Stats,
    delta_min: f64,
    budget: SegmentBudget,
    undecided_left: usize,
    reported_undecided: Vec<[f64; 3]>,
}

impl Run<'_> {
    fn sample_count(&self) -> usize {
        self.t.num_vertices().saturating_sub(FAR)
    }

    /// Test the edge (a, b) and queue it if bad.
    fn test_edge(&mut self, a: usize, b: usize) {
        if a < FAR || b < FAR {
            return; // not restricted, by the far lemma
        }
        let Some((ca, cb, l, r)) = dual_float(&self.t, a, b) else {
            return;
        };
        self.stats.dual_tests += 1;
        let pa = pos(&self.t, a);
        let pb = pos(&self.t, b);
        let v0 = [pa[0], pa[1], 0.0];
        let test = test_segment(self.f, ca, cb, v0, &self.dbox, self.budget);
        let Some((class, badness, point, radius)) = self.badness(&test, pa, pb) else {
            return;
        };
        self.heap.push(Entry {
            class,
            badness,
            a,
            b,
            left: l,
            right: r,
            point,
            radius,
        });
    }

    fn badness(
        &self,
        test: &DualTest,
        pa: [f64; 2],
        pb: [f64; 2],
    ) -> Option<(Bad, f64, [f64; 3], f64)> {
        let v0 = [pa[0], pa[1], 0.0];
        if !test.undecided.is_empty() && self.undecided_left > 0 {
            let u = test.undecided[0];
            let q = project(self.f, u, 30, 1e-14 * self.domain.diagonal()).unwrap_or(u);
            let q = if self.domain.contains(q) {
                [q[0], q[1], 0.0]
            } else {
                u
            };
            return Some((Bad::Undecided, 0.0, q, dist(q, v0)));
        }
        let x = test.largest()?;
        if test.crossings.len() >= 2 {
            return Some((Bad::Multiple, x.radius, x.point, x.radius));
        }
        if x.radius > self.p.facet_size {
            return Some((Bad::Size, x.radius / self.p.facet_size, x.point, x.radius));
        }
        if let Some(db) = self.p.facet_distance {
            let m = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.0];
            let (d, y) = test
                .crossings
                .iter()
                .map(|y| (dist(m, y.point), y))
                .max_by(|a, b| a.0.total_cmp(&b.0))?;
            if d > db {
                return Some((Bad::Distance, d / db, y.point, y.radius));
            }
        }
        None
    }

    /// Is the queued edge still there with the same two triangles?
    fn valid(&self, e: &Entry) -> bool {
        matches!(edge_faces(&self.t, e.a, e.b), Some((_, _, l, r)) if l == e.left && r == e.right)
    }

    /// Insert `p`; on success re-test the edges whose dual changed: those of the new
    /// vertex's star (its spokes and the edges of its link).
    fn insert(&mut self, p: [f64; 3], hint: usize, why: Bad) -> bool {
        if !self.domain.contains(p) || !p[0].is_finite() || !p[1].is_finite() {
            self.stats.refused += 1;
            return false;
        }
        let n0 = self.t.num_vertices();
        let r = self
            .t
            .insert_with_hint(Point2::new(p[0], p[1]), FixedVertexHandle::from_index(hint));
        let v = match r {
            Ok(v) if self.t.num_vertices() > n0 => v,
            _ => {
                self.stats.refused += 1;
                return false;
            }
        };
        self.stats.insertions += 1;
        *self
            .stats
            .insertions_by_reason
            .entry(why.name().to_string())
            .or_default() += 1;
        let mut todo: Vec<(usize, usize)> = Vec::new();
        for e in self.t.vertex(v).out_edges() {
            let w = e.to().fix().index();
            todo.push((v.index(), w));
            // The link edge opposite v in the triangle left of v → w.
            if !e.is_outer_edge() {
                let n = e.next();
                todo.push((n.from().fix().index(), n.to().fix().index()));
            }
        }
        for (a, b) in todo {
            self.test_edge(a.min(b), a.max(b));
        }
        true
    }

    fn refine(&mut self, t0: std::time::Instant, progress: &dyn Progress) -> Option<String> {
        while let Some(e) = self.heap.pop() {
            if !self.valid(&e) {
                continue;
            }
            if self.sample_count() >= self.p.max_vertices {
                self.heap.push(e);
                return Some(format!(
                    "vertex budget reached: {} vertices (raise --max-vertices)",
                    self.p.max_vertices
                ));
            }
            if let Some(tl) = self.p.time_limit {
                if t0.elapsed().as_secs_f64() > tl {
                    self.heap.push(e);
                    return Some(format!("time limit reached: {tl} s (raise --time-limit)"));
                }
            }
            // The crossing is the centre of an empty disk through a and b: its distance
            // to every sample point is at least its radius.
            if e.radius < self.delta_min {
                self.stats.refused += 1;
                continue;
            }
            if e.class == Bad::Undecided {
                if self.undecided_left == 0 {
                    self.reported_undecided.push(e.point);
                    continue;
                }
                self.undecided_left -= 1;
                self.stats.undecided_insertions += 1;
            }
            if self.insert(e.point, e.a, e.class) && self.stats.insertions % 256 == 0 {
                progress.inc(256);
            }
        }
        None
    }
}

/// The seed lines: `n` horizontal and `n` vertical lines across D at generic offsets
/// and two slanted lines through points near the centre, as segment end points
/// (extended past D; crossings outside D are not sought).
pub fn seed_lines(domain: &Aabb, n: usize) -> Vec<([f64; 3], [f64; 3])> {
    let (x0, y0) = (domain.min[0], domain.min[1]);
    let (w, h) = (domain.max[0] - x0, domain.max[1] - y0);
    let mut v = Vec::new();
    for k in 0..n {
        // Generic fractions: (k + 0.5)/n shifted by an irrational amount.
        let s = ((k as f64 + 0.5) / n as f64 + 0.0123 * std::f64::consts::SQRT_2).fract();
        let y = y0 + s * h;
        v.push(([x0 - 0.1 * w, y, 0.0], [x0 + 1.1 * w, y, 0.0]));
        let s = ((k as f64 + 0.5) / n as f64 + 0.0271 * std::f64::consts::E).fract();
        let x = x0 + s * w;
        v.push(([x, y0 - 0.1 * h, 0.0], [x, y0 + 1.1 * h, 0.0]));
    }
    let c = domain.center();
    let d = w.max(h);
    for (dx, dy, ox) in [(1.0, 0.618, 0.031), (1.0, -0.577, -0.047)] {
        let o = [c[0] + ox * w, c[1] + 0.013 * h, 0.0];
        v.push((
            [o[0] - d * dx, o[1] - d * dy, 0.0],
            [o[0] + d * dx, o[1] + d * dy, 0.0],
        ));
    }
    v
}

/// Run the refinement (seeds, then worst edge first until the criteria hold or a
/// guard stops it). Used by [`Mesher::mesh`] and the figures.
pub fn refine(
    p: &BoissonnatOudot2,
    f: &dyn Implicit,
    domain: &Aabb,
    progress: &dyn Progress,
) -> Result<Refinement> {
    let t0 = std::time::Instant::now();
    let s = domain.size();
    let diam = (s[0] * s[0] + s[1] * s[1]).sqrt();
    let facet_size = if p.facet_size.is_nan() {
        diam / 20.0
    } else {
        p.facet_size
    };
    let facet_distance = p.facet_distance.or(Some(diam / 200.0));
    let params = BoissonnatOudot2 {
        facet_size,
        facet_distance,
        ..p.clone()
    };
    let mut t = Dt::new();
    for q in far_points(domain) {
        t.insert(Point2::new(q[0], q[1]))
            .map_err(|e| Error::Domain(format!("far point not insertable: {e:?}")))?;
    }
    let mut run = Run {
        f,
        domain: *domain,
        dbox: domain.intervals(),
        p: &params,
        t,
        heap: BinaryHeap::new(),
        stats: Bo2Stats {
            facet_size,
            facet_distance,
            seeding: "fallback-lines".into(),
            manifold: p.manifold,
            seeding_note: "certified critical points of a height are implemented for surfaces only (implicit::critical: curves are Unsupported); seeds are the crossings of fixed lines with f = 0 (isolated by interval arithmetic): a component no line meets is missed".into(),
            ..Default::default()
        },
        delta_min: 1e-9 * diam,
        budget: SegmentBudget::default(),
        undecided_left: p.max_undecided_insertions,
        reported_undecided: Vec::new(),
    };
    let mut regions: Vec<Uncertified> = Vec::new();

    // 1. Seeds.
    progress.start("bo seeds", 0);
    let lines = seed_lines(domain, p.seed_lines);
    run.stats.seed_lines = lines.len();
    let mut seeds = Vec::new();
    for (a, b) in lines {
        let test = test_segment(f, a, b, a, &run.dbox, run.budget);
        for u in &test.undecided {
            regions.push(Uncertified::new(
                Aabb { min: *u, max: *u }.inflate(1e-9 * diam),
                "grazing: a seed line touches f = 0 here (crossing not isolated)",
            ));
        }
        for x in &test.crossings {
            if seeds.len() >= p.max_vertices {
                break;
            }
            let q = x.point;
            if !domain.contains(q) {
                continue;
            }
            let n0 = run.t.num_vertices();
            match run.t.insert(Point2::new(q[0], q[1])) {
                Ok(v) if run.t.num_vertices() > n0 => seeds.push(v.index()),
                _ => run.stats.refused += 1,
            }
        }
    }
    run.stats.seed_vertices = seeds.len();
    for (a, b) in sample_edges(&run.t) {
        run.test_edge(a, b);
    }

    // 2. Refinement.
    progress.start("bo refinement", 0);
    let mut stop = run.refine(t0, progress);
    // The manifold phase (module doc).
    while stop.is_none() && p.manifold {
        let s = scan(&run.t, f, domain, false, run.budget);
        let mut degree: HashMap<usize, usize> = HashMap::new();
        for e in &s.edges {
            for v in e.v {
                *degree.entry(v).or_default() += 1;
            }
        }
        let bad: Vec<&RestrictedEdge> = s
            .edges
            .iter()
            .filter(|e| e.v.iter().any(|v| degree[v] != 2))
            .collect();
        if bad.is_empty() {
            break;
        }
        if run.stats.manifold_rounds >= p.max_manifold_rounds {
            stop = Some(format!(
                "manifold phase stopped after {} rounds with {} edges at branch points or open ends",
                p.max_manifold_rounds,
                bad.len()
            ));
            break;
        }
        run.stats.manifold_rounds += 1;
        for e in bad {
            let (a, b) = (e.v[0].min(e.v[1]), e.v[0].max(e.v[1]));
            let (Some(x), Some((_, _, l, r))) = (e.test.largest(), edge_faces(&run.t, a, b)) else {
                continue;
            };
            run.heap.push(Entry {
                class: Bad::Manifold,
                badness: x.radius,
                a,
                b,
                left: l,
                right: r,
                point: x.point,
                radius: x.radius,
            });
        }
        stop = run.refine(t0, progress);
    }
    for u in &run.reported_undecided {
        regions.push(Uncertified::new(
            Aabb { min: *u, max: *u }.inflate(1e-9 * diam),
            "grazing or tangent crossing of a Voronoi edge not resolved by refinement (insertion cap reached)",
        ));
    }
    if stop.is_none() && !run.reported_undecided.is_empty() {
        stop = Some(format!(
            "{} undecided crossings left after {} insertions for them",
            run.reported_undecided.len(),
            p.max_undecided_insertions
        ));
    }
    run.stats.refinement_complete = stop.is_none();
    run.stats.stop_reason = stop;
    run.stats.vertices = run.sample_count();
    run.stats.seconds_refine = t0.elapsed().as_secs_f64();
    Ok(Refinement {
        t: run.t,
        stats: run.stats,
        seeds,
        regions,
    })
}

/// The restricted edges of a scan as a curve over the vertices they use (in order of
/// first use).
pub fn to_curve(t: &Dt, scan: &Scan2) -> Curve2 {
    let mut map: HashMap<usize, u32> = HashMap::new();
    let mut c = Curve2::default();
    for e in &scan.edges {
        let s = e.v.map(|v| {
            *map.entry(v).or_insert_with(|| {
                c.vertices.push(pos(t, v));
                (c.vertices.len() - 1) as u32
            })
        });
        c.segments.push(s);
    }
    c
}

fn mesh_bo2(
    p: &BoissonnatOudot2,
    f: &dyn Implicit,
    domain: &Aabb,
    progress: &dyn Progress,
) -> Result<MeshOutput> {
    let Refinement {
        t,
        mut stats,
        seeds,
        mut regions,
    } = refine(p, f, domain, progress)?;
    let diam = domain.diagonal();
    let budget = SegmentBudget::default();
    let float = scan(&t, f, domain, false, budget);

    // Certificate: the interval re-derivation.
    let tc = std::time::Instant::now();
    progress.start("bo certify", 0);
    let cert = scan(&t, f, domain, true, budget);
    let valid = delaunay_check(&t);
    let keys = |s: &Scan2| -> HashSet<(usize, usize)> {
        s.edges
            .iter()
            .map(|e| (e.v[0].min(e.v[1]), e.v[0].max(e.v[1])))
            .collect()
    };
    stats.certified_mismatches = keys(&float).symmetric_difference(&keys(&cert)).count();
    stats.certified_segments = cert.segments;
    stats.certified_undecided = cert.undecided.len();
    stats.delaunay_valid = valid;
    stats.far_lemma = cert.far_lemma;
    for (_, pts, why) in cert.undecided.iter().take(20) {
        let p0 = pts.first().copied().unwrap_or([f64::NAN; 3]);
        if p0[0].is_finite() {
            regions.push(Uncertified::new(
                Aabb { min: p0, max: p0 }.inflate(1e-9 * diam),
                *why,
            ));
        }
    }
    let mut claims = Vec::new();
    let mut reason = String::from(
        "isotopy not claimed for curves: no certified lower bound of lfs (psi) in 2D, the vertices are floating-point points near f = 0 (not on it), and the seeds come from fallback lines (a component may be missed)",
    );
    let rigorous = f.is_rigorous();
    let out_scan = if rigorous && valid && cert.far_lemma && cert.undecided.is_empty() {
        let used: HashSet<usize> = cert.edges.iter().flat_map(|e| e.v).collect();
        let sample_points = t.num_vertices() - FAR;
        claims.push(Claim::RestrictedDelaunayCurve {
            edges: cert.edges.len(),
            voronoi_edges: cert.segments,
            multiple_crossings: cert.multiple_crossings,
            sample_points,
            isolated_sample_points: sample_points - used.len(),
        });
        stats.certified_max_ball_radius = Some(
            cert.edges
                .iter()
                .flat_map(|e| e.test.crossings.iter().map(|x| x.radius_sup))
                .fold(0.0f64, f64::max),
        );
        cert
    } else {
        reason = format!(
            "restricted Delaunay edges not certified: {}; {reason}",
            if !rigorous {
                "the function has no rigorous interval extension".to_string()
            } else if !valid {
                "the exact Delaunay check failed".to_string()
            } else if !cert.far_lemma {
                "no sample point, or one outside the domain (the far lemma does not apply)"
                    .to_string()
            } else {
                format!("{} dual segments undecided", cert.undecided.len())
            }
        );
        float
    };
    stats.seconds_certify = tc.elapsed().as_secs_f64();

    let curve = to_curve(&t, &out_scan);
    stats.edges = curve.segments.len();
    stats.multiple_crossing_segments = out_scan.multiple_crossings;
    let used: HashSet<usize> = out_scan.edges.iter().flat_map(|e| e.v).collect();
    stats.seeds_not_incident = seeds.iter().filter(|v| !used.contains(v)).count();
    let mut max_r: f64 = 0.0;
    let mut max_d: f64 = 0.0;
    for e in &out_scan.edges {
        let [a, b] = e.v.map(|v| pos(&t, v));
        let m = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.0];
        for x in &e.test.crossings {
            max_r = max_r.max(x.radius);
            max_d = max_d.max(dist(m, x.point));
        }
    }
    if !out_scan.edges.is_empty() {
        stats.max_ball_radius = Some(max_r);
        stats.max_distance = Some(max_d);
    }
    if !stats.refinement_complete {
        reason = format!(
            "stopped before the refinement was complete: {}; {reason}",
            stats.stop_reason.clone().unwrap_or_default()
        );
    }
    Ok(MeshOutput {
        mesh: Mesh::Curve(curve),
        certificate: Certificate::uncertified(reason, claims, regions),
        stats: stats_map(&stats),
        angles: None,
    })
}

impl Mesher for BoissonnatOudot2 {
    fn name(&self) -> &'static str {
        "bo"
    }
    fn dim(&self) -> usize {
        2
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        check_input(f, domain, 2, "bo")?;
        mesh_bo2(self, f, domain, progress)
    }
}
