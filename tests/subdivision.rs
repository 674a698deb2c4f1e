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

/// A tiny local marching-squares component counter for the Fig 1.5 comparison (the shared
/// marching-squares mesher lives elsewhere): an n × m grid over the domain, a vertex on
/// every sign-change edge, the saddle case resolved by the centre value. Returns the
/// number of closed components.
fn ms_components(f: &dyn Implicit, dom: &certmesh::Aabb, n: usize) -> usize {
    let s = dom.size();
    let m = ((n as f64) * s[1] / s[0]).round().max(1.0) as usize;
    let p = |i: usize, j: usize| {
        [
            dom.min[0] + s[0] * i as f64 / n as f64,
            dom.min[1] + s[1] * j as f64 / m as f64,
            0.0,
        ]
    };
    let v: Vec<Vec<bool>> = (0..=n)
        .map(|i| (0..=m).map(|j| f.eval(p(i, j)) >= 0.0).collect())
        .collect();
    // Edge ids: horizontal (i,j)-(i+1,j) and vertical (i,j)-(i,j+1).
    let hid = |i: usize, j: usize| i * (m + 1) + j;
    let vid = |i: usize, j: usize| (n * (m + 1)) + i * m + j;
    let total = n * (m + 1) + (n + 1) * m;
    let mut parent: Vec<usize> = (0..total).collect();
    fn find(p: &mut Vec<usize>, x: usize) -> usize {
        let mut r = x;
        while p[r] != r {
            r = p[r];
        }
        p[x] = r;
        r
    }
    let mut used = vec![false; total];
    for i in 0..n {
        for j in 0..m {
            // Corners CCW: (i,j) (i+1,j) (i+1,j+1) (i,j+1); edges: bottom, right, top, left.
            let c = [v[i][j], v[i + 1][j], v[i + 1][j + 1], v[i][j + 1]];
            let e = [hid(i, j), vid(i + 1, j), hid(i, j + 1), vid(i, j)];
            let cut: Vec<usize> = (0..4).filter(|&k| c[k] != c[(k + 1) % 4]).collect();
            let pairs: Vec<(usize, usize)> = match cut.len() {
                2 => vec![(cut[0], cut[1])],
                4 => {
                    let centre = f.eval([
                        dom.min[0] + s[0] * (i as f64 + 0.5) / n as f64,
                        dom.min[1] + s[1] * (j as f64 + 0.5) / m as f64,
                        0.0,
                    ]) >= 0.0;
                    if centre == c[0] {
                        vec![(0, 3), (1, 2)]
                    } else {
                        vec![(0, 1), (2, 3)]
                    }
                }
                _ => vec![],
            };
            for (a, b) in pairs {
                used[e[a]] = true;
                used[e[b]] = true;
                let (ra, rb) = (find(&mut parent, e[a]), find(&mut parent, e[b]));
                parent[ra] = rb;
            }
        }
    }
    let mut roots = std::collections::HashSet::new();
    for k in 0..total {
        if used[k] {
            roots.insert(find(&mut parent, k));
        }
    }
    roots.len()
}

/// Regenerates the tables and figures of papers/meshing-of-surfaces/ (run with
/// `cargo test --release --test subdivision paper -- --ignored --nocapture`).
#[test]
#[ignore]
fn paper_tables_and_figures() {
    use certmesh::plantinga_vegter::{run_pv, PvParams};
    use certmesh::snyder::run_snyder;
    use certmesh::subdivision::{leaf_boxes, AngleBound};
    use std::fmt::Write;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/meshing-of-surfaces");
    let mut md = String::new();
    let boxes = |o: &MeshOutput| o.stats["boxes"].as_u64().unwrap();
    let leaves = |o: &MeshOutput| o.stats["leaves"].as_u64().unwrap();
    // 1. Curves.
    writeln!(md, "### Curves: Plantinga–Vegter and Snyder\n\n| curve | expected | PV leaves | PV certified | PV components | Snyder leaves | Snyder certified | Snyder components |\n|---|---|---|---|---|---|---|---|").unwrap();
    for e in catalog::curves() {
        let f = e.function();
        let (t1, pv) = run_pv(&f, &e.domain, &PvParams::new(2), 2, &NoProgress).unwrap();
        let (t2, sn) = run_snyder(&f, &e.domain, &SnyderParams::new(2), 2, &NoProgress).unwrap();
        let comp = |o: &MeshOutput| match &o.mesh {
            Mesh::Curve(c) => curve_components(c)
                .map(|x| x.to_string())
                .unwrap_or("open".into()),
            _ => "-".into(),
        };
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            e.name,
            e.topology
                .map(|t| t.components.to_string())
                .unwrap_or("singular".into()),
            leaves(&pv),
            pv.certificate.is_certified(),
            comp(&pv),
            leaves(&sn),
            sn.certificate.is_certified(),
            comp(&sn)
        )
        .unwrap();
        if let Mesh::Curve(c) = &pv.mesh {
            certmesh::plot_subdivision::draw_subdivision_svg(
                &dir.join(format!("fig-pv-{}", e.name)),
                &f,
                &e.domain,
                &leaf_boxes(&t1),
                c,
                720,
            )
            .unwrap();
        }
        if let Mesh::Curve(c) = &sn.mesh {
            certmesh::plot_subdivision::draw_subdivision_svg(
                &dir.join(format!("fig-snyder-{}", e.name)),
                &f,
                &e.domain,
                &leaf_boxes(&t2),
                c,
                720,
            )
            .unwrap();
        }
    }
    // 2. Fig 1.5: marching squares on regular grids vs PV on the protrusion.
    let e = catalog::get("protrusion").unwrap();
    let f = e.function();
    writeln!(md, "\n### Fig 1.5: `protrusion` (1 component)\n\n| method | grid / leaves | point evaluations | components |\n|---|---|---|---|").unwrap();
    for n in [4usize, 6, 8, 10, 12, 16, 24, 32] {
        let m = ((n as f64) * e.domain.size()[1] / e.domain.size()[0]).round() as usize;
        writeln!(
            md,
            "| marching squares | {n} x {m} | {} | {} |",
            (n + 1) * (m + 1),
            ms_components(&f, &e.domain, n)
        )
        .unwrap();
    }
    for md_ in [0u32, 2] {
        let cf = certmesh::implicit::Counted::new(&f);
        let (_, pv) = run_pv(
            &cf,
            &e.domain,
            &PvParams::new(2).with_min_depth(md_),
            2,
            &NoProgress,
        )
        .unwrap();
        let c = cf.counts();
        let comp = match &pv.mesh {
            Mesh::Curve(c) => curve_components(c),
            _ => None,
        };
        writeln!(md, "| PV (min_depth {md_}), certified={} | {} leaves | {} points + {} interval + {} interval-gradient | {:?} |", pv.certificate.is_certified(), leaves(&pv), c.points, c.intervals, c.interval_gradients, comp).unwrap();
    }
    // 3. Surfaces.
    writeln!(md, "\n### Surfaces\n\n| surface | PV boxes | PV leaves | PV certified | PV genera | PV time (ms) | Snyder (generic shift, depth 14) leaves | Snyder certified | Snyder uncertified boxes |\n|---|---|---|---|---|---|---|---|---|").unwrap();
    for e in catalog::surfaces() {
        let f = e.function();
        let t0 = std::time::Instant::now();
        let (_, pv) = run_pv(&f, &e.domain, &PvParams::new(3), 3, &NoProgress).unwrap();
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        let (_, sn) = run_snyder(
            &f,
            &e.domain,
            &SnyderParams::new(3)
                .with_max_depth(14)
                .with_generic_shift(true),
            3,
            &NoProgress,
        )
        .unwrap();
        let gen = match &pv.mesh {
            Mesh::Surface(m) => surface_genera(m)
                .map(|g| format!("{g:?}"))
                .unwrap_or("not closed".into()),
            _ => "-".into(),
        };
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {:.0} | {} | {} | {} |",
            e.name,
            boxes(&pv),
            leaves(&pv),
            pv.certificate.is_certified(),
            gen,
            ms,
            leaves(&sn),
            sn.certificate.is_certified(),
            sn.stats["uncertified_boxes"]
        )
        .unwrap();
        eprintln!("{}", e.name);
    }
    // 4. Exercise 9: crude vs sharp angle bound.
    std::fs::write(dir.join("subdivision-tables.md"), &md).unwrap();
    writeln!(md, "\n### Exercise 9: boxes (leaves + internal) needed for a gradient-cone angle bound (depth limit 7 for surfaces, 11 for curves; * = limit hit)\n\n| entry | 90° (SNV) | 60° crude | 60° sharp | 45° crude | 45° sharp |\n|---|---|---|---|---|---|").unwrap();
    let mut tot = [0u64; 5];
    for e in catalog::entries().into_iter().filter(|e| e.smooth) {
        let f = e.function();
        let mut row = Vec::new();
        let mut cfgs = vec![(90.0, AngleBound::Sharp)];
        for a in [60.0, 45.0] {
            cfgs.push((a, AngleBound::Crude));
            cfgs.push((a, AngleBound::Sharp));
        }
        for (k, (a, b)) in cfgs.into_iter().enumerate() {
            let p = PvParams::new(e.dim)
                .with_max_angle(a, b)
                .with_max_depth(if e.dim == 2 { 11 } else { 7 });
            let (_, o) = run_pv(&f, &e.domain, &p, e.dim, &NoProgress).unwrap();
            let n = boxes(&o);
            tot[k] += n;
            row.push(format!(
                "{n}{}",
                if o.certificate.is_certified() {
                    ""
                } else {
                    "*"
                }
            ));
        }
        writeln!(md, "| {} | {} |", e.name, row.join(" | ")).unwrap();
    }
    writeln!(
        md,
        "| **total** | {} |",
        tot.iter()
            .map(|t| t.to_string())
            .collect::<Vec<_>>()
            .join(" | ")
    )
    .unwrap();
    std::fs::write(dir.join("subdivision-tables.md"), &md).unwrap();
    println!("{md}");
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
            let nu = certmesh::geom::norm(u);
            let nv = certmesh::geom::norm(v);
            prop_assume!(nu > 1e-9 && nv > 1e-9);
            let cos = certmesh::geom::dot(u, v) / (nu * nv);
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
        let d0 = certmesh::geom::dist(p, q);
        let d1 = certmesh::geom::dist(m.map(p), m.map(q));
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
            if certmesh::geom::dot(left, f.grad(mid).g) < 0.0 {
                good += 1;
            }
        }
        assert_eq!(good, c.segments.len(), "{}", m.name());
    }
}
