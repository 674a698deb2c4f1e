//! Placing point labels so that they overlap neither each other nor the points: a
//! greedy search over eight positions around each point (right first, as a reader
//! expects), in figure units, keeping the label inside the plotting area.

/// A label's box in figure units: (x0, y0, x1, y1), y down.
type Box2 = (f64, f64, f64, f64);

/// The estimated box of `text` at font size `size` (figure units) with its top-left
/// corner at (x, y): sans-serif glyphs average 0.6 em.
pub fn text_box(text: &str, size: f64, x: f64, y: f64) -> Box2 {
    (x, y, x + 0.6 * size * text.chars().count() as f64, y + size)
}

fn overlap(a: Box2, b: Box2) -> f64 {
    let w = (a.2.min(b.2) - a.0.max(b.0)).max(0.0);
    let h = (a.3.min(b.3) - a.1.max(b.1)).max(0.0);
    w * h
}

/// Top-left corners for `labels` at `points` (figure units) with font `size`, inside
/// `bounds`, avoiding the points themselves (disks of radius `r`) and earlier labels;
/// where every position overlaps, the least-overlapping one.
pub fn place(
    points: &[(f64, f64)],
    labels: &[String],
    size: f64,
    r: f64,
    bounds: Box2,
) -> Vec<(f64, f64)> {
    place_avoiding(points, labels, size, r, bounds, &[])
}

/// Boxes of half-width `w` every `step` along the segment a–b (figure units): a drawn
/// line as obstacles for [`place_avoiding`].
pub fn along(a: (f64, f64), b: (f64, f64), w: f64, step: f64) -> Vec<Box2> {
    let n = ((b.0 - a.0).hypot(b.1 - a.1) / step.max(1e-9))
        .ceil()
        .max(1.0) as usize;
    (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let (x, y) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
            (x - w, y - w, x + w, y + w)
        })
        .collect()
}

/// [`place`], also keeping the labels off `obstacles` (e.g. the drawn lines, [`along`]).
pub fn place_avoiding(
    points: &[(f64, f64)],
    labels: &[String],
    size: f64,
    r: f64,
    bounds: Box2,
    obstacles: &[Box2],
) -> Vec<(f64, f64)> {
    let mut taken: Vec<Box2> = points
        .iter()
        .map(|&(x, y)| (x - r, y - r, x + r, y + r))
        .chain(obstacles.iter().copied())
        .collect();
    let mut out = Vec::with_capacity(labels.len());
    for (&(x, y), l) in points.iter().zip(labels) {
        let (w, h) = (0.6 * size * l.chars().count() as f64, size);
        let g = r + 0.25 * size;
        let cands = [
            (x + g, y - 0.5 * h),
            (x - g - w, y - 0.5 * h),
            (x - 0.5 * w, y - g - h),
            (x - 0.5 * w, y + g),
            (x + g, y - g - h),
            (x + g, y + g),
            (x - g - w, y - g - h),
            (x - g - w, y + g),
        ];
        let score = |&(cx, cy): &(f64, f64)| {
            let b = (cx, cy, cx + w, cy + h);
            let outside = (bounds.0 - b.0).max(0.0)
                + (b.2 - bounds.2).max(0.0)
                + (bounds.1 - b.1).max(0.0)
                + (b.3 - bounds.3).max(0.0);
            taken.iter().map(|t| overlap(*t, b)).sum::<f64>() + outside * h * 4.0
        };
        let best = cands
            .iter()
            .copied()
            .min_by(|a, b| score(a).total_cmp(&score(b)))
            .unwrap_or((x + g, y));
        taken.push((best.0, best.1, best.0 + w, best.1 + h));
        out.push(best);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn labels_keep_off_lines() {
        // A line running right from the point: the label goes elsewhere.
        let line = along((100.0, 100.0), (400.0, 100.0), 2.0, 4.0);
        let l = vec!["W3".to_string()];
        let at = place_avoiding(
            &[(100.0, 100.0)],
            &l,
            30.0,
            8.0,
            (0.0, 0.0, 1000.0, 1000.0),
            &line,
        );
        let b = text_box(&l[0], 30.0, at[0].0, at[0].1);
        assert!(line.iter().all(|o| overlap(*o, b) == 0.0), "{b:?}");
        let free = place(&[(100.0, 100.0)], &l, 30.0, 8.0, (0.0, 0.0, 1000.0, 1000.0));
        assert!(free[0].0 > 100.0, "right first without obstacles: {free:?}");
    }
    #[test]
    fn crowded_labels_do_not_overlap() {
        let pts = [(100.0, 100.0), (104.0, 100.0), (108.0, 102.0)];
        let labels: Vec<String> = ["alpha", "beta", "gamma"].map(String::from).to_vec();
        let at = place(&pts, &labels, 30.0, 8.0, (0.0, 0.0, 1000.0, 1000.0));
        let boxes: Vec<_> = at
            .iter()
            .zip(&labels)
            .map(|(p, l)| text_box(l, 30.0, p.0, p.1))
            .collect();
        for i in 0..3 {
            for j in i + 1..3 {
                assert_eq!(overlap(boxes[i], boxes[j]), 0.0, "{i} {j}: {boxes:?}");
            }
        }
    }
}
