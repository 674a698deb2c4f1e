//! Regenerates `papers/meshing-of-surfaces/` (`certmesh reproduce meshing-of-surfaces`):
//! the tables of `subdivision-tables.md` and `report.json`, the subdivision pictures of
//! every catalog curve (like Figs 1.7 and 1.9 of the chapter, §1.2.3–1.2.4), and the
//! boxes-per-depth figure of the 3D runs, and sections z = 0 of marching cubes and PV
//! meshes of `two-spheres` and `thin-torus` (`fig-slice-*`).
//!
//! Sections (each a table in `subdivision-tables.md`):
//! 1. curves: Plantinga–Vegter and Snyder, certificate and components;
//! 2. Fig 1.5: marching squares on regular grids of `protrusion` versus PV;
//! 3. surfaces: PV, Snyder in generic position (depth 14) and Snyder on the plain grid;
//! 4. the paraboloid case of §1.2.3 both ways, and the singular entries;
//! 5. the 3D side-by-side: marching cubes and tetrahedra over a range of grids versus PV
//!    and Snyder on `two-spheres` and `thin-torus`, with evaluation counts;
//! 6. boxes per depth of the 3D runs;
//! 7. Exercise 9: crude versus sharp gradient-cone angle bound.
//!
//! `quick` keeps the run to seconds (fewer grids and surfaces, no Snyder depth-14 runs on
//! the large surfaces); the test suite runs it.
//! (Over 800 lines on purpose: one generator per paper folder, its sections in the
//! order of the tables it writes, so a table and the code that computes it sit together.)
use crate::catalog::{self, Entry};
use crate::error::{Error, Result};
use crate::implicit::{Counted, EvalCounts};
use crate::marching::{MarchingCubes, MarchingSquares, MarchingTetrahedra};
use crate::mesher::options::Crossing;
use crate::mesher::{self, Certificate, Mesh, MeshOutput, Mesher, NoProgress, Run};
use crate::metrics;
use crate::subdivision::plantinga_vegter::{run_pv, PlantingaVegter, PvParams};
use crate::subdivision::snyder::{run_snyder, Snyder, SnyderParams};
use crate::subdivision::{leaf_boxes, AngleBound};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

/// The topology an output has, in words, and whether it is the catalog's.
#[derive(Clone, Debug, Serialize)]
pub struct Found {
    /// e.g. "2 components, genus [0, 0]".
    pub text: String,
    /// `None` for entries without an expected topology (singular).
    pub ok: Option<bool>,
}

/// Judge a mesh against the catalog entry's topology (shared metrics, so the tables and
/// `certmesh compare` agree).
pub fn found(e: &Entry, mesh: &Mesh) -> Result<Found> {
    match mesh {
        Mesh::Curve(c) => {
            let t = metrics::analyze_curve(c)?;
            Ok(match &e.topology {
                Some(want) => {
                    let v = metrics::curve_verdict(&t, want);
                    Found {
                        text: v.found,
                        ok: Some(v.ok),
                    }
                }
                None => Found {
                    text: format!(
                        "{} components ({} closed)",
                        t.components, t.closed_components
                    ),
                    ok: None,
                },
            })
        }
        m => {
            let surf = m
                .surface()
                .ok_or_else(|| Error::Param("no surface in the output".into()))?;
            let r = metrics::analyze(surf)?;
            Ok(match &e.topology {
                Some(want) => {
                    let v = metrics::verdict(&r, want);
                    Found {
                        text: v.found,
                        ok: Some(v.ok),
                    }
                }
                None => Found {
                    text: format!(
                        "{} components, closed = {}, genus {:?}",
                        r.components, r.closed, r.genus
                    ),
                    ok: None,
                },
            })
        }
    }
}

fn stat_u64(o: &MeshOutput, key: &str) -> u64 {
    o.stats.get(key).and_then(|v| v.as_u64()).unwrap_or(0)
}

fn regions(o: &MeshOutput) -> Vec<mesher::Uncertified> {
    match &o.certificate {
        Certificate::Uncertified { regions, .. } => regions.clone(),
        _ => Vec::new(),
    }
}

/// One curve run (section 1).
#[derive(Clone, Debug, Serialize)]
pub struct CurveRow {
    pub curve: String,
    pub expected: String,
    pub pv_leaves: u64,
    pub pv_certified: bool,
    pub pv_found: Found,
    pub snyder_leaves: u64,
    pub snyder_certified: bool,
    pub snyder_found: Found,
}

/// One row of the Fig 1.5 table (section 2).
#[derive(Clone, Debug, Serialize)]
pub struct Fig15Row {
    pub method: String,
    /// "n x m" cells, or leaves.
    pub size: String,
    pub evaluations: EvalCounts,
    pub certified: bool,
    pub found: Found,
}

/// One surface (section 3).
#[derive(Clone, Debug, Serialize)]
pub struct SurfaceRow {
    pub surface: String,
    pub expected: String,
    pub pv_boxes: u64,
    pub pv_leaves: u64,
    pub pv_certified: bool,
    pub pv_found: Found,
    pub pv_seconds: f64,
    pub pv_boxes_by_depth: BTreeMap<u8, u64>,
    /// Snyder with the generic motion, depth 14 (`None`: not run in quick mode).
    pub snyder_shift: Option<SnyderRun>,
    /// Snyder on the plain (axis-aligned, dyadic) grid, depth 10.
    pub snyder_plain: Option<SnyderRun>,
}

#[derive(Clone, Debug, Serialize)]
pub struct SnyderRun {
    pub max_depth: u32,
    pub boxes: u64,
    pub leaves: u64,
    pub certified: bool,
    pub uncertified_boxes: u64,
    pub found: Found,
    pub seconds: f64,
    pub boxes_by_depth: BTreeMap<u8, u64>,
}

/// A singular or grazing case (section 4).
#[derive(Clone, Debug, Serialize)]
pub struct CaseRow {
    pub entry: String,
    pub method: String,
    pub certified: bool,
    pub leaves: u64,
    pub uncertified_regions: usize,
    /// Regions whose reason names a singular point.
    pub singular_regions: usize,
    /// Largest distance of an uncertified region's centre from the origin (where the
    /// node of the singular entries and the tangency of `paraboloid-cap` are).
    pub farthest_region: Option<f64>,
    pub found: Found,
}

/// One run of the 3D side-by-side (section 5).
#[derive(Clone, Debug, Serialize)]
pub struct SideRow {
    pub surface: String,
    /// "mc", "mt", "pv", "pv-linear", "snyder-shift".
    pub method: String,
    /// Cells along each side (grid meshers).
    pub grid: Option<usize>,
    /// Boxes (subdivision meshers).
    pub boxes: Option<u64>,
    pub found: Found,
    pub certified: bool,
    pub evaluations: EvalCounts,
    pub seconds: f64,
}

impl SideRow {
    pub fn correct(&self) -> bool {
        self.found.ok == Some(true)
    }
}

/// Exercise 9 (section 7): boxes for 90° (SNV), 60° crude/sharp, 45° crude/sharp, and
/// whether the depth limit was hit.
#[derive(Clone, Debug, Serialize)]
pub struct Ex9Row {
    pub entry: String,
    pub boxes: Vec<u64>,
    pub limit_hit: Vec<bool>,
}

/// Everything the reproduction computed.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Report {
    pub quick: bool,
    pub curves: Vec<CurveRow>,
    pub fig15: Vec<Fig15Row>,
    pub surfaces: Vec<SurfaceRow>,
    pub cases: Vec<CaseRow>,
    pub side_by_side: Vec<SideRow>,
    pub exercise9: Vec<Ex9Row>,
}

fn by_depth(o: &MeshOutput) -> BTreeMap<u8, u64> {
    o.stats
        .get("boxes_by_depth")
        .and_then(|v| v.as_object())
        .map(|m| {
            m.iter()
                .filter_map(|(k, v)| Some((k.parse().ok()?, v.as_u64()?)))
                .collect()
        })
        .unwrap_or_default()
}

fn snyder_run(e: &Entry, depth: u32, shift: bool) -> Result<SnyderRun> {
    let m = Snyder::new(
        SnyderParams::new(3)
            .with_max_depth(depth)
            .with_generic_shift(shift),
    );
    let r = mesher::run(&m, &e.function(), &e.domain, &NoProgress)?;
    Ok(SnyderRun {
        max_depth: depth,
        boxes: stat_u64(&r.output, "boxes"),
        leaves: stat_u64(&r.output, "leaves"),
        certified: r.output.certificate.is_certified(),
        uncertified_boxes: stat_u64(&r.output, "uncertified_boxes"),
        found: found(e, &r.output.mesh)?,
        seconds: r.seconds,
        boxes_by_depth: by_depth(&r.output),
    })
}

fn case_row(e: &Entry, method: &str, m: &dyn Mesher) -> Result<CaseRow> {
    let r = mesher::run(m, &e.function(), &e.domain, &NoProgress)?;
    let regs = regions(&r.output);
    Ok(CaseRow {
        entry: e.name.into(),
        method: method.into(),
        certified: r.output.certificate.is_certified(),
        leaves: stat_u64(&r.output, "leaves"),
        uncertified_regions: regs.len(),
        singular_regions: regs
            .iter()
            .filter(|x| x.reason.contains("singular"))
            .count(),
        farthest_region: regs
            .iter()
            .map(|x| crate::kernel::geom::norm(x.region.center()))
            .fold(None, |a: Option<f64>, d| Some(a.map_or(d, |a| a.max(d)))),
        found: found(e, &r.output.mesh)?,
    })
}

fn side_row(e: &Entry, method: &str, grid: Option<usize>, r: &Run) -> Result<SideRow> {
    Ok(SideRow {
        surface: e.name.into(),
        method: method.into(),
        grid,
        boxes: r.output.stats.get("boxes").and_then(|v| v.as_u64()),
        found: found(e, &r.output.mesh)?,
        certified: r.output.certificate.is_certified(),
        evaluations: r.evaluations,
        seconds: r.seconds,
    })
}

/// Grids of the side-by-side per surface.
fn grids(name: &str, quick: bool) -> Vec<usize> {
    match (name, quick) {
        ("two-spheres", true) => vec![16, 27, 32],
        // Every grid 16³–64³, then around 2.4/h = 117.5: for odd N the grid points
        // nearest the 0.02 gap are (±h/2, ±h/2, ±h/2), inside both spheres while
        // 0.75h² − 0.51h + 0.0101 < 0, i.e. h > 0.02042, N ≤ 117.
        ("two-spheres", false) => (16..=64)
            .chain([100, 101, 115, 116, 117, 118, 119, 120, 121])
            .collect(),
        (_, true) => vec![16, 24, 34],
        (_, false) => (16..=48).collect(),
    }
}

/// Compute everything (no files written).
pub fn compute(quick: bool) -> Result<Report> {
    let mut rep = Report {
        quick,
        ..Default::default()
    };
    // 1. Curves.
    for e in catalog::curves() {
        let f = e.function();
        let (_, pv) = run_pv(&f, &e.domain, &PvParams::new(2), 2, &NoProgress)?;
        let (_, sn) = run_snyder(&f, &e.domain, &SnyderParams::new(2), 2, &NoProgress)?;
        rep.curves.push(CurveRow {
            curve: e.name.into(),
            expected: expected(&e),
            pv_leaves: stat_u64(&pv, "leaves"),
            pv_certified: pv.certificate.is_certified(),
            pv_found: found(&e, &pv.mesh)?,
            snyder_leaves: stat_u64(&sn, "leaves"),
            snyder_certified: sn.certificate.is_certified(),
            snyder_found: found(&e, &sn.mesh)?,
        });
    }
    // 2. Fig 1.5 with the shared marching squares (`certmesh curve --algo ms`).
    let e = catalog::get("protrusion")?;
    let f = e.function();
    for n in [4usize, 6, 8, 10, 12, 16, 24, 32] {
        let r = mesher::run(
            &MarchingSquares::new().resolution(n),
            &f,
            &e.domain,
            &NoProgress,
        )?;
        let s = e.domain.size();
        let m = ((n as f64) * s[1] / s[0]).round() as usize;
        rep.fig15.push(Fig15Row {
            method: "marching squares".into(),
            size: format!("{n} x {m}"),
            evaluations: r.evaluations,
            certified: false,
            found: found(&e, &r.output.mesh)?,
        });
    }
    for (label, p) in [
        ("PV (bisection to 1e-9)", PvParams::new(2)),
        (
            "PV (linear crossings)",
            PvParams::new(2).with_crossing(Crossing::Linear, 1e-9),
        ),
    ] {
        let cf = Counted::new(&f);
        let (_, pv) = run_pv(&cf, &e.domain, &p, 2, &NoProgress)?;
        rep.fig15.push(Fig15Row {
            method: label.into(),
            size: format!("{} leaves", stat_u64(&pv, "leaves")),
            evaluations: cf.counts(),
            certified: pv.certificate.is_certified(),
            found: found(&e, &pv.mesh)?,
        });
    }
    // 3. Surfaces.
    let heavy = ["torus", "genus2", "genus5", "tanglecube", "thin-torus"];
    for e in catalog::surfaces() {
        if quick && heavy.contains(&e.name) {
            continue;
        }
        let r = mesher::run(
            &PlantingaVegter::default(),
            &e.function(),
            &e.domain,
            &NoProgress,
        )?;
        let (snyder_shift, snyder_plain) = if quick {
            (None, None)
        } else {
            (
                Some(snyder_run(&e, 14, true)?),
                Some(snyder_run(&e, 10, false)?),
            )
        };
        rep.surfaces.push(SurfaceRow {
            surface: e.name.into(),
            expected: expected(&e),
            pv_boxes: stat_u64(&r.output, "boxes"),
            pv_leaves: stat_u64(&r.output, "leaves"),
            pv_certified: r.output.certificate.is_certified(),
            pv_found: found(&e, &r.output.mesh)?,
            pv_seconds: r.seconds,
            pv_boxes_by_depth: by_depth(&r.output),
            snyder_shift,
            snyder_plain,
        });
    }
    // 4. The paraboloid both ways (§1.2.3) and the singular entries.
    let para = catalog::get("paraboloid-cap")?;
    for (label, shift) in [
        ("snyder, depth 8", false),
        ("snyder --generic-shift, depth 8", true),
    ] {
        let m = Snyder::new(
            SnyderParams::new(3)
                .with_max_depth(8)
                .with_generic_shift(shift),
        );
        rep.cases.push(case_row(&para, label, &m)?);
    }
    let cone = catalog::get("double-cone")?;
    rep.cases.push(case_row(
        &cone,
        "pv, depth 8",
        &PlantingaVegter::new(PvParams::new(3).with_max_depth(8)),
    )?);
    rep.cases.push(case_row(
        &cone,
        "snyder, depth 7",
        &Snyder::new(SnyderParams::new(3).with_max_depth(7)),
    )?);
    let lem = catalog::get("lemniscate")?;
    rep.cases.push(case_row(
        &lem,
        "pv",
        &crate::subdivision::plantinga_vegter::PlantingaVegter2::default(),
    )?);
    rep.cases.push(case_row(
        &lem,
        "snyder",
        &crate::subdivision::snyder::Snyder2::default(),
    )?);
    // 5. The 3D side-by-side.
    for name in ["two-spheres", "thin-torus"] {
        let e = catalog::get(name)?;
        let f = e.function();
        for n in grids(name, quick) {
            let r = mesher::run(
                &MarchingCubes::new().resolution(n),
                &f,
                &e.domain,
                &NoProgress,
            )?;
            rep.side_by_side.push(side_row(&e, "mc", Some(n), &r)?);
            let r = mesher::run(
                &MarchingTetrahedra::new().resolution(n),
                &f,
                &e.domain,
                &NoProgress,
            )?;
            rep.side_by_side.push(side_row(&e, "mt", Some(n), &r)?);
        }
        let r = mesher::run(&PlantingaVegter::default(), &f, &e.domain, &NoProgress)?;
        rep.side_by_side.push(side_row(&e, "pv", None, &r)?);
        let lin = PlantingaVegter::new(PvParams::new(3).with_crossing(Crossing::Linear, 1e-9));
        let r = mesher::run(&lin, &f, &e.domain, &NoProgress)?;
        rep.side_by_side.push(side_row(&e, "pv-linear", None, &r)?);
        if !quick || name == "two-spheres" {
            let sn = Snyder::new(
                SnyderParams::new(3)
                    .with_max_depth(14)
                    .with_generic_shift(true),
            );
            let r = mesher::run(&sn, &f, &e.domain, &NoProgress)?;
            rep.side_by_side
                .push(side_row(&e, "snyder-shift", None, &r)?);
        }
    }
    // 7. Exercise 9.
    for e in catalog::entries().into_iter().filter(|e| e.smooth) {
        if quick && !(e.dim == 2 || e.name == "sphere") {
            continue;
        }
        let f = e.function();
        let mut cfgs = vec![(90.0, AngleBound::Sharp)];
        for a in [60.0, 45.0] {
            cfgs.push((a, AngleBound::Crude));
            cfgs.push((a, AngleBound::Sharp));
        }
        let mut row = Ex9Row {
            entry: e.name.into(),
            boxes: Vec::new(),
            limit_hit: Vec::new(),
        };
        for (a, b) in cfgs {
            let p = PvParams::new(e.dim)
                .with_max_angle(a, b)
                .with_max_depth(if e.dim == 2 { 11 } else { 7 });
            let (_, o) = run_pv(&f, &e.domain, &p, e.dim, &NoProgress)?;
            row.boxes.push(stat_u64(&o, "boxes"));
            row.limit_hit.push(!o.certificate.is_certified());
        }
        rep.exercise9.push(row);
    }
    Ok(rep)
}

/// The expected topology of a catalog entry, as the tables print it.
pub fn expected(e: &Entry) -> String {
    match &e.topology {
        Some(t) => {
            let c = format!(
                "{} component{}",
                t.components,
                if t.components == 1 { "" } else { "s" }
            );
            if e.dim == 2 {
                c
            } else {
                format!("{c}, genus {:?}", t.genus)
            }
        }
        None => "singular".into(),
    }
}

fn ok_mark(f: &Found) -> &'static str {
    match f.ok {
        Some(true) => "yes",
        Some(false) => "**no**",
        None => "–",
    }
}

fn evals(c: &EvalCounts) -> String {
    let mut parts = vec![format!("{} pt", c.points)];
    if c.intervals > 0 {
        parts.push(format!("{} iv", c.intervals));
    }
    if c.interval_gradients > 0 {
        parts.push(format!("{} iv-grad", c.interval_gradients));
    }
    if c.gradients > 0 {
        parts.push(format!("{} grad", c.gradients));
    }
    parts.join(" + ")
}

fn depth_list(m: &BTreeMap<u8, u64>) -> String {
    m.iter()
        .map(|(d, n)| format!("{d}:{n}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The markdown of every table.
pub fn markdown(rep: &Report) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Tables (generated by `certmesh reproduce meshing-of-surfaces{}`)\n",
        if rep.quick { " --quick" } else { "" }
    );
    let _ = writeln!(md, "Evaluation counts: pt = point evaluations of f, iv = interval evaluations, iv-grad = interval gradients (forward mode over intervals; several times the cost of a point evaluation each). Times are wall-clock on a shared 2-core machine and only indicative.\n");
    // 1.
    let _ = writeln!(md, "## 1. Curves: Plantinga–Vegter and Snyder\n\n| curve | expected | PV leaves | PV certified | PV found | PV right | Snyder leaves | Snyder certified | Snyder found | Snyder right |\n|---|---|---|---|---|---|---|---|---|---|");
    for r in &rep.curves {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.curve,
            r.expected,
            r.pv_leaves,
            r.pv_certified,
            r.pv_found.text,
            ok_mark(&r.pv_found),
            r.snyder_leaves,
            r.snyder_certified,
            r.snyder_found.text,
            ok_mark(&r.snyder_found)
        );
    }
    // 2.
    let _ = writeln!(md, "\n## 2. Fig 1.5: `protrusion` (1 component); marching squares is `certmesh curve protrusion --algo ms --resolution N` (ambiguous squares: negative corners separated)\n\n| method | grid / leaves | evaluations | certified | found | right |\n|---|---|---|---|---|---|");
    for r in &rep.fig15 {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} |",
            r.method,
            r.size,
            evals(&r.evaluations),
            r.certified,
            r.found.text,
            ok_mark(&r.found)
        );
    }
    // 3.
    let _ = writeln!(md, "\n## 3. Surfaces\n\nSnyder (shift) = `--generic-shift --max-depth 14`; Snyder (plain) = axis-aligned grid, `--max-depth 10`.\n\n| surface | expected | PV boxes | PV leaves | PV certified | PV found | PV right | PV time (ms) | Snyder (shift) leaves | certified | right | time (ms) | Snyder (plain) certified | uncertified boxes | right |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &rep.surfaces {
        let sh = r.snyder_shift.as_ref().map_or("– | – | – | –".into(), |s| {
            format!(
                "{} | {} | {} | {:.0}",
                s.leaves,
                s.certified,
                ok_mark(&s.found),
                s.seconds * 1e3
            )
        });
        let pl = r.snyder_plain.as_ref().map_or("– | – | –".into(), |s| {
            format!(
                "{} | {} | {}",
                s.certified,
                s.uncertified_boxes,
                ok_mark(&s.found)
            )
        });
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {:.0} | {} | {} |",
            r.surface,
            r.expected,
            r.pv_boxes,
            r.pv_leaves,
            r.pv_certified,
            r.pv_found.text,
            ok_mark(&r.pv_found),
            r.pv_seconds * 1e3,
            sh,
            pl
        );
    }
    // 4.
    let _ = writeln!(md, "\n## 4. Grazing and singular cases\n\n`paraboloid-cap` is tangent to the grid plane z = 0 at the origin, a grid corner (the chapter's paraboloid z = x² − xy + y², §1.2.3); `double-cone` and `lemniscate` have a node at the origin. \"farthest\" is the largest distance of an uncertified region's centre from the origin.\n\n| entry | method | certified | leaves | uncertified regions | naming a singular point | farthest | found |\n|---|---|---|---|---|---|---|---|");
    for r in &rep.cases {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            r.entry,
            r.method,
            r.certified,
            r.leaves,
            r.uncertified_regions,
            r.singular_regions,
            r.farthest_region.map_or("–".into(), |d| format!("{d:.3}")),
            r.found.text
        );
    }
    md.push_str(&format!(
        "\n![{DOUBLE_CONE}]({DOUBLE_CONE}.png)\n\n*{DOUBLE_CONE_CAPTION}*\n"
    ));
    // 5.
    let _ = writeln!(md, "\n## 5. The difference a certificate makes, in 3D\n\nMarching cubes (`mc`) and marching tetrahedra (`mt`) on N³ cells versus Plantinga–Vegter (`pv`: crossings bisected to 1e-9 of the edge; `pv-linear`: crossings interpolated, same topology and certificate) and Snyder in generic position (depth 14).\n");
    for name in ["two-spheres", "thin-torus"] {
        let rows: Vec<&SideRow> = rep
            .side_by_side
            .iter()
            .filter(|r| r.surface == name)
            .collect();
        if rows.is_empty() {
            continue;
        }
        let _ = writeln!(md, "### `{name}`\n");
        let _ = writeln!(md, "{}\n", side_summary(&rows));
        let _ = writeln!(md, "| method | grid / boxes | found | right | certified | evaluations | total evaluations | time (ms) |\n|---|---|---|---|---|---|---|---|");
        for r in rows {
            let size = match (r.grid, r.boxes) {
                (Some(n), _) => format!("{n}³"),
                (None, Some(b)) => format!("{b} boxes"),
                _ => "–".into(),
            };
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} | {} | {:.1} |",
                r.method,
                size,
                r.found.text,
                ok_mark(&r.found),
                r.certified,
                evals(&r.evaluations),
                r.evaluations.total(),
                r.seconds * 1e3
            );
        }
        let _ = writeln!(md);
    }
    // 6.
    let _ = writeln!(md, "## 6. Boxes per depth (leaves + internal boxes at each level; `boxes_by_depth` of the JSON report)\n\n| surface | method | boxes by depth (depth:count) |\n|---|---|---|");
    for r in &rep.surfaces {
        let _ = writeln!(
            md,
            "| {} | pv | {} |",
            r.surface,
            depth_list(&r.pv_boxes_by_depth)
        );
        if let Some(s) = &r.snyder_shift {
            let _ = writeln!(
                md,
                "| {} | snyder (shift) | {} |",
                r.surface,
                depth_list(&s.boxes_by_depth)
            );
        }
    }
    // 7.
    let _ = writeln!(md, "\n## 7. Exercise 9: boxes (leaves + internal) needed for a gradient-cone angle bound (depth limit 7 for surfaces, 11 for curves; * = limit hit)\n\n| entry | 90° (SNV) | 60° crude | 60° sharp | 45° crude | 45° sharp |\n|---|---|---|---|---|---|");
    let mut tot = [0u64; 5];
    for r in &rep.exercise9 {
        let cells: Vec<String> = r
            .boxes
            .iter()
            .zip(&r.limit_hit)
            .enumerate()
            .map(|(k, (b, hit))| {
                tot[k] += b;
                format!("{b}{}", if *hit { "*" } else { "" })
            })
            .collect();
        let _ = writeln!(md, "| {} | {} |", r.entry, cells.join(" | "));
    }
    let _ = writeln!(
        md,
        "| **total** | {} |",
        tot.iter()
            .map(|t| t.to_string())
            .collect::<Vec<_>>()
            .join(" | ")
    );
    md
}

/// What the side-by-side shows, in words computed from the rows: where the grid meshers
/// are wrong, and how their evaluation counts compare with PV's.
pub fn side_summary(rows: &[&SideRow]) -> String {
    let mut s = String::new();
    let Some(pv) = rows.iter().find(|r| r.method == "pv") else {
        return s;
    };
    let lin = rows.iter().find(|r| r.method == "pv-linear");
    let e_pv = pv.evaluations.total();
    let _ = write!(
        s,
        "PV: {}, certified = {}, {} evaluations ({})",
        pv.found.text,
        pv.certified,
        e_pv,
        evals(&pv.evaluations)
    );
    if let Some(l) = lin {
        let _ = write!(
            s,
            "; with linear crossings {} ({})",
            l.evaluations.total(),
            evals(&l.evaluations)
        );
    }
    let _ = writeln!(s, ".");
    let e_min = lin.map_or(e_pv, |l| l.evaluations.total().min(e_pv));
    for m in ["mc", "mt"] {
        let g: Vec<&&SideRow> = rows.iter().filter(|r| r.method == m).collect();
        if g.is_empty() {
            continue;
        }
        let wrong: Vec<usize> = g
            .iter()
            .filter(|r| !r.correct())
            .filter_map(|r| r.grid)
            .collect();
        let wrong_costly: Vec<usize> = g
            .iter()
            .filter(|r| !r.correct() && r.evaluations.total() >= e_min)
            .filter_map(|r| r.grid)
            .collect();
        // The smallest grid from which every larger tested grid is right.
        let from = g
            .iter()
            .rposition(|r| !r.correct())
            .map_or(Some(0), |i| (i + 1 < g.len()).then_some(i + 1))
            .map(|i| g[i]);
        let _ = write!(
            s,
            "* `{m}`: wrong at {} of {} grids {}³–{}³{}",
            wrong.len(),
            g.len(),
            g[0].grid.unwrap_or(0),
            g[g.len() - 1].grid.unwrap_or(0),
            if wrong.is_empty() {
                String::new()
            } else {
                format!(
                    " ({})",
                    wrong
                        .iter()
                        .map(|n| format!("{n}³"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            }
        );
        if !wrong_costly.is_empty() {
            let _ = write!(
                s,
                "; wrong with at least PV's evaluation count ({e_min}, the cheaper PV run) at {}",
                wrong_costly
                    .iter()
                    .map(|n| format!("{n}³"))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        match from {
            Some(r) => {
                let _ = writeln!(
                    s,
                    "; right at every tested grid from {}³ on ({} evaluations, {:.2}× PV's {e_min}).",
                    r.grid.unwrap_or(0),
                    r.evaluations.total(),
                    r.evaluations.total() as f64 / e_min.max(1) as f64
                );
            }
            None => {
                let _ = writeln!(s, "; wrong at the largest tested grid.");
            }
        }
    }
    s
}

/// The cross-section of a triangle mesh with the plane z = z0, as a planar polyline set
/// (sign⁺ convention for vertices on the plane, so every crossing lies on an edge with a
/// strict sign change and neighbouring triangles share it).
pub fn slice(m: &crate::mesh::TriMesh, z0: f64) -> crate::mesh::Curve2 {
    let mut c = crate::mesh::Curve2::default();
    let mut ids: std::collections::HashMap<(u32, u32), u32> = Default::default();
    let above = |v: u32| m.vertices[v as usize][2] >= z0;
    for t in &m.triangles {
        let mut pts = Vec::with_capacity(2);
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if above(a) == above(b) {
                continue;
            }
            let key = (a.min(b), a.max(b));
            let id = *ids.entry(key).or_insert_with(|| {
                let (p, q) = (m.vertices[key.0 as usize], m.vertices[key.1 as usize]);
                let s = (z0 - p[2]) / (q[2] - p[2]);
                c.vertices
                    .push([p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])]);
                (c.vertices.len() - 1) as u32
            });
            pts.push(id);
        }
        if let [a, b] = pts[..] {
            c.segments.push([a, b]);
        }
    }
    c
}

/// Slice figures of the side-by-side: `fig-slice-<surface>-<method>.{svg,png}`, the
/// section z = 0 of the output (black) over the true section (red pixels).
fn slice_figures(out: &Path, quick: bool) -> Result<()> {
    for (name, n) in [("two-spheres", 27usize), ("thin-torus", 33)] {
        if quick && name == "thin-torus" {
            continue;
        }
        let e = catalog::get(name)?;
        let f = e.function();
        let mut plane = e.domain;
        plane.min[2] = 0.0;
        plane.max[2] = 0.0;
        let runs: [(String, Box<dyn Mesher>); 2] = [
            (
                format!("mc{n}"),
                Box::new(MarchingCubes::new().resolution(n)),
            ),
            ("pv".into(), Box::new(PlantingaVegter::default())),
        ];
        for (label, m) in runs {
            let o = m.mesh(&f, &e.domain, &NoProgress)?;
            if let Some(surf) = o.mesh.surface() {
                crate::reproduce::plot_subdivision::draw_subdivision_svg(
                    &out.join(format!("fig-slice-{name}-{label}")),
                    &f,
                    &plane,
                    &[],
                    &slice(surf, 0.0),
                )?;
            }
        }
    }
    Ok(())
}

/// Figures of the exact sweep like the chapter's Fig. 1.16: `fig-gvn-<curve>.svg`.
pub fn sweep_figures(out: &Path) -> Result<()> {
    let sq = |h: f64| crate::kernel::geom::Aabb {
        min: [-h, -h, 0.0],
        max: [h, h, 0.0],
    };
    for (name, f, d) in [
        ("lemniscate", "(x^2 + y^2)^2 - 2*(x^2 - y^2)", sq(1.6)),
        ("limacon", "(x^2 + y^2 - x)^2 - (x^2 + y^2)/4", sq(1.6)),
        ("acnode", "y^2 - x^2*(x - 1)", sq(2.5)),
        ("devils-curve", "y^2*(y^2 - 1) - x^2*(x^2 - 2)", sq(2.5)),
    ] {
        let p = crate::algebraic::from_formula(f)?;
        let r = crate::algebraic::analyse(&p, &d, &crate::algebraic::SweepParams::default())?;
        crate::reproduce::plot_sweep::write_sweep(
            &out.join(format!("fig-gvn-{name}")),
            &r,
            &d,
            &format!("GVN sweep: {f}"),
        )?;
    }
    Ok(())
}

fn write(out: &Path, name: &str, text: &str) -> Result<()> {
    let p = out.join(name);
    std::fs::write(&p, text).map_err(|e| Error::io(&p, e))
}

/// Figures: the subdivision of every catalog curve (PV and Snyder) and the boxes per
/// depth of the 3D PV runs.
const DOUBLE_CONE: &str = "render-double-cone-pv";
const DOUBLE_CONE_CAPTION: &str = "An uncertified Plantinga–Vegter output coloured by its own certificate: vermillion faces meet a region it reported uncertified (the singular apex, the surface meeting the domain boundary), grey faces are covered by no claim; nothing here is certified (`certmesh render --surface double-cone --algo pv --max-depth 6 --color certificate --wire`).";

/// The rendering of section 4: PV on the double cone, coloured by its certificate.
fn double_cone_render(out: &Path) -> Result<()> {
    let e = catalog::get("double-cone")?;
    let m = crate::mesher::registry::build(
        "pv",
        3,
        &crate::mesher::options::MesherOptions {
            max_depth: Some(6),
            ..Default::default()
        },
    )?;
    let o = m.mesh(&e.function(), &e.domain, &NoProgress)?;
    let t = o
        .mesh
        .surface()
        .ok_or_else(|| Error::Param("pv made no surface".into()))?;
    crate::render::render(
        &out.join(DOUBLE_CONE),
        crate::render::Input::Surface(t),
        Some(&o.certificate),
        &crate::render::RenderOptions {
            color: crate::render::ColorBy::Certificate,
            wire: true,
            title: "Plantinga–Vegter on the double cone (depth 6)".into(),
            ..Default::default()
        },
        &crate::figure::output::default_formats(),
    )
    .map(|_| ())
}

fn figures(out: &Path, rep: &Report) -> Result<()> {
    double_cone_render(out)?;
    for e in catalog::curves() {
        let f = e.function();
        let (t1, pv) = run_pv(&f, &e.domain, &PvParams::new(2), 2, &NoProgress)?;
        let (t2, sn) = run_snyder(&f, &e.domain, &SnyderParams::new(2), 2, &NoProgress)?;
        for (label, t, o) in [("pv", &t1, &pv), ("snyder", &t2, &sn)] {
            if let Mesh::Curve(c) = &o.mesh {
                crate::reproduce::plot_subdivision::draw_subdivision_svg(
                    &out.join(format!("fig-{label}-{}", e.name)),
                    &f,
                    &e.domain,
                    &leaf_boxes(t),
                    c,
                )?;
            }
        }
    }
    let series = |pick: &dyn Fn(&SurfaceRow) -> Option<BTreeMap<u8, u64>>| {
        rep.surfaces
            .iter()
            .filter(|r| {
                [
                    "sphere",
                    "torus",
                    "genus5",
                    "tanglecube",
                    "two-spheres",
                    "thin-torus",
                ]
                .contains(&r.surface.as_str())
            })
            .filter_map(|r| {
                Some(crate::reproduce::plot::Series {
                    name: r.surface.clone(),
                    points: pick(r)?
                        .iter()
                        .map(|(&d, &n)| (d as f64, (n as f64).log10()))
                        .collect(),
                })
            })
            .collect::<Vec<_>>()
    };
    crate::reproduce::plot::lines(
        &out.join("fig-boxes-per-depth"),
        "Plantinga–Vegter: boxes per depth",
        "depth (level of the octree)",
        "log10(boxes)",
        &series(&|r| Some(r.pv_boxes_by_depth.clone())),
    )?;
    let sn = series(&|r| r.snyder_shift.as_ref().map(|s| s.boxes_by_depth.clone()));
    if !sn.is_empty() {
        crate::reproduce::plot::lines(
            &out.join("fig-boxes-per-depth-snyder"),
            "Snyder (generic shift): boxes per depth",
            "depth (level of the octree)",
            "log10(boxes)",
            &sn,
        )?;
    }
    Ok(())
}

/// Compute, then write `subdivision-tables.md`, `report.json` and the figures into `out`.
pub fn reproduce_report(out: &Path, quick: bool) -> Result<Report> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let rep = compute(quick)?;
    write(out, "subdivision-tables.md", &markdown(&rep))?;
    write(
        out,
        "report.json",
        &serde_json::to_string_pretty(&rep).expect("the report serializes"),
    )?;
    figures(out, &rep)?;
    slice_figures(out, quick)?;
    sweep_figures(out)?;
    crate::reproduce::plot_rdt2d::rdt2d_figures(out)?;
    Ok(rep)
}

/// Regenerate `papers/meshing-of-surfaces/` (or `out`); `quick` runs in seconds.
pub fn reproduce(out: &Path, quick: bool) -> Result<()> {
    reproduce_report(out, quick).map(|_| ())
}
