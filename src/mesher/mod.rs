//! The one small interface every mesher implements, and the honest report it returns.
//!
//! A mesher takes the oracle ([`Implicit`]), a domain box and its own parameters (the
//! fields of the struct implementing [`Mesher`], built like spade's
//! `RefinementParameters`), and returns a [`MeshOutput`] with a [`Certificate`] saying
//! exactly what was proven, or where and why nothing was.
use crate::error::Result;
use crate::implicit::{EvalCounts, Implicit};
use crate::kernel::geom::Aabb;
use crate::mesh::{Curve2, TetMesh, TriMesh};
use serde::{Deserialize, Serialize};

pub mod claims;
pub mod options;
pub mod registry;

pub use claims::{Cause, Claim, HomeomorphismBy};

/// What a mesher produced.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum Mesh {
    /// A surface triangulation of f = 0.
    Surface(TriMesh),
    /// A tetrahedral mesh of f <= 0... (see the mesher for its sign convention), with
    /// its boundary surface.
    Volume { tets: TetMesh, boundary: TriMesh },
    /// A polyline approximation of the curve f = 0.
    Curve(Curve2),
}

impl Mesh {
    /// The surface to compare against f = 0 (the boundary for a volume mesh).
    pub fn surface(&self) -> Option<&TriMesh> {
        match self {
            Mesh::Surface(m) => Some(m),
            Mesh::Volume { boundary, .. } => Some(boundary),
            Mesh::Curve(_) => None,
        }
    }
}

/// A place where nothing could be proven, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Uncertified {
    /// The region (a box of the subdivision, or a small box around a point).
    pub region: Aabb,
    /// Why: "depth limit hit", "grazing intersection", "possible singular point", ...
    pub reason: String,
    /// The reason by kind.
    #[serde(default)]
    pub cause: Cause,
}

impl Uncertified {
    pub fn new(region: Aabb, reason: impl Into<String>) -> Self {
        let reason = reason.into();
        Uncertified {
            region,
            cause: Cause::of(&reason),
            reason,
        }
    }
}

/// What was proven about the output.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "lowercase")]
pub enum Certificate {
    /// Every listed claim was established by interval or exact arithmetic.
    Certified {
        claims: Vec<String>,
        /// The claims, typed (the same statements as `claims`).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        claims_typed: Vec<Claim>,
    },
    /// Nothing (or only `claims`) was proven; `regions` say where the proof failed.
    /// `reason` is a one-line summary.
    Uncertified {
        reason: String,
        claims: Vec<String>,
        regions: Vec<Uncertified>,
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        claims_typed: Vec<Claim>,
    },
}

impl Certificate {
    /// Everything proven: the typed claims (their texts become `claims`).
    pub fn certified(claims: Vec<Claim>) -> Self {
        Certificate::Certified {
            claims: claims.iter().map(|c| c.to_string()).collect(),
            claims_typed: claims,
        }
    }
    /// Not everything proven: what was (`claims`) and where and why not.
    pub fn uncertified(
        reason: impl Into<String>,
        claims: Vec<Claim>,
        regions: Vec<Uncertified>,
    ) -> Self {
        Certificate::Uncertified {
            reason: reason.into(),
            claims: claims.iter().map(|c| c.to_string()).collect(),
            claims_typed: claims,
            regions,
        }
    }
    /// The typed claims.
    pub fn claims_typed(&self) -> &[Claim] {
        match self {
            Certificate::Certified { claims_typed, .. }
            | Certificate::Uncertified { claims_typed, .. } => claims_typed,
        }
    }
    /// Is the output proven to have the topology of f = 0 (an isotopy or a
    /// homeomorphism claim)?
    pub fn proves_topology(&self) -> bool {
        self.is_certified() && self.claims_typed().iter().any(Claim::is_topological)
    }
    pub fn is_certified(&self) -> bool {
        matches!(self, Certificate::Certified { .. })
    }
    /// A baseline that proves nothing.
    pub fn none(reason: impl Into<String>) -> Self {
        Certificate::uncertified(reason, Vec::new(), Vec::new())
    }
    pub fn claims(&self) -> &[String] {
        match self {
            Certificate::Certified { claims, .. } | Certificate::Uncertified { claims, .. } => {
                claims
            }
        }
    }
    pub fn reason(&self) -> Option<&str> {
        match self {
            Certificate::Certified { .. } => None,
            Certificate::Uncertified { reason, .. } => Some(reason),
        }
    }
}

/// A mesher's result: the mesh, the certificate, and algorithm-specific statistics
/// (boxes per depth, criteria used, ...) as JSON for `--json` reports.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MeshOutput {
    pub mesh: Mesh,
    pub certificate: Certificate,
    pub stats: serde_json::Map<String, serde_json::Value>,
    /// The surface's triangle angles as `--metrics fast` measures them
    /// ([`crate::metrics::angles::triangle_extremes`]), when the mesher measured them
    /// for its own statistics (GradNormal, MidNormal); the report then takes them
    /// instead of measuring the same triangles again. They describe `mesh` as
    /// returned: whoever changes the mesh afterwards sets this to `None`. Not
    /// serialised.
    #[serde(skip)]
    pub angles: Option<crate::metrics::angles::TriangleAngles>,
}

/// A mesher's typed statistics (a `Serialize` struct: `SubdivisionStats`,
/// `MarchingStats`, `StuffingStats`, `GradNormalStats`) as the report's `stats` map,
/// one entry per field. A struct that does not serialise to a JSON object is a bug.
pub fn stats_map<T: Serialize>(s: &T) -> serde_json::Map<String, serde_json::Value> {
    match serde_json::to_value(s) {
        Ok(serde_json::Value::Object(m)) => m,
        other => panic!("mesher statistics must serialise to a JSON object, got {other:?}"),
    }
}

/// Progress reporting from long runs (the CLI shows an indicatif bar; the library
/// default does nothing).
pub trait Progress: Sync {
    /// Begin a phase of `total` steps (0 if unknown).
    fn start(&self, _phase: &str, _total: u64) {}
    fn inc(&self, _n: u64) {}
    fn finish(&self) {}
}

/// A [`Progress`] that ignores everything.
pub struct NoProgress;
impl Progress for NoProgress {}

/// The interface of every mesher.
pub trait Mesher: Send + Sync {
    /// The name used on the command line (`--algo NAME`).
    fn name(&self) -> &'static str;
    /// 2 for curve meshers, 3 for surface and volume meshers.
    fn dim(&self) -> usize;
    /// Mesh f = 0 inside `domain`.
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput>;
}

/// A run as the harness reports it: the output plus timing and evaluation counts
/// measured outside the mesher.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Run {
    pub algo: String,
    pub output: MeshOutput,
    pub seconds: f64,
    pub evaluations: EvalCounts,
}

/// The input checks every mesher makes, written once: the function's dimension against
/// the mesher's, and a domain box with finite corners and positive extent along each of
/// the `dim` axes. [`run`] calls it before the mesher; every mesher's `mesh` calls it
/// too, for callers that use the library directly.
pub fn check_input(f: &dyn Implicit, domain: &Aabb, dim: usize, algo: &str) -> Result<()> {
    let what = |d: usize| {
        if d == 2 {
            "curves f(x, y)"
        } else {
            "surfaces f(x, y, z)"
        }
    };
    if f.dim() != dim {
        return Err(crate::error::Error::Param(format!(
            "'{algo}' meshes {}, but the function is {}D (a {})",
            what(dim),
            f.dim(),
            if f.dim() == 2 { "curve" } else { "surface" }
        )));
    }
    let d = Aabb::new(domain.min, domain.max)?;
    for k in 0..dim {
        if !(d.max[k] > d.min[k]) {
            return Err(crate::error::Error::Domain(format!(
                "axis {} range [{}, {}] is empty",
                ["x", "y", "z"][k],
                d.min[k],
                d.max[k]
            )));
        }
    }
    Ok(())
}

/// Run a mesher with timing and counted evaluations.
pub fn run(
    m: &dyn Mesher,
    f: &dyn Implicit,
    domain: &Aabb,
    progress: &dyn Progress,
) -> Result<Run> {
    check_input(f, domain, m.dim(), m.name())?;
    let counted = crate::implicit::Counted::new(f);
    let t0 = std::time::Instant::now();
    let output = m.mesh(&counted, domain, progress)?;
    let seconds = t0.elapsed().as_secs_f64();
    let mut output = output;
    // No mesher may claim more than it computed: a non-rigorous oracle certifies
    // nothing, and an uncertified run keeps no partial claim either.
    if !f.is_rigorous()
        && (output.certificate.is_certified() || !output.certificate.claims().is_empty())
    {
        output.certificate = Certificate::uncertified(
            "the function has no rigorous interval extension",
            Vec::new(),
            Vec::new(),
        );
    }
    Ok(Run {
        algo: m.name().to_string(),
        output,
        seconds,
        evaluations: counted.counts(),
    })
}
