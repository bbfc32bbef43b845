//! The scenario format's own types for a TEMPEST job's planner and simulation settings.
//! They mirror areo-mission's configuration types field for field and convert into
//! them (defaults are the library's), so renaming a library field cannot change what a
//! scenario file says.

use areo_mission as m;
use serde::{Deserialize, Serialize};

/// An electronics level.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum LoadLevelSpec {
    /// Low.
    Low,
    /// Medium.
    Medium,
    /// High.
    High,
}

impl LoadLevelSpec {
    fn to_lib(self) -> m::LoadLevel {
        match self {
            LoadLevelSpec::Low => m::LoadLevel::Low,
            LoadLevelSpec::Medium => m::LoadLevel::Medium,
            LoadLevelSpec::High => m::LoadLevel::High,
        }
    }
    fn of(l: m::LoadLevel) -> LoadLevelSpec {
        match l {
            m::LoadLevel::Low => LoadLevelSpec::Low,
            m::LoadLevel::Medium => LoadLevelSpec::Medium,
            m::LoadLevel::High => LoadLevelSpec::High,
        }
    }
}

/// Local constraints of one kind of action.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ConstraintsSpec {
    /// No action on slopes above the maximum.
    pub max_slope: bool,
    /// No action while the Sun is below the horizontal.
    pub daylight: bool,
    /// No action in shadow or at night.
    pub direct_sun: bool,
    /// No drive whose heading puts the Sun in a navigation camera's view.
    pub sun_in_camera: bool,
}

impl ConstraintsSpec {
    fn to_lib(self) -> m::Constraints {
        m::Constraints {
            max_slope: self.max_slope,
            daylight: self.daylight,
            direct_sun: self.direct_sun,
            sun_in_camera: self.sun_in_camera,
        }
    }
    fn of(c: m::Constraints) -> ConstraintsSpec {
        ConstraintsSpec {
            max_slope: c.max_slope,
            daylight: c.daylight,
            direct_sun: c.direct_sun,
            sun_in_camera: c.sun_in_camera,
        }
    }
}

/// TEMPEST's actions and their constraints.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ActionSpec {
    /// Duration of one Charge, s.
    pub charge_s: f64,
    /// Duration of one Hibernate, s.
    pub hibernate_s: f64,
    /// Electronics level while charging.
    pub charge_load: LoadLevelSpec,
    /// Constraints on drives.
    pub drive: ConstraintsSpec,
    /// Constraints on Charge.
    pub charge: ConstraintsSpec,
    /// Constraints on Hibernate.
    pub hibernate: ConstraintsSpec,
    /// Steepest slope allowed where `max_slope` applies, degrees (default: the
    /// locomotor's maximum).
    pub max_slope_deg: Option<f64>,
    /// Round every duration up to a multiple of this, s (0: exact).
    pub time_quantum_s: f64,
    /// Round every energy change to a multiple of this, Wh (0: exact).
    pub energy_quantum_wh: f64,
    /// The rover's stationary action: `None`, the paper's Charge and Hibernate of fixed
    /// durations; `Some(step)`, waits in steps of `step` s (1..=86400), charging where
    /// the array sees the Sun and sleeping where it does not.
    pub wait_step_s: Option<f64>,
}

impl Default for ActionSpec {
    fn default() -> ActionSpec {
        ActionSpec::of(&m::ActionConfig::default())
    }
}

impl ActionSpec {
    fn of(a: &m::ActionConfig) -> ActionSpec {
        ActionSpec {
            charge_s: a.charge_s,
            hibernate_s: a.hibernate_s,
            charge_load: LoadLevelSpec::of(a.charge_load),
            drive: ConstraintsSpec::of(a.drive),
            charge: ConstraintsSpec::of(a.charge),
            hibernate: ConstraintsSpec::of(a.hibernate),
            max_slope_deg: a.max_slope_deg,
            time_quantum_s: a.time_quantum_s,
            energy_quantum_wh: a.energy_quantum_wh,
            wait_step_s: a.wait_step_s,
        }
    }
}

impl From<&ActionSpec> for m::ActionConfig {
    fn from(a: &ActionSpec) -> m::ActionConfig {
        m::ActionConfig {
            charge_s: a.charge_s,
            hibernate_s: a.hibernate_s,
            charge_load: a.charge_load.to_lib(),
            drive: a.drive.to_lib(),
            charge: a.charge.to_lib(),
            hibernate: a.hibernate.to_lib(),
            max_slope_deg: a.max_slope_deg,
            time_quantum_s: a.time_quantum_s,
            energy_quantum_wh: a.energy_quantum_wh,
            wait_step_s: a.wait_step_s,
        }
    }
}

/// What the planner minimises.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum ObjectiveSpec {
    /// The composite L + B (BESTPCOST): fewest steps, then least energy.
    Energy,
    /// Time to the last goal (BESTPCOST on duration).
    Time,
    /// Energy the loads draw (BESTPCOST), whatever the array gives back.
    EnergyUsed,
    /// Risk margin (BESTDPARMS): the plan needing least battery at its start among
    /// plans no longer than `max_duration_s` (`Duration(…)` is the older name).
    #[serde(alias = "Duration")]
    Margin {
        /// The longest acceptable plan, s.
        max_duration_s: f64,
    },
}

impl From<ObjectiveSpec> for m::Objective {
    fn from(o: ObjectiveSpec) -> m::Objective {
        match o {
            ObjectiveSpec::Energy => m::Objective::Energy,
            ObjectiveSpec::Time => m::Objective::Time,
            ObjectiveSpec::EnergyUsed => m::Objective::EnergyUsed,
            ObjectiveSpec::Margin { max_duration_s } => m::Objective::Margin { max_duration_s },
        }
    }
}

impl From<m::Objective> for ObjectiveSpec {
    fn from(o: m::Objective) -> ObjectiveSpec {
        match o {
            m::Objective::Energy => ObjectiveSpec::Energy,
            m::Objective::Time => ObjectiveSpec::Time,
            m::Objective::EnergyUsed => ObjectiveSpec::EnergyUsed,
            m::Objective::Margin { max_duration_s } => ObjectiveSpec::Margin { max_duration_s },
        }
    }
}

/// Label class widths for resolution pruning.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResolutionSpec {
    /// Time class width, s.
    pub time_s: f64,
    /// Energy class width, Wh (`None`: energy exact).
    #[serde(default)]
    pub energy_wh: Option<f64>,
}

/// How the objective's L counts length.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum PathLengthSpec {
    /// A drive counts its planar length in cells; a stationary action counts one.
    #[default]
    Distance,
    /// Every action counts one step, whatever its length (the paper's eq. 4).
    Steps,
}

/// The tick a planner block plans on when it sets neither `tick_s` nor any field of the
/// approximate search ([`SearchSpec::Exact`]), s.
pub const DEFAULT_TICK_S: f64 = 60.0;

/// The TEMPEST planner's settings. Read from a file, a block that sets neither
/// `tick_s` nor any field of the approximate search plans exactly on a
/// [`DEFAULT_TICK_S`] tick; [`PlannerSpec::default`] is the library's defaults as they
/// are (the approximate search), for code that sets its fields itself.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "PlannerFields", into = "PlannerWritten")]
pub struct PlannerSpec {
    /// Actions and their constraints.
    pub actions: ActionSpec,
    /// What to minimise.
    pub objective: ObjectiveSpec,
    /// How the objective's L counts length.
    pub path_length: PathLengthSpec,
    /// Worst-case path length as a multiple of the straight-line distance.
    pub detour_factor: f64,
    /// Longest total wait the worst case allows, s (default one solar day).
    pub max_wait_s: Option<f64>,
    /// Least battery energy on arrival at the last goal, Wh above the floor.
    pub goal_energy_wh: f64,
    /// Which search plans. In a file: `tick_s` (or nothing: [`DEFAULT_TICK_S`]) for
    /// the exact search, `approximate: true` beside the approximate search's fields for
    /// the paper's classes; those fields without it are refused, naming `tick_s`, and
    /// beside `tick_s` refused as unused.
    pub search: SearchSpec,
}

/// Which search plans, with the settings only it reads.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum SearchSpec {
    /// Exactly at one time step, s (1..=86400): drives depart on ticks, the rover waits
    /// in whole ticks (charging where lit, asleep where not), the battery exact, each
    /// goal reached at any instant of its window. The plan is optimal over every such
    /// plan and "unreachable" a proof. `actions.wait_step_s`, the actions' quanta and
    /// `path_length: Steps` are refused beside it.
    Exact {
        /// The tick, s.
        tick_s: f64,
    },
    /// The paper's time and energy classes and goal instants.
    Approximate(ClassesSpec),
}

/// The approximate search's settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClassesSpec {
    /// Label class widths for resolution pruning.
    pub resolution: ResolutionSpec,
    /// Goal instants spread over the final goal window.
    pub goal_times: usize,
    /// Start intervals per intermediate goal (multi-goal chaining).
    pub segment_starts: usize,
    /// Searches again with the time classes halved up to this many times when the
    /// settings find no plan (0..=6): with continuous action times before
    /// "unreachable", with quantised ones before the last resort exact at the quanta
    /// (see docs/tempest.md).
    pub unreachable_retries: u32,
}

impl Default for ClassesSpec {
    fn default() -> ClassesSpec {
        ClassesSpec::of(&m::Classes::default())
    }
}

impl ClassesSpec {
    fn of(c: &m::Classes) -> ClassesSpec {
        ClassesSpec {
            resolution: ResolutionSpec { time_s: c.resolution.time_s, energy_wh: c.resolution.energy_wh },
            goal_times: c.goal_times,
            segment_starts: c.segment_starts,
            unreachable_retries: c.unreachable_retries,
        }
    }

    fn to_lib(self) -> m::Classes {
        m::Classes {
            resolution: m::Resolution { time_s: self.resolution.time_s, energy_wh: self.resolution.energy_wh },
            goal_times: self.goal_times,
            segment_starts: self.segment_starts,
            unreachable_retries: self.unreachable_retries,
        }
    }
}

impl SearchSpec {
    /// The tick of the exact search, s (`None`: the approximate search).
    pub fn tick_s(&self) -> Option<f64> {
        match self {
            SearchSpec::Exact { tick_s } => Some(*tick_s),
            SearchSpec::Approximate(_) => None,
        }
    }

    /// The approximate search's settings (`None`: the exact search).
    pub fn classes(&self) -> Option<&ClassesSpec> {
        match self {
            SearchSpec::Exact { .. } => None,
            SearchSpec::Approximate(classes) => Some(classes),
        }
    }

    fn to_lib(self) -> m::SearchMode {
        match self {
            SearchSpec::Exact { tick_s } => m::SearchMode::Exact { tick_s },
            SearchSpec::Approximate(classes) => m::SearchMode::Approximate(classes.to_lib()),
        }
    }
}

/// A planner block as written: which fields it sets, so that a block setting none of
/// the approximate search's plans on the default tick.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlannerFields {
    #[serde(default)]
    actions: Option<ActionSpec>,
    #[serde(default)]
    objective: Option<ObjectiveSpec>,
    #[serde(default)]
    resolution: Option<ResolutionSpec>,
    #[serde(default)]
    path_length: Option<PathLengthSpec>,
    #[serde(default)]
    goal_times: Option<usize>,
    #[serde(default)]
    segment_starts: Option<usize>,
    #[serde(default)]
    detour_factor: Option<f64>,
    #[serde(default)]
    max_wait_s: Option<Option<f64>>,
    #[serde(default)]
    goal_energy_wh: Option<f64>,
    #[serde(default)]
    unreachable_retries: Option<u32>,
    #[serde(default)]
    tick_s: Option<f64>,
    /// Opts in to the approximate search's fields (the paper's classes), which are
    /// otherwise refused.
    #[serde(default)]
    approximate: bool,
}

impl TryFrom<PlannerFields> for PlannerSpec {
    type Error = String;

    fn try_from(f: PlannerFields) -> Result<PlannerSpec, String> {
        let d = PlannerSpec::default();
        let dc = ClassesSpec::default();
        let actions = f.actions.unwrap_or(d.actions.clone());
        // Each approximate field: whether the block writes it, and whether to other than
        // its default.
        let written = [
            ("resolution", f.resolution.is_some(), f.resolution.is_some_and(|r| r != dc.resolution)),
            ("goal_times", f.goal_times.is_some(), f.goal_times.is_some_and(|g| g != dc.goal_times)),
            ("segment_starts", f.segment_starts.is_some(), f.segment_starts.is_some_and(|g| g != dc.segment_starts)),
            (
                "unreachable_retries",
                f.unreachable_retries.is_some(),
                f.unreachable_retries.is_some_and(|r| r != dc.unreachable_retries),
            ),
            ("actions.wait_step_s", actions.wait_step_s != d.actions.wait_step_s, false),
            ("actions.time_quantum_s", actions.time_quantum_s != d.actions.time_quantum_s, false),
            ("actions.energy_quantum_wh", actions.energy_quantum_wh != d.actions.energy_quantum_wh, false),
        ];
        let approximate = written.iter().find(|w| w.1).map(|w| w.0);
        if let Some(field) = approximate
            && !f.approximate
            && f.tick_s.is_none()
        {
            return Err(format!(
                "field `planner.{field}` belongs to the approximate search (the paper's time and energy \
                 classes, whose plan may cost more than the optimum and whose \"unreachable\" is no proof): the \
                 planner is exact on one time step, `tick_s` (s, 1..=86400; default {DEFAULT_TICK_S} s) — write \
                 `tick_s` in its place, or `approximate: true` beside it to plan with the classes"
            ));
        }
        // A setting that would have no effect is refused, naming both fields.
        if f.approximate && f.tick_s.is_some() {
            return Err("fields `planner.approximate: true` and `planner.tick_s` both given: the approximate search \
                        has no tick — write `tick_s` to plan exactly, or `approximate: true` (with its \
                        `resolution`) to plan with the paper's classes"
                .into());
        }
        let objective = f.objective.unwrap_or(d.objective);
        let path_length = f.path_length.unwrap_or(d.path_length);
        if path_length != PathLengthSpec::Distance && objective != ObjectiveSpec::Energy {
            return Err(format!(
                "field `planner.path_length` counts the L of the `Energy` objective (L + B), but \
                 `planner.objective` is {objective:?}, which has no L: remove `path_length` or plan by `Energy`"
            ));
        }
        let search = if f.approximate {
            SearchSpec::Approximate(ClassesSpec {
                resolution: f.resolution.unwrap_or(dc.resolution),
                goal_times: f.goal_times.unwrap_or(dc.goal_times),
                segment_starts: f.segment_starts.unwrap_or(dc.segment_starts),
                unreachable_retries: f.unreachable_retries.unwrap_or(dc.unreachable_retries),
            })
        } else {
            let tick_s = f.tick_s.unwrap_or(DEFAULT_TICK_S);
            // The exact search counts L as the distance driven (waits split anywhere must
            // cost the whole); the rover waits in steps of the tick, unquantised.
            let unused = (written.iter())
                .find(|w| if w.0.starts_with("actions.") { w.1 } else { w.2 })
                .map(|w| w.0)
                .or((path_length != PathLengthSpec::Distance).then_some("path_length"));
            if let Some(field) = unused {
                return Err(format!(
                    "field `planner.{field}` is not used with `tick_s` (one time step, the plan exact at it: \
                     {tick_s} s) — remove `{}`",
                    field.trim_start_matches("actions.")
                ));
            }
            SearchSpec::Exact { tick_s }
        };
        Ok(PlannerSpec {
            actions,
            objective,
            path_length,
            detour_factor: f.detour_factor.unwrap_or(d.detour_factor),
            max_wait_s: f.max_wait_s.unwrap_or(d.max_wait_s),
            goal_energy_wh: f.goal_energy_wh.unwrap_or(d.goal_energy_wh),
            search,
        })
    }
}

/// A planner block as written back out: every field of its search, and `approximate:
/// true` where the spec plans with the approximate search, so that it reads back the same.
#[derive(Serialize)]
struct PlannerWritten {
    actions: ActionSpec,
    objective: ObjectiveSpec,
    #[serde(skip_serializing_if = "Option::is_none")]
    resolution: Option<ResolutionSpec>,
    path_length: PathLengthSpec,
    #[serde(skip_serializing_if = "Option::is_none")]
    goal_times: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    segment_starts: Option<usize>,
    detour_factor: f64,
    max_wait_s: Option<f64>,
    goal_energy_wh: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    unreachable_retries: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    tick_s: Option<f64>,
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    approximate: bool,
}

impl From<PlannerSpec> for PlannerWritten {
    fn from(p: PlannerSpec) -> PlannerWritten {
        let classes = p.search.classes().copied();
        PlannerWritten {
            approximate: classes.is_some(),
            actions: p.actions,
            objective: p.objective,
            resolution: classes.map(|c| c.resolution),
            path_length: p.path_length,
            goal_times: classes.map(|c| c.goal_times),
            segment_starts: classes.map(|c| c.segment_starts),
            detour_factor: p.detour_factor,
            max_wait_s: p.max_wait_s,
            goal_energy_wh: p.goal_energy_wh,
            unreachable_retries: classes.map(|c| c.unreachable_retries),
            tick_s: p.search.tick_s(),
        }
    }
}

impl PlannerSpec {
    /// The library's defaults, exact on [`DEFAULT_TICK_S`]: what a file's planner block
    /// that sets nothing, or no block, means.
    pub fn on_the_default_tick() -> PlannerSpec {
        PlannerSpec { search: SearchSpec::Exact { tick_s: DEFAULT_TICK_S }, ..PlannerSpec::default() }
    }

    /// The rover's actions as the library takes them: on a tick, waits in steps of it.
    pub fn action_config(&self) -> m::ActionConfig {
        let mut actions: m::ActionConfig = (&self.actions).into();
        if let SearchSpec::Exact { tick_s } = self.search {
            actions.wait_step_s = Some(tick_s);
        }
        actions
    }
}

impl Default for PlannerSpec {
    fn default() -> PlannerSpec {
        let d = m::PlannerConfig::default();
        PlannerSpec {
            actions: ActionSpec::of(&d.actions),
            objective: d.objective.into(),
            path_length: match d.path_length {
                m::PathLength::Distance => PathLengthSpec::Distance,
                m::PathLength::Steps => PathLengthSpec::Steps,
            },
            detour_factor: d.detour_factor,
            max_wait_s: d.max_wait_s,
            goal_energy_wh: d.goal_energy_wh,
            search: match d.search {
                m::SearchMode::Exact { tick_s } => SearchSpec::Exact { tick_s },
                m::SearchMode::Approximate(classes) => SearchSpec::Approximate(ClassesSpec::of(&classes)),
            },
        }
    }
}

impl From<&PlannerSpec> for m::PlannerConfig {
    fn from(p: &PlannerSpec) -> m::PlannerConfig {
        m::PlannerConfig {
            actions: p.action_config(),
            objective: p.objective.into(),
            path_length: match p.path_length {
                PathLengthSpec::Distance => m::PathLength::Distance,
                PathLengthSpec::Steps => m::PathLength::Steps,
            },
            detour_factor: p.detour_factor,
            max_wait_s: p.max_wait_s,
            goal_energy_wh: p.goal_energy_wh,
            search: p.search.to_lib(),
            meter: m::ExpansionMeter::default(),
            // Set by the run from its work and memory budgets, not by the file.
            max_expansions: None,
            max_search_bytes: None,
        }
    }
}

/// Execution noise of a simulation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NoiseSpec {
    /// Largest fractional drive slowdown (0 ≤ · ≤ 2; 0.2 = up to 20 % slower).
    pub drive_slowdown: f64,
    /// Largest fractional loss of solar input (0 ≤ · ≤ 1).
    pub solar_loss: f64,
    /// Seed of the ChaCha8 generator.
    pub seed: u64,
}

impl Default for NoiseSpec {
    fn default() -> NoiseSpec {
        let d = m::Noise::default();
        NoiseSpec { drive_slowdown: d.drive_slowdown, solar_loss: d.solar_loss, seed: d.seed }
    }
}

/// A simulated run's settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimSpec {
    /// Sensing radius around the rover, cells (≥ 0).
    pub sense_radius_cells: f64,
    /// Execution noise.
    pub noise: NoiseSpec,
    /// Most actions to execute before giving up (≥ 1).
    pub max_steps: usize,
    /// After re-plans, also plan the same problem from scratch and record its cost and
    /// expansions beside the re-plan's (slow).
    pub compare_fresh: bool,
    /// Which re-plans `compare_fresh` compares: 1 every one; n every n-th, and every
    /// one after sensing changed the map or a goal was reached (≥ 1).
    pub fresh_every: usize,
}

impl Default for SimSpec {
    fn default() -> SimSpec {
        let d = m::SimConfig::default();
        SimSpec {
            sense_radius_cells: d.sense_radius_cells,
            noise: NoiseSpec {
                drive_slowdown: d.noise.drive_slowdown,
                solar_loss: d.noise.solar_loss,
                seed: d.noise.seed,
            },
            max_steps: d.max_steps,
            compare_fresh: d.compare_fresh,
            fresh_every: d.fresh_every,
        }
    }
}

impl From<&SimSpec> for m::SimConfig {
    fn from(s: &SimSpec) -> m::SimConfig {
        m::SimConfig {
            sense_radius_cells: s.sense_radius_cells,
            noise: m::Noise {
                drive_slowdown: s.noise.drive_slowdown,
                solar_loss: s.noise.solar_loss,
                seed: s.noise.seed,
            },
            max_steps: s.max_steps,
            compare_fresh: s.compare_fresh,
            fresh_every: s.fresh_every,
            uncertainty: None,
            stream: 0,
        }
    }
}

/// How execution departs from the model, and the confidence a plan must hold at
/// (`areo_mission::uncertainty::Uncertainty`). Every σ is a fraction of the nominal
/// value; the factors are normal with mean 1.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct UncertaintySpec {
    /// Probability each planned quantity must hold with, 0.5..=0.999 (0.5: the
    /// deterministic plan); default 0.95.
    pub confidence: f64,
    /// σ of each drive's duration factor (slip, detours), 0..=0.5.
    pub drive_time_sigma: f64,
    /// σ of each action's electrical load factor, 0..=0.5.
    pub power_draw_sigma: f64,
    /// σ of each action's solar input factor (dust, optical depth), 0..=0.5.
    pub solar_sigma: f64,
    /// σ of the delay before each action, s, 0..=3600 (half-normal, spent at the
    /// action's load with the array off-line); every action is planned that much longer
    /// by the delay's quantile.
    pub action_delay_sigma_s: f64,
    /// σ of the start's delay, s, 0..=86 400 (half-normal: the rover is ready late,
    /// never early); the plan starts later by the delay's quantile.
    pub start_delay_sigma_s: f64,
    /// RMS error of the map's heights, m, 0..=100: the open-loop executions drive on
    /// `terrain_clones` error clones of the map instead of the truth.
    pub terrain_sigma_m: f64,
    /// Correlation length of the height error, m (at least two cells); default 100.
    pub terrain_correlation_m: f64,
    /// Error clones the executions share, 0..=100; default 0 (drive on the truth).
    pub terrain_clones: usize,
    /// Error clones the plan must hold on, 0..=100 (needs `terrain_sigma_m` > 0);
    /// default 0 (the plan is made on the map alone).
    pub terrain_plan_clones: usize,
    /// `Execution` (default): an execution draws its factors once (a systematic
    /// departure, all traverse long); `Action`: every action draws its own.
    pub correlation: m::uncertainty::Correlation,
}

impl Default for UncertaintySpec {
    fn default() -> UncertaintySpec {
        let d = m::uncertainty::Uncertainty::default();
        UncertaintySpec {
            confidence: d.confidence,
            drive_time_sigma: d.drive_time_sigma,
            power_draw_sigma: d.power_draw_sigma,
            solar_sigma: d.solar_sigma,
            action_delay_sigma_s: d.action_delay_sigma_s,
            start_delay_sigma_s: d.start_delay_sigma_s,
            terrain_sigma_m: d.terrain_sigma_m,
            terrain_correlation_m: d.terrain_correlation_m,
            terrain_clones: d.terrain_clones,
            terrain_plan_clones: d.terrain_plan_clones,
            correlation: d.correlation,
        }
    }
}

impl From<&UncertaintySpec> for m::uncertainty::Uncertainty {
    fn from(u: &UncertaintySpec) -> m::uncertainty::Uncertainty {
        m::uncertainty::Uncertainty {
            confidence: u.confidence,
            drive_time_sigma: u.drive_time_sigma,
            power_draw_sigma: u.power_draw_sigma,
            solar_sigma: u.solar_sigma,
            action_delay_sigma_s: u.action_delay_sigma_s,
            start_delay_sigma_s: u.start_delay_sigma_s,
            terrain_sigma_m: u.terrain_sigma_m,
            terrain_correlation_m: u.terrain_correlation_m,
            terrain_clones: u.terrain_clones,
            terrain_plan_clones: u.terrain_plan_clones,
            correlation: u.correlation,
        }
    }
}

/// The Pareto front's settings (`areo_mission::Mission::pareto_front`).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FrontSpec {
    /// How far apart the approximate search's walk along the front takes margins, Wh
    /// (0.001..=1000; default 1): a plan within this above a found one's margin may be
    /// missed. Refused on a tick, where the front is exact.
    pub margin_step_wh: Option<f64>,
}

impl FrontSpec {
    /// The margin step the approximate search walks the front in, Wh.
    pub fn step_wh(&self) -> f64 {
        self.margin_step_wh.unwrap_or(1.0)
    }
}

/// Open-loop executions of the initial plan (`areo_mission::uncertainty::MonteCarlo`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MonteCarloSpec {
    /// Executions, 1..=100 000; default 1000.
    pub runs: usize,
    /// Seed; run i draws from the seed's ChaCha8 stream i; default 1.
    pub seed: u64,
    /// Closed-loop executions besides (re-planning after every action, as `simulate:`
    /// does with its settings), 0..=10 000; default 0. Each costs a whole simulation.
    pub closed_loop_runs: usize,
}

impl Default for MonteCarloSpec {
    fn default() -> MonteCarloSpec {
        let d = m::uncertainty::MonteCarlo::default();
        MonteCarloSpec { runs: d.runs, seed: d.seed, closed_loop_runs: 0 }
    }
}

impl From<&MonteCarloSpec> for m::uncertainty::MonteCarlo {
    fn from(s: &MonteCarloSpec) -> m::uncertainty::MonteCarlo {
        m::uncertainty::MonteCarlo { runs: s.runs, seed: s.seed }
    }
}
