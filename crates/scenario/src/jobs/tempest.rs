//! The TEMPEST job: build the believed and true worlds, plan (and simulate), and
//! write plan.json, plan.csv, route.geojson, replans.csv, executed.csv and the plots.

use std::path::{Path, PathBuf};
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
use geojson::FeatureCollection;
use hifitime::Duration;
use serde_json::json;

mod chance;
mod front;
mod layers;

use crate::error::{Error, Result};
use crate::format::{ScenarioFile, TempestJob, TerrainSource, Truth};
use crate::jobs::RunOptions;
use crate::outcome::{Failure, Outcome};
use crate::output::csv::{Fixed, write_rows};
use crate::output::geojson::{collection, feature, line, point};
use crate::output::plots::{Marker, RoutePlot, Series, TimePlot};
use crate::output::{json_for, write_file};
use areo_mission::{contact, metrics};
use serde::Serialize;

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
        TerrainSource::File(rel) => {
            let base = file.path.parent().unwrap_or(Path::new("."));
            areo_terrain::read(&base.join(rel)).map_err(|e| Error::from(e).referenced_by(&file.path, field))?
        }
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
}

/// What planning (or simulating) gave.
enum Run {
    /// No plan reaches the goals from the start.
    Unreachable { binding: areo_mission::Binding, message: String, proven: bool, work: NoPlanWork },
    /// The searches stopped at the work (`memory: false`) or memory budget before they
    /// had an answer; `message` names the file and the flag.
    Stopped { memory: bool, message: String, work: NoPlanWork },
    /// A plan, its wall time (s) and the search graphs' bytes after it.
    Plan { plan: MissionPlan, seconds: f64, search_bytes: u64 },
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

/// A TEMPEST job's result: the prepared worlds, the run, the haven map (off Mars) and
/// the process's peak memory. Facts, the summary and the files are read off it.
struct TempestReport {
    prepared: Prepared,
    run: Run,
    /// The chance-constrained plan's comparison and Monte Carlo, with `uncertainty`.
    chance: Option<chance::Chance>,
    /// The Pareto front, with `pareto_front`.
    front: Option<areo_mission::ParetoFront>,
    havens: Option<contact::Havens>,
    peak_memory_mb: Option<f64>,
}

/// Runs a TEMPEST job: prepare, compute, then the facts and files of the report.
pub(crate) fn run(job: &TempestJob, file: &ScenarioFile, opts: RunOptions<'_>) -> Result<Outcome> {
    let prepared = prepare(job, file, opts)?;
    let report = compute(job, file, opts, prepared)?;
    let ctx = report.context(job);
    let mut o = outcome(&ctx, &report);
    if let Some(dir) = opts.out_dir {
        o.files.extend(write_outputs(dir, &ctx, &report.run)?);
        if let Some(c) = &report.chance {
            o.files.extend(chance::write(dir, &ctx, c)?);
        }
        if let Some(f) = &report.front {
            o.files.extend(front::write(dir, &ctx, f)?);
        }
    }
    Ok(o)
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
    let p = &job.planner;
    let narrowest_s = p.resolution.time_s / 2f64.powi(p.unreachable_retries as i32);
    if let Some(shift_s) = world.narrow_horizon_within(narrowest_s) {
        notes.push(format!(
            "horizon map: one byte per angle (approximate: within {:.2}°, which moves a shadow's edge by at most the Sun's elevation change in {shift_s:.0} s; time classes of {narrowest_s:.0} s)",
            areo_terrain::horizon::NARROW_ERROR_DEG,
        ));
    }
    let truth = match truth_dem {
        Some(d) => Some(World::truth(d, &config, &job.body.model(), &world).map_err(located)?),
        None => None,
    };
    let precalc_s = clock.elapsed().as_secs_f64();
    opts.progress.advance(1);
    let model = action_model(job, file, &world, rover)?;
    // A chance-constrained plan is made on the model worsened to the confidence.
    let model = match chance::uncertainty(job) {
        Some(u) => model.with_margins(u.margins()),
        None => model,
    };
    let (start, goals) = locate(job, file, &world, frame)?;
    Ok(Prepared { world, truth, config, model, frame, start, goals, precalc_s, notes, crs_not_read })
}

/// The action model with the job's Communicate sessions, its start battery checked.
fn action_model(job: &TempestJob, file: &ScenarioFile, world: &World, rover: ResourceModel) -> Result<ActionModel> {
    let mut model = ActionModel::new(rover, (&job.planner.actions).into());
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
                format!("({x}, {y}) m is off {what}: allowed {w:.0}..{east:.0} m east, {s:.0}..{n:.0} m north")
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
/// `budget::EXPANSION_STEPS` of the estimate's steps; `budget::search_allowance`) — the
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

fn compute(job: &TempestJob, file: &ScenarioFile, opts: RunOptions<'_>, prepared: Prepared) -> Result<TempestReport> {
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
    Ok(TempestReport { prepared, run, chance, front, havens, peak_memory_mb: peak_memory_mb() })
}

impl TempestReport {
    fn context<'a>(&'a self, job: &'a TempestJob) -> Context<'a> {
        let p = &self.prepared;
        Context {
            job,
            world: &p.world,
            truth: p.truth.as_ref().unwrap_or(&p.world),
            frame: p.frame,
            start: p.start,
            goals: &p.goals,
            model: &p.model,
            precalc_s: p.precalc_s,
            havens: self.havens.as_ref(),
        }
    }
}

/// The report's facts and summary.
fn outcome(ctx: &Context<'_>, report: &TempestReport) -> Outcome {
    let mut o = Outcome::default();
    let (world, precalc_s) = (ctx.world, ctx.precalc_s);
    o.summary.extend(report.prepared.notes.iter().cloned());
    if let Some(crs) = &report.prepared.crs_not_read {
        o.text("map_crs_not_read", crs.clone());
    }
    if ctx.job.horizon_sectors > 0 {
        o.number("horizon_bytes_per_angle", if world.horizon_is_narrow() { 1.0 } else { 2.0 });
    }
    if no_plan_outcome(&mut o, ctx, report) {
        return o;
    }
    o.number("precalc_s", precalc_s);
    if let Some(mb) = report.peak_memory_mb {
        o.number("peak_memory_mb", mb);
    }
    o.count("cells", world.cells() as u64);
    match &report.run {
        Run::Unreachable { .. } | Run::Stopped { .. } => {}
        Run::Plan { plan, seconds, search_bytes } => {
            o.number("initial_plan_s", *seconds);
            // The segments' graphs as the plan leaves them (the most they held).
            o.number("peak_search_mb", *search_bytes as f64 / 1e6);
            plan_facts(&mut o, ctx, plan);
            if let Some(c) = &report.chance {
                chance::facts(&mut o, ctx, plan, c);
            }
            if let Some(f) = &report.front {
                front::facts(&mut o, ctx, plan, f);
            }
            o.text("status", "planned");
            o.number("goals_reached", 0.0);
            o.summary.push(format!(
                "{} × {} cells; pre-calculation {precalc_s:.2} s, planning {seconds:.3} s ({} expansions)",
                world.cols(),
                world.rows(),
                plan.expansions
            ));
        }
        Run::Simulated(r) => {
            o.number("initial_plan_s", r.plans[0].wall_s);
            plan_facts(&mut o, ctx, &r.plans[0].plan);
            if let Some(c) = &report.chance {
                chance::facts(&mut o, ctx, &r.plans[0].plan, c);
            }
            if let Some(f) = &report.front {
                front::facts(&mut o, ctx, &r.plans[0].plan, f);
            }
            sim_facts(&mut o, ctx, r, report.peak_memory_mb);
            if let SimStatus::Unreachable { binding, message, proven } = &r.status {
                o.flag("unreachable_proven", *proven);
                o.failure = Some(Failure::Unreachable {
                    binding: *binding,
                    message: message.clone(),
                    after_actions: Some(r.steps.len()),
                });
            }
        }
    }
    o
}

/// The facts and summary of a run without a plan — unreachable, or stopped by a
/// budget — into `o`; false when the run has a plan.
fn no_plan_outcome(o: &mut Outcome, ctx: &Context<'_>, report: &TempestReport) -> bool {
    let precalc_s = ctx.precalc_s;
    match &report.run {
        Run::Unreachable { binding, message, proven, work } => {
            o.failure = Some(Failure::Unreachable { binding: *binding, message: message.clone(), after_actions: None });
            o.text("status", "unreachable");
            o.text("binding", message.clone());
            o.flag("unreachable_proven", *proven);
            o.number("goals_reached", 0.0);
            o.number("precalc_s", precalc_s);
            o.summary.push(format!("no plan: the goals are unreachable ({message})"));
            no_plan_facts(o, work, report.peak_memory_mb);
            if let Some(u) = chance::uncertainty(ctx.job).filter(|u| u.margins() != areo_mission::Perturbation::NONE) {
                o.summary.push(format!(
                    "(planned at confidence {}: every action made worse by its margins; a deterministic plan may still exist)",
                    u.confidence
                ));
            }
            true
        }
        Run::Stopped { memory, message, work } => {
            o.failure = Some(Failure::Stopped { message: message.clone() });
            o.text("status", "stopped");
            o.text("stopped_by", if *memory { "memory" } else { "work" });
            o.number("goals_reached", 0.0);
            o.number("precalc_s", precalc_s);
            o.summary.push(format!("no answer: {message}"));
            no_plan_facts(o, work, report.peak_memory_mb);
            true
        }
        Run::Plan { .. } | Run::Simulated(_) => false,
    }
}

/// What the "no plan" verdict cost, as facts and a summary line.
fn no_plan_facts(o: &mut Outcome, work: &NoPlanWork, peak_memory_mb: Option<f64>) {
    o.number("no_plan_s", work.seconds);
    o.count("no_plan_expansions", work.expansions);
    let planning = work.phases.iter().find(|p| p.0 == "planning").map_or(0, |p| p.1);
    o.count("no_plan_planning_expansions", planning);
    o.count("no_plan_probes", work.phases.len() as u64 - 1);
    if let Some(mb) = peak_memory_mb {
        o.number("peak_memory_mb", mb);
    }
    let probes: Vec<String> = (work.phases.iter())
        .filter_map(|&(p, n)| p.strip_prefix("no plan: ").map(|p| format!("{n} with {p}")))
        .collect();
    let probes = if probes.is_empty() {
        String::new()
    } else {
        format!("; the probes naming the binding constraint {}", probes.join(", "))
    };
    o.summary.push(format!(
        "no plan after {} expansions in {:.1} s: {planning} at the settings and their fallbacks{probes}",
        work.expansions, work.seconds
    ));
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
    havens: Option<&'a contact::Havens>,
    job: &'a TempestJob,
    world: &'a World,
    truth: &'a World,
    frame: Frame,
    start: Start,
    goals: &'a [u32],
    model: &'a ActionModel,
    precalc_s: f64,
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
        let (lat_deg, lon_deg) = self.world.lat_lon(cell);
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

/// Communicate sessions the plan covers, and drives that would overlap one (none may).
fn session_facts(o: &mut Outcome, ctx: &Context<'_>, plan: &MissionPlan) {
    let sessions = ctx.model.sessions();
    if !sessions.is_empty() {
        o.count("communicate_sessions", sessions.len() as u64);
        let (t0, t1) = (plan.waypoints.first().map_or(0.0, |w| w.t_s), plan.waypoints.last().map_or(0.0, |w| w.t_s));
        o.count("plan_sessions", sessions.iter().filter(|(a, b)| *a < t1 && *b > t0).count() as u64);
        let overlapping = plan
            .waypoints
            .windows(2)
            .filter(|w| matches!(w[0].action, Some(Action::Drive(_))))
            .filter(|w| sessions.iter().any(|&(a, b)| w[0].t_s < b && w[1].t_s > a))
            .count();
        o.count("plan_drives_during_sessions", overlapping as u64);
    }
}

fn plan_facts(o: &mut Outcome, ctx: &Context<'_>, plan: &MissionPlan) {
    let (drives, charges, hibernations) = plan.action_counts();
    o.count("initial_plan_waypoints", plan.waypoints.len() as u64);
    o.count("initial_plan_drives", drives as u64);
    o.count("initial_plan_charges", charges as u64);
    o.count("initial_plan_hibernations", hibernations as u64);
    o.number("initial_plan_duration_h", plan.duration_s() / 3600.0);
    o.number("initial_plan_min_battery_wh", plan.min_battery_wh());
    o.count("initial_plan_expansions", plan.expansions);
    o.number("e_max_wh", plan.e_max_wh);
    let drive_wps: Vec<_> = plan.waypoints.iter().filter(|w| matches!(w.action, Some(Action::Drive(_)))).collect();
    let length: f64 = plan
        .waypoints
        .windows(2)
        .map(|w| (w[1].easting_m - w[0].easting_m).hypot(w[1].northing_m - w[0].northing_m))
        .sum();
    o.number("initial_plan_distance_m", length);
    o.count("initial_plan_goals", plan.waypoints.iter().filter(|w| w.goal.is_some()).count() as u64);
    o.number(
        "initial_plan_sunlit_drive_fraction",
        if drive_wps.is_empty() {
            1.0
        } else {
            drive_wps.iter().filter(|w| w.lit).count() as f64 / drive_wps.len() as f64
        },
    );
    o.count("initial_plan_night_drives", drive_wps.iter().filter(|w| w.sun_elevation_deg <= 0.0).count() as u64);
    session_facts(o, ctx, plan);
    for r in &ctx.job.regions {
        o.flag(&format!("initial_plan_enters_{}", r.name), ctx.enters(plan.waypoints.iter().map(|w| w.cell), r));
    }
    if ctx.job.body.model() != areo_ephemeris::Body::Mars {
        body_facts(o, ctx, plan);
    }
    o.summary.push(format!(
        "initial plan: {} waypoints ({}, {}, {}) over {:.1} h; lowest predicted battery {:.0} Wh (absolute); \
         E_max {:.2} Wh",
        plan.waypoints.len(),
        super::counted(drives, "drive"),
        super::counted(charges, "charge"),
        super::counted(hibernations, "hibernation"),
        plan.duration_s() / 3600.0,
        plan.min_battery_wh(),
        plan.e_max_wh
    ));
    resolution_facts(o, ctx, plan);
}

/// What the search that found the plan approximated, said as what it is: its classes,
/// and which fallback (energy exact, halved classes, exact at the quanta) found it.
fn resolution_facts(o: &mut Outcome, ctx: &Context<'_>, plan: &MissionPlan) {
    let resolution = ctx.job.planner.resolution;
    let fallback = resolution.energy_wh.is_some() && plan.energy_classes_wh.is_none();
    o.flag("initial_plan_exact_energy_fallback", fallback);
    o.summary.push(format!(
        "search resolution: time classes of {:.0} s (approximate: labels of a class are compared as one instant); {}",
        resolution.time_s,
        match (resolution.energy_wh, fallback) {
            (None, _) => "energy exact (Pareto labels)".to_string(),
            (Some(w), false) => format!(
                "energy classes of {w} Wh (approximate: a kept label may need up to {w} Wh more than one it dropped)"
            ),
            (Some(w), true) => format!(
                "no plan with energy classes of {w} Wh, so the planner searched again with energy exact (fallback)"
            ),
        }
    ));
    // The last resort for quantised actions: a search exact at the quanta (reported
    // even where the classes were one quantum already: its goal instants and start
    // times are not the settings'); before it, and for continuous actions instead of
    // it, the retries at halved classes the settings asked for.
    let quantised = ctx.job.planner.actions.time_quantum_s >= 1.0;
    let at_quanta = plan.exact_at_quanta;
    let halved = plan.time_classes_s < resolution.time_s && !at_quanta;
    o.flag("initial_plan_quanta_fallback", at_quanta);
    o.flag("initial_plan_halved_classes_fallback", halved);
    if halved {
        let exactness = if quantised {
            "before the last resort exact at the quanta, which it made unnecessary"
        } else {
            "still approximate: no class width is exact for continuous action times"
        };
        o.summary.push(format!(
            "no plan at these classes, so the planner searched again at time classes of {:.0} s (fallback: \
             `unreachable_retries`; {exactness})",
            plan.time_classes_s
        ));
    }
    if at_quanta {
        o.summary.push(format!(
            "no plan at these classes, so the planner searched again exact at the actions' quanta (fallback: time classes of {:.0} s, energy exact, every goal instant a coarser goal_times would use)",
            plan.time_classes_s
        ));
    }
}

/// Facts of a plan off Mars: driving in shadow, Earth contact, the Sun's sweep, the
/// circuit, and the waits at safe havens — each measured on the plan by sampling, not
/// taken from the planner's constraints.
fn body_facts(o: &mut Outcome, ctx: &Context<'_>, plan: &MissionPlan) {
    use contact::{contact_along, shadowed_drive_h, waits};
    o.number("initial_plan_shadowed_drive_h", shadowed_drive_h(ctx.world, plan, CONTACT_STEP_S));
    if let Some(com) = &ctx.job.communicate
        && ctx.model.needs_earth()
    {
        let c = contact_along(ctx.world, plan, com.duration_min * 60.0, CONTACT_STEP_S);
        o.number("initial_plan_contact_max_gap_h", c.max_gap_h);
        o.number("initial_plan_earth_in_view_fraction", c.in_view_fraction);
        o.summary.push(format!(
            "Earth contact: in view {:.0} % of the plan; longest gap without {} min of contact {:.1} h",
            100.0 * c.in_view_fraction,
            com.duration_min,
            c.max_gap_h
        ));
    }
    let sun = metrics::sun_along(ctx.world, plan, CONTACT_STEP_S);
    o.number("initial_plan_sun_azimuth_swept_deg", sun.azimuth_swept_deg);
    o.number("initial_plan_lowest_sun_deg", sun.lowest_elevation_deg);
    if let Some(last) = plan.waypoints.last() {
        o.flag("initial_plan_closes_circuit", ctx.world.chebyshev(last.cell, ctx.start.cell) <= 1.0);
    }
    // Sun-synchronous driving: drives whose array faces within 90° of the Sun's
    // azimuth (the heading from the drive's displacement).
    if let Some(array) = ctx.model.rover().solar {
        o.number(
            "initial_plan_panel_sunward_drive_fraction",
            metrics::sunward_drive_fraction(ctx.world, plan, array.facing_deg),
        );
    }
    if let Some(h) = ctx.havens {
        o.count("safe_haven_cells", h.haven.iter().filter(|&&x| x).count() as u64);
        o.number("safe_haven_survive_h", h.survive_h.min(1e6));
        let ws = waits(plan, h, floor_wh(ctx), HAVEN_STEP_S);
        o.count("initial_plan_waits", ws.len() as u64);
        o.count("initial_plan_waits_at_havens", ws.iter().filter(|w| w.haven).count() as u64);
        let longest = ws.iter().max_by(|a, b| (a.to_h - a.from_h).total_cmp(&(b.to_h - b.from_h)));
        o.number("initial_plan_longest_wait_h", longest.map_or(0.0, |w| w.to_h - w.from_h));
        o.flag("initial_plan_longest_wait_at_haven", longest.is_some_and(|w| w.haven));
        o.summary.push(format!(
            "safe havens: {} cells (shadows shorter than the {:.0} h a full battery lasts asleep); the plan waits {} \
             times for at least {:.1} h, {} of them at havens",
            h.haven.iter().filter(|&&x| x).count(),
            h.survive_h.min(1e6),
            ws.len(),
            HAVEN_STEP_S / 3600.0,
            ws.iter().filter(|w| w.haven).count()
        ));
    }
}

fn sim_facts(o: &mut Outcome, ctx: &Context<'_>, r: &SimReport, peak_memory_mb: Option<f64>) {
    let status = match &r.status {
        SimStatus::Completed => "completed",
        SimStatus::Unreachable { .. } => "unreachable",
        SimStatus::BatteryDepleted => "battery_depleted",
        SimStatus::Stuck(_) => "stuck",
        SimStatus::StepLimit => "step_limit",
    };
    o.text("status", status);
    o.count("goals_reached", r.goals_reached.len() as u64);
    let epoch = ctx.world.epoch();
    for &(g, t) in &r.goals_reached {
        let name = ctx.goal_name(g);
        o.number(&format!("goal_{name}_arrival_h"), ctx.hours(t));
        let (_, lon) = ctx.world.lat_lon(ctx.goals[g]);
        let at = epoch + Duration::from_seconds(t);
        let ltst = ctx.world.local_solar_time_h(t, lon);
        o.number(&format!("goal_{name}_arrival_ltst_h"), ltst);
        o.summary.push(format!("reached {name} at {} (after {:.1} h, LTST {ltst:.2} h)", format_utc(at), ctx.hours(t)));
    }
    let drive_h = hours_in(r, |a| matches!(a, Action::Drive(_)));
    let charge_h = hours_in(r, |a| a == Action::Charge);
    let hibernate_h = hours_in(r, |a| a == Action::Hibernate);
    let replans: Vec<_> = r.plans.iter().filter(|p| p.kind != PlanKind::Initial).collect();
    let route_changes = replans.iter().filter(|p| p.route_changed).count();
    o.count("zigzag_pairs", metrics::zigzag_pairs(&r.steps) as u64);
    let min_battery = r.steps.iter().map(|s| s.battery_above_floor_wh).fold(r.start.energy_wh, f64::min);
    let floor = floor_wh(ctx);
    o.count("actions", r.steps.len() as u64);
    o.number("distance_m", r.distance_m());
    o.number("energy_used_wh", r.energy_used_wh());
    o.number("energy_gained_wh", r.energy_gained_wh());
    // Absolute charges, as everywhere a name says `battery_wh`; the search's E beside.
    o.number("final_battery_wh", r.final_battery_above_floor_wh() + floor);
    o.number("final_battery_above_floor_wh", r.final_battery_above_floor_wh());
    o.number("min_battery_wh", min_battery + floor);
    o.count("nights", r.nights() as u64);
    o.number("drive_h", drive_h);
    o.number("charge_h", charge_h);
    o.number("hibernate_h", hibernate_h);
    o.count("replans", replans.len() as u64);
    o.count("route_changes", route_changes as u64);
    restart_facts(o, r);
    let asked = ctx.job.planner.resolution.energy_wh;
    let fallbacks = r.plans.iter().filter(|p| asked.is_some() && p.plan.energy_classes_wh.is_none()).count();
    o.count("exact_energy_fallbacks", fallbacks as u64);
    search_facts(o, r);
    o.number("world_mb", worlds_mb(ctx));
    o.count("refused_actions", r.steps.iter().filter(|s| s.refused.is_some()).count() as u64);
    o.count("night_drives", metrics::night_drives(&r.steps) as u64);
    o.number("sunlit_drive_fraction", metrics::sunlit_drive_fraction(ctx.truth, &r.steps));
    o.number("mission_h", ctx.hours(r.end_t_s()));
    if let Some(m) = r.median_replan_s() {
        o.number("median_replan_s", m);
        let max = replans.iter().map(|p| p.wall_s).fold(0.0, f64::max);
        o.number("max_replan_s", max);
        let initial = r.plans[0].wall_s.max(1e-9);
        o.number("median_replan_fraction", m / initial);
    }
    for reg in &ctx.job.regions {
        let route = std::iter::once(r.start.cell).chain(r.steps.iter().map(|s| s.to));
        o.flag(&format!("route_enters_{}", reg.name), ctx.enters(route, reg));
    }
    sim_summary(o, ctx, r, status, peak_memory_mb);
}

/// The 95th percentile of sorted, non-empty `values` (nearest rank).
fn p95(values: &[f64]) -> f64 {
    values[(values.len() * 95).div_ceil(100).saturating_sub(1)]
}

/// The simulated run's search figures: re-plan expansions against the initial plan's
/// (restarts included), the search's memory, and with `compare_fresh` the re-plans
/// against fresh searches of the same problems.
fn search_facts(o: &mut Outcome, r: &SimReport) {
    // Deterministic search costs: each re-plan's expansions against the initial plan's
    // — restarts included, as the fresh plans they are (counted apart as well) — and
    // the search's memory.
    let mut fractions: Vec<f64> = r.replan_expansion_fractions();
    fractions.sort_by(f64::total_cmp);
    if let Some(&max) = fractions.last() {
        o.number("replan_expansions_median", fractions[fractions.len() / 2]);
        o.number("replan_expansions_p95", p95(&fractions));
        o.number("replan_expansions_max", max);
    }
    o.number("peak_search_mb", r.peak_search_bytes() as f64 / 1e6);
    // Re-plans that repaired the kept graphs for cells sensing changed.
    o.count(
        "replans_after_sensing",
        r.plans.iter().filter(|p| p.kind != PlanKind::Initial && p.changed_cells > 0).count() as u64,
    );
    // With `compare_fresh`: re-plans against the same problem searched from scratch.
    let compared: Vec<(&areo_mission::PlanRecord, (u64, f64))> =
        r.plans.iter().filter_map(|p| p.fresh.map(|f| (p, f))).collect();
    if !compared.is_empty() {
        o.count("fresh_compared", compared.len() as u64);
        o.count("replans_above_fresh", compared.iter().filter(|(p, (e, _))| p.expansions > *e).count() as u64);
        let worst = compared.iter().map(|(p, (_, c))| (p.plan.cost - c).abs() / c.abs().max(1.0)).fold(0.0, f64::max);
        o.number("replan_fresh_cost_difference", worst);
        o.summary.push(format!(
            "compared with fresh plans: {} re-plans, {} expanded more than the fresh search; costs within {:.2e} (relative)",
            compared.len(),
            compared.iter().filter(|(p, (e, _))| p.expansions > *e).count(),
            worst
        ));
    }
}

/// The re-plans on the kept graphs that found nothing and were replaced by plans made
/// afresh: how many, the work the failed re-plans did and the fresh plans' expansions,
/// and with `compare_fresh` how many a fresh search of the same problem contradicted
/// (it found a plan where the kept graphs found none).
fn restart_facts(o: &mut Outcome, r: &SimReport) {
    let restarts: Vec<(&areo_mission::PlanRecord, &areo_mission::Restart)> =
        r.plans.iter().filter_map(|p| p.restart.as_ref().map(|x| (p, x))).collect();
    o.count("restarts", restarts.len() as u64);
    if restarts.is_empty() {
        return;
    }
    o.count("restart_replan_work", restarts.iter().map(|(_, x)| x.replan_work).sum());
    o.count("restart_expansions", restarts.iter().map(|(p, _)| p.expansions).sum());
    let compared: Vec<bool> = restarts.iter().filter_map(|(_, x)| x.fresh_found).collect();
    if !compared.is_empty() {
        o.count("restarts_fresh_compared", compared.len() as u64);
        o.count("restarts_fresh_disagree", compared.iter().filter(|&&found| found).count() as u64);
    }
}

/// Hours the executed run spent in the actions `which` accepts.
fn hours_in(r: &SimReport, which: impl Fn(Action) -> bool) -> f64 {
    // A fold from +0: `sum` of no f64 is -0, which prints as "-0.0 h".
    r.steps.iter().filter(|s| which(s.action)).map(|s| s.duration_s).fold(0.0, |a, d| a + d) / 3600.0
}

/// The simulated run in words: where it got, its battery, its re-plans and memory.
fn sim_summary(o: &mut Outcome, ctx: &Context<'_>, r: &SimReport, status: &str, peak_memory_mb: Option<f64>) {
    let floor = floor_wh(ctx);
    let (drive_h, charge_h, hibernate_h) = (
        hours_in(r, |a| matches!(a, Action::Drive(_))),
        hours_in(r, |a| a == Action::Charge),
        hours_in(r, |a| a == Action::Hibernate),
    );
    let replans: Vec<_> = r.plans.iter().filter(|p| p.kind != PlanKind::Initial).collect();
    let route_changes = replans.iter().filter(|p| p.route_changed).count();
    let restarts = r.plans.iter().filter(|p| p.kind == PlanKind::Restart).count();
    let min_battery = r.steps.iter().map(|s| s.battery_above_floor_wh).fold(r.start.energy_wh, f64::min);
    let mut fractions: Vec<f64> = r.replan_expansion_fractions();
    fractions.sort_by(f64::total_cmp);
    o.summary.push(format!(
        "{status}: {} of {} goals; {:.0} m driven in {drive_h:.1} h; charged {charge_h:.1} h, hibernated {hibernate_h:.1} h; \
         {} night(s)",
        r.goals_reached.len(),
        ctx.goals.len(),
        r.distance_m(),
        r.nights()
    ));
    o.summary.push(format!(
        "battery: used {:.0} Wh, gained {:.0} Wh, ends at {:.0} Wh ({:.0} Wh above the {floor:.0} Wh floor), \
         lowest {:.0} Wh ({:.0} Wh above the floor)",
        r.energy_used_wh(),
        r.energy_gained_wh(),
        r.final_battery_above_floor_wh() + floor,
        r.final_battery_above_floor_wh(),
        min_battery + floor,
        min_battery
    ));
    o.summary.push(format!(
        "{} ({route_changes} changed the route), median {:.2} ms, initial plan {:.1} ms",
        super::counted(replans.len(), "re-plan"),
        1e3 * r.median_replan_s().unwrap_or(0.0),
        1e3 * r.plans[0].wall_s
    ));
    if !fractions.is_empty() {
        o.summary.push(format!(
            "re-plan expansions: median {:.3} %, 95th percentile {:.2} %, largest {:.1} % of the initial plan's{}",
            100.0 * fractions[fractions.len() / 2],
            100.0 * p95(&fractions),
            100.0 * fractions[fractions.len() - 1],
            if restarts > 0 { format!(" ({restarts} restart(s) included)") } else { String::new() }
        ));
    }
    if restarts > 0 {
        let mut why: Vec<String> =
            r.plans.iter().filter_map(|p| p.restart.as_ref()).map(|x| format!("{:?}", x.binding)).collect();
        why.dedup();
        let compared: Vec<bool> = r.plans.iter().filter_map(|p| p.restart.as_ref()?.fresh_found).collect();
        o.summary.push(format!(
            "{restarts} restart(s): re-planning on the kept graphs found nothing ({}), so the rover planned afresh{}",
            why.join(", "),
            if compared.is_empty() {
                String::new()
            } else {
                format!(
                    "; a fresh search of the same problem found a plan in {} of {}",
                    compared.iter().filter(|&&f| f).count(),
                    compared.len()
                )
            }
        ));
    }
    o.summary.push(format!(
        "pre-calculation {:.2} s (slope, horizon maps, Sun table); memory: search graphs {:.0} MB at most, worlds {:.0} MB, process peak {}",
        ctx.precalc_s,
        r.peak_search_bytes() as f64 / 1e6,
        worlds_mb(ctx),
        peak_memory_mb.map_or("unknown".into(), |mb| format!("{mb:.0} MB"))
    ));
    if let SimStatus::Unreachable { message, .. } = &r.status {
        o.summary.push(format!("stopped: the next goal is unreachable ({message})"));
    }
}

fn write_outputs(dir: &Path, ctx: &Context<'_>, run: &Run) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let (initial, report) = match run {
        // Nothing planned: facts.json (written by the caller) says why.
        Run::Unreachable { .. } | Run::Stopped { .. } => return Ok(Vec::new()),
        Run::Plan { plan, .. } => (plan, None),
        Run::Simulated(r) => (&r.plans[0].plan, Some(r)),
    };
    let mut put = |name: &str, write: &dyn Fn(&Path) -> Result<()>| -> Result<()> {
        let path = dir.join(name);
        write(&path)?;
        files.push(path);
        Ok(())
    };
    put("plan.json", &|p| write_file(p, json_for(p, initial, true)?.as_bytes()))?;
    put("plan.csv", &|p| write_rows(p, plan_rows(ctx, initial)))?;
    if let Some(r) = report {
        put("simulation.json", &|p| write_file(p, json_for(p, r, false)?.as_bytes()))?;
        put("executed.csv", &|p| write_rows(p, executed_rows(ctx, r)))?;
        put("replans.csv", &|p| write_rows(p, replan_rows(ctx, r)))?;
    }
    put("route.geojson", &|p| crate::output::geojson::write(p, &route_geojson(ctx, initial, report)))?;
    put("route.kml", &|p| route_kml(ctx, initial, report).write(p))?;
    if let Some(h) = ctx.havens {
        put("waits.csv", &|p| write_rows(p, wait_rows(ctx, initial, h)))?;
    }
    files.extend(layers::write(dir, ctx.world, ctx.truth, shadow_time_s(ctx)?)?);
    files.extend(plots(dir, ctx, initial, report)?);
    Ok(files)
}

/// A row of waits.csv: one of the plan's waits with its place, span, lowest charge and
/// whether at a haven.
#[derive(Serialize, Default)]
struct WaitRow {
    x_m: Fixed<1>,
    y_m: Fixed<1>,
    from_h: Fixed<3>,
    to_h: Fixed<3>,
    hours: Fixed<3>,
    lowest_battery_above_floor_wh: Fixed<1>,
    safe_haven: bool,
    longest_shadow_h: Fixed<1>,
    longest_earth_loss_h: Fixed<1>,
}

fn wait_rows(ctx: &Context<'_>, plan: &MissionPlan, havens: &contact::Havens) -> Vec<WaitRow> {
    contact::waits(plan, havens, floor_wh(ctx), HAVEN_STEP_S)
        .into_iter()
        .map(|w| {
            let (x, y) = ctx.local(w.cell);
            let i = w.cell as usize;
            WaitRow {
                x_m: Fixed(x),
                y_m: Fixed(y),
                from_h: Fixed(w.from_h),
                to_h: Fixed(w.to_h),
                hours: Fixed(w.to_h - w.from_h),
                lowest_battery_above_floor_wh: Fixed(w.lowest_battery_above_floor_wh),
                safe_haven: w.haven,
                longest_shadow_h: Fixed(f64::from(havens.longest_shadow_h[i])),
                longest_earth_loss_h: Fixed(f64::from(havens.longest_earth_loss_h[i])),
            }
        })
        .collect()
}

fn action_name(a: Option<Action>) -> &'static str {
    a.map_or("arrive", Action::name)
}

/// A row of plan.csv: one waypoint.
#[derive(Serialize, Default)]
struct PlanRow {
    index: usize,
    utc: String,
    t_s: Fixed<1>,
    sol: i64,
    ltst_h: Fixed<4>,
    col: usize,
    row: usize,
    x_m: Fixed<2>,
    y_m: Fixed<2>,
    lat_deg: Fixed<7>,
    lon_deg: Fixed<7>,
    elevation_m: Fixed<2>,
    action: &'static str,
    required_wh: Fixed<3>,
    battery_wh: Fixed<3>,
    slope_deg: Fixed<3>,
    sun_elevation_deg: Fixed<3>,
    sun_above_ground_deg: Fixed<3>,
    lit: u8,
    goal: String,
}

fn plan_rows<'a>(ctx: &'a Context<'_>, plan: &'a MissionPlan) -> impl Iterator<Item = PlanRow> + 'a {
    plan.waypoints.iter().enumerate().map(move |(index, w)| {
        let (x, y) = ctx.local(w.cell);
        PlanRow {
            index,
            utc: w.utc.clone(),
            t_s: Fixed(w.t_s),
            sol: ctx.world.local_sol(w.t_s, w.lon_deg),
            ltst_h: Fixed(w.ltst_h),
            col: w.col_row.0,
            row: w.col_row.1,
            x_m: Fixed(x),
            y_m: Fixed(y),
            lat_deg: Fixed(w.lat_deg),
            lon_deg: Fixed(w.lon_deg),
            elevation_m: Fixed(ctx.world.elevation(w.cell).unwrap_or(f64::NAN)),
            action: action_name(w.action),
            required_wh: Fixed(w.required_wh),
            battery_wh: Fixed(w.battery_wh),
            slope_deg: Fixed(w.slope_deg),
            sun_elevation_deg: Fixed(w.sun_elevation_deg),
            sun_above_ground_deg: Fixed(w.sun_above_ground_deg),
            lit: u8::from(w.lit),
            goal: w.goal.map(|g| ctx.goal_name(g).to_string()).unwrap_or_default(),
        }
    })
}

/// A row of executed.csv: one executed action.
#[derive(Serialize, Default)]
struct ExecutedRow {
    step: usize,
    utc: String,
    t_s: Fixed<1>,
    sol: i64,
    ltst_h: Fixed<4>,
    col: usize,
    row: usize,
    x_m: Fixed<2>,
    y_m: Fixed<2>,
    lat_deg: Fixed<7>,
    lon_deg: Fixed<7>,
    elevation_m: Fixed<2>,
    action: &'static str,
    duration_s: Fixed<1>,
    energy_wh: Fixed<3>,
    battery_wh: Fixed<3>,
    battery_above_floor_wh: Fixed<3>,
    distance_m: Fixed<3>,
    sun_elevation_deg: Fixed<3>,
    refused: String,
}

fn executed_rows<'a>(ctx: &'a Context<'_>, r: &'a SimReport) -> impl Iterator<Item = ExecutedRow> + 'a {
    r.steps.iter().enumerate().map(move |(i, st)| {
        let (col, row) = ctx.world.col_row(st.cell);
        let (x, y) = ctx.local(st.cell);
        let p = ctx.place(st.cell, st.t_s);
        ExecutedRow {
            step: i + 1,
            utc: format_utc(ctx.world.epoch() + Duration::from_seconds(st.t_s)),
            t_s: Fixed(st.t_s),
            sol: p.sol,
            ltst_h: Fixed(p.ltst_h),
            col,
            row,
            x_m: Fixed(x),
            y_m: Fixed(y),
            lat_deg: Fixed(p.lat_deg),
            lon_deg: Fixed(p.lon_deg),
            elevation_m: Fixed(p.elevation_m),
            action: st.action.name(),
            duration_s: Fixed(st.duration_s),
            energy_wh: Fixed(st.energy_wh),
            battery_wh: Fixed(st.battery_above_floor_wh + floor_wh(ctx)),
            battery_above_floor_wh: Fixed(st.battery_above_floor_wh),
            distance_m: Fixed(st.distance_m),
            sun_elevation_deg: Fixed(st.sun_elevation_deg),
            refused: st.refused.map(|(a, b)| format!("{} ({})", a.name(), b.describe())).unwrap_or_default(),
        }
    })
}

/// A row of replans.csv: one plan of a simulated run (the initial plan, a re-plan or
/// a restart), with its fresh comparison when asked for.
#[derive(Serialize, Default)]
struct ReplanRow {
    step: usize,
    kind: &'static str,
    utc: String,
    t_s: Fixed<1>,
    wall_ms: Fixed<3>,
    expansions: u64,
    changed_cells: usize,
    route_changed: u8,
    waypoints: usize,
    cost: Fixed<4>,
    duration_h: Fixed<3>,
    min_battery_wh: Fixed<2>,
    search_mb: Fixed<1>,
    fresh_expansions: Option<u64>,
    fresh_cost: Option<Fixed<4>>,
    restart_binding: Option<String>,
    restart_replan_work: Option<u64>,
    restart_fresh_found: Option<u8>,
}

fn replan_rows<'a>(ctx: &'a Context<'_>, r: &'a SimReport) -> impl Iterator<Item = ReplanRow> + 'a {
    r.plans.iter().map(move |p| ReplanRow {
        step: p.step,
        kind: match p.kind {
            PlanKind::Initial => "initial",
            PlanKind::Replan => "replan",
            PlanKind::Restart => "restart",
        },
        utc: format_utc(ctx.world.epoch() + Duration::from_seconds(p.t_s)),
        t_s: Fixed(p.t_s),
        wall_ms: Fixed(1e3 * p.wall_s),
        expansions: p.expansions,
        changed_cells: p.changed_cells,
        route_changed: u8::from(p.route_changed),
        waypoints: p.plan.waypoints.len(),
        cost: Fixed(p.plan.cost),
        duration_h: Fixed(p.plan.duration_s() / 3600.0),
        min_battery_wh: Fixed(p.plan.min_battery_wh()),
        search_mb: Fixed(p.search_bytes as f64 / 1e6),
        fresh_expansions: p.fresh.map(|f| f.0),
        fresh_cost: p.fresh.map(|f| Fixed(f.1)),
        restart_binding: p.restart.as_ref().map(|x| format!("{:?}", x.binding)),
        restart_replan_work: p.restart.as_ref().map(|x| x.replan_work),
        restart_fresh_found: p.restart.as_ref().and_then(|x| x.fresh_found).map(u8::from),
    })
}

/// The routes, start and goals as KML for Google Earth (with the body's hint).
fn route_kml(ctx: &Context<'_>, initial: &MissionPlan, report: Option<&SimReport>) -> crate::output::kml::Kml {
    let at = |cell: u32| ctx.world.lat_lon(cell);
    let mut kml = crate::output::kml::Kml::new("areo TEMPEST route", ctx.world.dem().georef().surface.body());
    kml.line("initial plan", "ffdc5a1e", initial.waypoints.iter().map(|w| at(w.cell)));
    if let Some(r) = report {
        let cells = std::iter::once(r.start.cell).chain(r.steps.iter().map(|s| s.to));
        kml.line("executed route", "ff281edc", cells.map(at));
    }
    let utc = |t_s: f64| format_utc(ctx.world.epoch() + Duration::from_seconds(t_s));
    kml.point("start", &format!("start at {}", utc(ctx.start.t_min)), at(ctx.start.cell));
    for (i, &g) in ctx.goals.iter().enumerate() {
        let reached = initial.waypoints.iter().find(|w| w.goal == Some(i)).map(|w| w.utc.clone());
        let description = match reached {
            Some(t) => format!("goal {} of the plan, reached at {t}", i + 1),
            None => format!("goal {} of the plan", i + 1),
        };
        kml.point(ctx.goal_name(i), &description, at(g));
    }
    kml
}

fn route_geojson(ctx: &Context<'_>, initial: &MissionPlan, report: Option<&SimReport>) -> FeatureCollection {
    let at = |cell: u32| ctx.world.lat_lon(cell);
    let floor = floor_wh(ctx);
    let mut features =
        vec![feature(line(initial.waypoints.iter().map(|w| at(w.cell))), json!({"name": "initial plan"}))];
    // Every point says where and when it is as a mission counts it, beside its charge
    // (absolute, and above the floor: the search's E).
    let located = |cell: u32, t_s: f64, mut properties: serde_json::Value, above_floor_wh: f64| {
        let p = ctx.place(cell, t_s);
        let extra = json!({
            "utc": format_utc(ctx.world.epoch() + Duration::from_seconds(t_s)), "t_h": t_s / 3600.0,
            "sol": p.sol, "ltst_h": p.ltst_h, "elevation_m": p.elevation_m,
            "battery_wh": above_floor_wh + floor, "battery_above_floor_wh": above_floor_wh,
        });
        if let (Some(o), serde_json::Value::Object(e)) = (properties.as_object_mut(), extra) {
            o.extend(e);
        }
        feature(point(at(cell)), properties)
    };
    match report {
        None => {
            for (i, w) in initial.waypoints.iter().enumerate() {
                let props = json!({
                    "kind": "waypoint", "index": i, "action": action_name(w.action), "required_wh": w.required_wh,
                });
                features.push(located(w.cell, w.t_s, props, w.battery_wh - floor));
            }
        }
        Some(r) => {
            let cells = std::iter::once(r.start.cell).chain(r.steps.iter().map(|s| s.to));
            features.push(feature(line(cells.map(at)), json!({"name": "executed route"})));
            for (i, s) in r.steps.iter().enumerate() {
                let props =
                    json!({"kind": "executed", "step": i + 1, "action": s.action.name(), "energy_wh": s.energy_wh});
                features.push(located(s.cell, s.t_s, props, s.battery_above_floor_wh));
            }
        }
    }
    features.push(feature(point(at(ctx.start.cell)), json!({"kind": "start", "name": "start"})));
    for (i, &g) in ctx.goals.iter().enumerate() {
        features.push(feature(point(at(g)), json!({"kind": "goal", "name": ctx.goal_name(i), "order": i})));
    }
    collection(features, &ctx.world.dem().georef().surface)
}

/// Night intervals (the Sun's centre below the horizontal) over [0, end_s], hours
/// since the epoch.
fn nights(world: &World, end_s: f64) -> Vec<(f64, f64)> {
    let start = world.epoch();
    night_intervals(&world.site(), &HorizonMask::flat(), start, start + Duration::from_seconds(end_s))
        .into_iter()
        .map(|(a, b)| ((a - start).to_seconds() / 3600.0, (b - start).to_seconds() / 3600.0))
        .collect()
}

fn plots(dir: &Path, ctx: &Context<'_>, initial: &MissionPlan, report: Option<&SimReport>) -> Result<Vec<PathBuf>> {
    let mut files = route_plots(dir, ctx, initial, report)?;
    let end_s =
        report.map_or(initial.waypoints.last().map_or(0.0, |w| w.t_s), |r| r.end_t_s().max(initial.duration_s()));
    let night = nights(ctx.truth, end_s);
    files.extend(distance_plot(dir, ctx, initial, report, (end_s, &night))?);
    files.extend(energy_plot(dir, ctx, initial, report, (end_s, &night))?);
    Ok(files)
}

/// The time plots' tick labels as the job's `plot_time` asks.
fn time_ticks(ctx: &Context<'_>) -> crate::output::plots::TimeTicks {
    use crate::output::plots::TimeTicks;
    match ctx.job.plot_time {
        crate::format::PlotTime::Hours => TimeTicks::Numbers,
        crate::format::PlotTime::Utc => TimeTicks::Utc { epoch: ctx.truth.epoch() },
        crate::format::PlotTime::LocalSolar => TimeTicks::LocalSolar {
            ltst0_h: ctx.truth.local_solar_time_h(0.0, ctx.truth.lat_lon(ctx.start.cell).1),
            day_h: ctx.job.body.model().solar_day_s() / 3600.0,
        },
    }
}

/// The x axis's name for the job's `plot_time`.
fn time_axis_name(ctx: &Context<'_>) -> String {
    match ctx.job.plot_time {
        crate::format::PlotTime::Hours => "hours since the start".into(),
        crate::format::PlotTime::Utc => "UTC".into(),
        crate::format::PlotTime::LocalSolar => "local true solar time at the start".into(),
    }
}

/// The job's `shadow_utc` (default its start), s after the world's epoch.
fn shadow_time_s(ctx: &Context<'_>) -> Result<f64> {
    Ok(match &ctx.job.shadow_utc {
        Some(s) => (parse_utc(s)? - ctx.truth.epoch()).to_seconds(),
        None => 0.0,
    })
}

/// The routes over the hillshade with shadows at the job's `shadow_utc` (and the
/// haven map off Mars).
fn route_plots(
    dir: &Path,
    ctx: &Context<'_>,
    initial: &MissionPlan,
    report: Option<&SimReport>,
) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let world = ctx.truth;
    let dem = world.dem();
    // (a) Routes over the hillshade with shadows at the chosen time.
    let t_shadow = shadow_time_s(ctx)?;
    let sun = world.sun(t_shadow.clamp(0.0, world.span_s()));
    let shadowed: Vec<bool> = (0..world.cells() as u32).map(|c| !world.lit(c, &sun)).collect();
    let slope = areo_terrain::slope::slope_aspect(dem);
    let background = areo_terrain::hillshade::hillshade_rgb(
        dem,
        &slope,
        Some(&shadowed),
        sun.azimuth_deg,
        sun.elevation_deg.max(5.0),
    );
    let to_xy = |cells: &mut dyn Iterator<Item = u32>| cells.map(|c| ctx.local(c)).collect::<Vec<_>>();
    let mut series = vec![Series {
        label: "initial plan".into(),
        points: to_xy(&mut initial.waypoints.iter().map(|w| w.cell)),
        rgb: (30, 90, 220),
        width: 2,
    }];
    if let Some(r) = report {
        // Significant re-plans: those that changed the route, at most six, spread out.
        let changed: Vec<_> = r.plans.iter().filter(|p| p.kind != PlanKind::Initial && p.route_changed).collect();
        let pick = changed.len().div_ceil(6).max(1);
        for p in changed.iter().step_by(pick) {
            series.push(Series {
                label: format!("re-plan after action {}", p.step),
                points: to_xy(&mut p.plan.waypoints.iter().map(|w| w.cell)),
                rgb: (240, 150, 30),
                width: 1,
            });
        }
        let mut cells = vec![r.start.cell];
        cells.extend(r.steps.iter().map(|s| s.to));
        series.push(Series {
            label: "executed route".into(),
            points: to_xy(&mut cells.into_iter()),
            rgb: (220, 30, 40),
            width: 3,
        });
    }
    let mut markers = vec![Marker { label: "start".into(), at: ctx.local(ctx.start.cell), rgb: (40, 200, 60) }];
    for (i, &g) in ctx.goals.iter().enumerate() {
        markers.push(Marker { label: ctx.goal_name(i).to_string(), at: ctx.local(g), rgb: (250, 220, 40) });
    }
    // Every goal in visiting order: the last goal's name alone read as the plot's subject.
    let n = ctx.goals.len();
    let visits = if n <= 4 {
        (0..n).map(|i| ctx.goal_name(i)).collect::<Vec<_>>().join(" → ")
    } else {
        format!("{} goals ending at {}", n, ctx.goal_name(n - 1))
    };
    let title = format!(
        "Routes to {visits} over the terrain (shadows at {})",
        format_utc(world.epoch() + Duration::from_seconds(t_shadow))
    );
    let route = framed(dem, &background, series.clone(), markers.clone(), title);
    files.extend(crate::output::plots::route(dir, "route", &route)?);
    if let Some(h) = ctx.havens {
        files.extend(haven_plots(dir, ctx, initial, h, series, markers)?);
    }
    Ok(files)
}

/// The straight-line distance to the final goal against time, with the nights
/// (`end_s`, s, and the nights, h).
fn distance_plot(
    dir: &Path,
    ctx: &Context<'_>,
    initial: &MissionPlan,
    report: Option<&SimReport>,
    (end_s, night): (f64, &[(f64, f64)]),
) -> Result<Vec<PathBuf>> {
    // (b) Distance to the final goal against time.
    let last = *ctx.goals.last().unwrap_or(&ctx.start.cell);
    let goal_xy = ctx.local(last);
    let dist = |cell: u32| {
        let (x, y) = ctx.local(cell);
        (x - goal_xy.0).hypot(y - goal_xy.1)
    };
    let mut dseries = vec![Series {
        label: "initial plan".into(),
        points: initial.waypoints.iter().map(|w| (w.t_s / 3600.0, dist(w.cell))).collect(),
        rgb: (30, 90, 220),
        width: 2,
    }];
    if let Some(r) = report {
        let mut pts = vec![(r.start.t_min / 3600.0, dist(r.start.cell))];
        for s in &r.steps {
            pts.push(((s.t_s + s.duration_s) / 3600.0, dist(s.to)));
        }
        dseries.push(Series { label: "executed".into(), points: pts, rgb: (220, 30, 40), width: 2 });
    }
    let d0 = dist(ctx.start.cell);
    let v = ctx.model.top_speed_m_s();
    let t_zero = ctx.start.t_min + d0 / v;
    dseries.push(Series {
        label: "straight line at top speed".into(),
        points: vec![(ctx.start.t_min / 3600.0, d0), (t_zero / 3600.0, 0.0)],
        rgb: (90, 90, 90),
        width: 1,
    });
    crate::output::plots::time(
        dir,
        "distance",
        &TimePlot {
            title: "Straight-line distance to the final goal".into(),
            x_label: time_axis_name(ctx),
            y_label: "distance, m".into(),
            series: dseries,
            nights: night.to_vec(),
            x_range: (0.0, end_s / 3600.0),
            windows: Vec::new(),
            windows_label: String::new(),
            dots: false,
            x_ticks: time_ticks(ctx),
        },
    )
}

/// The energy required to finish and the battery's charge against time.
fn energy_plot(
    dir: &Path,
    ctx: &Context<'_>,
    initial: &MissionPlan,
    report: Option<&SimReport>,
    (end_s, night): (f64, &[(f64, f64)]),
) -> Result<Vec<PathBuf>> {
    // (c) Required energy and battery charge against time.
    let mut eseries = vec![
        Series {
            label: "required energy E (initial plan)".into(),
            points: initial.waypoints.iter().map(|w| (w.t_s / 3600.0, w.required_wh)).collect(),
            rgb: (120, 40, 180),
            width: 2,
        },
        Series {
            label: "predicted charge above floor (initial plan)".into(),
            points: initial.waypoints.iter().map(|w| (w.t_s / 3600.0, w.battery_wh - floor_wh(ctx))).collect(),
            rgb: (30, 90, 220),
            width: 2,
        },
    ];
    if let Some(r) = report
        && let Some(first) = r.plans.iter().find(|p| p.kind != PlanKind::Initial && p.route_changed)
    {
        eseries.push(Series {
            label: format!("required energy E (first route change, action {})", first.step),
            points: first.plan.waypoints.iter().map(|w| (w.t_s / 3600.0, w.required_wh)).collect(),
            rgb: (40, 170, 200),
            width: 2,
        });
    }
    if let Some(r) = report {
        let mut pts = vec![(r.start.t_min / 3600.0, r.start.energy_wh)];
        for s in &r.steps {
            pts.push(((s.t_s + s.duration_s) / 3600.0, s.battery_above_floor_wh));
        }
        eseries.push(Series { label: "executed charge above floor".into(), points: pts, rgb: (220, 30, 40), width: 2 });
    }
    crate::output::plots::time(
        dir,
        "energy",
        &TimePlot {
            title: "Battery: energy required to finish and charge".into(),
            x_label: time_axis_name(ctx),
            y_label: "Wh above the battery floor".into(),
            series: eseries,
            nights: night.to_vec(),
            x_range: (0.0, end_s / 3600.0),
            windows: Vec::new(),
            windows_label: String::new(),
            dots: false,
            x_ticks: time_ticks(ctx),
        },
    )
}

/// A route plot framed on its routes and markers: their bounding box with a margin, on
/// whole cells of `dem`, over `background` (RGB, the whole map).
fn framed(dem: &Dem, background: &[u8], series: Vec<Series>, markers: Vec<Marker>, title: String) -> RoutePlot {
    let (dx, dy) = (dem.dx(), dem.dy());
    let (mut lo, mut hi) = ((f64::INFINITY, f64::INFINITY), (f64::NEG_INFINITY, f64::NEG_INFINITY));
    for p in series.iter().flat_map(|s| s.points.iter()).chain(markers.iter().map(|m| &m.at)) {
        lo = (lo.0.min(p.0), lo.1.min(p.1));
        hi = (hi.0.max(p.0), hi.1.max(p.1));
    }
    let margin = (0.15 * (hi.0 - lo.0).max(hi.1 - lo.1)).max(5.0 * dx.max(dy));
    let col0 = (((lo.0 - margin) / dx).floor().max(0.0) as usize).min(dem.cols() - 1);
    let col1 = (((hi.0 + margin) / dx).ceil() as usize).clamp(col0 + 1, dem.cols());
    // Rows count from the north edge.
    let height_m = dem.rows() as f64 * dy;
    let row0 = (((height_m - hi.1 - margin) / dy).floor().max(0.0) as usize).min(dem.rows() - 1);
    let row1 = (((height_m - lo.1 + margin) / dy).ceil() as usize).clamp(row0 + 1, dem.rows());
    let (cols, rows) = (col1 - col0, row1 - row0);
    let mut crop = Vec::with_capacity(cols * rows * 3);
    for r in row0..row1 {
        let i = 3 * (r * dem.cols() + col0);
        crop.extend_from_slice(&background[i..i + 3 * cols]);
    }
    RoutePlot {
        title,
        background: crop,
        cols,
        rows,
        origin: (col0 as f64 * dx, height_m - row1 as f64 * dy),
        extent: (cols as f64 * dx, rows as f64 * dy),
        series,
        markers,
    }
}

/// Off Mars: the safe havens under the plan (`havens.png`), then [`sky_plot`].
fn haven_plots(
    dir: &Path,
    ctx: &Context<'_>,
    plan: &MissionPlan,
    havens: &contact::Havens,
    series: Vec<Series>,
    mut markers: Vec<Marker>,
) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let world = ctx.world;
    let dem = world.dem();
    let slope = areo_terrain::slope::slope_aspect(dem);
    let sun = world.sun(0.0);
    let mut rgb =
        areo_terrain::hillshade::hillshade_rgb(dem, &slope, None, sun.azimuth_deg, sun.elevation_deg.max(5.0));
    // Havens tinted green, ground the Sun leaves dark longer than a battery lasts
    // tinted blue.
    for (i, px) in rgb.chunks_exact_mut(3).enumerate() {
        let tint = if havens.haven[i] {
            Some((40u16, 200u16, 80u16))
        } else if world.passable(i as u32) {
            Some((40, 60, 200))
        } else {
            None
        };
        if let Some((r, g, b)) = tint {
            px[0] = ((u16::from(px[0]) + r) / 2) as u8;
            px[1] = ((u16::from(px[1]) + g) / 2) as u8;
            px[2] = ((u16::from(px[2]) + b) / 2) as u8;
        }
    }
    for w in contact::waits(plan, havens, floor_wh(ctx), HAVEN_STEP_S) {
        markers.push(Marker {
            label: format!("wait {:.1} h", w.to_h - w.from_h),
            at: ctx.local(w.cell),
            rgb: if w.haven { (20, 140, 40) } else { (200, 40, 40) },
        });
    }
    let title = format!(
        "Safe havens (green): shadows under {:.0} h{}",
        havens.survive_h.min(1e6),
        if ctx.model.needs_earth() { ", the Earth never lost longer than the contact interval" } else { "" }
    );
    files.extend(crate::output::plots::route(dir, "havens", &framed(dem, &rgb, series, markers, title))?);
    files.extend(sky_plot(dir, ctx, plan)?);
    Ok(files)
}

/// The Sun and the Earth over the plan, at the site, with the Communicate sessions
/// shaded (`sky.png`).
fn sky_plot(dir: &Path, ctx: &Context<'_>, plan: &MissionPlan) -> Result<Vec<PathBuf>> {
    let world = ctx.world;
    let end_s = plan.waypoints.last().map_or(world.span_s(), |w| w.t_s).max(3600.0);
    let n = ((end_s / CONTACT_STEP_S).ceil() as usize).max(2);
    let hours = |k: usize| end_s * k as f64 / n as f64;
    let mut sky = vec![Series {
        label: "Sun elevation, °".into(),
        points: (0..=n).map(|k| (hours(k) / 3600.0, world.sun(hours(k)).elevation_deg)).collect(),
        rgb: (230, 160, 20),
        width: 2,
    }];
    if world.earth(0.0).is_some() {
        sky.push(Series {
            label: "Earth elevation, °".into(),
            points: (0..=n).filter_map(|k| Some((hours(k) / 3600.0, world.earth(hours(k))?.elevation_deg))).collect(),
            rgb: (30, 90, 220),
            width: 2,
        });
    }
    let sessions: Vec<(f64, f64)> = ctx
        .model
        .sessions()
        .iter()
        .map(|&(a, b)| (a / 3600.0, b / 3600.0))
        .filter(|&(a, _)| a <= end_s / 3600.0)
        .collect();
    crate::output::plots::time(
        dir,
        "sky",
        &TimePlot {
            title: format!(
                "The Sun{} over the plan, at the site",
                if world.earth(0.0).is_some() { " and the Earth" } else { "" }
            ),
            x_label: time_axis_name(ctx),
            y_label: "elevation, degrees".into(),
            series: sky,
            nights: nights(world, end_s),
            x_range: (0.0, end_s / 3600.0),
            windows: sessions,
            windows_label: "Communicate session".into(),
            dots: false,
            x_ticks: time_ticks(ctx),
        },
    )
}

fn floor_wh(ctx: &Context<'_>) -> f64 {
    let b = &ctx.model.rover().battery;
    b.capacity_wh * b.min_soc
}
