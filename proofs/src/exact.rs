//! Exact arithmetic for the final threshold comparisons (num-rational): every f64 is an
//! exact dyadic rational, and cos of a threshold angle given in degrees is enclosed
//! between two rationals by the alternating Taylor series with rational bounds on π.
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};
use std::cmp::Ordering;

/// The exact value of a finite f64.
pub fn rat(x: f64) -> BigRational {
    BigRational::from_float(x).unwrap_or_else(BigRational::zero)
}

/// The exact value of a decimal literal such as "35.2" or "-101.445".
pub fn decimal(s: &str) -> Option<BigRational> {
    let s = s.trim();
    let (neg, s) = match s.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, s),
    };
    let (ip, fp) = match s.split_once('.') {
        Some((a, b)) => (a, b),
        None => (s, ""),
    };
    if ip.is_empty() && fp.is_empty() {
        return None;
    }
    if !ip.chars().chain(fp.chars()).all(|c| c.is_ascii_digit()) {
        return None;
    }
    let digits: BigInt = format!("{ip}{fp}").parse().ok()?;
    let den = BigInt::from(10u32).pow(fp.len() as u32);
    let r = BigRational::new(digits, den);
    Some(if neg { -r } else { r })
}

/// Rational bounds on π (the first 30 decimals; π = 3.141592653589793238462643383279|50…).
fn pi_bounds() -> (BigRational, BigRational) {
    let lo = decimal("3.141592653589793238462643383279").unwrap_or_else(BigRational::zero);
    let hi = decimal("3.141592653589793238462643383280").unwrap_or_else(BigRational::zero);
    (lo, hi)
}

/// Rational enclosure of cos(x) for 0 <= x <= 4, by the alternating Taylor series
/// Σ (−1)^k x^{2k}/(2k)!, whose error after the term k = n is at most x^{2n+2}/(2n+2)!.
fn cos_rat(x: &BigRational) -> (BigRational, BigRational) {
    let x2 = x * x;
    let mut term = BigRational::one();
    let mut sum = BigRational::one();
    let n = 30;
    for k in 1..=n {
        term = -term * &x2 / BigRational::from_integer(BigInt::from((2 * k - 1) * (2 * k)));
        sum += &term;
    }
    let next =
        (term * &x2 / BigRational::from_integer(BigInt::from((2 * n + 1) * (2 * n + 2)))).abs();
    (&sum - &next, &sum + &next)
}

/// A rational enclosure [lo, hi] of cos(deg°) for 0 <= deg <= 180 given exactly as a
/// rational number of degrees. cos is decreasing on [0, π], so the bounds on π give
/// cos(deg·π_hi/180) <= cos(deg°) <= cos(deg·π_lo/180). 90° gives exactly 0.
pub fn cos_deg(deg: &BigRational) -> (BigRational, BigRational) {
    // Memoised: a pure function, called with the same few thresholds by every summary.
    use std::collections::HashMap;
    use std::sync::{Mutex, OnceLock};
    type Memo = Mutex<HashMap<BigRational, (BigRational, BigRational)>>;
    static MEMO: OnceLock<Memo> = OnceLock::new();
    let memo = MEMO.get_or_init(|| Mutex::new(HashMap::new()));
    if let Some(r) = memo.lock().unwrap_or_else(|e| e.into_inner()).get(deg) {
        return r.clone();
    }
    let r = cos_deg_uncached(deg);
    memo.lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(deg.clone(), r.clone());
    r
}

fn cos_deg_uncached(deg: &BigRational) -> (BigRational, BigRational) {
    if *deg == BigRational::from_integer(BigInt::from(90)) {
        return (BigRational::zero(), BigRational::zero());
    }
    let (plo, phi) = pi_bounds();
    let d180 = BigRational::from_integer(BigInt::from(180));
    let xlo = deg * plo / &d180;
    let xhi = deg * phi / d180;
    let (lo, _) = cos_rat(&xhi);
    let (_, hi) = cos_rat(&xlo);
    (lo, hi)
}

/// Verdict of a one-sided claim about an extreme, decided exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    Proven,
    Refuted,
    Undecided,
}

impl Verdict {
    pub fn name(&self) -> &'static str {
        match self {
            Verdict::Proven => "proven",
            Verdict::Refuted => "refuted",
            Verdict::Undecided => "undecided",
        }
    }
}

/// "every angle >= deg": the largest cosine `max_cos` (certified upper bound `ub`,
/// attained up to the witness value whose lower bound is `witness_lo`) must be <= cos(deg).
pub fn angle_at_least(deg: &BigRational, ub: f64, witness_lo: f64) -> Verdict {
    let (clo, chi) = cos_deg(deg);
    if rat(ub).cmp(&clo) != Ordering::Greater {
        Verdict::Proven
    } else if rat(witness_lo) > chi {
        Verdict::Refuted
    } else {
        Verdict::Undecided
    }
}

/// "every angle <= deg": the smallest cosine (certified lower bound `lb`, witness upper
/// bound `witness_hi`) must be >= cos(deg).
pub fn angle_at_most(deg: &BigRational, lb: f64, witness_hi: f64) -> Verdict {
    let (clo, chi) = cos_deg(deg);
    if rat(lb).cmp(&chi) != Ordering::Less {
        Verdict::Proven
    } else if rat(witness_hi) < clo {
        Verdict::Refuted
    } else {
        Verdict::Undecided
    }
}

/// Display value of an angle in degrees from a cosine bound, rounded outward by 1e-12°
/// (f64 `acos` is accurate to a few ulps; no verdict depends on these numbers).
pub fn deg_lo(cos_hi: f64) -> f64 {
    cos_hi.clamp(-1.0, 1.0).acos().to_degrees() - 1e-12
}
pub fn deg_hi(cos_lo: f64) -> f64 {
    cos_lo.clamp(-1.0, 1.0).acos().to_degrees() + 1e-12
}
