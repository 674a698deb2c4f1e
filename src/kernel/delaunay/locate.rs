//! Point location by a visibility walk (Devillers, Pion and Teillaud, "Walking in a
//! triangulation", 2002): from a start cell, cross any facet whose plane separates the
//! cell from the query, testing the facets in a random order (a seeded generator, so
//! runs are reproducible) — the randomisation is what guarantees termination on
//! Delaunay triangulations. The facet the walk came through is not tested again.
use super::predicates::orient3d;
use super::{Delaunay, InsertError, NONE};

impl Delaunay {
    #[inline]
    fn next_rand(&mut self) -> u64 {
        // xorshift64
        let mut x = self.rng;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.rng = x;
        x
    }

    /// A live cell whose closure contains `p`, walking from `start`. Errors with
    /// [`InsertError::Duplicate`] if `p` is a vertex and with
    /// [`InsertError::OutsideDomain`] if the walk leaves the far box.
    pub fn locate(&mut self, p: [f64; 3], start: u32) -> Result<u32, InsertError> {
        let mut c = start;
        let mut prev = NONE;
        let mut bits = self.next_rand();
        let mut left = 32;
        'walk: loop {
            let cell = self.cells[c as usize];
            let q = cell.v.map(|v| self.pts[v as usize]);
            if left == 0 {
                bits = self.next_rand();
                left = 32;
            }
            let r = (bits & 3) as usize;
            bits >>= 2;
            left -= 1;
            for k in 0..4 {
                let i = (r + k) & 3;
                let n = cell.n[i];
                if n != NONE && n >> 2 == prev {
                    continue;
                }
                let mut t = q;
                t[i] = p;
                if orient3d(t[0], t[1], t[2], t[3]) < 0.0 {
                    if n == NONE {
                        return Err(InsertError::OutsideDomain);
                    }
                    prev = c;
                    c = n >> 2;
                    continue 'walk;
                }
            }
            for k in 0..4 {
                if q[k] == p {
                    return Err(InsertError::Duplicate(cell.v[k]));
                }
            }
            return Ok(c);
        }
    }
}
