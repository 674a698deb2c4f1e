//! Proofs as a job array: running every shard `--shard i/N` and merging gives the same
//! certificate as the unsharded run, field for field (only the informative wall-clock
//! `seconds` differs), in the library and through the shipped scripts
//! (`scripts/parallel.sh`, `scripts/slurm/`), whose dry run prints the right commands.
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A scratch folder removed when the test ends, passed or failed (every run used to leave
/// three `proofs-shards-PID-*` folders in the temporary directory).
struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<std::ffi::OsStr> for Scratch {
    fn as_ref(&self) -> &std::ffi::OsStr {
        self.0.as_os_str()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn tmp(name: &str) -> Scratch {
    let d = std::env::temp_dir().join(format!("proofs-shards-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    Scratch(d)
}

/// The certificate as JSON without its wall-clock fields.
fn without_seconds(v: &mut serde_json::Value) {
    if let Some(o) = v.as_object_mut() {
        o.remove("seconds");
    }
}

fn json_of<T: serde::Serialize>(t: &T) -> serde_json::Value {
    let mut v = serde_json::to_value(t).unwrap();
    without_seconds(&mut v);
    v
}

fn read(p: &Path) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_slice(
        &std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display())),
    )
    .unwrap();
    without_seconds(&mut v);
    v
}

/// Report the first field where two certificates differ (a plain assert_eq on two large
/// JSON values prints megabytes).
fn assert_same(a: &serde_json::Value, b: &serde_json::Value, what: &str) {
    let (oa, ob) = (a.as_object().unwrap(), b.as_object().unwrap());
    let ka: Vec<_> = oa.keys().collect();
    let kb: Vec<_> = ob.keys().collect();
    assert_eq!(ka, kb, "{what}: different fields");
    for k in ka {
        assert!(oa[k] == ob[k], "{what}: field '{k}' differs");
    }
}

#[test]
fn stuffing_shards_merge_to_the_unsharded_certificate() {
    let row = certmesh::stuffing::row("min-exposed-unsafe").unwrap();
    let run = |shard| {
        let mut cfg = proofs::stuffing::Config::new(row);
        cfg.tol_deg = 5.0;
        cfg.shard = shard;
        proofs::stuffing::run(&cfg).unwrap()
    };
    let whole = run(None);
    // The shards handed to merge out of order: the result may not depend on it.
    let parts: Vec<_> = [2, 0, 1].iter().map(|&i| run(Some((i, 3)))).collect();
    let merged = proofs::stuffing::merge(parts).unwrap();
    assert_same(&json_of(&whole), &json_of(&merged), "stuffing 3 shards");
    proofs::stuffing::check(&merged).unwrap();
}

#[test]
fn gradnormal_shards_merge_to_the_unsharded_certificate() {
    use proofs::geometry::DiagonalRule;
    use proofs::gradnormal::{cases::Ratio, Config};
    let ratio = Ratio::parse("sommerville").unwrap();
    let run = |shard| {
        let mut cfg = Config::new(ratio, DiagonalRule::Paper);
        cfg.tol_cos = 0.5 * 0.5 * std::f64::consts::PI / 180.0;
        cfg.shard = shard;
        proofs::gradnormal::run(&cfg).unwrap()
    };
    let whole = run(None);
    let parts: Vec<_> = [1, 3, 0, 2].iter().map(|&i| run(Some((i, 4)))).collect();
    let merged = proofs::gradnormal::merge(parts).unwrap();
    assert_same(&json_of(&whole), &json_of(&merged), "gradnormal 4 shards");
    proofs::gradnormal::check(&merged).unwrap();
}

/// The dry run of the Slurm submission prints the array submission, one command per
/// task (shard i/N into DIR/shard-i-of-N.json), the dependent merge job, the merge and
/// the check: exactly these lines.
#[test]
fn slurm_dry_run_prints_the_commands() {
    let o = Command::new("bash")
        .arg(repo().join("scripts/slurm/submit.sh"))
        .args(["3", "certs/x", "stuffing", "--row", "max-dihedral-double"])
        .env("DRY_RUN", "1")
        .env("PROOFS", "proofs")
        .env("SBATCH_ARGS", "--partition=short")
        .output()
        .unwrap();
    assert!(o.status.success(), "{o:?}");
    let text = String::from_utf8(o.stdout).unwrap();
    let lines: Vec<&str> = text.lines().map(str::trim_end).collect();
    let slurm = repo().join("scripts/slurm");
    let slurm = slurm.canonicalize().unwrap();
    let s = slurm.display();
    let mut want = vec![format!(
        "sbatch --parsable --partition=short --array=0-2 --export=ALL {s}/shard.sbatch stuffing --row max-dihedral-double"
    )];
    for i in 0..3 {
        want.push(format!(
            "proofs stuffing --row max-dihedral-double --shard {i}/3 -o certs/x/shard-{i}-of-3.json"
        ));
    }
    want.push(format!(
        "sbatch --partition=short --dependency=afterok:JOBID --export=ALL {s}/merge.sbatch"
    ));
    want.push(
        "proofs merge certs/x/shard-0-of-3.json certs/x/shard-1-of-3.json certs/x/shard-2-of-3.json -o certs/x/merged.json"
            .into(),
    );
    want.push("proofs check certs/x/merged.json".into());
    assert_eq!(lines, want);
    // Bad N and a task index outside the array are refused.
    let bad = Command::new("bash")
        .arg(repo().join("scripts/slurm/submit.sh"))
        .args(["1", "certs/x", "stuffing"])
        .env("DRY_RUN", "1")
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    let bad = Command::new("bash")
        .arg(repo().join("scripts/slurm/shard.sbatch"))
        .args(["stuffing"])
        .env("DRY_RUN", "1")
        .env("SHARDS", "3")
        .env("DIR", "d")
        .env("SLURM_ARRAY_TASK_ID", "3")
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
}

/// `scripts/parallel.sh` really runs the shards (two at a time), merges and checks; the
/// merged certificate equals the unsharded one written by the same binary.
#[test]
fn parallel_script_merges_to_the_unsharded_certificate() {
    let bin = env!("CARGO_BIN_EXE_proofs");
    let dir = tmp("parallel");
    let args = ["stuffing", "--row", "min-exposed-unsafe", "--tol-deg", "5"];
    let o = Command::new("bash")
        .arg(repo().join("scripts/parallel.sh"))
        .arg("3")
        .arg(&dir)
        .args(args)
        .env("PROOFS", bin)
        .env("JOBS", "2")
        .output()
        .unwrap();
    assert!(o.status.success(), "{o:?}");
    let whole = dir.join("whole.json");
    let o = Command::new(bin)
        .args(args)
        .arg("-o")
        .arg(&whole)
        .output()
        .unwrap();
    assert!(o.status.success(), "{o:?}");
    assert_same(
        &read(&whole),
        &read(&dir.join("merged.json")),
        "parallel.sh",
    );
    // A missing shard: the merge step fails and says so.
    std::fs::remove_file(dir.join("shard-1-of-3.json")).unwrap();
    let o = Command::new("bash")
        .arg(repo().join("scripts/slurm/merge.sbatch"))
        .env("PROOFS", bin)
        .env("SHARDS", "3")
        .env("DIR", &dir)
        .output()
        .unwrap();
    assert!(!o.status.success());
}

/// `proofs report DIR` assembles PROOF.md's tables from the row certificates: the row's
/// line carries the enclosure of the certificate's own summary, the other rows read
/// "(not run)"; `proofs witness` recomputes the witnesses in floats and agrees, and a
/// distorted witness makes it disagree (exit 1).
#[test]
fn report_and_witness_from_certificates() {
    let bin = env!("CARGO_BIN_EXE_proofs");
    let dir = tmp("report");
    let cert = dir.join("min-exposed-unsafe.json");
    let o = Command::new(bin)
        .args([
            "stuffing",
            "--row",
            "min-exposed-unsafe",
            "--tol-deg",
            "5",
            "--json",
            "-o",
        ])
        .arg(&cert)
        .output()
        .unwrap();
    assert!(o.status.success(), "{o:?}");
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    std::fs::write(dir.join("min-exposed-unsafe.summary.json"), &o.stdout).unwrap();
    let o = Command::new(bin).arg("report").arg(&dir).output().unwrap();
    assert!(o.status.success(), "{o:?}");
    let md = String::from_utf8(o.stdout).unwrap();
    for b in summary["bounds"].as_array().unwrap() {
        if b["paper"].is_null() {
            continue;
        }
        let line = format!(
            "| min-exposed-unsafe | {} | {:.4} | [{:.6}, {:.6}] |",
            b["bound"].as_str().unwrap(),
            b["paper"].as_f64().unwrap(),
            b["certified_deg"][0].as_f64().unwrap(),
            b["certified_deg"][1].as_f64().unwrap()
        );
        assert!(md.contains(&line), "missing {line} in\n{md}");
    }
    assert!(md.contains("| max-dihedral-double | (not run) |"));
    assert!(md.contains(&format!(
        "| min-exposed-unsafe | 14913 -> 1936 | 0 | {} | {} |",
        summary["problems"], summary["leaves"]
    )));
    // witness: agrees on the real summary (and on the certificate itself).
    for f in ["min-exposed-unsafe.summary.json", "min-exposed-unsafe.json"] {
        let o = Command::new(bin)
            .arg("witness")
            .arg(dir.join(f))
            .output()
            .unwrap();
        assert!(o.status.success(), "{f}: {o:?}");
        let text = String::from_utf8(o.stdout).unwrap();
        assert!(
            text.contains("agrees") && !text.contains("DISAGREES"),
            "{text}"
        );
    }
    // Move one witness vertex: the float recomputation no longer matches.
    let mut bad = summary.clone();
    let b = bad["bounds"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|b| !b["witness"].is_null())
        .unwrap();
    // Stretch the tetrahedron along x: every angle not fixed by symmetry moves.
    for k in 0..4 {
        let v = b["witness"]["vertices_h"][k][0].as_f64().unwrap();
        b["witness"]["vertices_h"][k][0] = serde_json::json!(1.3 * v + 0.1 * k as f64);
    }
    let p = dir.join("bad.summary.json");
    std::fs::write(&p, serde_json::to_vec(&bad).unwrap()).unwrap();
    let o = Command::new(bin).arg("witness").arg(&p).output().unwrap();
    assert_eq!(o.status.code(), Some(1), "{o:?}");
    assert!(String::from_utf8_lossy(&o.stdout).contains("DISAGREES"));
    // An empty folder is an input error.
    let empty = tmp("report-empty");
    let o = Command::new(bin)
        .arg("report")
        .arg(&empty)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{o:?}");
}
