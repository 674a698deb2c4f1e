//! The angle functions of the stuffing proof as rigorous interval functions of the
//! case parameters, with first-order duals (value + gradient in up to four parameters)
//! for mean-value enclosures (see [`crate::ival`] for why).
//!
//! Angles are handled through their cosines (no `acos` in the proof path, §4.1 of the
//! GradNormal proof's convention): for a plane angle at `a` in triangle `abc`,
//! `cos = (b−a)·(c−a) / √(|b−a|²|c−a|²)`; for the dihedral angle at edge `ab` of
//! tetrahedron `abcd`, with `u = b − a`, the normals `n_c = u × (c−a)`, `n_d = u × (d−a)`
//! are the components of `c − a`, `d − a` orthogonal to `u` rotated by 90° about `u`, so
//! `cos = n_c·n_d / √(|n_c|²|n_d|²)`.
use super::cases::{Alphas, Case, Kind, Seg, DEN};
use crate::ival::{iv, pt};
use inari::Interval;

/// Number of independent variables of a dual.
pub const NV: usize = 4;

/// The stuffing proof's duals (the shared [`crate::ival::Dual`]).
pub type Dn = crate::ival::Dual<NV>;

pub type V3 = [Dn; 3];

#[inline]
fn vsub(a: &V3, b: &V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
fn dot(a: &V3, b: &V3) -> Dn {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
fn cross(a: &V3, b: &V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// cos of the angle at `a` in triangle `abc`.
#[inline]
pub fn cos_plane(a: &V3, b: &V3, c: &V3) -> Dn {
    let (u, v) = (vsub(b, a), vsub(c, a));
    dot(&u, &v).div((dot(&u, &u) * dot(&v, &v)).sqrt())
}

/// cos of the dihedral angle at edge `ab` of tetrahedron `abcd`.
#[inline]
pub fn cos_dihedral(a: &V3, b: &V3, c: &V3, d: &V3) -> Dn {
    let u = vsub(b, a);
    let nc = cross(&u, &vsub(c, a));
    let nd = cross(&u, &vsub(d, a));
    dot(&nc, &nd).div((dot(&nc, &nc) * dot(&nd, &nd)).sqrt())
}

/// How a vertex of a problem varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// Not a parameter (fixed kind).
    Fixed,
    /// At the lower (false) or upper (true) end of its range (the §4.1 reduction).
    End(bool),
    /// Free: variable number k ∈ [0, 1].
    Var(usize),
}

/// A vertex's geometry in intervals: position = p + (t0 + x·(t1 − t0))·d.
#[derive(Clone, Copy, Debug)]
pub struct Geo {
    p: [Interval; 3],
    d: [Interval; 3],
    t0: Interval,
    t1: Interval,
    pub param: bool,
}

impl Geo {
    pub fn new(s: &Seg, a: &Alphas) -> Geo {
        let r = a.range(s);
        let den = pt(DEN as f64);
        Geo {
            p: s.p.map(|x| pt(x as f64)),
            d: s.d.map(|x| pt(x as f64)),
            t0: pt(r[0] as f64) / den,
            t1: pt(r[1] as f64) / den,
            param: s.kind != Kind::Fixed,
        }
    }
    /// The position as duals for a role, with variables ranging over the box.
    #[inline]
    pub fn at(&self, role: Role, x: &[Interval]) -> V3 {
        let t = match role {
            Role::Fixed => return self.p.map(Dn::cst),
            Role::End(false) => Dn::cst(self.t0),
            Role::End(true) => Dn::cst(self.t1),
            Role::Var(k) => Dn::cst(self.t0) + Dn::var(x[k], k).scale(self.t1 - self.t0),
        };
        [0, 1, 2].map(|i| Dn::cst(self.p[i]) + t.scale(self.d[i]))
    }
    /// Plain f64 position (display and figures only).
    pub fn at_f64(&self, role: Role, x: &[f64]) -> [f64; 3] {
        let t = match role {
            Role::Fixed => 0.0,
            Role::End(false) => self.t0.mid(),
            Role::End(true) => self.t1.mid(),
            Role::Var(k) => self.t0.mid() + x[k] * (self.t1.mid() - self.t0.mid()),
        };
        [0, 1, 2].map(|i| self.p[i].mid() + t * self.d[i].mid())
    }
}

/// What a problem computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum What {
    /// Dihedral at edge (v[0], v[1]) of the tetrahedron (v[0], v[1], v[2], v[3]).
    Dihedral,
    /// The three plane angles of triangle (v[0], v[1], v[2]).
    Face { exposed: bool },
}

/// One branch-and-bound problem: a function of `dim` variables on [0,1]^dim.
#[derive(Clone, Debug)]
pub struct Problem {
    pub case: usize,
    pub what: What,
    /// Vertex indices into the case (4 for a dihedral, 3 for a face).
    pub verts: Vec<usize>,
    pub roles: Vec<Role>,
    pub dim: usize,
    pub geo: Vec<Geo>,
}

impl Problem {
    pub fn n_out(&self) -> usize {
        match self.what {
            What::Dihedral => 1,
            What::Face { .. } => 3,
        }
    }
    fn eval(&self, x: &[Interval]) -> Vec<Dn> {
        let p: Vec<V3> = (0..self.verts.len())
            .map(|k| self.geo[k].at(self.roles[k], x))
            .collect();
        match self.what {
            What::Dihedral => vec![cos_dihedral(&p[0], &p[1], &p[2], &p[3])],
            What::Face { .. } => vec![
                cos_plane(&p[0], &p[1], &p[2]),
                cos_plane(&p[1], &p[2], &p[0]),
                cos_plane(&p[2], &p[0], &p[1]),
            ],
        }
    }
    /// Mean-value enclosures of the cosines over the box `lo..hi` (each in [0,1]).
    pub fn enclose(&self, lo: &[f64], hi: &[f64]) -> Vec<Interval> {
        let x: Vec<Interval> = (0..self.dim).map(|k| iv(lo[k], hi[k])).collect();
        let c: Vec<f64> = (0..self.dim).map(|k| 0.5 * (lo[k] + hi[k])).collect();
        let xc: Vec<Interval> = c.iter().map(|&v| pt(v)).collect();
        let over = self.eval(&x);
        let at = self.eval(&xc);
        over.iter()
            .zip(&at)
            .map(|(o, a)| {
                let mut mv = a.v;
                for k in 0..self.dim {
                    mv = mv + o.g[k] * (x[k] - pt(c[k]));
                }
                let r = mv.intersection(o.v);
                let r = if r.is_empty() { mv.convex_hull(o.v) } else { r };
                let r = r.intersection(iv(-1.0, 1.0));
                if r.is_empty() {
                    iv(-1.0, 1.0)
                } else {
                    r
                }
            })
            .collect()
    }
    /// Tight enclosures of the cosines at a point (None when undefined there).
    pub fn point(&self, x: &[f64]) -> Option<Vec<Interval>> {
        let xi: Vec<Interval> = x.iter().map(|&v| pt(v)).collect();
        let v: Vec<Interval> = self.eval(&xi).iter().map(|d| d.v).collect();
        if v.iter()
            .any(|y| y.is_empty() || !y.inf().is_finite() || !y.sup().is_finite())
        {
            return None;
        }
        Some(v)
    }
    /// Vertex positions (in black-edge units h) of the case at a point, for witnesses.
    pub fn config(&self, case: &Case, a: &Alphas, x: &[f64]) -> [[f64; 3]; 4] {
        let mut out = [[0.0; 3]; 4];
        for (k, s) in case.v.iter().enumerate() {
            let g = Geo::new(s, a);
            let role = match self.verts.iter().position(|&v| v == k) {
                Some(j) => self.roles[j],
                None => Role::End(false),
            };
            let role = if s.kind == Kind::Fixed {
                Role::Fixed
            } else {
                role
            };
            out[k] = g.at_f64(role, x).map(|c| 0.5 * c);
        }
        out
    }
}

/// The problems of one case: the dihedral angles (with the §4.1 reduction when the
/// case's tetrahedron cannot be flat, `reduce`) and the faces' plane angles.
pub fn problems(ci: usize, case: &Case, a: &Alphas, dihedrals: bool, reduce: bool) -> Vec<Problem> {
    let geo: Vec<Geo> = case.v.iter().map(|s| Geo::new(s, a)).collect();
    let mut out = Vec::new();
    if dihedrals {
        for (i, j, k, l) in certmesh::kernel::geom::TET_EDGES_WITH_OPPOSITE {
            let verts = vec![i, j, k, l];
            let g: Vec<Geo> = verts.iter().map(|&v| geo[v]).collect();
            // Free variables: a and b always; c and d too without the reduction.
            let mut dim = 0;
            let mut base = Vec::new();
            for (pos, &v) in verts.iter().enumerate() {
                base.push(if !geo[v].param {
                    Role::Fixed
                } else if pos < 2 || !reduce {
                    dim += 1;
                    Role::Var(dim - 1)
                } else {
                    Role::End(false)
                });
            }
            // Endpoint combinations of c and d.
            let ends: Vec<usize> = (2..4).filter(|&p| base[p] == Role::End(false)).collect();
            for m in 0..(1usize << ends.len()) {
                let mut roles = base.clone();
                for (b, &p) in ends.iter().enumerate() {
                    roles[p] = Role::End(m >> b & 1 == 1);
                }
                out.push(Problem {
                    case: ci,
                    what: What::Dihedral,
                    verts: verts.clone(),
                    roles,
                    dim,
                    geo: g.clone(),
                });
            }
        }
    }
    for f in [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]] {
        let mut dim = 0;
        let roles: Vec<Role> = f
            .iter()
            .map(|&v| {
                if geo[v].param {
                    dim += 1;
                    Role::Var(dim - 1)
                } else {
                    Role::Fixed
                }
            })
            .collect();
        out.push(Problem {
            case: ci,
            what: What::Face {
                exposed: case.exposed(f),
            },
            verts: f.to_vec(),
            roles,
            dim,
            geo: f.iter().map(|&v| geo[v]).collect(),
        });
    }
    out
}
