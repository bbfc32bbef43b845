//! Re-planning on kept graphs returns what a fresh search of the same problem
//! returns, checked on a multi-goal world with moving shadows, Earth contact and
//! sensing — the lunar-south-pole scenario on the approximate planner's settings
//! (four chained goals, 6 start intervals, 12 goal instants, 1 h / 100 Wh classes)
//! executed on true terrain with
//! three landforms its map lacks (`tests/tempest/lunar-sensing.ron`). Every re-plan
//! after sensing changed the map or a goal was reached is compared, and every 50th of
//! the others (plan extension alone); `cargo xtask bench fresh` compares all of them.

use std::path::Path;

use areo_scenario::budget::Budget;
use areo_scenario::outcome::Fact;
use areo_scenario::{NoProgress, RunOptions, format::load, run};

#[test]
fn lunar_replans_on_kept_graphs_equal_fresh_searches() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/tempest/lunar-sensing.ron");
    let file = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let o = run(&file, RunOptions { out_dir: None, progress: &NoProgress, budget: Budget::for_this_machine() })
        .unwrap_or_else(|e| panic!("{e}"));
    let number = |name: &str| o.facts.get(name).and_then(Fact::as_number).unwrap_or_else(|| panic!("{name}: {o:?}"));
    assert_eq!(o.failure, None, "{:?}", o.summary);
    assert_eq!(number("goals_reached"), 4.0, "{:?}", o.summary);
    // The check is not idle: sensing repaired the graphs often, and the route changed.
    let sensed = number("replans_after_sensing");
    assert!(sensed >= 20.0, "{sensed} re-plans after sensing");
    assert!(number("route_changes") >= 3.0, "{:?}", o.summary);
    // Those, the three goal changes and every 50th of ~360 re-plans.
    let compared = number("fresh_compared");
    assert!(compared >= sensed + 3.0 + 5.0, "{compared} compared, {sensed} after sensing");
    // Equal costs, and no re-plan did more work than searching afresh.
    assert!(number("replan_fresh_cost_difference") <= 1e-9, "{:?}", o.summary);
    assert_eq!(number("replans_above_fresh"), 0.0, "{:?}", o.summary);
    assert_eq!(number("restarts"), 0.0, "{:?}", o.summary);
}

/// A rover three times slower than planned on goal windows with no room to wait: its
/// re-plans on the kept graphs find nothing and it plans afresh. Each restart is
/// counted with its work, and compared with a fresh search of the problem the re-plan
/// answered, which agrees that it has no plan.
#[test]
fn restarts_are_counted_with_their_work_and_compared_with_fresh_searches() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(root.join("tests/tempest/small.ron")).unwrap();
    let rover = root.join("scenarios/rovers/mock-solar-rover.ron");
    let text = text
        .replace("\"../../scenarios/rovers/mock-solar-rover.ron\"", &format!("{:?}", rover.display().to_string()))
        .replace(
            "planner: (approximate: true, goal_times: 200,",
            "planner: (approximate: true, detour_factor: 1.0, max_wait_s: 0, goal_times: 200,",
        )
        .replace("drive_slowdown: 0.1", "drive_slowdown: 2.0")
        .replace("simulate: (sense_radius_cells: 2,", "simulate: (sense_radius_cells: 2, compare_fresh: true,");
    let dir = root.join("target/fresh-replans-tests");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("slow.ron");
    std::fs::write(&path, text).unwrap();
    let file = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let o = run(&file, RunOptions { out_dir: None, progress: &NoProgress, budget: Budget::for_this_machine() })
        .unwrap_or_else(|e| panic!("{e}"));
    let number = |name: &str| o.facts.get(name).and_then(Fact::as_number).unwrap_or_else(|| panic!("{name}: {o:?}"));
    let restarts = number("restarts");
    assert!(restarts >= 1.0, "{:?}", o.summary);
    assert!(number("restart_replan_work") > 0.0 && number("restart_expansions") > 0.0, "{:?}", o.summary);
    assert_eq!(number("restarts_fresh_compared"), restarts);
    assert_eq!(number("restarts_fresh_disagree"), 0.0, "{:?}", o.summary);
    let line = o.summary.iter().find(|l| l.contains("restart(s): re-planning")).expect("a summary line");
    assert!(line.contains("GoalWindow") && line.contains("found a plan in 0 of"), "{line}");
}
