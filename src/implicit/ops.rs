//! The primitive operations of the surface oracle: everything a mesher asks of f
//! beyond single evaluations, written once. As in the chapter's lists of "primitive
//! operations" (Boissonnat et al., *Meshing of Surfaces*, 2007, §1.2.3, §1.3.1,
//! §1.4.1) and CGAL's surface-mesher oracle, a mesher is characterised by which of
//! these it calls:
//!
//! | operation | what it proves | used by |
//! |---|---|---|
//! | [`point_sign`] | the sign of f at a point, or "undecided" (0 in the enclosure, or f undefined there) | Snyder, Plantinga–Vegter (grid corners) |
//! | [`excludes_zero`], [`enclose`] | 0 ∉ □f over a box (natural ∩ mean-value enclosure; the mean-value form only where f is continuous) | Snyder, Plantinga–Vegter, the pruned marching meshers |
//! | [`IntervalIsolation::isolate`] | all roots of f on a segment, each in its own piece with 0 ∉ □f' (unique), or failure (a grazing root) | Snyder (every box edge) |
//! | [`isolate_segment`] | all roots of f on a segment in general position whose end points are known only as boxes (interval circumcentres), each in its own piece with 0 ∉ □(d/dt f) (unique), or the undecided pieces (tangent, grazing, an end on f = 0) | restricted-Delaunay meshing (every Voronoi edge) |
//! | [`locate`], [`crossing_t`] | the position of one crossing between two points of opposite sign (bisection, or the linear fast path); no certificate | every lattice and subdivision mesher |
//! | [`project`], [`project_steps`] | Newton projection onto f = 0 (no certificate) | GradNormal, MidNormal, the fidelity metrics |
//! | [`Implicit::regularity`] | f defined, continuous, C^∞ on a box | every certified criterion |
//! | [`critical_points_of_f`](crate::implicit::critical::critical_points_of_f), [`critical_points_on_surface`](crate::implicit::critical::critical_points_on_surface), [`euler_characteristic`](crate::implicit::critical::euler_characteristic) | every critical point of f (∇f = 0), or of a height ⟨n, x⟩ on f = 0, in its own existence-and-uniqueness box (interval Krawczyk), every other box excluded or reported undecided; the Morse index from a certified Hessian inertia; χ(S) by Morse counting | restricted-Delaunay seeds, the Morse census |
//!
//! Certified critical points of f on a box face or segment (interval Newton /
//! Krawczyk) belong here too; the Delaunay-refinement and Morse methods that need them
//! add them.
use crate::error::{Error, Result};
use crate::implicit::{IBox, Implicit, Regularity};
use crate::kernel::geom::{dot, lerp, scale, sub};
use inari::Interval;
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

// ---------------------------------------------------------------------------------
// The sign of f at a point.

/// The sign of f at a grid point, decided by interval arithmetic.
#[derive(Clone, Copy, Debug)]
pub struct PointSign {
    /// sign⁺: true for f >= 0.
    pub pos: bool,
    /// f at the point (float evaluation).
    pub value: f64,
    /// The enclosure decided the sign (or f is exactly 0).
    pub rigorous: bool,
}

pub fn point_sign(f: &dyn Implicit, p: [f64; 3]) -> PointSign {
    let b = p.map(|x| Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE));
    let i = f.eval_interval(&b);
    let value = f.eval(p);
    // An empty enclosure means f is undefined at p (1/0): no sign is proven.
    if i.is_empty() {
        PointSign {
            pos: value >= 0.0,
            value,
            rigorous: false,
        }
    } else if i.inf() >= 0.0 {
        PointSign {
            pos: true,
            value,
            rigorous: true,
        }
    } else if i.sup() < 0.0 {
        PointSign {
            pos: false,
            value,
            rigorous: true,
        }
    } else {
        PointSign {
            pos: value >= 0.0,
            value,
            rigorous: false,
        }
    }
}

// ---------------------------------------------------------------------------------
// Enclosures over a box.

/// Is the box free of zeros of f (0 ∉ □f)?
#[inline]
pub fn excludes_zero(i: Interval) -> bool {
    i.inf() > 0.0 || i.sup() < 0.0
}

/// Is the box free of zeros of f + ε (the sign⁺ convention): □f ⊂ [0, ∞) or (-∞, 0)?
#[inline]
pub fn no_zero_plus(i: Interval) -> bool {
    i.inf() >= 0.0 || i.sup() < 0.0
}

/// An enclosure of f over a box: the natural interval extension intersected with the
/// mean-value form f(c) + Σ □∂_k f(B)·(B_k − c_k). The mean-value form's width is O(h²)
/// near points where the partials vanish, where the natural extension of a rotated
/// formula (generic position) only reaches O(h) — without it Snyder's face test never
/// proves a face near a tangency empty (the dependency problem). Returns it with the
/// gradient enclosure.
pub fn enclose(f: &dyn Implicit, b: &IBox) -> (Interval, [Interval; 3]) {
    let d = f.grad_interval(b);
    (mean_value(f, b, &d), d.g)
}

/// The natural enclosure `d.v` intersected with the mean-value form built from the
/// gradient enclosure `d.g` (see [`enclose`]).
pub fn mean_value(f: &dyn Implicit, b: &IBox, d: &crate::implicit::Dual<Interval>) -> Interval {
    mean_value_if(f, b, d, || f.regularity(b) >= Regularity::Continuous)
}

/// [`mean_value`] with the continuity question answered by `continuous` (asked only
/// when the mean-value form tightens): a caller that has proven f C¹ on a box
/// containing `b` (regularity is inclusion-monotone) passes `|| true` and saves the
/// decorated evaluation. The result is [`mean_value`]'s whenever `continuous()` equals
/// `f.regularity(b) >= Continuous`.
pub fn mean_value_if(
    f: &dyn Implicit,
    b: &IBox,
    d: &crate::implicit::Dual<Interval>,
    continuous: impl FnOnce() -> bool,
) -> Interval {
    let c = [0, 1, 2].map(|k| b[k].mid());
    let cb = c.map(|x| Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE));
    // Summed in the fast interval type (inari's bounds, bit for bit).
    use crate::implicit::directed::Iv;
    let mut mv = Iv::from_interval(f.eval_interval(&cb));
    for k in 0..3 {
        if b[k].wid() > 0.0 {
            mv = mv
                + Iv::from_interval(d.g[k]) * (Iv::from_interval(b[k]) - Iv::from_interval(cb[k]));
        }
    }
    let v = d.v.intersection(mv.to_interval());
    // The mean-value form is an enclosure only for a continuous f whose derivative
    // enclosures are slopes (C¹, or Lipschitz through |·|, min, max): across a pole or
    // a gap of the domain it may exclude values f takes. Ask only when it tightens.
    if v.is_empty() || v == d.v || !continuous() {
        d.v
    } else {
        v
    }
}

// ---------------------------------------------------------------------------------
// Roots on a segment.

/// How a crossing of f = 0 on a segment with a sign change is located.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Crossing {
    /// Linear interpolation of the end values (fast; no fidelity guarantee).
    Linear,
    /// Bisection on f to the tolerance (default).
    #[default]
    Bisection,
}

impl std::str::FromStr for Crossing {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "linear" => Ok(Crossing::Linear),
            "bisection" => Ok(Crossing::Bisection),
            _ => Err(Error::Unknown {
                kind: "crossing method",
                name: s.into(),
                known: "linear bisection".into(),
            }),
        }
    }
}

/// The parameter t in [0, 1] of a crossing on the segment a→b, where `fa` and `fb`
/// have opposite signs (or one is zero). `tol` is the tolerance in t; bisection
/// stops at it or when the midpoint is no longer representable.
pub fn crossing_t(
    f: &dyn Implicit,
    a: [f64; 3],
    fa: f64,
    b: [f64; 3],
    fb: f64,
    how: Crossing,
    tol: f64,
) -> f64 {
    if fa == 0.0 {
        return 0.0;
    }
    if fb == 0.0 {
        return 1.0;
    }
    let linear = (fa / (fa - fb)).clamp(0.0, 1.0);
    match how {
        Crossing::Linear => linear,
        Crossing::Bisection => {
            let neg_at_lo = fa < 0.0;
            bisect(f, a, b, tol, |fm| {
                (fm != 0.0).then_some((fm < 0.0) == neg_at_lo)
            })
        }
    }
}

/// Levels of bisection [`discontinuity_on_segment`] spends localising a point where f
/// is not proven continuous (the piece is then 2⁻³⁰ of the segment).
pub const DISCONTINUITY_DEPTH: u32 = 30;

/// Is f proven continuous on the segment a → b? `None` when it is: f is at least
/// [`Regularity::Continuous`] on the segment's bounding box, or on each piece of a
/// bisection of the segment (an enclosure that only overestimates is resolved by the
/// bisection). Otherwise `Some(p)`, the midpoint of a piece 2⁻ᵈᵉᵖᵗʰ of the segment long
/// on which it is not: a pole, or the edge of f's domain. A lattice mesher asks this of
/// each sign-change edge: a sign change across a pole is no zero of f (1/(x − a)
/// changes sign at x = a), and without the question the pole is meshed as a surface.
/// At most 4·`depth` + 1 pieces are tested; a segment that needs more (f not
/// continuous on many pieces) is answered with the first piece left.
pub fn discontinuity_on_segment(
    f: &dyn Implicit,
    a: [f64; 3],
    b: [f64; 3],
    depth: u32,
) -> Option<[f64; 3]> {
    let piece = |t0: f64, t1: f64| -> IBox {
        let (p, q) = (lerp(a, b, t0), lerp(a, b, t1));
        // The float points of the piece's ends may differ from the true ones by an
        // ulp: widen the box by one on each side so it holds the true segment piece.
        [0, 1, 2].map(|k| {
            let lo = p[k].min(q[k]).next_down();
            let hi = p[k].max(q[k]).next_up();
            Interval::try_from((lo, hi)).unwrap_or(Interval::ENTIRE)
        })
    };
    let ok = |t0: f64, t1: f64| f.regularity(&piece(t0, t1)) >= Regularity::Continuous;
    if ok(0.0, 1.0) {
        return None;
    }
    let mut stack = vec![(0.0f64, 1.0f64, 0u32)];
    let mut tested = 1u32;
    while let Some((t0, t1, d)) = stack.pop() {
        let m = 0.5 * (t0 + t1);
        if d >= depth || tested > 4 * depth || !(t0 < m && m < t1) {
            return Some(lerp(a, b, m));
        }
        for (u0, u1) in [(m, t1), (t0, m)] {
            tested += 1;
            if !ok(u0, u1) {
                stack.push((u0, u1, d + 1));
            }
        }
    }
    None
}

/// Must a lattice mesher ask [`discontinuity_on_segment`] of its sign-change edges
/// inside the box `b`? Not when one decorated evaluation proves f continuous on all of
/// `b` (every polynomial, every rational function whose poles lie outside `b`), and not
/// when f has no rigorous interval methods ([`Implicit::is_rigorous`]: a mesh's signed
/// distance, a Rust closure), whose regularity proves nothing either way: there the
/// question cannot be answered, and refusing every edge would refuse every input.
pub fn edges_need_pole_check(f: &dyn Implicit, b: &crate::kernel::geom::Aabb) -> bool {
    f.is_rigorous() && f.regularity(&b.intervals()) < Regularity::Continuous
}

/// The error of a lattice mesher for a sign change that [`discontinuity_on_segment`]
/// found not to be a zero of f: the edge from `p` (f = `fp`) to `q` (f = `fq`),
/// `which` naming it in the mesher's lattice, and the point `x` where f is not proven
/// continuous.
pub fn sign_change_not_a_zero(
    p: [f64; 3],
    fp: f64,
    q: [f64; 3],
    fq: f64,
    which: &str,
    x: [f64; 3],
) -> Error {
    Error::NotFinite(format!(
        "f changes sign between {p:?} and {q:?} ({which}; f = {fp} and {fq}) but is not \
         proven continuous near {x:?}: a pole or the edge of f's domain, not a zero of f \
         (meshing it would add a false surface there)"
    ))
}

/// The lattice meshers' pole check over a list of sign-change edges: when
/// [`edges_need_pole_check`] holds on `near` (a box holding every edge; `None`: no
/// edges), the first edge (in list order) on which [`discontinuity_on_segment`] finds a
/// point is refused with [`sign_change_not_a_zero`]. `ends` gives an edge's end points,
/// `name` names it in the mesher's lattice (asked only for the edge refused).
pub fn refuse_pole_edges<E: Sync>(
    f: &dyn Implicit,
    near: Option<crate::kernel::geom::Aabb>,
    edges: &[E],
    ends: impl Fn(&E) -> ([f64; 3], [f64; 3]) + Sync,
    name: impl Fn(&E) -> String + Sync,
) -> Result<()> {
    use rayon::prelude::*;
    if !near.is_some_and(|b| edges_need_pole_check(f, &b)) {
        return Ok(());
    }
    let first = edges.par_iter().find_map_first(|e| {
        let (a, b) = ends(e);
        discontinuity_on_segment(f, a, b, DISCONTINUITY_DEPTH)
            .map(|x| sign_change_not_a_zero(a, f.eval(a), b, f.eval(b), &name(e), x))
    });
    first.map_or(Ok(()), Err)
}

/// One segment for [`crossing_t_batch`]: its ends and the values of f there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignChange {
    pub a: [f64; 3],
    pub fa: f64,
    pub b: [f64; 3],
    pub fb: f64,
}

/// [`crossing_t`] on every segment, bit for bit: the bisections of all segments advance
/// together, each round evaluating the midpoints of the unfinished ones in one batch
/// ([`Implicit::eval_batch`]).
pub fn crossing_t_batch(
    f: &dyn Implicit,
    segs: &[SignChange],
    how: Crossing,
    tol: f64,
) -> Vec<f64> {
    let mut out: Vec<f64> = segs
        .iter()
        .map(|s| {
            if s.fa == 0.0 {
                0.0
            } else if s.fb == 0.0 {
                1.0
            } else {
                (s.fa / (s.fa - s.fb)).clamp(0.0, 1.0)
            }
        })
        .collect();
    if how == Crossing::Linear {
        return out;
    }
    // (segment, lo, hi) of the bisections still running.
    let mut active: Vec<(usize, f64, f64)> = segs
        .iter()
        .enumerate()
        .filter(|(_, s)| s.fa != 0.0 && s.fb != 0.0)
        .map(|(i, _)| (i, 0.0, 1.0))
        .collect();
    let (mut xs, mut v): ([Vec<f64>; 3], Vec<f64>) = Default::default();
    while !active.is_empty() {
        // The loop condition and the midpoint test of `bisect`: a finished segment
        // takes its final value here.
        active.retain(|&(i, lo, hi)| {
            let mid = 0.5 * (lo + hi);
            let go = hi - lo > tol && !(mid <= lo || mid >= hi);
            if !go {
                out[i] = 0.5 * (lo + hi);
            }
            go
        });
        xs.iter_mut().for_each(Vec::clear);
        for &(i, lo, hi) in &active {
            let p = lerp(segs[i].a, segs[i].b, 0.5 * (lo + hi));
            (0..3).for_each(|k| xs[k].push(p[k]));
        }
        v.resize(active.len(), 0.0);
        f.eval_batch([&xs[0], &xs[1], &xs[2]], &mut v);
        let mut keep = 0;
        for j in 0..active.len() {
            let (i, lo, hi) = active[j];
            let mid = 0.5 * (lo + hi);
            let fm = v[j];
            if fm == 0.0 {
                out[i] = mid;
                continue;
            }
            active[keep] = if (fm < 0.0) == (segs[i].fa < 0.0) {
                (i, mid, hi)
            } else {
                (i, lo, mid)
            };
            keep += 1;
        }
        active.truncate(keep);
    }
    out
}

/// Locate the crossing of f + ε = 0 between `pa` (sign `sa`) and `pb` by bisection on
/// sign⁺ to `tol` (relative), or by linear interpolation of the end values.
pub fn locate(
    f: &dyn Implicit,
    pa: [f64; 3],
    sa: bool,
    pb: [f64; 3],
    tol: f64,
    linear: Option<(f64, f64)>,
) -> [f64; 3] {
    if let Some((fa, fb)) = linear {
        let t = if fa == fb {
            0.5
        } else {
            (fa / (fa - fb)).clamp(0.0, 1.0)
        };
        return lerp(pa, pb, t);
    }
    lerp(pa, pb, bisect(f, pa, pb, tol, |fm| Some((fm >= 0.0) == sa)))
}

/// Bisection on the segment a→b for the parameter of a crossing: `stays(f(mid))` says
/// whether the crossing lies above mid (`Some(true)`), below (`Some(false)`), or at mid
/// (`None`). Stops at width `tol` or when the midpoint is no longer representable.
fn bisect(
    f: &dyn Implicit,
    a: [f64; 3],
    b: [f64; 3],
    tol: f64,
    stays: impl Fn(f64) -> Option<bool>,
) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while hi - lo > tol {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        match stays(f.eval(lerp(a, b, mid))) {
            None => return mid,
            Some(true) => lo = mid,
            Some(false) => hi = mid,
        }
    }
    0.5 * (lo + hi)
}

/// Snyder's interval root isolation on an edge (§1.2.3): bisect until, on each piece,
/// 0 ∉ □f (no root) or 0 ∉ □f' (at most one root, present iff the end signs differ).
/// Grazing roots (f = f' = 0) make it fail at `max_depth` bisections.
pub struct IntervalIsolation {
    pub max_depth: u32,
    pub tol: f64,
}

impl IntervalIsolation {
    /// The isolating pieces `[t0, t1]` of the segment, or `None` if isolation failed.
    pub fn isolate(
        &self,
        f: &dyn Implicit,
        pa: [f64; 3],
        sa: bool,
        pb: [f64; 3],
        sb: bool,
        steps: &AtomicU64,
    ) -> Option<Vec<(f64, f64, bool)>> {
        let k = (0..3).find(|&k| pa[k] != pb[k])?;
        let mut out = Vec::new();
        if self.rec(
            f,
            pa,
            pb,
            k,
            (0.0, sa),
            (1.0, sb),
            self.max_depth,
            steps,
            &mut out,
        ) {
            Some(out)
        } else {
            None
        }
    }
    #[allow(clippy::too_many_arguments)]
    fn rec(
        &self,
        f: &dyn Implicit,
        pa: [f64; 3],
        pb: [f64; 3],
        k: usize,
        (t0, s0): (f64, bool),
        (t1, s1): (f64, bool),
        depth: u32,
        steps: &AtomicU64,
        out: &mut Vec<(f64, f64, bool)>,
    ) -> bool {
        steps.fetch_add(1, Relaxed);
        let a = lerp(pa, pb, t0);
        let b = lerp(pa, pb, t1);
        let ib = [0, 1, 2].map(|j| {
            Interval::try_from((a[j].min(b[j]), a[j].max(b[j]))).unwrap_or(Interval::ENTIRE)
        });
        let (v, dg) = enclose(f, &ib);
        let d = crate::implicit::Dual { v, g: dg };
        if no_zero_plus(d.v) {
            return s0 == s1;
        }
        if excludes_zero(d.g[k]) {
            if s0 != s1 {
                out.push((t0, t1, s0));
            }
            return true;
        }
        if depth == 0 {
            return false;
        }
        let tm = 0.5 * (t0 + t1);
        let ps = point_sign(f, lerp(pa, pb, tm));
        if !ps.rigorous {
            return false;
        }
        self.rec(f, pa, pb, k, (t0, s0), (tm, ps.pos), depth - 1, steps, out)
            && self.rec(f, pa, pb, k, (tm, ps.pos), (t1, s1), depth - 1, steps, out)
    }
}

// ---------------------------------------------------------------------------------
// Projection onto f = 0.

/// One Newton step p ← p − f ∇f / |∇f|² from `d` = (f, ∇f) at p (the z component of
/// ∇f ignored for curves): the new point and the step length, or `None` where ∇f
/// vanishes or a value is not finite.
fn newton_step(
    f: &dyn Implicit,
    p: [f64; 3],
    d: crate::implicit::Dual<f64>,
) -> Option<([f64; 3], f64)> {
    let mut g = d.g;
    if f.dim() == 2 {
        g[2] = 0.0;
    }
    let g2 = dot(g, g);
    if !(g2 > 0.0) || !d.v.is_finite() || !g2.is_finite() {
        return None;
    }
    let t = d.v / g2;
    Some((sub(p, scale(g, t)), t.abs() * g2.sqrt()))
}

/// Project `p` onto f = 0 by Newton steps. `None` when ∇f vanishes, a value is not
/// finite, or the last step is still longer than `tol` after `steps` steps.
pub fn project(f: &dyn Implicit, p: [f64; 3], steps: usize, tol: f64) -> Option<[f64; 3]> {
    let mut q = p;
    for _ in 0..steps.max(1) {
        let (r, len) = newton_step(f, q, f.grad(q))?;
        q = r;
        if len <= tol {
            return Some(q);
        }
    }
    None
}

/// The loop of the batch projections: up to `rounds` rounds over the points still
/// moving, one batch gradient ([`Implicit::grad_batch`]) per round; `step(i, p, d)`
/// gets point `i` at `p` with (f, ∇f) = `d` there and returns its next position, or
/// `None` once it is settled. `given`: (f, ∇f) at `pts` already (what
/// [`Implicit::grad_batch`] gives there), used by the first round instead of an
/// evaluation.
fn batch_rounds(
    f: &dyn Implicit,
    pts: &[[f64; 3]],
    given: Option<&[crate::implicit::Dual<f64>]>,
    rounds: usize,
    mut step: impl FnMut(usize, [f64; 3], crate::implicit::Dual<f64>) -> Option<[f64; 3]>,
) {
    let mut active: Vec<usize> = (0..pts.len()).collect();
    let mut cur: Vec<[f64; 3]> = pts.to_vec();
    let mut d = vec![crate::implicit::Dual::ZERO; pts.len()];
    for round in 0..rounds {
        if active.is_empty() {
            break;
        }
        let n = active.len();
        match given {
            Some(g) if round == 0 => d.copy_from_slice(g),
            _ => f.grad_batch(&cur[..n], &mut d[..n]),
        }
        let mut keep = 0;
        for j in 0..n {
            if let Some(q) = step(active[j], cur[j], d[j]) {
                active[keep] = active[j];
                cur[keep] = q;
                keep += 1;
            }
        }
        active.truncate(keep);
    }
}

/// [`project`] of every point of `pts`, bit for bit, with the batch gradient: each
/// Newton round evaluates the points not yet settled in one batch.
pub fn project_batch(
    f: &dyn Implicit,
    pts: &[[f64; 3]],
    steps: usize,
    tol: f64,
) -> Vec<Option<[f64; 3]>> {
    project_rounds(f, pts, None, steps, tol, false)
}

/// [`project_batch`], except that a point where f is exactly 0 is kept as it is (also
/// where ∇f vanishes there, e.g. f ≡ 0, where `project` gives up): its first round's
/// value decides it, with no separate evaluation of f. Bit for bit the points of
/// evaluating f first and projecting the others.
pub fn project_batch_or_on(
    f: &dyn Implicit,
    pts: &[[f64; 3]],
    steps: usize,
    tol: f64,
) -> Vec<Option<[f64; 3]>> {
    project_rounds(f, pts, None, steps, tol, true)
}

/// [`project_batch_or_on`], given (f, ∇f) at every point of `pts` (`grads`, what
/// [`Implicit::grad_batch`] gives there, e.g. from a test made before): the first
/// round evaluates nothing. The same points, bit for bit.
pub fn project_batch_or_on_given(
    f: &dyn Implicit,
    pts: &[[f64; 3]],
    grads: &[crate::implicit::Dual<f64>],
    steps: usize,
    tol: f64,
) -> Vec<Option<[f64; 3]>> {
    assert_eq!(pts.len(), grads.len(), "one gradient per point");
    project_rounds(f, pts, Some(grads), steps, tol, true)
}

/// The Newton rounds of [`project_batch`] (`keep_on_s`: and of [`project_batch_or_on`]).
fn project_rounds(
    f: &dyn Implicit,
    pts: &[[f64; 3]],
    given: Option<&[crate::implicit::Dual<f64>]>,
    steps: usize,
    tol: f64,
    keep_on_s: bool,
) -> Vec<Option<[f64; 3]>> {
    let mut out = vec![None; pts.len()];
    let mut first = vec![keep_on_s; pts.len()];
    batch_rounds(f, pts, given, steps.max(1), |i, p, d| {
        if std::mem::take(&mut first[i]) && d.v == 0.0 {
            out[i] = Some(p);
            return None;
        }
        // A point whose gradient vanishes or is not finite is dropped (None).
        let (r, len) = newton_step(f, p, d)?;
        if len <= tol {
            out[i] = Some(r);
            None
        } else {
            Some(r)
        }
    });
    out
}

/// Exactly `steps` Newton steps (fewer if f vanishes exactly), as GradNormal's
/// Algorithm 2, line 6 prescribes: the point, and whether every step had a usable
/// gradient (if not, the point where it stopped). One gradient evaluation per step.
pub fn project_steps(f: &dyn Implicit, mut p: [f64; 3], steps: usize) -> ([f64; 3], bool) {
    for _ in 0..steps {
        let d = f.grad(p);
        if d.v == 0.0 {
            break;
        }
        match newton_step(f, p, d) {
            Some((q, _)) => p = q,
            None => return (p, false),
        }
    }
    (p, true)
}

/// [`project_steps`] of every point of `pts`, bit for bit, with the batch gradient:
/// each round evaluates the points still moving in one batch.
pub fn project_steps_batch(
    f: &dyn Implicit,
    pts: &[[f64; 3]],
    steps: usize,
) -> Vec<([f64; 3], bool)> {
    let mut out: Vec<([f64; 3], bool)> = pts.iter().map(|&p| (p, true)).collect();
    batch_rounds(f, pts, None, steps, |i, p, d| {
        if d.v == 0.0 {
            return None;
        }
        match newton_step(f, p, d) {
            Some((q, _)) => {
                out[i] = (q, true);
                Some(q)
            }
            None => {
                out[i] = (p, false);
                None
            }
        }
    });
    out
}

// ---------------------------------------------------------------------------------
// All roots on a segment in general position, with uncertain end points.

/// One root of f on a segment, certified unique in its piece `[t0, t1]` of the
/// parameter: 0 ∉ □(d/dt f) on the piece and the end signs differ.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SegmentRoot {
    pub t0: f64,
    pub t1: f64,
    /// f < 0 at `t0` and f > 0 at `t1` (the segment enters {f > 0}).
    pub rising: bool,
}

/// What [`isolate_segment`] found: every root of f on the segment, each in its own
/// piece, unless `undecided` lists pieces where neither exclusion nor uniqueness could
/// be proven (a tangent or grazing crossing, an end point on f = 0, f not smooth).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SegmentRoots {
    pub roots: Vec<SegmentRoot>,
    pub undecided: Vec<[f64; 2]>,
    /// Pieces processed.
    pub pieces: u32,
}

impl SegmentRoots {
    /// Is the list of roots proven complete?
    pub fn complete(&self) -> bool {
        self.undecided.is_empty()
    }
}

/// Limits of [`isolate_segment`].
#[derive(Clone, Copy, Debug)]
pub struct SegmentBudget {
    /// Bisections along one path (the piece width is then 2^-depth of the segment).
    pub max_depth: u32,
    /// Pieces processed in all; the rest is reported undecided.
    pub max_pieces: u32,
}

impl Default for SegmentBudget {
    fn default() -> Self {
        SegmentBudget {
            max_depth: 40,
            max_pieces: 4000,
        }
    }
}

fn hull(x: f64, y: f64) -> Interval {
    Interval::try_from((x.min(y), x.max(y))).unwrap_or(Interval::ENTIRE)
}

/// Every root of f on the segment X(t) = a + t (b − a), t ∈ [0, 1], where the end
/// points are known only to lie in the boxes `a` ∈ `ea`, `b` ∈ `eb` (e.g. interval
/// enclosures of Voronoi vertices; degenerate boxes for float points). Roots outside
/// the box `inside` (when given) are not sought: a piece whose enclosure X(T) misses
/// it is dropped, and a piece is only concluded once X(T) ⊂ `inside`.
///
/// Unlike [`IntervalIsolation`] (Snyder's axis-aligned edges) the derivative is the
/// directional one, g'(t) = ∇f(X(t))·(b − a), enclosed by □∇f(X(T))·(□b − □a), and
/// the exclusion test is the natural enclosure intersected with the one-dimensional
/// mean-value form g(m) + □g'(T)(T − m). Per piece T = [t0, t1], with the end signs
/// proven on the point enclosures X(t0), X(t1):
/// 1. 0 ∉ □g(T): no root;
/// 2. f smooth on X(T) and 0 ∉ □g'(T): g is monotone, so one root if the end signs
///    differ, none if they agree;
/// 3. otherwise bisect (the split point moved if its sign is undecided), down to
///    `max_depth`, then report the piece undecided.
///
/// Both conclusions hold for the true segment from any a ∈ `ea` to any b ∈ `eb`:
/// every enclosure contains the values along it (inclusion isotonicity).
pub fn isolate_segment(
    f: &dyn Implicit,
    ea: &IBox,
    eb: &IBox,
    inside: Option<&IBox>,
    budget: SegmentBudget,
) -> SegmentRoots {
    // Arithmetic in the fast interval type `Iv`: inari's bounds, bit for bit.
    use crate::implicit::directed::Iv;
    let (iva, ivb) = (ea.map(Iv::from_interval), eb.map(Iv::from_interval));
    let dir: [Iv; 3] = [0, 1, 2].map(|k| ivb[k] - iva[k]);
    let at = |t: Iv| -> IBox { [0, 1, 2].map(|k| (iva[k] + t * dir[k]).to_interval()) };
    let pt = |t: f64| Iv::from_interval(Interval::try_from((t, t)).unwrap_or(Interval::ENTIRE));
    let sign = |t: f64| segment_sign(f, ea, eb, t);
    let mut out = SegmentRoots::default();
    // Stack of pieces (t0, t1, sign at t0, sign at t1, depth); the right half is pushed
    // first so that roots come out in increasing t.
    let mut stack = vec![(0.0f64, 1.0f64, sign(0.0), sign(1.0), 0u32)];
    while let Some((t0, t1, s0, s1, depth)) = stack.pop() {
        if out.pieces >= budget.max_pieces {
            out.undecided.push([t0, t1]);
            continue;
        }
        out.pieces += 1;
        let tt = Iv::from_interval(hull(t0, t1));
        let x = at(tt);
        let mut within = true;
        if let Some(d) = inside {
            if (0..3).any(|k| x[k].sup() < d[k].inf() || x[k].inf() > d[k].sup()) {
                continue; // X(T) misses the box: nothing sought here
            }
            within = (0..3).all(|k| d[k].inf() <= x[k].inf() && x[k].sup() <= d[k].sup());
        }
        // The value enclosure alone first: most pieces (a Voronoi edge far from S)
        // end here, without the gradient or the regularity pass. Exclusion needs no
        // smoothness: a piece whose enclosure misses 0 holds no zero of f.
        let v0 = f.eval_interval(&x);
        if !v0.is_empty() && excludes_zero(v0) {
            continue;
        }
        let reg = f.regularity(&x);
        let d = f.grad_interval(&x);
        let mut enc = d.v;
        let mut dg = Interval::ENTIRE;
        if reg == Regularity::Smooth {
            let g = d.g.map(Iv::from_interval);
            let dgi = g[0] * dir[0] + g[1] * dir[1] + g[2] * dir[2];
            dg = dgi.to_interval();
            let m = 0.5 * (t0 + t1);
            let mv = Iv::from_interval(f.eval_interval(&at(pt(m)))) + dgi * (tt - pt(m));
            let both = enc.intersection(mv.to_interval());
            if !both.is_empty() {
                enc = both;
            }
        }
        if !enc.is_empty() && excludes_zero(enc) {
            continue;
        }
        if within && reg == Regularity::Smooth && !dg.is_empty() && excludes_zero(dg) {
            if let (Some(a), Some(b)) = (s0, s1) {
                if a != b {
                    out.roots.push(SegmentRoot { t0, t1, rising: b });
                }
                continue;
            }
        }
        if depth >= budget.max_depth {
            out.undecided.push([t0, t1]);
            continue;
        }
        let w = t1 - t0;
        let split = [0.5, 0.375, 0.625, 0.25, 0.75]
            .iter()
            .map(|&q| t0 + q * w)
            .filter(|&tm| tm > t0 && tm < t1)
            .find_map(|tm| sign(tm).map(|s| (tm, s)));
        match split {
            Some((tm, sm)) => {
                stack.push((tm, t1, Some(sm), s1, depth + 1));
                stack.push((t0, tm, s0, Some(sm), depth + 1));
            }
            None => out.undecided.push([t0, t1]),
        }
    }
    out
}

/// The sign of f at parameter t of the boxed segment of [`isolate_segment`], proven
/// for every a ∈ `ea`, b ∈ `eb` (true: f > 0), or `None` when 0 is in the enclosure.
pub fn segment_sign(f: &dyn Implicit, ea: &IBox, eb: &IBox, t: f64) -> Option<bool> {
    use crate::implicit::directed::Iv;
    let tt = Iv::from_interval(Interval::try_from((t, t)).ok()?);
    let iv = Iv::from_interval;
    // In `Iv`: inari's bounds, bit for bit.
    let x: IBox = [0, 1, 2].map(|k| (iv(ea[k]) + tt * (iv(eb[k]) - iv(ea[k]))).to_interval());
    let v = f.eval_interval(&x);
    if v.is_empty() {
        None
    } else if v.inf() > 0.0 {
        Some(true)
    } else if v.sup() < 0.0 {
        Some(false)
    } else {
        None
    }
}

/// A float point of a root isolated by [`isolate_segment`] on the float segment
/// a → b: the Illinois variant of regula falsi on f along the piece (the root is
/// simple and unique there, so it converges superlinearly) until the bracket is
/// narrower than `tol` in t or 60 steps; no certificate (the piece is the certificate).
pub fn segment_root_point(
    f: &dyn Implicit,
    a: [f64; 3],
    b: [f64; 3],
    root: &SegmentRoot,
    tol: f64,
) -> ([f64; 3], f64) {
    let g = |t: f64| f.eval(lerp(a, b, t));
    let (mut lo, mut hi) = (root.t0, root.t1);
    let (mut glo, mut ghi) = (g(lo), g(hi));
    if glo == 0.0 {
        return (lerp(a, b, lo), lo);
    }
    if ghi == 0.0 || (glo < 0.0) == (ghi < 0.0) {
        // An exact zero, or float signs that disagree with the certified ones (a tiny
        // piece): its midpoint.
        let t = if ghi == 0.0 { hi } else { 0.5 * (lo + hi) };
        return (lerp(a, b, t), t);
    }
    let mut side = 0i8;
    let mut t = 0.5 * (lo + hi);
    for _ in 0..60 {
        t = (lo * ghi - hi * glo) / (ghi - glo);
        if !(t > lo && t < hi) {
            t = 0.5 * (lo + hi);
        }
        let gt = g(t);
        if gt == 0.0 || hi - lo <= tol {
            break;
        }
        if (gt < 0.0) == (glo < 0.0) {
            lo = t;
            glo = gt;
            if side == -1 {
                ghi *= 0.5;
            }
            side = -1;
        } else {
            hi = t;
            ghi = gt;
            if side == 1 {
                glo *= 0.5;
            }
            side = 1;
        }
        if hi - lo <= tol {
            t = if glo.abs() < ghi.abs() { lo } else { hi };
            break;
        }
    }
    (lerp(a, b, t), t)
}
