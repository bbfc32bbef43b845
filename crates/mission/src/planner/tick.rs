//! The planner on a tick ([`SearchMode::Exact`](super::SearchMode::Exact)):
//! every planning call is one exact search ([`crate::exact`]) from where the rover is
//! to the goals still ahead, within the goal windows fixed when the mission was planned.
//! No classes, no goal instants, no start intervals: the plan is optimal over every plan
//! whose drives depart on ticks and whose waits end on them, and "unreachable" is a
//! proof at that tick.
//!
//! A re-plan returns what a fresh search returns, with less work:
//!
//! - When the world did not change and the rover stands where, when and with the
//!   battery the last plan said it would (on a tick, after the settle), the rest of
//!   that plan is kept. By Bellman's principle it is optimal from there: a cheaper way
//!   on would, after the part already driven, have been a cheaper plan from the start,
//!   which the exact search would have returned.
//! - When sensing changed cells the rest of the plan does not touch, the rest still
//!   costs what it did, and only plans through the changed cells can have become
//!   cheaper: a *repair* searches for a plan cheaper than the rest, guided by the cost
//!   to go that earlier searches learned ([`crate::exact::Learned`]), which is exact
//!   wherever nothing changed. It expands the labels whose bound the change lowered
//!   below the rest's cost; none left proves the rest optimal.
//! - Otherwise a search from the rover's state, guided the same way.

use super::{Allowance, Classes, Mission, PlannerConfig};
use crate::action_model::{Action, ActionModel};
use crate::domain::{Label, SharedGeometry, Start};
use crate::error::{Error, Result};
use crate::exact::{ExactGoal, ExactOutcome, ExactQuery, ExactStep, Learned};
use crate::plan::{MissionPlan, Waypoint};
use crate::world::World;

/// Slack for comparing the rover's state with a plan's prediction (s, Wh).
const SAME_STATE: f64 = 1e-6;

/// What a mission on a tick keeps between planning calls.
#[derive(Debug)]
pub(super) struct TickState {
    /// The tick, s.
    pub tick_s: f64,
    /// The goal windows of the goals still ahead, s after the epoch, fixed when the
    /// mission was planned (a re-plan answers the same problem as a fresh search).
    pub windows: Vec<(f64, f64)>,
    /// The last plan's steps, from the state it was searched from.
    last: Option<KeptPlan>,
    /// The last search's expansions, labels kept and bytes.
    pub expanded: u64,
    pub kept: u64,
    pub bytes: u64,
    /// Whether the last call kept the rest of the plan before (without a search, or
    /// after a repair proved it optimal).
    pub reused: bool,
    /// Cells sensing changed since the last plan was searched.
    changed: Vec<u32>,
    /// What the largest search and the newest others learned, oldest first.
    learned: Vec<Learned>,
}

/// The most searches whose learned cost-to-go is kept ([`TickState::learn`]).
const LEARNED_LAYERS: usize = 3;

/// The probes that name the binding constraint after a proof may expand this many times
/// the labels the proof expanded, and at least [`PROBE_FLOOR`].
const PROBE_SHARE: u64 = 4;

/// The least share of the probes, expansions (a small proof's probes run to the end).
const PROBE_FLOOR: u64 = 2_000_000;

/// The most cells changed since a search for what it learned to be kept.
const MOST_CHANGED: usize = 256;

impl TickState {
    /// Bytes the learned cost-to-go holds.
    pub(super) fn learned_bytes(&self) -> u64 {
        self.learned.iter().map(Learned::bytes).sum()
    }

    /// Keeps what a search learned: the largest lesson kept so far and the newest others,
    /// [`LEARNED_LAYERS`] in all. The largest covers the most of the map (the initial
    /// plan's, or a re-plan that searched as widely); a re-plan's few labels are true of
    /// the world near the rover as sensed last, clamped by the few cells changed since,
    /// where the large lesson's are clamped by every cell sensed after it (gale-mola-
    /// traverse's median re-plan after sensing: 1.28 % of the initial plan's expansions
    /// with only the two largest kept, 0.62 % so).
    fn learn(&mut self, learned: Option<Learned>) {
        let Some(l) = learned else { return };
        self.learned.push(l);
        while self.learned.len() > LEARNED_LAYERS {
            let largest = (0..self.learned.len()).max_by_key(|&i| self.learned[i].labels()).unwrap_or(0);
            self.learned.remove(usize::from(largest == 0));
        }
    }
}

#[derive(Debug, Clone)]
struct KeptPlan {
    steps: Vec<ExactStep>,
    /// The battery above the floor before the first step, Wh.
    start_wh: f64,
    /// The mission's goals ahead when it was searched.
    goals: usize,
}

impl KeptPlan {
    /// The rest of the plan from `start`, if the rover is where, when and with the
    /// battery one of its steps starts with, with `goals` goals ahead: its steps and
    /// their cost.
    fn rest_from(&self, start: Start, goals: usize) -> Option<(Vec<ExactStep>, f64)> {
        let dropped = self.goals.checked_sub(goals)?;
        let mut before = (self.steps.first()?.t_s, self.start_wh, 0usize, 0.0);
        for (i, step) in self.steps.iter().enumerate() {
            let (t, e, reached, cost) = before;
            let here = step.cell == start.cell
                && (t - start.t_min).abs() <= SAME_STATE
                && (e - start.energy_wh).abs() <= SAME_STATE
                && reached == dropped;
            if here && i > 0 {
                let rest = self.steps[i..]
                    .iter()
                    .map(|s| ExactStep {
                        goals_reached: s.goals_reached - dropped,
                        cost_after: s.cost_after - cost,
                        ..*s
                    })
                    .collect();
                return Some((rest, self.steps.last()?.cost_after - cost));
            }
            before = (step.t_s + step.duration_s, step.battery_wh, step.goals_reached, step.cost_after);
        }
        None
    }
}

impl<'a> Mission<'a> {
    /// [`Mission::plan`] on a tick: the goal windows fixed from the start, then one
    /// exact search.
    pub(super) fn plan_at_tick(
        world: &'a World,
        model: &'a ActionModel,
        config: PlannerConfig,
        tick_s: f64,
        start: Start,
        goals: &[u32],
    ) -> Result<(Mission<'a>, MissionPlan)> {
        check_tick(model, &config, tick_s)?;
        let mut mission = Mission::at_tick(world, model, config, tick_s, start, goals);
        // `Mission::plan` checked the problem.
        let plan = mission.tick_search()?;
        Ok((mission, plan))
    }

    /// A mission on a tick before its first search: its goal windows fixed from the
    /// start (under Margin, none past the longest acceptable plan).
    fn at_tick(
        world: &'a World,
        model: &'a ActionModel,
        config: PlannerConfig,
        tick_s: f64,
        start: Start,
        goals: &[u32],
    ) -> Mission<'a> {
        let allowance = Allowance::new(config.max_expansions, config.max_search_bytes);
        let mut mission = Mission {
            world,
            model,
            config,
            start,
            goals: goals.to_vec(),
            segments: Vec::new(),
            geometry: SharedGeometry::default(),
            last_resort: false,
            given_t_max: start.t_max,
            widened_for_s: tick_s,
            allowance,
            classes: Classes::default(),
            tick: Some(TickState {
                tick_s,
                windows: Vec::new(),
                last: None,
                expanded: 0,
                kept: 0,
                bytes: 0,
                reused: false,
                changed: Vec::new(),
                learned: Vec::new(),
            }),
        };
        let mut windows = mission.windows();
        if let crate::domain::Objective::Margin { max_duration_s } = mission.config.objective {
            // The longest acceptable plan, from the instant the rover is ready: every
            // goal by then.
            let deadline = start.t_min + max_duration_s;
            for w in &mut windows {
                w.1 = w.1.min(deadline);
            }
        }
        mission.tick.as_mut().expect("a mission on a tick").windows = windows;
        mission
    }

    /// The goal windows a mission on a tick planned from `start` to `goals` would keep
    /// (see [`Mission::goal_windows`]), without planning it.
    pub fn tick_windows_from(
        world: &'a World,
        model: &'a ActionModel,
        config: &PlannerConfig,
        tick_s: f64,
        start: Start,
        goals: &[u32],
    ) -> Vec<(f64, f64)> {
        Mission::at_tick(world, model, config.clone(), tick_s, start, goals).goal_windows()
    }

    /// The query of the problem as it now stands: from the mission's start to the
    /// goals ahead within their kept windows.
    pub(super) fn tick_query<'m>(&'m self, model: &'m ActionModel, start: Start) -> ExactQuery<'m> {
        let windows = &self.tick.as_ref().expect("a mission on a tick").windows;
        ExactQuery {
            world: self.world,
            model,
            start,
            goals: (self.goals.iter().zip(windows))
                .map(|(&cell, &(open_s, close_s))| ExactGoal { cell, open_s, close_s })
                .collect(),
            goal_energy_wh: self.config.goal_energy_wh,
            objective: self.config.objective,
            max_labels: u64::MAX,
            settle: true,
        }
    }

    /// Runs `query` within the call's work and memory allowance (every expansion one
    /// unit of work, the memory what the search holds).
    pub(super) fn tick_solve(&self, query: &ExactQuery<'_>) -> Result<ExactOutcome> {
        let out = query.solve_with(&mut self.budget(0));
        self.allowance.check()?;
        Ok(out)
    }

    /// Whether a search may go on, asked before each expansion with the bytes it holds
    /// (`also` held beside it): one unit of work spent and metered each time.
    fn budget(&self, also: u64) -> impl FnMut(u64) -> bool + '_ {
        move |held| {
            self.allowance.spend();
            self.config.meter.add(1);
            !self.allowance.exhausted() && !self.allowance.outgrown(held + also)
        }
    }

    /// [`Mission::tick_solve`] guided by what earlier searches learned, for a plan
    /// cheaper than `upper` if given; also what this search learned.
    fn tick_solve_guided(&self, query: &ExactQuery<'_>, upper: Option<f64>) -> Result<(ExactOutcome, Option<Learned>)> {
        let state = self.tick.as_ref().expect("a mission on a tick");
        let out = query.solve_guided(&state.learned, upper, &mut self.budget(state.learned_bytes()));
        self.allowance.check()?;
        Ok(out)
    }

    /// The plan from the mission's start as the world now stands: the rest of the last
    /// plan if `reuse` and the rover is where it said (see the module's documentation),
    /// else an exact search. No plan: the verdict, a proof at the tick.
    pub(super) fn tick_plan(&mut self, changed: &[u32]) -> Result<MissionPlan> {
        let start = self.start;
        let goals = self.goals.len();
        let state = self.tick.as_mut().expect("a mission on a tick");
        for l in &mut state.learned {
            l.sensed(changed);
        }
        // A lesson whose world has changed in many cells bounds little that the
        // search's own bound does not, and costs a bound per change to use.
        state.learned.retain(|l| l.changed() <= MOST_CHANGED);
        state.changed.extend_from_slice(changed);
        state.changed.sort_unstable();
        state.changed.dedup();
        // A margin is a plan's worst moment, not a sum: the rest of the plan with the
        // least margin used need not be the best rest (its worst moment may lie
        // behind), so a plan by Margin is always searched afresh.
        let sum = !matches!(self.config.objective, crate::domain::Objective::Margin { .. });
        let rest = if sum { state.last.as_ref().and_then(|k| k.rest_from(start, goals)) } else { None };
        let rest = rest.filter(|(steps, _)| !touches(self.world, steps, &state.changed));
        if let Some((steps, cost)) = &rest
            && state.changed.is_empty()
        {
            state.reused = true;
            state.expanded = 0;
            return Ok(self.tick_waypoints(steps, *cost, 0));
        }
        // Goals that slopes or obstacles cut off (sensing may have cut them off since the
        // plan): a proof without a search.
        super::problem::check_problem(self.world, self.model, &self.config, start, &self.goals)?;
        let Some((steps, cost)) = rest else { return self.tick_search() };
        // The rest avoids every changed cell, so it costs what it did: repair.
        let (out, _) = self.tick_solve_guided(&self.tick_query(self.model, start), Some(cost))?;
        let state = self.tick.as_mut().expect("a mission on a tick");
        (state.expanded, state.kept, state.bytes) = (out.expanded, out.kept, out.bytes);
        if let Some((better, steps)) = out.plan {
            state.reused = false;
            state.changed.clear();
            state.last = Some(KeptPlan { steps: steps.clone(), start_wh: start.energy_wh, goals });
            return Ok(self.tick_waypoints(&steps, better, out.expanded));
        }
        // The rest is now proven optimal on the world as it stands.
        state.reused = true;
        state.changed.clear();
        Ok(self.tick_waypoints(&steps, cost, out.expanded))
    }

    /// One exact search from the mission's start (its problem checked already), kept as
    /// the last plan.
    fn tick_search(&mut self) -> Result<MissionPlan> {
        let (start, goals) = (self.start, self.goals.len());
        let (out, learned) = self.tick_solve_guided(&self.tick_query(self.model, start), None)?;
        let state = self.tick.as_mut().expect("a mission on a tick");
        (state.reused, state.expanded, state.kept, state.bytes) = (false, out.expanded, out.kept, out.bytes);
        state.changed.clear();
        state.learn(learned);
        let Some((cost, steps)) = out.plan else {
            state.last = None;
            // The search proved it: the probes that name the binding constraint get a
            // bounded share of the work, so that the verdict comes about as fast.
            self.allowance.share_for_probes(PROBE_SHARE.saturating_mul(out.expanded).max(PROBE_FLOOR));
            return Err(self.explain_unreachable());
        };
        state.last = Some(KeptPlan { steps: steps.clone(), start_wh: start.energy_wh, goals });
        Ok(self.tick_waypoints(&steps, cost, out.expanded))
    }

    /// What a fresh exact search of the problem as it now stands returns (`None`: no
    /// plan), for comparison with a re-plan.
    pub(super) fn tick_fresh(&self) -> Result<Option<MissionPlan>> {
        let bytes = self.search_bytes();
        let out = self.allowance.beside(bytes, || self.tick_solve(&self.tick_query(self.model, self.start)))?;
        Ok(out.plan.map(|(cost, steps)| self.tick_waypoints(&steps, cost, out.expanded)))
    }

    /// The plan's waypoints from exact steps: one per step (a drive's waypoint covers its
    /// settle; the wait to the first tick from a start between ticks is the idle before
    /// the plan's first waypoint), then the last goal.
    pub(super) fn tick_waypoints(&self, steps: &[ExactStep], cost: f64, expansions: u64) -> MissionPlan {
        let (world, model) = (self.world, self.model);
        let tick = self.tick.as_ref().map_or(0.0, |state| state.tick_s);
        let floor = {
            let b = &model.rover().battery;
            b.capacity_wh * b.min_soc
        };
        let required = required_before(world, model, steps, self.config.goal_energy_wh);
        let mut waypoints = Vec::with_capacity(steps.len() + 1);
        let mut battery = self.start.energy_wh;
        let mut reached = 0usize;
        let mut pending_goal = None;
        for (i, step) in steps.iter().enumerate() {
            let partial = step.action == Action::Wait && step.duration_s < tick - SAME_STATE;
            if !partial {
                let label = Label { t: step.t_s, e: required[i] };
                waypoints.push(waypoint(world, step.cell, label, Some(step.action), floor + battery, pending_goal));
                pending_goal = None;
            }
            // A partial wait belongs to the waypoint before it (none: the idle before
            // the plan's first waypoint).
            if let Some(w) = waypoints.last_mut() {
                w.drawn_wh += step_effect(world, model, step).map_or(f64::NAN, |e| e.load_wh);
            }
            if step.goals_reached > reached {
                pending_goal = Some(step.goals_reached - 1);
                reached = step.goals_reached;
            }
            battery = step.battery_wh;
        }
        let end = steps.last().map_or((self.start.cell, self.start.t_min), |s| {
            let to = match s.action {
                Action::Drive(k) => model.drive_geometry(world, s.cell, k).map_or(s.cell, |g| g.to),
                _ => s.cell,
            };
            (to, s.t_s + s.duration_s)
        });
        let label = Label { t: end.1, e: self.config.goal_energy_wh };
        let last_goal = pending_goal.or(Some(self.goals.len().saturating_sub(1)));
        waypoints.push(waypoint(world, end.0, label, None, floor + battery, last_goal));
        MissionPlan {
            waypoints,
            cost,
            e_max_wh: model.gain_bounds(world).0,
            objective: self.config.objective,
            expansions,
            segments: self.goals.len(),
            energy_classes_wh: None,
            time_classes_s: tick,
            exact_at_quanta: false,
            tick_s: Some(tick),
        }
    }

    /// The mission's state on a tick after the rover reached the first goal ahead.
    pub(super) fn tick_goal_reached(&mut self) {
        if let Some(state) = self.tick.as_mut()
            && !state.windows.is_empty()
        {
            state.windows.remove(0);
        }
    }

    /// "Unreachable" on a tick: what the search proved.
    pub(super) fn tick_proof(&self) -> String {
        let tick = self.tick.as_ref().map_or(0.0, |state| state.tick_s);
        let close = self.tick.as_ref().and_then(|s| s.windows.last()).map_or(0.0, |w| w.1);
        format!(
            "proven at the tick of {tick} s: no plan whose drives depart and waits end on ticks reaches the goals in \
             order within their windows (the last by {close:.0} s), nor at any multiple of the tick (every plan \
             at a tick is one at half of it); a finer tick may"
        )
    }
}

/// Whether any of `steps` starts or ends in one of the `changed` cells (sorted).
fn touches(world: &World, steps: &[ExactStep], changed: &[u32]) -> bool {
    let hit = |c: u32| changed.binary_search(&c).is_ok();
    steps.iter().any(|s| {
        hit(s.cell)
            || match s.action {
                Action::Drive(k) => crate::action_model::neighbour(world, s.cell, k).is_none_or(hit),
                _ => false,
            }
    })
}

/// The least battery above the floor each step needs at its start for the plan to
/// hold `goal_wh` at its end, Wh (replayed backward through each step's effect, its
/// settle included).
fn required_before(world: &World, model: &ActionModel, steps: &[ExactStep], goal_wh: f64) -> Vec<f64> {
    let mut need = vec![0.0; steps.len()];
    let mut after = goal_wh;
    for (i, s) in steps.iter().enumerate().rev() {
        after = step_effect(world, model, s).map_or(after, |e| e.required_before(after));
        need[i] = after;
    }
    need
}

/// An exact step's effect, a drive's settle included.
fn step_effect(world: &World, model: &ActionModel, s: &ExactStep) -> Option<crate::Effect> {
    match s.action {
        Action::Drive(k) => model.drive(world, s.cell, k, s.t_s).ok().and_then(|(to, drive)| {
            let settle = model.wait(world, to, s.t_s + drive.duration_s, s.settle_s).ok()?;
            Some(drive.then(&settle))
        }),
        _ => model.wait(world, s.cell, s.t_s, s.duration_s).ok(),
    }
}

fn waypoint(
    world: &World,
    cell: u32,
    label: Label,
    action: Option<Action>,
    battery_wh: f64,
    goal: Option<usize>,
) -> Waypoint {
    let (x, y) = world.center(cell);
    let (lat, lon) = world.lat_lon(cell);
    Waypoint::new(world, cell, (x, y, lat, lon), label, action, battery_wh, &world.sun(label.t), goal)
}

/// A mission's settings refused on a tick, naming the field.
pub(super) fn check_tick(model: &ActionModel, config: &PlannerConfig, tick_s: f64) -> Result<()> {
    if config.path_length != crate::domain::PathLength::Distance {
        // The exact search counts L as drive length (a wait's share its length over a
        // Hibernate's); counting every step as one would make a wait split in two dearer
        // than the whole, and the waits on a tick compose.
        return Err(Error::Config {
            field: "path_length",
            message: format!(
                "{:?} is not searched on a tick ({tick_s} s): the exact search counts L as the distance driven, a \
                 wait its length over a Hibernate's, so that waits split anywhere cost the whole; use `Distance`, \
                 or `Steps` with `approximate: true`",
                config.path_length
            ),
        });
    }
    if model.wait_step_s() != Some(tick_s) {
        return Err(Error::Config {
            field: "tick_s",
            message: format!(
                "{tick_s} s: the rover must wait in steps of the tick (its wait step is {:?}; set \
                 `actions.wait_step_s` to the tick)",
                model.wait_step_s()
            ),
        });
    }
    Ok(())
}
