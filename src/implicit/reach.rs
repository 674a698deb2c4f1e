//! A certified lower bound of the reach τ of S = {f = 0} ∩ D, the oracle operation
//! behind ψ ≤ ε·lfs in Boissonnat–Oudot refinement (the chapter "Meshing of Surfaces",
//! Boissonnat et al., 2007, §1.3.1; its research problem 2 of §1.6 asks whether
//! interval arithmetic can give a conservative lower bound ψ).
//!
//! **Theorem used.** For a compact C² surface without boundary, τ = min(1/κ_max, Δ/2),
//! with κ_max the largest absolute normal curvature and Δ the length of the shortest
//! chord [x, y] (x ≠ y) normal to S at both ends (a "bottleneck"; Aamari, Kim, Chazal,
//! Michel, Rinaldo and Wasserman, "Estimating the reach of a manifold", Electronic
//! Journal of Statistics, 2019, Theorem 3.4, after Federer, "Curvature measures",
//! 1959). Since lfs ≥ τ everywhere, a constant ψ ≤ 0.1·τ̄ is 1-Lipschitz and ≤ 0.1·lfs.
//!
//! **Hypotheses, checked.** 0 ∉ □f on the six faces of D (S ∩ D is closed and away
//! from ∂D; [`super::critical::boundary_clear`]); f proven C^∞ and 0 ∉ □|∇f|² on every
//! leaf box that may meet S (S is a regular C² surface there).
//!
//! **Curvature.** Octree boxes B with 0 ∈ □f(B) cover S. For a unit tangent t at
//! x ∈ S ∩ B the normal curvature is tᵀH(x)t/|∇f(x)|; with P = I − nnᵀ the tangent
//! projector, |κ| ≤ max|eig(PHP)| / |∇f|, bounded over the box from interval
//! enclosures of the trace and Frobenius norm of PHP, or by ‖H‖_F or the ∞-norm of
//! □H(B) when smaller (`tangent_curvature_bound`). The box with the largest bound is
//! split first (best-first), down to `max_depth`: κ̄ is the largest bound left.
//!
//! **Bottleneck.** Prove that no double-normal chord is shorter than Δ₀ by a dual-tree
//! branch-and-bound over pairs of S-boxes (A, B), starting from (D, D). A pair is
//! dropped when (1) the boxes are at least Δ₀ apart; (2) some component of
//! (□B − □A) × □∇f(A) (or × □∇f(B)) excludes 0: no chord from A to B is parallel to
//! the normal at its end in A (or in B); (3) the hull C of A ∪ B has small normal
//! variation, 0 < inf Σ_k □∂_k f(C)·□∂_k f(C): for x ≠ y in S ∩ C, f(y) − f(x) = 0 =
//! ∇f(ξ)·(y − x) for some ξ ∈ [x, y] ⊂ C, so y − x ⊥ ∇f(ξ); if also y − x ∥ ∇f(x)
//! then ∇f(x) ⊥ ∇f(ξ), excluded. Otherwise the shallower box is split. A pair still
//! standing at `max_depth` makes the attempt fail; Δ₀ is then lowered (up to
//! `attempts` times).
//!
//! Then τ̄ = min(1/κ̄, Δ₀/2) ≤ τ. Measured tightness is reported beside the true reach.
use super::critical::{boundary_clear, Bx};
use super::ops::enclose;
use super::{IBox, Implicit, Regularity};
use inari::Interval;
use serde::Serialize;
use std::collections::{BinaryHeap, HashMap};

/// Limits of [`reach_lower_bound`].
#[derive(Clone, Copy, Debug)]
pub struct ReachOptions {
    /// Octree depth of the leaf boxes (width 2^-depth of D's).
    pub max_depth: u32,
    /// Box evaluations allowed (curvature and bottleneck together).
    pub max_boxes: usize,
    /// Box pairs allowed in the bottleneck search.
    pub max_pairs: usize,
    /// Δ₀ tries, each 0.7 times the previous, starting from 1.9/κ̄.
    pub attempts: u32,
}

impl Default for ReachOptions {
    fn default() -> Self {
        ReachOptions {
            max_depth: 9,
            max_boxes: 400_000,
            max_pairs: 3_000_000,
            attempts: 5,
        }
    }
}

/// The result of [`reach_lower_bound`].
#[derive(Clone, Debug, Default, Serialize)]
pub struct ReachBound {
    /// τ̄ ≤ reach(S), certified; `None` with `reason` when not proven.
    pub tau: Option<f64>,
    /// κ̄ ≥ every absolute normal curvature of S.
    pub curvature_bound: Option<f64>,
    /// Δ₀: no double-normal chord of S is shorter.
    pub bottleneck_bound: Option<f64>,
    pub reason: Option<String>,
    /// Leaf boxes that may meet S.
    pub surface_boxes: usize,
    pub boxes: usize,
    pub pairs: usize,
}

#[derive(Clone, Copy)]
struct Node {
    b: IBox,
    /// 0 ∈ □f(b) (the box may meet S).
    surface: bool,
    smooth: bool,
    grad: [Interval; 3],
}

type Key = (u32, u64, u64, u64);

struct Tree<'a> {
    f: &'a dyn Implicit,
    d: Bx,
    memo: HashMap<Key, Node>,
    boxes: usize,
}

impl<'a> Tree<'a> {
    fn node(&mut self, k: Key) -> Node {
        if let Some(n) = self.memo.get(&k) {
            return *n;
        }
        let (depth, ix, iy, iz) = k;
        let s = (1u64 << depth) as f64;
        let idx = [ix, iy, iz];
        let b: IBox = [0, 1, 2].map(|a| {
            let w = self.d.hi[a] - self.d.lo[a];
            let lo = self.d.lo[a] + w * (idx[a] as f64 / s);
            let hi = if idx[a] + 1 == 1u64 << depth {
                self.d.hi[a]
            } else {
                self.d.lo[a] + w * ((idx[a] + 1) as f64 / s)
            };
            Interval::try_from((lo, hi)).unwrap_or(Interval::ENTIRE)
        });
        self.boxes += 1;
        let (v, g) = enclose(self.f, &b);
        let n = Node {
            b,
            surface: !(v.inf() > 0.0 || v.sup() < 0.0),
            smooth: self.f.regularity(&b) == Regularity::Smooth,
            grad: g,
        };
        self.memo.insert(k, n);
        n
    }
    fn children(&mut self, k: Key) -> Vec<Key> {
        let (d, x, y, z) = k;
        let mut out = Vec::with_capacity(8);
        for c in 0..8u64 {
            let ck = (
                d + 1,
                2 * x + (c & 1),
                2 * y + (c >> 1 & 1),
                2 * z + (c >> 2 & 1),
            );
            if self.node(ck).surface {
                out.push(ck);
            }
        }
        out
    }
}

/// An upper bound of |tᵀHt|/|∇f| over unit t ⊥ ∇f, for ∇f ∈ `g`, H ∈ `hp` (packed
/// `[xx, xy, xz, yy, yz, zz]`): with n = ∇f/|∇f| and P = I − nnᵀ (interval
/// enclosures), M = PHP is symmetric with Mn = 0, so its eigenvalues are 0, λ₁, λ₂
/// (the normal curvatures' extremes times |∇f|), and
/// max|λᵢ| = (|tr M| + √(2‖M‖²_F − (tr M)²)) / 2.
fn tangent_curvature_bound(g: &[Interval; 3], hp: &[Interval; 6], g2: Interval) -> Option<f64> {
    let norm = g2.sqrt();
    let n: [Interval; 3] = [0, 1, 2].map(|k| g[k] / norm);
    let one = Interval::try_from((1.0, 1.0)).unwrap();
    let zero = Interval::try_from((0.0, 0.0)).unwrap();
    let idx = |i: usize, j: usize| -> usize {
        let (a, b) = (i.min(j), i.max(j));
        [[0, 1, 2], [1, 3, 4], [2, 4, 5]][a][b]
    };
    let p: [[Interval; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| (if i == j { one } else { zero }) - n[i] * n[j])
    });
    let h: [[Interval; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| hp[idx(i, j)]));
    let mul = |a: &[[Interval; 3]; 3], b: &[[Interval; 3]; 3]| -> [[Interval; 3]; 3] {
        std::array::from_fn(|i| {
            std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j])
        })
    };
    let m = mul(&mul(&p, &h), &p);
    let tr = m[0][0] + m[1][1] + m[2][2];
    let mut f2 = zero;
    for row in &m {
        for x in row {
            f2 = f2 + x.sqr();
        }
    }
    let two = Interval::try_from((2.0, 2.0)).unwrap();
    let disc = two * f2 - tr.sqr();
    if tr.is_empty() || disc.is_empty() || !f2.sup().is_finite() {
        return None;
    }
    let lam = (tr.mag() + disc.sup().max(0.0).sqrt()) * 0.5;
    // Fall back to ‖H‖_F ≥ ‖H‖₂ when it is smaller (wide boxes: n enters PHP four
    // times, and the interval product does not know it is the same n).
    let mut fh = zero;
    for row in &h {
        for x in row {
            fh = fh + x.sqr();
        }
    }
    // And the ∞-norm (Gershgorin): for a symmetric matrix it bounds the spectral norm.
    let gersh = h
        .iter()
        .map(|row| row.iter().map(|x| x.mag()).sum::<f64>())
        .fold(0.0f64, f64::max)
        * (1.0 + 1e-12);
    let lam = lam.min(fh.sup().sqrt()).min(gersh);
    let k = lam / norm.inf() * (1.0 + 1e-12);
    (k.is_finite() && norm.inf() > 0.0).then_some(k)
}

fn excl(i: Interval) -> bool {
    !i.is_empty() && (i.inf() > 0.0 || i.sup() < 0.0)
}

fn cross(a: [Interval; 3], b: [Interval; 3]) -> [Interval; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A certified lower bound of the reach of S = {f = 0} ∩ `domain` (module doc).
pub fn reach_lower_bound(f: &dyn Implicit, domain: Bx, opts: ReachOptions) -> ReachBound {
    let mut r = ReachBound::default();
    let fail = |mut r: ReachBound, why: String| {
        r.reason = Some(why);
        r
    };
    if !f.is_rigorous() {
        return fail(r, "the oracle's interval methods are not rigorous".into());
    }
    if !boundary_clear(f, domain, 16, opts.max_boxes) {
        return fail(
            r,
            "the surface meets the domain boundary (0 not excluded on a face)".into(),
        );
    }
    let mut tree = Tree {
        f,
        d: domain,
        memo: HashMap::new(),
        boxes: 0,
    };
    let root: Key = (0, 0, 0, 0);
    if !tree.node(root).surface {
        return fail(r, "S is empty (0 excluded on the whole domain)".into());
    }
    // Curvature, best first.
    let kappa = |n: &Node, f: &dyn Implicit| -> Option<f64> {
        if !n.smooth {
            return None;
        }
        let h = f.hessian_interval(&n.b);
        let g2 = h.g[0].sqr() + h.g[1].sqr() + h.g[2].sqr();
        if !(g2.inf() > 0.0) {
            return None;
        }
        let k = tangent_curvature_bound(&h.g, &h.h, g2).unwrap_or(f64::INFINITY);
        k.is_finite().then_some(k)
    };
    #[derive(PartialEq)]
    struct Item(f64, Key);
    impl Eq for Item {}
    impl PartialOrd for Item {
        fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
            Some(self.cmp(o))
        }
    }
    impl Ord for Item {
        fn cmp(&self, o: &Self) -> std::cmp::Ordering {
            self.0.total_cmp(&o.0).then(self.1.cmp(&o.1))
        }
    }
    let mut heap = BinaryHeap::new();
    heap.push(Item(f64::INFINITY, root));
    let mut leaves = 0usize;
    let kbar = loop {
        let Some(Item(k, key)) = heap.pop() else {
            break 0.0; // no box meets S at the leaf depth
        };
        if tree.boxes > opts.max_boxes {
            return fail(
                r,
                format!(
                    "box budget ({}) spent bounding the curvature",
                    opts.max_boxes
                ),
            );
        }
        if key.0 >= opts.max_depth {
            if k.is_finite() {
                leaves = heap.len() + 1;
                break k;
            }
            let n = tree.node(key);
            return fail(
                r,
                format!(
                    "possible singular point or non-smooth f near {:?}: 0 in |grad f|^2 or f not proven smooth at the leaf depth",
                    Bx::from_ibox(&n.b).mid()
                ),
            );
        }
        for c in tree.children(key) {
            let n = tree.node(c);
            let kc = kappa(&n, f).unwrap_or(f64::INFINITY);
            heap.push(Item(kc, c));
        }
    };
    r.surface_boxes = leaves;
    if kbar == 0.0 {
        return fail(r, "no leaf box meets S".into());
    }
    r.curvature_bound = Some(kbar);
    // Bottleneck.
    let mut delta = 1.9 / kbar;
    for _ in 0..opts.attempts {
        match no_short_double_normal(&mut tree, delta, opts, &mut r.pairs) {
            Ok(()) => {
                r.bottleneck_bound = Some(delta);
                r.tau = Some((1.0 / kbar).min(0.5 * delta));
                r.boxes = tree.boxes;
                return r;
            }
            Err(stop) => {
                if stop {
                    break;
                }
                delta *= 0.7;
            }
        }
    }
    r.boxes = tree.boxes;
    fail(
        r,
        format!("could not exclude double-normal chords shorter than {delta:.3e} (pair budget or depth)"),
    )
}

/// Err(true): budget spent (stop); Err(false): a pair survived at the leaf depth.
fn no_short_double_normal(
    tree: &mut Tree,
    delta: f64,
    opts: ReachOptions,
    pairs: &mut usize,
) -> Result<(), bool> {
    let root: Key = (0, 0, 0, 0);
    let mut stack: Vec<(Key, Key)> = vec![(root, root)];
    while let Some((ka, kb)) = stack.pop() {
        *pairs += 1;
        if *pairs > opts.max_pairs || tree.boxes > opts.max_boxes {
            return Err(true);
        }
        let a = tree.node(ka);
        let b = tree.node(kb);
        // (1) distance.
        let gap2: f64 = (0..3)
            .map(|k| {
                let g = (b.b[k].inf() - a.b[k].sup()).max(a.b[k].inf() - b.b[k].sup());
                if g > 0.0 {
                    // round down
                    (g * (1.0 - 1e-12)).powi(2) * (1.0 - 1e-12)
                } else {
                    0.0
                }
            })
            .sum();
        if gap2 >= delta * delta * (1.0 + 1e-9) {
            continue;
        }
        // (2) normality.
        let chord: [Interval; 3] = [0, 1, 2].map(|k| b.b[k] - a.b[k]);
        if a.smooth && cross(chord, a.grad).into_iter().any(excl) {
            continue;
        }
        if b.smooth && cross(chord, b.grad).into_iter().any(excl) {
            continue;
        }
        // (3) small normal variation on the hull.
        let hull: IBox = [0, 1, 2].map(|k| a.b[k].convex_hull(b.b[k]));
        if tree.f.regularity(&hull) == Regularity::Smooth {
            let g = tree.f.grad_interval(&hull).g;
            let dot = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
            if !dot.is_empty() && dot.inf() > 0.0 {
                continue;
            }
        }
        if ka.0 >= opts.max_depth && kb.0 >= opts.max_depth {
            return Err(false);
        }
        if ka == kb {
            let ch = tree.children(ka);
            for i in 0..ch.len() {
                for j in i..ch.len() {
                    stack.push((ch[i], ch[j]));
                }
            }
        } else if ka.0 <= kb.0 {
            for c in tree.children(ka) {
                stack.push((c, kb));
            }
        } else {
            for c in tree.children(kb) {
                stack.push((ka, c));
            }
        }
    }
    Ok(())
}
