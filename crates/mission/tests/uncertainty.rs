//! Chance-constrained plans and open-loop Monte Carlo (areo_mission::uncertainty).

use areo_mission::uncertainty::{Correlation, MonteCarlo, Uncertainty, open_loop, summarise};
use areo_mission::{ActionConfig, Mission, MissionPlan, PlannerConfig, Start};

use crate::common::*;

/// A flat Mars world of 24 × 16 cells of 20 m and a Hyperion-class rover with a 600 Wh
/// battery: the worlds of these tests.
fn dawn() -> (areo_mission::World, areo_mission::ActionModel) {
    (mars_world(flat(24, 16, 20.0), 30.0, None), model(600.0, ActionConfig::default()))
}

fn same_plan(a: &MissionPlan, b: &MissionPlan) -> bool {
    a.cost == b.cost
        && a.waypoints.len() == b.waypoints.len()
        && a.waypoints
            .iter()
            .zip(&b.waypoints)
            .all(|(x, y)| x.cell == y.cell && x.t_s == y.t_s && x.action == y.action && x.battery_wh == y.battery_wh)
}

#[test]
fn a_confidence_of_one_half_or_no_spread_gives_the_deterministic_plan_exactly() {
    let (world, model) = dawn();
    let start = Start { cell: world.cell(2, 8), t_min: 0.0, t_max: 0.0, energy_wh: 120.0 };
    let goals = [world.cell(21, 3), world.cell(20, 13)];
    let (_, det) = Mission::plan(&world, &model, PlannerConfig::default(), start, &goals).unwrap();
    let spread = Uncertainty {
        confidence: 0.5,
        drive_time_sigma: 0.2,
        power_draw_sigma: 0.1,
        solar_sigma: 0.2,
        ..Uncertainty::default()
    };
    let none = Uncertainty { confidence: 0.95, ..Uncertainty::default() };
    for u in [spread, none] {
        let m = model.clone().with_margins(u.margins());
        let (_, plan) = Mission::plan(&world, &m, PlannerConfig::default(), start, &goals).unwrap();
        assert!(same_plan(&det, &plan), "{u:?}");
    }
    // A real margin changes it: slower, hungrier drives under less light cost more.
    let u = Uncertainty { confidence: 0.95, ..spread };
    let m = model.clone().with_margins(u.margins());
    let (_, plan) = Mission::plan(&world, &m, PlannerConfig::default(), start, &goals).unwrap();
    assert!(plan.cost > det.cost * 1.05, "{} vs {}", plan.cost, det.cost);
}

#[test]
fn executed_without_spread_a_plan_does_what_it_predicted() {
    // Zero σ: every execution is the nominal model. The deterministic plan's open-loop
    // run must reproduce its predicted battery and arrival times; the chance-
    // constrained plan (made on a worse model) must do at least as well as it predicted.
    let (world, model) = dawn();
    let start = Start { cell: world.cell(2, 8), t_min: 0.0, t_max: 0.0, energy_wh: 120.0 };
    let goals = [world.cell(21, 3), world.cell(20, 13)];
    let (_, det) = Mission::plan(&world, &model, PlannerConfig::default(), start, &goals).unwrap();
    let flat_u = Uncertainty { confidence: 0.95, ..Uncertainty::default() };
    let mc = MonteCarlo { runs: 3, seed: 1 };
    let runs = open_loop(&det, &model, &world, start, &flat_u, &mc).unwrap();
    let arrivals: Vec<f64> = det.waypoints.iter().filter(|w| w.goal.is_some()).map(|w| w.t_s).collect();
    // Waypoint batteries are absolute; the executions' are above the floor.
    let b = &model.rover().battery;
    let floor = b.capacity_wh * b.min_soc;
    for r in &runs {
        assert!(r.succeeded(), "{r:?}");
        assert_eq!(r.battery_wh.len(), det.waypoints.len() - 1);
        for ((t, e), w) in r.battery_wh.iter().zip(&det.waypoints[1..]) {
            assert!((t - w.t_s).abs() < 1e-6 && (e + floor - w.battery_wh).abs() < 1e-6, "{t} {e} vs {w:?}");
        }
        assert!((r.lowest_battery_wh + floor - det.min_battery_wh()).abs() < 1e-6);
        assert_eq!(r.arrivals_s.len(), 2);
        for (a, b) in r.arrivals_s.iter().zip(&arrivals) {
            assert!((a - b).abs() < 1e-6, "{a} vs {b}");
        }
    }
    let u = Uncertainty {
        confidence: 0.95,
        drive_time_sigma: 0.2,
        power_draw_sigma: 0.1,
        solar_sigma: 0.2,
        ..Uncertainty::default()
    };
    let (_, chance) =
        Mission::plan(&world, &model.clone().with_margins(u.margins()), PlannerConfig::default(), start, &goals)
            .unwrap();
    let runs = open_loop(&chance, &model, &world, start, &flat_u, &mc).unwrap();
    let arrivals: Vec<f64> = chance.waypoints.iter().filter(|w| w.goal.is_some()).map(|w| w.t_s).collect();
    for r in &runs {
        assert!(r.succeeded() && r.lowest_battery_wh + floor >= chance.min_battery_wh() - 1e-6, "{r:?}");
        for (a, b) in r.arrivals_s.iter().zip(&arrivals) {
            assert!(*a <= b + 1e-6, "early or on time: {a} vs {b}");
        }
    }
}

#[test]
fn the_chance_constrained_plan_holds_at_its_confidence_where_the_deterministic_one_does_not() {
    // The battery binds: the rover starts before dawn with 120 Wh above its floor and
    // must hibernate until the Sun is high enough to charge. The deterministic plan
    // reaches that point with 1.5 Wh in hand; executions a little hungrier or dimmer than the model
    // run it below the floor about 40 % of the time. Planned at 0.95, the plan keeps
    // enough in hand for ≥ 0.95 of executions.
    let (world, model) = dawn();
    let start = Start { cell: world.cell(2, 8), t_min: 0.0, t_max: 0.0, energy_wh: 120.0 };
    let goals = [world.cell(21, 3), world.cell(20, 13)];
    let u = Uncertainty {
        confidence: 0.95,
        drive_time_sigma: 0.15,
        power_draw_sigma: 0.1,
        solar_sigma: 0.15,
        correlation: Correlation::Action,
        ..Uncertainty::default()
    };
    let mc = MonteCarlo { runs: 1000, seed: 3 };
    let (_, det) = Mission::plan(&world, &model, PlannerConfig::default(), start, &goals).unwrap();
    let (_, chance) =
        Mission::plan(&world, &model.clone().with_margins(u.margins()), PlannerConfig::default(), start, &goals)
            .unwrap();
    let d = summarise(&open_loop(&det, &model, &world, start, &u, &mc).unwrap(), goals.len());
    let c = summarise(&open_loop(&chance, &model, &world, start, &u, &mc).unwrap(), goals.len());
    // (Measured: 0.595, every failure the battery; the chance-constrained plan 1000 of
    // 1000 — the per-action bound is conservative under independence.)
    assert!(d.success_probability < 0.8, "deterministic {d:?}");
    assert_eq!(d.failures.iter().map(|f| f.0.as_str()).collect::<Vec<_>>(), ["battery_depleted"]);
    assert!(c.success_probability >= 0.95 && c.success_interval.0 > 0.93, "chance-constrained {c:?}");
    // What it costs: a longer plan or more charging.
    assert!(chance.cost > det.cost, "{} vs {}", chance.cost, det.cost);
    // The same seed gives the same executions whatever the thread count.
    let again = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| open_loop(&chance, &model, &world, start, &u, &mc).unwrap());
    assert_eq!(again, open_loop(&chance, &model, &world, start, &u, &mc).unwrap());
}

#[test]
fn closed_loop_runs_are_simulations_with_drawn_departures() {
    use areo_mission::uncertainty::closed_loop;
    use areo_mission::{SimConfig, Simulation, simulate};
    let (world, model) = dawn();
    let start = Start { cell: world.cell(2, 8), t_min: 0.0, t_max: 0.0, energy_wh: 120.0 };
    let goals = [world.cell(21, 3), world.cell(20, 13)];
    let sim = Simulation {
        believed: &world,
        truth: &world,
        model: &model,
        planner: PlannerConfig::default(),
        start,
        goals: &goals,
        config: SimConfig::default(),
    };
    // No spread: every run is the noiseless simulation.
    let plain = simulate(&sim, &mut |_| {}).unwrap();
    let none = Uncertainty { confidence: 0.95, ..Uncertainty::default() };
    let runs = closed_loop(&sim, &none, &MonteCarlo { runs: 2, seed: 5 }).unwrap();
    let arrivals: Vec<f64> = plain.goals_reached.iter().map(|g| g.1).collect();
    for r in &runs {
        assert!(r.succeeded());
        assert_eq!(r.arrivals_s, arrivals);
        assert_eq!(r.battery_wh.len(), plain.steps.len());
    }
    // With spread: the same seed gives the same runs on one thread as on many, and the
    // draws differ between runs.
    let u = Uncertainty { confidence: 0.95, drive_time_sigma: 0.1, power_draw_sigma: 0.1, solar_sigma: 0.1, ..none };
    let mc = MonteCarlo { runs: 4, seed: 5 };
    let many = closed_loop(&sim, &u, &mc).unwrap();
    let one =
        rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(|| closed_loop(&sim, &u, &mc).unwrap());
    assert_eq!(many, one);
    assert!(many.windows(2).any(|w| w[0].lowest_battery_wh != w[1].lowest_battery_wh), "{many:?}");
    // On a truth the map does not show (rolling ground, ±3 m), the runs sense and
    // re-plan: each believes the map as given (sensing writes into the believed world,
    // so shared belief made runs learn from one another and a second call differ from
    // the first), and the believed map is left as it was.
    let rolling = mars_world(
        areo_terrain::Dem::from_fn(24, 16, 20.0, 20.0, |x, y| 3.0 * (x / 37.0).sin() * (y / 23.0).cos()).unwrap(),
        30.0,
        None,
    );
    let sensing = Simulation { truth: &rolling, ..sim.clone() };
    let first = closed_loop(&sensing, &u, &mc).unwrap();
    let second = closed_loop(&sensing, &u, &mc).unwrap();
    assert_eq!(first, second);
    assert!(first.iter().zip(&many).all(|(a, b)| a != b), "the rolling truth changes every run");
    assert!((0..world.cells() as u32).all(|c| world.elevation(c) == Some(0.0)));
    // On error clones of the truth, run i drives on clone i mod n.
    let truths = [rolling, mars_world(flat(24, 16, 20.0), 30.0, None)];
    let on = |t: &[areo_mission::World]| areo_mission::uncertainty::closed_loop_on(&sim, t, &u, &mc).unwrap();
    let (mixed, rolling_only, flat_only) = (on(&truths), on(&truths[..1]), on(&truths[1..]));
    for (i, r) in mixed.iter().enumerate() {
        assert_eq!(r, if i % 2 == 0 { &rolling_only[i] } else { &flat_only[i] }, "run {i}");
    }
    assert_eq!(rolling_only, first);
    assert_eq!(flat_only, many);
}

#[test]
fn re_plans_at_a_confidence_equal_fresh_searches() {
    // The chance-constrained search is the ordinary search on a worse model: the kept
    // graphs must answer every re-plan as a fresh search of the same problem does.
    use areo_mission::{SimConfig, Simulation, simulate};
    let (world, nominal) = dawn();
    let u = Uncertainty {
        confidence: 0.95,
        drive_time_sigma: 0.1,
        power_draw_sigma: 0.1,
        solar_sigma: 0.1,
        ..Uncertainty::default()
    };
    let model = nominal.with_margins(u.margins());
    let start = Start { cell: world.cell(2, 8), t_min: 0.0, t_max: 0.0, energy_wh: 160.0 };
    let goals = [world.cell(21, 3), world.cell(20, 13)];
    let config = SimConfig { compare_fresh: true, uncertainty: Some(u), stream: 3, ..SimConfig::default() };
    let sim = Simulation {
        believed: &world,
        truth: &world,
        model: &model,
        planner: PlannerConfig::default(),
        start,
        goals: &goals,
        config,
    };
    let report = simulate(&sim, &mut |_| {}).unwrap();
    let compared: Vec<_> = report.plans.iter().filter_map(|p| p.fresh.map(|f| (p.step, p.plan.cost, f.1))).collect();
    assert!(compared.len() >= 10, "{} re-plans compared", compared.len());
    for (step, replan, fresh) in compared {
        assert!((replan - fresh).abs() < 1e-6, "step {step}: re-plan {replan} vs fresh {fresh}");
    }
}

#[test]
fn a_delay_margin_lengthens_every_action_and_is_spent_without_sunlight() {
    use areo_mission::{Action, Perturbation};
    let (world, nominal) = dawn();
    let u = Uncertainty { confidence: 0.95, action_delay_sigma_s: 300.0, ..Uncertainty::default() };
    // Φ⁻¹(0.975) = 1.959964: the half-normal delay's 95th percentile.
    let q = u.action_delay_margin_s();
    assert!((q - 587.989).abs() < 1e-2, "{q}");
    assert_eq!(u.margins(), Perturbation { delay_s: q, ..Perturbation::NONE });
    let delayed = nominal.clone().with_margins(u.margins());
    let from = world.cell(5, 8);
    // At midday: a drive, the same drive after the delay at its own load and no sun.
    let t0 = (0..200).map(|i| i as f64 * 600.0).find(|&t| world.sun(t).elevation_deg > 45.0).unwrap();
    let (_, a) = nominal.drive(&world, from, 2, t0).unwrap();
    let (_, b) = delayed.drive(&world, from, 2, t0).unwrap();
    let g = nominal.drive_geometry(&world, from, 2).unwrap();
    let eff = nominal.rover().battery.discharge_efficiency;
    assert!((b.duration_s - a.duration_s - q).abs() < 1e-9);
    // The move itself starts later, so its solar part differs a little; the wait costs
    // its load over q exactly.
    let wait = g.load_w * q / 3600.0 / eff;
    assert!((b.energy_wh - a.energy_wh - wait).abs() < 0.02 * wait, "{} vs {} + {wait}", b.energy_wh, a.energy_wh);
    // A charge: q longer, and no more gained than without the delay.
    let c0 = nominal.stay(&world, Action::Charge, from, t0).unwrap();
    let c1 = delayed.stay(&world, Action::Charge, from, t0).unwrap();
    assert!((c1.duration_s - c0.duration_s - q).abs() < 1e-9);
    assert!(c1.energy_wh > c0.energy_wh, "{} vs {}", c1.energy_wh, c0.energy_wh);
}
