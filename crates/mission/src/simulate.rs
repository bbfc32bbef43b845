//! Execution simulation (Tompkins et al., section 6): the rover believes one map and
//! drives on the true terrain. After every action it senses the true terrain within a
//! radius (elevation, slope, normal, horizon), pushes the changes into the planner and
//! re-plans from where it now is (plan extension + re-planning, [`Mission::advance`]),
//! until every goal is reached or none is reachable.
//!
//! Each action is executed on the true world from the rover's actual time and battery,
//! so drives and charges see the true slope and light. Optional execution noise makes
//! drives slower and solar input lower than modelled (seeded, so a run repeats
//! exactly). An action the true world forbids (a drive the plan assumed possible that
//! now ends after dark, say) is refused: the rover hibernates for one hibernate period
//! and re-plans. Every plan is kept with its statistics.

use std::time::Instant;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::action_model::{Action, ActionModel, Binding, Perturbation};
use crate::domain::Start;
use crate::error::{Error, Result};
use crate::plan::MissionPlan;
use crate::planner::{Mission, PlannerConfig};
use crate::world::World;

mod fresh;

pub use fresh::{FreshCheck, FreshPlan, PlannedOn};

/// Simulation parameters (scenario fields).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimConfig {
    /// Sensing radius around the rover, cells (≥ 0; the paper's rover sensed 2).
    pub sense_radius_cells: f64,
    /// Execution noise.
    pub noise: Noise,
    /// Most actions to execute before giving up (≥ 1).
    pub max_steps: usize,
    /// For checking the planner: after re-plans (see `fresh_every`), also plan the same
    /// problem from scratch ([`Mission::fresh`]) and record its cost and expansions
    /// beside the re-plan's (slow: a whole search per re-plan compared).
    pub compare_fresh: bool,
    /// With `compare_fresh`, which re-plans are compared: 1 (the default) every one;
    /// n > 1 every n-th, and every one after sensing changed the map or a goal was
    /// reached (where the kept graphs are repaired or re-seeded) — for worlds whose
    /// fresh search is too slow to repeat after each of hundreds of actions.
    #[serde(default = "every_replan")]
    pub fresh_every: usize,
    /// Draw the execution's departures from this model instead of `noise`'s uniform
    /// ones (a closed-loop Monte Carlo run, [`crate::uncertainty::closed_loop`]).
    #[serde(default)]
    pub uncertainty: Option<crate::uncertainty::Uncertainty>,
    /// The ChaCha8 stream of `noise.seed` the departures are drawn from (0: the seed's
    /// first stream, as before streams existed).
    #[serde(default)]
    pub stream: u64,
}

fn every_replan() -> usize {
    1
}

impl Default for SimConfig {
    fn default() -> SimConfig {
        SimConfig {
            sense_radius_cells: 2.0,
            noise: Noise::default(),
            max_steps: 20_000,
            compare_fresh: false,
            fresh_every: 1,
            uncertainty: None,
            stream: 0,
        }
    }
}

/// Execution noise: each drive takes up to `drive_slowdown` longer than modelled and
/// each action gets up to `solar_loss` less solar power, uniformly at random.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Noise {
    /// Largest fractional drive slowdown (0 ≤ · ≤ 2; 0.2 = up to 20 % slower).
    pub drive_slowdown: f64,
    /// Largest fractional loss of solar input (0 ≤ · ≤ 1).
    pub solar_loss: f64,
    /// Seed of the ChaCha8 generator.
    pub seed: u64,
}

impl Default for Noise {
    fn default() -> Noise {
        Noise { drive_slowdown: 0.0, solar_loss: 0.0, seed: 1 }
    }
}

impl SimConfig {
    /// Checks ranges, naming the first bad field.
    pub fn validate(&self) -> Result<()> {
        let bad = |field: &'static str, message: String| Err(Error::Config { field, message });
        if !(self.sense_radius_cells >= 0.0 && self.sense_radius_cells <= 100.0) {
            return bad("sense_radius_cells", format!("{}: allowed 0..=100 cells", self.sense_radius_cells));
        }
        if !(0.0..=2.0).contains(&self.noise.drive_slowdown) {
            return bad("noise.drive_slowdown", format!("{}: allowed 0..=2", self.noise.drive_slowdown));
        }
        if !(0.0..=1.0).contains(&self.noise.solar_loss) {
            return bad("noise.solar_loss", format!("{}: allowed 0..=1", self.noise.solar_loss));
        }
        if let Some(u) = &self.uncertainty {
            u.validate()?;
        }
        if !(1..=1_000_000).contains(&self.max_steps) {
            return bad("max_steps", format!("{}: allowed 1..=1000000", self.max_steps));
        }
        if self.fresh_every == 0 {
            return bad("fresh_every", "0: allowed 1 (every re-plan) or more".to_string());
        }
        Ok(())
    }
}

/// Why a plan was made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum PlanKind {
    /// The first plan, before the rover moves.
    Initial,
    /// After an action: plan extension, with re-planning when sensing changed the map.
    Replan,
    /// After an action, when re-planning on the kept graphs found nothing: a fresh plan
    /// from the rover's state to the remaining goals.
    Restart,
}

/// One plan the simulation made, with its statistics.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PlanRecord {
    /// Actions executed before this plan.
    pub step: usize,
    /// Why.
    pub kind: PlanKind,
    /// Mission time when planned, s after the epoch.
    pub t_s: f64,
    /// Wall-clock time the planner took, s.
    pub wall_s: f64,
    /// Nodes expanded.
    pub expansions: u64,
    /// Cells whose sensed values differed from the map.
    pub changed_cells: usize,
    /// Bytes held by the search graphs after this plan (see [`Mission::search_bytes`]).
    pub search_bytes: u64,
    /// Whether the route ahead differs from the previous plan's remaining route.
    pub route_changed: bool,
    /// Whether the re-plan kept the rest of the plan before: nothing changed, or a
    /// repair proved the rest optimal after sensing changed cells off it.
    #[serde(default)]
    pub kept_rest: bool,
    /// With [`SimConfig::compare_fresh`]: the same problem planned from scratch — its
    /// expansions and cost (`None` when not compared, or no fresh plan exists). On a
    /// tick, by a new, independent planner instance from the rover's state (see
    /// [`FreshCheck`]).
    pub fresh: Option<(u64, f64)>,
    /// On a tick, with [`SimConfig::compare_fresh`]: how the re-plan compares with the
    /// independent instance.
    #[serde(default)]
    pub fresh_check: Option<FreshCheck>,
    /// For a [`PlanKind::Restart`]: the re-plan that found nothing and why.
    pub restart: Option<Restart>,
    /// The plan.
    pub plan: MissionPlan,
}

/// A re-plan on the kept graphs that found nothing, replaced by a plan made afresh
/// from the rover's state (new goal windows and instants from where it now is).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Restart {
    /// The constraint the failed re-plan named as binding.
    pub binding: Binding,
    /// Its message.
    pub reason: String,
    /// The work the failed re-plan did (its binding probes included), expansions
    /// ([`Mission::last_call_work`]); the plan made afresh counts its own in
    /// [`PlanRecord::expansions`].
    pub replan_work: u64,
    /// With [`SimConfig::compare_fresh`]: whether a search from scratch of the problem
    /// the re-plan answered (the kept goal instants and start intervals) found a plan.
    /// `Some(true)` is a re-plan that disagrees with a fresh search: the kept graphs
    /// lost a plan. `Some(false)`: both find nothing there; the restart's plan comes
    /// from the goal instants of a new mission.
    pub fresh_found: Option<bool>,
}

/// One executed action.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ExecutedStep {
    /// Start time, s after the epoch.
    pub t_s: f64,
    /// Where it started.
    pub cell: u32,
    /// Where it ended.
    pub to: u32,
    /// The action.
    pub action: Action,
    /// Duration, s.
    pub duration_s: f64,
    /// Battery energy used (negative: gained), Wh.
    pub energy_wh: f64,
    /// Energy the rover's loads drew over it, Wh (whatever the sources gave meanwhile).
    #[serde(default)]
    pub load_wh: f64,
    /// Battery charge after it, Wh above the floor (the search's E; the absolute charge
    /// adds the battery's floor).
    pub battery_above_floor_wh: f64,
    /// Drive length (3-D), m; 0 for stationary actions.
    pub distance_m: f64,
    /// Sun elevation at the start, degrees.
    pub sun_elevation_deg: f64,
    /// The action the plan asked for, when the true world refused it (the rover
    /// hibernated instead), and why.
    pub refused: Option<(Action, Binding)>,
}

/// How a simulation ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum SimStatus {
    /// Every goal reached.
    Completed,
    /// A re-plan found no plan; the binding constraint.
    Unreachable {
        /// The binding constraint.
        binding: Binding,
        /// The planner's message.
        message: String,
        /// Whether no plan exists at all (see [`crate::Error::Unreachable`]).
        proven: bool,
    },
    /// The battery fell below its floor (the plan was too optimistic for the noise).
    BatteryDepleted,
    /// Neither the plan's action nor hibernation is possible.
    Stuck(Binding),
    /// `max_steps` actions executed without finishing.
    StepLimit,
}

/// What happened.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SimReport {
    /// How it ended.
    pub status: SimStatus,
    /// Every plan, the initial one first.
    pub plans: Vec<PlanRecord>,
    /// Every executed action.
    pub steps: Vec<ExecutedStep>,
    /// (goal index, arrival time s) for each goal reached.
    pub goals_reached: Vec<(usize, f64)>,
    /// The start, as given.
    pub start: Start,
    /// The goals, as given.
    pub goals: Vec<u32>,
}

impl SimReport {
    /// Distance driven, m.
    pub fn distance_m(&self) -> f64 {
        self.steps.iter().map(|s| s.distance_m).sum()
    }

    /// Battery energy drawn (sum of draining actions), Wh.
    pub fn energy_used_wh(&self) -> f64 {
        self.steps.iter().map(|s| s.energy_wh.max(0.0)).sum()
    }

    /// Battery energy gained (sum of charging actions), Wh.
    pub fn energy_gained_wh(&self) -> f64 {
        self.steps.iter().map(|s| (-s.energy_wh).max(0.0)).sum()
    }

    /// Nights the rover spent on `world` (its Sun): sunsets crossed from the start to
    /// the end, at the Sun table's step, plus one if it started in the dark — a wait
    /// may run from an evening to the next morning.
    pub fn nights(&self, world: &World) -> usize {
        let step = world.sun_step_s();
        let (t0, t1) = (self.start.t_min, self.end_t_s());
        let samples = ((t1 - t0) / step).ceil().max(0.0) as usize;
        let mut n = 0;
        let mut prev_day: Option<bool> = None;
        for k in 0..=samples {
            let day = world.sun((t0 + k as f64 * step).min(t1)).elevation_deg > 0.0;
            match prev_day {
                None | Some(true) if !day => n += 1,
                _ => {}
            }
            prev_day = Some(day);
        }
        n
    }

    /// Each re-plan's expansions as a fraction of the initial plan's, in plan order (a
    /// restart counts as what it is: a fresh plan).
    pub fn replan_expansion_fractions(&self) -> Vec<f64> {
        let initial = self.plans.first().map_or(1, |p| p.expansions.max(1)) as f64;
        self.plans.iter().skip(1).map(|p| p.expansions as f64 / initial).collect()
    }

    /// The most bytes the search graphs held after any plan.
    pub fn peak_search_bytes(&self) -> u64 {
        self.plans.iter().map(|p| p.search_bytes).max().unwrap_or(0)
    }

    /// Median wall-clock time of the re-plans (not the initial plan), s.
    pub fn median_replan_s(&self) -> Option<f64> {
        let mut t: Vec<f64> = self.plans.iter().filter(|p| p.kind != PlanKind::Initial).map(|p| p.wall_s).collect();
        if t.is_empty() {
            return None;
        }
        t.sort_by(f64::total_cmp);
        Some(t[t.len() / 2])
    }

    /// Battery charge at the end, Wh above the floor.
    pub fn final_battery_above_floor_wh(&self) -> f64 {
        self.steps.last().map_or(self.start.energy_wh, |s| s.battery_above_floor_wh)
    }

    /// Time at the end, s after the epoch.
    pub fn end_t_s(&self) -> f64 {
        self.steps.last().map_or(self.start.t_min, |s| s.t_s + s.duration_s)
    }
}

/// What a progress observer is told after each action.
#[derive(Debug, Clone, Copy)]
pub struct SimProgress {
    /// Actions executed.
    pub step: usize,
    /// Mission time, s after the epoch.
    pub t_s: f64,
    /// Goals reached so far.
    pub goals_reached: usize,
}

/// What a simulation runs: the map the rover plans on, the terrain it drives on, the
/// rover, the planner, where and when it starts, and its goals in order.
#[derive(Debug, Clone)]
pub struct Simulation<'a> {
    /// The map the planner believes.
    pub believed: &'a World,
    /// The terrain the rover drives on and senses (same grid as `believed`).
    pub truth: &'a World,
    /// The rover's resource models and action settings.
    pub model: &'a ActionModel,
    /// The planner's settings.
    pub planner: PlannerConfig,
    /// Where, when and with how much energy the rover starts.
    pub start: Start,
    /// The goal cells, in the order they are visited.
    pub goals: &'a [u32],
    /// Sensing, noise and step limits.
    pub config: SimConfig,
}

/// Runs the simulation: plans on `believed`, executes on `truth`, senses, re-plans,
/// until done; `on_step` hears of every executed action. Errors only for bad inputs
/// or a first plan that cannot be made; an unreachable goal found later ends the run
/// with [`SimStatus::Unreachable`] and everything so far kept.
pub fn simulate(simulation: &Simulation<'_>, on_step: &mut dyn FnMut(SimProgress)) -> Result<SimReport> {
    let Simulation { believed, truth, model, start, goals, config: ref sim, .. } = *simulation;
    sim.validate()?;
    let config = simulation.planner.clone();
    let (mut mission, mut plan, mut report) = initial_plan(simulation)?;
    let (mut rng, once) = noise_source(sim);
    // The rover executes on the nominal model; planning margins are the planner's.
    let executor = model.nominal();
    let (mut cell, mut t, mut battery) = (start.cell, start.t_min, start.energy_wh);
    let capacity = model.capacity_wh();
    let mut next_goal = 0usize;
    for step in 1..=sim.max_steps {
        let Some(action) = plan.waypoints.first().and_then(|w| w.action) else {
            // The plan ends here: the rover stands on the last goal.
            if next_goal < goals.len() {
                report.goals_reached.push((next_goal, t));
            }
            report.status = SimStatus::Completed;
            break;
        };
        // The plan may start a little after now (its start window): idle until then.
        let t_plan = plan.waypoints.first().map_or(t, |w| w.t_s);
        (t, battery) = idle_until(&mut report, (&executor, truth), (cell, t, battery, capacity), t_plan);
        let perturbation = draw_perturbation(sim, once, &mut rng);
        let what = (action, planned_wait_s(&config, &plan, action, t));
        let Ok((executed, mut lowest)) =
            execute_step(&executor, truth, what, (cell, t, battery, capacity), perturbation)
                .map_err(|b| report.status = SimStatus::Stuck(b))
        else {
            break;
        };
        let (to, duration_s) = (executed.to, executed.duration_s);
        // On a tick a drive that goes on settles to the next tick first.
        let goes_on = plan.waypoints.get(1).is_some_and(|w| w.action.is_some());
        let tick = config.search.tick_s().filter(|_| matches!(executed.action, Action::Drive(_)) && goes_on);
        battery = executed.battery_above_floor_wh;
        report.steps.push(executed);
        cell = to;
        t += duration_s;
        if let Some((settle, low)) = tick.and_then(|q| settle_step(&executor, truth, (cell, t, battery, capacity), q)) {
            (battery, t, lowest) = (settle.battery_above_floor_wh, settle.t_s + settle.duration_s, lowest.min(low));
            report.steps.push(settle);
        }
        on_step(SimProgress { step, t_s: t, goals_reached: report.goals_reached.len() });
        if battery < 0.0 || lowest < -1e-9 {
            report.status = SimStatus::BatteryDepleted;
            break;
        }
        let goal_reached = arrive(&mut report, &mut mission, &mut next_goal, cell, t);
        let changed = believed.sense(truth, &disc(believed, cell, sim.sense_radius_cells))?;
        let clock = Instant::now();
        let here = Start { cell, t_min: t, t_max: t, energy_wh: battery };
        // Re-planning keeps the mission's goal instants and graphs; when that finds
        // nothing (their discretisation can miss a narrow way through), plan afresh from
        // here, as an executive would, before declaring the goals unreachable.
        let remaining = &goals[next_goal.min(goals.len() - 1)..];
        let outcome = replan(&mut mission, (believed, model, &config), sim.compare_fresh, here, &changed, remaining);
        match outcome {
            Ok((p, restart)) => {
                // Plan extension alone moves the start, and the kept graph must still
                // answer as a fresh one: with `fresh_every: 1` every re-plan is compared,
                // sensed change or not; thinned out, never those that repaired or
                // re-seeded the graphs.
                let compared = step % sim.fresh_every == 0 || !changed.is_empty() || goal_reached;
                let compare = sim.compare_fresh && restart.is_none() && compared;
                let route_changed = !same_route(&plan, &p, cell);
                let at = (step, t, clock.elapsed().as_secs_f64());
                let compare = compare.then_some(((believed, model, &config), here, remaining));
                report.plans.push(record_replan(&mission, &p, restart, at, (changed.len(), route_changed), compare)?);
                plan = p;
            }
            Err(Error::Unreachable { binding, message, proven }) => {
                report.status = SimStatus::Unreachable { binding, message, proven };
                break;
            }
            Err(e) => return Err(e),
        }
    }
    Ok(report)
}

/// The first plan, before the rover moves (after sensing around its start), and the
/// report that records it.
fn initial_plan<'a>(simulation: &Simulation<'a>) -> Result<(Mission<'a>, MissionPlan, SimReport)> {
    let Simulation { believed, truth, model, ref planner, start, goals, config: ref sim } = *simulation;
    let mut report = SimReport {
        status: SimStatus::StepLimit,
        plans: Vec::new(),
        steps: Vec::new(),
        goals_reached: Vec::new(),
        start,
        goals: goals.to_vec(),
    };
    let sensed = believed.sense(truth, &disc(believed, start.cell, sim.sense_radius_cells))?;
    let clock = Instant::now();
    let (mission, plan) = Mission::plan(believed, model, planner.clone(), start, goals)?;
    report.plans.push(PlanRecord {
        step: 0,
        kind: PlanKind::Initial,
        t_s: start.t_min,
        wall_s: clock.elapsed().as_secs_f64(),
        expansions: plan.expansions,
        changed_cells: sensed.len(),
        search_bytes: mission.search_bytes(),
        route_changed: true,
        kept_rest: false,
        fresh: None,
        fresh_check: None,
        restart: None,
        plan: plan.clone(),
    });
    Ok((mission, plan, report))
}

/// Executes `action` from `cell` at `t` with `battery` (of `capacity`) on the true world
/// under `perturbation`; where the truth refuses it, the rover hibernates (or waits a step) instead. The
/// executed step (with the battery after it) and the lowest charge inside it: the
/// battery is checked at every integration sample of the action, not only at its end,
/// since a stay that drains before the Sun rises can run out inside it. `Err`: not even
/// that is possible, and why.
fn execute_step(
    executor: &ActionModel,
    truth: &World,
    (action, wait_s): (Action, Option<f64>),
    (cell, t, battery, capacity): (u32, f64, f64, f64),
    perturbation: Perturbation,
) -> std::result::Result<(ExecutedStep, f64), Binding> {
    let sun_elevation_deg = truth.sun(t).elevation_deg;
    let done = match (action, wait_s) {
        (Action::Wait, Some(d)) => executor.execute_wait(truth, cell, t, d, perturbation).map(|e| (cell, e)),
        _ => executor.execute(truth, action, cell, t, perturbation),
    };
    let (executed, refused, (to, effect)) = match done {
        Ok(o) => (action, None, o),
        Err(why) => {
            let stay = executor.fallback_stay();
            (stay, Some((action, why)), executor.execute(truth, stay, cell, t, perturbation)?)
        }
    };
    let step = ExecutedStep {
        t_s: t,
        cell,
        to,
        action: executed,
        duration_s: effect.duration_s,
        energy_wh: effect.energy_wh,
        load_wh: effect.load_wh,
        battery_above_floor_wh: effect.after(battery, capacity),
        distance_m: drive_length_m(truth, cell, to),
        sun_elevation_deg,
        refused,
    };
    Ok((step, effect.lowest(battery, capacity)))
}

/// The rover idles from `t` until `until` (a plan that starts later): the idle recorded,
/// the time and battery after it.
fn idle_until(
    report: &mut SimReport,
    (executor, truth): (&ActionModel, &World),
    (cell, t, battery, capacity): (u32, f64, f64, f64),
    until: f64,
) -> (f64, f64) {
    if until <= t + 1e-6 {
        return (t, battery);
    }
    let (idle, _) = idle_step(executor, truth, cell, t, until - t, battery, capacity);
    let after = idle.battery_above_floor_wh;
    report.steps.push(idle);
    (until, after)
}

/// On a tick a wait lasts until the plan's next step, however many ticks: its duration
/// from `t`, s (`None`: not a wait on a tick).
fn planned_wait_s(config: &PlannerConfig, plan: &MissionPlan, action: Action, t: f64) -> Option<f64> {
    config
        .search
        .tick_s()
        .filter(|_| action == Action::Wait)
        .and_then(|_| plan.waypoints.get(1))
        .map(|w| w.t_s - t)
        .filter(|&d| d > 1e-6)
}

/// On a tick the plan goes on from the next tick: after a drive that ends between ticks
/// the rover settles there (charging where lit, asleep where not) before it senses and
/// re-plans. The wait and the lowest charge inside it; `None` on a tick.
fn settle_step(
    executor: &ActionModel,
    truth: &World,
    (cell, t, battery, capacity): (u32, f64, f64, f64),
    tick: f64,
) -> Option<(ExecutedStep, f64)> {
    let next = ((t / tick + 1e-9).floor() + 1.0) * tick;
    if next - t <= 1e-6 || (t / tick - (t / tick).round()).abs() <= 1e-9 {
        return None;
    }
    Some(idle_step(executor, truth, cell, t, next - t, battery, capacity))
}

/// The record of re-plan (or restart) `p` made at (`step`, `t`) in `wall_s`, after
/// sensing changed `changed_cells` cells, with whether it changed the route; with
/// `compare`, the same problem searched afresh beside it.
fn record_replan(
    mission: &Mission<'_>,
    p: &MissionPlan,
    restart: Option<Restart>,
    (step, t, wall_s): (usize, f64, f64),
    (changed_cells, route_changed): (usize, bool),
    compare: Option<(fresh::PlannedOn<'_>, Start, &[u32])>,
) -> Result<PlanRecord> {
    let (fresh, fresh_check) = match compare {
        None => (None, None),
        // On a tick: a new planner instance from the rover's state.
        Some((problem, here, remaining)) if problem.2.search.tick_s().is_some() => {
            match FreshCheck::of(mission, p, problem, here, remaining)? {
                Some((fresh, check)) => (fresh, Some(check)),
                None => (None, None),
            }
        }
        Some(_) => (mission.fresh()?.map(|f| (f.expansions, f.cost)), None),
    };
    Ok(PlanRecord {
        step,
        kind: if restart.is_some() { PlanKind::Restart } else { PlanKind::Replan },
        t_s: t,
        wall_s,
        expansions: p.expansions,
        changed_cells,
        search_bytes: mission.search_bytes(),
        route_changed,
        kept_rest: restart.is_none() && mission.kept_rest(),
        fresh,
        fresh_check,
        restart,
        plan: p.clone(),
    })
}

/// Whether the rover, now at `cell` at `t`, has reached the next goal; if so it is
/// recorded and the mission moves on to the goal after it. At the last goal the plan may
/// still charge to the goal energy: the run ends when the plan does.
fn arrive(report: &mut SimReport, mission: &mut Mission<'_>, next_goal: &mut usize, cell: u32, t: f64) -> bool {
    if *next_goal >= report.goals.len() || cell != report.goals[*next_goal] {
        return false;
    }
    report.goals_reached.push((*next_goal, t));
    *next_goal += 1;
    if *next_goal < report.goals.len() {
        mission.goal_reached();
    }
    true
}

/// The run's random numbers (seeded, on the run's own stream) and the systematic
/// departure drawn once, before the first action, when the uncertainty model has one.
fn noise_source(sim: &SimConfig) -> (ChaCha8Rng, Option<Perturbation>) {
    let mut rng = ChaCha8Rng::seed_from_u64(sim.noise.seed);
    rng.set_stream(sim.stream);
    let once = sim.uncertainty.map(|u| u.sample(&mut rng));
    (rng, once)
}

/// The rover idling at the low load from `t` for `duration_s` (until its plan starts),
/// as an executed Hibernate (or a wait), and the lowest charge inside it.
fn idle_step(
    executor: &ActionModel,
    truth: &World,
    cell: u32,
    t: f64,
    duration_s: f64,
    battery: f64,
    capacity: f64,
) -> (ExecutedStep, f64) {
    // A rover that waits charges while it idles where its array sees the Sun.
    let (action, (energy_wh, load_wh), after, lowest) = match executor.idle_wait(truth, cell, t, duration_s) {
        Some(w) => (Action::Wait, (w.energy_wh, w.load_wh), w.after(battery, capacity), w.lowest(battery, capacity)),
        None => {
            // Asleep with the array off-line: the battery gives what the loads draw.
            let e = executor.idle_wh(duration_s);
            let after = (battery - e).min(capacity);
            (Action::Hibernate, (e, e), after, after)
        }
    };
    let step = ExecutedStep {
        t_s: t,
        cell,
        to: cell,
        action,
        duration_s,
        energy_wh,
        load_wh,
        battery_above_floor_wh: after,
        distance_m: 0.0,
        sun_elevation_deg: truth.sun(t).elevation_deg,
        refused: None,
    };
    (step, lowest)
}

/// The 3-D length of a drive from `cell` to `to` on `world`, m (0 for a stay).
fn drive_length_m(world: &World, cell: u32, to: u32) -> f64 {
    if to == cell {
        return 0.0;
    }
    let (a, b) = (world.center(cell), world.center(to));
    let rise = world.elevation(to).unwrap_or(0.0) - world.elevation(cell).unwrap_or(0.0);
    (a.0 - b.0).hypot(a.1 - b.1).hypot(rise)
}

/// The next action's departure from the nominal model: drawn from the uncertainty
/// model (about the run's systematic departure `once`, if any), or else the noise.
fn draw_perturbation(sim: &SimConfig, once: Option<Perturbation>, rng: &mut ChaCha8Rng) -> Perturbation {
    match (&sim.uncertainty, once) {
        (Some(u), Some(p)) => u.next(p, rng),
        (Some(u), None) => u.sample(rng),
        (None, _) => Perturbation::drive_and_solar(
            1.0 + sim.noise.drive_slowdown * rng.random::<f64>(),
            1.0 - sim.noise.solar_loss * rng.random::<f64>(),
        ),
    }
}

/// Plan extension and re-planning from `here` after sensing changed `changed`. The
/// re-plan keeps the mission's goal instants and graphs; when that finds nothing (their
/// discretisation can miss a narrow way through), the rover plans afresh from here to
/// the `remaining` goals, as an executive would, before declaring them unreachable —
/// a restart, returned with the failed re-plan's verdict and work and, with
/// `compare_fresh`, what a fresh search of the re-plan's own problem found.
fn replan<'a>(
    mission: &mut Mission<'a>,
    (believed, model, config): (&'a World, &'a ActionModel, &PlannerConfig),
    compare_fresh: bool,
    here: Start,
    changed: &[u32],
    remaining: &[u32],
) -> Result<(MissionPlan, Option<Restart>)> {
    let (binding, reason) = match mission.advance(here, changed) {
        Ok(p) => return Ok((p, None)),
        Err(Error::Unreachable { binding, message, .. }) => (binding, message),
        Err(e) => return Err(e),
    };
    let replan_work = mission.last_call_work();
    // The re-plan is compared like every other: the same problem searched from scratch
    // on the kept goal instants.
    let fresh_found = if compare_fresh { Some(mission.fresh()?.is_some()) } else { None };
    let restart = Restart { binding, reason, replan_work, fresh_found };
    // The kept graphs stay alive until the new mission replaces them.
    let held = mission.search_bytes();
    let fresh =
        PlannerConfig { max_search_bytes: config.max_search_bytes.map(|m| m.saturating_sub(held)), ..config.clone() };
    // Past the last goal the plan only stays there (to reach the goal energy): the
    // fresh plan is to that goal from where the rover stands (`remaining`).
    let (m, p) = Mission::plan(believed, model, fresh, here, remaining)?;
    *mission = m;
    Ok((p, Some(restart)))
}

/// The cells within `radius` cells (centre to centre) of `cell`.
fn disc(world: &World, cell: u32, radius: f64) -> Vec<u32> {
    let (c, r) = world.col_row(cell);
    let k = radius.floor() as i64;
    let mut out = Vec::new();
    for dr in -k..=k {
        for dc in -k..=k {
            if ((dc * dc + dr * dr) as f64).sqrt() > radius + 1e-9 {
                continue;
            }
            let (nc, nr) = (c as i64 + dc, r as i64 + dr);
            if nc >= 0 && nr >= 0 && (nc as usize) < world.cols() && (nr as usize) < world.rows() {
                out.push(world.cell(nc as usize, nr as usize));
            }
        }
    }
    out
}

/// Whether `new` drives the same cells as what remains of `old` from `cell` on.
fn same_route(old: &MissionPlan, new: &MissionPlan, cell: u32) -> bool {
    let route = |p: &MissionPlan| {
        let mut cells: Vec<u32> = p.waypoints.iter().map(|w| w.cell).collect();
        cells.dedup();
        cells
    };
    let old_route = route(old);
    let Some(at) = old_route.iter().position(|&c| c == cell) else {
        return false;
    };
    old_route[at..] == route(new)[..]
}
