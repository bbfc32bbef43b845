//! `cargo xtask bench replan`: re-planning after sensing on a tick, in one sitting. The
//! simulated runs of valley-detour, gale-mola-traverse and lita-scale (as shipped, every
//! re-plan after sensing compared with a fresh search): each re-plan after sensing
//! changed the map against the initial plan's expansions (median,
//! 95th percentile, largest), the repairs that proved the rest of a plan optimal, and
//! the comparison with fresh searches. Then valley-detour's whole run beside the
//! approximate search's (time classes of 1200 s, 25 Wh energy classes, 72 goal
//! instants), the README's first command.

use std::path::Path;

use areo_scenario::format::planner::{ObjectiveSpec, PlannerSpec, ResolutionSpec};

use super::{check_all, number, run_file_with};

/// One run's figures: (median, 95th percentile, largest) re-plan after sensing against
/// the initial plan, and the largest relative cost difference from a fresh search.
struct Figures {
    median: f64,
    p95: f64,
    largest: f64,
    fresh_difference: f64,
}

fn sensing_run(
    path: &Path,
    name: &str,
    change: impl FnOnce(&mut areo_scenario::format::TempestJob),
) -> Result<Figures, String> {
    let (o, wall) = run_file_with(path, true, change)?;
    let fact = |f: &str| number(&o, f);
    let figures = Figures {
        median: fact("sensing_replan_expansions_median"),
        p95: fact("sensing_replan_expansions_p95"),
        largest: fact("replan_expansions_max"),
        fresh_difference: fact("replan_fresh_cost_difference"),
    };
    println!(
        "{name}: initial plan {} expansions; {} re-plans, {} after sensing: median {:.2} %, 95th percentile {:.2} %, \
         largest re-plan {:.2} % of the initial plan's; {} kept without a search, {} repaired; {} compared with fresh \
         searches, {} expanded more, costs within {:.1e}; whole run with the comparisons {wall:.1} s",
        fact("initial_plan_expansions"),
        fact("replans"),
        fact("replans_after_sensing"),
        100.0 * figures.median,
        100.0 * figures.p95,
        100.0 * figures.largest,
        fact("replans_kept_rest"),
        fact("replans_repaired"),
        fact("fresh_compared"),
        fact("replans_above_fresh"),
        figures.fresh_difference,
    );
    Ok(figures)
}

/// valley-detour's whole run as shipped and with the approximate search, without
/// comparisons: (initial plan s, whole run s) of each.
fn valley_against_approximate(root: &Path) -> Result<[(f64, f64); 2], String> {
    let path = root.join("scenarios/valley-detour.ron");
    let mut out = [(0.0, 0.0); 2];
    for (i, approximate) in [false, true].into_iter().enumerate() {
        let (o, wall) = run_file_with(&path, false, |job| {
            if approximate {
                job.planner = PlannerSpec {
                    actions: job.planner.actions.clone(),
                    objective: ObjectiveSpec::Energy,
                    goal_energy_wh: job.planner.goal_energy_wh,
                    max_wait_s: job.planner.max_wait_s,
                    search: areo_scenario::format::planner::SearchSpec::Approximate(
                        areo_scenario::format::planner::ClassesSpec {
                            resolution: ResolutionSpec { time_s: 1200.0, energy_wh: Some(25.0) },
                            goal_times: 72,
                            ..areo_scenario::format::planner::ClassesSpec::default()
                        },
                    ),
                    ..PlannerSpec::default()
                };
            }
        })?;
        let name = if approximate { "approximate search (1200 s, 25 Wh classes)" } else { "exact on its 60 s tick" };
        println!(
            "valley-detour, {name}: initial plan {:.2} s ({} expansions), whole run {wall:.1} s, {} of 2 goals, \
             largest re-plan {:.0} % of the initial plan's",
            number(&o, "initial_plan_s"),
            number(&o, "initial_plan_expansions"),
            number(&o, "goals_reached"),
            100.0 * number(&o, "replan_expansions_max"),
        );
        out[i] = (number(&o, "initial_plan_s"), wall);
    }
    Ok(out)
}

pub(crate) fn run(root: &Path) -> Result<bool, String> {
    let mut runs = Vec::new();
    for name in ["valley-detour", "gale-mola-traverse", "lita-scale"] {
        runs.push((name, sensing_run(&root.join("scenarios").join(format!("{name}.ron")), name, |_| {})?));
    }
    let [(exact_plan, exact_run), (approx_plan, approx_run)] = valley_against_approximate(root)?;
    let mut checks: Vec<(String, f64, f64)> = Vec::new();
    for (name, f) in &runs {
        checks.push((format!("{name}: median re-plan after sensing / initial"), f.median, 0.01));
        checks.push((format!("{name}: 95th percentile"), f.p95, 0.10));
        checks.push((format!("{name}: largest re-plan / initial"), f.largest, 1.0));
        checks.push((format!("{name}: cost against fresh searches (relative)"), f.fresh_difference, 1e-9));
    }
    checks.push(("valley-detour initial plan / the approximate search's".into(), exact_plan / approx_plan, 1.5));
    checks.push(("valley-detour whole run / the approximate search's".into(), exact_run / approx_run, 2.0));
    checks.push(("valley-detour whole run, s".into(), exact_run, 10.0));
    let checks: Vec<(&str, f64, f64)> = checks.iter().map(|(n, v, l)| (n.as_str(), *v, *l)).collect();
    Ok(check_all(&checks))
}
