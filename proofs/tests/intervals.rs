//! Enclosure properties of the interval primitives and of the angle objective.
use inari::Interval;
use proofs::bnb::{Enclosure, Objective};
use proofs::exact::{cos_deg, decimal, rat};
use proofs::geometry::DiagonalRule;
use proofs::gradnormal::cases::{Derived, Ratio};
use proofs::gradnormal::eval::TriObj;
use proofs::ival::{iv, mean_value, pt, D2};
use proptest::prelude::*;

fn sorted(a: f64, b: f64) -> (f64, f64) {
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

proptest! {
    #[test]
    fn d2_ops_enclose_values_and_derivatives(
        a in 0.5f64..3.0, b in 0.5f64..3.0, w in 0.0f64..0.2, t in 0.0f64..1.0, s in 0.0f64..1.0
    ) {
        // f(x, y) = sqrt(x*y + x) / (y + 1) - x over the box [a, a+w] x [b, b+w].
        let f = |x: f64, y: f64| (x * y + x).sqrt() / (y + 1.0) - x;
        let fx = |x: f64, y: f64| (y + 1.0) / (2.0 * (x * y + x).sqrt()) / (y + 1.0) - 1.0;
        let (x, y) = (a + t * w, b + s * w);
        let eval = |u: D2, v: D2| (u * v + u).sqrt().div(v + D2::cst(pt(1.0))) - u;
        let over = eval(D2::var(iv(a, a + w), 0), D2::var(iv(b, b + w), 1));
        prop_assert!(over.v.contains(f(x, y)));
        let gx = fx(x, y);
        prop_assert!(over.g[0].inf() <= gx + 1e-12 && gx - 1e-12 <= over.g[0].sup());
        // Mean-value enclosure.
        let (cx, cy) = (a + 0.5 * w, b + 0.5 * w);
        let at = eval(D2::var(pt(cx), 0), D2::var(pt(cy), 1)).v;
        let mv = mean_value(&over, at, [iv(a, a + w) - pt(cx), iv(b, b + w) - pt(cy)]);
        prop_assert!(mv.contains(f(x, y)));
    }

    #[test]
    fn triangle_objective_encloses_point_values(
        case in 0usize..18, dom in 0usize..64, u0 in 0.0f64..1.0, u1 in 0.0f64..1.0,
        v0 in 0.0f64..1.0, v1 in 0.0f64..1.0, t in 0.0f64..1.0, s in 0.0f64..1.0
    ) {
        let ratio = Ratio::Sommerville;
        let cases = Derived::new(ratio).cases(DiagonalRule::Paper).unwrap();
        let c = &cases[case];
        let d = &c.domains[dom % c.domains.len()];
        let obj = TriObj::new(ratio, c, d);
        let (ua, ub) = sorted(u0, u1);
        let (va, vb) = sorted(v0, v1);
        let (u, v) = (ua + t * (ub - ua), va + s * (vb - va));
        let Enclosure::Values(vals) = obj.enclose([ua, ub], [va, vb]) else {
            panic!("paper-rule domains have no extra constraint");
        };
        // Independent f64 evaluation of the projected angles at the normal of (u, v).
        let m = obj.normal_f64(u, v);
        let pos = |x: [i64; 3]| {
            [x[0] as f64, 3f64.sqrt() / 2.0 * x[1] as f64, ratio.f64() * x[2] as f64]
        };
        let p = c.vertices.clone().map(|q| pos(q.xi));
        for k in 0..3 {
            let (a, b, cc) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            let pr = |x: [f64; 3]| {
                let d = x[0] * m[0] + x[1] * m[1] + x[2] * m[2];
                [x[0] - d * m[0], x[1] - d * m[1], x[2] - d * m[2]]
            };
            let e1 = pr([b[0] - a[0], b[1] - a[1], b[2] - a[2]]);
            let e2 = pr([cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]]);
            let dot = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
            let n = ((e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2])
                * (e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2])).sqrt();
            let cosv = dot / n;
            let x: Interval = vals[k];
            prop_assert!(x.inf() - 1e-9 <= cosv && cosv <= x.sup() + 1e-9,
                "case {case} angle {k}: cos {cosv} not in [{}, {}]", x.inf(), x.sup());
            let pv = obj.point(u, v).unwrap()[k];
            prop_assert!(pv.inf() - 1e-9 <= cosv && cosv <= pv.sup() + 1e-9);
        }
    }

    #[test]
    fn rational_cos_encloses_f64_cos(deg_milli in 0u32..180_000) {
        let deg = deg_milli as f64 / 1000.0;
        let (lo, hi) = cos_deg(&decimal(&format!("{}", deg)).unwrap());
        let c = deg.to_radians().cos();
        prop_assert!(lo <= hi);
        prop_assert!(rat(c - 1e-12) <= hi && lo <= rat(c + 1e-12));
        prop_assert!(&hi - &lo < rat(1e-25));
    }
}

#[test]
fn cos_of_special_angles() {
    // cos 60° = 1/2 lies in the enclosure; cos 90° is exactly 0.
    let (lo, hi) = cos_deg(&decimal("60").unwrap());
    assert!(lo <= rat(0.5) && rat(0.5) <= hi);
    let (lo, hi) = cos_deg(&decimal("90").unwrap());
    assert!(lo == rat(0.0) && hi == rat(0.0));
    assert!(decimal("35.25").unwrap() == rat(35.25));
    assert!(decimal("x1").is_none());
}
