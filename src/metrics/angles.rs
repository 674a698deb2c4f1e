//! Element shape: triangle angles, tetrahedron dihedral and face angles, edge-length
//! ratios, radius ratios, and histograms of them.
//!
//! Angles use the atan2(|u×v|, u·v) form ([`geom::angle_deg`]), accurate near 0° and
//! 180° where acos loses half the digits.
use super::min_max;
use crate::error::Result;
use crate::kernel::geom::{self, cross, dot, norm, sub};
use crate::mesh::{TetMesh, TriMesh};
use rayon::prelude::*;
use serde::Serialize;

/// A triangle counts as degenerate (no meaningful angles) when a vertex index repeats
/// or its area is below this fraction of its longest edge squared, i.e. the triangle's
/// height is below ~1e-12 of its size. Degenerate elements are counted, and left out of
/// the angle ranges and histograms.
pub const DEGENERATE_REL: f64 = 1e-12;

/// The three angles of triangle `abc` in degrees, at a, b, c.
pub fn triangle_angles(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    [
        geom::angle_deg(c, a, b),
        geom::angle_deg(a, b, c),
        geom::angle_deg(b, c, a),
    ]
}

/// Longest over shortest edge (infinite when two corners coincide).
pub fn edge_ratio(pts: &[[f64; 3]]) -> f64 {
    let n = pts.len();
    edge_ratio_of((0..n).flat_map(|i| (i + 1..n).map(move |j| geom::dist(pts[i], pts[j]))))
}

/// Longest over shortest of the given edge lengths, in [`edge_ratio`]'s way.
#[inline]
fn edge_ratio_of(lens: impl IntoIterator<Item = f64>) -> f64 {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for l in lens {
        lo = lo.min(l);
        hi = hi.max(l);
    }
    if lo > 0.0 {
        hi / lo
    } else {
        f64::INFINITY
    }
}

/// Is the triangle numerically flat (see [`DEGENERATE_REL`])?
pub fn triangle_is_degenerate(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    let l2 = [sub(b, a), sub(c, b), sub(a, c)]
        .iter()
        .map(|e| dot(*e, *e))
        .fold(0.0, f64::max);
    let area2 = norm(cross(sub(b, a), sub(c, a)));
    !(area2 > DEGENERATE_REL * l2)
}

/// The angle at `b` of the triangle `a b c` as the pair of [`geom::angle_deg`]: atan2 of it
/// is the angle (the same operations, so the same bits).
pub(crate) fn angle_pair(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> (f64, f64) {
    let (u, v) = (sub(a, b), sub(c, b));
    (norm(cross(u, v)), dot(u, v))
}

/// A running minimum and maximum of angles given as atan2 pairs (y ≥ 0), computing
/// atan2 only for a pair that may beat the current extremes: with (cos m, sin m) of
/// the current minimum m, cos m · y − sin m · x = |(x, y)| sin(θ − m), so a value above
/// 10⁻⁹ (|x| + |y|) proves θ > m + 10⁻⁹ rad, far beyond the rounding of atan2 and of
/// the test (about 10⁻¹⁶ relative); likewise for the maximum. The extremes are
/// therefore those of atan2 over every pair, bit for bit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Extremes {
    pub(crate) min: f64,
    pub(crate) max: f64,
    // (cos, sin) of the current extremes; (0, 0) before the first value, so that the
    // first pair is always computed.
    pub(crate) min_dir: [f64; 2],
    pub(crate) max_dir: [f64; 2],
}

impl Extremes {
    pub(crate) const EMPTY: Extremes = Extremes {
        min: f64::INFINITY,
        max: f64::NEG_INFINITY,
        min_dir: [0.0; 2],
        max_dir: [0.0; 2],
    };
    #[inline]
    pub(crate) fn offer(&mut self, (y, x): (f64, f64)) {
        let r = 1e-9 * (y.abs() + x.abs());
        let above_min = self.min_dir[0] * y - self.min_dir[1] * x > r;
        let below_max = self.max_dir[0] * y - self.max_dir[1] * x < -r;
        if above_min && below_max {
            return;
        }
        let t = y.atan2(x);
        let a = t.to_degrees();
        if a < self.min {
            self.min = a;
            self.min_dir = [t.cos(), t.sin()];
        }
        if a > self.max {
            self.max = a;
            self.max_dir = [t.cos(), t.sin()];
        }
    }
    /// The extremes of both (the reduction of parallel folds).
    #[inline]
    pub(crate) fn merge(&mut self, o: Extremes) {
        if o.min < self.min {
            (self.min, self.min_dir) = (o.min, o.min_dir);
        }
        if o.max > self.max {
            (self.max, self.max_dir) = (o.max, o.max_dir);
        }
    }
}

/// A histogram over `[lo, lo + bin_width * counts.len())`; values outside are clamped
/// into the first or last bin.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Histogram {
    pub lo: f64,
    pub bin_width: f64,
    pub counts: Vec<u64>,
}

impl Histogram {
    /// Bins of width `bin_width` covering `[lo, hi]`.
    pub fn new(lo: f64, hi: f64, bin_width: f64, values: impl IntoIterator<Item = f64>) -> Self {
        let mut h = Histogram::empty(lo, hi, bin_width);
        for v in values {
            h.add(v);
        }
        h
    }
    /// No values yet: the bins of [`Histogram::new`].
    pub fn empty(lo: f64, hi: f64, bin_width: f64) -> Self {
        let bins = if bin_width > 0.0 && hi > lo {
            ((hi - lo) / bin_width).ceil().max(1.0) as usize
        } else {
            1
        };
        let bw = if bin_width > 0.0 { bin_width } else { 1.0 };
        Histogram {
            lo,
            bin_width: bw,
            counts: vec![0u64; bins],
        }
    }
    /// Count `v` (NaN is left out; values beyond the ends go to the end bins).
    #[inline]
    pub fn add(&mut self, v: f64) {
        if v.is_nan() {
            return;
        }
        let k = ((v - self.lo) / self.bin_width).floor();
        let k = if k < 0.0 {
            0
        } else {
            (k as usize).min(self.counts.len() - 1)
        };
        self.counts[k] += 1;
    }
    /// The counts of both (histograms of the same bins).
    pub fn merge(mut self, o: &Histogram) -> Self {
        for (a, b) in self.counts.iter_mut().zip(&o.counts) {
            *a += b;
        }
        self
    }
    pub fn total(&self) -> u64 {
        self.counts.iter().sum()
    }
    /// Fractions of the total per bin (all zero for an empty histogram).
    pub fn normalized(&self) -> Vec<f64> {
        let t = self.total().max(1) as f64;
        self.counts.iter().map(|&c| c as f64 / t).collect()
    }
    /// The left edge of bin `k`.
    pub fn bin_lo(&self, k: usize) -> f64 {
        self.lo + k as f64 * self.bin_width
    }
}

/// Angle and edge-ratio summary of a triangle mesh.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TriangleAngles {
    pub triangles: usize,
    /// Triangles left out of the ranges (see [`DEGENERATE_REL`]).
    pub degenerate: usize,
    /// `None` when there is no non-degenerate triangle.
    pub min_angle_deg: Option<f64>,
    pub max_angle_deg: Option<f64>,
    pub mean_min_angle_deg: Option<f64>,
    pub min_edge_ratio: Option<f64>,
    pub max_edge_ratio: Option<f64>,
    /// Histogram of all angles, bins of `bin_width` degrees over [0, 180].
    pub histogram: Histogram,
}

/// The angles of every triangle, `None` for degenerate ones.
pub fn per_triangle(mesh: &TriMesh) -> Result<Vec<Option<[f64; 3]>>> {
    super::check_trimesh(mesh)?;
    Ok(mesh
        .triangles
        .par_iter()
        .map(|t| {
            if TriMesh::repeats_vertex(*t) {
                return None;
            }
            let [a, b, c] = mesh.corners_of(*t);
            if triangle_is_degenerate(a, b, c) {
                None
            } else {
                Some(triangle_angles(a, b, c))
            }
        })
        .collect())
}

/// The smallest of three angles given as atan2 pairs (y ≥ 0), in degrees, with one
/// atan2 where the order is proven: for θ, φ ∈ [0, π], x_θ y_φ − y_θ x_φ =
/// |p_θ| |p_φ| sin(φ − θ) has the sign of φ − θ, and a value beyond 10⁻⁹ of the
/// pairs' sizes proves |φ − θ| > 10⁻⁹ rad, far beyond the rounding of the test and of
/// atan2. A pair not proven larger than the current smallest is evaluated, so the
/// result is the minimum of the three atan2 values, bit for bit.
#[inline]
fn smallest_angle_deg(p: [(f64, f64); 3]) -> f64 {
    // Is p's angle proven larger than q's?
    let larger = |p: (f64, f64), q: (f64, f64)| {
        let r = 1e-9 * (p.0.abs() + p.1.abs()) * (q.0.abs() + q.1.abs());
        q.1 * p.0 - q.0 * p.1 > r
    };
    // Every angle not proven larger than another is evaluated: the smallest computed
    // value is among them (it cannot be proven larger than any other).
    let mut m = f64::INFINITY;
    for j in 0..3 {
        if !(0..3).any(|i| i != j && larger(p[j], p[i])) {
            m = m.min(p[j].0.atan2(p[j].1).to_degrees());
        }
    }
    m
}

/// Per triangle, what [`triangle_ranges`] needs, from the three edge vectors computed
/// once: the three angle pairs of [`angle_pair`] and the edge lengths of
/// [`edge_ratio`], bit for bit (negating a vector is exact, so cross(−u, v) and
/// dot(−u, v) are the negated cross(u, v) and dot(u, v)), or `None` when the triangle
/// is degenerate by [`triangle_is_degenerate`] (whose doubled area is the first pair's
/// norm, and whose edges are these).
#[inline]
fn triangle_pairs(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Option<([(f64, f64); 3], f64)> {
    let (ab, bc, ca) = (sub(b, a), sub(c, b), sub(a, c));
    let l2 = [dot(ab, ab), dot(bc, bc), dot(ca, ca)];
    let pa = (norm(cross(ca, ab)), -dot(ca, ab));
    if !(pa.0 > DEGENERATE_REL * l2.iter().copied().fold(0.0, f64::max)) {
        return None;
    }
    let pb = (norm(cross(ab, bc)), -dot(ab, bc));
    let pc = (norm(cross(bc, ca)), -dot(bc, ca));
    // edge_ratio's order: |a − b|, |a − c|, |b − c|.
    let ratio = edge_ratio_of([l2[0].sqrt(), l2[2].sqrt(), l2[1].sqrt()]);
    Some(([pa, pb, pc], ratio))
}

/// [`triangle_summary`] without the histogram (what the mesh report shows): the same
/// values bit for bit, for a fraction of the work. One parallel pass over fixed
/// chunks of triangles; the extremes compute atan2 only for an angle that may beat
/// them ([`Extremes`]), each triangle's smallest angle with one atan2 where the order
/// of its angles is proven ([`smallest_angle_deg`]), and the mean sums the same values
/// in mesh order (chunk by chunk, in order).
pub fn triangle_ranges(mesh: &TriMesh) -> Result<TriangleAngles> {
    super::check_trimesh(mesh)?;
    const CHUNK: usize = 8192;
    let tris = &mesh.triangles;
    struct Part {
        smallest: Vec<f64>,
        ext: Extremes,
        ratios: Option<(f64, f64)>,
    }
    let parts: Vec<Part> = tris
        .par_chunks(CHUNK)
        .map(|ch| {
            let mut p = Part {
                smallest: Vec::with_capacity(ch.len()),
                ext: Extremes::EMPTY,
                ratios: None,
            };
            for t in ch {
                if TriMesh::repeats_vertex(*t) {
                    continue;
                }
                let [a, b, c] = mesh.corners_of(*t);
                let Some((pairs, r)) = triangle_pairs(a, b, c) else {
                    continue;
                };
                p.smallest.push(smallest_angle_deg(pairs));
                for q in pairs {
                    p.ext.offer(q);
                }
                p.ratios = Some(p.ratios.map_or((r, r), |(l, h)| (l.min(r), h.max(r))));
            }
            p
        })
        .collect();
    let mut ext = Extremes::EMPTY;
    let mut ratios: Option<(f64, f64)> = None;
    let (mut ok, mut sum) = (0usize, 0.0f64);
    for p in &parts {
        ext.merge(p.ext);
        if let Some((l, h)) = p.ratios {
            ratios = Some(ratios.map_or((l, h), |(a, b)| (a.min(l), b.max(h))));
        }
        ok += p.smallest.len();
        for &s in &p.smallest {
            sum += s;
        }
    }
    Ok(TriangleAngles {
        triangles: tris.len(),
        degenerate: tris.len() - ok,
        min_angle_deg: (ok > 0).then_some(ext.min),
        max_angle_deg: (ok > 0).then_some(ext.max),
        mean_min_angle_deg: (ok > 0).then(|| sum / ok as f64),
        min_edge_ratio: ratios.map(|x| x.0),
        max_edge_ratio: ratios.map(|x| x.1),
        histogram: Histogram::empty(0.0, 180.0, 180.0),
    })
}

/// x |x|: monotone in x, so the signed squares of two cosines order them as the
/// cosines do (and the angles the other way).
#[inline(always)]
fn signed_square(x: f64) -> f64 {
    x * x.abs()
}

/// The margin of [`triangle_extremes`]'s first test, which needs no square root. An
/// angle with edge vectors u, v and x = u·v is skipped when x |x| lies below
/// (cos m |cos m| − margin) |u|² |v|² and above (cos M |cos M| + margin) |u|² |v|²,
/// where m and M are the current extremes (m as [`Extremes`] keeps it: the cosine of
/// the atan2 it came from). Each computed quantity is within a few units in the last
/// place (10⁻¹⁵ relative) of the exact one, and the signed square of the cosine is
/// within 10⁻¹⁵ of the one atan2 of the computed pair gives, so a skipped angle's
/// pair is strictly inside the range and [`Extremes::offer`] would change nothing.
/// Likewise the triangle is proven not flat (the test of [`triangle_is_degenerate`],
/// y > DEGENERATE_REL · l²max with y = |u × v|) when y² exceeds (DEGENERATE_REL ·
/// l²max)² (1 + margin), with DEGENERATE_REL · l²max above 10⁻¹⁵⁰ (its square
/// a normal number). Near 90° the signed square is flat, so the margin there is
/// √margin ≈ 3 · 10⁻⁴ rad in angle: only fewer skips, never a wrong one.
const INSIDE_MARGIN: f64 = 1e-7;

/// The smallest and largest triangle angle, the same values as [`triangle_ranges`]
/// (bit for bit), and the number of degenerate triangles; without the mean smallest
/// angle and the edge ratios (`None`: the report's `--metrics fast`, which prints only
/// the range). Per triangle: the three edge vectors, one cross product (its norm is
/// the degeneracy test's doubled area, and the sine part of every angle's atan2 pair
/// up to rounding) and three dot products; an angle's exact pair ([`angle_pair`]) and
/// its atan2 are computed only when the approximate pair may beat an extreme
/// ([`Extremes`], with a margin covering the difference: see below). No atan2 for the
/// others, and no per-triangle smallest angle.
pub fn triangle_extremes(mesh: &TriMesh) -> Result<TriangleAngles> {
    super::check_trimesh(mesh)?;
    const CHUNK: usize = 8192;
    let tris = &mesh.triangles;
    let parts: Vec<(Extremes, usize)> = tris
        .par_chunks(CHUNK)
        .map(|ch| {
            let mut ext = Extremes::EMPTY;
            let mut ok = 0usize;
            for t in ch {
                if TriMesh::repeats_vertex(*t) {
                    continue;
                }
                let [a, b, c] = mesh.corners_of(*t);
                let (ab, bc, ca) = (sub(b, a), sub(c, b), sub(a, c));
                let (lab, lbc, lca) = (dot(ab, ab), dot(bc, bc), dot(ca, ca));
                let l2max = lab.max(lbc).max(lca);
                let xs = [-dot(ca, ab), -dot(ab, bc), -dot(bc, ca)];
                // First, without a square root: a triangle proven not flat whose three
                // angles are proven strictly inside the current range changes nothing
                // (see `INSIDE_MARGIN`).
                let cr = cross(ca, ab);
                let dl = DEGENERATE_REL * l2max;
                if dl > 1e-150 && dot(cr, cr) > dl * dl * (1.0 + INSIDE_MARGIN) {
                    let (qmin, qmax) = (
                        signed_square(ext.min_dir[0]) - INSIDE_MARGIN,
                        signed_square(ext.max_dir[0]) + INSIDE_MARGIN,
                    );
                    let inside = |x: f64, p: f64| {
                        let q = signed_square(x);
                        q < qmin * p && q > qmax * p
                    };
                    if inside(xs[0], lca * lab)
                        && inside(xs[1], lab * lbc)
                        && inside(xs[2], lbc * lca)
                    {
                        ok += 1;
                        continue;
                    }
                }
                // The pair of the angle at a, exactly as `triangle_pairs` (and
                // `triangle_is_degenerate`) compute it.
                let y = norm(cr);
                if !(y > dl) {
                    continue;
                }
                ok += 1;
                // The exact pairs of the angles at b and c have |u×v| of their own edge
                // vectors for y: the same doubled area, computed from other products.
                // Each computed norm is within a few ulps of |u| |v| ≤ l2max of the
                // true doubled area, so |y − y_exact| ≤ 1e-14 l2max (generously);
                // adding twice that to Extremes' margin (and doubling its relative
                // part) keeps every skip proven for the exact pair: its test value is
                // then still above 1e-9 (|x| + |y|).
                let slack = 2e-14 * l2max;
                for (k, &x) in xs.iter().enumerate() {
                    let r = 2e-9 * (y + x.abs()) + slack;
                    let above_min = ext.min_dir[0] * y - ext.min_dir[1] * x > r;
                    let below_max = ext.max_dir[0] * y - ext.max_dir[1] * x < -r;
                    if above_min && below_max {
                        continue;
                    }
                    ext.offer(match k {
                        0 => (y, x),
                        1 => (norm(cross(ab, bc)), x),
                        _ => (norm(cross(bc, ca)), x),
                    });
                }
            }
            (ext, ok)
        })
        .collect();
    let mut ext = Extremes::EMPTY;
    let mut ok = 0;
    for (e, n) in parts {
        ext.merge(e);
        ok += n;
    }
    Ok(TriangleAngles {
        triangles: tris.len(),
        degenerate: tris.len() - ok,
        min_angle_deg: (ok > 0).then_some(ext.min),
        max_angle_deg: (ok > 0).then_some(ext.max),
        mean_min_angle_deg: None,
        min_edge_ratio: None,
        max_edge_ratio: None,
        histogram: Histogram::empty(0.0, 180.0, 180.0),
    })
}

/// Summary of the triangle angles, with a histogram of `bin_width` degrees.
pub fn triangle_summary(mesh: &TriMesh, bin_width: f64) -> Result<TriangleAngles> {
    let per = per_triangle(mesh)?;
    // Ranges and histogram in one parallel pass: min, max and integer counts are exact
    // reductions, so the result does not depend on the split.
    let lohi =
        |a: Option<(f64, f64)>, v: f64| Some(a.map_or((v, v), |(l, h)| (l.min(v), h.max(v))));
    let both = |a: Option<(f64, f64)>, b: Option<(f64, f64)>| match (a, b) {
        (Some((l, h)), Some((m, k))) => Some((l.min(m), h.max(k))),
        (x, None) | (None, x) => x,
    };
    type Acc = (Option<(f64, f64)>, Option<(f64, f64)>, Histogram, usize);
    let none = || -> Acc { (None, None, Histogram::empty(0.0, 180.0, bin_width), 0) };
    let (angles, ratios, histogram, ok) = per
        .par_iter()
        .enumerate()
        .fold(none, |mut acc, (i, a)| {
            if let Some(a) = a {
                for &x in a {
                    acc.0 = lohi(acc.0, x);
                    acc.2.add(x);
                }
                acc.1 = lohi(acc.1, edge_ratio(&mesh.corners(i)));
                acc.3 += 1;
            }
            acc
        })
        .reduce(none, |a, b| {
            (both(a.0, b.0), both(a.1, b.1), a.2.merge(&b.2), a.3 + b.3)
        });
    // The mean in mesh order (a fixed summation order).
    let mean_min_angle_deg = (ok > 0).then(|| {
        per.iter()
            .flatten()
            .map(|a| a[0].min(a[1]).min(a[2]))
            .sum::<f64>()
            / ok as f64
    });
    Ok(TriangleAngles {
        triangles: mesh.triangles.len(),
        degenerate: mesh.triangles.len() - ok,
        min_angle_deg: angles.map(|x| x.0),
        max_angle_deg: angles.map(|x| x.1),
        mean_min_angle_deg,
        min_edge_ratio: ratios.map(|x| x.0),
        max_edge_ratio: ratios.map(|x| x.1),
        histogram,
    })
}

/// The six edges of a tetrahedron as corner pairs; edge `e` is opposite edge `5 - e`:
/// the `(i, j)` of [`geom::TET_EDGES_WITH_OPPOSITE`].
pub const TET_EDGES: [[usize; 2]; 6] = {
    let e = geom::TET_EDGES_WITH_OPPOSITE;
    let mut out = [[0; 2]; 6];
    let mut k = 0;
    while k < 6 {
        out[k] = [e[k].0, e[k].1];
        k += 1;
    }
    out
};

/// Six times the signed volume: positive for the mesh's orientation convention.
pub fn signed_volume6(p: &[[f64; 3]; 4]) -> f64 {
    dot(sub(p[1], p[0]), cross(sub(p[2], p[0]), sub(p[3], p[0])))
}

/// Outward (away from corner k) normal of the face opposite corner k, unnormalised,
/// whatever the tetrahedron's orientation.
fn outward_normal(p: &[[f64; 3]; 4], k: usize) -> [f64; 3] {
    let f: Vec<usize> = (0..4).filter(|&i| i != k).collect();
    let n = cross(sub(p[f[1]], p[f[0]]), sub(p[f[2]], p[f[0]]));
    if dot(n, sub(p[k], p[f[0]])) > 0.0 {
        geom::scale(n, -1.0)
    } else {
        n
    }
}

/// The six interior dihedral angles in degrees, at the edges of [`TET_EDGES`].
///
/// The dihedral angle at edge ij is 180° minus the angle between the outward normals of
/// the two faces containing ij (the faces opposite the other two corners k, l); the angle
/// between normals is taken in atan2 form. Orientation-independent: an inverted
/// tetrahedron has the same angles as its mirror image.
pub fn dihedral_angles(p: &[[f64; 3]; 4]) -> [f64; 6] {
    let n: [[f64; 3]; 4] = [0, 1, 2, 3].map(|k| outward_normal(p, k));
    geom::TET_EDGES_WITH_OPPOSITE.map(|(_, _, k, l)| {
        let between = norm(cross(n[k], n[l])).atan2(dot(n[k], n[l])).to_degrees();
        180.0 - between
    })
}

/// The twelve face (plane) angles in degrees: three per face, faces opposite corners 0..3.
pub fn face_angles(p: &[[f64; 3]; 4]) -> [f64; 12] {
    let mut out = [0.0; 12];
    for k in 0..4 {
        let f: Vec<usize> = (0..4).filter(|&i| i != k).collect();
        let a = triangle_angles(p[f[0]], p[f[1]], p[f[2]]);
        out[3 * k..3 * k + 3].copy_from_slice(&a);
    }
    out
}

/// Radius ratio 3 r_in / R_circ: 1 for the regular tetrahedron, 0 for a flat one.
pub fn radius_ratio(p: &[[f64; 3]; 4]) -> f64 {
    let v6 = signed_volume6(p).abs();
    let area2: f64 = (0..4).map(|k| norm(outward_normal(p, k))).sum();
    if !(v6 > 0.0) || !(area2 > 0.0) {
        return 0.0;
    }
    // r_in = 3V / A with V = v6 / 6 and A = area2 / 2 (|n_k| is twice a face's area).
    // R_circ = |a|²(b×c) + |b|²(c×a) + |c|²(a×b) over 2 a·(b×c), with a, b, c the edges at p0.
    let r_in = v6 / area2;
    let a = sub(p[1], p[0]);
    let b = sub(p[2], p[0]);
    let c = sub(p[3], p[0]);
    let num = geom::add(
        geom::add(
            geom::scale(cross(b, c), dot(a, a)),
            geom::scale(cross(c, a), dot(b, b)),
        ),
        geom::scale(cross(a, b), dot(c, c)),
    );
    let r_circ = norm(num) / (2.0 * signed_volume6(p).abs());
    (3.0 * r_in / r_circ).min(1.0)
}

/// Is the tetrahedron numerically flat: repeated corner, or |6V| below
/// [`DEGENERATE_REL`] times its longest edge cubed?
pub fn tet_is_degenerate(p: &[[f64; 3]; 4]) -> bool {
    let l = TET_EDGES
        .iter()
        .map(|&[i, j]| geom::dist(p[i], p[j]))
        .fold(0.0, f64::max);
    !(signed_volume6(p).abs() > DEGENERATE_REL * l * l * l)
}

/// Shape summary of a tetrahedral mesh.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TetAngles {
    pub tets: usize,
    /// Tetrahedra with negative signed volume (against the mesh convention); their
    /// angles are still measured.
    pub inverted: usize,
    /// Flat or index-repeating tetrahedra, left out of the ranges.
    pub degenerate: usize,
    /// Serialised in place (flattened): the JSON fields are the range fields.
    #[serde(flatten)]
    pub ranges: TetRanges,
    /// Histogram of dihedral angles, bins of `bin_width` degrees over [0, 180].
    pub dihedral_histogram: Histogram,
}

/// The ranges of the shape measures over the non-degenerate tetrahedra of a mesh
/// (`None` when there is none), as [`TetAngles`] and [`super::TetStats`] report them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TetRanges {
    pub min_dihedral_deg: Option<f64>,
    pub max_dihedral_deg: Option<f64>,
    pub min_face_angle_deg: Option<f64>,
    pub max_face_angle_deg: Option<f64>,
    pub min_edge_ratio: Option<f64>,
    pub max_edge_ratio: Option<f64>,
    pub min_radius_ratio: Option<f64>,
}

/// Per-tetrahedron measures; `None` for degenerate tetrahedra.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TetShape {
    pub volume6: f64,
    pub dihedral: [f64; 6],
    pub face: [f64; 12],
    pub edge_ratio: f64,
    pub radius_ratio: f64,
}

pub fn tet_shape(p: &[[f64; 3]; 4]) -> TetShape {
    TetShape {
        volume6: signed_volume6(p),
        dihedral: dihedral_angles(p),
        face: face_angles(p),
        edge_ratio: edge_ratio(p),
        radius_ratio: radius_ratio(p),
    }
}

pub fn tet_summary(mesh: &TetMesh, bin_width: f64) -> Result<TetAngles> {
    super::check_tetmesh(mesh)?;
    let per: Vec<(f64, Option<TetShape>)> = mesh
        .tets
        .par_iter()
        .map(|t| {
            let p = t.map(|i| mesh.vertices[i as usize]);
            let v6 = signed_volume6(&p);
            let repeated = (0..4).any(|i| (i + 1..4).any(|j| t[i] == t[j]));
            if repeated || tet_is_degenerate(&p) {
                (v6, None)
            } else {
                (v6, Some(tet_shape(&p)))
            }
        })
        .collect();
    let ok: Vec<&TetShape> = per.iter().filter_map(|(_, s)| s.as_ref()).collect();
    let (min_dihedral_deg, max_dihedral_deg) =
        min_max(ok.iter().flat_map(|s| s.dihedral.iter().copied()));
    let (min_face_angle_deg, max_face_angle_deg) =
        min_max(ok.iter().flat_map(|s| s.face.iter().copied()));
    let (min_edge_ratio, max_edge_ratio) = min_max(ok.iter().map(|s| s.edge_ratio));
    let (min_radius_ratio, _) = min_max(ok.iter().map(|s| s.radius_ratio));
    Ok(TetAngles {
        tets: mesh.tets.len(),
        inverted: per.iter().filter(|(v, _)| *v < 0.0).count(),
        degenerate: per.iter().filter(|(_, s)| s.is_none()).count(),
        ranges: TetRanges {
            min_dihedral_deg,
            max_dihedral_deg,
            min_face_angle_deg,
            max_face_angle_deg,
            min_edge_ratio,
            max_edge_ratio,
            min_radius_ratio,
        },
        dihedral_histogram: Histogram::new(
            0.0,
            180.0,
            bin_width,
            ok.iter().flat_map(|s| s.dihedral.iter().copied()),
        ),
    })
}

/// The three angles (degrees) of every triangle, degenerate ones included (their
/// angles are whatever the float computation gives: 0, 180 or NaN).
pub fn all_angles(m: &TriMesh) -> Vec<f64> {
    m.triangles
        .par_iter()
        .flat_map_iter(|t| {
            let [a, b, c] = t.map(|i| m.vertices[i as usize]);
            triangle_angles(a, b, c)
        })
        .collect()
}

/// What a mesher that reports its own angle range (GradNormal, MidNormal: Table 1's
/// smallest and largest angle over every triangle, [`angle_range_all`]) computes once
/// for itself and for the report: `--metrics fast`'s [`triangle_extremes`], and the
/// range over every triangle. With no degenerate triangle the two ranges are the same
/// values, bit for bit (both are atan2 of the same pairs: [`angle_pair`]'s at each
/// corner, whose cross product and dot product differ from `triangle_extremes`' by a
/// sign only, which rounding keeps exact), so the second pass is made only when some
/// triangle is degenerate. The extremes are `None` for a mesh that `triangle_extremes`
/// refuses (a non-finite coordinate or an index out of range: the report then says so).
pub fn extremes_and_range_all(m: &TriMesh) -> (Option<TriangleAngles>, (f64, f64)) {
    let Ok(ext) = triangle_extremes(m) else {
        return (None, angle_range_all(m));
    };
    let all = match (ext.degenerate, ext.min_angle_deg, ext.max_angle_deg) {
        (0, Some(lo), Some(hi)) => (lo, hi),
        _ => angle_range_all(m),
    };
    (Some(ext), all)
}

/// Smallest and largest angle (degrees) over every triangle, degenerate ones included
/// (the GradNormal paper's Table 1 measures all triangles); (NaN, NaN) for an empty mesh.
/// [`triangle_summary`] leaves degenerate triangles out instead. The angles of
/// [`triangle_angles`], with atan2 only for an angle that may beat the current
/// extremes ([`Extremes`]): the same two values, bit for bit.
pub fn angle_range_all(m: &TriMesh) -> (f64, f64) {
    if m.triangles.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let e = m
        .triangles
        .par_iter()
        .with_min_len(4096)
        .fold(
            || Extremes::EMPTY,
            |mut e, t| {
                let [a, b, c] = t.map(|i| m.vertices[i as usize]);
                // The pairs of `triangle_angles`' three `angle_deg`.
                e.offer(angle_pair(c, a, b));
                e.offer(angle_pair(a, b, c));
                e.offer(angle_pair(b, c, a));
                e
            },
        )
        .reduce(
            || Extremes::EMPTY,
            |mut x, y| {
                x.merge(y);
                x
            },
        );
    (e.min, e.max)
}
