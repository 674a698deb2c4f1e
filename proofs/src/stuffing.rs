//! `proofs stuffing`: certify the six angle bounds of every row of Table 1 of Labelle &
//! Shewchuk 2007 (Theorem 1, §4.1) on the mesher's own stencil table, and the "safe"
//! property (no BCC tetrahedron inverts).
//!
//! Method (§4.1): the configuration space is cut into cases ([`crate::stuffing_cases`]);
//! each case becomes branch-and-bound problems ([`crate::stuffing_eval`]): the dihedral
//! angle at each edge `ab` with the other two vertices at the ends of their segments
//! (the paper's reduction: a quadtree over the parameters of `a` and `b`), valid because
//! the case's tetrahedron is proven never flat — its signed volume is multilinear in the
//! parameters, so its sign over the whole box is decided exactly at the box corners
//! ([`crate::stuffing_cases::volume_range`]); where that fails, the dihedral is searched
//! over all parameters without the reduction. Plane angles: an octree over the (at most
//! three) parameters of each face.
//!
//! The search is global: one best witness per bound is shared by all problems, and a box
//! is final when it can improve no bound by more than the tolerance *and* it decides the
//! paper's value and the paper's tightness margin (value ± 0.0001°) either way. So a
//! verdict is undecided only when the true extreme equals the paper's value exactly (or
//! the depth limit is hit: reported as `unresolved`).
//!
//! Verdict rule (the paper: "lower bounds are rounded down; upper bounds are rounded
//! up"): a lower bound B is *proven* when every angle is certified ≥ B, *refuted* when a
//! witness angle is certified < B; an upper bound symmetrically; the comparison is exact
//! (rational enclosures of cos B, [`crate::exact`]). Tightness ("tight to within
//! 0.0001°"): *attained* when a witness is certified within 0.0001° of B, *not attained*
//! when every angle is certified farther than that.
use crate::exact::{self, Verdict};
use crate::stuffing_cases::{self, Alphas, Case, Counts, Kind, Seg, DEN};
use crate::stuffing_eval::{problems, Problem, What};
use certmesh::stuffing::params::{Row, TABLE1};
use inari::Interval;
use num_rational::BigRational;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;

pub const FORMAT: &str = "certmesh-proofs/stuffing/1";

/// The six bounds of a row: (name, kind, is a lower bound). Kind 0 = dihedral,
/// 1 = plane angle of any face, 2 = plane angle of exposed faces.
pub const BOUNDS: [(&str, usize, bool); 6] = [
    ("min_dihedral", 0, true),
    ("max_dihedral", 0, false),
    ("min_plane", 1, true),
    ("max_plane", 1, false),
    ("min_exposed", 2, true),
    ("max_exposed", 2, false),
];

/// The tightness margin of Theorem 1, in degrees (as a decimal string: exact).
pub const MARGIN: &str = "0.0001";

#[derive(Clone, Debug)]
pub struct Config {
    pub row: &'static Row,
    /// Target width of every extreme's enclosure, degrees.
    pub tol_deg: f64,
    pub max_depth: u8,
    pub shard: Option<(usize, usize)>,
    pub progress: bool,
}

impl Config {
    pub fn new(row: &'static Row) -> Config {
        Config {
            row,
            tol_deg: 1e-4,
            max_depth: 40,
            shard: None,
            progress: false,
        }
    }
    /// The tolerance on cosines: d(cos θ) = sin θ dθ and every bound of Table 1 lies in
    /// [5°, 170°], where sin θ > 0.087; 0.05 leaves a margin.
    pub fn tol_cos(&self) -> f64 {
        0.05 * self.tol_deg.to_radians()
    }
}

/// The row's paper values per bound (None = n/a).
pub fn paper_values(row: &Row) -> [Option<f64>; 6] {
    row.bounds.entries()
}

/// The decimal string of a Table 1 value (four decimals, exact).
pub fn decimal_of(x: f64) -> String {
    format!("{x:.4}")
}

/// Which bounds an output of a problem feeds.
fn feeds(w: What) -> &'static [usize] {
    match w {
        What::Dihedral => &[0, 1],
        What::Face { exposed: false } => &[2, 3],
        What::Face { exposed: true } => &[2, 3, 4, 5],
    }
}

/// A leaf: its dyadic cell (depth, indices) and the cosine bounds of each output.
/// Serialised as one array `[depth, i_0, …, i_{dim−1}, lo_0, hi_0, …]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Leaf {
    pub d: u8,
    pub idx: Vec<u64>,
    pub vals: Vec<[f64; 2]>,
}

impl Leaf {
    pub fn to_vec(&self) -> Vec<f64> {
        let mut v = vec![self.d as f64];
        v.extend(self.idx.iter().map(|&i| i as f64));
        for [a, b] in &self.vals {
            v.push(*a);
            v.push(*b);
        }
        v
    }
    pub fn from_vec(v: &[f64], dim: usize, n_out: usize) -> Result<Leaf, String> {
        if v.len() != 1 + dim + 2 * n_out {
            return Err(format!("malformed leaf of length {}", v.len()));
        }
        let int = crate::bnb::leaf_index;
        let d = int(v[0])?;
        if d > 60 {
            return Err(format!("leaf depth {d}"));
        }
        let idx = v[1..1 + dim]
            .iter()
            .map(|&x| int(x))
            .collect::<Result<Vec<u64>, String>>()?;
        if idx.iter().any(|&i| i >= 1u64 << d) {
            return Err("leaf index out of range".into());
        }
        let vals = v[1 + dim..].chunks(2).map(|c| [c[0], c[1]]).collect();
        Ok(Leaf {
            d: d as u8,
            idx,
            vals,
        })
    }
    /// The box (exact dyadic bounds).
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let s = 0.5f64.powi(self.d as i32);
        (
            self.idx.iter().map(|&i| i as f64 * s).collect(),
            self.idx.iter().map(|&i| (i + 1) as f64 * s).collect(),
        )
    }
}

/// A point of a problem with the enclosure of one output there.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Witness {
    pub case: usize,
    pub problem: usize,
    pub output: usize,
    pub x: Vec<f64>,
    /// Enclosure of the cosine at the point.
    pub cos: [f64; 2],
}

/// The certificate of one problem.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ProblemCert {
    pub case: usize,
    pub problem: usize,
    pub leaves: Vec<Vec<f64>>,
    pub unresolved: usize,
}

/// A certified bound.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoundResult {
    pub bound: String,
    pub paper: Option<f64>,
    /// Enclosure of the true extreme's cosine: [lo, hi].
    pub cos: Option<[f64; 2]>,
    /// Enclosure of the true extreme in degrees (display; rounded outward by 1e-12°).
    pub deg: Option<[f64; 2]>,
    pub verdict: Option<Verdict>,
    /// "attained" | "not attained" | "unknown" (within 0.0001° of the paper's value).
    pub tight: Option<String>,
    pub witness: Option<Witness>,
    /// The witness configuration: case vertices (units of the black edge length h).
    pub witness_config: Option<[[f64; 3]; 4]>,
    pub witness_case: Option<[Seg; 4]>,
}

/// The safe property: the minimum signed volume of a warped BCC tetrahedron.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SafeResult {
    pub counts: Counts,
    /// min and max of 6·volume/(6·volume of the unwarped tetrahedron), exact ratio as f64.
    pub min_ratio: f64,
    /// Minimum 6·volume in units of h³ (doubled coordinates halved).
    pub min_volume_h3: f64,
    pub verdict: Verdict,
    pub note: String,
    pub witness_case: [Seg; 4],
    pub witness_t: [f64; 4],
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Certificate {
    pub format: String,
    pub row: String,
    pub alphas: Alphas,
    pub tol_cos: f64,
    pub max_depth: u8,
    pub counts: Counts,
    pub shard: Option<[usize; 2]>,
    pub seconds: f64,
    /// Cases whose dihedrals were searched without the reduction (volume may vanish).
    pub unreduced: Vec<usize>,
    pub problems: Vec<ProblemCert>,
    pub witnesses: Vec<Option<Witness>>,
    pub bounds: Vec<BoundResult>,
    pub safe: SafeResult,
    pub leaves: usize,
    pub unresolved: usize,
}

/// Does the row state dihedral bounds (min-exposed-unsafe: n/a, its tetrahedra can be flat)?
fn has_dihedrals(row: &Row) -> bool {
    row.bounds.min_dihedral.is_some() || row.bounds.max_dihedral.is_some()
}

/// The problems of every case, with the reduction decided exactly per case.
pub fn all_problems(row: &Row, cases: &[Case]) -> (Vec<Vec<Problem>>, Vec<usize>) {
    let a = Alphas::of(row);
    let dih = has_dihedrals(row);
    let mut unreduced = Vec::new();
    let probs = cases
        .iter()
        .enumerate()
        .map(|(ci, c)| {
            let (r, _) = stuffing_cases::volume_range(c, &a);
            let reduce = r[0] > 0 || r[1] < 0;
            if !reduce && dih {
                unreduced.push(ci);
            }
            problems(ci, c, &a, dih, reduce)
        })
        .collect();
    (probs, unreduced)
}

/// Cosine thresholds per bound: the paper's value and the tightness margin.
fn thresholds(row: &Row) -> Vec<Vec<f64>> {
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
    fn needs(&self, pr: &Problem, vals: &[Interval]) -> bool {
        vals.iter().any(|v| {
            feeds(pr.what).iter().any(|&b| {
                let is_min = BOUNDS[b].2;
                let best = load(&self.best[b]);
                if is_min {
                    v.sup() > best + self.tol
                        || self.thr[b].iter().any(|&c| best <= c && v.sup() > c)
                } else {
                    v.inf() < best - self.tol
                        || self.thr[b].iter().any(|&c| best >= c && v.inf() < c)
                }
            })
        })
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

/// The depth limit of a problem (the partition check sums volumes in u128).
fn depth_limit(dim: usize, max_depth: u8) -> u8 {
    if dim == 0 {
        0
    } else {
        max_depth.min((120 / dim) as u8)
    }
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

fn solve(pr: &Problem, pi: usize, sh: &Shared, max_depth: u8) -> ProblemCert {
    let dim = pr.dim;
    let lim = depth_limit(dim, max_depth);
    let mut leaves = Vec::new();
    let mut unresolved = 0;
    let mut stack: Vec<(u8, Vec<u64>)> = vec![(0, vec![0; dim])];
    while let Some((d, idx)) = stack.pop() {
        let (lo, hi) = cell_box(d, &idx);
        let vals = pr.enclose(&lo, &hi);
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
            if need {
                unresolved += 1;
            }
            leaves.push(
                Leaf {
                    d,
                    idx,
                    vals: vals.iter().map(|v| [v.inf(), v.sup()]).collect(),
                }
                .to_vec(),
            );
        }
    }
    ProblemCert {
        case: pr.case,
        problem: pi,
        leaves,
        unresolved,
    }
}

/// The safe property, decided exactly at the corners of every warped-BCC case.
pub fn safe_property(row: &Row) -> SafeResult {
    let a = Alphas::of(row);
    let (cases, counts) = stuffing_cases::bcc_cases(&a);
    let unwarped = 4i128 * (DEN as i128).pow(3);
    let mut min = (i128::MAX, 0usize, [0i64; 4]);
    for (i, c) in cases.iter().enumerate() {
        let (r, t) = stuffing_cases::volume_range(c, &a);
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

fn strictly_positive_on_real_set(c: &Case, a: &Alphas) -> bool {
    let ranges = c.v.map(|s| a.range(&s));
    for m in 0..16u32 {
        let top = |k: usize| m >> k & 1 == 1;
        // Corners of the real set: no warp parameter at an unattainable top.
        let real =
            (0..4).all(|k| c.v[k].kind != Kind::Warp || !top(k) || top_attainable(&c.v[k], a));
        let t: [i64; 4] = [0, 1, 2, 3].map(|k| ranges[k][top(k) as usize]);
        let p = [0, 1, 2, 3].map(|k| stuffing_cases::pos_exact(&c.v[k], t[k]));
        let vol = stuffing_cases::orient_exact(&p);
        if vol < 0 || (real && vol == 0) {
            return false;
        }
    }
    true
}

/// Run the proof of one row.
pub fn run(cfg: &Config) -> Result<Certificate, String> {
    let t0 = std::time::Instant::now();
    let row = cfg.row;
    let a = Alphas::of(row);
    let (cases, counts) = stuffing_cases::output_cases(&a);
    let (probs, unreduced) = all_problems(row, &cases);
    let in_shard = |ci: usize| cfg.shard.is_none_or(|(i, n)| ci % n == i);
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
    let certs: Vec<ProblemCert> = mine
        .par_iter()
        .map(|&(pi, pr)| {
            let c = solve(pr, pi, &sh, cfg.max_depth);
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
    let witnesses = sh.wit.into_inner().unwrap_or_else(|e| e.into_inner());
    let mut cert = Certificate {
        format: FORMAT.into(),
        row: row.name.into(),
        alphas: a,
        tol_cos: cfg.tol_cos(),
        max_depth: cfg.max_depth,
        counts,
        shard: cfg.shard.map(|(i, n)| [i, n]),
        seconds: 0.0,
        unreduced,
        leaves: certs.iter().map(|c| c.leaves.len()).sum(),
        unresolved: certs.iter().map(|c| c.unresolved).sum(),
        problems: certs,
        witnesses,
        bounds: Vec::new(),
        safe: safe_property(row),
    };
    cert.bounds = summarize(&cert, &cases, &probs)?;
    cert.seconds = t0.elapsed().as_secs_f64();
    Ok(cert)
}

/// The bound results from the recorded leaves and witnesses.
fn summarize(
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

fn results(
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
    let (cases, counts) = stuffing_cases::output_cases(&a);
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
    let (cases, _) = stuffing_cases::output_cases(&out.alphas);
    let (probs, _) = all_problems(row, &cases);
    out.problems.sort_by_key(|p| (p.case, p.problem));
    out.bounds = summarize(&out, &cases, &probs)?;
    Ok(out)
}

/// The JSON summary printed by `proofs stuffing --json`.
pub fn summary_json(c: &Certificate, path: &str) -> serde_json::Value {
    serde_json::json!({
        "row": c.row,
        "alpha_long": c.alphas.long as f64 / DEN as f64,
        "alpha_short": c.alphas.short as f64 / DEN as f64,
        "ordered": c.alphas.ordered,
        "double_sided": c.alphas.double_sided,
        "cases": c.counts,
        "unreduced_cases": c.unreduced.len(),
        "problems": c.problems.len(),
        "leaves": c.leaves,
        "unresolved": c.unresolved,
        "seconds": c.seconds,
        "certificate": path,
        "bounds": c.bounds.iter().map(|b| serde_json::json!({
            "bound": b.bound,
            "paper": b.paper,
            "certified_deg": b.deg,
            "certified_cos": b.cos,
            "verdict": b.verdict,
            "tight": b.tight,
            "witness": b.witness_config.map(|v| serde_json::json!({
                "vertices_h": v,
                "case": b.witness_case,
                "params": b.witness.as_ref().map(|w| w.x.clone()),
                "cos": b.witness.as_ref().map(|w| w.cos),
            })),
        })).collect::<Vec<_>>(),
        "safe": c.safe,
    })
}

/// Every row name (for `--row all`).
pub fn row_names() -> Vec<&'static str> {
    TABLE1.iter().map(|r| r.name).collect()
}
