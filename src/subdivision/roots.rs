//! Signs at grid points and the roots of f on box edges: the root finders the
//! assembly asks (sign change with bisection, Snyder's interval isolation).
use super::*;
use crate::implicit::Implicit;
use crate::kernel::geom::lerp;
use std::sync::atomic::AtomicU64;

/// An elementary segment of the subdivision: two grid points joined along an axis with
/// no grid point strictly between them. `a < b` by key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Seg {
    pub a: u64,
    pub b: u64,
}

/// The crossings found on one elementary segment, ordered from `a` to `b`.
#[derive(Clone, Debug, Default)]
pub struct SegRoots {
    pub pos: Vec<[f64; 3]>,
    /// False when interval root isolation failed (grazing): the count is then only the
    /// parity of the end signs.
    pub isolated: bool,
}

/// An elementary box edge with the signs of f at its ends.
#[derive(Clone, Copy, Debug)]
pub struct SignedSegment {
    pub a: [f64; 3],
    pub sa: PointSign,
    pub b: [f64; 3],
    pub sb: PointSign,
}

/// How the crossings on a segment are found.
pub trait RootFinder: Sync {
    /// Crossings of f + ε = 0 on the segment from `a` to `b` (in that order), given the
    /// end signs. Adds root-isolation steps to `steps`.
    fn roots(&self, f: &dyn Implicit, e: SignedSegment, steps: &AtomicU64) -> SegRoots;
}

/// Plantinga–Vegter crossings: one per sign change (a vertex on every edge whose end
/// signs differ, §1.2.4).
pub struct SignChange {
    pub tol: f64,
    pub linear: bool,
}

impl RootFinder for SignChange {
    fn roots(&self, f: &dyn Implicit, e: SignedSegment, _steps: &AtomicU64) -> SegRoots {
        let pos = if e.sa.pos != e.sb.pos {
            let linear = self.linear.then_some((e.sa.value, e.sb.value));
            vec![locate(f, e.a, e.sa.pos, e.b, self.tol, linear)]
        } else {
            Vec::new()
        };
        SegRoots {
            pos,
            isolated: true,
        }
    }
}

impl RootFinder for IntervalIsolation {
    fn roots(&self, f: &dyn Implicit, e: SignedSegment, steps: &AtomicU64) -> SegRoots {
        let SignedSegment {
            a: pa,
            sa,
            b: pb,
            sb,
        } = e;
        match self.isolate(f, pa, sa.pos, pb, sb.pos, steps) {
            Some(pieces) => SegRoots {
                pos: pieces
                    .into_iter()
                    .map(|(t0, t1, s0)| {
                        let a = lerp(pa, pb, t0);
                        let b = lerp(pa, pb, t1);
                        locate(f, a, s0, b, self.tol / (t1 - t0).max(1e-300), None)
                    })
                    .collect(),
                isolated: true,
            },
            None => SegRoots {
                pos: if sa.pos != sb.pos {
                    vec![locate(f, pa, sa.pos, pb, self.tol, None)]
                } else {
                    Vec::new()
                },
                isolated: false,
            },
        }
    }
}
