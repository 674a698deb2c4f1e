//! Validity check of a [`Delaunay`] triangulation, with the exact predicates and the
//! same symbolic perturbation as construction:
//!
//! * every live cell is positively oriented (exact `orient3d` > 0);
//! * neighbour codes are symmetric and neighbours share exactly the facet's 3 vertices;
//! * every interior facet is locally Delaunay: the vertex of the neighbour opposite the
//!   facet is outside the cell's (perturbed) circumsphere — by the Delaunay lemma this
//!   makes the whole triangulation Delaunay;
//! * the boundary is the far box (12 triangles) and V − E + F − T = 1 (a ball);
//! * every inserted vertex is in some cell, its incident-cell pointer is right, and no
//!   two vertices in cells have the same coordinates.
use super::predicates::{insphere_sos, orient3d};
use super::{Delaunay, NONE};
use serde::Serialize;
use std::collections::HashSet;

/// What [`check`] found. `valid` is the conjunction of all the counts being zero and
/// the topological figures being right.
#[derive(Clone, Debug, Default, Serialize, PartialEq, Eq)]
pub struct CheckReport {
    pub valid: bool,
    pub cells: usize,
    pub non_positive_cells: usize,
    pub asymmetric_neighbours: usize,
    pub non_delaunay_facets: usize,
    pub hull_facets: usize,
    pub vertices_in_cells: usize,
    pub inserted_vertices: usize,
    pub edges: usize,
    pub euler_characteristic: i64,
    pub bad_incident_cells: usize,
    pub repeated_positions: usize,
    /// The first problem met, for a human.
    pub first_problem: Option<String>,
}

fn note(r: &mut CheckReport, s: String) {
    if r.first_problem.is_none() {
        r.first_problem = Some(s);
    }
}

/// Check `t`; see the module documentation.
pub fn check(t: &Delaunay) -> CheckReport {
    let mut r = CheckReport::default();
    let mut edges: HashSet<(u32, u32)> = HashSet::new();
    let mut in_cells = vec![false; t.pts.len()];
    let mut faces2 = 0usize; // 2F = 4T + H
    for c in t.cells() {
        r.cells += 1;
        let cell = t.cells[c as usize];
        let p = cell.v.map(|v| t.pts[v as usize]);
        if cell.v.iter().any(|&v| v as usize >= t.pts.len()) {
            r.non_positive_cells += 1;
            let msg = format!("cell {c} has vertex ids {:?} out of range", cell.v);
            note(&mut r, msg);
            continue;
        }
        if orient3d(p[0], p[1], p[2], p[3]) <= 0.0 {
            r.non_positive_cells += 1;
            let msg = format!("cell {c} {:?} is not positively oriented", cell.v);
            note(&mut r, msg);
        }
        for a in 0..4 {
            in_cells[cell.v[a] as usize] = true;
            for b in a + 1..4 {
                let (x, y) = (cell.v[a].min(cell.v[b]), cell.v[a].max(cell.v[b]));
                edges.insert((x, y));
            }
        }
        faces2 += 4;
        for i in 0..4 {
            let n = cell.n[i];
            if n == NONE {
                r.hull_facets += 1;
                faces2 += 1;
                continue;
            }
            let (d, j) = (n >> 2, (n & 3) as usize);
            if !t.is_live(d) || t.cells[d as usize].n[j] != c * 4 + i as u32 {
                r.asymmetric_neighbours += 1;
                note(
                    &mut r,
                    format!("cell {c} facet {i}: neighbour code {n} does not point back"),
                );
                continue;
            }
            let other = t.cells[d as usize];
            let shared = (0..4)
                .filter(|&k| k != i)
                .all(|k| other.v.contains(&cell.v[k]))
                && !cell.v.contains(&other.v[j]);
            if !shared {
                r.asymmetric_neighbours += 1;
                note(
                    &mut r,
                    format!("cells {c} and {d} do not share facet {i}'s vertices"),
                );
                continue;
            }
            if c < d {
                let w = t.pts[other.v[j] as usize];
                if insphere_sos(p[0], p[1], p[2], p[3], w) >= 0 {
                    r.non_delaunay_facets += 1;
                    let msg = format!(
                        "facet {i} of cell {c}: vertex {} of cell {d} is inside its circumsphere",
                        other.v[j]
                    );
                    note(&mut r, msg);
                }
            }
        }
    }
    r.edges = edges.len();
    r.vertices_in_cells = in_cells.iter().filter(|&&b| b).count();
    let faces = faces2 / 2;
    r.euler_characteristic =
        r.vertices_in_cells as i64 - r.edges as i64 + faces as i64 - r.cells as i64;
    for (v, &c) in t.vcell.iter().enumerate() {
        if c == NONE {
            if in_cells[v] {
                r.bad_incident_cells += 1;
                note(
                    &mut r,
                    format!("vertex {v} is in a cell but marked not inserted"),
                );
            }
            continue;
        }
        r.inserted_vertices += 1;
        if !t.is_live(c) || !t.cells[c as usize].v.contains(&(v as u32)) {
            r.bad_incident_cells += 1;
            note(
                &mut r,
                format!("vertex {v}: incident cell {c} does not hold it"),
            );
        }
    }
    let mut pos: Vec<[u64; 3]> = (0..t.pts.len())
        .filter(|&v| in_cells[v])
        .map(|v| t.pts[v].map(|x| (x + 0.0).to_bits()))
        .collect();
    pos.sort_unstable();
    r.repeated_positions = pos.windows(2).filter(|w| w[0] == w[1]).count();
    if r.repeated_positions > 0 {
        let msg = format!("{} repeated vertex positions", r.repeated_positions);
        note(&mut r, msg);
    }
    if r.hull_facets != 12 {
        let msg = format!("{} hull facets, expected the far box's 12", r.hull_facets);
        note(&mut r, msg);
    }
    if r.euler_characteristic != 1 {
        let msg = format!(
            "Euler characteristic {} (expected 1)",
            r.euler_characteristic
        );
        note(&mut r, msg);
    }
    if r.inserted_vertices != r.vertices_in_cells {
        let msg = format!(
            "{} inserted vertices but {} in cells",
            r.inserted_vertices, r.vertices_in_cells
        );
        note(&mut r, msg);
    }
    if r.cells != t.live {
        let msg = format!("{} live cells counted, {} recorded", r.cells, t.live);
        note(&mut r, msg);
    }
    r.valid = r.first_problem.is_none();
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::delaunay::{random_points, Sampler, DEAD};

    fn base() -> Delaunay {
        Delaunay::from_points(&random_points(200, Sampler::Uniform, 5), 1)
            .unwrap()
            .0
    }

    /// The check is not vacuous: each kind of corruption is caught.
    #[test]
    fn corruptions_are_detected() {
        let t = base();
        assert!(t.check().valid);
        let c = t.finite_cells().next().unwrap() as usize;

        let mut u = t.clone();
        u.cells[c].v.swap(0, 1); // negative orientation (and neighbours now mismatched)
        let r = u.check();
        assert!(!r.valid && r.non_positive_cells >= 1, "{r:?}");

        let mut u = t.clone();
        let n = u.cells[c].n[0];
        u.cells[c].n[0] = u.cells[c].n[1];
        u.cells[c].n[1] = n;
        let r = u.check();
        assert!(!r.valid && r.asymmetric_neighbours >= 1, "{r:?}");

        let mut u = t.clone();
        u.vcell[u.cells[c].v[0] as usize] = NONE;
        assert!(!u.check().valid);

        // A non-Delaunay but otherwise valid triangulation: move a vertex slightly
        // (keeping orientations) so that some facet is no longer locally Delaunay.
        let mut found = false;
        for v in FAR_START..t.pts.len() {
            let mut u = t.clone();
            let p = u.pts[v];
            u.pts[v] = [p[0] * 1.05, p[1] * 1.05, p[2] * 1.05];
            let r = u.check();
            if r.non_positive_cells == 0 && r.non_delaunay_facets > 0 {
                assert!(!r.valid);
                found = true;
                break;
            }
        }
        assert!(found);

        let mut u = t.clone();
        u.cells[c].v[0] = DEAD; // a cell vanishes: hole
        assert!(!u.check().valid);
    }

    const FAR_START: usize = crate::kernel::delaunay::FAR as usize;
}
