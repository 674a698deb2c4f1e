//! Generic position: a rigid motion of the grid (the chapter's shifted grid).
//!
//! The moved grid meshes a rotated box containing the domain, so its proof is about
//! f = 0 inside that box. [`GenericMotion::outside_domain`] proves that f = 0 does not
//! meet the rotated box outside the domain, which turns it into a proof about f = 0
//! inside the domain (or names where it could not).
use crate::implicit::{IBox, Implicit};
use crate::kernel::geom::Aabb;
use crate::mesher::Uncertified;
use crate::subdivision::{enclose, excludes_zero, Tree, Verdict};
use inari::Interval;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};

/// The start of the reason of a region where f = 0 may meet the meshed rotated box
/// outside the domain (the isotopy is then proven for a set that is not f = 0 inside
/// the domain, and nothing is claimed).
pub const OUTSIDE_DOMAIN_REASON: &str = "f = 0 may meet the rotated box outside the domain";
/// Bisection levels below a leaf that the search of [`GenericMotion::outside_domain`]
/// may go.
pub const OUTSIDE_EXTRA_LEVELS: u32 = 8;
/// Boxes the search of [`GenericMotion::outside_domain`] may test in all (each test is
/// one interval image and at most 2·dim enclosures of f).
pub const OUTSIDE_MAX_BOXES: u64 = 1 << 18;
/// Failed leaves beyond which [`GenericMotion::outside_domain`] reports one region per
/// leaf instead of grouping touching leaves (the grouping is quadratic).
const OUTSIDE_GROUP_MAX: usize = 4096;

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
    /// An enclosure of the image R b + t of a box `b` of the moved coordinates (interval
    /// arithmetic: the image lies inside it, also for the float matrix R).
    pub fn map_ibox(&self, b: &IBox) -> IBox {
        let c = crate::implicit::number::point;
        [0, 1, 2].map(|i| {
            c(self.rot[i][0]) * b[0]
                + c(self.rot[i][1]) * b[1]
                + c(self.rot[i][2]) * b[2]
                + c(self.shift[i])
        })
    }
    /// Is f = 0 proven absent from the image of the moved box `b` outside `domain`
    /// (the first `dim` axes)? The image lies in the enclosure H of [`Self::map_ibox`];
    /// H outside the domain is covered by at most 2·dim closed slabs (H cut by a face
    /// plane of the domain, on the far side), each an axis-aligned box on which the
    /// enclosure of f must exclude 0 strictly (as for an empty leaf). A box whose
    /// image is inside the domain has no slab. A slab where f is undefined everywhere
    /// is not proven.
    fn outside_free(&self, f: &dyn Implicit, b: &IBox, domain: &Aabb, dim: usize) -> bool {
        let h = self.map_ibox(b);
        if h.iter().any(|x| x.is_empty()) {
            return false;
        }
        for k in 0..dim {
            let (lo, hi) = (h[k].inf(), h[k].sup());
            let mut slabs = Vec::new();
            if lo < domain.min[k] {
                slabs.push((lo, domain.min[k].min(hi)));
            }
            if hi > domain.max[k] {
                slabs.push((domain.max[k].max(lo), hi));
            }
            for (a, z) in slabs {
                let mut s = h;
                match Interval::try_from((a, z)) {
                    Ok(i) => s[k] = i,
                    Err(_) => return false,
                }
                let plain = f.eval_interval(&s);
                if plain.is_empty() || !excludes_zero(plain) && !excludes_zero(enclose(f, &s).0) {
                    return false;
                }
            }
        }
        true
    }
    /// The regions where f = 0 may meet the rotated box outside the domain, each as
    /// an [`Uncertified`] region of the original coordinates (empty: proven that it
    /// does not, so f = 0 inside the rotated box is f = 0 inside the domain).
    ///
    /// `tree` is the subdivision of the moved box `self.domain` of `f`'s moved oracle;
    /// its leaves cover the moved box. A leaf proven free of f = 0 ([`Verdict::Empty`])
    /// needs nothing; a leaf that failed is reported by the subdivision already. Every
    /// other leaf must be proven free of f = 0 outside the domain: by
    /// [`Self::outside_free`] on the leaf, else on its bisections (in the moved
    /// frame, at most [`OUTSIDE_EXTRA_LEVELS`] levels, [`OUTSIDE_MAX_BOXES`] boxes in
    /// all, stopped by `deadline`). Leaves not proven are grouped where they touch, and
    /// each group is one region, named by the first sub-box the search could not prove.
    pub fn outside_domain(
        &self,
        f: &dyn Implicit,
        tree: &Tree,
        domain: &Aabb,
        deadline: Option<std::time::Instant>,
    ) -> Vec<Uncertified> {
        let dim = tree.grid.dim;
        let used = AtomicU64::new(0);
        let stopped = AtomicBool::new(false);
        // (leaf index, the first sub-box not proven, why the search ended)
        let failed: Vec<(usize, IBox, &'static str)> = tree
            .leaves
            .par_iter()
            .enumerate()
            .filter(|(_, l)| matches!(l.verdict, Verdict::Proven { .. }))
            .filter_map(|(i, l)| {
                let ib = tree.grid.cell_ibox(l.cell);
                let mut stack = vec![(ib, 0u32)];
                while let Some((b, level)) = stack.pop() {
                    let n = used.fetch_add(1, Relaxed);
                    if n >= OUTSIDE_MAX_BOXES || stopped.load(Relaxed) {
                        stopped.store(true, Relaxed);
                        return Some((i, b, "the search ran out of its box budget or time"));
                    }
                    if n % 256 == 0 && deadline.is_some_and(|d| std::time::Instant::now() > d) {
                        stopped.store(true, Relaxed);
                        return Some((i, b, "the search ran out of its box budget or time"));
                    }
                    if self.outside_free(f, &b, domain, dim) {
                        continue;
                    }
                    if level >= OUTSIDE_EXTRA_LEVELS {
                        return Some((i, b, "not excluded by interval arithmetic"));
                    }
                    let mid = b.map(|x| x.mid());
                    let nz = if dim == 3 { 2 } else { 1 };
                    for m in 0..(4 * nz) {
                        let mut c = b;
                        for k in 0..dim {
                            let half = if m >> k & 1 == 0 {
                                Interval::try_from((b[k].inf(), mid[k]))
                            } else {
                                Interval::try_from((mid[k], b[k].sup()))
                            };
                            match half {
                                Ok(h) => c[k] = h,
                                Err(_) => {
                                    return Some((i, b, "not excluded by interval arithmetic"))
                                }
                            }
                        }
                        stack.push((c, level + 1));
                    }
                }
                None
            })
            .collect();
        // Group touching leaves (closed integer spans meet on every axis).
        // (Rem's joins keep every set's root at its smallest member: the first leaf.)
        let n = failed.len();
        let mut sets = crate::metrics::topology::UnionFind::for_join(n);
        if n <= OUTSIDE_GROUP_MAX {
            let spans: Vec<([u32; 3], [u32; 3])> = failed
                .iter()
                .map(|(i, _, _)| tree.grid.cell_lo_hi(tree.leaves[*i].cell))
                .collect();
            for a in 0..n {
                for b in a + 1..n {
                    let (la, ha) = spans[a];
                    let (lb, hb) = spans[b];
                    if (0..dim).all(|k| la[k] <= hb[k] && lb[k] <= ha[k]) {
                        sets.join(a as u32, b as u32);
                    }
                }
            }
        }
        let mut out: Vec<Uncertified> = Vec::new();
        let mut group_of: std::collections::HashMap<usize, usize> = Default::default();
        for a in 0..n {
            let r = sets.find(a as u32) as usize;
            let (i, _, _) = failed[a];
            let leaf = self.map_box(&tree.grid.cell_aabb(tree.leaves[i].cell));
            match group_of.get(&r) {
                Some(&g) => out[g].region = out[g].region.union(&leaf),
                None => {
                    // Named by the first (in leaf order) sub-box not proven.
                    let (_, b, why) = failed[r];
                    let c = self.map(b.map(|x| x.mid()));
                    let near = if dim == 2 {
                        format!("({:.4}, {:.4})", c[0], c[1])
                    } else {
                        format!("({:.4}, {:.4}, {:.4})", c[0], c[1], c[2])
                    };
                    group_of.insert(r, out.len());
                    out.push(Uncertified::new(
                        leaf,
                        format!(
                            "{OUTSIDE_DOMAIN_REASON} near {near} ({why}; generic position \
                             meshes a rotated box containing the domain, and isotopy to f = 0 \
                             inside the domain needs f = 0 absent from the rest)"
                        ),
                    ));
                }
            }
        }
        out
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
