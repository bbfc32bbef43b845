//! Scenario format v1: one RON file describes one job.
//!
//! ```ron
//! Scenario(
//!     version: 1,
//!     description: "A sol of sunlight at Gale crater",
//!     job: SunTable(
//!         site: (lat_deg: -4.5895, lon_east_deg: 137.4417),
//!         start_utc: "2012-08-06T05:17:57Z",
//!         duration_h: 24.66,
//!         step_min: 10,
//!     ),
//! )
//! ```
//!
//! Every struct denies unknown fields. Newtype variants may be written without their
//! inner parentheses (`SunTable(site: …)`), and optional fields without `Some(…)`.
//! Loading checks syntax, then value ranges; either kind of error names the file,
//! the line:column and the field. `docs/scenarios.md` documents every field.

pub mod ga;
pub mod locate;
pub mod planner;
pub mod rover_files;
pub(crate) mod setting;
pub mod synth;
mod validate;
mod validate_jobs;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::Error;

pub use self::validate::{Checks, Validate};

/// The body a scenario is set on, as the file names it (`Mars`, `Moon`, `Earth`): the
/// format's own name, so renaming areo-body's enum cannot change what files say.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum BodySpec {
    /// Mars (default).
    #[default]
    Mars,
    /// The Moon.
    Moon,
    /// The Earth.
    Earth,
}

impl BodySpec {
    /// The libraries' body of this name.
    pub fn model(self) -> areo_ephemeris::Body {
        self.into()
    }
}

impl From<BodySpec> for areo_ephemeris::Body {
    fn from(b: BodySpec) -> areo_ephemeris::Body {
        match b {
            BodySpec::Mars => areo_ephemeris::Body::Mars,
            BodySpec::Moon => areo_ephemeris::Body::Moon,
            BodySpec::Earth => areo_ephemeris::Body::Earth,
        }
    }
}

/// The scenario format version this build reads.
pub(crate) const FORMAT_VERSION: u32 = 1;

/// A scenario file: a versioned job description.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Format version; must be 1 (the version this build reads).
    pub version: u32,
    /// One line on what the scenario shows.
    #[serde(default)]
    pub description: String,
    /// What to run.
    pub job: Job,
}

/// The jobs areo can run. Later planners add variants.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Job {
    /// The Sun over a site at regular steps: position, local time and flux.
    SunTable(SunTableJob),
    /// Terrain (synthesised or from a file) lit by the Sun of a given place and time:
    /// slope, shadows and a preview.
    TerrainShadow(TerrainShadowJob),
    /// TEMPEST: plan a traverse in position, time and energy through ordered goals,
    /// and optionally simulate it on true terrain with sensing and re-planning.
    Tempest(Box<TempestJob>),
    /// Physics-based action planning (Farritor et al.): a genetic algorithm over
    /// action modules for the LSR-1, scored on the quasi-static model.
    Actions(Box<ActionsJob>),
}

/// An action-planning job (see `docs/actions.md`). Positions are metres in the
/// terrain's frame (synthesised terrain: east and north of its south-west corner).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActionsJob {
    /// The terrain. Rocks of a synthesised terrain are also collision obstacles.
    pub terrain: TerrainSource,
    /// Rover parameter file (RON), relative to the scenario; default LSR-1.
    #[serde(default)]
    pub rover: Option<String>,
    /// The task.
    pub task: ga::TaskSpec,
    /// Execution settings (μ, stability floor, gripper reach, body box).
    #[serde(default)]
    pub execution: ga::ExecSpec,
    /// Terrain classes on the synthesised terrain's features: each names a feature (its
    /// index in `terrain.features`), a class and the class's wheel–ground μ, which holds
    /// wherever the feature shapes the ground; default none (`execution.mu`
    /// everywhere).
    #[serde(default)]
    pub feature_classes: Vec<ga::FeatureClassSpec>,
    /// Fitness weights.
    #[serde(default)]
    pub weights: ga::WeightsSpec,
    /// GA settings.
    #[serde(default)]
    pub ga: ga::GaSpec,
    /// Modules forced in or out of the filtered inventory.
    #[serde(default)]
    pub overrides: ga::OverridesSpec,
    /// Runs of the GA, each with its own inventory (Table 1 codes) and optionally μ;
    /// default one run, "plan", on the filtered inventory.
    #[serde(default)]
    pub runs: Vec<ActionsRun>,
    /// A friction scan: (from, to, step) in μ; each μ runs the GA on the first run's
    /// inventory.
    #[serde(default)]
    pub mu_scan: Option<(f64, f64, f64)>,
    /// A line across the path (y of the ditch's far edge, m): the scan reports the
    /// smallest μ whose best plan gets past it.
    #[serde(default)]
    pub ditch_far_edge_y_m: Option<f64>,
    /// A straight climb from the task's start examined pose by pose, without the GA:
    /// (step, length), m. Writes the stability margin, pitch and front-wheel load with
    /// the arm stowed and reached forward (`climb.csv`, `climb.png`, `climb_…` facts).
    #[serde(default)]
    pub climb_profile: Option<(f64, f64)>,
    /// The paper's friction study: the first run's best plan executed unchanged at each
    /// μ, (from, to, step) — from which μ up it still crosses and completes, and what
    /// stops it below (`replay.csv`, `replay_…` facts).
    #[serde(default)]
    pub mu_replay: Option<(f64, f64, f64)>,
    /// The friction scan repeated for each GA seed (first, last), at most 100: the
    /// thresholds' median and spread over seeds (`scan_seeds.csv`, `scan_seeds_…`
    /// facts). Needs `mu_scan`.
    #[serde(default)]
    pub mu_scan_seeds: Option<(u64, u64)>,
    /// The straight climb (`climb_profile`) repeated with each assumed rover parameter
    /// set to each of its values: `[(BogieLimitDeg, [35, 45, 55]), (CgHeightM, [0.25,
    /// 0.28])]` (`sensitivity.csv`, `sensitivity_…` facts). Needs `climb_profile`.
    #[serde(default)]
    pub sensitivity: Vec<(areo_rover::Assumed, Vec<f64>)>,
}

/// One GA run of an actions job.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActionsRun {
    /// Name (facts are `runs.NAME.…`).
    pub name: String,
    /// Table 1 codes; default the filtered inventory.
    #[serde(default)]
    pub inventory: Option<Vec<u16>>,
    /// μ for this run; default the execution's.
    #[serde(default)]
    pub mu: Option<f64>,
    /// Where crossover cuts the first parent, for this run; default the GA's.
    #[serde(default)]
    pub crossover: Option<ga::CrossoverSpec>,
    /// A seed study: run the GA once for every seed from `.0` to `.1` (inclusive, at
    /// most 1000 seeds) and report the success fraction, the median first-solved
    /// generation and the pooled look-ahead histogram; default the GA's one seed.
    #[serde(default)]
    pub seeds: Option<(u64, u64)>,
}

/// A TEMPEST mission (see `docs/tempest.md`). Positions are metres east and north of
/// the map's south-west corner.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TempestJob {
    /// The map the rover believes.
    pub terrain: TerrainSource,
    /// The terrain the rover drives on; default: the map is true.
    #[serde(default)]
    pub truth: Truth,
    /// The body: `Mars` (default), `Moon` or `Earth` — its Sun (and Earth) ephemeris,
    /// radius and curvature, gravity, atmosphere and day length.
    #[serde(default)]
    pub body: BodySpec,
    /// Where on the body the map lies; synthesised maps are placed with their centre
    /// here (polar stereographic at or beyond 80° of latitude).
    pub site: SiteSpec,
    /// Mission start, ISO 8601 UTC (t = 0).
    pub start_utc: String,
    /// Planning horizon, hours (0 < h ≤ 2400).
    pub horizon_h: f64,
    /// Sun table step, minutes (1/60 ≤ min ≤ 60); default 2.
    #[serde(default = "default_sun_step_min")]
    pub sun_step_min: f64,
    /// Horizon-map sectors for terrain shadows (16..=360), 0 for none; default 64.
    #[serde(default = "default_sectors")]
    pub horizon_sectors: usize,
    /// Atmospheric optical depth τ (0 ≤ τ ≤ 10); default 0.5; ignored on the Moon.
    #[serde(default = "default_tau")]
    pub tau: f64,
    /// Rover resource-model file (RON), relative to the scenario; default: the shipped
    /// Hyperion-class rover. A locomotor that names no gravity gets the body's.
    #[serde(default)]
    pub rover: Option<String>,
    /// Battery capacity override, Wh (> 0).
    #[serde(default)]
    pub battery_capacity_wh: Option<f64>,
    /// Start position.
    pub start: PointSpec,
    /// Battery charge at the start, Wh above the battery's floor (≥ 0, at most the
    /// usable capacity).
    pub start_battery_above_floor_wh: f64,
    /// How long after `start_utc` the rover may set off, minutes (≥ 0); default 0.
    #[serde(default)]
    pub start_window_min: f64,
    /// Goals, in the order they must be reached (at least one).
    pub goals: Vec<GoalSpec>,
    /// Planner settings (areo-mission `PlannerConfig`); every field has a default, and
    /// without the block the planner is exact on the default tick
    /// ([`planner::DEFAULT_TICK_S`]), as with a block that sets none of the approximate
    /// search's fields.
    #[serde(default = "planner::PlannerSpec::on_the_default_tick")]
    pub planner: planner::PlannerSpec,
    /// Simulate execution (sensing, noise, re-planning); default: plan only.
    #[serde(default)]
    pub simulate: Option<planner::SimSpec>,
    /// Named circular regions; the run reports whether plans and the route enter them.
    #[serde(default)]
    pub regions: Vec<RegionSpec>,
    /// Ground the rover must keep out of, drawn on a raster; default none.
    #[serde(default)]
    pub no_go: Option<NoGoSpec>,
    /// What the ground is, cell by cell, and what each class does to a drive; default
    /// none (the rover's own model everywhere).
    #[serde(default)]
    pub terrain_classes: Option<TerrainClassesSpec>,
    /// When the route plot's shadows are drawn, ISO 8601 UTC; default `start_utc`.
    #[serde(default)]
    pub shadow_utc: Option<String>,
    /// How the time plots label their time axis: `Hours` since the start (default),
    /// `Utc`, or `LocalSolar` (local true solar time at the start, with the sol).
    #[serde(default)]
    pub plot_time: PlotTime,
    /// A Communicate session with Earth each sol; default none.
    #[serde(default)]
    pub communicate: Option<CommunicateSpec>,
    /// Plan in this part of the map only, for maps too large to hold (metre-scale
    /// DTMs): a GeoTIFF is read a window at a time, and the region gets the whole map's
    /// slopes and horizons (read with the halo its lowest Sun needs), so memory follows
    /// the region, not the map. Default: the whole map.
    #[serde(default)]
    pub plan_region: Option<PlanRegionSpec>,
    /// How execution departs from the model and the confidence the plan must hold at:
    /// the plan is made chance-constrained (docs/tempest.md, "Plans under
    /// uncertainty"); default none (the deterministic plan).
    #[serde(default)]
    pub uncertainty: Option<planner::UncertaintySpec>,
    /// Execute the initial plan open-loop this many times on factors drawn from
    /// `uncertainty` (with `uncertainty` only): `monte_carlo.csv`, `mc_…` facts and
    /// plots; with a confidence above 0.5 the deterministic plan is executed the same
    /// way for comparison.
    #[serde(default)]
    pub monte_carlo: Option<planner::MonteCarloSpec>,
    /// Also search the Pareto front of the plans to the goal in (arrival time, energy
    /// used, battery margin) — one goal only: `pareto_front.csv`, `pareto_front.json`,
    /// `front_…` facts and two plots, so an operator can pick a plan. Default none.
    #[serde(default)]
    pub pareto_front: Option<planner::FrontSpec>,
}

/// A rectangle of the map to plan in, metres from the map's south-west corner (as
/// `start` and `goals`), and the lowest Sun its horizons must answer for.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanRegionSpec {
    /// West and east edges, m (0 ≤ west < east).
    pub x_m: (f64, f64),
    /// South and north edges, m (0 ≤ south < north).
    pub y_m: (f64, f64),
    /// The lowest Sun the region's horizons answer for, degrees (0.5..=89; default 2):
    /// horizons below it are stored as it, so a Sun lower than this counts as hidden
    /// (it gives little power anyway). The halo read around the region is relief / tan
    /// of it.
    #[serde(default = "default_lowest_sun_deg")]
    pub lowest_sun_deg: f64,
}

fn default_lowest_sun_deg() -> f64 {
    2.0
}

/// Communicate sessions: the rover stands still with its radio on (high electronics
/// load). By default one per sol, centred on the Earth's highest point in the site's
/// sky that sol (Mars); with `every_h`, one ending at every `every_h` hours from the
/// start — at least `duration_min` minutes of contact every `every_h` hours.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CommunicateSpec {
    /// Session length, minutes (1..=720).
    pub duration_min: f64,
    /// Lowest Earth elevation for a once-a-sol session, degrees (−90..90); a sol whose
    /// Earth stays lower has no session. Default 10.
    #[serde(default = "default_earth_elevation")]
    pub min_earth_elevation_deg: f64,
    /// A session every this many hours (more than the session, at most the horizon),
    /// instead of once a sol; needed on the Moon, whose solar day is a month.
    #[serde(default)]
    pub every_h: Option<f64>,
    /// Contact deadlines, hours after the start: a session ends at each (the last
    /// `duration_min` before it), in addition to the `every_h` ones.
    #[serde(default)]
    pub deadlines_h: Vec<f64>,
    /// Whether the rover must stand where the Earth is above the terrain's horizon
    /// for the whole session (direct-to-Earth radio); default: true on the Moon, false
    /// elsewhere (Mars rovers talk through orbiters).
    #[serde(default)]
    pub earth_in_view: Option<bool>,
}

fn default_earth_elevation() -> f64 {
    10.0
}

/// The true terrain of a simulation.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub enum Truth {
    /// The map is true.
    #[default]
    Map,
    /// The map plus these landforms (what the map lacks: a higher pass, a boulder).
    AddFeatures(Vec<synth::FeatureSpec>),
    /// Another terrain on the same grid.
    Terrain(TerrainSource),
}

/// A point, m east and north of the map's south-west corner.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointSpec {
    /// East, m.
    pub x_m: f64,
    /// North, m.
    pub y_m: f64,
}

/// A goal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GoalSpec {
    /// Name for reports and plots.
    pub name: String,
    /// East, m.
    pub x_m: f64,
    /// North, m.
    pub y_m: f64,
}

/// The time axis of a TEMPEST run's time plots.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum PlotTime {
    /// Hours since the start.
    #[default]
    Hours,
    /// UTC, month-day hour:minute.
    Utc,
    /// Local true solar time at the start's longitude, with the local sol.
    LocalSolar,
}

/// A no-go mask: a raster (GeoTIFF or ESRI ASCII) whose non-zero cells the rover never
/// enters, on the map's grid or resampled onto it by nearest neighbour.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoGoSpec {
    /// The raster, relative to the scenario file.
    pub file: String,
    /// Keep this far from every masked cell too (cell centres within it), m
    /// (0..=10 000; default 0).
    #[serde(default)]
    pub inflate_m: f64,
}

/// A terrain-class map: a raster of integer class ids (GeoTIFF or ESRI ASCII), on the
/// map's grid or resampled onto it by nearest neighbour, and what each id is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainClassesSpec {
    /// The raster, relative to the scenario file.
    pub file: String,
    /// Every id the raster holds where it covers the map (at most 254).
    pub classes: Vec<TerrainClassSpec>,
}

/// One terrain class.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainClassSpec {
    /// Its value in the raster (an integer, 0..=254; `classes.tif` writes 255 where no
    /// class is).
    pub id: i64,
    /// A name for reports (letters, digits, `_` and `-`).
    pub name: String,
    /// Drive speed over the rover's on the same slope (0.01..=10; default 1).
    #[serde(default = "one")]
    pub speed_factor: f64,
    /// Locomotion power over the rover's at the same speed and slope — its rolling
    /// resistance and sinkage, lumped (0.01..=10; default 1).
    #[serde(default = "one")]
    pub power_factor: f64,
    /// Steepest slope a drive may touch on it, degrees (0..90; default: the rover's).
    #[serde(default)]
    pub max_slope_deg: Option<f64>,
}

fn one() -> f64 {
    1.0
}

/// A named circle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    /// Name (facts are `initial_plan_enters_NAME`, `route_enters_NAME`).
    pub name: String,
    /// Centre east, m.
    pub x_m: f64,
    /// Centre north, m.
    pub y_m: f64,
    /// Radius, m (> 0).
    pub radius_m: f64,
}

fn default_sun_step_min() -> f64 {
    2.0
}

fn default_sectors() -> usize {
    64
}

/// Where terrain comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum TerrainSource {
    /// Synthesised from a description (see `docs/scenarios.md`).
    Synth(synth::SynthSpec),
    /// A DEM file (GeoTIFF, ESRI ASCII or PDS3), relative to the scenario file.
    File(String),
}

/// Shadows on terrain at one instant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainShadowJob {
    /// The terrain.
    pub terrain: TerrainSource,
    /// The body: `Mars` (default), `Moon` or `Earth`.
    #[serde(default)]
    pub body: BodySpec,
    /// Where on the body the map lies (for the Sun's direction; a synthesised map is
    /// placed with its centre here).
    pub site: SiteSpec,
    /// When, ISO 8601 UTC.
    pub utc: String,
    /// Ignore planetary curvature; default false.
    #[serde(default)]
    pub flat: bool,
}

/// A table of the Sun's position over a site (see [`crate::run`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SunTableJob {
    /// Where.
    pub site: SiteSpec,
    /// First instant, ISO 8601 UTC.
    pub start_utc: String,
    /// Length of the table, hours (0 < h ≤ 24 × 800, a bit over a Mars year).
    pub duration_h: f64,
    /// Step between rows, minutes (1/60 ≤ min ≤ 1440).
    pub step_min: f64,
    /// Atmospheric optical depth τ for the surface flux (0 ≤ τ ≤ 10); default 0.5.
    #[serde(default = "default_tau")]
    pub tau: f64,
    /// Horizon elevation per equal azimuth sector from north, degrees; default flat.
    #[serde(default)]
    pub horizon_deg: Option<Vec<f64>>,
}

fn default_tau() -> f64 {
    0.5
}

/// A place on the job's body.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SiteSpec {
    /// Latitude, degrees [−90, 90]: planetocentric on Mars and the Moon, geodetic
    /// (WGS84) on the Earth.
    pub lat_deg: f64,
    /// East longitude, degrees [−360, 360].
    pub lon_east_deg: f64,
}

/// A scenario read from disk, with its name (the file stem) and path.
#[derive(Debug, Clone)]
pub struct ScenarioFile {
    /// Where it was read from.
    pub path: PathBuf,
    /// The file stem, used to name outputs (`out/NAME/`) and expectations.
    pub name: String,
    /// The parsed, validated scenario.
    pub scenario: Scenario,
    /// The text it was parsed from (to place errors found later, while running).
    pub text: String,
}

impl ScenarioFile {
    /// An error about the value of `field` (dotted, e.g. `job.goals[1]`) found while
    /// running: placed at its line:column when the field is written in the file.
    pub(crate) fn error_at(&self, field: &str, message: impl Into<String>) -> Error {
        let segments = validate_jobs::field_segments(field);
        match locate::field_position(&self.text, &segments) {
            Some((line, col)) => {
                Error::Invalid { path: self.path.clone(), line, col, field: field.to_string(), message: message.into() }
            }
            None => Error::Scenario { path: self.path.clone(), field: field.to_string(), message: message.into() },
        }
    }
}

/// Reads, parses and validates a scenario file.
pub fn load(path: &Path) -> Result<ScenarioFile, Error> {
    let text = crate::read_text(path).map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    let scenario = parse(path, &text)?;
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scenario".into());
    Ok(ScenarioFile { path: path.to_path_buf(), name, scenario, text })
}

/// Loads the scenario at `path` with fields replaced as `areo run --set PATH=VALUE`
/// gives them: PATH addresses a field as a sweep's axis does (`job.tau`,
/// `job.goals[1].x_m`), VALUE is RON (`0.6`, `"2012-08-06T22:15:00Z"`, `Mars`). The
/// field must be written in the file (any value), as for a sweep; the result is
/// validated as the file would be, and errors name the setting.
pub fn load_with(path: &Path, sets: &[String]) -> Result<ScenarioFile, Error> {
    load_setting(path, sets).map_err(|(e, from_sets)| {
        if !from_sets {
            return e;
        }
        // A value the field's type cannot take is a syntax error of the edited text:
        // name the setting that alone makes the file unreadable.
        if let Error::Syntax { message, .. } = &e
            && let Ok(text) = crate::read_text(path)
            && let Some(set) = sets.iter().find(|set| {
                apply_setting(path, &text, set).is_ok_and(|one| matches!(parse(path, &one), Err(Error::Syntax { .. })))
            })
        {
            let (field, value) = set.split_once('=').unwrap_or((set, ""));
            let message = format!("{}: not a value `{}` can take ({message})", value.trim(), field.trim());
            return Error::usage(format!("--set {set}"), message);
        }
        Error::usage(format!("--set {}", sets.join(" --set ")), e.to_string())
    })
}

/// [`load_with`] for a library caller: an error the settings cause is the scenario's
/// own (`Invalid` names the field, its line and column in the file), not a usage error
/// of the command line.
pub fn load_set(path: &Path, sets: &[String]) -> Result<ScenarioFile, Error> {
    load_setting(path, sets).map_err(|(e, _)| e)
}

/// [`load_with`]'s work; an error says whether the settings caused it (the file
/// parsed as written). Each value must be one RON value ([`setting::one_value`]): it
/// replaces its field's value and nothing else.
fn load_setting(path: &Path, sets: &[String]) -> Result<ScenarioFile, (Error, bool)> {
    let mut file = load(path).map_err(|e| (e, false))?;
    if sets.is_empty() {
        return Ok(file);
    }
    let mut text = file.text.clone();
    for set in sets {
        text = apply_setting(path, &text, set)?;
    }
    file.scenario = parse(path, &text).map_err(|e| (e, true))?;
    file.text = text;
    Ok(file)
}

/// `text` with the value of the field that `set` (`PATH=VALUE`) names replaced by its
/// value.
fn apply_setting(path: &Path, text: &str, set: &str) -> Result<String, (Error, bool)> {
    let Some((field, value)) = set.split_once('=') else {
        return Err((Error::usage(format!("--set {set}"), "write PATH=VALUE, e.g. job.tau=0.6"), false));
    };
    let (field, value) = (field.trim(), value.trim());
    if let Err(why) = setting::one_value(value) {
        return Err((Error::usage(format!("--set {set}"), format!("the value of `{field}` {why}")), false));
    }
    let span = crate::sweep::value_span(text, &crate::sweep::segments(field)).ok_or_else(|| {
        let message = "is not written in the file: write the field out (any value) to set it".to_string();
        (Error::Scenario { path: path.to_path_buf(), field: field.to_string(), message }, true)
    })?;
    let mut text = text.to_string();
    text.replace_range(span, value);
    Ok(text)
}

/// Refuses the first number in `text` (a file of `kind`, e.g. "a scenario") that is not
/// finite — `NaN`, `inf`, or a literal too large for f64 — with its field and place.
pub(crate) fn refuse_non_finite(path: &Path, text: &str, kind: &str) -> Result<(), Error> {
    match locate::scalars(text).into_iter().find(|s| s.value().is_some_and(|v| !v.is_finite())) {
        None => Ok(()),
        Some(bad) => Err(Error::Invalid {
            path: path.to_path_buf(),
            line: bad.line,
            col: bad.col,
            field: validate::Violation { path: bad.path, message: String::new() }.dotted(),
            message: format!("`{}` is not a finite number: every number in {kind} must be finite", bad.text),
        }),
    }
}

/// Parses and validates scenario text; `path` only labels errors.
pub fn parse(path: &Path, text: &str) -> Result<Scenario, Error> {
    refuse_hostile_shape(path, text)?;
    let scenario: Scenario = ron_options().from_str(text).map_err(|e| {
        // A number of the wrong type (−1 for a count, 2^64 for an index) is a syntax
        // error to RON; name the field it was written for.
        let (line, col) = (e.span.start.line, e.span.start.col);
        let field = locate::scalars(text)
            .into_iter()
            .find(|s| {
                let cols = s.col..=s.col + s.text.chars().count();
                s.line == line && (cols.contains(&col) || (e.span.end.line == line && cols.contains(&e.span.end.col)))
            })
            .map(|s| validate::Violation { path: s.path, message: String::new() }.dotted());
        let mut located = syntax_error(path, &e);
        if let (Error::Syntax { message, .. }, Some(f)) = (&mut located, field.filter(|f| !f.is_empty())) {
            *message = format!("field `{f}`: {message}");
        }
        located
    })?;
    // Every number must be finite, whatever field it is in: NaN and infinity (written,
    // or a literal too large for f64) are refused here once, with their place.
    refuse_non_finite(path, text, "a scenario")?;
    let mut checks = Checks::default();
    scenario.validate(&mut checks);
    if let Some(v) = checks.into_first() {
        let (line, col) = locate::field_position(text, &v.path).unwrap_or((1, 1));
        return Err(Error::Invalid { path: path.to_path_buf(), line, col, field: v.dotted(), message: v.message });
    }
    Ok(scenario)
}

/// A RON parse error of `path` as [`Error::Syntax`] at its line and column.
pub(crate) fn syntax_error(path: &Path, e: &ron::error::SpannedError) -> Error {
    Error::Syntax {
        path: path.to_path_buf(),
        line: e.span.start.line,
        col: e.span.start.col,
        message: match e.code {
            // Said with what is allowed: a count, a seed or an index is a whole number
            // of 0 or more, and fits its field.
            ron::Error::IntegerOutOfBounds => {
                "integer out of bounds: allowed a whole number of 0 or more that fits the field (counts, seeds \
                 and indices)"
                    .to_string()
            }
            ref code => code.to_string(),
        },
    }
}

/// Reads and parses a RON file of areo's dialect ([`ron_options`]): unreadable is
/// [`Error::Read`], unparsable [`Error::Syntax`].
pub(crate) fn read_ron<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, Error> {
    let text = crate::read_text(path).map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    refuse_hostile_shape(path, &text)?;
    ron_options().from_str(&text).map_err(|e| syntax_error(path, &e))
}

/// Refuses what areo-rover's shape limits refuse (nesting, list lengths), where it starts.
pub(crate) fn refuse_hostile_shape(path: &Path, text: &str) -> Result<(), Error> {
    match areo_rover::refused_shape(text) {
        None => Ok(()),
        Some((line, col, message)) => Err(Error::Syntax { path: path.to_path_buf(), line, col, message }),
    }
}

/// The RON options every areo file is read with (areo-rover's, for one dialect).
pub(crate) fn ron_options() -> ron::Options {
    areo_rover::ron_options()
}

#[cfg(test)]
mod body_tests {
    use super::BodySpec;

    #[test]
    fn each_body_the_file_names_is_the_librarys_body_of_that_name() {
        for (text, model) in [
            ("Mars", areo_ephemeris::Body::Mars),
            ("Moon", areo_ephemeris::Body::Moon),
            ("Earth", areo_ephemeris::Body::Earth),
        ] {
            let body: BodySpec = ron::from_str(text).unwrap();
            assert_eq!(body.model(), model);
            assert_eq!(ron::to_string(&body).unwrap(), text, "written back as read");
        }
        assert_eq!(BodySpec::default().model(), areo_ephemeris::Body::default());
        assert!(ron::from_str::<BodySpec>("Venus").is_err());
    }
}
