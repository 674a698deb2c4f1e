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
use crate::subdivision::{
    assemble, cos_lower_bound, cut_arcs, excludes_zero, mean_value, snv_dot, subdivide, tree_stats,
    AngleBound, Budget, Decision, Grid, Pairing, SignChange, TileCrossing, Tree, Verdict,
    DEFAULT_MAX_BOXES, MAX_LEVEL,
};

/// The reason for a box on which f is defined nowhere (an empty enclosure): "no zero"
/// would be vacuous and is almost always a mistake in the formula (x/0).
pub const UNDEFINED_BOX: &str =
    "f is undefined on this whole box (a division by 0, a root of a negative number)";

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

/// `--max-boxes` at least 1, `--time-limit` positive and finite.
pub(crate) fn check_budget(max_boxes: u64, time_limit: Option<f64>) -> Result<()> {
    if max_boxes == 0 {
        return Err(Error::Param("max_boxes must be at least 1".into()));
    }
    if let Some(t) = time_limit {
        if !(t > 0.0 && t.is_finite()) {
            return Err(Error::Param(format!(
                "time_limit {t} must be a positive number of seconds"
            )));
        }
    }
    Ok(())
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

/// Plantinga–Vegter for surfaces (octree). Name `pv`, dim 3.
#[derive(Clone, Debug)]
pub struct PlantingaVegter {
    pub params: PvParams,
}

/// Plantinga–Vegter for curves (quadtree). Name `pv`, dim 2.
#[derive(Clone, Debug)]
pub struct PlantingaVegter2 {
    pub params: PvParams,
}

impl Default for PlantingaVegter {
    fn default() -> Self {
        PlantingaVegter {
            params: PvParams::new(3),
        }
    }
}
impl Default for PlantingaVegter2 {
    fn default() -> Self {
        PlantingaVegter2 {
            params: PvParams::new(2),
        }
    }
}

impl PlantingaVegter {
    pub fn new(params: PvParams) -> Self {
        PlantingaVegter { params }
    }
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Ok(PlantingaVegter {
            params: PvParams::from_options(o, 3)?,
        })
    }
}
impl PlantingaVegter2 {
    pub fn new(params: PvParams) -> Self {
        PlantingaVegter2 { params }
    }
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Ok(PlantingaVegter2 {
            params: PvParams::from_options(o, 2)?,
        })
    }
}

impl Mesher for PlantingaVegter {
    fn name(&self) -> &'static str {
        "pv"
    }
    fn dim(&self) -> usize {
        3
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        Ok(run_pv(f, domain, &self.params, 3, progress)?.1)
    }
}

impl Mesher for PlantingaVegter2 {
    fn name(&self) -> &'static str {
        "pv"
    }
    fn dim(&self) -> usize {
        2
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        Ok(run_pv(f, domain, &self.params, 2, progress)?.1)
    }
}

/// Check the function's and the domain's dimension against the mesher's.
pub(crate) fn check_input(f: &dyn Implicit, domain: &Aabb, dim: usize, algo: &str) -> Result<()> {
    if f.dim() != dim {
        return Err(Error::Param(format!(
            "{algo}: this mesher is for {dim}D input but the function is {}D",
            f.dim()
        )));
    }
    let d = Aabb::new(domain.min, domain.max)?;
    for k in 0..dim {
        if !(d.max[k] > d.min[k]) {
            return Err(Error::Domain(format!(
                "axis {} range [{}, {}] is empty",
                ["x", "y", "z"][k],
                d.min[k],
                d.max[k]
            )));
        }
    }
    Ok(())
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

/// The domain boundary (found by the soundness property test). The argument behind
/// Theorem 2 lets the curve cross a box edge twice unnoticed because it "cannot leave
/// the adjacent cube without violating the Small Normal Variation condition" there
/// (the chapter, Fig. 1.9c); on the boundary of the domain there is no adjacent cube,
/// and the arc that dips out of the domain and comes back is lost: f = 1.5x² + y² −
/// 2.25 on [−1.63, 0.24] × [−1.49, −0.49] has two arcs inside the domain, and the
/// unguarded algorithm meshed one. So a box touching the boundary is accepted only if
/// * in 2D, on each of its edges on the boundary, 0 ∉ □f or 0 ∉ □∂f/∂t (at most one
///   crossing, seen by the end signs);
/// * in 3D, on each of its faces on the boundary, 0 ∉ □f: the surface stays inside
///   the domain, the setting in which the theorem is proven. A surface that crosses
///   the boundary is reported uncertified there.
pub(crate) fn boundary_failure(
    f: &dyn Implicit,
    g: &Grid,
    c: crate::subdivision::Cell,
) -> Option<Decision> {
    let (lo, hi) = g.cell_lo_hi(c);
    let top = 1u32 << g.depth;
    for k in 0..g.dim {
        for (side, on) in [(lo[k], lo[k] == 0), (hi[k], hi[k] == top)] {
            if !on {
                continue;
            }
            let (mut a, mut b) = (lo, hi);
            a[k] = side;
            b[k] = side;
            let fb = g.ibox(a, b);
            if g.dim == 2 {
                let t = 1 - k; // the edge runs along the other axis
                let d = f.grad_interval(&fb);
                if excludes_zero(d.v) {
                    continue;
                }
                if !excludes_zero(d.g[t]) {
                    return Some(Decision::Split(
                        "f = 0 may cross a domain edge twice (Theorem 2 needs a monotone f there)",
                    ));
                }
                // A zero exactly at an end (the curve through a corner of the domain,
                // or touching it there) is not seen by the sign⁺ convention correctly.
                for p in [g.point(a), g.point(b)] {
                    let pb = p.map(crate::implicit::number::point);
                    if !excludes_zero(f.eval_interval(&pb)) {
                        return Some(Decision::Split(
                            "f = 0 may pass through a grid point on the domain boundary",
                        ));
                    }
                }
            } else {
                let v = f.eval_interval(&fb);
                if !excludes_zero(v) {
                    // Smaller boxes may prove a face near the surface free of it, but
                    // where the face's corners have proven opposite signs the surface
                    // does cross the boundary: no refinement helps, stop here.
                    let signs: Vec<_> = face_corners(a, b, k)
                        .into_iter()
                        .map(|q| crate::implicit::ops::point_sign(f, g.point(q)))
                        .collect();
                    let crosses = signs.iter().all(|s| s.rigorous)
                        && signs.iter().any(|s| s.pos)
                        && signs.iter().any(|s| !s.pos);
                    let reason = "f = 0 may meet the domain boundary (Theorem 2 is proven for a surface inside the domain)";
                    return Some(if crosses {
                        Decision::Leaf(Verdict::Failed(
                            "f = 0 meets the domain boundary (Theorem 2 is proven for a surface inside the domain)",
                        ))
                    } else {
                        Decision::Split(reason)
                    });
                }
            }
        }
    }
    None
}

/// The four corners of the face spanned by grid points `a` and `b` (equal in axis
/// `normal`).
fn face_corners(a: [u32; 3], b: [u32; 3], normal: usize) -> [[u32; 3]; 4] {
    let (u, v) = match normal {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    let mut out = [a; 4];
    for (m, q) in out.iter_mut().enumerate() {
        if m & 1 == 1 {
            q[u] = b[u];
        }
        if m & 2 == 2 {
            q[v] = b[v];
        }
    }
    out
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
