//! Geometric fidelity of a mesh to the surface f = 0 it approximates: distance
//! estimates at the vertices, a sampled two-sided Hausdorff estimate, and the deviation
//! of the triangle normals from ∇f.
//!
//! A quantity that could not be measured is not reported as 0: it is NaN (`null` in
//! JSON) with the reason in [`Fidelity::fidelity_undefined`] (e.g. no mesh point could
//! be projected onto f = 0 because f has a pole there, or f = 0 was never found); an
//! infinite one (|f|/|∇f| where ∇f = 0 ≠ f, the distance to an empty mesh) is `inf`
//! (`null` in JSON) with its reason there too.
//!
//! These are *measurements*, not certificates: sampling can miss the worst point (an
//! underestimate), and a mesh point's distance is taken to its Newton projection, a
//! point of the surface but not always the nearest one (an overestimate per sample).
//! Each field says what it measures.
use crate::error::{Error, Result};
use crate::implicit::Implicit;
use crate::kernel::bvh::SegBvh;
use crate::kernel::cellgrid::TriGrid;
use crate::kernel::geom::{self, Aabb};
use crate::mesh::{Curve2, TriMesh};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;

/// What the mesh → surface distance of one sample is (the clause every
/// `HAUSDORFF_KIND*` ends with, and [`MESH_TO_SURFACE_KIND`]).
macro_rules! per_sample_upper_bound {
    () => {
        "each mesh sample's distance is to its Newton projection onto f = 0, an upper \
         bound of its distance to f = 0 per sample (the projection is a point of f = 0, \
         not always the nearest: with several components it can be much larger)"
    };
}

/// What the Hausdorff fields are: maxima over finite samples, so estimates, not bounds;
/// on the mesh → surface side each sample's distance is an upper bound of its own
/// (the distance to its Newton projection), so the maximum can also exceed the true one.
pub const HAUSDORFF_KIND: &str = concat!(
    "estimate (maximum over samples; not a bound; mesh → surface: ",
    per_sample_upper_bound!(),
    ")"
);

/// What the Hausdorff fields are when [`FidelityParams::project_vertices`] is off (the
/// report's `--metrics fast`): the mesh side from the fixed budget of area-proportional
/// samples alone, so a lower estimate of the mesh → surface side than with every vertex.
pub const HAUSDORFF_KIND_SAMPLED: &str = concat!(
    "sampled estimate (maximum over a fixed budget of area-proportional mesh samples, \
     vertices left out, and over surface points; not a bound; mesh → surface: ",
    per_sample_upper_bound!(),
    ")"
);

/// What the Hausdorff fields are when [`FidelityParams::thin_samples`] kept only part
/// of the mesh samples (the report's `--metrics fast` on a small mesh, see
/// [`crate::harness::compare::fast_fidelity_params`]).
pub const HAUSDORFF_KIND_THINNED: &str = concat!(
    "sampled estimate (maximum over a budget sized to the mesh: every k-th of the full \
     report's area-proportional mesh samples, then all of them and the corners on the \
     triangles of the largest distances, the other vertices left out, and surface points \
     from a seed grid as coarse as the mesh allows; not a bound; mesh → surface: ",
    per_sample_upper_bound!(),
    ")"
);

/// What [`Fidelity::hausdorff_mesh_to_surface`] is (and so the two-sided `hausdorff`
/// when it is the larger): the maximum over samples of per-sample upper bounds. Not a
/// bound either way: sampling can miss the farthest point, and a sample's Newton
/// projection can land on a farther part of f = 0 than the nearest one.
pub const MESH_TO_SURFACE_KIND: &str = concat!(
    "maximum over samples (not a bound); ",
    per_sample_upper_bound!()
);

/// How much sampling to do. Defaults: 50 000 mesh samples, a 48³ (curves: 256²) seed
/// grid, 16 Newton steps, domain = mesh bounding box grown by 10% of its diagonal,
/// every mesh sample kept (no thinning).
#[derive(Clone, Debug, PartialEq)]
pub struct FidelityParams {
    /// Points sampled on the mesh (area-proportional, deterministic), besides its vertices.
    pub mesh_samples: usize,
    /// Seeds per axis of the grid from which surface points are found.
    pub seed_grid: usize,
    pub newton_steps: usize,
    /// Where to look for the surface. Give the catalog entry's domain to catch
    /// components the mesh misses entirely.
    pub domain: Option<Aabb>,
    /// Compute only the Hausdorff fields (both directions): the first-order distance
    /// estimate and the normal deviation, which need a gradient (and a Newton
    /// projection) per vertex and per element, are left undefined with the reason
    /// [`NOT_COMPUTED`]. The Hausdorff values are the same as without it.
    pub hausdorff_only: bool,
    /// Project every vertex onto f = 0 for the mesh → surface side, besides the
    /// `mesh_samples` (default). Off (the report's `--metrics fast`): the samples alone
    /// (thinned by [`FidelityParams::thin_samples`] if asked), and the surface → mesh
    /// distances by [`super::nearest::closest_dist2_all`] (the same distances as with
    /// it on, without a triangle index when it can). Every sample is one of the points
    /// projected with it on, so the mesh → surface estimate is at most the one with it
    /// on, and the surface → mesh side is the same; [`Fidelity::hausdorff_kind`] says
    /// which was done.
    pub project_vertices: bool,
    /// Keep only every k-th mesh sample, centred (samples k·m + (k − 1)/2 of the
    /// `mesh_samples`; k odd), and then, adaptively, the corners and every sample of
    /// the elements (triangles, segments) that hold the [`REFINE_WORST`] largest of
    /// their distances: the maximum sits on a few elements, and is most likely found
    /// next to the largest distances of the even sample. Each point is one of the
    /// points of the unthinned run with [`FidelityParams::project_vertices`] on (a
    /// vertex, or the sample with the same index), projected the same way, so the mesh
    /// → surface maximum is at most that run's; the mean is the one of the evenly
    /// spread samples alone. 1 (the default) keeps every sample.
    pub thin_samples: usize,
}

/// Why a field is undefined when [`FidelityParams::hausdorff_only`] skipped it.
pub const NOT_COMPUTED: &str = "not computed (Hausdorff fields only: --metrics fast)";

impl Default for FidelityParams {
    fn default() -> Self {
        FidelityParams {
            mesh_samples: 50_000,
            seed_grid: 0,
            newton_steps: 16,
            domain: None,
            hausdorff_only: false,
            project_vertices: true,
            thin_samples: 1,
        }
    }
}

impl FidelityParams {
    pub fn mesh_samples(mut self, n: usize) -> Self {
        self.mesh_samples = n;
        self
    }
    /// 0 means the default (48 for surfaces, 256 for curves).
    pub fn seed_grid(mut self, n: usize) -> Self {
        self.seed_grid = n;
        self
    }
    pub fn newton_steps(mut self, n: usize) -> Self {
        self.newton_steps = n;
        self
    }
    pub fn domain(mut self, d: Aabb) -> Self {
        self.domain = Some(d);
        self
    }
    pub fn hausdorff_only(mut self, yes: bool) -> Self {
        self.hausdorff_only = yes;
        self
    }
    pub fn project_vertices(mut self, yes: bool) -> Self {
        self.project_vertices = yes;
        self
    }
    /// Keep every `k`-th mesh sample (rounded down to an odd number, at least 1): see
    /// [`FidelityParams::thin_samples`].
    pub fn thin_samples(mut self, k: usize) -> Self {
        self.thin_samples = if k <= 1 { 1 } else { k - (1 - k % 2) };
        self
    }
}

/// Fidelity of a mesh to f = 0. Distances are in model units.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Fidelity {
    /// max over used vertices of |f|/|∇f|: the first-order distance estimate
    /// (infinite if ∇f vanishes at a vertex where f does not).
    pub max_distance_estimate: f64,
    pub mean_distance_estimate: f64,
    /// Mesh → surface: max over vertices and samples (samples only when
    /// [`FidelityParams::project_vertices`] is off) of the distance to their Newton
    /// projection onto f = 0. Each distance bounds the distance to the surface from
    /// above (the projection is a point of the surface, not always the nearest one:
    /// when f = 0 has several components, a projection can land on a farther one, and
    /// this maximum then exceeds the true mesh → surface distance). See
    /// [`MESH_TO_SURFACE_KIND`].
    pub hausdorff_mesh_to_surface: f64,
    pub mean_mesh_to_surface: f64,
    /// Surface → mesh: max over surface points (grid seeds projected by Newton) of the
    /// exact distance to the mesh (closest point, `kernel::cellgrid`).
    pub hausdorff_surface_to_mesh: f64,
    pub mean_surface_to_mesh: f64,
    /// The larger of the two directions.
    pub hausdorff: f64,
    pub fidelity_mesh_samples: usize,
    pub fidelity_surface_samples: usize,
    /// Mesh samples whose Newton projection did not converge (left out).
    pub fidelity_unconverged: usize,
    /// Angle between each element's normal and ∇f at its centroid's projection,
    /// ignoring orientation (min(θ, 180° − θ)), in degrees.
    pub normal_dev_max_deg: f64,
    pub normal_dev_mean_deg: f64,
    /// Elements whose normal points against ∇f (θ > 90°): against the convention that
    /// normals point towards f > 0. Always 0 for curves (which carry no orientation).
    pub flipped_normals: usize,
    /// What the `hausdorff*` numbers are: [`HAUSDORFF_KIND`] (sampled estimates), or
    /// [`HAUSDORFF_KIND_SAMPLED`] when the vertices were left out.
    pub hausdorff_kind: &'static str,
    /// For each field above that is undefined (NaN, `null` in JSON) or infinite: why.
    /// Empty when every number was measured.
    pub fidelity_undefined: BTreeMap<String, String>,
}

/// Max and mean of measured values, or why there are none: NaN with a reason when
/// `attempted` points gave no value (`none_reason`), or when a value is NaN.
fn measured(
    values: &[f64],
    attempted: usize,
    fields: [&str; 2],
    none_reason: impl FnOnce() -> String,
    undefined: &mut BTreeMap<String, String>,
) -> (f64, f64) {
    if values.is_empty() && attempted > 0 {
        let why = none_reason();
        for f in fields {
            undefined.insert(f.into(), why.clone());
        }
        return (f64::NAN, f64::NAN);
    }
    let nan = values.iter().filter(|v| v.is_nan()).count();
    if nan > 0 {
        let why = format!(
            "undefined (NaN) at {nan} of {} points: f or ∇f is not defined there",
            values.len()
        );
        for f in fields {
            undefined.insert(f.into(), why.clone());
        }
        return (f64::NAN, f64::NAN);
    }
    let inf = values.iter().filter(|v| v.is_infinite()).count();
    if inf > 0 {
        undefined.insert(
            fields[0].into(),
            format!("infinite at {inf} of {} points", values.len()),
        );
    }
    max_mean(values)
}

/// The larger of the two directions, NaN (with the reason) when either is undefined.
fn two_sided(h_ms: f64, h_sm: f64, undefined: &mut BTreeMap<String, String>) -> f64 {
    let mut why = Vec::new();
    for (name, h) in [
        ("hausdorff_mesh_to_surface", h_ms),
        ("hausdorff_surface_to_mesh", h_sm),
    ] {
        if !h.is_finite() {
            if let Some(r) = undefined.get(name) {
                why.push(format!("{name}: {r}"));
            }
        }
    }
    let h = if h_ms.is_nan() || h_sm.is_nan() {
        f64::NAN
    } else {
        h_ms.max(h_sm)
    };
    if !h.is_finite() {
        undefined.insert("hausdorff".into(), why.join("; "));
    }
    h
}

/// Surface → mesh distances, or why there are none: `candidates` seeds were near
/// f = 0 and `found` of them projected onto it; `dists` are the found points'
/// distances to the mesh (empty when the mesh has no element).
fn surface_to_mesh(
    dists: &[f64],
    candidates: usize,
    found: usize,
    undefined: &mut BTreeMap<String, String>,
) -> (f64, f64) {
    if found > 0 && dists.is_empty() {
        let why = format!("f = 0 was found at {found} points but the mesh is empty");
        undefined.insert("hausdorff_surface_to_mesh".into(), why.clone());
        undefined.insert("mean_surface_to_mesh".into(), why);
        return (f64::INFINITY, f64::INFINITY);
    }
    measured(
        dists,
        candidates,
        ["hausdorff_surface_to_mesh", "mean_surface_to_mesh"],
        || {
            format!(
                "no point of f = 0 could be located: Newton did not converge from any of the \
                 {candidates} seeds near it (f may have a pole there, or ∇f vanish)"
            )
        },
        undefined,
    )
}

/// Project `p` onto f = 0 by Newton steps (the oracle's
/// [`project`](crate::implicit::ops::project)).
pub use crate::implicit::ops::{project, project_batch};

/// Points per batch of [`project_samples`] (one rayon task each).
const BATCH: usize = 1024;

/// Every point projected onto f = 0 by Newton steps ([`project_batch`]), in order;
/// a point where f is exactly 0 is on f = 0 already, also where ∇f vanishes there
/// (e.g. f ≡ 0), where `project` gives up: its distance is then measured (0), not
/// left out. Batches of [`BATCH`] points in parallel, with the batch evaluator; the
/// same points, bit for bit, as projecting each point alone.
fn project_samples(
    f: &dyn Implicit,
    pts: &[[f64; 3]],
    steps: usize,
    tol: f64,
) -> Vec<Option<[f64; 3]>> {
    pts.par_chunks(BATCH)
        .flat_map_iter(|c| crate::implicit::ops::project_batch_or_on(f, c, steps, tol))
        .collect()
}

/// How many of the largest distances of a thinned mesh side have their elements
/// sampled in full ([`FidelityParams::thin_samples`]).
pub const REFINE_WORST: usize = 32;

/// What a thinned mesh side adds ([`FidelityParams::thin_samples`]): the elements of
/// the [`REFINE_WORST`] largest distances `d` (of the samples `kept`, every `k`-th),
/// ascending, and every sample index of `0..ns` (of the unthinned run) on them, not
/// already kept, ascending. `elem(i)` is sample i's element, non-decreasing in i, so
/// an element's samples are one run of indices, found by bisection.
fn refine_indices(
    d: &[Option<f64>],
    kept: &[usize],
    k: usize,
    ns: usize,
    elem: impl Fn(usize) -> usize,
) -> (Vec<usize>, Vec<usize>) {
    let mut worst: Vec<(f64, usize)> = d
        .iter()
        .zip(kept)
        .filter_map(|(d, &i)| d.filter(|d| d.is_finite()).map(|d| (d, i)))
        .collect();
    let m = REFINE_WORST.min(worst.len());
    if m == 0 {
        return (Vec::new(), Vec::new());
    }
    worst.select_nth_unstable_by(m - 1, |a, b| b.0.total_cmp(&a.0));
    let mut elems: Vec<usize> = worst[..m].iter().map(|&(_, i)| elem(i)).collect();
    elems.sort_unstable();
    elems.dedup();
    // The first index in 0..ns where `below` is false (`below` true then false).
    let first = |below: &dyn Fn(usize) -> bool| {
        let (mut lo, mut hi) = (0, ns);
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            if below(mid) {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    };
    let mut out = Vec::new();
    for &e in &elems {
        let lo = first(&|i| elem(i) < e);
        let hi = first(&|i| elem(i) <= e);
        out.extend((lo..hi).filter(|i| i % k != (k - 1) / 2));
    }
    (elems, out)
}

/// The first-order distance estimate |f|/|∇f| at `p`.
pub fn distance_estimate(f: &dyn Implicit, p: [f64; 3]) -> f64 {
    estimate_from(f.grad(p), f.dim())
}

/// [`distance_estimate`] at every point (the batch gradient, in parallel batches).
pub fn distance_estimates_at(f: &dyn Implicit, pts: &[[f64; 3]]) -> Vec<f64> {
    pts.par_chunks(BATCH)
        .flat_map_iter(|c| {
            let mut d = vec![crate::implicit::Dual::ZERO; c.len()];
            f.grad_batch(c, &mut d);
            d.into_iter().map(|d| estimate_from(d, f.dim()))
        })
        .collect()
}

/// |f|/|∇f| from f and ∇f at a point (∇f's z component ignored for curves).
fn estimate_from(d: crate::implicit::Dual<f64>, dim: usize) -> f64 {
    let mut g = d.g;
    if dim == 2 {
        g[2] = 0.0;
    }
    let n = geom::norm(g);
    if d.v == 0.0 {
        0.0
    } else if n > 0.0 {
        d.v.abs() / n
    } else {
        f64::INFINITY
    }
}

/// The R2 low-discrepancy sequence (Roberts 2018): well-spread, deterministic.
fn r2(i: usize) -> (f64, f64) {
    const A1: f64 = 0.754_877_666_246_692_7;
    const A2: f64 = 0.569_840_290_998_053_2;
    let x = (0.5 + A1 * i as f64).fract();
    let y = (0.5 + A2 * i as f64).fract();
    (x, y)
}

fn max_mean(v: &[f64]) -> (f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0);
    }
    let m = v.iter().copied().fold(0.0, f64::max);
    (m, v.iter().sum::<f64>() / v.len() as f64)
}

/// Surface points: centres of an n^dim grid over `domain`, kept where the first-order
/// distance is under a cell diagonal, projected by Newton, kept if converged and still
/// in the domain (grown by one cell).
pub fn surface_points(
    f: &dyn Implicit,
    domain: &Aabb,
    n: usize,
    steps: usize,
    tol: f64,
) -> Vec<[f64; 3]> {
    surface_points_counted(f, domain, n, steps, tol).0
}

/// [`surface_points`], with the number of seeds that were near f = 0 (by the first-order
/// estimate) before projection: more seeds than points means Newton failed on some.
pub fn surface_points_counted(
    f: &dyn Implicit,
    domain: &Aabb,
    n: usize,
    steps: usize,
    tol: f64,
) -> (Vec<[f64; 3]>, usize) {
    let planar = f.dim() == 2;
    let n = n.max(2);
    let size = domain.size();
    let h = size.map(|s| s / n as f64);
    let reach = geom::norm(if planar { [h[0], h[1], 0.0] } else { h });
    let nz = if planar { 1 } else { n };
    let grown = domain.inflate(reach);
    let seed = |idx: usize| {
        let (i, j, k) = (idx % n, (idx / n) % n, idx / (n * n));
        [
            domain.min[0] + (i as f64 + 0.5) * h[0],
            domain.min[1] + (j as f64 + 0.5) * h[1],
            if planar {
                0.0
            } else {
                domain.min[2] + (k as f64 + 0.5) * h[2]
            },
        ]
    };
    // The grid in batches, in order: the seeds near f = 0 by the first-order
    // estimate, then their projections (batch evaluation throughout).
    let total = n * n * nz;
    let per: Vec<(Vec<[f64; 3]>, usize)> = (0..total.div_ceil(BATCH))
        .into_par_iter()
        .map(|b| {
            let seeds: Vec<[f64; 3]> = (b * BATCH..((b + 1) * BATCH).min(total))
                .map(seed)
                .collect();
            let mut d = vec![crate::implicit::Dual::ZERO; seeds.len()];
            f.grad_batch(&seeds, &mut d);
            // (Their values and gradients are the first Newton round's.)
            let (near, near_d): (Vec<[f64; 3]>, Vec<_>) = seeds
                .iter()
                .zip(&d)
                .filter(|(_, &d)| estimate_from(d, f.dim()) < reach)
                .unzip();
            let found =
                crate::implicit::ops::project_batch_or_on_given(f, &near, &near_d, steps, tol)
                    .into_iter()
                    .flatten()
                    .filter(|&q| grown.contains(q))
                    .collect();
            (found, near.len())
        })
        .collect();
    let candidates = per.iter().map(|(_, c)| c).sum();
    (per.into_iter().flat_map(|(p, _)| p).collect(), candidates)
}

/// |f|/|∇f| over the vertices (NaN where f is undefined, inf where ∇f = 0 ≠ f).
fn distance_estimates(est: &[f64], undefined: &mut BTreeMap<String, String>) -> (f64, f64) {
    let (max, mean) = measured(
        est,
        0,
        ["max_distance_estimate", "mean_distance_estimate"],
        String::new,
        undefined,
    );
    if max.is_infinite() {
        undefined.insert(
            "max_distance_estimate".into(),
            format!(
                "|f|/|∇f| is infinite at {} of {} vertices (∇f = 0 where f ≠ 0, or f infinite)",
                est.iter().filter(|v| v.is_infinite()).count(),
                est.len()
            ),
        );
    }
    (max, mean)
}

/// Mesh → surface distances of the points that projected onto f = 0.
fn mesh_to_surface(
    d: &[f64],
    attempted: usize,
    undefined: &mut BTreeMap<String, String>,
) -> (f64, f64) {
    measured(
        d,
        attempted,
        ["hausdorff_mesh_to_surface", "mean_mesh_to_surface"],
        || {
            format!(
                "no mesh point could be projected onto f = 0: Newton did not converge from any \
                 of the {attempted} points (f may have a pole there, or no zero nearby)"
            )
        },
        undefined,
    )
}

/// Normal deviation over the elements where ∇f could be evaluated; undefined when no
/// element's centre could be projected onto f = 0 (it would be measured off f = 0).
fn normal_deviation(
    dev: &[f64],
    elements: usize,
    projected: usize,
    undefined: &mut BTreeMap<String, String>,
) -> (f64, f64) {
    if elements > 0 && projected == 0 {
        let why = format!(
            "no element centre of the {elements} could be projected onto f = 0: ∇f there \
             says nothing about f = 0"
        );
        undefined.insert("normal_dev_max_deg".into(), why.clone());
        undefined.insert("normal_dev_mean_deg".into(), why);
        return (f64::NAN, f64::NAN);
    }
    measured(
        dev,
        elements,
        ["normal_dev_max_deg", "normal_dev_mean_deg"],
        || {
            format!(
                "∇f vanishes or is undefined at the projection of all {elements} elements \
                 (or every element is degenerate)"
            )
        },
        undefined,
    )
}

fn default_domain(pts: &[[f64; 3]], planar: bool) -> Result<Aabb> {
    let b = Aabb::of_points(pts).ok_or_else(|| Error::Param("the mesh has no vertices".into()))?;
    let mut d = b.inflate(0.1 * b.diagonal().max(1e-300));
    if planar {
        d.min[2] = 0.0;
        d.max[2] = 0.0;
    }
    Ok(d)
}

/// The vertices (of `n`) that some element uses, in order.
fn used_vertices<const K: usize>(n: usize, elements: &[[u32; K]]) -> impl Iterator<Item = u32> {
    let mut used = vec![false; n];
    for e in elements {
        for &v in e {
            used[v as usize] = true;
        }
    }
    (0..n as u32).filter(move |&v| used[v as usize])
}

/// The distances from points to the mesh, given a hint (see [`Elements::closest`]).
type Closest<'a> = dyn Fn(&[[f64; 3]], f64) -> Vec<f64> + Sync + 'a;

/// What the two fidelity measures differ in (triangles in space, segments in the
/// plane); [`measure`] does the rest once.
struct Elements<'a> {
    /// The vertices used by some element.
    verts: Vec<[f64; 3]>,
    /// The measure (area, length) of each element.
    weights: Vec<f64>,
    /// Sample `i` of element `e` (a deterministic low-discrepancy point on it).
    sample: &'a (dyn Fn(usize, usize) -> [f64; 3] + Sync),
    /// The distances from points to the mesh (of those that have one: none when the
    /// mesh has no element), given a typical distance from the mesh to the surface
    /// (the mesh → surface estimate, NaN when there is none), which may make the
    /// search faster but never changes a distance.
    closest: &'a Closest<'a>,
    /// The normal of element `e` and the point where ∇f is compared with it.
    normal: &'a (dyn Fn(usize) -> Option<([f64; 3], [f64; 3])> + Sync),
    /// The corners of element `e`, pushed onto the vector.
    corners: &'a (dyn Fn(usize, &mut Vec<[f64; 3]>) + Sync),
    /// Seed grid when `params.seed_grid` is 0.
    default_seed_grid: usize,
    /// A curve in the plane z = 0 (∇f's z component is ignored; no orientation).
    planar: bool,
}

/// The fidelity measures of a mesh given by its [`Elements`].
fn measure(f: &dyn Implicit, params: &FidelityParams, mut el: Elements) -> Result<Fidelity> {
    let verts = &el.verts;
    let domain = match params.domain {
        Some(d) => d,
        None => default_domain(verts, el.planar)?,
    };
    let tol = 1e-10 * domain.diagonal().max(f64::MIN_POSITIVE);
    let steps = params.newton_steps;

    let mut undefined = BTreeMap::new();
    let skip = |undefined: &mut BTreeMap<String, String>, fields: &[&str]| {
        for k in fields {
            undefined.insert(k.to_string(), NOT_COMPUTED.to_string());
        }
        (f64::NAN, f64::NAN)
    };
    let (max_est, mean_est) = if params.hausdorff_only {
        skip(
            &mut undefined,
            &["max_distance_estimate", "mean_distance_estimate"],
        )
    } else {
        let est = distance_estimates_at(f, verts);
        distance_estimates(&est, &mut undefined)
    };

    let n_el = el.weights.len();
    let mut cum = std::mem::take(&mut el.weights);
    // Side by side: the mesh → surface projections, and the surface points (their
    // distances to the mesh come after, with the first side's estimate as a hint).
    let ((m2s, attempted, unconverged, even_mean), (spts, candidates)) = rayon::join(
        || {
            // Measure-proportional deterministic samples: stratified along the
            // cumulative measure.
            // (The measures become their running sums in place: no second array.)
            let cum = &mut cum;
            let mut acc = 0.0;
            for w in cum.iter_mut() {
                acc += *w;
                *w = acc;
            }
            let cum = &*cum;
            let total = acc;
            let ns = if total > 0.0 { params.mesh_samples } else { 0 };
            // The element of sample i (non-decreasing in i).
            let elem = |i: usize| {
                let u = (i as f64 + 0.5) / ns as f64 * total;
                cum.partition_point(|&c| c < u).min(n_el - 1)
            };
            let dist_of = |pts: &[[f64; 3]]| -> Vec<Option<f64>> {
                project_samples(f, pts, steps, tol)
                    .into_iter()
                    .zip(pts)
                    .map(|(q, &p)| q.map(|q| geom::dist(p, q)))
                    .collect()
            };
            // Every k-th sample, centred (k odd, see `FidelityParams::thin_samples`).
            let k = params.thin_samples.max(1);
            let kept: Vec<usize> = ((k - 1) / 2..ns).step_by(k).collect();
            let samples: Vec<[f64; 3]> =
                kept.par_iter().map(|&i| (el.sample)(elem(i), i)).collect();
            let from: Vec<[f64; 3]> = if params.project_vertices {
                verts.iter().chain(&samples).copied().collect()
            } else {
                samples
            };
            let mut m2s = dist_of(&from);
            // Thinned: the mean is the one of the evenly spread samples; then every
            // sample of the elements that hold the largest distances, where the
            // maximum is most likely (see `FidelityParams::thin_samples`).
            let mut mean = None;
            if k > 1 {
                let off = from.len() - kept.len();
                let even: Vec<f64> = m2s[off..].iter().flatten().copied().collect();
                mean = Some(max_mean(&even).1);
                let (elems, extra) = refine_indices(&m2s[off..], &kept, k, ns, elem);
                // Their corners (each once; already among the points when every vertex
                // is), then their samples.
                let mut pts = Vec::new();
                if !params.project_vertices {
                    for e in elems {
                        (el.corners)(e, &mut pts);
                    }
                }
                pts.sort_unstable_by(|a, b| a.map(f64::to_bits).cmp(&b.map(f64::to_bits)));
                pts.dedup();
                pts.par_extend(extra.par_iter().map(|&i| (el.sample)(elem(i), i)));
                m2s.extend(dist_of(&pts));
            }
            let attempted = m2s.len();
            let unconverged = m2s.iter().filter(|d| d.is_none()).count();
            let m2s: Vec<f64> = m2s.into_iter().flatten().collect();
            (m2s, attempted, unconverged, mean)
        },
        || {
            let n = if params.seed_grid == 0 {
                el.default_seed_grid
            } else {
                params.seed_grid
            };
            surface_points_counted(f, &domain, n, steps, tol)
        },
    );
    let (h_ms, mut mean_ms) = mesh_to_surface(&m2s, attempted, &mut undefined);
    // The surface → mesh distances, after the mesh → surface side, whose estimate
    // tells the search how far to look first.
    let s2m = (el.closest)(&spts, h_ms);
    let spts_len = spts.len();
    if let Some(m) = even_mean.filter(|m| m.is_finite() && mean_ms.is_finite()) {
        mean_ms = m;
    }

    let (h_sm, mean_sm) = surface_to_mesh(&s2m, candidates, spts_len, &mut undefined);

    let (dmax, dmean, flipped) = if params.hausdorff_only {
        let (a, b) = skip(
            &mut undefined,
            &["normal_dev_max_deg", "normal_dev_mean_deg"],
        );
        (a, b, 0)
    } else {
        // Normal deviation at the projections of the elements' centres (at the centre
        // itself where Newton fails; if it fails everywhere, the deviation is undefined).
        let (normals, centres): (Vec<[f64; 3]>, Vec<[f64; 3]>) = (0..n_el)
            .into_par_iter()
            .filter_map(|e| (el.normal)(e).filter(|(n, _)| geom::norm(*n) > 0.0))
            .unzip();
        let proj = project_samples(f, &centres, steps, tol);
        let projected = proj.iter().filter(|q| q.is_some()).count();
        let at: Vec<[f64; 3]> = proj
            .iter()
            .zip(&centres)
            .map(|(q, &c)| q.unwrap_or(c))
            .collect();
        let dev: Vec<f64> = at
            .par_chunks(BATCH)
            .zip(normals.par_chunks(BATCH))
            .flat_map_iter(|(q, ns)| {
                let mut d = vec![crate::implicit::Dual::ZERO; q.len()];
                f.grad_batch(q, &mut d);
                d.into_iter().zip(ns).filter_map(|(d, &n)| {
                    let mut g = d.g;
                    if el.planar {
                        g[2] = 0.0;
                    }
                    (geom::norm(g) > 0.0).then(|| {
                        geom::norm(geom::cross(n, g))
                            .atan2(geom::dot(n, g))
                            .to_degrees()
                    })
                })
            })
            .collect();
        // A curve's segments carry no orientation: no flipped normals.
        let flipped = if el.planar {
            0
        } else {
            dev.iter().filter(|&&a| a > 90.0).count()
        };
        let unsigned: Vec<f64> = dev.iter().map(|&a| a.min(180.0 - a)).collect();
        let (dmax, dmean) = normal_deviation(&unsigned, n_el, projected, &mut undefined);
        (dmax, dmean, flipped)
    };

    Ok(Fidelity {
        max_distance_estimate: max_est,
        mean_distance_estimate: mean_est,
        hausdorff_mesh_to_surface: h_ms,
        mean_mesh_to_surface: mean_ms,
        hausdorff_surface_to_mesh: h_sm,
        mean_surface_to_mesh: mean_sm,
        hausdorff: two_sided(h_ms, h_sm, &mut undefined),
        fidelity_mesh_samples: m2s.len(),
        fidelity_surface_samples: s2m.len(),
        fidelity_unconverged: unconverged,
        normal_dev_max_deg: dmax,
        normal_dev_mean_deg: dmean,
        flipped_normals: flipped,
        hausdorff_kind: if params.project_vertices {
            HAUSDORFF_KIND
        } else if params.thin_samples > 1 {
            HAUSDORFF_KIND_THINNED
        } else {
            HAUSDORFF_KIND_SAMPLED
        },
        fidelity_undefined: undefined,
    })
}

/// Fidelity of a triangle mesh to f = 0.
pub fn surface_fidelity(
    mesh: &TriMesh,
    f: &dyn Implicit,
    params: &FidelityParams,
) -> Result<Fidelity> {
    super::check_trimesh(mesh)?;
    if f.dim() != 3 {
        return Err(Error::Param(format!(
            "a triangle mesh needs a surface f(x, y, z), got a function of dimension {}",
            f.dim()
        )));
    }
    // The used vertices, unless nothing needs them (the report's `--metrics fast`
    // with its domain given).
    let need_verts = !params.hausdorff_only || params.project_vertices || params.domain.is_none();
    let verts: Vec<[f64; 3]> = if need_verts {
        used_vertices(mesh.vertices.len(), &mesh.triangles)
            .map(|v| mesh.vertices[v as usize])
            .collect()
    } else {
        Vec::new()
    };
    let weights: Vec<f64> = (0..mesh.triangles.len())
        .into_par_iter()
        .with_min_len(4096)
        .map(|t| {
            let [a, b, c] = mesh.corners(t);
            0.5 * geom::norm(geom::cross(geom::sub(b, a), geom::sub(c, a)))
        })
        .collect();
    // A uniform grid, not a BVH: a linear build for the few thousand surface points
    // (the same exact distances, see `kernel::cellgrid`); with the vertices left out,
    // sweeps over the triangles, or the cheaper centroid grid (the same distances
    // again, see `super::nearest`), after the mesh → surface side.
    let grid = if params.project_vertices {
        Some(TriGrid::new(mesh)?)
    } else {
        None
    };
    let sample = |t: usize, i: usize| {
        let [a, b, c] = mesh.corners(t);
        let (r1, r2) = r2(i);
        let s = r1.sqrt();
        let (wa, wb, wc) = (1.0 - s, s * (1.0 - r2), s * r2);
        [0, 1, 2].map(|k| wa * a[k] + wb * b[k] + wc * c[k])
    };
    let closest = |pts: &[[f64; 3]], hint: f64| -> Vec<f64> {
        match &grid {
            Some(g) => pts
                .par_iter()
                .filter_map(|&p| g.closest_dist2(p).map(f64::sqrt))
                .collect(),
            None => super::nearest::closest_dist2_all(mesh, pts, hint)
                .into_iter()
                .filter_map(|d| d.map(f64::sqrt))
                .collect(),
        }
    };
    let normal = |t: usize| {
        let [a, b, c] = mesh.corners(t);
        let n = geom::cross(geom::sub(b, a), geom::sub(c, a));
        Some((n, geom::scale(geom::add(geom::add(a, b), c), 1.0 / 3.0)))
    };
    measure(
        f,
        params,
        Elements {
            verts,
            weights,
            sample: &sample,
            closest: &closest,
            normal: &normal,
            corners: &|t, out| out.extend(mesh.corners(t)),
            default_seed_grid: 48,
            planar: false,
        },
    )
}

/// Fidelity of a planar curve to f(x, y) = 0: the same measures in 2D (segment samples,
/// a 2D seed grid, segment normals against ∇f without orientation).
pub fn curve_fidelity(
    curve: &Curve2,
    f: &dyn Implicit,
    params: &FidelityParams,
) -> Result<Fidelity> {
    super::check_curve(curve)?;
    if f.dim() != 2 {
        return Err(Error::Param(format!(
            "a curve needs a function f(x, y), got a function of dimension {}",
            f.dim()
        )));
    }
    let lift = |v: u32| {
        let [x, y] = curve.vertices[v as usize];
        [x, y, 0.0]
    };
    let verts: Vec<[f64; 3]> = used_vertices(curve.vertices.len(), &curve.segments)
        .map(lift)
        .collect();
    let weights: Vec<f64> = curve
        .segments
        .iter()
        .map(|&[a, b]| geom::dist(lift(a), lift(b)))
        .collect();
    let bvh = SegBvh::new(curve)?;
    let sample = |s: usize, i: usize| {
        let [a, b] = curve.segments[s];
        geom::lerp(lift(a), lift(b), r2(i).0)
    };
    let closest = |pts: &[[f64; 3]], _hint: f64| -> Vec<f64> {
        pts.par_iter()
            .filter_map(|&p| bvh.closest([p[0], p[1]]).map(|c| c.dist2.sqrt()))
            .collect()
    };
    let normal = |s: usize| {
        let [a, b] = curve.segments[s];
        let (a, b) = (lift(a), lift(b));
        let d = geom::sub(b, a);
        Some(([d[1], -d[0], 0.0], geom::lerp(a, b, 0.5)))
    };
    measure(
        f,
        params,
        Elements {
            verts,
            weights,
            sample: &sample,
            closest: &closest,
            normal: &normal,
            corners: &|s, out| out.extend(curve.segments[s].map(lift)),
            default_seed_grid: 256,
            planar: true,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// `refine_indices` against a brute force: the elements of the 32 largest
        /// finite distances of the kept samples (ties broken either way, so checked as
        /// "every element listed holds one of the 32 largest, and none larger was left
        /// out"), and exactly the not-kept indices of `0..ns` on them.
        #[test]
        fn refine_indices_equal_brute_force(
            weights in prop::collection::vec(0.01f64..5.0, 1..200),
            ns in 1usize..3000,
            k in (1usize..20).prop_map(|k| 2 * k + 1),
            seed in any::<u64>(),
        ) {
            let mut cum = Vec::new();
            let mut acc = 0.0;
            for w in &weights {
                acc += w;
                cum.push(acc);
            }
            let total = acc;
            let elem = |i: usize| {
                let u = (i as f64 + 0.5) / ns as f64 * total;
                cum.partition_point(|&c| c < u).min(weights.len() - 1)
            };
            let kept: Vec<usize> = ((k - 1) / 2..ns).step_by(k).collect();
            // Distances: a hash of the index, some missing (unconverged), some infinite.
            let d: Vec<Option<f64>> = kept
                .iter()
                .map(|&i| {
                    let h = (i as u64 ^ seed).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11;
                    match h % 17 {
                        0 => None,
                        1 => Some(f64::INFINITY),
                        _ => Some(h as f64 / (1u64 << 53) as f64),
                    }
                })
                .collect();
            let (elems, extra) = refine_indices(&d, &kept, k, ns, elem);
            let mut finite: Vec<(f64, usize)> = d
                .iter()
                .zip(&kept)
                .filter_map(|(d, &i)| d.filter(|d| d.is_finite()).map(|d| (d, i)))
                .collect();
            finite.sort_by(|a, b| b.0.total_cmp(&a.0));
            let m = REFINE_WORST.min(finite.len());
            let cut = if m > 0 { finite[m - 1].0 } else { f64::INFINITY };
            // Every sample strictly above the cut has its element listed; every listed
            // element holds a sample at or above it.
            for &(x, i) in &finite {
                if x > cut {
                    prop_assert!(elems.contains(&elem(i)));
                }
            }
            for &e in &elems {
                prop_assert!(finite.iter().any(|&(x, i)| x >= cut && elem(i) == e));
            }
            prop_assert!(elems.windows(2).all(|w| w[0] < w[1]));
            prop_assert!(elems.len() <= m);
            let want: Vec<usize> = (0..ns)
                .filter(|&i| i % k != (k - 1) / 2 && elems.contains(&elem(i)))
                .collect();
            prop_assert_eq!(extra, want);
        }
    }
}
