//! MidNormal and GradNormal (Hass & Trnkova, "Approximating isosurfaces by
//! guaranteed-quality triangular meshes", 2020).
//!
//! * [`tiling`]: the Goldberg tetrahedron τ(a, e), its labels A–D and midpoints K–Q,
//!   the paper's diagonals, and the lattice of the space-filling tiling, as plain data
//!   (the `proofs` crate reads the same tables);
//! * [`midnormal`]: Algorithm 1 with interval pruning of empty space;
//! * [`valence4`]: the valence-four removal of Algorithm 2;
//! * [`planar`]: the planar version of Sec. 3 (curves on the triangle tiling);
//! (`crate::reproduce::gradnormal` regenerates `papers/gradnormal/`.)
//!
//! Meshers: [`MidNormal`] (`"midnormal"`) and [`GradNormal`] (`"gradnormal"`), both
//! built from [`MesherOptions`] through [`GradNormalParams::from_options`]; the planar
//! [`planar::MidNormal2`] / [`planar::GradNormal2`] carry the same names with `dim() == 2`.
//!
//! Certificates are honest: GradNormal's angle bound (Theorem 1.1(3)) holds only as
//! e → 0 and its topology claim (Theorem 1.1(1)) only at a scale the paper does not
//! quantify, so both meshers report `Uncertified` with the *measured* angle range in
//! the statistics.
pub mod midnormal;
pub mod planar;
pub mod tiling;
pub mod valence4;
pub mod witness;

pub use midnormal::{extract, NormalSurface, DEFAULT_MAX_TRIANGLES};
pub use tiling::Goldberg;

use crate::error::{Error, Result};
use crate::implicit::Implicit;
use crate::kernel::geom::{dist, Aabb};
use crate::mesh::TriMesh;
use crate::mesher::options::MesherOptions;
use crate::mesher::{Certificate, Mesh, MeshOutput, Mesher, Progress};
use crate::metrics::angles::extremes_and_range_all;
use rayon::prelude::*;

/// How a quadrilateral (an elementary normal quadrilateral, or the square left by a
/// valence-four removal) is split into two triangles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DiagonalRule {
    /// The paper's diagonals: LMNQ → MN, KMPN → MN, KLPQ → LQ (Algorithm 1), and K K₂ for
    /// the valence-four square (Appendix A, the triangle K L K₂).
    #[default]
    Paper,
    /// The other diagonal of every quadrilateral.
    Alternate,
    /// The shorter diagonal after the projection (GradNormal) or of the midpoint
    /// quadrilateral (MidNormal, where ties go to the paper's).
    Shorter,
}

impl std::str::FromStr for DiagonalRule {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "paper" => Ok(DiagonalRule::Paper),
            "alternate" => Ok(DiagonalRule::Alternate),
            "shorter" => Ok(DiagonalRule::Shorter),
            _ => Err(Error::Unknown {
                kind: "diagonal rule",
                name: s.into(),
                known: "paper alternate shorter".into(),
            }),
        }
    }
}

impl DiagonalRule {
    pub fn name(&self) -> &'static str {
        match self {
            DiagonalRule::Paper => "paper",
            DiagonalRule::Alternate => "alternate",
            DiagonalRule::Shorter => "shorter",
        }
    }
}

/// Parameters of MidNormal and GradNormal (builder style; defaults documented per field).
#[derive(Clone, Debug, PartialEq)]
pub struct GradNormalParams {
    /// Edge length e of the tiling's base triangles. Default: longest domain side /
    /// `resolution`.
    pub scale: Option<f64>,
    /// Used when `scale` is unset: e = longest domain side / resolution. Default 64.
    pub resolution: usize,
    /// a/e of the Goldberg tetrahedron. Default √2/4 (the Sommerville tetrahedron; see
    /// `papers/gradnormal/GOLDBERG.md`).
    pub a_ratio: f64,
    /// Diagonals of the elementary quadrilaterals. Default `Paper`.
    pub quad_rule: DiagonalRule,
    /// Diagonal of the square left by a valence-four removal. Default `Paper`.
    pub v4_rule: DiagonalRule,
    /// Remove valence-four vertices (GradNormal step 3). Default true.
    pub remove_valence4: bool,
    /// Gradient projection steps v ← v − f∇f/|∇f|². Default 1 (the paper); more steps
    /// are Newton iterations towards the surface.
    pub newton_steps: usize,
    /// Octree leaf size in lattice steps. Default 8.
    pub leaf: usize,
    /// Refuse runs expected to produce more triangles than this (default
    /// [`midnormal::DEFAULT_MAX_TRIANGLES`]; `--set max_triangles=N`).
    pub max_triangles: u64,
    /// Prune empty blocks with interval arithmetic. Default true.
    pub prune: bool,
}

impl Default for GradNormalParams {
    fn default() -> Self {
        GradNormalParams {
            scale: None,
            resolution: 64,
            a_ratio: tiling::SOMMERVILLE_RATIO,
            quad_rule: DiagonalRule::Paper,
            v4_rule: DiagonalRule::Paper,
            remove_valence4: true,
            newton_steps: 1,
            leaf: 8,
            max_triangles: midnormal::DEFAULT_MAX_TRIANGLES,
            prune: true,
        }
    }
}

/// The `--set` keys MidNormal understands.
pub const MIDNORMAL_KEYS: &[&str] = &["a_ratio", "quad_rule", "leaf", "prune", "max_triangles"];
/// The `--set` keys GradNormal understands:
/// * `a_ratio` (f64, default √2/4): a/e of the Goldberg tetrahedron;
/// * `quad_rule` (`paper` | `alternate` | `shorter`): diagonals of the quadrilaterals;
/// * `v4_rule` (`paper` | `alternate` | `shorter`): diagonal after a valence-four removal;
/// * `remove_valence4` (bool, default true);
/// * `newton_steps` (usize, default 1): projection steps;
/// * `leaf` (usize, default 8): octree leaf size; `prune` (bool, default true).
pub const GRADNORMAL_KEYS: &[&str] = &[
    "a_ratio",
    "quad_rule",
    "v4_rule",
    "remove_valence4",
    "newton_steps",
    "leaf",
    "prune",
];

impl GradNormalParams {
    pub fn new() -> Self {
        Self::default()
    }
    pub fn with_scale(mut self, e: f64) -> Self {
        self.scale = Some(e);
        self
    }
    pub fn with_resolution(mut self, n: usize) -> Self {
        self.resolution = n;
        self
    }
    pub fn with_a_ratio(mut self, r: f64) -> Self {
        self.a_ratio = r;
        self
    }
    pub fn with_quad_rule(mut self, r: DiagonalRule) -> Self {
        self.quad_rule = r;
        self
    }
    pub fn with_v4_rule(mut self, r: DiagonalRule) -> Self {
        self.v4_rule = r;
        self
    }
    pub fn with_remove_valence4(mut self, b: bool) -> Self {
        self.remove_valence4 = b;
        self
    }
    pub fn with_newton_steps(mut self, n: usize) -> Self {
        self.newton_steps = n;
        self
    }
    pub fn with_leaf(mut self, n: usize) -> Self {
        self.leaf = n;
        self
    }
    pub fn with_prune(mut self, b: bool) -> Self {
        self.prune = b;
        self
    }
    /// Read the shared options (`scale`, `resolution`) and the `extra` keys of
    /// [`GRADNORMAL_KEYS`] (`algo` selects which keys are legal).
    pub fn from_options_for(o: &MesherOptions, algo: &str) -> Result<Self> {
        let keys = if algo == "midnormal" {
            MIDNORMAL_KEYS
        } else {
            GRADNORMAL_KEYS
        };
        o.check_keys(algo, keys)?;
        let mut p = GradNormalParams {
            scale: o.scale,
            ..Default::default()
        };
        if let Some(r) = o.resolution {
            p.resolution = r;
        }
        if let Some(v) = o.get::<f64>("a_ratio")? {
            p.a_ratio = v;
        }
        if let Some(v) = o.get::<DiagonalRule>("quad_rule")? {
            p.quad_rule = v;
        }
        if let Some(v) = o.get::<DiagonalRule>("v4_rule")? {
            p.v4_rule = v;
        }
        if let Some(v) = o.get::<bool>("remove_valence4")? {
            p.remove_valence4 = v;
        }
        if let Some(v) = o.get::<usize>("newton_steps")? {
            p.newton_steps = v;
        }
        if let Some(v) = o.get::<usize>("leaf")? {
            p.leaf = v;
        }
        if let Some(v) = o.get::<bool>("prune")? {
            p.prune = v;
        }
        if let Some(v) = o.get::<u64>("max_triangles")? {
            p.max_triangles = v;
        }
        p.validate()?;
        Ok(p)
    }
    /// [`Self::from_options_for`] with GradNormal's keys.
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Self::from_options_for(o, "gradnormal")
    }
    fn validate(&self) -> Result<()> {
        if let Some(e) = self.scale {
            if !(e.is_finite() && e > 0.0) {
                return Err(Error::Param(format!("scale e = {e} must be positive")));
            }
        }
        if self.resolution == 0 {
            return Err(Error::Param("resolution must be at least 1".into()));
        }
        if !(self.a_ratio.is_finite() && self.a_ratio > 0.0) {
            return Err(Error::Param(format!(
                "a_ratio = {} must be positive",
                self.a_ratio
            )));
        }
        if self.leaf == 0 || self.leaf > 64 {
            return Err(Error::Param(format!(
                "leaf = {} must be in 1..=64",
                self.leaf
            )));
        }
        if self.newton_steps > 100 {
            return Err(Error::Param(format!(
                "newton_steps = {} must be at most 100",
                self.newton_steps
            )));
        }
        Ok(())
    }
    /// The scale e on a domain.
    pub fn edge_length(&self, domain: &Aabb) -> f64 {
        self.scale.unwrap_or_else(|| {
            let s = domain.size();
            s[0].max(s[1]).max(s[2]) / self.resolution as f64
        })
    }
    pub fn goldberg(&self, domain: &Aabb) -> Goldberg {
        Goldberg::with_ratio(self.edge_length(domain), self.a_ratio)
    }
}

/// The MidNormal mesher (Algorithm 1): normal surface with midpoint vertices.
#[derive(Clone, Debug, Default)]
pub struct MidNormal {
    pub params: GradNormalParams,
}

impl MidNormal {
    pub fn new(params: GradNormalParams) -> Self {
        MidNormal { params }
    }
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Ok(MidNormal {
            params: GradNormalParams::from_options_for(o, "midnormal")?,
        })
    }
    /// The normal surface with its statistics (no certificate).
    pub fn surface(
        &self,
        f: &dyn Implicit,
        domain: &Aabb,
        progress: &dyn Progress,
    ) -> Result<NormalSurface> {
        crate::mesher::check_input(f, domain, 3, "midnormal")?;
        let g = self.params.goldberg(domain);
        // At the midpoints every quadrilateral of the Sommerville tiling is a square, so
        // `Shorter` ties; it falls back to the paper's diagonals.
        let rule = match self.params.quad_rule {
            DiagonalRule::Shorter => DiagonalRule::Paper,
            r => r,
        };
        extract(
            f,
            domain,
            &g,
            rule,
            false,
            self.params.leaf,
            self.params.prune,
            self.params.max_triangles,
            progress,
        )
    }
}

/// What a MidNormal or GradNormal run did (the part both share), serialised field by
/// field into the report's `stats` map.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct NormalSurfaceStats {
    /// The Goldberg tiling's scale e and its parameter a.
    pub e: f64,
    pub a: f64,
    /// a / e as given by `--a`.
    pub a_ratio: f64,
    /// The diagonal rule for quadrilaterals.
    pub quad_rule: &'static str,
    pub tets_total: u64,
    pub tets_visited: u64,
    pub crossing_tets: u64,
    /// Leaf blocks of the interval pruning.
    pub leaf_blocks: u64,
    pub interval_evals: u64,
    pub vertex_evals: u64,
    /// The measured triangle angles of the output.
    pub min_angle_deg: f64,
    pub max_angle_deg: f64,
    /// What the paper guarantees about the angles, and when.
    pub angle_guarantee: &'static str,
    /// Always false: Theorem 1.1(1) needs an unquantified small e.
    pub topology_certified: bool,
    pub topology_note: &'static str,
}

impl NormalSurfaceStats {
    fn new(
        p: &GradNormalParams,
        g: &Goldberg,
        x: &midnormal::ExtractStats,
        (lo, hi): (f64, f64),
        guarantee: &'static str,
    ) -> Self {
        NormalSurfaceStats {
            e: g.e,
            a: g.a,
            a_ratio: p.a_ratio,
            quad_rule: p.quad_rule.name(),
            tets_total: x.tets_total,
            tets_visited: x.tets_visited,
            crossing_tets: x.crossing_tets,
            leaf_blocks: x.leaves,
            interval_evals: x.interval_evals,
            vertex_evals: x.point_evals,
            min_angle_deg: lo,
            max_angle_deg: hi,
            angle_guarantee: guarantee,
            topology_certified: false,
            topology_note: "Theorem 1.1(1) gives the topology of f = 0 only for e small enough, \
                            which is not quantified",
        }
    }
}

/// GradNormal's statistics: the shared ones and what Algorithm 2 adds.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GradNormalStats {
    #[serde(flatten)]
    pub surface: NormalSurfaceStats,
    /// The diagonal rule after removing valence-4 vertices.
    pub v4_rule: &'static str,
    pub newton_steps: usize,
    /// Valence-4 vertices: found, removed, removed by the fallback, skipped.
    pub valence4_found: usize,
    pub valence4_removed: usize,
    pub valence4_fallback: usize,
    pub valence4_skipped: usize,
    /// Vertices whose Newton projection onto f = 0 failed.
    pub projection_failures: usize,
    /// The largest projection displacement, in units of e.
    pub max_displacement_over_e: f64,
    /// The largest |f| at a projected vertex.
    pub max_residual: f64,
}

/// Nothing is proven: the angle bound is asymptotic and the topology claim holds only
/// below an unquantified scale (recorded in the statistics, never as a claim).
fn uncertified() -> Certificate {
    Certificate::none("angle bound is asymptotic (e → 0): measured range reported")
}

impl Mesher for MidNormal {
    fn name(&self) -> &'static str {
        "midnormal"
    }
    fn dim(&self) -> usize {
        3
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        let ns = self.surface(f, domain, progress)?;
        let g = ns.goldberg.unwrap_or_else(|| self.params.goldberg(domain));
        let mesh = TriMesh::new(ns.vertices, ns.triangles);
        let (angles, range) = extremes_and_range_all(&mesh);
        let stats = NormalSurfaceStats::new(
            &self.params,
            &g,
            &ns.stats,
            range,
            "Lemma 4.1: [45°, 90°] for the Sommerville tiling (exact at the midpoints)",
        );
        Ok(MeshOutput {
            mesh: Mesh::Surface(mesh),
            certificate: uncertified(),
            stats: crate::mesher::stats_map(&stats),
            // Measured once above, for Table 1's range and for the report.
            angles,
        })
    }
}

/// The GradNormal mesher (Algorithm 2).
#[derive(Clone, Debug, Default)]
pub struct GradNormal {
    pub params: GradNormalParams,
}

/// One projection: `steps` iterations of v ← v − f(v)∇f/|∇f|² (Algorithm 2, line 6),
/// the oracle's [`project_steps`](crate::implicit::ops::project_steps).
pub use crate::implicit::ops::project_steps as project;

/// What GradNormal did, besides the mesh.
#[derive(Clone, Debug, Default)]
pub struct GradNormalReport {
    pub goldberg: Option<Goldberg>,
    pub extract: midnormal::ExtractStats,
    pub valence4: valence4::Valence4Stats,
    /// Vertices left in place because ∇f vanished or was not finite.
    pub projection_failures: usize,
    /// Largest projection displacement, in units of e.
    pub max_displacement: f64,
    /// Largest |f| at the final vertices.
    pub max_residual: f64,
}

impl GradNormal {
    pub fn new(params: GradNormalParams) -> Self {
        GradNormal { params }
    }
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Ok(GradNormal {
            params: GradNormalParams::from_options(o)?,
        })
    }
    /// The pipeline of Algorithm 2 up to (not including) vertex compaction, keeping what
    /// the reproduction and the witness planes inspect: the lattice keys of the vertices,
    /// the elementary (MidNormal) triangles and the triangles after valence-four removal.
    pub fn stages(
        &self,
        f: &dyn Implicit,
        domain: &Aabb,
        progress: &dyn Progress,
    ) -> Result<Stages> {
        crate::mesher::check_input(f, domain, 3, "gradnormal")?;
        let p = &self.params;
        let g = p.goldberg(domain);
        let keep_quads = p.quad_rule == DiagonalRule::Shorter;
        let ns = extract(
            f,
            domain,
            &g,
            p.quad_rule,
            keep_quads,
            p.leaf,
            p.prune,
            p.max_triangles,
            progress,
        )?;
        // Step 2 (line 6): gradient projection. Positions do not depend on connectivity,
        // so projecting first lets the `Shorter` rules see projected positions.
        // In batches of 1024 vertices (batch gradients; the same points, bit for bit,
        // as `project` vertex by vertex).
        let proj: Vec<([f64; 3], bool)> = ns
            .vertices
            .par_chunks(1024)
            .flat_map_iter(|c| crate::implicit::ops::project_steps_batch(f, c, p.newton_steps))
            .collect();
        let projection_failures = proj.iter().filter(|x| !x.1).count();
        let max_displacement = ns
            .vertices
            .par_iter()
            .zip(proj.par_iter())
            .map(|(a, b)| dist(*a, b.0) / g.e)
            .reduce(|| 0.0, f64::max);
        let pos: Vec<[f64; 3]> = proj.into_iter().map(|x| x.0).collect();
        let mut elementary = ns.triangles.clone();
        for q in &ns.quads {
            let d0 = dist(pos[q[0] as usize], pos[q[2] as usize]);
            let d1 = dist(pos[q[1] as usize], pos[q[3] as usize]);
            let at = if d0 <= d1 { 0 } else { 1 };
            elementary.extend(midnormal::split_quad(*q, at));
        }
        // Step 3 (line 5): valence-four removal.
        let mut alive = vec![true; pos.len()];
        let (triangles, valence4) = if p.remove_valence4 {
            valence4::remove_valence4(&elementary, &pos, Some(&ns.keys), p.v4_rule, &mut alive)
        } else {
            (elementary.clone(), Default::default())
        };
        Ok(Stages {
            goldberg: g,
            surface: ns,
            positions: pos,
            elementary,
            triangles,
            valence4,
            projection_failures,
            max_displacement,
        })
    }

    /// The mesh and the report (no certificate).
    pub fn run(
        &self,
        f: &dyn Implicit,
        domain: &Aabb,
        progress: &dyn Progress,
    ) -> Result<(TriMesh, GradNormalReport)> {
        let st = self.stages(f, domain, progress)?;
        let mut report = GradNormalReport {
            goldberg: Some(st.goldberg),
            extract: st.surface.stats.clone(),
            valence4: st.valence4,
            projection_failures: st.projection_failures,
            max_displacement: st.max_displacement,
            ..Default::default()
        };
        let mut mesh = TriMesh::new(st.positions, st.triangles);
        mesh.compact();
        report.max_residual = mesh
            .vertices
            .par_iter()
            .map(|&v| f.eval(v).abs())
            .reduce(|| 0.0, f64::max);
        Ok((mesh, report))
    }
}

/// What [`GradNormal::stages`] returns: the uncompacted pipeline state.
pub struct Stages {
    pub goldberg: Goldberg,
    /// The MidNormal surface on the lattice (vertex keys, unprojected positions).
    pub surface: NormalSurface,
    /// Vertex positions after the projection step (indexed like `surface.vertices`).
    pub positions: Vec<[f64; 3]>,
    /// The elementary normal triangles, quadrilaterals split.
    pub elementary: Vec<[u32; 3]>,
    /// The output triangles (after valence-four removal when enabled).
    pub triangles: Vec<[u32; 3]>,
    pub valence4: valence4::Valence4Stats,
    pub projection_failures: usize,
    pub max_displacement: f64,
}

impl Mesher for GradNormal {
    fn name(&self) -> &'static str {
        "gradnormal"
    }
    fn dim(&self) -> usize {
        3
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        let (mesh, r) = self.run(f, domain, progress)?;
        let g = r.goldberg.unwrap_or_else(|| self.params.goldberg(domain));
        let (angles, range) = extremes_and_range_all(&mesh);
        let stats = GradNormalStats {
            surface: NormalSurfaceStats::new(
                &self.params,
                &g,
                &r.extract,
                range,
                "Theorem 1.1(3): [35.2°, 101.5°] only as e → 0; not certified at this e",
            ),
            v4_rule: self.params.v4_rule.name(),
            newton_steps: self.params.newton_steps,
            valence4_found: r.valence4.found,
            valence4_removed: r.valence4.removed,
            valence4_fallback: r.valence4.fallback,
            valence4_skipped: r.valence4.skipped,
            projection_failures: r.projection_failures,
            max_displacement_over_e: r.max_displacement,
            max_residual: r.max_residual,
        };
        Ok(MeshOutput {
            mesh: Mesh::Surface(mesh),
            certificate: uncertified(),
            stats: crate::mesher::stats_map(&stats),
            // Measured once above, for Table 1's range and for the report.
            angles,
        })
    }
}
