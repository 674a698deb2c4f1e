//! Restricted-Delaunay surface meshing (the chapter "Meshing of Surfaces", Boissonnat,
//! Cohen-Steiner, Mourrain, Rote and Vegter, 2007, §1.3).
//!
//! * [`restricted`]: the machinery every driver shares — dual Voronoi segments of the
//!   kernel's facets, all their crossings with S by certified root isolation, facet
//!   orientation, the full scan and its certified (interval-circumcentre) version.
//! * [`bo`]: the Boissonnat–Oudot refinement driver with CGAL's criteria
//!   (`--algo bo`, §1.3.1).
pub mod bo;
pub mod restricted;

pub use bo::BoissonnatOudot;
