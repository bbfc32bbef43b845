//! Re-planning states, rebuilt from the shipped scenarios' own runs
//! (`tests/tempest/lita-step20.ron`, `tests/tempest/valley-step77.ron`), planned at the
//! scenarios' settings and at finer ones: where the settings as shipped find a plan, the
//! finer ones checked here must too. Actions there are unquantised, so no search is exact
//! and this is not guaranteed by construction (docs/tempest.md, "The approximate
//! search"); these are the states where it once failed, kept as regressions. The
//! one dimension found to lose plans at these states — more `goal_times` at
//! valley-detour's, at 62–72 Wh — is measured in docs/tempest.md; at 64 Wh it is
//! asserted here with what recovers it on request (`planner.unreachable_retries`).

use std::path::{Path, PathBuf};

use areo_scenario::budget::Budget;
use areo_scenario::outcome::Outcome;
use areo_scenario::{NoProgress, RunOptions, format::load_set, run};

fn state(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/tempest").join(name)
}

fn plan(path: &Path, sets: &[&str]) -> Outcome {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let file = load_set(path, &sets).unwrap_or_else(|e| panic!("{sets:?}: {e}"));
    run(&file, RunOptions { out_dir: None, progress: &NoProgress, budget: Budget::for_this_machine() })
        .unwrap_or_else(|e| panic!("{sets:?}: {e}"))
}

fn number(o: &Outcome, name: &str) -> f64 {
    o.facts.get(name).and_then(|f| f.as_number()).unwrap_or_else(|| panic!("{name}: {:?}", o.facts.get(name)))
}

/// A plan that is one: found, reaching the goal, never below the battery's floor.
fn assert_planned(o: &Outcome, what: &str) {
    assert_eq!(o.failure, None, "{what}: {:?}", o.summary);
    assert!(number(o, "initial_plan_waypoints") > 1.0, "{what}");
    // The mock solar rover's floor: 10 % of 1000 Wh.
    assert!(number(o, "initial_plan_min_battery_wh") >= 100.0 - 1e-6, "{what}");
}

#[test]
fn lita_step20_keeps_its_plan_at_finer_settings() {
    let path = state("lita-step20.ron");
    let shipped = plan(&path, &[]);
    assert_planned(&shipped, "as shipped (300 s, 25 Wh, 8 goal instants)");
    for sets in [
        &["job.planner.resolution.time_s=150"][..],
        &["job.planner.resolution.energy_wh=10"],
        &["job.planner.resolution.energy_wh=None"],
        &["job.planner.goal_times=12"],
        &["job.planner.goal_times=50"],
        // The case: 200 goal instants found no plan where 8 did.
        &["job.planner.goal_times=200"],
        &["job.planner.resolution.time_s=150", "job.planner.resolution.energy_wh=10", "job.planner.goal_times=200"],
    ] {
        assert_planned(&plan(&path, sets), &format!("{sets:?}"));
    }
}

#[test]
fn valley_step77_keeps_its_plan_at_finer_classes_down_to_a_tight_battery() {
    let path = state("valley-step77.ron");
    // From 80 Wh above the floor down to 64 Wh (the shipped settings plan the detour
    // from 62 Wh, not from 60; 100 goal instants instead of 72 find none at 62–72 Wh).
    let mut planned = None;
    for battery in [80, 68, 64] {
        let b = format!("job.start_battery_above_floor_wh={battery}");
        let shipped = plan(&path, &[&b]);
        assert_planned(&shipped, &format!("{battery} Wh as shipped"));
        planned.get_or_insert(shipped);
        for finer in [
            "job.planner.resolution.time_s=600",
            "job.planner.resolution.energy_wh=10",
            // The case: E collapsed lost this plan; E exact must find it.
            "job.planner.resolution.energy_wh=None",
        ] {
            assert_planned(&plan(&path, &[&b, finer]), &format!("{battery} Wh, {finer}"));
        }
    }
    // Below what any setting plans with: "unreachable (battery)", and not called a proof.
    let low = plan(&path, &["job.start_battery_above_floor_wh=40"]);
    assert!(matches!(low.failure, Some(areo_scenario::outcome::Failure::Unreachable { .. })), "{:?}", low.failure);
    assert_eq!(low.facts.get("unreachable_proven"), Some(&areo_scenario::outcome::Fact::Flag(false)));
    // What the verdict cost, split between the plan's settings and the two probes that
    // named the battery (all constraints relaxed first, then the battery alone, which
    // makes a plan, so no other probe runs — the goal windows, which close before the
    // horizon, are named as a possibility, not searched).
    let total = number(&low, "no_plan_expansions");
    let planning = number(&low, "no_plan_planning_expansions");
    assert_eq!(number(&low, "no_plan_probes"), 2.0);
    assert!(planning > 0.0 && planning < total, "{planning} of {total}");
    assert!(number(&low, "no_plan_s") > 0.0);
    let line = low.summary.iter().find(|l| l.starts_with("no plan after ")).expect("the work line");
    let probes: Vec<f64> = ["with every constraint relaxed", "with battery relaxed"]
        .iter()
        .map(|p| {
            let before = &line[..line.find(p).unwrap_or_else(|| panic!("{p}: {line}"))];
            before.trim_end().rsplit([' ', ',']).next().unwrap().parse().unwrap()
        })
        .collect();
    assert_eq!(planning + probes.iter().sum::<f64>(), total, "{line}");
    // A planned state (80 Wh, above) reports no such line.
    assert!(!planned.expect("80 Wh planned").facts.contains_key("no_plan_expansions"));
}

/// valley-detour on its former classes (`sweeps/valley-detour-classes.base.ron`),
/// planned only (no simulation), from its own start with a
/// battery low enough that charging decides: two goals, so `segment_starts` matters
/// too (measured at 40, 20, 10 and 5 Wh: every setting below plans; at
/// 1 Wh none does at 72 goal instants and 100 instants do).
#[test]
fn valley_detour_keeps_its_two_goal_plan_at_finer_settings() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(root.join("scenarios/sweeps/valley-detour-classes.base.ron")).unwrap();
    let simulate = "        simulate: (sense_radius_cells: 2),\n";
    assert!(text.contains(simulate));
    let rovers = format!("\"{}/", root.join("scenarios/rovers").display());
    let dir = std::env::temp_dir().join(format!("areo_resolution_states_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("valley-plan.ron");
    std::fs::write(&path, text.replace(simulate, "").replace("\"../rovers/", &rovers)).unwrap();
    for battery in [20, 5] {
        let b = format!("job.start_battery_above_floor_wh={battery}");
        assert_planned(&plan(&path, &[&b]), &format!("{battery} Wh as shipped"));
        for finer in [
            "job.planner.segment_starts=32",
            "job.planner.segment_starts=48",
            "job.planner.resolution.time_s=600",
            "job.planner.resolution.energy_wh=None",
        ] {
            let o = plan(&path, &[&b, finer]);
            assert_planned(&o, &format!("{battery} Wh, {finer}"));
            assert_eq!(number(&o, "initial_plan_goals"), 2.0, "{battery} Wh, {finer}");
        }
    }
}

/// The dimension that loses plans at valley-detour's state: from 64 Wh above the floor,
/// 100 goal instants instead of 72 find no plan at the shipped 1200 s classes ("not a
/// proof", said so). `planner.unreachable_retries: 2` searches again at 600 s and then
/// 300 s, and 300 s finds the detour: the plan reports the classes it was found at and
/// says it is a fallback; one retry (600 s) is not enough, and its message names the
/// classes it searched. (No retry count is a guarantee: docs/tempest.md.)
#[test]
fn valley_step77_at_100_goal_instants_needs_the_retries_at_halved_classes() {
    use areo_scenario::outcome::{Fact, Failure};
    let path = state("valley-step77.ron");
    let sets = ["job.start_battery_above_floor_wh=64", "job.planner.goal_times=100"];
    let once = plan(&path, &[sets[0], sets[1], "job.planner.unreachable_retries=1"]);
    match &once.failure {
        Some(Failure::Unreachable { message, .. }) => {
            assert!(message.contains("not a proof: searched at time classes of 600 s"), "{message}");
            assert!(message.contains("the configured 1200 s halved 1 time(s)"), "{message}");
        }
        other => panic!("one retry: {other:?}"),
    }
    let twice = plan(&path, &[sets[0], sets[1], "job.planner.unreachable_retries=2"]);
    assert_planned(&twice, "100 goal instants, two retries");
    assert_eq!(twice.facts.get("initial_plan_halved_classes_fallback"), Some(&Fact::Flag(true)));
    assert_eq!(twice.facts.get("initial_plan_quanta_fallback"), Some(&Fact::Flag(false)));
    assert!(twice.summary.iter().any(|l| l.contains("searched again at time classes of 300 s")), "{:?}", twice.summary);
    // The 26–28 h detour through the night, as at 72 instants.
    let hours = number(&twice, "initial_plan_duration_h");
    assert!((25.0..30.0).contains(&hours), "{hours} h");
    // Retries run only where the settings found nothing: at 72 instants the shipped
    // classes plan, and the retries change nothing.
    let shipped = plan(&path, &[sets[0]]);
    let with_retries = plan(&path, &[sets[0], "job.planner.unreachable_retries=2"]);
    assert_eq!(shipped.facts.get("initial_plan_halved_classes_fallback"), Some(&Fact::Flag(false)));
    assert_eq!(number(&shipped, "initial_plan_duration_h"), number(&with_retries, "initial_plan_duration_h"));
    assert_eq!(number(&shipped, "initial_plan_expansions"), number(&with_retries, "initial_plan_expansions"));
}

/// A retry count out of range is refused before any search, naming the file, the field
/// and what is allowed.
#[test]
fn unreachable_retries_out_of_range_name_the_file_and_the_field() {
    let path = state("valley-step77.ron");
    for (sets, allowed) in [
        (&["job.planner.unreachable_retries=7"][..], "allowed 0..=6"),
        // 3 s halved twice is under the 1 s a class can be.
        (&["job.planner.unreachable_retries=2", "job.planner.resolution.time_s=3"], "allowed: at least 1 s"),
        (&["job.planner.unreachable_retries=-1"], "allowed a whole number of 0 or more"),
    ] {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let error = match load_set(&path, &sets) {
            Err(e) => e.to_string(),
            Ok(file) => match run(
                &file,
                RunOptions { out_dir: None, progress: &NoProgress, budget: Budget::for_this_machine() },
            ) {
                Err(e) => e.to_string(),
                Ok(o) => panic!("{sets:?}: ran ({:?})", o.failure),
            },
        };
        assert!(error.contains("valley-step77.ron"), "{sets:?}: {error}");
        assert!(error.contains("unreachable_retries"), "{sets:?}: {error}");
        assert!(error.contains(allowed), "{sets:?}: {error}");
    }
}

/// With quantised actions `unreachable_retries` searches at halved classes before the
/// last resort exact at the quanta. On `small-quantised.ron` (3 Wh, two goal instants,
/// 40-minute classes) the settings find nothing: without retries the exact search
/// finds the 32.4 h plan; with one retry the 20-minute classes find it, for an eighth
/// of the expansions, and the plan and the summary say which fallback it is.
#[test]
fn quantised_actions_retry_at_halved_classes_before_the_exact_search() {
    use areo_scenario::outcome::Fact;
    let path = state("small-quantised.ron");
    let exact = plan(&path, &[]);
    let retried = plan(&path, &["job.planner.unreachable_retries=1"]);
    for (o, what) in [(&exact, "the last resort"), (&retried, "one retry")] {
        assert_planned(o, what);
        let hours = number(o, "initial_plan_duration_h");
        assert!((30.0..35.0).contains(&hours), "{what}: {hours} h");
    }
    assert_eq!(exact.facts.get("initial_plan_quanta_fallback"), Some(&Fact::Flag(true)));
    assert_eq!(exact.facts.get("initial_plan_halved_classes_fallback"), Some(&Fact::Flag(false)));
    assert_eq!(retried.facts.get("initial_plan_quanta_fallback"), Some(&Fact::Flag(false)));
    assert_eq!(retried.facts.get("initial_plan_halved_classes_fallback"), Some(&Fact::Flag(true)));
    assert!(
        retried.summary.iter().any(|l| l.contains("searched again at time classes of 1200 s")
            && l.contains("before the last resort exact at the quanta")),
        "{:?}",
        retried.summary
    );
    assert!(exact.summary.iter().any(|l| l.contains("exact at the actions' quanta")), "{:?}", exact.summary);
    // Its one simulated step charges: no drive, and no "-0.0 h" of driving (a sum of
    // no f64 is -0).
    assert!(retried.summary.iter().any(|l| l.contains("0 m driven in 0.0 h")), "{:?}", retried.summary);
    assert!(retried.summary.iter().any(|l| l.starts_with("1 re-plan (")), "{:?}", retried.summary);
    // Measured: 1 030 713 expansions at the quanta, 126 690 with the retry.
    let (at_quanta, by_retry) =
        (number(&exact, "initial_plan_expansions"), number(&retried, "initial_plan_expansions"));
    assert!(by_retry * 5.0 < at_quanta, "{by_retry} expansions with the retry, {at_quanta} at the quanta");
}

/// The guaranteed mode on a whole mission: `sweeps/valley-detour-resolution.sweep.ron`
/// runs valley-detour with its actions quantised to a minute at its own settings and
/// at five finer ones (100 and 144 goal instants, 600 s classes, 48 start intervals,
/// energy exact), and every task completes both goals in daylight with the 100 Wh the
/// mission asks for — through the wall's discovery, the detour and the night.
#[test]
fn valley_detour_at_quanta_completes_at_its_settings_and_five_finer_ones() {
    use areo_scenario::outcome::Fact;
    let sweep_path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/sweeps/valley-detour-resolution.sweep.ron");
    let dir = std::env::temp_dir().join(format!("areo-valley-resolution-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let tasks = areo_scenario::sweep::expand(&sweep_path, &dir).unwrap();
    assert_eq!(tasks.len(), 6);
    for task in &tasks {
        // As `areo sweep run` does: the base's relative paths (its rover file) resolve
        // from the base's directory, and the outputs go under the sweep directory.
        let o = match areo_scenario::sweep::run_task(&dir, task.index, false, &NoProgress, Budget::for_this_machine()) {
            Ok(areo_scenario::sweep::TaskRun::Ran(_, o)) => o,
            other => panic!("{}: {other:?}", task.id),
        };
        assert_eq!(o.facts.get("status"), Some(&Fact::Text("completed".into())), "{}: {:?}", task.id, o.summary);
        assert_eq!(number(&o, "goals_reached"), 2.0, "{}", task.id);
        assert_eq!(number(&o, "night_drives"), 0.0, "{}", task.id);
        assert!(number(&o, "final_battery_above_floor_wh") >= 100.0 - 1e-6, "{}", task.id);
        // The detour waits out one night and reaches goal 2 the next day.
        let arrival = number(&o, "goals.goal2.arrival_h");
        assert!((28.0..34.0).contains(&arrival), "{}: goal 2 after {arrival} h", task.id);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `path` with `sets`, planned on a tick of `tick_s` with no other resolution knob.
fn plan_on_tick(path: &Path, sets: &[&str], tick_s: f64) -> Outcome {
    use areo_scenario::format::{
        Job,
        planner::{PlannerSpec, SearchSpec},
    };
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let mut file = load_set(path, &sets).unwrap_or_else(|e| panic!("{sets:?}: {e}"));
    let Job::Tempest(job) = &mut file.scenario.job else { panic!("{path:?} is not a TEMPEST job") };
    job.planner = PlannerSpec {
        search: SearchSpec::Exact { tick_s },
        objective: job.planner.objective,
        goal_energy_wh: job.planner.goal_energy_wh,
        max_wait_s: job.planner.max_wait_s,
        ..PlannerSpec::default()
    };
    run(&file, RunOptions { out_dir: None, progress: &NoProgress, budget: Budget::for_this_machine() })
        .unwrap_or_else(|e| panic!("{sets:?}: {e}"))
}

/// The kept re-planning states on a 60 s tick, where every answer is exact: lita's
/// step 20 plans (200 goal instants lost it once); valley's step 77 plans the detour
/// through the night from 64 Wh (where 100 goal instants lost it), and from 40 Wh
/// "unreachable" is a proof naming the battery.
#[test]
fn the_kept_states_plan_on_a_60_s_tick_and_unreachable_is_a_proof() {
    use areo_scenario::outcome::Failure;
    let lita = plan_on_tick(&state("lita-step20.ron"), &[], 60.0);
    assert_planned(&lita, "lita step 20 on a 60 s tick");
    assert_eq!(number(&lita, "initial_plan_tick_s"), 60.0);
    let valley = state("valley-step77.ron");
    let planned = plan_on_tick(&valley, &["job.start_battery_above_floor_wh=64"], 60.0);
    assert_planned(&planned, "valley step 77 at 64 Wh on a 60 s tick");
    // The detour through the night, the night waited out in one wait.
    let hours = number(&planned, "initial_plan_duration_h");
    assert!((24.0..30.0).contains(&hours), "{hours} h");
    assert!(number(&planned, "initial_plan_waypoints") < 120.0, "{:?}", planned.summary);
    let low = plan_on_tick(&valley, &["job.start_battery_above_floor_wh=40"], 60.0);
    match &low.failure {
        Some(Failure::Unreachable { message, .. }) => {
            assert!(message.contains("battery energy"), "{message}");
            assert!(message.contains("proven at the tick of 60 s"), "{message}");
            assert!(!message.contains("not a proof"), "{message}");
        }
        other => panic!("40 Wh on a 60 s tick: {other:?}"),
    }
}
