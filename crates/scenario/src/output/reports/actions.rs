//! An actions report's summary lines.

use crate::output::counted;
use crate::report::actions::{ActionsReport, ClimbFigures, ReplayFigures, ScanFigures, ScanSeedFigures, StudyFigures};

/// The report in words: the design space, each run's seed study, the friction scans,
/// the replay, the climbs and each run's best plan.
pub(crate) fn summary(r: &ActionsReport) -> Vec<String> {
    let codes: Vec<String> = r.inventory.iter().map(u16::to_string).collect();
    let mut lines = vec![format!(
        "inventory: {} of 26 modules after the task filters ({}); D = N^m for m = {}: 10^{:.0} → 10^{:.0}",
        r.inventory.len(),
        codes.join(" "),
        r.plan_modules,
        r.design_space_log10_full,
        r.design_space_log10_filtered
    )];
    for (name, c) in &r.feature_classes {
        lines.push(format!("terrain class {name}: μ {} on {} cells of its features", c.mu, c.cells));
    }
    let runs = || r.run_order.iter().filter_map(|name| r.runs.get(name).map(|f| (name, f)));
    for (name, f) in runs() {
        if let Some(study) = &f.study {
            lines.push(study_line(name, study));
        }
    }
    if let Some(scan) = &r.scan {
        scan_lines(&mut lines, scan);
    }
    if let Some(seeds) = &r.scan_seeds {
        scan_seed_lines(&mut lines, seeds);
    }
    if let Some(replay) = &r.replay {
        lines.push(replay_line(replay));
    }
    if let Some(climb) = &r.climb {
        lines.extend(climb_line(climb));
    }
    sensitivity_lines(&mut lines, r);
    for (name, f) in runs() {
        let e = &f.executed;
        lines.push(format!(
            "{name}: {} in {}; fitness {:.2}; {} ({}); stability min {:.0} %, mean {:.0} %; {:.0} s, {:.2} Wh{}",
            if e.complete { "task complete" } else { "not complete" },
            counted(e.modules, "module"),
            f.best_fitness,
            counted(e.samples, "sample"),
            e.taken,
            100.0 * e.min_stability,
            100.0 * e.mean_stability,
            e.time_s,
            e.energy_wh,
            e.stopped_at.as_ref().map_or(String::new(), |at| format!("; stopped at {at}"))
        ));
        if let Some(b) = &f.binding_said {
            lines.push(format!("{name}: bound by the {b}"));
        }
    }
    lines
}

fn study_line(name: &str, s: &StudyFigures) -> String {
    format!(
        "{name}: seeds {}..{}: solved by generation {} in {} of {}; median first-solved generation {}; {} improving crossovers, {:.0} % adding 1–4 successful modules",
        s.first_seed,
        s.last_seed,
        s.last_generation,
        s.solved,
        s.seeds,
        s.first_solved_median.map_or("never (half or more unsolved)".into(), |m| format!("{m}")),
        s.pooled_improving_crossovers,
        100.0 * s.pooled_lookahead_1_to_4_fraction
    )
}

fn scan_lines(lines: &mut Vec<String>, s: &ScanFigures) {
    for what in ["crossing", "completing"] {
        if let Some(b) = s.scan_binding_below.get(what) {
            lines.push(format!("below the {what} threshold (μ = {}): {}", b.mu, b.said));
        }
    }
    let from = |mu: Option<f64>| mu.map_or("never".into(), |m| format!("{m}"));
    lines.push(format!(
        "friction scan μ = {}..{}: ditch crossed from μ = {}, task completed from μ = {}",
        s.scan_mu_first,
        s.scan_mu_last,
        from(s.scan_min_mu_crossing_ditch),
        from(s.scan_min_mu_completing)
    ));
}

fn scan_seed_lines(lines: &mut Vec<String>, s: &ScanSeedFigures) {
    for what in ["crossing_ditch", "completing"] {
        let Some(t) = s.scan_seeds_min_mu.get(what) else { continue };
        let never = s.scan_seeds_never.get(what).copied().unwrap_or(0);
        lines.push(format!(
            "friction scan over {} seeds, least μ {what}: median {}, range {}–{}{}",
            s.scan_seeds,
            t.median.map_or("above the scan".into(), |m| m.to_string()),
            t.least,
            t.greatest,
            if never > 0 { format!(", {never} never") } else { String::new() }
        ));
    }
}

fn replay_line(r: &ReplayFigures) -> String {
    let at = |m: Option<f64>| m.map_or("no μ listed".into(), |m| format!("μ = {m}"));
    format!(
        "{}'s best plan (found at μ = {}) replayed: crosses the ditch from {}, completes from {}{}",
        r.replay_run,
        r.replay_found_at_mu,
        at(r.replay_min_mu_crossing_ditch),
        at(r.replay_min_mu_completing),
        match (r.replay_highest_failing_mu, r.replay_stops_at_module) {
            (Some(mu), Some(module)) => format!(
                "; at μ = {mu} it stops at module {module}{}",
                r.replay_failure_said.as_ref().map_or(String::new(), |f| format!(" ({f})"))
            ),
            _ => String::new(),
        }
    )
}

fn climb_line(c: &ClimbFigures) -> Option<String> {
    let (Some(distance), Some(pitch), Some(stowed), Some(forward), Some(tool), Some(least_stowed), Some(least_forward)) = (
        c.climb_stop_distance_m,
        c.climb_last_pitch_deg,
        c.climb_last_margin_stowed,
        c.climb_last_margin_forward,
        c.climb_forward_tool_m,
        c.climb_min_margin_stowed,
        c.climb_min_margin_forward,
    ) else {
        return None;
    };
    Some(format!(
        "straight climb: {} after {distance:.2} m at {pitch:.1}° of pitch; stability margin there {stowed:.3} stowed, {forward:.3} with the arm forward (tool at {tool:.2} m); least margins {least_stowed:.3} and {least_forward:.3}",
        match c.climb_stop.as_str() {
            "kinematics" => "no pose (a joint limit or the map's edge)",
            "tip_over" => "tipped over",
            _ => "climbed its length",
        }
    ))
}

fn sensitivity_lines(lines: &mut Vec<String>, r: &ActionsReport) {
    for (field, value) in &r.sensitivity_order {
        let Some(s) = r.sensitivity.get(field).and_then(|v| v.get(value)) else { continue };
        if let Some(why) = &s.refused {
            lines.push(format!("{} = {}: refused ({why})", s.parameter, s.value));
            continue;
        }
        let last = match (s.last_pitch_deg, s.last_margin_stowed, s.last_margin_forward) {
            (Some(pitch), Some(stowed), Some(forward)) => {
                format!(" at {pitch:.1}° of pitch; margin stowed {stowed:.3}, arm forward {forward:.3}")
            }
            _ => String::new(),
        };
        lines.push(format!(
            "{} = {}: straight climb {} after {:.2} m{last}",
            s.parameter,
            s.value,
            match s.stop.as_str() {
                "kinematics" => "has no pose (a joint limit)",
                "tip_over" => "tips over with the arm stowed",
                _ => "goes its length",
            },
            s.stop_distance_m.unwrap_or(0.0)
        ));
    }
}
