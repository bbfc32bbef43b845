//! The TEMPEST job's facts and summary lines: the plan, its sessions and resolution,
//! the body's figures, the simulated run, its search costs and restarts.

use super::*;

/// Communicate sessions the plan covers, and drives that would overlap one (none may).
pub(super) fn session_facts(o: &mut Outcome, ctx: &Context<'_>, plan: &MissionPlan) {
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

pub(super) fn plan_facts(o: &mut Outcome, ctx: &Context<'_>, plan: &MissionPlan) {
    let (drives, charges, hibernations) = plan.action_counts();
    o.count("initial_plan_waypoints", plan.waypoints.len() as u64);
    o.count("initial_plan_drives", drives as u64);
    o.count("initial_plan_charges", charges as u64);
    o.count("initial_plan_hibernations", hibernations as u64);
    o.count("initial_plan_wait_steps", plan.wait_steps() as u64);
    o.number("initial_plan_duration_h", plan.duration_s() / 3600.0);
    o.number("initial_plan_min_battery_wh", plan.min_battery_wh());
    o.count("initial_plan_expansions", plan.expansions);
    // The objective's value: Wh (L + B, energy used, margin) or s (time).
    o.number("initial_plan_cost", plan.cost);
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
        crate::jobs::counted(drives, "drive"),
        crate::jobs::counted(charges, "charge"),
        crate::jobs::counted(hibernations, "hibernation"),
        plan.duration_s() / 3600.0,
        plan.min_battery_wh(),
        plan.e_max_wh
    ));
    resolution_facts(o, ctx, plan);
}

/// What the search that found the plan approximated, said as what it is: its classes,
/// and which fallback (energy exact, halved classes, exact at the quanta) found it.
pub(super) fn resolution_facts(o: &mut Outcome, ctx: &Context<'_>, plan: &MissionPlan) {
    if let Some(tick) = plan.tick_s {
        o.number("initial_plan_tick_s", tick);
        o.summary.push(format!(
            "search: exact at the tick of {tick:.0} s (drives depart and waits end on ticks, energy exact, goals \
             reached at any instant of their windows; no approximation, no fallback)"
        ));
        return;
    }
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
pub(super) fn body_facts(o: &mut Outcome, ctx: &Context<'_>, plan: &MissionPlan) {
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

pub(super) fn sim_facts(o: &mut Outcome, ctx: &Context<'_>, r: &SimReport, peak_memory_mb: Option<f64>) {
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
    o.count("nights", r.nights(ctx.truth) as u64);
    o.number("drive_h", drive_h);
    o.number("charge_h", charge_h);
    o.number("hibernate_h", hibernate_h);
    o.number("wait_h", hours_in(r, |a| a == Action::Wait));
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
pub(super) fn p95(values: &[f64]) -> f64 {
    values[(values.len() * 95).div_ceil(100).saturating_sub(1)]
}

/// The simulated run's search figures: re-plan expansions against the initial plan's
/// (restarts included), the search's memory, and with `compare_fresh` the re-plans
/// against fresh searches of the same problems.
pub(super) fn search_facts(o: &mut Outcome, r: &SimReport) {
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
    // On a tick: re-plans that kept the rest of the last plan (nothing changed and the
    // rover where it said: optimal by Bellman's principle) rather than search again.
    let replans = r.plans.iter().filter(|p| p.kind == PlanKind::Replan);
    if r.plans.first().is_some_and(|p| p.plan.tick_s.is_some()) {
        let kept = replans.filter(|p| p.expansions == 0).count() as u64;
        o.count("replans_kept_rest", kept);
        o.summary.push(format!(
            "re-plans on the tick: {kept} kept the rest of the last plan (the world unchanged, the rover where the \
             plan said), the others searched exactly from where the rover stood"
        ));
    }
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
pub(super) fn restart_facts(o: &mut Outcome, r: &SimReport) {
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

/// The summary line on the run's restarts, if any: the bindings the failed re-plans
/// named and what a fresh search of their problems found.
pub(super) fn restart_summary(o: &mut Outcome, r: &SimReport, restarts: usize) {
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
}

/// Hours the executed run spent in the actions `which` accepts.
pub(super) fn hours_in(r: &SimReport, which: impl Fn(Action) -> bool) -> f64 {
    // A fold from +0: `sum` of no f64 is -0, which prints as "-0.0 h".
    r.steps.iter().filter(|s| which(s.action)).map(|s| s.duration_s).fold(0.0, |a, d| a + d) / 3600.0
}

/// The simulated run in words: where it got, its battery, its re-plans and memory.
pub(super) fn sim_summary(
    o: &mut Outcome,
    ctx: &Context<'_>,
    r: &SimReport,
    status: &str,
    peak_memory_mb: Option<f64>,
) {
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
         {}{} night(s)",
        r.goals_reached.len(),
        ctx.goals.len(),
        r.distance_m(),
        match hours_in(r, |a| a == Action::Wait) {
            h if h > 0.0 => format!("waited {h:.1} h; "),
            _ => String::new(),
        },
        r.nights(ctx.truth)
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
        crate::jobs::counted(replans.len(), "re-plan"),
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
    restart_summary(o, r, restarts);
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
