//! areo-actions integration tests: inventory filters, the executor's bookkeeping and
//! constraints, the fitness, and the GA's determinism and progress.

use areo_actions::*;
use areo_rover::RoverParams;
use areo_rover::evaluation::Evaluator;
use areo_rover::motion::Module;
use areo_terrain::analytic::{Plane, Wall};

fn task(target: (f64, f64)) -> Task {
    Task {
        start: (0.0, 0.0, 0.0),
        target,
        target_radius_m: 0.15,
        samples: Vec::new(),
        samples_wanted: 0,
        rocks: Vec::new(),
        manipulation: false,
        communication: false,
        video: false,
        recharge: false,
        tray: false,
    }
}

/// LSR-1 on a map `w` × `h` metres.
fn room(w: f64, h: f64) -> Surroundings {
    Surroundings::new((w, h), &RoverParams::lsr1())
}

fn scale(t: &Task) -> Scale {
    Scale {
        start_distance_m: t.start_distance_m(),
        samples_wanted: t.samples_wanted,
        reference_time_s: t.start_distance_m() / 0.03,
        battery_wh: 48.0,
        s_floor: 0.2,
    }
}

const FLAT: Plane = Plane { z0: 0.0, gx: 0.0, gy: 0.0 };

#[test]
fn filters_remove_what_a_mobility_task_cannot_need_and_say_why() {
    let t = task((0.0, 2.0));
    // On a map too narrow for a U-turn on the tight arcs (1.0 + 0.6 + 0.1 = 1.7 m),
    // point turns and backing stay.
    let inv = Inventory::for_task(&t, &room(1.6, 4.0), &Overrides::default());
    // Mobility only: the 8 driving modules stay; arm, grasp, tray, video, comms,
    // sleep, sweep and recharge go, each with a reason.
    assert_eq!(inv.codes(), vec![101, 102, 103, 104, 105, 106, 107, 108]);
    assert_eq!(inv.removed.len(), 18);
    assert!(inv.removed.iter().all(|r| !r.reason.is_empty()));
    let reason = |code| inv.removed.iter().find(|r| r.code == code).unwrap().reason.clone();
    assert!(reason(3002).contains("no samples"));
    assert!(reason(1001).contains("no manipulation"));
    assert!(reason(921).contains("communication"));
    // D = N^m: 26^40 before, 8^40 after.
    assert!((design_space_log10(26, 40) - 40.0 * 26f64.log10()).abs() < 1e-12);
    assert!((design_space_log10(26, 40) - design_space_log10(8, 40) - 40.0 * (26.0f64 / 8.0).log10()).abs() < 1e-9);
    // The scenario can force modules in (task 2's arm) and out.
    let forced = Inventory::for_task(
        &t,
        &room(1.6, 4.0),
        &Overrides { force_in: vec![1001, 1002, 1003, 1004], force_out: vec![102, 103, 104] },
    );
    assert_eq!(forced.codes(), vec![101, 105, 106, 107, 108, 1001, 1002, 1003, 1004]);
    assert!(forced.removed.iter().any(|r| r.code == 102 && r.reason.contains("forced out")));
    // Sampling tasks keep the sample modules.
    let mut s = task((0.0, 2.0));
    s.samples = vec![Sample { x_m: 0.0, y_m: 1.0, mass_kg: 0.1 }];
    s.samples_wanted = 1;
    let codes = Inventory::for_task(&s, &room(1.6, 4.0), &Overrides::default()).codes();
    for c in [3000, 3001, 3002, 3003] {
        assert!(codes.contains(&c), "{c}");
    }
    // The tray only for in-situ measurements.
    assert!(!codes.contains(&2010) && !codes.contains(&2020));
    s.tray = true;
    let codes = Inventory::for_task(&s, &room(1.6, 4.0), &Overrides::default()).codes();
    assert!(codes.contains(&2010) && codes.contains(&2020));
    // With room for a U-turn on the tight arcs and the target ahead, the point turns
    // and backing go too: the paper's nine modules for task 1, each removal with its
    // reason.
    s.tray = false;
    let nine = Inventory::for_task(&s, &room(1.8, 4.0), &Overrides::default());
    assert_eq!(nine.codes(), vec![101, 105, 106, 107, 108, 3000, 3001, 3002, 3003]);
    let reason = |code| nine.removed.iter().find(|r| r.code == code).unwrap().reason.clone();
    assert!(reason(103).contains("U-turn") && reason(104).contains("1.80 m"), "{}", reason(103));
    assert!(reason(102).contains("ahead"), "{}", reason(102));
    // A target behind the start keeps backing.
    let mut back = s.clone();
    back.target = (0.0, -2.0);
    assert!(Inventory::for_task(&back, &room(4.0, 4.0), &Overrides::default()).codes().contains(&102));
    assert_eq!(Inventory::from_codes(&[101, 999]), Err(999));
}

#[test]
fn a_straight_plan_on_flat_ground_advances_ten_centimetres_per_module_and_stops_at_the_target() {
    let p = RoverParams::lsr1();
    let ev = Evaluator::new(&p);
    let t = task((0.0, 1.0));
    let ex = Executor::new(&FLAT, &ev, &t, ExecConfig::default());
    let plan = vec![Module::Forward; 15];
    let e = ex.run(&plan, true);
    // The target (radius 15 cm) is reached after 9 modules (0.9 m); the rest is not run.
    assert!(e.complete);
    assert_eq!(e.prefix_len, 9);
    assert!((e.distance_to_target_m - 0.1).abs() < 1e-9);
    assert_eq!(e.trace.len(), 9);
    for (k, s) in e.trace.iter().enumerate() {
        assert!((s.y_m - 0.1 * (k + 1) as f64).abs() < 1e-9);
        assert_eq!(s.code, 101);
        // Six equal loads on flat ground: W/6.
        for l in s.wheel_loads_n {
            assert!((l - 7.0 * 9.81 / 6.0).abs() < 1e-6, "{l}");
        }
    }
    assert!((e.min_stability - 1.0).abs() < 1e-9 && e.failure.is_none());
    assert!((e.time_s - 9.0 * 0.10 / 0.03).abs() < 1e-9);
    // Rolling on flat ground: each motor gives c_rr·r·W/6 of its 3.5 N·m.
    let tau = p.rolling_resistance * p.wheel_radius_m * 7.0 * 9.81 / 6.0;
    assert!((e.peak_saturation - tau / p.wheel_torque_max_nm).abs() < 1e-9, "{}", e.peak_saturation);
    // Fitness: full progress bonus minus time and energy, no stability penalty.
    let w = Weights::default();
    let f = fitness(&e, &w, &scale(&t));
    let expected = w.progress * 0.9 - w.time * e.time_s / (1.0 / 0.03) - w.energy * e.energy_wh / 48.0 + w.complete;
    assert!((f - expected).abs() < 1e-9, "{f} vs {expected}");
}

#[test]
fn constraints_stop_a_plan_with_its_successful_prefix() {
    let p = RoverParams::lsr1();
    let ev = Evaluator::new(&p);
    // A 0.5 m wall 0.6 m ahead: the rover drives up to it and fails on the wall.
    let wall = Wall { x_step: 0.6, low_m: 0.0, high_m: 0.5 };
    let mut t = task((2.0, 0.0));
    t.start = (0.0, 0.0, 90.0);
    let ex = Executor::new(&wall, &ev, &t, ExecConfig { mu: 0.8, ..ExecConfig::default() });
    let e = ex.run(&[Module::Forward; 20], false);
    let (at, why) = e.failure.clone().expect("the wall stops the plan");
    assert_eq!(e.prefix_len, at);
    assert!((1..=5).contains(&at), "fails within the 0.6 m before the wall: {at}");
    // The wall stops the wheels (a typed physical limit, not text).
    assert!(matches!(why, ExecFailure::Motion(areo_rover::motion::MotionFailure::Violation(_))), "{why}");
    assert!(
        ["slip", "saturation", "loss_of_contact", "kinematics", "tip_over"].contains(&why.kind()),
        "{}",
        why.kind()
    );
    // A rock taller than the belly (0.26 m) on the path hits the body.
    let mut r = task((0.0, 2.0));
    r.rocks = vec![Rock { x_m: 0.0, y_m: 0.9, height_m: 0.35, width_m: 0.2 }];
    let ex = Executor::new(&FLAT, &ev, &r, ExecConfig::default());
    let e = ex.run(&[Module::Forward; 20], false);
    assert_eq!(e.failure.as_ref().map(|f| f.1.clone()), Some(ExecFailure::Collision(0)));
    // The body's front (0.30 m ahead of the reference) meets the ball (0.10 m radius)
    // around 0.5 m of travel.
    assert!((4..=6).contains(&e.prefix_len), "{}", e.prefix_len);
    // A low rock passes under the belly.
    r.rocks[0].height_m = 0.15;
    let ex = Executor::new(&FLAT, &ev, &r, ExecConfig::default());
    assert!(ex.run(&[Module::Forward; 20], false).complete);
}

#[test]
fn the_stability_penalty_is_zero_above_eighty_percent_and_full_at_the_floor() {
    assert_eq!(stability_penalty(0.9, 0.8, 0.2), 0.0);
    assert_eq!(stability_penalty(0.8, 0.8, 0.2), 0.0);
    assert!((stability_penalty(0.5, 0.8, 0.2) + 0.25).abs() < 1e-12);
    assert!((stability_penalty(0.2, 0.8, 0.2) + 1.0).abs() < 1e-12);
}

fn ga_run(threads: usize, seed: u64) -> GaReport {
    let p = RoverParams::lsr1();
    let ev = Evaluator::new(&p);
    let t = task((0.6, 2.0));
    let ex = Executor::new(&FLAT, &ev, &t, ExecConfig::default());
    let inv = Inventory::from_codes(&[101, 105, 106, 107, 108]).unwrap();
    let config = GaConfig { population: 20, generations: 8, initial_length: (10, 30), seed, ..GaConfig::default() };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| evolve(&ex, &inv, &Weights::default(), &scale(&t), &config).unwrap())
}

#[test]
fn the_ga_is_seeded_identical_for_any_thread_count_and_never_loses_its_best() {
    let a = ga_run(1, 3);
    let b = ga_run(2, 3);
    assert_eq!(a, b, "same seed, 1 and 2 threads");
    assert_ne!(a.best.plan, ga_run(2, 4).best.plan, "another seed, another run");
    // Elitism: the best fitness never decreases.
    for w in a.generations.windows(2) {
        assert!(w[1].best >= w[0].best - 1e-12, "{} then {}", w[0].best, w[1].best);
    }
    assert_eq!(a.evaluations, 20 * 9);
    // A 2.1 m trip to the north-north-east over flat ground: the GA completes it.
    assert!(a.best.execution.complete, "{:?}", a.generations.last());
    assert!(a.first_solved.is_some());
    // Improving crossovers extend the successful prefix by a few modules, not dozens.
    assert!(!a.lookahead.is_empty());
    let small = a.lookahead.iter().filter(|d| d.abs() <= 10).count();
    assert!(small * 2 >= a.lookahead.len(), "{:?}", a.lookahead);
}

#[test]
fn bad_settings_name_the_field() {
    let err = GaConfig { population: 1, ..GaConfig::default() }.validate().unwrap_err();
    assert!(err.to_string().contains("population"), "{err}");
    let mut t = task((1.0, 1.0));
    t.samples_wanted = 2;
    assert!(t.validate().unwrap_err().to_string().contains("samples_wanted"));
}

#[test]
fn resuming_from_a_parents_prefix_gives_the_same_execution_as_running_afresh() {
    let p = RoverParams::lsr1();
    let ev = Evaluator::new(&p);
    // Over a 20 cm step 0.8 m ahead, with a sample on the way.
    let ground = Wall { x_step: 0.8, low_m: 0.0, high_m: 0.05 };
    let mut t = task((1.6, 0.0));
    t.start = (0.0, 0.0, 90.0);
    t.samples = vec![Sample { x_m: 0.45, y_m: 0.0, mass_kg: 0.1 }];
    t.samples_wanted = 1;
    let ex = Executor::new(&ground, &ev, &t, ExecConfig::default());
    let parent_plan: Vec<Module> = [Module::Forward; 3]
        .into_iter()
        .chain([Module::Grasp, Module::ArcLeftWide, Module::Forward, Module::ArcRightWide])
        .chain([Module::Forward; 10])
        .collect();
    let parent = ex.run(&parent_plan, false);
    assert_eq!(parent.samples, 1);
    for cut in [0, 1, 4, 6, 9, 30] {
        let mut child: Vec<Module> = parent_plan[..cut.min(parent_plan.len())].to_vec();
        child.extend([Module::ArcRightTight, Module::Forward, Module::Forward, Module::ArcLeftTight]);
        child.extend([Module::Forward; 8]);
        let fresh = ex.run(&child, false);
        let resumed = ex.resume(&child, &parent, cut);
        assert_eq!(resumed, fresh, "cut at {cut}");
        // Going on from the cut's checkpoint alone ends where the fresh run ends.
        if (1..=parent.checkpoints.len()).contains(&cut) {
            let on = ex.continue_from(&parent.checkpoints[cut - 1], &child[cut..]);
            let end = |e: &Execution| e.checkpoints.last().map(|c| (*c.state(), c.collected().to_vec(), c.time_s()));
            assert_eq!(end(&on), end(&fresh), "cut at {cut}");
            assert_eq!((on.complete, on.samples, &on.taken), (fresh.complete, fresh.samples, &fresh.taken));
            assert_eq!(on.prefix_len + cut, fresh.prefix_len);
        }
    }
    // The sample taken is named: the task's first (and only) one.
    assert_eq!(parent.taken, vec![0]);
}

#[test]
fn a_rock_already_in_the_map_is_not_counted_twice_by_the_body_test() {
    // Synthesised rocks are part of the map *and* listed for the body test: the rock's
    // top is its height above the ground beside it, not above its own apex. An 18 cm
    // rock between the wheels passes under the 26 cm belly; a 32 cm one does not.
    use areo_terrain::synth::{Feature, TerrainSpec};
    let p = RoverParams::lsr1();
    let ev = Evaluator::new(&p);
    for (height, hits) in [(0.18, false), (0.32, true)] {
        let rock = Rock { x_m: 1.0, y_m: 1.2, height_m: height, width_m: 0.22 };
        let dem = TerrainSpec {
            cols: 100,
            rows: 150,
            cell_m: 0.02,
            base_m: 0.0,
            seed: 1,
            noise: None,
            features: vec![Feature::Rock { x_m: 1.0, y_m: 1.2, height_m: height, width_m: 0.22 }],
        }
        .build()
        .unwrap();
        let mut t = task((1.0, 2.4));
        t.start = (1.0, 0.6, 0.0);
        t.rocks = vec![rock];
        let ex = Executor::new(&dem, &ev, &t, ExecConfig::default());
        let run = ex.run(&[Module::Forward; 12], false);
        let collided = matches!(run.failure, Some((_, ExecFailure::Collision(0))));
        assert_eq!(collided, hits, "{height} m rock: {:?}", run.failure);
        if !hits {
            assert!(run.failure.is_none() && run.prefix_len == 12, "{:?}", run.failure);
        }
    }
}

#[test]
fn climb_margins_on_a_uniform_slope_follow_the_rear_tip_angle() {
    let p = RoverParams::lsr1();
    let ev = Evaluator::new(&p);
    let rear_tip = |arm: &areo_rover::arm::ArmState| {
        let (_, cg) = arm.system_mass_cg(&p).unwrap();
        ((p.axle_x_m.middle - p.axle_x_m.rear + cg.x) / cg.z).atan()
    };
    let stowed = areo_rover::arm::ArmState::stowed(&p);
    let forward = arm_reached_forward(&ev);
    // 1001 stops at the arm's reach: one more 2 cm step would not be reachable.
    assert!(forward.tool_m[0] > stowed.tool_m[0] + 0.2);
    assert!(forward.moved([0.02, 0.0, 0.0], &p).is_err());
    let (a0, a1) = (rear_tip(&stowed), rear_tip(&forward));
    // Facing up a 30° plane: the pitch is the slope, and the margin is the rear
    // axis's force angle over its flat-ground value, (α − θ)/α₀, with α the rear tip
    // angle of the arm's configuration and α₀ the stowed one.
    let theta = 30f64.to_radians();
    let plane = Plane { z0: 0.0, gx: 0.0, gy: theta.tan() };
    let climb = climb_margins(&plane, &ev, (0.0, 0.0, 0.0), 2.0, 0.1, 0.3);
    assert_eq!(climb.stop, None);
    assert_eq!(climb.poses.len(), 4);
    for pose in &climb.poses {
        assert!((pose.pitch_deg - 30.0).abs() < 1e-6, "{pose:?}");
        assert!((pose.stowed.margin - (a0 - theta) / a0).abs() < 1e-6, "{pose:?} vs {}", (a0 - theta) / a0);
        assert!((pose.forward.margin - (a1 - theta) / a0).abs() < 1e-6, "{pose:?} vs {}", (a1 - theta) / a0);
        assert_eq!(pose.stowed.violation, None);
    }
    // Between the two tip angles the stowed rover tips over and the reached-forward
    // one stands: the climb stops at its first pose, on tipping.
    let between = 0.5 * (a0 + a1);
    let steep = Plane { z0: 0.0, gx: 0.0, gy: between.tan() };
    let climb = climb_margins(&steep, &ev, (0.0, 0.0, 0.0), 2.0, 0.1, 0.3);
    assert_eq!(climb.stop, Some("tip_over"));
    assert_eq!(climb.poses.len(), 1);
    assert_eq!(climb.poses[0].stowed.margin, 0.0);
    // (Its front wheels have lost their load there, so the margin is no longer the
    // rear axis's alone; it lies between 0 and the gap of the two tip angles.)
    let f = climb.poses[0].forward;
    assert!(f.margin > 0.0 && f.margin < (a1 - a0) / a0, "{:?}", climb.poses[0]);
    assert_eq!(f.violation, None);
}

#[test]
fn a_plan_replayed_over_friction_needs_tan_of_the_slope_and_never_fails_above() {
    // Twelve modules straight up a uniform 20° plane. Quasi-statically the ground's
    // tangential forces hold the weight's component along the slope with traction
    // ≤ μN at every wheel, so the least μ is tan 20° = 0.364 whatever the load
    // sharing (rolling resistance is a loss in the wheel's torque, not a ground force,
    // in areo-rover's model). The plan is the same at every μ; only the limit changes.
    let p = RoverParams::lsr1();
    let ev = Evaluator::new(&p);
    let slope = Plane { z0: 0.0, gx: 0.0, gy: 20f64.to_radians().tan() };
    let t = task((0.0, 1.0));
    let plan = [Module::Forward; 12];
    let mus: Vec<f64> = (20..=80).map(|k| f64::from(k) / 100.0).collect();
    let replay = friction_replay(&slope, &ev, &t, ExecConfig::default(), &plan, &mus, Some(0.5));
    let least = replay.min_mu_completing.expect("completes at μ = 0.8");
    assert!((least - 0.37).abs() < 1e-9, "needs {least}: tan 20° rounded up to the list's 0.01");
    // More friction never stops a plan that went through with less.
    let mut seen_complete = false;
    for point in &replay.points {
        assert!(point.complete || !seen_complete, "completes below μ = {} and not at it", point.mu);
        seen_complete |= point.complete;
        if !point.complete {
            // Below the threshold the plan stops on the slope at the first module, on
            // a friction limit.
            let (at, why) = point.failure.clone().expect("a failing point names its failure");
            assert_eq!(at, 0, "μ {}", point.mu);
            assert!(["slip", "start_pose"].contains(&why.kind()), "μ {}: {}", point.mu, why.kind());
        }
    }
    let worst = replay.highest_failing().expect("fails at μ = 0.2");
    assert!((worst.mu - (least - 0.01)).abs() < 1e-9, "the highest failing μ is just below the threshold");
    // Crossing 0.5 m needs the same friction as completing here.
    assert_eq!(replay.min_mu_crossing, replay.min_mu_completing);
}

#[test]
fn exported_steering_angles_are_the_directions_the_wheels_actually_roll() {
    // Two tight left arcs, a straight module and a right turn in place on flat ground.
    // Each corner wheel's chord over a module must point along the body's heading at
    // the module's middle turned by the wheel's exported steering angle: the wheels'
    // positions come from the kinematics, the angles from the arc's geometry.
    let p = RoverParams::lsr1();
    let ev = Evaluator::new(&p);
    let mut t = task((3.0, 3.0));
    t.start = (1.0, 1.0, 30.0);
    let plan = [Module::ArcLeftTight, Module::ArcLeftTight, Module::Forward, Module::TurnRight, Module::ArmForward];
    let run = Executor::new(&FLAT, &ev, &t, ExecConfig::default()).run(&plan, true);
    assert_eq!(run.prefix_len, plan.len(), "{:?}", run.failure);
    let cmds = commands(&plan, &run, &p, t.start.2);
    assert_eq!(cmds.len(), plan.len());
    // 10 cm on a 50 cm radius turns the rover 0.2 rad to the left.
    assert!((cmds[1].turn_deg - 0.2f64.to_degrees()).abs() < 0.05, "{}", cmds[1].turn_deg);
    assert!((cmds[3].turn_deg + 5.0).abs() < 0.05, "{}", cmds[3].turn_deg);
    assert_eq!((cmds[1].arc_radius_m, cmds[2].arc_radius_m, cmds[3].arc_radius_m), (Some(0.5), None, Some(0.0)));
    // Wheels in the trace: left front, middle, rear, right front, middle, rear.
    let corner = [0, 3, 2, 5];
    for k in [1, 3] {
        let (before, after) = (&run.trace[k - 1], &run.trace[k]);
        let steer = cmds[k].steering_deg.expect("a drive steers");
        let mid_heading = before.heading_deg - cmds[k].turn_deg / 2.0;
        for (s, &w) in steer.iter().zip(&corner) {
            let (dx, dy) = (after.wheels[w][0] - before.wheels[w][0], after.wheels[w][1] - before.wheels[w][1]);
            let mut chord = dx.atan2(dy).to_degrees();
            // A wheel rolling backward (the rear-right wheel of a right turn in place
            // rolls forward, the front-right backward): compare directions, not senses.
            let expected = mid_heading - s;
            let mut diff = (chord - expected + 540.0).rem_euclid(360.0) - 180.0;
            if diff.abs() > 90.0 {
                chord += 180.0;
                diff = (chord - expected + 540.0).rem_euclid(360.0) - 180.0;
            }
            assert!(diff.abs() < 0.5, "module {k} wheel {w}: rolls at {chord:.2}°, steered to {expected:.2}°");
        }
    }
    // The tight arc's inner front wheel turns atan(0.4 / (0.5 − 0.3)) = 63.4°.
    assert!((cmds[0].steering_deg.unwrap()[0] - 63.435).abs() < 0.01);
    // Non-driving modules do not steer; the arm module moves the tool 2 cm forward and
    // its joints are a solution for that tool.
    assert!(cmds[4].steering_deg.is_none());
    assert!((cmds[4].tool_m[0] - cmds[3].tool_m[0] - 0.02).abs() < 1e-9);
    assert!(cmds[4].arm_joints_deg.is_some());
    // The commands account for the whole execution's time and energy.
    let time: f64 = cmds.iter().map(|c| c.duration_s).sum();
    let energy: f64 = cmds.iter().map(|c| c.energy_wh).sum();
    assert!((time - run.time_s).abs() < 1e-9 && time > 0.0);
    assert!((energy - run.energy_wh).abs() < 1e-12 && energy > 0.0);
}
