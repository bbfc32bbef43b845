//! The fitness of an executed plan: equation (17) of Farritor et al.,
//! f = w1·D + w2·A + w3·Σ h(S_j) − w4·T − w5·E + w6·[task complete],
//! every term computed on the successful prefix (partial credit up to the failure).
//!
//! [A] The paper does not give its weights or normalisations (see
//! shared/reference/rover_physics.md §7.2); these are areo's, all in the scenario:
//! D = progress toward the target over the start distance (−1..1); A = samples
//! collected over those wanted (over 1 if none are wanted); h(S) ([`stability_penalty`]) = 0 for S ≥ `s_free`,
//! −((s_free − S)/(s_free − s_floor))² down to the floor, with the plan failing below
//! it, summed over the executed modules and divided by the start distance in modules
//! (10 cm) so it stays comparable across tasks; T = time over the time to drive the
//! start distance at nominal speed; E = energy over the battery's usable energy.

use serde::{Deserialize, Serialize};

use crate::executor::Execution;

/// Weights and shape of the fitness.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Weights {
    /// w1: progress toward the target.
    pub progress: f64,
    /// w2: samples.
    pub samples: f64,
    /// w3: stability (Σ h(S)).
    pub stability: f64,
    /// w4: time.
    pub time: f64,
    /// w5: energy.
    pub energy: f64,
    /// w6: task complete.
    pub complete: f64,
    /// No penalty at or above this margin (0..1).
    pub s_free: f64,
}

impl Default for Weights {
    fn default() -> Weights {
        Weights { progress: 10.0, samples: 5.0, stability: 2.0, time: 0.5, energy: 0.5, complete: 10.0, s_free: 0.8 }
    }
}

impl Weights {
    /// Checks ranges, naming the first bad field: every weight 0..=1e6 (a larger one
    /// only rescales the others, and products must stay finite), `s_free` 0..=1.
    pub fn validate(&self) -> crate::Result<()> {
        for (field, w) in [
            ("progress", self.progress),
            ("samples", self.samples),
            ("stability", self.stability),
            ("time", self.time),
            ("energy", self.energy),
            ("complete", self.complete),
        ] {
            if !(0.0..=1e6).contains(&w) {
                return Err(crate::Error::Config { field: field.into(), message: format!("{w}: allowed 0..=1e6") });
            }
        }
        if !(0.0..=1.0).contains(&self.s_free) {
            return Err(crate::Error::Config {
                field: "s_free".into(),
                message: format!("{}: allowed 0..=1 (a fraction of the flat-ground margin)", self.s_free),
            });
        }
        Ok(())
    }
}

/// Normalisation constants of one task.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scale {
    /// Start distance to the target, m.
    pub start_distance_m: f64,
    /// Samples wanted (≥ 1 for the normalisation).
    pub samples_wanted: usize,
    /// Time to drive the start distance at nominal speed, s.
    pub reference_time_s: f64,
    /// Usable battery energy, Wh.
    pub battery_wh: f64,
    /// The hard stability floor (0..1).
    pub s_floor: f64,
}

/// The paper's h(S): 0 above `s_free`, a quadratic penalty down to the floor.
pub fn stability_penalty(s: f64, s_free: f64, s_floor: f64) -> f64 {
    if s >= s_free {
        0.0
    } else {
        let x = ((s_free - s) / (s_free - s_floor).max(1e-9)).min(1.0);
        -x * x
    }
}

/// The fitness of an execution.
pub fn fitness(e: &Execution, w: &Weights, k: &Scale) -> f64 {
    let d0 = k.start_distance_m.max(1e-9);
    let progress = ((d0 - e.distance_to_target_m) / d0).clamp(-1.0, 1.0);
    let samples = e.samples as f64 / k.samples_wanted.max(1) as f64;
    let modules = (d0 / 0.10).max(1.0);
    let stability: f64 =
        e.stabilities.iter().map(|&s| stability_penalty(s, w.s_free, k.s_floor)).sum::<f64>() / modules;
    let time = e.time_s / k.reference_time_s.max(1e-9);
    let energy = e.energy_wh / k.battery_wh.max(1e-9);
    w.progress * progress + w.samples * samples + w.stability * stability - w.time * time - w.energy * energy
        + if e.complete { w.complete } else { 0.0 }
}
