//! The planner on a tick (`SearchMode::Exact`): its plan is the exact search's over
//! the mission's goal windows and replays on the model; a simulated run's re-plans —
//! those that keep the rest of the last plan and those that search again — cost what
//! fresh searches cost; "unreachable" is a proof that names the constraint that binds.

use areo_mission::exact::{ExactGoal, ExactQuery};
use areo_mission::{
    Action, ActionConfig, Binding, Error, Mission, Objective, Perturbation, PlanKind, PlannerConfig, SearchMode,
    SimConfig, SimStatus, Simulation, Start, World, simulate,
};
use areo_terrain::Dem;

use crate::common::{mars_world, model};

const TICK_S: f64 = 600.0;

/// Rolling ground on 20 m cells; with `wall`, a 40 m wall across columns 9–10 from row 3
/// down to the south edge.
fn ground(wall: bool) -> Dem {
    Dem::from_fn(16, 12, 20.0, 20.0, move |x, y| {
        let (c, r) = ((x / 20.0).floor() as usize, (11.0 - (y / 20.0).floor()) as usize);
        let base = 4.0 * (x / 61.0).sin() + 3.0 * (y / 37.0).cos();
        if wall && (9..=10).contains(&c) && r >= 3 { base + 40.0 } else { base }
    })
    .unwrap()
}

/// Drives in daylight only, at any heading; waits in steps of the tick.
fn actions() -> ActionConfig {
    let mut a = ActionConfig { wait_step_s: Some(TICK_S), ..Default::default() };
    a.drive.sun_in_camera = false;
    a
}

fn planner(objective: Objective) -> PlannerConfig {
    PlannerConfig { actions: actions(), objective, search: SearchMode::Exact { tick_s: TICK_S }, ..Default::default() }
}

/// The first instant after `from` the Sun sets, s (searched on the Sun table's steps).
fn sunset_after(world: &World, from: f64) -> f64 {
    let mut t = from;
    while world.sun(t).elevation_deg <= 0.0 {
        t += 60.0;
    }
    while world.sun(t).elevation_deg > 0.0 {
        t += 60.0;
    }
    t
}

#[test]
fn a_plan_on_a_tick_is_the_exact_searchs_and_replays_on_the_model() {
    let world = mars_world(ground(false), 40.0, Some(16));
    let model = model(600.0, actions());
    // An hour before sunset with 400 Wh (the night asleep takes about 265 Wh): the rover
    // crosses the map through the night.
    let t0 = sunset_after(&world, 0.0) - 3600.0;
    let start = Start { cell: world.cell(1, 10), t_min: t0, t_max: t0, energy_wh: 400.0 };
    let goal = world.cell(14, 1);
    for objective in [Objective::Energy, Objective::Time] {
        let (mission, plan) = Mission::plan(&world, &model, planner(objective), start, &[goal]).unwrap();
        assert_eq!(plan.tick_s, Some(TICK_S));
        let windows = mission.goal_windows();
        let exact = ExactQuery {
            world: &world,
            model: &model,
            start,
            goals: vec![ExactGoal { cell: goal, open_s: windows[0].0, close_s: windows[0].1 }],
            goal_energy_wh: 0.0,
            objective,
            max_labels: 10_000_000,
            settle: true,
        }
        .solve();
        let (cost, _) = exact.plan.expect("the exact search plans");
        assert!((plan.cost - cost).abs() <= 1e-9 * (1.0 + cost), "{objective:?}: {} vs {cost}", plan.cost);
        // Forward on the model: each action from its waypoint reaches the next one's
        // cell, then the rover waits (charging or asleep) until it — less than a tick
        // after a drive, whole ticks after a wait's first (a wait lasts until the next
        // waypoint); the battery is the waypoints'.
        let floor = 600.0 * model.rover().battery.min_soc;
        let capacity = model.capacity_wh();
        let mut battery = start.energy_wh;
        let first = &plan.waypoints[0];
        if first.t_s > t0 {
            battery = model.wait(&world, start.cell, t0, first.t_s - t0).unwrap().after(battery, capacity);
        }
        assert!(first.t_s - t0 < TICK_S);
        for w in plan.waypoints.windows(2) {
            assert!((w[0].battery_wh - floor - battery).abs() < 1e-6, "{w:?}");
            let action = w[0].action.unwrap();
            let (to, effect) = model.execute(&world, action, w[0].cell, w[0].t_s, Perturbation::NONE).unwrap();
            assert_eq!(to, w[1].cell);
            assert!(effect.lowest(battery, capacity) >= -1e-9);
            battery = effect.after(battery, capacity);
            let gap = w[1].t_s - w[0].t_s - effect.duration_s;
            if action == Action::Wait {
                assert!(gap > -1e-6 && ((gap / TICK_S) - (gap / TICK_S).round()).abs() < 1e-9, "a wait then {gap} s");
            } else {
                assert!((-1e-6..TICK_S).contains(&gap), "{action:?} leaves a gap of {gap} s");
            }
            if gap > 1e-6 {
                battery = model.wait(&world, to, w[0].t_s + effect.duration_s, gap).unwrap().after(battery, capacity);
            }
            // Every departure after the first is on a tick.
            let phase = w[1].t_s / TICK_S;
            assert!(w[1].action.is_none() || (phase - phase.round()).abs() < 1e-9, "{:?}", w[1]);
        }
        let last = plan.waypoints.last().unwrap();
        assert_eq!((last.cell, last.goal, last.action), (goal, Some(0), None));
        // The night is waited out, not driven through.
        assert!(plan.wait_steps() > 0);
    }
}

#[test]
fn re_plans_on_a_tick_cost_what_fresh_searches_cost() {
    // No horizon maps: the wall would change every cell's horizon, and sensing any cell
    // would then change the map.
    let map = mars_world(ground(false), 40.0, None);
    let truth = mars_world(ground(true), 40.0, None);
    let model = model(600.0, actions());
    let t0 = sunset_after(&map, 0.0) - 3.0 * 3600.0;
    let start = Start { cell: map.cell(2, 8), t_min: t0, t_max: t0, energy_wh: 350.0 };
    let goals = [map.cell(5, 4), map.cell(13, 8)];
    let config = SimConfig { compare_fresh: true, fresh_every: 1, sense_radius_cells: 2.0, ..Default::default() };
    let sim = Simulation {
        believed: &map,
        truth: &truth,
        model: &model,
        planner: planner(Objective::Energy),
        start,
        goals: &goals,
        config,
    };
    let report = simulate(&sim, &mut |_| {}).unwrap();
    assert_eq!(report.status, SimStatus::Completed, "{:?}", report.status);
    assert_eq!(report.goals_reached.len(), 2);
    let (mut kept, mut searched, mut repaired) = (0, 0, 0);
    for p in report.plans.iter().filter(|p| p.kind != PlanKind::Initial) {
        assert_eq!(p.kind, PlanKind::Replan, "no restarts on a tick");
        let (fresh_expansions, fresh) = p.fresh.expect("every re-plan compared");
        assert!((p.plan.cost - fresh).abs() <= 1e-9 * (1.0 + fresh), "step {}: {} vs {fresh}", p.step, p.plan.cost);
        if p.expansions == 0 {
            kept += 1
        } else if p.kept_rest {
            // A repair: sensing changed cells off the rest of the plan, and the search for
            // a cheaper plan found none, with less work than a fresh search.
            assert!(p.changed_cells > 0 && p.expansions < fresh_expansions, "{}: {} expansions", p.step, p.expansions);
            repaired += 1
        } else {
            searched += 1
        }
    }
    // Both kinds were tested: the rest of a plan kept where nothing changed, searches
    // where the wall came into view (on this small map always across the rest of the
    // plan: repairs are tested in repair.rs and on the shipped scenarios).
    assert!(kept > 5 && searched > 0, "{kept} kept, {repaired} repaired, {searched} searched");
    assert!(report.plans.iter().any(|p| p.changed_cells > 0 && p.route_changed));
    // The rover settled on ticks: every drive after the first departs on one.
    for s in report.steps.iter().filter(|s| matches!(s.action, Action::Drive(_)) && s.t_s > t0) {
        let phase = s.t_s / TICK_S;
        assert!((phase - phase.round()).abs() < 1e-9, "{s:?}");
    }
}

#[test]
fn unreachable_on_a_tick_is_a_proof_naming_what_binds() {
    let world = mars_world(ground(false), 40.0, Some(16));
    let model = model(600.0, actions());
    // Ten minutes of daylight left, a goal across the map: the rover must wait the night.
    let t0 = sunset_after(&world, 0.0) - 600.0;
    let goal = world.cell(14, 1);
    let plan_with = |energy_wh: f64| {
        let start = Start { cell: world.cell(1, 10), t_min: t0, t_max: t0, energy_wh };
        Mission::plan(&world, &model, planner(Objective::Energy), start, &[goal]).map(|(_, p)| p)
    };
    match plan_with(100.0) {
        Err(Error::Unreachable { binding, message, proven }) => {
            assert_eq!(binding, Binding::Battery, "{message}");
            assert!(proven);
            assert!(message.contains("proven at the tick of 600 s"), "{message}");
        }
        other => panic!("expected unreachable, got {other:?}"),
    }
    // With the battery to sleep through the night it plans.
    assert!(plan_with(450.0).is_ok());
}

/// A proof stays a proof when the searches that name the binding constraint run out of
/// work: the verdict says the constraint was not determined (never a budget stop).
/// Below the proof's own work the call is stopped undecided, as before.
#[test]
fn a_proof_whose_probes_run_out_of_work_stays_a_proof() {
    let world = mars_world(ground(false), 40.0, Some(16));
    let model = model(600.0, actions());
    let t0 = sunset_after(&world, 0.0) - 600.0;
    let goal = world.cell(14, 1);
    let start = Start { cell: world.cell(1, 10), t_min: t0, t_max: t0, energy_wh: 100.0 };
    let plan_with = |max_expansions: Option<u64>| {
        let meter = areo_mission::ExpansionMeter::counting();
        let config = PlannerConfig { max_expansions, meter: meter.clone(), ..planner(Objective::Energy) };
        (Mission::plan(&world, &model, config, start, &[goal]).map(|(_, p)| p), meter)
    };
    // Unlimited: the proof, then the probes, which name the battery.
    let (verdict, meter) = plan_with(None);
    assert!(matches!(verdict, Err(Error::Unreachable { binding: Binding::Battery, .. })), "{verdict:?}");
    let by_phase = meter.expansions_by_phase();
    let proof = by_phase[0].1;
    let probes: u64 = by_phase[1..].iter().map(|p| p.1).sum();
    assert!(proof > 0 && probes > 0, "{by_phase:?}");
    // The budget covers the proof and a little of the probes.
    match plan_with(Some(proof + probes / 10)).0 {
        Err(Error::Unreachable { binding, message, proven }) => {
            assert_eq!(binding, Binding::Undetermined, "{message}");
            assert!(proven, "{message}");
            assert!(message.contains("not determined") && message.contains("proven at the tick"), "{message}");
        }
        other => panic!("expected a proof with the binding undetermined, got {other:?}"),
    }
    // Short of the proof: no verdict.
    assert!(matches!(plan_with(Some(proof / 2)).0, Err(Error::WorkLimit { .. })));
}

/// The paper's L in steps is not searched on a tick (a wait split in two would cost more
/// than the whole): refused, naming the field.
#[test]
fn steps_as_the_path_length_are_refused_on_a_tick() {
    let world = mars_world(ground(false), 10.0, None);
    let model = model(150.0, actions());
    let start = Start { cell: world.cell(1, 10), t_min: 0.0, t_max: 0.0, energy_wh: 50.0 };
    let config = PlannerConfig { path_length: areo_mission::PathLength::Steps, ..planner(Objective::Energy) };
    match Mission::plan(&world, &model, config, start, &[world.cell(5, 5)]) {
        Err(Error::Config { field, message }) => {
            assert_eq!(field, "path_length");
            assert!(message.contains("Steps") && message.contains("approximate: true"), "{message}");
        }
        other => panic!("expected a configuration error, got {other:?}"),
    }
}

#[test]
fn a_tick_needs_the_rover_to_wait_in_its_steps() {
    let world = mars_world(ground(false), 10.0, None);
    let model = model(150.0, ActionConfig { wait_step_s: Some(300.0), ..actions() });
    let start = Start { cell: world.cell(1, 10), t_min: 0.0, t_max: 0.0, energy_wh: 50.0 };
    match Mission::plan(&world, &model, planner(Objective::Energy), start, &[world.cell(5, 5)]) {
        Err(Error::Config { field, message }) => {
            assert_eq!(field, "tick_s");
            assert!(message.contains("wait_step_s"), "{message}");
        }
        other => panic!("expected a configuration error, got {other:?}"),
    }
    let bad = PlannerConfig { search: SearchMode::Exact { tick_s: 0.5 }, ..planner(Objective::Energy) };
    assert!(matches!(bad.validate(), Err(Error::Config { field: "tick_s", .. })));
    assert!(planner(Objective::Time).validate().is_ok());
}

/// Margin on a tick: among plans no longer than `max_duration_s` (every goal by the
/// deadline), the one whose battery at its lowest stays highest. Given more time than the
/// fastest plan takes, it keeps a higher battery than the fastest plan; given less, no
/// plan exists, and the verdict is a proof.
#[test]
fn margin_on_a_tick_keeps_the_battery_highest_within_the_longest_acceptable_plan() {
    let world = mars_world(ground(false), 40.0, Some(16));
    let model = model(600.0, actions());
    let t0 = sunset_after(&world, 0.0) - 6.0 * 3600.0;
    let start = Start { cell: world.cell(1, 10), t_min: t0, t_max: t0, energy_wh: 120.0 };
    let goal = world.cell(14, 1);
    let lowest = |p: &areo_mission::MissionPlan| p.waypoints.iter().map(|w| w.battery_wh).fold(f64::INFINITY, f64::min);
    let (_, fastest) = Mission::plan(&world, &model, planner(Objective::Time), start, &[goal]).unwrap();
    let margin = |hours: f64| planner(Objective::Margin { max_duration_s: hours * 3600.0 });
    let (_, safest) = Mission::plan(&world, &model, margin(4.0), start, &[goal]).unwrap();
    assert!(safest.duration_s() <= 4.0 * 3600.0 + 1e-6, "{} s", safest.duration_s());
    assert!(
        lowest(&safest) > lowest(&fastest) + 1.0,
        "{} Wh against the fastest's {} Wh",
        lowest(&safest),
        lowest(&fastest)
    );
    // The cost is the Wh drawn below the start at the lowest point (inside actions too,
    // which the waypoints do not show): no waypoint lower.
    let floor = model.rover().battery.capacity_wh * model.rover().battery.min_soc;
    assert!(lowest(&safest) >= floor + start.energy_wh - safest.cost - 1e-6, "cost {}", safest.cost);
    let too_short = fastest.duration_s() / 2.0 / 3600.0;
    match Mission::plan(&world, &model, margin(too_short), start, &[goal]) {
        Err(Error::Unreachable { proven, message, .. }) => assert!(proven, "{message}"),
        other => panic!("expected unreachable in {too_short} h, got {:?}", other.map(|(_, p)| p.cost)),
    }
}

/// `compare_fresh` on a tick asks a new planner instance: a re-plan equal to it is
/// `Equal`; one that costs more, or less, where the other problem admits the cheaper
/// plan is `Differs` (the check can fail); a cheaper re-plan that reaches the goal
/// after the instance's window closes is explained by the windows.
#[test]
fn an_independent_planner_instance_tells_a_lost_optimum_from_a_window() {
    use areo_mission::FreshCheck;
    let world = mars_world(ground(true), 40.0, Some(16));
    let model = model(600.0, actions());
    let t0 = sunset_after(&world, 0.0) - 6.0 * 3600.0;
    let goal = world.cell(14, 1);
    let start = Start { cell: world.cell(1, 10), t_min: t0, t_max: t0, energy_wh: 400.0 };
    let config = planner(Objective::Energy);
    let (mission, plan) = Mission::plan(&world, &model, config.clone(), start, &[goal]).unwrap();
    let check = |p: &areo_mission::MissionPlan| {
        FreshCheck::of(&mission, p, (&world, &model, &config), start, &[goal]).unwrap().expect("compared").1
    };
    assert_eq!(check(&plan), FreshCheck::Equal);
    let dearer = areo_mission::MissionPlan { cost: plan.cost + 1.0, ..plan.clone() };
    assert_eq!(check(&dearer), FreshCheck::Differs, "the instance's plan meets the mission's windows");
    let cheaper = areo_mission::MissionPlan { cost: plan.cost - 1.0, ..plan.clone() };
    assert_eq!(check(&cheaper), FreshCheck::Differs, "the re-plan meets the instance's windows");
    // The same cheaper plan, but reaching the goal after every window closes.
    let mut late = cheaper.clone();
    let at_goal = late.waypoints.iter_mut().find(|w| w.goal.is_some()).expect("the goal's waypoint");
    at_goal.t_s = mission.goal_windows()[0].1 + 3600.0;
    assert_eq!(check(&late), FreshCheck::Windows);
}
