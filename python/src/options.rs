//! `mesh(..., **params)`: the keyword arguments as the library's `MesherOptions`, by
//! their field names (`resolution`, `facet_angle`, `max_depth`, ...; dashes accepted),
//! with algorithm-specific settings under `settings={key: value}` (the command line's
//! `--set key=value`). An unknown name is an error, never silently ignored.
use crate::CertmeshError;
use certmesh::mesher::options::{Crossing, MesherOptions};
use pyo3::PyResult;

/// The accepted option names.
pub fn names() -> Vec<String> {
    let mut v: Vec<String> = match serde_json::to_value(MesherOptions::default()) {
        Ok(serde_json::Value::Object(m)) => m.keys().filter(|k| *k != "extra").cloned().collect(),
        _ => Vec::new(),
    };
    v.push("settings".into());
    v
}

/// Parse the JSON object of keyword arguments.
pub fn parse(text: &str) -> PyResult<MesherOptions> {
    let v: serde_json::Value =
        serde_json::from_str(text).map_err(|e| CertmeshError::new_err(format!("options: {e}")))?;
    let serde_json::Value::Object(given) = v else {
        return Err(CertmeshError::new_err("options must be a dict"));
    };
    let known = names();
    let mut obj = serde_json::Map::new();
    for (k, v) in given {
        let key = k.replace('-', "_");
        if !known.contains(&key) {
            return Err(CertmeshError::new_err(format!(
                "unknown option '{k}' (known: {})",
                known.join(", ")
            )));
        }
        if v.is_null() {
            continue;
        }
        let v = match key.as_str() {
            "crossing" => {
                let s = v.as_str().ok_or_else(|| {
                    CertmeshError::new_err("crossing must be 'linear' or 'bisection'")
                })?;
                let c: Crossing = s.parse().map_err(crate::err)?;
                serde_json::to_value(c).expect("serialises")
            }
            "settings" => {
                let serde_json::Value::Object(m) = v else {
                    return Err(CertmeshError::new_err(
                        "settings must be a dict of key: value",
                    ));
                };
                let m: serde_json::Map<String, serde_json::Value> = m
                    .into_iter()
                    .map(|(k, v)| {
                        let s = match v {
                            serde_json::Value::String(s) => s,
                            other => other.to_string(),
                        };
                        (k, serde_json::Value::String(s))
                    })
                    .collect();
                obj.insert("extra".into(), serde_json::Value::Object(m));
                continue;
            }
            _ => v,
        };
        obj.insert(key, v);
    }
    // Fields absent from the object take their defaults (switches off, values None).
    let mut full = serde_json::to_value(MesherOptions::default()).expect("serialises");
    if let serde_json::Value::Object(m) = &mut full {
        m.extend(obj);
    }
    serde_json::from_value(full).map_err(|e| CertmeshError::new_err(format!("options: {e}")))
}
