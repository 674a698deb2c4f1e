//! The planar version (Sec. 3, Figs 7–9): curves f(x, y) = 0 on the tiling of the
//! plane by equilateral triangles of side e.
//!
//! Step 1 (Fig 7): in every triangle whose vertices do not all have the same sign (f = 0
//! counts as positive, as in Algorithm 1), join the midpoints of the two edges with a
//! sign change. Step 2 (Fig 9): move each vertex by v ← v − f∇f/|∇f|². There is no
//! step 3 in the plane. Segments are oriented with {f < 0} on their left (the curve runs
//! counter-clockwise around the inside). Empty space is pruned with interval
//! arithmetic over a quadtree of lattice blocks.
use super::GradNormalParams;
use crate::error::{Error, Result};
use crate::implicit::ops::refuse_pole_edges;
use crate::implicit::Implicit;
use crate::kernel::geom::{dist, Aabb};
use crate::mesh::Curve2;
use crate::mesher::options::MesherOptions;
use crate::mesher::{Certificate, Mesh, MeshOutput, Mesher, Progress};
use rayon::prelude::*;

const H: f64 = 0.866_025_403_784_438_6;

/// A triangle's vertices and, for each vertex, the (origin i, origin j, direction) key
/// of the edge opposite it.
type TriEdges = ([[i64; 2]; 3], [(i64, i64, u64); 3]);
const OFF: i64 = 1 << 30;

/// Keys of the three edge directions from a lattice point: (1,0), (0,1), (−1,1).
const DIRS: [[i64; 2]; 3] = [[1, 0], [0, 1], [-1, 1]];

#[inline]
fn key(i: i64, j: i64, dir: u64) -> u64 {
    ((((i + OFF) as u64) << 31 | ((j + OFF) as u64)) << 2) | dir
}

fn endpoints(k: u64) -> ([i64; 2], [i64; 2]) {
    let dir = (k & 3) as usize;
    let v = k >> 2;
    let i = (v >> 31) as i64 - OFF;
    let j = (v & ((1 << 31) - 1)) as i64 - OFF;
    ([i, j], [i + DIRS[dir][0], j + DIRS[dir][1]])
}

#[inline]
fn point(e: f64, i: i64, j: i64) -> [f64; 3] {
    [e * (i as f64 + 0.5 * j as f64), e * H * j as f64, 0.0]
}

/// The planar normal curve: midpoint vertices (with lattice edge keys) and oriented
/// segments.
#[derive(Clone, Debug, Default)]
pub struct NormalCurve {
    pub e: f64,
    pub keys: Vec<u64>,
    pub vertices: Vec<[f64; 2]>,
    pub segments: Vec<[u32; 2]>,
    pub triangles_visited: u64,
    pub crossing_triangles: u64,
}

/// Step 1 on `domain` at scale `e`.
pub fn extract2(
    f: &dyn Implicit,
    domain: &Aabb,
    e: f64,
    leaf: usize,
    prune: bool,
) -> Result<NormalCurve> {
    if !(e.is_finite() && e > 0.0) {
        return Err(Error::Param(format!("scale e = {e} must be positive")));
    }
    let h = H * e;
    let j0 = (domain.min[1] / h).floor() as i64 - 1;
    let j1 = (domain.max[1] / h).ceil() as i64 + 1;
    let i0 = (domain.min[0] / e - 0.5 * j1 as f64).floor() as i64 - 1;
    let i1 = (domain.max[0] / e - 0.5 * j0 as f64).ceil() as i64 + 1;
    for v in [i0, i1, j0, j1] {
        if v.abs() >= (1 << 29) {
            return Err(Error::TooLarge(format!(
                "lattice index {v}: scale e = {e} too small for the domain"
            )));
        }
    }
    let dom = domain.inflate(e);
    let leaf = leaf.max(1) as i64;
    type Blk = ([i64; 2], [i64; 2]);
    fn bbox(e: f64, b: &Blk) -> Aabb {
        Aabb {
            min: [
                e * (b.0[0] as f64 + 0.5 * b.0[1] as f64),
                e * H * b.0[1] as f64,
                0.0,
            ],
            max: [
                e * (b.1[0] as f64 + 0.5 * b.1[1] as f64),
                e * H * b.1[1] as f64,
                0.0,
            ],
        }
    }
    fn descend(
        f: &dyn Implicit,
        e: f64,
        b: Blk,
        dom: &Aabb,
        leaf: i64,
        prune: bool,
        out: &mut Vec<Blk>,
    ) {
        let bb = bbox(e, &b);
        if (0..2).any(|k| bb.min[k] > dom.max[k] || bb.max[k] < dom.min[k]) {
            return;
        }
        if prune {
            let iv = f.eval_interval(&bb.intervals());
            if !iv.is_empty() && (iv.inf() >= 0.0 || iv.sup() < 0.0) {
                return;
            }
        }
        let ext = [b.1[0] - b.0[0], b.1[1] - b.0[1]];
        let k = if ext[0] >= ext[1] { 0 } else { 1 };
        if ext[k] <= leaf {
            out.push(b);
            return;
        }
        let mid = b.0[k] + ext[k] / 2;
        let (mut lo, mut hi) = (b, b);
        lo.1[k] = mid;
        hi.0[k] = mid;
        descend(f, e, lo, dom, leaf, prune, out);
        descend(f, e, hi, dom, leaf, prune, out);
    }
    let mut leaves = Vec::new();
    descend(f, e, ([i0, j0], [i1, j1]), &dom, leaf, prune, &mut leaves);
    type Out = (Vec<[u64; 2]>, u64, u64);
    let outs: Vec<Result<Out>> = leaves
        .par_iter()
        .map(|&(lo, hi)| {
            let nj = (hi[1] - lo[1] + 1) as usize;
            let mut vals = vec![0.0; (hi[0] - lo[0] + 1) as usize * nj];
            for i in lo[0]..=hi[0] {
                for j in lo[1]..=hi[1] {
                    let p = point(e, i, j);
                    let v = f.eval(p);
                    if v.is_nan() {
                        return Err(Error::NotFinite(format!(
                            "f is NaN at ({}, {})",
                            p[0], p[1]
                        )));
                    }
                    vals[(i - lo[0]) as usize * nj + (j - lo[1]) as usize] = v;
                }
            }
            let val = |i: i64, j: i64| vals[(i - lo[0]) as usize * nj + (j - lo[1]) as usize];
            let mut segs = Vec::new();
            let (mut visited, mut crossing) = (0u64, 0u64);
            for i in lo[0]..hi[0] {
                for j in lo[1]..hi[1] {
                    // Up and down triangles with their three edges: edge k is opposite
                    // vertex k; (origin, dir) keys.
                    let tris: [TriEdges; 2] = [
                        (
                            [[i, j], [i + 1, j], [i, j + 1]],
                            [(i + 1, j, 2), (i, j, 1), (i, j, 0)],
                        ),
                        (
                            [[i + 1, j], [i, j + 1], [i + 1, j + 1]],
                            [(i, j + 1, 0), (i + 1, j, 1), (i + 1, j, 2)],
                        ),
                    ];
                    for (vs, es) in tris {
                        visited += 1;
                        let pos = vs.map(|[a, b]| val(a, b) >= 0.0);
                        let npos = pos.iter().filter(|&&x| x).count();
                        if npos == 0 || npos == 3 {
                            continue;
                        }
                        crossing += 1;
                        // The lone vertex; the segment joins the midpoints of its two edges
                        // (the edges not opposite it).
                        let lone = (0..3)
                            .find(|&k| pos[k] != pos[(k + 1) % 3] && pos[k] != pos[(k + 2) % 3])
                            .unwrap();
                        let e1 = es[(lone + 1) % 3];
                        let e2 = es[(lone + 2) % 3];
                        let k1 = key(e1.0, e1.1, e1.2);
                        let k2 = key(e2.0, e2.1, e2.2);
                        // Orientation: {f < 0} on the left of m1 -> m2.
                        let m1 = mid(e, e1);
                        let m2 = mid(e, e2);
                        let pl = point(e, vs[lone][0], vs[lone][1]);
                        let d = [m2[0] - m1[0], m2[1] - m1[1]];
                        let left = [-d[1], d[0]];
                        let side = left[0] * (pl[0] - m1[0]) + left[1] * (pl[1] - m1[1]);
                        // The lone vertex should be on the left iff it is negative.
                        let lone_neg = !pos[lone];
                        if (side > 0.0) == lone_neg {
                            segs.push([k1, k2]);
                        } else {
                            segs.push([k2, k1]);
                        }
                    }
                }
            }
            Ok((segs, visited, crossing))
        })
        .collect();
    let mut all = Vec::new();
    let (mut visited, mut crossing) = (0, 0);
    for o in outs {
        let (s, v, c) = o?;
        all.extend(s);
        visited += v;
        crossing += c;
    }
    let mut keys: Vec<u64> = all.iter().flatten().copied().collect();
    keys.par_sort_unstable();
    keys.dedup();
    let idx = |k: u64| keys.binary_search(&k).expect("key present") as u32;
    let segments = all.iter().map(|s| s.map(idx)).collect();
    let vertices: Vec<[f64; 2]> = keys
        .iter()
        .map(|&k| {
            let (p, q) = endpoints(k);
            let (a, b) = (point(e, p[0], p[1]), point(e, q[0], q[1]));
            [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
        })
        .collect();
    // Every vertex is on a lattice edge whose ends differ in sign: a sign change across
    // a pole of f is no zero of f, and is refused with the edge named. The vertices are
    // the edges' midpoints and every lattice edge is e long: the midpoints' box grown
    // by e holds every edge.
    let mids: Vec<[f64; 3]> = vertices
        .iter()
        .map(|v: &[f64; 2]| [v[0], v[1], 0.0])
        .collect();
    let near = Aabb::of_points(&mids).map(|b| b.inflate(e));
    let ends = |&k: &u64| {
        let (p, q) = endpoints(k);
        (point(e, p[0], p[1]), point(e, q[0], q[1]))
    };
    let name = |&k: &u64| {
        let (p, q) = endpoints(k);
        format!("lattice edge {p:?}–{q:?}")
    };
    refuse_pole_edges(f, near, &keys, ends, name)?;
    Ok(NormalCurve {
        e,
        keys,
        vertices,
        segments,
        triangles_visited: visited,
        crossing_triangles: crossing,
    })
}

fn mid(e: f64, (i, j, d): (i64, i64, u64)) -> [f64; 3] {
    let a = point(e, i, j);
    let b = point(e, i + DIRS[d as usize][0], j + DIRS[d as usize][1]);
    [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.0]
}

/// The planar MidNormal (`"midnormal"`, dim 2).
#[derive(Clone, Debug, Default)]
pub struct MidNormal2 {
    pub params: GradNormalParams,
}

/// The planar GradNormal (`"gradnormal"`, dim 2): MidNormal plus the projection step.
#[derive(Clone, Debug, Default)]
pub struct GradNormal2 {
    pub params: GradNormalParams,
}

/// `--set` keys of the planar meshers.
pub const PLANAR_KEYS: &[&str] = &["newton_steps", "leaf", "prune"];

fn params2(o: &MesherOptions, algo: &str) -> Result<GradNormalParams> {
    o.check_keys(algo, PLANAR_KEYS)?;
    let mut p = GradNormalParams {
        scale: o.scale,
        ..Default::default()
    };
    if let Some(r) = o.resolution {
        if r == 0 {
            return Err(Error::Param("resolution must be at least 1".into()));
        }
        p.resolution = r;
    }
    if let Some(e) = p.scale {
        if !(e.is_finite() && e > 0.0) {
            return Err(Error::Param(format!("scale e = {e} must be positive")));
        }
    }
    if let Some(v) = o.get::<usize>("newton_steps")? {
        if v > 100 {
            return Err(Error::Param(format!(
                "newton_steps = {v} must be at most 100"
            )));
        }
        p.newton_steps = v;
    }
    if let Some(v) = o.get::<usize>("leaf")? {
        if v == 0 || v > 256 {
            return Err(Error::Param(format!("leaf = {v} must be in 1..=256")));
        }
        p.leaf = v;
    }
    if let Some(v) = o.get::<bool>("prune")? {
        p.prune = v;
    }
    Ok(p)
}

impl MidNormal2 {
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Ok(MidNormal2 {
            params: params2(o, "midnormal")?,
        })
    }
}
impl GradNormal2 {
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Ok(GradNormal2 {
            params: params2(o, "gradnormal")?,
        })
    }
}

fn run2(
    p: &GradNormalParams,
    f: &dyn Implicit,
    domain: &Aabb,
    steps: usize,
    name: &str,
) -> Result<MeshOutput> {
    crate::mesher::check_input(f, domain, 2, name)?;
    let s = domain.size();
    let e = p.scale.unwrap_or(s[0].max(s[1]) / p.resolution as f64);
    let nc = extract2(f, domain, e, 16.max(p.leaf), p.prune)?;
    let mut failures = 0usize;
    let vertices: Vec<[f64; 2]> = if steps == 0 {
        nc.vertices.clone()
    } else {
        let r: Vec<([f64; 3], bool)> = nc
            .vertices
            .par_iter()
            .map(|v| {
                // Curves ignore z: project with the (x, y) gradient only.
                let mut q = [v[0], v[1], 0.0];
                let mut ok = true;
                for _ in 0..steps {
                    let d = f.grad(q);
                    let g = [d.g[0], d.g[1], 0.0];
                    let g2 = g[0] * g[0] + g[1] * g[1];
                    if d.v == 0.0 {
                        break;
                    }
                    if !(g2 > 0.0 && g2.is_finite()) {
                        ok = false;
                        break;
                    }
                    q = [q[0] - d.v * g[0] / g2, q[1] - d.v * g[1] / g2, 0.0];
                }
                (q, ok)
            })
            .collect();
        failures = r.iter().filter(|x| !x.1).count();
        r.into_iter().map(|(q, _)| [q[0], q[1]]).collect()
    };
    let mut min_len = f64::INFINITY;
    let mut max_len: f64 = 0.0;
    for s in &nc.segments {
        let a = vertices[s[0] as usize];
        let b = vertices[s[1] as usize];
        let l = dist([a[0], a[1], 0.0], [b[0], b[1], 0.0]) / e;
        min_len = min_len.min(l);
        max_len = max_len.max(l);
    }
    let max_residual = vertices
        .iter()
        .map(|v| f.eval([v[0], v[1], 0.0]).abs())
        .fold(0.0, f64::max);
    let stats = PlanarStats {
        e,
        triangles_visited: nc.triangles_visited,
        crossing_triangles: nc.crossing_triangles,
        min_segment_over_e: min_len,
        max_segment_over_e: max_len,
        max_residual,
        projection_failures: failures,
    };
    Ok(MeshOutput {
        mesh: Mesh::Curve(Curve2 {
            vertices,
            segments: nc.segments,
        }),
        certificate: Certificate::none(
            "planar MidNormal/GradNormal: topology holds only for e small enough (not quantified)",
        ),
        stats: crate::mesher::stats_map(&stats),
        angles: None,
    })
}

/// What a planar MidNormal/GradNormal run did, serialised field by field into the
/// report's `stats` map.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PlanarStats {
    /// The triangle tiling's scale.
    pub e: f64,
    pub triangles_visited: u64,
    pub crossing_triangles: u64,
    /// The shortest and longest output segment, in units of e.
    pub min_segment_over_e: f64,
    pub max_segment_over_e: f64,
    /// The largest |f| at an output vertex.
    pub max_residual: f64,
    /// Vertices whose projection onto f = 0 failed (GradNormal only).
    pub projection_failures: usize,
}

impl Mesher for MidNormal2 {
    fn name(&self) -> &'static str {
        "midnormal"
    }
    fn dim(&self) -> usize {
        2
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, _p: &dyn Progress) -> Result<MeshOutput> {
        run2(&self.params, f, domain, 0, "midnormal")
    }
}

impl Mesher for GradNormal2 {
    fn name(&self) -> &'static str {
        "gradnormal"
    }
    fn dim(&self) -> usize {
        2
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, _p: &dyn Progress) -> Result<MeshOutput> {
        run2(
            &self.params,
            f,
            domain,
            self.params.newton_steps,
            "gradnormal",
        )
    }
}
