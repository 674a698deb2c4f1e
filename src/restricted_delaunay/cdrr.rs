//! Cheng–Dey–Ramos–Ray topology refinement (`--algo cdrr`): the chapter "Meshing of
//! Surfaces" (Boissonnat et al., 2007), §1.3.2, "Topology Refinement Algorithm":
//! check tests (1)–(4) in this order, insert the point a failed test defines, repeat
//! until nothing is inserted. Then the topological ball property holds and the
//! restricted Delaunay triangulation is homeomorphic to S (Theorem 5) — the claim
//! `homeomorphic (topological ball property)`, never isotopy (Research Problem 4).
//!
//! 1. **Seeds**: the certified critical points of a generic height with a small seed
//!    triangle each (shared with `bo`). They only speed the start: a component
//!    without samples lies in some Voronoi cell and fails test (4) there.
//! 2. **Rounds**: run the checks of [`super::tbp`] with `stop_early` (the tests in
//!    the chapter's order, each on every Voronoi face); the failures of the first
//!    failing test give the round's insertions:
//!    (1) a Voronoi edge crossing S twice or more: the crossing farthest from its
//!    sites; an undecided (tangent, grazing) crossing: its approximate point
//!    projected onto S; (2) a non-manifold edge or vertex p: the crossing farthest
//!    from p over the restricted facets at p; (3) a Voronoi facet and (4) a Voronoi
//!    cell that could not be proven: the centre of the first box not decided,
//!    projected onto S by Newton (the chapter inserts a point of S it computes; any
//!    point of S is harmless to correctness, it only matters for termination).
//!    Points of one round closer to each other than half their distance to the
//!    failing site are inserted once.
//! 3. **Geometry** (optional, `--facet-size`): once the TBP holds, facets whose
//!    largest surface Delaunay ball exceeds the size get their crossing inserted,
//!    and the topology rounds run again (the chapter's "Improving the Geometry").
//! 4. **Guards**: `--max-vertices`, `--time-limit`, a round limit; a round that
//!    inserts nothing (every point refused, or a failure with no point of S near)
//!    stops the run. A run stopped by a guard reports the Voronoi faces where the
//!    certificate failed, as uncertified regions. The time limit counts from the
//!    start of the run and bounds the checks too: a check that reaches it leaves its
//!    remaining Voronoi faces unproven ([`TbpOptions::deadline`]), and the final check
//!    with the full cover budget runs only while time is left.
use super::bo::{seed_points, to_mesh, triangle_circumcentre};
use super::tbp::{self, Failure, TbpOptions, TbpReport, Test};
use crate::error::{Error, Result};
use crate::implicit::ops::{project, SegmentBudget};
use crate::implicit::Implicit;
use crate::kernel::delaunay::Delaunay;
use crate::kernel::geom::{dist, Aabb};
use crate::mesher::options::MesherOptions;
use crate::mesher::{
    check_input, stats_map, Certificate, Claim, HomeomorphismBy, Mesh, MeshOutput, Mesher,
    Progress, Uncertified,
};
use serde::Serialize;
use std::collections::BTreeMap;

/// The `--set` keys of `cdrr`.
pub const SETTINGS: &[&str] = &["seed", "rounds", "cover-boxes", "critical-boxes"];

/// Cheng–Dey–Ramos–Ray refinement; see the module documentation.
#[derive(Clone, Debug)]
pub struct ChengDeyRamosRay {
    pub max_vertices: usize,
    pub time_limit: Option<f64>,
    pub max_rounds: usize,
    /// Geometry rounds: the largest surface Delaunay ball allowed.
    pub facet_size: Option<f64>,
    pub seed: u64,
    pub critical_boxes: usize,
    /// Box budget of one facet or cell check.
    pub cover_boxes: u32,
}

impl Default for ChengDeyRamosRay {
    fn default() -> Self {
        ChengDeyRamosRay {
            max_vertices: 200_000,
            time_limit: None,
            max_rounds: 300,
            facet_size: None,
            seed: 1,
            critical_boxes: 200_000,
            cover_boxes: 3000,
        }
    }
}

impl ChengDeyRamosRay {
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        o.check_keys("cdrr", SETTINGS)?;
        let mut m = ChengDeyRamosRay::default();
        if let Some(n) = o.max_vertices {
            if n < 4 {
                return Err(Error::Param("--max-vertices must be at least 4".into()));
            }
            m.max_vertices = n;
        }
        if let Some(s) = o.facet_size {
            if !(s.is_finite() && s > 0.0) {
                return Err(Error::Param(format!(
                    "--facet-size must be a positive number, got {s}"
                )));
            }
            m.facet_size = Some(s);
        }
        m.time_limit = Some(o.time_limit_or_default());
        if let Some(s) = o.get::<u64>("seed")? {
            m.seed = s;
        }
        if let Some(n) = o.get::<usize>("rounds")? {
            m.max_rounds = n.max(1);
        }
        if let Some(n) = o.get::<u32>("cover-boxes")? {
            m.cover_boxes = n.max(16);
        }
        if let Some(n) = o.get::<usize>("critical-boxes")? {
            m.critical_boxes = n.max(1);
        }
        Ok(m)
    }
}

/// Statistics of a run (the report's `stats`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct CdrrStats {
    pub vertices: usize,
    pub facets: usize,
    pub seed_vertices: usize,
    pub critical_points: usize,
    pub seeding_complete: bool,
    pub rounds: usize,
    /// Insertions per test that defined them (edge, manifold, facet, cell, size).
    pub insertions_by_test: BTreeMap<String, usize>,
    pub refused: usize,
    pub refinement_complete: bool,
    pub stop_reason: Option<String>,
    /// The last check.
    pub tbp: TbpReport,
    pub seconds_checks: f64,
}

fn test_name(t: Test) -> &'static str {
    match t {
        Test::Setup => "setup",
        Test::Edge => "edge",
        Test::Manifold => "manifold",
        Test::Facet => "facet",
        Test::Cell => "cell",
    }
}

/// A failure's refinement points (best first), its site, and the test's name.
type Candidates = (Vec<[f64; 3]>, [f64; 3], &'static str);

/// The points a failed test defines, best first (each on S, inside the domain). An
/// undecided Voronoi edge (a tangent crossing, or end points enclosed too loosely, as
/// for a sliver's circumcentre) also offers the projections of its cells' circumcentres
/// (a projection lies in the circumsphere when the cell's vertices are on S) and of its
/// dual triangle's circumcentre (a point of the edge's line).
fn refinement_points(f: &dyn Implicit, domain: &Aabb, t: &Delaunay, x: &Failure) -> Vec<[f64; 3]> {
    let tol = 1e-14 * domain.diagonal();
    let on_s = |q: [f64; 3]| -> Option<[f64; 3]> {
        if f.eval(q).abs() < 1e-12 {
            Some(q)
        } else {
            project(f, q, 40, tol)
        }
    };
    let mut cands: Vec<[f64; 3]> = Vec::new();
    match x.test {
        Test::Setup => {}
        Test::Edge if x.sites.len() == 3 => {
            cands.push(x.point);
            cands.extend(x.alternatives.iter().copied());
            let s = [0, 1, 2].map(|k| t.point(x.sites[k]));
            cands.push(triangle_circumcentre(s[0], s[1], s[2]));
        }
        _ => cands.push(x.point),
    }
    cands
        .into_iter()
        .filter_map(on_s)
        .filter(|q| domain.contains(*q))
        .collect()
}

impl Mesher for ChengDeyRamosRay {
    fn name(&self) -> &'static str {
        "cdrr"
    }
    fn dim(&self) -> usize {
        3
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        check_input(f, domain, 3, "cdrr")?;
        let t0 = std::time::Instant::now();
        let diam = domain.diagonal();
        let mut stats = CdrrStats::default();
        let mut t = Delaunay::with_domain(domain.min, domain.max, self.seed)?;
        progress.start("cdrr seeds", 0);
        let rho = self.facet_size.map(|s| s / 4.0).unwrap_or(diam / 80.0);
        let seeds = seed_points(
            f,
            domain,
            rho,
            self.critical_boxes,
            SegmentBudget::default(),
        );
        stats.critical_points = seeds.crit.points.len();
        stats.seeding_complete = seeds.crit.complete;
        for (q, _) in &seeds.points {
            match t.insert(*q) {
                Ok(_) => stats.seed_vertices += 1,
                Err(_) => stats.refused += 1,
            }
        }
        // Rounds use a small cover budget (a face not proven quickly gets a point);
        // a face proven with any budget is proven, so the cache keeps it.
        // The time limit bounds the rounds' checks and the final one too.
        let deadline = self
            .time_limit
            .map(|tl| t0 + std::time::Duration::from_secs_f64(tl));
        let opts = TbpOptions {
            deadline,
            stop_early: true,
            cover: tbp::cover::CoverBudget {
                max_boxes: (self.cover_boxes / 10).max(16),
                ..Default::default()
            },
            directions: 2,
            ..Default::default()
        };
        let full = TbpOptions {
            deadline,
            stop_early: false,
            cover: tbp::cover::CoverBudget {
                max_boxes: self.cover_boxes,
                ..Default::default()
            },
            ..Default::default()
        };
        let mut cache = tbp::TbpCache::default();
        progress.start("cdrr rounds", 0);
        let mut stop: Option<String> = None;
        let check = loop {
            let tc = std::time::Instant::now();
            let check = tbp::check_cached(&t, f, domain, &opts, &mut cache);
            let check_seconds = tc.elapsed().as_secs_f64();
            stats.seconds_checks += check_seconds;
            stats.rounds += 1;
            progress.inc(1);
            let mut points: Vec<Candidates> = Vec::new();
            if check.failures.iter().any(|x| x.test == Test::Setup) {
                stop = Some(format!(
                    "a hypothesis of the certificate fails: {}",
                    check
                        .failures
                        .iter()
                        .filter(|x| x.test == Test::Setup)
                        .map(|x| x.reason.as_str())
                        .collect::<Vec<_>>()
                        .join("; ")
                ));
                break check;
            }
            // The time limit, before the refinement points are computed (a Newton
            // projection or more per failure).
            let over = |tl: f64| t0.elapsed().as_secs_f64() > tl;
            if let Some(tl) = self
                .time_limit
                .filter(|&tl| !check.report.holds && over(tl))
            {
                stop = Some(format!("time limit reached: {tl} s (raise --time-limit)"));
                break check;
            }
            for x in &check.failures {
                let qs = refinement_points(f, domain, &t, x);
                if let Some(&q) = qs.first() {
                    let site = x.sites.first().map(|&v| t.point(v)).unwrap_or(q);
                    points.push((qs, site, test_name(x.test)));
                }
            }
            if check.report.holds {
                // Geometry: surface balls larger than the size bound.
                if let Some(size) = self.facet_size {
                    for fct in &check.rdt.facets {
                        if let Some(c) = fct.test.largest() {
                            if c.radius > size {
                                points.push((vec![c.point], t.point(fct.v[0]), "size"));
                            }
                        }
                    }
                }
                if points.is_empty() {
                    break check;
                }
            }
            if stats.rounds >= self.max_rounds {
                stop = Some(format!("round limit reached: {} rounds", self.max_rounds));
                break check;
            }
            // The next round's check costs about this one's times the growth of the
            // triangulation (its scan and exact check are linear in the cells): stop
            // now when it would end past the limit (the geometry rounds included).
            let n = t.points().len() - crate::kernel::delaunay::FAR as usize;
            let next = check_seconds * (n + points.len()) as f64 / n.max(1) as f64;
            if let Some(tl) = self.time_limit.filter(|&tl| over(tl - next)) {
                stop = Some(format!(
                    "time limit reached: {tl} s (the next round's check would end past it, about {next:.1} s; raise --time-limit)"
                ));
                break check;
            }
            // One insertion per neighbourhood of a round.
            let mut chosen: Vec<[f64; 3]> = Vec::new();
            let mut inserted = 0;
            'failures: for (qs, site, why) in points {
                let r = 0.5 * dist(qs[0], site);
                if chosen.iter().any(|c| dist(*c, qs[0]) < r) {
                    continue;
                }
                let n = t.points().len() - crate::kernel::delaunay::FAR as usize;
                if n >= self.max_vertices {
                    break;
                }
                for q in qs {
                    match t.insert(q) {
                        Ok(_) => {
                            chosen.push(q);
                            inserted += 1;
                            *stats.insertions_by_test.entry(why.into()).or_default() += 1;
                            continue 'failures;
                        }
                        Err(_) => stats.refused += 1,
                    }
                }
            }
            let n = t.points().len() - crate::kernel::delaunay::FAR as usize;
            if n >= self.max_vertices {
                stop = Some(format!(
                    "vertex budget reached: {} vertices (raise --max-vertices)",
                    self.max_vertices
                ));
                break check;
            }
            if inserted == 0 {
                stop = Some(
                    "no refinement point could be inserted for the failing Voronoi faces (none projects onto S inside the domain, or all are duplicates)"
                        .into(),
                );
                break check;
            }
        };
        // A run stopped by a guard: the final check with the full budget (it may prove
        // faces the rounds' small budget could not) and every test reported, unless the
        // time limit has passed (then the last round's check, which is cut short by the
        // deadline too, is the report).
        let setup_failed = check.failures.iter().any(|x| x.test == Test::Setup);
        let out_of_time = deadline.is_some_and(|d| std::time::Instant::now() >= d);
        let check = if check.report.holds || setup_failed || out_of_time {
            check
        } else {
            let c = tbp::check_cached(&t, f, domain, &full, &mut cache);
            if c.report.holds {
                stop = None;
            }
            c
        };
        let (mesh, _) = to_mesh(&t, &check.rdt);
        stats.vertices = t.points().len() - crate::kernel::delaunay::FAR as usize;
        stats.facets = mesh.triangles.len();
        stats.refinement_complete = stop.is_none() && check.report.holds;
        stats.stop_reason = stop.clone();
        stats.tbp = check.report.clone();
        let certificate = certificate(&check, stop.as_deref(), diam);
        Ok(MeshOutput {
            mesh: Mesh::Surface(mesh),
            certificate,
            stats: stats_map(&stats),
            angles: None,
        })
    }
}

/// The certificate of a TBP check: `homeomorphic (topological ball property)` when it
/// holds, else uncertified with the failing Voronoi faces.
pub fn certificate(check: &tbp::Tbp, stop: Option<&str>, diam: f64) -> Certificate {
    let r = &check.report;
    if r.holds {
        let claims = vec![
            Claim::RestrictedDelaunay {
                facets: check.rdt.facets.len(),
                voronoi_edges: check.rdt.segments,
                multiple_crossings: check.rdt.multiple_crossings,
            },
            Claim::Homeomorphic {
                by: HomeomorphismBy::TopologicalBallProperty,
                voronoi_edges: r.voronoi_edges,
                voronoi_facets: r.voronoi_facets,
                voronoi_cells: r.voronoi_cells,
            },
        ];
        return Certificate::certified(claims);
    }
    let regions: Vec<Uncertified> = check
        .failures
        .iter()
        .take(20)
        .map(|x| {
            Uncertified::new(
                Aabb {
                    min: x.point,
                    max: x.point,
                }
                .inflate(1e-9 * diam),
                format!("topological ball property, test {:?}: {}", x.test, x.reason),
            )
        })
        .collect();
    let first = check
        .failures
        .first()
        .map(|x| x.reason.clone())
        .unwrap_or_else(|| {
            format!(
                "tests not run{}: {:?}",
                if r.timed_out {
                    " before the time limit"
                } else {
                    ""
                },
                r.skipped
            )
        });
    Certificate::uncertified(
        format!(
            "topological ball property not proven ({} edge, {} manifold, {} facet, {} cell failures; first: {first}){}",
            r.edge_failures,
            r.manifold_failures,
            r.facet_failures,
            r.cell_failures,
            stop.map(|s| format!("; stopped: {s}")).unwrap_or_default()
        ),
        Vec::new(),
        regions,
    )
}
