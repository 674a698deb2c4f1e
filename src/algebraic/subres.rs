//! Subresultants of two polynomials in y over Z\[x\]: the whole chain by Ducos'
//! algorithm (the subresultant PRS with Lazard's and Ducos' exact divisions, L. Ducos,
//! "Optimizations of the subresultant algorithm", J. Pure Appl. Algebra 145, 2000), and
//! single coefficients from the definition, as determinants of Sylvester submatrices
//! (fraction-free Bareiss elimination over Z\[x\]); the signed-subresultant
//! (Sturm–Habicht) count of distinct real roots by permanences minus variations.
use super::bipoly::BiPoly;
use super::upoly::UPoly;
use num_bigint::BigInt;
use num_traits::One;

/// The determinant of a square matrix over Z\[x\] (Bareiss; exact divisions).
pub fn det(mut m: Vec<Vec<UPoly>>) -> UPoly {
    let n = m.len();
    if n == 0 {
        return UPoly::constant(BigInt::one());
    }
    let mut neg = false;
    let mut prev = UPoly::constant(BigInt::one());
    for k in 0..n {
        if m[k][k].is_zero() {
            match (k + 1..n).find(|&r| !m[r][k].is_zero()) {
                Some(r) => {
                    m.swap(k, r);
                    neg = !neg;
                }
                None => return UPoly::zero(),
            }
        }
        if k + 1 == n {
            break;
        }
        for i in k + 1..n {
            for j in k + 1..n {
                let t = m[i][j].mul(&m[k][k]).sub(&m[i][k].mul(&m[k][j]));
                m[i][j] = t.div_exact(&prev).expect("Bareiss division is exact");
            }
            m[i][k] = UPoly::zero();
        }
        prev = m[k][k].clone();
    }
    let d = m[n - 1][n - 1].clone();
    if neg {
        d.neg()
    } else {
        d
    }
}

/// The subresultant coefficient det_{j,i}(P, Q) (deg P = p > deg Q = q, 0 ≤ i ≤ j < q
/// or j = q): the coefficient of yⁱ in the j-th subresultant S_j. The rows are
/// y^(q−j−1)·P, …, P, y^(p−j−1)·Q, …, Q; the columns the coefficients of
/// y^(p+q−j−1), …, y^(j+1), and yⁱ.
pub fn sub_coef(p: &BiPoly, q: &BiPoly, j: usize, i: usize) -> UPoly {
    let (dp, dq) = (p.deg_y() as usize, q.deg_y() as usize);
    assert!(dp > dq && j <= dq && i <= j);
    let mut rows: Vec<(&BiPoly, usize)> = Vec::new();
    for r in 0..dq - j {
        rows.push((p, dq - j - 1 - r));
    }
    for r in 0..dp - j {
        rows.push((q, dp - j - 1 - r));
    }
    let mut cols: Vec<usize> = (j + 1..dp + dq - j).rev().collect();
    cols.push(i);
    let m: Vec<Vec<UPoly>> = rows
        .iter()
        .map(|(poly, sh)| {
            cols.iter()
                .map(|&c| {
                    if c >= *sh && c - sh < poly.c.len() {
                        poly.c[c - sh].clone()
                    } else {
                        UPoly::zero()
                    }
                })
                .collect()
        })
        .collect();
    det(m)
}

/// The j-th subresultant S_j(P, Q) as a polynomial in y over Z\[x\].
pub fn subresultant(p: &BiPoly, q: &BiPoly, j: usize) -> BiPoly {
    BiPoly::new((0..=j).map(|i| sub_coef(p, q, j, i)).collect())
}

fn scale(a: &BiPoly, k: &UPoly) -> BiPoly {
    BiPoly::new(a.c.iter().map(|p| p.mul(k)).collect())
}

fn div(a: &BiPoly, k: &UPoly) -> BiPoly {
    a.div_x(k).expect("subresultant division is exact")
}

/// The subresultant chain S_j(P, Q), j = 0 … deg Q (index j; zero where the chain
/// is defective), for deg P = deg Q + 1 ≥ 2, by Ducos' algorithm: with s = sres_d of
/// the last regular S_d = A and B = S_(d−1) of degree e, S_e = lc(B)^(δ−1)·B/s^(δ−1)
/// (δ = d − e, Lazard's exact divisions one power at a time) and
/// S_(e−1) = prem(A, −B)/(s^δ·lc(A)).
pub fn chain(p: &BiPoly, q: &BiPoly) -> Vec<BiPoly> {
    let (dp, dq) = (p.deg_y() as usize, q.deg_y() as usize);
    assert!(dq >= 1 && dp == dq + 1, "chain: deg P = deg Q + 1 ≥ 2");
    let mut out = vec![BiPoly::zero(); dq + 1];
    out[dq] = q.clone();
    let mut s = q.lc_y();
    let mut a = q.clone();
    let mut b = p.prem(&neg(q));
    loop {
        let d = a.deg_y() as usize;
        if b.is_zero() {
            break;
        }
        let e = b.deg_y() as usize;
        out[d - 1] = b.clone();
        let delta = d - e;
        let mut c = b.clone();
        if delta > 1 {
            let lb = b.lc_y();
            for _ in 1..delta {
                c = div(&scale(&c, &lb), &s);
            }
            out[e] = c.clone();
        }
        if e == 0 {
            break;
        }
        let nb = div(&a.prem(&neg(&b)), &s.pow(delta as u32).mul(&a.lc_y()));
        a = c;
        s = a.lc_y();
        b = nb;
    }
    out
}

fn neg(a: &BiPoly) -> BiPoly {
    BiPoly::new(a.c.iter().map(|p| p.neg()).collect())
}

/// The subresultant chain S_0 … S_(deg Q): Ducos' algorithm when
/// deg P = deg Q + 1 ≥ 2 (always so for (f, f_y) with a constant leading coefficient),
/// the determinants otherwise.
pub fn full_chain(p: &BiPoly, q: &BiPoly) -> Vec<BiPoly> {
    if q.deg_y() >= 1 && p.deg_y() == q.deg_y() + 1 {
        return chain(p, q);
    }
    (0..=q.deg_y().max(0) as usize)
        .map(|j| subresultant(p, q, j))
        .collect()
}

/// The principal coefficients sres_j (the coefficient of yʲ of S_j) of a chain.
pub fn principal_of(ch: &[BiPoly]) -> Vec<UPoly> {
    ch.iter()
        .enumerate()
        .map(|(j, s)| s.c.get(j).cloned().unwrap_or_default())
        .collect()
}

/// The coefficients of y⁰ … y^(j−1) of S_j in a chain.
pub fn lower_of(ch: &[BiPoly], j: usize) -> Vec<UPoly> {
    (0..j)
        .map(|i| ch[j].c.get(i).cloned().unwrap_or_default())
        .collect()
}

/// The principal subresultant coefficients sres_j, j = 0 … deg Q.
pub fn principal(p: &BiPoly, q: &BiPoly) -> Vec<UPoly> {
    principal_of(&full_chain(p, q))
}

/// The resultant Res_y(P, Q) = sres_0.
pub fn resultant(p: &BiPoly, q: &BiPoly) -> UPoly {
    principal(p, q).swap_remove(0)
}

/// The sign (−1)^((d−j)(d−j−1)/2) turning sres_j of (f, f_y) into the signed
/// (Sturm–Habicht) coefficient, d = deg_y f.
pub fn sturm_habicht_sign(d: usize, j: usize) -> i32 {
    let t = (d - j) * (d - j).saturating_sub(1) / 2;
    if t % 2 == 0 {
        1
    } else {
        -1
    }
}

/// Permanences minus variations of a sign sequence a_d, …, a_0 (first entry non-zero;
/// trailing zeros ignored): for consecutive non-zeros t apart, add
/// (−1)^(t(t−1)/2)·sign(product) if t is odd, 0 if t is even.
pub fn pmv(signs: &[i32]) -> i64 {
    let nz: Vec<usize> = (0..signs.len()).filter(|&i| signs[i] != 0).collect();
    let mut s = 0i64;
    for w in nz.windows(2) {
        let t = w[1] - w[0];
        if t % 2 == 1 {
            let e = if (t * (t - 1) / 2) % 2 == 0 { 1 } else { -1 };
            s += e * (signs[w[0]] * signs[w[1]]) as i64;
        }
    }
    s
}

/// The number of distinct real roots of f(α, ·) from the signs of sres_j(α),
/// j = d−1 … 0 (`sres_signs[j]`), and the sign of lc_y(f) (a constant).
pub fn distinct_real_roots(d: usize, lc_sign: i32, sres_signs: &[i32]) -> i64 {
    let mut seq = vec![lc_sign];
    for j in (0..d).rev() {
        seq.push(sturm_habicht_sign(d, j) * sres_signs[j]);
    }
    pmv(&seq)
}
