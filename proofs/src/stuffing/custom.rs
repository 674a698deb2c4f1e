//! Any parameter pair, audited: `proofs stuffing --alpha-long A --alpha-short B`.
//!
//! A custom pair becomes a [`Row`] without paper values (every bound "n/a"), so the same
//! branch and bound certifies the enclosure of each of the six extremes, with a witness,
//! but states no verdict against a paper value. Its name records the parameters exactly
//! (`custom:0.21509,0.35900,unordered,double-sided`), so `proofs check` and `proofs merge`
//! re-derive the row from the certificate alone.
use super::cases::DEN;
use certmesh::stuffing::params::{Bounds, Row, TABLE1};
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

const PREFIX: &str = "custom:";

/// The parameters of a custom row: α_long and α_short as multiples of 1/[`DEN`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Params {
    pub long: i64,
    pub short: i64,
    pub ordered: bool,
    pub double_sided: bool,
}

impl Params {
    /// Read α as a decimal string with at most five decimals, exactly (no float).
    pub fn alpha(s: &str, what: &str) -> Result<i64, String> {
        let bad = || {
            format!("{what} {s:?}: give a decimal in (0, 0.5] with at most five decimals (the proof works in units of 1e-5)")
        };
        let t = s.trim();
        let (int, frac) = t.split_once('.').unwrap_or((t, ""));
        if int.is_empty() && frac.is_empty()
            || frac.len() > 5
            || !int.chars().all(|c| c.is_ascii_digit())
            || !frac.chars().all(|c| c.is_ascii_digit())
        {
            return Err(bad());
        }
        let int: i64 = if int.is_empty() {
            0
        } else {
            int.parse().map_err(|_| bad())?
        };
        let frac_v: i64 = format!("{frac:0<5}").parse().map_err(|_| bad())?;
        let v = int
            .checked_mul(DEN)
            .and_then(|x| x.checked_add(frac_v))
            .ok_or_else(bad)?;
        Ok(v)
    }
    /// Check the ranges the case enumeration assumes (§3: α ≤ 1/2, so at most one
    /// endpoint of an edge warps; α > 0, or nothing warps and cut points reach lattice
    /// points).
    pub fn new(long: i64, short: i64, ordered: bool, double_sided: bool) -> Result<Params, String> {
        if !(0 < long && long < DEN / 2) {
            return Err(format!(
                "--alpha-long {}: must lie in (0, 0.5): at 0.5 both ends of a black edge may warp to its midpoint",
                long as f64 / DEN as f64
            ));
        }
        if !(0 < short && short <= DEN / 2) {
            return Err(format!(
                "--alpha-short {}: must lie in (0, 0.5] (Labelle-Shewchuk §3, §6)",
                short as f64 / DEN as f64
            ));
        }
        Ok(Params {
            long,
            short,
            ordered,
            double_sided,
        })
    }
    /// The row name that encodes these parameters exactly.
    pub fn name(&self) -> String {
        format!(
            "{PREFIX}{},{},{},{}",
            decimal(self.long),
            decimal(self.short),
            if self.ordered { "ordered" } else { "unordered" },
            if self.double_sided {
                "double-sided"
            } else {
                "one-sided"
            }
        )
    }
    /// Parse a name made by [`Params::name`].
    pub fn parse(name: &str) -> Option<Params> {
        let rest = name.strip_prefix(PREFIX)?;
        let parts: Vec<&str> = rest.split(',').collect();
        let [l, s, o, d] = parts.as_slice() else {
            return None;
        };
        let ordered = match *o {
            "ordered" => true,
            "unordered" => false,
            _ => return None,
        };
        let double_sided = match *d {
            "double-sided" => true,
            "one-sided" => false,
            _ => return None,
        };
        let p = Params::new(
            Params::alpha(l, "alpha_long").ok()?,
            Params::alpha(s, "alpha_short").ok()?,
            ordered,
            double_sided,
        )
        .ok()?;
        (p.name() == name).then_some(p)
    }
    /// The Table 1 row with exactly these parameters, if any.
    pub fn table1_row(&self) -> Option<&'static Row> {
        let r = |x: f64| (x * DEN as f64).round() as i64;
        TABLE1.iter().find(|row| {
            r(row.alpha_long) == self.long
                && r(row.alpha_short) == self.short
                && row.ordered == self.ordered
                && row.double_sided == self.double_sided
        })
    }
}

/// Five decimals, exactly.
fn decimal(v: i64) -> String {
    format!("{}.{:05}", v / DEN, v % DEN)
}

/// The row of a custom parameter set (made once per process and kept: rows are
/// `'static` throughout the proof code).
pub fn row(p: &Params) -> &'static Row {
    static CACHE: OnceLock<Mutex<HashMap<Params, &'static Row>>> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    let mut m = cache.lock().unwrap_or_else(|e| e.into_inner());
    m.entry(*p).or_insert_with(|| {
        let name: &'static str = Box::leak(p.name().into_boxed_str());
        Box::leak(Box::new(Row {
            name,
            label: "custom parameters (audit)",
            alpha_long: p.long as f64 / DEN as f64,
            alpha_short: p.short as f64 / DEN as f64,
            ordered: p.ordered,
            // Decided by the proof (the safe property), not assumed.
            safe: false,
            double_sided: p.double_sided,
            bounds: Bounds {
                min_dihedral: None,
                max_dihedral: None,
                min_plane: None,
                max_plane: None,
                min_exposed: None,
                max_exposed: None,
            },
            asterisks: &[],
            daggers: &[],
        }))
    })
}

/// Is this row a custom one (no paper values; dihedrals always searched)?
pub fn is_custom(row: &Row) -> bool {
    row.name.starts_with(PREFIX)
}

/// A Table 1 row by name, or a custom row by its encoded name.
pub fn resolve(name: &str) -> Result<&'static Row, String> {
    if name.starts_with(PREFIX) {
        return Params::parse(name)
            .map(|p| row(&p))
            .ok_or_else(|| format!("row {name:?}: not a valid custom parameter name"));
    }
    certmesh::stuffing::row(name).map_err(|e| e.to_string())
}

/// What an audit of a custom pair established, beside the six enclosures.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Audit {
    /// The Table 1 row with exactly these parameters (then its paper values apply:
    /// run `--row NAME` for verdicts against them).
    pub table1_row: Option<&'static str>,
    /// Output-tetrahedron cases whose signed volume reaches 0 on the closed
    /// configuration space (their dihedrals are searched without the reduction).
    pub flat_output_cases: usize,
    /// The safe property (no warped BCC tetrahedron inverts), decided exactly.
    pub safe: &'static str,
    /// The smallest volume ratio of a warped BCC tetrahedron to the unwarped one, over
    /// the closed configuration space (exact, shown as f64).
    pub min_bcc_volume_ratio: f64,
    /// One sentence: bounds, or the flat/inverted verdict.
    pub verdict: String,
}

/// The audit of a custom-row certificate (`None` for a Table 1 row).
pub fn audit(c: &super::Certificate) -> Option<Audit> {
    let p = Params::parse(&c.row)?;
    let safe = c.safe.verdict;
    let verdict = if c.partial {
        "a shard: no verdict until `proofs merge` has every shard".to_string()
    } else if safe == crate::exact::Verdict::Refuted {
        format!(
            "unsafe: a warped BCC tetrahedron inverts (volume ratio {:.6} at case {:?}, t = {:?}); the six enclosures bound the output tetrahedra of the stencil table",
            c.safe.min_ratio, c.safe.witness_case, c.safe.witness_t
        )
    } else if !c.unreduced.is_empty() {
        format!(
            "{} output-tetrahedron cases reach volume 0 on the closed configuration space: (nearly) flat output tetrahedra are admitted; the dihedral enclosures say how close",
            c.unreduced.len()
        )
    } else if c.safe.min_ratio == 0.0 {
        "no output tetrahedron can be flat, but warped BCC tetrahedra come arbitrarily close to flat (volume ratio infimum 0, not attained); the six bounds are certified".to_string()
    } else {
        "every output tetrahedron keeps positive volume; the six bounds are certified".to_string()
    };
    Some(Audit {
        table1_row: p.table1_row().map(|r| r.name),
        flat_output_cases: c.unreduced.len(),
        safe: safe.name(),
        min_bcc_volume_ratio: c.safe.min_ratio,
        verdict,
    })
}
