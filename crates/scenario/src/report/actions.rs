//! The actions job's report: the design space, each GA run's best plan and seed study,
//! the friction scans, the replay, the straight climb and the sensitivity climbs.
//!
//! Figures keyed by a run, a threshold, a seed count or an assumed value are maps, so a
//! fact names its key in its path (`runs.lsr1.best_fitness`,
//! `scan_binding_below.crossing.wheel`, `sensitivity.FIELD.VALUE.stop`); groups whose
//! figures carry their own prefix (`scan_…`, `replay_…`, `climb_…`) are flattened.

use std::collections::BTreeMap;

use areo_actions::{Command, Execution, Generation, TraceStep};
use serde::Serialize;

use super::actions_view::ActionsView;
use super::plots::Plot;

/// An actions job's result.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ActionsReport {
    /// log10 of the design space D = N^m over all 26 modules.
    pub design_space_log10_full: f64,
    /// log10 of the design space over the modules the task filters keep.
    pub design_space_log10_filtered: f64,
    /// The plan length m the design space counts, modules.
    pub plan_modules: usize,
    /// The codes of the modules the task filters keep.
    pub inventory: Vec<u16>,
    /// The modules they removed, and why.
    pub removed: Vec<RemovedModule>,
    /// The terrain classes on the features, by name.
    pub feature_classes: BTreeMap<String, FeatureClassFigures>,
    /// Each GA run, by name.
    pub runs: BTreeMap<String, GaRunFigures>,
    /// The runs' names in the scenario's order.
    pub run_order: Vec<String>,
    /// The friction scan's thresholds.
    #[serde(flatten)]
    pub scan: Option<ScanFigures>,
    /// The friction scan's thresholds over seeds.
    #[serde(flatten)]
    pub scan_seeds: Option<ScanSeedFigures>,
    /// The first run's best plan replayed over friction.
    #[serde(flatten)]
    pub replay: Option<ReplayFigures>,
    /// The straight climb.
    #[serde(flatten)]
    pub climb: Option<ClimbFigures>,
    /// The straight climb with each assumed value changed: by field (its dots as `_`),
    /// then by value (`0.27` as `0p27`, `-5` as `m5`).
    pub sensitivity: BTreeMap<String, BTreeMap<String, SensitivityFigures>>,
    /// The sensitivity climbs' keys (field, value) in the scenario's order.
    pub sensitivity_order: Vec<(String, String)>,
    /// Each run's best plan in full (its GA history, trace, commands and plots), by
    /// run name.
    pub best_plans: BTreeMap<String, BestPlan>,
    /// The plots of the whole job: the seed studies' `success_by_generation` and
    /// `lookahead_RUN`, and the straight `climb`.
    pub plots: Vec<Plot>,
}

/// A run's best plan in full.
#[derive(Debug, Clone, Serialize)]
pub struct BestPlan {
    /// The plan, its execution and trace, and the GA's history (`plan.json`).
    pub plan: GaPlanRecord,
    /// The plan as commands the rover runs (`commands.json`).
    pub commands: CommandList,
    /// `top_view`, `side_profile`, `stability`, `friction`, `fitness`, `lookahead`.
    pub plots: Vec<Plot>,
    /// What the run's `view.html` shows.
    pub view: ActionsView,
}

/// The best plan and how the GA found it. (Fields in alphabetical order, as
/// `plan.json` has always listed them.)
#[derive(Debug, Clone, Serialize)]
pub struct GaPlanRecord {
    /// The modules' Table 1 codes.
    pub codes: Vec<u16>,
    /// The plan executed as the GA scored it.
    pub execution: Execution,
    /// The first generation whose best plan completes the task.
    pub first_solved: Option<usize>,
    /// Its fitness.
    pub fitness: f64,
    /// Each generation's best and mean fitness.
    pub generations: Vec<Generation>,
    /// The change in successful-prefix length of each improving crossover, modules.
    pub lookahead: Vec<i64>,
    /// The plan executed again with a trace, a step per module.
    pub trace: Vec<TraceStep>,
}

/// The best plan as commands. (Fields in alphabetical order, as `commands.json` has
/// always listed them.)
#[derive(Debug, Clone, Serialize)]
pub struct CommandList {
    /// One command per executed module.
    pub commands: Vec<Command>,
    /// Whether the plan completes the task.
    pub complete: bool,
    /// The friction coefficient it was executed at.
    pub mu: f64,
    /// The rover's name.
    pub rover: String,
    /// Where it starts.
    pub start: StartPose,
}

/// A start on the map. (Fields in alphabetical order, as `commands.json` lists them.)
#[derive(Debug, Clone, Copy, Serialize)]
pub struct StartPose {
    /// Heading, degrees clockwise from north.
    pub heading_deg: f64,
    /// East, m.
    pub x_m: f64,
    /// North, m.
    pub y_m: f64,
}

/// One seed of a run's study.
#[derive(Debug, Clone, Default, Serialize)]
pub struct SeedRow {
    /// The run.
    pub run: String,
    /// The seed.
    pub seed: u64,
    /// The first generation whose best plan completes the task.
    pub first_solved_generation: Option<usize>,
    /// The best plan's fitness.
    pub best_fitness: f64,
    /// Samples it takes.
    pub samples: usize,
    /// Which ("s1 s4", "none").
    pub taken: String,
    /// Its least stability margin.
    pub min_stability: f64,
    /// How it ended: `none` (it ran to its end) or a failure's kind.
    pub stopped_by: String,
}

/// One pose of the straight climb, arm stowed and forward (a margin that cannot be
/// computed — no admissible pose — is not finite).
#[derive(Debug, Clone, Default, Serialize)]
pub struct ClimbPoseRow {
    /// From the start, m.
    pub distance_m: f64,
    /// Pitch, degrees.
    pub pitch_deg: f64,
    /// Stability margin, arm stowed.
    pub margin_stowed: f64,
    /// Stability margin, arm forward.
    pub margin_forward: f64,
    /// The front wheels' share of the load, arm stowed.
    pub front_load_stowed: f64,
    /// The front wheels' share of the load, arm forward.
    pub front_load_forward: f64,
    /// Friction needed, arm stowed.
    pub friction_needed_stowed: f64,
    /// Friction needed, arm forward.
    pub friction_needed_forward: f64,
    /// What the stowed pose violates (empty: nothing).
    pub violation_stowed: String,
    /// What the forward pose violates (empty: nothing).
    pub violation_forward: String,
}

/// One GA run: its best plan as the GA scored it and as executed, and its seed study.
#[derive(Debug, Clone, Default, Serialize)]
pub struct GaRunFigures {
    /// Whether the best plan completes the task.
    pub complete: bool,
    /// Its fitness.
    pub best_fitness: f64,
    /// Samples it takes.
    pub samples: usize,
    /// Which, by their 1-based number in the task ("s1 s4", "none"), with samples.
    pub samples_taken: Option<String>,
    /// How many lie left of the way, with samples.
    pub samples_left: Option<usize>,
    /// How many lie right of the way, with samples.
    pub samples_right: Option<usize>,
    /// The least stability margin along it.
    pub min_stability: f64,
    /// The highest actuator saturation along it.
    pub peak_saturation: f64,
    /// The highest friction needed over friction available.
    pub peak_friction_ratio: f64,
    /// Modules executed successfully.
    pub prefix: usize,
    /// From where it ends to the target, m.
    pub distance_to_target_m: f64,
    /// Plans evaluated.
    pub evaluations: usize,
    /// Modules executed over all evaluations.
    pub modules_executed: usize,
    /// Wall time of the run, s.
    pub seconds: f64,
    /// The first generation whose best plan completes the task.
    pub first_solved_generation: Option<usize>,
    /// Of the improving crossovers, the share adding 1–4 successful modules.
    pub lookahead_1_to_4_fraction: f64,
    /// Modules the run may use.
    pub modules: usize,
    /// log10 of its design space.
    pub design_space_log10: f64,
    /// Arm-forward modules less arm-back ones in the executed plan.
    pub arm_forward_net: f64,
    /// Pitch where the plan last stood, degrees.
    pub last_pitch_deg: Option<f64>,
    /// The front wheels' share of the load there.
    pub last_front_load_fraction: Option<f64>,
    /// What stopped the best plan (`tip_over`, `slip`, …), if it stopped.
    pub failure: Option<String>,
    /// The wheel whose force limit bound it.
    pub binding_wheel: Option<String>,
    /// Whether that wheel was climbing.
    pub binding_climbing: Option<bool>,
    /// The binding force limit, in words.
    pub binding_said: Option<String>,
    /// The best plan executed again with a trace.
    pub executed: ExecutedBest,
    /// The run repeated over seeds.
    #[serde(flatten)]
    pub study: Option<StudyFigures>,
}

/// A run's best plan executed with a trace.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ExecutedBest {
    /// Whether it completes the task.
    pub complete: bool,
    /// Modules executed successfully.
    pub modules: usize,
    /// Samples taken.
    pub samples: usize,
    /// Which ("s1 s4", "none").
    pub taken: String,
    /// The least stability margin.
    pub min_stability: f64,
    /// The mean stability margin.
    pub mean_stability: f64,
    /// Time, s.
    pub time_s: f64,
    /// Energy, Wh.
    pub energy_wh: f64,
    /// Where and why it stopped, in words ("module 7 (3002): …").
    pub stopped_at: Option<String>,
}

/// A run repeated over seeds.
#[derive(Debug, Clone, Default, Serialize)]
pub struct StudyFigures {
    /// Seeds run.
    pub seeds: usize,
    /// The first seed.
    pub first_seed: u64,
    /// The last seed.
    pub last_seed: u64,
    /// The last generation (0-based) the success fraction counts to.
    pub last_generation: usize,
    /// Seeds solved by then.
    pub solved: usize,
    /// Share solved by the last generation.
    pub success_fraction: f64,
    /// Median first-solved generation (absent when half or more never solve it).
    pub first_solved_median: Option<f64>,
    /// Pooled over seeds: the share of improving crossovers adding 1–4 modules.
    pub pooled_lookahead_1_to_4_fraction: f64,
    /// Pooled improving crossovers.
    pub pooled_improving_crossovers: usize,
    /// Earliest first-solved generation over the seeds that solved it.
    pub first_solved_earliest: Option<usize>,
    /// Latest.
    pub first_solved_latest: Option<usize>,
    /// Least stability margin of the solved seeds' best plans: its lowest.
    pub solved_least_margin_min: Option<f64>,
    /// Its highest.
    pub solved_least_margin_max: Option<f64>,
    /// How the seeds' best plans ended: a count per kind (`none`, `tip_over`, …).
    pub seeds_stopped_by: BTreeMap<String, usize>,
    /// With samples: the share of seeds whose plan took samples left of the way only.
    pub left_only_fraction: Option<f64>,
    /// Pooled: the share of crossovers that did not extend the prefix.
    pub pooled_lookahead_none_fraction: f64,
    /// Pooled: the share adding five modules or more.
    pub pooled_lookahead_5_plus_fraction: f64,
    /// Of the crossovers extending the prefix, the share adding fewer than five.
    pub pooled_extending_under_5_fraction: Option<f64>,
    /// Every seed, in order.
    pub seed_rows: Vec<SeedRow>,
}

/// The friction scan.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ScanFigures {
    /// The least μ whose best plan crosses the ditch.
    pub scan_min_mu_crossing_ditch: Option<f64>,
    /// The least μ whose best plan completes the task.
    pub scan_min_mu_completing: Option<f64>,
    /// Whether crossing needs less friction than completing.
    pub scan_ditch_needs_less_friction_than_hill: Option<bool>,
    /// What binds just below each threshold (`crossing`, `completing`).
    pub scan_binding_below: BTreeMap<String, ForceBinding>,
    /// The scan's first μ.
    pub scan_mu_first: f64,
    /// Its last μ.
    pub scan_mu_last: f64,
    /// The GA's best plan at each μ.
    pub scan_points: Vec<ScanPointRow>,
}

/// A force limit that bound a plan.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ForceBinding {
    /// The wheel.
    pub wheel: String,
    /// Whether it was climbing.
    pub climbing: bool,
    /// Its contact's distance along the way, m.
    pub y_m: f64,
    /// The μ it was found at.
    pub mu: f64,
    /// The wheel on the steepest ground.
    pub steepest_wheel: String,
    /// Whether that one was climbing.
    pub steepest_climbing: bool,
    /// The steepest contact angle, degrees.
    pub steepest_angle_deg: f64,
    /// The binding in words.
    pub said: String,
}

/// The friction scan over seeds.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ScanSeedFigures {
    /// Seeds swept.
    pub scan_seeds: usize,
    /// Seeds that never got there, by threshold (`crossing_ditch`, `completing`).
    pub scan_seeds_never: BTreeMap<String, usize>,
    /// The thresholds over the seeds that got there, by threshold.
    pub scan_seeds_min_mu: BTreeMap<String, SeedThreshold>,
    /// Each seed's scan.
    pub scan_seed_rows: Vec<SeedScanRow>,
}

/// One threshold's μ over seeds.
#[derive(Debug, Clone, Default, Serialize)]
pub struct SeedThreshold {
    /// The least.
    pub least: f64,
    /// The greatest.
    pub greatest: f64,
    /// The median, a seed that never gets there counting as above every μ (absent when
    /// half or more never do).
    pub median: Option<f64>,
}

/// The first run's best plan replayed over friction.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ReplayFigures {
    /// The run whose best plan is replayed.
    pub replay_run: String,
    /// The μ it was found at.
    pub replay_found_at_mu: f64,
    /// At the highest failing μ: the module it stops at (1-based).
    pub replay_stops_at_module: Option<usize>,
    /// And why, in words.
    pub replay_failure_said: Option<String>,
    /// The replayed plan at each μ.
    pub replay_points: Vec<ReplayPointRow>,
    /// The least μ it crosses the ditch from.
    pub replay_min_mu_crossing_ditch: Option<f64>,
    /// The least μ it completes from.
    pub replay_min_mu_completing: Option<f64>,
    /// The highest μ where it fails.
    pub replay_highest_failing_mu: Option<f64>,
    /// How far it got there, m.
    pub replay_highest_failing_max_y_m: Option<f64>,
    /// What stopped it there.
    pub replay_failure: Option<String>,
    /// At which module (1-based).
    pub replay_failure_module: Option<usize>,
    /// That module's code.
    pub replay_failure_code: Option<u16>,
    /// The wheel whose force limit bound it.
    pub replay_binding_wheel: Option<String>,
    /// Whether it was climbing.
    pub replay_binding_climbing: Option<bool>,
    /// Its contact's distance along the way, m.
    pub replay_binding_y_m: Option<f64>,
    /// The wheel on the steepest ground.
    pub replay_binding_steepest_wheel: Option<String>,
    /// Whether that one was climbing.
    pub replay_binding_steepest_climbing: Option<bool>,
    /// The steepest contact angle, degrees.
    pub replay_binding_steepest_angle_deg: Option<f64>,
}

/// The straight climb.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ClimbFigures {
    /// What ended it: `none`, `kinematics` or `tip_over`.
    pub climb_stop: String,
    /// Where, m along the way.
    pub climb_stop_distance_m: Option<f64>,
    /// Pitch at its last pose, degrees.
    pub climb_last_pitch_deg: Option<f64>,
    /// Stability margin there, arm stowed.
    pub climb_last_margin_stowed: Option<f64>,
    /// With the arm forward.
    pub climb_last_margin_forward: Option<f64>,
    /// The highest pitch, degrees.
    pub climb_max_pitch_deg: Option<f64>,
    /// The least margin, arm stowed.
    pub climb_min_margin_stowed: Option<f64>,
    /// With the arm forward.
    pub climb_min_margin_forward: Option<f64>,
    /// The most the arm forward adds to the margin.
    pub climb_max_margin_gain: Option<f64>,
    /// The front wheels' least share of the load, arm stowed.
    pub climb_min_front_load_stowed: Option<f64>,
    /// How far forward the arm holds its tool, m.
    pub climb_forward_tool_m: Option<f64>,
    /// Every pose along the climb.
    pub climb_poses: Vec<ClimbPoseRow>,
}

/// The straight climb with one assumed value changed.
#[derive(Debug, Clone, Default, Serialize)]
pub struct SensitivityFigures {
    /// The assumed parameter, as the rover file names it.
    pub parameter: String,
    /// Its value.
    pub value: f64,
    /// Why the value was refused (it is not a rover), if it was.
    pub refused: Option<String>,
    /// What ended it: `none`, `kinematics`, `tip_over`, or `refused` (the value is not
    /// a rover).
    pub stop: String,
    /// Where, m along the way.
    pub stop_distance_m: Option<f64>,
    /// Pitch at its last pose, degrees.
    pub last_pitch_deg: Option<f64>,
    /// Stability margin there, arm stowed.
    pub last_margin_stowed: Option<f64>,
    /// With the arm forward.
    pub last_margin_forward: Option<f64>,
    /// The least margin, arm stowed.
    pub min_margin_stowed: Option<f64>,
    /// With the arm forward.
    pub min_margin_forward: Option<f64>,
    /// The highest pitch, degrees.
    pub max_pitch_deg: Option<f64>,
    /// Where the stowed rover tips over: whether the margin with the arm forward stays
    /// above 0 there.
    pub arm_keeps_it_standing: Option<bool>,
}

/// A module the task filters removed.
#[derive(Debug, Clone, Default, Serialize)]
pub struct RemovedModule {
    /// Its Table 1 code.
    pub code: u16,
    /// Why.
    pub reason: String,
}

/// The force limit that bound a plan, where it bound.
#[derive(Debug, Clone, Default, Serialize)]
pub struct WheelBinding {
    /// The wheel.
    pub wheel: String,
    /// Whether it was climbing.
    pub climbing: bool,
    /// Its contact, m east and north in the task's frame.
    pub contact_x_m: f64,
    /// North.
    pub contact_y_m: f64,
    /// The contact angle, degrees.
    pub contact_angle_deg: f64,
    /// The rover's pitch, degrees.
    pub pitch_deg: f64,
    /// The wheel on the steepest ground.
    pub steepest_wheel: String,
    /// Its contact angle, degrees.
    pub steepest_angle_deg: f64,
    /// Whether it was climbing.
    pub steepest_climbing: bool,
}

/// The GA afresh at one μ of the friction scan.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ScanPointRow {
    /// The friction coefficient.
    pub mu: f64,
    /// Whether the best plan completes the task.
    pub complete: bool,
    /// Its fitness.
    pub best_fitness: f64,
    /// Modules executed successfully.
    pub prefix: usize,
    /// How far along the way it got, m.
    pub max_y_m: f64,
    /// What stopped it, in words (empty if nothing did).
    pub failure: String,
    /// The force limit that bound it.
    pub binding: Option<WheelBinding>,
}

/// One seed's friction scan.
#[derive(Debug, Clone, Default, Serialize)]
pub struct SeedScanRow {
    /// The GA seed.
    pub seed: u64,
    /// The least μ whose best plan crosses the ditch.
    pub min_mu_crossing_ditch: Option<f64>,
    /// The least μ whose best plan completes.
    pub min_mu_completing: Option<f64>,
    /// The μ values whose best plan completed.
    pub completed_at: Vec<f64>,
}

/// The replayed plan at one μ.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ReplayPointRow {
    /// The friction coefficient.
    pub mu: f64,
    /// Whether it completes the task.
    pub complete: bool,
    /// Modules executed successfully.
    pub modules_executed: usize,
    /// How far along the way it got, m.
    pub max_y_m: f64,
    /// The module it stopped at (1-based).
    pub failure_module: Option<usize>,
    /// That module's code.
    pub failure_code: Option<u16>,
    /// Why, in words (empty if nothing stopped it).
    pub failure: String,
    /// The force limit that bound it.
    pub binding: Option<WheelBinding>,
}

/// A terrain class on the features of an actions job's terrain.
#[derive(Debug, Clone, Default, Serialize)]
pub struct FeatureClassFigures {
    /// Its wheel–ground friction coefficient.
    pub mu: f64,
    /// The map cells it holds (where its features shape the ground and no class of
    /// lower μ does).
    pub cells: usize,
}
