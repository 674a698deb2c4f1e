//! A case whose extremes are known in closed form, run through the same branch and bound.
//!
//! Right triangle with legs along x and y (P0 = 0, P1 = 4x̂, P2 = 4(√3/2)ŷ in Ξ coordinates
//! (0,0,0), (4,0,0), (0,4,0) at a/e = 1), normals μ = (α, β, 2)·k with |α|, |β| <= 1, i.e.
//! m = (α, β/H, 2) with H = √3/2. The projected right angle has
//! cos θ = −m_x m_y / sqrt((|m|² − m_x²)(|m|² − m_y²)), whose extremes over the square are
//! at the corners α = ±1, β = ∓1 ... : with γ = 1/(2H) = 1/√3, s = 1/2:
//! max cos = sγ / sqrt((1 + γ²)(1 + s²)) = 1/(2√5).
use proofs::bnb::{check_case, solve, Objective, Search};
use proofs::gradnormal::cases::{Case, Domain, NamedPt, Ratio};
use proofs::gradnormal::eval::TriObj;

fn case() -> (Case, Domain) {
    let p = |n: &str, xi: [i64; 3]| NamedPt { name: n.into(), xi };
    let dom = Domain {
        rays: [[-1, -1, 2], [1, -1, 2], [1, 1, 2], [-1, 1, 2]],
        extra: None,
    };
    let c = Case {
        name: "right triangle".into(),
        group: "test".into(),
        vertices: [p("O", [0, 0, 0]), p("X", [4, 0, 0]), p("Y", [0, 4, 0])],
        region: "square".into(),
        pieces: Vec::new(),
        domains: vec![dom.clone()],
    };
    (c, dom)
}

#[test]
fn right_angle_extremes_match_closed_form() {
    let (c, d) = case();
    let obj = TriObj::new(Ratio::Value(1.0), &c, &d);
    let dyns: Vec<&dyn Objective> = vec![&obj];
    let tol = 1e-9;
    let cert = solve(
        &dyns,
        Search {
            tol,
            max_depth: 40,
            seed: 5,
        },
    )
    .unwrap();
    let exact = 1.0 / (2.0 * 5f64.sqrt());
    let mx = cert.max[0].bound;
    let mn = cert.min[0].bound;
    assert!(
        mx[0] <= exact + 1e-15 && exact - 1e-15 <= mx[1],
        "{mx:?} vs {exact}"
    );
    assert!(
        mn[0] <= -exact + 1e-15 && -exact - 1e-15 <= mn[1],
        "{mn:?} vs {}",
        -exact
    );
    assert!(mx[1] - mx[0] <= tol && mn[1] - mn[0] <= tol);
    // The witnesses are at the corners (u, v) = (1, 0)/(0, 1) for the max and (0,0)/(1,1)
    // for the min of cos.
    let w = &cert.max[0].witness;
    assert!((w.u - w.v).abs() > 0.999, "max witness at {w:?}");
    check_case(
        &dyns,
        &cert,
        Search {
            tol,
            max_depth: 40,
            seed: 5,
        },
    )
    .unwrap();
}
