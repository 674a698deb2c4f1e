//! Bivariate integer polynomials as polynomials in y over Z\[x\] (`c[j]` is the
//! coefficient of yʲ), and the conversion of a formula that is a polynomial with
//! rational coefficients into one (the oracle's polynomial capability).
use super::upoly::UPoly;
use crate::error::{Error, Result};
use crate::implicit::expr::{BinOp, Expr, UnOp};
use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};
use std::collections::BTreeMap;

/// f(x, y) = Σ c\[j\](x)·yʲ, no trailing zero coefficients.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct BiPoly {
    pub c: Vec<UPoly>,
}

/// The largest total degree a formula may expand to (a budget against `(x+y)^1000`).
pub const MAX_FORMULA_DEGREE: u32 = 64;

impl BiPoly {
    pub fn new(mut c: Vec<UPoly>) -> Self {
        while c.last().is_some_and(|p| p.is_zero()) {
            c.pop();
        }
        BiPoly { c }
    }
    /// From integer terms (coefficient, power of x, power of y).
    pub fn from_terms(t: &[(i64, usize, usize)]) -> Self {
        let mut m: BTreeMap<(usize, usize), BigInt> = BTreeMap::new();
        for &(a, i, j) in t {
            *m.entry((i, j)).or_default() += BigInt::from(a);
        }
        Self::from_map(&m)
    }
    /// A dense polynomial of total degree `d` with coefficients in [−10, 10] drawn by a
    /// linear congruential generator from `seed` (the benches' and the CGAL script's
    /// dense random curves; the coefficient of y^d is made non-zero).
    pub fn dense_random(d: usize, seed: u64) -> Self {
        let mut s = seed;
        let mut t = Vec::new();
        for i in 0..=d {
            for j in 0..=d - i {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let mut c = ((s >> 33) % 21) as i64 - 10;
                if i + j == d && j == d && c == 0 {
                    c = 1;
                }
                t.push((c, i, j));
            }
        }
        Self::from_terms(&t)
    }
    fn from_map(m: &BTreeMap<(usize, usize), BigInt>) -> Self {
        let dy = m.keys().map(|k| k.1).max().map_or(0, |d| d + 1);
        let mut c = vec![Vec::<BigInt>::new(); dy];
        for (&(i, j), a) in m {
            if c[j].len() <= i {
                c[j].resize(i + 1, BigInt::zero());
            }
            c[j][i] += a;
        }
        Self::new(c.into_iter().map(UPoly::new).collect())
    }
    pub fn is_zero(&self) -> bool {
        self.c.is_empty()
    }
    pub fn deg_y(&self) -> isize {
        self.c.len() as isize - 1
    }
    pub fn deg_x(&self) -> isize {
        self.c.iter().map(|p| p.deg()).max().unwrap_or(-1)
    }
    /// Total degree (−1 for zero).
    pub fn total_degree(&self) -> isize {
        self.c
            .iter()
            .enumerate()
            .filter(|(_, p)| !p.is_zero())
            .map(|(j, p)| j as isize + p.deg())
            .max()
            .unwrap_or(-1)
    }
    pub fn max_bits(&self) -> u64 {
        self.c.iter().map(|p| p.max_bits()).max().unwrap_or(0)
    }
    /// Coefficient of xⁱyʲ.
    pub fn coef(&self, i: usize, j: usize) -> BigInt {
        self.c.get(j).map(|p| p.coef(i)).unwrap_or_default()
    }
    pub fn dy(&self) -> Self {
        Self::new(
            self.c
                .iter()
                .enumerate()
                .skip(1)
                .map(|(j, p)| p.scale(&BigInt::from(j)))
                .collect(),
        )
    }
    pub fn dx(&self) -> Self {
        Self::new(self.c.iter().map(|p| p.derivative()).collect())
    }
    pub fn mul(&self, o: &Self) -> Self {
        if self.is_zero() || o.is_zero() {
            return Self::zero();
        }
        let mut r = vec![UPoly::zero(); self.c.len() + o.c.len() - 1];
        for (i, a) in self.c.iter().enumerate() {
            for (j, b) in o.c.iter().enumerate() {
                r[i + j] = r[i + j].add(&a.mul(b));
            }
        }
        Self::new(r)
    }
    pub fn zero() -> Self {
        BiPoly { c: Vec::new() }
    }
    /// The shear f(x + s·y, y).
    pub fn shear(&self, s: i64) -> Self {
        if s == 0 {
            return self.clone();
        }
        let mut m: BTreeMap<(usize, usize), BigInt> = BTreeMap::new();
        let sb = BigInt::from(s);
        for (j, p) in self.c.iter().enumerate() {
            for (i, a) in p.c.iter().enumerate() {
                if a.is_zero() {
                    continue;
                }
                // a·(x + s y)^i·y^j = Σ_l C(i,l) s^l x^(i−l) y^(j+l)
                let mut binom = BigInt::one();
                let mut sp = BigInt::one();
                for l in 0..=i {
                    *m.entry((i - l, j + l)).or_default() += a * &binom * &sp;
                    binom = binom * BigInt::from(i - l) / BigInt::from(l + 1);
                    sp *= &sb;
                }
            }
        }
        Self::from_map(&m)
    }
    /// The leading coefficient in y (a polynomial in x).
    pub fn lc_y(&self) -> UPoly {
        self.c.last().cloned().unwrap_or_default()
    }
    /// f(x0 + x1·t, y0 + y1·t) as a primitive integer polynomial in t (up to a positive
    /// rational factor). Zero when f vanishes on the line.
    ///
    /// In integers: with x0 + x1·t = (A0 + A1·t)/Dx and y0 + y1·t = (B0 + B1·t)/Dy
    /// (Dx, Dy > 0 the lcm of the denominators), Dx^DX·Dy^DY·f(…) (DX, DY the degrees
    /// in x and y) by homogeneous Horner, then its primitive part: the same
    /// polynomial as [`BiPoly::on_line_q`] (the primitive part with a positive leading
    /// coefficient is unique), without a rational gcd per operation.
    pub fn on_line(
        &self,
        x0: &BigRational,
        x1: &BigRational,
        y0: &BigRational,
        y1: &BigRational,
    ) -> UPoly {
        if self.c.is_empty() {
            return UPoly::zero();
        }
        let dx = x0.denom().lcm(x1.denom());
        let dy = y0.denom().lcm(y1.denom());
        let num = |v: &BigRational, d: &BigInt| v.numer() * (d / v.denom());
        let lx = [num(x0, &dx), num(x1, &dx)];
        let ly = [num(y0, &dy), num(y1, &dy)];
        let big_dx = self.deg_x().max(0) as usize;
        let big_dy = self.c.len() - 1;
        let pows = |d: &BigInt, n: usize| {
            let mut v = vec![BigInt::one()];
            for _ in 0..n {
                let t = v.last().unwrap() * d;
                v.push(t);
            }
            v
        };
        let (dxp, dyp) = (pows(&dx, big_dx), pows(&dy, big_dy));
        // Σ_i c_i·l^i·D^(n−i) by Horner: acc ← acc·l + c_i·D^(n−i).
        fn mul_lin(a: &[BigInt], l: &[BigInt; 2]) -> Vec<BigInt> {
            let mut r = vec![BigInt::zero(); a.len() + 1];
            for (i, x) in a.iter().enumerate() {
                if x.is_zero() {
                    continue;
                }
                if !l[0].is_zero() {
                    r[i] += x * &l[0];
                }
                if !l[1].is_zero() {
                    r[i + 1] += x * &l[1];
                }
            }
            r
        }
        fn add_const(a: &mut Vec<BigInt>, c: BigInt) {
            if a.is_empty() {
                a.push(c);
            } else {
                a[0] += c;
            }
        }
        let mut acc: Vec<BigInt> = Vec::new();
        for (j, p) in self.c.iter().enumerate().rev() {
            // px = D_x^DX·p(lx/D_x)
            let mut px: Vec<BigInt> = Vec::new();
            let n = p.c.len();
            for (i, a) in p.c.iter().enumerate().rev() {
                px = mul_lin(&px, &lx);
                if !a.is_zero() {
                    add_const(&mut px, a * &dxp[n - 1 - i]);
                }
            }
            if n > 0 && n - 1 < big_dx {
                let f = &dxp[big_dx - (n - 1)];
                for x in px.iter_mut() {
                    *x *= f;
                }
            }
            // acc ← acc·ly + px·Dy^(DY−j)
            acc = mul_lin(&acc, &ly);
            let f = &dyp[big_dy - j];
            if acc.len() < px.len() {
                acc.resize(px.len(), BigInt::zero());
            }
            for (t, x) in px.into_iter().enumerate() {
                acc[t] += x * f;
            }
        }
        UPoly::new(acc).primitive()
    }
    /// [`BiPoly::on_line`] in rational arithmetic (the reference of its proptest).
    pub fn on_line_q(
        &self,
        x0: &BigRational,
        x1: &BigRational,
        y0: &BigRational,
        y1: &BigRational,
    ) -> UPoly {
        let lx = [x0.clone(), x1.clone()];
        let ly = [y0.clone(), y1.clone()];
        let mut acc: Vec<BigRational> = Vec::new();
        for p in self.c.iter().rev() {
            // acc = acc·ly + p(lx)
            let mut px: Vec<BigRational> = Vec::new();
            for a in p.c.iter().rev() {
                px = qmul(&px, &lx);
                qadd_const(&mut px, &BigRational::from_integer(a.clone()));
            }
            acc = qmul(&acc, &ly);
            acc = qadd(&acc, &px);
        }
        q_to_primitive(&acc)
    }
    /// f(q, y) as a primitive integer polynomial in y.
    pub fn at_x(&self, q: &BigRational) -> UPoly {
        self.on_line(
            q,
            &BigRational::zero(),
            &BigRational::zero(),
            &BigRational::one(),
        )
    }
    /// Content in Z\[x\]: the gcd of the y-coefficients.
    pub fn content_x(&self) -> UPoly {
        let mut g = UPoly::zero();
        for p in &self.c {
            g = g.gcd(p);
            if g.deg() == 0 {
                break;
            }
        }
        g
    }
    /// Divide every coefficient exactly by a polynomial in x.
    pub fn div_x(&self, g: &UPoly) -> Option<Self> {
        let mut c = Vec::new();
        for p in &self.c {
            c.push(p.div_exact(g)?);
        }
        Some(Self::new(c))
    }
    fn lc_sign_normal(self) -> Self {
        if self.lc_y().lc().is_negative() {
            Self::new(self.c.iter().map(|p| p.neg()).collect())
        } else {
            self
        }
    }
    /// Primitive part over Z\[x\] (positive leading coefficient).
    pub fn primitive(&self) -> Self {
        if self.is_zero() {
            return Self::zero();
        }
        let g = self.content_x();
        self.div_x(&g).expect("content divides").lc_sign_normal()
    }
    /// Pseudo-remainder in y over Z\[x\]: lc(b)^(deg self − deg b + 1)·self mod b
    /// (self returned when its degree is below b's).
    pub fn prem(&self, b: &Self) -> Self {
        let db = b.c.len() - 1;
        let lb = b.lc_y();
        let mut r = self.clone();
        if r.c.len() <= db {
            return r;
        }
        let mut steps = r.c.len() - db;
        while !r.is_zero() && r.c.len() > db {
            let k = r.c.len() - 1 - db;
            let lr = r.lc_y();
            let mut c: Vec<UPoly> = r.c.iter().map(|p| p.mul(&lb)).collect();
            for (j, bj) in b.c.iter().enumerate() {
                c[j + k] = c[j + k].sub(&lr.mul(bj));
            }
            r = Self::new(c);
            steps -= 1;
        }
        if steps > 0 {
            let f = lb.pow(steps as u32);
            r = Self::new(r.c.iter().map(|p| p.mul(&f)).collect());
        }
        r
    }
    /// Exact quotient in Z\[x\]\[y\]; `None` if it does not divide.
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
        let lb = b.lc_y();
        let mut r = self.c.clone();
        let mut q = vec![UPoly::zero(); r.len() - db];
        for k in (0..q.len()).rev() {
            let qk = r[k + db].div_exact(&lb)?;
            for (j, bj) in b.c.iter().enumerate() {
                r[j + k] = r[j + k].sub(&qk.mul(bj));
            }
            q[k] = qk;
        }
        if r.iter().any(|p| !p.is_zero()) {
            return None;
        }
        Some(Self::new(q))
    }
    /// Divided by the gcd of all its integer coefficients (itself when that is 0 or 1).
    pub fn without_integer_content(self) -> Self {
        let g = self
            .c
            .iter()
            .fold(BigInt::zero(), |g, p| g.gcd(&p.content()));
        if g.is_zero() || g.is_one() {
            return self;
        }
        Self::new(
            self.c
                .iter()
                .map(|p| UPoly::new(p.c.iter().map(|a| a / &g).collect()))
                .collect(),
        )
    }
    /// gcd in Z\[x, y\] (primitive PRS in y with contents in Z\[x\]), up to an integer
    /// factor: the part of degree ≥ 1 in y is primitive over Z (its coefficients have no
    /// common integer factor), so that it divides both polynomials exactly in
    /// Z\[x\]\[y\] (Gauss's lemma), times the gcd of their contents in x.
    pub fn gcd(&self, o: &Self) -> Self {
        if self.is_zero() {
            return o.primitive();
        }
        if o.is_zero() {
            return self.primitive();
        }
        let cg = self.content_x().gcd(&o.content_x());
        let (mut a, mut b) = (self.primitive(), o.primitive());
        if a.deg_y() < b.deg_y() {
            std::mem::swap(&mut a, &mut b);
        }
        while b.deg_y() > 0 {
            let r = a.prem(&b);
            a = b;
            b = if r.is_zero() { r } else { r.primitive() };
        }
        let g = if b.is_zero() {
            a
        } else {
            BiPoly::new(vec![UPoly::constant(BigInt::one())])
        };
        // `primitive` divides by the content in x, which `UPoly::gcd` gives without
        // its integer factor: the pseudo-remainders' powers of leading coefficients
        // are still in g (e.g. 16 (y² + x² − 1) for (x² + y² − 1)² and its
        // derivative in y), and must go for g to divide exactly.
        let g = g.primitive().without_integer_content();
        Self::new(g.c.iter().map(|p| p.mul(&cg)).collect()).lc_sign_normal()
    }
    /// The square-free part f / gcd(f, f_y, f_x-content) for f with a constant
    /// leading coefficient in y (so no factor depends on x alone).
    pub fn squarefree_y(&self) -> Self {
        let g = self.gcd(&self.dy());
        if g.deg_y() <= 0 {
            return self.primitive();
        }
        self.div_exact(&g).expect("gcd divides").primitive()
    }
}

fn qmul(a: &[BigRational], b: &[BigRational]) -> Vec<BigRational> {
    if a.is_empty() || b.is_empty() {
        return Vec::new();
    }
    let mut r = vec![BigRational::zero(); a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            r[i + j] += x * y;
        }
    }
    r
}
fn qadd(a: &[BigRational], b: &[BigRational]) -> Vec<BigRational> {
    let n = a.len().max(b.len());
    (0..n)
        .map(|i| a.get(i).cloned().unwrap_or_default() + b.get(i).cloned().unwrap_or_default())
        .collect()
}
fn qadd_const(a: &mut Vec<BigRational>, c: &BigRational) {
    if a.is_empty() {
        a.push(BigRational::zero());
    }
    a[0] += c;
}
/// A rational polynomial times the lcm of its denominators, primitive.
pub fn q_to_primitive(a: &[BigRational]) -> UPoly {
    let mut l = BigInt::one();
    for x in a {
        l = l.lcm(x.denom());
    }
    let lq = BigRational::from_integer(l);
    UPoly::new(a.iter().map(|x| (x * &lq).to_integer()).collect()).primitive()
}

/// A polynomial with rational coefficients during conversion: exponents of (x, y, z)
/// ↦ coefficient.
pub type QPoly = BTreeMap<[u32; 3], BigRational>;

fn qp_add(a: &QPoly, b: &QPoly, sign: i32) -> QPoly {
    let mut r = a.clone();
    for (k, v) in b {
        let e = r.entry(*k).or_insert_with(BigRational::zero);
        if sign > 0 {
            *e += v;
        } else {
            *e -= v;
        }
    }
    r.retain(|_, v| !v.is_zero());
    r
}
fn qp_deg(a: &QPoly) -> u32 {
    a.keys().map(|k| k[0] + k[1] + k[2]).max().unwrap_or(0)
}
fn qp_mul(a: &QPoly, b: &QPoly) -> QPoly {
    let mut r = QPoly::new();
    for (i, x) in a {
        for (k, y) in b {
            let e = [i[0] + k[0], i[1] + k[1], i[2] + k[2]];
            *r.entry(e).or_insert_with(BigRational::zero) += x * y;
        }
    }
    r.retain(|_, v| !v.is_zero());
    r
}
fn qp_const(a: &QPoly) -> Option<BigRational> {
    if a.is_empty() {
        return Some(BigRational::zero());
    }
    if a.len() == 1 {
        if let Some(v) = a.get(&[0, 0, 0]) {
            return Some(v.clone());
        }
    }
    None
}

/// A decimal literal read exactly (digits, optional fraction, optional exponent).
pub fn decimal_exact(text: &str) -> Option<BigRational> {
    let (mant, exp) = match text.find(['e', 'E']) {
        Some(i) => (&text[..i], text[i + 1..].parse::<i64>().ok()?),
        None => (text, 0),
    };
    let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
    let digits = format!("{int}{frac}");
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let m = BigInt::parse_bytes(digits.as_bytes(), 10)?;
    let e10 = exp - frac.len() as i64;
    if e10.abs() > 2000 {
        return None;
    }
    let p = num_traits::pow(BigInt::from(10), e10.unsigned_abs() as usize);
    Some(if e10 >= 0 {
        BigRational::from_integer(m * p)
    } else {
        BigRational::new(m, p)
    })
}

fn not_poly(e: &Expr, why: &str) -> Error {
    Error::Param(format!(
        "the formula is not a polynomial with rational coefficients: the term '{e}' {why}"
    ))
}

/// The polynomial of a formula in x, y (`vars` 2) or x, y, z (`vars` 3), exactly.
pub fn to_qpoly(e: &Expr, vars: usize) -> Result<QPoly> {
    Ok(match e {
        Expr::Var(k) => {
            if *k >= vars {
                return Err(not_poly(e, "uses z (the sweep handles curves f(x, y))"));
            }
            let mut key = [0; 3];
            key[*k] = 1;
            QPoly::from([(key, BigRational::one())])
        }
        Expr::Const(_, text) => {
            let v = decimal_exact(text).ok_or_else(|| not_poly(e, "is not a rational constant"))?;
            let mut m = QPoly::new();
            if !v.is_zero() {
                m.insert([0, 0, 0], v);
            }
            m
        }
        Expr::Un(UnOp::Neg, a) => {
            let a = to_qpoly(a, vars)?;
            a.into_iter().map(|(k, v)| (k, -v)).collect()
        }
        Expr::Un(op, _) => {
            return Err(not_poly(
                e,
                &format!("applies {}, which is not polynomial", op.name()),
            ));
        }
        Expr::Bin(op, a, b) => {
            let (pa, pb) = (to_qpoly(a, vars)?, to_qpoly(b, vars)?);
            match op {
                BinOp::Add => qp_add(&pa, &pb, 1),
                BinOp::Sub => qp_add(&pa, &pb, -1),
                BinOp::Mul => {
                    if qp_deg(&pa) + qp_deg(&pb) > MAX_FORMULA_DEGREE {
                        return Err(not_poly(
                            e,
                            &format!("has degree above {MAX_FORMULA_DEGREE}"),
                        ));
                    }
                    qp_mul(&pa, &pb)
                }
                BinOp::Div => match qp_const(&pb) {
                    Some(c) if !c.is_zero() => pa.into_iter().map(|(k, v)| (k, v / &c)).collect(),
                    Some(_) => return Err(not_poly(e, "divides by zero")),
                    None => return Err(not_poly(e, "divides by a non-constant")),
                },
                BinOp::Min | BinOp::Max => {
                    return Err(not_poly(e, "takes a min or max, which is not polynomial"))
                }
            }
        }
        Expr::Pow(a, n) => {
            let pa = to_qpoly(a, vars)?;
            if *n < 0 {
                match qp_const(&pa) {
                    Some(c) if !c.is_zero() => {
                        let v = num_traits::pow(c.recip(), n.unsigned_abs() as usize);
                        return Ok(QPoly::from([([0, 0, 0], v)]));
                    }
                    _ => return Err(not_poly(e, "has a negative power of a non-constant")),
                }
            }
            let n = *n as u32;
            if qp_deg(&pa).saturating_mul(n) > MAX_FORMULA_DEGREE {
                return Err(not_poly(
                    e,
                    &format!("has degree above {MAX_FORMULA_DEGREE}"),
                ));
            }
            let mut r = QPoly::from([([0, 0, 0], BigRational::one())]);
            for _ in 0..n {
                r = qp_mul(&r, &pa);
            }
            r
        }
    })
}

/// The polynomial f(x, y) of a curve formula, exactly, as a primitive integer
/// polynomial (denominators cleared, content divided out; the zero set is unchanged).
/// Anything that is not a polynomial with rational coefficients is an error naming
/// the term.
pub fn from_expr(e: &Expr) -> Result<BiPoly> {
    let q = to_qpoly(e, 2)?;
    let mut l = BigInt::one();
    for v in q.values() {
        l = l.lcm(v.denom());
    }
    let lq = BigRational::from_integer(l);
    let mut m: BTreeMap<(usize, usize), BigInt> = BTreeMap::new();
    for (k, v) in &q {
        m.insert((k[0] as usize, k[1] as usize), (v * &lq).to_integer());
    }
    Ok(BiPoly::from_map(&m).without_integer_content())
}

/// The polynomial of a curve formula given as text.
pub fn from_formula(text: &str) -> Result<BiPoly> {
    from_expr(&crate::implicit::expr::parse(text, 2)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn arb_bi(d: usize, r: i64) -> impl Strategy<Value = BiPoly> {
        prop::collection::vec(prop::collection::vec(-r..=r, 1..=d + 1), 1..=d + 1)
            .prop_map(|rows| BiPoly::new(rows.iter().map(|v| UPoly::from_i64(v)).collect()))
    }
    fn arb_q() -> impl Strategy<Value = BigRational> {
        (-40i64..=40, 1i64..=12).prop_map(|(a, b)| BigRational::new(a.into(), b.into()))
    }

    /// A polynomial monic in y (so y-regular, as the sweep needs) with coefficients in
    /// [-r, r] below its leading term.
    fn arb_monic(d: usize, r: i64) -> impl Strategy<Value = BiPoly> {
        prop::collection::vec(prop::collection::vec(-r..=r, 1..=d + 1), 1..=d).prop_map(|rows| {
            let mut c: Vec<UPoly> = rows.iter().map(|v| UPoly::from_i64(v)).collect();
            c.push(UPoly::from_i64(&[1]));
            BiPoly::new(c)
        })
    }

    /// (x² + y² − 1)²: the gcd with its y-derivative came out as 16 (y² + x² − 1),
    /// which does not divide it in Z\[x\]\[y\], and the exact sweep panicked ("gcd
    /// divides") on `certmesh curve -f "(x^2+y^2-1)^2" --algo sweep`.
    #[test]
    fn squarefree_part_of_a_square_with_integer_content_in_its_gcd() {
        let f = from_formula("(x^2+y^2-1)^2").unwrap();
        assert_eq!(f.squarefree_y(), from_formula("x^2+y^2-1").unwrap());
        let g = f.gcd(&f.dy());
        assert_eq!(g, from_formula("x^2+y^2-1").unwrap());
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]
        /// The square-free part of p², p monic in y: it divides p² exactly, its own
        /// square-free part is itself, and it is p's (p² and p have the same square-free
        /// part: the product of p's distinct irreducible factors).
        #[test]
        fn squarefree_part_of_a_square_is_that_of_its_root(p in arb_monic(3, 4)) {
            let f = p.mul(&p);
            let s = f.squarefree_y();
            prop_assert!(f.div_exact(&s).is_some(), "{s:?} does not divide {f:?}");
            prop_assert_eq!(&s.squarefree_y(), &s);
            prop_assert_eq!(&s, &p.squarefree_y());
            // The gcd divides both exactly.
            let g = f.gcd(&f.dy());
            prop_assert!(f.div_exact(&g).is_some() && f.dy().div_exact(&g).is_some());
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]
        /// The integer `on_line` equals the rational reference on every line, the
        /// fibres x = q (`at_x`) and lines through zeros of f included.
        #[test]
        fn on_line_integer_equals_rational(
            f in arb_bi(5, 9), x0 in arb_q(), x1 in arb_q(), y0 in arb_q(), y1 in arb_q(),
        ) {
            prop_assert_eq!(f.on_line(&x0, &x1, &y0, &y1), f.on_line_q(&x0, &x1, &y0, &y1));
            let z = BigRational::zero();
            let o = BigRational::one();
            prop_assert_eq!(f.on_line(&x0, &z, &z, &o), f.on_line_q(&x0, &z, &z, &o));
            prop_assert_eq!(f.on_line(&z, &o, &y0, &z), f.on_line_q(&z, &o, &y0, &z));
        }
    }
}
