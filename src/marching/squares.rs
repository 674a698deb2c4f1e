//! Marching squares: the 2D baseline, with the same face rule as marching cubes' cube
//! faces ("negative corners are separated" on a square with four crossings), so the
//! output is closed polylines away from the domain boundary. Crossing vertices are
//! shared through grid edges.
//!
//! Segments are oriented with f < 0 on their left: each closed polyline runs
//! counter-clockwise around the region it encloses when that region is negative.
use super::{face_rule, Cells, Marching, Place, Table};
use crate::error::{Error, Result};
use crate::kernel::geom::lerp;
use crate::lattice::grid::Field;
use crate::mesh::Curve2;
use std::collections::HashMap;
use std::sync::OnceLock;

/// Marching squares, `"ms"`: [`Marching`] over the [`Squares`] table. Defaults
/// ([`GridParams::default`](super::GridParams::default)): 64 cells along the longest
/// side, linear interpolation, no pruning.
pub type MarchingSquares = Marching<Squares>;

/// The marching squares table: 16 sign cases of the square, from the face rule.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Squares;

impl Cells for Squares {
    const ALGO: &'static str = "ms";
    const TITLE: &'static str = "marching squares";
    const TYPE_NAME: &'static str = "MarchingSquares";
    fn table() -> Table {
        Table::Square(table())
    }
}

/// Marching squares on an already sampled planar grid, crossings by linear
/// interpolation.
pub fn marching_squares<F: Field>(field: &F) -> Result<Curve2> {
    Ok(extract(field, table(), Place::Linear)?.0)
}

/// The table (see [`Table::Square`]), built from the face rule at first use.
fn table() -> &'static [Vec<(u8, u8)>; 16] {
    static T: OnceLock<[Vec<(u8, u8)>; 16]> = OnceLock::new();
    T.get_or_init(|| {
        std::array::from_fn(|case| {
            face_rule([0, 1, 2, 3].map(|m| case >> m & 1 == 1))
                .map(|(m, m2)| (m as u8, m2 as u8))
                .collect()
        })
    })
}

/// The extraction with a square table: the curve and the cells with a sign change.
pub(crate) fn extract<F: Field>(
    field: &F,
    table: &[Vec<(u8, u8)>; 16],
    place: Place,
) -> Result<(Curve2, u64)> {
    let g = *field.grid();
    if g.dim() != 2 {
        return Err(Error::Param("marching squares needs a planar grid".into()));
    }
    let [cx, cy, _] = g.cells();
    let mut vertices: Vec<[f64; 2]> = Vec::new();
    let mut segments = Vec::new();
    // Crossing vertex of grid edge (vertex index * 2 + axis), created on first use.
    let mut ids: HashMap<usize, u32> = HashMap::new();
    let mut vertex = |i: usize, j: usize, axis: usize| -> u32 {
        let key = g.index(i, j, 0) * 2 + axis;
        *ids.entry(key).or_insert_with(|| {
            let (i2, j2) = if axis == 0 { (i + 1, j) } else { (i, j + 1) };
            let (a, b) = (field.value(i, j, 0), field.value(i2, j2, 0));
            let (p, q) = (g.point(i, j, 0), g.point(i2, j2, 0));
            let x = lerp(p, q, place.t(p, a, q, b));
            vertices.push([x[0], x[1]]);
            (vertices.len() - 1) as u32
        })
    };
    // Corners counter-clockwise (seen from +z) and the edge from corner m to m + 1, as
    // (lower vertex offset, axis).
    const Q: [[usize; 2]; 4] = [[0, 0], [1, 0], [1, 1], [0, 1]];
    const E: [([usize; 2], usize); 4] = [([0, 0], 0), ([1, 0], 1), ([0, 1], 0), ([0, 0], 1)];
    let mut visited = 0u64;
    for j in 0..cy {
        for i in 0..cx {
            let v = Q.map(|o| field.value(i + o[0], j + o[1], 0));
            // (Dense samples are finite; a sparse field's NaN marks a pruned cell.)
            if F::SPARSE && v.iter().any(|x| x.is_nan()) {
                continue;
            }
            let case = (0..4).fold(0, |c, m| c | (((v[m] < 0.0) as usize) << m));
            if case == 0 || case == 15 {
                continue;
            }
            visited += 1;
            // The face rule's segments have the negative corner on their right: emit
            // each reversed (negative on the left).
            for &(m, m2) in &table[case] {
                let (o1, a1) = E[m as usize];
                let (o2, a2) = E[m2 as usize];
                let s = vertex(i + o1[0], j + o1[1], a1);
                let e = vertex(i + o2[0], j + o2[1], a2);
                segments.push([e, s]);
            }
        }
    }
    Ok((Curve2 { vertices, segments }, visited))
}
