//! The interval tests the criteria are built from: exclusion of zero, the
//! mean-value enclosure, Small Normal Variation (eq 1.2) and its angle bounds; and the
//! hypotheses both subdivision meshers check the same way (input, budget, the domain
//! boundary).
use super::tree::{Decision, Grid, Verdict};
use crate::error::{Error, Result};
use crate::implicit::ops::excludes_zero;
use crate::implicit::Implicit;
use inari::Interval;

/// The interval scalar product ⟨□∇f, □∇f⟩ over the first `dim` components (eq 1.2):
/// each factor varies independently, so its lower bound is exactly the minimum of
/// ⟨u, v⟩ over u, v in the gradient box.
pub fn snv_dot(g: &[Interval; 3], dim: usize) -> Interval {
    let mut s = Interval::try_from((0.0, 0.0)).unwrap();
    for gk in g.iter().take(dim) {
        s = s + *gk * *gk;
    }
    s
}

/// How the maximal angle between two gradients over a box is bounded (Exercise 9).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AngleBound {
    /// cos α ≥ a / b for ⟨□∇f, □∇f⟩ = [a, b] (the chapter's crude bound).
    Crude,
    /// The exact maximal angle over the gradient box: attained at a pair of its vertices
    /// once all vertex pairs make an angle < 90° (each vertex cone is convex), evaluated
    /// with interval arithmetic.
    Sharp,
}

/// A rigorous lower bound on cos α over all pairs of gradients in the box `g`
/// (`None` when nothing positive can be proven).
pub fn cos_lower_bound(g: &[Interval; 3], dim: usize, how: AngleBound) -> Option<f64> {
    match how {
        AngleBound::Crude => {
            let d = snv_dot(g, dim);
            if d.inf() > 0.0 {
                Some((Interval::try_from((d.inf(), d.inf())).ok()? / d.sup_iv()).inf())
            } else {
                None
            }
        }
        AngleBound::Sharp => {
            if !(0..dim).any(|k| excludes_zero(g[k])) {
                return None;
            }
            let nv = 1usize << dim;
            let vert = |m: usize| -> [Interval; 3] {
                let mut v = [Interval::try_from((0.0, 0.0)).unwrap(); 3];
                for k in 0..dim {
                    let x = if m >> k & 1 == 0 {
                        g[k].inf()
                    } else {
                        g[k].sup()
                    };
                    v[k] = Interval::try_from((x, x)).unwrap();
                }
                v
            };
            let mut best = f64::INFINITY;
            for a in 0..nv {
                for b in a + 1..nv {
                    let (u, v) = (vert(a), vert(b));
                    let mut d = Interval::try_from((0.0, 0.0)).unwrap();
                    let mut nu = d;
                    let mut nvv = d;
                    for k in 0..dim {
                        d = d + u[k] * v[k];
                        nu = nu + u[k] * u[k];
                        nvv = nvv + v[k] * v[k];
                    }
                    let c = d / (nu.sqrt() * nvv.sqrt());
                    if c.is_empty() || c.inf().is_nan() {
                        return None;
                    }
                    best = best.min(c.inf());
                }
            }
            if best > 0.0 {
                Some(best.min(1.0))
            } else {
                None
            }
        }
    }
}

trait SupIv {
    fn sup_iv(&self) -> Interval;
}
impl SupIv for Interval {
    fn sup_iv(&self) -> Interval {
        Interval::try_from((self.sup(), self.sup())).unwrap_or(Interval::ENTIRE)
    }
}

// ---------------------------------------------------------------------------------
// Hypotheses shared by Snyder and Plantinga–Vegter: input, budget, domain boundary.

/// The reason for a box on which f is defined nowhere (an empty enclosure): "no zero"
/// would be vacuous and is almost always a mistake in the formula (x/0).
pub const UNDEFINED_BOX: &str =
    "f is undefined on this whole box (a division by 0, a root of a negative number)";

/// The reason for a box on which the enclosure of f is exactly [0, 0]: f vanishes on
/// the whole box, its zero set there is the box itself, not a surface or a curve, and
/// no subdivision can change that (so the box is not split until the budget runs out).
pub const ZERO_BOX: &str =
    "f is identically 0 on this whole box: its zero set is not a surface or curve there";

/// The enclosure proves f = 0 everywhere on the box.
pub(crate) fn identically_zero(v: Interval) -> bool {
    !v.is_empty() && v.inf() == 0.0 && v.sup() == 0.0
}

/// `--max-boxes` at least 1, `--time-limit` positive and finite.
pub(crate) fn check_budget(max_boxes: u64, time_limit: Option<f64>) -> Result<()> {
    if max_boxes == 0 {
        return Err(Error::Param("max_boxes must be at least 1".into()));
    }
    if let Some(t) = time_limit {
        crate::mesher::options::check_time_limit(t)?;
    }
    Ok(())
}

/// The domain boundary (found by the soundness property test). The argument behind
/// Theorem 2 lets the curve cross a box edge twice unnoticed because it "cannot leave
/// the adjacent cube without violating the Small Normal Variation condition" there
/// (the chapter, Fig. 1.9c); on the boundary of the domain there is no adjacent cube,
/// and the arc that dips out of the domain and comes back is lost: f = 1.5x² + y² −
/// 2.25 on [−1.63, 0.24] × [−1.49, −0.49] has two arcs inside the domain, and the
/// unguarded algorithm meshed one. So a box touching the boundary is accepted only if
/// * in 2D, on each of its edges on the boundary, 0 ∉ □f or 0 ∉ □∂f/∂t (at most one
///   crossing, seen by the end signs);
/// * in 3D, on each of its faces on the boundary, 0 ∉ □f: the surface stays inside
///   the domain, the setting in which the theorem is proven. A surface that crosses
///   the boundary is reported uncertified there.
pub(crate) fn boundary_failure(
    f: &dyn Implicit,
    g: &Grid,
    c: crate::subdivision::Cell,
) -> Option<Decision> {
    let (lo, hi) = g.cell_lo_hi(c);
    let top = 1u32 << g.depth;
    for k in 0..g.dim {
        for (side, on) in [(lo[k], lo[k] == 0), (hi[k], hi[k] == top)] {
            if !on {
                continue;
            }
            let (mut a, mut b) = (lo, hi);
            a[k] = side;
            b[k] = side;
            let fb = g.ibox(a, b);
            if g.dim == 2 {
                let t = 1 - k; // the edge runs along the other axis
                let d = f.grad_interval(&fb);
                if excludes_zero(d.v) {
                    continue;
                }
                if !excludes_zero(d.g[t]) {
                    return Some(Decision::Split(
                        "f = 0 may cross a domain edge twice (Theorem 2 needs a monotone f there)",
                    ));
                }
                // A zero exactly at an end (the curve through a corner of the domain,
                // or touching it there) is not seen by the sign⁺ convention correctly.
                for p in [g.point(a), g.point(b)] {
                    let pb = p.map(crate::implicit::number::point);
                    if !excludes_zero(f.eval_interval(&pb)) {
                        return Some(Decision::Split(
                            "f = 0 may pass through a grid point on the domain boundary",
                        ));
                    }
                }
            } else {
                let v = f.eval_interval(&fb);
                if !excludes_zero(v) {
                    // Smaller boxes may prove a face near the surface free of it, but
                    // where the face's corners have proven opposite signs the surface
                    // does cross the boundary: no refinement helps, stop here.
                    let signs: Vec<_> = face_corners(a, b, k)
                        .into_iter()
                        .map(|q| crate::implicit::ops::point_sign(f, g.point(q)))
                        .collect();
                    let crosses = signs.iter().all(|s| s.rigorous)
                        && signs.iter().any(|s| s.pos)
                        && signs.iter().any(|s| !s.pos);
                    let reason = "f = 0 may meet the domain boundary (Theorem 2 is proven for a surface inside the domain)";
                    return Some(if crosses {
                        Decision::Leaf(Verdict::Failed(
                            "f = 0 meets the domain boundary (Theorem 2 is proven for a surface inside the domain)",
                        ))
                    } else {
                        Decision::Split(reason)
                    });
                }
            }
        }
    }
    None
}

/// The four corners of the face spanned by grid points `a` and `b` (equal in axis
/// `normal`).
fn face_corners(a: [u32; 3], b: [u32; 3], normal: usize) -> [[u32; 3]; 4] {
    let (u, v) = match normal {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    let mut out = [a; 4];
    for (m, q) in out.iter_mut().enumerate() {
        if m & 1 == 1 {
            q[u] = b[u];
        }
        if m & 2 == 2 {
            q[v] = b[v];
        }
    }
    out
}
