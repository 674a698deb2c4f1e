//! Statistics of a finished subdivision ([`SubdivisionStats`]) and the leaf boxes for figures.
use super::*;
use crate::kernel::geom::Aabb;
use crate::mesher::{Cause, Certificate, Claim, Uncertified};
use std::collections::BTreeMap;

/// The statistics of a finished subdivision, shared by every criterion (a criterion adds
/// its own settings with [`Criterion::add_stats`](super::engine::Criterion::add_stats)).
/// Serialised field by field into the report's `stats` map.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SubdivisionStats {
    /// Leaf boxes of the final tree.
    pub leaves: usize,
    /// Boxes that were split.
    pub internal_boxes: usize,
    /// `leaves + internal_boxes`.
    pub boxes: usize,
    /// Leaves per depth (the root has depth 0).
    pub leaves_by_depth: BTreeMap<u8, usize>,
    /// All boxes (leaves and split ones) per depth.
    pub boxes_by_depth: BTreeMap<u8, usize>,
    /// Leaves per verdict label (`empty`, `proven (x)`, `failed: …`).
    pub leaves_by_criterion: BTreeMap<String, usize>,
    /// Splits made by the 2:1 balance (Plantinga–Vegter only; 0 otherwise).
    pub balance_splits: usize,
    /// No budget (boxes, time) stopped the subdivision, as in spade's
    /// `RefinementResult`; leaves left undecided at the depth limit are counted in
    /// `uncertified_boxes`.
    pub refinement_complete: bool,
    /// Interval bisection steps of the root isolation on box edges.
    pub root_isolation_steps: u64,
    /// Crossings of f = 0 with box edges placed.
    pub crossings: usize,
    /// Leaves the criterion could not decide.
    pub uncertified_boxes: usize,
    /// Undecided leaves plus undecided edges and faces found while assembling.
    pub uncertified_regions: usize,
}

/// The statistics of `tree` and its assembly.
pub fn tree_stats(tree: &Tree, a: &Assembled) -> SubdivisionStats {
    let failed = tree.failures().len();
    SubdivisionStats {
        leaves: tree.leaves.len(),
        internal_boxes: tree.internal.len(),
        boxes: tree.leaves.len() + tree.internal.len(),
        leaves_by_depth: tree.by_depth(),
        boxes_by_depth: tree.boxes_by_depth(),
        leaves_by_criterion: tree.by_verdict(),
        balance_splits: tree.balance_splits,
        refinement_complete: tree.refinement_complete,
        root_isolation_steps: a.root_steps,
        crossings: a.crossings,
        uncertified_boxes: failed,
        uncertified_regions: failed + a.uncertain.len(),
    }
}

/// Cells touching a point set, for tests and figures: the leaves with their boxes and
/// verdicts.
pub fn leaf_boxes(tree: &Tree) -> Vec<(Aabb, Verdict)> {
    tree.leaves
        .iter()
        .map(|l| (tree.grid.cell_aabb(l.cell), l.verdict))
        .collect()
}

/// "N region(s) not certified: n₁ reason₁; n₂ reason₂; …", the reasons in order of
/// [`Cause`] (a pole or a discontinuity first, the budgets last), then by count: every
/// cause is named, not only the first region's (a pole plane was hidden behind the
/// domain boundary's regions).
pub fn regions_summary(regions: &[Uncertified]) -> String {
    /// Reasons named; the rest are counted.
    const NAMED: usize = 6;
    let mut by_reason: std::collections::HashMap<&str, (Cause, usize)> = Default::default();
    for r in regions {
        by_reason.entry(&r.reason).or_insert((r.cause, 0)).1 += 1;
    }
    let mut counts: Vec<(Cause, &str, usize)> =
        by_reason.into_iter().map(|(t, (c, n))| (c, t, n)).collect();
    counts.sort_by(|a, b| a.0.cmp(&b.0).then(b.2.cmp(&a.2)).then(a.1.cmp(b.1)));
    let mut parts: Vec<String> = counts
        .iter()
        .take(NAMED)
        .map(|(_, t, n)| format!("{n} {t}"))
        .collect();
    if counts.len() > NAMED {
        let rest: usize = counts[NAMED..].iter().map(|c| c.2).sum();
        parts.push(format!("{rest} for {} other reasons", counts.len() - NAMED));
    }
    format!(
        "{} region(s) not certified: {}",
        regions.len(),
        parts.join("; ")
    )
}

/// The certificate of a finished subdivision run: certified (isotopy by `theorem`
/// inside `inside`, the regularity of the zero set it rests on, the boxes excluded as
/// empty) when no region failed, else uncertified with the regions.
pub fn certificate(
    theorem: &str,
    tree: &Tree,
    dim: usize,
    inside: &Aabb,
    generic_position: bool,
    mut regions: Vec<Uncertified>,
) -> Certificate {
    if !regions.is_empty() {
        // The most serious causes first (stable: tree order within a cause), so the
        // regions a report lists are those of a pole before those of a budget.
        regions.sort_by_key(|r| r.cause);
        return Certificate::uncertified(regions_summary(&regions), Vec::new(), regions);
    }
    let empty = tree
        .leaves
        .iter()
        .filter(|l| l.verdict == Verdict::Empty)
        .count();
    Certificate::certified(vec![
        Claim::Isotopic {
            inside: *inside,
            theorem: theorem.to_string(),
            generic_position,
        },
        Claim::RegularZeroSet {
            dim,
            inside: *inside,
        },
        Claim::ExcludedEmpty {
            empty,
            boxes: tree.leaves.len(),
        },
    ])
}

#[cfg(test)]
mod summary_tests {
    use super::*;

    fn region(reason: &str) -> Uncertified {
        Uncertified::new(Aabb::new([0.0; 3], [1.0; 3]).unwrap(), reason)
    }

    /// Every reason counted, a pole before the far more numerous boundary regions and
    /// the budget last; past six reasons the rest are counted, not listed.
    #[test]
    fn the_summary_counts_every_reason_most_serious_first() {
        let mut rs = vec![region(BOX_BUDGET_REASON)];
        rs.extend((0..5).map(|_| region("f = 0 meets the domain boundary")));
        rs.extend((0..2).map(|_| region(UNDEFINED_BOX)));
        rs.push(region(
            "f is not continuous on this box (pole or domain boundary)",
        ));
        let s = regions_summary(&rs);
        assert_eq!(
            s,
            format!(
                "9 region(s) not certified: 1 f is not continuous on this box (pole or \
                 domain boundary); 2 {UNDEFINED_BOX}; 5 f = 0 meets the domain boundary; \
                 1 {BOX_BUDGET_REASON}"
            )
        );
        let many: Vec<Uncertified> = (0..9).map(|k| region(&format!("other {k}"))).collect();
        let s = regions_summary(&many);
        assert!(s.ends_with("; 3 for 3 other reasons"), "{s}");
        assert_eq!(s.matches("other ").count(), 6 + 1, "{s}");
    }
}
