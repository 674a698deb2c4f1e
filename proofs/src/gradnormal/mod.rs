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

/// Run parameters.
#[derive(Clone, Copy, Debug)]
pub struct Config {
    pub ratio: Ratio,
    pub rule: DiagonalRule,
    /// Target width of the cosine enclosures: 1e-6° of angle is at least 0.5·1e-6·π/180
    /// in cosine for angles in [30°, 150°].
    pub tol_cos: f64,
    pub max_depth: u8,
    pub shard: Option<(usize, usize)>,
    pub progress: bool,
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

/// Run the proof (or one shard of it).
pub fn run(cfg: &Config) -> Result<Certificate, String> {
    let t0 = std::time::Instant::now();
    let derived = Derived::new(cfg.ratio);
    let cases = derived.cases(cfg.rule)?;
    let n = cases.len();
    let chosen: Vec<(usize, Case)> = cases
        .into_iter()
        .enumerate()
        .filter(|(i, _)| cfg.shard.map_or(true, |(k, m)| i % m == k))
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
    let search = Search {
        tol: cfg.tol_cos,
        max_depth: cfg.max_depth,
        seed: 9,
    };
    let entries: Result<Vec<CaseEntry>, String> = chosen
        .into_par_iter()
        .map(|(index, case)| {
            let objs = objectives(cfg.ratio, &case);
            let dyns: Vec<&dyn Objective> = objs.iter().map(|o| o as &dyn Objective).collect();
            let cert = bnb::solve(&dyns, search).map_err(|e| format!("case {}: {e}", case.name))?;
            bar.inc(1);
            Ok(CaseEntry { index, case, cert })
        })
        .collect();
    bar.finish_and_clear();
    let mut cert = Certificate {
        format: FORMAT.into(),
        ratio: cfg.ratio.label(),
        rule: cfg.rule.name().into(),
        tol_cos: cfg.tol_cos,
        max_depth: cfg.max_depth,
        n_cases: n,
        shard: cfg.shard.map(|(a, b)| [a, b]),
        seconds: 0.0,
        cases: entries?,
        summary: None,
        claims: Vec::new(),
    };
    finish(&mut cert)?;
    cert.seconds = t0.elapsed().as_secs_f64();
    Ok(cert)
}

/// Fill summary and claims when every case is present.
fn finish(cert: &mut Certificate) -> Result<(), String> {
    cert.cases.sort_by_key(|c| c.index);
    let complete = cert.cases.len() == cert.n_cases
        && cert.cases.iter().enumerate().all(|(i, c)| c.index == i);
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
#[derive(Debug)]
pub struct CheckReport {
    pub cases: usize,
    pub leaves: usize,
    pub complete: bool,
    pub claims: Vec<Claim>,
}

/// Re-verify a certificate independently of the search.
pub fn check(cert: &Certificate) -> Result<CheckReport, String> {
    if cert.format != FORMAT {
        return Err(format!("unknown certificate format `{}`", cert.format));
    }
    let ratio = Ratio::parse(&cert.ratio)?;
    let rule: DiagonalRule = cert.rule.parse().map_err(|e| format!("{e}"))?;
    let derived = Derived::new(ratio);
    let cases = derived.cases(rule)?;
    if cases.len() != cert.n_cases {
        return Err(format!(
            "the tiling gives {} cases, the certificate says {}",
            cases.len(),
            cert.n_cases
        ));
    }
    let mut seen = vec![false; cases.len()];
    for e in &cert.cases {
        let c = cases
            .get(e.index)
            .ok_or_else(|| format!("case index {} out of range", e.index))?;
        if std::mem::replace(&mut seen[e.index], true) {
            return Err(format!("case {} appears twice", e.index));
        }
        if *c != e.case {
            return Err(format!(
                "case {} ({}) differs from the case derived from the tiling",
                e.index, e.case.name
            ));
        }
    }
    let results: Result<Vec<()>, String> = cert
        .cases
        .par_iter()
        .map(|e| {
            let objs = objectives(ratio, &e.case);
            let dyns: Vec<&dyn Objective> = objs.iter().map(|o| o as &dyn Objective).collect();
            bnb::check_case(&dyns, &e.cert)
                .map_err(|m| format!("case {} ({}): {m}", e.index, e.case.name))?;
            Ok(())
        })
        .collect();
    results?;
    let complete = seen.iter().all(|&s| s);
    let mut claims = Vec::new();
    if complete {
        let mut sorted = cert.cases.clone();
        sorted.sort_by_key(|c| c.index);
        let (s, c) = summarize(ratio, rule, &sorted);
        if cert.summary.as_ref() != Some(&s) {
            return Err(
                "the summary differs from the one recomputed from the verified cases".into(),
            );
        }
        if cert.claims != c {
            return Err(
                "the claims/verdicts differ from the ones recomputed from the verified cases"
                    .into(),
            );
        }
        claims = c;
    } else if cert.summary.is_some() || !cert.claims.is_empty() {
        return Err("a partial certificate (shard) must not state a summary or claims".into());
    }
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

/// Combine shard certificates of the same run.
pub fn merge(parts: Vec<Certificate>) -> Result<Certificate, String> {
    let mut it = parts.into_iter();
    let mut out = it.next().ok_or("nothing to merge")?;
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
        out.cases.extend(p.cases);
    }
    let mut idx: Vec<usize> = out.cases.iter().map(|c| c.index).collect();
    idx.sort();
    if idx.windows(2).any(|w| w[0] == w[1]) {
        return Err("a case appears in two shards".into());
    }
    out.shard = None;
    finish(&mut out)?;
    if out.summary.is_none() {
        out.shard = Some([0, 0]);
    }
    Ok(out)
}

/// Human-readable label of a tet vertex index (for reports).
pub fn label(k: usize) -> &'static str {
    LABELS[k]
}
