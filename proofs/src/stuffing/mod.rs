//! `proofs stuffing`: certify the six angle bounds of every row of Table 1 of Labelle &
//! Shewchuk 2007 (Theorem 1, §4.1) on the mesher's own stencil table, and the "safe"
//! property (no BCC tetrahedron inverts).
//!
//! Method (§4.1): the configuration space is cut into cases ([`crate::stuffing::cases`]);
//! each case becomes branch-and-bound problems ([`crate::stuffing::eval`]): the dihedral
//! angle at each edge `ab` with the other two vertices at the ends of their segments
//! (the paper's reduction: a quadtree over the parameters of `a` and `b`), valid because
//! the case's tetrahedron is proven never flat — its signed volume is multilinear in the
//! parameters, so its sign over the whole box is decided exactly at the box corners
//! ([`crate::stuffing::cases::volume_range`]); where that fails, the dihedral is searched
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
pub mod cases;
mod check;
pub mod contexts;
pub mod custom;
pub mod eval;
pub mod figures;
pub mod graded;
pub mod pareto;
mod safe;
mod search;
mod summary;
pub mod tables;

pub use check::{check, merge, CheckReport};
pub use safe::safe_property;
pub use search::run;

use crate::exact::Verdict;
use cases::{Alphas, Case, Counts, Seg, DEN};
use certmesh::stuffing::params::{Row, TABLE1};
use eval::{problems, Problem, What};
use serde::{Deserialize, Serialize};

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

/// The smallest tolerance accepted (degrees), as for the GradNormal proof.
pub const MIN_TOL_DEG: f64 = crate::gradnormal::MIN_TOL_DEG;

#[derive(Clone, Debug)]
pub struct Config {
    pub row: &'static Row,
    /// Target width of every extreme's enclosure, degrees.
    pub tol_deg: f64,
    pub max_depth: u8,
    pub shard: Option<(usize, usize)>,
    pub progress: bool,
    /// The work budget of the run (boxes, time).
    pub budget: crate::bnb::Budget,
}

impl Config {
    pub fn new(row: &'static Row) -> Config {
        Config {
            row,
            tol_deg: 1e-4,
            max_depth: 40,
            shard: None,
            progress: false,
            budget: crate::bnb::Budget::default(),
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
    /// Leaves at the depth limit that could still change a bound by more than the
    /// tolerance, or a threshold decision, given the final witnesses (derived; checked).
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
    /// True for a shard: a partial result, not a proof of the row; its bounds then carry
    /// no verdict (added field; read as `false` when absent; `check` requires it to
    /// agree with `shard`).
    #[serde(default)]
    pub partial: bool,
    /// Wall-clock seconds (informative only: the one field `check` cannot recompute).
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

/// Are dihedrals searched? For a Table 1 row when it states dihedral bounds
/// (min-exposed-unsafe: n/a, its tetrahedra can be flat); for a custom pair always.
fn has_dihedrals(row: &Row) -> bool {
    custom::is_custom(row) || row.bounds.min_dihedral.is_some() || row.bounds.max_dihedral.is_some()
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
            let (r, _) = cases::volume_range(c, &a);
            let reduce = r[0] > 0 || r[1] < 0;
            if !reduce && dih {
                unreduced.push(ci);
            }
            problems(ci, c, &a, dih, reduce)
        })
        .collect();
    (probs, unreduced)
}

/// The JSON summary printed by `proofs stuffing --json`.
pub fn summary_json(c: &Certificate, path: &str) -> serde_json::Value {
    serde_json::json!({
        "row": c.row,
        "partial": c.partial,
        "shard": c.shard.map(|s| format!("{}/{}", s[0], s[1])),
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
        "audit": custom::audit(c),
    })
}

/// Everything a row's proof derives from the stencil table: the output-tetrahedron
/// cases and counts, their problems, the unreduced cases and the safe property.
pub(crate) struct Tables {
    pub cases: Vec<Case>,
    pub counts: Counts,
    pub probs: Vec<Vec<Problem>>,
    pub unreduced: Vec<usize>,
    pub safe: SafeResult,
}

/// The row's [`Tables`], computed once per process (a pure function of the row's
/// parameters and the mesher's stencil table; `check` re-derives them the first time).
pub(crate) fn tables(row: &'static Row) -> std::sync::Arc<Tables> {
    use std::collections::HashMap;
    use std::sync::{Arc, Mutex, OnceLock};
    static CACHE: OnceLock<Mutex<HashMap<&'static str, Arc<Tables>>>> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    if let Some(t) = cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .get(row.name)
    {
        return t.clone();
    }
    let a = Alphas::of(row);
    let (cases, counts) = cases::output_cases(&a);
    let (probs, unreduced) = all_problems(row, &cases);
    let t = Arc::new(Tables {
        cases,
        counts,
        probs,
        unreduced,
        safe: safe_property(row),
    });
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(row.name, t.clone());
    t
}

/// Every row name (for `--row all`).
pub fn row_names() -> Vec<&'static str> {
    TABLE1.iter().map(|r| r.name).collect()
}
