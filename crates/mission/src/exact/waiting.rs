//! A wait at a cell as the departures that matter.
//!
//! A label that may wait a plain tick where it stands (drives may depart at the tick's
//! end, the cell is not the next goal's) stands for its waits there. Waiting `m` ticks
//! and then driving `k` (call it P1) reaches the neighbour at the same instant as
//! driving `k` at once and waiting the `m` ticks there (P2): both depart on ticks, so
//! their settles to the next tick are equally long. Where P2 is possible and holds at
//! least P1's battery at no more cost, every plan that goes on from P1 goes on from P2
//! at no more cost, so P1 is not made (`covered`). It is checked one tick at a time:
//! the drive of a label that waited a plain tick against its parent's drive followed
//! by that tick where it landed (or against what that drive was itself compared with,
//! when it was not made).
//!
//! The waits themselves run on at once while the search would take them soon: each
//! wait label whose estimate is within [`WAIT_BAND`] of the queue's least is kept on
//! its instant's staircase (it beats and is beaten as any label there, so later
//! arrivals at the cell meet it) but not queued — its departures are made with it and
//! its own wait goes on in the next one (`waited`). After [`WAIT_TICKS`] ticks, or
//! where the wait stops being plain (a night, a session, whose wait runs on), or leaves
//! the band, the last wait label is queued as any other; where a label of the same
//! instant beats one, what beats it goes on instead. A search guided by what earlier
//! ones learned does not run waits on: its estimates lie close to its optimum from the
//! start, so the band would reach past it (on gale-mola-traverse such repairs made
//! more labels than the fresh searches of the same problems).
//!
//! This keeps the optimum. Replacing P1 by P2 moves `m` ticks of waiting from before a
//! drive to after it, so repeating the replacement along a plan ends (each moves
//! waiting later in the plan's sequence of actions). P2's wait at the neighbour is
//! compared tick by tick, as the search itself waits there; where the search waits
//! there in one longer step instead (a wait that runs on), the battery is the same
//! (waits compose exactly) and the cost no more (a step's cost is never below zero, so
//! one step costs at most what its parts do). Tested against the Dijkstra with no
//! dominance that waits tick by tick (`tests/exact.rs`, `tests/fine_ticks.rs`).
//!
//! Used under L + B and EnergyUsed, where a wait's cost depends on the cell it is spent
//! at, and under Time, where a label below a full battery does not jump
//! ([`super::forward`]): there a wait runs on only while its estimate ties the queue's
//! least (`WAIT_BAND_TIME`), which the waits that charge what the plan needs do. Under
//! Margin, whose queue orders by margin and then arrival, the checks saved no time on
//! devon-island. Not used next to the next goal's cell (a wait there may open its
//! window, and an arrival there counts by its instant), nor for a drive that lands
//! there.

use rustc_hash::FxHashMap;

use super::{Departures, ExactQuery, Moves, Node};
use crate::action_model::Action;
use crate::domain::Objective;
use crate::effect::Effect;

/// How many ticks one wait label stands for before the next is queued: a longer run
/// makes fewer labels expanded but makes departures a search that ends sooner would
/// never have reached.
pub(super) const WAIT_TICKS: u32 = 16;

/// How far above the queue's least estimate, as a part of it, a wait label may be and
/// still be made at once with its departures rather than queued: the labels an A*
/// search takes soon. The most made in vain are the wait labels whose estimates lie in
/// this band above the optimum's cost.
pub(super) const WAIT_BAND: f64 = 1e-3;

/// [`WAIT_BAND`] under Time: a wait runs on only while its estimate ties the queue's
/// least. Under Time the estimate is an instant; a wait that charges nothing (a full
/// battery, a shadow) raises it by its tick, so a band of a part in a thousand of the
/// clock — minutes, several ticks, at mission scale — would run waits on that the
/// search would never take (on the whole MOLA Gale map at 300 h, seven times the
/// labels: `cargo xtask bench static`). A wait that charges a battery the rest of the
/// plan needs lowers the earliest arrival the bound sees by as much as it lasts, so
/// its estimate ties: those are the waits worth running on.
const WAIT_BAND_TIME: f64 = 1e-12;

/// Batteries compared to a nanowatt-hour, as the staircase compares them.
const SLACK_WH: f64 = 1e-9;

/// The one-tick waits at a cell from a tick, a pure function of the two: a memo, as
/// [`Moves`] is for drives.
pub(super) struct Waits {
    memo: FxHashMap<(u32, u64), Option<Effect>>,
}

impl Waits {
    pub(super) fn new() -> Waits {
        Waits { memo: FxHashMap::default() }
    }

    fn get(&mut self, query: &ExactQuery<'_>, cell: u32, t: f64, tick: f64) -> Option<Effect> {
        if self.memo.len() >= Moves::CAPACITY && !self.memo.contains_key(&(cell, t.to_bits())) {
            self.memo.clear();
        }
        *self.memo.entry((cell, t.to_bits())).or_insert_with(|| query.model.wait(query.world, cell, t, tick).ok())
    }

    pub(super) fn bytes(&self) -> usize {
        self.memo.capacity() * size_of::<((u32, u64), Option<Effect>)>()
    }
}

/// What the waits did, for the outcome.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct WaitCounts {
    /// Wait labels made inside a wait and kept without being queued.
    pub(super) waited: u64,
    /// Departures after a wait not made: driving first and waiting after beat them.
    pub(super) covered: u64,
}

/// How [`ExactQuery::wait_on`] asks the search to take a label.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Take {
    /// Keep it unless beaten or hopeless, and queue it.
    Queue,
    /// A wait label: keep it without queueing where the search would expand it next
    /// anyway (its estimate within [`WAIT_BAND`] of the queue's least), else queue it. Its index where
    /// it was kept without queueing.
    IfNext,
}

/// The search's side of [`ExactQuery::wait_on`]: `keep(label, take)`.
pub(super) type Keep<'k> = dyn FnMut(Node, Take) -> Option<u32> + 'k;

/// Per direction, a plan to the drive's landing that departed earlier and waited there
/// since (P2 in the module's documentation).
pub(super) type Later = [Option<Node>; 8];

impl ExactQuery<'_> {
    /// Whether the one-tick wait `waited` from `node` stands for its waits (see the
    /// module's documentation): the search settles, `node` is on a tick away from the
    /// next goal's cell and the wait is a plain tick at the same cell.
    pub(super) fn stands_for_waits(&self, node: &Node, waited: &Node, tick: f64) -> bool {
        let phase = node.t / tick;
        matches!(self.objective, Objective::Energy | Objective::EnergyUsed | Objective::Time)
            && self.settle
            && waited.cell == node.cell
            && waited.goal == node.goal
            && (phase - phase.round()).abs() < 1e-9
            && (waited.t - node.t - tick).abs() < 1e-9 * tick
            && self.goals.get(node.goal as usize).is_none_or(|g| g.cell != node.cell)
    }

    /// How far above the queue's least estimate, as a part of it, a wait label is made
    /// at once rather than queued.
    pub(super) fn wait_band(&self) -> f64 {
        if self.objective == Objective::Time { WAIT_BAND_TIME } else { WAIT_BAND }
    }

    /// The plans P2 for the drives of `waited`, a one-tick wait from `parent` (index
    /// `p`) that stands for its waits: `parent`'s own drives, each followed by the tick
    /// of waiting where it landed.
    pub(super) fn later_of(&self, parent: &Node, p: u32, (tick, e_max): (f64, f64), caches: Caches<'_>) -> Later {
        let (moves, waits) = caches;
        let goal_cell = self.goals.get(parent.goal as usize).map(|g| g.cell);
        let from = *moves.get(parent.cell, parent.t, || self.moves_from(parent.cell, parent.t, tick));
        let mut later = [None; 8];
        for (k, mv) in from.iter().enumerate() {
            later[k] = mv
                .as_ref()
                .and_then(|mv| self.drive_from(parent, p, k as u8, mv, e_max))
                .filter(|(d, _)| d.goal == parent.goal && Some(d.cell) != goal_cell)
                .map(|(d, _)| d);
        }
        self.wait_later(&mut later, (tick, e_max), waits);
        later
    }

    /// Each plan of `later` one tick of waiting on.
    fn wait_later(&self, later: &mut Later, (tick, e_max): (f64, f64), waits: &mut Waits) {
        for v in later.iter_mut() {
            *v = v.and_then(|x| {
                let wait = waits.get(self, x.cell, x.t, tick)?;
                self.step(&x, x.parent, Action::Wait, x.cell, &wait, e_max).map(|(n, _)| n)
            });
        }
    }

    /// Takes the drive `label` in direction `k` from a label that had reached `goal`
    /// goals: not made where `later[k]` beats it, else kept and queued, and then the
    /// plan P2 for the next tick's drive (none where it lands at the next goal's cell).
    pub(super) fn take_drive(
        &self,
        label: Node,
        (goal, k): (u16, u8),
        later: &mut Later,
        counts: &mut WaitCounts,
        keep: &mut Keep<'_>,
    ) {
        let slot = &mut later[k as usize];
        if slot.is_some_and(|p2| beats(&p2, &label)) {
            counts.covered += 1;
            return;
        }
        keep(label, Take::Queue);
        let goal_cell = self.goals.get(goal as usize).map(|g| g.cell);
        *slot = (label.goal == goal && Some(label.cell) != goal_cell).then_some(label);
    }

    /// Makes the departures that matter from the waits that follow, starting with the
    /// one-tick wait `first` (which stands for its waits); `later` holds the plans P2
    /// for its drives.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn wait_on(
        &self,
        first: Node,
        mut later: Later,
        (tick, e_max): (f64, f64),
        departures: &Departures,
        (moves, waits): Caches<'_>,
        counts: &mut WaitCounts,
        keep: &mut Keep<'_>,
    ) {
        let mut w = first;
        for m in 1..=WAIT_TICKS {
            let plain = departures.next_after(w.t).is_some_and(|next| (next - w.t - tick).abs() < 1e-9 * tick);
            if m == WAIT_TICKS || !plain {
                keep(w, Take::Queue);
                return;
            }
            let Some(j) = keep(w, Take::IfNext) else { return };
            counts.waited += 1;
            self.wait_later(&mut later, (tick, e_max), waits);
            let from = *moves.get(w.cell, w.t, || self.moves_from(w.cell, w.t, tick));
            for (k, mv) in from.iter().enumerate() {
                // (A drive refused now keeps its P2: a plan still.)
                if let Some((p1, _)) = mv.as_ref().and_then(|mv| self.drive_from(&w, j, k as u8, mv, e_max)) {
                    self.take_drive(p1, (w.goal, k as u8), &mut later, counts, keep);
                }
            }
            let Some(wait) = waits.get(self, w.cell, w.t, tick) else { return };
            let Some((next, _)) = self.step(&w, j, Action::Wait, w.cell, &wait, e_max) else { return };
            w = next;
        }
    }
}

/// The memos of drives and waits.
pub(super) type Caches<'c> = (&'c mut Moves, &'c mut Waits);

/// Whether `p2` beats `p1`: the same goal and instant, at least its battery at no more
/// cost (to the staircase's tolerances).
fn beats(p2: &Node, p1: &Node) -> bool {
    p2.goal == p1.goal
        && super::instant_key(p2.t) == super::instant_key(p1.t)
        && p2.e >= p1.e - SLACK_WH
        && p2.cost <= p1.cost + 1e-9 * p1.cost.abs().max(1.0)
}
