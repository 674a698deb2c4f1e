//! The chapter's remedy for degenerate critical points, as an explicit, reported
//! transformation (the chapter "Meshing of Surfaces", §1.5.1: "multiply f by a + ‖x − b‖").
//!
//! g(x) = f(x)·h(x) with h > 0 everywhere, so g has the sign of f at every point:
//! **{g ≤ 0} = {f ≤ 0} and g = 0 ⟺ f = 0**, and on f = 0, ∇g = h·∇f, so the zero set
//! is regular where f's is. Everything Morse counting proves about the sublevel set
//! {g ≤ 0} (its χ, hence χ(S) = 2·χ({f ≤ 0})) is therefore proven about f's. What
//! changes is every *other* level set, and the critical points: a degenerate critical
//! set of f inside {f < 0} (the torus's circle of minima, the superquadric's flat
//! minimum) generically breaks up into isolated, non-degenerate critical points of g
//! (on the torus, ∇f has no component along the circle, so ∇g = h∇f + f∇h vanishes on
//! it only where ∇h is normal to the circle: the nearest and the farthest point of
//! the circle from b, a saddle and a minimum).
//!
//! Two forms of h (`--remedy KIND[:A[:BX,BY,BZ]]` of `certmesh morse`,
//! `--set remedy=...` of `--algo stander-hart`):
//! * `chapter`: h = a + ‖x − b‖, as the chapter writes it. It is **not differentiable
//!   at b**: every box containing b is reported `Continuous`, never smooth, so the
//!   interval Hessian cannot certify a critical point there; the census is certified
//!   only if the boxes around b are excluded by the sign (b in {f > 0}) — otherwise the
//!   report says the search was blocked there.
//! * `smooth`: h = a + ‖x − b‖², C^∞ everywhere, our variant with the same effect on the
//!   zero set and the sublevel set. This is what the certified census uses by default.
//!
//! a > 0 is required (else h may vanish, and g = 0 would gain the sphere ‖x − b‖ = √−a…
//! or b itself): the transformation is refused otherwise. The default b is a fixed
//! generic point off the catalog's symmetry axes (relative to the domain), the default
//! a = 1. Tests: `tests/morse.rs` (the torus, thin torus and superquadric certified
//! through the remedy; g's sign equals f's on random points; the chapter's form
//! refused near b).
use crate::error::{Error, Result};
use crate::implicit::critical::Bx;
use crate::implicit::number::{Dual, Hyper, Num};
use crate::implicit::{IBox, Implicit, Regularity};
use inari::Interval;
use serde::Serialize;

/// Which h.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RemedyKind {
    /// h = a + ‖x − b‖ (the chapter's; not smooth at b).
    Chapter,
    /// h = a + ‖x − b‖² (smooth).
    Smooth,
}

/// The transformation g = f·h, as the report states it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Remedy {
    pub kind: RemedyKind,
    /// a > 0.
    pub a: f64,
    /// The centre b.
    pub b: [f64; 3],
}

/// Fractions of the domain's half-widths that place the default b: irrational-looking
/// and different per axis, so b lies on no symmetry axis or plane of the catalog.
const DEFAULT_B: [f64; 3] = [0.1371, 0.0713, 0.0529];

impl Remedy {
    /// Parse `KIND[:A[:BX,BY,BZ]]` (`chapter` or `smooth`); a missing a is 1, a missing
    /// b the default generic point of `domain`.
    pub fn parse(s: &str, domain: Bx) -> Result<Remedy> {
        let bad = |why: String| Error::Param(format!("remedy '{s}': {why}"));
        let mut parts = s.splitn(3, ':');
        let kind = match parts.next().unwrap_or("").trim() {
            "chapter" => RemedyKind::Chapter,
            "smooth" => RemedyKind::Smooth,
            k => {
                return Err(bad(format!(
                "unknown kind '{k}' (use 'smooth' for a + |x - b|^2 or 'chapter' for a + |x - b|)"
            )))
            }
        };
        let a = match parts.next() {
            Some(t) => t
                .trim()
                .parse::<f64>()
                .map_err(|_| bad(format!("a = '{t}' is not a number")))?,
            None => 1.0,
        };
        let b = match parts.next() {
            Some(t) => {
                let v: Vec<f64> = t
                    .split(',')
                    .map(|c| c.trim().parse::<f64>())
                    .collect::<std::result::Result<_, _>>()
                    .map_err(|_| bad(format!("b = '{t}' is not bx,by,bz")))?;
                if v.len() != 3 {
                    return Err(bad(format!("b = '{t}' needs three coordinates")));
                }
                [v[0], v[1], v[2]]
            }
            None => {
                let mut b = [0.0; 3];
                for k in 0..3 {
                    let c = 0.5 * (domain.lo[k] + domain.hi[k]);
                    b[k] = c + DEFAULT_B[k] * 0.5 * (domain.hi[k] - domain.lo[k]);
                }
                b
            }
        };
        Remedy::new(kind, a, b).map_err(|e| match e {
            Error::Param(m) => bad(m),
            e => e,
        })
    }

    /// A checked transformation: a > 0 and finite, b finite.
    pub fn new(kind: RemedyKind, a: f64, b: [f64; 3]) -> Result<Remedy> {
        if !(a.is_finite() && a > 0.0) {
            return Err(Error::Param(format!(
                "a must be a positive number (h = a + |x - b|{} must not vanish), got {a}",
                if kind == RemedyKind::Smooth { "^2" } else { "" }
            )));
        }
        if b.iter().any(|c| !c.is_finite()) {
            return Err(Error::Param(format!("b must be finite, got {b:?}")));
        }
        Ok(Remedy { kind, a, b })
    }

    /// h at a point of any number type.
    fn h<T: Num>(&self, p: [T; 3]) -> T {
        let mut s = T::lit(0.0);
        for (k, pk) in p.into_iter().enumerate() {
            s = s + (pk.sub_const(&crate::implicit::number::Const::exact(self.b[k]))).square();
        }
        match self.kind {
            RemedyKind::Smooth => s.add_const(&crate::implicit::number::Const::exact(self.a)),
            RemedyKind::Chapter => s
                .sqrt()
                .add_const(&crate::implicit::number::Const::exact(self.a)),
        }
    }

    /// The formula of g for the report.
    pub fn describe(&self, f: &str) -> String {
        let [x, y, z] = self.b;
        let norm = format!("(x - {x})^2 + (y - {y})^2 + (z - {z})^2");
        match self.kind {
            RemedyKind::Smooth => format!("({f}) * ({} + {norm})", self.a),
            RemedyKind::Chapter => format!("({f}) * ({} + sqrt({norm}))", self.a),
        }
    }

    /// g = f·h over `f`.
    pub fn apply<'a>(&self, f: &'a dyn Implicit) -> Remedied<'a> {
        Remedied { inner: f, r: *self }
    }
}

/// g = f·h (see the module documentation).
pub struct Remedied<'a> {
    pub inner: &'a dyn Implicit,
    pub r: Remedy,
}

impl Implicit for Remedied<'_> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn eval(&self, p: [f64; 3]) -> f64 {
        self.inner.eval(p) * self.r.h(p)
    }
    fn eval_interval(&self, b: &IBox) -> Interval {
        self.inner.eval_interval(b) * self.r.h(*b)
    }
    fn grad(&self, p: [f64; 3]) -> Dual<f64> {
        self.inner.grad(p) * self.r.h([0, 1, 2].map(|k| Dual::var(p[k], k)))
    }
    fn grad_interval(&self, b: &IBox) -> Dual<Interval> {
        self.inner.grad_interval(b) * self.r.h([0, 1, 2].map(|k| Dual::var(b[k], k)))
    }
    fn hessian(&self, p: [f64; 3]) -> Hyper<f64> {
        self.inner.hessian(p) * self.r.h([0, 1, 2].map(|k| Hyper::var(p[k], k)))
    }
    fn hessian_interval(&self, b: &IBox) -> Hyper<Interval> {
        self.inner.hessian_interval(b) * self.r.h([0, 1, 2].map(|k| Hyper::var(b[k], k)))
    }
    fn is_rigorous(&self) -> bool {
        self.inner.is_rigorous()
    }
    fn regularity(&self, b: &IBox) -> Regularity {
        let own = match self.r.kind {
            RemedyKind::Smooth => Regularity::Smooth,
            // ‖x − b‖ is continuous everywhere and smooth away from b: a box whose
            // closure may contain b is only continuous.
            RemedyKind::Chapter => {
                let holds_b =
                    (0..3).all(|k| b[k].inf() <= self.r.b[k] && self.r.b[k] <= b[k].sup());
                if holds_b {
                    Regularity::Continuous
                } else {
                    Regularity::Smooth
                }
            }
        };
        own.min(self.inner.regularity(b))
    }
    fn describe(&self) -> String {
        self.r.describe(&self.inner.describe())
    }
}
