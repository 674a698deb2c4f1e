//! The embedding signature of a planar straight-line graph: a canonical string of its
//! components, the degrees ≠ 2 of their vertices, their faces with dual degrees, and
//! the nesting of components in faces. Two curve meshes with different signatures are
//! not isotopic; the lemniscate and the limaçon have the same abstract graph (one
//! vertex of degree 4, two loops) but different signatures (`C[4]{O2 b1 b1}` and
//! `C[4]{O1 b1 b2}`).
//!
//! Format, per component: `C` (or `F` for the component holding the domain frame),
//! then `[d1,d2,…]` the sorted degrees ≠ 2 of its vertices (an isolated vertex is
//! `0`; frame vertices are not listed), then `{…}` its faces: `O` (its outer face) or
//! `b` (a bounded face) followed by the dual degree (the number of distinct faces of
//! the same component across its edges), a bounded face followed by `[…]` with the
//! components nested in it. Components and faces are sorted; siblings are joined by
//! ` | `. When some vertex lies on the boundary of the domain box (an unbounded curve
//! clipped), the box boundary is added as a frame standing for the circle at infinity.
//!
//! Predicates (the rotation order at a vertex, point in face) are exact on the float
//! coordinates (`robust`); the signature is that of the PSLG as drawn. It is an
//! invariant, not a complete classification (the rotation system is used to find the
//! faces but is not itself written out).
use crate::error::{Error, Result};
use crate::kernel::geom::Aabb;
use crate::kernel::predicates::orient2d;
use crate::mesh::Curve2;
use std::cmp::Ordering;
use std::collections::{BTreeMap, BTreeSet};

/// Relative tolerance for "on the box boundary".
const BOUNDARY_TOL: f64 = 1e-9;

struct Graph {
    pts: Vec<[f64; 2]>,
    /// Outgoing half-edges per vertex, sorted counter-clockwise: target vertices.
    rot: Vec<Vec<usize>>,
    frame: Vec<bool>,
    has_frame: bool,
}

/// Upper half (angle in [0, π)) or lower.
fn half(a: [f64; 2], b: [f64; 2]) -> u8 {
    if b[1] > a[1] || (b[1] == a[1] && b[0] > a[0]) {
        0
    } else {
        1
    }
}

fn ccw_cmp(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Ordering {
    let (hb, hc) = (half(a, b), half(a, c));
    if hb != hc {
        return hb.cmp(&hc);
    }
    let o = orient2d(a, b, c);
    if o > 0.0 {
        Ordering::Less
    } else if o < 0.0 {
        Ordering::Greater
    } else {
        Ordering::Equal
    }
}

fn build(c: &Curve2, frame_box: Option<&Aabb>) -> Result<Graph> {
    let mut pts = c.vertices.clone();
    for p in &pts {
        if !p[0].is_finite() || !p[1].is_finite() {
            return Err(Error::Param(
                "embedding signature: a vertex is not finite".into(),
            ));
        }
    }
    let mut edges: BTreeSet<(usize, usize)> = BTreeSet::new();
    for s in &c.segments {
        let (a, b) = (s[0] as usize, s[1] as usize);
        if a >= pts.len() || b >= pts.len() {
            return Err(Error::Param(
                "embedding signature: a segment index is out of range".into(),
            ));
        }
        if a != b && pts[a] != pts[b] {
            edges.insert((a.min(b), a.max(b)));
        }
    }
    let mut frame = vec![false; pts.len()];
    let mut has_frame = false;
    if let Some(bx) = frame_box {
        let (x0, y0, x1, y1) = (bx.min[0], bx.min[1], bx.max[0], bx.max[1]);
        let tol = BOUNDARY_TOL * (x1 - x0).abs().max(y1 - y0).max(1.0);
        // Perimeter parameter, counter-clockwise from the lower-left corner.
        let (w, h) = (x1 - x0, y1 - y0);
        let param = |p: [f64; 2]| -> Option<f64> {
            if (p[1] - y0).abs() <= tol {
                Some(p[0] - x0)
            } else if (p[0] - x1).abs() <= tol {
                Some(w + p[1] - y0)
            } else if (p[1] - y1).abs() <= tol {
                Some(w + h + x1 - p[0])
            } else if (p[0] - x0).abs() <= tol {
                Some(2.0 * w + h + y1 - p[1])
            } else {
                None
            }
        };
        let mut on: Vec<(f64, usize)> = Vec::new();
        let used: BTreeSet<usize> = edges.iter().flat_map(|&(a, b)| [a, b]).collect();
        for &i in &used {
            if let Some(t) = param(pts[i]) {
                on.push((t, i));
            }
        }
        if !on.is_empty() {
            has_frame = true;
            for (k, corner) in [[x0, y0], [x1, y0], [x1, y1], [x0, y1]].iter().enumerate() {
                if on.iter().any(|&(_, i)| pts[i] == *corner) {
                    continue;
                }
                let t = [0.0, w, w + h, 2.0 * w + h][k];
                pts.push(*corner);
                frame.push(false);
                on.push((t, pts.len() - 1));
            }
            on.sort_by(|a, b| a.0.total_cmp(&b.0));
            for &(_, i) in &on {
                frame[i] = true;
            }
            for k in 0..on.len() {
                let (a, b) = (on[k].1, on[(k + 1) % on.len()].1);
                if a != b {
                    edges.insert((a.min(b), a.max(b)));
                }
            }
        }
    }
    let mut rot = vec![Vec::new(); pts.len()];
    for &(a, b) in &edges {
        rot[a].push(b);
        rot[b].push(a);
    }
    for (v, r) in rot.iter_mut().enumerate() {
        let pv = pts[v];
        r.sort_by(|&b, &c| ccw_cmp(pv, pts[b], pts[c]));
    }
    Ok(Graph {
        pts,
        rot,
        frame,
        has_frame,
    })
}

/// Winding number of the closed polygon `cyc` around `p` (exact orientation tests).
fn winding(pts: &[[f64; 2]], cyc: &[usize], p: [f64; 2]) -> i64 {
    let mut w = 0i64;
    for k in 0..cyc.len() {
        let (a, b) = (pts[cyc[k]], pts[cyc[(k + 1) % cyc.len()]]);
        if a[1] <= p[1] {
            if b[1] > p[1] && orient2d(a, b, p) > 0.0 {
                w += 1;
            }
        } else if b[1] <= p[1] && orient2d(a, b, p) < 0.0 {
            w -= 1;
        }
    }
    w
}

/// The embedding signature of `c`; `frame_box`: the domain, whose boundary closes
/// curves that leave it.
pub fn embedding_signature(c: &Curve2, frame_box: Option<&Aabb>) -> Result<String> {
    let g = build(c, frame_box)?;
    let n = g.pts.len();
    // Components (every input vertex counts: an isolated vertex is a component).
    let mut comp = vec![usize::MAX; n];
    let mut ncomp = 0;
    for s in 0..n {
        if comp[s] != usize::MAX {
            continue;
        }
        let mut st = vec![s];
        comp[s] = ncomp;
        while let Some(v) = st.pop() {
            for &w in &g.rot[v] {
                if comp[w] == usize::MAX {
                    comp[w] = ncomp;
                    st.push(w);
                }
            }
        }
        ncomp += 1;
    }
    // Faces: trace half-edges (v → w); the next one leaves w just clockwise of (w → v).
    let mut he_face: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    let mut faces: Vec<Vec<usize>> = Vec::new();
    for v in 0..n {
        for &w in &g.rot[v] {
            if he_face.contains_key(&(v, w)) {
                continue;
            }
            let fid = faces.len();
            let mut cyc = Vec::new();
            let (mut a, mut b) = (v, w);
            let mut guard = 0usize;
            while !he_face.contains_key(&(a, b)) {
                guard += 1;
                if guard > 4 * n + 8 * c.segments.len() + 16 {
                    return Err(Error::Param(
                        "embedding signature: face tracing did not close".into(),
                    ));
                }
                he_face.insert((a, b), fid);
                cyc.push(a);
                let r = &g.rot[b];
                let i = r.iter().position(|&x| x == a).expect("twin");
                let nx = r[(i + r.len() - 1) % r.len()];
                (a, b) = (b, nx);
            }
            faces.push(cyc);
        }
    }
    let area = |cyc: &[usize]| -> f64 {
        let mut s = 0.0;
        for k in 0..cyc.len() {
            let (a, b) = (g.pts[cyc[k]], g.pts[cyc[(k + 1) % cyc.len()]]);
            s += a[0] * b[1] - a[1] * b[0];
        }
        s / 2.0
    };
    let fcomp: Vec<usize> = faces.iter().map(|cy| comp[cy[0]]).collect();
    let fa: Vec<f64> = faces.iter().map(|cy| area(cy)).collect();
    // Outer face per component: the smallest signed area (clockwise).
    let mut outer = vec![usize::MAX; ncomp];
    for (f, &k) in fcomp.iter().enumerate() {
        if outer[k] == usize::MAX || fa[f] < fa[outer[k]] {
            outer[k] = f;
        }
    }
    // Dual degrees.
    let mut adj: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); faces.len()];
    for (&(a, b), &f) in &he_face {
        let t = he_face[&(b, a)];
        if t != f {
            adj[f].insert(t);
        }
    }
    // Nesting: the innermost bounded face of another component containing a vertex.
    let mut parent: Vec<Option<usize>> = vec![None; ncomp];
    let rep: Vec<usize> = (0..ncomp)
        .map(|k| (0..n).find(|&v| comp[v] == k).unwrap())
        .collect();
    for k in 0..ncomp {
        let p = g.pts[rep[k]];
        let mut best: Option<usize> = None;
        for f in 0..faces.len() {
            if fcomp[f] == k || outer[fcomp[f]] == f {
                continue;
            }
            if winding(&g.pts, &faces[f], p) != 0 && best.is_none_or(|b| fa[f] < fa[b]) {
                best = Some(f);
            }
        }
        parent[k] = best;
    }
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); faces.len()];
    let mut top = Vec::new();
    for k in 0..ncomp {
        match parent[k] {
            Some(f) => children[f].push(k),
            None => top.push(k),
        }
    }
    fn comp_str(
        k: usize,
        g: &Graph,
        comp: &[usize],
        faces: &[Vec<usize>],
        fcomp: &[usize],
        outer: &[usize],
        adj: &[BTreeSet<usize>],
        children: &[Vec<usize>],
        depth: usize,
    ) -> String {
        let n = g.pts.len();
        let is_frame = g.has_frame && (0..n).any(|v| comp[v] == k && g.frame[v]);
        let mut degs: Vec<usize> = (0..n)
            .filter(|&v| comp[v] == k && !g.frame[v] && g.rot[v].len() != 2)
            .map(|v| g.rot[v].len())
            .collect();
        degs.sort();
        let mut fs: Vec<String> = Vec::new();
        let mut o = String::new();
        for f in 0..faces.len() {
            if fcomp[f] != k {
                continue;
            }
            if outer[k] == f {
                o = format!("O{}", adj[f].len());
                continue;
            }
            let mut s = format!("b{}", adj[f].len());
            if !children[f].is_empty() && depth < 64 {
                let mut ch: Vec<String> = children[f]
                    .iter()
                    .map(|&c| comp_str(c, g, comp, faces, fcomp, outer, adj, children, depth + 1))
                    .collect();
                ch.sort();
                s += &format!("[{}]", ch.join(" | "));
            }
            fs.push(s);
        }
        fs.sort();
        if !o.is_empty() {
            fs.insert(0, o);
        }
        format!(
            "{}[{}]{{{}}}",
            if is_frame { "F" } else { "C" },
            degs.iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join(","),
            fs.join(" ")
        )
    }
    let mut ts: Vec<String> = top
        .iter()
        .map(|&k| comp_str(k, &g, &comp, &faces, &fcomp, &outer, &adj, &children, 0))
        .collect();
    ts.sort();
    Ok(ts.join(" | "))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(pts: &[[f64; 2]], off: u32) -> (Vec<[f64; 2]>, Vec<[u32; 2]>) {
        let n = pts.len() as u32;
        (
            pts.to_vec(),
            (0..n).map(|i| [off + i, off + (i + 1) % n]).collect(),
        )
    }

    #[test]
    fn square_nested_and_figure_eight() {
        let (v, s) = poly(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], 0);
        let c = Curve2 {
            vertices: v.clone(),
            segments: s.clone(),
        };
        assert_eq!(embedding_signature(&c, None).unwrap(), "C[]{O1 b1}");
        // A square inside a bigger one, plus an isolated point outside both.
        let (v2, s2) = poly(&[[-1.0, -1.0], [2.0, -1.0], [2.0, 2.0], [-1.0, 2.0]], 4);
        let mut c2 = Curve2 {
            vertices: [v, v2].concat(),
            segments: [s, s2].concat(),
        };
        c2.vertices.push([5.0, 5.0]);
        assert_eq!(
            embedding_signature(&c2, None).unwrap(),
            "C[0]{} | C[]{O1 b1[C[]{O1 b1}]}"
        );
        // Figure eight (two triangles sharing a vertex) vs a triangle inside a triangle
        // touching it at a vertex (the limaçon pattern).
        let eight = Curve2 {
            vertices: vec![
                [0.0, 0.0],
                [1.0, 1.0],
                [1.0, -1.0],
                [-1.0, 1.0],
                [-1.0, -1.0],
            ],
            segments: vec![[0, 1], [1, 2], [2, 0], [0, 3], [3, 4], [4, 0]],
        };
        assert_eq!(embedding_signature(&eight, None).unwrap(), "C[4]{O2 b1 b1}");
        let lima = Curve2 {
            vertices: vec![[0.0, 0.0], [3.0, 2.0], [3.0, -2.0], [1.0, 0.5], [1.0, -0.5]],
            segments: vec![[0, 1], [1, 2], [2, 0], [0, 3], [3, 4], [4, 0]],
        };
        assert_eq!(embedding_signature(&lima, None).unwrap(), "C[4]{O1 b1 b2}");
    }

    #[test]
    fn frame_closes_a_crossing_line() {
        let bx = Aabb {
            min: [-1.0, -1.0, 0.0],
            max: [1.0, 1.0, 0.0],
        };
        let c = Curve2 {
            vertices: vec![[-1.0, 0.0], [0.0, 0.1], [1.0, 0.0]],
            segments: vec![[0, 1], [1, 2]],
        };
        assert_eq!(embedding_signature(&c, Some(&bx)).unwrap(), "F[]{O2 b2 b2}");
    }
}
