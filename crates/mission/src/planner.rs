//! Planning to one or more goals (Tompkins et al., "Specifying Start and Goal States",
//! "Multiple-Goal Planning", "Plan Extension", "Re-Planning").
//!
//! Goal and start windows come from best- and worst-case durations: the fastest
//! straight-line travel, and the detoured slowest travel plus the longest wait allowed.
//! Segments are planned backward from the last goal (Figure 3). The last segment's goals
//! are even instants of its goal window; its start window at the previous goal is split
//! into even intervals, one search per interval (the same ISE graph, re-pointed at each
//! interval: identical answers, less work), each giving a candidate (start label, cost,
//! path). The candidates become the goals, with their costs carried, of the segment
//! before, and so on down to the first segment and the rover's start. The chain from
//! the start is the optimum over this discretisation.
//!
//! Re-planning keeps every segment's graph. After a world change, every segment is
//! told which cells changed; segments are re-planned from the latest one whose graph
//! the change touched, backward, and a segment whose goals (the next segment's
//! candidates) changed has its graph repaired around the changed goals.

mod front;
mod problem;
mod tick;
mod verdict;
mod work;

pub use front::{FrontPlan, ParetoFront, non_dominated};
use problem::check_problem;
pub(crate) use work::Allowance;
pub use work::ExpansionMeter;

use std::rc::Rc;

use areo_ise::{Goal, PathStep, Search, Stats};
use serde::{Deserialize, Serialize};

use crate::action_model::{Action, ActionConfig, ActionModel};
use crate::domain::{Label, Objective, PathLength, Resolution, SharedGeometry, Start, TempestDomain};
use crate::error::{Error, Result};
use crate::plan::{MissionPlan, Waypoint};
use crate::world::World;

/// Which search a mission plans with, and the settings only that search reads.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum SearchMode {
    /// Exactly at one time step ([`crate::exact`]): drives depart on ticks, waits end on
    /// them, the energy exact, goals reached at any instant of their windows — every
    /// planning call one exact search, so the plan is optimal over every such plan,
    /// "unreachable" is a proof at the tick and a re-plan is what a fresh search
    /// returns. The rover must wait in steps of the tick
    /// ([`ActionConfig::wait_step_s`]).
    Exact {
        /// The tick, s (1..=86400).
        tick_s: f64,
    },
    /// The paper's search over time and energy classes and goal instants (its plan may
    /// cost more than the optimum, and its "unreachable" is no proof).
    Approximate(Classes),
}

impl SearchMode {
    /// The tick of the exact search, s (`None`: the approximate search).
    pub fn tick_s(&self) -> Option<f64> {
        match self {
            SearchMode::Exact { tick_s } => Some(*tick_s),
            SearchMode::Approximate(_) => None,
        }
    }

    /// The approximate search's settings (`None`: the exact search).
    pub fn classes(&self) -> Option<&Classes> {
        match self {
            SearchMode::Exact { .. } => None,
            SearchMode::Approximate(classes) => Some(classes),
        }
    }
}

/// The approximate search's settings: its classes, goal instants, start intervals and
/// retries.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Classes {
    /// Label class widths for resolution pruning (see [`Resolution`]).
    pub resolution: Resolution,
    /// Goal instants spread over the final goal window.
    pub goal_times: usize,
    /// Start intervals per intermediate goal (multi-goal chaining).
    pub segment_starts: usize,
    /// How many times to search again with the time classes halved (after the
    /// energy-exact search) when the settings find no plan (0..=6; default 0).
    /// Narrower classes merge fewer instants, so they find plans wider ones miss. With
    /// continuous action times (`time_quantum_s` 0 or under 1 s) that is all there is
    /// before "unreachable", and no width is exact, so it is not a guarantee that a
    /// finer setting keeps a plan (docs/tempest.md). With quantised actions the
    /// retries (never at classes of one quantum or narrower) come before the last
    /// resort exact at the quanta, which then runs only if they too find nothing: the
    /// guarantee is the last resort's, the retries make a plan cheaper to find. A plan
    /// found so is at the narrower classes ([`MissionPlan::time_classes_s`]).
    pub unreachable_retries: u32,
}

impl Default for Classes {
    fn default() -> Classes {
        Classes {
            resolution: Resolution { time_s: 60.0, energy_wh: None },
            goal_times: 24,
            segment_starts: 8,
            unreachable_retries: 0,
        }
    }
}

/// Planner parameters (scenario fields).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlannerConfig {
    /// Actions and their constraints.
    pub actions: ActionConfig,
    /// What to minimise.
    pub objective: Objective,
    /// How the objective's L counts length (see [`PathLength`]).
    pub path_length: PathLength,
    /// Worst-case path length as a multiple of the straight-line distance.
    pub detour_factor: f64,
    /// Longest total wait (charging, hibernating) the worst case allows, s; default
    /// (`None`) one solar day of the world's body (a sol on Mars, a synodic month on
    /// the Moon, a day on the Earth).
    pub max_wait_s: Option<f64>,
    /// Least battery energy on arrival at the last goal, Wh above the floor.
    pub goal_energy_wh: f64,
    /// Which search plans, with what only it reads ([`SearchMode`]).
    pub search: SearchMode,
    /// Counts the searches' expansions as they happen, for a progress display (not a
    /// scenario field; no effect on the plan).
    #[serde(skip)]
    pub meter: ExpansionMeter,
    /// The most work one planning call ([`Mission::plan`], [`Mission::advance`],
    /// [`Mission::replan`], …) may do over all its searches — the finer-class retries
    /// and the binding-constraint probes included — in label expansions, every hundred
    /// labels a new one is compared with in its Pareto front counting one more
    /// ([`ExpansionMeter::work`]). A call that
    /// reaches it stops with [`Error::WorkLimit`]: no plan, and no proof that none
    /// exists. `None`: no limit. Not a scenario field: the run's work budget sets it.
    #[serde(skip)]
    pub max_expansions: Option<u64>,
    /// The most memory the search graphs of one planning call may hold, bytes: the
    /// mission's graphs, their drive-geometry and landmark caches, and — while a probe
    /// or a fresh comparison runs beside it — the mission's own. Checked every
    /// [`areo_ise::MEMORY_CHECK_EVERY`] expansions; a call that reaches it stops with
    /// [`Error::MemoryLimit`]: no plan, and no proof that none exists. `None`: no
    /// limit. Not a scenario field: the run's memory budget sets it.
    #[serde(skip)]
    pub max_search_bytes: Option<u64>,
}

impl Default for PlannerConfig {
    fn default() -> PlannerConfig {
        PlannerConfig {
            actions: ActionConfig::default(),
            objective: Objective::Energy,
            path_length: PathLength::Distance,
            detour_factor: 1.5,
            max_wait_s: None,
            goal_energy_wh: 0.0,
            search: SearchMode::Approximate(Classes::default()),
            meter: ExpansionMeter::default(),
            max_expansions: None,
            max_search_bytes: None,
        }
    }
}

impl PlannerConfig {
    /// Checks the actions' ranges, naming the first bad field.
    fn validate_actions(&self) -> Result<()> {
        let bad = |field: &'static str, message: String| Err(Error::Config { field, message });
        let a = &self.actions;
        if let SearchMode::Exact { tick_s } = self.search
            && !(1.0..=86_400.0).contains(&tick_s)
        {
            return bad("tick_s", format!("{tick_s}: allowed 1..=86400 s"));
        }
        // Physical ranges: a step of a second to days, classes that a search can hold.
        if !((1.0..=1e6).contains(&a.charge_s) && (1.0..=1e6).contains(&a.hibernate_s)) {
            return bad("actions.charge_s", "charge_s and hibernate_s: allowed 1..=1e6 s".into());
        }
        if let Some(w) = a.wait_step_s
            && !(1.0..=86_400.0).contains(&w)
        {
            return bad(
                "actions.wait_step_s",
                format!("{w}: allowed 1..=86400 s (or None: the paper's Charge and Hibernate)"),
            );
        }
        if !(a.time_quantum_s == 0.0 || (1e-3..=86_400.0).contains(&a.time_quantum_s)) {
            return bad(
                "actions.time_quantum_s",
                format!("{}: allowed 0 (exact) or 0.001..=86400 s", a.time_quantum_s),
            );
        }
        if !(a.energy_quantum_wh == 0.0 || (1e-6..=1e6).contains(&a.energy_quantum_wh)) {
            return bad(
                "actions.energy_quantum_wh",
                format!("{}: allowed 0 (exact) or 1e-6..=1e6 Wh", a.energy_quantum_wh),
            );
        }
        if let Some(m) = a.max_slope_deg
            && !(m > 0.0 && m < 90.0)
        {
            return bad("actions.max_slope_deg", format!("{m}: allowed 0..90 degrees"));
        }
        Ok(())
    }

    /// Checks ranges, naming the first bad field.
    pub fn validate(&self) -> Result<()> {
        let bad = |field: &'static str, message: String| Err(Error::Config { field, message });
        self.validate_actions()?;
        if let SearchMode::Approximate(classes) = &self.search {
            classes.validate(self.actions.wait_step_s)?;
        }
        if !(0.0..=1e7).contains(&self.goal_energy_wh) {
            return bad("goal_energy_wh", format!("{}: allowed 0..=1e7 Wh", self.goal_energy_wh));
        }
        if !(1.0..=100.0).contains(&self.detour_factor) {
            return bad("detour_factor", format!("{}: allowed 1..=100", self.detour_factor));
        }
        if let Some(w) = self.max_wait_s
            && !(0.0..=1e7).contains(&w)
        {
            return bad("max_wait_s", format!("{w}: allowed 0..=1e7 s"));
        }
        if let Objective::Margin { max_duration_s } = self.objective
            && !(max_duration_s > 0.0 && max_duration_s <= 1e8)
        {
            return bad("objective.max_duration_s", format!("{max_duration_s}: allowed 0 (exclusive)..=1e8 s"));
        }
        Ok(())
    }
}

impl Classes {
    /// Checks ranges beside the rover's wait step (s), naming the first bad field.
    fn validate(&self, wait_step_s: Option<f64>) -> Result<()> {
        let bad = |field: &'static str, message: String| Err(Error::Config { field, message });
        if !(1.0..=1e6).contains(&self.resolution.time_s) {
            return bad("resolution.time_s", format!("{}: allowed 1..=1e6 s", self.resolution.time_s));
        }
        if let Some(w) = wait_step_s
            && w < self.resolution.time_s
        {
            // Labels of one time class are compared as one instant: a wait step inside a
            // class looks like no wait at all and costs more, so the search drops it and
            // the rover could never wait out a night.
            return bad(
                "actions.wait_step_s",
                format!(
                    "{w} s is shorter than the time classes (`resolution.time_s` {} s): allowed at least time_s",
                    self.resolution.time_s
                ),
            );
        }
        if !(1..=10_000).contains(&self.goal_times) {
            return bad("goal_times", format!("{}: allowed 1..=10000", self.goal_times));
        }
        if !(1..=10_000).contains(&self.segment_starts) {
            return bad("segment_starts", format!("{}: allowed 1..=10000", self.segment_starts));
        }
        if self.unreachable_retries > 6 {
            return bad("unreachable_retries", format!("{}: allowed 0..=6", self.unreachable_retries));
        }
        if self.resolution.time_s / 2f64.powi(self.unreachable_retries as i32) < 1.0 {
            return bad(
                "unreachable_retries",
                format!(
                    "{}: time classes of {} s halved that often are under 1 s (allowed: at least 1 s)",
                    self.unreachable_retries, self.resolution.time_s
                ),
            );
        }
        Ok(())
    }
}

/// A candidate path of one segment: from one of its start labels to one of its goals.
#[derive(Debug, Clone)]
struct Candidate {
    start: Label,
    cost: f64,
    path: Vec<PathStep<TempestDomain<'static>>>,
}

/// One segment: its search graph and its candidates.
struct Segment<'a> {
    from: u32,
    to: u32,
    domain: TempestDomain<'a>,
    search: Search<TempestDomain<'a>>,
    goals: Vec<(Label, f64)>,
    /// Start intervals (for all segments but the first).
    intervals: Vec<(f64, f64)>,
    candidates: Vec<Candidate>,
    stats: Stats,
}

impl std::fmt::Debug for Segment<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Segment")
            .field("from", &self.from)
            .field("to", &self.to)
            .field("goals", &self.goals.len())
            .field("candidates", &self.candidates.len())
            .finish()
    }
}

/// A planned mission to an ordered list of goals, kept for plan extension and
/// re-planning.
#[derive(Debug)]
pub struct Mission<'a> {
    world: &'a World,
    model: &'a ActionModel,
    config: PlannerConfig,
    start: Start,
    goals: Vec<u32>,
    segments: Vec<Segment<'a>>,
    /// The drive geometries, shared by every segment's domain.
    geometry: SharedGeometry,
    /// The last-resort search at the quanta (see [`Mission::finer_classes`]): the goal
    /// instants of every smaller `goal_times`, one start interval per quantum at each
    /// intermediate goal, and a staircase of candidates in each (see `solve_from`).
    last_resort: bool,
    /// The start window's close as given, before widening, s.
    given_t_max: f64,
    /// The time class width the start window was widened for, s (the configured one:
    /// the last resort keeps it).
    widened_for_s: f64,
    /// The expansions the current planning call may still make.
    allowance: Allowance,
    /// The approximate search's classes as this search uses them (finer than the
    /// configured ones after a try found no plan; unused on a tick).
    classes: Classes,
    /// On a tick ([`SearchMode::Exact`]): the tick, the kept windows and last plan.
    tick: Option<tick::TickState>,
}

fn goal_list(goals: &[(Label, f64)], cell: u32) -> Vec<Goal<TempestDomain<'static>>> {
    goals.iter().map(|&(label, cost)| Goal { state: cell, label, cost }).collect()
}

// The ISE types only carry labels, states and actions: a path or goal of one domain
// lifetime is a path or goal of any other.
fn relabel_goals<'a>(g: Vec<Goal<TempestDomain<'static>>>) -> Vec<Goal<TempestDomain<'a>>> {
    g.into_iter().map(|g| Goal { state: g.state, label: g.label, cost: g.cost }).collect()
}

fn own_path(p: Vec<PathStep<TempestDomain<'_>>>) -> Vec<PathStep<TempestDomain<'static>>> {
    p.into_iter().map(|s| PathStep { state: s.state, label: s.label, via: s.via, cost_so_far: s.cost_so_far }).collect()
}

impl<'a> Mission<'a> {
    /// Plans from `start` through `goals` (cells, in order).
    pub fn plan(
        world: &'a World,
        model: &'a ActionModel,
        config: PlannerConfig,
        start: Start,
        goals: &[u32],
    ) -> Result<(Mission<'a>, MissionPlan)> {
        check_problem(world, model, &config, start, goals)?;
        let classes = match config.search {
            SearchMode::Exact { tick_s } => return Mission::plan_at_tick(world, model, config, tick_s, start, goals),
            SearchMode::Approximate(classes) => classes,
        };
        // Each try searches the same problem — the same goal windows, and a start window
        // never narrower than the last try's — at finer classes than the last, so that
        // what a coarser setting finds a finer one finds too (see `finer_classes`).
        let geometry = SharedGeometry::default();
        let allowance = Allowance::new(config.max_expansions, config.max_search_bytes);
        let (mut classes, mut start, mut last_resort) = (classes, start, false);
        let (given_t_max, widened_for_s) = (start.t_max, classes.resolution.time_s);
        loop {
            let mut mission = Mission {
                world,
                model,
                config: PlannerConfig { search: SearchMode::Approximate(classes), ..config.clone() },
                start,
                goals: goals.to_vec(),
                segments: Vec::new(),
                geometry: Rc::clone(&geometry),
                last_resort,
                given_t_max,
                widened_for_s,
                allowance: allowance.clone(),
                classes,
                tick: None,
            };
            mission.widen_start();
            mission.build_segments();
            mission.solve_from(Some(mission.segments.len() - 1), &[], false);
            allowance.check()?;
            if let Some(plan) = mission.assemble()? {
                return Ok((mission, plan));
            }
            start = mission.start;
            match mission.finer_classes() {
                Some((finer, resort)) => {
                    if resort {
                        // As wide as a coarser setting's could be (see `widen_start`):
                        // one Hibernate, or two of these time classes.
                        let width = model.stay_duration_s(model.fallback_stay()).max(2.0 * classes.resolution.time_s);
                        start.t_max = start.t_max.max(start.t_min + width);
                    }
                    (classes, last_resort) = (finer, resort);
                }
                None => return Err(mission.explain_unreachable()),
            }
        }
    }

    /// The next, finer settings to search this problem at when its own found no plan,
    /// and whether they are the last resort: energy exact first (energy classes can
    /// drop the one label a tight battery needs); then the time classes halved, up to
    /// [`PlannerConfig::unreachable_retries`] times (for quantised actions never down to
    /// one quantum); then, for quantised actions, a search
    /// exact at the quanta that holds every plan a coarser setting could find — time
    /// classes of one quantum (one instant each), the goal instants of every smaller
    /// `goal_times` (`final_goal_times`), the widest start window a coarser setting
    /// could have had (see `Mission::plan`), and at each intermediate goal one start
    /// interval per quantum, each keeping its staircase of ways on (cost against the
    /// battery they need). `None` after that (after the retries when actions are not
    /// quantised, or on a quantum under the 1 s a class can be). A plan found this way
    /// reports the classes it was searched with ([`MissionPlan::energy_classes_wh`],
    /// [`MissionPlan::time_classes_s`]).
    fn finer_classes(&self) -> Option<(Classes, bool)> {
        let mut finer = self.classes;
        if finer.resolution.energy_wh.is_some() {
            finer.resolution.energy_wh = None;
            return Some((finer, false));
        }
        let q = self.model.config().time_quantum_s;
        if self.last_resort {
            return None;
        }
        // The retries the settings ask for, each at half the last one's classes: for
        // continuous times (or quanta under a class's 1 s) all there is, since no search
        // is exact; for quantised actions a cheaper try before the exact one, and never
        // at classes as narrow as a quantum (which is the last resort's).
        let narrowest = self.widened_for_s / 2f64.powi(self.classes.unreachable_retries as i32);
        let half = self.classes.resolution.time_s / 2.0;
        if self.classes.resolution.time_s > narrowest * (1.0 + 1e-9) && (q < 1.0 || half > q * (1.0 + 1e-9)) {
            finer.resolution.time_s = half;
            return Some((finer, false));
        }
        if q < 1.0 {
            return None;
        }
        finer.resolution.time_s = finer.resolution.time_s.min(q);
        Some((finer, true))
    }

    /// The goal instants at the last goal: `goal_times` even instants over its window
    /// (on the time quantum's grid when actions are quantised, so that quantised paths
    /// can meet them). Even sets are not nested — 4 and 8 instants share only the ends
    /// — so the last-resort search takes the instants of every `goal_times` up to this
    /// one: more instants then never take away an arrival time a coarser setting's plan
    /// used. Sorted.
    pub fn final_goal_times(&self) -> Vec<f64> {
        let q = self.model.config().time_quantum_s;
        let (lo, hi) = *self.windows().last().expect("at least one goal");
        let even = |n: usize| (0..n).map(move |j| if n == 1 { hi } else { lo + (hi - lo) * j as f64 / (n - 1) as f64 });
        let m = self.classes.goal_times;
        let counts = if self.last_resort { 1..=m } else { m..=m };
        let mut times: Vec<f64> = counts.flat_map(even).collect();
        for t in &mut times {
            if q > 0.0 {
                *t = (*t / q).round() * q;
            }
        }
        times.sort_by(f64::total_cmp);
        times.dedup();
        times
    }

    /// The arrival windows at each goal (best case, worst case), s after the epoch.
    pub fn goal_windows(&self) -> Vec<(f64, f64)> {
        if let Some(t) = &self.tick {
            return t.windows.clone();
        }
        self.windows()
    }

    /// The start, with its window as planned (see [`Start`]).
    pub fn start(&self) -> Start {
        self.start
    }

    /// A path's time is fixed by its goal instant and its actions: a start window
    /// narrower than the gaps a path can bridge could miss every goal instant, so it is
    /// widened. Waits come in whole Hibernate periods (or wait steps, where the rover
    /// waits), so a window as long as one of them (or as the spacing of the goal
    /// instants, if shorter), and no narrower
    /// than two time classes, lets some number of waits meet an instant; the rover
    /// idles from the window's opening to the plan's start, and that idle's energy is
    /// counted (see `TempestDomain::is_start`). The last-resort search starts from a
    /// window as wide as any setting with time classes of at most half a Hibernate
    /// gives (see `Mission::plan`).
    fn widen_start(&mut self) {
        let (lo, hi) = *self.windows().last().expect("at least one goal");
        let m = self.classes.goal_times.max(2) - 1;
        // Resolution pruning keeps one label per time class, so starts can shift by up
        // to one class width: the window is at least that wide too.
        let width = ((hi - lo) / m as f64)
            .min(self.model.stay_duration_s(self.model.fallback_stay()))
            .max(2.0 * self.widened_for_s);
        if self.start.t_max - self.start.t_min < width {
            self.start.t_max = self.start.t_min + width;
        }
    }

    /// The best- and worst-case arrival windows at each goal.
    ///
    /// From the start window as given, not as widened: the widening depends on the
    /// settings, and the goal instants, spread over these windows, must not.
    fn windows(&self) -> Vec<(f64, f64)> {
        let top = self.model.top_speed_m_s(self.world);
        // The slowest: a third of the rover's speed on its slowest terrain class.
        let (slowest, fastest) = self.world.speed_factor_range();
        let slow = top / fastest * slowest / 3.0;
        let mut out = Vec::new();
        let (mut best, mut worst) = (self.start.t_min, self.given_t_max);
        let max_wait_s = self.config.max_wait_s.unwrap_or_else(|| self.world.body().solar_day_s().round());
        let mut at = self.start.cell;
        for (i, &g) in self.goals.iter().enumerate() {
            let d = self.world.octile_m(at, g);
            best += d / top;
            worst += self.config.detour_factor * d / slow;
            if i + 1 == self.goals.len() {
                worst += max_wait_s;
            }
            out.push((best, worst.max(best).min(self.world.span_s())));
            at = g;
        }
        // Intermediate goals may wait too: the wait allowance applies to every goal.
        for w in out.iter_mut().take(self.goals.len() - 1) {
            w.1 = (w.1 + max_wait_s).min(self.world.span_s());
        }
        out
    }

    /// The problem the kept graphs answer, segment by segment: (from, to, start, goal
    /// labels, start intervals, arriving) — the goal instants and start intervals as
    /// they were made, which after plan extension are not what [`Mission::windows`]
    /// would make from the rover's new start.
    #[allow(clippy::type_complexity)]
    fn kept_problem(&self) -> Vec<(u32, u32, Start, Vec<(Label, f64)>, Vec<(f64, f64)>, bool)> {
        let n = self.segments.len();
        (self.segments.iter().enumerate())
            .map(|(k, seg)| {
                let start = if k == 0 {
                    self.start
                } else {
                    let (t_min, t_max) = seg.intervals[0];
                    Start { t_min, t_max, ..seg.domain.start }
                };
                let goals = if k + 1 == n { seg.goals.clone() } else { Vec::new() };
                (seg.from, seg.to, start, goals, seg.intervals.clone(), k > 0)
            })
            .collect()
    }

    /// The arrival windows at each goal of the kept problem: the next segment's start
    /// intervals, and the span of the last segment's goal instants ([`Mission::windows`]
    /// before any segment is built).
    fn kept_windows(&self) -> Vec<(f64, f64)> {
        if let Some(t) = &self.tick {
            return t.windows.clone();
        }
        if self.segments.is_empty() {
            return self.windows();
        }
        let n = self.segments.len();
        (0..n)
            .map(|k| match self.segments.get(k + 1) {
                Some(next) => (next.intervals[0].0, next.intervals.last().map_or(0.0, |i| i.1)),
                None => {
                    let t = self.segments[k].goals.iter().map(|g| g.0.t);
                    (t.clone().fold(f64::INFINITY, f64::min), t.fold(f64::NEG_INFINITY, f64::max))
                }
            })
            .collect()
    }

    fn build_segments(&mut self) {
        let windows = self.windows();
        let n = self.goals.len();
        let mut segments = Vec::with_capacity(n);
        for k in 0..n {
            let from = if k == 0 { self.start.cell } else { self.goals[k - 1] };
            let to = self.goals[k];
            let (start, intervals) = if k == 0 {
                (self.start, vec![(self.start.t_min, self.start.t_max)])
            } else {
                let (lo, hi) = windows[k - 1];
                let q = self.model.config().time_quantum_s;
                // The last resort: one interval per quantum (at most one instant each).
                let m = if self.last_resort {
                    ((hi - lo) / q).ceil().clamp(1.0, 10_000.0) as usize
                } else {
                    self.classes.segment_starts
                };
                // Half-open intervals (the last one closed), so no instant is in two.
                let iv: Vec<(f64, f64)> = (0..m)
                    .map(|j| {
                        let a = lo + (hi - lo) * j as f64 / m as f64;
                        let b = lo + (hi - lo) * (j + 1) as f64 / m as f64;
                        (a, if j + 1 == m { b } else { b - 1e-6 })
                    })
                    .collect();
                let s = Start { cell: from, t_min: iv[0].0, t_max: iv[0].1, energy_wh: self.model.capacity_wh() };
                (s, iv)
            };
            let goals = if k + 1 == n {
                self.final_goal_times().into_iter().map(|t| (Label { t, e: self.config.goal_energy_wh }, 0.0)).collect()
            } else {
                Vec::new()
            };
            segments.push(self.new_segment(from, to, start, goals, intervals, k > 0));
        }
        self.segments = segments;
    }

    /// A segment with a new, empty graph seeded with `goals` at `to`; `arriving`: it
    /// starts at an intermediate goal (see [`TempestDomain::arriving`]).
    fn new_segment(
        &self,
        from: u32,
        to: u32,
        start: Start,
        goals: Vec<(Label, f64)>,
        intervals: Vec<(f64, f64)>,
        arriving: bool,
    ) -> Segment<'a> {
        let domain = TempestDomain::new(
            self.world,
            self.model,
            start,
            self.config.objective,
            self.classes.resolution,
            self.config.path_length,
        )
        .sharing_geometry(&self.geometry)
        .metered(self.config.meter.clone())
        .allowing(self.allowance.clone());
        let domain = if arriving { domain.arriving() } else { domain };
        let search = Search::new(&domain, relabel_goals(goal_list(&goals, to)), domain.mode());
        Segment { from, to, domain, search, goals, intervals, candidates: Vec::new(), stats: Stats::default() }
    }

    /// Re-solves the segments that need it, from the latest one down to the first:
    /// every kept graph is told which cells `changed` first, and re-planning starts at
    /// the latest segment whose graph they touched (the paper's rule) — or at `last`,
    /// or the first segment when its start moved, whichever is later. A segment
    /// before it takes the next one's candidates as its goals through
    /// [`Search::set_goals`], which repairs its graph where the seeds changed.
    fn solve_from(&mut self, last: Option<usize>, changed: &[u32], start_moved: bool) {
        let mut top = if start_moved { Some(0) } else { None };
        for (k, seg) in self.segments.iter_mut().enumerate() {
            if !changed.is_empty() {
                let fell = seg.domain.forget(changed);
                seg.search.heuristic_fell(&seg.domain, fell);
            }
            // Statistics are per call: a segment not searched again did no work.
            seg.stats = Stats::default();
            if !changed.is_empty() {
                let repair = seg.search.update(&seg.domain, changed);
                add_stats(&mut seg.stats, &repair);
                if repair.invalidated > 0 || repair.reopened > 0 {
                    top = top.max(Some(k));
                }
            }
        }
        let Some(top) = top.max(last) else { return };
        for k in (0..=top).rev() {
            if k + 1 < self.segments.len() {
                // This segment's goals are the next segment's candidates.
                let goals: Vec<(Label, f64)> =
                    self.segments[k + 1].candidates.iter().map(|c| (c.start, c.cost)).collect();
                let seg = &mut self.segments[k];
                if goals != seg.goals {
                    let repair = seg.search.set_goals(&seg.domain, relabel_goals(goal_list(&goals, seg.to)));
                    add_stats(&mut seg.stats, &repair);
                    seg.goals = goals;
                }
            }
            // The other segments' graphs (the shared drive geometries are the domain's).
            let others: u64 = (self.segments.iter().enumerate())
                .filter(|&(j, _)| j != k)
                .map(|(_, s)| s.search.bytes() + s.domain.landmark_bytes() as u64)
                .sum();
            self.allowance.hold(others);
            let seg = &mut self.segments[k];
            seg.candidates.clear();
            let full = seg.domain.start.energy_wh;
            for (j, &(t_min, t_max)) in seg.intervals.clone().iter().enumerate() {
                seg.domain.start.t_min = t_min;
                seg.domain.start.t_max = t_max;
                seg.domain.start.energy_wh = full;
                if j > 0 || k > 0 || start_moved {
                    seg.search.start_moved(&seg.domain);
                }
                loop {
                    let plan = seg.search.plan(&seg.domain);
                    add_stats(&mut seg.stats, &plan.stats);
                    let Some(path) = plan.path else { break };
                    let start = path[0].label;
                    seg.candidates.push(Candidate { start, cost: plan.cost, path: own_path(path) });
                    // An intermediate goal's arrival battery is not known here: the
                    // cheapest way on may need more than the segment before can bring.
                    // An exact chain keeps the cheapest way on for each battery it
                    // could arrive with — the staircase of (cost, energy) — by asking
                    // again with a start that holds less than the last way needed.
                    // (One search per step: only the last-resort search does this.)
                    if k == 0 || !self.last_resort {
                        break;
                    }
                    // The last resort has energy exact: any less than the last way needed.
                    seg.domain.start.energy_wh = start.e - 1e-6;
                    if seg.domain.start.energy_wh < 0.0 {
                        break;
                    }
                    seg.search.start_moved(&seg.domain);
                }
            }
            seg.domain.start.energy_wh = full;
        }
    }

    /// The chained plan from the first segment's best candidate.
    fn assemble(&self) -> Result<Option<MissionPlan>> {
        let Some(first) = self.segments[0].candidates.first() else { return Ok(None) };
        let mut steps: Vec<(PathStep<TempestDomain<'static>>, usize)> = Vec::new();
        let mut current = first;
        for k in 0..self.segments.len() {
            let Some(end) = current.path.last().map(|s| s.label) else { return Ok(None) };
            for s in &current.path {
                steps.push((s.clone(), k));
            }
            if k + 1 < self.segments.len() {
                // The candidate of the next segment that starts where this one ended.
                let next = self.segments[k + 1]
                    .candidates
                    .iter()
                    .find(|c| c.start.t.to_bits() == end.t.to_bits() && c.start.e.to_bits() == end.e.to_bits());
                let Some(next) = next else { return Ok(None) };
                current = next;
                // Its first step repeats the goal we are standing on.
                steps.pop();
            }
        }
        self.waypoints(&steps, first.cost).map(Some)
    }

    fn waypoints(&self, steps: &[(PathStep<TempestDomain<'static>>, usize)], cost: f64) -> Result<MissionPlan> {
        let capacity = self.model.capacity_wh();
        let floor = {
            let b = &self.model.rover().battery;
            b.capacity_wh * b.min_soc
        };
        // The rover idles from the opening of its start window to the plan's start.
        let t_first = steps.first().map_or(self.start.t_min, |(s, _)| s.label.t);
        let idle_s = t_first - self.start.t_min;
        let mut battery = match self.model.idle_wait(self.world, self.start.cell, self.start.t_min, idle_s) {
            Some(wait) => wait.after(self.start.energy_wh, capacity),
            None => self.start.energy_wh - self.model.idle_wh(idle_s),
        };
        let mut waypoints = Vec::with_capacity(steps.len());
        for (i, (step, segment)) in steps.iter().enumerate() {
            let next_action = if i + 1 < steps.len() { step.via } else { None };
            let sun = self.world.sun(step.label.t);
            let (x, y) = self.world.center(step.state);
            let (lat, lon) = self.world.lat_lon(step.state);
            // A goal is reached where its segment ends: the last step, or the first step
            // of the next segment (which stands on the goal; `assemble` dropped the
            // segment's own last step, which repeated it).
            let arrived_goal = if i + 1 == steps.len() {
                Some(*segment)
            } else {
                i.checked_sub(1).map(|p| steps[p].1).filter(|previous| previous != segment)
            };
            waypoints.push(Waypoint::new(
                self.world,
                step.state,
                (x, y, lat, lon),
                step.label,
                next_action,
                floor + battery,
                &sun,
                arrived_goal,
            ));
            if let Some(a) = next_action {
                let effect = match a {
                    Action::Drive(k) => self.model.drive(self.world, step.state, k, step.label.t).map(|(_, e)| e),
                    stay => self.model.stay(self.world, stay, step.state, step.label.t),
                };
                let e = effect.map_err(|b| Error::Replay {
                    step: i,
                    action: format!("{a:?}"),
                    cell: step.state,
                    binding: b.describe().to_string(),
                })?;
                battery = e.after(battery, capacity);
                if let Some(w) = waypoints.last_mut() {
                    w.drawn_wh = e.load_wh;
                }
            }
        }
        let (e_max, _) = self.model.gain_bounds(self.world);
        let expansions = self.segments.iter().map(|s| s.stats.expansions).sum();
        Ok(MissionPlan {
            waypoints,
            cost,
            e_max_wh: e_max,
            objective: self.config.objective,
            expansions,
            segments: self.segments.len(),
            energy_classes_wh: self.classes.resolution.energy_wh,
            time_classes_s: self.classes.resolution.time_s,
            exact_at_quanta: self.last_resort,
            tick_s: None,
        })
    }

    /// Re-plans after the world changed in `changed` cells (from [`World::set_blocked`]
    /// or [`World::set_slope`]).
    pub fn replan(&mut self, changed: &[u32]) -> Result<MissionPlan> {
        self.allowance.begin();
        if self.tick.is_some() {
            return self.tick_plan(changed);
        }
        self.solve_from(None, changed, false);
        self.allowance.check()?;
        self.assemble()?.ok_or_else(|| self.explain_unreachable())
    }

    /// Plan extension and re-planning in one call, as a rover does after each action:
    /// it is now at `start` (cell, time window, battery) and has sensed the world
    /// change in `changed` cells. Every segment's graph is kept; the segments searched
    /// again are the first and those up to the latest one the change touched.
    pub fn advance(&mut self, start: Start, changed: &[u32]) -> Result<MissionPlan> {
        self.allowance.begin();
        self.start = start;
        self.given_t_max = start.t_max;
        if self.tick.is_some() {
            return self.tick_plan(changed);
        }
        self.widen_start();
        let start = self.start;
        let seg = &mut self.segments[0];
        seg.from = start.cell;
        seg.domain.moved_to(start);
        seg.intervals = vec![(start.t_min, start.t_max)];
        let restricted = seg.search.restrict(&seg.domain);
        self.solve_from(None, changed, true);
        add_stats(&mut self.segments[0].stats, &restricted);
        self.allowance.check()?;
        self.assemble()?.ok_or_else(|| self.explain_unreachable())
    }

    /// The plan a search from scratch makes of the problem as it now stands — the same
    /// start, goals, goal instants and start intervals, on the world as it now is, with
    /// new graphs — for checking what re-planning on the kept graphs gives (its cost,
    /// its expansions) against. `None` when no plan exists.
    pub fn fresh(&self) -> Result<Option<MissionPlan>> {
        self.allowance.begin();
        if self.tick.is_some() {
            return self.tick_fresh();
        }
        let n = self.segments.len();
        let mut segments = Vec::with_capacity(n);
        for (from, to, start, goals, intervals, arriving) in self.kept_problem() {
            segments.push(self.new_segment(from, to, start, goals, intervals, arriving));
        }
        let mut fresh = Mission {
            world: self.world,
            model: self.model,
            config: self.config.clone(),
            start: self.start,
            goals: self.goals.clone(),
            segments,
            geometry: Rc::clone(&self.geometry),
            last_resort: self.last_resort,
            given_t_max: self.given_t_max,
            widened_for_s: self.widened_for_s,
            allowance: self.allowance.clone(),
            classes: self.classes,
            tick: None,
        };
        // The mission beside the fresh search; the drive geometries both share are then
        // counted twice, which errs towards stopping early.
        self.allowance.beside(self.search_bytes(), || fresh.solve_from(Some(n - 1), &[], n > 0));
        self.allowance.check()?;
        fresh.assemble()
    }

    /// The rover has reached the first remaining goal: its segment is dropped and the
    /// next goal's segment becomes the first (call [`Mission::advance`] next). Returns
    /// false, changing nothing, when it was the last goal.
    pub fn goal_reached(&mut self) -> bool {
        if self.goals.len() <= 1 {
            return false;
        }
        self.goals.remove(0);
        if self.tick.is_some() {
            self.tick_goal_reached();
        } else {
            self.segments.remove(0);
        }
        true
    }

    /// The goals still ahead, in order.
    pub fn goals(&self) -> &[u32] {
        &self.goals
    }

    /// Plan extension: re-plans from the rover's current state (cell, time window,
    /// energy), reusing the first segment's graph.
    pub fn extend(&mut self, start: Start) -> Result<MissionPlan> {
        self.advance(start, &[])
    }

    /// The work the last planning call did over all its searches (the binding
    /// constraint's probes included), in expansions: what
    /// [`PlannerConfig::max_expansions`] holds it to ([`ExpansionMeter::work`]).
    pub fn last_call_work(&self) -> u64 {
        self.allowance.spent()
    }

    /// Whether the last call on a tick kept the rest of the plan before: nothing
    /// changed, or a repair proved the rest optimal (always false off a tick).
    pub fn kept_rest(&self) -> bool {
        self.tick.as_ref().is_some_and(|t| t.reused)
    }

    /// Search statistics of the last call, per segment.
    pub fn stats(&self) -> Vec<Stats> {
        self.segments.iter().map(|s| s.stats).collect()
    }

    /// Labels alive over all segment graphs (for memory reports).
    pub fn labels_alive(&self) -> u64 {
        if let Some(t) = &self.tick {
            return t.kept;
        }
        self.segments.iter().map(|s| s.stats.labels_alive).sum()
    }

    /// Bytes the segments' search graphs, tables, open lists and drive-geometry caches
    /// hold now — the search's memory, apart from the worlds' (terrain, horizon maps,
    /// Sun table).
    pub fn search_bytes(&self) -> u64 {
        if let Some(t) = &self.tick {
            return t.bytes + t.learned_bytes();
        }
        let geometry = self.segments.first().map_or(0, |s| s.domain.geometry_bytes() as u64);
        geometry + self.segments.iter().map(|s| s.search.bytes() + s.domain.landmark_bytes() as u64).sum::<u64>()
    }
}

fn add_stats(total: &mut Stats, s: &Stats) {
    total.expansions += s.expansions;
    total.generated += s.generated;
    total.pruned_dominance += s.pruned_dominance;
    total.compared += s.compared;
    total.pruned_resolution += s.pruned_resolution;
    total.pruned_constraint += s.pruned_constraint;
    total.invalidated += s.invalidated;
    total.reopened += s.reopened;
    total.reclaimed += s.reclaimed;
    total.beaten_subtrees += s.beaten_subtrees;
    total.parked += s.parked;
    total.labels_alive = s.labels_alive;
    total.bytes = s.bytes;
}
