//! Shared machinery of the cube-based certified meshers of §1.2 of the chapter
//! (Snyder §1.2.3, Plantinga–Vegter §1.2.4): a quadtree/octree of boxes over the domain,
//! interval criteria, 2:1 balancing, the sign of f at grid points, interval root
//! isolation on box edges, and the assembly of the mesh from per-face crossing patterns.
//!
//! # Geometry
//! The domain box is the root cell; a cell of level `l` has integer index `idx` and, in
//! units of the finest level `D = depth`, occupies `[idx << (D-l), (idx+1) << (D-l)]`.
//! Grid points are stored as integer coordinates; [`Grid::point`] maps them to space by a
//! fixed monotone formula, so neighbouring cells share corners exactly.
//!
//! # Zero values
//! Every sign is taken with the convention **f == 0 counts as positive** (`sign⁺`), i.e.
//! the meshers mesh f + ε = 0 for an infinitesimal ε > 0, which is isotopic to f = 0
//! where ∇f ≠ 0. The sign of f at a grid point is decided by interval evaluation at the
//! point; a point whose enclosure straddles 0 without being exactly [0, 0] is reported as
//! an uncertified region (its float sign is used).
//!
//! # Assembling the mesh
//! The boundary of each non-empty leaf is cut into *tiles*: its faces, split recursively
//! wherever a smaller neighbour has a corner at the face centre (the "transmission" of the
//! smaller boxes' pattern to the larger box, chapter §1.2.3 last paragraphs, and the
//! balanced subdivision of §1.2.4). Tile edges are split at every grid point lying on them
//! (elementary segments), so both boxes sharing a tile see the same points, signs and
//! crossings. Crossings on each tile are paired by an algorithm-specific [`Pairing`] rule
//! that depends only on the tile (never on the box it is seen from) — this is what makes
//! the face choices consistent across neighbouring boxes (Fig 1.10). The directed
//! segments (f > 0 on the left seen from outside the box) close into cycles on the box
//! boundary; each cycle is triangulated as a fan (3D). In 2D the single tile is the box.
use crate::kernel::geom::{lerp, Aabb};
use crate::implicit::{IBox, Implicit};
use crate::mesh::{Curve2, TriMesh};
use crate::mesher::Uncertified;
use inari::Interval;
use rayon::prelude::*;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

pub mod plantinga_vegter;
pub mod snyder;

/// The deepest level a tree may have (21 bits per packed grid coordinate).
pub const MAX_LEVEL: u32 = 20;

/// A cell of the tree: a level and an integer index per axis (z index 0 in 2D).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Cell {
    pub level: u8,
    pub idx: [u32; 3],
}

impl Cell {
    pub const ROOT: Cell = Cell {
        level: 0,
        idx: [0, 0, 0],
    };
    /// A unique key (level in the top bits).
    pub fn key(&self) -> u64 {
        ((self.level as u64) << 58)
            | (self.idx[0] as u64)
            | ((self.idx[1] as u64) << 21)
            | ((self.idx[2] as u64) << 42)
    }
    /// The 4 (2D) or 8 (3D) children.
    pub fn children(&self, dim: usize) -> Vec<Cell> {
        let nz: u32 = if dim == 3 { 2 } else { 1 };
        let mut out = Vec::with_capacity(4 * nz as usize);
        for dz in 0..nz {
            for dy in 0..2 {
                for dx in 0..2 {
                    out.push(Cell {
                        level: self.level + 1,
                        idx: [
                            2 * self.idx[0] + dx,
                            2 * self.idx[1] + dy,
                            2 * self.idx[2] + dz,
                        ],
                    });
                }
            }
        }
        out
    }
    /// Lower corner and side length in finest-level units.
    pub fn span(&self, depth: u32) -> ([u32; 3], u32) {
        let s = depth - self.level as u32;
        (self.idx.map(|i| i << s), 1u32 << s)
    }
}

/// Pack a grid point (finest-level integer coordinates) into a key. Along an
/// axis-parallel segment the smaller key is the smaller coordinate.
#[inline]
pub fn pkey(p: [u32; 3]) -> u64 {
    (p[0] as u64) | ((p[1] as u64) << 21) | ((p[2] as u64) << 42)
}

/// The domain, its dimension and the finest level.
#[derive(Clone, Copy, Debug)]
pub struct Grid {
    pub domain: Aabb,
    pub dim: usize,
    pub depth: u32,
}

impl Grid {
    /// A point of the finest grid in space. Monotone in each coordinate, so cells tile
    /// the domain exactly.
    #[inline]
    pub fn point(&self, p: [u32; 3]) -> [f64; 3] {
        let n = (1u64 << self.depth) as f64;
        let mut out = [0.0; 3];
        for k in 0..3 {
            if k == 2 && self.dim == 2 {
                out[k] = self.domain.min[2];
                continue;
            }
            let t = p[k] as f64 / n;
            out[k] = if p[k] as f64 == n {
                self.domain.max[k]
            } else {
                self.domain.min[k] + (self.domain.max[k] - self.domain.min[k]) * t
            };
        }
        out
    }
    /// The box spanned by two grid points.
    pub fn ibox(&self, lo: [u32; 3], hi: [u32; 3]) -> IBox {
        let a = self.point(lo);
        let b = self.point(hi);
        [0, 1, 2].map(|k| Interval::try_from((a[k], b[k])).unwrap_or(Interval::ENTIRE))
    }
    pub fn cell_lo_hi(&self, c: Cell) -> ([u32; 3], [u32; 3]) {
        let (lo, s) = c.span(self.depth);
        let mut hi = lo.map(|v| v + s);
        if self.dim == 2 {
            hi[2] = 0;
        }
        (lo, hi)
    }
    pub fn cell_ibox(&self, c: Cell) -> IBox {
        let (lo, hi) = self.cell_lo_hi(c);
        self.ibox(lo, hi)
    }
    pub fn cell_aabb(&self, c: Cell) -> Aabb {
        let (lo, hi) = self.cell_lo_hi(c);
        Aabb {
            min: self.point(lo),
            max: self.point(hi),
        }
    }
}

/// Which criterion ended the subdivision of a leaf.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Verdict {
    /// 0 ∉ □f: no zero in the box.
    Empty,
    /// Small Normal Variation ⟨□∇f, □∇f⟩ > 0 (eq 1.2).
    Snv,
    /// Snyder's Lemma 2 with □∂f/∂x_k ∌ 0: parameterizable in the other variables.
    Param(u8),
    /// No criterion held before the depth limit; the reason.
    Failed(&'static str),
}

impl Verdict {
    pub fn label(&self, dim: usize) -> String {
        let names = ["x", "y", "z"];
        match self {
            Verdict::Empty => "f != 0".into(),
            Verdict::Snv => "SNV".into(),
            Verdict::Param(k) => {
                let others: Vec<&str> = (0..dim)
                    .filter(|&j| j != *k as usize)
                    .map(|j| names[j])
                    .collect();
                format!("parameterizable in {}", others.join(","))
            }
            Verdict::Failed(r) => format!("uncertified: {r}"),
        }
    }
    pub fn certified(&self) -> bool {
        !matches!(self, Verdict::Failed(_))
    }
}

/// The outcome of testing one box.
#[derive(Clone, Copy, Debug)]
pub enum Decision {
    Leaf(Verdict),
    /// Split; the reason is reported if the depth limit stops the splitting.
    Split(&'static str),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Leaf {
    pub cell: Cell,
    pub verdict: Verdict,
}

/// A finished subdivision: the leaves, the set of split (internal) cells and the set of
/// all leaf corners.
pub struct Tree {
    pub grid: Grid,
    pub leaves: Vec<Leaf>,
    pub internal: HashSet<u64>,
    pub points: HashSet<u64>,
    /// Splits made by balancing.
    pub balance_splits: usize,
    /// False when the budget stopped the subdivision (spade's `refinement_complete`):
    /// the boxes it did not test are `Failed` leaves with the budget's reason.
    pub refinement_complete: bool,
}

/// The work a subdivision may do: a number of box tests and a wall-clock deadline.
/// A box reached after the budget is spent becomes a `Failed` leaf with the budget's
/// reason, so a stopped run returns what it has and says why
/// ([`Tree::refinement_complete`] is false).
#[derive(Debug)]
pub struct Budget {
    /// Box tests allowed (`--max-boxes`).
    pub max_boxes: u64,
    /// Stop when this instant has passed (`--time-limit`).
    pub deadline: Option<std::time::Instant>,
    used: AtomicU64,
    stopped: std::sync::atomic::AtomicBool,
}

/// Default box budget of the subdivision meshers: about 10⁷ box tests (a few seconds
/// and under 1 GB on the catalog; every smooth catalog entry needs far fewer).
pub const DEFAULT_MAX_BOXES: u64 = 10_000_000;

/// The reason given to boxes left untested when the box budget ran out.
pub const BOX_BUDGET_REASON: &str = "box budget exhausted (raise --max-boxes)";
/// The reason given to boxes left untested when the time limit passed.
pub const TIME_LIMIT_REASON: &str = "time limit reached (raise --time-limit)";

impl Budget {
    pub fn new(max_boxes: u64, time_limit: Option<f64>) -> Budget {
        Budget {
            max_boxes,
            deadline: time_limit
                .map(|s| std::time::Instant::now() + std::time::Duration::from_secs_f64(s)),
            used: AtomicU64::new(0),
            stopped: std::sync::atomic::AtomicBool::new(false),
        }
    }
    /// No limit (tests and library callers that bound the depth themselves).
    pub fn unlimited() -> Budget {
        Budget::new(u64::MAX, None)
    }
    /// Take one box test; `Err(reason)` once the budget is spent.
    fn take(&self) -> std::result::Result<(), &'static str> {
        let n = self.used.fetch_add(1, Relaxed);
        if n >= self.max_boxes {
            self.stopped.store(true, Relaxed);
            return Err(BOX_BUDGET_REASON);
        }
        if let Some(d) = self.deadline {
            // Checking the clock costs ~20 ns: do it every 1024 boxes.
            if n % 1024 == 0 && std::time::Instant::now() > d {
                self.stopped.store(true, Relaxed);
            }
            if self.stopped.load(Relaxed) {
                return Err(TIME_LIMIT_REASON);
            }
        }
        Ok(())
    }
    /// Box tests used so far.
    pub fn used(&self) -> u64 {
        self.used.load(Relaxed).min(self.max_boxes)
    }
    /// Did the budget stop the run?
    pub fn exhausted(&self) -> bool {
        self.stopped.load(Relaxed)
    }
    /// Refuse, before any work, a subdivision whose forced levels alone exceed the
    /// budget: `min_depth` splits every box not proven empty, 2^(dim·min_depth) boxes.
    pub fn check_min_depth(&self, dim: usize, min_depth: u32) -> crate::Result<()> {
        let boxes = 2f64.powi((dim as u32 * min_depth) as i32);
        if boxes > self.max_boxes as f64 {
            return Err(crate::Error::TooLarge(format!(
                "min_depth {min_depth} forces up to {boxes:.3e} boxes in {dim}D, more than the \
                 box budget {} (lower --min-depth or raise --max-boxes)",
                self.max_boxes
            )));
        }
        Ok(())
    }
}

/// Subdivide from the root, testing each box with `classify` (called from rayon
/// threads). Boxes at level < `min_depth` that are not proven empty are split anyway;
/// boxes at `max_depth` still undecided become `Failed` leaves, and so do the boxes
/// reached after `budget` is spent.
pub fn subdivide<C>(
    grid: Grid,
    min_depth: u32,
    max_depth: u32,
    budget: &Budget,
    classify: &C,
) -> Tree
where
    C: Fn(&Grid, Cell) -> Decision + Sync,
{
    let lim = Limits {
        min_depth,
        max_depth,
        budget,
    };
    let (leaves, internal) = rec(&grid, Cell::ROOT, &lim, classify);
    let mut t = Tree {
        grid,
        leaves,
        internal: internal.iter().map(|c| c.key()).collect(),
        points: HashSet::new(),
        balance_splits: 0,
        refinement_complete: !budget.exhausted(),
    };
    t.leaves.sort_unstable_by_key(|l| l.cell);
    t
}

struct Limits<'a> {
    min_depth: u32,
    max_depth: u32,
    budget: &'a Budget,
}

fn rec<C>(grid: &Grid, cell: Cell, lim: &Limits, classify: &C) -> (Vec<Leaf>, Vec<Cell>)
where
    C: Fn(&Grid, Cell) -> Decision + Sync,
{
    if cell.level >= 4 {
        let mut l = Vec::new();
        let mut i = Vec::new();
        rec_seq(grid, cell, lim, classify, &mut l, &mut i);
        return (l, i);
    }
    match decide(grid, cell, lim, classify) {
        Ok(v) => (vec![Leaf { cell, verdict: v }], Vec::new()),
        Err(()) => {
            let parts: Vec<(Vec<Leaf>, Vec<Cell>)> = cell
                .children(grid.dim)
                .into_par_iter()
                .map(|c| rec(grid, c, lim, classify))
                .collect();
            let mut l = Vec::new();
            let mut i = vec![cell];
            for (a, b) in parts {
                l.extend(a);
                i.extend(b);
            }
            (l, i)
        }
    }
}

fn rec_seq<C>(
    grid: &Grid,
    cell: Cell,
    lim: &Limits,
    classify: &C,
    leaves: &mut Vec<Leaf>,
    internal: &mut Vec<Cell>,
) where
    C: Fn(&Grid, Cell) -> Decision + Sync,
{
    match decide(grid, cell, lim, classify) {
        Ok(v) => leaves.push(Leaf { cell, verdict: v }),
        Err(()) => {
            internal.push(cell);
            for c in cell.children(grid.dim) {
                rec_seq(grid, c, lim, classify, leaves, internal);
            }
        }
    }
}

/// `Ok(verdict)` for a leaf, `Err(())` to split.
fn decide<C>(
    grid: &Grid,
    cell: Cell,
    lim: &Limits,
    classify: &C,
) -> std::result::Result<Verdict, ()>
where
    C: Fn(&Grid, Cell) -> Decision + Sync,
{
    if let Err(reason) = lim.budget.take() {
        return Ok(Verdict::Failed(reason));
    }
    match classify(grid, cell) {
        Decision::Leaf(Verdict::Empty) => Ok(Verdict::Empty),
        Decision::Leaf(v) if (cell.level as u32) >= lim.min_depth => Ok(v),
        Decision::Leaf(_) => Err(()),
        Decision::Split(reason) => {
            if cell.level as u32 >= lim.max_depth {
                Ok(Verdict::Failed(reason))
            } else {
                Err(())
            }
        }
    }
}

/// Is the box free of zeros of f (0 ∉ □f)?
#[inline]
pub fn excludes_zero(i: Interval) -> bool {
    i.inf() > 0.0 || i.sup() < 0.0
}

/// Is the box free of zeros of f + ε (the sign⁺ convention): □f ⊂ [0, ∞) or (-∞, 0)?
#[inline]
pub fn no_zero_plus(i: Interval) -> bool {
    i.inf() >= 0.0 || i.sup() < 0.0
}

/// An enclosure of f over a box: the natural interval extension intersected with the
/// mean-value form f(c) + Σ □∂_k f(B)·(B_k − c_k). The mean-value form's width is O(h²)
/// near points where the partials vanish, where the natural extension of a rotated
/// formula (generic position) only reaches O(h) — without it Snyder's face test never
/// proves a face near a tangency empty (the dependency problem). Returns it with the
/// gradient enclosure.
pub fn enclose(f: &dyn Implicit, b: &IBox) -> (Interval, [Interval; 3]) {
    let d = f.grad_interval(b);
    (mean_value(f, b, &d), d.g)
}

/// The natural enclosure `d.v` intersected with the mean-value form built from the
/// gradient enclosure `d.g` (see [`enclose`]).
pub fn mean_value(f: &dyn Implicit, b: &IBox, d: &crate::implicit::Dual<Interval>) -> Interval {
    let c = [0, 1, 2].map(|k| b[k].mid());
    let cb = c.map(|x| Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE));
    let mut mv = f.eval_interval(&cb);
    for k in 0..3 {
        if b[k].wid() > 0.0 {
            mv = mv + d.g[k] * (b[k] - cb[k]);
        }
    }
    let v = d.v.intersection(mv);
    // The mean-value form is an enclosure only for a continuous f whose derivative
    // enclosures are slopes (C¹, or Lipschitz through |·|, min, max): across a pole or
    // a gap of the domain it may exclude values f takes. Ask only when it tightens.
    if v.is_empty() || v == d.v || f.regularity(b) < crate::implicit::Regularity::Continuous {
        d.v
    } else {
        v
    }
}

/// The interval scalar product ⟨□∇f, □∇f⟩ over the first `dim` components (eq 1.2):
/// each factor varies independently, so its lower bound is exactly the minimum of
/// ⟨u, v⟩ over u, v in the gradient box.
pub fn snv_dot(g: &[Interval; 3], dim: usize) -> Interval {
    let mut s = Interval::try_from((0.0, 0.0)).unwrap();
    for gk in g.iter().take(dim) {
        s = s + *gk * *gk;
    }
    s
}

/// How the maximal angle between two gradients over a box is bounded (Exercise 9).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AngleBound {
    /// cos α ≥ a / b for ⟨□∇f, □∇f⟩ = [a, b] (the chapter's crude bound).
    Crude,
    /// The exact maximal angle over the gradient box: attained at a pair of its vertices
    /// once all vertex pairs make an angle < 90° (each vertex cone is convex), evaluated
    /// with interval arithmetic.
    Sharp,
}

/// A rigorous lower bound on cos α over all pairs of gradients in the box `g`
/// (`None` when nothing positive can be proven).
pub fn cos_lower_bound(g: &[Interval; 3], dim: usize, how: AngleBound) -> Option<f64> {
    match how {
        AngleBound::Crude => {
            let d = snv_dot(g, dim);
            if d.inf() > 0.0 {
                Some((Interval::try_from((d.inf(), d.inf())).ok()? / d.sup_iv()).inf())
            } else {
                None
            }
        }
        AngleBound::Sharp => {
            if !(0..dim).any(|k| excludes_zero(g[k])) {
                return None;
            }
            let nv = 1usize << dim;
            let vert = |m: usize| -> [Interval; 3] {
                let mut v = [Interval::try_from((0.0, 0.0)).unwrap(); 3];
                for k in 0..dim {
                    let x = if m >> k & 1 == 0 {
                        g[k].inf()
                    } else {
                        g[k].sup()
                    };
                    v[k] = Interval::try_from((x, x)).unwrap();
                }
                v
            };
            let mut best = f64::INFINITY;
            for a in 0..nv {
                for b in a + 1..nv {
                    let (u, v) = (vert(a), vert(b));
                    let mut d = Interval::try_from((0.0, 0.0)).unwrap();
                    let mut nu = d;
                    let mut nvv = d;
                    for k in 0..dim {
                        d = d + u[k] * v[k];
                        nu = nu + u[k] * u[k];
                        nvv = nvv + v[k] * v[k];
                    }
                    let c = d / (nu.sqrt() * nvv.sqrt());
                    if c.is_empty() || c.inf().is_nan() {
                        return None;
                    }
                    best = best.min(c.inf());
                }
            }
            if best > 0.0 {
                Some(best.min(1.0))
            } else {
                None
            }
        }
    }
}

trait SupIv {
    fn sup_iv(&self) -> Interval;
}
impl SupIv for Interval {
    fn sup_iv(&self) -> Interval {
        Interval::try_from((self.sup(), self.sup())).unwrap_or(Interval::ENTIRE)
    }
}

impl Tree {
    /// Record every leaf corner (the vertices of the subdivision).
    pub fn collect_points(&mut self) {
        let g = self.grid;
        let pts: Vec<u64> = self
            .leaves
            .par_iter()
            .flat_map_iter(|l| corners(&g, l.cell).into_iter().map(pkey))
            .collect();
        self.points = pts.into_iter().collect();
    }

    /// 2:1 balancing (§1.2.4): split every non-empty leaf touching (by a face, edge or
    /// corner) a leaf more than one level finer, until none does. Children of a split
    /// box are re-tested for emptiness only: the SNV condition carries over to sub-boxes
    /// (interval evaluation is inclusion monotone).
    pub fn balance(&mut self, f: &dyn Implicit) {
        let dim = self.grid.dim;
        loop {
            let internal = &self.internal;
            let grid = self.grid;
            let need: Vec<bool> = self
                .leaves
                .par_iter()
                .map(|l| l.verdict != Verdict::Empty && needs_split(&grid, internal, l.cell))
                .collect();
            if !need.iter().any(|&b| b) {
                break;
            }
            let mut kept = Vec::with_capacity(self.leaves.len());
            let mut split = Vec::new();
            for (l, n) in self.leaves.iter().zip(need) {
                if n {
                    split.push(*l);
                } else {
                    kept.push(*l);
                }
            }
            self.balance_splits += split.len();
            let new: Vec<Leaf> = split
                .par_iter()
                .flat_map_iter(|l| {
                    l.cell.children(dim).into_iter().map(move |c| {
                        let v = if excludes_zero(f.eval_interval(&grid.cell_ibox(c))) {
                            Verdict::Empty
                        } else {
                            l.verdict
                        };
                        Leaf {
                            cell: c,
                            verdict: v,
                        }
                    })
                })
                .collect();
            for l in &split {
                self.internal.insert(l.cell.key());
            }
            kept.extend(new);
            self.leaves = kept;
        }
        self.leaves.sort_unstable_by_key(|l| l.cell);
    }

    /// Leaves by level.
    pub fn by_depth(&self) -> BTreeMap<u8, usize> {
        let mut m = BTreeMap::new();
        for l in &self.leaves {
            *m.entry(l.cell.level).or_insert(0) += 1;
        }
        m
    }

    /// Boxes (leaves and internal, i.e. every box the criteria were evaluated on) by
    /// level: the work per depth of a run.
    pub fn boxes_by_depth(&self) -> BTreeMap<u8, usize> {
        let mut m = self.by_depth();
        for &k in &self.internal {
            // The level sits in the top bits of the key (`Cell::key`).
            *m.entry((k >> 58) as u8).or_insert(0) += 1;
        }
        m
    }

    /// Leaves by verdict label.
    pub fn by_verdict(&self) -> BTreeMap<String, usize> {
        let mut m = BTreeMap::new();
        for l in &self.leaves {
            *m.entry(l.verdict.label(self.grid.dim)).or_insert(0) += 1;
        }
        m
    }

    /// Failed leaves as uncertified regions.
    pub fn failures(&self) -> Vec<Uncertified> {
        self.leaves
            .iter()
            .filter_map(|l| match l.verdict {
                Verdict::Failed(r) => Some(Uncertified {
                    region: self.grid.cell_aabb(l.cell),
                    reason: r.to_string(),
                }),
                _ => None,
            })
            .collect()
    }
}

fn corners(g: &Grid, c: Cell) -> Vec<[u32; 3]> {
    let (lo, hi) = g.cell_lo_hi(c);
    let nz = if g.dim == 3 { 2 } else { 1 };
    let mut v = Vec::with_capacity(8);
    for z in 0..nz {
        for y in 0..2 {
            for x in 0..2 {
                v.push([
                    if x == 0 { lo[0] } else { hi[0] },
                    if y == 0 { lo[1] } else { hi[1] },
                    if z == 0 { lo[2] } else { hi[2] },
                ]);
            }
        }
    }
    v
}

/// Does leaf `c` touch an internal cell of level `c.level + 1` (i.e. a leaf at least two
/// levels finer)?
fn needs_split(g: &Grid, internal: &HashSet<u64>, c: Cell) -> bool {
    let n = 1i64 << c.level;
    let zr: &[i64] = if g.dim == 3 { &[-1, 0, 1] } else { &[0] };
    for &dz in zr {
        for dy in [-1i64, 0, 1] {
            for dx in [-1i64, 0, 1] {
                if dx == 0 && dy == 0 && dz == 0 {
                    continue;
                }
                let d = [dx, dy, dz];
                let mut ni = [0u32; 3];
                let mut ok = true;
                for k in 0..3 {
                    let v = c.idx[k] as i64 + d[k];
                    if v < 0 || v >= n {
                        ok = false;
                    }
                    ni[k] = v.max(0) as u32;
                }
                if !ok {
                    continue;
                }
                let nb = Cell {
                    level: c.level,
                    idx: ni,
                };
                if !internal.contains(&nb.key()) {
                    continue;
                }
                // Children of the neighbour that touch c.
                for ch in nb.children(g.dim) {
                    let touches = (0..g.dim).all(|k| {
                        let b = ch.idx[k] - 2 * nb.idx[k];
                        match d[k] {
                            1 => b == 0,
                            -1 => b == 1,
                            _ => true,
                        }
                    });
                    if touches && internal.contains(&ch.key()) {
                        return true;
                    }
                }
            }
        }
    }
    false
}

/// The sign of f at a grid point, decided by interval arithmetic.
#[derive(Clone, Copy, Debug)]
pub struct PointSign {
    /// sign⁺: true for f >= 0.
    pub pos: bool,
    /// f at the point (float evaluation).
    pub value: f64,
    /// The enclosure decided the sign (or f is exactly 0).
    pub rigorous: bool,
}

pub fn point_sign(f: &dyn Implicit, p: [f64; 3]) -> PointSign {
    let b = p.map(|x| Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE));
    let i = f.eval_interval(&b);
    let value = f.eval(p);
    // An empty enclosure means f is undefined at p (1/0): no sign is proven.
    if i.is_empty() {
        PointSign {
            pos: value >= 0.0,
            value,
            rigorous: false,
        }
    } else if i.inf() >= 0.0 {
        PointSign {
            pos: true,
            value,
            rigorous: true,
        }
    } else if i.sup() < 0.0 {
        PointSign {
            pos: false,
            value,
            rigorous: true,
        }
    } else {
        PointSign {
            pos: value >= 0.0,
            value,
            rigorous: false,
        }
    }
}

/// An elementary segment of the subdivision: two grid points joined along an axis with
/// no grid point strictly between them. `a < b` by key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Seg {
    pub a: u64,
    pub b: u64,
}

fn unpack(k: u64) -> [u32; 3] {
    let m = (1u64 << 21) - 1;
    [
        (k & m) as u32,
        ((k >> 21) & m) as u32,
        ((k >> 42) & m) as u32,
    ]
}

/// The crossings found on one elementary segment, ordered from `a` to `b`.
#[derive(Clone, Debug, Default)]
pub struct SegRoots {
    pub pos: Vec<[f64; 3]>,
    /// False when interval root isolation failed (grazing): the count is then only the
    /// parity of the end signs.
    pub isolated: bool,
}

/// How the crossings on a segment are found.
pub trait RootFinder: Sync {
    /// Crossings of f + ε = 0 on the segment from `pa` to `pb` (in that order), given the
    /// end signs. Adds root-isolation steps to `steps`.
    fn roots(
        &self,
        f: &dyn Implicit,
        pa: [f64; 3],
        sa: PointSign,
        pb: [f64; 3],
        sb: PointSign,
        steps: &AtomicU64,
    ) -> SegRoots;
}

/// How the crossings on a tile are paired.
pub trait Pairing: Sync {
    /// `cross` lists the tile's crossings in counter-clockwise order (seen from outside,
    /// i.e. against the tile normal), each with its position, the side of the tile it
    /// lies on (0..4, sides in the same order) and the sign⁺ just after it. `corners` are
    /// the tile's corners in the same order. Returns pairs of indices into `cross`.
    fn pair(
        &self,
        f: &dyn Implicit,
        corners: &[[f64; 3]; 4],
        normal_axis: usize,
        cross: &[TileCrossing],
    ) -> Vec<(usize, usize)>;
}

#[derive(Clone, Copy, Debug)]
pub struct TileCrossing {
    pub pos: [f64; 3],
    pub side: usize,
    pub after_pos: bool,
}

/// The non-crossing pairing of crossings in cyclic order that cuts off the arcs of one
/// sign (`cut_negative`: each negative arc c_i → c_{i+1} becomes a chord, so the positive
/// region of the tile is joined).
pub fn cut_arcs(cross: &[TileCrossing], cut_negative: bool) -> Vec<(usize, usize)> {
    let n = cross.len();
    let mut out = Vec::with_capacity(n / 2);
    for i in 0..n {
        if cross[i].after_pos != cut_negative {
            out.push((i, (i + 1) % n));
        }
    }
    out
}

/// A crossing vertex: an elementary segment and the root's rank on it.
pub type CrossKey = (Seg, u32);

/// What a leaf produced: directed segments (2D) or boundary cycles (3D), by crossing key.
struct LeafOut {
    segs: Vec<(CrossKey, CrossKey)>,
}

/// The assembled result.
pub struct Assembled {
    pub curve: Option<Curve2>,
    pub surface: Option<TriMesh>,
    pub uncertain: Vec<Uncertified>,
    pub root_steps: u64,
    pub crossings: usize,
    pub segments: usize,
}

/// The grid points on the segment from `a` to `b` (inclusive, in order): recursively,
/// a midpoint is present iff it is a leaf corner.
fn seg_points(points: &HashSet<u64>, a: [u32; 3], b: [u32; 3], out: &mut Vec<[u32; 3]>) {
    // `out` already holds `a`.
    let k = (0..3).find(|&k| a[k] != b[k]);
    if let Some(k) = k {
        let (lo, hi) = (a[k].min(b[k]), a[k].max(b[k]));
        if hi - lo >= 2 {
            let mut m = a;
            m[k] = (lo + hi) / 2;
            if points.contains(&pkey(m)) {
                seg_points(points, a, m, out);
                seg_points(points, m, b, out);
                return;
            }
        }
    }
    out.push(b);
}

/// A tile: a square in a plane normal to `axis`, corners counter-clockwise seen from
/// outside the leaf, and its boundary points.
struct Tile {
    corners: [[u32; 3]; 4],
    axis: usize,
}

fn leaf_tiles(tree: &Tree, c: Cell) -> Vec<Tile> {
    let g = &tree.grid;
    let (lo, hi) = g.cell_lo_hi(c);
    if g.dim == 2 {
        return vec![Tile {
            corners: [
                [lo[0], lo[1], 0],
                [hi[0], lo[1], 0],
                [hi[0], hi[1], 0],
                [lo[0], hi[1], 0],
            ],
            axis: 2,
        }];
    }
    let mut out = Vec::new();
    for k in 0..3 {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        for side in 0..2 {
            let w = if side == 0 { lo[k] } else { hi[k] };
            let mk = |a: u32, b: u32| {
                let mut p = [0u32; 3];
                p[k] = w;
                p[u] = a;
                p[v] = b;
                p
            };
            // CCW about +e_k is (u,v) order; the outward normal of the low face is -e_k.
            let sq = if side == 1 {
                [
                    mk(lo[u], lo[v]),
                    mk(hi[u], lo[v]),
                    mk(hi[u], hi[v]),
                    mk(lo[u], hi[v]),
                ]
            } else {
                [
                    mk(lo[u], lo[v]),
                    mk(lo[u], hi[v]),
                    mk(hi[u], hi[v]),
                    mk(hi[u], lo[v]),
                ]
            };
            split_tile(&tree.points, sq, k, &mut out);
        }
    }
    out
}

/// Split a face square where a finer neighbour has a corner at its centre.
fn split_tile(points: &HashSet<u64>, sq: [[u32; 3]; 4], axis: usize, out: &mut Vec<Tile>) {
    let mid = |a: [u32; 3], b: [u32; 3]| [0, 1, 2].map(|k| (a[k] + b[k]) / 2);
    let c = mid(sq[0], sq[2]);
    let big = (0..3).any(|k| sq[0][k].abs_diff(sq[2][k]) >= 2);
    if big && points.contains(&pkey(c)) {
        let m01 = mid(sq[0], sq[1]);
        let m12 = mid(sq[1], sq[2]);
        let m23 = mid(sq[2], sq[3]);
        let m30 = mid(sq[3], sq[0]);
        // The four quarters keep the parent's orientation.
        split_tile(points, [sq[0], m01, c, m30], axis, out);
        split_tile(points, [m01, sq[1], m12, c], axis, out);
        split_tile(points, [c, m12, sq[2], m23], axis, out);
        split_tile(points, [m30, c, m23, sq[3]], axis, out);
    } else {
        out.push(Tile { corners: sq, axis });
    }
}

/// Build the mesh from a finished tree. Every non-empty leaf is meshed (failed leaves
/// too, best effort: the run is then uncertified anyway).
pub fn assemble(
    f: &dyn Implicit,
    tree: &Tree,
    finder: &dyn RootFinder,
    pairing: &dyn Pairing,
) -> Assembled {
    let g = tree.grid;
    let active: Vec<Cell> = tree
        .leaves
        .iter()
        .filter(|l| l.verdict != Verdict::Empty)
        .map(|l| l.cell)
        .collect();
    // 1. Tiles and their boundary point lists.
    type TileData = (Tile, Vec<[u32; 3]>, [usize; 4]);
    let tiles: Vec<Vec<TileData>> = active
        .par_iter()
        .map(|&c| {
            leaf_tiles(tree, c)
                .into_iter()
                .map(|t| {
                    let mut pts = vec![t.corners[0]];
                    let mut starts = [0usize; 4];
                    for s in 0..4 {
                        starts[s] = pts.len() - 1;
                        seg_points(&tree.points, t.corners[s], t.corners[(s + 1) % 4], &mut pts);
                    }
                    pts.pop(); // the closing corner repeats the first
                    (t, pts, starts)
                })
                .collect()
        })
        .collect();
    // 2. Unique points and segments.
    let mut pset: HashSet<u64> = HashSet::new();
    let mut sset: HashSet<Seg> = HashSet::new();
    for lt in &tiles {
        for (_, pts, _) in lt {
            for i in 0..pts.len() {
                let a = pkey(pts[i]);
                let b = pkey(pts[(i + 1) % pts.len()]);
                pset.insert(a);
                sset.insert(Seg {
                    a: a.min(b),
                    b: a.max(b),
                });
            }
        }
    }
    let plist: Vec<u64> = pset.into_iter().collect();
    let signs: HashMap<u64, PointSign> = plist
        .par_iter()
        .map(|&k| (k, point_sign(f, g.point(unpack(k)))))
        .collect();
    let mut uncertain: Vec<Uncertified> = Vec::new();
    for (k, s) in &signs {
        if !s.rigorous {
            let p = g.point(unpack(*k));
            uncertain.push(Uncertified {
                region: Aabb { min: p, max: p },
                reason: "sign of f at a grid point not decided by interval arithmetic".into(),
            });
        }
    }
    // 3. Crossings per segment.
    let steps = AtomicU64::new(0);
    let slist: Vec<Seg> = sset.into_iter().collect();
    let roots: HashMap<Seg, SegRoots> = slist
        .par_iter()
        .map(|&s| {
            let (pa, pb) = (g.point(unpack(s.a)), g.point(unpack(s.b)));
            (s, finder.roots(f, pa, signs[&s.a], pb, signs[&s.b], &steps))
        })
        .collect();
    for (s, r) in &roots {
        if !r.isolated {
            let (pa, pb) = (g.point(unpack(s.a)), g.point(unpack(s.b)));
            uncertain.push(Uncertified {
                region: Aabb::of_points(&[pa, pb]).unwrap_or(g.domain),
                reason: "grazing intersection: roots on a box edge not isolated".into(),
            });
        }
    }
    let bad_tiles = AtomicU64::new(0);
    // 4. Pair the crossings on each tile and collect directed segments per leaf.
    let outs: Vec<LeafOut> = tiles
        .par_iter()
        .map(|lt| {
            let mut segs = Vec::new();
            for (t, pts, starts) in lt {
                let n = pts.len();
                let mut cross: Vec<TileCrossing> = Vec::new();
                let mut keys: Vec<CrossKey> = Vec::new();
                let mut side = 0usize;
                for i in 0..n {
                    while side < 3 && i >= starts[side + 1] {
                        side += 1;
                    }
                    let (ka, kb) = (pkey(pts[i]), pkey(pts[(i + 1) % n]));
                    let s = Seg {
                        a: ka.min(kb),
                        b: ka.max(kb),
                    };
                    let r = &roots[&s];
                    let m = r.pos.len();
                    let mut after = signs[&ka].pos;
                    for j in 0..m {
                        let (rank, pos) = if ka < kb {
                            (j, r.pos[j])
                        } else {
                            (m - 1 - j, r.pos[m - 1 - j])
                        };
                        after = !after;
                        cross.push(TileCrossing {
                            pos,
                            side,
                            after_pos: after,
                        });
                        keys.push((s, rank as u32));
                    }
                }
                if cross.is_empty() {
                    continue;
                }
                let corners = t.corners.map(|p| g.point(p));
                let pairs = pairing.pair(f, &corners, t.axis, &cross);
                // A chord must join a crossing where f turns negative to one where it
                // turns positive; otherwise the rule's premise failed on this tile.
                let consistent = pairs.len() * 2 == cross.len()
                    && pairs
                        .iter()
                        .all(|&(i, j)| cross[i].after_pos != cross[j].after_pos);
                let pairs = if consistent {
                    pairs
                } else {
                    bad_tiles.fetch_add(1, Relaxed);
                    cut_arcs(&cross, true)
                };
                for (i, j) in pairs {
                    // Direct the chord so that f > 0 lies on its left seen from outside:
                    // the region left of i→j contains the arc just after j.
                    if cross[j].after_pos {
                        segs.push((keys[i], keys[j]));
                    } else {
                        segs.push((keys[j], keys[i]));
                    }
                }
            }
            LeafOut { segs }
        })
        .collect();
    // 5. Vertex numbering.
    let mut index: HashMap<CrossKey, u32> = HashMap::new();
    let mut verts: Vec<[f64; 3]> = Vec::new();
    let mut ncross = 0;
    let mut sorted_roots: Vec<(&Seg, &SegRoots)> = roots.iter().collect();
    sorted_roots.sort_unstable_by_key(|(s, _)| **s);
    for (s, r) in sorted_roots {
        for (j, p) in r.pos.iter().enumerate() {
            index.insert((*s, j as u32), verts.len() as u32);
            verts.push(*p);
            ncross += 1;
        }
    }
    let root_steps = steps.load(Relaxed);
    let nbad = bad_tiles.load(Relaxed);
    if nbad > 0 {
        uncertain.push(Uncertified {
            region: g.domain,
            reason: format!(
                "{nbad} face tile(s) whose crossing pattern contradicts the connection rule"
            ),
        });
    }
    let nseg: usize = outs.iter().map(|o| o.segs.len()).sum();
    if g.dim == 2 {
        // Each leaf segment is a curve segment; store with f < 0 on the left
        // (counter-clockwise around the solid {f <= 0}).
        let mut segments = Vec::new();
        for o in &outs {
            for (a, b) in &o.segs {
                segments.push([index[b], index[a]]);
            }
        }
        let curve = Curve2 {
            vertices: verts.iter().map(|p| [p[0], p[1]]).collect(),
            segments,
        };
        return Assembled {
            curve: Some(curve),
            surface: None,
            uncertain,
            root_steps,
            crossings: ncross,
            segments: nseg,
        };
    }
    // 3D: close the directed segments of each leaf into cycles and fan them.
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let mut bad = 0usize;
    for (o, &c) in outs.iter().zip(&active) {
        let mut next: HashMap<u32, u32> = HashMap::new();
        let mut ok = true;
        for (a, b) in &o.segs {
            if next.insert(index[a], index[b]).is_some() {
                ok = false;
            }
        }
        let mut seen: HashSet<u32> = HashSet::new();
        let mut starts: Vec<u32> = next.keys().copied().collect();
        starts.sort_unstable();
        for s in starts {
            if seen.contains(&s) {
                continue;
            }
            let mut cyc = vec![s];
            seen.insert(s);
            let mut v = s;
            loop {
                match next.get(&v) {
                    Some(&w) if w == s => break,
                    Some(&w) if !seen.contains(&w) => {
                        seen.insert(w);
                        cyc.push(w);
                        v = w;
                    }
                    _ => {
                        ok = false;
                        break;
                    }
                }
            }
            match cyc.len() {
                0 | 1 => ok = false,
                // A two-gon (a → b on one tile, b → a on another: a cap cutting one edge
                // twice, Snyder): the disk collapses to the edge ab, which the two
                // neighbouring boxes already use in opposite directions.
                2 => {}
                3 => tris.push([cyc[0], cyc[1], cyc[2]]),
                n => {
                    let mut cen = [0.0; 3];
                    for &i in &cyc {
                        for k in 0..3 {
                            cen[k] += verts[i as usize][k] / n as f64;
                        }
                    }
                    let ci = verts.len() as u32;
                    verts.push(cen);
                    for i in 0..n {
                        tris.push([ci, cyc[i], cyc[(i + 1) % n]]);
                    }
                }
            }
        }
        if !ok {
            bad += 1;
            uncertain.push(Uncertified {
                region: g.cell_aabb(c),
                reason: "boundary crossing pattern of the box does not close into simple cycles"
                    .into(),
            });
        }
    }
    let _ = bad;
    Assembled {
        curve: None,
        surface: Some(TriMesh::new(verts, tris)),
        uncertain,
        root_steps,
        crossings: ncross,
        segments: nseg,
    }
}

/// Locate the crossing of f + ε = 0 between `pa` (sign `sa`) and `pb` by bisection on
/// sign⁺ to `tol` (relative), or by linear interpolation of the end values.
pub fn locate(
    f: &dyn Implicit,
    pa: [f64; 3],
    sa: bool,
    pb: [f64; 3],
    tol: f64,
    linear: Option<(f64, f64)>,
) -> [f64; 3] {
    if let Some((fa, fb)) = linear {
        let t = if fa == fb {
            0.5
        } else {
            (fa / (fa - fb)).clamp(0.0, 1.0)
        };
        return lerp(pa, pb, t);
    }
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while hi - lo > tol {
        let m = 0.5 * (lo + hi);
        if m <= lo || m >= hi {
            break;
        }
        if (f.eval(lerp(pa, pb, m)) >= 0.0) == sa {
            lo = m;
        } else {
            hi = m;
        }
    }
    lerp(pa, pb, 0.5 * (lo + hi))
}

/// Plantinga–Vegter crossings: one per sign change (a vertex on every edge whose end
/// signs differ, §1.2.4).
pub struct SignChange {
    pub tol: f64,
    pub linear: bool,
}

impl RootFinder for SignChange {
    fn roots(
        &self,
        f: &dyn Implicit,
        pa: [f64; 3],
        sa: PointSign,
        pb: [f64; 3],
        sb: PointSign,
        _steps: &AtomicU64,
    ) -> SegRoots {
        let pos = if sa.pos != sb.pos {
            vec![locate(
                f,
                pa,
                sa.pos,
                pb,
                self.tol,
                self.linear.then_some((sa.value, sb.value)),
            )]
        } else {
            Vec::new()
        };
        SegRoots {
            pos,
            isolated: true,
        }
    }
}

/// Snyder's interval root isolation on an edge (§1.2.3): bisect until, on each piece,
/// 0 ∉ □f (no root) or 0 ∉ □f' (at most one root, present iff the end signs differ).
/// Grazing roots (f = f' = 0) make it fail at `max_depth` bisections.
pub struct IntervalIsolation {
    pub max_depth: u32,
    pub tol: f64,
}

impl IntervalIsolation {
    /// The isolating pieces `[t0, t1]` of the segment, or `None` if isolation failed.
    pub fn isolate(
        &self,
        f: &dyn Implicit,
        pa: [f64; 3],
        sa: bool,
        pb: [f64; 3],
        sb: bool,
        steps: &AtomicU64,
    ) -> Option<Vec<(f64, f64, bool)>> {
        let k = (0..3).find(|&k| pa[k] != pb[k])?;
        let mut out = Vec::new();
        if self.rec(
            f,
            pa,
            pb,
            k,
            (0.0, sa),
            (1.0, sb),
            self.max_depth,
            steps,
            &mut out,
        ) {
            Some(out)
        } else {
            None
        }
    }
    #[allow(clippy::too_many_arguments)]
    fn rec(
        &self,
        f: &dyn Implicit,
        pa: [f64; 3],
        pb: [f64; 3],
        k: usize,
        (t0, s0): (f64, bool),
        (t1, s1): (f64, bool),
        depth: u32,
        steps: &AtomicU64,
        out: &mut Vec<(f64, f64, bool)>,
    ) -> bool {
        steps.fetch_add(1, Relaxed);
        let a = lerp(pa, pb, t0);
        let b = lerp(pa, pb, t1);
        let ib = [0, 1, 2].map(|j| {
            Interval::try_from((a[j].min(b[j]), a[j].max(b[j]))).unwrap_or(Interval::ENTIRE)
        });
        let (v, dg) = enclose(f, &ib);
        let d = crate::implicit::Dual { v, g: dg };
        if no_zero_plus(d.v) {
            return s0 == s1;
        }
        if excludes_zero(d.g[k]) {
            if s0 != s1 {
                out.push((t0, t1, s0));
            }
            return true;
        }
        if depth == 0 {
            return false;
        }
        let tm = 0.5 * (t0 + t1);
        let ps = point_sign(f, lerp(pa, pb, tm));
        if !ps.rigorous {
            return false;
        }
        self.rec(f, pa, pb, k, (t0, s0), (tm, ps.pos), depth - 1, steps, out)
            && self.rec(f, pa, pb, k, (tm, ps.pos), (t1, s1), depth - 1, steps, out)
    }
}

impl RootFinder for IntervalIsolation {
    fn roots(
        &self,
        f: &dyn Implicit,
        pa: [f64; 3],
        sa: PointSign,
        pb: [f64; 3],
        sb: PointSign,
        steps: &AtomicU64,
    ) -> SegRoots {
        match self.isolate(f, pa, sa.pos, pb, sb.pos, steps) {
            Some(pieces) => SegRoots {
                pos: pieces
                    .into_iter()
                    .map(|(t0, t1, s0)| {
                        let a = lerp(pa, pb, t0);
                        let b = lerp(pa, pb, t1);
                        locate(f, a, s0, b, self.tol / (t1 - t0).max(1e-300), None)
                    })
                    .collect(),
                isolated: true,
            },
            None => SegRoots {
                pos: if sa.pos != sb.pos {
                    vec![locate(f, pa, sa.pos, pb, self.tol, None)]
                } else {
                    Vec::new()
                },
                isolated: false,
            },
        }
    }
}

/// Statistics shared by both meshers, as JSON.
pub fn tree_stats(tree: &Tree, a: &Assembled) -> serde_json::Map<String, serde_json::Value> {
    use serde_json::json;
    let mut m = serde_json::Map::new();
    m.insert("leaves".into(), json!(tree.leaves.len()));
    m.insert("internal_boxes".into(), json!(tree.internal.len()));
    m.insert(
        "boxes".into(),
        json!(tree.leaves.len() + tree.internal.len()),
    );
    m.insert(
        "leaves_by_depth".into(),
        json!(tree
            .by_depth()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect::<BTreeMap<String, usize>>()),
    );
    m.insert(
        "boxes_by_depth".into(),
        json!(tree
            .boxes_by_depth()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect::<BTreeMap<String, usize>>()),
    );
    m.insert("leaves_by_criterion".into(), json!(tree.by_verdict()));
    m.insert("balance_splits".into(), json!(tree.balance_splits));
    m.insert(
        "refinement_complete".into(),
        json!(tree.refinement_complete),
    );
    m.insert("root_isolation_steps".into(), json!(a.root_steps));
    m.insert("crossings".into(), json!(a.crossings));
    let failed = tree.failures();
    m.insert("uncertified_boxes".into(), json!(failed.len()));
    m.insert(
        "uncertified_regions".into(),
        json!(failed.len() + a.uncertain.len()),
    );
    m
}

/// Cells touching a point set, for tests and figures: the leaves with their boxes and
/// verdicts.
pub fn leaf_boxes(tree: &Tree) -> Vec<(Aabb, Verdict)> {
    tree.leaves
        .iter()
        .map(|l| (tree.grid.cell_aabb(l.cell), l.verdict))
        .collect()
}

/// The "generic position" remedy of §1.2.3: a fixed rotation R and translation t, so that
/// no grid plane is tangent to the surface at a dyadic point. The meshers mesh
/// g(p) = f(R p + t) over the box `domain` of p-space that covers the original domain and
/// map each output vertex p back to R p + t (a rigid motion: orientation is kept).
#[derive(Clone, Copy, Debug)]
pub struct GenericMotion {
    pub rot: [[f64; 3]; 3],
    pub shift: [f64; 3],
    /// The box meshed in the moved coordinates (covers R⁻¹(domain − t)).
    pub domain: Aabb,
}

impl GenericMotion {
    /// Rotation by 0.0837 rad (about 4.8°) about the axis (1, 2, 3)/√14 (3D) or about z
    /// (2D), translation by (0.01234567, 0.02345679, 0.01357913) times the domain size:
    /// arbitrary, non-dyadic, fixed so runs are reproducible.
    pub fn new(domain: &Aabb, dim: usize) -> Self {
        let th: f64 = 0.0837;
        let (c, s) = (th.cos(), th.sin());
        let rot = if dim == 2 {
            [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
        } else {
            let n = 14f64.sqrt();
            let (x, y, z) = (1.0 / n, 2.0 / n, 3.0 / n);
            let t = 1.0 - c;
            [
                [c + x * x * t, x * y * t - z * s, x * z * t + y * s],
                [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
                [z * x * t - y * s, z * y * t + x * s, c + z * z * t],
            ]
        };
        let size = domain.size();
        let mut shift = [
            0.01234567 * size[0],
            0.02345679 * size[1],
            0.01357913 * size[2],
        ];
        if dim == 2 {
            shift[2] = 0.0;
        }
        // Cover the domain: the preimage of its corners under q = R p + t.
        let mut pts = Vec::new();
        for m in 0..8 {
            let q = [0, 1, 2].map(|k| {
                if m >> k & 1 == 0 {
                    domain.min[k]
                } else {
                    domain.max[k]
                }
            });
            let d = [0, 1, 2].map(|k| q[k] - shift[k]);
            // Rᵀ d
            pts.push([0, 1, 2].map(|j| rot[0][j] * d[0] + rot[1][j] * d[1] + rot[2][j] * d[2]));
        }
        let mut dom = Aabb::of_points(&pts).unwrap_or(*domain);
        // Grow the box unevenly: a box symmetric about R⁻¹(centre − t) would put its
        // level-1 grid corner exactly on the domain centre again.
        let ds = dom.size();
        for k in 0..3 {
            dom.min[k] -= 0.0173 * ds[k];
            dom.max[k] += 0.0411 * ds[k];
        }
        if dim == 2 {
            dom.min[2] = domain.min[2];
            dom.max[2] = domain.min[2];
        }
        GenericMotion {
            rot,
            shift,
            domain: dom,
        }
    }
    /// The moved oracle g(p) = f(R p + t).
    pub fn apply<'a>(&self, f: &'a dyn Implicit) -> crate::implicit::Transformed<'a> {
        crate::implicit::Transformed {
            inner: f,
            rot: self.rot,
            shift: self.shift,
        }
    }
    /// Map a vertex of the moved mesh back: R p + t.
    pub fn map(&self, p: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|i| {
            self.rot[i][0] * p[0] + self.rot[i][1] * p[1] + self.rot[i][2] * p[2] + self.shift[i]
        })
    }
    /// Map a box of the moved coordinates back (its bounding box).
    pub fn map_box(&self, b: &Aabb) -> Aabb {
        let mut pts = Vec::new();
        for m in 0..8 {
            let q = [0, 1, 2].map(|k| if m >> k & 1 == 0 { b.min[k] } else { b.max[k] });
            pts.push(self.map(q));
        }
        Aabb::of_points(&pts).unwrap_or(*b)
    }
}
