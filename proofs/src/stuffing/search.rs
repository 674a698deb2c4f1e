//! The search of the stuffing proof: a depth-first branch and bound per problem, pruned
//! against the best witnesses found so far.
//!
//! **Deterministic, whatever the sharding or the thread schedule.** Every run first
//! seeds the witnesses at the corners and centre of *every* problem of the row (cheap
//! point evaluations, the same in every shard); then each problem is searched on its own,
//! pruned against the seed and its own improvements only, never against what another
//! problem found meanwhile. So each problem's leaves depend on the row and the tolerance
//! alone, a shard holds exactly the problems of the unsharded run, and `proofs merge` of
//! all shards gives the unsharded certificate field for field (only the wall-clock
//! `seconds` differs). A certificate records the witnesses of its own problems only (so
//! a shard's enclosures speak of its own cases); the checker recomputes the row's seed
//! to re-apply the stopping rule. Ties between witnesses of equal cosine are broken by
//! [`prefer`]: the smaller (case, problem, output, point).
use super::cases::{self, Alphas};
use super::eval::Problem;
use super::safe::safe_property;
use super::summary::{depth_limit, finish, leaf_needs, thresholds};
use super::{
    all_problems, feeds, Certificate, Config, Leaf, ProblemCert, Witness, BOUNDS, FORMAT,
    MIN_TOL_DEG,
};
use crate::bnb::{Budget, BUDGET_ERROR};
use rayon::prelude::*;
use std::cmp::Ordering as Cmp;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Is witness `y` better than `x` for bound `b`: a larger cosine lower end for a lower
/// bound (a smaller angle), a smaller upper end for an upper bound; on a tie the smaller
/// (case, problem, output, point), so the choice never depends on the order of search.
pub(super) fn prefer(b: usize, y: &Witness, x: &Witness) -> bool {
    let by_cos = if BOUNDS[b].2 {
        y.cos[0].total_cmp(&x.cos[0])
    } else {
        x.cos[1].total_cmp(&y.cos[1])
    };
    match by_cos {
        Cmp::Greater => true,
        Cmp::Less => false,
        Cmp::Equal => {
            let key = |w: &Witness| (w.case, w.problem, w.output);
            match key(y).cmp(&key(x)) {
                Cmp::Less => true,
                Cmp::Greater => false,
                Cmp::Equal => {
                    y.x.iter()
                        .zip(&x.x)
                        .map(|(a, b)| a.total_cmp(b))
                        .find(|c| *c != Cmp::Equal)
                        == Some(Cmp::Less)
                }
            }
        }
    }
}

/// Fold candidate `y` into the witness slot of bound `b`.
pub(super) fn fold(slot: &mut Option<Witness>, b: usize, y: Witness) {
    match slot {
        Some(x) if !prefer(b, &y, x) => {}
        _ => *slot = Some(y),
    }
}

/// The witnesses of one search (the seed, or one problem's search on top of it).
#[derive(Clone)]
struct Best {
    /// Per bound: best witness cosine (max for lower bounds, min for upper bounds).
    best: [f64; 6],
    wit: Vec<Option<Witness>>,
}

impl Best {
    fn new() -> Best {
        Best {
            best: std::array::from_fn(|b| if BOUNDS[b].2 { -2.0 } else { 2.0 }),
            wit: vec![None; BOUNDS.len()],
        }
    }
    fn offer_witness(&mut self, b: usize, w: Witness) {
        fold(&mut self.wit[b], b, w);
        if let Some(x) = &self.wit[b] {
            self.best[b] = if BOUNDS[b].2 { x.cos[0] } else { x.cos[1] };
        }
    }
    fn offer(&mut self, pr: &Problem, pi: usize, x: &[f64], vals: &[inari::Interval]) {
        for (o, v) in vals.iter().enumerate() {
            for &b in feeds(pr.what) {
                let is_min = BOUNDS[b].2;
                let cand = if is_min { v.inf() } else { v.sup() };
                // Only a candidate at least as good as the current one can take the slot.
                let worse = if is_min {
                    cand < self.best[b]
                } else {
                    cand > self.best[b]
                };
                if worse {
                    continue;
                }
                self.offer_witness(
                    b,
                    Witness {
                        case: pr.case,
                        problem: pi,
                        output: o,
                        x: x.to_vec(),
                        cos: [v.inf(), v.sup()],
                    },
                );
            }
        }
    }
    fn merge(&mut self, other: Best) {
        for (b, w) in other.wit.into_iter().enumerate() {
            if let Some(w) = w {
                self.offer_witness(b, w);
            }
        }
    }
}

/// The row-wide pruning context: thresholds and tolerance.
struct Shared {
    thr: Vec<Vec<f64>>,
    tol: f64,
}

impl Shared {
    /// Could this box still change a bound or a threshold decision?
    fn needs(&self, best: &Best, pr: &Problem, vals: &[[f64; 2]]) -> bool {
        leaf_needs(pr, vals, &best.best, &self.thr, self.tol)
    }
}

/// The seed: corners and centre of every listed problem (the search prunes against the
/// seed of every problem of the row; a certificate records the seed of its own problems).
fn seed_over(list: &[(usize, &Problem)]) -> Best {
    list.par_iter()
        .map(|&(pi, pr)| {
            let mut b = Best::new();
            let (lo, hi) = (vec![0.0; pr.dim], vec![1.0; pr.dim]);
            let mut pts = corners(pr.dim, &lo, &hi);
            pts.push(vec![0.5; pr.dim]);
            for x in pts {
                if let Some(v) = pr.point(&x) {
                    b.offer(pr, pi, &x, &v);
                }
            }
            b
        })
        .reduce(Best::new, |mut a, b| {
            a.merge(b);
            a
        })
}

/// The per-bound best cosines of the seed of every problem of the row (what the search
/// pruned against; the checker re-applies the stopping rule with it).
pub(super) fn seed_best(probs: &[Vec<Problem>]) -> [f64; 6] {
    let all: Vec<(usize, &Problem)> = probs.iter().flat_map(|ps| ps.iter().enumerate()).collect();
    seed_over(&all).best
}

/// The better of two per-bound best cosines.
pub(super) fn better_of(a: [f64; 6], b: [f64; 6]) -> [f64; 6] {
    std::array::from_fn(|i| {
        if BOUNDS[i].2 {
            a[i].max(b[i])
        } else {
            a[i].min(b[i])
        }
    })
}

/// The box of a cell.
fn cell_box(d: u8, idx: &[u64]) -> (Vec<f64>, Vec<f64>) {
    Leaf {
        d,
        idx: idx.to_vec(),
        vals: Vec::new(),
    }
    .bounds()
}

fn corners(dim: usize, lo: &[f64], hi: &[f64]) -> Vec<Vec<f64>> {
    (0..1usize << dim)
        .map(|m| {
            (0..dim)
                .map(|k| if m >> k & 1 == 1 { hi[k] } else { lo[k] })
                .collect()
        })
        .collect()
}

fn solve(
    pr: &Problem,
    pi: usize,
    sh: &Shared,
    mut best: Best,
    max_depth: u8,
    budget: &Budget,
) -> Option<(ProblemCert, Best)> {
    let dim = pr.dim;
    // The witnesses this problem itself found (the certificate records these); `best`
    // also holds the row's seed, which the pruning uses.
    let mut own = Best::new();
    let lim = depth_limit(dim, max_depth);
    let mut leaves = Vec::new();
    let mut stack: Vec<(u8, Vec<u64>)> = vec![(0, vec![0; dim])];
    while let Some((d, idx)) = stack.pop() {
        if !budget.charge(1) {
            return None;
        }
        let (lo, hi) = cell_box(d, &idx);
        let vals: Vec<[f64; 2]> = pr
            .enclose(&lo, &hi)
            .iter()
            .map(|v| [v.inf(), v.sup()])
            .collect();
        let c: Vec<f64> = (0..dim).map(|k| 0.5 * (lo[k] + hi[k])).collect();
        if let Some(v) = pr.point(&c) {
            best.offer(pr, pi, &c, &v);
            own.offer(pr, pi, &c, &v);
        }
        if sh.needs(&best, pr, &vals) {
            // Extremes sit on the boundary of the box more often than not.
            for x in corners(dim, &lo, &hi) {
                if let Some(v) = pr.point(&x) {
                    best.offer(pr, pi, &x, &v);
                    own.offer(pr, pi, &x, &v);
                }
            }
        }
        let need = sh.needs(&best, pr, &vals);
        if need && d < lim {
            for m in 0..1usize << dim {
                let ch: Vec<u64> = (0..dim).map(|k| 2 * idx[k] + (m >> k & 1) as u64).collect();
                stack.push((d + 1, ch));
            }
        } else {
            leaves.push(Leaf { d, idx, vals }.to_vec());
        }
    }
    // The unresolved count is derived from the final witnesses ([`finish`]).
    Some((
        ProblemCert {
            case: pr.case,
            problem: pi,
            leaves,
            unresolved: 0,
        },
        own,
    ))
}

/// Run the proof of one row.
pub fn run(cfg: &Config) -> Result<Certificate, String> {
    let t0 = std::time::Instant::now();
    let row = cfg.row;
    let a = Alphas::of(row);
    let (cases, counts) = cases::output_cases(&a);
    let (probs, unreduced) = all_problems(row, &cases);
    if !(cfg.tol_deg.is_finite() && cfg.tol_deg >= MIN_TOL_DEG && cfg.tol_deg <= 90.0) {
        return Err(format!(
            "--tol-deg {}: must be in [{MIN_TOL_DEG:e}, 90] (below {MIN_TOL_DEG:e}° f64 interval arithmetic cannot reach the target)",
            cfg.tol_deg
        ));
    }
    let shard = match cfg.shard {
        Some((_, 1)) => None,
        s => s,
    };
    crate::gradnormal::check_shard(shard.map(|(i, n)| [i, n]))?;
    let in_shard = |ci: usize| shard.is_none_or(|(i, n)| ci % n == i);
    let mine: Vec<(usize, &Problem)> = probs
        .iter()
        .enumerate()
        .filter(|(ci, _)| in_shard(*ci))
        .flat_map(|(_, ps)| ps.iter().enumerate())
        .collect();
    let sh = Shared {
        thr: thresholds(row),
        tol: cfg.tol_cos(),
    };
    // The pruning seed covers every problem of the row, in every shard alike.
    let all: Vec<(usize, &Problem)> = probs.iter().flat_map(|ps| ps.iter().enumerate()).collect();
    let seeded = seed_over(&all);
    let done = AtomicUsize::new(0);
    let total = mine.len();
    let certs: Vec<Option<(ProblemCert, Best)>> = mine
        .par_iter()
        .map(|&(pi, pr)| {
            let c = solve(pr, pi, &sh, seeded.clone(), cfg.max_depth, &cfg.budget);
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            if cfg.progress && n % 2000 == 0 {
                eprintln!(
                    "  {} / {} problems, {:.0} s",
                    n,
                    total,
                    t0.elapsed().as_secs_f64()
                );
            }
            c
        })
        .collect();
    if cfg.budget.is_exhausted() {
        return Err(format!("{}: {}", BUDGET_ERROR, cfg.budget.message()));
    }
    // The certificate's witnesses: the seed of this run's own problems and what each of
    // them found (the fold is order-independent), so a shard's enclosures speak of its
    // own problems and the merge of all shards has the unsharded run's witnesses.
    let mut found = if shard.is_none() {
        seeded
    } else {
        seed_over(&mine)
    };
    let mut certs_out = Vec::with_capacity(certs.len());
    for (c, b) in certs.into_iter().flatten() {
        found.merge(b);
        certs_out.push(c);
    }
    let certs = certs_out;
    let witnesses = found.wit;
    let mut cert = Certificate {
        format: FORMAT.into(),
        row: row.name.into(),
        alphas: a,
        tol_cos: cfg.tol_cos(),
        max_depth: cfg.max_depth,
        counts,
        shard: shard.map(|(i, n)| [i, n]),
        partial: shard.is_some(),
        seconds: 0.0,
        unreduced,
        leaves: 0,
        unresolved: 0,
        problems: certs,
        witnesses,
        bounds: Vec::new(),
        safe: safe_property(row),
    };
    finish(&mut cert, &cases, &probs)?;
    cert.seconds = t0.elapsed().as_secs_f64();
    Ok(cert)
}
