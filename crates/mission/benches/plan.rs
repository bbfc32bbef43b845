//! TEMPEST planning on a seeded 200 × 150 DEM of 100 m cells with the Mars24 Sun and
//! terrain shadows: an initial 42-waypoint plan for a Hyperion-class rover, and a
//! re-plan after a 2-cell sensing update next to the rover. (`cargo xtask bench
//! mission` runs the LITA-sized case: 2527 × 2356 cells.)

use areo_ephemeris::{Mars24, Site, flux::Atmosphere, parse_utc};
use areo_mission::{
    ActionConfig, ActionModel, Classes, Mission, PlannerConfig, Resolution, SearchMode, Start, World, WorldConfig,
};
use areo_rover::resources::ResourceModel;
use areo_terrain::synth::{Noise, TerrainSpec};
use criterion::{Criterion, criterion_group, criterion_main};

fn world() -> World {
    world_of(200, 150)
}

/// The bench terrain's first `cols` × `rows` cells.
fn world_of(cols: usize, rows: usize) -> World {
    let dem = TerrainSpec {
        cols,
        rows,
        cell_m: 100.0,
        base_m: 0.0,
        seed: 7,
        noise: Some(Noise { amplitude_m: 150.0, wavelength_m: 30_000.0, octaves: 5, persistence: 0.45 }),
        features: vec![],
    }
    .build()
    .expect("valid terrain");
    World::new(dem, &world_config(), &Mars24).expect("valid world")
}

/// The bench world's settings: three sols from a March 2025 midnight at Gale.
fn world_config() -> WorldConfig {
    WorldConfig {
        epoch: parse_utc("2025-03-01T00:00:00Z").expect("valid time"),
        span_s: 3.0 * areo_ephemeris::SOL_S,
        sun_step_s: 120.0,
        horizon_sectors: Some(32),
        atmosphere: Atmosphere::BeerLambert { tau: 0.5 },
        site: Some(Site::new(-4.6, 137.4).expect("valid site")),
    }
}

/// The first instant the Sun climbs past 10°, s.
fn morning(world: &World) -> f64 {
    let mut t0 = 0.0;
    while !(world.sun(t0).elevation_deg > 10.0 && world.sun(t0 - 600.0).elevation_deg <= 10.0) {
        t0 += 600.0;
    }
    t0
}

/// The planner settings the benches use.
fn config() -> PlannerConfig {
    PlannerConfig {
        max_wait_s: Some(6.0 * 3600.0),
        search: SearchMode::Approximate(Classes {
            resolution: Resolution { time_s: 300.0, energy_wh: None },
            goal_times: 8,
            ..Classes::default()
        }),
        ..PlannerConfig::default()
    }
}

fn plan(c: &mut Criterion) {
    let world = world();
    let t0 = morning(&world);
    let model = ActionModel::new(ResourceModel::hyperion(), ActionConfig::default());
    let start = Start { cell: world.cell(20, 50), t_min: t0, t_max: t0 + 600.0, energy_wh: 800.0 };
    let goal = [world.cell(60, 70)];
    let config = config();
    let mut g = c.benchmark_group("tempest_200x150");
    g.sample_size(10);
    g.bench_function("initial_plan_40_cells", |b| {
        b.iter(|| Mission::plan(&world, &model, config.clone(), start, &goal).expect("a plan").1.waypoints.len())
    });
    // The same plan counted for a progress display: the meter's cost per expansion.
    let metered = PlannerConfig { meter: areo_mission::ExpansionMeter::counting(), ..config.clone() };
    g.bench_function("initial_plan_40_cells_metered", |b| {
        b.iter(|| Mission::plan(&world, &model, metered.clone(), start, &goal).expect("a plan").1.waypoints.len())
    });
    let (mut mission, first) = Mission::plan(&world, &model, config.clone(), start, &goal).expect("a plan");
    let (c0, r0) = first.waypoints[2].col_row;
    let cells = [world.cell(c0, r0 + 1), world.cell(c0 + 1, r0 + 1)];
    g.bench_function("replan_2_cells_blocked_then_cleared", |b| {
        b.iter(|| {
            let changed = world.set_blocked(&cells, true);
            let a = mission.replan(&changed).expect("a plan").cost;
            let changed = world.set_blocked(&cells, false);
            a + mission.replan(&changed).expect("a plan").cost
        })
    });
    g.finish();
}

/// Plans under uncertainty on the same world: the chance-constrained plan (0.95, 10 %
/// systematic departures) beside the deterministic one, and 1000 open-loop executions
/// of it (target ≤ 10 s on 2 cores; the chance-constrained plan ≤ 3× the deterministic
/// plan's time).
fn uncertainty(c: &mut Criterion) {
    use areo_mission::uncertainty::{MonteCarlo, Uncertainty, open_loop};
    let world = world();
    let t0 = morning(&world);
    let model = ActionModel::new(ResourceModel::hyperion(), ActionConfig::default());
    let u = Uncertainty { drive_time_sigma: 0.1, power_draw_sigma: 0.1, solar_sigma: 0.1, ..Uncertainty::default() };
    let chance = model.clone().with_margins(u.margins());
    let start = Start { cell: world.cell(20, 50), t_min: t0, t_max: t0 + 600.0, energy_wh: 800.0 };
    let goal = [world.cell(60, 70)];
    let config = config();
    let mut g = c.benchmark_group("tempest_uncertainty");
    g.sample_size(10);
    g.bench_function("deterministic_plan", |b| {
        b.iter(|| Mission::plan(&world, &model, config.clone(), start, &goal).expect("a plan").1.waypoints.len())
    });
    g.bench_function("chance_constrained_plan_0p95", |b| {
        b.iter(|| Mission::plan(&world, &chance, config.clone(), start, &goal).expect("a plan").1.waypoints.len())
    });
    // The terrain's height error in the plan: 10 error clones (1 m RMS over 1 km, as a
    // MOLA-class map might be wrong), built, and the plan made on their envelope.
    let uncertain = Uncertainty { terrain_sigma_m: 1.0, terrain_correlation_m: 1000.0, terrain_plan_clones: 10, ..u };
    let clones =
        || areo_mission::uncertainty::planning_clones(&uncertain, &world, &world_config(), &Mars24).expect("clones");
    g.bench_function("envelope_of_10_clones_built", |b| {
        b.iter(|| World::envelope(&world, &clones()).expect("an envelope").terrain_members())
    });
    let envelope = World::envelope(&world, &clones()).expect("an envelope");
    g.bench_function("chance_constrained_plan_0p95_on_10_clones", |b| {
        b.iter(|| Mission::plan(&envelope, &chance, config.clone(), start, &goal).expect("a plan").1.waypoints.len())
    });
    let (_, plan) = Mission::plan(&world, &chance, config.clone(), start, &goal).expect("a plan");
    let mc = MonteCarlo { runs: 1000, seed: 1 };
    g.bench_function("open_loop_1000_runs", |b| {
        b.iter(|| open_loop(&plan, &model, &world, start, &u, &mc).expect("valid").len())
    });
    g.finish();
}

/// The Pareto front in (arrival, energy used, margin) against the plan it goes with, on a
/// 24 × 16 corner of the bench world (a 450 m drive, 4 goal instants, 1 h waits).
fn front(c: &mut Criterion) {
    let world = world_of(24, 16);
    let t0 = morning(&world);
    let model = ActionModel::new(ResourceModel::hyperion(), ActionConfig::default());
    let start = Start { cell: world.cell(5, 8), t_min: t0, t_max: t0 + 600.0, energy_wh: 300.0 };
    let goal = [world.cell(9, 10)];
    let config = PlannerConfig {
        max_wait_s: Some(3600.0),
        search: SearchMode::Approximate(Classes { goal_times: 4, ..*config().search.classes().expect("approximate") }),
        ..config()
    };
    let mut g = c.benchmark_group("tempest_front");
    g.sample_size(10);
    g.bench_function("plan", |b| {
        b.iter(|| Mission::plan(&world, &model, config.clone(), start, &goal).expect("a plan").1.waypoints.len())
    });
    let (mission, _) = Mission::plan(&world, &model, config.clone(), start, &goal).expect("a plan");
    g.bench_function("pareto_front_1wh", |b| b.iter(|| mission.pareto_front(1.0).expect("a front").plans.len()));
    g.finish();
}

/// The terrain-class lookups a plan makes: the initial plan on the same world with no
/// classes, and with every cell of one class whose factors are the rover's own (the
/// same plan, expansion for expansion, so the difference is the lookups), and with a
/// class map of sand and bedrock (a different plan, for scale).
fn ground(c: &mut Criterion) {
    use areo_mission::{ClassMap, TerrainClass};
    use std::sync::Arc;
    let plain = world();
    let t0 = morning(&plain);
    let model = ActionModel::new(ResourceModel::hyperion(), ActionConfig::default());
    let start = Start { cell: plain.cell(20, 50), t_min: t0, t_max: t0 + 600.0, energy_wh: 800.0 };
    let goal = [plain.cell(60, 70)];
    let class = |name: &str, speed: f64, power: f64| TerrainClass {
        name: name.into(),
        speed_factor: speed,
        power_factor: power,
        max_slope_deg: None,
    };
    let mut nominal = world();
    let cells = nominal.cells();
    nominal.set_ground(Arc::new(ClassMap::new(vec![class("nominal", 1.0, 1.0)], vec![0; cells]).unwrap())).unwrap();
    let mut mixed = world();
    let sand_bedrock = (0..cells as u32).map(|c| u8::from((mixed.col_row(c).0 / 10).is_multiple_of(2))).collect();
    let classes = vec![class("sand", 0.6, 1.8), class("bedrock", 1.0, 0.9)];
    mixed.set_ground(Arc::new(ClassMap::new(classes, sand_bedrock).unwrap())).unwrap();
    let config = config();
    let a = Mission::plan(&plain, &model, config.clone(), start, &goal).expect("a plan").1;
    let b = Mission::plan(&nominal, &model, config.clone(), start, &goal).expect("a plan").1;
    assert_eq!((a.expansions, a.cost), (b.expansions, b.cost), "one class of the rover's own factors changes nothing");
    let mut g = c.benchmark_group("tempest_ground");
    g.sample_size(10);
    for (name, world) in [("no_classes", &plain), ("one_nominal_class", &nominal), ("sand_and_bedrock", &mixed)] {
        g.bench_function(name, |b| {
            b.iter(|| Mission::plan(world, &model, config.clone(), start, &goal).expect("a plan").1.waypoints.len())
        });
    }
    g.finish();
}

criterion_group!(benches, plan, uncertainty, front, ground);
criterion_main!(benches);
