//! # certmesh — certified meshing of implicit curves and surfaces
//!
//! A newcomer finds each algorithm by its paper's name; everything an algorithm asks of
//! the surface goes through one oracle, and what regenerates the papers' tables and
//! figures lives apart from the algorithms.
//!
//! * [`implicit`]: the oracle — formulas, the tape evaluator (f64, intervals, gradients,
//!   Hessians, regularity flags) and, in [`implicit::ops`], the primitive operations the
//!   meshers ask for (the sign at a point, the roots on a segment, projection);
//! * [`kernel`]: geometry, exact predicates, the bounding-volume hierarchy;
//! * [`lattice`]: regular grids, the BCC lattice, interval pruning of empty space;
//! * [`mesh`], [`io`]: mesh types and file formats; [`metrics`]: angles, topology,
//!   fidelity; [`catalog`]: named test surfaces and curves with their known topology;
//! * [`mesher`]: the one interface every algorithm implements, its options, its honest
//!   report (typed certificates) and the registry of algorithms by name;
//! * the meshers: [`marching`] (marching cubes, tetrahedra, squares), [`subdivision`]
//!   (the engine, with Snyder and Plantinga–Vegter), [`gradnormal`] (GradNormal and
//!   MidNormal, Hass–Trnkova), [`stuffing`] (isosurface stuffing, Labelle–Shewchuk);
//! * [`reproduce`]: everything that regenerates `papers/<name>/`, with the plots it
//!   needs; [`harness`]: the comparison and the demo, returning data (only the CLI
//!   prints).
//!
//! No algorithm module imports [`reproduce`] or [`harness`]; the subdivision engine
//! imports no mesher.
pub mod algebraic;
pub mod catalog;
pub mod error;
pub mod figure;
pub mod gradnormal;
pub mod harness;
pub mod implicit;
pub mod io;
pub mod kernel;
pub mod lattice;
pub mod marching;
pub mod mesh;
pub mod mesher;
pub mod metrics;
pub mod morse;
pub mod render;
pub mod reproduce;
pub mod restricted_delaunay;
pub mod stuffing;
pub mod subdivision;

pub use error::{Error, Result};
pub use implicit::{Formula, Implicit};
pub use kernel::geom::Aabb;
pub use mesher::options::MesherOptions;
pub use mesher::{Certificate, MeshOutput, Mesher};
