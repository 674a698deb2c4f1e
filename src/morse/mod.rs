//! Morse theory for implicit surfaces (the chapter "Meshing of Surfaces", Boissonnat,
//! Cohen-Steiner, Mourrain, Rote, Vegter, 2007, §1.5): the certified Morse census of
//! `certmesh morse` ([`analyze`], [`MorseReport`]) and the Stander–Hart sweep
//! ([`stander_hart`], `--algo stander-hart`).
//!
//! The census reports, from the interval Krawczyk machinery of
//! [`crate::implicit::critical`]:
//! * the critical points of f (∇f = 0) in the domain with isolating boxes, value
//!   enclosures and certified Morse indices; boxes where nothing was decided are
//!   summarised by reason (the torus's circle of minima gives "possibly degenerate"
//!   boxes all along the circle: f is then reported as *not proven Morse*, never
//!   guessed);
//! * χ({f ≤ 0}) = Σ_{f(p) < 0} (−1)^index and χ(S) = 2·χ({f ≤ 0}) when every
//!   hypothesis is proven ([`crate::implicit::critical::sublevel_euler_characteristic`]);
//! * the census #min − #saddle + #max of a height ⟨n, x⟩ on S, which is χ(S) when the
//!   search on S is complete, every index certified and S away from ∂D
//!   ([`crate::implicit::critical::euler_characteristic`]);
//! * optionally the χ of a mesh beside the certified one ([`MorseReport::with_mesh`]).
//!
//! Not certified by critical data alone: the number of components and their nesting
//! (the chapter's Fig. 1.23: two functions with the same critical points, values and
//! indices can have non-homeomorphic zero sets); χ(S) is what Morse counting gives.
use crate::implicit::critical::{
    self, Budget, Bx, CriticalPoint, CriticalReport, MorseIndex, Problem, Side, Stats, UndecidedBox,
};
use crate::implicit::Implicit;
use crate::mesh::TriMesh;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

pub mod bcsv;
pub mod octree;
pub mod patch;
pub mod remedy;
pub mod stander_hart;

/// The budgets and the height direction of a census.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct MorseOptions {
    /// The search for ∇f = 0 (default: depth 30, 400 000 boxes; a degenerate critical
    /// set such as the torus's circle spends the box budget, and is reported).
    pub gradient: Budget,
    /// The search for the critical points of the height on S (default [`Budget`]).
    pub surface: Budget,
    /// The height direction (`None`: [`critical::DEFAULT_DIRECTION`]).
    pub direction: Option<[f64; 3]>,
    /// Count the critical points of g = f·h instead of f (the chapter's remedy for
    /// degenerate critical points, [`remedy`]); `None`: f itself. Explicit only, and
    /// reported ([`MorseReport::transformation`]).
    #[serde(skip)]
    pub remedy: Option<remedy::Remedy>,
}

impl Default for MorseOptions {
    fn default() -> Self {
        MorseOptions {
            gradient: Budget {
                max_depth: 30,
                ..Budget::default()
            },
            surface: Budget::default(),
            direction: None,
            remedy: None,
        }
    }
}

impl MorseOptions {
    /// The same options with at most `n` boxes per search.
    pub fn with_max_boxes(mut self, n: usize) -> Self {
        self.gradient.max_boxes = n;
        self.surface.max_boxes = n;
        self
    }
}

/// One isolated critical point as the report lists it.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MorsePoint {
    /// A small box proven to contain the critical point.
    pub enclosure: Bx,
    /// The box in which it is proven the only critical point.
    pub isolating: Bx,
    pub point: [f64; 3],
    /// Enclosure of the critical value (f, or the height on S).
    pub value: [f64; 2],
    pub index: MorseIndex,
    /// minimum, saddle (index 1), saddle (index 2), maximum (of f); minimum, saddle,
    /// maximum (height on S); or "possibly degenerate" / "index undecided".
    pub kind: String,
    /// For critical points of f: the side of the level 0 (f < 0 counted in χ({f ≤ 0})).
    pub side: Option<Side>,
}

/// The undecided boxes of a search, summarised (the torus yields 10⁵ of them).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct UndecidedSummary {
    pub count: usize,
    /// Count per reason (`possibly-degenerate`, `budget`, ...).
    pub by_reason: BTreeMap<String, usize>,
    /// The bounding box of all undecided boxes.
    pub hull: Option<Bx>,
    /// An enclosure of f over all of them (the hull of the per-box enclosures).
    pub f_range: Option<[f64; 2]>,
    /// The first few boxes, for inspection.
    pub examples: Vec<UndecidedBox>,
}

impl UndecidedSummary {
    fn of(f: &dyn Implicit, u: &[UndecidedBox]) -> Self {
        let mut s = UndecidedSummary {
            count: u.len(),
            ..Default::default()
        };
        for b in u {
            let r = serde_json::to_value(b.reason)
                .ok()
                .and_then(|v| v.as_str().map(String::from))
                .unwrap_or_else(|| format!("{:?}", b.reason));
            *s.by_reason.entry(r).or_default() += 1;
            let h = s.hull.get_or_insert(b.region);
            for k in 0..3 {
                h.lo[k] = h.lo[k].min(b.region.lo[k]);
                h.hi[k] = h.hi[k].max(b.region.hi[k]);
            }
            let v = f.eval_interval(&b.region.to_ibox());
            let (lo, hi) = if v.is_empty() {
                (f64::NEG_INFINITY, f64::INFINITY)
            } else {
                (v.inf(), v.sup())
            };
            let r = s.f_range.get_or_insert([lo, hi]);
            r[0] = r[0].min(lo);
            r[1] = r[1].max(hi);
        }
        s.examples = u.iter().take(8).cloned().collect();
        s
    }
}

/// The critical points of f (∇f = 0).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GradientCensus {
    /// Every box excluded, covered or isolated: `points` is every critical point.
    pub complete: bool,
    /// Complete and every index certified: f is proven Morse on the domain.
    pub morse: bool,
    /// Why f is not proven Morse (`None` when it is).
    pub not_morse_reason: Option<String>,
    pub points: Vec<MorsePoint>,
    /// Certified indices 0..3 over all points, and points without a certified index.
    pub index_counts: [usize; 4],
    pub without_index: usize,
    pub undecided: UndecidedSummary,
    pub stats: Stats,
}

/// χ({f ≤ 0}) and χ(S) = 2χ({f ≤ 0}) from the critical points of f.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SublevelChi {
    pub chi_sublevel: Option<i64>,
    pub chi_surface: Option<i64>,
    pub reason: Option<String>,
    /// The counted critical points (f < 0) by index.
    pub counted: [usize; 4],
    pub boundary_positive: bool,
    /// Undecided boxes proven to lie in {f > 0} (harmless) and the others.
    pub undecided_above: usize,
    pub undecided_blocking: usize,
}

/// The census of a height function on S.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct HeightCensus {
    /// The requested direction d.
    pub direction: [f64; 3],
    /// The exact height direction n = e₁ × e₂ (midpoint; within ulps of d/|d|).
    pub normal: [f64; 3],
    pub complete: bool,
    pub points: Vec<MorsePoint>,
    pub minima: usize,
    pub saddles: usize,
    pub maxima: usize,
    pub without_index: usize,
    /// #min − #saddle + #max over the certified points (a count, not a claim).
    pub census: i64,
    /// χ(S), present only when certified.
    pub chi: Option<i64>,
    pub reason: Option<String>,
    /// 0 ∉ □f on every piece of ∂D.
    pub boundary_clear: bool,
    pub undecided: UndecidedSummary,
    pub stats: Stats,
}

/// The χ of a mesh beside the certified one.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MeshCheck {
    /// Where the mesh came from (a file name).
    pub source: String,
    pub euler_characteristic: i64,
    pub components: usize,
    pub genus: Vec<usize>,
    pub closed: bool,
    pub manifold: bool,
    /// The mesh χ equals the certified χ(S) (`None`: no certified χ).
    pub agrees: Option<bool>,
}

/// The report of `certmesh morse`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MorseReport {
    pub domain: Bx,
    pub gradient: GradientCensus,
    pub sublevel: SublevelChi,
    pub height: HeightCensus,
    /// χ(S), when at least one of the two certificates holds.
    pub chi: Option<i64>,
    /// Which certificates gave it: "sublevel", "height" or both.
    pub chi_from: Vec<String>,
    /// Both certified and different: an internal inconsistency (a bug), never silent.
    pub inconsistent: bool,
    pub mesh: Option<MeshCheck>,
    /// The transformation whose critical points the f census counts, when one was
    /// asked for (`--remedy`): the gradient census and χ({f ≤ 0}) are then those of g.
    pub transformation: Option<Transformation>,
    pub seconds: f64,
}

/// What the census of a transformed function proves about f (see [`remedy`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Transformation {
    /// `smooth` (h = a + |x − b|²) or `chapter` (h = a + |x − b|).
    pub kind: String,
    pub a: f64,
    pub b: [f64; 3],
    /// g written out.
    pub g: String,
    /// Why its census is f's.
    pub statement: String,
}

impl Transformation {
    fn of(r: &remedy::Remedy, f: &dyn Implicit) -> Self {
        Transformation {
            kind: match r.kind {
                remedy::RemedyKind::Smooth => "smooth".into(),
                remedy::RemedyKind::Chapter => "chapter".into(),
            },
            a: r.a,
            b: r.b,
            g: r.describe(&f.describe()),
            statement: "h > 0 everywhere (a > 0), so g has the sign of f: {g <= 0} = {f <= 0} and g = 0 is S; the critical points, values and indices listed are g's, and chi({g <= 0}) is chi({f <= 0})".into(),
        }
    }
}

fn kind_of(index: MorseIndex, on_surface: bool) -> String {
    match (index, on_surface) {
        (MorseIndex::Certified { index: 0 }, _) => "minimum".into(),
        (MorseIndex::Certified { index: 1 }, true) => "saddle".into(),
        (MorseIndex::Certified { index: 2 }, true) => "maximum".into(),
        (MorseIndex::Certified { index: 1 }, false) => "saddle (index 1)".into(),
        (MorseIndex::Certified { index: 2 }, false) => "saddle (index 2)".into(),
        (MorseIndex::Certified { index: 3 }, false) => "maximum".into(),
        (MorseIndex::Certified { index }, _) => format!("index {index}"),
        (MorseIndex::PossiblyDegenerate, _) => "possibly degenerate".into(),
        (MorseIndex::Undecided, _) => "index undecided".into(),
    }
}

fn point(p: &CriticalPoint, on_surface: bool) -> MorsePoint {
    MorsePoint {
        enclosure: p.enclosure,
        isolating: p.isolating,
        point: p.point,
        value: p.value,
        index: p.index,
        kind: kind_of(p.index, on_surface),
        side: (!on_surface).then(|| critical::side(p.value)),
    }
}

fn sort_points(v: &mut [MorsePoint]) {
    v.sort_by(|a, b| {
        a.value[0]
            .total_cmp(&b.value[0])
            .then(a.point[0].total_cmp(&b.point[0]))
            .then(a.point[1].total_cmp(&b.point[1]))
            .then(a.point[2].total_cmp(&b.point[2]))
    });
}

/// The census of the critical points of f from a gradient search.
pub fn gradient_census(f: &dyn Implicit, r: &CriticalReport) -> GradientCensus {
    let (index_counts, without_index) = r.index_counts();
    let mut points: Vec<MorsePoint> = r.points.iter().map(|p| point(p, false)).collect();
    sort_points(&mut points);
    let undecided = UndecidedSummary::of(f, &r.undecided);
    let not_morse_reason = if !r.complete {
        let reasons: Vec<String> = undecided
            .by_reason
            .iter()
            .map(|(k, v)| format!("{v} {k}"))
            .collect();
        Some(format!(
            "the search for grad f = 0 is incomplete: {} undecided boxes ({}){}",
            undecided.count,
            reasons.join(", "),
            if undecided.by_reason.contains_key("possibly-degenerate") {
                "; possibly degenerate boxes mean a degenerate or non-isolated critical set may be there (not proven, not guessed)"
            } else {
                ""
            }
        ))
    } else if without_index > 0 {
        Some(format!(
            "{without_index} isolated critical points without a certified index"
        ))
    } else {
        None
    };
    GradientCensus {
        complete: r.complete,
        morse: not_morse_reason.is_none(),
        not_morse_reason,
        points,
        index_counts,
        without_index,
        undecided,
        stats: r.stats.clone(),
    }
}

/// The full census of f on `domain` (see the module doc). Never panics; a refused
/// input (a curve, a degenerate box) gives a report that certifies nothing.
pub fn analyze(f: &dyn Implicit, domain: Bx, opts: &MorseOptions) -> MorseReport {
    let t0 = std::time::Instant::now();
    let remedied = opts.remedy.map(|r| r.apply(f));
    let g: &dyn Implicit = match &remedied {
        Some(g) => g,
        None => f,
    };
    let sub = critical::sublevel_euler_characteristic(g, domain, opts.gradient);
    let gradient = gradient_census(g, &sub.gradient);
    let sublevel = SublevelChi {
        chi_sublevel: sub.chi_sublevel,
        chi_surface: sub.chi_surface,
        reason: sub.reason.clone(),
        counted: sub.counted,
        boundary_positive: sub.boundary_positive,
        undecided_above: sub.undecided_above,
        undecided_blocking: sub.undecided_blocking,
    };
    let e = critical::euler_characteristic(f, domain, opts.direction, opts.surface);
    let (direction, normal) = match &e.surface.problem {
        Problem::Height {
            direction, normal, ..
        } => (*direction, *normal),
        Problem::Gradient => ([0.0; 3], [0.0; 3]),
    };
    let mut hpoints: Vec<MorsePoint> = e.surface.points.iter().map(|p| point(p, true)).collect();
    sort_points(&mut hpoints);
    let (_, without_index) = e.surface.index_counts();
    let height = HeightCensus {
        direction,
        normal,
        complete: e.surface.complete,
        points: hpoints,
        minima: e.minima,
        saddles: e.saddles,
        maxima: e.maxima,
        without_index,
        census: e.minima as i64 - e.saddles as i64 + e.maxima as i64,
        chi: e.chi,
        reason: e.reason.clone(),
        boundary_clear: e.boundary_clear,
        undecided: UndecidedSummary::of(f, &e.surface.undecided),
        stats: e.surface.stats.clone(),
    };
    let mut chi_from = Vec::new();
    if sublevel.chi_surface.is_some() {
        chi_from.push("sublevel".to_string());
    }
    if height.chi.is_some() {
        chi_from.push("height".to_string());
    }
    let inconsistent = matches!((sublevel.chi_surface, height.chi), (Some(a), Some(b)) if a != b);
    MorseReport {
        domain,
        chi: sublevel.chi_surface.or(height.chi),
        chi_from,
        inconsistent,
        gradient,
        sublevel,
        height,
        mesh: None,
        transformation: opts.remedy.map(|r| Transformation::of(&r, f)),
        seconds: t0.elapsed().as_secs_f64(),
    }
}

/// The certified χ(S) of f = 0 in `domain`, cheaply: first by the critical points of f
/// (a gradient search of at most `gradient_boxes` boxes: cheap when f is Morse, and
/// cheap to give up on a degenerate critical set), else by the generic height census
/// (at most `surface_boxes` boxes). `(None, reason)` when neither certificate holds.
/// Used by the comparison harness's χ column.
pub fn certified_chi(
    f: &dyn Implicit,
    domain: Bx,
    gradient_boxes: usize,
    surface_boxes: usize,
) -> (Option<i64>, Option<String>) {
    let g = Budget {
        max_depth: 30,
        max_boxes: gradient_boxes,
        ..Budget::default()
    };
    let sub = critical::sublevel_euler_characteristic(f, domain, g);
    if let Some(c) = sub.chi_surface {
        return (Some(c), None);
    }
    let s = Budget {
        max_boxes: surface_boxes,
        ..Budget::default()
    };
    let e = critical::euler_characteristic(f, domain, None, s);
    match e.chi {
        Some(c) => (Some(c), None),
        None => (
            None,
            Some(format!(
                "from f: {}; from the height: {}",
                sub.reason.unwrap_or_default(),
                e.reason.unwrap_or_default()
            )),
        ),
    }
}

fn fmt_p(p: [f64; 3]) -> String {
    format!("({:.4}, {:.4}, {:.4})", p[0], p[1], p[2])
}

fn fmt_v(v: [f64; 2]) -> String {
    let m = 0.5 * (v[0] + v[1]);
    let r = 0.5 * (v[1] - v[0]);
    if r < 5e-7 * (1.0 + m.abs()) {
        format!("{m:.6}")
    } else {
        format!("[{:.6}, {:.6}]", v[0], v[1])
    }
}

fn side_text(s: Option<Side>) -> &'static str {
    match s {
        Some(Side::Below) => "f < 0",
        Some(Side::Above) => "f > 0",
        Some(Side::Undecided) => "f ~ 0 (undecided)",
        None => "",
    }
}

fn undecided_lines(u: &UndecidedSummary, out: &mut Vec<String>) {
    if u.count == 0 {
        return;
    }
    let reasons: Vec<String> = u
        .by_reason
        .iter()
        .map(|(k, v)| format!("{v} {k}"))
        .collect();
    out.push(format!(
        "  undecided: {} boxes ({})",
        u.count,
        reasons.join(", ")
    ));
    if let Some(h) = u.hull {
        out.push(format!("    within {} .. {}", fmt_p(h.lo), fmt_p(h.hi)));
    }
    if let Some(r) = u.f_range {
        out.push(format!("    f over them in [{:.4}, {:.4}]", r[0], r[1]));
    }
}

impl MorseReport {
    /// The χ of a triangle mesh beside the certified χ(S).
    pub fn with_mesh(&mut self, source: &str, mesh: &TriMesh) -> crate::error::Result<()> {
        let t = crate::metrics::analyze(mesh)?;
        self.mesh = Some(MeshCheck {
            source: source.to_string(),
            euler_characteristic: t.euler_characteristic,
            components: t.components,
            genus: t.genus.clone(),
            closed: t.closed,
            manifold: t.manifold,
            agrees: self.chi.map(|c| c == t.euler_characteristic),
        });
        Ok(())
    }

    /// The readable report, one line per entry; at most `max_points` points per list.
    pub fn text(&self, max_points: usize) -> Vec<String> {
        let mut o = Vec::new();
        if let Some(t) = &self.transformation {
            o.push(format!(
                "transformation ({} remedy, asked for): the f census below is that of g = {}",
                t.kind, t.g
            ));
            o.push(format!("  {}", t.statement));
        }
        // With a transformation the listed points, values and the Morse property are g's.
        let fname = if self.transformation.is_some() {
            "g"
        } else {
            "f"
        };
        let g = &self.gradient;
        o.push(format!(
            "critical points of {fname} (grad {fname} = 0): {} isolated, search {} ({} boxes, {:.1} ms)",
            g.points.len(),
            if g.complete { "complete" } else { "incomplete" },
            g.stats.boxes,
            g.stats.millis
        ));
        for (i, p) in g.points.iter().enumerate().take(max_points) {
            o.push(format!(
                "  {:>3}  {}  {fname} = {}  {}  {}",
                i + 1,
                fmt_p(p.point),
                fmt_v(p.value),
                p.kind,
                side_text(p.side)
            ));
        }
        if g.points.len() > max_points {
            o.push(format!(
                "  ... {} more (--json lists all)",
                g.points.len() - max_points
            ));
        }
        undecided_lines(&g.undecided, &mut o);
        let c = g.index_counts;
        o.push(format!(
            "  indices 0/1/2/3: {}/{}/{}/{}{}",
            c[0],
            c[1],
            c[2],
            c[3],
            if g.without_index > 0 {
                format!(", {} without a certified index", g.without_index)
            } else {
                String::new()
            }
        ));
        match &g.not_morse_reason {
            None => o.push(format!("{fname} is Morse on the domain: certified (every critical point isolated, every index certified)")),
            Some(r) => o.push(format!("{fname} is NOT proven Morse on the domain: {r}")),
        }
        let s = &self.sublevel;
        let k = s.counted;
        match (s.chi_sublevel, s.chi_surface) {
            (Some(a), Some(b)) => {
                o.push(format!(
                    "chi({{f <= 0}}) = {} - {} + {} - {} = {a}: certified",
                    k[0], k[1], k[2], k[3]
                ));
                o.push(format!(
                    "chi(S) = 2 chi({{f <= 0}}) = {b}: certified (f > 0 on the boundary, f Morse on {{f <= 0}}, no critical value 0{})",
                    if s.undecided_above > 0 {
                        format!("; {} undecided boxes proven in {{f > 0}}", s.undecided_above)
                    } else {
                        String::new()
                    }
                ));
            }
            _ => o.push(format!(
                "chi({{f <= 0}}), chi(S) from f: uncertified: {}",
                s.reason.as_deref().unwrap_or("")
            )),
        }
        let h = &self.height;
        o.push(format!(
            "height <n, x> on S, n = {}: {} critical points, search {} ({} boxes, {:.1} ms)",
            fmt_p(h.normal),
            h.points.len(),
            if h.complete { "complete" } else { "incomplete" },
            h.stats.boxes,
            h.stats.millis
        ));
        for (i, p) in h.points.iter().enumerate().take(max_points) {
            o.push(format!(
                "  {:>3}  {}  h = {}  {}",
                i + 1,
                fmt_p(p.point),
                fmt_v(p.value),
                p.kind
            ));
        }
        if h.points.len() > max_points {
            o.push(format!(
                "  ... {} more (--json lists all)",
                h.points.len() - max_points
            ));
        }
        undecided_lines(&h.undecided, &mut o);
        match h.chi {
            Some(c) => o.push(format!(
                "  census #min - #saddle + #max = {} - {} + {} = {c}: chi(S) certified",
                h.minima, h.saddles, h.maxima
            )),
            None => o.push(format!(
                "  census #min - #saddle + #max = {} - {} + {} = {}: uncertified: {}",
                h.minima,
                h.saddles,
                h.maxima,
                h.census,
                h.reason.as_deref().unwrap_or("")
            )),
        }
        match self.chi {
            Some(_) if self.inconsistent => o.push(format!(
                "chi(S): INCONSISTENT certificates (sublevel {:?}, height {:?}): a bug, please report",
                self.sublevel.chi_surface, self.height.chi
            )),
            Some(c) => o.push(format!(
                "chi(S) = {c}: certified (by {})",
                self.chi_from.join(" and ")
            )),
            None => o.push("chi(S): uncertified".into()),
        }
        if let Some(m) = &self.mesh {
            o.push(format!(
                "mesh {}: chi = {}, {} component{}, genus {:?}, {}{}",
                m.source,
                m.euler_characteristic,
                m.components,
                if m.components == 1 { "" } else { "s" },
                m.genus,
                if m.closed && m.manifold {
                    "closed manifold"
                } else {
                    "not a closed manifold"
                },
                match m.agrees {
                    Some(true) => ": agrees with the certified chi(S)",
                    Some(false) => ": DIFFERS from the certified chi(S)",
                    None => " (no certified chi to compare with)",
                }
            ));
        }
        o.push("not certified by critical data: the number of components and their nesting (the chapter's Fig. 1.23)".into());
        o
    }
}
