//! TEMPEST as an ISE [`Domain`]: IPARMS are grid cells; a label carries the time t at
//! the cell (s after the epoch) and E, the least battery energy needed from there to
//! reach the goal (Wh above the battery's floor).
//!
//! Searching backward, an action that used Δe forward gives its predecessor
//! E' = max(E + Δe, peak) ([`Effect::required_before`], with `peak` ≥ 0 the most the
//! action draws from its start to any instant within): gains can bring E to zero,
//! which means "reachable even from an empty battery", never below; an action whose
//! drain after its fullest instant would not fit below the capacity is refused
//! ([`Effect::fits`]), and a path needing more than the usable capacity is abandoned
//! (the global constraint). The objective is the paper's composite L + B
//! (eqs. 3–5): every step costs Δe + E_max ≥ 0, with E_max a bound on the largest
//! single-step gain, so cost grows monotonically and BESTPCOST applies; or, for the
//! Arctic configuration, path duration under a maximum with "less required energy is
//! better" (BESTDPARMS).
//!
//! Labels are Pareto labels: at each (cell, time class) the search keeps every label
//! that no other dominates in (cost, E) — a label needing no more energy at no greater
//! cost dominates — so the labels a tight battery needs survive beside the cheapest
//! one. E is bucketed only when the scenario asks for energy classes, an approximation
//! the planner reports (see [`Resolution`] for what pruning guarantees).

use std::cell::RefCell;
use std::rc::Rc;

use areo_ise::{Domain, Predecessor};
use serde::{Deserialize, Serialize};

use crate::action_model::{Action, ActionModel, DriveGeometry, NEIGHBOURS};
use crate::effect::Effect;
use crate::landmark::{Edges, Landmark};
use crate::world::World;

/// A search label.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Label {
    /// Time at the cell, s after the epoch.
    pub t: f64,
    /// Least battery energy needed from here to reach the goal, Wh.
    pub e: f64,
}

/// What the search minimises.
///
/// Every objective's step cost is ≥ 0 and additive, and none depends on E, so Pareto
/// labels in (cost, E) stay sound under each.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Objective {
    /// The composite L + B of Tompkins et al. (BESTPCOST): fewest steps, then least
    /// energy.
    Energy,
    /// Time to the last goal (BESTPCOST on duration): the plan from its departure in
    /// the start window to its arrival at the last goal that takes least time, waits
    /// included.
    Time,
    /// Energy used (BESTPCOST on the loads' energy, [`crate::Effect::load_wh`]): the
    /// plan whose drives, charges and hibernations draw least, whatever the array gives
    /// back.
    EnergyUsed,
    /// Risk margin (BESTDPARMS, the paper's Arctic setting): among plans no longer than
    /// `max_duration_s`, the one that needs least battery at its start — the largest
    /// margin between the battery the rover has and the battery the plan needs. On a
    /// tick the margin is read forward: the plan whose battery at its lowest (inside
    /// actions too) stays highest, its cost the Wh drawn below the start battery there
    /// (ties: the earlier arrival). The two agree wherever the battery does not reach
    /// its cap before that lowest point; past a full charge the battery the rover
    /// holds at its worst moment is the margin a planner reads off the plot.
    #[serde(alias = "Duration")]
    Margin {
        /// The longest acceptable plan, s.
        max_duration_s: f64,
    },
}

impl Objective {
    /// The objective's name in scenarios and reports.
    pub fn name(self) -> &'static str {
        match self {
            Objective::Energy => "Energy",
            Objective::Time => "Time",
            Objective::EnergyUsed => "EnergyUsed",
            Objective::Margin { .. } => "Margin",
        }
    }
}

/// How the L term of the L + B objective counts a plan's length (eq. 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum PathLength {
    /// A drive counts its planar length in cells (a diagonal √2 of a straight step on
    /// square cells, the shorter cell side being one); a stationary action counts one.
    /// Zig-zags cost what they drive.
    #[default]
    Distance,
    /// The paper's eq. 4: every action counts one step, whatever its length.
    Steps,
}

impl PathLength {
    /// The share of L, in steps, of `action` on a grid of `dx` × `dy` m cells: ≥ 1 for
    /// every action, so every step's cost Δe + E_max·units stays ≥ 0.
    pub fn units(self, action: Action, dx: f64, dy: f64) -> f64 {
        match (self, action) {
            (PathLength::Distance, Action::Drive(k)) => {
                let (dc, dr) = NEIGHBOURS[k as usize % 8];
                (f64::from(dc) * dx).hypot(f64::from(dr) * dy) / dx.min(dy)
            }
            _ => 1.0,
        }
    }
}

/// Where and when a plan may start. The planner widens a window narrower than the
/// spacing of its goal instants to that spacing, so that some goal instant is reachable.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Start {
    /// Start cell.
    pub cell: u32,
    /// Earliest start, s after the epoch.
    pub t_min: f64,
    /// Latest start, s after the epoch.
    pub t_max: f64,
    /// Battery energy available at the start, Wh above the floor.
    pub energy_wh: f64,
}

/// Resolution of the label classes.
///
/// What pruning guarantees. At one cell, labels whose times fall in one class of
/// `time_s` are compared as if they were at one instant; every kept plan is evaluated
/// at the real times of its actions. Then:
/// - `energy_wh: None` (the default): E is a Pareto dimension, never bucketed — a label
///   is dropped only when another of its time class needs no more battery energy at no
///   greater cost (ties: the later time). No plan is lost for want of energy; the one
///   approximation is time (a dropped label's plan is represented by one up to
///   `time_s` earlier or later at that cell). With `time_s` no wider than the actions'
///   time quantum (and goal instants on that grid) a class holds one instant and the
///   search is exact.
/// - `energy_wh: Some(w)`: energy classes, an explicit approximation for speed — of the
///   labels of one (time class, energy class) the cheapest stands, so a kept label may
///   need up to `w` more energy than one it dropped, and a plan that only the dropped
///   label allowed can be lost. The planner reports the classes it used, and when it
///   finds no plan with them it searches again with E exact before it calls a goal
///   unreachable (reported as a fallback). `w` is at most half the usable battery, so E
///   is never collapsed to one class.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Resolution {
    /// Time class width, s.
    pub time_s: f64,
    /// Energy class width, Wh (`None`: E exact; see above).
    #[serde(default)]
    pub energy_wh: Option<f64>,
}

/// Energy classes per time class in a key (its low 24 bits).
const ENERGY_CLASSES: i64 = 1 << 24;

/// The TEMPEST search domain over a world and a rover.
#[derive(Debug, Clone)]
pub struct TempestDomain<'a> {
    world: &'a World,
    model: &'a ActionModel,
    /// The start. It may move (plan extension, start intervals); the search graph is
    /// kept, so nothing the engine prunes may depend on it: see `reachable_from`.
    pub start: Start,
    /// The start the domain was made with: a lower bound on reachable times that stays
    /// valid for every later start (a rover only reaches later starts from it, and the
    /// start intervals of a segment begin at its first one), so pruning with it never
    /// loses a label that a later start needs.
    reachable_from: (u32, f64),
    /// Whether the rover idles from the start window's opening to a start label's
    /// time (a real start: it is ready when the window opens), or arrives at the label's
    /// time (the start intervals of an intermediate goal: it reached the goal then, and
    /// idles for nothing before it).
    idles_before_start: bool,
    objective: Objective,
    resolution: Resolution,
    length: PathLength,
    /// Each drive direction's share of L, steps (see [`PathLength::units`]).
    drive_units: [f64; 8],
    e_max: f64,
    /// Lower bounds on the cost of a drive step east–west, north–south and diagonally
    /// (for the heuristic).
    step_floors: [f64; 3],
    capacity: f64,
    /// The geometry of the drives into each cell the search touched — shared by the
    /// segments of one mission, as it depends only on the world and the model.
    geometry: SharedGeometry,
    /// The cached 2-D lower bound on the cost from the first start to each cell (see
    /// [`crate::landmark`]).
    landmark: RefCell<Landmark>,
    /// The landmark's anchor: the start the domain was made with.
    anchor: u32,
    /// An upper bound on the sources while driving, W (for the landmark's drive costs).
    drive_source_w: f64,
    /// The cost of the time a plan must spend standing in the dark (see [`DarkCost`]).
    dark: Option<DarkCost>,
    /// Counts expansions for a progress display.
    meter: crate::planner::ExpansionMeter,
    /// The expansions the planning call may still make ([`Domain::exhausted`]).
    allowance: crate::planner::Allowance,
    /// The start window's close when the engine's keys were last brought up to date
    /// ([`Domain::heuristic_drop`]): the dark-time bound falls as it moves later.
    keyed_t_max: std::cell::Cell<f64>,
}

/// A lower bound on the cost of the time a plan spends in *deep night* — instants from
/// which the Sun is below the horizon for at least the longest action's duration either
/// way. With drives allowed only in daylight, every action that overlaps deep night is a
/// stay wholly in the dark, which costs at least E_max plus its load against the
/// generator (the array gains nothing); so from the start window's close to a label's
/// time the plan pays at least `rate` per second of deep night. Drives never overlap it,
/// so the bound adds to the drive-cost bounds (octile, landmark), and it is consistent:
/// a step's share of it is at most the step's cost. A plan that must wait out a night
/// is then seen to cost the night from anywhere — the spatial bounds alone let the
/// search spread as far as a night's cost reaches (valley-detour at four times the
/// area).
#[derive(Debug, Clone)]
pub(crate) struct DarkCost {
    /// Sun-table step, s.
    step_s: f64,
    /// The bound from t = 0 to each table instant, cost units.
    cumulative: Vec<f64>,
    /// The *time bound* from t = 0 to each table instant: the cost of any action is at
    /// least the integral, over its span, of the least cost per second an action there
    /// can have (`ActionModel::cost_rate_floor`, with the most the array can give in
    /// the Sun-table samples around) — so a plan pays at least the bound's rise from
    /// the start window's close to a label, drives or not. Stays in the day cost little
    /// only near noon; a label hours after the rover could be there is seen to cost
    /// the waiting.
    any: Vec<f64>,
}

impl DarkCost {
    pub(crate) fn new(
        world: &World,
        model: &ActionModel,
        objective: Objective,
        e_max: f64,
        drive_units: f64,
        drive_source_w: f64,
    ) -> Option<DarkCost> {
        if objective != Objective::Energy {
            return None;
        }
        let table = world.sun_table();
        if table.len() < 3 {
            return None;
        }
        let step_s = world.span_s() / (table.len() - 2) as f64;
        let stays = model.stays();
        let dark_rate = if model.config().drive.daylight {
            stays
                .iter()
                .map(|&a| {
                    (e_max * model.stay_units(a) + model.dark_stay_floor_wh(a)).max(0.0) / model.stay_duration_s(a)
                })
                .fold(f64::INFINITY, f64::min)
        } else {
            0.0
        };
        let dark_rate = if dark_rate.is_finite() { dark_rate.max(0.0) } else { 0.0 };
        let longest = stays.iter().map(|&a| model.stay_duration_s(a)).fold(model.longest_drive_s(world), f64::max);
        let reach = (longest / step_s).ceil() as usize + 1;
        // The stay that can charge: Charge, or a wait step.
        let charge_reach = (model.stay_duration_s(stays[0]) / step_s).ceil() as usize + 1;
        let drive_reach = (model.longest_drive_s(world) / step_s).ceil() as usize + 1;
        let dark: Vec<bool> = table.iter().map(|s| s.elevation_deg <= 0.0).collect();
        let mut cumulative = Vec::with_capacity(table.len());
        let mut any = Vec::with_capacity(table.len());
        cumulative.push(0.0);
        any.push(0.0);
        for k in 0..table.len() - 1 {
            // Every action overlapping the interval [k, k + 1] of the table lies within
            // `reach` samples of it; elevations and beams are interpolated linearly, so
            // the samples there bound them. The interval is deep night when the Sun is
            // down at every one of them.
            let (lo, hi) = (k.saturating_sub(reach), (k + 1 + reach).min(table.len() - 1));
            let deep = dark[lo..=hi].iter().all(|&d| d);
            cumulative.push(cumulative[k] + if deep { dark_rate * step_s } else { 0.0 });
            // Each kind of action is bounded over its own duration around the interval:
            // a charge's half hour sees less of a rising Sun than a two-hour window.
            let solar_within = |reach: usize| {
                let (lo, hi) = (k.saturating_sub(reach), (k + 1 + reach).min(table.len() - 1));
                table[lo..=hi].iter().map(|s| model.solar_peak_w(s.beam_w_m2)).fold(0.0, f64::max)
            };
            let solar_w = (solar_within(charge_reach), solar_within(drive_reach));
            let rate = model.cost_rate_floor(world, e_max, drive_units, solar_w, drive_source_w);
            any.push(any[k] + rate * step_s);
        }
        let useful = cumulative.last().is_some_and(|&c| c > 0.0) || any.last().is_some_and(|&c| c > 0.0);
        useful.then_some(DarkCost { step_s, cumulative, any })
    }

    fn interpolate(&self, table: &[f64], t: f64) -> f64 {
        sampled_at(table, self.step_s, t)
    }

    /// The dark-time bound from t = 0 to `t` (s after the epoch).
    pub(crate) fn at(&self, t: f64) -> f64 {
        self.interpolate(&self.cumulative, t)
    }

    /// The time bound from t = 0 to `t` (s after the epoch).
    pub(crate) fn any_at(&self, t: f64) -> f64 {
        self.interpolate(&self.any, t)
    }
}

/// A table sampled every `step_s` (at least two samples) at `t` s after the epoch,
/// linear between samples and clamped to its ends: the time bounds' clocks.
pub(crate) fn sampled_at(table: &[f64], step_s: f64, t: f64) -> f64 {
    let pos = (t / step_s).clamp(0.0, (table.len() - 1) as f64);
    let k = (pos as usize).min(table.len() - 2);
    let f = pos - k as f64;
    table[k] + (table[k + 1] - table[k]) * f
}

/// Drive geometries by arrival cell, computed on first use: the search expands a cell
/// once per time class it reaches there (dozens of times), and the geometry does not
/// depend on time. Paged like the engine's state table, so memory grows with the
/// region searched; cells the world reports changed are forgotten
/// ([`TempestDomain::forget`]).
#[derive(Debug, Clone, Default)]
pub(crate) struct GeometryCache {
    pages: Vec<Option<Box<[Into]>>>,
}

/// A drive-geometry cache shared by the domains of one world and one action model (a
/// mission's segments): on the 10 m lunar plan, four copies held 280 MB.
pub(crate) type SharedGeometry = Rc<RefCell<GeometryCache>>;

/// The 8 drives into one cell: `None` until computed, then each drive's source cell and
/// geometry (`None` where no drive is possible).
type Into = Option<[Option<(u32, DriveGeometry)>; 8]>;

const GEOMETRY_PAGE: usize = 256;

impl<'a> TempestDomain<'a> {
    /// The domain counting its expansions into `meter`.
    pub fn metered(mut self, meter: crate::planner::ExpansionMeter) -> TempestDomain<'a> {
        self.meter = meter;
        self
    }

    /// The domain spending its expansions from `allowance` (shared by the searches of one
    /// planning call): it stops the search when that is spent.
    pub(crate) fn allowing(mut self, allowance: crate::planner::Allowance) -> TempestDomain<'a> {
        self.allowance = allowance;
        self
    }

    /// The domain.
    pub fn new(
        world: &'a World,
        model: &'a ActionModel,
        start: Start,
        objective: Objective,
        resolution: Resolution,
        length: PathLength,
    ) -> TempestDomain<'a> {
        let (e_max, _) = model.gain_bounds(world);
        let (dx, dy) = (world.dem().dx(), world.dem().dy());
        let drive_units = std::array::from_fn(|k| length.units(Action::Drive(k as u8), dx, dy));
        // East–west, north–south and diagonal drives (directions 2, 0 and 1).
        let units = [drive_units[2], drive_units[0], drive_units[1]];
        let floors = model.drive_energy_floors_wh(world);
        let step_floors = std::array::from_fn(|i| (floors[i] + e_max * units[i]).max(0.0));
        TempestDomain {
            world,
            model,
            start,
            reachable_from: (start.cell, start.t_min),
            idles_before_start: true,
            objective,
            resolution,
            length,
            drive_units,
            e_max,
            step_floors,
            capacity: model.capacity_wh(),
            geometry: SharedGeometry::default(),
            landmark: RefCell::new(Landmark::new(start.cell)),
            anchor: start.cell,
            drive_source_w: model.drive_source_bound_w(world),
            dark: DarkCost::new(
                world,
                model,
                objective,
                e_max,
                drive_units.iter().copied().fold(f64::INFINITY, f64::min),
                model.drive_source_bound_w(world),
            ),
            keyed_t_max: std::cell::Cell::new(start.t_max),
            meter: crate::planner::ExpansionMeter::default(),
            allowance: crate::planner::Allowance::default(),
        }
    }

    /// The drives out of `from` that are possible at some time, each with the least its
    /// step can cost at any time (the landmark's graph). A drive's feasibility apart from
    /// time (map, passability, slopes) is symmetric, so whatever the landmark reaches
    /// can reach it back.
    fn floor_edges(&self, from: u32, out: Edges<'_>) {
        for k in 0..8u8 {
            if let Ok(g) = self.model.drive_geometry(self.world, from, k) {
                let cost = match self.objective {
                    Objective::Energy => {
                        let e = self.model.drive_energy_floor_wh(&g, self.drive_source_w);
                        (e + self.e_max * self.drive_units[k as usize]).max(0.0)
                    }
                    Objective::Time | Objective::Margin { .. } => g.duration_s,
                    Objective::EnergyUsed => self.model.drive_load_floor_wh(&g),
                };
                out.push((g.to, cost));
            }
        }
    }

    /// The landmark's bound on the cost from the current start to `state`: D(state) −
    /// D(start), when the landmark reaches both.
    fn landmark_bound(&self, state: u32) -> Option<f64> {
        let mut landmark = self.landmark.borrow_mut();
        let edges = |c: u32, out: Edges<'_>| self.floor_edges(c, out);
        let to = landmark.distance(state, edges)?;
        let from = landmark.distance(self.start.cell, edges)?;
        Some(to - from)
    }

    /// The octile bound on the cost from the current start to `state`: the per-direction
    /// floors of any drive, or the straight-line time at top speed.
    fn octile_bound(&self, state: u32) -> f64 {
        match self.objective {
            Objective::Energy => {
                // The cheapest way across the cell offsets with these step floors: as
                // many diagonals as possible if one is cheaper than its two straights.
                let ((c0, r0), (c1, r1)) = (self.world.col_row(state), self.world.col_row(self.start.cell));
                let (a, b) = ((c0 as f64 - c1 as f64).abs(), (r0 as f64 - r1 as f64).abs());
                let [wx, wy, wd] = self.step_floors;
                a * wx + b * wy + a.min(b) * (wd - wx - wy).min(0.0)
            }
            Objective::Time | Objective::Margin { .. } => {
                self.world.octile_m(state, self.start.cell) / self.model.top_speed_m_s(self.world)
            }
            // Any drive draws at least the least load over its time at top speed.
            Objective::EnergyUsed => {
                let wh = self.world.octile_m(state, self.start.cell) / self.model.top_speed_m_s(self.world)
                    * self.model.least_load_w()
                    / 3600.0;
                wh - 1e-9 * wh
            }
        }
    }

    /// What any plan costs between the start window's close and a label at `t`, where
    /// the objective counts time: its duration, or the least load over it.
    fn elapsed_bound(&self, t: f64) -> f64 {
        let elapsed = (t - self.start.t_max).max(0.0);
        match self.objective {
            Objective::Time => elapsed,
            Objective::EnergyUsed => {
                let wh = elapsed * self.model.least_load_w() / 3600.0;
                wh - 1e-9 * wh
            }
            Objective::Energy | Objective::Margin { .. } => 0.0,
        }
    }

    /// The dark-time bound from the start window's close to `t` (see [`DarkCost`]).
    fn dark_bound(&self, t: f64) -> f64 {
        self.dark.as_ref().map_or(0.0, |d| (d.at(t) - d.at(self.start.t_max)).max(0.0))
    }

    /// The time bound from the start window's close to `t` (see [`DarkCost`]).
    fn time_bound(&self, t: f64) -> f64 {
        self.dark.as_ref().map_or(0.0, |d| (d.any_at(t) - d.any_at(self.start.t_max)).max(0.0))
    }

    /// The rover is now at `start` (plan extension): it becomes the start, and the
    /// lower bound on reachable times is taken from it — never earlier than before, as
    /// the rover cannot outrun its top speed. Call [`areo_ise::Search::restrict`] next,
    /// so the kept graph drops the labels no longer reachable, as a fresh search would
    /// never make them.
    pub fn moved_to(&mut self, start: Start) {
        self.start = start;
        self.reachable_from = (start.cell, start.t_min);
        self.idles_before_start = true;
    }

    /// The earliest time the rover can be at `cell`: the first start plus the fastest
    /// travel from it, s after the epoch.
    fn earliest(&self, cell: u32) -> f64 {
        let (cell0, t0) = self.reachable_from;
        t0 + self.world.octile_m(cell, cell0) / self.model.top_speed_m_s(self.world)
    }

    /// The drives into `cell` (see [`GeometryCache`]).
    fn drives_into(&self, cell: u32) -> [Option<(u32, DriveGeometry)>; 8] {
        let mut cache = self.geometry.borrow_mut();
        let (page, slot) = (cell as usize / GEOMETRY_PAGE, cell as usize % GEOMETRY_PAGE);
        if cache.pages.len() <= page {
            cache.pages.resize_with(page + 1, || None);
        }
        let entry = &mut cache.pages[page].get_or_insert_with(|| vec![None; GEOMETRY_PAGE].into_boxed_slice())[slot];
        *entry.get_or_insert_with(|| std::array::from_fn(|k| self.model.drive_geometry_into(self.world, cell, k as u8)))
    }

    /// Forgets the cached drive geometry around `changed` cells (their elevation, slope
    /// or passability changed, so every drive into or out of them may have) and repairs
    /// the landmark where drives became cheaper. The planner calls this with the cells
    /// it reports to the search. Returns a bound on how far the heuristic of any label
    /// fell, for [`areo_ise::Search::heuristic_fell`].
    pub fn forget(&mut self, changed: &[u32]) -> Option<f64> {
        if changed.is_empty() {
            return Some(0.0);
        }
        self.forget_geometry(changed);
        if self.start.cell == self.anchor {
            // The rover is where the map is anchored: the map is repaired where drives
            // got cheaper and the fall is bounded, so the engine keeps its open list.
            // (Where they got dearer the old bound stays: looser, still a bound.)
            let fall = self.landmark.borrow_mut().lower(
                changed,
                |c, out| self.successors(c, out),
                |c, out: Edges<'_>| self.floor_edges(c, out),
            );
            return Some(fall);
        }
        // The rover has moved on: the map is made again from where it now is, as tight
        // as a fresh search's. Its fall cannot be bounded from the old map's distances
        // (they were from another anchor), so the engine keys its open list again.
        self.anchor = self.start.cell;
        let landmark = Landmark::new(self.anchor);
        *self.landmark.get_mut() = landmark;
        None
    }

    fn forget_geometry(&self, changed: &[u32]) {
        let mut cache = self.geometry.borrow_mut();
        let mut around = Vec::with_capacity(9);
        for &cell in changed {
            around.clear();
            // The cell and its neighbours on the map.
            self.successors(cell, &mut around);
            for &n in &around {
                if let Some(Some(page)) = cache.pages.get_mut(n as usize / GEOMETRY_PAGE) {
                    page[n as usize % GEOMETRY_PAGE] = None;
                }
            }
        }
    }

    /// Bytes held by the drive-geometry cache and the landmark.
    pub fn cache_bytes(&self) -> usize {
        self.geometry_bytes() + self.landmark_bytes()
    }

    /// Bytes held by the drive-geometry cache (which segments may share).
    pub(crate) fn geometry_bytes(&self) -> usize {
        let cache = self.geometry.borrow();
        cache.pages.iter().flatten().count() * GEOMETRY_PAGE * std::mem::size_of::<Into>()
            + cache.pages.capacity() * std::mem::size_of::<Option<Box<[Into]>>>()
    }

    /// Bytes held by the landmark.
    pub(crate) fn landmark_bytes(&self) -> usize {
        self.landmark.borrow().bytes()
    }

    /// The battery a start label at `state` needs when the window opens: at a real
    /// start the rover idles from the window's opening to the plan's start (asleep, or
    /// waiting where it waits — charging where lit); at an intermediate goal it arrives
    /// at the label's time.
    fn needed_at_start(&self, state: u32, label: &Label) -> f64 {
        if !self.idles_before_start {
            return label.e;
        }
        let idle_s = label.t - self.start.t_min;
        match self.model.idle_wait(self.world, state, self.start.t_min, idle_s) {
            Some(w) if w.fits(label.e, self.capacity) => w.required_before(label.e),
            Some(_) => f64::INFINITY,
            None => label.e + self.model.idle_wh(idle_s),
        }
    }

    /// The domain of a segment that starts at an intermediate goal: its start labels
    /// are arrivals there, at their own time, so the battery a way on needs is compared
    /// with the battery whole — not less an idle from the interval's opening, which
    /// would refuse a way on that needs a full battery unless it left exactly at the
    /// opening. [`TempestDomain::moved_to`] (the rover is there) undoes it.
    pub(crate) fn arriving(mut self) -> TempestDomain<'a> {
        self.idles_before_start = false;
        self
    }

    /// The domain, with its drive geometries kept in `cache` (the same world and action
    /// model's, else the geometries would be wrong).
    pub(crate) fn sharing_geometry(mut self, cache: &SharedGeometry) -> TempestDomain<'a> {
        self.geometry = Rc::clone(cache);
        self
    }

    /// E_max used by the objective, Wh.
    pub fn e_max_wh(&self) -> f64 {
        self.e_max
    }

    /// The objective.
    pub fn objective(&self) -> Objective {
        self.objective
    }

    /// How L counts length.
    pub fn path_length(&self) -> PathLength {
        self.length
    }

    /// The cost of `action` when it used `energy_wh` over `duration_s`: Δe + E_max × its
    /// share of L (eqs. 3–5), or its duration.
    pub fn step_cost(&self, action: Action, effect: Effect) -> f64 {
        let Effect { energy_wh, duration_s, load_wh, .. } = effect;
        match self.objective {
            Objective::Energy => {
                let units = match action {
                    Action::Drive(k) => self.drive_units[k as usize % 8],
                    stay => self.model.stay_units(stay),
                };
                (energy_wh + self.e_max * units).max(0.0)
            }
            Objective::Time | Objective::Margin { .. } => duration_s,
            Objective::EnergyUsed => load_wh,
        }
    }

    /// The search mode for this objective.
    pub fn mode(&self) -> areo_ise::Mode {
        match self.objective {
            Objective::Energy | Objective::Time | Objective::EnergyUsed => areo_ise::Mode::BestPathCost,
            Objective::Margin { max_duration_s } => areo_ise::Mode::BestDparms { max_cost: max_duration_s },
        }
    }

    /// The predecessor label reached backward through `action` with `effect`, and the
    /// step's cost.
    fn step(&self, from: u32, label: &Label, action: Action, effect: Effect) -> Predecessor<Self> {
        // The battery must stay above the floor inside the action too, and what the
        // action draws after its fullest instant must fit below the capacity: a step
        // that cannot carry `label.e` to its end needs more than the battery holds.
        let e = if effect.fits(label.e, self.capacity) { effect.required_before(label.e) } else { f64::INFINITY };
        let t = label.t - effect.duration_s;
        let mut cost = self.step_cost(action, effect);
        if !matches!(action, Action::Drive(_)) {
            // Among plans of equal cost, wait as late as possible: a rover that re-plans
            // after every action and always finds the wait first would never set off.
            // The bias is a millionth of a step and shrinks to zero over the horizon.
            let scale = match self.objective {
                Objective::Energy => self.e_max * self.model.stay_units(action),
                Objective::Time | Objective::Margin { .. } => effect.duration_s,
                Objective::EnergyUsed => effect.load_wh,
            };
            cost += 1e-6 * scale * (1.0 - t / self.world.span_s()).clamp(0.0, 1.0);
        }
        Predecessor { state: from, label: Label { t, e }, cost }
    }

    /// [`Domain::expand`], returning whether a drive could arrive at (`state`,
    /// `label.t`) — `None` when no drive was wanted, so it was not asked.
    fn expand_arriving(
        &self,
        state: u32,
        label: &Label,
        wanted: impl Fn(Action) -> bool,
        mut visit: impl FnMut(Action, Predecessor<Self>),
    ) -> Option<bool> {
        self.meter.add(1);
        self.allowance.spend();
        let mut arrives = None;
        if (0..8).any(|k| wanted(Action::Drive(k))) {
            let arrival = self.model.arrival(self.world, state, label.t);
            arrives = Some(arrival.is_some());
            if let Some(arrival) = arrival {
                for (k, drive) in (0..8).zip(self.drives_into(state)) {
                    if wanted(Action::Drive(k))
                        && let Some((from, geometry)) = drive
                        && let Some((from, effect)) = self.model.drive_into(self.world, &arrival, k, from, geometry)
                    {
                        visit(Action::Drive(k), self.step(from, label, Action::Drive(k), effect));
                    }
                }
            }
        }
        for &stay in self.model.stays() {
            if wanted(stay)
                && let Ok(effect) = self.model.stay(self.world, stay, state, label.t - self.model.stay_duration_s(stay))
            {
                visit(stay, self.step(state, label, stay, effect));
            }
        }
        arrives
    }
}

impl Domain for TempestDomain<'_> {
    type State = u32;
    type Label = Label;
    type Key = i64;
    type Move = Action;
    // A cell collects hundreds of time classes; dominance is tested only within one
    // (its dominance group), among the few Pareto labels that survive there.
    const MANY_LABELS: bool = true;
    const DOMINANCE: bool = true;

    /// The 8 drives share their arrival (the Sun at `label.t`, the light and checks at
    /// this cell), computed once and only if a drive is wanted; then Charge and
    /// Hibernate.
    fn expand(
        &self,
        state: u32,
        label: &Label,
        wanted: impl Fn(Action) -> bool,
        visit: impl FnMut(Action, Predecessor<Self>),
    ) {
        self.expand_arriving(state, label, wanted, visit);
    }

    /// Whether no drive can arrive: the arrival's checks are this cell's alone (its
    /// slope, its light at this time), so they stand until sensing changes the cell.
    fn expand_all(&self, state: u32, label: &Label, visit: impl FnMut(Action, Predecessor<Self>)) -> bool {
        self.expand_arriving(state, label, |_| true, visit) == Some(false)
    }

    fn predecessor_state(&self, state: u32, action: Action) -> Option<u32> {
        match action {
            Action::Drive(k) => {
                let (c, r) = self.world.col_row(state);
                let (dc, dr) = NEIGHBOURS[k as usize % 8];
                let (pc, pr) = (c as i64 - i64::from(dc), r as i64 - i64::from(dr));
                let inside =
                    pc >= 0 && pr >= 0 && (pc as usize) < self.world.cols() && (pr as usize) < self.world.rows();
                // Off the map: no drive; the transition says so.
                inside.then(|| self.world.cell(pc as usize, pr as usize))
            }
            _ => Some(state),
        }
    }

    fn lands_in(&self, state: u32, pred: u32) -> impl Fn(&Label, i64) -> bool {
        // A step from a label at `state` into `pred` starts at the label's time less
        // its duration: the stays' fixed durations, or the one drive from `pred` into
        // `state` (none: nothing lands). Compared by time class: the energy class of
        // the step depends on E.
        let durations: [Option<f64>; 2] = if pred == state {
            let stays = self.model.stays();
            [stays.first(), stays.get(1)].map(|a| a.map(|&a| self.model.stay_duration_s(a)))
        } else {
            let drive = self.drives_into(state).into_iter().flatten().find(|&(from, _)| from == pred);
            [drive.map(|(_, g)| g.duration_s), None]
        };
        let time_s = self.resolution.time_s;
        move |label: &Label, key: i64| {
            durations.iter().flatten().any(|d| ((label.t - d) / time_s).floor() as i64 == key >> 24)
        }
    }

    fn successors(&self, state: u32, out: &mut Vec<u32>) {
        let (c, r) = self.world.col_row(state);
        for (dc, dr) in NEIGHBOURS {
            let (nc, nr) = (c as i64 + i64::from(dc), r as i64 + i64::from(dr));
            if nc >= 0 && nr >= 0 && (nc as usize) < self.world.cols() && (nr as usize) < self.world.rows() {
                out.push(self.world.cell(nc as usize, nr as usize));
            }
        }
        out.push(state);
    }

    fn key(&self, _state: u32, label: &Label) -> i64 {
        // Time class in the high bits, energy class (if any) in the low 24.
        let t = (label.t / self.resolution.time_s).floor() as i64;
        let e = match self.resolution.energy_wh {
            Some(w) => ((label.e / w).floor() as i64).clamp(0, ENERGY_CLASSES - 1),
            None => 0,
        };
        (t << 24) | e
    }

    fn dominance_group(&self, _state: u32, key: i64) -> i64 {
        // The time class.
        key & !(ENERGY_CLASSES - 1)
    }

    fn pareto_classes(&self) -> bool {
        self.resolution.energy_wh.is_none()
    }

    fn dominates(&self, _state: u32, a: &Label, cost_a: f64, b: &Label, cost_b: f64) -> bool {
        // Called within a time class only. Completions toward the start depend on the
        // label's time (exactly when a class holds one instant) and on E only through
        // E' = max(E + Δe, peak), the capacity check and the start's battery, all monotone in E;
        // step costs do not depend on E. Equal in both, the later label stands (a
        // rover can reach a cell later more easily than earlier), so which one is kept
        // does not depend on the order they came in.
        a.e <= b.e && cost_a <= cost_b && (a.e < b.e || cost_a < cost_b || a.t >= b.t)
    }

    fn stands_in_for(&self, _state: u32, better: &Label, beaten: &Label) -> bool {
        // At the same instant every step has the same time, effect and cost from both,
        // and E' = max(E + Δe, peak) keeps the order of E: each step from `better`
        // dominates the matching step from `beaten`. At another instant of the same
        // class the steps differ, so the beaten subtree must go.
        better.t.to_bits() == beaten.t.to_bits()
    }

    fn within_global(&self, state: u32, label: &Label, _cost: f64) -> bool {
        // A label is kept while its time class holds an instant the rover can still
        // reach: the first start plus the fastest travel from it (not the current
        // start: a label pruned for a late start interval would be lost to an earlier
        // one, as the engine keeps its graph). Whole classes, as the search compares
        // labels: when the rover moves on, what `Search::restrict` drops are classes
        // no reachable label can be in, so nothing it pruned needs making again — a
        // fresh search keeps the same labels. Labels before that instant in its class
        // stay in the graph, set aside as dormant if the search reaches them.
        label.e <= self.capacity + 1e-9 && self.class_within_global(state, self.key(state, label))
    }

    fn class_within_global(&self, state: u32, key: i64) -> bool {
        // The time class [kΔ, (k+1)Δ) holds a reachable instant.
        ((key >> 24) + 1) as f64 * self.resolution.time_s > self.earliest(state) - 1e-6
    }

    fn exhausted(&self) -> bool {
        self.allowance.exhausted()
    }

    fn outgrown(&self, graph_bytes: u64) -> bool {
        self.allowance.outgrown(graph_bytes + (self.geometry_bytes() + self.landmark_bytes()) as u64)
    }

    fn compared(&self, labels: u64) {
        self.meter.add_work(self.allowance.compared(labels));
    }

    fn is_start(&self, state: u32, label: &Label) -> bool {
        state == self.start.cell
            && label.t >= self.start.t_min - 1e-9
            && label.t <= self.start.t_max + 1e-9
            && self.needed_at_start(state, label) <= self.start.energy_wh + 1e-9
    }

    fn start_state(&self) -> Option<u32> {
        Some(self.start.cell)
    }

    fn dense_index(&self, state: u32) -> Option<u32> {
        Some(state)
    }

    fn heuristic(&self, state: u32, label: &Label) -> f64 {
        // The larger of two bounds that each obey the triangle inequality over the
        // drives: the octile floors (terrain-blind) and the landmark (which knows walls
        // and slopes, but loosens behind its anchor) — both on drives — plus the cost
        // of the deep night between the start and the label, which only stays pay; or
        // the time bound (what any actions filling the time since the start cost at
        // least), where that is larger.
        let octile = self.octile_bound(state);
        let drives = self.landmark_bound(state).map_or(octile, |l| octile.max(l));
        (drives + self.dark_bound(label.t)).max(self.time_bound(label.t)).max(self.elapsed_bound(label.t))
    }

    fn heuristic_drop(&self, previous: u32) -> Option<f64> {
        // The start moved from `previous`. The octile bound falls by at most the octile
        // bound between the two starts; the landmark's D(s) − D(start) by D(start) −
        // D(previous). A landmark that reached the old start but not the new one would
        // lose its term everywhere: unknown.
        let octile = self.octile_bound(previous);
        // The dark-time bound counts from the start window's close: it falls as that
        // moves later.
        let keyed = self.keyed_t_max.replace(self.start.t_max);
        let (dark, time) = self.dark.as_ref().map_or((0.0, 0.0), |d| {
            ((d.at(self.start.t_max) - d.at(keyed)).max(0.0), (d.any_at(self.start.t_max) - d.any_at(keyed)).max(0.0))
        });
        let mut landmark = self.landmark.borrow_mut();
        let edges = |c: u32, out: Edges<'_>| self.floor_edges(c, out);
        let (before, now) = (landmark.distance(previous, edges), landmark.distance(self.start.cell, edges));
        // The elapsed-time bound counts from the window's close too.
        let elapsed = self.elapsed_bound(self.start.t_max + (self.start.t_max - keyed).max(0.0));
        // The heuristic is max(drives + dark, time, elapsed): it falls by at most the
        // largest of the falls.
        match (before, now) {
            (Some(b), Some(n)) => Some((octile.max(n - b) + dark).max(time).max(elapsed)),
            (Some(_), None) => None,
            (None, _) => Some((octile + dark).max(time).max(elapsed)),
        }
    }

    fn dormant(&self, state: u32, label: &Label) -> Option<f64> {
        // The latest start from which the rover could still be here at `label.t`,
        // driving straight at top speed: a label of a later window's start can never
        // be reached — nor can anything searched behind it (earlier, and farther).
        let latest =
            label.t - self.world.octile_m(state, self.start.cell) / self.model.top_speed_m_s(self.world) + 1e-6;
        (latest < self.start.t_min).then_some(latest)
    }

    fn release_threshold(&self) -> f64 {
        self.start.t_min
    }

    fn release_drift(&self, previous: u32) -> f64 {
        // The latest-start bound moves by at most the fastest travel between the starts.
        self.world.octile_m(previous, self.start.cell) / self.model.top_speed_m_s(self.world)
    }

    fn better(&self, a: &Label, b: &Label) -> bool {
        a.e < b.e
    }
}
