//! The angle functions: the three angles of a midpoint triangle orthogonally projected to
//! the plane with normal m, as rigorous interval functions of the chart parameters.
//!
//! With w_e = m × e for an edge vector e, the projected edges satisfy
//! (P e)·(P e') = (w_e · w_e')/|m|², so the cosine of the projected angle between e and
//! e' is (w_e·w_e')/(|w_e||w_e'|): homogeneous of degree 0 in m, hence no normalisation
//! of m and no transcendental function is needed (Sec. 4.3: angles compared through
//! cosines).
use super::cases::{Case, Domain, Ratio, Xi};
use crate::bnb::{Enclosure, Objective};
use crate::ival::{cross_c, ddot, iv, mean_value, pt, DVec3, IVec3, D2};
use inari::Interval;

/// Interval position of a Ξ point (up to the common factor e/4): (Ξx, (√3/2)Ξy, (a/e)Ξz).
pub fn position(ratio: Ratio, x: Xi) -> IVec3 {
    let h = pt(3.0).sqrt() / pt(2.0);
    [
        pt(x[0] as f64),
        h * pt(x[1] as f64),
        ratio.interval() * pt(x[2] as f64),
    ]
}

/// 1/D with D = diag(1, √3/2, a/e): m = D⁻¹ μ.
pub fn inv_d(ratio: Ratio) -> IVec3 {
    let h = pt(3.0).sqrt() / pt(2.0);
    [pt(1.0), pt(1.0) / h, pt(1.0) / ratio.interval()]
}

/// One domain of one case as an [`Objective`] with three outputs: cos of the projected
/// angle at each vertex of the triangle.
pub struct TriObj {
    edges: [IVec3; 3],
    rays: [[f64; 3]; 4],
    inv_d: IVec3,
    extra: Option<(IVec3, IVec3)>,
}

fn vsubi(a: IVec3, b: IVec3) -> IVec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

impl TriObj {
    pub fn new(ratio: Ratio, case: &Case, dom: &Domain) -> TriObj {
        let p = [0, 1, 2].map(|k| position(ratio, case.vertices[k].xi));
        let d = |x: Xi| position(ratio, x);
        TriObj {
            edges: [vsubi(p[1], p[0]), vsubi(p[2], p[1]), vsubi(p[0], p[2])],
            rays: dom.rays.map(|r| r.map(|x| x as f64)),
            inv_d: inv_d(ratio),
            extra: dom.extra.as_ref().map(|s| (d(s.keep), d(s.other))),
        }
    }

    /// m(u, v) as duals: μ = (1−u)(1−v) q0 + u(1−v) q1 + u v q2 + (1−u) v q3 (the
    /// bilinear map of the square onto the cone quadrilateral), m = D⁻¹ μ.
    fn normal(&self, u: D2, v: D2) -> DVec3 {
        let uv = u * v;
        let r = &self.rays;
        [0, 1, 2].map(|k| {
            let mu = D2::cst(pt(r[0][k]))
                + u.scale(pt(r[1][k] - r[0][k]))
                + v.scale(pt(r[3][k] - r[0][k]))
                + uv.scale(pt(r[0][k] - r[1][k] + r[2][k] - r[3][k]));
            mu.scale(self.inv_d[k])
        })
    }

    /// Cosines of the projected angles at vertices 0, 1, 2 (duals).
    fn cosines(&self, m: &DVec3) -> [D2; 3] {
        let w = self.edges.map(|e| cross_c(m, &e));
        let n = w.map(|x| ddot(&x, &x));
        // angle at vertex 0 is between e01 and −e20, etc.
        let c = |a: usize, b: usize| -> D2 { (-ddot(&w[a], &w[b])).div((n[a] * n[b]).sqrt()) };
        [c(0, 2), c(1, 0), c(2, 1)]
    }

    /// |m × other|² − |m × keep|² (≥ 0 where the kept diagonal is not longer).
    fn extra_gap(&self, m: &DVec3) -> Option<D2> {
        self.extra.as_ref().map(|(k, o)| {
            let (wk, wo) = (cross_c(m, k), cross_c(m, o));
            ddot(&wo, &wo) - ddot(&wk, &wk)
        })
    }

    /// The unit normal m at a chart point (display only).
    pub fn normal_f64(&self, u: f64, v: f64) -> [f64; 3] {
        let m = self.normal(D2::cst(pt(u)), D2::cst(pt(v)));
        let m = m.map(|x| x.v.mid());
        let n = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
        m.map(|x| x / n)
    }
}

impl Objective for TriObj {
    fn n_out(&self) -> usize {
        3
    }
    fn enclose(&self, u: [f64; 2], v: [f64; 2]) -> Enclosure {
        let (ui, vi) = (iv(u[0], u[1]), iv(v[0], v[1]));
        let m = self.normal(D2::var(ui, 0), D2::var(vi, 1));
        if let Some(g) = self.extra_gap(&m) {
            if g.v.sup() < 0.0 {
                return Enclosure::Outside;
            }
        }
        let over = self.cosines(&m);
        let (cu, cv) = (0.5 * (u[0] + u[1]), 0.5 * (v[0] + v[1]));
        let mc = self.normal(D2::var(pt(cu), 0), D2::var(pt(cv), 1));
        let at = self.cosines(&mc);
        let half = [ui - pt(cu), vi - pt(cv)];
        Enclosure::Values(
            (0..3)
                .map(|k| {
                    // A cosine lies in [-1, 1]; an empty or unbounded result (a projected
                    // edge that may vanish on the box) becomes the trivial enclosure.
                    let x = mean_value(&over[k], at[k].v, half).intersection(iv(-1.0, 1.0));
                    if x.is_empty() {
                        iv(-1.0, 1.0)
                    } else {
                        x
                    }
                })
                .collect::<Vec<Interval>>(),
        )
    }
    fn point(&self, u: f64, v: f64) -> Option<Vec<Interval>> {
        let m = self.normal(D2::cst(pt(u)), D2::cst(pt(v)));
        if let Some(g) = self.extra_gap(&m) {
            if !(g.v.inf() >= 0.0) {
                return None;
            }
        }
        let c = self.cosines(&m);
        let vals: Vec<Interval> = c.iter().map(|x| x.v).collect();
        if vals
            .iter()
            .any(|x| x.is_empty() || !x.inf().is_finite() || !x.sup().is_finite())
        {
            return None;
        }
        Some(vals)
    }
}
