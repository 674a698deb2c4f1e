//! Tests of the isosurface-stuffing proof: the case enumeration against the meshes the
//! mesher actually produces, a hand-checkable sub-case (the undisturbed BCC
//! tetrahedron), enclosure properties of the angle functions, and certificate checking.
use certmesh::catalog;
use certmesh::lattice::bcc::NEIGHBORS;
use certmesh::stuffing::stencils::TABLE;
use certmesh::stuffing::{self, generate, prepare, Field};
use proofs::stuffing::cases::{canonical, output_cases, Alphas, Case, Kind, Seg, Sym, DEN};
use proofs::stuffing::eval::{problems, What};
use proptest::prelude::*;
use std::collections::HashSet;

/// Map a mesh vertex (doubled lattice coordinates `c`) to its vertex descriptor: a
/// lattice point (`Fixed`), a cut point on the central part of an edge, or a warped
/// point near a lattice point; with its parameter.
fn descriptor(c: [f64; 3], a: &Alphas) -> Option<(Seg, f64)> {
    let r = c.map(|x| x.round());
    let on_lattice = (0..3).all(|k| (c[k] - r[k]).abs() < 1e-7)
        && (r[0] as i64 - r[1] as i64) % 2 == 0
        && (r[0] as i64 - r[2] as i64) % 2 == 0;
    if on_lattice {
        return Some((Seg::fixed(r.map(|x| x as i64)), 0.0));
    }
    // Candidate lattice points around c, and the edge from one of them through c.
    let f = c.map(|x| x.floor() as i64);
    for dx in -1..=2 {
        for dy in -1..=2 {
            for dz in -1..=2 {
                let q = [f[0] + dx, f[1] + dy, f[2] + dz];
                if (q[0] - q[1]) % 2 != 0 || (q[0] - q[2]) % 2 != 0 {
                    continue;
                }
                for d in NEIGHBORS {
                    let n2 = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) as f64;
                    let w = [0, 1, 2].map(|k| c[k] - q[k] as f64);
                    let t = (w[0] * d[0] as f64 + w[1] * d[1] as f64 + w[2] * d[2] as f64) / n2;
                    let res = (0..3)
                        .map(|k| (w[k] - t * d[k] as f64).abs())
                        .fold(0.0, f64::max);
                    if res > 1e-7 || !(t > 0.0 && t <= 0.5) {
                        continue;
                    }
                    let s = Seg::warp(q, d);
                    let al = a.alpha(&s) as f64 / DEN as f64;
                    return Some(if t < al - 1e-9 {
                        (s, t)
                    } else {
                        let e = [q[0] + d[0], q[1] + d[1], q[2] + d[2]];
                        let cut = Seg::cut(q, e);
                        // Parameter measured from the canonical start of the cut.
                        let tc = if cut.p == q { t } else { 1.0 - t };
                        (cut, tc)
                    });
                }
            }
        }
    }
    None
}

fn in_range(s: &Seg, t: f64, a: &Alphas) -> bool {
    let r = a.range(s);
    let (lo, hi) = (r[0] as f64 / DEN as f64, r[1] as f64 / DEN as f64);
    t >= lo - 1e-9 && t <= hi + 1e-9
}

/// Every output tetrahedron of real meshes lies in some enumerated case, with every
/// vertex inside its segment's range (§4.1's configuration space covers the mesher).
#[test]
fn enumeration_covers_the_meshers_output_tetrahedra() {
    let syms = Sym::all();
    let runs = [
        ("sphere", "min-dihedral-unsafe", 11, [0.31, 0.17, 0.73]),
        ("torus", "min-dihedral-safe-ordered", 13, [0.62, 0.91, 0.05]),
        ("genus2", "max-exposed-safe", 12, [0.11, 0.43, 0.29]),
        ("blob", "min-exposed-safe-ordered", 11, [0.5, 0.25, 0.125]),
        ("tanglecube", "min-dihedral-double", 10, [0.21, 0.67, 0.38]),
    ];
    let mut hit_total = HashSet::new();
    for (surf, rowname, res, off) in runs {
        let e = catalog::get(surf).unwrap();
        let f = e.function();
        let row = stuffing::row(rowname).unwrap();
        let a = Alphas::of(row);
        let (cases, _) = output_cases(&a);
        let set: HashSet<Vec<Seg>> = cases.iter().map(|c| c.v.to_vec()).collect();
        let p = stuffing::StuffingParams::new()
            .with_row(rowname)
            .unwrap()
            .with_resolution(res)
            .with_offset(off);
        let fl: Field = prepare(&f, &e.domain, &p).unwrap();
        let (origin, h) = (fl.lat.origin, fl.lat.h);
        let out = generate(fl, &f, &p).unwrap();
        let m = &out.mesh;
        assert!(m.tets.len() > 500, "{surf}: {} tets", m.tets.len());
        let mut hit = HashSet::new();
        for t in &m.tets {
            let d: Vec<(Seg, f64)> = t
                .iter()
                .map(|&i| {
                    let v = m.vertices[i as usize];
                    let c = [0, 1, 2].map(|k| (v[k] - origin[k]) / (0.5 * h));
                    descriptor(c, &a)
                        .unwrap_or_else(|| panic!("{surf}: vertex {v:?} off the lattice edges"))
                })
                .collect();
            for (s, t) in &d {
                assert!(in_range(s, *t, &a), "{surf} {rowname}: {s:?} at {t}");
            }
            // A lattice point may also be a zero-labelled point exactly on the surface
            // (a warp of length 0): try those readings when the plain one is not a case.
            let segs: Vec<Seg> = d.iter().map(|x| x.0).collect();
            let mut found = None;
            let fixed: Vec<usize> = (0..4).filter(|&k| segs[k].kind == Kind::Fixed).collect();
            for mask in 0..(1usize << fixed.len()) {
                let mut variants = vec![segs.clone()];
                for (b, &k) in fixed.iter().enumerate() {
                    if mask >> b & 1 == 1 {
                        variants = variants
                            .into_iter()
                            .flat_map(|v| {
                                NEIGHBORS.iter().map(move |&n| {
                                    let mut w = v.clone();
                                    w[k] = Seg::warp(w[k].p, n);
                                    w
                                })
                            })
                            .collect();
                    }
                }
                if let Some(v) = variants
                    .into_iter()
                    .find(|v| set.contains(&canonical(v, &syms)))
                {
                    found = Some(canonical(&v, &syms));
                    break;
                }
            }
            let key = found.unwrap_or_else(|| panic!("{surf} {rowname}: tet {segs:?} in no case"));
            hit.insert(key);
        }
        assert!(hit.len() > 20, "{surf}: only {} distinct cases", hit.len());
        hit_total.extend(hit);
    }
    assert!(hit_total.len() > 100);
}

/// The undisturbed BCC tetrahedron (pattern ++++): dihedral angles 60° at its four red
/// edges and 90° at its two black edges; faces isosceles with angles arccos(1/3) at the
/// apex and arccos(1/√3) at the base (sides h, √3h/2, √3h/2).
#[test]
fn undisturbed_bcc_tetrahedron() {
    let row = stuffing::row("min-dihedral-unsafe").unwrap();
    let a = Alphas::of(row);
    let (cases, _) = output_cases(&a);
    let syms = Sym::all();
    let key = canonical(&TABLE.reference.map(Seg::fixed), &syms);
    let (ci, case) = cases
        .iter()
        .enumerate()
        .find(|(_, c)| c.v.to_vec() == key)
        .expect("the whole BCC tetrahedron is a case");
    let ps = problems(ci, case, &a, true, true);
    let mut dihedral = Vec::new();
    let mut plane = Vec::new();
    for p in &ps {
        assert_eq!(p.dim, 0);
        let v = p.point(&[]).unwrap();
        match p.what {
            What::Dihedral => dihedral.extend(v),
            What::Face { exposed } => {
                assert!(!exposed);
                plane.extend(v)
            }
        }
    }
    let count = |xs: &[inari::Interval], c: f64| {
        xs.iter()
            .filter(|x| x.contains(c) && x.wid() < 1e-12)
            .count()
    };
    assert_eq!(dihedral.len(), 6);
    assert_eq!(count(&dihedral, 0.5), 4);
    assert_eq!(count(&dihedral, 0.0), 2);
    assert_eq!(plane.len(), 12);
    assert_eq!(count(&plane, 1.0 / 3.0), 4);
    assert_eq!(count(&plane, 1.0 / 3f64.sqrt()), 8);
}

/// The reduction's precondition on a hand-checkable case: a BCC tetrahedron with one
/// vertex warped can never be flat for the safe rows.
#[test]
fn warped_vertex_keeps_volume_positive_for_safe_rows() {
    let row = stuffing::row("min-dihedral-safe").unwrap();
    let a = Alphas::of(row);
    let r = TABLE.reference;
    // Warp vertex 0 toward vertex 1 (along the black edge) by up to α_long.
    let d = [r[1][0] - r[0][0], r[1][1] - r[0][1], r[1][2] - r[0][2]];
    let mut v = r.map(Seg::fixed);
    v[0] = Seg::warp(r[0], d);
    let c = Case { v, multiplicity: 1 };
    let (range, _) = proofs::stuffing::cases::volume_range(&c, &a);
    let whole =
        proofs::stuffing::cases::orient_exact(&r.map(|p| p.map(|x| x as i128 * DEN as i128)));
    // e0 moves along the edge toward e1: its height over the face (e1, o0, o1) shrinks
    // linearly, so the volume is (1 − t)·V for t ∈ [0, α_long].
    let al = a.long as i128;
    let (x, y) = (range[0].abs(), range[1].abs());
    assert!(range[0].signum() == range[1].signum());
    assert_eq!(x.max(y), whole.abs());
    assert_eq!(x.min(y), whole.abs() * (DEN as i128 - al) / DEN as i128);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Enclosures contain the point values at random points of random boxes.
    #[test]
    fn enclosures_contain_point_values(ci in 0usize..1900, pi in 0usize..64, s in prop::collection::vec(0.0f64..1.0, 12)) {
        let row = stuffing::row("max-dihedral-safe").unwrap();
        let a = Alphas::of(row);
        let (cases, _) = output_cases(&a);
        let ci = ci % cases.len();
        let ps = problems(ci, &cases[ci], &a, true, true);
        let p = &ps[pi % ps.len()];
        let lo: Vec<f64> = (0..p.dim).map(|k| s[k] * 0.9).collect();
        let hi: Vec<f64> = (0..p.dim).map(|k| lo[k] + s[4 + k] * (1.0 - lo[k])).collect();
        let x: Vec<f64> = (0..p.dim).map(|k| lo[k] + s[8 + k] * (hi[k] - lo[k])).collect();
        let e = p.enclose(&lo, &hi);
        if let Some(v) = p.point(&x) {
            for k in 0..v.len() {
                prop_assert!(e[k].inf() <= v[k].inf() && v[k].sup() <= e[k].sup(),
                    "case {ci} {:?} output {k}: {:?} not in {:?}", p.what, v[k], e[k]);
            }
        }
    }
}

/// A shard certificate is accepted by `check` and rejected after tampering.
#[test]
fn stuffing_certificate_check_and_tamper() {
    let row = stuffing::row("max-exposed-safe").unwrap();
    let mut cfg = proofs::stuffing::Config::new(row);
    cfg.shard = Some((0, 400));
    cfg.tol_deg = 1e-2;
    let cert = proofs::stuffing::run(&cfg).unwrap();
    assert!(!cert.problems.is_empty());
    let r = proofs::stuffing::check(&cert).unwrap();
    assert!(!r.complete);
    // `merge` refuses an incomplete set of shards (one of 400; the same shard twice).
    assert!(proofs::stuffing::merge(vec![cert.clone()]).is_err());
    assert!(proofs::stuffing::merge(vec![cert.clone(), cert.clone()]).is_err());
    // Tamper with one leaf bound: the recomputed enclosure no longer fits.
    let mut bad = cert.clone();
    let pc = bad
        .problems
        .iter_mut()
        .find(|p| p.leaves.iter().any(|l| l.len() > 3))
        .unwrap();
    let l = pc.leaves.iter_mut().find(|l| l.len() > 3).unwrap();
    let n = l.len();
    l[n - 1] = l[n - 2]; // shrink the last output's interval to a point
    l[n - 2] += 1e-3;
    assert!(proofs::stuffing::check(&bad).is_err());
    // Drop a leaf: the partition is incomplete.
    let mut bad = cert.clone();
    let pc = bad
        .problems
        .iter_mut()
        .find(|p| p.leaves.len() > 1)
        .unwrap();
    pc.leaves.pop();
    assert!(proofs::stuffing::check(&bad).is_err());
    // Drop a problem: coverage fails.
    let mut bad = cert.clone();
    bad.problems.pop();
    assert!(proofs::stuffing::check(&bad).is_err());
    // Claim a stronger witness than the configuration gives.
    let mut bad = cert;
    if let Some(w) = bad.witnesses.iter_mut().flatten().next() {
        w.cos = [w.cos[0] + 1e-3, w.cos[1] + 1e-3];
        assert!(proofs::stuffing::check(&bad).is_err());
    }
}

/// The safe property: the worst warped BCC tetrahedron has all four vertices warped by
/// α_long along black edges, volume (1 − 4α_long)·V: safe exactly when α_long < 1/4
/// (why the safe rows use 0.24999). With α_short = 0.5 the closed configuration space
/// reaches volume 0 only where the §6 convention excludes it.
#[test]
fn safe_property_matches_the_closed_form() {
    use proofs::exact::Verdict;
    for name in [
        "min-dihedral-unsafe",
        "max-dihedral-safe",
        "max-exposed-safe-ordered",
    ] {
        let row = stuffing::row(name).unwrap();
        let s = proofs::stuffing::safe_property(row);
        let expect = 1.0 - 4.0 * row.alpha_long;
        assert!((s.min_ratio - expect).abs() < 1e-12, "{name}: {s:?}");
        let v = if row.safe {
            Verdict::Proven
        } else {
            Verdict::Refuted
        };
        assert_eq!(s.verdict, v, "{name}");
    }
    let s = proofs::stuffing::safe_property(stuffing::row("min-exposed-safe-ordered").unwrap());
    assert_eq!(s.min_ratio, 0.0);
    assert_eq!(s.verdict, Verdict::Proven);
    assert!(!s.note.is_empty());
}

/// `merge` refuses incomplete or overlapping shard sets; two halves of a row merge into
/// a certificate that checks and states verdicts, which the halves do not.
#[test]
fn stuffing_merge_requires_complete_disjoint_shards() {
    let row = stuffing::row("min-exposed-unsafe").unwrap();
    let halves: Vec<_> = (0..2)
        .map(|i| {
            let mut cfg = proofs::stuffing::Config::new(row);
            cfg.tol_deg = 5.0;
            cfg.shard = Some((i, 2));
            let c = proofs::stuffing::run(&cfg).unwrap();
            assert!(c.partial && c.bounds.iter().all(|b| b.verdict.is_none()));
            c
        })
        .collect();
    assert!(proofs::stuffing::merge(vec![halves[0].clone()]).is_err());
    assert!(proofs::stuffing::merge(vec![
        halves[0].clone(),
        halves[0].clone(),
        halves[1].clone()
    ])
    .is_err());
    let m = proofs::stuffing::merge(halves).unwrap();
    let r = proofs::stuffing::check(&m).unwrap();
    assert!(r.complete && m.bounds.iter().any(|b| b.verdict.is_some()));
}
