//! `proofs witness`: an independent floating-point recomputation of the witness
//! configurations of `proofs stuffing` summaries. It reads only the witness vertex
//! coordinates (`vertices_h`) and the vertex kinds from the summary JSON and recomputes
//! the angle with its own plain f64 vector code — nothing of the branch and bound, the
//! stencil tables or the interval evaluators — so an error there cannot hide here.
use serde_json::Value;

type V = [f64; 3];

fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// The angle between two vectors, in degrees.
fn angle(u: V, v: V) -> f64 {
    (dot(u, v) / (dot(u, u) * dot(v, v)).sqrt())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

/// The six dihedral angles of a tetrahedron, in degrees.
pub fn dihedrals(p: &[V; 4]) -> Vec<f64> {
    let mut out = Vec::new();
    for i in 0..4 {
        for j in i + 1..4 {
            let o: Vec<usize> = (0..4).filter(|&m| m != i && m != j).collect();
            let e = sub(p[j], p[i]);
            out.push(angle(
                cross(e, sub(p[o[0]], p[i])),
                cross(e, sub(p[o[1]], p[i])),
            ));
        }
    }
    out
}

/// The plane angles of the given faces (vertex index triples), in degrees.
pub fn plane_angles(p: &[V; 4], faces: &[[usize; 3]]) -> Vec<f64> {
    let mut out = Vec::new();
    for f in faces {
        for a in 0..3 {
            let (x, y, z) = (p[f[a]], p[f[(a + 1) % 3]], p[f[(a + 2) % 3]]);
            out.push(angle(sub(y, x), sub(z, x)));
        }
    }
    out
}

/// One recomputed witness.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Recomputed {
    pub row: String,
    pub bound: String,
    pub paper: Option<f64>,
    /// The extreme angle of the witness tetrahedron, recomputed in f64.
    pub float_deg: f64,
    pub certified_deg: [f64; 2],
    /// Does the float value lie in the certified enclosure (widened by `slack` degrees
    /// for the rounding of the float recomputation)?
    pub agrees: bool,
}

/// Recompute every witness of one summary (the JSON of `proofs stuffing --json`).
pub fn recompute(summary: &Value, slack: f64) -> Result<Vec<Recomputed>, String> {
    let row = summary["row"]
        .as_str()
        .ok_or("summary without a row")?
        .to_string();
    let mut out = Vec::new();
    for b in summary["bounds"]
        .as_array()
        .ok_or("summary without bounds")?
    {
        let w = &b["witness"];
        if w.is_null() {
            continue;
        }
        let bound = b["bound"]
            .as_str()
            .ok_or("bound without a name")?
            .to_string();
        let vs = w["vertices_h"]
            .as_array()
            .filter(|v| v.len() == 4)
            .ok_or_else(|| format!("row {row}, {bound}: the witness needs four vertices"))?;
        let mut p = [[0.0; 3]; 4];
        for (i, v) in vs.iter().enumerate() {
            for k in 0..3 {
                p[i][k] = v[k].as_f64().ok_or_else(|| {
                    format!("row {row}, {bound}: vertex {i} is not three numbers")
                })?;
            }
        }
        let vals = if bound.contains("dihedral") {
            dihedrals(&p)
        } else {
            // Exposed faces: those without a fixed lattice vertex (on the surface side).
            let kinds: Vec<String> = w["case"]
                .as_array()
                .map(|c| {
                    c.iter()
                        .map(|k| k["kind"].as_str().unwrap_or("").to_string())
                        .collect()
                })
                .unwrap_or_default();
            let all = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
            let faces: Vec<[usize; 3]> = all
                .into_iter()
                .filter(|f| {
                    bound.ends_with("plane")
                        || f.iter()
                            .all(|&k| kinds.get(k).is_some_and(|s| s != "Fixed"))
                })
                .collect();
            plane_angles(&p, &faces)
        };
        if vals.is_empty() {
            return Err(format!(
                "row {row}, {bound}: the witness has no face to measure"
            ));
        }
        let x = if bound.starts_with("min") {
            vals.iter().cloned().fold(f64::INFINITY, f64::min)
        } else {
            vals.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        };
        let lo = b["certified_deg"][0]
            .as_f64()
            .ok_or("certified_deg missing")?;
        let hi = b["certified_deg"][1]
            .as_f64()
            .ok_or("certified_deg missing")?;
        out.push(Recomputed {
            row: row.clone(),
            bound,
            paper: b["paper"].as_f64(),
            float_deg: x,
            certified_deg: [lo, hi],
            agrees: lo - slack <= x && x <= hi + slack,
        });
    }
    Ok(out)
}
