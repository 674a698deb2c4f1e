//! Graded interior tetrahedra (§5): fine uniform BCC tetrahedra on the surface,
//! coarser ones inside, from a sparse octree (any subset of children).
//!
//! Steps, as in the paper: (1) leaf cubes of width `h` that have a nonnegative and a
//! nonpositive probe point (8 corners + centre); (2) the Continuation Condition; (3) the
//! extra leaves that protect the asterisked bounds (a leaf with a violated centre and a
//! face with two opposite violated corners gets a neighbour across that face); (4) the
//! octree of the leaves and their ancestors; (5) the Weak Balance Condition; (6) the
//! background grid of Fig 10 (BCC, bisected and quadrisected BCC tetrahedra,
//! half-pyramids), with the duplicate tetrahedra the figure warns about removed by a
//! hash set; (7) cut points, warping (arbitrary order) and the stencils on the BCC
//! tetrahedra; every other background tetrahedron becomes an output tetrahedron when it
//! has a positive vertex.
//!
//! Coordinates are doubled finest-lattice coordinates (see [`crate::lattice::bcc`]); an octant
//! of level `L` has corners at multiples of `2^(L+1)` and half-width `2^L`.
//!
//! Limitation of this implementation: the lattice values come from the uniform
//! continuation (so f is evaluated at the fine lattice inside the domain too, which
//! costs evaluations but not tetrahedra).
use super::field::{Field, OUT};
use super::stencils::{pattern_index, EDGES, TABLE};
use super::warp::violates;
use super::{QuadZero, Stuffed, StuffingParams};
use crate::error::{Error, Result};
use crate::implicit::Implicit;
use crate::kernel::geom::{lerp, Aabb};
use crate::lattice::bcc::{orient, Coord, TET_TEMPLATES};
use crate::mesh::TetMesh;
use std::collections::{HashMap, HashSet};

/// Kinds of background tetrahedra (Fig 7).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    Bcc,
    Bisected,
    Quadrisected,
    HalfPyramid,
}

/// Counts reported by the graded mesher.
#[derive(Clone, Debug, Default)]
pub struct GradedStats {
    pub leaves: usize,
    pub octants: usize,
    pub background: [usize; 4],
}

type Oct = (u32, Coord);

struct Signs<'a> {
    f: &'a dyn Implicit,
    fl: &'a Field,
    extra: HashMap<Coord, i8>,
}

impl Signs<'_> {
    fn get(&mut self, c: Coord) -> i8 {
        if let Some(id) = self.fl.lat.id(c) {
            let s = self.fl.sign[id as usize];
            if s != OUT && s != -3 {
                return s;
            }
        }
        if let Some(&s) = self.extra.get(&c) {
            return s;
        }
        let v = -self.f.eval(self.fl.lat.position_of(c));
        let s = if v > 0.0 {
            1
        } else if v < 0.0 {
            -1
        } else {
            0
        };
        self.extra.insert(c, s);
        s
    }
}

fn add(a: Coord, b: Coord) -> Coord {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn unit(k: usize, s: i64) -> Coord {
    let mut v = [0; 3];
    v[k] = s;
    v
}

/// Graded isosurface stuffing of `{f <= 0}`.
pub fn stuff_graded(
    f: &dyn Implicit,
    domain: &Aabb,
    p: &StuffingParams,
) -> Result<(Stuffed, GradedStats)> {
    let h = p.spacing(domain)?;
    let lat = Field::lattice(domain, h, p.offset)?;
    let mut fl = Field::evaluate(f, lat, p.seeding, false, p.parallel)?;
    fl.compute_cuts(f, p.crossing, p.tolerance, p.parallel)?;
    let (al, as_) = p.alphas();
    let n = fl.lat.n;
    let in_window = |c: Coord| (0..3).all(|k| c[k] >= 0 && c[k] < n[k] as i64);
    let mut signs = Signs {
        f,
        fl: &fl,
        extra: HashMap::new(),
    };
    // (1) Leaf cubes straddling the surface.
    let corner = |c: Coord, b: usize| -> Coord {
        [
            2 * c[0] + 2 * (b & 1) as i64,
            2 * c[1] + 2 * (b >> 1 & 1) as i64,
            2 * c[2] + 2 * (b >> 2 & 1) as i64,
        ]
    };
    let centre = |c: Coord| -> Coord { [2 * c[0] + 1, 2 * c[1] + 1, 2 * c[2] + 1] };
    let mut leaves: HashSet<Coord> = HashSet::new();
    let mut work = Vec::new();
    for k in 0..n[2] as i64 {
        for j in 0..n[1] as i64 {
            for i in 0..n[0] as i64 {
                let c = [i, j, k];
                // Quick reject: no probe is known to be nonnegative (points outside
                // P are negative and not adjacent to a positive point).
                let known_nonneg = (0..9).any(|b| {
                    let q = if b < 8 { corner(c, b) } else { centre(c) };
                    fl.lat.id(q).is_some_and(|id| {
                        let x = fl.sign[id as usize];
                        x == 0 || x == 1
                    })
                });
                if !known_nonneg {
                    continue;
                }
                let mut s: Vec<i8> = (0..8).map(|b| signs.get(corner(c, b))).collect();
                s.push(signs.get(centre(c)));
                if s.iter().any(|&x| x >= 0) && s.iter().any(|&x| x <= 0) && leaves.insert(c) {
                    work.push(c);
                }
            }
        }
    }
    // (2) Continuation Condition, to a fixpoint.
    let mut clipped = false;
    while let Some(c) = work.pop() {
        let mut push = |q: Coord, leaves: &mut HashSet<Coord>, work: &mut Vec<Coord>| {
            if !in_window(q) {
                clipped = true;
            } else if leaves.insert(q) {
                work.push(q);
            }
        };
        for a in 0..3 {
            for s in [0usize, 1] {
                let cs: Vec<i8> = (0..8)
                    .filter(|b| (b >> a & 1) == s)
                    .map(|b| signs.get(corner(c, b)))
                    .collect();
                if cs.iter().any(|&x| x <= 0) && cs.iter().any(|&x| x >= 0) {
                    push(add(c, unit(a, 2 * s as i64 - 1)), &mut leaves, &mut work);
                }
            }
        }
        let sc = signs.get(centre(c));
        for b in 0..8 {
            let sv = signs.get(corner(c, b));
            if sv == 0 || sc == 0 || sv == -sc {
                for a in 0..3 {
                    let dir = 2 * (b >> a & 1) as i64 - 1;
                    push(add(c, unit(a, dir)), &mut leaves, &mut work);
                }
            }
        }
    }
    // (3) Extra leaves for the asterisked bounds.
    let violated = |q: Coord| -> bool {
        let Some(id) = fl.lat.id(q) else { return false };
        let odd = fl.is_odd(id);
        (0..14).any(|d| matches!(fl.cut_at(id, d), Some((t, _)) if violates(odd, d, t, al, as_)))
    };
    let snapshot: Vec<Coord> = leaves.iter().copied().collect();
    for c in snapshot {
        if !violated(centre(c)) {
            continue;
        }
        for a in 0..3 {
            for s in [0usize, 1] {
                let bs: Vec<usize> = (0..8).filter(|b| (b >> a & 1) == s).collect();
                // bs in binary order: opposite corners are (0,3) and (1,2).
                let v: Vec<bool> = bs.iter().map(|&b| violated(corner(c, b))).collect();
                if (v[0] && v[3]) || (v[1] && v[2]) {
                    let q = add(c, unit(a, 2 * s as i64 - 1));
                    if in_window(q) {
                        leaves.insert(q);
                    } else {
                        // The half-pyramid this leaf protects stays: the asterisk
                        // guarantee (and the non-BCC safe property that uses it) does
                        // not hold there, so the run is reported clipped.
                        clipped = true;
                    }
                }
            }
        }
    }
    // (4) Octree: leaves and ancestors.
    let maxn = *n.iter().max().expect("3 axes") as i64;
    let mut root = 0u32;
    while (1i64 << root) < maxn {
        root += 1;
    }
    let mut tree: HashSet<Oct> = HashSet::new();
    for &c in &leaves {
        for l in 0..=root {
            let key = (l, [c[0] >> l, c[1] >> l, c[2] >> l]);
            if !tree.insert(key) {
                break;
            }
        }
    }
    // (5) Weak Balance Condition, to a fixpoint.
    loop {
        let mut new = Vec::new();
        for &(l, idx) in &tree {
            let s_l = 1i64 << (l + 1);
            let base = [idx[0] * s_l, idx[1] * s_l, idx[2] * s_l];
            for a in 0..3 {
                let (b, c) = ((a + 1) % 3, (a + 2) % 3);
                for (ob, oc) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let mut p0 = base;
                    p0[b] += ob * s_l;
                    p0[c] += oc * s_l;
                    for big in (l + 2)..=root {
                        let sz = 1i64 << (big + 1);
                        let ia = p0[a].div_euclid(sz);
                        let opts = |x: i64| -> Vec<i64> {
                            if x.rem_euclid(sz) == 0 {
                                vec![x / sz - 1, x / sz]
                            } else {
                                vec![x.div_euclid(sz)]
                            }
                        };
                        for jb in opts(p0[b]) {
                            for jc in opts(p0[c]) {
                                let mut o = [0i64; 3];
                                o[a] = ia;
                                o[b] = jb;
                                o[c] = jc;
                                if !tree.contains(&(big, o)) {
                                    continue;
                                }
                                // Children of o meeting the interior of the edge.
                                let half = sz / 2;
                                let ca = (p0[a] - ia * sz) / half;
                                let copts = |x: i64, ob: i64| -> Vec<i64> {
                                    let r = x - ob * sz;
                                    if r == half {
                                        vec![0, 1]
                                    } else if r < half {
                                        vec![0]
                                    } else {
                                        vec![1]
                                    }
                                };
                                for cb in copts(p0[b], jb) {
                                    for cc in copts(p0[c], jc) {
                                        let mut ch = [0i64; 3];
                                        ch[a] = 2 * o[a] + ca;
                                        ch[b] = 2 * o[b] + cb;
                                        ch[c] = 2 * o[c] + cc;
                                        if !tree.contains(&(big - 1, ch)) {
                                            new.push((big - 1, ch));
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        if new.is_empty() {
            break;
        }
        tree.extend(new);
    }
    // (6) Background grid (Fig 10).
    let bg = background_grid(&tree, |c| signs.get(c) < 0);
    let mut stats = GradedStats {
        leaves: leaves.len(),
        octants: tree.len(),
        background: [0; 4],
    };
    for k in bg.values() {
        stats.background[*k as usize] += 1;
    }
    // (7) Cut points and warping on the BCC tetrahedra that cross the surface.
    let mut tets: Vec<([Coord; 4], Kind)> = bg.into_iter().collect();
    tets.sort_unstable_by_key(|a| a.0);
    let mut sg: HashMap<Coord, i8> = HashMap::new();
    for (t, _) in &tets {
        for v in t {
            let s = signs.get(*v);
            sg.insert(*v, s);
        }
    }
    // Cut edges: (+ end, − end) → t from the + end.
    let mut cuts: HashMap<(Coord, Coord), f64> = HashMap::new();
    for (t, kind) in &tets {
        let s = t.map(|v| sg[&v]);
        if !(s.contains(&1) && s.contains(&-1)) {
            continue;
        }
        if *kind != Kind::Bcc {
            return Err(Error::Param(format!(
                "graded stuffing: a {kind:?} background tetrahedron at {:?} crosses the surface",
                fl.lat.position_of(t[0])
            )));
        }
        for i in 0..4 {
            for j in 0..4 {
                if s[i] == 1 && s[j] == -1 {
                    let (pi, pj) = (t[i], t[j]);
                    let id = fl.lat.id(pi).expect("in window");
                    let d =
                        crate::lattice::bcc::dir_of([pj[0] - pi[0], pj[1] - pi[1], pj[2] - pi[2]])
                            .ok_or_else(|| {
                                Error::Param("graded stuffing: a cut edge is not a BCC edge".into())
                            })?;
                    let (tt, _) = fl
                        .cut_at(id, d)
                        .ok_or_else(|| Error::Param("graded stuffing: missing cut point".into()))?;
                    cuts.insert((pi, pj), tt);
                }
            }
        }
    }
    // Warping (§3.2) on the background grid's cut edges: arbitrary order by colour
    // classes (as in the uniform mesher), or the two loops of ordered warping.
    let mut adj: HashMap<Coord, Vec<(Coord, Coord)>> = HashMap::new();
    for &(a, b) in cuts.keys() {
        adj.entry(a).or_default().push((a, b));
        adj.entry(b).or_default().push((a, b));
    }
    for v in adj.values_mut() {
        v.sort_unstable();
    }
    let mut pts: Vec<Coord> = adj.keys().copied().collect();
    pts.sort_unstable_by_key(|&c| (fl.colour(fl.lat.id(c).expect("in window")), c));
    let mut warp: HashMap<Coord, [f64; 3]> = HashMap::new();
    let mut alive: HashSet<(Coord, Coord)> = cuts.keys().copied().collect();
    let mut nwarp = 0;
    // Warp q to pos: its cut edges die, q lies on the surface.
    fn snap(
        q: Coord,
        pos: [f64; 3],
        adj: &HashMap<Coord, Vec<(Coord, Coord)>>,
        alive: &mut HashSet<(Coord, Coord)>,
        sg: &mut HashMap<Coord, i8>,
        warp: &mut HashMap<Coord, [f64; 3]>,
    ) {
        for e in &adj[&q] {
            alive.remove(e);
        }
        sg.insert(q, 0);
        warp.insert(q, pos);
    }
    // Does the cut on edge (a = +, b = −) violate endpoint q? Returns (t from q, other).
    let viol = |q: Coord, (a, b): (Coord, Coord)| -> Option<(f64, Coord)> {
        let t = cuts[&(a, b)];
        let (tq, other) = if a == q { (t, b) } else { (1.0 - t, a) };
        let d = crate::lattice::bcc::dir_of([other[0] - q[0], other[1] - q[1], other[2] - q[2]])?;
        let odd = q[0] & 1 != 0;
        violates(odd, d, tq, al, as_).then_some((tq * fl.lat.edge_length(d), other))
    };
    let nearest = |q: Coord,
                   alive: &HashSet<(Coord, Coord)>,
                   ok: &dyn Fn(Coord) -> bool|
     -> Option<[f64; 3]> {
        let mut best: Option<(f64, [f64; 3])> = None;
        for &e in &adj[&q] {
            if !alive.contains(&e) {
                continue;
            }
            if let Some((dist, other)) = viol(q, e) {
                if ok(other) && best.is_none_or(|(bd, _)| dist < bd) {
                    let tq = cuts[&e];
                    let tq = if e.0 == q { tq } else { 1.0 - tq };
                    best = Some((
                        dist,
                        lerp(fl.lat.position_of(q), fl.lat.position_of(other), tq),
                    ));
                }
            }
        }
        best.map(|b| b.1)
    };
    if p.order == super::Order::Arbitrary {
        for q in pts {
            if let Some(pos) = nearest(q, &alive, &|_| true) {
                snap(q, pos, &adj, &mut alive, &mut sg, &mut warp);
                nwarp += 1;
            }
        }
    } else {
        let mut count: HashMap<Coord, u32> = HashMap::new();
        for &q in &pts {
            if sg[&q] == 1 {
                let c = adj[&q].iter().filter(|&&e| viol(q, e).is_some()).count() as u32;
                count.insert(q, c);
            }
        }
        let mut queue: std::collections::VecDeque<Coord> =
            pts.iter().copied().filter(|q| sg[q] == -1).collect();
        while let Some(q) = queue.pop_front() {
            if sg[&q] != -1 {
                continue;
            }
            let target = {
                let cnt = &count;
                nearest(q, &alive, &|o: Coord| cnt.get(&o) == Some(&0))
            };
            let Some(pos) = target else { continue };
            for &e in &adj[&q] {
                if !alive.contains(&e) {
                    continue;
                }
                let pp = e.0;
                if viol(pp, e).is_some() {
                    let c = count.get_mut(&pp).expect("positive end");
                    *c -= 1;
                    if *c == 0 {
                        for &e2 in &adj[&pp] {
                            if alive.contains(&e2) && e2.1 != q {
                                queue.push_back(e2.1);
                            }
                        }
                    }
                }
            }
            snap(q, pos, &adj, &mut alive, &mut sg, &mut warp);
            nwarp += 1;
        }
        for &q in &pts {
            if sg[&q] != 1 {
                continue;
            }
            if let Some(pos) = nearest(q, &alive, &|_| true) {
                snap(q, pos, &adj, &mut alive, &mut sg, &mut warp);
                nwarp += 1;
            }
        }
    }
    // Emission.
    let mut vid: HashMap<Coord, u32> = HashMap::new();
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut cut_vid: HashMap<(Coord, Coord), u32> = HashMap::new();
    let mut out = Vec::new();
    let mut qz = 0;
    let mut qz_kept = 0;
    let templates: HashMap<[Coord; 3], usize> = TET_TEMPLATES
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let mut o = [t.offsets[0], t.offsets[1], t.offsets[2], t.offsets[3]];
            o.sort_unstable();
            ([o[1], o[2], o[3]], i)
        })
        .collect();
    let keep_qz = matches!(p.quadruple_zero, QuadZero::Keep);
    for (t, kind) in &tets {
        let s = t.map(|v| sg[&v]);
        if !s.contains(&1) {
            if s == [0, 0, 0, 0] && *kind == Kind::Bcc {
                qz += 1;
                if !keep_qz {
                    continue;
                }
                qz_kept += 1;
            } else {
                continue;
            }
        }
        let mut vtx = |c: Coord, vertices: &mut Vec<[f64; 3]>| -> u32 {
            *vid.entry(c).or_insert_with(|| {
                vertices.push(
                    warp.get(&c)
                        .copied()
                        .unwrap_or_else(|| fl.lat.position_of(c)),
                );
                vertices.len() as u32 - 1
            })
        };
        if !s.contains(&-1) {
            let mut g = t.map(|c| vtx(c, &mut vertices));
            if orient(t) < 0 {
                g.swap(0, 1);
            }
            out.push(g);
            continue;
        }
        // A surface BCC tetrahedron: canonical naming via the templates.
        let evens: Vec<Coord> = t.iter().copied().filter(|c| c[0] & 1 == 0).collect();
        let base = *evens.iter().min().expect("two even vertices");
        let mut rel: Vec<Coord> = t
            .iter()
            .map(|c| [c[0] - base[0], c[1] - base[1], c[2] - base[2]])
            .collect();
        rel.sort_unstable();
        let ti = templates[&[rel[1], rel[2], rel[3]]];
        let tp = TET_TEMPLATES[ti];
        let named = tp.offsets.map(|o| add(base, o));
        let sn = named.map(|c| sg[&c]);
        let st = &TABLE.stencils[pattern_index(sn)];
        let flip = tp.orientation != TABLE.reference_orientation;
        for lt in st.tets() {
            let mut g = [0u32; 4];
            for (slot, &l) in lt.iter().enumerate() {
                g[slot] = if l < 4 {
                    vtx(named[l as usize], &mut vertices)
                } else {
                    let [u, v] = EDGES[(l - 4) as usize];
                    let (a, b) = (named[u as usize], named[v as usize]);
                    let key = if sn[u as usize] == 1 { (a, b) } else { (b, a) };
                    let tt = cuts[&key];
                    *cut_vid.entry(key).or_insert_with(|| {
                        vertices.push(lerp(
                            fl.lat.position_of(key.0),
                            fl.lat.position_of(key.1),
                            tt,
                        ));
                        vertices.len() as u32 - 1
                    })
                };
            }
            if flip {
                g.swap(0, 1);
            }
            out.push(g);
        }
    }
    let mut mesh = TetMesh {
        vertices,
        tets: out,
    };
    super::emit::compact(&mut mesh, &mut []);
    let stuffed = Stuffed {
        mesh,
        lattice_points_evaluated: fl.evaluated + signs.extra.len(),
        cut_points: cuts.len(),
        warped: nwarp,
        quadruple_zero_found: qz,
        quadruple_zero_kept: qz_kept,
        quadruple_zero_well_shaped: 0,
        clipped: clipped || fl.clipped,
        spacing: h,
    };
    Ok((stuffed, stats))
}

/// Step (6) of [`stuff_graded`]: the background grid of Fig 10 for a (balanced) octree
/// given as `(level, index)` octants. Internal octants whose centre is negative
/// (`negative_centre`) are skipped, as in the mesher. Returns every background
/// tetrahedron (positively oriented, keyed by its sorted vertices) with its kind.
/// Public so that `proofs stuffing --graded` reads the non-BCC shapes from the same code.
pub fn background_grid(
    tree: &HashSet<(u32, Coord)>,
    mut negative_centre: impl FnMut(Coord) -> bool,
) -> HashMap<[Coord; 4], Kind> {
    let mut vset: HashSet<Coord> = HashSet::new();
    for &(l, idx) in tree {
        let s = 1i64 << (l + 1);
        let hw = s / 2;
        for b in 0..8 {
            vset.insert([
                idx[0] * s + s * (b & 1) as i64,
                idx[1] * s + s * (b >> 1 & 1) as i64,
                idx[2] * s + s * (b >> 2 & 1) as i64,
            ]);
        }
        vset.insert([idx[0] * s + hw, idx[1] * s + hw, idx[2] * s + hw]);
    }
    let has_child = |l: u32, idx: Coord| -> bool {
        l > 0
            && (0..8).any(|b| {
                tree.contains(&(
                    l - 1,
                    [
                        2 * idx[0] + (b & 1),
                        2 * idx[1] + (b >> 1 & 1),
                        2 * idx[2] + (b >> 2 & 1),
                    ],
                ))
            })
    };
    let mut bg: HashMap<[Coord; 4], Kind> = HashMap::new();
    let mut put = |mut t: [Coord; 4], k: Kind| {
        if orient(&t) < 0 {
            t.swap(0, 1);
        }
        let mut key = t;
        key.sort_unstable();
        bg.entry(key).or_insert(k);
    };
    let octs: Vec<Oct> = tree.iter().copied().collect();
    for &(l, idx) in &octs {
        let s = 1i64 << (l + 1);
        let hw = s / 2;
        let c = [idx[0] * s + hw, idx[1] * s + hw, idx[2] * s + hw];
        let leaf = !has_child(l, idx);
        if !leaf && negative_centre(c) {
            continue;
        }
        for a in 0..3 {
            let (b, cc) = ((a + 1) % 3, (a + 2) % 3);
            for dir in [-1i64, 1] {
                let d = add(c, unit(a, dir * hw));
                // Face corners in cyclic order.
                let q = [
                    add(add(d, unit(b, -hw)), unit(cc, -hw)),
                    add(add(d, unit(b, hw)), unit(cc, -hw)),
                    add(add(d, unit(b, hw)), unit(cc, hw)),
                    add(add(d, unit(b, -hw)), unit(cc, hw)),
                ];
                let edges = [(q[0], q[1]), (q[1], q[2]), (q[2], q[3]), (q[3], q[0])];
                let mid = |e: (Coord, Coord)| {
                    [
                        (e.0[0] + e.1[0]) / 2,
                        (e.0[1] + e.1[1]) / 2,
                        (e.0[2] + e.1[2]) / 2,
                    ]
                };
                if !vset.contains(&d) {
                    let nb = add(idx, unit(a, dir));
                    if tree.contains(&(l, nb)) {
                        let c2 = add(c, unit(a, dir * s));
                        for e in edges {
                            let m = mid(e);
                            if !vset.contains(&m) {
                                put([e.0, e.1, c, c2], Kind::Bcc);
                            } else {
                                put([e.0, m, c, c2], Kind::Bisected);
                                put([e.1, m, c, c2], Kind::Bisected);
                            }
                        }
                    } else {
                        // Half-pyramids; the diagonal adjoins a corner or the centre of
                        // the parent octant.
                        let ps = 2 * s;
                        let pidx = [idx[0] >> 1, idx[1] >> 1, idx[2] >> 1];
                        let is_parent_vertex = |v: Coord| {
                            (0..3).all(|k| v[k] - pidx[k] * ps == 0 || v[k] - pidx[k] * ps == ps)
                                || (0..3).all(|k| v[k] - pidx[k] * ps == s)
                        };
                        let k0 = (0..4).find(|&k| is_parent_vertex(q[k])).unwrap_or(0);
                        let r = |k: usize| q[(k0 + k) % 4];
                        put([r(0), r(1), r(2), c], Kind::HalfPyramid);
                        put([r(0), r(2), r(3), c], Kind::HalfPyramid);
                    }
                } else {
                    for e in edges {
                        let m = mid(e);
                        if !vset.contains(&m) {
                            put([e.0, e.1, d, c], Kind::Bisected);
                        } else {
                            for pnt in [e.0, e.1] {
                                // The child of o at corner pnt.
                                let ch = [0, 1, 2]
                                    .map(|k| 2 * idx[k] + ((pnt[k] - idx[k] * s) / hw).clamp(0, 1));
                                if !(l > 0 && tree.contains(&(l - 1, ch))) {
                                    put([pnt, m, d, c], Kind::Quadrisected);
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    bg
}
