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
use crate::mesher::options::{Crossing, MesherOptions};
use crate::subdivision::criteria::{boundary_failure, identically_zero, UNDEFINED_BOX, ZERO_BOX};
use crate::subdivision::engine::{Criterion, SubdivisionMesher, SubdivisionParams};
use crate::subdivision::{
    cos_lower_bound, cut_arcs, excludes_zero, mean_value, snv_dot, AngleBound, Cell, Decision,
    FaceTile, Grid, Pairing, RootFinder, SignChange, Verdict,
};

/// The theorem a certified run invokes.
pub const PV_THEOREM: &str = "Plantinga–Vegter";
/// The claim of a certified run.
pub const PV_CLAIM: &str = "isotopic to f = 0 inside the domain (Plantinga–Vegter)";

/// The settings of the Plantinga–Vegter criterion (the limits every subdivision mesher
/// has are in [`SubdivisionParams`]).
#[derive(Clone, Debug)]
pub struct PvCriterion {
    /// How crossings are located (default bisection); topology never depends on it.
    pub crossing: Crossing,
    /// Largest angle between two gradients allowed in an accepted box, in degrees
    /// (default 90: Small Normal Variation, eq 1.2). Smaller values refine further
    /// (Exercise 9); `--set max_angle=45`.
    pub max_angle: f64,
    /// The angle bound used when `max_angle < 90` (default sharp); `--set angle_bound=crude|sharp`.
    pub angle_bound: AngleBound,
}

impl Default for PvCriterion {
    fn default() -> Self {
        PvCriterion {
            crossing: Crossing::Bisection,
            max_angle: 90.0,
            angle_bound: AngleBound::Sharp,
        }
    }
}

/// Parameters of both Plantinga–Vegter meshers: the shared limits (default depth limit
/// 12 for surfaces, 16 for curves) and [`PvCriterion`].
pub type PvParams = SubdivisionParams<PvCriterion>;

impl PvParams {
    pub fn with_max_angle(mut self, deg: f64, bound: AngleBound) -> Self {
        self.criterion.max_angle = deg;
        self.criterion.angle_bound = bound;
        self
    }
    pub fn with_crossing(mut self, c: Crossing, tol: f64) -> Self {
        self.criterion.crossing = c;
        self.tolerance = tol;
        self
    }
}

impl Criterion for PvCriterion {
    const ALGO: &'static str = "pv";
    const THEOREM: &'static str = PV_THEOREM;
    const SETTINGS: &'static [&'static str] = &["max_angle", "angle_bound"];
    const BALANCED: bool = true;
    fn default_max_depth(dim: usize) -> u32 {
        if dim == 2 {
            16
        } else {
            12
        }
    }
    /// `crossing`, and `--set max_angle=DEG`, `--set angle_bound=crude|sharp`.
    fn apply_options(p: &mut PvParams, o: &MesherOptions, _dim: usize) -> Result<()> {
        if let Some(c) = o.crossing {
            p.criterion.crossing = c;
        }
        if let Some(a) = o.get::<f64>("max_angle")? {
            p.criterion.max_angle = a;
        }
        if let Some(b) = o.get::<String>("angle_bound")? {
            p.criterion.angle_bound = parse_bound(&b)?;
        }
        Ok(())
    }
    fn validate(&self) -> Result<()> {
        if !(self.max_angle > 0.0 && self.max_angle <= 90.0) {
            return Err(Error::Param(format!(
                "max_angle {} must lie in (0, 90] degrees",
                self.max_angle
            )));
        }
        Ok(())
    }
    fn classify(p: &PvParams, f: &dyn Implicit, g: &Grid, c: Cell) -> Decision {
        pv_classify(f, g, c, p)
    }
    fn root_finder(p: &PvParams) -> Box<dyn RootFinder> {
        Box::new(SignChange {
            tol: p.tolerance,
            linear: p.criterion.crossing == Crossing::Linear,
        })
    }
    fn pairing(&self) -> &dyn Pairing {
        &PvPairing
    }
    fn add_stats(&self, stats: &mut serde_json::Map<String, serde_json::Value>) {
        stats.insert("max_angle_deg".into(), serde_json::json!(self.max_angle));
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
/// type, name `pv`, the engine run with [`PvCriterion`]. [`PlantingaVegter`] and
/// [`PlantingaVegter2`] name the two instances.
pub type PlantingaVegterN<const D: usize> = SubdivisionMesher<PvCriterion, D>;
/// Plantinga–Vegter for surfaces (dim 3).
pub type PlantingaVegter = PlantingaVegterN<3>;
/// Plantinga–Vegter for curves (dim 2).
pub type PlantingaVegter2 = PlantingaVegterN<2>;

/// The Plantinga–Vegter subdivision test of one box.
pub(crate) fn pv_classify(f: &dyn Implicit, g: &Grid, c: Cell, p: &PvParams) -> Decision {
    let ib = g.cell_ibox(c);
    let v = f.eval_interval(&ib);
    if v.is_empty() {
        return Decision::Leaf(Verdict::Failed(UNDEFINED_BOX));
    }
    if identically_zero(v) {
        return Decision::Leaf(Verdict::Failed(ZERO_BOX));
    }
    if excludes_zero(v) {
        return Decision::Leaf(Verdict::Empty);
    }
    let d = f.grad_interval(&ib);
    // The mean-value form proves more boxes near (but off) the curve empty.
    if excludes_zero(mean_value(f, &ib, &d)) {
        return Decision::Leaf(Verdict::Empty);
    }
    let ok = if p.criterion.max_angle >= 90.0 {
        snv_dot(&d.g, g.dim).inf() > 0.0
    } else {
        cos_lower_bound(&d.g, g.dim, p.criterion.angle_bound)
            .is_some_and(|c| c >= p.criterion.max_angle.to_radians().cos())
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
        Decision::Leaf(Verdict::SNV)
    } else if (0..g.dim).all(|k| d.g[k].contains(0.0)) {
        Decision::Split("possible singular point: 0 in □f and 0 in □∇f")
    } else {
        Decision::Split("depth limit hit")
    }
}

/// Run Plantinga–Vegter; also returns the tree (in moved coordinates when the criterion asks for
/// generic position): [`crate::subdivision::engine::run_subdivision`].
pub use crate::subdivision::engine::run_subdivision as run_pv;

/// The connection rules of §1.2.4.
pub struct PvPairing;

impl Pairing for PvPairing {
    fn pair(&self, f: &dyn Implicit, tile: FaceTile) -> Vec<(usize, usize)> {
        let FaceTile {
            corners,
            normal_axis,
            cross,
        } = tile;
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
