//! `proofs`: computer-assisted proofs about certmesh's meshers, re-checked with rigorous
//! interval arithmetic (inari) and exact rational arithmetic, written as certificates
//! that can be re-verified independently.
pub mod bnb;
pub mod cases;
pub mod eval;
pub mod exact;
pub mod geometry;
pub mod gradnormal;
pub mod ival;
pub mod maps;
pub mod report;
pub mod stuffing;
pub mod stuffing_cases;
pub mod stuffing_eval;
pub mod stuffing_fig;
pub mod stuffing_graded;
