//! Brute-force references: forward Dijkstra over a fully enumerated state graph.

use ordered_float::OrderedFloat;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::hash::Hash;

/// Least cost from `start` to any state accepted by `is_goal` (plus that goal's
/// terminal cost), exploring `next(state)` → (state, cost) exhaustively.
pub(crate) fn dijkstra<S: Copy + Eq + Hash + Ord>(
    start: S,
    mut next: impl FnMut(S) -> Vec<(S, f64)>,
    mut goal_cost: impl FnMut(S) -> Option<f64>,
) -> Option<f64> {
    let mut dist: HashMap<S, f64> = HashMap::new();
    let mut heap = BinaryHeap::new();
    dist.insert(start, 0.0);
    heap.push(Reverse((OrderedFloat(0.0), start)));
    let mut best: Option<f64> = None;
    while let Some(Reverse((OrderedFloat(d), s))) = heap.pop() {
        if d > dist[&s] {
            continue;
        }
        if best.is_some_and(|b| d >= b) {
            break;
        }
        if let Some(c) = goal_cost(s) {
            best = Some(best.map_or(d + c, |b: f64| b.min(d + c)));
        }
        for (t, c) in next(s) {
            let nd = d + c;
            if dist.get(&t).is_none_or(|&old| nd < old) {
                dist.insert(t, nd);
                heap.push(Reverse((OrderedFloat(nd), t)));
            }
        }
    }
    best
}
