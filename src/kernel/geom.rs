//! Axis-aligned boxes and small vector helpers shared by every algorithm.
use crate::error::{Error, Result};
use inari::Interval;
use serde::{Deserialize, Serialize};

/// A closed axis-aligned box `[min, max]` in R³. For curves the z-range is `[0, 0]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Aabb {
    /// A box from its corners; rejects NaN, infinite or inverted ranges.
    pub fn new(min: [f64; 3], max: [f64; 3]) -> Result<Self> {
        for k in 0..3 {
            if !min[k].is_finite() || !max[k].is_finite() {
                return Err(Error::Domain(format!(
                    "axis {} range [{}, {}] is not finite",
                    ["x", "y", "z"][k],
                    min[k],
                    max[k]
                )));
            }
            if min[k] > max[k] {
                return Err(Error::Domain(format!(
                    "axis {} range [{}, {}] is inverted",
                    ["x", "y", "z"][k],
                    min[k],
                    max[k]
                )));
            }
        }
        Ok(Aabb { min, max })
    }
    /// The cube `[-h, h]³`.
    pub fn cube(h: f64) -> Self {
        Aabb {
            min: [-h; 3],
            max: [h; 3],
        }
    }
    /// A planar box (z = 0) for curves.
    pub fn rect(min: [f64; 2], max: [f64; 2]) -> Self {
        Aabb {
            min: [min[0], min[1], 0.0],
            max: [max[0], max[1], 0.0],
        }
    }
    pub fn size(&self) -> [f64; 3] {
        [
            self.max[0] - self.min[0],
            self.max[1] - self.min[1],
            self.max[2] - self.min[2],
        ]
    }
    pub fn center(&self) -> [f64; 3] {
        [
            0.5 * (self.min[0] + self.max[0]),
            0.5 * (self.min[1] + self.max[1]),
            0.5 * (self.min[2] + self.max[2]),
        ]
    }
    pub fn diagonal(&self) -> f64 {
        norm(self.size())
    }
    pub fn contains(&self, p: [f64; 3]) -> bool {
        (0..3).all(|k| p[k] >= self.min[k] && p[k] <= self.max[k])
    }
    /// The box as three intervals, for interval evaluation. Exact: the
    /// endpoints are floats already.
    pub fn intervals(&self) -> [Interval; 3] {
        [0, 1, 2]
            .map(|k| Interval::try_from((self.min[k], self.max[k])).unwrap_or(Interval::ENTIRE))
    }
    /// The box grown by `d` on every side (in every axis with nonzero extent).
    pub fn inflate(&self, d: f64) -> Self {
        let mut b = *self;
        for k in 0..3 {
            if self.max[k] > self.min[k] {
                b.min[k] -= d;
                b.max[k] += d;
            }
        }
        b
    }
    /// The union of two boxes.
    pub fn union(&self, o: &Aabb) -> Self {
        let mut b = *self;
        for k in 0..3 {
            b.min[k] = b.min[k].min(o.min[k]);
            b.max[k] = b.max[k].max(o.max[k]);
        }
        b
    }
    /// The smallest box holding the points, or `None` for no points.
    pub fn of_points(pts: &[[f64; 3]]) -> Option<Self> {
        let mut it = pts.iter();
        let p = *it.next()?;
        let mut b = Aabb { min: p, max: p };
        for q in it {
            for k in 0..3 {
                b.min[k] = b.min[k].min(q[k]);
                b.max[k] = b.max[k].max(q[k]);
            }
        }
        Some(b)
    }
    /// [`Aabb::of_points`] in parallel chunks (the same box: a minimum and a maximum do
    /// not depend on the order), for the vertices of a large mesh.
    pub fn of_points_par(pts: &[[f64; 3]]) -> Option<Self> {
        use rayon::prelude::*;
        pts.par_chunks(8192)
            .filter_map(Aabb::of_points)
            .reduce_with(|a, b| a.union(&b))
    }
    /// The largest coordinate in size of any point of the box (that of a corner): the
    /// scale of the coordinates, for margins relative to them.
    pub fn max_abs(&self) -> f64 {
        self.min
            .iter()
            .chain(&self.max)
            .fold(0.0f64, |m, x| m.max(x.abs()))
    }
}

#[inline]
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
#[inline]
pub fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}
#[inline]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
#[inline]
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
#[inline]
pub fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm(sub(a, b))
}
#[inline]
pub fn lerp(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [
        a[0] + t * (b[0] - a[0]),
        a[1] + t * (b[1] - a[1]),
        a[2] + t * (b[2] - a[2]),
    ]
}
/// Unit vector, or the zero vector when `a` is zero.
#[inline]
pub fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    if n > 0.0 {
        scale(a, 1.0 / n)
    } else {
        a
    }
}
/// The angle at `b` in the triangle `a b c`, in degrees.
pub fn angle_deg(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let u = sub(a, b);
    let v = sub(c, b);
    // atan2 of |u×v| and u·v is accurate for angles near 0 and 180 degrees.
    norm(cross(u, v)).atan2(dot(u, v)).to_degrees()
}

/// The six edges `(i, j)` of a tetrahedron with the opposite edge `(k, l)`: the dihedral
/// angle at edge ij is the angle between faces ijk and ijl.
pub const TET_EDGES_WITH_OPPOSITE: [(usize, usize, usize, usize); 6] = [
    (0, 1, 2, 3),
    (0, 2, 1, 3),
    (0, 3, 1, 2),
    (1, 2, 0, 3),
    (1, 3, 0, 2),
    (2, 3, 0, 1),
];

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The parallel box is the serial one, and no point of it is larger in size
        /// than `max_abs`, which a corner reaches.
        #[test]
        fn parallel_box_and_scale(
            pts in proptest::collection::vec(
                proptest::array::uniform3(-1e6f64..1e6),
                0..20_000,
            ),
        ) {
            let b = Aabb::of_points(&pts);
            prop_assert_eq!(Aabb::of_points_par(&pts), b);
            if let Some(b) = b {
                let m = b.max_abs();
                prop_assert!(pts.iter().flatten().all(|x| x.abs() <= m));
                prop_assert!(b.min.iter().chain(&b.max).any(|x| x.abs() == m));
            }
        }
    }
}
