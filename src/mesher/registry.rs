//! The registry: algorithm names on the command line → meshers. Every mesher module
//! provides `from_options(&MesherOptions)`; the comparison harness treats all alike.
use crate::error::{Error, Result};
use crate::mesher::options::MesherOptions;
use crate::mesher::Mesher;

/// One registered algorithm.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct AlgoInfo {
    /// The `--algo` name.
    pub name: &'static str,
    /// 2 for curves, 3 for surfaces.
    pub dim: usize,
    /// Can its output carry a certificate?
    pub certifying: bool,
    pub summary: &'static str,
}

type Ctor = fn(&MesherOptions) -> Result<Box<dyn Mesher>>;

macro_rules! entry {
    ($name:expr, $dim:expr, $cert:expr, $summary:expr, $ty:ty) => {
        (
            AlgoInfo {
                name: $name,
                dim: $dim,
                certifying: $cert,
                summary: $summary,
            },
            (|o: &MesherOptions| -> Result<Box<dyn Mesher>> {
                Ok(Box::new(<$ty>::from_options(o)?))
            }) as Ctor,
        )
    };
}

fn table() -> Vec<(AlgoInfo, Ctor)> {
    use crate::gradnormal::{planar, GradNormal, MidNormal};
    use crate::marching::{MarchingCubes, MarchingSquares, MarchingTetrahedra};
    use crate::stuffing::Stuffing;
    use crate::subdivision::plantinga_vegter::{PlantingaVegter, PlantingaVegter2};
    use crate::subdivision::snyder::{Snyder, Snyder2};
    vec![
        entry!(
            "mc",
            3,
            false,
            "marching cubes on a regular grid (baseline)",
            MarchingCubes
        ),
        entry!(
            "mt",
            3,
            false,
            "marching tetrahedra (Kuhn split) on a regular grid (baseline)",
            MarchingTetrahedra
        ),
        entry!(
            "pv",
            3,
            true,
            "Plantinga–Vegter octree, small normal variation: certified isotopy",
            PlantingaVegter
        ),
        entry!(
            "snyder",
            3,
            true,
            "Snyder octree, global parameterizability: certified isotopy where it terminates",
            Snyder
        ),
        entry!(
            "midnormal",
            3,
            false,
            "MidNormal on the Sommerville/BCC tiling (Hass–Trnkova Alg. 1)",
            MidNormal
        ),
        entry!(
            "gradnormal",
            3,
            false,
            "GradNormal: MidNormal + gradient projection + valence-4 removal (Alg. 2)",
            GradNormal
        ),
        entry!(
            "stuffing",
            3,
            false,
            "isosurface stuffing (Labelle–Shewchuk): tetrahedral mesh of f <= 0",
            Stuffing
        ),
        entry!(
            "ms",
            2,
            false,
            "marching squares on a regular grid (baseline)",
            MarchingSquares
        ),
        entry!(
            "pv",
            2,
            true,
            "Plantinga–Vegter quadtree: certified isotopy",
            PlantingaVegter2
        ),
        entry!(
            "snyder",
            2,
            true,
            "Snyder quadtree: certified isotopy where it terminates",
            Snyder2
        ),
        entry!(
            "midnormal",
            2,
            false,
            "planar MidNormal on the triangle tiling",
            planar::MidNormal2
        ),
        entry!(
            "gradnormal",
            2,
            false,
            "planar GradNormal (midpoints + projection)",
            planar::GradNormal2
        ),
    ]
}

/// Every registered algorithm.
pub fn list() -> Vec<AlgoInfo> {
    table().into_iter().map(|(i, _)| i).collect()
}

/// Build the mesher `name` for functions of dimension `dim` (2 curve, 3 surface).
pub fn build(name: &str, dim: usize, o: &MesherOptions) -> Result<Box<dyn Mesher>> {
    let t = table();
    if let Some((_, ctor)) = t.iter().find(|(i, _)| i.name == name && i.dim == dim) {
        return ctor(o);
    }
    let known: Vec<&str> = t
        .iter()
        .filter(|(i, _)| i.dim == dim)
        .map(|(i, _)| i.name)
        .collect();
    let other = t.iter().any(|(i, _)| i.name == name);
    let kind = if dim == 2 {
        "curve algorithm"
    } else {
        "surface algorithm"
    };
    if other {
        return Err(Error::Param(format!(
            "algorithm '{name}' does not handle {}; use one of: {}",
            if dim == 2 {
                "curves f(x, y)"
            } else {
                "surfaces f(x, y, z)"
            },
            known.join(" ")
        )));
    }
    Err(Error::Unknown {
        kind,
        name: name.to_string(),
        known: known.join(" "),
    })
}
