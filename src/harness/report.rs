//! The report of one mesher run (`certmesh mesh`, `certmesh curve`), assembled in one
//! place: the comparison row ([`compare::evaluate`]: topology verdict, angles,
//! Hausdorff estimate, time, certificate) plus what a single run adds (the mesher's
//! statistics, evaluation counts, the domain and where it came from, whether a budget
//! stopped the run). The command line serialises it (`--json`) or prints
//! [`MeshReport::text`]; it adds nothing of its own.
//!
//! The JSON fields are those of [`compare::Row`] (flattened) and the ones below; they
//! are part of the interface (tests/cli.rs reads them): add fields, never rename.
use crate::catalog::Topology;
use crate::error::Result;
pub use crate::harness::compare::Metrics;
use crate::harness::compare::{self, Row};
use crate::implicit::{EvalCounts, Implicit};
use crate::kernel::geom::Aabb;
use crate::mesher::{Certificate, Run};
use crate::metrics::{Stats, Verdict};
use serde::Serialize;

/// Where the domain of a run came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DomainSource {
    /// Given by `--domain` (JSON: "--domain").
    #[serde(rename = "--domain")]
    Given,
    /// The catalog entry's box.
    Catalog,
    /// The default box of a formula, [-2, 2]³ or [-2, 2]².
    Default,
    /// The unit cube a `--mesh-input` mesh is normalised into.
    #[serde(rename = "unit cube")]
    UnitCube,
}

impl DomainSource {
    /// The name used in the JSON report.
    pub fn as_str(self) -> &'static str {
        match self {
            DomainSource::Given => "--domain",
            DomainSource::Catalog => "catalog",
            DomainSource::Default => "default",
            DomainSource::UnitCube => "unit cube",
        }
    }
}

/// The report of one run.
#[derive(Clone, Debug, Serialize)]
pub struct MeshReport {
    #[serde(flatten)]
    pub row: Row,
    /// Number of uncertified regions (0 when certified).
    pub uncertified_boxes: usize,
    /// The certificate's one-line reason when uncertified.
    pub reason: Option<String>,
    /// The mesher's own statistics (boxes per depth, criteria, ...).
    pub stats: serde_json::Map<String, serde_json::Value>,
    /// Evaluations of f by kind (point, interval, gradient, ...).
    pub evaluation_counts: EvalCounts,
    pub domain: Aabb,
    pub domain_source: DomainSource,
    /// `false` when a budget stopped the refinement (present only for meshers that
    /// refine).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refinement_complete: Option<bool>,
    /// Why the run stopped early, if it did.
    pub stopped: Option<String>,
    /// Remarks about the run (an option that had no effect, ...).
    pub notes: Vec<String>,
    /// The mesh file written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub output: Option<String>,
    /// Wall time of the report's measures (topology, angles, Hausdorff estimate at the
    /// `--metrics` level), in seconds, beside the mesher's `seconds`.
    pub metrics_seconds: f64,
}

/// Why a run stopped before its refinement was complete (a budget), if it did: the
/// mesher's own `stop_reason` when its statistics carry one, else the budget named by
/// its regions.
pub fn stop_reason(run: &Run) -> Option<String> {
    let complete = run
        .output
        .stats
        .get("refinement_complete")
        .and_then(|v| v.as_bool());
    if complete != Some(false) {
        return None;
    }
    // The refinement meshers (bo, cdrr) say which guard stopped them.
    if let Some(why) = run
        .output
        .stats
        .get("stop_reason")
        .and_then(|v| v.as_str())
        .filter(|s| !s.is_empty())
    {
        return Some(why.to_string());
    }
    let budget = [
        crate::subdivision::BOX_BUDGET_REASON,
        crate::subdivision::TIME_LIMIT_REASON,
        crate::subdivision::MEMORY_LIMIT_REASON,
    ];
    let from_regions = match &run.output.certificate {
        Certificate::Uncertified { regions, .. } => budget
            .iter()
            .find(|b| regions.iter().any(|r| r.reason == **b))
            .map(|b| b.to_string()),
        _ => None,
    };
    Some(from_regions.unwrap_or_else(|| "a work budget was spent".into()))
}

/// Judge a run (the comparison row) and add what a single run reports.
pub fn mesh_report(
    surface: &str,
    f: &dyn Implicit,
    domain: &Aabb,
    domain_source: DomainSource,
    expected: Option<&Topology>,
    run: &Run,
    metrics: compare::Metrics,
) -> Result<MeshReport> {
    let clock = std::time::Instant::now();
    let row = compare::evaluate_with(surface, f, domain, expected, run, metrics)?;
    let metrics_seconds = clock.elapsed().as_secs_f64();
    let c = &run.output.certificate;
    Ok(MeshReport {
        row,
        uncertified_boxes: match c {
            Certificate::Uncertified { regions, .. } => regions.len(),
            _ => 0,
        },
        reason: c.reason().map(str::to_string),
        stats: run.output.stats.clone(),
        evaluation_counts: run.evaluations,
        domain: *domain,
        domain_source,
        refinement_complete: run
            .output
            .stats
            .get("refinement_complete")
            .and_then(|v| v.as_bool()),
        stopped: stop_reason(run),
        notes: Vec::new(),
        output: None,
        metrics_seconds,
    })
}

/// The domain as the reports print it: `[x0, x1] × [y0, y1] (× [z0, z1])`, each bound
/// by [`short_num`] (1e-100, not a hundred zeros).
pub fn domain_text(domain: &Aabb, dim: usize) -> String {
    (0..dim)
        .map(|k| {
            format!(
                "[{}, {}]",
                short_num(domain.min[k]),
                short_num(domain.max[k])
            )
        })
        .collect::<Vec<_>>()
        .join(" × ")
}

impl MeshReport {
    /// The readable report: the comparison row as a one-line table, the domain, why
    /// the run stopped, up to `max_regions` uncertified regions, the proven claims, the
    /// notes.
    pub fn text(&self, max_regions: usize) -> Vec<String> {
        let mut out = vec![compare::markdown(std::slice::from_ref(&self.row))
            .trim_end()
            .to_string()];
        let dom = domain_text(&self.domain, self.row.dim);
        out.push(format!(
            "domain: {dom}{}",
            match self.domain_source {
                DomainSource::Default => " (the default domain of a formula; set --domain)",
                DomainSource::Catalog => " (the catalog's)",
                DomainSource::UnitCube => " (the unit cube of --mesh-input)",
                DomainSource::Given => "",
            }
        ));
        if let Some(why) = &self.stopped {
            // A run can stop on a budget after its check proved the output as it is
            // (cdrr's topological ball check before the vertex budget): then only the
            // refinement is partial, not the certificate.
            let what = if self.row.certificate.is_certified() {
                "the refinement's criteria are not all met, but the certificate above was \
                 proven for the output as it is"
            } else {
                "the output is partial and nothing is certified"
            };
            out.push(format!(
                "stopped before the refinement was complete: {why} (refinement_complete: false); \
                 {what}"
            ));
        }
        if let Some(n) = &self.row.hausdorff_note {
            out.push(format!("Hausdorff (est.): {n}"));
        }
        if let Certificate::Uncertified { regions, .. } = &self.row.certificate {
            for r in regions.iter().take(max_regions) {
                out.push(format!(
                    "uncertified region {:?}..{:?}: {}",
                    r.region.min, r.region.max, r.reason
                ));
            }
            if regions.len() > max_regions {
                out.push(format!(
                    "... and {} more uncertified regions (see --json)",
                    regions.len() - max_regions
                ));
            }
        }
        for c in self.row.certificate.claims() {
            out.push(format!("proven: {c}"));
        }
        for n in &self.notes {
            out.push(format!("note: {n}"));
        }
        if let Some(o) = &self.output {
            out.push(format!("wrote {o}"));
        }
        out
    }
}

/// What `certmesh stats MESH` reports for a triangle mesh: the statistics and, when the
/// surface is a catalog entry with a known topology, the verdict against it.
#[derive(Clone, Debug, Serialize)]
pub struct StatsReport {
    #[serde(flatten)]
    pub stats: Stats,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub topology_verdict: Option<Verdict>,
    /// What `hausdorff_mesh_to_surface` is, when the fidelity was measured
    /// ([`crate::metrics::fidelity::MESH_TO_SURFACE_KIND`]: per sample an upper bound).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hausdorff_mesh_to_surface_kind: Option<&'static str>,
}

impl StatsReport {
    pub fn new(stats: Stats, topology_verdict: Option<Verdict>) -> Self {
        let hausdorff_mesh_to_surface_kind = stats
            .fidelity
            .as_ref()
            .map(|_| crate::metrics::fidelity::MESH_TO_SURFACE_KIND);
        StatsReport {
            stats,
            topology_verdict,
            hausdorff_mesh_to_surface_kind,
        }
    }
}

/// A number given by the user or exact in the run (a domain bound, a parameter) for a
/// readable text: the shortest digits that read back to `x` (Rust's float printing),
/// plain for 1e-4 <= |x| < 1e16 and for 0, scientific otherwise (1e-100, not 100
/// zeros and a 1). JSON keeps the numbers themselves.
pub fn short_num(x: f64) -> String {
    let a = x.abs();
    if !x.is_finite() || a == 0.0 || (1e-4..1e16).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A number for a readable report: scientific with `prec` digits, "undefined" for NaN.
pub fn num(x: f64, prec: usize) -> String {
    if x.is_nan() {
        "undefined".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{x:.prec$e}")
    }
}

impl StatsReport {
    /// The readable report of the mesh file `name`.
    pub fn text(&self, name: &str) -> Vec<String> {
        let s = &self.stats;
        let mut out = Vec::new();
        let plural =
            |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
        let genus = if s.genus.is_empty() {
            "genus: n/a (no closed orientable component)".to_string()
        } else {
            format!("genus per closed component: {:?}", s.genus)
        };
        out.push(format!(
            "{name}: {} vertices ({} used, {} isolated), {} faces, {} edges, χ = {}, {}, closed: {}, manifold: {}, oriented: {}, {}, {}",
            s.vertices + s.isolated_vertices,
            s.vertices,
            s.isolated_vertices,
            s.faces,
            s.edges,
            s.euler_characteristic,
            plural(s.components, "component", "components"),
            s.closed,
            s.manifold,
            s.consistently_oriented,
            plural(s.boundary_loops, "boundary loop", "boundary loops"),
            genus
        ));
        if let (Some(x), Some(y)) = (s.min_angle_deg, s.max_angle_deg) {
            out.push(format!(
                "angles: [{x:.3}°, {y:.3}°], {} degenerate triangles",
                s.degenerate_triangles
            ));
        }
        if s.non_manifold_edges + s.non_manifold_vertices + s.degenerate_faces + s.duplicate_faces
            > 0
        {
            out.push(format!(
                "defects: {} non-manifold edges, {} non-manifold vertices, {} degenerate faces, {} duplicate faces",
                s.non_manifold_edges, s.non_manifold_vertices, s.degenerate_faces, s.duplicate_faces
            ));
        }
        if let Some(fd) = &s.fidelity {
            out.push(format!(
                "fidelity: Hausdorff (est.) ≈ {} (mesh→surface {} (per-sample upper bounds), surface→mesh {}), max |f|/|∇f| = {}, normal deviation max {}",
                num(fd.hausdorff, 3),
                num(fd.hausdorff_mesh_to_surface, 3),
                num(fd.hausdorff_surface_to_mesh, 3),
                num(fd.max_distance_estimate, 3),
                if fd.normal_dev_max_deg.is_finite() {
                    format!("{:.2}°", fd.normal_dev_max_deg)
                } else {
                    num(fd.normal_dev_max_deg, 2)
                }
            ));
            out.push(format!(
                "  mesh→surface: {}",
                crate::metrics::fidelity::MESH_TO_SURFACE_KIND
            ));
            // The reasons of the measured fields (the means and the two-sided maximum
            // repeat them; --json has every field).
            for (field, why) in &fd.fidelity_undefined {
                if field != "hausdorff"
                    && !field.starts_with("mean_")
                    && !field.ends_with("mean_deg")
                {
                    out.push(format!("  {field}: {why}"));
                }
            }
        }
        if let Some(vd) = &self.topology_verdict {
            out.push(format!(
                "topology: {} (expected {}, found {}) {}",
                if vd.ok { "ok" } else { "WRONG" },
                vd.expected,
                vd.found,
                vd.reason
            ));
        }
        out
    }
}
