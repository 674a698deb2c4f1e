//! Plantinga–Vegter and Snyder on the catalog: certificates and topology.
use certmesh::catalog;
use certmesh::mesh::{Curve2, TriMesh};
use certmesh::mesher::{Mesh, MeshOutput, Mesher, NoProgress};
use certmesh::subdivision::plantinga_vegter::{PlantingaVegter, PlantingaVegter2};
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
        let n = certmesh::kernel::geom::cross(
            certmesh::kernel::geom::sub(b, a),
            certmesh::kernel::geom::sub(c, a),
        );
        let cen = [0, 1, 2].map(|k| (a[k] + b[k] + c[k]) / 3.0);
        if certmesh::kernel::geom::dot(n, f.grad(cen).g) > 0.0 {
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

use certmesh::subdivision::snyder::{Snyder, Snyder2, SnyderParams};

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
            .with_max_depth(14)
            .with_generic_shift(true);
        let out = Snyder::new(p).mesh(&f, &e.domain, &NoProgress).unwrap();
        eprintln!(
            "snyder {}: {:?} {:?} {:?}",
            e.name,
            out.stats.get("leaves"),
            out.certificate.reason(),
            t0.elapsed()
        );
        // In generic position every smooth catalog surface certifies (finding 2 of
        // papers/meshing-of-surfaces/README.md).
        assert!(
            out.certificate.is_certified(),
            "{}: {:?}",
            e.name,
            out.certificate.reason()
        );
        check_topology(e.name, &out, &f);
        // The claim is about the domain, not the rotated box the grid meshed.
        for c in out.certificate.claims_typed() {
            if let certmesh::mesher::Claim::Isotopic { inside, .. } = c {
                assert_eq!(inside, &e.domain, "{}", e.name);
            }
        }
        assert!(out.certificate.proves_topology(), "{}", e.name);
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
                certmesh::subdivision::plantinga_vegter::PvParams::new(3).with_max_depth(8),
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
            let d = certmesh::kernel::geom::norm(r.region.center());
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
        // The ellipse lies strictly inside the domain (x from cx - a ≥ -1.2 to
        // cx + a ≤ 1.2 against -1.5 + ox ≤ -1.4 and 1.5 + ox ≥ 1.4; y from cy - b ≥ -1.15
        // to cy + b ≤ 1.15 against -1.5 + oy ≤ -1.4 and 1.4 + oy ≥ 1.3), so it is one
        // closed curve. An earlier range (b up to 1, cy and oy up to ±0.3 and ±0.2) let
        // it leave the top of the domain (b = 0.979, cy = 0.294, oy = -0.183: y up to
        // 1.273 > 1.217), and the certified output was then an open arc.
        fn pv_random_ellipse(a in 0.2f64..0.95, b in 0.2f64..0.9, cx in -0.25f64..0.25, cy in -0.25f64..0.25,
                             ox in -0.1f64..0.1, oy in -0.1f64..0.1) {
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
        // The ellipsoid lies strictly inside the domain (x from cx - a ≥ -1.15 to
        // cx + a ≤ 1.15, the domain from -1.3 + o ≤ -1.2 to 1.3 + o ≥ 1.2): a surface
        // that leaves the domain must not be certified (tests/soundness.rs), and an
        // earlier range here (a up to 1, o up to 0.2) let it poke out at x = -1.13.
        fn pv_random_ellipsoid(a in 0.3f64..0.95, b in 0.3f64..1.0, c in 0.3f64..1.0,
                               cx in -0.2f64..0.2, o in -0.1f64..0.1) {
            let f = Formula::surface(&format!("(x - ({cx}))^2/{a}^2 + y^2/{b}^2 + z^2/{c}^2 - 1")).unwrap();
            let dom = certmesh::Aabb { min: [-1.3 + o, -1.25, -1.2 - o], max: [1.3 + o, 1.2, 1.25] };
            let out = PlantingaVegter::new(certmesh::subdivision::plantinga_vegter::PvParams::new(3).with_min_depth(1))
                .mesh(&f, &dom, &NoProgress).unwrap();
            prop_assert!(out.certificate.is_certified());
            if let Mesh::Surface(m) = &out.mesh {
                prop_assert_eq!(surface_genera(m), Some(vec![0]));
                prop_assert!(outward_fraction(&f, m) > 0.9);
            }
            // Snyder, plain and in generic position: where it certifies, the topology
            // is right (termination is not guaranteed, §1.2.3, so no certificate is
            // demanded of it here).
            for shift in [false, true] {
                let p = SnyderParams::new(3).with_max_depth(9).with_generic_shift(shift);
                let out = Snyder::new(p).mesh(&f, &dom, &NoProgress).unwrap();
                if out.certificate.is_certified() {
                    if let Mesh::Surface(m) = &out.mesh {
                        prop_assert_eq!(surface_genera(m), Some(vec![0]), "shift {}", shift);
                        prop_assert!(outward_fraction(&f, m) > 0.9);
                    }
                }
            }
        }
    }
}

/// The reproduction of papers/meshing-of-surfaces/ in quick mode (the full run is
/// `certmesh reproduce meshing-of-surfaces`): the files are written and the computed
/// tables say what the paper folder claims.
#[test]
fn reproduce_quick_mode() {
    use certmesh::reproduce::meshing_of_surfaces::reproduce_report;
    let dir = std::env::temp_dir().join(format!("certmesh-mos-{}", std::process::id()));
    let rep = reproduce_report(&dir, true).unwrap();
    for f in [
        "subdivision-tables.md",
        "report.json",
        "fig-boxes-per-depth.svg",
        "fig-boxes-per-depth.png",
        "fig-pv-protrusion.svg",
        "fig-snyder-protrusion.png",
    ] {
        let p = dir.join(f);
        assert!(
            std::fs::metadata(&p).is_ok_and(|m| m.len() > 0),
            "{f} not written"
        );
    }
    // PV certifies every smooth curve and surface of the run with the catalog topology.
    for c in &rep.curves {
        if c.expected != "singular" {
            assert!(c.pv_certified && c.pv_found.ok == Some(true), "{c:?}");
        } else {
            assert!(!c.pv_certified && !c.snyder_certified, "{c:?}");
        }
    }
    for s in &rep.surfaces {
        if s.expected != "singular" {
            assert!(s.pv_certified && s.pv_found.ok == Some(true), "{s:?}");
        } else {
            assert!(!s.pv_certified, "{s:?}");
        }
        // Boxes per depth add up to the boxes of the run, and level 0 is the root.
        assert_eq!(s.pv_boxes_by_depth.values().sum::<u64>(), s.pv_boxes);
        assert_eq!(s.pv_boxes_by_depth.get(&0), Some(&1));
    }
    // Fig 1.5: marching squares splits the protrusion on some grid; PV does not.
    assert!(rep
        .fig15
        .iter()
        .any(|r| r.method == "marching squares" && r.found.ok == Some(false)));
    assert!(rep
        .fig15
        .iter()
        .filter(|r| r.method.starts_with("PV"))
        .all(|r| r.certified && r.found.ok == Some(true)));
    // The paraboloid both ways: uncertified on the plain grid, certified when shifted.
    let para: Vec<_> = rep
        .cases
        .iter()
        .filter(|c| c.entry == "paraboloid-cap")
        .collect();
    assert_eq!(para.len(), 2);
    assert!(!para[0].certified && para[0].uncertified_regions > 0);
    assert!(para[1].certified && para[1].found.ok == Some(true));
    for c in rep.cases.iter().filter(|c| c.entry != "paraboloid-cap") {
        assert!(!c.certified && c.singular_regions > 0, "{c:?}");
    }
    // Side-by-side: at 27³ the grid points straddle the 0.02 gap of two-spheres
    // symmetrically (x = ±1.2/27 both inside a sphere), so marching cubes merges them;
    // PV is right and certified.
    let mc27 = rep
        .side_by_side
        .iter()
        .find(|r| r.surface == "two-spheres" && r.method == "mc" && r.grid == Some(27))
        .unwrap();
    assert!(!mc27.correct() && !mc27.certified);
    for r in rep
        .side_by_side
        .iter()
        .filter(|r| r.method.starts_with("pv"))
    {
        assert!(r.correct() && r.certified, "{r:?}");
        assert!(r.evaluations.interval_gradients > 0);
    }
    assert!(std::fs::metadata(dir.join("fig-slice-two-spheres-mc27.png")).is_ok());
    let md = std::fs::read_to_string(dir.join("subdivision-tables.md")).unwrap();
    assert!(md.contains("## 5. The difference a certificate makes, in 3D"));
    let _ = std::fs::remove_dir_all(&dir);
}

mod primitives {
    use certmesh::subdivision::{
        cos_lower_bound, enclose, AngleBound, GenericMotion, IntervalIsolation,
    };
    use certmesh::{Formula, Implicit};
    use inari::Interval;
    use proptest::prelude::*;
    use std::sync::atomic::AtomicU64;

    fn iv(a: f64, b: f64) -> Interval {
        Interval::try_from((a.min(b), a.max(b))).unwrap()
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
        /// The mean-value ∩ natural enclosure contains f at every point of the box.
        #[test]
        fn enclose_contains_values(x0 in -2.0f64..2.0, y0 in -2.0f64..2.0, z0 in -2.0f64..2.0,
                                   w in 0.0f64..1.0, t in proptest::array::uniform3(0.0f64..1.0)) {
            let f = Formula::surface("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8 + x*y*z").unwrap();
            let b = [iv(x0, x0 + w), iv(y0, y0 + 0.5 * w), iv(z0, z0 + 0.25 * w)];
            let (v, g) = enclose(&f, &b);
            let p = [x0 + t[0] * w, y0 + t[1] * 0.5 * w, z0 + t[2] * 0.25 * w];
            prop_assert!(v.contains(f.eval(p)));
            let gp = f.grad(p).g;
            for k in 0..3 {
                prop_assert!(g[k].contains(gp[k]));
            }
        }

        /// Both angle bounds are lower bounds of the cosine of any two vectors in the box,
        /// and the sharp one is never worse than the crude one.
        #[test]
        fn angle_bounds_are_sound(lo in proptest::array::uniform3(-1.0f64..3.0),
                                  wid in proptest::array::uniform3(0.0f64..1.0),
                                  s in proptest::array::uniform3(0.0f64..1.0),
                                  t in proptest::array::uniform3(0.0f64..1.0)) {
            let g = [0, 1, 2].map(|k| iv(lo[k], lo[k] + wid[k]));
            let u = [0, 1, 2].map(|k| lo[k] + s[k] * wid[k]);
            let v = [0, 1, 2].map(|k| lo[k] + t[k] * wid[k]);
            let nu = certmesh::kernel::geom::norm(u);
            let nv = certmesh::kernel::geom::norm(v);
            prop_assume!(nu > 1e-9 && nv > 1e-9);
            let cos = certmesh::kernel::geom::dot(u, v) / (nu * nv);
            let crude = cos_lower_bound(&g, 3, AngleBound::Crude);
            let sharp = cos_lower_bound(&g, 3, AngleBound::Sharp);
            if let Some(c) = crude {
                prop_assert!(c <= cos + 1e-12);
                prop_assert!(sharp.is_some_and(|s| s + 1e-12 >= c));
            }
            if let Some(c) = sharp {
                prop_assert!(c <= cos + 1e-12);
            }
        }

        /// Root isolation finds exactly the roots of a polynomial with known simple roots
        /// on the segment, each located within the tolerance.
        #[test]
        fn isolation_counts_roots(r in proptest::collection::vec(-0.95f64..0.95, 1..5)) {
            let mut rs = r.clone();
            rs.sort_by(|a, b| a.partial_cmp(b).unwrap());
            prop_assume!(rs.windows(2).all(|w| w[1] - w[0] > 1e-3));
            let text = rs.iter().map(|a| format!("(x - ({a}))")).collect::<Vec<_>>().join("*");
            let f = Formula::curve(&text).unwrap();
            let iso = IntervalIsolation { max_depth: 40, tol: 1e-12 };
            let (pa, pb) = ([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
            let steps = AtomicU64::new(0);
            let pieces = iso.isolate(&f, pa, f.eval(pa) >= 0.0, pb, f.eval(pb) >= 0.0, &steps).unwrap();
            prop_assert_eq!(pieces.len(), rs.len());
            for ((t0, t1, _), a) in pieces.iter().zip(&rs) {
                let (x0, x1) = (-1.0 + 2.0 * t0, -1.0 + 2.0 * t1);
                prop_assert!(x0 <= *a && *a <= x1);
            }
        }
    }

    /// A double root touching from below (grazing: f + ε has two roots there) is never
    /// isolated; touching from above is provably no root of f + ε (sign⁺ convention).
    #[test]
    fn isolation_fails_on_a_grazing_root() {
        let iso = IntervalIsolation {
            max_depth: 30,
            tol: 1e-12,
        };
        let steps = AtomicU64::new(0);
        let below = Formula::curve("0 - (x - 0.3)^2").unwrap();
        assert!(iso
            .isolate(
                &below,
                [-1.0, 0.0, 0.0],
                false,
                [1.0, 0.0, 0.0],
                false,
                &steps
            )
            .is_none());
        let above = Formula::curve("(x - 0.3)^2").unwrap();
        assert_eq!(
            iso.isolate(
                &above,
                [-1.0, 0.0, 0.0],
                true,
                [1.0, 0.0, 0.0],
                true,
                &steps
            ),
            Some(vec![])
        );
    }

    /// The generic motion's meshed box covers the domain, and the motion is rigid.
    #[test]
    fn generic_motion_covers_the_domain() {
        let d = certmesh::Aabb::cube(2.0);
        let m = GenericMotion::new(&d, 3);
        let back = m.map_box(&m.domain);
        for k in 0..3 {
            assert!(back.min[k] <= d.min[k] && back.max[k] >= d.max[k]);
        }
        let (p, q) = ([0.1, 0.2, 0.3], [-0.4, 0.5, 0.9]);
        let d0 = certmesh::kernel::geom::dist(p, q);
        let d1 = certmesh::kernel::geom::dist(m.map(p), m.map(q));
        assert!((d0 - d1).abs() < 1e-12);
        // The domain centre is not a grid point of any level up to 20 of the moved box.
        let c = [0, 1, 2].map(|k| {
            let r = &m.rot;
            // Rᵀ(0 - t)
            -(r[0][k] * m.shift[0] + r[1][k] * m.shift[1] + r[2][k] * m.shift[2])
        });
        for k in 0..3 {
            let t = (c[k] - m.domain.min[k]) / (m.domain.max[k] - m.domain.min[k])
                * (1u64 << 20) as f64;
            assert!((t - t.round()).abs() > 1e-6);
        }
    }
}

/// Curve segments run counter-clockwise around the solid {f <= 0} (f < 0 on the left).
#[test]
fn curve_orientation_is_ccw_around_the_solid() {
    let e = catalog::get("cassini-2").unwrap();
    let f = e.function();
    for m in [
        &PlantingaVegter2::default() as &dyn Mesher,
        &Snyder2::default(),
    ] {
        let out = m.mesh(&f, &e.domain, &NoProgress).unwrap();
        let Mesh::Curve(c) = &out.mesh else {
            panic!("not a curve")
        };
        // Each segment's left normal points to f < 0.
        let mut good = 0;
        for s in &c.segments {
            let (a, b) = (c.vertices[s[0] as usize], c.vertices[s[1] as usize]);
            let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, 0.0];
            let left = [-(b[1] - a[1]), b[0] - a[0], 0.0];
            if certmesh::kernel::geom::dot(left, f.grad(mid).g) < 0.0 {
                good += 1;
            }
        }
        assert_eq!(good, c.segments.len(), "{}", m.name());
    }
}

/// The section of a certified sphere mesh by z = 0 is one closed curve near the unit
/// circle; the section of marching cubes' 27³ two-spheres mesh is one merged curve, PV's
/// two (the slice figures of papers/meshing-of-surfaces/).
#[test]
fn slices_of_meshes() {
    use certmesh::marching::MarchingCubes;
    use certmesh::reproduce::meshing_of_surfaces::slice;
    let e = catalog::get("sphere").unwrap();
    let f = e.function();
    let out = PlantingaVegter::default()
        .mesh(&f, &e.domain, &NoProgress)
        .unwrap();
    let c = slice(out.mesh.surface().unwrap(), 0.0);
    assert_eq!(curve_components(&c), Some(1));
    for v in &c.vertices {
        let r = (v[0] * v[0] + v[1] * v[1]).sqrt();
        assert!((r - 1.0).abs() < 0.05, "slice vertex at radius {r}");
    }
    let e = catalog::get("two-spheres").unwrap();
    let f = e.function();
    let mc = MarchingCubes::new()
        .resolution(27)
        .mesh(&f, &e.domain, &NoProgress)
        .unwrap();
    let pv = PlantingaVegter::default()
        .mesh(&f, &e.domain, &NoProgress)
        .unwrap();
    assert_eq!(
        curve_components(&slice(mc.mesh.surface().unwrap(), 0.0)),
        Some(1)
    );
    assert_eq!(
        curve_components(&slice(pv.mesh.surface().unwrap(), 0.0)),
        Some(2)
    );
}

/// The `stats` map is the typed `SubdivisionStats` serialised field by field: it reads
/// back as the struct, and its counts agree with each other and with the mesh.
#[test]
fn subdivision_stats_read_back_as_the_typed_struct() {
    use certmesh::subdivision::SubdivisionStats;
    let mut runs: Vec<(&str, MeshOutput)> = Vec::new();
    let torus = catalog::get("torus").unwrap();
    let t = torus.function();
    runs.push((
        "pv torus",
        PlantingaVegter::default()
            .mesh(&t, &torus.domain, &NoProgress)
            .unwrap(),
    ));
    runs.push((
        "snyder torus",
        Snyder::default()
            .mesh(&t, &torus.domain, &NoProgress)
            .unwrap(),
    ));
    let lem = catalog::get("lemniscate").unwrap();
    let l = lem.function();
    runs.push((
        "pv lemniscate",
        PlantingaVegter2::default()
            .mesh(&l, &lem.domain, &NoProgress)
            .unwrap(),
    ));
    for (name, out) in runs {
        let s: SubdivisionStats =
            serde_json::from_value(serde_json::Value::Object(out.stats.clone()))
                .unwrap_or_else(|e| panic!("{name}: stats do not read back: {e}"));
        assert_eq!(s.boxes, s.leaves + s.internal_boxes, "{name}");
        assert_eq!(
            s.leaves_by_depth.values().sum::<usize>(),
            s.leaves,
            "{name}"
        );
        assert_eq!(
            s.leaves_by_criterion.values().sum::<usize>(),
            s.leaves,
            "{name}"
        );
        assert_eq!(s.boxes_by_depth.values().sum::<usize>(), s.boxes, "{name}");
        assert!(s.uncertified_regions >= s.uncertified_boxes, "{name}");
        assert_eq!(
            out.certificate.is_certified(),
            s.uncertified_regions == 0 && s.refinement_complete,
            "{name}: certified iff nothing is left undecided"
        );
    }
}

// ---- The budget reserves the assembly's time and memory. ----

use certmesh::subdivision::{
    subdivide, Budget, Decision, Grid, Verdict, ASSEMBLY_BYTES_PER_ACTIVE_LEAF,
    ASSEMBLY_BYTES_PER_BOX, ASSEMBLY_SECONDS_PER_ACTIVE_LEAF, MEMORY_LIMIT_REASON,
    TIME_LIMIT_REASON,
};

fn split_everything_grid() -> Grid {
    Grid {
        domain: certmesh::Aabb {
            min: [-1.0; 3],
            max: [1.0; 3],
        },
        dim: 3,
        depth: 9,
    }
}

/// The leaves the budget stopped with `reason`.
fn failed_by(t: &certmesh::subdivision::Tree, reason: &'static str) -> usize {
    t.leaves
        .iter()
        .filter(|l| l.verdict == Verdict::Failed(reason))
        .count()
}

/// Boxes that are split to the depth limit everywhere (a criterion that never holds, as
/// on a singular surface): the leaves are all failed, all to be assembled.
fn split_all(_: &Grid, _: certmesh::subdivision::Cell) -> Decision {
    Decision::Split("test: never decided")
}

/// The deadline reserves the assembly's time: a 0.5 s limit stops the subdivision once
/// the leaves made so far would take 0.5 s to assemble, whatever the clock says (the
/// full tree has 8⁹ = 134 M leaves; a run that ignored the reservation would make
/// millions in 0.5 s on this machine and spend a minute assembling them).
#[test]
fn the_deadline_reserves_the_assembly_time() {
    let budget = Budget::new(u64::MAX, Some(0.5));
    let t = subdivide(split_everything_grid(), 0, 9, &budget, &split_all);
    assert!(!t.refinement_complete);
    let stopped = failed_by(&t, TIME_LIMIT_REASON);
    let tested = t.leaves.len() - stopped;
    assert!(stopped > 0);
    // Leaves made before the stop: at most what 0.5 s of assembly covers, plus the
    // 1024 boxes between two checks on each thread.
    let most = (0.5 / ASSEMBLY_SECONDS_PER_ACTIVE_LEAF) as usize + 4096;
    assert!(tested <= most, "{tested} leaves tested, at most {most}");
}

/// The memory cap stops the subdivision with its own reason, and the leaves made are
/// within the cap by the same estimate.
#[test]
fn the_memory_cap_stops_the_subdivision_and_says_so() {
    let cap = 64 << 20;
    let budget = Budget::new(u64::MAX, None).with_max_bytes(cap);
    let t = subdivide(split_everything_grid(), 0, 9, &budget, &split_all);
    assert!(!t.refinement_complete);
    let stopped = failed_by(&t, MEMORY_LIMIT_REASON);
    assert!(stopped > 0);
    let boxes = (t.leaves.len() + t.internal.len()) as u64;
    let tested = (t.leaves.len() - stopped) as u64;
    let estimate = tested * ASSEMBLY_BYTES_PER_ACTIVE_LEAF + boxes * ASSEMBLY_BYTES_PER_BOX;
    assert!(
        estimate <= cap + 4096 * (ASSEMBLY_BYTES_PER_ACTIVE_LEAF + ASSEMBLY_BYTES_PER_BOX),
        "{tested} leaves, {boxes} boxes: {estimate} bytes against a cap of {cap}"
    );
    assert!(MEMORY_LIMIT_REASON.contains("16 GiB"));
}
