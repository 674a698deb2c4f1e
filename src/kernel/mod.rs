//! Geometry shared by every algorithm: vector helpers and boxes ([`geom`]), exact
//! orientation predicates ([`predicates`]), and the bounding-volume hierarchy for
//! closest points and winding numbers ([`bvh`]).
pub mod bvh;
pub mod cellgrid;
pub mod delaunay;
pub mod geom;
pub mod predicates;
pub mod rng;
