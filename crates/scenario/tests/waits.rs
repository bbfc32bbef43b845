//! A TEMPEST run whose rover waits (`actions.wait_step_s`) instead of the paper's Charge
//! and Hibernate: an evening start on the small simulation world, so that the rover must
//! wait out the night before it may drive on.

use std::path::Path;

use areo_scenario::budget::Budget;
use areo_scenario::outcome::Fact;
use areo_scenario::{NoProgress, RunOptions, format::load, run};

#[test]
fn a_rover_that_waits_crosses_the_night_in_wait_steps_and_idles_waiting() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(root.join("tests/tempest/small.ron")).unwrap();
    let rover = root.join("scenarios/rovers/mock-solar-rover.ron");
    // Late afternoon at Gale (about 17:30 local solar time): the night falls on the way.
    let text = text
        .replace("\"../../scenarios/rovers/mock-solar-rover.ron\"", &format!("{:?}", rover.display().to_string()))
        .replace("2012-08-06T23:00:00Z", "2012-08-07T08:00:00Z")
        .replace("planner: (goal_times: 200,", "planner: (actions: (wait_step_s: Some(600)), goal_times: 200,");
    assert!(text.contains("wait_step_s") && text.contains("08:00:00Z"), "the overrides apply");
    let dir = root.join("target/waits-tests");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("evening.ron");
    std::fs::write(&path, text).unwrap();
    let file = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let o = run(&file, RunOptions { out_dir: None, progress: &NoProgress, budget: Budget::for_this_machine() })
        .unwrap_or_else(|e| panic!("{e}"));
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
