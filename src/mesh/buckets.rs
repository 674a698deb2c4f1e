//! Linear-time grouping of mesh elements by a vertex (issue 20): a counting sort by one
//! vertex of each item (an edge's or face's smallest), then a sort of each bucket, which
//! is small (about a vertex degree). The edge-face incidence of the topology analysis,
//! the face-tetrahedron incidence of the stuffing checks and the boundary extraction
//! all use it instead of a global sort or a hash map: two passes over the items and one
//! pass of small in-cache sorts, the latter in parallel.
use rayon::prelude::*;

/// Items grouped by vertex: bucket `v` is `items[start[v]..start[v + 1]]`.
#[derive(Clone, Debug, Default)]
pub struct Buckets<T> {
    start: Vec<u32>,
    items: Vec<T>,
}

/// Vertices per parallel task of [`Buckets::sort_each_by_key`].
const CHUNK: usize = 4096;

impl<T: Copy + Default + Send + Sync> Buckets<T> {
    /// Bucket items over vertices `0..n`. `each(emit)` calls `emit(vertex, item)` for
    /// every item; it is called twice (count, then fill) and must emit the same
    /// sequence both times. Within a bucket, items keep their emission order.
    pub fn build(n: usize, each: impl Fn(&mut dyn FnMut(u32, T))) -> Self {
        let mut start = vec![0u32; n + 1];
        let mut total = 0u64;
        each(&mut |v, _| {
            start[v as usize + 1] += 1;
            total += 1;
        });
        assert!(total < u32::MAX as u64, "{total} items: too many to bucket");
        for k in 0..n {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut items = vec![T::default(); start[n] as usize];
        each(&mut |v, x| {
            let slot = &mut fill[v as usize];
            items[*slot as usize] = x;
            *slot += 1;
        });
        Buckets { start, items }
    }

    /// Number of vertices (buckets).
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The items of vertex `v`.
    #[inline]
    pub fn bucket(&self, v: usize) -> &[T] {
        &self.items[self.start[v] as usize..self.start[v + 1] as usize]
    }

    /// The positions in [`Buckets::items`] of buckets `lo..hi`, which follow one
    /// another (e.g. a row of grid cells).
    #[inline]
    pub fn span(&self, lo: usize, hi: usize) -> std::ops::Range<usize> {
        self.start[lo] as usize..self.start[hi] as usize
    }

    /// Every item, bucket after bucket.
    pub fn items(&self) -> &[T] {
        &self.items
    }

    /// Sort every bucket by `key` (unstable), buckets in parallel.
    pub fn sort_each_by_key<K: Ord>(&mut self, key: impl Fn(&T) -> K + Sync) {
        let n = self.len();
        let start = &self.start;
        let mut tasks = Vec::with_capacity(n / CHUNK + 1);
        let mut rest: &mut [T] = &mut self.items;
        for c in (0..n).step_by(CHUNK) {
            let end = (c + CHUNK).min(n);
            let (mine, tail) = rest.split_at_mut((start[end] - start[c]) as usize);
            tasks.push((c, end, mine));
            rest = tail;
        }
        tasks.into_par_iter().for_each(|(c, end, items)| {
            let base = start[c];
            for v in c..end {
                let b = &mut items[(start[v] - base) as usize..(start[v + 1] - base) as usize];
                if b.len() > 1 {
                    b.sort_unstable_by_key(&key);
                }
            }
        });
    }

    /// Every run of items with equal `key` in bucket `v` (after
    /// [`Buckets::sort_each_by_key`] with the same key: one run per distinct key).
    #[inline]
    pub fn runs<'a, K: PartialEq + 'a>(
        &'a self,
        v: usize,
        key: impl Fn(&T) -> K + 'a,
    ) -> impl Iterator<Item = &'a [T]> + 'a {
        self.bucket(v).chunk_by(move |a, b| key(a) == key(b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_by_vertex_and_key() {
        let pairs = [(2u32, 7u32), (0, 5), (2, 3), (2, 7), (1, 1), (0, 5)];
        let mut b = Buckets::build(4, |emit| {
            for &(v, x) in &pairs {
                emit(v, x);
            }
        });
        assert_eq!(b.len(), 4);
        assert_eq!(b.bucket(2), &[7, 3, 7]);
        assert!(b.bucket(3).is_empty());
        // Buckets 0..2 follow one another: 5, 5, then 1.
        assert_eq!(&b.items()[b.span(0, 2)], &[5, 5, 1]);
        assert_eq!(b.span(3, 4), 6..6);
        b.sort_each_by_key(|&x| x);
        let runs: Vec<Vec<u32>> = b.runs(2, |&x| x).map(|r| r.to_vec()).collect();
        assert_eq!(runs, vec![vec![3], vec![7, 7]]);
        let runs: Vec<usize> = b.runs(0, |&x| x).map(|r| r.len()).collect();
        assert_eq!(runs, vec![2]);
    }
}
