//! Parameters shared by the command line and every mesher's constructor. Each mesher
//! reads the fields it understands (and documents its defaults); algorithm-specific
//! knobs come through `extra` (`--set key=value`).
use crate::error::{Error, Result};
pub use crate::implicit::ops::Crossing;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Options common to the meshers. `None` means "the mesher's documented default".
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct MesherOptions {
    /// Grid cells along the longest side of the domain (lattice methods).
    pub resolution: Option<usize>,
    /// Lattice edge length (GradNormal's e, stuffing's lattice spacing).
    pub scale: Option<f64>,
    /// Maximum subdivision depth (subdivision meshers).
    pub max_depth: Option<u32>,
    /// Minimum subdivision depth before criteria are tested.
    pub min_depth: Option<u32>,
    /// Move the grid to generic position (rotation + translation) first.
    pub generic_shift: bool,
    /// How edge crossings are located.
    pub crossing: Option<Crossing>,
    /// Tolerance of the crossing search, relative to the edge length.
    pub tolerance: Option<f64>,
    /// Prune empty space with interval arithmetic.
    pub prune: bool,
    /// A named parameter set (e.g. a row of the stuffing Table 1).
    pub params: Option<String>,
    /// Graded variant (stuffing).
    pub graded: bool,
    /// Box tests allowed (subdivision meshers; `--max-boxes`).
    pub max_boxes: Option<u64>,
    /// Wall-clock limit in seconds (subdivision meshers; `--time-limit`).
    pub time_limit: Option<f64>,
    /// Algorithm-specific settings, `key=value`.
    pub extra: BTreeMap<String, String>,
}

impl MesherOptions {
    /// An algorithm-specific setting parsed as `T`, with a clear error naming the key.
    pub fn get<T: std::str::FromStr>(&self, key: &str) -> Result<Option<T>> {
        match self.extra.get(key) {
            None => Ok(None),
            Some(v) => v
                .parse::<T>()
                .map(Some)
                .map_err(|_| Error::Param(format!("--set {key}={v}: cannot parse the value"))),
        }
    }
    /// Reject `--set` keys the mesher does not know (typos must not pass silently).
    pub fn check_keys(&self, algo: &str, known: &[&str]) -> Result<()> {
        for k in self.extra.keys() {
            if !known.contains(&k.as_str()) {
                return Err(Error::Param(format!(
                    "algorithm '{algo}' has no setting '{k}' (it knows: {})",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                )));
            }
        }
        Ok(())
    }
}
