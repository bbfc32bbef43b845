//! The actions job's files and plots: CSV rows, the plan's and the GA's files, the top
//! view, side profile, trace and GA plots.

use super::*;

/// A row of commands.csv: one command of the best plan as the rover would run it.
#[derive(Serialize, Default)]
pub(super) struct CommandRow {
    pub(super) step: usize,
    pub(super) code: u16,
    pub(super) action: String,
    pub(super) distance_m: Fixed<3>,
    pub(super) arc_radius_m: Option<Fixed<3>>,
    pub(super) turn_deg: Fixed<3>,
    pub(super) steer_left_front_deg: Option<Fixed<2>>,
    pub(super) steer_right_front_deg: Option<Fixed<2>>,
    pub(super) steer_left_rear_deg: Option<Fixed<2>>,
    pub(super) steer_right_rear_deg: Option<Fixed<2>>,
    pub(super) arm_yaw_deg: Option<Fixed<2>>,
    pub(super) arm_shoulder_deg: Option<Fixed<2>>,
    pub(super) arm_elbow_deg: Option<Fixed<2>>,
    pub(super) tool_x_m: Fixed<3>,
    pub(super) tool_y_m: Fixed<3>,
    pub(super) tool_z_m: Fixed<3>,
    pub(super) duration_s: Fixed<2>,
    pub(super) energy_wh: Fixed<5>,
    pub(super) end_x_m: Fixed<3>,
    pub(super) end_y_m: Fixed<3>,
    pub(super) end_heading_deg: Fixed<2>,
    pub(super) stability: Option<Fixed<4>>,
}

/// commands.json and commands.csv: the best plan's executed modules as commands (arc,
/// distance, steering, arm joints, duration, energy; `areo_actions::commands`).
pub(super) fn write_commands(dir: &Path, setup: &Setup, run: &RunResult) -> Result<Vec<PathBuf>> {
    let cmds = areo_actions::commands(&run.report.best.plan, &run.best, &setup.params, setup.task.start.2);
    let json_path = dir.join("commands.json");
    let doc = serde_json::json!({
        "rover": setup.params.name,
        "start": { "x_m": setup.task.start.0, "y_m": setup.task.start.1, "heading_deg": setup.task.start.2 },
        "mu": run.exec.mu,
        "complete": run.best.complete,
        "commands": cmds,
    });
    write_file(&json_path, json_for(&json_path, &doc, true)?.as_bytes())?;
    let csv_path = dir.join("commands.csv");
    let pick = |a: Option<[f64; 4]>, i: usize| a.map(|a| Fixed(a[i]));
    let joint = |a: Option<[f64; 3]>, i: usize| a.map(|a| Fixed(a[i]));
    write_rows(
        &csv_path,
        cmds.iter().map(|c| CommandRow {
            step: c.step,
            code: c.code,
            action: c.action.to_string(),
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
        }),
    )?;
    Ok(vec![json_path, csv_path])
}

/// A run's files: plan.json, plan.csv, ga.csv and the plots.
pub(super) fn write_outputs(
    dir: &Path,
    setup: &Setup,
    report: &GaReport,
    trace: &[TraceStep],
    mu: f64,
) -> Result<Vec<PathBuf>> {
    let mut files = plan_files(dir, report, trace)?;
    files.extend(top_view_plot(dir, setup, trace)?);
    files.extend(side_profile_plot(dir, setup, trace)?);
    files.extend(trace_plots(dir, trace, mu)?);
    files.extend(ga_plots(dir, report)?);
    Ok(files)
}

/// plan.json (the best plan with its execution, trace and the GA's history), plan.csv
/// (the trace) and ga.csv (per generation).
pub(super) fn plan_files(dir: &Path, report: &GaReport, trace: &[TraceStep]) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let mut put = |name: &str, text: String| -> Result<()> {
        let path = dir.join(name);
        write_file(&path, text.as_bytes())?;
        files.push(path);
        Ok(())
    };
    let plan_json = serde_json::json!({
        "codes": report.best.plan.iter().map(|m| m.code()).collect::<Vec<_>>(),
        "fitness": report.best.fitness,
        "execution": report.best.execution,
        "trace": trace,
        "generations": report.generations,
        "first_solved": report.first_solved,
        "lookahead": report.lookahead,
    });
    put("plan.json", json_for(&dir.join("plan.json"), &plan_json, true)?)?;
    let trace_rows = trace.iter().enumerate().map(|(i, t)| TraceRow {
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
    put("plan.csv", rows_to_csv(&dir.join("plan.csv"), trace_rows)?)?;
    let generations = report.generations.iter().map(|g| GenerationRow {
        generation: g.index,
        best: Fixed(g.best),
        mean: Fixed(g.mean),
        best_prefix: g.best_prefix,
        solved: u8::from(g.solved),
    });
    put("ga.csv", rows_to_csv(&dir.join("ga.csv"), generations)?)?;
    Ok(files)
}

/// The best plan's top view over a hillshade, with rocks and samples.
pub(super) fn top_view_plot(dir: &Path, setup: &Setup, trace: &[TraceStep]) -> Result<Vec<PathBuf>> {
    let (dem, task) = (&setup.dem, &setup.task);
    // Top view over a hillshade, with rocks and samples.
    let slope = areo_terrain::slope::slope_aspect(dem);
    let background = areo_terrain::hillshade::hillshade_rgb(dem, &slope, None, 315.0, 45.0);
    let (x0, y0) = (dem.extent().x_min, dem.extent().y_min);
    let mut path = vec![(task.start.0, task.start.1)];
    path.extend(trace.iter().map(|t| (t.x_m, t.y_m)));
    let mut markers = vec![
        Marker { label: "start".into(), at: (task.start.0, task.start.1), rgb: (40, 200, 60) },
        Marker { label: "target".into(), at: task.target, rgb: (250, 220, 40) },
    ];
    for (i, s) in task.samples.iter().enumerate() {
        markers.push(Marker { label: format!("s{}", i + 1), at: (s.x_m, s.y_m), rgb: (60, 200, 220) });
    }
    for (i, r) in task.rocks.iter().enumerate() {
        markers.push(Marker { label: format!("rock {}", i + 1), at: (r.x_m, r.y_m), rgb: (120, 120, 120) });
    }
    let top = RoutePlot {
        title: "Best plan: top view".into(),
        background,
        cols: dem.cols(),
        rows: dem.rows(),
        origin: (x0, y0),
        extent: (dem.cols() as f64 * dem.dx(), dem.rows() as f64 * dem.dy()),
        series: vec![Series { label: "reference point".into(), points: path, rgb: (220, 30, 40), width: 2 }],
        markers,
    };
    crate::output::plots::route(dir, "top_view", &top)
}

/// The side profile along the path, with the rover drawn at a few steps: the first,
/// the lowest, the steepest-pitched ones, and the last.
pub(super) fn side_profile_plot(dir: &Path, setup: &Setup, trace: &[TraceStep]) -> Result<Vec<PathBuf>> {
    let (dem, task, params) = (&setup.dem, &setup.task, &setup.params);
    // Side profile along the path, with the rover drawn at a few steps: the first,
    // the steepest-pitched ones, and the last.
    let mut along = Vec::with_capacity(trace.len() + 1);
    let mut s_acc = 0.0;
    let mut prev = (task.start.0, task.start.1);
    along.push(0.0);
    for t in trace {
        s_acc += (t.x_m - prev.0).hypot(t.y_m - prev.1);
        prev = (t.x_m, t.y_m);
        along.push(s_acc);
    }
    let mut ground = Vec::new();
    let mut last = (task.start.0, task.start.1);
    let mut dist = 0.0;
    for t in trace.iter() {
        let steps = 5;
        for k in 1..=steps {
            let f = k as f64 / steps as f64;
            let (x, y) = (last.0 + (t.x_m - last.0) * f, last.1 + (t.y_m - last.1) * f);
            let d = dist + (t.x_m - last.0).hypot(t.y_m - last.1) * f;
            if let Some(z) = areo_terrain::Ground::height(dem, x, y) {
                ground.push((d, z));
            }
        }
        dist += (t.x_m - last.0).hypot(t.y_m - last.1);
        last = (t.x_m, t.y_m);
    }
    let mut picks: Vec<usize> = Vec::new();
    if !trace.is_empty() {
        let mut by_pitch: Vec<usize> = (0..trace.len()).collect();
        by_pitch.sort_by(|&a, &b| trace[b].pitch_deg.abs().total_cmp(&trace[a].pitch_deg.abs()));
        let last = trace.len() - 1;
        picks.push(0);
        picks.push(last);
        // The lowest body (in a ditch), then the steepest pitches — each an eighth of
        // the way from every pose already drawn, so their labels stay apart (turns and
        // arm moves do not advance along the path, so steps alone do not space them).
        if let Some(low) = (0..trace.len()).min_by(|&a, &b| trace[a].z_m.total_cmp(&trace[b].z_m)) {
            by_pitch.insert(0, low);
        }
        let spacing = along[last + 1] / 8.0;
        for i in by_pitch {
            if picks.iter().all(|&p| (along[p + 1] - along[i + 1]).abs() > spacing) {
                picks.push(i);
            }
            if picks.len() >= 5 {
                break;
            }
        }
        picks.sort_unstable();
        picks.dedup();
    }
    let rovers = picks
        .iter()
        .map(|&i| {
            let t = &trace[i];
            let d = along[i + 1];
            // Project each axle on the path direction at that step.
            let (sx, sy) = (t.heading_deg.to_radians().sin(), t.heading_deg.to_radians().cos());
            let wheel = |k: usize| {
                let w = t.wheels[k];
                (d + (w[0] - t.x_m) * sx + (w[1] - t.y_m) * sy, w[2])
            };
            let wheels = [wheel(0), wheel(1), wheel(2), wheel(3), wheel(4), wheel(5)];
            ProfileRover { wheels, body: (d, t.z_m), label: format!("{} ({:.0}°)", i + 1, t.pitch_deg) }
        })
        .collect();
    crate::output::plots::profile(
        dir,
        "side_profile",
        &ProfilePlot {
            title: "Side profile: ground under the path, the rover at key steps (left side)".into(),
            ground,
            rovers,
            wheel_radius_m: params.wheel_radius_m,
        },
    )
}

/// The stability margin and the friction needed along the plan.
pub(super) fn trace_plots(dir: &Path, trace: &[TraceStep], mu: f64) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let stability: Vec<(f64, f64)> =
        trace.iter().enumerate().filter_map(|(i, t)| t.stability.map(|s| ((i + 1) as f64, 100.0 * s))).collect();
    files.extend(crate::output::plots::time(
        dir,
        "stability",
        &TimePlot {
            title: "Stability margin along the plan".into(),
            x_label: "module".into(),
            y_label: "least margin in the module, % of flat ground".into(),
            series: vec![Series { label: "stability margin".into(), points: stability, rgb: (30, 90, 220), width: 2 }],
            nights: Vec::new(),
            x_range: (0.0, trace.len().max(1) as f64),
            windows: Vec::new(),
            windows_label: String::new(),
            dots: false,
            x_ticks: Default::default(),
        },
    )?);
    let friction: Vec<(f64, f64)> = trace.iter().enumerate().map(|(i, t)| (i as f64 + 1.0, t.friction_used)).collect();
    files.extend(crate::output::plots::time(
        dir,
        "friction",
        &TimePlot {
            title: "Friction needed along the plan (largest |T|/N over each module's poses)".into(),
            x_label: "module".into(),
            y_label: "friction needed".into(),
            series: vec![
                Series { label: "needed".into(), points: friction, rgb: (200, 90, 20), width: 2 },
                Series {
                    label: format!("μ = {mu}"),
                    points: vec![(0.0, mu), (trace.len().max(1) as f64, mu)],
                    rgb: (120, 120, 120),
                    width: 1,
                },
            ],
            nights: Vec::new(),
            x_range: (0.0, trace.len().max(1) as f64),
            windows: Vec::new(),
            windows_label: String::new(),
            dots: false,
            x_ticks: Default::default(),
        },
    )?);
    Ok(files)
}

/// Fitness per generation and the look-ahead histogram.
pub(super) fn ga_plots(dir: &Path, report: &GaReport) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let best: Vec<(f64, f64)> = report.generations.iter().map(|g| (g.index as f64, g.best)).collect();
    let mean: Vec<(f64, f64)> = report.generations.iter().map(|g| (g.index as f64, g.mean)).collect();
    files.extend(crate::output::plots::time(
        dir,
        "fitness",
        &TimePlot {
            title: "Fitness per generation".into(),
            x_label: "generation".into(),
            y_label: "fitness".into(),
            series: vec![
                Series { label: "best".into(), points: best, rgb: (220, 30, 40), width: 2 },
                Series { label: "mean".into(), points: mean, rgb: (30, 90, 220), width: 2 },
            ],
            nights: Vec::new(),
            x_range: (0.0, report.generations.len().saturating_sub(1).max(1) as f64),
            windows: Vec::new(),
            windows_label: String::new(),
            dots: false,
            x_ticks: Default::default(),
        },
    )?);
    files.extend(crate::output::plots::histogram(
        dir,
        "lookahead",
        &HistogramPlot {
            title: "Look-ahead of improving crossovers".into(),
            x_label: "change in successful-prefix length, modules".into(),
            y_label: "crossovers".into(),
            bin_width: None,
            series: vec![(report.lookahead.clone(), (30, 90, 220))],
        },
    )?);
    Ok(files)
}

/// A row of plan.csv: one module of the best plan as executed.
#[derive(Serialize, Default)]
pub(super) struct TraceRow {
    pub(super) step: usize,
    pub(super) code: u16,
    pub(super) x_m: Fixed<4>,
    pub(super) y_m: Fixed<4>,
    pub(super) z_m: Fixed<4>,
    pub(super) heading_deg: Fixed<2>,
    pub(super) pitch_deg: Fixed<2>,
    pub(super) stability: Option<Fixed<4>>,
    pub(super) load_lf_n: Fixed<3>,
    pub(super) load_lm_n: Fixed<3>,
    pub(super) load_lr_n: Fixed<3>,
    pub(super) load_rf_n: Fixed<3>,
    pub(super) load_rm_n: Fixed<3>,
    pub(super) load_rr_n: Fixed<3>,
    pub(super) energy_wh: Fixed<6>,
}

/// A row of ga.csv: one generation.
#[derive(Serialize, Default)]
pub(super) struct GenerationRow {
    pub(super) generation: usize,
    pub(super) best: Fixed<5>,
    pub(super) mean: Fixed<5>,
    pub(super) best_prefix: usize,
    pub(super) solved: u8,
}

/// A row of seeds.csv: one seed of a run's study.
#[derive(Serialize, Default)]
pub(super) struct SeedRow {
    pub(super) run: String,
    pub(super) seed: u64,
    pub(super) first_solved_generation: Option<usize>,
    pub(super) best_fitness: Fixed<4>,
    pub(super) samples: usize,
    pub(super) taken: String,
    pub(super) min_stability: Fixed<4>,
    /// How the seed's best plan ended: `none` (it ran to its end) or a failure's kind.
    pub(super) stopped_by: String,
}

/// A row of climb.csv: one pose of the straight climb, arm stowed and forward.
#[derive(Serialize, Default)]
pub(super) struct ClimbRow {
    pub(super) distance_m: Fixed<3>,
    pub(super) pitch_deg: Fixed<3>,
    pub(super) margin_stowed: Option<Fixed<4>>,
    pub(super) margin_forward: Option<Fixed<4>>,
    pub(super) front_load_stowed: Option<Fixed<4>>,
    pub(super) front_load_forward: Option<Fixed<4>>,
    pub(super) friction_needed_stowed: Option<Fixed<4>>,
    pub(super) friction_needed_forward: Option<Fixed<4>>,
    pub(super) violation_stowed: &'static str,
    pub(super) violation_forward: &'static str,
}
