//! The interval tests the criteria are built from: exclusion of zero, the
//! mean-value enclosure, Small Normal Variation (eq 1.2) and its angle bounds.
use crate::implicit::ops::excludes_zero;
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
