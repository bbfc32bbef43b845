//! A TEMPEST report's files written from the report alone: the plan and the run
//! (`plan.json`, `simulation.json`), the tables (`plan.csv`, `executed.csv`,
//! `replans.csv`, `waits.csv`, each column at the decimals its CSV row type gives; the
//! two with latitudes with a `.prj` naming their CRS), the
//! routes (`route.geojson`, `route.kml`), the map layers as Cloud-Optimized GeoTIFFs
//! (`dem.tif`, `slope.tif`, `direct_sun.tif`), the Monte Carlo's and the Pareto front's tables (`monte_carlo.csv`,
//! `pareto_front.csv`, `pareto_front.json`) and the plots.

use std::path::{Path, PathBuf};

use geojson::FeatureCollection;
use serde::Serialize;
use serde_json::json;

use crate::error::Result;
use crate::output::csv::{Fixed, write_rows};
use crate::output::geojson::{collection, feature, line, point};
use crate::output::{bands, json_for, write_file, write_with};
use areo_terrain::geotiff;

/// The direct-sun layer's value where the map has no data.
const NO_DATA: u8 = 255;
use crate::report::tempest::{
    ExecutedRow, FrontRow, MapLayers, MonteCarloRow, PlanRow, ReplanRow, RoutePlaces, TempestReport, WaitRow,
};

/// Writes the files into `dir`; returns them (none without a plan).
pub(crate) fn write(dir: &Path, r: &TempestReport) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let Some(plan) = &r.plan else { return Ok(files) };
    let mut put = |name: &str, write: &dyn Fn(&Path) -> Result<()>| -> Result<()> {
        let path = dir.join(name);
        write(&path)?;
        files.push(path);
        Ok(())
    };
    let t = &r.tables;
    put("plan.json", &|p| write_file(p, json_for(p, plan, true)?.as_bytes()))?;
    put("plan.csv", &|p| write_rows(p, t.plan.iter().map(PlanCsv::from)))?;
    // A table's lat_deg/lon_deg are on the run's CRS: its WKT2 in a `.prj` of the same
    // stem, where GDAL's CSV driver (GeoCSV) reads a layer's CRS.
    let prj = |p: &Path| match &r.route {
        Some(route) => write_file(p, format!("{}\n", route.geography.crs_wkt2).as_bytes()),
        None => Ok(()),
    };
    if r.route.is_some() {
        put("plan.prj", &prj)?;
    }
    if let Some(sim) = &r.simulation {
        put("simulation.json", &|p| write_file(p, json_for(p, sim, false)?.as_bytes()))?;
    }
    if let Some(rows) = &t.executed {
        put("executed.csv", &|p| write_rows(p, rows.iter().map(ExecutedCsv::from)))?;
        if r.route.is_some() {
            put("executed.prj", &prj)?;
        }
    }
    if let Some(rows) = &t.replans {
        put("replans.csv", &|p| write_rows(p, rows.iter().map(ReplanCsv::from)))?;
    }
    if let Some(route) = &r.route {
        put("route.geojson", &|p| crate::output::geojson::write(p, &route_geojson(r, route)))?;
        put("route.kml", &|p| route_kml(r, route).write(p))?;
        let timed = super::tempest_time::route_time_geojson(r, route);
        put("route_time.geojson", &|p| write_file(p, json_for(p, &timed, true)?.as_bytes()))?;
        let layer = super::tempest_time::route_time_mmgis_layer(&route.run);
        put("route_time.mmgis.json", &|p| write_file(p, json_for(p, &layer, true)?.as_bytes()))?;
        let czml = super::tempest_time::route_czml(r, route);
        put("route.czml", &|p| write_file(p, json_for(p, &czml, true)?.as_bytes()))?;
        put("route.cesium.html", &|p| write_file(p, super::tempest_time::route_cesium_page(p, &czml)?.as_bytes()))?;
    }
    if let Some(rows) = &t.waits {
        put("waits.csv", &|p| write_rows(p, rows.iter().map(WaitCsv::from)))?;
    }
    if let Some(l) = &r.layers {
        write_layers(r, l, &mut put)?;
    }
    if let Some(rows) = &t.monte_carlo {
        put("monte_carlo.csv", &|p| write_rows(p, rows.iter().map(MonteCarloCsv::from)))?;
    }
    if let Some(rows) = &t.pareto_front {
        put("pareto_front.csv", &|p| write_rows(p, rows.iter().map(FrontCsv::from)))?;
    }
    if let Some(plans) = &r.pareto_plans {
        put("pareto_front.json", &|p| write_file(p, json_for(p, plans, true)?.as_bytes()))?;
    }
    if let Some(view) = &r.view {
        put("view.html", &|p| super::view::write(p, view, r.simulation.is_some()).map(|_| ()))?;
    }
    for plot in &r.plots {
        files.extend(crate::output::plots::write(dir, plot)?);
    }
    if let Some(layers) = &r.layers {
        files.extend(super::shadows::write(dir, layers)?);
    }
    Ok(files)
}

/// Writes one file by its name with the function given (and lists it).
type Put<'a> = dyn FnMut(&str, &dyn Fn(&Path) -> Result<()>) -> Result<()> + 'a;

/// The map layers as Cloud-Optimized GeoTIFFs, each band saying what it holds
/// (`output::bands`), with the names of the codes of the class and mask layers beside
/// them.
fn write_layers(r: &TempestReport, l: &MapLayers, put: &mut Put<'_>) -> Result<()> {
    // Cloud-Optimized GeoTIFFs: tiled, with overviews, for map servers as for GIS.
    let (elevation, slope) = (&bands::ELEVATION, &bands::SLOPE);
    put("dem.tif", &|p| {
        write_with(p, |tmp| Ok(geotiff::write_cog_f32(&l.grid, &l.elevation_m.values, elevation, tmp)?))
    })?;
    put("slope.tif", &|p| write_with(p, |tmp| Ok(geotiff::write_cog_f32(&l.grid, &l.slope_deg.values, slope, tmp)?)))?;
    put("direct_sun.tif", &|p| {
        let (grid, values, at) =
            (&l.shadow_grid, &l.direct_sun.values, (l.direct_sun_utc.as_str(), &bands::DIRECT_SUN));
        write_with(p, |tmp| Ok(geotiff::write_cog_u8_at(grid, values, Some(NO_DATA), at, tmp)?))
    })?;
    if let Some(no_go) = &l.no_go {
        put("no_go.tif", &|p| {
            write_with(p, |tmp| Ok(geotiff::write_cog_u8(&l.grid, &no_go.values, None, &bands::NO_GO, tmp)?))
        })?;
        let names: Vec<(u8, &str)> = (0u8..).zip(bands::NO_GO_NAMES).collect();
        put("no_go.tif.aux.xml", &|p| write_file(p, bands::category_sidecar(&names).as_bytes()))?;
    }
    if let Some(classes) = &l.classes {
        let named: Vec<(u8, &str)> = r
            .terrain_classes
            .as_ref()
            .map(|t| t.classes.iter().map(|(name, c)| (c.id, name.as_str())).collect())
            .unwrap_or_default();
        let ids: Vec<u8> = named.iter().map(|&(id, _)| id).collect();
        let colours = bands::class_colours(&ids);
        let band = geotiff::Band { description: bands::CLASSES, unit: "", colours: &colours };
        put("classes.tif", &|p| {
            write_with(p, |tmp| Ok(geotiff::write_cog_u8(&l.grid, &classes.values, Some(255), &band, tmp)?))
        })?;
        put("classes.tif.aux.xml", &|p| write_file(p, bands::category_sidecar(&named).as_bytes()))?;
    }
    Ok(())
}

/// A row of monte_carlo.csv.
#[derive(Serialize, Default)]
struct MonteCarloCsv<'a> {
    plan: &'a str,
    run: usize,
    succeeded: bool,
    failure: &'a str,
    failed_at_action: &'a str,
    goals_reached: usize,
    last_arrival_h: Option<Fixed<3>>,
    lowest_battery_wh: Fixed<2>,
}

impl<'a> From<&'a MonteCarloRow> for MonteCarloCsv<'a> {
    fn from(r: &'a MonteCarloRow) -> MonteCarloCsv<'a> {
        MonteCarloCsv {
            plan: &r.plan,
            run: r.run,
            succeeded: r.succeeded,
            failure: &r.failure,
            failed_at_action: &r.failed_at_action,
            goals_reached: r.goals_reached,
            last_arrival_h: r.last_arrival_h.map(Fixed),
            lowest_battery_wh: Fixed(r.lowest_battery_wh),
        }
    }
}

/// A row of pareto_front.csv.
#[derive(Serialize, Default)]
struct FrontCsv<'a> {
    plan: usize,
    departure_utc: &'a str,
    departure_h: Fixed<3>,
    arrival_utc: &'a str,
    arrival_h: Fixed<3>,
    duration_h: Fixed<3>,
    energy_used_wh: Fixed<2>,
    margin_wh: Fixed<2>,
    lowest_battery_wh: Fixed<2>,
    drives: usize,
    charges: usize,
    hibernations: usize,
}

impl<'a> From<&'a FrontRow> for FrontCsv<'a> {
    fn from(r: &'a FrontRow) -> FrontCsv<'a> {
        FrontCsv {
            plan: r.plan,
            departure_utc: &r.departure_utc,
            departure_h: Fixed(r.departure_h),
            arrival_utc: &r.arrival_utc,
            arrival_h: Fixed(r.arrival_h),
            duration_h: Fixed(r.duration_h),
            energy_used_wh: Fixed(r.energy_used_wh),
            margin_wh: Fixed(r.margin_wh),
            lowest_battery_wh: Fixed(r.lowest_battery_wh),
            drives: r.drives,
            charges: r.charges,
            hibernations: r.hibernations,
        }
    }
}

/// The routes, start and goals as KML for Google Earth (with the body's hint).
fn route_kml(r: &TempestReport, route: &RoutePlaces) -> crate::output::kml::Kml {
    let mut kml = crate::output::kml::Kml::new("areo TEMPEST route", &route.geography);
    kml.line("initial plan", "ffdc5a1e", r.tables.plan.iter().map(|w| (w.lat_deg, w.lon_deg)));
    if let Some(cells) = &route.executed {
        kml.line("executed route", "ff281edc", cells.iter().copied());
    }
    let start = &route.start;
    kml.point("start", &format!("start at {}", start.utc.as_deref().unwrap_or("")), (start.lat_deg, start.lon_deg));
    for (i, g) in route.goals.iter().enumerate() {
        let description = match &g.utc {
            Some(t) => format!("goal {} of the plan, reached at {t}", i + 1),
            None => format!("goal {} of the plan", i + 1),
        };
        kml.point(&g.name, &description, (g.lat_deg, g.lon_deg));
    }
    kml
}

/// The routes as GeoJSON: every point says where and when it is as a mission counts it,
/// beside its charge (absolute, and above the floor: the search's E).
fn route_geojson(r: &TempestReport, route: &RoutePlaces) -> FeatureCollection {
    let floor = r.battery_floor_wh;
    let plan = &r.tables.plan;
    let mut features =
        vec![feature(line(plan.iter().map(|w| (w.lat_deg, w.lon_deg))), json!({"name": "initial plan"}))];
    match (&route.executed, &r.tables.executed) {
        (Some(cells), Some(steps)) => {
            features.push(feature(line(cells.iter().copied()), json!({"name": "executed route"})));
            for s in steps {
                let props = json!({"kind": "executed", "step": s.step, "action": s.action, "energy_wh": s.energy_wh});
                let when = When { utc: &s.utc, t_s: s.t_s, sol: s.sol, ltst_h: s.ltst_h, elevation_m: s.elevation_m };
                features.push(located((s.lat_deg, s.lon_deg), props, &when, s.battery_above_floor_wh, floor));
            }
        }
        _ => {
            for w in plan {
                let props =
                    json!({"kind": "waypoint", "index": w.index, "action": w.action, "required_wh": w.required_wh});
                let when = When { utc: &w.utc, t_s: w.t_s, sol: w.sol, ltst_h: w.ltst_h, elevation_m: w.elevation_m };
                features.push(located((w.lat_deg, w.lon_deg), props, &when, w.battery_wh - floor, floor));
            }
        }
    }
    let start = &route.start;
    features.push(feature(point((start.lat_deg, start.lon_deg)), json!({"kind": "start", "name": "start"})));
    for (i, g) in route.goals.iter().enumerate() {
        features.push(feature(point((g.lat_deg, g.lon_deg)), json!({"kind": "goal", "name": g.name, "order": i})));
    }
    collection(features, &route.geography)
}

/// Where in time a point of the route is, as a mission counts it.
struct When<'a> {
    utc: &'a str,
    t_s: f64,
    sol: i64,
    ltst_h: f64,
    elevation_m: f64,
}

/// A point feature at `at` with `properties`, its time and place, and its charge.
fn located(
    at: (f64, f64),
    mut properties: serde_json::Value,
    when: &When<'_>,
    above_floor_wh: f64,
    floor_wh: f64,
) -> geojson::Feature {
    let extra = json!({
        "utc": when.utc, "t_h": when.t_s / 3600.0, "sol": when.sol, "ltst_h": when.ltst_h,
        "elevation_m": when.elevation_m,
        "battery_wh": above_floor_wh + floor_wh, "battery_above_floor_wh": above_floor_wh,
    });
    if let (Some(o), serde_json::Value::Object(e)) = (properties.as_object_mut(), extra) {
        o.extend(e);
    }
    feature(point(at), properties)
}

/// A row of plan.csv.
#[derive(Serialize, Default)]
struct PlanCsv {
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
    action: String,
    end_utc: String,
    duration_s: Fixed<1>,
    energy_drawn_wh: Fixed<3>,
    battery_change_wh: Fixed<3>,
    required_wh: Fixed<3>,
    battery_wh: Fixed<3>,
    slope_deg: Fixed<3>,
    pitch_deg: Option<Fixed<3>>,
    roll_deg: Option<Fixed<3>>,
    class: String,
    sun_elevation_deg: Fixed<3>,
    sun_above_ground_deg: Fixed<3>,
    lit: u8,
    goal: String,
}

impl From<&PlanRow> for PlanCsv {
    fn from(w: &PlanRow) -> PlanCsv {
        PlanCsv {
            index: w.index,
            utc: w.utc.clone(),
            t_s: Fixed(w.t_s),
            sol: w.sol,
            ltst_h: Fixed(w.ltst_h),
            col: w.col,
            row: w.row,
            x_m: Fixed(w.x_m),
            y_m: Fixed(w.y_m),
            lat_deg: Fixed(w.lat_deg),
            lon_deg: Fixed(w.lon_deg),
            elevation_m: Fixed(w.elevation_m),
            action: w.action.clone(),
            end_utc: w.end_utc.clone(),
            duration_s: Fixed(w.duration_s),
            energy_drawn_wh: Fixed(w.energy_drawn_wh),
            battery_change_wh: Fixed(w.battery_change_wh),
            required_wh: Fixed(w.required_wh),
            battery_wh: Fixed(w.battery_wh),
            slope_deg: Fixed(w.slope_deg),
            pitch_deg: w.pitch_deg.map(Fixed),
            roll_deg: w.roll_deg.map(Fixed),
            class: w.class.clone(),
            sun_elevation_deg: Fixed(w.sun_elevation_deg),
            sun_above_ground_deg: Fixed(w.sun_above_ground_deg),
            lit: u8::from(w.lit),
            goal: w.goal.clone(),
        }
    }
}

/// A row of executed.csv.
#[derive(Serialize, Default)]
struct ExecutedCsv {
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
    action: String,
    duration_s: Fixed<1>,
    end_utc: String,
    energy_wh: Fixed<3>,
    energy_drawn_wh: Fixed<3>,
    battery_wh: Fixed<3>,
    battery_above_floor_wh: Fixed<3>,
    distance_m: Fixed<3>,
    pitch_deg: Option<Fixed<3>>,
    roll_deg: Option<Fixed<3>>,
    class: String,
    sun_elevation_deg: Fixed<3>,
    refused: String,
}

impl From<&ExecutedRow> for ExecutedCsv {
    fn from(s: &ExecutedRow) -> ExecutedCsv {
        ExecutedCsv {
            step: s.step,
            utc: s.utc.clone(),
            t_s: Fixed(s.t_s),
            sol: s.sol,
            ltst_h: Fixed(s.ltst_h),
            col: s.col,
            row: s.row,
            x_m: Fixed(s.x_m),
            y_m: Fixed(s.y_m),
            lat_deg: Fixed(s.lat_deg),
            lon_deg: Fixed(s.lon_deg),
            elevation_m: Fixed(s.elevation_m),
            action: s.action.clone(),
            duration_s: Fixed(s.duration_s),
            end_utc: s.end_utc.clone(),
            energy_wh: Fixed(s.energy_wh),
            energy_drawn_wh: Fixed(s.energy_drawn_wh),
            battery_wh: Fixed(s.battery_wh),
            battery_above_floor_wh: Fixed(s.battery_above_floor_wh),
            distance_m: Fixed(s.distance_m),
            pitch_deg: s.pitch_deg.map(Fixed),
            roll_deg: s.roll_deg.map(Fixed),
            class: s.class.clone(),
            sun_elevation_deg: Fixed(s.sun_elevation_deg),
            refused: s.refused.clone(),
        }
    }
}

/// A row of replans.csv.
#[derive(Serialize, Default)]
struct ReplanCsv {
    step: usize,
    kind: String,
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
    fresh_check: Option<String>,
    restart_binding: Option<String>,
    restart_replan_work: Option<u64>,
    restart_fresh_found: Option<u8>,
}

impl From<&ReplanRow> for ReplanCsv {
    fn from(p: &ReplanRow) -> ReplanCsv {
        ReplanCsv {
            step: p.step,
            kind: p.kind.clone(),
            utc: p.utc.clone(),
            t_s: Fixed(p.t_s),
            wall_ms: Fixed(p.wall_ms),
            expansions: p.expansions,
            changed_cells: p.changed_cells,
            route_changed: u8::from(p.route_changed),
            waypoints: p.waypoints,
            cost: Fixed(p.cost),
            duration_h: Fixed(p.duration_h),
            min_battery_wh: Fixed(p.min_battery_wh),
            search_mb: Fixed(p.search_mb),
            fresh_expansions: p.fresh_expansions,
            fresh_cost: p.fresh_cost.map(Fixed),
            fresh_check: p.fresh_check.clone(),
            restart_binding: p.restart_binding.clone(),
            restart_replan_work: p.restart_replan_work,
            restart_fresh_found: p.restart_fresh_found.map(u8::from),
        }
    }
}

/// A row of waits.csv.
#[derive(Serialize, Default)]
struct WaitCsv {
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

impl From<&WaitRow> for WaitCsv {
    fn from(w: &WaitRow) -> WaitCsv {
        WaitCsv {
            x_m: Fixed(w.x_m),
            y_m: Fixed(w.y_m),
            from_h: Fixed(w.from_h),
            to_h: Fixed(w.to_h),
            hours: Fixed(w.hours),
            lowest_battery_above_floor_wh: Fixed(w.lowest_battery_above_floor_wh),
            safe_haven: w.safe_haven,
            longest_shadow_h: Fixed(w.longest_shadow_h),
            longest_earth_loss_h: Fixed(w.longest_earth_loss_h),
        }
    }
}
