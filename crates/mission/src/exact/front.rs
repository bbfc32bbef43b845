//! The exact search's Pareto front: every plan on the tick that no other beats at once
//! in arrival time, energy used (the loads' draw, [`crate::Effect::load_wh`]) and margin
//! (the lowest battery above the floor along the plan, inside actions too).
//!
//! Labels are expanded in order of their instant, so every label of an instant exists
//! before any is expanded (drives and waits take time). At a (cell, goal, instant) a
//! label is dropped for another with at least its battery, at most its energy used and
//! at least its lowest battery: whatever the rover does next from the first it can do
//! from the other, arriving as early, drawing no more and keeping as much. A label
//! reaching the last goal is a candidate and is not expanded; a label whose earliest
//! arrival, least energy to come and lowest battery so far are all beaten by a
//! candidate already found is dropped too — every plan from it would be dominated. The
//! candidates no other dominates are the front.

use std::cmp::Reverse;

use dary_heap::QuaternaryHeap;
use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use super::bound::Bound;
use super::{Departures, ExactQuery, ExactStep, Instant, Moves, NONE, Node, Ordered, instant_key, ordered};
use crate::action_model::Action;
use crate::domain::Objective;

/// One plan of the front.
#[derive(Debug, Clone, PartialEq)]
pub struct FrontPoint {
    /// When it reaches the last goal, s after the epoch.
    pub arrival_s: f64,
    /// What its actions' loads draw, Wh.
    pub energy_used_wh: f64,
    /// Its lowest battery above the floor, inside actions too, Wh.
    pub lowest_wh: f64,
    /// The plan.
    pub steps: Vec<ExactStep>,
}

/// The front and what finding it took.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactFront {
    /// The non-dominated plans, by arrival, then energy used.
    pub points: Vec<FrontPoint>,
    /// Labels expanded.
    pub expanded: u64,
    /// Labels kept.
    pub kept: u64,
    /// Whether the caller's check stopped the search before it could finish (the front
    /// is then incomplete).
    pub stopped: bool,
    /// The most the labels, their index and queue held, bytes.
    pub bytes: u64,
}

/// A label on its instant's list: battery, energy used, lowest battery, index.
type Entry = (f64, f64, f64, u32);

/// A candidate at the last goal: arrival, energy used, lowest battery, index.
type Found = (f64, f64, f64, u32);

const EPS: f64 = 1e-9;

/// Whether (t, used, low) is at least as good as (t2, used2, low2) in each.
fn no_worse(a: (f64, f64, f64), b: (f64, f64, f64)) -> bool {
    a.0 <= b.0 + EPS && a.1 <= b.1 + EPS * b.1.abs().max(1.0) && a.2 >= b.2 - EPS
}

impl ExactQuery<'_> {
    /// The Pareto front of the plans on the tick in (arrival, energy used, lowest
    /// battery); see the module's notes. Its objective is ignored.
    pub fn front(&self) -> ExactFront {
        self.front_with(&mut |_| true)
    }

    /// [`ExactQuery::front`], asking `go_on` before every expansion with the bytes the
    /// search holds whether to go on.
    pub fn front_with(&self, go_on: &mut dyn FnMut(u64) -> bool) -> ExactFront {
        let query = ExactQuery { objective: Objective::EnergyUsed, ..self.clone() };
        let tick = query.model.wait_step_s().unwrap_or_else(|| query.model.stay_duration_s(Action::Hibernate));
        let e_max = query.model.gain_bounds(query.world).0;
        let mut bound = Bound::new(&query, e_max, tick);
        let departures = Departures::new(query.world, query.model, tick);
        let mut moves = Moves::new();
        let last = query.goals.len() as u16;
        let mut nodes: Vec<Node> = Vec::new();
        let mut lows: Vec<f64> = Vec::new();
        let mut at: FxHashMap<Instant, SmallVec<[Entry; 2]>> = FxHashMap::default();
        let mut found: Vec<Found> = Vec::new();
        let mut open: QuaternaryHeap<Reverse<(Ordered, u32)>> = QuaternaryHeap::new();
        let mut out = ExactFront { points: Vec::new(), expanded: 0, kept: 0, stopped: false, bytes: 0 };
        let start = Node {
            cell: query.start.cell,
            goal: query.reached(0, query.start.cell, query.start.t_min, query.start.energy_wh),
            t: query.start.t_min,
            e: query.start.energy_wh,
            cost: 0.0,
            parent: NONE,
            action: None,
            dead: false,
        };
        nodes.push(start);
        lows.push(start.e);
        open.push(Reverse((ordered(start.t), 0)));
        while let Some(Reverse((_, i))) = open.pop() {
            let node = nodes[i as usize];
            if node.dead {
                continue;
            }
            let low = lows[i as usize];
            if node.goal == last {
                if !found.iter().any(|f| no_worse((f.0, f.1, f.2), (node.t, node.cost, low))) {
                    found.push((node.t, node.cost, low, i));
                }
                continue;
            }
            let held = (nodes.len() * (size_of::<Node>() + size_of::<f64>())
                + at.len() * size_of::<(Instant, SmallVec<[Entry; 2]>)>()
                + open.len() * size_of::<(Ordered, u32)>()
                + moves.bytes()
                + bound.bytes()) as u64;
            out.bytes = out.bytes.max(held);
            if out.kept >= query.max_labels || !go_on(held) {
                out.stopped = true;
                break;
            }
            out.expanded += 1;
            // No jumping waits: the front weighs each plan's lowest battery too, which
            // a wait moved to another cell changes.
            for (next, step_low) in query.successors(node, i, (tick, e_max), &departures, (&mut moves, None)) {
                let low = low.min(step_low);
                let rest = bound.at(next.cell, next.goal, next.t, next.e);
                if !rest.is_finite() {
                    continue;
                }
                let earliest = if next.goal == last {
                    next.t
                } else {
                    bound.arrival(next.cell, next.goal as usize, next.t, next.e)
                };
                if found.iter().any(|f| no_worse((f.0, f.1, f.2), (earliest, next.cost + rest, low))) {
                    continue;
                }
                let list = at.entry((next.cell, next.goal, instant_key(next.t))).or_default();
                let j = nodes.len() as u32;
                if admit(list, &mut nodes, (next.e, next.cost, low, j)) {
                    nodes.push(next);
                    lows.push(low);
                    out.kept += 1;
                    open.push(Reverse((ordered(next.t), j)));
                }
            }
        }
        out.points = front_of(&found, |i| query.steps(&nodes, i));
        out
    }
}

/// Adds `entry` to its instant's `list` unless a label there has at least its battery,
/// at most its energy used and at least its lowest battery; marks dead the labels it
/// beats so. Whether it was added.
fn admit(list: &mut SmallVec<[Entry; 2]>, nodes: &mut [Node], entry: Entry) -> bool {
    let (e, used, low, _) = entry;
    if list.iter().any(|s| s.0 >= e - EPS && no_worse((0.0, s.1, s.2), (0.0, used, low))) {
        return false;
    }
    list.retain(|s| {
        let beaten = e >= s.0 - EPS && no_worse((0.0, used, low), (0.0, s.1, s.2));
        if beaten {
            nodes[s.3 as usize].dead = true;
        }
        !beaten
    });
    list.push(entry);
    true
}

/// The candidates no other beats, by arrival, then energy used, each with its plan
/// (`steps` of a label's index). Candidates are found in order of arrival; one found
/// later at the same instant may beat an earlier one.
fn front_of(found: &[Found], steps: impl Fn(u32) -> Vec<ExactStep>) -> Vec<FrontPoint> {
    let points: Vec<(f64, f64, f64)> = found.iter().map(|f| (f.0, f.1, f.2)).collect();
    let mut out: Vec<FrontPoint> = (found.iter().enumerate())
        .filter(|&(k, _)| {
            !points.iter().enumerate().any(|(m, &p)| m != k && no_worse(p, points[k]) && !no_worse(points[k], p))
        })
        .map(|(_, f)| FrontPoint { arrival_s: f.0, energy_used_wh: f.1, lowest_wh: f.2, steps: steps(f.3) })
        .collect();
    out.sort_by(|a, b| a.arrival_s.total_cmp(&b.arrival_s).then(a.energy_used_wh.total_cmp(&b.energy_used_wh)));
    out
}
