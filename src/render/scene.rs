//! What is drawn: the faces of a triangle mesh or the boundary of a tetrahedral mesh
//! (after an optional cut, which exposes the tetrahedra the plane cuts, as in the
//! stuffing paper's Fig. 1), each with its quality and its certificate class.
use crate::error::{Error, Result};
use crate::kernel::geom::Aabb;
use crate::mesh::{TetMesh, TriMesh, TET_FACES};
use crate::mesher::{Certificate, Claim};
use crate::metrics::angles::{dihedral_angles, triangle_angles};
use std::collections::HashMap;

/// A half-space cut: keep the points with `n·p ≤ d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    pub n: [f64; 3],
    pub d: f64,
}

impl Plane {
    /// Parse `x=0.1`, `y<-0.2`, `z>0` (keep the side named; `=` keeps ≤) or `a,b,c,d`
    /// (keep a·x + b·y + c·z ≤ d).
    pub fn parse(s: &str) -> Result<Plane> {
        let t = s.replace(' ', "");
        let bad = || {
            Error::Param(format!(
                "--cut: '{s}' is not a plane (give x=0.1, y<0, z>0.2 or a,b,c,d for a·x + b·y + c·z <= d)"
            ))
        };
        if let Some(axis) = t.chars().next().filter(|c| "xyz".contains(*c)) {
            let k = "xyz".find(axis).unwrap_or(0);
            let rest = &t[1..];
            let (sign, v) = if let Some(v) = rest.strip_prefix(">=").or(rest.strip_prefix('>')) {
                (-1.0, v)
            } else if let Some(v) = rest
                .strip_prefix("<=")
                .or(rest.strip_prefix('<'))
                .or(rest.strip_prefix('='))
            {
                (1.0, v)
            } else {
                return Err(bad());
            };
            let d: f64 = v.parse().map_err(|_| bad())?;
            let mut n = [0.0; 3];
            n[k] = sign;
            return Ok(Plane { n, d: sign * d }).and_then(Plane::checked);
        }
        let v: Vec<f64> = t
            .split(',')
            .map(|x| x.parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| bad())?;
        match v.as_slice() {
            [a, b, c, d] => Plane {
                n: [*a, *b, *c],
                d: *d,
            }
            .checked(),
            _ => Err(bad()),
        }
    }
    fn checked(self) -> Result<Plane> {
        let l = (self.n.iter().map(|x| x * x).sum::<f64>()).sqrt();
        if !(l > 0.0) || !l.is_finite() || !self.d.is_finite() {
            return Err(Error::Param(
                "--cut: the plane's normal must be a finite, non-zero vector".into(),
            ));
        }
        Ok(self)
    }
    pub fn keeps(&self, p: [f64; 3]) -> bool {
        self.n[0] * p[0] + self.n[1] * p[1] + self.n[2] * p[2] <= self.d
    }
}

/// Which typed claim, if any, covers a face (see [`classify`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CertClass {
    /// Inside the box of an `Isotopic` claim of a certified output.
    Isotopic,
    /// Meets a region the mesher reported uncertified.
    Uncertified,
    /// Neither: the mesher made no claim about it (nothing is inferred).
    NoClaim,
}

impl CertClass {
    pub fn name(self) -> &'static str {
        match self {
            CertClass::Isotopic => "claimed: isotopic to f = 0 (its box)",
            CertClass::Uncertified => "meets a region reported uncertified",
            CertClass::NoClaim => "no claim covers it",
        }
    }
}

fn meets(b: &Aabb, lo: [f64; 3], hi: [f64; 3]) -> bool {
    (0..3).all(|k| lo[k] <= b.max[k] && hi[k] >= b.min[k])
}

/// The certificate class of a face with corners `p`, read off the mesher's typed
/// certificate only: a face meeting one of its uncertified regions is `Uncertified`;
/// else, a face of a *certified* output inside the box of one of its `Isotopic` claims
/// is `Isotopic`; else `NoClaim`.
pub fn classify(cert: &Certificate, p: &[[f64; 3]; 3]) -> CertClass {
    let lo = [0, 1, 2].map(|k| p.iter().map(|q| q[k]).fold(f64::INFINITY, f64::min));
    let hi = [0, 1, 2].map(|k| p.iter().map(|q| q[k]).fold(f64::NEG_INFINITY, f64::max));
    if let Certificate::Uncertified { regions, .. } = cert {
        if regions.iter().any(|r| meets(&r.region, lo, hi)) {
            return CertClass::Uncertified;
        }
    }
    let inside = |b: &Aabb| p.iter().all(|q| b.contains(*q));
    if cert.is_certified()
        && cert.claims_typed().iter().any(|c| match c {
            Claim::Isotopic { inside: b, .. } => inside(b),
            _ => false,
        })
    {
        return CertClass::Isotopic;
    }
    CertClass::NoClaim
}

/// A face to draw, in world coordinates.
#[derive(Clone, Copy, Debug)]
pub struct Face {
    pub p: [[f64; 3]; 3],
    /// Vertex indices (for Gouraud normals).
    pub v: [u32; 3],
    /// Smallest angle of the triangle, or smallest dihedral angle of its tetrahedron.
    pub quality: f64,
    /// A face the cut exposed (interior to the uncut tetrahedral mesh).
    pub cut: bool,
}

/// The faces of a triangle mesh (those kept by `cut`).
pub fn tri_faces(m: &TriMesh, cut: Option<Plane>) -> Vec<Face> {
    m.triangles
        .iter()
        .filter_map(|t| {
            let p = t.map(|i| m.vertices[i as usize]);
            let c = [0, 1, 2].map(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0);
            if cut.is_some_and(|pl| !pl.keeps(c)) {
                return None;
            }
            let a = triangle_angles(p[0], p[1], p[2]);
            Some(Face {
                p,
                v: *t,
                quality: a.iter().copied().fold(f64::INFINITY, f64::min),
                cut: false,
            })
        })
        .collect()
}

/// The boundary faces of the tetrahedra kept by `cut` (centroid on the kept side):
/// the mesh's own boundary plus, with a cut, the faces of the cut tetrahedra it exposes.
pub fn tet_faces(m: &TetMesh, cut: Option<Plane>) -> Vec<Face> {
    let mut all: HashMap<[u32; 3], u32> = HashMap::new();
    for t in &m.tets {
        for f in TET_FACES {
            let mut k = f.map(|i| t[i]);
            k.sort_unstable();
            *all.entry(k).or_default() += 1;
        }
    }
    let mut kept: HashMap<[u32; 3], (usize, [u32; 3], u32)> = HashMap::new();
    for (ti, t) in m.tets.iter().enumerate() {
        let p = t.map(|i| m.vertices[i as usize]);
        let c = [0, 1, 2].map(|k| (p[0][k] + p[1][k] + p[2][k] + p[3][k]) / 4.0);
        if cut.is_some_and(|pl| !pl.keeps(c)) {
            continue;
        }
        for f in TET_FACES {
            let v = f.map(|i| t[i]);
            let mut k = v;
            k.sort_unstable();
            kept.entry(k).and_modify(|e| e.2 += 1).or_insert((ti, v, 1));
        }
    }
    let mut out: Vec<Face> = kept
        .into_iter()
        .filter(|(_, (_, _, n))| *n == 1)
        .map(|(k, (ti, v, _))| {
            let tp = m.tets[ti].map(|i| m.vertices[i as usize]);
            let q = dihedral_angles(&tp)
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            Face {
                p: v.map(|i| m.vertices[i as usize]),
                v,
                quality: q,
                cut: all.get(&k).copied().unwrap_or(1) > 1,
            }
        })
        .collect();
    out.sort_by_key(|f| f.v);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn planes_parse_and_reject() {
        assert_eq!(
            Plane::parse("x=0.5").unwrap(),
            Plane {
                n: [1.0, 0.0, 0.0],
                d: 0.5
            }
        );
        assert_eq!(
            Plane::parse("y > 0").unwrap(),
            Plane {
                n: [0.0, -1.0, 0.0],
                d: -0.0
            }
        );
        assert!(Plane::parse("0,0,1,0.2").unwrap().keeps([0.0, 0.0, 0.1]));
        assert!(Plane::parse("w=1").is_err());
        assert!(Plane::parse("0,0,0,1").is_err());
        assert!(Plane::parse("x=abc").is_err());
    }
}
