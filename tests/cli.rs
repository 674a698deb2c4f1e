//! The command line as a user meets it: clear errors with positions, JSON fields.
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
    let (code, _, err) = certmesh(&["mesh", "--formula", "x", "--algo", "mc"]);
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
