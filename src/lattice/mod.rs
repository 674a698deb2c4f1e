//! Lattices the lattice meshers sample f on: regular grids ([`grid`]), the
//! body-centred cubic lattice of isosurface stuffing ([`bcc`]), and the interval octree
//! that prunes empty space before sampling ([`octree`]).
pub mod bcc;
pub mod grid;
pub mod octree;
