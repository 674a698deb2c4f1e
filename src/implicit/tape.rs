//! A formula compiled to a flat instruction tape (SSA: instruction `i` writes slot `i`),
//! with common subexpressions shared. One generic interpreter serves every [`Num`].
use super::directed::Iv;
use super::expr::{BinOp, Expr, UnOp};
use super::number::{Const, Num};
use inari::Interval;
use std::collections::HashMap;
use std::mem::MaybeUninit;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Op {
    Var(u8),
    Const(u32),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Min(u32, u32),
    Max(u32, u32),
    /// Fused constant operations `(register, constant index)`: `r + c`, `r - c`,
    /// `c - r`, `r * c`, `r / c`. A formula's constants mostly appear as such operands;
    /// fusing them saves an instruction and lets each number type use the cheapest
    /// rigorous form ([`Num::mul_const`] etc.).
    AddC(u32, u32),
    SubC(u32, u32),
    CSub(u32, u32),
    MulC(u32, u32),
    DivC(u32, u32),
    Neg(u32),
    /// `r²`, also for `r * r` (tight for intervals).
    Square(u32),
    Powi(u32, i32),
    Sqrt(u32),
    Abs(u32),
    Sin(u32),
    Cos(u32),
    Exp(u32),
    Ln(u32),
}

/// The compiled tape.
#[derive(Clone, Debug, Default)]
pub struct Tape {
    // Private: the unchecked register reads below rely on the SSA invariant that
    // `compile` establishes (every operand index is smaller than its instruction's,
    // every constant index is within `consts`).
    ops: Vec<Op>,
    /// The constants, materialised once: `value` serves f64, `lo`/`hi` intervals.
    consts: Vec<Const>,
}

/// One interpreter body for the `Copy` hot-path types (f64, [`Iv`]): registers are
/// written in place into a buffer of at least `ops.len()` slots (no per-instruction
/// capacity checks, no initialisation: SSA order writes every slot before its reads).
macro_rules! interpret_copy {
    ($self:ident, $vars:expr, $regs:ident, $T:ty, load: $load:expr,
     cst: |$c:ident| $cst:expr,
     add_c: |$a1:ident, $k1:ident| $add_c:expr, sub_c: |$a2:ident, $k2:ident| $sub_c:expr,
     c_sub: |$a3:ident, $k3:ident| $c_sub:expr, mul_c: |$a4:ident, $k4:ident| $mul_c:expr,
     div_c: |$a5:ident, $k5:ident| $div_c:expr, square: |$a6:ident| $square:expr,
     powi: |$a7:ident, $n:ident| $powi:expr) => {{
        let n = $self.ops.len();
        assert!($regs.len() >= n && n > 0, "register buffer too small");
        let vars = $vars;
        let consts = &$self.consts[..];
        for (i, op) in $self.ops.iter().enumerate() {
            // SAFETY: SSA (see `Tape`): every operand index j < i < n <= regs.len(), and
            // slot j was written at instruction j.
            let r =
                |j: u32| -> $T { unsafe { $load($regs.as_ptr().add(j as usize) as *const $T) } };
            let v: $T = match *op {
                Op::Var(k) => vars[k as usize],
                Op::Const(ci) => {
                    let $c = &consts[ci as usize];
                    $cst
                }
                Op::Add(a, b) => r(a) + r(b),
                Op::Sub(a, b) => r(a) - r(b),
                Op::Mul(a, b) => r(a) * r(b),
                Op::Div(a, b) => r(a) / r(b),
                Op::Min(a, b) => Num::min(&r(a), &r(b)),
                Op::Max(a, b) => Num::max(&r(a), &r(b)),
                Op::AddC(a, ci) => {
                    let ($a1, $k1) = (r(a), &consts[ci as usize]);
                    $add_c
                }
                Op::SubC(a, ci) => {
                    let ($a2, $k2) = (r(a), &consts[ci as usize]);
                    $sub_c
                }
                Op::CSub(a, ci) => {
                    let ($a3, $k3) = (r(a), &consts[ci as usize]);
                    $c_sub
                }
                Op::MulC(a, ci) => {
                    let ($a4, $k4) = (r(a), &consts[ci as usize]);
                    $mul_c
                }
                Op::DivC(a, ci) => {
                    let ($a5, $k5) = (r(a), &consts[ci as usize]);
                    $div_c
                }
                Op::Neg(a) => -r(a),
                Op::Square(a) => {
                    let $a6 = r(a);
                    $square
                }
                Op::Powi(a, m) => {
                    let ($a7, $n) = (r(a), m);
                    $powi
                }
                Op::Sqrt(a) => Num::sqrt(&r(a)),
                Op::Abs(a) => Num::abs(&r(a)),
                Op::Sin(a) => Num::sin(&r(a)),
                Op::Cos(a) => Num::cos(&r(a)),
                Op::Exp(a) => Num::exp(&r(a)),
                Op::Ln(a) => Num::ln(&r(a)),
            };
            // SAFETY: i < n <= regs.len().
            unsafe { *$regs.get_unchecked_mut(i) = MaybeUninit::new(v) };
        }
        // SAFETY: slot n - 1 was written by the last instruction.
        unsafe { $regs[n - 1].assume_init() }
    }};
}

/// Read an `Iv` register as two 8-byte loads. The interpreter stores a result as its
/// two halves; a single 16-byte load of them (which the compiler otherwise emits)
/// cannot be served by store-to-load forwarding and stalls on every dependency
/// (measured: ~10% of interval evaluation time on one load). Volatile keeps the loads
/// separate.
///
/// # Safety
/// `p` points to an initialised `Iv`.
#[inline(always)]
pub(crate) unsafe fn load_iv(p: *const Iv) -> Iv {
    Iv {
        lo: std::ptr::read_volatile(std::ptr::addr_of!((*p).lo)),
        hi: std::ptr::read_volatile(std::ptr::addr_of!((*p).hi)),
    }
}

/// One instruction in any [`Num`], operands read through `r`: the step of the generic
/// interpreter [`Tape::eval`], and the per-lane fallback of the batch interpreter
/// (`super::batch`), so both compute exactly what the scalar paths compute.
#[inline(always)]
pub(crate) fn apply<T: Num>(op: Op, consts: &[Const], vars: &[T; 3], r: impl Fn(u32) -> T) -> T {
    let k = |i: u32| &consts[i as usize];
    match op {
        Op::Var(j) => vars[j as usize].clone(),
        Op::Const(c) => T::cst(*k(c)),
        Op::Add(a, b) => r(a) + r(b),
        Op::Sub(a, b) => r(a) - r(b),
        Op::Mul(a, b) => r(a) * r(b),
        Op::Div(a, b) => r(a) / r(b),
        Op::Min(a, b) => r(a).min(&r(b)),
        Op::Max(a, b) => r(a).max(&r(b)),
        Op::AddC(a, c) => r(a).add_const(k(c)),
        Op::SubC(a, c) => r(a).sub_const(k(c)),
        Op::CSub(a, c) => r(a).const_sub(k(c)),
        Op::MulC(a, c) => r(a).mul_const(k(c)),
        Op::DivC(a, c) => r(a).div_const(k(c)),
        Op::Neg(a) => -r(a),
        Op::Square(a) => r(a).square(),
        Op::Powi(a, n) => r(a).powi(n),
        Op::Sqrt(a) => r(a).sqrt(),
        Op::Abs(a) => r(a).abs(),
        Op::Sin(a) => r(a).sin(),
        Op::Cos(a) => r(a).cos(),
        Op::Exp(a) => r(a).exp(),
        Op::Ln(a) => r(a).ln(),
    }
}

impl Tape {
    pub fn compile(e: &Expr) -> Tape {
        let mut b = Builder {
            tape: Tape::default(),
            memo: HashMap::new(),
            const_memo: HashMap::new(),
        };
        b.emit(e);
        b.tape
    }

    pub fn ops(&self) -> &[Op] {
        &self.ops
    }
    pub fn consts(&self) -> &[Const] {
        &self.consts
    }
    pub fn len(&self) -> usize {
        self.ops.len()
    }
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Evaluate at `vars` in any [`Num`], using `regs` as scratch (cleared first; reuse
    /// it across calls to avoid allocation).
    #[inline]
    pub fn eval<T: Num>(&self, vars: &[T; 3], regs: &mut Vec<T>) -> T {
        regs.clear();
        regs.reserve(self.ops.len());
        for &op in &self.ops {
            let v = apply(op, &self.consts, vars, |i| regs[i as usize].clone());
            regs.push(v);
        }
        regs.pop().expect("a compiled tape is never empty")
    }

    /// [`Tape::eval`] with registers in `regs` (at least [`Tape::len`] slots, e.g. on
    /// the stack): no allocation, no thread-local lookup. The same values as
    /// [`Tape::eval`] (both run [`apply`]).
    #[inline]
    pub fn eval_in<T: Num + Copy>(&self, vars: &[T; 3], regs: &mut [MaybeUninit<T>]) -> T {
        let n = self.ops.len();
        assert!(regs.len() >= n && n > 0, "register buffer too small");
        for (i, &op) in self.ops.iter().enumerate() {
            // SAFETY: SSA (see `Tape`): every operand j < i was written at instruction j.
            let v = apply(op, &self.consts, vars, |j| unsafe {
                regs.get_unchecked(j as usize).assume_init()
            });
            regs[i] = MaybeUninit::new(v);
        }
        // SAFETY: slot n - 1 was written by the last instruction.
        unsafe { regs[n - 1].assume_init() }
    }

    /// Specialised f64 evaluation: the hot path of every lattice method. `regs` is
    /// grown as needed (reuse it across calls to avoid allocation).
    #[inline]
    pub fn eval_f64(&self, p: [f64; 3], regs: &mut Vec<f64>) -> f64 {
        if regs.len() < self.ops.len() {
            regs.resize(self.ops.len(), 0.0);
        }
        // SAFETY: viewing initialised f64s as MaybeUninit; only initialised values are
        // written back.
        let slots = unsafe { &mut *(regs.as_mut_slice() as *mut [f64] as *mut [MaybeUninit<f64>]) };
        self.eval_f64_in(p, slots)
    }

    /// f64 evaluation with registers in `regs` (at least [`Tape::len`] slots).
    #[inline]
    pub fn eval_f64_in(&self, p: [f64; 3], regs: &mut [MaybeUninit<f64>]) -> f64 {
        interpret_copy!(self, p, regs, f64, load: |p: *const f64| *p,
            cst: |c| c.value,
            add_c: |a, c| a + c.value,
            sub_c: |a, c| a - c.value,
            c_sub: |a, c| c.value - a,
            mul_c: |a, c| a * c.value,
            div_c: |a, c| a / c.value,
            square: |a| a * a,
            powi: |a, n| a.powi(n))
    }

    /// Interval evaluation with the fast outward-rounding kernel [`Iv`] (the hot path of
    /// every pruning octree; the same bounds as inari's, see `directed`), registers in
    /// `regs` (at least [`Tape::len`] slots).
    #[inline]
    pub fn eval_iv_in(&self, b: [Iv; 3], regs: &mut [MaybeUninit<Iv>]) -> Iv {
        interpret_copy!(self, b, regs, Iv, load: load_iv,
            cst: |c| Iv::from_const(c),
            add_c: |a, c| a.add_const(c),
            sub_c: |a, c| a.sub_const(c),
            c_sub: |a, c| a.const_sub(c),
            mul_c: |a, c| a.mul_const(c),
            div_c: |a, c| a.div_const(c),
            square: |a| a.sqr(),
            powi: |a, n| Num::powi(&a, n))
    }

    /// [`Tape::eval_iv_in`] with a growable buffer.
    #[inline]
    pub fn eval_iv(&self, b: [Iv; 3], regs: &mut Vec<Iv>) -> Iv {
        if regs.len() < self.ops.len() {
            regs.resize(self.ops.len(), Iv::point(0.0));
        }
        // SAFETY: as in `eval_f64`.
        let slots = unsafe { &mut *(regs.as_mut_slice() as *mut [Iv] as *mut [MaybeUninit<Iv>]) };
        self.eval_iv_in(b, slots)
    }

    /// Interval evaluation over a box of inari intervals (through [`Tape::eval_iv`]).
    #[inline]
    pub fn eval_interval(&self, b: &[Interval; 3], regs: &mut Vec<Iv>) -> Interval {
        self.eval_iv(b.map(Iv::from_interval), regs).to_interval()
    }
}

struct Builder {
    tape: Tape,
    memo: HashMap<Op, u32>,
    const_memo: HashMap<(u64, u64, u64), u32>,
}

impl Builder {
    fn push(&mut self, op: Op) -> u32 {
        if let Some(&i) = self.memo.get(&op) {
            return i;
        }
        let i = self.tape.ops.len() as u32;
        self.tape.ops.push(op);
        self.memo.insert(op, i);
        i
    }
    /// The index of constant `c` in the tape's table (shared between uses).
    fn constant(&mut self, c: Const) -> u32 {
        let key = (c.value.to_bits(), c.lo.to_bits(), c.hi.to_bits());
        match self.const_memo.get(&key) {
            Some(&ci) => ci,
            None => {
                let ci = self.tape.consts.len() as u32;
                self.tape.consts.push(c);
                self.const_memo.insert(key, ci);
                ci
            }
        }
    }
    fn emit(&mut self, e: &Expr) -> u32 {
        match e {
            Expr::Var(k) => self.push(Op::Var(*k as u8)),
            Expr::Const(c, _) => {
                let ci = self.constant(*c);
                self.push(Op::Const(ci))
            }
            Expr::Un(op, a) => {
                let a = self.emit(a);
                self.push(match op {
                    UnOp::Neg => Op::Neg(a),
                    UnOp::Sqrt => Op::Sqrt(a),
                    UnOp::Abs => Op::Abs(a),
                    UnOp::Sin => Op::Sin(a),
                    UnOp::Cos => Op::Cos(a),
                    UnOp::Exp => Op::Exp(a),
                    UnOp::Ln => Op::Ln(a),
                })
            }
            Expr::Pow(a, n) => {
                let a = self.emit(a);
                match n {
                    1 => a,
                    2 => self.push(Op::Square(a)),
                    _ => self.push(Op::Powi(a, *n)),
                }
            }
            Expr::Bin(op, a, b) => {
                // Fuse a constant operand into the instruction (see `Op::AddC`).
                let konst = |e: &Expr| match e {
                    Expr::Const(c, _) => Some(*c),
                    _ => None,
                };
                let (ca, cb) = (konst(a), konst(b));
                let fused = match (op, ca, cb) {
                    (_, Some(_), Some(_)) => None,
                    (BinOp::Add, _, Some(c)) => Some((Op::AddC as fn(u32, u32) -> Op, &**a, c)),
                    (BinOp::Add, Some(c), _) => Some((Op::AddC as fn(u32, u32) -> Op, &**b, c)),
                    (BinOp::Sub, _, Some(c)) => Some((Op::SubC as fn(u32, u32) -> Op, &**a, c)),
                    (BinOp::Sub, Some(c), _) => Some((Op::CSub as fn(u32, u32) -> Op, &**b, c)),
                    (BinOp::Mul, _, Some(c)) => Some((Op::MulC as fn(u32, u32) -> Op, &**a, c)),
                    (BinOp::Mul, Some(c), _) => Some((Op::MulC as fn(u32, u32) -> Op, &**b, c)),
                    (BinOp::Div, _, Some(c)) => Some((Op::DivC as fn(u32, u32) -> Op, &**a, c)),
                    _ => None,
                };
                if let Some((mk, e, c)) = fused {
                    let r = self.emit(e);
                    let ci = self.constant(c);
                    return self.push(mk(r, ci));
                }
                let a = self.emit(a);
                let b = self.emit(b);
                if *op == BinOp::Mul && a == b {
                    // x * x: the tight square (x·x over [-1, 2] is [0, 4], not [-2, 4]).
                    return self.push(Op::Square(a));
                }
                self.push(match op {
                    BinOp::Add => Op::Add(a, b),
                    BinOp::Sub => Op::Sub(a, b),
                    BinOp::Mul => Op::Mul(a, b),
                    BinOp::Div => Op::Div(a, b),
                    BinOp::Min => Op::Min(a, b),
                    BinOp::Max => Op::Max(a, b),
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The catalog's genus-2 polynomial compiles to fused constant instructions only:
    /// no separate constant loads, and squares instead of powers.
    #[test]
    fn genus2_constants_are_fused() {
        let f = crate::catalog::get("genus2").unwrap().function();
        let ops = f.tape().ops();
        eprintln!("{} ops: {:?}", ops.len(), ops);
        assert!(!ops.iter().any(|o| matches!(o, Op::Const(_) | Op::Powi(..))));
        assert!(ops.iter().filter(|o| matches!(o, Op::Square(_))).count() >= 4);
    }
}
