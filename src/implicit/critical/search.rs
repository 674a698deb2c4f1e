//! The branch and bound shared by both systems: exclusion, Krawczyk isolation, Newton
//! inflation for zeros on box faces, identification of zeros found twice (see the
//! parent module's doc).
use super::linalg::{self, excludes_zero, pt, IMat};
use super::{
    Budget, Bx, CriticalPoint, CriticalReport, MorseIndex, Problem, Reason, Stats, UndecidedBox,
};
use crate::implicit::{IBox, Implicit, Regularity};
use inari::Interval;
use std::time::Instant;

/// A square system F = 0 on boxes: what [`solve`] needs.
pub(super) trait System {
    fn f(&self) -> &dyn Implicit;
    /// Enclosures of F and J over a box where f is smooth.
    fn enclose(&self, x: &IBox) -> ([Interval; 3], IMat<3>);
    /// An enclosure of F at a point.
    fn at(&self, m: [f64; 3]) -> [Interval; 3];
    /// F and J at a point in floats (Newton iterates only).
    fn float(&self, p: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]);
    /// Can a box where f is only `reg` be excluded?
    fn exclude_nonsmooth(&self, x: &IBox, reg: Regularity) -> bool;
    /// Index and critical value at an isolated zero with enclosure `e`.
    fn classify(&self, e: &IBox) -> (MorseIndex, Interval);
}

fn widths(x: &IBox) -> [f64; 3] {
    x.map(|i| i.wid())
}

pub(super) fn bisect(x: &IBox) -> (IBox, IBox) {
    let w = widths(x);
    let k = (0..3).max_by(|&i, &j| w[i].total_cmp(&w[j])).unwrap_or(0);
    let m = x[k].mid();
    let mut l = *x;
    let mut r = *x;
    l[k] = Interval::try_from((x[k].inf(), m)).unwrap_or(x[k]);
    r[k] = Interval::try_from((m, x[k].sup())).unwrap_or(x[k]);
    (l, r)
}

fn subset(a: &IBox, b: &IBox) -> bool {
    (0..3).all(|k| a[k].subset(b[k]))
}

fn intersect(a: &IBox, b: &IBox) -> IBox {
    [0, 1, 2].map(|k| a[k].intersection(b[k]))
}

fn is_empty(a: &IBox) -> bool {
    a.iter().any(|x| x.is_empty())
}

fn contains_zero(x: Interval) -> bool {
    !excludes_zero(x) && !x.is_empty()
}

/// An isolating box and the enclosure of its one zero.
struct Isolated {
    iso: IBox,
    encl: IBox,
}

struct Search<'s, S: System> {
    sys: &'s S,
    domain: IBox,
    budget: Budget,
    found: Vec<Isolated>,
    points: Vec<CriticalPoint>,
    undecided: Vec<UndecidedBox>,
    stats: Stats,
}

/// The Krawczyk step on a smooth box: the operator, or `None` if J(X) has no usable
/// midpoint inverse.
fn krawczyk_step<S: System>(sys: &S, x: &IBox, jx: &IMat<3>) -> Option<(IBox, f64)> {
    let y = linalg::inverse(&linalg::mid_mat(jx))?;
    let m = [0, 1, 2].map(|k| x[k].mid());
    let fm = sys.at(m);
    Some(linalg::krawczyk(x, &m, &fm, jx, &y))
}

impl<S: System> Search<'_, S> {
    /// Record an isolating box `iso` (f smooth on it, K(iso) ⊂ int iso) with first
    /// enclosure `k`.
    fn isolate(&mut self, iso: IBox, k: IBox, depth: u32) {
        let mut encl = intersect(&k, &iso);
        for _ in 0..self.budget.shrink_steps {
            let (_, j) = self.sys.enclose(&encl);
            let Some((k2, _)) = krawczyk_step(self.sys, &encl, &j) else {
                break;
            };
            let next = intersect(&k2, &encl);
            if is_empty(&next) {
                break; // cannot happen for a box holding a zero; keep the last one
            }
            let shrunk = (0..3).any(|i| next[i].wid() < 0.7 * encl[i].wid());
            encl = next;
            if !shrunk {
                break;
            }
        }
        // Same zero as an earlier box, a different one, or undecided.
        for other in &self.found {
            if subset(&encl, &other.iso) || subset(&other.encl, &iso) {
                // The same zero, already accounted for; iso still covers boxes.
                self.found.push(Isolated { iso, encl });
                return;
            }
        }
        for other in &self.found {
            if !is_empty(&intersect(&encl, &other.encl)) {
                self.undecided.push(UndecidedBox {
                    region: Bx::from_ibox(&encl),
                    reason: Reason::Ambiguous,
                    depth,
                });
                self.found.push(Isolated { iso, encl });
                return;
            }
        }
        let inside = subset(&encl, &self.domain);
        let outside = is_empty(&intersect(&encl, &self.domain));
        if inside {
            let (index, value) = self.sys.classify(&encl);
            let e = Bx::from_ibox(&encl);
            self.points.push(CriticalPoint {
                enclosure: e,
                isolating: Bx::from_ibox(&iso),
                point: e.mid(),
                value: [value.inf(), value.sup()],
                index,
            });
        } else if !outside {
            self.undecided.push(UndecidedBox {
                region: Bx::from_ibox(&encl),
                reason: Reason::OnDomainBoundary,
                depth,
            });
        }
        self.found.push(Isolated { iso, encl });
    }

    /// A float Newton iterate from `m`, if it converges.
    fn newton(&self, m: [f64; 3]) -> Option<[f64; 3]> {
        let mut p = m;
        for _ in 0..20 {
            let (fp, j) = self.sys.float(p);
            let step = linalg::solve(&j, &fp)?;
            let q = [0, 1, 2].map(|k| p[k] - step[k]);
            let len = step.iter().fold(0.0f64, |s, x| s.max(x.abs()));
            if !len.is_finite() {
                return None;
            }
            p = q;
            if len <= 1e-14 * (1.0 + p.iter().fold(0.0f64, |s, x| s.max(x.abs()))) {
                return Some(p);
            }
        }
        None
    }

    /// Try an isolating box around a Newton iterate from the middle of x.
    fn inflate(&mut self, x: &IBox, depth: u32) -> bool {
        let m = [0, 1, 2].map(|k| x[k].mid());
        let Some(p) = self.newton(m) else {
            return false;
        };
        let w = widths(x);
        let r = w.iter().fold(0.0f64, |s, &v| s.max(v));
        // Only a zero near x helps here.
        if (0..3).any(|k| (p[k] - m[k]).abs() > w[k]) {
            return false;
        }
        let xp: IBox =
            [0, 1, 2].map(|k| Interval::try_from((p[k] - r, p[k] + r)).unwrap_or(Interval::ENTIRE));
        if self.sys.f().regularity(&xp) != Regularity::Smooth {
            return false;
        }
        let (_, j) = self.sys.enclose(&xp);
        self.stats.krawczyk_tests += 1;
        let Some((k, _)) = krawczyk_step(self.sys, &xp, &j) else {
            return false;
        };
        if linalg::strictly_inside(&k, &xp) {
            self.stats.inflations += 1;
            self.isolate(xp, k, depth);
            true
        } else {
            false
        }
    }

    fn undecided(&mut self, x: &IBox, reason: Reason, depth: u32) {
        self.undecided.push(UndecidedBox {
            region: Bx::from_ibox(x),
            reason,
            depth,
        });
    }

    fn run(&mut self) {
        let deadline = self.budget.time_limit.and_then(|s| {
            std::time::Instant::now().checked_add(std::time::Duration::try_from_secs_f64(s).ok()?)
        });
        let mut stack: Vec<(IBox, u32, bool)> = vec![(self.domain, 0, false)];
        while let Some((x, depth, parent_smooth)) = stack.pop() {
            // The clock every 1024 boxes (it costs ~20 ns).
            let late = self.stats.boxes % 1024 == 0
                && deadline.is_some_and(|d| std::time::Instant::now() > d);
            if self.stats.boxes >= self.budget.max_boxes || late {
                let why = if late {
                    Reason::TimeLimit
                } else {
                    Reason::Budget
                };
                self.undecided(&x, why, depth);
                for (y, d, _) in std::mem::take(&mut stack) {
                    self.undecided(&y, why, d);
                }
                break;
            }
            self.stats.boxes += 1;
            self.stats.max_depth = self.stats.max_depth.max(depth);
            if self.found.iter().any(|c| subset(&x, &c.iso)) {
                self.stats.covered += 1;
                continue;
            }
            // f is C^∞ near a sub-box of a box where it is C^∞ near.
            let reg = if parent_smooth {
                Regularity::Smooth
            } else {
                self.sys.f().regularity(&x)
            };
            if reg != Regularity::Smooth {
                if self.sys.exclude_nonsmooth(&x, reg) {
                    self.stats.excluded += 1;
                    continue;
                }
                if depth >= self.budget.max_depth.min(self.budget.nonsmooth_depth) {
                    let why = if reg == Regularity::Continuous {
                        Reason::NotDifferentiable
                    } else {
                        Reason::NotContinuous
                    };
                    self.undecided(&x, why, depth);
                } else {
                    let (l, r) = bisect(&x);
                    stack.push((l, depth + 1, false));
                    stack.push((r, depth + 1, false));
                }
                continue;
            }
            let (fx, jx) = self.sys.enclose(&x);
            if fx.iter().any(|&v| !contains_zero(v)) {
                self.stats.excluded += 1;
                continue;
            }
            // Centred form Fᵢ(m) + Jᵢ(X)(X − m).
            let m = [0, 1, 2].map(|k| x[k].mid());
            let fm = self.sys.at(m);
            let xm: [Interval; 3] = [0, 1, 2].map(|k| x[k] - pt(m[k]));
            let centred = linalg::mat_vec(&jx, &xm);
            if (0..3).any(|i| !contains_zero(fm[i] + centred[i])) {
                self.stats.excluded += 1;
                continue;
            }
            let mut next = x;
            let mut contracts = false;
            if let Some(y) = linalg::inverse(&linalg::mid_mat(&jx)) {
                self.stats.krawczyk_tests += 1;
                let (k, norm) = linalg::krawczyk(&x, &m, &fm, &jx, &y);
                if linalg::disjoint(&k, &x) {
                    self.stats.excluded += 1;
                    continue;
                }
                if linalg::strictly_inside(&k, &x) {
                    self.isolate(x, k, depth);
                    continue;
                }
                contracts = norm < 0.5;
                // Every zero of x lies in K(x) ∩ x.
                let kx = intersect(&k, &x);
                if !is_empty(&kx) {
                    next = kx;
                }
            }
            if contracts
                && self.inflate(&x, depth)
                && self.found.last().is_some_and(|c| subset(&x, &c.iso))
            {
                self.stats.covered += 1;
                continue;
            }
            if depth >= self.budget.max_depth {
                let reason = if contains_zero(linalg::det(&jx)) {
                    Reason::PossiblyDegenerate
                } else {
                    Reason::DepthLimit
                };
                self.undecided(&x, reason, depth);
                continue;
            }
            let (wx, wn) = (widths(&x), widths(&next));
            let wmax = |w: [f64; 3]| w.iter().fold(0.0f64, |s, &v| s.max(v));
            if wmax(wn) < 0.7 * wmax(wx) {
                stack.push((next, depth + 1, true));
            } else {
                let (l, r) = bisect(&next);
                stack.push((l, depth + 1, true));
                stack.push((r, depth + 1, true));
            }
        }
    }
}

pub(super) fn solve<S: System>(
    sys: &S,
    problem: Problem,
    domain: Bx,
    budget: Budget,
) -> CriticalReport {
    let t0 = Instant::now();
    let mut s = Search {
        sys,
        domain: domain.to_ibox(),
        budget,
        found: Vec::new(),
        points: Vec::new(),
        undecided: Vec::new(),
        stats: Stats::default(),
    };
    let valid = (0..3).all(|k| {
        domain.lo[k].is_finite() && domain.hi[k].is_finite() && domain.lo[k] < domain.hi[k]
    });
    let d = s.domain;
    if sys.f().dim() != 3 || !valid {
        s.undecided(&d, Reason::Unsupported, 0);
    } else if !sys.f().is_rigorous() {
        s.undecided(&d, Reason::NotRigorous, 0);
    } else {
        s.run();
    }
    s.stats.millis = t0.elapsed().as_secs_f64() * 1e3;
    CriticalReport {
        problem,
        domain,
        complete: s.undecided.is_empty(),
        points: s.points,
        undecided: s.undecided,
        stats: s.stats,
    }
}
