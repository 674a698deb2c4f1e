//! Field-by-field comparison of a stated certificate part with the recomputed one: the
//! checker recomputes every number and verdict a certificate states and rejects the
//! first difference, naming its field (`bounds[0].deg[1]`, `summary.min_deg[0]`, ...).
use serde::Serialize;
use serde_json::Value;

/// The first path at which two JSON values differ, with both values.
pub fn first_difference(path: &str, a: &Value, b: &Value) -> Option<(String, String, String)> {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for (k, va) in x {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                match y.get(k) {
                    Some(vb) => {
                        if let Some(d) = first_difference(&p, va, vb) {
                            return Some(d);
                        }
                    }
                    None => return Some((p, va.to_string(), "(absent)".into())),
                }
            }
            for (k, vb) in y {
                if !x.contains_key(k) {
                    return Some((format!("{path}.{k}"), "(absent)".into(), vb.to_string()));
                }
            }
            None
        }
        (Value::Array(x), Value::Array(y)) => {
            for (i, (va, vb)) in x.iter().zip(y).enumerate() {
                if let Some(d) = first_difference(&format!("{path}[{i}]"), va, vb) {
                    return Some(d);
                }
            }
            if x.len() != y.len() {
                return Some((
                    format!("{path} (length)"),
                    x.len().to_string(),
                    y.len().to_string(),
                ));
            }
            None
        }
        (Value::Number(x), Value::Number(y)) => {
            // Compare as numbers (1 and 1.0 are the same f64), exactly.
            let same = match (x.as_f64(), y.as_f64()) {
                (Some(p), Some(q)) => p == q,
                _ => x == y,
            };
            (!same).then(|| (path.to_string(), a.to_string(), b.to_string()))
        }
        _ => (a != b).then(|| (path.to_string(), a.to_string(), b.to_string())),
    }
}

/// Err naming the first differing field when `stated` and `recomputed` differ.
pub fn same<T: Serialize>(path: &str, stated: &T, recomputed: &T) -> Result<(), String> {
    let a = serde_json::to_value(stated).map_err(|e| format!("{path}: {e}"))?;
    let b = serde_json::to_value(recomputed).map_err(|e| format!("{path}: {e}"))?;
    match first_difference(path, &a, &b) {
        None => Ok(()),
        Some((p, x, y)) => Err(format!(
            "{p}: the certificate states {x}, recomputed from the leaves and the tables: {y}"
        )),
    }
}
