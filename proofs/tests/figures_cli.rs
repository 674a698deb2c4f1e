//! `proofs stuffing-figures` on inputs that give no figure: each is an error naming the
//! problem, and nothing is written (it used to exit 0 and write nothing).
use std::process::Command;

fn figures(args: &[&str], dir: &std::path::Path) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_proofs"))
        .arg("stuffing-figures")
        .args(args)
        .current_dir(dir)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

#[test]
fn stuffing_figures_without_certificates_is_an_error() {
    let dir = std::env::temp_dir().join(format!("proofs-figs-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("empty")).unwrap();
    std::fs::write(dir.join("notes.txt"), "not json\n").unwrap();
    for (args, says) in [
        (
            vec!["--certs", "missing", "--out", "figs"],
            "no such certificate file or folder",
        ),
        (
            vec!["--certs", "notes.txt", "--out", "figs"],
            "not a stuffing certificate",
        ),
        (
            vec!["--certs", "empty", "--out", "figs"],
            "no stuffing certificate",
        ),
        (
            vec!["--certs", "empty", "--out", "figs", "--bounds", "nope"],
            "unknown bound 'nope'",
        ),
    ] {
        let (code, err) = figures(&args, &dir);
        assert_ne!(code, 0, "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(
            !dir.join("figs").exists(),
            "{args:?} created the output folder"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `--format` takes the figure formats of certmesh's style; an unknown one is a usage
/// error before any work (exit 2), naming it.
#[test]
fn an_unknown_figure_format_is_an_input_error() {
    let dir = std::env::temp_dir().join(format!("proofs-figs-fmt-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("empty")).unwrap();
    let (code, err) = figures(&["--certs", "empty", "--format", "svg,jpeg"], &dir);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("jpeg"), "{err}");
    assert!(!dir.join("papers").exists());
    std::fs::remove_dir_all(&dir).ok();
}
