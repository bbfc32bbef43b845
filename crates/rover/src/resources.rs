//! TEMPEST's coarse rover resource models (Tompkins et al. 2004, Table 2): locomotor,
//! solar array, nuclear generator, battery, electronics loads and navigation cameras,
//! read from a RON file (`params/hyperion.ron` ships a Hyperion-class solar rover).
//!
//! Conventions: power in W, energy in J inside (Wh only in file fields that say so),
//! angles in degrees only in file fields; azimuths clockwise from north; TEMPEST's
//! energy sign (Δe > 0 consumes battery energy).

use std::path::Path;

use serde::Deserialize;

use crate::error::{Error, Result, parse_ron, read_text};

/// Gravity of a locomotor whose file and job name none, m/s²: Mars's, where the
/// library's planners began (a scenario sets its body's, see `areo-scenario`).
const MARS_GRAVITY: f64 = 3.711;

/// The shipped Hyperion-class parameters.
pub const HYPERION_RON: &str = include_str!("../params/hyperion.ron");

/// All resource models of one rover.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResourceModel {
    /// A name for reports.
    pub name: String,
    /// Driving.
    pub locomotor: Locomotor,
    /// Solar array, if any.
    #[serde(default)]
    pub solar: Option<SolarArray>,
    /// Radioisotope generator output, W (0 without one).
    #[serde(default)]
    pub nuclear_w: f64,
    /// The battery.
    pub battery: Battery,
    /// Electronics loads.
    pub electronics: Electronics,
    /// Navigation cameras (the Sun must stay out of their view while driving).
    #[serde(default)]
    pub cameras: Vec<Camera>,
}

/// The locomotor: power to drive at a speed up a slope.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Locomotor {
    /// Rover mass, kg.
    pub mass_kg: f64,
    /// Nominal speed on flat ground, m/s.
    pub speed_m_s: f64,
    /// Effective rolling-resistance coefficient (force / weight) on flat ground.
    pub rolling_resistance: f64,
    /// Drive-train efficiency, 0..=1 (electrical → wheel power).
    pub drive_efficiency: f64,
    /// Steepest slope the rover can climb, degrees.
    pub max_slope_deg: f64,
    /// Gravity, m/s²; default: the body's (a scenario fills it in from its `body`;
    /// with no body, Mars's 3.711).
    #[serde(default)]
    pub gravity_m_s2: Option<f64>,
    /// Largest roll (side tilt) a drive may put the rover at, degrees (0..90); none:
    /// no limit beyond the slope's.
    #[serde(default)]
    pub max_roll_deg: Option<f64>,
    /// Largest nose-up pitch a drive may put the rover at, degrees (0..90).
    #[serde(default)]
    pub max_pitch_up_deg: Option<f64>,
    /// Largest nose-down pitch a drive may put the rover at, degrees (0..90).
    #[serde(default)]
    pub max_pitch_down_deg: Option<f64>,
}

impl Locomotor {
    /// Range checks of the roll and pitch limits: each, where given, in (0, 90) degrees.
    fn check_tilt_limits(&self, origin: &str) -> Result<()> {
        for (field, v) in [
            ("locomotor.max_roll_deg", self.max_roll_deg),
            ("locomotor.max_pitch_up_deg", self.max_pitch_up_deg),
            ("locomotor.max_pitch_down_deg", self.max_pitch_down_deg),
        ] {
            if let Some(value) = v
                && !(value > 0.0 && value < 90.0)
            {
                return Err(Error::Invalid {
                    origin: origin.into(),
                    field,
                    value,
                    why: "allowed 0..90 degrees".into(),
                });
            }
        }
        Ok(())
    }

    /// The gravity the locomotor works against, m/s².
    pub fn gravity(&self) -> f64 {
        self.gravity_m_s2.unwrap_or(MARS_GRAVITY)
    }

    /// Electrical power to drive at `speed_m_s` up a slope of `slope_deg` (negative
    /// downhill), W: m·g·v·(c_rr·cos θ + sin θ)/η, never below 0 (no regeneration).
    pub fn power_w(&self, speed_m_s: f64, slope_deg: f64) -> f64 {
        let (sin, cos) = slope_deg.to_radians().sin_cos();
        self.power_on_w(speed_m_s, sin, cos)
    }

    /// [`Locomotor::power_w`] for a slope given by its sine and cosine (a planner that
    /// knows rise and run needs no trigonometry), W.
    pub fn power_on_w(&self, speed_m_s: f64, sin: f64, cos: f64) -> f64 {
        let wheel = self.mass_kg * self.gravity() * speed_m_s * (self.rolling_resistance * cos + sin);
        (wheel / self.drive_efficiency).max(0.0)
    }

    /// Speed on a slope: nominal, reduced in proportion to the slope up to
    /// `max_slope_deg`, where it falls to a third (a coarse model of careful driving).
    pub fn speed_on_slope_m_s(&self, slope_deg: f64) -> f64 {
        let f = (slope_deg.abs() / self.max_slope_deg).min(1.0);
        self.speed_m_s * (1.0 - 2.0 / 3.0 * f)
    }
}

/// A flat solar array fixed to the body.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolarArray {
    /// Active area, m².
    pub area_m2: f64,
    /// Conversion efficiency, 0..=1.
    pub efficiency: f64,
    /// Panel tilt from the body's horizontal, degrees (0 = facing up).
    pub tilt_deg: f64,
    /// Azimuth the tilted panel faces relative to the rover's heading, degrees.
    pub facing_deg: f64,
}

impl SolarArray {
    /// The panel's unit normal in local east-north-up for a rover heading
    /// `heading_deg` (azimuth) standing on ground with unit normal `ground_enu`.
    pub fn normal_enu(&self, heading_deg: f64, ground_enu: [f64; 3]) -> [f64; 3] {
        tilt_onto(self.level_normal_enu(heading_deg), ground_enu)
    }

    /// The panel's unit normal for a rover heading `heading_deg` on level ground.
    pub fn level_normal_enu(&self, heading_deg: f64) -> [f64; 3] {
        let (st, ct) = self.tilt_deg.to_radians().sin_cos();
        let az = (heading_deg + self.facing_deg).to_radians();
        [st * az.sin(), st * az.cos(), ct]
    }

    /// A level-rover panel normal (from [`SolarArray::level_normal_enu`]) tipped onto
    /// ground with unit normal `ground_enu`: no trigonometry, for planners that reuse
    /// the level normals of a few headings.
    pub fn tipped_normal_enu(level: [f64; 3], ground_enu: [f64; 3]) -> [f64; 3] {
        tilt_onto(level, ground_enu)
    }

    /// Electrical power, W, for beam flux `beam_w_m2` from unit direction `sun_enu`, a
    /// panel normal `normal_enu`, and whether the rover is in shadow.
    pub fn power_w(&self, beam_w_m2: f64, sun_enu: [f64; 3], normal_enu: [f64; 3], shadowed: bool) -> f64 {
        if shadowed {
            return 0.0;
        }
        let cos_i = sun_enu[0] * normal_enu[0] + sun_enu[1] * normal_enu[1] + sun_enu[2] * normal_enu[2];
        beam_w_m2 * cos_i.max(0.0) * self.area_m2 * self.efficiency
    }
}

/// Rotates `v` by the rotation that takes straight up to `ground` (the rover's
/// attitude on the slope).
fn tilt_onto(v: [f64; 3], ground: [f64; 3]) -> [f64; 3] {
    let inv = 1.0 / (ground[0] * ground[0] + ground[1] * ground[1] + ground[2] * ground[2]).sqrt();
    let g = [ground[0] * inv, ground[1] * inv, ground[2] * inv];
    // Rodrigues about the unnormalised axis a = up × g (|a| = sin, g_z = cos): the
    // rotation is v cos + a × v + a (a·v) / (1 + cos) — no square root, one division.
    let a = [-g[1], g[0]];
    let c = g[2];
    if a[0] * a[0] + a[1] * a[1] < 1e-24 || c <= -1.0 + 1e-12 {
        return v;
    }
    let av = (a[0] * v[0] + a[1] * v[1]) / (1.0 + c);
    let cross = [a[1] * v[2], -a[0] * v[2], a[0] * v[1] - a[1] * v[0]];
    [v[0] * c + cross[0] + a[0] * av, v[1] * c + cross[1] + a[1] * av, v[2] * c + cross[2]]
}

/// The battery.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Battery {
    /// Capacity, Wh.
    pub capacity_wh: f64,
    /// Lowest allowed state of charge, 0..1.
    pub min_soc: f64,
    /// Highest allowed state of charge, 0..=1.
    pub max_soc: f64,
    /// Fraction of charging power stored, 0..=1.
    pub charge_efficiency: f64,
    /// Fraction of stored energy delivered, 0..=1.
    pub discharge_efficiency: f64,
}

impl Battery {
    /// Usable energy between the state-of-charge limits, J.
    pub fn usable_j(&self) -> f64 {
        self.capacity_wh * 3600.0 * (self.max_soc - self.min_soc)
    }

    /// The stored energy (J, measured from empty) after `dt_s` seconds at a net bus
    /// power `net_w` (positive charges), with efficiencies and the state-of-charge
    /// window; returns (new energy, energy that could not be stored or delivered).
    pub fn step(&self, stored_j: f64, net_w: f64, dt_s: f64) -> (f64, f64) {
        let (lo, hi) = (self.capacity_wh * 3600.0 * self.min_soc, self.capacity_wh * 3600.0 * self.max_soc);
        let bus_j = net_w * dt_s;
        let delta = if bus_j >= 0.0 { bus_j * self.charge_efficiency } else { bus_j / self.discharge_efficiency };
        let target = stored_j + delta;
        let clamped = target.clamp(lo, hi);
        let lost = if bus_j >= 0.0 {
            (target - clamped) / self.charge_efficiency
        } else {
            (clamped - target) * self.discharge_efficiency
        };
        (clamped, lost)
    }
}

/// Electronics power levels, W.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Electronics {
    /// Hibernation.
    pub low_w: f64,
    /// Charging, idle.
    pub medium_w: f64,
    /// Driving, sensing, communicating.
    pub high_w: f64,
}

/// An electronics level.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Load {
    /// Hibernation.
    Low,
    /// Charging, idle.
    Medium,
    /// Driving, sensing, communicating.
    High,
}

impl Electronics {
    /// Power at a level, W.
    pub fn power_w(&self, load: Load) -> f64 {
        match load {
            Load::Low => self.low_w,
            Load::Medium => self.medium_w,
            Load::High => self.high_w,
        }
    }
}

/// A navigation camera fixed to the body.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    /// Pointing azimuth relative to the rover heading, degrees.
    pub yaw_deg: f64,
    /// Pointing elevation (negative = looking down), degrees.
    pub pitch_deg: f64,
    /// Full horizontal field of view, degrees.
    pub hfov_deg: f64,
    /// Full vertical field of view, degrees.
    pub vfov_deg: f64,
}

impl Camera {
    /// Whether the Sun at (`sun_az_deg`, `sun_el_deg`) falls in the field of view for a
    /// rover heading `heading_deg` on level ground.
    pub fn sees_sun(&self, heading_deg: f64, sun_az_deg: f64, sun_el_deg: f64) -> bool {
        let d_el = sun_el_deg - self.pitch_deg;
        if d_el.abs() > self.vfov_deg / 2.0 {
            return false;
        }
        // Into (−180°, 180°] by whole turns: planners call this for every drive, and
        // their angles are within a turn or two, where fmod costs more than a loop.
        let mut d_az = sun_az_deg - heading_deg - self.yaw_deg;
        if !d_az.is_finite() {
            return false;
        }
        while d_az > 180.0 {
            d_az -= 360.0;
        }
        while d_az <= -180.0 {
            d_az += 360.0;
        }
        d_az.abs() <= self.hfov_deg / 2.0
    }
}

impl ResourceModel {
    /// The shipped Hyperion-class model.
    pub fn hyperion() -> ResourceModel {
        // The shipped file is checked by the tests; failing here is a build defect.
        ResourceModel::parse(HYPERION_RON, "params/hyperion.ron").expect("the shipped Hyperion parameters are valid")
    }

    /// Reads and validates a resource-model file.
    pub fn load(path: &Path) -> Result<ResourceModel> {
        ResourceModel::parse(&read_text(path)?, &path.display().to_string())
    }

    /// Parses and validates; `origin` labels errors.
    pub fn parse(text: &str, origin: &str) -> Result<ResourceModel> {
        let m: ResourceModel = parse_ron(text, origin)?;
        m.validate(origin)?;
        Ok(m)
    }

    /// Range checks.
    pub fn validate(&self, origin: &str) -> Result<()> {
        let bad = |field: &'static str, value: f64, why: &str| {
            Err(Error::Invalid { origin: origin.into(), field, value, why: why.into() })
        };
        let l = &self.locomotor;
        // Physical ranges, so that no product overflows and no search step is absurd.
        for (f, v, hi, why) in [
            ("locomotor.mass_kg", l.mass_kg, 1e4, "allowed 0 (exclusive)..=10000 kg"),
            ("locomotor.speed_m_s", l.speed_m_s, 100.0, "allowed 0 (exclusive)..=100 m/s"),
            ("locomotor.gravity_m_s2", l.gravity(), 100.0, "allowed 0 (exclusive)..=100 m/s²"),
            ("battery.capacity_wh", self.battery.capacity_wh, 1e7, "allowed 0 (exclusive)..=1e7 Wh"),
        ] {
            if !(v > 0.0 && v <= hi) {
                return bad(f, v, why);
            }
        }
        if !(l.rolling_resistance >= 0.0 && l.rolling_resistance < 1.0) {
            return bad("locomotor.rolling_resistance", l.rolling_resistance, "allowed 0..1");
        }
        if !(l.max_slope_deg > 0.0 && l.max_slope_deg < 60.0) {
            return bad("locomotor.max_slope_deg", l.max_slope_deg, "allowed 0..60 degrees");
        }
        l.check_tilt_limits(origin)?;
        let b = &self.battery;
        for (f, v) in [
            ("locomotor.drive_efficiency", l.drive_efficiency),
            ("battery.charge_efficiency", b.charge_efficiency),
            ("battery.discharge_efficiency", b.discharge_efficiency),
            ("battery.max_soc", b.max_soc),
        ] {
            if !(v > 0.0 && v <= 1.0) {
                return bad(f, v, "allowed 0 (exclusive)..=1");
            }
        }
        if !(b.min_soc >= 0.0 && b.min_soc < b.max_soc) {
            return bad("battery.min_soc", b.min_soc, "allowed 0..max_soc");
        }
        if let Some(s) = &self.solar {
            if !(s.area_m2 > 0.0 && s.area_m2 <= 1e4) {
                return bad("solar.area_m2", s.area_m2, "allowed 0 (exclusive)..=10000 m²");
            }
            if !(s.facing_deg.abs() <= 360.0) {
                return bad("solar.facing_deg", s.facing_deg, "allowed -360..=360 degrees");
            }
            if !(s.efficiency > 0.0 && s.efficiency <= 1.0) {
                return bad("solar.efficiency", s.efficiency, "area > 0 and efficiency in 0 (exclusive)..=1");
            }
            if !(0.0..=90.0).contains(&s.tilt_deg) {
                return bad("solar.tilt_deg", s.tilt_deg, "allowed 0..=90");
            }
        }
        let e = &self.electronics;
        if !(e.low_w >= 0.0 && e.low_w <= e.medium_w && e.medium_w <= e.high_w) {
            return bad("electronics.low_w", e.low_w, "need 0 ≤ low_w ≤ medium_w ≤ high_w");
        }
        if !(e.high_w <= 1e6) {
            return bad("electronics.high_w", e.high_w, "allowed 0..=1e6 W");
        }
        if !(self.nuclear_w >= 0.0 && self.nuclear_w <= 1e6) {
            return bad("nuclear_w", self.nuclear_w, "allowed 0..=1e6 W");
        }
        for c in &self.cameras {
            if !(c.yaw_deg.abs() <= 360.0 && c.pitch_deg.abs() <= 90.0) {
                return bad("cameras.yaw_deg", c.yaw_deg, "yaw within -360..=360 and pitch within -90..=90 degrees");
            }
            if !(c.hfov_deg > 0.0 && c.hfov_deg < 360.0 && c.vfov_deg > 0.0 && c.vfov_deg <= 180.0) {
                return bad("cameras.hfov_deg", c.hfov_deg, "fields of view must be within (0, 360) and (0, 180]");
            }
        }
        Ok(())
    }

    /// Whether any navigation camera would see the Sun driving at `heading_deg`.
    pub fn sun_in_cameras(&self, heading_deg: f64, sun_az_deg: f64, sun_el_deg: f64) -> bool {
        self.cameras.iter().any(|c| c.sees_sun(heading_deg, sun_az_deg, sun_el_deg))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tilting_onto_the_ground_is_the_rotation_taking_up_to_its_normal() {
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        // A 30° slope facing east (its normal leans east), given unnormalised.
        let (s, c) = 30f64.to_radians().sin_cos();
        let ground = [2.0 * s, 0.0, 2.0 * c];
        let up = tilt_onto([0.0, 0.0, 1.0], ground);
        assert!((up[0] - s).abs() < 1e-12 && up[1].abs() < 1e-12 && (up[2] - c).abs() < 1e-12, "{up:?}");
        // The rotation axis (north) is fixed; east tips down by the slope.
        let north = tilt_onto([0.0, 1.0, 0.0], ground);
        assert!((north[1] - 1.0).abs() < 1e-12 && north[0].abs() < 1e-12 && north[2].abs() < 1e-12);
        let east = tilt_onto([1.0, 0.0, 0.0], ground);
        assert!((east[0] - c).abs() < 1e-12 && (east[2] + s).abs() < 1e-12, "{east:?}");
        // Any vector keeps its length and its angle to the normal's image.
        let v = [0.3, -0.5, 0.8];
        let w = tilt_onto(v, [-0.2, 0.4, 0.9]);
        assert!((dot(v, v) - dot(w, w)).abs() < 1e-12);
        let n = tilt_onto([0.0, 0.0, 1.0], [-0.2, 0.4, 0.9]);
        assert!((dot(w, n) - v[2]).abs() < 1e-12);
        // Level ground changes nothing.
        assert_eq!(tilt_onto(v, [0.0, 0.0, 3.0]), v);
    }

    #[test]
    fn locomotor_power_is_the_work_against_resistance_and_gravity() {
        let l = ResourceModel::hyperion().locomotor;
        let flat = l.power_w(0.3, 0.0);
        assert!((flat - l.mass_kg * l.gravity() * 0.3 * l.rolling_resistance / l.drive_efficiency).abs() < 1e-9);
        let up = l.power_w(0.3, 10.0);
        let th = 10f64.to_radians();
        let expect = l.mass_kg * l.gravity() * 0.3 * (l.rolling_resistance * th.cos() + th.sin()) / l.drive_efficiency;
        assert!((up - expect).abs() < 1e-9 && up > flat);
        assert_eq!(l.power_w(0.3, -45.0), 0.0, "no regeneration downhill");
        assert!((l.speed_on_slope_m_s(l.max_slope_deg) - l.speed_m_s / 3.0).abs() < 1e-12);
    }

    #[test]
    fn solar_power_follows_incidence_attitude_and_shadow() {
        let s = SolarArray { area_m2: 2.0, efficiency: 0.25, tilt_deg: 0.0, facing_deg: 0.0 };
        let up = [0.0, 0.0, 1.0];
        let e = 30f64.to_radians();
        let sun = [0.0, e.cos(), e.sin()]; // north, 30° up
        assert!((s.power_w(500.0, sun, s.normal_enu(0.0, up), false) - 500.0 * 0.5 * 0.5).abs() < 1e-9);
        assert_eq!(s.power_w(500.0, sun, up, true), 0.0);
        // On a 30° slope facing the Sun the flat panel points straight at a 60°-high Sun…
        let g = [0.0, 30f64.to_radians().sin(), 30f64.to_radians().cos()];
        let n = s.normal_enu(0.0, g);
        let sun60 = [0.0, 60f64.to_radians().cos(), 60f64.to_radians().sin()];
        assert!((s.power_w(500.0, sun60, n, false) - 500.0 * 0.5).abs() < 1e-9, "{n:?}");
        // …and a panel tilted 60° toward the heading does so on level ground.
        let tilted = SolarArray { tilt_deg: 30.0, ..s };
        let n = tilted.normal_enu(0.0, up);
        assert!((n[1] - 0.5).abs() < 1e-12 && (n[2] - 30f64.to_radians().cos()).abs() < 1e-12);
    }

    #[test]
    fn battery_applies_efficiencies_and_its_window() {
        let b = Battery {
            capacity_wh: 100.0,
            min_soc: 0.2,
            max_soc: 0.9,
            charge_efficiency: 0.9,
            discharge_efficiency: 0.95,
        };
        assert!((b.usable_j() - 70.0 * 3600.0).abs() < 1e-6);
        let half = 50.0 * 3600.0;
        let (e, lost) = b.step(half, 100.0, 360.0); // 10 Wh in
        assert!((e - (half + 9.0 * 3600.0)).abs() < 1e-6 && lost == 0.0);
        let (e, _) = b.step(half, -95.0, 360.0); // 9.5 Wh out → 10 Wh from the cells
        assert!((e - (half - 10.0 * 3600.0)).abs() < 1e-6);
        let (e, lost) = b.step(half, 1000.0, 3600.0);
        assert!((e - 90.0 * 3600.0).abs() < 1e-6 && lost > 0.0, "clamped at max_soc");
        let (e, lost) = b.step(half, -1000.0, 3600.0);
        assert!((e - 20.0 * 3600.0).abs() < 1e-6 && lost > 0.0, "clamped at min_soc");
    }

    #[test]
    fn cameras_see_the_sun_only_within_their_field() {
        let c = Camera { yaw_deg: 0.0, pitch_deg: -15.0, hfov_deg: 60.0, vfov_deg: 45.0 };
        assert!(c.sees_sun(90.0, 100.0, 5.0), "driving east into a low morning Sun");
        assert!(!c.sees_sun(90.0, 100.0, 20.0), "Sun above the view");
        assert!(!c.sees_sun(270.0, 100.0, 5.0), "Sun behind");
        assert!(c.sees_sun(350.0, 10.0, 0.0), "wraps through north");
    }

    #[test]
    fn shipped_hyperion_loads_and_bad_values_are_named() {
        let h = ResourceModel::hyperion();
        assert!(h.solar.is_some() && h.locomotor.mass_kg > 100.0);
        let err = ResourceModel::parse(&HYPERION_RON.replacen("max_soc: 1.0", "max_soc: 1.2", 1), "h.ron").unwrap_err();
        assert!(err.to_string().contains("battery.max_soc") && err.to_string().contains("h.ron"), "{err}");
    }
}
