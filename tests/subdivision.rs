//! Plantinga–Vegter and Snyder on the catalog: certificates and topology.
use certmesh::catalog;
use certmesh::mesh::{Curve2, TriMesh};
use certmesh::mesher::{Mesh, MeshOutput, Mesher, NoProgress};
use certmesh::plantinga_vegter::{PlantingaVegter, PlantingaVegter2};
use certmesh::Implicit;
use std::collections::HashMap;

/// Private stand-in for the shared metrics module: the components of a closed curve
/// (every vertex of degree 2), or None if the polyline set is not closed.
fn curve_components(c: &Curve2) -> Option<usize> {
    let mut deg = vec![0usize; c.vertices.len()];
    for s in &c.segments {
        deg[s[0] as usize] += 1;
        deg[s[1] as usize] += 1;
        if s[0] == s[1] {
            return None;
        }
    }
    if deg.iter().any(|&d| d != 2 && d != 0) {
        return None;
    }
    let p = c.polylines();
    if p.iter().any(|(_, closed)| !closed) {
        return None;
    }
    Some(p.len())
}

/// Private stand-in for the shared metrics: for a closed oriented 2-manifold triangle mesh,
/// the sorted genus of each component; None if not closed, not manifold or not oriented.
fn surface_genera(m: &TriMesh) -> Option<Vec<usize>> {
    let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
    for t in &m.triangles {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            if a == b {
                return None;
            }
            *edges.entry((a, b)).or_insert(0) += 1;
        }
    }
    for (&(a, b), &n) in &edges {
        if n != 1 || edges.get(&(b, a)) != Some(&1) {
            return None;
        }
    }
    // Union-find on vertices.
    let n = m.vertices.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut Vec<usize>, x: usize) -> usize {
        let mut r = x;
        while p[r] != r {
            r = p[r];
        }
        let mut y = x;
        while p[y] != r {
            let nx = p[y];
            p[y] = r;
            y = nx;
        }
        r
    }
    for t in &m.triangles {
        let a = find(&mut parent, t[0] as usize);
        for &v in &t[1..] {
            let b = find(&mut parent, v as usize);
            parent[b] = a;
        }
    }
    let mut chi: HashMap<usize, i64> = HashMap::new();
    let mut used = vec![false; n];
    for t in &m.triangles {
        let r = find(&mut parent, t[0] as usize);
        *chi.entry(r).or_insert(0) += 1; // F
        for &v in t {
            used[v as usize] = true;
        }
    }
    for v in 0..n {
        if used[v] {
            let r = find(&mut parent, v);
            *chi.entry(r).or_insert(0) += 1; // V
        }
    }
    for &(a, b) in edges.keys() {
        if a < b {
            let r = find(&mut parent, a as usize);
            *chi.entry(r).or_insert(0) -= 1; // E
        }
    }
    let mut g: Vec<usize> = chi
        .values()
        .map(|&c| {
            if c > 2 || (2 - c) % 2 != 0 {
                usize::MAX
            } else {
                ((2 - c) / 2) as usize
            }
        })
        .collect();
    if g.contains(&usize::MAX) {
        return None;
    }
    g.sort_unstable();
    Some(g)
}

/// Fraction of triangles whose normal agrees with ∇f at the centroid (orientation check).
fn outward_fraction(f: &dyn Implicit, m: &TriMesh) -> f64 {
    let mut good = 0;
    for t in 0..m.triangles.len() {
        let [a, b, c] = m.corners(t);
        let n = certmesh::geom::cross(certmesh::geom::sub(b, a), certmesh::geom::sub(c, a));
        let cen = [0, 1, 2].map(|k| (a[k] + b[k] + c[k]) / 3.0);
        if certmesh::geom::dot(n, f.grad(cen).g) > 0.0 {
            good += 1;
        }
    }
    good as f64 / m.triangles.len().max(1) as f64
}

fn check_topology(name: &str, out: &MeshOutput, f: &dyn Implicit) {
    let e = catalog::get(name).unwrap();
    let t = e.topology.unwrap();
    match &out.mesh {
        Mesh::Curve(c) => {
            assert_eq!(
                curve_components(c),
                Some(t.components),
                "{name}: components"
            );
        }
        Mesh::Surface(m) => {
            let mut want: Vec<usize> = t.genus.to_vec();
            want.sort_unstable();
            assert_eq!(surface_genera(m), Some(want), "{name}: genera");
            let frac = outward_fraction(f, m);
            assert!(
                frac > 0.9,
                "{name}: only {frac} of normals point toward f > 0"
            );
        }
        _ => panic!("unexpected mesh kind"),
    }
}

#[test]
fn pv_curves_certified_with_catalog_topology() {
    for e in catalog::curves().into_iter().filter(|e| e.smooth) {
        let f = e.function();
        let out = PlantingaVegter2::default()
            .mesh(&f, &e.domain, &NoProgress)
            .unwrap();
        assert!(
            out.certificate.is_certified(),
            "{}: {:?}",
            e.name,
            out.certificate.reason()
        );
        check_topology(e.name, &out, &f);
    }
}

#[test]
fn pv_surfaces_certified_with_catalog_topology() {
    for e in catalog::surfaces().into_iter().filter(|e| e.smooth) {
        let f = e.function();
        let out = PlantingaVegter::default()
            .mesh(&f, &e.domain, &NoProgress)
            .unwrap();
        eprintln!("{}: {:?}", e.name, out.stats.get("leaves"));
        assert!(
            out.certificate.is_certified(),
            "{}: {:?}",
            e.name,
            out.certificate.reason()
        );
        check_topology(e.name, &out, &f);
    }
}

use certmesh::snyder::{Snyder, Snyder2, SnyderParams};

#[test]
fn snyder_curves_certified_with_catalog_topology() {
    for e in catalog::curves().into_iter().filter(|e| e.smooth) {
        let f = e.function();
        let out = Snyder2::default().mesh(&f, &e.domain, &NoProgress).unwrap();
        eprintln!(
            "snyder {}: {:?} {:?}",
            e.name,
            out.stats.get("leaves"),
            out.certificate.reason()
        );
        if out.certificate.is_certified() {
            check_topology(e.name, &out, &f);
        }
    }
}

#[test]
fn snyder_surfaces_generic_position() {
    for e in catalog::surfaces().into_iter().filter(|e| e.smooth) {
        let f = e.function();
        let t0 = std::time::Instant::now();
        let p = SnyderParams::new(3)
            .with_max_depth(7)
            .with_generic_shift(true);
        let out = Snyder::new(p).mesh(&f, &e.domain, &NoProgress).unwrap();
        eprintln!(
            "snyder {}: {:?} {:?} {:?}",
            e.name,
            out.stats.get("leaves"),
            out.certificate.reason(),
            t0.elapsed()
        );
        if out.certificate.is_certified() {
            check_topology(e.name, &out, &f);
        }
    }
}

#[test]
fn snyder_paraboloid_needs_generic_shift() {
    let e = catalog::get("paraboloid-cap").unwrap();
    let f = e.function();
    let p = SnyderParams::new(3).with_max_depth(8);
    let plain = Snyder::new(p.clone())
        .mesh(&f, &e.domain, &NoProgress)
        .unwrap();
    assert!(!plain.certificate.is_certified());
    let shifted = Snyder::new(p.with_generic_shift(true))
        .mesh(&f, &e.domain, &NoProgress)
        .unwrap();
    eprintln!(
        "{:?} / {:?}",
        plain.certificate.reason(),
        shifted.certificate.reason()
    );
    if let certmesh::Certificate::Uncertified { regions, .. } = &shifted.certificate {
        for r in regions.iter().take(30) {
            eprintln!("{:?} {:?} {}", r.region.min, r.region.size(), r.reason);
        }
    }
    assert!(
        shifted.certificate.is_certified(),
        "{:?}",
        shifted.certificate.reason()
    );
    check_topology("paraboloid-cap", &shifted, &f);
}

fn uncertified_regions(out: &MeshOutput) -> Vec<certmesh::mesher::Uncertified> {
    match &out.certificate {
        certmesh::Certificate::Uncertified { regions, .. } => regions.clone(),
        _ => Vec::new(),
    }
}

#[test]
fn singular_entries_reported_near_the_singular_point() {
    for (name, mesher) in [
        (
            "double-cone",
            Box::new(PlantingaVegter::new(
                certmesh::plantinga_vegter::PvParams::new(3).with_max_depth(8),
            )) as Box<dyn Mesher>,
        ),
        (
            "double-cone",
            Box::new(Snyder::new(SnyderParams::new(3).with_max_depth(7))),
        ),
        ("lemniscate", Box::new(PlantingaVegter2::default())),
        ("lemniscate", Box::new(Snyder2::default())),
    ] {
        let e = catalog::get(name).unwrap();
        let f = e.function();
        let out = mesher.mesh(&f, &e.domain, &NoProgress).unwrap();
        assert!(
            !out.certificate.is_certified(),
            "{name} must not be certified"
        );
        let regions = uncertified_regions(&out);
        let singular: Vec<_> = regions
            .iter()
            .filter(|r| r.reason.contains("singular"))
            .collect();
        assert!(
            !singular.is_empty(),
            "{name}: no region names a singular point"
        );
        for r in singular {
            // Every box suspected of a singular point lies near the node at the origin.
            let d = certmesh::geom::norm(r.region.center());
            assert!(
                d < 0.1,
                "{name}: singular box at distance {d} from the node"
            );
        }
        // The boxes containing the origin are among the reported ones.
        assert!(regions
            .iter()
            .any(|r| r.region.inflate(1e-12).contains([0.0; 3])));
    }
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let e = catalog::get("sphere").unwrap();
    let f = e.function();
    // A 3D function given to the 2D mesher.
    assert!(PlantingaVegter2::default()
        .mesh(&f, &e.domain, &NoProgress)
        .is_err());
    // A flat domain.
    let flat = certmesh::Aabb {
        min: [0.0; 3],
        max: [1.0, 1.0, 0.0],
    };
    assert!(PlantingaVegter::default()
        .mesh(&f, &flat, &NoProgress)
        .is_err());
    // Options out of range.
    let o = certmesh::MesherOptions {
        max_depth: Some(40),
        ..Default::default()
    };
    assert!(PlantingaVegter::from_options(&o).is_err());
    let mut o = certmesh::MesherOptions::default();
    o.extra.insert("max_angel".into(), "45".into());
    assert!(PlantingaVegter::from_options(&o).is_err());
}

mod props {
    use super::*;
    use certmesh::Formula;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]
        #[test]
        fn pv_random_ellipse(a in 0.2f64..1.0, b in 0.2f64..1.0, cx in -0.3f64..0.3, cy in -0.3f64..0.3,
                             ox in -0.2f64..0.2, oy in -0.2f64..0.2) {
            let f = Formula::curve(&format!("(x - ({cx}))^2/{a}^2 + (y - ({cy}))^2/{b}^2 - 1")).unwrap();
            let dom = certmesh::Aabb::rect([-1.5 + ox, -1.5 + oy], [1.5 + ox, 1.4 + oy]);
            for m in [&PlantingaVegter2::default() as &dyn Mesher, &Snyder2::default()] {
                let out = m.mesh(&f, &dom, &NoProgress).unwrap();
                prop_assert!(out.certificate.is_certified());
                if let Mesh::Curve(c) = &out.mesh {
                    prop_assert_eq!(curve_components(c), Some(1));
                }
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 6, ..ProptestConfig::default() })]
        #[test]
        fn pv_random_ellipsoid(a in 0.3f64..1.0, b in 0.3f64..1.0, c in 0.3f64..1.0,
                               cx in -0.2f64..0.2, o in -0.2f64..0.2) {
            let f = Formula::surface(&format!("(x - ({cx}))^2/{a}^2 + y^2/{b}^2 + z^2/{c}^2 - 1")).unwrap();
            let dom = certmesh::Aabb { min: [-1.3 + o, -1.25, -1.2 - o], max: [1.3 + o, 1.2, 1.25] };
            let out = PlantingaVegter::new(certmesh::plantinga_vegter::PvParams::new(3).with_min_depth(1))
                .mesh(&f, &dom, &NoProgress).unwrap();
            prop_assert!(out.certificate.is_certified());
            if let Mesh::Surface(m) = &out.mesh {
                prop_assert_eq!(surface_genera(m), Some(vec![0]));
                prop_assert!(outward_fraction(&f, m) > 0.9);
            }
        }
    }
}
