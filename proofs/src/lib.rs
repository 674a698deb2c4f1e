//! `proofs`: computer-assisted proofs about certmesh's meshers, re-checked with rigorous
//! interval arithmetic (inari) and exact rational arithmetic, written as certificates
//! that can be re-verified independently.
//!
//! Layout: one folder per proof ([`gradnormal`], [`stuffing`]) beside the shared
//! machinery: the branch and bound over the unit square ([`bnb`]), interval helpers and
//! duals ([`ival`]), exact threshold comparisons ([`exact`]) and the project's tiling
//! data ([`geometry`]).
pub mod bnb;
pub mod exact;
pub mod fields;
pub mod geometry;
pub mod gradnormal;
pub mod ival;
pub mod stuffing;
pub mod witness_check;
