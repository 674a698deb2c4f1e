//! Reading and writing certificates, and the checks of inputs before the work starts.
use super::fail::{Fail, Kind};
use proofs::gradnormal::Certificate;
use proofs::stuffing;
use std::path::PathBuf;

/// Read a JSON file into `T`; a parse error carries its byte offset.
pub(crate) fn read_json<T: serde::de::DeserializeOwned>(
    p: &PathBuf,
    what: &str,
) -> Result<T, Fail> {
    let text =
        std::fs::read_to_string(p).map_err(|e| Fail::input(format!("{}: {e}", p.display())))?;
    serde_json::from_str(&text).map_err(|e| {
        // Byte offset of (line, column), both 1-based.
        let off = text
            .split_inclusive('\n')
            .take(e.line().saturating_sub(1))
            .map(|l| l.len())
            .sum::<usize>()
            + e.column().saturating_sub(1);
        Fail {
            kind: Kind::Input,
            msg: format!("{}: not a {what}: {e}", p.display()),
            position: Some(off),
        }
    })
}

pub(crate) fn load(p: &PathBuf) -> Result<Certificate, Fail> {
    read_json(p, "GradNormal certificate")
}

pub(crate) fn load_stuffing(p: &PathBuf) -> Result<stuffing::Certificate, Fail> {
    read_json(p, "stuffing certificate")
}

pub(crate) fn save_json<T: serde::Serialize>(p: &PathBuf, c: &T) -> Result<(), Fail> {
    let f = std::fs::File::create(p).map_err(|e| Fail::input(format!("{}: {e}", p.display())))?;
    serde_json::to_writer(std::io::BufWriter::new(f), c)
        .map_err(|e| Fail::input(format!("{}: {e}", p.display())))
}

/// Check an output path before the work starts: its folder exists and it is not a
/// folder itself.
pub(crate) fn check_out_path(p: &std::path::Path) -> Result<(), Fail> {
    if p.is_dir() {
        return Err(Fail::input(format!(
            "{}: is a directory (-o expects a file)",
            p.display()
        )));
    }
    let parent = p.parent().filter(|d| !d.as_os_str().is_empty());
    if let Some(d) = parent {
        if !d.is_dir() {
            return Err(Fail::input(format!(
                "{}: the folder {} does not exist",
                p.display(),
                d.display()
            )));
        }
    }
    Ok(())
}

pub(crate) fn parse_shard(s: &str) -> Result<(usize, usize), Fail> {
    let bad = || Fail::input(format!("--shard {s}: expects i/N with 0 <= i < N"));
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let i: usize = i.trim().parse().map_err(|_| bad())?;
    let n: usize = n.trim().parse().map_err(|_| bad())?;
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

/// Is the file a stuffing certificate (by its `format` field; any other file is read
/// as a GradNormal certificate and refused with a position if it is none)?
pub(crate) fn is_stuffing(p: &PathBuf) -> Result<bool, Fail> {
    Ok(format_of(p)?.is_some_and(|f| f == stuffing::FORMAT))
}

/// Is this a graded dagger certificate (`proofs stuffing --graded --certificates`)?
pub(crate) fn is_graded(p: &PathBuf) -> Result<bool, Fail> {
    Ok(format_of(p)?.is_some_and(|f| f == stuffing::graded::DAGGER_FORMAT))
}

/// The `format` field of a JSON certificate, if it has one.
fn format_of(p: &PathBuf) -> Result<Option<String>, Fail> {
    #[derive(serde::Deserialize)]
    struct Head {
        format: Option<String>,
    }
    let text =
        std::fs::read_to_string(p).map_err(|e| Fail::input(format!("{}: {e}", p.display())))?;
    Ok(serde_json::from_str::<Head>(&text)
        .ok()
        .and_then(|h| h.format))
}

pub(crate) fn check_tol_deg(tol_deg: f64) -> Result<(), Fail> {
    if !(stuffing::MIN_TOL_DEG..=90.0).contains(&tol_deg) {
        return Err(Fail::input(format!(
            "--tol-deg {tol_deg:e}: must be in [{:e}, 90] (below {:e}° f64 interval arithmetic cannot reach the target)",
            stuffing::MIN_TOL_DEG,
            stuffing::MIN_TOL_DEG
        )));
    }
    Ok(())
}
