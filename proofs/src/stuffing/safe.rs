//! The safe property (no warped BCC tetrahedron inverts), decided exactly.
use super::cases::{self, Alphas, Case, Kind, Seg, DEN};
use super::SafeResult;
use crate::exact::Verdict;
use certmesh::stuffing::params::Row;

/// The safe property, decided exactly at the corners of every warped-BCC case.
pub fn safe_property(row: &Row) -> SafeResult {
    let a = Alphas::of(row);
    let (cases, counts) = cases::bcc_cases(&a);
    let unwarped = 4i128 * (DEN as i128).pow(3);
    let mut min = (i128::MAX, 0usize, [0i64; 4]);
    for (i, c) in cases.iter().enumerate() {
        let (r, t) = cases::volume_range(c, &a);
        if r[0] < min.0 {
            min = (r[0], i, t[0]);
        }
    }
    let c = &cases[min.1];
    let mut note = String::new();
    let verdict = if min.0 > 0 {
        Verdict::Proven
    } else if min.0 < 0 {
        Verdict::Refuted
    } else {
        // The closed box reaches volume 0. The real parameter set excludes the faces
        // t = α of warped vertices (a cut at distance exactly α·|e| violates nothing),
        // except that with α_short = 0.5 the odd endpoint of a red edge does warp to
        // its midpoint (§6). A multilinear function that is ≥ 0 at every corner and
        // vanishes at a point vanishes on the whole face holding that point in its
        // relative interior; every face meeting the real set has a corner in it. So
        // volume > 0 on the real set iff volume > 0 at every corner inside it.
        let strict = cases.iter().all(|c| strictly_positive_on_real_set(c, &a));
        if strict {
            note = "volume >= 0 on the closed configuration space and > 0 on the real \
                    one (the zeros need a warp of exactly alpha, excluded by the \
                    violation rule and the Sec. 6 midpoint convention)"
                .into();
            Verdict::Proven
        } else {
            note = "a BCC tetrahedron can become flat (volume 0)".into();
            Verdict::Undecided
        }
    };
    SafeResult {
        counts,
        min_ratio: min.0 as f64 / unwarped as f64,
        min_volume_h3: min.0 as f64 / (DEN as f64).powi(3) / 8.0,
        verdict,
        note,
        witness_case: c.v,
        witness_t: min.2.map(|t| t as f64 / DEN as f64),
    }
}

/// Is a warp parameter at the top of its range actually attainable? Only for the odd
/// endpoint of a red edge with α_short = 0.5 (§6).
fn top_attainable(s: &Seg, a: &Alphas) -> bool {
    s.kind == Kind::Warp && !s.black() && a.short == DEN / 2 && s.p[0] & 1 != 0
}

pub(crate) fn strictly_positive_on_real_set(c: &Case, a: &Alphas) -> bool {
    let ranges = c.v.map(|s| a.range(&s));
    for m in 0..16u32 {
        let top = |k: usize| m >> k & 1 == 1;
        // Corners of the real set: no warp parameter at an unattainable top.
        let real =
            (0..4).all(|k| c.v[k].kind != Kind::Warp || !top(k) || top_attainable(&c.v[k], a));
        let t: [i64; 4] = [0, 1, 2, 3].map(|k| ranges[k][top(k) as usize]);
        let p = [0, 1, 2, 3].map(|k| cases::pos_exact(&c.v[k], t[k]));
        let vol = cases::orient_exact(&p);
        if vol < 0 || (real && vol == 0) {
            return false;
        }
    }
    true
}
