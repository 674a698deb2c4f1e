//! The first NaN or infinite number of a slice, found fast when there is none: the
//! check every mesh (its coordinates) and every sampled grid (its values) passes
//! before anything is computed from them.
use rayon::prelude::*;

/// Numbers per task of the parallel pass (slices up to this long are checked serially).
const CHUNK: usize = 1 << 14;

/// Whether some value of `xs` is NaN or infinite: an OR of comparisons, without a
/// branch per value, which the compiler vectorises.
#[inline]
fn any_non_finite(xs: &[f64]) -> bool {
    xs.iter().fold(false, |b, x| b | !x.is_finite())
}

/// The index of the first NaN or infinite value of `xs` (`None`: every value is
/// finite). One branch-free pass, in parallel chunks on long slices; the first bad
/// value is searched only when there is one. (A search value by value, rayon's
/// `position_first`, took a third of the marching-cubes mesher at its defaults.)
pub fn first_non_finite(xs: &[f64]) -> Option<usize> {
    let bad = if xs.len() <= CHUNK {
        any_non_finite(xs)
    } else {
        xs.par_chunks(CHUNK).any(any_non_finite)
    };
    if bad {
        xs.iter().position(|x| !x.is_finite())
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The same index as a plain search, on slices shorter and longer than a
        /// chunk, with NaN, ±∞ or nothing planted at random places.
        #[test]
        fn equals_the_plain_search(
            len in prop_oneof![0usize..100, 16_000usize..50_000],
            bad in proptest::collection::vec((0.0f64..1.0, 0usize..3), 0..4),
        ) {
            let mut xs: Vec<f64> = (0..len).map(|i| (i as f64).sin() * 1e300).collect();
            for &(at, kind) in &bad {
                if len > 0 {
                    let i = ((at * len as f64) as usize).min(len - 1);
                    xs[i] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY][kind];
                }
            }
            prop_assert_eq!(
                first_non_finite(&xs),
                xs.iter().position(|x| !x.is_finite())
            );
        }
    }

    #[test]
    fn finds_the_first_of_several() {
        let mut xs = vec![1.0; 40_000];
        xs[39_000] = f64::NAN;
        xs[20_000] = f64::NEG_INFINITY;
        assert_eq!(first_non_finite(&xs), Some(20_000));
        assert_eq!(first_non_finite(&xs[..20_000]), None);
        assert_eq!(first_non_finite(&[]), None);
        assert_eq!(
            first_non_finite(&[f64::MAX, -f64::MAX, f64::MIN_POSITIVE]),
            None
        );
    }
}
