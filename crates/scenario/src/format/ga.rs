//! The scenario format's own types for an actions job's task and GA settings. They
//! mirror areo-actions' configuration types field for field and convert into them, so
//! renaming a library field cannot change what a scenario file says
//! (`tests/robustness.rs` round-trips every shipped scenario through them).

use serde::{Deserialize, Serialize};

/// A science sample on the ground.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampleSpec {
    /// Position, map frame, m.
    pub x_m: f64,
    /// Position, map frame, m.
    pub y_m: f64,
    /// Mass, kg (> 0).
    pub mass_kg: f64,
}

/// A rock: a collision obstacle for the rover's body.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RockSpec {
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
pub struct TaskSpec {
    /// Start: reference point (x, y), m, and heading, degrees clockwise from north.
    pub start: (f64, f64, f64),
    /// Target: (x, y), m.
    pub target: (f64, f64),
    /// The target is reached within this distance, m (> 0).
    pub target_radius_m: f64,
    /// Science samples on the ground.
    #[serde(default)]
    pub samples: Vec<SampleSpec>,
    /// Samples the task asks for (0 = none needed; collecting is still rewarded).
    #[serde(default)]
    pub samples_wanted: usize,
    /// Rocks.
    #[serde(default)]
    pub rocks: Vec<RockSpec>,
    /// The task needs the arm to move.
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
    /// In-situ measurements that put the science tray down.
    #[serde(default)]
    pub tray: bool,
}

impl From<&TaskSpec> for areo_actions::Task {
    fn from(t: &TaskSpec) -> areo_actions::Task {
        areo_actions::Task {
            start: t.start,
            target: t.target,
            target_radius_m: t.target_radius_m,
            samples: t
                .samples
                .iter()
                .map(|s| areo_actions::Sample { x_m: s.x_m, y_m: s.y_m, mass_kg: s.mass_kg })
                .collect(),
            samples_wanted: t.samples_wanted,
            rocks: t.rocks.iter().map(RockSpec::to_rock).collect(),
            manipulation: t.manipulation,
            communication: t.communication,
            video: t.video,
            recharge: t.recharge,
            tray: t.tray,
        }
    }
}

impl RockSpec {
    /// The library's rock.
    pub fn to_rock(&self) -> areo_actions::Rock {
        areo_actions::Rock { x_m: self.x_m, y_m: self.y_m, height_m: self.height_m, width_m: self.width_m }
    }
}

/// A terrain class on one feature of a synthesised terrain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeatureClassSpec {
    /// The feature's index in the terrain's `features`.
    pub feature: usize,
    /// The class's name (letters, digits, `_` and `-`).
    pub class: String,
    /// Its wheel–ground friction coefficient (0.01..=5). Sinkage is not modelled: the
    /// wheels are rigid on rigid ground.
    pub mu: f64,
}

/// Execution settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ExecSpec {
    /// Friction coefficient μ.
    pub mu: f64,
    /// Hard floor of the stability margin S (0..1): below it the plan fails.
    pub stability_floor: f64,
    /// Body box half extents (forward, left, up), m.
    pub body_half_m: (f64, f64, f64),
}

impl Default for ExecSpec {
    fn default() -> ExecSpec {
        let d = areo_actions::ExecConfig::default();
        ExecSpec { mu: d.mu, stability_floor: d.stability_floor, body_half_m: d.body_half_m }
    }
}

impl From<&ExecSpec> for areo_actions::ExecConfig {
    fn from(e: &ExecSpec) -> areo_actions::ExecConfig {
        areo_actions::ExecConfig { mu: e.mu, stability_floor: e.stability_floor, body_half_m: e.body_half_m }
    }
}

/// Fitness weights (eq. 17).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WeightsSpec {
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

impl Default for WeightsSpec {
    fn default() -> WeightsSpec {
        let d = areo_actions::Weights::default();
        WeightsSpec {
            progress: d.progress,
            samples: d.samples,
            stability: d.stability,
            time: d.time,
            energy: d.energy,
            complete: d.complete,
            s_free: d.s_free,
        }
    }
}

impl From<&WeightsSpec> for areo_actions::Weights {
    fn from(w: &WeightsSpec) -> areo_actions::Weights {
        areo_actions::Weights {
            progress: w.progress,
            samples: w.samples,
            stability: w.stability,
            time: w.time,
            energy: w.energy,
            complete: w.complete,
            s_free: w.s_free,
        }
    }
}

/// Where crossover cuts the first parent.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum CrossoverSpec {
    /// A discrete normal centred on the parent's failure point; with probability
    /// `uniform`, uniform over the plan instead.
    Centred {
        /// Standard deviation, modules (> 0).
        sigma: f64,
        /// Probability of a uniform draw instead (0..1).
        uniform: f64,
    },
    /// Uniform over the plan.
    Uniform,
}

impl From<CrossoverSpec> for areo_actions::CrossoverPoint {
    fn from(c: CrossoverSpec) -> areo_actions::CrossoverPoint {
        match c {
            CrossoverSpec::Centred { sigma, uniform } => areo_actions::CrossoverPoint::Centred { sigma, uniform },
            CrossoverSpec::Uniform => areo_actions::CrossoverPoint::Uniform,
        }
    }
}

impl From<areo_actions::CrossoverPoint> for CrossoverSpec {
    fn from(c: areo_actions::CrossoverPoint) -> CrossoverSpec {
        match c {
            areo_actions::CrossoverPoint::Centred { sigma, uniform } => CrossoverSpec::Centred { sigma, uniform },
            areo_actions::CrossoverPoint::Uniform => CrossoverSpec::Uniform,
        }
    }
}

/// GA settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GaSpec {
    /// Plans per generation (≥ 2).
    pub population: usize,
    /// Generations (≥ 1).
    pub generations: usize,
    /// Length range of the random initial plans, modules.
    pub initial_length: (usize, usize),
    /// Longest plan, modules.
    pub max_length: usize,
    /// Crossover point distribution.
    pub crossover: CrossoverSpec,
    /// Per-module probability of replacement by a random module of the inventory.
    pub mutate_replace: f64,
    /// Per-plan probability of inserting a random module.
    pub mutate_insert: f64,
    /// Per-plan probability of deleting a module.
    pub mutate_delete: f64,
    /// Tournament size for selection (≥ 1).
    pub tournament: usize,
    /// Best plans copied unchanged into the next generation.
    pub elitism: usize,
    /// Seed of the ChaCha8 generator.
    pub seed: u64,
}

impl Default for GaSpec {
    fn default() -> GaSpec {
        let d = areo_actions::GaConfig::default();
        GaSpec {
            population: d.population,
            generations: d.generations,
            initial_length: d.initial_length,
            max_length: d.max_length,
            crossover: d.crossover.into(),
            mutate_replace: d.mutate_replace,
            mutate_insert: d.mutate_insert,
            mutate_delete: d.mutate_delete,
            tournament: d.tournament,
            elitism: d.elitism,
            seed: d.seed,
        }
    }
}

impl From<&GaSpec> for areo_actions::GaConfig {
    fn from(g: &GaSpec) -> areo_actions::GaConfig {
        areo_actions::GaConfig {
            population: g.population,
            generations: g.generations,
            initial_length: g.initial_length,
            max_length: g.max_length,
            crossover: g.crossover.into(),
            mutate_replace: g.mutate_replace,
            mutate_insert: g.mutate_insert,
            mutate_delete: g.mutate_delete,
            tournament: g.tournament,
            elitism: g.elitism,
            seed: g.seed,
        }
    }
}

/// Modules forced in or out of the filtered inventory (Table 1 codes).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OverridesSpec {
    /// Keep these even if a filter would remove them.
    pub force_in: Vec<u16>,
    /// Remove these whatever the filters say.
    pub force_out: Vec<u16>,
}

impl From<&OverridesSpec> for areo_actions::Overrides {
    fn from(o: &OverridesSpec) -> areo_actions::Overrides {
        areo_actions::Overrides { force_in: o.force_in.clone(), force_out: o.force_out.clone() }
    }
}
