//! Waits the search need not take one tick at a time.
//!
//! Under Time a wait costs what it lasts wherever it is spent, and a drive lasts the
//! same whenever it departs, its settle ending on the same grid of ticks. So a plan
//! that waits `w` at a cell and then drives to a neighbour reaches the neighbour at the
//! instant the plan that drives now and waits `w` there reaches, at the same cost.
//! Where the rover landing now refills there within a few ticks and then stays full,
//! and at each earlier tick holds at least what a full battery would hold after the
//! later drive, driving first is never worse. Where that holds for every drive allowed
//! now, the wait from the cell jumps [`FORWARD_TICKS`] ticks, or to the first tick at
//! which a drive refused now (the Sun in a camera, a shadow, a session) may depart,
//! if that comes sooner: the shorter waits are beaten, the longer ones pass through the
//! jump, and no departure the waits between would make is lost — the drives refused
//! now are refused at every tick the jump passes over. A label that reaches the cell
//! strictly inside a jump from a battery that stays full there is beaten the same way
//! (its drives are the waiting plan's), and is dropped.
//!
//! Repeated along a plan this moves its waits later, to a cell where it does not hold
//! or to the last goal, where a plan ends on arrival: the optimum is kept. It is not
//! used next to the next goal's cell (a wait there may open its window) nor off the
//! settled ticks.

use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use super::{ExactQuery, Moves, Node, Settle};
use crate::effect::Effect;

/// How far a wait jumps, ticks: a longer jump asks each neighbour to stay full longer.
pub(super) const FORWARD_TICKS: u32 = 16;

/// The most ticks a landing may take to refill before the wait may jump.
const REFILL_TICKS: usize = 4;

/// Batteries compared to a nanowatt-hour, as the staircase compares them.
const SLACK_WH: f64 = 1e-9;

/// Where one of the label's drives lands: its direction, cell, settled instant and
/// battery above the floor.
#[derive(Debug, Clone, Copy)]
struct Landing {
    k: u8,
    cell: u32,
    t: f64,
    e: f64,
}

/// The drives from one label, gathered while its successors are made.
pub(super) struct Forward {
    /// Whether a jump is still possible.
    pub(super) open: bool,
    /// The next goal's cell, where a later arrival may reach the goal that an earlier
    /// one does not (its window, the battery it must hold).
    goal: Option<u32>,
    lands: SmallVec<[Landing; 8]>,
    /// The directions whose drives are refused now but not at every time, as bits.
    refused_for_now: u8,
}

impl Forward {
    pub(super) fn new(open: bool, goal: Option<u32>) -> Forward {
        Forward { open, goal, lands: SmallVec::new(), refused_for_now: 0 }
    }

    /// Drive `k` is refused now, but not at every time: waiting may let it depart.
    pub(super) fn refused_for_now(&mut self, k: u8) {
        self.refused_for_now |= 1 << k;
    }

    /// Drive `k` lands at `cell` at the tick `t` with `e` Wh.
    pub(super) fn lands(&mut self, k: u8, cell: u32, t: f64, e: f64) {
        if Some(cell) == self.goal {
            self.open = false;
        }
        if self.open {
            self.lands.push(Landing { k, cell, t, e });
        }
    }
}

/// The waits one tick at a time at a cell from a tick (`waits[j]`: the first `j + 1`
/// ticks as one wait), and whether a full battery stays full from the first tick's end
/// to the jump's.
#[derive(Debug, Clone, Copy)]
struct Refill {
    waits: [Option<Effect>; REFILL_TICKS],
    steady: bool,
}

impl Refill {
    /// The battery after the first `m` ticks from `e`, or `None` where it runs out.
    fn after(&self, m: usize, e: f64, capacity: f64) -> Option<f64> {
        let w = self.waits[m - 1]?;
        (w.lowest(e, capacity) >= -SLACK_WH).then(|| w.after(e, capacity))
    }

    /// The fewest ticks after which a battery of `e` is full, staying full to the jump's
    /// end.
    fn ticks_to_full(&self, e: f64, capacity: f64) -> Option<usize> {
        if !self.steady {
            return None;
        }
        (1..=REFILL_TICKS).find(|&m| self.after(m, e, capacity).is_some_and(|a| a >= capacity - SLACK_WH))
    }
}

/// The refills asked about (many labels around a cell ask at the same tick: a memo as
/// [`Moves`]) and the jumps made from a full battery.
pub(super) struct Refills {
    tick: f64,
    /// The most [`REFILL_TICKS`] ticks of waiting can charge, Wh.
    most_refill_wh: f64,
    memo: FxHashMap<(u32, u64), Refill>,
    /// Per cell and goal, the ticks `(from, to)` the last jump from a battery that
    /// stays full there passed over.
    jumped: FxHashMap<(u32, u16), (f64, f64)>,
    /// The jumps made.
    pub(super) jumps: u64,
}

impl Refills {
    pub(super) fn new(query: &ExactQuery<'_>, tick: f64) -> Refills {
        let most_refill_wh = query.model.charge_bound_w(query.world) * REFILL_TICKS as f64 * tick / 3600.0;
        Refills { tick, most_refill_wh, memo: FxHashMap::default(), jumped: FxHashMap::default(), jumps: 0 }
    }

    /// Whether `node` lies strictly inside a jump at its cell and goal (and is beaten).
    pub(super) fn passed(&self, node: &Node) -> bool {
        let phase = node.t / self.tick;
        (phase - phase.round()).abs() < 1e-9
            && self
                .jumped
                .get(&(node.cell, node.goal))
                .is_some_and(|&(from, to)| node.t > from + 1e-6 && node.t < to - 1e-6)
    }

    fn refill(&mut self, query: &ExactQuery<'_>, cell: u32, t: f64) -> Refill {
        if self.memo.len() >= Moves::CAPACITY && !self.memo.contains_key(&(cell, t.to_bits())) {
            self.memo.clear();
        }
        let tick = self.tick;
        *self.memo.entry((cell, t.to_bits())).or_insert_with(|| {
            let (model, world) = (query.model, query.world);
            let mut waits = [None; REFILL_TICKS];
            let mut sum: Option<Effect> = None;
            for (m, slot) in waits.iter_mut().enumerate() {
                let one = model.wait(world, cell, t + m as f64 * tick, tick).ok();
                sum = match (sum, one) {
                    (None, Some(w)) if m == 0 => Some(w),
                    (Some(s), Some(w)) => Some(s.then(&w)),
                    _ => None,
                };
                *slot = sum;
            }
            // Full from the first tick's end on: nothing drawn between any two
            // instants up to the jump's end.
            let rest = f64::from(FORWARD_TICKS - 1) * tick;
            let steady = model.wait(world, cell, t + tick, rest).is_ok_and(|w| w.deepest_wh <= SLACK_WH);
            Refill { waits, steady }
        })
    }

    pub(super) fn bytes(&self) -> usize {
        self.memo.capacity() * size_of::<((u32, u64), Refill)>()
            + self.jumped.capacity() * size_of::<((u32, u16), (f64, f64))>()
    }
}

impl ExactQuery<'_> {
    /// How many ticks the wait from `node` may jump, given its drives gathered in
    /// `forward` (see the module's documentation): `None` where it may not; records the
    /// jump where the battery stays full at the cell.
    pub(super) fn jumps(
        &self,
        node: &Node,
        forward: &Forward,
        moves: &mut Moves,
        refills: &mut Refills,
    ) -> Option<u32> {
        let (capacity, tick) = (self.model.capacity_wh(), refills.tick);
        // No landing that no wait could refill in time: most labels with a battery
        // far from full stop here, before any wait is integrated.
        if !forward.open || forward.lands.iter().any(|l| l.e + refills.most_refill_wh < capacity - SLACK_WH) {
            return None;
        }
        let mut refill: SmallVec<[(Landing, Refill, usize); 8]> = SmallVec::new();
        for &l in &forward.lands {
            let r = refills.refill(self, l.cell, l.t);
            let m = r.ticks_to_full(l.e, capacity)?;
            refill.push((l, r, m));
        }
        // Before a landing is full, it must hold what the later drive from a full
        // battery would land with.
        for m in 1..REFILL_TICKS {
            if refill.iter().all(|&(_, _, full)| full <= m) {
                break;
            }
            let t = node.t + m as f64 * tick;
            let later = *moves.get(node.cell, t, || self.moves_from(node.cell, t, tick));
            for &(l, r, _) in refill.iter().filter(|&&(_, _, full)| full > m) {
                let Some(mv) = later[l.k as usize] else { continue };
                let landed = mv.drive.after(capacity, capacity);
                let most = match mv.settle {
                    Settle::OnTick => landed,
                    Settle::Wait(w) => w.after(landed, capacity),
                    Settle::Refused => continue,
                };
                if r.after(m, l.e, capacity).is_none_or(|e| e < most - SLACK_WH) {
                    return None;
                }
            }
        }
        // Last, as the dearest check: the drives refused now at the ticks ahead.
        let ticks = self.until_allowed(node, forward.refused_for_now, tick);
        if ticks < 2 {
            return None;
        }
        let to = node.t + f64::from(ticks) * tick;
        if refills.refill(self, node.cell, node.t).ticks_to_full(node.e, capacity).is_some() {
            refills.jumped.insert((node.cell, node.goal), (node.t, to));
        }
        refills.jumps += 1;
        Some(ticks)
    }

    /// The ticks from `node` to the first at which one of the drives `refused` (bits by
    /// direction) may depart from its cell, at most [`FORWARD_TICKS`]. Each is asked on
    /// its own, without its settle (a drive departs where [`ActionModel::drive`] allows
    /// it, whatever follows).
    ///
    /// [`ActionModel::drive`]: crate::ActionModel::drive
    fn until_allowed(&self, node: &Node, refused: u8, tick: f64) -> u32 {
        if refused == 0 {
            return FORWARD_TICKS;
        }
        (1..FORWARD_TICKS)
            .find(|&m| {
                let t = node.t + f64::from(m) * tick;
                (0..8u8).any(|k| refused & (1 << k) != 0 && self.model.drive(self.world, node.cell, k, t).is_ok())
            })
            .unwrap_or(FORWARD_TICKS)
    }
}
