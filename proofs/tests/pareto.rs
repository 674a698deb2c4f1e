//! The certified Pareto front (`proofs pareto`): the front is exactly the set of
//! non-dominated pairs of a family (against a brute-force definition), findings are
//! pairs that beat a Table 1 row of their family on both bounds, and the command
//! refuses what `check` rejects.
use proofs::stuffing::pareto::{findings, front, Point, CRITERIA};
use proptest::prelude::*;

fn point(a: f64, b: f64, ordered: bool, d: [f64; 6], safe: &'static str) -> Point {
    Point {
        alpha_long: a,
        alpha_short: b,
        ordered,
        double_sided: false,
        proven_deg: d,
        width_deg: [1e-3; 6],
        safe,
        flat_output_cases: 0,
        certificate: format!("p-{a}-{b}.json"),
        leaves: 1,
        seconds: 0.0,
    }
}

proptest! {
    #[test]
    fn front_is_the_non_dominated_set(
        vals in prop::collection::vec((0u8..12, 0u8..12, any::<bool>()), 1..25)
    ) {
        // Coarse integer values make ties (equal bounds) frequent.
        let pts: Vec<Point> = vals
            .iter()
            .enumerate()
            .map(|(i, &(lo, hi, ord))| {
                let mut d = [0.0; 6];
                d[0] = lo as f64;
                d[1] = 150.0 + hi as f64;
                d[2] = (lo / 2) as f64;
                d[3] = 140.0 + (hi / 3) as f64;
                point(0.2 + i as f64 * 1e-3, 0.4, ord, d, "proven")
            })
            .collect();
        for (_, lo, hi) in CRITERIA {
            for fam in [(false, false), (true, false)] {
                let f = front(&pts, fam, lo, hi);
                let better = |q: &Point, p: &Point| {
                    q.proven_deg[lo] >= p.proven_deg[lo]
                        && q.proven_deg[hi] <= p.proven_deg[hi]
                        && (q.proven_deg[lo] > p.proven_deg[lo] || q.proven_deg[hi] < p.proven_deg[hi])
                };
                for (i, p) in pts.iter().enumerate() {
                    let in_fam = (p.ordered, p.double_sided) == fam;
                    let dominated = pts
                        .iter()
                        .any(|q| (q.ordered, q.double_sided) == fam && better(q, p));
                    prop_assert_eq!(f.contains(&i), in_fam && !dominated, "point {}", i);
                }
                for w in f.windows(2) {
                    prop_assert!(pts[w[0]].proven_deg[lo] <= pts[w[1]].proven_deg[lo]);
                }
            }
        }
    }
}

#[test]
fn findings_need_both_bounds_the_family_and_safety() {
    let row = certmesh::stuffing::row("min-dihedral-safe").unwrap();
    let (a, b) = (
        row.bounds.min_dihedral.unwrap(),
        row.bounds.max_dihedral.unwrap(),
    );
    let mut d = [0.0, 180.0, 0.0, 180.0, 0.0, 180.0];
    d[0] = a + 0.01;
    d[1] = b - 0.01;
    let beats = point(0.24, 0.41, false, d, "proven");
    let one_side = point(
        0.24,
        0.42,
        false,
        [a + 0.01, b + 0.01, 0.0, 180.0, 0.0, 180.0],
        "proven",
    );
    let unsafe_pair = point(0.26, 0.41, false, d, "refuted");
    let ordered = point(0.24, 0.43, true, d, "proven");
    let pts = vec![beats, one_side, unsafe_pair, ordered];
    let f = findings(&pts);
    let hits: Vec<(usize, &str)> = f
        .iter()
        .map(|f| (f.point, f.row))
        .filter(|h| h.1 == "min-dihedral-safe")
        .collect();
    assert_eq!(hits, vec![(0, "min-dihedral-safe")], "{f:?}");
    // The unsafe pair may beat the unsafe rows, never a safe one.
    assert!(f
        .iter()
        .filter(|f| f.point == 2)
        .all(|f| f.row.contains("unsafe")));
    // The ordered pair is compared with ordered rows only.
    assert!(f
        .iter()
        .filter(|f| f.point == 3)
        .all(|f| certmesh::stuffing::row(f.row).unwrap().ordered));
}

/// End to end on real certificates (release: about a minute per pair; run with
/// `cargo test --release -p proofs --test pareto -- --ignored`): two pairs certified,
/// one tampered; `proofs pareto` refuses the folder with the tampered one, accepts it
/// without, and writes both plots.
#[test]
#[ignore]
fn pareto_command_end_to_end() {
    use std::process::Command;
    let bin = env!("CARGO_BIN_EXE_proofs");
    let dir = std::env::temp_dir().join(format!("proofs-pareto-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (a, b) in [("0.2", "0.4"), ("0.24", "0.4")] {
        let o = Command::new(bin)
            .args([
                "stuffing",
                "--alpha-long",
                a,
                "--alpha-short",
                b,
                "--tol-deg",
                "5",
                "-o",
            ])
            .arg(dir.join(format!("p-{a}-{b}.json")))
            .output()
            .unwrap();
        assert!(o.status.success(), "{o:?}");
    }
    let o = Command::new(bin)
        .arg("pareto")
        .arg(&dir)
        .arg("--out")
        .arg(dir.join("fig"))
        .arg("--json")
        .output()
        .unwrap();
    assert!(o.status.success(), "{o:?}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["points"].as_array().unwrap().len(), 2);
    assert!(
        dir.join("fig/pareto-dihedral.svg").exists() && dir.join("fig/pareto-plane.png").exists()
    );
    // Tamper: a leaf count that the checker recomputes.
    let p = dir.join("p-0.2-0.4.json");
    let mut c: serde_json::Value = serde_json::from_slice(&std::fs::read(&p).unwrap()).unwrap();
    c["leaves"] = serde_json::json!(c["leaves"].as_u64().unwrap() + 1);
    std::fs::write(&p, serde_json::to_vec(&c).unwrap()).unwrap();
    let o = Command::new(bin).arg("pareto").arg(&dir).output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{o:?}");
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("rejected by check"),
        "{o:?}"
    );
}
