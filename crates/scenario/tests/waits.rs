//! A TEMPEST run whose rover waits (`actions.wait_step_s`) instead of the paper's Charge
//! and Hibernate: an evening start on the small simulation world, so that the rover must
//! wait out the night before it may drive on.

use std::path::Path;

use areo_scenario::budget::Budget;
use areo_scenario::outcome::Fact;
use areo_scenario::{NoProgress, RunOptions, format::load, run};

#[test]
fn a_rover_that_waits_crosses_the_night_in_wait_steps_and_idles_waiting() {
    // Late afternoon at Gale (about 17:30 local solar time): the night falls on the way.
    let o = run_file(&small_with(
        &[
            ("2012-08-06T23:00:00Z", "2012-08-07T08:00:00Z"),
            (
                "planner: (approximate: true, goal_times: 200,",
                "planner: (approximate: true, actions: (wait_step_s: Some(600)), goal_times: 200,",
            ),
        ],
        "evening.ron",
    ));
    let number = |name: &str| o.facts.get(name).and_then(Fact::as_number).unwrap_or_else(|| panic!("{name}: {o:?}"));
    assert_eq!(o.failure, None, "{:?}", o.summary);
    assert_eq!(number("goals_reached"), 1.0, "{:?}", o.summary);
    // The plan stands still in wait steps only, and the run waited through the night.
    assert_eq!(number("initial_plan_charges") + number("initial_plan_hibernations"), 0.0, "{:?}", o.summary);
    assert!(number("initial_plan_wait_steps") >= 20.0, "{:?}", o.summary);
    assert!(number("wait_h") >= 8.0 && number("nights") >= 1.0, "{:?}", o.summary);
    assert!(o.summary.iter().any(|l| l.contains("waited")), "{:?}", o.summary);
    // Before each plan's start the rover idles as it waits — charging where lit — not
    // asleep with its array off-line: asleep, the idles before the re-plans' starts
    // (16 h of them) emptied the battery and the goal became unreachable.
    assert_eq!(number("hibernate_h"), 0.0, "{:?}", o.summary);
    assert!(number("min_battery_wh") > number("final_battery_wh") - number("final_battery_above_floor_wh"));
}

/// small.ron's planner settings.
const SMALL_PLANNER: &str = "planner: (approximate: true, goal_times: 200, resolution: (time_s: 600, energy_wh: 25)),";

/// small.ron's simulation settings.
const SMALL_SIMULATE: &str =
    "        simulate: (sense_radius_cells: 2, noise: (drive_slowdown: 0.1, solar_loss: 0.1, seed: 5)),\n";

/// small.ron with each `(from, to)` of `changes` applied (each must apply), written as
/// `name` under target/waits-tests.
fn small_with(changes: &[(&str, &str)], name: &str) -> std::path::PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let rover = root.join("scenarios/rovers/mock-solar-rover.ron");
    let mut text = std::fs::read_to_string(root.join("tests/tempest/small.ron"))
        .unwrap()
        .replace("\"../../scenarios/rovers/mock-solar-rover.ron\"", &format!("{:?}", rover.display().to_string()));
    for (from, to) in changes {
        assert!(text.contains(from), "the change of {from:?} applies");
        text = text.replace(from, to);
    }
    let dir = root.join("target/waits-tests");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn run_file(path: &Path) -> areo_scenario::Outcome {
    let file = load(path).unwrap_or_else(|e| panic!("{e}"));
    run(&file, RunOptions { out_dir: None, progress: &NoProgress, budget: Budget::for_this_machine() })
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_run_on_a_tick_plans_exactly_and_re_plans_as_fresh_searches_do() {
    let o = run_file(&small_with(
        &[
            (SMALL_SIMULATE, ""),
            (
                SMALL_PLANNER,
                "planner: (tick_s: Some(600)),\n        simulate: (sense_radius_cells: 2, compare_fresh: true),",
            ),
        ],
        "tick.ron",
    ));
    let number = |name: &str| o.facts.get(name).and_then(Fact::as_number).unwrap_or_else(|| panic!("{name}: {o:?}"));
    assert_eq!(o.failure, None, "{:?}", o.summary);
    assert_eq!(number("goals_reached"), 1.0, "{:?}", o.summary);
    assert_eq!(number("initial_plan_tick_s"), 600.0);
    assert!(o.summary.iter().any(|l| l.contains("exact at the tick of 600 s")), "{:?}", o.summary);
    // Every re-plan — those that kept the rest of the plan and those that searched after
    // the hill came into view — costs what a fresh search costs.
    assert!(number("fresh_compared") >= 10.0, "{:?}", o.summary);
    assert!(number("replan_fresh_cost_difference") <= 1e-12, "{:?}", o.summary);
    assert!(number("replans_after_sensing") >= 1.0, "{:?}", o.summary);
    assert_eq!(number("restarts"), 0.0, "{:?}", o.summary);
}

#[test]
fn the_knobs_a_tick_replaces_are_refused_naming_tick_s() {
    for (planner, field) in [
        ("planner: (tick_s: Some(600), goal_times: 200),", "planner.goal_times"),
        ("planner: (tick_s: Some(600), resolution: (time_s: 600)),", "planner.resolution"),
        ("planner: (tick_s: Some(600), actions: (wait_step_s: Some(600))),", "planner.actions.wait_step_s"),
        ("planner: (tick_s: Some(600), segment_starts: 3),", "planner.segment_starts"),
        ("planner: (tick_s: Some(600), path_length: Steps),", "planner.path_length"),
    ] {
        let err = load(&small_with(&[(SMALL_PLANNER, planner)], "refused.ron")).expect_err(planner).to_string();
        assert!(err.contains(field) && err.contains("tick_s") && err.contains("refused.ron"), "{planner}: {err}");
    }
    let margin = "planner: (tick_s: Some(600), objective: Margin(max_duration_s: 86400)),";
    assert!(load(&small_with(&[(SMALL_PLANNER, margin)], "ok.ron")).is_ok());
    assert!(load(&small_with(&[(SMALL_PLANNER, "planner: (tick_s: Some(600), objective: Time),")], "ok.ron")).is_ok());
    let err = load(&small_with(&[(SMALL_PLANNER, "planner: (tick_s: Some(0.5)),")], "refused.ron"))
        .expect_err("a half-second tick");
    assert!(err.to_string().contains("planner.tick_s") && err.to_string().contains("1..=86400"), "{err}");
}

/// A planner block that sets none of the approximate search's fields, or none at all,
/// plans exactly on the default tick; one that sets any of them (even to its default value) asks for the
/// approximate search, and a given `tick_s` is kept as written.
#[test]
fn a_planner_block_without_the_approximate_fields_plans_on_the_default_tick() {
    use areo_scenario::format::{Job, planner::DEFAULT_TICK_S};
    let tick_of = |planner: &str| {
        let file = load(&small_with(&[(SMALL_PLANNER, planner)], "default-tick.ron")).unwrap_or_else(|e| panic!("{e}"));
        let Job::Tempest(job) = &file.scenario.job else { panic!("a TEMPEST job") };
        (job.planner.search.tick_s(), job.planner.max_wait_s)
    };
    assert_eq!(tick_of("planner: (),"), (Some(DEFAULT_TICK_S), None));
    assert_eq!(tick_of(""), (Some(DEFAULT_TICK_S), None), "no planner block");
    assert_eq!(tick_of("planner: (max_wait_s: 7200, objective: Time),"), (Some(DEFAULT_TICK_S), Some(7200.0)));
    assert_eq!(tick_of("planner: (tick_s: 600),"), (Some(600.0), None));
    // The approximate search's fields are refused, naming the field and `tick_s`, unless
    // the block opts in to that search.
    for (fields, field) in [
        ("resolution: (time_s: 60)", "planner.resolution"),
        ("goal_times: 24", "planner.goal_times"),
        ("segment_starts: 8", "planner.segment_starts"),
        ("unreachable_retries: 0", "planner.unreachable_retries"),
        ("actions: (time_quantum_s: 5)", "planner.actions.time_quantum_s"),
        ("actions: (wait_step_s: 600)", "planner.actions.wait_step_s"),
    ] {
        let planner = format!("planner: ({fields}),");
        let err = load(&small_with(&[(SMALL_PLANNER, &planner)], "refused.ron")).expect_err(&planner).to_string();
        assert!(err.contains(field) && err.contains("tick_s") && err.contains("approximate: true"), "{planner}: {err}");
        assert_eq!(tick_of(&format!("planner: (approximate: true, {fields}),")).0, None, "{fields}");
    }
    assert_eq!(tick_of("planner: (approximate: true),").0, None);
    // A setting with no effect in the mode chosen is refused, naming both fields.
    for (planner, fields) in [
        ("planner: (approximate: true, tick_s: 60),", ["planner.approximate", "planner.tick_s"]),
        (
            "planner: (objective: Time, path_length: Steps, approximate: true),",
            ["planner.path_length", "planner.objective"],
        ),
        (
            "planner: (objective: EnergyUsed, path_length: Steps, approximate: true),",
            ["planner.path_length", "planner.objective"],
        ),
    ] {
        let err = load(&small_with(&[(SMALL_PLANNER, planner)], "refused.ron")).expect_err(planner).to_string();
        assert!(fields.iter().all(|f| err.contains(f)) && err.contains("refused.ron"), "{planner}: {err}");
    }
    assert_eq!(tick_of("planner: (objective: Energy, path_length: Steps, approximate: true),").0, None);
    // And it runs so: exact at 60 s, the goal reached.
    let o = run_file(&small_with(&[(SMALL_SIMULATE, ""), (SMALL_PLANNER, "planner: (),")], "default-tick.ron"));
    assert_eq!(o.failure, None, "{:?}", o.summary);
    assert!(o.summary.iter().any(|l| l.contains("exact at the tick of 60 s")), "{:?}", o.summary);
}
