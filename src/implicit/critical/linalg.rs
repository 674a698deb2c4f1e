//! A small dense interval linear-algebra kit for n ≤ 4, outward rounded by inari:
//! interval matrix × vector, the float inverse of a midpoint matrix, the Krawczyk
//! operator, interval determinants and principal minors, and the inertia of an
//! interval symmetric matrix by Jacobi's sign rule (Sylvester's leading minors).
//!
//! Every interval operation is inari's (IEEE 1788, outward rounding); floats enter
//! only as the *preconditioner* Y of the Krawczyk operator and the midpoint m, which
//! are used as exact point intervals, so their rounding errors cost sharpness, never
//! rigour.
use inari::Interval;

/// A point interval `[x, x]` (the whole line for a non-finite float).
#[inline]
pub fn pt(x: f64) -> Interval {
    Interval::try_from((x, x)).unwrap_or(Interval::ENTIRE)
}

/// An interval vector.
pub type IVec<const N: usize> = [Interval; N];
/// An interval matrix, row-major.
pub type IMat<const N: usize> = [[Interval; N]; N];

/// Interval matrix × interval vector.
pub fn mat_vec<const N: usize>(a: &IMat<N>, x: &IVec<N>) -> IVec<N> {
    std::array::from_fn(|i| {
        let mut s = pt(0.0);
        for j in 0..N {
            s += a[i][j] * x[j];
        }
        s
    })
}

/// Interval matrix × interval matrix.
pub fn mat_mul<const N: usize>(a: &IMat<N>, b: &IMat<N>) -> IMat<N> {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let mut s = pt(0.0);
            for k in 0..N {
                s += a[i][k] * b[k][j];
            }
            s
        })
    })
}

/// A float matrix as point intervals.
pub fn to_imat<const N: usize>(y: &[[f64; N]; N]) -> IMat<N> {
    std::array::from_fn(|i| std::array::from_fn(|j| pt(y[i][j])))
}

/// The midpoint matrix (NaN where an entry is empty or unbounded).
pub fn mid_mat<const N: usize>(a: &IMat<N>) -> [[f64; N]; N] {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let e = a[i][j];
            if e.is_empty() || !e.inf().is_finite() || !e.sup().is_finite() {
                f64::NAN
            } else {
                e.mid()
            }
        })
    })
}

/// The inverse of a float matrix by Gauss–Jordan elimination with partial pivoting,
/// or `None` if it is (numerically) singular. Only a preconditioner: its accuracy
/// affects how soon the Krawczyk test succeeds, not its correctness.
pub fn inverse<const N: usize>(a: &[[f64; N]; N]) -> Option<[[f64; N]; N]> {
    let mut m = *a;
    let mut inv: [[f64; N]; N] =
        std::array::from_fn(|i| std::array::from_fn(|j| (i == j) as u8 as f64));
    let scale = a.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    for c in 0..N {
        let p = (c..N).max_by(|&i, &j| m[i][c].abs().total_cmp(&m[j][c].abs()))?;
        if m[p][c].is_nan() || m[p][c].abs() <= 1e-13 * scale {
            return None;
        }
        m.swap(p, c);
        inv.swap(p, c);
        let d = m[c][c];
        for j in 0..N {
            m[c][j] /= d;
            inv[c][j] /= d;
        }
        for i in 0..N {
            if i != c {
                let f = m[i][c];
                if f != 0.0 {
                    for j in 0..N {
                        m[i][j] -= f * m[c][j];
                        inv[i][j] -= f * inv[c][j];
                    }
                }
            }
        }
    }
    inv.iter().flatten().all(|x| x.is_finite()).then_some(inv)
}

/// Solve a float linear system by the inverse (for float Newton steps).
pub fn solve<const N: usize>(a: &[[f64; N]; N], b: &[f64; N]) -> Option<[f64; N]> {
    let y = inverse(a)?;
    Some(std::array::from_fn(|i| {
        (0..N).map(|j| y[i][j] * b[j]).sum()
    }))
}

/// The Krawczyk operator
/// K(X) = m − Y·F(m) + (I − Y·J(X))·(X − m)
/// (Krawczyk, "Newton-Algorithmen zur Bestimmung von Nullstellen mit Fehlerschranken",
/// Computing 4, 1969; Moore, "A test for existence of solutions to nonlinear systems",
/// SIAM J. Numer. Anal. 14, 1977; Neumaier, *Interval Methods for Systems of
/// Equations*, 1990, §5.1), with `fm` an interval enclosure of F at the point m (not
/// a float), `jx` an enclosure of the Jacobian over X and Y any float matrix.
/// Returned with the "contraction" ‖I − Y·J(X)‖∞ (magnitudes), which tells whether
/// the box is small enough for the test to be able to succeed.
///
/// What it proves, for F C¹ on X (the caller checks [`crate::implicit::Regularity`]):
/// every zero of F in X lies in K(X) (mean value theorem row by row, for any Y), so
/// K(X) ∩ X = ∅ excludes X; and K(X) ⊂ int X implies that X holds exactly one zero
/// (Brouwer's fixed point theorem for existence; K(X) ⊂ int X also forces Y and every
/// matrix in J(X) to be non-singular, hence uniqueness: Neumaier 1990, Thm 5.1.7).
pub fn krawczyk<const N: usize>(
    x: &IVec<N>,
    m: &[f64; N],
    fm: &IVec<N>,
    jx: &IMat<N>,
    y: &[[f64; N]; N],
) -> (IVec<N>, f64) {
    let yi = to_imat(y);
    let yj = mat_mul(&yi, jx);
    let c: IMat<N> =
        std::array::from_fn(|i| std::array::from_fn(|j| pt((i == j) as u8 as f64) - yj[i][j]));
    let norm = c
        .iter()
        .map(|r| {
            r.iter()
                .map(|e| if e.is_empty() { f64::INFINITY } else { e.mag() })
                .sum::<f64>()
        })
        .fold(0.0f64, f64::max);
    let xm: IVec<N> = std::array::from_fn(|k| x[k] - pt(m[k]));
    let yfm = mat_vec(&yi, fm);
    let cx = mat_vec(&c, &xm);
    let k = std::array::from_fn(|i| pt(m[i]) - yfm[i] + cx[i]);
    (k, if norm.is_nan() { f64::INFINITY } else { norm })
}

/// Is `k` non-empty, bounded and inside the interior of `x`, component by component?
/// (Not inari's `interior`, which holds for empty and for unbounded intervals.)
pub fn strictly_inside<const N: usize>(k: &IVec<N>, x: &IVec<N>) -> bool {
    (0..N).all(|i| {
        !k[i].is_empty()
            && k[i].inf().is_finite()
            && k[i].sup().is_finite()
            && k[i].inf() > x[i].inf()
            && k[i].sup() < x[i].sup()
    })
}

/// Is some component of `k` disjoint from `x` (or empty)?
pub fn disjoint<const N: usize>(k: &IVec<N>, x: &IVec<N>) -> bool {
    (0..N).any(|i| k[i].is_empty() || k[i].disjoint(x[i]))
}

/// 0 ∉ x strictly (and x not empty).
#[inline]
pub fn excludes_zero(x: Interval) -> bool {
    !x.is_empty() && (x.inf() > 0.0 || x.sup() < 0.0)
}

/// The sign of an interval that excludes 0: `Some(1)` or `Some(-1)`, else `None`.
#[inline]
pub fn sign(x: Interval) -> Option<i8> {
    if !excludes_zero(x) {
        None
    } else if x.inf() > 0.0 {
        Some(1)
    } else {
        Some(-1)
    }
}

/// The determinant of the principal submatrix on the indices `idx` (in that order),
/// by cofactor expansion in interval arithmetic (an enclosure of the determinant of
/// every real matrix in the interval matrix; n ≤ 4).
pub fn principal_det<const N: usize>(a: &IMat<N>, idx: &[usize]) -> Interval {
    match idx.len() {
        0 => pt(1.0),
        1 => a[idx[0]][idx[0]],
        _ => {
            // Expand along the first row of the submatrix.
            let r = idx[0];
            let mut s = pt(0.0);
            for (c_pos, &c) in idx.iter().enumerate() {
                let rows: Vec<usize> = idx[1..].to_vec();
                let cols: Vec<usize> = idx.iter().copied().filter(|&j| j != c).collect();
                let minor = minor_det(a, &rows, &cols);
                let term = a[r][c] * minor;
                s = if c_pos % 2 == 0 { s + term } else { s - term };
            }
            s
        }
    }
}

/// The determinant of the submatrix with the given rows and columns (equal lengths).
fn minor_det<const N: usize>(a: &IMat<N>, rows: &[usize], cols: &[usize]) -> Interval {
    match rows.len() {
        0 => pt(1.0),
        1 => a[rows[0]][cols[0]],
        2 => a[rows[0]][cols[0]] * a[rows[1]][cols[1]] - a[rows[0]][cols[1]] * a[rows[1]][cols[0]],
        _ => {
            let mut s = pt(0.0);
            for (k, &c) in cols.iter().enumerate() {
                let sub_cols: Vec<usize> = cols.iter().copied().filter(|&j| j != c).collect();
                let term = a[rows[0]][c] * minor_det(a, &rows[1..], &sub_cols);
                s = if k % 2 == 0 { s + term } else { s - term };
            }
            s
        }
    }
}

/// An enclosure of det A over the interval matrix.
pub fn det<const N: usize>(a: &IMat<N>) -> Interval {
    let idx: Vec<usize> = (0..N).collect();
    principal_det(a, &idx)
}

/// The inertia of every symmetric matrix in the interval matrix `a` (the number of
/// negative eigenvalues), certified by Jacobi's rule: if the leading principal minors
/// D₁, …, Dₙ of a symmetric matrix are all non-zero, the number of negative eigenvalues
/// equals the number of sign changes in 1, D₁, …, Dₙ (Jacobi 1857; Gantmacher, *The
/// Theory of Matrices*, 1959, vol. 1, ch. X §3, Thm 2). A symmetric permutation PAPᵀ
/// has the same eigenvalues, so every ordering of the variables is tried until one
/// gives minors that all exclude 0. `None` if none does (degenerate, or the enclosure
/// too wide to tell).
///
/// When no ordering works (a zero diagonal, as for the saddle xy + z² whose Hessian
/// has a zero leading minor in every order), the rule is applied to the congruent
/// matrix QᵀAQ, with Q the float eigenvector matrix of mid A used as an exact real
/// matrix: by Sylvester's law of inertia QᵀAQ has the inertia of A whenever Q is
/// non-singular, which is proven by 0 ∉ □det Q. QᵀAQ is nearly diagonal, so its
/// leading minors are far from 0 unless A is (nearly) singular.
pub fn inertia<const N: usize>(a: &IMat<N>) -> Option<usize> {
    let mut perm: Vec<usize> = (0..N).collect();
    loop {
        if let Some(k) = jacobi_count(a, &perm) {
            return Some(k);
        }
        if !next_permutation(&mut perm) {
            break;
        }
    }
    let mid = mid_mat(a);
    if mid.iter().flatten().any(|x| !x.is_finite()) {
        return None;
    }
    let q = to_imat(&eigenvectors(&mid));
    if !excludes_zero(det(&q)) {
        return None;
    }
    let qt: IMat<N> = std::array::from_fn(|i| std::array::from_fn(|j| q[j][i]));
    let b = mat_mul(&qt, &mat_mul(a, &q));
    let id: Vec<usize> = (0..N).collect();
    jacobi_count(&b, &id)
}

/// Float eigenvectors (columns) of a symmetric matrix by cyclic Jacobi rotations.
/// Only a change of basis for [`inertia`]: its accuracy is never relied on.
#[allow(clippy::needless_range_loop)]
pub fn eigenvectors<const N: usize>(a: &[[f64; N]; N]) -> [[f64; N]; N] {
    let mut m = *a;
    let mut v: [[f64; N]; N] =
        std::array::from_fn(|i| std::array::from_fn(|j| (i == j) as u8 as f64));
    for _sweep in 0..30 {
        let off: f64 = (0..N)
            .flat_map(|i| (0..N).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| m[i][j] * m[i][j])
            .sum();
        if off < 1e-30 {
            break;
        }
        for p in 0..N {
            for q in p + 1..N {
                if m[p][q].abs() < 1e-300 {
                    continue;
                }
                let theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..N {
                    let (mkp, mkq) = (m[k][p], m[k][q]);
                    m[k][p] = c * mkp - s * mkq;
                    m[k][q] = s * mkp + c * mkq;
                }
                for k in 0..N {
                    let (mpk, mqk) = (m[p][k], m[q][k]);
                    m[p][k] = c * mpk - s * mqk;
                    m[q][k] = s * mpk + c * mqk;
                }
                for k in 0..N {
                    let (vkp, vkq) = (v[k][p], v[k][q]);
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
        }
    }
    v
}

fn jacobi_count<const N: usize>(a: &IMat<N>, perm: &[usize]) -> Option<usize> {
    let mut prev = 1i8;
    let mut changes = 0;
    for k in 1..=N {
        let s = sign(principal_det(a, &perm[..k]))?;
        if s != prev {
            changes += 1;
        }
        prev = s;
    }
    Some(changes)
}

/// Lexicographic next permutation; false after the last one.
fn next_permutation(p: &mut [usize]) -> bool {
    let n = p.len();
    if n < 2 {
        return false;
    }
    let mut i = n - 1;
    while i > 0 && p[i - 1] >= p[i] {
        i -= 1;
    }
    if i == 0 {
        return false;
    }
    let mut j = n - 1;
    while p[j] <= p[i - 1] {
        j -= 1;
    }
    p.swap(i - 1, j);
    p[i..].reverse();
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iv(a: f64, b: f64) -> Interval {
        Interval::try_from((a, b)).unwrap()
    }

    #[test]
    fn inverse_and_det() {
        let a = [[2.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 4.0]];
        let y = inverse(&a).unwrap();
        for i in 0..3 {
            for j in 0..3 {
                let s: f64 = (0..3).map(|k| a[i][k] * y[k][j]).sum();
                assert!((s - (i == j) as u8 as f64).abs() < 1e-14);
            }
        }
        // det = 2(12 − 1) − 1(4 − 0) = 18
        assert!(det(&to_imat(&a)).contains(18.0));
        assert!(inverse(&[[1.0, 2.0], [2.0, 4.0]]).is_none());
    }

    #[test]
    fn inertia_by_jacobi() {
        // [[0, 1], [1, 0]] (eigenvalues ±1): D₁ = 0 in both orders, so Jacobi's rule
        // alone is undecided; the congruence decides index 1.
        let s = to_imat(&[[0.0, 1.0], [1.0, 0.0]]);
        assert_eq!(jacobi_count(&s, &[0, 1]), None);
        assert_eq!(inertia(&s), Some(1));
        // diag(−1, 2, −3): two negative eigenvalues.
        let d = to_imat(&[[-1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, -3.0]]);
        assert_eq!(inertia(&d), Some(2));
        // [[0, 1, 0], [1, 0, 0], [0, 0, 1]] has eigenvalues −1, 1, 1; D₁ = 0 in the
        // identity order, so a permutation is needed: starting with index 2 still
        // meets a 0 pivot; the rule must then say undecided or 1, never another value.
        let p = to_imat(&[[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]);
        assert_eq!(jacobi_count(&p, &[0, 1, 2]), None);
        assert_eq!(jacobi_count(&p, &[2, 0, 1]), None);
        // ... so the congruence QᵀAQ decides it.
        assert_eq!(inertia(&p), Some(1));
        // A random symmetric matrix against its float eigenvalues.
        let r = [[1.0, 2.0, -0.5], [2.0, -3.0, 0.25], [-0.5, 0.25, 0.1]];
        let v = eigenvectors(&r);
        let lam: Vec<f64> = (0..3)
            .map(|k| {
                let col = [v[0][k], v[1][k], v[2][k]];
                (0..3)
                    .map(|i| col[i] * (0..3).map(|j| r[i][j] * col[j]).sum::<f64>())
                    .sum()
            })
            .collect();
        let neg = lam.iter().filter(|&&x| x < 0.0).count();
        assert_eq!(inertia(&to_imat(&r)), Some(neg));
        // An interval matrix straddling singularity: undecided.
        let w = [[iv(-0.1, 0.1), pt(0.0)], [pt(0.0), pt(1.0)]];
        assert_eq!(inertia(&w), None);
    }

    #[test]
    fn krawczyk_linear() {
        // F(x) = A x − b with A = [[2, 1], [1, 3]], b = (3, 4): zero (1, 1).
        let a = [[2.0, 1.0], [1.0, 3.0]];
        let x = [iv(0.5, 1.5), iv(0.4, 1.6)];
        let m = [1.0, 1.0];
        let fm = [pt(0.0), pt(0.0)];
        let y = inverse(&a).unwrap();
        let (k, norm) = krawczyk(&x, &m, &fm, &to_imat(&a), &y);
        assert!(norm < 1e-12);
        assert!(strictly_inside(&k, &x));
        let far = [iv(5.0, 6.0), iv(5.0, 6.0)];
        let mf = [5.5, 5.5];
        let fmf = [pt(2.0 * 5.5 + 5.5 - 3.0), pt(5.5 + 3.0 * 5.5 - 4.0)];
        let (k, _) = krawczyk(&far, &mf, &fmf, &to_imat(&a), &y);
        assert!(disjoint(&k, &far));
    }
}
