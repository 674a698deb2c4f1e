//! Named test surfaces and curves with their known topology, so a run can be judged
//! right or wrong (the topology verdict of the comparison harness).
use crate::error::{Error, Result};
use crate::implicit::Formula;
use crate::kernel::geom::Aabb;
use serde::Serialize;

/// The expected topology of a catalog entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Topology {
    /// Number of connected components of f = 0 inside the domain.
    pub components: usize,
    /// Genus of each component (surfaces); 0 for curves (each component is a circle).
    pub genus: &'static [usize],
}

/// One catalog entry.
#[derive(Clone, Debug, Serialize)]
pub struct Entry {
    pub name: &'static str,
    /// 2 (curve) or 3 (surface).
    pub dim: usize,
    pub formula: &'static str,
    pub domain: Aabb,
    /// `None` for singular entries, whose zero set is not a manifold.
    pub topology: Option<Topology>,
    pub smooth: bool,
    pub note: &'static str,
}

impl Entry {
    pub fn function(&self) -> Formula {
        Formula::with_dim(self.formula, self.dim).expect("catalog formulas parse")
    }
    /// Euler characteristic expected of a closed surface mesh (sum of 2 - 2g).
    pub fn euler_characteristic(&self) -> Option<i64> {
        let t = self.topology?;
        if self.dim == 2 {
            return Some(0);
        }
        Some(t.genus.iter().map(|&g| 2 - 2 * g as i64).sum())
    }
}

const fn b3(h: f64) -> Aabb {
    Aabb {
        min: [-h, -h, -h],
        max: [h, h, h],
    }
}
const fn b2(hx: f64, hy: f64) -> Aabb {
    Aabb {
        min: [-hx, -hy, 0.0],
        max: [hx, hy, 0.0],
    }
}
const fn t(components: usize, genus: &'static [usize]) -> Option<Topology> {
    Some(Topology { components, genus })
}

/// All entries, surfaces then curves.
pub fn entries() -> Vec<Entry> {
    vec![
        Entry { name: "sphere", dim: 3, formula: "x^2 + y^2 + z^2 - 1", domain: b3(1.5), topology: t(1, &[0]), smooth: true, note: "unit sphere" },
        Entry { name: "ellipsoid", dim: 3, formula: "x^2 + 4*y^2 + 16*z^2 - 1", domain: b3(1.25), topology: t(1, &[0]), smooth: true, note: "semi-axes 1, 1/2, 1/4: curvature varies by 64x" },
        Entry { name: "torus", dim: 3, formula: "(x^2 + y^2 + z^2 + 0.6^2 - 0.25^2)^2 - 4*0.6^2*(x^2 + y^2)", domain: b3(1.0), topology: t(1, &[1]), smooth: true, note: "ring torus, radii R = 0.6, r = 0.25" },
        Entry { name: "genus2", dim: 3, formula: "z^2 + 0.5*(x^2/1.44 + y^2/0.64 - 1)*((x - 0.55)^2 + y^2 - 0.09)*((x + 0.55)^2 + y^2 - 0.09)", domain: b3(1.5), topology: t(1, &[2]), smooth: true, note: "thickened planar region: ellipse (1.2 x 0.8) with two round holes (r = 0.3); z^2 + u(x,y) = 0 with u < 0 on the region" },
        Entry { name: "genus5", dim: 3, formula: "z^2 + 0.2*(x^2 + y^2 - 1.44)*((x - 0.75)^2 + y^2 - 0.04)*((x - 0.2318)^2 + (y - 0.7133)^2 - 0.04)*((x + 0.6068)^2 + (y - 0.4408)^2 - 0.04)*((x + 0.6068)^2 + (y + 0.4408)^2 - 0.04)*((x - 0.2318)^2 + (y + 0.7133)^2 - 0.04)", domain: b3(1.5), topology: t(1, &[5]), smooth: true, note: "thickened disk of radius 1.2 with five holes (r = 0.2) on a circle of radius 0.75" },
        Entry { name: "tanglecube", dim: 3, formula: "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", domain: b3(3.0), topology: t(1, &[5]), smooth: true, note: "the classic tanglecube (genus 5)" },
        Entry { name: "two-spheres", dim: 3, formula: "((x - 0.51)^2 + y^2 + z^2 - 0.25)*((x + 0.51)^2 + y^2 + z^2 - 0.25)", domain: b3(1.2), topology: t(2, &[0, 0]), smooth: true, note: "two spheres of radius 0.5, 0.02 apart: coarse grids merge them" },
        Entry { name: "thin-torus", dim: 3, formula: "(x^2 + y^2 + z^2 + 0.6^2 - 0.05^2)^2 - 4*0.6^2*(x^2 + y^2)", domain: b3(1.0), topology: t(1, &[1]), smooth: true, note: "tube radius 0.05: coarse grids miss or break it" },
        Entry { name: "paraboloid-cap", dim: 3, formula: "x^2 - x*y + y^2 + (z - 0.5)^2 - 0.25", domain: b3(2.0), topology: t(1, &[0]), smooth: true, note: "ellipsoid tangent to the grid plane z = 0 at the origin (a grid corner), osculating the chapter's paraboloid z = x^2 - xy + y^2 there: Snyder's grazing case" },
        Entry { name: "double-cone", dim: 3, formula: "x^2 + y^2 - z^2", domain: b3(1.0), topology: None, smooth: false, note: "singular at the origin: must be reported, never certified" },
        Entry { name: "blob", dim: 3, formula: "x^2 + y^2 + z^2 - 1 + 0.8*x*y*z", domain: b3(1.6), topology: t(1, &[0]), smooth: true, note: "star-shaped in the box: along each ray r^2 - 1 + 0.8 r^3 c, |c| <= 3^-1.5, has one root for r < 2.77" },
        Entry { name: "superquadric", dim: 3, formula: "x^4 + y^4 + z^4 - 1", domain: b3(1.5), topology: t(1, &[0]), smooth: true, note: "rounded cube; flat regions where the curvature vanishes" },
        // Curves.
        Entry { name: "circle", dim: 2, formula: "x^2 + y^2 - 1", domain: b2(1.5, 1.5), topology: t(1, &[0]), smooth: true, note: "unit circle" },
        Entry { name: "ellipse", dim: 2, formula: "x^2/4 + y^2 - 1", domain: b2(2.5, 1.5), topology: t(1, &[0]), smooth: true, note: "semi-axes 2 and 1" },
        Entry { name: "cassini-1", dim: 2, formula: "(x^2 + y^2)^2 - 2*(x^2 - y^2) - (1.1^4 - 1)", domain: b2(2.0, 1.5), topology: t(1, &[0]), smooth: true, note: "Cassini oval with b/a = 1.1: one component with a waist" },
        Entry { name: "cassini-2", dim: 2, formula: "(x^2 + y^2)^2 - 2*(x^2 - y^2) - (0.9^4 - 1)", domain: b2(2.0, 1.5), topology: t(2, &[0, 0]), smooth: true, note: "Cassini oval with b/a = 0.9: two components" },
        Entry { name: "protrusion", dim: 2, formula: "(x^2 - 1)^2 + y^2 - 1.01", domain: b2(1.8, 1.5), topology: t(1, &[0]), smooth: true, note: "two lobes joined by a neck 0.2 wide, like Fig 1.5 of the chapter: coarse marching squares splits it into two cycles" },
        Entry { name: "near-touching", dim: 2, formula: "((x - 0.51)^2 + y^2 - 0.25)*((x + 0.51)^2 + y^2 - 0.25)", domain: b2(1.2, 0.8), topology: t(2, &[0, 0]), smooth: true, note: "two circles of radius 0.5, 0.02 apart" },
        Entry { name: "lemniscate", dim: 2, formula: "(x^2 + y^2)^2 - 2*(x^2 - y^2)", domain: b2(1.7, 1.0), topology: None, smooth: false, note: "lemniscate of Bernoulli: a node at the origin, must be reported" },
        Entry { name: "superellipse", dim: 2, formula: "x^4 + y^4 - 1", domain: b2(1.5, 1.5), topology: t(1, &[0]), smooth: true, note: "curvature vanishes at the four axis points" },
    ]
}

/// Look an entry up by name.
pub fn get(name: &str) -> Result<Entry> {
    let all = entries();
    let known = all.iter().map(|e| e.name).collect::<Vec<_>>().join(" ");
    all.into_iter()
        .find(|e| e.name == name)
        .ok_or(Error::Unknown {
            kind: "catalog entry",
            name: name.to_string(),
            known,
        })
}

pub fn surfaces() -> Vec<Entry> {
    entries().into_iter().filter(|e| e.dim == 3).collect()
}
pub fn curves() -> Vec<Entry> {
    entries().into_iter().filter(|e| e.dim == 2).collect()
}
