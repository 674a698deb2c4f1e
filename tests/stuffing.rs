//! Isosurface stuffing: conformity, Table 1 angle bounds, fidelity (Theorem 2),
//! topology, quadruple-zero options and double-sided meshing.
//!
//! Over 800 lines on purpose: the tests share the catalog fixtures and the exact
//! checks at the top of the file; they follow the paper's sections in order.
use certmesh::catalog;
use certmesh::implicit::Implicit;
use certmesh::mesh::{TetMesh, TriMesh};
use certmesh::mesher::options::{Crossing, MesherOptions};
use certmesh::mesher::{Mesh, Mesher, NoProgress};
use certmesh::stuffing::{
    check_conforming, quality, stuff, stuff_double_sided, Order, QuadZero, Seeding, Side, Stuffing,
    StuffingParams, TABLE1,
};
use std::collections::{HashMap, HashSet};

/// Private Euler-characteristic helper (the shared one lives in `metrics`):
/// V − E + F of a triangle mesh, counting only vertices used by triangles.
fn euler_characteristic_private(m: &TriMesh) -> i64 {
    let mut v = HashSet::new();
    let mut e = HashSet::new();
    for t in &m.triangles {
        for k in 0..3 {
            v.insert(t[k]);
            let (a, b) = (t[k], t[(k + 1) % 3]);
            e.insert((a.min(b), a.max(b)));
        }
    }
    v.len() as i64 - e.len() as i64 + m.triangles.len() as i64
}

/// Connected components of a triangle mesh (private helper).
fn components_private(m: &TriMesh) -> usize {
    let n = m.vertices.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut Vec<usize>, x: usize) -> usize {
        let mut r = x;
        while p[r] != r {
            r = p[r];
        }
        let mut y = x;
        while p[y] != r {
            let z = p[y];
            p[y] = r;
            y = z;
        }
        r
    }
    for t in &m.triangles {
        let a = find(&mut parent, t[0] as usize);
        for &o in &t[1..] {
            let b = find(&mut parent, o as usize);
            parent[b] = a;
        }
    }
    let used: HashSet<usize> = m.triangles.iter().flatten().map(|&i| i as usize).collect();
    used.into_iter()
        .map(|i| find(&mut parent, i))
        .collect::<HashSet<_>>()
        .len()
}

fn smooth_surfaces() -> Vec<catalog::Entry> {
    catalog::surfaces()
        .into_iter()
        .filter(|e| e.smooth)
        .collect()
}

/// Deterministic pseudo-random offsets (xorshift) so failures are reproducible.
fn offsets(seed: u64, n: usize) -> Vec<[f64; 3]> {
    let mut s = seed | 1;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n).map(|_| [next(), next(), next()]).collect()
}

fn check_bounds(name: &str, row: &certmesh::stuffing::Row, q: &quality::AngleSummary) {
    let b = row.bounds;
    let ctx = format!("{name} row {}: {q:?}", row.name);
    if let Some(x) = b.min_dihedral {
        assert!(q.min_dihedral_deg >= x, "min dihedral: {ctx}");
    }
    if let Some(x) = b.max_dihedral {
        assert!(q.max_dihedral_deg <= x, "max dihedral: {ctx}");
    }
    if let Some(x) = b.min_plane {
        assert!(q.min_plane_deg >= x, "min plane: {ctx}");
    }
    if let Some(x) = b.max_plane {
        assert!(q.max_plane_deg <= x, "max plane: {ctx}");
    }
    if let Some(x) = b.min_exposed {
        assert!(q.min_exposed_deg >= x, "min exposed: {ctx}");
    }
    if let Some(x) = b.max_exposed {
        assert!(q.max_exposed_deg <= x, "max exposed: {ctx}");
    }
}

#[test]
fn every_row_meets_its_table1_bounds_and_is_conforming() {
    let surfaces = smooth_surfaces();
    let mut runs = 0;
    for (ri, row) in TABLE1.iter().enumerate() {
        for (si, e) in surfaces.iter().enumerate() {
            let f = e.function();
            for (k, res) in [13usize, 22].into_iter().enumerate() {
                let off = offsets((ri * 100 + si * 10 + k) as u64 + 7, 1)[0];
                let p = StuffingParams::new()
                    .with_row(row.name)
                    .unwrap()
                    .with_resolution(res)
                    .with_offset(off);
                let s = stuff(&f, &e.domain, &p).unwrap();
                assert!(!s.clipped, "{} clipped", e.name);
                let b = s.mesh.boundary();
                let nonmanifold = check_conforming(&s.mesh, &b)
                    .unwrap_or_else(|m| panic!("{} row {} res {res}: {m}", e.name, row.name));
                // Surfaces whose features the lattice resolves give a 2-manifold boundary.
                if res == 22
                    && ["sphere", "ellipsoid", "torus", "blob", "superquadric"].contains(&e.name)
                {
                    assert_eq!(nonmanifold, 0, "{} row {}", e.name, row.name);
                }
                let q = quality::summarize(&s.mesh, &b);
                // The thin torus (tube radius 0.05) falls between lattice points at
                // these coarse resolutions; every other surface is resolved.
                assert!(q.tetrahedra > 0 || e.name == "thin-torus", "{}", e.name);
                check_bounds(e.name, row, &q);
                if row.safe || row.bounds.min_dihedral.is_some() {
                    assert_eq!(q.inverted, 0, "{} row {}", e.name, row.name);
                }
                runs += 1;
            }
        }
    }
    assert_eq!(runs, 13 * surfaces.len() * 2);
}

#[test]
fn boundary_vertices_lie_on_the_surface() {
    for name in ["sphere", "torus", "blob"] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        let p = StuffingParams::new().with_resolution(20);
        let s = stuff(&f, &e.domain, &p).unwrap();
        let b = s.mesh.boundary();
        // Bisection to full precision: |f| is at the level of f's variation over one
        // ulp of the edge parameter.
        let h = s.spacing;
        for v in &b.vertices {
            let g = f.grad(*v);
            let gn = (g.g[0].powi(2) + g.g[1].powi(2) + g.g[2].powi(2)).sqrt();
            assert!(
                g.v.abs() <= 1e-12 * (1.0 + gn * h),
                "{name}: f = {} at {v:?}",
                g.v
            );
        }
        // And the mesh really has a boundary everywhere on the surface.
        assert!(b.triangles.len() > 100);
    }
}

#[test]
fn linear_crossings_lose_the_surface_property() {
    let e = catalog::get("torus").unwrap();
    let f = e.function();
    let p = StuffingParams::new()
        .with_resolution(16)
        .with_crossing(Crossing::Linear);
    let s = stuff(&f, &e.domain, &p).unwrap();
    let b = s.mesh.boundary();
    let worst = b
        .vertices
        .iter()
        .map(|v| f.eval(*v).abs())
        .fold(0.0, f64::max);
    assert!(
        worst > 1e-6,
        "linear interpolation is not on the surface: {worst}"
    );
    check_conforming(&s.mesh, &b).unwrap();
}

/// Point-in-tetrahedral-mesh by barycentric tests (brute force over candidate tets).
fn inside_mesh(m: &TetMesh, grid: &HashMap<[i64; 3], Vec<usize>>, cell: f64, p: [f64; 3]) -> bool {
    let key = p.map(|x| (x / cell).floor() as i64);
    let Some(list) = grid.get(&key) else {
        return false;
    };
    list.iter().any(|&t| {
        let c = m.corners(t);
        let o = |a: [f64; 3], b: [f64; 3], cc: [f64; 3], d: [f64; 3]| {
            quality::orientation([a, b, cc, d])
        };
        o(p, c[1], c[2], c[3]) >= 0.0
            && o(c[0], p, c[2], c[3]) >= 0.0
            && o(c[0], c[1], p, c[3]) >= 0.0
            && o(c[0], c[1], c[2], p) >= 0.0
    })
}

fn tet_grid(m: &TetMesh, cell: f64) -> HashMap<[i64; 3], Vec<usize>> {
    let mut g: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for t in 0..m.tets.len() {
        let c = m.corners(t);
        let lo = [0, 1, 2]
            .map(|k| (c.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min) / cell).floor() as i64);
        let hi = [0, 1, 2].map(|k| {
            (c.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max) / cell).floor() as i64
        });
        for i in lo[0]..=hi[0] {
            for j in lo[1]..=hi[1] {
                for k in lo[2]..=hi[2] {
                    g.entry([i, j, k]).or_default().push(t);
                }
            }
        }
    }
    g
}

#[test]
fn theorem2_points_far_from_the_surface_are_classified_correctly() {
    // Distances to the sphere and torus are known in closed form.
    let dist = |name: &str, p: [f64; 3]| -> f64 {
        match name {
            "sphere" => ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0).abs(),
            _ => {
                let r = (p[0] * p[0] + p[1] * p[1]).sqrt() - 0.6;
                ((r * r + p[2] * p[2]).sqrt() - 0.25).abs()
            }
        }
    };
    for (name, rowname) in [
        ("sphere", "min-dihedral-unsafe"),
        ("torus", "min-exposed-safe-ordered"),
    ] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        let p = StuffingParams::new()
            .with_row(rowname)
            .unwrap()
            .with_resolution(18);
        let s = stuff(&f, &e.domain, &p).unwrap();
        let omega_c = p.row.omega() * s.spacing;
        let cell = s.spacing;
        let grid = tet_grid(&s.mesh, cell);
        let mut checked = 0;
        let mut state = 12345u64;
        for _ in 0..4000 {
            let mut r = || {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 11) as f64 / (1u64 << 53) as f64
            };
            let q = [0, 1, 2].map(|k| e.domain.min[k] + (e.domain.max[k] - e.domain.min[k]) * r());
            if dist(name, q) <= omega_c {
                continue;
            }
            checked += 1;
            let inside = f.eval(q) < 0.0;
            assert_eq!(
                inside_mesh(&s.mesh, &grid, cell, q),
                inside,
                "{name}: point {q:?}"
            );
        }
        assert!(checked > 1000);
    }
}

#[test]
fn boundary_has_catalog_topology_at_adequate_resolution() {
    for (name, res) in [
        ("sphere", 16),
        ("ellipsoid", 40),
        ("torus", 32),
        ("genus2", 48),
        ("two-spheres", 96),
        ("blob", 20),
    ] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        let p = StuffingParams::new()
            .with_row("min-dihedral-safe")
            .unwrap()
            .with_resolution(res);
        let s = stuff(&f, &e.domain, &p).unwrap();
        let b = s.mesh.boundary();
        assert_eq!(
            check_conforming(&s.mesh, &b),
            Ok(0),
            "{name}: manifold boundary"
        );
        assert_eq!(
            Some(euler_characteristic_private(&b)),
            e.euler_characteristic(),
            "{name}"
        );
        assert_eq!(
            components_private(&b),
            e.topology.unwrap().components,
            "{name}"
        );
    }
}

#[test]
fn parallel_serial_and_seeding_modes_agree() {
    let e = catalog::get("genus2").unwrap();
    let f = e.function();
    for order in [Order::Arbitrary, Order::Ordered] {
        let base = StuffingParams::new().with_resolution(20).with_order(order);
        let a = stuff(&f, &e.domain, &base.clone().with_parallel(true)).unwrap();
        let b = stuff(&f, &e.domain, &base.clone().with_parallel(false)).unwrap();
        let c = stuff(
            &f,
            &e.domain,
            &base.clone().with_seeding(Seeding::BoundingBox),
        )
        .unwrap();
        assert_eq!(a.mesh, b.mesh);
        assert_eq!(a.mesh.tets.len(), c.mesh.tets.len());
        assert!(c.lattice_points_evaluated > a.lattice_points_evaluated);
    }
}

#[test]
fn continuation_evaluates_only_near_the_domain() {
    // A small sphere in a big box: the box has ~2·65³ lattice points.
    let f = certmesh::Formula::surface("x^2 + y^2 + z^2 - 0.04").unwrap();
    let dom = certmesh::Aabb::cube(2.0);
    let p = StuffingParams::new().with_resolution(64);
    let s = stuff(&f, &dom, &p).unwrap();
    assert!(
        s.lattice_points_evaluated < 40_000,
        "{}",
        s.lattice_points_evaluated
    );
    assert!(s.mesh.tets.len() > 1000);
}

#[test]
fn warping_never_moves_both_ends_of_an_edge_toward_each_other() {
    use certmesh::stuffing::{prepare, warp};
    for name in ["tanglecube", "genus2"] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        for order in [Order::Arbitrary, Order::Ordered] {
            let p = StuffingParams::new().with_resolution(19).with_order(order);
            let mut fl = prepare(&f, &e.domain, &p).unwrap();
            let n = warp::warp(&mut fl, 0.28511, 0.39882, order, true);
            assert!(n > 50 && n == fl.warp_toward.len(), "{name}: {n}");
            for (&q, &o) in &fl.warp_toward {
                // §4.1: two vertices sharing an edge cannot both warp toward each other.
                assert_ne!(fl.warp_toward.get(&o), Some(&q), "{name} {order:?}");
                if order == Order::Ordered {
                    // Ordered warping: never along an edge whose other end also warps.
                    assert!(!fl.warp_toward.contains_key(&o), "{name}: {q} -> {o}");
                }
            }
        }
    }
}

#[test]
fn ordered_warping_meets_the_ordered_row_bounds() {
    // With ordered warping, the output is still conforming and within the ordered
    // row's bounds on a surface with many cut points.
    let e = catalog::get("tanglecube").unwrap();
    let f = e.function();
    let row = certmesh::stuffing::row("min-dihedral-safe-ordered").unwrap();
    for res in [17, 29] {
        let p = StuffingParams::new()
            .with_row(row.name)
            .unwrap()
            .with_resolution(res);
        let s = stuff(&f, &e.domain, &p).unwrap();
        assert!(s.warped > 0);
        let b = s.mesh.boundary();
        check_conforming(&s.mesh, &b).unwrap();
        check_bounds("tanglecube", row, &quality::summarize(&s.mesh, &b));
    }
}

#[test]
fn quadruple_zero_options() {
    // A coarse lattice on genus2 warps all four vertices of some BCC tetrahedra
    // (found by a probe over the catalog; 24 of them at resolution 10).
    let e = catalog::get("genus2").unwrap();
    let f = e.function();
    let dom = e.domain;
    let mut counts = HashMap::new();
    for q in [
        QuadZero::Discard,
        QuadZero::Heuristic,
        QuadZero::Keep,
        QuadZero::Report,
    ] {
        let p = StuffingParams::new()
            .with_row("min-dihedral-double")
            .unwrap()
            .with_resolution(10)
            .with_quadruple_zero(q);
        let s = stuff(&f, &dom, &p).unwrap();
        assert!(s.quadruple_zero_found > 0, "{q:?}");
        counts.insert(format!("{q:?}"), (s.mesh.tets.len(), s.quadruple_zero_kept));
        let b = s.mesh.boundary();
        check_conforming(&s.mesh, &b).unwrap();
        let qs = quality::summarize(&s.mesh, &b);
        assert_eq!(qs.inverted, 0);
    }
    assert_eq!(counts["Discard"].1, 0);
    assert_eq!(counts["Report"].1, 0);
    assert!(counts["Keep"].1 > 0);
    assert!(counts["Heuristic"].1 <= counts["Keep"].1);
    // The report option names the resolution problem in the certificate.
    let mut o = MesherOptions::default();
    o.resolution = Some(10);
    o.params = Some("min-dihedral-double".into());
    o.extra.insert("quadruple_zero".into(), "report".into());
    let out = Stuffing::from_options(&o)
        .unwrap()
        .mesh(&f, &dom, &NoProgress)
        .unwrap();
    match out.certificate {
        certmesh::Certificate::Uncertified { regions, .. } => {
            assert!(regions.iter().any(|r| r.reason.contains("quadruple-zero")))
        }
        c => panic!("{c:?}"),
    }
}

#[test]
fn double_sided_meshes_are_compatible() {
    let e = catalog::get("torus").unwrap();
    let f = e.function();
    let p = StuffingParams::new()
        .with_row("min-dihedral-double")
        .unwrap()
        .with_resolution(16);
    let (verts, tin, tout) = stuff_double_sided(&f, &e.domain, &p).unwrap();
    let ti = TetMesh {
        vertices: verts.clone(),
        tets: tin,
    };
    let to = TetMesh {
        vertices: verts,
        tets: tout,
    };
    let bi = ti.boundary();
    // Every boundary triangle of the inside mesh is a face of the outside mesh.
    let key = |mut t: [u32; 3]| {
        t.sort_unstable();
        t
    };
    let mut out_faces = HashSet::new();
    for t in &to.tets {
        for fc in [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]] {
            out_faces.insert(key(fc.map(|k| t[k])));
        }
    }
    // boundary() compacts vertices: map back by position.
    let pos: HashMap<[u64; 3], u32> = ti
        .vertices
        .iter()
        .enumerate()
        .map(|(i, v)| (v.map(f64::to_bits), i as u32))
        .collect();
    for t in &bi.triangles {
        let g = t.map(|i| pos[&bi.vertices[i as usize].map(f64::to_bits)]);
        assert!(
            out_faces.contains(&key(g)),
            "inside boundary triangle {g:?} not matched outside"
        );
    }
    // Together they are conforming and none is inverted.
    let mut all = ti.clone();
    all.tets.extend_from_slice(&to.tets);
    check_conforming(&all, &all.boundary()).unwrap();
    let q = quality::summarize(&all, &all.boundary());
    assert_eq!(q.inverted, 0);
    let row = certmesh::stuffing::row("min-dihedral-double").unwrap();
    assert!(q.min_dihedral_deg >= row.bounds.min_dihedral.unwrap());
    assert!(q.max_dihedral_deg <= row.bounds.max_dihedral.unwrap());
}

#[test]
fn outside_side_meshes_the_exterior() {
    let e = catalog::get("sphere").unwrap();
    let f = e.function();
    let p = StuffingParams::new()
        .with_resolution(12)
        .with_side(Side::Outside);
    let s = stuff(&f, &e.domain, &p).unwrap();
    let q = quality::summarize(&s.mesh, &s.mesh.boundary());
    assert_eq!(q.inverted, 0);
    // The exterior mesh contains points near the box corner and none at the centre.
    let vol: f64 = (0..s.mesh.tets.len())
        .map(|t| {
            let c = s.mesh.corners(t);
            let u = certmesh::kernel::geom::sub(c[1], c[0]);
            let v = certmesh::kernel::geom::sub(c[2], c[0]);
            let w = certmesh::kernel::geom::sub(c[3], c[0]);
            certmesh::kernel::geom::dot(certmesh::kernel::geom::cross(u, v), w) / 6.0
        })
        .sum();
    assert!(vol > 10.0, "exterior volume {vol}");
}

#[test]
fn mesher_interface_and_options() {
    let e = catalog::get("sphere").unwrap();
    let f = e.function();
    let mut o = MesherOptions::default();
    o.resolution = Some(12);
    o.params = Some("max-dihedral-safe".into());
    let m = Stuffing::from_options(&o).unwrap();
    assert_eq!(m.name(), "stuffing");
    let out = m.mesh(&f, &e.domain, &NoProgress).unwrap();
    for k in [
        "tetrahedra",
        "min_dihedral_deg",
        "max_dihedral_deg",
        "min_plane_deg",
        "max_plane_deg",
        "min_exposed_deg",
        "max_exposed_deg",
        "inverted",
    ] {
        assert!(out.stats.contains_key(k), "{k}");
    }
    assert!(!out.certificate.is_certified());
    assert!(out
        .certificate
        .reason()
        .unwrap()
        .contains("certified for this stencil table by `proofs stuffing`"));
    match &out.mesh {
        Mesh::Volume { tets, boundary } => {
            assert_eq!(out.stats["tetrahedra"], tets.tets.len());
            assert!(!boundary.triangles.is_empty());
        }
        _ => panic!("volume expected"),
    }
    // Too fine a lattice is a clear error, not an allocation failure.
    let mut huge = o.clone();
    huge.resolution = Some(2000);
    assert!(matches!(
        Stuffing::from_options(&huge)
            .unwrap()
            .mesh(&f, &e.domain, &NoProgress),
        Err(certmesh::Error::TooLarge(_))
    ));
    // The graded variant through the options.
    let mut og = o.clone();
    og.graded = true;
    og.resolution = Some(16);
    let out_g = Stuffing::from_options(&og)
        .unwrap()
        .mesh(&f, &e.domain, &NoProgress)
        .unwrap();
    assert!(out_g.stats["octants"].as_u64().unwrap() > 0);
    assert!(out_g.stats["graded"].as_bool().unwrap());
    // Bad options are errors naming the problem.
    let mut bad = o.clone();
    bad.params = Some("no-such-row".into());
    assert!(Stuffing::from_options(&bad)
        .unwrap_err()
        .to_string()
        .contains("no-such-row"));
    let mut bad = o.clone();
    bad.extra.insert("alpha_long".into(), "0.7".into());
    assert!(Stuffing::from_options(&bad).is_err());
    let mut bad = o.clone();
    bad.extra.insert("typo".into(), "1".into());
    assert!(Stuffing::from_options(&bad).is_err());
    // Explicit α values are accepted but claim no Table 1 bound.
    let mut ok = o.clone();
    ok.extra.insert("alpha_long".into(), "0.2".into());
    ok.extra.insert("alpha_short".into(), "0.3".into());
    let out = Stuffing::from_options(&ok)
        .unwrap()
        .mesh(&f, &e.domain, &NoProgress)
        .unwrap();
    assert!(out.certificate.reason().unwrap().contains("no Table 1"));
    // A NaN-valued function is an error, not a panic.
    let nan = certmesh::Formula::surface("sqrt(x) + y^2 + z^2 - 1").unwrap();
    let mut obox = o.clone();
    obox.extra.insert("seeding".into(), "box".into());
    let r = Stuffing::from_options(&obox)
        .unwrap()
        .mesh(&nan, &e.domain, &NoProgress);
    assert!(matches!(r, Err(certmesh::Error::NotFinite(_))), "{r:?}");
}

#[test]
fn reproduce_quick_writes_tables_and_histograms() {
    let dir = std::env::temp_dir().join(format!("certmesh-stuffing-{}", std::process::id()));
    certmesh::reproduce::stuffing_report::reproduce(&dir, true).unwrap();
    let md = std::fs::read_to_string(dir.join("README.md")).unwrap();
    for r in TABLE1.iter() {
        assert!(md.contains(r.name), "{}", r.name);
    }
    assert!(md.contains("within the guaranteed bounds: **yes**"));
    assert!(!md.contains("VIOLATED"));
    for f in ["hist-sphere.svg", "hist-sphere.png", "hist-torus.svg"] {
        assert!(std::fs::metadata(dir.join(f)).unwrap().len() > 1000, "{f}");
    }
    let svg = std::fs::read_to_string(dir.join("hist-sphere.svg")).unwrap();
    assert!(svg.contains("<rect"));
    std::fs::remove_dir_all(&dir).ok();
}

/// Regenerates `papers/stuffing/` (slow; run with `--ignored`).
#[test]
#[ignore]
fn reproduce_papers_stuffing() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/stuffing");
    certmesh::reproduce::stuffing_report::reproduce(&dir, false).unwrap();
}

#[test]
fn histogram_bins_are_two_degrees() {
    let b = certmesh::reproduce::stuffing_report::bins_2deg(&[
        0.5, 1.9, 2.0, 59.99, 60.0, 179.9, 180.0,
    ]);
    assert_eq!(b[0], 2);
    assert_eq!(b[1], 1);
    assert_eq!(b[29], 1);
    assert_eq!(b[30], 1);
    assert_eq!(b[89], 2);
    assert_eq!(b.iter().sum::<u64>(), 7);
}

fn check_bounds_with(ctx: &str, b: certmesh::stuffing::params::Bounds, q: &quality::AngleSummary) {
    let ok = |lo: Option<f64>, x: f64| lo.is_none_or(|l| x >= l);
    let okh = |hi: Option<f64>, x: f64| hi.is_none_or(|h| x <= h);
    assert!(
        ok(b.min_dihedral, q.min_dihedral_deg),
        "min dihedral {ctx} {q:?}"
    );
    assert!(
        okh(b.max_dihedral, q.max_dihedral_deg),
        "max dihedral {ctx} {q:?}"
    );
    assert!(ok(b.min_plane, q.min_plane_deg), "min plane {ctx} {q:?}");
    assert!(okh(b.max_plane, q.max_plane_deg), "max plane {ctx} {q:?}");
    assert!(
        ok(b.min_exposed, q.min_exposed_deg),
        "min exposed {ctx} {q:?}"
    );
    assert!(
        okh(b.max_exposed, q.max_exposed_deg),
        "max exposed {ctx} {q:?}"
    );
}

#[test]
fn graded_meshes_conform_and_meet_the_bounds() {
    use certmesh::stuffing::graded::stuff_graded;
    // Unordered and ordered rows, incl. the daggered min-exposed-unsafe row with its
    // weaker graded bound 158.1918°. (The other dagger, 147.0470° of
    // min-exposed-safe-ordered, does not hold: see
    // `graded_dagger_147_is_exceeded_on_a_half_pyramid`.)
    let rows = [
        "max-dihedral-unsafe",
        "min-dihedral-unsafe",
        "max-dihedral-safe",
        "min-exposed-unsafe",
        "max-exposed-safe",
        "min-dihedral-double",
        "min-dihedral-safe-ordered",
        "max-exposed-safe-ordered",
    ];
    for (k, (name, res)) in [("sphere", 20usize), ("torus", 28), ("blob", 20)]
        .into_iter()
        .enumerate()
    {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        for (ri, rn) in rows.iter().enumerate() {
            let row = certmesh::stuffing::row(rn).unwrap();
            let off = offsets((k * 10 + ri) as u64 + 99, 1)[0];
            let p = StuffingParams::new()
                .with_row(row.name)
                .unwrap()
                .with_resolution(res)
                .with_offset(off);
            let (g, st) = stuff_graded(&f, &e.domain, &p).unwrap();
            let b = g.mesh.boundary();
            assert_eq!(check_conforming(&g.mesh, &b), Ok(0), "{name} {}", row.name);
            assert_eq!(
                Some(euler_characteristic_private(&b)),
                e.euler_characteristic(),
                "{name}"
            );
            let q = quality::summarize(&g.mesh, &b);
            assert_eq!(q.inverted, 0, "{name}");
            check_bounds_with(
                &format!("{name} {} {st:?}", row.name),
                row.graded_bounds(),
                &q,
            );
            // Grading pays: fewer tetrahedra than the uniform mesh, same surface.
            let u = stuff(&f, &e.domain, &p).unwrap();
            assert!(
                g.mesh.tets.len() < u.mesh.tets.len(),
                "{name}: {} vs {}",
                g.mesh.tets.len(),
                u.mesh.tets.len()
            );
            assert!(st.background.iter().all(|&c| c > 0), "{st:?}");
            let ub = u.mesh.boundary();
            assert_eq!(
                ub.triangles.len(),
                b.triangles.len(),
                "{name}: same surface triangles"
            );
        }
    }
}

#[test]
fn f_is_evaluated_once_per_lattice_point() {
    // With linear cut points the only point evaluations are the lattice values.
    let e = catalog::get("torus").unwrap();
    let f = e.function();
    for seeding in [Seeding::Continuation, Seeding::BoundingBox] {
        let counted = certmesh::implicit::Counted::new(&f);
        let p = StuffingParams::new()
            .with_resolution(20)
            .with_crossing(Crossing::Linear)
            .with_seeding(seeding);
        let s = stuff(&counted, &e.domain, &p).unwrap();
        assert_eq!(
            counted.counts().points,
            s.lattice_points_evaluated as u64,
            "{seeding:?}"
        );
        assert!(s.mesh.tets.len() > 1000);
    }
}

/// Graded bounds (§5) for every Table 1 row on the catalog at several resolutions and
/// random lattice offsets (slow: `cargo test --release --test stuffing -- --ignored`).
/// The only bound ever exceeded is the daggered 147.0470° of min-exposed-safe-ordered
/// (see `graded_dagger_147_is_exceeded_on_a_half_pyramid`); everything else holds.
#[test]
#[ignore = "graded scan over all rows: ~7 minutes in release"]
fn graded_scan_all_rows() {
    use certmesh::stuffing::graded::stuff_graded;
    let mut exceeded = Vec::new();
    for name in ["sphere", "torus", "genus2", "genus5", "blob", "tanglecube"] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        for row in certmesh::stuffing::TABLE1.iter() {
            for res in [14usize, 21, 30] {
                for off in offsets(res as u64 * 7 + name.len() as u64, 4) {
                    let p = StuffingParams::new()
                        .with_row(row.name)
                        .unwrap()
                        .with_resolution(res)
                        .with_offset(off);
                    let (g, _) = stuff_graded(&f, &e.domain, &p).unwrap();
                    let b = g.mesh.boundary();
                    assert_eq!(check_conforming(&g.mesh, &b), Ok(0), "{name} {}", row.name);
                    let q = quality::summarize(&g.mesh, &b);
                    assert_eq!(q.inverted, 0, "{name} {}", row.name);
                    let mut gb = row.graded_bounds();
                    if row.name == "min-exposed-safe-ordered" && q.max_plane_deg > 147.047 {
                        exceeded.push((name, res, off, q.max_plane_deg));
                        gb.max_plane = None;
                    }
                    check_bounds_with(&format!("{name} {} res {res} {off:?}", row.name), gb, &q);
                }
            }
        }
    }
    eprintln!("dagger 147.0470 exceeded in: {exceeded:?}");
}

/// Finding (papers/stuffing/README.md): the graded dagger bound 147.0470° on the largest
/// plane angle (row min-exposed-safe-ordered, α_short = 0.5, §5) does not hold. In a
/// half-pyramid (apex: the centre of a fine cube whose face borders a coarse octant), both
/// ends of the base's blue diagonal can warp *away* from the apex along red edges into the
/// neighbouring fine cubes — the rules of §3.2 and §5 allow it (ordered warping only forbids
/// warping toward a vertex that also warps; the asterisk rule of §5 only forbids all three
/// vertices of the red-red-blue triangle warping) — and the red-red-blue triangle's angle at
/// the unwarped apex opens beyond 147.0470°. Witness: genus5 at 21 cubes, offset below.
#[test]
fn graded_dagger_147_is_exceeded_on_a_half_pyramid() {
    use certmesh::kernel::geom::angle_deg;
    use certmesh::stuffing::graded::stuff_graded;
    let e = catalog::get("genus5").unwrap();
    let f = e.function();
    let row = certmesh::stuffing::row("min-exposed-safe-ordered").unwrap();
    let p = StuffingParams::new()
        .with_row(row.name)
        .unwrap()
        .with_resolution(21)
        .with_offset([3.17e-7, 0.70842, 0.013406]);
    let (g, _) = stuff_graded(&f, &e.domain, &p).unwrap();
    let b = g.mesh.boundary();
    assert_eq!(check_conforming(&g.mesh, &b), Ok(0));
    let q = quality::summarize(&g.mesh, &b);
    assert_eq!(q.inverted, 0);
    // Every other graded bound holds; only the daggered max plane angle is exceeded.
    let mut gb = row.graded_bounds();
    assert_eq!(gb.max_plane, Some(147.0470));
    gb.max_plane = None;
    check_bounds_with("witness", gb, &q);
    assert!(q.max_plane_deg > 150.0, "{q:?}");

    // Locate the offending triangle and check it is the red-red-blue triangle of a
    // half-pyramid: the apex an unwarped cube centre, the two others warped corners.
    let h = p.spacing(&e.domain).unwrap();
    let lat = certmesh::stuffing::Field::lattice(&e.domain, h, p.offset).unwrap();
    let grid = |v: [f64; 3]| [0, 1, 2].map(|k| (v[k] - lat.origin[k]) / h);
    let mut found = false;
    for t in 0..g.mesh.tets.len() {
        let c = g.mesh.corners(t);
        for i in 0..4 {
            for j in 0..4 {
                for k in (j + 1)..4 {
                    if i == j || i == k || angle_deg(c[j], c[i], c[k]) <= 150.0 {
                        continue;
                    }
                    // Apex: a lattice point, a cube centre (half-integer grid coordinates).
                    let a = grid(c[i]);
                    assert!(
                        a.iter().all(|x| (x - x.floor() - 0.5).abs() < 1e-9),
                        "{a:?}"
                    );
                    assert!(f.eval(c[i]).abs() > 1e-6, "apex not warped");
                    for v in [c[j], c[k]] {
                        // Warped: on the surface, off the lattice, and on a red edge from
                        // a cube corner adjacent to the apex's cube (distance √3/2 h from
                        // the apex before warping).
                        assert!(f.eval(v).abs() < 1e-9);
                        let gv = grid(v);
                        let corner = gv.map(|x| (x + 0.0).round());
                        let d2: f64 = (0..3).map(|m| (corner[m] - a[m]).powi(2)).sum();
                        assert!((d2 - 0.75).abs() < 1e-9, "{gv:?} from {a:?}");
                    }
                    found = true;
                }
            }
        }
    }
    assert!(found);
    // Independent closed form: apex at the origin, base corners (½,−½,−½) and (½,½,½)
    // (the blue diagonal of the face x = ½), each warped by α_short = ½ of its red edge
    // away from the apex's cube, toward the neighbouring centres (0,−1,−1) and (0,1,1).
    // The supremum of the apex angle is arccos(−17/19) ≈ 153.4746° > 147.0470°.
    let w = |c: [f64; 3], to: [f64; 3]| [0, 1, 2].map(|m| c[m] + 0.5 * (to[m] - c[m]));
    let ang = angle_deg(
        w([0.5, -0.5, -0.5], [0.0, -1.0, -1.0]),
        [0.0; 3],
        w([0.5, 0.5, 0.5], [0.0, 1.0, 1.0]),
    );
    assert!((ang - (-17.0f64 / 19.0).acos().to_degrees()).abs() < 1e-9);
    assert!(ang > q.max_plane_deg && q.max_plane_deg > 147.0470);
}
