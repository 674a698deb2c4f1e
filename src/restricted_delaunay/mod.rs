//! Restricted-Delaunay surface meshing (the chapter "Meshing of Surfaces", Boissonnat,
//! Cohen-Steiner, Mourrain, Rote and Vegter, 2007, §1.3).
//!
//! * [`restricted`]: the machinery every driver shares — dual Voronoi segments of the
//!   kernel's facets, all their crossings with S by certified root isolation, facet
//!   orientation, the full scan and its certified (interval-circumcentre) version.
//! * [`bo`]: the Boissonnat–Oudot refinement driver with CGAL's criteria
//!   (`--algo bo`, §1.3.1).
//! * [`tbp`]: the topological ball property checked with interval arithmetic (tests
//!   (1)–(4) of §1.3.2 as checks; Theorem 5: homeomorphism).
//! * [`certify`]: `certmesh certify`, the TBP certificate of anyone's mesh.
//! * [`cdrr`]: the Cheng–Dey–Ramos–Ray refinement driver (`--algo cdrr`, §1.3.2).
//! * [`curve`]: the Boissonnat–Oudot refinement of curves f(x, y) = 0 on `spade`
//!   (`certmesh curve --algo bo`).
//! * [`perturbed`]: Theorem 3 for floating-point vertices, through a certified
//!   point set on S with the same restricted triangulation (`bo --certify`).
pub mod bo;
pub mod cdrr;
pub mod certify;
pub mod curve;
pub mod perturbed;
pub mod restricted;
pub mod tbp;

pub use bo::BoissonnatOudot;
pub use cdrr::ChengDeyRamosRay;
pub use curve::BoissonnatOudot2;
