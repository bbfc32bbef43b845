//! The exact search's A* bound: the cheapest drives to each remaining goal over a 2-D
//! graph of the least each drive can cost at any time, and what the time before the
//! earliest the rover can arrive costs above those floors (the deep night, the slow
//! hours, and under L + B the shortfall clock: a Sun short of the drives' credit, the
//! stays).
//!
//! Its 2-D parts are Dijkstras backward from each goal over the drives' floors, run
//! lazily: each goes only as far as the cells the search asks about need (a cell's
//! distance is final once the backward search has settled it, and the search goes on
//! from where it stopped at the next cell asked about). A route of a few kilometres on
//! a map of millions of cells so weighs the drives of the cells around it, not the
//! map's; the values are the very distances a whole-map Dijkstra gives, so the bound,
//! and the search, do not change.

use super::ExactQuery;
use areo_rover::resources::Load;

use crate::action_model::{Action, ActionModel, NEIGHBOURS};
use crate::domain::{DarkCost, Objective, PathLength, sampled_at};
use crate::landmark::{Edges, Landmark};
use crate::world::World;

/// The weights of a drive the backward searches sum, as rows of [`Weigher::weigh`].
const OBJECTIVE: usize = 0;
const DURATION: usize = 1;
const TICKS: usize = 2;
const LOAD: usize = 3;

/// Cells per page of the weighed drives.
const PAGE: usize = 256;

/// The largest f32 not above `x`.
pub(super) fn floor_f32(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x { y.next_down() } else { y }
}

/// What weighs a drive: the query's objective and model, and the tick.
struct Weigher<'a> {
    world: &'a World,
    model: &'a ActionModel,
    objective: Objective,
    e_max: f64,
    tick: f64,
    source_w: f64,
    /// What every drive draws each second at least, W, taken off the [`LOAD`] row
    /// ([`Harvest`]).
    base_w: f64,
}

impl Weigher<'_> {
    /// The drives into `cell` from the neighbour behind each direction, weighed: per
    /// row ([`OBJECTIVE`], [`DURATION`], [`TICKS`], [`LOAD`]) the objective's floor
    /// (the least its energy can be under any Sun), the duration, the duration in whole
    /// ticks and the loads' least energy above the base every drive draws — f32 rounded
    /// down, so that sums of them stay lower bounds; infinite where no drive exists.
    fn weigh(&self, cell: u32) -> Weighed {
        let mut w = [[f32::INFINITY; 8]; 4];
        let (dx, dy) = (self.world.dem().dx(), self.world.dem().dy());
        for k in 0..8u8 {
            let Some((_, g)) = self.model.drive_geometry_into(self.world, cell, k) else { continue };
            let load = self.model.drive_load_floor_wh(&g);
            let floor = match self.objective {
                Objective::Energy => {
                    let units = PathLength::Distance.units(Action::Drive(k), dx, dy);
                    (self.model.drive_energy_floor_wh(&g, self.source_w) + self.e_max * units).max(0.0)
                }
                Objective::EnergyUsed => load,
                Objective::Time | Objective::Margin { .. } => g.duration_s,
            };
            let k = k as usize;
            w[OBJECTIVE][k] = floor_f32(floor);
            w[DURATION][k] = floor_f32(g.duration_s);
            w[TICKS][k] = floor_f32((g.duration_s / self.tick - 1e-9).ceil() * self.tick);
            let above = load - self.base_w * g.duration_s / 3600.0 - 1e-9 * load.abs();
            w[LOAD][k] = floor_f32(above.max(0.0));
        }
        w
    }
}

/// The drives into a cell weighed, a row per weight ([`Weigher::weigh`]).
type Weighed = [[f32; 8]; 4];

/// The drives into each cell the backward searches have met, weighed when first met
/// ([`Weigher::weigh`]), in pages allocated as the searches reach them.
struct Weights<'a> {
    weigher: Weigher<'a>,
    pages: Vec<Option<Box<[Option<Weighed>]>>>,
    /// How many pages are allocated.
    held: usize,
}

impl<'a> Weights<'a> {
    fn new(weigher: Weigher<'a>) -> Weights<'a> {
        let n = weigher.world.cols() * weigher.world.rows();
        Weights { weigher, pages: vec![None; n.div_ceil(PAGE)], held: 0 }
    }

    /// The drives into `cell`, weighed.
    fn into(&mut self, cell: u32) -> &Weighed {
        let (page, at) = (cell as usize / PAGE, cell as usize % PAGE);
        let held = &mut self.held;
        let page = self.pages[page].get_or_insert_with(|| {
            *held += 1;
            vec![None; PAGE].into_boxed_slice()
        });
        page[at].get_or_insert_with(|| self.weigher.weigh(cell))
    }

    /// A backward search's edges over row `row`: the drives into a cell, each from the
    /// neighbour behind its direction, with its weight.
    fn edges(&mut self, row: usize, to: u32, out: Edges<'_>) {
        let world = self.weigher.world;
        let (c, r) = world.col_row(to);
        let weights = self.into(to)[row];
        for (k, &weight) in weights.iter().enumerate() {
            if weight != f32::INFINITY {
                // On the map: the drive exists.
                let (dc, dr) = NEIGHBOURS[k];
                let from = world.cell((c as i64 - i64::from(dc)) as usize, (r as i64 - i64::from(dr)) as usize);
                out.push((from, f64::from(weight)));
            }
        }
    }

    fn bytes(&self) -> usize {
        self.pages.len() * size_of::<Option<Box<[Option<Weighed>]>>>() + self.held * PAGE * size_of::<Option<Weighed>>()
    }
}

/// A Dijkstra backward from a goal over one row of the drives' weights (never
/// negative), run as far as the cells asked about need ([`Landmark`]).
struct Backward {
    row: usize,
    distances: Landmark,
}

/// The A* bound from a label to the last goal: the cheapest drives through the
/// remaining goals over each drive's floor (2-D, any time), plus what the span between
/// the label's instant and the earliest it can arrive costs above those floors — the
/// deep night, or under L + B the shortfall clock ([`Shortfall`]) — or all of that span
/// at any action's least cost per second, the approximate planner's time bound
/// (`domain::DarkCost`). Under the
/// Time objective, the earliest arrival less the label's instant.
///
/// The earliest arrival: over the drives that exist (a detour round an obstacle takes
/// its time), each drive but the last lasting whole ticks (its settle), the drives
/// outside the Communicate sessions ([`FreeTime`]), the last ending where a drive may
/// end (in daylight under the daylight rule), and no earlier than the sources can have
/// given the battery what the drives ahead load it with ([`Harvest`]).
/// A plan that cannot beat the sunset is so seen to wait out the night, and to pay for
/// it in the bound.
pub(super) struct Bound<'a> {
    weights: Weights<'a>,
    searches: Vec<Backward>,
    /// Per goal and weight row, the index of its backward search in `searches` (two
    /// rows may share one: under Time the objective's floor is the duration; without
    /// settles the whole ticks are the durations).
    per_goal: Vec<[usize; 4]>,
    /// Per goal and weight row, the sum from the goal through the later goals.
    tails: Vec<[f64; 4]>,
    /// What the whole-tick sums may exceed the truth by: the first drive from a start
    /// between ticks and the last drive, unsettled, s.
    slack_s: f64,
    /// Under the daylight rule, the Sun-table step and, per table instant, the first
    /// instant at or after it with the Sun above the horizon.
    day: Option<(f64, Vec<f64>)>,
    /// The last goal's window's close, s after the epoch.
    close_s: f64,
    harvest: Harvest,
    /// The time outside the sessions, for the drives at their own durations.
    free: FreeTime,
    /// The ticks outside the sessions, for the drives with their settles: a drive
    /// departs on a tick outside any session and no tick inside it falls in one (it
    /// would overlap the session), so the tick intervals from the sessions' first tick
    /// to the first after their end hold no part of a drive and its settle.
    free_ticks: FreeTime,
    /// The tick, s.
    tick: f64,
    /// Whether the cost is the time taken (the bound is then the earliest arrival).
    time_objective: bool,
    dark: Option<DarkCost>,
    shortfall: Option<Shortfall>,
}

/// The sum of `search`'s weights from `cell` to its goal (infinite: no way there).
fn distance(search: &mut Backward, weights: &mut Weights<'_>, cell: u32) -> f64 {
    let row = search.row;
    search.distances.distance(cell, |to, out| weights.edges(row, to, out)).unwrap_or(f64::INFINITY)
}

impl<'a> Bound<'a> {
    pub(super) fn new(query: &ExactQuery<'a>, e_max: f64, tick: f64) -> Bound<'a> {
        let (world, model) = (query.world, query.model);
        let time_objective = matches!(query.objective, Objective::Time | Objective::Margin { .. });
        let source_w = model.drive_source_bound_w(world);
        let harvest = Harvest::new(query);
        let weigher =
            Weigher { world, model, objective: query.objective, e_max, tick, source_w, base_w: harvest.base_w };
        let mut weights = Weights::new(weigher);
        let mut searches = Vec::new();
        let mut add = |goal: u32, row: usize| {
            searches.push(Backward { row, distances: Landmark::new(goal) });
            searches.len() - 1
        };
        let per_goal: Vec<[usize; 4]> = query
            .goals
            .iter()
            .map(|g| {
                let mut rows = [0; 4];
                rows[DURATION] = add(g.cell, DURATION);
                rows[OBJECTIVE] = if time_objective { rows[DURATION] } else { add(g.cell, OBJECTIVE) };
                rows[TICKS] = if query.settle { add(g.cell, TICKS) } else { rows[DURATION] };
                rows[LOAD] = add(g.cell, LOAD);
                rows
            })
            .collect();
        let mut tails = vec![[0.0; 4]; query.goals.len() + 1];
        for i in (0..query.goals.len().saturating_sub(1)).rev() {
            for row in 0..4 {
                let leg = distance(&mut searches[per_goal[i + 1][row]], &mut weights, query.goals[i].cell);
                tails[i][row] = tails[i + 1][row] + leg;
            }
        }
        let day = model.config().drive.daylight.then(|| {
            let step = world.sun_step_s();
            let table = world.sun_table();
            let mut first = vec![f64::INFINITY; table.len() + 1];
            for k in (0..table.len()).rev() {
                // The Sun comes up somewhere after the last sample below the horizon.
                first[k] = if table[k].elevation_deg > 0.0 { k as f64 * step } else { first[k + 1] };
            }
            (step, first)
        });
        let units = (0..8u8)
            .map(|k| PathLength::Distance.units(Action::Drive(k), world.dem().dx(), world.dem().dy()))
            .fold(f64::INFINITY, f64::min);
        Bound {
            weights,
            searches,
            per_goal,
            tails,
            slack_s: if query.settle { 2.0 * tick } else { 0.0 },
            day,
            close_s: query.goals.last().map_or(f64::INFINITY, |g| g.close_s),
            harvest,
            free: FreeTime::new(model.sessions()),
            free_ticks: FreeTime::new(&if query.settle { on_ticks(model.sessions(), tick) } else { Vec::new() }),
            tick,
            time_objective,
            dark: DarkCost::new(world, model, query.objective, e_max, units, source_w),
            shortfall: Shortfall::new(query, e_max, source_w),
        }
    }

    /// The sum of weight `row` from `cell` through the goals from `goal` on.
    fn remaining(&mut self, row: usize, goal: usize, cell: u32) -> f64 {
        distance(&mut self.searches[self.per_goal[goal][row]], &mut self.weights, cell) + self.tails[goal][row]
    }

    /// The least cost from a label at `cell` at `t` with `e` above the floor, `goal`
    /// goals reached, to the end of any plan (infinite: none can reach the goals).
    pub(super) fn at(&mut self, cell: u32, goal: u16, t: f64, e: f64) -> f64 {
        let g = goal as usize;
        if g >= self.per_goal.len() {
            return 0.0;
        }
        let arrival = self.arrival(cell, g, t, e);
        if !arrival.is_finite() {
            return f64::INFINITY;
        }
        let drives = self.remaining(OBJECTIVE, g, cell);
        self.until(drives, t, arrival)
    }

    /// The least cost of a plan from a label at `t` whose drives' floors sum to at least
    /// `drives` and which reaches the last goal no earlier than `arrival`: under Time the
    /// longer of the drives and the span; otherwise the drives plus what the clocks
    /// charge over the span.
    fn until(&self, drives: f64, t: f64, arrival: f64) -> f64 {
        if self.time_objective {
            return drives.max(arrival - t);
        }
        // Any plan from here spends at least until the arrival on its way: the deep
        // night in that span with stays, and all of it at the least cost per second.
        match &self.dark {
            Some(d) => {
                let short = self.shortfall.as_ref().map_or(0.0, |s| s.at(arrival) - s.at(t));
                let span = (d.at(arrival) - d.at(t)).max(short).max(0.0);
                (drives + span).max((d.any_at(arrival) - d.any_at(t)).max(0.0))
            }
            None => drives + self.shortfall.as_ref().map_or(0.0, |s| (s.at(arrival) - s.at(t)).max(0.0)),
        }
    }

    /// The earliest the rover at `cell` at `t` with `e`, `goal` goals reached, can reach
    /// the last goal, s after the epoch (infinite: never within the Sun table, or after
    /// the last goal's window).
    pub(super) fn arrival(&mut self, cell: u32, goal: usize, t: f64, e: f64) -> f64 {
        let plain = self.remaining(DURATION, goal, cell);
        let ticks = self.remaining(TICKS, goal, cell) - self.slack_s;
        let least = plain.max(ticks);
        let load = self.remaining(LOAD, goal, cell);
        // A start between ticks may lie in the last interval of a session that ends
        // between ticks: one tick less.
        let stepped = self.free_ticks.after(t, ticks - self.tick);
        let at = (t + least).max(self.free.after(t, plain)).max(stepped).max(self.harvest.ready(load, plain, t, e));
        if at > self.close_s + 1e-9 {
            return f64::INFINITY;
        }
        if least <= 0.0 {
            // At the goal: no drive left to end in daylight.
            return at;
        }
        match &self.day {
            Some((step, first)) if self.weights.weigher.world.sun(at).elevation_deg <= 0.0 => {
                // The last drive ends in daylight: no earlier than the sample before
                // the first one with the Sun up.
                let k = (at / step).ceil() as usize;
                match first.get(k) {
                    Some(&up) if up.is_finite() => at.max(up - step),
                    _ => f64::INFINITY,
                }
            }
            _ => at,
        }
    }

    /// The bytes the bound holds: its weighed drives and its searches.
    pub(super) fn bytes(&self) -> usize {
        self.weights.bytes() + self.searches.iter().map(|s| s.distances.bytes()).sum::<usize>()
    }
}

/// Upper bounds on the array's power at each Sun-table instant, W, for a rover standing
/// (on ground no steeper than the map's steepest passable cell and the slope rule allow)
/// and for one driving, that hold for any Sun on the arc to the neighbouring instants:
/// between samples the Sun moves along an arc at most `arc` from both ends, so the
/// ground's tilt widened by it bounds the incidence there (and the beam, linear between
/// samples, is at most the larger end's). The start's cell may be steeper than the
/// drives allow; a hair for the f32 slopes.
fn solar_bounds(query: &ExactQuery<'_>) -> (Vec<f64>, Vec<f64>) {
    let (world, model) = (query.world, query.model);
    let table = world.sun_table();
    let arc = table
        .windows(2)
        .map(|w| {
            (w[0].enu[0] * w[1].enu[0] + w[0].enu[1] * w[1].enu[1] + w[0].enu[2] * w[1].enu[2]).clamp(-1.0, 1.0).acos()
        })
        .fold(0.0, f64::max)
        .to_degrees();
    let drives = model.ground_tilt_bound_deg().min(world.steepest_tilt_deg()) + arc + 0.01;
    let ground = drives.max(world.slope_deg(query.start.cell) + arc + 0.01);
    let stay_w = table.iter().map(|s| model.stay_solar_bound_w(s, ground)).collect();
    let drive_w = table.iter().map(|s| model.drive_solar_bound_w(s, drives)).collect();
    (stay_w, drive_w)
}

/// Under L + B, the least any plan pays above its drives' floors, as a clock: from the
/// epoch to each Sun-table instant, the integral of the least rate at which an action
/// overlapping the instant costs more than the floors count. A drive's floor credits
/// it with the most the sources can ever give while driving; the Sun short of that
/// (low, or behind the array's best incidence) is energy the drive does not gain
/// ([`ActionModel::drive_shortfall_rate`]). A stay counts in no floor, so all of its
/// cost is above them ([`ActionModel::stay_rate_floor`]), with the array turned to the
/// Sun on ground no steeper than the rover may stand on ([`solar_bounds`]). Every
/// instant of a plan lies in some action, drive or stay, so the plan from `t` to its
/// end pays at least the clock's rise over that span above its drives' floors: a rover
/// that drives through the morning pays for the Sun being low, one that waits for noon
/// pays for the wait.
/// Where the drives' floors may be clamped at zero (a drive gaining more than E_max
/// per unit of L) the credit is not paid back, and drives count nothing.
struct Shortfall {
    step_s: f64,
    cumulative: Vec<f64>,
}

impl Shortfall {
    fn new(query: &ExactQuery<'_>, e_max: f64, source_w: f64) -> Option<Shortfall> {
        let (world, model) = (query.world, query.model);
        let table = world.sun_table();
        if query.objective != Objective::Energy || table.len() < 3 {
            return None;
        }
        let step_s = world.sun_step_s();
        let (stay_w, drive_w) = solar_bounds(query);
        let stay_s = model.stays().iter().map(|&a| model.stay_duration_s(a)).fold(0.0, f64::max);
        let drive_s = model.longest_drive_s(world);
        let reach = |d: f64| (d / step_s).ceil() as usize + 1;
        // The most within `r` samples of the interval [k, k + 1]: the Sun is interpolated
        // linearly between samples, and an action overlapping the interval lies there.
        let within = |v: &[f64], k: usize, r: usize| {
            v[k.saturating_sub(r)..=(k + 1 + r).min(v.len() - 1)].iter().copied().fold(0.0, f64::max)
        };
        let daylight = model.config().drive.daylight;
        // In the deep night a stay pays at least E_max per unit of L and its load in the
        // dark: the dark-time bound's rate (`domain::DarkCost`), so that this clock
        // rises at least as fast as that one everywhere.
        let dark_rate = model
            .stays()
            .iter()
            .map(|&a| (e_max * model.stay_units(a) + model.dark_stay_floor_wh(a)).max(0.0) / model.stay_duration_s(a))
            .fold(f64::INFINITY, f64::min);
        let unclamped = model.drive_floors_unclamped(world, e_max);
        // Every action overlapping an interval lies within `r` samples of it.
        let r = reach(stay_s.max(drive_s));
        let mut cumulative = Vec::with_capacity(table.len());
        cumulative.push(0.0);
        for k in 0..table.len() - 1 {
            let stay = model.stay_rate_floor(e_max, within(&stay_w, k, reach(stay_s)));
            // Under the daylight rule no drive overlaps the deep night.
            let deep = daylight
                && table[k.saturating_sub(r)..=(k + 1 + r).min(table.len() - 1)].iter().all(|s| s.elevation_deg <= 0.0);
            let drive =
                if unclamped { model.drive_shortfall_rate(within(&drive_w, k, reach(drive_s)), source_w) } else { 0.0 };
            let rate = if deep { stay.max(dark_rate) } else { stay.min(drive) };
            cumulative.push(cumulative[k] + rate * step_s);
        }
        cumulative.last().is_some_and(|&c| c > 0.0).then_some(Shortfall { step_s, cumulative })
    }

    /// The clock at `t`, s after the epoch.
    fn at(&self, t: f64) -> f64 {
        sampled_at(&self.cumulative, self.step_s, t)
    }
}

/// Lower bounds on what a plan that reaches one of a set of cells costs from a label,
/// whatever the cells' data now are: for a cell x, the least drives from the label's
/// cell to x, then at some instant t′ on from the label's, the bound from x at t′ with
/// any battery and any goal reached since — with the cost the clock itself charges
/// between the two instants (the shortfall clock under L + B, the time under Time), which
/// both parts of the plan pay separately and so add. A learned bound
/// ([`super::learned`]) is clamped by these: it was true of a world without the cells'
/// changes, and only plans that reach them can have become cheaper.
///
/// The most recent [`Through::OWN`] cells are bounded each on its own, and also by the
/// label's own battery ([`Bound::via`]: a label that must charge before it can finish
/// is seen to, wherever it passes); older ones together (the least drives to any of
/// them, the least of their bounds, any battery): looser, but what it holds does not
/// grow with them.
pub(super) struct Through {
    own: Vec<Reach>,
    older: Option<Reach>,
}

/// The cells a [`Reach`] bounds plans through, the least drives from any cell to the
/// nearest of them, and on first use, per goal reached and tick index up to the last
/// goal's close, the least over that tick and every later one of each clock's cost
/// since the epoch plus the least bound from one of the cells with a full battery and
/// that many goals reached or more: with the clock that adds to the drives (`.0`) and
/// with the one that covers them (`.1`).
struct Reach {
    cells: Vec<u32>,
    to: Backward,
    suffix: Option<Vec<(Vec<f64>, Vec<f64>)>>,
}

impl Through {
    /// Cells bounded each on its own.
    const OWN: usize = 16;

    /// Bounds for `cells`, the most recently changed last.
    pub(super) fn new(cells: &[u32]) -> Through {
        let split = cells.len().saturating_sub(Self::OWN);
        let reach = |cells: &[u32]| Reach {
            cells: cells.to_vec(),
            to: Backward { row: OBJECTIVE, distances: Landmark::from_anchors(cells) },
            suffix: None,
        };
        Through {
            own: cells[split..].iter().map(|c| reach(std::slice::from_ref(c))).collect(),
            older: (split > 0).then(|| reach(&cells[..split])),
        }
    }

    pub(super) fn bytes(&self) -> usize {
        self.own.iter().chain(&self.older).map(Reach::bytes).sum()
    }
}

impl Reach {
    fn bytes(&self) -> usize {
        self.to.distances.bytes() + self.suffix.iter().flatten().map(|(a, b)| (a.len() + b.len()) * 8).sum::<usize>()
    }
}

impl Bound<'_> {
    /// The clocks' costs from the epoch to `t`: the one that adds to the drives' floors
    /// and the one that covers the drives ([`Through`]).
    fn clocks(&self, t: f64) -> (f64, f64) {
        if self.time_objective {
            return (0.0, t);
        }
        match &self.dark {
            Some(d) => (self.shortfall.as_ref().map_or_else(|| d.at(t), |s| s.at(t)), d.any_at(t)),
            None => (0.0, 0.0),
        }
    }

    /// The least cost of any plan from a label at `cell` at `t` with `e` above the floor,
    /// `goal` goals reached, that reaches one of `through`'s cells (infinite: none can).
    pub(super) fn through(&mut self, through: &mut Through, cell: u32, goal: u16, t: f64, e: f64) -> f64 {
        let j = (t / self.tick + 1e-9).floor();
        if j < 0.0 {
            return 0.0;
        }
        let now = self.clocks(t);
        let mut least = f64::INFINITY;
        for reach in through.own.iter_mut().chain(through.older.as_mut()) {
            least = least.min(self.reach(reach, cell, goal, (j as usize, t), now, e));
        }
        least
    }

    fn reach(&mut self, reach: &mut Reach, cell: u32, goal: u16, (j, t): (usize, f64), now: (f64, f64), e: f64) -> f64 {
        let (now_add, now_cover) = now;
        let drives = distance(&mut reach.to, &mut self.weights, cell);
        if !drives.is_finite() {
            return f64::INFINITY;
        }
        if reach.suffix.is_none() {
            reach.suffix = Some(self.suffix_minima(&reach.cells));
        }
        let per_goal = reach.suffix.as_ref().expect("just made");
        let Some((add, cover)) = per_goal.get(goal as usize) else { return f64::INFINITY };
        let Some(&a) = add.get(j) else { return f64::INFINITY };
        let any_battery = (drives + a - now_add).max(cover[j] - now_cover);
        let with_battery = match reach.cells[..] {
            [x] => self.via(drives, x, goal, t, e),
            _ => 0.0,
        };
        any_battery.max(with_battery).max(0.0)
    }

    /// The least cost of any plan from a label at `t` with `e` above the floor, `goal`
    /// goals reached, that drives to `x` at a cost of at least `to_x` on its way: the
    /// label's own battery bounds the whole plan's harvest ([`Harvest`]), and the drives
    /// from `x` on, with every goal not reached before `x`, bound its drives and arrival.
    /// Every term of [`Bound::arrival`] holds of a plan that is at `x` at any instant from
    /// `t` on, so the span from `t` to that arrival is charged once, the floors of the
    /// drives to `x` and from it added.
    fn via(&mut self, to_x: f64, x: u32, goal: u16, t: f64, e: f64) -> f64 {
        let mut least = f64::INFINITY;
        for g in goal as usize..self.per_goal.len() {
            let arrival = self.arrival(x, g, t, e);
            if arrival.is_finite() {
                let drives = to_x + self.remaining(OBJECTIVE, g, x);
                least = least.min(self.until(drives, t, arrival));
            }
        }
        least
    }

    /// [`Reach`]'s suffix minima for `cells`.
    fn suffix_minima(&mut self, cells: &[u32]) -> Vec<(Vec<f64>, Vec<f64>)> {
        let goals = self.per_goal.len();
        let ticks = (self.close_s.min(self.weights.weigher.world.span_s()) / self.tick + 1e-9).floor() as usize + 1;
        let full = self.weights.weigher.model.capacity_wh();
        // A cell no drive enters is never reached (its bound would search the whole map
        // to find no way on from it).
        let mut open = Vec::with_capacity(cells.len());
        for &c in cells {
            if Weights::into(&mut self.weights, c)[OBJECTIVE].iter().any(|w| w.is_finite()) {
                open.push(c);
            }
        }
        let mut out = vec![(vec![f64::INFINITY; ticks], vec![f64::INFINITY; ticks]); goals];
        for j in (0..ticks).rev() {
            let t = j as f64 * self.tick;
            let (add, cover) = self.clocks(t);
            let mut rest = f64::INFINITY;
            for g in (0..goals).rev() {
                for &cell in &open {
                    rest = rest.min(self.at(cell, g as u16, t, full));
                }
                let later = out[g].0.get(j + 1).copied().unwrap_or(f64::INFINITY);
                out[g].0[j] = (add + rest).min(later);
                let later = out[g].1.get(j + 1).copied().unwrap_or(f64::INFINITY);
                out[g].1[j] = (cover + rest).min(later);
            }
        }
        out
    }
}

/// Sessions widened to whole tick intervals: from the first tick at or after each
/// start to the first at or after its end (empty where no tick falls inside).
fn on_ticks(sessions: &[(f64, f64)], tick: f64) -> Vec<(f64, f64)> {
    let up = |x: f64| (x / tick - 1e-9).ceil() * tick;
    sessions.iter().map(|&(a, b)| (up(a), up(b))).filter(|(a, b)| b > a).collect()
}

/// The time the rover may drive in: no drive overlaps a Communicate session
/// ([`ActionModel::with_sessions`]), so drives of `d` seconds from `t` end no earlier
/// than the instant by which `d` seconds outside the sessions have passed. A plan that
/// would cross a session's hours is so seen to stand through it, and to pay for it in
/// the bound (under Time, and in the deep night's and slow hours' costs under L + B).
struct FreeTime {
    /// The sessions, overlapping ones merged, sorted: (start, end), s after the epoch.
    sessions: Vec<(f64, f64)>,
    /// Per session, the sessions' time before its start, s; and last, all of it.
    before: Vec<f64>,
    /// Per session, the time outside sessions from the epoch to its start, s
    /// (non-decreasing).
    free_before: Vec<f64>,
}

impl FreeTime {
    fn new(sessions: &[(f64, f64)]) -> FreeTime {
        let mut merged: Vec<(f64, f64)> = Vec::with_capacity(sessions.len());
        for &(a, b) in sessions {
            match merged.last_mut() {
                Some(last) if a <= last.1 => last.1 = last.1.max(b),
                _ => merged.push((a, b)),
            }
        }
        let mut before = Vec::with_capacity(merged.len() + 1);
        before.push(0.0);
        for &(a, b) in &merged {
            before.push(before[before.len() - 1] + b - a);
        }
        let free_before = merged.iter().zip(&before).map(|(s, b)| s.0 - b).collect();
        FreeTime { sessions: merged, before, free_before }
    }

    /// The time outside sessions from the epoch to `t`, s.
    fn free_at(&self, t: f64) -> f64 {
        let k = self.sessions.partition_point(|s| s.0 < t);
        if k == 0 {
            return t;
        }
        let (a, b) = self.sessions[k - 1];
        t - self.before[k - 1] - (t.min(b) - a)
    }

    /// The earliest instant, s after the epoch, by which `d` seconds outside sessions
    /// have passed since `t`.
    fn after(&self, t: f64, d: f64) -> f64 {
        if d <= 0.0 {
            return t;
        }
        let target = self.free_at(t) + d;
        // The sessions that start before the free time reaches the target lie wholly
        // before the instant sought (the free time stands still through each).
        let k = self.free_before.partition_point(|&f| f < target);
        (target + self.before[k]).max(t)
    }
}

/// The earliest instant the battery can hold what the rest of the plan needs: the sources
/// less the loads over the span from the label's instant to the arrival must cover the
/// drives' loads ahead and what the battery must hold at the end, whatever the battery's
/// cap, which only makes it later.
///
/// Every instant of a plan lies in a stay or a drive. A stay gains at most what the array
/// at its best incidence on ground the rover may stand on and the generator give less
/// the charge load, or loses the sleeping load (the wait charges only where that drains
/// less); a drive draws each second at least the high electronics load (its base), and
/// its loads above that base are the [`LOAD`] row, summed over the cheapest way. So the
/// sources less the loads are at most the stays' rate over the whole span, less each
/// drive's penalty — the base less the array while driving, above the stays' rate, at
/// least `penalty_w` at any instant — over the drives' least duration, less the loads
/// above the base. (Where driving could gain more than staying, the rate is the larger of
/// the two and there is no penalty.) The array's bounds hold for any Sun on the arc to the
/// neighbouring table instants ([`solar_bounds`]). A label near the goal in the evening
/// without the battery to finish is seen to wait for the morning, and one with an empty
/// battery under a low Sun to bank what its drives will draw.
///
/// The efficiencies tighten it: each action's net bus energy x reaches the battery as
/// η_c·x when it charges and x / η_d when it draws, so with P the sum of the charging
/// nets and N of the drawing ones, the battery ends at e + η_c·P − N / η_d, at least the
/// hold. The sources less the loads over the span are P − N. If hold ≥ e, then
/// η_c·(P − N) ≥ hold − e + N·(1/η_d − η_c), so P − N ≥ (hold − e) / η_c; otherwise
/// N ≤ η_d·(e − hold + η_c·P), so P − N ≥ P·(1 − η_d·η_c) − η_d·(e − hold), at least
/// η_d·(hold − e). Energy quanta round each action's change on its own: with quanta the
/// bound counts only the sources (no loads, no efficiencies).
struct Harvest {
    /// The battery to hold above the floor at the last goal, Wh.
    hold_wh: f64,
    /// What a Wh short of the hold costs the sources less the loads, and what a Wh
    /// above it saves them: 1/η_c and η_d (1 and 1 with energy quanta).
    short_per_wh: f64,
    spare_per_wh: f64,
    /// What every drive draws each second at least, W (0 with energy quanta).
    base_w: f64,
    /// What a second of driving costs at least above a second of staying, W.
    penalty_w: f64,
    /// The Sun-table step, s, and at each table instant the most the sources less the
    /// loads can have given since the epoch, Wh, with its running maxima
    /// ([`Harvest::first_reaching`]).
    step_s: f64,
    given: Vec<f64>,
    maxima: Vec<Vec<f64>>,
}

impl Harvest {
    fn new(query: &ExactQuery<'_>) -> Harvest {
        let (world, model) = (query.world, query.model);
        let rover = model.rover();
        let exact = model.config().energy_quantum_wh <= 0.0;
        let draw = model.draw_factor();
        let power = |load: Load| if exact { rover.electronics.power_w(load) * draw } else { 0.0 };
        let (base_w, charge_w, sleep_w) =
            (power(Load::High), power(model.config().charge_load.load()), power(Load::Low));
        let (stay_w, drive_w) = solar_bounds(query);
        let interval = |v: &[f64], k: usize| v[k].max(v[k + 1]);
        let n = stay_w.len();
        let stay: Vec<f64> = (0..n.saturating_sub(1))
            .map(|k| (rover.nuclear_w + interval(&stay_w, k) - charge_w).max(rover.nuclear_w - sleep_w))
            .collect();
        let drive: Vec<f64> =
            (0..n.saturating_sub(1)).map(|k| rover.nuclear_w + interval(&drive_w, k) - base_w).collect();
        let least = stay.iter().zip(&drive).map(|(s, d)| s - d).fold(f64::INFINITY, f64::min);
        let penalty_w = if exact && least >= 0.0 { least } else { 0.0 };
        let step_s = world.sun_step_s();
        let mut given = Vec::with_capacity(n);
        given.push(0.0);
        for (s, d) in stay.iter().zip(&drive) {
            let w = if penalty_w > 0.0 { *s } else { s.max(*d) };
            given.push(given[given.len() - 1] + w * step_s / 3600.0);
        }
        let mut maxima = vec![given.clone()];
        while 1 << maxima.len() <= given.len() {
            let (last, half) = (&maxima[maxima.len() - 1], 1 << (maxima.len() - 1));
            maxima.push((0..given.len() + 1 - 2 * half).map(|i| last[i].max(last[i + half])).collect());
        }
        let battery = &rover.battery;
        Harvest {
            hold_wh: query.goal_energy_wh.max(0.0),
            short_per_wh: if exact { 1.0 / battery.charge_efficiency } else { 1.0 },
            spare_per_wh: if exact { battery.discharge_efficiency } else { 1.0 },
            base_w,
            penalty_w,
            step_s,
            given,
            maxima,
        }
    }

    /// The most the sources less the loads can have given from the epoch to `t`, Wh.
    fn given_at(&self, t: f64) -> f64 {
        sampled_at(&self.given, self.step_s, t)
    }

    /// The first table instant at or after index `from` at which `given` reaches
    /// `target`: the running maxima over blocks of 2^j instants skip each block that
    /// stays below it.
    fn first_reaching(&self, from: usize, target: f64) -> Option<usize> {
        let mut i = from;
        for j in (0..self.maxima.len()).rev() {
            if i + (1 << j) <= self.given.len() && self.maxima[j][i] < target {
                i += 1 << j;
            }
        }
        (i < self.given.len()).then_some(i)
    }

    /// The earliest a rover at `t` with `e` above the floor, whose drives ahead last at
    /// least `drive_s` and load it above their base with at least `load_wh`, can have
    /// what the rest of the plan needs, s (infinite: not within the Sun table).
    fn ready(&self, load_wh: f64, drive_s: f64, t: f64, e: f64) -> f64 {
        let short = self.hold_wh - e;
        let need = load_wh
            + self.penalty_w * drive_s / 3600.0
            + short * if short > 0.0 { self.short_per_wh } else { self.spare_per_wh };
        if need <= 0.0 {
            return t;
        }
        let (now, target) = (self.given_at(t), self.given_at(t) + need);
        let from = ((t / self.step_s).ceil().max(0.0) as usize).min(self.given.len());
        let Some(k) = self.first_reaching(from, target) else { return f64::INFINITY };
        // Linear between instants: the crossing lies after the last one below.
        let (t0, g0) = if k == from { (t, now) } else { ((k - 1) as f64 * self.step_s, self.given[k - 1]) };
        let (t1, g1) = (k as f64 * self.step_s, self.given[k]);
        let f = if g1 > g0 { ((target - g0) / (g1 - g0)).clamp(0.0, 1.0) } else { 1.0 };
        (t0 + (t1 - t0) * f).max(t)
    }
}

#[cfg(test)]
mod tests {
    use super::FreeTime;

    /// Two overlapping sessions, 100–200 s and 150–250 s (merged: 100–250 s), and one
    /// of 400–500 s: the free time passes around them.
    #[test]
    fn drives_end_after_the_free_time_they_need_has_passed() {
        let free = FreeTime::new(&[(100.0, 200.0), (150.0, 250.0), (400.0, 500.0)]);
        assert_eq!(free.after(0.0, 50.0), 50.0);
        // Exactly up to a session's start, then past it.
        assert_eq!(free.after(0.0, 100.0), 100.0);
        assert_eq!(free.after(0.0, 101.0), 251.0);
        // From inside a session: its rest first.
        assert_eq!(free.after(120.0, 10.0), 260.0);
        // Across the second session, or up to it.
        assert_eq!(free.after(300.0, 150.0), 550.0);
        assert_eq!(free.after(300.0, 100.0), 400.0);
        assert_eq!(free.after(600.0, 10.0), 610.0);
        assert_eq!(FreeTime::new(&[]).after(5.0, 10.0), 15.0);
    }
}
