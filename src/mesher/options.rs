//! Parameters shared by the command line and every mesher's constructor. Each mesher
//! reads the fields it understands (and documents its defaults); algorithm-specific
//! knobs come through `extra` (`--set key=value`).
use crate::error::{Error, Result};
pub use crate::implicit::ops::Crossing;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The wall-clock limit, in seconds, of a mesher built from [`MesherOptions`] without
/// `--time-limit`: pv, snyder, stander-hart, bo (surfaces and curves) and cdrr. Their
/// other budgets (boxes, vertices) bound the work but not its time: near a pole or a
/// singular point a refinement may spend minutes before it reaches them (cdrr on two
/// touching spheres, 226 s to its 200,000 vertices; bo over 300 s). A run stopped by
/// the limit says so and certifies nothing. The library's parameter types
/// (`PvParams::new`, ...) have no limit unless one is set.
pub const DEFAULT_TIME_LIMIT: f64 = 60.0;

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
    /// Wall-clock limit in seconds (subdivision and refinement meshers:
    /// `--time-limit`); `None` means [`DEFAULT_TIME_LIMIT`].
    pub time_limit: Option<f64>,
    /// Smallest triangle angle in degrees (restricted-Delaunay meshers; CGAL's
    /// `facet_angle`).
    pub facet_angle: Option<f64>,
    /// Largest surface Delaunay ball radius (CGAL's `facet_size`).
    pub facet_size: Option<f64>,
    /// Largest distance from a facet's circumcentre to the surface (CGAL's
    /// `facet_distance`).
    pub facet_distance: Option<f64>,
    /// Refine until the output is a 2-manifold (CGAL's `Manifold_tag`).
    pub manifold: bool,
    /// Vertex budget (refinement meshers; `--max-vertices`).
    pub max_vertices: Option<usize>,
    /// Run the (slower) certification pass (meshers whose certificate is optional).
    pub certify: bool,
    /// Algorithm-specific settings, `key=value`.
    pub extra: BTreeMap<String, String>,
}

/// A wall-clock limit must be a positive, finite number of seconds (the one check of
/// `--time-limit` for every command and mesher).
pub fn check_time_limit(t: f64) -> Result<()> {
    if t.is_finite() && t > 0.0 {
        Ok(())
    } else {
        Err(Error::Param(format!(
            "--time-limit must be a positive number of seconds, got {t}"
        )))
    }
}

impl MesherOptions {
    /// `--time-limit`, or [`DEFAULT_TIME_LIMIT`] without it.
    pub fn time_limit_or_default(&self) -> f64 {
        self.time_limit.unwrap_or(DEFAULT_TIME_LIMIT)
    }
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
    /// The options that are set (a value given, a switch on), by their command-line
    /// names (`max-depth`, not `max_depth`); `--set` keys are not among them (each
    /// mesher checks its own with [`MesherOptions::check_keys`]).
    pub fn given(&self) -> Vec<&'static str> {
        let mut v = Vec::new();
        let mut add = |on: bool, name: &'static str| {
            if on {
                v.push(name)
            }
        };
        add(self.resolution.is_some(), "resolution");
        add(self.scale.is_some(), "scale");
        add(self.max_depth.is_some(), "max-depth");
        add(self.min_depth.is_some(), "min-depth");
        add(self.generic_shift, "generic-shift");
        add(self.crossing.is_some(), "crossing");
        add(self.tolerance.is_some(), "tolerance");
        add(self.prune, "prune");
        add(self.params.is_some(), "params");
        add(self.graded, "graded");
        add(self.max_boxes.is_some(), "max-boxes");
        add(self.time_limit.is_some(), "time-limit");
        add(self.facet_angle.is_some(), "facet-angle");
        add(self.facet_size.is_some(), "facet-size");
        add(self.facet_distance.is_some(), "facet-distance");
        add(self.manifold, "manifold");
        add(self.max_vertices.is_some(), "max-vertices");
        add(self.certify, "certify");
        v
    }
    /// The same options with every one a mesher does not read (not in `reads`) back at
    /// its default: how a comparison matrix hands one set of options to meshers that
    /// read different parts of it.
    pub fn restricted_to(&self, reads: &[&str]) -> MesherOptions {
        let r = |name: &str| reads.contains(&name);
        MesherOptions {
            resolution: self.resolution.filter(|_| r("resolution")),
            scale: self.scale.filter(|_| r("scale")),
            max_depth: self.max_depth.filter(|_| r("max-depth")),
            min_depth: self.min_depth.filter(|_| r("min-depth")),
            generic_shift: self.generic_shift && r("generic-shift"),
            crossing: self.crossing.filter(|_| r("crossing")),
            tolerance: self.tolerance.filter(|_| r("tolerance")),
            prune: self.prune && r("prune"),
            params: self.params.clone().filter(|_| r("params")),
            graded: self.graded && r("graded"),
            max_boxes: self.max_boxes.filter(|_| r("max-boxes")),
            time_limit: self.time_limit.filter(|_| r("time-limit")),
            facet_angle: self.facet_angle.filter(|_| r("facet-angle")),
            facet_size: self.facet_size.filter(|_| r("facet-size")),
            facet_distance: self.facet_distance.filter(|_| r("facet-distance")),
            manifold: self.manifold && r("manifold"),
            max_vertices: self.max_vertices.filter(|_| r("max-vertices")),
            certify: self.certify && r("certify"),
            extra: self.extra.clone(),
        }
    }
}
