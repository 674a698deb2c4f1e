//! Angle measurements used by the stuffing stats and the Table 1 checks: dihedral
//! angles, plane angles of every tetrahedron face, plane angles of the exposed
//! (boundary) triangles, and inverted-tetrahedron counts (exact `orient3d`).
use crate::kernel::geom::{cross, dot, sub, TET_EDGES_WITH_OPPOSITE};
use crate::mesh::{Buckets, FaceItem, TetMesh, TriMesh, TET_FACES};
use crate::metrics::angles::{angle_pair, Extremes};
use rayon::prelude::*;
use serde::Serialize;

/// The six dihedral angles of a tetrahedron, in degrees.
pub fn dihedrals(p: [[f64; 3]; 4]) -> [f64; 6] {
    dihedral_pairs(p).map(deg)
}

/// Each dihedral angle of [`dihedrals`] as a pair (y, x) with y ≥ 0 whose atan2 is the
/// angle, in the order of [`TET_EDGES_WITH_OPPOSITE`]. With n_k the normal of the face
/// opposite corner k (the faces of [`TET_FACES`], one orientation for all four), the angle
/// at edge ij between faces ijk and ijl is π minus the angle between n_l and n_k, and
/// |n_k × n_l| = |det| |p_j − p_i| (det = 6 × the signed volume), so the pair is
/// (|det| |p_j − p_i|, −n_k · n_l): four cross products and six square roots per
/// tetrahedron, no division. A flat tetrahedron gives y = 0 (0° or 180°).
///
/// Loops rather than `array::map`, which the compiler left as out-of-line calls here
/// (measured: with the maps, this arithmetic made the summary no faster).
#[inline]
fn dihedral_pairs(p: [[f64; 3]; 4]) -> [(f64, f64); 6] {
    let mut n = [[0.0; 3]; 4];
    for (nk, &[a, b, c]) in n.iter_mut().zip(&TET_FACES) {
        *nk = cross(sub(p[b], p[a]), sub(p[c], p[a]));
    }
    let det = dot(n[3], sub(p[3], p[0])).abs();
    let mut out = [(0.0, 0.0); 6];
    for (o, &(i, j, k, l)) in out.iter_mut().zip(&TET_EDGES_WITH_OPPOSITE) {
        let e = sub(p[j], p[i]);
        *o = (det * dot(e, e).sqrt(), -dot(n[k], n[l]));
    }
    out
}

/// The angle of a pair, in degrees.
fn deg((y, x): (f64, f64)) -> f64 {
    y.atan2(x).to_degrees()
}

/// The 12 plane angles of a tetrahedron's faces.
pub fn plane_angles(p: [[f64; 3]; 4]) -> [f64; 12] {
    plane_angle_pairs(p).map(deg)
}

fn plane_angle_pairs(p: [[f64; 3]; 4]) -> [(f64, f64); 12] {
    let mut out = [(0.0, 0.0); 12];
    for (fi, f) in TET_FACES.iter().enumerate() {
        for k in 0..3 {
            out[3 * fi + k] = angle_pair(p[f[(k + 2) % 3]], p[f[k]], p[f[(k + 1) % 3]]);
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

/// Per fold: dihedral, plane and exposed extremes, and the inverted count.
type Acc = (Extremes, Extremes, Extremes, usize);
const NONE: Acc = (Extremes::EMPTY, Extremes::EMPTY, Extremes::EMPTY, 0);

fn merge(mut a: Acc, b: Acc) -> Acc {
    for (x, y) in [(&mut a.0, b.0), (&mut a.1, b.1), (&mut a.2, b.2)] {
        x.merge(y);
    }
    a.3 += b.3;
    a
}

fn finish(tetrahedra: usize, (d, p, e, inverted): Acc) -> AngleSummary {
    AngleSummary {
        tetrahedra,
        min_dihedral_deg: d.min,
        max_dihedral_deg: d.max,
        min_plane_deg: p.min,
        max_plane_deg: p.max,
        min_exposed_deg: e.min,
        max_exposed_deg: e.max,
        inverted,
    }
}

/// The dihedral angles and exact orientations of every tetrahedron, in parallel; with
/// `plane`, the plane angles of every tetrahedron's faces too.
fn tet_pass(tets: &TetMesh, plane: bool) -> Acc {
    (0..tets.tets.len())
        .into_par_iter()
        .fold(
            || NONE,
            |mut s, t| {
                let p = tets.corners(t);
                dihedral_pairs(p).into_iter().for_each(|q| s.0.offer(q));
                if plane {
                    plane_angle_pairs(p).into_iter().for_each(|q| s.1.offer(q));
                }
                if orientation(p) <= 0.0 {
                    s.3 += 1;
                }
                s
            },
        )
        .reduce(|| NONE, merge)
}

/// The three angle pairs of a triangle, as [`plane_angle_pairs`] measures a face.
#[inline(always)]
fn triangle_pairs([a, b, c]: [[f64; 3]; 3]) -> [(f64, f64); 3] {
    [
        angle_pair(c, a, b),
        angle_pair(a, b, c),
        angle_pair(b, c, a),
    ]
}

/// Every angle and orientation of the mesh, tetrahedra and boundary triangles in
/// parallel (min, max and counts are exact reductions: the result does not depend on
/// the split).
pub fn summarize(tets: &TetMesh, boundary: &TriMesh) -> AngleSummary {
    let t = tet_pass(tets, true);
    let b = (0..boundary.triangles.len())
        .into_par_iter()
        .fold(
            || NONE,
            |mut s, t| {
                triangle_pairs(boundary.corners(t))
                    .into_iter()
                    .for_each(|q| s.2.offer(q));
                s
            },
        )
        .reduce(|| NONE, merge);
    finish(tets.tets.len(), merge(t, b))
}

/// [`summarize`] of a mesh and its boundary ([`TetMesh::boundary_with`]) from the mesh's
/// faces grouped by [`TetMesh::face_buckets`]`(false)`: each face's plane angles are
/// measured once rather than once per tetrahedron that has it, and the exposed angles
/// are those of the faces in one tetrahedron. The same values bit for bit: the angle at
/// a vertex of a triangle is computed from the same two differences whichever way the
/// triangle is oriented (a swap only negates the cross product, exactly), and the
/// boundary triangles are those faces, on the same coordinates.
pub fn summarize_faces(tets: &TetMesh, faces: &Buckets<FaceItem>) -> AngleSummary {
    let t = tet_pass(tets, false);
    let v = &tets.vertices;
    let f = (0..faces.len())
        .into_par_iter()
        .fold(
            || NONE,
            |mut s, k| {
                for run in faces.runs(k, |x| x.0) {
                    let [a, b, c] = run[0].1;
                    let pairs = triangle_pairs([v[a as usize], v[b as usize], v[c as usize]]);
                    pairs.into_iter().for_each(|q| s.1.offer(q));
                    if run.len() == 1 {
                        pairs.into_iter().for_each(|q| s.2.offer(q));
                    }
                }
                s
            },
        )
        .reduce(|| NONE, merge);
    finish(tets.tets.len(), merge(t, f))
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
    use crate::kernel::geom::angle_deg;
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
        /// `summarize` (which skips atan2 where a pair cannot beat the extremes) gives
        /// the extremes of every angle computed one by one, bit for bit, and the
        /// inverted count: on random tetrahedra, on lattice points (many equal
        /// angles, ties and right angles) and with degenerate ones.
        #[test]
        fn summary_equals_every_angle(
            pts in prop::collection::vec(pt(), 4..40),
            lattice in prop::collection::vec([0i32..3, 0i32..3, 0i32..3], 4..40),
            idx in prop::collection::vec([0usize..1000, 0usize..1000, 0usize..1000, 0usize..1000], 1..60),
            on_lattice in any::<bool>(),
        ) {
            let vertices: Vec<[f64; 3]> = if on_lattice {
                lattice.iter().map(|q| q.map(|c| c as f64 * 0.5)).collect()
            } else {
                pts
            };
            let n = vertices.len();
            let tets: Vec<[u32; 4]> = idx.iter().map(|t| t.map(|i| (i % n) as u32)).collect();
            let triangles: Vec<[u32; 3]> = tets.iter().map(|t| [t[0], t[1], t[2]]).collect();
            let mesh = TetMesh { vertices: vertices.clone(), tets };
            let boundary = TriMesh { vertices, triangles };
            let s = summarize(&mesh, &boundary);
            let fold = |xs: Vec<f64>| {
                xs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &a| (lo.min(a), hi.max(a)))
            };
            let d = fold((0..mesh.tets.len()).flat_map(|t| dihedrals(mesh.corners(t))).collect());
            let p = fold((0..mesh.tets.len()).flat_map(|t| plane_angles(mesh.corners(t))).collect());
            let e = fold((0..boundary.triangles.len()).flat_map(|t| {
                let [a, b, c] = boundary.corners(t);
                [angle_deg(c, a, b), angle_deg(a, b, c), angle_deg(b, c, a)]
            }).collect());
            let bits = |x: f64| x.to_bits();
            prop_assert_eq!((bits(s.min_dihedral_deg), bits(s.max_dihedral_deg)), (bits(d.0), bits(d.1)));
            prop_assert_eq!((bits(s.min_plane_deg), bits(s.max_plane_deg)), (bits(p.0), bits(p.1)));
            prop_assert_eq!((bits(s.min_exposed_deg), bits(s.max_exposed_deg)), (bits(e.0), bits(e.1)));
            let inv = (0..mesh.tets.len()).filter(|&t| orientation(mesh.corners(t)) <= 0.0).count();
            prop_assert_eq!(s.inverted, inv);
            // From the grouped faces: the summary of the mesh and its true boundary.
            let faces = mesh.face_buckets(false);
            let by_faces = summarize_faces(&mesh, &faces);
            let whole = summarize(&mesh, &mesh.boundary_with(&faces));
            let all = |s: &AngleSummary| {
                [s.min_dihedral_deg, s.max_dihedral_deg, s.min_plane_deg, s.max_plane_deg, s.min_exposed_deg, s.max_exposed_deg].map(bits)
            };
            prop_assert_eq!(all(&by_faces), all(&whole));
            prop_assert_eq!((by_faces.tetrahedra, by_faces.inverted), (whole.tetrahedra, whole.inverted));
        }

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
            // The same angles, edge by edge, as the metrics compute them (the angle
            // between outward normals, atan2 of their cross product's norm and dot).
            // Tolerance: the rounding of either, about 1e-16 over the sine of the
            // faces' angles; the tetrahedra kept are not nearly flat.
            let other = crate::metrics::angles::dihedral_angles(&p);
            let v6 = o.abs();
            let scale = [a, b, c, d].iter().map(|q| dot(sub(*q, a), sub(*q, a))).fold(0.0, f64::max);
            prop_assume!(v6 > 1e-3 * scale.powf(1.5));
            for (u, v) in dihedrals(p).iter().zip(other) {
                prop_assert!((u - v).abs() < 1e-7, "{:?} vs {:?}", dihedrals(p), other);
            }
            // Face angles of each face sum to 180°.
            let pa = plane_angles(p);
            for f in 0..4 {
                prop_assert!((pa[3 * f] + pa[3 * f + 1] + pa[3 * f + 2] - 180.0).abs() < 1e-6);
            }
        }
    }
}
