//! Implicit functions f: R³ → R (or R² → R for curves; z is then ignored) and the
//! oracle every mesher queries: values, interval enclosures, gradients, Hessians.
//!
//! Like CGAL's surface oracle, [`Implicit`] answers only the primitive operations the
//! algorithms need. Three ways to provide one:
//! * [`Formula`]: text in the formula language, compiled to a tape;
//! * [`FromGeneric`]: Rust code generic over [`Num`] (every mode, rigorous);
//! * [`PointFn`]: a plain `Fn([f64;3]) -> f64` with a Lipschitz bound (intervals from
//!   the bound; used for signed distance to a mesh).
pub mod batch;
pub mod critical;
pub mod directed;
pub mod expr;
pub mod lanes;
pub mod number;
pub mod ops;
pub mod reach;
pub mod regularity;
pub mod sdf;
pub mod sparse;
pub mod tape;

pub use directed::Iv;
pub use expr::{parse, Expr};
pub use number::{Const, Dual, Hyper, Num};
pub use regularity::{Dec, Regularity};
pub use tape::Tape;

use crate::error::Result;
use inari::Interval;
use std::cell::RefCell;
use std::mem::MaybeUninit;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

/// A box as three intervals.
pub type IBox = [Interval; 3];

/// The oracle. `Send + Sync` so meshers can evaluate from rayon threads.
pub trait Implicit: Send + Sync {
    /// 2 for a curve f(x, y), 3 for a surface.
    fn dim(&self) -> usize {
        3
    }
    /// f at a point.
    fn eval(&self, p: [f64; 3]) -> f64;
    /// A rigorous enclosure of f over a box (when [`Implicit::is_rigorous`]).
    fn eval_interval(&self, b: &IBox) -> Interval;
    /// f at many points, given as coordinate slices (`p[0][i], p[1][i], p[2][i]` is
    /// point `i`), into `out[i]`: the values of [`Implicit::eval`], bit for bit.
    /// Formulas evaluate [`batch::LANES`] points per pass of the tape (SIMD); the
    /// default calls `eval` point by point. Panics if the slices differ in length.
    fn eval_batch(&self, p: [&[f64]; 3], out: &mut [f64]) {
        assert!(
            p.iter().all(|v| v.len() == out.len()),
            "batch slices of different lengths"
        );
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.eval([p[0][i], p[1][i], p[2][i]]);
        }
    }
    /// Enclosures over many boxes into `out`: the bounds of [`Implicit::eval_interval`],
    /// bit for bit (formulas: SIMD lanes, see [`batch`]). Panics if the lengths differ.
    fn eval_interval_batch(&self, b: &[IBox], out: &mut [Interval]) {
        assert!(b.len() == out.len(), "batch slices of different lengths");
        for (o, q) in out.iter_mut().zip(b) {
            *o = self.eval_interval(q);
        }
    }
    /// f and its gradient at a point.
    fn grad(&self, p: [f64; 3]) -> Dual<f64>;
    /// f and its gradient at many points into `out`: the values of [`Implicit::grad`],
    /// bit for bit (formulas and generic Rust functions: [`batch::LANES`] points per
    /// pass, see [`lanes`]); the default calls `grad` point by point. Panics if the
    /// lengths differ.
    fn grad_batch(&self, p: &[[f64; 3]], out: &mut [Dual<f64>]) {
        assert!(p.len() == out.len(), "batch slices of different lengths");
        for (o, &q) in out.iter_mut().zip(p) {
            *o = self.grad(q);
        }
    }
    /// Enclosures of f and of its gradient over a box.
    fn grad_interval(&self, b: &IBox) -> Dual<Interval>;
    /// f, gradient and Hessian at a point.
    fn hessian(&self, p: [f64; 3]) -> Hyper<f64>;
    /// Enclosures of f, gradient and Hessian over a box.
    fn hessian_interval(&self, b: &IBox) -> Hyper<Interval>;
    /// Are the interval methods proven enclosures? Meshers certify nothing otherwise.
    fn is_rigorous(&self) -> bool {
        true
    }
    /// Is f proven defined, continuous, smooth on the box (see [`Regularity`])? Every
    /// criterion that invokes a theorem about C¹ functions asks this before it
    /// certifies a box. The default proves nothing.
    fn regularity(&self, _b: &IBox) -> Regularity {
        Regularity::Undefined
    }
    /// A human-readable description (the formula, or a name).
    fn describe(&self) -> String {
        "<rust function>".into()
    }
    /// The expression tree, when f is a formula (the exact methods convert it to a
    /// polynomial: `algebraic::from_expr`). The default has none.
    fn expression(&self) -> Option<&Expr> {
        None
    }
}

fn ivars(b: &IBox) -> [Dual<Interval>; 3] {
    [0, 1, 2].map(|k| Dual::var(b[k], k))
}

/// Rust code generic over the number type: write it once, get every evaluation mode.
///
/// ```
/// use certmesh::implicit::{FromGeneric, GenericFn, Implicit, Num};
/// struct Sphere;
/// impl GenericFn for Sphere {
///     fn eval<T: Num>(&self, [x, y, z]: [T; 3]) -> T {
///         x.powi(2) + y.powi(2) + z.powi(2) - T::lit(1.0)
///     }
/// }
/// let f = FromGeneric(Sphere);
/// assert_eq!(f.eval([1.0, 0.0, 0.0]), 0.0);
/// assert_eq!(f.grad([1.0, 0.0, 0.0]).g, [2.0, 0.0, 0.0]);
/// ```
pub trait GenericFn: Send + Sync {
    fn eval<T: Num>(&self, p: [T; 3]) -> T;
    fn dim(&self) -> usize {
        3
    }
}

/// Adapter from [`GenericFn`] to [`Implicit`].
pub struct FromGeneric<G>(pub G);

impl<G: GenericFn> Implicit for FromGeneric<G> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn eval(&self, p: [f64; 3]) -> f64 {
        self.0.eval(p)
    }
    fn eval_interval(&self, b: &IBox) -> Interval {
        self.0.eval(*b)
    }
    fn grad_batch(&self, p: &[[f64; 3]], out: &mut [Dual<f64>]) {
        lanes::grad_batch(p, out, |v| self.0.eval(v))
    }
    fn grad(&self, p: [f64; 3]) -> Dual<f64> {
        self.0.eval([0, 1, 2].map(|k| Dual::var(p[k], k)))
    }
    fn grad_interval(&self, b: &IBox) -> Dual<Interval> {
        self.0.eval(ivars(b))
    }
    fn hessian(&self, p: [f64; 3]) -> Hyper<f64> {
        self.0.eval([0, 1, 2].map(|k| Hyper::var(p[k], k)))
    }
    fn hessian_interval(&self, b: &IBox) -> Hyper<Interval> {
        self.0.eval([0, 1, 2].map(|k| Hyper::var(b[k], k)))
    }
    fn regularity(&self, b: &IBox) -> Regularity {
        regularity::finish(self.0.eval(b.map(|x| Dec::var(Iv::from_interval(x)))))
    }
}

/// A parsed and compiled formula.
#[derive(Clone, Debug)]
pub struct Formula {
    text: String,
    expr: Expr,
    tape: Tape,
    /// The tape compiled for sparse interval gradients (polynomial tapes only).
    sparse: Option<sparse::GradTape>,
    dim: usize,
}

/// Tapes up to this length evaluate in f64 and `Iv` with registers on the stack.
const STACK_REGS: usize = 64;

thread_local! {
    static S_F64: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
    static S_IV: RefCell<Vec<Iv>> = const { RefCell::new(Vec::new()) };
    static S_DF: RefCell<Vec<Dual<f64>>> = const { RefCell::new(Vec::new()) };
    static S_DI: RefCell<Vec<Dual<Iv>>> = const { RefCell::new(Vec::new()) };
    static S_HF: RefCell<Vec<Hyper<f64>>> = const { RefCell::new(Vec::new()) };
    static S_HI: RefCell<Vec<Hyper<Iv>>> = const { RefCell::new(Vec::new()) };
    static S_DEC: RefCell<Vec<Dec>> = const { RefCell::new(Vec::new()) };
}

impl Formula {
    /// Parse a surface formula f(x, y, z).
    pub fn surface(text: &str) -> Result<Self> {
        Self::with_dim(text, 3)
    }
    /// Parse a curve formula f(x, y).
    pub fn curve(text: &str) -> Result<Self> {
        Self::with_dim(text, 2)
    }
    pub fn with_dim(text: &str, dim: usize) -> Result<Self> {
        let expr = parse(text, dim)?;
        let tape = Tape::compile(&expr);
        Ok(Formula {
            text: text.to_string(),
            expr,
            sparse: sparse::GradTape::compile(&tape),
            tape,
            dim,
        })
    }
    pub fn text(&self) -> &str {
        &self.text
    }
    pub fn expr(&self) -> &Expr {
        &self.expr
    }
    pub fn tape(&self) -> &Tape {
        &self.tape
    }
    /// The sparse gradient program, when the tape is polynomial.
    pub fn sparse_gradient(&self) -> Option<&sparse::GradTape> {
        self.sparse.as_ref()
    }
    /// [`Implicit::grad_interval`] by dense forward mode on `Dual<Iv>` (every partial
    /// computed): the reference the sparse path is tested against.
    pub fn grad_interval_dense(&self, b: &IBox) -> Dual<Iv> {
        let v = [0, 1, 2].map(|k| Dual::var(Iv::from_interval(b[k]), k));
        if self.tape.len() <= STACK_REGS {
            let mut regs = [MaybeUninit::<Dual<Iv>>::uninit(); STACK_REGS];
            self.tape.eval_in(&v, &mut regs)
        } else {
            S_DI.with(|s| self.tape.eval(&v, &mut s.borrow_mut()))
        }
    }
}

impl Implicit for Formula {
    fn dim(&self) -> usize {
        self.dim
    }
    #[inline]
    fn eval(&self, p: [f64; 3]) -> f64 {
        // Registers on the stack for ordinary formulas (no thread-local, no borrow
        // flag, no initialisation: see `Tape::eval_f64_in`).
        if self.tape.len() <= STACK_REGS {
            let mut regs = [MaybeUninit::<f64>::uninit(); STACK_REGS];
            self.tape.eval_f64_in(p, &mut regs)
        } else {
            S_F64.with(|s| self.tape.eval_f64(p, &mut s.borrow_mut()))
        }
    }
    #[inline]
    fn eval_interval(&self, b: &IBox) -> Interval {
        let v = b.map(Iv::from_interval);
        if self.tape.len() <= STACK_REGS {
            let mut regs = [MaybeUninit::<Iv>::uninit(); STACK_REGS];
            self.tape.eval_iv_in(v, &mut regs).to_interval()
        } else {
            S_IV.with(|s| self.tape.eval_iv(v, &mut s.borrow_mut()).to_interval())
        }
    }
    fn eval_batch(&self, p: [&[f64]; 3], out: &mut [f64]) {
        batch::eval_points(&self.tape, p, out)
    }
    fn eval_interval_batch(&self, b: &[IBox], out: &mut [Interval]) {
        batch::eval_boxes(&self.tape, b, out)
    }
    fn grad_batch(&self, p: &[[f64; 3]], out: &mut [Dual<f64>]) {
        let mut regs = Vec::with_capacity(self.tape.len());
        lanes::grad_batch(p, out, |v| self.tape.eval(&v, &mut regs))
    }
    fn grad(&self, p: [f64; 3]) -> Dual<f64> {
        let v = [0, 1, 2].map(|k| Dual::var(p[k], k));
        if self.tape.len() <= STACK_REGS {
            let mut regs = [MaybeUninit::<Dual<f64>>::uninit(); STACK_REGS];
            return self.tape.eval_in(&v, &mut regs);
        }
        S_DF.with(|s| self.tape.eval(&v, &mut s.borrow_mut()))
    }
    fn grad_interval(&self, b: &IBox) -> Dual<Interval> {
        // Derivatives over the fast kernel `Iv` (same bounds as inari, see `directed`);
        // polynomial tapes skip the structurally zero partials (`sparse`, same values).
        if let Some(d) = self
            .sparse
            .as_ref()
            .and_then(|s| s.eval(b.map(Iv::from_interval)))
        {
            return Dual {
                v: d.v.to_interval(),
                g: d.g.map(Iv::to_interval),
            };
        }
        let d = self.grad_interval_dense(b);
        Dual {
            v: d.v.to_interval(),
            g: d.g.map(Iv::to_interval),
        }
    }
    // Hessians keep the thread-local workspace and `Tape::eval`: for their large
    // registers (80 and 160 bytes) `Tape::eval_in` on stack registers is slower
    // (issue 20, genus 2, CPU clock, one run: 2.40 M/s on 64 or 48 stack registers,
    // 2.68 M/s here).
    fn hessian(&self, p: [f64; 3]) -> Hyper<f64> {
        let v = [0, 1, 2].map(|k| Hyper::var(p[k], k));
        S_HF.with(|s| self.tape.eval(&v, &mut s.borrow_mut()))
    }
    fn hessian_interval(&self, b: &IBox) -> Hyper<Interval> {
        let v = [0, 1, 2].map(|k| Hyper::var(Iv::from_interval(b[k]), k));
        let h = S_HI.with(|s| self.tape.eval(&v, &mut s.borrow_mut()));
        Hyper {
            v: h.v.to_interval(),
            g: h.g.map(Iv::to_interval),
            h: h.h.map(Iv::to_interval),
        }
    }
    fn regularity(&self, b: &IBox) -> Regularity {
        // A polynomial tape (the sparse program exists only for +, −, ×, squares,
        // non-negative integer powers and division by constants that exclude 0) is
        // smooth on every non-empty box: no tape pass needed.
        if self.sparse.is_some() && b.iter().all(|x| !x.is_empty()) {
            return Regularity::Smooth;
        }
        let v = b.map(|x| Dec::var(Iv::from_interval(x)));
        regularity::finish(S_DEC.with(|s| self.tape.eval(&v, &mut s.borrow_mut())))
    }
    fn describe(&self) -> String {
        self.text.clone()
    }
    fn expression(&self) -> Option<&Expr> {
        Some(&self.expr)
    }
}

/// A plain point function with a gradient closure and a Lipschitz bound `lipschitz`
/// (|f(p) - f(q)| <= L |p - q|). Interval enclosures come from the bound around the
/// box centre; they are rigorous only if the bound is and f is computed exactly, so
/// [`Implicit::is_rigorous`] is false: meshers built on it never claim a certificate.
/// Derivative enclosures are the whole line (nothing is known about them).
pub struct PointFn<F, G> {
    pub f: F,
    pub gradient: G,
    pub lipschitz: f64,
    pub dim: usize,
    pub name: String,
}

impl<F, G> Implicit for PointFn<F, G>
where
    F: Fn([f64; 3]) -> f64 + Send + Sync,
    G: Fn([f64; 3]) -> [f64; 3] + Send + Sync,
{
    fn dim(&self) -> usize {
        self.dim
    }
    fn eval(&self, p: [f64; 3]) -> f64 {
        (self.f)(p)
    }
    fn eval_interval(&self, b: &IBox) -> Interval {
        let c = [0, 1, 2].map(|k| b[k].mid());
        let r = [0, 1, 2].map(|k| b[k].rad());
        let rad = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt() * self.lipschitz;
        let v = (self.f)(c);
        // Widen by a relative epsilon for the rounding of v and rad.
        let slack = 1e-12 * (v.abs() + rad);
        Interval::try_from((v - rad - slack, v + rad + slack)).unwrap_or(Interval::ENTIRE)
    }
    fn grad(&self, p: [f64; 3]) -> Dual<f64> {
        Dual {
            v: (self.f)(p),
            g: (self.gradient)(p),
        }
    }
    fn grad_interval(&self, b: &IBox) -> Dual<Interval> {
        Dual {
            v: self.eval_interval(b),
            g: [Interval::ENTIRE; 3],
        }
    }
    fn hessian(&self, p: [f64; 3]) -> Hyper<f64> {
        let d = self.grad(p);
        Hyper {
            v: d.v,
            g: d.g,
            h: [f64::NAN; 6],
        }
    }
    fn hessian_interval(&self, b: &IBox) -> Hyper<Interval> {
        Hyper {
            v: self.eval_interval(b),
            g: [Interval::ENTIRE; 3],
            h: [Interval::ENTIRE; 6],
        }
    }
    fn is_rigorous(&self) -> bool {
        false
    }
    /// Lipschitz, hence continuous; nothing is known about derivatives.
    fn regularity(&self, _b: &IBox) -> Regularity {
        Regularity::Continuous
    }
    fn describe(&self) -> String {
        self.name.clone()
    }
}

/// Evaluation counts, by kind.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize, PartialEq, Eq)]
pub struct EvalCounts {
    pub points: u64,
    pub intervals: u64,
    pub gradients: u64,
    pub interval_gradients: u64,
    pub hessians: u64,
    /// Regularity checks ([`Implicit::regularity`]: one decorated interval evaluation
    /// each), counted apart so the interval counts stay comparable with runs before
    /// the checks existed.
    #[serde(default)]
    pub regularity: u64,
}

impl EvalCounts {
    /// All evaluations of any kind.
    pub fn total(&self) -> u64 {
        self.points
            + self.intervals
            + self.gradients
            + self.interval_gradients
            + self.hessians
            + self.regularity
    }
}

/// Wraps an oracle and counts every query, so the harness reports evaluations the same
/// way for every mesher (a mesher cannot under-report).
pub struct Counted<'a> {
    inner: &'a dyn Implicit,
    c: Shards,
}

/// The six counters of [`EvalCounts`] in one cache line per shard; each rayon thread
/// counts in its own shard, so parallel meshers do not contend for one line (a
/// shared counter cost a third of a stuffing run on 2 threads).
#[derive(Default)]
#[repr(align(64))]
struct Shard([AtomicU64; 6]);

const SHARDS: usize = 8;

#[derive(Default)]
struct Shards([Shard; SHARDS]);

impl Shards {
    #[inline]
    fn add(&self, kind: usize, n: u64) {
        let s = rayon::current_thread_index().map_or(0, |i| (i + 1) % SHARDS);
        self.0[s].0[kind].fetch_add(n, Relaxed);
    }
    fn load(&self, kind: usize) -> u64 {
        self.0.iter().map(|s| s.0[kind].load(Relaxed)).sum()
    }
}

impl<'a> Counted<'a> {
    pub fn new(inner: &'a dyn Implicit) -> Self {
        Counted {
            inner,
            c: Default::default(),
        }
    }
    pub fn counts(&self) -> EvalCounts {
        EvalCounts {
            points: self.c.load(0),
            intervals: self.c.load(1),
            gradients: self.c.load(2),
            interval_gradients: self.c.load(3),
            hessians: self.c.load(4),
            regularity: self.c.load(5),
        }
    }
}

impl Implicit for Counted<'_> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    #[inline]
    fn eval(&self, p: [f64; 3]) -> f64 {
        self.c.add(0, 1);
        self.inner.eval(p)
    }
    fn eval_interval(&self, b: &IBox) -> Interval {
        self.c.add(1, 1);
        self.inner.eval_interval(b)
    }
    fn eval_batch(&self, p: [&[f64]; 3], out: &mut [f64]) {
        self.c.add(0, out.len() as u64);
        self.inner.eval_batch(p, out)
    }
    fn eval_interval_batch(&self, b: &[IBox], out: &mut [Interval]) {
        self.c.add(1, out.len() as u64);
        self.inner.eval_interval_batch(b, out)
    }
    fn grad(&self, p: [f64; 3]) -> Dual<f64> {
        self.c.add(2, 1);
        self.inner.grad(p)
    }
    fn grad_batch(&self, p: &[[f64; 3]], out: &mut [Dual<f64>]) {
        self.c.add(2, out.len() as u64);
        self.inner.grad_batch(p, out)
    }
    fn grad_interval(&self, b: &IBox) -> Dual<Interval> {
        self.c.add(3, 1);
        self.inner.grad_interval(b)
    }
    fn hessian(&self, p: [f64; 3]) -> Hyper<f64> {
        self.c.add(4, 1);
        self.inner.hessian(p)
    }
    fn hessian_interval(&self, b: &IBox) -> Hyper<Interval> {
        self.c.add(4, 1);
        self.inner.hessian_interval(b)
    }
    fn is_rigorous(&self) -> bool {
        self.inner.is_rigorous()
    }
    fn regularity(&self, b: &IBox) -> Regularity {
        self.c.add(5, 1);
        self.inner.regularity(b)
    }
    fn describe(&self) -> String {
        self.inner.describe()
    }
    fn expression(&self) -> Option<&Expr> {
        self.inner.expression()
    }
}

/// An oracle moved by a rigid motion: g(p) = f(R p + t). Used by the "generic position"
/// remedy of subdivision meshers (the chapter's shifted grid). Derivatives follow the
/// chain rule with the rotation.
pub struct Transformed<'a> {
    pub inner: &'a dyn Implicit,
    /// Row-major rotation matrix R.
    pub rot: [[f64; 3]; 3],
    pub shift: [f64; 3],
}

impl Transformed<'_> {
    fn map_f(&self, p: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|i| {
            self.rot[i][0] * p[0] + self.rot[i][1] * p[1] + self.rot[i][2] * p[2] + self.shift[i]
        })
    }
    fn map_i(&self, b: &IBox) -> IBox {
        let c = |x: f64| number::point(x);
        [0, 1, 2].map(|i| {
            c(self.rot[i][0]) * b[0]
                + c(self.rot[i][1]) * b[1]
                + c(self.rot[i][2]) * b[2]
                + c(self.shift[i])
        })
    }
    fn pull_g<T: Num>(&self, g: [T; 3], cv: impl Fn(f64) -> T) -> [T; 3] {
        // ∇g(p) = Rᵀ ∇f(Rp + t)
        [0, 1, 2].map(|j| {
            cv(self.rot[0][j]) * g[0].clone()
                + cv(self.rot[1][j]) * g[1].clone()
                + cv(self.rot[2][j]) * g[2].clone()
        })
    }
    fn pull_h<T: Num>(&self, h: [T; 6], cv: impl Fn(f64) -> T) -> [T; 6] {
        // H_g = Rᵀ H_f R
        let hf = |i: usize, j: usize| h[number::hidx(i, j)].clone();
        let mut out: Vec<T> = Vec::with_capacity(6);
        for (a, b) in [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)] {
            let mut acc = cv(0.0);
            for i in 0..3 {
                for j in 0..3 {
                    acc = acc + cv(self.rot[i][a] * self.rot[j][b]) * hf(i, j);
                }
            }
            out.push(acc);
        }
        [0, 1, 2, 3, 4, 5].map(|k| out[k].clone())
    }
}

impl Implicit for Transformed<'_> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn eval(&self, p: [f64; 3]) -> f64 {
        self.inner.eval(self.map_f(p))
    }
    fn eval_interval(&self, b: &IBox) -> Interval {
        self.inner.eval_interval(&self.map_i(b))
    }
    fn grad(&self, p: [f64; 3]) -> Dual<f64> {
        let d = self.inner.grad(self.map_f(p));
        Dual {
            v: d.v,
            g: self.pull_g(d.g, |x| x),
        }
    }
    fn grad_interval(&self, b: &IBox) -> Dual<Interval> {
        let d = self.inner.grad_interval(&self.map_i(b));
        Dual {
            v: d.v,
            g: self.pull_g(d.g, number::point),
        }
    }
    fn hessian(&self, p: [f64; 3]) -> Hyper<f64> {
        let d = self.inner.hessian(self.map_f(p));
        Hyper {
            v: d.v,
            g: self.pull_g(d.g, |x| x),
            h: self.pull_h(d.h, |x| x),
        }
    }
    fn hessian_interval(&self, b: &IBox) -> Hyper<Interval> {
        let d = self.inner.hessian_interval(&self.map_i(b));
        // Products rot[i][a]*rot[j][b] are rounded: enclose them by widening one ulp.
        let cv = |x: f64| {
            Interval::try_from((number::next_down(x), number::next_up(x)))
                .unwrap_or(Interval::ENTIRE)
        };
        Hyper {
            v: d.v,
            g: self.pull_g(d.g, number::point),
            h: self.pull_h(d.h, cv),
        }
    }
    fn is_rigorous(&self) -> bool {
        self.inner.is_rigorous()
    }
    fn regularity(&self, b: &IBox) -> Regularity {
        self.inner.regularity(&self.map_i(b))
    }
    fn describe(&self) -> String {
        format!("{} (moved to generic position)", self.inner.describe())
    }
}
