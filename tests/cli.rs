//! The command line as a user meets it: clear errors with positions, JSON fields.
//!
//! Over 800 lines on purpose: every subcommand's tests in one test executable (one
//! compile and link instead of one per subcommand); each test is independent, and
//! they are grouped by subcommand.
use std::process::Command;

fn certmesh(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_certmesh"))
        .args(args)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

#[test]
fn formula_errors_give_the_column_and_exit_2() {
    let (code, _, err) = certmesh(&[
        "mesh",
        "--formula",
        "x^2 + * y",
        "--domain",
        "-1,-1,-1,1,1,1",
        "--algo",
        "mc",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("unexpected '*' at column 7"), "{err}");
}

#[test]
fn unknown_names_list_the_known_ones() {
    let (code, _, err) = certmesh(&["mesh", "no-such-surface", "--algo", "mc"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("unknown catalog entry 'no-such-surface'") && err.contains("tanglecube"),
        "{err}"
    );
    let (code, _, err) = certmesh(&["mesh", "sphere", "--algo", "no-such-algo"]);
    assert_eq!(code, 2);
    assert!(err.contains("no-such-algo"), "{err}");
}

#[test]
fn bad_domains_are_rejected() {
    // A formula without --domain now has a default domain (issue 12), so the case that
    // must name --domain is a --domain of the wrong length.
    let (code, _, err) = certmesh(&[
        "mesh",
        "--formula",
        "x",
        "--domain",
        "1,2,3",
        "--algo",
        "mc",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--domain"), "{err}");
    let (code, _, err) = certmesh(&[
        "mesh",
        "--formula",
        "x",
        "--domain",
        "1,1,1,0,0,0",
        "--algo",
        "mc",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("inverted"), "{err}");
    let (code, _, err) = certmesh(&[
        "mesh",
        "--formula",
        "x",
        "--domain",
        "0,0,0,inf,1,1",
        "--algo",
        "mc",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("not finite"), "{err}");
}

#[test]
fn surfaces_json_lists_the_whole_catalog() {
    let (code, out, _) = certmesh(&["surfaces", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let names: Vec<&str> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    for n in [
        "sphere",
        "ellipsoid",
        "torus",
        "genus2",
        "genus5",
        "tanglecube",
        "two-spheres",
        "thin-torus",
        "paraboloid-cap",
        "double-cone",
        "blob",
    ] {
        assert!(names.contains(&n), "{n} missing");
    }
    for n in [
        "circle",
        "ellipse",
        "cassini-1",
        "cassini-2",
        "protrusion",
        "near-touching",
        "lemniscate",
    ] {
        assert!(names.contains(&n), "{n} missing");
    }
}

#[test]
fn stats_json_on_a_real_mesh() {
    let (code, out, err) = certmesh(&["stats", "data/spot.obj", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for k in [
        "vertices",
        "faces",
        "euler_characteristic",
        "components",
        "closed",
        "manifold",
        "min_angle_deg",
        "max_angle_deg",
    ] {
        assert!(v.get(k).is_some(), "{k} missing");
    }
    assert_eq!(v["euler_characteristic"], 2);
    assert_eq!(v["closed"], true);
}

/// `stats --formula`: the mesh → surface distance of a sample is to its Newton
/// projection, a point of f = 0 but not always the nearest (with several components it
/// can be much farther), so the text and --json say that it is an upper bound per
/// sample. Here a sphere of radius 1.15 against f = 0 = the spheres of radii 1 and 1.2:
/// every vertex is 0.05 from the surface, so the maximum of per-sample upper bounds is
/// at least that.
#[test]
fn stats_says_the_mesh_to_surface_distance_is_an_upper_bound_per_sample() {
    let d = tmp("stats-upper");
    let (code, out, err) = certmesh_in(
        &d,
        &[
            "mesh",
            "--formula",
            "x^2 + y^2 + z^2 - 1.3225",
            "--algo",
            "pv",
            "-o",
            "s.obj",
            "-q",
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    let args = [
        "stats",
        "s.obj",
        "--formula",
        "(x^2 + y^2 + z^2 - 1)*(x^2 + y^2 + z^2 - 1.44)",
    ];
    let (code, out, err) = certmesh_in(&d, &[&args[..], &["--json"]].concat());
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let kind = v["hausdorff_mesh_to_surface_kind"]
        .as_str()
        .unwrap_or_else(|| panic!("no hausdorff_mesh_to_surface_kind: {out}"));
    assert!(
        kind.contains("upper bound") && kind.contains("per sample") && kind.contains("Newton"),
        "{kind}"
    );
    assert!(
        v["hausdorff_kind"]
            .as_str()
            .unwrap()
            .contains("upper bound"),
        "{out}"
    );
    let h = v["hausdorff_mesh_to_surface"].as_f64().unwrap();
    assert!(h >= 0.049, "{h}: below the vertices' distance to f = 0");
    let (code, text, err) = certmesh_in(&d, &args);
    assert_eq!(code, 0, "{err}");
    assert!(
        text.contains("(per-sample upper bounds)") && text.contains(kind),
        "{text}"
    );
    std::fs::remove_dir_all(&d).unwrap();
}

/// Tiny and huge domains print readably in text (1e-100, not a hundred zeros): the
/// report's domain line and the empty-zero-set error; --json keeps the numbers
/// themselves.
#[test]
fn tiny_and_huge_domains_print_in_scientific_notation() {
    for (formula, domain, bound) in [
        (
            "x^2 + y^2 + z^2 - 1e-200",
            "--domain=-1e-100,-1e-100,-1e-100,1e-100,1e-100,1e-100",
            "1e-100",
        ),
        (
            "x^2 + y^2 + z^2 - 1e200",
            "--domain=-1e100,-1e100,-1e100,1e100,1e100,1e100",
            "1e100",
        ),
    ] {
        let args = ["mesh", "--formula", formula, domain, "--algo", "mc"];
        let (code, text, err) = certmesh(&args);
        assert_eq!(code, 0, "{err}");
        let line = text
            .lines()
            .find(|l| l.starts_with("domain: "))
            .unwrap_or_else(|| panic!("no domain line: {text}"));
        let b = format!("[-{bound}, {bound}]");
        assert_eq!(
            line.strip_prefix("domain: "),
            Some(format!("{b} × {b} × {b}").as_str()),
            "{line}"
        );
        // The table's Hausdorff column too: neither "0.0000" nor a hundred digits.
        let row = text.lines().nth(2).unwrap_or_default();
        let hd = row.split('|').nth(6).unwrap_or_default().trim();
        assert!(hd.contains('e') && hd.len() < 16, "{row}");
        let (code, out, err) = certmesh(&[&args[..], &["--json"]].concat());
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let x: f64 = bound.parse().unwrap();
        assert_eq!(v["domain"]["min"], serde_json::json!([-x, -x, -x]), "{out}");
        assert_eq!(v["domain"]["max"], serde_json::json!([x, x, x]), "{out}");
    }
    // The empty-zero-set error names the domain the same way.
    let (code, _, err) = certmesh(&[
        "mesh",
        "--formula",
        "x^2 + y^2 + z^2 + 1",
        "--domain=-1e-100,-1e-100,-1e-100,1e-100,1e-100,1e-100",
        "--algo",
        "mc",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("[-1e-100, 1e-100] × [-1e-100, 1e-100]") && !err.contains("0000000000"),
        "{err}"
    );
}

#[test]
fn stats_reports_the_bunny_scan_defects() {
    let (code, out, err) = certmesh(&["stats", "data/stanford-bunny.obj", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["faces"], 69451);
    assert_eq!(v["closed"], false);
    assert!(v["isolated_vertices"].as_u64().unwrap() > 0);
    assert!(v["boundary_loops"].as_u64().unwrap() > 0);
}

#[test]
fn malformed_mesh_files_name_the_line() {
    let dir = std::env::temp_dir().join(format!("certmesh-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("bad.obj");
    std::fs::write(&p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    let (code, _, err) = certmesh(&["stats", p.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("line 4"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn stats_histogram_with_emphasis_and_bad_factor() {
    let dir = std::env::temp_dir().join(format!("certmesh-emph-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mesh = dir.join("t.vtk");
    let (code, _, err) = certmesh(&[
        "mesh",
        "sphere",
        "--algo",
        "stuffing",
        "-o",
        mesh.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let base = dir.join("h");
    let (code, _, err) = certmesh(&[
        "stats",
        mesh.to_str().unwrap(),
        "--histogram",
        base.to_str().unwrap(),
        "--emphasis",
        "20",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(base.with_extension("svg").exists() && base.with_extension("png").exists());
    let (code, _, err) = certmesh(&["stats", mesh.to_str().unwrap(), "--emphasis", "0.5"]);
    assert_ne!(code, 0);
    assert!(err.contains("--emphasis"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `--mesh-input`: a scanned-style mesh with a hole is remeshed through its signed
/// distance (GradNormal, Sec. 5.1); bad files and margins are clear errors.
#[test]
fn mesh_input_remeshes_a_mesh_with_a_hole() {
    let dir = std::env::temp_dir().join(format!("certmesh-cli-meshinput-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let m = certmesh::implicit::sdf::uv_sphere(16, 32, 2.0);
    // Cut a cap off: an open mesh, as a scan with a hole.
    let open = certmesh::mesh::TriMesh::new(
        m.vertices.clone(),
        m.triangles
            .iter()
            .copied()
            .filter(|t| t.iter().all(|&i| m.vertices[i as usize][2] < 1.9))
            .collect(),
    );
    let input = dir.join("open-sphere.obj");
    certmesh::io::write_tri(&input, &open).unwrap();
    let out = dir.join("remesh.obj");
    let (code, stdout, err) = certmesh(&[
        "mesh",
        "--mesh-input",
        input.to_str().unwrap(),
        "--fill-holes",
        "--algo",
        "gradnormal",
        "--scale",
        "0.05",
        "-o",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["closed"], serde_json::json!(true), "{stdout}");
    assert_eq!(v["genus"], serde_json::json!([0]), "{stdout}");
    assert!(v["faces"].as_u64().unwrap() > 500, "{stdout}");
    let mesh = certmesh::io::read_tri(&out).unwrap();
    // Normalised into the unit cube with the default 5% margin: radius 0.45 about ½.
    for p in &mesh.vertices {
        let r = certmesh::kernel::geom::dist(*p, [0.5; 3]);
        assert!((r - 0.45).abs() < 0.03, "vertex at radius {r}");
    }
    let (code, _, err) = certmesh(&[
        "mesh",
        "--mesh-input",
        "/nonexistent/scan.obj",
        "--algo",
        "gradnormal",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("/nonexistent/scan.obj"), "{err}");
    let (code, _, err) = certmesh(&[
        "mesh",
        "--mesh-input",
        input.to_str().unwrap(),
        "--margin",
        "0.7",
        "--algo",
        "gradnormal",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("margin"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

// ---------------------------------------------------------------------------------
// Issue 13 "smaller defects" and issue 12 "what users expect".

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A fresh, empty temporary folder for one test.
fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("certmesh-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Run certmesh in `dir`.
fn certmesh_in(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_certmesh"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// The repository (for data/ files).
fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Run `line` with `sh -c` in `dir`, the certmesh binary first on PATH.
fn sh_in(dir: &Path, line: &str) -> (i32, String, String, Duration) {
    let bin = Path::new(env!("CARGO_BIN_EXE_certmesh")).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let t0 = Instant::now();
    let out = Command::new("sh")
        .arg("-c")
        .arg(line)
        .current_dir(dir)
        .env("PATH", path)
        .output()
        .expect("sh runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
        t0.elapsed(),
    )
}

/// A JSON error object: exactly the keys error, kind, position.
fn json_error(out: &str) -> serde_json::Value {
    let v: serde_json::Value =
        serde_json::from_str(out).unwrap_or_else(|e| panic!("not JSON ({e}): {out}"));
    let o = v.as_object().expect("an object");
    let mut keys: Vec<&str> = o.keys().map(|k| k.as_str()).collect();
    keys.sort();
    assert_eq!(keys, ["error", "kind", "position"], "{out}");
    assert!(v["error"].as_str().is_some_and(|s| !s.is_empty()), "{out}");
    v
}

#[test]
fn json_errors_are_objects_on_stdout_with_exit_2() {
    let dir = tmp("jsonerr");
    let bad = dir.join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    let bad = bad.to_str().unwrap();
    // (arguments, expected kind, expected position)
    let cases: Vec<(Vec<&str>, &str, serde_json::Value)> = vec![
        (
            vec!["mesh", "--formula", "x^2 + * y", "--algo", "mc", "--json"],
            "formula",
            serde_json::json!(7),
        ),
        (
            vec![
                "curve",
                "--formula",
                "x^2 + y^2 - 1",
                "--domain",
                "1,1,0,0",
                "--algo",
                "ms",
                "--json",
            ],
            "domain",
            serde_json::Value::Null,
        ),
        (
            vec!["mesh", "no-such-surface", "--algo", "mc", "--json"],
            "unknown-name",
            serde_json::Value::Null,
        ),
        (
            vec![
                "mesh",
                "sphere",
                "--algo",
                "mc",
                "--resolution",
                "abc",
                "--json",
            ],
            "usage",
            serde_json::Value::Null,
        ),
        (
            vec![
                "mesh",
                "sphere",
                "--algo",
                "mc",
                "--crossing",
                "cubic",
                "--json",
            ],
            "unknown-name",
            serde_json::Value::Null,
        ),
        (vec!["stats", bad, "--json"], "file", serde_json::json!(4)),
        (
            vec!["stats", "/nonexistent/m.obj", "--json"],
            "io",
            serde_json::Value::Null,
        ),
        (
            vec!["stats", "data-not-here.obj", "--formula", "x +", "--json"],
            "formula",
            serde_json::json!(4),
        ),
        (
            vec!["compare", "--surfaces", "no-such", "--json"],
            "unknown-name",
            serde_json::Value::Null,
        ),
        (
            vec!["compare", "--surfaces", "circle", "--json"],
            "parameter",
            serde_json::Value::Null,
        ),
        (
            vec!["surfaces", "--json", "--bogus"],
            "usage",
            serde_json::Value::Null,
        ),
        (
            vec!["algos", "--json", "extra"],
            "usage",
            serde_json::Value::Null,
        ),
        (
            vec!["demo", "--out", bad, "--json"],
            "io",
            serde_json::Value::Null,
        ),
    ];
    for (args, kind, pos) in cases {
        let (code, out, err) = certmesh_in(&dir, &args);
        assert_eq!(code, 2, "{args:?}: {out} {err}");
        let v = json_error(&out);
        assert_eq!(v["kind"], kind, "{args:?}: {out}");
        assert_eq!(v["position"], pos, "{args:?}: {out}");
        assert!(
            !err.contains("error"),
            "{args:?}: the error goes to stdout as JSON, stderr: {err}"
        );
    }
    // Without --json the same error is text on stderr, with the same exit code.
    let (code, out, err) = certmesh_in(&dir, &["mesh", "--formula", "x^2 + * y", "--algo", "mc"]);
    assert_eq!(code, 2);
    assert!(out.is_empty() && err.contains("column 7"), "{out} {err}");
    // `reproduce` has no --json: an unknown paper is an input error (2) naming the papers.
    let (code, _, err) = certmesh_in(&dir, &["reproduce", "no-such-paper"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("meshing-of-surfaces"), "{err}");
    // A failure while writing at the end is a runtime failure (exit 1): /dev/full
    // passes the checks (it opens) and fails on the write.
    if Path::new("/dev/full").exists() {
        std::os::unix::fs::symlink("/dev/full", dir.join("full.obj")).unwrap();
        let (code, out, err) = certmesh_in(
            &dir,
            &["mesh", "sphere", "--algo", "mc", "-o", "full.obj", "--json"],
        );
        assert_eq!(code, 1, "{out} {err}");
        let v = json_error(&out);
        assert_eq!(v["kind"], "io", "{out}");
    }
    // A reader that stops early (`| head`) is not a crash.
    // (The report lists thousands of regions: far more than a pipe buffer holds.)
    let (code, out, err, _) = sh_in(
        &dir,
        "certmesh mesh --formula 0 --domain -1,-1,-1,1,1,1 --algo pv --max-boxes 2000 --json | head -n 1",
    );
    assert_eq!(code, 0);
    assert_eq!(out.trim(), "{");
    assert!(!err.contains("panicked"), "{err}");
    // Help and version are not errors.
    assert_eq!(certmesh_in(&dir, &["--help"]).0, 0);
    assert_eq!(certmesh_in(&dir, &["--version"]).0, 0);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn outputs_are_checked_before_the_work_starts() {
    let dir = tmp("outcheck");
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let in_file = format!("{}/y.obj", file.display());
    std::fs::create_dir(dir.join("d.obj")).unwrap();
    // Resolution 500 marching cubes on the sphere takes far longer than the limit below
    // if the mesher ran: each of these must fail before it starts.
    for (out, what) in [
        ("y.xyz", "xyz"),
        ("/nonexistent-dir/y.obj", "does not exist"),
        (in_file.as_str(), "does not exist"),
        ("d.obj", "is a directory"),
        ("c.svg", "cannot hold"),
    ] {
        let t0 = Instant::now();
        let (code, stdout, err) = certmesh_in(
            &dir,
            &[
                "mesh",
                "sphere",
                "--algo",
                "mc",
                "--resolution",
                "500",
                "-o",
                out,
                "--json",
            ],
        );
        let dt = t0.elapsed();
        assert_eq!(code, 2, "{out}: {stdout} {err}");
        let v = json_error(&stdout);
        assert!(
            v["error"].as_str().unwrap().contains(what),
            "{out}: {stdout}"
        );
        assert!(
            dt < Duration::from_secs(3),
            "{out}: failed only after {dt:?}"
        );
    }
    // A curve cannot go to a surface format; a volume boundary must be a triangle format.
    let (code, _, err) = certmesh_in(&dir, &["curve", "circle", "--algo", "ms", "-o", "c.obj"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cannot hold a curve"), "{err}");
    let (code, _, err) = certmesh_in(
        &dir,
        &[
            "mesh",
            "sphere",
            "--algo",
            "stuffing",
            "-o",
            "t.vtk",
            "--boundary",
            "b.svg",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("b.svg"), "{err}");
    // Nothing was left behind by the checks.
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    let mut left = left;
    left.sort();
    assert_eq!(
        left,
        ["a-file", "d.obj"].map(std::ffi::OsString::from),
        "{left:?}"
    );
    // The other commands' outputs are checked the same way.
    let (code, _, err) = certmesh_in(
        &dir,
        &[
            "compare",
            "--surfaces",
            "sphere",
            "--algos",
            "mc",
            "-o",
            "t.txt",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("table format 'txt'"), "{err}");
    let (code, _, err) = certmesh_in(
        &dir,
        &[
            "compare",
            "--surfaces",
            "sphere",
            "--algos",
            "mc",
            "-o",
            "/nonexistent-dir/t.md",
        ],
    );
    assert_eq!(code, 2, "{err}");
    let spot = repo().join("data/spot.obj");
    let (code, _, err) = certmesh_in(
        &dir,
        &[
            "stats",
            spot.to_str().unwrap(),
            "--histogram",
            "/nonexistent-dir/h",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("does not exist"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A long polynomial: `terms` copies of 0.0002·(x² + y² + z² − 1) summed term by term,
/// i.e. the unit sphere scaled, as one formula of about 48 bytes per copy.
fn long_sphere(terms: usize) -> String {
    vec!["0.0002*x^2 + 0.0002*y^2 + 0.0002*z^2 - 0.0002"; terms].join(" + ")
}

#[test]
fn formulas_beyond_the_argument_limit_come_from_files() {
    let dir = tmp("formulafile");
    let text = long_sphere(5000);
    assert!(text.len() > 200 * 1024, "{}", text.len());
    std::fs::write(dir.join("long.txt"), format!("{text}\n")).unwrap();
    for form in [
        vec!["--formula", "@long.txt"],
        vec!["--formula-file", "long.txt"],
    ] {
        let mut args = vec!["mesh"];
        args.extend(form.iter().copied());
        args.extend([
            "--algo",
            "mc",
            "--resolution",
            "12",
            "-o",
            "l.obj",
            "--json",
        ]);
        let (code, out, err) = certmesh_in(&dir, &args);
        assert_eq!(code, 0, "{form:?}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["components"], 1, "{out}");
        assert_eq!(v["genus"], serde_json::json!([0]), "{out}");
        assert_eq!(v["domain_source"], "default", "{out}");
        // The scaled sphere: the mesh is within a cell of the unit sphere.
        let m = certmesh::io::read_tri(dir.join("l.obj")).unwrap();
        for p in &m.vertices {
            let r = certmesh::kernel::geom::norm(*p);
            assert!((r - 1.0).abs() < 0.34, "vertex at radius {r}");
        }
    }
    // stats reads a formula file too.
    let (code, out, err) = certmesh_in(
        &dir,
        &["stats", "l.obj", "--formula", "@long.txt", "--json"],
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["hausdorff"].as_f64().unwrap() < 0.2, "{out}");
    // The same formula as an argument is beyond what the OS lets a program receive
    // (on Linux one argument is at most 128 KiB): this is why the file form exists.
    let direct = Command::new(env!("CARGO_BIN_EXE_certmesh"))
        .args(["mesh", "--formula", &text, "--algo", "mc", "-o"])
        .arg(dir.join("d.obj"))
        .output();
    if cfg!(target_os = "linux") {
        assert!(
            direct.is_err(),
            "the OS accepted a {} byte argument",
            text.len()
        );
    }
    // Errors in a formula file name the file and the column; a missing file is an i/o
    // error naming the path.
    std::fs::write(dir.join("bad.txt"), "x^2 + * y\n").unwrap();
    let (code, out, _) = certmesh_in(
        &dir,
        &["mesh", "--formula", "@bad.txt", "--algo", "mc", "--json"],
    );
    assert_eq!(code, 2);
    let v = json_error(&out);
    assert_eq!(v["position"], 7, "{out}");
    assert!(
        v["error"].as_str().unwrap().starts_with("bad.txt: "),
        "{out}"
    );
    let (code, out, _) = certmesh_in(
        &dir,
        &[
            "mesh",
            "--formula-file",
            "nope.txt",
            "--algo",
            "mc",
            "--json",
        ],
    );
    assert_eq!(code, 2);
    assert!(
        json_error(&out)["error"]
            .as_str()
            .unwrap()
            .contains("nope.txt"),
        "{out}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn formulas_have_a_documented_default_domain() {
    let dir = tmp("defaultdomain");
    // The README's first example.
    let (code, out, err) = certmesh_in(
        &dir,
        &[
            "mesh",
            "--formula",
            "x^2 + y^2 + z^2 - 1",
            "--algo",
            "mc",
            "-o",
            "sphere.obj",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("domain: [-2, 2] × [-2, 2] × [-2, 2] (the default domain"),
        "{out}"
    );
    assert!(dir.join("sphere.obj").exists());
    let (code, out, err) = certmesh_in(
        &dir,
        &[
            "curve",
            "--formula",
            "x^2 + y^2 - 1",
            "--algo",
            "pv",
            "-o",
            "c.svg",
            "--json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["domain_source"], "default");
    assert_eq!(v["domain"]["min"], serde_json::json!([-2.0, -2.0, 0.0]));
    assert_eq!(v["domain"]["max"], serde_json::json!([2.0, 2.0, 0.0]));
    assert_eq!(v["certified"], true, "{out}");
    assert_eq!(v["components"], 1, "{out}");
    // A catalog entry keeps its own domain and says so.
    let (_, out, _) = certmesh_in(&dir, &["mesh", "sphere", "--algo", "mc", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["domain_source"], "catalog");
    // The default is documented in --help.
    let (_, help, _) = certmesh_in(&dir, &["mesh", "--help"]);
    assert!(help.contains("[-2, 2]³"), "{help}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The ```sh blocks of README.md, line by line (comments after `  #` removed), and the
/// inline `certmesh ...` code spans outside them.
fn readme_commands() -> Vec<String> {
    let text = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let mut cmds = Vec::new();
    let mut in_sh = false;
    let mut in_other = false;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with("```") {
            if in_sh || in_other {
                in_sh = false;
                in_other = false;
            } else if t == "```sh" {
                in_sh = true;
            } else {
                in_other = true;
            }
            continue;
        }
        if in_sh {
            let cmd = match t.find("  #") {
                Some(i) => t[..i].trim(),
                None => t,
            };
            if !cmd.is_empty() && !cmd.starts_with('#') {
                cmds.push(cmd.to_string());
            }
        } else if !in_other {
            for (k, span) in t.split('`').enumerate() {
                if k % 2 == 1 && span.starts_with("certmesh ") && !cmds.contains(&span.to_string())
                {
                    cmds.push(span.to_string());
                }
            }
        }
    }
    cmds
}

/// Commands shown in the README that the test does not run as written, with what it
/// runs instead (None: not run) and why.
const README_ALLOWLIST: &[(&str, Option<&str>, &str)] = &[
    (
        "cargo run --release -- demo",
        Some("certmesh demo --quick"),
        "the full demo takes minutes in a test build; the quick demo runs the same code",
    ),
    (
        "bash .ci/run",
        None,
        "the test suite itself (it would run this test recursively)",
    ),
    (
        "pip install ./python",
        None,
        "python/run-tests.sh runs it in a virtual environment (called by .ci/run)",
    ),
];

/// The example lines of `certmesh SUB --help`: after "Example:"/"Examples:", every
/// non-empty line up to the next blank line must be a whole command (a wrapped line
/// would fail here, not silently go untested).
fn help_examples(help: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_block = false;
    for line in help.lines() {
        let t = line.trim();
        if let Some(rest) = t.strip_prefix("Example:") {
            if rest.trim().is_empty() {
                in_block = true;
            } else {
                out.push(rest.trim().to_string());
            }
            continue;
        }
        if t == "Examples:" {
            in_block = true;
            continue;
        }
        if in_block {
            if t.is_empty() {
                in_block = false;
            } else {
                out.push(t.to_string());
            }
        }
    }
    for c in &out {
        assert!(
            c.starts_with("certmesh "),
            "a help example that is not a command (wrapped?): {c}"
        );
    }
    out
}

/// Every command README.md shows (its ```sh blocks and inline `certmesh ...` spans) and
/// every example of the `--help` texts runs and exits 0, in one temporary folder with
/// the repository's data/ linked in, README first (in order: later commands read what
/// earlier ones wrote), then the help examples. A command shown in both places runs
/// once. The only commands not run as shown are in README_ALLOWLIST, with the reason.
#[test]
fn every_documented_command_runs() {
    let dir = tmp("documented");
    std::os::unix::fs::symlink(repo().join("data"), dir.join("data")).unwrap();
    let cmds = readme_commands();
    assert!(
        cmds.iter().filter(|c| c.starts_with("certmesh ")).count() >= 10,
        "{cmds:?}"
    );
    assert!(
        cmds.contains(
            &"certmesh mesh --formula \"x^2 + y^2 + z^2 - 1\" --algo mc -o sphere.obj".to_string()
        ),
        "{cmds:?}"
    );
    let mut todo: Vec<String> = Vec::new();
    for c in &cmds {
        match README_ALLOWLIST.iter().find(|(shown, _, _)| shown == c) {
            Some((_, instead, why)) => {
                eprintln!("README: `{c}` runs as {instead:?} ({why})");
                if let Some(i) = instead {
                    todo.push(i.to_string());
                }
            }
            None => {
                assert!(
                    !c.starts_with("cargo "),
                    "`{c}`: a cargo command in the README must be in README_ALLOWLIST"
                );
                todo.push(c.clone());
            }
        }
    }
    // The help examples, in this order (stats' example reads the mesh example's torus).
    let mut from_help = 0;
    for sub in [
        "surfaces",
        "algos",
        "mesh",
        "curve",
        "stats",
        "compare",
        "certify",
        "demo",
        "reproduce",
        "render",
        "figures",
    ] {
        let (code, help, err) = certmesh_in(&dir, &[sub, "--help"]);
        assert_eq!(code, 0, "{err}");
        let ex = help_examples(&help);
        assert!(!ex.is_empty(), "`certmesh {sub} --help` shows no example");
        from_help += ex.len();
        todo.extend(ex);
    }
    assert!(from_help >= 12, "{from_help} help examples");
    let mut done: Vec<&str> = Vec::new();
    for c in &todo {
        if done.contains(&c.as_str()) {
            continue;
        }
        let (code, out, err, dt) = sh_in(&dir, c);
        eprintln!("`{c}`: exit {code} in {dt:.1?}");
        assert_eq!(code, 0, "documented command `{c}` failed:\n{out}\n{err}");
        done.push(c);
    }
    // The files the README says its commands write.
    for f in [
        "sphere.obj",
        "torus.obj",
        "torus-angles.svg",
        "torus-angles.png",
        "cassini.svg",
        "ellipse.csv",
        "x.obj",
        "quartic.ply",
        "cmp.csv",
        "spot-remesh.obj",
        "out/demo/compare.json",
    ] {
        assert!(dir.join(f).exists(), "{f} was not written");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn progress_is_shown_on_a_terminal_only_and_not_with_quiet() {
    let dir = tmp("progress");
    let bunny = repo().join("data/stanford-bunny.obj");
    let args = format!(
        "stats {} --formula 'x^2 + y^2 + z^2 - 0.01'",
        bunny.display()
    );
    // stderr not a terminal (as here): nothing but the report.
    let (code, _, err, _) = sh_in(&dir, &format!("certmesh {args}"));
    assert_eq!(code, 0, "{err}");
    assert!(err.is_empty(), "progress drawn on a pipe: {err}");
    // On a terminal (util-linux `script` gives one), a run of over a second shows its
    // phases; with --quiet it does not.
    let has_script = Command::new("script").arg("--version").output().is_ok();
    if !has_script {
        eprintln!("no `script` program: the terminal half of this test is skipped");
        return;
    }
    let bin = env!("CARGO_BIN_EXE_certmesh");
    let tty = |extra: &str| {
        let out = Command::new("script")
            .args(["-qec", &format!("{bin} {extra} {args}"), "/dev/null"])
            .output()
            .unwrap();
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let shown = tty("");
    assert!(
        shown.contains("fidelity") && shown.contains("(0s)"),
        "{shown}"
    );
    let quiet = tty("--quiet");
    assert!(quiet.contains("vertices"), "{quiet}");
    assert!(!quiet.contains("fidelity ("), "{quiet}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn compare_checks_dimensions_and_writes_the_format_of_its_extension() {
    let dir = tmp("compare");
    let (code, out, err) = certmesh_in(&dir, &["compare", "--surfaces", "sphere", "--algos", "ms"]);
    assert_eq!(code, 2, "{out}");
    assert!(err.contains("'ms' meshes curves (2D) only"), "{err}");
    let (code, _, err) = certmesh_in(&dir, &["compare", "--surfaces", "circle"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("'circle' is a curve: give it with --curves"),
        "{err}"
    );
    let (code, _, err) = certmesh_in(&dir, &["compare", "--curves", "sphere"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("'sphere' is a surface: give it with --surfaces"),
        "{err}"
    );
    let base = [
        "compare",
        "--surfaces",
        "sphere",
        "--curves",
        "circle",
        "--algos",
        "mc,ms",
        "--resolution",
        "16",
    ];
    for (file, check) in [("cmp.json", "json"), ("cmp.md", "md"), ("cmp.csv", "csv")] {
        let mut args = base.to_vec();
        args.extend(["-o", file]);
        let (code, out, err) = certmesh_in(&dir, &args);
        assert_eq!(code, 0, "{err}");
        assert!(
            out.contains("| sphere | mc |") && out.contains("| circle | ms |"),
            "{out}"
        );
        assert!(
            out.contains("not run") && out.contains("ms on sphere"),
            "{out}"
        );
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        match check {
            "json" => {
                let v: serde_json::Value = serde_json::from_str(&text).expect("JSON in cmp.json");
                let rows = v.as_array().unwrap();
                assert_eq!(rows.len(), 2, "{text}");
                assert!(rows
                    .iter()
                    .any(|r| r["surface"] == "circle" && r["algo"] == "ms"));
            }
            "md" => assert!(text.starts_with("| surface | algo |"), "{text}"),
            _ => {
                let lines: Vec<&str> = text.lines().collect();
                assert_eq!(lines.len(), 3, "{text}");
                assert!(lines[0].starts_with("surface,algo,dim,"), "{text}");
                assert!(lines[1].starts_with("sphere,mc,3,true,"), "{text}");
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn stats_histogram_with_an_image_extension_writes_that_file() {
    let dir = tmp("hist");
    let spot = repo().join("data/spot.obj");
    let (code, out, err) = certmesh_in(
        &dir,
        &["stats", spot.to_str().unwrap(), "--histogram", "h.png"],
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        dir.join("h.png").exists() && dir.join("h.svg").exists(),
        "{out}"
    );
    assert!(!dir.join("h.png.png").exists() && !dir.join("h.png.svg").exists());
    let (code, _, err) = certmesh_in(
        &dir,
        &["stats", spot.to_str().unwrap(), "--histogram", "g.svg"],
    );
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("g.png").exists() && dir.join("g.svg").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn undefined_and_infinite_figures_are_reported_as_such() {
    let dir = tmp("honest");
    // pv on 1/x meshes the pole x = 0 (uncertified; the lattice meshers refuse the
    // sign change across it): f = 0 itself is empty, so no point of it is located.
    let (code, out, err) = certmesh_in(
        &dir,
        &[
            "mesh",
            "--formula",
            "1/x",
            "--domain",
            "-1.1,-1,-1,1,1,1",
            "--algo",
            "pv",
            "-o",
            "p.obj",
            "--json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["faces"].as_u64().unwrap() > 0, "{out}");
    assert_eq!(v["hausdorff"], serde_json::Value::Null, "{out}");
    let note = v["hausdorff_note"].as_str().expect("a reason");
    assert!(
        note.starts_with("undefined") && note.contains("no point of f = 0"),
        "{note}"
    );
    assert!(
        v["hausdorff_kind"].as_str().unwrap().contains("estimate"),
        "{out}"
    );
    let (_, text, _) = certmesh_in(
        &dir,
        &[
            "mesh",
            "--formula",
            "1/x",
            "--domain",
            "-1.1,-1,-1,1,1,1",
            "--algo",
            "pv",
            "-o",
            "p.obj",
        ],
    );
    assert!(
        text.contains("Hausdorff (est.)") && text.contains("| undefined |"),
        "{text}"
    );
    // stats: null in JSON with the reason, "undefined" in text; the field names stay.
    // The mesh is a square on the pole plane, as mc made before it refused the pole.
    std::fs::write(
        dir.join("p.obj"),
        "v 0.01 -1 -1\nv 0.01 1 -1\nv 0.01 1 1\nv 0.01 -1 1\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    let (code, out, err) = certmesh_in(&dir, &["stats", "p.obj", "--formula", "1/x", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for k in [
        "hausdorff",
        "hausdorff_mesh_to_surface",
        "hausdorff_surface_to_mesh",
    ] {
        assert_eq!(v[k], serde_json::Value::Null, "{k}: {out}");
        assert!(v["fidelity_undefined"][k].as_str().is_some(), "{k}: {out}");
    }
    // The normals cannot be compared with ∇f on f = 0 either (no centre projects).
    assert_eq!(v["normal_dev_max_deg"], serde_json::Value::Null, "{out}");
    assert!(
        v["fidelity_undefined"]["normal_dev_max_deg"]
            .as_str()
            .is_some(),
        "{out}"
    );
    let (_, text, _) = certmesh_in(&dir, &["stats", "p.obj", "--formula", "1/x"]);
    assert!(text.contains("Hausdorff (est.) ≈ undefined"), "{text}");
    assert!(text.contains("normal deviation max undefined"), "{text}");
    // f ≡ 0: every point is on f = 0 (distance 0 is measured, not assumed), but there is
    // no normal to compare with: undefined, not 0.
    let (_, out, _) = certmesh_in(&dir, &["stats", "p.obj", "--formula", "0", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["hausdorff_mesh_to_surface"], 0.0, "{out}");
    assert!(
        v["hausdorff_surface_to_mesh"].as_f64().unwrap() > 0.1,
        "{out}"
    );
    assert_eq!(v["normal_dev_max_deg"], serde_json::Value::Null, "{out}");
    assert!(
        v["fidelity_undefined"]["normal_dev_max_deg"]
            .as_str()
            .unwrap()
            .contains("∇f"),
        "{out}"
    );
    // A regular case has every figure, and no reasons.
    let (_, out, _) = certmesh_in(
        &dir,
        &[
            "mesh",
            "sphere",
            "--algo",
            "mc",
            "--resolution",
            "24",
            "-o",
            "s.obj",
        ],
    );
    assert!(out.contains("wrote s.obj"), "{out}");
    let (_, out, _) = certmesh_in(&dir, &["stats", "s.obj", "--surface", "sphere", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["hausdorff"].as_f64().unwrap() < 0.05, "{out}");
    assert_eq!(v["fidelity_undefined"], serde_json::json!({}), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_run_stopped_by_its_box_budget_says_so() {
    let dir = tmp("budget");
    let t0 = Instant::now();
    let (code, out, err) = certmesh_in(
        &dir,
        &[
            "mesh",
            "--formula",
            "(x^2 + y^2 + z^2 - 0.25)^2",
            "--domain",
            "-1,-1,-1,1,1,1",
            "--algo",
            "pv",
            "--max-boxes",
            "2000",
            "-o",
            "x.obj",
            "--json",
        ],
    );
    let dt = t0.elapsed();
    assert_eq!(code, 0, "{err}");
    assert!(dt < Duration::from_secs(20), "took {dt:?}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["certified"], false, "{out}");
    assert_eq!(v["certificate"]["status"], "uncertified");
    assert_eq!(v["stats"]["refinement_complete"], false);
    assert_eq!(v["refinement_complete"], false);
    assert_eq!(v["stopped"], "box budget exhausted (raise --max-boxes)");
    let (code, text, _) = certmesh_in(
        &dir,
        &[
            "mesh",
            "--formula",
            "(x^2 + y^2 + z^2 - 0.25)^2",
            "--domain",
            "-1,-1,-1,1,1,1",
            "--algo",
            "pv",
            "--max-boxes",
            "2000",
            "-o",
            "x.obj",
        ],
    );
    assert_eq!(code, 0);
    assert!(
        text.contains(
            "stopped before the refinement was complete: box budget exhausted (raise --max-boxes)"
        ),
        "{text}"
    );
    assert!(!text.contains("proven:"), "{text}");
    // A complete run has no `stopped`.
    let (_, out, _) = certmesh_in(&dir, &["mesh", "sphere", "--algo", "pv", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["stopped"], serde_json::Value::Null, "{out}");
    assert_eq!(v["refinement_complete"], true, "{out}");
    // The options are documented and checked.
    let (_, help, _) = certmesh_in(&dir, &["mesh", "--help"]);
    assert!(
        help.contains("--max-boxes") && help.contains("refinement_complete: false"),
        "{help}"
    );
    assert!(help.contains("--time-limit"), "{help}");
    let (code, _, err) = certmesh_in(
        &dir,
        &["mesh", "sphere", "--algo", "pv", "--time-limit", "-1"],
    );
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = certmesh_in(
        &dir,
        &["mesh", "sphere", "--algo", "pv", "--max-boxes", "0"],
    );
    assert_eq!(code, 2, "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// An option the chosen mesher does not read is an error naming both (it used to be
/// ignored silently); in a comparison each option must be read by one of the meshers
/// run, and goes only to those that read it.
#[test]
fn options_a_mesher_does_not_read_are_errors() {
    let (code, out, _) = certmesh(&[
        "mesh",
        "sphere",
        "--algo",
        "pv",
        "--resolution",
        "32",
        "--json",
    ]);
    assert_eq!(code, 2, "{out}");
    let e = json_error(&out);
    let msg = e["error"].as_str().unwrap();
    assert!(
        msg.contains("--resolution") && msg.contains("'pv'"),
        "{msg}"
    );
    let (code, _, err) = certmesh(&["mesh", "sphere", "--algo", "mc", "--max-depth", "5"]);
    assert_eq!(code, 2);
    assert!(err.contains("--max-depth") && err.contains("'mc'"), "{err}");
    // Read by one of the two: accepted, and mc still runs at that resolution.
    let (code, out, err) = certmesh(&[
        "compare",
        "--surfaces",
        "sphere",
        "--algos",
        "mc,pv",
        "--resolution",
        "12",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let rows: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(rows.as_array().unwrap().len(), 2);
    // Read by neither.
    let (code, _, err) = certmesh(&[
        "compare",
        "--surfaces",
        "sphere",
        "--algos",
        "mc,pv",
        "--graded",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--graded"), "{err}");
}

// ---------------------------------------------------------------------------------
// morse

/// `certmesh morse`: the tanglecube's 27 critical points with values and indices,
/// χ = −8 by both certificates (hand derivation in tests/morse.rs).
#[test]
fn morse_tanglecube_json() {
    let (code, out, err) = certmesh(&["morse", "tanglecube", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["surface"], "tanglecube");
    assert_eq!(v["domain_source"], "catalog");
    assert_eq!(v["gradient"]["points"].as_array().unwrap().len(), 27);
    assert_eq!(
        v["gradient"]["index_counts"],
        serde_json::json!([8, 12, 6, 1])
    );
    assert_eq!(v["gradient"]["morse"], true);
    assert_eq!(v["sublevel"]["chi_sublevel"], -4);
    assert_eq!(v["sublevel"]["chi_surface"], -8);
    assert_eq!(v["height"]["chi"], -8);
    assert_eq!(v["chi"], -8);
    assert_eq!(v["expected_chi"], -8);
    let p = &v["gradient"]["points"][0];
    assert_eq!(p["kind"], "minimum");
    assert_eq!(p["side"], "below");
    assert!(p["value"][0].as_f64().unwrap() <= -6.95 && -6.95 <= p["value"][1].as_f64().unwrap());
    // The text report says the same.
    let (code, out, _) = certmesh(&["morse", "tanglecube"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("chi({f <= 0}) = 8 - 12 + 0 - 0 = -4: certified"),
        "{out}"
    );
    assert!(
        out.contains("chi(S) = -8: certified (by sublevel and height)"),
        "{out}"
    );
}

/// The torus is reported not Morse for f (its circle of minima), with no χ from f,
/// and χ = 0 certified by the generic height; beside it a mesh's χ.
#[test]
fn morse_torus_not_morse_and_mesh_chi() {
    let dir = tmp("morse-torus");
    let (code, _, err) = certmesh_in(&dir, &["mesh", "torus", "--algo", "pv", "-o", "t.obj"]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = certmesh_in(
        &dir,
        &[
            "morse",
            "torus",
            "--max-boxes",
            "20000",
            "--mesh",
            "t.obj",
            "--json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["gradient"]["morse"], false);
    assert!(v["gradient"]["not_morse_reason"]
        .as_str()
        .unwrap()
        .contains("possibly"));
    assert!(
        v["gradient"]["undecided"]["by_reason"]["possibly-degenerate"]
            .as_u64()
            .unwrap()
            > 0
    );
    assert!(v["sublevel"]["chi_surface"].is_null());
    assert!(v["sublevel"]["reason"]
        .as_str()
        .unwrap()
        .contains("not proven Morse"));
    assert_eq!(v["height"]["chi"], 0);
    assert_eq!(v["chi"], 0);
    assert_eq!(v["mesh"]["euler_characteristic"], 0);
    assert_eq!(v["mesh"]["agrees"], true);
    let (code, out, _) = certmesh_in(
        &dir,
        &["morse", "torus", "--max-boxes", "20000", "--mesh", "t.obj"],
    );
    assert_eq!(code, 0);
    assert!(out.contains("f is NOT proven Morse"), "{out}");
    assert!(out.contains("agrees with the certified chi(S)"), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A formula with an axis height: the sphere's two poles; a domain cutting S gives
/// nothing certified; bad options are JSON errors with exit 2.
#[test]
fn morse_formula_height_and_errors() {
    let (code, out, err) = certmesh(&[
        "morse",
        "--formula",
        "x^2 + y^2 + z^2 - 1",
        "--height",
        "0,0,1",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["domain_source"], "default");
    assert_eq!(v["height"]["minima"], 1);
    assert_eq!(v["height"]["maxima"], 1);
    assert_eq!(v["chi"], 2);
    let top = &v["height"]["points"][1];
    assert!(
        (top["point"][2].as_f64().unwrap() - 1.0).abs() < 1e-9,
        "{top}"
    );
    let (code, out, _) = certmesh(&[
        "morse",
        "--formula",
        "x^2 + y^2 + z^2 - 1",
        "--domain",
        "0,-2,-2,2,2,2",
        "--json",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["chi"].is_null());
    assert!(v["sublevel"]["reason"]
        .as_str()
        .unwrap()
        .contains("boundary"));
    for bad in [
        vec!["morse", "sphere", "--height", "0,0,0", "--json"],
        vec!["morse", "sphere", "--height", "1,2", "--json"],
        vec!["morse", "sphere", "--max-boxes", "0", "--json"],
        vec!["morse", "--formula", "x^2 + * y", "--json"],
        vec!["morse", "circle", "--json"],
        vec!["morse", "nosuch", "--json"],
        vec!["morse", "sphere", "--mesh", "/nonexistent/m.obj", "--json"],
    ] {
        let (code, out, _) = certmesh(&bad);
        assert_eq!(code, 2, "{bad:?}: {out}");
        json_error(&out);
    }
}

/// Every example of `certmesh morse --help` runs (the torus mesh first, which the
/// last example reads).
#[test]
fn morse_help_examples_run() {
    let dir = tmp("morse-help");
    let (code, help, err) = certmesh_in(&dir, &["morse", "--help"]);
    assert_eq!(code, 0, "{err}");
    let ex = help_examples(&help);
    assert!(ex.len() >= 4, "{ex:?}");
    let (code, _, err) = certmesh_in(
        &dir,
        &[
            "mesh",
            "torus",
            "--algo",
            "mc",
            "--resolution",
            "32",
            "-o",
            "torus.obj",
        ],
    );
    assert_eq!(code, 0, "{err}");
    for c in &ex {
        let (code, out, err, dt) = sh_in(&dir, c);
        eprintln!("`{c}`: exit {code} in {dt:.1?}");
        assert_eq!(code, 0, "help example `{c}` failed:\n{out}\n{err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `--algo stander-hart`: listed by `algos`, the sweep's levels in the JSON stats,
/// certified on the tanglecube; a bad --set is an error with exit 2.
#[test]
fn stander_hart_from_the_command_line() {
    let (code, out, _) = certmesh(&["algos"]);
    assert_eq!(code, 0);
    assert!(out.contains("stander-hart"), "{out}");
    let dir = tmp("stander-hart");
    let (code, out, err) = certmesh_in(
        &dir,
        &[
            "mesh",
            "tanglecube",
            "--algo",
            "stander-hart",
            "-o",
            "t.obj",
            "--json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["certified"], true);
    assert_eq!(v["topology_ok"], true);
    assert_eq!(v["mesh_chi"], -8);
    let sh = &v["stats"]["stander_hart"];
    assert_eq!(sh["levels"].as_array().unwrap().len(), 3);
    assert_eq!(sh["chi_predicted"], -8);
    assert!(dir.join("t.obj").exists());
    let (code, out, _) = certmesh_in(
        &dir,
        &[
            "mesh",
            "sphere",
            "--algo",
            "stander-hart",
            "--set",
            "steps=0",
            "-o",
            "s.obj",
            "--json",
        ],
    );
    assert_eq!(code, 2, "{out}");
    json_error(&out);
    std::fs::remove_dir_all(&dir).ok();
}

/// An uncertified stander-hart run lists no claim as made, in the text report (no
/// "proven:" line) or in --json (`claims` empty): on the torus f is not proven Morse,
/// so the sweep is not certified, though its last level is a certified PV mesh. That
/// level's own claims are in the stats (`last_level_claims`), and the stats'
/// `certified` list leaves out the critical data it could not certify.
#[test]
fn an_uncertified_stander_hart_run_lists_no_claims() {
    let args = [
        "mesh",
        "torus",
        "--algo",
        "stander-hart",
        "--metrics",
        "none",
    ];
    let (code, out, err) = certmesh(&[&args[..], &["--json"]].concat());
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["certified"], false, "{out}");
    let cert = &v["certificate"];
    assert_eq!(cert["status"], "uncertified", "{cert}");
    assert_eq!(cert["claims"], serde_json::json!([]), "{cert}");
    assert!(
        cert["claims_typed"].as_array().is_none_or(|c| c.is_empty()),
        "{cert}"
    );
    let sh = &v["stats"]["stander_hart"];
    assert_eq!(sh["critical_data_certified"], false);
    let certified = sh["certified"].to_string();
    assert!(!certified.contains("critical points"), "{certified}");
    assert!(
        sh["not_certified"].to_string().contains("critical data"),
        "{sh}"
    );
    // The last level is PV's certified mesh of f = 0: its claims are kept, as its.
    let last = sh["levels"].as_array().unwrap().last().unwrap().clone();
    assert_eq!(last["certified"], true, "{last}");
    assert!(
        sh["last_level_claims"].to_string().contains("isotopic"),
        "{sh}"
    );
    let (code, out, err) = certmesh(&args);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("uncertified"), "{out}");
    assert!(!out.contains("proven:"), "{out}");
}

/// `--algo bcsv`: certified isotopic on the sphere (Theorem B: the census χ(S) = 2
/// equals χ(Ŝ)); with a census budget of one box only W-certified, never certified;
/// the attempts in the JSON stats; a bad --resolution is an error.
#[test]
fn bcsv_from_the_command_line() {
    let dir = tmp("bcsv");
    let (code, out, err) = certmesh_in(
        &dir,
        &["mesh", "sphere", "--algo", "bcsv", "-o", "s.obj", "--json"],
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["certified"], true);
    assert_eq!(v["topology_ok"], true);
    assert_eq!(v["stats"]["isotopy_certified"], true);
    assert_eq!(v["stats"]["chi_certified"], 2);
    assert!(v["stats"]["attempts"].as_array().unwrap().len() >= 1);
    let (code, out, err) = certmesh_in(
        &dir,
        &[
            "mesh",
            "sphere",
            "--algo",
            "bcsv",
            "--set",
            "census-boxes=1",
            "-o",
            "s.obj",
            "--json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["certified"], false);
    assert_eq!(v["stats"]["w_certified"], true);
    assert!(v["certificate"]["reason"]
        .as_str()
        .unwrap()
        .starts_with("W-certified"));
    let (code, out, _) = certmesh_in(
        &dir,
        &[
            "mesh",
            "sphere",
            "--algo",
            "bcsv",
            "--resolution",
            "2",
            "-o",
            "s.obj",
            "--json",
        ],
    );
    assert_eq!(code, 2, "{out}");
    json_error(&out);
    std::fs::remove_dir_all(&dir).ok();
}

// ---------------------------------------------------------------------------------
// certmesh delaunay

#[test]
fn delaunay_random_points_are_built_checked_and_reported() {
    for on in ["uniform", "sphere", "torus"] {
        let (code, out, err) = certmesh(&[
            "delaunay", "--random", "300", "--on", on, "--seed", "4", "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["n_points"], 300, "{out}");
        assert_eq!(v["n_inserted"], 300, "{out}");
        assert_eq!(v["valid"], true, "{out}");
        assert_eq!(v["check"]["non_positive_cells"], 0);
        assert_eq!(v["check"]["non_delaunay_facets"], 0);
        // A 3-ball: V - E + F - T = 1, every cell counted.
        assert_eq!(v["check"]["euler_characteristic"], 1);
        assert_eq!(v["cells"], v["check"]["cells"]);
        assert!(v["points_per_second"].as_f64().unwrap() > 0.0);
        assert!(v["memory_bytes"].as_u64().unwrap() > 300 * 24);
    }
    let (code, out, _) = certmesh(&["delaunay", "--random", "200"]);
    assert_eq!(code, 0);
    assert!(out.contains("points/s") && out.contains("valid"), "{out}");
}

#[test]
fn delaunay_point_file_to_vtk_and_duplicates() {
    let dir = tmp("delaunay");
    // A 3x3x3 integer grid (massive ties) plus one duplicate.
    let mut s = String::from("# grid\n");
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                s += &format!("{i} {j} {k}\n");
            }
        }
    }
    s += "1 1 1\n";
    std::fs::write(dir.join("g.xyz"), s).unwrap();
    let (code, out, err) = certmesh_in(&dir, &["delaunay", "g.xyz", "-o", "t.vtk", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["n_points"], 28);
    assert_eq!(v["n_inserted"], 27);
    assert_eq!(v["duplicates"], serde_json::json!([27]));
    assert_eq!(v["valid"], true);
    // The written tetrahedra fill the grid's cube: total volume 8.
    let m = certmesh::io::read_tet(dir.join("t.vtk")).unwrap();
    let vol: f64 = m
        .tets
        .iter()
        .map(|t| {
            let p = t.map(|i| m.vertices[i as usize]);
            let d = |a: [f64; 3], b: [f64; 3]| [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let (a, b, c) = (d(p[0], p[1]), d(p[0], p[2]), d(p[0], p[3]));
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                .abs()
                / 6.0
        })
        .sum();
    assert!((vol - 8.0).abs() < 1e-9, "volume {vol}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn delaunay_errors_are_clear() {
    let dir = tmp("delaunay-err");
    std::fs::write(dir.join("bad.xyz"), "0 0 0\n1 0 0\n0 1\n").unwrap();
    std::fs::write(dir.join("nan.xyz"), "0 0 0\n1 nan 0\n").unwrap();
    let (code, _, err) = certmesh_in(&dir, &["delaunay", "bad.xyz"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("line 3") && err.contains("three coordinates"),
        "{err}"
    );
    let cases: Vec<(Vec<&str>, &str, serde_json::Value)> = vec![
        (
            vec!["delaunay", "bad.xyz", "--json"],
            "file",
            serde_json::json!(3),
        ),
        (
            vec!["delaunay", "nan.xyz", "--json"],
            "file",
            serde_json::json!(2),
        ),
        (
            vec!["delaunay", "missing.xyz", "--json"],
            "io",
            serde_json::Value::Null,
        ),
        (
            vec!["delaunay", "--random", "10", "--on", "cube", "--json"],
            "unknown-name",
            serde_json::Value::Null,
        ),
        (
            vec!["delaunay", "--random", "10", "-o", "t.obj", "--json"],
            "parameter",
            serde_json::Value::Null,
        ),
        (
            vec!["delaunay", "--json"],
            "parameter",
            serde_json::Value::Null,
        ),
        (
            vec!["delaunay", "--random", "x", "--json"],
            "usage",
            serde_json::Value::Null,
        ),
        (
            vec!["delaunay", "--random", "999999999999", "--json"],
            "too-large",
            serde_json::Value::Null,
        ),
    ];
    for (args, kind, pos) in cases {
        let (code, out, _) = certmesh_in(&dir, &args);
        assert_eq!(code, 2, "{args:?}: {out}");
        let v = json_error(&out);
        assert_eq!(v["kind"], kind, "{args:?}: {out}");
        assert_eq!(v["position"], pos, "{args:?}: {out}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `--metrics` (issue 20): `fast` (the default) and `full` give the same report but for
/// the Hausdorff estimate, which `fast` takes over a sample sized to this small mesh:
/// every 39th of `full`'s 20,000 mesh samples, without the vertices, refined on the
/// triangles of the largest distances, and the surface
/// points of a 12³ seed grid instead of 40³ (and says so: `hausdorff_kind`,
/// `hausdorff_mesh_samples`, `hausdorff_surface_samples`); `none` keeps every key,
/// leaves topology and Hausdorff empty and says why; other levels are refused.
#[test]
fn metrics_levels_keep_the_keys() {
    let run = |level: Option<&str>| {
        let mut args = vec![
            "mesh",
            "torus",
            "--algo",
            "mc",
            "--resolution",
            "24",
            "--json",
        ];
        if let Some(l) = level {
            args.extend(["--metrics", l]);
        }
        let (code, out, err) = certmesh(&args);
        assert_eq!(code, 0, "{err}");
        let mut v: serde_json::Value = serde_json::from_str(&out).expect("json");
        let o = v.as_object_mut().unwrap();
        o.remove("seconds");
        // The report's own wall time, beside the mesher's.
        let t = o.remove("metrics_seconds").expect("metrics_seconds");
        assert!(t.as_f64().is_some_and(|t| t >= 0.0 && t < 60.0), "{t}");
        v
    };
    let (default, fast, full, none) = (
        run(None),
        run(Some("fast")),
        run(Some("full")),
        run(Some("none")),
    );
    assert_eq!(default, fast);
    let (hf, hu) = (
        fast["hausdorff"].as_f64().unwrap(),
        full["hausdorff"].as_f64().unwrap(),
    );
    // Two estimates of one distance from different samples: close, not ordered (the
    // surface sides come from different seeds).
    assert!(
        hf > 0.0 && hf <= 2.0 * hu && hf >= 0.5 * hu,
        "fast {hf}, full {hu}"
    );
    assert!(fast["hausdorff_kind"]
        .as_str()
        .unwrap()
        .contains("sampled estimate"));
    assert!(fast["hausdorff_kind"]
        .as_str()
        .unwrap()
        .contains("vertices left out"));
    assert!(fast["hausdorff_kind"]
        .as_str()
        .unwrap()
        .contains("sized to the mesh"));
    assert!(!full["hausdorff_kind"].as_str().unwrap().contains("sampled"));
    // Samples 19, 58, ..., 19 + 39·512 of the 20,000 (all converge on this torus), then
    // the corners and the other samples of the triangles of the 32 largest distances.
    let n = fast["hausdorff_mesh_samples"].as_u64().unwrap();
    assert!(n > 513 && n < 513 + 32 * 3 + 2_000, "{n} mesh samples");
    assert!(full["hausdorff_mesh_samples"].as_u64().unwrap() > 20_000);
    let (sf, su) = (
        fast["hausdorff_surface_samples"].as_u64().unwrap(),
        full["hausdorff_surface_samples"].as_u64().unwrap(),
    );
    assert!(
        sf > 500 && 4 * sf < su,
        "fast {sf}, full {su} surface points"
    );
    let rest = |v: &serde_json::Value| {
        let mut v = v.clone();
        let o = v.as_object_mut().unwrap();
        for k in [
            "hausdorff",
            "hausdorff_kind",
            "hausdorff_mesh_samples",
            "hausdorff_surface_samples",
        ] {
            o.remove(k);
        }
        v
    };
    assert_eq!(rest(&fast), rest(&full));
    assert_eq!(fast["topology_ok"], serde_json::json!(true));
    let keys = |v: &serde_json::Value| v.as_object().unwrap().keys().cloned().collect::<Vec<_>>();
    assert_eq!(keys(&none), keys(&fast));
    assert!(none["hausdorff"].is_null() && none["topology_ok"].is_null());
    assert_eq!(
        none["hausdorff_note"],
        serde_json::json!("not computed (--metrics none)")
    );
    assert_eq!(none["faces"], fast["faces"]);
    let (code, _, err) = certmesh(&["mesh", "torus", "--algo", "mc", "--metrics", "most"]);
    assert_eq!(code, 2);
    assert!(err.contains("most"), "{err}");
}

/// `certmesh mesh -o out.ply` where out.ply is a FIFO with a reader: the reader gets
/// the whole mesh, the same bytes as a file. (The check made before the work used to
/// open the FIFO and close it again, which ended the reader's input, so the writer
/// then waited for a reader forever; `timeout` turns such a wait into a failure.)
#[cfg(unix)]
#[test]
fn mesh_output_into_a_fifo() {
    let d = tmp("fifo");
    let (rc, _, err, _) = sh_in(
        &d,
        "mkfifo out.ply && { cat out.ply > got.ply & } && \
         timeout 60 certmesh mesh sphere --algo mc -o out.ply --json > run.json; \
         rc=$?; wait; exit $rc",
    );
    assert_eq!(rc, 0, "{err}");
    let (rc, _, err) = certmesh_in(&d, &["mesh", "sphere", "--algo", "mc", "-o", "file.ply"]);
    assert_eq!(rc, 0, "{err}");
    let (got, want) = (
        std::fs::read(d.join("got.ply")).unwrap(),
        std::fs::read(d.join("file.ply")).unwrap(),
    );
    assert!(
        !want.is_empty() && got == want,
        "{} bytes through the FIFO, {} in the file",
        got.len(),
        want.len()
    );
    std::fs::remove_dir_all(&d).ok();
}

/// Arguments that look like options (found by an adversarial run): a formula that
/// starts with a minus sign is a formula, a negative number is the option's value and
/// gets that option's range error, a missing argument is named in the JSON error, and
/// a time limit past what the clock can hold is no limit (it used to panic).
#[test]
fn leading_minus_signs_and_huge_time_limits() {
    let dir = tmp("minus");
    let out = dir.join("s.ply");
    let out = out.to_str().unwrap();
    let (code, stdout, err) = certmesh(&[
        "mesh",
        "--formula",
        "-x^2 - y^2 - z^2 + 1",
        "--algo",
        "mc",
        "--resolution",
        "12",
        "-q",
        "--json",
        "-o",
        out,
    ]);
    assert_eq!(code, 0, "{stdout}{err}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["found"], "1 component, genus [0]", "{stdout}");
    let (code, stdout, _) = certmesh(&[
        "mesh",
        "sphere",
        "--algo",
        "pv",
        "--time-limit",
        "-1",
        "--json",
        "-o",
        out,
    ]);
    assert_eq!(code, 2, "{stdout}");
    let e = json_error(&stdout);
    assert!(
        e["error"]
            .as_str()
            .unwrap()
            .contains("--time-limit must be a positive"),
        "{e}"
    );
    let (code, stdout, _) = certmesh(&["mesh", "sphere", "--margin", "0.1", "--json", "-o", out]);
    assert_eq!(code, 2, "{stdout}");
    let e = json_error(&stdout);
    assert!(e["error"].as_str().unwrap().contains("--mesh-input"), "{e}");
    for limit in ["1e19", "1e300"] {
        let (code, stdout, err) = certmesh(&[
            "mesh",
            "sphere",
            "--algo",
            "pv",
            "--time-limit",
            limit,
            "-q",
            "--json",
            "-o",
            out,
        ]);
        assert_eq!(code, 0, "--time-limit {limit}: {stdout}{err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Refused before any work (found by an adversarial run): a --domain whose width
/// overflows (it ran 31 s, then failed on NaN coordinates), and a Delaunay run whose
/// estimated heap exceeds the limit (10⁸ random points, about 50 GB, was accepted).
#[test]
fn overflowing_domains_and_huge_point_counts_are_refused_up_front() {
    let dir = tmp("upfront");
    let t0 = Instant::now();
    let (code, out, _) = certmesh_in(
        &dir,
        &[
            "mesh",
            "sphere",
            "--algo",
            "pv",
            "--domain=-1e308,-1e308,-1e308,1e308,1e308,1e308",
            "--json",
            "-o",
            "x.ply",
        ],
    );
    assert_eq!(code, 2, "{out}");
    let e = json_error(&out);
    assert_eq!(e["kind"], "domain", "{e}");
    assert!(e["error"].as_str().unwrap().contains("overflows"), "{e}");
    let (code, out, _) = certmesh_in(&dir, &["delaunay", "--random", "100000000", "--json"]);
    assert_eq!(code, 2, "{out}");
    let e = json_error(&out);
    assert_eq!(e["kind"], "too-large", "{e}");
    assert!(e["error"].as_str().unwrap().contains("GB"), "{e}");
    assert!(t0.elapsed() < Duration::from_secs(20), "{:?}", t0.elapsed());
    std::fs::remove_dir_all(&dir).ok();
}

/// A render the input cannot satisfy is an input error (exit 2, like every bad
/// parameter), not a failure during the work (exit 1): `--color certificate` on a mesh
/// file (which carries no certificate), and a mesh with no faces.
#[test]
fn render_errors_of_the_input_exit_2() {
    let d = tmp("render-input");
    std::fs::write(d.join("empty.obj"), "").unwrap();
    let spot = repo().join("data/spot.obj");
    for (args, says) in [
        (
            vec![
                spot.to_str().unwrap(),
                "--color",
                "certificate",
                "-o",
                "a.svg",
            ],
            "certificate",
        ),
        (vec!["empty.obj", "-o", "b.svg"], "no faces"),
    ] {
        let mut all = vec!["render"];
        all.extend(args);
        let (code, out, err) = certmesh_in(&d, &all);
        assert_eq!(code, 2, "{all:?}: {out}{err}");
        assert!(err.contains(says), "{all:?}: {err}");
        assert!(!d.join("a.svg").exists() && !d.join("b.svg").exists());
    }
    std::fs::remove_dir_all(&d).unwrap();
}

/// A refinement mesher stopped by a guard: the report names the guard (the mesher's
/// own stop reason), not "a work budget was spent".
#[test]
fn the_report_names_the_guard_that_stopped_bo() {
    let d = tmp("bo-guard");
    let (code, out, err) = certmesh_in(
        &d,
        &[
            "mesh",
            "sphere",
            "--algo",
            "bo",
            "--max-vertices",
            "60",
            "-o",
            "s.ply",
            "--json",
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let stopped = v["stopped"].as_str().expect("stopped");
    assert!(stopped.contains("--max-vertices"), "{stopped}");
    std::fs::remove_dir_all(&d).unwrap();
}

/// A bo facet size below the scale of its seed triangles (radius facet-size / 4, never
/// below 1e-9 of the domain's diagonal) is a parameter error (exit 2) that names the
/// facet size and the smallest usable one, not "found no point of f = 0" (the sphere
/// has points: bo placed no seed triangle and its output was empty). The smallest
/// usable value it names is accepted, and a value just below it refused.
#[test]
fn a_bo_facet_size_below_the_seed_scale_is_a_parameter_error() {
    let d = tmp("bo-tiny-facet");
    // `certmesh mesh sphere --algo bo` with more arguments, in `d`.
    let bo = |more: &[&str]| {
        certmesh_in(
            &d,
            &[&["mesh", "sphere", "--algo", "bo"][..], more].concat(),
        )
    };
    let (code, out, err) = bo(&["--facet-size", "1e-20", "--json"]);
    assert_eq!(code, 2, "{out}{err}");
    let v = json_error(&out);
    assert_eq!(v["kind"], "parameter", "{out}");
    let msg = v["error"].as_str().unwrap();
    assert!(
        msg.contains("--facet-size 1e-20 is too small") && !msg.contains("found no point"),
        "{msg}"
    );
    // The smallest usable value, as printed, is 4e-9 x the diagonal of the sphere's
    // catalog domain [-1.5, 1.5]^3, rounded up.
    let smallest = msg
        .split("smallest usable --facet-size here is ")
        .nth(1)
        .and_then(|t| t.split_whitespace().next())
        .unwrap_or_else(|| panic!("no smallest value in: {msg}"));
    let x: f64 = smallest.parse().unwrap();
    let floor = 4e-9 * (27.0f64).sqrt();
    assert!(x >= floor && x < 1.01 * floor, "{smallest} vs {floor}");
    // --seed-radius likewise names itself.
    let (code, out, _) = bo(&["--set", "seed-radius=1e-12", "--json"]);
    assert_eq!(code, 2, "{out}");
    let v = json_error(&out);
    assert!(
        v["error"]
            .as_str()
            .unwrap()
            .contains("seed-radius=1e-12 is too small"),
        "{out}"
    );
    // Just below the smallest value: refused; at it: meshed (stopped by the vertex
    // budget, with a partial output).
    let below = format!("{}", 0.999 * floor);
    let (code, out, _) = bo(&["--facet-size", &below, "--json"]);
    assert_eq!(code, 2, "{out}");
    let (code, out, err) = bo(&["--facet-size", smallest, "--max-vertices", "200", "--json"]);
    assert_eq!(code, 0, "{out}{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(
        v["stopped"]
            .as_str()
            .is_some_and(|s| s.contains("--max-vertices")),
        "{out}"
    );
    std::fs::remove_dir_all(&d).unwrap();
}

/// An empty zero set is an error (exit 2, kind `empty-zero-set`) that says whether the
/// emptiness is proven (pv, snyder, the exact sweep) or only not seen (a lattice mesher),
/// and writes no file. A sphere that fits between two grid vertices of mc at resolution
/// 4 is "not seen", and pv then meshes it: the uncertified message must not claim more.
#[test]
fn an_empty_zero_set_is_an_error_that_says_whether_it_is_proven() {
    let dir = std::env::temp_dir().join(format!("certmesh-empty-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("e.ply");
    let o = out.to_str().unwrap();
    for (algo, proven) in [
        ("pv", true),
        ("snyder", true),
        ("mc", false),
        ("gradnormal", false),
    ] {
        let (code, stdout, err) = certmesh(&[
            "mesh",
            "--formula",
            "x^2 + y^2 + z^2 + 1",
            "--algo",
            algo,
            "-o",
            o,
            "--json",
        ]);
        assert_eq!(code, 2, "{algo}: {stdout}{err}");
        let v: serde_json::Value = serde_json::from_str(&stdout).expect("JSON error");
        assert_eq!(v["kind"], "empty-zero-set", "{algo}: {v}");
        let msg = v["error"].as_str().unwrap();
        assert_eq!(msg.contains("proven by"), proven, "{algo}: {msg}");
        assert_eq!(msg.contains("not proven empty"), !proven, "{algo}: {msg}");
        assert!(
            msg.contains("[-2, 2] × [-2, 2] × [-2, 2]") && msg.contains("--domain"),
            "{msg}"
        );
        assert!(!out.exists(), "{algo} wrote a file");
    }
    // A small sphere between mc's grid vertices: not seen by mc, found by pv.
    let small = [
        "--formula",
        "(x - 0.5)^2 + (y - 0.5)^2 + (z - 0.5)^2 - 0.01",
    ];
    let (code, _, err) = certmesh(
        &[
            &["mesh"][..],
            &small[..],
            &["--algo", "mc", "--resolution", "4", "-o", o],
        ]
        .concat(),
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("not proven empty"), "{err}");
    let (code, stdout, err) =
        certmesh(&[&["mesh"][..], &small[..], &["--algo", "pv", "-o", o, "-q"]].concat());
    assert_eq!(code, 0, "{stdout}{err}");
    assert!(out.exists());
    // Curves: the exact sweep proves x² + y² + 1 = 0 empty.
    let (code, _, err) = certmesh(&[
        "curve",
        "--formula",
        "x^2 + y^2 + 1",
        "--algo",
        "gvn",
        "-o",
        dir.join("e.svg").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("proven by 'sweep'") && err.contains("no curve"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `morse` has a wall-clock limit per search (default 60 s): with a box budget that
/// would run for minutes on the double sphere (a degenerate critical set everywhere
/// on S), each search stops at the limit, reports its remaining boxes as "time-limit",
/// and certifies nothing; a non-positive limit is refused.
#[test]
fn morse_searches_stop_at_their_time_limit() {
    let args = [
        "morse",
        "--formula",
        "(x^2 + y^2 + z^2 - 0.25)^2",
        "--domain",
        "-1,-1,-1,1,1,1",
        "--max-boxes",
        "1000000000000",
        "--max-depth",
        "60",
        "--json",
        "--time-limit",
    ];
    let (code, out, err) = certmesh(&[&args[..], &["0.5"]].concat());
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for search in ["gradient", "height"] {
        let n = v[search]["undecided"]["by_reason"]["time-limit"].as_u64();
        assert!(
            n.is_some_and(|n| n > 0),
            "{search}: {}",
            v[search]["undecided"]
        );
    }
    assert!(v["chi"].is_null(), "{}", v["chi"]);
    let (code, out, err) = certmesh(&[&args[..], &["0"]].concat());
    assert_eq!(code, 2, "{out}{err}");
    assert!(out.contains("--time-limit"), "{out}");
    // stander-hart's own search for grad f = 0 stops at the mesher's --time-limit.
    let (code, out, err) = certmesh(&[
        "mesh",
        "--formula",
        "(x^2 + y^2 + z^2 - 0.25)^2",
        "--domain",
        "-1,-1,-1,1,1,1",
        "--algo",
        "stander-hart",
        "--set",
        "gradient-boxes=1000000000000",
        "--set",
        "gradient-depth=60",
        "--time-limit",
        "0.5",
        "--metrics",
        "none",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["certified"], false);
    assert!(
        v["reason"].as_str().unwrap().contains("time-limit"),
        "{}",
        v["reason"]
    );
}

/// `certify --time-limit`: a limit that passes before the checks leaves them not run
/// and the verdict says so (exit 0, not certified); a limit of 0 is refused (exit 2).
#[test]
fn certify_stops_at_its_time_limit() {
    let dir = tmp("certify-time");
    let (code, _, err) = certmesh_in(
        &dir,
        &["mesh", "sphere", "--algo", "cdrr", "-o", "s.obj", "-q"],
    );
    assert_eq!(code, 0, "{err}");
    let certify = |limit: &str| {
        certmesh_in(
            &dir,
            &[
                "certify",
                "s.obj",
                "--surface",
                "sphere",
                "--json",
                "--time-limit",
                limit,
            ],
        )
    };
    let (code, out, err) = certify("1e-9");
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["homeomorphic"], false);
    assert_eq!(v["tbp"]["timed_out"], true);
    assert!(
        v["verdict"].as_str().unwrap().contains("time limit"),
        "{}",
        v["verdict"]
    );
    let (code, out, err) = certify("60");
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["homeomorphic"], true, "{}", v["verdict"]);
    let (code, out, _) = certify("0");
    assert_eq!(code, 2, "{out}");
    assert!(out.contains("--time-limit"), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The exact sweep keeps isolated points of f = 0: a curve that is one point is not
/// "proven empty", the point is a component of the report, and the CSV and SVG files
/// hold it (a polyline of one row; a filled dot).
#[test]
fn isolated_points_of_a_curve_are_kept_and_written() {
    let dir = tmp("isolated");
    let run = |formula: &str, out: &str| {
        let (code, o, err) = certmesh_in(
            &dir,
            &[
                "curve",
                "--formula",
                formula,
                "--algo",
                "sweep",
                "-o",
                out,
                "--json",
            ],
        );
        assert_eq!(code, 0, "{formula}: {o}{err}");
        serde_json::from_str::<serde_json::Value>(&o).unwrap()
    };
    // The point (0, 0) alone.
    let v = run("x^2 + y^2", "p.csv");
    assert_eq!(v["certified"], true, "{v}");
    assert_eq!(v["components"], 1, "{v}");
    let csv = std::fs::read_to_string(dir.join("p.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 1, "{csv}");
    let f: Vec<f64> = rows[0]
        .split(',')
        .skip(3)
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(f, [0.0, 0.0], "{csv}");
    // The unit circle and its centre: two components; the SVG draws the point.
    let v = run("(x^2 + y^2)*(x^2 + y^2 - 1)", "c.svg");
    assert_eq!(v["components"], 2, "{v}");
    let svg = std::fs::read_to_string(dir.join("c.svg")).unwrap();
    assert_eq!(svg.matches("<circle").count(), 1, "{svg}");
    // A circle touching the domain's top side from outside meets it at (1/2, 2).
    let v = run("(x - 1/2)^2 + (y - 3)^2 - 1", "t.csv");
    assert_eq!(v["components"], 1, "{v}");
    let csv = std::fs::read_to_string(dir.join("t.csv")).unwrap();
    assert!(csv.contains(",0.5,2.0"), "{csv}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The exact sweep stops at --time-limit: three conics meeting tangently in pairs
/// (degree 6) ran for hours in its exact root searches; at a 1 s limit it ends with an
/// error naming the limit (exit 2, kind too-large), and writes nothing.
#[test]
fn the_sweep_stops_at_its_time_limit() {
    let dir = tmp("sweep-time");
    let (code, out, err) = certmesh_in(
        &dir,
        &[
            "curve",
            "--formula",
            "(x^2+y^2-1)*(x^2+4*y^2-1)*(4*x^2+y^2-1)",
            "--algo",
            "sweep",
            "-o",
            "c.csv",
            "--json",
            "--time-limit",
            "1",
        ],
    );
    assert_eq!(code, 2, "{out}{err}");
    let v = json_error(&out);
    assert_eq!(v["kind"], "too-large", "{v}");
    assert!(
        v["error"].as_str().unwrap().contains("time limit of 1 s"),
        "{v}"
    );
    assert!(!dir.join("c.csv").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// A run stopped by its budget after its check proved the output as it is (cdrr's
/// topological ball check, then the vertex budget) keeps its certificate, and the
/// report does not say "nothing is certified" beside it.
#[test]
fn a_certified_run_stopped_by_its_budget_says_what_holds() {
    let d = tmp("cdrr-budget-certified");
    let (code, text, err) = certmesh_in(
        &d,
        &[
            "mesh",
            "sphere",
            "--algo",
            "cdrr",
            "--facet-size",
            "1e-20",
            "--max-vertices",
            "2000",
            "-o",
            "s.ply",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(text.contains("certified: homeomorphic"), "{text}");
    let line = text
        .lines()
        .find(|l| l.starts_with("stopped before the refinement was complete"))
        .unwrap_or_else(|| panic!("no stop line: {text}"));
    assert!(
        line.contains("vertex budget") && !line.contains("nothing is certified"),
        "{line}"
    );
    assert!(line.contains("proven for the output as it is"), "{line}");
    std::fs::remove_dir_all(&d).unwrap();
}
