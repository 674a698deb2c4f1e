//! Generic certified branch and bound over the unit square, with checkable certificates.
//!
//! A *case* is a list of domains, each a map from the unit square [0,1]² onto part of a
//! parameter space, and a vector-valued function on it (the [`Objective`]). The search
//! refines a quadtree on every domain until each output's minimum and maximum over the
//! union of the domains is enclosed to within `tol`: a box is final when none of its
//! interval bounds can improve an extreme by more than `tol` beyond the best witness.
//! The certificate ([`CaseCert`]) lists every leaf of every quadtree (its path and
//! interval bounds, or "outside" when an extra constraint excludes it) and the witness
//! points. [`check_case`] re-verifies a certificate without the search: the leaves must
//! partition each square exactly (checked with integer arithmetic), every leaf and every
//! witness is re-evaluated and must give exactly the recorded bounds, the stopping rule
//! is re-applied with the final witnesses, and the extremes and the unresolved count
//! must be exactly those derived from the leaves and witnesses ([`derive`]). Every loop
//! of a search is charged to a [`Budget`].
use inari::Interval;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;

/// A dyadic box of the unit square: depth d, cell (ix, iy) of the 2^d × 2^d grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Cell {
    pub d: u8,
    pub ix: u64,
    pub iy: u64,
}

impl Cell {
    pub const ROOT: Cell = Cell { d: 0, ix: 0, iy: 0 };
    /// The box [u0,u1] × [v0,v1] (exact: dyadic numbers).
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        let s = (0.5f64).powi(self.d as i32);
        (
            [self.ix as f64 * s, (self.ix + 1) as f64 * s],
            [self.iy as f64 * s, (self.iy + 1) as f64 * s],
        )
    }
    pub fn children(&self) -> [Cell; 4] {
        let (d, x, y) = (self.d + 1, 2 * self.ix, 2 * self.iy);
        [
            Cell { d, ix: x, iy: y },
            Cell {
                d,
                ix: x + 1,
                iy: y,
            },
            Cell {
                d,
                ix: x,
                iy: y + 1,
            },
            Cell {
                d,
                ix: x + 1,
                iy: y + 1,
            },
        ]
    }
    pub fn parent(&self) -> Option<Cell> {
        (self.d > 0).then(|| Cell {
            d: self.d - 1,
            ix: self.ix / 2,
            iy: self.iy / 2,
        })
    }
    pub fn valid(&self) -> bool {
        self.d <= 50 && self.ix < (1u64 << self.d) && self.iy < (1u64 << self.d)
    }
}

/// What an objective says about a box.
pub enum Enclosure {
    /// The box is certified to lie outside the region (an extra constraint is negative).
    Outside,
    /// Interval enclosures of every output over the box (∩ region).
    Values(Vec<Interval>),
}

/// A vector-valued function on a domain parametrised by the unit square.
pub trait Objective: Sync {
    fn n_out(&self) -> usize;
    /// Enclose every output over the box u × v.
    fn enclose(&self, u: [f64; 2], v: [f64; 2]) -> Enclosure;
    /// Tight enclosures of the outputs at a point, or None when the point is not
    /// certified to lie in the region (it cannot serve as a witness).
    fn point(&self, u: f64, v: f64) -> Option<Vec<Interval>>;
}

/// A leaf of a quadtree: its cell and the bounds [lo, hi] of each output, or None when
/// certified outside. Serialised compactly as one array `[d, ix, iy, lo0, hi0, ...]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "Vec<f64>", try_from = "Vec<f64>")]
pub struct Leaf {
    pub cell: Cell,
    pub vals: Option<Vec<[f64; 2]>>,
}

impl From<Leaf> for Vec<f64> {
    fn from(l: Leaf) -> Vec<f64> {
        let mut out = vec![l.cell.d as f64, l.cell.ix as f64, l.cell.iy as f64];
        if let Some(v) = l.vals {
            for [a, b] in v {
                out.push(a);
                out.push(b);
            }
        }
        out
    }
}

/// A leaf coordinate stored as a JSON number: a non-negative integer below 2^50 or
/// the certificate is malformed (shared by the GradNormal and stuffing certificates).
pub(crate) fn leaf_index(x: f64) -> Result<u64, String> {
    if x >= 0.0 && x.fract() == 0.0 && x < 1.2e15 {
        Ok(x as u64)
    } else {
        Err(format!("malformed leaf index {x}"))
    }
}

impl TryFrom<Vec<f64>> for Leaf {
    type Error = String;
    fn try_from(v: Vec<f64>) -> Result<Leaf, String> {
        if v.len() < 3 || v.len() % 2 == 0 {
            return Err(format!("malformed leaf of length {}", v.len()));
        }
        let int = leaf_index;
        let cell = Cell {
            d: int(v[0])?.min(255) as u8,
            ix: int(v[1])?,
            iy: int(v[2])?,
        };
        let vals = if v.len() == 3 {
            None
        } else {
            Some(v[3..].chunks(2).map(|c| [c[0], c[1]]).collect())
        };
        Ok(Leaf { cell, vals })
    }
}

/// `Witness::domain` of an extreme without a witness point (one-sided bound only).
pub const NO_WITNESS: usize = usize::MAX;

/// A point of a domain and the enclosure of the outputs there.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Witness {
    pub domain: usize,
    pub u: f64,
    pub v: f64,
    /// Enclosure of the output at the point.
    pub value: [f64; 2],
}

/// A certified enclosure [lo, hi] of an extreme (min or max) of one output, and the
/// witness attaining it up to the enclosure's width.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Extreme {
    pub bound: [f64; 2],
    pub witness: Witness,
}

/// The certificate of one case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseCert {
    /// One list of leaves per domain.
    pub leaves: Vec<Vec<Leaf>>,
    /// Per output: the minimum and the maximum.
    pub min: Vec<Extreme>,
    pub max: Vec<Extreme>,
    /// Leaves kept at the depth limit although they could still improve an extreme by
    /// more than `tol` given the final witnesses (the enclosures stay valid, only wider).
    pub unresolved: usize,
}

/// Search parameters.
#[derive(Clone, Copy, Debug)]
pub struct Search {
    /// Target width of every extreme's enclosure.
    pub tol: f64,
    pub max_depth: u8,
    /// Seed witnesses on an n × n grid of every domain before the search.
    pub seed: usize,
}

impl Search {
    /// The depth at which the search stops refining (the partition check sums areas in
    /// u128, hence at most 50).
    pub fn depth_limit(&self) -> u8 {
        self.max_depth.min(50)
    }
}

/// A work budget shared by every loop of a run: a number of boxes (interval
/// evaluations) and an optional wall-clock limit. A search that exhausts it stops with
/// an error naming the limit and the option that raises it; no certificate is written.
#[derive(Clone, Debug)]
pub struct Budget(std::sync::Arc<BudgetInner>);

#[derive(Debug)]
pub struct BudgetInner {
    pub max_boxes: u64,
    pub time_limit: Option<f64>,
    start: std::time::Instant,
    boxes: std::sync::atomic::AtomicU64,
    exhausted: std::sync::atomic::AtomicBool,
}

/// The default box budget (`--max-boxes`): 20 million boxes, about 2 GB of leaves at
/// most; the largest proof of the repository (stuffing row min-dihedral-double at
/// 1e-4°) needs about 4.5 million.
pub const DEFAULT_MAX_BOXES: u64 = 20_000_000;

impl Default for Budget {
    fn default() -> Budget {
        Budget::new(DEFAULT_MAX_BOXES, None)
    }
}

impl Budget {
    pub fn new(max_boxes: u64, time_limit: Option<f64>) -> Budget {
        Budget(std::sync::Arc::new(BudgetInner {
            max_boxes,
            time_limit,
            start: std::time::Instant::now(),
            boxes: std::sync::atomic::AtomicU64::new(0),
            exhausted: std::sync::atomic::AtomicBool::new(false),
        }))
    }
    /// Charge `n` boxes; false once the budget is exhausted (then every later call is
    /// false too).
    pub fn charge(&self, n: u64) -> bool {
        use std::sync::atomic::Ordering::Relaxed;
        if self.0.exhausted.load(Relaxed) {
            return false;
        }
        let used = self.0.boxes.fetch_add(n, Relaxed) + n;
        let over_time = used % 4096 < n
            && self
                .0
                .time_limit
                .is_some_and(|t| self.0.start.elapsed().as_secs_f64() > t);
        if used > self.0.max_boxes || over_time {
            self.0.exhausted.store(true, Relaxed);
            return false;
        }
        true
    }
    pub fn boxes(&self) -> u64 {
        self.0.boxes.load(std::sync::atomic::Ordering::Relaxed)
    }
    pub fn max_boxes(&self) -> u64 {
        self.0.max_boxes
    }
    pub fn time_limit(&self) -> Option<f64> {
        self.0.time_limit
    }
    /// A fresh budget with the same limits (for the next of several runs).
    pub fn fresh(&self) -> Budget {
        Budget::new(self.0.max_boxes, self.0.time_limit)
    }
    /// Exhaust the budget now (an interrupt from the caller): every later
    /// [`Budget::charge`] is false and the run stops as if its limit were reached.
    pub fn stop(&self) {
        self.0
            .exhausted
            .store(true, std::sync::atomic::Ordering::Relaxed);
    }
    pub fn is_exhausted(&self) -> bool {
        self.0.exhausted.load(std::sync::atomic::Ordering::Relaxed)
    }
    /// The message of a run stopped by this budget.
    pub fn message(&self) -> String {
        let t = self.0.start.elapsed().as_secs_f64();
        match self.0.time_limit {
            Some(l) if t > l => format!(
                "stopped by the time limit of {l} s (--time-limit SECONDS raises it) after {} boxes: the run is incomplete, no certificate was written",
                self.boxes()
            ),
            _ => format!(
                "stopped by the work budget of {} boxes (--max-boxes N raises it) after {t:.1} s: the run is incomplete, no certificate was written",
                self.0.max_boxes
            ),
        }
    }
}

/// The error of a run stopped by its budget.
pub const BUDGET_ERROR: &str = "budget exhausted";

struct Best {
    min: Vec<(f64, Witness)>,
    max: Vec<(f64, Witness)>,
}

impl Best {
    fn offer(&mut self, domain: usize, u: f64, v: f64, vals: &[Interval]) {
        for (k, x) in vals.iter().enumerate() {
            if x.is_empty() || !x.sup().is_finite() || !x.inf().is_finite() {
                continue;
            }
            let w = Witness {
                domain,
                u,
                v,
                value: [x.inf(), x.sup()],
            };
            if x.sup() < self.min[k].0 {
                self.min[k] = (x.sup(), w.clone());
            }
            if x.inf() > self.max[k].0 {
                self.max[k] = (x.inf(), w);
            }
        }
    }
}

/// Could a box with recorded bounds `vals` still improve an extreme by more than `tol`,
/// given the best witness values `bmin` (smallest upper end of a minimum witness) and
/// `bmax`? The search refines such boxes; the checker re-applies the same test with the
/// final witnesses (the test is monotone: a witness only ever improves, so a box final
/// during the search is final at the end).
pub fn leaf_needs(vals: &[[f64; 2]], bmin: &[f64], bmax: &[f64], tol: f64) -> bool {
    vals.iter().enumerate().any(|(k, x)| {
        // Written so that a NaN bound needs refinement.
        let final_lo = x[0] >= bmin[k] - tol;
        let final_hi = x[1] <= bmax[k] + tol;
        !(final_lo && final_hi)
    })
}

/// Run the branch and bound on one case (default budget).
pub fn solve(domains: &[&dyn Objective], s: Search) -> Result<CaseCert, String> {
    solve_within(domains, s, &Budget::default())
}

/// Run the branch and bound on one case within a budget.
pub fn solve_within(
    domains: &[&dyn Objective],
    s: Search,
    budget: &Budget,
) -> Result<CaseCert, String> {
    let n = domains.first().map(|d| d.n_out()).unwrap_or(0);
    let dummy = Witness {
        domain: 0,
        u: 0.0,
        v: 0.0,
        value: [f64::NAN, f64::NAN],
    };
    let mut best = Best {
        min: vec![(f64::INFINITY, dummy.clone()); n],
        max: vec![(f64::NEG_INFINITY, dummy); n],
    };
    for (di, dom) in domains.iter().enumerate() {
        for i in 0..s.seed {
            for j in 0..s.seed {
                let u = (i as f64 + 0.5) / s.seed as f64;
                let v = (j as f64 + 0.5) / s.seed as f64;
                if let Some(vals) = dom.point(u, v) {
                    best.offer(di, u, v, &vals);
                }
            }
        }
    }
    let lim = s.depth_limit();
    let mut leaves: Vec<Vec<Leaf>> = vec![Vec::new(); domains.len()];
    let mut stack: Vec<(usize, Cell)> = (0..domains.len()).map(|d| (d, Cell::ROOT)).collect();
    while let Some((di, cell)) = stack.pop() {
        if !budget.charge(1) {
            return Err(BUDGET_ERROR.into());
        }
        let (u, v) = cell.bounds();
        match domains[di].enclose(u, v) {
            Enclosure::Outside => leaves[di].push(Leaf { cell, vals: None }),
            Enclosure::Values(vals) => {
                let (cu, cv) = (0.5 * (u[0] + u[1]), 0.5 * (v[0] + v[1]));
                if let Some(pv) = domains[di].point(cu, cv) {
                    best.offer(di, cu, cv, &pv);
                }
                let pairs: Vec<[f64; 2]> = vals.iter().map(|x| interval_pair(*x)).collect();
                let needs = |best: &Best| {
                    let bmin: Vec<f64> = best.min.iter().map(|b| b.0).collect();
                    let bmax: Vec<f64> = best.max.iter().map(|b| b.0).collect();
                    leaf_needs(&pairs, &bmin, &bmax, s.tol)
                };
                // Extremes typically sit on the boundary (Lemma 7.1), often at a vertex
                // of the region: witnesses at box centres alone would approach them only
                // linearly in the box width, so also try the corners.
                if needs(&best) {
                    for cu in u {
                        for cv in v {
                            if let Some(pv) = domains[di].point(cu, cv) {
                                best.offer(di, cu, cv, &pv);
                            }
                        }
                    }
                }
                if needs(&best) && cell.d < lim {
                    for c in cell.children() {
                        stack.push((di, c));
                    }
                } else {
                    leaves[di].push(Leaf {
                        cell,
                        vals: Some(pairs),
                    });
                }
            }
        }
    }
    let wmin: Vec<Witness> = best.min.into_iter().map(|b| b.1).collect();
    let wmax: Vec<Witness> = best.max.into_iter().map(|b| b.1).collect();
    Ok(derive(leaves, wmin, wmax, n, s))
}

fn interval_pair(x: Interval) -> [f64; 2] {
    if x.is_empty() {
        [f64::NEG_INFINITY, f64::INFINITY]
    } else {
        [x.inf(), x.sup()]
    }
}

/// The witness of an extreme without a witness point (one-sided bound only).
fn no_witness() -> Witness {
    Witness {
        domain: NO_WITNESS,
        u: 0.0,
        v: 0.0,
        value: [f64::MIN, f64::MAX],
    }
}

/// The best witness value of a minimum (`is_min`) or maximum witness: +∞ / −∞ without
/// a witness point.
fn witness_best(w: &Witness, is_min: bool) -> f64 {
    let real = w.domain != NO_WITNESS && w.value.iter().all(|x| x.is_finite());
    match (real, is_min) {
        (true, true) => w.value[1],
        (true, false) => w.value[0],
        (false, true) => f64::INFINITY,
        (false, false) => f64::NEG_INFINITY,
    }
}

/// The derived parts of a case certificate from its leaves and witnesses: the
/// enclosure of every extreme (from the leaves on one side, the witness on the other)
/// and the number of unresolved leaves (at the depth limit and still able to improve an
/// extreme by more than `tol` given the final witnesses). The search and the checker
/// both call this, so a certificate states exactly what its leaves and witnesses give.
pub fn derive(
    leaves: Vec<Vec<Leaf>>,
    wmin: Vec<Witness>,
    wmax: Vec<Witness>,
    n: usize,
    s: Search,
) -> CaseCert {
    let (min, max, unresolved) = derive_parts(&leaves, &wmin, &wmax, n, s);
    CaseCert {
        leaves,
        min,
        max,
        unresolved,
    }
}

/// [`derive`] without taking the leaves: (min, max, unresolved).
pub fn derive_parts(
    leaves: &[Vec<Leaf>],
    wmin: &[Witness],
    wmax: &[Witness],
    n: usize,
    s: Search,
) -> (Vec<Extreme>, Vec<Extreme>, usize) {
    let lim = s.depth_limit();
    // A region excluded everywhere by its extra constraint (e.g. a diagonal that is
    // never the shorter one) is an empty case: no extremes, every leaf outside.
    if leaves.iter().flatten().all(|l| l.vals.is_none()) {
        return (Vec::new(), Vec::new(), 0);
    }
    let bmin: Vec<f64> = (0..n)
        .map(|k| wmin.get(k).map_or(f64::INFINITY, |w| witness_best(w, true)))
        .collect();
    let bmax: Vec<f64> = (0..n)
        .map(|k| {
            wmax.get(k)
                .map_or(f64::NEG_INFINITY, |w| witness_best(w, false))
        })
        .collect();
    let mut lo = vec![f64::INFINITY; n];
    let mut hi = vec![f64::NEG_INFINITY; n];
    let mut unresolved = 0;
    for l in leaves.iter().flatten() {
        if let Some(v) = &l.vals {
            for k in 0..n.min(v.len()) {
                lo[k] = lo[k].min(v[k][0]);
                hi[k] = hi[k].max(v[k][1]);
            }
            if l.cell.d >= lim && leaf_needs(v, &bmin, &bmax, s.tol) {
                unresolved += 1;
            }
        }
    }
    let mut min = Vec::new();
    let mut max = Vec::new();
    for k in 0..n {
        if !bmin[k].is_finite() || !bmax[k].is_finite() {
            // No point of the region was certified (e.g. it is only the tie set of a
            // diagonal rule): keep the one-sided bounds, claim no attained value.
            min.push(Extreme {
                bound: [lo[k], f64::MAX],
                witness: no_witness(),
            });
            max.push(Extreme {
                bound: [f64::MIN, hi[k]],
                witness: no_witness(),
            });
            continue;
        }
        min.push(Extreme {
            bound: [lo[k], bmin[k]],
            witness: wmin[k].clone(),
        });
        max.push(Extreme {
            bound: [bmax[k], hi[k]],
            witness: wmax[k].clone(),
        });
    }
    (min, max, unresolved)
}

/// Check that the leaves partition the unit square: no leaf is (a descendant of) another,
/// and the areas sum to exactly 1 (integer arithmetic at the finest depth).
pub fn check_partition(leaves: &[Leaf]) -> Result<(), String> {
    let maxd = leaves.iter().map(|l| l.cell.d).max().unwrap_or(0);
    if maxd > 50 {
        return Err("leaf deeper than 50".into());
    }
    let set: HashSet<Cell> = leaves.iter().map(|l| l.cell).collect();
    if set.len() != leaves.len() {
        return Err("duplicate leaf".into());
    }
    let mut area: u128 = 0;
    for l in leaves {
        if !l.cell.valid() {
            return Err(format!("invalid cell {:?}", l.cell));
        }
        let mut p = l.cell.parent();
        while let Some(c) = p {
            if set.contains(&c) {
                return Err(format!("leaf {:?} overlaps leaf {:?}", l.cell, c));
            }
            p = c.parent();
        }
        area += 1u128 << (2 * (maxd - l.cell.d) as u32);
    }
    if area != 1u128 << (2 * maxd as u32) {
        return Err("leaves do not cover the unit square".into());
    }
    Ok(())
}

/// Re-verify a case certificate against its domains and search parameters,
/// independently of the search: the leaves partition every square; every leaf is
/// re-evaluated and its recorded bounds must be exactly the recomputed ones (the
/// interval code is deterministic); every witness is re-evaluated likewise; every leaf
/// above the depth limit satisfies the stopping rule with the final witnesses (so the
/// stated tolerance and depth are met); and the extremes and the unresolved count must be
/// exactly those derived from the leaves and witnesses ([`derive`]). Errors name the
/// field (`leaves[d][i]`, `min[k].bound`, ...).
pub fn check_case(domains: &[&dyn Objective], cert: &CaseCert, s: Search) -> Result<(), String> {
    check_case_derived(domains, cert, s)?;
    check_case_leaves(domains, cert)
}

/// The re-evaluation part of [`check_case`]: every leaf's recorded bounds must be
/// exactly the recomputed ones (the expensive part).
pub fn check_case_leaves(domains: &[&dyn Objective], cert: &CaseCert) -> Result<(), String> {
    for (di, (dom, leaves)) in domains.iter().zip(&cert.leaves).enumerate() {
        for (li, l) in leaves.iter().enumerate() {
            let (u, v) = l.cell.bounds();
            let rec = match dom.enclose(u, v) {
                Enclosure::Outside => None,
                Enclosure::Values(vals) => {
                    Some(vals.iter().map(|x| interval_pair(*x)).collect::<Vec<_>>())
                }
            };
            if rec != l.vals {
                return Err(format!(
                    "leaves[{di}][{li}] (cell {}/{}/{}): recorded {:?}, recomputed {:?}",
                    l.cell.d, l.cell.ix, l.cell.iy, l.vals, rec
                ));
            }
        }
    }
    Ok(())
}

/// Everything of [`check_case`] but the leaf re-evaluation (cheap): the partition, the
/// depth limit, the witnesses re-evaluated, the stopping rule, and the derived fields.
pub fn check_case_derived(
    domains: &[&dyn Objective],
    cert: &CaseCert,
    s: Search,
) -> Result<(), String> {
    let n = domains.first().map(|d| d.n_out()).unwrap_or(0);
    if cert.leaves.len() != domains.len() {
        return Err(format!(
            "leaves: {} leaf lists for {} domains",
            cert.leaves.len(),
            domains.len()
        ));
    }
    let lim = s.depth_limit();
    for (di, leaves) in cert.leaves.iter().enumerate() {
        check_partition(leaves).map_err(|e| format!("leaves[{di}]: {e}"))?;
        for (li, l) in leaves.iter().enumerate() {
            if l.cell.d > lim {
                return Err(format!(
                    "leaves[{di}][{li}]: depth {} beyond the depth limit {lim} (max_depth)",
                    l.cell.d
                ));
            }
            if l.vals.as_ref().is_some_and(|v| v.len() != n) {
                return Err(format!("leaves[{di}][{li}]: wrong number of outputs"));
            }
        }
    }
    // Witnesses: re-evaluated exactly.
    for (name, ext) in [("min", &cert.min), ("max", &cert.max)] {
        for (k, e) in ext.iter().enumerate() {
            let w = &e.witness;
            if w.domain == NO_WITNESS {
                continue;
            }
            let dom = domains
                .get(w.domain)
                .ok_or_else(|| format!("{name}[{k}].witness.domain: {} out of range", w.domain))?;
            if !(0.0..=1.0).contains(&w.u) || !(0.0..=1.0).contains(&w.v) {
                return Err(format!("{name}[{k}].witness: outside the unit square"));
            }
            let val = dom
                .point(w.u, w.v)
                .ok_or_else(|| format!("{name}[{k}].witness: not certified inside its region"))?;
            let x = val
                .get(k)
                .ok_or_else(|| format!("{name}[{k}]: output out of range"))?;
            let r = interval_pair(*x);
            if r != w.value {
                return Err(format!(
                    "{name}[{k}].witness.value: recorded {:?}, recomputed {:?}",
                    w.value, r
                ));
            }
        }
    }
    let empty = cert.min.is_empty() && cert.max.is_empty();
    let wmin: Vec<Witness> = cert.min.iter().map(|e| e.witness.clone()).collect();
    let wmax: Vec<Witness> = cert.max.iter().map(|e| e.witness.clone()).collect();
    if !empty && (wmin.len() != n || wmax.len() != n) {
        return Err(format!(
            "min/max: {} and {} extremes for {n} outputs",
            wmin.len(),
            wmax.len()
        ));
    }
    let (emin, emax, eunres) = derive_parts(&cert.leaves, &wmin, &wmax, n, s);
    // The stopping rule: a leaf above the depth limit cannot improve an extreme.
    let bmin: Vec<f64> = emin
        .iter()
        .map(|e| witness_best(&e.witness, true))
        .collect();
    let bmax: Vec<f64> = emax
        .iter()
        .map(|e| witness_best(&e.witness, false))
        .collect();
    if !emin.is_empty() {
        for (di, leaves) in cert.leaves.iter().enumerate() {
            for (li, l) in leaves.iter().enumerate() {
                if let Some(v) = &l.vals {
                    if l.cell.d < lim && leaf_needs(v, &bmin, &bmax, s.tol) {
                        return Err(format!(
                            "leaves[{di}][{li}]: refinement stopped at depth {} < {lim} although the leaf could still improve an extreme by more than tol = {}",
                            l.cell.d, s.tol
                        ));
                    }
                }
            }
        }
    }
    crate::fields::same("min", &cert.min, &emin)?;
    crate::fields::same("max", &cert.max, &emax)?;
    crate::fields::same("unresolved", &cert.unresolved, &eunres)?;
    Ok(())
}
