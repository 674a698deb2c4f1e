//! Bowyer–Watson insertion (Bowyer, "Computing Dirichlet tessellations", 1981; Watson,
//! "Computing the n-dimensional Delaunay tessellation with application to Voronoi
//! polytopes", 1981): the cavity of cells whose (perturbed) circumsphere contains the
//! new point is grown breadth-first from a cell in conflict (visited cells marked by two
//! spare bits of their own record, no hash set or stamp array), its boundary facets are
//! recorded, the cavity cells are freed, and each boundary facet is joined to the new
//! point. New cells are glued to each other through a small open-addressing table
//! keyed by the boundary edge they share; cavity, boundary and table are scratch
//! arrays reused across insertions.
use super::predicates::{insphere_sos, orient3d};
use super::{Boundary, Cell, Delaunay, InsertError, Slot, DEAD, NONE};

/// Cavity-search marks in the top bits of a cell's `v[3]` (vertex ids are below 2³⁰,
/// [`super::MAX_VERTICES`]): set while one insertion runs, cleared before it returns —
/// cavity cells die, boundary-outer cells are unmarked when glued to the new cells.
const IN_CAVITY: u32 = 1 << 31;
const NOT_IN_CONFLICT: u32 = 1 << 30;
const FLAGS: u32 = IN_CAVITY | NOT_IN_CONFLICT;

impl Delaunay {
    /// Triangulate the 8 far corners: the perturbed Delaunay tetrahedra of 8 points are
    /// found by brute force (70 four-sets), which is exact and cheap.
    pub(crate) fn init_box(&mut self) {
        let mut tets: Vec<[u32; 4]> = Vec::new();
        for a in 0..8u32 {
            for b in a + 1..8 {
                for c in b + 1..8 {
                    for d in c + 1..8 {
                        let mut t = [a, b, c, d];
                        let p = t.map(|v| self.pts[v as usize]);
                        let o = orient3d(p[0], p[1], p[2], p[3]);
                        if o == 0.0 {
                            continue;
                        }
                        if o < 0.0 {
                            t.swap(0, 1);
                        }
                        let p = t.map(|v| self.pts[v as usize]);
                        let empty = (0..8u32).filter(|e| !t.contains(e)).all(|e| {
                            insphere_sos(p[0], p[1], p[2], p[3], self.pts[e as usize]) < 0
                        });
                        if empty {
                            tets.push(t);
                        }
                    }
                }
            }
        }
        for &t in &tets {
            self.push_cell(Cell { v: t, n: [NONE; 4] });
        }
        let m = tets.len();
        for x in 0..m {
            for i in 0..4 {
                let f: Vec<u32> = (0..4).filter(|&k| k != i).map(|k| tets[x][k]).collect();
                for y in 0..m {
                    if y == x {
                        continue;
                    }
                    if let Some(j) = (0..4).find(|&j| !f.contains(&tets[y][j])) {
                        if f.iter().all(|v| tets[y].contains(v)) {
                            self.cells[x].n[i] = (y * 4 + j) as u32;
                        }
                    }
                }
            }
        }
        for (x, t) in tets.iter().enumerate() {
            for &v in t {
                self.vcell[v as usize] = x as u32;
            }
        }
        self.last = 0;
    }

    #[inline]
    fn push_cell(&mut self, c: Cell) -> u32 {
        self.live += 1;
        if let Some(id) = self.free.pop() {
            self.cells[id as usize] = c;
            id
        } else {
            self.cells.push(c);
            (self.cells.len() - 1) as u32
        }
    }

    #[inline]
    pub(crate) fn in_conflict(&self, c: u32, p: [f64; 3]) -> bool {
        let v = self.cells[c as usize].v;
        let pts = &self.pts[..];
        let q = [
            pts[v[0] as usize],
            pts[v[1] as usize],
            pts[v[2] as usize],
            pts[v[3] as usize],
        ];
        insphere_sos(q[0], q[1], q[2], q[3], p) > 0
    }

    /// Locate and insert vertex `v` (already in `pts`).
    pub(crate) fn insert_vertex(&mut self, v: u32, start: u32) -> Result<(), InsertError> {
        let p = self.pts[v as usize];
        let c = self.locate(p, start)?;
        self.dig(v, c);
        Ok(())
    }

    /// Insert vertex `v` whose point is in conflict with cell `c` (and is no vertex).
    pub(crate) fn dig(&mut self, v: u32, c: u32) {
        let p = self.pts[v as usize];
        let mut cavity = std::mem::take(&mut self.cavity);
        let mut bnd = std::mem::take(&mut self.bnd);
        cavity.clear();
        bnd.clear();
        cavity.push(c);
        self.cells[c as usize].v[3] |= IN_CAVITY;
        let mut k = 0;
        while k < cavity.len() {
            let cc = cavity[k];
            k += 1;
            let mut cell = self.cells[cc as usize];
            cell.v[3] &= !FLAGS;
            for i in 0..4 {
                let n = cell.n[i];
                if n != NONE {
                    let d = (n >> 2) as usize;
                    let w3 = self.cells[d].v[3];
                    if w3 & IN_CAVITY != 0 {
                        continue;
                    }
                    if w3 & NOT_IN_CONFLICT == 0 {
                        if self.in_conflict(d as u32, p) {
                            self.cells[d].v[3] = w3 | IN_CAVITY;
                            cavity.push(d as u32);
                            continue;
                        }
                        self.cells[d].v[3] = w3 | NOT_IN_CONFLICT;
                    }
                }
                let mut nv = cell.v;
                nv[i] = v;
                bnd.push(Boundary {
                    v: nv,
                    i: i as u32,
                    outer: n,
                });
            }
        }
        // Free the cavity.
        for &cc in &cavity {
            let dead = &mut self.cells[cc as usize].v;
            dead[0] = DEAD;
            dead[3] &= !FLAGS;
            self.free.push(cc);
        }
        self.live -= cavity.len();
        // Gluing table: power of two ≥ 4 × (3 × boundary facets / 2) entries, so
        // linear probing stays short.
        let need = (bnd.len() * 6).next_power_of_two().max(128);
        if self.table.len() < need {
            self.table = vec![Slot::default(); need];
            self.gen = 0;
        }
        self.gen = self.gen.wrapping_add(1);
        if self.gen == 0 {
            self.table.iter_mut().for_each(|s| s.gen = 0);
            self.gen = 1;
        }
        let gen = self.gen;
        let mask = self.table.len() - 1;
        let shift = 64 - self.table.len().trailing_zeros();
        let mut last = NONE;
        for b in &bnd {
            let i = b.i as usize;
            let id = self.push_cell(Cell {
                v: b.v,
                n: [NONE; 4],
            });
            let idu = id as usize;
            self.cells[idu].n[i] = b.outer;
            if b.outer != NONE {
                let o = &mut self.cells[(b.outer >> 2) as usize];
                o.n[(b.outer & 3) as usize] = id * 4 + i as u32;
                o.v[3] &= !FLAGS; // the outer cell survives: clear its mark
            }
            for j in 0..4 {
                if j == i {
                    continue;
                }
                // Facet j holds v and the two boundary vertices other than b.v[j].
                let mut e = [0u32; 2];
                let mut m = 0;
                for (x, &w) in b.v.iter().enumerate() {
                    if x != i && x != j {
                        e[m] = w;
                        m += 1;
                    }
                }
                let (a, bb) = if e[0] < e[1] {
                    (e[0], e[1])
                } else {
                    (e[1], e[0])
                };
                // Multiplicative hashing: the top bits of the product.
                let mut h = ((((a as u64) << 32) | bb as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
                    >> shift) as usize;
                let code = id * 4 + j as u32;
                loop {
                    let s = &mut self.table[h];
                    if s.gen != gen {
                        *s = Slot {
                            gen,
                            a,
                            b: bb,
                            code,
                        };
                        break;
                    }
                    if s.a == a && s.b == bb {
                        let other = s.code;
                        s.a = NONE; // tombstone: probing continues past it
                        self.cells[idu].n[j] = other;
                        self.cells[(other >> 2) as usize].n[(other & 3) as usize] = code;
                        break;
                    }
                    h = (h + 1) & mask;
                }
            }
            for w in b.v {
                self.vcell[w as usize] = id;
            }
            last = id;
        }
        self.last = last;
        self.cavity = cavity;
        self.bnd = bnd;
    }
}
