//! What a finished search teaches the next search of the same problem: a lower bound on
//! the cost still to pay from every state it labelled.
//!
//! A search that found the optimum C* from its start reached each label at cost g by a
//! real beginning of a plan; every plan through that label costs at least C*, so from the
//! label's state at least C* − g remains. What remains from a state (cell, goals
//! reached, instant, battery) does not depend on where the rover started, and more
//! battery never costs more: a later search from any start may take, at a state with
//! battery e, the largest C* − g over the labels of that cell, goals and instant that
//! held at least e. This is Adaptive A* (Koenig & Likhachev, "Adaptive A*", AAMAS 2005)
//! over labels with a resource. The later search stays exact because the learned values
//! only raise an admissible bound.
//!
//! The values are true of the world the search saw. Sensing changes cells, and only a
//! plan that reaches a changed cell can have become cheaper (every action reads the data
//! of the cells it starts and ends in, nothing else): each learned value is clamped by
//! a lower bound on the plans that reach one of the cells changed since
//! ([`super::bound::Through`]). Never used under Margin, whose cost is not a sum.

use super::bound::{Bound, Through};
use super::{ExactGoal, ExactQuery, Instants, Node};
use crate::domain::Objective;

/// What a search's problem was, for telling whether a later query asks the same (its
/// goals the same or the later part of them).
#[derive(Debug, Clone, PartialEq)]
struct Problem {
    goals: Vec<ExactGoal>,
    goal_energy_wh: f64,
    objective: Objective,
    tick: f64,
    e_max: f64,
    settle: bool,
}

/// The cost-to-go a finished search learned, and the cells changed since
/// ([`Learned::sensed`]).
pub struct Learned {
    optimum: f64,
    problem: Problem,
    /// The labels on ticks that no other beat, as (cell, goals reached, tick) packed by
    /// [`pack`], cost from the search's start and battery above the floor;
    /// sorted by key, each key's labels by battery, most first, the cost falling along
    /// them (as the search's staircases).
    entries: Vec<(u64, f64, f64)>,
    labels: u64,
    changed: Vec<u32>,
}

/// A (cell, goals reached, tick index) key, if it fits: the tick index in 24 bits
/// (16.7 million ticks), the goals in 8.
fn pack(cell: u32, goal: u16, tick_index: f64) -> Option<u64> {
    (goal < 256 && (0.0..f64::from(1u32 << 24)).contains(&tick_index))
        .then(|| (u64::from(cell) << 32) | (u64::from(goal) << 24) | tick_index as u64)
}

/// The tick index of `t`, if it lies on a tick (to a microsecond, as the search
/// compares instants).
fn on_tick(t: f64, tick: f64) -> Option<f64> {
    let j = (t / tick).round();
    ((j * tick - t).abs() < 1e-6).then_some(j)
}

impl std::fmt::Debug for Learned {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Learned")
            .field("optimum", &self.optimum)
            .field("labels", &self.labels)
            .field("changed", &self.changed.len())
            .finish()
    }
}

impl Learned {
    /// The labels a lesson holds at most (24 bytes each): a larger search's lesson
    /// would take more memory than it saves work (lunar-south-pole-10m's 17.5 million
    /// labels, 420 MB, for a plan that is never re-planned), and none is drawn.
    pub const MOST_LABELS: usize = 4_000_000;

    /// What the search with these staircases and this optimum learned, unless it holds
    /// more than [`Learned::MOST_LABELS`].
    pub(super) fn new(query: &ExactQuery<'_>, tick: f64, e_max: f64, optimum: f64, at: Instants) -> Option<Learned> {
        let held: usize = at.shards.iter().flat_map(|s| s.values()).map(|l| l.len()).sum();
        if held > Self::MOST_LABELS {
            return None;
        }
        let mut entries = Vec::with_capacity(held);
        for shard in at.shards {
            for ((cell, goal, t_us), list) in shard {
                let Some(key) = on_tick(t_us as f64 * 1e-6, tick).and_then(|j| pack(cell, goal, j)) else { continue };
                entries.extend(list.iter().map(|stair| (key, stair.cost, stair.e)));
            }
        }
        // Stable: each key's labels keep their staircase's order.
        entries.sort_by_key(|entry| entry.0);
        let labels = entries.len() as u64;
        Some(Learned { optimum, problem: Problem::of(query, tick, e_max), entries, labels, changed: Vec::new() })
    }

    /// The labels it learned from.
    pub fn labels(&self) -> u64 {
        self.labels
    }

    /// Bytes it holds.
    pub fn bytes(&self) -> u64 {
        (self.entries.capacity() * size_of::<(u64, f64, f64)>() + self.changed.capacity() * 4) as u64
    }

    /// The world changed in `cells` since the search (kept in the order of their last
    /// change, the latest last).
    pub fn sensed(&mut self, cells: &[u32]) {
        for &c in cells {
            self.changed.retain(|&k| k != c);
            self.changed.push(c);
        }
    }

    /// How many cells changed since the search.
    pub fn changed(&self) -> usize {
        self.changed.len()
    }

    /// The least cost still to pay from a state of the search's own goal numbering, if
    /// the search labelled its cell, goals and instant with at least its battery.
    fn cost_to_go(&self, cell: u32, goal: u16, t: f64, e: f64) -> Option<f64> {
        let key = pack(cell, goal, on_tick(t, self.problem.tick)?)?;
        let first = self.entries.partition_point(|entry| entry.0 < key);
        // The key's labels, by battery, most first, the cost falling along them: the
        // cheapest with at least `e` ends the run of those (batteries within a
        // nanowatt-hour are one, as the search's own dominance takes them).
        let cheapest = self.entries[first..].iter().take_while(|entry| entry.0 == key && entry.2 >= e - 1e-9).last()?;
        Some(self.optimum - cheapest.1)
    }
}

impl Problem {
    fn of(query: &ExactQuery<'_>, tick: f64, e_max: f64) -> Problem {
        Problem {
            goals: query.goals.clone(),
            goal_energy_wh: query.goal_energy_wh,
            objective: query.objective,
            tick,
            e_max,
            settle: query.settle,
        }
    }

    /// How many of this problem's goals `later` has dropped, if it asks the rest of it.
    fn dropped(&self, later: &Problem) -> Option<u16> {
        let dropped = self.goals.len().checked_sub(later.goals.len())?;
        let same = self.goals[dropped..] == later.goals[..]
            && self.goal_energy_wh == later.goal_energy_wh
            && self.objective == later.objective
            && self.tick == later.tick
            && self.e_max == later.e_max
            && self.settle == later.settle;
        same.then_some(dropped as u16)
    }
}

/// The learned bounds a search is guided by.
pub(super) struct Guides<'l> {
    layers: Vec<Layer<'l>>,
}

struct Layer<'l> {
    learned: &'l Learned,
    /// The goals the learning search had that the query has reached.
    dropped: u16,
    through: Through,
}

impl<'l> Guides<'l> {
    /// The layers of `learned` that asked the query's problem (or its later part).
    pub(super) fn new(learned: &'l [Learned], query: &ExactQuery<'_>, tick: f64, e_max: f64) -> Guides<'l> {
        let problem = Problem::of(query, tick, e_max);
        let additive = !matches!(query.objective, Objective::Margin { .. });
        let layers = learned
            .iter()
            .filter(|_| additive)
            .filter_map(|l| {
                let dropped = l.problem.dropped(&problem)?;
                Some(Layer { learned: l, dropped, through: Through::new(&l.changed) })
            })
            .collect();
        Guides { layers }
    }

    /// Whether any learned bound applies.
    pub(super) fn any(&self) -> bool {
        !self.layers.is_empty()
    }

    /// The bound from `node`: `floor` (the search's own) raised by what the layers
    /// learned, each clamped where cells changed since.
    pub(super) fn at(&mut self, bound: &mut Bound<'_>, node: &Node, floor: f64) -> f64 {
        let mut best = floor;
        for layer in &mut self.layers {
            let Some(h) = layer.learned.cost_to_go(node.cell, node.goal + layer.dropped, node.t, node.e) else {
                continue;
            };
            if h <= best {
                continue;
            }
            let clamp = if layer.learned.changed.is_empty() {
                f64::INFINITY
            } else {
                bound.through(&mut layer.through, node.cell, node.goal, node.t, node.e)
            };
            best = best.max(h.min(clamp));
        }
        best
    }

    pub(super) fn bytes(&self) -> usize {
        self.layers.iter().map(|l| l.through.bytes()).sum()
    }
}
