//! Angle measurements used by the stuffing stats and the Table 1 checks: dihedral
//! angles, plane angles of every tetrahedron face, plane angles of the exposed
//! (boundary) triangles, and inverted-tetrahedron counts (exact `orient3d`).
use crate::kernel::geom::{angle_deg, cross, dot, norm, sub};
use crate::mesh::{TetMesh, TriMesh};
use rayon::prelude::*;
use serde::Serialize;

/// The six dihedral angles of a tetrahedron, in degrees.
pub fn dihedrals(p: [[f64; 3]; 4]) -> [f64; 6] {
    const E: [(usize, usize, usize, usize); 6] = crate::kernel::geom::TET_EDGES_WITH_OPPOSITE;
    E.map(|(i, j, k, l)| {
        let e = sub(p[j], p[i]);
        let ee = dot(e, e);
        let perp = |q: [f64; 3]| {
            let v = sub(q, p[i]);
            let s = if ee > 0.0 { dot(v, e) / ee } else { 0.0 };
            [v[0] - s * e[0], v[1] - s * e[1], v[2] - s * e[2]]
        };
        let (a, b) = (perp(p[k]), perp(p[l]));
        norm(cross(a, b)).atan2(dot(a, b)).to_degrees()
    })
}

/// The 12 plane angles of a tetrahedron's faces.
pub fn plane_angles(p: [[f64; 3]; 4]) -> [f64; 12] {
    const F: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
    let mut out = [0.0; 12];
    for (fi, f) in F.iter().enumerate() {
        for k in 0..3 {
            out[3 * fi + k] = angle_deg(p[f[(k + 2) % 3]], p[f[k]], p[f[(k + 1) % 3]]);
        }
    }
    out
}

/// Extreme angles of a tetrahedral mesh and its boundary.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct AngleSummary {
    pub tetrahedra: usize,
    pub min_dihedral_deg: f64,
    pub max_dihedral_deg: f64,
    pub min_plane_deg: f64,
    pub max_plane_deg: f64,
    pub min_exposed_deg: f64,
    pub max_exposed_deg: f64,
    /// Tetrahedra with nonpositive signed volume (exact predicate).
    pub inverted: usize,
}

/// Signed volume sign by the exact `orient3d` predicate: > 0 for positive tets.
pub use crate::kernel::predicates::tet_orientation as orientation;

/// Every angle and orientation of the mesh, tetrahedra and boundary triangles in
/// parallel (min, max and counts are exact reductions: the result does not depend on
/// the split).
pub fn summarize(tets: &TetMesh, boundary: &TriMesh) -> AngleSummary {
    let empty = AngleSummary {
        tetrahedra: tets.tets.len(),
        min_dihedral_deg: f64::INFINITY,
        max_dihedral_deg: f64::NEG_INFINITY,
        min_plane_deg: f64::INFINITY,
        max_plane_deg: f64::NEG_INFINITY,
        min_exposed_deg: f64::INFINITY,
        max_exposed_deg: f64::NEG_INFINITY,
        inverted: 0,
    };
    let join = |mut s: AngleSummary, o: AngleSummary| {
        s.min_dihedral_deg = s.min_dihedral_deg.min(o.min_dihedral_deg);
        s.max_dihedral_deg = s.max_dihedral_deg.max(o.max_dihedral_deg);
        s.min_plane_deg = s.min_plane_deg.min(o.min_plane_deg);
        s.max_plane_deg = s.max_plane_deg.max(o.max_plane_deg);
        s.min_exposed_deg = s.min_exposed_deg.min(o.min_exposed_deg);
        s.max_exposed_deg = s.max_exposed_deg.max(o.max_exposed_deg);
        s.inverted += o.inverted;
        s
    };
    let t = (0..tets.tets.len())
        .into_par_iter()
        .fold(
            || empty,
            |mut s, t| {
                let p = tets.corners(t);
                for a in dihedrals(p) {
                    s.min_dihedral_deg = s.min_dihedral_deg.min(a);
                    s.max_dihedral_deg = s.max_dihedral_deg.max(a);
                }
                for a in plane_angles(p) {
                    s.min_plane_deg = s.min_plane_deg.min(a);
                    s.max_plane_deg = s.max_plane_deg.max(a);
                }
                if orientation(p) <= 0.0 {
                    s.inverted += 1;
                }
                s
            },
        )
        .reduce(|| empty, join);
    let b = (0..boundary.triangles.len())
        .into_par_iter()
        .fold(
            || empty,
            |mut s, t| {
                let [a, b, c] = boundary.corners(t);
                for x in [angle_deg(c, a, b), angle_deg(a, b, c), angle_deg(b, c, a)] {
                    s.min_exposed_deg = s.min_exposed_deg.min(x);
                    s.max_exposed_deg = s.max_exposed_deg.max(x);
                }
                s
            },
        )
        .reduce(|| empty, join);
    join(t, b)
}

/// All dihedral angles (for histograms).
pub fn all_dihedrals(tets: &TetMesh) -> Vec<f64> {
    (0..tets.tets.len())
        .flat_map(|t| dihedrals(tets.corners(t)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn bcc_tet_angles() {
        // The BCC tetrahedron: dihedral angles 60° and 90° (§3).
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 0.5, 0.5],
            [0.5, 0.5, -0.5],
        ];
        let mut d = dihedrals(p).to_vec();
        d.sort_by(f64::total_cmp);
        let want = [60.0, 60.0, 60.0, 60.0, 90.0, 90.0];
        for (a, b) in d.iter().zip(want) {
            assert!((a - b).abs() < 1e-9, "{d:?}");
        }
        // This naming is negatively oriented.
        assert!(orientation(p) < 0.0);
        assert!(orientation([p[1], p[0], p[2], p[3]]) > 0.0);
    }

    use proptest::prelude::*;

    fn pt() -> impl Strategy<Value = [f64; 3]> {
        [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0]
    }

    proptest! {
        /// Dihedral angles are in [0°, 180°], invariant under vertex permutations, and
        /// a swap of two vertices flips the exact orientation.
        #[test]
        fn dihedral_invariants(a in pt(), b in pt(), c in pt(), d in pt()) {
            let p = [a, b, c, d];
            let o = orientation(p);
            prop_assume!(o != 0.0);
            let mut x = dihedrals(p).to_vec();
            let mut y = dihedrals([b, a, d, c]).to_vec();
            x.sort_by(f64::total_cmp);
            y.sort_by(f64::total_cmp);
            for (u, v) in x.iter().zip(&y) {
                prop_assert!((0.0..=180.0).contains(u));
                prop_assert!((u - v).abs() < 1e-6);
            }
            prop_assert_eq!(orientation([b, a, c, d]).signum(), -o.signum());
            // Face angles of each face sum to 180°.
            let pa = plane_angles(p);
            for f in 0..4 {
                prop_assert!((pa[3 * f] + pa[3 * f + 1] + pa[3 * f + 2] - 180.0).abs() < 1e-6);
            }
        }
    }
}
