//! Issue 34, item 6: re-planning on kept graphs returns what a fresh search of the same
//! problem returns, checked on a multi-goal world with moving shadows, Earth contact and
//! sensing — the shipped lunar-south-pole scenario (four chained goals, 6 start
//! intervals, 12 goal instants, 1 h / 100 Wh classes) executed on true terrain with
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
