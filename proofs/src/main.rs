//! `proofs`: computer-assisted proofs about certmesh's meshers, re-checked with rigorous
//! interval arithmetic (inari) and exact rational arithmetic, written as certificates
//! that can be re-verified independently.
use clap::Parser;

/// Computer-assisted proofs and certificates for certmesh.
///
/// The proofs verify the project's own data (the GradNormal tiling and diagonal rules,
/// the isosurface-stuffing stencil table), read from the same code the meshers use, so
/// a certificate speaks about the meshes certmesh actually produces.
#[derive(Parser)]
#[command(name = "proofs", version, about, long_about)]
struct Cli {}

fn main() {
    let _ = Cli::parse();
    println!("no proof is implemented in this build yet; see `proofs --help`");
}
