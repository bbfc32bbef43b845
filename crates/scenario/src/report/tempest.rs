//! The TEMPEST job's report: how the search ended, the plan's figures, the simulated
//! run's, the plan under uncertainty's and the Pareto front's, and the plan and run
//! themselves as the mission crate gives them.
//!
//! Groups whose figures carry their own prefix (`initial_plan_…`, `no_plan_…`,
//! `chance_…`, `front_…`) are flattened into the report, so a fact keeps the field's
//! name; figures keyed by a goal, a region or a failure are maps (`goals.NAME.arrival_h`,
//! `route_enters.NAME`, `mc.failed.NAME`).

use std::collections::BTreeMap;

use areo_mission::{MissionPlan, SimReport};
use areo_terrain::geotiff::Grid;
use serde::Serialize;

use super::Raster;
use super::plots::Plot;

/// A TEMPEST job's result.
#[derive(Debug, Clone, Default, Serialize)]
pub struct TempestReport {
    /// `planned`, `completed`, `unreachable`, `stopped`, `battery_depleted`, `stuck`
    /// or `step_limit`.
    pub status: String,
    /// Without a plan: the binding constraint, as the planner names it.
    pub binding: Option<String>,
    /// Whether "unreachable" is a proof (the exact search emptied its graph).
    pub unreachable_proven: Option<bool>,
    /// Stopped by a budget: `work` or `memory`.
    pub stopped_by: Option<String>,
    /// The map file's CRS, when areo does not read its projection (a local frame).
    pub map_crs_not_read: Option<String>,
    /// The no-go mask, when the job has one.
    pub no_go: Option<NoGoFigures>,
    /// The terrain classes, when the job has them: each class's cells, and the time
    /// and energy the plan and the run drive on it.
    pub terrain_classes: Option<ClassFigures>,
    /// Bytes per horizon angle the horizon maps hold (1 or 2), with horizon maps.
    pub horizon_bytes_per_angle: Option<f64>,
    /// Slope, horizon maps and the Sun table, s.
    pub precalc_s: f64,
    /// The process's peak resident memory, MB (where the system reports it).
    pub peak_memory_mb: Option<f64>,
    /// Cells of the planning map (with a plan).
    pub cells: Option<usize>,
    /// Its columns and rows (with a plan).
    pub map_cols_rows: Option<(usize, usize)>,
    /// What the map approximates or how it is read (a cut region, one-byte horizons,
    /// a grid whose north is not true north), in words.
    pub notes: Vec<String>,
    /// Stopped by a budget: what stopped it, naming the file and the flag.
    pub stopped_message: Option<String>,
    /// Without a plan under uncertainty margins: the confidence planned at.
    pub planned_at_confidence: Option<f64>,
    /// The goals asked for.
    pub goals_total: usize,
    /// The battery's floor (capacity × min_soc), Wh.
    pub battery_floor_wh: f64,
    /// Goals reached (a plan without simulation reaches none yet).
    pub goals_reached: usize,
    /// The search graphs at their largest, MB.
    pub peak_search_mb: Option<f64>,
    /// What a run without a plan cost.
    #[serde(flatten)]
    pub no_plan: Option<NoPlanFigures>,
    /// The initial plan's figures.
    #[serde(flatten)]
    pub initial_plan: Option<PlanFigures>,
    /// The simulated run's figures.
    #[serde(flatten)]
    pub run: Option<RunFigures>,
    /// The plan under uncertainty: margins, the deterministic plan beside it and the
    /// Monte Carlo executions.
    #[serde(flatten)]
    pub chance: Option<ChanceFigures>,
    /// The Pareto front of arrival, energy used and margin.
    #[serde(flatten)]
    pub front: Option<FrontFigures>,
    /// The plan's and the run's tables.
    pub tables: TempestTables,
    /// The start, the goals and the executed route on the body (with a plan).
    pub route: Option<RoutePlaces>,
    /// The map layers under the route (with a plan).
    pub layers: Option<MapLayers>,
    /// The initial plan, as the planner made it.
    pub plan: Option<MissionPlan>,
    /// The simulated run: every plan and executed action.
    pub simulation: Option<SimReport>,
    /// The Pareto front's plans, in the order of `tables.pareto_front` (with
    /// `pareto_front`).
    pub pareto_plans: Option<Vec<MissionPlan>>,
    /// The plots: `route`, `distance`, `energy`; off Mars `havens` and `sky`; under
    /// uncertainty `mc_arrival`, `mc_battery`, `mc_lowest_battery`; with a front
    /// `front_energy` and `front_margin` (with a plan).
    pub plots: Vec<Plot>,
    /// What the plan viewer shows (with a plan).
    pub view: Option<super::view::ViewData>,
}

/// What a "no plan" verdict cost.
#[derive(Debug, Clone, Default, Serialize)]
pub struct NoPlanFigures {
    /// Wall time from the first search to the verdict, s.
    pub no_plan_s: f64,
    /// Label expansions of every search: the plan's, its fallbacks', the probes'.
    pub no_plan_expansions: u64,
    /// Those of the searches at the settings and their fallbacks.
    pub no_plan_planning_expansions: u64,
    /// Relaxed probes run to name the binding constraint.
    pub no_plan_probes: u64,
    /// Each probe's relaxation and its expansions.
    pub no_plan_probe_expansions: Vec<(String, u64)>,
}

/// The initial plan's figures.
#[derive(Debug, Clone, Default, Serialize)]
pub struct PlanFigures {
    /// Wall time of the search, s.
    pub initial_plan_s: f64,
    /// Labels the search graphs hold after it (without simulation).
    pub initial_plan_labels: Option<u64>,
    /// Waypoints, the start included.
    pub initial_plan_waypoints: usize,
    /// Drive actions.
    pub initial_plan_drives: usize,
    /// Charge actions.
    pub initial_plan_charges: usize,
    /// Hibernate actions.
    pub initial_plan_hibernations: usize,
    /// Wait steps.
    pub initial_plan_wait_steps: usize,
    /// From the start to the last goal, h.
    pub initial_plan_duration_h: f64,
    /// The lowest predicted battery charge, Wh (absolute).
    pub initial_plan_min_battery_wh: f64,
    /// Label expansions of the search.
    pub initial_plan_expansions: u64,
    /// The objective's value: Wh (L + B, energy used, margin) or s (time).
    pub initial_plan_cost: f64,
    /// The plan's E_max, Wh.
    pub e_max_wh: f64,
    /// Straight-line length of the route, m.
    pub initial_plan_distance_m: f64,
    /// Goals the plan reaches.
    pub initial_plan_goals: usize,
    /// Fraction of drives that start in direct sun (1 without drives).
    pub initial_plan_sunlit_drive_fraction: f64,
    /// Drives that start with the Sun below the horizon.
    pub initial_plan_night_drives: usize,
    /// The largest roll of the initial plan's drives (either side), degrees.
    pub initial_plan_max_roll_deg: Option<f64>,
    /// The steepest nose-up pitch of its drives, degrees (0 if none climbs).
    pub initial_plan_max_pitch_up_deg: Option<f64>,
    /// The steepest nose-down pitch of its drives, degrees (positive; 0 if none descends).
    pub initial_plan_max_pitch_down_deg: Option<f64>,
    /// Whether the route enters each named region.
    pub initial_plan_enters: BTreeMap<String, bool>,
    /// The exact search's tick, s.
    pub initial_plan_tick_s: Option<f64>,
    /// The approximate search: whether no plan at the energy classes made it search
    /// again with energy exact.
    pub initial_plan_exact_energy_fallback: Option<bool>,
    /// The approximate search: whether it searched again exact at the actions' quanta.
    pub initial_plan_quanta_fallback: Option<bool>,
    /// The approximate search: whether it searched again at halved time classes.
    pub initial_plan_halved_classes_fallback: Option<bool>,
    /// The approximate search's settings and the classes its plan was found at.
    pub approximate: Option<ApproximateSearch>,
    /// Communicate sessions and the drives that would overlap one.
    #[serde(flatten)]
    pub sessions: Option<SessionFigures>,
    /// Off Mars: shadowed driving, Earth contact, the Sun's azimuth span, waits at havens.
    #[serde(flatten)]
    pub body: Option<BodyFigures>,
}

/// The approximate search (`approximate: true`): its classes.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ApproximateSearch {
    /// The time classes asked for, s.
    pub time_classes_asked_s: f64,
    /// The energy classes asked for, Wh (absent: energy exact).
    pub energy_classes_asked_wh: Option<f64>,
    /// The time classes the plan was found at, s.
    pub time_classes_s: f64,
    /// Whether the actions have a time quantum (their last resort is a search exact at
    /// the quanta).
    pub quantised: bool,
}

/// Communicate sessions the plan covers.
#[derive(Debug, Clone, Default, Serialize)]
pub struct SessionFigures {
    /// Sessions over the horizon.
    pub communicate_sessions: usize,
    /// Sessions within the plan's span.
    pub plan_sessions: usize,
    /// Drives that overlap a session (none may).
    pub plan_drives_during_sessions: usize,
}

/// A plan's figures off Mars, measured on the plan by sampling.
#[derive(Debug, Clone, Default, Serialize)]
pub struct BodyFigures {
    /// Hours driven out of direct sun.
    pub initial_plan_shadowed_drive_h: f64,
    /// The longest gap without a whole session of Earth contact, h.
    pub initial_plan_contact_max_gap_h: Option<f64>,
    /// Fraction of the plan with the Earth in view.
    pub initial_plan_earth_in_view_fraction: Option<f64>,
    /// The contact a gap is measured without: a session of this length, min.
    pub contact_session_min: Option<f64>,
    /// How far the Sun's azimuth turns over the plan, degrees.
    pub initial_plan_sun_azimuth_span_deg: f64,
    /// The Sun's lowest elevation over the plan, degrees.
    pub initial_plan_lowest_sun_deg: f64,
    /// Whether the plan ends within a cell of its start.
    pub initial_plan_closes_circuit: Option<bool>,
    /// Fraction of drives whose solar array faces within 90° of the Sun.
    pub initial_plan_panel_sunward_drive_fraction: Option<f64>,
    /// Safe havens and the plan's waits, with a haven map.
    #[serde(flatten)]
    pub havens: Option<HavenFigures>,
}

/// Cells where the rover can wait out a shadow, and the plan's waits.
#[derive(Debug, Clone, Default, Serialize)]
pub struct HavenFigures {
    /// Cells whose shadows are shorter than a full battery lasts asleep.
    pub safe_haven_cells: usize,
    /// How long a full battery lasts asleep, h.
    pub safe_haven_survive_h: f64,
    /// The plan's waits of at least the haven map's step.
    pub initial_plan_waits: usize,
    /// Those at havens.
    pub initial_plan_waits_at_havens: usize,
    /// The longest wait, h.
    pub initial_plan_longest_wait_h: f64,
    /// Whether the longest wait is at a haven.
    pub initial_plan_longest_wait_at_haven: bool,
    /// The shortest wait counted, h.
    pub waits_counted_from_h: f64,
}

/// A goal reached in the simulated run.
#[derive(Debug, Clone, Default, Serialize)]
pub struct GoalArrival {
    /// The instant, ISO 8601 UTC.
    pub arrival_utc: String,
    /// Hours after the start.
    pub arrival_h: f64,
    /// Local solar time at the goal, hours.
    pub arrival_ltst_h: f64,
}

/// The simulated run's figures.
#[derive(Debug, Clone, Default, Serialize)]
pub struct RunFigures {
    /// Each goal reached, by name.
    pub goals: BTreeMap<String, GoalArrival>,
    /// The goals' names in the order reached.
    pub arrival_order: Vec<String>,
    /// Drives that undo the one before (back and forth).
    pub zigzag_pairs: usize,
    /// Executed actions.
    pub actions: usize,
    /// Distance driven, m.
    pub distance_m: f64,
    /// Energy drawn, Wh.
    pub energy_used_wh: f64,
    /// Energy gained, Wh.
    pub energy_gained_wh: f64,
    /// The battery at the end, Wh (absolute).
    pub final_battery_wh: f64,
    /// The battery at the end above its floor, Wh.
    pub final_battery_above_floor_wh: f64,
    /// The lowest battery, Wh (absolute).
    pub min_battery_wh: f64,
    /// Nights the run spans.
    pub nights: usize,
    /// Hours driving.
    pub drive_h: f64,
    /// Hours charging.
    pub charge_h: f64,
    /// Hours hibernating.
    pub hibernate_h: f64,
    /// Hours waiting.
    pub wait_h: f64,
    /// Re-plans (restarts included).
    pub replans: usize,
    /// Re-plans that changed the route.
    pub route_changes: usize,
    /// Re-plans on the kept graphs that found nothing and were replaced by fresh plans.
    pub restarts: usize,
    /// The work those failed re-plans did (expansions).
    pub restart_replan_work: Option<u64>,
    /// The fresh plans' expansions.
    pub restart_expansions: Option<u64>,
    /// With `compare_fresh`: restarts compared with a fresh search of the same problem.
    pub restarts_fresh_compared: Option<usize>,
    /// Of those, how many a fresh search contradicted (it found a plan).
    pub restarts_fresh_disagree: Option<usize>,
    /// The binding constraint each failed re-plan named, consecutive repeats once.
    pub restart_bindings: Vec<String>,
    /// The approximate search: plans that fell back to energy exact.
    pub exact_energy_fallbacks: usize,
    /// Each re-plan's expansions against the initial plan's: median.
    pub replan_expansions_median: Option<f64>,
    /// 95th percentile.
    pub replan_expansions_p95: Option<f64>,
    /// Largest.
    pub replan_expansions_max: Option<f64>,
    /// Re-plans that repaired the kept graphs for cells sensing changed.
    pub replans_after_sensing: usize,
    /// On a tick: re-plans that kept the rest of the last plan without a search.
    pub replans_kept_rest: Option<usize>,
    /// On a tick: re-plans after sensing changed the map whose repair proved the rest
    /// of the plan optimal.
    pub replans_repaired: Option<usize>,
    /// On a tick: the expansions of the re-plans after sensing changed the map against
    /// the initial plan's, median.
    pub sensing_replan_expansions_median: Option<f64>,
    /// 95th percentile.
    pub sensing_replan_expansions_p95: Option<f64>,
    /// With `compare_fresh`: re-plans compared with fresh searches.
    pub fresh_compared: Option<usize>,
    /// Of those, how many expanded more than the fresh search.
    pub replans_above_fresh: Option<usize>,
    /// The largest relative cost difference from the fresh search, over the re-plans
    /// whose difference the goal windows do not explain.
    pub replan_fresh_cost_difference: Option<f64>,
    /// On a tick: compared re-plans whose cost differs from the independent planner
    /// instance's where the other problem admits the cheaper plan (a search lost its
    /// optimum; 0 expected).
    pub fresh_differs: Option<usize>,
    /// On a tick: compared re-plans whose difference the goal windows explain (the
    /// instance's are made from the rover's state, the mission's were fixed at its
    /// start).
    pub fresh_windows_explained: Option<usize>,
    /// The worlds held, MB.
    pub world_mb: f64,
    /// Actions the rover refused.
    pub refused_actions: usize,
    /// Drives with the Sun below the horizon.
    pub night_drives: usize,
    /// Fraction of driving in direct sun.
    pub sunlit_drive_fraction: f64,
    /// From the start to the end of the run, h.
    pub mission_h: f64,
    /// Median re-plan wall time, s.
    pub median_replan_s: Option<f64>,
    /// Longest re-plan wall time, s.
    pub max_replan_s: Option<f64>,
    /// Median re-plan over the initial plan's wall time.
    pub median_replan_fraction: Option<f64>,
    /// Whether the route enters each named region.
    pub route_enters: BTreeMap<String, bool>,
}

/// The plan under uncertainty.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ChanceFigures {
    /// The confidence each quantity is planned at.
    pub chance_confidence: f64,
    /// Its standard normal quantile.
    pub chance_z: f64,
    /// Drive time factor planned with.
    pub chance_drive_time_factor: f64,
    /// Load factor planned with.
    pub chance_draw_factor: f64,
    /// Sunlight factor planned with.
    pub chance_solar_factor: f64,
    /// Delay before each action, s.
    pub chance_action_delay_s: f64,
    /// Start delay allowed for, s.
    pub chance_start_delay_s: f64,
    /// Error clones of the terrain the executions drive on.
    pub mc_terrain_clones: Option<usize>,
    /// Error clones the plan is made to hold on.
    pub chance_terrain_plan_clones: Option<usize>,
    /// The clones' height error (RMS), m.
    pub chance_terrain_sigma_m: Option<f64>,
    /// The distance it is correlated over, m.
    pub chance_terrain_correlation_m: Option<f64>,
    /// `Execution` or `Action`.
    pub chance_correlation: String,
    /// The deterministic plan, when there is none: why.
    pub deterministic_plan: Option<String>,
    /// The deterministic plan's duration, h.
    pub deterministic_plan_duration_h: Option<f64>,
    /// Its lowest battery above the floor, Wh.
    pub deterministic_plan_min_battery_wh: Option<f64>,
    /// What the margins cost in time, h.
    pub chance_extra_duration_h: Option<f64>,
    /// And in energy drawn, Wh.
    pub chance_extra_energy_used_wh: Option<f64>,
    /// The plan's cost over the deterministic one's.
    pub chance_cost_ratio: Option<f64>,
    /// Open-loop executions of the plan.
    pub mc: Option<MonteCarloFigures>,
    /// Open-loop executions of the deterministic plan.
    pub mc_deterministic: Option<MonteCarloFigures>,
    /// Closed-loop executions (re-planning after every action) of the plan.
    pub mc_closed: Option<MonteCarloFigures>,
    /// Closed-loop executions planning deterministically.
    pub mc_closed_deterministic: Option<MonteCarloFigures>,
}

/// Monte Carlo executions of one plan.
#[derive(Debug, Clone, Default, Serialize)]
pub struct MonteCarloFigures {
    /// Executions.
    pub runs: usize,
    /// Fraction that reached every goal with the battery above its floor.
    pub success_probability: f64,
    /// 95 % Wilson interval: low.
    pub success_ci_low: f64,
    /// High.
    pub success_ci_high: f64,
    /// Fraction whose battery never fell below its floor.
    pub battery_ok_probability: f64,
    /// Fraction that reached each goal, by name.
    pub goal_probability: BTreeMap<String, f64>,
    /// The last goal's arrival, h after the start: 5th percentile.
    pub last_arrival_h_p05: Option<f64>,
    /// 50th.
    pub last_arrival_h_p50: Option<f64>,
    /// 95th.
    pub last_arrival_h_p95: Option<f64>,
    /// The lowest battery above the floor, Wh: 5th percentile.
    pub lowest_battery_wh_p05: f64,
    /// 50th.
    pub lowest_battery_wh_p50: f64,
    /// Executions that failed each way, by name.
    pub failed: BTreeMap<String, usize>,
}

/// The Pareto front.
#[derive(Debug, Clone, Default, Serialize)]
pub struct FrontFigures {
    /// Plans on the front.
    pub front_plans: usize,
    /// Searches made.
    pub front_searches: usize,
    /// Plans before the non-dominated filter.
    pub front_candidates: usize,
    /// The approximate front's margin step, Wh (absent on a tick: the front is exact).
    pub front_margin_step_wh: Option<f64>,
    /// The front's earliest arrival, h.
    pub front_earliest_arrival_h: Option<f64>,
    /// Latest arrival, h.
    pub front_latest_arrival_h: Option<f64>,
    /// Least energy used, Wh.
    pub front_least_energy_used_wh: Option<f64>,
    /// Most energy used, Wh.
    pub front_most_energy_used_wh: Option<f64>,
    /// Least margin, Wh.
    pub front_least_margin_wh: Option<f64>,
    /// Largest margin, Wh.
    pub front_largest_margin_wh: Option<f64>,
    /// The job's plan's energy used, Wh.
    pub plan_energy_used_wh: Option<f64>,
    /// The job's plan's margin, Wh.
    pub plan_margin_wh: Option<f64>,
    /// Whether a front plan beats the job's plan.
    pub plan_dominated_by_front: Option<bool>,
}

/// The plan's and the simulated run's tables: a row per waypoint, executed action, plan,
/// wait, Monte Carlo execution and front plan (`plan.csv`, `executed.csv`,
/// `replans.csv`, `waits.csv`, `monte_carlo.csv`, `pareto_front.csv`).
#[derive(Debug, Clone, Default, Serialize)]
pub struct TempestTables {
    /// The initial plan's waypoints.
    pub plan: Vec<PlanRow>,
    /// The simulated run's executed actions (with a simulation).
    pub executed: Option<Vec<ExecutedRow>>,
    /// The simulated run's plans: the initial one, re-plans and restarts.
    pub replans: Option<Vec<ReplanRow>>,
    /// The initial plan's waits, with a haven map (off Mars).
    pub waits: Option<Vec<WaitRow>>,
    /// Every Monte Carlo execution, open and closed loop (with `monte_carlo`).
    pub monte_carlo: Option<Vec<MonteCarloRow>>,
    /// The Pareto front's plans (with `pareto_front`).
    pub pareto_front: Option<Vec<FrontRow>>,
}

/// One waypoint of the plan.
#[derive(Debug, Clone, Default, Serialize)]
pub struct PlanRow {
    /// Its index, 0 the start.
    pub index: usize,
    /// ISO 8601 UTC.
    pub utc: String,
    /// Seconds after the start.
    pub t_s: f64,
    /// The local solar day since the start's.
    pub sol: i64,
    /// Local true solar time, hours.
    pub ltst_h: f64,
    /// Grid column.
    pub col: usize,
    /// Grid row.
    pub row: usize,
    /// Map metres east of the map's south-west corner.
    pub x_m: f64,
    /// Map metres north.
    pub y_m: f64,
    /// Planetocentric latitude, degrees.
    pub lat_deg: f64,
    /// East longitude, degrees.
    pub lon_deg: f64,
    /// Elevation, m.
    pub elevation_m: f64,
    /// The action taken from here (`arrive` at the last).
    pub action: String,
    /// When the action ends (the next waypoint's instant; the last waypoint's own).
    pub end_utc: String,
    /// How long the action lasts, s (0 at the last waypoint).
    pub duration_s: f64,
    /// What the action's loads draw, Wh (replayed on the planner's model; 0 at the last
    /// waypoint).
    pub energy_drawn_wh: f64,
    /// The battery's change over the action, Wh (positive: charged).
    pub battery_change_wh: f64,
    /// Least energy above the floor needed from here to the last goal, Wh.
    pub required_wh: f64,
    /// Predicted battery charge, Wh (absolute).
    pub battery_wh: f64,
    /// Slope, degrees.
    pub slope_deg: f64,
    /// The drive from here: the slope along it (the rover's pitch, positive uphill),
    /// degrees; none for other actions.
    pub pitch_deg: Option<f64>,
    /// The drive from here: the rover's roll (positive right side up), degrees.
    pub roll_deg: Option<f64>,
    /// The terrain class here, with terrain classes (empty where unclassified).
    pub class: String,
    /// The Sun's elevation, degrees.
    pub sun_elevation_deg: f64,
    /// The Sun above the terrain's horizon here, degrees.
    pub sun_above_ground_deg: f64,
    /// Whether the cell is in direct sun.
    pub lit: bool,
    /// The goal reached here, if one is.
    pub goal: String,
}

/// One executed action of the simulated run.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ExecutedRow {
    /// Its number, from 1.
    pub step: usize,
    /// When it started, ISO 8601 UTC.
    pub utc: String,
    /// Seconds after the start.
    pub t_s: f64,
    /// The local solar day since the start's.
    pub sol: i64,
    /// Local true solar time, hours.
    pub ltst_h: f64,
    /// Grid column where it started.
    pub col: usize,
    /// Grid row.
    pub row: usize,
    /// Map metres east.
    pub x_m: f64,
    /// Map metres north.
    pub y_m: f64,
    /// Planetocentric latitude, degrees.
    pub lat_deg: f64,
    /// East longitude, degrees.
    pub lon_deg: f64,
    /// Elevation, m.
    pub elevation_m: f64,
    /// The action.
    pub action: String,
    /// How long it took, s.
    pub duration_s: f64,
    /// Energy drawn (negative: gained), Wh.
    pub energy_wh: f64,
    /// What the action's loads drew, Wh (whatever the sources gave meanwhile).
    pub energy_drawn_wh: f64,
    /// When it ended, ISO 8601 UTC.
    pub end_utc: String,
    /// The battery after it, Wh (absolute).
    pub battery_wh: f64,
    /// The battery after it above the floor, Wh.
    pub battery_above_floor_wh: f64,
    /// Distance driven, m.
    pub distance_m: f64,
    /// A drive's pitch on the true terrain (positive uphill), degrees.
    pub pitch_deg: Option<f64>,
    /// A drive's roll on the true terrain (positive right side up), degrees.
    pub roll_deg: Option<f64>,
    /// The terrain class where it started, with terrain classes.
    pub class: String,
    /// The Sun's elevation, degrees.
    pub sun_elevation_deg: f64,
    /// The action refused and why, if the world refused one.
    pub refused: String,
}

/// One plan of the simulated run.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ReplanRow {
    /// The executed actions before it.
    pub step: usize,
    /// `initial`, `replan` or `restart`.
    pub kind: String,
    /// When, ISO 8601 UTC.
    pub utc: String,
    /// Seconds after the start.
    pub t_s: f64,
    /// Its wall time, ms.
    pub wall_ms: f64,
    /// Label expansions.
    pub expansions: u64,
    /// Cells sensing changed before it.
    pub changed_cells: usize,
    /// Whether it changed the route.
    pub route_changed: bool,
    /// Its waypoints.
    pub waypoints: usize,
    /// Its cost (the objective's unit).
    pub cost: f64,
    /// Its duration, h.
    pub duration_h: f64,
    /// Its lowest predicted battery, Wh (absolute).
    pub min_battery_wh: f64,
    /// The search graphs after it, MB.
    pub search_mb: f64,
    /// With `compare_fresh`: a fresh search's expansions.
    pub fresh_expansions: Option<u64>,
    /// And its cost.
    pub fresh_cost: Option<f64>,
    /// On a tick, how the re-plan compares with the new planner instance: `equal`,
    /// `windows` (a difference the goal windows explain) or `differs` (a lost optimum).
    pub fresh_check: Option<String>,
    /// A restart: the binding constraint the failed re-plan named.
    pub restart_binding: Option<String>,
    /// The failed re-plan's work, expansions.
    pub restart_replan_work: Option<u64>,
    /// Whether a fresh search of the same problem found a plan.
    pub restart_fresh_found: Option<bool>,
}

/// One of the plan's waits.
#[derive(Debug, Clone, Default, Serialize)]
pub struct WaitRow {
    /// Map metres east.
    pub x_m: f64,
    /// Map metres north.
    pub y_m: f64,
    /// From, h after the start.
    pub from_h: f64,
    /// To, h after the start.
    pub to_h: f64,
    /// Its length, h.
    pub hours: f64,
    /// The lowest charge during it above the floor, Wh.
    pub lowest_battery_above_floor_wh: f64,
    /// Whether it is at a safe haven.
    pub safe_haven: bool,
    /// The longest shadow there over the span, h.
    pub longest_shadow_h: f64,
    /// The longest loss of the Earth there, h.
    pub longest_earth_loss_h: f64,
}

/// Where the route runs, for the maps: the body and its CRS, the start, the goals and the
/// executed route.
#[derive(Debug, Clone, Serialize)]
pub struct RoutePlaces {
    /// The run's name (its scenario file's), which names the route's layers.
    pub run: String,
    /// The body and the geographic CRS of every place.
    pub geography: super::Geography,
    /// The start.
    pub start: RoutePoint,
    /// The goals, in order.
    pub goals: Vec<RoutePoint>,
    /// The executed route's cells as (latitude, east longitude), degrees: the start,
    /// then where each action ended (with a simulation).
    pub executed: Option<Vec<(f64, f64)>>,
    /// The route in time: the executed route's vertices (the start, then where and when
    /// each action ended), or without a simulation the initial plan's waypoints.
    pub timeline: Vec<RouteVertex>,
}

/// A vertex of the route in time.
#[derive(Debug, Clone, Default, Serialize)]
pub struct RouteVertex {
    /// Planetocentric latitude, degrees.
    pub lat_deg: f64,
    /// East longitude, degrees.
    pub lon_deg: f64,
    /// Elevation on the map, m.
    pub elevation_m: f64,
    /// When the rover is there, ISO 8601 UTC.
    pub utc: String,
    /// The same instant, s since 1970-01-01T00:00:00 UTC.
    pub unix_s: f64,
    /// The same instant, h since the start.
    pub t_h: f64,
    /// The battery there, Wh (absolute).
    pub battery_wh: f64,
    /// The Sun's elevation there and then, degrees.
    pub sun_elevation_deg: f64,
    /// What brought the rover there (`start` at the first vertex; `drive`, `wait`,
    /// `charge`, `hibernate`), or for a plan's waypoint what it does next.
    pub activity: String,
}

/// A named place of the route.
#[derive(Debug, Clone, Default, Serialize)]
pub struct RoutePoint {
    /// Its name (`start`, or the goal's).
    pub name: String,
    /// Planetocentric latitude, degrees.
    pub lat_deg: f64,
    /// East longitude, degrees.
    pub lon_deg: f64,
    /// The map's elevation there, m (the DEM's datum).
    pub elevation_m: Option<f64>,
    /// The start's instant, or when the plan reaches the goal, ISO 8601 UTC.
    pub utc: Option<String>,
}

/// The map layers a GIS puts the route over: the planner's elevation and slope, and the
/// true terrain's direct sun at the job's `shadow_utc`.
#[derive(Debug, Clone, Serialize)]
pub struct MapLayers {
    /// Which map the elevation and slope are: `as planned` (no simulation: the map the
    /// plan was made on) or `as sensed` (after a simulated run: the map with every cell
    /// the rover sensed replaced by the true terrain's).
    pub map: String,
    /// The planner's map grid (size, cell, corner, projection).
    pub grid: Grid,
    /// Elevation, m (NaN where the map has no data).
    pub elevation_m: Raster<f32>,
    /// Slope, degrees (NaN where the map has no data).
    pub slope_deg: Raster<f32>,
    /// The true terrain's grid.
    pub shadow_grid: Grid,
    /// Direct sun on the true terrain: 1 lit, 0 in a cast shadow, facing away or at
    /// night, 255 no data.
    pub direct_sun: Raster<u8>,
    /// The instant of `direct_sun`, ISO 8601 UTC: the job's `shadow_utc`, within the
    /// Sun table's span.
    pub direct_sun_utc: String,
    /// The true terrain's direct sun through the run (`shadows/`).
    pub shadow_series: ShadowSeries,
    /// What keeps each cell of the map out, with a no-go mask: 0 free, 1 masked, 2
    /// within `inflate_m` of the mask, 3 cut off from the start (`no_go.tif`).
    pub no_go: Option<Raster<u8>>,
    /// Each cell's terrain class id, with terrain classes; 255 where unclassified
    /// (`classes.tif`).
    pub classes: Option<Raster<u8>>,
}

/// The no-go mask as the run applied it.
#[derive(Debug, Clone, Default, Serialize)]
pub struct NoGoFigures {
    /// The mask's file, as the scenario names it.
    pub file: String,
    /// The inflation, m.
    pub inflate_m: f64,
    /// Map cells the mask marks.
    pub masked_cells: usize,
    /// Map cells within `inflate_m` of a masked one (and not masked).
    pub inflated_cells: usize,
    /// Passable map cells the start cannot reach for the mask (and missing data).
    pub island_cells: usize,
    /// Masked and inflated cells over the map's.
    pub kept_out_fraction: f64,
    /// Reading, resampling, inflating it and finding the islands, s (wall clock).
    pub prepare_s: f64,
}

/// The terrain classes as the run applied them.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ClassFigures {
    /// The class map's file, as the scenario names it.
    pub file: String,
    /// Each class, by name.
    pub classes: BTreeMap<String, ClassUse>,
    /// Map cells no class covers (outside the class map): the rover's own model holds.
    pub unclassified_cells: usize,
    /// The initial plan's drive time over unclassified cells, s.
    pub unclassified_plan_drive_time_s: f64,
    /// Reading and resampling the class map, s (wall clock).
    pub prepare_s: f64,
}

/// One terrain class, and how much driving it takes.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ClassUse {
    /// Its id in the class map.
    pub id: u8,
    /// Drive speed over the rover's.
    pub speed_factor: f64,
    /// Locomotion power over the rover's.
    pub power_factor: f64,
    /// Its own slope limit, degrees, if any.
    pub max_slope_deg: Option<f64>,
    /// Map cells of the class.
    pub cells: usize,
    /// The initial plan's drive time on it, s (each drive's halves on their own cells).
    pub plan_drive_time_s: f64,
    /// What the initial plan's drives draw on it, Wh.
    pub plan_drive_energy_wh: f64,
    /// The simulated run's drive time on it, s.
    pub run_drive_time_s: Option<f64>,
    /// What the run's drives drew on it, Wh.
    pub run_drive_energy_wh: Option<f64>,
}

/// The most instants a shadow series holds.
pub const SERIES_FRAMES: usize = 240;

/// The longest side of a shadow series' maps, pixels: a larger map is downsampled by
/// whole cells.
pub const SERIES_PIXELS: usize = 1024;

/// The true terrain's direct sun at instants of the Sun table through the run — every
/// `every_steps`-th, so that at most [`SERIES_FRAMES`] span it — on the whole map,
/// downsampled by whole cells to at most [`SERIES_PIXELS`] a side (each pixel its
/// block's north-west cell).
#[derive(Debug, Clone, Default, Serialize)]
pub struct ShadowSeries {
    /// Map cells per pixel along each axis.
    pub cells_per_pixel: usize,
    /// Pixels west to east.
    pub cols: usize,
    /// Pixels north to south.
    pub rows: usize,
    /// The Sun table's step, s.
    pub sun_step_s: f64,
    /// Sun-table steps between two instants of the series.
    pub every_steps: usize,
    /// The instants, s since 1970-01-01T00:00:00 UTC.
    pub unix_s: Vec<f64>,
    /// The same, ISO 8601 UTC.
    pub utc: Vec<String>,
    /// Each instant's direct sun: base64 of a bitset, pixel i (row-major from the
    /// north-west) at bit i % 8 of byte i / 8, set where the ground is in direct sun.
    pub frames: Vec<String>,
    /// Where the true terrain has data, as the same kind of bitset.
    pub valid: String,
    /// The series' map in east longitude (−180..180) and latitude, degrees, on its
    /// body: a closed ring of points along its edges from its south-west corner; round a pole, the
    /// cap out to its farthest point; empty for a map in a local frame.
    pub footprint: Vec<[f64; 2]>,
    /// Its box: west, south, east, north, degrees (the whole body for a local frame).
    pub bbox: [f64; 4],
}

/// One Monte Carlo execution of a plan.
#[derive(Debug, Clone, Default, Serialize)]
pub struct MonteCarloRow {
    /// The plan executed: `chance_constrained`, `deterministic`, or either with
    /// `_closed_loop` (re-planning as it goes).
    pub plan: String,
    /// The execution's number.
    pub run: usize,
    /// Whether it reached every goal with the battery above its floor.
    pub succeeded: bool,
    /// What failed, as the simulation names it (empty when it succeeded).
    pub failure: String,
    /// The action it failed at (empty when it succeeded).
    pub failed_at_action: String,
    /// Goals reached.
    pub goals_reached: usize,
    /// When it reached the last goal, h since the start (when it reached every goal).
    pub last_arrival_h: Option<f64>,
    /// The battery at its lowest, Wh above its floor.
    pub lowest_battery_wh: f64,
}

/// One plan of the Pareto front.
#[derive(Debug, Clone, Default, Serialize)]
pub struct FrontRow {
    /// Its index in `pareto_plans`.
    pub plan: usize,
    /// When it leaves, UTC.
    pub departure_utc: String,
    /// When it leaves, h since the start.
    pub departure_h: f64,
    /// When it arrives, UTC.
    pub arrival_utc: String,
    /// When it arrives, h since the start.
    pub arrival_h: f64,
    /// Its duration, h.
    pub duration_h: f64,
    /// Energy it draws, Wh.
    pub energy_used_wh: f64,
    /// Its battery margin, Wh.
    pub margin_wh: f64,
    /// The battery at its lowest, Wh.
    pub lowest_battery_wh: f64,
    /// Its drives.
    pub drives: usize,
    /// Its charges.
    pub charges: usize,
    /// Its hibernations.
    pub hibernations: usize,
}
