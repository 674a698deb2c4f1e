//! Every field of both certificate kinds is checked: each certificate is serialised to
//! JSON, every scalar is mutated (numbers by one ulp and by a visible amount, integers by
//! ±1, strings and enum values to other values, booleans flipped, nulls filled) and every
//! array is shortened and lengthened, one mutation at a time, and `check` must reject
//! every mutated certificate (a certificate that no longer deserialises counts as
//! rejected: the CLI refuses it as an input error).
//!
//! Long arrays (cases, leaves, problems, ...) are sampled at their first and last
//! element, so every field of the schema is mutated in several instances.
//! Leaf contents are mutated in the shard certificates (small: every re-evaluation is
//! fast), the summaries, claims, bounds and verdicts in the complete ones.
//!
//! Not mutated, with the reason:
//! - `seconds`: the run's wall-clock time, informative only (the one field `check`
//!   cannot recompute; documented in both certificate types);
//! - `tol_cos` and `max_depth` upwards, or `tol_cos` by one ulp: these are parameters
//!   of the search, not results; `check` verifies that every leaf meets the stated
//!   tolerance and depth limit (the stopping rule re-applied with the final witnesses),
//!   so a tolerance the leaves do not meet is rejected (mutated here: ×1e-6, and the
//!   depth −1); a larger one, or a smaller one that the leaves still meet, is a statement that
//!   stays true of the same leaves;
//! - witness points (`u`, `v`, `x`) by one ulp: a witness is any certified point of the
//!   region, and a point one ulp away can have the same enclosure and the same derived
//!   values, which is then an equally valid certificate; they are moved by 0.01 instead.
use proofs::geometry::DiagonalRule;
use proofs::gradnormal::cases::Ratio;
use serde_json::Value;

fn next_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1);
    }
    let b = x.to_bits();
    f64::from_bits(if x > 0.0 { b + 1 } else { b - 1 })
}

/// The sampled indices of an array of length n.
fn sample(n: usize) -> Vec<usize> {
    let mut v = vec![0, n.saturating_sub(1)];
    v.retain(|&i| i < n);
    v.dedup();
    v
}

/// The last component of a path ("a.b[3].c" -> "c", "a.x[0]" -> "x").
fn field(path: &str) -> &str {
    let last = path.rsplit('.').next().unwrap_or(path);
    last.split('[').next().unwrap_or(last)
}

const ENUMS: [&[&str]; 3] = [
    &["proven", "refuted", "undecided"],
    &["attained", "not attained", "unknown"],
    &["Fixed", "Cut", "Warp"],
];

/// The mutations of one scalar at `path`.
fn mutations(path: &str, v: &Value, skip_leaves: bool) -> Vec<Value> {
    let f = field(path);
    if f == "seconds" {
        return Vec::new();
    }
    if skip_leaves && path.contains("leaves[") {
        return Vec::new();
    }
    match v {
        Value::Number(n) => {
            let x = n.as_f64().unwrap_or(0.0);
            let mut out = Vec::new();
            let is_int = n.is_u64() || n.is_i64();
            if is_int {
                out.push(serde_json::json!(x - 1.0));
                if !matches!(f, "tol_cos" | "max_depth") {
                    out.push(serde_json::json!(x + 1.0));
                }
            } else if matches!(f, "u" | "v" | "x") {
                out.push(serde_json::json!(if x < 0.5 { x + 0.01 } else { x - 0.01 }));
            } else if matches!(f, "tol_cos" | "max_depth") {
                out.push(serde_json::json!(x * 1e-6));
            } else {
                out.push(serde_json::json!(next_up(x)));
                out.push(serde_json::json!(x + 1e-3 * x.abs().max(1.0)));
            }
            out
        }
        Value::String(s) => {
            for e in ENUMS {
                if e.contains(&s.as_str()) {
                    return e
                        .iter()
                        .filter(|&&o| o != s)
                        .map(|&o| Value::String(o.into()))
                        .collect();
                }
            }
            vec![Value::String(format!("{s}x")), Value::String(String::new())]
        }
        Value::Bool(b) => vec![Value::Bool(!b)],
        Value::Null => vec![
            serde_json::json!(0),
            serde_json::json!("proven"),
            serde_json::json!([0.5, 0.6]),
        ],
        _ => Vec::new(),
    }
}

/// Every mutation of `root`: (JSON pointer, readable path and change, new value).
fn mutate_all(root: &Value, skip_leaves: bool) -> Vec<(String, String, Value)> {
    let mut out = Vec::new();
    let mut stack: Vec<(String, String)> = vec![(String::new(), String::new())];
    while let Some((ptr, path)) = stack.pop() {
        let v = root.pointer(&ptr).expect("pointer");
        match v {
            Value::Object(m) => {
                for k in m.keys() {
                    let p = if path.is_empty() {
                        k.clone()
                    } else {
                        format!("{path}.{k}")
                    };
                    stack.push((format!("{ptr}/{k}"), p));
                }
            }
            Value::Array(a) => {
                if skip_leaves && path.contains("leaves") {
                    continue;
                }
                if !a.is_empty() {
                    let mut shorter = a.clone();
                    shorter.pop();
                    out.push((
                        ptr.clone(),
                        format!("{path} (last element removed)"),
                        Value::Array(shorter),
                    ));
                    let mut longer = a.clone();
                    longer.push(a[a.len() - 1].clone());
                    out.push((
                        ptr.clone(),
                        format!("{path} (last element repeated)"),
                        Value::Array(longer),
                    ));
                }
                for i in sample(a.len()) {
                    stack.push((format!("{ptr}/{i}"), format!("{path}[{i}]")));
                }
            }
            scalar => {
                for m in mutations(&path, scalar, skip_leaves) {
                    if &m != scalar {
                        out.push((ptr.clone(), format!("{path} ({scalar} -> {m})"), m));
                    }
                }
            }
        }
    }
    out
}

/// Mutate every field of `cert` (one at a time, in place) and return the number of
/// mutations and those `check` accepted.
fn accepted<C, R>(
    cert: &C,
    skip_leaves: bool,
    check: impl Fn(&C) -> Result<R, String>,
) -> (usize, Vec<String>)
where
    C: serde::Serialize + serde::de::DeserializeOwned,
{
    let mut doc = serde_json::to_value(cert).expect("serialise");
    let back = C::deserialize(&doc).expect("roundtrip");
    assert!(check(&back).is_ok(), "the genuine certificate is accepted");
    drop(back);
    let muts = mutate_all(&doc, skip_leaves);
    let n = muts.len();
    let t0 = std::time::Instant::now();
    let mut bad = Vec::new();
    for (ptr, what, new) in muts {
        let slot = doc.pointer_mut(&ptr).expect("pointer");
        let old = std::mem::replace(slot, new);
        let ok = match C::deserialize(&doc) {
            Err(_) => false,
            Ok(c) => check(&c).is_ok(),
        };
        if ok {
            bad.push(what);
        }
        *doc.pointer_mut(&ptr).expect("pointer") = old;
    }
    eprintln!(
        "{n} mutations checked in {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    (n, bad)
}

fn gradnormal_cert(shard: Option<(usize, usize)>) -> proofs::gradnormal::Certificate {
    let mut c = proofs::gradnormal::Config::new(Ratio::Sommerville, DiagonalRule::Paper);
    c.tol_cos = 2e-2;
    c.max_depth = 5;
    c.shard = shard;
    proofs::gradnormal::run(&c).expect("run")
}

fn stuffing_cert(row: &str, shard: Option<(usize, usize)>) -> proofs::stuffing::Certificate {
    let r = certmesh::stuffing::row(row).expect("row");
    let mut c = proofs::stuffing::Config::new(r);
    c.tol_deg = 5.0;
    c.shard = shard;
    proofs::stuffing::run(&c).expect("run")
}

#[test]
fn every_gradnormal_field_is_checked() {
    let mut report = Vec::new();
    // A shard (every leaf field) and the complete certificate (summary and claims).
    let shard = gradnormal_cert(Some((1, 9)));
    assert!(shard.partial && shard.summary.is_none());
    let (n1, bad1) = accepted(&shard, false, proofs::gradnormal::check);
    let full = gradnormal_cert(None);
    assert!(!full.partial && full.summary.is_some());
    let (n2, bad2) = accepted(&full, true, proofs::gradnormal::check);
    eprintln!("gradnormal: {n1} + {n2} mutations");
    report.extend(bad1);
    report.extend(bad2);
    assert!(n1 > 200 && n2 > 500, "{n1} and {n2} mutations");
    assert!(
        report.is_empty(),
        "accepted mutations:\n{}",
        report.join("\n")
    );
}

#[test]
fn every_stuffing_field_is_checked() {
    let mut report = Vec::new();
    // A shard of a row with dihedral bounds (every leaf field, no verdicts) and a
    // complete row (bounds, verdicts, tightness, safe property).
    let shard = stuffing_cert("max-dihedral-unsafe", Some((3, 700)));
    assert!(shard.partial && shard.bounds.iter().all(|b| b.verdict.is_none()));
    let (n1, bad1) = accepted(&shard, false, proofs::stuffing::check);
    // A shard's leaves are pruned against the seed of the whole row (the search is
    // deterministic so): a shard far from the row's extremes meets even the ×1e-6
    // tolerance, and the mutated shard is then a true certificate (see the module doc).
    // The complete certificate below must still reject it.
    let bad1: Vec<String> = bad1
        .into_iter()
        .filter(|m| !m.starts_with("tol_cos ("))
        .collect();
    let full = stuffing_cert("min-exposed-unsafe", None);
    assert!(!full.partial && full.bounds.iter().any(|b| b.verdict.is_some()));
    let (n2, bad2) = accepted(&full, true, proofs::stuffing::check);
    let mut tight = full.clone();
    tight.tol_cos *= 1e-6;
    assert!(
        proofs::stuffing::check(&tight).is_err(),
        "a complete row must reject a tolerance its leaves do not meet"
    );
    eprintln!("stuffing: {n1} + {n2} mutations");
    report.extend(bad1);
    report.extend(bad2);
    assert!(n1 > 200 && n2 > 200, "{n1} and {n2} mutations");
    assert!(
        report.is_empty(),
        "accepted mutations:\n{}",
        report.join("\n")
    );
}
