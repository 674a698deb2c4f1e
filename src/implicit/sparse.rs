//! Interval gradients of polynomial tapes in *sparse* forward mode: the same numbers as
//! forward mode on [`Dual<Iv>`] (the generic interpreter [`Tape::eval_in`]), with the
//! structurally zero partial derivatives neither stored nor computed.
//!
//! Forward mode carries three partials per register; most of them are identically zero
//! (x² has no y- or z-derivative), and the dense interpreter multiplies and adds those
//! zeros. [`GradTape::compile`] tracks, per register, which partials can be non-zero
//! and emits a flat program of [`Iv`] operations for the others only:
//! * a partial that is a copy of an operand's (a sum with a structurally zero other
//!   term, `r ± c`) is not recomputed: its slot is the operand's slot;
//! * a product keeps the terms whose factors are not structurally zero, in the dense
//!   order (`a' b + a b'`); a difference with only the subtrahend's partial negates it.
//!
//! **The same values.** Every skipped term is `[0, 0]` times an interval, or a sum with
//! `[0, 0]`; for polynomial operations (`+ − ×`, squares, non-negative powers,
//! constants, division by a constant enclosure without 0) on non-empty boxes every
//! register is a non-empty interval, so a skipped product is a zero interval (inari's
//! 0 · [a, b] = 0 for unbounded [a, b] too) and adding a zero interval returns the other
//! term exactly (round-to-nearest x + 0 = x, error 0; inari likewise). Results differ
//! from the dense ones at most in the sign of a zero bound, which no comparison sees.
//! Tapes with other operations (division by a register, roots, |·|, min, max,
//! transcendental functions, negative powers) and empty input boxes take the dense
//! path; `tests/batch.rs` compares both paths bound for bound on random formulas.
use super::directed::Iv;
use super::number::{Const, Dual, Num};
use super::tape::{Op, Tape};
use std::mem::MaybeUninit;

/// One operation of the flat program; it writes the slot of its own index.
#[derive(Clone, Copy, Debug)]
enum G {
    Var(u8),
    /// `[1, 1]`: the seed of a variable's own partial.
    One,
    Cst(u32),
    Add(u16, u16),
    Sub(u16, u16),
    Mul(u16, u16),
    /// `a · b + c · d`: a product's partial with both terms.
    MulAdd(u16, u16, u16, u16),
    Neg(u16),
    Sqr(u16),
    Powi(u16, i32),
    /// `n · a^(n − 1)`: the derivative of `a^n` (as `Dual::powi` computes it).
    PowiDer(u16, i32),
    AddC(u16, u32),
    SubC(u16, u32),
    CSub(u16, u32),
    MulC(u16, u32),
    DivC(u16, u32),
}

/// A polynomial tape compiled for sparse interval gradients (see the module docs).
#[derive(Clone, Debug)]
pub struct GradTape {
    prog: Vec<G>,
    consts: Vec<Const>,
    /// Slot of the value and of each partial of the result (`None`: structurally 0).
    out: (u16, [Option<u16>; 3]),
}

/// Programs up to this length run with their slots on the stack; longer tapes take
/// the dense path.
const SLOTS: usize = 160;

impl GradTape {
    /// The sparse program of `tape`, or `None` when the tape has an operation outside
    /// the polynomial set above, or is too long.
    // The loops over k index the operands' and the result's partials together.
    #[allow(clippy::needless_range_loop)]
    pub fn compile(tape: &Tape) -> Option<GradTape> {
        let consts = tape.consts().to_vec();
        let mut prog: Vec<G> = Vec::new();
        // Per tape register: the value's slot and each partial's slot.
        let mut regs: Vec<(u16, [Option<u16>; 3])> = Vec::with_capacity(tape.len());
        let push = |prog: &mut Vec<G>, g: G| -> Option<u16> {
            prog.push(g);
            u16::try_from(prog.len() - 1).ok()
        };
        for &op in tape.ops() {
            let r = |j: u32| regs[j as usize];
            let nonzero_const = |c: u32| {
                let k = &consts[c as usize];
                k.lo > 0.0 || k.hi < 0.0
            };
            let reg = match op {
                Op::Var(k) => {
                    let v = push(&mut prog, G::Var(k))?;
                    let mut g = [None; 3];
                    g[k as usize] = Some(push(&mut prog, G::One)?);
                    (v, g)
                }
                Op::Const(c) => (push(&mut prog, G::Cst(c))?, [None; 3]),
                Op::Add(a, b) => {
                    let (ra, rb) = (r(a), r(b));
                    let v = push(&mut prog, G::Add(ra.0, rb.0))?;
                    let mut g = [None; 3];
                    for k in 0..3 {
                        g[k] = match (ra.1[k], rb.1[k]) {
                            (Some(x), Some(y)) => Some(push(&mut prog, G::Add(x, y))?),
                            (x, None) => x,
                            (None, y) => y,
                        };
                    }
                    (v, g)
                }
                Op::Sub(a, b) => {
                    let (ra, rb) = (r(a), r(b));
                    let v = push(&mut prog, G::Sub(ra.0, rb.0))?;
                    let mut g = [None; 3];
                    for k in 0..3 {
                        g[k] = match (ra.1[k], rb.1[k]) {
                            (Some(x), Some(y)) => Some(push(&mut prog, G::Sub(x, y))?),
                            (x, None) => x,
                            (None, Some(y)) => Some(push(&mut prog, G::Neg(y))?),
                        };
                    }
                    (v, g)
                }
                Op::Mul(a, b) => {
                    let (ra, rb) = (r(a), r(b));
                    let v = push(&mut prog, G::Mul(ra.0, rb.0))?;
                    let mut g = [None; 3];
                    for k in 0..3 {
                        // Dense: a'·b + a·b'.
                        g[k] = match (ra.1[k], rb.1[k]) {
                            (Some(x), Some(y)) => {
                                Some(push(&mut prog, G::MulAdd(x, rb.0, ra.0, y))?)
                            }
                            (Some(x), None) => Some(push(&mut prog, G::Mul(x, rb.0))?),
                            (None, Some(y)) => Some(push(&mut prog, G::Mul(ra.0, y))?),
                            (None, None) => None,
                        };
                    }
                    (v, g)
                }
                Op::AddC(a, c) => {
                    let ra = r(a);
                    (push(&mut prog, G::AddC(ra.0, c))?, ra.1)
                }
                Op::SubC(a, c) => {
                    let ra = r(a);
                    (push(&mut prog, G::SubC(ra.0, c))?, ra.1)
                }
                Op::CSub(a, c) => {
                    let ra = r(a);
                    let v = push(&mut prog, G::CSub(ra.0, c))?;
                    let mut g = [None; 3];
                    for k in 0..3 {
                        if let Some(x) = ra.1[k] {
                            g[k] = Some(push(&mut prog, G::Neg(x))?);
                        }
                    }
                    (v, g)
                }
                Op::MulC(a, c) => {
                    let ra = r(a);
                    let v = push(&mut prog, G::MulC(ra.0, c))?;
                    let mut g = [None; 3];
                    for k in 0..3 {
                        if let Some(x) = ra.1[k] {
                            g[k] = Some(push(&mut prog, G::MulC(x, c))?);
                        }
                    }
                    (v, g)
                }
                Op::DivC(a, c) if nonzero_const(c) => {
                    let ra = r(a);
                    let v = push(&mut prog, G::DivC(ra.0, c))?;
                    let mut g = [None; 3];
                    for k in 0..3 {
                        if let Some(x) = ra.1[k] {
                            g[k] = Some(push(&mut prog, G::DivC(x, c))?);
                        }
                    }
                    (v, g)
                }
                Op::Neg(a) => {
                    let ra = r(a);
                    let v = push(&mut prog, G::Neg(ra.0))?;
                    let mut g = [None; 3];
                    for k in 0..3 {
                        if let Some(x) = ra.1[k] {
                            g[k] = Some(push(&mut prog, G::Neg(x))?);
                        }
                    }
                    (v, g)
                }
                Op::Square(a) => {
                    // Dense: value a², partials (a + a)·a'.
                    let ra = r(a);
                    let v = push(&mut prog, G::Sqr(ra.0))?;
                    let mut g = [None; 3];
                    if ra.1.iter().any(Option::is_some) {
                        let d = push(&mut prog, G::Add(ra.0, ra.0))?;
                        for k in 0..3 {
                            if let Some(x) = ra.1[k] {
                                g[k] = Some(push(&mut prog, G::Mul(d, x))?);
                            }
                        }
                    }
                    (v, g)
                }
                Op::Powi(a, n) if n >= 2 => {
                    // Dense: d = n·a^(n−1), value a^n, partials d·a'.
                    let ra = r(a);
                    let mut g = [None; 3];
                    if ra.1.iter().any(Option::is_some) {
                        let d = push(&mut prog, G::PowiDer(ra.0, n))?;
                        for k in 0..3 {
                            if let Some(x) = ra.1[k] {
                                g[k] = Some(push(&mut prog, G::Mul(d, x))?);
                            }
                        }
                    }
                    (push(&mut prog, G::Powi(ra.0, n))?, g)
                }
                _ => return None,
            };
            regs.push(reg);
        }
        if prog.len() > SLOTS {
            return None;
        }
        let out = *regs.last()?;
        Some(GradTape { prog, consts, out })
    }

    /// Operations of the program (for tests and benches: the dense interpreter runs
    /// four interval values per tape instruction).
    pub fn len(&self) -> usize {
        self.prog.len()
    }
    pub fn is_empty(&self) -> bool {
        self.prog.is_empty()
    }

    /// Value and gradient enclosures over the box `b`, or `None` for an empty box (the
    /// caller then takes the dense path).
    #[inline]
    pub fn eval(&self, b: [Iv; 3]) -> Option<Dual<Iv>> {
        if !b.iter().all(|x| x.lo <= x.hi) {
            return None;
        }
        let mut s = [MaybeUninit::<Iv>::uninit(); SLOTS];
        let consts = &self.consts[..];
        let n = self.prog.len();
        assert!(n <= SLOTS && n > 0);
        for (i, g) in self.prog.iter().enumerate() {
            // SAFETY: `compile` emits operands of smaller index only (each slot is
            // written by its operation before any later one reads it), and i < n <=
            // SLOTS.
            let r = |j: u16| -> Iv {
                unsafe { super::tape::load_iv(s.as_ptr().add(j as usize) as *const Iv) }
            };
            let k = |c: u32| &consts[c as usize];
            let v = match *g {
                G::Var(j) => b[j as usize],
                G::One => Iv::cst(Const::exact(1.0)),
                G::Cst(c) => Iv::cst(*k(c)),
                G::Add(a, c) => r(a) + r(c),
                G::Sub(a, c) => r(a) - r(c),
                G::Mul(a, c) => r(a) * r(c),
                G::MulAdd(a, c, d, e) => r(a) * r(c) + r(d) * r(e),
                G::Neg(a) => -r(a),
                G::Sqr(a) => r(a).square(),
                G::Powi(a, m) => Num::powi(&r(a), m),
                G::PowiDer(a, m) => Iv::lit(m as f64) * Num::powi(&r(a), m - 1),
                G::AddC(a, c) => r(a).add_const(k(c)),
                G::SubC(a, c) => r(a).sub_const(k(c)),
                G::CSub(a, c) => r(a).const_sub(k(c)),
                G::MulC(a, c) => r(a).mul_const(k(c)),
                G::DivC(a, c) => r(a).div_const(k(c)),
            };
            // SAFETY: i < n <= SLOTS.
            unsafe { *s.get_unchecked_mut(i) = MaybeUninit::new(v) };
        }
        // SAFETY: every slot named by `out` was written.
        let get = |j: u16| unsafe { s[j as usize].assume_init() };
        let zero = Iv::lit(0.0);
        Some(Dual {
            v: get(self.out.0),
            g: self.out.1.map(|x| x.map_or(zero, get)),
        })
    }
}
