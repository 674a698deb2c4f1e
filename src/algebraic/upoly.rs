//! Dense univariate integer polynomials (`Vec<BigInt>`, constant term first): ring
//! operations, pseudo-division, content and primitive part, gcd by the primitive
//! remainder sequence, square-free part, exact evaluation and signs at rationals.
use num_bigint::{BigInt, Sign};
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

/// A polynomial Σ c\[i\]·xⁱ with integer coefficients; no trailing zeros (the zero
/// polynomial is the empty vector).
#[derive(Clone, Debug, PartialEq, Eq, Hash, Default)]
pub struct UPoly {
    pub c: Vec<BigInt>,
}

impl UPoly {
    pub fn new(mut c: Vec<BigInt>) -> Self {
        while c.last().is_some_and(|x| x.is_zero()) {
            c.pop();
        }
        UPoly { c }
    }
    pub fn from_i64(c: &[i64]) -> Self {
        Self::new(c.iter().map(|&x| BigInt::from(x)).collect())
    }
    pub fn zero() -> Self {
        UPoly { c: Vec::new() }
    }
    pub fn constant(a: BigInt) -> Self {
        Self::new(vec![a])
    }
    /// x − a/b scaled to b·x − a.
    pub fn linear_root(a: &BigRational) -> Self {
        Self::new(vec![-a.numer().clone(), a.denom().clone()])
    }
    pub fn is_zero(&self) -> bool {
        self.c.is_empty()
    }
    /// Degree; −1 for the zero polynomial.
    pub fn deg(&self) -> isize {
        self.c.len() as isize - 1
    }
    pub fn lc(&self) -> BigInt {
        self.c.last().cloned().unwrap_or_default()
    }
    pub fn coef(&self, i: usize) -> BigInt {
        self.c.get(i).cloned().unwrap_or_default()
    }
    pub fn is_constant(&self) -> bool {
        self.c.len() <= 1
    }
    pub fn add(&self, o: &Self) -> Self {
        let n = self.c.len().max(o.c.len());
        Self::new((0..n).map(|i| self.coef(i) + o.coef(i)).collect())
    }
    pub fn sub(&self, o: &Self) -> Self {
        let n = self.c.len().max(o.c.len());
        Self::new((0..n).map(|i| self.coef(i) - o.coef(i)).collect())
    }
    pub fn neg(&self) -> Self {
        UPoly {
            c: self.c.iter().map(|x| -x).collect(),
        }
    }
    pub fn mul(&self, o: &Self) -> Self {
        if self.is_zero() || o.is_zero() {
            return Self::zero();
        }
        let mut r = vec![BigInt::zero(); self.c.len() + o.c.len() - 1];
        for (i, a) in self.c.iter().enumerate() {
            if a.is_zero() {
                continue;
            }
            for (j, b) in o.c.iter().enumerate() {
                r[i + j] += a * b;
            }
        }
        Self::new(r)
    }
    pub fn scale(&self, k: &BigInt) -> Self {
        Self::new(self.c.iter().map(|x| x * k).collect())
    }
    pub fn pow(&self, e: u32) -> Self {
        let mut r = Self::constant(BigInt::one());
        for _ in 0..e {
            r = r.mul(self);
        }
        r
    }
    /// Multiply by xᵏ.
    pub fn shift_up(&self, k: usize) -> Self {
        if self.is_zero() {
            return Self::zero();
        }
        let mut c = vec![BigInt::zero(); k];
        c.extend(self.c.iter().cloned());
        UPoly { c }
    }
    pub fn derivative(&self) -> Self {
        Self::new(
            self.c
                .iter()
                .enumerate()
                .skip(1)
                .map(|(i, a)| a * BigInt::from(i))
                .collect(),
        )
    }
    /// The gcd of the coefficients (non-negative; 0 for the zero polynomial).
    pub fn content(&self) -> BigInt {
        let mut g = BigInt::zero();
        for a in &self.c {
            g = g.gcd(a);
            if g.is_one() {
                break;
            }
        }
        g
    }
    /// Divided by its content, with a positive leading coefficient.
    pub fn primitive(&self) -> Self {
        if self.is_zero() {
            return Self::zero();
        }
        let mut g = self.content();
        if self.lc().is_negative() {
            g = -g;
        }
        UPoly {
            c: self.c.iter().map(|x| x / &g).collect(),
        }
    }
    /// Pseudo-remainder: lc(b)^(deg a − deg b + 1)·a mod b. `b` must be non-zero.
    pub fn prem(&self, b: &Self) -> Self {
        assert!(!b.is_zero(), "pseudo-division by zero");
        let db = b.c.len() - 1;
        let lb = b.lc();
        let mut r = self.clone();
        if r.c.len() <= db {
            return r;
        }
        let mut steps = r.c.len() - db;
        while !r.is_zero() && r.c.len() > db {
            let k = r.c.len() - 1 - db;
            let lr = r.lc();
            // r = lb·r − lr·x^k·b
            let mut c: Vec<BigInt> = r.c.iter().map(|x| x * &lb).collect();
            for (j, bj) in b.c.iter().enumerate() {
                c[j + k] -= &lr * bj;
            }
            r = Self::new(c);
            steps -= 1;
        }
        if steps > 0 {
            let f = num_traits::pow(lb, steps);
            r = r.scale(&f);
        }
        r
    }
    /// Exact quotient a / b over Z; `None` if b does not divide a in Z\[x\].
    pub fn div_exact(&self, b: &Self) -> Option<Self> {
        if b.is_zero() {
            return None;
        }
        if self.is_zero() {
            return Some(Self::zero());
        }
        if self.c.len() < b.c.len() {
            return None;
        }
        let db = b.c.len() - 1;
        let lb = b.lc();
        let mut r = self.c.clone();
        let mut q = vec![BigInt::zero(); r.len() - db];
        for k in (0..q.len()).rev() {
            let t = &r[k + db];
            let (qk, rem) = t.div_rem(&lb);
            if !rem.is_zero() {
                return None;
            }
            for (j, bj) in b.c.iter().enumerate() {
                r[j + k] -= &qk * bj;
            }
            q[k] = qk;
        }
        if r.iter().any(|x| !x.is_zero()) {
            return None;
        }
        Some(Self::new(q))
    }
    /// Primitive gcd (positive leading coefficient), by the modular method
    /// (`modgcd`: images mod word-size primes, Chinese remaindering, verified by trial
    /// division, so exact), falling back to the primitive remainder sequence.
    pub fn gcd(&self, o: &Self) -> Self {
        let (a, b) = (self.primitive(), o.primitive());
        if a.is_zero() {
            return b;
        }
        if b.is_zero() {
            return a;
        }
        if a.deg() == 0 || b.deg() == 0 {
            return Self::constant(BigInt::one());
        }
        super::modgcd::gcd_primitive(&a, &b).unwrap_or_else(|| a.gcd_prs(&b))
    }
    /// Primitive gcd (positive leading coefficient) by the primitive remainder sequence
    /// (the reference the modular gcd is tested against, and its fallback).
    pub fn gcd_prs(&self, o: &Self) -> Self {
        let (mut a, mut b) = (self.primitive(), o.primitive());
        if a.is_zero() {
            return b;
        }
        if b.is_zero() {
            return a;
        }
        if a.deg() < b.deg() {
            std::mem::swap(&mut a, &mut b);
        }
        while !b.is_zero() {
            let r = a.prem(&b).primitive();
            a = b;
            b = r;
        }
        a.primitive()
    }
    /// The square-free part p / gcd(p, p'), primitive.
    pub fn squarefree(&self) -> Self {
        if self.deg() <= 0 {
            return self.primitive();
        }
        let g = self.gcd(&self.derivative());
        self.primitive()
            .div_exact(&g)
            .expect("gcd divides")
            .primitive()
    }
    /// p(a/b)·bⁿ (n = deg p), an integer with the sign of p(a/b) when b > 0.
    pub fn eval_hom(&self, a: &BigInt, b: &BigInt) -> BigInt {
        // Horner on Σ c_i a^i b^(n−i): acc_k = acc_(k−1)·a + c_(n−k)·b^k.
        let mut acc = BigInt::zero();
        let mut bpow = BigInt::one();
        for (k, c) in self.c.iter().rev().enumerate() {
            if k == 0 {
                acc = c.clone();
            } else {
                bpow *= b;
                acc = acc * a + c * &bpow;
            }
        }
        acc
    }
    /// p at a rational, exactly.
    pub fn eval_q(&self, x: &BigRational) -> BigRational {
        let mut acc = BigRational::zero();
        for c in self.c.iter().rev() {
            acc = acc * x + BigRational::from_integer(c.clone());
        }
        acc
    }
    /// The sign of p at a rational: −1, 0 or 1.
    pub fn sign_at(&self, x: &BigRational) -> i32 {
        sign(&self.eval_hom(x.numer(), x.denom()))
    }
    /// p(−x).
    pub fn reflect(&self) -> Self {
        Self::new(
            self.c
                .iter()
                .enumerate()
                .map(|(i, a)| if i % 2 == 1 { -a } else { a.clone() })
                .collect(),
        )
    }
    /// xⁿ·p(1/x).
    pub fn reverse(&self) -> Self {
        Self::new(self.c.iter().rev().cloned().collect())
    }
    /// p(x + 1).
    pub fn taylor_shift1(&self) -> Self {
        let mut a = self.c.clone();
        let n = a.len();
        for i in 0..n {
            for j in (i..n.saturating_sub(1)).rev() {
                let t = a[j + 1].clone();
                a[j] += t;
            }
        }
        Self::new(a)
    }
    /// 2^(k·n)·p(x / 2^k) (k ≥ 0): coefficient i times 2^(k(n−i)).
    pub fn scale_down_pow2(&self, k: u64) -> Self {
        let n = self.c.len().saturating_sub(1) as u64;
        Self::new(
            self.c
                .iter()
                .enumerate()
                .map(|(i, a)| a << ((n - i as u64) * k))
                .collect(),
        )
    }
    /// p(2^k·x): coefficient i times 2^(k·i).
    pub fn scale_up_pow2(&self, k: u64) -> Self {
        Self::new(
            self.c
                .iter()
                .enumerate()
                .map(|(i, a)| a << (i as u64 * k))
                .collect(),
        )
    }
    /// The number of sign changes of the coefficient sequence (zeros skipped).
    pub fn sign_variations(&self) -> usize {
        let mut v = 0;
        let mut last = 0;
        for a in &self.c {
            let s = sign(a);
            if s != 0 {
                if last != 0 && s != last {
                    v += 1;
                }
                last = s;
            }
        }
        v
    }
    /// Bits of the largest coefficient.
    pub fn max_bits(&self) -> u64 {
        self.c.iter().map(|a| a.bits()).max().unwrap_or(0)
    }
    /// Divide by (x − r) for an exact root r = a/b: returns the quotient of (b·x − a).
    pub fn deflate(&self, r: &BigRational) -> Self {
        self.div_exact(&Self::linear_root(r))
            .expect("deflate at an exact root")
    }
}

pub fn sign(a: &BigInt) -> i32 {
    match a.sign() {
        Sign::Minus => -1,
        Sign::NoSign => 0,
        Sign::Plus => 1,
    }
}

pub fn q(a: i64, b: i64) -> BigRational {
    BigRational::new(BigInt::from(a), BigInt::from(b))
}

pub fn qi(a: i64) -> BigRational {
    BigRational::from_integer(BigInt::from(a))
}

/// Sturm count: the number of distinct real roots of p in (a, b\] (reference method for
/// the tests; the sweep uses Descartes).
pub fn sturm_count(p: &UPoly, a: &BigRational, b: &BigRational) -> usize {
    let seq = sturm_sequence(p);
    if seq.is_empty() {
        return 0;
    }
    let var = |x: &BigRational| {
        let mut v = 0;
        let mut last = 0;
        for s in seq.iter() {
            let t = s.sign_at(x);
            if t != 0 {
                if last != 0 && t != last {
                    v += 1;
                }
                last = t;
            }
        }
        v as isize
    };
    (var(a) - var(b)).max(0) as usize
}

type SturmMemo = std::cell::RefCell<std::collections::HashMap<UPoly, std::rc::Rc<Vec<UPoly>>>>;
thread_local! {
    static STURM: SturmMemo = Default::default();
}

/// Forget the remembered Sturm sequences (called with the gcd memo's reset at the start
/// of every sweep and every check, so each run does its own work).
pub fn clear_sturm_memo() {
    STURM.with(|m| m.borrow_mut().clear());
}

/// The Sturm sequence of p's square-free part (empty when it is constant), remembered
/// within a run: the checker counts roots of the same event or fibre polynomial in
/// many intervals, and the sequence depends on p only.
fn sturm_sequence(p: &UPoly) -> std::rc::Rc<Vec<UPoly>> {
    if let Some(s) = STURM.with(|m| m.borrow().get(p).cloned()) {
        return s;
    }
    let seq = std::rc::Rc::new(sturm_sequence_uncached(p));
    STURM.with(|m| m.borrow_mut().insert(p.clone(), seq.clone()));
    seq
}

fn sturm_sequence_uncached(p: &UPoly) -> Vec<UPoly> {
    let p = p.squarefree();
    if p.deg() <= 0 {
        return Vec::new();
    }
    let mut seq = vec![p.clone(), p.derivative()];
    loop {
        let n = seq.len();
        let pr = seq[n - 2].prem(&seq[n - 1]);
        if pr.is_zero() {
            break;
        }
        // prem = lc(b)^e·rem: the true remainder has the sign of lc(prem)·sign(lc b)^e;
        // the next Sturm polynomial is −rem up to a positive factor.
        let e = seq[n - 2].deg() - seq[n - 1].deg() + 1;
        let s_scale = if seq[n - 1].lc().is_negative() && e % 2 == 1 {
            -1
        } else {
            1
        };
        let s_true = sign(&pr.lc()) * s_scale;
        let mut r = pr.primitive();
        if sign(&r.lc()) != -s_true {
            r = r.neg();
        }
        seq.push(r);
    }
    seq
}
