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
    /// The shared options it reads, by their command-line names; any other option given
    /// to it is an error ([`build`]).
    pub reads: &'static [&'static str],
}

const MARCHING: &[&str] = &["resolution", "crossing", "tolerance", "prune"];
const PV: &[&str] = &[
    "max-depth",
    "min-depth",
    "crossing",
    "tolerance",
    "max-boxes",
    "time-limit",
];
const SNYDER: &[&str] = &[
    "max-depth",
    "min-depth",
    "tolerance",
    "generic-shift",
    "max-boxes",
    "time-limit",
];
const GRADNORMAL: &[&str] = &["resolution", "scale"];
const STUFFING: &[&str] = &[
    "resolution",
    "scale",
    "crossing",
    "tolerance",
    "params",
    "graded",
];

const BO: &[&str] = &[
    "facet-angle",
    "facet-size",
    "facet-distance",
    "manifold",
    "max-vertices",
    "time-limit",
    "certify",
];

/// The 2D `bo` (curves): `BO` without the angle criterion (its first entry); `--manifold` refines branch points and
/// open ends; `--certify` is accepted and always on (the certified re-derivation is
/// cheap in 2D).
const BO2: &[&str] = BO.split_at(1).1;

const CDRR: &[&str] = &["facet-size", "max-vertices", "time-limit"];

type Ctor = fn(&MesherOptions) -> Result<Box<dyn Mesher>>;

macro_rules! entry {
    ($name:expr, $dim:expr, $cert:expr, $summary:expr, $ty:ty, $reads:expr) => {
        (
            AlgoInfo {
                name: $name,
                dim: $dim,
                certifying: $cert,
                summary: $summary,
                reads: $reads,
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
            MarchingCubes,
            MARCHING
        ),
        entry!(
            "mt",
            3,
            false,
            "marching tetrahedra (Kuhn split) on a regular grid (baseline)",
            MarchingTetrahedra,
            MARCHING
        ),
        entry!(
            "pv",
            3,
            true,
            "Plantinga–Vegter octree, small normal variation: certified isotopy",
            PlantingaVegter,
            PV
        ),
        entry!(
            "snyder",
            3,
            true,
            "Snyder octree, global parameterizability: certified isotopy where it terminates",
            Snyder,
            SNYDER
        ),
        entry!(
            "midnormal",
            3,
            false,
            "MidNormal on the Sommerville/BCC tiling (Hass–Trnkova Alg. 1)",
            MidNormal,
            GRADNORMAL
        ),
        entry!(
            "gradnormal",
            3,
            false,
            "GradNormal: MidNormal + gradient projection + valence-4 removal (Alg. 2)",
            GradNormal,
            GRADNORMAL
        ),
        entry!(
            "stuffing",
            3,
            false,
            "isosurface stuffing (Labelle–Shewchuk): tetrahedral mesh of f <= 0",
            Stuffing,
            STUFFING
        ),
        entry!(
            "stander-hart",
            3,
            true,
            "Stander–Hart sweep: certified critical points of f order the levels, each meshed by PV",
            crate::morse::stander_hart::StanderHart,
            PV
        ),
        entry!(
            "bcsv",
            3,
            false,
            "Boissonnat–Cohen-Steiner–Vegter PL interpolation on a uniform Kuhn grid (--set octree=true: the tetrahedra of an adaptive 2:1 octree): isotopic when Thm 8's conditions hold, W is a 3-manifold and the certified chi(S) equals chi(S-hat) (Theorem B, bcsv.md); else W-certified at most",
            crate::morse::bcsv::Bcsv,
            &["resolution", "max-depth", "max-boxes", "time-limit"]
        ),
        entry!(
            "bo",
            3,
            true,
            "Boissonnat-Oudot restricted-Delaunay refinement, CGAL's criteria; --certify: exact restricted triangulation; with --set size=reach, ambient isotopy (Theorem 3 through a certified point set on S) where every hypothesis is checked",
            crate::restricted_delaunay::BoissonnatOudot,
            BO
        ),
        entry!(
            "cdrr",
            3,
            true,
            "Cheng-Dey-Ramos-Ray refinement: tests (1)-(4) until the topological ball property is proven (homeomorphic, Thm 5; isotopy not claimed)",
            crate::restricted_delaunay::ChengDeyRamosRay,
            CDRR
        ),
        entry!(
            "ms",
            2,
            false,
            "marching squares on a regular grid (baseline)",
            MarchingSquares,
            MARCHING
        ),
        entry!(
            "pv",
            2,
            true,
            "Plantinga–Vegter quadtree: certified isotopy",
            PlantingaVegter2,
            PV
        ),
        entry!(
            "snyder",
            2,
            true,
            "Snyder quadtree: certified isotopy where it terminates",
            Snyder2,
            SNYDER
        ),
        entry!(
            "sweep",
            2,
            true,
            "González-Vega–Necula sweep: exact topology of polynomial curves, singular points included",
            crate::algebraic::Sweep,
            &["time-limit"]
        ),
        entry!(
            "bo",
            2,
            true,
            "Boissonnat-Oudot restricted-Delaunay refinement of a curve on spade: restricted Delaunay edges certified by interval circumcentres (isotopy not claimed; seeds from fallback lines)",
            crate::restricted_delaunay::BoissonnatOudot2,
            BO2
        ),
        entry!(
            "midnormal",
            2,
            false,
            "planar MidNormal on the triangle tiling",
            planar::MidNormal2,
            GRADNORMAL
        ),
        entry!(
            "gradnormal",
            2,
            false,
            "planar GradNormal (midpoints + projection)",
            planar::GradNormal2,
            GRADNORMAL
        ),
    ]
}

/// Build `name` for a comparison matrix: the options it does not read are dropped
/// (the matrix checks with [`check_used`] that each option is read by some mesher).
pub fn build_shared(name: &str, dim: usize, o: &MesherOptions) -> Result<Box<dyn Mesher>> {
    let name = canonical(name);
    match table().iter().find(|(i, _)| i.name == name && i.dim == dim) {
        Some((info, _)) => build(name, dim, &o.restricted_to(info.reads)),
        None => build(name, dim, o),
    }
}

/// Every option given must be read by at least one of the meshers `(name, dim)`.
pub fn check_used(algos: &[(&str, usize)], o: &MesherOptions) -> Result<()> {
    let t = table();
    let infos: Vec<&AlgoInfo> = t
        .iter()
        .map(|(i, _)| i)
        .filter(|i| algos.contains(&(i.name, i.dim)))
        .collect();
    for x in o.given() {
        if !infos.iter().any(|i| i.reads.contains(&x)) {
            let names: Vec<&str> = infos.iter().map(|i| i.name).collect();
            return Err(Error::Param(format!(
                "option --{x} is not used by any of the algorithms run ({})",
                names.join(", ")
            )));
        }
    }
    Ok(())
}

/// Every registered algorithm.
pub fn list() -> Vec<AlgoInfo> {
    table().into_iter().map(|(i, _)| i).collect()
}

/// Alternative names: `gvn` is the González-Vega–Necula sweep `sweep`.
pub fn canonical(name: &str) -> &str {
    match name {
        "gvn" => "sweep",
        n => n,
    }
}

/// Build the mesher `name` for functions of dimension `dim` (2 curve, 3 surface). An
/// option it does not read is an error naming the option and the mesher.
pub fn build(name: &str, dim: usize, o: &MesherOptions) -> Result<Box<dyn Mesher>> {
    let name = canonical(name);
    let t = table();
    if let Some((info, ctor)) = t.iter().find(|(i, _)| i.name == name && i.dim == dim) {
        if let Some(x) = o.given().into_iter().find(|x| !info.reads.contains(x)) {
            return Err(Error::Param(format!(
                "option --{x} is not used by '{name}' ({}D); it reads {}",
                dim,
                if info.reads.is_empty() {
                    "none".to_string()
                } else {
                    info.reads
                        .iter()
                        .map(|r| format!("--{r}"))
                        .collect::<Vec<_>>()
                        .join(" ")
                }
            )));
        }
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
