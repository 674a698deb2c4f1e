//! The restricted Delaunay triangulation of a point set by a surface S = {f = 0} ∩ D:
//! the facets of the 3D Delaunay triangulation whose dual Voronoi edge meets S (the
//! chapter "Meshing of Surfaces", Boissonnat et al., 2007, §1.3). Shared by every
//! restricted-Delaunay driver (Boissonnat–Oudot here, Cheng–Dey–Ramos–Ray later): dual
//! segments, their crossings with S, facet orientation, the full scan, and the
//! certified re-derivation with interval circumcentres.
//!
//! **Dual segments.** The kernel's far box makes every cell a finite tetrahedron, so
//! the Voronoi edge dual to an interior facet is the segment between the circumcentres
//! of its two cells. Facets on the far box's hull (their dual a ray) and every facet
//! with a far corner are never restricted, by [`far_lemma`]: once every other vertex
//! lies in D and each far corner is farther than diam(D) from D, a point of D is
//! closer to any vertex in D than to a far corner, so it lies in no far corner's
//! Voronoi cell, and a Voronoi edge of a facet with a far corner is in that cell.
//!
//! **Crossings.** Every crossing of a dual segment with S is found by certified root
//! isolation on the segment ([`crate::implicit::ops::isolate_segment`]), not by the
//! signs at its ends: a Voronoi edge can cross S twice (thin parts, near-touching
//! components), which a sign-at-the-ends oracle (CGAL's) cannot see. Each crossing x is
//! the centre of a surface Delaunay ball of radius |x − a|, a any vertex of the facet.
//!
//! **Orientation.** A restricted facet is oriented with its normal pointing to the
//! f > 0 side at its (largest-ball) crossing: the Voronoi edge runs from the
//! circumcentre of cell c to that of its neighbour d in the direction of c's outward
//! normal of the facet, so a rising crossing orients the facet outward from c.
use crate::implicit::ops::{
    excludes_zero, isolate_segment, segment_root_point, segment_sign, SegmentBudget, SegmentRoot,
};
use crate::implicit::{IBox, Implicit};
use crate::kernel::delaunay::{circumcentre, CellId, Delaunay, VertexId};
use crate::kernel::geom::{dist, Aabb};
use inari::Interval;
use serde::Serialize;

/// The vertices of facet `i` of a positively oriented cell, ordered so that their
/// normal (right-hand rule) points out of the cell.
pub const OUTWARD: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

/// One crossing of a dual segment with S.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct FacetCrossing {
    /// A float point of the crossing (bisection inside its certified piece).
    pub point: [f64; 3],
    /// Radius of the surface Delaunay ball centred there.
    pub radius: f64,
    /// An upper bound of that radius over the crossing's certified piece (in
    /// `Certified` scans: outward-rounded over the interval segment; else `radius`).
    pub radius_sup: f64,
    /// The segment enters {f > 0} here (from the first cell towards its neighbour).
    pub rising: bool,
    /// The certified piece of the segment parameter.
    pub piece: [f64; 2],
}

/// A facet with the crossings of its dual segment.
#[derive(Clone, Debug, Serialize)]
pub struct DualTest {
    pub crossings: Vec<FacetCrossing>,
    /// Pieces of the segment parameter where isolation failed (tangent or grazing
    /// crossings, a Voronoi vertex on S), with a float point of each.
    pub undecided: Vec<[f64; 3]>,
    /// Interval pieces processed.
    pub pieces: u32,
}

impl DualTest {
    pub fn restricted(&self) -> bool {
        !self.crossings.is_empty()
    }
    /// The crossing with the largest surface Delaunay ball.
    pub fn largest(&self) -> Option<&FacetCrossing> {
        self.crossings
            .iter()
            .max_by(|a, b| a.radius.total_cmp(&b.radius))
    }
}

/// The refinement queue's order, shared by the drivers (`bo`, `curve`): an entry type
/// with fields `class` (an `Ord` kind of badness) and `badness: f64` is ordered for a
/// max-heap that pops the lowest class first, then the largest badness.
macro_rules! worst_first_order {
    ($t:ty) => {
        impl PartialEq for $t {
            fn eq(&self, o: &Self) -> bool {
                self.cmp(o) == std::cmp::Ordering::Equal
            }
        }
        impl Eq for $t {}
        impl PartialOrd for $t {
            fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
                Some(self.cmp(o))
            }
        }
        impl Ord for $t {
            fn cmp(&self, o: &Self) -> std::cmp::Ordering {
                o.class
                    .cmp(&self.class)
                    .then(self.badness.total_cmp(&o.badness))
            }
        }
    };
}
pub(crate) use worst_first_order;

/// The point `p` as a box.
pub fn point_box(p: [f64; 3]) -> IBox {
    p.map(|x| Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE))
}

/// Crossings of S with the float segment a → b (the float circumcentres of the two
/// cells), `v0` a vertex of the facet (for the ball radius). Roots are isolated by
/// interval arithmetic on this float segment; only the circumcentres are floats.
pub fn test_segment(
    f: &dyn Implicit,
    a: [f64; 3],
    b: [f64; 3],
    v0: [f64; 3],
    domain: &IBox,
    budget: SegmentBudget,
) -> DualTest {
    let r = isolate_segment(f, &point_box(a), &point_box(b), Some(domain), budget);
    let crossings = r
        .roots
        .iter()
        .map(|root: &SegmentRoot| {
            let (p, _) = segment_root_point(f, a, b, root, 1e-15);
            FacetCrossing {
                point: p,
                radius: dist(p, v0),
                radius_sup: dist(p, v0),
                rising: root.rising,
                piece: [root.t0, root.t1],
            }
        })
        .collect();
    let undecided = r
        .undecided
        .iter()
        .map(|u| crate::kernel::geom::lerp(a, b, 0.5 * (u[0] + u[1])))
        .collect();
    DualTest {
        crossings,
        undecided,
        pieces: r.pieces,
    }
}

/// A sub-piece of a certified root's piece that still holds the root: the end signs
/// of [t − δ, t + δ] around the float root t proven opposite (interval evaluation on
/// the boxed segment), δ growing from 1e-12; the whole piece if that fails. The root
/// is unique in its piece, so it lies in any sub-piece with opposite end signs.
fn narrow(f: &dyn Implicit, a: &IBox, b: &IBox, root: &SegmentRoot, t: f64) -> SegmentRoot {
    let sign = |t: f64| segment_sign(f, a, b, t);
    let mut d = 1e-12;
    while d < 1e-3 {
        let (l, h) = ((t - d).max(root.t0), (t + d).min(root.t1));
        if l < h && sign(l) == Some(!root.rising) && sign(h) == Some(root.rising) {
            return SegmentRoot {
                t0: l,
                t1: h,
                rising: root.rising,
            };
        }
        d *= 16.0;
    }
    *root
}

/// sup |x − v| over the enclosure a + T (b − a) of the crossing's piece T and v in the
/// box `v`.
fn radius_sup(a: &IBox, b: &IBox, root: &SegmentRoot, v: &IBox) -> f64 {
    let tt = Interval::try_from((root.t0, root.t1)).unwrap_or(Interval::ENTIRE);
    let d2 = (0..3)
        .map(|k| (a[k] + tt * (b[k] - a[k]) - v[k]).sqr())
        .fold(Interval::try_from((0.0, 0.0)).unwrap(), |s, x| s + x);
    // sqrt rounded up: one ulp-scale margin over the float square root.
    d2.sup().sqrt() * (1.0 + 4.0 * f64::EPSILON)
}

/// Does every Voronoi edge of a facet with a far corner miss D? (See the module doc;
/// checked with outward-rounded intervals.) False if some inserted non-far vertex lies
/// outside D, or if there is none.
pub fn far_lemma(t: &Delaunay, domain: &Aabb) -> bool {
    let mut any = false;
    for v in crate::kernel::delaunay::FAR..t.points().len() as u32 {
        if !t.is_inserted(v) {
            continue;
        }
        if !domain.contains(t.point(v)) {
            return false;
        }
        any = true;
    }
    if !any {
        return false;
    }
    let d = domain.intervals();
    // The interval difference d − d = [lo − hi, hi − lo] ⊇ every coordinate difference
    // inside the box (not 0: the two operands are independent points).
    #[allow(clippy::eq_op)]
    let w: [Interval; 3] = [0, 1, 2].map(|k| d[k] - d[k]);
    let diam2 = w[0].sqr() + w[1].sqr() + w[2].sqr();
    (0..crate::kernel::delaunay::FAR).all(|q| {
        let p = t.point(q);
        // Distance from the corner to the box, per axis (a lower bound).
        let gap: [Interval; 3] = [0, 1, 2].map(|k| {
            let pk = Interval::try_from((p[k], p[k])).unwrap_or(Interval::ENTIRE);
            if p[k] < domain.min[k] {
                d[k].inf_interval() - pk
            } else if p[k] > domain.max[k] {
                pk - d[k].sup_interval()
            } else {
                Interval::try_from((0.0, 0.0)).unwrap()
            }
        });
        let g2 = gap[0].sqr() + gap[1].sqr() + gap[2].sqr();
        g2.inf() > diam2.sup()
    })
}

trait Ends {
    fn inf_interval(&self) -> Interval;
    fn sup_interval(&self) -> Interval;
}
impl Ends for Interval {
    fn inf_interval(&self) -> Interval {
        Interval::try_from((self.inf(), self.inf())).unwrap_or(Interval::ENTIRE)
    }
    fn sup_interval(&self) -> Interval {
        Interval::try_from((self.sup(), self.sup())).unwrap_or(Interval::ENTIRE)
    }
}

/// An interval enclosure of the circumcentre of a tetrahedron with float vertices
/// (the same formula as [`circumcentre`], in outward-rounded arithmetic), or `None`
/// when the enclosure of the determinant contains 0 (a sliver too flat to enclose).
pub fn circumcentre_interval(p: [[f64; 3]; 4]) -> Option<IBox> {
    circumcentre_of_boxes(p.map(point_box))
}

/// [`circumcentre_interval`] for vertices anywhere in the boxes `p`: an enclosure of
/// the circumcentres of all such tetrahedra.
pub fn circumcentre_of_boxes(p: [IBox; 4]) -> Option<IBox> {
    // In the fast interval type `Iv`: inari's bounds, bit for bit.
    use crate::implicit::directed::Iv;
    let q = p.map(|x| x.map(Iv::from_interval));
    let d: [[Iv; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|k| q[i + 1][k] - q[0][k]));
    let (l, [c12, c20, c01], det) = crate::kernel::delaunay::circumcentre_terms(d, |x: Iv| x.sqr());
    if !(det.lo > 0.0 || det.hi < 0.0) {
        return None;
    }
    let two = Iv::point(2.0);
    let c: IBox = std::array::from_fn(|k| {
        (q[0][k] + (l[0] * c12[k] + l[1] * c20[k] + l[2] * c01[k]) / (two * det)).to_interval()
    });
    c.iter()
        .all(|x| x.inf().is_finite() && x.sup().is_finite())
        .then_some(c)
}

/// The facet `(c, i)` as 3 vertex ids, outward from `c` when `outward`, else inward.
pub fn facet_vertices(t: &Delaunay, c: CellId, i: usize, outward: bool) -> [VertexId; 3] {
    let v = t.cell_vertices(c);
    let o = OUTWARD[i];
    if outward {
        [v[o[0]], v[o[1]], v[o[2]]]
    } else {
        [v[o[0]], v[o[2]], v[o[1]]]
    }
}

/// A facet's key: its sorted vertex ids.
pub fn key(v: [VertexId; 3]) -> [VertexId; 3] {
    let mut k = v;
    k.sort_unstable();
    k
}

/// One restricted facet of a scan.
#[derive(Clone, Debug, Serialize)]
pub struct RestrictedFacet {
    /// Vertex ids, oriented towards f > 0.
    pub v: [VertexId; 3],
    pub cell: CellId,
    pub facet: usize,
    pub test: DualTest,
}

/// A dual segment whose crossings were not all decided.
#[derive(Clone, Debug, Serialize)]
pub struct UndecidedFacet {
    pub v: [VertexId; 3],
    pub cell: CellId,
    pub facet: usize,
    /// A float point near each undecided piece (or the segment's midpoint when the
    /// circumcentres could not be enclosed).
    pub points: Vec<[f64; 3]>,
    pub reason: &'static str,
}

/// The restricted Delaunay triangulation of the current vertex set.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Scan {
    pub facets: Vec<RestrictedFacet>,
    pub undecided: Vec<UndecidedFacet>,
    /// Dual segments tested (facets without a far corner).
    pub segments: usize,
    /// Facets with a far corner, not restricted by [`far_lemma`].
    pub far_facets: usize,
    /// Did [`far_lemma`] hold? (If not, the far facets are in `undecided`.)
    pub far_lemma: bool,
    /// Segments with two or more crossings.
    pub multiple_crossings: usize,
    /// Interval pieces processed.
    pub pieces: u64,
}

/// How the end points of the dual segments are taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ends3 {
    /// Float circumcentres (the refinement's view).
    Float,
    /// Interval enclosures of the exact circumcentres (the certificate's view).
    Certified,
}

/// The interval circumcentre of every live cell of `t` ([`circumcentre_interval`]), by
/// cell id (`None` for dead cells and unenclosed slivers); computed in parallel.
pub fn certified_circumcentres(t: &Delaunay) -> Vec<Option<IBox>> {
    use rayon::prelude::*;
    (0..t.cell_capacity() as u32)
        .into_par_iter()
        .map(|c| {
            t.is_live(c)
                .then(|| circumcentre_interval(t.cell_vertices(c).map(|v| t.point(v))))
                .flatten()
        })
        .collect()
}

/// Test every facet of `t`: the restricted facets, and the facets whose dual could
/// not be decided. `cc` holds the float circumcentre per cell id (`Float` mode; the
/// `Certified` mode encloses them itself, see [`scan_certified`]).
pub fn scan(
    t: &Delaunay,
    f: &dyn Implicit,
    domain: &Aabb,
    cc: &[[f64; 3]],
    ends: Ends3,
    budget: SegmentBudget,
) -> Scan {
    match ends {
        Ends3::Float => scan_ends(t, f, domain, SegmentEnds::Float(cc), budget),
        Ends3::Certified => {
            let icc = certified_circumcentres(t);
            scan_certified(t, f, domain, &icc, budget)
        }
    }
}

/// The `Certified` scan with the interval circumcentres `icc` given (by cell id, as
/// [`certified_circumcentres`] returns them).
pub fn scan_certified(
    t: &Delaunay,
    f: &dyn Implicit,
    domain: &Aabb,
    icc: &[Option<IBox>],
    budget: SegmentBudget,
) -> Scan {
    scan_ends(t, f, domain, SegmentEnds::Certified(icc, None), budget)
}

/// The `Certified` scan for vertices anywhere in their boxes `vboxes` (by vertex id),
/// `icc` the circumcentre enclosures over those boxes
/// ([`super::perturbed::boxed_circumcentres`]): every conclusion (crossings, radius
/// bounds) holds for every choice of the vertices in their boxes. A facet with a
/// vertex without a box is reported undecided ("circumcentre not enclosed").
pub fn scan_boxed(
    t: &Delaunay,
    f: &dyn Implicit,
    domain: &Aabb,
    icc: &[Option<IBox>],
    vboxes: &[Option<IBox>],
    budget: SegmentBudget,
) -> Scan {
    scan_ends(
        t,
        f,
        domain,
        SegmentEnds::Certified(icc, Some(vboxes)),
        budget,
    )
}

enum SegmentEnds<'a> {
    Float(&'a [[f64; 3]]),
    /// Circumcentre enclosures, and the vertex boxes when the vertices are boxes.
    Certified(&'a [Option<IBox>], Option<&'a [Option<IBox>]>),
}

/// What one facet's dual segment gave.
enum Outcome {
    /// A far-corner facet (restricted never, by [`far_lemma`], when it holds).
    Far,
    /// A cell's circumcentre could not be enclosed: the midpoint of the float segment.
    Unenclosed([f64; 3]),
    Tested(DualTest),
}

/// Segments per batch of the one-enclosure pre-test (and per parallel task).
const CHUNK: usize = 256;

/// The hull of two boxes: it contains the segment between any of their points.
fn join(a: &IBox, b: &IBox) -> IBox {
    std::array::from_fn(|k| a[k].convex_hull(b[k]))
}

/// The scan proper. The facets are cut into chunks tested in parallel; in each chunk
/// one batched interval enclosure of f over the hull of each segment's end boxes
/// settles the segments it proves free of S (0 ∉ □f on a box containing the whole
/// segment: no crossing, nothing undecided); the others get full root isolation. The
/// outcomes are folded in the kernel's facet order, so the scan is the same whatever
/// the number of threads.
fn scan_ends(
    t: &Delaunay,
    f: &dyn Implicit,
    domain: &Aabb,
    ends: SegmentEnds,
    budget: SegmentBudget,
) -> Scan {
    use rayon::prelude::*;
    let dbox = domain.intervals();
    let lemma = far_lemma(t, domain);
    let mut s = Scan {
        far_lemma: lemma,
        ..Default::default()
    };
    let all: Vec<(CellId, usize, CellId)> = t.facets(false).map(|(c, i, d, _)| (c, i, d)).collect();
    let test = |&(c, i, d): &(CellId, usize, CellId)| -> Option<(IBox, IBox)> {
        let fv = facet_vertices(t, c, i, true);
        if fv.iter().any(|&v| t.is_far(v)) {
            return None;
        }
        match ends {
            SegmentEnds::Float(cc) => Some((point_box(cc[c as usize]), point_box(cc[d as usize]))),
            SegmentEnds::Certified(icc, _) => Some((icc[c as usize]?, icc[d as usize]?)),
        }
    };
    let outcomes: Vec<Outcome> = all
        .par_chunks(CHUNK)
        .flat_map_iter(|chunk| {
            let segs: Vec<Option<(IBox, IBox)>> = chunk.iter().map(test).collect();
            let hulls: Vec<IBox> = segs.iter().flatten().map(|(a, b)| join(a, b)).collect();
            let mut enc = vec![Interval::EMPTY; hulls.len()];
            f.eval_interval_batch(&hulls, &mut enc);
            let mut k = 0;
            chunk
                .iter()
                .zip(segs)
                .map(|(&(c, i, d), seg)| {
                    let fv = facet_vertices(t, c, i, true);
                    if fv.iter().any(|&v| t.is_far(v)) {
                        return Outcome::Far;
                    }
                    let Some((a, b)) = seg else {
                        let m = crate::kernel::geom::lerp(
                            circumcentre(t.cell_vertices(c).map(|v| t.point(v))),
                            circumcentre(t.cell_vertices(d).map(|v| t.point(v))),
                            0.5,
                        );
                        return Outcome::Unenclosed(m);
                    };
                    let e = enc[k];
                    k += 1;
                    if !e.is_empty() && excludes_zero(e) {
                        return Outcome::Tested(DualTest {
                            crossings: Vec::new(),
                            undecided: Vec::new(),
                            pieces: 1,
                        });
                    }
                    let v0 = t.point(fv[0]);
                    Outcome::Tested(match ends {
                        SegmentEnds::Float(cc) => {
                            test_segment(f, cc[c as usize], cc[d as usize], v0, &dbox, budget)
                        }
                        SegmentEnds::Certified(_, vb) => {
                            let b0 = match vb {
                                None => point_box(v0),
                                Some(vb) => match vb.get(fv[0] as usize).copied().flatten() {
                                    Some(b0) => b0,
                                    None => return Outcome::Unenclosed(v0),
                                },
                            };
                            certified_segment(f, &a, &b, v0, &b0, &dbox, budget)
                        }
                    })
                })
                .collect::<Vec<_>>()
        })
        .collect();
    for (&(c, i, _), outcome) in all.iter().zip(outcomes) {
        let fv = facet_vertices(t, c, i, true);
        let test = match outcome {
            Outcome::Far => {
                s.far_facets += 1;
                if !lemma {
                    s.undecided.push(UndecidedFacet {
                        v: fv,
                        cell: c,
                        facet: i,
                        points: Vec::new(),
                        reason: "far-corner facet: a vertex lies outside the domain",
                    });
                }
                continue;
            }
            Outcome::Unenclosed(m) => {
                s.segments += 1;
                s.undecided.push(UndecidedFacet {
                    v: fv,
                    cell: c,
                    facet: i,
                    points: vec![m],
                    reason: "circumcentre not enclosed (a sliver cell)",
                });
                continue;
            }
            Outcome::Tested(x) => x,
        };
        s.segments += 1;
        s.pieces += test.pieces as u64;
        if !test.undecided.is_empty() {
            s.undecided.push(UndecidedFacet {
                v: fv,
                cell: c,
                facet: i,
                points: test.undecided.clone(),
                reason: "tangent or grazing crossing (roots not isolated)",
            });
        }
        if test.crossings.len() >= 2 {
            s.multiple_crossings += 1;
        }
        if let Some(x) = test.largest() {
            let v = facet_vertices(t, c, i, x.rising);
            s.facets.push(RestrictedFacet {
                v,
                cell: c,
                facet: i,
                test,
            });
        }
    }
    s
}

/// Every crossing of S with the segment between any points of the boxes `a` and `b`
/// (interval circumcentres), by certified root isolation; each crossing's float point
/// on the segment of the boxes' midpoints, its radius bound over the certified piece
/// and the facet vertex's box `b0` (holding `v0`).
fn certified_segment(
    f: &dyn Implicit,
    a: &IBox,
    b: &IBox,
    v0: [f64; 3],
    b0: &IBox,
    dbox: &IBox,
    budget: SegmentBudget,
) -> DualTest {
    let r = isolate_segment(f, a, b, Some(dbox), budget);
    let am = a.map(|x| x.mid());
    let bm = b.map(|x| x.mid());
    DualTest {
        crossings: r
            .roots
            .iter()
            .map(|root| {
                let (p, tp) = segment_root_point(f, am, bm, root, 1e-12);
                let narrow = narrow(f, a, b, root, tp);
                FacetCrossing {
                    point: p,
                    radius: dist(p, v0),
                    radius_sup: radius_sup(a, b, &narrow, b0),
                    rising: root.rising,
                    piece: [root.t0, root.t1],
                }
            })
            .collect(),
        undecided: r
            .undecided
            .iter()
            .map(|u| crate::kernel::geom::lerp(am, bm, 0.5 * (u[0] + u[1])))
            .collect(),
        pieces: r.pieces,
    }
}
