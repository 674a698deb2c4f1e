//! Typed certificate claims and typed reasons for uncertified regions, so that a script
//! or the comparison harness can ask "which outputs are proven isotopic" without
//! parsing prose. Each claim's `Display` is the sentence the report prints (the
//! `claims` strings of the JSON report); the typed form is in `claims_typed`.
use crate::kernel::geom::Aabb;
use serde::{Deserialize, Serialize};
use std::fmt;

/// One proven statement about a mesher's output.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Claim {
    /// The output is isotopic to f = 0 inside `inside` (the domain), by `theorem`. With
    /// `generic_position` the grid meshed a rotated box containing the domain, and f = 0
    /// was proven not to meet that box outside the domain (so `inside` is still the
    /// domain, never the rotated box or its hull).
    Isotopic {
        inside: Aabb,
        theorem: String,
        generic_position: bool,
    },
    /// f = 0 inside `inside` is a regular curve (`dim` 2) or surface (3): every box
    /// meeting it was proven C^∞ with ∇f bounded away from 0.
    RegularZeroSet { dim: usize, inside: Aabb },
    /// `empty` of the `boxes` leaves were proven free of f = 0 (0 ∉ □f).
    ExcludedEmpty { empty: usize, boxes: usize },
    /// Every interior triangle lies in exactly two tetrahedra and the boundary is
    /// watertight and consistently oriented (exact combinatorial check).
    Conforming { nonmanifold_edges: usize },
    /// The number of tetrahedra with non-positive orientation (exact orient3d).
    InvertedTetrahedra { count: usize },
    /// The output is exactly the restricted Delaunay triangulation of its vertex set:
    /// the Delaunay triangulation (with the far-box corners; exact predicates with
    /// symbolic perturbation) passed its exact check, and on each of the
    /// `voronoi_edges` dual segments (interval circumcentres) every crossing with
    /// f = 0 was isolated by interval arithmetic, none undecided.
    RestrictedDelaunay {
        facets: usize,
        voronoi_edges: usize,
        /// Dual segments crossing f = 0 more than once.
        multiple_crossings: usize,
    },
    /// Every surface Delaunay ball of the restricted triangulation has radius at most
    /// `psi` = 0.099 × `reach_lower_bound`, a certified lower bound of the reach (hence
    /// of lfs): the weak ε-sample condition, ε = 0.099 < 0.1, of the chapter "Meshing of Surfaces"
    /// (Boissonnat et al., 2007, §1.3.1) on every ball.
    WeakSample {
        psi: f64,
        reach_lower_bound: f64,
        max_ball_radius: f64,
    },
    /// Every vertex p lies within `max_offset` of a point p* of f = 0 (certified root
    /// isolation along ∇f), and for every choice of such points the Delaunay
    /// tetrahedralization (`cells` cells, all positively oriented, `facets` facets all
    /// strictly locally Delaunay) and the restricted facets are the output's, with
    /// surface Delaunay balls of radius at most `max_ball_radius` (interval arithmetic
    /// over the vertex boxes): Theorem 3's sample on S, for floating-point vertices.
    PerturbedSample {
        max_offset: f64,
        cells: usize,
        facets: usize,
        /// Of the facets, those locally Delaunay only in the non-strict sense, exactly:
        /// four of their five points are corners of one face of the far box, or all
        /// five are samples on S when S is a round sphere.
        exactly_cospherical: usize,
        max_ball_radius: f64,
    },
    /// The output is exactly the restricted Delaunay graph (by f = 0 inside the
    /// domain) of the refinement's sample of `sample_points` points, for a curve
    /// f(x, y) = 0: the 2D Delaunay triangulation (spade, with four far points) passed
    /// the exact orient2d/incircle check, and on each of the `voronoi_edges` dual
    /// segments (interval circumcentres) every crossing with f = 0 was isolated by
    /// interval arithmetic, none undecided; edges with a far end point are not
    /// restricted by the far lemma (checked with intervals). `isolated_sample_points`
    /// sample points lie on no restricted edge and are not output vertices.
    RestrictedDelaunayCurve {
        edges: usize,
        voronoi_edges: usize,
        /// Dual segments crossing f = 0 more than once.
        multiple_crossings: usize,
        sample_points: usize,
        isolated_sample_points: usize,
    },
    /// The output is homeomorphic (not proven isotopic) to f = 0 inside the domain,
    /// `by` a theorem whose every hypothesis was checked with interval arithmetic.
    Homeomorphic {
        by: HomeomorphismBy,
        voronoi_edges: usize,
        voronoi_facets: usize,
        voronoi_cells: usize,
    },
}

/// The theorems that prove a homeomorphism.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HomeomorphismBy {
    /// The restricted Delaunay triangulation of a point set with the topological ball
    /// property (the chapter "Meshing of Surfaces", Boissonnat et al., 2007, §1.3.2,
    /// Theorem 5, after Edelsbrunner and Shah's closed-ball property), every Voronoi
    /// edge, facet and cell meeting f = 0 checked (tests (1)-(4) as checks).
    TopologicalBallProperty,
}

impl fmt::Display for Claim {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Claim::Isotopic {
                theorem,
                generic_position,
                ..
            } => {
                write!(f, "isotopic to f = 0 inside the domain ({theorem})")?;
                if *generic_position {
                    write!(f, ", grid in generic position (the meshed region is a rotated box containing the domain; f = 0 is proven not to meet it outside the domain)")?;
                }
                Ok(())
            }
            Claim::RegularZeroSet { dim, .. } => write!(
                f,
                "f = 0 inside the domain is a regular {}: every box meeting it is proven C^inf \
                 with a gradient bounded away from 0 (interval regularity flags and enclosures)",
                if *dim == 2 { "curve" } else { "surface" }
            ),
            Claim::ExcludedEmpty { empty, boxes } => write!(
                f,
                "{empty} of {boxes} boxes proven free of f = 0 (0 not in the enclosure of f)"
            ),
            Claim::Conforming { nonmanifold_edges } => {
                write!(f, "conforming: every interior triangle in exactly two tetrahedra, boundary watertight and consistently oriented")?;
                if *nonmanifold_edges == 0 {
                    write!(f, ", a closed 2-manifold")?;
                } else {
                    write!(
                        f,
                        ", with {nonmanifold_edges} non-manifold edges where the solid pinches"
                    )?;
                }
                write!(f, " (exact combinatorial check)")
            }
            Claim::InvertedTetrahedra { count } => {
                write!(f, "{count} inverted tetrahedra (exact orient3d)")
            }
            Claim::RestrictedDelaunay {
                facets,
                voronoi_edges,
                multiple_crossings,
            } => write!(
                f,
                "exactly the restricted Delaunay triangulation of its vertices: {facets} facets; \
                 all crossings of f = 0 with {voronoi_edges} dual Voronoi edges isolated by interval \
                 arithmetic ({multiple_crossings} edges cross more than once), Delaunay \
                 triangulation checked with exact predicates"
            ),
            Claim::RestrictedDelaunayCurve {
                edges,
                voronoi_edges,
                multiple_crossings,
                sample_points,
                isolated_sample_points,
            } => write!(
                f,
                "exactly the restricted Delaunay graph of the sample by the curve ({sample_points} \
                 points, {isolated_sample_points} of them on no restricted edge and left out): {edges} edges; \
                 all crossings of f = 0 with {voronoi_edges} dual Voronoi edges isolated by interval \
                 arithmetic ({multiple_crossings} edges cross more than once), Delaunay \
                 triangulation checked with exact predicates"
            ),
            Claim::WeakSample {
                psi,
                reach_lower_bound,
                max_ball_radius,
            } => write!(
                f,
                "every surface Delaunay ball has radius <= {max_ball_radius:.3e} <= psi = {psi:.3e} = 0.099 x \
                 {reach_lower_bound:.3e} (a certified lower bound of the reach, hence of lfs): \
                 the weak 0.099-sample condition on every ball (interval arithmetic)"
            ),
            Claim::PerturbedSample {
                max_offset,
                cells,
                facets,
                exactly_cospherical,
                max_ball_radius,
            } => write!(
                f,
                "every vertex is within {max_offset:.1e} of a certified point of f = 0, and for every such \
                 point set the Delaunay tetrahedralization ({cells} cells, all positive; {facets} facets, all \
                 strictly locally Delaunay but {exactly_cospherical} exactly cospherical: on a face of the far \
                 box, or five samples of a round sphere S) and the restricted facets are the output's, surface Delaunay balls <= \
                 {max_ball_radius:.3e} (interval arithmetic over the vertex boxes)"
            ),
            Claim::Homeomorphic {
                by: HomeomorphismBy::TopologicalBallProperty,
                voronoi_edges,
                voronoi_facets,
                voronoi_cells,
            } => write!(
                f,
                "homeomorphic (topological ball property) to f = 0 inside the domain: the chapter's \
                 Theorem 5, every hypothesis checked with interval arithmetic on {voronoi_edges} \
                 Voronoi edges, {voronoi_facets} facets and {voronoi_cells} cells; not proven \
                 isotopic (Research Problem 4)"
            ),
        }
    }
}

impl Claim {
    /// Does this claim state that the output has the topology of f = 0 (isotopic, or
    /// homeomorphic: the same components and genera)?
    pub fn is_topological(&self) -> bool {
        matches!(self, Claim::Isotopic { .. } | Claim::Homeomorphic { .. })
    }
    /// Does this claim state an isotopy (not only a homeomorphism)?
    pub fn is_isotopy(&self) -> bool {
        matches!(self, Claim::Isotopic { .. })
    }
}

/// Why a region is uncertified, by kind (the text is in the region's `reason`). Ordered
/// from the input's own defects (a pole) to the run's limits (the budgets).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum Cause {
    /// f may have a pole, a gap of its domain, or a discontinuity on the box.
    NotContinuous,
    /// f is continuous but not differentiable there (|x|, min, max, √ at 0).
    NotDifferentiable,
    /// f is undefined on the whole box.
    Undefined,
    /// 0 ∈ □f and 0 ∈ □∇f: a singular point may be there.
    PossiblySingular,
    /// The criterion did not hold before the depth limit.
    DepthLimit,
    /// Roots on a box edge could not be isolated (a grazing intersection).
    Grazing,
    /// A face tangent to the surface (Snyder's top/bottom faces).
    TangentFace,
    /// f = 0 meets the boundary of the domain where the theorem needs it not to.
    DomainBoundary,
    /// f = 0 may meet the part of the meshed region outside the domain (generic
    /// position meshes a rotated box containing the domain).
    OutsideDomain,
    /// The sign of f at a grid point is undecided (0 in its enclosure).
    UndecidedSign,
    /// The box budget (`--max-boxes`) ran out.
    BoxBudget,
    /// The time limit (`--time-limit`) passed.
    TimeLimit,
    /// Anything else (the lattice does not resolve the surface, ...).
    #[default]
    Other,
}

impl Cause {
    /// The kind of a reason text written by the meshers (their reasons are constants;
    /// this is the one place that maps them).
    pub fn of(reason: &str) -> Cause {
        let r = reason;
        if r.starts_with("f is not continuous") {
            Cause::NotContinuous
        } else if r.starts_with("f is not differentiable") {
            Cause::NotDifferentiable
        } else if r.starts_with("f is undefined") {
            Cause::Undefined
        } else if r.starts_with("possible singular point") {
            Cause::PossiblySingular
        } else if r.starts_with("depth limit") {
            Cause::DepthLimit
        } else if r.starts_with("grazing") {
            Cause::Grazing
        } else if r.starts_with("top/bottom face") {
            Cause::TangentFace
        } else if r.starts_with(crate::subdivision::OUTSIDE_DOMAIN_REASON) {
            Cause::OutsideDomain
        } else if r.contains("domain boundary") || r.contains("domain edge") {
            Cause::DomainBoundary
        } else if r.starts_with("sign of f") {
            Cause::UndecidedSign
        } else if r.starts_with("box budget") {
            Cause::BoxBudget
        } else if r.starts_with("time limit") {
            Cause::TimeLimit
        } else {
            Cause::Other
        }
    }
}
