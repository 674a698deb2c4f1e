//! The tree of boxes: cells and their integer grid, verdicts, the work budget, the
//! parallel subdivision driven by a criterion, and 2:1 balancing (§1.2.4).
use super::*;
use crate::implicit::{IBox, Implicit};
use crate::kernel::geom::Aabb;
use crate::mesher::Uncertified;
use inari::Interval;
use rayon::prelude::*;
use rustc_hash::FxHashSet as HashSet;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

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

pub fn unpack(k: u64) -> [u32; 3] {
    let m = (1u64 << 21) - 1;
    [
        (k & m) as u32,
        ((k >> 21) & m) as u32,
        ((k >> 42) & m) as u32,
    ]
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

/// Which criterion ended the subdivision of a leaf. A criterion names its own proofs
/// ([`Verdict::Proven`]), so adding a criterion does not change this type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Verdict {
    /// 0 ∉ □f: no zero in the box.
    Empty,
    /// The criterion `by` holds on the box; `axis`: the coordinate it singles out, if
    /// any (Snyder's Lemma 2 with □∂f/∂x_k ∌ 0: parameterizable in the other variables).
    Proven { by: &'static str, axis: Option<u8> },
    /// No criterion held before the depth limit; the reason.
    Failed(&'static str),
}

impl Verdict {
    /// Small Normal Variation ⟨□∇f, □∇f⟩ > 0 (eq 1.2), Plantinga–Vegter's criterion.
    pub const SNV: Verdict = Verdict::Proven {
        by: "SNV",
        axis: None,
    };
    /// Snyder's Lemma 2 with □∂f/∂x_k ∌ 0.
    pub const fn param(k: u8) -> Verdict {
        Verdict::Proven {
            by: "parameterizable",
            axis: Some(k),
        }
    }
    pub fn label(&self, dim: usize) -> String {
        let names = ["x", "y", "z"];
        match self {
            Verdict::Empty => "f != 0".into(),
            Verdict::Proven { by, axis: None } => by.to_string(),
            Verdict::Proven { by, axis: Some(k) } => {
                let others: Vec<&str> = (0..dim)
                    .filter(|&j| j != *k as usize)
                    .map(|j| names[j])
                    .collect();
                format!("{by} in {}", others.join(","))
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
    /// Stop when this instant has passed (`--time-limit`), less the time the assembly of
    /// what exists will take ([`ASSEMBLY_SECONDS_PER_ACTIVE_LEAF`]).
    pub deadline: Option<std::time::Instant>,
    /// Stop when the assembly of what exists would hold this much memory
    /// ([`MAX_SUBDIVISION_BYTES`] unless set with [`Budget::with_max_bytes`]).
    pub max_bytes: u64,
    used: AtomicU64,
    /// Leaves that are not proven empty: the ones the assembly tiles and meshes.
    active: AtomicU64,
    stopped: std::sync::atomic::AtomicBool,
    out_of_memory: std::sync::atomic::AtomicBool,
}

/// What the work after the subdivision (balancing, collecting the corners, assembling
/// the tiles of every leaf not proven empty, listing the failed ones) costs per leaf
/// not proven empty, in seconds of wall time; and per box of any kind. Measured on a
/// 2-thread AMD EPYC: the double sphere (x² + y² + z² − 1/4)², whose 391,000 such leaves
/// among 1.04 M boxes took 4.1 s after a subdivision of 0.3 s. The deadline reserves this
/// time: without it a `--time-limit 2` run made 8 M boxes in 2 s and then spent 80 s
/// and 7.9 GB assembling them.
pub const ASSEMBLY_SECONDS_PER_ACTIVE_LEAF: f64 = 10e-6;
pub const ASSEMBLY_SECONDS_PER_BOX: f64 = 0.3e-6;
/// The memory the same work holds per leaf not proven empty (its tiles and their point
/// lists, its failed region) and per box (the leaf or internal cell, its corners in
/// the point set): the double sphere peaked at 1.0 GB for 1.04 M boxes and 4.0 GB for
/// 4.2 M.
pub const ASSEMBLY_BYTES_PER_ACTIVE_LEAF: u64 = 2560;
pub const ASSEMBLY_BYTES_PER_BOX: u64 = 128;
/// The memory a subdivision may plan to use (the same 16 GiB as `certmesh delaunay`).
pub const MAX_SUBDIVISION_BYTES: u64 = 16 << 30;

/// Default box budget of the subdivision meshers: 10⁶ box tests (seconds
/// and under 1 GB on the catalog; every smooth catalog entry needs far fewer).
pub const DEFAULT_MAX_BOXES: u64 = 1_000_000;

/// The reason given to boxes left untested when the box budget ran out.
pub const BOX_BUDGET_REASON: &str = "box budget exhausted (raise --max-boxes)";
/// The reason given to boxes left untested when the time limit passed.
pub const TIME_LIMIT_REASON: &str = "time limit reached (raise --time-limit)";
/// The reason given to boxes left untested when the estimated memory of the output
/// reached its cap ([`MAX_SUBDIVISION_BYTES`] by default).
pub const MEMORY_LIMIT_REASON: &str =
    "box budget exhausted: the output would need more than 16 GiB (lower --max-boxes or --max-depth, or shrink the domain)";

impl Budget {
    pub fn new(max_boxes: u64, time_limit: Option<f64>) -> Budget {
        Budget {
            max_boxes,
            // A limit past what the clock can represent (1e19 s, 1e300 s) is no limit:
            // no deadline rather than an overflow.
            deadline: time_limit.and_then(|s| {
                let d = std::time::Duration::try_from_secs_f64(s).ok()?;
                std::time::Instant::now().checked_add(d)
            }),
            max_bytes: MAX_SUBDIVISION_BYTES,
            used: AtomicU64::new(0),
            active: AtomicU64::new(0),
            stopped: std::sync::atomic::AtomicBool::new(false),
            out_of_memory: std::sync::atomic::AtomicBool::new(false),
        }
    }
    /// The same budget with another memory cap (tests; a caller with less memory).
    pub fn with_max_bytes(mut self, bytes: u64) -> Budget {
        self.max_bytes = bytes;
        self
    }
    /// Count a leaf that is not proven empty (the assembly's work and memory).
    fn note_active(&self) {
        self.active.fetch_add(1, Relaxed);
    }
    /// The wall time and memory the assembly of what exists so far will take.
    fn assembly_estimate(&self, boxes: u64) -> (f64, u64) {
        let active = self.active.load(Relaxed);
        (
            active as f64 * ASSEMBLY_SECONDS_PER_ACTIVE_LEAF
                + boxes as f64 * ASSEMBLY_SECONDS_PER_BOX,
            active
                .saturating_mul(ASSEMBLY_BYTES_PER_ACTIVE_LEAF)
                .saturating_add(boxes.saturating_mul(ASSEMBLY_BYTES_PER_BOX)),
        )
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
        // Every 1024 boxes (the clock costs ~20 ns): the deadline, with the time the
        // assembly of the leaves made so far will take reserved before it, and the
        // memory that assembly will hold.
        if n % 1024 == 0 {
            let (seconds, bytes) = self.assembly_estimate(n);
            if bytes > self.max_bytes {
                self.out_of_memory.store(true, Relaxed);
                self.stopped.store(true, Relaxed);
            }
            if let Some(d) = self.deadline {
                let reserve = std::time::Duration::from_secs_f64(seconds.min(1e9));
                if std::time::Instant::now() + reserve > d {
                    self.stopped.store(true, Relaxed);
                }
            }
        }
        if self.stopped.load(Relaxed) {
            return Err(if self.out_of_memory.load(Relaxed) {
                MEMORY_LIMIT_REASON
            } else {
                TIME_LIMIT_REASON
            });
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
        points: HashSet::default(),
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
    let d = match lim.budget.take() {
        Err(reason) => Ok(Verdict::Failed(reason)),
        Ok(()) => match classify(grid, cell) {
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
        },
    };
    if matches!(d, Ok(v) if v != Verdict::Empty) {
        lim.budget.note_active();
    }
    d
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
        self.balance_with(false, &|g: &Grid, c: Cell, v: Verdict| {
            if excludes_zero(f.eval_interval(&g.cell_ibox(c))) {
                Verdict::Empty
            } else {
                v
            }
        });
    }

    /// 2:1 balancing with the criterion's own rule for the children of a split leaf
    /// (`child(grid, cell, parent verdict)`); `all`: split empty leaves too (a fully
    /// graded tree, every leaf within one level of each neighbour by a face, an edge
    /// or a corner), else only the leaves that are not empty (Plantinga–Vegter).
    pub fn balance_with(
        &mut self,
        all: bool,
        child: &(dyn Fn(&Grid, Cell, Verdict) -> Verdict + Sync),
    ) {
        let dim = self.grid.dim;
        loop {
            let internal = &self.internal;
            let grid = self.grid;
            let need: Vec<bool> = self
                .leaves
                .par_iter()
                .map(|l| {
                    (all || l.verdict != Verdict::Empty) && needs_split(&grid, internal, l.cell)
                })
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
                    l.cell.children(dim).into_iter().map(move |c| Leaf {
                        cell: c,
                        verdict: if l.verdict == Verdict::Empty {
                            Verdict::Empty
                        } else {
                            child(&grid, c, l.verdict)
                        },
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
                Verdict::Failed(r) => {
                    Some(Uncertified::new(self.grid.cell_aabb(l.cell), r.to_string()))
                }
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
