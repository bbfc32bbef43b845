//! What the TEMPEST report shows of the plan and the run: the plan, executed, waits
//! and re-plan tables, the route's places, and the plots.

use super::*;
use crate::report::tempest::{
    ExecutedRow, PlanRow, ReplanRow, RoutePlaces, RoutePoint, RouteVertex, TempestTables, WaitRow,
};

/// The report's tables of the plan and the simulated run.
pub(super) fn tables(ctx: &Context<'_>, initial: &MissionPlan, sim: Option<&SimReport>) -> TempestTables {
    TempestTables {
        plan: plan_rows(ctx, initial).collect(),
        executed: sim.map(|r| executed_rows(ctx, r).collect()),
        replans: sim.map(|r| replan_rows(ctx, r).collect()),
        waits: ctx.havens.map(|h| wait_rows(ctx, initial, h)),
        monte_carlo: None,
        pareto_front: None,
    }
}

/// The plan's waits with their place, span, lowest charge and whether at a haven.
fn wait_rows(ctx: &Context<'_>, plan: &MissionPlan, havens: &contact::Havens) -> Vec<WaitRow> {
    contact::waits(plan, havens, floor_wh(ctx), HAVEN_STEP_S)
        .into_iter()
        .map(|w| {
            let (x_m, y_m) = ctx.local(w.cell);
            let i = w.cell as usize;
            WaitRow {
                x_m,
                y_m,
                from_h: w.from_h,
                to_h: w.to_h,
                hours: w.to_h - w.from_h,
                lowest_battery_above_floor_wh: w.lowest_battery_above_floor_wh,
                safe_haven: w.haven,
                longest_shadow_h: f64::from(havens.longest_shadow_h[i]),
                longest_earth_loss_h: f64::from(havens.longest_earth_loss_h[i]),
            }
        })
        .collect()
}

pub(super) fn action_name(a: Option<Action>) -> &'static str {
    a.map_or("arrive", Action::name)
}

/// The terrain class of `cell` by name (empty where unclassified or without classes).
fn class_name(world: &World, cell: u32) -> String {
    world.ground().and_then(|g| g.class_of(cell)).map(|c| c.name.clone()).unwrap_or_default()
}

fn plan_rows<'a>(ctx: &'a Context<'_>, plan: &'a MissionPlan) -> impl Iterator<Item = PlanRow> + 'a {
    plan.waypoints.iter().enumerate().map(move |(index, w)| {
        let (x_m, y_m) = ctx.local(w.cell);
        let next = plan.waypoints.get(index + 1).unwrap_or(w);
        PlanRow {
            index,
            utc: w.utc.clone(),
            t_s: w.t_s,
            sol: ctx.world.local_sol(w.t_s, w.lon_deg),
            ltst_h: w.ltst_h,
            col: w.col_row.0,
            row: w.col_row.1,
            x_m,
            y_m,
            lat_deg: w.lat_deg,
            lon_deg: crate::report::lon180(w.lon_deg),
            elevation_m: ctx.world.elevation(w.cell).unwrap_or(f64::NAN),
            action: action_name(w.action).to_string(),
            end_utc: next.utc.clone(),
            duration_s: next.t_s - w.t_s,
            energy_drawn_wh: w.drawn_wh,
            battery_change_wh: next.battery_wh - w.battery_wh,
            required_wh: w.required_wh,
            battery_wh: w.battery_wh,
            slope_deg: w.slope_deg,
            pitch_deg: w.drive_attitude_deg.map(|a| a.0),
            roll_deg: w.drive_attitude_deg.map(|a| a.1),
            class: class_name(ctx.world, w.cell),
            sun_elevation_deg: w.sun_elevation_deg,
            sun_above_ground_deg: w.sun_above_ground_deg,
            lit: w.lit,
            goal: w.goal.map(|g| ctx.goal_name(g).to_string()).unwrap_or_default(),
        }
    })
}

fn executed_rows<'a>(ctx: &'a Context<'_>, r: &'a SimReport) -> impl Iterator<Item = ExecutedRow> + 'a {
    r.steps.iter().enumerate().map(move |(i, st)| {
        let (col, row) = ctx.world.col_row(st.cell);
        let (x_m, y_m) = ctx.local(st.cell);
        let p = ctx.place(st.cell, st.t_s);
        let attitude = match st.action {
            Action::Drive(k) => ctx.truth.drive_attitude_deg(st.cell, k),
            _ => None,
        };
        ExecutedRow {
            step: i + 1,
            utc: format_utc(ctx.world.epoch() + Duration::from_seconds(st.t_s)),
            t_s: st.t_s,
            sol: p.sol,
            ltst_h: p.ltst_h,
            col,
            row,
            x_m,
            y_m,
            lat_deg: p.lat_deg,
            lon_deg: crate::report::lon180(p.lon_deg),
            elevation_m: p.elevation_m,
            action: st.action.name().to_string(),
            duration_s: st.duration_s,
            energy_wh: st.energy_wh,
            energy_drawn_wh: st.load_wh,
            end_utc: format_utc(ctx.world.epoch() + Duration::from_seconds(st.t_s + st.duration_s)),
            battery_wh: st.battery_above_floor_wh + floor_wh(ctx),
            battery_above_floor_wh: st.battery_above_floor_wh,
            distance_m: st.distance_m,
            pitch_deg: attitude.map(|a| a.0),
            roll_deg: attitude.map(|a| a.1),
            class: class_name(ctx.truth, st.cell),
            sun_elevation_deg: st.sun_elevation_deg,
            refused: st.refused.map(|(a, b)| format!("{} ({})", a.name(), b.describe())).unwrap_or_default(),
        }
    })
}

fn replan_rows<'a>(ctx: &'a Context<'_>, r: &'a SimReport) -> impl Iterator<Item = ReplanRow> + 'a {
    r.plans.iter().map(move |p| ReplanRow {
        step: p.step,
        kind: match p.kind {
            PlanKind::Initial => "initial",
            PlanKind::Replan => "replan",
            PlanKind::Restart => "restart",
        }
        .to_string(),
        utc: format_utc(ctx.world.epoch() + Duration::from_seconds(p.t_s)),
        t_s: p.t_s,
        wall_ms: 1e3 * p.wall_s,
        expansions: p.expansions,
        changed_cells: p.changed_cells,
        route_changed: p.route_changed,
        waypoints: p.plan.waypoints.len(),
        cost: p.plan.cost,
        duration_h: p.plan.duration_s() / 3600.0,
        min_battery_wh: p.plan.min_battery_wh(),
        search_mb: p.search_bytes as f64 / 1e6,
        fresh_expansions: p.fresh.map(|f| f.0),
        fresh_cost: p.fresh.map(|f| f.1),
        fresh_check: p.fresh_check.map(|c| {
            match c {
                areo_mission::FreshCheck::Equal => "equal",
                areo_mission::FreshCheck::Windows => "windows",
                areo_mission::FreshCheck::Differs => "differs",
            }
            .to_string()
        }),
        restart_binding: p.restart.as_ref().map(|x| format!("{:?}", x.binding)),
        restart_replan_work: p.restart.as_ref().map(|x| x.replan_work),
        restart_fresh_found: p.restart.as_ref().and_then(|x| x.fresh_found),
    })
}

/// The start, the goals (with when the plan reaches each) and the executed route on the
/// body.
pub(super) fn route_places(ctx: &Context<'_>, initial: &MissionPlan, sim: Option<&SimReport>) -> RoutePlaces {
    let place = |name: &str, cell: u32, utc: Option<String>| {
        let (lat_deg, lon) = ctx.world.lat_lon(cell);
        let lon_deg = crate::report::lon180(lon);
        RoutePoint { name: name.to_string(), lat_deg, lon_deg, elevation_m: ctx.world.elevation(cell), utc }
    };
    let start_utc = format_utc(ctx.world.epoch() + Duration::from_seconds(ctx.start.t_min));
    let goals = (ctx.goals.iter().enumerate())
        .map(|(i, &g)| {
            let reached = initial.waypoints.iter().find(|w| w.goal == Some(i)).map(|w| w.utc.clone());
            place(ctx.goal_name(i), g, reached)
        })
        .collect();
    RoutePlaces {
        run: ctx.name.to_string(),
        geography: crate::report::Geography::of(&ctx.world.dem().georef().surface),
        start: place("start", ctx.start.cell, Some(start_utc)),
        goals,
        executed: sim.map(|r| {
            let cells = std::iter::once(r.start.cell).chain(r.steps.iter().map(|s| s.to));
            cells.map(|c| ctx.world.lat_lon(c)).map(|(lat, lon)| (lat, crate::report::lon180(lon))).collect()
        }),
        timeline: match sim {
            Some(r) => executed_timeline(ctx, r),
            None => planned_timeline(ctx, initial),
        },
    }
}

/// A vertex of the route at `cell` at `t_s`, with the battery and what brought the
/// rover there.
fn vertex(ctx: &Context<'_>, cell: u32, t_s: f64, battery_wh: f64, activity: &str) -> RouteVertex {
    let p = ctx.place(cell, t_s);
    let at = ctx.world.epoch() + Duration::from_seconds(t_s);
    RouteVertex {
        lat_deg: p.lat_deg,
        lon_deg: crate::report::lon180(p.lon_deg),
        elevation_m: p.elevation_m,
        utc: format_utc(at),
        unix_s: at.to_unix_seconds(),
        t_h: ctx.hours(t_s),
        battery_wh,
        sun_elevation_deg: ctx.world.sun(t_s.clamp(0.0, ctx.world.span_s())).elevation_deg,
        activity: activity.to_string(),
    }
}

/// The executed route: the start, then where and when each action ended.
fn executed_timeline(ctx: &Context<'_>, r: &SimReport) -> Vec<RouteVertex> {
    let floor = floor_wh(ctx);
    let first = vertex(ctx, r.start.cell, r.start.t_min, r.start.energy_wh + floor, "start");
    let ends = r
        .steps
        .iter()
        .map(|s| vertex(ctx, s.to, s.t_s + s.duration_s, s.battery_above_floor_wh + floor, s.action.name()));
    std::iter::once(first).chain(ends).collect()
}

/// The initial plan's waypoints, each with what the rover does next.
fn planned_timeline(ctx: &Context<'_>, plan: &MissionPlan) -> Vec<RouteVertex> {
    (plan.waypoints.iter()).map(|w| vertex(ctx, w.cell, w.t_s, w.battery_wh, action_name(w.action))).collect()
}

/// Night intervals (the Sun's centre below the horizontal) over [0, end_s], hours
/// since the epoch.
pub(super) fn nights(world: &World, end_s: f64) -> Vec<(f64, f64)> {
    let start = world.epoch();
    night_intervals(&world.site(), &HorizonMask::flat(), start, start + Duration::from_seconds(end_s))
        .into_iter()
        .map(|(a, b)| ((a - start).to_seconds() / 3600.0, (b - start).to_seconds() / 3600.0))
        .collect()
}

/// The plan's and the run's plots: the routes (and off Mars the havens and the sky),
/// the distance to the final goal and the battery against time.
pub(super) fn plots(ctx: &Context<'_>, initial: &MissionPlan, report: Option<&SimReport>) -> Result<Vec<Plot>> {
    let mut plots = route_plots(ctx, initial, report)?;
    let end_s =
        report.map_or(initial.waypoints.last().map_or(0.0, |w| w.t_s), |r| r.end_t_s().max(initial.duration_s()));
    let night = nights(ctx.truth, end_s);
    plots.push(distance_plot(ctx, initial, report, (end_s, &night)));
    plots.push(energy_plot(ctx, initial, report, (end_s, &night)));
    Ok(plots)
}

/// The time plots' tick labels as the job's `plot_time` asks.
pub(super) fn time_ticks(ctx: &Context<'_>) -> crate::report::plots::TimeTicks {
    use crate::report::plots::TimeTicks;
    match ctx.job.plot_time {
        crate::format::PlotTime::Hours => TimeTicks::Numbers,
        crate::format::PlotTime::Utc => TimeTicks::Utc { epoch_unix_s: ctx.truth.epoch().to_unix_seconds() },
        crate::format::PlotTime::LocalSolar => TimeTicks::LocalSolar {
            ltst0_h: ctx.truth.local_solar_time_h(0.0, ctx.truth.lat_lon(ctx.start.cell).1),
            day_h: ctx.job.body.model().solar_day_s() / 3600.0,
        },
    }
}

/// The x axis's name for the job's `plot_time`.
pub(super) fn time_axis_name(ctx: &Context<'_>) -> String {
    match ctx.job.plot_time {
        crate::format::PlotTime::Hours => "hours since the start".into(),
        crate::format::PlotTime::Utc => "UTC".into(),
        crate::format::PlotTime::LocalSolar => "local true solar time at the start".into(),
    }
}

/// The job's `shadow_utc` (default its start), s after the world's epoch.
pub(super) fn shadow_time_s(ctx: &Context<'_>) -> Result<f64> {
    Ok(match &ctx.job.shadow_utc {
        Some(s) => (parse_utc(s)? - ctx.truth.epoch()).to_seconds(),
        None => 0.0,
    })
}

/// The routes over the hillshade with shadows at the job's `shadow_utc` (and the
/// haven map off Mars).
pub(super) fn route_plots(ctx: &Context<'_>, initial: &MissionPlan, report: Option<&SimReport>) -> Result<Vec<Plot>> {
    let world = ctx.truth;
    let dem = world.dem();
    // (a) Routes over the hillshade with shadows at the chosen time.
    let t_shadow = shadow_time_s(ctx)?;
    let sun = world.sun(t_shadow.clamp(0.0, world.span_s()));
    let shadowed: Vec<bool> = (0..world.cells() as u32).map(|c| !world.lit(c, &sun)).collect();
    let slope = areo_terrain::slope::slope_aspect(dem);
    let mut background = areo_terrain::hillshade::hillshade_rgb(
        dem,
        &slope,
        Some(&shadowed),
        sun.azimuth_deg,
        sun.elevation_deg.max(5.0),
    );
    // Ground the no-go mask keeps out, tinted red.
    if let Some(codes) = ctx.no_go.filter(|c| c.len() == world.cells()) {
        for (i, _) in codes.iter().enumerate().filter(|(_, c)| **c != no_go::FREE) {
            let p = &mut background[3 * i..3 * i + 3];
            p.copy_from_slice(&[p[0] / 2 + 128, p[1] / 2, p[2] / 2]);
        }
    }
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
    let mut plots = vec![Plot::route("route", framed(dem, &background, series.clone(), markers.clone(), title))];
    if let Some(h) = ctx.havens {
        plots.extend(haven_plots(ctx, initial, h, series, markers));
    }
    Ok(plots)
}

/// The straight-line distance to the final goal against time, with the nights
/// (`end_s`, s, and the nights, h).
pub(super) fn distance_plot(
    ctx: &Context<'_>,
    initial: &MissionPlan,
    report: Option<&SimReport>,
    (end_s, night): (f64, &[(f64, f64)]),
) -> Plot {
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
    let v = ctx.model.top_speed_m_s(ctx.world);
    let t_zero = ctx.start.t_min + d0 / v;
    dseries.push(Series {
        label: "straight line at top speed".into(),
        points: vec![(ctx.start.t_min / 3600.0, d0), (t_zero / 3600.0, 0.0)],
        rgb: (90, 90, 90),
        width: 1,
    });
    Plot::time(
        "distance",
        TimePlot {
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
pub(super) fn energy_plot(
    ctx: &Context<'_>,
    initial: &MissionPlan,
    report: Option<&SimReport>,
    (end_s, night): (f64, &[(f64, f64)]),
) -> Plot {
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
    Plot::time(
        "energy",
        TimePlot {
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
pub(super) fn framed(
    dem: &Dem,
    background: &[u8],
    series: Vec<Series>,
    markers: Vec<Marker>,
    title: String,
) -> RoutePlot {
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
pub(super) fn haven_plots(
    ctx: &Context<'_>,
    plan: &MissionPlan,
    havens: &contact::Havens,
    series: Vec<Series>,
    mut markers: Vec<Marker>,
) -> [Plot; 2] {
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
    [Plot::route("havens", framed(dem, &rgb, series, markers, title)), sky_plot(ctx, plan)]
}

/// The Sun and the Earth over the plan, at the site, with the Communicate sessions
/// shaded (`sky.png`).
pub(super) fn sky_plot(ctx: &Context<'_>, plan: &MissionPlan) -> Plot {
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
    Plot::time(
        "sky",
        TimePlot {
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
