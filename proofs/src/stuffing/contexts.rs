//! Every octree context of the graded mesher's non-BCC background tetrahedra (Labelle &
//! Shewchuk 2007, §5, Fig 10), as a finite superset: the model behind the
//! `all-contexts` verdicts of the two dagger bounds and of the non-BCC safe property.
//!
//! **Instances.** Fig 10 makes a non-BCC tetrahedron in exactly four ways, each from an
//! octant `o` of some level `L` (width `S = 2^(L+1)` in doubled finest-lattice
//! coordinates, centre `c`) and one of its square faces `s` (centre `d`):
//! * half-pyramid (`L ≥ 0`): `s` is not shared with an octant of `o`'s size, and
//!   `conv(c, three corners of s)` (either diagonal: a superset of the parent rule);
//! * bisected A (`L ≥ 1`): `s` is shared with a same-size octant `o'` (centre `c'`),
//!   there is no vertex at `d`, an edge `e` of `s` has a midpoint vertex `m`:
//!   `conv(p, m, c, c')` for an endpoint `p` of `e`;
//! * bisected B (`L ≥ 1`): a vertex at `d`, an edge `e` without a midpoint vertex:
//!   `conv(e, d, c)`;
//! * quadrisected (`L ≥ 1`): a vertex at `d`, `e` with a midpoint vertex `m`, `o` has
//!   no child at the endpoint `p`: `conv(p, m, d, c)`.
//!
//! Each construction's condition *forbids* some finest (level-0) cubes from being
//! octants: the cube region across `s` (half-pyramid: that octant is absent, so are its
//! descendants), the eight finest cubes around `d` (bisected A: a finest cube there
//! would put a vertex at `d`) or around `m` (bisected B), the child region of `o` at `p`
//! (quadrisected). These are necessary conditions only.
//!
//! **Warps.** A vertex of an output non-BCC tetrahedron warps only along a cut edge of
//! a finest BCC tetrahedron (the mesher refuses anything else), and such a warp
//! *requires* finest cubes to be leaves ([`required_cubes`]: the straddling rule and
//! the Continuation Condition). A warp is kept when none of the cubes it requires is
//! forbidden by the instance. Requirements of different vertices are not combined with
//! each other (a superset again).
//!
//! **Levels.** Instances are enumerated at their real coordinates for `L ≤ K` (warps
//! along finest edges, `t ∈ [0, α]`); an instance of level `L > K` is the finest one of
//! its shape scaled by `2^(L - L_min)` with warps shrunk by the same factor, so the
//! levels above `K` are covered by the free model (every direction at every vertex) with
//! `α·2^-K` ([`tail_alphas`]).
use super::cases::{add, canonical, sub, Alphas, Seg, Sym};
use super::graded::{collect_face_cases, directions, FaceCase};
use certmesh::stuffing::graded::Kind;
use std::collections::{BTreeMap, HashSet};

/// A finest (level-0) cube by index: the region `[2i, 2i + 2]³` in doubled coordinates.
pub type Cube = [i64; 3];

/// The finest cubes that must be leaves of the octree for a vertex `v` to warp along the
/// finest BCC edge `(v, v + d)` (necessary conditions; the edge is cut, so its ends have
/// opposite strict signs). Red edge (a corner and the centre of finest cube `L`): `L`
/// straddles the surface, so it is a leaf, and the corner/centre sign change makes the
/// Continuation Condition create `L`'s three face neighbours at that corner. Black
/// corner–corner edge: the four cubes around it have corners of both signs, so they are
/// leaves. Black centre–centre edge: both cubes are finest octants (it is an edge of a
/// finest BCC tetrahedron).
pub fn required_cubes(v: [i64; 3], d: [i64; 3]) -> Vec<Cube> {
    let w = add(v, d);
    let odd = |p: [i64; 3]| p[0].rem_euclid(2) == 1;
    let cube_of_centre = |p: [i64; 3]| p.map(|x| (x - 1).div_euclid(2));
    if d.iter().all(|&x| x.abs() == 1) {
        let (corner, centre) = if odd(v) { (w, v) } else { (v, w) };
        let idx = cube_of_centre(centre);
        let mut out = vec![idx];
        for a in 0..3 {
            let mut n = idx;
            n[a] += corner[a] - centre[a];
            out.push(n);
        }
        out
    } else if odd(v) {
        vec![cube_of_centre(v), cube_of_centre(w)]
    } else {
        let a = (0..3).find(|&k| d[k] != 0).unwrap_or(0);
        let lo = v[a].min(w[a]).div_euclid(2);
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        [(0, 0), (0, 1), (1, 0), (1, 1)]
            .iter()
            .map(|&(sb, sc)| {
                let mut idx = [0i64; 3];
                idx[a] = lo;
                idx[b] = v[b].div_euclid(2) - sb;
                idx[c] = v[c].div_euclid(2) - sc;
                idx
            })
            .collect()
    }
}

/// How Fig 10 made an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Rule {
    HalfPyramid,
    BisectedA,
    BisectedB,
    Quadrisected,
}

impl Rule {
    pub fn kind(self) -> Kind {
        match self {
            Rule::HalfPyramid => Kind::HalfPyramid,
            Rule::BisectedA | Rule::BisectedB => Kind::Bisected,
            Rule::Quadrisected => Kind::Quadrisected,
        }
    }
}

/// One way a non-BCC background tetrahedron arises, with the finest cubes its rule
/// forbids.
#[derive(Clone, Debug)]
pub struct Instance {
    pub rule: Rule,
    pub level: u32,
    pub v: [[i64; 3]; 4],
    pub forbidden: HashSet<Cube>,
    /// A finest half-pyramid's apex and the two ends of its diagonal: step (3) of §5
    /// (a leaf with a violated centre and a face with two opposite violated corners gets
    /// the neighbour across that face, which a half-pyramid's face does not have) means
    /// the three are never all violated, so never all warped.
    pub asterisk: Option<[[i64; 3]; 3]>,
}

impl Instance {
    /// Are these warp choices (one per vertex of `p`, vertices of this instance) allowed
    /// by the asterisk rule?
    pub fn asterisk_ok(&self, p: &[[i64; 3]], ch: &[Option<[i64; 3]>]) -> bool {
        let Some(tri) = self.asterisk else {
            return true;
        };
        !tri.iter()
            .all(|q| p.iter().zip(ch).any(|(v, c)| v == q && c.is_some()))
    }
}

fn unit(k: usize, s: i64) -> [i64; 3] {
    let mut u = [0; 3];
    u[k] = s;
    u
}

/// The finest cubes inside the axis-aligned region `[lo, hi]` (doubled coordinates,
/// even bounds).
fn cubes_in(lo: [i64; 3], hi: [i64; 3]) -> impl Iterator<Item = Cube> {
    let (a, b) = (lo.map(|x| x / 2), hi.map(|x| x / 2));
    (a[0]..b[0])
        .flat_map(move |i| (a[1]..b[1]).flat_map(move |j| (a[2]..b[2]).map(move |k| [i, j, k])))
}

/// The eight finest cubes having the even point `p` as a corner.
fn cubes_around(p: [i64; 3]) -> impl Iterator<Item = Cube> {
    (0..8).map(move |b: usize| [0, 1, 2].map(|k| p[k] / 2 - ((b >> k & 1) as i64)))
}

/// Every instance of level `level` made from the octant `[0, S]³` (all six faces, every
/// edge, endpoint and diagonal: the cube symmetries are applied later, to the faces).
pub fn instances(level: u32) -> Vec<Instance> {
    let s = 1i64 << (level + 1);
    let h = s / 2;
    let c = [h, h, h];
    let mut out = Vec::new();
    for a in 0..3 {
        let (b, cc) = ((a + 1) % 3, (a + 2) % 3);
        for side in [0i64, 1] {
            let dir = 2 * side - 1;
            let d = add(c, unit(a, dir * h));
            let q = [
                add(add(d, unit(b, -h)), unit(cc, -h)),
                add(add(d, unit(b, h)), unit(cc, -h)),
                add(add(d, unit(b, h)), unit(cc, h)),
                add(add(d, unit(b, -h)), unit(cc, h)),
            ];
            let edges = [(q[0], q[1]), (q[1], q[2]), (q[2], q[3]), (q[3], q[0])];
            let mid = |e: ([i64; 3], [i64; 3])| [0, 1, 2].map(|k| (e.0[k] + e.1[k]) / 2);
            // Half-pyramids: the region across s is not an octant.
            let mut lo = [0, 0, 0];
            let mut hi = [s, s, s];
            lo[a] = if side == 1 { s } else { -s };
            hi[a] = lo[a] + s;
            let across: HashSet<Cube> = cubes_in(lo, hi).collect();
            for k0 in 0..4 {
                let r = |k: usize| q[(k0 + k) % 4];
                out.push(Instance {
                    rule: Rule::HalfPyramid,
                    level,
                    v: [r(0), r(1), r(2), c],
                    forbidden: across.clone(),
                    // Step (3) looks at the finest leaves only.
                    asterisk: (level == 0).then(|| [c, r(0), r(2)]),
                });
            }
            if level == 0 {
                continue;
            }
            let c2 = add(c, unit(a, dir * s));
            let around_d: HashSet<Cube> = cubes_around(d).collect();
            for e in edges {
                let m = mid(e);
                for p in [e.0, e.1] {
                    out.push(Instance {
                        rule: Rule::BisectedA,
                        level,
                        v: [p, m, c, c2],
                        forbidden: around_d.clone(),
                        asterisk: None,
                    });
                    // The child of o at corner p.
                    let clo = p.map(|x| if x == 0 { 0 } else { h });
                    out.push(Instance {
                        rule: Rule::Quadrisected,
                        level,
                        v: [p, m, d, c],
                        forbidden: cubes_in(clo, clo.map(|x| x + h)).collect(),
                        asterisk: None,
                    });
                }
                out.push(Instance {
                    rule: Rule::BisectedB,
                    level,
                    v: [e.0, e.1, d, c],
                    forbidden: cubes_around(m).collect(),
                    asterisk: None,
                });
            }
        }
    }
    out
}

/// The warp options of vertex `p` of instance `inst`: `None` (not warped) and every
/// finest direction whose required cubes are all allowed and that does not point at
/// another vertex of the tetrahedron (no edge of a non-BCC output tetrahedron is cut).
pub fn warp_options(inst: &Instance, p: [i64; 3]) -> Vec<Option<[i64; 3]>> {
    std::iter::once(None)
        .chain(
            directions()
                .into_iter()
                .filter(|&d| !inst.v.contains(&add(p, d)))
                .filter(|&d| {
                    required_cubes(p, d)
                        .iter()
                        .all(|q| !inst.forbidden.contains(q))
                })
                .map(Some),
        )
        .collect()
}

/// Every face configuration of every instance of levels `0..=k` (each vertex fixed or
/// warped along one of its [`warp_options`]), reduced by the 48 cube symmetries.
/// Returns the cases and the raw count.
pub fn face_cases_all_contexts(k: u32) -> (Vec<FaceCase>, usize) {
    let syms = Sym::all();
    let mut raw = 0;
    let mut map: BTreeMap<Vec<Seg>, usize> = BTreeMap::new();
    for level in 0..=k {
        for inst in instances(level) {
            for f in [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]] {
                let p = f.map(|i| inst.v[i]);
                let opts = p.map(|q| warp_options(&inst, q));
                for a in &opts[0] {
                    for b in &opts[1] {
                        for c in &opts[2] {
                            if !inst.asterisk_ok(&p, &[*a, *b, *c]) {
                                continue;
                            }
                            raw += 1;
                            let v: Vec<Seg> = [*a, *b, *c]
                                .iter()
                                .zip(p)
                                .map(|(ch, q)| match ch {
                                    None => Seg::fixed(q),
                                    Some(d) => Seg::warp(q, *d),
                                })
                                .collect();
                            *map.entry(canonical(&v, &syms)).or_insert(0) += 1;
                        }
                    }
                }
            }
        }
    }
    (collect_face_cases(map), raw)
}

/// The safe property of the non-BCC tetrahedra (no warped one inverts or flattens),
/// decided exactly over the all-contexts model: the smallest 6·volume of every instance
/// of levels `0..=k` with every vertex fixed or warped along one of its
/// [`warp_options`], at least one vertex fixed (§5: a non-BCC background tetrahedron is
/// output when it has a positive vertex, and a vertex that warped is zero), and of every shape's finest instance with every direction and
/// `α·2^-k` above. The volume is multilinear in the warp parameters
/// ([`super::cases::volume_range`]), so its minimum over a closed box is at a corner and
/// exact.
#[derive(Clone, Debug, serde::Serialize)]
pub struct NonBccSafe {
    /// `proven` (every volume > 0 on the closed configuration space), or `refuted on the
    /// superset` (a configuration of volume ≤ 0; the superset's, not necessarily one the
    /// mesher builds).
    pub verdict: String,
    pub levels: u32,
    /// Configurations (tetrahedron, warp directions) decided.
    pub configurations: usize,
    /// The smallest 6·volume over the unwarped 6·volume, as f64 (exact ratio rounded).
    pub min_ratio: f64,
    /// Where: the kind, the level (`None`: the tail), the segments and the parameters
    /// (fractions of the edges).
    pub witness: (String, Option<u32>, [Seg; 4], [f64; 4]),
}

pub fn safe_non_bcc(a: &Alphas, k: u32) -> NonBccSafe {
    use rayon::prelude::*;
    // (tetrahedron, level or None, options per vertex, alphas)
    type Job = (Instance, Option<u32>, Vec<Vec<Option<[i64; 3]>>>, Alphas);
    let mut jobs: Vec<Job> = Vec::new();
    for level in 0..=k {
        for inst in instances(level) {
            let opts = inst.v.iter().map(|&p| warp_options(&inst, p)).collect();
            jobs.push((inst, Some(level), opts, *a));
        }
    }
    let tail = tail_alphas(a, k);
    for sh in super::graded::shapes() {
        let opts =
            sh.v.iter()
                .map(|&p| {
                    std::iter::once(None)
                        .chain(
                            directions()
                                .into_iter()
                                .filter(|&d| !sh.v.contains(&add(p, d)))
                                .map(Some),
                        )
                        .collect()
                })
                .collect();
        let rule = match sh.kind {
            Kind::HalfPyramid => Rule::HalfPyramid,
            Kind::Quadrisected => Rule::Quadrisected,
            _ => Rule::BisectedA,
        };
        let inst = Instance {
            rule,
            level: sh.level,
            v: sh.v,
            forbidden: HashSet::new(),
            asterisk: None,
        };
        jobs.push((inst, None, opts, tail));
    }
    type Found = (
        i128,
        i128,
        usize,
        [Seg; 4],
        [i64; 4],
        Kind,
        Option<u32>,
        usize,
    );
    let per: Vec<Found> = jobs
        .par_iter()
        .map(|(inst, level, opts, al)| {
            // Positively oriented (swap the first two vertices if need be).
            let orient0 = |v: &[[i64; 3]; 4]| {
                super::cases::orient_exact(&v.map(|q| super::cases::pos_exact(&Seg::fixed(q), 0)))
            };
            let (v, opts) = if orient0(&inst.v) < 0 {
                let mut v = inst.v;
                v.swap(0, 1);
                let mut o = opts.clone();
                o.swap(0, 1);
                (v, o)
            } else {
                (inst.v, opts.clone())
            };
            let unwarped = orient0(&v);
            let seg = |i: usize, ch: Option<[i64; 3]>| match ch {
                None => Seg::fixed(v[i]),
                Some(d) => Seg::warp(v[i], d),
            };
            let mut best = (i128::MAX, [seg(0, None); 4], [0i64; 4]);
            let (mut n, mut flat_on_real_set) = (0, 0);
            for a0 in &opts[0] {
                for a1 in &opts[1] {
                    for a2 in &opts[2] {
                        for a3 in &opts[3] {
                            // An output non-BCC tetrahedron has a positive vertex, and a
                            // positive vertex is one that did not warp.
                            if a0.is_some() && a1.is_some() && a2.is_some() && a3.is_some() {
                                continue;
                            }
                            if !inst.asterisk_ok(&v, &[*a0, *a1, *a2, *a3]) {
                                continue;
                            }
                            n += 1;
                            let c = super::cases::Case {
                                v: [seg(0, *a0), seg(1, *a1), seg(2, *a2), seg(3, *a3)],
                                multiplicity: 1,
                            };
                            let (r, t) = super::cases::volume_range(&c, al);
                            // A zero on the closed box only: decided on the real set (a
                            // warp of exactly α is excluded by the strict violation rule,
                            // the §6 midpoint convention aside), as in the BCC proof.
                            if r[0] < 0
                                || (r[0] == 0
                                    && !super::safe::strictly_positive_on_real_set(&c, al))
                            {
                                flat_on_real_set += 1;
                            }
                            if r[0] < best.0 {
                                best = (r[0], c.v, t[0]);
                            }
                        }
                    }
                }
            }
            (
                best.0,
                unwarped,
                n,
                best.1,
                best.2,
                inst.rule.kind(),
                *level,
                flat_on_real_set,
            )
        })
        .collect();
    let configurations = per.iter().map(|p| p.2).sum();
    let ratio = |x: &Found| x.0 as f64 / x.1 as f64;
    let w = per
        .iter()
        .min_by(|x, y| ratio(x).total_cmp(&ratio(y)))
        .expect("instances");
    // Decided exactly: every minimum is an exact integer 6·volume.
    let flat: usize = per.iter().map(|p| p.7).sum();
    let zero_on_closure = per.iter().any(|p| p.0 == 0);
    let proven = flat == 0;
    let den = super::cases::DEN as f64;
    NonBccSafe {
        verdict: if proven && zero_on_closure {
            "proven (volume 0 only at warps of exactly α, which the strict violation rule excludes)"
                .into()
        } else if proven {
            "proven".into()
        } else {
            format!("refuted on the superset ({flat} configurations flat or inverted)")
        },
        levels: k,
        configurations,
        min_ratio: ratio(w),
        witness: (format!("{:?}", w.5), w.6, w.3, w.4.map(|t| t as f64 / den)),
    }
}

/// The α of the levels above `K`: `α·2^-K`, rounded up (a larger range is a superset).
pub fn tail_alphas(a: &Alphas, k: u32) -> Alphas {
    let sc = |x: i64| (x + (1 << k) - 1) >> k;
    Alphas {
        long: sc(a.long),
        short: sc(a.short),
        ..*a
    }
}

/// The octant-lattice point below the smallest corner of `v`'s bounding box.
pub fn lattice_shift(level: u32, v: &[[i64; 3]; 4]) -> [i64; 3] {
    let s = 1i64 << (level + 1);
    [0, 1, 2].map(|k| v.iter().map(|p| p[k]).min().unwrap_or(0).div_euclid(s) * s)
}

/// The vertices of `v` minus the octant-lattice translation of its smallest corner
/// (a key that is invariant under translations by the level's octant lattice).
pub fn lattice_key(level: u32, v: &[[i64; 3]; 4]) -> Vec<[i64; 3]> {
    let m = lattice_shift(level, v);
    let mut out: Vec<[i64; 3]> = v.iter().map(|&p| sub(p, m)).collect();
    out.sort_unstable();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stuffing::graded::sample_trees_n;
    use certmesh::stuffing::graded::background_grid;
    use std::collections::HashMap;

    /// The level of a non-BCC tetrahedron: its shortest edge is half an octant's width
    /// at level L for the bisected and quadrisected kinds (the midpoint), and a
    /// half-pyramid's shortest edge is its apex-to-corner edge, half a diagonal.
    fn level_of(kind: Kind, v: &[[i64; 3]; 4]) -> u32 {
        let mut lmin = i64::MAX;
        for i in 0..4 {
            for j in 0..4 {
                if i != j {
                    let e = sub(v[i], v[j]);
                    lmin = lmin.min(e.iter().map(|x| x.abs()).max().unwrap_or(0));
                }
            }
        }
        // Half-pyramid: apex-corner edge spans h = S/2 per axis; others: the midpoint
        // edge spans h along one axis. Either way S = 2·lmin.
        let _ = kind;
        (2 * lmin).trailing_zeros() - 1
    }

    /// Independent check of the instance list against the mesher's own background grid
    /// (`background_grid`, the Fig 10 code that `stuff_graded` runs): on the sample
    /// octrees, every non-BCC tetrahedron is an enumerated instance of its level (up to
    /// the octant lattice's translations) whose forbidden cubes are all absent from the
    /// tree. So the enumeration contains what the mesher builds, and the forbidden sets
    /// are never violated by a real tree.
    #[test]
    fn every_sampled_non_bcc_tetrahedron_is_an_instance_whose_forbidden_cubes_are_absent() {
        let mut by_key: HashMap<(u32, Vec<[i64; 3]>), Vec<Instance>> = HashMap::new();
        for l in 0..=3 {
            for i in instances(l) {
                by_key.entry((l, lattice_key(l, &i.v))).or_default().push(i);
            }
        }
        let mut seen = [0usize; 4];
        for tree in sample_trees_n(4) {
            let bg = background_grid(&tree, |_| false);
            for (t, kind) in &bg {
                if *kind == Kind::Bcc {
                    continue;
                }
                let l = level_of(*kind, t);
                let key = lattice_key(l, t);
                let cands = by_key
                    .get(&(l, key.clone()))
                    .unwrap_or_else(|| panic!("{kind:?} {t:?} level {l}: no instance"));
                let ok = cands.iter().any(|i| {
                    // The translation taking the instance onto t (even: octant lattice).
                    let shift = sub(lattice_shift(l, t), lattice_shift(l, &i.v));
                    i.rule.kind() == *kind
                        && i.forbidden
                            .iter()
                            .all(|q| !tree.contains(&(0, add(*q, shift.map(|x| x / 2)))))
                });
                assert!(ok, "{kind:?} {t:?}: every matching instance is violated");
                seen[*kind as usize] += 1;
            }
        }
        // All three non-BCC kinds occur in the sample.
        assert!(seen[1] > 0 && seen[2] > 0 && seen[3] > 0, "{seen:?}");
    }

    /// The forbidden sets decide the known cases: the half-pyramid's apex cannot warp
    /// along a red edge to a corner on the coarse face (the neighbour across it is the
    /// absent cube), and the realised 147.0470° witness (both ends of the blue diagonal
    /// warped away from the apex along red edges) is allowed.
    #[test]
    fn half_pyramid_options_exclude_the_coarse_side_and_keep_the_witness() {
        let hp = instances(0)
            .into_iter()
            .find(|i| {
                i.rule == Rule::HalfPyramid
                    && i.v[3] == [1, 1, 1]
                    && i.v[..3].contains(&[2, 0, 0])
                    && i.v[..3].contains(&[2, 2, 2])
            })
            .expect("the witness half-pyramid on face x = 2");
        let apex = warp_options(&hp, [1, 1, 1]);
        assert!(!apex.contains(&Some([1, 1, 1])));
        assert!(!apex.contains(&Some([1, -1, -1])));
        assert!(apex.contains(&Some([-1, -1, -1])));
        assert!(warp_options(&hp, [2, 0, 0]).contains(&Some([-1, -1, -1])));
        assert!(warp_options(&hp, [2, 2, 2]).contains(&Some([-1, 1, 1])));
        // Toward the coarse side along the normal: the four cubes around that black edge
        // include the absent one.
        assert!(!warp_options(&hp, [2, 0, 0]).contains(&Some([2, 0, 0])));
    }
}
