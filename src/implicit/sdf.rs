//! Signed distance to a triangle mesh as an [`Implicit`] (Hass & Trnkova 2020, Sec. 5.1:
//! "a signed-distance-function can be obtained from the original Stanford Bunny mesh,
//! after filling in holes"), so GradNormal can remesh a scan.
//!
//! * distance: exact point–triangle distance (Ericson's routine) through [`TriBvh`];
//! * sign: the generalised winding number w (Jacobson et al. 2013), evaluated
//!   hierarchically (Barill et al. 2018, accuracy β = 2, exact solid angles near the
//!   query); f < 0 where w > 1/2. It tolerates holes (w degrades smoothly across them)
//!   and isolated vertices (they are not triangles and are ignored);
//! * gradient: the unit direction from the closest point, times the sign (|∇d| = 1 away
//!   from the medial axis); on the surface, the closest triangle's unit normal;
//! * Hessian: central finite differences of that gradient with step
//!   [`MeshSdf::fd_step`] (not an enclosure; the distance is not C² across the medial
//!   axis or near edges and vertices of the mesh, so expect large values there).
//!
//! Enclosures: d is 1-Lipschitz where the sign is consistent, so over a box of
//! half-diagonal r, [d(c) − r, d(c) + r] plus the values at the eight corners (which
//! catch a sign jump of an open scan inside the box). This is floating point and the
//! winding sign of an open scan is a heuristic, not a proof: [`Implicit::is_rigorous`]
//! is false, so no mesher certifies anything from a [`MeshSdf`].
use crate::error::{Error, Result};
use crate::implicit::{Dual, Hyper, IBox, Implicit};
use crate::kernel::bvh::{Closest, TriBvh};
use crate::kernel::geom::{add, cross, dot, norm, scale, sub, Aabb};
use crate::mesh::TriMesh;
use inari::Interval;
use std::collections::HashMap;

/// Signed distance to a triangle mesh; f < 0 inside (winding number > 1/2).
#[derive(Clone, Debug)]
pub struct MeshSdf {
    bvh: TriBvh,
    /// Unit normal of each triangle, by mesh index (zero for degenerate triangles).
    normals: Vec<[f64; 3]>,
    bbox: Aabb,
    /// Step of the finite-difference Hessian (default 1e-5 × the bounding-box diagonal).
    pub fd_step: f64,
    name: String,
}

impl MeshSdf {
    /// Build from a mesh. Errors name the problem: no triangles, an index out of range
    /// (with the triangle), a non-finite coordinate (with the vertex), or only
    /// zero-area triangles.
    pub fn new(mesh: &TriMesh) -> Result<Self> {
        if mesh.triangles.is_empty() {
            return Err(Error::Param(
                "signed distance needs a mesh with at least one triangle".into(),
            ));
        }
        // Only vertices used by triangles matter (a scan's isolated vertices are ignored),
        // but every coordinate must be finite so the report can name the bad vertex.
        if let Some(k) = crate::kernel::finite::first_non_finite(mesh.vertices.as_flattened()) {
            let i = k / 3;
            return Err(Error::NotFinite(format!(
                "vertex {i} of the input mesh has coordinates {:?}",
                mesh.vertices[i]
            )));
        }
        let bvh = TriBvh::new(mesh)?;
        let normals: Vec<[f64; 3]> = (0..mesh.triangles.len())
            .map(|t| {
                let [a, b, c] = mesh.corners(t);
                let n = cross(sub(b, a), sub(c, a));
                let l = norm(n);
                if l > 0.0 {
                    scale(n, 1.0 / l)
                } else {
                    [0.0; 3]
                }
            })
            .collect();
        if normals.iter().all(|n| *n == [0.0; 3]) {
            return Err(Error::Param(
                "every triangle of the input mesh has zero area".into(),
            ));
        }
        let used: Vec<[f64; 3]> = mesh
            .triangles
            .iter()
            .flat_map(|t| t.iter().map(|&i| mesh.vertices[i as usize]))
            .collect();
        let bbox = Aabb::of_points(&used).expect("at least one triangle");
        Ok(MeshSdf {
            bvh,
            normals,
            fd_step: 1e-5 * bbox.diagonal().max(f64::MIN_POSITIVE),
            bbox,
            name: "signed distance to a mesh".into(),
        })
    }

    /// The same, with a name for reports (e.g. the file name).
    pub fn named(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// The bounding box of the triangles.
    pub fn bbox(&self) -> Aabb {
        self.bbox
    }

    /// The generalised winding number at `p` (hierarchical, β = 2).
    pub fn winding_number(&self, p: [f64; 3]) -> f64 {
        self.bvh.winding_number(p)
    }

    /// The closest point and the sign (−1 inside, +1 outside).
    pub fn closest(&self, p: [f64; 3]) -> (Closest, f64) {
        let c = self.bvh.closest(p).expect("the mesh has triangles");
        let s = if c.dist2 == 0.0 || self.bvh.winding_number(p) <= 0.5 {
            1.0
        } else {
            -1.0
        };
        (c, s)
    }
}

impl Implicit for MeshSdf {
    fn eval(&self, p: [f64; 3]) -> f64 {
        let (c, s) = self.closest(p);
        s * c.dist2.sqrt()
    }

    fn eval_interval(&self, b: &IBox) -> Interval {
        let lo = [0, 1, 2].map(|k| b[k].inf());
        let hi = [0, 1, 2].map(|k| b[k].sup());
        if !lo.iter().chain(&hi).all(|x| x.is_finite()) {
            return Interval::ENTIRE;
        }
        let c = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        let h = [0, 1, 2].map(|k| 0.5 * (hi[k] - lo[k]));
        let r = dot(h, h).sqrt();
        let v = self.eval(c);
        let (mut a, mut z) = (v - r, v + r);
        // Corner check: a sign jump of an open scan's winding number breaks the
        // Lipschitz bound; the corners catch the jumps that cut the box's corners.
        for m in 0..8 {
            let q = [0, 1, 2].map(|k| if m >> k & 1 == 0 { lo[k] } else { hi[k] });
            let x = self.eval(q);
            a = a.min(x);
            z = z.max(x);
        }
        // Widen for the rounding of v, r and the distance computation.
        let slack = 1e-12 * (v.abs() + r) + 1e-300;
        Interval::try_from((a - slack, z + slack)).unwrap_or(Interval::ENTIRE)
    }

    fn grad(&self, p: [f64; 3]) -> Dual<f64> {
        let (c, s) = self.closest(p);
        let d = c.dist2.sqrt();
        let g = if d > 0.0 {
            scale(sub(p, c.point), s / d)
        } else {
            self.normals[c.index as usize]
        };
        Dual { v: s * d, g }
    }

    fn grad_interval(&self, b: &IBox) -> Dual<Interval> {
        // |∇d| ≤ 1 wherever d is differentiable; nothing finer is known.
        let unit = Interval::try_from((-1.0, 1.0)).expect("valid");
        Dual {
            v: self.eval_interval(b),
            g: [unit; 3],
        }
    }

    fn hessian(&self, p: [f64; 3]) -> Hyper<f64> {
        let d = self.grad(p);
        let h = self.fd_step;
        let mut m = [[0.0; 3]; 3];
        for (k, row) in m.iter_mut().enumerate() {
            let mut e = [0.0; 3];
            e[k] = h;
            let gp = self.grad(add(p, e)).g;
            let gm = self.grad(sub(p, e)).g;
            for j in 0..3 {
                row[j] = (gp[j] - gm[j]) / (2.0 * h);
            }
        }
        let s = |i: usize, j: usize| 0.5 * (m[i][j] + m[j][i]);
        Hyper {
            v: d.v,
            g: d.g,
            h: [s(0, 0), s(0, 1), s(0, 2), s(1, 1), s(1, 2), s(2, 2)],
        }
    }

    fn hessian_interval(&self, b: &IBox) -> Hyper<Interval> {
        let d = self.grad_interval(b);
        Hyper {
            v: d.v,
            g: d.g,
            h: [Interval::ENTIRE; 6],
        }
    }

    fn is_rigorous(&self) -> bool {
        false
    }

    fn describe(&self) -> String {
        self.name.clone()
    }
}

/// What [`fill_holes`] did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct HoleReport {
    /// Boundary loops closed by a fan.
    pub filled: usize,
    /// Boundary edges left open (at non-manifold boundary vertices where the loop could
    /// not be traced).
    pub open_edges: usize,
    /// Vertices referenced by no triangle (kept; the distance ignores them).
    pub isolated_vertices: usize,
}

/// Close every boundary loop by a fan around its centroid (one new vertex per loop).
/// Boundary half-edges are those without a twin; the fan triangles use them reversed,
/// so they keep the mesh's orientation.
pub fn fill_holes(mesh: &TriMesh) -> (TriMesh, HoleReport) {
    let mut half: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * mesh.triangles.len());
    for t in &mesh.triangles {
        for k in 0..3 {
            *half.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    // Hole edges b → a for each boundary half-edge a → b.
    let mut out: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut n_hole = 0usize;
    let mut keys: Vec<(u32, u32)> = half
        .iter()
        .filter(|(&(a, b), &c)| c == 1 && !half.contains_key(&(b, a)))
        .map(|(&e, _)| e)
        .collect();
    keys.sort_unstable();
    for (a, b) in keys {
        out.entry(b).or_default().push(a);
        n_hole += 1;
    }
    let mut m = mesh.clone();
    let mut report = HoleReport::default();
    let mut starts: Vec<u32> = out.keys().copied().collect();
    starts.sort_unstable();
    let mut used_edges = 0usize;
    for s in starts {
        while let Some(first) = out.get_mut(&s).and_then(|v| v.pop()) {
            // Trace s → first → ... back to s.
            let mut lp = vec![s, first];
            let mut cur = first;
            let mut closed = false;
            while lp.len() <= n_hole + 1 {
                if cur == s {
                    closed = true;
                    break;
                }
                match out.get_mut(&cur).and_then(|v| v.pop()) {
                    Some(nx) => {
                        lp.push(nx);
                        cur = nx;
                    }
                    None => break,
                }
            }
            if !closed || lp.len() < 4 {
                // lp.len() < 4: a loop of two edges (a doubled edge) needs no fan.
                continue;
            }
            lp.pop(); // the repeated start
            used_edges += lp.len();
            let cen = scale(
                lp.iter()
                    .fold([0.0; 3], |acc, &v| add(acc, m.vertices[v as usize])),
                1.0 / lp.len() as f64,
            );
            let ci = m.vertices.len() as u32;
            m.vertices.push(cen);
            for k in 0..lp.len() {
                m.triangles.push([lp[k], lp[(k + 1) % lp.len()], ci]);
            }
            report.filled += 1;
        }
    }
    report.open_edges = n_hole - used_edges;
    let mut used = vec![false; mesh.vertices.len()];
    for t in &mesh.triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    report.isolated_vertices = used.iter().filter(|u| !**u).count();
    (m, report)
}

/// Map the triangles' bounding box into the unit cube: centred at (½, ½, ½), longest
/// side 1 − 2·margin (the paper tiles the unit cube). Returns the mesh and the map
/// (scale s, shift t: x ↦ s·x + t).
pub fn normalize_to_unit_cube(mesh: &TriMesh, margin: f64) -> Result<(TriMesh, f64, [f64; 3])> {
    if !(margin.is_finite() && (0.0..0.5).contains(&margin)) {
        return Err(Error::Param(format!(
            "margin = {margin} must be in [0, 0.5)"
        )));
    }
    let used: Vec<[f64; 3]> = mesh
        .triangles
        .iter()
        .flat_map(|t| {
            t.iter().map(|&i| {
                mesh.vertices
                    .get(i as usize)
                    .copied()
                    .unwrap_or([f64::NAN; 3])
            })
        })
        .collect();
    if used.is_empty() {
        return Err(Error::Param("the mesh has no triangles".into()));
    }
    if let Some(k) = crate::kernel::finite::first_non_finite(used.as_flattened()).map(|i| i / 3) {
        return Err(Error::NotFinite(format!(
            "corner {} of triangle {} is out of range or not finite",
            k % 3,
            k / 3
        )));
    }
    let b = Aabb::of_points(&used).expect("non-empty");
    let sz = b.size();
    let side = sz[0].max(sz[1]).max(sz[2]);
    if !(side > 0.0) {
        return Err(Error::Domain(
            "the mesh's triangles span a single point".into(),
        ));
    }
    let s = (1.0 - 2.0 * margin) / side;
    let c = b.center();
    let t = [0.5 - s * c[0], 0.5 - s * c[1], 0.5 - s * c[2]];
    let mut m = mesh.clone();
    for v in &mut m.vertices {
        *v = add(scale(*v, s), t);
    }
    Ok((m, s, t))
}

/// A UV sphere of the given radius centred at the origin, outward oriented, closed
/// (poles are single vertices): `rings` ≥ 2 latitude bands, `segments` ≥ 3 longitudes.
pub fn uv_sphere(rings: usize, segments: usize, radius: f64) -> TriMesh {
    use std::f64::consts::{PI, TAU};
    let rings = rings.max(2);
    let segments = segments.max(3);
    let mut v = vec![[0.0, 0.0, radius]];
    for i in 1..rings {
        let th = PI * i as f64 / rings as f64;
        for j in 0..segments {
            let ph = TAU * j as f64 / segments as f64;
            v.push([
                radius * th.sin() * ph.cos(),
                radius * th.sin() * ph.sin(),
                radius * th.cos(),
            ]);
        }
    }
    let south = v.len() as u32;
    v.push([0.0, 0.0, -radius]);
    let at = |i: usize, j: usize| (1 + (i - 1) * segments + j % segments) as u32;
    let mut t = Vec::new();
    for j in 0..segments {
        t.push([0, at(1, j), at(1, j + 1)]);
        t.push([south, at(rings - 1, j + 1), at(rings - 1, j)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    TriMesh::new(v, t)
}

/// Read a triangle mesh (OBJ/PLY/OFF/STL by extension), optionally fill its holes, and
/// normalise it into the unit cube with `margin`: the signed distance and what was done.
pub fn from_file(path: &std::path::Path, margin: f64, fill: bool) -> Result<(MeshSdf, HoleReport)> {
    let mesh = crate::io::read_tri(path)?;
    let (mesh, report) = if fill {
        fill_holes(&mesh)
    } else {
        (mesh, HoleReport::default())
    };
    let (mesh, _, _) = normalize_to_unit_cube(&mesh, margin)?;
    let name = path
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string());
    let sdf = MeshSdf::new(&mesh)?.named(format!(
        "signed distance to {name}{}",
        if fill { " (holes filled)" } else { "" }
    ));
    Ok((sdf, report))
}
