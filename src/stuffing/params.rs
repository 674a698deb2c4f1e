//! Table 1 of Labelle & Shewchuk 2007 as data: the thirteen (α_long, α_short) choices
//! and their guaranteed angle bounds (all 76 numeric entries), with the asterisk and
//! dagger marks of §5. The `proofs` crate re-verifies these rows on our stencil table.
use crate::error::{Error, Result};
use serde::Serialize;

/// The six guaranteed bounds of a row, in degrees. `None` = "n/a" in the paper.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Bounds {
    pub min_dihedral: Option<f64>,
    pub max_dihedral: Option<f64>,
    /// Plane angles of all triangular faces (interior faces included).
    pub min_plane: Option<f64>,
    pub max_plane: Option<f64>,
    /// Plane angles of the triangles exposed on the mesh boundary.
    pub min_exposed: Option<f64>,
    pub max_exposed: Option<f64>,
}

/// Which bound a mark refers to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Which {
    MinDihedral,
    MaxDihedral,
    MinPlane,
    MaxPlane,
    MinExposed,
    MaxExposed,
}

/// One row of Table 1.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Row {
    /// The `--params` name.
    pub name: &'static str,
    /// The row label of the paper.
    pub label: &'static str,
    pub alpha_long: f64,
    pub alpha_short: f64,
    /// Ordered warping (§3.2).
    pub ordered: bool,
    /// "safe": no BCC tetrahedron can invert.
    pub safe: bool,
    /// "double-sided": bounds include quadruple-zero tetrahedra.
    pub double_sided: bool,
    pub bounds: Bounds,
    /// Bounds marked `*` (graded meshes need the extra leaves of §5 for them).
    pub asterisks: &'static [Which],
    /// Bounds marked `†`, with their weaker value for graded meshes (§5).
    pub daggers: &'static [(Which, f64)],
}

const fn b(a: f64, bb: f64, c: f64, d: f64, e: f64, f: f64) -> Bounds {
    Bounds {
        min_dihedral: Some(a),
        max_dihedral: Some(bb),
        min_plane: Some(c),
        max_plane: Some(d),
        min_exposed: Some(e),
        max_exposed: Some(f),
    }
}

use Which::*;

/// The thirteen rows, in the paper's order.
pub const TABLE1: [Row; 13] = [
    Row {
        name: "max-dihedral-unsafe",
        label: "maximum dihedral angle, unsafe",
        alpha_long: 0.26649,
        alpha_short: 0.36918,
        ordered: false,
        safe: false,
        double_sided: false,
        bounds: b(8.9716, 158.7403, 11.9072, 150.9944, 12.0162, 147.6786),
        asterisks: &[MaxDihedral],
        daggers: &[],
    },
    Row {
        name: "min-dihedral-unsafe",
        label: "minimum dihedral angle, unsafe",
        alpha_long: 0.28511,
        alpha_short: 0.39882,
        ordered: false,
        safe: false,
        double_sided: false,
        bounds: b(10.7843, 164.7373, 9.0454, 154.9845, 9.0454, 154.9845),
        asterisks: &[MinDihedral],
        daggers: &[],
    },
    Row {
        name: "max-dihedral-safe",
        label: "maximum dihedral angle, safe",
        alpha_long: 0.24999,
        alpha_short: 0.40173,
        ordered: false,
        safe: true,
        double_sided: false,
        bounds: b(9.0551, 160.5331, 8.7614, 155.7053, 8.7614, 155.7053),
        asterisks: &[],
        daggers: &[],
    },
    Row {
        name: "min-dihedral-safe",
        label: "minimum dihedral angle, safe",
        alpha_long: 0.24999,
        alpha_short: 0.41189,
        ordered: false,
        safe: true,
        double_sided: false,
        bounds: b(9.3171, 161.6432, 7.7810, 158.2252, 7.7810, 158.2252),
        asterisks: &[],
        daggers: &[],
    },
    Row {
        name: "min-dihedral-safe-ordered",
        label: "... with ordered warping",
        alpha_long: 0.24999,
        alpha_short: 0.42978,
        ordered: true,
        safe: true,
        double_sided: false,
        bounds: b(9.7766, 163.5685, 10.5695, 149.7137, 15.1645, 138.1929),
        asterisks: &[],
        daggers: &[],
    },
    Row {
        name: "max-dihedral-double",
        label: "max dihedral, double-sided, safe",
        alpha_long: 0.21509,
        alpha_short: 0.35900,
        ordered: false,
        safe: true,
        double_sided: true,
        bounds: b(6.4917, 164.1013, 8.8535, 157.8278, 13.0689, 145.1886),
        asterisks: &[],
        daggers: &[],
    },
    Row {
        name: "min-dihedral-double",
        label: "min dihedral, double-sided, safe",
        alpha_long: 0.22383,
        alpha_short: 0.39700,
        ordered: false,
        safe: true,
        double_sided: true,
        bounds: b(7.6872, 168.0481, 9.2237, 155.0594, 9.2237, 154.5340),
        asterisks: &[],
        daggers: &[],
    },
    Row {
        name: "min-dihedral-double-ordered",
        label: "... with ordered warping",
        alpha_long: 0.22385,
        alpha_short: 0.40501,
        ordered: true,
        safe: true,
        double_sided: true,
        bounds: b(7.8653, 168.0572, 9.5400, 154.6644, 14.4726, 135.7164),
        asterisks: &[],
        daggers: &[],
    },
    Row {
        name: "max-exposed-safe",
        label: "max exposed plane angle, safe",
        alpha_long: 0.23926,
        alpha_short: 0.27376,
        ordered: false,
        safe: true,
        double_sided: false,
        bounds: b(5.3440, 163.8969, 6.2646, 158.2960, 11.8387, 124.9195),
        asterisks: &[MaxExposed],
        daggers: &[],
    },
    Row {
        name: "max-exposed-safe-ordered",
        label: "... with ordered warping",
        alpha_long: 0.23463,
        alpha_short: 0.29505,
        ordered: true,
        safe: true,
        double_sided: false,
        bounds: b(5.8017, 162.1673, 7.2694, 158.0368, 12.1108, 124.0867),
        asterisks: &[MaxExposed],
        daggers: &[],
    },
    Row {
        name: "min-exposed-unsafe",
        label: "min exposed plane angle, unsafe",
        alpha_long: 0.36378,
        alpha_short: 0.33951,
        ordered: false,
        safe: false,
        double_sided: false,
        bounds: Bounds {
            min_dihedral: None,
            max_dihedral: None,
            min_plane: Some(10.4741),
            max_plane: Some(149.6794),
            min_exposed: Some(15.1285),
            max_exposed: Some(149.5205),
        },
        asterisks: &[MinExposed, MaxExposed],
        daggers: &[(MaxPlane, 158.1918)],
    },
    Row {
        name: "min-exposed-safe",
        label: "min exposed plane angle, safe",
        alpha_long: 0.24999,
        alpha_short: 0.35464,
        ordered: false,
        safe: true,
        double_sided: false,
        bounds: b(7.8390, 160.5447, 10.4213, 153.7863, 13.5241, 144.1259),
        asterisks: &[],
        daggers: &[],
    },
    Row {
        name: "min-exposed-safe-ordered",
        label: "... with ordered warping",
        alpha_long: 0.23573,
        alpha_short: 0.5,
        ordered: true,
        safe: true,
        double_sided: false,
        bounds: b(7.4904, 169.1465, 9.2685, 145.4921, 16.4299, 144.9032),
        asterisks: &[],
        daggers: &[(MaxPlane, 147.0470)],
    },
];

/// The default row: the paper's headline parameters (Figs 4 and 6).
pub const DEFAULT_ROW: &str = "min-dihedral-unsafe";

/// Look a row up by its `--params` name.
pub fn row(name: &str) -> Result<&'static Row> {
    TABLE1
        .iter()
        .find(|r| r.name == name)
        .ok_or_else(|| Error::Unknown {
            kind: "stuffing parameter row",
            name: name.to_string(),
            known: TABLE1.iter().map(|r| r.name).collect::<Vec<_>>().join(" "),
        })
}

impl Bounds {
    /// The numeric entries (for counting and tables), in column order.
    pub fn entries(&self) -> [Option<f64>; 6] {
        [
            self.min_dihedral,
            self.max_dihedral,
            self.min_plane,
            self.max_plane,
            self.min_exposed,
            self.max_exposed,
        ]
    }
}

impl Row {
    /// Theorem 2's ω (unscaled lattice): points farther than ω·h from the surface are
    /// classified correctly.
    pub fn omega(&self) -> f64 {
        omega(self.alpha_long, self.alpha_short)
    }
    /// The bounds that hold for a graded mesh (§5): daggered entries weaken.
    pub fn graded_bounds(&self) -> Bounds {
        let mut b = self.bounds;
        for &(w, v) in self.daggers {
            if w == MaxPlane {
                b.max_plane = Some(v);
            }
        }
        b
    }
}

/// ω = max{√(α_long² + α_long + 5/16), ½√(3α_short² + 3α_short + 5/4)} (Theorem 2).
pub fn omega(alpha_long: f64, alpha_short: f64) -> f64 {
    (alpha_long * alpha_long + alpha_long + 5.0 / 16.0)
        .sqrt()
        .max(0.5 * (3.0 * alpha_short * alpha_short + 3.0 * alpha_short + 1.25).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn seventy_six_entries() {
        let n: usize = TABLE1
            .iter()
            .map(|r| r.bounds.entries().iter().flatten().count())
            .sum();
        assert_eq!(n, 76);
        for r in &TABLE1 {
            assert!(r.alpha_long > 0.0 && r.alpha_long < 0.5);
            assert!(r.alpha_short > 0.0 && r.alpha_short <= 0.5);
            let e = r.bounds.entries();
            if let (Some(lo), Some(hi)) = (e[0], e[1]) {
                assert!(lo < 60.0 && hi > 90.0);
            }
        }
        assert!(row("nope").is_err());
        assert_eq!(
            row("min-dihedral-safe-ordered").unwrap().alpha_short,
            0.42978
        );
    }
}
