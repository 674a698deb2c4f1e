//! Boissonnat–Cohen-Steiner–Vegter: piecewise-linear interpolation of f (the chapter
//! "Meshing of Surfaces", §1.5.2, Theorem 8, Figs. 1.23–1.24): `--algo bcsv`.
//!
//! **What is built.** Two versions of T. *Adaptive* (`--set octree=true`; [`octree`]): the
//! chapter's octree, refined by a BCSV criterion run by the one subdivision engine
//! (excluded where 0 ∉ □f; elsewhere split to the attempt's minimum level and on until
//! proven free of critical points), 2:1 balanced, cut into conforming tetrahedra (Kuhn
//! where a leaf has no hanging vertex, else a cone from its centre); attempts at
//! minimum level 2, 3, … up to log2 `--resolution`. *Uniform* (the default):
//! the Kuhn (Freudenthal) triangulation of a uniform n³ grid of the domain (6
//! tetrahedra per cube), cubes excluded by an octree over the grid (a block with
//! 0 ∉ □f at once; a single cube also by up to 64 octant sub-proofs); attempts at
//! n = 4, 8, 16, … up to `--resolution` (default 64). In both, W is the union of the
//! boxes not excluded, grown by repair rounds until it is a PL 3-manifold. f̂ is the
//! linear interpolation of values at the vertices of W: f's proven sign on ∂W, f's
//! midpoint elsewhere (any nonzero value at an interior vertex whose sign is
//! undecided). Ŝ = f̂⁻¹(0) is extracted exactly (marching tetrahedra on f̂).
//!
//! **What is proven per attempt** (papers/meshing-of-surfaces/bcsv.md states and proves
//! Theorem B from exactly these):
//! * (E) S ∩ D ⊂ W: every cube outside W has 0 ∉ □f with f continuous on it.
//! * (1) f ≠ 0 on ∂W: a face of ∂W is a face of a cube outside W or lies on ∂D, where
//!   0 ∉ □f is checked (else the attempt fails: S may meet ∂D).
//! * (2) no critical point of f in W: every W cube is proven C^∞ (regularity flags)
//!   with 0 ∉ □∂f/∂x_k for some k, on each octant piece.
//! * (M) W is a PL 3-manifold: every vertex link of its Kuhn complex is a 2-sphere or a
//!   2-disc ([`check_manifold`]); where not, the cubes around the vertex are added.
//! * (3) W collapses onto Ŝ after subdivision: W is cut by Ŝ into the convex cells
//!   tet ∩ {f̂ ≥ 0}, tet ∩ {f̂ ≤ 0} with their faces (a polyhedral complex in which Ŝ is
//!   a subcomplex); a greedy sequence of elementary collapses (remove a cell τ ∉ Ŝ with
//!   exactly one coface σ, and σ) is searched, recorded and replayed by an independent
//!   checker ([`replay`]). A greedy failure proves nothing: the next attempt refines.
//! * (χ) the certified χ(S) of the Morse census ([`crate::morse::certified_chi`]) equals
//!   χ(Ŝ) ([`chi_of_s`], exact); if not, the next attempt refines.
//!
//! **Certificate.** With all of them, S and Ŝ are isotopic (Theorem B; it replaces
//! Theorem 8's premises on the critical points of f and f̂, which concern irrational
//! points and cannot be checked as stated, by the certified χ(S)): claim `Isotopic`.
//! With all but (χ): **W-certified**, never isotopic (conditions (1)–(3) do not give
//! isotopy by themselves; bcsv.md has the example). Otherwise nothing is certified and
//! the output is the finest grid's marching tetrahedra.
use crate::error::{Error, Result};
use crate::implicit::critical::linalg::{excludes_zero, pt, sign};
use crate::implicit::{IBox, Implicit, Regularity};
use crate::kernel::geom::Aabb;
use crate::mesh::TriMesh;
use crate::mesher::options::MesherOptions;
use crate::mesher::{check_input, Certificate, Claim, Mesh, MeshOutput, Mesher, Progress};
use crate::morse::octree::{self, Octree};
use crate::subdivision::{Verdict, DEFAULT_MAX_BOXES};
use inari::Interval;
use serde::Serialize;
use std::collections::{HashMap, HashSet};

/// The mesher.
#[derive(Clone, Debug)]
pub struct Bcsv {
    /// Uniform version: the finest grid (cells per axis) tried (default 64,
    /// `--resolution`). Adaptive version: the finest minimum level tried is
    /// log2 of it.
    pub max_resolution: usize,
    /// Box budget of the Morse census giving the certified χ(S) (default 20 000 for
    /// ∇f = 0, five times that for the height on S; `--set census-boxes=N`).
    pub census_boxes: usize,
    /// The adaptive octree (2:1 balanced, conforming tetrahedra; [`octree`]) instead of
    /// the uniform Kuhn grid (`--set octree=false|true`).
    pub octree: bool,
    /// Adaptive version: the depth limit of the octree (default 12, `--max-depth`).
    pub max_depth: u32,
    /// Adaptive version: box tests per attempt (default 10⁶, `--max-boxes`).
    pub max_boxes: u64,
    /// Wall-clock limit in seconds from the start (none here; `--time-limit` or its
    /// default from options): no attempt (nor an adaptive attempt's local round)
    /// starts after it, an adaptive attempt's octree stops at it, and so does the work
    /// after the octree or grid (the excluded leaves' signs, each repair round, the
    /// manifold check, condition (2) on repair leaves, condition (3)'s vertex values
    /// and cut complex; checked every 1,024 items), before the collapse search and
    /// before its replay. The census, the octree's balancing, one collapse search and
    /// the uncertified fallback run whole. Before these checks a round ran whole once
    /// its octree was built (26 s at a 10 s limit on a torus with a sphere in its
    /// tube; genus 5 at a 1 s limit, about 4 s; now 1.04 s).
    pub time_limit: Option<f64>,
}

/// Whether `--algo bcsv` is adaptive unless told (`--set octree=`). Uniform: the
/// adaptive version certifies every smooth catalog surface at default settings (the
/// uniform one needs `--resolution 256` for two-spheres and thin-torus), but its
/// failed local tries make it up to 100× slower (tanglecube, release build, quiet
/// machine: 65 s against 0.65 s; bcsv.md).
pub const OCTREE_DEFAULT: bool = false;

impl Bcsv {
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        o.check_keys("bcsv", &["census-boxes", "octree"])?;
        let max_resolution = o.resolution.unwrap_or(64);
        let census_boxes = o.get::<usize>("census-boxes")?.unwrap_or(20_000);
        if census_boxes == 0 {
            return Err(Error::Param(
                "bcsv: --set census-boxes must be at least 1".into(),
            ));
        }
        if !(4..=256).contains(&max_resolution) {
            return Err(Error::Param(format!(
                "bcsv: --resolution {max_resolution} must lie in 4..=256"
            )));
        }
        let octree = o.get::<bool>("octree")?.unwrap_or(OCTREE_DEFAULT);
        let max_depth = o.max_depth.unwrap_or(12);
        if !(2..=16).contains(&max_depth) {
            return Err(Error::Param(format!(
                "bcsv: --max-depth {max_depth} must lie in 2..=16"
            )));
        }
        let max_boxes = o.max_boxes.unwrap_or(DEFAULT_MAX_BOXES);
        if max_boxes == 0 {
            return Err(Error::Param("bcsv: --max-boxes must be at least 1".into()));
        }
        Ok(Bcsv {
            max_resolution,
            census_boxes,
            octree,
            max_depth,
            max_boxes,
            time_limit: Some(o.time_limit_or_default()),
        })
    }
}

/// A vertex of the cut complex: a grid vertex, or the zero of f̂ on a grid edge.
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq, PartialOrd, Ord)]
pub enum VKey {
    Grid(u32),
    Cut(u32, u32),
}

fn cut(a: u32, b: u32) -> VKey {
    VKey::Cut(a.min(b), a.max(b))
}

#[derive(Clone, Debug, Hash, PartialEq, Eq)]
enum CKey {
    V(VKey),
    E(VKey, VKey),
    P(Vec<VKey>),
    T(u32, u8, i8),
}

/// One cell of the cut complex.
#[derive(Clone, Debug, Serialize)]
pub struct Cell {
    pub dim: u8,
    /// Its faces of dimension `dim − 1`.
    pub faces: Vec<u32>,
    /// A cell of Ŝ.
    pub in_s: bool,
}

/// The polyhedral complex W cut by Ŝ.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Complex {
    pub cells: Vec<Cell>,
}

#[derive(Default)]
struct Builder {
    ids: HashMap<CKey, u32>,
    cx: Complex,
}

impl Builder {
    fn add(&mut self, k: CKey, dim: u8, faces: impl FnOnce(&mut Self) -> Vec<u32>) -> u32 {
        if let Some(&i) = self.ids.get(&k) {
            return i;
        }
        let faces = faces(self);
        let i = self.cx.cells.len() as u32;
        self.cx.cells.push(Cell {
            dim,
            faces,
            in_s: false,
        });
        self.ids.insert(k, i);
        i
    }
    fn vertex(&mut self, v: VKey) -> u32 {
        self.add(CKey::V(v), 0, |_| Vec::new())
    }
    fn edge(&mut self, a: VKey, b: VKey) -> u32 {
        let (a, b) = (a.min(b), a.max(b));
        self.add(CKey::E(a, b), 1, |s| vec![s.vertex(a), s.vertex(b)])
    }
    /// A polygon given in cyclic order.
    fn polygon(&mut self, cyc: &[VKey]) -> u32 {
        let mut key = cyc.to_vec();
        key.sort();
        let cyc = cyc.to_vec();
        self.add(CKey::P(key), 2, move |s| {
            (0..cyc.len())
                .map(|i| s.edge(cyc[i], cyc[(i + 1) % cyc.len()]))
                .collect()
        })
    }
    /// A polygon given by its edges.
    fn polygon_edges(&mut self, segs: &[(VKey, VKey)]) -> u32 {
        let mut key: Vec<VKey> = segs.iter().flat_map(|&(a, b)| [a, b]).collect();
        key.sort();
        key.dedup();
        let segs = segs.to_vec();
        self.add(CKey::P(key), 2, move |s| {
            segs.iter().map(|&(a, b)| s.edge(a, b)).collect()
        })
    }
    fn mark(&mut self, c: u32) {
        self.cx.cells[c as usize].in_s = true;
        let faces = self.cx.cells[c as usize].faces.clone();
        for f in faces {
            self.mark(f);
        }
    }
}

const TET_FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]];

/// Add the pieces of one tetrahedron (grid vertex ids `t`, signs `s`); returns the cut
/// polygon's key segments when the tetrahedron changes sign.
fn add_tet(b: &mut Builder, key: (u32, u8), t: [u32; 4], s: [i8; 4]) -> Option<Vec<(VKey, VKey)>> {
    let mixed = s.iter().any(|&x| x != s[0]);
    let mut cut_poly = None;
    let mut c_id = None;
    if mixed {
        let mut segs = Vec::new();
        for f in TET_FACES {
            let cuts: Vec<VKey> = (0..3)
                .filter_map(|i| {
                    let (u, w) = (f[i], f[(i + 1) % 3]);
                    (s[u] != s[w]).then(|| cut(t[u], t[w]))
                })
                .collect();
            if cuts.len() == 2 {
                segs.push((cuts[0], cuts[1]));
            }
        }
        let c = b.polygon_edges(&segs);
        b.mark(c);
        c_id = Some(c);
        cut_poly = Some(segs);
    }
    for sigma in [1i8, -1] {
        if !s.contains(&sigma) {
            continue;
        }
        let mut polys = Vec::new();
        for f in TET_FACES {
            let mut part = Vec::new();
            for i in 0..3 {
                let (u, w) = (f[i], f[(i + 1) % 3]);
                if s[u] == sigma {
                    part.push(VKey::Grid(t[u]));
                }
                if s[u] != s[w] {
                    part.push(cut(t[u], t[w]));
                }
            }
            if part.len() >= 3 && part.iter().any(|v| matches!(v, VKey::Grid(_))) {
                polys.push(b.polygon(&part));
            }
        }
        if let Some(c) = c_id {
            polys.push(c);
        }
        b.add(CKey::T(key.0, key.1, sigma), 3, |_| polys);
    }
    cut_poly
}

/// Greedy collapse of the complex onto its Ŝ cells: the sequence of (τ, σ) pairs, or
/// `None` when the greedy search gets stuck (which proves nothing).
pub fn greedy_collapse(cx: &Complex) -> Option<Vec<(u32, u32)>> {
    let (seq, alive) = greedy_run(cx);
    (0..cx.cells.len())
        .all(|i| alive[i] == cx.cells[i].in_s)
        .then_some(seq)
}

/// The greedy search: the sequence found and the cells still alive where it stopped.
fn greedy_run(cx: &Complex) -> (Vec<(u32, u32)>, Vec<bool>) {
    let n = cx.cells.len();
    let mut cof: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (i, c) in cx.cells.iter().enumerate() {
        for &f in &c.faces {
            cof[f as usize].push(i as u32);
        }
    }
    let mut cnt: Vec<usize> = cof.iter().map(|v| v.len()).collect();
    let mut alive = vec![true; n];
    // One queue per dimension of τ: always collapse the highest free pair first, in
    // breadth-first order (fronts move in from ∂W like a watershed; depth-first order
    // leaves closed walls where fronts meet).
    let mut stacks: [std::collections::VecDeque<u32>; 3] = Default::default();
    for i in 0..n as u32 {
        let c = &cx.cells[i as usize];
        if cnt[i as usize] == 1 && !c.in_s && c.dim < 3 {
            stacks[c.dim as usize].push_back(i);
        }
    }
    let mut seq = Vec::new();
    loop {
        let Some(t) = stacks.iter_mut().rev().find_map(|s| s.pop_front()) else {
            break;
        };
        let tu = t as usize;
        if !alive[tu] || cx.cells[tu].in_s || cnt[tu] != 1 {
            continue;
        }
        let Some(&s) = cof[tu].iter().find(|&&x| alive[x as usize]) else {
            continue;
        };
        if cnt[s as usize] != 0 {
            continue;
        }
        alive[tu] = false;
        alive[s as usize] = false;
        seq.push((t, s));
        let faces = cx.cells[s as usize]
            .faces
            .iter()
            .filter(|&&f| f != t)
            .chain(cx.cells[tu].faces.iter());
        for &f in faces {
            let fu = f as usize;
            cnt[fu] -= 1;
            if cnt[fu] == 1 && !cx.cells[fu].in_s && alive[fu] {
                stacks[cx.cells[fu].dim as usize].push_back(f);
            }
        }
    }
    (seq, alive)
}

/// Replay a collapse sequence on the complex, checking every step from scratch
/// (independent of [`greedy_collapse`]): the complex is closed (every face one
/// dimension lower, Ŝ closed under faces); each step removes a cell τ ∉ Ŝ that is a
/// face of σ and of no other remaining cell, σ having no remaining coface; at the end
/// exactly the cells of Ŝ remain.
pub fn replay(cx: &Complex, seq: &[(u32, u32)]) -> std::result::Result<(), String> {
    let n = cx.cells.len();
    for (i, c) in cx.cells.iter().enumerate() {
        for &f in &c.faces {
            let fc = cx
                .cells
                .get(f as usize)
                .ok_or(format!("cell {i}: face {f} missing"))?;
            if fc.dim + 1 != c.dim {
                return Err(format!("cell {i}: face {f} of dimension {}", fc.dim));
            }
            if c.in_s && !fc.in_s {
                return Err(format!("cell {i} of S has face {f} outside S"));
            }
        }
    }
    let mut alive = vec![true; n];
    // Coface lists, filtered by `alive` at each step.
    let mut cof: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (j, c) in cx.cells.iter().enumerate() {
        for &f in &c.faces {
            cof[f as usize].push(j as u32);
        }
    }
    for (k, &(t, s)) in seq.iter().enumerate() {
        let (tu, su) = (t as usize, s as usize);
        if tu >= n || su >= n || !alive[tu] || !alive[su] {
            return Err(format!("step {k}: a cell already removed or missing"));
        }
        if cx.cells[tu].in_s {
            return Err(format!("step {k}: removes cell {t} of S"));
        }
        let live: Vec<u32> = cof[tu]
            .iter()
            .copied()
            .filter(|&j| alive[j as usize])
            .collect();
        if live != [s] {
            return Err(format!(
                "step {k}: cell {t} is not a free face of {s} ({live:?})"
            ));
        }
        if cof[su].iter().any(|&j| alive[j as usize]) {
            return Err(format!("step {k}: cell {s} is not maximal"));
        }
        alive[tu] = false;
        alive[su] = false;
    }
    for i in 0..n {
        if alive[i] != cx.cells[i].in_s {
            return Err(format!(
                "after the sequence cell {i} {} (dimension {})",
                if alive[i] {
                    "remains outside S"
                } else {
                    "of S was removed"
                },
                cx.cells[i].dim
            ));
        }
    }
    Ok(())
}

/// One attempt, as reported.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Attempt {
    pub resolution: usize,
    pub w_cubes: usize,
    pub w_tets: usize,
    pub cells: usize,
    pub collapse_steps: usize,
    /// Interior vertices of W whose sign of f is undecided (f̂ is given a nonzero
    /// value there; allowed by Theorem B).
    pub free_vertices: usize,
    /// Rounds that grew W to make it a 3-manifold.
    pub repair_rounds: usize,
    /// χ(Ŝ), exact, when the collapse was replayed.
    pub chi_hat: Option<i64>,
    /// `None` when every condition held.
    pub failure: Option<String>,
    /// Adaptive version: the minimum level of the boxes not excluded (the attempt's
    /// size condition; `resolution` is then 2^min_level), the leaves of the balanced
    /// tree and the deepest level.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_level: Option<u32>,
    pub leaves: usize,
    pub deepest: u32,
    /// Adaptive version: rounds of local refinement (where the collapse got stuck, or
    /// where a leaf a repair round needed was not proven free of critical points).
    pub local_rounds: usize,
    /// The tetrahedra where the greedy collapse got stuck (not reported).
    #[serde(skip)]
    pub stuck_tets: Vec<u32>,
}

struct Grid {
    lo: [f64; 3],
    h: [f64; 3],
    n: usize,
}

impl Grid {
    fn vid(&self, i: usize, j: usize, k: usize) -> u32 {
        let m = self.n + 1;
        (i + m * (j + m * k)) as u32
    }
    fn pos(&self, v: u32) -> [f64; 3] {
        let m = (self.n + 1) as u32;
        let ijk = [v % m, (v / m) % m, v / (m * m)];
        [0, 1, 2].map(|a| self.lo[a] + self.h[a] * ijk[a] as f64)
    }
    fn block(&self, lo: [usize; 3], hi: [usize; 3]) -> IBox {
        [0, 1, 2].map(|a| {
            let l = self.lo[a] + self.h[a] * lo[a] as f64;
            let h = self.lo[a] + self.h[a] * hi[a] as f64;
            Interval::try_from((l, h)).unwrap_or(Interval::ENTIRE)
        })
    }
    fn cube(&self, i: usize, j: usize, k: usize) -> IBox {
        let c = [i, j, k];
        [0, 1, 2].map(|a| {
            let lo = self.lo[a] + self.h[a] * c[a] as f64;
            let hi = self.lo[a] + self.h[a] * (c[a] + 1) as f64;
            Interval::try_from((lo, hi)).unwrap_or(Interval::ENTIRE)
        })
    }
}

/// Bisect a box into its 8 octants.
fn octants(b: &IBox) -> Vec<IBox> {
    let mut out = Vec::with_capacity(8);
    for m in 0..8 {
        out.push([0, 1, 2].map(|a| {
            let (lo, hi, mid) = (b[a].inf(), b[a].sup(), b[a].mid());
            let (l, h) = if m >> a & 1 == 0 {
                (lo, mid)
            } else {
                (mid, hi)
            };
            Interval::try_from((l, h)).unwrap_or(b[a])
        }));
    }
    out
}

/// The proven sign of f on the box (f continuous, 0 ∉ □f), splitting into octants up
/// to `depth` times; `None` when not proven.
fn proven_sign(f: &dyn Implicit, b: &IBox, depth: u32) -> Option<i8> {
    let (v, _) = crate::implicit::ops::enclose(f, b);
    if f.regularity(b) >= Regularity::Continuous {
        if let Some(s) = sign(v) {
            return Some(s);
        }
    }
    if depth == 0 {
        return None;
    }
    let mut out = None;
    for o in octants(b) {
        let s = proven_sign(f, &o, depth - 1)?;
        if *out.get_or_insert(s) != s {
            return None;
        }
    }
    out
}

/// Is the box proven free of critical points of f (f C^∞, some 0 ∉ □∂f/∂x_k on each
/// piece), splitting into octants up to `depth` times? `Err` when f is not proven
/// smooth.
fn proven_regular(f: &dyn Implicit, b: &IBox, depth: u32) -> std::result::Result<bool, ()> {
    if f.regularity(b) != Regularity::Smooth {
        return Err(());
    }
    if f.grad_interval(b).g.iter().any(|&x| excludes_zero(x)) {
        return Ok(true);
    }
    if depth == 0 {
        return Ok(false);
    }
    for o in octants(b) {
        if !proven_regular(f, &o, depth - 1)? {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Octant splits allowed in the per-cube proofs (up to 64 pieces).
use octree::PROOF_DEPTH;

/// The six Kuhn tetrahedra of the grid cube (i, j, k), as grid vertex ids (the one
/// table of [`crate::marching::tets`]).
fn kuhn(g: &Grid, c: [usize; 3]) -> [[u32; 4]; 6] {
    crate::marching::tets::kuhn_tets().map(|t| {
        t.map(|q| {
            let v = [0, 1, 2].map(|a| c[a] + usize::from(q >> a & 1));
            g.vid(v[0], v[1], v[2])
        })
    })
}

struct Success {
    mesh: TriMesh,
    complex: Complex,
    seq: Vec<(u32, u32)>,
    /// Boxes (cubes or leaves) outside W, proven free of S.
    empty_cubes: usize,
    /// Boxes (cubes or leaves) of W.
    w_cubes: usize,
    w_tets: usize,
    /// Boxes in all.
    leaves: usize,
}

/// The complex of one tetrahedron with grid vertex ids `t` and signs `s` (±1) cut by
/// f̂ = 0 (for tests of the collapse and its replay).
pub fn tet_complex(t: [u32; 4], s: [i8; 4]) -> Complex {
    let mut b = Builder::default();
    add_tet(&mut b, (0, 0), t, s);
    b.cx
}

/// One attempt at resolution `n`: the cut complex of W and its replayed collapse
/// sequence, or why the attempt failed (for tests and independent checkers).
pub fn w_complex(
    f: &dyn Implicit,
    domain: &Aabb,
    n: usize,
) -> std::result::Result<(Complex, Vec<(u32, u32)>), String> {
    let mut rep = Attempt {
        resolution: n,
        ..Default::default()
    };
    match attempt(f, domain, n, None, &mut rep) {
        Some(s) => Ok((s.complex, s.seq)),
        None => Err(rep.failure.unwrap_or_default()),
    }
}

/// Classify the cubes of the index block `lo..hi` (an octree over the grid): a block
/// proven free of S marks all its cubes with the proven sign of f, at once; a single
/// cube gets the octant sub-proofs; everything else is left 0 (in W).
fn classify(f: &dyn Implicit, g: &Grid, lo: [usize; 3], hi: [usize; 3], state: &mut [i8]) {
    let n = g.n;
    let single = (0..3).all(|a| hi[a] - lo[a] == 1);
    let b = g.block(lo, hi);
    if let Some(s) = proven_sign(f, &b, if single { PROOF_DEPTH } else { 0 }) {
        for k in lo[2]..hi[2] {
            for j in lo[1]..hi[1] {
                for i in lo[0]..hi[0] {
                    state[i + n * (j + n * k)] = s;
                }
            }
        }
        return;
    }
    if single {
        return;
    }
    let mid = [0, 1, 2].map(|a| (lo[a] + hi[a]) / 2);
    for m in 0..8usize {
        let mut l = lo;
        let mut h = hi;
        let mut skip = false;
        for a in 0..3 {
            if hi[a] - lo[a] == 1 {
                if m >> a & 1 == 1 {
                    skip = true;
                }
            } else if m >> a & 1 == 0 {
                h[a] = mid[a];
            } else {
                l[a] = mid[a];
            }
        }
        if !skip {
            classify(f, g, l, h, state);
        }
    }
}

/// Check that the union of the tetrahedra `tets` (a simplicial complex: they meet in
/// common faces) is a PL 3-manifold with boundary: the link of every vertex is a
/// combinatorial 2-sphere or 2-disc (every link vertex's own link a path or a cycle,
/// the link connected, χ = 2 without boundary, χ = 1 with boundary).
pub fn check_manifold(tets: &[[u32; 4]]) -> std::result::Result<(), String> {
    match manifold_defects(tets, None)
        .expect("no deadline")
        .into_iter()
        .next()
    {
        None => Ok(()),
        Some((_, why)) => Err(why),
    }
}

/// The vertices at which the union of `tets` is not a 3-manifold, with why; `None` when
/// `deadline` passed before every vertex was checked.
fn manifold_defects(
    tets: &[[u32; 4]],
    deadline: Option<std::time::Instant>,
) -> Option<Vec<(u32, String)>> {
    let mut bad = Vec::new();
    let mut links: HashMap<u32, Vec<[u32; 3]>> = HashMap::new();
    for t in tets {
        for (q, face) in TET_FACES.iter().enumerate() {
            links.entry(t[q]).or_default().push(face.map(|i| t[i]));
        }
    }
    fn find(p: &mut HashMap<u32, u32>, x: u32) -> u32 {
        let mut r = x;
        while let Some(&q) = p.get(&r) {
            if q == r {
                break;
            }
            r = q;
        }
        p.insert(x, r);
        r
    }
    for (k, (&v, tris)) in links.iter().enumerate() {
        if k % 1024 == 0 && past(deadline) {
            return None;
        }
        let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
        // Per link vertex x, the union-find of its neighbours joined by triangles.
        let mut fans: HashMap<u32, HashMap<u32, u32>> = HashMap::new();
        let mut comp: HashMap<u32, u32> = HashMap::new();
        for t in tris {
            for e in 0..3 {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                *edges.entry((a.min(b), a.max(b))).or_default() += 1;
                let c = t[(e + 2) % 3];
                let fan = fans.entry(c).or_default();
                fan.entry(a).or_insert(a);
                fan.entry(b).or_insert(b);
                let (ra, rb) = (find(fan, a), find(fan, b));
                fan.insert(ra, rb);
                comp.entry(a).or_insert(a);
                comp.entry(b).or_insert(b);
                let (ra, rb) = (find(&mut comp, a), find(&mut comp, b));
                comp.insert(ra, rb);
            }
        }
        if let Some((e, c)) = edges.iter().find(|(_, &c)| c > 2) {
            bad.push((
                v,
                format!("W is not a 3-manifold at vertex {v}: link edge {e:?} in {c} triangles"),
            ));
            continue;
        }
        let mut broken = None;
        for (x, fan) in fans.iter_mut() {
            let keys: Vec<u32> = fan.keys().copied().collect();
            let r0 = find(fan, keys[0]);
            if keys.iter().any(|&k| find(fan, k) != r0) {
                broken = Some(*x);
                break;
            }
        }
        if let Some(x) = broken {
            bad.push((
                v,
                format!("W is not a 3-manifold at the edge ({v}, {x}): its link is disconnected"),
            ));
            continue;
        }
        let keys: Vec<u32> = comp.keys().copied().collect();
        let r0 = find(&mut comp, keys[0]);
        if keys.iter().any(|&k| find(&mut comp, k) != r0) {
            bad.push((
                v,
                format!("W is not a 3-manifold at vertex {v}: its link is disconnected"),
            ));
            continue;
        }
        let chi = keys.len() as i64 - edges.len() as i64 + tris.len() as i64;
        let boundary = edges.values().any(|&c| c == 1);
        let want = if boundary { 1 } else { 2 };
        if chi != want {
            bad.push((
                v,
                format!(
                    "W is not a 3-manifold at vertex {v}: its link has chi {chi}{}",
                    if boundary {
                        " and a boundary (not a disc)"
                    } else {
                        " (not a sphere)"
                    }
                ),
            ));
        }
    }
    bad.sort();
    Some(bad)
}

/// χ of the cells of Ŝ in the cut complex (V − E + F, exact).
pub fn chi_of_s(cx: &Complex) -> i64 {
    cx.cells
        .iter()
        .filter(|c| c.in_s)
        .map(|c| if c.dim == 1 { -1 } else { 1 })
        .sum()
}

/// Repair rounds of W allowed per attempt (each adds the cubes around the vertices
/// where W is not a 3-manifold).
const MAX_REPAIR: usize = 8;

/// The W cubes (not proven free of S, plus repairs) with conditions (1) and (2)
/// proven on them, the proven signs of f at the vertices of ∂W, and the Kuhn
/// tetrahedra of W, checked to form a 3-manifold; `None` with `rep.failure` else.
#[allow(clippy::type_complexity)]
fn loop_w(
    f: &dyn Implicit,
    g: &Grid,
    state: &[i8],
    deadline: Option<std::time::Instant>,
    rep: &mut Attempt,
) -> Option<(Vec<[usize; 3]>, HashMap<u32, i8>, Vec<[u32; 4]>)> {
    let n = g.n;
    // W: the cubes not proven free of S, grown by the repair rounds below.
    let mut inw: Vec<bool> = state.iter().map(|&s| s == 0).collect();
    let mut checked = vec![false; n * n * n];
    let mut round = 0usize;
    loop {
        if timed_out(deadline, rep, &format!("in repair round {round}")) {
            return None;
        }
        // Proven signs of f at the vertices of ∂W: from an incident cube outside W
        // (proven free of S), or from a boundary face of the domain on which 0 ∉ □f.
        let out_sign = |c: [i64; 3]| -> Option<i8> {
            if c.iter().any(|&x| x < 0 || x >= n as i64) {
                return None;
            }
            let ci = c[0] as usize + n * (c[1] as usize + n * c[2] as usize);
            (!inw[ci]).then_some(state[ci])
        };
        let mut proven: HashMap<u32, i8> = HashMap::new();
        let mut w_cubes: Vec<[usize; 3]> = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let ci = i + n * (j + n * k);
                    if !inw[ci] {
                        continue;
                    }
                    w_cubes.push([i, j, k]);
                    let b = g.cube(i, j, k);
                    if !checked[ci] {
                        checked[ci] = true;
                        let Ok(regular) = proven_regular(f, &b, PROOF_DEPTH) else {
                            rep.failure = Some(format!(
                                "f is not proven smooth on a W cube near {:?}",
                                g.pos(g.vid(i, j, k))
                            ));
                            return None;
                        };
                        if !regular {
                            rep.failure = Some(format!(
                                "condition (2): 0 in the gradient enclosure of a W cube near {:?} (a critical point may be in W)",
                                g.pos(g.vid(i, j, k))
                            ));
                            return None;
                        }
                    }
                    let c = [i, j, k];
                    for a in 0..3 {
                        for side in [0, n - 1] {
                            if c[a] != side {
                                continue;
                            }
                            let up = side != 0;
                            // A cube added by a repair round has its proven sign.
                            let s = if state[ci] != 0 {
                                Some(state[ci])
                            } else {
                                let mut face = b;
                                face[a] = pt(if up { b[a].sup() } else { b[a].inf() });
                                sign(crate::implicit::ops::enclose(f, &face).0)
                            };
                            let Some(s) = s else {
                                rep.failure = Some("S may meet the domain boundary (0 in the enclosure of f on a boundary face of W)".into());
                                return None;
                            };
                            for u in 0..2 {
                                for w in 0..2 {
                                    let mut q = c;
                                    q[a] += usize::from(up);
                                    q[(a + 1) % 3] += u;
                                    q[(a + 2) % 3] += w;
                                    let id = g.vid(q[0], q[1], q[2]);
                                    if *proven.entry(id).or_insert(s) != s {
                                        rep.failure = Some(format!(
                                            "two proven signs of f at the grid vertex {:?} (an internal inconsistency)",
                                            g.pos(id)
                                        ));
                                        return None;
                                    }
                                }
                            }
                        }
                    }
                    for corner in 0..8usize {
                        let v = [0, 1, 2].map(|a| c[a] + (corner >> a & 1));
                        for around in 0..8usize {
                            let q = [0, 1, 2].map(|a| v[a] as i64 - (around >> a & 1) as i64);
                            if let Some(s) = out_sign(q) {
                                let id = g.vid(v[0], v[1], v[2]);
                                if *proven.entry(id).or_insert(s) != s {
                                    rep.failure = Some(format!(
                                        "two proven signs of f at the grid vertex {:?} (an internal inconsistency)",
                                        g.pos(id)
                                    ));
                                    return None;
                                }
                            }
                        }
                    }
                }
            }
        }
        rep.w_cubes = w_cubes.len();
        rep.repair_rounds = round;
        // The Kuhn tetrahedra of W, and the manifold check (repair: add the cubes
        // around each defective vertex; they are proven free of S, and get the
        // condition (2) proof in the next round).
        let mut tets: Vec<[u32; 4]> = Vec::with_capacity(6 * w_cubes.len());
        for &c in &w_cubes {
            tets.extend(kuhn(g, c));
        }
        let Some(defects) = manifold_defects(&tets, deadline) else {
            timed_out(deadline, rep, "in the manifold check");
            return None;
        };
        if defects.is_empty() {
            break Some((w_cubes, proven, tets));
        }
        let mut added = 0;
        for (v, _) in &defects {
            let m = (n + 1) as u32;
            let ijk = [v % m, (v / m) % m, v / (m * m)].map(|x| x as i64);
            for around in 0..8usize {
                let q = [0, 1, 2].map(|a| ijk[a] - (around >> a & 1) as i64);
                if q.iter().all(|&x| x >= 0 && x < n as i64) {
                    let ci = q[0] as usize + n * (q[1] as usize + n * q[2] as usize);
                    if !inw[ci] {
                        inw[ci] = true;
                        added += 1;
                    }
                }
            }
        }
        round += 1;
        if added == 0 || round > MAX_REPAIR {
            rep.failure = Some(format!("{} (after {round} repair rounds)", defects[0].1));
            break None;
        }
    }
}

fn attempt(
    f: &dyn Implicit,
    d: &Aabb,
    n: usize,
    deadline: Option<std::time::Instant>,
    rep: &mut Attempt,
) -> Option<Success> {
    let size = d.size();
    let g = Grid {
        lo: d.min,
        h: [0, 1, 2].map(|a| size[a] / n as f64),
        n,
    };
    // The cubes: ±1 proven free of S with that sign of f (octree exclusion), 0 in W.
    let mut state = vec![0i8; n * n * n];
    classify(f, &g, [0; 3], [n; 3], &mut state);
    let empty_cubes = state.iter().filter(|&&s| s != 0).count();
    let (_, proven, tets) = loop_w(f, &g, &state, deadline, rep)?;
    let (mesh, complex, seq) = certify_tets(f, &tets, &|v| g.pos(v), &proven, deadline, rep)?;
    Some(Success {
        mesh,
        complex,
        seq,
        empty_cubes,
        w_cubes: rep.w_cubes,
        w_tets: tets.len(),
        leaves: n * n * n,
    })
}

/// Conditions (3) and (χ)'s χ(Ŝ) on the tetrahedra of W (vertex positions `pos`, the
/// proven signs of f at the vertices of ∂W `proven`), given (E), (1), (2) and (M): f̂'s
/// vertex values, the cut complex, its greedy collapse and the replay, and Ŝ as
/// triangles oriented towards f̂ > 0. Shared by the uniform and the adaptive versions.
fn certify_tets(
    f: &dyn Implicit,
    tets: &[[u32; 4]],
    pos: &dyn Fn(u32) -> [f64; 3],
    proven: &HashMap<u32, i8>,
    deadline: Option<std::time::Instant>,
    rep: &mut Attempt,
) -> Option<(TriMesh, Complex, Vec<(u32, u32)>)> {
    // f̂'s values at the vertices of W: f's midpoint where its sign is proven (and equal
    // to the proven sign on ∂W); at a vertex of ∂W whose point enclosure straddles 0,
    // the proven sign with a tiny magnitude; at an interior vertex of W with an
    // undecided sign, any nonzero value (Theorem B of bcsv.md does not use f̂ = f
    // there).
    let mut val: HashMap<u32, f64> = HashMap::new();
    for (k, t) in tets.iter().enumerate() {
        if k % 1024 == 0 && timed_out(deadline, rep, "in condition (3)'s vertex values") {
            return None;
        }
        for &id in t {
            if val.contains_key(&id) {
                continue;
            }
            let e = f.eval_interval(&pos(id).map(pt));
            let mid = 0.5 * (e.inf() + e.sup());
            let x = match (sign(e), proven.get(&id)) {
                (Some(s), Some(&p)) if s != p => {
                    rep.failure = Some(format!(
                        "the point sign of f at {:?} contradicts a proven cube sign (an internal inconsistency)",
                        pos(id)
                    ));
                    return None;
                }
                (Some(s), _) => {
                    if mid != 0.0 && mid.is_finite() && (mid > 0.0) == (s > 0) {
                        mid
                    } else if s > 0 {
                        e.inf()
                    } else {
                        e.sup()
                    }
                }
                (None, Some(&p)) => f64::from(p) * mid.abs().max(f64::MIN_POSITIVE),
                (None, None) => {
                    if !mid.is_finite() {
                        rep.failure = Some(format!(
                            "f has no finite enclosure at the grid vertex {:?}",
                            pos(id)
                        ));
                        return None;
                    }
                    rep.free_vertices += 1;
                    if mid == 0.0 {
                        f64::MIN_POSITIVE
                    } else {
                        mid
                    }
                }
            };
            val.insert(id, x);
        }
    }
    // The cut complex and Ŝ.
    let mut bld = Builder::default();
    let mut cuts: Vec<([u32; 4], [i8; 4], Vec<(VKey, VKey)>)> = Vec::new();
    for (ti, &t) in tets.iter().enumerate() {
        if ti % 1024 == 0 && timed_out(deadline, rep, "in condition (3)'s cut complex") {
            return None;
        }
        let sg = t.map(|v| if val[&v] > 0.0 { 1i8 } else { -1 });
        if let Some(segs) = add_tet(&mut bld, (ti as u32, 0), t, sg) {
            cuts.push((t, sg, segs));
        }
    }
    rep.w_tets = tets.len();
    let cx = bld.cx;
    rep.cells = cx.cells.len();
    if timed_out(deadline, rep, "before condition (3)'s collapse") {
        return None;
    }
    let (seq, alive) = greedy_run(&cx);
    if (0..cx.cells.len()).any(|i| alive[i] != cx.cells[i].in_s) {
        rep.failure = Some("condition (3): the greedy collapse of W onto the cut surface got stuck (proves nothing; refine)".into());
        // Where: the tetrahedra with a piece left (the adaptive version refines there).
        // A tetrahedron is stuck when one of its cells, or of their faces, is left.
        fn left(cx: &Complex, alive: &[bool], c: u32) -> bool {
            let cell = &cx.cells[c as usize];
            (alive[c as usize] && !cell.in_s) || cell.faces.iter().any(|&g| left(cx, alive, g))
        }
        rep.stuck_tets = bld
            .ids
            .iter()
            .filter_map(|(k, &c)| match k {
                CKey::T(t, _, _) if left(&cx, &alive, c) => Some(*t),
                _ => None,
            })
            .collect();
        rep.stuck_tets.sort_unstable();
        rep.stuck_tets.dedup();
        return None;
    }
    if timed_out(deadline, rep, "before the collapse's replay") {
        return None;
    }
    if let Err(e) = replay(&cx, &seq) {
        rep.failure = Some(format!("the collapse sequence failed its replay: {e}"));
        return None;
    }
    rep.collapse_steps = seq.len();
    rep.chi_hat = Some(chi_of_s(&cx));
    // Ŝ as triangles, oriented towards f̂ > 0.
    let mut mesh = TriMesh::default();
    let mut vid: HashMap<VKey, u32> = HashMap::new();
    let mut point = |key: VKey, mesh: &mut TriMesh| -> u32 {
        *vid.entry(key).or_insert_with(|| {
            let VKey::Cut(a, b) = key else {
                unreachable!("cut polygons have cut vertices")
            };
            let (pa, pb) = (pos(a), pos(b));
            let (fa, fb) = (val[&a], val[&b]);
            let s = fa / (fa - fb);
            mesh.vertices
                .push([0, 1, 2].map(|q| pa[q] + s * (pb[q] - pa[q])));
            (mesh.vertices.len() - 1) as u32
        })
    };
    for (t, sg, segs) in &cuts {
        // Walk the segments into a cycle.
        let mut cyc = vec![segs[0].0, segs[0].1];
        let mut used = vec![false; segs.len()];
        used[0] = true;
        while cyc.len() < segs.len() {
            let last = *cyc.last().unwrap();
            let Some(k) =
                (0..segs.len()).find(|&k| !used[k] && (segs[k].0 == last || segs[k].1 == last))
            else {
                break;
            };
            used[k] = true;
            cyc.push(if segs[k].0 == last {
                segs[k].1
            } else {
                segs[k].0
            });
        }
        let ids: Vec<u32> = cyc.iter().map(|&c| point(c, &mut mesh)).collect();
        // Orientation, combinatorially: the same cycle through the edge midpoints is
        // the zero set of the interpolant of the signs (±1), whose gradient points
        // towards f̂ > 0; compare with that cycle's Newell normal (grid points only,
        // so degenerate cut points near a vertex cannot flip it).
        use crate::kernel::geom::{cross, dot, sub};
        let mids: Vec<[f64; 3]> = cyc
            .iter()
            .map(|&c| {
                let VKey::Cut(a, b) = c else {
                    unreachable!("cut polygons have cut vertices")
                };
                let (pa, pb) = (pos(a), pos(b));
                [0, 1, 2].map(|q| 0.5 * (pa[q] + pb[q]))
            })
            .collect();
        let mut nrm = [0.0; 3];
        for q in 0..mids.len() {
            let c = cross(mids[q], mids[(q + 1) % mids.len()]);
            nrm = [0, 1, 2].map(|r| nrm[r] + c[r]);
        }
        let p = t.map(|v| pos(v));
        let e = [1, 2, 3].map(|q| sub(p[q], p[0]));
        let dv = [1, 2, 3].map(|q| f64::from(sg[q] - sg[0]));
        let cr = [cross(e[1], e[2]), cross(e[2], e[0]), cross(e[0], e[1])];
        let det = dot(e[0], cr[0]);
        let grad =
            [0, 1, 2].map(|r| (dv[0] * cr[0][r] + dv[1] * cr[1][r] + dv[2] * cr[2][r]) / det);
        let flip = dot(nrm, grad) < 0.0;
        for q in 1..ids.len() - 1 {
            let tri = [ids[0], ids[q], ids[q + 1]];
            mesh.triangles
                .push(if flip { [tri[0], tri[2], tri[1]] } else { tri });
        }
    }
    Some((mesh, cx, seq))
}

/// One attempt of adaptive BCSV: the octree refined by [`octree::criterion`] with every
/// box not excluded split at least to `min_level` (at most to `max_depth`, within
/// `max_boxes` box tests), balanced 2:1 and tetrahedralized conformingly; W the leaves
/// not excluded, grown by repair rounds until a 3-manifold; then the shared conditions
/// ([`certify_tets`]).
fn attempt_octree(
    f: &dyn Implicit,
    d: &Aabb,
    min_level: u32,
    max_depth: u32,
    max_boxes: u64,
    deadline: Option<std::time::Instant>,
    rep: &mut Attempt,
) -> Option<Success> {
    let mut force = HashSet::new();
    for round in 0.. {
        if round > 0 && past(deadline) {
            rep.failure = Some(format!("{TIME_LIMIT} (before local round {round})"));
            return None;
        }
        *rep = Attempt {
            resolution: rep.resolution,
            min_level: rep.min_level,
            local_rounds: round,
            ..Default::default()
        };
        match try_octree(f, d, min_level, max_depth, max_boxes, deadline, &force, rep) {
            Ok(s) => return Some(s),
            Err(cells) if round < LOCAL_ROUNDS && !cells.is_empty() => force.extend(cells),
            Err(_) => return None,
        }
    }
    unreachable!("the loop returns")
}

/// Rounds of local refinement per adaptive attempt.
const LOCAL_ROUNDS: usize = 4;

/// Why a run stopped at its time limit.
const TIME_LIMIT: &str = "time limit reached (raise --time-limit)";

/// Has the deadline passed?
fn past(deadline: Option<std::time::Instant>) -> bool {
    deadline.is_some_and(|d| std::time::Instant::now() >= d)
}

/// The stop reason when `last` ended at the time limit `limit` (seconds), inside.
fn stopped_during(last: Option<&Attempt>, limit: f64) -> Option<String> {
    let last = last?;
    let why = last.failure.as_deref()?.strip_prefix(TIME_LIMIT)?;
    Some(format!(
        "{TIME_LIMIT}: {limit} s, during the attempt at resolution {}{why}",
        last.resolution
    ))
}

/// Has the deadline passed? If so, say so in the attempt's failure (`at`: where the
/// work stopped) and leave no tetrahedra to refine: the attempt ends there.
fn timed_out(deadline: Option<std::time::Instant>, rep: &mut Attempt, at: &str) -> bool {
    if !past(deadline) {
        return false;
    }
    rep.failure = Some(format!("{TIME_LIMIT} ({at})"));
    rep.stuck_tets.clear();
    true
}

/// One try of an adaptive attempt, the cells in `force` split once more; `Err` with
/// the leaves to split where a local refinement may help (none: it fails as is).
fn try_octree(
    f: &dyn Implicit,
    d: &Aabb,
    min_level: u32,
    max_depth: u32,
    max_boxes: u64,
    deadline: Option<std::time::Instant>,
    force: &HashSet<u64>,
    rep: &mut Attempt,
) -> std::result::Result<Success, Vec<u64>> {
    // The octree's own limit: the seconds left.
    let left = deadline.map(|d| {
        d.saturating_duration_since(std::time::Instant::now())
            .as_secs_f64()
    });
    let oct = Octree::build(f, d, min_level, max_depth, max_boxes, left, force);
    let tree = &oct.tree;
    let grid = tree.grid;
    rep.leaves = tree.leaves.len();
    rep.deepest = tree
        .leaves
        .iter()
        .map(|l| l.cell.level as u32)
        .max()
        .unwrap_or(0);
    if let Some(l) = tree
        .leaves
        .iter()
        .find(|l| matches!(l.verdict, Verdict::Failed(_)))
    {
        let Verdict::Failed(why) = l.verdict else {
            unreachable!()
        };
        let failed = tree
            .leaves
            .iter()
            .filter(|l| !l.verdict.certified())
            .count();
        rep.failure = Some(format!(
            "the octree refinement stopped{} with {failed} undecided leaves, e.g. at level {} near {:?}: {why}",
            if tree.refinement_complete {
                format!(" at the depth limit {max_depth}")
            } else {
                " by its budget (boxes: raise --max-boxes; or the time limit)".to_string()
            },
            l.cell.level,
            grid.cell_aabb(l.cell).center()
        ));
        return Err(Vec::new());
    }
    let nl = tree.leaves.len();
    let mut inw: Vec<bool> = tree
        .leaves
        .iter()
        .map(|l| l.verdict != Verdict::Empty)
        .collect();
    let empty = nl - inw.iter().filter(|&&w| w).count();
    // The proven sign of f on each excluded leaf (the criterion's proof, repeated).
    let mut leaf_sign: Vec<i8> = vec![0; nl];
    for (i, l) in tree.leaves.iter().enumerate() {
        if i % 1024 == 0 && timed_out(deadline, rep, "in the excluded leaves' signs") {
            return Err(Vec::new());
        }
        if !inw[i] {
            let Some(s) = octree::sign_on(f, &grid, l.cell, None) else {
                rep.failure =
                    Some("an excluded leaf lost its proof (an internal inconsistency)".into());
                return Err(Vec::new());
            };
            leaf_sign[i] = s;
        }
    }
    let mut vs = oct.vertices();
    let mut cache: HashMap<usize, octree::LeafTets> = HashMap::new();
    let mut round = 0usize;
    loop {
        if timed_out(deadline, rep, &format!("in repair round {round}")) {
            return Err(Vec::new());
        }
        let w: Vec<usize> = (0..nl).filter(|&i| inw[i]).collect();
        let mut tets: Vec<[u32; 4]> = Vec::new();
        let mut tet_leaf: Vec<usize> = Vec::new();
        let mut proven: HashMap<u32, i8> = HashMap::new();
        for &i in &w {
            let lt = cache.entry(i).or_insert_with(|| oct.leaf_tets(i, &mut vs));
            tets.extend_from_slice(&lt.tets);
            tet_leaf.extend(std::iter::repeat(i).take(lt.tets.len()));
            let cell = tree.leaves[i].cell;
            for p in &lt.pieces {
                // A piece of ∂W: across an excluded leaf (its proven sign), or on ∂D
                // (the proven sign of f on the leaf's whole face, or on the leaf itself
                // when a repair round added it).
                let s = match p.across {
                    Some(j) if inw[j] => continue,
                    Some(j) => leaf_sign[j],
                    None if leaf_sign[i] != 0 => leaf_sign[i],
                    None => {
                        match octree::sign_on(f, &grid, cell, Some((p.axis as usize, p.side))) {
                            Some(s) => s,
                            None => {
                                rep.failure = Some(format!(
                                    "S may meet the domain boundary (0 in the enclosure of f on a boundary face of the W leaf near {:?})",
                                    grid.cell_aabb(cell).center()
                                ));
                                return Err(Vec::new());
                            }
                        }
                    }
                };
                for &v in &p.verts {
                    if *proven.entry(v).or_insert(s) != s {
                        rep.failure = Some(format!(
                            "two proven signs of f at the vertex {:?} (an internal inconsistency)",
                            vs.pos(v)
                        ));
                        return Err(Vec::new());
                    }
                }
            }
        }
        rep.w_cubes = w.len();
        rep.repair_rounds = round;
        let Some(defects) = manifold_defects(&tets, deadline) else {
            timed_out(deadline, rep, "in the manifold check");
            return Err(Vec::new());
        };
        if defects.is_empty() {
            let pos = |v: u32| vs.pos(v);
            let Some((mesh, complex, seq)) = certify_tets(f, &tets, &pos, &proven, deadline, rep)
            else {
                // Refine the leaves where the collapse got stuck.
                let mut cells: Vec<u64> = rep
                    .stuck_tets
                    .iter()
                    .map(|&t| tree.leaves[tet_leaf[t as usize]].cell.key())
                    .collect();
                cells.sort_unstable();
                cells.dedup();
                return Err(cells);
            };
            return Ok(Success {
                mesh,
                complex,
                seq,
                empty_cubes: empty,
                w_cubes: w.len(),
                w_tets: tets.len(),
                leaves: nl,
            });
        }
        // Repair: add the leaves around each defective vertex. They were excluded
        // (so (E) and (1) still hold); condition (2) is proven on them here.
        let mut added = 0;
        let mut unproven = Vec::new();
        for (v, _) in &defects {
            for j in oct.leaves_at(vs.coords[*v as usize]) {
                if inw[j] {
                    continue;
                }
                if timed_out(deadline, rep, "in condition (2) on repair leaves") {
                    return Err(Vec::new());
                }
                let b = grid.cell_ibox(tree.leaves[j].cell);
                if proven_regular(f, &b, PROOF_DEPTH) != Ok(true) {
                    rep.failure = Some(format!(
                        "condition (2) on a leaf added to make W a 3-manifold near {:?}: not proven free of critical points ({})",
                        grid.cell_aabb(tree.leaves[j].cell).center(),
                        defects[0].1
                    ));
                    // Split it and the leaves of W at the defect: a finer W may not
                    // need it.
                    unproven.extend(
                        oct.leaves_at(vs.coords[*v as usize])
                            .into_iter()
                            .map(|k| tree.leaves[k].cell.key()),
                    );
                    continue;
                }
                inw[j] = true;
                added += 1;
            }
        }
        if !unproven.is_empty() {
            // Split those leaves: their parts near the defect may be provable.
            return Err(unproven);
        }
        round += 1;
        if added == 0 || round > MAX_REPAIR {
            rep.failure = Some(format!("{} (after {round} repair rounds)", defects[0].1));
            // Refine the leaves at the defects that remain.
            let mut cells: Vec<u64> = defects
                .iter()
                .flat_map(|(v, _)| oct.leaves_at(vs.coords[*v as usize]))
                .map(|k| tree.leaves[k].cell.key())
                .collect();
            cells.sort_unstable();
            cells.dedup();
            return Err(cells);
        }
    }
}

/// One adaptive attempt with minimum level `min_level`: the cut complex of W and its
/// replayed collapse sequence, or why the attempt failed (for tests and independent
/// checkers).
pub fn w_complex_octree(
    f: &dyn Implicit,
    domain: &Aabb,
    min_level: u32,
    max_depth: u32,
) -> std::result::Result<(Complex, Vec<(u32, u32)>), String> {
    let mut rep = Attempt::default();
    match attempt_octree(
        f,
        domain,
        min_level,
        max_depth,
        DEFAULT_MAX_BOXES,
        None,
        &mut rep,
    ) {
        Some(s) => Ok((s.complex, s.seq)),
        None => Err(rep.failure.unwrap_or_default()),
    }
}

impl Mesher for Bcsv {
    fn name(&self) -> &'static str {
        "bcsv"
    }
    fn dim(&self) -> usize {
        3
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        check_input(f, domain, 3, "bcsv")?;
        let t0 = std::time::Instant::now();
        // The certified χ(S) of the Morse census (the replacement of Theorem 8's
        // premises, Theorem B of bcsv.md): computed once.
        let (chi_s, chi_reason) = if f.is_rigorous() {
            crate::morse::certified_chi(
                f,
                crate::implicit::critical::Bx::from(*domain),
                self.census_boxes,
                5 * self.census_boxes,
            )
        } else {
            (
                None,
                Some("the oracle's interval methods are not rigorous".into()),
            )
        };
        let census_seconds = t0.elapsed().as_secs_f64();
        let mut attempts: Vec<Attempt> = Vec::new();
        let mut n = 4usize.min(self.max_resolution);
        let mut found = None;
        let mut w_found = None;
        progress.start("bcsv attempts", 0);
        let deadline = self
            .time_limit
            .and_then(|s| t0.checked_add(std::time::Duration::try_from_secs_f64(s).ok()?));
        let mut stopped: Option<String> = None;
        let limit = self.time_limit.unwrap_or(f64::NAN);
        loop {
            let mut rep = Attempt {
                resolution: n,
                ..Default::default()
            };
            if !attempts.is_empty() && past(deadline) {
                stopped = Some(stopped_during(attempts.last(), limit).unwrap_or_else(|| {
                    format!("{TIME_LIMIT}: {limit} s, before the attempt at resolution {n}")
                }));
                break;
            }
            let r = if !f.is_rigorous() {
                rep.failure = Some("the oracle's interval methods are not rigorous".into());
                None
            } else if self.octree {
                let level = n.trailing_zeros();
                rep.min_level = Some(level);
                attempt_octree(
                    f,
                    domain,
                    level,
                    self.max_depth.max(level),
                    self.max_boxes,
                    deadline,
                    &mut rep,
                )
            } else {
                attempt(f, domain, n, deadline, &mut rep)
            };
            if let Some(s) = r {
                if chi_s.is_some() && chi_s == rep.chi_hat {
                    attempts.push(rep);
                    found = Some((n, s));
                    break;
                }
                if let (Some(c), Some(h)) = (chi_s, rep.chi_hat) {
                    rep.failure = Some(format!(
                        "W-certified, but chi(S-hat) = {h} differs from the certified chi(S) = {c}: refine"
                    ));
                }
                // Keep the first W-certified attempt in case no finer one is isotopic.
                if w_found.is_none() {
                    w_found = Some((n, s));
                }
                if chi_s.is_none() {
                    attempts.push(rep);
                    break;
                }
            }
            attempts.push(rep);
            progress.inc(1);
            let last = if self.octree {
                2 * n > self.max_resolution
            } else {
                n >= self.max_resolution
            };
            if last || !f.is_rigorous() {
                break;
            }
            n = (2 * n).min(self.max_resolution);
        }
        progress.finish();
        if stopped.is_none() && found.is_none() {
            // The last attempt ran out of time (the loop ended with it).
            stopped = stopped_during(attempts.last(), limit);
        }
        let mut stats = serde_json::Map::new();
        stats.insert(
            "attempts".into(),
            serde_json::to_value(&attempts).expect("serialises"),
        );
        stats.insert(
            "chi_certified".into(),
            serde_json::to_value(chi_s).expect("serialises"),
        );
        stats.insert(
            "chi_certified_reason".into(),
            serde_json::to_value(&chi_reason).expect("serialises"),
        );
        stats.insert("census_seconds".into(), census_seconds.into());
        stats.insert(
            "stop_reason".into(),
            serde_json::to_value(&stopped).expect("serialises"),
        );
        // Appended to an uncertified outcome's reason when the time limit ended it.
        let stop_note = stopped
            .as_ref()
            .map(|s| format!("; stopped: {s}"))
            .unwrap_or_default();
        let w_statement = if self.octree {
            "W-certified on the adaptive octree (2:1 balanced, conforming tetrahedra): Theorem 8's conditions"
        } else {
            "W-certified on the uniform Kuhn grid: Theorem 8's conditions"
        };
        let w_statement = format!("{w_statement} (1) f != 0 on the boundary of W, (2) no critical point of f in W, (3) a subdivision of W collapses onto the PL surface (sequence replayed), W a 3-manifold and S inside W, proven with intervals");
        let isotopic = found.is_some();
        let chosen = found.or(w_found);
        match chosen {
            Some((n, s)) => {
                stats.insert("w_certified".into(), true.into());
                stats.insert("isotopy_certified".into(), isotopic.into());
                stats.insert("resolution".into(), n.into());
                stats.insert("octree".into(), self.octree.into());
                stats.insert("w_boxes".into(), s.w_cubes.into());
                stats.insert("w_tetrahedra".into(), s.w_tets.into());
                if self.octree {
                    stats.insert("min_level".into(), n.trailing_zeros().into());
                    stats.insert("max_depth".into(), self.max_depth.into());
                    stats.insert("leaves".into(), s.leaves.into());
                } else {
                    stats.insert("tetrahedra".into(), (6 * n * n * n).into());
                }
                stats.insert("complex_cells".into(), s.complex.cells.len().into());
                stats.insert("collapse_steps".into(), s.seq.len().into());
                stats.insert("collapse_replayed".into(), true.into());
                stats.insert("chi_hat".into(), chi_of_s(&s.complex).into());
                let mut claims = vec![
                    Claim::RegularZeroSet {
                        dim: 3,
                        inside: *domain,
                    },
                    Claim::ExcludedEmpty {
                        empty: s.empty_cubes,
                        boxes: s.leaves,
                    },
                ];
                let certificate = if isotopic {
                    let statement = format!(
                        "{w_statement}; in place of the theorem's premises on critical points, the certified chi(S) of the Morse census equals chi(S-hat) = {}: S and S-hat are isotopic (Theorem B, papers/meshing-of-surfaces/bcsv.md)",
                        chi_of_s(&s.complex)
                    );
                    stats.insert("statement".into(), statement.into());
                    claims.insert(
                        0,
                        Claim::Isotopic {
                            inside: *domain,
                            theorem: "BCSV Theorem 8 conditions with the certified chi(S) = chi(S-hat), Theorem B of papers/meshing-of-surfaces/bcsv.md".into(),
                            generic_position: false,
                        },
                    );
                    Certificate::certified(claims)
                } else {
                    let statement = format!(
                        "{w_statement}; isotopy not claimed: {}",
                        match (chi_s, &chi_reason) {
                            (Some(c), _) => format!(
                                "chi(S-hat) = {} differs from the certified chi(S) = {c} up to resolution {}",
                                chi_of_s(&s.complex),
                                self.max_resolution
                            ),
                            (None, r) => format!(
                                "chi(S) is not certified by the Morse census ({})",
                                r.as_deref().unwrap_or("")
                            ),
                        }
                    ) + &stop_note;
                    stats.insert("statement".into(), statement.clone().into());
                    Certificate::uncertified(statement, claims, Vec::new())
                };
                Ok(MeshOutput {
                    mesh: Mesh::Surface(s.mesh),
                    certificate,
                    stats,
                    angles: None,
                })
            }
            None => {
                stats.insert("w_certified".into(), false.into());
                stats.insert("isotopy_certified".into(), false.into());
                let last = attempts
                    .last()
                    .and_then(|a| a.failure.clone())
                    .unwrap_or_default();
                let reason = format!(
                    "no W-certified attempt up to resolution {} (last: {last}){stop_note}",
                    self.max_resolution
                );
                // The finest attempt's marching tetrahedra on f̂ as an uncertified output.
                let mt = crate::marching::MarchingTetrahedra::from_options(&MesherOptions {
                    resolution: Some(self.max_resolution),
                    ..Default::default()
                })?;
                let out = mt.mesh(f, domain, &crate::mesher::NoProgress)?;
                Ok(MeshOutput {
                    mesh: out.mesh,
                    certificate: Certificate::uncertified(
                        reason,
                        Vec::new(),
                        vec![crate::mesher::Uncertified::new(*domain, last)],
                    ),
                    stats,
                    angles: None,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The work after the octree stops at a deadline that has passed: the manifold
    /// check returns nothing, and condition (3) ends with the time limit as its failure
    /// and no tetrahedra to refine.
    #[test]
    fn checks_stop_at_a_past_deadline() {
        let g = Grid {
            lo: [-1.0; 3],
            h: [1.0; 3],
            n: 2,
        };
        let tets: Vec<[u32; 4]> = (0..2)
            .flat_map(|k| (0..2).flat_map(move |j| (0..2).map(move |i| [i, j, k])))
            .flat_map(|c| kuhn(&g, c))
            .collect();
        let now = Some(std::time::Instant::now());
        assert_eq!(manifold_defects(&tets, None), Some(Vec::new()));
        assert_eq!(manifold_defects(&tets, now), None);
        let f = crate::Formula::surface("x^2 + y^2 + z^2 - 0.25").unwrap();
        let mut rep = Attempt {
            stuck_tets: vec![1, 2],
            ..Default::default()
        };
        let pos = |v: u32| g.pos(v);
        assert!(certify_tets(&f, &tets, &pos, &HashMap::new(), now, &mut rep).is_none());
        let why = rep.failure.unwrap();
        assert!(why.starts_with(TIME_LIMIT), "{why}");
        assert!(rep.stuck_tets.is_empty());
        // Without a deadline the same work runs to its own verdict (here: the ball W
        // does not collapse onto the sphere, so the tetrahedra are left to refine).
        let mut rep = Attempt::default();
        assert!(certify_tets(&f, &tets, &pos, &HashMap::new(), None, &mut rep).is_none());
        let why = rep.failure.unwrap();
        assert!(why.starts_with("condition (3)"), "{why}");
        assert!(!rep.stuck_tets.is_empty());
    }
}
