//! Marching tetrahedra: each grid cube is split into the 6 Kuhn (Freudenthal)
//! tetrahedra around its main diagonal from corner (0,0,0) to (1,1,1), one
//! `(c0, c0 + e_a, c0 + e_a + e_b, c7)` per permutation `(a, b, c)` of the axes. Every
//! cube uses the same diagonal direction, so the split of a shared face is the same
//! from both sides: the tetrahedra form one global triangulation of the grid, and the
//! surface is watertight with no ambiguity rule at all. A tetrahedron with one corner
//! of a sign gives one triangle, two and two give a quad cut into two triangles along
//! a diagonal that lies inside the tetrahedron (it never lies on a shared face).
//!
//! Grid edges are of 7 kinds (the 0/1 offsets +x, +y, +z, the face diagonals and the
//! main diagonal); crossings are shared through them like marching cubes' edges.
use super::{extract, mesh_3d, GridParams, Place, Scheme};
use crate::error::Result;
use crate::implicit::Implicit;
use crate::kernel::geom::{cross, dot, Aabb};
use crate::lattice::grid::Field;
use crate::mesh::TriMesh;
use crate::mesher::options::{Crossing, MesherOptions};
use crate::mesher::{MeshOutput, Mesher, Progress};
use std::sync::OnceLock;

/// Marching tetrahedra, `"mt"`. Defaults ([`GridParams::default`]): 64 cells along the
/// longest side, linear interpolation, no pruning.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MarchingTetrahedra {
    pub params: GridParams,
}

impl MarchingTetrahedra {
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
        Ok(MarchingTetrahedra {
            params: GridParams::from_options("mt", o)?,
        })
    }
}

impl Mesher for MarchingTetrahedra {
    fn name(&self) -> &'static str {
        "mt"
    }
    fn dim(&self) -> usize {
        3
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        mesh_3d(
            "marching tetrahedra",
            table(),
            &self.params,
            f,
            domain,
            progress,
        )
    }
}

/// Marching tetrahedra on an already sampled grid, crossings by linear interpolation.
pub fn marching_tetrahedra<F: Field>(field: &F) -> Result<TriMesh> {
    Ok(extract(field, table(), Place::Linear)?.mesh)
}

fn table() -> &'static Scheme {
    static T: OnceLock<Scheme> = OnceLock::new();
    T.get_or_init(build)
}

/// The six Kuhn tetrahedra of the unit cube, as corner indices.
pub(crate) fn kuhn_tets() -> [[u8; 4]; 6] {
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    perms.map(|[a, b, _]| [0u8, 1 << a, (1 << a) | (1 << b), 7])
}

fn pos(c: u8) -> [f64; 3] {
    [(c & 1) as f64, ((c >> 1) & 1) as f64, ((c >> 2) & 1) as f64]
}

fn mid(a: u8, b: u8) -> [f64; 3] {
    let (p, q) = (pos(a), pos(b));
    [0, 1, 2].map(|k| 0.5 * (p[k] + q[k]))
}

fn build() -> Scheme {
    let mut s = Scheme {
        dirs: vec![1, 2, 4],
        edges: Vec::new(),
        cases: Vec::with_capacity(256),
    };
    let tets = kuhn_tets();
    for case in 0..256usize {
        let neg = |c: u8| case >> c & 1 == 1;
        let mut tris = Vec::new();
        for t in &tets {
            let (n, p): (Vec<u8>, Vec<u8>) = t.iter().partition(|&&c| neg(c));
            // Triangles as corner pairs (one crossing per pair).
            let polys: Vec<[(u8, u8); 3]> = match (n.len(), p.len()) {
                (1, 3) => vec![[(n[0], p[0]), (n[0], p[1]), (n[0], p[2])]],
                (3, 1) => vec![[(n[0], p[0]), (n[1], p[0]), (n[2], p[0])]],
                (2, 2) => {
                    let (a, b, c, d) = (n[0], n[1], p[0], p[1]);
                    // The quad ac, ad, bd, bc, cut along ac–bd (inside the tetrahedron).
                    vec![[(a, c), (a, d), (b, d)], [(a, c), (b, d), (b, c)]]
                }
                _ => vec![],
            };
            // Orientation from the midpoint surface, which separates the corners
            // exactly: the normal must point from the negative to the positive corners.
            let centroid = |cs: &[u8]| {
                let mut m = [0.0; 3];
                for &c in cs {
                    let q = pos(c);
                    for k in 0..3 {
                        m[k] += q[k] / cs.len() as f64;
                    }
                }
                m
            };
            let (cn, cp) = (centroid(&n), centroid(&p));
            let toward = [0, 1, 2].map(|k| cp[k] - cn[k]);
            for tri in polys {
                let [x, y, z] = tri.map(|(a, b)| mid(a, b));
                let nrm = cross(
                    [0, 1, 2].map(|k| y[k] - x[k]),
                    [0, 1, 2].map(|k| z[k] - x[k]),
                );
                let mut e = tri.map(|(a, b)| s.edge(a, b));
                if dot(nrm, toward) < 0.0 {
                    e.swap(1, 2);
                }
                tris.push(e);
            }
        }
        s.cases.push(tris);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kuhn_split_fills_the_cube_and_uses_19_edges() {
        let vol: f64 = kuhn_tets()
            .iter()
            .map(|t| {
                let [a, b, c, d] = t.map(pos);
                let u = [0, 1, 2].map(|k| b[k] - a[k]);
                let v = [0, 1, 2].map(|k| c[k] - a[k]);
                let w = [0, 1, 2].map(|k| d[k] - a[k]);
                dot(cross(u, v), w).abs() / 6.0
            })
            .sum();
        assert!((vol - 1.0).abs() < 1e-12);
        let t = table();
        assert_eq!(t.dirs.len(), 7);
        assert_eq!(t.edges.len(), 19);
        // A lone negative corner 0 is in all six tetrahedra: six triangles.
        assert_eq!(t.cases[1].len(), 6);
        assert_eq!(t.cases[2].len(), 2);
    }
}
