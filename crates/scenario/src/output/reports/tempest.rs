//! A TEMPEST report's summary lines.

use crate::output::counted;
use crate::report::tempest::{
    BodyFigures, ChanceFigures, ClassFigures, FrontFigures, MonteCarloFigures, NoPlanFigures, PlanFigures, RunFigures,
    TempestReport,
};

/// The report in words: how the search ended, the plan, the uncertainty and the front,
/// the simulated run.
pub(crate) fn summary(r: &TempestReport) -> Vec<String> {
    let mut lines = r.notes.clone();
    if let Some(n) = &r.no_go {
        lines.push(format!(
            "no-go mask {}: {} cells kept out ({:.1} % of the map: {} marked, {} within {} m of them), {} cut off from the start",
            n.file,
            n.masked_cells + n.inflated_cells,
            100.0 * n.kept_out_fraction,
            n.masked_cells,
            n.inflated_cells,
            n.inflate_m,
            n.island_cells
        ));
    }
    if let Some(c) = &r.terrain_classes {
        terrain_classes(&mut lines, c, r.initial_plan.is_some());
    }
    if let Some(work) = &r.no_plan {
        no_plan(&mut lines, r, work);
        return lines;
    }
    if let Some(plan) = &r.initial_plan {
        initial_plan(&mut lines, plan);
    }
    if let Some(chance) = &r.chance {
        uncertainty(&mut lines, chance);
    }
    if let Some(front) = &r.front {
        pareto_front(&mut lines, r, front);
    }
    match (&r.run, &r.initial_plan, r.map_cols_rows) {
        (Some(run), _, _) => simulated(&mut lines, r, run),
        (None, Some(plan), Some((cols, rows))) => lines.push(format!(
            "{cols} × {rows} cells; pre-calculation {:.2} s, planning {:.3} s ({} expansions)",
            r.precalc_s, plan.initial_plan_s, plan.initial_plan_expansions
        )),
        (None, _, _) => {}
    }
    lines
}

fn no_plan(lines: &mut Vec<String>, r: &TempestReport, work: &NoPlanFigures) {
    match (&r.binding, &r.stopped_message) {
        (Some(binding), _) => lines.push(format!("no plan: the goals are unreachable ({binding})")),
        (None, Some(message)) => lines.push(format!("no answer: {message}")),
        (None, None) => {}
    }
    let probes: Vec<String> = work.no_plan_probe_expansions.iter().map(|(p, n)| format!("{n} with {p}")).collect();
    let probes = if probes.is_empty() {
        String::new()
    } else {
        format!("; the probes naming the binding constraint {}", probes.join(", "))
    };
    lines.push(format!(
        "no plan after {} expansions in {:.1} s: {} at the settings and their fallbacks{probes}",
        work.no_plan_expansions, work.no_plan_s, work.no_plan_planning_expansions
    ));
    if let Some(confidence) = r.planned_at_confidence {
        lines.push(format!(
            "(planned at confidence {confidence}: every action made worse by its margins; a deterministic plan may still exist)"
        ));
    }
}

fn initial_plan(lines: &mut Vec<String>, p: &PlanFigures) {
    if let Some(body) = &p.body {
        off_mars(lines, body);
    }
    lines.push(format!(
        "initial plan: {} waypoints ({}, {}, {}) over {:.1} h; lowest predicted battery {:.0} Wh (absolute); \
         E_max {:.2} Wh",
        p.initial_plan_waypoints,
        counted(p.initial_plan_drives, "drive"),
        counted(p.initial_plan_charges, "charge"),
        counted(p.initial_plan_hibernations, "hibernation"),
        p.initial_plan_duration_h,
        p.initial_plan_min_battery_wh,
        p.e_max_wh
    ));
    if let Some(tick) = p.initial_plan_tick_s {
        lines.push(format!(
            "search: exact at the tick of {tick:.0} s (drives depart and waits end on ticks, energy exact, goals \
             reached at any instant of their windows; no approximation, no fallback)"
        ));
    }
    if let Some(a) = &p.approximate {
        approximate(lines, p, a);
    }
}

/// What the approximate search approximated, said as what it is, and which fallback
/// found the plan.
fn approximate(lines: &mut Vec<String>, p: &PlanFigures, a: &crate::report::tempest::ApproximateSearch) {
    let fallback = p.initial_plan_exact_energy_fallback == Some(true);
    lines.push(format!(
        "search resolution: time classes of {:.0} s (approximate: labels of a class are compared as one instant); {}",
        a.time_classes_asked_s,
        match (a.energy_classes_asked_wh, fallback) {
            (None, _) => "energy exact (Pareto labels)".to_string(),
            (Some(w), false) => format!(
                "energy classes of {w} Wh (approximate: a kept label may need up to {w} Wh more than one it dropped)"
            ),
            (Some(w), true) => format!(
                "no plan with energy classes of {w} Wh, so the planner searched again with energy exact (fallback)"
            ),
        }
    ));
    if p.initial_plan_halved_classes_fallback == Some(true) {
        let exactness = if a.quantised {
            "before the last resort exact at the quanta, which it made unnecessary"
        } else {
            "still approximate: no class width is exact for continuous action times"
        };
        lines.push(format!(
            "no plan at these classes, so the planner searched again at time classes of {:.0} s (fallback: \
             `unreachable_retries`; {exactness})",
            a.time_classes_s
        ));
    }
    if p.initial_plan_quanta_fallback == Some(true) {
        lines.push(format!(
            "no plan at these classes, so the planner searched again exact at the actions' quanta (fallback: time classes of {:.0} s, energy exact, every goal instant a coarser goal_times would use)",
            a.time_classes_s
        ));
    }
}

fn off_mars(lines: &mut Vec<String>, b: &BodyFigures) {
    if let (Some(minutes), Some(gap), Some(in_view)) =
        (b.contact_session_min, b.initial_plan_contact_max_gap_h, b.initial_plan_earth_in_view_fraction)
    {
        lines.push(format!(
            "Earth contact: in view {:.0} % of the plan; longest gap without {minutes} min of contact {gap:.1} h",
            100.0 * in_view
        ));
    }
    if let Some(h) = &b.havens {
        lines.push(format!(
            "safe havens: {} cells (shadows shorter than the {:.0} h a full battery lasts asleep); the plan waits {} \
             times for at least {:.1} h, {} of them at havens",
            h.safe_haven_cells,
            h.safe_haven_survive_h,
            h.initial_plan_waits,
            h.waits_counted_from_h,
            h.initial_plan_waits_at_havens
        ));
    }
}

fn uncertainty(lines: &mut Vec<String>, c: &ChanceFigures) {
    if let (Some(clones), Some(sigma), Some(correlation)) =
        (c.mc_terrain_clones, c.chance_terrain_sigma_m, c.chance_terrain_correlation_m)
    {
        lines.push(format!(
            "the open-loop and closed-loop executions drive on {clones} error clones of the terrain (height RMS {sigma} m, correlated over {correlation} m)"
        ));
    }
    if let Some(clones) = c.chance_terrain_plan_clones {
        lines.push(format!(
            "the plan is made to hold on the map and {clones} error clones of it (seeds from 2^63, never the Monte Carlo's): each drive as slow and as hungry as on its worst, sunlight only where every one is lit and at most the least any gives"
        ));
    }
    let bound = if c.chance_correlation == "Action" {
        "a draw per action: a conservative bound"
    } else {
        "one draw per execution: each quantity at its quantile"
    };
    lines.push(format!(
        "plan under uncertainty ({bound}): confidence {} (z = {:.3}); planned with drives ×{:.3}, loads ×{:.3}, sunlight ×{:.3}, {:.0} s before each action, a start {:.0} s late",
        c.chance_confidence,
        c.chance_z,
        c.chance_drive_time_factor,
        c.chance_draw_factor,
        c.chance_solar_factor,
        c.chance_action_delay_s,
        c.chance_start_delay_s
    ));
    if let (Some(extra_h), Some(extra_wh), Some(ratio)) =
        (c.chance_extra_duration_h, c.chance_extra_energy_used_wh, c.chance_cost_ratio)
    {
        lines.push(format!(
            "the margins cost {extra_h:+.2} h and {extra_wh:+.1} Wh drawn against the deterministic plan (cost ×{ratio:.3})"
        ));
    }
    monte_carlo(lines, c);
}

fn monte_carlo(lines: &mut Vec<String>, c: &ChanceFigures) {
    if let Some(s) = &c.mc {
        let det = c.mc_deterministic.as_ref().map_or(String::new(), |d: &MonteCarloFigures| {
            format!(
                "; the deterministic plan {:.3} [{:.3}, {:.3}]",
                d.success_probability, d.success_ci_low, d.success_ci_high
            )
        });
        lines.push(format!(
            "open-loop Monte Carlo, {} runs: the plan reaches every goal with the battery above its floor in {:.3} [{:.3}, {:.3}] (95 % Wilson){det}",
            s.runs, s.success_probability, s.success_ci_low, s.success_ci_high
        ));
    }
    if let Some(s) = &c.mc_closed {
        let det = c
            .mc_closed_deterministic
            .as_ref()
            .map_or(String::new(), |d| format!("; planning deterministically {:.3}", d.success_probability));
        lines.push(format!(
            "closed-loop Monte Carlo (re-planning after every action), {} runs: every goal reached with the battery above its floor in {:.3}{det}",
            s.runs, s.success_probability
        ));
    }
}

fn pareto_front(lines: &mut Vec<String>, r: &TempestReport, f: &FrontFigures) {
    let (Some(early), Some(late), Some(least), Some(most), Some(low), Some(high)) = (
        f.front_earliest_arrival_h,
        f.front_latest_arrival_h,
        f.front_least_energy_used_wh,
        f.front_most_energy_used_wh,
        f.front_least_margin_wh,
        f.front_largest_margin_wh,
    ) else {
        lines.push("Pareto front: no plan".into());
        return;
    };
    let on_tick = r.initial_plan.as_ref().is_some_and(|p| p.initial_plan_tick_s.is_some());
    let how = match f.front_margin_step_wh {
        Some(step) if !on_tick => format!(
            "{} searches, {} plans before the filter; margins walked {step} Wh apart, so a plan within that above a found \
             one's margin may be missing",
            f.front_searches, f.front_candidates
        ),
        _ => {
            "exact on the tick: every plan on it that no other beats in all three, the margin its lowest battery above \
              the floor"
                .to_string()
        }
    };
    lines.push(format!(
        "Pareto front: {} plans in (arrival, energy used, margin) — arrival {early:.2}–{late:.2} h, energy used {least:.1}–{most:.1} \
         Wh, margin {low:.1}–{high:.1} Wh ({how})",
        f.front_plans,
    ));
}

fn simulated(lines: &mut Vec<String>, r: &TempestReport, f: &RunFigures) {
    for (name, g) in f.arrival_order.iter().filter_map(|n| f.goals.get(n).map(|g| (n, g))) {
        lines.push(format!(
            "reached {name} at {} (after {:.1} h, LTST {:.2} h)",
            g.arrival_utc, g.arrival_h, g.arrival_ltst_h
        ));
    }
    if let Some(kept) = f.replans_kept_rest {
        lines.push(format!(
            "re-plans on the tick: {kept} kept the rest of the last plan (the world unchanged, the rover where the \
             plan said), {} after sensing kept it once a repair proved it optimal, the others searched exactly from \
             where the rover stood",
            f.replans_repaired.unwrap_or(0)
        ));
    }
    if let (Some(median), Some(p95)) = (f.sensing_replan_expansions_median, f.sensing_replan_expansions_p95) {
        lines.push(format!(
            "re-plans after sensing changed the map ({}): expansions median {:.2} %, 95th percentile {:.1} % of the \
             initial plan's",
            f.replans_after_sensing,
            100.0 * median,
            100.0 * p95
        ));
    }
    if let (Some(compared), Some(above), Some(worst)) =
        (f.fresh_compared, f.replans_above_fresh, f.replan_fresh_cost_difference)
    {
        let independent = match (f.fresh_differs, f.fresh_windows_explained) {
            (Some(differs), Some(windows)) => format!(
                " (each by a new planner instance from the rover's state: {differs} differ where both problems admit \
                 the cheaper plan, {windows} differ by the goal windows)"
            ),
            _ => String::new(),
        };
        lines.push(format!(
            "compared with fresh plans: {compared} re-plans{independent}, {above} expanded more than the fresh search; \
             costs within {worst:.2e} (relative)"
        ));
    }
    run_lines(lines, r, f);
}

fn run_lines(lines: &mut Vec<String>, r: &TempestReport, f: &RunFigures) {
    let floor = r.battery_floor_wh;
    lines.push(format!(
        "{}: {} of {} goals; {:.0} m driven in {:.1} h; charged {:.1} h, hibernated {:.1} h; {}{} night(s)",
        r.status,
        r.goals_reached,
        r.goals_total,
        f.distance_m,
        f.drive_h,
        f.charge_h,
        f.hibernate_h,
        if f.wait_h > 0.0 { format!("waited {:.1} h; ", f.wait_h) } else { String::new() },
        f.nights
    ));
    lines.push(format!(
        "battery: used {:.0} Wh, gained {:.0} Wh, ends at {:.0} Wh ({:.0} Wh above the {floor:.0} Wh floor), \
         lowest {:.0} Wh ({:.0} Wh above the floor)",
        f.energy_used_wh,
        f.energy_gained_wh,
        f.final_battery_wh,
        f.final_battery_above_floor_wh,
        f.min_battery_wh,
        f.min_battery_wh - floor
    ));
    let initial_s = r.initial_plan.as_ref().map_or(0.0, |p| p.initial_plan_s);
    lines.push(format!(
        "{} ({} changed the route), median {:.2} ms, initial plan {:.1} ms",
        counted(f.replans, "re-plan"),
        f.route_changes,
        1e3 * f.median_replan_s.unwrap_or(0.0),
        1e3 * initial_s
    ));
    if let (Some(median), Some(p95), Some(max)) =
        (f.replan_expansions_median, f.replan_expansions_p95, f.replan_expansions_max)
    {
        lines.push(format!(
            "re-plan expansions: median {:.3} %, 95th percentile {:.2} %, largest {:.1} % of the initial plan's{}",
            100.0 * median,
            100.0 * p95,
            100.0 * max,
            if f.restarts > 0 { format!(" ({} restart(s) included)", f.restarts) } else { String::new() }
        ));
    }
    if f.restarts > 0 {
        lines.push(format!(
            "{} restart(s): re-planning on the kept graphs found nothing ({}), so the rover planned afresh{}",
            f.restarts,
            f.restart_bindings.join(", "),
            match (f.restarts_fresh_compared, f.restarts_fresh_disagree) {
                (Some(n), Some(found)) =>
                    format!("; a fresh search of the same problem found a plan in {found} of {n}"),
                _ => String::new(),
            }
        ));
    }
    lines.push(format!(
        "pre-calculation {:.2} s (slope, horizon maps, Sun table); memory: search graphs {:.0} MB at most, worlds {:.0} MB, process peak {}",
        r.precalc_s,
        r.peak_search_mb.unwrap_or(0.0),
        f.world_mb,
        r.peak_memory_mb.map_or("unknown".into(), |mb| format!("{mb:.0} MB"))
    ));
    if r.status == "unreachable"
        && let Some(binding) = &r.binding
    {
        lines.push(format!("stopped: the next goal is unreachable ({binding})"));
    }
}

/// The terrain classes: cells per class, and where the plan and the run drive.
fn terrain_classes(lines: &mut Vec<String>, c: &ClassFigures, planned: bool) {
    let cells: Vec<String> = c.classes.iter().map(|(name, u)| format!("{name} {}", u.cells)).collect();
    lines.push(format!(
        "terrain classes {}: {} cells{}",
        c.file,
        cells.join(", "),
        if c.unclassified_cells > 0 { format!(", {} unclassified", c.unclassified_cells) } else { String::new() }
    ));
    if planned {
        let mut used: Vec<String> = (c.classes.iter())
            .filter(|(_, u)| u.plan_drive_time_s > 0.0)
            .map(|(name, u)| format!("{name} {:.2} h, {:.1} Wh", u.plan_drive_time_s / 3600.0, u.plan_drive_energy_wh))
            .collect();
        if c.unclassified_plan_drive_time_s > 0.0 {
            used.push(format!("unclassified {:.2} h", c.unclassified_plan_drive_time_s / 3600.0));
        }
        lines.push(format!(
            "initial plan drives on: {}",
            if used.is_empty() { "nothing".into() } else { used.join("; ") }
        ));
    }
    let run: Vec<String> = (c.classes.iter())
        .filter_map(|(name, u)| Some((name, u.run_drive_time_s?, u.run_drive_energy_wh?)))
        .filter(|(_, t, _)| *t > 0.0)
        .map(|(name, t, e)| format!("{name} {:.2} h, {e:.1} Wh", t / 3600.0))
        .collect();
    if !run.is_empty() {
        lines.push(format!("the run drove on: {}", run.join("; ")));
    }
}
