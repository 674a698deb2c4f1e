//! A formula compiled to a flat instruction tape (SSA: instruction `i` writes slot `i`),
//! with common subexpressions shared. One generic interpreter serves every [`Num`].
use super::expr::{BinOp, Expr, UnOp};
use super::number::{Const, Num};
use inari::Interval;
use std::collections::HashMap;

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
    Neg(u32),
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
    // `compile` establishes (every operand index is smaller than its instruction's).
    ops: Vec<Op>,
    consts: Vec<Const>,
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

    /// Evaluate at `vars`, using `regs` as scratch (cleared first; reuse it across
    /// calls to avoid allocation).
    #[inline]
    pub fn eval<T: Num>(&self, vars: &[T; 3], regs: &mut Vec<T>) -> T {
        regs.clear();
        for op in &self.ops {
            let r = |i: &u32| regs[*i as usize].clone();
            let v = match op {
                Op::Var(k) => vars[*k as usize].clone(),
                Op::Const(c) => T::cst(self.consts[*c as usize]),
                Op::Add(a, b) => r(a) + r(b),
                Op::Sub(a, b) => r(a) - r(b),
                Op::Mul(a, b) => r(a) * r(b),
                Op::Div(a, b) => r(a) / r(b),
                Op::Min(a, b) => r(a).min(&r(b)),
                Op::Max(a, b) => r(a).max(&r(b)),
                Op::Neg(a) => -r(a),
                Op::Square(a) => r(a).powi(2),
                Op::Powi(a, n) => r(a).powi(*n),
                Op::Sqrt(a) => r(a).sqrt(),
                Op::Abs(a) => r(a).abs(),
                Op::Sin(a) => r(a).sin(),
                Op::Cos(a) => r(a).cos(),
                Op::Exp(a) => r(a).exp(),
                Op::Ln(a) => r(a).ln(),
            };
            regs.push(v);
        }
        regs.pop().expect("a compiled tape is never empty")
    }

    /// Specialised f64 evaluation: the hot path of every lattice method.
    #[inline]
    pub fn eval_f64(&self, p: [f64; 3], regs: &mut Vec<f64>) -> f64 {
        regs.clear();
        regs.reserve(self.ops.len());
        for op in &self.ops {
            // SAFETY: SSA (see `Tape`): operand i < current length of `regs`.
            let r = |i: &u32| unsafe { *regs.get_unchecked(*i as usize) };
            let v = match *op {
                Op::Var(k) => p[k as usize],
                Op::Const(c) => self.consts[c as usize].value,
                Op::Add(a, b) => r(&a) + r(&b),
                Op::Sub(a, b) => r(&a) - r(&b),
                Op::Mul(a, b) => r(&a) * r(&b),
                Op::Div(a, b) => r(&a) / r(&b),
                Op::Min(a, b) => r(&a).min(r(&b)),
                Op::Max(a, b) => r(&a).max(r(&b)),
                Op::Neg(a) => -r(&a),
                Op::Square(a) => {
                    let x = r(&a);
                    x * x
                }
                Op::Powi(a, n) => r(&a).powi(n),
                Op::Sqrt(a) => r(&a).sqrt(),
                Op::Abs(a) => r(&a).abs(),
                Op::Sin(a) => r(&a).sin(),
                Op::Cos(a) => r(&a).cos(),
                Op::Exp(a) => r(&a).exp(),
                Op::Ln(a) => r(&a).ln(),
            };
            regs.push(v);
        }
        regs[regs.len() - 1]
    }
}

impl Tape {
    /// Specialised interval evaluation (the hot path of every pruning octree): direct
    /// inari calls, `sqr` for squares (tight), constants converted once per call.
    #[inline]
    pub fn eval_interval(&self, b: &[Interval; 3], regs: &mut Vec<Interval>) -> Interval {
        regs.clear();
        regs.reserve(self.ops.len());
        for op in &self.ops {
            // SAFETY: SSA (see `Tape`): operand i < current length of `regs`.
            let r = |i: &u32| unsafe { *regs.get_unchecked(*i as usize) };
            let v = match *op {
                Op::Var(k) => b[k as usize],
                Op::Const(c) => Interval::cst(self.consts[c as usize]),
                Op::Add(a, b) => r(&a) + r(&b),
                Op::Sub(a, b) => r(&a) - r(&b),
                Op::Mul(a, b) if a == b => r(&a).sqr(),
                Op::Mul(a, b) => r(&a) * r(&b),
                Op::Div(a, b) => r(&a) / r(&b),
                Op::Min(a, b) => r(&a).min(r(&b)),
                Op::Max(a, b) => r(&a).max(r(&b)),
                Op::Neg(a) => -r(&a),
                Op::Square(a) => r(&a).sqr(),
                Op::Powi(a, n) => Num::powi(&r(&a), n),
                Op::Sqrt(a) => r(&a).sqrt(),
                Op::Abs(a) => r(&a).abs(),
                Op::Sin(a) => Num::sin(&r(&a)),
                Op::Cos(a) => Num::cos(&r(&a)),
                Op::Exp(a) => Num::exp(&r(&a)),
                Op::Ln(a) => Num::ln(&r(&a)),
            };
            regs.push(v);
        }
        regs[regs.len() - 1]
    }
}

struct Builder {
    tape: Tape,
    memo: HashMap<Op, u32>,
    const_memo: HashMap<(u64, u64), u32>,
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
    fn emit(&mut self, e: &Expr) -> u32 {
        match e {
            Expr::Var(k) => self.push(Op::Var(*k as u8)),
            Expr::Const(c, _) => {
                let key = (c.lo.to_bits(), c.hi.to_bits());
                let ci = match self.const_memo.get(&key) {
                    Some(&ci) => ci,
                    None => {
                        let ci = self.tape.consts.len() as u32;
                        self.tape.consts.push(*c);
                        self.const_memo.insert(key, ci);
                        ci
                    }
                };
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
                let a = self.emit(a);
                let b = self.emit(b);
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
