//! Batch evaluation of a [`Tape`]: many points (or many boxes) per call, in structure
//! of arrays, [`LANES`] at a time.
//!
//! The interpreter walks the tape once per chunk of [`LANES`] points; each instruction
//! then works on a whole register of `LANES` values (fixed-size arrays the compiler
//! turns into AVX2 instructions on this crate's `target-cpu=haswell`; on other targets
//! the same loops run scalar). The dispatch cost of the interpreter is shared by the
//! lanes, and registers live in a caller-owned [`BatchScratch`] (no thread-local
//! lookup in the hot loop).
//!
//! **Bit for bit the scalar results.** f64 lanes perform exactly the IEEE operations of
//! [`Tape::eval_f64_in`] (no contraction into FMAs: Rust never fuses). Interval lanes
//! compute each bound with the same error-free transformations as the scalar kernel
//! [`Iv`] (the helpers of [`super::directed`] are shared, not copied); a lane whose
//! operands leave the fast path's preconditions (the `moderate`/`bounded` checks), and
//! every instruction without a vector kernel (division by an interval, powers, roots,
//! transcendental functions, min/max), is recomputed by the scalar [`Iv`] operation
//! itself, which falls back to inari where it does. Outward rounding is therefore
//! exactly that of the scalar path (the proptests of `tests/batch.rs` check bounds
//! bit for bit against the scalar tape and against inari's generic interpreter).
use super::directed::{self as d, Iv};
use super::number::{Const, Num};
use super::tape::{apply, Op, Tape};
use super::IBox;
use inari::Interval;

/// Points (boxes) per interpreter pass: two AVX2 registers of f64 per value.
pub const LANES: usize = 8;

type L = [f64; LANES];

/// Register files for the batch interpreters; reuse one across calls (per thread) to
/// avoid allocation.
#[derive(Clone, Debug, Default)]
pub struct BatchScratch {
    f: Vec<L>,
    lo: Vec<L>,
    hi: Vec<L>,
}

#[inline(always)]
fn map1(a: &L, f: impl Fn(f64) -> f64) -> L {
    let mut o = [0.0; LANES];
    for k in 0..LANES {
        o[k] = f(a[k]);
    }
    o
}

#[inline(always)]
fn map2(a: &L, b: &L, f: impl Fn(f64, f64) -> f64) -> L {
    let mut o = [0.0; LANES];
    for k in 0..LANES {
        o[k] = f(a[k], b[k]);
    }
    o
}

/// One chunk of f64 lanes; `regs` has at least `tape.len()` registers.
fn f64_chunk(ops: &[Op], consts: &[Const], v: [&L; 3], regs: &mut [L]) -> L {
    for (i, op) in ops.iter().enumerate() {
        let (done, rest) = regs.split_at_mut(i);
        let r = |j: u32| &done[j as usize];
        let k = |c: u32| consts[c as usize].value;
        rest[0] = match *op {
            Op::Var(j) => *v[j as usize],
            Op::Const(c) => [k(c); LANES],
            Op::Add(a, b) => map2(r(a), r(b), |x, y| x + y),
            Op::Sub(a, b) => map2(r(a), r(b), |x, y| x - y),
            Op::Mul(a, b) => map2(r(a), r(b), |x, y| x * y),
            Op::Div(a, b) => map2(r(a), r(b), |x, y| x / y),
            Op::Min(a, b) => map2(r(a), r(b), |x, y| Num::min(&x, &y)),
            Op::Max(a, b) => map2(r(a), r(b), |x, y| Num::max(&x, &y)),
            Op::AddC(a, c) => {
                let c = k(c);
                map1(r(a), |x| x + c)
            }
            Op::SubC(a, c) => {
                let c = k(c);
                map1(r(a), |x| x - c)
            }
            Op::CSub(a, c) => {
                let c = k(c);
                map1(r(a), |x| c - x)
            }
            Op::MulC(a, c) => {
                let c = k(c);
                map1(r(a), |x| x * c)
            }
            Op::DivC(a, c) => {
                let c = k(c);
                map1(r(a), |x| x / c)
            }
            Op::Neg(a) => map1(r(a), |x| -x),
            Op::Square(a) => map1(r(a), |x| x * x),
            Op::Powi(a, n) => map1(r(a), |x| x.powi(n)),
            Op::Sqrt(a) => map1(r(a), f64::sqrt),
            Op::Abs(a) => map1(r(a), f64::abs),
            Op::Sin(a) => map1(r(a), |x| Num::sin(&x)),
            Op::Cos(a) => map1(r(a), |x| Num::cos(&x)),
            Op::Exp(a) => map1(r(a), |x| Num::exp(&x)),
            Op::Ln(a) => map1(r(a), |x| Num::ln(&x)),
        };
    }
    regs[ops.len() - 1]
}

/// A vector result: bounds and, per lane, whether the fast path's preconditions held.
struct VecIv {
    lo: L,
    hi: L,
    ok: [bool; LANES],
}

#[inline(always)]
fn all(ok: &[bool; LANES]) -> bool {
    ok.iter().fold(true, |a, &b| a & b)
}

/// A vector result from a per-lane kernel `f(k) = (lo, hi, ok)` (branch-free kernels
/// inline into SIMD code).
#[inline(always)]
fn lanes(f: impl Fn(usize) -> (f64, f64, bool)) -> VecIv {
    let mut o = VecIv {
        lo: [0.0; LANES],
        hi: [0.0; LANES],
        ok: [false; LANES],
    };
    for k in 0..LANES {
        (o.lo[k], o.hi[k], o.ok[k]) = f(k);
    }
    o
}

/// `a + b` on lanes (the scalar `Iv + Iv`: round-to-nearest sums moved outward by
/// their exact TwoSum errors).
#[inline(always)]
fn v_add(al: &L, ah: &L, bl: &L, bh: &L) -> VecIv {
    lanes(|k| {
        let ok = d::bounded(al[k]) & d::bounded(ah[k]) & d::bounded(bl[k]) & d::bounded(bh[k]);
        (d::add_dn(al[k], bl[k]), d::add_up(ah[k], bh[k]), ok)
    })
}

/// `a - b` on lanes (the scalar `Iv - Iv`).
#[inline(always)]
fn v_sub(al: &L, ah: &L, bl: &L, bh: &L) -> VecIv {
    lanes(|k| {
        let ok = d::bounded(al[k]) & d::bounded(ah[k]) & d::bounded(bl[k]) & d::bounded(bh[k]);
        (d::add_dn(al[k], -bh[k]), d::add_up(ah[k], -bl[k]), ok)
    })
}

/// `a · b` on lanes (the scalar `Iv * Iv`, both of its cases computed and selected).
#[inline(always)]
fn v_mul(al: &L, ah: &L, bl: &L, bh: &L) -> VecIv {
    lanes(|k| {
        let (a, b, c, e) = (al[k], ah[k], bl[k], bh[k]);
        let ok =
            d::moderate(a) & d::moderate(b) & d::moderate(c) & d::moderate(e) & (a <= b) & (c <= e);
        let (ac_dn, be_up) = (d::mul_dn(a, c), d::mul_up(b, e));
        if (a >= 0.0) & (c >= 0.0) {
            // Both non-negative: the scalar kernel's two-product case.
            return (ac_dn, be_up, ok);
        }
        let lo = ac_dn
            .min(d::mul_dn(a, e))
            .min(d::mul_dn(b, c))
            .min(d::mul_dn(b, e));
        let hi = d::mul_up(a, c)
            .max(d::mul_up(a, e))
            .max(d::mul_up(b, c))
            .max(be_up);
        (lo, hi, ok)
    })
}

/// `x²` on lanes (the scalar [`Iv::sqr`], its three cases selected).
#[inline(always)]
fn v_sqr(al: &L, ah: &L) -> VecIv {
    lanes(|k| {
        let (a, b) = (al[k], ah[k]);
        let ok = d::moderate(a) & d::moderate(b) & (a <= b);
        let m = (-a).max(b);
        if a >= 0.0 {
            (d::mul_dn(a, a), d::mul_up(b, b), ok)
        } else if b <= 0.0 {
            (d::mul_dn(b, b), d::mul_up(a, a), ok)
        } else {
            (0.0, d::mul_up(m, m), ok)
        }
    })
}

/// `x · c` on lanes for a point constant `c` (the scalar `mul_point`).
#[inline(always)]
fn v_mul_point(al: &L, ah: &L, c: f64) -> VecIv {
    let mc = d::moderate(c);
    lanes(|k| {
        let (a, b) = (al[k], ah[k]);
        let ok = d::moderate(a) & d::moderate(b) & mc & (a <= b);
        let (x, y) = if c >= 0.0 { (a, b) } else { (b, a) };
        (d::mul_dn(x, c), d::mul_up(y, c), ok)
    })
}

/// `x / c` on lanes for a positive constant enclosure `[cl, ch]` (the scalar
/// `div_const_iv`, case `cl > 0`).
#[inline(always)]
fn v_div_pos(al: &L, ah: &L, cl: f64, ch: f64) -> VecIv {
    let mc = d::moderate(cl) & d::moderate(ch);
    lanes(|k| {
        let (a, b) = (al[k], ah[k]);
        let ok = d::moderate(a) & d::moderate(b) & mc & (a <= b);
        let dl = if a >= 0.0 { ch } else { cl };
        let dh = if b >= 0.0 { cl } else { ch };
        (d::div_dn_pos(a, dl), d::div_up_pos(b, dh), ok)
    })
}

/// One chunk of interval lanes; `lo`, `hi` have at least `tape.len()` registers.
fn iv_chunk(
    ops: &[Op],
    consts: &[Const],
    vl: [&L; 3],
    vh: [&L; 3],
    lo: &mut [L],
    hi: &mut [L],
) -> (L, L) {
    for (i, &op) in ops.iter().enumerate() {
        let (dl, rl) = lo.split_at_mut(i);
        let (dh, rh) = hi.split_at_mut(i);
        let (rl, rh) = (&mut rl[0], &mut rh[0]);
        let reg = |j: u32| (&dl[j as usize], &dh[j as usize]);
        let splat = |c: &Const| ([c.lo; LANES], [c.hi; LANES]);
        let fast = match op {
            Op::Var(j) => {
                *rl = *vl[j as usize];
                *rh = *vh[j as usize];
                continue;
            }
            Op::Const(c) => {
                (*rl, *rh) = splat(&consts[c as usize]);
                continue;
            }
            Op::Neg(a) => {
                let (al, ah) = reg(a);
                *rl = map1(ah, |x| -x);
                *rh = map1(al, |x| -x);
                continue;
            }
            Op::Add(a, b) => {
                let ((al, ah), (bl, bh)) = (reg(a), reg(b));
                Some(v_add(al, ah, bl, bh))
            }
            Op::Sub(a, b) => {
                let ((al, ah), (bl, bh)) = (reg(a), reg(b));
                Some(v_sub(al, ah, bl, bh))
            }
            Op::Mul(a, b) => {
                let ((al, ah), (bl, bh)) = (reg(a), reg(b));
                Some(v_mul(al, ah, bl, bh))
            }
            Op::AddC(a, c) => {
                let ((al, ah), (cl, ch)) = (reg(a), splat(&consts[c as usize]));
                Some(v_add(al, ah, &cl, &ch))
            }
            Op::SubC(a, c) => {
                let ((al, ah), (cl, ch)) = (reg(a), splat(&consts[c as usize]));
                Some(v_sub(al, ah, &cl, &ch))
            }
            Op::CSub(a, c) => {
                let ((al, ah), (cl, ch)) = (reg(a), splat(&consts[c as usize]));
                Some(v_sub(&cl, &ch, al, ah))
            }
            Op::MulC(a, c) => {
                let (al, ah) = reg(a);
                let c = &consts[c as usize];
                // Only the point-constant case of `Num::mul_const` has a vector kernel.
                (c.lo == c.hi).then(|| v_mul_point(al, ah, c.lo))
            }
            Op::DivC(a, c) => {
                let (al, ah) = reg(a);
                let c = &consts[c as usize];
                (c.lo > 0.0).then(|| v_div_pos(al, ah, c.lo, c.hi))
            }
            Op::Square(a) => {
                let (al, ah) = reg(a);
                Some(v_sqr(al, ah))
            }
            _ => None,
        };
        let scalar = |k: usize| {
            let v = [0, 1, 2].map(|a| Iv::new(vl[a][k], vh[a][k]));
            apply(op, consts, &v, |j| {
                Iv::new(dl[j as usize][k], dh[j as usize][k])
            })
        };
        match fast {
            Some(VecIv { lo: l, hi: h, ok }) => {
                *rl = l;
                *rh = h;
                if !all(&ok) {
                    for k in (0..LANES).filter(|&k| !ok[k]) {
                        let s = scalar(k);
                        (rl[k], rh[k]) = (s.lo, s.hi);
                    }
                }
            }
            None => {
                for k in 0..LANES {
                    let s = scalar(k);
                    (rl[k], rh[k]) = (s.lo, s.hi);
                }
            }
        }
    }
    let n = ops.len() - 1;
    (lo[n], hi[n])
}

/// Copy `src[at..at + LANES]` into lanes, repeating the first value past the end.
#[inline(always)]
fn gather(src: &[f64], at: usize) -> L {
    let mut o = [src[at]; LANES];
    let n = (src.len() - at).min(LANES);
    o[..n].copy_from_slice(&src[at..at + n]);
    o
}

/// [`gather`] along each axis. (Written out: `p.map` was left out of line, a call per
/// chunk.)
#[inline(always)]
fn gather3(p: [&[f64]; 3], at: usize) -> [L; 3] {
    [gather(p[0], at), gather(p[1], at), gather(p[2], at)]
}

/// Registers for a tape of `n` instructions: `regs` when large enough, else a new
/// buffer in `spill`.
fn registers<'a>(regs: &'a mut [L], spill: &'a mut Vec<L>, n: usize) -> &'a mut [L] {
    if regs.len() >= n {
        regs
    } else {
        spill.resize(n, [0.0; LANES]);
        spill
    }
}

/// f64 lanes over `n` points: `load(at)` gives the coordinates of points
/// `at..at + LANES` (padded), `store(at, values)` takes the results.
pub(crate) fn f64_points(
    tape: &Tape,
    n: usize,
    regs: &mut [L],
    load: impl Fn(usize) -> [L; 3],
    mut store: impl FnMut(usize, &L),
) {
    let (ops, consts) = (tape.ops(), tape.consts());
    if ops.is_empty() {
        return;
    }
    let mut spill = Vec::new();
    let regs = registers(regs, &mut spill, ops.len());
    for at in (0..n).step_by(LANES) {
        let v = load(at);
        let r = f64_chunk(ops, consts, [&v[0], &v[1], &v[2]], regs);
        store(at, &r);
    }
}

/// Interval lanes over `n` boxes, as [`f64_points`] (`load` gives lower and upper
/// bounds, `store` takes lower and upper bounds).
pub(crate) fn iv_boxes(
    tape: &Tape,
    n: usize,
    lo: &mut [L],
    hi: &mut [L],
    load: impl Fn(usize) -> ([L; 3], [L; 3]),
    mut store: impl FnMut(usize, &L, &L),
) {
    let (ops, consts) = (tape.ops(), tape.consts());
    if ops.is_empty() {
        return;
    }
    let (mut s1, mut s2) = (Vec::new(), Vec::new());
    let lo = registers(lo, &mut s1, ops.len());
    let hi = registers(hi, &mut s2, ops.len());
    for at in (0..n).step_by(LANES) {
        let (vl, vh) = load(at);
        let (rl, rh) = iv_chunk(
            ops,
            consts,
            [&vl[0], &vl[1], &vl[2]],
            [&vh[0], &vh[1], &vh[2]],
            lo,
            hi,
        );
        store(at, &rl, &rh);
    }
}

/// Register files on the stack for tapes up to this length (larger ones allocate once
/// per call).
pub(crate) const STACK_REGS: usize = 64;

/// f at points given as coordinate slices (`p[a][i]`, a = x, y, z) into `out`, bit
/// for bit the scalar values, registers on the stack for ordinary tapes.
pub(crate) fn eval_points(tape: &Tape, p: [&[f64]; 3], out: &mut [f64]) {
    let n = out.len();
    assert!(
        p.iter().all(|v| v.len() == n),
        "batch slices of different lengths"
    );
    if n == 0 {
        return;
    }
    let mut regs = [[0.0; LANES]; STACK_REGS];
    f64_points(
        tape,
        n,
        &mut regs,
        |at| gather3(p, at),
        |at, r| {
            let m = (n - at).min(LANES);
            out[at..at + m].copy_from_slice(&r[..m]);
        },
    );
}

/// Interval enclosures over boxes of inari intervals, bit for bit the scalar ones.
pub(crate) fn eval_boxes(tape: &Tape, b: &[IBox], out: &mut [Interval]) {
    let n = out.len();
    assert!(b.len() == n, "batch slices of different lengths");
    if n == 0 {
        return;
    }
    let mut lo = [[0.0; LANES]; STACK_REGS];
    let mut hi = [[0.0; LANES]; STACK_REGS];
    iv_boxes(
        tape,
        n,
        &mut lo,
        &mut hi,
        |at| {
            let (mut l, mut h) = ([[0.0; LANES]; 3], [[0.0; LANES]; 3]);
            for k in 0..LANES {
                // Padding lanes repeat the first box of the chunk.
                let q = &b[if at + k < n { at + k } else { at }];
                for a in 0..3 {
                    let v = Iv::from_interval(q[a]);
                    (l[a][k], h[a][k]) = (v.lo, v.hi);
                }
            }
            (l, h)
        },
        |at, l, h| {
            for k in 0..(n - at).min(LANES) {
                out[at + k] = Iv::new(l[k], h[k]).to_interval();
            }
        },
    );
}

impl Tape {
    /// f at the points `(x[i], y[i], z[i])` into `out[i]`, bit for bit what
    /// [`Tape::eval_f64_in`] returns. Panics if the slices differ in length.
    pub fn eval_f64_batch(
        &self,
        x: &[f64],
        y: &[f64],
        z: &[f64],
        out: &mut [f64],
        s: &mut BatchScratch,
    ) {
        let n = out.len();
        assert!(
            x.len() == n && y.len() == n && z.len() == n,
            "batch slices of different lengths"
        );
        if s.f.len() < self.len() {
            s.f.resize(self.len(), [0.0; LANES]);
        }
        f64_points(
            self,
            n,
            &mut s.f,
            |at| [gather(x, at), gather(y, at), gather(z, at)],
            |at, r| {
                let m = (n - at).min(LANES);
                out[at..at + m].copy_from_slice(&r[..m]);
            },
        );
    }

    /// Interval enclosures over the boxes `[lo[a][i], hi[a][i]]` (a = x, y, z) into
    /// `[out_lo[i], out_hi[i]]`: bit for bit the bounds of [`Tape::eval_iv_in`] (hence of
    /// inari). Panics if the slices differ in length.
    pub fn eval_iv_batch(
        &self,
        lo: [&[f64]; 3],
        hi: [&[f64]; 3],
        out_lo: &mut [f64],
        out_hi: &mut [f64],
        s: &mut BatchScratch,
    ) {
        let n = out_lo.len();
        assert!(
            out_hi.len() == n && lo.iter().chain(hi.iter()).all(|v| v.len() == n),
            "batch slices of different lengths"
        );
        if s.lo.len() < self.len() {
            s.lo.resize(self.len(), [0.0; LANES]);
            s.hi.resize(self.len(), [0.0; LANES]);
        }
        let BatchScratch { lo: rl, hi: rh, .. } = s;
        iv_boxes(
            self,
            n,
            rl,
            rh,
            |at| (gather3(lo, at), gather3(hi, at)),
            |at, l, h| {
                let m = (n - at).min(LANES);
                out_lo[at..at + m].copy_from_slice(&l[..m]);
                out_hi[at..at + m].copy_from_slice(&h[..m]);
            },
        );
    }
}
