//! The one subdivision engine: a mesher of §1.2 is a [`Criterion`] (the paper's box
//! test, the root finder on box edges, the pairing rule of crossings on a face) run by
//! [`run_subdivision`] over the shared machinery (subdivide, balance, assemble, the
//! certificate). As in CGAL's surface mesher, the criterion is a separate object and the
//! variants are composed from small bases: Snyder ([`crate::subdivision::snyder`]) and
//! Plantinga–Vegter ([`crate::subdivision::plantinga_vegter`]) differ only in their
//! criterion; a new one (the Morse issue's, say) implements [`Criterion`] and gets the
//! engine, the limits, the budget, the statistics and a [`Mesher`] for free. Its leaves
//! carry [`Verdict::Proven`] with its own label: the engine's types do not change.
//!
//! Parameters follow spade's `RefinementParameters`: [`SubdivisionParams`] holds the
//! limits every subdivision mesher has (each default documented on its field) and the
//! criterion's own settings in `criterion`, with builder methods for both.
use crate::error::{Error, Result};
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;
use crate::mesher::check_input;
use crate::mesher::options::MesherOptions;
use crate::mesher::{Mesh, MeshOutput, Mesher, Progress};
use crate::subdivision::criteria::check_budget;
use crate::subdivision::{
    assemble, certificate, subdivide, tree_stats, Budget, Cell, Decision, GenericMotion, Grid,
    Pairing, RootFinder, Tree, Verdict, DEFAULT_MAX_BOXES, MAX_LEVEL,
};

/// Levels above the depth limit at which a box that f is not proven C¹ on stops being
/// bisected and is reported uncertified with the reason (see [`run_subdivision`]).
pub const NONSMOOTH_MARGIN: u32 = 4;
/// The level below which [`NONSMOOTH_MARGIN`] never stops a box (a depth limit of 8
/// or less is not affected).
pub const NONSMOOTH_MIN_LEVEL: u32 = 8;

/// The parameters of a subdivision mesher: the limits shared by all of them and the
/// criterion's own settings.
#[derive(Clone, Debug)]
pub struct SubdivisionParams<K> {
    /// Boxes are split at least to this level (default 2) before a criterion may stop
    /// them (boxes with 0 ∉ □f stop earlier). Only refines the output.
    pub min_depth: u32,
    /// Depth limit (the criterion's default: see [`Criterion::default_max_depth`]); a box
    /// still undecided there is reported uncertified. At most [`MAX_LEVEL`].
    pub max_depth: u32,
    /// Tolerance of the crossing location on box edges, relative to the edge length
    /// (default 1e-9); the topology never depends on it.
    pub tolerance: f64,
    /// Box tests allowed (default [`DEFAULT_MAX_BOXES`]; `--max-boxes`). A run that
    /// spends them stops, reports `refinement_complete: false` and certifies nothing.
    pub max_boxes: u64,
    /// Wall-clock limit of the subdivision in seconds (default none here; built from
    /// options, `--time-limit` or [`crate::mesher::options::DEFAULT_TIME_LIMIT`]).
    pub time_limit: Option<f64>,
    /// The criterion's own settings.
    pub criterion: K,
}

impl<K: Criterion> SubdivisionParams<K> {
    /// The documented defaults for functions of dimension `dim` (2 or 3).
    pub fn new(dim: usize) -> Self {
        SubdivisionParams {
            min_depth: 2,
            max_depth: K::default_max_depth(dim),
            tolerance: 1e-9,
            max_boxes: DEFAULT_MAX_BOXES,
            time_limit: None,
            criterion: K::default(),
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
    pub fn with_tolerance(mut self, t: f64) -> Self {
        self.tolerance = t;
        self
    }
    /// From the shared options (`max_depth`, `min_depth`, `tolerance`, `max_boxes`,
    /// `time_limit`) and the criterion's (`--set` keys it lists in
    /// [`Criterion::SETTINGS`], and whatever else it reads in
    /// [`Criterion::apply_options`]).
    pub fn from_options(o: &MesherOptions, dim: usize) -> Result<Self> {
        o.check_keys(K::ALGO, K::SETTINGS)?;
        let mut p = Self::new(dim);
        K::apply_options(&mut p, o, dim)?;
        if let Some(d) = o.max_depth {
            p.max_depth = d;
        }
        if let Some(d) = o.min_depth {
            p.min_depth = d;
        }
        if let Some(t) = o.tolerance {
            p.tolerance = t;
        }
        if let Some(n) = o.max_boxes {
            p.max_boxes = n;
        }
        p.time_limit = Some(o.time_limit_or_default());
        p.validate()?;
        Ok(p)
    }
    /// Check the limits and the criterion's settings.
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
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(Error::Param(format!(
                "tolerance {} must lie in (0, 1)",
                self.tolerance
            )));
        }
        check_budget(self.max_boxes, self.time_limit)?;
        self.criterion.validate()
    }
}

/// What a subdivision mesher of §1.2 adds to the engine: its box test, its root finder,
/// its pairing rule. Everything else (the tree, balancing, assembly, budget, statistics,
/// certificate, generic position) is the engine's.
pub trait Criterion: Clone + std::fmt::Debug + Default + Send + Sync + Sized + 'static {
    /// The `--algo` name.
    const ALGO: &'static str;
    /// The theorem a certified run invokes (named in the claim).
    const THEOREM: &'static str;
    /// The `--set` keys it reads.
    const SETTINGS: &'static [&'static str];
    /// Should neighbouring leaves differ by at most one level (Plantinga–Vegter's
    /// balancing, §1.2.4)?
    const BALANCED: bool;
    /// The default depth limit for functions of dimension `dim`.
    fn default_max_depth(dim: usize) -> u32;
    /// Read the criterion's options (called before the shared limits are applied, so
    /// that an explicit `--max-depth` wins).
    fn apply_options(p: &mut SubdivisionParams<Self>, o: &MesherOptions, dim: usize) -> Result<()>;
    /// Check the criterion's own settings.
    fn validate(&self) -> Result<()>;
    /// The box test: a leaf with its verdict, or split with the reason it failed.
    fn classify(p: &SubdivisionParams<Self>, f: &dyn Implicit, g: &Grid, c: Cell) -> Decision;
    /// The crossings of f on an elementary edge.
    fn root_finder(p: &SubdivisionParams<Self>) -> Box<dyn RootFinder>;
    /// The pairing of crossings on a face tile.
    fn pairing(&self) -> &dyn Pairing;
    /// Mesh in generic position (a rotation and translation of the grid first)?
    fn generic_position(&self) -> bool {
        false
    }
    /// Settings worth reporting in the run's statistics.
    fn add_stats(&self, _stats: &mut serde_json::Map<String, serde_json::Value>) {}
}

/// Run the subdivision mesher of criterion `K` on f inside `domain`; also returns the
/// tree (in moved coordinates when the criterion asks for generic position).
pub fn run_subdivision<K: Criterion>(
    f: &dyn Implicit,
    domain: &Aabb,
    p: &SubdivisionParams<K>,
    dim: usize,
    progress: &dyn Progress,
) -> Result<(Tree, MeshOutput)> {
    check_input(f, domain, dim, K::ALGO)?;
    p.validate()?;
    let motion = p
        .criterion
        .generic_position()
        .then(|| GenericMotion::new(domain, dim));
    let moved;
    let (g, dom): (&dyn Implicit, Aabb) = match &motion {
        Some(m) => {
            moved = m.apply(f);
            (&moved, m.domain)
        }
        None => (f, *domain),
    };
    let grid = Grid {
        domain: dom,
        dim,
        depth: p.max_depth,
    };
    let budget = Budget::new(p.max_boxes, p.time_limit);
    budget.check_min_depth(dim, p.min_depth)?;
    progress.start("subdivision", 0);
    // A box that f is not proven C¹ on (a pole, a kink, the edge of f's domain) is
    // bisected only to `NONSMOOTH_MARGIN` levels above the depth limit: no criterion
    // certifies it, and localising a pole plane to the depth limit costs 4ᵏ boxes (a
    // pole plane through the default domain spent the whole box budget, 11 s, and was
    // reported as "box budget exhausted" instead of by its cause). Never before level
    // `NONSMOOTH_MIN_LEVEL`: refining near a pole can still prove boxes empty (beside
    // the pole of 1/x, 1/x dominates and □f excludes 0). A function without rigorous
    // interval methods (a mesh's signed distance, a Python callback) has no regularity
    // to ask (it would read as "not continuous" everywhere) and is split as before.
    let nonsmooth_stop = g.is_rigorous();
    let nonsmooth_level = p
        .max_depth
        .saturating_sub(NONSMOOTH_MARGIN)
        .max(NONSMOOTH_MIN_LEVEL);
    let mut tree =
        subdivide(
            grid,
            p.min_depth,
            p.max_depth,
            &budget,
            &|gr: &Grid, c| match K::classify(p, g, gr, c) {
                Decision::Split(why) if nonsmooth_stop && c.level as u32 >= nonsmooth_level => {
                    match g.regularity(&gr.cell_ibox(c)).c1_failure() {
                        Some(not_c1) => Decision::Leaf(Verdict::Failed(not_c1)),
                        None => Decision::Split(why),
                    }
                }
                d => d,
            },
        );
    if K::BALANCED {
        tree.balance(g);
    }
    tree.collect_points();
    progress.inc(tree.leaves.len() as u64);
    progress.finish();
    let finder = K::root_finder(p);
    let asm = assemble(g, &tree, finder.as_ref(), p.criterion.pairing());
    let mut stats = crate::mesher::stats_map(&tree_stats(&tree, &asm));
    p.criterion.add_stats(&mut stats);
    let mut regions = tree.failures();
    regions.extend(asm.uncertain.iter().cloned());
    let mut mesh = if dim == 2 {
        Mesh::Curve(asm.curve.unwrap_or_default())
    } else {
        Mesh::Surface(asm.surface.unwrap_or_default())
    };
    if let Some(m) = &motion {
        for r in &mut regions {
            r.region = m.map_box(&r.region);
        }
        // The proof is about f = 0 inside the rotated box; the claim is about the
        // domain: f = 0 must be proven absent from the rest of the box, or the run is
        // uncertified there (found by an adversarial test: a sphere outside the domain
        // but inside the rotated box was meshed and certified as "inside the domain").
        regions.extend(m.outside_domain(f, &tree, domain, budget.deadline));
        match &mut mesh {
            Mesh::Curve(c) => {
                for v in &mut c.vertices {
                    let q = m.map([v[0], v[1], dom.min[2]]);
                    *v = [q[0], q[1]];
                }
            }
            Mesh::Surface(s) => {
                for v in &mut s.vertices {
                    *v = m.map(*v);
                }
            }
            Mesh::Volume { .. } => {}
        }
    }
    // The claim is about the domain, also in generic position (never the moved box
    // `dom`, whose coordinates are the rotated frame's).
    let certificate = certificate(K::THEOREM, &tree, dim, domain, motion.is_some(), regions);
    Ok((
        tree,
        MeshOutput {
            mesh,
            certificate,
            stats,
            angles: None,
        },
    ))
}

/// The subdivision mesher of criterion `K` in dimension `D` (2: curves, quadtree; 3:
/// surfaces, octree).
#[derive(Clone, Debug)]
pub struct SubdivisionMesher<K, const D: usize> {
    pub params: SubdivisionParams<K>,
}

impl<K: Criterion, const D: usize> Default for SubdivisionMesher<K, D> {
    fn default() -> Self {
        SubdivisionMesher {
            params: SubdivisionParams::new(D),
        }
    }
}

impl<K: Criterion, const D: usize> SubdivisionMesher<K, D> {
    pub fn new(params: SubdivisionParams<K>) -> Self {
        SubdivisionMesher { params }
    }
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Ok(SubdivisionMesher {
            params: SubdivisionParams::from_options(o, D)?,
        })
    }
}

impl<K: Criterion, const D: usize> Mesher for SubdivisionMesher<K, D> {
    fn name(&self) -> &'static str {
        K::ALGO
    }
    fn dim(&self) -> usize {
        D
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        Ok(run_subdivision(f, domain, &self.params, D, progress)?.1)
    }
}
