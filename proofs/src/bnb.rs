//! Generic certified branch and bound over the unit square, with checkable certificates.
//!
//! A *case* is a list of domains, each a map from the unit square [0,1]² onto part of a
//! parameter space, and a vector-valued function on it (the [`Objective`]). The search
//! refines a quadtree on every domain until each output's minimum and maximum over the
//! union of the domains is enclosed to within `tol`: a box is final when none of its
//! interval bounds can improve an extreme by more than `tol` beyond the best witness.
//! The certificate ([`CaseCert`]) lists every leaf of every quadtree (its path and
//! interval bounds, or "outside" when an extra constraint excludes it) and the witness
//! points. [`check_case`] re-verifies a certificate without the search: the leaves must
//! partition each square exactly (checked with integer arithmetic), every leaf is
//! re-evaluated, every witness re-evaluated, and the stated enclosures must contain the
//! recomputed ones.
use inari::Interval;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;

/// A dyadic box of the unit square: depth d, cell (ix, iy) of the 2^d × 2^d grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Cell {
    pub d: u8,
    pub ix: u64,
    pub iy: u64,
}

impl Cell {
    pub const ROOT: Cell = Cell { d: 0, ix: 0, iy: 0 };
    /// The box [u0,u1] × [v0,v1] (exact: dyadic numbers).
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        let s = (0.5f64).powi(self.d as i32);
        (
            [self.ix as f64 * s, (self.ix + 1) as f64 * s],
            [self.iy as f64 * s, (self.iy + 1) as f64 * s],
        )
    }
    pub fn children(&self) -> [Cell; 4] {
        let (d, x, y) = (self.d + 1, 2 * self.ix, 2 * self.iy);
        [
            Cell { d, ix: x, iy: y },
            Cell {
                d,
                ix: x + 1,
                iy: y,
            },
            Cell {
                d,
                ix: x,
                iy: y + 1,
            },
            Cell {
                d,
                ix: x + 1,
                iy: y + 1,
            },
        ]
    }
    pub fn parent(&self) -> Option<Cell> {
        (self.d > 0).then(|| Cell {
            d: self.d - 1,
            ix: self.ix / 2,
            iy: self.iy / 2,
        })
    }
    pub fn valid(&self) -> bool {
        self.d <= 50 && self.ix < (1u64 << self.d) && self.iy < (1u64 << self.d)
    }
}

/// What an objective says about a box.
pub enum Enclosure {
    /// The box is certified to lie outside the region (an extra constraint is negative).
    Outside,
    /// Interval enclosures of every output over the box (∩ region).
    Values(Vec<Interval>),
}

/// A vector-valued function on a domain parametrised by the unit square.
pub trait Objective: Sync {
    fn n_out(&self) -> usize;
    /// Enclose every output over the box u × v.
    fn enclose(&self, u: [f64; 2], v: [f64; 2]) -> Enclosure;
    /// Tight enclosures of the outputs at a point, or None when the point is not
    /// certified to lie in the region (it cannot serve as a witness).
    fn point(&self, u: f64, v: f64) -> Option<Vec<Interval>>;
}

/// A leaf of a quadtree: its cell and the bounds [lo, hi] of each output, or None when
/// certified outside. Serialised compactly as one array `[d, ix, iy, lo0, hi0, ...]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "Vec<f64>", try_from = "Vec<f64>")]
pub struct Leaf {
    pub cell: Cell,
    pub vals: Option<Vec<[f64; 2]>>,
}

impl From<Leaf> for Vec<f64> {
    fn from(l: Leaf) -> Vec<f64> {
        let mut out = vec![l.cell.d as f64, l.cell.ix as f64, l.cell.iy as f64];
        if let Some(v) = l.vals {
            for [a, b] in v {
                out.push(a);
                out.push(b);
            }
        }
        out
    }
}

/// A leaf coordinate stored as a JSON number: a non-negative integer below 2^50 or
/// the certificate is malformed (shared by the GradNormal and stuffing certificates).
pub(crate) fn leaf_index(x: f64) -> Result<u64, String> {
    if x >= 0.0 && x.fract() == 0.0 && x < 1.2e15 {
        Ok(x as u64)
    } else {
        Err(format!("malformed leaf index {x}"))
    }
}

impl TryFrom<Vec<f64>> for Leaf {
    type Error = String;
    fn try_from(v: Vec<f64>) -> Result<Leaf, String> {
        if v.len() < 3 || v.len() % 2 == 0 {
            return Err(format!("malformed leaf of length {}", v.len()));
        }
        let int = leaf_index;
        let cell = Cell {
            d: int(v[0])?.min(255) as u8,
            ix: int(v[1])?,
            iy: int(v[2])?,
        };
        let vals = if v.len() == 3 {
            None
        } else {
            Some(v[3..].chunks(2).map(|c| [c[0], c[1]]).collect())
        };
        Ok(Leaf { cell, vals })
    }
}

/// `Witness::domain` of an extreme without a witness point (one-sided bound only).
pub const NO_WITNESS: usize = usize::MAX;

/// A point of a domain and the enclosure of the outputs there.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Witness {
    pub domain: usize,
    pub u: f64,
    pub v: f64,
    /// Enclosure of the output at the point.
    pub value: [f64; 2],
}

/// A certified enclosure [lo, hi] of an extreme (min or max) of one output, and the
/// witness attaining it up to the enclosure's width.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Extreme {
    pub bound: [f64; 2],
    pub witness: Witness,
}

/// The certificate of one case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseCert {
    /// One list of leaves per domain.
    pub leaves: Vec<Vec<Leaf>>,
    /// Per output: the minimum and the maximum.
    pub min: Vec<Extreme>,
    pub max: Vec<Extreme>,
    /// Leaves kept at the depth limit although they could still improve an extreme by
    /// more than `tol` (the enclosures stay valid, only wider).
    pub unresolved: usize,
}

/// Search parameters.
#[derive(Clone, Copy, Debug)]
pub struct Search {
    /// Target width of every extreme's enclosure.
    pub tol: f64,
    pub max_depth: u8,
    /// Seed witnesses on an n × n grid of every domain before the search.
    pub seed: usize,
}

struct Best {
    min: Vec<(f64, Witness)>,
    max: Vec<(f64, Witness)>,
}

impl Best {
    fn offer(&mut self, domain: usize, u: f64, v: f64, vals: &[Interval]) {
        for (k, x) in vals.iter().enumerate() {
            if x.is_empty() || !x.sup().is_finite() || !x.inf().is_finite() {
                continue;
            }
            let w = Witness {
                domain,
                u,
                v,
                value: [x.inf(), x.sup()],
            };
            if x.sup() < self.min[k].0 {
                self.min[k] = (x.sup(), w.clone());
            }
            if x.inf() > self.max[k].0 {
                self.max[k] = (x.inf(), w);
            }
        }
    }
}

/// Run the branch and bound on one case.
pub fn solve(domains: &[&dyn Objective], s: Search) -> Result<CaseCert, String> {
    let n = domains.first().map(|d| d.n_out()).unwrap_or(0);
    let dummy = Witness {
        domain: 0,
        u: 0.0,
        v: 0.0,
        value: [f64::NAN, f64::NAN],
    };
    let mut best = Best {
        min: vec![(f64::INFINITY, dummy.clone()); n],
        max: vec![(f64::NEG_INFINITY, dummy); n],
    };
    for (di, dom) in domains.iter().enumerate() {
        for i in 0..s.seed {
            for j in 0..s.seed {
                let u = (i as f64 + 0.5) / s.seed as f64;
                let v = (j as f64 + 0.5) / s.seed as f64;
                if let Some(vals) = dom.point(u, v) {
                    best.offer(di, u, v, &vals);
                }
            }
        }
    }
    let mut leaves: Vec<Vec<Leaf>> = vec![Vec::new(); domains.len()];
    let mut unresolved = 0;
    let mut stack: Vec<(usize, Cell)> = (0..domains.len()).map(|d| (d, Cell::ROOT)).collect();
    while let Some((di, cell)) = stack.pop() {
        let (u, v) = cell.bounds();
        match domains[di].enclose(u, v) {
            Enclosure::Outside => leaves[di].push(Leaf { cell, vals: None }),
            Enclosure::Values(vals) => {
                let (cu, cv) = (0.5 * (u[0] + u[1]), 0.5 * (v[0] + v[1]));
                if let Some(pv) = domains[di].point(cu, cv) {
                    best.offer(di, cu, cv, &pv);
                }
                let needs = |best: &Best| {
                    vals.iter().enumerate().any(|(k, x)| {
                        x.is_empty()
                            || x.inf() < best.min[k].0 - s.tol
                            || x.sup() > best.max[k].0 + s.tol
                    })
                };
                // Extremes typically sit on the boundary (Lemma 7.1), often at a vertex
                // of the region: witnesses at box centres alone would approach them only
                // linearly in the box width, so also try the corners.
                if needs(&best) {
                    for cu in u {
                        for cv in v {
                            if let Some(pv) = domains[di].point(cu, cv) {
                                best.offer(di, cu, cv, &pv);
                            }
                        }
                    }
                }
                let need = needs(&best);
                if need && cell.d < s.max_depth.min(50) {
                    for c in cell.children() {
                        stack.push((di, c));
                    }
                } else {
                    if need {
                        unresolved += 1;
                    }
                    leaves[di].push(Leaf {
                        cell,
                        vals: Some(vals.iter().map(|x| interval_pair(*x)).collect()),
                    });
                }
            }
        }
    }
    // A region excluded everywhere by its extra constraint (e.g. a diagonal that is
    // never the shorter one) is an empty case: no extremes, every leaf outside.
    if leaves.iter().flatten().all(|l| l.vals.is_none()) {
        return Ok(CaseCert {
            leaves,
            min: Vec::new(),
            max: Vec::new(),
            unresolved,
        });
    }
    let (min, max) = extremes(&leaves, &best, n)?;
    Ok(CaseCert {
        leaves,
        min,
        max,
        unresolved,
    })
}

fn interval_pair(x: Interval) -> [f64; 2] {
    if x.is_empty() {
        [f64::NEG_INFINITY, f64::INFINITY]
    } else {
        [x.inf(), x.sup()]
    }
}

fn extremes(
    leaves: &[Vec<Leaf>],
    best: &Best,
    n: usize,
) -> Result<(Vec<Extreme>, Vec<Extreme>), String> {
    let mut lo = vec![f64::INFINITY; n];
    let mut hi = vec![f64::NEG_INFINITY; n];
    for l in leaves.iter().flatten() {
        if let Some(v) = &l.vals {
            for k in 0..n {
                lo[k] = lo[k].min(v[k][0]);
                hi[k] = hi[k].max(v[k][1]);
            }
        }
    }
    let mut min = Vec::new();
    let mut max = Vec::new();
    for k in 0..n {
        if !best.min[k].0.is_finite() || !best.max[k].0.is_finite() {
            // No point of the region was certified (e.g. it is only the tie set of a
            // diagonal rule): keep the one-sided bounds, claim no attained value.
            let none = Witness {
                domain: NO_WITNESS,
                u: 0.0,
                v: 0.0,
                value: [f64::MIN, f64::MAX],
            };
            min.push(Extreme {
                bound: [lo[k], f64::MAX],
                witness: none.clone(),
            });
            max.push(Extreme {
                bound: [f64::MIN, hi[k]],
                witness: none,
            });
            continue;
        }
        min.push(Extreme {
            bound: [lo[k], best.min[k].0],
            witness: best.min[k].1.clone(),
        });
        max.push(Extreme {
            bound: [best.max[k].0, hi[k]],
            witness: best.max[k].1.clone(),
        });
    }
    Ok((min, max))
}

/// Check that the leaves partition the unit square: no leaf is (a descendant of) another,
/// and the areas sum to exactly 1 (integer arithmetic at the finest depth).
pub fn check_partition(leaves: &[Leaf]) -> Result<(), String> {
    let maxd = leaves.iter().map(|l| l.cell.d).max().unwrap_or(0);
    if maxd > 50 {
        return Err("leaf deeper than 50".into());
    }
    let set: HashSet<Cell> = leaves.iter().map(|l| l.cell).collect();
    if set.len() != leaves.len() {
        return Err("duplicate leaf".into());
    }
    let mut area: u128 = 0;
    for l in leaves {
        if !l.cell.valid() {
            return Err(format!("invalid cell {:?}", l.cell));
        }
        let mut p = l.cell.parent();
        while let Some(c) = p {
            if set.contains(&c) {
                return Err(format!("leaf {:?} overlaps leaf {:?}", l.cell, c));
            }
            p = c.parent();
        }
        area += 1u128 << (2 * (maxd - l.cell.d) as u32);
    }
    if area != 1u128 << (2 * maxd as u32) {
        return Err("leaves do not cover the unit square".into());
    }
    Ok(())
}

fn contains(outer: [f64; 2], inner: Interval) -> bool {
    !inner.is_empty() && outer[0] <= inner.inf() && inner.sup() <= outer[1]
}

/// Re-verify a case certificate against its domains, independently of the search.
/// Returns the recomputed enclosures of (min, max) per output.
pub type Recomputed = (Vec<[f64; 2]>, Vec<[f64; 2]>);

pub fn check_case(domains: &[&dyn Objective], cert: &CaseCert) -> Result<Recomputed, String> {
    let n = domains.first().map(|d| d.n_out()).unwrap_or(0);
    if cert.leaves.len() != domains.len() {
        return Err(format!(
            "{} leaf lists for {} domains",
            cert.leaves.len(),
            domains.len()
        ));
    }
    let empty = cert.min.is_empty() && cert.max.is_empty();
    if !empty && (cert.min.len() != n || cert.max.len() != n) {
        return Err("wrong number of extremes".into());
    }
    if empty && cert.leaves.iter().flatten().any(|l| l.vals.is_some()) {
        return Err("a case stated empty has leaves inside its region".into());
    }
    let mut lo = vec![f64::INFINITY; n];
    let mut hi = vec![f64::NEG_INFINITY; n];
    for (di, (dom, leaves)) in domains.iter().zip(&cert.leaves).enumerate() {
        check_partition(leaves).map_err(|e| format!("domain {di}: {e}"))?;
        for l in leaves {
            let (u, v) = l.cell.bounds();
            match (dom.enclose(u, v), &l.vals) {
                (Enclosure::Outside, None) => {}
                (Enclosure::Values(vals), Some(rec)) => {
                    if rec.len() != n {
                        return Err(format!("domain {di}: leaf {:?} has wrong arity", l.cell));
                    }
                    for k in 0..n {
                        if !contains(rec[k], vals[k]) {
                            return Err(format!(
                                "domain {di}: leaf {:?} output {k}: recorded bound {:?} does not contain the recomputed [{}, {}]",
                                l.cell, rec[k], vals[k].inf(), vals[k].sup()
                            ));
                        }
                        lo[k] = lo[k].min(vals[k].inf());
                        hi[k] = hi[k].max(vals[k].sup());
                    }
                }
                (Enclosure::Values(_), None) => {
                    return Err(format!(
                    "domain {di}: leaf {:?} is recorded as outside but is not certified outside",
                    l.cell
                ))
                }
                (Enclosure::Outside, Some(_)) => {
                    // A conservative certificate: bounds on an excluded box are harmless,
                    // but recomputing them is impossible; still include them.
                    let rec = l.vals.as_ref().map(|v| v.as_slice()).unwrap_or(&[]);
                    for k in 0..n.min(rec.len()) {
                        lo[k] = lo[k].min(rec[k][0]);
                        hi[k] = hi[k].max(rec[k][1]);
                    }
                }
            }
        }
    }
    let mut rmin = Vec::new();
    let mut rmax = Vec::new();
    if empty {
        return Ok((rmin, rmax));
    }
    for k in 0..n {
        let wit = |e: &Extreme| -> Result<Interval, String> {
            let w = &e.witness;
            let dom = domains
                .get(w.domain)
                .ok_or_else(|| format!("witness domain {} out of range", w.domain))?;
            if !(0.0..=1.0).contains(&w.u) || !(0.0..=1.0).contains(&w.v) {
                return Err("witness outside the unit square".into());
            }
            let val = dom
                .point(w.u, w.v)
                .ok_or("witness not certified inside its region")?;
            let x = val[k];
            if !contains(w.value, x) {
                return Err(format!(
                    "output {k}: witness value {:?} does not contain the recomputed [{}, {}]",
                    w.value,
                    x.inf(),
                    x.sup()
                ));
            }
            Ok(x)
        };
        let m = if cert.min[k].witness.domain == NO_WITNESS {
            [lo[k], f64::MAX]
        } else {
            [lo[k], wit(&cert.min[k])?.sup()]
        };
        let mx = if cert.max[k].witness.domain == NO_WITNESS {
            [f64::MIN, hi[k]]
        } else {
            [wit(&cert.max[k])?.inf(), hi[k]]
        };
        if !(cert.min[k].bound[0] <= m[0] && m[1] <= cert.min[k].bound[1]) {
            return Err(format!(
                "output {k}: stated minimum {:?} does not contain the recomputed {:?}",
                cert.min[k].bound, m
            ));
        }
        if !(cert.max[k].bound[0] <= mx[0] && mx[1] <= cert.max[k].bound[1]) {
            return Err(format!(
                "output {k}: stated maximum {:?} does not contain the recomputed {:?}",
                cert.max[k].bound, mx
            ));
        }
        rmin.push(m);
        rmax.push(mx);
    }
    Ok((rmin, rmax))
}
