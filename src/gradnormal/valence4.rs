//! Step 3 of GradNormal (Algorithm 2, line 5; Sec. 4.3, Fig 10): remove every vertex of
//! valence four together with its four triangles and re-triangulate the quadrilateral
//! by a diagonal.
//!
//! In the Sommerville tiling a valence-four vertex is the midpoint M of a 90° lattice
//! edge AD whose four tetrahedra (the octahedron of Fig 12) all cut off A (or all cut
//! off D). Its link is the square K L K₂ L₂ of midpoints of AB, AC, AB₂, AC₂, where AB is
//! the *vertical* lattice edge (or, when D is cut off, DB₂ is vertical). The Appendix
//! analyses the triangle K L K₂, i.e. the diagonal K K₂: the one through the midpoint of
//! the vertical lattice edge. That is [`DiagonalRule::Paper`]; `Alternate` takes L L₂,
//! `Shorter` the shorter diagonal in the current (projected) positions.
use super::midnormal::split_quad;
use super::tiling::EDGE_DIRS;
use super::DiagonalRule;
use crate::kernel::geom::dist;
use std::collections::HashMap;

/// What the valence-four step did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Valence4Stats {
    /// Vertices of valence four found (closed fans of four triangles).
    pub found: usize,
    /// Vertices removed.
    pub removed: usize,
    /// Removed with the rule's fallback (shorter diagonal) because the lattice structure
    /// was not the octahedron's (only at coarse scales).
    pub fallback: usize,
    /// Skipped: a neighbouring removal had changed the fan, or both diagonals already
    /// existed as edges (removing would break manifoldness).
    pub skipped: usize,
}

/// Remove valence-four vertices. `keys` are the lattice edge keys of the vertices
/// (needed by the paper's rule), `pos` the positions used by the `Shorter` rule.
/// Returns the new triangle list; `alive[v]` is cleared for removed vertices.
pub fn remove_valence4(
    triangles: &[[u32; 3]],
    pos: &[[f64; 3]],
    keys: Option<&[u64]>,
    rule: DiagonalRule,
    alive: &mut [bool],
) -> (Vec<[u32; 3]>, Valence4Stats) {
    let n = pos.len();
    let mut deg = vec![0u32; n + 1];
    for t in triangles {
        for &v in t {
            deg[v as usize] += 1;
        }
    }
    let mut start = vec![0usize; n + 1];
    for v in 0..n {
        start[v + 1] = start[v] + deg[v] as usize;
    }
    let mut fill = start.clone();
    let mut inc = vec![0u32; start[n]];
    for (ti, t) in triangles.iter().enumerate() {
        for &v in t {
            inc[fill[v as usize]] = ti as u32;
            fill[v as usize] += 1;
        }
    }
    let mut tris: Vec<[u32; 3]> = triangles.to_vec();
    let mut dead = vec![false; tris.len()];
    let mut added: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut stats = Valence4Stats::default();
    let has_edge = |tris: &Vec<[u32; 3]>,
                    dead: &Vec<bool>,
                    added: &HashMap<u32, Vec<u32>>,
                    a: u32,
                    b: u32|
     -> bool {
        let orig = inc[start[a as usize]..start[a as usize + 1]].iter();
        let extra = added.get(&a).into_iter().flatten();
        orig.chain(extra)
            .any(|&t| !dead[t as usize] && tris[t as usize].contains(&b))
    };
    for v in 0..n {
        if deg[v] != 4 || !alive[v] {
            continue;
        }
        let star = &inc[start[v]..start[v + 1]];
        // The fan: each triangle (v, a, b) in orientation order contributes a -> b.
        let mut next = [(u32::MAX, u32::MAX); 4];
        let mut ok = true;
        for (k, &t) in star.iter().enumerate() {
            if dead[t as usize] {
                ok = false;
                break;
            }
            let tri = tris[t as usize];
            let r = tri.iter().position(|&x| x as usize == v).unwrap();
            next[k] = (tri[(r + 1) % 3], tri[(r + 2) % 3]);
        }
        if !ok {
            stats.skipped += 1;
            continue;
        }
        let mut ring = [0u32; 4];
        ring[0] = next[0].0;
        for k in 1..4 {
            match next.iter().find(|e| e.0 == ring[k - 1]) {
                Some(e) => ring[k] = e.1,
                None => ok = false,
            }
        }
        // A closed fan: the cycle returns to its start and has four distinct vertices.
        let closes = ok
            && next.iter().any(|e| e.0 == ring[3] && e.1 == ring[0])
            && (0..4).all(|x| (x + 1..4).all(|y| ring[x] != ring[y]));
        if !closes {
            continue;
        }
        stats.found += 1;
        let shorter = || -> u8 {
            let d0 = dist(pos[ring[0] as usize], pos[ring[2] as usize]);
            let d1 = dist(pos[ring[1] as usize], pos[ring[3] as usize]);
            if d0 <= d1 {
                0
            } else {
                1
            }
        };
        // Which of the two pairs (0: ring0-ring2, 1: ring1-ring3) holds the midpoint of a
        // vertical lattice edge (the paper's K K₂).
        let vertical_pair = keys.and_then(|k| {
            let vert: Vec<bool> = ring
                .iter()
                .map(|&w| EDGE_DIRS[(k[w as usize] & 7) as usize] == EDGE_DIRS[0])
                .collect();
            match (vert[0] || vert[2], vert[1] || vert[3]) {
                (true, false) => Some(0u8),
                (false, true) => Some(1u8),
                _ => None,
            }
        });
        let mut at = match (rule, vertical_pair) {
            (DiagonalRule::Paper, Some(p)) => p,
            (DiagonalRule::Alternate, Some(p)) => 1 - p,
            (DiagonalRule::Shorter, _) => shorter(),
            (_, None) => {
                stats.fallback += 1;
                shorter()
            }
        };
        let diag_exists = |at: u8| {
            has_edge(
                &tris,
                &dead,
                &added,
                ring[at as usize],
                ring[at as usize + 2],
            )
        };
        if diag_exists(at) {
            if diag_exists(1 - at) {
                stats.skipped += 1;
                continue;
            }
            at = 1 - at;
        }
        for &t in star {
            dead[t as usize] = true;
        }
        for t in split_quad(ring, at) {
            let id = tris.len() as u32;
            tris.push(t);
            dead.push(false);
            for &w in &t {
                added.entry(w).or_default().push(id);
            }
        }
        alive[v] = false;
        stats.removed += 1;
    }
    let out = tris
        .into_iter()
        .zip(dead)
        .filter(|(_, d)| !d)
        .map(|(t, _)| t)
        .collect();
    (out, stats)
}
