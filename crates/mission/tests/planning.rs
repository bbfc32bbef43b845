//! Single-goal planning: the octile path on easy ground, charging and hibernating when
//! the battery or the night binds, and clear "unreachable" answers.

use areo_mission::{
    Action, ActionConfig, Binding, Classes, Error, ExpansionMeter, Mission, PlannerConfig, SearchMode, Start, World,
};
use areo_terrain::Dem;

use crate::common::*;

fn octile(dc: f64, dr: f64, cell: f64) -> f64 {
    let (lo, hi) = (dc.abs().min(dr.abs()), dc.abs().max(dr.abs()));
    (hi - lo + lo * std::f64::consts::SQRT_2) * cell
}

#[test]
fn flat_lit_ground_with_a_large_battery_gives_the_octile_shortest_path() {
    let world = fixed_sun_world(flat(40, 30, 10.0), 120.0, 60.0, 30.0);
    let model = model(1e5, ActionConfig::default());
    let start = Start { cell: world.cell(2, 3), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = world.cell(33, 20);
    let (_m, plan) = Mission::plan(&world, &model, PlannerConfig::default(), start, &[goal]).unwrap();
    let (drives, charges, hibernations) = plan.action_counts();
    assert_eq!((charges, hibernations), (0, 0), "no need to stop");
    assert_eq!(drives, 31, "Chebyshev steps");
    let mut length = 0.0;
    for w in plan.waypoints.windows(2) {
        length += (w[1].easting_m - w[0].easting_m).hypot(w[1].northing_m - w[0].northing_m);
    }
    assert!((length - octile(31.0, 17.0, 10.0)).abs() < 1e-6, "{length}");
    assert_eq!(plan.waypoints.last().unwrap().cell, goal);
    assert_eq!(plan.waypoints.last().unwrap().goal, Some(0));
    // Times advance by each drive's duration at 0.3 m/s on flat ground.
    assert!((plan.duration_s() - length / 0.3).abs() < 1e-6);
    assert!(plan.e_max_wh > 0.0);
}

/// The progress meter counts what the plan reports as its expansions, and changes
/// nothing about the plan.
#[test]
fn the_expansion_meter_counts_the_plans_expansions() {
    let world = fixed_sun_world(flat(40, 30, 10.0), 120.0, 60.0, 30.0);
    let model = model(1e5, ActionConfig::default());
    let start = Start { cell: world.cell(2, 3), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = world.cell(33, 20);
    let meter = areo_mission::ExpansionMeter::counting();
    let config = PlannerConfig { meter: meter.clone(), ..PlannerConfig::default() };
    let (_m, plan) = Mission::plan(&world, &model, config, start, &[goal]).unwrap();
    let (_m, plain) = Mission::plan(&world, &model, PlannerConfig::default(), start, &[goal]).unwrap();
    assert!(plan.expansions > 100, "{}", plan.expansions);
    assert_eq!(meter.expansions(), plan.expansions);
    assert_eq!(plan, plain);
}

#[test]
fn a_small_battery_before_night_makes_the_plan_wait() {
    // Late afternoon near the equator, 1.8 km to go at ≤ 0.3 m/s with drives allowed
    // only in daylight: the rover cannot arrive before sunset, so it must stop for the
    // night (hibernate) or charge, and its predicted battery never goes below the floor.
    let world = mars_world(flat(100, 5, 20.0), 48.0, None);
    let model = model(1000.0, ActionConfig::default());
    // Find the first instant with the Sun 20° up in the afternoon.
    let mut t0 = 0.0;
    let mut prev = world.sun(0.0).elevation_deg;
    while t0 < 40.0 * 3600.0 {
        t0 += 60.0;
        let e = world.sun(t0).elevation_deg;
        if prev > 20.0 && e <= 20.0 {
            break;
        }
        prev = e;
    }
    let start = Start { cell: world.cell(3, 2), t_min: t0, t_max: t0 + 600.0, energy_wh: 450.0 };
    let config = PlannerConfig {
        max_wait_s: Some(20.0 * 3600.0),
        search: SearchMode::Approximate(Classes {
            goal_times: 24,
            resolution: areo_mission::Resolution { time_s: 300.0, energy_wh: None },
            ..Classes::default()
        }),
        ..PlannerConfig::default()
    };
    let (_m, plan) = Mission::plan(&world, &model, config, start, &[world.cell(93, 2)]).unwrap();
    let (drives, charges, hibernations) = plan.action_counts();
    assert!(drives >= 90, "{drives}");
    assert!(charges + hibernations > 0, "the plan stops for the night");
    let floor = 100.0;
    assert!(plan.min_battery_wh() >= floor - 1e-6, "battery floor kept: {}", plan.min_battery_wh());
    // No drive in the dark.
    for w in &plan.waypoints {
        if let Some(Action::Drive(_)) = w.action {
            assert!(w.sun_elevation_deg > 0.0, "drive at night: {w:?}");
        }
    }
}

/// Night driving allowed, but a 50 Wh battery cannot pay for 1.5 km of it: the world,
/// the model, the start, the planner settings and the goal of a case where the battery
/// binds.
fn battery_bound() -> (World, areo_mission::ActionModel, Start, PlannerConfig, u32) {
    let mut actions = ActionConfig::default();
    actions.drive.daylight = false;
    let small = crate::common::model(50.0, actions);
    let long = fixed_sun_world(flat(80, 3, 20.0), 90.0, -30.0, 12.0);
    let start = Start { cell: long.cell(2, 1), t_min: 0.0, t_max: 0.0, energy_wh: 45.0 };
    let quick = PlannerConfig { max_wait_s: Some(3600.0), ..PlannerConfig::default() };
    let goal = long.cell(77, 1);
    (long, small, start, quick, goal)
}

#[test]
fn unreachable_goals_name_the_binding_constraint() {
    // A plateau with 40° walls: the rover (20° maximum) cannot climb it.
    let dem = areo_terrain::Dem::from_fn(40, 40, 10.0, 10.0, |x, y| {
        let d = (x - 200.0).hypot(y - 200.0);
        if d < 60.0 {
            80.0
        } else if d < 120.0 {
            80.0 * (120.0 - d) / 60.0
        } else {
            0.0
        }
    })
    .unwrap();
    let world = fixed_sun_world(dem, 90.0, 50.0, 40.0);
    let model = model(1e5, ActionConfig::default());
    let start = Start { cell: world.cell(2, 2), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    match Mission::plan(&world, &model, PlannerConfig::default(), start, &[world.cell(20, 20)]) {
        Err(Error::Unreachable { binding, message, proven }) => {
            assert_eq!(binding, Binding::Slope, "{message}");
            assert!(message.contains("slope"));
            // Slopes do not depend on time: no setting can find a plan.
            assert!(proven && !message.contains("not a proof"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // Permanent night with drives needing daylight: darkness binds.
    let night = fixed_sun_world(flat(20, 20, 10.0), 90.0, -30.0, 12.0);
    let start = Start { cell: night.cell(2, 2), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    match Mission::plan(&night, &model, PlannerConfig::default(), start, &[night.cell(15, 15)]) {
        Err(Error::Unreachable { binding, .. }) => assert_eq!(binding, Binding::Darkness),
        other => panic!("{other:?}"),
    }
    let (long, small, start, quick, goal) = battery_bound();
    match Mission::plan(&long, &small, quick, start, &[goal]) {
        Err(Error::Unreachable { binding, message, proven }) => {
            assert_eq!(binding, Binding::Battery, "{message}");
            // Unquantised actions: a verdict at these classes, said to be one.
            assert!(!proven, "{message}");
            assert!(message.contains("not a proof") && message.contains("time_quantum_s: 0"), "{message}");
            // What may still find a plan, without promising that more goal instants do.
            assert!(message.contains("another `goal_times`") && !message.contains("a finer setting"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

/// When no one relaxation makes a plan, the answer says whether all of them at once do
/// (the constraints bind together) or not (only time is left): before, both read "no
/// passable cells connect start and goal", though start and goal were connected.
#[test]
fn constraints_that_bind_only_together_and_time_are_named_as_such() {
    // Permanent night, drives only in daylight, a 50 Wh battery for 1.5 km: unlimited
    // battery alone still cannot drive in the dark, driving in the dark alone runs the
    // battery flat.
    let night = fixed_sun_world(flat(80, 3, 20.0), 90.0, -30.0, 12.0);
    let small = model(50.0, ActionConfig::default());
    let start = Start { cell: night.cell(2, 1), t_min: 0.0, t_max: 0.0, energy_wh: 45.0 };
    let quick = PlannerConfig { max_wait_s: Some(3600.0), ..PlannerConfig::default() };
    let meter = ExpansionMeter::counting();
    let watched = PlannerConfig { meter: meter.clone(), ..quick.clone() };
    match Mission::plan(&night, &small, watched, start, &[night.cell(77, 1)]) {
        Err(Error::Unreachable { binding, message, proven }) => {
            // All at once made a plan, then each one alone was searched, and a watcher
            // was told which; sessions were never searched (there are none). The goal
            // windows close before the 12 h horizon (`max_wait_s` of an hour), so
            // opening them alone was searched too (first; listed in phase order).
            let phases = [
                "planning",
                "no plan: every constraint relaxed",
                "no plan: battery relaxed",
                "no plan: darkness relaxed",
                "no plan: shadow relaxed",
                "no plan: Sun in the cameras relaxed",
                "no plan: goal windows relaxed",
            ];
            assert_eq!(meter.phases_seen(), phases);
            assert_eq!(meter.phase(), "planning");
            assert_eq!(binding, Binding::Together, "{message}");
            assert!(message.contains("none relaxed alone") && !message.contains("passable"), "{message}");
            // Only the constraints this rover, its actions and the mission have are
            // named: no sessions here (they were listed whatever the case).
            let named = "several constraints together (battery, darkness, shadow, the Sun in the cameras: ";
            assert!(message.starts_with(named), "{message}");
            assert!(!proven, "{message}");
        }
        other => panic!("{other:?}"),
    }
    // Charging without direct sun and no camera rule: battery and darkness are all
    // there is to relax, and all the message names.
    let mut fewer = ActionConfig::default();
    (fewer.charge.direct_sun, fewer.drive.sun_in_camera) = (false, false);
    match Mission::plan(&night, &model(50.0, fewer), quick.clone(), start, &[night.cell(77, 1)]) {
        Err(Error::Unreachable { binding, message, .. }) => {
            assert_eq!(binding, Binding::Together, "{message}");
            assert!(message.starts_with("several constraints together (battery, darkness: none"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // The same night with a battery that can pay for the drive: darkness alone binds.
    let big = model(1e5, ActionConfig::default());
    let full = Start { energy_wh: 5e4, ..start };
    match Mission::plan(&night, &big, quick.clone(), full, &[night.cell(77, 1)]) {
        Err(Error::Unreachable { binding, .. }) => assert_eq!(binding, Binding::Darkness),
        other => panic!("{other:?}"),
    }
}

/// Daylight and a large battery, but a wall with one gap at the far end: the detour is
/// 1.1 km, 1 h at 0.3 m/s, the straight line 200 m, and the world spans 45 min — the
/// horizon binds, named as such; in a world of 2 h the detour is planned.
#[test]
fn a_detour_longer_than_the_world_names_the_horizon() {
    let big = model(1e5, ActionConfig::default());
    let quick = PlannerConfig { max_wait_s: Some(3600.0), ..PlannerConfig::default() };
    let walled =
        Dem::from_fn(30, 40, 10.0, 10.0, |x, y| if (140.0..160.0).contains(&x) && y < 370.0 { 500.0 } else { 0.0 })
            .unwrap();
    let short = fixed_sun_world(walled, 90.0, 50.0, 0.75);
    let start = Start { cell: short.cell(5, 38), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = short.cell(25, 38);
    let meter = ExpansionMeter::counting();
    let watched = PlannerConfig { meter: meter.clone(), ..quick.clone() };
    match Mission::plan(&short, &big, watched, start, &[goal]) {
        Err(Error::Unreachable { binding, message, .. }) => {
            assert_eq!(binding, Binding::Horizon, "{message}");
            // Nothing relaxed at once made a plan, so nothing alone is searched.
            assert_eq!(meter.phases_seen(), ["planning", "no plan: every constraint relaxed"]);
            assert!(!message.contains("passable"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // The same wall in a world spanning 2 h: the detour is planned, so the wall is no
    // block and the horizon was the binding constraint.
    let walled =
        Dem::from_fn(30, 40, 10.0, 10.0, |x, y| if (140.0..160.0).contains(&x) && y < 370.0 { 500.0 } else { 0.0 })
            .unwrap();
    let long = fixed_sun_world(walled, 90.0, 50.0, 2.0);
    let (_m, plan) = Mission::plan(&long, &big, quick, start, &[goal]).unwrap();
    assert!(plan.duration_s() > 2700.0, "{}", plan.duration_s());
}

#[test]
fn bad_inputs_are_errors_naming_the_field() {
    let world = fixed_sun_world(flat(10, 10, 10.0), 90.0, 50.0, 10.0);
    let model = model(1000.0, ActionConfig::default());
    let start = Start { cell: 5000, t_min: 0.0, t_max: 0.0, energy_wh: 500.0 };
    match Mission::plan(&world, &model, PlannerConfig::default(), start, &[world.cell(5, 5)]) {
        Err(Error::Config { field, .. }) => assert_eq!(field, "start"),
        other => panic!("{other:?}"),
    }
    let start = Start { cell: world.cell(1, 1), ..start };
    let bad = PlannerConfig { detour_factor: 0.5, ..PlannerConfig::default() };
    match Mission::plan(&world, &model, bad, start, &[world.cell(5, 5)]) {
        Err(Error::Config { field, message }) => {
            assert!(field == "detour_factor" && message.contains("allowed 1..=100"))
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(Mission::plan(&world, &model, PlannerConfig::default(), start, &[]), Err(Error::Config { .. })));
    // Energy classes wider than half the usable battery (900 Wh here) would collapse E.
    let collapsing = PlannerConfig {
        search: SearchMode::Approximate(Classes {
            resolution: areo_mission::Resolution { time_s: 60.0, energy_wh: Some(451.0) },
            ..Classes::default()
        }),
        ..PlannerConfig::default()
    };
    match Mission::plan(&world, &model, collapsing, start, &[world.cell(5, 5)]) {
        Err(Error::Config { field, message }) => {
            assert!(field == "resolution.energy_wh" && message.contains("450.0 Wh"), "{message}")
        }
        other => panic!("{other:?}"),
    }
    let widest = PlannerConfig {
        search: SearchMode::Approximate(Classes {
            resolution: areo_mission::Resolution { time_s: 60.0, energy_wh: Some(450.0) },
            ..Classes::default()
        }),
        ..PlannerConfig::default()
    };
    assert!(Mission::plan(&world, &model, widest, start, &[world.cell(5, 5)]).is_ok());
}

#[test]
fn the_duration_objective_keeps_under_its_maximum_and_prefers_less_energy() {
    // The Arctic configuration: BESTDPARMS on duration, "less required energy is
    // better". Its start needs no more energy than the L + B plan whenever that plan
    // fits under the maximum duration, and it never exceeds the maximum.
    // Quantised times and energies with classes as fine as the quanta: both searches
    // are exact, so the inequality must hold exactly.
    let world = mars_world(flat(30, 12, 20.0), 30.0, None);
    let mut actions = ActionConfig {
        time_quantum_s: 60.0,
        energy_quantum_wh: 1.0,
        charge_s: 600.0,
        hibernate_s: 1200.0,
        ..Default::default()
    };
    actions.drive.daylight = false;
    let model = model(3000.0, actions);
    let start = Start { cell: world.cell(2, 2), t_min: 0.0, t_max: 600.0, energy_wh: 2500.0 };
    let goal = [world.cell(26, 9)];
    let base = PlannerConfig {
        max_wait_s: Some(3600.0),
        search: SearchMode::Approximate(Classes {
            goal_times: 12,
            resolution: areo_mission::Resolution { time_s: 60.0, energy_wh: None },
            ..Classes::default()
        }),
        ..PlannerConfig::default()
    };
    let (_m, energy_plan) = Mission::plan(&world, &model, base.clone(), start, &goal).unwrap();
    let max = energy_plan.duration_s() + 3600.0;
    let cfg = PlannerConfig { objective: areo_mission::Objective::Margin { max_duration_s: max }, ..base.clone() };
    let (_m, duration_plan) = Mission::plan(&world, &model, cfg, start, &goal).unwrap();
    assert!(duration_plan.cost <= max + 1e-6, "{} > {max}", duration_plan.cost);
    assert!((duration_plan.cost - duration_plan.duration_s()).abs() < 1e-6, "the cost is the duration");
    let (e_d, e_e) = (duration_plan.waypoints[0].required_wh, energy_plan.waypoints[0].required_wh);
    assert!(e_d <= e_e + 1e-9, "BESTDPARMS start energy {e_d} Wh vs L+B {e_e} Wh");
    // Too short a maximum: no plan, and the answer says so.
    let tight = PlannerConfig { objective: areo_mission::Objective::Margin { max_duration_s: 60.0 }, ..base };
    assert!(matches!(Mission::plan(&world, &model, tight, start, &goal), Err(Error::Unreachable { .. })));
}

#[test]
fn waypoints_carry_place_time_light_and_energy() {
    let world = mars_world(flat(20, 10, 20.0), 30.0, Some(16));
    let mut actions = ActionConfig::default();
    actions.drive.daylight = false;
    let model = model(3000.0, actions);
    let start = Start { cell: world.cell(1, 1), t_min: 0.0, t_max: 600.0, energy_wh: 2000.0 };
    let (_m, plan) = Mission::plan(
        &world,
        &model,
        PlannerConfig {
            search: SearchMode::Approximate(Classes { goal_times: 8, ..Classes::default() }),
            ..PlannerConfig::default()
        },
        start,
        &[world.cell(15, 8)],
    )
    .unwrap();
    // 3000 Wh with a 10 % floor.
    let floor = 300.0;
    let first = &plan.waypoints[0];
    assert!((first.battery_wh - (floor + 2000.0)).abs() < 1e-9, "battery is absolute: {}", first.battery_wh);
    for w in &plan.waypoints {
        assert!((w.lat_deg - (-4.6)).abs() < 1e-9 && (w.lon_deg - 137.4).abs() < 1e-9, "no georeference: the site");
        assert!(w.utc.starts_with("2025-03-0") && w.utc.ends_with('Z'), "{}", w.utc);
        assert!((0.0..24.0).contains(&w.ltst_h));
        assert!(w.lit == (w.sun_elevation_deg > 0.0), "flat ground: lit iff the Sun is up");
        assert!(w.required_wh >= 0.0 && w.required_wh <= 2700.0 + 1e-9);
        assert!(w.battery_wh >= floor - 1e-9 && w.battery_wh <= 3000.0 + 1e-9);
    }
    // The waypoints' times increase and the required energy is what the battery had.
    assert!(plan.waypoints.windows(2).all(|p| p[1].t_s > p[0].t_s));
    assert!(first.required_wh <= 2000.0 + 1e-9);
    let json = serde_json::to_string(&plan).unwrap();
    let back: areo_mission::MissionPlan = serde_json::from_str(&json).unwrap();
    assert_eq!(back.waypoints.len(), plan.waypoints.len());
    for (a, b) in back.waypoints.iter().zip(&plan.waypoints) {
        assert!(a.cell == b.cell && a.action == b.action && a.utc == b.utc && (a.t_s - b.t_s).abs() < 1e-6);
    }
}

#[test]
fn a_communicate_session_holds_the_rover_still_at_the_radio_load() {
    // 31 drives east on flat lit ground (about 17 min) with a session from minute 3 to
    // minute 83: no drive may overlap it, so the plan stops for it and arrives later.
    let world = fixed_sun_world(flat(40, 30, 10.0), 120.0, 60.0, 30.0);
    let start = Start { cell: world.cell(2, 3), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = world.cell(33, 3);
    let free = model(1e5, ActionConfig::default());
    let (_m, direct) = Mission::plan(&world, &free, PlannerConfig::default(), start, &[goal]).unwrap();
    let session = (180.0, 5000.0);
    let talking = model(1e5, ActionConfig::default()).with_sessions(vec![session]);
    let (_m, plan) = Mission::plan(&world, &talking, PlannerConfig::default(), start, &[goal]).unwrap();
    for w in plan.waypoints.windows(2) {
        if let Some(Action::Drive(_)) = w[0].action {
            assert!(w[1].t_s <= session.0 + 1e-9 || w[0].t_s >= session.1 - 1e-9, "drive across the session: {w:?}");
        }
    }
    // The plan may start as late as its widened start window allows (at most an hour),
    // but 17 minutes of driving cannot fit before the session: it arrives after it.
    assert_eq!(direct.action_counts().0, plan.action_counts().0, "the same 31 drives");
    assert!(plan.waypoints.last().unwrap().t_s >= session.1 + 1.0);
    // A stationary action inside the session draws at least the high (radio) load.
    let quiet = free.stay(&world, Action::Hibernate, start.cell, 400.0).unwrap();
    let radio = talking.stay(&world, Action::Hibernate, start.cell, 400.0).unwrap();
    assert!(radio.energy_wh > quiet.energy_wh + 1.0, "{} vs {}", radio.energy_wh, quiet.energy_wh);
    // Drives that would overlap it are refused with the binding named.
    assert_eq!(talking.drive(&world, start.cell, 2, 1000.0).unwrap_err(), Binding::Communicate);
}

/// 14 × 12 cells of 20 m with slopes up to ~25°, under the real Sun for a sol, with
/// terrain shadows (a 16-sector horizon map).
fn steep_lit_world() -> areo_mission::World {
    let dem =
        areo_terrain::Dem::from_fn(14, 12, 20.0, 20.0, |x, y| 6.0 * (x / 23.0).sin() * (y / 31.0).cos() + 0.15 * x)
            .unwrap();
    mars_world(dem, 24.0, Some(16))
}

#[test]
fn drive_energy_floors_bound_every_drive_on_steep_lit_ground() {
    // Slopes up to ~25° on 20 m cells under the real Sun with terrain shadows: the
    // heuristic's per-direction floors must not exceed any drive's energy, whatever
    // the cell, heading and time.
    let world = steep_lit_world();
    for quantum in [0.0, 1.0] {
        let actions = ActionConfig { time_quantum_s: 60.0, energy_quantum_wh: quantum, ..Default::default() };
        let model = model(1e6, actions);
        let floors = model.drive_energy_floors_wh(&world);
        let (mut tightest, mut drives) = ([f64::INFINITY; 3], 0);
        for cell in 0..(14 * 12) as u32 {
            let (c, r) = world.col_row(cell);
            for k in 0..8 {
                let mut t = 0.0;
                while t < 23.0 * 3600.0 {
                    if let Ok((to, effect)) = model.drive(&world, cell, k, t) {
                        let (tc, tr) = world.col_row(to);
                        let dir = if tr == r {
                            0
                        } else if tc == c {
                            1
                        } else {
                            2
                        };
                        assert!(
                            effect.energy_wh >= floors[dir] - 1e-9,
                            "cell {cell} heading {k} at {t} s: {} Wh below the floor {}",
                            effect.energy_wh,
                            floors[dir]
                        );
                        tightest[dir] = tightest[dir].min(effect.energy_wh - floors[dir]);
                        drives += 1;
                    }
                    t += 1200.0;
                }
            }
        }
        assert!(drives > 10_000, "{drives} drives checked");
        // Useful bounds: the best drive in each direction comes within 15 Wh of its floor
        // (the floors assume the best Sun of the sol on the best-tipped array).
        assert!(tightest.iter().all(|&gap| (0.0..15.0).contains(&gap)), "gaps {tightest:?}, floors {floors:?}");
    }
}

#[test]
fn a_backward_expansion_equals_its_actions_one_by_one_and_the_forward_drives() {
    // The search expands with `expand`, which shares the arrival cell's Sun and light
    // among the 8 drives: asked for one action at a time (as a repair's partial
    // expansion asks) it must give exactly the same steps, and each
    // drive's predecessor, driven forward, must arrive when and where the label says,
    // using the energy the step charged.
    use areo_ise::Domain;
    use areo_mission::{Label, Objective, PathLength, Resolution, TempestDomain};
    let world = steep_lit_world();
    let model = model(2000.0, ActionConfig::default());
    let start = Start { cell: 0, t_min: 0.0, t_max: 3600.0, energy_wh: 1000.0 };
    let domain = TempestDomain::new(
        &world,
        &model,
        start,
        Objective::Energy,
        Resolution { time_s: 60.0, energy_wh: None },
        PathLength::Distance,
    );
    let mut drives = 0;
    let actions: Vec<Action> = (0..8).map(Action::Drive).chain([Action::Charge, Action::Hibernate]).collect();
    for cell in 0..(14 * 12) as u32 {
        let mut t = 1800.0;
        while t < 23.0 * 3600.0 {
            let label = Label { t, e: 40.0 };
            let mut batch = Vec::new();
            domain.expand(cell, &label, |_| true, |a, step| batch.push((a, step)));
            let mut one_by_one = Vec::new();
            for &want in &actions {
                domain.expand(cell, &label, |a| a == want, |a, step| one_by_one.push((a, step)));
            }
            assert_eq!(batch.len(), one_by_one.len(), "cell {cell} at {t} s");
            for ((a, s), (b, u)) in batch.iter().zip(&one_by_one) {
                assert_eq!(a, b);
                assert_eq!((s.state, s.label, s.cost.to_bits()), (u.state, u.label, u.cost.to_bits()));
            }
            for (a, step) in &batch {
                let Action::Drive(k) = *a else { continue };
                let (to, effect) = model.drive(&world, step.state, k, step.label.t).expect("feasible forward");
                assert_eq!(to, cell);
                assert!((step.label.t + effect.duration_s - t).abs() < 1e-6);
                assert!((step.label.e - effect.required_before(40.0)).abs() < 1e-9);
                drives += 1;
            }
            t += 1700.0;
        }
    }
    assert!(drives > 2000, "{drives} drives compared");
}

#[test]
fn a_world_for_a_region_cut_from_a_larger_map_sees_what_the_whole_map_sees() {
    use areo_mission::World;
    use areo_terrain::shadow::Curvature;
    use areo_terrain::synth::{Feature, Noise, TerrainSpec};
    use areo_terrain::tiles::{RegionHorizon, ShadowHalo, region, relief};
    let dem = TerrainSpec {
        cols: 120,
        rows: 90,
        cell_m: 30.0,
        base_m: 0.0,
        seed: 4,
        noise: Some(Noise { amplitude_m: 20.0, wavelength_m: 900.0, octaves: 3, persistence: 0.5 }),
        features: vec![Feature::Hill { x_m: 1500.0, y_m: 1500.0, radius_m: 400.0, slope_deg: 25.0 }],
    }
    .build()
    .unwrap();
    // The Sun on a sector centre (16 sectors), 15° up; horizons kept down to 10°.
    let sun = FixedSun::new(&site(), 112.5, 15.0);
    let whole = World::new(dem.clone(), &config(2.0, Some(16)), &sun).unwrap();
    let mut src = dem.clone();
    let rel = relief(&mut src, 64).unwrap().unwrap();
    let halo = ShadowHalo::new(rel, &areo_terrain::geotiff::Grid::of(&dem), 10.0).unwrap();
    let plan =
        RegionHorizon { sectors: 16, curvature: Curvature::Sphere { radius_m: 3_389_500.0 }, lowest_deg: 10.0, halo };
    let (c0, r0, w, h) = (35, 25, 50, 40);
    let part =
        World::for_region(region(&mut src, (c0, r0, w, h), Some(plan)).unwrap(), &config(2.0, Some(16)), &sun).unwrap();
    assert_eq!((part.cols(), part.rows()), (w, h));
    let s = part.sun(0.0);
    let mut shadowed = 0;
    for r in 0..h {
        for c in 0..w {
            let (a, b) = (part.cell(c, r), whole.cell(c0 + c, r0 + r));
            assert_eq!(part.slope_deg(a).to_bits(), whole.slope_deg(b).to_bits(), "({c}, {r})");
            assert_eq!(part.normal(a), whole.normal(b));
            assert_eq!(part.lit(a, &s), whole.lit(b, &whole.sun(0.0)), "({c}, {r})");
            shadowed += usize::from(!part.lit(a, &s));
        }
    }
    assert!(shadowed > 20, "some cells in the hill's shadow: {shadowed}");
    // A region map of the wrong number of sectors is a located error.
    let other = region(&mut src, (c0, r0, w, h), Some(RegionHorizon { sectors: 32, ..plan })).unwrap();
    assert!(World::for_region(other, &config(2.0, Some(16)), &sun).is_err());
}

/// A wall runs east from the world's western edge between the start and the goal; the
/// way round is past its eastern end. `cols` × `rows` cells of 20 m, the south-west
/// corner at the origin, so a larger world adds ground north and east of the same
/// problem.
fn walled_world(cols: usize, rows: usize) -> areo_mission::World {
    let dem = areo_terrain::Dem::from_fn(cols, rows, 20.0, 20.0, |x, y| {
        let wall = (330.0..370.0).contains(&y) && x < 640.0;
        1.5 * (x / 53.0).sin() + 1.0 * (y / 37.0).cos() + if wall { 80.0 } else { 0.0 }
    })
    .unwrap();
    mars_world(dem, 14.0, None)
}

#[test]
fn the_cached_bound_guides_a_detour_so_a_wider_world_adds_little_work() {
    // The octile floors do not see the wall, so a search guided by them alone floods
    // every cell within the detour's extra cost of the straight line — as far as the
    // world reaches. The landmark bound (a 2-D Dijkstra over the drives possible at
    // some time) knows the way round: nine times the area must cost at most 1.3 times
    // the expansions, with the same plan.
    let model = model(2000.0, quantised_actions(1200.0));
    let config = PlannerConfig {
        actions: quantised_actions(1200.0),
        max_wait_s: Some(3600.0),
        search: SearchMode::Approximate(Classes {
            resolution: areo_mission::Resolution { time_s: 60.0, energy_wh: None },
            goal_times: 8,
            segment_starts: 4,
            ..Classes::default()
        }),
        ..PlannerConfig::default()
    };
    let mut answers = Vec::new();
    for (cols, rows) in [(40, 30), (120, 90)] {
        let world = walled_world(cols, rows);
        let cell = |x: f64, y: f64| world.cell_at(x, y).unwrap();
        let start = Start { cell: cell(300.0, 150.0), t_min: 0.0, t_max: 600.0, energy_wh: 1500.0 };
        let (_m, plan) = Mission::plan(&world, &model, config.clone(), start, &[cell(300.0, 550.0)]).unwrap();
        // The route goes round the wall's end.
        assert!(plan.waypoints.iter().any(|w| w.easting_m > 640.0 && (330.0..370.0).contains(&w.northing_m)));
        answers.push((plan.cost, plan.expansions));
    }
    let ((small_cost, small), (large_cost, large)) = (answers[0], answers[1]);
    assert!((small_cost - large_cost).abs() < 1e-9, "the same plan: {small_cost} vs {large_cost}");
    assert!(large * 10 <= small * 13, "{large} expansions in the larger world, {small} in the smaller");
}

#[test]
fn a_narrowed_horizon_map_changes_light_only_where_the_sun_grazes_the_horizon() {
    // Rough Mars terrain under the real Sun over a sol, 32-sector horizons: the
    // one-byte map may only change a cell's light where the Sun stands within the
    // stated error of the two-byte map's horizon, and must change some (else the test
    // sees nothing).
    let dem = areo_terrain::Dem::from_fn(60, 50, 20.0, 20.0, |x, y| {
        25.0 * (x / 90.0).sin() * (y / 70.0).cos() + 12.0 * ((x + y) / 45.0).sin()
    })
    .unwrap();
    let wide = mars_world(dem.clone(), 25.0, Some(32));
    let mut narrow = mars_world(dem, 25.0, Some(32));
    // Mars's Sun rises at up to about ¼° a minute: narrowed for 20-min classes, with a
    // shadow-edge shift near the 85 s of the equator's fastest Sun.
    let shift = narrow.narrow_horizon_within(1200.0).expect("narrowed at 20-min classes");
    assert!(narrow.horizon_is_narrow() && (60.0..=120.0).contains(&shift), "{shift} s");
    let error = 90.0 / 255.0;
    let (mut changed, mut lit) = (0, 0);
    for sun in wide.sun_table().iter().step_by(5) {
        for cell in 0..wide.cells() as u32 {
            let (a, b) = (wide.lit(cell, sun), narrow.lit(cell, sun));
            lit += usize::from(a);
            if a != b {
                changed += 1;
                let margin = sun.elevation_deg - wide.horizon_floor_deg(cell, sun.azimuth_deg);
                assert!(margin.abs() <= error + 1e-9, "cell {cell}: light changed {margin}° from the horizon");
            }
        }
    }
    assert!(changed > 0 && lit > 10 * changed, "{changed} changes among {lit} lit samples");
    // A polar Sun that skims the horizon is too slow: the map keeps two bytes.
    let mut polar = areo_mission::World::new(
        areo_terrain::Dem::from_fn(30, 30, 20.0, 20.0, |x, _| x / 50.0).unwrap(),
        &areo_mission::WorldConfig {
            site: Some(areo_ephemeris::Site::new(-89.5, 0.0).unwrap()),
            ..config(25.0, Some(32))
        },
        &areo_ephemeris::Mars24,
    )
    .unwrap();
    assert_eq!(polar.narrow_horizon_within(1200.0), None);
    assert!(!polar.horizon_is_narrow());
}

#[test]
fn the_world_memory_estimate_bounds_a_built_world() {
    // 200 × 150 cells with 16 horizon sectors: the estimate made before building holds
    // the world's grids, its horizon map and its DEM (the Sun table, 12 h at 2 min, is
    // not per cell: under 64 kB), and is not loose by more than a third.
    let dem = Dem::from_fn(200, 150, 10.0, 10.0, |x, y| (0.01 * x).sin() * 20.0 + 0.02 * y).unwrap();
    let world = mars_world(dem, 12.0, Some(16));
    let cells = world.cells() as u64;
    let estimate = World::estimate_bytes(cells, 16, false);
    let held = world.bytes() as u64 + cells * areo_terrain::Dem::BYTES_PER_CELL;
    assert!(estimate + 64_000 >= held, "estimate {estimate} B, held {held} B");
    assert!(3 * estimate <= 4 * held, "estimate {estimate} B, held {held} B");
    // A true world beside it adds its DEM and grids, not another horizon map.
    let with_truth = World::estimate_bytes(cells, 16, true) - estimate;
    assert_eq!(with_truth, cells * (areo_terrain::Dem::BYTES_PER_CELL + World::GRID_BYTES_PER_CELL));
}

/// `max_search_bytes` bounds what a planning call's graphs hold, the probes beside the
/// mission included: a call whose graphs outgrow it stops with `MemoryLimit` — not
/// "unreachable" — having held more than the limit and no more than the whole search
/// holds; a limit the graphs never reach changes nothing.
#[test]
fn a_planning_call_stops_when_its_graphs_outgrow_their_memory_and_says_so() {
    // A plan whose search holds about 300 000 labels (90 MB).
    let world = fixed_sun_world(flat(40, 30, 10.0), 120.0, 60.0, 30.0);
    let model = model(1e5, ActionConfig::default());
    let start = Start { cell: world.cell(2, 3), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = world.cell(33, 20);
    let config = PlannerConfig::default();
    let meter = areo_mission::ExpansionMeter::counting();
    let (mission, free) =
        Mission::plan(&world, &model, PlannerConfig { meter: meter.clone(), ..config.clone() }, start, &[goal])
            .unwrap();
    let whole = mission.search_bytes();
    let roomy = PlannerConfig { max_search_bytes: Some(whole + 1), ..config.clone() };
    assert_eq!(Mission::plan(&world, &model, roomy, start, &[goal]).unwrap().1, free);
    for limit in [whole / 2, whole * 9 / 10] {
        let tight = PlannerConfig { max_search_bytes: Some(limit), ..config.clone() };
        match Mission::plan(&world, &model, tight, start, &[goal]) {
            Err(Error::MemoryLimit { bytes, limit: l }) => {
                assert_eq!(l, limit);
                assert!(
                    limit < bytes && bytes <= whole,
                    "held {bytes} B at a limit of {limit} B; the whole search {whole} B"
                );
            }
            other => panic!("limit {limit} of {whole} B: {:?}", other.map(|(_, p)| p.cost)),
        }
    }

    // No plan: the probes that name the binding constraint run beside the mission's
    // graphs, which count; a limit that stops any of it is reported as the limit.
    let (long, small, start, quick, goal) = battery_bound();
    let unlimited = Mission::plan(&long, &small, quick.clone(), start, &[goal]);
    assert!(matches!(unlimited, Err(Error::Unreachable { binding: Binding::Battery, .. })), "{unlimited:?}");
    let stopped_in = |limit: u64| {
        let meter = areo_mission::ExpansionMeter::counting();
        let capped = PlannerConfig { max_search_bytes: Some(limit), meter: meter.clone(), ..quick.clone() };
        match Mission::plan(&long, &small, capped, start, &[goal]) {
            Err(Error::MemoryLimit { bytes, .. }) => Some((bytes, meter.phases_seen())),
            Err(Error::Unreachable { binding: Binding::Battery, .. }) => None,
            other => panic!("{:?}", other.map(|(_, p)| p.cost)),
        }
    };
    // The smallest limit the whole call fits in, by bisection; just under it the call
    // stops in a probe, holding more than any one graph of it alone.
    let (mut lo, mut hi) = (1u64, 1u64 << 32);
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if stopped_in(mid).is_some() { lo = mid } else { hi = mid }
    }
    let (bytes, phases) = stopped_in(lo).unwrap();
    assert!(bytes > lo && phases.len() > 1, "{bytes} B at {lo} B, phases {phases:?}");
}

/// `max_expansions` bounds a planning call's work, the finer-class retries and the
/// binding-constraint probes included: a call that reaches it stops with
/// `WorkLimit` — not "unreachable" — and a limit the call does not reach changes
/// nothing.
#[test]
fn a_planning_call_stops_at_its_expansion_limit_and_says_so() {
    let counted = |world: &World, model: &areo_mission::ActionModel, config: PlannerConfig, start, goal| {
        let meter = areo_mission::ExpansionMeter::counting();
        let out = Mission::plan(world, model, PlannerConfig { meter: meter.clone(), ..config }, start, &[goal]);
        (out.map(|(_, plan)| plan), meter.work())
    };
    // A plan: found in n expansions; n allowed gives the same plan, fewer stop.
    let world = fixed_sun_world(flat(40, 30, 10.0), 120.0, 60.0, 30.0);
    let model = model(1e5, ActionConfig::default());
    let start = Start { cell: world.cell(2, 3), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = world.cell(33, 20);
    let (free, n) = counted(&world, &model, PlannerConfig::default(), start, goal);
    let free = free.unwrap();
    assert!(n > 100, "{n}");
    let just = PlannerConfig { max_expansions: Some(n), ..PlannerConfig::default() };
    assert_eq!(counted(&world, &model, just, start, goal).0.unwrap(), free);
    let short = PlannerConfig { max_expansions: Some(n - 1), ..PlannerConfig::default() };
    match counted(&world, &model, short, start, goal) {
        (Err(Error::WorkLimit { expansions, limit }), spent) => {
            // Stopped at the first expansion that would pass the limit: the work may have
            // reached it within the last expansion's comparisons, not beyond that.
            assert_eq!((expansions, limit), (spent, n - 1));
            assert!((n - 1..=n).contains(&spent), "{spent} of {n}");
        }
        other => panic!("{other:?}"),
    }

    // No plan: the answer "unreachable (battery)" needs the probes' work too; a limit
    // that stops any of it is reported as the limit, never as "unreachable".
    let (long, small, start, quick, goal) = battery_bound();
    let (refused, m) = counted(&long, &small, quick.clone(), start, goal);
    assert!(matches!(refused, Err(Error::Unreachable { binding: Binding::Battery, .. })), "{refused:?}");
    let just = PlannerConfig { max_expansions: Some(m), ..quick.clone() };
    assert!(matches!(
        counted(&long, &small, just, start, goal).0,
        Err(Error::Unreachable { binding: Binding::Battery, .. })
    ));
    // The work counts the comparisons in the Pareto fronts beside the expansions: one
    // more expansion's worth for every hundred labels a new one was compared with.
    let meter = areo_mission::ExpansionMeter::counting();
    let _ = Mission::plan(&long, &small, PlannerConfig { meter: meter.clone(), ..quick.clone() }, start, &[goal]);
    assert_eq!(meter.work(), m);
    assert!(meter.work() > meter.expansions(), "{} against {}", meter.work(), meter.expansions());
    // Stopped in the search itself and among the probes (the search is about 85 % of
    // the work here).
    for limit in [m / 10, m * 9 / 10, m - 1] {
        let capped = PlannerConfig { max_expansions: Some(limit), ..quick.clone() };
        match counted(&long, &small, capped, start, goal) {
            (Err(Error::WorkLimit { expansions, .. }), spent) => {
                assert_eq!(expansions, spent);
                assert!((limit..=limit + 1).contains(&spent), "{spent} of {limit}");
            }
            other => panic!("limit {limit} of {m}: {other:?}"),
        }
    }
}

/// The first instant after `after` s at which the Sun goes down, to the minute.
fn sunset_after(world: &World, after: f64) -> f64 {
    let mut t = after;
    while world.sun(t).elevation_deg <= 0.0 {
        t += 60.0;
    }
    while world.sun(t).elevation_deg > 0.0 {
        t += 60.0;
    }
    t
}

/// A drive that cannot end before dark, drives only in daylight and a battery that never
/// binds: the plan must wait out the night, and with `max_wait_s` of an hour the goal
/// window closes long before the morning. Darkness relaxed alone makes a plan, so it is
/// named, and the message says the goal windows may bind too (not searched: opening
/// them is a search over a longer span); relaxing them does make the plan.
#[test]
fn a_goal_window_that_closes_before_the_morning_is_named_and_relaxing_it_plans() {
    let world = mars_world(flat(80, 3, 20.0), 36.0, None);
    let big = model(1e5, ActionConfig::default());
    let t0 = sunset_after(&world, 0.0) - 40.0 * 60.0;
    let start = Start { cell: world.cell(2, 1), t_min: t0, t_max: t0, energy_wh: 5e4 };
    let goal = world.cell(77, 1);
    let hour = PlannerConfig { max_wait_s: Some(3600.0), ..PlannerConfig::default() };
    match Mission::plan(&world, &big, hour.clone(), start, &[goal]) {
        Err(Error::Unreachable { binding, message, .. }) => {
            assert_eq!(binding, Binding::Darkness, "{message}");
            assert!(message.contains("`max_wait_s` 3600 s") && message.contains("(not searched)"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // Relaxed to the default (a sol of waiting), the same plan drives on in the morning.
    let sol = PlannerConfig { max_wait_s: None, ..hour };
    let (_, plan) = Mission::plan(&world, &big, sol, start, &[goal]).unwrap();
    let last = plan.waypoints.last().unwrap();
    assert_eq!(last.cell, goal);
    assert!(last.t_s > sunset_after(&world, 0.0) + 6.0 * 3600.0, "arrives after the night: {} s", last.t_s);
}

/// A wall with one gap at its far end makes the way five times the straight line; with
/// no detour allowed beyond the straight line and a minute of waiting, no plan arrives
/// within the goal window even with every constraint relaxed. The verdict names the goal
/// windows (opened to the horizon, the way is found), where it named the planning
/// horizon, and opening them does plan.
#[test]
fn a_goal_window_shorter_than_the_only_way_is_named_not_the_horizon() {
    let walled =
        Dem::from_fn(30, 40, 10.0, 10.0, |x, y| if (140.0..160.0).contains(&x) && y < 370.0 { 500.0 } else { 0.0 })
            .unwrap();
    let world = fixed_sun_world(walled, 90.0, 50.0, 3.0);
    let big = model(1e5, ActionConfig::default());
    let start = Start { cell: world.cell(5, 38), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = world.cell(25, 38);
    let tight = PlannerConfig { max_wait_s: Some(60.0), detour_factor: 1.0, ..PlannerConfig::default() };
    match Mission::plan(&world, &big, tight.clone(), start, &[goal]) {
        Err(Error::Unreachable { binding, message, .. }) => {
            assert_eq!(binding, Binding::GoalWindow, "{message}");
            assert!(message.contains("`detour_factor` 1") && message.contains("raise `max_wait_s`"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    let open = PlannerConfig { max_wait_s: Some(world.span_s()), ..tight };
    let (_, plan) = Mission::plan(&world, &big, open, start, &[goal]).unwrap();
    assert_eq!(plan.waypoints.last().unwrap().cell, goal);
}
