//! Certify anyone's surface mesh (`certmesh certify`): is it the restricted Delaunay
//! triangulation of its own vertices, and do those vertices have the topological ball
//! property? Both together prove the mesh homeomorphic to S = {f = 0} by Theorem 5 of
//! the chapter "Meshing of Surfaces" (Boissonnat et al., 2007, §1.3.2); see
//! [`super::tbp`]. Nothing is inserted, no local feature size is assumed, and the
//! vertices need not lie on S (the report gives max |f|/|∇f| over them, an
//! outward-rounded first-order estimate of their distance to S, for information).
//!
//! The sample P is the set of distinct vertices the triangles use (unreferenced
//! vertices are left out; exact duplicates are merged). The mesh equals the
//! restricted triangulation when the two sets of vertex triples are equal (either
//! orientation); otherwise the differing triangles are listed.
//!
//! A mesh with duplicate vertices (two indices, one point) is never certified: its
//! triangles, as the file connects them, are not the complex that was checked (a
//! surface cut open along an edge whose vertices are doubled has the same triangles as
//! point sets, but boundary edges and pinched vertices). The report then says whether
//! the copy with those vertices merged would be.
use super::tbp::{self, Failure, TbpOptions, TbpReport, Test};
use crate::error::{Error, Result};
use crate::implicit::Implicit;
use crate::kernel::delaunay::{Delaunay, VertexId};
use crate::kernel::geom::Aabb;
use crate::mesh::TriMesh;
use inari::Interval;
use serde::Serialize;
use std::collections::{HashMap, HashSet};

/// Limits of `certify`.
#[derive(Clone, Copy, Debug)]
pub struct CertifyOptions {
    pub tbp: TbpOptions,
    /// Seed of the kernel's insertion order.
    pub seed: u64,
    /// How many differing triangles and failures the report lists (all are counted).
    pub max_listed: usize,
    /// Seconds from the start: the Voronoi facets and cells not checked by then are
    /// not proven (the report says so). `None`: no limit.
    pub time_limit: Option<f64>,
}

/// The largest estimated heap of a check ([`estimated_bytes`]): 16 GiB, as for
/// `certmesh delaunay`. A larger mesh is refused before any work.
pub const MAX_BYTES: u64 = 16 << 30;

/// Heap per sample point of a check, rounded up: the triangulation, its interval
/// circumcentres, the dual segments' scan, the Voronoi adjacency and the covers' cache
/// together. Measured as peak resident memory over the points of MC tori of 13,000
/// to 140,000 vertices (see [`estimated_bytes`]).
pub const BYTES_PER_POINT: u64 = 6_000;

/// Heap a check of a mesh with `n` used vertices is estimated to need.
pub fn estimated_bytes(n: usize) -> u64 {
    (n as u64).saturating_mul(BYTES_PER_POINT)
}

impl Default for CertifyOptions {
    fn default() -> Self {
        CertifyOptions {
            tbp: TbpOptions::default(),
            seed: 1,
            max_listed: 20,
            time_limit: None,
        }
    }
}

/// A triangle of one set and not of the other (mesh vertex ids).
#[derive(Clone, Debug, Serialize)]
pub struct Differing {
    pub vertices: [u32; 3],
    /// In the given mesh (and not in the restricted triangulation), or the reverse.
    pub in_mesh: bool,
}

/// A TBP failure with mesh vertex ids as its sites.
#[derive(Clone, Debug, Serialize)]
pub struct MeshFailure {
    pub test: Test,
    pub sites: Vec<u32>,
    pub point: [f64; 3],
    pub reason: String,
}

/// What `certify` found.
#[derive(Clone, Debug, Serialize)]
pub struct CertifyReport {
    pub mesh_vertices: usize,
    pub mesh_triangles: usize,
    /// Distinct vertices used by triangles: the sample P.
    pub sample_points: usize,
    pub unreferenced_vertices: usize,
    /// Vertices at the same point as an earlier one (merged in P). Any makes the mesh
    /// uncertified (see the module's documentation).
    pub duplicate_vertices: usize,
    pub vertices_outside_domain: usize,
    /// Facets of the certified restricted Delaunay triangulation of P.
    pub rdt_facets: usize,
    /// (a) The mesh is the restricted Delaunay triangulation of its vertices.
    pub is_rdt: bool,
    pub mesh_triangles_not_in_rdt: usize,
    pub rdt_facets_not_in_mesh: usize,
    pub differing: Vec<Differing>,
    /// (b) The topological ball property.
    pub tbp: TbpReport,
    pub failures: Vec<MeshFailure>,
    /// Outward-rounded max over the vertices of |f| / |∇f| (`None` where ∇f may vanish).
    pub max_f_over_grad: Option<f64>,
    /// (c) (a) and (b), and no duplicate vertices: the mesh is homeomorphic to S.
    pub homeomorphic: bool,
    pub verdict: String,
    pub seconds: f64,
}

fn isup(x: Interval) -> f64 {
    x.sup()
}

/// sup |f(p)| / inf |∇f(p)| over the points, in interval arithmetic.
fn max_f_over_grad(f: &dyn Implicit, pts: &[[f64; 3]]) -> Option<f64> {
    let mut m: f64 = 0.0;
    for p in pts {
        let b = p.map(tbp::cover::pt);
        let d = f.grad_interval(&b);
        let g2 = d.g[0].sqr() + d.g[1].sqr() + d.g[2].sqr();
        let grad_away_from_0 = g2.inf() > 0.0;
        if !grad_away_from_0 || d.v.is_empty() {
            return None;
        }
        let fv = isup(d.v.abs());
        let r = fv / g2.inf().sqrt();
        m = m.max(r * (1.0 + 4.0 * f64::EPSILON));
    }
    Some(m)
}

/// Certify `mesh` against f = 0 inside `domain`. Returns the report and the certified
/// restricted Delaunay triangulation of the mesh's vertices (oriented towards f > 0).
pub fn certify_mesh(
    mesh: &TriMesh,
    f: &dyn Implicit,
    domain: &Aabb,
    o: &CertifyOptions,
) -> Result<(CertifyReport, TriMesh)> {
    let t0 = std::time::Instant::now();
    if f.dim() != 3 {
        return Err(Error::Param(
            "certify compares a surface mesh with a surface f(x, y, z) = 0; the function is a curve"
                .into(),
        ));
    }
    let nv = mesh.vertices.len();
    if mesh.triangles.is_empty() {
        return Err(Error::Param("the mesh has no triangles".into()));
    }
    for (i, t) in mesh.triangles.iter().enumerate() {
        if let Some(&v) = t.iter().find(|&&v| v as usize >= nv) {
            return Err(Error::Param(format!(
                "triangle {i} refers to vertex {v}, but the mesh has {nv} vertices"
            )));
        }
    }
    let mut used: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    let bytes = estimated_bytes(used.len());
    if bytes > MAX_BYTES {
        return Err(Error::Param(format!(
            "the mesh has {} vertices in its triangles: checking them would need about {:.1} GB ({} bytes per vertex), more than the {:.1} GB limit",
            used.len(),
            bytes as f64 / 1e9,
            BYTES_PER_POINT,
            MAX_BYTES as f64 / 1e9
        )));
    }
    let pts: Vec<[f64; 3]> = used.iter().map(|&v| mesh.vertices[v as usize]).collect();
    let (t, bulk) = Delaunay::from_points(&pts, o.seed)?;
    // Mesh vertex -> kernel vertex (duplicates -> their first occurrence).
    let mut dup: HashMap<usize, usize> = HashMap::new();
    for &(i, first) in &bulk.duplicates {
        dup.insert(i, first);
    }
    let local: HashMap<u32, usize> = used.iter().enumerate().map(|(k, &v)| (v, k)).collect();
    let kernel_of = |v: u32| -> VertexId {
        let k = local[&v];
        t.vertex_of_input(*dup.get(&k).unwrap_or(&k))
    };
    let mesh_of = |v: VertexId| -> u32 { t.input_index(v).map(|k| used[k]).unwrap_or(u32::MAX) };
    let outside = pts.iter().filter(|p| !domain.contains(**p)).count();

    let tbp_options = TbpOptions {
        deadline: o
            .time_limit
            .map(|tl| t0 + std::time::Duration::from_secs_f64(tl)),
        ..o.tbp
    };
    let check = tbp::check(&t, f, domain, &tbp_options);
    let key = |v: [VertexId; 3]| {
        let mut k = v;
        k.sort_unstable();
        k
    };
    let rdt: HashSet<[VertexId; 3]> = check.rdt.facets.iter().map(|x| key(x.v)).collect();
    let given: Vec<([VertexId; 3], [u32; 3])> = mesh
        .triangles
        .iter()
        .map(|tr| (key(tr.map(kernel_of)), *tr))
        .collect();
    let given_set: HashSet<[VertexId; 3]> = given.iter().map(|x| x.0).collect();
    let mut differing = Vec::new();
    let mut not_in_rdt = 0;
    let mut seen = HashSet::new();
    for (k, tr) in &given {
        // A degenerate triangle (a repeated vertex) is never a Delaunay facet.
        let degenerate = k[0] == k[1] || k[1] == k[2];
        if (degenerate || !rdt.contains(k)) && seen.insert(*k) {
            not_in_rdt += 1;
            if differing.len() < o.max_listed {
                differing.push(Differing {
                    vertices: *tr,
                    in_mesh: true,
                });
            }
        }
    }
    let duplicate_triangles = given.len() - given_set.len();
    let mut missing: Vec<[VertexId; 3]> = rdt.difference(&given_set).copied().collect();
    missing.sort_unstable();
    for k in &missing {
        if differing.len() < 2 * o.max_listed {
            differing.push(Differing {
                vertices: k.map(mesh_of),
                in_mesh: false,
            });
        }
    }
    let is_rdt = not_in_rdt == 0 && missing.is_empty() && duplicate_triangles == 0;
    let failures: Vec<MeshFailure> = check
        .failures
        .iter()
        .take(o.max_listed)
        .map(|x: &Failure| MeshFailure {
            test: x.test,
            sites: x.sites.iter().map(|&v| mesh_of(v)).collect(),
            point: x.point,
            reason: x.reason.clone(),
        })
        .collect();
    let holds = check.report.holds;
    let duplicates = bulk.duplicates.len();
    let homeomorphic = is_rdt && holds && duplicates == 0;
    let verdict = if homeomorphic {
        "certified homeomorphic to f = 0 inside the domain (topological ball property, Theorem 5; homeomorphism, not isotopy)".to_string()
    } else {
        let mut why = Vec::new();
        if duplicates > 0 {
            why.push(format!(
                "{duplicates} vertices repeat the point of an earlier vertex, so the \
                 triangles as the file connects them are not the triangulation checked \
                 (the copy with those vertices merged {})",
                if is_rdt && holds {
                    "would be certified"
                } else {
                    "would not be certified either"
                }
            ));
        }
        if !is_rdt {
            why.push(format!(
                "the mesh is not the restricted Delaunay triangulation of its vertices ({} of its triangles are not restricted facets{}, {} restricted facets are missing)",
                not_in_rdt,
                if duplicate_triangles > 0 {
                    format!(", {duplicate_triangles} duplicated")
                } else {
                    String::new()
                },
                missing.len()
            ));
        }
        if !holds {
            let r = &check.report;
            why.push(format!(
                "the topological ball property is not proven ({} set-up, {} Voronoi edge, {} manifold, {} Voronoi facet, {} Voronoi cell failures{})",
                check.failures.iter().filter(|x| x.test == Test::Setup).count(),
                r.edge_failures,
                r.manifold_failures,
                r.facet_failures,
                r.cell_failures,
                if outside > 0 {
                    format!("; {outside} vertices outside the domain")
                } else {
                    String::new()
                }
            ));
            if r.timed_out {
                why.push(format!(
                    "the time limit ({} s) passed before the checks were done: {} not run on every Voronoi face (raise --time-limit)",
                    o.time_limit.unwrap_or(f64::NAN),
                    r.skipped
                        .iter()
                        .map(|t| format!("{t:?}").to_lowercase())
                        .collect::<Vec<_>>()
                        .join(", ")
                ));
            }
        }
        format!("not certified: {}", why.join("; "))
    };
    let (rdt_mesh, _) = super::bo::to_mesh(&t, &check.rdt);
    let report = CertifyReport {
        mesh_vertices: nv,
        mesh_triangles: mesh.triangles.len(),
        sample_points: pts.len() - bulk.duplicates.len(),
        unreferenced_vertices: nv - used.len(),
        duplicate_vertices: bulk.duplicates.len(),
        vertices_outside_domain: outside,
        rdt_facets: check.rdt.facets.len(),
        is_rdt,
        mesh_triangles_not_in_rdt: not_in_rdt,
        rdt_facets_not_in_mesh: missing.len(),
        differing,
        tbp: check.report,
        failures,
        max_f_over_grad: max_f_over_grad(f, &pts),
        homeomorphic,
        verdict,
        seconds: t0.elapsed().as_secs_f64(),
    };
    Ok((report, rdt_mesh))
}
