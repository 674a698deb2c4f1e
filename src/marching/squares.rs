//! Marching squares: the 2D baseline, with the same face rule as marching cubes' cube
//! faces ("negative corners are separated" on a square with four crossings), so the
//! output is closed polylines away from the domain boundary. Crossing vertices are
//! shared through grid edges.
//!
//! Segments are oriented with f < 0 on their left: each closed polyline runs
//! counter-clockwise around the region it encloses when that region is negative.
use super::{base_stats, check_curve, crosses, crossing_t_linear, GridParams};
use crate::error::{Error, Result};
use crate::implicit::ops::crossing_t;
use crate::implicit::{Counted, Implicit};
use crate::kernel::geom::{lerp, Aabb};
use crate::lattice::grid::{Field, Grid, Samples};
use crate::lattice::octree;
use crate::mesh::Curve2;
use crate::mesher::options::{Crossing, MesherOptions};
use crate::mesher::{Certificate, Mesh, MeshOutput, Mesher, Progress};
use serde_json::json;
use std::collections::HashMap;

/// Marching squares, `"ms"`. Defaults ([`GridParams::default`]): 64 cells along the
/// longest side, linear interpolation, no pruning.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MarchingSquares {
    pub params: GridParams,
}

impl MarchingSquares {
    pub fn new() -> Self {
        Self::default()
    }
    /// Cells along the longest side of the domain (default 64).
    pub fn resolution(mut self, n: usize) -> Self {
        self.params.resolution = n;
        self
    }
    /// Linear interpolation (default) or bisection on f.
    pub fn crossing(mut self, c: Crossing) -> Self {
        self.params.crossing = c;
        self
    }
    /// Bisection tolerance, as a fraction of the edge (default 1e-6).
    pub fn tolerance(mut self, t: f64) -> Self {
        self.params.tolerance = t;
        self
    }
    /// Prune empty space with intervals (default false). Same output, fewer evaluations.
    pub fn prune(mut self, p: bool) -> Self {
        self.params.prune = p;
        self
    }
    /// Side of the pruning descent's leaf blocks, in cells (default 4).
    pub fn leaf(mut self, n: usize) -> Self {
        self.params.leaf = n;
        self
    }
    /// From `--resolution`, `--crossing`, `--tolerance`, `--prune`, `--set leaf=N`.
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        Ok(MarchingSquares {
            params: GridParams::from_options("ms", o)?,
        })
    }
}

impl Mesher for MarchingSquares {
    fn name(&self) -> &'static str {
        "ms"
    }
    fn dim(&self) -> usize {
        2
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        let p = &self.params;
        p.check()?;
        check_curve("ms", f)?;
        let grid = Grid::new(domain, p.resolution, 2)?;
        let mut stats = base_stats(&grid, p);
        let bis = Counted::new(f);
        let bisect = match p.crossing {
            Crossing::Linear => None,
            Crossing::Bisection => Some((&bis as &dyn Implicit, p.tolerance)),
        };
        let (curve, visited) = if p.prune {
            let (s, st) = octree::sample_pruned_with(f, &grid, p.leaf, progress)?;
            stats.insert("cells_pruned".into(), json!(st.cells_pruned));
            stats.insert(
                "interval_evaluations".into(),
                json!(st.interval_evaluations),
            );
            stats.insert("point_evaluations".into(), json!(st.point_evaluations));
            squares(&s, bisect)?
        } else {
            let s = Samples::sample(f, &grid, progress)?;
            stats.insert("cells_pruned".into(), json!(0));
            stats.insert("interval_evaluations".into(), json!(0));
            stats.insert("point_evaluations".into(), json!(grid.num_vertices()));
            squares(&s, bisect)?
        };
        stats.insert("cells_visited".into(), json!(visited));
        stats.insert("crossing_evaluations".into(), json!(bis.counts().points));
        Ok(MeshOutput {
            mesh: Mesh::Curve(curve),
            certificate: Certificate::none(
                "marching squares proves nothing: it reads the signs of f at grid vertices \
                 only, so components and necks smaller than a cell are missed or merged",
            ),
            stats,
        })
    }
}

/// Marching squares on an already sampled planar grid, crossings by linear
/// interpolation.
pub fn marching_squares<F: Field>(field: &F) -> Result<Curve2> {
    Ok(squares(field, None)?.0)
}

/// The extraction; returns the curve and the number of cells with a sign change.
fn squares<F: Field>(field: &F, bisect: Option<(&dyn Implicit, f64)>) -> Result<(Curve2, u64)> {
    let g = *field.grid();
    if g.dim() != 2 {
        return Err(Error::Param("marching squares needs a planar grid".into()));
    }
    let [cx, cy, _] = g.cells();
    let mut vertices: Vec<[f64; 2]> = Vec::new();
    let mut segments = Vec::new();
    // Crossing vertex of grid edge (vertex index * 2 + axis), created on first use.
    let mut ids: HashMap<usize, u32> = HashMap::new();
    let mut vertex = |i: usize, j: usize, axis: usize| -> u32 {
        let key = g.index(i, j, 0) * 2 + axis;
        *ids.entry(key).or_insert_with(|| {
            let (i2, j2) = if axis == 0 { (i + 1, j) } else { (i, j + 1) };
            let (a, b) = (field.value(i, j, 0), field.value(i2, j2, 0));
            let (p, q) = (g.point(i, j, 0), g.point(i2, j2, 0));
            let t = match bisect {
                None => crossing_t_linear(a, b),
                Some((f, tol)) => crossing_t(f, p, a, q, b, Crossing::Bisection, tol),
            };
            let x = lerp(p, q, t);
            vertices.push([x[0], x[1]]);
            (vertices.len() - 1) as u32
        })
    };
    // Corners counter-clockwise (seen from +z) and the edge from corner m to m + 1, as
    // (lower vertex offset, axis).
    const Q: [[usize; 2]; 4] = [[0, 0], [1, 0], [1, 1], [0, 1]];
    const E: [([usize; 2], usize); 4] = [([0, 0], 0), ([1, 0], 1), ([0, 1], 0), ([0, 0], 1)];
    let mut visited = 0u64;
    for j in 0..cy {
        for i in 0..cx {
            let v = Q.map(|o| field.value(i + o[0], j + o[1], 0));
            if F::SPARSE && v.iter().any(|x| x.is_nan()) {
                continue;
            }
            let cr = [0, 1, 2, 3].map(|m| crosses(v[m], v[(m + 1) % 4]));
            if !cr.iter().any(|&c| c) {
                continue;
            }
            visited += 1;
            // Walking counter-clockwise, join each positive-to-negative crossing to the
            // next crossing: the negative corner in between is on the segment's right,
            // so emit the segment reversed (negative on the left).
            for m in 0..4 {
                if v[m] >= 0.0 && v[(m + 1) % 4] < 0.0 {
                    let m2 = (1..4).map(|o| (m + o) % 4).find(|&m2| cr[m2]).unwrap();
                    let (o1, a1) = E[m];
                    let (o2, a2) = E[m2];
                    let s = vertex(i + o1[0], j + o1[1], a1);
                    let e = vertex(i + o2[0], j + o2[1], a2);
                    segments.push([e, s]);
                }
            }
        }
    }
    Ok((Curve2 { vertices, segments }, visited))
}
