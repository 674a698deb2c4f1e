//! f64 samples of the projected angles of a case (display only: the boundary-arc plots
//! and the maps; no verdict depends on them).
use super::cases::{Case, Ratio, Xi};

/// Sample the three projected angles (degrees, f64, display only) of a case at μ.
pub fn angles_at(ratio: Ratio, case: &Case, mu: [f64; 3]) -> [f64; 3] {
    let h = 3f64.sqrt() / 2.0;
    let r = ratio.f64();
    let pos = |x: Xi| [x[0] as f64, h * x[1] as f64, r * x[2] as f64];
    let m = [mu[0], mu[1] / h, mu[2] / r];
    let p = case.vertices.clone().map(|v| pos(v.xi));
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    [0, 1, 2].map(|k| {
        let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
        let (u, v) = (cross(m, sub(b, a)), cross(m, sub(c, a)));
        (dot(u, v) / (dot(u, u) * dot(v, v)).sqrt())
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees()
    })
}
