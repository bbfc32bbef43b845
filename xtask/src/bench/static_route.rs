//! `cargo xtask bench static`: a route on which nothing depends on time, planned on a
//! tick. On crops of the real MOLA Gale map (463 m cells) the rover drives by day or
//! night, its battery far larger than the route needs, across the middle of the crop
//! (from its 3/8 point to the reachable cell nearest its 5/8 point) under the Time
//! objective: the exact tick search (60 s, drives settling to ticks)
//! at horizons of 50 to 300 h, beside a plain Dijkstra (the `pathfinding` crate) over the
//! same drives, each lasting what it lasts in a tick plan (whole ticks; the last one
//! needs no settle, so the tick plan may be up to one tick shorter). The tick search's
//! work should not grow with the horizon.

use std::path::Path;
use std::time::Instant;

use areo_mission::exact::{ExactGoal, ExactQuery};
use areo_mission::{ActionConfig, ActionModel, Objective, Start, World};

const TICK_S: f64 = 60.0;

fn world(root: &Path, size: usize, horizon_h: f64) -> Result<World, String> {
    let path = root.join("../shared/data/dem/gale_mola_463m.tif");
    let map = areo_terrain::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let size = size.min(map.cols()).min(map.rows());
    let (c0, r0) = ((map.cols() - size) / 2, (map.rows() - size) / 2);
    let dem = map.crop(c0, r0, size, size).map_err(|e| e.to_string())?;
    let (x, y) = dem.cell_center(size / 2, size / 2);
    let (lat, lon) = dem.geographic(x, y).ok_or_else(|| format!("{}: not georeferenced", path.display()))?;
    let config = areo_mission::WorldConfig {
        epoch: areo_ephemeris::parse_utc("2012-08-06T12:00:00Z").map_err(|e| e.to_string())?,
        span_s: horizon_h * 3600.0,
        sun_step_s: 600.0,
        horizon_sectors: None,
        atmosphere: areo_ephemeris::flux::Atmosphere::Baseline { peak_w_m2: 500.0 },
        site: Some(areo_ephemeris::Site::new(lat, lon).map_err(|e| e.to_string())?),
    };
    World::new(dem, &config, &areo_ephemeris::Mars24).map_err(|e| e.to_string())
}

/// The passable cell nearest (`col`, `row`) with a gentle slope.
fn passable_near(world: &World, col: usize, row: usize) -> u32 {
    (0..world.cols() * world.rows())
        .map(|i| i as u32)
        .filter(|&c| world.passable(c) && world.slope_deg(c) < 15.0)
        .min_by_key(|&c| {
            let (x, y) = world.col_row(c);
            (x as i64 - col as i64).pow(2) + (y as i64 - row as i64).pow(2)
        })
        .unwrap_or(0)
}

/// The cell reachable from `start` nearest (`col`, `row`).
fn reachable_near(world: &World, model: &ActionModel, start: u32, col: usize, row: usize) -> u32 {
    let reached = pathfinding::directed::bfs::bfs_reach(start, |&cell| {
        (0..8u8).filter_map(|k| model.drive_geometry(world, cell, k).ok()).map(|g| g.to).collect::<Vec<_>>()
    });
    reached
        .min_by_key(|&c| {
            let (x, y) = world.col_row(c);
            (x as i64 - col as i64).pow(2) + (y as i64 - row as i64).pow(2)
        })
        .unwrap_or(start)
}

/// The least sum of the drives' tick durations (whole ticks, ms) from `start` to `goal`.
fn dijkstra(world: &World, model: &ActionModel, start: u32, goal: u32) -> Option<(Vec<u32>, u64)> {
    pathfinding::directed::dijkstra::dijkstra(
        &start,
        |&cell| {
            (0..8u8)
                .filter_map(|k| model.drive_geometry(world, cell, k).ok())
                .map(|g| (g.to, ((g.duration_s / TICK_S - 1e-9).ceil() * TICK_S * 1000.0) as u64))
                .collect::<Vec<_>>()
        },
        |&cell| cell == goal,
    )
}

pub(crate) fn run(root: &Path) -> Result<bool, String> {
    println!("static route on the MOLA Gale map (463 m cells), Time objective, no daylight rule, tick {TICK_S} s:");
    let mut rover = areo_rover::resources::ResourceModel::hyperion();
    rover.battery.capacity_wh = 1.0e7;
    let mut actions = ActionConfig { wait_step_s: Some(TICK_S), ..Default::default() };
    actions.drive.daylight = false;
    actions.drive.sun_in_camera = false;
    let model = ActionModel::new(rover, actions);
    for size in [128, 256, 897] {
        for horizon_h in [50.0, 150.0, 300.0] {
            let world = world(root, size, horizon_h)?;
            // A route across the middle of the crop, between its 3/8 and 5/8 points.
            let start_cell = passable_near(&world, size * 3 / 8, size * 3 / 8);
            let goal_cell = reachable_near(&world, &model, start_cell, size * 5 / 8, size * 5 / 8);
            let clock = Instant::now();
            let reference = dijkstra(&world, &model, start_cell, goal_cell);
            let dijkstra_s = clock.elapsed().as_secs_f64();
            let query = ExactQuery {
                world: &world,
                model: &model,
                start: Start { cell: start_cell, t_min: 0.0, t_max: 0.0, energy_wh: 5.0e6 },
                goals: vec![ExactGoal { cell: goal_cell, open_s: 0.0, close_s: world.span_s() }],
                goal_energy_wh: 0.0,
                objective: Objective::Time,
                max_labels: 50_000_000,
                settle: true,
            };
            let clock = Instant::now();
            let out = query.solve();
            let tick_s = clock.elapsed().as_secs_f64();
            let reference_h = reference.as_ref().map(|(path, ms)| (path.len(), *ms as f64 / 3.6e6));
            match (&out.plan, reference_h) {
                (Some((cost, steps)), Some((cells, hours))) => println!(
                    "  {size}² crop, horizon {horizon_h:.0} h: tick search {tick_s:.3} s, {} expansions, {} labels, \
                     {:.2} h over {} drives; Dijkstra {dijkstra_s:.3} s, {:.2} h over {} drives; {:.1} × the \
                     Dijkstra's time, cost difference {:.0} s",
                    out.expanded,
                    out.kept,
                    cost / 3600.0,
                    steps.iter().filter(|s| matches!(s.action, areo_mission::Action::Drive(_))).count(),
                    hours,
                    cells - 1,
                    tick_s / dijkstra_s.max(1e-9),
                    cost - hours * 3600.0
                ),
                (plan, reference) => println!(
                    "  {size}² crop, horizon {horizon_h:.0} h: tick search {tick_s:.3} s, plan {:?}, stopped {}; \
                     Dijkstra {reference:?}",
                    plan.as_ref().map(|p| p.0),
                    out.stopped
                ),
            }
        }
    }
    traverses(root)?;
    four_sol_traverses(root)?;
    Ok(true)
}

/// Multi-sol single-goal traverses on the shipped 64² crop of the Gale map (the
/// gale-mola-traverse scenario, its second goal alone, 13.7 km away, a 120 h horizon,
/// on its 60 s tick, no simulation): each must plan, or be proven unreachable, in
/// seconds. The variants: as shipped (600 Wh, L + B), under the Time objective, from the
/// same start with 120 Wh and with 10 Wh (the default `max_wait_s`: the battery must be
/// charged on the way), and with a horizon too short for the drive (a proof).
fn traverses(root: &Path) -> Result<(), String> {
    use areo_scenario::format::planner::ObjectiveSpec;
    println!("multi-sol traverses on the 64² Gale crop (463 m cells), one goal 13.7 km away, tick 60 s:");
    type Change = fn(&mut areo_scenario::format::TempestJob);
    let variants: [(&str, Change); 5] = [
        ("600 Wh, L + B", |_| {}),
        ("600 Wh, Time", |job| job.planner.objective = ObjectiveSpec::Time),
        ("120 Wh, default max_wait_s", |job| {
            job.start_battery_above_floor_wh = 120.0;
            job.planner.max_wait_s = None;
        }),
        ("10 Wh, default max_wait_s", |job| {
            job.start_battery_above_floor_wh = 10.0;
            job.planner.max_wait_s = None;
        }),
        ("a 10 h horizon", |job| job.horizon_h = 10.0),
    ];
    for (what, change) in variants {
        let (outcome, wall) = super::run_scenario_with(root, "gale-mola-traverse", false, |job| {
            job.goals.remove(0);
            job.simulate = None;
            job.horizon_h = 120.0;
            change(job);
        })?;
        let fact = |name: &str| super::number(&outcome, name);
        match &outcome.failure {
            None => println!(
                "  {what}: {:.1} h plan, {} expansions, {wall:.2} s",
                fact("initial_plan_duration_h"),
                fact("initial_plan_expansions")
            ),
            Some(failure) => {
                let verdict = failure.to_string();
                let proven = if verdict.contains("proven") { "proven" } else { "not proven" };
                println!(
                    "  {what}: no plan ({proven}), {} expansions at the settings, {} in all with the probes \
                     naming what binds, {wall:.2} s",
                    fact("no_plan_planning_expansions"),
                    fact("no_plan_expansions")
                );
            }
        }
    }
    Ok(())
}

/// The four-sol traverse on crops of the Gale map around gale-mola-traverse's: from its
/// start to a goal 14.8 km south-west, a 200 h horizon, four sols of waiting allowed,
/// on its 60 s tick with no simulation; from 600 Wh (enough for the drive) and from
/// 120 Wh (charged on the way, a battery–time trade-off at every cell), under L + B
/// and Time, and from 120 Wh over a horizon too short (a proof); on the shipped 64²
/// crop (columns and rows 400–463 of the map) and on the 128² and 256² crops with the
/// same centre, the route unmoved on the ground.
fn four_sol_traverses(root: &Path) -> Result<(), String> {
    use areo_scenario::format::{GoalSpec, TerrainSource, Truth, planner::ObjectiveSpec};
    let path = root.join("../shared/data/dem/gale_mola_463m.tif");
    let map = areo_terrain::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let dir = std::env::temp_dir().join(format!("areo-bench-gale-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    println!("four-sol traverses on Gale crops (463 m cells), one goal 14.8 km away, 200 h, tick 60 s:");
    for size in [64usize, 128, 256] {
        let first = 432 - size / 2;
        let crop = map.crop(first, first, size, size).map_err(|e| e.to_string())?;
        let file = dir.join(format!("gale_mola_crop_{size}.tif"));
        areo_terrain::geotiff::write(&crop, &file).map_err(|e| format!("{}: {e}", file.display()))?;
        let cells = ((size - 64) / 2) as f64;
        let (dx, dy) = (cells * crop.dx(), cells * crop.dy());
        // The last two: a 52 h horizon, shorter than the 54.3 h the route needs from
        // 120 Wh, so "unreachable" must be proven.
        for (battery_wh, objective, name, horizon_h) in [
            (600.0, ObjectiveSpec::Energy, "L + B", 200.0),
            (600.0, ObjectiveSpec::Time, "Time", 200.0),
            (120.0, ObjectiveSpec::Energy, "L + B", 200.0),
            (120.0, ObjectiveSpec::Time, "Time", 200.0),
            (120.0, ObjectiveSpec::Energy, "L + B", 52.0),
            (120.0, ObjectiveSpec::Time, "Time", 52.0),
        ] {
            let (outcome, wall) = super::run_scenario_with(root, "gale-mola-traverse", false, |job| {
                job.terrain = TerrainSource::File(file.display().to_string());
                job.truth = Truth::Map;
                job.simulate = None;
                job.regions.clear();
                job.horizon_h = horizon_h;
                job.start.x_m += dx;
                job.start.y_m += dy;
                job.start_battery_above_floor_wh = battery_wh;
                job.goals = vec![GoalSpec { name: "far".into(), x_m: 8000.0 + dx, y_m: 14500.0 + dy }];
                job.planner.max_wait_s = Some(4.0 * 88775.0);
                job.planner.objective = objective;
            })?;
            let fact = |name: &str| super::number(&outcome, name);
            let verdict = match &outcome.failure {
                None => format!(
                    "{:.1} h plan, {} expansions",
                    fact("initial_plan_duration_h"),
                    fact("initial_plan_expansions")
                ),
                Some(failure) => format!(
                    "no plan ({}), {} expansions at the settings, {} with the probes naming what binds",
                    if failure.to_string().contains("proven") { "proven" } else { "not proven" },
                    fact("no_plan_planning_expansions"),
                    fact("no_plan_expansions")
                ),
            };
            // (A run without a plan reports no search graphs.)
            let graphs = fact("peak_search_mb");
            let graphs = if graphs.is_finite() { format!(", search graphs {graphs:.0} MB") } else { String::new() };
            println!("  {size}², {battery_wh:.0} Wh, {name}, {horizon_h:.0} h: {verdict}{graphs}, {wall:.2} s");
        }
    }
    std::fs::remove_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))
}
