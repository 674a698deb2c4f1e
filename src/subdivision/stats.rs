//! Statistics of a finished subdivision, as JSON, and the leaf boxes for figures.
use super::*;
use crate::kernel::geom::Aabb;
use crate::mesher::{Certificate, Claim, Uncertified};
use std::collections::BTreeMap;

/// Statistics shared by both meshers, as JSON.
pub fn tree_stats(tree: &Tree, a: &Assembled) -> serde_json::Map<String, serde_json::Value> {
    use serde_json::json;
    let mut m = serde_json::Map::new();
    m.insert("leaves".into(), json!(tree.leaves.len()));
    m.insert("internal_boxes".into(), json!(tree.internal.len()));
    m.insert(
        "boxes".into(),
        json!(tree.leaves.len() + tree.internal.len()),
    );
    m.insert(
        "leaves_by_depth".into(),
        json!(tree
            .by_depth()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect::<BTreeMap<String, usize>>()),
    );
    m.insert(
        "boxes_by_depth".into(),
        json!(tree
            .boxes_by_depth()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect::<BTreeMap<String, usize>>()),
    );
    m.insert("leaves_by_criterion".into(), json!(tree.by_verdict()));
    m.insert("balance_splits".into(), json!(tree.balance_splits));
    m.insert(
        "refinement_complete".into(),
        json!(tree.refinement_complete),
    );
    m.insert("root_isolation_steps".into(), json!(a.root_steps));
    m.insert("crossings".into(), json!(a.crossings));
    let failed = tree.failures();
    m.insert("uncertified_boxes".into(), json!(failed.len()));
    m.insert(
        "uncertified_regions".into(),
        json!(failed.len() + a.uncertain.len()),
    );
    m
}

/// Cells touching a point set, for tests and figures: the leaves with their boxes and
/// verdicts.
pub fn leaf_boxes(tree: &Tree) -> Vec<(Aabb, Verdict)> {
    tree.leaves
        .iter()
        .map(|l| (tree.grid.cell_aabb(l.cell), l.verdict))
        .collect()
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
    regions: Vec<Uncertified>,
) -> Certificate {
    if !regions.is_empty() {
        return Certificate::uncertified(
            format!(
                "{} region(s) not certified (first: {})",
                regions.len(),
                regions[0].reason
            ),
            Vec::new(),
            regions,
        );
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
