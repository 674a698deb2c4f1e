//! `proofs check` and `proofs merge` for stuffing certificates.
use super::cases::Alphas;
use super::summary::{depth_limit, derive, final_best, finish, leaf_needs, thresholds};
use super::{feeds, BoundResult, Certificate, Leaf, SafeResult, Witness, BOUNDS, FORMAT};
use rayon::prelude::*;
use std::collections::HashSet;

/// What `check` found.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CheckReport {
    pub problems: usize,
    pub leaves: usize,
    pub complete: bool,
    pub bounds: Vec<BoundResult>,
    pub safe: SafeResult,
}

/// Partition check of a list of dyadic cells of [0,1]^dim.
pub(crate) fn check_partition(dim: usize, cells: &[(u8, Vec<u64>)]) -> Result<(), String> {
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

/// Re-verify a certificate independently of the search, field by field: re-derive the
/// row's parameters, the cases and the problems from the stencil table; check that
/// exactly the problems of the shard (all without one) are present, in order, and that
/// each one's leaves partition its box; re-evaluate every leaf and every witness (the
/// recorded values must be exactly the recomputed ones); re-apply the stopping rule with
/// the final witnesses; then recompute every derived field (unresolved counts, totals,
/// bounds, enclosures, verdicts, tightness, witness configurations, the safe property)
/// and reject the first one that differs, naming it. Only `seconds` is not recomputable.
pub fn check(cert: &Certificate) -> Result<CheckReport, String> {
    if cert.format != FORMAT {
        return Err(format!(
            "format: unknown certificate format `{}`",
            cert.format
        ));
    }
    let row = super::custom::resolve(&cert.row).map_err(|e| format!("row: {e}"))?;
    if row.name != cert.row {
        return Err(format!(
            "row: `{}` is not the row's name `{}`",
            cert.row, row.name
        ));
    }
    let a = Alphas::of(row);
    crate::fields::same("alphas", &cert.alphas, &a)?;
    let min_tol = 0.05 * super::MIN_TOL_DEG.to_radians();
    if !(cert.tol_cos.is_finite() && cert.tol_cos >= min_tol && cert.tol_cos <= 2.0) {
        return Err(format!(
            "tol_cos: {} outside [{min_tol:e}, 2] (below what f64 interval arithmetic reaches)",
            cert.tol_cos
        ));
    }
    if cert.max_depth > 60 {
        return Err(format!("max_depth: {} > 60", cert.max_depth));
    }
    crate::gradnormal::check_shard(cert.shard).map_err(|e| format!("shard: {e}"))?;
    if cert.partial != cert.shard.is_some() {
        return Err(format!(
            "partial: the certificate states {}, but shard is {:?}",
            cert.partial, cert.shard
        ));
    }
    let tables = super::tables(row);
    let (cases, counts, probs, unreduced) = (
        &tables.cases,
        &tables.counts,
        &tables.probs,
        &tables.unreduced,
    );
    crate::fields::same("counts", &cert.counts, counts)?;
    crate::fields::same("unreduced", &cert.unreduced, unreduced)?;
    let in_shard = |ci: usize| cert.shard.is_none_or(|[i, n]| ci % n == i);
    let expected: Vec<(usize, usize)> = probs
        .iter()
        .enumerate()
        .filter(|(ci, _)| in_shard(*ci))
        .flat_map(|(ci, ps)| (0..ps.len()).map(move |pi| (ci, pi)))
        .collect();
    let got: Vec<(usize, usize)> = cert.problems.iter().map(|p| (p.case, p.problem)).collect();
    if got != expected {
        let at = got
            .iter()
            .zip(&expected)
            .position(|(x, y)| x != y)
            .unwrap_or(got.len().min(expected.len()));
        return Err(format!(
            "problems: the certificate lists {} problems, the stencil table gives {} (for this shard), in (case, problem) order; first difference at problems[{at}]: {:?} vs {:?}",
            got.len(),
            expected.len(),
            got.get(at),
            expected.get(at)
        ));
    }
    if cert.witnesses.len() != BOUNDS.len() {
        return Err(format!(
            "witnesses: {} entries for {} bounds",
            cert.witnesses.len(),
            BOUNDS.len()
        ));
    }
    // Witnesses: re-evaluated, must lie in a problem (of this shard) feeding their bound.
    for (b, w) in cert.witnesses.iter().enumerate() {
        let Some(w) = w else { continue };
        let name = format!("witnesses[{b}] ({})", BOUNDS[b].0);
        if !in_shard(w.case) {
            return Err(format!("{name}.case: {} is not in this shard", w.case));
        }
        let pr = probs
            .get(w.case)
            .and_then(|p| p.get(w.problem))
            .ok_or_else(|| format!("{name}: names a problem that does not exist"))?;
        if !feeds(pr.what).contains(&b) || w.output >= pr.n_out() || w.x.len() != pr.dim {
            return Err(format!("{name}: malformed (problem, output or dimension)"));
        }
        if w.x.iter().any(|x| !(0.0..=1.0).contains(x)) {
            return Err(format!("{name}.x: outside its parameter box"));
        }
        let v = pr
            .point(&w.x)
            .ok_or_else(|| format!("{name}: undefined at its point"))?[w.output];
        if w.cos != [v.inf(), v.sup()] {
            return Err(format!(
                "{name}.cos: recorded {:?}, recomputed [{}, {}]",
                w.cos,
                v.inf(),
                v.sup()
            ));
        }
    }
    let thr = thresholds(row);
    // The stopping rule is re-applied against what the search pruned with: the final
    // witnesses and the seed of every problem of the row (recomputed here; for a whole
    // row the witnesses already include it, for a shard it comes from other shards too).
    let best =
        super::search::better_of(final_best(&cert.witnesses), super::search::seed_best(probs));
    // Cheap checks first: leaf format, partition, depth limit, stopping rule; then
    // every derived field; then the re-evaluation of every leaf (the expensive part).
    let parsed: Vec<Result<Vec<Leaf>, String>> = cert
        .problems
        .par_iter()
        .enumerate()
        .map(|(i, pc)| {
            let pr = &probs[pc.case][pc.problem];
            let leaves = pc
                .leaves
                .iter()
                .enumerate()
                .map(|(j, l)| {
                    Leaf::from_vec(l, pr.dim, pr.n_out())
                        .map_err(|e| format!("problems[{i}].leaves[{j}]: {e}"))
                })
                .collect::<Result<Vec<Leaf>, String>>()?;
            check_partition(
                pr.dim,
                &leaves.iter().map(|l| (l.d, l.idx.clone())).collect::<Vec<_>>(),
            )
            .map_err(|e| {
                format!(
                    "problems[{i}].leaves (case {} problem {}): {e}",
                    pc.case, pc.problem
                )
            })?;
            let lim = depth_limit(pr.dim, cert.max_depth);
            for (j, l) in leaves.iter().enumerate() {
                if l.d > lim {
                    return Err(format!(
                        "problems[{i}].leaves[{j}]: depth {} beyond the depth limit {lim} (max_depth)",
                        l.d
                    ));
                }
                if l.d < lim && leaf_needs(pr, &l.vals, &best, &thr, cert.tol_cos) {
                    return Err(format!(
                        "problems[{i}].leaves[{j}]: refinement stopped at depth {} < {lim} although the leaf could still change a bound by more than tol_cos = {} or a threshold decision",
                        l.d, cert.tol_cos
                    ));
                }
            }
            Ok(leaves)
        })
        .collect();
    let mut all_leaves = Vec::with_capacity(parsed.len());
    for r in parsed {
        all_leaves.push(r?);
    }
    // Every derived field, recomputed from the leaves and witnesses.
    let re = derive(cert, cases, probs)?;
    for (i, (s, r)) in cert
        .problems
        .iter()
        .zip(&re.unresolved_per_problem)
        .enumerate()
    {
        crate::fields::same(&format!("problems[{i}].unresolved"), &s.unresolved, r)?;
    }
    crate::fields::same("leaves", &cert.leaves, &re.leaves)?;
    crate::fields::same("unresolved", &cert.unresolved, &re.unresolved)?;
    crate::fields::same("bounds", &cert.bounds, &re.bounds)?;
    let safe = tables.safe.clone();
    crate::fields::same("safe", &cert.safe, &safe)?;
    // Every leaf re-evaluated: the recorded bounds must be exactly the recomputed ones.
    let evals: Vec<Result<usize, String>> = cert
        .problems
        .par_iter()
        .zip(&all_leaves)
        .enumerate()
        .map(|(i, (pc, leaves))| {
            let pr = &probs[pc.case][pc.problem];
            for (j, l) in leaves.iter().enumerate() {
                let (blo, bhi) = l.bounds();
                let v: Vec<[f64; 2]> = pr
                    .enclose(&blo, &bhi)
                    .iter()
                    .map(|x| [x.inf(), x.sup()])
                    .collect();
                if v != l.vals {
                    return Err(format!(
                        "problems[{i}].leaves[{j}] (case {} problem {} cell {}/{:?}): recorded {:?}, recomputed {:?}",
                        pc.case, pc.problem, l.d, l.idx, l.vals, v
                    ));
                }
            }
            Ok(leaves.len())
        })
        .collect();
    let mut n_leaves = 0;
    for r in evals {
        n_leaves += r?;
    }
    Ok(CheckReport {
        problems: cert.problems.len(),
        leaves: n_leaves,
        complete: cert.shard.is_none(),
        bounds: re.bounds,
        safe,
    })
}

/// Merge the shard certificates of one row into one: the shards must be i/N for every
/// i in 0..N of one N, each exactly once (complete and disjoint), of the same run
/// parameters, and each must hold exactly its shard's problems. The derived fields are
/// recomputed for the whole row.
pub fn merge(parts: Vec<Certificate>) -> Result<Certificate, String> {
    let mut it = parts.into_iter();
    let mut out = it.next().ok_or("nothing to merge")?;
    let n = match out.shard {
        Some([_, n]) if n >= 2 => n,
        _ => return Err("merge: the first certificate is not a shard".into()),
    };
    let row = super::custom::resolve(&out.row)?;
    if Alphas::of(row) != out.alphas {
        return Err("merge: the row's parameters differ from the certificate's".into());
    }
    let tables = super::tables(row);
    let (cases, probs) = (&tables.cases, &tables.probs);
    let mut shards: Vec<usize> = Vec::new();
    let mut all = Vec::new();
    let mut witnesses: Vec<Option<Witness>> = vec![None; BOUNDS.len()];
    let first = std::mem::take(&mut out.problems);
    let first_w = std::mem::take(&mut out.witnesses);
    let mut seconds = 0.0;
    for p in std::iter::once((out.shard, first, first_w, out.seconds, None)).chain(it.map(|p| {
        (
            p.shard,
            p.problems.clone(),
            p.witnesses.clone(),
            p.seconds,
            Some(p),
        )
    })) {
        let (shard, problems, ws, secs, cert) = p;
        if let Some(c) = &cert {
            if c.format != out.format
                || c.row != out.row
                || c.alphas != out.alphas
                || c.tol_cos != out.tol_cos
                || c.max_depth != out.max_depth
                || c.counts != out.counts
                || c.unreduced != out.unreduced
            {
                return Err(
                    "certificates of different runs (row, tolerance or depth differ)".into(),
                );
            }
        }
        let i = match shard {
            Some([i, m]) if m == n && i < m => i,
            s => return Err(format!("merge: shard {s:?} is not i/{n}")),
        };
        let idx: Vec<(usize, usize)> = problems.iter().map(|p| (p.case, p.problem)).collect();
        let expect: Vec<(usize, usize)> = probs
            .iter()
            .enumerate()
            .filter(|(ci, _)| ci % n == i)
            .flat_map(|(ci, ps)| (0..ps.len()).map(move |pi| (ci, pi)))
            .collect();
        if idx != expect {
            return Err(format!(
                "merge: shard {i}/{n} holds {} problems, its shard of the stencil table has {}",
                idx.len(),
                expect.len()
            ));
        }
        shards.push(i);
        seconds += secs;
        all.extend(problems);
        for b in 0..BOUNDS.len() {
            if let Some(y) = ws.get(b).cloned().flatten() {
                super::search::fold(&mut witnesses[b], b, y);
            }
        }
    }
    let mut sorted = shards.clone();
    sorted.sort_unstable();
    if sorted != (0..n).collect::<Vec<_>>() {
        return Err(format!(
            "merge: the shards {shards:?} are not 0..{n}, each exactly once (incomplete or overlapping)"
        ));
    }
    all.sort_by_key(|p| (p.case, p.problem));
    out.problems = all;
    out.witnesses = witnesses;
    out.seconds = seconds;
    out.shard = None;
    finish(&mut out, cases, probs)?;
    Ok(out)
}
