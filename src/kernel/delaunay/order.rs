//! Insertion order for bulk construction: biased randomized insertion order (Amenta,
//! Choi and Rote, "Incremental constructions con BRIO", 2003) with a Hilbert-curve
//! order inside each round, so that consecutive points are close (short walks, cache
//! locality) while the rounds keep the expected-case guarantees of randomized
//! incremental construction. The Hilbert index follows Skilling, "Programming the
//! Hilbert curve", 2004 (transpose form).

pub use crate::kernel::rng::Rng as SplitMix;

const BITS: u32 = 21;

/// Hilbert index of a point with 21-bit integer coordinates (63-bit key).
pub fn hilbert_key(mut x: [u32; 3]) -> u64 {
    let m = 1u32 << (BITS - 1);
    let mut q = m;
    while q > 1 {
        let p = q - 1;
        for i in 0..3 {
            if x[i] & q != 0 {
                x[0] ^= p;
            } else {
                let t = (x[0] ^ x[i]) & p;
                x[0] ^= t;
                x[i] ^= t;
            }
        }
        q >>= 1;
    }
    x[1] ^= x[0];
    x[2] ^= x[1];
    let mut t = 0;
    q = m;
    while q > 1 {
        if x[2] & q != 0 {
            t ^= q - 1;
        }
        q >>= 1;
    }
    for v in x.iter_mut() {
        *v ^= t;
    }
    let mut key = 0u64;
    for b in (0..BITS).rev() {
        for v in x {
            key = (key << 1) | ((v >> b) & 1) as u64;
        }
    }
    key
}

/// Smallest round size: rounds below it are merged into the first.
const MIN_ROUND: usize = 64;

/// A BRIO order of `points` (indices into it): rounds of roughly doubling size, each
/// sorted along a Hilbert curve over the bounding box of all points. Deterministic for
/// a given seed.
pub fn brio_order(points: &[[f64; 3]], seed: u64) -> Vec<u32> {
    let n = points.len();
    if n == 0 {
        return Vec::new();
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let scale: [f64; 3] = std::array::from_fn(|k| {
        let w = hi[k] - lo[k];
        if w > 0.0 {
            ((1u32 << BITS) - 1) as f64 / w
        } else {
            0.0
        }
    });
    // Number of rounds so that the first has about MIN_ROUND points.
    let mut rounds = 1u32;
    while (n >> rounds) >= MIN_ROUND && rounds < 40 {
        rounds += 1;
    }
    let mut rng = SplitMix(seed ^ 0xB410_0000_0000_0001);
    // key: round in the top bits is not possible with a 63-bit Hilbert key, so sort
    // by (round, key).
    let mut keyed: Vec<(u32, u64, u32)> = points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // A point survives to an earlier round with probability 1/2 each time:
            // round = rounds-1 - (number of leading successes), clamped at 0.
            let z = rng.next_u64().trailing_ones();
            let round = (rounds - 1).saturating_sub(z);
            let c: [u32; 3] = std::array::from_fn(|k| ((p[k] - lo[k]) * scale[k]) as u32);
            (round, hilbert_key(c), i as u32)
        })
        .collect();
    keyed.sort_unstable_by_key(|&(r, k, i)| (r, k, i));
    keyed.into_iter().map(|(_, _, i)| i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hilbert_neighbours_are_adjacent() {
        // Along the curve on a 4x4x4 sub-grid of the full grid, consecutive cells
        // differ by one step in one axis (scaled to the top 2 bits).
        let s = 1u32 << (BITS - 2);
        let mut cells: Vec<(u64, [u32; 3])> = Vec::new();
        for x in 0..4 {
            for y in 0..4 {
                for z in 0..4 {
                    let c = [x * s, y * s, z * s];
                    cells.push((hilbert_key(c), [x, y, z]));
                }
            }
        }
        cells.sort();
        for w in cells.windows(2) {
            let d: u32 = (0..3).map(|k| w[0].1[k].abs_diff(w[1].1[k])).sum();
            assert_eq!(d, 1, "{:?} -> {:?}", w[0].1, w[1].1);
        }
    }

    #[test]
    fn brio_is_a_permutation() {
        let mut r = SplitMix(3);
        let pts: Vec<[f64; 3]> = (0..1000)
            .map(|_| [r.uniform(), r.uniform(), r.uniform()])
            .collect();
        let mut o = brio_order(&pts, 1);
        o.sort();
        assert!(o.iter().enumerate().all(|(i, &v)| v as usize == i));
    }
}
