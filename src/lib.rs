//! # certmesh — certified meshing of implicit curves and surfaces
//!
//! * [`implicit`]: formulas, the tape evaluator (f64, intervals, gradients, Hessians);
//! * [`catalog`]: named test surfaces and curves with their known topology;
//! * [`mesh`], [`io`]: mesh types and file formats;
//! * [`metrics`]: angles, topology, fidelity;
//! * [`mesher`]: the one interface every algorithm implements, and its honest report;
//! * the meshers, one module per algorithm.
pub mod bcc;
pub mod catalog;
pub mod error;
pub mod geom;
pub mod implicit;
pub mod mesh;
pub mod mesher;
pub mod stuffing;

pub use error::{Error, Result};
pub use geom::Aabb;
pub use implicit::{Formula, Implicit};
pub use mesher::{Certificate, MeshOutput, Mesher};
pub mod options;
pub mod roots;
pub use options::MesherOptions;
