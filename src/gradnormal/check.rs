//! Small mesh checks used by the GradNormal report and reproduction: angles and the
//! topology of a closed triangle mesh. (The shared `metrics` module supersedes these
//! when merged; they are kept minimal on purpose.)
use crate::kernel::geom::angle_deg;
use crate::mesh::TriMesh;
use rayon::prelude::*;
use std::collections::HashMap;

/// The three angles (degrees) of every triangle.
pub fn angles(m: &TriMesh) -> Vec<f64> {
    m.triangles
        .par_iter()
        .flat_map_iter(|t| {
            let [a, b, c] = t.map(|i| m.vertices[i as usize]);
            [angle_deg(c, a, b), angle_deg(a, b, c), angle_deg(b, c, a)]
        })
        .collect()
}

/// Smallest and largest angle (degrees); (NaN, NaN) for an empty mesh.
pub fn angle_range(m: &TriMesh) -> (f64, f64) {
    if m.triangles.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    m.triangles
        .par_iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.vertices[i as usize]);
            let x = [angle_deg(c, a, b), angle_deg(a, b, c), angle_deg(b, c, a)];
            (x[0].min(x[1]).min(x[2]), x[0].max(x[1]).max(x[2]))
        })
        .reduce(
            || (f64::INFINITY, f64::NEG_INFINITY),
            |p, q| (p.0.min(q.0), p.1.max(q.1)),
        )
}

/// Topology of a triangle mesh.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Topo {
    pub vertices: usize,
    pub edges: usize,
    pub faces: usize,
    /// Edges not shared by exactly two triangles.
    pub boundary_or_nonmanifold_edges: usize,
    /// Edges whose two triangles traverse them in the same direction.
    pub misoriented_edges: usize,
    /// Vertices whose triangles do not form a single fan (disk).
    pub nonmanifold_vertices: usize,
    pub components: usize,
    pub euler: i64,
    /// Genus per component (closed, orientable components only), sorted.
    pub genus: Vec<usize>,
}

impl Topo {
    /// A closed oriented 2-manifold.
    pub fn is_closed_manifold(&self) -> bool {
        self.boundary_or_nonmanifold_edges == 0
            && self.misoriented_edges == 0
            && self.nonmanifold_vertices == 0
    }
}

fn find(p: &mut [u32], mut x: u32) -> u32 {
    while p[x as usize] != x {
        p[x as usize] = p[p[x as usize] as usize];
        x = p[x as usize];
    }
    x
}

/// Count edges, components, Euler characteristic and genus of `m` (unused vertices
/// are ignored).
pub fn topology(m: &TriMesh) -> Topo {
    let nv = m.vertices.len();
    let mut edges: HashMap<(u32, u32), (u32, i32)> = HashMap::with_capacity(m.triangles.len() * 2);
    for t in &m.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            let e = edges.entry(key).or_insert((0, 0));
            e.0 += 1;
            e.1 += if a < b { 1 } else { -1 };
        }
    }
    let bad = edges.values().filter(|e| e.0 != 2).count();
    let mis = edges.values().filter(|e| e.0 == 2 && e.1 != 0).count();
    let mut used = vec![false; nv];
    let mut parent: Vec<u32> = (0..nv as u32).collect();
    for t in &m.triangles {
        for &v in t {
            used[v as usize] = true;
        }
        let a = find(&mut parent, t[0]);
        for &v in &t[1..] {
            let b = find(&mut parent, v);
            parent[b as usize] = a;
        }
    }
    // Vertex fans: the link edges (opposite edges) of each vertex must form one cycle.
    let mut link: Vec<Vec<(u32, u32)>> = vec![Vec::new(); nv];
    for t in &m.triangles {
        for k in 0..3 {
            link[t[k] as usize].push((t[(k + 1) % 3], t[(k + 2) % 3]));
        }
    }
    let mut nonmanifold_vertices = 0;
    for l in link.iter().filter(|l| !l.is_empty()) {
        let next: HashMap<u32, u32> = l.iter().copied().collect();
        let mut x = l[0].0;
        let mut steps = 0;
        while let Some(&y) = next.get(&x) {
            x = y;
            steps += 1;
            if x == l[0].0 || steps > l.len() {
                break;
            }
        }
        if next.len() != l.len() || steps != l.len() || x != l[0].0 {
            nonmanifold_vertices += 1;
        }
    }
    // Per component V − E + F.
    let mut comp: HashMap<u32, (i64, i64, i64)> = HashMap::new();
    for (v, &u) in used.iter().enumerate() {
        if u {
            comp.entry(find(&mut parent, v as u32)).or_default().0 += 1;
        }
    }
    for &(a, _) in edges.keys() {
        comp.entry(find(&mut parent, a)).or_default().1 += 1;
    }
    for t in &m.triangles {
        comp.entry(find(&mut parent, t[0])).or_default().2 += 1;
    }
    let mut genus: Vec<usize> = comp
        .values()
        .map(|&(v, e, f)| ((2 - (v - e + f)) / 2).max(0) as usize)
        .collect();
    genus.sort_unstable();
    let nused = used.iter().filter(|&&u| u).count();
    Topo {
        vertices: nused,
        edges: edges.len(),
        faces: m.triangles.len(),
        boundary_or_nonmanifold_edges: bad,
        misoriented_edges: mis,
        nonmanifold_vertices,
        components: comp.len(),
        euler: nused as i64 - edges.len() as i64 + m.triangles.len() as i64,
        genus,
    }
}
