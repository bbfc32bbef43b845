//! Where a plot's legend and marker labels go so that neither hides the other, nor
//! (where there is room) the data: boxes in pixels, chosen among candidate places by
//! what each would cover.

/// A box on the page, px: left, top, width, height.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Bounds {
    pub x: i32,
    pub y: i32,
    pub w: i32,
    pub h: i32,
}

impl Bounds {
    pub(crate) fn intersects(&self, o: &Bounds) -> bool {
        self.x < o.x + o.w && o.x < self.x + self.w && self.y < o.y + o.h && o.y < self.y + self.h
    }

    pub(crate) fn contains(&self, (x, y): (i32, i32)) -> bool {
        x >= self.x && x <= self.x + self.w && y >= self.y && y <= self.y + self.h
    }

    fn within(&self, area: &Bounds) -> bool {
        self.x >= area.x && self.y >= area.y && self.x + self.w <= area.x + area.w && self.y + self.h <= area.y + area.h
    }
}

/// A label to place: its marker's centre and the label's size, px.
pub(crate) type Anchor = ((i32, i32), (i32, i32));

/// The gap between a legend and the plotting area's edge, px (plotters' own).
const EDGE: i32 = 5;

/// The nine places a legend of `size` can take in `area` (corners, edge middles,
/// centre last), in order of preference.
fn legend_places(area: &Bounds, (w, h): (i32, i32)) -> Vec<Bounds> {
    let xs = [area.x + area.w - w - EDGE, area.x + EDGE, area.x + (area.w - w) / 2];
    let ys = [area.y + EDGE, area.y + area.h - h - EDGE, area.y + (area.h - h) / 2];
    let mut out = Vec::with_capacity(9);
    for &y in &ys {
        for &x in &xs {
            out.push(Bounds { x, y, w, h });
        }
    }
    out
}

/// The legend's box: the place in `area` that covers none of `keep` (marker labels'
/// likely boxes) if one does, and the fewest `points` (the data's vertices) among
/// those.
pub(crate) fn legend_place(area: &Bounds, size: (i32, i32), keep: &[Bounds], points: &[(i32, i32)]) -> Bounds {
    let places = legend_places(area, size);
    let cost = |b: &Bounds| {
        let hidden = keep.iter().filter(|k| k.intersects(b)).count();
        let covered = points.iter().filter(|p| b.contains(**p)).count();
        (hidden, covered)
    };
    // `min_by_key` keeps the first of equals: the preferred place wins ties.
    places.into_iter().min_by_key(cost).unwrap_or(Bounds { x: area.x, y: area.y, w: size.0, h: size.1 })
}

/// Boxes for labels of the given sizes beside their anchors (marker centres), each
/// clear of `avoid`, of the labels placed before it and of the other anchors' markers
/// (`radius` px) where a candidate allows, and inside `area`; otherwise the candidate
/// that overlaps least.
pub(crate) fn place_labels(area: &Bounds, labels: &[Anchor], radius: i32, avoid: &[Bounds]) -> Vec<Bounds> {
    let markers: Vec<Bounds> = labels
        .iter()
        .map(|&((x, y), _)| Bounds { x: x - radius, y: y - radius, w: 2 * radius, h: 2 * radius })
        .collect();
    let mut placed: Vec<Bounds> = Vec::with_capacity(labels.len());
    for &((x, y), (w, h)) in labels {
        let gap = radius + 2;
        // Beside the marker first, then stacked farther above and below it.
        let mut candidates = Vec::with_capacity(24);
        for k in 0..4 {
            let step = k * (h + 2);
            candidates.extend([
                (x + gap, y - h - 2 - step),
                (x + gap, y + 2 + step),
                (x - gap - w, y - h - 2 - step),
                (x - gap - w, y + 2 + step),
                (x - w / 2, y - gap - h - step),
                (x - w / 2, y + gap + step),
            ]);
        }
        let score = |b: &Bounds| {
            let clashes = avoid.iter().chain(&placed).chain(&markers).filter(|o| o.intersects(b)).count();
            clashes + usize::from(!b.within(area))
        };
        // `min_by_key` keeps the first of equals: the nearest place wins ties.
        let best =
            candidates.iter().map(|&(x, y)| Bounds { x, y, w, h }).min_by_key(score).unwrap_or(Bounds { x, y, w, h });
        placed.push(best);
    }
    placed
}

#[cfg(test)]
mod tests {
    use super::*;

    const AREA: Bounds = Bounds { x: 60, y: 40, w: 800, h: 600 };

    #[test]
    fn the_legend_leaves_the_corner_with_a_label_and_prefers_upper_right() {
        let size = (150, 100);
        let free = legend_place(&AREA, size, &[], &[]);
        assert_eq!((free.x, free.y), (60 + 800 - 150 - 5, 45));
        // A label in the upper right corner sends it to the next place without one.
        let label = Bounds { x: 800, y: 50, w: 40, h: 14 };
        let moved = legend_place(&AREA, size, &[label], &[]);
        assert!(!moved.intersects(&label));
        assert_eq!((moved.x, moved.y), (65, 45));
        // Data in the upper left too: the place covering fewest points wins.
        let points: Vec<(i32, i32)> = (0..50).map(|i| (70 + i, 60 + i)).collect();
        let third = legend_place(&AREA, size, &[label], &points);
        assert!(!third.intersects(&label) && points.iter().all(|p| !third.contains(*p)), "{third:?}");
    }

    #[test]
    fn labels_of_close_markers_do_not_overlap() {
        // Five markers 10 px apart in a row, labels 60 × 14 px.
        let labels: Vec<Anchor> = (0..5).map(|i| ((300 + 10 * i, 300), (60, 14))).collect();
        let placed = place_labels(&AREA, &labels, 6, &[]);
        let clashes = (0..5)
            .flat_map(|i| (i + 1..5).map(move |j| (i, j)))
            .filter(|&(i, j)| placed[i].intersects(&placed[j]))
            .count();
        assert_eq!(clashes, 0, "{placed:?}");
        // Nor over a marker (6 px radius).
        for b in &placed {
            for &((x, y), _) in &labels {
                assert!(!b.intersects(&Bounds { x: x - 6, y: y - 6, w: 12, h: 12 }), "{b:?} over ({x}, {y})");
            }
        }
        // A lone label near the right edge goes left of its marker, inside the area.
        let edge = place_labels(&AREA, &[((855, 300), (60, 14))], 6, &[]);
        assert!(edge[0].within(&AREA) && edge[0].x + 60 < 855, "{edge:?}");
    }
}
