//! Signed distance to a triangle mesh (`certmesh::implicit::sdf`): distance, winding-number sign
//! with and without holes, gradient, enclosures, normalisation and bad input.
use certmesh::implicit::sdf::{fill_holes, normalize_to_unit_cube, uv_sphere, MeshSdf};
use certmesh::implicit::Implicit;
use certmesh::kernel::bvh::TriBvh;
use certmesh::kernel::geom::{dot, norm, scale, sub};
use certmesh::mesh::TriMesh;
use inari::Interval;
use proptest::prelude::*;

/// The polyhedral sphere's distance differs from |p| − 1 by at most the sagitta of its
/// largest facet; with 64 × 128 facets that is below 1.5e-3.
#[test]
fn sphere_mesh_sdf_matches_exact_distance() {
    let m = uv_sphere(64, 128, 1.0);
    let f = MeshSdf::new(&m).unwrap();
    let mut worst: f64 = 0.0;
    let mut inside = 0;
    for k in 0..400 {
        // Deterministic points in [-2, 2]^3 (a Weyl sequence).
        let p = [0.618034, 0.7548777, 0.5698403].map(|a: f64| 4.0 * ((k as f64 * a) % 1.0) - 2.0);
        let exact = norm(p) - 1.0;
        let d = f.eval(p);
        worst = worst.max((d - exact).abs());
        if exact < -1e-2 {
            inside += 1;
            assert!(d < 0.0, "inside point {p:?} got {d}");
        }
        if exact > 1e-2 {
            assert!(d > 0.0, "outside point {p:?} got {d}");
        }
    }
    assert!(inside > 10, "the sample must reach inside");
    assert!(worst < 1.5e-3, "largest deviation {worst}");
}

/// A sphere with a hole (a polar cap removed): the winding number still separates the
/// inside from the outside away from the hole, and `fill_holes` closes the loop so the
/// mesh is closed again with the same sign everywhere.
#[test]
fn sign_survives_a_hole_and_filling_closes_it() {
    let m = uv_sphere(24, 48, 1.0);
    // Remove the triangles touching the north pole and the first ring: a hole of
    // radius sin(2π/24) ≈ 0.26 around +z.
    let open = TriMesh::new(
        m.vertices.clone(),
        m.triangles
            .iter()
            .copied()
            .filter(|t| t.iter().all(|&i| m.vertices[i as usize][2] < 0.97))
            .collect(),
    );
    assert!(open.triangles.len() < m.triangles.len());
    let f = MeshSdf::new(&open).unwrap();
    for p in [
        [0.0, 0.0, 0.0],
        [0.3, -0.2, -0.5],
        [0.0, 0.5, 0.4],
        [0.0, 0.0, 0.8],
    ] {
        assert!(f.eval(p) < 0.0, "inside {p:?}: {}", f.eval(p));
        assert!(f.winding_number(p) > 0.5);
    }
    for p in [[1.5, 0.0, 0.0], [0.0, 0.0, -1.4], [0.0, 0.0, 1.3]] {
        assert!(f.eval(p) > 0.0, "outside {p:?}: {}", f.eval(p));
    }
    let (closed, rep) = fill_holes(&open);
    assert_eq!(rep.filled, 1);
    assert_eq!(rep.open_edges, 0);
    let t = certmesh::metrics::analyze(&closed).unwrap();
    assert!(t.is_closed_oriented_manifold(), "{t:?}");
    assert_eq!(t.genus, vec![0]);
    let g = MeshSdf::new(&closed).unwrap();
    // Closed: the winding number is 1 inside, 0 outside (up to the far-field error of
    // a few percent at β = 2).
    for (p, want) in [
        ([0.0, 0.0, 0.9], 1.0),
        ([0.0, 0.0, 1.2], 0.0),
        ([0.1, 0.2, -0.3], 1.0),
    ] {
        let w = g.winding_number(p);
        assert!((w - want).abs() < 0.1, "{p:?}: {w}");
    }
    // Isolated vertices change nothing.
    let mut iso = closed.clone();
    iso.vertices.push([0.0, 0.0, 0.0]);
    iso.vertices.push([5.0, 5.0, 5.0]);
    let h = MeshSdf::new(&iso).unwrap();
    for p in [[0.1, 0.2, 0.3], [0.0, 3.0, 0.0]] {
        assert_eq!(h.eval(p), g.eval(p));
    }
    // A fill triangle turns the hole's rim into a surface: the distance on the axis
    // just above the cap is now to the fan, not to the rim.
    assert!(g.eval([0.0, 0.0, 1.05]) < f.eval([0.0, 0.0, 1.05]));
}

/// The hierarchical winding number agrees with the exact sum of solid angles.
#[test]
fn fast_winding_number_matches_exact() {
    let m = uv_sphere(20, 40, 1.0);
    let b = TriBvh::new(&m).unwrap();
    for k in 0..200 {
        let p = [0.31, 0.77, 0.53].map(|a: f64| 3.0 * ((k as f64 * a + 0.1) % 1.0) - 1.5);
        let (w, x) = (b.winding_number(p), b.winding_number_exact(p));
        // β = 2 with the order-2 expansion: a few percent (0.057 at the centre, where
        // every node is far field), always on the right side of 1/2.
        assert!((w - x).abs() < 0.1, "{p:?}: fast {w} exact {x}");
        assert_eq!(w > 0.5, x > 0.5, "{p:?}: fast {w} exact {x}");
        let want = if norm(p) < 0.95 {
            1.0
        } else if norm(p) > 1.05 {
            0.0
        } else {
            x
        };
        assert!((x - want).abs() < 1e-6, "{p:?}: exact {x}");
    }
}

/// The gradient is the finite-difference gradient of f, and has unit length.
#[test]
fn gradient_matches_finite_differences() {
    let m = uv_sphere(32, 64, 1.0);
    let f = MeshSdf::new(&m).unwrap();
    let h = 1e-6;
    for p in [
        [0.5, 0.1, -0.2],
        [1.3, 0.4, 0.2],
        [-0.2, -0.9, 0.7],
        [0.13, 0.41, -0.27],
    ] {
        let d = f.grad(p);
        assert_eq!(d.v, f.eval(p));
        assert!((norm(d.g) - 1.0).abs() < 1e-12);
        for k in 0..3 {
            let mut a = p;
            let mut b = p;
            a[k] += h;
            b[k] -= h;
            let fd = (f.eval(a) - f.eval(b)) / (2.0 * h);
            assert!(
                (fd - d.g[k]).abs() < 1e-5,
                "{p:?} axis {k}: {fd} vs {}",
                d.g[k]
            );
        }
        // One projection step lands on the mesh (distance ~ 0).
        let q = sub(p, scale(d.g, d.v / dot(d.g, d.g)));
        assert!(f.eval(q).abs() < 1e-12, "{p:?} -> {q:?}: {}", f.eval(q));
    }
    // Finite-difference Hessian: above the pole the closest point is the pole vertex,
    // so d = |p − pole| and its Hessian is (I − n nᵀ)/|p − pole| = diag(1, 1, 0) at
    // distance 1.
    let h = f.hessian([0.0, 0.0, 2.0]);
    assert!(
        (h.h[0] - 1.0).abs() < 1e-4 && (h.h[3] - 1.0).abs() < 1e-4,
        "{:?}",
        h.h
    );
    assert!(h.h[5].abs() < 1e-4 && h.h[1].abs() < 1e-4, "{:?}", h.h);
    assert!(!f.is_rigorous());
}

/// The Lipschitz enclosure contains sampled values and excludes 0 far from the mesh.
#[test]
fn interval_enclosure_contains_samples() {
    let m = uv_sphere(16, 32, 1.0);
    let f = MeshSdf::new(&m).unwrap();
    let iv =
        |lo: [f64; 3], hi: [f64; 3]| [0, 1, 2].map(|k| Interval::try_from((lo[k], hi[k])).unwrap());
    let b = iv([0.8, -0.3, -0.1], [1.4, 0.2, 0.3]);
    let e = f.eval_interval(&b);
    for k in 0..100 {
        let t = [0.3, 0.61, 0.83].map(|a: f64| (k as f64 * a) % 1.0);
        let p = [0.8 + 0.6 * t[0], -0.3 + 0.5 * t[1], -0.1 + 0.4 * t[2]];
        assert!(e.contains(f.eval(p)), "{p:?}: {} not in {e:?}", f.eval(p));
    }
    let far = f.eval_interval(&iv([3.0, 3.0, 3.0], [3.5, 3.2, 3.1]));
    assert!(far.inf() > 0.0, "{far:?}");
    let deep = f.eval_interval(&iv([-0.1, -0.1, -0.1], [0.1, 0.1, 0.1]));
    assert!(deep.sup() < 0.0, "{deep:?}");
    let g = f.grad_interval(&b);
    assert!(g.g.iter().all(|x| x.inf() >= -1.0 && x.sup() <= 1.0));
}

#[test]
fn bad_input_is_an_error_naming_the_problem() {
    let e = MeshSdf::new(&TriMesh::default()).unwrap_err().to_string();
    assert!(e.contains("at least one triangle"), "{e}");
    let bad_index = TriMesh::new(vec![[0.0; 3], [1.0, 0.0, 0.0]], vec![[0, 1, 7]]);
    let e = MeshSdf::new(&bad_index).unwrap_err().to_string();
    assert!(e.contains("triangle 0") && e.contains("vertex 7"), "{e}");
    let nan = TriMesh::new(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, f64::NAN, 0.0]],
        vec![[0, 1, 2]],
    );
    let e = MeshSdf::new(&nan).unwrap_err().to_string();
    assert!(e.contains("vertex 2"), "{e}");
    let flat = TriMesh::new(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
        vec![[0, 1, 2]],
    );
    let e = MeshSdf::new(&flat).unwrap_err().to_string();
    assert!(e.contains("zero area"), "{e}");
    let m = uv_sphere(4, 8, 1.0);
    let e = normalize_to_unit_cube(&m, 0.5).unwrap_err().to_string();
    assert!(e.contains("margin"), "{e}");
    let e =
        certmesh::implicit::sdf::from_file(std::path::Path::new("/nonexistent/x.obj"), 0.05, true)
            .err()
            .unwrap()
            .to_string();
    assert!(e.contains("/nonexistent/x.obj"), "{e}");
}

#[test]
fn normalisation_fits_the_unit_cube() {
    let mut m = uv_sphere(8, 16, 3.0);
    for v in &mut m.vertices {
        v[0] = 2.0 * v[0] + 10.0;
    }
    m.vertices.push([1e6, 1e6, 1e6]); // isolated: ignored
    let (n, s, _) = normalize_to_unit_cube(&m, 0.1).unwrap();
    assert!((s - 0.8 / 12.0).abs() < 1e-12);
    let used: Vec<[f64; 3]> = n
        .triangles
        .iter()
        .flatten()
        .map(|&i| n.vertices[i as usize])
        .collect();
    let lo = (0..3)
        .map(|k| used.iter().map(|v| v[k]).fold(f64::INFINITY, f64::min))
        .collect::<Vec<_>>();
    let hi = (0..3)
        .map(|k| used.iter().map(|v| v[k]).fold(f64::NEG_INFINITY, f64::max))
        .collect::<Vec<_>>();
    assert!(
        (lo[0] - 0.1).abs() < 1e-12 && (hi[0] - 0.9).abs() < 1e-12,
        "{lo:?} {hi:?}"
    );
    assert!((lo[1] + hi[1] - 1.0).abs() < 1e-12 && lo[1] > 0.1);
}

/// GradNormal on the signed distance of a sphere mesh gives a closed genus-0 surface
/// near the sphere, and reports no certificate.
#[test]
fn gradnormal_remeshes_a_mesh_sdf() {
    use certmesh::gradnormal::{GradNormal, GradNormalParams};
    use certmesh::mesher::{Mesher, NoProgress};
    let m = uv_sphere(32, 64, 1.0);
    let (n, _, _) = normalize_to_unit_cube(&m, 0.1).unwrap();
    let f = MeshSdf::new(&n).unwrap();
    let dom = certmesh::Aabb::new([0.0; 3], [1.0; 3]).unwrap();
    let out = GradNormal::new(GradNormalParams::new().with_scale(0.05))
        .mesh(&f, &dom, &NoProgress)
        .unwrap();
    let certmesh::mesher::Mesh::Surface(s) = &out.mesh else {
        panic!("surface expected")
    };
    let t = certmesh::metrics::analyze(s).unwrap();
    assert!(
        t.is_closed_oriented_manifold() && t.genus == vec![0],
        "{t:?}"
    );
    for v in &s.vertices {
        let r = norm(sub(*v, [0.5; 3]));
        assert!((r - 0.4).abs() < 2e-3, "vertex at radius {r}");
    }
    assert!(!out.certificate.is_certified());
}

proptest! {
    /// A closed tetrahedron's exact winding number is 1 inside and 0 outside.
    #[test]
    fn tetrahedron_winding_number(x in -1.0f64..1.0, y in -1.0f64..1.0, z in -1.0f64..1.0) {
        let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        // Outward orientation.
        let t = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        let b = TriBvh::new(&TriMesh::new(v, t)).unwrap();
        let w = b.winding_number_exact([x, y, z]);
        let margin = x.min(y).min(z).min(1.0 - x - y - z);
        if margin > 1e-6 {
            prop_assert!((w - 1.0).abs() < 1e-9, "{w}");
        } else if margin < -1e-6 {
            prop_assert!(w.abs() < 1e-9, "{w}");
        }
    }
}
