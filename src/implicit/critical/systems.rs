//! The two square systems solved by the search: ∇f = 0, and (f, ∇f·e₁, ∇f·e₂) = 0
//! for the critical points of a height on S (see the parent module's doc for the
//! frame and the index of the height).
use super::linalg::{self, excludes_zero, pt, IMat};
use super::search::System;
use super::MorseIndex;
use crate::implicit::{IBox, Implicit, Regularity};
use inari::Interval;
use serde::{Deserialize, Serialize};

pub(super) fn sym(h: &[Interval; 6]) -> IMat<3> {
    use crate::implicit::number::hidx;
    std::array::from_fn(|i| std::array::from_fn(|j| h[hidx(i, j)]))
}

fn symf(h: &[f64; 6]) -> [[f64; 3]; 3] {
    use crate::implicit::number::hidx;
    std::array::from_fn(|i| std::array::from_fn(|j| h[hidx(i, j)]))
}

fn point_box(m: [f64; 3]) -> IBox {
    m.map(pt)
}

fn idot(a: &[Interval; 3], b: &[Interval; 3]) -> Interval {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(super) struct Gradient<'a> {
    pub(super) f: &'a dyn Implicit,
}

impl System for Gradient<'_> {
    fn f(&self) -> &dyn Implicit {
        self.f
    }
    fn enclose(&self, x: &IBox) -> ([Interval; 3], IMat<3>) {
        let h = self.f.hessian_interval(x);
        (h.g, sym(&h.h))
    }
    fn at(&self, m: [f64; 3]) -> [Interval; 3] {
        self.f.grad_interval(&point_box(m)).g
    }
    fn float(&self, p: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
        let h = self.f.hessian(p);
        (h.g, symf(&h.h))
    }
    fn exclude_nonsmooth(&self, _x: &IBox, _reg: Regularity) -> bool {
        false
    }
    fn classify(&self, e: &IBox) -> (MorseIndex, Interval) {
        let h = self.f.hessian_interval(e);
        let a = sym(&h.h);
        let index = match linalg::inertia(&a) {
            Some(k) => MorseIndex::Certified { index: k as u8 },
            None if !excludes_zero(linalg::det(&a)) => MorseIndex::PossiblyDegenerate,
            None => MorseIndex::Undecided,
        };
        (index, self.f.eval_interval(e))
    }
}

/// The tangent frame of a height direction.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Frame {
    pub d: [f64; 3],
    pub e1: [f64; 3],
    pub e2: [f64; 3],
}

impl Frame {
    /// e₁ = normalise(d × a) with a the axis of d's smallest component, e₂ = d × e₁.
    /// `None` for a zero or non-finite d.
    pub fn new(d: [f64; 3]) -> Option<Frame> {
        use crate::kernel::geom::{cross, dot, scale};
        let n = dot(d, d).sqrt();
        if !(n.is_finite() && n > 0.0) {
            return None;
        }
        let d = scale(d, 1.0 / n);
        let k = (0..3).min_by(|&i, &j| d[i].abs().total_cmp(&d[j].abs()))?;
        let mut a = [0.0; 3];
        a[k] = 1.0;
        let e1 = cross(d, a);
        let e1 = scale(e1, 1.0 / dot(e1, e1).sqrt());
        let e2 = cross(d, e1);
        Some(Frame { d, e1, e2 })
    }
    /// n = e₁ × e₂, enclosed: the exact height direction.
    pub fn normal(&self) -> [Interval; 3] {
        let a = self.e1.map(pt);
        let b = self.e2.map(pt);
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }
    /// Eᵀ H E for E = [e₁ e₂], in floats.
    pub fn restrict(&self, h: &[[f64; 3]; 3]) -> [[f64; 2]; 2] {
        let e = [self.e1, self.e2];
        std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                let mut s = 0.0;
                for i in 0..3 {
                    for j in 0..3 {
                        s += e[a][i] * h[i][j] * e[b][j];
                    }
                }
                s
            })
        })
    }
}

/// The Hessian of the height ⟨n, x⟩ restricted to S at a critical point p, in the
/// basis e₁, e₂, in floats: −(1/λ) Eᵀ H_f E with λ = ∇f·n/|n|² (see the module doc).
/// For tests and diagnostics; the certified index uses the interval version.
pub fn height_hessian_on_surface(f: &dyn Implicit, frame: &Frame, p: [f64; 3]) -> [[f64; 2]; 2] {
    let h = f.hessian(p);
    let n = frame.normal().map(|x| x.mid());
    let lambda = crate::kernel::geom::dot(h.g, n) / crate::kernel::geom::dot(n, n);
    let m = frame.restrict(&symf(&h.h));
    m.map(|r| r.map(|x| -x / lambda))
}

pub(super) struct Height<'a> {
    pub(super) f: &'a dyn Implicit,
    pub(super) frame: Frame,
    pub(super) e1: [Interval; 3],
    pub(super) e2: [Interval; 3],
    pub(super) n: [Interval; 3],
}

impl System for Height<'_> {
    fn f(&self) -> &dyn Implicit {
        self.f
    }
    fn enclose(&self, x: &IBox) -> ([Interval; 3], IMat<3>) {
        let h = self.f.hessian_interval(x);
        let hm = sym(&h.h);
        let he1 = linalg::mat_vec(&hm, &self.e1);
        let he2 = linalg::mat_vec(&hm, &self.e2);
        (
            [h.v, idot(&h.g, &self.e1), idot(&h.g, &self.e2)],
            [h.g, he1, he2],
        )
    }
    fn at(&self, m: [f64; 3]) -> [Interval; 3] {
        let d = self.f.grad_interval(&point_box(m));
        [d.v, idot(&d.g, &self.e1), idot(&d.g, &self.e2)]
    }
    fn float(&self, p: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
        use crate::kernel::geom::dot;
        let h = self.f.hessian(p);
        let hm = symf(&h.h);
        let mv = |e: [f64; 3]| [0, 1, 2].map(|i| dot(hm[i], e));
        (
            [h.v, dot(h.g, self.frame.e1), dot(h.g, self.frame.e2)],
            [h.g, mv(self.frame.e1), mv(self.frame.e2)],
        )
    }
    fn exclude_nonsmooth(&self, x: &IBox, reg: Regularity) -> bool {
        // f continuous on X and 0 ∉ □f: X holds no point of S.
        reg >= Regularity::Continuous && excludes_zero(self.f.eval_interval(x))
    }
    fn classify(&self, e: &IBox) -> (MorseIndex, Interval) {
        let h = self.f.hessian_interval(e);
        let hm = sym(&h.h);
        let es = [self.e1, self.e2];
        let m: IMat<2> = std::array::from_fn(|a| {
            std::array::from_fn(|b| idot(&es[a], &linalg::mat_vec(&hm, &es[b])))
        });
        let value = idot(&self.n, e);
        let Some(s) = linalg::sign(idot(&h.g, &self.n)) else {
            return (MorseIndex::Undecided, value);
        };
        // The restricted Hessian of the height is −(1/λ) M with sign(λ) = s.
        let a: IMat<2> = m.map(|r| r.map(|x| if s > 0 { -x } else { x }));
        let index = match linalg::inertia(&a) {
            Some(k) => MorseIndex::Certified { index: k as u8 },
            None if !excludes_zero(linalg::det(&a)) => MorseIndex::PossiblyDegenerate,
            None => MorseIndex::Undecided,
        };
        (index, value)
    }
}
