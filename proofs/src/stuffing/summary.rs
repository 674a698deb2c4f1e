//! The bound results (enclosures, verdicts, tightness, witness configurations) from the
//! recorded leaves and witnesses: used by the search and re-derived by the checker.
use super::cases::{Alphas, Case};
use super::eval::Problem;
use super::{
    decimal_of, feeds, has_dihedrals, paper_values, BoundResult, Certificate, Leaf, Witness,
    BOUNDS, MARGIN,
};
use crate::exact::{self, Verdict};
use certmesh::stuffing::params::Row;
use num_rational::BigRational;

/// The bound results from the recorded leaves and witnesses.
pub(super) fn summarize(
    cert: &Certificate,
    cases: &[Case],
    probs: &[Vec<Problem>],
) -> Result<Vec<BoundResult>, String> {
    let row = certmesh::stuffing::row(&cert.row).map_err(|e| e.to_string())?;
    let mut lo = [f64::INFINITY; 6];
    let mut hi = [f64::NEG_INFINITY; 6];
    for pc in &cert.problems {
        let pr = probs
            .get(pc.case)
            .and_then(|p| p.get(pc.problem))
            .ok_or("certificate names a problem that does not exist")?;
        for l in &pc.leaves {
            let leaf = Leaf::from_vec(l, pr.dim, pr.n_out())?;
            for v in &leaf.vals {
                for &b in feeds(pr.what) {
                    lo[b] = lo[b].min(v[0]);
                    hi[b] = hi[b].max(v[1]);
                }
            }
        }
    }
    Ok(results(
        row,
        &cert.alphas,
        lo,
        hi,
        &cert.witnesses,
        cases,
        probs,
    ))
}

pub(super) fn results(
    row: &Row,
    a: &Alphas,
    lo: [f64; 6],
    hi: [f64; 6],
    wit: &[Option<Witness>],
    cases: &[Case],
    probs: &[Vec<Problem>],
) -> Vec<BoundResult> {
    let paper = paper_values(row);
    BOUNDS
        .iter()
        .enumerate()
        .map(|(b, &(name, kind, is_min))| {
            let w = wit.get(b).cloned().flatten();
            let skip = kind == 0 && !has_dihedrals(row);
            let (cos, deg) = match (&w, skip) {
                (Some(w), false) if is_min => {
                    let c = [w.cos[0], hi[b]];
                    (Some(c), Some([exact::deg_lo(c[1]), exact::deg_hi(c[0])]))
                }
                (Some(w), false) => {
                    let c = [lo[b], w.cos[1]];
                    (Some(c), Some([exact::deg_lo(c[1]), exact::deg_hi(c[0])]))
                }
                _ => (None, None),
            };
            let (verdict, tight) = match (paper[b], &w, skip) {
                (Some(p), Some(w), false) => {
                    let bd = exact::decimal(&decimal_of(p)).unwrap_or_default();
                    let m = exact::decimal(MARGIN).unwrap_or_default();
                    let (v, t) = if is_min {
                        let mb: BigRational = &bd + &m;
                        (
                            exact::angle_at_least(&bd, hi[b], w.cos[0]),
                            exact::angle_at_least(&mb, hi[b], w.cos[0]),
                        )
                    } else {
                        let mb: BigRational = &bd - &m;
                        (
                            exact::angle_at_most(&bd, lo[b], w.cos[1]),
                            exact::angle_at_most(&mb, lo[b], w.cos[1]),
                        )
                    };
                    let t = match t {
                        Verdict::Refuted => "attained",
                        Verdict::Proven => "not attained",
                        Verdict::Undecided => "unknown",
                    };
                    (Some(v), Some(t.to_string()))
                }
                _ => (None, None),
            };
            let (config, wcase) = match (&w, skip) {
                (Some(w), false) => match (cases.get(w.case), probs.get(w.case)) {
                    (Some(c), Some(ps)) => match ps.get(w.problem) {
                        Some(pr) => (Some(pr.config(c, a, &w.x)), Some(c.v)),
                        None => (None, None),
                    },
                    _ => (None, None),
                },
                _ => (None, None),
            };
            BoundResult {
                bound: name.into(),
                paper: paper[b],
                cos,
                deg,
                verdict,
                tight,
                witness: if skip { None } else { w },
                witness_config: config,
                witness_case: wcase,
            }
        })
        .collect()
}
