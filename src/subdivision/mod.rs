//! Shared machinery of the cube-based certified meshers of §1.2 of the chapter
//! (Snyder §1.2.3, Plantinga–Vegter §1.2.4): a quadtree/octree of boxes over the domain,
//! interval criteria, 2:1 balancing, the sign of f at grid points, interval root
//! isolation on box edges, and the assembly of the mesh from per-face crossing patterns.
//!
//! # Geometry
//! The domain box is the root cell; a cell of level `l` has integer index `idx` and, in
//! units of the finest level `D = depth`, occupies `[idx << (D-l), (idx+1) << (D-l)]`.
//! Grid points are stored as integer coordinates; [`Grid::point`] maps them to space by a
//! fixed monotone formula, so neighbouring cells share corners exactly.
//!
//! # Zero values
//! Every sign is taken with the convention **f == 0 counts as positive** (`sign⁺`), i.e.
//! the meshers mesh f + ε = 0 for an infinitesimal ε > 0, which is isotopic to f = 0
//! where ∇f ≠ 0. The sign of f at a grid point is decided by interval evaluation at the
//! point; a point whose enclosure straddles 0 without being exactly [0, 0] is reported as
//! an uncertified region (its float sign is used).
//!
//! # Assembling the mesh
//! The boundary of each non-empty leaf is cut into *tiles*: its faces, split recursively
//! wherever a smaller neighbour has a corner at the face centre (the "transmission" of the
//! smaller boxes' pattern to the larger box, chapter §1.2.3 last paragraphs, and the
//! balanced subdivision of §1.2.4). Tile edges are split at every grid point lying on them
//! (elementary segments), so both boxes sharing a tile see the same points, signs and
//! crossings. Crossings on each tile are paired by an algorithm-specific [`Pairing`] rule
//! that depends only on the tile (never on the box it is seen from) — this is what makes
//! the face choices consistent across neighbouring boxes (Fig 1.10). The directed
//! segments (f > 0 on the left seen from outside the box) close into cycles on the box
//! boundary; each cycle is triangulated as a fan (3D). In 2D the single tile is the box.
//!
//! # Files
//! [`tree`] (cells, verdicts, budget, subdivision, balancing), [`criteria`] (interval
//! tests), [`roots`] (signs and root finders on edges), [`assemble`] (tiles, pairing,
//! cycles), [`generic`] (generic position), [`stats`]; the two meshers built on them:
//! [`snyder`] (Lemma 2) and [`plantinga_vegter`] (Small Normal Variation).
pub mod assemble;
pub mod criteria;
pub mod engine;
pub mod generic;
pub mod plantinga_vegter;
pub mod roots;
pub mod snyder;
pub mod stats;
pub mod tree;

pub use crate::implicit::ops::{
    enclose, excludes_zero, locate, mean_value, no_zero_plus, point_sign, IntervalIsolation,
    PointSign,
};
pub use assemble::*;
pub use criteria::*;
pub use generic::*;
pub use roots::*;
pub use stats::*;
pub use tree::*;
