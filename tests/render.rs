//! `certmesh render` as a library: the picture shows the mesh, the cut exposes
//! tetrahedra, and certificate colours are exactly the mesher's typed claims.
use certmesh::catalog;
use certmesh::figure::check::check_svg;
use certmesh::figure::output::Format;
use certmesh::mesher::registry;
use certmesh::mesher::{Certificate, Mesh, MeshOutput, NoProgress};
use certmesh::render::{self, classify, CertClass, ColorBy, Input, Plane, RenderOptions};
use certmesh::MesherOptions;

fn run(surface: &str, algo: &str, o: MesherOptions) -> MeshOutput {
    let e = catalog::get(surface).unwrap();
    registry::build(algo, 3, &o)
        .unwrap()
        .mesh(&e.function(), &e.domain, &NoProgress)
        .unwrap()
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("certmesh-render-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn pixel(png: &[u8], x: usize, y: usize) -> [u8; 3] {
    let d = png::Decoder::new(png);
    let mut r = d.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size()];
    let info = r.next_frame(&mut buf).unwrap();
    let o = (y * info.width as usize + x) * 4;
    [buf[o], buf[o + 1], buf[o + 2]]
}

#[test]
fn a_surface_mesh_is_drawn_in_the_middle_with_its_colour_bar() {
    let out = run(
        "sphere",
        "mc",
        MesherOptions {
            resolution: Some(10),
            ..Default::default()
        },
    );
    let Mesh::Surface(m) = &out.mesh else {
        panic!("mc makes surfaces")
    };
    let d = tmp("sphere");
    let r = render::render(
        &d.join("s"),
        Input::Surface(m),
        None,
        &RenderOptions {
            wire: true,
            gouraud: true,
            ..Default::default()
        },
        &[Format::Svg, Format::Png],
    )
    .unwrap();
    assert_eq!(r.faces, m.triangles.len());
    let png = std::fs::read(d.join("s.png")).unwrap();
    assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 990);
    let h = u32::from_be_bytes(png[20..24].try_into().unwrap()) as usize;
    assert_eq!(pixel(&png, 2, 2), [255, 255, 255], "corner is background");
    let c = pixel(&png, 495, (h as f64 * 0.4) as usize);
    assert_ne!(c, [255, 255, 255], "the sphere covers the middle");
    let rep = check_svg(&std::fs::read_to_string(d.join("s.svg")).unwrap()).unwrap();
    assert!(rep.problems.is_empty(), "{:?}", rep.problems);
    assert!(
        rep.texts.iter().any(|t| t.contains("smallest angle")),
        "{:?}",
        rep.texts
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_cut_exposes_the_tetrahedra_it_cuts_and_only_the_kept_side() {
    let out = run(
        "sphere",
        "stuffing",
        MesherOptions {
            resolution: Some(6),
            ..Default::default()
        },
    );
    let Mesh::Volume { tets, .. } = &out.mesh else {
        panic!("stuffing makes volumes")
    };
    let cut = Plane::parse("x=0").unwrap();
    let whole = render::scene::tet_faces(tets, None);
    assert!(whole.iter().all(|f| !f.cut));
    let faces = render::scene::tet_faces(tets, Some(cut));
    assert!(faces.iter().any(|f| f.cut), "the cut shows interior faces");
    assert!(faces.len() < whole.len() + faces.iter().filter(|f| f.cut).count());
    // Every face drawn belongs to a kept tetrahedron: its centroid side is x <= 0 up
    // to the tetrahedron's size.
    let hmax = 2.0 / 6.0 * 1.5;
    assert!(faces.iter().all(|f| f.p.iter().all(|p| p[0] <= hmax)));
    let d = tmp("cut");
    let r = render::render(
        &d.join("c"),
        Input::Volume(tets),
        None,
        &RenderOptions {
            cut: Some(cut),
            color: ColorBy::None,
            ..Default::default()
        },
        &[Format::Svg],
    )
    .unwrap();
    assert!(r.cut_faces > 0);
    let rep = check_svg(&std::fs::read_to_string(d.join("c.svg")).unwrap()).unwrap();
    assert!(rep.problems.is_empty(), "{:?}", rep.problems);
    // A cut keeping nothing is an error, not an empty picture.
    let e = render::render(
        &d.join("none"),
        Input::Volume(tets),
        None,
        &RenderOptions {
            cut: Some(Plane::parse("x<-5").unwrap()),
            ..Default::default()
        },
        &[Format::Svg],
    )
    .unwrap_err();
    assert!(e.to_string().contains("removes every face"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn certificate_colours_are_the_typed_claims_never_more() {
    // An uncertified output: no face may be coloured as proven.
    let cone = run(
        "double-cone",
        "pv",
        MesherOptions {
            max_depth: Some(5),
            ..Default::default()
        },
    );
    let Certificate::Uncertified { regions, .. } = &cone.certificate else {
        panic!("the double cone is singular: never certified")
    };
    let Mesh::Surface(m) = &cone.mesh else {
        panic!()
    };
    let mut n_unc = 0;
    for t in &m.triangles {
        let p = t.map(|i| m.vertices[i as usize]);
        let c = classify(&cone.certificate, &p);
        assert_ne!(c, CertClass::Isotopic, "a false certificate");
        // Uncertified exactly when a vertex-bounding box meets a reported region.
        let meets = regions.iter().any(|r| {
            (0..3).all(|k| {
                let lo = p.iter().map(|q| q[k]).fold(f64::INFINITY, f64::min);
                let hi = p.iter().map(|q| q[k]).fold(f64::NEG_INFINITY, f64::max);
                lo <= r.region.max[k] && hi >= r.region.min[k]
            })
        });
        assert_eq!(c == CertClass::Uncertified, meets);
        n_unc += usize::from(meets);
    }
    assert!(n_unc > 0 && n_unc < m.triangles.len());
    // A certified output: every face inside the isotopy claim's box.
    let sphere = run(
        "sphere",
        "pv",
        MesherOptions {
            max_depth: Some(5),
            ..Default::default()
        },
    );
    assert!(
        sphere.certificate.proves_topology(),
        "{:?}",
        sphere.certificate
    );
    let Mesh::Surface(s) = &sphere.mesh else {
        panic!()
    };
    assert!(s.triangles.iter().all(|t| classify(
        &sphere.certificate,
        &t.map(|i| s.vertices[i as usize])
    ) == CertClass::Isotopic));
    // Certificate colouring without a certificate is refused (before anything is
    // written: the folder stays empty, and is removed).
    let nocert = tmp("nocert");
    let e = render::render(
        &nocert.join("x"),
        Input::Surface(s),
        None,
        &RenderOptions {
            color: ColorBy::Certificate,
            ..Default::default()
        },
        &[Format::Svg],
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("needs the mesher's certificate"),
        "{e}"
    );
    std::fs::remove_dir(&nocert).expect("nothing was written");
}

/// A title longer than a figure can hold is refused before any drawing (a 100,000-character
/// one took 20 s), naming the limit; one at the limit is drawn.
#[test]
fn an_overlong_title_is_refused() {
    let out = run(
        "sphere",
        "mc",
        MesherOptions {
            resolution: Some(6),
            ..Default::default()
        },
    );
    let Mesh::Surface(m) = &out.mesh else {
        panic!("mc makes surfaces")
    };
    let d = tmp("title");
    let with = |n: usize| RenderOptions {
        title: "é".repeat(n),
        ..Default::default()
    };
    let e = render::render(
        &d.join("t"),
        Input::Surface(m),
        None,
        &with(100_000),
        &[Format::Svg],
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("100000 characters") && e.contains("200"), "{e}");
    assert!(!d.join("t.svg").exists());
    render::render(
        &d.join("t"),
        Input::Surface(m),
        None,
        &with(render::MAX_TITLE_CHARS),
        &[Format::Svg],
    )
    .unwrap();
    assert!(d.join("t.svg").exists());
    let _ = std::fs::remove_dir_all(&d);
}
