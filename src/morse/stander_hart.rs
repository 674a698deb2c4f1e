//! The Stander–Hart sweep through the level parameter (the chapter "Meshing of
//! Surfaces", §1.5.1, Fig. 1.22): `--algo stander-hart`.
//!
//! The chapter sweeps the level a from below min f up to 0, maintaining a mesh of
//! f = a and patching it at every critical value. Its step length "has not been
//! analysed". This version replaces the small steps by what Morse theory proves:
//! 1. **Critical data** (certified): the critical points of f in the domain by the
//!    interval Krawczyk search ([`crate::implicit::critical`]), each with a value
//!    enclosure and a certified index, and f > 0 proven on ∂D
//!    ([`crate::implicit::critical::sublevel_euler_characteristic`]; the sweep needs
//!    exactly its hypotheses: f Morse on {f ≤ 0}, no critical value 0).
//! 2. **Levels**: the value enclosures below 0 are grouped into clusters (overlapping
//!    enclosures: equal values by symmetry, e.g. the tanglecube's 8 minima); one level
//!    a_k in each gap between clusters, and a = 0 last. On f⁻¹[a_k, a_{k+1}] there is no
//!    critical point (the search is complete there), so the level sets are isotopic
//!    along that interval (gradient flow of f/|∇f|², which stays in int D because f > 0
//!    on ∂D and a ≤ 0): one level per gap suffices, and `--set steps=N` adds more for
//!    an animation.
//! 3. **Transitions**: passing a cluster, {f ≤ a} gains one λ-cell per critical point
//!    of index λ (Milnor, *Morse Theory*, 1963, Thm 3.2): index 0 a new sphere is born,
//!    index 1 a 1-handle (two pieces join, or a tunnel opens: Fig. 1.22 read left to
//!    right), index 2 a 2-handle (a tunnel closes, or a piece pinches off), index 3 a
//!    cavity fills (a sphere dies). So χ(f⁻¹(a)) = 2·Σ_{f(p) < a} (−1)^index, which is
//!    checked against each level mesh's χ. Which of the two readings of index 1 or 2
//!    happens is *not* determined by critical data (Fig. 1.23): not claimed.
//! 4. **Level meshes**: each level f = a_k is meshed by Plantinga–Vegter (its own
//!    certificate, reported per level); the mesh of f = 0 is the last level and the
//!    output. Every level is meshed afresh, so the sequence of level meshes
//!    (`--set levels-dir=DIR`, each with its own certificate; `--set steps=N` for more
//!    frames) animates the sweep. The chapter's patching of the previous mesh
//!    (ray-shot triangle removal and a cylinder for a new handle, a cut and two caps
//!    for a pinch) is offered beside it for animations, `--set patch=true`
//!    ([`crate::morse::patch`]): uncertified, reported per level with its χ against
//!    the Morse prediction; it never replaces the certified output.
//!
//! **Certificate.** Certified when the critical data are certified and the last
//! level's Plantinga–Vegter run is: the claims are then PV's isotopy claims for the
//! output; the stats (`stander_hart`) state the critical values, indices, the levels
//! and each level's own certificate. Otherwise uncertified, with why (e.g. the
//! torus: f is not proven Morse, its circle of minima), and no claims: the last
//! level's own PV claims are then only in the stats (`last_level_claims`), and the
//! stats' `certified` list leaves out the critical data when they are not certified. The chapter's remedy for
//! degenerate critical points (multiply f by a + ‖x − b‖) is offered only when asked
//! for, `--set remedy=smooth|chapter[:A[:BX,BY,BZ]]` ([`crate::morse::remedy`]): the
//! sweep then runs through the levels of g = f·h, which has the sign of f, so its
//! level 0 is S and {g ≤ 0} = {f ≤ 0}; the report states the transformation
//! (`stander_hart.transformation`) and that the intermediate levels are g's, not f's.
//! The chapter's own h is not smooth at b, where the certified interval Hessian does
//! not apply (boxes around b stay undecided unless f > 0 there); `smooth`,
//! h = a + ‖x − b‖², is our variant that certifies the torus, the thin torus and the
//! superquadric (`papers/meshing-of-surfaces/morse.md`, §3).
use crate::error::{Error, Result};
use crate::implicit::critical::{self, Budget, Bx, MorseIndex, Side};
use crate::implicit::number::{Dual, Hyper};
use crate::implicit::{Counted, IBox, Implicit, Regularity};
use crate::kernel::geom::Aabb;
use crate::mesher::options::MesherOptions;
use crate::mesher::{check_input, Certificate, MeshOutput, Mesher, Progress};
use crate::subdivision::plantinga_vegter::PlantingaVegter;
use inari::Interval;
use serde::Serialize;
use serde_json::json;

/// The `--set` keys of `stander-hart` (all other keys go to Plantinga–Vegter).
pub const SETTINGS: &[&str] = &[
    "steps",
    "levels-dir",
    "gradient-boxes",
    "remedy",
    "patch",
    "gradient-depth",
];

/// f − a: the level set f = a as the zero set of an oracle.
pub struct Level<'a> {
    pub inner: &'a dyn Implicit,
    pub a: f64,
}

impl Implicit for Level<'_> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn eval(&self, p: [f64; 3]) -> f64 {
        self.inner.eval(p) - self.a
    }
    fn eval_interval(&self, b: &IBox) -> Interval {
        self.inner.eval_interval(b) - critical::linalg::pt(self.a)
    }
    fn grad(&self, p: [f64; 3]) -> Dual<f64> {
        let d = self.inner.grad(p);
        Dual {
            v: d.v - self.a,
            g: d.g,
        }
    }
    fn grad_interval(&self, b: &IBox) -> Dual<Interval> {
        let d = self.inner.grad_interval(b);
        Dual {
            v: d.v - critical::linalg::pt(self.a),
            g: d.g,
        }
    }
    fn hessian(&self, p: [f64; 3]) -> Hyper<f64> {
        let h = self.inner.hessian(p);
        Hyper {
            v: h.v - self.a,
            g: h.g,
            h: h.h,
        }
    }
    fn hessian_interval(&self, b: &IBox) -> Hyper<Interval> {
        let h = self.inner.hessian_interval(b);
        Hyper {
            v: h.v - critical::linalg::pt(self.a),
            g: h.g,
            h: h.h,
        }
    }
    fn is_rigorous(&self) -> bool {
        self.inner.is_rigorous()
    }
    fn regularity(&self, b: &IBox) -> Regularity {
        self.inner.regularity(b)
    }
    fn describe(&self) -> String {
        format!("({}) - ({})", self.inner.describe(), self.a)
    }
}

/// The Stander–Hart mesher.
#[derive(Clone, Debug)]
pub struct StanderHart {
    /// The mesher of every level.
    pub pv: PlantingaVegter,
    /// Levels per critical-free gap (default 1: enough for the isotopy; more for an
    /// animation of the sweep). At most 64.
    pub steps: usize,
    /// Write every level mesh as `level-KK.obj` into this folder.
    pub levels_dir: Option<std::path::PathBuf>,
    /// Box budget of the search for ∇f = 0 (default 50 000, `--set gradient-boxes=N`;
    /// a degenerate critical set spends it, and the sweep is then uncertified). The
    /// search also stops at the time limit of `pv` (`--time-limit`).
    pub gradient_boxes: usize,
    /// Bisection depth of that search (default 30, `--set gradient-depth=D`, 1..=200;
    /// a nearly degenerate critical point, such as the thin torus's through the
    /// remedy, needs 45).
    pub gradient_depth: u32,
    /// Sweep the levels of g = f·h instead of f (`--set remedy=...`, see
    /// [`crate::morse::remedy`]); kept as text until the domain is known.
    pub remedy: Option<String>,
    /// Also run the chapter's patching of the previous mesh from the empty mesh
    /// (`--set patch=true`, [`crate::morse::patch`]): uncertified, for animations;
    /// reported per level (`stander_hart.patched`), written as `patched-KK.obj` with
    /// `levels-dir`.
    pub patch: bool,
}

impl StanderHart {
    pub fn from_options(o: &MesherOptions) -> Result<Self> {
        let mut pv_opts = o.clone();
        pv_opts.extra.retain(|k, _| !SETTINGS.contains(&k.as_str()));
        let pv = PlantingaVegter::from_options(&pv_opts).map_err(|e| match e {
            Error::Param(m) => Error::Param(format!(
                "{m} (stander-hart also knows: {})",
                SETTINGS.join(", ")
            )),
            e => e,
        })?;
        let steps = o.get::<usize>("steps")?.unwrap_or(1);
        if !(1..=64).contains(&steps) {
            return Err(Error::Param(format!(
                "--set steps={steps}: must lie in 1..=64"
            )));
        }
        let gradient_boxes = o.get::<usize>("gradient-boxes")?.unwrap_or(50_000);
        if gradient_boxes == 0 {
            return Err(Error::Param(
                "--set gradient-boxes must be at least 1".into(),
            ));
        }
        let levels_dir = o.extra.get("levels-dir").map(std::path::PathBuf::from);
        if let Some(d) = &levels_dir {
            if !d.is_dir() {
                return Err(Error::Param(format!(
                    "--set levels-dir={}: not an existing folder",
                    d.display()
                )));
            }
        }
        let patch = o.get::<bool>("patch")?.unwrap_or(false);
        let gradient_depth = o.get::<u32>("gradient-depth")?.unwrap_or(30);
        if !(1..=200).contains(&gradient_depth) {
            return Err(Error::Param(format!(
                "--set gradient-depth={gradient_depth}: must lie in 1..=200"
            )));
        }
        let remedy = o.extra.get("remedy").cloned();
        if let Some(r) = &remedy {
            // Refuse a malformed transformation before any work (the domain only moves
            // the default b).
            crate::morse::remedy::Remedy::parse(r, Bx::from(Aabb::cube(1.0)))?;
        }
        Ok(StanderHart {
            pv,
            steps,
            levels_dir,
            gradient_boxes,
            gradient_depth,
            remedy,
            patch,
        })
    }
}

/// A cluster of critical values (overlapping enclosures).
#[derive(Clone, Debug, Serialize)]
pub struct Cluster {
    /// The hull of the value enclosures.
    pub value: [f64; 2],
    /// Critical points by index 0..3.
    pub indices: [usize; 4],
    /// What happens to {f ≤ a} as a passes the cluster.
    pub events: Vec<String>,
    /// χ(f⁻¹(a)) just above the cluster, predicted by Morse theory.
    pub chi_after: i64,
}

/// One level of the sweep.
#[derive(Clone, Debug, Serialize)]
pub struct LevelRun {
    pub a: f64,
    /// χ(f⁻¹(a)) predicted by the critical data (`None` when they are not certified).
    pub chi_predicted: Option<i64>,
    pub chi_mesh: i64,
    pub components: usize,
    pub genus: Vec<usize>,
    pub vertices: usize,
    pub triangles: usize,
    /// The level mesh's own Plantinga–Vegter certificate proves its isotopy to f = a.
    pub certified: bool,
    pub certificate_reason: Option<String>,
    pub evaluations: u64,
    pub seconds: f64,
    pub file: Option<String>,
}

fn events(indices: &[usize; 4]) -> Vec<String> {
    let what = [
        "index 0: a sphere is born",
        "index 1: a 1-handle (two pieces join, or a tunnel opens; which one is not determined by critical data)",
        "index 2: a 2-handle (a tunnel closes, or a piece pinches off; not determined by critical data)",
        "index 3: a cavity fills (a sphere dies)",
    ];
    (0..4)
        .filter(|&i| indices[i] > 0)
        .map(|i| format!("{} x {}", indices[i], what[i]))
        .collect()
}

/// The clusters of critical values below 0 of a complete, certified search, in
/// increasing order.
pub fn clusters(points: &[critical::CriticalPoint]) -> Vec<Cluster> {
    let mut below: Vec<(&critical::CriticalPoint, u8)> = points
        .iter()
        .filter(|p| critical::side(p.value) == Side::Below)
        .filter_map(|p| p.index.index().map(|i| (p, i)))
        .collect();
    below.sort_by(|a, b| a.0.value[0].total_cmp(&b.0.value[0]));
    let mut out: Vec<Cluster> = Vec::new();
    for (p, i) in below {
        match out.last_mut() {
            Some(c) if p.value[0] <= c.value[1] => {
                c.value[1] = c.value[1].max(p.value[1]);
                c.indices[i as usize] += 1;
            }
            _ => {
                let mut indices = [0; 4];
                indices[i as usize] = 1;
                out.push(Cluster {
                    value: p.value,
                    indices,
                    events: vec![],
                    chi_after: 0,
                });
            }
        }
    }
    let mut chi = 0i64;
    for c in &mut out {
        chi += 2
            * (c.indices[0] as i64 - c.indices[1] as i64 + c.indices[2] as i64
                - c.indices[3] as i64);
        c.chi_after = chi;
        c.events = events(&c.indices);
    }
    out
}

impl StanderHart {
    /// The chapter's sweep by patching (see [`crate::morse::patch`]): from the empty
    /// mesh, patch at every critical point below each level and move onto it.
    fn patched_sweep(
        &self,
        f: &dyn Implicit,
        domain: &Aabb,
        points: &[critical::CriticalPoint],
        levels: &[(f64, Option<i64>)],
    ) -> Result<Vec<crate::morse::patch::PatchedLevel>> {
        use crate::morse::patch::{self, Crossing, PatchedLevel};
        let mut below: Vec<(f64, Crossing)> = points
            .iter()
            .filter(|p| critical::side(p.value) == Side::Below)
            .filter_map(|p| {
                p.index.index().map(|i| {
                    (
                        0.5 * (p.value[0] + p.value[1]),
                        Crossing {
                            point: p.point,
                            index: i,
                        },
                    )
                })
            })
            .collect();
        below.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut m = crate::mesh::TriMesh::default();
        let mut out = Vec::new();
        let mut prev = f64::NEG_INFINITY;
        let max_step = 0.05 * domain.diagonal();
        for (k, &(a, chi_predicted)) in levels.iter().enumerate() {
            let cross: Vec<Crossing> = below
                .iter()
                .filter(|(v, _)| *v > prev && *v < a)
                .map(|(_, c)| *c)
                .collect();
            let (applied, failed, max_residual) = patch::advance(&mut m, f, &cross, a, max_step);
            let (chi, closed_manifold) = patch::shape(&m);
            let file = match &self.levels_dir {
                Some(d) if !m.triangles.is_empty() => {
                    let p = d.join(format!("patched-{k:02}.obj"));
                    crate::io::write_tri(&p, &m)?;
                    Some(p.display().to_string())
                }
                _ => None,
            };
            out.push(PatchedLevel {
                a,
                applied,
                failed,
                vertices: m.vertices.len(),
                triangles: m.triangles.len(),
                chi,
                chi_predicted,
                closed_manifold,
                max_residual,
                file,
            });
            prev = a;
        }
        Ok(out)
    }
}

impl Mesher for StanderHart {
    fn name(&self) -> &'static str {
        "stander-hart"
    }
    fn dim(&self) -> usize {
        3
    }
    fn mesh(&self, f: &dyn Implicit, domain: &Aabb, progress: &dyn Progress) -> Result<MeshOutput> {
        check_input(f, domain, 3, "stander-hart")?;
        let t0 = std::time::Instant::now();
        // The search for ∇f = 0 has the mesher's time limit too (a degenerate critical
        // set with a large `gradient-boxes` otherwise runs for minutes).
        let budget = Budget {
            max_depth: self.gradient_depth,
            max_boxes: self.gradient_boxes,
            time_limit: self.pv.params.time_limit,
            ..Budget::default()
        };
        let remedy = match &self.remedy {
            Some(r) => Some(crate::morse::remedy::Remedy::parse(r, Bx::from(*domain))?),
            None => None,
        };
        let remedied = remedy.map(|r| r.apply(f));
        // The swept function: f, or g = f·h when the remedy was asked for (same sign
        // everywhere, so the same zero set and sublevel set {≤ 0}).
        let swept: &dyn Implicit = match &remedied {
            Some(g) => g,
            None => f,
        };
        let counted = Counted::new(swept);
        let sub = critical::sublevel_euler_characteristic(&counted, Bx::from(*domain), budget);
        let critical_evals = counted.counts().total();
        let critical_seconds = t0.elapsed().as_secs_f64();
        let morse_ok = sub.chi_sublevel.is_some();
        let cl = if morse_ok {
            clusters(&sub.gradient.points)
        } else {
            Vec::new()
        };
        // The levels: one (or `steps`) in each gap between clusters, then 0.
        let mut levels: Vec<(f64, Option<i64>)> = Vec::new();
        for k in 0..cl.len() {
            let lo = cl[k].value[1];
            let hi = if k + 1 < cl.len() {
                cl[k + 1].value[0]
            } else {
                0.0
            };
            for s in 1..=self.steps {
                let a = lo + (hi - lo) * s as f64 / (self.steps + 1) as f64;
                if a > lo && a < hi {
                    levels.push((a, Some(cl[k].chi_after)));
                }
            }
        }
        let chi_final = cl.last().map_or(0, |c| c.chi_after);
        levels.push((0.0, morse_ok.then_some(chi_final)));
        progress.start("stander-hart levels", levels.len() as u64);
        let mut runs: Vec<LevelRun> = Vec::new();
        let mut last: Option<MeshOutput> = None;
        for (k, &(a, chi_predicted)) in levels.iter().enumerate() {
            // Levels a < 0 of the swept function; the last level a = 0 of f itself (the
            // same set: g = 0 iff f = 0), so the output is Plantinga–Vegter's mesh of f.
            let lf = Level {
                inner: if a == 0.0 { f } else { swept },
                a,
            };
            let c = Counted::new(&lf);
            let t = std::time::Instant::now();
            let out = self.pv.mesh(&c, domain, &crate::mesher::NoProgress)?;
            let seconds = t.elapsed().as_secs_f64();
            let surf = out.mesh.surface().cloned().unwrap_or_default();
            let topo = crate::metrics::analyze(&surf)?;
            let file = match &self.levels_dir {
                Some(d) => {
                    let p = d.join(format!("level-{k:02}.obj"));
                    crate::io::write_tri(&p, &surf)?;
                    Some(p.display().to_string())
                }
                None => None,
            };
            runs.push(LevelRun {
                a,
                chi_predicted,
                chi_mesh: topo.euler_characteristic,
                components: topo.components,
                genus: topo.genus.clone(),
                vertices: surf.vertices.len(),
                triangles: surf.triangles.len(),
                certified: out.certificate.proves_topology(),
                certificate_reason: out.certificate.reason().map(String::from),
                evaluations: c.counts().total(),
                seconds,
                file,
            });
            progress.inc(1);
            last = Some(out);
        }
        progress.finish();
        let patched = if self.patch && morse_ok {
            self.patched_sweep(swept, domain, &sub.gradient.points, &levels)?
        } else {
            Vec::new()
        };
        let pv_out = last.expect("at least the level 0");
        let mismatches: Vec<f64> = runs
            .iter()
            .filter(|r| r.certified && r.chi_predicted.is_some_and(|c| c != r.chi_mesh))
            .map(|r| r.a)
            .collect();
        let final_run = runs.last().expect("level 0");
        let reason = if !morse_ok {
            Some(format!(
                "the sweep is not certified: {}",
                sub.reason.clone().unwrap_or_default()
            ))
        } else if !pv_out.certificate.proves_topology() {
            Some(format!(
                "the last level (f = 0) is not certified by Plantinga-Vegter: {}",
                pv_out.certificate.reason().unwrap_or("")
            ))
        } else if !mismatches.is_empty() {
            Some(format!(
                "the chi of certified level meshes differs from the Morse prediction at a = {mismatches:?}: an internal inconsistency"
            ))
        } else {
            None
        };
        // The claims are the last level's Plantinga–Vegter claims, made by the sweep
        // only when it is certified: an uncertified sweep lists none (a claim beside
        // "uncertified" reads as made by the run). What the last level's own PV run
        // proved stays in the stats: `levels[].certified` and `last_level_claims`.
        let last_level_claims: Vec<String> = if pv_out.certificate.is_certified() {
            pv_out.certificate.claims().to_vec()
        } else {
            Vec::new()
        };
        let certificate = match &reason {
            None => Certificate::certified(pv_out.certificate.claims_typed().to_vec()),
            Some(r) => {
                let regions = match &pv_out.certificate {
                    Certificate::Uncertified { regions, .. } => regions.clone(),
                    _ => Vec::new(),
                };
                Certificate::uncertified(r.clone(), Vec::new(), regions)
            }
        };
        // What the sweep proved: the critical data and what follows from them only
        // when they are certified.
        let mut certified_items: Vec<&str> = Vec::new();
        let mut not_certified: Vec<String> = Vec::new();
        if morse_ok {
            certified_items.extend([
                "the critical points of f in the domain, their value enclosures and Morse indices (interval Krawczyk, certified Hessian inertia)",
                "no critical point in f^-1[a_k, a_k+1] between consecutive levels: the level sets are isotopic there",
                "chi of every level set, 2 * sum of (-1)^index below it",
            ]);
        } else {
            not_certified.push(format!(
                "the critical data (critical points, value enclosures, Morse indices), and with them the isotopy between levels and the chi of each level: {}",
                sub.reason.clone().unwrap_or_default()
            ));
        }
        certified_items.push(
            "each level mesh to the extent of its own Plantinga-Vegter certificate (levels[].certified)",
        );
        not_certified.extend([
            "which reading of an index-1 or index-2 transition happens (join vs tunnel; the chapter's Fig. 1.23)".to_string(),
            "patched meshes (--set patch=true): the chapter's ray-shot patching, for animations only; the output is level 0 meshed afresh".to_string(),
            if remedy.is_some() {
                "the levels a < 0 as level sets of f: with the remedy they are g's (only a = 0 is shared)"
            } else {
                "the remedy for degenerate critical points (--set remedy=smooth or chapter) was not asked for"
            }
            .to_string(),
        ]);
        let total_level_evals: u64 = runs.iter().map(|r| r.evaluations).sum();
        let points: Vec<serde_json::Value> = sub
            .gradient
            .points
            .iter()
            .map(|p| {
                json!({
                    "point": p.point, "value": p.value,
                    "index": p.index.index(),
                    "degenerate": matches!(p.index, MorseIndex::PossiblyDegenerate),
                })
            })
            .collect();
        let mut stats = pv_out.stats.clone();
        stats.insert(
            "stander_hart".into(),
            json!({
                "transformation": remedy.map(|r| json!({
                    "kind": r.kind, "a": r.a, "b": r.b, "g": r.describe(&f.describe()),
                    "statement": "h > 0, so g = f*h has the sign of f: {g <= 0} = {f <= 0} and g = 0 is S; the critical data and the intermediate levels (a < 0) are g's, the last level (a = 0) is f = 0",
                })),
                "patched": if self.patch {
                    if morse_ok { json!(patched) } else { json!("not run: the critical data are not certified") }
                } else {
                    serde_json::Value::Null
                },
                "critical_data_certified": morse_ok,
                "critical_data_reason": sub.reason,
                "critical_points": points,
                "undecided_boxes": sub.gradient.undecided.len(),
                "undecided_above_zero": sub.undecided_above,
                "clusters": cl,
                "levels": runs,
                "chi_predicted": final_run.chi_predicted,
                "chi_final_mesh": final_run.chi_mesh,
                "critical_search_evaluations": critical_evals,
                "critical_search_seconds": critical_seconds,
                "level_evaluations": total_level_evals,
                "pv_alone_evaluations": final_run.evaluations,
                "last_level_claims": last_level_claims,
                "last_level_claims_are": "the claims of the last level's own Plantinga-Vegter certificate (f = 0, the output), empty when that level is not certified; the sweep's certificate makes them only when it is certified",
                "certified": certified_items,
                "not_certified": not_certified,
            }),
        );
        Ok(MeshOutput {
            mesh: pv_out.mesh,
            certificate,
            stats,
            angles: None,
        })
    }
}
