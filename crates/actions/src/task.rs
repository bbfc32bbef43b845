//! What the rover is asked to do: where it starts, where the target is, the science
//! samples on the ground, the rocks it must not hit, and what the task needs.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// A science sample on the ground.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sample {
    /// Position, map frame, m.
    pub x_m: f64,
    /// Position, map frame, m.
    pub y_m: f64,
    /// Mass, kg (> 0).
    pub mass_kg: f64,
}

/// A rock: a collision obstacle for the rover's body (its wheels climb it as terrain).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rock {
    /// Centre, map frame, m.
    pub x_m: f64,
    /// Centre, map frame, m.
    pub y_m: f64,
    /// Height above the ground, m (> 0).
    pub height_m: f64,
    /// Width, m (> 0).
    pub width_m: f64,
}

/// A task (Farritor et al., section 4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Task {
    /// Start: reference point (x, y), m, and heading, degrees clockwise from north.
    pub start: (f64, f64, f64),
    /// Target: (x, y), m.
    pub target: (f64, f64),
    /// The target is reached within this distance, m (> 0).
    pub target_radius_m: f64,
    /// Science samples on the ground.
    #[serde(default)]
    pub samples: Vec<Sample>,
    /// Samples the task asks for (0 = none needed; collecting is still rewarded).
    #[serde(default)]
    pub samples_wanted: usize,
    /// Rocks.
    #[serde(default)]
    pub rocks: Vec<Rock>,
    /// The task needs the arm to move (a manipulation task, or the CG shift of task 2).
    #[serde(default)]
    pub manipulation: bool,
    /// The task needs a communication with the ground station.
    #[serde(default)]
    pub communication: bool,
    /// The task needs video.
    #[serde(default)]
    pub video: bool,
    /// The battery may need recharging on the way.
    #[serde(default)]
    pub recharge: bool,
    /// In-situ measurements that put the science tray down (2010/2020); samples alone
    /// are grasped and carried.
    #[serde(default)]
    pub tray: bool,
}

impl Task {
    /// Checks values, naming the first bad field.
    pub fn validate(&self) -> Result<()> {
        let bad = |field: String, message: String| Err(Error::Config { field, message });
        // Positions within 10 km of the map origin: an action plan covers metres.
        const FAR: f64 = 1e4;
        for (field, v) in
            [("start", self.start.0), ("start", self.start.1), ("target", self.target.0), ("target", self.target.1)]
        {
            if !(v.abs() <= FAR) {
                return bad(field.into(), format!("{v}: coordinates allowed -10000..=10000 m"));
            }
        }
        if !(self.start.2.abs() <= 360.0) {
            return bad("start".into(), format!("heading {}: allowed -360..=360 degrees", self.start.2));
        }
        if !(self.target_radius_m > 0.0 && self.target_radius_m <= FAR) {
            return bad("target_radius_m".into(), format!("{}: allowed 0 (exclusive)..=10000 m", self.target_radius_m));
        }
        for (i, s) in self.samples.iter().enumerate() {
            if !(s.x_m.abs() <= FAR && s.y_m.abs() <= FAR) {
                return bad(format!("samples[{i}]"), format!("({}, {}): allowed -10000..=10000 m", s.x_m, s.y_m));
            }
        }
        for (i, r) in self.rocks.iter().enumerate() {
            if !(r.x_m.abs() <= FAR && r.y_m.abs() <= FAR && r.height_m <= 100.0 && r.width_m <= 100.0) {
                return bad(
                    format!("rocks[{i}]"),
                    "x_m, y_m allowed -10000..=10000 m; height_m, width_m at most 100 m".into(),
                );
            }
        }
        for (i, s) in self.samples.iter().enumerate() {
            if !(s.mass_kg > 0.0 && s.mass_kg < 100.0) {
                return bad(format!("samples[{i}].mass_kg"), format!("{}: allowed (0, 100) kg", s.mass_kg));
            }
        }
        for (i, r) in self.rocks.iter().enumerate() {
            if !(r.height_m > 0.0 && r.width_m > 0.0) {
                return bad(format!("rocks[{i}]"), "height_m and width_m must be > 0".into());
            }
        }
        if self.samples_wanted > self.samples.len() {
            return bad(
                "samples_wanted".into(),
                format!("{}: only {} samples are on the ground", self.samples_wanted, self.samples.len()),
            );
        }
        Ok(())
    }

    /// Straight-line distance from the start to the target, m.
    pub fn start_distance_m(&self) -> f64 {
        (self.target.0 - self.start.0).hypot(self.target.1 - self.start.1)
    }
}
