//! The pieces of the `proofs` binary beside its argument parsing and dispatch
//! (`main.rs`): errors and exit codes, files, output.
pub(crate) mod fail;
pub(crate) mod files;
pub(crate) mod print;
