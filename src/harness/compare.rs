//! The comparison harness: run every (surface, algorithm) pair through the same
//! interface and judge the outputs side by side — topology verdict against the catalog,
//! components and genus found, angle range, Hausdorff estimate, time, evaluations and the
//! certificate.
use crate::catalog::{Entry, Topology};
use crate::error::Result;
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;
use crate::mesher::options::MesherOptions;
use crate::mesher::registry as algorithms;
use crate::mesher::{self, Certificate, Mesh, Progress, Run};
use crate::metrics::{self, FidelityParams};
use serde::Serialize;

/// One row of the comparison table.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub surface: String,
    pub algo: String,
    pub dim: usize,
    /// Topology verdict against the catalog (`None`: no expected topology, e.g. singular).
    pub topology_ok: Option<bool>,
    pub expected: String,
    pub found: String,
    pub topology_reason: String,
    pub components: usize,
    /// Genus per closed component (surfaces).
    pub genus: Vec<usize>,
    pub closed: bool,
    pub manifold: bool,
    pub vertices: usize,
    /// Triangles (surfaces) or segments (curves).
    pub faces: usize,
    pub tetrahedra: Option<usize>,
    pub min_angle_deg: Option<f64>,
    pub max_angle_deg: Option<f64>,
    /// Sampled two-sided Hausdorff estimate (not a bound). `null` in JSON when it is
    /// undefined or infinite; `hausdorff_note` then says why.
    pub hausdorff: Option<f64>,
    /// Why `hausdorff` is undefined or infinite (e.g. no mesh point projects onto f = 0).
    pub hausdorff_note: Option<String>,
    /// What `hausdorff` is: a sampled estimate (under `--metrics fast`, from mesh
    /// samples without the vertices, [`metrics::fidelity::HAUSDORFF_KIND_SAMPLED`], or
    /// from a subset of `full`'s points sized to a small mesh,
    /// [`metrics::fidelity::HAUSDORFF_KIND_THINNED`]).
    pub hausdorff_kind: &'static str,
    /// How many mesh points (vertices and samples, or samples only) the mesh → surface
    /// side of `hausdorff` is the maximum over (those whose projection converged);
    /// `None` when no fidelity was measured.
    pub hausdorff_mesh_samples: Option<usize>,
    /// How many surface points the surface → mesh side is the maximum over.
    pub hausdorff_surface_samples: Option<usize>,
    pub seconds: f64,
    pub evaluations: u64,
    pub certified: bool,
    pub certificate: Certificate,
    /// Set when the mesher failed; the other fields are then empty.
    pub error: Option<String>,
    /// The Euler characteristic V − E + F of the output surface (`None` for curves).
    pub mesh_chi: Option<i64>,
    /// χ(S) certified by Morse counting ([`crate::morse::certified_chi`]): a
    /// mesh-independent topology check, the same for every mesher of a surface
    /// (`None`: not certified, see `certified_chi_note`; curves: not computed).
    pub certified_chi: Option<i64>,
    /// Why `certified_chi` is absent.
    pub certified_chi_note: Option<String>,
    /// Curves: the embedding signature of the output (components, degrees ≠ 2, faces
    /// with dual degrees, nesting; [`metrics::embedding_signature`]), clipped curves
    /// closed by the domain frame.
    pub signature: Option<String>,
    /// Curves: does the signature equal the one of the certified runs on the same
    /// curve (the exact sweep's first)? `None` when no run on the curve is certified.
    pub isotopy_agrees: Option<bool>,
}

impl Row {
    fn failed(surface: &str, algo: &str, dim: usize, e: String) -> Row {
        Row {
            surface: surface.into(),
            algo: algo.into(),
            dim,
            topology_ok: None,
            expected: String::new(),
            found: String::new(),
            topology_reason: String::new(),
            components: 0,
            genus: vec![],
            closed: false,
            manifold: false,
            vertices: 0,
            faces: 0,
            tetrahedra: None,
            min_angle_deg: None,
            max_angle_deg: None,
            hausdorff: None,
            hausdorff_note: None,
            hausdorff_kind: metrics::fidelity::HAUSDORFF_KIND,
            hausdorff_mesh_samples: None,
            hausdorff_surface_samples: None,
            seconds: 0.0,
            evaluations: 0,
            certified: false,
            certificate: Certificate::none(e.clone()),
            error: Some(e),
            mesh_chi: None,
            certified_chi: None,
            certified_chi_note: None,
            signature: None,
            isotopy_agrees: None,
        }
    }
}

/// How much fidelity sampling the harness does (kept modest so a matrix runs fast).
pub fn fidelity_params(domain: &Aabb, dim: usize) -> FidelityParams {
    FidelityParams::default()
        .mesh_samples(20_000)
        .seed_grid(if dim == 2 { 200 } else { 40 })
        .domain(*domain)
}

/// The mesh size (triangles) from which `--metrics fast` keeps all of
/// [`fidelity_params`]' mesh samples and seeds: 640,000, about 32 triangles per sample.
pub const FAST_FULL_SIZE: usize = 640_000;
/// The most `--metrics fast` thins the mesh samples: 1 in 39 (20,000 / 39: 513 kept).
pub const FAST_MAX_THIN: usize = 39;
/// The coarsest seed grid of `--metrics fast`: 12 per axis instead of 40 (about 1,400
/// surface points on the catalog's torus and genus 2). At 8 per axis the surface →
/// mesh side of GradNormal's genus 2 at its defaults fell to 0.45 of the 40³ one; at 12
/// it is within 4 %, as on the marching-cubes torus (measured, `papers/bench-report.md`).
pub const FAST_MIN_SEED_GRID: usize = 12;

/// [`fidelity_params`] sized to a surface mesh of `elements` triangles, for the
/// report's `--metrics fast`: with r = [`FAST_FULL_SIZE`] / `elements`, every k-th of
/// the 20,000 mesh samples (k the largest odd number ≤ r, at most [`FAST_MAX_THIN`]:
/// about one sample per 32 triangles), refined on the triangles of the largest
/// distances (their corners and all their samples: `FidelityParams::thin_samples`),
/// every point one of `full`'s; and a seed grid
/// of 40 / √r per axis (rounded, between [`FAST_MIN_SEED_GRID`] and 40), so that the
/// surface points, about proportional to its square, shrink about as much. The
/// report's work then grows with the mesh, rather than being the fixed sample of
/// `full` (and of `certmesh compare`, whose rows stay comparable) for a mesh of a few
/// thousand triangles as for one of a million. Curves (`dim` 2) keep the full sample.
pub fn fast_fidelity_params(domain: &Aabb, dim: usize, elements: usize) -> FidelityParams {
    let p = fidelity_params(domain, dim);
    if dim == 2 {
        return p;
    }
    let r = FAST_FULL_SIZE as f64 / elements.max(1) as f64;
    let k = (r.floor() as usize).clamp(1, FAST_MAX_THIN);
    let n = ((p.seed_grid as f64 / r.max(1.0).sqrt()).round() as usize)
        .clamp(FAST_MIN_SEED_GRID, p.seed_grid);
    p.thin_samples(k).seed_grid(n)
}

/// The fidelity parameters of the report at `level` for a mesh of `elements`
/// triangles or segments: `Full`, [`fidelity_params`]; `Fast`,
/// [`fast_fidelity_params`], the Hausdorff fields only, without projecting every
/// vertex (`None` computes no fidelity).
pub fn level_fidelity_params(
    level: Metrics,
    domain: &Aabb,
    dim: usize,
    elements: usize,
) -> FidelityParams {
    if level == Metrics::Fast {
        fast_fidelity_params(domain, dim, elements)
            .hausdorff_only(true)
            .project_vertices(false)
    } else {
        fidelity_params(domain, dim)
    }
}

/// How much of the report to compute (`certmesh mesh --metrics`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Metrics {
    /// Only what the run itself gives (sizes, time, certificate): no topology, angles
    /// or Hausdorff estimate (their fields are empty and say why).
    None,
    /// Every field of the row, skipping the measures the row does not report (the
    /// per-vertex distance estimate, the normal deviation, the mean smallest angle and
    /// the edge ratios), with a sampled Hausdorff estimate: the mesh → surface side
    /// from the area-proportional mesh samples alone (not every vertex as well), so at
    /// most `Full`'s. On a surface mesh of fewer than [`FAST_FULL_SIZE`] triangles the
    /// sample is sized to the mesh ([`fast_fidelity_params`]): a subset of `Full`'s mesh
    /// points, every k-th sample refined on the triangles of the largest distances (so
    /// that side is still at most `Full`'s), and surface points from a
    /// coarser seed grid (that side an estimate of its own); from that size up, the
    /// surface → mesh side is `Full`'s. `hausdorff_kind`,
    /// `hausdorff_mesh_samples` and `hausdorff_surface_samples` say which. Every other
    /// field of the row is `Full`'s.
    #[default]
    Fast,
    /// Every measure, as `certmesh compare` computes them.
    Full,
}

impl Metrics {
    /// Parse `none`, `fast` or `full`.
    pub fn parse(s: &str) -> Result<Metrics> {
        match s {
            "none" => Ok(Metrics::None),
            "fast" => Ok(Metrics::Fast),
            "full" => Ok(Metrics::Full),
            _ => Err(crate::error::Error::Param(format!(
                "--metrics {s}: expected none, fast or full"
            ))),
        }
    }
}

/// Why the topology and Hausdorff fields are empty under [`Metrics::None`].
pub const METRICS_NONE: &str = "not computed (--metrics none)";

/// Judge one run against f and the expected topology (every measure).
pub fn evaluate(
    surface: &str,
    f: &dyn Implicit,
    domain: &Aabb,
    expected: Option<&Topology>,
    run: &Run,
) -> Result<Row> {
    evaluate_with(surface, f, domain, expected, run, Metrics::Full)
}

/// [`evaluate`] computing the measures `level` asks for.
pub fn evaluate_with(
    surface: &str,
    f: &dyn Implicit,
    domain: &Aabb,
    expected: Option<&Topology>,
    run: &Run,
    level: Metrics,
) -> Result<Row> {
    let dim = f.dim();
    let mut row = Row::failed(surface, &run.algo, dim, String::new());
    row.error = None;
    row.seconds = run.seconds;
    row.evaluations = run.evaluations.total();
    row.certified = run.output.certificate.is_certified();
    row.certificate = run.output.certificate.clone();
    if level == Metrics::None {
        // Sizes straight from the mesh (vertices as stored, not only the used ones).
        let (v, fc) = match &run.output.mesh {
            Mesh::Curve(c) => (c.vertices.len(), c.segments.len()),
            m => {
                let surf = m.surface().expect("surface or volume");
                (surf.vertices.len(), surf.triangles.len())
            }
        };
        (row.vertices, row.faces) = (v, fc);
        if let Mesh::Volume { tets, .. } = &run.output.mesh {
            row.tetrahedra = Some(tets.tets.len());
        }
        row.found = METRICS_NONE.into();
        row.topology_reason = METRICS_NONE.into();
        row.hausdorff_note = Some(METRICS_NONE.into());
        return Ok(row);
    }
    match &run.output.mesh {
        Mesh::Curve(c) => {
            let params = level_fidelity_params(level, domain, dim, c.segments.len());
            let s = metrics::curve_stats(c, Some(f), &params)?;
            row.components = s.topology.components;
            row.closed = s.topology.open_ends == 0;
            row.manifold = s.topology.branch_points == 0;
            row.vertices = c.vertices.len();
            row.faces = c.segments.len();
            row.signature = metrics::embedding_signature(c, Some(domain)).ok();
            set_hausdorff(&mut row, s.fidelity.as_ref());
            if let Some(t) = expected {
                set_verdict(&mut row, metrics::curve_verdict(&s.topology, t));
            } else {
                row.found = components(s.topology.components);
            }
        }
        m => {
            let surf = m.surface().expect("surface or volume");
            let params = level_fidelity_params(level, domain, dim, surf.triangles.len());
            let (s, report) = if level == Metrics::Fast {
                // A mesher that measured the angles for its own statistics hands them
                // on (GradNormal, MidNormal): the same extremes, not measured twice.
                match (&run.output.mesh, &run.output.angles) {
                    (Mesh::Surface(_), Some(a)) if a.triangles == surf.triangles.len() => {
                        metrics::stats_and_topology_fast_given(surf, Some(f), &params, a)?
                    }
                    _ => metrics::stats_and_topology_fast(surf, Some(f), &params)?,
                }
            } else {
                metrics::stats_and_topology(surf, Some(f), &params)?
            };
            row.components = s.components;
            row.genus = s.genus.clone();
            row.closed = s.closed;
            row.manifold = s.manifold;
            row.vertices = s.vertices;
            row.faces = s.faces;
            row.min_angle_deg = s.min_angle_deg;
            row.max_angle_deg = s.max_angle_deg;
            set_hausdorff(&mut row, s.fidelity.as_ref());
            if let Mesh::Volume { tets, .. } = m {
                row.tetrahedra = Some(tets.tets.len());
            }
            row.mesh_chi = Some(report.euler_characteristic);
            if let Some(t) = expected {
                set_verdict(&mut row, metrics::verdict(&report, t));
            } else {
                row.found = format!(
                    "{}, genus {:?}",
                    components(report.components),
                    report.genus
                );
            }
        }
    }
    Ok(row)
}

/// The topology verdict of a row.
fn set_verdict(row: &mut Row, v: metrics::Verdict) {
    row.topology_ok = Some(v.ok);
    (row.expected, row.found, row.topology_reason) = (v.expected, v.found, v.reason);
}

/// The Hausdorff estimate of a row and, when it is not a finite number, why.
fn set_hausdorff(row: &mut Row, fd: Option<&metrics::Fidelity>) {
    row.hausdorff = fd.map(|x| x.hausdorff);
    if let Some(x) = fd {
        row.hausdorff_kind = x.hausdorff_kind;
    }
    row.hausdorff_mesh_samples = fd.map(|x| x.fidelity_mesh_samples);
    row.hausdorff_surface_samples = fd.map(|x| x.fidelity_surface_samples);
    row.hausdorff_note = fd.filter(|x| !x.hausdorff.is_finite()).map(|x| {
        let what = if x.hausdorff.is_nan() {
            "undefined"
        } else {
            "infinite"
        };
        match x.fidelity_undefined.get("hausdorff") {
            Some(r) if !r.is_empty() => format!("{what}: {r}"),
            _ => what.to_string(),
        }
    });
}

/// Box budgets of the certified χ column (gradient search, then height census).
pub const CHI_GRADIENT_BOXES: usize = 20_000;
pub const CHI_SURFACE_BOXES: usize = 100_000;

/// Run the matrix `entries × algos`. Algorithms that do not handle an entry's dimension
/// are skipped; a mesher error becomes a row with `error` set (the matrix goes on).
pub fn compare(
    entries: &[Entry],
    algos: &[String],
    opts: &MesherOptions,
    progress: &dyn Progress,
) -> Vec<Row> {
    compare_with(entries, algos, opts, progress, &mut |_, _| Ok(()))
}

/// [`compare`], handing every successful run to `on_run` (e.g. to write its mesh).
pub fn compare_with(
    entries: &[Entry],
    algos: &[String],
    opts: &MesherOptions,
    progress: &dyn Progress,
    on_run: &mut dyn FnMut(&Entry, &Run) -> Result<()>,
) -> Vec<Row> {
    let mut rows = Vec::new();
    let jobs: Vec<(&Entry, &String)> = entries
        .iter()
        .flat_map(|e| algos.iter().map(move |a| (e, a)))
        .filter(|(e, a)| {
            algorithms::list()
                .iter()
                .any(|i| i.name == a.as_str() && i.dim == e.dim)
        })
        .collect();
    progress.start("compare", jobs.len() as u64);
    let mut chis: Vec<(&str, (Option<i64>, Option<String>))> = Vec::new();
    for (e, a) in jobs {
        let f = e.function();
        let chi = match chis.iter().find(|(n, _)| *n == e.name) {
            Some((_, c)) => c.clone(),
            None => {
                let c = if e.dim == 3 {
                    crate::morse::certified_chi(
                        &f,
                        e.domain.into(),
                        CHI_GRADIENT_BOXES,
                        CHI_SURFACE_BOXES,
                    )
                } else {
                    (None, Some("curves: not computed".to_string()))
                };
                chis.push((e.name, c.clone()));
                c
            }
        };
        let row = algorithms::build_shared(a, e.dim, opts)
            .and_then(|m| mesher::run(m.as_ref(), &f, &e.domain, &mesher::NoProgress))
            .and_then(|run| {
                on_run(e, &run)?;
                evaluate(e.name, &f, &e.domain, e.topology.as_ref(), &run)
            });
        let mut row = row.unwrap_or_else(|err| Row::failed(e.name, a, e.dim, err.to_string()));
        (row.certified_chi, row.certified_chi_note) = chi;
        rows.push(row);
        progress.inc(1);
    }
    progress.finish();
    set_isotopy_agreement(&mut rows);
    rows
}

/// For every curve, compare each run's embedding signature with the reference: the
/// certified sweep's (`sweep`), else the first certified run's.
pub fn set_isotopy_agreement(rows: &mut [Row]) {
    let curves: Vec<String> = rows
        .iter()
        .filter(|r| r.dim == 2)
        .map(|r| r.surface.clone())
        .collect();
    for c in curves {
        let on = |r: &&Row| {
            r.surface == c
                && r.dim == 2
                && r.error.is_none()
                && r.certified
                && r.signature.is_some()
        };
        let reference = rows
            .iter()
            .filter(on)
            .find(|r| r.algo == "sweep")
            .or_else(|| rows.iter().find(on))
            .and_then(|r| r.signature.clone());
        for r in rows.iter_mut().filter(|r| r.surface == c && r.dim == 2) {
            r.isotopy_agrees = match (&reference, &r.signature) {
                (Some(a), Some(b)) => Some(a == b),
                _ => None,
            };
        }
    }
}

fn fmt_opt(x: Option<f64>, prec: usize) -> String {
    match x {
        None => "–".into(),
        Some(v) if v.is_nan() => "undefined".into(),
        Some(v) if v.is_infinite() => "inf".into(),
        // Fixed decimals for the usual sizes; scientific below 10^-3 (a tiny domain's
        // distances are not "0.0000") and from 10^6 up (not a hundred digits).
        Some(v) if v != 0.0 && !(1e-3..1e6).contains(&v.abs()) => format!("{v:.prec$e}"),
        Some(v) => format!("{v:.prec$}"),
    }
}

/// "certified", with the topological claim's kind: `isotopic` (PV, Snyder, ...) or
/// `homeomorphic` (the topological ball property of `cdrr`).
fn certified_kind(claims: &[crate::mesher::Claim]) -> String {
    if claims.iter().any(|c| c.is_isotopy()) {
        "certified: isotopic".into()
    } else if claims.iter().any(|c| c.is_topological()) {
        "certified: homeomorphic (topological ball property)".into()
    } else {
        "certified".into()
    }
}

/// The comparison as CSV (one row per run; the certificate as its one-line summary).
pub fn csv(rows: &[Row]) -> String {
    fn field(s: &str) -> String {
        if s.contains([',', '"', '\n']) {
            format!("\"{}\"", s.replace('"', "\"\""))
        } else {
            s.to_string()
        }
    }
    let num = |x: Option<f64>| match x {
        Some(v) if v.is_nan() => "undefined".to_string(),
        Some(v) => v.to_string(),
        None => String::new(),
    };
    let mut s = String::from(
        "surface,algo,dim,topology_ok,expected,found,components,genus,closed,manifold,vertices,faces,tetrahedra,min_angle_deg,max_angle_deg,hausdorff_est,hausdorff_note,seconds,evaluations,certified,certificate,error,mesh_chi,certified_chi\n",
    );
    for r in rows {
        let cert = match &r.certificate {
            Certificate::Certified { claims_typed, .. } => certified_kind(claims_typed),
            Certificate::Uncertified { reason, .. } => format!("uncertified: {reason}"),
        };
        let cols = [
            field(&r.surface),
            field(&r.algo),
            r.dim.to_string(),
            r.topology_ok.map(|b| b.to_string()).unwrap_or_default(),
            field(&r.expected),
            field(&r.found),
            r.components.to_string(),
            field(
                &r.genus
                    .iter()
                    .map(|g| g.to_string())
                    .collect::<Vec<_>>()
                    .join(" "),
            ),
            r.closed.to_string(),
            r.manifold.to_string(),
            r.vertices.to_string(),
            r.faces.to_string(),
            r.tetrahedra.map(|t| t.to_string()).unwrap_or_default(),
            num(r.min_angle_deg),
            num(r.max_angle_deg),
            num(r.hausdorff),
            field(r.hausdorff_note.as_deref().unwrap_or("")),
            r.seconds.to_string(),
            r.evaluations.to_string(),
            r.certified.to_string(),
            field(&cert),
            field(r.error.as_deref().unwrap_or("")),
            r.mesh_chi.map(|c| c.to_string()).unwrap_or_default(),
            r.certified_chi.map(|c| c.to_string()).unwrap_or_default(),
        ];
        s += &cols.join(",");
        s.push('\n');
    }
    s
}

/// The comparison as a markdown table.
pub fn markdown(rows: &[Row]) -> String {
    let mut s = format!(
        "| {} |\n|{}\n",
        COLUMNS.join(" | "),
        "---|".repeat(COLUMNS.len())
    );
    for r in rows {
        let c = cells(r).map(|c| c.replace('|', "/"));
        s += &format!("| {} |\n", c.join(" | "));
    }
    s
}

/// The columns of the comparison table ([`markdown`], the demo's HTML page).
pub const COLUMNS: [&str; 10] = [
    "surface",
    "algo",
    "topology",
    "found",
    "angles (deg)",
    "Hausdorff (est.)",
    "time (s)",
    "evals",
    "certificate",
    "χ mesh / certified",
];

/// One row's cells under [`COLUMNS`] (markdown emphasis on a wrong topology or χ).
pub fn cells(r: &Row) -> [String; 10] {
    if let Some(e) = &r.error {
        let mut c: [String; 10] = Default::default();
        c[0] = r.surface.clone();
        c[1] = r.algo.clone();
        c[2] = "error".into();
        c[3] = e.clone();
        return c;
    }
    let verdict = match r.topology_ok {
        Some(true) => "ok".to_string(),
        Some(false) => "**WRONG**".to_string(),
        None => "n/a".to_string(),
    };
    let angles = match (r.min_angle_deg, r.max_angle_deg) {
        (Some(a), Some(b)) => format!("{a:.1}–{b:.1}"),
        _ => "–".into(),
    };
    let cert = match &r.certificate {
        Certificate::Certified { claims_typed, .. } => certified_kind(claims_typed),
        Certificate::Uncertified {
            reason, regions, ..
        } => {
            if regions.is_empty() {
                format!("uncertified: {reason}")
            } else {
                format!("uncertified ({} regions): {reason}", regions.len())
            }
        }
    };
    let chi = |c: Option<i64>| c.map(|c| c.to_string()).unwrap_or_else(|| "–".into());
    let chis = match (r.mesh_chi, r.certified_chi) {
        (Some(m), Some(c)) if m != c => format!("**{m}** / {c}"),
        (m, c) => format!("{} / {}", chi(m), chi(c)),
    };
    [
        r.surface.clone(),
        r.algo.clone(),
        verdict,
        r.found.clone(),
        angles,
        fmt_opt(r.hausdorff, 4),
        format!("{:.3}", r.seconds),
        r.evaluations.to_string(),
        cert,
        chis,
    ]
}

/// The curves' embedding signatures and whether each run agrees with the certified
/// reference (a markdown list; empty without curves).
pub fn signatures_markdown(rows: &[Row]) -> String {
    let curves: Vec<&Row> = rows
        .iter()
        .filter(|r| r.dim == 2 && r.error.is_none())
        .collect();
    if curves.is_empty() {
        return String::new();
    }
    let mut s = String::from("\nIsotopy (embedding signatures; reference: the certified runs):\n\n| curve | algo | signature | agrees |\n|---|---|---|---|\n");
    for r in curves {
        let agrees = match r.isotopy_agrees {
            Some(true) => "yes",
            Some(false) => "**no**",
            None => "n/a (nothing certified)",
        };
        s += &format!(
            "| {} | {} | `{}` | {} |\n",
            r.surface,
            r.algo,
            r.signature.as_deref().unwrap_or("–").replace('|', "/"),
            agrees
        );
    }
    s
}

/// "1 component", "2 components".
fn components(n: usize) -> String {
    format!("{n} component{}", if n == 1 { "" } else { "s" })
}
