//! Adaptive BCSV (`--algo bcsv`, the chapter "Meshing of Surfaces", §1.5.2): the
//! conforming tetrahedralization of the 2:1-balanced octree, the isotopy certificate
//! on the sphere and the torus, the replay of the recorded collapse against tampering,
//! and the singular double cone never certified.
use certmesh::catalog;
use certmesh::mesher::{self, registry, NoProgress};
use certmesh::morse::bcsv::{chi_of_s, replay, w_complex_octree};
use certmesh::morse::octree::{check_conforming, orient, Octree};
use certmesh::MesherOptions;

/// The tetrahedra of every leaf of the balanced octree of `name` (minimum level
/// `level`, depth limit `depth`), with the vertex table.
fn all_tets(name: &str, level: u32, depth: u32) -> (Octree, Vec<[u32; 3]>, Vec<[u32; 4]>) {
    let e = catalog::get(name).unwrap();
    let oct = Octree::build(
        &e.function(),
        &e.domain,
        level,
        depth,
        1_000_000,
        None,
        &Default::default(),
    );
    let mut vs = oct.vertices();
    let mut tets = Vec::new();
    for i in 0..oct.tree.leaves.len() {
        tets.extend(oct.leaf_tets(i, &mut vs).tets);
    }
    let coords = vs.coords.clone();
    (oct, coords, tets)
}

/// Every interior triangle in exactly two tetrahedra on opposite sides, every boundary
/// triangle in one, all positively oriented, the volumes summing exactly to the
/// domain's (integer coordinates) and, in space, to 1e-12; on trees with several
/// levels (hanging faces and edges present). Tampered complexes are rejected.
#[test]
fn octree_tetrahedra_conform() {
    let mut most_levels = 0;
    for (name, level, depth) in [("sphere", 2, 6), ("torus", 3, 7), ("two-spheres", 2, 7)] {
        let (oct, coords, tets) = all_tets(name, level, depth);
        let levels = oct.tree.by_depth();
        assert!(levels.len() >= 2, "{name}: levels {levels:?}");
        most_levels = most_levels.max(levels.len());
        let top = 1u32 << (oct.tree.grid.depth + 1);
        check_conforming(&coords, &tets, top).unwrap_or_else(|e| panic!("{name}: {e}"));
        // Coned leaves (not six Kuhn tetrahedra) are present.
        assert!(tets.len() > 6 * oct.tree.leaves.len(), "{name}");
        // The volume in space.
        let vs = oct.vertices();
        let pos = |v: u32| vs.grid.point(coords[v as usize]);
        let vol: f64 = tets
            .iter()
            .map(|t| {
                let p = t.map(pos);
                let e = [1, 2, 3].map(|q| [0, 1, 2].map(|a| p[q][a] - p[0][a]));
                (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1])
                    - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0])
                    + e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]))
                    / 6.0
            })
            .sum();
        let s = oct.tree.grid.domain.size();
        let want = s[0] * s[1] * s[2];
        assert!(
            (vol - want).abs() <= 1e-12 * want,
            "{name}: {vol} vs {want}"
        );
        // Tampering: a missing tetrahedron, a reversed one, a duplicated one.
        assert!(check_conforming(&coords, &tets[1..], top).is_err());
        let mut rev = tets.clone();
        rev[0].swap(0, 1);
        assert!(orient(&coords, rev[0]) < 0);
        assert!(check_conforming(&coords, &rev, top).is_err());
        let mut dup = tets.clone();
        dup.push(tets[0]);
        assert!(check_conforming(&coords, &dup, top).is_err());
    }
    // two-spheres is refined deep into the gap: leaves of several sizes side by side.
    assert!(most_levels >= 4, "{most_levels}");
}

/// A run of adaptive BCSV with the defaults.
fn run(name: &str) -> mesher::Run {
    let e = catalog::get(name).unwrap();
    let mut o = MesherOptions::default();
    o.extra.insert("octree".into(), "true".into());
    let m = registry::build("bcsv", 3, &o).unwrap();
    mesher::run(m.as_ref(), &e.function(), &e.domain, &NoProgress).unwrap()
}

/// Certified isotopic on the sphere and the torus, checked independently: the
/// output's topology against the catalog, its χ against a separate Morse census, the
/// collapse rebuilt and replayed here.
#[test]
fn adaptive_bcsv_certifies_sphere_and_torus() {
    for name in ["sphere", "torus"] {
        let r = run(name);
        let s = &r.output.stats;
        assert_eq!(s["octree"], true, "{name}");
        assert_eq!(s["isotopy_certified"], true, "{name}: {:?}", s["attempts"]);
        assert!(r.output.certificate.proves_topology());
        let e = catalog::get(name).unwrap();
        let t = certmesh::metrics::analyze(r.output.mesh.surface().unwrap()).unwrap();
        assert!(certmesh::metrics::verdict(&t, e.topology.as_ref().unwrap()).ok);
        assert!(t.is_closed_oriented_manifold());
        let (chi, _) =
            certmesh::morse::certified_chi(&e.function(), e.domain.into(), 20_000, 100_000);
        assert_eq!(Some(t.euler_characteristic), chi, "{name}");
        let level = s["min_level"].as_u64().unwrap() as u32;
        let depth = s["max_depth"].as_u64().unwrap() as u32;
        let (cx, seq) = w_complex_octree(&e.function(), &e.domain, level, depth).unwrap();
        assert!(replay(&cx, &seq).is_ok());
        assert_eq!(chi_of_s(&cx), t.euler_characteristic);
        assert_eq!(s["collapse_steps"], seq.len());
    }
}

/// The recorded collapse of an adaptive W replays; tampered sequences do not.
#[test]
fn adaptive_replay_rejects_tampering() {
    let e = catalog::get("sphere").unwrap();
    let (cx, seq) = w_complex_octree(&e.function(), &e.domain, 3, 12).unwrap();
    assert!(replay(&cx, &seq).is_ok());
    assert!(replay(&cx, &seq[..seq.len() - 1]).is_err(), "unfinished");
    let mut swapped = seq.clone();
    swapped.swap(0, seq.len() - 1);
    assert!(replay(&cx, &swapped).is_err(), "out of order");
    let mut rev = seq.clone();
    rev.reverse();
    assert!(replay(&cx, &rev).is_err(), "reversed");
    let s_cell = cx.cells.iter().position(|c| c.in_s && c.dim == 2).unwrap() as u32;
    let mut bad = seq.clone();
    bad[0].0 = s_cell;
    assert!(replay(&cx, &bad).is_err(), "removes a cell of S");
    // A domain cutting the sphere: not W-certified (S meets ∂D).
    let d = certmesh::Aabb::new([0.0, -1.5, -1.5], [1.5, 1.5, 1.5]).unwrap();
    assert!(w_complex_octree(&e.function(), &d, 3, 8).is_err());
}

/// The double cone (singular at the apex, on S) is never certified: the refinement
/// cannot exclude the apex nor prove it free of critical points.
#[test]
fn adaptive_bcsv_refuses_the_double_cone() {
    let r = run("double-cone");
    assert_eq!(r.output.stats["w_certified"], false);
    assert_eq!(r.output.stats["isotopy_certified"], false);
    assert!(!r.output.certificate.is_certified());
    let a = r.output.stats["attempts"].as_array().unwrap();
    assert!(a.iter().all(|x| x["failure"].is_string()));
}

/// The uniform version stays available (`--set octree=false`) and still certifies.
#[test]
fn uniform_bcsv_still_available() {
    let e = catalog::get("sphere").unwrap();
    let mut o = MesherOptions::default();
    o.extra.insert("octree".into(), "false".into());
    let m = registry::build("bcsv", 3, &o).unwrap();
    let r = mesher::run(m.as_ref(), &e.function(), &e.domain, &NoProgress).unwrap();
    assert_eq!(r.output.stats["octree"], false);
    assert_eq!(r.output.stats["isotopy_certified"], true);
    o.extra.insert("octree".into(), "maybe".into());
    assert!(registry::build("bcsv", 3, &o).is_err());
}
