//! Generic position: a rigid motion of the grid (the chapter's shifted grid).
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;

/// The "generic position" remedy of §1.2.3: a fixed rotation R and translation t, so that
/// no grid plane is tangent to the surface at a dyadic point. The meshers mesh
/// g(p) = f(R p + t) over the box `domain` of p-space that covers the original domain and
/// map each output vertex p back to R p + t (a rigid motion: orientation is kept).
#[derive(Clone, Copy, Debug)]
pub struct GenericMotion {
    pub rot: [[f64; 3]; 3],
    pub shift: [f64; 3],
    /// The box meshed in the moved coordinates (covers R⁻¹(domain − t)).
    pub domain: Aabb,
}

impl GenericMotion {
    /// Rotation by 0.0837 rad (about 4.8°) about the axis (1, 2, 3)/√14 (3D) or about z
    /// (2D), translation by (0.01234567, 0.02345679, 0.01357913) times the domain size:
    /// arbitrary, non-dyadic, fixed so runs are reproducible.
    pub fn new(domain: &Aabb, dim: usize) -> Self {
        let th: f64 = 0.0837;
        let (c, s) = (th.cos(), th.sin());
        let rot = if dim == 2 {
            [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
        } else {
            let n = 14f64.sqrt();
            let (x, y, z) = (1.0 / n, 2.0 / n, 3.0 / n);
            let t = 1.0 - c;
            [
                [c + x * x * t, x * y * t - z * s, x * z * t + y * s],
                [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
                [z * x * t - y * s, z * y * t + x * s, c + z * z * t],
            ]
        };
        let size = domain.size();
        let mut shift = [
            0.01234567 * size[0],
            0.02345679 * size[1],
            0.01357913 * size[2],
        ];
        if dim == 2 {
            shift[2] = 0.0;
        }
        // Cover the domain: the preimage of its corners under q = R p + t.
        let mut pts = Vec::new();
        for m in 0..8 {
            let q = [0, 1, 2].map(|k| {
                if m >> k & 1 == 0 {
                    domain.min[k]
                } else {
                    domain.max[k]
                }
            });
            let d = [0, 1, 2].map(|k| q[k] - shift[k]);
            // Rᵀ d
            pts.push([0, 1, 2].map(|j| rot[0][j] * d[0] + rot[1][j] * d[1] + rot[2][j] * d[2]));
        }
        let mut dom = Aabb::of_points(&pts).unwrap_or(*domain);
        // Grow the box unevenly: a box symmetric about R⁻¹(centre − t) would put its
        // level-1 grid corner exactly on the domain centre again.
        let ds = dom.size();
        for k in 0..3 {
            dom.min[k] -= 0.0173 * ds[k];
            dom.max[k] += 0.0411 * ds[k];
        }
        if dim == 2 {
            dom.min[2] = domain.min[2];
            dom.max[2] = domain.min[2];
        }
        GenericMotion {
            rot,
            shift,
            domain: dom,
        }
    }
    /// The moved oracle g(p) = f(R p + t).
    pub fn apply<'a>(&self, f: &'a dyn Implicit) -> crate::implicit::Transformed<'a> {
        crate::implicit::Transformed {
            inner: f,
            rot: self.rot,
            shift: self.shift,
        }
    }
    /// Map a vertex of the moved mesh back: R p + t.
    pub fn map(&self, p: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|i| {
            self.rot[i][0] * p[0] + self.rot[i][1] * p[1] + self.rot[i][2] * p[2] + self.shift[i]
        })
    }
    /// Map a box of the moved coordinates back (its bounding box).
    pub fn map_box(&self, b: &Aabb) -> Aabb {
        let mut pts = Vec::new();
        for m in 0..8 {
            let q = [0, 1, 2].map(|k| if m >> k & 1 == 0 { b.min[k] } else { b.max[k] });
            pts.push(self.map(q));
        }
        Aabb::of_points(&pts).unwrap_or(*b)
    }
}
