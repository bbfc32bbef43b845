//! The TEMPEST report's figures: the plan, its sessions and resolution, the body's
//! figures, the simulated run, its search costs and restarts. (The summary lines are
//! written from the report, in `output::reports::tempest`.)

use super::*;
use crate::report::tempest::{
    ApproximateSearch, BodyFigures, GoalArrival, HavenFigures, PlanFigures, RunFigures, SessionFigures,
};

/// Communicate sessions the plan covers, and drives that would overlap one (none may).
pub(super) fn session_figures(ctx: &Context<'_>, plan: &MissionPlan) -> Option<SessionFigures> {
    let sessions = ctx.model.sessions();
    if sessions.is_empty() {
        return None;
    }
    let (t0, t1) = (plan.waypoints.first().map_or(0.0, |w| w.t_s), plan.waypoints.last().map_or(0.0, |w| w.t_s));
    let overlapping = plan
        .waypoints
        .windows(2)
        .filter(|w| matches!(w[0].action, Some(Action::Drive(_))))
        .filter(|w| sessions.iter().any(|&(a, b)| w[0].t_s < b && w[1].t_s > a))
        .count();
    Some(SessionFigures {
        communicate_sessions: sessions.len(),
        plan_sessions: sessions.iter().filter(|(a, b)| *a < t1 && *b > t0).count(),
        plan_drives_during_sessions: overlapping,
    })
}

/// The initial plan's figures (its search took `seconds`).
pub(super) fn plan_figures(ctx: &Context<'_>, plan: &MissionPlan, seconds: f64) -> PlanFigures {
    let m = metrics::PlanMetrics::of_plan(plan);
    let mut f = PlanFigures {
        initial_plan_s: seconds,
        initial_plan_labels: None,
        initial_plan_waypoints: plan.waypoints.len(),
        initial_plan_drives: m.drives,
        initial_plan_charges: m.charges,
        initial_plan_hibernations: m.hibernations,
        initial_plan_wait_steps: m.wait_steps,
        initial_plan_duration_h: plan.duration_s() / 3600.0,
        initial_plan_min_battery_wh: plan.min_battery_wh(),
        initial_plan_expansions: plan.expansions,
        initial_plan_cost: plan.cost,
        e_max_wh: plan.e_max_wh,
        initial_plan_distance_m: m.distance_m,
        initial_plan_goals: plan.waypoints.iter().filter(|w| w.goal.is_some()).count(),
        initial_plan_sunlit_drive_fraction: m.sunlit_drive_fraction,
        initial_plan_night_drives: m.night_drives,
        initial_plan_enters: (ctx.job.regions.iter())
            .map(|r| (r.name.clone(), ctx.enters(plan.waypoints.iter().map(|w| w.cell), r)))
            .collect(),
        sessions: session_figures(ctx, plan),
        ..PlanFigures::default()
    };
    if ctx.job.body.model() != areo_ephemeris::Body::Mars {
        f.body = Some(body_figures(ctx, plan));
    }
    let attitudes: Vec<(f64, f64)> = plan.waypoints.iter().filter_map(|w| w.drive_attitude_deg).collect();
    if !attitudes.is_empty() {
        let most = |f: &dyn Fn(&(f64, f64)) -> f64| attitudes.iter().map(f).fold(0.0, f64::max);
        f.initial_plan_max_roll_deg = Some(most(&|a| a.1.abs()));
        f.initial_plan_max_pitch_up_deg = Some(most(&|a| a.0));
        f.initial_plan_max_pitch_down_deg = Some(most(&|a| -a.0));
    }
    resolution_figures(&mut f, ctx, plan);
    f
}

/// What the search that found the plan approximated, said as what it is: its classes,
/// and which fallback (energy exact, halved classes, exact at the quanta) found it.
pub(super) fn resolution_figures(f: &mut PlanFigures, ctx: &Context<'_>, plan: &MissionPlan) {
    if let Some(tick) = plan.tick_s {
        f.initial_plan_tick_s = Some(tick);
        return;
    }
    let resolution = ctx.job.planner.search.classes().copied().unwrap_or_default().resolution;
    let fallback = resolution.energy_wh.is_some() && plan.energy_classes_wh.is_none();
    f.initial_plan_exact_energy_fallback = Some(fallback);
    // The last resort for quantised actions: a search exact at the quanta (reported
    // even where the classes were one quantum already: its goal instants and start
    // times are not the settings'); before it, and for continuous actions instead of
    // it, the retries at halved classes the settings asked for.
    let quantised = ctx.job.planner.actions.time_quantum_s >= 1.0;
    let at_quanta = plan.exact_at_quanta;
    let halved = plan.time_classes_s < resolution.time_s && !at_quanta;
    f.initial_plan_quanta_fallback = Some(at_quanta);
    f.initial_plan_halved_classes_fallback = Some(halved);
    f.approximate = Some(ApproximateSearch {
        time_classes_asked_s: resolution.time_s,
        energy_classes_asked_wh: resolution.energy_wh,
        time_classes_s: plan.time_classes_s,
        quantised,
    });
}

/// Facts of a plan off Mars: driving in shadow, Earth contact, the Sun's azimuth span, the
/// circuit, and the waits at safe havens — each measured on the plan by sampling, not
/// taken from the planner's constraints.
pub(super) fn body_figures(ctx: &Context<'_>, plan: &MissionPlan) -> BodyFigures {
    use contact::{contact_along, shadowed_drive_h, waits};
    let sun = metrics::sun_along(ctx.world, plan, CONTACT_STEP_S);
    let mut f = BodyFigures {
        initial_plan_shadowed_drive_h: shadowed_drive_h(ctx.world, plan, CONTACT_STEP_S),
        initial_plan_sun_azimuth_span_deg: sun.azimuth_span_deg,
        initial_plan_lowest_sun_deg: sun.lowest_elevation_deg,
        initial_plan_closes_circuit: plan
            .waypoints
            .last()
            .map(|last| ctx.world.chebyshev(last.cell, ctx.start.cell) <= 1.0),
        // Sun-synchronous driving: drives whose array faces within 90° of the Sun's
        // azimuth (the heading from the drive's displacement).
        initial_plan_panel_sunward_drive_fraction: (ctx.model.rover().solar)
            .map(|array| metrics::sunward_drive_fraction(ctx.world, plan, array.facing_deg)),
        ..BodyFigures::default()
    };
    if let Some(com) = &ctx.job.communicate
        && ctx.model.needs_earth()
    {
        let c = contact_along(ctx.world, plan, com.duration_min * 60.0, CONTACT_STEP_S);
        f.initial_plan_contact_max_gap_h = Some(c.max_gap_h);
        f.initial_plan_earth_in_view_fraction = Some(c.in_view_fraction);
        f.contact_session_min = Some(com.duration_min);
    }
    if let Some(h) = ctx.havens {
        let ws = waits(plan, h, floor_wh(ctx), HAVEN_STEP_S);
        let longest = ws.iter().max_by(|a, b| (a.to_h - a.from_h).total_cmp(&(b.to_h - b.from_h)));
        f.havens = Some(HavenFigures {
            safe_haven_cells: h.haven.iter().filter(|&&x| x).count(),
            safe_haven_survive_h: h.survive_h.min(1e6),
            initial_plan_waits: ws.len(),
            initial_plan_waits_at_havens: ws.iter().filter(|w| w.haven).count(),
            initial_plan_longest_wait_h: longest.map_or(0.0, |w| w.to_h - w.from_h),
            initial_plan_longest_wait_at_haven: longest.is_some_and(|w| w.haven),
            waits_counted_from_h: HAVEN_STEP_S / 3600.0,
        });
    }
    f
}

/// The simulated run's figures into `report`.
pub(super) fn sim_figures(report: &mut TempestReport, ctx: &Context<'_>, r: &SimReport) {
    let status = match &r.status {
        SimStatus::Completed => "completed",
        SimStatus::Unreachable { .. } => "unreachable",
        SimStatus::BatteryDepleted => "battery_depleted",
        SimStatus::Stuck(_) => "stuck",
        SimStatus::StepLimit => "step_limit",
    };
    report.status = status.into();
    report.goals_reached = r.goals_reached.len();
    let mut f = RunFigures::default();
    let epoch = ctx.world.epoch();
    for &(g, t) in &r.goals_reached {
        let name = ctx.goal_name(g);
        let (_, lon) = ctx.world.lat_lon(ctx.goals[g]);
        let at = epoch + Duration::from_seconds(t);
        let ltst = ctx.world.local_solar_time_h(t, lon);
        let arrival = GoalArrival { arrival_utc: format_utc(at), arrival_h: ctx.hours(t), arrival_ltst_h: ltst };
        f.goals.insert(name.to_string(), arrival);
        f.arrival_order.push(name.to_string());
    }
    let m = metrics::PlanMetrics::of_run(r, ctx.truth);
    let replans: Vec<_> = r.plans.iter().filter(|p| p.kind != PlanKind::Initial).collect();
    let route_changes = replans.iter().filter(|p| p.route_changed).count();
    f.zigzag_pairs = metrics::zigzag_pairs(&r.steps);
    let min_battery = r.steps.iter().map(|s| s.battery_above_floor_wh).fold(r.start.energy_wh, f64::min);
    let floor = floor_wh(ctx);
    f.actions = r.steps.len();
    f.distance_m = m.distance_m;
    f.energy_used_wh = r.energy_used_wh();
    f.energy_gained_wh = r.energy_gained_wh();
    // Absolute charges, as everywhere a name says `battery_wh`; the search's E beside.
    f.final_battery_wh = r.final_battery_above_floor_wh() + floor;
    f.final_battery_above_floor_wh = r.final_battery_above_floor_wh();
    f.min_battery_wh = min_battery + floor;
    f.nights = r.nights(ctx.truth);
    (f.drive_h, f.charge_h, f.hibernate_h, f.wait_h) = (m.drive_h, m.charge_h, m.hibernate_h, m.wait_h);
    f.replans = replans.len();
    f.route_changes = route_changes;
    restart_figures(&mut f, r);
    let asked = ctx.job.planner.search.classes().and_then(|c| c.resolution.energy_wh);
    f.exact_energy_fallbacks = r.plans.iter().filter(|p| asked.is_some() && p.plan.energy_classes_wh.is_none()).count();
    report.peak_search_mb = Some(search_figures(&mut f, r));
    f.world_mb = worlds_mb(ctx);
    f.refused_actions = r.steps.iter().filter(|s| s.refused.is_some()).count();
    f.night_drives = m.night_drives;
    f.sunlit_drive_fraction = m.sunlit_drive_fraction;
    f.mission_h = ctx.hours(r.end_t_s());
    if let Some(m) = r.median_replan_s() {
        f.median_replan_s = Some(m);
        f.max_replan_s = Some(replans.iter().map(|p| p.wall_s).fold(0.0, f64::max));
        f.median_replan_fraction = Some(m / r.plans[0].wall_s.max(1e-9));
    }
    for reg in &ctx.job.regions {
        let route = std::iter::once(r.start.cell).chain(r.steps.iter().map(|s| s.to));
        f.route_enters.insert(reg.name.clone(), ctx.enters(route, reg));
    }
    report.run = Some(f);
}

/// The 95th percentile of sorted, non-empty `values` (nearest rank).
pub(super) fn p95(values: &[f64]) -> f64 {
    values[(values.len() * 95).div_ceil(100).saturating_sub(1)]
}

/// The simulated run's search figures: re-plan expansions against the initial plan's
/// (restarts included), and with `compare_fresh` the re-plans against fresh searches
/// of the same problems. Returns the search graphs' peak, MB.
pub(super) fn search_figures(f: &mut RunFigures, r: &SimReport) -> f64 {
    // Deterministic search costs: each re-plan's expansions against the initial plan's
    // — restarts included, as the fresh plans they are (counted apart as well) — and
    // the search's memory.
    let mut fractions: Vec<f64> = r.replan_expansion_fractions();
    fractions.sort_by(f64::total_cmp);
    if let Some(&max) = fractions.last() {
        f.replan_expansions_median = Some(fractions[fractions.len() / 2]);
        f.replan_expansions_p95 = Some(p95(&fractions));
        f.replan_expansions_max = Some(max);
    }
    // Re-plans that repaired the kept graphs for cells sensing changed.
    f.replans_after_sensing = r.plans.iter().filter(|p| p.kind != PlanKind::Initial && p.changed_cells > 0).count();
    // On a tick: re-plans that kept the rest of the last plan (nothing changed and the
    // rover where it said: optimal by Bellman's principle) rather than search again.
    let replans = r.plans.iter().filter(|p| p.kind == PlanKind::Replan);
    if r.plans.first().is_some_and(|p| p.plan.tick_s.is_some()) {
        let kept = replans.filter(|p| p.expansions == 0).count();
        f.replans_kept_rest = Some(kept);
        // Re-plans after sensing changed the map: their work against the initial
        // plan's, and how many a repair ended by proving the rest of the plan optimal.
        let initial = r.plans[0].expansions.max(1) as f64;
        let mut sensed: Vec<f64> = r
            .plans
            .iter()
            .filter(|p| p.kind != PlanKind::Initial && p.changed_cells > 0)
            .map(|p| p.expansions as f64 / initial)
            .collect();
        sensed.sort_by(f64::total_cmp);
        if !sensed.is_empty() {
            f.sensing_replan_expansions_median = Some(sensed[sensed.len() / 2]);
            f.sensing_replan_expansions_p95 = Some(p95(&sensed));
        }
        f.replans_repaired =
            Some(r.plans.iter().filter(|p| p.kind == PlanKind::Replan && p.changed_cells > 0 && p.kept_rest).count());
    }
    // With `compare_fresh`: re-plans against the same problem searched from scratch.
    let compared: Vec<(&areo_mission::PlanRecord, (u64, f64))> =
        r.plans.iter().filter_map(|p| p.fresh.map(|f| (p, f))).collect();
    if !compared.is_empty() {
        f.fresh_compared = Some(compared.len());
        f.replans_above_fresh = Some(compared.iter().filter(|(p, (e, _))| p.expansions > *e).count());
        let explained = |p: &areo_mission::PlanRecord| p.fresh_check == Some(areo_mission::FreshCheck::Windows);
        let worst = (compared.iter().filter(|(p, _)| !explained(p)))
            .map(|(p, (_, c))| (p.plan.cost - c).abs() / c.abs().max(1.0))
            .fold(0.0, f64::max);
        f.replan_fresh_cost_difference = Some(worst);
    }
    // On a tick, against an independent planner instance.
    let checks: Vec<areo_mission::FreshCheck> = r.plans.iter().filter_map(|p| p.fresh_check).collect();
    if !checks.is_empty() {
        f.fresh_compared = Some(checks.len());
        f.fresh_differs = Some(checks.iter().filter(|&&c| c == areo_mission::FreshCheck::Differs).count());
        f.fresh_windows_explained = Some(checks.iter().filter(|&&c| c == areo_mission::FreshCheck::Windows).count());
    }
    r.peak_search_bytes() as f64 / 1e6
}

/// The re-plans on the kept graphs that found nothing and were replaced by plans made
/// afresh: how many, the work the failed re-plans did and the fresh plans' expansions,
/// and with `compare_fresh` how many a fresh search of the same problem contradicted
/// (it found a plan where the kept graphs found none).
pub(super) fn restart_figures(f: &mut RunFigures, r: &SimReport) {
    let restarts: Vec<(&areo_mission::PlanRecord, &areo_mission::Restart)> =
        r.plans.iter().filter_map(|p| p.restart.as_ref().map(|x| (p, x))).collect();
    f.restarts = restarts.len();
    if restarts.is_empty() {
        return;
    }
    f.restart_replan_work = Some(restarts.iter().map(|(_, x)| x.replan_work).sum());
    f.restart_bindings = restarts.iter().map(|(_, x)| format!("{:?}", x.binding)).collect();
    f.restart_bindings.dedup();
    f.restart_expansions = Some(restarts.iter().map(|(p, _)| p.expansions).sum());
    let compared: Vec<bool> = restarts.iter().filter_map(|(_, x)| x.fresh_found).collect();
    if !compared.is_empty() {
        f.restarts_fresh_compared = Some(compared.len());
        f.restarts_fresh_disagree = Some(compared.iter().filter(|&&found| found).count());
    }
}
