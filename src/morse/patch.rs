//! The chapter's patching of the previous level mesh (the chapter "Meshing of
//! Surfaces", §1.5.1, Fig. 1.22), offered for animations of the Stander–Hart sweep
//! (`--algo stander-hart --set patch=true`). **Nothing here is certified**: a patched
//! mesh is a picture of the sweep, not a proven approximation; the sweep's output and
//! certificate remain the freshly meshed level 0 (`stander_hart`).
//!
//! The sweep starts, as the chapter's, from the empty mesh below min f. Passing a
//! cluster of critical values, each critical point patches the mesh by its index
//! (eigenvectors of the Hessian of f at the point):
//! * **index 0** (a sphere is born): a small closed ellipsoid around the point, its
//!   semi-axes √(2(a − f(p))/λᵢ) from the quadratic model of f at the new level a;
//! * **index 1** (a 1-handle): a ray shot from the point along ±v (v the eigenvector of
//!   the negative eigenvalue: the direction in which the two sheets face each other)
//!   hits one triangle on each side; both are removed and their boundaries joined by a
//!   cylinder of six triangles — "ray-shot triangle removal and a cylinder";
//! * **index 2** (a 2-handle: a tunnel closes, or a piece pinches off): the mesh is cut
//!   by the plane through the point normal to u (the eigenvector of the positive
//!   eigenvalue, the axis of the neck of {f > a}): the ring of triangles that the plane
//!   crosses around the point is removed and the two boundary loops capped by fans —
//!   "a cut and two caps";
//! * **index 3** (a cavity fills): the smallest component whose bounding box holds the
//!   point is removed.
//!
//! Then every vertex is moved onto the new level f = a by a few Newton steps along ∇f
//! (x ← x − (f(x) − a)∇f/|∇f|²). The report per level gives what was patched, what
//! could not be (a ray that hit nothing, a cut that did not leave two loops), the χ
//! and closedness of the patched mesh beside the Morse prediction, and the largest
//! residual |f − a|/|∇f| over its vertices.
use crate::implicit::Implicit;
use crate::kernel::geom::{add, cross, dot, norm, scale, sub};
use crate::mesh::TriMesh;
use serde::Serialize;
use std::collections::HashMap;

/// A critical point that the sweep passes.
#[derive(Clone, Copy, Debug)]
pub struct Crossing {
    pub point: [f64; 3],
    pub index: u8,
}

/// One patched level.
#[derive(Clone, Debug, Serialize)]
pub struct PatchedLevel {
    pub a: f64,
    /// The patches applied before moving onto this level ("index 0 at (..)", ...).
    pub applied: Vec<String>,
    /// Patches that could not be applied, with why.
    pub failed: Vec<String>,
    pub vertices: usize,
    pub triangles: usize,
    /// χ of the patched mesh (V − E + F), beside the Morse prediction.
    pub chi: i64,
    pub chi_predicted: Option<i64>,
    pub closed_manifold: bool,
    /// max |f − a|/|∇f| over the vertices after the Newton steps (an estimate of the
    /// distance to the level; not a bound).
    pub max_residual: f64,
    pub file: Option<String>,
}

/// The Hessian's eigenpairs at p, ascending (bounded iterations: a Hessian that is not
/// finite, or an eigensolver that does not converge, is an error, never a hang).
fn eigen(f: &dyn Implicit, p: [f64; 3]) -> Result<[(f64, [f64; 3]); 3], String> {
    let h = f.hessian(p).h;
    if h.iter().any(|v| !v.is_finite()) {
        return Err("the Hessian is not finite there".into());
    }
    let idx = [[0, 1, 2], [1, 3, 4], [2, 4, 5]];
    let m = nalgebra::Matrix3::from_fn(|i, j| h[idx[i][j]]);
    let e = m
        .try_symmetric_eigen(1e-14, 1000)
        .ok_or("the eigensolver did not converge")?;
    let mut out: Vec<(f64, [f64; 3])> = (0..3)
        .map(|k| {
            let v = e.eigenvectors.column(k);
            (e.eigenvalues[k], [v[0], v[1], v[2]])
        })
        .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok([out[0], out[1], out[2]])
}

/// Möller–Trumbore: the ray parameter t > 0 at which o + t·d meets triangle (a, b, c).
fn ray_hit(o: [f64; 3], d: [f64; 3], [a, b, c]: [[f64; 3]; 3]) -> Option<f64> {
    let e1 = sub(b, a);
    let e2 = sub(c, a);
    let p = cross(d, e2);
    let det = dot(e1, p);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = sub(o, a);
    let u = dot(s, p) / det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = cross(s, e1);
    let v = dot(d, q) / det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = dot(e2, q) / det;
    (t > 0.0).then_some(t)
}

fn nearest_hit(m: &TriMesh, o: [f64; 3], d: [f64; 3]) -> Option<usize> {
    (0..m.triangles.len())
        .filter_map(|t| ray_hit(o, d, m.corners(t)).map(|s| (s, t)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, t)| t)
}

fn fmt(p: [f64; 3]) -> String {
    format!("({:.3}, {:.3}, {:.3})", p[0], p[1], p[2])
}

/// Index 0: an ellipsoid around p from the quadratic model at level a.
fn birth(m: &mut TriMesh, f: &dyn Implicit, p: [f64; 3], a: f64) -> Result<(), String> {
    let e = eigen(f, p)?;
    let rise = (a - f.eval(p)).max(0.0);
    if e.iter().any(|(l, _)| *l <= 0.0) || rise <= 0.0 {
        return Err(
            "the Hessian is not positive definite there, or the level is not above f(p)".into(),
        );
    }
    let s = crate::mesh::icosphere(1);
    let base = m.vertices.len() as u32;
    for q in &s.vertices {
        let mut x = p;
        for (k, (l, v)) in e.iter().enumerate() {
            x = add(x, scale(*v, q[k] * (2.0 * rise / l).sqrt()));
        }
        m.vertices.push(x);
    }
    // The eigenvector frame may be left-handed: keep the ellipsoid outward.
    let flip = dot(cross(e[0].1, e[1].1), e[2].1) < 0.0;
    for t in &s.triangles {
        let t = t.map(|i| i + base);
        m.triangles.push(if flip { [t[0], t[2], t[1]] } else { t });
    }
    Ok(())
}

/// Index 1: remove the triangles hit by rays along ±v and join them by a cylinder.
fn handle(m: &mut TriMesh, f: &dyn Implicit, p: [f64; 3]) -> Result<(), String> {
    let v = eigen(f, p)?[0].1;
    let t1 = nearest_hit(m, p, v).ok_or("the ray along +v hit no triangle")?;
    let t2 = nearest_hit(m, p, scale(v, -1.0)).ok_or("the ray along -v hit no triangle")?;
    if t1 == t2 {
        return Err("both rays hit the same triangle".into());
    }
    let a = m.triangles[t1];
    let b = m.triangles[t2];
    if a.iter().any(|x| b.contains(x)) {
        return Err("the two hit triangles share a vertex".into());
    }
    // Match a[i] with b[(k − i) mod 3] (the reversed cyclic order), k with the shortest
    // total length of the cylinder's long edges.
    let pos = |i: u32| m.vertices[i as usize];
    let k = (0..3)
        .min_by(|&k1, &k2| {
            let len = |k: usize| -> f64 {
                (0..3)
                    .map(|i| norm(sub(pos(a[i]), pos(b[(k + 3 - i) % 3]))))
                    .sum()
            };
            len(k1).total_cmp(&len(k2))
        })
        .unwrap();
    let sigma = |i: usize| b[(k + 3 - i) % 3];
    let (hi, lo) = (t1.max(t2), t1.min(t2));
    m.triangles.swap_remove(hi);
    m.triangles.swap_remove(lo);
    // The cylinder uses a's edges in a's direction and b's in b's (the opposite of the
    // remaining neighbours), so the orientation stays consistent.
    for i in 0..3 {
        let j = (i + 1) % 3;
        let (x, y) = (a[i], a[j]);
        let (sx, sy) = (sigma(i), sigma(j));
        m.triangles.push([x, y, sy]);
        m.triangles.push([x, sy, sx]);
    }
    Ok(())
}

/// Index 2: cut the ring of triangles the plane through p normal to u crosses near p,
/// cap the two loops.
fn pinch(m: &mut TriMesh, f: &dyn Implicit, p: [f64; 3]) -> Result<(), String> {
    let u = eigen(f, p)?[2].1;
    let side: Vec<bool> = m
        .vertices
        .iter()
        .map(|x| dot(sub(*x, p), u) >= 0.0)
        .collect();
    let crosses = |t: &[u32; 3]| {
        let s = t.map(|i| side[i as usize]);
        s[0] != s[1] || s[1] != s[2]
    };
    // The crossing triangle nearest p, then its edge-connected crossing neighbours.
    let centroid = |t: &[u32; 3]| {
        let c = t.map(|i| m.vertices[i as usize]);
        scale(add(add(c[0], c[1]), c[2]), 1.0 / 3.0)
    };
    let start = (0..m.triangles.len())
        .filter(|&t| crosses(&m.triangles[t]))
        .min_by(|&x, &y| {
            norm(sub(centroid(&m.triangles[x]), p))
                .total_cmp(&norm(sub(centroid(&m.triangles[y]), p)))
        })
        .ok_or("the plane crosses no triangle")?;
    let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (k, t) in m.triangles.iter().enumerate() {
        for i in 0..3 {
            let (x, y) = (t[i], t[(i + 1) % 3]);
            by_edge.entry((x.min(y), x.max(y))).or_default().push(k);
        }
    }
    let mut ring = vec![false; m.triangles.len()];
    let mut stack = vec![start];
    ring[start] = true;
    while let Some(k) = stack.pop() {
        let t = m.triangles[k];
        for i in 0..3 {
            let (x, y) = (t[i], t[(i + 1) % 3]);
            if side[x as usize] == side[y as usize] {
                continue; // follow the ring across the edges the plane cuts
            }
            for &n in &by_edge[&(x.min(y), x.max(y))] {
                if !ring[n] && crosses(&m.triangles[n]) {
                    ring[n] = true;
                    stack.push(n);
                }
            }
        }
    }
    let kept: Vec<[u32; 3]> = m
        .triangles
        .iter()
        .zip(&ring)
        .filter(|(_, r)| !**r)
        .map(|(t, _)| *t)
        .collect();
    // Boundary half-edges of what is kept, chained into loops.
    let mut used: HashMap<(u32, u32), usize> = HashMap::new();
    for t in &kept {
        for i in 0..3 {
            *used.entry((t[i], t[(i + 1) % 3])).or_default() += 1;
        }
    }
    let mut next: HashMap<u32, u32> = HashMap::new();
    for (&(x, y), _) in used
        .iter()
        .filter(|(&(x, y), _)| !used.contains_key(&(y, x)))
    {
        if next.insert(x, y).is_some() {
            return Err("the cut left a boundary vertex of degree > 2".into());
        }
    }
    let mut loops: Vec<Vec<u32>> = Vec::new();
    let mut seen: std::collections::HashSet<u32> = Default::default();
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort();
    for s in starts {
        if seen.contains(&s) {
            continue;
        }
        let mut l = vec![s];
        seen.insert(s);
        let mut x = next[&s];
        while x != s {
            if !seen.insert(x) || !next.contains_key(&x) {
                return Err("the cut's boundary is not a set of closed loops".into());
            }
            l.push(x);
            x = next[&x];
        }
        loops.push(l);
    }
    if loops.len() != 2 {
        return Err(format!(
            "the cut left {} boundary loops, not 2",
            loops.len()
        ));
    }
    m.triangles = kept;
    for l in loops {
        let c = l
            .iter()
            .fold([0.0; 3], |s, &i| add(s, m.vertices[i as usize]));
        let c = scale(c, 1.0 / l.len() as f64);
        let ci = m.vertices.len() as u32;
        m.vertices.push(c);
        for i in 0..l.len() {
            // The kept mesh uses l[i] → l[i+1]; the cap uses it backwards.
            m.triangles.push([l[(i + 1) % l.len()], l[i], ci]);
        }
    }
    Ok(())
}

/// Index 3: remove the smallest component whose bounding box holds p.
fn death(m: &mut TriMesh, p: [f64; 3]) -> Result<(), String> {
    let mut uf = crate::metrics::topology::UnionFind::new(m.vertices.len());
    for t in &m.triangles {
        uf.union(t[0], t[1]);
        uf.union(t[0], t[2]);
    }
    let mut boxes: HashMap<u32, ([f64; 3], [f64; 3])> = HashMap::new();
    for t in &m.triangles {
        let r = uf.find(t[0]);
        for &i in t {
            let x = m.vertices[i as usize];
            let e = boxes.entry(r).or_insert((x, x));
            for k in 0..3 {
                e.0[k] = e.0[k].min(x[k]);
                e.1[k] = e.1[k].max(x[k]);
            }
        }
    }
    let target = boxes
        .iter()
        .filter(|(_, (lo, hi))| (0..3).all(|k| lo[k] <= p[k] && p[k] <= hi[k]))
        .min_by(|x, y| norm(sub(x.1 .1, x.1 .0)).total_cmp(&norm(sub(y.1 .1, y.1 .0))))
        .map(|(r, _)| *r)
        .ok_or("no component's bounding box holds the point")?;
    let tris = std::mem::take(&mut m.triangles);
    m.triangles = tris
        .into_iter()
        .filter(|t| uf.find(t[0]) != target)
        .collect();
    Ok(())
}

/// Newton steps onto f = a; the largest residual |f − a|/|∇f| after them.
fn project(m: &mut TriMesh, f: &dyn Implicit, a: f64, max_step: f64) -> f64 {
    let mut worst: f64 = 0.0;
    for x in &mut m.vertices {
        let mut r = f64::INFINITY;
        for _ in 0..40 {
            let d = f.grad(*x);
            let g2 = dot(d.g, d.g);
            if !(g2 > 1e-300) || !d.v.is_finite() {
                break;
            }
            r = (d.v - a).abs() / g2.sqrt();
            if r < 1e-12 {
                break;
            }
            let mut step = scale(d.g, (d.v - a) / g2);
            // Damped near critical points, where |∇f| is tiny and the step huge.
            let len = norm(step);
            if len > max_step {
                step = scale(step, max_step / len);
            }
            *x = sub(*x, step);
        }
        let d = f.grad(*x);
        let g = norm(d.g);
        if g > 0.0 && d.v.is_finite() {
            r = (d.v - a).abs() / g;
        }
        worst = worst.max(r);
    }
    worst
}

/// Patch `m` for the crossings (sorted by value by the caller) and move it onto f = a
/// (Newton steps no longer than `max_step`).
pub fn advance(
    m: &mut TriMesh,
    f: &dyn Implicit,
    crossings: &[Crossing],
    a: f64,
    max_step: f64,
) -> (Vec<String>, Vec<String>, f64) {
    let mut applied = Vec::new();
    let mut failed = Vec::new();
    for c in crossings {
        let what = match c.index {
            0 => "index 0: sphere born",
            1 => "index 1: cylinder between ray-shot triangles",
            2 => "index 2: cut and two caps",
            _ => "index 3: component removed",
        };
        let r = match c.index {
            0 => birth(m, f, c.point, a),
            1 => handle(m, f, c.point),
            2 => pinch(m, f, c.point),
            _ => death(m, c.point),
        };
        match r {
            Ok(()) => applied.push(format!("{what} at {}", fmt(c.point))),
            Err(e) => failed.push(format!("{what} at {}: {e}", fmt(c.point))),
        }
    }
    m.compact();
    let res = project(m, f, a, max_step);
    (applied, failed, res)
}

/// χ and closed-manifoldness of a (possibly empty) patched mesh.
pub fn shape(m: &TriMesh) -> (i64, bool) {
    if m.triangles.is_empty() {
        return (0, true);
    }
    match crate::metrics::analyze(m) {
        Ok(t) => (t.euler_characteristic, t.closed && t.manifold),
        Err(_) => (0, false),
    }
}
