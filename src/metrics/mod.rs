//! Mesh metrics: element shape ([`angles`]), combinatorial topology and the topology
//! verdict ([`topology`]), fidelity to the implicit surface ([`fidelity`]), and the
//! [`Stats`] summary that `certmesh stats` prints.
pub mod angles;
pub mod embedding;
pub mod fidelity;
pub mod nearest;
pub mod topology;

pub use angles::{Histogram, TetAngles, TetRanges, TriangleAngles};
pub use embedding::embedding_signature;
pub use fidelity::{Fidelity, FidelityParams};
pub use topology::{
    analyze, analyze_curve, analyze_tets, curve_verdict, tet_verdict, verdict, CurveTopology,
    TetTopology, TopologyReport, Verdict,
};

use crate::error::{Error, Result};
use crate::implicit::Implicit;
use crate::mesh::{Curve2, TetMesh, TriMesh};
use serde::Serialize;

/// The smallest and largest of `values` (`None` for none), e.g. an angle range. NaN
/// values are skipped (`f64::min`/`max` ignore them), so a NaN never hides a range.
pub fn min_max(values: impl IntoIterator<Item = f64>) -> (Option<f64>, Option<f64>) {
    let mut lo: Option<f64> = None;
    let mut hi: Option<f64> = None;
    for v in values {
        lo = Some(lo.map_or(v, |l| l.min(v)));
        hi = Some(hi.map_or(v, |h| h.max(v)));
    }
    (lo, hi)
}

/// Euler characteristic V − E + F of a triangle mesh, counting only the vertices that
/// faces use and leaving degenerate (index-repeating) faces out — the convention of
/// [`analyze`], so that every module computes χ the same way.
pub fn euler_characteristic(mesh: &TriMesh) -> Result<i64> {
    Ok(analyze(mesh)?.euler_characteristic)
}

/// Number of connected components (through shared vertices) of a triangle mesh, as in
/// [`analyze`] (isolated vertices are not components).
pub fn components(mesh: &TriMesh) -> Result<usize> {
    Ok(analyze(mesh)?.components)
}

/// Bin width (degrees) of the angle histograms in [`Stats`].
pub const ANGLE_BIN_DEG: f64 = 5.0;

fn check_indices<const N: usize>(nv: usize, what: &str, elems: &[[u32; N]]) -> Result<()> {
    // The largest index first (a branch-free fold the compiler vectorises); only a
    // mesh that fails is searched for the first bad element, to name it.
    let largest = elems
        .iter()
        .fold(0u32, |m, e| e.iter().fold(m, |m, &v| m.max(v)));
    if elems.is_empty() || (largest as usize) < nv {
        return Ok(());
    }
    for (i, e) in elems.iter().enumerate() {
        if let Some(&v) = e.iter().find(|&&v| v as usize >= nv) {
            return Err(Error::Param(format!(
                "{what} {i} refers to vertex {v}, but the mesh has {nv} vertices"
            )));
        }
    }
    Ok(())
}

fn check_finite<const D: usize>(verts: &[[f64; D]]) -> Result<()> {
    match crate::kernel::finite::first_non_finite(verts.as_flattened()) {
        Some(k) => Err(Error::NotFinite(format!(
            "vertex {} has coordinates {:?}",
            k / D,
            verts[k / D]
        ))),
        None => Ok(()),
    }
}

/// Every index in range and every coordinate finite: metrics never panic on bad input.
pub fn check_trimesh(m: &TriMesh) -> Result<()> {
    check_finite(&m.vertices)?;
    check_indices(m.vertices.len(), "triangle", &m.triangles)
}
pub fn check_tetmesh(m: &TetMesh) -> Result<()> {
    check_finite(&m.vertices)?;
    check_indices(m.vertices.len(), "tetrahedron", &m.tets)
}
pub fn check_curve(c: &Curve2) -> Result<()> {
    check_finite(&c.vertices)?;
    check_indices(c.vertices.len(), "segment", &c.segments)
}

/// What `certmesh stats MESH [--surface S] --json` prints for a triangle mesh.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stats {
    /// Vertices used by at least one face (χ counts these).
    pub vertices: usize,
    /// Vertices of the file that no face uses (a scan's stray points).
    pub isolated_vertices: usize,
    pub faces: usize,
    pub edges: usize,
    pub euler_characteristic: i64,
    pub components: usize,
    pub closed: bool,
    pub manifold: bool,
    pub orientable: bool,
    pub consistently_oriented: bool,
    pub boundary_edges: usize,
    pub boundary_loops: usize,
    pub non_manifold_edges: usize,
    pub non_manifold_vertices: usize,
    pub degenerate_faces: usize,
    pub duplicate_faces: usize,
    /// Genera of the closed orientable manifold components, ascending.
    pub genus: Vec<usize>,
    /// Over non-degenerate triangles (`null` when there is none).
    pub min_angle_deg: Option<f64>,
    pub max_angle_deg: Option<f64>,
    pub mean_min_angle_deg: Option<f64>,
    /// Numerically flat triangles, left out of the angle ranges.
    pub degenerate_triangles: usize,
    pub min_edge_ratio: Option<f64>,
    pub max_edge_ratio: Option<f64>,
    /// Present when a surface was given.
    #[serde(flatten)]
    pub fidelity: Option<Fidelity>,
}

/// Statistics of a triangle mesh, with fidelity fields when `f` is given (default
/// sampling; see [`stats_with`]).
pub fn stats(mesh: &TriMesh, f: Option<&dyn Implicit>) -> Result<Stats> {
    stats_with(mesh, f, &FidelityParams::default())
}

pub fn stats_with(
    mesh: &TriMesh,
    f: Option<&dyn Implicit>,
    params: &FidelityParams,
) -> Result<Stats> {
    Ok(stats_and_topology(mesh, f, params)?.0)
}

/// [`stats_with`] and the [`TopologyReport`] it was computed from (for a verdict
/// without analysing the mesh a second time).
pub fn stats_and_topology(
    mesh: &TriMesh,
    f: Option<&dyn Implicit>,
    params: &FidelityParams,
) -> Result<(Stats, TopologyReport)> {
    stats_and_topology_at(mesh, f, params, Angles::Ranges)
}

/// [`stats_and_topology`] for the report's `--metrics fast`: the angle range without
/// the mean smallest angle and the edge ratios (`None`; [`angles::triangle_extremes`],
/// the same range bit for bit), every other field as [`stats_and_topology`] computes
/// it with `params`.
pub fn stats_and_topology_fast(
    mesh: &TriMesh,
    f: Option<&dyn Implicit>,
    params: &FidelityParams,
) -> Result<(Stats, TopologyReport)> {
    stats_and_topology_at(mesh, f, params, Angles::Extremes)
}

/// [`stats_and_topology_fast`] with the angle range given: `angles` must be
/// [`angles::triangle_extremes`] of `mesh` (a mesher's own measure,
/// [`crate::mesher::MeshOutput::angles`]), which is then not computed again.
pub fn stats_and_topology_fast_given(
    mesh: &TriMesh,
    f: Option<&dyn Implicit>,
    params: &FidelityParams,
    angles: &angles::TriangleAngles,
) -> Result<(Stats, TopologyReport)> {
    stats_and_topology_at(mesh, f, params, Angles::Given(angles))
}

/// Which angle measures the report computes.
#[derive(Clone, Copy)]
enum Angles<'a> {
    /// [`angles::triangle_ranges`]: the range, the mean smallest angle, the ratios.
    Ranges,
    /// [`angles::triangle_extremes`]: the range only.
    Extremes,
    /// The extremes, measured already.
    Given(&'a angles::TriangleAngles),
}

fn stats_and_topology_at(
    mesh: &TriMesh,
    f: Option<&dyn Implicit>,
    params: &FidelityParams,
    which: Angles,
) -> Result<(Stats, TopologyReport)> {
    // Three independent measures, side by side on rayon's threads (each is parallel
    // inside too; the serial parts of one overlap the others).
    let (topo, (ang, fidelity)) = rayon::join(
        || analyze(mesh),
        || {
            rayon::join(
                || match which {
                    Angles::Ranges => angles::triangle_ranges(mesh),
                    Angles::Extremes => angles::triangle_extremes(mesh),
                    Angles::Given(a) => Ok(a.clone()),
                },
                || {
                    f.map(|f| fidelity::surface_fidelity(mesh, f, params))
                        .transpose()
                },
            )
        },
    );
    let (topo, ang, fidelity) = (topo?, ang?, fidelity?);
    let stats = Stats {
        vertices: topo.vertices,
        isolated_vertices: topo.isolated_vertices,
        faces: topo.faces,
        edges: topo.edges,
        euler_characteristic: topo.euler_characteristic,
        components: topo.components,
        closed: topo.closed,
        manifold: topo.manifold,
        orientable: topo.orientable,
        consistently_oriented: topo.consistently_oriented,
        boundary_edges: topo.boundary_edges,
        boundary_loops: topo.boundary_loops,
        non_manifold_edges: topo.non_manifold_edges,
        non_manifold_vertices: topo.non_manifold_vertices,
        degenerate_faces: topo.degenerate_faces,
        duplicate_faces: topo.duplicate_faces,
        genus: topo.genus.clone(),
        min_angle_deg: ang.min_angle_deg,
        max_angle_deg: ang.max_angle_deg,
        mean_min_angle_deg: ang.mean_min_angle_deg,
        degenerate_triangles: ang.degenerate,
        min_edge_ratio: ang.min_edge_ratio,
        max_edge_ratio: ang.max_edge_ratio,
        fidelity,
    };
    Ok((stats, topo))
}

/// Statistics of a tetrahedral mesh: conformity, its boundary's topology and angles,
/// dihedral and face angles; fidelity of the boundary when `f` is given.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TetStats {
    pub vertices: usize,
    pub isolated_vertices: usize,
    pub tets: usize,
    pub components: usize,
    pub boundary_faces: usize,
    pub interior_faces: usize,
    pub nonconforming_faces: usize,
    pub degenerate_tets: usize,
    /// Negative signed volume.
    pub inverted_tets: usize,
    /// Numerically flat tetrahedra, left out of the angle ranges.
    pub flat_tets: usize,
    pub boundary_euler_characteristic: i64,
    pub boundary_components: usize,
    pub boundary_closed_manifold: bool,
    pub boundary_genus: Vec<usize>,
    /// Dihedral, face angle, edge ratio and radius ratio ranges (flattened in JSON).
    #[serde(flatten)]
    pub ranges: TetRanges,
    /// Triangle angles of the boundary surface.
    pub boundary_min_angle_deg: Option<f64>,
    pub boundary_max_angle_deg: Option<f64>,
    #[serde(flatten)]
    pub fidelity: Option<Fidelity>,
}

pub fn tet_stats(
    mesh: &TetMesh,
    f: Option<&dyn Implicit>,
    params: &FidelityParams,
) -> Result<TetStats> {
    let topo = analyze_tets(mesh)?;
    let ang = angles::tet_summary(mesh, ANGLE_BIN_DEG)?;
    let surf = mesh.boundary();
    let bang = angles::triangle_ranges(&surf)?;
    let fidelity = match f {
        Some(f) => Some(fidelity::surface_fidelity(&surf, f, params)?),
        None => None,
    };
    Ok(TetStats {
        vertices: topo.vertices,
        isolated_vertices: topo.isolated_vertices,
        tets: topo.tets,
        components: topo.components,
        boundary_faces: topo.boundary_faces,
        interior_faces: topo.interior_faces,
        nonconforming_faces: topo.nonconforming_faces,
        degenerate_tets: topo.degenerate_tets,
        inverted_tets: ang.inverted,
        flat_tets: ang.degenerate,
        boundary_euler_characteristic: topo.boundary_euler_characteristic,
        boundary_components: topo.boundary.components,
        boundary_closed_manifold: topo.boundary_closed_manifold,
        boundary_genus: topo.boundary.genus.clone(),
        ranges: ang.ranges,
        boundary_min_angle_deg: bang.min_angle_deg,
        boundary_max_angle_deg: bang.max_angle_deg,
        fidelity,
    })
}

/// Statistics of a planar curve.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CurveStats {
    #[serde(flatten)]
    pub topology: CurveTopology,
    pub min_segment_length: Option<f64>,
    pub max_segment_length: Option<f64>,
    /// Smallest angle between consecutive segments at degree-2 vertices (180° is
    /// straight), a measure of how sharply the polyline turns.
    pub min_turn_angle_deg: Option<f64>,
    #[serde(flatten)]
    pub fidelity: Option<Fidelity>,
}

pub fn curve_stats(
    curve: &Curve2,
    f: Option<&dyn Implicit>,
    params: &FidelityParams,
) -> Result<CurveStats> {
    let topology = analyze_curve(curve)?;
    let p = |v: u32| {
        let [x, y] = curve.vertices[v as usize];
        [x, y, 0.0]
    };
    let (lo, hi) = min_max(
        curve
            .segments
            .iter()
            .map(|&[a, b]| crate::kernel::geom::dist(p(a), p(b))),
    );
    let mut nbrs: Vec<Vec<u32>> = vec![Vec::new(); curve.vertices.len()];
    for &[a, b] in &curve.segments {
        if a != b {
            nbrs[a as usize].push(b);
            nbrs[b as usize].push(a);
        }
    }
    let (turn, _) = min_max(
        nbrs.iter()
            .enumerate()
            .filter(|(_, n)| n.len() == 2)
            .map(|(v, n)| crate::kernel::geom::angle_deg(p(n[0]), p(v as u32), p(n[1]))),
    );
    let fidelity = match f {
        Some(f) => Some(fidelity::curve_fidelity(curve, f, params)?),
        None => None,
    };
    Ok(CurveStats {
        topology,
        min_segment_length: lo,
        max_segment_length: hi,
        min_turn_angle_deg: turn,
        fidelity,
    })
}
