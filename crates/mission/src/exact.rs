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
//! the same cost, and halving the tick never loses a plan nor makes it dearer. Where no
//! drive may depart (a night under the daylight rule, a communication session) a wait
//! runs on to the first tick one may: the ticks between hold nothing but more waiting,
//! so a night is one wait, not one label per tick per battery trade-off. A goal
//! counts as reached at any instant of its window the rover is there: on arrival
//! (before the settle), or at the end of a wait; the last goal ends the plan on
//! arrival.
//!
//! Labels carry the battery exactly (no classes), and one is dropped only for another
//! at the same cell, goal and instant with at least its battery at no more cost (costs
//! equal to a part in 10⁹ counting as equal: sums in another order round apart); labels
//! at different ticks are compared where the earlier one's waits reach the later one's
//! instant. The search is A* on an admissible bound (the cheapest drives to each
//! remaining goal over a 2-D graph of the least each drive can cost at any time, and
//! under L + B what the time before the earliest the rover can arrive costs above those
//! floors: a Sun short of the drives' credit, the stays), so the first
//! label to reach the last goal is optimal over every plan of this form, and an empty
//! queue proves that none exists. The bound's 2-D searches run backward from each goal
//! only as far as the cells the search asks about, so a query on a map of millions of
//! cells weighs the drives around its route, not the map's.
//!
//! Under Time a wait where driving on first is never worse jumps several ticks
//! (`forward`): the flood of labels waiting tick by tick behind a bound that cannot see
//! the waits ahead shrinks, and the optimum is kept. Under L + B, EnergyUsed and Time a
//! wait stands for its ticks (`waiting`): a drive after a wait is made only where
//! driving a tick earlier and waiting where it lands does not beat it, and a wait the
//! search would take soon runs on at once, its labels kept where later arrivals meet
//! them (under Time only while its estimate ties the queue's least).
//!
//! `settle: false` drops the settle: drives chain at their own durations and only
//! waits end on ticks. That search is exact too, but labels between ticks are compared
//! only at the very same instant, and routes of near-equal cost reach a cell at
//! different instants: the labels multiply (docs/tempest.md gives the counts). It is
//! kept to measure what the settle costs and saves.

use std::cmp::Reverse;

use dary_heap::QuaternaryHeap;
use rustc_hash::FxHashMap;
use smallvec::SmallVec;

mod bound;
mod forward;
mod front;
mod learned;
mod waiting;

use bound::Bound;
use forward::{Forward, Refills};
pub use front::{ExactFront, FrontPoint};
use learned::Guides;
pub use learned::Learned;
use waiting::{Take, WaitCounts, Waits};

use crate::action_model::{Action, ActionModel};
use crate::domain::{Objective, PathLength, Start};
use crate::effect::Effect;
use crate::world::World;

/// The exact search's A* bound: a lower bound on what any plan from a label costs to
/// its end — the cheapest drives through the remaining goals at their floors, and
/// under L + B what the time until the earliest arrival costs above them (the deep
/// night, a Sun short of its best while driving, the waits). The search's optimum
/// rests on it never exceeding a plan's cost.
pub struct ExactBound<'a>(Bound<'a>);

impl std::fmt::Debug for ExactBound<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ExactBound").finish_non_exhaustive()
    }
}

impl ExactBound<'_> {
    /// The least cost from the rover at `cell` at `t_s` (s after the epoch) with
    /// `battery_wh` above the floor and `goals_reached` goals reached to the end of any
    /// plan (infinite: none can reach the goals).
    pub fn at(&mut self, cell: u32, goals_reached: usize, t_s: f64, battery_wh: f64) -> f64 {
        self.0.at(cell, goals_reached as u16, t_s, battery_wh)
    }

    /// The least cost of any plan from the rover at `cell` at `t_s` with `battery_wh`
    /// above the floor and `goals_reached` goals reached that drives into one of
    /// `cells` on its way (infinite: none can): the bound a re-plan's learned values
    /// are clamped by where sensing changed those cells.
    pub fn through(&mut self, cells: &[u32], cell: u32, goals_reached: usize, t_s: f64, battery_wh: f64) -> f64 {
        let mut through = bound::Through::new(cells);
        self.0.through(&mut through, cell, goals_reached as u16, t_s, battery_wh)
    }
}

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
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ExactOutcome {
    /// The optimal plan's cost and steps, or `None`: no plan of this form exists.
    pub plan: Option<(f64, Vec<ExactStep>)>,
    /// Labels expanded: taken off the queue, or made inside a wait with their
    /// departures (`waited`).
    pub expanded: u64,
    /// Labels kept (not dominated when made).
    pub kept: u64,
    /// Labels kept that were not on a tick: the rover driving through a cell.
    pub between_ticks: u64,
    /// The (cell, goal, instant) triples that held a label: `kept` over this is how
    /// many battery–cost trade-offs an instant holds on average.
    pub instants: u64,
    /// Waits that jumped several ticks at once under Time, where driving on first is
    /// never worse (see the module's documentation).
    pub jumps: u64,
    /// Of the labels expanded, the ones made inside a wait that stands for its ticks
    /// (kept, never queued: their departures are made with them; see `waiting`).
    pub waited: u64,
    /// Departures from inside such waits not made: driving first and waiting after
    /// beats them.
    pub covered: u64,
    /// Whether the search stopped at its label budget (or its caller's
    /// [`ExactQuery::solve_with`] check) before it could decide.
    pub stopped: bool,
    /// The most the labels, their index, the queue, the memo of drives and the
    /// bound's backward searches held,
    /// bytes.
    pub bytes: u64,
}

impl ExactOutcome {
    fn counts(&mut self, jumps: u64, waits: WaitCounts) {
        (self.jumps, self.waited, self.covered) = (jumps, waits.waited, waits.covered);
        self.expanded += waits.waited;
    }
}

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

/// A drive from a cell at an instant, and how it settles to the next tick.
#[derive(Debug, Clone, Copy)]
struct Move {
    to: u32,
    drive: Effect,
    settle: Settle,
}

#[derive(Debug, Clone, Copy)]
enum Settle {
    /// The drive ends on a tick (or the search does not settle).
    OnTick,
    /// The wait to the next tick.
    Wait(Effect),
    /// No wait is possible at the drive's end (the horizon, a session out of view).
    Refused,
}

/// The drives from a cell at an instant are a pure function of the two, and the
/// search expands several labels there (goals, battery trade-offs: up to tens when
/// the battery binds): a memo keyed by the cell and the instant's exact bits, so that
/// a hit returns exactly what a fresh evaluation would. It grows with the instants
/// the search touches and starts afresh past [`Moves::CAPACITY`] entries: a small
/// search allocates little, a large one holds at most ~3.3 MB (a hit is a label of
/// the same instant, made shortly before: eight times the entries saved no time on
/// valley-detour's initial plan on a 60 s tick, 1.19 s against 1.08–1.21 s).
struct Moves {
    memo: FxHashMap<(u32, u64), [Option<Move>; 8]>,
}

impl Moves {
    /// The entries of a table of 4096 places, the most it holds before it doubles (it
    /// keeps an eighth of its places free): one entry more would double the memory of
    /// this memo and the waits' and refills' beside it, 4096 places of which are never
    /// filled before the memo starts afresh.
    const CAPACITY: usize = 4096 / 8 * 7;

    fn new() -> Moves {
        Moves { memo: FxHashMap::default() }
    }

    fn get(&mut self, cell: u32, t: f64, eval: impl FnOnce() -> [Option<Move>; 8]) -> &[Option<Move>; 8] {
        if self.memo.len() >= Self::CAPACITY && !self.memo.contains_key(&(cell, t.to_bits())) {
            self.memo.clear();
        }
        self.memo.entry((cell, t.to_bits())).or_insert_with(eval)
    }

    fn bytes(&self) -> usize {
        self.memo.capacity() * size_of::<((u32, u64), [Option<Move>; 8])>()
    }
}

/// No label: the start's parent.
const NONE: u32 = u32::MAX;

/// A (cell, goal, instant) triple: the key of a staircase.
type Instant = (u32, u16, i64);

/// A label on its instant's staircase: its battery, cost and index.
#[derive(Debug, Clone, Copy)]
struct Stair {
    e: f64,
    cost: f64,
    label: u32,
}

/// The labels of one instant that no other there beats (most instants hold one).
type Staircase = SmallVec<[Stair; 1]>;

/// The staircases by (cell, goal, instant), in shards by cell: a table grows by doubling,
/// and while it moves its entries the old and the new one are both held — in one table of
/// tens of millions of instants that is gigabytes at once (lunar-south-pole-10m's
/// process peaked at 2.2 × its search's own count), in a shard of it a 64th.
struct Instants {
    shards: Vec<FxHashMap<Instant, Staircase>>,
}

impl Instants {
    const SHARDS: usize = 64;

    fn new() -> Instants {
        Instants { shards: (0..Self::SHARDS).map(|_| FxHashMap::default()).collect() }
    }

    fn entry(&mut self, key: Instant, new: impl FnOnce() -> Staircase) -> &mut Staircase {
        self.shards[key.0 as usize % Self::SHARDS].entry(key).or_insert_with(new)
    }
}

/// Instants compared to a microsecond: sums of drive durations in another order round
/// differently.
fn instant_key(t: f64) -> i64 {
    (t * 1e6).round() as i64
}

/// The search's labels, their staircases and queue, its outcome so far, and what
/// places a label among them: the bound, what earlier searches learned, the cut.
struct Frontier<'b> {
    nodes: Vec<Node>,
    at: Instants,
    open: QuaternaryHeap<Reverse<(Ordered, Ordered, u32)>>,
    out: ExactOutcome,
    bound: Bound<'b>,
    guides: Guides<'b>,
    cut: f64,
    /// Whether waits may run on at once (`waiting`).
    run_on: bool,
    /// How far above the queue's least estimate a wait runs on, as a part of it.
    band: f64,
    tick: f64,
}

impl Frontier<'_> {
    /// Takes `label` unless a jump passed it, its bound is infinite or at the cut, or
    /// a label of its instant beats it: queued, or with [`Take::IfNext`] kept without
    /// queueing where the search would take it soon (its index then).
    fn take(&mut self, query: &ExactQuery<'_>, refills: &Refills, label: Node, take: Take) -> Option<u32> {
        if refills.passed(&label) {
            return None;
        }
        let (first, second) = query.key(&mut self.bound, &mut self.guides, &label)?;
        if first.0 >= self.cut {
            return None;
        }
        let next = take == Take::IfNext
            && self.run_on
            && self.open.peek().is_none_or(|Reverse((f, _, _))| first.0 <= f.0 + self.band * f.0.abs().max(1.0));
        let j = query.keep(label, &mut self.nodes, &mut self.at, &mut self.out, self.tick)?;
        if next {
            return Some(j);
        }
        self.open.push(Reverse((first, second, j)));
        None
    }

    /// What the labels, their index, the queue, the bound and the lessons hold, bytes.
    fn bytes(&self) -> usize {
        self.nodes.len() * size_of::<Node>()
            + self.out.instants as usize * size_of::<(Instant, Staircase)>()
            + self.open.len() * size_of::<(Ordered, Ordered, u32)>()
            + self.bound.bytes()
            + self.guides.bytes()
    }
}

impl ExactQuery<'_> {
    /// Runs the search. `None` in the outcome's plan with `stopped` false is a proof
    /// that no plan whose waits end on ticks reaches the goals.
    pub fn solve(&self) -> ExactOutcome {
        self.solve_with(&mut |_| true)
    }

    /// [`ExactQuery::solve`], asking `go_on` before every expansion with the bytes the
    /// search holds (its labels, their index and queue, its memo) whether to go on (a caller's work and memory budget): `false` stops the
    /// search undecided.
    pub fn solve_with(&self, go_on: &mut dyn FnMut(u64) -> bool) -> ExactOutcome {
        self.search(go_on, &[], None).0
    }

    /// [`ExactQuery::solve_with`] guided by what earlier searches of the same problem
    /// learned ([`Learned`]: the same plan, less work), and, with `upper`, only for
    /// plans cheaper than `upper` by more than a part in 10⁹: `None` in the outcome's
    /// plan then says that none is. Also what this search learned, when it found a plan
    /// under an objective that is a sum.
    pub fn solve_guided(
        &self,
        learned: &[Learned],
        upper: Option<f64>,
        go_on: &mut dyn FnMut(u64) -> bool,
    ) -> (ExactOutcome, Option<Learned>) {
        self.search(go_on, learned, upper)
    }

    /// The A* bound the search ranks labels by ([`ExactBound`]), for checking it
    /// against plans.
    pub fn bound(&self) -> ExactBound<'_> {
        let tick = self.model.wait_step_s().unwrap_or_else(|| self.model.stay_duration_s(Action::Hibernate));
        ExactBound(Bound::new(self, self.model.gain_bounds(self.world).0, tick))
    }

    fn search(
        &self,
        go_on: &mut dyn FnMut(u64) -> bool,
        learned: &[Learned],
        upper: Option<f64>,
    ) -> (ExactOutcome, Option<Learned>) {
        let tick = self.model.wait_step_s().unwrap_or_else(|| self.model.stay_duration_s(Action::Hibernate));
        let e_max = self.model.gain_bounds(self.world).0;
        let guides = Guides::new(learned, self, tick, e_max);
        let mut f = Frontier {
            nodes: Vec::new(),
            at: Instants::new(),
            open: QuaternaryHeap::new(),
            out: ExactOutcome::default(),
            bound: Bound::new(self, e_max, tick),
            // Labels whose estimate comes within a part in 10⁹ of `upper` cannot lead
            // to a cheaper plan.
            cut: upper.map_or(f64::INFINITY, |u| u - 1e-9 * u.abs().max(1.0)),
            // A search guided by what earlier ones learned has estimates close to its
            // optimum from the start: waits run on at once there would be made past it.
            run_on: !guides.any() && upper.is_none(),
            band: self.wait_band(),
            guides,
            tick,
        };
        let departures = Departures::new(self.world, self.model, tick);
        let (mut moves, mut waits) = (Moves::new(), Waits::new());
        let mut refills = Refills::new(self, tick);
        let mut counts = WaitCounts::default();
        let start = Node {
            cell: self.start.cell,
            goal: self.reached(0, self.start.cell, self.start.t_min, self.start.energy_wh),
            t: self.start.t_min,
            e: self.start.energy_wh,
            cost: 0.0,
            parent: NONE,
            action: None,
            dead: false,
        };
        self.keep(start, &mut f.nodes, &mut f.at, &mut f.out, tick);
        if let Some((first, second)) = self.key(&mut f.bound, &mut f.guides, &start)
            && first.0 < f.cut
        {
            f.open.push(Reverse((first, second, 0u32)));
        }
        while let Some(Reverse((_, _, i))) = f.open.pop() {
            let node = f.nodes[i as usize];
            if node.dead || refills.passed(&node) {
                continue;
            }
            if node.goal as usize == self.goals.len() {
                f.out.plan = Some((node.cost, self.steps(&f.nodes, i)));
                f.out.counts(refills.jumps, counts);
                // The labels and the queue are done with before the lesson is drawn from
                // the staircases (each shard freed as it is read).
                let Frontier { out, at, nodes, open, .. } = f;
                drop((nodes, open, moves, waits, refills));
                let learned = (!matches!(self.objective, Objective::Margin { .. }))
                    .then(|| Learned::new(self, tick, e_max, node.cost, at))
                    .flatten();
                return (out, learned);
            }
            let held = (f.bytes() + moves.bytes() + refills.bytes() + waits.bytes()) as u64;
            f.out.bytes = f.out.bytes.max(held);
            if f.out.kept >= self.max_labels || !go_on(held) {
                f.out.stopped = true;
                f.out.counts(refills.jumps, counts);
                return (f.out, None);
            }
            f.out.expanded += 1;
            let caches = (&mut moves, &mut waits);
            self.expand(&mut f, (node, i), (e_max, &departures), caches, (&mut refills, &mut counts));
        }
        f.out.counts(refills.jumps, counts);
        (f.out, None)
    }

    /// Makes the labels one step from `node` (index `i`) and takes them into the
    /// frontier: the drives (those after a plain tick of waiting only where driving a
    /// tick earlier and waiting after does not beat them) and the wait, which stands for
    /// its ticks where it may (`waiting`).
    fn expand(
        &self,
        f: &mut Frontier<'_>,
        (node, i): (Node, u32),
        (e_max, departures): (f64, &Departures),
        (moves, waits): (&mut Moves, &mut Waits),
        (refills, counts): (&mut Refills, &mut WaitCounts),
    ) {
        let tick = f.tick;
        let next = self.successors(node, i, (tick, e_max), departures, (moves, Some(refills)));
        let mut later = match f.nodes.get(node.parent as usize) {
            Some(parent) if node.action == Some(Action::Wait) && self.stands_for_waits(parent, &node, tick) => {
                self.later_of(parent, node.parent, (tick, e_max), (moves, waits))
            }
            _ => [None; 8],
        };
        let mut keep = |label: Node, take: Take| f.take(self, refills, label, take);
        for &(label, _) in &next {
            match label.action {
                Some(Action::Drive(k)) => self.take_drive(label, (node.goal, k), &mut later, counts, &mut keep),
                _ if self.stands_for_waits(&node, &label, tick) => {
                    self.wait_on(label, later, (tick, e_max), departures, (moves, waits), counts, &mut keep);
                }
                _ => {
                    keep(label, Take::Queue);
                }
            }
        }
    }

    /// A label's place in the queue, or `None` where the bound is infinite (no plan from
    /// it reaches the goals in time). For a sum: A*'s estimate, ties to the label further
    /// along (more cost so far). For Margin, whose cost only grows along a plan and has
    /// no useful estimate: the cost, then the earliest arrival — A* on time among the
    /// labels of equal margin, so that the first label at the last goal has the least
    /// margin used and, of those, arrives first.
    fn key(&self, bound: &mut Bound<'_>, guides: &mut Guides<'_>, node: &Node) -> Option<(Ordered, Ordered)> {
        let mut rest = bound.at(node.cell, node.goal, node.t, node.e);
        if !rest.is_finite() {
            return None;
        }
        if guides.any() {
            rest = guides.at(bound, node, rest);
        }
        Some(match self.objective {
            Objective::Margin { .. } => {
                // A plan from here that uses no more margin keeps the battery at least
                // at the start's less the margin used: it holds that much at the last
                // goal too, so the sources must give it more first. (Ordering only:
                // plans that use more margin may still arrive earlier.)
                let keep = (self.start.energy_wh - node.cost - self.goal_energy_wh).max(0.0);
                let arrival = if keep > 0.0 {
                    node.t + bound.at(node.cell, node.goal, node.t, node.e - keep)
                } else {
                    node.t + rest
                };
                (ordered(node.cost), ordered(arrival))
            }
            _ => (ordered(node.cost + rest), ordered(-node.cost)),
        })
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
    /// it reaches the last goal), and a wait to the next tick — each with the lowest
    /// battery above the floor inside its step, Wh.
    fn successors(
        &self,
        node: Node,
        i: u32,
        (tick, e_max): (f64, f64),
        departures: &Departures,
        (cache, refills): (&mut Moves, Option<&mut Refills>),
    ) -> Vec<(Node, f64)> {
        let mut out = Vec::with_capacity(9);
        let last = self.goals.len();
        let at_goal = self.goals.get(node.goal as usize).is_some_and(|g| g.cell == node.cell);
        // Where every drive from here lands where the battery soon refills, waiting
        // first is no better than driving now and waiting there (`forward`).
        let mut forward = Forward::new(
            refills.is_some() && self.waits_may_move_on(&node, at_goal, tick),
            self.goals.get(node.goal as usize).map(|g| g.cell),
        );
        let moves = *cache.get(node.cell, node.t, || self.moves_from(node.cell, node.t, tick));
        for (k, m) in moves.iter().enumerate() {
            let Some(m) = m else {
                // Refused now: waiting may let it depart, unless it is refused at any time.
                if self.model.drive_geometry(self.world, node.cell, k as u8).is_ok() {
                    forward.refused_for_now(k as u8);
                }
                continue;
            };
            match self.drive_from(&node, i, k as u8, m, e_max) {
                Some(arrived) if arrived.0.goal as usize == last => out.push(arrived),
                Some(landed) => {
                    forward.lands(k as u8, landed.0.cell, landed.0.t, landed.0.e);
                    out.push(landed);
                }
                None => forward.open = false,
            }
        }
        if let Some(end) = self.wait_end(&node, at_goal, departures, &forward, (cache, refills))
            && let Ok(wait) = self.model.wait(self.world, node.cell, node.t, end - node.t)
            && let Some(waited) = self.step(&node, i, Action::Wait, node.cell, &wait, e_max)
        {
            out.push(waited);
        }
        out
    }

    /// The label after `action` (with `effect`) from `from` (index `i`) to `to`, if the
    /// battery holds inside it, with the lowest battery above the floor inside the step,
    /// Wh.
    fn step(&self, from: &Node, i: u32, action: Action, to: u32, effect: &Effect, e_max: f64) -> Option<(Node, f64)> {
        let lowest = effect.lowest(from.e, self.model.capacity_wh());
        if lowest < -1e-9 {
            return None;
        }
        let (t, e) = (from.t + effect.duration_s, effect.after(from.e, self.model.capacity_wh()));
        let node = Node {
            cell: to,
            goal: self.reached(from.goal, to, t, e),
            t,
            e,
            cost: match self.objective {
                // The battery drawn below the start at the plan's lowest so far.
                Objective::Margin { .. } => from.cost.max(self.start.energy_wh - lowest),
                _ => from.cost + self.step_cost(action, effect, e_max),
            },
            parent: i,
            action: Some(action),
            dead: false,
        };
        Some((node, lowest))
    }

    /// The label after drive `k` (`mv`) from `from` (index `i`) with its settle to the
    /// next tick (none where it reaches the last goal: the plan ends on arrival), and the
    /// lowest battery inside; `None` where the battery runs out or no settle is possible.
    fn drive_from(&self, from: &Node, i: u32, k: u8, mv: &Move, e_max: f64) -> Option<(Node, f64)> {
        let (arrived, low) = self.step(from, i, Action::Drive(k), mv.to, &mv.drive, e_max)?;
        match mv.settle {
            _ if arrived.goal as usize == self.goals.len() => Some((arrived, low)),
            Settle::OnTick => Some((arrived, low)),
            Settle::Refused => None,
            // The settle: the drive and the wait to the next tick are one step of the
            // plan (the drive's label is not kept: no plan departs from it).
            Settle::Wait(wait) => {
                let (mut settled, settle_low) = self.step(&arrived, i, Action::Wait, mv.to, &wait, e_max)?;
                settled.action = Some(Action::Drive(k));
                Some((settled, low.min(settle_low)))
            }
        }
    }

    /// Where the wait from `node` ends, s after the epoch. A wait runs on to the first
    /// tick from which a drive may depart: the ticks between hold nothing but more
    /// waiting, and waits compose exactly. At the next goal's cell every tick may reach
    /// it (its window opening, the battery it must hold), so the wait there is one
    /// tick. Where driving on first is no worse (`forward`), it jumps.
    fn wait_end(
        &self,
        node: &Node,
        at_goal: bool,
        departures: &Departures,
        forward: &Forward,
        (cache, refills): (&mut Moves, Option<&mut Refills>),
    ) -> Option<f64> {
        let tick = departures.tick;
        let end =
            if at_goal { Some(((node.t / tick + 1e-9).floor() + 1.0) * tick) } else { departures.next_after(node.t) };
        if let Some(next) = end
            && (next - node.t - tick).abs() < 1e-9 * tick
            && let Some(refills) = refills
            && let Some(ticks) = self.jumps(node, forward, cache, refills)
        {
            return Some(node.t + f64::from(ticks) * tick);
        }
        end
    }

    /// Whether a wait from `node` may be cut short by [`Forward`]: under Time (a wait
    /// costs what it lasts wherever it is spent), on the settled search's ticks, away
    /// from the next goal's cell (whose window a wait may open).
    fn waits_may_move_on(&self, node: &Node, at_goal: bool, tick: f64) -> bool {
        let phase = node.t / tick;
        matches!(self.objective, Objective::Time) && self.settle && !at_goal && (phase - phase.round()).abs() < 1e-9
    }

    /// The eight drives from `cell` departing at `t`, each with its settle to the next
    /// tick: `None` where the drive is refused.
    fn moves_from(&self, cell: u32, t: f64, tick: f64) -> [Option<Move>; 8] {
        std::array::from_fn(|k| {
            let (to, drive) = self.model.drive(self.world, cell, k as u8, t).ok()?;
            let arrival = t + drive.duration_s;
            let phase = arrival / tick;
            let settle = if !self.settle || (phase - phase.round()).abs() < 1e-9 {
                Settle::OnTick
            } else {
                let end = ((phase + 1e-9).floor() + 1.0) * tick;
                self.model.wait(self.world, to, arrival, end - arrival).map_or(Settle::Refused, Settle::Wait)
            };
            Some(Move { to, drive, settle })
        })
    }

    /// Keeps `node` unless a label at its cell, goal and instant has at least its
    /// battery at no more cost; drops the labels it beats. Its index, if kept. Both
    /// are binary searches on the instant's staircase.
    fn keep(
        &self,
        node: Node,
        nodes: &mut Vec<Node>,
        at: &mut Instants,
        out: &mut ExactOutcome,
        tick: f64,
    ) -> Option<u32> {
        let list = at.entry((node.cell, node.goal, instant_key(node.t)), || {
            out.instants += 1;
            Staircase::new()
        });
        // The staircase is sorted by battery, most first, the cost falling along it (of
        // two labels neither beats, the one with more battery costs more; their
        // batteries differ by more than the slack). The labels with at least this
        // battery are a prefix, the cheapest of them its last. It holds each label's
        // battery and cost beside its index, so the searches touch one short array.
        // Costs are sums in different orders: equal to a part in 10⁹ is equal (else the
        // rounding of equal costs would keep both labels as a trade-off).
        let slack = 1e-9 * node.cost.abs().max(1.0);
        let p = list.partition_point(|s| s.e >= node.e - 1e-9);
        if p > 0 && list[p - 1].cost <= node.cost + slack {
            return None;
        }
        // Those with at most this battery start at q; the ones it beats (no cheaper) lead
        // that run.
        let q = list.partition_point(|s| s.e > node.e + 1e-9);
        let mut r = q;
        while r < list.len() && list[r].cost >= node.cost - slack {
            nodes[list[r].label as usize].dead = true;
            r += 1;
        }
        let j = nodes.len() as u32;
        list.drain(q..r);
        list.insert(q, Stair { e: node.e, cost: node.cost, label: j });
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
            // (Margin's cost is not a sum: `successors` takes the plan's lowest battery.)
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

    fn steps(&self, nodes: &[Node], mut i: u32) -> Vec<ExactStep> {
        let mut steps = Vec::new();
        while nodes[i as usize].parent != NONE {
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
        merge_waits(steps, self.model.wait_step_s().unwrap_or(f64::INFINITY))
    }
}

/// Waits back to back at a cell as one wait (they compose exactly): a plan's step is
/// then a drive or a wait of any length. A first wait shorter than a tick (from a start
/// between ticks) stays apart, as does a wait whose end reaches a goal.
fn merge_waits(steps: Vec<ExactStep>, tick: f64) -> Vec<ExactStep> {
    let mut merged: Vec<ExactStep> = Vec::with_capacity(steps.len());
    let mut reached = 0;
    for step in steps {
        match merged.last_mut() {
            Some(last)
                if last.action == Action::Wait
                    && step.action == Action::Wait
                    && last.cell == step.cell
                    && last.duration_s >= tick - 1e-6
                    && last.goals_reached == reached
                    && step.goals_reached == reached =>
            {
                last.duration_s += step.duration_s;
                (last.battery_wh, last.cost_after) = (step.battery_wh, step.cost_after);
            }
            _ => {
                reached = merged.last().map_or(0, |l| l.goals_reached);
                merged.push(step);
            }
        }
    }
    merged
}

/// The ticks from which a drive may depart ([`ActionModel::drives_may_depart`]), as
/// the first such tick from each tick on.
struct Departures {
    tick: f64,
    /// Per tick index, the index of the first tick at or after it from which a drive
    /// may depart (`u32::MAX`: none before the horizon).
    first_from: Vec<u32>,
}

impl Departures {
    fn new(world: &World, model: &ActionModel, tick: f64) -> Departures {
        let n = (world.span_s() / tick).floor() as usize + 1;
        let mut first_from = vec![u32::MAX; n + 1];
        for k in (0..n).rev() {
            first_from[k] = if model.drives_may_depart(world, k as f64 * tick) { k as u32 } else { first_from[k + 1] };
        }
        Departures { tick, first_from }
    }

    /// The first tick after `t` from which a drive may depart, s.
    fn next_after(&self, t: f64) -> Option<f64> {
        let k = (t / self.tick + 1e-9).floor() as usize + 1;
        let first = *self.first_from.get(k)?;
        (first != u32::MAX).then(|| f64::from(first) * self.tick)
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

#[cfg(test)]
mod tests {
    use super::bound::floor_f32;

    /// The bound's drive weights are f32: each must be the largest f32 not above the
    /// f64 weight, or a sum of them could exceed a plan's cost and the search lose its
    /// optimum.
    #[test]
    fn drive_weights_round_down_to_the_nearest_f32() {
        // 0.1 and 1/3 round up to nearest in f32, 0.7 and 2/3 down; 1e-46 underflows to 0
        // (round to nearest) or a subnormal; 1e39 overflows f32.
        for x in [0.1, 0.7, 1.0 / 3.0, 2.0 / 3.0, 123.456_789, 86_399.999_999, 1e-46, 3.0, 0.0, 1e39] {
            let y = floor_f32(x);
            assert!(f64::from(y) <= x, "{x}: {y} is above it");
            assert!(f64::from(y.next_up()) > x, "{x}: {y} is not the nearest below");
        }
        assert_eq!(floor_f32(0.1), 0.1f32.next_down(), "0.1 rounds up in f32");
        assert_eq!(floor_f32(0.7), 0.7f32, "0.7 rounds down in f32");
    }
}
