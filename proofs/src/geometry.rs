//! The project's GradNormal tiling data, as the proof reads it: re-exported from the
//! mesher's own module, so the proof verifies exactly the data the mesher uses.
pub use certmesh::gradnormal::tiling::{
    Goldberg, NormalQuad, TetType, A, B, C, D, EDGE_DIRS, HELIX_OF_LABEL, K, L, LABELS, M,
    MIDPOINT_EDGES, MIDPOINT_NAMES, N, NORMAL_QUADS, NORMAL_TRIANGLES, P, PAPER_RATIOS, Q,
    SOMMERVILLE_RATIO,
};
pub use certmesh::gradnormal::DiagonalRule;
