//! The plan TEMPEST hands to the rover: waypoints with where, when, what next, and the
//! energy picture (TEMPEST's required energy E and the predicted battery charge).

use areo_ephemeris::format_utc;
use hifitime::Duration;
use serde::{Deserialize, Serialize};

use crate::action_model::Action;
use crate::domain::{Label, Objective};
use crate::world::{GridSun, World};

/// One waypoint of a plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Waypoint {
    /// Grid cell.
    pub cell: u32,
    /// Column and row.
    pub col_row: (usize, usize),
    /// Cell centre, easting in the DEM's projected CRS, m (a scenario's map metres are
    /// measured from the map's south-west corner instead).
    pub easting_m: f64,
    /// Cell centre, northing in the DEM's projected CRS, m.
    pub northing_m: f64,
    /// Latitude, degrees (planetocentric, from the DEM's georeference).
    pub lat_deg: f64,
    /// East longitude, degrees.
    pub lon_deg: f64,
    /// Time, s after the plan's epoch.
    pub t_s: f64,
    /// Time, ISO 8601 UTC.
    pub utc: String,
    /// Local true solar time at the waypoint, hours (on the Moon a lunar hour is 1/24
    /// of a synodic month).
    pub ltst_h: f64,
    /// The action taken from here (`None` at the final goal).
    pub action: Option<Action>,
    /// Least battery energy needed from here to the last goal, Wh above the floor (E).
    pub required_wh: f64,
    /// Predicted battery charge, Wh (absolute, including the floor).
    pub battery_wh: f64,
    /// What the rover's loads draw from here to the next waypoint, Wh (the action and,
    /// on a tick, its settle; 0 at the last goal), on the world the plan was made on.
    #[serde(default)]
    pub drawn_wh: f64,
    /// Slope, degrees.
    pub slope_deg: f64,
    /// The drive's from here: its pitch (the slope along it, positive uphill) and its
    /// roll (positive right side up), degrees, on the map ([`World::drive_attitude_deg`]);
    /// `None` for any other action.
    #[serde(default)]
    pub drive_attitude_deg: Option<(f64, f64)>,
    /// The terrain class here (an index into the map's [`crate::ClassMap`]), if any.
    #[serde(default)]
    pub class: Option<u8>,
    /// Sun elevation above the horizontal, degrees.
    pub sun_elevation_deg: f64,
    /// Sun elevation above the local ground plane, degrees (TEMPEST's LOS value).
    pub sun_above_ground_deg: f64,
    /// Lit by the Sun (not in terrain shadow, Sun up).
    pub lit: bool,
    /// The Earth above the terrain's horizon here (never on the Earth itself).
    #[serde(default)]
    pub earth_in_view: bool,
    /// The goal reached here (0-based), if any.
    pub goal: Option<usize>,
}

impl Waypoint {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        world: &World,
        cell: u32,
        (x, y, lat, lon): (f64, f64, f64, f64),
        label: Label,
        action: Option<Action>,
        battery_wh: f64,
        sun: &GridSun,
        goal: Option<usize>,
    ) -> Waypoint {
        let epoch = world.epoch() + Duration::from_seconds(label.t);
        Waypoint {
            cell,
            col_row: world.col_row(cell),
            easting_m: x,
            northing_m: y,
            lat_deg: lat,
            lon_deg: lon,
            t_s: label.t,
            utc: format_utc(epoch),
            ltst_h: world.local_solar_time_h(label.t, lon),
            action,
            required_wh: label.e,
            battery_wh,
            drawn_wh: 0.0,
            slope_deg: world.slope_deg(cell),
            drive_attitude_deg: match action {
                Some(Action::Drive(k)) => world.drive_attitude_deg(cell, k),
                _ => None,
            },
            class: world.ground().and_then(|g| g.class_index(cell)),
            sun_elevation_deg: sun.elevation_deg,
            sun_above_ground_deg: world.sun_above_ground_deg(cell, sun),
            lit: world.lit(cell, sun),
            earth_in_view: world.earth_visible(cell, label.t),
            goal,
        }
    }
}

/// A plan from the start through every goal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MissionPlan {
    /// Waypoints from the start to the last goal.
    pub waypoints: Vec<Waypoint>,
    /// Objective value (L + B in Wh for the energy objective; s for duration).
    pub cost: f64,
    /// E_max used by the energy objective, Wh.
    pub e_max_wh: f64,
    /// The objective.
    pub objective: Objective,
    /// Nodes expanded by the last planning call, all segments.
    pub expansions: u64,
    /// Number of segments (goals).
    pub segments: usize,
    /// The energy class width the plan was searched with, Wh (`None`: E exact). An
    /// approximation (see [`crate::Resolution`]); `None` here while the planner was
    /// given classes means it found nothing with them and fell back to exact E.
    #[serde(default)]
    pub energy_classes_wh: Option<f64>,
    /// The time class width the plan was searched with, s. Narrower than the scenario's
    /// `resolution.time_s` when the planner found nothing at that width and searched
    /// again at the actions' time quantum (exact at the quanta) before calling the goal
    /// unreachable.
    #[serde(default)]
    pub time_classes_s: f64,
    /// Whether the last resort found the plan: the search exact at the actions' quanta
    /// (one-quantum classes, the goal instants of every smaller `goal_times`, the
    /// widest start window and start times), run when the settings found nothing — a
    /// fallback, even where the settings' classes were one quantum already.
    #[serde(default)]
    pub exact_at_quanta: bool,
    /// The tick the plan is exact at, s ([`crate::SearchMode::Exact`]): optimal
    /// over every plan whose drives depart and waits end on ticks. `None`: searched
    /// over time classes (see the fields above).
    #[serde(default)]
    pub tick_s: Option<f64>,
}

impl MissionPlan {
    /// Plan duration, s.
    pub fn duration_s(&self) -> f64 {
        match (self.waypoints.first(), self.waypoints.last()) {
            (Some(a), Some(b)) => b.t_s - a.t_s,
            _ => 0.0,
        }
    }

    /// How many times each kind of action appears: (drives, charges, hibernations);
    /// wait steps are counted by [`MissionPlan::wait_steps`].
    pub fn action_counts(&self) -> (usize, usize, usize) {
        let mut c = (0, 0, 0);
        for w in &self.waypoints {
            match w.action {
                Some(Action::Drive(_)) => c.0 += 1,
                Some(Action::Charge) => c.1 += 1,
                Some(Action::Hibernate) => c.2 += 1,
                Some(Action::Wait) | None => {}
            }
        }
        c
    }

    /// How many wait steps the plan has (see [`crate::ActionConfig::wait_step_s`]).
    pub fn wait_steps(&self) -> usize {
        self.waypoints.iter().filter(|w| w.action == Some(Action::Wait)).count()
    }

    /// The energy the plan's actions' loads draw, replayed forward on `model` in
    /// `world` (see [`crate::Effect::load_wh`]), Wh; or the first action the replay
    /// refuses (its index and why).
    pub fn energy_used_wh(
        &self,
        world: &World,
        model: &crate::ActionModel,
    ) -> Result<f64, (usize, Action, crate::Binding)> {
        let mut used = 0.0;
        for (i, w) in self.waypoints.iter().enumerate() {
            let Some(a) = w.action else { continue };
            let (_, effect) =
                model.execute(world, a, w.cell, w.t_s, crate::Perturbation::NONE).map_err(|b| (i, a, b))?;
            used += effect.load_wh;
        }
        Ok(used)
    }

    /// The lowest predicted battery charge along the plan, Wh.
    pub fn min_battery_wh(&self) -> f64 {
        self.waypoints.iter().map(|w| w.battery_wh).fold(f64::INFINITY, f64::min)
    }
}
