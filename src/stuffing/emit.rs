//! Step 4 of §3 (§3.3): fill every BCC tetrahedron with a positive vertex from the
//! stencil table, and apply the quadruple-zero policy.
use super::field::{Field, NONE, OUT};
use super::stencils::{pattern_index, EDGES, TABLE};
use crate::lattice::bcc::{dir_of, TET_TEMPLATES};
use crate::mesh::TetMesh;
use rayon::prelude::*;

/// Which side of the surface is meshed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Side {
    /// The solid `{f <= 0}` (the paper's `{f >= 0}` after the sign flip).
    #[default]
    Inside,
    /// The exterior `{f >= 0}`: the stencils with + and − swapped (§3.3).
    Outside,
}

/// Result of stencil emission.
#[derive(Clone, Debug, Default)]
pub struct Emitted {
    pub mesh: TetMesh,
    /// Quadruple-zero BCC tetrahedra (vertex ids into `mesh.vertices`), positively
    /// oriented combinatorially (they may be geometrically inverted).
    pub quadruple_zero: Vec<[u32; 4]>,
    /// A tetrahedron with a positive vertex had a vertex outside P (window border).
    pub clipped: bool,
}

/// Direction index from local vertex `u` to `v` of each template, for the 6 edges.
fn edge_dirs() -> [[(usize, usize); 6]; 12] {
    let mut out = [[(0, 0); 6]; 12];
    for (ti, t) in TET_TEMPLATES.iter().enumerate() {
        for (k, [u, v]) in EDGES.iter().enumerate() {
            let (a, b) = (t.offsets[*u as usize], t.offsets[*v as usize]);
            let d = dir_of([b[0] - a[0], b[1] - a[1], b[2] - a[2]]).expect("BCC edge");
            out[ti][k] = (d, d ^ 1);
        }
    }
    out
}

/// Assign output vertices (lattice points with sign 0 or ±1 on `side`, and surviving
/// cut points) and emit the stencils. `side`: which sign is "positive".
pub fn emit(fl: &mut Field, side: Side, parallel: bool) -> Emitted {
    let pos_sign: i8 = if side == Side::Inside { 1 } else { -1 };
    let np = fl.lat.n_points();
    let mut vid = vec![NONE; np];
    let mut vertices = Vec::new();
    for id in 0..np {
        let s = fl.sign[id];
        if s == 0 || s == pos_sign {
            vid[id] = vertices.len() as u32;
            vertices.push(fl.point_position(id as u32));
        }
    }
    for r in 0..fl.cuts.len() {
        let p = fl.cuts[r].p;
        for d in 0..14 {
            let t = fl.cuts[r].t[d];
            if !t.is_nan() {
                let q = fl.lat.neighbor(p, d).expect("cut edge in window");
                fl.cuts[r].vid[d] = vertices.len() as u32;
                vertices.push(fl.cut_position(p, q, t));
            }
        }
    }
    let dirs = edge_dirs();
    let table = &*TABLE;
    let lat = &fl.lat;
    let f: &Field = fl;
    let n = lat.n;
    let n_even = lat.n_even();
    // Index offsets of each template's vertices from its base point's even index (even
    // vertices) or from the odd point (2i+1, 2j+1, 2k+1)'s index (odd vertices).
    let deltas: [[i64; 4]; 12] = std::array::from_fn(|ti| {
        std::array::from_fn(|v| {
            let o = TET_TEMPLATES[ti].offsets[v];
            if o[0] & 1 == 0 {
                let d = [o[0] / 2, o[1] / 2, o[2] / 2];
                (d[2] * (n[1] as i64 + 1) + d[1]) * (n[0] as i64 + 1) + d[0]
            } else {
                let d = [
                    (o[0] - 1).div_euclid(2),
                    (o[1] - 1).div_euclid(2),
                    (o[2] - 1).div_euclid(2),
                ];
                (d[2] * n[1] as i64 + d[1]) * n[0] as i64 + d[0]
            }
        })
    });
    let slab = |k: usize| -> (Vec<[u32; 4]>, Vec<[u32; 4]>, bool) {
        let mut tets = Vec::new();
        let mut qz = Vec::new();
        let mut clipped = false;
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                let base = [2 * i as i64, 2 * j as i64, 2 * k as i64];
                // The base point is a vertex of all 12 tetrahedra: if it is not in P,
                // none of them has a positive vertex (P holds every neighbour of one)
                // and none is quadruple-zero.
                let b = lat.id(base).expect("base in window");
                if f.sign[b as usize] == OUT {
                    continue;
                }
                let interior = i >= 1 && j >= 1 && k >= 1 && i < n[0] && j < n[1] && k < n[2];
                let odd_base = (n_even + (k * n[1] + j) * n[0] + i) as i64;
                for (ti, t) in TET_TEMPLATES.iter().enumerate() {
                    let mut ids = [0u32; 4];
                    let mut ok = true;
                    if interior {
                        // Fast path: constant index offsets away from the window border.
                        for v in 0..4 {
                            ids[v] = (deltas[ti][v]
                                + if t.offsets[v][0] & 1 == 0 {
                                    b as i64
                                } else {
                                    odd_base
                                }) as u32;
                        }
                    }
                    for v in 0..4 {
                        if interior {
                            break;
                        }
                        let o = t.offsets[v];
                        match lat.id([base[0] + o[0], base[1] + o[1], base[2] + o[2]]) {
                            Some(id) => ids[v] = id,
                            None => {
                                ok = false;
                                break;
                            }
                        }
                    }
                    if !ok {
                        continue;
                    }
                    let raw = ids.map(|id| f.sign[id as usize]);
                    if raw == [pos_sign; 4] {
                        // Wholly inside: the ++++ stencil is the tetrahedron itself.
                        let mut g = ids.map(|id| vid[id as usize]);
                        // (e0, e1, o0, o1) is positively oriented iff the template is.
                        if t.orientation < 0 {
                            g.swap(0, 1);
                        }
                        tets.push(g);
                        continue;
                    }
                    if !raw.contains(&pos_sign) && raw != [0, 0, 0, 0] {
                        continue;
                    }
                    if raw.contains(&OUT) || raw.contains(&-3) {
                        clipped = true;
                        continue;
                    }
                    let s = raw.map(|x| x * pos_sign);
                    let st = &table.stencils[pattern_index(s)];
                    let flip = t.orientation != table.reference_orientation;
                    for lt in st.tets() {
                        let mut g = [0u32; 4];
                        for (slot, &l) in lt.iter().enumerate() {
                            g[slot] = if l < 4 {
                                vid[ids[l as usize] as usize]
                            } else {
                                let e = (l - 4) as usize;
                                let [u, v] = EDGES[e];
                                let (du, dv) = dirs[ti][e];
                                let (a, b) = (ids[u as usize], ids[v as usize]);
                                // The cut record lives at the inside-positive end.
                                let (p, d) = if f.sign[a as usize] == 1 {
                                    (a, du)
                                } else {
                                    (b, dv)
                                };
                                f.cuts[f.surf[p as usize] as usize].vid[d]
                            };
                        }
                        if flip {
                            g.swap(0, 1);
                        }
                        if st.quadruple_zero {
                            qz.push(g);
                        } else {
                            tets.push(g);
                        }
                    }
                }
            }
        }
        (tets, qz, clipped)
    };
    let parts: Vec<(Vec<[u32; 4]>, Vec<[u32; 4]>, bool)> = if parallel {
        (0..=n[2]).into_par_iter().map(slab).collect()
    } else {
        (0..=n[2]).map(slab).collect()
    };
    let mut out = Emitted::default();
    let total: usize = parts.iter().map(|p| p.0.len()).sum();
    let mut tets = Vec::with_capacity(total);
    for (t, q, c) in parts {
        tets.extend_from_slice(&t);
        out.quadruple_zero.extend_from_slice(&q);
        out.clipped |= c;
    }
    out.mesh = TetMesh { vertices, tets };
    out
}

/// Drop vertices no tetrahedron uses, renumbering (also renumbers `extra`).
pub fn compact(mesh: &mut TetMesh, extra: &mut [[u32; 4]]) {
    let mut map = vec![NONE; mesh.vertices.len()];
    let mut verts = Vec::with_capacity(mesh.vertices.len());
    for t in mesh.tets.iter_mut().chain(extra.iter_mut()) {
        for i in t.iter_mut() {
            let m = &mut map[*i as usize];
            if *m == NONE {
                *m = verts.len() as u32;
                verts.push(mesh.vertices[*i as usize]);
            }
            *i = *m;
        }
    }
    mesh.vertices = verts;
}
