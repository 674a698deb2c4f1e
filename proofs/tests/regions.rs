//! The derived regions agree with actually cutting the tetrahedron (and the octahedra)
//! by random planes, using the mesher's own vertex positions (`Goldberg::tetrahedron`).
use proofs::geometry::{DiagonalRule, Goldberg, NORMAL_QUADS, NORMAL_TRIANGLES};
use proofs::gradnormal::cases::{Derived, Ratio};
use proptest::prelude::*;

fn positions(r: f64) -> ([[f64; 3]; 4], Derived) {
    (
        Goldberg::with_ratio(1.0, r).tetrahedron(),
        Derived::new(Ratio::Value(r)),
    )
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// μ = D m for the Ξ-coordinate constraints.
fn mu(m: [f64; 3], r: f64) -> [f64; 3] {
    [m[0], m[1] * 3f64.sqrt() / 2.0, m[2] * r]
}

/// The octahedron points (f64) around the right-angled edge at vertex v.
fn ring(d: &Derived, t: &[[f64; 3]; 4], g: &Goldberg, v: usize) -> Option<Vec<[f64; 3]>> {
    let o = d.octahedra.iter().find(|o| o.edge.contains(&v))?;
    let _ = t;
    Some(
        o.ring
            .iter()
            .map(|(_, l)| g.vertex(l[0], l[1], l[2]))
            .collect(),
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    #[test]
    fn random_planes_agree_with_regions(
        x in -1.0f64..1.0, y in -1.0f64..1.0, z in -1.0f64..1.0, c in -2.0f64..2.0,
        ri in 0usize..3
    ) {
        let r = [0.3535533905932738, 0.5, 0.25][ri];
        let g = Goldberg::with_ratio(1.0, r);
        let (t, d) = positions(r);
        let m = [x, y, z];
        prop_assume!(dot(m, m) > 1e-3);
        let cases = d.cases(DiagonalRule::Paper).unwrap();
        let s: Vec<f64> = t.iter().map(|p| dot(m, *p) - c).collect();
        prop_assume!(s.iter().all(|v| v.abs() > 1e-9));
        let pos: Vec<usize> = (0..4).filter(|&k| s[k] > 0.0).collect();
        let inside = |name_prefix: &str, mm: [f64; 3]| -> bool {
            cases.iter().filter(|cs| cs.name.starts_with(name_prefix)).all(|cs| {
                cs.pieces.iter().any(|p| !p.rays.is_empty() && p.contains(mu(mm, r)))
            })
        };
        // Elementary triangle: one vertex alone (orient m towards it).
        for (v, flip) in [(pos.first().copied(), 1.0), (None, -1.0)] {
            let _ = (v, flip);
        }
        let alone = if pos.len() == 1 { Some((pos[0], m, c)) }
            else if pos.len() == 3 { (0..4).find(|k| !pos.contains(k)).map(|k| (k, m.map(|a| -a), -c)) }
            else { None };
        if let Some((v, mm, cc)) = alone {
            let (_, mids) = NORMAL_TRIANGLES[v];
            let name = format!("{} {} {} (cut", proofs::geometry::MIDPOINT_NAMES[mids[0]],
                proofs::geometry::MIDPOINT_NAMES[mids[1]], proofs::geometry::MIDPOINT_NAMES[mids[2]]);
            // Removed iff the whole octahedron ring lies on the far side.
            let removed = match ring(&d, &t, &g, v) {
                Some(pts) => pts.iter().all(|p| dot(mm, *p) - cc < 0.0),
                None => false,
            };
            let in_region = inside(&name, mm);
            if !removed {
                prop_assert!(in_region, "surviving triangle {name} with normal {mm:?} outside its region");
            } else {
                // The valence-four square's region must contain the normal.
                let mut ok = false;
                for cs in cases.iter().filter(|cs| cs.group == "valence4") {
                    ok |= cs.region.starts_with(&format!("Y_{}", proofs::geometry::LABELS[v]))
                        && cs.pieces.iter().any(|p| p.contains(mu(mm, r)));
                }
                prop_assert!(ok || d.octahedra.is_empty(), "removed vertex but normal not in Y");
            }
        }
        if pos.len() == 2 {
            let q = NORMAL_QUADS.iter().find(|q| {
                (q.side.contains(&pos[0]) && q.side.contains(&pos[1]))
                    || (!q.side.contains(&pos[0]) && !q.side.contains(&pos[1]))
            }).unwrap();
            let mm = if q.side.contains(&pos[0]) { m } else { m.map(|a| -a) };
            let name = q.name;
            let ok = cases.iter().filter(|cs| cs.name.ends_with(&format!("of {name}"))).all(|cs| {
                cs.pieces.iter().any(|p| p.contains(mu(mm, r)))
            });
            prop_assert!(ok, "quad {name}: normal {mm:?} outside its region");
        }
    }

    #[test]
    fn normals_inside_a_region_produce_the_triangle(
        case in 0usize..4, piece in 0usize..2, a in 0.0f64..1.0, b in 0.0f64..1.0, cw in 0.0f64..1.0
    ) {
        // A random normal in the cone of a piece (convex combination of its rays): some
        // plane with that normal cuts off the vertex alone and keeps its triangle.
        let r = 0.3535533905932738;
        let g = Goldberg::with_ratio(1.0, r);
        let (t, d) = positions(r);
        let cases = d.cases(DiagonalRule::Paper).unwrap();
        let cs = &cases[case];
        let p = &cs.pieces[piece % cs.pieces.len()];
        prop_assume!(p.rays.len() >= 3);
        let w = [a, b, cw, 0.1];
        let mut muv = [0.0; 3];
        for (i, ray) in p.rays.iter().enumerate() {
            for k in 0..3 { muv[k] += w[i % 4] * ray[k] as f64 + 1e-3 * ray[k] as f64; }
        }
        let m = [muv[0], muv[1] / (3f64.sqrt() / 2.0), muv[2] / r];
        let (v, _) = NORMAL_TRIANGLES[case];
        let others: Vec<f64> = (0..4).filter(|&k| k != v).map(|k| dot(m, t[k])).collect();
        let top = others.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        prop_assert!(dot(m, t[v]) > top, "vertex not above the others");
        let ring_top = ring(&d, &t, &g, v).unwrap().iter().map(|q| dot(m, *q)).fold(f64::NEG_INFINITY, f64::max);
        // Offset just above the other three: the triangle exists, and survives iff some
        // ring point is above the plane.
        let cc = top + 1e-9 * (1.0 + top.abs());
        prop_assert!(ring_top > cc, "the triangle would always be removed");
    }
}
