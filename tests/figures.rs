//! The figure style, checked on the files it writes: printed width, fonts ≥ 7 pt at that
//! width, labelled axes, a legend whenever there is more than one series; PNG at
//! 300 dpi; PDF. And the checker itself must reject figures that break the rules.
use certmesh::figure::check::check_svg;
use certmesh::figure::output::{figure_as, Format, Meta};
use certmesh::figure::style::{self, Width};
use certmesh::reproduce::plot::{self, Bar, Marker, PointSet, Series};
use std::path::Path;

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("certmesh-figures-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn passes(svg: &Path) -> certmesh::figure::check::Report {
    let r = check_svg(&std::fs::read_to_string(svg).unwrap()).unwrap();
    assert!(r.problems.is_empty(), "{}: {:?}", svg.display(), r.problems);
    assert!(r.min_font_pt >= 7.0, "{}", r.min_font_pt);
    r
}

#[test]
fn charts_meet_the_style_in_every_format() {
    certmesh::figure::output::set_default_formats(&Format::ALL);
    let d = tmp("charts");
    // A histogram with rare bins magnified and two bound markers.
    let mut bars: Vec<Bar> = (0..90)
        .map(|i| Bar {
            lo: 2.0 * i as f64,
            width: 2.0,
            height: (100000.0 * (-((i as f64 - 40.0) / 8.0).powi(2)).exp()).round(),
        })
        .collect();
    bars.retain(|b| b.height > 0.0);
    plot::histogram(
        &d.join("hist"),
        "dihedral angles",
        "dihedral angle (degrees)",
        "angles per 2° bin",
        &bars,
        &[
            Marker {
                x: 10.7,
                label: "proven min 10.7°".into(),
            },
            Marker {
                x: 164.8,
                label: "proven max 164.8°".into(),
            },
        ],
        20.0,
    )
    .unwrap();
    let r = passes(&d.join("hist.svg"));
    assert!((r.width_in - 3.3).abs() < 1e-9);
    let legend = r.meta.unwrap().legend;
    assert!(legend.iter().any(|l| l.contains("×20")), "{legend:?}");
    // Ticks are whole numbers with grouped thousands, never "20.0" or "100000.0".
    assert!(
        r.texts.iter().any(|t| t == "50" || t == "100"),
        "{:?}",
        r.texts
    );
    assert!(!r.texts.iter().any(|t| t.ends_with(".0")), "{:?}", r.texts);
    plot::lines(
        &d.join("lines"),
        "",
        "depth",
        "boxes",
        &[
            Series {
                name: "a".into(),
                points: vec![(0.0, 1.0), (1.0, 4.0)],
            },
            Series {
                name: "b".into(),
                points: vec![(0.0, 2.0), (1.0, 3.0)],
            },
        ],
    )
    .unwrap();
    passes(&d.join("lines.svg"));
    plot::scatter(
        &d.join("scatter"),
        "front",
        "min angle (degrees)",
        "max angle (degrees)",
        &[PointSet {
            name: "pairs".into(),
            points: vec![(10.0, 160.0), (10.1, 160.1), (10.2, 160.0)],
            labels: vec![
                "(0.24, 0.3)".into(),
                "(0.25, 0.3)".into(),
                "(0.26, 0.3)".into(),
            ],
            joined: true,
            filled: true,
        }],
    )
    .unwrap();
    assert!((passes(&d.join("scatter.svg")).width_in - 7.0).abs() < 1e-9);
    // PNG at 300 dpi of the printed width; PDF present.
    let png = std::fs::read(d.join("hist.png")).unwrap();
    let w = u32::from_be_bytes(png[16..20].try_into().unwrap());
    assert_eq!(w, 990, "3.3 in at 300 dpi");
    assert!(png.windows(4).any(|c| c == b"pHYs"));
    assert!(std::fs::read(d.join("hist.pdf"))
        .unwrap()
        .starts_with(b"%PDF"));
    if std::env::var_os("CERTMESH_KEEP_FIGURES").is_none() {
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn the_checker_rejects_what_the_style_forbids() {
    let d = tmp("bad");
    // Tiny text, a declared axis label that is not drawn, two series without a legend.
    let meta = Meta::chart("x (m)", "y (m)", vec![], 2);
    figure_as(
        &d.join("bad"),
        Width::Column,
        0.6,
        &meta,
        &[Format::Svg],
        |area| {
            let mut c = style::chart(area, "", 0.0..1.0, 0.0..1.0)?;
            c.configure_mesh()
                .label_style(("sans-serif", 10.0))
                .x_desc("x (m)")
                .draw()
                .map_err(|e| certmesh::Error::Param(e.to_string()))?;
            Ok(())
        },
    )
    .unwrap();
    let r = check_svg(&std::fs::read_to_string(d.join("bad.svg")).unwrap()).unwrap();
    let all = r.problems.join("\n");
    assert!(all.contains("pt at the printed width"), "{all}");
    assert!(all.contains("`y (m)` is not drawn"), "{all}");
    assert!(all.contains("2 series and no legend"), "{all}");
    assert!(!all.contains("`x (m)` is not drawn"), "{all}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn subdivision_pictures_have_axes_and_a_legend_of_the_certifying_criteria() {
    use certmesh::mesher::{Mesh, NoProgress};
    use certmesh::subdivision::leaf_boxes;
    use certmesh::subdivision::plantinga_vegter::{run_pv, PvParams};
    let e = certmesh::catalog::get("cassini-2").unwrap();
    let f = e.function();
    let (tree, out) = run_pv(&f, &e.domain, &PvParams::new(2), 2, &NoProgress).unwrap();
    let Mesh::Curve(c) = &out.mesh else {
        panic!("a curve")
    };
    let d = tmp("subdivision");
    let base = d.join("pv");
    certmesh::reproduce::plot_subdivision::draw_subdivision_svg(
        &base,
        &f,
        &e.domain,
        &leaf_boxes(&tree),
        c,
    )
    .unwrap();
    let r = passes(&d.join("pv.svg"));
    let legend = r.meta.unwrap().legend;
    // One entry per criterion that certified a leaf, plus the two curves.
    assert!(
        legend.iter().any(|l| l == "small normal variation"),
        "{legend:?}"
    );
    assert!(legend.iter().any(|l| l == "output"), "{legend:?}");
    let _ = std::fs::remove_dir_all(&d);
}
