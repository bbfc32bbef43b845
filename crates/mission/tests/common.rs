//! Test worlds: synthetic DEMs, a fixed Sun or Mars24, the Hyperion-class rover.

use areo_ephemeris::flux::Atmosphere;
use areo_ephemeris::{Mars24, Site, SunModel, SunState, parse_utc};
use areo_mission::{ActionConfig, ActionModel, World, WorldConfig};
use areo_rover::resources::ResourceModel;
use areo_terrain::Dem;
use hifitime::Epoch;

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

/// An f64 ordered by `total_cmp`, for the brute-force searches' heaps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Ord64(pub(crate) f64);
impl Eq for Ord64 {}
impl PartialOrd for Ord64 {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Ord64 {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0)
    }
}
