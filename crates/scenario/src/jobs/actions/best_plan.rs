//! What the actions report holds of each run's best plan: the plan and the GA's
//! history, the commands, and the plots (top view, side profile, stability, friction,
//! fitness, look-ahead).

use super::*;

/// A run's best plan in full.
pub(super) fn best_plan(setup: &Setup, run: &RunResult) -> BestPlan {
    let (report, trace) = (&run.report, &run.best.trace);
    let task = &setup.task;
    let commands = areo_actions::commands(&report.best.plan, &run.best, &setup.params, task.start.2);
    let profile = PathProfile::new(setup, trace);
    let mut plots = vec![top_view_plot(setup, trace), side_profile_plot(setup, trace, &profile)];
    plots.extend(trace_plots(trace, run.exec.mu));
    plots.extend(ga_plots(report));
    let view = view(setup, run, &commands, &profile);
    BestPlan {
        plan: GaPlanRecord {
            codes: report.best.plan.iter().map(|m| m.code()).collect(),
            execution: report.best.execution.clone(),
            first_solved: report.first_solved,
            fitness: report.best.fitness,
            generations: report.generations.clone(),
            lookahead: report.lookahead.clone(),
            trace: trace.clone(),
        },
        commands: CommandList {
            commands,
            complete: run.best.complete,
            mu: run.exec.mu,
            rover: setup.params.name.clone(),
            start: StartPose { heading_deg: task.start.2, x_m: task.start.0, y_m: task.start.1 },
        },
        view,
        plots,
    }
}

/// The best plan's top view over a hillshade, with rocks and samples.
fn top_view_plot(setup: &Setup, trace: &[TraceStep]) -> Plot {
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
    Plot::route("top_view", top)
}

/// The path in profile: each step's distance along the reference point's path (the
/// start at 0, then after each module), and the ground under the path sampled five
/// times per module, (distance, height), m.
struct PathProfile {
    along: Vec<f64>,
    ground: Vec<(f64, f64)>,
}

impl PathProfile {
    fn new(setup: &Setup, trace: &[TraceStep]) -> PathProfile {
        let (dem, task) = (&setup.dem, &setup.task);
        let mut along = Vec::with_capacity(trace.len() + 1);
        let mut ground = Vec::new();
        let mut last = (task.start.0, task.start.1);
        let mut dist = 0.0;
        along.push(0.0);
        for t in trace {
            let step = (t.x_m - last.0).hypot(t.y_m - last.1);
            for k in 1..=5 {
                let f = f64::from(k) / 5.0;
                let (x, y) = (last.0 + (t.x_m - last.0) * f, last.1 + (t.y_m - last.1) * f);
                if let Some(z) = areo_terrain::Ground::height(dem, x, y) {
                    ground.push((dist + step * f, z));
                }
            }
            dist += step;
            last = (t.x_m, t.y_m);
            along.push(dist);
        }
        PathProfile { along, ground }
    }

    /// A map point (east, north, up) near step `i`'s rover in profile: placed along the
    /// path by its offset along the rover's heading.
    fn place(&self, trace: &[TraceStep], i: usize, p: [f64; 3]) -> (f64, f64) {
        let t = &trace[i];
        let (sx, sy) = (t.heading_deg.to_radians().sin(), t.heading_deg.to_radians().cos());
        (self.along[i + 1] + (p[0] - t.x_m) * sx + (p[1] - t.y_m) * sy, p[2])
    }
}

/// The side profile along the path, with the rover drawn at a few steps: the first,
/// the lowest, the steepest-pitched ones, and the last.
fn side_profile_plot(setup: &Setup, trace: &[TraceStep], profile: &PathProfile) -> Plot {
    let along = &profile.along;
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
            let wheels = t.wheels.map(|w| profile.place(trace, i, w));
            ProfileRover { wheels, body: (along[i + 1], t.z_m), label: format!("{} ({:.0}°)", i + 1, t.pitch_deg) }
        })
        .collect();
    Plot::profile(
        "side_profile",
        ProfilePlot {
            title: "Side profile: ground under the path, the rover at key steps (left side)".into(),
            ground: profile.ground.clone(),
            rovers,
            wheel_radius_m: setup.params.wheel_radius_m,
        },
    )
}

/// The viewer's data: the terrain from above (downsampled by whole cells to at most
/// [`ACTIONS_VIEW_PIXELS`] a side), the path in profile and the rover after each module.
fn view(setup: &Setup, run: &RunResult, commands: &[areo_actions::Command], profile: &PathProfile) -> ActionsView {
    let (dem, task, params) = (&setup.dem, &setup.task, &setup.params);
    let trace = &run.best.trace;
    let slope = areo_terrain::slope::slope_aspect(dem);
    let rgb = areo_terrain::hillshade::hillshade_rgb(dem, &slope, None, 315.0, 45.0);
    let k = dem.cols().max(dem.rows()).div_ceil(ACTIONS_VIEW_PIXELS).max(1);
    let (w, h) = (dem.cols() / k, dem.rows() / k);
    let values =
        (0..h).flat_map(|r| (0..w).map(move |c| (r * k) * dem.cols() + c * k)).map(|i| rgb[3 * i + 1]).collect();
    let pivot = params.rocker_pivot_m;
    let steps = trace
        .iter()
        .enumerate()
        .map(|(i, t)| {
            // The tool about the body reference (the rocker pivots' midpoint), turned by
            // the pitch into the profile's plane.
            let (f, u) = (t.tool_m[0] - pivot.x, t.tool_m[2] - pivot.z);
            let (sin, cos) = t.pitch_deg.to_radians().sin_cos();
            // Heading is clockwise from north: forward (sin h, cos h), left (−cos h, sin h).
            let (sin_h, cos_h) = t.heading_deg.to_radians().sin_cos();
            let (fwd, left) = ((sin_h, cos_h), (-cos_h, sin_h));
            let offset = |side: &[[f64; 3]]| {
                side.iter().map(|w| (w[0] - t.x_m) * left.0 + (w[1] - t.y_m) * left.1).sum::<f64>() / side.len() as f64
            };
            let section = |lateral: f64| -> Vec<Option<f32>> {
                let n = (2.0 * SECTION_HALF_M / SECTION_STEP_M).round() as usize;
                (0..=n)
                    .map(|j| {
                        let s = -SECTION_HALF_M + j as f64 * SECTION_STEP_M;
                        let (x, y) = (t.x_m + s * fwd.0 + lateral * left.0, t.y_m + s * fwd.1 + lateral * left.1);
                        areo_terrain::Ground::height(dem, x, y).map(|z| z as f32)
                    })
                    .collect()
            };
            ActionsViewStep {
                left_ground_m: section(offset(&t.wheels[..3])),
                right_ground_m: section(offset(&t.wheels[3..])),
                code: t.code,
                action: commands.get(i).map_or_else(String::new, |c| c.action.to_string()),
                along_m: profile.along[i + 1],
                at_m: (t.x_m, t.y_m, t.z_m),
                heading_deg: t.heading_deg,
                pitch_deg: t.pitch_deg,
                wheels_top_m: t.wheels.map(|w| (w[0], w[1])),
                wheels_profile_m: t.wheels.map(|w| profile.place(trace, i, w)),
                tool_profile_m: (profile.along[i + 1] + f * cos - u * sin, t.z_m + f * sin + u * cos),
                wheel_loads_n: t.wheel_loads_n,
                stability: t.stability,
                friction_used: t.friction_used,
                energy_wh: t.energy_wh,
                duration_s: t.duration_s,
            }
        })
        .collect();
    let extent = dem.extent();
    ActionsView {
        run: run.name.clone(),
        rover: params.name.clone(),
        mu: run.exec.mu,
        stability_floor: run.exec.stability_floor,
        wheel_radius_m: params.wheel_radius_m,
        body_half_m: run.exec.body_half_m,
        hillshade: Raster { cols: w, rows: h, values },
        // The image starts at the map's north-west corner and drops its last rows
        // and columns when they do not fill a pixel.
        map_origin_m: (extent.x_min, extent.y_max - (h * k) as f64 * dem.dy()),
        map_size_m: ((w * k) as f64 * dem.dx(), (h * k) as f64 * dem.dy()),
        start: task.start,
        target: (task.target.0, task.target.1, task.target_radius_m),
        samples: task.samples.iter().map(|s| (s.x_m, s.y_m)).collect(),
        rocks: task.rocks.iter().map(|r| (r.x_m, r.y_m, r.width_m)).collect(),
        ground: profile.ground.clone(),
        section_half_step_m: (SECTION_HALF_M, SECTION_STEP_M),
        steps,
    }
}

/// The stability margin and the friction needed along the plan.
fn trace_plots(trace: &[TraceStep], mu: f64) -> [Plot; 2] {
    let stability: Vec<(f64, f64)> =
        trace.iter().enumerate().filter_map(|(i, t)| t.stability.map(|s| ((i + 1) as f64, 100.0 * s))).collect();
    let stability = Plot::time(
        "stability",
        TimePlot {
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
    );
    let friction: Vec<(f64, f64)> = trace.iter().enumerate().map(|(i, t)| (i as f64 + 1.0, t.friction_used)).collect();
    let friction = Plot::time(
        "friction",
        TimePlot {
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
    );
    [stability, friction]
}

/// Fitness per generation and the look-ahead histogram.
fn ga_plots(report: &GaReport) -> [Plot; 2] {
    let best: Vec<(f64, f64)> = report.generations.iter().map(|g| (g.index as f64, g.best)).collect();
    let mean: Vec<(f64, f64)> = report.generations.iter().map(|g| (g.index as f64, g.mean)).collect();
    let fitness = Plot::time(
        "fitness",
        TimePlot {
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
    );
    let lookahead = Plot::histogram(
        "lookahead",
        HistogramPlot {
            title: "Look-ahead of improving crossovers".into(),
            x_label: "change in successful-prefix length, modules".into(),
            y_label: "crossovers".into(),
            bin_width: None,
            series: vec![(report.lookahead.clone(), (30, 90, 220))],
        },
    );
    [fitness, lookahead]
}
