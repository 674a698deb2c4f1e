//! The refuted claims of Hass & Trnkova (2020), shown in real meshes (issue #6).
//!
//! The `proofs gradnormal` certificate refutes Theorem 1.1's upper bound 101.5°, the
//! Appendix A / Sec. 4.3 bound 101.45°, and Fig 14's extremes 35.3004° / 101.445° of the
//! valence-four triangles (`papers/gradnormal/PROOF.md`). Its witnesses are plane
//! normals on the *boundary* of a region of normals, where the offending triangle is
//! created or not depending on ties; here each witness normal is moved slightly into
//! the region, the plane n·x = c is meshed by the project's [`GradNormal`] mesher (the
//! paper's rules, e = 0.2, in [−1, 1]³), and the offending angle is read off the output
//! mesh, over triangles at least e inside the box.
//!
//! For a plane one gradient step is the exact orthogonal projection, so each output
//! triangle is exactly the paper's model (an elementary triangle or a valence-four
//! triangle, projected onto the plane): no approximation separates the mesh from the
//! claim. To attribute an angle to the valence-four step (Fig 14's claims concern only
//! those triangles) the pipeline is replayed with its lattice keys and each output
//! triangle is matched, bit for bit, to a replayed one.
use super::{GradNormal, GradNormalParams};
use crate::error::{Error, Result};
use crate::implicit::Formula;
use crate::kernel::geom::{angle_deg, dot, Aabb};
use crate::mesh::TriMesh;
use crate::mesher::NoProgress;
use std::collections::HashSet;

/// The certified extremes of the paper's rule at a/e = √2/4 (`papers/gradnormal/PROOF.md`):
/// min ∈ [35.264388818°, 35.264389683°], max ∈ [101.536959033°, 101.536959532°].
pub const CERTIFIED_MIN: (f64, f64) = (35.264388818, 35.264389683);
pub const CERTIFIED_MAX: (f64, f64) = (101.536959033, 101.536959532);

/// The proof's witness of the largest angle: the valence-four square at BC, cut at C,
/// triangle mid(CA) mid(CD) mid(CA₂), angle at mid(CD); m = (2/3, −1/√3, −√2/3)
/// (printed as (0.666666667, −0.577350269, −0.471404521), C and D₂ at the same height).
pub fn max_witness_normal() -> [f64; 3] {
    [2.0 / 3.0, -(1.0f64 / 3.0).sqrt(), -(2.0f64).sqrt() / 3.0]
}

/// The proof's witness of the smallest valence-four angle: the square at AD, cut at A,
/// triangle mid(AB) mid(AC) mid(AB₂), angle at mid(AB); m = (−1/√3, 0, −√(2/3)) = n_BCD
/// (printed as (−0.577350269, 0, −0.816496581)), a vertex of the region Y.
pub fn min_witness_normal() -> [f64; 3] {
    [-(1.0f64 / 3.0).sqrt(), 0.0, -(2.0f64 / 3.0).sqrt()]
}

/// The extreme angles of one GradNormal mesh of a plane, over the interior triangles,
/// and over those made by the valence-four removal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneAngles {
    pub min_all: f64,
    pub max_all: f64,
    pub min_v4: f64,
    pub max_v4: f64,
    /// Interior triangles of the mesher's output.
    pub triangles: usize,
    /// Of them, made by the valence-four removal.
    pub v4_triangles: usize,
    /// Output triangles not found in the replayed pipeline (0 unless the replay differs).
    pub unmatched: usize,
}

fn bits(t: [[f64; 3]; 3]) -> [[u64; 3]; 3] {
    let mut b = t.map(|p| p.map(f64::to_bits));
    b.sort_unstable();
    b
}

/// Mesh n·x = c in [−1, 1]³ with GradNormal (`params`, scale default 0.2) and measure.
pub fn plane_angles(n: [f64; 3], c: f64, params: &GradNormalParams) -> Result<PlaneAngles> {
    let b = Aabb::cube(1.0);
    let f = Formula::surface(&format!(
        "{:e}*x + {:e}*y + {:e}*z - {:e}",
        n[0], n[1], n[2], c
    ))?;
    let mut params = params.clone();
    if params.scale.is_none() {
        params.scale = Some(0.2);
    }
    // The mesher's output: the mesh whose angles are reported.
    let (mesh, _) = GradNormal::new(params.clone()).run(&f, &b, &NoProgress)?;
    // The pipeline's stages (the function `GradNormal::run` itself uses), keeping the
    // elementary triangles to tell which ones the valence-four step made.
    let st = GradNormal::new(params.clone()).stages(&f, &b, &NoProgress)?;
    let (g, pos, elementary, tris) = (st.goldberg, st.positions, st.elementary, st.triangles);
    let corners = |t: &[u32; 3]| t.map(|i| pos[i as usize]);
    let elem: HashSet<[[u64; 3]; 3]> = elementary.iter().map(|t| bits(corners(t))).collect();
    let all: HashSet<[[u64; 3]; 3]> = tris.iter().map(|t| bits(corners(t))).collect();
    let inner = b.inflate(-g.e);
    let mut out = PlaneAngles {
        min_all: f64::INFINITY,
        max_all: f64::NEG_INFINITY,
        min_v4: f64::INFINITY,
        max_v4: f64::NEG_INFINITY,
        triangles: 0,
        v4_triangles: 0,
        unmatched: 0,
    };
    for t in 0..mesh.triangles.len() {
        let [p, q, r] = mesh.corners(t);
        if ![p, q, r].iter().all(|&x| inner.contains(x)) {
            continue;
        }
        out.triangles += 1;
        let a = [angle_deg(r, p, q), angle_deg(p, q, r), angle_deg(q, r, p)];
        let (lo, hi) = (a[0].min(a[1]).min(a[2]), a[0].max(a[1]).max(a[2]));
        out.min_all = out.min_all.min(lo);
        out.max_all = out.max_all.max(hi);
        let k = bits([p, q, r]);
        if !all.contains(&k) {
            out.unmatched += 1;
        } else if !elem.contains(&k) {
            out.v4_triangles += 1;
            out.min_v4 = out.min_v4.min(lo);
            out.max_v4 = out.max_v4.max(hi);
        }
    }
    Ok(out)
}

/// A claim of the paper and the real mesh that contradicts it.
#[derive(Clone, Debug)]
pub struct RefutedClaim {
    pub claim: &'static str,
    /// The paper's value, and whether the claim is an upper (true) or lower bound.
    pub paper_value: f64,
    pub upper: bool,
    /// Whether only the valence-four triangles count (Fig 14).
    pub valence4_only: bool,
    /// The proof's witness normal the search started from.
    pub witness: [f64; 3],
    /// The plane meshed: normal and offset.
    pub normal: [f64; 3],
    pub offset: f64,
    /// The offending angle measured in the GradNormal mesh.
    pub measured: f64,
    pub measurement: PlaneAngles,
}

impl RefutedClaim {
    /// Does the measured angle contradict the claim?
    pub fn shown(&self) -> bool {
        if self.upper {
            self.measured > self.paper_value
        } else {
            self.measured < self.paper_value
        }
    }
}

fn tangent_basis(m: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    use crate::kernel::geom::{cross, normalize};
    let a = if m[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = normalize(cross(m, a));
    let v = cross(m, u);
    (u, v)
}

/// The candidate planes around a witness normal: normals m + δ(cos φ u + sin φ v),
/// normalised, for δ ∈ {1e-3, 3e-4, 1e-4} and 12 directions φ, each at the offsets
/// c = ±f·δ·e, f ∈ {0.05, 0.2, 0.5}, e = 0.2. Why offsets this small: the witnesses
/// are normals of lattice planes (several lattice vertices at equal heights, e.g. C and
/// D₂ for the maximum), and the offending triangle needs the plane to pass *between*
/// two such vertices, which the tilt δ separates by about δ·e; the origin is a lattice
/// vertex, so these planes pass just beside a lattice level. (A generic offset gives a
/// plane strictly between two levels: a periodic mesh of one shape, 50.8°/67.8° here.)
pub fn candidates(m: [f64; 3]) -> Vec<([f64; 3], f64)> {
    let (u, v) = tangent_basis(m);
    let mut out = Vec::new();
    for d in [1e-3, 3e-4, 1e-4] {
        for f in [0.05, 0.2, 0.5] {
            for sign in [1.0, -1.0] {
                let c = sign * f * d * 0.2;
                for k in 0..12 {
                    let phi = std::f64::consts::TAU * k as f64 / 12.0;
                    let w = [0, 1, 2].map(|i| m[i] + d * (phi.cos() * u[i] + phi.sin() * v[i]));
                    let l = dot(w, w).sqrt();
                    out.push((w.map(|x| x / l), c));
                }
            }
        }
    }
    out
}

/// For each refuted claim, the most offending plane among [`candidates`] around the
/// proof's witness, meshed with the paper's rules at e = 0.2.
pub fn refuted_claims() -> Result<Vec<RefutedClaim>> {
    use rayon::prelude::*;
    let params = GradNormalParams::new().with_scale(0.2);
    let mut out = Vec::new();
    // (claim, paper value, upper bound?, valence-four only?, witness)
    let specs: [(&str, f64, bool, bool, [f64; 3]); 4] = [
        (
            "Theorem 1.1: all angles ≤ 101.5° (as e → 0)",
            101.5,
            true,
            false,
            max_witness_normal(),
        ),
        (
            "Appendix A / Sec. 4.3: all angles ≤ 101.45°",
            101.45,
            true,
            false,
            max_witness_normal(),
        ),
        (
            "Fig 14: the valence-four triangles' largest angle is 101.445°",
            101.4455,
            true,
            true,
            max_witness_normal(),
        ),
        (
            "Fig 14: the valence-four triangles' smallest angle is 35.3004°",
            35.30035,
            false,
            true,
            min_witness_normal(),
        ),
    ];
    let mut cache: Vec<([f64; 3], Vec<(([f64; 3], f64), PlaneAngles)>)> = Vec::new();
    for (claim, value, upper, v4, m) in specs {
        if !cache.iter().any(|(w, _)| *w == m) {
            let res: Vec<(([f64; 3], f64), PlaneAngles)> = candidates(m)
                .par_iter()
                .map(|&(n, c)| plane_angles(n, c, &params).map(|a| ((n, c), a)))
                .collect::<Result<_>>()?;
            cache.push((m, res));
        }
        let res = &cache.iter().find(|(w, _)| *w == m).expect("cached").1;
        let pick = |a: &PlaneAngles| match (upper, v4) {
            (true, false) => a.max_all,
            (true, true) => a.max_v4,
            (false, false) => a.min_all,
            (false, true) => a.min_v4,
        };
        let best = res
            .iter()
            .filter(|(_, a)| pick(a).is_finite())
            .max_by(|x, y| {
                let (a, b) = (pick(&x.1), pick(&y.1));
                if upper {
                    a.total_cmp(&b)
                } else {
                    b.total_cmp(&a)
                }
            })
            .ok_or_else(|| {
                Error::Param(format!(
                    "no candidate plane produced a triangle for '{claim}'"
                ))
            })?;
        out.push(RefutedClaim {
            claim,
            paper_value: value,
            upper,
            valence4_only: v4,
            witness: m,
            normal: best.0 .0,
            offset: best.0 .1,
            measured: pick(&best.1),
            measurement: best.1,
        });
    }
    Ok(out)
}

/// The markdown section of `papers/gradnormal/README.md` listing the claims.
pub fn markdown(claims: &[RefutedClaim]) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(s, "## Refuted claims, shown in real meshes (issue #6)\n");
    let _ = writeln!(s, "Each proof witness (`papers/gradnormal/PROOF.md`) is a plane normal on the boundary of a region, where the offending triangle exists or not by a tie; it is moved into the region by δ ∈ {{10⁻³, 3·10⁻⁴, 10⁻⁴}} in 12 directions, with the plane offset c = ±(0.05, 0.2 or 0.5)·δ·e (the witnesses are normals of lattice planes; the offending triangle needs the plane to pass between two lattice vertices that the tilt separates by about δ·e, so it must pass just beside a lattice level; a generic offset gives a periodic mesh of one triangle shape), the plane n·x = c is meshed in [−1, 1]³ by the project's GradNormal mesher (paper's rules, a/e = √2/4, e = 0.2, one projection step, which for a plane is the exact orthogonal projection), and the angle is measured on the output triangles at least e inside the box. Fig 14's claims concern only the triangles made by the valence-four removal; those are identified by replaying the pipeline with the lattice keys and matching the output triangles bit for bit. Certified extremes for comparison: min ∈ [{:.9}°, {:.9}°], max ∈ [{:.9}°, {:.9}°]. Regenerated by `certmesh reproduce gradnormal`; checked by the test `refuted_claims_show_in_the_real_mesh`.\n",
        CERTIFIED_MIN.0, CERTIFIED_MIN.1, CERTIFIED_MAX.0, CERTIFIED_MAX.1);
    let _ = writeln!(
        s,
        "| claim | proof witness m | plane meshed: n, c | angle in the mesh | triangles counted (valence-four) | shown? |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    for c in claims {
        let f = |v: [f64; 3]| format!("({:.9}, {:.9}, {:.9})", v[0], v[1], v[2]);
        let _ = writeln!(
            s,
            "| {} | {} | {}, {:.3e} | **{:.6}°** {} {}° | {} ({}) | {} |",
            c.claim,
            f(c.witness),
            f(c.normal),
            c.offset,
            c.measured,
            if c.upper { ">" } else { "<" },
            c.paper_value,
            c.measurement.triangles,
            c.measurement.v4_triangles,
            if c.shown() { "**yes**" } else { "no" }
        );
    }
    let _ = writeln!(s, "\nReproduce one row: `certmesh mesh --formula \"n0*x + n1*y + n2*z - c\" --domain -1,-1,-1,1,1,1 --algo gradnormal --scale 0.2 -o plane.obj`, then `certmesh stats plane.obj` (the stats include the 2-ring of triangles at the box boundary; the table excludes triangles within e of it). The measured angles stay inside the certified enclosures, as they must: they are values at normals inside the region, the certified numbers are the suprema/infima over its closure.\n");
    s
}

/// A plane's mesh as the mesher outputs it (for writing the witness meshes).
pub fn plane_mesh(n: [f64; 3], c: f64) -> Result<TriMesh> {
    let f = Formula::surface(&format!(
        "{:e}*x + {:e}*y + {:e}*z - {:e}",
        n[0], n[1], n[2], c
    ))?;
    Ok(GradNormal::new(GradNormalParams::new().with_scale(0.2))
        .run(&f, &Aabb::cube(1.0), &NoProgress)?
        .0)
}
