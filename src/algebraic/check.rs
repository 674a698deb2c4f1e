//! The re-checkable certificate of the González-Vega–Necula sweep, and its checker.
//!
//! The certificate records the input polynomial, the shear, every event (its
//! defining polynomial and final isolating interval, its sign vector of principal
//! subresultants, k, m, the genericity test and the real-only r-test, the root boxes
//! with their branch counts and inside/boundary decisions, the excluded boxes of a
//! clustered multiple root), every rational fibre (its isolating intervals and
//! inside decisions), and the output graph. [`check_curve`] re-verifies each claim
//! with exact rationals, without any search or refinement: a sign by interval Horner
//! on the recorded interval (or an exact gcd zero test), a root count by Sturm
//! sequences, a root box by endpoint signs and an interval enclosure of f_v, the
//! completeness of the events by Sturm counts of the discriminant and of the side
//! polynomials; then it rebuilds the graph from the verified counts and compares it.
//! The polynomial pipeline (shear, square-free part, subresultants) is recomputed, as
//! it is deterministic.
use super::algnum::{eval_interval, exact_interval_sign, root_bound_log2, RealAlg};
use super::bipoly::BiPoly;
use super::subres;
use super::sweep::{genericity_holds, is_root_at_beta, sk_poly, Label, BOX_SEARCH_STEPS};
use super::upoly::{sign, sturm_count, UPoly};
use crate::error::{Error, Result};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};
use serde::{Deserialize, Serialize};

/// The format tag of a curve certificate.
pub const CERT_FORMAT: &str = "certmesh-gvn-curve/1";

/// A closed rational interval (exact rationals as text, `a/b` or `a`).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct CertInterval {
    pub lo: String,
    pub hi: String,
}

impl CertInterval {
    pub fn new(lo: &BigRational, hi: &BigRational) -> Self {
        CertInterval {
            lo: lo.to_string(),
            hi: hi.to_string(),
        }
    }
}

/// A rational fibre u = q: the isolating intervals of the roots of g(q, ·), bottom to
/// top, and whether each root is inside the domain.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct CertFibre {
    pub q: String,
    pub roots: Vec<CertInterval>,
    pub inside: Vec<bool>,
}

/// A root of an event fibre.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct CertRoot {
    pub lo: String,
    pub hi: String,
    /// The multiple root (generic: β's box; non-generic: the cluster).
    pub special: bool,
    /// On a side of the domain.
    pub boundary: bool,
    /// Kept in the output (inside the domain or on its boundary).
    pub keep: bool,
    /// Branches to the left and to the right.
    pub left: usize,
    pub right: usize,
}

/// An event u = α (the root of `poly` in [lo, hi]).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct CertEvent {
    pub poly: Vec<String>,
    pub lo: String,
    pub hi: String,
    /// A root of the discriminant.
    pub critical: bool,
    /// A vertical side of the domain (shear 0).
    pub side: bool,
    /// Crossings with sides of the domain: v = v0 + v1·u.
    pub bpoints: Vec<[String; 2]>,
    /// Signs of sres_j(α), index j = 0 … d − 1 (critical events).
    pub signs: Vec<i32>,
    pub k: Option<usize>,
    /// Distinct real roots of the fibre.
    pub m: usize,
    pub generic: Option<bool>,
    /// Non-generic: signs of the principal subresultants of S_k and ∂S_k/∂v at α, and
    /// the distinct real roots r of S_k(α, ·).
    pub r_signs: Vec<i32>,
    pub r: Option<usize>,
    pub roots: Vec<CertRoot>,
    /// Cluster mode: boxes where 0 ∉ f(α, box), proving the rest of the line empty.
    pub excluded: Vec<CertInterval>,
    pub branches: Option<(usize, usize)>,
    pub label: Option<Label>,
}

/// The certificate of one sweep.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct CurveCert {
    pub format: String,
    /// f(x, y) = Σ f\[j\]\[i\]·xⁱyʲ, integer coefficients.
    pub f: Vec<Vec<String>>,
    pub shear: i64,
    /// xmin, ymin, xmax, ymax.
    pub domain: [String; 4],
    pub events: Vec<CertEvent>,
    /// Per strip: the events on its left and right.
    pub strips: Vec<(Option<usize>, Option<usize>)>,
    pub fibres: Vec<CertFibre>,
    pub vertices: Vec<[f64; 2]>,
    pub segments: Vec<[u32; 2]>,
}

/// What the checker verified.
#[derive(Clone, Debug, Serialize)]
pub struct CheckReport {
    /// The polynomial the certificate is about, f(x, y) with the certificate's integer
    /// coefficients (a multiple of the formula meshed: the sweep clears denominators),
    /// in the formula syntax of `--formula`.
    pub polynomial: String,
    /// The domain checked, exact rationals: xmin, ymin, xmax, ymax.
    pub domain: [String; 4],
    pub shear: i64,
    pub degree: usize,
    pub events: usize,
    pub critical_events: usize,
    pub fibres: usize,
    pub vertices: usize,
    pub segments: usize,
    /// Individual claims verified (signs, counts, boxes, decisions).
    pub claims: usize,
}

impl CheckReport {
    /// The domain for a readable text, `[xmin, xmax] × [ymin, ymax]`: a bound that is
    /// exactly a float (the sweep's bounds are the floats given) by that float's
    /// shortest digits, another short rational ("1/3") as it is, others "≈" a float
    /// (the JSON `domain` has the exact rationals).
    pub fn domain_text(&self) -> String {
        let b = |k: usize| readable_rational(&self.domain[k]);
        format!("[{}, {}] × [{}, {}]", b(0), b(2), b(1), b(3))
    }
}

fn readable_rational(t: &str) -> String {
    use num_traits::ToPrimitive;
    let Ok(q) = t.parse::<BigRational>() else {
        return t.to_string();
    };
    match q.to_f64() {
        Some(x) if x.is_finite() && BigRational::from_float(x).is_some_and(|r| r == q) => {
            crate::harness::report::short_num(x)
        }
        _ if t.len() <= 20 => t.to_string(),
        Some(x) if x.is_finite() => format!("≈{}", crate::harness::report::short_num(x)),
        _ => t.to_string(),
    }
}

/// f(x, y) = Σ f\[j\]\[i\]·xⁱyʲ as text in the formula syntax ("2*x^2 + 6*y^2 - 9"),
/// terms by decreasing total degree, then decreasing degree in x.
fn poly_text(f: &[Vec<String>]) -> Result<String> {
    let mut terms: Vec<(usize, usize, BigInt)> = Vec::new();
    for (j, row) in f.iter().enumerate() {
        for (i, a) in row.iter().enumerate() {
            let a: BigInt = a
                .trim()
                .parse()
                .map_err(|_| bad(format!("'{a}' is not an integer")))?;
            if !a.is_zero() {
                terms.push((i, j, a));
            }
        }
    }
    terms.sort_by(|a, b| (b.0 + b.1, b.0).cmp(&(a.0 + a.1, a.0)));
    if terms.is_empty() {
        return Ok("0".into());
    }
    let mut out = String::new();
    for (k, (i, j, a)) in terms.iter().enumerate() {
        let mono: Vec<String> = [("x", *i), ("y", *j)]
            .iter()
            .filter(|(_, e)| *e > 0)
            .map(|(v, e)| {
                if *e == 1 {
                    v.to_string()
                } else {
                    format!("{v}^{e}")
                }
            })
            .collect();
        let mag = a.abs();
        let body = match (mono.is_empty(), mag.is_one()) {
            (true, _) => mag.to_string(),
            (false, true) => mono.join("*"),
            (false, false) => format!("{mag}*{}", mono.join("*")),
        };
        match (k, a.is_negative()) {
            (0, true) => out += &format!("-{body}"),
            (0, false) => out += &body,
            (_, true) => out += &format!(" - {body}"),
            (_, false) => out += &format!(" + {body}"),
        }
    }
    Ok(out)
}

fn bad(msg: impl std::fmt::Display) -> Error {
    Error::Param(format!("curve certificate rejected: {msg}"))
}

fn pq(s: &str) -> Result<BigRational> {
    s.trim()
        .parse::<BigRational>()
        .map_err(|_| bad(format!("'{s}' is not a rational number")))
}

fn ppoly(v: &[String]) -> Result<UPoly> {
    let mut c = Vec::new();
    for a in v {
        c.push(
            a.trim()
                .parse::<BigInt>()
                .map_err(|_| bad(format!("'{a}' is not an integer")))?,
        );
    }
    Ok(UPoly::new(c))
}

type Iv = (BigRational, BigRational);

fn imul(a: &Iv, b: &Iv) -> Iv {
    let ps = [&a.0 * &b.0, &a.0 * &b.1, &a.1 * &b.0, &a.1 * &b.1];
    (
        ps.iter().min().unwrap().clone(),
        ps.iter().max().unwrap().clone(),
    )
}
fn iadd(a: &Iv, b: &Iv) -> Iv {
    (&a.0 + &b.0, &a.1 + &b.1)
}
fn isign(a: &Iv) -> Option<i32> {
    if a.0.is_positive() {
        Some(1)
    } else if a.1.is_negative() {
        Some(-1)
    } else {
        None
    }
}
/// Σ cs\[j\]·Jʲ by interval Horner, exactly (no rounding).
fn eval2(cs: &[Iv], j: &Iv) -> Iv {
    let mut acc = cs
        .last()
        .cloned()
        .unwrap_or((BigRational::zero(), BigRational::zero()));
    for c in cs.iter().rev().skip(1) {
        acc = iadd(&imul(&acc, j), c);
    }
    acc
}
fn coefs(g: &BiPoly, i: &Iv) -> Vec<Iv> {
    g.c.iter().map(|p| eval_interval(p, &i.0, &i.1)).collect()
}

/// The claimed sign of q at α, verified without refining α.
fn verify_sign(a: &RealAlg, q: &UPoly, claimed: i32) -> Result<bool> {
    Ok(match claimed {
        0 => a.is_root_of(q),
        1 | -1 => {
            if a.is_exact() {
                q.sign_at(&a.lo) == claimed
            } else {
                exact_interval_sign(q, &a.lo, &a.hi) == Some(claimed)
            }
        }
        _ => false,
    })
}

/// An isolating interval of a root of the square-free `p`: exact and a root, or open
/// with non-root endpoints and one root inside (Sturm).
fn verify_isolating(p: &UPoly, lo: &BigRational, hi: &BigRational) -> bool {
    if lo > hi {
        return false;
    }
    if lo == hi {
        return p.sign_at(lo) == 0;
    }
    p.sign_at(lo) != 0 && p.sign_at(hi) != 0 && sturm_count(p, lo, hi) == 1
}

/// One root of `p` in the open interval (lo, hi), or the exact root lo = hi; the
/// endpoints may be (other) roots.
fn verify_isolating_open(p: &UPoly, lo: &BigRational, hi: &BigRational) -> bool {
    if lo > hi {
        return false;
    }
    if lo == hi {
        return p.sign_at(lo) == 0;
    }
    sturm_count(p, lo, hi) - usize::from(p.sign_at(hi) == 0) == 1
}

struct Dom {
    s: BigRational,
    xmin: BigRational,
    xmax: BigRational,
    ymin: BigRational,
    ymax: BigRational,
}

impl Dom {
    /// Definitely inside (Some(true)) / outside (Some(false)) for a point known to lie
    /// in the closed box u × v (strictly inside it when `open`).
    fn classify(&self, u: &Iv, v: &Iv, open: bool) -> Option<bool> {
        let x = iadd(u, &imul(v, &(self.s.clone(), self.s.clone())));
        let lt = |a: &BigRational, b: &BigRational| if open { a <= b } else { a < b };
        if lt(&self.ymin, &v.0)
            && lt(&v.1, &self.ymax)
            && lt(&self.xmin, &x.0)
            && lt(&x.1, &self.xmax)
        {
            return Some(true);
        }
        if lt(&v.1, &self.ymin)
            || lt(&self.ymax, &v.0)
            || lt(&x.1, &self.xmin)
            || lt(&self.xmax, &x.0)
        {
            return Some(false);
        }
        None
    }
}

/// The largest coefficient of f the checker accepts, in bits (the sweep's default
/// `max-bits` is 512), and as decimal characters (sign included).
pub const MAX_F_BITS: u64 = 8192;
const MAX_F_CHARS: usize = (MAX_F_BITS as usize * 30103).div_ceil(100_000) + 1;

/// The checker's size limits, derived from f's total degree `d` and coefficient size
/// `tau` (bits), so that a bloated certificate is refused before any arithmetic: exact
/// rationals cost time quadratic in their length (a 60,000-digit interval end that
/// still isolates its root took 15 s to verify, a 100,000-digit one over a minute).
///
/// - Every number: at most 8,192 + d²(τ + 64)/3 characters. The sweep's numbers are an
///   event's polynomial (a factor of the discriminant or of f on a side: at most
///   2d(τ + 2 log₂ d + log₂ 2d) bits by Hadamard's bound on the Sylvester determinant,
///   below d²(τ + 64) bits for d ≥ 2) and isolating intervals (dyadic a/2ᵏ, refined by
///   at most `REFINE_STEPS` = 4,000 bisections per decision: about 1,200 digits for
///   each of a and 2ᵏ per decision, so three decisions' full refinement of one number
///   fit in 8,192), and the domain's corners (doubles: at most 1,075 bits, 325 digits).
///   The catalog's certificates use at most 74 characters; a number at the limit costs
///   about a third of a second.
/// - Counts: at most d² + 4d + 2 events (the discriminant has at most d(d − 1) roots,
///   each of the four sides at most d crossings, and the two vertical sides), one more
///   fibre than events, at most d roots per fibre or event fibre, at most 4 side
///   crossings and d² + 1 coefficients per event polynomial, and at most
///   `BOX_SEARCH_STEPS` excluded boxes per event (the sweep's search visits no more).
fn check_sizes(c: &CurveCert, d: usize, tau: u64) -> Result<()> {
    let max_chars = 8192 + (d * d).saturating_mul(tau as usize + 64) / 3;
    let long = |what: String, s: &str| -> Result<()> {
        if s.len() > max_chars {
            return Err(bad(format!(
                "{what} has {} characters, above the checker's limit of {max_chars} for a curve of degree {d} with {tau}-bit coefficients",
                s.len()
            )));
        }
        Ok(())
    };
    let count = |what: String, n: usize, max: usize| -> Result<()> {
        if n > max {
            return Err(bad(format!(
                "{what}: {n}, above the {max} a curve of degree {d} can have"
            )));
        }
        Ok(())
    };
    for (k, x) in c.domain.iter().enumerate() {
        long(format!("domain corner {k}"), x)?;
    }
    let max_events = d * d + 4 * d + 2;
    count("events".into(), c.events.len(), max_events)?;
    count("rational fibres".into(), c.fibres.len(), max_events + 1)?;
    count("strips".into(), c.strips.len(), max_events + 1)?;
    for (i, e) in c.events.iter().enumerate() {
        count(
            format!("event {i}'s polynomial coefficients"),
            e.poly.len(),
            d * d + 1,
        )?;
        count(format!("event {i}'s roots"), e.roots.len(), d)?;
        count(format!("event {i}'s side crossings"), e.bpoints.len(), 4)?;
        count(
            format!("event {i}'s excluded boxes"),
            e.excluded.len(),
            BOX_SEARCH_STEPS,
        )?;
        for a in &e.poly {
            long(format!("a coefficient of event {i}'s polynomial"), a)?;
        }
        long(format!("event {i}'s interval"), &e.lo)?;
        long(format!("event {i}'s interval"), &e.hi)?;
        for b in e.bpoints.iter().flatten() {
            long(format!("event {i}'s side crossing"), b)?;
        }
        for (j, r) in e.roots.iter().enumerate() {
            long(format!("event {i}, root {j}"), &r.lo)?;
            long(format!("event {i}, root {j}"), &r.hi)?;
        }
        for x in &e.excluded {
            long(format!("event {i}'s excluded box"), &x.lo)?;
            long(format!("event {i}'s excluded box"), &x.hi)?;
        }
    }
    for (i, fb) in c.fibres.iter().enumerate() {
        count(format!("fibre {i}'s roots"), fb.roots.len(), d)?;
        long(format!("fibre {i}'s abscissa"), &fb.q)?;
        for (j, r) in fb.roots.iter().enumerate() {
            long(format!("fibre {i}, root {j}"), &r.lo)?;
            long(format!("fibre {i}, root {j}"), &r.hi)?;
        }
    }
    Ok(())
}

/// Re-verify every claim of a curve certificate with exact rationals.
pub fn check_curve(c: &CurveCert) -> Result<CheckReport> {
    super::algnum::clear_gcd_memo();
    if c.format != CERT_FORMAT {
        return Err(bad(format!("unknown format '{}'", c.format)));
    }
    let mut claims = 0usize;
    if let Some((field, len)) =
        c.f.iter()
            .flatten()
            .map(|a| ("f", a.len()))
            .find(|&(_, len)| len > MAX_F_CHARS)
    {
        return Err(bad(format!(
            "a coefficient of {field} has {len} characters, above the checker's limit of {MAX_F_CHARS} (coefficients of {MAX_F_BITS} bits)"
        )));
    }
    let f = BiPoly::new(c.f.iter().map(|p| ppoly(p)).collect::<Result<Vec<_>>>()?);
    if f.is_zero() {
        return Err(bad("f is zero"));
    }
    let s = c.shear;
    if s.abs() > 64 {
        return Err(bad("shear out of range"));
    }
    let dt = f.total_degree();
    if dt > 16 {
        return Err(bad("degree above 16"));
    }
    check_sizes(c, dt.max(1) as usize, f.max_bits())?;
    let g0 = f.shear(s);
    if dt > 0 && (g0.deg_y() <= 0 || g0.lc_y().deg() != 0) {
        return Err(bad(format!("f(x + {s}·y, y) is not y-regular")));
    }
    let g = g0.squarefree_y();
    let [x0, y0, x1, y1] = [0, 1, 2, 3].map(|i| pq(&c.domain[i]));
    let dom = Dom {
        s: BigRational::from_integer(BigInt::from(s)),
        xmin: x0?,
        ymin: y0?,
        xmax: x1?,
        ymax: y1?,
    };
    if dom.xmin >= dom.xmax || dom.ymin >= dom.ymax {
        return Err(bad("empty domain"));
    }
    let sq = dom.s.clone();
    let (u_lo, u_hi) = if s >= 0 {
        (&dom.xmin - &sq * &dom.ymax, &dom.xmax - &sq * &dom.ymin)
    } else {
        (&dom.xmin - &sq * &dom.ymin, &dom.xmax - &sq * &dom.ymax)
    };
    let polynomial = poly_text(&c.f)?;
    let domain = [&dom.xmin, &dom.ymin, &dom.xmax, &dom.ymax].map(|q| q.to_string());
    let report = |claims| CheckReport {
        polynomial: polynomial.clone(),
        domain: domain.clone(),
        shear: s,
        degree: g.total_degree().max(0) as usize,
        events: c.events.len(),
        critical_events: c.events.iter().filter(|e| e.critical).count(),
        fibres: c.fibres.len(),
        vertices: c.vertices.len(),
        segments: c.segments.len(),
        claims,
    };
    if g.deg_y() <= 0 {
        if !c.events.is_empty()
            || !c.fibres.is_empty()
            || !c.vertices.is_empty()
            || !c.segments.is_empty()
            || !c.strips.is_empty()
        {
            return Err(bad("f has no real zeros but the certificate lists some"));
        }
        return Ok(report(1));
    }
    let d = g.deg_y() as usize;
    let gy = g.dy();
    let gx = g.dx();
    let chain = subres::full_chain(&g, &gy);
    let sres = subres::principal_of(&chain);
    let disc = &sres[0];
    let lc_sign = sign(&g.lc_y().coef(0));
    // Events: isolating, ordered, inside the u-range, critical iff D(α) = 0.
    let mut alphas: Vec<RealAlg> = Vec::new();
    for (i, e) in c.events.iter().enumerate() {
        let p = ppoly(&e.poly)?;
        let (lo, hi) = (pq(&e.lo)?, pq(&e.hi)?);
        if p.is_zero() {
            return Err(bad(format!("event {i}: zero polynomial")));
        }
        let p = p.squarefree();
        if !verify_isolating(&p, &lo, &hi) {
            return Err(bad(format!(
                "event {i}: [{lo}, {hi}] does not isolate a root of its polynomial"
            )));
        }
        let inside_range = if e.side {
            lo == hi && (lo == u_lo || lo == u_hi)
        } else if lo == hi {
            lo > u_lo && hi < u_hi
        } else {
            lo >= u_lo && hi <= u_hi
        };
        if !inside_range {
            return Err(bad(format!("event {i} is outside the domain's u-range")));
        }
        if let Some(prev) = alphas.last() {
            if prev.hi >= lo {
                return Err(bad(format!(
                    "events {} and {i} are not ordered and disjoint",
                    i - 1
                )));
            }
        }
        let a = if lo == hi {
            RealAlg::exact(lo)
        } else {
            RealAlg::new(p, lo, hi)
        };
        if a.is_root_of(disc) != e.critical {
            return Err(bad(format!("event {i}: the critical flag is wrong")));
        }
        if !e.critical && !e.side && e.bpoints.is_empty() {
            return Err(bad(format!("event {i} has no reason")));
        }
        if e.side
            && (e.critical || s != 0 || !a.is_exact() || (a.lo != dom.xmin && a.lo != dom.xmax))
        {
            return Err(bad(format!(
                "event {i}: a side event must be an exact vertical side at shear 0"
            )));
        }
        claims += 2;
        alphas.push(a);
    }
    // Completeness of the critical events.
    let dsq = disc.squarefree();
    if s == 0 && (dsq.sign_at(&u_lo) == 0 || dsq.sign_at(&u_hi) == 0) {
        return Err(bad("a vertical side lies on a critical x-value"));
    }
    let n_crit = sturm_count(&dsq, &u_lo, &u_hi) - usize::from(dsq.sign_at(&u_hi) == 0);
    if n_crit != c.events.iter().filter(|e| e.critical).count() {
        return Err(bad(format!("the discriminant has {n_crit} roots in the u-range, the certificate lists a different number of critical events")));
    }
    claims += 1;
    // Completeness of the box events: per side, the crossings.
    let zero = BigRational::zero();
    let one = BigRational::one();
    let mut sides: Vec<(BigRational, BigRational, BigRational, BigRational)> = Vec::new();
    for cy in [&dom.ymin, &dom.ymax] {
        sides.push((
            cy.clone(),
            zero.clone(),
            &dom.xmin - &sq * cy,
            &dom.xmax - &sq * cy,
        ));
    }
    if s != 0 {
        for cx in [&dom.xmin, &dom.xmax] {
            let (mut a, mut b) = (cx - &sq * &dom.ymax, cx - &sq * &dom.ymin);
            if s < 0 {
                std::mem::swap(&mut a, &mut b);
            }
            sides.push((cx / &sq, -(&one / &sq), a, b));
        }
    } else {
        let n_side = c.events.iter().filter(|e| e.side).count();
        if n_side != 2
            || !c.events.first().is_some_and(|e| e.side)
            || !c.events.last().is_some_and(|e| e.side)
        {
            return Err(bad(
                "shear 0 needs the two vertical sides as the first and last events",
            ));
        }
    }
    let mut seen = 0usize;
    for (v0, v1, a, b) in &sides {
        let h = g.on_line(&zero, &one, v0, v1);
        if h.is_zero() {
            return Err(bad("a side of the domain lies on the curve"));
        }
        if h.sign_at(a) == 0 || h.sign_at(b) == 0 {
            return Err(bad("the curve passes through a corner of the domain"));
        }
        let n = sturm_count(&h, a, b);
        let mut listed = 0;
        for (i, e) in c.events.iter().enumerate() {
            let mut here = 0;
            for bp in &e.bpoints {
                if pq(&bp[0])? == *v0 && pq(&bp[1])? == *v1 {
                    here += 1;
                    if !alphas[i].is_root_of(&h) {
                        return Err(bad(format!("event {i}: a listed side crossing is not one")));
                    }
                }
            }
            if here > 1 {
                return Err(bad(format!("event {i}: a side crossing listed twice")));
            }
            listed += here;
        }
        if listed != n {
            return Err(bad(format!(
                "a side meets the curve {n} times, the certificate lists {listed}"
            )));
        }
        seen += listed;
        claims += 1;
    }
    if seen != c.events.iter().map(|e| e.bpoints.len()).sum::<usize>() {
        return Err(bad("a side crossing is on no side of the domain"));
    }
    // Strips and rational fibres.
    let n_ev = c.events.len();
    let mut strips: Vec<(Option<usize>, Option<usize>)> = Vec::new();
    if n_ev == 0 {
        strips.push((None, None));
    } else {
        if s != 0 {
            strips.push((None, Some(0)));
        }
        for i in 0..n_ev - 1 {
            strips.push((Some(i), Some(i + 1)));
        }
        if s != 0 {
            strips.push((Some(n_ev - 1), None));
        }
    }
    if strips != c.strips || c.fibres.len() != strips.len() {
        return Err(bad("the strips do not match the events"));
    }
    let mut counts = Vec::new();
    for (si, (fb, st)) in c.fibres.iter().zip(&strips).enumerate() {
        let q = pq(&fb.q)?;
        let left_ok = match st.0 {
            Some(l) => q > alphas[l].hi,
            None => q > u_lo,
        };
        let right_ok = match st.1 {
            Some(r) => q < alphas[r].lo,
            None => q < u_hi,
        };
        if !left_ok || !right_ok {
            return Err(bad(format!("fibre {si} is not between its events")));
        }
        verify_rational_fibre(&g, &q, &fb.roots, &fb.inside, &dom, si)?;
        claims += 1 + fb.roots.len();
        counts.push(fb.roots.len());
    }
    // Event fibres.
    let mut ev_ends: Vec<Vec<(bool, usize, usize)>> = Vec::new();
    for (ei, e) in c.events.iter().enumerate() {
        let a = &alphas[ei];
        let n_l = strips
            .iter()
            .position(|st| st.1 == Some(ei))
            .map(|i| counts[i]);
        let n_r = strips
            .iter()
            .position(|st| st.0 == Some(ei))
            .map(|i| counts[i]);
        let mut mode = 0; // 0 plain, 1 generic, 2 cluster
        let (mut num, mut den) = (UPoly::zero(), UPoly::zero());
        let m;
        if e.critical {
            if e.signs.len() != d {
                return Err(bad(format!("event {ei}: sign vector of the wrong length")));
            }
            for j in 1..d {
                if !verify_sign(a, &sres[j], e.signs[j])? {
                    return Err(bad(format!("event {ei}: the sign of sres_{j} is wrong")));
                }
                claims += 1;
            }
            if e.signs[0] != 0 {
                return Err(bad(format!(
                    "event {ei}: sres_0 = D vanishes at a critical event"
                )));
            }
            let k = (1..d)
                .find(|&j| e.signs[j] != 0)
                .ok_or_else(|| bad(format!("event {ei}: no non-zero subresultant")))?;
            if e.k != Some(k) {
                return Err(bad(format!("event {ei}: k is wrong")));
            }
            m = subres::distinct_real_roots(d, lc_sign, &e.signs).max(0) as usize;
            if e.m != m {
                return Err(bad(format!("event {ei}: m is wrong (the signs give {m})")));
            }
            let sk: Vec<UPoly> = subres::lower_of(&chain, k);
            let generic =
                (0..k.saturating_sub(1)).all(|i| genericity_holds(a, &sres[k], &sk, k, i));
            if e.generic != Some(generic) {
                return Err(bad(format!("event {ei}: the genericity claim is wrong")));
            }
            claims += 2;
            if generic {
                mode = 1;
                num = sk[k - 1].neg();
                den = sres[k].scale(&BigInt::from(k));
                if e.r.is_some() || !e.r_signs.is_empty() {
                    return Err(bad(format!("event {ei}: r-test on a generic fibre")));
                }
            } else {
                let skp = sk_poly(&sres[k], &sk);
                let ps = subres::principal(&skp, &skp.dy());
                if e.r_signs.len() != k {
                    return Err(bad(format!("event {ei}: r-test signs of the wrong length")));
                }
                for j in 0..k {
                    if !verify_sign(a, &ps[j], e.r_signs[j])? {
                        return Err(bad(format!("event {ei}: an r-test sign is wrong")));
                    }
                }
                let r = subres::distinct_real_roots(k, e.signs[k], &e.r_signs).max(0) as usize;
                if e.r != Some(r) || r > 1 {
                    return Err(bad(format!(
                        "event {ei}: the r-test is wrong or fails (r = {r})"
                    )));
                }
                claims += k + 1;
                mode = if r == 1 { 2 } else { 0 };
            }
        } else {
            if e.k.is_some() || !e.signs.is_empty() || e.generic.is_some() || e.r.is_some() {
                return Err(bad(format!(
                    "event {ei}: subresultant claims on a non-critical event"
                )));
            }
            m = n_l.or(n_r).unwrap_or(0);
            if n_l.is_some() && n_r.is_some() && n_l != n_r {
                return Err(bad(format!(
                    "event {ei}: a non-critical event between fibres of different counts"
                )));
            }
            if e.m != m {
                return Err(bad(format!("event {ei}: m is wrong")));
            }
        }
        if e.roots.len() != m {
            return Err(bad(format!(
                "event {ei}: {} roots listed, m = {m}",
                e.roots.len()
            )));
        }
        let boxes: Vec<Iv> = e
            .roots
            .iter()
            .map(|r| Ok((pq(&r.lo)?, pq(&r.hi)?)))
            .collect::<Result<_>>()?;
        let nspecial = e.roots.iter().filter(|r| r.special).count();
        if nspecial != usize::from(mode != 0) {
            return Err(bad(format!("event {ei}: wrong number of multiple roots")));
        }
        if !e.critical && a.is_exact() {
            // A rational non-critical fibre: Sturm-isolated like a sample.
            let ivs: Vec<CertInterval> = e
                .roots
                .iter()
                .map(|r| CertInterval {
                    lo: r.lo.clone(),
                    hi: r.hi.clone(),
                })
                .collect();
            verify_fibre_roots(&g, &a.lo, &ivs, &format!("event {ei}"))?;
        } else {
            let iu: Iv = (a.lo.clone(), a.hi.clone());
            let cs = coefs(&g, &iu);
            let csy = coefs(&gy, &iu);
            for (ri, (r, b)) in e.roots.iter().zip(&boxes).enumerate() {
                if b.0 > b.1 || (ri > 0 && boxes[ri - 1].1 > b.0) {
                    return Err(bad(format!(
                        "event {ei}: root boxes not ordered and disjoint"
                    )));
                }
                if r.special {
                    if mode == 1 {
                        let (nl, nh) = eval_interval(&num, &a.lo, &a.hi);
                        let (dl, dh) = eval_interval(&den, &a.lo, &a.hi);
                        if !(dl.is_positive() || dh.is_negative()) {
                            return Err(bad(format!(
                                "event {ei}: β's denominator is not bounded away from 0"
                            )));
                        }
                        let qs = [&nl / &dl, &nl / &dh, &nh / &dl, &nh / &dh];
                        let (bl, bh) = (qs.iter().min().unwrap(), qs.iter().max().unwrap());
                        if !(&b.0 <= bl && bh <= &b.1) {
                            return Err(bad(format!(
                                "event {ei}: the multiple root's box does not enclose β"
                            )));
                        }
                    }
                    continue;
                }
                let (sa, sb) = (
                    isign(&eval2(&cs, &(b.0.clone(), b.0.clone()))),
                    isign(&eval2(&cs, &(b.1.clone(), b.1.clone()))),
                );
                if sa.is_none() || sb.is_none() || sa == sb || isign(&eval2(&csy, b)).is_none() {
                    return Err(bad(format!(
                        "event {ei}: root box {ri} is not a certified simple root"
                    )));
                }
                claims += 1;
            }
            if mode == 2 {
                // The cluster: everything else on [−Y, Y] is excluded.
                let lc = BigRational::from_integer(g.lc_y().coef(0).abs());
                let mut bound = BigRational::zero();
                for cc in &cs[..cs.len() - 1] {
                    bound = bound.max(cc.0.abs()).max(cc.1.abs());
                }
                let y = BigRational::one() + bound / lc;
                let mut all: Vec<Iv> = boxes.clone();
                for x in &e.excluded {
                    let bx = (pq(&x.lo)?, pq(&x.hi)?);
                    // Excluded: 0 ∉ f(α, box), or f monotone on the box (0 ∉ f_v)
                    // with the same strict sign at both ends.
                    let end = |t: &BigRational| isign(&eval2(&cs, &(t.clone(), t.clone())));
                    let monotone_same = isign(&eval2(&csy, &bx)).is_some()
                        && end(&bx.0).is_some()
                        && end(&bx.0) == end(&bx.1);
                    if bx.0 > bx.1 || !(isign(&eval2(&cs, &bx)).is_some() || monotone_same) {
                        return Err(bad(format!("event {ei}: an excluded box is not excluded")));
                    }
                    all.push(bx);
                }
                all.sort();
                let covers = all.first().is_some_and(|b| b.0 <= -y.clone())
                    && all.last().is_some_and(|b| b.1 >= y)
                    && all.windows(2).all(|w| w[1].0 <= w[0].1);
                if !covers {
                    return Err(bad(format!("event {ei}: the boxes do not cover the fibre")));
                }
                claims += e.excluded.len();
            }
        }
        // Branch counts.
        let mut ends = Vec::new();
        for (ri, r) in e.roots.iter().enumerate() {
            let (l, rr) = if r.special {
                let (Some(nl), Some(nr)) = (n_l, n_r) else {
                    return Err(bad(format!(
                        "event {ei}: a multiple root without fibres on both sides"
                    )));
                };
                let (al, ar) = (nl as i64 - (m as i64 - 1), nr as i64 - (m as i64 - 1));
                if al < 0 || ar < 0 {
                    return Err(bad(format!("event {ei}: negative branch counts")));
                }
                if e.branches != Some((al as usize, ar as usize)) {
                    return Err(bad(format!("event {ei}: the branch counts are wrong")));
                }
                (al as usize, ar as usize)
            } else {
                (1, 1)
            };
            if (r.left, r.right) != (l, rr) {
                return Err(bad(format!(
                    "event {ei}: root {ri} has wrong branch counts"
                )));
            }
            claims += 1;
            ends.push((r.keep, l, rr));
        }
        if nspecial == 0 && e.branches.is_some() {
            return Err(bad(format!(
                "event {ei}: branch counts without a multiple root"
            )));
        }
        if e.critical && nspecial == 0 && (n_l != Some(m) || n_r != Some(m)) {
            return Err(bad(format!(
                "event {ei}: a phantom event changes the number of arcs"
            )));
        }
        // Side crossings and inside decisions.
        if !e.side {
            let iu: Iv = (a.lo.clone(), a.hi.clone());
            let mut hit = vec![false; m];
            for bp in &e.bpoints {
                let (v0, v1) = (pq(&bp[0])?, pq(&bp[1])?);
                let vb = iadd(&(v0.clone(), v0), &imul(&iu, &(v1.clone(), v1)));
                let hits: Vec<usize> = (0..m)
                    .filter(|&i| !(vb.1 < boxes[i].0 || vb.0 > boxes[i].1))
                    .collect();
                let inb = |b: &Iv| {
                    (vb.0 > b.0 && vb.1 < b.1) || (b.0 == b.1 && vb.0 == vb.1 && vb.0 == b.0)
                };
                if hits.len() != 1
                    || !inb(&boxes[hits[0]])
                    || e.roots[hits[0]].special
                    || hit[hits[0]]
                {
                    return Err(bad(format!(
                        "event {ei}: a side crossing is not located on one simple root"
                    )));
                }
                hit[hits[0]] = true;
                claims += 1;
            }
            for (ri, r) in e.roots.iter().enumerate() {
                if r.boundary != hit[ri] {
                    return Err(bad(format!("event {ei}: root {ri} boundary flag is wrong")));
                }
                let keep = if r.boundary {
                    Some(true)
                } else {
                    dom.classify(&iu, &boxes[ri], false)
                };
                if keep != Some(r.keep) {
                    return Err(bad(format!(
                        "event {ei}: root {ri} inside/outside decision is not proven"
                    )));
                }
                claims += 1;
            }
        } else {
            for (ri, r) in e.roots.iter().enumerate() {
                let b = &boxes[ri];
                let open = b.0 != b.1;
                let lt = |x: &BigRational, y: &BigRational| if open { x <= y } else { x < y };
                let keep = if lt(&dom.ymin, &b.0) && lt(&b.1, &dom.ymax) {
                    Some(true)
                } else if lt(&b.1, &dom.ymin) || lt(&dom.ymax, &b.0) {
                    Some(false)
                } else {
                    None
                };
                if r.boundary != r.keep || keep != Some(r.keep) {
                    return Err(bad(format!("event {ei}: root {ri} on a vertical side: the inside decision is not proven")));
                }
                claims += 1;
            }
        }
        // Labels.
        let label = e.roots.iter().position(|r| r.special).map(|i| {
            let (l, r) = (e.roots[i].left, e.roots[i].right);
            if l == 0 && r == 0 {
                Label::Isolated
            } else if mode == 1 {
                if is_root_at_beta(a, &gx, &num, &den, d) {
                    Label::Singular
                } else if l == 0 || r == 0 {
                    Label::XExtreme
                } else {
                    Label::Regular
                }
            } else if l + r != 2 {
                Label::Singular
            } else {
                Label::Multiple
            }
        });
        if label != e.label {
            return Err(bad(format!("event {ei}: the label is wrong")));
        }
        ev_ends.push(ends);
    }
    // Rebuild the graph from the verified counts.
    let mut nv = 0u32;
    let mut fib_ids: Vec<Vec<Option<u32>>> = Vec::new();
    for fb in &c.fibres {
        fib_ids.push(
            fb.inside
                .iter()
                .map(|&i| {
                    i.then(|| {
                        nv += 1;
                        nv - 1
                    })
                })
                .collect(),
        );
    }
    let mut ev_ids: Vec<Vec<(Option<u32>, usize, usize)>> = Vec::new();
    for ends in &ev_ends {
        ev_ids.push(
            ends.iter()
                .map(|&(k, l, r)| {
                    (
                        k.then(|| {
                            nv += 1;
                            nv - 1
                        }),
                        l,
                        r,
                    )
                })
                .collect(),
        );
    }
    if nv as usize != c.vertices.len() {
        return Err(bad(
            "the number of output vertices does not match the verified decisions",
        ));
    }
    let mut segs: Vec<[u32; 2]> = Vec::new();
    for (si, st) in strips.iter().enumerate() {
        for (left_side, e) in [(true, st.0), (false, st.1)] {
            let Some(e) = e else {
                if fib_ids[si].iter().any(|v| v.is_some()) {
                    return Err(bad("an arc inside the domain reaches the end of the sweep"));
                }
                continue;
            };
            let mut ends = Vec::new();
            for &(id, bl, br) in &ev_ids[e] {
                for _ in 0..(if left_side { br } else { bl }) {
                    ends.push(id);
                }
            }
            if ends.len() != counts[si] {
                return Err(bad(format!(
                    "strip {si}: {} branches meet {} arcs",
                    ends.len(),
                    counts[si]
                )));
            }
            for (i, end) in ends.iter().enumerate() {
                match (fib_ids[si][i], end) {
                    (Some(a), Some(b)) => segs.push(if left_side { [*b, a] } else { [a, *b] }),
                    (Some(_), None) => return Err(bad("an arc inside the domain ends outside")),
                    _ => {}
                }
            }
        }
    }
    let mut want = segs.clone();
    let mut got = c.segments.clone();
    want.sort();
    got.sort();
    if want != got {
        return Err(bad(
            "the output segments are not the ones the verified counts give",
        ));
    }
    // The drawing: vertices of a column share its u (x − s·y), columns in order, and
    // each column's vertices bottom to top in root order (float coordinates).
    let sf = s as f64;
    let mut columns: Vec<Vec<u32>> = Vec::new();
    let col_f = |si: usize| fib_ids[si].iter().flatten().copied().collect::<Vec<u32>>();
    let col_e = |ei: usize| ev_ids[ei].iter().filter_map(|x| x.0).collect::<Vec<u32>>();
    if n_ev == 0 {
        columns.push(col_f(0));
    } else {
        let mut si = 0;
        if s != 0 {
            columns.push(col_f(0));
            si = 1;
        }
        for ei in 0..n_ev {
            columns.push(col_e(ei));
            if si < strips.len() {
                columns.push(col_f(si));
                si += 1;
            }
        }
    }
    // Each vertex lies (up to float rounding) in its certified box.
    let near = |x: f64, lo: &BigRational, hi: &BigRational| {
        let (l, h) = (super::algnum::q_to_f64(lo), super::algnum::q_to_f64(hi));
        let tol = 1e-7 * (1.0 + l.abs().max(h.abs()));
        x >= l - tol && x <= h + tol
    };
    let uv_of = |i: u32| {
        let p = c.vertices[i as usize];
        [p[0] - sf * p[1], p[1]]
    };
    for (si, fb) in c.fibres.iter().enumerate() {
        let qv = pq(&fb.q)?;
        for (ri, id) in fib_ids[si].iter().enumerate() {
            if let Some(id) = id {
                let p = uv_of(*id);
                let (lo, hi) = (pq(&fb.roots[ri].lo)?, pq(&fb.roots[ri].hi)?);
                if !near(p[0], &qv, &qv) || !near(p[1], &lo, &hi) {
                    return Err(bad(format!(
                        "fibre {si}: vertex {id} is not at its certified position"
                    )));
                }
            }
        }
    }
    for (ei, e) in c.events.iter().enumerate() {
        for (ri, (id, _, _)) in ev_ids[ei].iter().enumerate() {
            if let Some(id) = id {
                let p = uv_of(*id);
                let (lo, hi) = (pq(&e.roots[ri].lo)?, pq(&e.roots[ri].hi)?);
                if !near(p[0], &alphas[ei].lo, &alphas[ei].hi) || !near(p[1], &lo, &hi) {
                    return Err(bad(format!(
                        "event {ei}: vertex {id} is not at its certified position"
                    )));
                }
            }
        }
    }
    let mut last_u = f64::NEG_INFINITY;
    for col in columns.iter().filter(|c| !c.is_empty()) {
        let uv: Vec<[f64; 2]> = col
            .iter()
            .map(|&i| {
                let p = c.vertices[i as usize];
                [p[0] - sf * p[1], p[1]]
            })
            .collect();
        let (lo, hi) = uv
            .iter()
            .fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p[0]), a.1.max(p[0])));
        let spread = 1e-7 * (1.0 + hi.abs());
        if !(lo > last_u) || hi - lo > spread || uv.windows(2).any(|w| !(w[0][1] < w[1][1])) {
            return Err(bad(
                "the output vertices are not drawn in the certified order",
            ));
        }
        last_u = hi;
    }
    claims += 1;
    Ok(report(claims))
}

fn verify_rational_fibre(
    g: &BiPoly,
    q: &BigRational,
    roots: &[CertInterval],
    inside: &[bool],
    dom: &Dom,
    idx: usize,
) -> Result<()> {
    verify_fibre_roots(g, q, roots, &format!("fibre {idx}"))?;
    if inside.len() != roots.len() {
        return Err(bad(format!(
            "fibre {idx}: inside flags of the wrong length"
        )));
    }
    for (i, r) in roots.iter().enumerate() {
        let (lo, hi) = (pq(&r.lo)?, pq(&r.hi)?);
        let open = lo != hi;
        let iu = (q.clone(), q.clone());
        if dom.classify(&iu, &(lo, hi), open) != Some(inside[i]) {
            return Err(bad(format!(
                "fibre {idx}: root {i} inside/outside decision is not proven"
            )));
        }
    }
    Ok(())
}

/// The intervals isolate all the real roots of g(q, ·), in order (Sturm counts).
fn verify_fibre_roots(
    g: &BiPoly,
    q: &BigRational,
    roots: &[CertInterval],
    what: &str,
) -> Result<()> {
    let gq = g.at_x(q);
    if gq.is_zero() {
        return Err(bad(format!("{what}: f vanishes on the whole line")));
    }
    let gq = gq.squarefree();
    let n = if gq.deg() <= 0 {
        0
    } else {
        let k = root_bound_log2(&gq);
        let b = BigRational::from_integer(BigInt::one() << k as u64);
        sturm_count(&gq, &-b.clone(), &b)
    };
    if roots.len() != n {
        return Err(bad(format!("{what}: {n} roots, {} listed", roots.len())));
    }
    let mut prev: Option<(BigRational, bool)> = None;
    for (i, r) in roots.iter().enumerate() {
        let (lo, hi) = (pq(&r.lo)?, pq(&r.hi)?);
        if !verify_isolating_open(&gq, &lo, &hi) {
            return Err(bad(format!("{what}: interval {i} does not isolate a root")));
        }
        if let Some((p, pexact)) = &prev {
            if p > &lo || (p == &lo && *pexact && lo == hi) {
                return Err(bad(format!("{what}: intervals not ordered and disjoint")));
            }
        }
        prev = Some((hi.clone(), lo == hi));
    }
    Ok(())
}
