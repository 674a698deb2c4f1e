//! Mesh types: flat arrays of vertices and index tuples (cache-friendly, cheap to
//! share with rayon). Orientation convention: triangles are counter-clockwise seen
//! from outside, i.e. their normals point towards f > 0; tetrahedra have positive
//! signed volume.
use serde::{Deserialize, Serialize};

pub mod buckets;
pub use buckets::Buckets;

/// A triangle surface mesh.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TriMesh {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

/// The faces of a tetrahedron: face `k` is opposite corner `k`, ordered so that it
/// points outward for a positively oriented tetrahedron.
pub const TET_FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

/// A face in [`TetMesh::face_buckets`]: its two larger vertices, and the face as its
/// tetrahedron orients it.
pub type FaceItem = ((u32, u32), [u32; 3]);

/// A tetrahedral volume mesh.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TetMesh {
    pub vertices: Vec<[f64; 3]>,
    pub tets: Vec<[u32; 4]>,
}

/// A set of planar polylines, stored as segments between vertices.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Curve2 {
    pub vertices: Vec<[f64; 2]>,
    pub segments: Vec<[u32; 2]>,
}

impl TriMesh {
    pub fn new(vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Self {
        TriMesh {
            vertices,
            triangles,
        }
    }
    /// The corners of triangle `t`.
    #[inline(always)]
    pub fn corners(&self, t: usize) -> [[f64; 3]; 3] {
        self.corners_of(self.triangles[t])
    }
    /// The corners of the triangle with vertex indices `t`.
    #[inline(always)]
    pub fn corners_of(&self, [a, b, c]: [u32; 3]) -> [[f64; 3]; 3] {
        // (Per corner: `[u32; 3].map` can be left out of line, a call per triangle.)
        let v = &self.vertices;
        [v[a as usize], v[b as usize], v[c as usize]]
    }
    /// Whether the triangle with vertex indices `t` names a vertex twice (a degenerate
    /// face: the metrics leave it out of the angles and the topology).
    #[inline(always)]
    pub fn repeats_vertex(t: [u32; 3]) -> bool {
        t[0] == t[1] || t[1] == t[2] || t[2] == t[0]
    }
    /// Drop vertices no triangle uses, renumbering the rest.
    pub fn compact(&mut self) {
        let mut map = vec![u32::MAX; self.vertices.len()];
        let mut verts = Vec::new();
        for t in &mut self.triangles {
            for i in t.iter_mut() {
                if map[*i as usize] == u32::MAX {
                    map[*i as usize] = verts.len() as u32;
                    verts.push(self.vertices[*i as usize]);
                }
                *i = map[*i as usize];
            }
        }
        self.vertices = verts;
    }
    /// Flip every triangle's orientation.
    pub fn flip(&mut self) {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
    }
}

/// The icosahedron subdivided `level` times, its vertices on the unit sphere, faces
/// oriented outward (level 1: 42 vertices, 80 triangles). Used by the patched
/// Stander–Hart sweep for a newborn sphere, and by the tests as a reference mesh.
pub fn icosphere(level: u32) -> TriMesh {
    let p = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<[f64; 3]> = [
        [-1.0, p, 0.0],
        [1.0, p, 0.0],
        [-1.0, -p, 0.0],
        [1.0, -p, 0.0],
        [0.0, -1.0, p],
        [0.0, 1.0, p],
        [0.0, -1.0, -p],
        [0.0, 1.0, -p],
        [p, 0.0, -1.0],
        [p, 0.0, 1.0],
        [-p, 0.0, -1.0],
        [-p, 0.0, 1.0],
    ]
    .into_iter()
    .map(crate::kernel::geom::normalize)
    .collect();
    let mut t: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid = std::collections::HashMap::new();
        let mut m = |a: u32, b: u32, v: &mut Vec<[f64; 3]>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(crate::kernel::geom::normalize(crate::kernel::geom::lerp(
                    v[a as usize],
                    v[b as usize],
                    0.5,
                )));
                v.len() as u32 - 1
            })
        };
        let mut nt = Vec::new();
        for [a, b, c] in t {
            let ab = m(a, b, &mut v);
            let bc = m(b, c, &mut v);
            let ca = m(c, a, &mut v);
            nt.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        t = nt;
    }
    TriMesh::new(v, t)
}

impl TetMesh {
    #[inline(always)]
    pub fn corners(&self, t: usize) -> [[f64; 3]; 4] {
        let [a, b, c, d] = self.tets[t];
        let v = &self.vertices;
        [v[a as usize], v[b as usize], v[c as usize], v[d as usize]]
    }
    /// Every face of every tetrahedron (of the non-degenerate ones, without a repeated
    /// vertex, when `skip_degenerate`), grouped by vertex set in linear time: bucket
    /// `lo` holds `((mid, hi), face)` for each face with sorted vertices `lo <= mid <=
    /// hi`, `face` as its tetrahedron orients it ([`TET_FACES`]), sorted; one run per
    /// vertex set ([`Buckets::runs`] by `.0`).
    pub fn face_buckets(&self, skip_degenerate: bool) -> Buckets<FaceItem> {
        let mut b = Buckets::build(self.vertices.len(), |emit| {
            for t in &self.tets {
                if skip_degenerate && (0..4).any(|i| (i + 1..4).any(|j| t[i] == t[j])) {
                    continue;
                }
                for f in TET_FACES {
                    let tri = f.map(|k| t[k]);
                    let mut key = tri;
                    key.sort_unstable();
                    emit(key[0], ((key[1], key[2]), tri));
                }
            }
        });
        b.sort_each_by_key(|&x| x);
        b
    }
    /// The boundary faces: faces in exactly one tetrahedron, oriented outward, in this
    /// mesh's vertex numbering, sorted.
    pub fn boundary_faces(&self) -> Vec<[u32; 3]> {
        Self::boundary_faces_of(&self.face_buckets(false))
    }
    /// [`TetMesh::boundary_faces`] from this mesh's [`TetMesh::face_buckets`].
    pub fn boundary_faces_of(faces: &Buckets<FaceItem>) -> Vec<[u32; 3]> {
        use rayon::prelude::*;
        let mut tris: Vec<[u32; 3]> = (0..faces.len())
            .into_par_iter()
            .flat_map_iter(|v| {
                faces
                    .runs(v, |x| x.0)
                    .filter(|r| r.len() == 1)
                    .map(|r| r[0].1)
            })
            .collect();
        tris.par_sort_unstable();
        tris
    }
    /// The boundary surface: [`TetMesh::boundary_faces`], with the vertices no face
    /// uses dropped (the rest renumbered in order of first use).
    pub fn boundary(&self) -> TriMesh {
        self.boundary_with(&self.face_buckets(false))
    }
    /// [`TetMesh::boundary`] from this mesh's [`TetMesh::face_buckets`] (`false`).
    pub fn boundary_with(&self, faces: &Buckets<FaceItem>) -> TriMesh {
        let mut m = TriMesh {
            vertices: self.vertices.clone(),
            triangles: Self::boundary_faces_of(faces),
        };
        m.compact();
        m
    }
}

impl Curve2 {
    /// The vertices of no segment, ascending: isolated points of the curve (the exact
    /// sweep keeps an isolated real point of f = 0 as one).
    pub fn isolated_vertices(&self) -> Vec<u32> {
        let mut used = vec![false; self.vertices.len()];
        for s in &self.segments {
            for &v in s {
                used[v as usize] = true;
            }
        }
        (0..self.vertices.len() as u32)
            .filter(|&v| !used[v as usize])
            .collect()
    }
    /// The polylines: maximal chains of segments, each with a flag saying whether it closes.
    pub fn polylines(&self) -> Vec<(Vec<u32>, bool)> {
        let n = self.vertices.len();
        let mut adj: Vec<Vec<(u32, usize)>> = vec![Vec::new(); n];
        for (s, &[a, b]) in self.segments.iter().enumerate() {
            adj[a as usize].push((b, s));
            adj[b as usize].push((a, s));
        }
        let mut used = vec![false; self.segments.len()];
        let mut out = Vec::new();
        // Open chains first (start at vertices of degree != 2), then cycles.
        let starts: Vec<usize> = (0..n).filter(|&v| adj[v].len() != 2).chain(0..n).collect();
        for v0 in starts {
            while let Some(&(_, s0)) = adj[v0].iter().find(|(_, s)| !used[*s]) {
                let mut chain = vec![v0 as u32];
                let mut v = v0;
                let mut s = s0;
                loop {
                    used[s] = true;
                    let [a, b] = self.segments[s];
                    let w = if a as usize == v { b } else { a } as usize;
                    chain.push(w as u32);
                    v = w;
                    match adj[v].iter().find(|(_, s)| !used[*s]) {
                        Some(&(_, s2)) if adj[v].len() == 2 => s = s2,
                        _ => break,
                    }
                }
                let closed = chain.len() > 2 && chain.first() == chain.last();
                out.push((chain, closed));
            }
        }
        out
    }
}
