//! The search of the stuffing proof: one global best witness per bound shared by all
//! problems, and a depth-first branch and bound per problem.
use super::cases::{self, Alphas};
use super::eval::Problem;
use super::safe::safe_property;
use super::summary::{depth_limit, finish, leaf_needs, thresholds};
use super::{
    all_problems, feeds, Certificate, Config, Leaf, ProblemCert, Witness, BOUNDS, FORMAT,
    MIN_TOL_DEG,
};
use crate::bnb::{Budget, BUDGET_ERROR};
use certmesh::stuffing::params::Row;
use inari::Interval;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;

struct Shared {
    /// Per bound: best witness cosine (max for lower bounds, min for upper bounds).
    best: Vec<AtomicU64>,
    wit: Mutex<Vec<Option<Witness>>>,
    thr: Vec<Vec<f64>>,
    tol: f64,
}

fn load(a: &AtomicU64) -> f64 {
    f64::from_bits(a.load(Ordering::Relaxed))
}

impl Shared {
    fn new(row: &Row, tol: f64) -> Shared {
        Shared {
            best: BOUNDS
                .iter()
                .map(|&(_, _, is_min)| AtomicU64::new(if is_min { -2.0f64 } else { 2.0 }.to_bits()))
                .collect(),
            wit: Mutex::new(vec![None; 6]),
            thr: thresholds(row),
            tol,
        }
    }
    fn offer(&self, pr: &Problem, pi: usize, x: &[f64], vals: &[Interval]) {
        for (o, v) in vals.iter().enumerate() {
            for &b in feeds(pr.what) {
                let is_min = BOUNDS[b].2;
                let cand = if is_min { v.inf() } else { v.sup() };
                let cur = load(&self.best[b]);
                let better = if is_min { cand > cur } else { cand < cur };
                if better {
                    let mut w = self.wit.lock().unwrap_or_else(|e| e.into_inner());
                    let cur = load(&self.best[b]);
                    if (is_min && cand > cur) || (!is_min && cand < cur) {
                        self.best[b].store(cand.to_bits(), Ordering::Relaxed);
                        w[b] = Some(Witness {
                            case: pr.case,
                            problem: pi,
                            output: o,
                            x: x.to_vec(),
                            cos: [v.inf(), v.sup()],
                        });
                    }
                }
            }
        }
    }
    /// Could this box still change a bound or a threshold decision?
    fn needs(&self, pr: &Problem, vals: &[[f64; 2]]) -> bool {
        let best: [f64; 6] = std::array::from_fn(|b| load(&self.best[b]));
        leaf_needs(pr, vals, &best, &self.thr, self.tol)
    }
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
    max_depth: u8,
    budget: &Budget,
) -> Option<ProblemCert> {
    let dim = pr.dim;
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
            sh.offer(pr, pi, &c, &v);
        }
        if sh.needs(pr, &vals) {
            // Extremes sit on the boundary of the box more often than not.
            for x in corners(dim, &lo, &hi) {
                if let Some(v) = pr.point(&x) {
                    sh.offer(pr, pi, &x, &v);
                }
            }
        }
        let need = sh.needs(pr, &vals);
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
    Some(ProblemCert {
        case: pr.case,
        problem: pi,
        leaves,
        unresolved: 0,
    })
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
    let sh = Shared::new(row, cfg.tol_cos());
    // Seed the global witnesses at the corners and centre of every problem.
    mine.par_iter().for_each(|&(pi, pr)| {
        let (lo, hi) = (vec![0.0; pr.dim], vec![1.0; pr.dim]);
        let mut pts = corners(pr.dim, &lo, &hi);
        pts.push(vec![0.5; pr.dim]);
        for x in pts {
            if let Some(v) = pr.point(&x) {
                sh.offer(pr, pi, &x, &v);
            }
        }
    });
    let done = AtomicUsize::new(0);
    let total = mine.len();
    let certs: Vec<Option<ProblemCert>> = mine
        .par_iter()
        .map(|&(pi, pr)| {
            let c = solve(pr, pi, &sh, cfg.max_depth, &cfg.budget);
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
    let certs: Vec<ProblemCert> = certs.into_iter().flatten().collect();
    let witnesses = sh.wit.into_inner().unwrap_or_else(|e| e.into_inner());
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
