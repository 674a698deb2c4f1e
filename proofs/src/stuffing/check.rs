//! `proofs check` and `proofs merge` for stuffing certificates.
use super::cases::{self, Alphas};
use super::safe::safe_property;
use super::summary::{results, summarize};
use super::{
    all_problems, feeds, BoundResult, Certificate, Leaf, SafeResult, Witness, BOUNDS, FORMAT,
};
use rayon::prelude::*;
use std::collections::HashSet;

/// What `check` found.
#[derive(Clone, Debug)]
pub struct CheckReport {
    pub problems: usize,
    pub leaves: usize,
    pub complete: bool,
    pub bounds: Vec<BoundResult>,
    pub safe: SafeResult,
}

/// Partition check of a list of dyadic cells of [0,1]^dim.
fn check_partition(dim: usize, cells: &[(u8, Vec<u64>)]) -> Result<(), String> {
    if dim == 0 {
        return if cells.len() == 1 {
            Ok(())
        } else {
            Err("a 0-dimensional problem needs exactly one leaf".into())
        };
    }
    let maxd = cells.iter().map(|c| c.0).max().unwrap_or(0) as u32;
    if maxd as usize * dim > 126 {
        return Err("leaf too deep".into());
    }
    let set: HashSet<(u8, Vec<u64>)> = cells.iter().cloned().collect();
    if set.len() != cells.len() {
        return Err("duplicate leaf".into());
    }
    let mut vol: u128 = 0;
    for (d, idx) in cells {
        let (mut pd, mut pi) = (*d, idx.clone());
        while pd > 0 {
            pd -= 1;
            for x in &mut pi {
                *x /= 2;
            }
            if set.contains(&(pd, pi.clone())) {
                return Err(format!("leaf {d}/{idx:?} overlaps another leaf"));
            }
        }
        vol += 1u128 << (dim as u32 * (maxd - *d as u32));
    }
    if vol != 1u128 << (dim as u32 * maxd) {
        return Err("leaves do not cover the parameter box".into());
    }
    Ok(())
}

/// Re-verify a certificate independently of the search: re-derive the cases and
/// problems from the stencil table, check that every problem (of the shard) is present
/// and its leaves partition its box, re-evaluate every leaf and every witness, recompute
/// the enclosures, the verdicts (exactly) and the safe property.
pub fn check(cert: &Certificate) -> Result<CheckReport, String> {
    if cert.format != FORMAT {
        return Err(format!("unknown certificate format `{}`", cert.format));
    }
    let row = certmesh::stuffing::row(&cert.row).map_err(|e| e.to_string())?;
    let a = Alphas::of(row);
    if a != cert.alphas {
        return Err("the row's parameters differ from the certificate's".into());
    }
    let (cases, counts) = cases::output_cases(&a);
    if counts != cert.counts {
        return Err(format!(
            "the stencil table gives {counts:?} cases, the certificate says {:?}",
            cert.counts
        ));
    }
    let (probs, unreduced) = all_problems(row, &cases);
    if unreduced != cert.unreduced {
        return Err("the reduction's precondition differs".into());
    }
    let in_shard = |ci: usize| cert.shard.is_none_or(|[i, n]| n > 0 && ci % n == i);
    let mut expected: HashSet<(usize, usize)> = HashSet::new();
    for (ci, ps) in probs.iter().enumerate() {
        if in_shard(ci) {
            for pi in 0..ps.len() {
                expected.insert((ci, pi));
            }
        }
    }
    let seen: HashSet<(usize, usize)> = cert.problems.iter().map(|p| (p.case, p.problem)).collect();
    if seen.len() != cert.problems.len() {
        return Err("a problem is listed twice".into());
    }
    if seen != expected {
        return Err(format!(
            "the certificate covers {} problems, the stencil table gives {} (for this shard)",
            seen.len(),
            expected.len()
        ));
    }
    let per_problem: Vec<Result<([f64; 6], [f64; 6], usize), String>> = cert
        .problems
        .par_iter()
        .map(|pc| {
            let pr = &probs[pc.case][pc.problem];
            let leaves = pc
                .leaves
                .iter()
                .map(|l| Leaf::from_vec(l, pr.dim, pr.n_out()))
                .collect::<Result<Vec<Leaf>, String>>()?;
            check_partition(
                pr.dim,
                &leaves.iter().map(|l| (l.d, l.idx.clone())).collect::<Vec<_>>(),
            )
            .map_err(|e| format!("case {} problem {}: {e}", pc.case, pc.problem))?;
            let mut lo = [f64::INFINITY; 6];
            let mut hi = [f64::NEG_INFINITY; 6];
            for l in &leaves {
                let (blo, bhi) = l.bounds();
                let v = pr.enclose(&blo, &bhi);
                for (k, x) in v.iter().enumerate() {
                    let r = l.vals[k];
                    if !(r[0] <= x.inf() && x.sup() <= r[1]) {
                        return Err(format!(
                            "case {} problem {} leaf {:?}: recorded {:?} does not contain the recomputed [{}, {}]",
                            pc.case, pc.problem, l.idx, r, x.inf(), x.sup()
                        ));
                    }
                    for &b in feeds(pr.what) {
                        lo[b] = lo[b].min(x.inf());
                        hi[b] = hi[b].max(x.sup());
                    }
                }
            }
            Ok((lo, hi, leaves.len()))
        })
        .collect();
    let mut lo = [f64::INFINITY; 6];
    let mut hi = [f64::NEG_INFINITY; 6];
    let mut n_leaves = 0;
    for r in per_problem {
        let (l, h, n) = r?;
        n_leaves += n;
        for b in 0..6 {
            lo[b] = lo[b].min(l[b]);
            hi[b] = hi[b].max(h[b]);
        }
    }
    // Witnesses: re-evaluated, must lie in a problem feeding their bound.
    let mut wit = Vec::new();
    for (b, w) in cert.witnesses.iter().enumerate() {
        let Some(w) = w else {
            wit.push(None);
            continue;
        };
        let pr = probs
            .get(w.case)
            .and_then(|p| p.get(w.problem))
            .ok_or("witness names a problem that does not exist")?;
        if !feeds(pr.what).contains(&b) || w.output >= pr.n_out() || w.x.len() != pr.dim {
            return Err(format!("witness of {} is malformed", BOUNDS[b].0));
        }
        if w.x.iter().any(|x| !(0.0..=1.0).contains(x)) {
            return Err("witness outside its parameter box".into());
        }
        let v = pr.point(&w.x).ok_or("witness undefined")?[w.output];
        if !(w.cos[0] <= v.inf() && v.sup() <= w.cos[1]) {
            return Err(format!(
                "witness of {}: recorded {:?} does not contain the recomputed [{}, {}]",
                BOUNDS[b].0,
                w.cos,
                v.inf(),
                v.sup()
            ));
        }
        wit.push(Some(Witness {
            cos: [v.inf(), v.sup()],
            ..w.clone()
        }));
    }
    let bounds = results(row, &a, lo, hi, &wit, &cases, &probs);
    // The stated enclosures must contain the recomputed ones, the verdicts agree.
    for (s, r) in cert.bounds.iter().zip(&bounds) {
        if r.verdict != s.verdict {
            return Err(format!(
                "{}: stated verdict {:?}, recomputed {:?}",
                s.bound, s.verdict, r.verdict
            ));
        }
        let ok = match (s.cos, r.cos) {
            (Some(s), Some(r)) => s[0] <= r[0] && r[1] <= s[1],
            (None, None) => true,
            _ => false,
        };
        if !ok {
            return Err(format!(
                "{}: stated enclosure {:?} does not contain the recomputed {:?}",
                s.bound, s.cos, r.cos
            ));
        }
    }
    let safe = safe_property(row);
    if safe != cert.safe {
        return Err("the safe property's result differs".into());
    }
    Ok(CheckReport {
        problems: cert.problems.len(),
        leaves: n_leaves,
        complete: cert.shard.is_none(),
        bounds,
        safe,
    })
}

/// Merge shard certificates of one row into one.
pub fn merge(parts: Vec<Certificate>) -> Result<Certificate, String> {
    let mut it = parts.into_iter();
    let mut out = it.next().ok_or("nothing to merge")?;
    let mut shards: Vec<Option<[usize; 2]>> = vec![out.shard];
    for p in it {
        if p.format != out.format
            || p.row != out.row
            || p.tol_cos != out.tol_cos
            || p.max_depth != out.max_depth
            || p.counts != out.counts
        {
            return Err("certificates of different runs (row, tolerance or depth differ)".into());
        }
        shards.push(p.shard);
        out.seconds += p.seconds;
        out.leaves += p.leaves;
        out.unresolved += p.unresolved;
        out.problems.extend(p.problems);
        for b in 0..6 {
            let is_min = BOUNDS[b].2;
            out.witnesses[b] = match (out.witnesses[b].take(), p.witnesses[b].clone()) {
                (Some(x), Some(y)) => {
                    let take_y = if is_min {
                        y.cos[0] > x.cos[0]
                    } else {
                        y.cos[1] < x.cos[1]
                    };
                    Some(if take_y { y } else { x })
                }
                (x, y) => x.or(y),
            };
        }
    }
    // Complete when the shards are 0..N of one N.
    let n = shards.first().copied().flatten().map(|s| s[1]);
    let complete = match n {
        Some(n) => {
            let mut got: Vec<usize> = shards.iter().flatten().map(|s| s[0]).collect();
            got.sort_unstable();
            got.dedup();
            shards.iter().all(|s| s.is_some_and(|s| s[1] == n)) && got == (0..n).collect::<Vec<_>>()
        }
        None => false,
    };
    if !complete {
        return Err("the shards are not 0..N of one N".into());
    }
    out.shard = None;
    let row = certmesh::stuffing::row(&out.row).map_err(|e| e.to_string())?;
    let (cases, _) = cases::output_cases(&out.alphas);
    let (probs, _) = all_problems(row, &cases);
    out.problems.sort_by_key(|p| (p.case, p.problem));
    out.bounds = summarize(&out, &cases, &probs)?;
    Ok(out)
}
