//! The incremental 3D Delaunay kernel (`certmesh::kernel::delaunay`): against brute
//! force on small sets, on degenerate inputs (integer grids, spheres, duplicates), on
//! refinement-style insertion, and at scale.
use certmesh::kernel::delaunay::predicates::{insphere_sos, orient3d};
use certmesh::kernel::delaunay::{
    build_report, random_points, Delaunay, InsertError, ReportOptions, Sampler,
};
use proptest::prelude::*;
use std::collections::BTreeSet;

type Tet = [u32; 4];

fn sorted(mut t: Tet) -> Tet {
    t.sort_unstable();
    t
}

fn cell_set(t: &Delaunay) -> BTreeSet<Tet> {
    t.cells().map(|c| sorted(t.cell_vertices(c))).collect()
}

/// Cells as sets of coordinates (bit patterns), to compare triangulations whose
/// vertex ids differ.
fn coord_cells(t: &Delaunay) -> BTreeSet<[[u64; 3]; 4]> {
    t.cells()
        .map(|c| {
            let mut v = t.cell_vertices(c).map(|v| t.point(v).map(f64::to_bits));
            v.sort_unstable();
            v
        })
        .collect()
}

/// All 4-sets of the triangulation's inserted vertices whose (perturbed) circumsphere
/// is empty: the Delaunay tetrahedra of the perturbed point set.
fn brute_force(t: &Delaunay) -> BTreeSet<Tet> {
    let ids: Vec<u32> = (0..t.points().len() as u32)
        .filter(|&v| t.is_inserted(v))
        .collect();
    let p = |v: u32| t.point(v);
    let mut out = BTreeSet::new();
    let n = ids.len();
    for a in 0..n {
        for b in a + 1..n {
            for c in b + 1..n {
                for d in c + 1..n {
                    let mut q = [ids[a], ids[b], ids[c], ids[d]];
                    let o = orient3d(p(q[0]), p(q[1]), p(q[2]), p(q[3]));
                    if o == 0.0 {
                        continue;
                    }
                    if o < 0.0 {
                        q.swap(0, 1);
                    }
                    let empty = ids
                        .iter()
                        .filter(|e| !q.contains(e))
                        .all(|&e| insphere_sos(p(q[0]), p(q[1]), p(q[2]), p(q[3]), p(e)) < 0);
                    if empty {
                        out.insert(sorted(q));
                    }
                }
            }
        }
    }
    out
}

fn assert_valid(t: &Delaunay) {
    let r = t.check();
    assert!(r.valid, "{r:?}");
}

/// Six times the signed volume (exact for small integer coordinates).
fn volume6(t: &Delaunay, c: u32) -> f64 {
    let p = t.cell_vertices(c).map(|v| t.point(v));
    let d: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|k| p[i + 1][k] - p[0][k]));
    d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
        - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
        + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Random float points (general position): the triangulation equals the brute-force
    /// set of empty-circumsphere tetrahedra, and cells of input points only are
    /// Delaunay by the plain (unperturbed, independent) exact predicate.
    #[test]
    fn matches_brute_force_random(
        pts in prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), 0..22),
        seed in any::<u64>(),
    ) {
        let (t, bulk) = Delaunay::from_points(&pts, seed).unwrap();
        prop_assert!(bulk.duplicates.is_empty());
        assert_valid(&t);
        prop_assert_eq!(cell_set(&t), brute_force(&t));
        for c in t.finite_cells() {
            let q = t.cell_vertices(c).map(|v| t.point(v));
            for (i, &e) in pts.iter().enumerate() {
                if t.cell_vertices(c).contains(&t.vertex_of_input(i)) {
                    continue;
                }
                prop_assert!(certmesh::kernel::predicates::insphere(q[0], q[1], q[2], q[3], e) < 0.0);
            }
        }
    }

    /// Integer points with massive ties and duplicates: still the brute-force
    /// (perturbed) Delaunay triangulation, whatever the seed, duplicates reported.
    #[test]
    fn matches_brute_force_integer_ties(
        pts in prop::collection::vec(prop::array::uniform3(0i32..3), 0..22),
        seed in any::<u64>(),
    ) {
        let pts: Vec<[f64; 3]> = pts.into_iter().map(|p| p.map(f64::from)).collect();
        let (t, bulk) = Delaunay::from_points(&pts, seed).unwrap();
        assert_valid(&t);
        let distinct: BTreeSet<[u64; 3]> = pts.iter().map(|p| p.map(f64::to_bits)).collect();
        prop_assert_eq!(bulk.duplicates.len(), pts.len() - distinct.len());
        for &(i, j) in &bulk.duplicates {
            // reported against the first occurrence, which is the inserted one
            prop_assert!(j < i && pts[i] == pts[j]);
            prop_assert!(pts[..j].iter().all(|q| *q != pts[j]));
            prop_assert!(t.is_inserted(t.vertex_of_input(j)) && !t.is_inserted(t.vertex_of_input(i)));
        }
        prop_assert_eq!(cell_set(&t), brute_force(&t));
        let (t2, _) = Delaunay::from_points(&pts, seed ^ 0xdead_beef).unwrap();
        prop_assert_eq!(coord_cells(&t), coord_cells(&t2));
    }
}

/// The 5×5×5 integer grid: every 4 points of a unit cube are cospherical and many are
/// coplanar. Valid, every point inserted, the finite cells tile the hull [0,4]³
/// (volume 64, no flat cell), and the result does not depend on the insertion order.
#[test]
fn grid_5x5x5() {
    let mut pts = Vec::new();
    for x in 0..5 {
        for y in 0..5 {
            for z in 0..5 {
                pts.push([x as f64, y as f64, z as f64]);
            }
        }
    }
    let (t, bulk) = Delaunay::from_points(&pts, 7).unwrap();
    assert!(bulk.duplicates.is_empty());
    let r = t.check();
    assert!(r.valid, "{r:?}");
    assert_eq!(r.vertices_in_cells, 125 + 8);
    let vol6: f64 = t.finite_cells().map(|c| volume6(&t, c)).sum();
    assert_eq!(vol6, 6.0 * 64.0);
    assert!(t.finite_cells().all(|c| volume6(&t, c) > 0.0));
    let mut rev = pts.clone();
    rev.reverse();
    let (t2, _) = Delaunay::from_points(&rev, 99).unwrap();
    assert_eq!(coord_cells(&t), coord_cells(&t2));
    // One at a time, in input order, gives the same triangulation.
    let mut t3 = Delaunay::with_domain([0.0; 3], [4.0; 3], 3).unwrap();
    for &p in &pts {
        t3.insert(p).unwrap();
    }
    assert_valid(&t3);
    let far_box_differs = t3.lo != t.lo;
    assert!(!far_box_differs);
    assert_eq!(coord_cells(&t), coord_cells(&t3));
}

/// Points on a sphere: every in-sphere test is nearly degenerate. Also exactly
/// cospherical points (a cube's corners and octahedron on the same sphere).
#[test]
fn sphere_points() {
    let pts = random_points(5000, Sampler::Sphere, 11);
    let (t, bulk) = Delaunay::from_points(&pts, 1).unwrap();
    assert!(bulk.duplicates.is_empty());
    let r = t.check();
    assert!(r.valid, "{r:?}");
    assert_eq!(r.vertices_in_cells, 5000 + 8);
    let mut exact = vec![];
    for s in [-1.0, 1.0] {
        for k in 0..3 {
            let mut p = [0.0; 3];
            p[k] = s * 2.0;
            exact.push(p);
        }
    }
    // 2·(±1,±1,±1)/√3 is not representable; use points with integer coordinates on
    // the sphere of radius 3: (±1,±2,±2) and permutations, (±3,0,0)...
    exact.clear();
    for a in [-1.0f64, 1.0] {
        for b in [-2.0f64, 2.0] {
            for c in [-2.0f64, 2.0] {
                exact.push([a, b, c]);
                exact.push([b, a, c]);
                exact.push([b, c, a]);
            }
        }
    }
    for s in [-3.0, 3.0] {
        exact.push([s, 0.0, 0.0]);
        exact.push([0.0, s, 0.0]);
        exact.push([0.0, 0.0, s]);
    }
    exact.push([0.0; 3]);
    let (t, _) = Delaunay::from_points(&exact, 5).unwrap();
    assert_valid(&t);
    assert_eq!(cell_set(&t), brute_force(&t));
    let torus = random_points(3000, Sampler::Torus, 2);
    let (t, _) = Delaunay::from_points(&torus, 5).unwrap();
    assert_valid(&t);
}

#[test]
fn duplicates_are_reported_not_inserted() {
    let mut pts = random_points(500, Sampler::Uniform, 4);
    pts.push(pts[10]);
    pts.push(pts[3]);
    pts.push(pts[10]);
    let rep = build_report(&pts, ReportOptions::default()).unwrap().1;
    assert_eq!(rep.duplicates, vec![500, 501, 502]);
    assert_eq!(rep.n_inserted, 500);
    assert_eq!(rep.valid, Some(true));
    let (mut t, _) = Delaunay::from_points(&pts[..500], 4).unwrap();
    let v42 = t.vertex_of_input(42);
    assert_eq!(t.point(v42), pts[42]);
    assert_eq!(t.input_index(v42), Some(42));
    assert_eq!(t.insert(pts[42]), Err(InsertError::Duplicate(v42)));
    let c = t.incident_cell(v42).unwrap();
    assert_eq!(
        t.insert_in_conflict_with(pts[42], c),
        Err(InsertError::Duplicate(v42))
    );
    assert_eq!(t.insert([0.0, f64::NAN, 0.0]), Err(InsertError::NonFinite));
    assert_eq!(t.insert([1e9, 0.0, 0.0]), Err(InsertError::OutsideDomain));
    assert_valid(&t);
    assert_eq!(t.check().vertices_in_cells, 508);
}

#[test]
fn non_finite_input_is_an_error_naming_the_point() {
    let mut pts = random_points(10, Sampler::Uniform, 4);
    pts[7][2] = f64::INFINITY;
    let e = Delaunay::from_points(&pts, 0).unwrap_err().to_string();
    assert!(e.contains("point 7"), "{e}");
    pts[7][2] = f64::NAN;
    assert!(build_report(&pts, ReportOptions::default()).is_err());
}

/// Refinement-style insertion: circumcentres of cells, inserted from that cell (no
/// walk), and from a wrong hint (fallback to the walk).
#[test]
fn insert_in_conflict_with_circumcentres() {
    let pts = random_points(2000, Sampler::Sphere, 8);
    let (mut t, _) = Delaunay::from_points(&pts, 2).unwrap();
    let mut inserted = 0;
    let mut k = 0u32;
    while inserted < 600 {
        k = k.wrapping_mul(1_103_515_245).wrapping_add(12345);
        let c = k % t.cell_capacity() as u32;
        if !t.is_live(c) || t.is_far_cell(c) {
            continue;
        }
        let z = t.circumcentre(c);
        if z.iter().any(|x| x.abs() > 1.5) {
            continue;
        }
        let hint = if inserted % 3 == 0 {
            t.cells().next().unwrap()
        } else {
            c
        };
        let v = t.insert_in_conflict_with(z, hint).unwrap();
        assert_eq!(t.point(v), z);
        inserted += 1;
    }
    assert_valid(&t);
    assert_eq!(t.check().vertices_in_cells, 2000 + 8 + 600);
}

#[test]
fn accessors_facets_and_vtk() {
    let pts = random_points(300, Sampler::Torus, 3);
    let (t, _) = Delaunay::from_points(&pts, 2).unwrap();
    let cells = t.num_cells();
    let all: Vec<_> = t.facets(false).collect();
    // 2·interior facets + 12 hull facets = 4·cells.
    assert_eq!(2 * all.len() + 12, 4 * cells);
    for &(c, i, d, j) in &all {
        assert_eq!(t.neighbor(c, i), Some((d, j)));
        assert_eq!(t.neighbor(d, j), Some((c, i)));
    }
    for (c, i, _, _) in t.facets(true) {
        assert!((0..4)
            .filter(|&k| k != i)
            .all(|k| !t.is_far(t.cell_vertices(c)[k])));
    }
    // Circumcentre is equidistant from the 4 vertices.
    for c in t.finite_cells().take(100) {
        let z = t.circumcentre(c);
        let d: Vec<f64> = t
            .cell_vertices(c)
            .iter()
            .map(|&v| {
                (0..3)
                    .map(|k| (t.point(v)[k] - z[k]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .collect();
        assert!(d.iter().all(|x| (x - d[0]).abs() <= 1e-6 * d[0]), "{d:?}");
    }
    let mut buf = Vec::new();
    certmesh::kernel::delaunay::write_vtk(&mut buf, &t).unwrap();
    let back = certmesh::io::vtk::parse(&buf).unwrap();
    assert_eq!(back.tets.len(), t.finite_cells().count());
    assert_eq!(back.vertices, pts);
}

#[test]
fn hundred_thousand_random_points() {
    let pts = random_points(100_000, Sampler::Uniform, 1);
    let (t, rep) = build_report(
        &pts,
        ReportOptions {
            seed: 3,
            check: true,
        },
    )
    .unwrap();
    let r = rep.check.clone().unwrap();
    assert!(r.valid, "{r:?}");
    assert_eq!(r.vertices_in_cells, 100_008);
    assert_eq!(rep.n_inserted, 100_000);
    // Random points: about 6.7 tetrahedra per point.
    assert!(
        (6.0..7.5).contains(&(t.num_cells() as f64 / 1e5)),
        "{}",
        t.num_cells()
    );
    // The estimate made before any work bounds the heap the triangulation holds.
    assert!(
        t.memory_bytes() as u64 <= Delaunay::estimated_bytes(pts.len()),
        "{} bytes",
        t.memory_bytes()
    );
    let json = serde_json::to_string(&rep).unwrap();
    assert!(json.contains("\"points_per_second\""));
}

#[test]
fn empty_and_tiny_inputs() {
    for n in 0..6 {
        let pts = random_points(n, Sampler::Uniform, n as u64);
        let (t, _) = Delaunay::from_points(&pts, 1).unwrap();
        assert_valid(&t);
    }
    let (t, b) = Delaunay::from_points(&[[1.0, 2.0, 3.0]; 4], 1).unwrap();
    assert_eq!(b.duplicates.len(), 3);
    assert_valid(&t);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// Scaling the input by a power of two inside the exact range
    /// ([`certmesh::kernel::delaunay::in_exact_range`]) changes no cell: every
    /// coordinate, the far box and the insertion order scale exactly, and the predicates
    /// are exact there, so their signs cannot change.
    #[test]
    fn power_of_two_scaling_keeps_every_cell(
        pts in prop::collection::vec(prop::array::uniform3(-1024i32..1024), 5..30),
        k in -120i32..100,
        seed in any::<u64>(),
    ) {
        let base: Vec<[f64; 3]> = pts.iter().map(|p| p.map(|x| x as f64 / 1024.0)).collect();
        let s = 2f64.powi(k);
        let scaled: Vec<[f64; 3]> = base.iter().map(|p| p.map(|x| x * s)).collect();
        let (a, _) = Delaunay::from_points(&base, seed).unwrap();
        let (b, _) = Delaunay::from_points(&scaled, seed).unwrap();
        assert_valid(&b);
        prop_assert_eq!(cell_set(&a), cell_set(&b));
    }
}

/// Coordinates outside the exact range are refused with an error naming the point (they
/// used to panic in the walk at 1e-150, or give an invalid triangulation at 1e-170:
/// found by an adversarial run); a box there is refused; an insertion there is refused
/// and leaves the triangulation as it was.
#[test]
fn coordinates_outside_the_exact_range_are_refused() {
    // The origin, the points 1 along each axis and (1, 1, 1), times s.
    let corners = |s: f64| {
        vec![
            [0.0; 3],
            [s, 0.0, 0.0],
            [0.0, s, 0.0],
            [0.0, 0.0, s],
            [s; 3],
        ]
    };
    for s in [1e-60, 1e-150, 1e-170, 1e-320, 1e60] {
        let e = Delaunay::from_points(&corners(s), 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("point 1") && e.contains("rescale"), "{s}: {e}");
        assert!(Delaunay::with_domain([-s; 3], [s; 3], 1).is_err(), "{s}");
    }
    let (t, _) = Delaunay::from_points(&corners(1e-40), 1).unwrap();
    assert_valid(&t);
    let (mut t, _) = Delaunay::from_points(&random_points(20, Sampler::Uniform, 3), 1).unwrap();
    let before = cell_set(&t);
    assert!(matches!(
        t.insert([1e-60, 0.1, 0.1]),
        Err(InsertError::OutOfRange)
    ));
    assert_eq!(cell_set(&t), before);
    assert_valid(&t);
}
