//! # certmesh — certified meshing of implicit curves and surfaces
//!
//! * [`implicit`]: formulas, the tape evaluator (f64, intervals, gradients, Hessians);
//! * [`catalog`]: named test surfaces and curves with their known topology;
//! * [`mesh`], [`io`]: mesh types and file formats;
//! * [`metrics`]: angles, topology, fidelity;
//! * [`mesher`]: the one interface every algorithm implements, and its honest report;
//! * the meshers, one module per algorithm.
pub mod bcc;
pub mod bvh;
pub mod catalog;
pub mod error;
pub mod geom;
pub mod gradnormal;
pub mod implicit;
pub mod io;
pub mod mesh;
pub mod mesher;
pub mod metrics;
pub mod stuffing;

pub use error::{Error, Result};
pub use geom::Aabb;
pub use implicit::{Formula, Implicit};
pub use mesher::{Certificate, MeshOutput, Mesher};
pub mod options;
pub mod roots;
pub mod sdf;
pub use options::MesherOptions;
pub mod algorithms;
pub mod compare;
pub mod demo;
pub mod grid;
pub mod marching;
pub mod octree;
pub mod plantinga_vegter;
pub mod plot;
pub mod plot_subdivision;
pub mod snyder;
pub mod subdivision;
