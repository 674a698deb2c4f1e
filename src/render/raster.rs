//! The z-buffer: orthographic projection of triangles into a pixel grid, depth test per
//! pixel, flat or Gouraud (per-vertex) Lambert shading, and a wireframe drawn in the same
//! pass from each pixel's distance to the triangle's edges (so hidden edges stay hidden).
//! This is the one part of the renderer no 2D crate provides; composition, text and
//! colour bars are SVG, rasterised by resvg / tiny-skia ([`crate::figure::output`]).

/// A triangle to draw: corners in view space (x right, y up, z towards the viewer),
/// its colour, and the per-corner normals for Gouraud shading (flat: the face normal).
#[derive(Clone, Copy, Debug)]
pub struct Tri {
    pub p: [[f64; 3]; 3],
    pub n: [[f64; 3]; 3],
    pub rgb: [u8; 3],
}

/// Pixels (RGBA8, opaque) of a rendering.
pub struct Image {
    pub w: u32,
    pub h: u32,
    pub rgba: Vec<u8>,
}

fn shade(n: [f64; 3], light: [f64; 3]) -> f64 {
    let l = (n[0] * light[0] + n[1] * light[1] + n[2] * light[2]).abs(); // two-sided
    0.35 + 0.65 * l
}

/// Render `tris` into `w × h` pixels mapping view-space `[x0, x1] × [y0, y1]`, on white;
/// `ss` samples per pixel side (supersampling), `wire` the edge width in pixels (0: none).
pub fn render(
    tris: &[Tri],
    (w, h): (u32, u32),
    (x0, x1, y0, y1): (f64, f64, f64, f64),
    ss: u32,
    wire: f64,
) -> Image {
    let (sw, sh) = ((w * ss) as usize, (h * ss) as usize);
    let mut depth = vec![f64::NEG_INFINITY; sw * sh];
    let mut col = vec![[255.0f64; 3]; sw * sh];
    let sx = sw as f64 / (x1 - x0);
    let sy = sh as f64 / (y1 - y0);
    let light = {
        let l: [f64; 3] = [-0.35, 0.45, 0.82];
        let n = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
        [l[0] / n, l[1] / n, l[2] / n]
    };
    let wire = wire * ss as f64;
    for t in tris {
        let q: Vec<[f64; 3]> =
            t.p.iter()
                .map(|p| [(p[0] - x0) * sx, (y1 - p[1]) * sy, p[2]])
                .collect();
        let area =
            (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[2][0] - q[0][0]) * (q[1][1] - q[0][1]);
        if area.abs() < 1e-12 {
            continue;
        }
        // Heights of the corners above their opposite edges, in pixels.
        let edge_len =
            |a: usize, b: usize| ((q[a][0] - q[b][0]).powi(2) + (q[a][1] - q[b][1]).powi(2)).sqrt();
        let heights = [
            area.abs() / edge_len(1, 2).max(1e-12),
            area.abs() / edge_len(2, 0).max(1e-12),
            area.abs() / edge_len(0, 1).max(1e-12),
        ];
        let inten: Vec<f64> = t.n.iter().map(|n| shade(*n, light)).collect();
        let bx0 = q
            .iter()
            .map(|p| p[0])
            .fold(f64::INFINITY, f64::min)
            .floor()
            .max(0.0) as usize;
        let bx1 = (q
            .iter()
            .map(|p| p[0])
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil() as usize)
            .min(sw);
        let by0 = q
            .iter()
            .map(|p| p[1])
            .fold(f64::INFINITY, f64::min)
            .floor()
            .max(0.0) as usize;
        let by1 = (q
            .iter()
            .map(|p| p[1])
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil() as usize)
            .min(sh);
        for py in by0..by1 {
            for px in bx0..bx1 {
                let (cx, cy) = (px as f64 + 0.5, py as f64 + 0.5);
                let e = |a: usize, b: usize| {
                    (q[b][0] - q[a][0]) * (cy - q[a][1]) - (q[b][1] - q[a][1]) * (cx - q[a][0])
                };
                let l = [e(1, 2) / area, e(2, 0) / area, e(0, 1) / area];
                if l.iter().any(|&v| v < -1e-9) {
                    continue;
                }
                let z = l[0] * q[0][2] + l[1] * q[1][2] + l[2] * q[2][2];
                let k = py * sw + px;
                if z <= depth[k] {
                    continue;
                }
                depth[k] = z;
                let s = l[0] * inten[0] + l[1] * inten[1] + l[2] * inten[2];
                let d_edge = (0..3)
                    .map(|i| l[i] * heights[i])
                    .fold(f64::INFINITY, f64::min);
                let mut c = t.rgb.map(|v| v as f64 * s);
                if wire > 0.0 && d_edge < wire {
                    c = [25.0, 25.0, 25.0];
                }
                col[k] = c;
            }
        }
    }
    // Box-filter the supersamples.
    let mut rgba = vec![255u8; (w * h * 4) as usize];
    let n = (ss * ss) as f64;
    for y in 0..h as usize {
        for x in 0..w as usize {
            let mut acc = [0.0; 3];
            for j in 0..ss as usize {
                for i in 0..ss as usize {
                    let c = col[(y * ss as usize + j) * sw + x * ss as usize + i];
                    for ch in 0..3 {
                        acc[ch] += c[ch];
                    }
                }
            }
            let o = (y * w as usize + x) * 4;
            for ch in 0..3 {
                rgba[o + ch] = (acc[ch] / n).round().clamp(0.0, 255.0) as u8;
            }
        }
    }
    Image { w, h, rgba }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn nearer_triangle_hides_the_farther() {
        let n = [[0.0, 0.0, 1.0]; 3];
        let far = Tri {
            p: [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]],
            n,
            rgb: [255, 0, 0],
        };
        let near = Tri {
            p: [[-1.0, -1.0, 1.0], [1.0, -1.0, 1.0], [0.0, 1.0, 1.0]],
            n,
            rgb: [0, 0, 255],
        };
        for order in [[far, near], [near, far]] {
            let im = render(&order, (20, 20), (-1.0, 1.0, -1.0, 1.0), 1, 0.0);
            let c = &im.rgba[(12 * 20 + 10) * 4..(12 * 20 + 10) * 4 + 3];
            assert!(c[2] > 100 && c[0] < 10, "{c:?}");
        }
    }
}
