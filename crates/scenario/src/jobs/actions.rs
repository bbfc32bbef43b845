//! The action-planning job: build the terrain and the task, filter the inventory, run
//! the GA (per run, or per μ of a friction scan), and report each run's best plan with its
//! history, commands and plots, the seed studies, the friction studies and the climb.

use std::path::Path;

use crate::format::synth::FeatureSpec;
use areo_actions::{
    ClimbProfile, ExecConfig, Execution, Executor, FrictionReplay, FrictionScan, GaConfig, GaReport, Inventory,
    Overrides, Rock, Scale, Surroundings, Task, TraceStep, Weights, climb_margins, design_space_log10, evolve,
    friction_replay, friction_scan,
};
use areo_rover::RoverParams;
use areo_rover::evaluation::Evaluator;
use areo_terrain::Dem;

use crate::error::{Error, Result};
use crate::format::{ActionsJob, ScenarioFile, TerrainSource};
use crate::jobs::RunOptions;
use crate::report::Raster;
use crate::report::Report;
use crate::report::actions::{
    ActionsReport, BestPlan, ClimbFigures, ClimbPoseRow, CommandList, ExecutedBest, ForceBinding, GaPlanRecord,
    GaRunFigures, RemovedModule, ReplayFigures, ReplayPointRow, ScanFigures, ScanPointRow, ScanSeedFigures, SeedRow,
    SeedScanRow, SeedThreshold, SensitivityFigures, StartPose, StudyFigures, WheelBinding,
};
use crate::report::actions_view::{ACTIONS_VIEW_PIXELS, ActionsView, ActionsViewStep, SECTION_HALF_M, SECTION_STEP_M};
use crate::report::plots::{HistogramPlot, Marker, Plot, ProfilePlot, ProfileRover, RoutePlot, Series, TimePlot};
use std::collections::BTreeMap;

mod best_plan;

use best_plan::*;

/// A GA setting refused by areo-actions, placed at its field in the scenario.
fn ga_error(file: &ScenarioFile, e: areo_actions::Error) -> Error {
    match e {
        areo_actions::Error::Config { field, message } => file.error_at(&format!("job.{field}"), message),
        other => Error::Actions(other),
    }
}

/// Terrain classes by name: each one's μ and the map cells it holds.
pub type ClassCells = BTreeMap<String, (f64, usize)>;

/// What an actions job plans on: the terrain, the task (with the synthesised rocks
/// added) and the rover.
#[derive(Debug)]
pub struct Setup {
    /// The terrain.
    pub dem: Dem,
    /// The task.
    pub task: Task,
    /// The rover.
    pub params: RoverParams,
    /// Execution settings.
    pub execution: ExecConfig,
    /// Fitness weights.
    pub weights: Weights,
    /// GA settings.
    pub ga: GaConfig,
    /// Modules forced in or out of the filtered inventory.
    pub overrides: Overrides,
    /// The terrain classes of the features, by name: μ and the cells it holds.
    pub feature_classes: ClassCells,
}

/// The synthesised terrain with the friction of its features' classes — each class's
/// μ wherever its feature shapes the ground (a height of its own over 1 µm), the least
/// where two overlap — and the cells each class holds (by name: its μ and count).
fn with_feature_classes(
    dem: Dem,
    job: &ActionsJob,
    spec: &crate::format::synth::SynthSpec,
) -> Result<(Dem, ClassCells)> {
    if job.feature_classes.is_empty() {
        return Ok((dem, BTreeMap::new()));
    }
    let mut mu = vec![f32::NAN; dem.cols() * dem.rows()];
    let mut owner: Vec<Option<usize>> = vec![None; mu.len()];
    for (i, k) in job.feature_classes.iter().enumerate() {
        let feature = spec.features[k.feature].to_feature();
        for r in 0..dem.rows() {
            for c in 0..dem.cols() {
                let (x, y) = dem.cell_center(c, r);
                let cell = r * dem.cols() + c;
                if feature.height(x, y).abs() > 1e-6 && !(mu[cell] <= k.mu as f32) {
                    (mu[cell], owner[cell]) = (k.mu as f32, Some(i));
                }
            }
        }
    }
    let mut cells: ClassCells = job.feature_classes.iter().map(|k| (k.class.clone(), (k.mu, 0))).collect();
    for i in owner.into_iter().flatten() {
        if let Some(e) = cells.get_mut(&job.feature_classes[i].class) {
            e.1 += 1;
        }
    }
    Ok((dem.with_friction(mu)?, cells))
}

/// Builds an actions job's terrain, task and rover (paths relative to `file`).
pub fn setup(job: &ActionsJob, file: &ScenarioFile) -> Result<Setup> {
    let base = file.path.parent().unwrap_or(Path::new("."));
    let mut feature_classes = BTreeMap::new();
    let (dem, synth_rocks): (Dem, Vec<Rock>) = match &job.terrain {
        TerrainSource::Synth(spec) => {
            let rocks = spec
                .features
                .iter()
                .filter_map(|f| match *f {
                    FeatureSpec::Rock { x_m, y_m, height_m, width_m } => Some(Rock { x_m, y_m, height_m, width_m }),
                    _ => None,
                })
                .collect();
            let (dem, cells) = with_feature_classes(spec.build()?, job, spec)
                .map_err(|e| e.referenced_by(&file.path, "job.feature_classes"))?;
            feature_classes = cells;
            (dem, rocks)
        }
        TerrainSource::File(rel) => (crate::terrain::read_job_dem(file, Path::new(rel), "job.terrain")?, Vec::new()),
    };
    let params = match &job.rover {
        Some(rel) => crate::format::rover_files::load_params(&base.join(rel))
            .map_err(|e| e.referenced_by(&file.path, "job.rover"))?,
        None => RoverParams::lsr1(),
    };
    let mut task = Task::from(&job.task);
    task.rocks.extend(synth_rocks);
    Ok(Setup {
        dem,
        task,
        params,
        execution: (&job.execution).into(),
        weights: (&job.weights).into(),
        ga: (&job.ga).into(),
        overrides: (&job.overrides).into(),
        feature_classes,
    })
}

/// One GA run's result: its report and wall time (s), the execution settings and
/// inventory it ran with, its seed study, and its best plan executed with a trace.
struct RunResult {
    name: String,
    report: GaReport,
    seconds: f64,
    exec: ExecConfig,
    inventory: Inventory,
    generations: usize,
    study: Option<SeedStudy>,
    best: Execution,
}

/// What an actions job computed (the public [`ActionsReport`], the summary and the
/// files are made from it): the filtered inventory, each run, the friction scan
/// (the μ values and their results, and the scan for each further seed), the first
/// run's best plan replayed over friction, and the climb profile.
struct Computed {
    filtered: Inventory,
    runs: Vec<RunResult>,
    scan: Option<(Vec<f64>, FrictionScan)>,
    scan_seeds: Vec<(u64, FrictionScan)>,
    replay: Option<FrictionReplay>,
    climb: Option<ClimbProfile>,
    sensitivity: Vec<areo_actions::SensitivityRow>,
}

/// Runs an actions job: compute, then the report.
pub(crate) fn run(job: &ActionsJob, file: &ScenarioFile, opts: RunOptions<'_>) -> Result<Report> {
    let setup = setup(job, file)?;
    opts.budget.check(&crate::budget::actions(job, (setup.dem.cols() * setup.dem.rows()) as u64))?;
    let computed = compute(job, file, opts, &setup)?;
    Ok(report(&setup, &computed))
}

/// The GA's scales for the task on this rover.
fn scale_of(setup: &Setup) -> Scale {
    let (task, params) = (&setup.task, &setup.params);
    Scale {
        start_distance_m: task.start_distance_m(),
        samples_wanted: task.samples_wanted,
        reference_time_s: task.start_distance_m() / params.speed_m_s,
        battery_wh: params.battery.capacity_wh * params.battery.usable_fraction,
        s_floor: setup.execution.stability_floor,
    }
}

/// The runs: the job's list, or one run on the filtered inventory.
fn run_plans(job: &ActionsJob, file: &ScenarioFile, setup: &Setup, filtered: &Inventory) -> Result<Vec<RunPlan>> {
    if job.runs.is_empty() {
        return Ok(vec![RunPlan {
            name: "plan".to_string(),
            inventory: filtered.clone(),
            mu: setup.execution.mu,
            ga: setup.ga.clone(),
            seeds: None,
        }]);
    }
    job.runs
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let inventory = match &r.inventory {
                Some(codes) => Inventory::from_codes(codes).map_err(|c| {
                    file.error_at(&format!("job.runs[{i}].inventory"), format!("{c} is not a Table 1 code"))
                })?,
                None => filtered.clone(),
            };
            let ga = GaConfig { crossover: r.crossover.map_or(setup.ga.crossover, Into::into), ..setup.ga.clone() };
            Ok(RunPlan { name: r.name.clone(), inventory, mu: r.mu.unwrap_or(setup.execution.mu), ga, seeds: r.seeds })
        })
        .collect()
}

/// The μ values of a `(first, last, step)` range (`mu_scan`, `mu_replay`), rounded to
/// 1e-6.
fn mu_values(range: Option<(f64, f64, f64)>) -> Vec<f64> {
    match range {
        Some((a, b, step)) => {
            let n = ((b - a) / step + 1e-9).floor() as usize;
            (0..=n).map(|k| ((a + step * k as f64) * 1e6).round() / 1e6).collect()
        }
        None => Vec::new(),
    }
}

/// Evolves every run (and its other seeds), scans μ and profiles the climb.
fn compute(job: &ActionsJob, file: &ScenarioFile, opts: RunOptions<'_>, setup: &Setup) -> Result<Computed> {
    let Setup { dem, task, params, execution, weights, ga, overrides, .. } = setup;
    let evaluator = Evaluator::new(params);
    let scale = scale_of(setup);
    let room = Surroundings::new((dem.cols() as f64 * dem.dx(), dem.rows() as f64 * dem.dy()), params);
    let filtered = Inventory::for_task(task, &room, overrides);
    let plans = run_plans(job, file, setup, &filtered)?;
    let scan = mu_values(job.mu_scan);
    let scan_seeds: Vec<u64> =
        job.mu_scan_seeds.map_or(Vec::new(), |(a, b)| (a..=b).filter(|&seed| seed != ga.seed).collect());
    // The run's own seed, then the study's others.
    let evolutions: usize = plans
        .iter()
        .map(|r| 1 + r.seeds.map_or(0, |(a, b)| (b - a + 1) as usize - usize::from((a..=b).contains(&r.ga.seed))))
        .sum();
    opts.progress.start((evolutions + scan.len() * (1 + scan_seeds.len())) as u64, "evolving");
    let mut runs = Vec::with_capacity(plans.len());
    for plan in &plans {
        let exec = ExecConfig { mu: plan.mu, ..*execution };
        let executor = Executor::new(dem, &evaluator, task, exec);
        if let Some(problem) = executor.start_problem() {
            return Err(file.error_at("job.task.start", format!("the start pose is not admissible: {problem}")));
        }
        let clock = std::time::Instant::now();
        let report = evolve(&executor, &plan.inventory, weights, &scale, &plan.ga).map_err(|e| ga_error(file, e))?;
        let seconds = clock.elapsed().as_secs_f64();
        opts.progress.advance(1);
        let study = match plan.seeds {
            None => None,
            Some((first, last)) => {
                let mut study = SeedStudy::default();
                for seed in first..=last {
                    let r = if seed == plan.ga.seed {
                        report.clone()
                    } else {
                        let ga = GaConfig { seed, ..plan.ga.clone() };
                        let r =
                            evolve(&executor, &plan.inventory, weights, &scale, &ga).map_err(|e| ga_error(file, e))?;
                        opts.progress.advance(1);
                        r
                    };
                    study.add(seed, &r, task);
                }
                Some(study)
            }
        };
        let best = executor.run(&report.best.plan, true);
        let (name, inventory, generations) = (plan.name.clone(), plan.inventory.clone(), plan.ga.generations);
        runs.push(RunResult { name, report, seconds, exec, inventory, generations, study, best });
    }
    let (scan, scan_seeds) = friction_scans(job, file, opts, setup, &plans[0].inventory, &scan, &scan_seeds)?;
    opts.progress.finish();
    let (replay, climb, sensitivity) = studies_without_the_ga(job, setup, &runs[0]);
    Ok(Computed { filtered, runs, scan, scan_seeds, replay, climb, sensitivity })
}

/// The friction scan at the GA's seed (`mu_scan`), and at each seed of
/// `mu_scan_seeds` (all of them, the GA's own included, in seed order; empty without).
#[allow(clippy::type_complexity)]
fn friction_scans(
    job: &ActionsJob,
    file: &ScenarioFile,
    opts: RunOptions<'_>,
    setup: &Setup,
    inventory: &Inventory,
    mus: &[f64],
    other_seeds: &[u64],
) -> Result<(Option<(Vec<f64>, FrictionScan)>, Vec<(u64, FrictionScan)>)> {
    if mus.is_empty() {
        return Ok((None, Vec::new()));
    }
    let evaluator = Evaluator::new(&setup.params);
    let scale = scale_of(setup);
    let scan_with = |ga: &GaConfig| {
        friction_scan(
            &setup.dem,
            &evaluator,
            &setup.task,
            setup.execution,
            inventory,
            &setup.weights,
            &scale,
            ga,
            mus,
            job.ditch_far_edge_y_m,
            |_| opts.progress.advance(1),
        )
        .map_err(|e| ga_error(file, e))
    };
    let result = scan_with(&setup.ga)?;
    let mut seeds = Vec::new();
    if let Some((a, b)) = job.mu_scan_seeds {
        if (a..=b).contains(&setup.ga.seed) {
            seeds.push((setup.ga.seed, result.clone()));
        }
        for &seed in other_seeds {
            seeds.push((seed, scan_with(&GaConfig { seed, ..setup.ga.clone() })?));
        }
        seeds.sort_by_key(|(seed, _)| *seed);
    }
    Ok((Some((mus.to_vec(), result)), seeds))
}

/// What needs no GA: the first run's best plan replayed over friction, the straight
/// climb, and the climb with each assumed parameter changed.
fn studies_without_the_ga(
    job: &ActionsJob,
    setup: &Setup,
    first: &RunResult,
) -> (Option<FrictionReplay>, Option<ClimbProfile>, Vec<areo_actions::SensitivityRow>) {
    let Setup { dem, task, params, execution, .. } = setup;
    let evaluator = Evaluator::new(params);
    let replay = job.mu_replay.map(|range| {
        friction_replay(
            dem,
            &evaluator,
            task,
            first.exec,
            &first.report.best.plan,
            &mu_values(Some(range)),
            job.ditch_far_edge_y_m,
        )
    });
    let climb =
        job.climb_profile.map(|(step, length)| climb_margins(dem, &evaluator, task.start, execution.mu, step, length));
    let sensitivity = match job.climb_profile {
        Some((step, length)) => job
            .sensitivity
            .iter()
            .flat_map(|(which, values)| {
                areo_actions::climb_sensitivity(dem, params, task.start, execution.mu, step, length, *which, values)
            })
            .collect(),
        None => Vec::new(),
    };
    (replay, climb, sensitivity)
}

/// The public report.
fn report(setup: &Setup, computed: &Computed) -> Report {
    let (task, m) = (&setup.task, setup.ga.initial_length.1);
    let filtered = &computed.filtered;
    let mut r = ActionsReport {
        design_space_log10_full: design_space_log10(26, m),
        design_space_log10_filtered: design_space_log10(filtered.modules.len(), m),
        plan_modules: m,
        inventory: filtered.codes(),
        removed: (filtered.removed.iter()).map(|r| RemovedModule { code: r.code, reason: r.reason.clone() }).collect(),
        feature_classes: (setup.feature_classes.iter())
            .map(|(name, &(mu, cells))| (name.clone(), crate::report::actions::FeatureClassFigures { mu, cells }))
            .collect(),
        ..ActionsReport::default()
    };
    for run in &computed.runs {
        let mut f = run_figures(&run.report, run.seconds, task);
        f.modules = run.inventory.modules.len();
        f.design_space_log10 = design_space_log10(run.inventory.modules.len(), m);
        f.study = run.study.as_ref().map(|study| StudyFigures {
            seed_rows: seed_rows(&run.name, study),
            ..study_figures(study, run.generations)
        });
        best_figures(&mut f, run);
        r.runs.insert(run.name.clone(), f);
        r.run_order.push(run.name.clone());
        r.best_plans.insert(run.name.clone(), best_plan(setup, run));
    }
    let studies: Vec<(String, &SeedStudy)> =
        computed.runs.iter().filter_map(|r| r.study.as_ref().map(|s| (r.name.clone(), s))).collect();
    if !studies.is_empty() {
        r.plots = study_plots(&studies, setup.ga.generations);
    }
    r.plots.extend(computed.climb.as_ref().map(climb_plot));
    r.scan = computed.scan.as_ref().map(|(values, result)| scan_figures(values, result));
    if !computed.scan_seeds.is_empty() {
        r.scan_seeds = Some(scan_seed_figures(&computed.scan_seeds));
    }
    r.replay = computed.replay.as_ref().map(|replay| replay_figures(&computed.runs[0], replay));
    r.climb = computed.climb.as_ref().map(climb_figures);
    (r.sensitivity, r.sensitivity_order) = sensitivity_figures(&computed.sensitivity);
    Report::Actions(Box::new(r))
}

/// The friction scan's thresholds and what binds just below each.
fn scan_figures(values: &[f64], result: &FrictionScan) -> ScanFigures {
    let (crossed, completed) = (result.min_mu_crossing, result.min_mu_completing);
    let mut f = ScanFigures {
        scan_mu_first: values[0],
        scan_mu_last: values[values.len() - 1],
        scan_points: (result.points.iter())
            .map(|p| ScanPointRow {
                mu: p.mu,
                complete: p.complete,
                best_fitness: p.best_fitness,
                prefix: p.prefix_len,
                max_y_m: p.max_y_m,
                failure: p.failure.as_ref().map(ToString::to_string).unwrap_or_default(),
                binding: p.binding.as_ref().map(wheel_binding),
            })
            .collect(),
        scan_min_mu_crossing_ditch: crossed,
        scan_min_mu_completing: completed,
        scan_ditch_needs_less_friction_than_hill: crossed.zip(completed).map(|(a, b)| a < b),
        ..ScanFigures::default()
    };
    // What binds just below each threshold: the best plan at the last μ that fails.
    for (what, threshold) in [("crossing", crossed), ("completing", completed)] {
        // (The nearest μ below whose best plan stopped on a force limit: a plan that
        // merely runs out of modules names no wheel.)
        let below = threshold.and_then(|t| result.points.iter().rev().find(|p| p.mu < t - 1e-9 && p.binding.is_some()));
        if let Some(b) = below.and_then(|p| p.binding.as_ref()) {
            let binding = ForceBinding {
                wheel: b.wheel.clone(),
                climbing: b.climbing,
                y_m: b.contact_m[1],
                mu: below.map_or(0.0, |p| p.mu),
                steepest_wheel: b.steepest.0.clone(),
                steepest_climbing: b.steepest.2,
                steepest_angle_deg: b.steepest.1,
                said: b.to_string(),
            };
            f.scan_binding_below.insert(what.to_string(), binding);
        }
    }
    f
}

/// A force limit as the report holds it.
fn wheel_binding(b: &areo_actions::WheelLimit) -> WheelBinding {
    WheelBinding {
        wheel: b.wheel.clone(),
        climbing: b.climbing,
        contact_x_m: b.contact_m[0],
        contact_y_m: b.contact_m[1],
        contact_angle_deg: b.contact_angle_deg,
        pitch_deg: b.pitch_deg,
        steepest_wheel: b.steepest.0.clone(),
        steepest_angle_deg: b.steepest.1,
        steepest_climbing: b.steepest.2,
    }
}

/// The friction scan's thresholds over seeds: median, least and greatest, and how many
/// seeds never got there.
fn scan_seed_figures(seeds: &[(u64, FrictionScan)]) -> ScanSeedFigures {
    let n = seeds.len();
    let rows = seeds.iter().map(|(seed, s)| SeedScanRow {
        seed: *seed,
        min_mu_crossing_ditch: s.min_mu_crossing,
        min_mu_completing: s.min_mu_completing,
        completed_at: s.points.iter().filter(|p| p.complete).map(|p| p.mu).collect(),
    });
    let mut f = ScanSeedFigures { scan_seeds: n, scan_seed_rows: rows.collect(), ..ScanSeedFigures::default() };
    for (what, pick) in [
        ("crossing_ditch", (|s: &FrictionScan| s.min_mu_crossing) as fn(&FrictionScan) -> Option<f64>),
        ("completing", |s: &FrictionScan| s.min_mu_completing),
    ] {
        let mut found: Vec<f64> = seeds.iter().filter_map(|(_, s)| pick(s)).collect();
        found.sort_by(f64::total_cmp);
        let never = n - found.len();
        f.scan_seeds_never.insert(what.to_string(), never);
        let (Some(&lo), Some(&hi)) = (found.first(), found.last()) else { continue };
        // A seed that never gets there counts as above every μ: the median exists while
        // fewer than half never do.
        let median = (2 * never < n).then(|| found[(n - 1) / 2]);
        f.scan_seeds_min_mu.insert(what.to_string(), SeedThreshold { least: lo, greatest: hi, median });
    }
    f
}

/// The replayed plan: from which μ up it crosses and completes, and what stops it at
/// the highest μ where it fails.
fn replay_figures(run: &RunResult, replay: &FrictionReplay) -> ReplayFigures {
    let mut r = ReplayFigures {
        replay_run: run.name.clone(),
        replay_found_at_mu: run.exec.mu,
        replay_points: (replay.points.iter())
            .map(|p| ReplayPointRow {
                mu: p.mu,
                complete: p.complete,
                modules_executed: p.prefix_len,
                max_y_m: p.max_y_m,
                failure_module: p.failure.as_ref().map(|(i, _)| i + 1),
                failure_code: p.failure.as_ref().map(|(i, _)| run.report.best.plan[*i].code()),
                failure: p.failure.as_ref().map(|(_, f)| f.to_string()).unwrap_or_default(),
                binding: p.binding.as_ref().map(wheel_binding),
            })
            .collect(),
        replay_min_mu_crossing_ditch: replay.min_mu_crossing,
        replay_min_mu_completing: replay.min_mu_completing,
        ..ReplayFigures::default()
    };
    let failing = replay.highest_failing();
    if let Some(p) = failing {
        r.replay_highest_failing_mu = Some(p.mu);
        r.replay_highest_failing_max_y_m = Some(p.max_y_m);
        r.replay_stops_at_module = Some(p.failure.as_ref().map_or(p.prefix_len + 1, |(i, _)| i + 1));
        r.replay_failure_said = p.failure.as_ref().map(|(_, f)| f.to_string());
        if let Some((i, f)) = &p.failure {
            r.replay_failure = Some(f.kind().to_string());
            r.replay_failure_module = Some(*i + 1);
            r.replay_failure_code = Some(run.report.best.plan[*i].code());
        }
        if let Some(b) = &p.binding {
            r.replay_binding_wheel = Some(b.wheel.clone());
            r.replay_binding_climbing = Some(b.climbing);
            r.replay_binding_y_m = Some(b.contact_m[1]);
            r.replay_binding_steepest_wheel = Some(b.steepest.0.clone());
            r.replay_binding_steepest_climbing = Some(b.steepest.2);
            r.replay_binding_steepest_angle_deg = Some(b.steepest.1);
        }
    }
    r
}

/// A run's best plan as executed: where it ended and what bound it.
fn best_figures(f: &mut GaRunFigures, run: &RunResult) {
    let (report, best) = (&run.report, &run.best);
    f.executed = ExecutedBest {
        complete: best.complete,
        modules: best.prefix_len,
        samples: best.samples,
        taken: taken_label(&best.taken),
        min_stability: best.min_stability,
        mean_stability: best.mean_stability,
        time_s: best.time_s,
        energy_wh: best.energy_wh,
        stopped_at: (best.failure.as_ref())
            .map(|(i, f)| format!("module {} ({}): {f}", i + 1, report.best.plan[*i].code())),
    };
    let executed = &report.best.plan[..best.prefix_len.min(report.best.plan.len())];
    let count = |m: areo_rover::motion::Module| executed.iter().filter(|&&x| x == m).count() as f64;
    use areo_rover::motion::Module as M;
    f.arm_forward_net = count(M::ArmForward) - count(M::ArmBack);
    if let Some(last) = best.trace.last() {
        f.last_pitch_deg = Some(last.pitch_deg);
        // Left and right front wheels' share of the load where the plan last stood:
        // near 0 as the rover rotates back over its rear wheels.
        let l = last.wheel_loads_n;
        let total: f64 = l.iter().sum();
        if total > 0.0 {
            f.last_front_load_fraction = Some((l[0] + l[3]) / total);
        }
    }
    f.failure = best.failure.as_ref().map(|(_, failure)| failure.kind().to_string());
    if let Some(b) = &best.binding {
        f.binding_wheel = Some(b.wheel.clone());
        f.binding_climbing = Some(b.climbing);
        f.binding_said = Some(b.to_string());
    }
}

/// A fact name's part for a parameter value: `0.27` → `0p27`, `-5` → `m5`.
fn value_key(v: f64) -> String {
    format!("{v}").replace('.', "p").replace('-', "m")
}

/// The figures of the sensitivity climbs, by field and value.
type SensitivityMap = BTreeMap<String, BTreeMap<String, SensitivityFigures>>;

/// Each assumed value's climb: what stopped it, where, and the margins at its end; and
/// the (field, value) keys in the scenario's order.
fn sensitivity_figures(rows: &[areo_actions::SensitivityRow]) -> (SensitivityMap, Vec<(String, String)>) {
    let (mut out, mut order) = (SensitivityMap::new(), Vec::new());
    for row in rows {
        let mut f =
            SensitivityFigures { parameter: row.parameter.field().to_string(), value: row.value, ..Default::default() };
        match &row.profile {
            Ok(p) => {
                f.stop = p.stop.unwrap_or("none").to_string();
                f.stop_distance_m = Some(p.stop_distance_m);
                // Without a pose the least margins are infinite: written, never a fact.
                f.min_margin_stowed = Some(p.least(|q| q.stowed.margin));
                f.min_margin_forward = Some(p.least(|q| q.forward.margin));
                if let Some(last) = p.poses.last() {
                    f.last_pitch_deg = Some(last.pitch_deg);
                    f.last_margin_stowed = Some(last.stowed.margin);
                    f.last_margin_forward = Some(last.forward.margin);
                    f.max_pitch_deg = Some(-p.least(|q| -q.pitch_deg));
                    f.arm_keeps_it_standing = Some(p.stop == Some("tip_over") && last.forward.margin > 0.0);
                }
            }
            Err(e) => {
                f.stop = "refused".into();
                f.refused = Some(e.to_string());
            }
        }
        let (field, value) = (row.parameter.field().replace('.', "_"), value_key(row.value));
        order.push((field.clone(), value.clone()));
        out.entry(field).or_default().insert(value, f);
    }
    (out, order)
}

/// The climb's facts: what ended it and where, and the margins along it.
fn climb_figures(profile: &ClimbProfile) -> ClimbFigures {
    let stop = profile.stop.unwrap_or("none").to_string();
    let Some(last) = profile.poses.last() else {
        return ClimbFigures { climb_stop: stop, climb_poses: climb_rows(profile), ..ClimbFigures::default() };
    };
    let max =
        |f: &dyn Fn(&areo_actions::ClimbPose) -> f64| profile.poses.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
    let front = profile.poses.iter().map(|p| p.stowed.front_load_fraction).filter(|f| f.is_finite());
    ClimbFigures {
        climb_stop: stop,
        climb_stop_distance_m: Some(profile.stop_distance_m),
        climb_last_pitch_deg: Some(last.pitch_deg),
        climb_last_margin_stowed: Some(last.stowed.margin),
        climb_last_margin_forward: Some(last.forward.margin),
        climb_max_pitch_deg: Some(max(&|p| p.pitch_deg)),
        climb_min_margin_stowed: Some(profile.least(|p| p.stowed.margin)),
        climb_min_margin_forward: Some(profile.least(|p| p.forward.margin)),
        climb_max_margin_gain: Some(max(&|p| p.forward.margin - p.stowed.margin)),
        climb_min_front_load_stowed: Some(front.fold(f64::INFINITY, f64::min)),
        climb_forward_tool_m: Some(profile.forward_tool_m[0]),
        climb_poses: climb_rows(profile),
    }
}

/// Every pose of the climb (`climb.csv`).
fn climb_rows(profile: &ClimbProfile) -> Vec<ClimbPoseRow> {
    let rows = profile.poses.iter().map(|p| ClimbPoseRow {
        distance_m: p.distance_m,
        pitch_deg: p.pitch_deg,
        margin_stowed: p.stowed.margin,
        margin_forward: p.forward.margin,
        front_load_stowed: p.stowed.front_load_fraction,
        front_load_forward: p.forward.front_load_fraction,
        friction_needed_stowed: p.stowed.friction_needed,
        friction_needed_forward: p.forward.friction_needed,
        violation_stowed: p.stowed.violation.unwrap_or("").to_string(),
        violation_forward: p.forward.violation.unwrap_or("").to_string(),
    });
    rows.collect()
}

/// The climb's plot: margins and front load along it.
fn climb_plot(profile: &ClimbProfile) -> Plot {
    let series = |label: &str, rgb, f: &dyn Fn(&areo_actions::ClimbPose) -> f64| Series {
        label: label.to_string(),
        points: profile.poses.iter().map(|p| (p.distance_m, f(p))).filter(|q| q.1.is_finite()).collect(),
        rgb,
        width: 2,
    };
    let end = profile.poses.last().map_or(1.0, |p| p.distance_m.max(0.01));
    Plot::time(
        "climb",
        TimePlot {
            title: "Straight climb: stability margin and front-wheel load, arm stowed and forward".into(),
            x_label: "distance from the start, m".into(),
            y_label: "margin S / front share of the load".into(),
            series: vec![
                series("margin, arm stowed", (220, 30, 40), &|p| p.stowed.margin),
                series("margin, arm forward", (30, 90, 220), &|p| p.forward.margin),
                series("front load, arm stowed", (40, 160, 60), &|p| p.stowed.front_load_fraction),
                series("pitch / 90°", (120, 120, 120), &|p| p.pitch_deg / 90.0),
            ],
            nights: Vec::new(),
            x_range: (0.0, end),
            windows: Vec::new(),
            windows_label: String::new(),
            dots: false,
            x_ticks: Default::default(),
        },
    )
}

/// One GA run of the job, as configured.
struct RunPlan {
    name: String,
    inventory: Inventory,
    mu: f64,
    ga: GaConfig,
    seeds: Option<(u64, u64)>,
}

/// A run repeated over seeds: what each seed's GA found.
#[derive(Debug, Default)]
struct SeedStudy {
    /// (seed, first-solved generation, best fitness, samples, least stability margin)
    seeds: Vec<(u64, Option<usize>, f64, usize, f64)>,
    /// The samples each seed's best plan took, as [`taken_label`] writes them, and how
    /// many of them lie left and right of the way.
    taken: Vec<(String, usize, usize)>,
    /// The task has samples to take (else the sample facts are left out).
    has_samples: bool,
    /// Every seed's look-ahead values, pooled.
    lookahead: Vec<i64>,
    /// How each seed's best plan ended: "none" (it ran to its end) or the failure's
    /// kind (`tip_over`, `slip`, …) — the paper's task 2 turns on which.
    stopped_by: Vec<&'static str>,
}

impl SeedStudy {
    fn add(&mut self, seed: u64, r: &GaReport, task: &Task) {
        let e = &r.best.execution;
        self.seeds.push((seed, r.first_solved, r.best.fitness, e.samples, e.min_stability));
        let (left, right) = sides(task, &e.taken);
        self.taken.push((taken_label(&e.taken), left, right));
        self.has_samples = !task.samples.is_empty();
        self.lookahead.extend_from_slice(&r.lookahead);
        self.stopped_by.push(e.failure.as_ref().map_or("none", |(_, f)| f.kind()));
    }

    /// Fraction of seeds solved by generation `g` (0-based, inclusive).
    fn solved_by(&self, g: usize) -> f64 {
        let n = self.seeds.iter().filter(|s| s.1.is_some_and(|f| f <= g)).count();
        n as f64 / self.seeds.len().max(1) as f64
    }

    /// The median first-solved generation, an unsolved seed counting as never; `None`
    /// when half the seeds or more never solve it.
    fn median_first_solved(&self) -> Option<f64> {
        let mut g: Vec<f64> = self.seeds.iter().map(|s| s.1.map_or(f64::INFINITY, |f| f as f64)).collect();
        g.sort_by(f64::total_cmp);
        let n = g.len();
        let m = if n == 0 {
            f64::INFINITY
        } else if n % 2 == 1 {
            g[n / 2]
        } else {
            0.5 * (g[n / 2 - 1] + g[n / 2])
        };
        m.is_finite().then_some(m)
    }
}

fn study_figures(study: &SeedStudy, generations: usize) -> StudyFigures {
    let n = study.seeds.len();
    let last = generations.saturating_sub(1);
    let la = &study.lookahead;
    let small = la.iter().filter(|d| (1..=4).contains(*d)).count();
    let share = |f: &dyn Fn(i64) -> bool| {
        if la.is_empty() { 0.0 } else { la.iter().filter(|d| f(**d)).count() as f64 / la.len() as f64 }
    };
    let mut f = StudyFigures {
        seeds: n,
        first_seed: study.seeds.first().map_or(0, |s| s.0),
        last_seed: study.seeds.last().map_or(0, |s| s.0),
        last_generation: last,
        solved: study.seeds.iter().filter(|s| s.1.is_some()).count(),
        success_fraction: study.solved_by(last),
        first_solved_median: study.median_first_solved(),
        pooled_lookahead_1_to_4_fraction: if la.is_empty() { 0.0 } else { small as f64 / la.len() as f64 },
        pooled_improving_crossovers: la.len(),
        pooled_lookahead_none_fraction: share(&|d| d <= 0),
        pooled_lookahead_5_plus_fraction: share(&|d| d >= 5),
        ..StudyFigures::default()
    };
    // Over the seeds that solved it: the range of first-solved generations and of their
    // best plans' least stability margins (the paper's "S ≥ 40 %").
    let solved: Vec<&(u64, Option<usize>, f64, usize, f64)> = study.seeds.iter().filter(|s| s.1.is_some()).collect();
    if !solved.is_empty() {
        let gens = solved.iter().filter_map(|s| s.1);
        f.first_solved_earliest = Some(gens.clone().min().unwrap_or(0));
        f.first_solved_latest = Some(gens.max().unwrap_or(0));
        let margins = solved.iter().map(|s| s.4);
        f.solved_least_margin_min = Some(margins.clone().fold(f64::INFINITY, f64::min));
        f.solved_least_margin_max = Some(margins.fold(f64::NEG_INFINITY, f64::max));
    }
    // How the seeds' best plans ended: a count per kind, every kind that occurred.
    let mut kinds: Vec<&str> = study.stopped_by.clone();
    kinds.sort_unstable();
    kinds.dedup();
    for kind in kinds {
        let count = study.stopped_by.iter().filter(|k| **k == kind).count();
        f.seeds_stopped_by.insert(kind.to_string(), count);
    }
    // The paper's plan took the samples on the left of the way and left the others.
    if study.has_samples {
        let left_only = study.taken.iter().filter(|t| t.1 > 0 && t.2 == 0).count();
        f.left_only_fraction = Some(left_only as f64 / n.max(1) as f64);
    }
    // Of the crossovers that extended the successful prefix, the share adding fewer than
    // five modules (the paper's Figure 3 counts these).
    let extending = la.iter().filter(|d| **d >= 1).count();
    if extending > 0 {
        f.pooled_extending_under_5_fraction = Some(small as f64 / extending as f64);
    }
    f
}

/// Every seed of a run's study (`seeds.csv`).
fn seed_rows(name: &str, study: &SeedStudy) -> Vec<SeedRow> {
    let rows = study.seeds.iter().zip(&study.taken).zip(&study.stopped_by).map(
        |((&(seed, first, fitness, samples, s), taken), stopped_by)| SeedRow {
            run: name.to_string(),
            seed,
            first_solved_generation: first,
            best_fitness: fitness,
            samples,
            taken: taken.0.clone(),
            min_stability: s,
            stopped_by: stopped_by.to_string(),
        },
    );
    rows.collect()
}

/// The success-by-generation plot and each study's pooled look-ahead histogram.
fn study_plots(studies: &[(String, &SeedStudy)], generations: usize) -> Vec<Plot> {
    let palette = [(220, 30, 40), (30, 90, 220), (40, 160, 60), (150, 60, 200)];
    let series = studies
        .iter()
        .enumerate()
        .map(|(k, (name, study))| Series {
            label: name.clone(),
            points: (0..generations).map(|g| (g as f64, 100.0 * study.solved_by(g))).collect(),
            rgb: palette[k % palette.len()],
            width: 2,
        })
        .collect();
    let mut plots = vec![Plot::time(
        "success_by_generation",
        TimePlot {
            title: "Seeds whose GA has completed the task, by generation".into(),
            x_label: "generation".into(),
            y_label: "seeds solved, %".into(),
            series,
            nights: Vec::new(),
            x_range: (0.0, generations.saturating_sub(1).max(1) as f64),
            windows: Vec::new(),
            windows_label: String::new(),
            dots: false,
            x_ticks: Default::default(),
        },
    )];
    for (name, study) in studies {
        plots.push(Plot::histogram(
            format!("lookahead_{name}"),
            HistogramPlot {
                title: format!("Look-ahead of improving crossovers, {name}, all seeds"),
                x_label: "change in successful-prefix length, modules".into(),
                y_label: "crossovers".into(),
                bin_width: None,
                series: vec![(study.lookahead.clone(), (30, 90, 220))],
            },
        ));
    }
    plots
}

/// The samples a plan took, by their 1-based number in the task ("s1 s4"), in the
/// order grasped; "none" for none.
fn taken_label(taken: &[usize]) -> String {
    if taken.is_empty() {
        return "none".to_string();
    }
    taken.iter().map(|k| format!("s{}", k + 1)).collect::<Vec<_>>().join(" ")
}

/// How many of the samples `taken` lie left and right of the way (the line from the
/// start to the target, looking toward the target).
fn sides(task: &Task, taken: &[usize]) -> (usize, usize) {
    let (dx, dy) = (task.target.0 - task.start.0, task.target.1 - task.start.1);
    let left = taken
        .iter()
        .filter(|&&k| {
            let s = &task.samples[k];
            dx * (s.y_m - task.start.1) - dy * (s.x_m - task.start.0) > 0.0
        })
        .count();
    (left, taken.len() - left)
}

/// A GA run's best plan as the GA scored it (its run took `seconds`).
fn run_figures(r: &GaReport, seconds: f64, task: &Task) -> GaRunFigures {
    let e = &r.best.execution;
    let small = r.lookahead.iter().filter(|d| (1..=4).contains(*d)).count();
    let sides = (!task.samples.is_empty()).then(|| sides(task, &e.taken));
    GaRunFigures {
        complete: e.complete,
        best_fitness: r.best.fitness,
        samples: e.samples,
        samples_taken: (!task.samples.is_empty()).then(|| taken_label(&e.taken)),
        samples_left: sides.map(|s| s.0),
        samples_right: sides.map(|s| s.1),
        min_stability: e.min_stability,
        peak_saturation: e.peak_saturation,
        peak_friction_ratio: e.peak_friction_ratio,
        prefix: e.prefix_len,
        distance_to_target_m: e.distance_to_target_m,
        evaluations: r.evaluations,
        modules_executed: r.modules_executed,
        seconds,
        first_solved_generation: r.first_solved,
        lookahead_1_to_4_fraction: if r.lookahead.is_empty() { 0.0 } else { small as f64 / r.lookahead.len() as f64 },
        ..GaRunFigures::default()
    }
}
