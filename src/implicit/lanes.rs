//! [`Lanes`]: [`LANES`] f64 values side by side, a [`Num`] whose every operation is the
//! f64 operation on each lane.
//!
//! Forward-mode derivatives over lanes, `Dual<Lanes>`, evaluate the gradient at
//! [`LANES`] points per pass of the tape (the batch gradient of
//! [`Implicit::grad_batch`](super::Implicit::grad_batch)): the interpreter's dispatch is
//! shared by the lanes and the per-lane loops compile to AVX2 on this crate's
//! `target-cpu=haswell`. Each lane performs exactly the IEEE operations of `Dual<f64>`
//! (the same `Dual` code, on the same f64 [`Num`] methods), so the batch gradient equals
//! the scalar one bit for bit (`tests/batch.rs`).
use super::batch::LANES;
use super::number::{Const, Dual, Num};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// [`LANES`] f64 values; every operation acts lane by lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lanes(pub [f64; LANES]);

impl Lanes {
    /// Every lane `v`.
    #[inline(always)]
    pub fn splat(v: f64) -> Self {
        Lanes([v; LANES])
    }
    #[inline(always)]
    fn map(&self, f: impl Fn(&f64) -> f64) -> Self {
        let mut o = [0.0; LANES];
        for k in 0..LANES {
            o[k] = f(&self.0[k]);
        }
        Lanes(o)
    }
    #[inline(always)]
    fn zip(&self, b: &Self, f: impl Fn(&f64, &f64) -> f64) -> Self {
        let mut o = [0.0; LANES];
        for k in 0..LANES {
            o[k] = f(&self.0[k], &b.0[k]);
        }
        Lanes(o)
    }
}

macro_rules! lane_binop {
    ($tr:ident, $m:ident, $op:tt) => {
        impl $tr for Lanes {
            type Output = Self;
            #[inline(always)]
            fn $m(self, o: Self) -> Self {
                self.zip(&o, |a, b| a $op b)
            }
        }
    };
}
lane_binop!(Add, add, +);
lane_binop!(Sub, sub, -);
lane_binop!(Mul, mul, *);
lane_binop!(Div, div, /);

impl Neg for Lanes {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
}

impl Num for Lanes {
    #[inline(always)]
    fn cst(c: Const) -> Self {
        Lanes::splat(<f64 as Num>::cst(c))
    }
    #[inline(always)]
    fn add_const(&self, c: &Const) -> Self {
        self.map(|a| a.add_const(c))
    }
    #[inline(always)]
    fn sub_const(&self, c: &Const) -> Self {
        self.map(|a| a.sub_const(c))
    }
    #[inline(always)]
    fn const_sub(&self, c: &Const) -> Self {
        self.map(|a| a.const_sub(c))
    }
    #[inline(always)]
    fn mul_const(&self, c: &Const) -> Self {
        self.map(|a| a.mul_const(c))
    }
    #[inline(always)]
    fn div_const(&self, c: &Const) -> Self {
        self.map(|a| a.div_const(c))
    }
    #[inline(always)]
    fn square(&self) -> Self {
        self.map(<f64 as Num>::square)
    }
    fn powi(&self, n: i32) -> Self {
        self.map(|a| a.powi(n))
    }
    fn sqrt(&self) -> Self {
        self.map(<f64 as Num>::sqrt)
    }
    fn abs(&self) -> Self {
        self.map(<f64 as Num>::abs)
    }
    fn sign(&self) -> Self {
        self.map(<f64 as Num>::sign)
    }
    fn kink(&self) -> Self {
        self.map(<f64 as Num>::kink)
    }
    fn min(&self, o: &Self) -> Self {
        self.zip(o, <f64 as Num>::min)
    }
    fn max(&self, o: &Self) -> Self {
        self.zip(o, <f64 as Num>::max)
    }
    fn sin(&self) -> Self {
        self.map(<f64 as Num>::sin)
    }
    fn cos(&self) -> Self {
        self.map(<f64 as Num>::cos)
    }
    fn exp(&self) -> Self {
        self.map(<f64 as Num>::exp)
    }
    fn ln(&self) -> Self {
        self.map(<f64 as Num>::ln)
    }
}

/// The gradient at every point of `p` into `out`, [`LANES`] points per call of `eval`
/// (f evaluated on `Dual<Lanes>`); the last, partial chunk repeats its last point in
/// the unused lanes. Panics if the lengths differ.
pub fn grad_batch(
    p: &[[f64; 3]],
    out: &mut [Dual<f64>],
    mut eval: impl FnMut([Dual<Lanes>; 3]) -> Dual<Lanes>,
) {
    assert!(p.len() == out.len(), "batch slices of different lengths");
    for (pc, oc) in p.chunks(LANES).zip(out.chunks_mut(LANES)) {
        let at = |k: usize| pc[k.min(pc.len() - 1)];
        // (Per axis: `[0, 1, 2].map` left this closure out of line.)
        let var = |a: usize| Dual::var(Lanes(std::array::from_fn(|k| at(k)[a])), a);
        let v = [var(0), var(1), var(2)];
        let d = eval(v);
        for (k, o) in oc.iter_mut().enumerate() {
            *o = Dual {
                v: d.v.0[k],
                g: [d.g[0].0[k], d.g[1].0[k], d.g[2].0[k]],
            };
        }
    }
}
