//! `proofs gradnormal`: the certified angle bounds of GradNormal over the full regions
//! of plane normals (Hass & Trnkova 2020, Thm 1.1, Lemma 4.1, Appendix A).
pub mod cases;
pub mod eval;
pub mod maps;
pub mod report;
pub mod sample;

use crate::bnb::{self, CaseCert, Objective, Search, Witness};
use crate::exact::{angle_at_least, angle_at_most, cos_deg, decimal, deg_hi, deg_lo, rat, Verdict};
use crate::geometry::{DiagonalRule, LABELS};
use cases::{exact_cos, midnormal_triangles, Case, Derived, Ratio};
use eval::TriObj;
use num_bigint::BigInt;
use num_rational::BigRational;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

pub const FORMAT: &str = "certmesh-proofs/gradnormal/1";

/// The smallest tolerance accepted (degrees): below it the f64 interval enclosures
/// (widths of a few ulps of the cosines, and the 1e-12° outward rounding of the degree
/// display) cannot reach the target, and the search would refine without end.
pub const MIN_TOL_DEG: f64 = 1e-12;

/// Run parameters.
#[derive(Clone, Debug)]
pub struct Config {
    pub ratio: Ratio,
    pub rule: DiagonalRule,
    /// Target width of the cosine enclosures: 1e-6° of angle is at least 0.5·1e-6·π/180
    /// in cosine for angles in [30°, 150°].
    pub tol_cos: f64,
    pub max_depth: u8,
    pub shard: Option<(usize, usize)>,
    pub progress: bool,
    /// The work budget of the run (boxes, time).
    pub budget: bnb::Budget,
}

impl Config {
    pub fn new(ratio: Ratio, rule: DiagonalRule) -> Config {
        Config {
            ratio,
            rule,
            tol_cos: 0.5e-6 * std::f64::consts::PI / 180.0,
            // The shorter-diagonal rule's regions are cut by a quadric (the tie of the two
            // projected diagonals); boxes straddling it converge only linearly, so its
            // depth is capped and the achieved widths are reported instead.
            max_depth: if rule == DiagonalRule::Shorter { 9 } else { 40 },
            shard: None,
            progress: false,
            budget: bnb::Budget::default(),
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseEntry {
    pub index: usize,
    pub case: Case,
    pub cert: CaseCert,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Claim {
    pub claim: String,
    pub verdict: Verdict,
    pub witness: String,
}

/// Enclosures of one projected angle's extremes (degrees) and the witness normals.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AngleSummary {
    pub vertex: String,
    pub min_deg: [f64; 2],
    pub max_deg: [f64; 2],
    pub min_normal: [f64; 3],
    pub max_normal: [f64; 3],
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseSummary {
    pub index: usize,
    pub name: String,
    pub group: String,
    pub region: String,
    pub leaves: usize,
    pub unresolved: usize,
    pub angles: Vec<AngleSummary>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Certified enclosure of the smallest projected angle over all cases (degrees).
    pub min_deg: [f64; 2],
    /// Certified enclosure of the largest projected angle over all cases (degrees).
    pub max_deg: [f64; 2],
    /// The same in cosines: enclosures of the largest and the smallest cosine.
    pub max_cos: [f64; 2],
    pub min_cos: [f64; 2],
    /// Valence-four square triangles only (Fig 14/15).
    pub v4_min_deg: [f64; 2],
    pub v4_max_deg: [f64; 2],
    pub midnormal_min_deg: f64,
    pub midnormal_max_deg: f64,
    pub cases: Vec<CaseSummary>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Certificate {
    pub format: String,
    pub ratio: String,
    pub rule: String,
    pub tol_cos: f64,
    pub max_depth: u8,
    pub n_cases: usize,
    pub shard: Option<[usize; 2]>,
    /// True for a shard: a partial result, not a proof of the claims (added field; a
    /// certificate without it is read as `false`, and `check` requires it to agree with
    /// `shard`).
    #[serde(default)]
    pub partial: bool,
    /// Wall-clock seconds of the run (informative only: the one field `check` cannot
    /// recompute).
    pub seconds: f64,
    pub cases: Vec<CaseEntry>,
    /// Present when the certificate covers every case.
    pub summary: Option<Summary>,
    pub claims: Vec<Claim>,
}

fn objectives(ratio: Ratio, case: &Case) -> Vec<TriObj> {
    case.domains
        .iter()
        .map(|d| TriObj::new(ratio, case, d))
        .collect()
}

/// The search parameters of a certificate.
fn search_of(tol_cos: f64, max_depth: u8) -> Search {
    Search {
        tol: tol_cos,
        max_depth,
        seed: 9,
    }
}

/// Is the tolerance (in cosine) one the search can reach? (Both `run` and `check`.)
fn check_tol_cos(tol_cos: f64) -> Result<(), String> {
    let min = 0.5 * MIN_TOL_DEG.to_radians();
    if !(tol_cos.is_finite() && tol_cos >= min && tol_cos <= 2.0) {
        return Err(format!(
            "tol_cos = {tol_cos}: outside [{min:e}, 2] (a tolerance below {MIN_TOL_DEG:e}° is below what f64 interval arithmetic reaches)"
        ));
    }
    Ok(())
}

/// Is a shard `(i, N)` well formed? `N = 1` is the whole run (not a shard).
pub fn check_shard(shard: Option<[usize; 2]>) -> Result<(), String> {
    match shard {
        Some([i, n]) if n < 2 || i >= n => Err(format!(
            "shard {i}/{n}: a shard is i/N with 0 <= i < N and N >= 2"
        )),
        _ => Ok(()),
    }
}

/// The cases of a ratio and rule, derived once per process (a pure function of the
/// tiling data; `check` derives them the first time).
pub fn cases_of(ratio: Ratio, rule: DiagonalRule) -> Result<std::sync::Arc<Vec<Case>>, String> {
    use std::collections::HashMap;
    use std::sync::{Arc, Mutex, OnceLock};
    type Cache = Mutex<HashMap<(String, String), Arc<Vec<Case>>>>;
    static CACHE: OnceLock<Cache> = OnceLock::new();
    let key = (ratio.label(), rule.name().to_string());
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    if let Some(c) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return Ok(c.clone());
    }
    let c = Arc::new(Derived::new(ratio).cases(rule)?);
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key, c.clone());
    Ok(c)
}

/// Run the proof (or one shard of it).
pub fn run(cfg: &Config) -> Result<Certificate, String> {
    let t0 = std::time::Instant::now();
    check_tol_cos(cfg.tol_cos)?;
    if cfg.max_depth > 50 {
        return Err(format!("max_depth = {}: at most 50", cfg.max_depth));
    }
    let shard = match cfg.shard {
        Some((_, 1)) => None,
        s => s,
    };
    check_shard(shard.map(|(a, b)| [a, b]))?;
    check_theorem_range(cfg.ratio)?;
    let derived = Derived::new(cfg.ratio);
    let cases = derived.cases(cfg.rule)?;
    let n = cases.len();
    let chosen: Vec<(usize, Case)> = cases
        .into_iter()
        .enumerate()
        .filter(|(i, _)| shard.is_none_or(|(k, m)| i % m == k))
        .collect();
    let bar = if cfg.progress {
        indicatif::ProgressBar::new(chosen.len() as u64)
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} cases {elapsed} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let search = search_of(cfg.tol_cos, cfg.max_depth);
    let entries: Result<Vec<CaseEntry>, String> = chosen
        .into_par_iter()
        .map(|(index, case)| {
            let objs = objectives(cfg.ratio, &case);
            let dyns: Vec<&dyn Objective> = objs.iter().map(|o| o as &dyn Objective).collect();
            let cert = bnb::solve_within(&dyns, search, &cfg.budget)
                .map_err(|e| format!("case {}: {e}", case.name))?;
            bar.inc(1);
            Ok(CaseEntry { index, case, cert })
        })
        .collect();
    bar.finish_and_clear();
    if cfg.budget.is_exhausted() {
        return Err(format!("{}: {}", bnb::BUDGET_ERROR, cfg.budget.message()));
    }
    let mut cert = Certificate {
        format: FORMAT.into(),
        ratio: cfg.ratio.label(),
        rule: cfg.rule.name().into(),
        tol_cos: cfg.tol_cos,
        max_depth: cfg.max_depth,
        n_cases: n,
        shard: shard.map(|(a, b)| [a, b]),
        partial: shard.is_some(),
        seconds: 0.0,
        cases: entries?,
        summary: None,
        claims: Vec::new(),
    };
    finish(&mut cert)?;
    cert.seconds = t0.elapsed().as_secs_f64();
    Ok(cert)
}

/// The theorem's range: the case analysis (Hass & Trnkova 2020, Sec. 4.3, Appendix A)
/// assumes a tiling by tetrahedra with no obtuse dihedral angle (the 90° edges carry the
/// valence-four configurations). τ's dihedral angle at CD becomes obtuse at
/// a/e = √2/2 (decided exactly); beyond it the regions no longer describe the mesh.
pub fn check_theorem_range(ratio: Ratio) -> Result<(), String> {
    let signs = cases::dihedral_signs(&ratio.squared());
    for (k, s) in signs.iter().enumerate() {
        if *s < 0 {
            let [p, q] = crate::geometry::MIDPOINT_EDGES[k];
            return Err(format!(
                "a/e = {}: the dihedral angle of the Goldberg tetrahedron at edge {}{} is obtuse; the GradNormal case analysis (Hass & Trnkova 2020, Sec. 4.3) assumes none is, which holds for 0 < a/e < sqrt(2)/2 = 0.70710678... (--a)",
                ratio.label(),
                LABELS[p],
                LABELS[q]
            ));
        }
    }
    Ok(())
}

/// Fill summary and claims: only a complete certificate (not a shard) states them.
fn finish(cert: &mut Certificate) -> Result<(), String> {
    cert.cases.sort_by_key(|c| c.index);
    let complete = cert.shard.is_none()
        && cert.cases.len() == cert.n_cases
        && cert.cases.iter().enumerate().all(|(i, c)| c.index == i);
    cert.partial = cert.shard.is_some();
    if complete {
        let ratio = Ratio::parse(&cert.ratio)?;
        let rule: DiagonalRule = cert.rule.parse().map_err(|e| format!("{e}"))?;
        let (s, c) = summarize(ratio, rule, &cert.cases);
        cert.summary = Some(s);
        cert.claims = c;
    } else {
        cert.summary = None;
        cert.claims = Vec::new();
    }
    Ok(())
}

fn witness_normal(ratio: Ratio, case: &Case, w: &Witness) -> [f64; 3] {
    match case.domains.get(w.domain) {
        Some(d) => TriObj::new(ratio, case, d).normal_f64(w.u, w.v),
        None => [0.0; 3],
    }
}

fn fmt_n(m: [f64; 3]) -> String {
    format!("({:.9}, {:.9}, {:.9})", m[0], m[1], m[2])
}

struct Global {
    cos: [f64; 2],
    at: Option<(usize, usize)>,
}

/// Summary and claims from (verified) case certificates.
pub fn summarize(ratio: Ratio, rule: DiagonalRule, cases: &[CaseEntry]) -> (Summary, Vec<Claim>) {
    let mut per = Vec::new();
    // Largest cosine (smallest angle) and smallest cosine (largest angle), overall and
    // for the valence-four squares.
    let mut gmax = Global {
        cos: [f64::NEG_INFINITY; 2],
        at: None,
    };
    let mut gmin = Global {
        cos: [f64::INFINITY; 2],
        at: None,
    };
    let mut vmax = Global {
        cos: [f64::NEG_INFINITY; 2],
        at: None,
    };
    let mut vmin = Global {
        cos: [f64::INFINITY; 2],
        at: None,
    };
    for (ci, e) in cases.iter().enumerate() {
        let mut angles = Vec::new();
        for k in 0..e.cert.min.len().min(e.cert.max.len()) {
            let (mn, mx) = (&e.cert.min[k], &e.cert.max[k]);
            angles.push(AngleSummary {
                vertex: e.case.vertices[k].name.clone(),
                min_deg: [deg_lo(mx.bound[1]), deg_hi(mx.bound[0])],
                max_deg: [deg_lo(mn.bound[1]), deg_hi(mn.bound[0])],
                min_normal: witness_normal(ratio, &e.case, &mx.witness),
                max_normal: witness_normal(ratio, &e.case, &mn.witness),
            });
            let upd = |g: &mut Global, hi: bool| {
                let b = if hi { mx.bound } else { mn.bound };
                if hi {
                    if b[0] > g.cos[0] {
                        g.at = Some((ci, k));
                    }
                    g.cos = [g.cos[0].max(b[0]), g.cos[1].max(b[1])];
                } else {
                    if b[1] < g.cos[1] {
                        g.at = Some((ci, k));
                    }
                    g.cos = [g.cos[0].min(b[0]), g.cos[1].min(b[1])];
                }
            };
            upd(&mut gmax, true);
            upd(&mut gmin, false);
            if e.case.group == "valence4" {
                upd(&mut vmax, true);
                upd(&mut vmin, false);
            }
        }
        per.push(CaseSummary {
            index: e.index,
            name: e.case.name.clone(),
            group: e.case.group.clone(),
            region: e.case.region.clone(),
            leaves: e.cert.leaves.iter().map(|l| l.len()).sum(),
            unresolved: e.cert.unresolved,
            angles,
        });
    }
    let wit = |g: &Global, hi: bool| -> String {
        match g.at {
            Some((ci, k)) => {
                let e = &cases[ci];
                let ex = if hi { &e.cert.max[k] } else { &e.cert.min[k] };
                let m = witness_normal(ratio, &e.case, &ex.witness);
                let h = 3f64.sqrt() / 2.0;
                let mu = [m[0], m[1] * h, m[2] * ratio.f64()];
                let levels =
                    crate::gradnormal::cases::describe_f64(mu, &Derived::new(ratio).named_points());
                format!(
                    "triangle {} ({}), angle at {}, plane normal m = {} (unit, e = 1; heights along m: {}), projected angle in [{:.9}°, {:.9}°]",
                    e.case.name,
                    e.case.region,
                    e.case.vertices[k].name,
                    fmt_n(m),
                    levels,
                    deg_lo(ex.witness.value[1]),
                    deg_hi(ex.witness.value[0])
                )
            }
            None => "no case".into(),
        }
    };
    // MidNormal (Lemma 4.1): exact.
    let derived = Derived::new(ratio);
    let r2 = ratio.squared();
    let half = BigRational::new(BigInt::from(1), BigInt::from(2));
    let (mut mid_lo_ok, mut mid_hi_ok) = (true, true);
    let (mut mid_min, mut mid_max) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut wlo, mut whi) = (String::new(), String::new());
    for (name, t) in midnormal_triangles(&derived, rule) {
        for (k, (s, c2)) in exact_cos(&r2, &t).into_iter().enumerate() {
            let c = s as f64
                * num_traits::ToPrimitive::to_f64(&c2)
                    .unwrap_or(f64::NAN)
                    .sqrt();
            let deg = c.clamp(-1.0, 1.0).acos().to_degrees();
            let at_least_45 = s <= 0 || c2 <= half;
            let at_most_90 = s >= 0;
            if deg < mid_min {
                mid_min = deg;
                wlo = format!("triangle {name}, angle at {} = {deg:.9}°", t[k].name);
            }
            if deg > mid_max {
                mid_max = deg;
                whi = format!("triangle {name}, angle at {} = {deg:.9}°", t[k].name);
            }
            mid_lo_ok &= at_least_45;
            mid_hi_ok &= at_most_90;
        }
    }
    let v = |b: bool| if b { Verdict::Proven } else { Verdict::Refuted };
    let mut claims = vec![
        Claim {
            claim: "Lemma 4.1: MidNormal angles >= 45°".into(),
            verdict: v(mid_lo_ok),
            witness: format!("smallest: {wlo} (exact rational cos²)"),
        },
        Claim {
            claim: "Lemma 4.1: MidNormal angles <= 90°".into(),
            verdict: v(mid_hi_ok),
            witness: format!("largest: {whi} (exact rational cos²)"),
        },
    ];
    let d = |s: &str| decimal(s).unwrap_or_else(|| rat(0.0));
    for (name, lo, hi) in [
        ("Theorem 1.1", "35.2", "101.5"),
        ("Appendix A / Sec. 4.3", "35.25", "101.45"),
    ] {
        claims.push(Claim {
            claim: format!("{name}: GradNormal angles >= {lo}°"),
            verdict: angle_at_least(&d(lo), gmax.cos[1], gmax.cos[0]),
            witness: wit(&gmax, true),
        });
        claims.push(Claim {
            claim: format!("{name}: GradNormal angles <= {hi}°"),
            verdict: angle_at_most(&d(hi), gmin.cos[0], gmin.cos[1]),
            witness: wit(&gmin, false),
        });
    }
    // Fig 14: the valence-four triangle's extreme angles are 35.3004° and 101.445° (to
    // the digits printed), here over the full region Y rather than one arc.
    let value_claim = |c: [f64; 2], t1: &str, t2: &str| -> Verdict {
        // θ = acos(C) ∈ [t1, t2] ⟺ C ∈ [cos t2, cos t1].
        let (l1, h1) = cos_deg(&d(t1));
        let (l2, h2) = cos_deg(&d(t2));
        let (clo, chi) = (rat(c[0]), rat(c[1]));
        if chi <= l1 && clo >= h2 {
            Verdict::Proven
        } else if clo > h1 || chi < l2 {
            Verdict::Refuted
        } else {
            Verdict::Undecided
        }
    };
    claims.push(Claim {
        claim: "Fig 14: smallest angle of the valence-four square triangles = 35.3004° (i.e. in [35.30035°, 35.30045°])".into(),
        verdict: value_claim(vmax.cos, "35.30035", "35.30045"),
        witness: wit(&vmax, true),
    });
    claims.push(Claim {
        claim: "Fig 14: largest angle of the valence-four square triangles = 101.445° (i.e. in [101.4445°, 101.4455°])".into(),
        verdict: value_claim(vmin.cos, "101.4445", "101.4455"),
        witness: wit(&vmin, false),
    });
    let summary = Summary {
        min_deg: [deg_lo(gmax.cos[1]), deg_hi(gmax.cos[0])],
        max_deg: [deg_lo(gmin.cos[1]), deg_hi(gmin.cos[0])],
        max_cos: gmax.cos,
        min_cos: gmin.cos,
        v4_min_deg: [deg_lo(vmax.cos[1]), deg_hi(vmax.cos[0])],
        v4_max_deg: [deg_lo(vmin.cos[1]), deg_hi(vmin.cos[0])],
        midnormal_min_deg: mid_min,
        midnormal_max_deg: mid_max,
        cases: per,
    };
    (summary, claims)
}

/// What `proofs check` found.
#[derive(Debug, Serialize)]
pub struct CheckReport {
    pub cases: usize,
    pub leaves: usize,
    pub complete: bool,
    pub claims: Vec<Claim>,
}

/// One per-case part of `check`.
type CaseCheck<'a> = dyn Fn(&[&dyn Objective], &CaseEntry) -> Result<(), String> + Sync + 'a;

/// Re-verify a certificate independently of the search: every field is recomputed
/// from the tiling and the leaves (the cases from the tiling data, every leaf and
/// witness re-evaluated, the stopping rule re-applied, the extremes, unresolved counts,
/// summary, claims and verdicts recomputed) and the first difference is reported with
/// its field. Only `seconds` (wall-clock) is not recomputable.
pub fn check(cert: &Certificate) -> Result<CheckReport, String> {
    if cert.format != FORMAT {
        return Err(format!(
            "format: unknown certificate format `{}`",
            cert.format
        ));
    }
    let ratio = Ratio::parse(&cert.ratio).map_err(|e| format!("ratio: {e}"))?;
    if ratio.label() != cert.ratio {
        return Err(format!(
            "ratio: `{}` is not in canonical form `{}`",
            cert.ratio,
            ratio.label()
        ));
    }
    check_theorem_range(ratio).map_err(|e| format!("ratio: {e}"))?;
    let rule: DiagonalRule = cert.rule.parse().map_err(|e| format!("rule: {e}"))?;
    if rule.name() != cert.rule {
        return Err(format!("rule: `{}` is not canonical", cert.rule));
    }
    check_tol_cos(cert.tol_cos).map_err(|e| format!("tol_cos: {e}"))?;
    if cert.max_depth > 50 {
        return Err(format!("max_depth: {} > 50", cert.max_depth));
    }
    check_shard(cert.shard).map_err(|e| format!("shard: {e}"))?;
    if cert.partial != cert.shard.is_some() {
        return Err(format!(
            "partial: the certificate states {}, but shard is {:?}",
            cert.partial, cert.shard
        ));
    }
    let cases = cases_of(ratio, rule)?;
    if cases.len() != cert.n_cases {
        return Err(format!(
            "n_cases: the tiling gives {} cases, the certificate says {}",
            cases.len(),
            cert.n_cases
        ));
    }
    // Coverage: exactly the cases of the shard (all without one), in index order.
    let expected: Vec<usize> = (0..cases.len())
        .filter(|i| cert.shard.is_none_or(|[k, m]| i % m == k))
        .collect();
    let got: Vec<usize> = cert.cases.iter().map(|e| e.index).collect();
    if got != expected {
        return Err(format!(
            "cases: indices {got:?}, the tiling and the shard give {expected:?}"
        ));
    }
    for (pos, e) in cert.cases.iter().enumerate() {
        crate::fields::same(&format!("cases[{pos}].case"), &e.case, &cases[e.index])?;
    }
    let search = search_of(cert.tol_cos, cert.max_depth);
    // Cheap checks first (structure, witnesses, stopping rule, derived fields), then the
    // summary and claims, then the re-evaluation of every leaf.
    let each = |f: &CaseCheck<'_>| {
        cert.cases
            .par_iter()
            .enumerate()
            .map(|(pos, e)| {
                let objs = objectives(ratio, &e.case);
                let dyns: Vec<&dyn Objective> = objs.iter().map(|o| o as &dyn Objective).collect();
                f(&dyns, e).map_err(|m| format!("cases[{pos}].cert.{m} (case {})", e.case.name))
            })
            .collect::<Result<Vec<()>, String>>()
    };
    each(&|d, e| bnb::check_case_derived(d, &e.cert, search))?;
    let complete = cert.shard.is_none();
    // The cases are verified complete (no shard) and in index order: the summary and
    // claims are recomputed from them exactly as `finish` does.
    let (summary, claims) = if complete {
        let (s, c) = summarize(ratio, rule, &cert.cases);
        (Some(s), c)
    } else {
        (None, Vec::new())
    };
    crate::fields::same("summary", &cert.summary, &summary)?;
    crate::fields::same("claims", &cert.claims, &claims)?;
    each(&|d, e| bnb::check_case_leaves(d, &e.cert))?;
    Ok(CheckReport {
        cases: cert.cases.len(),
        leaves: cert
            .cases
            .iter()
            .map(|e| e.cert.leaves.iter().map(|l| l.len()).sum::<usize>())
            .sum(),
        complete,
        claims,
    })
}

/// Combine the shard certificates of one run: the shards must be i/N for every i in
/// 0..N of one N, each exactly once (complete and disjoint), of the same parameters, and
/// each must hold exactly its shard's cases.
pub fn merge(parts: Vec<Certificate>) -> Result<Certificate, String> {
    let mut it = parts.into_iter();
    let mut out = it.next().ok_or("nothing to merge")?;
    let n = match out.shard {
        Some([_, n]) if n >= 2 => n,
        _ => return Err("merge: the first certificate is not a shard".into()),
    };
    let mut parts = vec![std::mem::take(&mut out.cases)];
    let mut shards = vec![out.shard];
    for p in it {
        if p.format != out.format
            || p.ratio != out.ratio
            || p.rule != out.rule
            || p.tol_cos != out.tol_cos
            || p.max_depth != out.max_depth
            || p.n_cases != out.n_cases
        {
            return Err(
                "certificates of different runs (ratio, rule, tolerance or depth differ)".into(),
            );
        }
        out.seconds += p.seconds;
        shards.push(p.shard);
        parts.push(p.cases);
    }
    let mut got: Vec<usize> = Vec::new();
    for s in &shards {
        match s {
            Some([i, m]) if *m == n && i < m => got.push(*i),
            _ => return Err(format!("merge: shard {s:?} is not i/{n}")),
        }
    }
    let mut sorted = got.clone();
    sorted.sort_unstable();
    if sorted != (0..n).collect::<Vec<_>>() {
        return Err(format!(
            "merge: the shards {got:?} are not 0..{n}, each exactly once (incomplete or overlapping)"
        ));
    }
    for (&i, cases) in got.iter().zip(&parts) {
        let idx: Vec<usize> = cases.iter().map(|c| c.index).collect();
        let expect: Vec<usize> = (0..out.n_cases).filter(|c| c % n == i).collect();
        if idx != expect {
            return Err(format!(
                "merge: shard {i}/{n} holds cases {idx:?}, expected {expect:?}"
            ));
        }
    }
    out.cases = parts.into_iter().flatten().collect();
    out.shard = None;
    finish(&mut out)?;
    Ok(out)
}

/// Human-readable label of a tet vertex index (for reports).
pub fn label(k: usize) -> &'static str {
    LABELS[k]
}
