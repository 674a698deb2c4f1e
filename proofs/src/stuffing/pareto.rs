//! `proofs pareto DIR`: the certified Pareto front of isosurface stuffing over
//! (α_long, α_short). Each point is a complete certificate of `proofs stuffing
//! --alpha-long A --alpha-short B` in DIR, re-verified by [`super::check`] before it is
//! used; its coordinates are the *proven* ends of the enclosures: the smallest angle is
//! at least the lower end, the largest at most the upper end. The front of a criterion
//! (dihedral, or plane angle) is the set of non-dominated pairs of one family (warping
//! order and sidedness); Table 1's rows of that family are compared with every point: a
//! pair whose proven bounds beat a row's two paper values is a finding.
use super::{cases::DEN, check, custom::Params, Certificate, BOUNDS};
use crate::exact::Verdict;
use certmesh::stuffing::params::TABLE1;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// One certified parameter pair.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Point {
    pub alpha_long: f64,
    pub alpha_short: f64,
    pub ordered: bool,
    pub double_sided: bool,
    /// Per bound (the order of [`BOUNDS`]): the proven value — the lower end of the
    /// enclosure for a smallest angle, the upper end for a largest angle (degrees).
    pub proven_deg: [f64; 6],
    /// The enclosure widths (degrees).
    pub width_deg: [f64; 6],
    pub safe: &'static str,
    pub flat_output_cases: usize,
    pub certificate: String,
    pub leaves: usize,
    pub seconds: f64,
}

impl Point {
    pub fn from_certificate(c: &Certificate, path: &str) -> Result<Point, String> {
        if c.partial {
            return Err(format!("{path}: a shard; merge the shards first"));
        }
        Params::parse(&c.row)
            .ok_or_else(|| format!("{path}: row '{}' is not an audited parameter pair", c.row))?;
        let mut proven = [f64::NAN; 6];
        let mut width = [f64::NAN; 6];
        for (b, (name, _, is_min)) in BOUNDS.iter().enumerate() {
            let r = c
                .bounds
                .iter()
                .find(|r| r.bound == *name)
                .ok_or_else(|| format!("{path}: no {name} bound"))?;
            let d = r
                .deg
                .ok_or_else(|| format!("{path}: {name} has no enclosure"))?;
            proven[b] = if *is_min { d[0] } else { d[1] };
            width[b] = d[1] - d[0];
        }
        Ok(Point {
            alpha_long: c.alphas.long as f64 / DEN as f64,
            alpha_short: c.alphas.short as f64 / DEN as f64,
            ordered: c.alphas.ordered,
            double_sided: c.alphas.double_sided,
            proven_deg: proven,
            width_deg: width,
            safe: c.safe.verdict.name(),
            flat_output_cases: c.unreduced.len(),
            certificate: path.to_string(),
            leaves: c.leaves,
            seconds: c.seconds,
        })
    }
    fn family(&self) -> (bool, bool) {
        (self.ordered, self.double_sided)
    }
    pub fn family_name(ordered: bool, double_sided: bool) -> String {
        format!(
            "{}, {}",
            if ordered { "ordered" } else { "unordered" },
            if double_sided {
                "double-sided"
            } else {
                "one-sided"
            }
        )
    }
}

/// A criterion: a pair of bounds, the smallest (maximised) and the largest (minimised).
pub const CRITERIA: [(&str, usize, usize); 2] = [("dihedral", 0, 1), ("plane", 2, 3)];

/// Does `q` dominate `p` on the criterion (at least as good on both, better on one)?
fn dominates(q: &Point, p: &Point, lo: usize, hi: usize) -> bool {
    let (qa, qb, pa, pb) = (
        q.proven_deg[lo],
        q.proven_deg[hi],
        p.proven_deg[lo],
        p.proven_deg[hi],
    );
    qa >= pa && qb <= pb && (qa > pa || qb < pb)
}

/// The non-dominated points of one family on one criterion, by increasing smallest angle.
pub fn front(points: &[Point], family: (bool, bool), lo: usize, hi: usize) -> Vec<usize> {
    let fam: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].family() == family)
        .collect();
    let mut f: Vec<usize> = fam
        .iter()
        .copied()
        .filter(|&i| {
            !fam.iter()
                .any(|&j| dominates(&points[j], &points[i], lo, hi))
        })
        .collect();
    f.sort_by(|&a, &b| points[a].proven_deg[lo].total_cmp(&points[b].proven_deg[lo]));
    f
}

/// A pair that beats a Table 1 row of its family on both bounds of a criterion.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Finding {
    pub criterion: &'static str,
    pub row: &'static str,
    pub row_values: [f64; 2],
    pub point: usize,
    pub proven: [f64; 2],
}

pub fn findings(points: &[Point]) -> Vec<Finding> {
    let mut out = Vec::new();
    for (crit, lo, hi) in CRITERIA {
        for r in TABLE1.iter() {
            let vals = [
                r.bounds.min_dihedral,
                r.bounds.max_dihedral,
                r.bounds.min_plane,
                r.bounds.max_plane,
            ];
            let (Some(a), Some(b)) = (vals[lo], vals[hi]) else {
                continue;
            };
            for (i, p) in points.iter().enumerate() {
                // Same family; a safe row is beaten only by a safe pair.
                if p.family() != (r.ordered, r.double_sided)
                    || (r.safe && p.safe != Verdict::Proven.name())
                {
                    continue;
                }
                if p.proven_deg[lo] > a && p.proven_deg[hi] < b {
                    out.push(Finding {
                        criterion: crit,
                        row: r.name,
                        row_values: [a, b],
                        point: i,
                        proven: [p.proven_deg[lo], p.proven_deg[hi]],
                    });
                }
            }
        }
    }
    out
}

/// Read and check every custom-pair certificate `DIR/*.json` (not `*.summary.json`).
pub fn read_dir(
    dir: &Path,
    load: impl Fn(&Path) -> Result<Certificate, String>,
    progress: bool,
) -> Result<Vec<Point>, String> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            let s = p.to_string_lossy();
            s.ends_with(".json") && !s.ends_with(".summary.json")
        })
        .collect();
    files.sort();
    let mut pts = Vec::new();
    for f in files {
        let c = load(&f)?;
        if Params::parse(&c.row).is_none() {
            continue; // a Table 1 row's certificate: not a point of the grid
        }
        let t0 = std::time::Instant::now();
        check(&c).map_err(|e| format!("{}: rejected by check: {e}", f.display()))?;
        if progress {
            eprintln!(
                "  checked {} ({:.1} s)",
                f.display(),
                t0.elapsed().as_secs_f64()
            );
        }
        pts.push(Point::from_certificate(&c, &f.display().to_string())?);
    }
    if pts.is_empty() {
        return Err(format!(
            "{}: no certificate of an audited parameter pair (proofs stuffing --alpha-long A --alpha-short B -o DIR/NAME.json)",
            dir.display()
        ));
    }
    pts.sort_by(|a, b| {
        (a.ordered, a.double_sided, a.alpha_long, a.alpha_short)
            .partial_cmp(&(b.ordered, b.double_sided, b.alpha_long, b.alpha_short))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    Ok(pts)
}

/// Reference points marked on the plots: parameter pairs of public implementations.
pub const IMPLEMENTATIONS: [(&str, f64, f64, bool); 2] = [
    ("Unreal Engine", 0.21509, 0.359, false),
    ("ModalSound", 0.25, 0.42978, true),
];

fn label(p: &Point) -> String {
    format!("({:.5}, {:.5})", p.alpha_long, p.alpha_short)
}

/// The markdown report: every point, the fronts, the findings.
pub fn markdown(points: &[Point]) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "| α_long | α_short | family | min dihedral ≥ | max dihedral ≤ | min plane ≥ | max plane ≤ | min exposed ≥ | max exposed ≤ | safe | flat cases | leaves | seconds | certificate |");
    let _ = writeln!(
        o,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for p in points {
        let d = &p.proven_deg;
        let _ = writeln!(
            o,
            "| {:.5} | {:.5} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {} | {} | {} | {:.0} | `{}` |",
            p.alpha_long,
            p.alpha_short,
            Point::family_name(p.ordered, p.double_sided),
            d[0], d[1], d[2], d[3], d[4], d[5],
            p.safe,
            p.flat_output_cases,
            p.leaves,
            p.seconds,
            Path::new(&p.certificate).file_name().map(|s| s.to_string_lossy().to_string()).unwrap_or_default()
        );
    }
    let mut fams: Vec<(bool, bool)> = points.iter().map(|p| p.family()).collect();
    fams.sort();
    fams.dedup();
    for (crit, lo, hi) in CRITERIA {
        for &fam in &fams {
            let f = front(points, fam, lo, hi);
            let _ = writeln!(
                o,
                "\n**Front, {crit} angles, {}** ({} of {} pairs non-dominated): {}",
                Point::family_name(fam.0, fam.1),
                f.len(),
                points.iter().filter(|p| p.family() == fam).count(),
                f.iter()
                    .map(|&i| format!(
                        "{} → [{:.4}°, {:.4}°]",
                        label(&points[i]),
                        points[i].proven_deg[lo],
                        points[i].proven_deg[hi]
                    ))
                    .collect::<Vec<_>>()
                    .join("; ")
            );
        }
    }
    let fs = findings(points);
    let _ = writeln!(o, "\n**Pairs that beat a Table 1 row of their family on both bounds of a criterion** (a safe row only by a safe pair):");
    if fs.is_empty() {
        let _ = writeln!(o, "none.");
    }
    for f in &fs {
        let p = &points[f.point];
        let _ = writeln!(
            o,
            "- {} angles: {} proves [{:.4}°, {:.4}°], Table 1 row `{}` states [{:.4}°, {:.4}°] (certificate `{}`).",
            f.criterion,
            label(p),
            f.proven[0],
            f.proven[1],
            f.row,
            f.row_values[0],
            f.row_values[1],
            p.certificate
        );
    }
    o
}

/// The plots `OUT/pareto-{dihedral,plane}.svg/png`: every pair of the unordered
/// one-sided family, its front joined, Table 1's unordered one-sided rows (paper values)
/// and the public implementations (their certified points when in DIR).
pub fn plots(points: &[Point], out: &Path) -> Result<Vec<PathBuf>, String> {
    use certmesh::reproduce::plot::{scatter, PointSet};
    let fam = (false, false);
    let mut written = Vec::new();
    for (crit, lo, hi) in CRITERIA {
        let in_fam: Vec<&Point> = points.iter().filter(|p| p.family() == fam).collect();
        // A pair whose tetrahedra can be flat proves only (0°, 180°): drawn, it would
        // squeeze every other point into a corner; it is counted in the legend instead.
        let flat = |p: &Point| p.proven_deg[lo] <= 1e-9 || p.proven_deg[hi] >= 180.0 - 1e-9;
        let n_flat = in_fam.iter().filter(|p| flat(p)).count();
        let in_fam: Vec<&Point> = in_fam.into_iter().filter(|p| !flat(p)).collect();
        let f = front(points, fam, lo, hi);
        let rows: Vec<_> = TABLE1
            .iter()
            .filter(|r| !r.ordered && !r.double_sided)
            .filter_map(|r| {
                let v = [
                    r.bounds.min_dihedral,
                    r.bounds.max_dihedral,
                    r.bounds.min_plane,
                    r.bounds.max_plane,
                ];
                Some(((v[lo]?, v[hi]?), r.name.to_string()))
            })
            .collect();
        let imps: Vec<_> = IMPLEMENTATIONS
            .iter()
            .filter_map(|(n, a, b, ord)| {
                points
                    .iter()
                    .find(|p| {
                        (p.alpha_long - a).abs() < 5e-6
                            && (p.alpha_short - b).abs() < 5e-6
                            && p.ordered == *ord
                            && !p.double_sided
                    })
                    .map(|p| {
                        (
                            (p.proven_deg[lo], p.proven_deg[hi]),
                            format!("{n}{}", if *ord { " (ordered)" } else { "" }),
                        )
                    })
            })
            .collect();
        let mut sets = vec![
            PointSet {
                name: if n_flat > 0 {
                    format!("certified pairs (unordered, one-sided; {n_flat} with only (0°, 180°) not shown)")
                } else {
                    "certified pairs (unordered, one-sided)".into()
                },
                points: in_fam
                    .iter()
                    .map(|p| (p.proven_deg[lo], p.proven_deg[hi]))
                    .collect(),
                labels: vec![],
                joined: false,
                filled: false,
            },
            PointSet {
                name: "certified Pareto front".into(),
                points: f
                    .iter()
                    .map(|&i| (points[i].proven_deg[lo], points[i].proven_deg[hi]))
                    .collect(),
                labels: f.iter().map(|&i| label(&points[i])).collect(),
                joined: true,
                filled: true,
            },
            PointSet {
                name: "Table 1 rows (paper values)".into(),
                points: rows.iter().map(|r| r.0).collect(),
                labels: rows.iter().map(|r| r.1.clone()).collect(),
                joined: false,
                filled: true,
            },
            PointSet {
                name: "public implementations (certified)".into(),
                points: imps.iter().map(|r| r.0).collect(),
                labels: imps.iter().map(|r| r.1.clone()).collect(),
                joined: false,
                filled: true,
            },
        ];
        sets.retain(|s| !s.points.is_empty());
        let base = out.join(format!("pareto-{crit}"));
        scatter(
            &base,
            &format!("Isosurface stuffing: certified {crit}-angle bounds over (α_long, α_short)"),
            &format!("proven smallest {crit} angle (degrees; larger is better)"),
            &format!("proven largest {crit} angle (degrees; smaller is better)"),
            &sets,
        )
        .map_err(|e| e.to_string())?;
        written.push(base.with_extension("svg"));
    }
    Ok(written)
}
