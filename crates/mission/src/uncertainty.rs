//! Plans under uncertainty: what TEMPEST's section 8 proposes — "constraints defined by
//! confidence intervals on arrival time and battery energy within ISE" — and a Monte
//! Carlo check of what such a plan buys.
//!
//! [`Uncertainty`] describes how execution departs from the model: each drive's
//! duration, each electrical load and each solar input multiplied by a normal factor
//! of mean 1 and a stated σ — drawn once per execution (a systematic departure, the
//! default) or for every action ([`Correlation`]) — and the confidence wanted. A
//! **chance-constrained plan** is made with the model worsened by each factor's
//! quantile at that confidence ([`Uncertainty::margins`], [`ActionModel::with_margins`]):
//! every action is planned as if it were that slow and that hungry, under that little
//! sunlight, and every constraint — the battery floor, darkness, shadows, sessions, the
//! horizon — is checked there. What that guarantees, under the model's normal factors:
//! any sum of the actions' durations or energies along the plan, `Σ dᵢ·fᵢ`, has mean
//! `Σ dᵢ` and standard deviation `σ·Σdᵢ` when one factor holds for the whole execution
//! (the margin `Σ dᵢ·(1 + zσ)` is then exactly its quantile) and `σ·√Σdᵢ² ≤ σ·Σdᵢ`
//! when every action draws its own (the margin is then conservative): exceeded with
//! probability at most 1 − confidence either way. The bound is per quantity and conservative; constraints that read a
//! time (darkness, shadows) are met early rather than late because the rover executes
//! each action no earlier than planned. [`open_loop`] measures what it buys.
//!
//! The search itself is unchanged: it runs over a model whose every action is worse,
//! so dominance, re-planning and `compare_fresh` work as in deterministic mode, and a
//! confidence of 0.5 (z = 0) or zero σ gives the deterministic plan exactly.
//!
//! The map's height error is a different kind of uncertainty — it moves slopes and
//! shadows cell by cell — so it is planned for on a different world:
//! [`planning_clones`] draws error clones of the map ([`dem_clone`]) and
//! [`World::envelope`] makes the world on which every drive costs its worst over them,
//! a cell is lit only where every one is lit and the array earns no more than the least
//! any gives; a plan made there holds on each clone (tests/terrain_error.rs), and
//! [`open_loop_on`] measures how it does on clones it never saw.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, Normal as StdNormal};

use crate::action_model::{ActionModel, Binding, Perturbation};
use crate::domain::Start;
use crate::error::{Error, Result};
use crate::plan::MissionPlan;
use crate::simulate::{SimReport, SimStatus, Simulation, simulate};
use crate::world::World;

/// Whether the factors are drawn once per execution or for every action.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Correlation {
    /// Once per execution: a systematic departure that holds all traverse long (a
    /// slip regime, dust on the array, a heater's draw). The margins are then exactly
    /// each quantity's quantile.
    #[default]
    Execution,
    /// Independently for every action: the margins are then conservative (a sum of
    /// independent factors spreads less than their sum of spreads).
    Action,
}

/// How execution departs from the model, and the confidence a plan must hold at
/// (scenario field `uncertainty:`). Every σ is a fraction of the nominal value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Uncertainty {
    /// Probability each planned quantity must hold with, 0.5..=0.999 (0.5: the
    /// deterministic plan).
    pub confidence: f64,
    /// σ of each drive's duration factor (slip, detours around rocks), 0..=0.5.
    pub drive_time_sigma: f64,
    /// σ of each action's electrical load factor (heaters, motor wear), 0..=0.5.
    pub power_draw_sigma: f64,
    /// σ of each action's solar input factor (dust, optical depth), 0..=0.5.
    pub solar_sigma: f64,
    /// σ of the delay before each action, s, 0..=3600: the rover waits |N(0, σ)| before
    /// every action (a late command, a wait for data), at the action's load with the
    /// array off-line.
    pub action_delay_sigma_s: f64,
    /// σ of the start's delay, s, 0..=86 400: the rover is ready |N(0, σ)| after the
    /// start window opens (a late uplink, a slow wake-up), with the stated charge.
    pub start_delay_sigma_s: f64,
    /// RMS error of the map's heights, m, 0..=100 (LOLA's polar DEMs: 0.3–0.5 m): the
    /// Monte Carlo executes on `terrain_clones` error clones of the map instead of the
    /// truth ([`dem_clone`]).
    pub terrain_sigma_m: f64,
    /// Correlation length of the height error, m (at least two cells of the map).
    pub terrain_correlation_m: f64,
    /// How many error clones the executions share (run i drives on clone i mod n),
    /// 0..=100; 0: the executions drive on the truth.
    pub terrain_clones: usize,
    /// How many error clones the plan must hold on, 0..=100 (0: it is made on the map
    /// alone): it is made on the envelope of the map and that many clones
    /// ([`World::envelope`], [`planning_clones`]), from seeds the Monte Carlo's never
    /// reach ([`PLANNING_CLONE_SEED`]).
    pub terrain_plan_clones: usize,
    /// Whether an execution draws its factors once or for every action.
    pub correlation: Correlation,
}

impl Default for Uncertainty {
    fn default() -> Uncertainty {
        Uncertainty {
            confidence: 0.95,
            drive_time_sigma: 0.0,
            power_draw_sigma: 0.0,
            solar_sigma: 0.0,
            action_delay_sigma_s: 0.0,
            start_delay_sigma_s: 0.0,
            terrain_sigma_m: 0.0,
            terrain_correlation_m: 100.0,
            terrain_clones: 0,
            terrain_plan_clones: 0,
            correlation: Correlation::Execution,
        }
    }
}

impl Uncertainty {
    /// Checks ranges, naming the first bad field.
    pub fn validate(&self) -> Result<()> {
        let bad = |field: &'static str, message: String| Err(Error::Config { field, message });
        if !(0.5..=0.999).contains(&self.confidence) {
            return bad("uncertainty.confidence", format!("{}: allowed 0.5..=0.999", self.confidence));
        }
        for (field, v) in [
            ("uncertainty.drive_time_sigma", self.drive_time_sigma),
            ("uncertainty.power_draw_sigma", self.power_draw_sigma),
            ("uncertainty.solar_sigma", self.solar_sigma),
        ] {
            if !(0.0..=0.5).contains(&v) {
                return bad(field, format!("{v}: allowed 0..=0.5 (a fraction of the nominal value)"));
            }
        }
        if !(0.0..=100.0).contains(&self.terrain_sigma_m) {
            return bad("uncertainty.terrain_sigma_m", format!("{} m: allowed 0..=100", self.terrain_sigma_m));
        }
        if !(self.terrain_correlation_m > 0.0 && self.terrain_correlation_m <= 1e6) {
            return bad(
                "uncertainty.terrain_correlation_m",
                format!("{} m: allowed > 0 and ≤ 1e6", self.terrain_correlation_m),
            );
        }
        if self.terrain_clones > 100 {
            return bad("uncertainty.terrain_clones", format!("{}: allowed 0..=100", self.terrain_clones));
        }
        if self.terrain_plan_clones > 100 {
            return bad("uncertainty.terrain_plan_clones", format!("{}: allowed 0..=100", self.terrain_plan_clones));
        }
        if self.terrain_plan_clones > 0 && self.terrain_sigma_m == 0.0 {
            return bad(
                "uncertainty.terrain_plan_clones",
                format!("{}: needs a height error (terrain_sigma_m > 0)", self.terrain_plan_clones),
            );
        }
        if !(0.0..=3600.0).contains(&self.action_delay_sigma_s) {
            return bad(
                "uncertainty.action_delay_sigma_s",
                format!("{} s: allowed 0..=3600", self.action_delay_sigma_s),
            );
        }
        if !(0.0..=86_400.0).contains(&self.start_delay_sigma_s) {
            return bad(
                "uncertainty.start_delay_sigma_s",
                format!("{} s: allowed 0..=86400", self.start_delay_sigma_s),
            );
        }
        Ok(())
    }

    /// The start delay the plan allows for, s: the confidence's quantile of the
    /// half-normal delay, σ·Φ⁻¹((1 + confidence)/2) (a delay is never negative, so its
    /// median is 0.674 σ: only σ = 0 gives no margin).
    pub fn start_delay_margin_s(&self) -> f64 {
        if self.start_delay_sigma_s == 0.0 {
            return 0.0;
        }
        self.start_delay_sigma_s * StdNormal::standard().inverse_cdf(0.5 * (1.0 + self.confidence))
    }

    /// The start a chance-constrained plan is made from: the window moved later by
    /// [`Uncertainty::start_delay_margin_s`].
    pub fn planning_start(&self, start: Start) -> Start {
        let m = self.start_delay_margin_s();
        Start { t_min: start.t_min + m, t_max: start.t_max + m, ..start }
    }

    /// One execution's start delay, s (0 without a σ; drawn from its own generator so
    /// the factors' draws do not depend on it).
    fn sample_start_delay(&self, seed: u64, run: usize) -> f64 {
        if self.start_delay_sigma_s == 0.0 {
            return 0.0;
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ START_DELAY_SALT);
        rng.set_stream(run as u64);
        Normal::new(0.0, self.start_delay_sigma_s).map_or(0.0, |n| n.sample(&mut rng).abs())
    }

    /// The standard normal quantile of the confidence (0 at 0.5, 1.645 at 0.95).
    pub fn z(&self) -> f64 {
        if self.confidence <= 0.5 {
            return 0.0;
        }
        StdNormal::standard().inverse_cdf(self.confidence)
    }

    /// The planning margins: each factor at its quantile (the solar one at its lower
    /// quantile, never below 0).
    pub fn margins(&self) -> Perturbation {
        let z = self.z();
        Perturbation {
            duration_factor: 1.0 + z * self.drive_time_sigma,
            solar_factor: (1.0 - z * self.solar_sigma).max(0.0),
            draw_factor: 1.0 + z * self.power_draw_sigma,
            delay_s: self.action_delay_margin_s(),
        }
    }

    /// The delay before each action the plan allows for, s: the confidence's quantile of
    /// the half-normal delay, σ·Φ⁻¹((1 + confidence)/2) (0 without a σ).
    pub fn action_delay_margin_s(&self) -> f64 {
        if self.action_delay_sigma_s == 0.0 {
            return 0.0;
        }
        self.action_delay_sigma_s * StdNormal::standard().inverse_cdf(0.5 * (1.0 + self.confidence))
    }

    /// One action's delay, s, |N(0, σ)|; nothing is drawn without a σ (so the other
    /// draws do not move).
    pub(crate) fn sample_delay(&self, rng: &mut ChaCha8Rng) -> f64 {
        if self.action_delay_sigma_s == 0.0 {
            return 0.0;
        }
        Normal::new(0.0, self.action_delay_sigma_s).map_or(0.0, |n| n.sample(rng).abs())
    }

    /// One action's departures: the factors (`once` for a systematic departure, else
    /// drawn now) and a delay drawn for the action.
    pub(crate) fn next(&self, once: Perturbation, rng: &mut ChaCha8Rng) -> Perturbation {
        let base = match self.correlation {
            Correlation::Execution => once,
            Correlation::Action => self.sample(rng),
        };
        Perturbation { delay_s: self.sample_delay(rng), ..base }
    }

    /// One action's factors, drawn independently (normal, mean 1, the σ above; a factor
    /// is kept at 0.05 or more, and solar input at 0 or more).
    pub(crate) fn sample(&self, rng: &mut ChaCha8Rng) -> Perturbation {
        let mut draw = |sigma: f64| -> f64 {
            if sigma == 0.0 {
                return 1.0;
            }
            // σ ≤ 0.5 is validated: the distribution exists.
            Normal::new(1.0, sigma).map_or(1.0, |n| n.sample(rng))
        };
        Perturbation {
            duration_factor: draw(self.drive_time_sigma).max(0.05),
            solar_factor: draw(self.solar_sigma).max(0.0),
            draw_factor: draw(self.power_draw_sigma).max(0.05),
            delay_s: 0.0,
        }
    }
}

/// An error clone of `dem`: its heights plus a smooth random field of RMS exactly
/// `sigma_m` whose features are about `correlation_m` across (value noise of that
/// wavelength, rescaled to the RMS), from `seed` — one of the equally likely maps a DEM
/// with that error could stand for. Cells without data stay without.
pub fn dem_clone(dem: &areo_terrain::Dem, sigma_m: f64, correlation_m: f64, seed: u64) -> Result<areo_terrain::Dem> {
    use areo_terrain::synth::{Noise, TerrainSpec};
    let cell = dem.dx().max(dem.dy());
    if !(correlation_m >= 2.0 * cell) {
        return Err(Error::Config {
            field: "uncertainty.terrain_correlation_m",
            message: format!("{correlation_m} m: allowed at least two cells ({} m)", 2.0 * cell),
        });
    }
    let field = TerrainSpec {
        cols: dem.cols(),
        rows: dem.rows(),
        cell_m: cell,
        base_m: 0.0,
        seed,
        noise: Some(Noise { amplitude_m: 1.0, wavelength_m: correlation_m, octaves: 1, persistence: 0.5 }),
        features: Vec::new(),
    }
    .build()?;
    let e = field.elevations();
    let mean = e.iter().map(|&v| f64::from(v)).sum::<f64>() / e.len().max(1) as f64;
    let rms = (e.iter().map(|&v| (f64::from(v) - mean).powi(2)).sum::<f64>() / e.len().max(1) as f64).sqrt();
    let scale = if rms > 0.0 { sigma_m / rms } else { 0.0 };
    let heights = dem.elevations().iter().zip(e).map(|(&z, &v)| z + ((f64::from(v) - mean) * scale) as f32).collect();
    Ok(dem.with_values(heights)?)
}

/// Separates the start delays' generator from the factors' (same seed).
const START_DELAY_SALT: u64 = 0x5354_4152_545f_444c;

/// How many executions, and the seed they are drawn from (scenario field
/// `monte_carlo:`). Run `i` draws from the ChaCha8 stream `i` of the seed, so the
/// results do not depend on how many threads run them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MonteCarlo {
    /// Executions, 1..=100 000.
    pub runs: usize,
    /// Seed.
    pub seed: u64,
}

impl Default for MonteCarlo {
    fn default() -> MonteCarlo {
        MonteCarlo { runs: 1000, seed: 1 }
    }
}

impl MonteCarlo {
    /// Checks ranges, naming the first bad field.
    pub fn validate(&self) -> Result<()> {
        if !(1..=100_000).contains(&self.runs) {
            return Err(Error::Config {
                field: "monte_carlo.runs",
                message: format!("{}: allowed 1..=100000", self.runs),
            });
        }
        Ok(())
    }
}

/// Why an open-loop execution failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RunFailure {
    /// The world refused a planned action (a drive ending after dark, a charge in
    /// shadow, past the horizon, …).
    Refused(Binding),
    /// The battery fell below its floor.
    BatteryDepleted,
    /// Closed loop: a re-plan found no way on (the binding constraint).
    Unreachable(Binding),
    /// Closed loop: the simulation's step limit ran out.
    StepLimit,
}

impl RunFailure {
    /// A short name for tables and facts.
    pub fn name(self) -> String {
        match self {
            RunFailure::Refused(b) => format!("refused_{}", format!("{b:?}").to_lowercase()),
            RunFailure::BatteryDepleted => "battery_depleted".into(),
            RunFailure::Unreachable(b) => format!("unreachable_{}", format!("{b:?}").to_lowercase()),
            RunFailure::StepLimit => "step_limit".into(),
        }
    }
}

/// One execution of a plan on sampled factors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SampledRun {
    /// The run's index (its random stream).
    pub run: usize,
    /// Why it failed, at which step of the plan; `None`: every goal reached.
    pub failure: Option<(usize, RunFailure)>,
    /// Arrival time at each goal reached, s after the epoch, in goal order.
    pub arrivals_s: Vec<f64>,
    /// The lowest battery charge along the way, Wh above the floor (negative when it
    /// fell below).
    pub lowest_battery_wh: f64,
    /// Battery charge after each executed action, Wh above the floor, with the time
    /// the action ended, s.
    pub battery_wh: Vec<(f64, f64)>,
}

impl SampledRun {
    /// Whether every goal was reached with the battery never below its floor.
    pub fn succeeded(&self) -> bool {
        self.failure.is_none()
    }
}

/// Executes `plan` open-loop — each action as planned, none earlier than its planned
/// start, with no re-planning — on `world` with `model` (its nominal form), `mc.runs`
/// times, each action's factors drawn from `uncertainty`. Runs in parallel; the result
/// is in run order and the same whatever the thread count.
pub fn open_loop(
    plan: &MissionPlan,
    model: &ActionModel,
    world: &World,
    start: Start,
    uncertainty: &Uncertainty,
    mc: &MonteCarlo,
) -> Result<Vec<SampledRun>> {
    open_loop_on(plan, model, std::slice::from_ref(world), start, uncertainty, mc)
}

/// The first seed of the error clones a plan is made to hold on: clone i of
/// [`planning_clones`] is drawn from seed `PLANNING_CLONE_SEED + i`, far from the seeds
/// the Monte Carlo draws its clones from (its own seed + i), so a plan is never checked
/// on the clones it was made for.
pub const PLANNING_CLONE_SEED: u64 = 1 << 63;

/// `uncertainty.terrain_plan_clones` error clones of the believed map `world`, each a
/// world built with `config` and `sun_model` ([`World::truth`]); none without a height
/// error. Planning on [`World::envelope`] of the map and these makes a plan that holds
/// on every one of them.
pub fn planning_clones(
    uncertainty: &Uncertainty,
    world: &World,
    config: &crate::WorldConfig,
    sun_model: &(impl areo_ephemeris::SunModel + Sync),
) -> Result<Vec<World>> {
    if uncertainty.terrain_plan_clones == 0 || uncertainty.terrain_sigma_m == 0.0 {
        return Ok(Vec::new());
    }
    (0..uncertainty.terrain_plan_clones as u64)
        .into_par_iter()
        .map(|i| {
            let dem = dem_clone(
                world.dem(),
                uncertainty.terrain_sigma_m,
                uncertainty.terrain_correlation_m,
                PLANNING_CLONE_SEED + i,
            )?;
            World::truth(dem, config, sun_model, world)
        })
        .collect()
}

/// [`open_loop`] on several worlds — error clones of the map ([`dem_clone`]): run i
/// drives on `worlds[i mod n]`.
pub fn open_loop_on(
    plan: &MissionPlan,
    model: &ActionModel,
    worlds: &[World],
    start: Start,
    uncertainty: &Uncertainty,
    mc: &MonteCarlo,
) -> Result<Vec<SampledRun>> {
    if worlds.is_empty() {
        return Err(Error::Config { field: "uncertainty.terrain_clones", message: "no world to execute on".into() });
    }
    uncertainty.validate()?;
    mc.validate()?;
    let nominal = model.nominal();
    Ok((0..mc.runs)
        .into_par_iter()
        .map(|run| {
            let mut rng = ChaCha8Rng::seed_from_u64(mc.seed);
            rng.set_stream(run as u64);
            let once = uncertainty.sample(&mut rng);
            let delay = uncertainty.sample_start_delay(mc.seed, run);
            let ready = Start { t_min: start.t_min + delay, ..start };
            let world = &worlds[run % worlds.len()];
            execute_once(plan, &nominal, world, ready, run, |_| uncertainty.next(once, &mut rng))
        })
        .collect())
}

/// Executes a mission closed-loop — planning, executing each action on the truth with
/// factors drawn from `uncertainty`, sensing and re-planning after every action, as
/// [`simulate`] does — `mc.runs` times, run i on the ChaCha8 stream i of `mc.seed`.
/// Runs in parallel; the result is in run order and the same whatever the thread
/// count, and leaves `simulation.believed` as it was. The simulation's own noise is
/// replaced by the draws.
pub fn closed_loop(simulation: &Simulation<'_>, uncertainty: &Uncertainty, mc: &MonteCarlo) -> Result<Vec<SampledRun>> {
    closed_loop_on(simulation, &[], uncertainty, mc)
}

/// [`closed_loop`] with run i driving on `truths[i % truths.len()]` (error clones of the
/// true terrain, [`dem_clone`]) in place of the simulation's truth, which it drives on
/// when `truths` is empty. The rover believes the simulation's map and learns the
/// clone's heights by sensing.
pub fn closed_loop_on(
    simulation: &Simulation<'_>,
    truths: &[World],
    uncertainty: &Uncertainty,
    mc: &MonteCarlo,
) -> Result<Vec<SampledRun>> {
    uncertainty.validate()?;
    mc.validate()?;
    (0..mc.runs)
        .into_par_iter()
        .map(|run| {
            // Each run believes the map as the call found it: sensing writes into the
            // world a simulation believes, and one run must not learn from another.
            let believed = simulation.believed.snapshot();
            let truth = if truths.is_empty() { simulation.truth } else { &truths[run % truths.len()] };
            let mut s = Simulation { believed: &believed, truth, ..simulation.clone() };
            // A late start is known when the rover wakes: it plans from then.
            let delay = uncertainty.sample_start_delay(mc.seed, run);
            s.start =
                Start { t_min: s.start.t_min + delay, t_max: s.start.t_max.max(s.start.t_min + delay), ..s.start };
            s.config.uncertainty = Some(*uncertainty);
            s.config.noise.seed = mc.seed;
            s.config.stream = run as u64;
            let report = simulate(&s, &mut |_| {})?;
            Ok(execution_of(run, &report))
        })
        .collect()
}

/// A simulated run as an [`SampledRun`].
fn execution_of(run: usize, r: &SimReport) -> SampledRun {
    let n = r.steps.len();
    let failure = match &r.status {
        SimStatus::Completed => None,
        SimStatus::BatteryDepleted => Some((n, RunFailure::BatteryDepleted)),
        SimStatus::Unreachable { binding, .. } => Some((n, RunFailure::Unreachable(*binding))),
        SimStatus::Stuck(b) => Some((n, RunFailure::Refused(*b))),
        SimStatus::StepLimit => Some((n, RunFailure::StepLimit)),
    };
    let battery_wh: Vec<(f64, f64)> =
        r.steps.iter().map(|s| (s.t_s + s.duration_s, s.battery_above_floor_wh)).collect();
    SampledRun {
        run,
        failure,
        arrivals_s: r.goals_reached.iter().map(|g| g.1).collect(),
        lowest_battery_wh: battery_wh.iter().map(|b| b.1).fold(r.start.energy_wh, f64::min),
        battery_wh,
    }
}

/// One open-loop execution, each action's factors from `factors(step)`.
fn execute_once(
    plan: &MissionPlan,
    model: &ActionModel,
    world: &World,
    start: Start,
    run: usize,
    mut factors: impl FnMut(usize) -> Perturbation,
) -> SampledRun {
    let capacity = model.capacity_wh();
    let (mut cell, mut t, mut battery) = (start.cell, start.t_min, start.energy_wh);
    let mut out =
        SampledRun { run, failure: None, arrivals_s: Vec::new(), lowest_battery_wh: battery, battery_wh: Vec::new() };
    for (step, w) in plan.waypoints.iter().enumerate() {
        // A goal's first waypoint is the arrival (the plan may charge there after).
        if w.goal == Some(out.arrivals_s.len()) {
            out.arrivals_s.push(t);
        }
        let Some(action) = w.action else { break };
        let p = factors(step);
        // Not before its planned start: an early rover sleeps until then.
        if w.t_s > t {
            battery = match model.idle_wait(world, cell, t, w.t_s - t) {
                Some(wait) => {
                    // A wait (a settle on a tick, a night) can dip inside.
                    out.lowest_battery_wh = out.lowest_battery_wh.min(wait.lowest(battery, capacity));
                    wait.after(battery, capacity)
                }
                None => (battery - model.idle_wh(w.t_s - t) * p.draw_factor).min(capacity),
            };
            t = w.t_s;
        }
        match model.execute(world, action, cell, t, p) {
            Ok((to, effect)) => {
                cell = to;
                t += effect.duration_s;
                // Checked inside the action too (its integration samples).
                out.lowest_battery_wh = out.lowest_battery_wh.min(effect.lowest(battery, capacity));
                battery = effect.after(battery, capacity);
            }
            Err(binding) => {
                out.failure = Some((step, RunFailure::Refused(binding)));
                return out;
            }
        }
        out.battery_wh.push((t, battery));
        out.lowest_battery_wh = out.lowest_battery_wh.min(battery);
        if out.lowest_battery_wh < -1e-9 {
            out.failure = Some((step, RunFailure::BatteryDepleted));
            return out;
        }
    }
    out
}

/// What a set of executions shows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Executions.
    pub runs: usize,
    /// Executions that reached every goal with the battery never below its floor.
    pub succeeded: usize,
    /// `succeeded / runs`.
    pub success_probability: f64,
    /// Wilson score interval of the success probability at 95 %.
    pub success_interval: (f64, f64),
    /// Executions whose battery never fell below its floor (whether or not every action
    /// was allowed).
    pub battery_ok_probability: f64,
    /// The fraction of executions that reached each goal.
    pub goal_probability: Vec<f64>,
    /// The last goal's arrival time over the executions that reached it, s: 5th, 50th
    /// and 95th percentiles.
    pub last_arrival_s: Option<(f64, f64, f64)>,
    /// The lowest battery charge, Wh above the floor: 5th and 50th percentiles.
    pub lowest_battery_wh: (f64, f64),
    /// How many executions failed each way, by [`RunFailure::name`], sorted by name.
    pub failures: Vec<(String, usize)>,
}

/// Summarises executions of a plan to `goals` goals.
pub fn summarise(executions: &[SampledRun], goals: usize) -> Summary {
    let n = executions.len().max(1);
    let succeeded = executions.iter().filter(|e| e.succeeded()).count();
    let battery_ok = executions.iter().filter(|e| e.lowest_battery_wh >= 0.0).count();
    let goal_probability =
        (0..goals).map(|g| executions.iter().filter(|e| e.arrivals_s.len() > g).count() as f64 / n as f64).collect();
    let mut last: Vec<f64> = executions
        .iter()
        .filter(|e| e.arrivals_s.len() >= goals)
        .filter_map(|e| e.arrivals_s.last().copied())
        .collect();
    last.sort_by(f64::total_cmp);
    let mut lowest: Vec<f64> = executions.iter().map(|e| e.lowest_battery_wh).collect();
    lowest.sort_by(f64::total_cmp);
    let mut failures: Vec<(String, usize)> = Vec::new();
    for e in executions {
        if let Some((_, f)) = e.failure {
            let name = f.name();
            match failures.iter_mut().find(|(k, _)| *k == name) {
                Some(entry) => entry.1 += 1,
                None => failures.push((name, 1)),
            }
        }
    }
    failures.sort();
    Summary {
        runs: executions.len(),
        succeeded,
        success_probability: succeeded as f64 / n as f64,
        success_interval: wilson(succeeded, executions.len()),
        battery_ok_probability: battery_ok as f64 / n as f64,
        goal_probability,
        last_arrival_s: (!last.is_empty())
            .then(|| (percentile(&last, 0.05), percentile(&last, 0.5), percentile(&last, 0.95))),
        lowest_battery_wh: (percentile(&lowest, 0.05), percentile(&lowest, 0.5)),
        failures,
    }
}

/// The `q` quantile of sorted values (nearest rank).
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let k = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[k - 1]
}

/// The Wilson score interval for `k` successes in `n` trials at 95 %.
pub fn wilson(k: usize, n: usize) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let z = 1.959_963_984_540_054;
    let (n, p) = (n as f64, k as f64 / n as f64);
    let centre = p + z * z / (2.0 * n);
    let half = z * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt();
    let d = 1.0 + z * z / n;
    (((centre - half) / d).max(0.0), ((centre + half) / d).min(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_quantile_and_the_margins_follow_the_confidence() {
        let mut u = Uncertainty {
            confidence: 0.95,
            drive_time_sigma: 0.1,
            power_draw_sigma: 0.05,
            solar_sigma: 0.2,
            ..Uncertainty::default()
        };
        // Φ⁻¹(0.95) = 1.644854 (tables).
        assert!((u.z() - 1.644_853_6).abs() < 1e-6);
        let m = u.margins();
        assert!((m.duration_factor - 1.164_485_4).abs() < 1e-6);
        assert!((m.draw_factor - 1.082_242_7).abs() < 1e-6);
        assert!((m.solar_factor - (1.0 - 0.328_970_7)).abs() < 1e-6);
        u.confidence = 0.5;
        assert_eq!(u.margins(), Perturbation::NONE);
        u.confidence = 0.99;
        assert!((u.z() - 2.326_347_9).abs() < 1e-6);
        u.confidence = 1.0;
        assert!(u.validate().unwrap_err().to_string().contains("uncertainty.confidence"));
        u.confidence = 0.9;
        u.solar_sigma = 0.7;
        assert!(u.validate().unwrap_err().to_string().contains("uncertainty.solar_sigma"));
    }

    #[test]
    fn start_delays_are_half_normal_and_the_margin_is_their_quantile() {
        let u = Uncertainty { confidence: 0.95, start_delay_sigma_s: 600.0, ..Uncertainty::default() };
        // Φ⁻¹(0.975) = 1.959964 (tables).
        assert!((u.start_delay_margin_s() - 600.0 * 1.959_964).abs() < 1e-3);
        let start = Start { cell: 3, t_min: 100.0, t_max: 160.0, energy_wh: 5.0 };
        let s = u.planning_start(start);
        assert!((s.t_min - 100.0 - 1175.978).abs() < 1e-2 && (s.t_max - s.t_min - 60.0).abs() < 1e-9);
        let n = 20_000;
        let d: Vec<f64> = (0..n).map(|i| u.sample_start_delay(9, i)).collect();
        assert!(d.iter().all(|&x| x >= 0.0));
        // The half-normal's mean is σ·√(2/π) = 478.7 s; 5 % of delays exceed the margin.
        let mean = d.iter().sum::<f64>() / n as f64;
        assert!((mean - 478.73).abs() < 10.0, "{mean}");
        let above = d.iter().filter(|&&x| x > u.start_delay_margin_s()).count() as f64 / n as f64;
        assert!((above - 0.05).abs() < 0.006, "{above}");
        let none = Uncertainty::default();
        assert_eq!((none.start_delay_margin_s(), none.sample_start_delay(9, 3)), (0.0, 0.0));
        assert!(Uncertainty { start_delay_sigma_s: -1.0, ..none }.validate().is_err());
    }

    #[test]
    fn an_error_clone_has_the_stated_rms_and_is_smooth_at_its_correlation_length() {
        let dem = areo_terrain::Dem::from_fn(120, 90, 10.0, 10.0, |x, y| 0.01 * x - 0.02 * y).unwrap();
        let a = dem_clone(&dem, 0.4, 200.0, 1).unwrap();
        let b = dem_clone(&dem, 0.4, 200.0, 2).unwrap();
        let diff = |c: &areo_terrain::Dem| -> Vec<f64> {
            c.elevations().iter().zip(dem.elevations()).map(|(p, q)| f64::from(p - q)).collect()
        };
        let (da, db) = (diff(&a), diff(&b));
        let rms = |d: &[f64]| (d.iter().map(|v| v * v).sum::<f64>() / d.len() as f64).sqrt();
        assert!((rms(&da) - 0.4).abs() < 1e-4, "{}", rms(&da));
        // Different seeds, different maps; the same seed, the same map.
        assert!(da.iter().zip(&db).any(|(p, q)| (p - q).abs() > 0.1));
        assert_eq!(dem_clone(&dem, 0.4, 200.0, 1).unwrap().elevations(), a.elevations());
        // Correlated over 200 m = 20 cells: neighbouring cells' errors differ by far less
        // than independent errors would (√2·σ ≈ 0.57 m RMS).
        let step: Vec<f64> = (0..90)
            .flat_map(|r| (0..119).map(move |c| (r, c)))
            .map(|(r, c)| da[r * 120 + c + 1] - da[r * 120 + c])
            .collect();
        assert!(rms(&step) < 0.15 * 0.57, "{}", rms(&step));
        // A correlation shorter than two cells is refused by name.
        assert!(dem_clone(&dem, 0.4, 15.0, 1).unwrap_err().to_string().contains("terrain_correlation_m"));
    }

    #[test]
    fn wilson_intervals_match_published_values() {
        // Wilson (1927) interval for 81 of 263 at 95 %: (0.2553, 0.3662) (Newcombe 1998,
        // Statistics in Medicine 17, table I, example).
        let (lo, hi) = wilson(81, 263);
        assert!((lo - 0.2553).abs() < 1e-4 && (hi - 0.3662).abs() < 1e-4, "{lo} {hi}");
        // 15 of 148: (0.0624, 0.1605).
        let (lo, hi) = wilson(15, 148);
        assert!((lo - 0.0624).abs() < 1e-4 && (hi - 0.1605).abs() < 1e-4, "{lo} {hi}");
        // All successes: the upper end is 1.
        assert_eq!(wilson(1000, 1000).1, 1.0);
        assert!((wilson(1000, 1000).0 - 0.99617).abs() < 1e-4);
    }

    #[test]
    fn sampled_factors_have_the_stated_mean_and_spread() {
        let u = Uncertainty {
            confidence: 0.9,
            drive_time_sigma: 0.1,
            power_draw_sigma: 0.2,
            solar_sigma: 0.05,
            correlation: Correlation::Action,
            ..Uncertainty::default()
        };
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let n = 20_000;
        let draws: Vec<Perturbation> = (0..n).map(|_| u.sample(&mut rng)).collect();
        for (get, sigma) in [
            (&(|p: &Perturbation| p.duration_factor) as &dyn Fn(&Perturbation) -> f64, 0.1),
            (&|p: &Perturbation| p.draw_factor, 0.2),
            (&|p: &Perturbation| p.solar_factor, 0.05),
        ] {
            let v: Vec<f64> = draws.iter().map(get).collect();
            let mean = v.iter().sum::<f64>() / n as f64;
            let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64).sqrt();
            // Standard errors: σ/√n ≤ 0.0015 for the mean.
            assert!((mean - 1.0).abs() < 0.006 && (sd - sigma).abs() < 0.05 * sigma, "{mean} {sd} vs {sigma}");
            // The margin's quantile is exceeded by about 1 − confidence of the draws.
            let above = v.iter().filter(|&&x| x > 1.0 + u.z() * sigma).count() as f64 / n as f64;
            assert!((above - 0.1).abs() < 0.01, "{above}");
        }
    }
}
