//! Checks the SVG plots a run wrote for what hides what: a legend over a label, labels
//! over each other, and on plots without a map background a legend over the data.
//! Text boxes are estimated from the font size (half an em per character, one em
//! high), as plotters lays text out; the legend is plotters' white box at 85 % opacity.

use std::path::Path;

/// A box, px: left, top, right, bottom.
#[derive(Debug, Clone, Copy)]
struct Rect {
    l: f64,
    t: f64,
    r: f64,
    b: f64,
}

impl Rect {
    fn overlaps(&self, o: &Rect) -> bool {
        // One pixel of slack: touching edges are not hiding anything.
        self.l + 1.0 < o.r && o.l + 1.0 < self.r && self.t + 1.0 < o.b && o.t + 1.0 < self.b
    }
    fn contains(&self, (x, y): (f64, f64)) -> bool {
        x > self.l && x < self.r && y > self.t && y < self.b
    }
}

struct Label {
    text: String,
    anchor: (f64, f64),
    size: f64,
    rect: Rect,
}

fn number(node: roxmltree::Node<'_, '_>, name: &str) -> f64 {
    node.attribute(name).and_then(|v| v.parse().ok()).unwrap_or(0.0)
}

/// The estimated box of a `<text>` element, if it is horizontal.
fn label(node: roxmltree::Node<'_, '_>) -> Option<Label> {
    if node.attribute("transform").is_some() {
        return None;
    }
    let text: String = node.text()?.trim().to_string();
    let (x, y, size) = (number(node, "x"), number(node, "y"), number(node, "font-size"));
    let w = 0.5 * size * text.chars().count() as f64;
    let left = match node.attribute("text-anchor") {
        Some("middle") => x - w / 2.0,
        Some("end") => x - w,
        _ => x,
    };
    let top = match node.attribute("dy") {
        Some("0.76em") => y,
        Some("0.5ex") => y - size / 2.0,
        _ => y - size,
    };
    Some(Label { text, anchor: (x, y), size, rect: Rect { l: left, t: top, r: left + w, b: top + size } })
}

/// What hides what in one SVG file's text.
pub(crate) fn problems_in(name: &str, svg: &str) -> Vec<String> {
    let doc = match roxmltree::Document::parse(svg) {
        Ok(d) => d,
        Err(e) => return vec![format!("{name}: not SVG: {e}")],
    };
    let mut out = Vec::new();
    let labels: Vec<Label> = doc.descendants().filter(|n| n.has_tag_name("text")).filter_map(label).collect();
    let legend = doc.descendants().find(|n| {
        n.has_tag_name("rect") && n.attribute("opacity") == Some("0.85") && n.attribute("fill") == Some("#FFFFFF")
    });
    let legend = legend.map(|n| {
        let (x, y) = (number(n, "x"), number(n, "y"));
        Rect { l: x, t: y, r: x + number(n, "width"), b: y + number(n, "height") }
    });
    // The legend's own entries: the smallest text anchored inside it.
    let inside: Vec<&Label> = legend.map_or(Vec::new(), |r| labels.iter().filter(|l| r.contains(l.anchor)).collect());
    let entry_size = inside.iter().map(|l| l.size).fold(f64::INFINITY, f64::min);
    let is_entry = |l: &Label| legend.is_some_and(|r| r.contains(l.anchor)) && l.size == entry_size;
    if let Some(r) = legend {
        for l in labels.iter().filter(|l| !is_entry(l)) {
            if l.rect.overlaps(&r) {
                out.push(format!("{name}: the legend covers the label {:?}", l.text));
            }
        }
        // Without a map under it, the legend must not hide the data either.
        if !doc.descendants().any(|n| n.has_tag_name("image")) {
            for line in doc.descendants().filter(|n| n.has_tag_name("polyline")) {
                let points: Vec<(f64, f64)> = line
                    .attribute("points")
                    .unwrap_or_default()
                    .split_whitespace()
                    .filter_map(|p| p.split_once(',').and_then(|(x, y)| Some((x.parse().ok()?, y.parse().ok()?))))
                    .collect();
                // The legend's sample lines lie wholly inside it.
                if points.iter().all(|p| r.contains(*p)) {
                    continue;
                }
                if let Some(p) = points.iter().find(|p| r.contains(**p)) {
                    out.push(format!("{name}: the legend covers the data at {p:?}"));
                    break;
                }
            }
        }
    }
    let free: Vec<&Label> = labels.iter().filter(|l| !is_entry(l)).collect();
    for (i, a) in free.iter().enumerate() {
        for b in &free[i + 1..] {
            if a.rect.overlaps(&b.rect) {
                out.push(format!("{name}: the labels {:?} and {:?} overlap", a.text, b.text));
            }
        }
    }
    out
}

/// What hides what in every SVG plot in `dir`.
pub(crate) fn problems(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return vec![format!("{}: cannot read", dir.display())];
    };
    let mut files: Vec<_> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    files.sort();
    for path in files.iter().filter(|p| p.extension().is_some_and(|x| x == "svg")) {
        let name = path.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        match std::fs::read_to_string(path) {
            Ok(svg) => out.extend(problems_in(&name, &svg)),
            Err(e) => out.push(format!("{name}: {e}")),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The checker sees the defect it is for: a label under a legend, two labels on one
    /// another, and a curve under a legend on a plot without a map.
    #[test]
    fn the_checker_finds_planted_overlaps() {
        let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="900" height="500">
            <rect x="700" y="20" width="150" height="60" opacity="0.85" fill="#FFFFFF" stroke="none"/>
            <text x="740" y="30" dy="0.76em" font-size="10">night</text>
            <text x="720" y="50" dy="0.76em" font-size="12">start</text>
            <text x="100" y="300" dy="0.76em" font-size="12">goal A</text>
            <text x="110" y="302" dy="0.76em" font-size="12">goal B</text>
            <polyline points="100,400 750,40 800,400"/>
            <polyline points="705,50 725,50"/>
        </svg>"##;
        let found = problems_in("planted.svg", svg);
        assert!(found.iter().any(|p| p.contains("covers the label \"start\"")), "{found:?}");
        assert!(found.iter().any(|p| p.contains("\"goal A\" and \"goal B\"")), "{found:?}");
        assert!(found.iter().any(|p| p.contains("covers the data at (750.0, 40.0)")), "{found:?}");
        assert!(!found.iter().any(|p| p.contains("\"night\"")), "the legend's own entry: {found:?}");
        assert_eq!(found.len(), 3, "{found:?}");
    }
}
