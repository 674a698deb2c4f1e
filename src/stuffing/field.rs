//! Steps 1 and 2 of §3 (lattice values and cut points): the subset P of the BCC
//! lattice where f is known, found by continuation (default) or over the whole box.
//!
//! Sign convention. The paper meshes `{g >= 0}` with `g` positive inside. certmesh's
//! solid is `{f <= 0}` with `f < 0` inside, so the paper's sign is `sign(-f)`: a
//! lattice point is *positive* (inside, "+") when `f < 0`, *negative* ("−") when
//! `f > 0`, and *zero* when `f == 0` exactly. Meshing the exterior (§3.3, double
//! sided) uses `sign(f)` instead.
use crate::error::{Error, Result};
use crate::implicit::ops::{refuse_pole_edges, SignChange};
use crate::implicit::Implicit;
use crate::kernel::geom::{lerp, Aabb};
use crate::lattice::bcc::{self, Lattice, NEIGHBORS};
use crate::mesher::options::Crossing;
use inari::Interval;
use rayon::prelude::*;
use std::collections::HashMap;

/// Not in P (never evaluated, or outside the lattice window).
pub const OUT: i8 = 2;
/// No record.
pub const NONE: u32 = u32::MAX;

/// Cut points on the edges of one positive lattice point: `t[d]` is the parameter of
/// the cut on the edge in direction `d`, measured from this point (NaN: no cut, or the
/// cut was discarded by warping). Cut points live only here, at their positive end.
#[derive(Clone, Debug)]
pub struct CutRec {
    pub p: u32,
    pub t: [f64; 14],
    /// Output vertex id of each surviving cut point (set when emitting).
    pub vid: [u32; 14],
}

/// The lattice with its values, cut points and warps.
#[derive(Clone, Debug)]
pub struct Field {
    pub lat: Lattice,
    /// f at each point of P (NaN elsewhere).
    pub f: Vec<f64>,
    /// The paper's sign at each point: 1, -1, 0, or [`OUT`].
    pub sign: Vec<i8>,
    /// Index into `cuts` for positive points with a cut edge.
    pub surf: Vec<u32>,
    pub cuts: Vec<CutRec>,
    /// Warped positions of lattice points (§3.2).
    pub warp: HashMap<u32, [f64; 3]>,
    /// For each warped point, the other end of the edge it moved along.
    pub warp_toward: HashMap<u32, u32>,
    /// Number of f evaluations at lattice points.
    pub evaluated: usize,
    /// A positive point has a neighbour outside the lattice window: the mesh is cut off.
    pub clipped: bool,
}

/// How the set P is found (§3.1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Seeding {
    /// Depth-first (here breadth-first, level-parallel) search over BCC edges from seed
    /// points; seeds come from an interval-arithmetic subdivision of the box, so f is
    /// evaluated only near the domain.
    #[default]
    Continuation,
    /// Evaluate f at every lattice point of the box (the paper's prototype).
    BoundingBox,
}

impl Field {
    /// The lattice window covering `domain` with a one-cell margin. `h` is the black edge
    /// length; `offset` shifts the lattice by a fraction of `h` per axis.
    pub fn lattice(domain: &Aabb, h: f64, offset: [f64; 3]) -> Result<Lattice> {
        if !(h > 0.0 && h.is_finite()) {
            return Err(Error::Param(format!(
                "lattice spacing {h} must be positive"
            )));
        }
        let size = domain.size();
        let mut n = [0usize; 3];
        let mut origin = [0.0; 3];
        for k in 0..3 {
            let cells = (size[k] / h).ceil() + 2.0;
            if cells > 4096.0 {
                return Err(Error::TooLarge(format!(
                    "{cells} lattice cells along axis {k} (spacing {h})"
                )));
            }
            n[k] = cells as usize + 1;
            origin[k] = domain.min[k] - h * (1.0 + offset[k].rem_euclid(1.0));
        }
        // About 17 bytes per lattice point (value, sign, cut index, vertex id).
        let total = (n[0] + 1) * (n[1] + 1) * (n[2] + 1) * 2;
        if total > 80_000_000 {
            return Err(Error::TooLarge(format!(
                "{total} lattice points (spacing {h}); at most 80,000,000 (about 1.4 GB)"
            )));
        }
        Ok(Lattice::new(origin, h, n))
    }

    fn empty(lat: Lattice) -> Self {
        let np = lat.n_points();
        Field {
            lat,
            f: vec![f64::NAN; np],
            sign: vec![OUT; np],
            surf: vec![NONE; np],
            cuts: Vec::new(),
            warp: HashMap::new(),
            warp_toward: HashMap::new(),
            evaluated: 0,
            clipped: false,
        }
    }

    /// Evaluate f on P. `outside`: mesh the exterior (signs swapped).
    pub fn evaluate(
        f: &dyn Implicit,
        lat: Lattice,
        seeding: Seeding,
        outside: bool,
        parallel: bool,
    ) -> Result<Self> {
        let mut fl = Field::empty(lat);
        match seeding {
            Seeding::BoundingBox => {
                let ids: Vec<u32> = (0..fl.lat.n_points() as u32).collect();
                fl.eval_ids(f, &ids, outside, parallel)?;
            }
            Seeding::Continuation => {
                let mut seeds = Vec::new();
                let lo = fl.lat.origin;
                let hi = fl.lat.position_of([
                    2 * fl.lat.n[0] as i64,
                    2 * fl.lat.n[1] as i64,
                    2 * fl.lat.n[2] as i64,
                ]);
                fl.seeds(f, [lo, hi], 0, &mut seeds);
                seeds.sort_unstable();
                seeds.dedup();
                let mut frontier = seeds;
                while !frontier.is_empty() {
                    fl.eval_ids(f, &frontier, outside, parallel)?;
                    // Expand nonnegative points: P must hold every neighbour of a
                    // positive point, and the search walks through the domain.
                    let mut next = Vec::new();
                    for &id in &frontier {
                        if fl.sign[id as usize] < 0 || fl.sign[id as usize] == OUT {
                            continue;
                        }
                        let c = fl.lat.coord(id);
                        for o in NEIGHBORS {
                            match fl.lat.id([c[0] + o[0], c[1] + o[1], c[2] + o[2]]) {
                                Some(q) => {
                                    if fl.f[q as usize].is_nan() && fl.sign[q as usize] == OUT {
                                        // Mark as queued (sign stays OUT until evaluated).
                                        fl.sign[q as usize] = -3;
                                        next.push(q);
                                    }
                                }
                                None => {
                                    if fl.sign[id as usize] > 0 {
                                        fl.clipped = true;
                                    }
                                }
                            }
                        }
                    }
                    frontier = next;
                }
            }
        }
        if seeding == Seeding::BoundingBox {
            // Positive points on the window's border lose neighbours.
            let l = &fl.lat;
            for (id, &s) in fl.sign.iter().enumerate() {
                if s == 1 {
                    let c = l.coord(id as u32);
                    if NEIGHBORS
                        .iter()
                        .any(|o| l.id([c[0] + o[0], c[1] + o[1], c[2] + o[2]]).is_none())
                    {
                        fl.clipped = true;
                        break;
                    }
                }
            }
        }
        Ok(fl)
    }

    /// Seeds by interval subdivision: boxes where f > 0 is proven are skipped; a box
    /// where f < 0 is proven gives one seed; boxes near the surface are refined to about
    /// two cells and all their lattice points are seeds.
    fn seeds(&self, f: &dyn Implicit, b: [[f64; 3]; 2], depth: u32, out: &mut Vec<u32>) {
        let bx =
            [0, 1, 2].map(|k| Interval::try_from((b[0][k], b[1][k])).unwrap_or(Interval::ENTIRE));
        let iv = f.eval_interval(&bx);
        if !iv.is_empty() && iv.inf() > 0.0 {
            return;
        }
        let h = self.lat.h;
        let size = (0..3).map(|k| b[1][k] - b[0][k]).fold(0.0, f64::max);
        let inside = !iv.is_empty() && iv.sup() < 0.0;
        if (inside && size >= h) || size <= 2.0 * h || depth > 40 {
            // Lattice points in the box (both sub-lattices).
            let s = 0.5 * h;
            let lo: Vec<i64> = (0..3)
                .map(|k| ((b[0][k] - self.lat.origin[k]) / s).ceil() as i64)
                .collect();
            let hi: Vec<i64> = (0..3)
                .map(|k| ((b[1][k] - self.lat.origin[k]) / s).floor() as i64)
                .collect();
            if inside {
                // One seed suffices: the search covers the rest.
                let c: Vec<i64> = (0..3).map(|k| ((lo[k] + hi[k]) / 4) * 2).collect();
                for cand in [[c[0], c[1], c[2]], [c[0] + 1, c[1] + 1, c[2] + 1]] {
                    if let Some(id) = self.lat.id(cand) {
                        out.push(id);
                        return;
                    }
                }
            }
            for i in lo[0].max(0)..=hi[0] {
                for j in lo[1].max(0)..=hi[1] {
                    for k in lo[2].max(0)..=hi[2] {
                        if let Some(id) = self.lat.id([i, j, k]) {
                            out.push(id);
                        }
                    }
                }
            }
            return;
        }
        let m = [0, 1, 2].map(|k| 0.5 * (b[0][k] + b[1][k]));
        for oct in 0..8 {
            let mut lo = b[0];
            let mut hi = b[1];
            for k in 0..3 {
                if oct >> k & 1 == 0 {
                    hi[k] = m[k];
                } else {
                    lo[k] = m[k];
                }
            }
            self.seeds(f, [lo, hi], depth + 1, out);
        }
    }

    fn eval_ids(
        &mut self,
        f: &dyn Implicit,
        ids: &[u32],
        outside: bool,
        parallel: bool,
    ) -> Result<()> {
        let lat = &self.lat;
        // Chunks of lattice points, each one batch call (SIMD lanes for formulas; the
        // same values as point by point).
        let eval = |(ids, out): (&[u32], &mut [f64])| {
            let mut ps: [Vec<f64>; 3] = Default::default();
            for &id in ids {
                for (a, x) in ps.iter_mut().zip(lat.position(id)) {
                    a.push(x);
                }
            }
            f.eval_batch([&ps[0], &ps[1], &ps[2]], out);
        };
        const CHUNK: usize = 1024;
        let mut vals = vec![0.0; ids.len()];
        if parallel {
            ids.par_chunks(CHUNK)
                .zip(vals.par_chunks_mut(CHUNK))
                .for_each(eval);
        } else {
            ids.chunks(CHUNK).zip(vals.chunks_mut(CHUNK)).for_each(eval);
        }
        for (&id, &v) in ids.iter().zip(&vals) {
            if v.is_nan() {
                return Err(Error::NotFinite(format!(
                    "f is NaN at lattice point {:?}",
                    self.lat.position(id)
                )));
            }
            self.f[id as usize] = v;
            let g = if outside { v } else { -v };
            self.sign[id as usize] = if g > 0.0 {
                1
            } else if g < 0.0 {
                -1
            } else {
                0
            };
        }
        self.evaluated += ids.len();
        Ok(())
    }

    /// Step 2: cut points on every edge with a positive and a negative end.
    /// `tol` is the tolerance on the edge parameter (0: full f64 precision).
    /// A sign change across a pole of f is refused (the error names the edge): it is
    /// no zero of f ([`crate::implicit::ops::discontinuity_on_segment`]).
    pub fn compute_cuts(
        &mut self,
        f: &dyn Implicit,
        how: Crossing,
        tol: f64,
        parallel: bool,
    ) -> Result<()> {
        let lat = &self.lat;
        let sign = &self.sign;
        let fv = &self.f;
        // The sign-changing edges of every positive point, in order (point, direction),
        // then their crossings in batches (the bisections of a batch advance together,
        // one batch evaluation per round), then one record per point.
        let edges_of = |p: usize| -> Vec<(u32, u8, SignChange)> {
            if sign[p] != 1 {
                return Vec::new();
            }
            let c = lat.coord(p as u32);
            let mut out = Vec::new();
            for (d, o) in NEIGHBORS.iter().enumerate() {
                if let Some(q) = lat.id([c[0] + o[0], c[1] + o[1], c[2] + o[2]]) {
                    if sign[q as usize] == -1 {
                        let (a, b) = (lat.position(p as u32), lat.position(q));
                        out.push((
                            p as u32,
                            d as u8,
                            SignChange {
                                a,
                                fa: fv[p],
                                b,
                                fb: fv[q as usize],
                            },
                        ));
                    }
                }
            }
            out
        };
        let n = lat.n_points();
        let edges: Vec<(u32, u8, SignChange)> = if parallel {
            (0..n).into_par_iter().flat_map_iter(edges_of).collect()
        } else {
            (0..n).flat_map(edges_of).collect()
        };
        let ends: Vec<[f64; 3]> = edges.iter().flat_map(|e| [e.2.a, e.2.b]).collect();
        refuse_pole_edges(
            f,
            Aabb::of_points(&ends),
            &edges,
            |e| (e.2.a, e.2.b),
            |_| "lattice edge".into(),
        )?;
        const BATCH: usize = 1024;
        let solve = |c: &[(u32, u8, SignChange)]| {
            let segs: Vec<SignChange> = c.iter().map(|e| e.2).collect();
            crate::implicit::ops::crossing_t_batch(f, &segs, how, tol)
        };
        let ts: Vec<f64> = if parallel {
            edges.par_chunks(BATCH).flat_map_iter(solve).collect()
        } else {
            edges.chunks(BATCH).flat_map(solve).collect()
        };
        let mut cuts: Vec<CutRec> = Vec::new();
        for (&(p, d, _), &t) in edges.iter().zip(&ts) {
            if cuts.last().is_none_or(|r| r.p != p) {
                cuts.push(CutRec {
                    p,
                    t: [f64::NAN; 14],
                    vid: [NONE; 14],
                });
            }
            cuts.last_mut().unwrap().t[d as usize] = t;
        }
        self.cuts = cuts;
        for (i, r) in self.cuts.iter().enumerate() {
            self.surf[r.p as usize] = i as u32;
        }
        Ok(())
    }

    /// The surviving cut on the edge of `q` in direction `d`: (parameter from `q`,
    /// the other end). Only edges between a positive and a negative point have one.
    #[inline]
    pub fn cut_at(&self, q: u32, d: usize) -> Option<(f64, u32)> {
        match self.sign[q as usize] {
            1 => {
                let r = self.surf[q as usize];
                if r == NONE {
                    return None;
                }
                let t = self.cuts[r as usize].t[d];
                if t.is_nan() {
                    return None;
                }
                Some((t, self.lat.neighbor(q, d)?))
            }
            -1 => {
                let p = self.lat.neighbor(q, d)?;
                if self.sign[p as usize] != 1 {
                    return None;
                }
                let r = self.surf[p as usize];
                if r == NONE {
                    return None;
                }
                let t = self.cuts[r as usize].t[d ^ 1];
                if t.is_nan() {
                    return None;
                }
                Some((1.0 - t, p))
            }
            _ => None,
        }
    }

    /// Position of the cut at parameter `t` from `q` towards `other`.
    #[inline]
    pub fn cut_position(&self, q: u32, other: u32, t: f64) -> [f64; 3] {
        lerp(self.lat.position(q), self.lat.position(other), t)
    }

    /// Warp `q` to `pos` (a cut point on the edge towards `toward`): value zero, all adjoining cut points discarded (§3, step 3).
    pub fn warp_to(&mut self, q: u32, pos: [f64; 3], toward: u32) {
        match self.sign[q as usize] {
            1 => {
                let r = self.surf[q as usize];
                if r != NONE {
                    self.cuts[r as usize].t = [f64::NAN; 14];
                }
            }
            -1 => {
                for d in 0..14 {
                    if let Some(p) = self.lat.neighbor(q, d) {
                        if self.sign[p as usize] == 1 {
                            let r = self.surf[p as usize];
                            if r != NONE {
                                self.cuts[r as usize].t[d ^ 1] = f64::NAN;
                            }
                        }
                    }
                }
            }
            _ => {}
        }
        self.sign[q as usize] = 0;
        self.warp.insert(q, pos);
        self.warp_toward.insert(q, toward);
    }

    /// Position of a lattice point after warping.
    #[inline]
    pub fn point_position(&self, id: u32) -> [f64; 3] {
        if self.sign[id as usize] == 0 {
            if let Some(p) = self.warp.get(&id) {
                return *p;
            }
        }
        self.lat.position(id)
    }

    /// Is `id` on the shifted sub-lattice?
    #[inline]
    pub fn is_odd(&self, id: u32) -> bool {
        id as usize >= self.lat.n_even()
    }

    /// The 4-colouring used for order-independent parallel warping: no two points of a
    /// colour share a BCC edge (black edges flip the parity of the half-coordinates'
    /// sum; red edges change the sub-lattice).
    #[inline]
    pub fn colour(&self, id: u32) -> usize {
        let c = self.lat.coord(id);
        let odd = bcc::is_odd(c);
        let h = if odd {
            ((c[0] - 1) / 2 + (c[1] - 1) / 2 + (c[2] - 1) / 2) & 1
        } else {
            (c[0] / 2 + c[1] / 2 + c[2] / 2) & 1
        };
        2 * odd as usize + h as usize
    }
}
