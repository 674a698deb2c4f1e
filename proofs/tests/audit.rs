//! `proofs stuffing --alpha-long A --alpha-short B`: custom parameter pairs. Their rows
//! are named by their parameters (exact decimals), certified by the same branch and
//! bound, re-derived by `check` from the name alone, and agree with the Table 1 row
//! whose parameters they are.
use certmesh::stuffing;
use proofs::stuffing::custom::{self, Params};

#[test]
fn alphas_are_read_exactly_and_out_of_range_values_refused() {
    assert_eq!(Params::alpha("0.21509", "a").unwrap(), 21509);
    assert_eq!(Params::alpha("0.359", "a").unwrap(), 35900);
    assert_eq!(Params::alpha(".5", "a").unwrap(), 50000);
    assert_eq!(Params::alpha("0.25", "a").unwrap(), 25000);
    for bad in ["0.123456", "abc", "", ".", "-0.2", "0.2e1", "1/4"] {
        assert!(Params::alpha(bad, "a").is_err(), "{bad:?} accepted");
    }
    // α_long = 0.5 lets both ends of a black edge warp to its midpoint; α = 0 warps
    // nothing; α_short may be 0.5 (§6's midpoint convention).
    assert!(Params::new(50000, 30000, false, false).is_err());
    assert!(Params::new(0, 30000, false, false).is_err());
    assert!(Params::new(20000, 0, false, false).is_err());
    assert!(Params::new(20000, 50001, false, false).is_err());
    assert!(Params::new(20000, 50000, false, false).is_ok());
}

#[test]
fn custom_names_round_trip_and_find_their_table1_row() {
    for &(l, s, o, d) in &[
        (21509, 35900, false, true),
        (25000, 42978, true, false),
        (1, 50000, true, true),
    ] {
        let p = Params::new(l, s, o, d).unwrap();
        let name = p.name();
        assert_eq!(Params::parse(&name), Some(p), "{name}");
        let row = custom::resolve(&name).unwrap();
        assert_eq!(row.name, name);
        assert!(custom::is_custom(row));
        assert_eq!((row.alpha_long * 1e5).round() as i64, l);
    }
    // Not a valid encoding: refused, not guessed.
    for bad in [
        "custom:0.2,0.3,unordered,one-sided",
        "custom:0.20000,0.30000,sorted,one-sided",
        "custom:0.60000,0.30000,unordered,one-sided",
    ] {
        assert!(custom::resolve(bad).is_err(), "{bad}");
    }
    let ue = Params::new(21509, 35900, false, true).unwrap();
    assert_eq!(ue.table1_row().map(|r| r.name), Some("max-dihedral-double"));
    let ms = Params::new(25000, 42978, true, false).unwrap();
    assert_eq!(ms.table1_row(), None);
}

/// A custom pair equal to a Table 1 row's parameters certifies enclosures of the same
/// extremes (same cases, same shard): each pair of enclosures intersects. Its
/// certificate passes `check`, which re-derives the row from the name; a name whose
/// parameters were changed fails it.
#[test]
fn a_custom_pair_agrees_with_its_table1_row_and_checks() {
    let row = stuffing::row("max-exposed-safe").unwrap();
    let p = Params::new(23926, 27376, false, false).unwrap();
    assert_eq!(p.table1_row().map(|r| r.name), Some(row.name));
    let run = |r: &'static certmesh::stuffing::params::Row| {
        let mut cfg = proofs::stuffing::Config::new(r);
        cfg.shard = Some((1, 300));
        cfg.tol_deg = 1e-2;
        proofs::stuffing::run(&cfg).unwrap()
    };
    let a = run(row);
    let b = run(custom::row(&p));
    assert_eq!(a.counts, b.counts);
    for (x, y) in a.bounds.iter().zip(&b.bounds) {
        let (Some(dx), Some(dy)) = (x.deg, y.deg) else {
            continue;
        };
        assert!(
            dx[0] <= dy[1] && dy[0] <= dx[1],
            "{}: row {:?} vs custom {:?} do not intersect",
            x.bound,
            dx,
            dy
        );
    }
    let r = proofs::stuffing::check(&b).unwrap();
    assert!(!r.complete);
    let audit = custom::audit(&b).unwrap();
    assert_eq!(audit.table1_row, Some(row.name));
    assert!(custom::audit(&a).is_none());
    let mut bad = b.clone();
    bad.row = Params::new(23927, 27376, false, false).unwrap().name();
    assert!(proofs::stuffing::check(&bad).is_err());
}
