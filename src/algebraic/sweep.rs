//! The González-Vega–Necula sweep (the chapter "Meshing of Surfaces", §1.4–§1.4.1):
//! the exact topology of f(x, y) = 0 inside a domain box, singular points included.
//!
//! 1. Frame: shear f_s(u, v) = f(u + s·v, v), s = 0, 1, −1, 2, … until f_s is
//!    y-regular (constant leading coefficient in v) and every real event fibre is
//!    generic (one multiple root); take its square-free part.
//! 2. Critical u-values: the real roots of D = Res_v(f_s, ∂f_s/∂v), isolated exactly
//!    (Descartes). Box events: where f = 0 meets a side of the domain (roots of f on
//!    the side's line). Between consecutive events the curve is a set of disjoint
//!    u-monotone arcs, each wholly inside or outside the domain.
//! 3. Event fibres: k = the first non-vanishing principal subresultant at α (exact
//!    zero tests), the genericity test S_k(α, v) = sres_k(α)·(v − β)^k, β from the
//!    subresultant coefficients, m = the distinct real roots from the Sturm–Habicht
//!    signs, the other m − 1 roots certified by interval bisection (outward-rounded
//!    f64 intervals first, exact rationals when f64 cannot decide); branch counts
//!    a_L = n_L − (m − 1), a_R = n_R − (m − 1). These subresultant tests run for all
//!    critical events before anything else, so a rejected shear costs little.
//! 4. Rational fibres between events, isolated exactly; join the i-th arc from the
//!    bottom on each side; keep what is inside the domain; unshear (determinant 1, so
//!    isotopy is kept).
//!
//! The certificate claims isotopy only when every step above completed exactly; a
//! budget that runs out is an error naming it, never a guess.
use super::algnum::{eval_interval, isolate, q_to_f64, RealAlg};
use super::bipoly::BiPoly;
use super::check::{CertEvent, CertFibre, CertInterval, CertRoot, CurveCert};
use super::fint;
use super::modgcd::{coprime_by_image, ModRing};
use super::subres;
use super::upoly::{sign, UPoly};
use crate::error::{Error, Result};
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;
use crate::mesh::Curve2;
use crate::mesher::options::MesherOptions;
use crate::mesher::{Certificate, Claim, Mesh, MeshOutput, Mesher, Progress};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};
use serde::{Deserialize, Serialize};
use std::cmp::Ordering;

/// Budgets of the sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepParams {
    /// Largest total degree accepted (default 10; at most 16 from the command line, the
    /// certificate checker's limit).
    pub max_degree: usize,
    /// Largest coefficient size in bits, after clearing denominators (default 512; at
    /// most [`super::check::MAX_F_BITS`] from the command line, the checker's limit).
    pub max_bits: u64,
    /// Shears tried: s = 0, ±1, …, ±max_shear (default 6).
    pub max_shear: i64,
    /// Extra fibres until every arc is proven within this distance of its polyline
    /// (`--set tolerance=T`; none by default).
    pub tolerance: Option<f64>,
    /// Budget of extra fibres (`--set max-extra-fibres=N`, default 4000).
    pub max_extra_fibres: usize,
    /// Wall-clock limit of [`analyse`] in seconds (none here; `--time-limit`, default
    /// 60 s, from the command line). The root searches of the fibres check it at every
    /// step: a curve whose exact arithmetic grows too long stops with an error naming
    /// the limit instead of running on (three conics meeting tangently in pairs,
    /// degree 6, ran for hours).
    pub time_limit: Option<f64>,
}

thread_local! {
    /// The deadline of the [`analyse`] running on this thread (the sweep is serial).
    static DEADLINE: std::cell::Cell<Option<std::time::Instant>> = const { std::cell::Cell::new(None) };
}

/// Has the running [`analyse`]'s time limit passed?
fn out_of_time() -> bool {
    DEADLINE.with(|d| d.get().is_some_and(|d| std::time::Instant::now() >= d))
}

/// Sets this thread's deadline for one [`analyse`] and clears it when dropped.
struct DeadlineGuard(Option<std::time::Instant>);

impl DeadlineGuard {
    fn set(limit: Option<f64>) -> DeadlineGuard {
        let d = limit.and_then(|s| {
            std::time::Instant::now().checked_add(std::time::Duration::try_from_secs_f64(s).ok()?)
        });
        DeadlineGuard(DEADLINE.with(|c| c.replace(d)))
    }
}

impl Drop for DeadlineGuard {
    fn drop(&mut self) {
        DEADLINE.with(|c| c.set(self.0));
    }
}

impl Default for SweepParams {
    fn default() -> Self {
        SweepParams {
            max_degree: 10,
            max_bits: 512,
            max_shear: 6,
            tolerance: None,
            max_extra_fibres: 4000,
            time_limit: None,
        }
    }
}

/// The mesher `--algo sweep` (curves).
#[derive(Clone, Debug, Default)]
pub struct Sweep {
    pub params: SweepParams,
}

impl Sweep {
    /// From `--set max-degree=N`, `--set max-bits=N`, `--set max-shear=N`,
    /// `--set tolerance=T` (extra fibres, [`super::tolerance`]) and
    /// `--set max-extra-fibres=N`.
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        o.check_keys(
            "sweep",
            &[
                "max-degree",
                "max-bits",
                "max-shear",
                "tolerance",
                "max-extra-fibres",
            ],
        )?;
        let mut p = SweepParams::default();
        // The same ranges as the certificate checker's, so that every certificate the
        // sweep writes can be re-checked.
        if let Some(v) = o.get::<usize>("max-degree")? {
            if !(1..=16).contains(&v) {
                return Err(Error::Param(
                    "--set max-degree must be in 1..=16 (the certificate checker's limit)".into(),
                ));
            }
            p.max_degree = v;
        }
        if let Some(v) = o.get::<u64>("max-bits")? {
            if !(1..=super::check::MAX_F_BITS).contains(&v) {
                return Err(Error::Param(format!(
                    "--set max-bits must be in 1..={} (the certificate checker's limit)",
                    super::check::MAX_F_BITS
                )));
            }
            p.max_bits = v;
        }
        if let Some(v) = o.get::<i64>("max-shear")? {
            if !(0..=64).contains(&v) {
                return Err(Error::Param("--set max-shear must be in 0..=64".into()));
            }
            p.max_shear = v;
        }
        if let Some(v) = o.get::<f64>("tolerance")? {
            if !(v > 0.0 && v.is_finite()) {
                return Err(Error::Param(
                    "--set tolerance must be a positive number".into(),
                ));
            }
            p.tolerance = Some(v);
        }
        if let Some(v) = o.get::<usize>("max-extra-fibres")? {
            p.max_extra_fibres = v;
        }
        p.time_limit = Some(o.time_limit_or_default());
        Ok(Sweep { params: p })
    }
}

/// What an event vertex is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Label {
    /// A smooth point of a non-critical fibre (a sample or a box event).
    Regular,
    /// A smooth point where the tangent is vertical (in the sheared frame).
    XExtreme,
    /// A singular point (∇f = 0) with branches on both sides or one.
    Singular,
    /// An isolated real point (no branches).
    Isolated,
    /// On the domain boundary.
    Boundary,
    /// The real multiple root of a non-generic fibre with two branches: topologically
    /// a regular point; smooth (vertical tangent) or singular (a cusp) not decided.
    Multiple,
}

/// One event of the sweep, as the certificate records it.
#[derive(Clone, Debug, Serialize)]
pub struct EventInfo {
    /// Isolating interval of the u-value (sheared frame), as exact rationals.
    pub u_lo: String,
    pub u_hi: String,
    /// Critical (a root of the discriminant) and/or on the domain boundary.
    pub critical: bool,
    pub boundary: bool,
    /// First non-vanishing principal subresultant index (critical events).
    pub k: Option<usize>,
    /// Distinct real roots of the fibre (Sturm–Habicht count for critical events).
    pub m: usize,
    /// Arcs on the left and right of the fibre (root counts of the rational fibres).
    pub n_left: usize,
    pub n_right: usize,
    /// Branches into the multiple root from the left and the right.
    pub branches: Option<(usize, usize)>,
    /// Multiplicity of the multiple root (generic fibres: k + 1).
    pub multiplicity: Option<usize>,
    /// Did the fibre pass the genericity test S_k(α, v) = sres_k(α)·(v − β)^k?
    pub generic: Option<bool>,
    /// When it did not: the distinct real roots of S_k(α, ·) (0: a phantom event,
    /// 1: one real multiple root, clustered).
    pub real_multiple_roots: Option<usize>,
    /// Label of the multiple root (critical events).
    pub label: Option<Label>,
    /// Is the multiple root inside the domain?
    pub inside: Option<bool>,
}

/// The result of the sweep before it becomes a mesher output.
#[derive(Clone, Debug, Serialize)]
pub struct SweepResult {
    /// The shear s (the analysed polynomial is f(u + s·v, v)).
    pub shear: i64,
    /// Shears rejected before, with the reason.
    pub rejected_shears: Vec<(i64, String)>,
    /// Total degree of the square-free polynomial analysed.
    pub degree: usize,
    /// Degree and bit size of the discriminant D = Res_v(f, f_v).
    pub resultant_degree: isize,
    pub resultant_bits: u64,
    pub events: Vec<EventInfo>,
    /// Root counts of the rational fibres, left to right.
    pub fibre_counts: Vec<usize>,
    #[serde(skip)]
    pub curve: Curve2,
    /// Per output vertex, its label.
    pub labels: Vec<Label>,
    /// The re-checkable certificate ([`super::check::check_curve`]).
    #[serde(skip)]
    pub cert: CurveCert,
    /// What the extra fibres of `--set tolerance` start from (the sheared polynomial,
    /// the events and strips with their certified intervals).
    #[serde(skip)]
    pub arcs: Option<Box<super::tolerance::ArcData>>,
    /// The extra fibres' report, when a tolerance was asked for.
    pub tolerance: Option<super::tolerance::ToleranceReport>,
}

/// The coefficients of a polynomial as decimal strings.
pub fn poly_strings(p: &UPoly) -> Vec<String> {
    p.c.iter().map(|a| a.to_string()).collect()
}

/// The i-th genericity condition of the k-th subresultant, a polynomial in u that
/// vanishes at α iff the coefficient of vⁱ of S_k(α, v) matches sres_k(α)·(v − β)^k
/// with β = −sres_{k,k−1}/(k·sres_k):
/// `sres_{k,i}·(k·sres_k)^{k−i} − sres_k·C(k,i)·sres_{k,k−1}^{k−i}`.
pub fn genericity_condition(sres_k: &UPoly, sk: &[UPoly], k: usize, i: usize) -> UPoly {
    let mut binom = BigInt::one();
    for t in 0..i {
        binom = binom * BigInt::from(k - t) / BigInt::from(t + 1);
    }
    let ksk = sres_k.scale(&BigInt::from(k));
    let lhs = sk[i].mul(&ksk.pow((k - i) as u32));
    let rhs = sres_k.mul(&sk[k - 1].pow((k - i) as u32)).scale(&binom);
    lhs.sub(&rhs)
}

/// The image of [`genericity_condition`] in (Z/q)\[u\]/(p̄), built from the images of
/// its factors (a ring homomorphism, so the same polynomial's image).
fn genericity_image(r: &ModRing, sres_k: &UPoly, sk: &[UPoly], k: usize, i: usize) -> Vec<u64> {
    let mut binom = BigInt::one();
    for t in 0..i {
        binom = binom * BigInt::from(k - t) / BigInt::from(t + 1);
    }
    let s = r.img(sres_k);
    let ks = r.scale(&s, r.int(&BigInt::from(k)));
    let lhs = r.mul(&r.img(&sk[i]), &r.pow(&ks, (k - i) as u32));
    let rhs = r.scale(
        &r.mul(&s, &r.pow(&r.img(&sk[k - 1]), (k - i) as u32)),
        r.int(&binom),
    );
    r.add(&lhs, &r.neg(&rhs))
}

/// Does the i-th genericity condition vanish at α? Exactly as
/// `α.is_root_of(&genericity_condition(…))`, after a modular proof that it does not
/// (`modgcd::coprime_by_image`), which avoids building the condition over Z.
pub fn genericity_holds(a: &RealAlg, sres_k: &UPoly, sk: &[UPoly], k: usize, i: usize) -> bool {
    if !a.is_exact() && coprime_by_image(&a.p, 2, |r| genericity_image(r, sres_k, sk, k, i)) {
        return false;
    }
    a.is_root_of(&genericity_condition(sres_k, sk, k, i))
}

/// The image of [`at_beta`] in (Z/q)\[u\]/(p̄), by the same homogeneous Horner.
fn at_beta_image(r: &ModRing, h: &BiPoly, num: &UPoly, den: &UPoly, d: usize) -> Vec<u64> {
    let n = h.c.len();
    if n == 0 {
        return Vec::new();
    }
    let (nu, de) = (r.img(num), r.img(den));
    let mut dpow = vec![r.pow(&de, (d + 1 - n) as u32)];
    for _ in 1..n {
        let next = r.mul(dpow.last().unwrap(), &de);
        dpow.push(next);
    }
    let mut acc = r.mul(&r.img(&h.c[n - 1]), &dpow[0]);
    for j in (0..n - 1).rev() {
        acc = r.add(&r.mul(&acc, &nu), &r.mul(&r.img(&h.c[j]), &dpow[n - 1 - j]));
    }
    acc
}

/// Is h(α, β(α)) = 0, i.e. α a root of [`at_beta`]? Exactly as
/// `α.is_root_of(&at_beta(…))`, after a modular proof that it is not
/// (`modgcd::coprime_by_image`): at an x-extreme the answer comes from one prime,
/// without building den^d·h(u, num/den) over Z.
pub fn is_root_at_beta(a: &RealAlg, h: &BiPoly, num: &UPoly, den: &UPoly, d: usize) -> bool {
    if !a.is_exact() && coprime_by_image(&a.p, 2, |r| at_beta_image(r, h, num, den, d)) {
        return false;
    }
    a.is_root_of(&at_beta(h, num, den, d))
}

/// S_k as a polynomial in v: coefficients `sk` (v⁰ … v^(k−1)) and sres_k.
pub fn sk_poly(sres_k: &UPoly, sk: &[UPoly]) -> BiPoly {
    let mut c = sk.to_vec();
    c.push(sres_k.clone());
    BiPoly::new(c)
}

/// den^d·h(u, num/den) for h = Σ h_j(u) vʲ: zero at α iff h(α, β(α)) = 0.
pub fn at_beta(h: &BiPoly, num: &UPoly, den: &UPoly, d: usize) -> UPoly {
    // Homogeneous Horner: Σ_j h_j·num^j·den^(d−j) with den^(d−j) built once.
    let n = h.c.len();
    if n == 0 {
        return UPoly::zero();
    }
    let mut dpow = vec![den.pow((d + 1 - n) as u32)];
    for _ in 1..n {
        let next = dpow.last().unwrap().mul(den);
        dpow.push(next);
    }
    // dpow[t] = den^(d − n + 1 + t); h_j needs den^(d − j) = dpow[n − 1 − j].
    let mut acc = h.c[n - 1].mul(&dpow[0]);
    for j in (0..n - 1).rev() {
        acc = acc.mul(num).add(&h.c[j].mul(&dpow[n - 1 - j]));
    }
    acc
}

fn rat(x: f64) -> Result<BigRational> {
    BigRational::from_float(x).ok_or_else(|| Error::Domain(format!("{x} is not finite")))
}
fn two() -> BigRational {
    BigRational::from_integer(BigInt::from(2))
}
fn pow2q(k: i64) -> BigRational {
    if k >= 0 {
        BigRational::from_integer(BigInt::one() << k as u64)
    } else {
        BigRational::new(BigInt::one(), BigInt::one() << (-k) as u64)
    }
}

/// A closed rational interval.
#[derive(Clone, Debug)]
struct Ri {
    lo: BigRational,
    hi: BigRational,
}
impl Ri {
    fn pt(x: &BigRational) -> Self {
        Ri {
            lo: x.clone(),
            hi: x.clone(),
        }
    }
    fn sign(&self) -> Option<i32> {
        if self.lo.is_positive() {
            Some(1)
        } else if self.hi.is_negative() {
            Some(-1)
        } else {
            None
        }
    }
    fn mul(&self, o: &Ri) -> Ri {
        let ps = [
            &self.lo * &o.lo,
            &self.lo * &o.hi,
            &self.hi * &o.lo,
            &self.hi * &o.hi,
        ];
        Ri {
            lo: ps.iter().min().unwrap().clone(),
            hi: ps.iter().max().unwrap().clone(),
        }
    }
    fn add(&self, o: &Ri) -> Ri {
        Ri {
            lo: &self.lo + &o.lo,
            hi: &self.hi + &o.hi,
        }
    }
    /// Widen outward to multiples of 2^−p (keeps the numbers small).
    fn round(&self, p: u64) -> Ri {
        let s = BigRational::from_integer(BigInt::one() << p);
        Ri {
            lo: (&self.lo * &s).floor() / &s,
            hi: (&self.hi * &s).ceil() / &s,
        }
    }
    fn abs_max(&self) -> BigRational {
        self.lo.abs().max(self.hi.abs())
    }
}

/// f over I × J, with the coefficient enclosures `cs` (over I) precomputed.
fn eval2(cs: &[Ri], j: &Ri, prec: u64) -> Ri {
    let mut acc = cs.last().cloned().unwrap_or(Ri::pt(&BigRational::zero()));
    for c in cs.iter().rev().skip(1) {
        acc = acc.mul(j).add(c).round(prec);
    }
    acc
}

fn coef_enclosures(g: &BiPoly, lo: &BigRational, hi: &BigRational, prec: u64) -> Vec<Ri> {
    g.c.iter()
        .map(|p| {
            let (a, b) = eval_interval(p, lo, hi);
            Ri { lo: a, hi: b }.round(prec)
        })
        .collect()
}

/// A root of an event fibre: an isolating interval of v.
#[derive(Clone, Debug)]
struct FRoot {
    lo: BigRational,
    hi: BigRational,
    special: bool,
    boundary: bool,
    /// On a side of the domain (not a vertical side at shear 0): v = v0 + v1·u.
    snap: Option<BPoint>,
}

/// β(α) = num(α)/den(α), the fibre's multiple root.
struct Special<'a> {
    num: &'a UPoly,
    den: &'a UPoly,
    /// The multiple root has multiplicity k + 1.
    k: usize,
}

fn special_box(s: &Special, a: &RealAlg) -> Option<Ri> {
    let (nl, nh) = eval_interval(s.num, &a.lo, &a.hi);
    let (dl, dh) = eval_interval(s.den, &a.lo, &a.hi);
    if !dl.is_positive() && !dh.is_negative() {
        return None;
    }
    let qs = [&nl / &dl, &nl / &dh, &nh / &dl, &nh / &dh];
    Some(Ri {
        lo: qs.iter().min().unwrap().clone(),
        hi: qs.iter().max().unwrap().clone(),
    })
}

/// How the roots of an event fibre are isolated.
#[derive(Clone, Copy)]
enum Mode<'a> {
    /// All m roots are simple (non-critical fibres and phantom events).
    Plain,
    /// m − 1 simple roots and the multiple root β(α) = num/den (the N rule).
    Generic(&'a Special<'a>),
    /// m − 1 simple roots and one real multiple root of unknown position: it lies in
    /// the one contiguous cluster of undecided boxes left after excluding the rest.
    Cluster,
}

/// Certify the distinct real roots of g(α, ·): `m` of them. Boxes: simple roots with
/// strictly opposite endpoint signs and 0 ∉ g_v(I, box); every other box has
/// 0 ∉ g(I, box). Generic mode: the box N around β is never examined, and success
/// (exactly m − 1 certified boxes outside it) proves N holds β alone, because m is
/// exact. Cluster mode: the boxes left undecided at the smallest width must form one
/// interval; with m − 1 simple boxes and everything else excluded, it holds the
/// remaining root. Returns the roots and, in cluster mode, the excluded boxes.
#[allow(clippy::type_complexity)]
fn fibre_roots(
    g: &BiPoly,
    gy: &BiPoly,
    alpha: &mut RealAlg,
    m: usize,
    mode: Mode,
) -> Result<(Vec<FRoot>, Vec<(BigRational, BigRational)>)> {
    if let Some(r) = fibre_roots_f64(g, gy, alpha, m, mode) {
        return Ok(r);
    }
    let lc = g.lc_y().coef(0).abs();
    let want = m - usize::from(!matches!(mode, Mode::Plain));
    for round in 0..12u64 {
        let prec = 96 + 24 * round;
        alpha.refine_to(&pow2q(-(12 + 8 * round as i64)));
        let cs = coef_enclosures(g, &alpha.lo, &alpha.hi, prec);
        let csy = coef_enclosures(gy, &alpha.lo, &alpha.hi, prec);
        let mut bound = BigRational::zero();
        for c in &cs[..cs.len() - 1] {
            bound = bound.max(c.abs_max());
        }
        let y = BigRational::one() + bound / BigRational::from_integer(lc.clone());
        let mut regions = Vec::new();
        let mut nbox = None;
        if let Mode::Generic(s) = mode {
            let Some(b) = special_box(s, alpha) else {
                continue;
            };
            let rho = pow2q(-(3 + 2 * round as i64));
            let n = Ri {
                lo: &b.lo - &rho,
                hi: &b.hi + &rho,
            };
            if -&y < n.lo {
                regions.push((-y.clone(), n.lo.clone()));
            }
            if n.hi < y {
                regions.push((n.hi.clone(), y.clone()));
            }
            nbox = Some(n);
        } else {
            regions.push((-y.clone(), y.clone()));
        }
        let cluster = matches!(mode, Mode::Cluster);
        let minw = pow2q(-(24 + 8 * round as i64));
        let kind = |a: &BigRational, b: &BigRational| {
            let j = Ri {
                lo: a.clone(),
                hi: b.clone(),
            };
            box_kind(
                eval2(&cs, &j, prec).sign(),
                || Some(eval2(&csy, &j, prec).sign()),
                || {
                    let end = |t: &BigRational| eval2(&cs, &Ri::pt(t), prec).sign();
                    Some((end(a), end(b)))
                },
            )
        };
        // Boxes split at their centre, unless g's sign there is not known: the centre
        // may be a root (a rational root of an exact fibre, e.g. v = 1/2 of x²y² − 1/4
        // sheared, over u = 1/2), which would then stay an end of two boxes at every
        // width, neither certified, and the same in every round when α is exact.
        // Then at 5/8 or 3/8 of the box, where its sign is known.
        let mid = |a: &BigRational, b: &BigRational| {
            if b - a < minw {
                return None;
            }
            let known = |t: &BigRational| eval2(&cs, &Ri::pt(t), prec).sign().is_some();
            let centre = (a + b) / two();
            if known(&centre) {
                return Some(centre);
            }
            [(5, 8), (3, 8)]
                .into_iter()
                .map(|(p, q)| a + (b - a) * BigRational::new(p.into(), q.into()))
                .find(|t| known(t))
                .or(Some(centre))
        };
        let Search::Done(found, excluded, undecided) =
            box_search(regions, BOX_SEARCH_STEPS, cluster, kind, mid)
        else {
            continue;
        };
        let Some(boxes) = finish_boxes(found, nbox.map(|n| (n.lo, n.hi)), undecided, want, cluster)
        else {
            continue;
        };
        return Ok((froots(boxes), excluded));
    }
    Err(Error::TooLarge(format!(
        "event fibre near u = {:.6}: the {want} simple roots were not certified within the refinement budget",
        alpha.to_f64()
    )))
}

/// One box of an event fibre, from interval evaluations of g and g_v over it.
enum BoxKind {
    /// 0 ∉ g(α, box).
    Empty,
    /// A certified simple root: strictly opposite end signs and 0 ∉ g_v(α, box).
    Root,
    /// g monotone on the box with the same strict sign at both ends: no root.
    SameSign,
    /// Undecided: split it.
    Open,
}

/// A box's kind from the sign of g over it, then (lazily) the sign of g_v over it and
/// the signs of g at its two ends; None when an evaluation failed.
fn box_kind(
    g: Option<i32>,
    gy: impl FnOnce() -> Option<Option<i32>>,
    ends: impl FnOnce() -> Option<(Option<i32>, Option<i32>)>,
) -> Option<BoxKind> {
    if g.is_some() {
        return Some(BoxKind::Empty);
    }
    if gy()?.is_some() {
        if let (Some(sa), Some(sb)) = ends()? {
            return Some(if sa != sb {
                BoxKind::Root
            } else {
                BoxKind::SameSign
            });
        }
    }
    Some(BoxKind::Open)
}

/// How a bisection search of an event fibre ended.
enum Search<T> {
    /// (simple-root boxes, boxes without a root, undecided boxes at the smallest width).
    Done(Vec<(T, T)>, Vec<(T, T)>, Vec<(T, T)>),
    /// Budget exhausted, or an undecided box at the smallest width outside cluster
    /// mode: try again with α refined.
    Failed,
    /// An evaluation failed (the f64 filter gives up).
    Abort,
}

/// The bisection of `regions` shared by the f64 filter and the exact rationals:
/// `kind` classifies a box (None: the evaluation failed), `mid` splits it (None: at
/// the smallest width).
/// Boxes one event fibre's root search may visit (exact rationals; half of it with
/// floats), and so the most excluded boxes a certificate's event can list.
pub(super) const BOX_SEARCH_STEPS: usize = 40_000;

fn box_search<T: Clone>(
    regions: Vec<(T, T)>,
    mut budget: usize,
    cluster: bool,
    kind: impl Fn(&T, &T) -> Option<BoxKind>,
    mid: impl Fn(&T, &T) -> Option<T>,
) -> Search<T> {
    let (mut found, mut excluded, mut undecided) = (Vec::new(), Vec::new(), Vec::new());
    let mut stack = regions;
    while let Some((a, b)) = stack.pop() {
        if budget == 0 {
            return Search::Failed;
        }
        if out_of_time() {
            return Search::Abort;
        }
        budget -= 1;
        match kind(&a, &b) {
            None => return Search::Abort,
            Some(BoxKind::Root) => found.push((a, b)),
            Some(BoxKind::Empty | BoxKind::SameSign) => {
                if cluster {
                    excluded.push((a, b));
                }
            }
            Some(BoxKind::Open) => match mid(&a, &b) {
                Some(m) => {
                    stack.push((m.clone(), b));
                    stack.push((a, m));
                }
                None if cluster => undecided.push((a, b)),
                None => return Search::Failed,
            },
        }
    }
    Search::Done(found, excluded, undecided)
}

/// The fibre's root boxes, sorted, each flagged special or not: the `want` simple
/// roots, then β's box N (generic mode) or the one contiguous cluster of undecided
/// boxes (cluster mode); None when the counts or the cluster do not work out.
fn finish_boxes<T: Clone + PartialOrd>(
    found: Vec<(T, T)>,
    nbox: Option<(T, T)>,
    mut undecided: Vec<(T, T)>,
    want: usize,
    cluster: bool,
) -> Option<Vec<((T, T), bool)>> {
    if found.len() != want {
        return None;
    }
    let mut out: Vec<((T, T), bool)> = found.into_iter().map(|x| (x, false)).collect();
    if let Some(n) = nbox {
        out.push((n, true));
    }
    if cluster {
        undecided.sort_by(|x, y| x.0.partial_cmp(&y.0).expect("ordered"));
        if undecided.is_empty() || undecided.windows(2).any(|w| w[0].1 != w[1].0) {
            return None;
        }
        let span = (undecided[0].0.clone(), undecided.last().unwrap().1.clone());
        out.push((span, true));
    }
    out.sort_by(|x, y| x.0 .0.partial_cmp(&y.0 .0).expect("ordered"));
    Some(out)
}

fn froots(boxes: Vec<((BigRational, BigRational), bool)>) -> Vec<FRoot> {
    boxes
        .into_iter()
        .map(|((lo, hi), special)| FRoot {
            lo,
            hi,
            special,
            boundary: false,
            snap: None,
        })
        .collect()
}

/// [`fibre_roots`] with the f64 filter: the same search and the same claims, every
/// box decided by outward-rounded interval Horner over an enclosure of α's isolating
/// interval. A claim proven here holds for the exact interval evaluation the checker
/// does (inclusion isotonicity), and the box endpoints are f64 values, exact rationals.
/// `None` when f64 cannot decide (the caller falls back to exact rationals).
#[allow(clippy::type_complexity)]
fn fibre_roots_f64(
    g: &BiPoly,
    gy: &BiPoly,
    alpha: &mut RealAlg,
    m: usize,
    mode: Mode,
) -> Option<(Vec<FRoot>, Vec<(BigRational, BigRational)>)> {
    use fint::{horner, iv_sign, pt};
    use inari::Interval;
    let polys = |b: &BiPoly| b.c.iter().map(fint::poly_iv).collect::<Option<Vec<_>>>();
    let (gf, gyf) = (polys(g)?, polys(gy)?);
    let lc = fint::int_iv(&g.lc_y().coef(0).abs())?;
    let spf = match mode {
        Mode::Generic(s) => Some((fint::poly_iv(s.num)?, fint::poly_iv(s.den)?, s.k)),
        _ => None,
    };
    let want = m - usize::from(!matches!(mode, Mode::Plain));
    let cluster = matches!(mode, Mode::Cluster);
    let q = |x: f64| BigRational::from_float(x).expect("finite");
    for round in 0..6u64 {
        // The excluded neighbourhood of β has radius ρ = 2^−rho; α's width is small
        // against ρ^(k+1), the size of f next to a root of multiplicity k + 1.
        let rho = 2 + 2 * round;
        let wlog = match &spf {
            Some((_, _, k)) => (*k as u64 + 1) * rho + 10,
            None => 20 + 8 * round,
        };
        if wlog > 52 {
            return None;
        }
        alpha.refine_to(&pow2q(-(wlog as i64)));
        let ai = fint::qq_iv(&alpha.lo, &alpha.hi)?;
        let cs: Vec<Interval> = gf.iter().map(|c| horner(c, ai)).collect();
        let csy: Vec<Interval> = gyf.iter().map(|c| horner(c, ai)).collect();
        let mag = cs[..cs.len() - 1]
            .iter()
            .map(|c| c.mag())
            .fold(0.0f64, f64::max);
        let y = (pt(1.0) + pt(mag) / lc).sup();
        if !y.is_finite() {
            return None;
        }
        let mut regions: Vec<(f64, f64)> = Vec::new();
        let mut nbox = None;
        if let Some((nf, df, _)) = &spf {
            let (ni, di) = (horner(nf, ai), horner(df, ai));
            if iv_sign(di).is_none() {
                continue;
            }
            let b = ni / di;
            let r = pt(2f64.powi(-(rho as i32)));
            let (lo, hi) = ((pt(b.inf()) - r).inf(), (pt(b.sup()) + r).sup());
            if !lo.is_finite() || !hi.is_finite() {
                return None;
            }
            if -y < lo {
                regions.push((-y, lo));
            }
            if hi < y {
                regions.push((hi, y));
            }
            nbox = Some((lo, hi));
        } else {
            regions.push((-y, y));
        }
        let ev = |c: &[Interval], a: f64, b: f64| -> Option<Interval> {
            Some(horner(c, Interval::try_from((a, b)).ok()?))
        };
        let minw = 2f64.powi(-((20 + 8 * round) as i32));
        let kind = |a: &f64, b: &f64| {
            let (a, b) = (*a, *b);
            box_kind(
                iv_sign(ev(&cs, a, b)?),
                || Some(iv_sign(ev(&csy, a, b)?)),
                || Some((iv_sign(ev(&cs, a, a)?), iv_sign(ev(&cs, b, b)?))),
            )
        };
        let mid = |a: &f64, b: &f64| {
            let m = a + (b - a) * 0.5;
            let wide = b - a >= minw * (1.0 + a.abs().max(b.abs()));
            (wide && *a < m && m < *b).then_some(m)
        };
        let (found, excluded, undecided) =
            match box_search(regions, BOX_SEARCH_STEPS / 2, cluster, kind, mid) {
                Search::Done(f, e, u) => (f, e, u),
                Search::Failed => continue,
                Search::Abort => return None,
            };
        let Some(boxes) = finish_boxes(found, nbox, undecided, want, cluster) else {
            continue;
        };
        let qb = |v: Vec<((f64, f64), bool)>| {
            v.into_iter()
                .map(|((a, b), sp)| ((q(a), q(b)), sp))
                .collect::<Vec<_>>()
        };
        let ex = excluded.into_iter().map(|(a, b)| (q(a), q(b))).collect();
        return Some((froots(qb(boxes)), ex));
    }
    None
}

/// Shrink the root boxes of an event fibre after refining α (keeps every invariant:
/// a regular box keeps a certified sign change, the special box is β's enclosure).
fn shrink(g: &BiPoly, alpha: &mut RealAlg, roots: &mut [FRoot], special: Option<&Special>) {
    let w = alpha.width() / BigRational::from_integer(BigInt::from(4));
    alpha.refine_to(&w);
    let prec = 160 + alpha.width().denom().bits();
    let cs = coef_enclosures(g, &alpha.lo, &alpha.hi, prec);
    for r in roots.iter_mut() {
        if r.special {
            if let Some(s) = special {
                if let Some(b) = special_box(s, alpha) {
                    r.lo = (&r.lo).max(&b.lo).clone();
                    r.hi = (&r.hi).min(&b.hi).clone();
                }
            }
            continue;
        }
        // The root's side of a trial point is read from the sign at the lower end, or,
        // where that is not known, at the upper end: an end can be another root of the
        // fibre, exactly (the fibre u = −9/4 of x²y² − 1/4 sheared has the roots 2 and
        // 2.45…, isolated as [2, 2] and [2, 4]), and a bisection that needed the sign
        // there never moved that end.
        let sl = eval2(&cs, &Ri::pt(&r.lo), prec).sign();
        let sh = match sl {
            Some(_) => None,
            None => eval2(&cs, &Ri::pt(&r.hi), prec).sign(),
        };
        for frac in [(1, 2), (1, 3), (2, 3)] {
            let t = BigRational::new(BigInt::from(frac.0), BigInt::from(frac.1));
            let mid = &r.lo + (&r.hi - &r.lo) * t;
            let Some(sm) = eval2(&cs, &Ri::pt(&mid), prec).sign() else {
                continue;
            };
            // The root is above mid when mid has the lower end's sign (the root is
            // simple and the only one inside), or not the upper end's.
            let above = match (sl, sh) {
                (Some(sl), _) => sm == sl,
                (None, Some(sh)) => sm != sh,
                (None, None) => break,
            };
            if above {
                r.lo = mid;
            } else {
                r.hi = mid;
            }
            break;
        }
    }
}

/// The domain in the sheared frame: the parallelogram ymin ≤ v ≤ ymax,
/// xmin ≤ u + s·v ≤ xmax.
struct Frame {
    s: BigRational,
    xmin: BigRational,
    xmax: BigRational,
    ymin: BigRational,
    ymax: BigRational,
}

impl Frame {
    /// Strictly inside (Some(true)), outside the closed domain (Some(false)), or
    /// undecided from the intervals.
    fn classify(&self, u: &Ri, v: &Ri) -> Option<bool> {
        let x = u.add(&v.mul(&Ri::pt(&self.s)));
        if v.lo > self.ymin && v.hi < self.ymax && x.lo > self.xmin && x.hi < self.xmax {
            return Some(true);
        }
        if v.hi < self.ymin || v.lo > self.ymax || x.hi < self.xmin || x.lo > self.xmax {
            return Some(false);
        }
        None
    }
}

/// A point of the boundary in an event fibre: v = v0 + v1·u.
#[derive(Clone, Debug)]
struct BPoint {
    v0: BigRational,
    v1: BigRational,
}

struct Event {
    u: RealAlg,
    critical: bool,
    /// A vertical side of the domain (s = 0): the whole fibre is boundary.
    side: bool,
    bpoints: Vec<BPoint>,
    /// The subresultant data of a critical event (computed before anything else, so
    /// that a rejected shear costs little).
    crit: Option<Crit>,
}

/// What the principal subresultants say about a critical fibre u = α.
#[derive(Clone, Debug)]
struct Crit {
    /// Signs of sres_j(α), j = 0 … d − 1.
    signs: Vec<i32>,
    k: usize,
    m: usize,
    generic: bool,
    /// Non-generic: the distinct real roots of S_k(α, ·) and the signs giving them.
    r: Option<usize>,
    r_signs: Vec<i32>,
}

/// k, m, the genericity test and the real-only r-test at a critical event; a
/// non-generic frame (r ≥ 2) is the `nongeneric` error.
fn critical_data(
    u: &mut RealAlg,
    g: &BiPoly,
    chain: &[BiPoly],
    sres: &[UPoly],
    lc_sign: i32,
    sk_cache: &mut std::collections::HashMap<usize, Vec<UPoly>>,
) -> Result<Crit> {
    let d = g.deg_y() as usize;
    let mut signs = vec![0i32; d];
    let mut k = None;
    for j in 1..d {
        let sg = u.sign_of(&sres[j])?;
        signs[j] = sg;
        if sg != 0 && k.is_none() {
            k = Some(j);
        }
    }
    let k = k.ok_or_else(|| Error::Param("internal: no non-zero subresultant".into()))?;
    let m = subres::distinct_real_roots(d, lc_sign, &signs).max(0) as usize;
    let sk = sk_cache
        .entry(k)
        .or_insert_with(|| subres::lower_of(chain, k));
    // Genericity: S_k(α, v) = sres_k(α)·(v − β)^k.
    let generic = (0..k.saturating_sub(1)).all(|i| genericity_holds(u, &sres[k], sk, k, i));
    let mut c = Crit {
        signs,
        k,
        m,
        generic,
        r: None,
        r_signs: Vec::new(),
    };
    if !generic {
        // The real-only test: r = the distinct real roots of S_k(α, ·).
        let skp = sk_poly(&sres[k], sk);
        let ps = subres::principal(&skp, &skp.dy());
        let mut rs = vec![0i32; k];
        for j in 0..k {
            rs[j] = u.sign_of(&ps[j])?;
        }
        let lck = u.sign_of(&sres[k])?;
        let r = subres::distinct_real_roots(k, lck, &rs).max(0) as usize;
        if r >= 2 {
            return Err(nongeneric(format!(
                "the fibre over u ≈ {:.6} has {r} real multiple roots (k = {k})",
                u.to_f64()
            )));
        }
        c.r = Some(r);
        c.r_signs = rs;
    }
    Ok(c)
}

fn nongeneric(msg: String) -> Error {
    Error::Param(format!("__nongeneric__{msg}"))
}

/// The exact topology of f = 0 inside `domain` (its x and y ranges).
pub fn analyse(f: &BiPoly, domain: &Aabb, p: &SweepParams) -> Result<SweepResult> {
    super::algnum::clear_gcd_memo();
    if f.is_zero() {
        return Err(Error::Param(
            "f is identically zero: its zero set is the whole plane".into(),
        ));
    }
    let d = f.total_degree();
    if d as usize > p.max_degree {
        return Err(Error::TooLarge(format!(
            "the polynomial has degree {d}, above the sweep's budget {} (raise --set max-degree)",
            p.max_degree
        )));
    }
    if f.max_bits() > p.max_bits {
        return Err(Error::TooLarge(format!(
            "the polynomial has {}-bit coefficients, above the sweep's budget {} (raise --set max-bits)",
            f.max_bits(),
            p.max_bits
        )));
    }
    let mut rejected = Vec::new();
    let mut shears = vec![0i64];
    for k in 1..=p.max_shear {
        shears.push(k);
        shears.push(-k);
    }
    let _deadline = DeadlineGuard::set(p.time_limit);
    let stopped = |p: &SweepParams| {
        Error::TooLarge(format!(
            "the sweep did not finish within its time limit of {} s (its exact root searches grew too long; raise --time-limit)",
            p.time_limit.unwrap_or(f64::NAN)
        ))
    };
    for s in shears {
        if out_of_time() {
            return Err(stopped(p));
        }
        let g = f.shear(s);
        if d > 0 && (g.deg_y() <= 0 || g.lc_y().deg() != 0) {
            rejected.push((
                s,
                "not y-regular (the leading coefficient in y is not constant)".into(),
            ));
            continue;
        }
        let g = squarefree_y_regular(g);
        match analyse_frame(f, &g, s, domain) {
            Ok(mut r) => {
                r.rejected_shears = rejected;
                if let Some(t) = p.tolerance {
                    super::tolerance::refine(
                        &mut r,
                        &super::tolerance::ToleranceParams {
                            tolerance: t,
                            max_fibres: p.max_extra_fibres,
                            max_depth: 40,
                        },
                    )?;
                }
                return Ok(r);
            }
            Err(Error::Param(m)) if m.starts_with("__nongeneric__") => {
                rejected.push((s, m.trim_start_matches("__nongeneric__").to_string()));
            }
            Err(_) if out_of_time() => return Err(stopped(p)),
            Err(e) => return Err(e),
        }
    }
    if out_of_time() {
        return Err(stopped(p));
    }
    Err(Error::TooLarge(format!(
        "no shear with |s| <= {} puts the curve in generic position (raise --set max-shear); tried: {}",
        p.max_shear,
        rejected
            .iter()
            .map(|(s, r)| format!("s = {s}: {r}"))
            .collect::<Vec<_>>()
            .join("; ")
    )))
}

/// `g.squarefree_y()` for a y-regular g (constant, non-zero lc_y), the same
/// polynomial, with the bivariate gcd skipped when a specialisation proves it trivial:
/// a common factor G of g and g_y with deg_y G ≥ 1 has a constant lc_y (it divides
/// lc_y g), so G(x0, ·) keeps its degree and divides g(x0, ·) and g_y(x0, ·) for every
/// integer x0; a square-free g(x0, ·) (univariate gcd with its derivative constant)
/// therefore proves deg_y gcd(g, g_y) = 0, and squarefree_y is then g.primitive().
fn squarefree_y_regular(g: BiPoly) -> BiPoly {
    let d = g.deg_y();
    if d >= 1 && g.lc_y().deg() == 0 {
        for x0 in [0i64, 1, -1, 2] {
            let gx = g.at_x(&BigRational::from_integer(BigInt::from(x0)));
            if gx.deg() == d && gx.gcd(&gx.derivative()).deg() == 0 {
                return g.primitive();
            }
        }
    }
    g.squarefree_y()
}

fn boundary_error(what: &str) -> Error {
    Error::Domain(format!(
        "{what}: the exact sweep needs the domain sides to meet the curve only at regular points of non-critical fibres, away from the corners; move or enlarge the domain slightly"
    ))
}

/// Insert `e` into the sorted event list, merging equal u-values.
/// The crossings of the curve with one side of the domain: the roots of `h` (f on the
/// side's line, as a polynomial in u) strictly inside the side's u-range (a, b), each an
/// event at the side point `bp`; a root at an end is the curve through a corner, and
/// h ≡ 0 the side on the curve (both refused).
fn side_crossings(
    events: &mut Vec<Event>,
    side: &str,
    h: &UPoly,
    a: &BigRational,
    b: &BigRational,
    bp: BPoint,
) -> Result<()> {
    if h.is_zero() {
        return Err(boundary_error(&format!(
            "a {side} side of the domain lies on the curve"
        )));
    }
    for mut r in isolate(h)? {
        let (ca, cb) = (r.cmp_q(a), r.cmp_q(b));
        if ca == Ordering::Equal || cb == Ordering::Equal {
            return Err(boundary_error(
                "the curve passes through a corner of the domain",
            ));
        }
        if ca == Ordering::Greater && cb == Ordering::Less {
            insert_event(
                events,
                Event {
                    u: r,
                    critical: false,
                    side: false,
                    bpoints: vec![bp.clone()],
                    crit: None,
                },
            )?;
        }
    }
    Ok(())
}

fn insert_event(events: &mut Vec<Event>, mut e: Event) -> Result<()> {
    for i in 0..events.len() {
        match e.u.compare(&mut events[i].u)? {
            Ordering::Less => {
                events.insert(i, e);
                return Ok(());
            }
            Ordering::Equal => {
                let t = &mut events[i];
                t.critical |= e.critical;
                t.side |= e.side;
                t.bpoints.extend(e.bpoints);
                return Ok(());
            }
            Ordering::Greater => {}
        }
    }
    events.push(e);
    Ok(())
}

fn analyse_frame(f: &BiPoly, g: &BiPoly, s: i64, domain: &Aabb) -> Result<SweepResult> {
    let fr = Frame {
        s: BigRational::from_integer(BigInt::from(s)),
        xmin: rat(domain.min[0])?,
        xmax: rat(domain.max[0])?,
        ymin: rat(domain.min[1])?,
        ymax: rat(domain.max[1])?,
    };
    let sq = &fr.s;
    let (u_lo, u_hi) = if s >= 0 {
        (&fr.xmin - sq * &fr.ymax, &fr.xmax - sq * &fr.ymin)
    } else {
        (&fr.xmin - sq * &fr.ymin, &fr.xmax - sq * &fr.ymax)
    };
    let mut out = SweepResult {
        shear: s,
        rejected_shears: Vec::new(),
        degree: g.total_degree().max(0) as usize,
        resultant_degree: -1,
        resultant_bits: 0,
        events: Vec::new(),
        fibre_counts: Vec::new(),
        curve: Curve2 {
            vertices: Vec::new(),
            segments: Vec::new(),
        },
        labels: Vec::new(),
        cert: CurveCert::default(),
        arcs: None,
        tolerance: None,
    };
    let mut cert = CurveCert {
        format: super::check::CERT_FORMAT.to_string(),
        f: f.c.iter().map(poly_strings).collect(),
        shear: s,
        domain: [
            fr.xmin.to_string(),
            fr.ymin.to_string(),
            fr.xmax.to_string(),
            fr.ymax.to_string(),
        ],
        ..Default::default()
    };
    let dy = g.deg_y();
    if dy <= 0 {
        // A non-zero constant: the real zero set is empty.
        out.cert = cert;
        return Ok(out);
    }
    let d = dy as usize;
    let gy = g.dy();
    let chain = subres::full_chain(g, &gy);
    let sres = subres::principal_of(&chain);
    let disc = sres[0].clone();
    out.resultant_degree = disc.deg();
    out.resultant_bits = disc.max_bits();
    let lc_sign = sign(&g.lc_y().coef(0));
    let mut events: Vec<Event> = Vec::new();
    // Critical u-values inside the domain's u-range.
    for mut a in isolate(&disc)? {
        let c_lo = a.cmp_q(&u_lo);
        let c_hi = a.cmp_q(&u_hi);
        if s == 0 && (c_lo == Ordering::Equal || c_hi == Ordering::Equal) {
            return Err(boundary_error(
                "a vertical side of the domain lies on a critical x-value of the curve",
            ));
        }
        if c_lo == Ordering::Greater && c_hi == Ordering::Less {
            insert_event(
                &mut events,
                Event {
                    u: a,
                    critical: true,
                    side: false,
                    bpoints: Vec::new(),
                    crit: None,
                },
            )?;
        }
    }
    // The subresultant data of every critical event first: a non-generic frame is
    // rejected before any fibre is computed.
    let mut sk_cache: std::collections::HashMap<usize, Vec<UPoly>> = Default::default();
    for ev in events.iter_mut() {
        ev.crit = Some(critical_data(
            &mut ev.u,
            g,
            &chain,
            &sres,
            lc_sign,
            &mut sk_cache,
        )?);
    }
    // Box events.
    let zero = BigRational::zero();
    let one = BigRational::one();
    let sides_h = [fr.ymin.clone(), fr.ymax.clone()];
    for c in &sides_h {
        let h = g.on_line(&zero, &one, c, &zero);
        // The side's u-range: x = u + s·c ∈ [xmin, xmax].
        let (a, b) = (&fr.xmin - sq * c, &fr.xmax - sq * c);
        let side_point = BPoint {
            v0: c.clone(),
            v1: zero.clone(),
        };
        side_crossings(&mut events, "horizontal", &h, &a, &b, side_point)?;
    }
    for c in [fr.xmin.clone(), fr.xmax.clone()] {
        if s == 0 {
            insert_event(
                &mut events,
                Event {
                    u: RealAlg::exact(c),
                    critical: false,
                    side: true,
                    bpoints: Vec::new(),
                    crit: None,
                },
            )?;
            continue;
        }
        // u + s·v = c: v = c/s − u/s.
        let (v0, v1) = (&c / sq, -(&one / sq));
        let h = g.on_line(&zero, &one, &v0, &v1);
        // v ∈ [ymin, ymax] ⇔ u ∈ [c − s·ymax, c − s·ymin] (s > 0), swapped for s < 0.
        let (mut a, mut b) = (&c - sq * &fr.ymax, &c - sq * &fr.ymin);
        if s < 0 {
            std::mem::swap(&mut a, &mut b);
        }
        let side_point = BPoint {
            v0: v0.clone(),
            v1: v1.clone(),
        };
        side_crossings(&mut events, "vertical", &h, &a, &b, side_point)?;
    }
    // Separate neighbouring events strictly, and choose the rational samples.
    let n_ev = events.len();
    for i in 0..n_ev.saturating_sub(1) {
        let (l, r) = events.split_at_mut(i + 1);
        let (a, b) = (&mut l[i].u, &mut r[0].u);
        let mut guard = 0;
        while a.hi >= b.lo {
            guard += 1;
            if guard > super::algnum::REFINE_STEPS {
                return Err(Error::TooLarge("event separation budget exhausted".into()));
            }
            if !a.is_exact() && (a.width() >= b.width() || b.is_exact()) {
                a.bisect();
            } else {
                b.bisect();
            }
        }
    }
    // Strips: (left event index or None, right event index or None, sample).
    let mut strips: Vec<(Option<usize>, Option<usize>, BigRational)> = Vec::new();
    let sample_between = |lo: &BigRational, hi: &BigRational| (lo + hi) / two();
    if n_ev == 0 {
        strips.push((None, None, sample_between(&u_lo, &u_hi)));
    } else {
        if s != 0 {
            let e0 = &mut events[0].u;
            while e0.lo <= u_lo {
                e0.bisect();
            }
            strips.push((None, Some(0), sample_between(&u_lo, &events[0].u.lo)));
        }
        for i in 0..n_ev - 1 {
            strips.push((
                Some(i),
                Some(i + 1),
                sample_between(&events[i].u.hi, &events[i + 1].u.lo),
            ));
        }
        if s != 0 {
            let e = &mut events[n_ev - 1].u;
            while e.hi >= u_hi {
                e.bisect();
            }
            strips.push((
                Some(n_ev - 1),
                None,
                sample_between(&events[n_ev - 1].u.hi, &u_hi),
            ));
        }
    }
    // Rational fibres.
    let mut verts: Vec<[f64; 2]> = Vec::new();
    let mut labels: Vec<Label> = Vec::new();
    let unshear = |u: f64, v: f64| [u + s as f64 * v, v];
    struct Sample {
        count: usize,
        /// Per root: vertex index when inside, None when outside.
        vid: Vec<Option<u32>>,
    }
    let mut samples = Vec::new();
    let (mut cfib_roots, mut cfib_inside) = (Vec::new(), Vec::new());
    let mut sample_roots: Vec<Vec<RealAlg>> = Vec::new();
    cert.strips = strips.iter().map(|st| (st.0, st.1)).collect();
    for (_, _, q) in &strips {
        let roots = isolate(&g.at_x(q))?;
        let mut vid = Vec::new();
        let mut kept_roots = Vec::new();
        for mut r in roots.clone() {
            // Inside test, exact: ymin < v < ymax and xmin < q + s·v < xmax.
            let mut inside =
                r.cmp_q(&fr.ymin) == Ordering::Greater && r.cmp_q(&fr.ymax) == Ordering::Less;
            if inside && s != 0 {
                let (mut a, mut b) = ((&fr.xmin - q) / sq, (&fr.xmax - q) / sq);
                if s < 0 {
                    std::mem::swap(&mut a, &mut b);
                }
                inside = r.cmp_q(&a) == Ordering::Greater && r.cmp_q(&b) == Ordering::Less;
            }
            if inside {
                r.refine_to(&pow2q(-40));
                vid.push(Some(verts.len() as u32));
                verts.push(unshear(q_to_f64(q), r.to_f64()));
                labels.push(Label::Regular);
            } else {
                vid.push(None);
            }
            cfib_roots.push(CertInterval::new(&r.lo, &r.hi));
            cfib_inside.push(inside);
            kept_roots.push(r);
        }
        sample_roots.push(kept_roots);
        cert.fibres.push(CertFibre {
            q: q.to_string(),
            roots: std::mem::take(&mut cfib_roots),
            inside: std::mem::take(&mut cfib_inside),
        });
        out.fibre_counts.push(roots.len());
        samples.push(Sample {
            count: roots.len(),
            vid,
        });
    }
    // Event fibres.
    let mut segs: Vec<[u32; 2]> = Vec::new();
    // Per event, per fibre root: (vertex id when kept, branches left, branches right).
    let mut ev_vertices: Vec<Vec<(Option<u32>, usize, usize)>> = Vec::new();
    let mut ev_boxes: Vec<Vec<(BigRational, BigRational)>> = Vec::new();
    // Per event: per root (special, on the boundary), and β = num/den when generic.
    #[allow(clippy::type_complexity)]
    let mut ev_kinds: Vec<(Vec<(bool, bool)>, Option<(UPoly, UPoly)>)> = Vec::new();
    #[allow(clippy::type_complexity)]
    let mut ev_snaps: Vec<Vec<Option<(BigRational, BigRational)>>> = Vec::new();
    let gx = g.dx();
    for (ei, ev) in events.iter_mut().enumerate() {
        let left = strips.iter().position(|st| st.1 == Some(ei));
        let right = strips.iter().position(|st| st.0 == Some(ei));
        let n_l = left.map(|i| samples[i].count);
        let n_r = right.map(|i| samples[i].count);
        let n_any = n_l.or(n_r).unwrap_or(0);
        let mut info = EventInfo {
            u_lo: ev.u.lo.to_string(),
            u_hi: ev.u.hi.to_string(),
            critical: ev.critical,
            boundary: ev.side || !ev.bpoints.is_empty(),
            k: None,
            m: n_any,
            multiplicity: None,
            generic: None,
            real_multiple_roots: None,
            n_left: n_l.unwrap_or(0),
            n_right: n_r.unwrap_or(0),
            branches: None,
            label: None,
            inside: None,
        };
        let mut cev = CertEvent {
            poly: poly_strings(&ev.u.p),
            lo: String::new(),
            hi: String::new(),
            critical: ev.critical,
            side: ev.side,
            bpoints: ev
                .bpoints
                .iter()
                .map(|b| [b.v0.to_string(), b.v1.to_string()])
                .collect(),
            signs: Vec::new(),
            k: None,
            m: n_any,
            generic: None,
            r_signs: Vec::new(),
            r: None,
            roots: Vec::new(),
            excluded: Vec::new(),
            branches: None,
            label: None,
        };
        let mut num = UPoly::zero();
        let mut den = UPoly::zero();
        let mut m = n_any;
        // The multiple root: generic (β = num/den), clustered (r = 1), none (phantom).
        let mut generic = false;
        let mut cluster = false;
        if let Some(c) = &ev.crit {
            let k = c.k;
            info.k = Some(k);
            cev.k = Some(k);
            cev.signs = c.signs.clone();
            m = c.m;
            info.m = m;
            cev.m = m;
            generic = c.generic;
            info.generic = Some(generic);
            cev.generic = Some(generic);
            if generic {
                num = sk_cache[&k][k - 1].neg();
                den = sres[k].scale(&BigInt::from(k));
                info.multiplicity = Some(k + 1);
            } else {
                info.real_multiple_roots = c.r;
                cev.r = c.r;
                cev.r_signs = c.r_signs.clone();
                cluster = c.r == Some(1);
            }
        }
        let special = Special {
            num: &num,
            den: &den,
            k: info.k.unwrap_or(1),
        };
        let mode = if generic {
            Mode::Generic(&special)
        } else if cluster {
            Mode::Cluster
        } else {
            Mode::Plain
        };
        let sp = if generic { Some(&special) } else { None };
        let mut roots: Vec<FRoot> = if ev.u.is_exact() && !ev.critical {
            let qv = ev.u.lo.clone();
            isolate(&g.at_x(&qv))?
                .into_iter()
                .map(|r| FRoot {
                    lo: r.lo,
                    hi: r.hi,
                    special: false,
                    boundary: false,
                    snap: None,
                })
                .collect()
        } else if m == 0 {
            Vec::new()
        } else {
            let (r, ex) = fibre_roots(g, &gy, &mut ev.u, m, mode)?;
            cev.excluded = ex.iter().map(|(a, b)| CertInterval::new(a, b)).collect();
            r
        };
        if roots.len() != m {
            return Err(Error::Param(format!(
                "internal: fibre over u ≈ {:.6} has {} roots, expected {m}",
                ev.u.to_f64(),
                roots.len()
            )));
        }
        // Branch counts.
        let mut bl = vec![1usize; roots.len()];
        let mut br = vec![1usize; roots.len()];
        let spi = roots.iter().position(|r| r.special);
        if let Some(i) = spi {
            let (Some(nl), Some(nr)) = (n_l, n_r) else {
                return Err(Error::Param(
                    "internal: critical event without two strips".into(),
                ));
            };
            let (al, ar) = (
                nl as isize - (m as isize - 1),
                nr as isize - (m as isize - 1),
            );
            if al < 0 || ar < 0 {
                return Err(Error::Param(format!(
                    "internal: inconsistent branch counts at u ≈ {:.6}",
                    ev.u.to_f64()
                )));
            }
            bl[i] = al as usize;
            br[i] = ar as usize;
            info.branches = Some((bl[i], br[i]));
            cev.branches = info.branches;
        } else if ev.critical && (n_l != Some(m) || n_r != Some(m)) {
            return Err(Error::Param(format!(
                "internal: phantom event at u ≈ {:.6} with {m} roots between fibres of {n_l:?} and {n_r:?}",
                ev.u.to_f64()
            )));
        }
        // Boundary points: which root each lies on.
        for bp in ev.bpoints.clone() {
            let mut guard = 0;
            loop {
                guard += 1;
                if guard > 400 {
                    return Err(Error::TooLarge(
                        "locating a boundary crossing: refinement budget exhausted".into(),
                    ));
                }
                let vb = Ri::pt(&bp.v0).add(
                    &Ri {
                        lo: ev.u.lo.clone(),
                        hi: ev.u.hi.clone(),
                    }
                    .mul(&Ri::pt(&bp.v1)),
                );
                let hits: Vec<usize> = (0..roots.len())
                    .filter(|&i| !(vb.hi < roots[i].lo || vb.lo > roots[i].hi))
                    .collect();
                let strictly_in = |r: &FRoot| {
                    (vb.lo > r.lo && vb.hi < r.hi)
                        || (r.lo == r.hi && vb.lo == vb.hi && vb.lo == r.lo)
                };
                if hits.len() == 1 && strictly_in(&roots[hits[0]]) {
                    let i = hits[0];
                    if roots[i].special {
                        if !generic {
                            return Err(boundary_error(
                                "a side of the domain passes near a multiple root of a non-generic fibre",
                            ));
                        }
                        // Is the crossing exactly β? (v0 + v1·x)·den − num at α.
                        let lin = super::bipoly::q_to_primitive(&[bp.v0.clone(), bp.v1.clone()]);
                        // q_to_primitive scales by a positive factor: zero test unaffected.
                        if ev.u.is_root_of(&lin.mul(&den).sub(&num)) {
                            return Err(boundary_error(
                                "a side of the domain passes through a singular point or a vertical tangent of the curve",
                            ));
                        }
                    } else {
                        if roots[i].boundary {
                            return Err(boundary_error(
                                "the curve passes through a corner of the domain",
                            ));
                        }
                        roots[i].boundary = true;
                        roots[i].snap = Some(bp.clone());
                        break;
                    }
                }
                shrink(g, &mut ev.u, &mut roots, sp);
            }
        }
        // Vertices: keep those inside or on the boundary.
        let mut evv = Vec::new();
        let mut keeps = Vec::new();
        for i in 0..roots.len() {
            let mut keep = None;
            if roots[i].boundary {
                keep = Some(true);
            } else if ev.side {
                // A vertical side fibre (s = 0, u = xmin or xmax exactly): roots strictly
                // within (ymin, ymax). The interval is one of isolate()'s on g(u, ·): an
                // open interval may start at an exact root listed before it (0, or a
                // Descartes midpoint), which its own polynomial has divided out. The
                // number is rebuilt with those ends divided out again and the isolation
                // verified (with the full square-free polynomial, bisect and cmp_q read
                // the root's side from p(lo) = 0 and moved to that other root).
                if !ev.u.is_exact() {
                    return Err(Error::Param(
                        "internal: a vertical side event at an irrational x".into(),
                    ));
                }
                let Some(mut r) =
                    RealAlg::checked(&g.at_x(&ev.u.lo), roots[i].lo.clone(), roots[i].hi.clone())
                else {
                    return Err(Error::Param(format!(
                        "internal: root {i} on the vertical side x = {} is not isolated by [{}, {}]",
                        ev.u.lo, roots[i].lo, roots[i].hi
                    )));
                };
                let (a, b) = (r.cmp_q(&fr.ymin), r.cmp_q(&fr.ymax));
                if a == Ordering::Equal || b == Ordering::Equal {
                    return Err(boundary_error(
                        "the curve passes through a corner of the domain",
                    ));
                }
                keep = Some(a == Ordering::Greater && b == Ordering::Less);
                if keep == Some(true) {
                    // The vertex's coordinate is the interval's midpoint.
                    r.refine_to(&pow2q(-40));
                    roots[i].boundary = true;
                }
                roots[i].lo = r.lo;
                roots[i].hi = r.hi;
            }
            let mut guard = 0;
            while keep.is_none() {
                guard += 1;
                if guard > 400 {
                    return Err(Error::TooLarge(
                        "deciding whether an event point is inside the domain: refinement budget exhausted".into(),
                    ));
                }
                let ui = Ri {
                    lo: ev.u.lo.clone(),
                    hi: ev.u.hi.clone(),
                };
                let vi = Ri {
                    lo: roots[i].lo.clone(),
                    hi: roots[i].hi.clone(),
                };
                keep = fr.classify(&ui, &vi);
                if keep.is_none() {
                    shrink(g, &mut ev.u, &mut roots, sp);
                }
            }
            keeps.push(keep == Some(true));
        }
        for i in 0..roots.len() {
            let keep = keeps[i];
            let label = if roots[i].boundary {
                Label::Boundary
            } else if roots[i].special {
                let (a, b) = (bl[i], br[i]);
                if a == 0 && b == 0 {
                    Label::Isolated
                } else if generic {
                    // Singular iff g_u(α, β(α)) = 0.
                    if is_root_at_beta(&ev.u, &gx, &num, &den, d) {
                        Label::Singular
                    } else if a == 0 || b == 0 {
                        Label::XExtreme
                    } else {
                        // Smooth with a vertical tangent and branches on both sides.
                        Label::Regular
                    }
                } else if a + b != 2 {
                    // A smooth point has exactly two branches.
                    Label::Singular
                } else {
                    Label::Multiple
                }
            } else {
                Label::Regular
            };
            if roots[i].special {
                info.label = Some(label);
                info.inside = Some(keep);
                cev.label = Some(label);
            }
            if keep {
                let u = ev.u.to_f64();
                let v = q_to_f64(&((&roots[i].lo + &roots[i].hi) / two()));
                evv.push((Some(verts.len() as u32), bl[i], br[i]));
                let mut p = unshear(u, v);
                if let Some(bp) = &roots[i].snap {
                    // Exactly on the side: y = v0, or x = c with v = v0 + v1·u.
                    let vv = q_to_f64(&bp.v0) + q_to_f64(&bp.v1) * u;
                    p = unshear(u, vv);
                    if bp.v1.is_zero() {
                        p[1] = q_to_f64(&bp.v0);
                    } else {
                        p[0] = q_to_f64(&(&bp.v0 * sq));
                    }
                }
                verts.push(p);
                labels.push(label);
            } else {
                evv.push((None, bl[i], br[i]));
            }
            cev.roots.push(CertRoot {
                lo: roots[i].lo.to_string(),
                hi: roots[i].hi.to_string(),
                special: roots[i].special,
                boundary: roots[i].boundary,
                keep,
                left: bl[i],
                right: br[i],
            });
        }
        ev_boxes.push(roots.iter().map(|r| (r.lo.clone(), r.hi.clone())).collect());
        ev_snaps.push(
            roots
                .iter()
                .map(|r| r.snap.as_ref().map(|b| (b.v0.clone(), b.v1.clone())))
                .collect(),
        );
        ev_kinds.push((
            roots.iter().map(|r| (r.special, r.boundary)).collect(),
            generic.then(|| (num.clone(), den.clone())),
        ));
        cev.lo = ev.u.lo.to_string();
        cev.hi = ev.u.hi.to_string();
        cert.events.push(cev);
        ev_vertices.push(evv);
        out.events.push(info);
    }
    // Connection: the i-th arc from the bottom of each strip joins the expanded
    // event vertices on both sides.
    for (si, (le, re, _)) in strips.iter().enumerate() {
        let smp = &samples[si];
        let expand = |e: usize, left_side: bool| -> Vec<Option<u32>> {
            let mut v = Vec::new();
            for &(id, bl, br) in &ev_vertices[e] {
                let n = if left_side { br } else { bl };
                for _ in 0..n {
                    v.push(id);
                }
            }
            v
        };
        for (side, e) in [(true, le), (false, re)] {
            let Some(e) = e else {
                if smp.vid.iter().any(|v| v.is_some()) {
                    return Err(Error::Param(
                        "internal: an arc inside the domain reaches the domain's extreme corner"
                            .into(),
                    ));
                }
                continue;
            };
            let ends = expand(*e, side);
            if ends.len() != smp.count {
                return Err(Error::Param(format!(
                    "internal: {} arcs meet the event fibre but the strip has {}",
                    ends.len(),
                    smp.count
                )));
            }
            for (i, end) in ends.iter().enumerate() {
                if let (Some(a), Some(b)) = (smp.vid[i], end) {
                    segs.push(if side { [*b, a] } else { [a, *b] });
                } else if smp.vid[i].is_some() {
                    return Err(Error::Param(
                        "internal: an arc inside the domain ends at a point outside".into(),
                    ));
                }
            }
        }
    }
    out.curve = Curve2 {
        vertices: verts,
        segments: segs,
    };
    out.labels = labels;
    cert.vertices = out.curve.vertices.clone();
    cert.segments = out.curve.segments.clone();
    out.cert = cert;
    out.arcs = Some(Box::new(super::tolerance::ArcData {
        g: g.clone(),
        s,
        events: events
            .iter()
            .zip(ev_boxes)
            .zip(&ev_vertices)
            .zip(ev_kinds)
            .zip(ev_snaps)
            .map(
                |((((e, boxes), vv), (kinds, beta)), snap)| super::tolerance::EventArcs {
                    snap,
                    u: e.u.clone(),
                    boxes,
                    special: kinds.iter().map(|k| k.0).collect(),
                    boundary: kinds.iter().map(|k| k.1).collect(),
                    beta,
                    vid: vv.iter().map(|v| v.0).collect(),
                    left: vv.iter().map(|v| v.1).collect(),
                    right: vv.iter().map(|v| v.2).collect(),
                },
            )
            .collect(),
        strips: strips
            .iter()
            .zip(sample_roots)
            .zip(&samples)
            .map(|(((l, r, q), roots), smp)| super::tolerance::StripArcs {
                left: *l,
                right: *r,
                q: q.clone(),
                roots,
                vid: smp.vid.clone(),
            })
            .collect(),
    }));
    Ok(out)
}

/// The key of the re-checkable certificate in the mesher's stats map (the CLI writes
/// it to the `--certificate` file and removes it from the report).
pub const CERT_STATS_KEY: &str = "recheckable_certificate";

/// Counts of what the sweep found (the `stats` of the report).
#[derive(Clone, Debug, Serialize)]
pub struct SweepStats {
    pub shear: i64,
    pub rejected_shears: Vec<(i64, String)>,
    pub degree: usize,
    pub resultant_degree: isize,
    pub resultant_bits: u64,
    pub events: usize,
    pub critical_events: usize,
    pub boundary_events: usize,
    pub singular_points: usize,
    pub isolated_points: usize,
    pub x_extreme_points: usize,
    pub fibre_counts: Vec<usize>,
    pub event_list: Vec<EventInfo>,
    /// The extra fibres of `--set tolerance` and the certified deviation bound.
    pub tolerance: Option<super::tolerance::ToleranceReport>,
}

impl Mesher for Sweep {
    fn name(&self) -> &'static str {
        "sweep"
    }
    fn dim(&self) -> usize {
        2
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, _p: &dyn Progress) -> Result<MeshOutput> {
        crate::mesher::check_input(f, domain, 2, "sweep")?;
        let e = f.expression().ok_or_else(|| {
            Error::Param(
                "the sweep needs f as a formula (a polynomial); this oracle has none".into(),
            )
        })?;
        let poly = super::bipoly::from_expr(e)?;
        let r = analyse(&poly, domain, &self.params)?;
        let count = |l: Label| r.labels.iter().filter(|&&x| x == l).count();
        let stats = SweepStats {
            shear: r.shear,
            rejected_shears: r.rejected_shears.clone(),
            degree: r.degree,
            resultant_degree: r.resultant_degree,
            resultant_bits: r.resultant_bits,
            events: r.events.len(),
            critical_events: r.events.iter().filter(|e| e.critical).count(),
            boundary_events: r.events.iter().filter(|e| e.boundary).count(),
            singular_points: count(Label::Singular),
            isolated_points: count(Label::Isolated),
            x_extreme_points: count(Label::XExtreme),
            fibre_counts: r.fibre_counts.clone(),
            event_list: r.events.clone(),
            tolerance: r.tolerance.clone(),
        };
        let mut d = *domain;
        d.min[2] = 0.0;
        d.max[2] = 0.0;
        let between = match &r.tolerance {
            Some(t) if t.not_reached.is_empty() => format!(
                "{} extra rational fibres; every arc proven within {:.3e} of its polyline (curve to polyline, interval enclosures of each arc between fibres)",
                t.extra_fibres, t.certified_bound
            ),
            Some(t) => format!(
                "{} extra rational fibres; {} of {} arcs proven within the tolerance {:.3e} (bound {:.3e}), the other {} not certified",
                t.extra_fibres,
                t.arcs_within_tolerance,
                t.arcs,
                t.tolerance,
                t.certified_bound,
                t.not_reached.len()
            ),
            None => "geometry between fibres not certified".to_string(),
        };
        let claim = Claim::Isotopic {
            inside: d,
            theorem: format!(
                "exact: González-Vega–Necula sweep in the frame x + {}·y (unsheared, determinant 1), resultant and Sturm–Habicht signs, Descartes isolation, real-only genericity test, re-checkable certificate (certmesh check-curve); straight segments between fibres ({between})",
                r.shear
            ),
            generic_position: false,
        };
        let mut stats = crate::mesher::stats_map(&stats);
        stats.insert(
            CERT_STATS_KEY.into(),
            serde_json::to_value(&r.cert).expect("certificate serializes"),
        );
        Ok(MeshOutput {
            mesh: Mesh::Curve(r.curve),
            certificate: Certificate::certified(vec![claim]),
            stats,
            angles: None,
        })
    }
}
