//! Test worlds: synthetic DEMs, a fixed Sun or Mars24, the Hyperion-class rover.

use areo_ephemeris::flux::Atmosphere;
use areo_ephemeris::{Mars24, Site, SunModel, SunState, parse_utc};
use areo_mission::{Action, ActionConfig, ActionModel, Objective, PathLength, World, WorldConfig};
use areo_rover::resources::ResourceModel;
use areo_terrain::Dem;
use hifitime::Epoch;
use rustc_hash::FxHashMap;

/// The Sun fixed at an azimuth and elevation over a site.
pub(crate) struct FixedSun {
    dir: [f64; 3],
}

impl FixedSun {
    pub(crate) fn new(site: &Site, az_deg: f64, el_deg: f64) -> FixedSun {
        let [e, n, u] = site.enu_axes();
        let (sa, ca) = az_deg.to_radians().sin_cos();
        let (se, ce) = el_deg.to_radians().sin_cos();
        FixedSun { dir: std::array::from_fn(|i| e[i] * sa * ce + n[i] * ca * ce + u[i] * se) }
    }
}

impl SunModel for FixedSun {
    fn sun(&self, _epoch: Epoch) -> SunState {
        SunState { direction_body_fixed: self.dir, distance_au: 1.52 }
    }
}

pub(crate) fn site() -> Site {
    Site::new(-4.6, 137.4).unwrap()
}

pub(crate) fn epoch() -> Epoch {
    parse_utc("2025-03-01T12:00:00Z").unwrap()
}

pub(crate) fn config(span_h: f64, horizon: Option<usize>) -> WorldConfig {
    WorldConfig {
        epoch: epoch(),
        span_s: span_h * 3600.0,
        sun_step_s: 120.0,
        horizon_sectors: horizon,
        atmosphere: Atmosphere::Baseline { peak_w_m2: 500.0 },
        site: Some(site()),
    }
}

/// A world on `dem` under a fixed Sun.
pub(crate) fn fixed_sun_world(dem: Dem, az: f64, el: f64, span_h: f64) -> World {
    World::new(dem, &config(span_h, None), &FixedSun::new(&site(), az, el)).unwrap()
}

/// A world on `dem` under the real Sun (Mars24), with terrain shadows.
pub(crate) fn mars_world(dem: Dem, span_h: f64, horizon: Option<usize>) -> World {
    World::new(dem, &config(span_h, horizon), &Mars24).unwrap()
}

pub(crate) fn flat(cols: usize, rows: usize, cell: f64) -> Dem {
    Dem::from_fn(cols, rows, cell, cell, |_, _| 0.0).unwrap()
}

/// Hyperion with a battery of `capacity_wh` (usable 90 %).
pub(crate) fn rover(capacity_wh: f64) -> ResourceModel {
    let mut r = ResourceModel::hyperion();
    r.battery.capacity_wh = capacity_wh;
    r
}

pub(crate) fn model(capacity_wh: f64, actions: ActionConfig) -> ActionModel {
    ActionModel::new(rover(capacity_wh), actions)
}

/// Actions on whole minutes and whole watt-hours (so label classes as fine as the
/// quanta make the search exact), with drives at any hour and charging without
/// direct sun.
pub(crate) fn quantised_actions(hibernate_s: f64) -> ActionConfig {
    let mut a = ActionConfig {
        time_quantum_s: 60.0,
        energy_quantum_wh: 1.0,
        charge_s: 600.0,
        hibernate_s,
        ..Default::default()
    };
    a.drive.daylight = false;
    a.charge.direct_sun = false;
    a
}

/// An action that succeeds, the cell it ends in and what it does.
pub(crate) type Move = (Action, u32, areo_mission::Effect);

/// Every action from (`cell`, `t`) forward: (action, destination, effect).
pub(crate) fn moves(world: &World, model: &ActionModel, cell: u32, t: f64) -> Vec<Move> {
    let mut out = Vec::new();
    for a in (0..8).map(Action::Drive).chain(model.stays().iter().copied()) {
        let r = match a {
            Action::Drive(k) => model.drive(world, cell, k, t),
            stay => model.stay(world, stay, cell, t).map(|e| (cell, e)),
        };
        if let Ok((to, e)) = r {
            out.push((a, to, e));
        }
    }
    out
}

/// [`moves`], remembered by cell and instant. The brute-force references meet the same
/// (cell, minute) at many battery levels or for many goal instants, and an action's
/// effect does not depend on the battery: computing it once per (cell, instant) keeps
/// the references independent of the planner and makes them faster (1.3–1.6× on
/// the chaining and Pareto references).
pub(crate) struct MoveMemo<'a> {
    world: &'a World,
    model: &'a ActionModel,
    memo: FxHashMap<(u32, u64), Vec<Move>>,
}

impl<'a> MoveMemo<'a> {
    pub(crate) fn new(world: &'a World, model: &'a ActionModel) -> MoveMemo<'a> {
        MoveMemo { world, model, memo: FxHashMap::default() }
    }

    /// The actions that succeed from `cell` at `t` s, as [`moves`] gives them.
    pub(crate) fn at(&mut self, cell: u32, t: f64) -> &[Move] {
        let (world, model) = (self.world, self.model);
        self.memo.entry((cell, t.to_bits())).or_insert_with(|| moves(world, model, cell, t))
    }
}

/// A step's cost in the planner's terms: Δe + E_max × length, or the duration, plus the
/// planner's wait-late tie-breaker on stationary actions.
pub(crate) fn step_cost(
    (world, model): (&World, &ActionModel),
    objective: Objective,
    e_max: f64,
    a: Action,
    t0: f64,
    e: areo_mission::Effect,
) -> f64 {
    let units = match a {
        Action::Drive(_) => PathLength::Distance.units(a, world.dem().dx(), world.dem().dy()),
        stay => model.stay_units(stay),
    };
    let (base, scale) = match objective {
        Objective::Energy => ((e.energy_wh + e_max * units).max(0.0), e_max * units),
        Objective::Time | Objective::Margin { .. } => (e.duration_s, e.duration_s),
        Objective::EnergyUsed => (e.load_wh, e.load_wh),
    };
    let bias =
        if matches!(a, Action::Drive(_)) { 0.0 } else { 1e-6 * scale * (1.0 - t0 / world.span_s()).clamp(0.0, 1.0) };
    base + bias
}

/// The whole minutes of a start window and the battery at each (the rover idles from
/// the window's opening: asleep, or waiting where it waits), where it is not below zero
/// — where the brute-force searches begin.
pub(crate) fn start_minutes(world: &World, model: &ActionModel, start: &areo_mission::Start) -> Vec<(i64, f64)> {
    let mut out = Vec::new();
    let capacity = model.capacity_wh();
    let mut m = (start.t_min / 60.0).ceil() as i64;
    while m as f64 * 60.0 <= start.t_max + 1e-9 {
        let idle_s = m as f64 * 60.0 - start.t_min;
        let battery = match model.idle_wait(world, start.cell, start.t_min, idle_s) {
            Some(w) if w.lowest(start.energy_wh, capacity) >= -1e-9 => w.after(start.energy_wh, capacity),
            Some(_) => -1.0,
            None => start.energy_wh - model.idle_wh(idle_s),
        };
        if battery >= 0.0 {
            out.push((m, battery));
        }
        m += 1;
    }
    out
}

/// The 7 × 5 crop (463 m cells) of the MOLA Gale map the real-terrain references use
/// (`crates/terrain/tests/data/gale_mola_crop_64.tif`, columns 36–42, rows 33–37), and
/// world settings over `span_h` hours with the Sun at the crop's own latitude and
/// longitude.
pub(crate) fn gale_crop(span_h: f64) -> (Dem, WorldConfig) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../terrain/tests/data/gale_mola_crop_64.tif");
    let crop = areo_terrain::read(&path).unwrap().crop(36, 33, 7, 5).unwrap();
    let (x, y) = crop.cell_center(3, 2);
    let (lat, lon) = crop.geographic(x, y).unwrap();
    let config = WorldConfig { site: Some(Site::new(lat, lon).unwrap()), ..config(span_h, Some(16)) };
    (crop, config)
}
