//! Geometry shared by every algorithm: vector helpers and boxes ([`geom`]), exact
//! orientation predicates ([`predicates`]), the bounding-volume hierarchy for
//! closest points and winding numbers ([`bvh`]), and the finite check of coordinates
//! and sampled values ([`finite`]).
pub mod bvh;
pub mod cellgrid;
pub mod delaunay;
pub mod finite;
pub mod geom;
pub mod predicates;
pub mod rng;
