//! Extra fibres for accuracy between fibres (`--algo gvn --set tolerance=T`).
//!
//! The sweep certifies the topology; its polyline joins each arc's points on
//! consecutive fibres by straight segments, and how far the curve strays from those
//! segments is not part of that proof (the chapter says so). Here, per strip, rational
//! fibres are added between the sweep's fibres until an interval proof bounds the
//! distance from every point of every arc inside the domain to its segment by T.
//!
//! **The enclosure.** Work in the sweep's sheared frame (u, v) = (x − s·y, y), where the
//! analysed polynomial is g. Between two consecutive nodes a < b of a strip (a node is
//! a rational fibre u = q, or the strip's event with its isolating interval
//! [α_lo, α_hi]), take a group of arcs (one arc between two rational fibres; at an
//! event end, all the arcs that end at the same event point) and a v-interval J that
//! contains the certified boxes of the group's end points on both nodes. If g has no
//! zero on the two horizontal edges U × {J_lo} and U × {J_hi}, U = [a_lo, b_hi]
//! (proven by outward-rounded interval Horner on sub-intervals of U), then every arc of
//! the group lies in U × J over [a, b]: inside the open strip an arc is the graph of a
//! continuous root function of g(u, ·) (the roots are simple there and keep their
//! order), it starts (or, at an event, tends) to a point inside J and ends inside J,
//! and leaving J would need a zero of g on one of the two edges (intermediate value
//! theorem). The boxes are the certified ones: isolating intervals at rational fibres,
//! the sweep's certified root boxes at events.
//!
//! **The bound.** The box U × J maps to a parallelogram P in (x, y) (the unshear is
//! linear); the distance to a segment is convex, so its maximum over P is at one of
//! P's four corners. The distance from each corner to the output segment (its two f64
//! end points, read as exact rationals) is computed exactly in rationals and rounded up
//! to f64. This bounds the distance from every point of the arc over [a, b] to the
//! polyline (one-sided: curve to polyline). Where no group box is proven, or the bound
//! stays above T when the fibre budget or the depth is spent (near vertical
//! tangents and singular points arcs can be steep), the arc is reported as not
//! reached, with the best bound proven if any; nothing is claimed there.
//!
//! The extra fibres keep the topology: every new fibre lies strictly inside a strip, so
//! it meets the strip's n arcs in n ordered simple roots, and straight segments between
//! ordered points of consecutive vertical lines (or from one event point to ordered
//! points) do not cross, which is the sweep's own argument. The re-checkable
//! certificate stays the sweep's (coarse) one; the extra fibres and their bounds are
//! not re-checked by `certmesh check-curve` (not done).
use super::algnum::{isolate, q_to_f64, var01, RealAlg};
use super::bipoly::BiPoly;
use super::fint;
use super::sweep::{Label, SweepResult};
use crate::error::{Error, Result};
use crate::implicit::number::next_up;
use inari::Interval;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};
use serde::Serialize;

/// An event as the extra fibres need it: its u (certified interval), the certified
/// v-boxes of its points, their vertices and branch counts.
#[derive(Clone, Debug)]
pub struct EventArcs {
    pub u: RealAlg,
    pub boxes: Vec<(BigRational, BigRational)>,
    /// Per point: the fibre's multiple root; on a side of the domain.
    pub special: Vec<bool>,
    pub boundary: Vec<bool>,
    /// A point on a side of the domain (not a vertical side at shear 0): v = v0 + v1·u.
    pub snap: Vec<Option<(BigRational, BigRational)>>,
    /// β(α) = num(α)/den(α) when the event passed the genericity test.
    pub beta: Option<(super::upoly::UPoly, super::upoly::UPoly)>,
    pub vid: Vec<Option<u32>>,
    pub left: Vec<usize>,
    pub right: Vec<usize>,
}

/// A strip: its events, its rational sample fibre and that fibre's roots and vertices.
#[derive(Clone, Debug)]
pub struct StripArcs {
    pub left: Option<usize>,
    pub right: Option<usize>,
    pub q: BigRational,
    pub roots: Vec<RealAlg>,
    pub vid: Vec<Option<u32>>,
}

/// The sweep's data the extra fibres start from.
#[derive(Clone, Debug)]
pub struct ArcData {
    /// The analysed (sheared, square-free) polynomial g(u, v).
    pub g: BiPoly,
    pub s: i64,
    pub events: Vec<EventArcs>,
    pub strips: Vec<StripArcs>,
}

/// An arc where the tolerance was not reached.
#[derive(Clone, Debug, Serialize)]
pub struct ArcMiss {
    /// Strip index (left to right) and arc index (bottom to top) in the sheared frame.
    pub strip: usize,
    pub arc: usize,
    /// The best deviation bound proven for the whole arc, if every piece got one.
    pub bound: Option<f64>,
}

/// What the extra fibres achieved.
#[derive(Clone, Debug, Serialize)]
pub struct ToleranceReport {
    pub tolerance: f64,
    /// Rational fibres added (over all strips).
    pub extra_fibres: usize,
    /// Arcs inside the domain, and those whose certified bound is ≤ the tolerance.
    pub arcs: usize,
    pub arcs_within_tolerance: usize,
    /// The largest certified bound over the arcs within tolerance (curve-to-polyline
    /// distance; one-sided).
    pub certified_bound: f64,
    /// Arcs where the tolerance was not reached (nothing is claimed there).
    pub not_reached: Vec<ArcMiss>,
}

/// Budgets of the extra fibres.
#[derive(Clone, Debug, Serialize)]
pub struct ToleranceParams {
    pub tolerance: f64,
    /// Extra fibres allowed over all strips (default 4000).
    pub max_fibres: usize,
    /// Bisection depth allowed per gap between the sweep's fibres (default 40).
    pub max_depth: usize,
}

/// A node of a strip: an event end (index) or a rational fibre.
#[derive(Clone, Debug)]
enum Node {
    Event(usize),
    Fibre {
        q: BigRational,
        /// Certified isolating intervals of all roots (bottom to top).
        boxes: Vec<(BigRational, BigRational)>,
        vid: Vec<Option<u32>>,
    },
}

fn qmin(a: &BigRational, b: &BigRational) -> BigRational {
    a.min(b).clone()
}
fn qmax(a: &BigRational, b: &BigRational) -> BigRational {
    a.max(b).clone()
}

/// An f64 upper bound of √x for a rational x ≥ 0.
fn sqrt_up(x: &BigRational) -> f64 {
    let mut f = q_to_f64(x);
    if BigRational::from_float(f).is_none_or(|r| &r < x) {
        f = next_up(f);
    }
    next_up(f.max(0.0).sqrt())
}

/// The squared distance from point c to the segment [p, q], exactly.
fn dist2_seg(c: &[BigRational; 2], p: &[BigRational; 2], q: &[BigRational; 2]) -> BigRational {
    let d = [&q[0] - &p[0], &q[1] - &p[1]];
    let w = [&c[0] - &p[0], &c[1] - &p[1]];
    let dd = &d[0] * &d[0] + &d[1] * &d[1];
    let t = if dd.is_zero() {
        BigRational::zero()
    } else {
        let t = (&w[0] * &d[0] + &w[1] * &d[1]) / &dd;
        t.max(BigRational::zero()).min(BigRational::one())
    };
    let e = [&w[0] - &t * &d[0], &w[1] - &t * &d[1]];
    &e[0] * &e[0] + &e[1] * &e[1]
}

/// Interval coefficients of g: per power of v, the coefficients in u.
struct GIv(Vec<Vec<Interval>>);

impl GIv {
    fn new(g: &BiPoly) -> Option<Self> {
        g.c.iter()
            .map(fint::poly_iv)
            .collect::<Option<Vec<_>>>()
            .map(GIv)
    }
    fn eval(&self, u: Interval, v: Interval) -> Interval {
        let mut acc = fint::pt(0.0);
        for cj in self.0.iter().rev() {
            acc = acc * v + fint::horner(cj, u);
        }
        acc
    }
}

/// The f64 end points of output vertex `id` as exact rationals.
fn vert_q(verts: &[[f64; 2]], id: u32) -> [BigRational; 2] {
    let p = verts[id as usize];
    [
        BigRational::from_float(p[0]).expect("finite vertex"),
        BigRational::from_float(p[1]).expect("finite vertex"),
    ]
}

struct Ctx<'a> {
    data: &'a ArcData,
    giv: GIv,
    events: Vec<RealAlg>,
    /// The event points' certified v-boxes, refined where possible.
    boxes: Vec<Vec<(BigRational, BigRational)>>,
    s: BigRational,
}

/// The sign of g over α's interval × {v}, when interval Horner proves it.
fn sign_over(giv: &GIv, a: &RealAlg, v: &BigRational) -> Option<i32> {
    let u = fint::qq_iv(&a.lo, &a.hi)?;
    let vi = fint::q_iv(v)?;
    fint::iv_sign(giv.eval(u, vi)).filter(|&s| s != 0)
}

/// Shrink the certified box (lo, hi) of a simple root of g(α, ·) (the sweep proved
/// exactly one root in it) to width ≤ w: bisection, each half decided by the signs of
/// g over α's interval at lo and at the midpoint (α refined when they are not proven;
/// gives up, keeping the last certified box, when they still are not).
fn shrink_simple(giv: &GIv, a: &mut RealAlg, bx: &mut (BigRational, BigRational), w: &BigRational) {
    let two = BigRational::from_integer(BigInt::from(2));
    let mut tries = 0;
    while &(&bx.1 - &bx.0) > w && tries < 400 {
        let m = (&bx.0 + &bx.1) / &two;
        match (sign_over(giv, a, &bx.0), sign_over(giv, a, &m)) {
            (Some(sl), Some(sm)) => {
                if sl == sm {
                    bx.0 = m;
                } else {
                    bx.1 = m;
                }
            }
            _ => {
                tries += 1;
                if a.is_exact() {
                    return;
                }
                let w2 = a.width() / &two;
                a.refine_to(&w2);
            }
        }
    }
}

/// The box of β(α) = num(α)/den(α) from α's interval (exact interval Horner), when
/// den's enclosure excludes 0.
fn beta_box(
    num: &super::upoly::UPoly,
    den: &super::upoly::UPoly,
    a: &RealAlg,
) -> Option<(BigRational, BigRational)> {
    use super::algnum::eval_interval;
    let (nl, nh) = eval_interval(num, &a.lo, &a.hi);
    let (dl, dh) = eval_interval(den, &a.lo, &a.hi);
    if !dl.is_positive() && !dh.is_negative() {
        return None;
    }
    let qs = [&nl / &dl, &nl / &dh, &nh / &dl, &nh / &dh];
    Some((qs.iter().min()?.clone(), qs.iter().max()?.clone()))
}

impl Ctx<'_> {
    fn u_range(&self, n: &Node) -> (BigRational, BigRational) {
        match n {
            Node::Event(e) => (self.events[*e].lo.clone(), self.events[*e].hi.clone()),
            Node::Fibre { q, .. } => (q.clone(), q.clone()),
        }
    }
    /// The certified v-box and the vertex of arc `i`'s end on node `n`; `left_end`: n
    /// is the piece's left node (so the arc leaves an event to the right).
    fn end(
        &self,
        n: &Node,
        i: usize,
        left_end: bool,
    ) -> Option<(usize, (BigRational, BigRational), Option<u32>)> {
        match n {
            Node::Fibre { boxes, vid, .. } => Some((i, boxes.get(i)?.clone(), *vid.get(i)?)),
            Node::Event(e) => {
                let ev = &self.data.events[*e];
                let counts = if left_end { &ev.right } else { &ev.left };
                let mut t = 0usize;
                for (r, &c) in counts.iter().enumerate() {
                    if i < t + c {
                        return Some((r, self.boxes[*e][r].clone(), ev.vid[r]));
                    }
                    t += c;
                }
                None
            }
        }
    }
    /// Bounds for the arcs `arcs` (inside the domain) over the piece between nodes a
    /// and b, whose vertices are `va[t]`, `vb[t]`: per arc, the certified bound or
    /// None.
    #[allow(clippy::too_many_arguments, clippy::type_complexity)]
    fn piece(
        &self,
        a: &Node,
        b: &Node,
        arcs: &[usize],
        verts: &[[f64; 2]],
        va: &[Option<u32>],
        vb: &[Option<u32>],
        tol: f64,
    ) -> Vec<Option<f64>> {
        let (ulo, _) = self.u_range(a);
        let (_, uhi) = self.u_range(b);
        let mut out = vec![None; arcs.len()];
        // Group the arcs by their end points on event nodes.
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut keys: Vec<(Option<usize>, Option<usize>)> = Vec::new();
        for (t, &i) in arcs.iter().enumerate() {
            let ka = match a {
                Node::Event(_) => self.end(a, i, true).map(|e| e.0),
                _ => None,
            };
            let kb = match b {
                Node::Event(_) => self.end(b, i, false).map(|e| e.0),
                _ => None,
            };
            let key = (ka, kb);
            let grouped = key.0.is_some() || key.1.is_some();
            match keys.iter().position(|k| grouped && *k == key) {
                Some(gi) => groups[gi].push(t),
                None => {
                    keys.push(key);
                    groups.push(vec![t]);
                }
            }
        }
        // Sheared coordinates of an output vertex: (x − s·y, y), exactly.
        let sheared = |id: u32| {
            let p = vert_q(verts, id);
            [&p[0] - &self.s * &p[1], p[1].clone()]
        };
        for grp in groups {
            // The chord ℓ: from the group's left vertex to the mean of its right
            // vertices (one arc: its own segment; a group shares one end point).
            let mut ends = Vec::new();
            for &t in &grp {
                let (Some(pa), Some(pb)) = (va[t], vb[t]) else {
                    continue;
                };
                ends.push((sheared(pa), sheared(pb)));
            }
            if ends.len() != grp.len() {
                continue;
            }
            let k = BigRational::from_integer(BigInt::from(ends.len()));
            let mean = |f: &dyn Fn(&([BigRational; 2], [BigRational; 2])) -> BigRational| {
                ends.iter().map(f).fold(BigRational::zero(), |x, y| x + y) / &k
            };
            let p0 = [mean(&|e| e.0[0].clone()), mean(&|e| e.0[1].clone())];
            let p1 = [mean(&|e| e.1[0].clone()), mean(&|e| e.1[1].clone())];
            if p1[0] <= p0[0] {
                continue;
            }
            let slope = (&p1[1] - &p0[1]) / (&p1[0] - &p0[0]);
            let ell = |u: &BigRational| &p0[1] + &slope * (u - &p0[0]);
            // Offsets c of the group's certified end boxes on the rational fibres from
            // ℓ (the proof needs the arcs inside the region at a fibre; at an event
            // end they tend to the event point, on ℓ, and nothing more is needed).
            let mut c0: Option<(BigRational, BigRational)> = None;
            for &t in &grp {
                let i = arcs[t];
                for (n, left) in [(a, true), (b, false)] {
                    if matches!(n, Node::Event(_)) {
                        continue;
                    }
                    let Some((_, (lo, hi), _)) = self.end(n, i, left) else {
                        continue;
                    };
                    let (ua, ub) = self.u_range(n);
                    for u in [&ua, &ub] {
                        let (l, h) = (&lo - ell(u), &hi - ell(u));
                        c0 = Some(match c0 {
                            None => (l, h),
                            Some((x, y)) => (qmin(&x, &l), qmax(&y, &h)),
                        });
                    }
                }
            }
            let Some((c0lo, c0hi)) = c0 else {
                continue;
            };
            let tq = BigRational::from_float(tol).unwrap_or_else(BigRational::one);
            for f in [-16i64, -4, 1, 4, 16, 64, 256] {
                let m = if f > 0 {
                    &tq * BigRational::from_integer(BigInt::from(f))
                } else {
                    &tq / BigRational::from_integer(BigInt::from(-f))
                };
                let (clo, chi) = (&c0lo - &m, &c0hi + &m);
                let du = &uhi - &ulo;
                let edge_ok = |c: &BigRational| {
                    let v0 = ell(&ulo) + c;
                    zero_free_segment(&self.data.g, &ulo, &du, &v0, &(&slope * &du))
                };
                if !(edge_ok(&clo) && edge_ok(&chi)) {
                    continue;
                }
                // Proven: the group lies in the parallelogram over [ulo, uhi] between
                // ℓ + clo and ℓ + chi. Its corners in (x, y):
                let corners: Vec<[BigRational; 2]> =
                    [(&ulo, &clo), (&ulo, &chi), (&uhi, &clo), (&uhi, &chi)]
                        .iter()
                        .map(|(u, c)| {
                            let v = ell(u) + *c;
                            [*u + &self.s * &v, v]
                        })
                        .collect();
                for &t in &grp {
                    let (pa, pb) = (
                        vert_q(verts, va[t].expect("checked")),
                        vert_q(verts, vb[t].expect("checked")),
                    );
                    let d2 = corners
                        .iter()
                        .map(|c| dist2_seg(c, &pa, &pb))
                        .max()
                        .expect("four corners");
                    out[t] = Some(sqrt_up(&d2));
                }
                break;
            }
        }
        out
    }
}

/// Is g ≠ 0 on the closed segment {(u0 + t·du, v0 + t·dv) : t ∈ [0, 1]}? Exactly:
/// h(t) = g(u0 + t·du, v0 + t·dv) (integer, up to a positive factor) is non-zero at
/// t = 0 and t = 1 and has no root in (0, 1) (Descartes: no sign variation of the
/// transformed polynomial, else the isolated real roots are compared with 0 and 1).
fn zero_free_segment(
    g: &BiPoly,
    u0: &BigRational,
    du: &BigRational,
    v0: &BigRational,
    dv: &BigRational,
) -> bool {
    let h = g.on_line(u0, du, v0, dv);
    if h.is_zero() {
        return false;
    }
    let (z, o) = (BigRational::zero(), BigRational::one());
    if h.sign_at(&z) == 0 || h.sign_at(&o) == 0 {
        return false;
    }
    if h.deg() <= 0 || var01(&h) == 0 {
        return true;
    }
    let Ok(roots) = isolate(&h) else {
        return false;
    };
    for mut r in roots {
        let (a, b) = (r.cmp_q(&z), r.cmp_q(&o));
        if a != std::cmp::Ordering::Less && b != std::cmp::Ordering::Greater {
            return false;
        }
    }
    true
}

/// Add rational fibres to the sweep's result until every arc inside the domain is
/// proven within `p.tolerance` of its polyline (or the budgets are spent); replaces
/// `r.curve`'s segments by the refined chains and appends the new vertices (labelled
/// regular). The certificate is left as it is.
pub fn refine(r: &mut SweepResult, p: &ToleranceParams) -> Result<()> {
    if !(p.tolerance > 0.0 && p.tolerance.is_finite()) {
        return Err(Error::Param(
            "--set tolerance must be a positive number".into(),
        ));
    }
    let Some(data) = r.arcs.take() else {
        r.tolerance = Some(ToleranceReport {
            tolerance: p.tolerance,
            extra_fibres: 0,
            arcs: 0,
            arcs_within_tolerance: 0,
            certified_bound: 0.0,
            not_reached: Vec::new(),
        });
        return Ok(());
    };
    let giv = GIv::new(&data.g).ok_or_else(|| {
        Error::TooLarge(
            "the polynomial's coefficients exceed the f64 range of the interval filter".into(),
        )
    })?;
    let s = data.s;
    let mut ctx = Ctx {
        data: &data,
        giv,
        events: data.events.iter().map(|e| e.u.clone()).collect(),
        boxes: data.events.iter().map(|e| e.boxes.clone()).collect(),
        s: BigRational::from_integer(BigInt::from(s)),
    };
    let two = BigRational::from_integer(BigInt::from(2));
    let fine = BigRational::new(BigInt::one(), BigInt::one() << 40u32);
    let mut verts = std::mem::take(&mut r.curve.vertices);
    // The event points first: their output vertices are the midpoints of certified
    // boxes, which the sweep leaves as wide as its proofs needed. Refine α and each
    // box (simple roots by bisection, the generic multiple root as num/den over α's
    // interval; a clustered multiple root and points on the domain's sides stay) to
    // well below the tolerance and move the vertex to the new midpoint (still inside
    // its certified box, so the certificate's claims are unchanged).
    let wt = BigRational::from_float(p.tolerance / 64.0)
        .unwrap_or_else(|| BigRational::new(BigInt::one(), BigInt::one() << 40u32))
        .min(BigRational::new(BigInt::one(), BigInt::one() << 10u32));
    for (e, ev) in data.events.iter().enumerate() {
        if ev.vid.iter().all(|v| v.is_none()) {
            continue;
        }
        let a = &mut ctx.events[e];
        a.refine_to(&wt);
        for ri in 0..ev.boxes.len() {
            let Some(id) = ev.vid[ri] else {
                continue;
            };
            if let Some((v0, v1)) = &ev.snap[ri] {
                // On a side: the sweep's own placement, at the refined u.
                let u = a.to_f64();
                let mut pt = [
                    u + s as f64 * (q_to_f64(v0) + q_to_f64(v1) * u),
                    q_to_f64(v0) + q_to_f64(v1) * u,
                ];
                if v1.is_zero() {
                    pt[1] = q_to_f64(v0);
                } else {
                    pt[0] = q_to_f64(&(v0 * &ctx.s));
                }
                verts[id as usize] = pt;
                continue;
            }
            let bx = &mut ctx.boxes[e][ri];
            if ev.special[ri] {
                let Some((num, den)) = &ev.beta else {
                    continue;
                };
                let mut t = 0;
                loop {
                    if let Some(b) = beta_box(num, den, a) {
                        // Both boxes hold β: keep their intersection.
                        let nb = (qmax(&bx.0, &b.0), qmin(&bx.1, &b.1));
                        if nb.0 <= nb.1 {
                            *bx = nb;
                        }
                    }
                    t += 1;
                    if &bx.1 - &bx.0 <= wt || t > 30 || a.is_exact() {
                        break;
                    }
                    let w2 = a.width() / BigRational::from_integer(BigInt::from(16));
                    a.refine_to(&w2);
                }
            } else {
                shrink_simple(&ctx.giv, a, bx, &wt);
            }
            let v = q_to_f64(&((&bx.0 + &bx.1) / &two));
            verts[id as usize] = [a.to_f64() + s as f64 * v, v];
        }
    }
    let mut labels = std::mem::take(&mut r.labels);
    let mut segs: Vec<[u32; 2]> = Vec::new();
    let mut extra = 0usize;
    let mut n_arcs = 0usize;
    let mut within = 0usize;
    let mut worst = 0.0f64;
    let mut misses = Vec::new();
    for (si, st) in data.strips.iter().enumerate() {
        let arcs: Vec<usize> = (0..st.vid.len()).filter(|&i| st.vid[i].is_some()).collect();
        if arcs.is_empty() {
            continue;
        }
        let (Some(le), Some(re)) = (st.left, st.right) else {
            return Err(Error::Param(
                "internal: an arc inside the domain in an unbounded strip".into(),
            ));
        };
        n_arcs += arcs.len();
        let count = st.vid.len();
        let sample = Node::Fibre {
            q: st.q.clone(),
            boxes: st
                .roots
                .iter()
                .map(|r| (r.lo.clone(), r.hi.clone()))
                .collect(),
            vid: st.vid.clone(),
        };
        // Per arc: the vertices of its chain (left to right) and its bound so far.
        let mut nodes = vec![Node::Event(le), sample, Node::Event(re)];
        let mut bound: Vec<Option<f64>> = vec![Some(0.0); arcs.len()];
        // Gaps to examine: (index of the left node, depth).
        let mut todo: Vec<(usize, usize)> = vec![(1, 0), (0, 0)];
        let mut done_pieces: Vec<(BigRational, Vec<Option<f64>>)> = Vec::new();
        while let Some((k, depth)) = todo.pop() {
            let (a, b) = (nodes[k].clone(), nodes[k + 1].clone());
            // Event ends: refine α until its interval is small against the gap.
            for (n, left) in [(&a, true), (&b, false)] {
                if let Node::Event(e) = n {
                    let other = if left { &b } else { &a };
                    let (olo, ohi) = ctx.u_range(other);
                    let ev = &mut ctx.events[*e];
                    let gap = if left { &olo - &ev.hi } else { &ev.lo - &ohi };
                    if gap.is_positive() {
                        let w = &gap / BigRational::from_integer(BigInt::from(64));
                        ev.refine_to(&w);
                    }
                }
            }
            let va: Vec<Option<u32>> = arcs
                .iter()
                .map(|&i| ctx.end(&a, i, true).and_then(|e| e.2))
                .collect();
            let vb: Vec<Option<u32>> = arcs
                .iter()
                .map(|&i| ctx.end(&b, i, false).and_then(|e| e.2))
                .collect();
            let bs = ctx.piece(&a, &b, &arcs, &verts, &va, &vb, p.tolerance);
            let ok = bs.iter().all(|x| x.is_some_and(|v| v <= p.tolerance));
            if ok || depth >= p.max_depth || extra >= p.max_fibres {
                let (lo, _) = ctx.u_range(&a);
                done_pieces.push((lo, bs));
                continue;
            }
            // A new fibre strictly inside the gap.
            let (_, alo_hi) = ctx.u_range(&a);
            let (blo, _) = ctx.u_range(&b);
            if alo_hi >= blo {
                let (lo, _) = ctx.u_range(&a);
                done_pieces.push((lo, vec![None; arcs.len()]));
                continue;
            }
            let q = (&alo_hi + &blo) / &two;
            let roots = isolate(&data.g.at_x(&q))?;
            if roots.len() != count {
                return Err(Error::Param(format!(
                    "internal: an extra fibre of strip {si} has {} roots, the strip {count}",
                    roots.len()
                )));
            }
            let mut boxes = Vec::new();
            let mut vid = Vec::new();
            for (i, mut rt) in roots.into_iter().enumerate() {
                if st.vid[i].is_some() {
                    rt.refine_to(&fine);
                    let v = rt.to_f64();
                    vid.push(Some(verts.len() as u32));
                    verts.push([q_to_f64(&q) + s as f64 * v, v]);
                    labels.push(Label::Regular);
                } else {
                    vid.push(None);
                }
                boxes.push((rt.lo, rt.hi));
            }
            extra += 1;
            nodes.insert(k + 1, Node::Fibre { q, boxes, vid });
            // Shift the pending gaps to the right of k.
            for t in todo.iter_mut() {
                if t.0 > k {
                    t.0 += 1;
                }
            }
            todo.push((k + 1, depth + 1));
            todo.push((k, depth + 1));
        }
        // Chains: consecutive nodes' vertices of each arc.
        for (t, &i) in arcs.iter().enumerate() {
            let mut chain: Vec<u32> = Vec::new();
            for (ni, n) in nodes.iter().enumerate() {
                let left = ni == 0;
                if let Some((_, _, Some(v))) = ctx.end(n, i, left) {
                    chain.push(v);
                } else {
                    return Err(Error::Param(
                        "internal: an arc inside the domain without a vertex".into(),
                    ));
                }
            }
            for w in chain.windows(2) {
                segs.push([w[0], w[1]]);
            }
            for (_, bs) in &done_pieces {
                bound[t] = match (bound[t], bs[t]) {
                    (Some(x), Some(y)) => Some(x.max(y)),
                    _ => None,
                };
            }
            match bound[t] {
                Some(b) if b <= p.tolerance => {
                    within += 1;
                    worst = worst.max(b);
                }
                b => misses.push(ArcMiss {
                    strip: si,
                    arc: i,
                    bound: b,
                }),
            }
        }
    }
    r.curve.vertices = verts;
    r.curve.segments = segs;
    r.labels = labels;
    r.tolerance = Some(ToleranceReport {
        tolerance: p.tolerance,
        extra_fibres: extra,
        arcs: n_arcs,
        arcs_within_tolerance: within,
        certified_bound: worst,
        not_reached: misses,
    });
    r.arcs = Some(data);
    Ok(())
}
