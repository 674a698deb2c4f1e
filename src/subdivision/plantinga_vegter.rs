//! The Plantinga–Vegter mesher (chapter §1.2.4, Theorems 1–2, Figs 1.9–1.10), for curves
//! ([`PlantingaVegter2`]) and surfaces ([`PlantingaVegter`]).
//!
//! 1. Subdivide the domain until every box satisfies, by interval arithmetic,
//!    0 ∉ □f or the Small Normal Variation condition ⟨□∇f, □∇f⟩ > 0 (eq 1.2).
//! 2. Balance: neighbours (sharing a face, edge or corner) differ by at most one level;
//!    boxes with 0 ∉ □f are never split.
//! 3. A vertex on every elementary edge whose end signs differ (sign⁺ convention: f == 0
//!    counts as positive, see [`crate::subdivision`]); a larger box's boundary includes
//!    the corners of its smaller neighbours, as in the Plantinga–Vegter paper.
//! 4. Connect: in 2D by the local rule of Fig 1.9d (never join the two crossings of a
//!    split side; the ambiguous alternating pattern of Fig 1.9a cannot occur under SNV);
//!    in 3D each face square with four or more crossings is resolved by the sign of f at
//!    its centre (the chapter's "consulting the value of f in the middle of the square"),
//!    which both boxes sharing the square compute identically; the boundary cycles of
//!    each box are fanned into triangles. Normals point toward f > 0.
//!
//! The run is certified ("isotopic to f = 0 inside the domain") only if every leaf met a
//! criterion and every grid-point sign was decided by interval arithmetic.
use crate::error::{Error, Result};
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;
use crate::mesher::options::{Crossing, MesherOptions};
use crate::mesher::{Mesh, MeshOutput, Mesher, Progress};
use crate::subdivision::certificate;
use crate::subdivision::criteria::{boundary_failure, check_budget, check_input, UNDEFINED_BOX};
use crate::subdivision::{
    assemble, cos_lower_bound, cut_arcs, excludes_zero, mean_value, snv_dot, subdivide, tree_stats,
    AngleBound, Budget, Decision, Grid, Pairing, SignChange, TileCrossing, Tree, Verdict,
    DEFAULT_MAX_BOXES, MAX_LEVEL,
};

/// The theorem a certified run invokes.
pub const PV_THEOREM: &str = "Plantinga–Vegter";
/// The claim of a certified run.
pub const PV_CLAIM: &str = "isotopic to f = 0 inside the domain (Plantinga–Vegter)";

/// Parameters of both Plantinga–Vegter meshers.
#[derive(Clone, Debug)]
pub struct PvParams {
    /// Boxes are split at least to this level (default 2) before a criterion may stop
    /// them (empty boxes stop earlier). Only refines the output.
    pub min_depth: u32,
    /// Depth limit (default 12 for surfaces, 16 for curves); a box still undecided there
    /// is reported uncertified.
    pub max_depth: u32,
    /// How crossings are located (default bisection); topology never depends on it.
    pub crossing: Crossing,
    /// Bisection tolerance relative to the edge length (default 1e-9).
    pub tolerance: f64,
    /// Largest angle between two gradients allowed in an accepted box, in degrees
    /// (default 90: Small Normal Variation, eq 1.2). Smaller values refine further
    /// (Exercise 9); `--set max_angle=45`.
    pub max_angle: f64,
    /// The angle bound used when `max_angle < 90` (default sharp); `--set angle_bound=crude|sharp`.
    pub angle_bound: AngleBound,
    /// Box tests allowed (default [`DEFAULT_MAX_BOXES`]; `--max-boxes`). A run that
    /// spends them stops, reports `refinement_complete: false` and certifies nothing.
    pub max_boxes: u64,
    /// Wall-clock limit of the subdivision in seconds (default none; `--time-limit`).
    pub time_limit: Option<f64>,
}

impl PvParams {
    pub fn new(dim: usize) -> Self {
        PvParams {
            min_depth: 2,
            max_depth: if dim == 2 { 16 } else { 12 },
            crossing: Crossing::Bisection,
            tolerance: 1e-9,
            max_angle: 90.0,
            angle_bound: AngleBound::Sharp,
            max_boxes: DEFAULT_MAX_BOXES,
            time_limit: None,
        }
    }
    pub fn with_max_boxes(mut self, n: u64) -> Self {
        self.max_boxes = n;
        self
    }
    pub fn with_time_limit(mut self, seconds: Option<f64>) -> Self {
        self.time_limit = seconds;
        self
    }
    pub fn with_max_depth(mut self, d: u32) -> Self {
        self.max_depth = d;
        self
    }
    pub fn with_min_depth(mut self, d: u32) -> Self {
        self.min_depth = d;
        self
    }
    pub fn with_max_angle(mut self, deg: f64, bound: AngleBound) -> Self {
        self.max_angle = deg;
        self.angle_bound = bound;
        self
    }
    pub fn with_crossing(mut self, c: Crossing, tol: f64) -> Self {
        self.crossing = c;
        self.tolerance = tol;
        self
    }
    /// From the shared options: `max_depth`, `min_depth`, `crossing`, `tolerance`, and
    /// `--set max_angle=DEG`, `--set angle_bound=crude|sharp`.
    pub fn from_options(o: &MesherOptions, dim: usize) -> Result<Self> {
        o.check_keys("pv", &["max_angle", "angle_bound"])?;
        let mut p = PvParams::new(dim);
        if let Some(d) = o.max_depth {
            p.max_depth = d;
        }
        if let Some(d) = o.min_depth {
            p.min_depth = d;
        }
        if let Some(c) = o.crossing {
            p.crossing = c;
        }
        if let Some(t) = o.tolerance {
            p.tolerance = t;
        }
        if let Some(n) = o.max_boxes {
            p.max_boxes = n;
        }
        p.time_limit = o.time_limit;
        if let Some(a) = o.get::<f64>("max_angle")? {
            p.max_angle = a;
        }
        if let Some(b) = o.get::<String>("angle_bound")? {
            p.angle_bound = parse_bound(&b)?;
        }
        p.validate()?;
        Ok(p)
    }
    pub fn validate(&self) -> Result<()> {
        if self.max_depth > MAX_LEVEL {
            return Err(Error::Param(format!(
                "max_depth {} exceeds the limit {MAX_LEVEL}",
                self.max_depth
            )));
        }
        if self.min_depth > self.max_depth {
            return Err(Error::Param(format!(
                "min_depth {} exceeds max_depth {}",
                self.min_depth, self.max_depth
            )));
        }
        if !(self.max_angle > 0.0 && self.max_angle <= 90.0) {
            return Err(Error::Param(format!(
                "max_angle {} must lie in (0, 90] degrees",
                self.max_angle
            )));
        }
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(Error::Param(format!(
                "tolerance {} must lie in (0, 1)",
                self.tolerance
            )));
        }
        check_budget(self.max_boxes, self.time_limit)?;
        Ok(())
    }
}

pub(crate) fn parse_bound(s: &str) -> Result<AngleBound> {
    match s {
        "crude" => Ok(AngleBound::Crude),
        "sharp" => Ok(AngleBound::Sharp),
        _ => Err(Error::Unknown {
            kind: "angle bound",
            name: s.into(),
            known: "crude sharp".into(),
        }),
    }
}

/// Plantinga–Vegter in dimension `D` (2: curves, quadtree; 3: surfaces, octree): one
/// type, name `pv`. [`PlantingaVegter`] and [`PlantingaVegter2`] name the two
/// instances.
#[derive(Clone, Debug)]
pub struct PlantingaVegterN<const D: usize> {
    pub params: PvParams,
}
/// Plantinga–Vegter for surfaces (dim 3).
pub type PlantingaVegter = PlantingaVegterN<3>;
/// Plantinga–Vegter for curves (dim 2).
pub type PlantingaVegter2 = PlantingaVegterN<2>;

impl<const D: usize> Default for PlantingaVegterN<D> {
    fn default() -> Self {
        PlantingaVegterN {
            params: PvParams::new(D),
        }
    }
}

impl<const D: usize> PlantingaVegterN<D> {
    pub fn new(params: PvParams) -> Self {
        PlantingaVegterN { params }
    }
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Ok(PlantingaVegterN {
            params: PvParams::from_options(o, D)?,
        })
    }
}

impl<const D: usize> Mesher for PlantingaVegterN<D> {
    fn name(&self) -> &'static str {
        "pv"
    }
    fn dim(&self) -> usize {
        D
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        Ok(run_pv(f, domain, &self.params, D, progress)?.1)
    }
}

/// The Plantinga–Vegter subdivision test of one box.
pub(crate) fn pv_classify(
    f: &dyn Implicit,
    g: &Grid,
    c: crate::subdivision::Cell,
    p: &PvParams,
) -> Decision {
    let ib = g.cell_ibox(c);
    let v = f.eval_interval(&ib);
    if v.is_empty() {
        return Decision::Leaf(Verdict::Failed(UNDEFINED_BOX));
    }
    if excludes_zero(v) {
        return Decision::Leaf(Verdict::Empty);
    }
    let d = f.grad_interval(&ib);
    // The mean-value form proves more boxes near (but off) the curve empty.
    if excludes_zero(mean_value(f, &ib, &d)) {
        return Decision::Leaf(Verdict::Empty);
    }
    let ok = if p.max_angle >= 90.0 {
        snv_dot(&d.g, g.dim).inf() > 0.0
    } else {
        cos_lower_bound(&d.g, g.dim, p.angle_bound)
            .is_some_and(|c| c >= p.max_angle.to_radians().cos())
    };
    if ok {
        // Theorem 2 needs f ∈ C¹ on the box: an enclosure over a pole "excludes 0"
        // without meaning anything.
        if let Some(reason) = f.regularity(&ib).c1_failure() {
            return Decision::Split(reason);
        }
        if let Some(d) = boundary_failure(f, g, c) {
            return d;
        }
        Decision::Leaf(Verdict::Snv)
    } else if (0..g.dim).all(|k| d.g[k].contains(0.0)) {
        Decision::Split("possible singular point: 0 in □f and 0 in □∇f")
    } else {
        Decision::Split("depth limit hit")
    }
}

/// Run Plantinga–Vegter; also returns the tree (for figures and reports).
pub fn run_pv(
    f: &dyn Implicit,
    domain: &Aabb,
    p: &PvParams,
    dim: usize,
    progress: &dyn Progress,
) -> Result<(Tree, MeshOutput)> {
    check_input(f, domain, dim, "pv")?;
    p.validate()?;
    let grid = Grid {
        domain: *domain,
        dim,
        depth: p.max_depth,
    };
    let budget = Budget::new(p.max_boxes, p.time_limit);
    budget.check_min_depth(dim, p.min_depth)?;
    progress.start("subdivision", 0);
    let mut tree = subdivide(grid, p.min_depth, p.max_depth, &budget, &|g: &Grid, c| {
        pv_classify(f, g, c, p)
    });
    tree.balance(f);
    tree.collect_points();
    progress.inc(tree.leaves.len() as u64);
    progress.finish();
    let finder = SignChange {
        tol: p.tolerance,
        linear: p.crossing == Crossing::Linear,
    };
    let asm = assemble(f, &tree, &finder, &PvPairing);
    let mut stats = tree_stats(&tree, &asm);
    stats.insert("max_angle_deg".into(), serde_json::json!(p.max_angle));
    let mut regions = tree.failures();
    regions.extend(asm.uncertain.iter().cloned());
    let certificate = certificate(PV_THEOREM, &tree, dim, domain, false, regions);
    let mesh = if dim == 2 {
        Mesh::Curve(asm.curve.unwrap_or_default())
    } else {
        Mesh::Surface(asm.surface.unwrap_or_default())
    };
    Ok((
        tree,
        MeshOutput {
            mesh,
            certificate,
            stats,
        },
    ))
}

/// The connection rules of §1.2.4.
pub struct PvPairing;

impl Pairing for PvPairing {
    fn pair(
        &self,
        f: &dyn Implicit,
        corners: &[[f64; 3]; 4],
        normal_axis: usize,
        cross: &[TileCrossing],
    ) -> Vec<(usize, usize)> {
        if cross.len() <= 2 {
            return cut_arcs(cross, true);
        }
        let neg = cut_arcs(cross, true);
        let pos = cut_arcs(cross, false);
        if normal_axis == 2 && corners.iter().all(|c| c[2] == corners[0][2]) && is_planar_2d(f) {
            // Fig 1.9d: two crossings on the same (split) side are never joined.
            let same =
                |v: &[(usize, usize)]| v.iter().any(|&(i, j)| cross[i].side == cross[j].side);
            match (same(&neg), same(&pos)) {
                (true, false) => return pos,
                (false, true) => return neg,
                _ => {}
            }
        }
        // The face ambiguity of Fig 1.10: decided by f at the centre of the square, which
        // both boxes sharing it evaluate identically (f == 0 counts as positive).
        let mut c = [0.0; 3];
        for p in corners {
            for k in 0..3 {
                c[k] += 0.25 * p[k];
            }
        }
        if f.eval(c) >= 0.0 {
            neg
        } else {
            pos
        }
    }
}

fn is_planar_2d(f: &dyn Implicit) -> bool {
    f.dim() == 2
}
