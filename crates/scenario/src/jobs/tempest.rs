//! The TEMPEST job: build the believed and true worlds, plan (and simulate), and
//! write plan.json, plan.csv, route.geojson, replans.csv, executed.csv and the plots.

use std::path::Path;
use std::time::Instant;

use areo_ephemeris::events::night_intervals;
use areo_ephemeris::flux::Atmosphere;
use areo_ephemeris::{HorizonMask, Site, format_utc, parse_utc};
use areo_mission::{
    Action, ActionModel, Error as MissionError, Mission, MissionPlan, PlanKind, SimReport, SimStatus, Simulation,
    Start, World, WorldConfig, simulate,
};
use areo_rover::resources::ResourceModel;
use areo_terrain::Dem;
use hifitime::Duration;

mod chance;
mod classes;
mod figures;
mod front;
mod layers;
mod no_go;
mod overlay;
mod tables;
mod view;

use figures::*;
use tables::*;

use crate::error::{Error, Result};
use crate::format::{ScenarioFile, TempestJob, TerrainSource, Truth};
use crate::jobs::RunOptions;
use crate::outcome::Failure;
use crate::report::Report;
use crate::report::plots::{Marker, Plot, RoutePlot, Series, TimePlot};
use crate::report::tempest::{NoPlanFigures, TempestReport};
use areo_mission::{contact, metrics};

/// The map's south-west corner in map coordinates: scenario positions are relative
/// to it.
#[derive(Debug, Clone, Copy)]
struct Frame {
    x0: f64,
    y0: f64,
}

impl Frame {
    fn of(dem: &Dem) -> Frame {
        let e = dem.extent();
        Frame { x0: e.x_min, y0: e.y_min }
    }
    fn to_map(self, x: f64, y: f64) -> (f64, f64) {
        (self.x0 + x, self.y0 + y)
    }
    fn to_local(self, (x, y): (f64, f64)) -> (f64, f64) {
        (x - self.x0, y - self.y0)
    }
}

fn scenario_error(file: &ScenarioFile, field: impl Into<String>, message: impl Into<String>) -> Error {
    file.error_at(&field.into(), message)
}

/// The scenario field behind a planner's `Config` error field.
fn planner_field(field: &str) -> String {
    match field {
        "start" | "goals" | "site" | "truth" => format!("job.{field}"),
        f if f.starts_with("pareto_front") => format!("job.{f}"),
        "span_s" => "job.horizon_h".into(),
        "sun_step_s" => "job.sun_step_min".into(),
        other => format!("job.planner.{other}"),
    }
}

/// The terrain a job plans on: the whole map, or a region cut from it.
enum Terrain {
    Whole(Dem),
    Region { region: areo_terrain::tiles::Region, frame: Frame },
}

/// Cuts `job.plan_region` from the job's map: a GeoTIFF a window at a time (other
/// formats, and synthesised maps, built whole first), with the whole map's slopes and
/// the horizons its lowest Sun needs.
fn cut_region(
    job: &TempestJob,
    spec: &crate::format::PlanRegionSpec,
    file: &ScenarioFile,
    site: &Site,
    sectors: usize,
    place: impl Fn(Dem) -> Result<Dem>,
) -> Result<Terrain> {
    use areo_terrain::tiles::{RegionHorizon, ShadowHalo, Source, region, relief};
    let at = |message: String| scenario_error(file, "job.plan_region", message);
    let tiff = match &job.terrain {
        TerrainSource::File(rel) => {
            let path = file.path.parent().unwrap_or(Path::new(".")).join(rel);
            if areo_terrain::DemFormat::of(&path) == Some(areo_terrain::DemFormat::GeoTiff) {
                let w = areo_terrain::geotiff::Windows::open(&path, 256 << 20)
                    .map_err(|e| Error::from(e).referenced_by(&file.path, "job.terrain"))?;
                // A map without a projection is placed at the site: read it whole.
                (w.grid().georef.projection != areo_terrain::Projection::Local).then_some(w)
            } else {
                None
            }
        }
        TerrainSource::Synth(_) => None,
    };
    let mut src: Box<dyn FnMut(usize, usize, usize, usize) -> areo_terrain::Result<Dem>>;
    let grid;
    match tiff {
        Some(mut w) => {
            grid = w.grid();
            let [x_min, x_max] = [grid.x0, grid.x0 + grid.cols as f64 * grid.dx];
            site_on_map(file, site, &grid.georef, [x_min, x_max, grid.y_top - grid.rows as f64 * grid.dy, grid.y_top])?;
            src = Box::new(move |c, r, cols, rows| w.window(c, r, cols, rows));
        }
        None => {
            let mut dem = place(load_terrain(&job.terrain, file, "job.terrain")?)?;
            grid = Source::grid(&dem);
            src = Box::new(move |c, r, cols, rows| Source::window(&mut dem, c, r, cols, rows));
        }
    }
    let mut src = Windowed { grid, read: src.as_mut() };
    let frame = Frame { x0: grid.x0, y0: grid.y_top - grid.rows as f64 * grid.dy };
    // The region's cells: those whose centres lie inside it.
    let span = |(lo, hi): (f64, f64), cell: f64, n: usize, name: &str| -> Result<(usize, usize)> {
        let first = ((lo / cell - 0.5).ceil().max(0.0)) as usize;
        let end = (((hi / cell - 0.5).floor() + 1.0).max(0.0) as usize).min(n);
        if first >= end {
            return Err(at(format!("{name} ({lo}, {hi}) m holds no cell centre of the {:.0} m map", n as f64 * cell)));
        }
        Ok((first, end - first))
    };
    let (c0, cols) = span(spec.x_m, grid.dx, grid.cols, "x_m")?;
    let (s0, rows) = span(spec.y_m, grid.dy, grid.rows, "y_m")?;
    // Rows count from the north.
    let r0 = grid.rows - s0 - rows;
    let horizon = if sectors > 0 {
        let Some(rel) = relief(&mut src, 1024)? else {
            return Err(at("the map has no cell with data".into()));
        };
        let halo = ShadowHalo::new(rel, &grid, spec.lowest_sun_deg)?;
        Some(RegionHorizon {
            sectors,
            // The planner's curvature, so that the horizons are the whole map world's.
            curvature: areo_mission::curvature_of(job.body.model()),
            lowest_deg: spec.lowest_sun_deg,
            halo,
        })
    } else {
        None
    };
    let region = region(&mut src, (c0, r0, cols, rows), horizon)?;
    Ok(Terrain::Region { region, frame })
}

/// A window reader as a [`areo_terrain::tiles::Source`].
struct Windowed<'a> {
    grid: areo_terrain::geotiff::Grid,
    read: &'a mut dyn FnMut(usize, usize, usize, usize) -> areo_terrain::Result<Dem>,
}

impl areo_terrain::tiles::Source for Windowed<'_> {
    fn grid(&self) -> areo_terrain::geotiff::Grid {
        self.grid
    }
    fn window(&mut self, col0: usize, row0: usize, cols: usize, rows: usize) -> areo_terrain::Result<Dem> {
        (self.read)(col0, row0, cols, rows)
    }
}

fn load_terrain(source: &TerrainSource, file: &ScenarioFile, field: &str) -> Result<Dem> {
    Ok(match source {
        TerrainSource::Synth(spec) => spec.build()?,
        TerrainSource::File(rel) => crate::terrain::read_job_dem(file, Path::new(rel), field)?,
    })
}

/// Peak resident memory of this process, MB of 10⁶ bytes like every other memory
/// figure (Linux), if known. VmHWM is in KiB.
fn peak_memory_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0 / 1e6)
}

/// Bytes the believed and the true worlds hold, MB: the truth counted only where it is
/// a world of its own (it is the map itself when `truth` is `Map`).
fn worlds_mb(ctx: &Context<'_>) -> f64 {
    let truth = if std::ptr::eq(ctx.world, ctx.truth) { 0 } else { ctx.truth.bytes() };
    (ctx.world.bytes() + truth) as f64 / 1e6
}

/// The worlds, rover and places a TEMPEST job plans with, built from its scenario.
struct Prepared {
    world: World,
    /// The true world when it differs from the believed one.
    truth: Option<World>,
    /// How the worlds were built (for the Monte Carlo's terrain clones).
    config: WorldConfig,
    model: ActionModel,
    frame: Frame,
    start: Start,
    goals: Vec<u32>,
    /// Slope, horizon maps and Sun table, s.
    precalc_s: f64,
    /// Lines saying what the world approximates (a cut region, one-byte horizons).
    notes: Vec<String>,
    /// The map file's CRS when areo does not read its projection (a local frame).
    crs_not_read: Option<String>,
    /// The no-go mask as applied, when the job has one.
    no_go: Option<no_go::NoGo>,
    /// The terrain classes' figures (cells per class), when the job has them.
    classes: Option<crate::report::tempest::ClassFigures>,
}

/// What planning (or simulating) gave.
enum Run {
    /// No plan reaches the goals from the start.
    Unreachable { binding: areo_mission::Binding, message: String, proven: bool, work: NoPlanWork },
    /// The searches stopped at the work (`memory: false`) or memory budget before they
    /// had an answer; `message` names the file and the flag.
    Stopped { memory: bool, message: String, work: NoPlanWork },
    /// A plan, its wall time (s), the search graphs' bytes and the labels they hold
    /// after it.
    Plan { plan: MissionPlan, seconds: f64, search_bytes: u64, labels: u64 },
    /// A simulated run with its re-plans.
    Simulated(SimReport),
}

/// What a "no plan" verdict cost: a planner waiting minutes for one wants to know
/// where they went.
#[derive(Debug, Clone, Default)]
struct NoPlanWork {
    /// Wall time from the first search to the verdict, s.
    seconds: f64,
    /// Label expansions of every search: the plan's, its fallbacks', the probes'.
    expansions: u64,
    /// Those of each phase, in [`areo_mission::ExpansionMeter::phases_seen`]'s order:
    /// "planning" (the settings and their fallbacks), then the relaxed probes that
    /// name the binding constraint.
    phases: Vec<(&'static str, u64)>,
}

impl NoPlanWork {
    /// The work `meter` counted since `start`.
    fn since(start: Instant, meter: &areo_mission::ExpansionMeter) -> NoPlanWork {
        NoPlanWork {
            seconds: start.elapsed().as_secs_f64(),
            expansions: meter.expansions(),
            phases: meter.expansions_by_phase(),
        }
    }
}

/// What a TEMPEST job computed: the prepared worlds, the run, the haven map (off Mars)
/// and the process's peak memory. The public [`TempestReport`], the summary and the
/// files are made from it.
struct Computed {
    prepared: Prepared,
    run: Run,
    /// The chance-constrained plan's comparison and Monte Carlo, with `uncertainty`.
    chance: Option<chance::Chance>,
    /// The Pareto front, with `pareto_front`.
    front: Option<areo_mission::ParetoFront>,
    havens: Option<contact::Havens>,
    peak_memory_mb: Option<f64>,
}

/// Runs a TEMPEST job: prepare, compute, then the report (and why it failed, when it
/// did).
pub(crate) fn run(job: &TempestJob, file: &ScenarioFile, opts: RunOptions<'_>) -> Result<(Report, Option<Failure>)> {
    let prepared = prepare(job, file, opts)?;
    let computed = compute(job, file, opts, prepared)?;
    let ctx = computed.context(job, &file.name);
    report(&ctx, &computed)
}

/// Refuses a site off a georeferenced map: the Sun and the Earth are computed at the
/// site, so a mistyped one (a longitude's sign, a swapped latitude) would light the map
/// with another place's sky. The map's own extent, widened by a tenth of its size each
/// way, is allowed.
fn site_on_map(file: &ScenarioFile, site: &Site, georef: &areo_terrain::Georef, extent: [f64; 4]) -> Result<()> {
    let [x_min, x_max, y_min, y_max] = extent;
    let Some((x, y)) = georef.projection.from_geographic(&georef.surface, site.lat_deg(), site.lon_east_deg()) else {
        return Ok(());
    };
    let (mx, my) = (0.1 * (x_max - x_min), 0.1 * (y_max - y_min));
    let (dx, dy) = ((x_min - mx - x).max(x - x_max - mx).max(0.0), (y_min - my - y).max(y - y_max - my).max(0.0));
    if dx == 0.0 && dy == 0.0 {
        return Ok(());
    }
    let middle = georef.projection.to_geographic(&georef.surface, 0.5 * (x_min + x_max), 0.5 * (y_min + y_max));
    let (lat, lon) = middle.unwrap_or((f64::NAN, f64::NAN));
    // How far, along the sphere, from the map's middle.
    let (p1, p2) = (site.lat_deg().to_radians(), lat.to_radians());
    let h = ((p2 - p1) / 2.0).sin().powi(2)
        + p1.cos() * p2.cos() * ((lon - site.lon_east_deg()).to_radians() / 2.0).sin().powi(2);
    let km = 2.0 * georef.surface.equatorial_radius_m * h.sqrt().min(1.0).asin() / 1000.0;
    Err(scenario_error(
        file,
        "job.site",
        format!(
            "({:.4}°, {:.4}°E) is off the map, {km:.1} km from its middle at ({lat:.4}°, {lon:.4}°E): the Sun and \
             the Earth are computed at the site, so it must be on the map (allowed: within its extent and a tenth \
             of its size around it)",
            site.lat_deg(),
            site.lon_east_deg(),
        ),
    ))
}

/// The job's terrain, placed at the site (a georeferenced map must hold the site).
fn prepare_terrain(job: &TempestJob, file: &ScenarioFile, site: &Site) -> Result<Terrain> {
    let place = |d: Dem| -> Result<Dem> {
        if d.georef().projection != areo_terrain::Projection::Local {
            let e = d.extent();
            site_on_map(file, site, d.georef(), [e.x_min, e.x_max, e.y_min, e.y_max])?;
        }
        Ok(d.placed_at(job.body.model().reference_surface(), site.lat_deg(), site.lon_east_deg())?)
    };
    Ok(match &job.plan_region {
        None => Terrain::Whole(place(load_terrain(&job.terrain, file, "job.terrain")?)?),
        Some(spec) => cut_region(job, spec, file, site, job.horizon_sectors, place)?,
    })
}

/// The true terrain when the job simulates on another than its map, placed at the site
/// on the map's grid.
fn true_terrain(job: &TempestJob, file: &ScenarioFile, site: &Site, terrain: &Terrain) -> Result<Option<Dem>> {
    let place = |d: Dem| d.placed_at(job.body.model().reference_surface(), site.lat_deg(), site.lon_east_deg());
    Ok(match (&job.truth, terrain) {
        (Truth::Map, _) | (_, Terrain::Region { .. }) => None,
        (Truth::AddFeatures(features), Terrain::Whole(map_dem)) => {
            let features: Vec<_> = features.iter().map(crate::format::synth::FeatureSpec::to_feature).collect();
            Some(areo_terrain::synth::add_features(map_dem, &features)?)
        }
        (Truth::Terrain(source), Terrain::Whole(map_dem)) => {
            let t = place(load_terrain(source, file, "job.truth")?)?;
            if (t.cols(), t.rows()) != (map_dem.cols(), map_dem.rows()) {
                return Err(scenario_error(
                    file,
                    "job.truth",
                    format!(
                        "the true terrain is {}×{} cells and the map {}×{}: they must share one grid",
                        t.cols(),
                        t.rows(),
                        map_dem.cols(),
                        map_dem.rows()
                    ),
                ));
            }
            Some(t)
        }
    })
}

/// The rover's resources: the job's rover file or Hyperion, with the job's battery
/// and the body's gravity unless the file gives one.
fn load_rover(job: &TempestJob, file: &ScenarioFile) -> Result<ResourceModel> {
    let mut rover = match &job.rover {
        None => ResourceModel::hyperion(),
        Some(rel) => {
            crate::format::rover_files::load_resources(&file.path.parent().unwrap_or(Path::new(".")).join(rel))
                .map_err(|e| e.referenced_by(&file.path, "job.rover"))?
        }
    };
    if let Some(c) = job.battery_capacity_wh {
        rover.battery.capacity_wh = c;
    }
    rover.locomotor.gravity_m_s2.get_or_insert(job.body.model().surface_gravity_m_s2());
    Ok(rover)
}

/// What the map approximates, said before its world is built: a CRS whose projection
/// areo does not read (returned too, for the facts) and a region cut from it.
fn map_notes(job: &TempestJob, file: &ScenarioFile, terrain: &Terrain) -> (Vec<String>, Option<String>) {
    let mut notes = Vec::new();
    let crs_not_read = match &job.terrain {
        TerrainSource::File(rel) => {
            crate::terrain::crs_not_read(&file.path.parent().unwrap_or(Path::new(".")).join(rel))
        }
        TerrainSource::Synth(_) => None,
    };
    if let Some(crs) = &crs_not_read {
        notes.push(format!(
            "map CRS: {crs}, a projection areo does not read; the map is a local frame placed at the site \
             (equirectangular there), so outputs are not in its CRS"
        ));
    }
    if let (Terrain::Region { region, .. }, Some(spec)) = (terrain, &job.plan_region) {
        notes.push(format!(
            "planning region of {} × {} cells cut from the map with its slopes and horizons (horizons below {}° stored as {}°)",
            region.dem.cols(),
            region.dem.rows(),
            spec.lowest_sun_deg,
            spec.lowest_sun_deg
        ));
    }
    (notes, crs_not_read)
}

/// A polar map whose central meridian is not the site's, said as what the Sun's and the
/// Earth's azimuths on the map were turned by.
fn grid_north_note(world: &World) -> Option<String> {
    let north = world.true_north_on_grid_deg();
    (north.abs() >= 0.005).then(|| {
        format!(
            "map grid: true north at the site is {north:.2}° clockwise of the grid's north (its central meridian is \
             not the site's); the Sun's and the Earth's azimuths are turned onto the grid"
        )
    })
}

/// Builds the worlds (after the budget check), the action model and the start and goal
/// cells.
fn prepare(job: &TempestJob, file: &ScenarioFile, opts: RunOptions<'_>) -> Result<Prepared> {
    let site = Site::on(job.body.model(), job.site.lat_deg, job.site.lon_east_deg)?;
    let epoch = parse_utc(&job.start_utc)?;
    let clock = Instant::now();
    opts.progress.start(3, "terrain");
    let terrain = prepare_terrain(job, file, &site)?;
    let rover = load_rover(job, file)?;
    let searched = match &terrain {
        Terrain::Whole(d) => d,
        Terrain::Region { region, .. } => &region.dem,
    };
    opts.budget.check(&crate::budget::tempest(job, crate::budget::SearchMap::of(searched)))?;
    let truth_dem = true_terrain(job, file, &site, &terrain)?;
    let (mut notes, crs_not_read) = map_notes(job, file, &terrain);
    opts.progress.advance(1);
    let config = WorldConfig {
        epoch,
        span_s: job.horizon_h * 3600.0,
        sun_step_s: job.sun_step_min * 60.0,
        horizon_sectors: (job.horizon_sectors > 0).then_some(job.horizon_sectors),
        atmosphere: Atmosphere::for_body(job.body.model(), job.tau),
        site: Some(site),
    };
    let located = |e: MissionError| match e {
        MissionError::Config { field, message } => scenario_error(file, planner_field(field), message),
        other => Error::from(other),
    };
    let (frame, mut world) = match terrain {
        Terrain::Whole(dem) => (Frame::of(&dem), World::new(dem, &config, &job.body.model()).map_err(located)?),
        Terrain::Region { region, frame } => {
            (frame, World::for_region(region, &config, &job.body.model()).map_err(located)?)
        }
    };
    notes.extend(grid_north_note(&world));
    // One byte per horizon angle where the search's time classes make its error small
    // (before the truth is built: it shares the map's horizons) — the narrowest classes
    // it may search, its retries at halved classes included.
    // (On a tick: the approximate search's default classes, 60 s.)
    let p = job.planner.search.classes().copied().unwrap_or_default();
    let narrowest_s = p.resolution.time_s / 2f64.powi(p.unreachable_retries as i32);
    if let Some(shift_s) = world.narrow_horizon_within(narrowest_s) {
        notes.push(format!(
            "horizon map: one byte per angle (approximate: within {:.2}°, which moves a shadow's edge by at most the Sun's elevation change in {shift_s:.0} s; time classes of {narrowest_s:.0} s)",
            areo_terrain::horizon::NARROW_ERROR_DEG,
        ));
    }
    let mut truth = match truth_dem {
        Some(d) => Some(World::truth(d, &config, &job.body.model(), &world).map_err(located)?),
        None => None,
    };
    let classes = classes::on(job, file, &mut world, truth.as_mut(), frame)?;
    let precalc_s = clock.elapsed().as_secs_f64();
    opts.progress.advance(1);
    let model = action_model(job, file, &world, rover)?;
    // A chance-constrained plan is made on the model worsened to the confidence.
    let model = match chance::uncertainty(job) {
        Some(u) => model.with_margins(u.margins()),
        None => model,
    };
    let (no_go, (start, goals)) = no_go::on(job, file, (&world, truth.as_ref()), frame)?;
    Ok(Prepared { world, truth, config, model, frame, start, goals, precalc_s, notes, crs_not_read, no_go, classes })
}

/// The action model with the job's Communicate sessions, its start battery and the
/// battery to hold at the last goal checked against what the battery holds.
fn action_model(job: &TempestJob, file: &ScenarioFile, world: &World, rover: ResourceModel) -> Result<ActionModel> {
    let mut model = ActionModel::new(rover, job.planner.action_config());
    if let Some(com) = &job.communicate {
        let needs_earth = com.earth_in_view.unwrap_or(job.body.model() == areo_ephemeris::Body::Moon);
        let schedule = areo_mission::contact::Schedule {
            duration_min: com.duration_min,
            min_earth_elevation_deg: com.min_earth_elevation_deg,
            every_h: com.every_h,
            deadlines_h: com.deadlines_h.clone(),
        };
        model = model.with_sessions(contact::sessions(world, &schedule)).sessions_need_earth(needs_earth);
    }
    if job.start_battery_above_floor_wh > model.capacity_wh() + 1e-9 {
        return Err(scenario_error(
            file,
            "job.start_battery_above_floor_wh",
            format!(
                "{} Wh: the battery holds at most {:.1} Wh above its floor",
                job.start_battery_above_floor_wh,
                model.capacity_wh()
            ),
        ));
    }
    // A plan cannot end with more than the battery holds: refused as the bad input it
    // is, not searched for until the work budget ends.
    if job.planner.goal_energy_wh > model.capacity_wh() + 1e-9 {
        return Err(scenario_error(
            file,
            "job.planner.goal_energy_wh",
            format!(
                "{} Wh: the battery holds at most {:.1} Wh above its floor",
                job.planner.goal_energy_wh,
                model.capacity_wh()
            ),
        ));
    }
    Ok(model)
}

/// The start and goal cells of the job's positions (metres from the map's south-west
/// corner), each on the map and on passable ground.
fn locate(job: &TempestJob, file: &ScenarioFile, world: &World, frame: Frame) -> Result<(Start, Vec<u32>)> {
    let cell_of = |field: String, x: f64, y: f64| -> Result<u32> {
        let (mx, my) = frame.to_map(x, y);
        let cell = world.cell_at(mx, my).ok_or_else(|| {
            scenario_error(file, field.clone(), {
                let e = world.dem().extent();
                let (w, s) = frame.to_local((e.x_min, e.y_min));
                let (east, n) = frame.to_local((e.x_max, e.y_max));
                let what = if job.plan_region.is_some() { "the planning region" } else { "the map" };
                format!("({x}, {y}) m is off {what}: allowed {w:.0}..={east:.0} m east, {s:.0}..={n:.0} m north")
            })
        })?;
        if !world.passable(cell) {
            return Err(scenario_error(file, field, format!("({x}, {y}) m is on missing data or blocked ground")));
        }
        Ok(cell)
    };
    let start_cell = cell_of("job.start".into(), job.start.x_m, job.start.y_m)?;
    let goals: Vec<u32> = job
        .goals
        .iter()
        .enumerate()
        .map(|(i, g)| cell_of(format!("job.goals[{i}]"), g.x_m, g.y_m))
        .collect::<Result<_>>()?;
    let start = Start {
        cell: start_cell,
        t_min: 0.0,
        t_max: job.start_window_min * 60.0,
        energy_wh: job.start_battery_above_floor_wh,
    };
    Ok((start, goals))
}

/// Runs `work` while a watcher thread shows `meter`'s expansions and phase on
/// `progress` (about every fifth of a second; it notices the end within 20 ms).
fn watching<T>(progress: &dyn crate::Progress, meter: &areo_mission::ExpansionMeter, work: impl FnOnce() -> T) -> T {
    let done = std::sync::atomic::AtomicBool::new(false);
    std::thread::scope(|scope| {
        scope.spawn(|| {
            let mut ticks = 0u32;
            // Each relaxed search after "no plan" is shown from zero against the same
            // estimate: it is a search of the same problem.
            let (mut phase, mut before) = (meter.phase(), 0);
            while !done.load(std::sync::atomic::Ordering::Relaxed) {
                if ticks.is_multiple_of(10) {
                    if meter.phase() != phase {
                        (phase, before) = (meter.phase(), meter.expansions());
                        progress.rename(phase);
                    }
                    progress.set(meter.expansions() - before);
                }
                ticks += 1;
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
        });
        let out = work();
        done.store(true, std::sync::atomic::Ordering::Relaxed);
        out
    })
}

/// Plans (or simulates) on the prepared worlds, and maps the haven cells off Mars.
/// A simulation writes what it senses into the map it believes: a copy of the map as
/// given, for the comparisons made after it (the deterministic plan, the Monte Carlo,
/// the front), when the job makes any.
/// An error of the uncertainty model, located at its scenario field.
fn located_uncertainty(file: &ScenarioFile, e: Error) -> Error {
    match e {
        Error::Mission(MissionError::Config { field, message }) if field.starts_with("uncertainty.") => {
            scenario_error(file, format!("job.{field}"), message)
        }
        Error::Mission(e @ (MissionError::WorkLimit { .. } | MissionError::MemoryLimit { .. })) => located(file, e),
        other => other,
    }
}

/// The job's planner settings as every search of the run uses them: no planning call
/// may expand more labels than the work budget leaves for searching (an expansion is
/// `search_cost::EXPANSION_STEPS` of the estimate's steps; `budget::search_allowance`) — the
/// estimate is checked before the run, this holds during it.
///
/// The search graphs may hold what the memory budget leaves beside the worlds
/// (`worlds_bytes`: the map, the truth, and any snapshot or envelope the run keeps): the
/// estimate counts the graphs per cell, and a search that floods — no plan at narrow
/// time classes over a long horizon — outgrows it; this stops it before the machine does.
fn planner_config(
    job: &TempestJob,
    opts: &RunOptions<'_>,
    world: &World,
    worlds_bytes: u64,
) -> areo_mission::PlannerConfig {
    let allowance = crate::budget::search_allowance(job, world.cells() as u64, &opts.budget);
    areo_mission::PlannerConfig {
        max_expansions: Some(allowance),
        max_search_bytes: Some(opts.budget.memory_bytes.saturating_sub(worlds_bytes)),
        ..(&job.planner).into()
    }
}

/// A planner error as the scenario's: a planning call stopped by its work limit names
/// the file and the flag that raises it.
fn located(file: &ScenarioFile, e: MissionError) -> Error {
    match e {
        MissionError::WorkLimit { expansions, .. } => Error::WorkSpent { path: file.path.clone(), expansions },
        MissionError::MemoryLimit { bytes, limit } => Error::MemorySpent { path: file.path.clone(), bytes, limit },
        e => e.into(),
    }
}

fn pristine_belief(job: &TempestJob, world: &World) -> Option<World> {
    (job.simulate.is_some() && (job.uncertainty.is_some() || job.pareto_front.is_some())).then(|| world.snapshot())
}

/// Bytes the worlds a run keeps hold (each once).
fn held_bytes(worlds: &[Option<&World>]) -> u64 {
    worlds.iter().flatten().map(|w| w.bytes() as u64).sum()
}

/// The planner's answer as the run's: a plan or a simulation, "unreachable" as a
/// verdict, any other error the scenario's (located).
fn run_or_verdict(
    file: &ScenarioFile,
    result: std::result::Result<Run, MissionError>,
    work: impl FnOnce() -> NoPlanWork,
) -> Result<Run> {
    match result {
        Ok(run) => Ok(run),
        Err(MissionError::Config { field, message }) => Err(scenario_error(file, planner_field(field), message)),
        Err(MissionError::Unreachable { binding, message, proven }) => {
            Ok(Run::Unreachable { binding, message, proven, work: work() })
        }
        // Stopped by a budget: the facts it has are written, and the run exits with
        // the code of its own (4), not bad input's.
        Err(e @ (MissionError::WorkLimit { .. } | MissionError::MemoryLimit { .. })) => {
            let memory = matches!(e, MissionError::MemoryLimit { .. });
            Ok(Run::Stopped { memory, message: located(file, e).to_string(), work: work() })
        }
        Err(e) => Err(located(file, e)),
    }
}

fn compute(job: &TempestJob, file: &ScenarioFile, opts: RunOptions<'_>, prepared: Prepared) -> Result<Computed> {
    let Prepared { world, truth, config, model, start, goals, .. } = &prepared;
    // A chance-constrained plan allows for a late start.
    let plan_start = chance::uncertainty(job).map_or(*start, |u| u.planning_start(*start));
    // The searches count their expansions into a meter that a watcher shows while the
    // planner works: against the budget's estimate (the labels the guided searches are
    // expected to expand; the searches stop at the budget) when planning, simulated minutes against the horizon when simulating.
    let meter = areo_mission::ExpansionMeter::counting();
    // Planning for the terrain's height error: on the envelope of the map and its clones.
    let envelope = chance::planning_envelope(job, world, config).map_err(|e| located_uncertainty(file, e))?;
    let plan_world = envelope.as_ref().unwrap_or(world);
    // A simulation senses into the world it believes: keep that world as given for the
    // comparisons after it (the map stays as given when the envelope is believed).
    let pristine = pristine_belief(job, plan_world);
    let belief = if envelope.is_some() { world } else { pristine.as_ref().unwrap_or(world) };
    let plan_belief = pristine.as_ref().unwrap_or(plan_world);
    let worlds_bytes = held_bytes(&[Some(world), truth.as_ref(), envelope.as_ref(), pristine.as_ref()]);
    let planner =
        areo_mission::PlannerConfig { meter: meter.clone(), ..planner_config(job, &opts, world, worlds_bytes) };
    let since = Instant::now();
    let result: std::result::Result<Run, MissionError> = match &job.simulate {
        None => {
            let map = crate::budget::SearchMap::of(world.dem());
            opts.progress.start(crate::budget::expected_expansions(job, map), "planning");
            watching(opts.progress, &meter, || {
                let clock = Instant::now();
                Mission::plan(plan_world, model, planner, plan_start, goals).map(|(mission, plan)| Run::Plan {
                    plan,
                    seconds: clock.elapsed().as_secs_f64(),
                    search_bytes: mission.search_bytes(),
                    labels: mission.labels_alive(),
                })
            })
        }
        Some(sim) => {
            opts.progress.start((job.horizon_h * 60.0).ceil() as u64, "simulated min");
            let simulation = Simulation {
                believed: plan_world,
                truth: truth.as_ref().unwrap_or(world),
                model,
                planner,
                start: plan_start,
                goals,
                config: sim.into(),
            };
            simulate(&simulation, &mut |p| opts.progress.set((p.t_s / 60.0) as u64)).map(Run::Simulated)
        }
    };
    opts.progress.finish();
    let run = run_or_verdict(file, result, || NoPlanWork::since(since, &meter))?;
    let initial = match &run {
        Run::Plan { plan, .. } => Some(plan),
        Run::Simulated(r) => Some(&r.plans[0].plan),
        Run::Unreachable { .. } | Run::Stopped { .. } => None,
    };
    let chance = match initial {
        Some(plan) => {
            let worlds = ((belief, plan_belief), truth.as_ref().unwrap_or(belief));
            let planner = planner_config(job, &opts, world, worlds_bytes);
            chance::evaluate(job, (worlds, config), model, planner, (*start, goals), plan)
                .map_err(|e| located_uncertainty(file, e))?
        }
        None => None,
    };
    let front = match initial {
        Some(_) => {
            let planner = planner_config(job, &opts, world, worlds_bytes);
            front::evaluate(job, file, (belief, model), (plan_start, goals), planner)?
        }
        None => None,
    };
    // Off Mars: where the rover can wait out a shadow or a loss of the Earth.
    let havens = (job.body.model() != areo_ephemeris::Body::Mars
        && !matches!(run, Run::Unreachable { .. } | Run::Stopped { .. }))
    .then(|| {
        let every = job.communicate.as_ref().filter(|_| model.needs_earth()).and_then(|c| c.every_h);
        contact::havens(world, model, world.span_s(), HAVEN_STEP_S, every)
    });
    Ok(Computed { prepared, run, chance, front, havens, peak_memory_mb: peak_memory_mb() })
}

impl Computed {
    fn context<'a>(&'a self, job: &'a TempestJob, name: &'a str) -> Context<'a> {
        let p = &self.prepared;
        Context {
            name,
            job,
            world: &p.world,
            truth: p.truth.as_ref().unwrap_or(&p.world),
            frame: p.frame,
            start: p.start,
            goals: &p.goals,
            model: &p.model,
            precalc_s: p.precalc_s,
            havens: self.havens.as_ref(),
            no_go: p.no_go.as_ref().map(|n| n.codes.as_slice()),
        }
    }
}

/// The public report, and why the run failed (`None` when it did not).
fn report(ctx: &Context<'_>, computed: &Computed) -> Result<(Report, Option<Failure>)> {
    let world = ctx.world;
    let mut r = TempestReport {
        notes: computed.prepared.notes.clone(),
        map_crs_not_read: computed.prepared.crs_not_read.clone(),
        no_go: computed.prepared.no_go.as_ref().map(|n| n.figures.clone()),
        horizon_bytes_per_angle: (ctx.job.horizon_sectors > 0).then_some(if world.horizon_is_narrow() {
            1.0
        } else {
            2.0
        }),
        precalc_s: ctx.precalc_s,
        peak_memory_mb: computed.peak_memory_mb,
        goals_total: ctx.goals.len(),
        battery_floor_wh: floor_wh(ctx),
        ..TempestReport::default()
    };
    let mut failure = None;
    match &computed.run {
        Run::Unreachable { .. } | Run::Stopped { .. } => failure = no_plan(&mut r, ctx, computed),
        Run::Plan { plan, seconds, search_bytes, labels } => {
            (r.cells, r.map_cols_rows) = (Some(world.cells()), Some((world.cols(), world.rows())));
            // The segments' graphs as the plan leaves them (the most they held).
            r.peak_search_mb = Some(*search_bytes as f64 / 1e6);
            let mut figures = plan_figures(ctx, plan, *seconds);
            // Labels those graphs hold (on a tick, every label the search kept: most
            // are never expanded).
            figures.initial_plan_labels = Some(*labels);
            r.initial_plan = Some(figures);
            r.chance = computed.chance.as_ref().map(|c| chance::figures(ctx, plan, c));
            r.front = computed.front.as_ref().map(|f| front::figures(ctx, plan, f));
            r.status = "planned".into();
            r.tables = tables(ctx, plan, None);
            r.route = Some(route_places(ctx, plan, None));
            let view = view::view(ctx, plan, None);
            r.layers = Some(layers::layers(ctx.world, ctx.truth, shadow_time_s(ctx)?, false, view::span_s(ctx, &view)));
            r.plots = plots(ctx, plan, None)?;
            r.view = Some(view);
            r.plan = Some(plan.clone());
        }
        Run::Simulated(sim) => {
            (r.cells, r.map_cols_rows) = (Some(world.cells()), Some((world.cols(), world.rows())));
            let initial = &sim.plans[0].plan;
            r.initial_plan = Some(plan_figures(ctx, initial, sim.plans[0].wall_s));
            r.chance = computed.chance.as_ref().map(|c| chance::figures(ctx, initial, c));
            r.front = computed.front.as_ref().map(|f| front::figures(ctx, initial, f));
            sim_figures(&mut r, ctx, sim);
            if let SimStatus::Unreachable { binding, message, proven } = &sim.status {
                r.unreachable_proven = Some(*proven);
                r.binding = Some(message.clone());
                failure = Some(Failure::Unreachable {
                    binding: *binding,
                    message: message.clone(),
                    after_actions: Some(sim.steps.len()),
                });
            }
            r.tables = tables(ctx, initial, Some(sim));
            r.route = Some(route_places(ctx, initial, Some(sim)));
            let view = view::view(ctx, initial, Some(sim));
            r.layers = Some(layers::layers(ctx.world, ctx.truth, shadow_time_s(ctx)?, true, view::span_s(ctx, &view)));
            r.plots = plots(ctx, initial, Some(sim))?;
            r.view = Some(view);
            r.plan = Some(initial.clone());
            r.simulation = Some(sim.clone());
        }
    }
    classes::ground_layers(&mut r, ctx, computed);
    if let Some(c) = &computed.chance {
        r.tables.monte_carlo = chance::rows(ctx, c);
        r.plots.extend(chance::plots(ctx, c));
    }
    if let Some(f) = &computed.front {
        r.tables.pareto_front = Some(front::rows(ctx, f));
        r.pareto_plans = Some(f.plans.iter().map(|p| p.plan.clone()).collect());
        r.plots.extend(front::plots(ctx, f));
    }
    Ok((Report::Tempest(Box::new(r)), failure))
}

/// The figures of a run without a plan — unreachable, or stopped by a budget — and why
/// it failed (`None` for a run with a plan).
fn no_plan(r: &mut TempestReport, ctx: &Context<'_>, computed: &Computed) -> Option<Failure> {
    let (failure, work) = match &computed.run {
        Run::Unreachable { binding, message, proven, work } => {
            r.status = "unreachable".into();
            r.binding = Some(message.clone());
            r.unreachable_proven = Some(*proven);
            // Planned with every action made worse by its margins: a deterministic plan
            // may still exist.
            r.planned_at_confidence = chance::uncertainty(ctx.job)
                .filter(|u| u.margins() != areo_mission::Perturbation::NONE)
                .map(|u| u.confidence);
            let failure = Failure::Unreachable { binding: *binding, message: message.clone(), after_actions: None };
            (failure, work)
        }
        Run::Stopped { memory, message, work } => {
            r.status = "stopped".into();
            r.stopped_by = Some(if *memory { "memory" } else { "work" }.into());
            r.stopped_message = Some(message.clone());
            (Failure::Stopped { message: message.clone() }, work)
        }
        Run::Plan { .. } | Run::Simulated(_) => return None,
    };
    r.no_plan = Some(NoPlanFigures {
        no_plan_s: work.seconds,
        no_plan_expansions: work.expansions,
        no_plan_planning_expansions: work.phases.iter().find(|p| p.0 == "planning").map_or(0, |p| p.1),
        no_plan_probes: work.phases.len() as u64 - 1,
        no_plan_probe_expansions: (work.phases.iter())
            .filter_map(|&(p, n)| p.strip_prefix("no plan: ").map(|p| (p.to_string(), n)))
            .collect(),
    });
    Some(failure)
}

/// Sampling step of the haven map and of the plan's contact and shadow checks, s.
const HAVEN_STEP_S: f64 = 1800.0;
const CONTACT_STEP_S: f64 = 300.0;

/// A cell at an instant: planetocentric latitude and east longitude (degrees),
/// elevation (m), the local sol since the start's (see [`World::local_sol`]) and local
/// true solar time (hours).
struct Place {
    lat_deg: f64,
    lon_deg: f64,
    elevation_m: f64,
    sol: i64,
    ltst_h: f64,
}

struct Context<'a> {
    /// The scenario's name.
    name: &'a str,
    havens: Option<&'a contact::Havens>,
    job: &'a TempestJob,
    world: &'a World,
    truth: &'a World,
    frame: Frame,
    start: Start,
    goals: &'a [u32],
    model: &'a ActionModel,
    precalc_s: f64,
    /// With a no-go mask, what keeps each cell of the map out (`no_go::FREE` …).
    no_go: Option<&'a [u8]>,
}

impl Context<'_> {
    fn local(&self, cell: u32) -> (f64, f64) {
        self.frame.to_local(self.world.center(cell))
    }
    fn goal_name(&self, i: usize) -> &str {
        &self.job.goals[i].name
    }
    fn enters(&self, cells: impl Iterator<Item = u32>, region: &crate::format::RegionSpec) -> bool {
        cells.into_iter().any(|c| {
            let (x, y) = self.local(c);
            (x - region.x_m).hypot(y - region.y_m) <= region.radius_m
        })
    }
    /// Where and when `cell` is at `t_s`, as a mission counts it.
    fn place(&self, cell: u32, t_s: f64) -> Place {
        let (lat_deg, lon) = self.world.lat_lon(cell);
        let lon_deg = crate::report::lon180(lon);
        Place {
            lat_deg,
            lon_deg,
            elevation_m: self.world.elevation(cell).unwrap_or(f64::NAN),
            sol: self.world.local_sol(t_s, lon_deg),
            ltst_h: self.world.local_solar_time_h(t_s, lon_deg),
        }
    }
    fn hours(&self, t_s: f64) -> f64 {
        t_s / 3600.0
    }
}

fn floor_wh(ctx: &Context<'_>) -> f64 {
    let b = &ctx.model.rover().battery;
    b.capacity_wh * b.min_soc
}
