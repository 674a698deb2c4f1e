//! The comparison harness judges outputs against the catalog: the uncertified baseline
//! merges the two spheres at a coarse odd resolution, the certified mesher does not.
use certmesh::catalog;
use certmesh::harness::compare::compare;
use certmesh::mesher::options::MesherOptions;
use certmesh::mesher::NoProgress;

#[test]
fn harness_flags_the_baselines_wrong_topology_and_certifies_pv() {
    let e = vec![catalog::get("two-spheres").unwrap()];
    let algos = vec!["mc".to_string(), "pv".to_string()];
    let o = MesherOptions {
        resolution: Some(21),
        ..Default::default()
    };
    let rows = compare(&e, &algos, &o, &NoProgress);
    assert_eq!(rows.len(), 2);
    let mc = rows.iter().find(|r| r.algo == "mc").unwrap();
    assert_eq!(mc.error, None);
    assert_eq!(
        mc.topology_ok,
        Some(false),
        "mc at 21 cells should merge the spheres: {}",
        mc.found
    );
    assert!(!mc.certified);
    let pv = rows.iter().find(|r| r.algo == "pv").unwrap();
    assert_eq!(pv.error, None);
    assert_eq!(
        pv.topology_ok,
        Some(true),
        "{} / {}",
        pv.found,
        pv.topology_reason
    );
    assert!(pv.certified);
    assert_eq!(pv.components, 2);
}
