//! Execution simulation: a map that lacks an obstacle, sensing, re-planning, noise.

use areo_mission::{
    Action, ActionConfig, ActionModel, Binding, Error, Mission, Noise, PlanKind, PlannerConfig, SimConfig, SimStatus,
    Simulation, Start, World, metrics::PlanMetrics, simulate,
};
use areo_terrain::Dem;

use crate::common::*;

/// A simulation with the default planner.
fn sim_of<'a>(
    believed: &'a World,
    truth: &'a World,
    model: &'a ActionModel,
    start: Start,
    goals: &'a [u32],
    config: SimConfig,
) -> Simulation<'a> {
    Simulation { believed, truth, model, planner: PlannerConfig::default(), start, goals, config }
}

/// Flat 30 × 20 cells of 10 m; the truth has a 30 m block (vertical walls: far above
/// the 20° limit) across the straight route, columns 14–16, rows `rows`.
fn block(rows: std::ops::RangeInclusive<usize>) -> Dem {
    Dem::from_fn(30, 20, 10.0, 10.0, |x, y| {
        let (c, r) = ((x / 10.0).floor() as usize, (19.0 - (y / 10.0).floor()) as usize);
        if (14..=16).contains(&c) && rows.contains(&r) { 30.0 } else { 0.0 }
    })
    .unwrap()
}

/// The flat map, the truth with the block across rows 3–16, an unconstrained rover and
/// its start on the west side, at noon under a fixed Sun.
fn block_problem() -> (World, World, ActionModel, Start) {
    let map = fixed_sun_world(flat(30, 20, 10.0), 120.0, 60.0, 10.0);
    let truth = fixed_sun_world(block(3..=16), 120.0, 60.0, 10.0);
    let model = model(1e5, ActionConfig::default());
    let start = Start { cell: map.cell(3, 10), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    (map, truth, model, start)
}

#[test]
fn an_obstacle_missing_from_the_map_is_sensed_and_detoured() {
    let (map, truth, model, start) = block_problem();
    let goal = map.cell(27, 10);
    let report = simulate(&sim_of(&map, &truth, &model, start, &[goal], SimConfig::default()), &mut |_| {}).unwrap();
    assert_eq!(report.status, SimStatus::Completed);
    assert_eq!(report.goals_reached.len(), 1);
    // The first plan believed the map: straight east, 24 drives.
    let first = &report.plans[0];
    assert_eq!(first.kind, PlanKind::Initial);
    assert_eq!(first.plan.action_counts().0, 24);
    assert!(first.plan.waypoints.iter().any(|w| (14..=16).contains(&w.col_row.0) && w.col_row.1 == 10));
    // Sensing found the block, and some re-plan changed the route.
    assert!(report.plans.iter().any(|p| p.kind == PlanKind::Replan && p.changed_cells > 0 && p.route_changed));
    // The rover never entered a cell too steep on the true terrain.
    for s in &report.steps {
        assert!(truth.slope_deg(s.to) <= 20.0 + 1e-9, "entered a {}° cell", truth.slope_deg(s.to));
    }
    // It went round: longer than the straight line, no shorter than the best route
    // with full knowledge of the truth.
    let (_m, best) = Mission::plan(&truth, &model, PlannerConfig::default(), start, &[goal]).unwrap();
    let best_len: f64 = best
        .waypoints
        .windows(2)
        .map(|w| (w[1].easting_m - w[0].easting_m).hypot(w[1].northing_m - w[0].northing_m))
        .sum();
    assert!(report.distance_m() > 240.0 + 1.0);
    assert!(report.distance_m() >= best_len - 1e-6, "{} < {best_len}", report.distance_m());
    assert_eq!(report.steps.last().unwrap().to, goal);
    // Energy bookkeeping: the battery changed by exactly the executed energies.
    let spent: f64 = report.steps.iter().map(|s| s.energy_wh).sum();
    assert!((report.final_battery_above_floor_wh() - (5e4 - spent)).abs() < 1e-6);
}

#[test]
fn execution_noise_is_seeded_and_slows_the_drives() {
    let map = fixed_sun_world(flat(30, 20, 10.0), 120.0, 60.0, 10.0);
    let model = model(1e5, ActionConfig::default());
    let start = Start { cell: map.cell(3, 10), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = map.cell(27, 4);
    let run = |noise: Noise| {
        let sim = SimConfig { noise, ..SimConfig::default() };
        simulate(&sim_of(&map, &map, &model, start, &[goal], sim.clone()), &mut |_| {}).unwrap()
    };
    let calm = run(Noise::default());
    let noisy = Noise { drive_slowdown: 0.3, solar_loss: 0.5, seed: 7 };
    let (a, b) = (run(noisy), run(noisy));
    let json = |r: &areo_mission::SimReport| serde_json::to_string(&r.steps).unwrap();
    assert_eq!(json(&a), json(&b), "same seed, same run");
    assert_ne!(json(&a), json(&run(Noise { seed: 8, ..noisy })), "another seed, another run");
    assert_eq!(calm.status, SimStatus::Completed);
    assert_eq!(a.status, SimStatus::Completed);
    let drive_time = |r: &areo_mission::SimReport| -> f64 {
        r.steps.iter().filter(|s| matches!(s.action, Action::Drive(_))).map(|s| s.duration_s).sum()
    };
    // About the same route (the map is true; a late rover may trade a wait for a
    // longer drive to meet its goal instant), each drive 0–30 % slower.
    assert!((a.distance_m() / calm.distance_m() - 1.0).abs() < 0.05, "{} vs {}", a.distance_m(), calm.distance_m());
    let per_metre = |r: &areo_mission::SimReport| drive_time(r) / r.distance_m();
    let ratio = per_metre(&a) / per_metre(&calm);
    assert!(ratio > 1.05 && ratio < 1.3, "{ratio}");
    // Without noise the map is the truth: the rover drives a route as short as the
    // first plan's (flat ground has many equal routes; re-plans may pick another).
    let planned: f64 = calm.plans[0]
        .plan
        .waypoints
        .windows(2)
        .map(|w| (w[1].easting_m - w[0].easting_m).hypot(w[1].northing_m - w[0].northing_m))
        .sum();
    assert!((calm.distance_m() - planned).abs() < 1e-6, "{} vs {planned}", calm.distance_m());
    assert!(calm.plans.iter().all(|p| p.changed_cells == 0));
}

#[test]
fn a_goal_the_truth_walls_off_ends_the_run_as_unreachable() {
    // The true block spans the whole map height: no way round.
    let map = fixed_sun_world(flat(30, 20, 10.0), 120.0, 60.0, 10.0);
    let truth = fixed_sun_world(block(0..=19), 120.0, 60.0, 10.0);
    let model = model(1e5, ActionConfig::default());
    let start = Start { cell: map.cell(3, 10), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let report =
        simulate(&sim_of(&map, &truth, &model, start, &[map.cell(27, 10)], SimConfig::default()), &mut |_| {}).unwrap();
    assert!(matches!(report.status, SimStatus::Unreachable { .. }), "{:?}", report.status);
    assert!(report.goals_reached.is_empty());
    assert!(!report.steps.is_empty(), "the rover drove until it saw the wall");
}

#[test]
fn bad_simulation_settings_name_the_field() {
    let map = fixed_sun_world(flat(10, 10, 10.0), 120.0, 60.0, 10.0);
    let model = model(1e5, ActionConfig::default());
    let start = Start { cell: map.cell(1, 1), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let sim = SimConfig { noise: Noise { solar_loss: 1.5, ..Noise::default() }, ..SimConfig::default() };
    let err = simulate(&sim_of(&map, &map, &model, start, &[map.cell(8, 8)], sim), &mut |_| {}).unwrap_err();
    assert!(matches!(err, Error::Config { field: "noise.solar_loss", .. }), "{err}");
    let sim = SimConfig { compare_fresh: true, fresh_every: 0, ..SimConfig::default() };
    let err = simulate(&sim_of(&map, &map, &model, start, &[map.cell(8, 8)], sim), &mut |_| {}).unwrap_err();
    assert!(matches!(err, Error::Config { field: "fresh_every", .. }), "{err}");
}

#[test]
fn fresh_every_compares_every_nth_replan_and_every_one_after_sensing_or_a_goal() {
    // Two goals past a block the map lacks: some re-plans repair the graphs for sensed
    // cells, one follows each goal, the rest only extend the plan.
    let (map, truth, model, start) = block_problem();
    let goals = [map.cell(22, 10), map.cell(27, 4)];
    let config = SimConfig { compare_fresh: true, fresh_every: 4, ..SimConfig::default() };
    let report = simulate(&sim_of(&map, &truth, &model, start, &goals, config), &mut |_| {}).unwrap();
    assert_eq!(report.goals_reached.len(), 2, "{:?}", report.status);
    let replans: Vec<_> = report.plans.iter().filter(|p| p.kind == PlanKind::Replan).collect();
    let mut kinds = [0; 3];
    for p in &replans {
        let sensed = p.changed_cells > 0;
        let at_goal = report.goals_reached.iter().any(|&(_, t)| t == p.t_s);
        let wanted = p.step % 4 == 0 || sensed || at_goal;
        assert_eq!(p.fresh.is_some(), wanted, "step {}: sensed {sensed}, at a goal {at_goal}", p.step);
        if let Some((_, cost)) = p.fresh {
            assert!((p.plan.cost - cost).abs() <= 1e-9 * cost.abs().max(1.0), "step {}", p.step);
        }
        kinds[usize::from(sensed) + 2 * usize::from(!sensed && at_goal)] += usize::from(wanted);
    }
    // All three reasons occurred, and some re-plans were left out.
    assert!(kinds.iter().all(|&k| k > 0), "{kinds:?}");
    assert!(replans.iter().any(|p| p.fresh.is_none()));
}

/// A rover slower than every plan allowed for: goal windows with no room to wait
/// (`max_wait_s` 0, no detour) and drives up to three times slower than planned. The
/// kept goal instants fall behind it, a re-plan on the kept graphs finds nothing, and
/// the rover plans afresh from where it is — each time counted as a restart with the
/// re-plan's verdict, its work, and a fresh search of the same problem, which must
/// agree that it has no plan (a re-plan that loses a plan a fresh search finds is a
/// defect, not a restart).
#[test]
fn a_re_plan_that_finds_nothing_restarts_and_is_compared_with_a_fresh_search() {
    let map = fixed_sun_world(flat(30, 20, 10.0), 120.0, 60.0, 10.0);
    let model = model(1e5, ActionConfig::default());
    let start = Start { cell: map.cell(3, 10), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = map.cell(27, 10);
    let planner = PlannerConfig { detour_factor: 1.0, max_wait_s: Some(0.0), ..PlannerConfig::default() };
    let run = |compare_fresh: bool| {
        let config = SimConfig {
            noise: Noise { drive_slowdown: 2.0, solar_loss: 0.0, seed: 3 },
            compare_fresh,
            ..SimConfig::default()
        };
        let sim = Simulation {
            believed: &map,
            truth: &map,
            model: &model,
            planner: planner.clone(),
            start,
            goals: &[goal],
            config,
        };
        simulate(&sim, &mut |_| {}).unwrap()
    };
    let report = run(true);
    assert_eq!(report.status, SimStatus::Completed, "{:?}", report.status);
    let restarts: Vec<_> = report.plans.iter().filter(|p| p.kind == PlanKind::Restart).collect();
    assert!(!restarts.is_empty(), "the slow rover fell behind its goal instants");
    for p in &restarts {
        let r = p.restart.as_ref().expect("a restart says why");
        // The binding is the one that binds: the goal windows (nothing else constrains
        // this rover), found by opening them — not a relaxed probe that searched goal
        // windows made anew from the rover's new start, which named the battery.
        assert_eq!(r.binding, Binding::GoalWindow, "{r:?}");
        assert!(r.reason.contains("`max_wait_s` 0 s"), "{r:?}");
        assert_eq!(r.fresh_found, Some(false), "the kept graphs agree with a fresh search: {r:?}");
    }
    // The failed re-plans' work is counted apart from the plans made afresh (a rover
    // late at its last goal finds its goal instants past without a single expansion).
    assert!(restarts.iter().map(|p| p.restart.as_ref().unwrap().replan_work).sum::<u64>() > 0);
    // Re-plans that found a plan carry no restart record; without the comparison the
    // restarts are the same and say nothing about a fresh search.
    assert!(report.plans.iter().filter(|p| p.kind != PlanKind::Restart).all(|p| p.restart.is_none()));
    let plain = run(false);
    let kinds = |r: &areo_mission::SimReport| r.plans.iter().map(|p| p.kind).collect::<Vec<_>>();
    assert_eq!(kinds(&plain), kinds(&report));
    assert!(plain.plans.iter().filter_map(|p| p.restart.as_ref()).all(|r| r.fresh_found.is_none()));
}

#[test]
fn a_run_that_follows_its_plan_measures_as_the_plan_does() {
    // The map is the truth and nothing is noisy: the rover executes its first plan, so
    // the plan's figures (read off its waypoints) and the run's (off its executed
    // steps) must agree.
    let map = fixed_sun_world(flat(30, 20, 10.0), 120.0, 60.0, 10.0);
    let model = model(1e5, ActionConfig::default());
    let start = Start { cell: map.cell(3, 4), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = map.cell(25, 15);
    let report = simulate(&sim_of(&map, &map, &model, start, &[goal], SimConfig::default()), &mut |_| {}).unwrap();
    assert_eq!(report.status, SimStatus::Completed);
    let planned = PlanMetrics::of_plan(&report.plans[0].plan);
    let ran = PlanMetrics::of_run(&report, &map);
    assert_eq!(planned.drives, 22, "{planned:?}");
    // Among plans of equal cost the planner leaves as late as it may: the rover idles
    // asleep until the plan's first waypoint, one stay the plan does not hold.
    let departure_s = report.plans[0].plan.waypoints[0].t_s;
    assert!(departure_s > 60.0, "{departure_s}");
    assert_eq!((ran.drives, ran.charges), (planned.drives, planned.charges));
    assert_eq!(ran.hibernations, planned.hibernations + 1);
    assert!((3600.0 * (ran.hibernate_h - planned.hibernate_h) - departure_s).abs() < 1e-6, "{ran:?}");
    // What the plan says its actions draw is what the rover's loads drew executing
    // them, besides that idle.
    let predicted: f64 = report.plans[0].plan.waypoints.iter().map(|w| w.drawn_wh).sum();
    let drawn: f64 = report.steps[1..].iter().map(|s| s.load_wh).sum();
    assert!(predicted > 0.0 && (predicted - drawn).abs() < 1e-6 * drawn, "{predicted} vs {drawn}");
    assert!((ran.drive_h - planned.drive_h).abs() < 1e-9, "{ran:?} {planned:?}");
    assert!((ran.distance_m - planned.distance_m).abs() < 1e-6, "{ran:?} {planned:?}");
    assert_eq!((ran.night_drives, ran.sunlit_drive_fraction), (planned.night_drives, planned.sunlit_drive_fraction));
    // 22 diagonal-or-straight steps over a 22 × 11 cell offset: 11 diagonals and 11
    // straight, 10 m cells.
    assert!((planned.distance_m - (110.0 * 2f64.sqrt() + 110.0)).abs() < 1e-6, "{planned:?}");
}

#[test]
fn a_detour_the_map_did_not_show_measures_longer_than_the_plan() {
    let (map, truth, model, start) = block_problem();
    let goal = map.cell(27, 10);
    let report = simulate(&sim_of(&map, &truth, &model, start, &[goal], SimConfig::default()), &mut |_| {}).unwrap();
    let planned = PlanMetrics::of_plan(&report.plans[0].plan);
    let ran = PlanMetrics::of_run(&report, &truth);
    // The first plan drove straight east: 24 drives, 240 m; the run went round.
    assert_eq!(planned.drives, 24);
    assert!((planned.distance_m - 240.0).abs() < 1e-6, "{planned:?}");
    assert!(ran.distance_m > planned.distance_m + 10.0 && ran.drives > planned.drives, "{ran:?}");
}
