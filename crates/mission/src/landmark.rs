//! The search's cached 2-D lower bound: for every cell, the least cost of driving to it
//! from one anchor cell (a segment's first start), over the grid of drives that are
//! possible at some time, each costed at the least it can cost at any time. Hybrid A*
//! and Nav2 Smac guide their searches with the same kind of bound; it knows what the
//! octile floors cannot — walls, cliffs and slopes to go around.
//!
//! The search runs backward from the goal, so its heuristic is a bound on the cost from
//! the rover's *current* start to a cell. With `D` the anchor's distances, the triangle
//! inequality gives `cost(start → s) ≥ D(s) − D(start)` (the ALT bound of Goldberg &
//! Harrelson, 2005, with the anchor as landmark): one map serves every later start, so
//! the rover moving never recomputes it.
//!
//! The map is filled lazily (a resumable Dijkstra): a cell's distance is settled when
//! the search first asks for it, so the work grows with the region the search explores,
//! not with the world (LITA's map holds 6 million cells; its route crosses 70). When
//! sensing changes the map — a wall where it showed a pass, a gentler slope — the map
//! is repaired where drives got cheaper, with a bound on how far any distance fell
//! ([`Landmark::lower`], so the engine keeps its open list), while the rover is still at
//! the anchor; once it has moved on, a new map is anchored at the rover (as tight as a
//! fresh search's) and the engine keys its open list again
//! ([`crate::TempestDomain::forget`]).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Cells per page of the distance table.
const PAGE: usize = 1 << 10;

/// Least-cost distances from one anchor cell, settled on demand.
#[derive(Debug, Clone)]
pub(crate) struct Landmark {
    /// Tentative or settled distance of each cell, in pages allocated as the search
    /// reaches them; `INFINITY`: not reached yet.
    pages: Vec<Option<Box<[f64; PAGE]>>>,
    /// How many pages are allocated.
    held: usize,
    /// The frontier: (distance bits, cell). Non-negative f64s order as their bits.
    heap: BinaryHeap<Reverse<(u64, u32)>>,
    /// The largest distance settled so far: every cell below it is settled.
    radius: f64,
}

/// The drives out of a cell: each destination and the least the drive can cost (≥ 0).
pub(crate) type Edges<'e> = &'e mut Vec<(u32, f64)>;

impl Landmark {
    /// The map for `anchor`; nothing is settled until asked.
    pub(crate) fn new(anchor: u32) -> Landmark {
        let mut l = Landmark { pages: Vec::new(), held: 0, heap: BinaryHeap::new(), radius: 0.0 };
        l.set(anchor, 0.0);
        l.heap.push(Reverse((0f64.to_bits(), anchor)));
        l
    }

    /// The map for the nearest of several anchors (a Dijkstra from all at once).
    pub(crate) fn from_anchors(anchors: &[u32]) -> Landmark {
        let mut l = Landmark { pages: Vec::new(), held: 0, heap: BinaryHeap::new(), radius: 0.0 };
        for &a in anchors {
            l.set(a, 0.0);
            l.heap.push(Reverse((0f64.to_bits(), a)));
        }
        l
    }

    fn value(&self, cell: u32) -> f64 {
        let i = cell as usize;
        self.pages.get(i / PAGE).and_then(|p| p.as_deref()).map_or(f64::INFINITY, |p| p[i % PAGE])
    }

    fn set(&mut self, cell: u32, d: f64) {
        let i = cell as usize;
        if self.pages.len() <= i / PAGE {
            self.pages.resize_with(i / PAGE + 1, || None);
        }
        let held = &mut self.held;
        self.pages[i / PAGE].get_or_insert_with(|| {
            *held += 1;
            Box::new([f64::INFINITY; PAGE])
        })[i % PAGE] = d;
    }

    /// Lowers `cell` to `d` if that is less than it has.
    fn relax(&mut self, cell: u32, d: f64) {
        if d < self.value(cell) {
            self.set(cell, d);
            self.heap.push(Reverse((d.to_bits(), cell)));
        }
    }

    /// Settles frontier cells while the least is below `bound`.
    fn settle_below(&mut self, bound: f64, edges: &mut impl FnMut(u32, Edges<'_>)) {
        let mut out = Vec::with_capacity(8);
        while let Some(&Reverse((bits, cell))) = self.heap.peek() {
            let d = f64::from_bits(bits);
            if d >= bound {
                break;
            }
            self.heap.pop();
            if d > self.value(cell) {
                // Superseded by a lower entry.
                continue;
            }
            self.radius = self.radius.max(d);
            out.clear();
            edges(cell, &mut out);
            for &(to, w) in &out {
                self.relax(to, d + w);
            }
        }
    }

    /// The least cost from the anchor to `cell`, settled now if it was not; `None` when
    /// no drive reaches it.
    pub(crate) fn distance(&mut self, cell: u32, mut edges: impl FnMut(u32, Edges<'_>)) -> Option<f64> {
        let d = self.value(cell);
        // Settled once nothing on the frontier is lower (all costs are ≥ 0). The
        // frontier's least is read once; most cells asked are far inside the radius.
        if d <= self.radius || self.heap.peek().is_none_or(|&Reverse((bits, _))| d <= f64::from_bits(bits)) {
            return d.is_finite().then_some(d);
        }
        loop {
            let d = self.value(cell);
            let Some(&Reverse((bits, _))) = self.heap.peek() else { break };
            if d <= f64::from_bits(bits) {
                break;
            }
            // Settle the next frontier cell.
            self.settle_below(f64::from_bits(bits).next_up(), &mut edges);
        }
        let d = self.value(cell);
        d.is_finite().then_some(d)
    }

    /// Sensing changed `changed` cells, so the drives into and out of them may cost
    /// less (or more) than before. Repairs the distances that fall — a decrease-only
    /// Dijkstra from the changed drives, so the map is that of the world where each
    /// drive costs the lesser of its old and new bounds, still a lower bound — and
    /// returns a bound on how far any settled distance fell: the most the search's
    /// heuristic can have dropped, so the engine keeps its open list (D* Lite's key
    /// modifier). Rises are left: the old distance is still a lower bound, only looser.
    ///
    /// The bound: a distance that falls does so along a new shortest path whose last
    /// changed drive ends at a changed cell or a neighbour of one (a head); after it the
    /// path's drives are unchanged, so the fall is at most the head's. A settled
    /// distance was at most the radius, so a head's old distance counts up to it.
    pub(crate) fn lower(
        &mut self,
        changed: &[u32],
        neighbours: impl Fn(u32, &mut Vec<u32>),
        mut edges: impl FnMut(u32, Edges<'_>),
    ) -> f64 {
        let mut heads = Vec::new();
        for &c in changed {
            neighbours(c, &mut heads);
            heads.push(c);
        }
        heads.sort_unstable();
        heads.dedup();
        let radius = self.radius;
        let before: Vec<f64> = heads.iter().map(|&q| self.value(q).min(radius)).collect();
        // Every drive with an end in a changed cell is relaxed with its new cost: those
        // out of the heads reach the changed cells and their neighbours.
        let mut out = Vec::with_capacity(8);
        for &q in &heads {
            let d = self.value(q);
            if !d.is_finite() {
                continue;
            }
            out.clear();
            edges(q, &mut out);
            for &(to, w) in &out {
                self.relax(to, d + w);
            }
        }
        // Bring everything below the old radius up to date: what was settled is again.
        self.settle_below(radius, &mut edges);
        heads.iter().zip(before).map(|(&q, b)| (b - self.value(q)).max(0.0)).fold(0.0, f64::max)
    }

    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        self.held * PAGE * 8
            + self.pages.capacity() * 8
            + self.heap.capacity() * std::mem::size_of::<Reverse<(u64, u32)>>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4-connected grid with per-cell entry costs (∞: a wall).
    fn grid_edges(cols: u32, rows: u32, cost: &[f64]) -> impl FnMut(u32, Edges<'_>) + '_ {
        move |c: u32, out: Edges<'_>| {
            let (x, y) = ((c % cols) as i64, (c / cols) as i64);
            for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let (nx, ny) = (x + dx, y + dy);
                if nx >= 0 && ny >= 0 && nx < cols as i64 && ny < rows as i64 {
                    let n = (ny * cols as i64 + nx) as u32;
                    if cost[n as usize].is_finite() && cost[c as usize].is_finite() {
                        out.push((n, cost[n as usize]));
                    }
                }
            }
        }
    }

    /// Bellman–Ford over the same grid: the reference.
    fn bellman_ford(cols: u32, rows: u32, cost: &[f64], anchor: u32) -> Vec<f64> {
        let n = (cols * rows) as usize;
        let mut d = vec![f64::INFINITY; n];
        d[anchor as usize] = 0.0;
        let mut edges = grid_edges(cols, rows, cost);
        let mut out = Vec::new();
        for _ in 0..n {
            for c in 0..n as u32 {
                out.clear();
                edges(c, &mut out);
                for &(to, w) in &out {
                    if d[c as usize] + w < d[to as usize] {
                        d[to as usize] = d[c as usize] + w;
                    }
                }
            }
        }
        d
    }

    fn world(seed: u64, cols: u32, rows: u32) -> Vec<f64> {
        // A deterministic mix of costs and walls.
        let mut x = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        (0..cols * rows)
            .map(|_| {
                x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                let r = (x >> 33) as f64 / (1u64 << 31) as f64;
                if r < 0.2 { f64::INFINITY } else { 1.0 + 4.0 * r }
            })
            .collect()
    }

    #[test]
    fn lazy_distances_equal_bellman_ford_in_any_order_of_asking() {
        let (cols, rows) = (13, 11);
        for seed in 0..20 {
            let mut cost = world(seed, cols, rows);
            cost[0] = 1.0;
            let reference = bellman_ford(cols, rows, &cost, 0);
            let mut l = Landmark::new(0);
            // Ask from the far corner back, so most answers come from a resumed search.
            for c in (0..cols * rows).rev() {
                let d = l.distance(c, grid_edges(cols, rows, &cost));
                let r = reference[c as usize];
                assert_eq!(d, r.is_finite().then_some(r), "seed {seed} cell {c}");
            }
        }
    }

    #[test]
    fn repairs_after_cheaper_cells_equal_a_map_of_the_cheaper_world_and_bound_the_fall() {
        let (cols, rows) = (13, 11);
        let neighbours = |c: u32, out: &mut Vec<u32>| {
            let (x, y) = ((c % cols) as i64, (c / cols) as i64);
            for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let (nx, ny) = (x + dx, y + dy);
                if nx >= 0 && ny >= 0 && nx < cols as i64 && ny < rows as i64 {
                    out.push((ny * cols as i64 + nx) as u32);
                }
            }
        };
        let mut falls = 0;
        for seed in 0..20 {
            let mut before = world(seed, cols, rows);
            before[0] = 1.0;
            let mut after = before.clone();
            // Sensing opens walls and makes cells cheaper.
            let changed: Vec<u32> = (0..cols * rows).filter(|&c| c % 17 == 5).take(3).collect();
            for &c in &changed {
                after[c as usize] = 0.5;
            }
            let old = bellman_ford(cols, rows, &before, 0);
            let new = bellman_ford(cols, rows, &after, 0);
            let mut l = Landmark::new(0);
            // Settle half the world, as a search part-way through would have.
            let asked: Vec<u32> = (0..cols * rows).step_by(2).collect();
            for &c in &asked {
                l.distance(c, grid_edges(cols, rows, &before));
            }
            let fall = l.lower(&changed, neighbours, grid_edges(cols, rows, &after));
            let mut largest: f64 = 0.0;
            for &c in &asked {
                if old[c as usize].is_finite() {
                    largest = largest.max(old[c as usize] - new[c as usize]);
                }
            }
            assert!(fall >= largest - 1e-12, "seed {seed}: bound {fall} below the largest fall {largest}");
            if largest > 0.0 {
                falls += 1;
            }
            // Every cell only got cheaper, so the repaired map is the cheaper world's.
            for c in 0..cols * rows {
                let d = l.distance(c, grid_edges(cols, rows, &after));
                let r = new[c as usize];
                assert_eq!(
                    d.map(|d| (d * 1e9).round()),
                    r.is_finite().then(|| (r * 1e9).round()),
                    "seed {seed} cell {c}"
                );
            }
        }
        assert!(falls >= 10, "only {falls} of 20 worlds had a distance fall: the test would not see a missed repair");
    }
}
