//! The graded variant's two dagger bounds (Labelle & Shewchuk 2007, §5): the largest
//! plane angle of the non-BCC background tetrahedra (bisected, quadrisected,
//! half-pyramids, Fig 10) when their vertices are warped.
//!
//! **Shapes.** Read from the mesher's own background-grid code
//! ([`certmesh::stuffing::graded::background_grid`]) on a small octree with three
//! levels (a root, its eight children, one child fully refined and one with a single
//! child), reduced to similarity classes under the 48 cube symmetries, translation and
//! scale; each class is kept at its *smallest* instance (finest level).
//!
//! **Configuration space (a superset of the realisable one).** §5: only BCC tetrahedra
//! cross the surface, so a non-BCC output tetrahedron has only + and warped (0) vertices,
//! at least one +. A warped vertex moves along one of the 14 fine BCC edges at it by
//! `t ∈ [0, α]` of that edge (α_long black, α_short red; the closure of the strict-<
//! rule, and it contains the §6 midpoint). We enumerate every face (the plane angles of a
//! face depend on its three vertices only) with each vertex fixed or warped along any of
//! the 14 directions, excluding only the pairs the rules forbid: two vertices of the face
//! joined by a fine BCC edge never warp toward each other, and with ordered warping never
//! toward a vertex that warps. Not imposed (hence a superset): whether a cut point can
//! sit on that edge at all, the signs of the neighbours. A coarser instance of a shape
//! is the finest one scaled by 2^k with the warps shrunk by 2^-k, `t ∈ [0, α/2^k] ⊂ [0, α]`
//! (angles are scale invariant), so the finest instance covers every level.
//! A bound *proven* on the superset holds for the mesher; a superset maximum above the
//! paper's value refutes nothing by itself, so the refutation uses a realised witness
//! (the mesher test `graded_dagger_147_is_exceeded_on_a_half_pyramid`).
use super::cases::{canonical, Alphas, Seg, Sym};
use super::eval::{cos_plane, Geo, Problem, Role, What, V3};
use crate::ival::pt;
use certmesh::stuffing::graded::{background_grid, Kind};
use certmesh::stuffing::Row;
use inari::Interval;
use rayon::prelude::*;
use std::collections::{BTreeMap, HashSet};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// The two daggered entries: (row, uniform max plane angle, graded value), both in the
/// "max plane angle" column.
pub const DAGGERS: [(&str, f64, f64); 2] = [
    ("min-exposed-unsafe", 149.6794, 158.1918),
    ("min-exposed-safe-ordered", 145.4921, 147.0470),
];

/// The 14 fine BCC edge vectors in doubled coordinates (black edge = 2).
pub fn directions() -> Vec<[i64; 3]> {
    let mut d = Vec::new();
    for k in 0..3 {
        for s in [-2, 2] {
            let mut v = [0; 3];
            v[k] = s;
            d.push(v);
        }
    }
    for m in 0..8 {
        d.push([0, 1, 2].map(|k| if m >> k & 1 == 1 { -1 } else { 1 }));
    }
    d
}

/// A similarity class of non-BCC background tetrahedra, at its finest instance.
#[derive(Clone, Debug)]
pub struct Shape {
    pub kind: Kind,
    /// Vertices in doubled finest-lattice coordinates.
    pub v: [[i64; 3]; 4],
    /// Octree level of this instance (scale 2^level).
    pub level: u32,
    /// Number of background tetrahedra of the sample octree in this class.
    pub instances: usize,
}

fn gcd(a: i64, b: i64) -> i64 {
    if b == 0 {
        a.abs()
    } else {
        gcd(b, a % b)
    }
}

/// The sample octree: root (level 2), its 8 children, child 0 with all 8 children,
/// child 7 with one child (so both full and partial refinement occur).
pub fn sample_tree() -> HashSet<(u32, [i64; 3])> {
    let mut t = HashSet::new();
    t.insert((2, [0, 0, 0]));
    for b in 0..8i64 {
        t.insert((1, [b & 1, b >> 1 & 1, b >> 2 & 1]));
        t.insert((0, [b & 1, b >> 1 & 1, b >> 2 & 1]));
    }
    t.insert((0, [2, 2, 2]));
    t
}

/// The non-BCC shapes of the mesher's background grid (see the module comment).
pub fn shapes() -> Vec<Shape> {
    let bg = background_grid(&sample_tree(), |_| false);
    let syms = Sym::all();
    let mut classes: BTreeMap<Vec<Seg>, Shape> = BTreeMap::new();
    for (t, kind) in bg {
        if kind == Kind::Bcc {
            continue;
        }
        let mut g = 0;
        for v in &t {
            for k in 0..3 {
                g = gcd(g, v[k] - t[0][k]);
            }
        }
        let segs: Vec<Seg> = t
            .iter()
            .map(|v| Seg::fixed([0, 1, 2].map(|k| (v[k] - t[0][k]) / g)))
            .collect();
        let key = canonical(&segs, &syms);
        let level = g.trailing_zeros();
        let e = classes.entry(key).or_insert(Shape {
            kind,
            v: t,
            level,
            instances: 0,
        });
        e.instances += 1;
        // The smallest level, then the smallest vertex list: deterministic (the octree's
        // hash order is not).
        if (level, t) < (e.level, e.v) {
            e.v = t;
            e.level = level;
        }
    }
    classes.into_values().collect()
}

/// One face configuration (canonical) with its multiplicity.
#[derive(Clone, Debug)]
pub struct FaceCase {
    pub v: [Seg; 3],
    pub multiplicity: usize,
}

/// Counts: raw (shape, face, warp choices) triples → distinct faces under symmetry.
pub fn face_cases(shapes: &[Shape]) -> (Vec<FaceCase>, usize) {
    let dirs = directions();
    let syms = Sym::all();
    let mut raw = 0;
    let mut map: BTreeMap<Vec<Seg>, usize> = BTreeMap::new();
    for s in shapes {
        for f in [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]] {
            let p = f.map(|i| s.v[i]);
            for m in 0..15usize.pow(3) {
                let ch = [m % 15, m / 15 % 15, m / 225];
                let seg = |i: usize| -> Seg {
                    if ch[i] == 14 {
                        Seg::fixed(p[i])
                    } else {
                        Seg::warp(p[i], dirs[ch[i]])
                    }
                };
                let v = [seg(0), seg(1), seg(2)];
                let chd = [0, 1, 2].map(|i| (ch[i] < 14).then(|| dirs[ch[i]]));
                let bad = !pair_rules_ok(&s.v, &p, &chd);
                if bad {
                    continue;
                }
                raw += 1;
                *map.entry(canonical(&v, &syms)).or_insert(0) += 1;
            }
        }
    }
    let cases = collect_face_cases(map);
    (cases, raw)
}

/// Sample octrees (the contexts), deterministic: a root of level 3, all its level-2 and
/// level-1 descendants, the level-1 octant P = [1,1,1] fully refined, and each of the 26
/// level-1 octants around P given a pseudo-random subset of its eight children (a sparse
/// octree, §5), `n` trees. Not closed under the mesher's balance/continuation steps, so
/// these contexts are a sample, not all octrees.
pub fn sample_trees_n(n: usize) -> Vec<HashSet<(u32, [i64; 3])>> {
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut out = Vec::new();
    for _ in 0..n {
        let mut t = HashSet::new();
        t.insert((3, [0, 0, 0]));
        for b in 0..8i64 {
            t.insert((2, [b & 1, b >> 1 & 1, b >> 2 & 1]));
        }
        for i in 0..64i64 {
            t.insert((1, [i & 3, i >> 2 & 3, i >> 4 & 3]));
        }
        for o in 0..27i64 {
            let q = [o % 3, o / 3 % 3, o / 9];
            for c in 0..8i64 {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                if q == [1, 1, 1] || seed >> 63 == 0 {
                    t.insert((0, [0, 1, 2].map(|k| 2 * q[k] + (c >> k & 1))));
                }
            }
        }
        out.push(t);
    }
    out
}

/// The default number of sample contexts.
pub const DEFAULT_TREES: usize = 96;

/// Face cases in context: every non-BCC tetrahedron of every sample tree, each vertex
/// fixed or warped along a fine BCC edge that *exists at it in that tree* (an edge of a
/// level-0 BCC tetrahedron of the background grid: the mesher's cut edges are fine BCC
/// edges of BCC tetrahedra, it refuses anything else), with the pair rules.
/// Returns (cases, raw count, non-BCC tetrahedra visited).
pub fn face_cases_in_context(trees: usize) -> (Vec<FaceCase>, usize, usize) {
    let dirs = directions();
    let syms = Sym::all();
    let mut raw = 0;
    let mut ntets = 0;
    let mut map: BTreeMap<Vec<Seg>, usize> = BTreeMap::new();
    for tree in sample_trees_n(trees) {
        let bg = background_grid(&tree, |_| false);
        let mut fine: HashSet<([i64; 3], [i64; 3])> = HashSet::new();
        for (t, kind) in &bg {
            if *kind != Kind::Bcc {
                continue;
            }
            for i in 0..4 {
                for j in 0..4 {
                    let d = crate::stuffing::cases::sub(t[j], t[i]);
                    if i != j && dirs.contains(&d) {
                        fine.insert((t[i], d));
                    }
                }
            }
        }
        for (t, kind) in &bg {
            if *kind == Kind::Bcc {
                continue;
            }
            ntets += 1;
            for f in [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]] {
                let p = f.map(|i| t[i]);
                let opts: Vec<Vec<Option<[i64; 3]>>> = p
                    .iter()
                    .map(|&q| {
                        std::iter::once(None)
                            .chain(
                                dirs.iter()
                                    .filter(|&&d| {
                                        fine.contains(&(q, d)) && continuation_ok(&tree, q, d)
                                    })
                                    .map(|&d| Some(d)),
                            )
                            .collect()
                    })
                    .collect();
                for a in &opts[0] {
                    for b in &opts[1] {
                        for c in &opts[2] {
                            let ch = [*a, *b, *c];
                            if !pair_rules_ok(t, &p, &ch) {
                                continue;
                            }
                            raw += 1;
                            let v: Vec<Seg> = (0..3)
                                .map(|i| match ch[i] {
                                    None => Seg::fixed(p[i]),
                                    Some(d) => Seg::warp(p[i], d),
                                })
                                .collect();
                            *map.entry(canonical(&v, &syms)).or_insert(0) += 1;
                        }
                    }
                }
            }
        }
    }
    let cases = collect_face_cases(map);
    (cases, raw, ntets)
}

/// Is a warp of `v` along the fine BCC edge `(v, v + d)` consistent with the octree
/// `tree` being closed under the mesher's leaf rule and Continuation Condition (§5,
/// steps (1)-(2) of `stuff_graded`)? The edge carries a cut, so its ends have opposite
/// signs. Red edge (a corner and the centre of fine cube L): L straddles the surface, so
/// it is a leaf, and the corner/centre sign change pushes L's three face neighbours at
/// that corner to be leaves. Black corner–corner edge: the four fine cubes around it have
/// corners of both signs, so they are leaves. Black centre–centre edge: both cubes are
/// fine (it is an edge of a fine BCC tetrahedron). A necessary condition only, so the
/// filtered set is still a superset of what the mesher realises in that tree.
pub fn continuation_ok(tree: &HashSet<(u32, [i64; 3])>, v: [i64; 3], d: [i64; 3]) -> bool {
    super::contexts::required_cubes(v, d)
        .iter()
        .all(|c| tree.contains(&(0, *c)))
}

/// The warping rules on a face of tetrahedron `t`. The mesher refuses a non-BCC
/// background tetrahedron with a + and a − vertex (§5: only BCC tetrahedra cross the
/// surface), and an output one has a + vertex, so every vertex was + or exactly 0 before
/// warping: no edge between two of its vertices carries a cut, so no vertex warps toward
/// another vertex of the same tetrahedron (this contains the pair rules: never both
/// toward each other; ordered, never toward a vertex that warps).
fn pair_rules_ok(t: &[[i64; 3]; 4], p: &[[i64; 3]; 3], ch: &[Option<[i64; 3]>; 3]) -> bool {
    !(0..3).any(|i| matches!(ch[i], Some(d) if t.contains(&crate::stuffing::cases::add(p[i], d))))
}

fn problem(ci: usize, c: &FaceCase, a: &Alphas) -> Problem {
    let geo: Vec<Geo> = c.v.iter().map(|s| Geo::new(s, a)).collect();
    let mut dim = 0;
    let roles = geo
        .iter()
        .map(|g| {
            if g.param {
                dim += 1;
                Role::Var(dim - 1)
            } else {
                Role::Fixed
            }
        })
        .collect();
    Problem {
        case: ci,
        what: What::Face { exposed: false },
        verts: vec![0, 1, 2],
        roles,
        dim,
        geo,
    }
}

/// The result for one dagger row.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct DaggerResult {
    pub row: String,
    /// "free" (superset over all octrees) or "sampled-contexts".
    pub model: String,
    /// Number of sample octrees (sampled-contexts model).
    pub trees: usize,
    /// `K` of the all-contexts model: levels `0..=K` enumerated, the free model with
    /// `α·2^-K` above.
    pub levels: Option<u32>,
    pub uniform: f64,
    pub paper: f64,
    pub shapes: Vec<(String, [[i64; 3]; 4], u32, usize)>,
    pub raw: usize,
    pub distinct: usize,
    pub leaves: usize,
    pub unresolved: usize,
    /// Certified enclosure of the superset's supremum of the max plane angle (degrees,
    /// outward-rounded from the cosine enclosure).
    pub enclosure_deg: [f64; 2],
    pub cos_enclosure: [f64; 2],
    /// proven / exceeded-on-superset / undecided.
    pub verdict: String,
    /// The superset witness: the face's vertex segments (p, d; t = x·α) and the parameters.
    pub witness: Option<(Vec<Seg>, Vec<f64>, [[f64; 3]; 3], [f64; 2])>,
    pub seconds: f64,
}

fn acos_deg(x: f64) -> f64 {
    x.clamp(-1.0, 1.0).acos().to_degrees()
}

/// Branch and bound over every face case: a certified enclosure of the smallest cosine
/// (largest plane angle) over the superset, decided against the paper's value.
///
/// `context`: false = the free model (all 14 directions at every vertex of the finest
/// instance of each shape, a superset over all octrees); true = the sampled-context model
/// ([`face_cases_in_context`], exact directions but only the sampled octrees).
pub fn run(row: &Row, tol_deg: f64, context: bool, trees: usize) -> DaggerResult {
    run_within(row, tol_deg, context, trees, &crate::bnb::Budget::default())
}

/// Which configuration space a dagger run searches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// Every direction at every vertex of the finest instance of each shape.
    Free,
    /// The sampled octree contexts ([`face_cases_in_context`]), this many trees.
    Sampled(usize),
    /// Every octree context ([`super::contexts`]): instances of levels `0..=K` at their
    /// real coordinates, the free model with `α·2^-K` above.
    AllContexts(u32),
}

impl Model {
    pub fn name(self) -> &'static str {
        match self {
            Model::Free => "free",
            Model::Sampled(_) => "sampled-contexts",
            Model::AllContexts(_) => "all-contexts",
        }
    }
}

/// The default `K` of the all-contexts model.
pub const DEFAULT_LEVELS: u32 = 3;

/// [`run`] within a work budget: a run that exhausts it returns the verdict
/// `incomplete: ...` (no bound is claimed).
pub fn run_within(
    row: &Row,
    tol_deg: f64,
    context: bool,
    trees: usize,
    budget: &crate::bnb::Budget,
) -> DaggerResult {
    let model = if context {
        Model::Sampled(trees)
    } else {
        Model::Free
    };
    run_model(row, tol_deg, model, budget)
}

/// The face cases of a model, each group with the α it is searched with.
pub fn model_cases(model: Model, a: &Alphas) -> (Vec<(Vec<FaceCase>, Alphas)>, usize) {
    match model {
        Model::Free => {
            let (c, r) = face_cases(&shapes());
            (vec![(c, *a)], r)
        }
        Model::Sampled(trees) => {
            let (c, r, _) = face_cases_in_context(trees);
            (vec![(c, *a)], r)
        }
        Model::AllContexts(k) => {
            let (c, r) = super::contexts::face_cases_all_contexts(k);
            let (t, rt) = face_cases(&shapes());
            (
                vec![(c, *a), (t, super::contexts::tail_alphas(a, k))],
                r + rt,
            )
        }
    }
}

/// The face cases and problems of a model for a row (in the order certificates use).
pub fn model_problems(model: Model, a: &Alphas) -> (Vec<FaceCase>, Vec<Problem>, usize) {
    let (groups, raw) = model_cases(model, a);
    let mut cases = Vec::new();
    let mut probs = Vec::new();
    for (cs, al) in groups {
        for c in cs {
            probs.push(problem(cases.len(), &c, &al));
            cases.push(c);
        }
    }
    (cases, probs, raw)
}

/// A leaf of one problem's search: the dyadic cell `(depth, index)` of `[0,1]^dim` and
/// the smallest lower end of the cosine enclosures on it.
pub type DaggerLeaf = (u32, Vec<u64>, f64);

/// The thresholds of a dagger search: cos of the paper's value widened by 1e-15 (≫ the
/// f64 cos error, < 1 ulp) on both sides, and the target width in cosine.
fn thresholds(paper: f64, tol_deg: f64) -> (f64, f64, f64) {
    let thr = paper.to_radians().cos();
    (thr - 1e-15, thr + 1e-15, tol_deg.to_radians() * 0.5)
}

/// The stopping rule: must a cell with smallest lower end `l` be split, given the best
/// (smallest) attained cosine `b`? Monotone in `b` (b only decreases during a search),
/// so a checker may re-apply it with the final `b`.
fn needs_split(l: f64, b: f64, thr: (f64, f64, f64)) -> bool {
    let (thr_lo, thr_hi, tol) = thr;
    l < b - tol || (l < thr_hi && b >= thr_lo)
}

/// The depth limit of the dagger searches.
const DEPTH_LIMIT: u32 = 40;

/// The smallest cosine attained at the sample points of a cell (its centre and corners)
/// and where: the witnesses of the search.
fn best_point(pr: &Problem, x: &[f64]) -> Option<[f64; 2]> {
    pr.point(x).and_then(|v| {
        v.iter()
            .map(|y| [y.inf(), y.sup()])
            .min_by(|a, b| a[1].total_cmp(&b[1]))
    })
}

/// The dagger branch and bound on the face cases of `model`.
pub fn run_model(
    row: &Row,
    tol_deg: f64,
    model: Model,
    budget: &crate::bnb::Budget,
) -> DaggerResult {
    certify_model(row, tol_deg, model, budget).result
}

/// [`run_model`], keeping the leaves: a certificate `proofs check` re-verifies.
pub fn certify_model(
    row: &Row,
    tol_deg: f64,
    model: Model,
    budget: &crate::bnb::Budget,
) -> DaggerCertificate {
    let t0 = std::time::Instant::now();
    let (_, _, paper) = *DAGGERS
        .iter()
        .find(|d| d.0 == row.name)
        .expect("a dagger row");
    let a = Alphas::of(row);
    let (cases, probs, raw) = model_problems(model, &a);
    let thr = thresholds(paper, tol_deg);
    let best = AtomicU64::new(2.0f64.to_bits());
    let wit: Mutex<Option<(usize, Vec<f64>, [f64; 2])>> = Mutex::new(None);
    let offer = |pi: usize, x: &[f64], y: [f64; 2]| {
        if y[1] < f64::from_bits(best.load(Ordering::Relaxed)) {
            let mut w = wit.lock().unwrap_or_else(|e| e.into_inner());
            if y[1] < f64::from_bits(best.load(Ordering::Relaxed)) {
                best.store(y[1].to_bits(), Ordering::Relaxed);
                *w = Some((pi, x.to_vec(), y));
            }
        }
    };
    let leaves: Vec<Vec<DaggerLeaf>> = probs
        .par_iter()
        .enumerate()
        .map(|(pi, pr)| {
            let dim = pr.dim;
            let mut out = Vec::new();
            let mut stack: Vec<(Vec<f64>, Vec<f64>, u32)> =
                vec![(vec![0.0; dim], vec![1.0; dim], 0)];
            while let Some((lo, hi, d)) = stack.pop() {
                if !budget.charge(1) {
                    break;
                }
                let vals = pr.enclose(&lo, &hi);
                let c: Vec<f64> = (0..dim).map(|k| 0.5 * (lo[k] + hi[k])).collect();
                for x in std::iter::once(c.clone()).chain((0..1usize << dim).map(|m| {
                    (0..dim)
                        .map(|k| if m >> k & 1 == 1 { hi[k] } else { lo[k] })
                        .collect()
                })) {
                    if let Some(y) = best_point(pr, &x) {
                        offer(pi, &x, y);
                    }
                }
                let l = vals.iter().map(|v| v.inf()).fold(f64::INFINITY, f64::min);
                let b = f64::from_bits(best.load(Ordering::Relaxed));
                if needs_split(l, b, thr) && d < DEPTH_LIMIT && dim > 0 {
                    for m in 0..1usize << dim {
                        let (mut l2, mut h2) = (lo.clone(), hi.clone());
                        for k in 0..dim {
                            if m >> k & 1 == 1 {
                                l2[k] = c[k];
                            } else {
                                h2[k] = c[k];
                            }
                        }
                        stack.push((l2, h2, d + 1));
                    }
                } else {
                    // lo is dyadic with denominator 2^d: the index is exact.
                    let idx = lo
                        .iter()
                        .map(|&x| (x * (1u64 << d) as f64) as u64)
                        .collect();
                    out.push((d, idx, l));
                }
            }
            out
        })
        .collect();
    let exhausted = budget.is_exhausted().then(|| budget.message());
    let witness = wit.into_inner().unwrap_or(None);
    let result = summarize(
        row,
        model,
        &cases,
        &probs,
        raw,
        thr,
        &leaves,
        witness.clone(),
        exhausted,
        t0.elapsed().as_secs_f64(),
    );
    DaggerCertificate {
        format: DAGGER_FORMAT.to_string(),
        row: row.name.to_string(),
        model: model.name().to_string(),
        trees: result.trees,
        levels: result.levels,
        tol_deg,
        leaves,
        best: witness,
        result,
    }
}

/// Every derived field of a dagger result, from the leaves and the best point: the
/// search and the checker share it.
#[allow(clippy::too_many_arguments)]
fn summarize(
    row: &Row,
    model: Model,
    cases: &[FaceCase],
    probs: &[Problem],
    raw: usize,
    thr: (f64, f64, f64),
    leaves: &[Vec<DaggerLeaf>],
    best: Option<(usize, Vec<f64>, [f64; 2])>,
    exhausted: Option<String>,
    seconds: f64,
) -> DaggerResult {
    let (_, uniform, paper) = *DAGGERS
        .iter()
        .find(|d| d.0 == row.name)
        .expect("a dagger row");
    let sh = shapes();
    let lo = leaves
        .iter()
        .flatten()
        .map(|l| l.2)
        .fold(f64::INFINITY, f64::min);
    let hi = best.as_ref().map_or(2.0, |b| b.2[1]);
    let unresolved = leaves
        .iter()
        .flatten()
        .filter(|l| needs_split(l.2, hi, thr))
        .count();
    let (thr_lo, thr_hi, _) = thr;
    let verdict = if let Some(m) = exhausted {
        format!("incomplete: {m}")
    } else if lo >= thr_hi {
        "proven".to_string()
    } else if hi < thr_lo {
        "exceeded-on-superset".to_string()
    } else {
        "undecided".to_string()
    };
    let witness = best.map(|(pi, x, cos)| {
        let pr = &probs[pi];
        let pos: Vec<[f64; 3]> = (0..3)
            .map(|k| pr.geo[k].at_f64(pr.roles[k], &x).map(|c| 0.5 * c))
            .collect();
        (cases[pi].v.to_vec(), x, [pos[0], pos[1], pos[2]], cos)
    });
    DaggerResult {
        row: row.name.to_string(),
        model: model.name().to_string(),
        trees: match model {
            Model::Sampled(n) => n,
            _ => 0,
        },
        levels: match model {
            Model::AllContexts(k) => Some(k),
            _ => None,
        },
        uniform,
        paper,
        shapes: sh
            .iter()
            .map(|s| (format!("{:?}", s.kind), s.v, s.level, s.instances))
            .collect(),
        raw,
        distinct: cases.len(),
        leaves: leaves.iter().map(|l| l.len()).sum(),
        unresolved,
        // acos is decreasing; widen by 1e-9° for the f64 acos.
        enclosure_deg: [acos_deg(hi) - 1e-9, acos_deg(lo) + 1e-9],
        cos_enclosure: [lo, hi],
        verdict,
        witness,
        seconds,
    }
}

/// The format name of a dagger certificate.
pub const DAGGER_FORMAT: &str = "certmesh-graded-dagger/1";

/// A dagger run with its leaves: `proofs check` re-derives the cases of the model,
/// checks that each problem's leaves partition its box, re-evaluates every leaf and the
/// best point, re-applies the stopping rule and recomputes every field of `result`.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct DaggerCertificate {
    pub format: String,
    pub row: String,
    pub model: String,
    pub trees: usize,
    pub levels: Option<u32>,
    pub tol_deg: f64,
    /// Per problem (in [`model_problems`] order), its leaves.
    pub leaves: Vec<Vec<DaggerLeaf>>,
    /// The best point: problem, parameters, the cosine enclosure there.
    pub best: Option<(usize, Vec<f64>, [f64; 2])>,
    pub result: DaggerResult,
}

/// Re-verify a dagger certificate (see [`DaggerCertificate`]); returns the recomputed
/// result, equal to the stated one in every field but `seconds`.
pub fn check_dagger(cert: &DaggerCertificate) -> Result<DaggerResult, String> {
    if cert.format != DAGGER_FORMAT {
        return Err(format!("format: unknown format `{}`", cert.format));
    }
    let row = certmesh::stuffing::row(&cert.row).map_err(|e| format!("row: {e}"))?;
    let (_, _, paper) = *DAGGERS
        .iter()
        .find(|d| d.0 == row.name)
        .ok_or_else(|| format!("row: `{}` has no dagger bound", cert.row))?;
    let model = match (cert.model.as_str(), cert.levels) {
        ("free", None) => Model::Free,
        ("sampled-contexts", None) if cert.trees > 0 => Model::Sampled(cert.trees),
        ("all-contexts", Some(k)) if (1..=6).contains(&k) => Model::AllContexts(k),
        (m, k) => return Err(format!("model: `{m}` with levels {k:?} is not a model")),
    };
    if !(cert.tol_deg >= super::MIN_TOL_DEG && cert.tol_deg <= 90.0) {
        return Err(format!("tol_deg: {} out of range", cert.tol_deg));
    }
    let thr = thresholds(paper, cert.tol_deg);
    let a = Alphas::of(row);
    let (cases, probs, raw) = model_problems(model, &a);
    if cert.leaves.len() != probs.len() {
        return Err(format!(
            "leaves: {} problems in the certificate, {} in the model",
            cert.leaves.len(),
            probs.len()
        ));
    }
    // The best point first: the stopping rule is re-applied with it.
    let best = match &cert.best {
        None => None,
        Some((pi, x, y)) => {
            let pr = probs
                .get(*pi)
                .ok_or_else(|| format!("best: problem {pi} does not exist"))?;
            if x.len() != pr.dim || x.iter().any(|v| !(0.0..=1.0).contains(v)) {
                return Err("best: the point is not in its problem's box".into());
            }
            let z = best_point(pr, x).ok_or("best: the point does not evaluate")?;
            if z != *y {
                return Err(format!("best: recomputed {z:?}, stated {y:?}"));
            }
            Some((*pi, x.clone(), z))
        }
    };
    let b = best.as_ref().map_or(2.0, |w| w.2[1]);
    probs
        .par_iter()
        .zip(&cert.leaves)
        .enumerate()
        .try_for_each(|(pi, (pr, ls))| -> Result<(), String> {
            let cells: Vec<(u8, Vec<u64>)> = ls
                .iter()
                .map(|l| (l.0.min(255) as u8, l.1.clone()))
                .collect();
            if ls.iter().any(|l| l.0 > DEPTH_LIMIT || l.1.len() != pr.dim) {
                return Err(format!(
                    "leaves[{pi}]: a leaf has the wrong depth or dimension"
                ));
            }
            super::check::check_partition(pr.dim, &cells)
                .map_err(|e| format!("leaves[{pi}]: {e}"))?;
            for (d, idx, l) in ls {
                let w = 1.0 / (1u64 << d) as f64;
                let lo: Vec<f64> = idx.iter().map(|&i| i as f64 * w).collect();
                let hi: Vec<f64> = lo.iter().map(|x| x + w).collect();
                let v = pr
                    .enclose(&lo, &hi)
                    .iter()
                    .map(|v| v.inf())
                    .fold(f64::INFINITY, f64::min);
                if v.to_bits() != l.to_bits() {
                    return Err(format!(
                        "leaves[{pi}]: cell {d}/{idx:?} encloses from {v}, stated {l}"
                    ));
                }
                if *d < DEPTH_LIMIT && pr.dim > 0 && needs_split(v, b, thr) {
                    return Err(format!(
                        "leaves[{pi}]: cell {d}/{idx:?} should have been split"
                    ));
                }
            }
            Ok(())
        })?;
    let r = summarize(
        row,
        model,
        &cases,
        &probs,
        raw,
        thr,
        &cert.leaves,
        best,
        cert.result
            .verdict
            .strip_prefix("incomplete: ")
            .map(str::to_string),
        cert.result.seconds,
    );
    crate::fields::same("result", &cert.result, &r)?;
    Ok(r)
}

/// The realised 147.0470° counterexample (README, mesher test
/// `graded_dagger_147_is_exceeded_on_a_half_pyramid`): the level-0 half-pyramid with
/// apex the fine cube centre (1,1,1) (unwarped) and base diagonal (2,0,0)–(2,2,2) on the
/// face x = 2 bordering a coarse octant; both diagonal ends warped *away* from the apex
/// along red edges into the neighbouring fine cubes, by `t` of the red edge (t < ½ with
/// the strict rule). Returns the interval cosine of the angle at the apex.
pub fn half_pyramid_witness_cos(t: f64) -> Interval {
    let tt = pt(t);
    let v = |p: [f64; 3], d: [f64; 3]| -> V3 {
        [0, 1, 2].map(|k| crate::stuffing::eval::Dn::cst(pt(p[k]) + tt * pt(d[k])))
    };
    let c = v([1.0, 1.0, 1.0], [0.0; 3]);
    let r0 = v([2.0, 0.0, 0.0], [-1.0, -1.0, -1.0]);
    let r2 = v([2.0, 2.0, 2.0], [-1.0, 1.0, 1.0]);
    cos_plane(&c, &r0, &r2).v
}

/// Face cases from canonical descriptors and their multiplicities (sorted by descriptor).
pub(crate) fn collect_face_cases(map: BTreeMap<Vec<Seg>, usize>) -> Vec<FaceCase> {
    map.into_iter()
        .map(|(k, multiplicity)| FaceCase {
            v: [k[0], k[1], k[2]],
            multiplicity,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn continuation_filter_rejects_a_red_warp_across_an_interface() {
        let mut t = sample_trees_n(1).swap_remove(0);
        // P = [4,8]^3 is fine. Corner (8,6,6) on its face x = 8, centre (7,5,5) of the
        // fine cube [6,8]x[4,6]x[4,6]: its neighbour across x = 8, idx [4,2,2], decides.
        t.remove(&(0, [4, 2, 2]));
        assert!(!continuation_ok(&t, [8, 6, 6], [-1, -1, -1]));
        t.insert((0, [4, 2, 2]));
        t.insert((0, [4, 3, 2]));
        t.insert((0, [4, 2, 3]));
        assert!(continuation_ok(&t, [8, 6, 6], [-1, -1, -1]));
        // Interior corner (6,6,6): all fine.
        assert!(continuation_ok(&t, [6, 6, 6], [-1, -1, -1]));
    }
}

#[cfg(test)]
mod witness_tests {
    use super::*;

    /// The realised counterexample to 147.0470° (mesher test
    /// `graded_dagger_147_is_exceeded_on_a_half_pyramid`), by interval arithmetic: at
    /// t = 0.49 (< ½, strict rule) the apex angle is certified > 147.0470°, and its cosine
    /// tends to −17/19 as t → ½.
    #[test]
    fn half_pyramid_witness_exceeds_147_0470() {
        let c = half_pyramid_witness_cos(0.49);
        assert!(c.sup() < 147.0470f64.to_radians().cos() - 1e-12, "{c:?}");
        let c5 = half_pyramid_witness_cos(0.5);
        assert!(c5.inf() <= -17.0 / 19.0 + 1e-12 && c5.sup() >= -17.0 / 19.0 - 1e-12);
        // Unwarped: the half-pyramid's own apex angle over the blue diagonal, 109.47°.
        let c0 = half_pyramid_witness_cos(0.0);
        assert!(c0.inf() <= -1.0 / 3.0 + 1e-12 && c0.sup() >= -1.0 / 3.0 - 1e-12);
    }

    /// The witness configuration is one of the enumerated faces (free model), so the
    /// enumeration covers it; and the free model's three shapes are the three non-BCC kinds.
    #[test]
    fn witness_face_is_enumerated_and_shapes_are_the_three_kinds() {
        let sh = shapes();
        let kinds: HashSet<String> = sh.iter().map(|s| format!("{:?}", s.kind)).collect();
        assert_eq!(kinds.len(), 3, "{sh:?}");
        assert!(!kinds.contains("Bcc"));
        let (cases, _) = face_cases(&sh);
        let w = canonical(
            &[
                Seg::fixed([1, 1, 1]),
                Seg::warp([2, 0, 0], [-1, -1, -1]),
                Seg::warp([2, 2, 2], [-1, 1, 1]),
            ],
            &Sym::all(),
        );
        assert!(cases.iter().any(|c| c.v.to_vec() == w));
    }
}

#[cfg(test)]
mod run_tests {
    use super::*;

    /// A small graded case end to end: two sample octrees, row min-exposed-safe-ordered;
    /// the realised half-pyramid configuration is in the sample, so the certified
    /// supremum exceeds 147.0470° and is arccos(−17/19); the realisable faces never
    /// reach 180° (the continuation filter excludes the free model's degenerate faces).
    #[test]
    fn small_sample_exceeds_147_0470_and_stays_below_180() {
        let r = certmesh::stuffing::row("min-exposed-safe-ordered").expect("row");
        let res = run(r, 1e-3, true, 2);
        assert_eq!(res.verdict, "exceeded-on-superset", "{res:?}");
        assert!(res.unresolved == 0 && res.leaves > 0);
        let c = -17.0f64 / 19.0;
        assert!(
            res.cos_enclosure[0] <= c + 1e-9 && res.cos_enclosure[1] >= c - 1e-6,
            "{res:?}"
        );
    }
}

#[cfg(test)]
mod all_contexts_tests {
    use super::*;

    /// The all-contexts model with levels 0..=1 (the free model with α/2 above) proves
    /// the 158.1918° dagger; its certificate passes the checker, and the checker rejects
    /// a changed leaf value, a missing leaf, a changed verdict and a moved best point.
    #[test]
    fn all_contexts_proves_158_1918_and_the_checker_rejects_tampering() {
        let r = certmesh::stuffing::row("min-exposed-unsafe").expect("row");
        let b = crate::bnb::Budget::default();
        let cert = certify_model(r, 1e-3, Model::AllContexts(1), &b);
        assert_eq!(cert.result.verdict, "proven", "{:?}", cert.result);
        assert!(cert.result.enclosure_deg[1] < 158.1918);
        // Attained (the paper's configuration): the enclosure is tight.
        assert!(cert.result.enclosure_deg[0] > 158.19);
        let ok = check_dagger(&cert).expect("the certificate checks");
        assert_eq!(ok.verdict, "proven");

        let (pi, _) = cert
            .leaves
            .iter()
            .enumerate()
            .find(|(_, l)| l.len() > 1)
            .expect("a split problem");
        let mut c = cert.clone();
        c.leaves[pi][0].2 -= 1e-9;
        assert!(check_dagger(&c).unwrap_err().contains("encloses from"));
        let mut c = cert.clone();
        c.leaves[pi].pop();
        assert!(check_dagger(&c).unwrap_err().contains("cover"));
        let mut c = cert.clone();
        c.result.verdict = "exceeded-on-superset".into();
        assert!(check_dagger(&c).unwrap_err().contains("verdict"));
        let mut c = cert.clone();
        if let Some(bp) = &mut c.best {
            bp.2[1] += 1e-6;
        }
        assert!(check_dagger(&c).unwrap_err().contains("best"));
        // A model the certificate was not made with.
        let mut c = cert;
        c.levels = Some(2);
        assert!(check_dagger(&c).is_err());
    }

    /// The safe property of the non-BCC tetrahedra over the all-contexts model: proven
    /// for both dagger rows (the ordered row's α_short = ½ reaches volume 0 only at a
    /// warp of exactly α, which the strict rule excludes; the unsafe row stays away
    /// from 0).
    #[test]
    fn non_bcc_safe_property_over_all_contexts() {
        use crate::stuffing::contexts::safe_non_bcc;
        for (row, zero) in [
            ("min-exposed-unsafe", false),
            ("min-exposed-safe-ordered", true),
        ] {
            let a = Alphas::of(certmesh::stuffing::row(row).expect("row"));
            let s = safe_non_bcc(&a, 1);
            assert!(s.verdict.starts_with("proven"), "{row}: {s:?}");
            assert_eq!(s.min_ratio == 0.0, zero, "{row}: {s:?}");
            assert!(s.configurations > 100_000);
        }
    }
}
