//! Certificates: a genuine one is accepted, tampered ones are rejected; shards merge.
use proofs::geometry::DiagonalRule;
use proofs::gradnormal::cases::Ratio;
use proofs::gradnormal::{check, merge, run, Config};

fn coarse() -> Config {
    let mut c = Config::new(Ratio::Sommerville, DiagonalRule::Paper);
    c.tol_cos = 1e-3;
    c.max_depth = 12;
    c
}

#[test]
fn genuine_accepted_tampered_rejected() {
    let cert = run(&coarse()).unwrap();
    let r = check(&cert).unwrap();
    assert!(r.complete && r.leaves > 0 && !r.claims.is_empty());
    // Roundtrip through JSON keeps it valid.
    let text = serde_json::to_string(&cert).unwrap();
    let back: proofs::gradnormal::Certificate = serde_json::from_str(&text).unwrap();
    check(&back).unwrap();

    // 1. Tighten a leaf bound.
    let mut t = cert.clone();
    let leaf = t.cases[0].cert.leaves[0]
        .iter_mut()
        .find(|l| l.vals.is_some())
        .unwrap();
    leaf.vals.as_mut().unwrap()[0][0] += 1e-3;
    assert!(check(&t).is_err());
    // 2. Drop a leaf (the partition is incomplete).
    let mut t = cert.clone();
    t.cases[1].cert.leaves[0].pop();
    assert!(check(&t).is_err());
    // 3. Claim a better extreme than the leaves support.
    let mut t = cert.clone();
    t.cases[2].cert.max[0].bound[1] -= 1e-4;
    assert!(check(&t).is_err());
    // 4. Flip a verdict.
    let mut t = cert.clone();
    let i = t
        .claims
        .iter()
        .position(|c| c.verdict == proofs::exact::Verdict::Refuted)
        .unwrap();
    t.claims[i].verdict = proofs::exact::Verdict::Proven;
    assert!(check(&t).is_err());
    // 5. Move a witness.
    let mut t = cert.clone();
    t.cases[3].cert.min[1].witness.u = (t.cases[3].cert.min[1].witness.u + 0.37) % 1.0;
    assert!(check(&t).is_err());
    // 6. Change the geometry of a case (a vertex of the triangle).
    let mut t = cert.clone();
    t.cases[4].case.vertices[0].xi[2] += 4;
    assert!(check(&t).is_err());
    // 7. Change a region ray.
    let mut t = cert.clone();
    t.cases[5].case.domains[0].rays[0][0] += 1;
    assert!(check(&t).is_err());
    // 8. Mark a leaf as outside.
    let mut t = cert.clone();
    t.cases[6].cert.leaves[0][0].vals = None;
    assert!(check(&t).is_err());
}

#[test]
fn shards_merge_to_the_full_certificate() {
    let full = run(&coarse()).unwrap();
    let parts: Vec<_> = (0..3)
        .map(|i| {
            let mut c = coarse();
            c.shard = Some((i, 3));
            let p = run(&c).unwrap();
            assert!(p.summary.is_none() && p.claims.is_empty());
            check(&p).unwrap();
            p
        })
        .collect();
    let m = merge(parts.clone()).unwrap();
    check(&m).unwrap();
    assert_eq!(m.claims, full.claims);
    assert_eq!(m.summary, full.summary);
    // A duplicated shard is refused.
    assert!(merge(vec![parts[0].clone(), parts[0].clone()]).is_err());
}

#[test]
fn shorter_rule_certificate_checks() {
    // The shorter-diagonal rule has regions cut by a quadric and cases that exist only
    // on tie sets (no certified interior point): the certificate must still verify.
    let mut c = Config::new(Ratio::Sommerville, DiagonalRule::Shorter);
    c.tol_cos = 1e-2;
    c.max_depth = 5;
    let cert = run(&c).unwrap();
    assert_eq!(cert.n_cases, 32);
    let r = check(&cert).unwrap();
    assert!(r.complete);
    let mut t = cert.clone();
    t.cases[7].cert.leaves[0][0].vals = Some(vec![[0.0, 0.0]; 3]);
    assert!(check(&t).is_err());
}

#[test]
fn merge_requires_complete_disjoint_shards() {
    let parts: Vec<_> = (0..3)
        .map(|i| {
            let mut c = coarse();
            c.shard = Some((i, 3));
            let p = run(&c).unwrap();
            assert!(p.partial);
            p
        })
        .collect();
    // Incomplete: a shard missing.
    assert!(merge(parts[..2].to_vec()).is_err());
    // Overlapping: a shard twice, even with every shard present.
    let mut dup = parts.clone();
    dup.push(parts[1].clone());
    assert!(merge(dup).is_err());
    // A shard whose cases were edited to another shard's.
    let mut moved = parts.clone();
    let e = moved[1].cases.pop().unwrap();
    moved[0].cases.push(e);
    assert!(merge(moved).is_err());
    // A partial certificate cannot pass for a complete one.
    let mut t = parts[0].clone();
    t.shard = None;
    t.partial = false;
    assert!(check(&t).is_err());
    let m = merge(parts).unwrap();
    assert!(!m.partial && m.shard.is_none() && m.summary.is_some());
    check(&m).unwrap();
}
