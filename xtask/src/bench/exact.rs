//! `cargo xtask bench exact`: what exactness at a tick costs. On synthetic Mars maps of
//! growing extent (rolling relief, 50 m cells, the Mars24 Sun over Gale, an afternoon
//! start and a goal across the map that the rover reaches the next day), three searches
//! of the same single-goal problem with the rover waiting in steps of the tick:
//! - the exact tick search (`areo_mission::exact`, drives depart on ticks and settle to
//!   the next one): optimal over its plans, "no plan" a proof;
//! - the same without the settle (drives chain at their own durations, only waits end
//!   on ticks): exact too, but its labels between ticks multiply — stopped at a label
//!   budget where it cannot finish;
//! - the approximate planner (`Mission::plan`, time classes of one tick, exact energy,
//!   72 goal instants), whose plans chain drives without settling.
//!
//! First, valley-detour as shipped and with the planner on a tick (`planner.tick_s`):
//! its initial plan under L + B and under the Time objective, and its whole run (the
//! missing pass sensed, re-plans, the night) under L + B, each within a work budget.

use std::path::Path;
use std::time::Instant;

use areo_scenario::format::planner::ObjectiveSpec;

use areo_mission::exact::{ExactGoal, ExactOutcome, ExactQuery};
use areo_mission::{
    ActionConfig, ActionModel, Classes, Mission, Objective, PlannerConfig, Resolution, SearchMode, Start, World,
};

/// Labels the chained search may keep before it is stopped.
const CHAIN_BUDGET: u64 = 3_000_000;

fn world(cols: usize) -> Result<World, String> {
    let dem = areo_terrain::Dem::from_fn(cols, cols * 3 / 4, 50.0, 50.0, |x, y| {
        30.0 * (x / 370.0).sin() + 25.0 * (y / 230.0).cos() + 5.0 * (x / 90.0 + y / 70.0).sin()
    })
    .map_err(|e| e.to_string())?;
    let config = areo_mission::WorldConfig {
        epoch: areo_ephemeris::parse_utc("2012-08-06T12:00:00Z").map_err(|e| e.to_string())?,
        span_s: 60.0 * 3600.0,
        sun_step_s: 120.0,
        horizon_sectors: Some(32),
        atmosphere: areo_ephemeris::flux::Atmosphere::Baseline { peak_w_m2: 500.0 },
        site: Some(areo_ephemeris::Site::new(-4.6, 137.4).map_err(|e| e.to_string())?),
    };
    World::new(dem, &config, &areo_ephemeris::Mars24).map_err(|e| e.to_string())
}

fn exact(world: &World, model: &ActionModel, start: Start, goal: ExactGoal, settle: bool) -> (ExactOutcome, f64) {
    let t = Instant::now();
    let query = ExactQuery {
        world,
        model,
        start,
        goals: vec![goal],
        goal_energy_wh: 0.0,
        objective: Objective::Energy,
        max_labels: if settle { 100_000_000 } else { CHAIN_BUDGET },
        settle,
    };
    let out = query.solve();
    (out, t.elapsed().as_secs_f64())
}

fn describe(out: &ExactOutcome, wall: f64) -> String {
    match (&out.plan, out.stopped) {
        (_, true) => format!("stopped at {} labels after {wall:.2} s ({} between ticks)", out.kept, out.between_ticks),
        (Some((cost, _)), false) => {
            format!("{wall:.2} s, {} labels at {} instants, cost {cost:.1}", out.kept, out.instants)
        }
        (None, false) => format!("{wall:.2} s, {} labels, no plan (proven)", out.kept),
    }
}

/// Work the valley-detour plans may spend, label expansions.
const VALLEY_EXPANSIONS: u64 = 20_000_000;

/// The same under the Time objective, where the approximate search runs away.
const VALLEY_TIME_EXPANSIONS: u64 = 5_000_000;

/// valley-detour's initial plan (no simulation) as shipped and on a tick of `tick_s`
/// (its classes, goal instants and start intervals dropped), in one sitting: each
/// one's wall time and facts, or where the work budget stopped the tick's search.
fn valley(root: &Path, tick_s: f64, objective: ObjectiveSpec, expansions: u64, whole: bool) -> Result<(), String> {
    let path = root.join("scenarios/valley-detour.ron");
    let shipped = areo_scenario::format::load(&path).map_err(|e| e.to_string())?;
    let plan_only = |mut file: areo_scenario::format::ScenarioFile, tick: Option<f64>| {
        if let areo_scenario::format::Job::Tempest(job) = &mut file.scenario.job {
            if !whole {
                job.simulate = None;
            }
            job.planner.objective = objective;
            if let Some(tick) = tick {
                let defaults = areo_scenario::format::planner::PlannerSpec::default();
                job.planner = areo_scenario::format::planner::PlannerSpec {
                    objective,
                    goal_energy_wh: job.planner.goal_energy_wh,
                    max_wait_s: job.planner.max_wait_s,
                    search: areo_scenario::format::planner::SearchSpec::Exact { tick_s: tick },
                    ..defaults
                };
            }
        }
        file
    };
    for (name, file) in
        [("as shipped", plan_only(shipped.clone(), None)), ("on a tick", plan_only(shipped, Some(tick_s)))]
    {
        let budget = areo_scenario::budget::Budget {
            work_steps: expansions * areo_scenario::budget::EXPANSION_STEPS,
            ..areo_scenario::budget::Budget::for_this_machine()
        };
        let clock = Instant::now();
        let outcome = areo_scenario::run(
            &file,
            areo_scenario::RunOptions { out_dir: None, progress: &areo_scenario::NoProgress, budget },
        );
        let wall = clock.elapsed().as_secs_f64();
        match outcome {
            Ok(o) if o.failure.is_none() && whole => {
                let fact =
                    |n: &str| o.facts.get(n).and_then(areo_scenario::outcome::Fact::as_number).unwrap_or(f64::NAN);
                println!(
                    "  valley-detour whole run {name}: {wall:.2} s, {} of 2 goals, initial plan {:.2} s, {} re-plans \
                     (largest {:.0} % of the initial plan's expansions), search graphs {:.0} MB, process peak {:.0} MB",
                    fact("goals_reached"),
                    fact("initial_plan_s"),
                    fact("replans"),
                    100.0 * fact("replan_expansions_max"),
                    fact("peak_search_mb"),
                    fact("peak_memory_mb")
                );
            }
            Ok(o) if o.failure.is_none() => {
                let fact =
                    |n: &str| o.facts.get(n).and_then(areo_scenario::outcome::Fact::as_number).unwrap_or(f64::NAN);
                println!(
                    "  valley-detour initial plan {name}: {wall:.2} s, {} expansions, cost {:.1}, {:.1} h, search graphs {:.0} MB",
                    fact("initial_plan_expansions"),
                    fact("initial_plan_cost"),
                    fact("initial_plan_duration_h"),
                    fact("peak_search_mb")
                );
            }
            Ok(o) => println!(
                "  valley-detour initial plan {name}: no plan after {wall:.1} s: {:?}; {}",
                o.failure,
                o.summary.last().map_or("", String::as_str)
            ),
            Err(e) => println!("  valley-detour initial plan {name}: stopped after {wall:.1} s: {e}"),
        }
    }
    Ok(())
}

pub(crate) fn run(root: &Path) -> Result<bool, String> {
    println!("valley-detour (80 x 60 cells, two goals, a night), L + B, tick 60 s:");
    valley(root, 60.0, ObjectiveSpec::Energy, VALLEY_EXPANSIONS, false)?;
    valley(root, 60.0, ObjectiveSpec::Energy, VALLEY_EXPANSIONS, true)?;
    println!("valley-detour, time to the last goal, tick 60 s:");
    valley(root, 60.0, ObjectiveSpec::Time, VALLEY_TIME_EXPANSIONS, false)?;
    println!("exactness at a tick: one goal across the map, an afternoon start, a night on the way");
    for (cols, tick) in [(20, 60.0), (40, 60.0), (80, 60.0), (80, 600.0)] {
        let world = world(cols)?;
        let mut rover = areo_rover::resources::ResourceModel::hyperion();
        rover.battery.capacity_wh = 1000.0;
        let actions = ActionConfig { wait_step_s: Some(tick), ..Default::default() };
        let model = ActionModel::new(rover, actions.clone());
        let t0 = 14.0 * 3600.0;
        let start = Start { cell: world.cell(2, 2), t_min: t0, t_max: t0, energy_wh: 800.0 };
        let goal = ExactGoal { cell: world.cell(cols - 3, cols * 3 / 4 - 3), open_s: t0, close_s: 50.0 * 3600.0 };
        let (settled, settled_s) = exact(&world, &model, start, goal, true);
        let (chained, chained_s) = exact(&world, &model, start, goal, false);
        let config = PlannerConfig {
            actions,
            max_wait_s: Some(goal.close_s - t0),
            search: SearchMode::Approximate(Classes {
                resolution: Resolution { time_s: tick, energy_wh: None },
                goal_times: 72,
                ..Classes::default()
            }),
            ..PlannerConfig::default()
        };
        let t = Instant::now();
        let planned = Mission::plan(&world, &model, config, start, &[goal.cell]);
        let planner_s = t.elapsed().as_secs_f64();
        println!("{cols} x {} cells, tick {tick} s:", cols * 3 / 4);
        println!("  exact, drives settle to ticks:      {}", describe(&settled, settled_s));
        println!("  exact, drives chained:              {}", describe(&chained, chained_s));
        match planned {
            Ok((_, plan)) => {
                let gap = settled.plan.as_ref().map_or(String::new(), |(c, _)| {
                    format!(", {:+.2} % against the settled optimum", 100.0 * (plan.cost - c) / c)
                });
                println!(
                    "  approximate planner (classes {tick} s): {planner_s:.2} s, {} expansions, cost {:.1}{gap}",
                    plan.expansions, plan.cost
                );
            }
            Err(e) => println!("  approximate planner (classes {tick} s): {planner_s:.2} s: {e}"),
        }
    }
    Ok(true)
}
