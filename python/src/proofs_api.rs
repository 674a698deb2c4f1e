//! `certmesh.proofs`: the `proofs` binary's certified branch and bound from Python.
//! Each function returns the certificate (the same JSON document `proofs ... --out`
//! writes, re-checkable with `proofs check`) and its summary.
use crate::{run, CertmeshError};
use proofs::bnb::Budget;
use proofs::gradnormal::{self, cases::Ratio};
use proofs::stuffing;
use pyo3::prelude::*;
use pyo3::types::PyDict;

fn budget(max_boxes: Option<u64>, time_limit: Option<f64>) -> PyResult<Budget> {
    if max_boxes == Some(0) {
        return Err(CertmeshError::new_err("max_boxes must be at least 1"));
    }
    if let Some(t) = time_limit {
        if !(t.is_finite() && t > 0.0) {
            return Err(CertmeshError::new_err(format!(
                "time_limit must be a positive number of seconds, got {t}"
            )));
        }
    }
    Ok(Budget::new(
        max_boxes.unwrap_or(proofs::bnb::DEFAULT_MAX_BOXES),
        time_limit,
    ))
}

fn check_tol(tol_deg: f64) -> PyResult<()> {
    if !(stuffing::MIN_TOL_DEG..=90.0).contains(&tol_deg) {
        return Err(CertmeshError::new_err(format!(
            "tol_deg {tol_deg:e}: must be in [{:e}, 90]",
            stuffing::MIN_TOL_DEG
        )));
    }
    Ok(())
}

fn to_json<T: serde::Serialize>(v: &T) -> String {
    serde_json::to_string(v).expect("certificates serialise")
}

/// The GradNormal angle bound (Hass–Trnkova 2020, Appendix A) for the tiling ratio
/// `a` and the diagonal rule.
#[pyfunction]
#[pyo3(signature = (a="sommerville", rule="paper", tol_deg=1e-6, max_boxes=None, time_limit=None, progress=None))]
fn gradnormal_proof<'py>(
    py: Python<'py>,
    a: &str,
    rule: &str,
    tol_deg: f64,
    max_boxes: Option<u64>,
    time_limit: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let ratio = Ratio::parse(a).map_err(|e| CertmeshError::new_err(format!("a: {e}")))?;
    let rule: certmesh::gradnormal::DiagonalRule = rule
        .parse()
        .map_err(|e| CertmeshError::new_err(format!("rule: {e}")))?;
    if !(tol_deg.is_finite() && tol_deg >= gradnormal::MIN_TOL_DEG && tol_deg <= 90.0) {
        return Err(CertmeshError::new_err(format!(
            "tol_deg {tol_deg:e}: must be in [{:e}, 90]",
            gradnormal::MIN_TOL_DEG
        )));
    }
    gradnormal::check_theorem_range(ratio).map_err(|e| CertmeshError::new_err(e.to_string()))?;
    let mut cfg = gradnormal::Config::new(ratio, rule);
    cfg.tol_cos = 0.5 * tol_deg * std::f64::consts::PI / 180.0;
    cfg.budget = budget(max_boxes, time_limit)?;
    let (cert, check) = run::interruptible(py, progress.as_ref(), |c| {
        let b = cfg.budget.clone();
        c.on_stop(move || b.stop());
        let cert = gradnormal::run(&cfg)?;
        let check = gradnormal::check(&cert)?;
        Ok((cert, check))
    })?;
    let d = PyDict::new(py);
    d.set_item("kind", "gradnormal")?;
    d.set_item("certificate", to_json(&cert))?;
    d.set_item("summary", to_json(&cert.summary))?;
    d.set_item("claims", to_json(&cert.claims))?;
    d.set_item("checked", to_json(&check))?;
    d.set_item("seconds", cert.seconds)?;
    Ok(d)
}

/// The isosurface-stuffing angle bounds (Labelle–Shewchuk 2007, §4.1) of a Table 1 row
/// or of any (alpha_long, alpha_short) pair.
#[pyfunction]
#[pyo3(signature = (row=None, alpha_long=None, alpha_short=None, ordered=false, side="both", tol_deg=1e-4, max_boxes=None, time_limit=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn stuffing_proof<'py>(
    py: Python<'py>,
    row: Option<String>,
    alpha_long: Option<String>,
    alpha_short: Option<String>,
    ordered: bool,
    side: &str,
    tol_deg: f64,
    max_boxes: Option<u64>,
    time_limit: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    use stuffing::custom::Params;
    let e = |m: String| CertmeshError::new_err(m);
    if side != "both" && side != "one" {
        return Err(e(format!("side must be 'both' or 'one', got '{side}'")));
    }
    let name = match (row, alpha_long, alpha_short) {
        (Some(r), None, None) => r,
        (None, Some(l), Some(s)) => Params::new(
            Params::alpha(&l, "alpha_long").map_err(e)?,
            Params::alpha(&s, "alpha_short").map_err(e)?,
            ordered,
            side == "both",
        )
        .map_err(e)?
        .name(),
        _ => {
            return Err(e(format!(
                "give row= (one of: {}) or both alpha_long= and alpha_short=",
                stuffing::row_names().join(", ")
            )))
        }
    };
    check_tol(tol_deg)?;
    let r = stuffing::custom::resolve(&name).map_err(|m| e(format!("row: {m}")))?;
    let mut cfg = stuffing::Config::new(r);
    cfg.tol_deg = tol_deg;
    cfg.budget = budget(max_boxes, time_limit)?;
    let (cert, check) = run::interruptible(py, progress.as_ref(), |c| {
        let b = cfg.budget.clone();
        c.on_stop(move || b.stop());
        let cert = stuffing::run(&cfg).map_err(|m| format!("row {name}: {m}"))?;
        let check = stuffing::check(&cert)?;
        Ok((cert, check))
    })?;
    let d = PyDict::new(py);
    d.set_item("kind", "stuffing")?;
    d.set_item("certificate", to_json(&cert))?;
    d.set_item("summary", to_json(&stuffing::summary_json(&cert, "")))?;
    d.set_item("checked", to_json(&check))?;
    Ok(d)
}

/// Re-check a certificate file written by `proofs` or by `certmesh.proofs`.
#[pyfunction]
fn check_certificate(py: Python<'_>, path: std::path::PathBuf) -> PyResult<String> {
    let text = std::fs::read_to_string(&path)
        .map_err(|e| CertmeshError::new_err(format!("{}: {e}", path.display())))?;
    let fail = |m: String| format!("{}: {m}", path.display());
    run::interruptible(py, None, move |_| {
        let head: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| fail(e.to_string()))?;
        if head.get("format").and_then(|f| f.as_str()) == Some(stuffing::FORMAT) {
            let c: stuffing::Certificate =
                serde_json::from_value(head).map_err(|e| fail(e.to_string()))?;
            let r = stuffing::check(&c).map_err(|m| fail(format!("check failed: {m}")))?;
            Ok(to_json(
                &serde_json::json!({"ok": true, "kind": "stuffing", "row": c.row, "report": r}),
            ))
        } else {
            let c: gradnormal::Certificate =
                serde_json::from_value(head).map_err(|e| fail(e.to_string()))?;
            let r = gradnormal::check(&c).map_err(|m| fail(format!("check failed: {m}")))?;
            Ok(to_json(
                &serde_json::json!({"ok": true, "kind": "gradnormal", "report": r}),
            ))
        }
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(gradnormal_proof, m)?)?;
    m.add_function(wrap_pyfunction!(stuffing_proof, m)?)?;
    m.add_function(wrap_pyfunction!(check_certificate, m)?)?;
    Ok(())
}
