//! Task 1 (scenarios/ditch-and-hill.ron) needs planning: straight driving and plans
//! that go straight and then hold one arc all fail on it — exhaustively over where the
//! arc starts — while the shipped GA run completes it (scenarios/expected).

use std::path::Path;

use areo_actions::{ExecConfig, Executor};
use areo_rover::evaluation::Evaluator;
use areo_rover::motion::Module;
use areo_scenario::format::{ActionsJob, Job, load};
use areo_scenario::jobs::actions::setup;

fn task1() -> (areo_scenario::format::ScenarioFile, ActionsJob) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/ditch-and-hill.ron");
    let file = load(&path).unwrap();
    let Job::Actions(job) = file.scenario.job.clone() else { panic!("task 1 is an actions job") };
    (file, *job)
}

#[test]
fn straight_and_single_arc_plans_fail_on_task_1() {
    let (file, job) = task1();
    let s = setup(&job, &file).unwrap();
    let ev = Evaluator::new(&s.params);
    let ex = Executor::new(&s.dem, &ev, &s.task, ExecConfig { ..job.execution });
    assert!(ex.start_problem().is_none());
    // Straight: 6 m of 101, more than the way.
    let straight = ex.run(&[Module::Forward; 60], false);
    assert!(!straight.complete);
    let (at, why) = straight.failure.clone().expect("straight driving is stopped");
    // By the rock in the left wheel track, 0.85 m ahead of the front wheels: the
    // front-left wheel cannot climb a rock as tall as itself.
    assert!(at <= 9, "stopped at module {at}: {why}");
    assert_eq!(why.kind(), "slip", "{why}");
    let arcs = [Module::ArcLeftTight, Module::ArcLeftWide, Module::ArcRightTight, Module::ArcRightWide];
    let mut plans = 0;
    for arc in arcs {
        for k in 0..=55 {
            let mut plan = vec![Module::Forward; k];
            plan.resize(80, arc);
            let run = ex.run(&plan, false);
            assert!(!run.complete, "{k} × 101 then {}: completed", arc.code());
            plans += 1;
        }
    }
    assert_eq!(plans, 4 * 56);
}
