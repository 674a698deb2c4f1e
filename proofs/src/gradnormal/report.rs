//! PROOF.md, figures, the derived regions and the a/e scan.
use super::cases::{Case, Derived, Ratio};
use super::sample::angles_at;
use crate::exact::{deg_hi, deg_lo};
use crate::geometry::{DiagonalRule, LABELS, MIDPOINT_EDGES, MIDPOINT_NAMES};
use crate::gradnormal::{self, Certificate, Config};
use std::fmt::Write as _;
use std::path::Path;

/// The derived regions of plane normals, with every vertex ray described by the order of
/// the tet and octahedron vertices along it ("A=B=C > D > ..." is the normal of the
/// plane through A, B, C with the others below).
pub fn regions_markdown(ratio: Ratio) -> Result<String, String> {
    let d = Derived::new(ratio);
    let pts = d.named_points();
    let mut s = String::new();
    let _ = writeln!(s, "a/e = {} ({:.9})\n", ratio.label(), ratio.f64());
    let _ = writeln!(
        s,
        "Dihedral angles of τ (exact sign of the cosine: + acute, 0 right, − obtuse):\n"
    );
    for (k, [p, q]) in MIDPOINT_EDGES.iter().enumerate() {
        let _ = writeln!(
            s,
            "- edge {}{} (midpoint {}): {}",
            LABELS[*p],
            LABELS[*q],
            MIDPOINT_NAMES[k],
            match d.dihedral_signs[k] {
                0 => "90° (four tetrahedra around it: valence-four vertices possible)",
                1 => "acute",
                _ => "obtuse",
            }
        );
    }
    let _ = writeln!(s);
    for o in &d.octahedra {
        let _ = writeln!(
            s,
            "Octahedron around {}{} (Fig 12): ring {} (lattice {:?})",
            LABELS[o.edge[0]],
            LABELS[o.edge[1]],
            o.ring
                .iter()
                .map(|r| r.0.clone())
                .collect::<Vec<_>>()
                .join(", "),
            o.ring.iter().map(|r| r.1).collect::<Vec<_>>()
        );
    }
    let _ = writeln!(s);
    let cases = d.cases(DiagonalRule::Paper)?;
    let mut seen = std::collections::BTreeSet::new();
    for c in &cases {
        if !seen.insert(c.region.clone()) {
            continue;
        }
        let _ = writeln!(s, "### Region {} (for {})\n", c.region, c.name);
        for (i, p) in c.pieces.iter().enumerate() {
            let _ = writeln!(
                s,
                "- piece {}: constraints {}; {} vertex rays (μ-space):",
                i + 1,
                p.constraints
                    .iter()
                    .map(|x| x.0.clone())
                    .collect::<Vec<_>>()
                    .join(", "),
                p.rays.len()
            );
            for r in &p.rays {
                let _ = writeln!(s, "  - μ = {:?}: {}", r, d.describe(*r, &pts));
            }
        }
        let _ = writeln!(s);
    }
    Ok(s)
}

/// Angle functions along every boundary arc of a case's region pieces (the paper's
/// Figs 14, 15, 17, 18): x = arc index + t.
pub fn boundary_series(
    ratio: Ratio,
    case: &Case,
    samples: usize,
) -> Vec<certmesh::reproduce::plot::Series> {
    let mut out: Vec<certmesh::reproduce::plot::Series> = (0..3)
        .map(|k| certmesh::reproduce::plot::Series {
            name: format!("angle at {}", case.vertices[k].name),
            points: Vec::new(),
        })
        .collect();
    let mut arc = 0usize;
    for p in &case.pieces {
        let n = p.rays.len();
        for i in 0..n {
            let (a, b) = (p.rays[i], p.rays[(i + 1) % n]);
            for s in 0..=samples {
                let t = s as f64 / samples as f64;
                let mu = [0, 1, 2].map(|k| (1.0 - t) * a[k] as f64 + t * b[k] as f64);
                let ang = angles_at(ratio, case, mu);
                for k in 0..3 {
                    out[k].points.push((arc as f64 + t, ang[k]));
                }
            }
            arc += 1;
        }
    }
    out
}

fn fmt2(x: [f64; 2]) -> String {
    format!("[{:.9}°, {:.9}°]", x[0], x[1])
}

/// The boundary-arc figures: `arcs-case<i>` for the cases `which` (the paper's Figs 17,
/// 14/15) and `arcs-all`, the pointwise min and max over every case (Fig 18), in `fig`.
pub fn write_arcs(fig: &Path, ratio: Ratio, cases: &[Case], which: &[usize]) -> Result<(), String> {
    let mut all = Vec::new();
    // The cases' arcs one after another (x = arcs of the cases before + arc + t), so
    // the envelope has no gaps to bridge.
    let mut offset = 0.0;
    for (i, c) in cases.iter().enumerate() {
        let series = boundary_series(ratio, c, 200);
        let arcs = series
            .first()
            .and_then(|s| s.points.last())
            .map_or(0.0, |p| p.0.round());
        if which.contains(&i) {
            let base = fig.join(format!("arcs-case{i}"));
            certmesh::reproduce::plot::lines(
                &base,
                &c.name,
                "boundary arc k + position t on it (no unit)",
                "projected angle (degrees)",
                &series,
            )
            .map_err(|e| e.to_string())?;
        }
        for (k, s) in series.into_iter().enumerate() {
            all.push(certmesh::reproduce::plot::Series {
                name: if i == 0 {
                    format!("angle {k}")
                } else {
                    String::new()
                },
                points: s.points.iter().map(|&(x, y)| (x + offset, y)).collect(),
            });
        }
        offset += arcs;
    }
    let envelope = envelope_series(&all);
    certmesh::reproduce::plot::lines(
        &fig.join("arcs-all"),
        &format!(
            "All {} triangles: min and max projected angle along their boundary arcs, case after case",
            cases.len()
        ),
        "boundary arc k (all cases) + t (no unit)",
        "projected angle (degrees)",
        &envelope,
    )
    .map_err(|e| e.to_string())?;
    Ok(())
}

/// Run every rule at `ratio`, write the certificates, figures and PROOF.md into `dir`.
pub fn write_papers(dir: &Path, ratio: Ratio, budget: &crate::bnb::Budget) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let fig = dir.join("figures");
    std::fs::create_dir_all(&fig).map_err(|e| format!("{}: {e}", fig.display()))?;
    let cert_dir = Path::new("target").join("proofs");
    std::fs::create_dir_all(&cert_dir).map_err(|e| format!("{}: {e}", cert_dir.display()))?;
    let mut runs: Vec<(DiagonalRule, Certificate, f64, String)> = Vec::new();
    for rule in [
        DiagonalRule::Paper,
        DiagonalRule::Alternate,
        DiagonalRule::Shorter,
    ] {
        let mut cfg = Config::new(ratio, rule);
        cfg.progress = true;
        cfg.budget = budget.clone();
        let cert = gradnormal::run(&cfg)?;
        let path = cert_dir.join(format!("gradnormal-{}-{}.json", ratio.label(), rule.name()));
        std::fs::write(
            &path,
            serde_json::to_string(&cert).map_err(|e| e.to_string())?,
        )
        .map_err(|e| format!("{}: {e}", path.display()))?;
        let t0 = std::time::Instant::now();
        gradnormal::check(&cert)?;
        let check_s = t0.elapsed().as_secs_f64();
        runs.push((rule, cert, check_s, path.display().to_string()));
    }
    let d = Derived::new(ratio);
    let paper = &runs[0].1;
    let cases = d.cases(DiagonalRule::Paper)?;
    write_arcs(&fig, ratio, &cases, &[0, 8, 10])?;
    super::maps::write_maps(&fig, ratio, &cases, &[0, 8, 10, 4])?;

    let mut s = String::new();
    let _ = writeln!(
        s,
        "# GradNormal angle bounds, certified over the full regions of plane normals\n"
    );
    let _ = writeln!(s, "Paper: J. Hass, M. Trnkova, *Approximating isosurfaces by guaranteed-quality triangular meshes*, Computer Graphics Forum (SGP) 2020, Theorem 1.1, Lemma 4.1, Sec. 4.3, Appendix A (Lemma 7.1, Claim 7.1, Figs 12–18).\n");
    let _ = writeln!(s, "Regenerate (this file, the figures and the certificates in `target/proofs/`):\n\n```\ncargo run --release -p proofs -- gradnormal --a {} --write-papers papers/gradnormal\ncargo run --release -p proofs -- check target/proofs/gradnormal-{}-paper.json\n```\n", ratio.label(), ratio.label());
    let _ = writeln!(s, "Geometry: the Goldberg tetrahedron τ(a, e) with a/e = {} read from the tiling data (`proofs/src/geometry.rs`, a mirror of `certmesh::gradnormal::tiling` until the merge), labels A = v0, B = v3, C = v1, D = v2, midpoints K = AB, L = AC, M = AD, N = BC, P = CD, Q = BD; the paper's diagonals LMNQ → MN, KMPN → MN, KLPQ → LQ, and for the valence-four square the diagonal through the midpoint of the vertical lattice edge (K K₂).\n", ratio.label());
    let _ = writeln!(s, "Method: for each of the {} triangles (4 elementary triangles, 3 × 2 quadrilateral halves, and the 2 triangles of the valence-four square at each end of both 90° edges AD and BC: 8, where the paper treats 2 and invokes symmetry), the region of plane normals is derived as an exact rational polyhedral cone (see *Regions* below), cut into bilinear quadrilaterals and covered by a quadtree; inari intervals with a mean-value form enclose cos of each projected angle on every leaf; the branch and bound stops when each extreme's enclosure is narrower than 1e-6°. All threshold comparisons are exact (num-rational, with a rational enclosure of cos of the threshold angle). `proofs check` re-verifies each certificate independently of the search (leaf partition, every leaf and witness re-evaluated, claims recomputed).\n", cases.len());
    let _ = writeln!(s, "## Claims (paper's diagonal rule)\n");
    let _ = writeln!(s, "| claim | certified | verdict |\n|---|---|---|");
    if let Some(sum) = &paper.summary {
        for c in &paper.claims {
            let cert = if c.claim.starts_with("Lemma 4.1") {
                format!(
                    "MidNormal angles exactly in [{:.6}°, {:.6}°]",
                    sum.midnormal_min_deg, sum.midnormal_max_deg
                )
            } else if c.claim.starts_with("Fig 14") {
                format!(
                    "valence-four triangles over all of Y: min {} , max {}",
                    fmt2(sum.v4_min_deg),
                    fmt2(sum.v4_max_deg)
                )
            } else {
                format!(
                    "min angle {} , max angle {}",
                    fmt2(sum.min_deg),
                    fmt2(sum.max_deg)
                )
            };
            let _ = writeln!(s, "| {} | {} | **{}** |", c.claim, cert, c.verdict.name());
        }
        let _ = writeln!(
            s,
            "\nWitnesses (plane normal m, unit, in the paper's coordinates with e = 1):\n"
        );
        for c in &paper.claims {
            let _ = writeln!(s, "- {} — {}: {}", c.claim, c.verdict.name(), c.witness);
        }
    }
    let _ = writeln!(s, "\n## Diagonal rules compared\n");
    let _ = writeln!(s, "| rule | cases | min angle | max angle | valence-four min | valence-four max | run (s) | check (s) | certificate |\n|---|---|---|---|---|---|---|---|---|");
    for (rule, c, chk, path) in &runs {
        if let Some(sum) = &c.summary {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {:.1} | {:.1} | `{}` |",
                rule.name(),
                c.n_cases,
                fmt2(sum.min_deg),
                fmt2(sum.max_deg),
                fmt2(sum.v4_min_deg),
                fmt2(sum.v4_max_deg),
                c.seconds,
                chk,
                path
            );
        }
    }
    let _ = writeln!(s, "\n`paper`: the paper's diagonals; `alternate`: the other diagonal of every quadrilateral and of the valence-four square; `shorter`: the diagonal that is shorter after projection (an extra quadratic constraint on the region, ties belong to both).\n");
    for (rule, c, _, _) in &runs {
        let _ = writeln!(
            s,
            "Verdicts with the `{}` rule: {}\n",
            rule.name(),
            c.claims
                .iter()
                .map(|x| format!("{} — **{}**", x.claim, x.verdict.name()))
                .collect::<Vec<_>>()
                .join("; ")
        );
    }
    let _ = writeln!(s, "## Per case (paper's rule)\n");
    let _ = writeln!(s, "| # | triangle | region | angle at | min angle | max angle | leaves |\n|---|---|---|---|---|---|---|");
    if let Some(sum) = &paper.summary {
        for cs in &sum.cases {
            for a in &cs.angles {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {} | {} | {} |",
                    cs.index,
                    cs.name,
                    cs.region,
                    a.vertex,
                    fmt2(a.min_deg),
                    fmt2(a.max_deg),
                    cs.leaves
                );
            }
        }
    }
    let _ = writeln!(s, "\n## Regions (derived, exact)\n");
    s.push_str(&regions_markdown(ratio)?);
    let _ = writeln!(s, "## Figures\n");
    let _ = writeln!(s, "- `figures/arcs-case0`, `arcs-case8`, `arcs-case10` (.svg/.png): the three projected angles of KLM, of L P Q (KLPQ split by LQ) and of the valence-four triangle K L K₂ along every boundary arc of their regions (the paper's Figs 17, 14/15).");
    let _ = writeln!(s, "- `figures/arcs-all`: pointwise min and max over all angles along all boundary arcs (Fig 18).");
    let _ = writeln!(s, "- `figures/map-case*`: the smallest and the largest projected angle over the full region (gnomonic chart), the new view of the interiors.");
    let _ = writeln!(s, "- `figures/scan-paper`: certified bounds against a/e (`proofs gradnormal --scan 9`, tolerance 1e-4°).\n");
    let _ = writeln!(s, "Display values in degrees come from f64 `acos` of certified cosine bounds, rounded outward by 1e-12°; no verdict depends on them (verdicts compare cosines exactly).\n");
    let _ = writeln!(s, "Generated by `proofs gradnormal --write-papers` on {} cases per rule; times are wall-clock on the build machine (2 shared cores).", paper.n_cases);
    let _ = (deg_lo(0.0), deg_hi(0.0));
    let path = dir.join("PROOF.md");
    let findings = dir.join("FINDINGS.md");
    if findings.exists() {
        let f = std::fs::read_to_string(&findings).map_err(|e| e.to_string())?;
        s.push_str("\n");
        s.push_str(&f);
    }
    std::fs::write(&path, s).map_err(|e| format!("{}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

fn envelope_series(
    all: &[certmesh::reproduce::plot::Series],
) -> Vec<certmesh::reproduce::plot::Series> {
    use std::collections::BTreeMap;
    let mut lo: BTreeMap<i64, f64> = BTreeMap::new();
    let mut hi: BTreeMap<i64, f64> = BTreeMap::new();
    for s in all {
        for &(x, y) in &s.points {
            let key = (x * 1000.0).round() as i64;
            let l = lo.entry(key).or_insert(f64::INFINITY);
            *l = l.min(y);
            let h = hi.entry(key).or_insert(f64::NEG_INFINITY);
            *h = h.max(y);
        }
    }
    vec![
        certmesh::reproduce::plot::Series {
            name: "min over all angles".into(),
            points: lo
                .into_iter()
                .map(|(k, v)| (k as f64 / 1000.0, v))
                .collect(),
        },
        certmesh::reproduce::plot::Series {
            name: "max over all angles".into(),
            points: hi
                .into_iter()
                .map(|(k, v)| (k as f64 / 1000.0, v))
                .collect(),
        },
    ]
}

/// The work estimate of one value of a `--scan` (paper rule, 1e-4°: about 170,000
/// boxes at a/e = √2/4; rounded up).
pub const SCAN_BOXES_PER_VALUE: u64 = 250_000;

/// Certified bounds against a/e (coarser tolerance 1e-4°), plotted; the runs share
/// `budget`.
pub fn scan(
    rule: DiagonalRule,
    n: usize,
    dir: &Path,
    budget: &crate::bnb::Budget,
) -> Result<Vec<String>, String> {
    if n < 2 {
        return Err(format!("--scan {n}: at least 2 values of a/e"));
    }
    let estimate = n as u64 * SCAN_BOXES_PER_VALUE;
    if estimate > budget.max_boxes() {
        return Err(format!(
            "--scan {n}: about {SCAN_BOXES_PER_VALUE} boxes per value of a/e, {estimate} in all, above the work budget of {} boxes (--max-boxes N raises it; or lower --scan)",
            budget.max_boxes()
        ));
    }
    let mut rows = Vec::new();
    let mut smin = Vec::new();
    let mut smax = Vec::new();
    for i in 0..n {
        let r = 0.2 + 0.4 * i as f64 / (n - 1) as f64;
        let mut cfg = Config::new(Ratio::Value(r), rule);
        cfg.tol_cos = 0.5e-4 * std::f64::consts::PI / 180.0;
        cfg.max_depth = 30;
        cfg.budget = budget.clone();
        let c = gradnormal::run(&cfg)?;
        if let Some(s) = &c.summary {
            rows.push(format!(
                "a/e = {r:.4}: min angle {}, max angle {}, MidNormal [{:.4}°, {:.4}°] ({:.1} s)",
                fmt2(s.min_deg),
                fmt2(s.max_deg),
                s.midnormal_min_deg,
                s.midnormal_max_deg,
                c.seconds
            ));
            smin.push((r, s.min_deg[0]));
            smax.push((r, s.max_deg[1]));
        }
    }
    std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    let series = vec![
        certmesh::reproduce::plot::Series {
            name: "certified min angle (lower end)".into(),
            points: smin,
        },
        certmesh::reproduce::plot::Series {
            name: "certified max angle (upper end)".into(),
            points: smax,
        },
    ];
    certmesh::reproduce::plot::lines(
        &dir.join(format!("scan-{}", rule.name())),
        "GradNormal certified angle bounds vs a/e",
        "a/e (length ratio, no unit)",
        "angle (degrees)",
        &series,
    )
    .map_err(|e| e.to_string())?;
    Ok(rows)
}
