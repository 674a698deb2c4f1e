//! Snyder's mesher by global parameterizability (chapter §1.2.3, Lemma 2), for curves
//! ([`Snyder2`]) and surfaces ([`Snyder`]).
//!
//! A box is accepted when 0 ∉ □f, or when some partial □∂f/∂x_k excludes 0 (the zero set
//! is a graph over the other variables, eq 1.1), the two faces normal to x_k (the "top"
//! and "bottom") each have 0 ∉ □f or an in-plane partial excluding 0, and the zeros of f
//! on all box edges are isolated by interval root isolation (each piece has 0 ∉ □f or
//! 0 ∉ □f'). The mesh of each box is built from the sorted crossings: on every face tile
//! (a face of the box, or of a smaller neighbour — the smaller boxes' pattern transmitted
//! to the larger box) the crossings sorted along the parameter direction are joined in
//! consecutive pairs (Fig 1.7), and in 3D the resulting boundary cycles of the box are
//! fanned into triangles (Fig 1.8e).
//!
//! Termination is not guaranteed (grazing edges, faces tangent to the surface as in the
//! chapter's paraboloid example): the depth is bounded, failing boxes are meshed by sign
//! changes only and reported. `generic_shift` moves the grid to a generic position
//! ([`GenericMotion`]).
use crate::error::{Error, Result};
use crate::implicit::Implicit;
use crate::mesher::options::MesherOptions;
use crate::subdivision::criteria::{boundary_failure, identically_zero, UNDEFINED_BOX, ZERO_BOX};
use crate::subdivision::engine::{Criterion, SubdivisionMesher, SubdivisionParams};
use crate::subdivision::plantinga_vegter::PvPairing;
use crate::subdivision::{
    enclose, excludes_zero, no_zero_plus, point_sign, Cell, Decision, FaceTile, Grid,
    IntervalIsolation, Pairing, RootFinder, Verdict,
};
use std::sync::atomic::AtomicU64;

/// The theorem a certified run invokes.
pub const SNYDER_THEOREM: &str = "Snyder, Lemma 2";
pub const SNYDER_CLAIM: &str = "isotopic to f = 0 inside the domain (Snyder, Lemma 2)";

/// The settings of Snyder's criterion (the limits every subdivision mesher has are in
/// [`SubdivisionParams`]).
#[derive(Clone, Debug)]
pub struct SnyderCriterion {
    /// Bisections allowed when isolating the roots on one edge (default 40; `--set root_depth=N`).
    pub root_depth: u32,
    /// Mesh in generic position (default false; `--generic-shift`).
    pub generic_shift: bool,
}

impl Default for SnyderCriterion {
    fn default() -> Self {
        SnyderCriterion {
            root_depth: 40,
            generic_shift: false,
        }
    }
}

/// Parameters of both Snyder meshers: the shared limits (default depth limit 10 for
/// surfaces, 16 for curves; 14 for surfaces built by [`SnyderParams::from_options`] with
/// `generic_shift`, the depth at which every smooth catalog surface certifies in generic
/// position) and [`SnyderCriterion`].
pub type SnyderParams = SubdivisionParams<SnyderCriterion>;

impl SnyderParams {
    pub fn with_generic_shift(mut self, on: bool) -> Self {
        self.criterion.generic_shift = on;
        self
    }
}

impl Criterion for SnyderCriterion {
    const ALGO: &'static str = "snyder";
    const THEOREM: &'static str = SNYDER_THEOREM;
    const SETTINGS: &'static [&'static str] = &["root_depth"];
    const BALANCED: bool = false;
    fn default_max_depth(dim: usize) -> u32 {
        if dim == 2 {
            16
        } else {
            10
        }
    }
    /// `generic_shift` (raising the default depth limit of surfaces to 14), and
    /// `--set root_depth=N`.
    fn apply_options(p: &mut SnyderParams, o: &MesherOptions, dim: usize) -> Result<()> {
        if o.generic_shift && dim == 3 {
            p.max_depth = 14;
        }
        p.criterion.generic_shift = o.generic_shift;
        if let Some(r) = o.get::<u32>("root_depth")? {
            p.criterion.root_depth = r;
        }
        Ok(())
    }
    fn validate(&self) -> Result<()> {
        if self.root_depth == 0 || self.root_depth > 60 {
            return Err(Error::Param(format!(
                "root_depth {} must lie in 1..=60",
                self.root_depth
            )));
        }
        Ok(())
    }
    fn classify(p: &SnyderParams, f: &dyn Implicit, g: &Grid, c: Cell) -> Decision {
        snyder_classify(f, g, c, p)
    }
    fn root_finder(p: &SnyderParams) -> Box<dyn RootFinder> {
        Box::new(isolation(p))
    }
    fn pairing(&self) -> &dyn Pairing {
        &SnyderPairing
    }
    fn generic_position(&self) -> bool {
        self.generic_shift
    }
    fn add_stats(&self, stats: &mut serde_json::Map<String, serde_json::Value>) {
        stats.insert(
            "generic_shift".into(),
            serde_json::json!(self.generic_shift),
        );
    }
}

/// Snyder's mesher in dimension `D` (2: curves, quadtree; 3: surfaces, octree): one
/// type, name `snyder`, the engine run with [`SnyderCriterion`]. [`Snyder`] and
/// [`Snyder2`] name the two instances.
pub type SnyderN<const D: usize> = SubdivisionMesher<SnyderCriterion, D>;
/// Snyder for surfaces (dim 3).
pub type Snyder = SnyderN<3>;
/// Snyder for curves (dim 2).
pub type Snyder2 = SnyderN<2>;

/// The interval root isolation on box edges (Lemma 2's edge condition and the crossings).
fn isolation(p: &SnyderParams) -> IntervalIsolation {
    IntervalIsolation {
        max_depth: p.criterion.root_depth,
        tol: p.tolerance,
    }
}

/// Face criterion of Lemma 2: f has no zero on the face in the sign⁺ sense (□f ⊂
/// [0, ∞) or (−∞, 0)), or one of the two in-plane partials excludes 0. Called only
/// for a face of a box already proven C^∞ with a partial bounded away from 0, where
/// the zero set is regular and the sign⁺ convention (meshing f + ε) is isotopic to
/// f = 0: a face the surface only touches (the blob at (±1, 0, 0)) is then fine. It
/// is never used to exclude a box: that needs 0 ∉ □f strictly.
fn face_ok(f: &dyn Implicit, ib: &crate::implicit::IBox, normal: usize) -> bool {
    let (v, g) = enclose(f, ib);
    no_zero_plus(v) || (0..3).any(|j| j != normal && excludes_zero(g[j]))
}

fn snyder_classify(f: &dyn Implicit, g: &Grid, c: Cell, p: &SnyderParams) -> Decision {
    let ib = g.cell_ibox(c);
    let (v, grad) = enclose(f, &ib);
    let d = crate::implicit::Dual { v, g: grad };
    let plain = f.eval_interval(&ib);
    if plain.is_empty() {
        return Decision::Leaf(Verdict::Failed(UNDEFINED_BOX));
    }
    if identically_zero(plain) {
        return Decision::Leaf(Verdict::Failed(ZERO_BOX));
    }
    // Only a strict exclusion proves the box free of f = 0: with □f ⊂ [0, ∞) the box
    // may hold a double zero ((x²+y²+z²−1)² vanishes on the sphere).
    if excludes_zero(d.v) {
        return Decision::Leaf(Verdict::Empty);
    }
    // Lemma 2 is about C¹ functions: no box is certified where f may have a pole, a
    // kink or a domain boundary.
    let smooth = f.regularity(&ib).c1_failure();
    let dim = g.dim;
    let (lo, hi) = g.cell_lo_hi(c);
    let mut any_param = false;
    let mut faces_failed = false;
    for k in 0..dim {
        if !excludes_zero(d.g[k]) {
            continue;
        }
        any_param = true;
        if let Some(reason) = smooth {
            return Decision::Split(reason);
        }
        if dim == 3 {
            let mut ok = true;
            for w in [lo[k], hi[k]] {
                let (mut a, mut b) = (lo, hi);
                a[k] = w;
                b[k] = w;
                if !face_ok(f, &g.ibox(a, b), k) {
                    ok = false;
                    break;
                }
            }
            if !ok {
                faces_failed = true;
                continue;
            }
        }
        // The sign⁺ convention and the edge isolation are blind to a zero set that
        // touches the domain boundary (a tangency, a corner): see `boundary_failure`.
        if let Some(d) = boundary_failure(f, g, c) {
            return d;
        }
        if !edges_isolated(f, g, lo, hi, p) {
            return Decision::Split("grazing intersection: roots on a box edge not isolated");
        }
        return Decision::Leaf(Verdict::param(k as u8));
    }
    if !any_param {
        // No partial excludes 0: the box may hold a singular point (∇f = 0).
        if (0..dim).all(|k| d.g[k].contains(0.0)) {
            return Decision::Split("possible singular point: 0 in □f and 0 in □∇f");
        }
        return Decision::Split("depth limit hit: no partial derivative excludes 0");
    }
    if faces_failed {
        return Decision::Split(
            "top/bottom face neither empty nor parameterizable (face tangent to the surface?)",
        );
    }
    Decision::Split("depth limit hit")
}

fn edges_isolated(
    f: &dyn Implicit,
    g: &Grid,
    lo: [u32; 3],
    hi: [u32; 3],
    p: &SnyderParams,
) -> bool {
    let iso = isolation(p);
    let steps = AtomicU64::new(0);
    for k in 0..g.dim {
        for m in 0..(1 << (g.dim - 1)) {
            let others: Vec<usize> = (0..g.dim).filter(|&j| j != k).collect();
            let mut a = lo;
            for (bit, &j) in others.iter().enumerate() {
                if m >> bit & 1 == 1 {
                    a[j] = hi[j];
                }
            }
            let mut b = a;
            b[k] = hi[k];
            let (pa, pb) = (g.point(a), g.point(b));
            let (sa, sb) = (point_sign(f, pa), point_sign(f, pb));
            if !sa.rigorous || !sb.rigorous {
                return false;
            }
            if iso.isolate(f, pa, sa.pos, pb, sb.pos, &steps).is_none() {
                return false;
            }
        }
    }
    true
}

/// Run Snyder; also returns the tree (in moved coordinates when the criterion asks for
/// generic position): [`crate::subdivision::engine::run_subdivision`].
pub use crate::subdivision::engine::run_subdivision as run_snyder;

/// Fig 1.7: on a tile parameterizable in u (□∂f/∂v ∌ 0), the crossings sorted by u pair
/// up consecutively. A crossing on the side u = u_min sorts before any other at the same
/// u, one on u = u_max after (the sign⁺ convention moves a root at a corner into the
/// edge where f < 0).
pub struct SnyderPairing;

impl Pairing for SnyderPairing {
    fn pair(&self, f: &dyn Implicit, tile: FaceTile) -> Vec<(usize, usize)> {
        let FaceTile {
            corners,
            normal_axis,
            cross,
        } = tile;
        let ib = [0, 1, 2].map(|k| {
            let lo = corners.iter().map(|c| c[k]).fold(f64::INFINITY, f64::min);
            let hi = corners
                .iter()
                .map(|c| c[k])
                .fold(f64::NEG_INFINITY, f64::max);
            inari::Interval::try_from((lo, hi)).unwrap_or(inari::Interval::ENTIRE)
        });
        let d = f.grad_interval(&ib);
        let inplane: Vec<usize> = (0..3).filter(|&j| j != normal_axis).collect();
        let sort_axis = if excludes_zero(d.g[inplane[1]]) {
            Some(inplane[0])
        } else if excludes_zero(d.g[inplane[0]]) {
            Some(inplane[1])
        } else {
            None
        };
        let Some(u) = sort_axis else {
            return PvPairing.pair(f, tile);
        };
        if cross.len() % 2 == 1 {
            return PvPairing.pair(f, tile);
        }
        let (umin, umax) = (ib[u].inf(), ib[u].sup());
        let rank = |side: usize| {
            let (a, b) = (corners[side], corners[(side + 1) % 4]);
            if a[u] == umin && b[u] == umin {
                0
            } else if a[u] == umax && b[u] == umax {
                2
            } else {
                1
            }
        };
        let mut order: Vec<usize> = (0..cross.len()).collect();
        order.sort_by(|&i, &j| {
            (cross[i].pos[u], rank(cross[i].side))
                .partial_cmp(&(cross[j].pos[u], rank(cross[j].side)))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        order.chunks(2).map(|c| (c[0], c[1])).collect()
    }
}
