//! Boissonnat–Oudot Delaunay refinement with CGAL's criteria (`--algo bo`): the
//! chapter "Meshing of Surfaces" (Boissonnat et al., 2007), §1.3.1, with the criteria
//! names of CGAL's Mesh_3 (`facet_angle`, `facet_size`, `facet_distance`) and its
//! `Manifold_tag` variant.
//!
//! 1. **Seeds**: the certified critical points of a generic height ⟨n, x⟩ on S
//!    ([`critical_points_on_surface`]); every compact component has at least two (its
//!    minimum and maximum), so once the search is complete every component is seeded.
//!    A small seed triangle (radius ρ, three points on the tangent circle projected
//!    onto S by Newton) is added around each.
//! 2. **Refinement**, worst facet first (a binary heap with stale entries dropped on
//!    pop): a restricted facet is bad when its dual segment has an undecided crossing
//!    (tangent or grazing: the tangency point is inserted, a bounded number of times),
//!    when it crosses S more than once (`--set multiple=keep` turns that off), when its
//!    smallest angle is below `facet_angle`, when a surface Delaunay ball is larger
//!    than `facet_size`, or when the distance from the facet's circumcentre to a
//!    crossing exceeds `facet_distance`. The refinement point is the crossing with the
//!    largest ball; it lies on the facet's Voronoi edge, hence in the circumsphere of
//!    one of its two cells, and is inserted from that cell without a walk
//!    ([`Delaunay::insert_in_conflict_with`]).
//! 3. **Manifold phase** (`--manifold`, CGAL's `Manifold_tag`): when the queue is
//!    empty, every restricted edge not in exactly two restricted facets, then every
//!    vertex whose restricted link is not one cycle, is refined by inserting the
//!    largest-ball crossing of an incident restricted facet; back to 2.
//! 4. **Guards**: `--max-vertices`, `--time-limit`, a minimum separation (a point
//!    closer than 1e-9·diam(D) to the facet's vertices is refused), a cap on the
//!    insertions for undecided crossings and on manifold rounds. A run stopped by one
//!    says `refinement_complete: false` and why.
//! 5. **Output**: the restricted facets, oriented towards f > 0.
//! 6. **Certificate** (`--certify`): the restricted triangulation is re-derived with
//!    interval circumcentres ([`super::restricted::scan`] in `Certified` mode); when
//!    every dual segment is decided it *is* the restricted Delaunay triangulation of
//!    the output's vertices, reported as a typed claim. Then a certified lower bound
//!    τ̄ of the reach ([`crate::implicit::reach`]) gives ψ = 0.099·τ̄ ≤ 0.1·lfs, and
//!    when every surface Delaunay ball (outward-rounded) has radius ≤ ψ the weak
//!    ε-sample condition (ε = 0.099 < 0.1) is claimed. Theorem 3 assumes the samples
//!    lie on S, and floating-point vertices only lie within ~1e-16 of it: the ambient
//!    isotopy is claimed through a certified point set P* on S with the output's
//!    restricted triangulation ([`super::perturbed`]), and when that fails the report
//!    names the hypothesis. `--set size=reach` refines to ψ (Theorem 4's criterion).
use super::perturbed::{perturbed_isotopy, PerturbedInputs, PerturbedReport, ISOTOPY_THEOREM};
use super::restricted::{self, key, test_segment, DualTest, Ends3, Scan};
use crate::error::{Error, Result};
use crate::harness::report::short_num;
use crate::implicit::critical::{critical_points_on_surface, Budget, Bx, Problem};
use crate::implicit::ops::{project, SegmentBudget};
use crate::implicit::reach::{reach_lower_bound, ReachBound, ReachOptions};
use crate::implicit::Implicit;
use crate::kernel::delaunay::{CellId, Delaunay, InsertError, VertexId};
use crate::kernel::geom::{add, cross, dist, dot, scale, sub, Aabb};
use crate::mesh::TriMesh;
use crate::mesher::options::MesherOptions;
use crate::mesher::{
    check_input, stats_map, Certificate, Claim, Mesh, MeshOutput, Mesher, Progress, Uncertified,
};
use serde::Serialize;
use std::collections::{BinaryHeap, HashMap};

/// ε of the weak ε-sample: Theorem 3 of the chapter needs ε < 0.1 (strictly).
pub const EPSILON: f64 = 0.099;

/// Seed-triangle radii tried per critical point at most (each a quarter of the one
/// before, down to [`MIN_SEPARATION`] of the domain's diagonal): enough to come down
/// from any facet size to the surface's scale.
const SEED_TRIES: usize = 40;

/// The smallest scale `bo` works at, as a fraction of the domain's diagonal: no seed
/// triangle has a smaller radius, and no refinement point closer than this to a
/// facet's vertices is inserted.
pub(crate) const MIN_SEPARATION: f64 = 1e-9;

/// Rounds of refinement after a certified scan that found grazing crossings.
const MAX_CERTIFY_ROUNDS: usize = 3;

/// The `--set` keys of `bo`.
pub const SETTINGS: &[&str] = &[
    "seed",
    "multiple",
    "seed-radius",
    "critical-boxes",
    "size",
    "reach-depth",
];

/// Boissonnat–Oudot refinement; see the module documentation.
#[derive(Clone, Debug)]
pub struct BoissonnatOudot {
    /// Smallest angle bound in degrees (CGAL's `facet_angle`, default 30; termination
    /// is proven up to 30).
    pub facet_angle: f64,
    /// Largest surface Delaunay ball radius (`facet_size`; default diam(D)/20). Below
    /// 4 × [`MIN_SEPARATION`] × diam(D) no seed triangle fits: refused by the run.
    pub facet_size: f64,
    /// Largest distance from a facet's circumcentre to its crossing
    /// (`facet_distance`; default diam(D)/200).
    pub facet_distance: Option<f64>,
    pub manifold: bool,
    pub max_vertices: usize,
    pub time_limit: Option<f64>,
    pub certify: bool,
    /// Refine facets whose dual segment crosses S more than once.
    pub refine_multiple: bool,
    /// Seed of the kernel's walk.
    pub seed: u64,
    /// Seed triangle radius (default facet_size / 4).
    pub seed_radius: Option<f64>,
    /// Box budget of the critical-point search.
    pub critical_boxes: usize,
    /// Insertions allowed for undecided crossings before they are reported.
    pub max_undecided_insertions: usize,
    /// Manifold-phase rounds.
    pub max_manifold_rounds: usize,
    /// `--set size=reach`: facet_size = 0.099 x the certified reach lower bound (the
    /// chapter's psi, Theorem 4), computed before the refinement.
    pub size_from_reach: bool,
    /// Octree depth of the reach bound.
    pub reach_depth: u32,
}

impl Default for BoissonnatOudot {
    fn default() -> Self {
        BoissonnatOudot {
            facet_angle: 30.0,
            facet_size: f64::NAN,
            facet_distance: None,
            manifold: false,
            max_vertices: 1_000_000,
            time_limit: None,
            certify: false,
            refine_multiple: true,
            seed: 1,
            seed_radius: None,
            critical_boxes: 200_000,
            max_undecided_insertions: 200,
            max_manifold_rounds: 50,
            size_from_reach: false,
            reach_depth: 7,
        }
    }
}

impl BoissonnatOudot {
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        o.check_keys("bo", SETTINGS)?;
        let mut m = BoissonnatOudot::default();
        if let Some(a) = o.facet_angle {
            if !(a.is_finite() && a >= 0.0 && a < 60.0) {
                return Err(Error::Param(format!(
                    "--facet-angle must be in [0, 60) degrees, got {a}"
                )));
            }
            m.facet_angle = a;
        }
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
        m.manifold = o.manifold;
        if let Some(n) = o.max_vertices {
            if n < 4 {
                return Err(Error::Param("--max-vertices must be at least 4".into()));
            }
            m.max_vertices = n;
        }
        m.time_limit = Some(o.time_limit_or_default());
        m.certify = o.certify;
        if let Some(s) = o.get::<u64>("seed")? {
            m.seed = s;
        }
        match o.extra.get("multiple").map(String::as_str) {
            None | Some("refine") => {}
            Some("keep") => m.refine_multiple = false,
            Some(v) => {
                return Err(Error::Param(format!(
                    "--set multiple={v}: expected refine or keep"
                )))
            }
        }
        match o.extra.get("size").map(String::as_str) {
            None => {}
            Some("reach") => m.size_from_reach = true,
            Some(v) => {
                return Err(Error::Param(format!(
                    "--set size={v}: the only value is 'reach' (give a number with --facet-size)"
                )))
            }
        }
        if let Some(d) = o.get::<u32>("reach-depth")? {
            m.reach_depth = d.clamp(2, 12);
        }
        m.seed_radius = pos("set seed-radius", o.get::<f64>("seed-radius")?)?;
        if let Some(n) = o.get::<usize>("critical-boxes")? {
            m.critical_boxes = n.max(1);
        }
        Ok(m)
    }
}

impl BoissonnatOudot {
    fn reach_options(&self) -> ReachOptions {
        ReachOptions {
            max_depth: self.reach_depth,
            ..ReachOptions::default()
        }
    }
}

/// Why a facet is bad, in refinement order (lower first).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
enum Bad {
    Undecided = 0,
    Multiple = 1,
    Angle = 2,
    Size = 3,
    Distance = 4,
    Manifold = 5,
}

struct Entry {
    class: Bad,
    badness: f64,
    cell: CellId,
    facet: usize,
    verts: [VertexId; 4],
    opposite: VertexId,
    point: [f64; 3],
    /// Insert from this cell (its circumsphere should contain the point).
    hint: CellId,
}

super::restricted::worst_first_order!(Entry);

/// Statistics of a run (the report's `stats`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct BoStats {
    pub facet_angle: f64,
    pub facet_size: f64,
    pub facet_distance: Option<f64>,
    pub manifold: bool,
    pub vertices: usize,
    pub facets: usize,
    pub critical_points: usize,
    pub seeding_complete: bool,
    pub seed_vertices: usize,
    /// Seeds from the fallback lines (only when the critical-point search is incomplete).
    pub fallback_seeds: usize,
    /// Seed vertices incident to no restricted facet at the end.
    pub seeds_not_incident: usize,
    pub insertions: usize,
    pub insertions_by_reason: HashMap<String, usize>,
    /// Refinement points refused: too close to a vertex, a duplicate, outside the box.
    pub refused: usize,
    pub undecided_insertions: usize,
    pub manifold_rounds: usize,
    /// Rounds in which the certified scan found grazing crossings the float refinement
    /// had not, and their tangency points were inserted (`--certify`).
    pub certify_rounds: usize,
    pub dual_tests: usize,
    pub interval_pieces: u64,
    pub multiple_crossing_segments: usize,
    pub refinement_complete: bool,
    pub stop_reason: Option<String>,
    pub min_angle_deg: Option<f64>,
    pub max_ball_radius: Option<f64>,
    pub max_distance: Option<f64>,
    /// Certified mode.
    pub certified_segments: Option<usize>,
    pub certified_undecided: Option<usize>,
    pub certified_mismatches: Option<usize>,
    pub delaunay_valid: Option<bool>,
    /// Certified: the largest surface Delaunay ball (outward-rounded).
    pub certified_max_ball_radius: Option<f64>,
    /// The certified reach lower bound (implicit::reach), when computed.
    pub reach: Option<ReachBound>,
    /// Certified: Theorem 3 through a certified point set on S
    /// ([`super::perturbed`]), when the weak-sample condition held.
    pub perturbed: Option<PerturbedReport>,
    pub seconds_refine: f64,
    pub seconds_certify: f64,
    pub seconds_perturbed: f64,
}

fn sin2_min_angle(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let (ab, bc, ca) = (sub(b, a), sub(c, b), sub(a, c));
    let n = cross(ab, sub(c, a));
    let area4 = dot(n, n); // (2·area)²
    let (l1, l2, l3) = (dot(ab, ab), dot(bc, bc), dot(ca, ca));
    let m = l1.min(l2).min(l3);
    // sin²θ at the vertex opposite the shortest edge = (2A)² · m / (l1 l2 l3)
    if l1 * l2 * l3 == 0.0 {
        0.0
    } else {
        area4 * m / (l1 * l2 * l3)
    }
}

/// Circumcentre of a triangle in 3D.
pub fn triangle_circumcentre(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let u = sub(b, a);
    let v = sub(c, a);
    let w = cross(u, v);
    let w2 = dot(w, w);
    if w2 == 0.0 {
        return scale(add(add(a, b), c), 1.0 / 3.0);
    }
    let num = add(scale(cross(v, w), dot(u, u)), scale(cross(w, u), dot(v, v)));
    add(a, scale(num, 0.5 / w2))
}

struct Run<'a> {
    f: &'a dyn Implicit,
    domain: Aabb,
    dbox: crate::implicit::IBox,
    p: &'a BoissonnatOudot,
    t: Delaunay,
    cc: Vec<[f64; 3]>,
    heap: BinaryHeap<Entry>,
    stats: BoStats,
    sin2_bound: f64,
    delta_min: f64,
    budget: SegmentBudget,
    undecided_left: usize,
    reported_undecided: Vec<[f64; 3]>,
}

impl<'a> Run<'a> {
    fn refresh_cc(&mut self, c: CellId) {
        if self.cc.len() < self.t.cell_capacity() {
            self.cc.resize(self.t.cell_capacity(), [0.0; 3]);
        }
        self.cc[c as usize] = self.t.circumcentre(c);
    }

    /// The cells incident to `v`.
    fn star(&self, v: VertexId) -> Vec<CellId> {
        let mut out = Vec::new();
        let Some(c0) = self.t.incident_cell(v) else {
            return out;
        };
        let mut seen = std::collections::HashSet::new();
        let mut stack = vec![c0];
        seen.insert(c0);
        while let Some(c) = stack.pop() {
            out.push(c);
            let cv = self.t.cell_vertices(c);
            for i in 0..4 {
                if cv[i] == v {
                    continue;
                }
                if let Some((d, _)) = self.t.neighbor(c, i) {
                    if seen.insert(d) {
                        stack.push(d);
                    }
                }
            }
        }
        out
    }

    /// Test facet (c, i) and queue it if bad.
    fn test_facet(&mut self, c: CellId, i: usize) {
        let Some((d, j)) = self.t.neighbor(c, i) else {
            return;
        };
        let fv = restricted::facet_vertices(&self.t, c, i, true);
        if fv.iter().any(|&v| self.t.is_far(v)) {
            return;
        }
        let pts = fv.map(|v| self.t.point(v));
        let test = test_segment(
            self.f,
            self.cc[c as usize],
            self.cc[d as usize],
            pts[0],
            &self.dbox,
            self.budget,
        );
        self.stats.dual_tests += 1;
        self.stats.interval_pieces += test.pieces as u64;
        if let Some((class, badness, point)) = self.badness(&test, pts) {
            let verts = self.t.cell_vertices(c);
            let opposite = self.t.cell_vertices(d)[j];
            // The point lies on the segment cc(c) → cc(d): nearer c's end is in c's
            // circumsphere more often (either may hold it; the kernel checks).
            let hint = if dist(point, self.cc[c as usize]) <= dist(point, self.cc[d as usize]) {
                c
            } else {
                d
            };
            self.heap.push(Entry {
                class,
                badness,
                cell: c,
                facet: i,
                verts,
                opposite,
                point,
                hint,
            });
        }
    }

    fn badness(&self, test: &DualTest, pts: [[f64; 3]; 3]) -> Option<(Bad, f64, [f64; 3])> {
        if !test.undecided.is_empty() && self.undecided_left > 0 {
            let u = test.undecided[0];
            let q = project(self.f, u, 30, 1e-14 * self.domain.diagonal()).unwrap_or(u);
            let q = if self.domain.contains(q) { q } else { u };
            return Some((Bad::Undecided, 0.0, q));
        }
        let x = test.largest()?;
        if self.p.refine_multiple && test.crossings.len() >= 2 {
            return Some((Bad::Multiple, x.radius, x.point));
        }
        let s2 = sin2_min_angle(pts[0], pts[1], pts[2]);
        if s2 < self.sin2_bound {
            return Some((Bad::Angle, self.sin2_bound - s2, x.point));
        }
        if x.radius > self.p.facet_size {
            return Some((Bad::Size, x.radius / self.p.facet_size, x.point));
        }
        if let Some(db) = self.p.facet_distance {
            let cc = triangle_circumcentre(pts[0], pts[1], pts[2]);
            let worst = test
                .crossings
                .iter()
                .map(|y| (dist(cc, y.point), y.point))
                .max_by(|a, b| a.0.total_cmp(&b.0))?;
            if worst.0 > db {
                return Some((Bad::Distance, worst.0 / db, worst.1));
            }
        }
        None
    }

    /// Is the queued entry still the same facet with the same dual segment?
    fn valid(&self, e: &Entry) -> bool {
        if !self.t.is_live(e.cell) || self.t.cell_vertices(e.cell) != e.verts {
            return false;
        }
        match self.t.neighbor(e.cell, e.facet) {
            Some((d, j)) => self.t.cell_vertices(d)[j] == e.opposite,
            None => false,
        }
    }

    /// Insert `p` from `hint`; on success re-test the facets of the new cells.
    fn insert(&mut self, p: [f64; 3], hint: CellId, why: &str) -> bool {
        let r = if self.t.is_live(hint) {
            self.t.insert_in_conflict_with(p, hint)
        } else {
            self.t.insert(p)
        };
        let v = match r {
            Ok(v) => v,
            Err(InsertError::Duplicate(_))
            | Err(InsertError::OutsideDomain)
            | Err(InsertError::NonFinite)
            | Err(InsertError::OutOfRange)
            | Err(InsertError::TooMany) => {
                self.stats.refused += 1;
                return false;
            }
        };
        self.stats.insertions += 1;
        *self
            .stats
            .insertions_by_reason
            .entry(why.to_string())
            .or_default() += 1;
        let star = self.star(v);
        for &c in &star {
            self.refresh_cc(c);
        }
        let in_star: std::collections::HashSet<CellId> = star.iter().copied().collect();
        for &c in &star {
            for i in 0..4 {
                match self.t.neighbor(c, i) {
                    Some((d, _)) if in_star.contains(&d) && d < c => continue,
                    _ => {}
                }
                self.test_facet(c, i);
            }
        }
        true
    }

    fn vertex_count(&self) -> usize {
        self.t.points().len() - crate::kernel::delaunay::FAR as usize
    }

    /// Pop and refine until the queue is empty or a guard stops the run.
    fn refine(&mut self, t0: std::time::Instant, progress: &dyn Progress) -> Option<String> {
        while let Some(e) = self.heap.pop() {
            if self.vertex_count() >= self.p.max_vertices {
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
            if !self.valid(&e) {
                continue;
            }
            let fv = restricted::facet_vertices(&self.t, e.cell, e.facet, true);
            let near = fv
                .iter()
                .map(|&v| dist(self.t.point(v), e.point))
                .fold(f64::INFINITY, f64::min);
            if near < self.delta_min {
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
            let why = match e.class {
                Bad::Undecided => "undecided",
                Bad::Multiple => "multiple",
                Bad::Angle => "angle",
                Bad::Size => "size",
                Bad::Distance => "distance",
                Bad::Manifold => "manifold",
            };
            if self.insert(e.point, e.hint, why) && self.stats.insertions % 256 == 0 {
                progress.inc(256);
            }
        }
        None
    }

    /// The manifold phase: queue the refinement of non-manifold edges and vertices.
    /// Returns the number queued.
    fn queue_manifold(&mut self, scan: &Scan) -> usize {
        let mut edges: HashMap<(VertexId, VertexId), Vec<usize>> = HashMap::new();
        for (k, fct) in scan.facets.iter().enumerate() {
            for e in 0..3 {
                let (a, b) = (fct.v[e], fct.v[(e + 1) % 3]);
                edges.entry((a.min(b), a.max(b))).or_default().push(k);
            }
        }
        let mut bad: Vec<usize> = Vec::new();
        for ks in edges.values() {
            if ks.len() != 2 {
                bad.extend(ks.iter().copied());
            }
        }
        if bad.is_empty() {
            // Vertices whose link is not one cycle (all edges are manifold here).
            let mut link: HashMap<VertexId, Vec<usize>> = HashMap::new();
            for (k, fct) in scan.facets.iter().enumerate() {
                for &v in &fct.v {
                    link.entry(v).or_default().push(k);
                }
            }
            for (&v, ks) in &link {
                if !is_disk(v, ks, scan) {
                    bad.extend(ks.iter().copied());
                }
            }
        }
        bad.sort_unstable();
        bad.dedup();
        let n = bad.len();
        for k in bad {
            let fct = &scan.facets[k];
            let Some(x) = fct.test.largest() else {
                continue;
            };
            let Some((d, j)) = self.t.neighbor(fct.cell, fct.facet) else {
                continue;
            };
            self.heap.push(Entry {
                class: Bad::Manifold,
                badness: x.radius,
                cell: fct.cell,
                facet: fct.facet,
                verts: self.t.cell_vertices(fct.cell),
                opposite: self.t.cell_vertices(d)[j],
                point: x.point,
                hint: fct.cell,
            });
        }
        n
    }
}

/// Seed points: the certified critical points of a generic height on S, each with a
/// seed triangle of radius `rho` around it (three points on its tangent circle,
/// projected onto S by Newton); when that search is incomplete, also every crossing
/// (certified isolation) of a fixed star of lines near the domain's centre (CGAL's
/// random rays, made reproducible). Points come with "from the fallback lines".
pub(crate) struct Seeds {
    pub crit: crate::implicit::critical::CriticalReport,
    pub points: Vec<([f64; 3], bool)>,
    /// The index in `points` of each critical point (in `crit.points` order).
    pub critical_at: Vec<usize>,
    pub regions: Vec<Uncertified>,
}

pub(crate) fn seed_points(
    f: &dyn Implicit,
    domain: &Aabb,
    rho: f64,
    critical_boxes: usize,
    budget: SegmentBudget,
) -> Seeds {
    let diam = domain.diagonal();
    let dbox = domain.intervals();
    let crit = critical_points_on_surface(
        f,
        Bx::new(domain.min, domain.max),
        None,
        Budget {
            max_boxes: critical_boxes,
            ..Budget::default()
        },
    );
    let mut regions = Vec::new();
    for u in crit.undecided.iter().take(20) {
        regions.push(Uncertified::new(
            Aabb {
                min: u.region.lo,
                max: u.region.hi,
            },
            format!(
                "critical-point search undecided here ({:?}): a component may be unseeded, or a singular point",
                u.reason
            ),
        ));
    }
    let (e1, e2) = match crit.problem {
        Problem::Height { e1, e2, .. } => (e1, e2),
        _ => ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
    };
    let mut points = Vec::new();
    let mut critical_at = Vec::with_capacity(crit.points.len());
    for cp in &crit.points {
        let x = cp.point;
        critical_at.push(points.len());
        points.push((x, false));
        // The seed triangle: three points of the tangent circle of radius r projected
        // onto S. When r is large for the surface there (a facet size beyond the
        // surface's size), the projections can land on one point, and the refinement
        // then works on a cluster of near-duplicate vertices until its limits (found
        // on the unit sphere with --facet-size 10). So each projection must stay at
        // r/3 to 3r from x and the three at least r/2 apart, else r is quartered (at
        // most SEED_TRIES times; then only x seeds this point).
        let mut r = rho;
        for _ in 0..SEED_TRIES {
            if r < MIN_SEPARATION * diam {
                break;
            }
            let tri: Vec<[f64; 3]> = (0..3)
                .filter_map(|k| {
                    let th = std::f64::consts::TAU * k as f64 / 3.0;
                    let q = add(x, add(scale(e1, r * th.cos()), scale(e2, r * th.sin())));
                    project(f, q, 30, 1e-14 * diam)
                        .filter(|&q| domain.contains(q) && (r / 3.0..3.0 * r).contains(&dist(q, x)))
                })
                .collect();
            let apart = |a: [f64; 3], b: [f64; 3]| dist(a, b) >= 0.5 * r;
            if tri.len() == 3
                && apart(tri[0], tri[1])
                && apart(tri[1], tri[2])
                && apart(tri[0], tri[2])
            {
                points.extend(tri.into_iter().map(|q| (q, false)));
                break;
            }
            r *= 0.25;
        }
    }
    if !crit.complete {
        let c = domain.center();
        let h = 0.5 * diam;
        for (k, d) in fallback_directions().into_iter().enumerate() {
            // Lines offset from the centre (a centre on S would make every line
            // tangent there, e.g. a cone's apex).
            let k = k as f64;
            let o = add(
                c,
                scale(
                    [(1.3 * k).sin(), (2.1 * k).cos(), (0.7 * k + 0.5).sin()],
                    0.2 * h,
                ),
            );
            let a = sub(o, scale(d, h));
            let b = add(o, scale(d, h));
            let test = test_segment(f, a, b, a, &dbox, budget);
            points.extend(test.crossings.iter().map(|x| (x.point, true)));
        }
    }
    Seeds {
        crit,
        points,
        critical_at,
        regions,
    }
}

/// 13 directions (3 axes, 4 diagonals, 6 face diagonals), slightly rotated so that no
/// line is a symmetry axis of the catalog's surfaces.
fn fallback_directions() -> Vec<[f64; 3]> {
    let mut v = vec![
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [1.0, 1.0, -1.0],
        [1.0, -1.0, 1.0],
        [-1.0, 1.0, 1.0],
        [1.0, 1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 0.0, 1.0],
        [1.0, 0.0, -1.0],
        [0.0, 1.0, 1.0],
        [0.0, 1.0, -1.0],
    ];
    for d in v.iter_mut() {
        let q = add(*d, [0.0123, 0.0311, 0.0457]);
        *d = scale(q, 1.0 / dot(q, q).sqrt());
    }
    v
}

/// Is the restricted star of `v` (facets `ks`, all with manifold edges) a single disk?
pub(crate) fn is_disk(v: VertexId, ks: &[usize], scan: &Scan) -> bool {
    // Link edges (a, b) opposite v; a single cycle iff connected and every link vertex
    // has degree 2 (degree 2 holds when the edges are manifold).
    let mut adj: HashMap<VertexId, Vec<VertexId>> = HashMap::new();
    for &k in ks {
        let f = scan.facets[k].v;
        let o: Vec<VertexId> = f.iter().copied().filter(|&w| w != v).collect();
        if o.len() != 2 {
            return false;
        }
        adj.entry(o[0]).or_default().push(o[1]);
        adj.entry(o[1]).or_default().push(o[0]);
    }
    if adj.values().any(|n| n.len() != 2) {
        return false;
    }
    let start = *adj.keys().next().unwrap();
    let mut seen = std::collections::HashSet::new();
    let mut stack = vec![start];
    while let Some(a) = stack.pop() {
        if seen.insert(a) {
            stack.extend(adj[&a].iter().copied());
        }
    }
    seen.len() == adj.len()
}

impl Mesher for BoissonnatOudot {
    fn name(&self) -> &'static str {
        "bo"
    }
    fn dim(&self) -> usize {
        3
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        check_input(f, domain, 3, "bo")?;
        let out = mesh_bo(self, f, domain, progress)?;
        Ok(out)
    }
}

/// The restricted facets of a scan as an oriented triangle mesh over the used vertices
/// (mesh vertex ids in kernel order).
pub(crate) fn to_mesh(t: &Delaunay, scan: &Scan) -> (TriMesh, Vec<VertexId>) {
    let mut map: HashMap<VertexId, u32> = HashMap::new();
    let mut order: Vec<VertexId> = Vec::new();
    let mut tris = Vec::with_capacity(scan.facets.len());
    for fct in &scan.facets {
        tris.push(fct.v.map(|v| {
            *map.entry(v).or_insert_with(|| {
                order.push(v);
                (order.len() - 1) as u32
            })
        }));
    }
    let vertices = order.iter().map(|&v| t.point(v)).collect();
    (
        TriMesh {
            vertices,
            triangles: tris,
        },
        order,
    )
}

/// A seed triangle below [`MIN_SEPARATION`] of the domain's diagonal is never placed,
/// and without one bo's refinement has no restricted facet to start from: its output is
/// empty, which would read as "no point of f = 0 found". So a facet size (seed radius
/// facet_size / 4) or `--set seed-radius` below that scale is refused up front, with
/// the smallest usable value.
fn check_seed_scale(p: &BoissonnatOudot, facet_size: f64, domain: &Aabb) -> Result<()> {
    let diam = domain.diagonal();
    let floor = MIN_SEPARATION * diam;
    let why = format!(
        "bo places no seed triangle of radius below {MIN_SEPARATION:e} of the domain's \
         diagonal ({}), and from isolated seed points alone the refinement may find no restricted facet \
         at all (then its output is empty, as if f = 0 had no point in the domain)",
        short_num(diam)
    );
    match p.seed_radius {
        Some(r) if r < floor => Err(Error::Param(format!(
            "--set seed-radius={} is too small for this domain: {why}; the smallest usable \
             seed-radius here is {}",
            short_num(r),
            round_up(floor)
        ))),
        Some(_) => Ok(()),
        None if facet_size / 4.0 < floor => {
            let given = if p.size_from_reach {
                format!(
                    "--set size=reach gives the facet size {} (0.99 x 0.099 x the certified \
                     reach bound), too small for this domain",
                    short_num(facet_size)
                )
            } else {
                format!(
                    "--facet-size {} is too small for this domain",
                    short_num(facet_size)
                )
            };
            Err(Error::Param(format!(
                "{given}: the seed triangles have radius facet-size / 4, and {why}; the \
                 smallest usable --facet-size here is {} (4 x {MIN_SEPARATION:e} x the diagonal)",
                round_up(4.0 * floor)
            )))
        }
        None => Ok(()),
    }
}

/// `x` rounded up to 3 significant digits (the printed value is at least `x`).
fn round_up(x: f64) -> String {
    if !(x.is_finite() && x > 0.0) {
        return short_num(x);
    }
    let e = x.log10().floor() as i32 - 2;
    let unit = 10f64.powi(e);
    let mut m = (x / unit).ceil();
    loop {
        let s = format!("{:.0}e{e}", m);
        match s.parse::<f64>() {
            Ok(v) if v >= x => return short_num(v),
            _ => m += 1.0,
        }
    }
}

fn mesh_bo(
    p: &BoissonnatOudot,
    f: &dyn Implicit,
    domain: &Aabb,
    progress: &dyn Progress,
) -> Result<MeshOutput> {
    let t0 = std::time::Instant::now();
    let diam = domain.diagonal();
    let facet_size = if p.facet_size.is_nan() {
        diam / 20.0
    } else {
        p.facet_size
    };
    let mut facet_distance = p.facet_distance.or(Some(diam / 200.0));
    let mut reach: Option<ReachBound> = None;
    let mut facet_size = facet_size;
    if p.size_from_reach {
        let rb = reach_lower_bound(f, Bx::new(domain.min, domain.max), p.reach_options());
        match rb.tau {
            Some(tau) => {
                // 1% below ψ: the certificate bounds each ball over its certified
                // piece (outward rounded), a little above the float radius refined to.
                facet_size = 0.99 * EPSILON * tau;
                if p.facet_distance.is_none() {
                    facet_distance = None;
                }
            }
            None => {
                return Err(Error::Param(format!(
                    "--set size=reach: no certified reach bound: {}",
                    rb.reason.unwrap_or_default()
                )))
            }
        }
        reach = Some(rb);
    }
    check_seed_scale(p, facet_size, domain)?;
    let params = BoissonnatOudot {
        facet_size,
        facet_distance,
        ..p.clone()
    };
    let t = Delaunay::with_domain(domain.min, domain.max, p.seed)?;
    let mut run = Run {
        f,
        domain: *domain,
        dbox: domain.intervals(),
        p: &params,
        t,
        cc: Vec::new(),
        heap: BinaryHeap::new(),
        stats: BoStats {
            facet_angle: p.facet_angle,
            facet_size,
            facet_distance,
            manifold: p.manifold,
            ..Default::default()
        },
        sin2_bound: p.facet_angle.to_radians().sin().powi(2),
        delta_min: MIN_SEPARATION * diam,
        budget: SegmentBudget::default(),
        undecided_left: p.max_undecided_insertions,
        reported_undecided: Vec::new(),
    };
    let mut regions: Vec<Uncertified> = Vec::new();
    let mut notes: Vec<String> = Vec::new();
    if p.facet_angle > 30.0 {
        notes.push(format!(
            "facet_angle {} > 30: termination is proven only up to 30 degrees",
            p.facet_angle
        ));
    }

    // 1. Seeds.
    progress.start("bo seeds", 0);
    let rho = p.seed_radius.unwrap_or(facet_size / 4.0);
    let seeds = seed_points(f, domain, rho, p.critical_boxes, run.budget);
    let crit = seeds.crit;
    run.stats.critical_points = crit.points.len();
    run.stats.seeding_complete = crit.complete;
    regions.extend(seeds.regions);
    let mut seed_ids: Vec<VertexId> = Vec::new();
    let mut point_vertex: Vec<Option<VertexId>> = Vec::with_capacity(seeds.points.len());
    for (q, fallback) in seeds.points {
        match run.t.insert(q) {
            Ok(v) => {
                seed_ids.push(v);
                point_vertex.push(Some(v));
                run.stats.fallback_seeds += fallback as usize;
            }
            Err(_) => {
                point_vertex.push(None);
                run.stats.refused += 1
            }
        }
    }
    // The seed vertex of each critical point (None: its insertion was refused).
    let critical_vertex: Vec<Option<VertexId>> =
        seeds.critical_at.iter().map(|&i| point_vertex[i]).collect();
    run.stats.seed_vertices = seed_ids.len();
    let cells: Vec<CellId> = run.t.cells().collect();
    for &c in &cells {
        run.refresh_cc(c);
    }
    for (c, i, _, _) in run.t.facets(false).collect::<Vec<_>>() {
        run.test_facet(c, i);
    }

    // 2-3. Refinement and the manifold phase.
    progress.start("bo refinement", 0);
    let mut stop = None;
    let mut scan;
    // With --certify: the certified scan of the final triangulation, when it was
    // computed here (see below).
    let mut certified_scan: Option<Scan> = None;
    // Time in those certified scans: counted as certification, not refinement.
    let mut certified_scan_seconds = 0.0;
    loop {
        loop {
            if stop.is_none() {
                stop = run.refine(t0, progress);
            }
            scan = restricted::scan(&run.t, f, domain, &run.cc, Ends3::Float, run.budget);
            if stop.is_some() || !p.manifold {
                break;
            }
            if run.stats.manifold_rounds >= p.max_manifold_rounds {
                stop = Some(format!(
                    "manifold phase stopped after {} rounds",
                    p.max_manifold_rounds
                ));
                break;
            }
            let queued = run.queue_manifold(&scan);
            if queued == 0 {
                break;
            }
            run.stats.manifold_rounds += 1;
        }
        if !p.certify || stop.is_some() {
            break;
        }
        // The certified scan (interval circumcentres) can find a grazing crossing the
        // float refinement did not: insert its tangency point (projected onto S) and
        // refine again, a few rounds at most; what is left is reported below.
        let ts = std::time::Instant::now();
        let cert = restricted::scan(&run.t, f, domain, &run.cc, Ends3::Certified, run.budget);
        certified_scan_seconds += ts.elapsed().as_secs_f64();
        if cert.undecided.is_empty() || run.stats.certify_rounds >= MAX_CERTIFY_ROUNDS {
            certified_scan = Some(cert);
            break;
        }
        run.stats.certify_rounds += 1;
        let mut inserted = 0;
        for u in &cert.undecided {
            let Some(&x) = u.points.first() else { continue };
            let q = project(f, x, 30, 1e-14 * domain.diagonal()).unwrap_or(x);
            let q = if domain.contains(q) { q } else { x };
            if run.insert(q, u.cell, "undecided (certify)") {
                inserted += 1;
            }
        }
        if inserted == 0 {
            certified_scan = Some(cert);
            break;
        }
    }
    for u in &run.reported_undecided {
        regions.push(Uncertified::new(
            Aabb {
                min: *u,
                max: *u,
            }
            .inflate(1e-9 * diam),
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
    run.stats.seconds_refine = t0.elapsed().as_secs_f64() - certified_scan_seconds;

    // 6. Certificate.
    let mut claims: Vec<Claim> = Vec::new();
    let mut reason = String::from(
        "ambient isotopy (Boissonnat-Oudot, Theorems 3-4) not certified: no certified reach bound (psi <= 0.1 lfs unproven)",
    );
    if p.certify {
        let tc = std::time::Instant::now();
        progress.start("bo certify", 0);
        let check = run.t.check();
        run.stats.delaunay_valid = Some(check.valid);
        let cert = match certified_scan.take() {
            Some(c) => c,
            None => restricted::scan(&run.t, f, domain, &run.cc, Ends3::Certified, run.budget),
        };
        let mut a: Vec<[VertexId; 3]> = scan.facets.iter().map(|x| key(x.v)).collect();
        let mut b: Vec<[VertexId; 3]> = cert.facets.iter().map(|x| key(x.v)).collect();
        a.sort_unstable();
        b.sort_unstable();
        let mismatches = {
            let sa: std::collections::HashSet<_> = a.iter().collect();
            let sb: std::collections::HashSet<_> = b.iter().collect();
            sa.symmetric_difference(&sb).count()
        };
        run.stats.certified_segments = Some(cert.segments);
        run.stats.certified_undecided = Some(cert.undecided.len());
        run.stats.certified_mismatches = Some(mismatches);
        for u in cert.undecided.iter().take(20) {
            let p0 = u
                .points
                .first()
                .copied()
                .unwrap_or_else(|| run.t.point(u.v[0]));
            regions.push(Uncertified::new(
                Aabb { min: p0, max: p0 }.inflate(1e-9 * diam),
                format!(
                    "grazing: dual Voronoi edge of facet {:?}: {}",
                    u.v, u.reason
                ),
            ));
        }
        if check.valid && cert.undecided.is_empty() && cert.far_lemma {
            claims.push(Claim::RestrictedDelaunay {
                facets: cert.facets.len(),
                voronoi_edges: cert.segments,
                multiple_crossings: cert.multiple_crossings,
            });
            // The output is the certified set.
            scan = cert;
            // Theorem 3 of the chapter: a weak eps-sample with eps < 0.1.
            let rb = match reach.take() {
                Some(rb) => rb,
                None => reach_lower_bound(f, Bx::new(domain.min, domain.max), p.reach_options()),
            };
            let r_sup = scan
                .facets
                .iter()
                .flat_map(|x| x.test.crossings.iter().map(|c| c.radius_sup))
                .fold(0.0f64, f64::max);
            run.stats.certified_max_ball_radius = Some(r_sup);
            match rb.tau {
                None => {
                    reason = format!(
                        "ambient isotopy (Boissonnat-Oudot, Theorems 3-4) not certified: no certified reach bound ({})",
                        rb.reason.clone().unwrap_or_default()
                    );
                }
                Some(tau) => {
                    let psi = EPSILON * tau;
                    if r_sup <= psi {
                        claims.push(Claim::WeakSample {
                            psi,
                            reach_lower_bound: tau,
                            max_ball_radius: r_sup,
                        });
                        reason = if !crit.complete {
                            "ambient isotopy (Boissonnat-Oudot, Theorem 3) not certified: the seeding is incomplete (a component may have no sample)".to_string()
                        } else {
                            let tp = std::time::Instant::now();
                            let r = perturbed_isotopy(
                                &run.t,
                                f,
                                domain,
                                &scan,
                                PerturbedInputs {
                                    tau,
                                    psi,
                                    crit: &crit,
                                    critical_vertex: &critical_vertex,
                                    budget: run.budget,
                                },
                            );
                            run.stats.seconds_perturbed = tp.elapsed().as_secs_f64();
                            let why = match r.failure.clone() {
                                None => String::new(),
                                Some(w) => format!("ambient isotopy (Boissonnat-Oudot, Theorem 3) not certified: {w}"),
                            };
                            if r.failure.is_none() {
                                claims.push(Claim::PerturbedSample {
                                    max_offset: r.max_offset,
                                    cells: r.robustness.cells,
                                    facets: r.robustness.facets,
                                    exactly_cospherical: r.robustness.far_face_cospherical
                                        + r.robustness.sphere_cospherical,
                                    max_ball_radius: r.max_ball_radius,
                                });
                                claims.push(Claim::Isotopic {
                                    inside: *domain,
                                    theorem: ISOTOPY_THEOREM.into(),
                                    generic_position: false,
                                });
                            } else if let Some(p0) = r.location {
                                regions.push(Uncertified::new(
                                    Aabb { min: p0, max: p0 }.inflate(1e-9 * diam),
                                    why.clone(),
                                ));
                            }
                            run.stats.perturbed = Some(r);
                            why
                        };
                    } else {
                        reason = format!(
                            "ambient isotopy (Boissonnat-Oudot, Theorems 3-4) not certified: surface Delaunay balls up to {r_sup:.3e} exceed psi = 0.099 x certified reach bound {tau:.3e} = {psi:.3e} (refine with --set size=reach)"
                        );
                    }
                }
            }
            run.stats.reach = Some(rb);
        } else {
            reason = format!(
                "restricted triangulation not certified: {}; {reason}",
                if !check.valid {
                    format!(
                        "Delaunay check failed ({})",
                        check.first_problem.unwrap_or_default()
                    )
                } else if !cert.far_lemma {
                    "no vertex, or a vertex outside the domain (the far-corner lemma does not apply)"
                        .to_string()
                } else {
                    format!("{} dual segments undecided", cert.undecided.len())
                }
            );
        }
        run.stats.seconds_certify = tc.elapsed().as_secs_f64() + certified_scan_seconds;
    }

    let (mesh, order) = to_mesh(&run.t, &scan);
    run.stats.vertices = run.vertex_count();
    run.stats.facets = mesh.triangles.len();
    run.stats.multiple_crossing_segments = scan.multiple_crossings;
    let used: std::collections::HashSet<VertexId> = order.iter().copied().collect();
    run.stats.seeds_not_incident = seed_ids.iter().filter(|v| !used.contains(v)).count();
    let mut min_angle = f64::INFINITY;
    let mut max_r: f64 = 0.0;
    let mut max_d: f64 = 0.0;
    for fct in &scan.facets {
        let q = fct.v.map(|v| run.t.point(v));
        min_angle = min_angle.min(sin2_min_angle(q[0], q[1], q[2]).sqrt().asin().to_degrees());
        let cc = triangle_circumcentre(q[0], q[1], q[2]);
        for x in &fct.test.crossings {
            max_r = max_r.max(x.radius);
            max_d = max_d.max(dist(cc, x.point));
        }
    }
    if !scan.facets.is_empty() {
        run.stats.min_angle_deg = Some(min_angle);
        run.stats.max_ball_radius = Some(max_r);
        run.stats.max_distance = Some(max_d);
    }
    if !crit.complete {
        reason = format!("seeding not certified: the critical-point search is incomplete ({} undecided boxes); {reason}", crit.undecided.len());
    }
    run.stats.refinement_complete = stop.is_none();
    run.stats.stop_reason = stop;
    let mut stats = stats_map(&run.stats);
    if !notes.is_empty() {
        stats.insert("notes".into(), notes.into());
    }
    // Certified only with the isotopy claim; a run stopped by a guard may still be
    // (the claims are about the output, whose criteria `refinement_complete` reports).
    let certificate =
        if reason.is_empty() && claims.iter().any(|c| matches!(c, Claim::Isotopic { .. })) {
            Certificate::certified(claims)
        } else {
            Certificate::uncertified(reason, claims, regions)
        };
    Ok(MeshOutput {
        mesh: Mesh::Surface(mesh),
        certificate,
        stats,
        angles: None,
    })
}
