//! TEMPEST's actions (Table 3) and local constraints (Table 4), evaluated forward in
//! time: what an action starting at a cell and an instant takes (duration) and costs
//! the battery, or which constraint forbids it.
//!
//! - Drive to one of the 8 neighbours: the 3-D distance over the slope-dependent speed;
//!   locomotor + high electronics load, against the solar array tilted with the rover
//!   on the ground and pointed along the drive.
//! - Charge: a fixed duration at the charge load (medium by default); by default it
//!   needs direct sun.
//! - Hibernate: a fixed duration at the low load, asleep: the solar array is off-line
//!   (Table 3 gives Hibernate no power source), so only a generator, if any, feeds it.
//!
//! Stationary actions point the array at the Sun (the rover turns to face it first)
//! [A]. Energy is integrated with the trapezoid rule over samples no further apart than
//! the Sun table's step; net power drains the battery through its discharge efficiency
//! and charges it through its charge efficiency.

use areo_rover::resources::{Load, ResourceModel};
use serde::{Deserialize, Serialize};

use crate::effect::{Drawn, Effect};
use crate::ground::Factors;
use crate::world::{GridSun, World};

mod bounds;
mod wait;

/// The azimuth of drive direction `k` (rows grow southward: a drive of (dc, dr) heads
/// atan2(dc, −dr) from north), degrees.
fn heading_of(k: u8) -> f64 {
    let (dc, dr) = NEIGHBOURS[k as usize % 8];
    f64::from(dc).atan2(-f64::from(dr)).to_degrees().rem_euclid(360.0)
}

/// The neighbour of `cell` in direction `k` of [`NEIGHBOURS`], if it is on the map.
pub(crate) fn neighbour(world: &World, cell: u32, k: u8) -> Option<u32> {
    let (c, r) = world.col_row(cell);
    let (dc, dr) = NEIGHBOURS[k as usize % 8];
    let (nc, nr) = (c as i64 + i64::from(dc), r as i64 + i64::from(dr));
    let on_map = nc >= 0 && nr >= 0 && nc < world.cols() as i64 && nr < world.rows() as i64;
    on_map.then(|| world.cell(nc as usize, nr as usize))
}

/// How far before the epoch a backward drive may start and still count as starting at
/// it: sums of drive durations round differently from the straight-line best case, s.
const EPOCH_SLACK_S: f64 = 1e-6;

/// Stationary actions sample the Sun at least this often, s.
const STATIONARY_SAMPLE_S: f64 = 1200.0;

/// The 8 neighbour offsets (dcol, drow), starting north and going clockwise (rows grow
/// southward).
pub const NEIGHBOURS: [(i32, i32); 8] = [(0, -1), (1, -1), (1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1)];

/// A TEMPEST action.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Action {
    /// Drive to neighbour `k` of [`NEIGHBOURS`].
    Drive(u8),
    /// Charge in place.
    Charge,
    /// Hibernate in place.
    Hibernate,
    /// Wait in place for one wait step ([`ActionConfig::wait_step_s`]), charging where the
    /// array sees the Sun and sleeping where it does not; steps back to back are one
    /// wait of their sum.
    Wait,
}

impl Action {
    /// A short name for plans.
    pub fn name(self) -> &'static str {
        match self {
            Action::Drive(k) => {
                ["drive N", "drive NE", "drive E", "drive SE", "drive S", "drive SW", "drive W", "drive NW"]
                    [k as usize % 8]
            }
            Action::Charge => "charge",
            Action::Hibernate => "hibernate",
            Action::Wait => "wait",
        }
    }
}

/// How an action departs from the nominal model: the simulation's execution noise, or
/// (as [`ActionModel::with_margins`]) the pessimistic model a chance-constrained plan
/// is made with.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Perturbation {
    /// Drive durations are multiplied by this (≥ 1: slower than planned).
    pub duration_factor: f64,
    /// Solar input is multiplied by this (≤ 1: dust, haze, a poorly pointed array).
    pub solar_factor: f64,
    /// Electrical loads (locomotion and electronics) are multiplied by this (≥ 1:
    /// hungrier than modelled).
    pub draw_factor: f64,
    /// A delay before the action, s (≥ 0: a late command, a wait for data), spent at
    /// the action's load with the array off-line (a conservative way to spend it).
    pub delay_s: f64,
}

impl Perturbation {
    /// Execution exactly as modelled.
    pub const NONE: Perturbation =
        Perturbation { duration_factor: 1.0, solar_factor: 1.0, draw_factor: 1.0, delay_s: 0.0 };

    /// Slower drives and less sunlight only (the simulation's noise).
    pub fn drive_and_solar(duration_factor: f64, solar_factor: f64) -> Perturbation {
        Perturbation { duration_factor, solar_factor, draw_factor: 1.0, delay_s: 0.0 }
    }
}

/// Local constraints of one action (Table 4), each on or off.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Constraints {
    /// No action on slopes above the maximum.
    pub max_slope: bool,
    /// No action while the Sun is below the horizontal.
    pub daylight: bool,
    /// No action in shadow or at night.
    pub direct_sun: bool,
    /// No drive whose heading puts the Sun in a navigation camera's view.
    pub sun_in_camera: bool,
}

/// Why an action is not possible.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Binding {
    /// The destination is off the map, missing data or blocked.
    Blocked,
    /// A slope above the maximum (the rover's or its terrain class's).
    Slope,
    /// A drive whose roll is above the rover's `max_roll_deg`.
    Roll,
    /// A drive whose pitch is above the rover's uphill or downhill limit.
    Pitch,
    /// The Sun is down.
    Darkness,
    /// In shadow (direct-sun constraint).
    Shadow,
    /// The Sun would be in a camera's view.
    SunInCamera,
    /// Outside the tabulated planning horizon.
    Horizon,
    /// The battery cannot hold the energy the path needs.
    Battery,
    /// A scheduled Communicate session: the rover must stand still.
    Communicate,
    /// A scheduled Communicate session: the rover must stand where the Earth is in view.
    EarthHidden,
    /// The goal windows: every goal must be reached within the fastest travel plus the
    /// detour allowance plus `max_wait_s` of waiting (`PlannerConfig::max_wait_s`), and
    /// a plan needs to wait longer.
    GoalWindow,
    /// Battery, darkness, shadow, camera and session constraints together (those the
    /// rover and its actions have): no one of them relaxed alone makes a plan, all
    /// relaxed at once do. The error's message names the ones relaxed.
    Together,
    /// No plan exists (proven), but the searches that relax one constraint at a time to
    /// name the one that binds ran out of their share of the call's work or memory
    /// before they could tell.
    Undetermined,
}

impl Binding {
    /// A description for reports.
    pub fn describe(self) -> &'static str {
        match self {
            Binding::Blocked => "no passable cells connect start and goal",
            Binding::Slope => "slopes above the rover's maximum (or a terrain class's)",
            Binding::Roll => "roll above the rover's max_roll_deg (drives across slopes)",
            Binding::Pitch => "pitch above the rover's uphill or downhill limit",
            Binding::Darkness => "darkness (driving needs daylight)",
            Binding::Shadow => "shadow (the action needs direct sun)",
            Binding::SunInCamera => "the Sun in the navigation cameras",
            Binding::Horizon => "the planning horizon (the goal cannot be reached within it)",
            Binding::Battery => "battery energy",
            Binding::GoalWindow => {
                "the goal windows (`max_wait_s`: the plan must wait longer than the windows allow; a plan is \
                 found with them open to the planning horizon)"
            }
            Binding::Communicate => "a scheduled Communicate session (the rover stands still)",
            Binding::EarthHidden => "a scheduled Communicate session (the Earth must be in view)",
            Binding::Together => {
                "several constraints together (battery, darkness, shadow, the Sun in the cameras, sessions: \
                 none relaxed alone makes a plan, all relaxed at once do)"
            }
            Binding::Undetermined => {
                "not determined (the searches that relax one constraint at a time ran out of their share of the \
                 work or memory budget)"
            }
        }
    }
}

/// The action parameters of a planner.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ActionConfig {
    /// Duration of one Charge, s.
    pub charge_s: f64,
    /// Duration of one Hibernate, s.
    pub hibernate_s: f64,
    /// Electronics level while charging.
    pub charge_load: LoadLevel,
    /// Constraints on drives.
    pub drive: Constraints,
    /// Constraints on Charge.
    pub charge: Constraints,
    /// Constraints on Hibernate.
    pub hibernate: Constraints,
    /// Steepest slope allowed where `max_slope` applies, degrees (default: the
    /// locomotor's maximum).
    pub max_slope_deg: Option<f64>,
    /// Round every duration up to a multiple of this, s (0: exact).
    pub time_quantum_s: f64,
    /// Round every energy change to a multiple of this, Wh (0: exact).
    pub energy_quantum_wh: f64,
    /// The rover's stationary action. `None`: the paper's Charge and Hibernate of fixed
    /// durations. `Some(step)`: it waits, in steps of `step` s that chain into waits of
    /// any whole number of steps, charging where its array sees the Sun and sleeping
    /// where it does not ([`Action::Wait`]).
    pub wait_step_s: Option<f64>,
}

impl Default for ActionConfig {
    fn default() -> ActionConfig {
        ActionConfig {
            charge_s: 1800.0,
            hibernate_s: 3600.0,
            charge_load: LoadLevel::Medium,
            drive: Constraints { max_slope: true, daylight: true, direct_sun: false, sun_in_camera: true },
            charge: Constraints { max_slope: false, daylight: false, direct_sun: true, sun_in_camera: false },
            hibernate: Constraints::default(),
            max_slope_deg: None,
            time_quantum_s: 0.0,
            energy_quantum_wh: 0.0,
            wait_step_s: None,
        }
    }
}

/// An electronics level, as written in scenarios.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum LoadLevel {
    /// Low.
    Low,
    /// Medium.
    Medium,
    /// High.
    High,
}

impl LoadLevel {
    pub(crate) fn load(self) -> Load {
        match self {
            LoadLevel::Low => Load::Low,
            LoadLevel::Medium => Load::Medium,
            LoadLevel::High => Load::High,
        }
    }
}

/// The shared arrival side of the drives into one cell at one time (see
/// [`ActionModel::arrival`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Arrival {
    to: u32,
    t1: f64,
    sun: GridSun,
    /// Whether the Sun lights the arrival cell (false without a solar array).
    lit: bool,
}

/// Evaluates actions for one rover in one world.
#[derive(Debug, Clone)]
pub struct ActionModel {
    rover: ResourceModel,
    config: ActionConfig,
    max_slope_deg: f64,
    /// The array's normal on level ground for each drive heading.
    level_normals: [[f64; 3]; 8],
    /// Azimuth of each drive direction, degrees.
    headings: [f64; 8],
    /// sin and cos of the array's tilt.
    tilt_sin_cos: (f64, f64),
    /// Scheduled Communicate sessions, s after the epoch, sorted.
    sessions: Vec<(f64, f64)>,
    /// Whether a session needs the Earth in view from where the rover stands.
    sessions_need_earth: bool,
    /// The planning margins every modelled action carries ([`ActionModel::with_margins`]).
    margins: Perturbation,
}

/// A drive's moving part: its time, its load and how they divide between its halves.
#[derive(Debug, Clone, Copy, Default)]
struct DriveRun {
    moving_s: f64,
    load_w: f64,
    from_time_share: f64,
    from_energy_share: f64,
}

impl DriveRun {
    /// The slower time and the hungrier load of two runs (shares from the slower).
    fn worst(self, other: DriveRun) -> DriveRun {
        let slower = if other.moving_s > self.moving_s { other } else { self };
        DriveRun { load_w: self.load_w.max(other.load_w), ..slower }
    }
}

/// A drive's time-independent part: where it ends, how long it takes, its slope and
/// its load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveGeometry {
    /// Destination cell.
    pub to: u32,
    /// Duration, s (quantised), the planning margin's delay included.
    pub duration_s: f64,
    /// The planning margin's delay before the drive moves, s (part of `duration_s`).
    pub delay_s: f64,
    /// Slope along the drive, degrees (positive uphill): the rover's pitch with its
    /// wheels on both cells.
    pub slope_deg: f64,
    /// The rover's roll on the drive, degrees (positive right side up): the larger
    /// across the heading of the two cells' ground ([`World::attitude_deg`]); on an
    /// envelope of terrains ([`World::envelope`]) the map's widened by how far the
    /// members' ground normals depart from it.
    pub roll_deg: f64,
    /// The share of the moving time spent on the first cell's half (½ where both cells
    /// are of one class).
    pub from_time_share: f64,
    /// The share of the moving energy (loads) spent on the first cell's half.
    pub from_energy_share: f64,
    /// Locomotion plus the high electronics load, W.
    pub load_w: f64,
    /// The share of the moving time the array is credited for: 1, or on an envelope of
    /// terrains ([`World::envelope`]) the fastest member's moving time over the
    /// slowest's (the fastest rover charges only that long, then waits asleep).
    pub solar_share: f64,
}

impl ActionModel {
    /// The model for `rover` with `config`.
    pub fn new(rover: ResourceModel, config: ActionConfig) -> ActionModel {
        let max_slope_deg = config.max_slope_deg.unwrap_or(rover.locomotor.max_slope_deg);
        let level_normals =
            std::array::from_fn(|k| rover.solar.map_or([0.0, 0.0, 1.0], |a| a.level_normal_enu(heading_of(k as u8))));
        let tilt_sin_cos = rover.solar.map_or((0.0, 1.0), |a| a.tilt_deg.to_radians().sin_cos());
        let headings = std::array::from_fn(|k| heading_of(k as u8));
        ActionModel {
            rover,
            config,
            max_slope_deg,
            level_normals,
            headings,
            tilt_sin_cos,
            sessions: Vec::new(),
            sessions_need_earth: false,
            margins: Perturbation::NONE,
        }
    }

    /// The same model with every action made worse by `margins` (drives slower, loads
    /// hungrier, sunlight weaker), so that a plan made with it holds for executions
    /// that depart from the nominal model by no more than that: how a chance-constrained
    /// plan is made ([`crate::uncertainty`]). Only worsening margins are accepted
    /// (duration and draw factors ≥ 1, solar factor in 0..=1), so every lower bound the
    /// search uses on the nominal model stays a lower bound.
    pub fn with_margins(mut self, margins: Perturbation) -> ActionModel {
        let ok = margins.duration_factor >= 1.0
            && margins.draw_factor >= 1.0
            && (0.0..=1e6).contains(&margins.delay_s)
            && (0.0..=1.0).contains(&margins.solar_factor)
            && margins.duration_factor.is_finite()
            && margins.draw_factor.is_finite();
        debug_assert!(ok, "margins must worsen the model: {margins:?}");
        if ok {
            self.margins = margins;
        }
        self
    }

    /// The planning margins (none unless [`ActionModel::with_margins`] set them).
    pub fn margins(&self) -> Perturbation {
        self.margins
    }

    /// This model without planning margins: how actions are executed.
    pub fn nominal(&self) -> ActionModel {
        ActionModel { margins: Perturbation::NONE, ..self.clone() }
    }

    /// Schedules Communicate sessions (start, end), s after the epoch: during each the
    /// rover stands still (no drive may overlap it) with its electronics at the high
    /// load (the radio), whatever stationary action it is in.
    pub fn with_sessions(mut self, mut sessions: Vec<(f64, f64)>) -> ActionModel {
        sessions.retain(|(a, b)| b > a);
        sessions.sort_by(|a, b| a.0.total_cmp(&b.0));
        self.sessions = sessions;
        self
    }

    /// Makes every session need the Earth in view from where the rover stands
    /// ([`World::earth_visible`], checked at each stationary sample inside a session):
    /// direct-to-Earth radio from the Moon.
    pub fn sessions_need_earth(mut self, need: bool) -> ActionModel {
        self.sessions_need_earth = need;
        self
    }

    /// Whether sessions need the Earth in view.
    pub fn needs_earth(&self) -> bool {
        self.sessions_need_earth
    }

    /// The scheduled Communicate sessions, s after the epoch.
    pub fn sessions(&self) -> &[(f64, f64)] {
        &self.sessions
    }

    fn in_session(&self, t: f64) -> bool {
        self.sessions.iter().any(|&(a, b)| t >= a && t < b)
    }

    /// Whether some drive may depart at `t` (s after the epoch) from some cell: false
    /// only where every drive is refused whatever the cell — past the horizon, in the
    /// dark under the daylight rule, inside a communication session.
    pub(crate) fn drives_may_depart(&self, world: &World, t: f64) -> bool {
        t <= world.span_s() && !(self.config.drive.daylight && world.sun(t).elevation_deg <= 0.0) && !self.in_session(t)
    }

    fn overlaps_session(&self, t0: f64, t1: f64) -> bool {
        self.sessions.iter().any(|&(a, b)| t0 < b && t1 > a)
    }

    /// The rover.
    pub fn rover(&self) -> &ResourceModel {
        &self.rover
    }

    /// The action parameters.
    pub fn config(&self) -> &ActionConfig {
        &self.config
    }

    /// Usable battery energy, Wh.
    pub fn capacity_wh(&self) -> f64 {
        let b = &self.rover.battery;
        b.capacity_wh * (b.max_soc - b.min_soc)
    }

    fn quantise_time(&self, d: f64) -> f64 {
        let q = self.config.time_quantum_s;
        if q > 0.0 { (d / q - 1e-9).ceil().max(1.0) * q } else { d }
    }

    fn quantise_energy(&self, e: f64) -> f64 {
        let q = self.config.energy_quantum_wh;
        // Round to nearest (ties to even) by the 1.5·2^52 trick: f64::round is a libm
        // call on the baseline target, and this runs for every generated label.
        const MAGIC: f64 = 6_755_399_441_055_744.0;
        if q > 0.0 { ((e / q + MAGIC) - MAGIC) * q } else { e }
    }

    /// A load energy rounded up to the energy quantum (see [`Effect::load_wh`]).
    fn quantise_load(&self, wh: f64) -> f64 {
        let q = self.config.energy_quantum_wh;
        if q > 0.0 { (wh / q - 1e-9).ceil().max(0.0) * q } else { wh }
    }

    /// The least power the loads draw in any action, W: the hibernation load, the
    /// charge load or the high electronics load a drive adds its locomotion to (no
    /// sessions: they only add the radio's).
    pub(crate) fn least_load_w(&self) -> f64 {
        let e = &self.rover.electronics;
        let charge = e.power_w(self.config.charge_load.load());
        e.power_w(Load::Low).min(charge).min(e.power_w(Load::High)) * self.margins.draw_factor
    }

    /// The least energy the loads draw on the drive with `geometry`, Wh (the load at
    /// its duration, before rounding up).
    pub(crate) fn drive_load_floor_wh(&self, geometry: &DriveGeometry) -> f64 {
        let wh = geometry.load_w * geometry.duration_s / 3600.0;
        wh - 1e-9 * wh.abs()
    }

    /// The drive from `from` to its neighbour `k`, or why it is not possible
    /// (independent of time). Half of it runs over each cell, at that cell's terrain
    /// class's speed and power ([`crate::ClassMap`]).
    pub fn drive_geometry(&self, world: &World, from: u32, k: u8) -> Result<DriveGeometry, Binding> {
        let to = neighbour(world, from, k).ok_or(Binding::Blocked)?;
        let (dc, dr) = NEIGHBOURS[k as usize % 8];
        if !world.passable(to) || !world.passable(from) {
            return Err(Binding::Blocked);
        }
        let (h0, h1) = (world.elevation(from).ok_or(Binding::Blocked)?, world.elevation(to).ok_or(Binding::Blocked)?);
        let dem = world.dem();
        let (ex, ny) = (f64::from(dc) * dem.dx(), f64::from(dr) * dem.dy());
        let run = (ex * ex + ny * ny).sqrt();
        let ground = (world.factors(from), world.factors(to));
        // The slope limit where a drive touches: the rover's, and each cell's class's.
        let limit = self.max_slope_deg.min(ground.0.max_slope_deg).min(ground.1.max_slope_deg);
        if self.config.drive.max_slope && (world.slope_deg(from) > limit || world.slope_deg(to) > limit) {
            return Err(Binding::Slope);
        }
        let roll_deg = self.drive_roll(world, (from, to), k)?;
        let (slope, run_over, solar_share) = match (world.member_heights(from), world.member_heights(to)) {
            (None, None) => {
                let (slope, over) = self.drive_over(run, h1 - h0, limit, ground)?;
                (slope, over, 1.0)
            }
            // An envelope of terrains: the drive as slow, as steep and as hungry as on
            // its worst member, credited with sunlight for its fastest member's time.
            (a, b) => {
                let n = world.terrain_members();
                let height = |m: Option<&[f32]>, own: f64, i: usize| m.map_or(own, |m| f64::from(m[i]));
                let (mut worst, mut fastest) = ((0.0f64, DriveRun::default()), f64::INFINITY);
                for i in 0..n {
                    let rise = height(b, h1, i) - height(a, h0, i);
                    if rise.is_nan() {
                        return Err(Binding::Blocked);
                    }
                    let (slope, over) = self.drive_over(run, rise, limit, ground)?;
                    if slope.abs() > worst.0.abs() {
                        worst.0 = slope;
                    }
                    worst.1 = worst.1.worst(over);
                    fastest = fastest.min(over.moving_s);
                }
                let moving = worst.1.moving_s;
                (worst.0, worst.1, if moving > 0.0 { fastest / moving } else { 1.0 })
            }
        };
        let delay_s = self.margins.delay_s;
        let duration_s = self.quantise_time(run_over.moving_s * self.margins.duration_factor + delay_s);
        Ok(DriveGeometry {
            to,
            duration_s,
            delay_s,
            slope_deg: slope,
            roll_deg,
            load_w: run_over.load_w,
            solar_share,
            from_time_share: run_over.from_time_share,
            from_energy_share: run_over.from_energy_share,
        })
    }

    /// The drive's roll ([`DriveGeometry::roll_deg`]), or `Roll` over the rover's limit.
    fn drive_roll(&self, world: &World, (from, to): (u32, u32), k: u8) -> Result<f64, Binding> {
        let heading = self.headings[k as usize % 8];
        let roll_at = |cell: u32| {
            let roll = world.attitude_deg(cell, heading).1;
            // On an envelope a member's ground tips the rover by at most the angle whose
            // chord is the spread, away from the map's.
            let widen =
                world.attitude_spread(cell).map_or(0.0, |chord| 2.0 * (chord / 2.0).min(1.0).asin().to_degrees());
            roll + widen.copysign(roll)
        };
        let (a, b) = (roll_at(from), roll_at(to));
        let roll = if b.abs() > a.abs() { b } else { a };
        match self.rover.locomotor.max_roll_deg {
            Some(max) if roll.abs() > max => Err(Binding::Roll),
            _ => Ok(roll),
        }
    }

    /// A drive over `run` m of ground rising `rise` m, half over a cell of class
    /// `ground.0` and half over one of `ground.1`: its slope (degrees) and its run (the
    /// moving time at the nominal speeds there and the load with the planning margin);
    /// `Slope` above `limit` (the rover's and the classes' slope limit), `Pitch` above
    /// the rover's pitch limits.
    fn drive_over(
        &self,
        run: f64,
        rise: f64,
        limit: f64,
        ground: (Factors, Factors),
    ) -> Result<(f64, DriveRun), Binding> {
        // run > 0: one-argument arctangent.
        let slope = (rise / run).atan().to_degrees();
        if self.config.drive.max_slope && slope.abs() > limit {
            return Err(Binding::Slope);
        }
        let loco = &self.rover.locomotor;
        if loco.max_pitch_up_deg.is_some_and(|m| slope > m) || loco.max_pitch_down_deg.is_some_and(|m| -slope > m) {
            return Err(Binding::Pitch);
        }
        let speed = loco.speed_on_slope_m_s(slope);
        let length = (run * run + rise * rise).sqrt();
        let electronics = self.rover.electronics.power_w(Load::High);
        let (sin, cos) = (rise / length, run / length);
        let draw = self.margins.draw_factor;
        if ground.0 == ground.1 {
            let (v, p) = (speed * ground.0.speed, ground.0.power);
            let load_w = (loco.power_on_w(v, sin, cos) * p + electronics) * draw;
            let over = DriveRun { moving_s: length / v, load_w, from_time_share: 0.5, from_energy_share: 0.5 };
            return Ok((slope, over));
        }
        // Each half at its own class's speed and power: the load is the energy over the
        // time.
        let half = |f: Factors| {
            let v = speed * f.speed;
            let t = 0.5 * length / v;
            (t, (loco.power_on_w(v, sin, cos) * f.power + electronics) * draw * t)
        };
        let ((t0, e0), (t1, e1)) = (half(ground.0), half(ground.1));
        let over = DriveRun {
            moving_s: t0 + t1,
            load_w: (e0 + e1) / (t0 + t1),
            from_time_share: t0 / (t0 + t1),
            from_energy_share: if e0 + e1 > 0.0 { e0 / (e0 + e1) } else { 0.5 },
        };
        Ok((slope, over))
    }

    /// The drive from `from` to neighbour `k` starting at `t0`.
    pub fn drive(&self, world: &World, from: u32, k: u8, t0: f64) -> Result<(u32, Effect), Binding> {
        let geometry = self.drive_geometry(world, from, k)?;
        self.drive_perturbed(world, from, k, geometry, t0, Perturbation::NONE)
    }

    /// The arrival side of the drives into `to` that end at `t1` — what the 8 headings
    /// of a backward expansion share: the Sun, whether it lights the cell and the
    /// heading-independent checks there. `None` when no drive can end there then.
    pub(crate) fn arrival(&self, world: &World, to: u32, t1: f64) -> Option<Arrival> {
        if t1 > world.span_s() {
            return None;
        }
        let sun = world.sun(t1);
        self.check(world, &self.config.drive, to, &sun, None).ok()?;
        let lit = self.rover.solar.is_some() && world.lit(to, &sun);
        Some(Arrival { to, t1, sun, lit })
    }

    /// The cell from which drive `k` leads into `to`, and the drive's geometry; `None`
    /// off the map or when the drive is impossible at any time.
    pub(crate) fn drive_geometry_into(&self, world: &World, to: u32, k: u8) -> Option<(u32, DriveGeometry)> {
        let (c, r) = world.col_row(to);
        let (dc, dr) = NEIGHBOURS[k as usize % 8];
        let (pc, pr) = (c as i64 - i64::from(dc), r as i64 - i64::from(dr));
        if pc < 0 || pr < 0 || pc >= world.cols() as i64 || pr >= world.rows() as i64 {
            return None;
        }
        let from = world.cell(pc as usize, pr as usize);
        Some((from, self.drive_geometry(world, from, k).ok()?))
    }

    /// The drive in direction `k` from `from` (with its `geometry`, from
    /// [`ActionModel::drive_geometry_into`]) that ends at `arrival`: the backward
    /// transition of [`ActionModel::drive`], which it equals — same checks, same energy.
    pub(crate) fn drive_into(
        &self,
        world: &World,
        arrival: &Arrival,
        k: u8,
        from: u32,
        DriveGeometry { duration_s: duration, delay_s: delay, load_w: load, solar_share: share, .. }: DriveGeometry,
    ) -> Option<(u32, Effect)> {
        let (t1, s1) = (arrival.t1, &arrival.sun);
        let t0 = t1 - duration;
        // A path from the earliest goal instant (the best case: straight at top speed)
        // starts at the epoch to within rounding, on either side of it.
        if t0 < -EPOCH_SLACK_S || self.overlaps_session(t0, t1) {
            return None;
        }
        let heading = self.headings[k as usize % 8];
        let rules = &self.config.drive;
        // The arrival cell passed its heading-free checks; the camera's depends on k.
        if rules.sun_in_camera
            && s1.elevation_deg > 0.0
            && self.rover.sun_in_cameras(heading, s1.azimuth_deg, s1.elevation_deg)
        {
            return None;
        }
        let s0 = world.sun(t0);
        self.check(world, rules, from, &s0, Some(heading)).ok()?;
        let lit0 = self.rover.solar.is_some() && world.lit(from, &s0);
        let p0 = load - self.drive_source_lit_w(world, from, &s0, k, lit0, share);
        let p1 = load - self.drive_source_lit_w(world, arrival.to, s1, k, arrival.lit, share);
        let drawn = self.drive_energy_wh(load, (p0, p1), duration, delay);
        Some((from, self.effect(&drawn, duration, load * duration / 3600.0)))
    }

    fn drive_perturbed(
        &self,
        world: &World,
        from: u32,
        k: u8,
        DriveGeometry { to, duration_s, delay_s, load_w: load, solar_share: share, .. }: DriveGeometry,
        t0: f64,
        p: Perturbation,
    ) -> Result<(u32, Effect), Binding> {
        // The margin's delay stays as planned; execution adds its own and moves slower.
        let delay = delay_s + p.delay_s;
        let duration = (duration_s - delay_s) * p.duration_factor + delay;
        let load = load * p.draw_factor;
        let t1 = t0 + duration;
        // The same slack as the backward transition (`drive_into`), so that a planned
        // drive replays forward.
        if t0 < -EPOCH_SLACK_S || t1 > world.span_s() {
            return Err(Binding::Horizon);
        }
        if self.overlaps_session(t0, t1) {
            return Err(Binding::Communicate);
        }
        let heading = self.headings[k as usize % 8];
        let (s0, s1) = (world.sun(t0), world.sun(t1));
        let rules = &self.config.drive;
        for (cell, sun) in [(from, &s0), (to, &s1)] {
            self.check(world, rules, cell, sun, Some(heading))?;
        }
        let lit = |cell: u32, sun: &GridSun| self.rover.solar.is_some() && world.lit(cell, sun);
        // The noise dims the array, not a generator.
        let nuclear = self.rover.nuclear_w;
        let source = |w: f64| nuclear + p.solar_factor * (w - nuclear);
        let p0 = load - source(self.drive_source_lit_w(world, from, &s0, k, lit(from, &s0), share));
        let p1 = load - source(self.drive_source_lit_w(world, to, &s1, k, lit(to, &s1), share));
        let drawn = self.drive_energy_wh(load, (p0, p1), duration, delay);
        Ok((to, self.effect(&drawn, duration, load * duration / 3600.0)))
    }

    /// A drive's battery energy, Wh: `delay` s at its load with only a generator, then
    /// the move, half at each end's net load (`net_w`).
    fn drive_energy_wh(&self, load_w: f64, net_w: (f64, f64), duration: f64, delay: f64) -> Drawn {
        let moving = (duration - delay).max(0.0);
        let mut drawn = Drawn::default();
        if delay > 0.0 {
            drawn.push(self.battery_wh(load_w - self.rover.nuclear_w, delay));
        }
        drawn.push(self.battery_wh(net_w.0, moving / 2.0));
        drawn.push(self.battery_wh(net_w.1, moving / 2.0));
        drawn
    }

    /// Pushes onto `drawn` a segment of `dt_s` over which the net bus load goes linearly
    /// from `q_w` to `p_w` (W, positive drains): split where it crosses zero, so that
    /// the drain and the gain each pass through their own efficiency and the battery's
    /// extreme inside the segment is seen.
    fn linear_segment(&self, drawn: &mut Drawn, q_w: f64, p_w: f64, dt_s: f64) {
        if q_w * p_w < 0.0 {
            let s = q_w / (q_w - p_w);
            drawn.push(self.battery_wh(0.5 * q_w, s * dt_s));
            drawn.push(self.battery_wh(0.5 * p_w, (1.0 - s) * dt_s));
        } else {
            drawn.push(self.battery_wh(0.5 * (q_w + p_w), dt_s));
        }
    }

    /// The effect of the segments in `drawn` over `duration_s`, with `load_wh` drawn by
    /// the loads, rounded to the quanta.
    fn effect(&self, drawn: &Drawn, duration_s: f64, load_wh: f64) -> Effect {
        let effect = drawn.effect(duration_s, self.quantise_load(load_wh));
        let q = self.config.energy_quantum_wh;
        if q > 0.0 { effect.quantised(q, |e| self.quantise_energy(e)) } else { effect }
    }

    /// Executes `action` from `cell` at `t0` as the rover would in the field, with
    /// execution departing from the model by `p` (slower drives, less solar input):
    /// the destination and the effect, or the constraint that forbids the action.
    /// Energies are not quantised.
    pub fn execute(
        &self,
        world: &World,
        action: Action,
        cell: u32,
        t0: f64,
        p: Perturbation,
    ) -> Result<(u32, Effect), Binding> {
        match action {
            Action::Drive(k) => {
                let geometry = self.drive_geometry(world, cell, k)?;
                self.drive_perturbed(world, cell, k, geometry, t0, p)
            }
            stay => self.stay_perturbed(world, stay, cell, t0, p).map(|e| (cell, e)),
        }
    }

    /// Duration of a stationary action (Charge, Wait, or Hibernate for any other), s,
    /// quantised. A wait is not commanded: no planning delay precedes it.
    pub fn stay_duration_s(&self, action: Action) -> f64 {
        match action {
            Action::Charge => self.quantise_time(self.config.charge_s + self.margins.delay_s),
            Action::Wait => self.wait_step_s().unwrap_or_else(|| self.quantise_time(self.config.hibernate_s)),
            _ => self.quantise_time(self.config.hibernate_s + self.margins.delay_s),
        }
    }

    /// The stationary action a rover falls back to where the one it was given is
    /// refused: a wait step where the rover waits, else a Hibernate.
    pub fn fallback_stay(&self) -> Action {
        if self.config.wait_step_s.is_some() { Action::Wait } else { Action::Hibernate }
    }

    /// A stationary action (Charge, Hibernate or one Wait step) at `cell` starting at
    /// `t0`.
    pub fn stay(&self, world: &World, action: Action, cell: u32, t0: f64) -> Result<Effect, Binding> {
        self.stay_perturbed(world, action, cell, t0, Perturbation::NONE)
    }

    fn stay_perturbed(
        &self,
        world: &World,
        action: Action,
        cell: u32,
        t0: f64,
        perturbation: Perturbation,
    ) -> Result<Effect, Binding> {
        if action == Action::Wait {
            return self.execute_wait(world, cell, t0, self.stay_duration_s(action), perturbation);
        }
        let (rules, load) = match action {
            Action::Charge => (&self.config.charge, self.config.charge_load.load()),
            _ => (&self.config.hibernate, Load::Low),
        };
        let duration = self.stay_duration_s(action) + perturbation.delay_s;
        // The delays come first, with the array off-line.
        let delay = self.margins.delay_s + perturbation.delay_s;
        let t1 = t0 + duration;
        if t0 < -EPOCH_SLACK_S || t1 > world.span_s() {
            return Err(Binding::Horizon);
        }
        if !world.passable(cell) {
            return Err(Binding::Blocked);
        }
        let draw = self.margins.draw_factor * perturbation.draw_factor;
        let load_w = self.rover.electronics.power_w(load) * draw;
        self.earth_in_view(world, cell, t0, t1)?;
        let n = ((duration / STATIONARY_SAMPLE_S).ceil() as usize).max(2);
        let mut energy = Drawn::default();
        let mut drawn = 0.0;
        let mut prev: Option<(f64, f64)> = None;
        for k in 0..=n {
            let t = t0 + duration * k as f64 / n as f64;
            let sun = world.sun(t);
            self.check(world, rules, cell, &sun, None)?;
            // A hibernating rover sleeps with its array off-line (Table 3 lists no power
            // source for Hibernate): only a generator feeds it.
            let nuclear = self.rover.nuclear_w;
            let source = match action {
                Action::Charge if t - t0 >= delay => {
                    nuclear + perturbation.solar_factor * (self.source_w(world, cell, &sun, None) - nuclear)
                }
                _ => nuclear,
            };
            let load_w =
                if self.in_session(t) { load_w.max(self.rover.electronics.power_w(Load::High) * draw) } else { load_w };
            let p = load_w - source;
            if let Some((q, l)) = prev {
                self.linear_segment(&mut energy, q, p, duration / n as f64);
                drawn += 0.5 * (load_w + l) * duration / n as f64 / 3600.0;
            }
            prev = Some((p, load_w));
        }
        Ok(self.effect(&energy, duration, drawn))
    }

    fn check(
        &self,
        world: &World,
        rules: &Constraints,
        cell: u32,
        sun: &GridSun,
        heading: Option<f64>,
    ) -> Result<(), Binding> {
        if rules.max_slope && world.slope_deg(cell) > self.max_slope_deg.min(world.factors(cell).max_slope_deg) {
            return Err(Binding::Slope);
        }
        if rules.daylight && sun.elevation_deg <= 0.0 {
            return Err(Binding::Darkness);
        }
        if rules.direct_sun && !world.lit(cell, sun) {
            return Err(if sun.elevation_deg <= 0.0 { Binding::Darkness } else { Binding::Shadow });
        }
        // Only a Sun above the horizon can blind a camera.
        if rules.sun_in_camera
            && sun.elevation_deg > 0.0
            && let Some(h) = heading
            && self.rover.sun_in_cameras(h, sun.azimuth_deg, sun.elevation_deg)
        {
            return Err(Binding::SunInCamera);
        }
        Ok(())
    }

    /// [`ActionModel::source_w`] for drive heading `k`, from the precomputed level
    /// normal, given whether the Sun lights the cell (so callers test it once), with
    /// the array credited for `share` of the time (see [`DriveGeometry::solar_share`]).
    fn drive_source_lit_w(&self, world: &World, cell: u32, sun: &GridSun, k: u8, lit: bool, share: f64) -> f64 {
        let mut p = self.rover.nuclear_w;
        if lit {
            p += share * self.array_w(world, cell, sun, self.level_normals[k as usize % 8]);
        }
        p
    }

    /// Power from the array (if lit, times the planning margin's solar factor) and any
    /// generator, W. With no heading the array is turned to face the Sun.
    pub fn source_w(&self, world: &World, cell: u32, sun: &GridSun, heading: Option<f64>) -> f64 {
        let mut p = self.rover.nuclear_w;
        if let Some(array) = &self.rover.solar
            && world.lit(cell, sun)
        {
            let level = match heading {
                Some(h) => array.level_normal_enu(h),
                None => {
                    // Facing the Sun: the panel's azimuth is the Sun's, read off its
                    // direction without trigonometry.
                    let (st, ct) = (self.tilt_sin_cos.0, self.tilt_sin_cos.1);
                    let h = sun.enu[0].hypot(sun.enu[1]).max(1e-12);
                    [st * sun.enu[0] / h, st * sun.enu[1] / h, ct]
                }
            };
            p += self.array_w(world, cell, sun, level);
        }
        p
    }

    /// The array's power on a lit cell with its normal `level` on level ground, W,
    /// times the planning margin's solar factor: tipped by the cell's ground normal;
    /// on an envelope of terrains at most the least over its members — the cosine with
    /// the Sun lowered by how far the members tip the array from the map's attitude
    /// ([`World::attitude_spread`]), one evaluation instead of one per member.
    fn array_w(&self, world: &World, cell: u32, sun: &GridSun, level: [f64; 3]) -> f64 {
        let Some(array) = &self.rover.solar else { return 0.0 };
        let n = areo_rover::resources::SolarArray::tipped_normal_enu(level, world.normal(cell));
        let mut w = array.power_w(sun.beam_w_m2, sun.enu, n, false);
        if let Some(spread) = world.attitude_spread(cell) {
            w = (w - sun.beam_w_m2 * array.area_m2 * array.efficiency * spread).max(0.0);
        }
        self.margins.solar_factor * w
    }

    /// Battery energy drawn by idling for `duration_s` (asleep at the hibernation load,
    /// array off-line): how a rover waits for its plan's start, Wh.
    pub fn idle_wh(&self, duration_s: f64) -> f64 {
        let load = self.rover.electronics.power_w(Load::Low) * self.margins.draw_factor;
        self.battery_wh(load - self.rover.nuclear_w, duration_s.max(0.0))
    }

    /// Battery energy for a net bus load `net_w` (W, positive drains) over `dt_s`, Wh.
    fn battery_wh(&self, net_w: f64, dt_s: f64) -> f64 {
        let b = &self.rover.battery;
        let wh = net_w * dt_s / 3600.0;
        if wh >= 0.0 { wh / b.discharge_efficiency } else { wh * b.charge_efficiency }
    }

    /// The fastest possible speed on `world`, m/s: the rover's on level ground on its
    /// fastest terrain class.
    pub fn top_speed_m_s(&self, world: &World) -> f64 {
        self.rover.locomotor.speed_m_s * world.speed_factor_range().1
    }
}
