//! χ({f ≤ 0}) by Morse counting of f itself, and χ(S) = 2·χ({f ≤ 0}).
//!
//! **The theorem used.** Let D be a box, M = {x ∈ D : f(x) ≤ 0}. Suppose
//! (a) f is C^∞ on a neighbourhood of M and continuous on a neighbourhood of ∂D;
//! (b) f > 0 on ∂D, so M is a compact subset of int D;
//! (c) every critical point of f in M is isolated, non-degenerate, with f ≠ 0 there
//!     (so 0 is a regular value and S = f⁻¹(0) ∩ D = ∂M is a compact regular surface).
//! Then M is a compact 3-manifold with boundary S and has the homotopy type of a CW
//! complex with one cell of dimension λ for each critical point of index λ in M
//! (Milnor, *Morse Theory*, 1963, Thm 3.5), so χ(M) = Σ_{f(p) < 0} (−1)^{index p}; and
//! χ(∂M) = 2·χ(M) for a compact 3-manifold (glue two copies of M along ∂M: the double
//! is a closed 3-manifold, χ = 0 = 2χ(M) − χ(∂M)).
//!
//! **What is checked, with intervals.** (b) by [`boundary_sign`] (every piece of a
//! subdivision of the six faces has 0 ∉ □f, regularity at least `Continuous`, and the
//! same sign +). (a) and (c) by the gradient search of [`critical_points_of_f`]: every
//! box of D was excluded (0 ∉ □∇f, proven on a box where f is C^∞), covered, or
//! isolated by Krawczyk with a certified index; an isolated point counts if its value
//! enclosure is < 0, is ignored if > 0, and blocks the proof if it contains 0. An
//! undecided box of the search (degenerate, budget, not smooth, ambiguous, on ∂D) is
//! harmless only when f is proven continuous on it with □f > 0 there: then it holds
//! no point of M, and (a), (c) do not concern it. Anything else: no χ, and the reason.
use super::linalg::excludes_zero;
use super::search::bisect;
use super::{critical_points_of_f, Budget, Bx, CriticalReport, MorseIndex};
use crate::implicit::{Implicit, Regularity};
use serde::{Deserialize, Serialize};

/// The sign of f on ∂D when it is proven constant and non-zero: every piece of the six
/// faces (each subdivided up to `max_depth` bisections, `max_boxes` pieces in all) has
/// 0 ∉ □f and f proven continuous on it. `None` when that was not proven (the surface
/// may meet ∂D, or f may be discontinuous there).
pub fn boundary_sign(f: &dyn Implicit, domain: Bx, max_depth: u32, max_boxes: usize) -> Option<i8> {
    let mut boxes = 0usize;
    let mut seen: Option<i8> = None;
    for axis in 0..3 {
        for side in [domain.lo[axis], domain.hi[axis]] {
            let mut face = domain;
            face.lo[axis] = side;
            face.hi[axis] = side;
            let mut stack = vec![(face.to_ibox(), 0u32)];
            while let Some((b, depth)) = stack.pop() {
                boxes += 1;
                if boxes > max_boxes {
                    return None;
                }
                let (v, _) = crate::implicit::ops::enclose(f, &b);
                if excludes_zero(v) && f.regularity(&b) >= Regularity::Continuous {
                    let s = if v.inf() > 0.0 { 1 } else { -1 };
                    if seen.is_some_and(|t| t != s) {
                        return None; // impossible for a continuous f; refuse anyway
                    }
                    seen = Some(s);
                    continue;
                }
                if depth >= max_depth {
                    return None;
                }
                let (l, r) = bisect(&b);
                stack.push((l, depth + 1));
                stack.push((r, depth + 1));
            }
        }
    }
    seen
}

/// Where an isolated critical value lies relative to the level 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Side {
    /// The value enclosure is < 0: the point lies in {f < 0} and is counted.
    Below,
    /// The value enclosure is > 0: not in {f ≤ 0}, not counted.
    Above,
    /// The enclosure contains 0: the point may lie on S (S may be singular).
    Undecided,
}

/// The side of a value enclosure.
pub fn side(value: [f64; 2]) -> Side {
    if value[1] < 0.0 {
        Side::Below
    } else if value[0] > 0.0 {
        Side::Above
    } else {
        Side::Undecided
    }
}

/// χ({f ≤ 0} ∩ D) and χ(S) by Morse counting of f (see the module doc).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SublevelReport {
    /// χ({f ≤ 0} ∩ D), present only when certified.
    pub chi_sublevel: Option<i64>,
    /// χ(S) = 2·χ({f ≤ 0}), present only when certified.
    pub chi_surface: Option<i64>,
    /// Why χ is not certified (`None` when it is).
    pub reason: Option<String>,
    /// Certified critical points with f < 0, by index 0..3: the counted ones.
    pub counted: [usize; 4],
    /// Isolated critical points with f > 0 (not counted).
    pub above: usize,
    /// Isolated critical points whose value enclosure contains 0.
    pub on_level: usize,
    /// Isolated critical points with f < 0 but no certified index.
    pub below_without_index: usize,
    /// Undecided boxes of the search proven to lie in {f > 0} (harmless).
    pub undecided_above: usize,
    /// Undecided boxes that may meet {f ≤ 0} (each blocks the proof).
    pub undecided_blocking: usize,
    /// f > 0 proven on ∂D.
    pub boundary_positive: bool,
    /// The gradient search itself.
    pub gradient: CriticalReport,
}

/// χ({f ≤ 0} ∩ `domain`) and χ(S) = 2χ by Morse counting of the critical points of f,
/// with every hypothesis checked (module doc); otherwise `None` and the reason.
pub fn sublevel_euler_characteristic(
    f: &dyn Implicit,
    domain: Bx,
    budget: Budget,
) -> SublevelReport {
    let gradient = critical_points_of_f(f, domain, budget);
    let sign = boundary_sign(
        f,
        domain,
        2 * budget.nonsmooth_depth.max(8),
        budget.max_boxes,
    );
    from_gradient(f, gradient, sign == Some(1))
}

/// The χ of {f ≤ 0} from a gradient search already made and the boundary check.
pub fn from_gradient(
    f: &dyn Implicit,
    gradient: CriticalReport,
    boundary_positive: bool,
) -> SublevelReport {
    let mut counted = [0usize; 4];
    let (mut above, mut on_level, mut below_without_index) = (0, 0, 0);
    for p in &gradient.points {
        match (side(p.value), p.index) {
            (Side::Above, _) => above += 1,
            (Side::Undecided, _) => on_level += 1,
            (Side::Below, MorseIndex::Certified { index }) => counted[index as usize] += 1,
            (Side::Below, _) => below_without_index += 1,
        }
    }
    let (mut undecided_above, mut undecided_blocking) = (0, 0);
    let mut blocking_reasons: Vec<String> = Vec::new();
    for u in &gradient.undecided {
        let b = u.region.to_ibox();
        let harmless = positive_on(f, &b, POSITIVE_SPLITS);
        if harmless {
            undecided_above += 1;
        } else {
            undecided_blocking += 1;
            blocking_reasons.push(
                serde_json::to_value(u.reason)
                    .ok()
                    .and_then(|v| v.as_str().map(String::from))
                    .unwrap_or_else(|| format!("{:?}", u.reason)),
            );
        }
    }
    blocking_reasons.sort();
    blocking_reasons.dedup();
    let valid = (0..3).all(|k| {
        gradient.domain.lo[k].is_finite()
            && gradient.domain.hi[k].is_finite()
            && gradient.domain.lo[k] < gradient.domain.hi[k]
    });
    let reason = if f.dim() != 3 {
        Some("not a surface f(x, y, z)".to_string())
    } else if !valid {
        Some("the domain is not a finite, non-degenerate box".to_string())
    } else if !f.is_rigorous() {
        Some("the oracle's interval methods are not rigorous".to_string())
    } else if !boundary_positive {
        Some("f > 0 on the domain boundary was not proven: {f <= 0} may meet the boundary, so it is not proven compact inside the domain".to_string())
    } else if undecided_blocking > 0 {
        Some(format!(
            "{undecided_blocking} undecided boxes of the gradient search may meet {{f <= 0}} ({}): f is not proven Morse there (a degenerate or non-isolated critical set, or not smooth)",
            blocking_reasons.join(", ")
        ))
    } else if on_level > 0 {
        Some(format!(
            "{on_level} critical points with a value enclosure containing 0: S may be singular"
        ))
    } else if below_without_index > 0 {
        Some(format!(
            "{below_without_index} critical points in {{f < 0}} without a certified index (possibly degenerate)"
        ))
    } else {
        None
    };
    let chi_sublevel = reason
        .is_none()
        .then(|| counted[0] as i64 - counted[1] as i64 + counted[2] as i64 - counted[3] as i64);
    SublevelReport {
        chi_sublevel,
        chi_surface: chi_sublevel.map(|c| 2 * c),
        reason,
        counted,
        above,
        on_level,
        below_without_index,
        undecided_above,
        undecided_blocking,
        boundary_positive,
        gradient,
    }
}

/// Bisection depth with which [`positive_on`] tries to prove f > 0 on an undecided box
/// (at most 2^9 = 512 sub-boxes, stopping at the first that fails).
const POSITIVE_SPLITS: u32 = 9;

/// f > 0 proven on the closed box `b`: f continuous there and the enclosure above 0,
/// on `b` itself or on every half of a bisection, `splits` levels deep (the halves
/// cover `b`). An undecided box of the gradient search on which this holds lies in
/// {f > 0} and cannot hide a critical point of {f <= 0}: e.g. the box around the kink
/// of the chapter's remedy a + |x - b| when f(b) > 0, whose natural enclosure at the
/// search's depth is too wide.
fn positive_on(f: &dyn Implicit, b: &crate::implicit::IBox, splits: u32) -> bool {
    if f.regularity(b) < Regularity::Continuous {
        return false;
    }
    let (v, _) = crate::implicit::ops::enclose(f, b);
    if excludes_zero(v) && v.inf() > 0.0 {
        return true;
    }
    if splits == 0 || v.sup() <= 0.0 {
        return false;
    }
    let (l, r) = bisect(b);
    positive_on(f, &l, splits - 1) && positive_on(f, &r, splits - 1)
}
