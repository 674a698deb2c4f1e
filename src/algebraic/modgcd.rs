//! The gcd of two integer polynomials by the modular method (G. E. Collins, W. S.
//! Brown, *On Euclid's algorithm and the computation of polynomial greatest common
//! divisors*, J. ACM 18(4), 1971, §7 "the modular algorithm"; in the textbook form of
//! K. O. Geddes, S. R. Czapor, G. Labahn, *Algorithms for Computer Algebra*, Kluwer
//! 1992, §7.4, Algorithm 7.1, with early termination by trial division).
//!
//! For primitive a, b ∈ Z\[x\] and γ = gcd(lc a, lc b): for word-size primes p not
//! dividing lc a · lc b, the monic gcd ḡ_p of a mod p and b mod p has degree ≥ deg g
//! (g = gcd(a, b) reduces to a divisor of both images, and p ∤ lc g because lc g | γ).
//! The images of the least degree seen are scaled by γ and combined by Chinese
//! remaindering (symmetric residues); when the combination stops changing, its
//! primitive part h is *trial-divided* into a and b. If h divides both, h is a common
//! divisor of degree ≥ deg g, so h = ±g: the answer is exact whatever the primes were
//! (an unlucky prime can only delay it). An image of degree 0 proves gcd = 1 at once
//! (deg g ≤ 0), which is the common case of the sweep's zero tests.
use super::upoly::UPoly;
use num_bigint::{BigInt, Sign};
use num_integer::Integer;
use num_traits::One;
use std::sync::OnceLock;

/// Primes below 2^62 (descending), found by a deterministic Miller–Rabin test.
fn primes() -> &'static [u64] {
    static P: OnceLock<Vec<u64>> = OnceLock::new();
    P.get_or_init(|| {
        let mut v = Vec::with_capacity(PRIMES);
        let mut n = (1u64 << 62) - 1;
        while v.len() < PRIMES {
            if is_prime(n) {
                v.push(n);
            }
            n -= 2;
        }
        v
    })
}

/// How many primes the modular gcd tries before it falls back to the primitive
/// remainder sequence (256 · 62 bits bound gcd coefficients far beyond the sweep's).
const PRIMES: usize = 256;

#[inline]
fn mulm(a: u64, b: u64, p: u64) -> u64 {
    ((a as u128 * b as u128) % p as u128) as u64
}

fn powm(mut a: u64, mut e: u64, p: u64) -> u64 {
    let mut r = 1u64;
    while e > 0 {
        if e & 1 == 1 {
            r = mulm(r, a, p);
        }
        a = mulm(a, a, p);
        e >>= 1;
    }
    r
}

/// Deterministic Miller–Rabin for n < 2^64 (the first twelve prime bases suffice).
pub(crate) fn is_prime(n: u64) -> bool {
    if n < 2 {
        return false;
    }
    const B: [u64; 12] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37];
    for &b in &B {
        if n.is_multiple_of(b) {
            return n == b;
        }
    }
    let (mut d, mut s) = (n - 1, 0);
    while d.is_multiple_of(2) {
        d /= 2;
        s += 1;
    }
    'base: for &b in &B {
        let mut x = powm(b, d, n);
        if x == 1 || x == n - 1 {
            continue;
        }
        for _ in 1..s {
            x = mulm(x, x, n);
            if x == n - 1 {
                continue 'base;
            }
        }
        return false;
    }
    true
}

/// a⁻¹ mod p for a ≠ 0 mod p (p prime), by the extended Euclidean algorithm (the
/// inverse is unique; Fermat's a^(p−2) took 62 u128 products and remainders, the
/// largest cost of the small gcds of root isolation). All values stay below 2^63 in
/// magnitude for p < 2^62.
fn invm(a: u64, p: u64) -> u64 {
    let (mut t, mut nt) = (0i64, 1i64);
    let (mut r, mut nr) = (p as i64, (a % p) as i64);
    while nr != 0 {
        let q = r / nr;
        (t, nt) = (nt, t - q * nt);
        (r, nr) = (nr, r - q * nr);
    }
    debug_assert_eq!(r, 1, "not invertible");
    if t < 0 {
        t += p as i64;
    }
    t as u64
}

/// a mod p in [0, p).
fn redm(a: &BigInt, p: u64) -> u64 {
    let mut r: u128 = 0;
    for d in a.iter_u64_digits().rev() {
        r = ((r << 64) | d as u128) % p as u128;
    }
    let r = r as u64;
    if a.sign() == Sign::Minus && r != 0 {
        p - r
    } else {
        r
    }
}

fn trim(v: &mut Vec<u64>) {
    while v.last() == Some(&0) {
        v.pop();
    }
}

/// The monic gcd of two polynomials over Z/p (constant term first, trimmed).
fn gcd_mod(mut a: Vec<u64>, mut b: Vec<u64>, p: u64) -> Vec<u64> {
    trim(&mut a);
    trim(&mut b);
    if a.len() < b.len() {
        std::mem::swap(&mut a, &mut b);
    }
    while !b.is_empty() {
        // a ← a mod b
        let db = b.len() - 1;
        let inv = invm(b[db], p);
        while a.len() > db {
            let k = a.len() - 1 - db;
            let q = mulm(a[a.len() - 1], inv, p);
            if q != 0 {
                for (j, &bj) in b.iter().enumerate() {
                    let t = mulm(q, bj, p);
                    let x = &mut a[j + k];
                    *x = if *x >= t { *x - t } else { *x + (p - t) };
                }
            }
            a.pop();
            trim(&mut a);
        }
        std::mem::swap(&mut a, &mut b);
    }
    if let Some(&l) = a.last() {
        let inv = invm(l, p);
        for x in a.iter_mut() {
            *x = mulm(*x, inv, p);
        }
    }
    a
}

/// Arithmetic in (Z/q)\[u\]/(p̄) for a prime q not dividing lc(p): the images of
/// polynomials built from big factors (at_beta, the genericity conditions) without
/// building them over Z.
pub(crate) struct ModRing {
    pub(crate) q: u64,
    /// p mod q, made monic.
    p: Vec<u64>,
}

impl ModRing {
    fn new(p: &UPoly, q: u64) -> Option<Self> {
        let l = redm(&p.lc(), q);
        if p.deg() < 1 || l == 0 {
            return None;
        }
        let inv = invm(l, q);
        Some(ModRing {
            q,
            p: p.c.iter().map(|x| mulm(redm(x, q), inv, q)).collect(),
        })
    }
    /// a mod p̄ (in place).
    fn reduce(&self, mut a: Vec<u64>) -> Vec<u64> {
        let q = self.q;
        let dp = self.p.len() - 1;
        trim(&mut a);
        while a.len() > dp {
            let k = a.len() - 1 - dp;
            let c = a[a.len() - 1];
            if c != 0 {
                for (j, &pj) in self.p.iter().enumerate() {
                    let t = mulm(c, pj, q);
                    let x = &mut a[j + k];
                    *x = if *x >= t { *x - t } else { *x + (q - t) };
                }
            }
            a.pop();
            trim(&mut a);
        }
        a
    }
    /// The image of an integer polynomial.
    pub(crate) fn img(&self, a: &UPoly) -> Vec<u64> {
        self.reduce(a.c.iter().map(|x| redm(x, self.q)).collect())
    }
    pub(crate) fn int(&self, a: &BigInt) -> u64 {
        redm(a, self.q)
    }
    pub(crate) fn mul(&self, a: &[u64], b: &[u64]) -> Vec<u64> {
        if a.is_empty() || b.is_empty() {
            return Vec::new();
        }
        let q = self.q;
        let mut r = vec![0u128; a.len() + b.len() - 1];
        for (i, &x) in a.iter().enumerate() {
            if x == 0 {
                continue;
            }
            for (j, &y) in b.iter().enumerate() {
                // Sums of products < 2^124 each: reduce every step to stay in u128.
                r[i + j] = (r[i + j] + x as u128 * y as u128) % q as u128;
            }
        }
        self.reduce(r.into_iter().map(|x| x as u64).collect())
    }
    pub(crate) fn add(&self, a: &[u64], b: &[u64]) -> Vec<u64> {
        let q = self.q;
        let n = a.len().max(b.len());
        let mut r: Vec<u64> = (0..n)
            .map(|i| {
                let (x, y) = (
                    a.get(i).copied().unwrap_or(0),
                    b.get(i).copied().unwrap_or(0),
                );
                let s = x as u128 + y as u128;
                (s % q as u128) as u64
            })
            .collect();
        trim(&mut r);
        r
    }
    pub(crate) fn scale(&self, a: &[u64], k: u64) -> Vec<u64> {
        let mut r: Vec<u64> = a.iter().map(|&x| mulm(x, k, self.q)).collect();
        trim(&mut r);
        r
    }
    pub(crate) fn neg(&self, a: &[u64]) -> Vec<u64> {
        a.iter()
            .map(|&x| if x == 0 { 0 } else { self.q - x })
            .collect()
    }
    pub(crate) fn pow(&self, a: &[u64], e: u32) -> Vec<u64> {
        let mut r = vec![1u64];
        for _ in 0..e {
            r = self.mul(&r, a);
        }
        r
    }
}

/// A proof that gcd(p, H) = 1 in Z\[u\] (so H vanishes at no root of p), from the
/// image of H in (Z/q)\[u\]/(p̄) given by `image` for one of the first `tries` primes
/// q ∤ lc(p): p = G·p′ and H = G·H′ with G = gcd(p, H); q ∤ lc(p) gives q ∤ lc(G), so
/// Ḡ keeps its degree and divides both p̄ and H̄, hence gcd(p̄, H̄ mod p̄) has degree
/// ≥ deg G (when H = 0, H̄ = 0 and the gcd is p̄ itself, of degree deg p ≥ 1). An
/// image gcd of degree 0 therefore proves deg G = 0. `false` proves nothing (the
/// caller then decides exactly).
pub(crate) fn coprime_by_image(
    p: &UPoly,
    tries: usize,
    image: impl Fn(&ModRing) -> Vec<u64>,
) -> bool {
    let mut n = 0;
    for &q in primes() {
        if n >= tries {
            break;
        }
        let Some(r) = ModRing::new(p, q) else {
            continue;
        };
        n += 1;
        let h = image(&r);
        if h.is_empty() {
            continue;
        }
        if gcd_mod(r.p.clone(), h, q).len() == 1 {
            return true;
        }
    }
    false
}

/// The primitive gcd (positive leading coefficient) of two *primitive* polynomials of
/// degree ≥ 1; `None` if the primes run out (the caller then uses the remainder
/// sequence).
pub(crate) fn gcd_primitive(a: &UPoly, b: &UPoly) -> Option<UPoly> {
    debug_assert!(a.deg() >= 1 && b.deg() >= 1);
    let (la, lb) = (a.lc(), b.lc());
    let gamma = la.gcd(&lb);
    let mut deg = usize::MAX;
    // The combined image: coefficients in [0, m), and its last symmetric lift.
    let mut acc: Vec<BigInt> = Vec::new();
    let mut m = BigInt::one();
    let mut last: Option<Vec<BigInt>> = None;
    for &p in primes() {
        if redm(&la, p) == 0 || redm(&lb, p) == 0 {
            continue;
        }
        let ap: Vec<u64> = a.c.iter().map(|x| redm(x, p)).collect();
        let bp: Vec<u64> = b.c.iter().map(|x| redm(x, p)).collect();
        let g = gcd_mod(ap, bp, p);
        let dg = g.len() - 1;
        if dg == 0 {
            return Some(UPoly::constant(BigInt::one()));
        }
        if dg > deg {
            continue; // unlucky prime
        }
        let gm = redm(&gamma, p);
        let g: Vec<u64> = g.iter().map(|&x| mulm(x, gm, p)).collect();
        if dg < deg {
            // every earlier prime was unlucky: start over
            deg = dg;
            acc = g.iter().map(|&x| BigInt::from(x)).collect();
            m = BigInt::from(p);
            last = None;
        } else {
            let minv = invm(redm(&m, p), p);
            for (c, &v) in acc.iter_mut().zip(&g) {
                let cp = redm(c, p);
                let d = if v >= cp { v - cp } else { v + (p - cp) };
                let t = mulm(d, minv, p);
                if t != 0 {
                    *c += &m * BigInt::from(t);
                }
            }
            m *= BigInt::from(p);
        }
        let half = &m >> 1u32;
        let lift: Vec<BigInt> = acc
            .iter()
            .map(|c| if c > &half { c - &m } else { c.clone() })
            .collect();
        if last.as_ref() == Some(&lift) {
            let h = UPoly::new(lift.clone()).primitive();
            if a.div_exact(&h).is_some() && b.div_exact(&h).is_some() {
                return Some(h);
            }
        }
        last = Some(lift);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_traits::Zero;

    #[test]
    fn primes_are_prime_and_distinct() {
        let p = primes();
        assert_eq!(p.len(), PRIMES);
        assert!(p.windows(2).all(|w| w[0] > w[1]));
        // a few by trial division against small factors, and known composites
        for &q in &p[..4] {
            assert!((3..20000u64).step_by(2).all(|d| q % d != 0));
        }
        assert!(!is_prime(3215031751)); // strong pseudoprime to bases 2, 3, 5, 7
        assert!(!is_prime((1u64 << 62) - 1));
        assert!(is_prime(2305843009213693951)); // 2^61 − 1
    }

    #[test]
    fn reduction_mod_p_matches_bigint_remainder() {
        let p = primes()[0];
        for s in [
            "0",
            "1",
            "-1",
            "123456789012345678901234567890",
            "-98765432109876543210987654321098765",
        ] {
            let a: BigInt = s.parse().unwrap();
            let want = a.mod_floor(&BigInt::from(p));
            assert_eq!(BigInt::from(redm(&a, p)), want, "{s}");
        }
    }

    use proptest::prelude::*;

    fn poly(v: &[i64]) -> UPoly {
        UPoly::from_i64(v)
    }

    /// A polynomial of degree 0..=deg with coefficients in [−r, r] (may be zero).
    fn arb(deg: usize, r: i64) -> impl Strategy<Value = UPoly> {
        prop::collection::vec(-r..=r, 1..=deg + 1).prop_map(|v| poly(&v))
    }

    fn check(a: &UPoly, b: &UPoly) -> Result<(), TestCaseError> {
        let g = a.gcd(b);
        let r = a.gcd_prs(b);
        prop_assert_eq!(&g, &r, "modular gcd differs from the remainder sequence");
        if a.is_zero() && b.is_zero() {
            prop_assert!(g.is_zero());
            return Ok(());
        }
        prop_assert!(g.lc() > BigInt::zero());
        prop_assert!(g.content().is_one());
        let ca = a.div_exact(&g);
        let cb = b.div_exact(&g);
        prop_assert!(ca.is_some() && cb.is_some(), "the gcd divides both");
        let (ca, cb) = (ca.unwrap(), cb.unwrap());
        if !ca.is_zero() && !cb.is_zero() {
            prop_assert!(ca.gcd_prs(&cb).deg() == 0, "the cofactors are coprime");
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// The modular "not a root" proof never misfires: when it claims gcd(p, H) = 1
        /// the exact gcd is 1; and with a shared factor (H = k·u + p·v with k | p) it
        /// never claims it. The image is built from factors, as the sweep does.
        #[test]
        fn coprime_by_image_is_sound(
            k in arb(3, 20), a in arb(4, 20), u in arb(4, 20), v in arb(3, 20),
        ) {
            let p = k.mul(&a);
            prop_assume!(p.deg() >= 1);
            let h = u.mul(&v).add(&a);
            let claim = coprime_by_image(&p, 2, |r| r.add(&r.mul(&r.img(&u), &r.img(&v)), &r.img(&a)));
            if claim {
                prop_assert_eq!(p.gcd(&h).deg(), 0, "claimed coprime, exact gcd non-trivial");
            }
            if k.deg() >= 1 {
                let shared = k.mul(&u).add(&p.mul(&v));
                let c = coprime_by_image(&p, 2, |r| {
                    r.add(&r.mul(&r.img(&k), &r.img(&u)), &r.mul(&r.img(&p), &r.img(&v)))
                });
                prop_assert!(!c, "claimed coprime with a shared factor");
                prop_assert!(shared.is_zero() || p.gcd(&shared).deg() >= 1);
            }
        }

        /// The Euclidean inverse equals Fermat's a^(p−2) on the modular gcd's primes.
        #[test]
        fn inverse_mod_p_equals_fermat(a in 1u64..u64::MAX, i in 0usize..256) {
            let p = primes()[i];
            let a = a % p;
            prop_assume!(a != 0);
            let inv = invm(a, p);
            prop_assert_eq!(inv, powm(a, p - 2, p));
            prop_assert_eq!(mulm(a, inv, p), 1);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// Unrelated polynomials (mostly coprime), zeros and constants included.
        #[test]
        fn modular_gcd_equals_prs_unrelated(a in arb(8, 20), b in arb(8, 20)) {
            check(&a, &b)?;
        }

        /// A common factor h²·k (repeated roots) times random cofactors, with a
        /// large-coefficient factor (up to ~2^150: several primes and the Chinese
        /// remainder path) in some cases.
        #[test]
        fn modular_gcd_equals_prs_common_factor(
            h in arb(3, 50), k in arb(4, 1000), u in arb(6, 30), v in arb(6, 30),
            big in 0u32..4,
        ) {
            let mut g = h.mul(&h).mul(&k);
            for _ in 0..big {
                g = g.mul(&k).mul(&k.scale(&BigInt::from(1i64 << 40)).add(&UPoly::from_i64(&[3])));
            }
            check(&g.mul(&u), &g.mul(&v))?;
            check(&g.mul(&u), &g.mul(&u).derivative())?;
        }
    }
}
