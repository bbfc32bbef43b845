//! The plan viewer's data ([`ViewData`]): the true terrain shaded and its direct sun at
//! instants across the run, downsampled by whole cells; the routes, goals and the
//! rover's track in the image's pixels.

use base64::Engine;

use super::*;
use crate::report::Raster;
use crate::report::view::{
    VIEW_FRAMES, VIEW_PIXELS, ViewClasses, ViewData, ViewGeo, ViewPlace, ViewRoute, ViewTrackPoint,
};
use areo_mission::UNCLASSIFIED;
use areo_terrain::Projection;

/// The viewer's data for the initial plan and, with a simulation, the run.
pub(super) fn view(ctx: &Context<'_>, initial: &MissionPlan, sim: Option<&SimReport>) -> ViewData {
    let truth = ctx.truth;
    let (cols, rows) = (truth.cols(), truth.rows());
    let ((c0, r0), (c1, r1)) = frame(ctx, initial, sim);
    let k = (c1 - c0).max(r1 - r0).div_ceil(VIEW_PIXELS).max(1);
    let (w, h) = ((c1 - c0).div_ceil(k), (r1 - r0).div_ceil(k));
    // The cell at each pixel: its block's north-west cell.
    let cells: Vec<u32> = (0..h)
        .flat_map(|y| (0..w).map(move |x| truth.cell((c0 + x * k).min(cols - 1), (r0 + y * k).min(rows - 1))))
        .collect();
    let px = |cell: u32| {
        let (c, r) = truth.col_row(cell);
        ((c as f64 - c0 as f64 + 0.5) / k as f64, (r as f64 - r0 as f64 + 0.5) / k as f64)
    };
    let place = |name: &str, cell: u32| {
        let (x, y) = px(cell);
        ViewPlace { name: name.to_string(), x, y }
    };
    let (track, routes) = match sim {
        Some(r) => (executed_track(ctx, r, &px), routes(initial, Some(r), &px)),
        None => (planned_track(ctx, initial, &px), routes(initial, None, &px)),
    };
    let (t0, t1) = (track.first().map_or(0.0, |p| p.unix_s), track.last().map_or(0.0, |p| p.unix_s));
    let epoch_unix = truth.epoch().to_unix_seconds();
    let times = frame_times(t0, t1);
    let sun_at = |t: f64| ctx.world.sun((t - epoch_unix).clamp(0.0, ctx.world.span_s())).elevation_deg;
    let lon = truth.lat_lon(ctx.start.cell).1;
    let rover = rover_cells(initial, sim, ctx.start.cell);
    let earth = (truth.body() != areo_ephemeris::Body::Earth)
        .then(|| times.iter().map(|&t| truth.earth_visible(cell_at(&rover, t - epoch_unix), t - epoch_unix)).collect());
    ViewData {
        name: ctx.name.to_string(),
        body: format!("{:?}", truth.body()),
        map_cols_rows: (cols, rows),
        origin_cells: (c0, r0),
        cells_per_pixel: k,
        cell_m: (truth.dem().dx(), truth.dem().dy()),
        hillshade: hillshade(truth, &cells, (w, h)),
        elevation_m: floats(cells.iter().map(|&c| truth.elevation(c).map_or(f32::NAN, |z| z as f32))),
        slope_deg: floats(cells.iter().map(|&c| truth.slope_deg(c) as f32)),
        north_deg: {
            let middle = cells.get((h / 2) * w + w / 2).copied().unwrap_or(ctx.start.cell);
            truth.dem().georef().projection.true_north_on_grid_deg(truth.lat_lon(middle).1)
        },
        battery_floor_wh: floor_wh(ctx),
        battery_capacity_wh: ctx.model.rover().battery.capacity_wh,
        frame_sun_elevation_deg: times.iter().map(|&t| sun_at(t)).collect(),
        frame_utc: times.iter().map(|&t| format_utc(truth.epoch() + Duration::from_seconds(t - epoch_unix))).collect(),
        frames: times.iter().map(|&t| direct_sun(truth, &cells, t - epoch_unix)).collect(),
        no_go: ctx.no_go.filter(|c| c.len() == truth.cells()).map(|codes| {
            let mut bits = vec![0u8; cells.len().div_ceil(8)];
            for (i, &c) in cells.iter().enumerate() {
                if codes[c as usize] != super::no_go::FREE {
                    bits[i / 8] |= 1 << (i % 8);
                }
            }
            base64::engine::general_purpose::STANDARD.encode(bits)
        }),
        classes: truth.ground().filter(|g| g.cells() == truth.cells()).map(|g| ViewClasses {
            names: g.classes().iter().map(|c| c.name.clone()).collect(),
            pixels: base64::engine::general_purpose::STANDARD
                .encode(cells.iter().map(|&c| g.class_index(c).unwrap_or(UNCLASSIFIED)).collect::<Vec<u8>>()),
        }),
        routes,
        start: place("start", ctx.start.cell),
        goals: ctx.goals.iter().enumerate().map(|(i, &g)| place(ctx.goal_name(i), g)).collect(),
        track,
        geo: geo(truth),
        frame_ltst_h: times.iter().map(|&t| truth.local_solar_time_h(t - epoch_unix, lon)).collect(),
        frame_sol: times.iter().map(|&t| truth.local_sol(t - epoch_unix, lon)).collect(),
        frame_earth_in_view: earth,
        sessions: ctx.model.sessions().iter().map(|&(a, b)| (a + epoch_unix, b + epoch_unix)).collect(),
        frame_unix_s: times,
    }
}

/// The map's projection on its sphere, for the viewer's latitude and longitude.
fn geo(truth: &World) -> ViewGeo {
    let g = truth.dem().georef();
    let (projection, lat_ts_deg, lon0_deg) = match g.projection {
        Projection::Equirectangular { lat_ts_deg, lon0_deg } => ("equirectangular", lat_ts_deg, lon0_deg),
        Projection::PolarStereographic { north: true, lon0_deg } => ("polar_north", 90.0, lon0_deg),
        Projection::PolarStereographic { north: false, lon0_deg } => ("polar_south", -90.0, lon0_deg),
        Projection::Local => ("local", 0.0, 0.0),
    };
    ViewGeo {
        projection: projection.to_string(),
        radius_m: g.surface.equatorial_radius_m,
        lat_ts_deg,
        lon0_deg,
        x0_m: truth.dem().x0(),
        y_top_m: truth.dem().y_top(),
        crs_name: g.geographic().name,
    }
}

/// Where the rover is from when, s after the epoch: the plan's waypoints, or with a
/// simulation where each action ended.
fn rover_cells(initial: &MissionPlan, sim: Option<&SimReport>, start: u32) -> Vec<(f64, u32)> {
    match sim {
        Some(r) => std::iter::once((r.start.t_min, r.start.cell))
            .chain(r.steps.iter().map(|s| (s.t_s + s.duration_s, s.to)))
            .collect(),
        None if initial.waypoints.is_empty() => vec![(0.0, start)],
        None => initial.waypoints.iter().map(|w| (w.t_s, w.cell)).collect(),
    }
}

/// The cell the rover is at `t_s` after the epoch (the last it reached by then).
fn cell_at(rover: &[(f64, u32)], t_s: f64) -> u32 {
    let k = rover.partition_point(|&(t, _)| t <= t_s);
    rover[k.saturating_sub(1)].1
}

/// The run's first and last instants on `view`'s track, s after the epoch.
pub(super) fn span_s(ctx: &Context<'_>, view: &ViewData) -> (f64, f64) {
    let epoch = ctx.truth.epoch().to_unix_seconds();
    let at = |p: Option<&ViewTrackPoint>| p.map_or(0.0, |p| p.unix_s - epoch);
    (at(view.track.first()), at(view.track.last()))
}

/// The cells the image shows, (north-west, south-east exclusive): every route's cells,
/// the start and the goals, with a margin of a sixth of their span (at least 20 cells),
/// within the map.
fn frame(ctx: &Context<'_>, initial: &MissionPlan, sim: Option<&SimReport>) -> ((usize, usize), (usize, usize)) {
    let world = ctx.truth;
    let mut cells: Vec<u32> = initial.waypoints.iter().map(|w| w.cell).collect();
    cells.push(ctx.start.cell);
    cells.extend(ctx.goals.iter().copied());
    if let Some(r) = sim {
        cells.extend(r.steps.iter().map(|s| s.to));
        cells.extend(r.plans.iter().flat_map(|p| p.plan.waypoints.iter().map(|w| w.cell)));
    }
    let (mut lo, mut hi) = ((usize::MAX, usize::MAX), (0, 0));
    for c in cells {
        let (col, row) = world.col_row(c);
        (lo, hi) = ((lo.0.min(col), lo.1.min(row)), (hi.0.max(col), hi.1.max(row)));
    }
    let margin = ((hi.0 - lo.0).max(hi.1 - lo.1) / 6).max(20);
    let lo = (lo.0.saturating_sub(margin), lo.1.saturating_sub(margin));
    let hi = ((hi.0 + margin + 1).min(world.cols()), (hi.1 + margin + 1).min(world.rows()));
    (lo, hi)
}

/// The frames' instants: every ten minutes or more from `t0` to `t1`, at most
/// [`VIEW_FRAMES`] of them.
fn frame_times(t0: f64, t1: f64) -> Vec<f64> {
    let step = ((t1 - t0) / (VIEW_FRAMES - 1) as f64).max(600.0);
    let n = (((t1 - t0) / step).floor() as usize + 1).min(VIEW_FRAMES);
    (0..n).map(|i| t0 + i as f64 * step).collect()
}

/// Values as base64 of little-endian float32.
fn floats(values: impl Iterator<Item = f32>) -> String {
    base64::engine::general_purpose::STANDARD.encode(values.flat_map(f32::to_le_bytes).collect::<Vec<u8>>())
}

/// The terrain shaded from the north-west at 45°, grey, at `cells`.
fn hillshade(truth: &World, cells: &[u32], (w, h): (usize, usize)) -> Raster<u8> {
    let dem = truth.dem();
    let slope = areo_terrain::slope::slope_aspect(dem);
    let rgb = areo_terrain::hillshade::hillshade_rgb(dem, &slope, None, 315.0, 45.0);
    let values = cells.iter().map(|&c| rgb[3 * c as usize + 1]).collect();
    Raster { cols: w, rows: h, values }
}

/// Direct sun at `cells` at `t_s` after the epoch, as a base64 bitset.
fn direct_sun(truth: &World, cells: &[u32], t_s: f64) -> String {
    let sun = truth.sun(t_s.clamp(0.0, truth.span_s()));
    let mut bits = vec![0u8; cells.len().div_ceil(8)];
    for (i, &c) in cells.iter().enumerate() {
        if truth.lit(c, &sun) && truth.sun_above_ground_deg(c, &sun) > 0.0 {
            bits[i / 8] |= 1 << (i % 8);
        }
    }
    base64::engine::general_purpose::STANDARD.encode(bits)
}

/// A track point at `cell` at `t_s` after the epoch.
fn track_point(
    ctx: &Context<'_>,
    px: &dyn Fn(u32) -> (f64, f64),
    at: (u32, f64),
    battery_wh: f64,
    activity: &str,
) -> ViewTrackPoint {
    let (cell, t_s) = at;
    let (x, y) = px(cell);
    let when = ctx.world.epoch() + Duration::from_seconds(t_s);
    ViewTrackPoint {
        unix_s: when.to_unix_seconds(),
        utc: format_utc(when),
        x,
        y,
        battery_wh,
        sun_elevation_deg: ctx.world.sun(t_s.clamp(0.0, ctx.world.span_s())).elevation_deg,
        activity: activity.to_string(),
    }
}

/// The executed run: the start, then where and when each action ended.
fn executed_track(ctx: &Context<'_>, r: &SimReport, px: &dyn Fn(u32) -> (f64, f64)) -> Vec<ViewTrackPoint> {
    let floor = floor_wh(ctx);
    let first = track_point(ctx, px, (r.start.cell, r.start.t_min), r.start.energy_wh + floor, "start");
    let ends = (r.steps.iter())
        .map(|s| track_point(ctx, px, (s.to, s.t_s + s.duration_s), s.battery_above_floor_wh + floor, s.action.name()));
    std::iter::once(first).chain(ends).collect()
}

/// The plan's waypoints, each with what comes next.
fn planned_track(ctx: &Context<'_>, plan: &MissionPlan, px: &dyn Fn(u32) -> (f64, f64)) -> Vec<ViewTrackPoint> {
    (plan.waypoints.iter())
        .map(|w| track_point(ctx, px, (w.cell, w.t_s), w.battery_wh, action_name(w.action)))
        .collect()
}

/// The initial plan, the re-plans that changed the route (at most six, spread out) and
/// the executed route.
fn routes(initial: &MissionPlan, sim: Option<&SimReport>, px: &dyn Fn(u32) -> (f64, f64)) -> Vec<ViewRoute> {
    let route = |name: String, kind: &str, cells: &mut dyn Iterator<Item = u32>| ViewRoute {
        name,
        kind: kind.to_string(),
        points: cells.map(px).collect(),
    };
    let mut out = vec![route("initial plan".into(), "plan", &mut initial.waypoints.iter().map(|w| w.cell))];
    if let Some(r) = sim {
        let changed: Vec<_> = r.plans.iter().filter(|p| p.kind != PlanKind::Initial && p.route_changed).collect();
        for p in changed.iter().step_by(changed.len().div_ceil(6).max(1)) {
            let name = format!("re-plan after action {}", p.step);
            out.push(route(name, "replan", &mut p.plan.waypoints.iter().map(|w| w.cell)));
        }
        let mut cells = std::iter::once(r.start.cell).chain(r.steps.iter().map(|s| s.to));
        out.push(route("executed route".into(), "executed", &mut cells));
    }
    out
}
