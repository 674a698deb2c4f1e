//! Certified critical points by interval Krawczyk subdivision, their Morse indices
//! from a certified Hessian inertia, and a certified Euler characteristic by Morse
//! counting: the oracle operation behind restricted-Delaunay seeds (one seed at each
//! critical point of a generic height function on S reaches every component) and the
//! Morse census.
//!
//! Two problems, one branch-and-bound (`search.rs`):
//! * [`critical_points_of_f`]: ∇f = 0 in a box (Jacobian: the Hessian);
//! * [`critical_points_on_surface`]: critical points of the height h(x) = ⟨n, x⟩ on
//!   S = {f = 0}, i.e. F(x) = (f, ∇f·e₁, ∇f·e₂) = 0 with e₁, e₂ ⊥ n (Jacobian rows ∇f,
//!   H e₁, H e₂). This is the system f = 0, f_u = f_v = 0 in coordinates (u, v, w)
//!   rotated so that n is the w axis, written without rotating the box (rotating a
//!   box inflates it).
//!
//! **The frame.** From a unit direction d (default [`DEFAULT_DIRECTION`]) we build
//! float vectors e₁ ⊥ d, e₂ = d × e₁. They are used as exact reals; the height whose
//! critical points are computed is h(x) = ⟨n, x⟩ with n = e₁ × e₂ *exactly* (enclosed
//! in intervals), within a few ulps of d. Then ∇f·e₁ = ∇f·e₂ = 0 ⇔ ∇f ∥ n exactly,
//! and the tangent plane at a critical point is exactly span(e₁, e₂).
//!
//! **Per box X** (each proof needs f C^∞ on a neighbourhood of X, asked of
//! [`Implicit::regularity`]; a box that is not `Smooth` is never certified, only
//! excluded by 0 ∉ □f when f is at least continuous there, for the surface problem):
//! 1. exclusion: 0 ∉ □Fᵢ(X) for some i, natural or centred form Fᵢ(m) + □J_i(X)(X − m);
//! 2. the Krawczyk operator K(X) = m − Y F(m) + (I − Y J(X))(X − m) with F(m) enclosed
//!    on the point box, Y the float inverse of mid J(X) ([`linalg::krawczyk`]):
//!    K(X) ∩ X = ∅ excludes X; K(X) ⊂ int X proves exactly one zero in X, then
//!    shrunk by iterating X ← K(X) ∩ X; otherwise X is replaced by K(X) ∩ X (every
//!    zero of X lies there) when that shrinks it, else bisected on its widest side;
//! 3. a zero on a face between two boxes is never inside either, so once the
//!    operator contracts (‖I − Y J(X)‖ < ½) a float Newton iterate x̃ from m is tried:
//!    if K ⊂ int X' for X' = x̃ ± max width(X), X' is an isolating box and every later
//!    box inside X' is "covered" (its zeros, if any, are X''s one zero).
//!
//! Two isolating boxes A, B with enclosures A* ⊂ A, B* ⊂ B of their zeros hold the
//! same zero if A* ⊂ B (B's zero is unique), different ones if A* ∩ B* = ∅; anything
//! else is reported as undecided. A zero whose enclosure straddles the domain's
//! boundary is undecided too. The search is `complete` when every box was excluded,
//! covered or isolated, and then the list of points is every critical point of the
//! domain, each exactly once.
//!
//! **Morse index of f** at x* in the enclosure E: the interval Hessian over E encloses
//! H_f(x*); [`linalg::inertia`] (Jacobi's sign rule on leading principal minors, every
//! symmetric permutation tried) certifies its number of negative eigenvalues.
//!
//! **Morse index of the height on S.** Let x* ∈ S with ∇f(x*) = λ n (λ ≠ 0 since the
//! Jacobian row ∇f of an isolated zero is non-zero), and γ a curve on S with γ(0) = x*,
//! γ'(0) = t ∈ T = span(e₁, e₂). Differentiating f(γ(s)) = 0 twice:
//! ⟨∇f, γ''⟩ + tᵀ H_f t = 0, so (h∘γ)''(0) = ⟨n, γ''(0)⟩ = −(1/λ) tᵀ H_f t.
//! (The γ''-term of a general height would be ⟨∇h, γ''⟩ and vanishes at a critical
//! point only after this substitution: this is the Lagrange multiplier μ = 1/λ of
//! h − μ f, whose Hessian −μ H_f is the second fundamental form of the height.)
//! In the basis E = [e₁ e₂] the Hessian of h|S is −(1/λ) Eᵀ H_f E, and its inertia
//! (Sylvester's law: independent of the basis and of positive scaling) is that of
//! −sign(λ)·Eᵀ H_f E, with sign(λ) = sign(∇f·n). In rotated coordinates with n = e_w:
//! −(1/f_w)·[[f_uu, f_uv], [f_uv, f_vv]]. Example: the unit sphere at its top point
//! d: ∇f = 2d (λ = 2), EᵀHE = 2I, so −I: index 2, a maximum. Checked against finite
//! differences of the height on a local graph of S in `tests/critical.rs`.
//!
//! **Euler characteristic** ([`euler_characteristic`]): if the surface search is
//! complete, every critical point has a certified index and 0 ∉ □f on the six faces
//! of the domain (subdivided), then S ∩ D is a compact surface without boundary
//! (f continuous on D, S away from ∂D), regular (a point of S with ∇f = 0 solves the
//! system, and every solution was isolated with a non-singular Jacobian, whose first
//! row is ∇f), and h|S is a Morse function, so χ(S) = Σ (−1)^index (Milnor, *Morse
//! Theory*, 1963, §5, Thm 5.2 and its corollary; the chapter "Meshing of Surfaces",
//! Boissonnat et al., 2007, §1.5).
//!
//! **χ({f ≤ 0}) and χ(S) from the critical points of f** ([`sublevel_euler_characteristic`],
//! `sublevel.rs`): Σ (−1)^index over the critical points with f < 0, when f > 0 is proven
//! on ∂D and f is proven Morse on {f ≤ 0}; then χ(S) = 2·χ({f ≤ 0}).
use crate::implicit::{IBox, Implicit};
use inari::Interval;
use linalg::pt;
use search::solve;
use serde::{Deserialize, Serialize};
use systems::{Gradient, Height};

pub mod linalg;
mod search;
mod sublevel;
mod systems;

pub use sublevel::{
    boundary_sign, from_gradient, side, sublevel_euler_characteristic, Side, SublevelReport,
};
pub use systems::{height_hessian_on_surface, Frame};

/// The default height direction, (1/π, 1/e, 1/√2) before normalisation (the frame
/// normalises it). Generic for the catalog's symmetric surfaces: no coordinate plane
/// or diagonal contains it and its components are distinct, so no symmetry of the
/// torus, tanglecube or genus-2 surface fixes it (an axis direction gives circles of
/// critical points on a torus of revolution).
pub const DEFAULT_DIRECTION: [f64; 3] = [
    std::f64::consts::FRAC_1_PI,
    0.367_879_441_171_442_3,
    std::f64::consts::FRAC_1_SQRT_2,
];

/// A box as bounds (serialisable).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bx {
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

impl Bx {
    pub fn new(lo: [f64; 3], hi: [f64; 3]) -> Self {
        Bx { lo, hi }
    }
    pub fn from_ibox(b: &IBox) -> Self {
        Bx {
            lo: b.map(|x| x.inf()),
            hi: b.map(|x| x.sup()),
        }
    }
    pub fn to_ibox(&self) -> IBox {
        [0, 1, 2].map(|k| Interval::try_from((self.lo[k], self.hi[k])).unwrap_or(Interval::ENTIRE))
    }
    pub fn contains(&self, p: [f64; 3]) -> bool {
        (0..3).all(|k| self.lo[k] <= p[k] && p[k] <= self.hi[k])
    }
    pub fn mid(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| 0.5 * (self.lo[k] + self.hi[k]))
    }
    pub fn max_width(&self) -> f64 {
        (0..3).map(|k| self.hi[k] - self.lo[k]).fold(0.0, f64::max)
    }
}

impl From<crate::kernel::geom::Aabb> for Bx {
    fn from(a: crate::kernel::geom::Aabb) -> Self {
        Bx::new(a.min, a.max)
    }
}

/// Limits of the search.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Budget {
    /// Bisections along one path (one side per bisection).
    pub max_depth: u32,
    /// Boxes processed in all.
    pub max_boxes: usize,
    /// Depth at which a box where f is not proven smooth is reported undecided
    /// instead of being bisected further (localising a pole plane costs 4ᵏ boxes).
    pub nonsmooth_depth: u32,
    /// Krawczyk iterations that shrink an isolating box.
    pub shrink_steps: u32,
    /// Wall-clock limit of the search, in seconds (none by default: the box budget
    /// bounds it; the command line's `morse --time-limit` sets one). The boxes left
    /// when it passes are reported undecided ([`Reason::TimeLimit`]).
    #[serde(default)]
    pub time_limit: Option<f64>,
}

impl Default for Budget {
    fn default() -> Self {
        Budget {
            max_depth: 60,
            max_boxes: 400_000,
            nonsmooth_depth: 12,
            shrink_steps: 12,
            time_limit: None,
        }
    }
}

/// Why a region is undecided.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Reason {
    /// The depth limit was reached with neither exclusion nor isolation.
    DepthLimit,
    /// The depth limit was reached and 0 ∈ □det J(X): the box may hold a degenerate
    /// (non-isolated or non-Morse) critical point.
    PossiblyDegenerate,
    /// The box budget ran out before this box was processed.
    Budget,
    /// The time limit passed before this box was processed.
    TimeLimit,
    /// f is continuous but not proven differentiable on the box.
    NotDifferentiable,
    /// f is not proven continuous (or defined) on the box: a pole, a domain boundary.
    NotContinuous,
    /// An isolated zero whose enclosure meets the domain's boundary.
    OnDomainBoundary,
    /// Two isolating boxes whose zeros could be neither identified nor separated.
    Ambiguous,
    /// The oracle's interval methods are not rigorous ([`Implicit::is_rigorous`]).
    NotRigorous,
    /// Not a surface f(x, y, z) (curves are not supported yet), or the domain is not
    /// a finite, non-degenerate box.
    Unsupported,
}

/// The Morse index of an isolated critical point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "kebab-case")]
pub enum MorseIndex {
    /// Number of negative eigenvalues of the (restricted) Hessian, certified.
    Certified { index: u8 },
    /// 0 ∈ □det of the (restricted) Hessian over the enclosure: possibly degenerate.
    PossiblyDegenerate,
    /// The determinant excludes 0 but no ordering of the minors decided the signs
    /// (or the sign of ∇f·n was not decided).
    Undecided,
}

impl MorseIndex {
    pub fn index(&self) -> Option<u8> {
        match self {
            MorseIndex::Certified { index } => Some(*index),
            _ => None,
        }
    }
}

/// One isolated critical point.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CriticalPoint {
    /// A small box proven to contain the critical point (iterated Krawczyk).
    pub enclosure: Bx,
    /// The box in which it is proven the *only* critical point.
    pub isolating: Bx,
    /// The midpoint of the enclosure.
    pub point: [f64; 3],
    /// An enclosure of the critical value: f (critical points of f) or the height
    /// ⟨n, x⟩ (critical points on S).
    pub value: [f64; 2],
    pub index: MorseIndex,
}

/// A region where the search decided nothing.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct UndecidedBox {
    pub region: Bx,
    pub reason: Reason,
    pub depth: u32,
}

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Stats {
    /// Boxes processed.
    pub boxes: usize,
    /// Boxes excluded (no critical point).
    pub excluded: usize,
    /// Boxes inside an isolating box found earlier.
    pub covered: usize,
    pub krawczyk_tests: usize,
    /// Isolating boxes found around a float Newton iterate.
    pub inflations: usize,
    pub max_depth: u32,
    pub millis: f64,
}

/// Which system was solved.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Problem {
    /// ∇f = 0.
    Gradient,
    /// Critical points of ⟨n, x⟩ on f = 0.
    Height {
        /// The requested unit direction d.
        direction: [f64; 3],
        /// The tangent frame e₁, e₂ (floats, used as exact reals).
        e1: [f64; 3],
        e2: [f64; 3],
        /// The effective height direction n = e₁ × e₂ (float midpoint; within a few
        /// ulps of d).
        normal: [f64; 3],
    },
}

/// The result of a search.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CriticalReport {
    pub problem: Problem,
    pub domain: Bx,
    /// True when every box was excluded, covered or isolated: `points` is then every
    /// critical point in the domain, each once.
    pub complete: bool,
    pub points: Vec<CriticalPoint>,
    pub undecided: Vec<UndecidedBox>,
    pub stats: Stats,
}

impl CriticalReport {
    /// Counts of certified indices 0, 1, 2, 3, and of points without one.
    pub fn index_counts(&self) -> ([usize; 4], usize) {
        let mut c = [0; 4];
        let mut none = 0;
        for p in &self.points {
            match p.index.index() {
                Some(i) => c[i as usize] += 1,
                None => none += 1,
            }
        }
        (c, none)
    }
}

// ---------------------------------------------------------------------------------
// Public API.

/// Every critical point of f (∇f = 0) in `domain`, each in an isolating box with its
/// certified Morse index, or the undecided regions (see the module doc).
pub fn critical_points_of_f(f: &dyn Implicit, domain: Bx, budget: Budget) -> CriticalReport {
    let sys = Gradient { f };
    solve(&sys, Problem::Gradient, domain, budget)
}

/// Every critical point of the height ⟨n, x⟩ on S = {f = 0} ∩ `domain`, n = e₁ × e₂
/// from the frame of `direction` (`None`: [`DEFAULT_DIRECTION`]), with the Morse
/// index of the height on S. A zero or non-finite direction falls back to the default.
pub fn critical_points_on_surface(
    f: &dyn Implicit,
    domain: Bx,
    direction: Option<[f64; 3]>,
    budget: Budget,
) -> CriticalReport {
    let frame = direction
        .and_then(Frame::new)
        .or_else(|| Frame::new(DEFAULT_DIRECTION))
        .expect("the default direction is a unit vector");
    let sys = Height {
        f,
        frame,
        e1: frame.e1.map(pt),
        e2: frame.e2.map(pt),
        n: frame.normal(),
    };
    let problem = Problem::Height {
        direction: frame.d,
        e1: frame.e1,
        e2: frame.e2,
        normal: sys.n.map(|x| x.mid()),
    };
    solve(&sys, problem, domain, budget)
}

/// The Euler characteristic of S = {f = 0} ∩ `domain` by Morse counting of a height.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EulerReport {
    /// χ(S), present only when certified.
    pub chi: Option<i64>,
    /// Why χ is not certified (`None` when it is).
    pub reason: Option<String>,
    /// Certified minima, saddles, maxima.
    pub minima: usize,
    pub saddles: usize,
    pub maxima: usize,
    /// 0 ∉ □f proven on the six faces of the domain.
    pub boundary_clear: bool,
    pub surface: CriticalReport,
}

/// χ(S) = #min − #saddle + #max of the height on S, certified only if the search is
/// complete, every index is certified and S does not meet ∂domain (module doc).
pub fn euler_characteristic(
    f: &dyn Implicit,
    domain: Bx,
    direction: Option<[f64; 3]>,
    budget: Budget,
) -> EulerReport {
    let surface = critical_points_on_surface(f, domain, direction, budget);
    let ([minima, saddles, maxima, _], no_index) = surface.index_counts();
    let boundary_clear = boundary_clear(
        f,
        domain,
        2 * budget.nonsmooth_depth.max(8),
        budget.max_boxes,
    );
    let reason = if !f.is_rigorous() {
        Some("the oracle's interval methods are not rigorous".to_string())
    } else if !boundary_clear {
        Some("the surface meets the domain boundary (or 0 ∈ □f on a boundary face could not be excluded)".to_string())
    } else if !surface.complete {
        let mut reasons: Vec<String> = surface
            .undecided
            .iter()
            .map(|u| format!("{:?}", u.reason))
            .collect();
        reasons.sort();
        reasons.dedup();
        Some(format!(
            "the critical-point search is incomplete: {} undecided boxes ({})",
            surface.undecided.len(),
            reasons.join(", ")
        ))
    } else if no_index > 0 {
        Some(format!(
            "{no_index} critical points without a certified index (possibly degenerate)"
        ))
    } else {
        None
    };
    let chi = reason
        .is_none()
        .then_some(minima as i64 - saddles as i64 + maxima as i64);
    EulerReport {
        chi,
        reason,
        minima,
        saddles,
        maxima,
        boundary_clear,
        surface,
    }
}

/// Is 0 ∉ □f proven on the six faces of the domain (each face subdivided up to
/// `max_depth` bisections, `max_boxes` boxes in all), with f proven continuous there?
/// The same search as [`boundary_sign`], which also says which sign.
pub fn boundary_clear(f: &dyn Implicit, domain: Bx, max_depth: u32, max_boxes: usize) -> bool {
    boundary_sign(f, domain, max_depth, max_boxes).is_some()
}
