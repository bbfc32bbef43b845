//! An actions report's files written from the report alone: `inventory.csv`,
//! `sweep.csv`, `sweep_seeds.csv`, `replay.csv` and `sensitivity.csv`.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::Result;
use crate::output::csv::{Fixed, write_rows};
use crate::report::actions::{ActionsReport, ReplayPointRow, SeedSweepRow, SensitivityFigures, SweepPointRow};

/// Writes the files into `dir`; returns them.
pub(crate) fn write(dir: &Path, r: &ActionsReport) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let kept = r.inventory.iter().map(|&code| InventoryCsv { code, kept: 1, reason: String::new() });
    let removed = r.removed.iter().map(|m| InventoryCsv { code: m.code, kept: 0, reason: m.reason.clone() });
    let path = dir.join("inventory.csv");
    write_rows(&path, kept.chain(removed))?;
    files.push(path);
    if let Some(sweep) = &r.sweep {
        let path = dir.join("sweep.csv");
        write_rows(&path, sweep.sweep_points.iter().map(SweepCsv::from))?;
        files.push(path);
    }
    if let Some(seeds) = &r.sweep_seeds {
        let path = dir.join("sweep_seeds.csv");
        write_rows(&path, seeds.sweep_seed_rows.iter().map(SeedSweepCsv::from))?;
        files.push(path);
    }
    if let Some(replay) = &r.replay {
        let path = dir.join("replay.csv");
        write_rows(&path, replay.replay_points.iter().map(ReplayCsv::from))?;
        files.push(path);
    }
    if !r.sensitivity_order.is_empty() {
        let rows = (r.sensitivity_order.iter())
            .filter_map(|(field, value)| r.sensitivity.get(field).and_then(|v| v.get(value)))
            .map(SensitivityCsv::from);
        let path = dir.join("sensitivity.csv");
        write_rows(&path, rows)?;
        files.push(path);
    }
    Ok(files)
}

/// A row of sensitivity.csv: one assumed value and the straight climb with it.
#[derive(Serialize, Default)]
struct SensitivityCsv {
    parameter: String,
    value: f64,
    stop: String,
    stop_distance_m: Option<Fixed<3>>,
    last_pitch_deg: Option<Fixed<2>>,
    last_margin_stowed: Option<Fixed<4>>,
    last_margin_forward: Option<Fixed<4>>,
    min_margin_stowed: Option<Fixed<4>>,
    min_margin_forward: Option<Fixed<4>>,
    /// Where the stowed rover tips over, the margin with the arm forward stays above 0.
    arm_keeps_it_standing: Option<u8>,
}

impl From<&SensitivityFigures> for SensitivityCsv {
    fn from(f: &SensitivityFigures) -> SensitivityCsv {
        SensitivityCsv {
            parameter: f.parameter.clone(),
            value: f.value,
            stop: f.refused.as_ref().map_or_else(|| f.stop.clone(), |why| format!("refused: {why}")),
            stop_distance_m: f.stop_distance_m.map(Fixed),
            last_pitch_deg: f.last_pitch_deg.map(Fixed),
            last_margin_stowed: f.last_margin_stowed.map(Fixed),
            last_margin_forward: f.last_margin_forward.map(Fixed),
            min_margin_stowed: f.min_margin_stowed.map(Fixed),
            min_margin_forward: f.min_margin_forward.map(Fixed),
            arm_keeps_it_standing: f.arm_keeps_it_standing.map(u8::from),
        }
    }
}

/// A row of inventory.csv: a module kept (1) or removed (0), and why.
#[derive(Serialize, Default)]
struct InventoryCsv {
    code: u16,
    kept: u8,
    reason: String,
}

/// A row of sweep.csv: the GA afresh at one μ.
#[derive(Serialize, Default)]
struct SweepCsv {
    /// As written in the sweep (shortest form: 0.5, 1).
    mu: String,
    complete: u8,
    best_fitness: Fixed<4>,
    prefix: usize,
    max_y_m: Fixed<3>,
    failure: String,
    binding_wheel: String,
    climbing: Option<u8>,
    contact_x_m: Option<Fixed<3>>,
    contact_y_m: Option<Fixed<3>>,
    contact_angle_deg: Option<Fixed<1>>,
    pitch_deg: Option<Fixed<1>>,
    steepest_wheel: String,
    steepest_angle_deg: Option<Fixed<1>>,
    steepest_climbing: Option<u8>,
}

impl From<&SweepPointRow> for SweepCsv {
    fn from(p: &SweepPointRow) -> SweepCsv {
        let b = p.binding.as_ref();
        SweepCsv {
            mu: p.mu.to_string(),
            complete: u8::from(p.complete),
            best_fitness: Fixed(p.best_fitness),
            prefix: p.prefix,
            max_y_m: Fixed(p.max_y_m),
            failure: p.failure.clone(),
            binding_wheel: b.map(|b| b.wheel.clone()).unwrap_or_default(),
            climbing: b.map(|b| u8::from(b.climbing)),
            contact_x_m: b.map(|b| Fixed(b.contact_x_m)),
            contact_y_m: b.map(|b| Fixed(b.contact_y_m)),
            contact_angle_deg: b.map(|b| Fixed(b.contact_angle_deg)),
            pitch_deg: b.map(|b| Fixed(b.pitch_deg)),
            steepest_wheel: b.map(|b| b.steepest_wheel.clone()).unwrap_or_default(),
            steepest_angle_deg: b.map(|b| Fixed(b.steepest_angle_deg)),
            steepest_climbing: b.map(|b| u8::from(b.steepest_climbing)),
        }
    }
}

/// A row of sweep_seeds.csv: one seed's thresholds and the μ values (space-separated)
/// whose best plan completed.
#[derive(Serialize, Default)]
struct SeedSweepCsv {
    seed: u64,
    min_mu_crossing_ditch: Option<f64>,
    min_mu_completing: Option<f64>,
    completed_at: String,
}

impl From<&SeedSweepRow> for SeedSweepCsv {
    fn from(s: &SeedSweepRow) -> SeedSweepCsv {
        SeedSweepCsv {
            seed: s.seed,
            min_mu_crossing_ditch: s.min_mu_crossing_ditch,
            min_mu_completing: s.min_mu_completing,
            completed_at: s.completed_at.iter().map(f64::to_string).collect::<Vec<_>>().join(" "),
        }
    }
}

/// A row of replay.csv: the replayed plan at one μ and what stopped it.
#[derive(Serialize, Default)]
struct ReplayCsv {
    mu: String,
    complete: u8,
    modules_executed: usize,
    max_y_m: Fixed<3>,
    failure_module: Option<usize>,
    failure_code: Option<u16>,
    failure: String,
    binding_wheel: String,
    climbing: Option<u8>,
    contact_y_m: Option<Fixed<3>>,
    contact_angle_deg: Option<Fixed<1>>,
    pitch_deg: Option<Fixed<1>>,
}

impl From<&ReplayPointRow> for ReplayCsv {
    fn from(p: &ReplayPointRow) -> ReplayCsv {
        let b = p.binding.as_ref();
        ReplayCsv {
            mu: p.mu.to_string(),
            complete: u8::from(p.complete),
            modules_executed: p.modules_executed,
            max_y_m: Fixed(p.max_y_m),
            failure_module: p.failure_module,
            failure_code: p.failure_code,
            failure: p.failure.clone(),
            binding_wheel: b.map(|b| b.wheel.clone()).unwrap_or_default(),
            climbing: b.map(|b| u8::from(b.climbing)),
            contact_y_m: b.map(|b| Fixed(b.contact_y_m)),
            contact_angle_deg: b.map(|b| Fixed(b.contact_angle_deg)),
            pitch_deg: b.map(|b| Fixed(b.pitch_deg)),
        }
    }
}
