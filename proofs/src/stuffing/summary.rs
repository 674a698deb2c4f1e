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

/// Cosine thresholds per bound: the paper's value and the tightness margin.
pub(super) fn thresholds(row: &Row) -> Vec<Vec<f64>> {
    let margin = 1e-4;
    BOUNDS
        .iter()
        .zip(paper_values(row))
        .map(|(&(_, _, is_min), p)| match p {
            None => Vec::new(),
            Some(b) => {
                let m = if is_min { b + margin } else { b - margin };
                vec![b.to_radians().cos(), m.to_radians().cos()]
            }
        })
        .collect()
}

/// The depth limit of a problem (the partition check sums volumes in u128).
pub(super) fn depth_limit(dim: usize, max_depth: u8) -> u8 {
    if dim == 0 {
        0
    } else {
        max_depth.min((120 / dim) as u8)
    }
}

/// Could a box with bounds `vals` (one [lo, hi] per output of `pr`) still change a
/// bound by more than `tol` or a threshold decision, given the best witness cosines
/// `best`? The search refines such boxes; the checker re-applies the test with the final
/// witnesses (it is monotone in the witnesses, which only improve).
pub(super) fn leaf_needs(
    pr: &Problem,
    vals: &[[f64; 2]],
    best: &[f64; 6],
    thr: &[Vec<f64>],
    tol: f64,
) -> bool {
    vals.iter().any(|v| {
        feeds(pr.what).iter().any(|&b| {
            let best = best[b];
            if BOUNDS[b].2 {
                v[1] > best + tol || thr[b].iter().any(|&c| best <= c && v[1] > c)
            } else {
                v[0] < best - tol || thr[b].iter().any(|&c| best >= c && v[0] < c)
            }
        })
    })
}

/// The best witness cosine per bound (the search's final state): the witness's lower
/// end for a lower bound (largest cosine), its upper end for an upper bound; ∓2 without
/// a witness.
pub(super) fn final_best(witnesses: &[Option<Witness>]) -> [f64; 6] {
    std::array::from_fn(|b| {
        let is_min = BOUNDS[b].2;
        match witnesses.get(b).cloned().flatten() {
            Some(w) if is_min => w.cos[0],
            Some(w) => w.cos[1],
            None if is_min => -2.0,
            None => 2.0,
        }
    })
}

/// The derived fields of a certificate (see [`derive`]).
pub(super) struct Derived {
    /// Per problem, in certificate order.
    pub unresolved_per_problem: Vec<usize>,
    pub leaves: usize,
    pub unresolved: usize,
    pub bounds: Vec<BoundResult>,
}

/// Every derived field of a certificate from its leaves and witnesses: the unresolved
/// count of every problem (leaves at the depth limit that could still change a bound or
/// a threshold decision given the final witnesses), the totals, and the bound results
/// (without verdicts or tightness for a shard). The search, `merge` and `check` all use
/// this.
pub(super) fn derive(
    cert: &Certificate,
    cases: &[Case],
    probs: &[Vec<Problem>],
) -> Result<Derived, String> {
    let row = super::custom::resolve(&cert.row).map_err(|e| format!("row: {e}"))?;
    let thr = thresholds(row);
    let best = final_best(&cert.witnesses);
    let mut lo = [f64::INFINITY; 6];
    let mut hi = [f64::NEG_INFINITY; 6];
    let (mut leaves, mut unresolved) = (0, 0);
    let mut per = Vec::with_capacity(cert.problems.len());
    for (i, pc) in cert.problems.iter().enumerate() {
        let pr = probs
            .get(pc.case)
            .and_then(|p| p.get(pc.problem))
            .ok_or_else(|| format!("problems[{i}]: names a problem that does not exist"))?;
        let lim = depth_limit(pr.dim, cert.max_depth);
        let mut u = 0;
        for (j, l) in pc.leaves.iter().enumerate() {
            let leaf = Leaf::from_vec(l, pr.dim, pr.n_out())
                .map_err(|e| format!("problems[{i}].leaves[{j}]: {e}"))?;
            for v in &leaf.vals {
                for &b in feeds(pr.what) {
                    lo[b] = lo[b].min(v[0]);
                    hi[b] = hi[b].max(v[1]);
                }
            }
            if leaf.d >= lim && leaf_needs(pr, &leaf.vals, &best, &thr, cert.tol_cos) {
                u += 1;
            }
        }
        per.push(u);
        leaves += pc.leaves.len();
        unresolved += u;
    }
    let mut bounds = results(row, &cert.alphas, lo, hi, &cert.witnesses, cases, probs);
    if cert.shard.is_some() {
        // A shard proves nothing about the row: its enclosures cover its own cases only,
        // so no verdict and no tightness is stated until `merge` has every shard.
        for b in &mut bounds {
            b.verdict = None;
            b.tight = None;
        }
    }
    Ok(Derived {
        unresolved_per_problem: per,
        leaves,
        unresolved,
        bounds,
    })
}

/// Fill every derived field of a certificate ([`derive`]).
pub(super) fn finish(
    cert: &mut Certificate,
    cases: &[Case],
    probs: &[Vec<Problem>],
) -> Result<(), String> {
    let d = derive(cert, cases, probs)?;
    for (pc, u) in cert.problems.iter_mut().zip(d.unresolved_per_problem) {
        pc.unresolved = u;
    }
    cert.leaves = d.leaves;
    cert.unresolved = d.unresolved;
    cert.partial = cert.shard.is_some();
    cert.bounds = d.bounds;
    Ok(())
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
