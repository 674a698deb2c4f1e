//! The `proofs` command line: exit codes (0 success, 1 a rejected certificate or a run
//! stopped by its budget, 2 usage and input errors), JSON errors with `--json`, work
//! budgets, shards labelled as partial.
use std::path::PathBuf;
use std::process::{Command, Output};

fn proofs(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_proofs"))
        .args(args)
        .output()
        .expect("run proofs")
}

/// A fresh folder for one test, removed when the test ends (also when it fails).
fn scratch() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("proofs-cli-")
        .tempdir()
        .expect("create a temporary folder")
}

fn json_error(o: &Output) -> serde_json::Value {
    let v: serde_json::Value = serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("not JSON ({e}): {}", String::from_utf8_lossy(&o.stdout)));
    assert!(v["error"].is_string(), "{v}");
    assert!(v["kind"].is_string(), "{v}");
    assert!(v.get("position").is_some(), "{v}");
    v
}

#[test]
fn unreachable_tolerance_and_out_of_range_parameters_are_input_errors() {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    let out = tmp("never.json");
    for args in [
        vec!["gradnormal", "--tol-deg", "1e-300"],
        vec!["gradnormal", "--a", "10"],
        // A negative number is the option's value, out of its range (not an unknown
        // argument: that was a usage error).
        vec!["gradnormal", "--a", "-1"],
        vec!["gradnormal", "--scan", "1000000"],
        vec![
            "stuffing",
            "--row",
            "max-dihedral-unsafe",
            "--tol-deg",
            "1e-300",
        ],
        vec!["stuffing", "--graded", "--trees", "100000000"],
    ] {
        let mut a = args.clone();
        a.extend(["-o", out.to_str().unwrap(), "--json"]);
        let o = proofs(&a);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {o:?}");
        let v = json_error(&o);
        assert_eq!(v["kind"], "input", "{args:?}: {v}");
        // Plain text on stderr without --json.
        let mut a = args.clone();
        a.extend(["-o", out.to_str().unwrap()]);
        let o = proofs(&a);
        assert_eq!(o.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&o.stderr).starts_with("error: "));
    }
    assert!(!out.exists());
    // The messages name the limit and the option that raises it.
    let o = proofs(&["gradnormal", "--scan", "1000000"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("--max-boxes") && e.contains("--scan"), "{e}");
    // An out-of-range a/e is echoed short (it was printed with 309 digits).
    let o = proofs(&["gradnormal", "--a", "1e308"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("got 1e308") && e.len() < 200, "{e}");
}

#[test]
fn usage_errors_are_json_with_json() {
    let o = proofs(&["gradnormal", "--no-such-option", "--json"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(json_error(&o)["kind"], "usage");
    let o = proofs(&["gradnormal", "--no-such-option"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(o.stdout.is_empty());
}

#[test]
fn a_run_stopped_by_its_budget_writes_no_certificate() {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    let out = tmp("budget.json");
    let o = proofs(&[
        "gradnormal",
        "--max-boxes",
        "2000",
        "-o",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(1), "{o:?}");
    let v = json_error(&o);
    assert_eq!(v["kind"], "budget");
    assert!(v["error"].as_str().unwrap().contains("--max-boxes"), "{v}");
    assert!(!out.exists());
}

#[test]
fn unreadable_certificates_are_input_errors_with_a_position() {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    let p = tmp("broken.json");
    std::fs::write(
        &p,
        "{\"format\": \"certmesh-proofs/gradnormal/1\", \"ratio\": 3,",
    )
    .unwrap();
    let o = proofs(&["check", p.to_str().unwrap(), "--json"]);
    assert_eq!(o.status.code(), Some(2));
    let v = json_error(&o);
    assert_eq!(v["kind"], "input");
    assert!(v["position"].as_u64().is_some(), "{v}");
    let o = proofs(&["check", tmp("missing.json").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let o = proofs(&[
        "stuffing-figures",
        "--certs",
        tmp("no-such-dir").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn a_shard_is_partial_and_a_tampered_summary_is_rejected() {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    let out = tmp("shard.json");
    let o = proofs(&[
        "stuffing",
        "--row",
        "max-dihedral-unsafe",
        "--tol-deg",
        "1",
        "--shard",
        "5/700",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("shard 5/700: a partial result, not a proof of the row"),
        "{text}"
    );
    assert!(
        !text.contains("proven"),
        "a shard states no verdict:\n{text}"
    );
    let o = proofs(&["check", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    assert!(String::from_utf8_lossy(&o.stdout).contains("partial"));
    // JSON: partial and shard fields, no verdicts.
    let o = proofs(&[
        "stuffing",
        "--row",
        "max-dihedral-unsafe",
        "--tol-deg",
        "1",
        "--shard",
        "5/700",
        "-o",
        out.to_str().unwrap(),
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["partial"], true);
    assert_eq!(v["shard"], "5/700");
    assert!(v["bounds"]
        .as_array()
        .unwrap()
        .iter()
        .all(|b| b["verdict"].is_null()));
    // Tamper with the stated enclosure of a bound: rejected, naming the field.
    let mut c: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    c["bounds"][2]["deg"] = serde_json::json!([9.5, 9.6]);
    let bad = tmp("tampered.json");
    std::fs::write(&bad, c.to_string()).unwrap();
    let o = proofs(&["check", bad.to_str().unwrap(), "--json"]);
    assert_eq!(o.status.code(), Some(1), "{o:?}");
    let v = json_error(&o);
    assert_eq!(v["kind"], "check");
    assert!(
        v["error"].as_str().unwrap().starts_with("bounds[2].deg"),
        "{v}"
    );
    // A merge of one shard of 700 is incomplete: refused.
    let o = proofs(&[
        "merge",
        out.to_str().unwrap(),
        "-o",
        tmp("m.json").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{o:?}");
}

#[test]
fn gradnormal_shard_is_partial() {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    let out = tmp("g-shard.json");
    let o = proofs(&[
        "gradnormal",
        "--tol-deg",
        "0.5",
        "--shard",
        "0/8",
        "-o",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["partial"], true);
    assert_eq!(v["shard"], "0/8");
    assert!(v["claims"].as_array().unwrap().is_empty() && v["min_deg"].is_null());
    let o = proofs(&[
        "gradnormal",
        "--tol-deg",
        "0.5",
        "--shard",
        "0/8",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("shard 0/8: a partial result"));
}

/// `proofs stuffing --alpha-long A --alpha-short B`: bad pairs are input errors (exit 2,
/// JSON with --json) before any work; a shard of an audit writes a certificate whose
/// summary carries the audit block, and `proofs check` accepts it.
#[test]
fn stuffing_audit_of_a_custom_pair() {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    let out = tmp("audit.json");
    for args in [
        vec!["stuffing", "--alpha-long", "0.5", "--alpha-short", "0.3"],
        vec![
            "stuffing",
            "--alpha-long",
            "0.2",
            "--alpha-short",
            "0.500001",
        ],
        vec!["stuffing", "--alpha-long", "abc", "--alpha-short", "0.3"],
        vec!["stuffing", "--alpha-long", "0.2"],
        vec![
            "stuffing",
            "--alpha-long",
            "0.2",
            "--alpha-short",
            "0.3",
            "--row",
            "max-exposed-safe",
        ],
        vec![
            "stuffing",
            "--alpha-long",
            "0.2",
            "--alpha-short",
            "0.3",
            "--graded",
        ],
        vec![
            "stuffing",
            "--alpha-long",
            "0.2",
            "--alpha-short",
            "0.3",
            "--side",
            "two",
        ],
    ] {
        let mut a = args.clone();
        a.extend(["-o", out.to_str().unwrap(), "--json"]);
        let o = proofs(&a);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {o:?}");
        json_error(&o);
    }
    assert!(!out.exists());
    let o = proofs(&[
        "stuffing",
        "--alpha-long",
        "0.21509",
        "--alpha-short",
        "0.359",
        "--side",
        "both",
        "--shard",
        "3/400",
        "--tol-deg",
        "0.01",
        "-o",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["row"], "custom:0.21509,0.35900,unordered,double-sided");
    assert_eq!(v["partial"], true);
    assert_eq!(v["audit"]["table1_row"], "max-dihedral-double");
    assert!(v["audit"]["verdict"].as_str().unwrap().contains("shard"));
    let o = proofs(&["check", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    // The plain-text report names the matching Table 1 row.
    let o = proofs(&[
        "stuffing",
        "--alpha-long",
        "0.21509",
        "--alpha-short",
        "0.359",
        "--side",
        "both",
        "--shard",
        "3/400",
        "--tol-deg",
        "0.01",
        "-o",
        out.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("parameters of Table 1 row max-dihedral-double"),
        "{text}"
    );
}

/// The graded dagger certificates shipped in papers/stuffing/graded/ re-verify with the
/// current code (`proofs check` re-derives the all-contexts model and every leaf): the
/// 158.1918° dagger proven, 147.0470° exceeded with the supremum arccos(−17/19).
#[test]
fn shipped_graded_dagger_certificates_check() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../papers/stuffing/graded");
    for (row, verdict) in [
        ("min-exposed-unsafe", "proven"),
        ("min-exposed-safe-ordered", "exceeded-on-superset"),
    ] {
        let p = dir.join(format!("graded-{row}-all-contexts.json"));
        let o = proofs(&["--json", "check", p.to_str().expect("utf-8 path")]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
        assert_eq!(v["kind"], "graded-dagger");
        assert_eq!(v["verdict"], verdict, "{v}");
        let hi = v["enclosure_deg"][1].as_f64().expect("enclosure");
        if verdict == "proven" {
            assert!(hi < 158.1918);
        } else {
            let sup = (-17.0f64 / 19.0).acos().to_degrees();
            let lo = v["enclosure_deg"][0].as_f64().expect("enclosure");
            assert!(lo <= sup + 1e-6 && hi >= sup - 1e-6, "{v}");
        }
    }
}
