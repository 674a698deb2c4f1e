//! Figures of the Boissonnat–Oudot refinement of a curve (`--algo bo` in 2D,
//! [`crate::restricted_delaunay::curve`]), like the chapter "Meshing of Surfaces"
//! (Boissonnat et al., 2007, §1.3) draws restricted Delaunay meshes: the sample, the
//! Voronoi edges of the sample (inside the domain), the crossings of those edges with
//! the curve (the centres of the curve Delaunay balls) with their balls, the restricted
//! Delaunay edges, and the curve itself; one figure per stage of the refinement
//! (`papers/meshing-of-surfaces/fig-rdt2d-<curve>-<stage>.{svg,png}`).
//!
//! A stage is the run stopped by `--max-vertices n`: the refinement is deterministic,
//! so the sample of the stage-n run is the first n points of the full run.
use crate::catalog;
use crate::error::{Error, Result};
use crate::figure::output::{self, Meta};
use crate::figure::palette::{self, tint};
use crate::figure::style::{self, perr, pt, stroke, Key, Width, LINE_PT, THIN_PT};
use crate::implicit::ops::SegmentBudget;
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;
use crate::mesher::NoProgress;
use crate::restricted_delaunay::curve::{refine, scan, BoissonnatOudot2, FAR};
use plotters::prelude::*;
use spade::handles::FixedVertexHandle;
use spade::Triangulation;
use std::path::Path;

const CURVE: RGBColor = palette::REDDISH_PURPLE;
const VORONOI: RGBColor = palette::GREY;
const RESTRICTED: RGBColor = palette::BLUE;
const CENTRE: RGBColor = palette::VERMILLION;

/// What one stage shows (also the numbers of the markdown section).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Stage {
    pub curve: String,
    pub file: String,
    pub max_vertices: Option<usize>,
    pub vertices: usize,
    pub restricted_edges: usize,
    pub refinement_complete: bool,
    pub largest_ball: f64,
}

/// Clip the segment a → b to the box (Liang–Barsky); `None` when it misses it.
fn clip(a: [f64; 2], b: [f64; 2], d: &Aabb) -> Option<([f64; 2], [f64; 2])> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let dx = [b[0] - a[0], b[1] - a[1]];
    for k in 0..2 {
        for (p, q) in [(-dx[k], a[k] - d.min[k]), (dx[k], d.max[k] - a[k])] {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
            } else {
                let r = q / p;
                if p < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
            }
        }
    }
    (t0 <= t1).then(|| {
        (
            [a[0] + t0 * dx[0], a[1] + t0 * dx[1]],
            [a[0] + t1 * dx[0], a[1] + t1 * dx[1]],
        )
    })
}

fn circumcentre(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> [f64; 2] {
    let (bx, by) = (b[0] - a[0], b[1] - a[1]);
    let (cx, cy) = (c[0] - a[0], c[1] - a[1]);
    let d = 2.0 * (bx * cy - by * cx);
    let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
    [
        a[0] + (cy * b2 - by * c2) / d,
        a[1] + (bx * c2 - cx * b2) / d,
    ]
}

/// Draw one stage: run the refinement with `params` (its `max_vertices` the stage),
/// then write `base.<ext>`.
pub fn stage_figure(
    base: &Path,
    name: &str,
    f: &dyn Implicit,
    domain: &Aabb,
    params: &BoissonnatOudot2,
    label: &str,
    view: Option<Aabb>,
) -> Result<Stage> {
    // The window drawn: the domain, or a zoom into it.
    let view = view.unwrap_or(*domain);
    let r = refine(params, f, domain, &NoProgress)?;
    let t = &r.t;
    let s = scan(t, f, domain, false, SegmentBudget::default());
    let pos = |v: usize| {
        let p = t.vertex(FixedVertexHandle::from_index(v)).position();
        [p.x, p.y]
    };
    // Voronoi edges of the sample inside the domain (duals of sample-sample edges;
    // the far points' cells miss the domain).
    let mut voronoi = Vec::new();
    for e in t.undirected_edges() {
        let d = e.as_directed();
        let [a, b] = d.vertices().map(|v| v.fix().index());
        if a < FAR || b < FAR {
            continue;
        }
        let (Some(l), Some(rr)) = (d.opposite_vertex(), d.rev().opposite_vertex()) else {
            continue;
        };
        let (pa, pb) = (pos(a), pos(b));
        let c0 = circumcentre(pa, pb, pos(l.fix().index()));
        let c1 = circumcentre(pb, pa, pos(rr.fix().index()));
        if let Some(seg) = clip(c0, c1, &view) {
            voronoi.push(seg);
        }
    }
    let samples: Vec<[f64; 2]> = (FAR..t.num_vertices()).map(pos).collect();
    let mut balls = Vec::new();
    let mut largest: f64 = 0.0;
    for e in &s.edges {
        for x in &e.test.crossings {
            balls.push(([x.point[0], x.point[1]], x.radius));
            largest = largest.max(x.radius);
        }
    }
    let stage = Stage {
        curve: name.to_string(),
        file: base
            .file_name()
            .map(|x| x.to_string_lossy().to_string())
            .unwrap_or_default(),
        max_vertices: (params.max_vertices < 1_000_000).then_some(params.max_vertices),
        vertices: samples.len(),
        restricted_edges: s.edges.len(),
        refinement_complete: r.stats.refinement_complete,
        largest_ball: largest,
    };

    let keys: Vec<(String, Key)> = vec![
        ("f = 0".into(), Key::Line(CURVE)),
        ("Voronoi edges of the sample".into(), Key::Line(VORONOI)),
        ("sample points".into(), Key::Dot(palette::BLACK, true)),
        ("restricted Delaunay edges".into(), Key::Line(RESTRICTED)),
        (
            "crossings: curve Delaunay ball centres".into(),
            Key::Dot(CENTRE, false),
        ),
        (
            "curve Delaunay balls".into(),
            Key::Dashed(tint(CENTRE, 0.3)),
        ),
    ];
    let meta = Meta::chart(
        "x (domain units)",
        "y (domain units)",
        keys.iter().map(|k| k.0.clone()).collect(),
        keys.len(),
    );
    let ds = view.size();
    if !(ds[0] > 0.0 && ds[1] > 0.0) {
        return Err(Error::Domain("a 2D figure needs a domain with area".into()));
    }
    let aspect = (ds[1] / ds[0]).clamp(0.3, 1.6) * 0.86 + 0.3;
    let title = format!(
        "{name}, {label}: {} points, {} restricted edges",
        stage.vertices, stage.restricted_edges
    );
    let inside = |p: [f64; 2]| {
        p[0] >= view.min[0] && p[0] <= view.max[0] && p[1] >= view.min[1] && p[1] <= view.max[1]
    };
    output::figure(base, Width::Column, aspect, &meta, |area| {
        let top = style::legend_below(area, &keys)?;
        let (x0, x1, y0, y1) = (view.min[0], view.max[0], view.min[1], view.max[1]);
        let mut chart = style::chart(&top, &title, x0..x1, y0..y1)?;
        style::axes(&mut chart, "x (domain units)", "y (domain units)")?;
        // The curve: grid cells where f changes sign, about 2 per printed point.
        let (pw, ph) = chart.plotting_area().dim_in_pixel();
        let (nx, ny) = ((pw as usize / 3).max(2), (ph as usize / 3).max(2));
        let (dx, dy) = ((x1 - x0) / nx as f64, (y1 - y0) / ny as f64);
        let signs: Vec<bool> = (0..=ny)
            .flat_map(|j| (0..=nx).map(move |i| (i, j)))
            .map(|(i, j)| f.eval([x0 + i as f64 * dx, y0 + j as f64 * dy, 0.0]) >= 0.0)
            .collect();
        let at = |i: usize, j: usize| signs[j * (nx + 1) + i];
        let mut cells = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let s0 = at(i, j);
                if s0 != at(i + 1, j) || s0 != at(i, j + 1) || s0 != at(i + 1, j + 1) {
                    let (cx, cy) = (x0 + i as f64 * dx, y0 + j as f64 * dy);
                    cells.push(Rectangle::new(
                        [(cx, cy), (cx + dx, cy + dy)],
                        tint(CURVE, 0.25).filled(),
                    ));
                }
            }
        }
        chart.draw_series(cells).map_err(perr)?;
        chart
            .draw_series(voronoi.iter().map(|(a, b)| {
                PathElement::new(
                    vec![(a[0], a[1]), (b[0], b[1])],
                    VORONOI.stroke_width(stroke(THIN_PT)),
                )
            }))
            .map_err(perr)?;
        // Balls as polygons in data coordinates, clipped to the domain.
        let ball_style = tint(CENTRE, 0.3).stroke_width(stroke(THIN_PT));
        for (c, rad) in &balls {
            let n = 96;
            let pts: Vec<[f64; 2]> = (0..=n)
                .map(|k| {
                    let th = std::f64::consts::TAU * k as f64 / n as f64;
                    [c[0] + rad * th.cos(), c[1] + rad * th.sin()]
                })
                .collect();
            let segs = pts
                .windows(2)
                .step_by(2)
                .filter_map(|w| clip(w[0], w[1], &view))
                .map(|(a, b)| PathElement::new(vec![(a[0], a[1]), (b[0], b[1])], ball_style));
            chart.draw_series(segs).map_err(perr)?;
        }
        chart
            .draw_series(
                s.edges
                    .iter()
                    .filter_map(|e| clip(pos(e.v[0]), pos(e.v[1]), &view))
                    .map(|(a, b)| {
                        PathElement::new(
                            vec![(a[0], a[1]), (b[0], b[1])],
                            RESTRICTED.stroke_width(stroke(LINE_PT * 1.5)),
                        )
                    }),
            )
            .map_err(perr)?;
        chart
            .draw_series(
                samples
                    .iter()
                    .filter(|p| inside(**p))
                    .map(|p| Circle::new((p[0], p[1]), pt(1.4) as i32, palette::BLACK.filled())),
            )
            .map_err(perr)?;
        chart
            .draw_series(balls.iter().filter(|(c, _)| inside(*c)).map(|(c, _)| {
                Circle::new(
                    (c[0], c[1]),
                    pt(1.3) as i32,
                    CENTRE.stroke_width(stroke(THIN_PT * 1.5)),
                )
            }))
            .map_err(perr)?;
        Ok(())
    })?;
    Ok(stage)
}

/// One figure of [`RUNS`].
struct Run {
    curve: &'static str,
    size: f64,
    distance: f64,
    /// The stage: a vertex budget, or `None` for the complete run.
    budget: Option<usize>,
    /// `--manifold`.
    manifold: bool,
    /// A zoom window (xmin, xmax, ymin, ymax), or `None` for the domain.
    zoom: Option<[f64; 4]>,
    suffix: &'static str,
}

const fn fig(curve: &'static str, size: f64, distance: f64, suffix: &'static str) -> Run {
    Run {
        curve,
        size,
        distance,
        budget: None,
        manifold: false,
        zoom: None,
        suffix,
    }
}

/// The figures drawn: three stages on cassini-1; near-touching at a coarse facet
/// distance (a bridge across the gap: the whole domain and a zoom), the same with the
/// manifold phase, and at a fine distance.
const RUNS: &[Run] = &[
    Run {
        budget: Some(8),
        ..fig("cassini-1", 0.25, 0.02, "0")
    },
    Run {
        budget: Some(16),
        ..fig("cassini-1", 0.25, 0.02, "1")
    },
    fig("cassini-1", 0.25, 0.02, "2"),
    fig("near-touching", 0.2, 0.05, "d0p05"),
    Run {
        zoom: Some([-0.16, 0.16, -0.13, 0.13]),
        ..fig("near-touching", 0.2, 0.05, "d0p05-zoom")
    },
    Run {
        manifold: true,
        zoom: Some([-0.16, 0.16, -0.13, 0.13]),
        ..fig("near-touching", 0.2, 0.05, "d0p05-manifold-zoom")
    },
    fig("near-touching", 0.2, 0.01, "d0p01"),
];

/// Write every `fig-rdt2d-*` figure into `out` and return the stages drawn.
pub fn rdt2d_figures(out: &Path) -> Result<Vec<Stage>> {
    let mut stages = Vec::new();
    for r in RUNS {
        let e = catalog::get(r.curve)?;
        let f = e.function();
        let params = BoissonnatOudot2 {
            facet_size: r.size,
            facet_distance: Some(r.distance),
            max_vertices: r.budget.unwrap_or(1_000_000),
            seed_lines: 1,
            manifold: r.manifold,
            ..Default::default()
        };
        let mut label = match r.budget {
            Some(n) => format!("stopped by --max-vertices {n}"),
            None => format!("complete (size {}, distance {})", r.size, r.distance),
        };
        if r.manifold {
            label.push_str(", manifold");
        }
        if r.zoom.is_some() {
            label.push_str(", zoom");
        }
        let view = r
            .zoom
            .map(|[x0, x1, y0, y1]| Aabb::rect([x0, y0], [x1, y1]));
        stages.push(stage_figure(
            &out.join(format!("fig-rdt2d-{}-{}", r.curve, r.suffix)),
            r.curve,
            &f,
            &e.domain,
            &params,
            &label,
            view,
        )?);
    }
    Ok(stages)
}
