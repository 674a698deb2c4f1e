//! The cases of the GradNormal angle proof, derived from the tiling data in
//! [`crate::geometry`] (Hass & Trnkova 2020, Sec. 4.3 and Appendix A).
//!
//! Coordinates. A lattice vertex (i, j, m) of the Goldberg tiling sits at
//! (e(i + j/2), e(√3/2)j, a·m). We store every point as the integer vector
//! Ξ = (4i + 2j, 4j, 4m) (so edge midpoints stay integral) and write positions as
//! D·Ξ/4 with D = diag(e, e√3/2, a). For a plane normal m put μ = D·m: then
//! m·(p − q) = μ·(Ξ_p − Ξ_q)/4, so every separation condition "p on the positive side
//! of q" is the *rational* half-space μ·(Ξ_p − Ξ_q) ≥ 0. Regions of normals are
//! therefore rational polyhedral cones in μ-space, whose vertex rays we enumerate
//! exactly (integer cross products, exact sign tests), and the angle functions are
//! evaluated at m = D⁻¹μ with D enclosed by intervals.
use crate::exact::rat;
use crate::geometry::{
    DiagonalRule, TetType, EDGE_DIRS, LABELS, MIDPOINT_EDGES, MIDPOINT_NAMES, NORMAL_QUADS,
    NORMAL_TRIANGLES,
};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, Zero};
use serde::{Deserialize, Serialize};

/// `x` as Rust prints it, or in scientific notation when that would be long (Rust
/// prints 1e308 with 309 digits and 1e-300 with 300 zeros).
fn short(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() > 24 {
        format!("{x:e}")
    } else {
        plain
    }
}

/// The Goldberg parameter a/e.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ratio {
    /// a/e = √2/4 exactly (the Sommerville tetrahedron, Appendix A).
    Sommerville,
    /// a/e equal to this f64 exactly.
    Value(f64),
}

impl Ratio {
    pub fn parse(s: &str) -> Result<Ratio, String> {
        match s {
            "sommerville" | "sqrt2/4" => Ok(Ratio::Sommerville),
            _ => {
                let x: f64 = s
                    .parse()
                    .map_err(|_| format!("bad a/e `{s}` (a number or `sommerville`)"))?;
                if x > 0.0 && x.is_finite() && x < 100.0 {
                    Ok(Ratio::Value(x))
                } else {
                    Err(format!("a/e must be in (0, 100), got {}", short(x)))
                }
            }
        }
    }
    pub fn label(&self) -> String {
        match self {
            Ratio::Sommerville => "sommerville".into(),
            Ratio::Value(x) => short(*x),
        }
    }
    pub fn f64(&self) -> f64 {
        match self {
            Ratio::Sommerville => crate::geometry::SOMMERVILLE_RATIO,
            Ratio::Value(x) => *x,
        }
    }
    /// Interval enclosure of a/e.
    pub fn interval(&self) -> inari::Interval {
        match self {
            Ratio::Sommerville => crate::ival::pt(2.0).sqrt() / crate::ival::pt(4.0),
            Ratio::Value(x) => crate::ival::pt(*x),
        }
    }
    /// (a/e)² exactly.
    pub fn squared(&self) -> BigRational {
        match self {
            Ratio::Sommerville => BigRational::new(BigInt::from(1), BigInt::from(8)),
            Ratio::Value(x) => {
                let r = rat(*x);
                &r * &r
            }
        }
    }
}

pub type Xi = [i64; 3];

/// A named point in Ξ coordinates.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct NamedPt {
    pub name: String,
    pub xi: Xi,
}

fn xi_of_lattice(l: [i64; 3]) -> Xi {
    [4 * l[0] + 2 * l[1], 4 * l[1], 4 * l[2]]
}

fn sub(a: Xi, b: Xi) -> Xi {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn mid(a: Xi, b: Xi) -> Xi {
    [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2]
}
pub fn cross_i(a: Xi, b: Xi) -> [i128; 3] {
    let (a, b) = (a.map(|x| x as i128), b.map(|x| x as i128));
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn dot_i(a: [i128; 3], b: Xi) -> i128 {
    a[0] * b[0] as i128 + a[1] * b[1] as i128 + a[2] * b[2] as i128
}
fn det3(a: [i128; 3], b: [i128; 3], c: [i128; 3]) -> i128 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}
fn gcd(a: i128, b: i128) -> i128 {
    if b == 0 {
        a.abs()
    } else {
        gcd(b, a % b)
    }
}

/// Euclidean dot product of two Ξ vectors, exactly, up to the common factor e²/16:
/// x x' + (3/4) y y' + (a/e)² z z'.
pub fn metric_dot(r2: &BigRational, u: Xi, v: Xi) -> BigRational {
    let i = |x: i64| BigRational::from_integer(BigInt::from(x));
    i(u[0] * v[0]) + i(3 * u[1] * v[1]) / i(4) + r2 * i(u[2] * v[2])
}

/// The tetrahedron τ in Ξ coordinates, label order A, B, C, D (read from
/// `TetType::all()[0]`, the mesher's canonical tetrahedron).
pub fn tet_lattice() -> [[i64; 3]; 4] {
    TetType::all()[0].verts
}

/// A right-angled (90°) edge of τ and the octahedron formed by its four tetrahedra
/// (Appendix A, Fig 12): the two vertices not on the edge and their images under the
/// point reflection through the edge midpoint, in cyclic order around the edge.
#[derive(Clone, Debug)]
pub struct Octahedron {
    pub edge: [usize; 2],
    /// Cyclic order around the edge: x, y, x₂, y₂ in lattice coordinates with names.
    pub ring: [(String, [i64; 3]); 4],
}

/// Exact sign of the cosine of the interior dihedral angle of τ at each edge, in the
/// order of MIDPOINT_EDGES (0 means exactly 90°).
pub fn dihedral_signs(r2: &BigRational) -> [i32; 6] {
    let t = tet_lattice().map(xi_of_lattice);
    MIDPOINT_EDGES.map(|[p, q]| {
        let others: Vec<usize> = (0..4).filter(|&k| k != p && k != q).collect();
        let tt = sub(t[q], t[p]);
        let tt2 = metric_dot(r2, tt, tt);
        let perp = |r: usize| -> [BigRational; 3] {
            let w = sub(t[r], t[p]);
            let wt = metric_dot(r2, w, tt);
            let f = |k: usize| {
                BigRational::from_integer(BigInt::from(w[k])) * &tt2
                    - &wt * BigRational::from_integer(BigInt::from(tt[k]))
            };
            [f(0), f(1), f(2)]
        };
        let (u, v) = (perp(others[0]), perp(others[1]));
        let d = &u[0] * &v[0]
            + BigRational::new(BigInt::from(3), BigInt::from(4)) * &u[1] * &v[1]
            + r2 * &u[2] * &v[2];
        if d.is_zero() {
            0
        } else if d.is_positive() {
            1
        } else {
            -1
        }
    })
}

/// The octahedra around the right-angled edges of τ.
pub fn octahedra(r2: &BigRational) -> Vec<Octahedron> {
    let l = tet_lattice();
    let signs = dihedral_signs(r2);
    let mut out = Vec::new();
    for (e, &[p, q]) in MIDPOINT_EDGES.iter().enumerate() {
        if signs[e] != 0 {
            continue;
        }
        let others: Vec<usize> = (0..4).filter(|&k| k != p && k != q).collect();
        let refl = |x: usize| -> [i64; 3] {
            [
                l[p][0] + l[q][0] - l[x][0],
                l[p][1] + l[q][1] - l[x][1],
                l[p][2] + l[q][2] - l[x][2],
            ]
        };
        let (x, y) = (others[0], others[1]);
        out.push(Octahedron {
            edge: [p, q],
            ring: [
                (LABELS[x].to_string(), l[x]),
                (LABELS[y].to_string(), l[y]),
                (format!("{}2", LABELS[x]), refl(x)),
                (format!("{}2", LABELS[y]), refl(y)),
            ],
        });
    }
    out
}

/// A convex polyhedral cone {μ : μ·n ≥ 0 for every constraint n} and its exact vertex
/// rays in cyclic order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Piece {
    /// Constraint normals, each Ξ_p − Ξ_q with a readable "p >= q".
    pub constraints: Vec<(String, Xi)>,
    /// Vertex rays in cyclic order (empty when the cone has no interior).
    pub rays: Vec<Xi>,
}

impl Piece {
    pub fn new(constraints: Vec<(String, Xi)>) -> Result<Piece, String> {
        let mut rays: Vec<[i128; 3]> = Vec::new();
        let ns: Vec<Xi> = constraints.iter().map(|c| c.1).collect();
        for i in 0..ns.len() {
            for j in i + 1..ns.len() {
                let r = cross_i(ns[i], ns[j]);
                if r == [0, 0, 0] {
                    continue;
                }
                for s in [1i128, -1] {
                    let r = r.map(|x| s * x);
                    if ns.iter().all(|&n| dot_i(r, n) >= 0) {
                        let g = gcd(gcd(r[0], r[1]), r[2]);
                        let r = r.map(|x| x / g);
                        if !rays.contains(&r) {
                            rays.push(r);
                        }
                    }
                }
            }
        }
        let full = rays.len() >= 3 && {
            let mut any = false;
            for i in 0..rays.len() {
                for j in 0..rays.len() {
                    for k in 0..rays.len() {
                        any |= det3(rays[i], rays[j], rays[k]) != 0;
                    }
                }
            }
            any
        };
        if !full {
            return Ok(Piece {
                constraints,
                rays: Vec::new(),
            });
        }
        // A pointed cone: no ray may be opposite another.
        let s = rays
            .iter()
            .fold([0i128; 3], |a, r| [a[0] + r[0], a[1] + r[1], a[2] + r[2]]);
        let r0 = rays[0];
        let half = |r: &[i128; 3]| -> u8 {
            let d = det3(s, r0, *r);
            if d > 0 || (d == 0 && r == &r0) {
                0
            } else {
                1
            }
        };
        // Sort within halves: a before b when det(s, a, b) > 0.
        rays.sort_by(|a, b| {
            half(a).cmp(&half(b)).then_with(|| {
                let d = det3(s, *a, *b);
                if d > 0 {
                    std::cmp::Ordering::Less
                } else if d < 0 {
                    std::cmp::Ordering::Greater
                } else {
                    std::cmp::Ordering::Equal
                }
            })
        });
        let mut out = Vec::new();
        for r in rays {
            let m = r.iter().map(|x| x.abs()).max().unwrap_or(0);
            if m >= (1i128 << 50) {
                return Err("cone ray too large for exact f64".into());
            }
            out.push([r[0] as i64, r[1] as i64, r[2] as i64]);
        }
        Ok(Piece {
            constraints,
            rays: out,
        })
    }
    /// Is μ (exactly) in the cone?
    pub fn contains(&self, mu: [f64; 3]) -> bool {
        self.constraints
            .iter()
            .all(|(_, n)| mu[0] * n[0] as f64 + mu[1] * n[1] as f64 + mu[2] * n[2] as f64 >= 0.0)
    }
    /// Fan triangulation from the first ray.
    pub fn fan(&self) -> Vec<[Xi; 3]> {
        (1..self.rays.len().saturating_sub(1))
            .map(|i| [self.rays[0], self.rays[i], self.rays[i + 1]])
            .collect()
    }
    /// Every fan triangle cut into three quadrilaterals (corner, edge midpoint, centroid,
    /// edge midpoint; sums of rays, which are the same directions as the averages): each
    /// is the bilinear image of the unit square with a non-degenerate Jacobian, so the
    /// mean-value enclosures converge quadratically everywhere, corners included.
    pub fn quads(&self) -> Vec<[Xi; 4]> {
        let add = |a: Xi, b: Xi| [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
        let mut out = Vec::new();
        for [a, b, c] in self.fan() {
            let g = add(add(a, b), c);
            // Scale so that corners, midpoints and centroid have comparable weights.
            let s = |x: Xi, k: i64| x.map(|t| t * k);
            let (a6, b6, c6) = (s(a, 6), s(b, 6), s(c, 6));
            let (ab, bc, ca) = (s(add(a, b), 3), s(add(b, c), 3), s(add(c, a), 3));
            let g2 = s(g, 2);
            out.push([a6, ab, g2, ca]);
            out.push([b6, bc, g2, ab]);
            out.push([c6, ca, g2, bc]);
        }
        out
    }
}

/// An extra (non-linear) constraint of the shorter-diagonal rule: keep the normals m for
/// which the projection of `keep` (a diagonal, Ξ difference) is not longer than that of
/// `other`: |m × D keep|² ≤ |m × D other|².
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shorter {
    pub keep: Xi,
    pub other: Xi,
}

/// One domain of a case: the cone quadrilateral spanned by four rays (bilinearly
/// parametrised by the unit square) and an optional extra constraint.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Domain {
    pub rays: [Xi; 4],
    pub extra: Option<Shorter>,
}

/// One triangle of the GradNormal mesh and its region of plane normals.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Case {
    pub name: String,
    /// "triangle", "quad" or "valence4".
    pub group: String,
    pub vertices: [NamedPt; 3],
    pub region: String,
    pub pieces: Vec<Piece>,
    pub domains: Vec<Domain>,
}

fn named(name: impl Into<String>, xi: Xi) -> NamedPt {
    NamedPt {
        name: name.into(),
        xi,
    }
}

fn split(c: [NamedPt; 4], at: usize) -> [[NamedPt; 3]; 2] {
    let c = |k: usize| c[(k + at) % 4].clone();
    [[c(0), c(1), c(2)], [c(0), c(2), c(3)]]
}

fn tri_name(v: &[NamedPt; 3]) -> String {
    v.iter()
        .map(|p| p.name.clone())
        .collect::<Vec<_>>()
        .join(" ")
}

/// The quadrilateral's triangles under a rule: (triangles, extra constraint).
fn quad_triangles(
    cycle: [NamedPt; 4],
    paper_at: usize,
    rule: DiagonalRule,
) -> Vec<([NamedPt; 3], Option<Shorter>)> {
    let diag = |at: usize| sub(cycle[at].xi, cycle[at + 2].xi);
    match rule {
        DiagonalRule::Paper => split(cycle.clone(), paper_at)
            .into_iter()
            .map(|t| (t, None))
            .collect(),
        DiagonalRule::Alternate => split(cycle.clone(), 1 - paper_at)
            .into_iter()
            .map(|t| (t, None))
            .collect(),
        DiagonalRule::Shorter => {
            let mut out = Vec::new();
            for at in [paper_at, 1 - paper_at] {
                let s = Shorter {
                    keep: diag(at),
                    other: diag(1 - at),
                };
                for t in split(cycle.clone(), at) {
                    out.push((t, Some(s.clone())));
                }
            }
            out
        }
    }
}

fn domains_of(pieces: &[Piece], extra: &Option<Shorter>) -> Vec<Domain> {
    pieces
        .iter()
        .flat_map(|p| p.quads())
        .map(|rays| Domain {
            rays,
            extra: extra.clone(),
        })
        .collect()
}

/// Everything the proof derives from the tiling for one a/e.
#[derive(Clone, Debug)]
pub struct Derived {
    pub ratio: Ratio,
    /// Tet vertices (Ξ), label order.
    pub tet: [Xi; 4],
    pub octahedra: Vec<Octahedron>,
    pub dihedral_signs: [i32; 6],
}

impl Derived {
    pub fn new(ratio: Ratio) -> Derived {
        let r2 = ratio.squared();
        Derived {
            ratio,
            tet: tet_lattice().map(xi_of_lattice),
            octahedra: octahedra(&r2),
            dihedral_signs: dihedral_signs(&r2),
        }
    }
    fn midpoint(&self, k: usize) -> NamedPt {
        let [p, q] = MIDPOINT_EDGES[k];
        named(MIDPOINT_NAMES[k], mid(self.tet[p], self.tet[q]))
    }
    fn sep(&self, hi: &[(String, Xi)], lo: &[(String, Xi)]) -> Vec<(String, Xi)> {
        let mut out = Vec::new();
        for (hn, h) in hi {
            for (ln, l) in lo {
                out.push((format!("{hn}>={ln}"), sub(*h, *l)));
            }
        }
        out
    }
    fn label(&self, k: usize) -> (String, Xi) {
        (LABELS[k].to_string(), self.tet[k])
    }
    /// The octahedron whose edge contains label v (v's right-angled edge), if any.
    pub fn octahedron_at(&self, v: usize) -> Result<Option<&Octahedron>, String> {
        let os: Vec<&Octahedron> = self
            .octahedra
            .iter()
            .filter(|o| o.edge.contains(&v))
            .collect();
        match os.len() {
            0 => Ok(None),
            1 => Ok(Some(os[0])),
            _ => Err(format!(
                "vertex {} lies on two right-angled edges; the valence-four analysis assumes one",
                LABELS[v]
            )),
        }
    }

    /// All cases for a diagonal rule.
    pub fn cases(&self, rule: DiagonalRule) -> Result<Vec<Case>, String> {
        let mut cases = Vec::new();
        // 1. Elementary triangles, minus the normals for which the triangle's vertex on
        //    the right-angled edge is always a removed valence-four vertex.
        for (v, mids) in NORMAL_TRIANGLES {
            let others: Vec<(String, Xi)> =
                (0..4).filter(|&k| k != v).map(|k| self.label(k)).collect();
            let x = self.sep(&[self.label(v)], &others);
            let tri = mids.map(|k| self.midpoint(k));
            let (pieces, region) = match self.octahedron_at(v)? {
                None => (
                    vec![Piece::new(x)?],
                    format!("X_{} (no valence-four vertex)", LABELS[v]),
                ),
                Some(o) => {
                    // v's valence-four removal needs both reflected points on the far
                    // side of every admissible plane; the triangle survives for some
                    // offset iff one of them lies strictly above max(others).
                    let mut pieces = Vec::new();
                    for (name, l) in o.ring.iter().skip(2) {
                        let mut c = x.clone();
                        c.extend(self.sep(&[(name.clone(), xi_of_lattice(*l))], &others));
                        pieces.push(Piece::new(c)?);
                    }
                    (
                        pieces,
                        format!(
                            "X_{v} minus Z_{v}: {v} above {b}, and {r1} or {r2} above max({b})",
                            v = LABELS[v],
                            b = others
                                .iter()
                                .map(|o| o.0.clone())
                                .collect::<Vec<_>>()
                                .join(","),
                            r1 = o.ring[2].0,
                            r2 = o.ring[3].0
                        ),
                    )
                }
            };
            cases.push(Case {
                name: format!("{} (cut {})", tri_name(&tri), LABELS[v]),
                group: "triangle".into(),
                vertices: tri,
                region,
                domains: domains_of(&pieces, &None),
                pieces,
            });
        }
        // 2. Quadrilaterals split by the rule's diagonal; never touched by step 3 (both
        //    of their vertices on right-angled edges are diagonal endpoints).
        for q in NORMAL_QUADS {
            let side: Vec<(String, Xi)> = q.side.iter().map(|&k| self.label(k)).collect();
            let other: Vec<(String, Xi)> = (0..4)
                .filter(|k| !q.side.contains(k))
                .map(|k| self.label(k))
                .collect();
            let piece = Piece::new(self.sep(&side, &other))?;
            let cycle = q.cycle.map(|k| self.midpoint(k));
            let at = q
                .cycle
                .iter()
                .position(|&x| x == q.diagonal[0])
                .ok_or("quad diagonal not in its cycle")?
                % 2;
            for (t, extra) in quad_triangles(cycle, at, rule) {
                cases.push(Case {
                    name: format!("{} of {}", tri_name(&t), q.name),
                    group: "quad".into(),
                    region: format!(
                        "{} above {}{}",
                        side.iter()
                            .map(|s| s.0.clone())
                            .collect::<Vec<_>>()
                            .join(","),
                        other
                            .iter()
                            .map(|s| s.0.clone())
                            .collect::<Vec<_>>()
                            .join(","),
                        if extra.is_some() {
                            ", diagonal shorter"
                        } else {
                            ""
                        }
                    ),
                    domains: domains_of(std::slice::from_ref(&piece), &extra),
                    pieces: vec![piece.clone()],
                    vertices: t,
                });
            }
        }
        // 3. The square left by a valence-four removal (Fig 10, 12), for each right edge
        //    and each end cut off.
        let lat = tet_lattice();
        for o in &self.octahedra {
            for (vi, &v) in o.edge.iter().enumerate() {
                let w = o.edge[1 - vi];
                let mut others: Vec<(String, Xi)> = vec![self.label(w)];
                others.extend(o.ring.iter().map(|(n, l)| (n.clone(), xi_of_lattice(*l))));
                let piece = Piece::new(self.sep(&[self.label(v)], &others))?;
                let cycle: [NamedPt; 4] = o.ring.clone().map(|(n, l)| {
                    named(
                        format!("mid({}{})", LABELS[v], n),
                        mid(self.tet[v], xi_of_lattice(l)),
                    )
                });
                // The paper's diagonal: through the midpoint of the vertical lattice edge.
                let vert = o
                    .ring
                    .iter()
                    .position(|(_, l)| {
                        let d = [l[0] - lat[v][0], l[1] - lat[v][1], l[2] - lat[v][2]];
                        d == EDGE_DIRS[0] || d == EDGE_DIRS[0].map(|x| -x)
                    })
                    .ok_or("no vertical edge at the valence-four square")?;
                for (t, extra) in quad_triangles(cycle, vert % 2, rule) {
                    cases.push(Case {
                        name: format!(
                            "{} of the valence-4 square at {}{} (cut {})",
                            tri_name(&t),
                            LABELS[o.edge[0]],
                            LABELS[o.edge[1]],
                            LABELS[v]
                        ),
                        group: "valence4".into(),
                        region: format!(
                            "Y_{}: {} above {}{}",
                            LABELS[v],
                            LABELS[v],
                            others
                                .iter()
                                .map(|s| s.0.clone())
                                .collect::<Vec<_>>()
                                .join(","),
                            if extra.is_some() {
                                ", diagonal shorter"
                            } else {
                                ""
                            }
                        ),
                        domains: domains_of(std::slice::from_ref(&piece), &extra),
                        pieces: vec![piece.clone()],
                        vertices: t,
                    });
                }
            }
        }
        Ok(cases)
    }

    /// All named points (tet and octahedra), for describing rays.
    pub fn named_points(&self) -> Vec<(String, Xi)> {
        let mut out: Vec<(String, Xi)> = (0..4).map(|k| self.label(k)).collect();
        for o in &self.octahedra {
            for (n, l) in o.ring.iter().skip(2) {
                out.push((n.clone(), xi_of_lattice(*l)));
            }
        }
        out
    }

    /// A ray described by the level sets of μ·Ξ over `pts`, highest first, e.g.
    /// "A=B=C > D > B2 > C2": the normal of the plane through A, B, C.
    pub fn describe(&self, ray: Xi, pts: &[(String, Xi)]) -> String {
        let mut v: Vec<(i128, &str)> = pts
            .iter()
            .map(|(n, x)| (dot_i(ray.map(|t| t as i128), *x), n.as_str()))
            .collect();
        v.sort_by(|a, b| b.0.cmp(&a.0));
        let mut s = String::new();
        for (i, (d, n)) in v.iter().enumerate() {
            if i > 0 {
                s.push_str(if *d == v[i - 1].0 { "=" } else { " > " });
            }
            s.push_str(n);
        }
        s
    }
}

/// A floating-point normal μ described by the level sets of μ·Ξ (tolerance 1e-7 of the
/// spread), to say on which boundary arcs or vertices a witness lies (display only).
pub fn describe_f64(mu: [f64; 3], pts: &[(String, Xi)]) -> String {
    let mut v: Vec<(f64, &str)> = pts
        .iter()
        .map(|(n, x)| {
            (
                mu[0] * x[0] as f64 + mu[1] * x[1] as f64 + mu[2] * x[2] as f64,
                n.as_str(),
            )
        })
        .collect();
    v.sort_by(|a, b| b.0.total_cmp(&a.0));
    let spread = (v[0].0 - v[v.len() - 1].0).abs().max(1e-300);
    let mut s = String::new();
    for (i, (d, n)) in v.iter().enumerate() {
        if i > 0 {
            s.push_str(if (v[i - 1].0 - d).abs() <= 1e-7 * spread {
                "="
            } else {
                " > "
            });
        }
        s.push_str(n);
    }
    s
}

/// Exact angles of the unprojected midpoint triangles (the MidNormal mesh, Lemma 4.1):
/// for each triangle and vertex, (sign of cos, cos² as a rational).
pub fn exact_cos(r2: &BigRational, t: &[NamedPt; 3]) -> [(i32, BigRational); 3] {
    [0, 1, 2].map(|k| {
        let (p, q, r) = (t[k].xi, t[(k + 1) % 3].xi, t[(k + 2) % 3].xi);
        let (u, v) = (sub(q, p), sub(r, p));
        let d = metric_dot(r2, u, v);
        let s = if d.is_zero() {
            0
        } else if d.is_positive() {
            1
        } else {
            -1
        };
        let c2 = &d * &d / (metric_dot(r2, u, u) * metric_dot(r2, v, v));
        (s, c2)
    })
}

/// The MidNormal triangles (unprojected) for a rule: the four elementary triangles and
/// the quadrilaterals split by the rule (for `Shorter`: the shorter diagonal of the
/// midpoint quadrilateral, ties to the paper's).
pub fn midnormal_triangles(d: &Derived, rule: DiagonalRule) -> Vec<(String, [NamedPt; 3])> {
    let r2 = d.ratio.squared();
    let mut out = Vec::new();
    for (v, mids) in NORMAL_TRIANGLES {
        let t = mids.map(|k| d.midpoint(k));
        out.push((format!("{} (cut {})", tri_name(&t), LABELS[v]), t));
    }
    for q in NORMAL_QUADS {
        let cycle = q.cycle.map(|k| d.midpoint(k));
        let paper = q
            .cycle
            .iter()
            .position(|&x| x == q.diagonal[0])
            .unwrap_or(0)
            % 2;
        let at = match rule {
            DiagonalRule::Paper => paper,
            DiagonalRule::Alternate => 1 - paper,
            DiagonalRule::Shorter => {
                let len = |a: usize| {
                    let x = sub(cycle[a].xi, cycle[a + 2].xi);
                    metric_dot(&r2, x, x)
                };
                if len(1 - paper) < len(paper) {
                    1 - paper
                } else {
                    paper
                }
            }
        };
        for t in split(cycle.clone(), at) {
            out.push((format!("{} of {}", tri_name(&t), q.name), t));
        }
    }
    out
}
