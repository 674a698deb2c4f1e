//! Geometric fidelity of a mesh to the surface f = 0 it approximates: distance
//! estimates at the vertices, a sampled two-sided Hausdorff estimate, and the deviation
//! of the triangle normals from ∇f.
//!
//! These are *measurements*, not certificates: sampling can miss the worst point (an
//! underestimate), and a mesh point's distance is taken to its Newton projection, a
//! point of the surface but not always the nearest one (an overestimate per sample).
//! Each field says what it measures.
use crate::bvh::{SegBvh, TriBvh};
use crate::error::{Error, Result};
use crate::geom::{self, Aabb};
use crate::implicit::Implicit;
use crate::mesh::{Curve2, TriMesh};
use rayon::prelude::*;
use serde::Serialize;

/// How much sampling to do. Defaults: 50 000 mesh samples, a 48³ (curves: 256²) seed
/// grid, 16 Newton steps, domain = mesh bounding box grown by 10% of its diagonal.
#[derive(Clone, Debug, PartialEq)]
pub struct FidelityParams {
    /// Points sampled on the mesh (area-proportional, deterministic), besides its vertices.
    pub mesh_samples: usize,
    /// Seeds per axis of the grid from which surface points are found.
    pub seed_grid: usize,
    pub newton_steps: usize,
    /// Where to look for the surface. Give the catalog entry's domain to catch
    /// components the mesh misses entirely.
    pub domain: Option<Aabb>,
}

impl Default for FidelityParams {
    fn default() -> Self {
        FidelityParams {
            mesh_samples: 50_000,
            seed_grid: 0,
            newton_steps: 16,
            domain: None,
        }
    }
}

impl FidelityParams {
    pub fn mesh_samples(mut self, n: usize) -> Self {
        self.mesh_samples = n;
        self
    }
    /// 0 means the default (48 for surfaces, 256 for curves).
    pub fn seed_grid(mut self, n: usize) -> Self {
        self.seed_grid = n;
        self
    }
    pub fn newton_steps(mut self, n: usize) -> Self {
        self.newton_steps = n;
        self
    }
    pub fn domain(mut self, d: Aabb) -> Self {
        self.domain = Some(d);
        self
    }
}

/// Fidelity of a mesh to f = 0. Distances are in model units.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Fidelity {
    /// max over used vertices of |f|/|∇f|: the first-order distance estimate
    /// (infinite if ∇f vanishes at a vertex where f does not).
    pub max_distance_estimate: f64,
    pub mean_distance_estimate: f64,
    /// Mesh → surface: max over vertices and samples of the distance to their Newton
    /// projection onto f = 0. Each distance bounds the distance to the surface from
    /// above (the projection is a point of the surface, not always the nearest one).
    pub hausdorff_mesh_to_surface: f64,
    pub mean_mesh_to_surface: f64,
    /// Surface → mesh: max over surface points (grid seeds projected by Newton) of the
    /// exact distance to the mesh (BVH closest point).
    pub hausdorff_surface_to_mesh: f64,
    pub mean_surface_to_mesh: f64,
    /// The larger of the two directions.
    pub hausdorff: f64,
    pub fidelity_mesh_samples: usize,
    pub fidelity_surface_samples: usize,
    /// Mesh samples whose Newton projection did not converge (left out).
    pub fidelity_unconverged: usize,
    /// Angle between each element's normal and ∇f at its centroid's projection,
    /// ignoring orientation (min(θ, 180° − θ)), in degrees.
    pub normal_dev_max_deg: f64,
    pub normal_dev_mean_deg: f64,
    /// Elements whose normal points against ∇f (θ > 90°): against the convention that
    /// normals point towards f > 0. Always 0 for curves (which carry no orientation).
    pub flipped_normals: usize,
}

/// Project `p` onto f = 0 by Newton steps p ← p − f ∇f / |∇f|². `None` when ∇f
/// vanishes, a value is not finite, or the last step is still above `tol`.
pub fn project(f: &dyn Implicit, p: [f64; 3], steps: usize, tol: f64) -> Option<[f64; 3]> {
    let planar = f.dim() == 2;
    let mut q = p;
    for _ in 0..steps.max(1) {
        let d = f.grad(q);
        let mut g = d.g;
        if planar {
            g[2] = 0.0;
        }
        let g2 = geom::dot(g, g);
        if !(g2 > 0.0) || !d.v.is_finite() || !g2.is_finite() {
            return None;
        }
        let t = d.v / g2;
        q = geom::sub(q, geom::scale(g, t));
        if (t.abs() * g2.sqrt()) <= tol {
            return Some(q);
        }
    }
    None
}

/// The first-order distance estimate |f|/|∇f| at `p`.
pub fn distance_estimate(f: &dyn Implicit, p: [f64; 3]) -> f64 {
    let d = f.grad(p);
    let mut g = d.g;
    if f.dim() == 2 {
        g[2] = 0.0;
    }
    let n = geom::norm(g);
    if d.v == 0.0 {
        0.0
    } else if n > 0.0 {
        d.v.abs() / n
    } else {
        f64::INFINITY
    }
}

/// The R2 low-discrepancy sequence (Roberts 2018): well-spread, deterministic.
fn r2(i: usize) -> (f64, f64) {
    const A1: f64 = 0.754_877_666_246_692_7;
    const A2: f64 = 0.569_840_290_998_053_2;
    let x = (0.5 + A1 * i as f64).fract();
    let y = (0.5 + A2 * i as f64).fract();
    (x, y)
}

fn max_mean(v: &[f64]) -> (f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0);
    }
    let m = v.iter().copied().fold(0.0, f64::max);
    (m, v.iter().sum::<f64>() / v.len() as f64)
}

/// Surface points: centres of an n^dim grid over `domain`, kept where the first-order
/// distance is under a cell diagonal, projected by Newton, kept if converged and still
/// in the domain (grown by one cell).
pub fn surface_points(
    f: &dyn Implicit,
    domain: &Aabb,
    n: usize,
    steps: usize,
    tol: f64,
) -> Vec<[f64; 3]> {
    let planar = f.dim() == 2;
    let n = n.max(2);
    let size = domain.size();
    let h = size.map(|s| s / n as f64);
    let reach = geom::norm(if planar { [h[0], h[1], 0.0] } else { h });
    let nz = if planar { 1 } else { n };
    let grown = domain.inflate(reach);
    (0..n * n * nz)
        .into_par_iter()
        .filter_map(|idx| {
            let (i, j, k) = (idx % n, (idx / n) % n, idx / (n * n));
            let p = [
                domain.min[0] + (i as f64 + 0.5) * h[0],
                domain.min[1] + (j as f64 + 0.5) * h[1],
                if planar {
                    0.0
                } else {
                    domain.min[2] + (k as f64 + 0.5) * h[2]
                },
            ];
            if !(distance_estimate(f, p) < reach) {
                return None;
            }
            let q = project(f, p, steps, tol)?;
            grown.contains(q).then_some(q)
        })
        .collect()
}

fn default_domain(pts: &[[f64; 3]], planar: bool) -> Result<Aabb> {
    let b = Aabb::of_points(pts).ok_or_else(|| Error::Param("the mesh has no vertices".into()))?;
    let mut d = b.inflate(0.1 * b.diagonal().max(1e-300));
    if planar {
        d.min[2] = 0.0;
        d.max[2] = 0.0;
    }
    Ok(d)
}

/// The vertices some element uses, in index order.
fn used_vertices<const N: usize>(nv: usize, elems: &[[u32; N]]) -> Vec<u32> {
    let mut used = vec![false; nv];
    for e in elems {
        for &v in e {
            used[v as usize] = true;
        }
    }
    (0..nv as u32).filter(|&v| used[v as usize]).collect()
}

/// `n` deterministic points spread over the elements in proportion to their sizes
/// (stratified along the cumulative size; none when the total is not positive):
/// `point(e, i)` places sample `i` in element `e`.
fn stratified(
    sizes: &[f64],
    n: usize,
    point: impl Fn(usize, usize) -> [f64; 3] + Sync,
) -> Vec<[f64; 3]> {
    let mut cum = Vec::with_capacity(sizes.len());
    let mut acc = 0.0;
    for s in sizes {
        acc += s;
        cum.push(acc);
    }
    let ns = if acc > 0.0 { n } else { 0 };
    (0..ns)
        .into_par_iter()
        .map(|i| {
            let u = (i as f64 + 0.5) / ns as f64 * acc;
            let e = cum.partition_point(|&c| c < u).min(sizes.len() - 1);
            point(e, i)
        })
        .collect()
}

/// What surfaces and curves measure alike: the search domain, the Newton tolerance and
/// steps, and the used vertices.
struct Setup<'a> {
    f: &'a dyn Implicit,
    verts: Vec<[f64; 3]>,
    domain: Aabb,
    tol: f64,
    steps: usize,
}

impl<'a> Setup<'a> {
    fn new(
        f: &'a dyn Implicit,
        verts: Vec<[f64; 3]>,
        planar: bool,
        params: &FidelityParams,
    ) -> Result<Self> {
        let domain = match params.domain {
            Some(d) => d,
            None => default_domain(&verts, planar)?,
        };
        Ok(Setup {
            f,
            verts,
            domain,
            tol: 1e-10 * domain.diagonal().max(f64::MIN_POSITIVE),
            steps: params.newton_steps,
        })
    }

    fn project(&self, p: [f64; 3]) -> Option<[f64; 3]> {
        project(self.f, p, self.steps, self.tol)
    }

    /// The report, from the mesh samples, the distance from a surface point to the mesh
    /// (`to_mesh`), the unsigned normal deviations and the flipped elements.
    fn finish(
        &self,
        samples: &[[f64; 3]],
        seed_grid: usize,
        to_mesh: impl Fn([f64; 3]) -> Option<f64> + Sync,
        deviations: &[f64],
        flipped_normals: usize,
    ) -> Fidelity {
        let est: Vec<f64> = self
            .verts
            .par_iter()
            .map(|&p| distance_estimate(self.f, p))
            .collect();
        let (max_est, mean_est) = max_mean(&est);
        let m2s: Vec<Option<f64>> = self
            .verts
            .par_iter()
            .chain(samples.par_iter())
            .map(|&p| self.project(p).map(|q| geom::dist(p, q)))
            .collect();
        let unconverged = m2s.iter().filter(|d| d.is_none()).count();
        let m2s: Vec<f64> = m2s.into_iter().flatten().collect();
        let (h_ms, mean_ms) = max_mean(&m2s);
        let spts = surface_points(self.f, &self.domain, seed_grid, self.steps, self.tol);
        let s2m: Vec<f64> = spts.par_iter().filter_map(|&p| to_mesh(p)).collect();
        let (h_sm, mean_sm) = max_mean(&s2m);
        let (dmax, dmean) = max_mean(deviations);
        Fidelity {
            max_distance_estimate: max_est,
            mean_distance_estimate: mean_est,
            hausdorff_mesh_to_surface: h_ms,
            mean_mesh_to_surface: mean_ms,
            hausdorff_surface_to_mesh: h_sm,
            mean_surface_to_mesh: mean_sm,
            hausdorff: h_ms.max(h_sm),
            fidelity_mesh_samples: m2s.len(),
            fidelity_surface_samples: s2m.len(),
            fidelity_unconverged: unconverged,
            normal_dev_max_deg: dmax,
            normal_dev_mean_deg: dmean,
            flipped_normals,
        }
    }
}

/// `params.seed_grid`, or `default` when it is 0.
fn seeds(params: &FidelityParams, default: usize) -> usize {
    if params.seed_grid == 0 {
        default
    } else {
        params.seed_grid
    }
}

/// Fidelity of a triangle mesh to f = 0.
pub fn surface_fidelity(
    mesh: &TriMesh,
    f: &dyn Implicit,
    params: &FidelityParams,
) -> Result<Fidelity> {
    super::check_trimesh(mesh)?;
    if f.dim() != 3 {
        return Err(Error::Param(format!(
            "a triangle mesh needs a surface f(x, y, z), got a function of dimension {}",
            f.dim()
        )));
    }
    let verts = used_vertices(mesh.vertices.len(), &mesh.triangles)
        .into_iter()
        .map(|v| mesh.vertices[v as usize])
        .collect();
    let setup = Setup::new(f, verts, false, params)?;

    // Area-proportional deterministic samples.
    let areas: Vec<f64> = (0..mesh.triangles.len())
        .map(|t| {
            let [a, b, c] = mesh.corners(t);
            0.5 * geom::norm(geom::cross(geom::sub(b, a), geom::sub(c, a)))
        })
        .collect();
    let samples = stratified(&areas, params.mesh_samples, |t, i| {
        let [a, b, c] = mesh.corners(t);
        let (r1, r2) = r2(i);
        let s = r1.sqrt();
        let (wa, wb, wc) = (1.0 - s, s * (1.0 - r2), s * r2);
        [0, 1, 2].map(|k| wa * a[k] + wb * b[k] + wc * c[k])
    });

    let bvh = TriBvh::new(mesh)?;

    // Normal deviation at the centroids' projections.
    let dev: Vec<Option<f64>> = (0..mesh.triangles.len())
        .into_par_iter()
        .map(|t| {
            let [a, b, c] = mesh.corners(t);
            let n = geom::cross(geom::sub(b, a), geom::sub(c, a));
            if !(geom::norm(n) > 0.0) {
                return None;
            }
            let cen = geom::scale(geom::add(geom::add(a, b), c), 1.0 / 3.0);
            let q = setup.project(cen).unwrap_or(cen);
            let g = f.grad(q).g;
            if !(geom::norm(g) > 0.0) {
                return None;
            }
            Some(
                geom::norm(geom::cross(n, g))
                    .atan2(geom::dot(n, g))
                    .to_degrees(),
            )
        })
        .collect();
    let dev: Vec<f64> = dev.into_iter().flatten().collect();
    let flipped = dev.iter().filter(|&&a| a > 90.0).count();
    let unsigned: Vec<f64> = dev.iter().map(|&a| a.min(180.0 - a)).collect();

    Ok(setup.finish(
        &samples,
        seeds(params, 48),
        |p| bvh.closest(p).map(|c| c.dist2.sqrt()),
        &unsigned,
        flipped,
    ))
}

/// Fidelity of a planar curve to f(x, y) = 0: the same measures in 2D (segment samples,
/// a 2D seed grid, segment normals against ∇f without orientation).
pub fn curve_fidelity(
    curve: &Curve2,
    f: &dyn Implicit,
    params: &FidelityParams,
) -> Result<Fidelity> {
    super::check_curve(curve)?;
    if f.dim() != 2 {
        return Err(Error::Param(format!(
            "a curve needs a function f(x, y), got a function of dimension {}",
            f.dim()
        )));
    }
    let lift = |v: u32| {
        let [x, y] = curve.vertices[v as usize];
        [x, y, 0.0]
    };
    let verts = used_vertices(curve.vertices.len(), &curve.segments)
        .into_iter()
        .map(lift)
        .collect();
    let setup = Setup::new(f, verts, true, params)?;

    let lens: Vec<f64> = curve
        .segments
        .iter()
        .map(|&[a, b]| geom::dist(lift(a), lift(b)))
        .collect();
    let samples = stratified(&lens, params.mesh_samples, |s, i| {
        let [a, b] = curve.segments[s];
        geom::lerp(lift(a), lift(b), r2(i).0)
    });

    let bvh = SegBvh::new(curve)?;

    let dev: Vec<f64> = curve
        .segments
        .par_iter()
        .filter_map(|&[a, b]| {
            let (a, b) = (lift(a), lift(b));
            let d = geom::sub(b, a);
            let n = [d[1], -d[0], 0.0];
            if !(geom::norm(n) > 0.0) {
                return None;
            }
            let mid = geom::lerp(a, b, 0.5);
            let q = setup.project(mid).unwrap_or(mid);
            let mut g = f.grad(q).g;
            g[2] = 0.0;
            if !(geom::norm(g) > 0.0) {
                return None;
            }
            let th = geom::norm(geom::cross(n, g))
                .atan2(geom::dot(n, g))
                .to_degrees();
            Some(th.min(180.0 - th))
        })
        .collect();
    Ok(setup.finish(
        &samples,
        seeds(params, 256),
        |p| bvh.closest([p[0], p[1]]).map(|c| c.dist2.sqrt()),
        &dev,
        0,
    ))
}
