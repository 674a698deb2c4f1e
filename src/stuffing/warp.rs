//! Step 3 of §3 (§3.2): violated lattice points snap to a violating cut point.
//!
//! A cut point `c` on edge `e` violates the endpoint `v` when `|cv| < α·|e|`, with
//! `α = α_long` on black edges and `α_short` on red ones. With `α_short = 0.5` we use
//! the convention of §6: a cut *exactly* at the midpoint of a red edge violates the
//! endpoint on the shifted lattice `Z³ + (½,½,½)` and not the one on `Z³`. A warped
//! point moves to the nearest violating cut point (the paper's usual choice).
//!
//! *Arbitrary order* is implemented as a 4-colour sweep ([`Field::colour`]): points of
//! one colour share no edge, so their decisions are independent and run in parallel;
//! the result equals a sequential run in colour order (deterministic for any thread
//! count). *Ordered warping* is the two-loop algorithm of §3.2, with a work queue.
use super::field::Field;
use crate::lattice::bcc::is_black_dir;
use rayon::prelude::*;
use std::collections::VecDeque;

/// Warping order (§3.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Order {
    #[default]
    Arbitrary,
    Ordered,
}

/// The violation rule, `t` measured from `q` along direction `d`.
#[inline]
pub fn violates(q_is_odd: bool, d: usize, t: f64, alpha_long: f64, alpha_short: f64) -> bool {
    if is_black_dir(d) {
        t < alpha_long
    } else {
        t < alpha_short || (alpha_short == 0.5 && t == 0.5 && q_is_odd)
    }
}

/// The nearest cut point violating `q` among the edges accepted by `ok(d, other)`.
fn nearest_violation(
    fl: &Field,
    q: u32,
    al: f64,
    as_: f64,
    ok: impl Fn(usize, u32) -> bool,
) -> Option<([f64; 3], u32)> {
    let odd = fl.is_odd(q);
    let mut best: Option<(f64, [f64; 3], u32)> = None;
    for d in 0..14 {
        if let Some((t, other)) = fl.cut_at(q, d) {
            if violates(odd, d, t, al, as_) && ok(d, other) {
                let dist = t * fl.lat.edge_length(d);
                if best.is_none_or(|(b, _, _)| dist < b) {
                    best = Some((dist, fl.cut_position(q, other, t), other));
                }
            }
        }
    }
    best.map(|b| (b.1, b.2))
}

/// Points that may be violated: positive points with cut edges and their negative
/// neighbours.
fn candidates(fl: &Field) -> Vec<u32> {
    let mut v = Vec::with_capacity(fl.cuts.len() * 3);
    for r in &fl.cuts {
        v.push(r.p);
        for d in 0..14 {
            if !r.t[d].is_nan() {
                if let Some(q) = fl.lat.neighbor(r.p, d) {
                    v.push(q);
                }
            }
        }
    }
    v.sort_unstable();
    v.dedup();
    v
}

/// Warp the lattice; returns the number of warped points.
pub fn warp(
    fl: &mut Field,
    alpha_long: f64,
    alpha_short: f64,
    order: Order,
    parallel: bool,
) -> usize {
    match order {
        Order::Arbitrary => warp_arbitrary(fl, alpha_long, alpha_short, parallel),
        Order::Ordered => warp_ordered(fl, alpha_long, alpha_short),
    }
}

fn warp_arbitrary(fl: &mut Field, al: f64, as_: f64, parallel: bool) -> usize {
    let cand = candidates(fl);
    let mut by_colour: [Vec<u32>; 4] = Default::default();
    for &q in &cand {
        by_colour[fl.colour(q)].push(q);
    }
    let mut n = 0;
    for class in &by_colour {
        let f: &Field = fl;
        let decide = |&q: &u32| nearest_violation(f, q, al, as_, |_, _| true).map(|p| (q, p));
        let moves: Vec<(u32, ([f64; 3], u32))> = if parallel {
            class.par_iter().filter_map(decide).collect()
        } else {
            class.iter().filter_map(decide).collect()
        };
        n += moves.len();
        for (q, p) in moves {
            fl.warp_to(q, p.0, p.1);
        }
    }
    n
}

/// Ordered warping (§3.2): first, negative points violated by a cut point on an edge to
/// an *unviolated* positive point warp (which can un-violate other positive points, so
/// the dependences cascade); then every still-violated positive point warps.
fn warp_ordered(fl: &mut Field, al: f64, as_: f64) -> usize {
    // Number of surviving cut points violating each positive point (by cut record).
    let viol_count = |fl: &Field, p: u32| -> u32 {
        let odd = fl.is_odd(p);
        (0..14)
            .filter(|&d| matches!(fl.cut_at(p, d), Some((t, _)) if violates(odd, d, t, al, as_)))
            .count() as u32
    };
    let mut count: Vec<u32> = fl.cuts.iter().map(|r| viol_count(fl, r.p)).collect();
    let mut queue: VecDeque<u32> = candidates(fl)
        .into_iter()
        .filter(|&q| fl.sign[q as usize] == -1)
        .collect();
    let mut n = 0;
    while let Some(q) = queue.pop_front() {
        if fl.sign[q as usize] != -1 {
            continue;
        }
        let target = {
            let f: &Field = fl;
            let cnt = &count;
            nearest_violation(f, q, al, as_, |_, p| cnt[f.surf[p as usize] as usize] == 0)
        };
        let Some((pos, toward)) = target else {
            continue;
        };
        // The cut points of q disappear: update the positive ends' counts.
        for d in 0..14 {
            if let Some((t, p)) = fl.cut_at(q, d) {
                let r = fl.surf[p as usize] as usize;
                if violates(fl.is_odd(p), d ^ 1, 1.0 - t, al, as_) {
                    count[r] -= 1;
                    if count[r] == 0 {
                        // p became unviolated: its negative neighbours may now warp.
                        for e in 0..14 {
                            if let Some((_, q2)) = fl.cut_at(p, e) {
                                if q2 != q {
                                    queue.push_back(q2);
                                }
                            }
                        }
                    }
                }
            }
        }
        fl.warp_to(q, pos, toward);
        n += 1;
    }
    // Second loop: positive points are never adjacent through a cut edge, so any order.
    let pos_cand: Vec<u32> = fl.cuts.iter().map(|r| r.p).collect();
    for p in pos_cand {
        if fl.sign[p as usize] != 1 {
            continue;
        }
        if let Some((pos, toward)) = nearest_violation(fl, p, al, as_, |_, _| true) {
            fl.warp_to(p, pos, toward);
            n += 1;
        }
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn midpoint_convention() {
        // Red edge (d = 6), cut exactly at the midpoint, α_short = 0.5.
        assert!(violates(true, 6, 0.5, 0.25, 0.5));
        assert!(!violates(false, 7, 0.5, 0.25, 0.5));
        // Only with α_short = 0.5 exactly.
        assert!(!violates(true, 6, 0.5, 0.25, 0.45));
        assert!(violates(false, 0, 0.2, 0.25, 0.45));
        assert!(!violates(false, 0, 0.25, 0.25, 0.45));
    }
}
