//! An exact forward search over plans on a tick: the planner's tick model, and the
//! reference the planner's approximate search is measured against.
//!
//! The rover's timeline is cut by one global grid of ticks (k × `tick_s` after the
//! epoch, the rover's wait step [`crate::ActionModel::wait_step_s`]). It departs on a
//! drive at a tick (or at the instant it is ready), drives at the drive's own
//! continuous duration, and then waits ([`Action::Wait`]: charging where its array sees
//! the Sun, asleep where it does not) until the next tick — the *settle* — before it
//! may drive again; it may also wait any whole number of ticks. Waits compose exactly
//! ([`crate::ActionModel::wait`]), so a settle to a tick is the same as a settle to a
//! finer tick followed by whole finer ticks: every plan at tick q is a plan at q/2 at
//! the same cost, and halving the tick never loses a plan nor makes it dearer. A goal
//! counts as reached at any instant of its window the rover is there: on arrival
//! (before the settle), or at the end of a wait; the last goal ends the plan on
//! arrival.
//!
//! Labels carry the battery exactly (no classes), and one is dropped only for another
//! at the same cell, goal and instant with at least its battery at no more cost (costs
//! equal to a part in 10⁹ counting as equal: sums in another order round apart); labels
//! at different ticks are compared where the earlier one's waits reach the later one's
//! instant. The search is A* on a consistent bound (the cheapest drives to each
//! remaining goal over a 2-D graph of the least each drive can cost at any time), so
//! the first label to reach the last goal is optimal over every plan of this form, and
//! an empty queue proves that none exists.
//!
//! `settle: false` drops the settle: drives chain at their own durations and only
//! waits end on ticks. That search is exact too, but labels between ticks are compared
//! only at the very same instant, and routes of near-equal cost reach a cell at
//! different instants: the labels multiply (docs/tempest.md gives the counts). It is
//! kept to measure what the settle costs and saves.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rustc_hash::FxHashMap;

use crate::action_model::{Action, ActionModel, NEIGHBOURS};
use crate::domain::{DarkCost, Objective, PathLength, Start};
use crate::effect::Effect;
use crate::world::World;

/// A goal of an exact query: its cell and the window in which reaching it counts, s
/// after the epoch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExactGoal {
    /// The goal cell.
    pub cell: u32,
    /// The window's opening, s after the epoch.
    pub open_s: f64,
    /// The window's close, s after the epoch.
    pub close_s: f64,
}

/// One step of an exact plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExactStep {
    /// When the action starts, s after the epoch.
    pub t_s: f64,
    /// Where it starts.
    pub cell: u32,
    /// The action (a wait lasts to the next tick).
    pub action: Action,
    /// Its duration, s: for a drive, with its settle.
    pub duration_s: f64,
    /// The wait to the next tick that follows a drive, s (part of `duration_s`).
    pub settle_s: f64,
    /// The battery above the floor at its end, Wh.
    pub battery_wh: f64,
    /// How many of the query's goals are reached at its end.
    pub goals_reached: usize,
    /// The plan's cost so far at its end.
    pub cost_after: f64,
}

/// What an exact search found and what it cost.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactOutcome {
    /// The optimal plan's cost and steps, or `None`: no plan of this form exists.
    pub plan: Option<(f64, Vec<ExactStep>)>,
    /// Labels taken off the queue and expanded.
    pub expanded: u64,
    /// Labels kept (not dominated when made).
    pub kept: u64,
    /// Labels kept that were not on a tick: the rover driving through a cell.
    pub between_ticks: u64,
    /// The (cell, goal, instant) triples that held a label: `kept` over this is how
    /// many battery–cost trade-offs an instant holds on average.
    pub instants: u64,
    /// Whether the search stopped at its label budget (or its caller's
    /// [`ExactQuery::solve_with`] check) before it could decide.
    pub stopped: bool,
    /// What the labels, their index and the queue held at the end, bytes.
    pub bytes: u64,
}

/// What one label costs in memory: the label, its place in the index and in the queue.
pub const BYTES_PER_LABEL: u64 =
    (std::mem::size_of::<Node>() + std::mem::size_of::<u32>() + std::mem::size_of::<(Ordered, Ordered, u32)>()) as u64;

/// An exact query: the rover at `start` (ready at `start.t_min` with
/// `start.energy_wh`), the goals in order, the battery to hold at the last one, what
/// to minimise and how many labels the search may keep.
#[derive(Debug, Clone)]
pub struct ExactQuery<'a> {
    /// The world.
    pub world: &'a World,
    /// The rover's actions; its wait step is the tick ([`ActionModel::wait_step_s`]).
    pub model: &'a ActionModel,
    /// Where and when the rover is ready, and its battery.
    pub start: Start,
    /// The goals, in order.
    pub goals: Vec<ExactGoal>,
    /// Battery to hold above the floor on reaching the last goal, Wh.
    pub goal_energy_wh: f64,
    /// Energy (L + B) or Time.
    pub objective: Objective,
    /// The most labels the search may keep before it stops undecided.
    pub max_labels: u64,
    /// Whether every drive is followed by a wait to the next tick (see the module's
    /// documentation).
    pub settle: bool,
}

#[derive(Debug, Clone, Copy)]
struct Node {
    cell: u32,
    goal: u16,
    t: f64,
    e: f64,
    cost: f64,
    parent: u32,
    action: Option<Action>,
    dead: bool,
}

/// Instants compared to a microsecond: sums of drive durations in another order round
/// differently.
fn instant_key(t: f64) -> i64 {
    (t * 1e6).round() as i64
}

impl ExactQuery<'_> {
    /// Runs the search. `None` in the outcome's plan with `stopped` false is a proof
    /// that no plan whose waits end on ticks reaches the goals.
    pub fn solve(&self) -> ExactOutcome {
        self.solve_with(&mut |_| true)
    }

    /// [`ExactQuery::solve`], asking `go_on` before every expansion with the labels kept
    /// so far whether to go on (a caller's work and memory budget): `false` stops the
    /// search undecided.
    pub fn solve_with(&self, go_on: &mut dyn FnMut(u64) -> bool) -> ExactOutcome {
        let mut out = self.search(go_on);
        out.bytes = out.kept * BYTES_PER_LABEL;
        out
    }

    fn search(&self, go_on: &mut dyn FnMut(u64) -> bool) -> ExactOutcome {
        let tick = self.model.wait_step_s().unwrap_or_else(|| self.model.stay_duration_s(Action::Hibernate));
        let e_max = self.model.gain_bounds(self.world).0;
        let bound = self.bound(e_max);
        let h = |cell: u32, goal: u16, t: f64| bound.at(self.world, cell, goal, t);
        let mut nodes: Vec<Node> = Vec::new();
        let mut at: FxHashMap<(u32, u16, i64), Vec<u32>> = FxHashMap::default();
        let mut open = BinaryHeap::new();
        let mut out =
            ExactOutcome { plan: None, expanded: 0, kept: 0, between_ticks: 0, instants: 0, stopped: false, bytes: 0 };
        let start = Node {
            cell: self.start.cell,
            goal: self.reached(0, self.start.cell, self.start.t_min, self.start.energy_wh),
            t: self.start.t_min,
            e: self.start.energy_wh,
            cost: 0.0,
            parent: u32::MAX,
            action: None,
            dead: false,
        };
        self.keep(start, &mut nodes, &mut at, &mut out, tick);
        open.push(Reverse((ordered(h(start.cell, start.goal, start.t)), Reverse(ordered(0.0)), 0u32)));
        while let Some(Reverse((_, _, i))) = open.pop() {
            let node = nodes[i as usize];
            if node.dead {
                continue;
            }
            if node.goal as usize == self.goals.len() {
                out.plan = Some((node.cost, self.steps(&nodes, i)));
                return out;
            }
            if out.kept >= self.max_labels || !go_on(out.kept) {
                out.stopped = true;
                return out;
            }
            out.expanded += 1;
            for next in self.successors(node, i, tick, e_max) {
                if let Some(j) = self.keep(next, &mut nodes, &mut at, &mut out, tick) {
                    open.push(Reverse((
                        ordered(next.cost + h(next.cell, next.goal, next.t)),
                        Reverse(ordered(next.cost)),
                        j,
                    )));
                }
            }
        }
        out
    }

    /// The search's bound (see [`Bound`]).
    fn bound(&self, e_max: f64) -> Bound {
        let drives: Vec<Vec<f64>> = self.goals.iter().map(|g| self.reverse_bound(g.cell, e_max)).collect();
        let mut tails = vec![0.0; self.goals.len() + 1];
        for i in (0..self.goals.len().saturating_sub(1)).rev() {
            tails[i] = tails[i + 1] + drives[i + 1][self.goals[i].cell as usize];
        }
        let speed = self.model.top_speed_m_s();
        let mut time_tails = vec![0.0; self.goals.len() + 1];
        for i in (0..self.goals.len().saturating_sub(1)).rev() {
            time_tails[i] = time_tails[i + 1] + self.world.octile_m(self.goals[i].cell, self.goals[i + 1].cell) / speed;
        }
        let units = (0..8u8)
            .map(|k| PathLength::Distance.units(Action::Drive(k), self.world.dem().dx(), self.world.dem().dy()))
            .fold(f64::INFINITY, f64::min);
        let source_w = self.model.drive_source_bound_w(self.world);
        Bound {
            drives,
            tails,
            time_tails,
            goals: self.goals.iter().map(|g| g.cell).collect(),
            speed,
            dark: DarkCost::new(self.world, self.model, self.objective, e_max, units, source_w),
        }
    }

    /// The goal index after arriving at `cell` at `t` with `e`, having reached
    /// `goal` goals: the next goal is reached at any instant of its window (the last
    /// with the battery it must hold).
    fn reached(&self, goal: u16, cell: u32, t: f64, e: f64) -> u16 {
        match self.goals.get(goal as usize) {
            Some(g) if g.cell == cell && t >= g.open_s - 1e-9 && t <= g.close_s + 1e-9 => {
                let last = goal as usize + 1 == self.goals.len();
                if !last || e >= self.goal_energy_wh - 1e-9 { goal + 1 } else { goal }
            }
            _ => goal,
        }
    }

    /// The labels one step from `node` (index `i`): each drive (with its settle, unless
    /// it reaches the last goal), and a wait to the next tick.
    fn successors(&self, node: Node, i: u32, tick: f64, e_max: f64) -> Vec<Node> {
        let capacity = self.model.capacity_wh();
        let next_tick = |t: f64| ((t / tick + 1e-9).floor() + 1.0) * tick;
        // The label after `effect` from `from`, if the battery holds inside it.
        let after = |from: &Node, action: Action, to: u32, effect: &Effect| -> Option<Node> {
            if effect.lowest(from.e, capacity) < -1e-9 {
                return None;
            }
            let (t, e) = (from.t + effect.duration_s, effect.after(from.e, capacity));
            Some(Node {
                cell: to,
                goal: self.reached(from.goal, to, t, e),
                t,
                e,
                cost: from.cost + self.step_cost(action, effect, e_max),
                parent: i,
                action: Some(action),
                dead: false,
            })
        };
        let mut out = Vec::with_capacity(9);
        for k in 0..8u8 {
            let Ok((to, drive)) = self.model.drive(self.world, node.cell, k, node.t) else { continue };
            let Some(arrived) = after(&node, Action::Drive(k), to, &drive) else { continue };
            let on_tick = ((arrived.t / tick) - (arrived.t / tick).round()).abs() < 1e-9;
            if !self.settle || on_tick || arrived.goal as usize == self.goals.len() {
                out.push(arrived);
                continue;
            }
            // The settle: the drive and the wait to the next tick are one step of the
            // plan (the drive's label is not kept: no plan departs from it).
            let Ok(wait) = self.model.wait(self.world, to, arrived.t, next_tick(arrived.t) - arrived.t) else {
                continue;
            };
            if let Some(mut settled) = after(&arrived, Action::Wait, to, &wait) {
                settled.action = Some(Action::Drive(k));
                out.push(settled);
            }
        }
        if let Ok(wait) = self.model.wait(self.world, node.cell, node.t, next_tick(node.t) - node.t)
            && let Some(waited) = after(&node, Action::Wait, node.cell, &wait)
        {
            out.push(waited);
        }
        out
    }

    /// Keeps `node` unless a label at its cell, goal and instant has at least its
    /// battery at no more cost; drops the labels it beats. Its index, if kept. Both
    /// are binary searches on the instant's staircase of labels.
    fn keep(
        &self,
        node: Node,
        nodes: &mut Vec<Node>,
        at: &mut FxHashMap<(u32, u16, i64), Vec<u32>>,
        out: &mut ExactOutcome,
        tick: f64,
    ) -> Option<u32> {
        let list = at.entry((node.cell, node.goal, instant_key(node.t))).or_insert_with(|| {
            out.instants += 1;
            Vec::new()
        });
        // The list is a staircase: sorted by battery, most first, the cost falling along
        // it (of two labels neither beats, the one with more battery costs more; their
        // batteries differ by more than the slack). The labels with at least this
        // battery are a prefix, the cheapest of them its last.
        // Costs are sums in different orders: equal to a part in 10⁹ is equal (else the
        // rounding of equal costs would keep both labels as a trade-off).
        let slack = 1e-9 * node.cost.abs().max(1.0);
        let p = list.partition_point(|&j| nodes[j as usize].e >= node.e - 1e-9);
        if p > 0 && nodes[list[p - 1] as usize].cost <= node.cost + slack {
            return None;
        }
        // Those with at most this battery start at q; the ones it beats (no cheaper) lead
        // that run.
        let q = list.partition_point(|&j| nodes[j as usize].e > node.e + 1e-9);
        let mut r = q;
        while r < list.len() && nodes[list[r] as usize].cost >= node.cost - slack {
            nodes[list[r] as usize].dead = true;
            r += 1;
        }
        let j = nodes.len() as u32;
        list.splice(q..r, [j]);
        nodes.push(node);
        out.kept += 1;
        let phase = node.t / tick;
        if (phase - phase.round()).abs() > 1e-9 {
            out.between_ticks += 1;
        }
        Some(j)
    }

    fn step_cost(&self, action: Action, effect: &Effect, e_max: f64) -> f64 {
        match self.objective {
            Objective::Time | Objective::Margin { .. } => effect.duration_s,
            Objective::EnergyUsed => effect.load_wh,
            Objective::Energy => {
                let units = match action {
                    Action::Drive(_) => {
                        PathLength::Distance.units(action, self.world.dem().dx(), self.world.dem().dy())
                    }
                    // A wait's share of L is its length over a Hibernate's.
                    _ => effect.duration_s / self.model.config().hibernate_s,
                };
                (effect.energy_wh + e_max * units).max(0.0)
            }
        }
    }

    /// The least cost of the drives from every cell to `goal`, at any time: a
    /// Dijkstra backward over each drive's floor (the least its energy can be under
    /// any Sun, or its duration).
    fn reverse_bound(&self, goal: u32, e_max: f64) -> Vec<f64> {
        let n = self.world.cols() * self.world.rows();
        let mut dist = vec![f64::INFINITY; n];
        let source_w = self.model.drive_source_bound_w(self.world);
        let mut heap = BinaryHeap::new();
        dist[goal as usize] = 0.0;
        heap.push(Reverse((ordered(0.0), goal)));
        while let Some(Reverse((d, to))) = heap.pop() {
            if d.0 > dist[to as usize] {
                continue;
            }
            let (c, r) = self.world.col_row(to);
            for (k, (dc, dr)) in NEIGHBOURS.iter().enumerate() {
                // The drive into `to` from the neighbour behind direction k.
                let (pc, pr) = (c as i64 - i64::from(*dc), r as i64 - i64::from(*dr));
                if pc < 0 || pr < 0 || pc as usize >= self.world.cols() || pr as usize >= self.world.rows() {
                    continue;
                }
                let from = self.world.cell(pc as usize, pr as usize);
                let Ok(g) = self.model.drive_geometry(self.world, from, k as u8) else { continue };
                let step = match self.objective {
                    Objective::Time | Objective::Margin { .. } => g.duration_s,
                    Objective::EnergyUsed => self.model.drive_load_floor_wh(&g),
                    Objective::Energy => {
                        let units = PathLength::Distance.units(
                            Action::Drive(k as u8),
                            self.world.dem().dx(),
                            self.world.dem().dy(),
                        );
                        (self.model.drive_energy_floor_wh(&g, source_w) + e_max * units).max(0.0)
                    }
                };
                let nd = d.0 + step;
                if nd < dist[from as usize] {
                    dist[from as usize] = nd;
                    heap.push(Reverse((ordered(nd), from)));
                }
            }
        }
        dist
    }

    fn steps(&self, nodes: &[Node], mut i: u32) -> Vec<ExactStep> {
        let mut steps = Vec::new();
        while nodes[i as usize].parent != u32::MAX {
            let node = nodes[i as usize];
            let parent = nodes[node.parent as usize];
            let action = node.action.expect("a label with a parent has an action");
            let duration_s = node.t - parent.t;
            let drive_s = match action {
                Action::Drive(k) => {
                    self.model.drive_geometry(self.world, parent.cell, k).map_or(duration_s, |g| g.duration_s)
                }
                _ => duration_s,
            };
            steps.push(ExactStep {
                t_s: parent.t,
                cell: parent.cell,
                action,
                duration_s,
                settle_s: (duration_s - drive_s).max(0.0),
                battery_wh: node.e,
                goals_reached: node.goal as usize,
                cost_after: node.cost,
            });
            i = node.parent;
        }
        steps.reverse();
        steps
    }
}

/// The A* bound from a label to the last goal: the cheapest drives through the
/// remaining goals over each drive's floor (2-D, any time), plus the deep night (or any
/// action's least cost per second) between the label's instant and the earliest it can
/// arrive — the approximate planner's own time bounds (`domain::DarkCost`).
struct Bound {
    /// Per goal, the drives' bound from every cell to it.
    drives: Vec<Vec<f64>>,
    /// Per goal, the drives' bound from it through the later goals.
    tails: Vec<f64>,
    /// Per goal, the least time from it through the later goals, s.
    time_tails: Vec<f64>,
    goals: Vec<u32>,
    speed: f64,
    dark: Option<DarkCost>,
}

impl Bound {
    fn at(&self, world: &World, cell: u32, goal: u16, t: f64) -> f64 {
        let g = goal as usize;
        if g >= self.goals.len() {
            return 0.0;
        }
        let drives = self.drives[g][cell as usize] + self.tails[g];
        // Any plan from here spends at least until `t + least` on its way: the deep
        // night in that span with stays, and all of it at the least cost per second.
        let least = world.octile_m(cell, self.goals[g]) / self.speed + self.time_tails[g];
        match &self.dark {
            Some(d) => {
                (drives + (d.at(t + least) - d.at(t)).max(0.0)).max((d.any_at(t + least) - d.any_at(t)).max(0.0))
            }
            None => drives,
        }
    }
}

/// A total order on costs (never NaN).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Ordered(f64);

impl Eq for Ordered {}

impl PartialOrd for Ordered {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Ordered {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

fn ordered(x: f64) -> Ordered {
    Ordered(x)
}
