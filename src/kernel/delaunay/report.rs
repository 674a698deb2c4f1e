//! What the command line needs: random point sets, a timed build with a serialisable
//! report, and a VTK writer (through [`crate::io::vtk`]).
use super::order::SplitMix;
use super::{CheckReport, Delaunay, FAR};
use crate::error::Result;
use crate::mesh::TetMesh;
use serde::Serialize;

/// Where [`random_points`] samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Sampler {
    /// Uniform in the cube [-1, 1]³.
    Uniform,
    /// Uniform on the unit sphere (every in-sphere test is nearly degenerate).
    Sphere,
    /// Uniform (by area) on the torus with radii 1 and 0.35 around the z axis.
    Torus,
}

/// `n` points from `on`, reproducible from `seed`.
pub fn random_points(n: usize, on: Sampler, seed: u64) -> Vec<[f64; 3]> {
    let mut r = SplitMix(seed);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        match on {
            Sampler::Uniform => {
                out.push([0; 3].map(|_| 2.0 * r.uniform() - 1.0));
            }
            Sampler::Sphere => {
                let q = [0; 3].map(|_| 2.0 * r.uniform() - 1.0);
                let n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
                if n2 > 1e-6 && n2 <= 1.0 {
                    let s = 1.0 / n2.sqrt();
                    out.push(q.map(|x| x * s));
                }
            }
            Sampler::Torus => {
                let (big, small) = (1.0, 0.35);
                let u = std::f64::consts::TAU * r.uniform();
                let v = std::f64::consts::TAU * r.uniform();
                // Area element ∝ (R + r cos v): rejection.
                if r.uniform() * (big + small) <= big + small * v.cos() {
                    let w = big + small * v.cos();
                    out.push([w * u.cos(), w * u.sin(), small * v.sin()]);
                }
            }
        }
    }
    out
}

/// Options of [`build_report`].
#[derive(Clone, Copy, Debug)]
pub struct ReportOptions {
    /// Seed of the insertion order and the walk.
    pub seed: u64,
    /// Run the (slower, exact) validity check.
    pub check: bool,
}

impl Default for ReportOptions {
    fn default() -> Self {
        ReportOptions {
            seed: 1,
            check: true,
        }
    }
}

/// The outcome of a timed build.
#[derive(Clone, Debug, Serialize)]
pub struct DelaunayReport {
    pub n_points: usize,
    pub n_inserted: usize,
    /// Input indices of points equal to an earlier one (not inserted).
    pub duplicates: Vec<usize>,
    /// Live cells, including those with a far vertex.
    pub cells: usize,
    /// Cells whose 4 vertices are input points.
    pub finite_cells: usize,
    /// Construction time (ordering + insertion), not the check.
    pub seconds: f64,
    pub points_per_second: f64,
    /// Estimated heap bytes of the triangulation.
    pub memory_bytes: usize,
    /// The check's verdict; `None` when the check was not asked for.
    pub valid: Option<bool>,
    pub check: Option<CheckReport>,
}

/// Build the triangulation of `points`, time it, and optionally check it. Errors on a
/// non-finite coordinate, naming the point.
pub fn build_report(
    points: &[[f64; 3]],
    opts: ReportOptions,
) -> Result<(Delaunay, DelaunayReport)> {
    let t0 = std::time::Instant::now();
    let (t, bulk) = Delaunay::from_points(points, opts.seed)?;
    let seconds = t0.elapsed().as_secs_f64();
    let check = opts.check.then(|| t.check());
    let n_inserted = points.len() - bulk.duplicates.len();
    let report = DelaunayReport {
        n_points: points.len(),
        n_inserted,
        duplicates: bulk.duplicates.iter().map(|d| d.0).collect(),
        cells: t.num_cells(),
        finite_cells: t.finite_cells().count(),
        seconds,
        points_per_second: if seconds > 0.0 {
            points.len() as f64 / seconds
        } else {
            0.0
        },
        memory_bytes: t.memory_bytes(),
        valid: check.as_ref().map(|c| c.valid),
        check,
    };
    Ok((t, report))
}

/// The tetrahedra with no far vertex. Mesh vertex `i` is bulk input point `i`
/// (duplicates are unreferenced vertices), then come the points added by
/// [`Delaunay::insert`] in the order they were added.
pub fn tet_mesh(t: &Delaunay) -> TetMesh {
    let n = t.num_inputs();
    let index = |v: u32| match t.input_index(v) {
        Some(i) => i as u32,
        None => v - FAR,
    };
    let mut vertices = vec![[0.0; 3]; t.points().len() - FAR as usize];
    for v in FAR..t.points().len() as u32 {
        vertices[index(v) as usize] = t.point(v);
    }
    debug_assert!(vertices.len() >= n);
    TetMesh {
        vertices,
        tets: t
            .finite_cells()
            .map(|c| t.cell_vertices(c).map(index))
            .collect(),
    }
}

/// Write the finite tetrahedra as a legacy VTK unstructured grid.
pub fn write_vtk(w: impl std::io::Write, t: &Delaunay) -> Result<()> {
    crate::io::vtk::write(w, &tet_mesh(t))
}

/// The terms of the circumcentre formula from the edge vectors d_i = p_{i+1} − p_0:
/// the squared lengths |d_i|², the cross products d1×d2, d2×d0, d0×d1 and the
/// determinant det = d0·(d1×d2); the centre is p0 + (Σ |d_i|² c_i) / (2 det). Generic
/// over the number type, so the float centre and its interval enclosure
/// (`restricted_delaunay`) are one formula; `sq` squares (intervals: the tight `sqr`).
pub fn circumcentre_terms<T>(d: [[T; 3]; 3], sq: impl Fn(T) -> T) -> ([T; 3], [[T; 3]; 3], T)
where
    T: Copy + std::ops::Add<Output = T> + std::ops::Sub<Output = T> + std::ops::Mul<Output = T>,
{
    let l: [T; 3] = d.map(|v| sq(v[0]) + sq(v[1]) + sq(v[2]));
    let cross = |a: [T; 3], b: [T; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let c = [cross(d[1], d[2]), cross(d[2], d[0]), cross(d[0], d[1])];
    let det = d[0][0] * c[0][0] + d[0][1] * c[0][1] + d[0][2] * c[0][2];
    (l, c, det)
}

/// Circumcentre of a tetrahedron in floating point (relative to `p[0]` for accuracy).
pub fn circumcentre(p: [[f64; 3]; 4]) -> [f64; 3] {
    let d: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|k| p[i + 1][k] - p[0][k]));
    let (l, [c12, c20, c01], det) = circumcentre_terms(d, |x: f64| x * x);
    let s = 0.5 / det;
    std::array::from_fn(|k| p[0][k] + s * (l[0] * c12[k] + l[1] * c20[k] + l[2] * c01[k]))
}
