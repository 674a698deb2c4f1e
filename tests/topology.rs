//! Combinatorial topology and the topology verdicts on hand-built meshes whose answers
//! are known exactly: Euler characteristic, components, boundary loops, manifoldness,
//! orientability and genus of triangle meshes, curves and tetrahedral meshes.
mod common;

use certmesh::catalog;
use certmesh::kernel::bvh::TriBvh;
use certmesh::kernel::geom;
use certmesh::mesh::{Curve2, TetMesh, TriMesh};
use certmesh::metrics::{self, angles, FidelityParams};
use common::*;

// ---------------------------------------------------------------- topology

#[test]
fn cube_is_a_sphere() {
    let r = metrics::analyze(&cube_surface()).unwrap();
    assert_eq!((r.vertices, r.edges, r.faces), (8, 18, 12));
    assert_eq!(r.euler_characteristic, 2);
    assert_eq!(r.components, 1);
    assert!(r.closed && r.manifold && r.orientable && r.consistently_oriented);
    assert_eq!(r.genus, vec![0]);
    let v = metrics::verdict(&r, &sphere_topology());
    assert!(v.ok, "{v:?}");
    assert_eq!(v.found, "1 component, genus [0]");
}

#[test]
fn hand_built_torus_has_genus_one() {
    let r = metrics::analyze(&torus(12, 8)).unwrap();
    assert_eq!(r.euler_characteristic, 0);
    assert_eq!(r.genus, vec![1]);
    assert!(r.closed && r.manifold && r.consistently_oriented);
    let t = catalog::get("torus").unwrap().topology.unwrap();
    assert!(metrics::verdict(&r, &t).ok);
    let v = metrics::verdict(&r, &sphere_topology());
    assert!(!v.ok);
    assert!(
        v.reason.contains("genus [1] instead of [0]"),
        "{}",
        v.reason
    );
}

#[test]
fn two_tetrahedra_are_two_components() {
    let m = concat(&tetra_surface([0.0; 3]), &tetra_surface([3.0, 0.0, 0.0]));
    let r = metrics::analyze(&m).unwrap();
    assert_eq!(r.components, 2);
    assert_eq!(r.euler_characteristic, 4);
    assert_eq!(r.genus, vec![0, 0]);
    let v = metrics::verdict(&r, &sphere_topology());
    assert!(!v.ok);
    assert!(
        v.reason.contains("2 components instead of 1"),
        "{}",
        v.reason
    );
    let two = catalog::get("two-spheres").unwrap().topology.unwrap();
    assert!(metrics::verdict(&r, &two).ok);
}

#[test]
fn removing_a_face_makes_one_boundary_loop() {
    let mut m = cube_surface();
    m.triangles.remove(5);
    let r = metrics::analyze(&m).unwrap();
    assert_eq!(r.boundary_edges, 3);
    assert_eq!(r.boundary_loops, 1);
    assert!(!r.closed && r.manifold);
    assert_eq!(r.euler_characteristic, 1);
    assert!(r.genus.is_empty(), "no closed component");
    assert_eq!(r.component_list[0].genus, Some(0), "a disk");
    let v = metrics::verdict(&r, &sphere_topology());
    assert!(!v.ok);
    assert!(
        v.reason.contains("not closed: 3 boundary edges in 1 loop"),
        "{}",
        v.reason
    );
    // Two separate holes: two loops.
    let mut m2 = cube_surface();
    m2.triangles.remove(11);
    m2.triangles.remove(0);
    assert_eq!(metrics::analyze(&m2).unwrap().boundary_loops, 2);
}

#[test]
fn non_manifold_edge_is_detected() {
    let mut m = cube_surface();
    m.vertices.push([0.5, 0.5, 3.0]);
    m.triangles.push([0, 1, 8]); // a fin on the edge 0-1
    let r = metrics::analyze(&m).unwrap();
    assert_eq!(r.non_manifold_edges, 1);
    assert!(!r.manifold);
    let v = metrics::verdict(&r, &sphere_topology());
    assert!(!v.ok);
    assert!(v.reason.contains("1 non-manifold edge"), "{}", v.reason);
}

#[test]
fn bow_tie_vertex_is_non_manifold() {
    let a = tetra_surface([0.0; 3]);
    let mut b = tetra_surface([0.0; 3]);
    for p in &mut b.vertices {
        *p = geom::scale(*p, -1.0);
    }
    let mut m = concat(&a, &b);
    // Weld b's vertex 0 (the origin) to a's vertex 0.
    for t in &mut m.triangles[4..] {
        for i in t.iter_mut() {
            if *i == 4 {
                *i = 0;
            }
        }
    }
    let r = metrics::analyze(&m).unwrap();
    assert_eq!(r.components, 1);
    assert_eq!(r.non_manifold_vertices, 1);
    assert_eq!(r.non_manifold_edges, 0);
    assert_eq!(r.isolated_vertices, 1, "the welded-away vertex");
    assert!(!metrics::verdict(&r, &sphere_topology()).ok);
}

#[test]
fn flipped_face_is_inconsistent() {
    let mut m = cube_surface();
    m.triangles[3].swap(1, 2);
    let r = metrics::analyze(&m).unwrap();
    assert_eq!(r.inconsistent_edges, 3);
    assert!(r.orientable, "a flip can be undone");
    assert!(!r.consistently_oriented);
    let mut all = cube_surface();
    all.flip();
    let r = metrics::analyze(&all).unwrap();
    assert!(r.consistently_oriented, "all flipped is consistent");
}

#[test]
fn moebius_strip_is_not_orientable() {
    // A strip of n quads whose ends are glued with a half twist.
    let n = 8u32;
    let mut v = Vec::new();
    for i in 0..n {
        let u = i as f64 / n as f64 * std::f64::consts::TAU;
        for s in [-0.3, 0.3] {
            let w = u / 2.0;
            let rr = 1.0 + s * w.cos();
            v.push([rr * u.cos(), rr * u.sin(), s * w.sin()]);
        }
    }
    let mut t = Vec::new();
    for i in 0..n {
        let (a, b) = (2 * i, 2 * i + 1);
        let (c, d) = if i + 1 < n {
            (2 * i + 2, 2 * i + 3)
        } else {
            (1, 0) // the twist
        };
        t.push([a, c, d]);
        t.push([a, d, b]);
    }
    let r = metrics::analyze(&TriMesh::new(v, t)).unwrap();
    assert!(!r.orientable);
    assert_eq!(
        r.boundary_loops, 1,
        "a Möbius strip has one boundary circle"
    );
    assert_eq!(r.euler_characteristic, 0);
    assert_eq!(r.component_list[0].genus, None);
}

#[test]
fn degenerate_duplicate_and_isolated() {
    let mut m = cube_surface();
    m.vertices.push([9.0, 9.0, 9.0]);
    m.triangles.push([0, 0, 1]);
    m.triangles.push(m.triangles[0]);
    let r = metrics::analyze(&m).unwrap();
    assert_eq!(r.isolated_vertices, 1);
    assert_eq!(r.degenerate_faces, 1);
    assert_eq!(r.duplicate_faces, 1);
    assert!(!r.manifold);
    let v = metrics::verdict(&r, &sphere_topology());
    assert!(!v.ok && v.reason.contains("degenerate face") && v.reason.contains("duplicate"));
}

#[test]
fn bad_indices_are_errors_not_panics() {
    let m = TriMesh::new(vec![[0.0; 3]; 3], vec![[0, 1, 7]]);
    let e = metrics::analyze(&m).unwrap_err().to_string();
    assert!(e.contains("triangle 0 refers to vertex 7"), "{e}");
    assert!(metrics::stats(&m, None).is_err());
    assert!(TriBvh::new(&m).is_err());
    assert!(angles::triangle_summary(&m, 5.0).is_err());
    let nan = TriMesh::new(vec![[0.0, f64::NAN, 0.0]; 3], vec![[0, 1, 2]]);
    assert!(metrics::analyze(&nan).is_err());
    let t = TetMesh {
        vertices: vec![[0.0; 3]; 4],
        tets: vec![[0, 1, 2, 4]],
    };
    assert!(metrics::analyze_tets(&t).is_err());
    assert!(angles::tet_summary(&t, 5.0).is_err());
}

#[test]
fn empty_mesh_gives_a_report() {
    let r = metrics::analyze(&TriMesh::default()).unwrap();
    assert_eq!((r.vertices, r.faces, r.components), (0, 0, 0));
    let v = metrics::verdict(&r, &sphere_topology());
    assert!(!v.ok && v.reason.contains("empty"));
    let s = metrics::stats(&TriMesh::default(), None).unwrap();
    assert_eq!(s.min_angle_deg, None);
}

#[test]
fn curve_topology_and_verdict() {
    let (v, s) = polygon(16, [0.0, 0.0], 1.0, 0);
    let c = Curve2 {
        vertices: v,
        segments: s,
    };
    let r = metrics::analyze_curve(&c).unwrap();
    assert_eq!((r.components, r.closed_components, r.open_ends), (1, 1, 0));
    let circle = catalog::get("circle").unwrap().topology.unwrap();
    assert!(metrics::curve_verdict(&r, &circle).ok);

    // Cut one segment: an open arc.
    let mut open = c.clone();
    open.segments.pop();
    let r = metrics::analyze_curve(&open).unwrap();
    assert_eq!((r.components, r.closed_components, r.open_ends), (1, 0, 2));
    let v = metrics::curve_verdict(&r, &circle);
    assert!(!v.ok && v.reason.contains("2 open ends"), "{v:?}");

    // A chord: two branch points.
    let mut chord = c.clone();
    chord.segments.push([0, 8]);
    let r = metrics::analyze_curve(&chord).unwrap();
    assert_eq!(r.branch_points, 2);
    assert!(!metrics::curve_verdict(&r, &circle).ok);

    // Two circles against cassini-2 and against circle.
    let (v2, s2) = polygon(16, [3.0, 0.0], 1.0, 16);
    let mut two = c.clone();
    two.vertices.extend(v2);
    two.segments.extend(s2);
    let r = metrics::analyze_curve(&two).unwrap();
    assert_eq!(r.closed_components, 2);
    let cas2 = catalog::get("cassini-2").unwrap().topology.unwrap();
    assert!(metrics::curve_verdict(&r, &cas2).ok);
    let v = metrics::curve_verdict(&r, &circle);
    assert!(!v.ok && v.reason.contains("2 components instead of 1"));
}

#[test]
fn tet_mesh_topology() {
    let m = cube_tets();
    let r = metrics::analyze_tets(&m).unwrap();
    assert_eq!(r.tets, 6);
    assert_eq!(r.boundary_faces, 12);
    assert_eq!(r.interior_faces, 6);
    assert_eq!(r.nonconforming_faces, 0);
    assert!(r.boundary_closed_manifold);
    assert_eq!(r.boundary_euler_characteristic, 2);
    assert!(r.boundary.consistently_oriented);
    assert!(metrics::tet_verdict(&r, &sphere_topology()).ok);
    let s = metrics::tet_stats(&m, None, &FidelityParams::default()).unwrap();
    assert_eq!(s.inverted_tets, 0);
    assert!((s.ranges.max_dihedral_deg.unwrap() - 90.0).abs() < 1e-12);
    // Kuhn tetrahedra are orthoschemes: dihedral angles 90° (×3), 60°, 45° (×2).
    assert!((s.ranges.min_dihedral_deg.unwrap() - 45.0).abs() < 1e-12);
    // A third tetrahedron on an interior face: non-conforming.
    let mut bad = m.clone();
    bad.vertices.push([2.0, 2.0, 2.0]);
    // Face 0-1-7 is shared by the tetrahedra 0-1-3-7 and 0-1-5-7 already.
    bad.tets.push([0, 1, 7, 8]);
    let r = metrics::analyze_tets(&bad).unwrap();
    assert!(r.nonconforming_faces >= 1);
    assert!(!metrics::tet_verdict(&r, &sphere_topology()).ok);
}
