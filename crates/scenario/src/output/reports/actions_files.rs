//! An actions report's files written from the report alone: `inventory.csv`,
//! `seeds.csv`, `climb.csv`, `scan.csv`, `scan_seeds.csv`, `replay.csv`,
//! `sensitivity.csv`, the job's plots, and each run's `plan.json`, `plan.csv`,
//! `ga.csv`, `commands.json`, `commands.csv` and plots (in a directory per run when
//! there are several).

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::{Error, Result};
use crate::output::csv::{Fixed, write_rows};
use crate::output::{json_for, write_file};
use crate::report::actions::{
    ActionsReport, BestPlan, ClimbPoseRow, ReplayPointRow, ScanPointRow, SeedRow, SeedScanRow, SensitivityFigures,
};

/// Writes the files into `dir`; returns them.
pub(crate) fn write(dir: &Path, r: &ActionsReport) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let kept = r.inventory.iter().map(|&code| InventoryCsv { code, kept: 1, reason: String::new() });
    let removed = r.removed.iter().map(|m| InventoryCsv { code: m.code, kept: 0, reason: m.reason.clone() });
    let path = dir.join("inventory.csv");
    write_rows(&path, kept.chain(removed))?;
    files.push(path);
    let studies = r.run_order.iter().filter_map(|name| r.runs.get(name)?.study.as_ref());
    if studies.clone().next().is_some() {
        let path = dir.join("seeds.csv");
        write_rows(&path, studies.flat_map(|s| s.seed_rows.iter().map(SeedCsv::from)))?;
        files.push(path);
    }
    if let Some(climb) = &r.climb {
        let path = dir.join("climb.csv");
        write_rows(&path, climb.climb_poses.iter().map(ClimbCsv::from))?;
        files.push(path);
    }
    for plot in &r.plots {
        files.extend(crate::output::plots::write(dir, plot)?);
    }
    for name in &r.run_order {
        let Some(best) = r.best_plans.get(name) else { continue };
        let sub = if r.run_order.len() == 1 { dir.to_path_buf() } else { dir.join(name) };
        std::fs::create_dir_all(&sub).map_err(|source| Error::Io { path: sub.clone(), source })?;
        files.extend(best_plan_files(&sub, best)?);
    }
    if let Some(scan) = &r.scan {
        let path = dir.join("scan.csv");
        write_rows(&path, scan.scan_points.iter().map(ScanCsv::from))?;
        files.push(path);
    }
    if let Some(seeds) = &r.scan_seeds {
        let path = dir.join("scan_seeds.csv");
        write_rows(&path, seeds.scan_seed_rows.iter().map(SeedScanCsv::from))?;
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

/// A run's files: plan.json, plan.csv, ga.csv, its plots, commands.json and
/// commands.csv.
fn best_plan_files(dir: &Path, best: &BestPlan) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let mut put = |name: &str, write: &dyn Fn(&Path) -> Result<()>| -> Result<()> {
        let path = dir.join(name);
        write(&path)?;
        files.push(path);
        Ok(())
    };
    let plan = &best.plan;
    put("plan.json", &|p| write_file(p, json_for(p, plan, true)?.as_bytes()))?;
    let trace = plan.trace.iter().enumerate().map(|(i, t)| TraceCsv {
        step: i + 1,
        code: t.code,
        x_m: Fixed(t.x_m),
        y_m: Fixed(t.y_m),
        z_m: Fixed(t.z_m),
        heading_deg: Fixed(t.heading_deg),
        pitch_deg: Fixed(t.pitch_deg),
        stability: t.stability.map(Fixed),
        load_lf_n: Fixed(t.wheel_loads_n[0]),
        load_lm_n: Fixed(t.wheel_loads_n[1]),
        load_lr_n: Fixed(t.wheel_loads_n[2]),
        load_rf_n: Fixed(t.wheel_loads_n[3]),
        load_rm_n: Fixed(t.wheel_loads_n[4]),
        load_rr_n: Fixed(t.wheel_loads_n[5]),
        energy_wh: Fixed(t.energy_wh),
    });
    put("plan.csv", &|p| write_rows(p, trace.clone()))?;
    let generations = plan.generations.iter().map(|g| GenerationCsv {
        generation: g.index,
        best: Fixed(g.best),
        mean: Fixed(g.mean),
        best_prefix: g.best_prefix,
        solved: u8::from(g.solved),
    });
    put("ga.csv", &|p| write_rows(p, generations.clone()))?;
    for plot in &best.plots {
        files.extend(crate::output::plots::write(dir, plot)?);
    }
    let commands = &best.commands;
    let json = dir.join("commands.json");
    write_file(&json, json_for(&json, commands, true)?.as_bytes())?;
    let csv = dir.join("commands.csv");
    let pick = |a: Option<[f64; 4]>, i: usize| a.map(|a| Fixed(a[i]));
    let joint = |a: Option<[f64; 3]>, i: usize| a.map(|a| Fixed(a[i]));
    let rows = commands.commands.iter().map(|c| CommandCsv {
        step: c.step,
        code: c.code,
        action: c.action,
        distance_m: Fixed(c.distance_m),
        arc_radius_m: c.arc_radius_m.map(Fixed),
        turn_deg: Fixed(c.turn_deg),
        steer_left_front_deg: pick(c.steering_deg, 0),
        steer_right_front_deg: pick(c.steering_deg, 1),
        steer_left_rear_deg: pick(c.steering_deg, 2),
        steer_right_rear_deg: pick(c.steering_deg, 3),
        arm_yaw_deg: joint(c.arm_joints_deg, 0),
        arm_shoulder_deg: joint(c.arm_joints_deg, 1),
        arm_elbow_deg: joint(c.arm_joints_deg, 2),
        tool_x_m: Fixed(c.tool_m[0]),
        tool_y_m: Fixed(c.tool_m[1]),
        tool_z_m: Fixed(c.tool_m[2]),
        duration_s: Fixed(c.duration_s),
        energy_wh: Fixed(c.energy_wh),
        end_x_m: Fixed(c.end[0]),
        end_y_m: Fixed(c.end[1]),
        end_heading_deg: Fixed(c.end[2]),
        stability: c.stability.map(Fixed),
    });
    write_rows(&csv, rows)?;
    let view = dir.join("view.html");
    super::actions_view::write(&view, &best.view)?;
    files.extend([json, csv, view]);
    Ok(files)
}

/// A row of commands.csv: one command of the best plan as the rover would run it.
#[derive(Serialize, Default)]
struct CommandCsv {
    step: usize,
    code: u16,
    action: &'static str,
    distance_m: Fixed<3>,
    arc_radius_m: Option<Fixed<3>>,
    turn_deg: Fixed<3>,
    steer_left_front_deg: Option<Fixed<2>>,
    steer_right_front_deg: Option<Fixed<2>>,
    steer_left_rear_deg: Option<Fixed<2>>,
    steer_right_rear_deg: Option<Fixed<2>>,
    arm_yaw_deg: Option<Fixed<2>>,
    arm_shoulder_deg: Option<Fixed<2>>,
    arm_elbow_deg: Option<Fixed<2>>,
    tool_x_m: Fixed<3>,
    tool_y_m: Fixed<3>,
    tool_z_m: Fixed<3>,
    duration_s: Fixed<2>,
    energy_wh: Fixed<5>,
    end_x_m: Fixed<3>,
    end_y_m: Fixed<3>,
    end_heading_deg: Fixed<2>,
    stability: Option<Fixed<4>>,
}

/// A row of plan.csv: one module of the best plan as executed.
#[derive(Serialize, Default, Clone)]
struct TraceCsv {
    step: usize,
    code: u16,
    x_m: Fixed<4>,
    y_m: Fixed<4>,
    z_m: Fixed<4>,
    heading_deg: Fixed<2>,
    pitch_deg: Fixed<2>,
    stability: Option<Fixed<4>>,
    load_lf_n: Fixed<3>,
    load_lm_n: Fixed<3>,
    load_lr_n: Fixed<3>,
    load_rf_n: Fixed<3>,
    load_rm_n: Fixed<3>,
    load_rr_n: Fixed<3>,
    energy_wh: Fixed<6>,
}

/// A row of ga.csv: one generation.
#[derive(Serialize, Default, Clone)]
struct GenerationCsv {
    generation: usize,
    best: Fixed<5>,
    mean: Fixed<5>,
    best_prefix: usize,
    solved: u8,
}

/// A row of seeds.csv: one seed of a run's study.
#[derive(Serialize, Default)]
struct SeedCsv<'a> {
    run: &'a str,
    seed: u64,
    first_solved_generation: Option<usize>,
    best_fitness: Fixed<4>,
    samples: usize,
    taken: &'a str,
    min_stability: Fixed<4>,
    stopped_by: &'a str,
}

impl<'a> From<&'a SeedRow> for SeedCsv<'a> {
    fn from(r: &'a SeedRow) -> SeedCsv<'a> {
        SeedCsv {
            run: &r.run,
            seed: r.seed,
            first_solved_generation: r.first_solved_generation,
            best_fitness: Fixed(r.best_fitness),
            samples: r.samples,
            taken: &r.taken,
            min_stability: Fixed(r.min_stability),
            stopped_by: &r.stopped_by,
        }
    }
}

/// A row of climb.csv: one pose of the straight climb, arm stowed and forward; a
/// margin that cannot be computed (no admissible pose) is an empty field.
#[derive(Serialize, Default)]
struct ClimbCsv<'a> {
    distance_m: Fixed<3>,
    pitch_deg: Fixed<3>,
    margin_stowed: Option<Fixed<4>>,
    margin_forward: Option<Fixed<4>>,
    front_load_stowed: Option<Fixed<4>>,
    front_load_forward: Option<Fixed<4>>,
    friction_needed_stowed: Option<Fixed<4>>,
    friction_needed_forward: Option<Fixed<4>>,
    violation_stowed: &'a str,
    violation_forward: &'a str,
}

impl<'a> From<&'a ClimbPoseRow> for ClimbCsv<'a> {
    fn from(p: &'a ClimbPoseRow) -> ClimbCsv<'a> {
        let num = |v: f64| v.is_finite().then_some(Fixed(v));
        ClimbCsv {
            distance_m: Fixed(p.distance_m),
            pitch_deg: Fixed(p.pitch_deg),
            margin_stowed: num(p.margin_stowed),
            margin_forward: num(p.margin_forward),
            front_load_stowed: num(p.front_load_stowed),
            front_load_forward: num(p.front_load_forward),
            friction_needed_stowed: num(p.friction_needed_stowed),
            friction_needed_forward: num(p.friction_needed_forward),
            violation_stowed: &p.violation_stowed,
            violation_forward: &p.violation_forward,
        }
    }
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

/// A row of scan.csv: the GA afresh at one μ.
#[derive(Serialize, Default)]
struct ScanCsv {
    /// As written in the scan (shortest form: 0.5, 1).
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

impl From<&ScanPointRow> for ScanCsv {
    fn from(p: &ScanPointRow) -> ScanCsv {
        let b = p.binding.as_ref();
        ScanCsv {
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

/// A row of scan_seeds.csv: one seed's thresholds and the μ values (space-separated)
/// whose best plan completed.
#[derive(Serialize, Default)]
struct SeedScanCsv {
    seed: u64,
    min_mu_crossing_ditch: Option<f64>,
    min_mu_completing: Option<f64>,
    completed_at: String,
}

impl From<&SeedScanRow> for SeedScanCsv {
    fn from(s: &SeedScanRow) -> SeedScanCsv {
        SeedScanCsv {
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
