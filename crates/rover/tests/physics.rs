//! The LSR-1 physics end to end: pose, coupled forces, stability, arm and energy,
//! against the reference's analytic values (shared/reference/rover_physics.md §6).

use areo_rover::RoverParams;
use areo_rover::arm::ArmState;
use areo_rover::evaluation::{Conditions, Evaluator, Place, Violation};
use areo_rover::forces::ForceFailure;
use areo_rover::kinematics::{Kinematics, newton_pose};
use areo_rover::motion::{Module, Motion, MotionFailure, RoverState, SampleSite};
use areo_terrain::Ground;
use areo_terrain::analytic::{Plane, Wall};

fn lsr1() -> RoverParams {
    RoverParams::lsr1()
}

fn hold(mu: f64) -> Conditions {
    Conditions { mu, direction: 0.0 }
}

fn slope(deg: f64) -> Plane {
    // Rising to the north.
    Plane { z0: 0.0, gx: 0.0, gy: deg.to_radians().tan() }
}

#[test]
fn flat_ground_six_equal_loads_no_torque_full_margin() {
    let p = lsr1();
    let ev = Evaluator::new(&p);
    let e = ev
        .evaluate(
            &Plane { z0: 1.0, gx: 0.0, gy: 0.0 },
            Place { x: 3.0, y: 4.0, heading: 0.7 },
            &ArmState::stowed(&p),
            &hold(0.5),
            None,
        )
        .unwrap();
    let w = 7.0 * 9.81;
    assert!((e.weight_n - w).abs() < 1e-9);
    assert!(e.pose.pitch.abs() < 1e-9 && e.pose.roll.abs() < 1e-9);
    for wheel in &e.pose.wheels {
        assert!((wheel.contact[2] - 1.0).abs() < 1e-9, "six contacts on the ground");
    }
    for n in e.normals_n() {
        assert!((n - w / 6.0).abs() < 1e-9, "{:?}", e.normals_n());
    }
    assert!((e.normals_n().iter().sum::<f64>() - w).abs() < 1e-9);
    assert!(e.torques_nm().iter().all(|t| t.abs() < 1e-9));
    assert!((e.stability - 1.0).abs() < 1e-9, "{}", e.stability);
}

#[test]
fn an_offset_cg_loads_the_wheels_by_the_lever_rule() {
    // Reference T2: x_G = +0.069 → per side (0.1954, 0.1954, 0.1092)·W; x_G = −0.10 →
    // (0.125, 0.125, 0.250)·W.
    for (xg, want) in [(0.069, [0.1954, 0.1954, 0.1092]), (-0.10, [0.125, 0.125, 0.250])] {
        let mut p = lsr1();
        p.cg_m.x = xg;
        let ev = Evaluator::new(&p);
        let e = ev
            .evaluate(
                &Plane { z0: 0.0, gx: 0.0, gy: 0.0 },
                Place { x: 0.0, y: 0.0, heading: 0.0 },
                &ArmState::stowed(&p),
                &hold(0.5),
                None,
            )
            .unwrap();
        for side in &e.sides {
            for (n, w) in side.normal_n.iter().zip(want) {
                assert!((n / e.weight_n - w).abs() < 5e-4, "x_G {xg}: {:?}", side.normal_n);
            }
        }
    }
}

#[test]
fn a_lateral_cg_offset_loads_one_side_more() {
    let mut p = lsr1();
    p.cg_m.y = 0.06;
    let ev = Evaluator::new(&p);
    let e = ev
        .evaluate(
            &Plane { z0: 0.0, gx: 0.0, gy: 0.0 },
            Place { x: 0.0, y: 0.0, heading: 0.0 },
            &ArmState::stowed(&p),
            &hold(0.5),
            None,
        )
        .unwrap();
    // Lever rule across the 0.60 m track: left (0.30 + 0.06)/0.60 = 60 %.
    assert!((e.pivot_loads_n[0] / e.weight_n - 0.6).abs() < 1e-9);
    let left: f64 = e.sides[0].normal_n.iter().sum();
    assert!((left / e.weight_n - 0.6).abs() < 1e-9);
}

#[test]
fn holding_on_a_slope_needs_mu_tan_theta_and_pitches_by_theta() {
    let p = lsr1();
    let ev = Evaluator::new(&p);
    let arm = ArmState::stowed(&p);
    for theta in [10.0f64, 20.0, 25.0, 30.0] {
        let g = slope(theta);
        let mu_star = theta.to_radians().tan();
        let e = ev.evaluate(&g, Place { x: 0.0, y: 0.0, heading: 0.0 }, &arm, &hold(mu_star + 1e-3), None).unwrap();
        assert!((e.pose.pitch.to_degrees() - theta).abs() < 1e-6, "{theta}: {}", e.pose.pitch.to_degrees());
        let sum_n: f64 = e.normals_n().iter().sum();
        assert!(
            (sum_n - e.weight_n * theta.to_radians().cos()).abs() < 1e-5,
            "{sum_n} vs {}",
            e.weight_n * theta.to_radians().cos()
        );
        let fail =
            ev.evaluate(&g, Place { x: 0.0, y: 0.0, heading: 0.0 }, &arm, &hold(mu_star - 1e-3), None).unwrap_err();
        assert!(matches!(fail, Violation::Forces { failure: ForceFailure::Slip, .. }), "{theta}: {fail:?}");
    }
}

/// A slope whose ground sets its own friction coefficient north of `y_from` (a terrain
/// class on part of it), and leaves the motion's elsewhere.
struct Classed {
    plane: Plane,
    y_from: f64,
    mu: f64,
}

impl Ground for Classed {
    fn height(&self, x: f64, y: f64) -> Option<f64> {
        self.plane.height(x, y)
    }
    fn normal(&self, x: f64, y: f64) -> Option<[f64; 3]> {
        self.plane.normal(x, y)
    }
    fn friction(&self, _x: f64, y: f64) -> Option<f64> {
        (y >= self.y_from).then_some(self.mu)
    }
}

#[test]
fn the_ground_s_own_friction_holds_where_it_sets_one_and_a_side_takes_its_slipperiest_wheel() {
    // Holding on 20° needs μ* = tan 20° = 0.364 (the test above). The motion's μ is
    // ample (0.6); sand of μ* − 0.001 under every wheel slips, and under the front
    // wheels only (the front axle is 0.40 m ahead) too: one slippery wheel sets its
    // side's μ. Sand of μ* + 0.001 holds, and the evaluation says how much friction was
    // available.
    let p = lsr1();
    let ev = Evaluator::new(&p);
    let arm = ArmState::stowed(&p);
    let mu_star = 20f64.to_radians().tan();
    let at = Place { x: 0.0, y: 0.0, heading: 0.0 };
    for (y_from, mu, holds) in
        [(-10.0, mu_star - 1e-3, false), (0.3, mu_star - 1e-3, false), (-10.0, mu_star + 1e-3, true), (0.6, 0.05, true)]
    {
        let g = Classed { plane: slope(20.0), y_from, mu };
        match ev.evaluate(&g, at, &arm, &hold(0.6), None) {
            Ok(e) => {
                assert!(holds, "sand from y = {y_from} at μ {mu} should slip");
                let available = if y_from < 0.6 { mu } else { 0.6 };
                assert!((e.friction_available - available).abs() < 1e-12, "{}", e.friction_available);
                assert!(e.friction_used <= available + 1e-9);
            }
            Err(v) => {
                assert!(!holds, "sand from y = {y_from} at μ {mu}: {v:?}");
                assert!(matches!(v, Violation::Forces { failure: ForceFailure::Slip, .. }), "{v:?}");
            }
        }
    }
}

/// The normalised margin on a slope of `deg` with the rover heading `heading_deg`
/// (0: straight up, 90: across, the slope rising on its left).
fn margin(deg: f64, heading_deg: f64) -> Result<f64, Violation> {
    let p = lsr1();
    let ev = Evaluator::new(&p);
    let e = ev.evaluate(
        &slope(deg),
        Place { x: 0.0, y: 0.0, heading: heading_deg.to_radians() },
        &ArmState::stowed(&p),
        &hold(5.0),
        None,
    )?;
    Ok(e.stability)
}

#[test]
fn tip_over_angles_are_atan_half_track_and_half_wheelbase_over_cg_height() {
    // Lateral: atan(0.30/0.25) = 50.19°, S = 1 − φ/50.19°; fore-aft: atan(0.40/0.25)
    // = 57.99° (T5, T6). Heading west puts the slope's rise on the rover's right.
    let lat = (0.30f64 / 0.25).atan().to_degrees();
    let lon = (0.40f64 / 0.25).atan().to_degrees();
    for phi in [10.0, 20.0, 30.0, 40.0] {
        let s = margin(phi, 270.0).unwrap();
        assert!((s - (1.0 - phi / lat)).abs() < 2e-3, "side slope {phi}: {s}");
    }
    for theta in [20.0, 30.0, 40.0] {
        let s = margin(theta, 180.0).unwrap();
        assert!((s - (1.0 - theta / lon)).abs() < 2e-3, "down a slope of {theta}: {s}");
    }
    // Past the tip angle the evaluation reports tip-over.
    assert_eq!(margin(lat + 1.0, 270.0), Err(Violation::TipOver));
}

#[test]
fn extending_the_arm_forward_raises_the_rear_tip_angle() {
    let p = lsr1();
    let ev = Evaluator::new(&p);
    let flat = Plane { z0: 0.0, gx: 0.0, gy: 0.0 };
    let rear = |arm: &ArmState| {
        let e = ev.evaluate(&flat, Place { x: 0.0, y: 0.0, heading: 0.0 }, arm, &hold(0.5), None).unwrap();
        // The rear axis: outward normal pointing south (heading north).
        let down = nalgebra::Vector3::new(0.0, 0.0, -1.0);
        let fa = e.force_angle;
        (0..fa.angles().len()).find(|&i| fa.outward(i, down).y < -0.9).map(|i| fa.angles()[i]).unwrap()
    };
    let stowed = ArmState::stowed(&p);
    let forward = ArmState { tool_m: [0.849, 0.0, 0.42], payload_kg: 0.0 };
    let (a0, a1) = (rear(&stowed), rear(&forward));
    // The CG moves forward by Δx = m_arm/m · Δx_arm; the rear angle is atan((0.40 + x_G)/h).
    let (_, cg0) = stowed.system_mass_cg(&p).unwrap();
    let (_, cg1) = forward.system_mass_cg(&p).unwrap();
    assert!(cg1.x > cg0.x + 0.03, "{cg0} → {cg1}");
    assert!((a0 - ((0.40 + cg0.x) / cg0.z).atan()).abs() < 1e-9);
    assert!((a1 - ((0.40 + cg1.x) / cg1.z).atan()).abs() < 1e-9);
    assert!(a1 > a0 + 2f64.to_radians(), "{} → {}", a0.to_degrees(), a1.to_degrees());
    // Facing up a 59° slope (past the stowed 57.99° backward tip), reaching forward
    // turns a tip into a stand.
    let hill = slope(59.0);
    assert_eq!(
        ev.evaluate(&hill, Place { x: 0.0, y: 0.0, heading: 0.0 }, &stowed, &hold(5.0), None).unwrap_err(),
        Violation::TipOver
    );
    assert!(ev.evaluate(&hill, Place { x: 0.0, y: 0.0, heading: 0.0 }, &forward, &hold(5.0), None).is_ok());
}

/// Smallest μ that holds `ground` at the pose, by bisection on feasibility.
fn mu_star(ground: &impl Ground, x: f64, heading_deg: f64, direction: f64) -> f64 {
    let mut p = lsr1();
    p.wheel_torque_max_nm = 3.5;
    let ev = Evaluator::new(&p);
    let arm = ArmState::stowed(&p);
    let ok = |mu: f64| {
        ev.evaluate(
            ground,
            Place { x, y: 0.0, heading: heading_deg.to_radians() },
            &arm,
            &Conditions { mu, direction },
            None,
        )
        .is_ok()
    };
    let (mut lo, mut hi) = (0.0, 3.0);
    assert!(ok(hi), "not even μ = 3 holds");
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if ok(mid) { hi = mid } else { lo = mid }
    }
    hi
}

#[test]
fn climbing_a_vertical_step_needs_the_reference_mu() {
    // T9: the front wheels against a wall taller than r, the others on flat ground:
    // μ* = 0.580, whatever the CG height.
    let wall = Wall { x_step: 0.0, low_m: 0.0, high_m: 0.30 };
    // Heading east, middle axles at x = −0.499999: the front wheels press 1 µm into
    // the wall's face, so they ride on it 1 mm above the ground.
    let mu = mu_star(&wall, -0.499999, 90.0, 0.0);
    assert!((mu - 0.580).abs() < 0.01, "{mu}");
}

#[test]
fn contact_error_stays_under_two_percent_of_the_diameter() {
    let p = lsr1();
    let k = Kinematics::new(&p);
    let terrains: Vec<Box<dyn Fn(f64, f64) -> f64>> = vec![
        Box::new(|_, _| 0.0),
        Box::new(|_, y| y * 20f64.to_radians().tan()),
        Box::new(|x, _| -x * 15f64.to_radians().tan()),
        Box::new(|x, y| 0.08 * (2.0 * x).sin() * (1.5 * y).cos() + 0.05 * (3.1 * x + 1.0).cos()),
    ];
    struct F<'a>(&'a dyn Fn(f64, f64) -> f64);
    impl Ground for F<'_> {
        fn height(&self, x: f64, y: f64) -> Option<f64> {
            Some((self.0)(x, y))
        }
        fn normal(&self, _: f64, _: f64) -> Option<[f64; 3]> {
            Some([0.0, 0.0, 1.0])
        }
    }
    for (t, f) in terrains.iter().enumerate() {
        let g = F(f.as_ref());
        for i in 0..12 {
            let (x, y, h) = (0.3 * i as f64, -0.2 * i as f64, 0.5 * i as f64);
            let pose = k.solve(&g, x, y, h, None).unwrap();
            let err = pose.contact_error_m(&g, p.wheel_radius_m);
            assert!(err < 0.02 * 0.20, "terrain {t}, pose {i}: {err}");
        }
    }
}

#[test]
fn newton_on_the_full_chain_agrees_with_the_planar_decomposition() {
    let p = lsr1();
    let k = Kinematics::new(&p);
    let rough = |x: f64, y: f64| 0.06 * (1.7 * x).sin() * (1.3 * y).cos() + 0.1 * y;
    struct F<G: Fn(f64, f64) -> f64>(G);
    impl<G: Fn(f64, f64) -> f64> Ground for F<G> {
        fn height(&self, x: f64, y: f64) -> Option<f64> {
            Some((self.0)(x, y))
        }
        fn normal(&self, _: f64, _: f64) -> Option<[f64; 3]> {
            Some([0.0, 0.0, 1.0])
        }
    }
    let g = F(rough);
    assert_newton_agrees(&p, &g);
    // On a plane crossed diagonally the two differ only by the planar model's
    // convention: its wheel planes tilt about the heading line, so its body axis is
    // yawed by ≈ tan(pitch)·sin(roll) (0.4° here) and its pitch differs by < 0.2°.
    let side = Plane { z0: 0.0, gx: -0.2, gy: 0.1 };
    let planar = k.solve(&side, 0.0, 0.0, 0.3, None).unwrap();
    let newton = newton_pose(&side, &p, 0.0, 0.0, 0.3, None).unwrap();
    assert!(
        (newton.roll - planar.roll).abs() < 0.2f64.to_radians()
            && (newton.pitch - planar.pitch).abs() < 0.2f64.to_radians(),
        "roll {} vs {}, pitch {} vs {}",
        newton.roll,
        planar.roll,
        newton.pitch,
        planar.pitch
    );
}

#[test]
fn a_ten_centimetre_move_costs_the_rolling_resistance_work_over_the_efficiency() {
    let p = lsr1();
    let ev = Evaluator::new(&p);
    let flat = Plane { z0: 0.0, gx: 0.0, gy: 0.0 };
    let motion = Motion::new(&ev, 0.6);
    let start = RoverState::new(&ev, 0.0, 0.0, 0.0);
    let step = motion.run(&flat, &start, Module::Forward, &[]).unwrap();
    let w = 7.0 * 9.81;
    let work_j = p.rolling_resistance * w * 0.10;
    let mech_j = step.energy.mechanical_wh * 3600.0;
    assert!((mech_j - work_j / p.drive.gear_efficiency).abs() < 1e-9, "{mech_j} J vs {}", work_j / 0.5);
    // Copper losses: six wheels at τ = c_rr·r·W/6 for 10 cm at 3 cm/s.
    let tau = p.rolling_resistance * p.wheel_radius_m * w / 6.0;
    let copper_j = 6.0 * p.drive.copper_loss_w_per_nm2() * tau * tau * (0.10 / p.speed_m_s);
    assert!((step.energy.copper_wh * 3600.0 - copper_j).abs() < 1e-9);
    assert!((step.duration_s - 0.10 / 0.03).abs() < 1e-12);
    assert!((step.state.y - 0.10).abs() < 1e-12 && step.state.x.abs() < 1e-12);
}

#[test]
fn a_drive_after_a_turn_to_a_sample_turns_back_first_so_sample_turns_never_steer() {
    let p = lsr1();
    let ev = Evaluator::new(&p);
    let flat = Plane { z0: 0.0, gx: 0.0, gy: 0.0 };
    let motion = Motion::new(&ev, 0.6);
    let start = RoverState::new(&ev, 0.0, 0.0, 0.0);
    let sample = [SampleSite { id: 0, x: -0.35, y: 0.45, mass_kg: 0.1 }];
    let turned = motion.run(&flat, &start, Module::TurnToSample, &sample).unwrap();
    let twice = motion.run(&flat, &turned.state, Module::TurnToSample, &sample).unwrap();
    assert!((twice.state.sample_turn - 30f64.to_radians()).abs() < 1e-12, "two 15° turns to the left");
    assert!((twice.state.heading + 30f64.to_radians()).abs() < 1e-12);
    // 101 from the stance: back to north first, then 10 cm straight north.
    let on = motion.run(&flat, &twice.state, Module::Forward, &sample).unwrap();
    assert!(on.state.heading.abs() < 1e-12 && on.state.sample_turn == 0.0);
    assert!(on.state.x.abs() < 1e-12 && (on.state.y - 0.10).abs() < 1e-12);
    // It pays for the turn back: a 30° turn at the turn rate, on top of the 10 cm.
    let plain = motion.run(&flat, &start, Module::Forward, &sample).unwrap();
    let turn_s = 30.0 / p.turn_rate_deg_s;
    assert!((on.duration_s - plain.duration_s - turn_s).abs() < 1e-9, "{} vs {}", on.duration_s, plain.duration_s);
    assert!(on.energy.net_wh() > plain.energy.net_wh() + p.hotel_power_w * turn_s / 3600.0 * 0.999);
    // Nothing is left to turn from.
    let back = motion.run(&flat, &on.state, Module::TurnFromSample, &sample);
    assert_eq!(back.unwrap_err().failure, MotionFailure::NothingToTurnTo);
}

#[test]
fn every_module_runs_and_arcs_follow_their_circles() {
    let p = lsr1();
    let ev = Evaluator::new(&p);
    let flat = Plane { z0: 0.0, gx: 0.0, gy: 0.0 };
    let motion = Motion::new(&ev, 0.6);
    let start = RoverState::new(&ev, 0.0, 0.0, 0.0);
    // A sample on the ground 0.57 m away, 38° to the left: "turn to sample" turns 15°
    // toward it and "grasp" reaches it from here.
    let sample = [SampleSite { id: 7, x: -0.35, y: 0.45, mass_kg: 0.1 }];
    for m in Module::ALL {
        assert_eq!(Module::from_code(m.code()), Some(m));
        let r = motion.run(&flat, &start, m, &sample);
        match m {
            Module::Release => assert_eq!(r.unwrap_err().failure, MotionFailure::NotHolding, "nothing to release"),
            Module::Grasp => assert_eq!(r.unwrap().grasped, Some(7)),
            Module::TurnToSample => {
                assert!((r.unwrap().state.heading + 15f64.to_radians()).abs() < 1e-12, "15° to the left")
            }
            // Nothing to undo from a fresh start.
            Module::TurnFromSample => assert_eq!(r.unwrap_err().failure, MotionFailure::NothingToTurnTo),
            _ => {
                let s = r.unwrap_or_else(|e| panic!("{m:?}: {e:?}"));
                assert!(s.duration_s > 0.0, "{m:?}");
            }
        }
    }
    // 105: 10 cm on a 0.5 m circle to the left: heading −0.2 rad (to the west), chord
    // 2R sin(0.1).
    let s = motion.run(&flat, &start, Module::ArcLeftTight, &[]).unwrap();
    assert!((s.state.heading + 0.2).abs() < 1e-12);
    assert!((s.state.x.hypot(s.state.y) - 2.0 * 0.5 * 0.1f64.sin()).abs() < 1e-12 && s.state.x < 0.0);
    // 103: 5° in place.
    let s = motion.run(&flat, &start, Module::TurnLeft, &[]).unwrap();
    assert!((s.state.heading + 5f64.to_radians()).abs() < 1e-12 && s.state.x == 0.0);
    // Recharging on flat ground at noon gains flux·area·efficiency for its duration.
    let s = motion.run(&flat, &start, Module::Recharge, &[]).unwrap();
    assert!((s.energy.solar_wh - 1000.0 * 0.25 * 0.18).abs() < 1e-9);
}

#[test]
fn a_drive_into_a_wall_stops_at_the_first_violation() {
    let p = lsr1();
    let ev = Evaluator::new(&p);
    // A 0.5 m wall across the path: the bogie passes its limit before the front axle
    // can climb it.
    let wall = Wall { x_step: 0.0, low_m: 0.0, high_m: 0.5 };
    let motion = Motion::new(&ev, 0.8);
    let mut state = RoverState::new(&ev, -0.60, 0.0, 90f64.to_radians());
    let mut stopped = None;
    for _ in 0..10 {
        match motion.run(&wall, &state, Module::Forward, &[]) {
            Ok(s) => state = s.state,
            Err(e) => {
                stopped = Some(e);
                break;
            }
        }
    }
    let e = stopped.expect("the wall stops the rover");
    assert!(e.state.x < 0.0 - 0.09, "stopped before the wall: {}", e.state.x);
    assert!(matches!(e.failure, areo_rover::motion::MotionFailure::Violation(_)), "{e:?}");
}

#[test]
fn contact_error_on_a_rough_dem_with_a_ditch_hill_and_rock() {
    // The action planner's kind of ground: 2 cm cells, a 25 cm deep ditch with 45°
    // walls, a 20° hill, a rock and noise. Every pose along three crossings keeps its
    // wheels within 2 % of the diameter (4 mm) of the terrain; the paper reports 0.5 cm.
    use areo_terrain::synth::{Feature, Noise, TerrainSpec};
    let dem = TerrainSpec {
        cols: 300,
        rows: 200,
        cell_m: 0.02,
        base_m: 0.0,
        seed: 3,
        noise: Some(Noise { amplitude_m: 0.02, wavelength_m: 0.5, octaves: 3, persistence: 0.5 }),
        features: vec![
            Feature::Hill { x_m: 4.5, y_m: 2.0, radius_m: 1.5, slope_deg: 20.0 },
            Feature::Ditch { from_m: (2.0, 0.0), to_m: (2.0, 4.0), width_m: 0.6, depth_m: 0.25, wall_deg: 45.0 },
            Feature::Rock { x_m: 1.2, y_m: 1.7, height_m: 0.08, width_m: 0.2 },
        ],
    }
    .build()
    .unwrap();
    let p = lsr1();
    let k = Kinematics::new(&p);
    let (mut worst, mut sum, mut n) = (0.0f64, 0.0, 0usize);
    for (y, heading) in [(1.7, 90.0f64), (2.0, 80.0), (2.4, 100.0)] {
        let mut warm = None;
        for i in 0..100 {
            let x = 0.8 + 0.03 * i as f64;
            let Ok(pose) = k.solve(&dem, x, y, heading.to_radians(), warm.as_ref()) else {
                warm = None;
                continue;
            };
            let e = pose.contact_error_m(&dem, p.wheel_radius_m);
            worst = worst.max(e);
            sum += e;
            n += 1;
            warm = Some(pose);
        }
    }
    assert!(n > 200, "most poses exist: {n}");
    assert!(worst < 0.004, "worst contact error {worst} m");
    let mean = sum / n as f64;
    assert!(mean < 0.001, "mean contact error {mean} m");
}

/// The modules of two samplings of one drive agree: as many, and each with the same
/// energy (2 %), least stability (0.03), most friction (0.05) and end.
fn same_modules(fine: &[areo_rover::motion::ModuleRun], coarse: &[areo_rover::motion::ModuleRun], case: &str) {
    assert_eq!(fine.len(), coarse.len(), "{case}: modules run");
    for (a, b) in fine.iter().zip(coarse) {
        let (ea, eb) = (a.energy.net_wh(), b.energy.net_wh());
        assert!((ea - eb).abs() <= 0.02 * ea.abs(), "{case}: energy {ea} vs {eb}");
        let (sa, sb) = (a.min_stability.unwrap(), b.min_stability.unwrap());
        assert!((sa - sb).abs() < 0.03, "{case}: min stability {sa} vs {sb}");
        assert!((a.max_friction - b.max_friction).abs() < 0.05, "{case}: friction");
        assert!((a.state.x - b.state.x).abs() < 1e-12);
    }
}

/// A map that counts the heights asked of it.
struct Counting<'a>(&'a areo_terrain::Dem, std::cell::Cell<usize>);

impl Ground for Counting<'_> {
    fn height(&self, x: f64, y: f64) -> Option<f64> {
        self.1.set(self.1.get() + 1);
        self.0.height(x, y)
    }
    fn normal(&self, x: f64, y: f64) -> Option<[f64; 3]> {
        Ground::normal(self.0, x, y)
    }
}

/// Up to `modules` forward drives on `dem` from (x, y, heading in degrees) at friction
/// μ, sampling at `coarse` strides: the modules run, where they stopped, and the heights
/// they asked for.
fn forward_drives(
    ev: &Evaluator,
    dem: &areo_terrain::Dem,
    (x0, y, heading, mu): (f64, f64, f64, f64),
    coarse: usize,
    modules: usize,
) -> (Vec<areo_rover::motion::ModuleRun>, Option<areo_rover::motion::Stopped>, usize) {
    let ground = Counting(dem, std::cell::Cell::new(0));
    let mut motion = Motion::new(ev, mu);
    motion.coarse_steps = coarse;
    let mut state = RoverState::new(ev, x0, y, f64::to_radians(heading));
    let mut steps = Vec::new();
    for _ in 0..modules {
        match motion.run(&ground, &state, Module::Forward, &[]) {
            Ok(s) => {
                state = s.state;
                steps.push(s);
            }
            Err(e) => return (steps, Some(e), ground.1.get()),
        }
    }
    (steps, None, ground.1.get())
}

#[test]
fn adaptive_sampling_finds_what_sampling_every_centimetre_finds() {
    // Forward drives across a ditch and over a rock, at several frictions: striding up
    // to 4 cm where the pose changes smoothly must stop where (and why) the 1 cm
    // sampling stops, and agree on energy and margins. On open ground with task 1's 5 mm
    // noise it must need under half the terrain queries; on very rough
    // ground (2 cm noise under a 20 cm wheel), and where the drives spend most of their
    // travel at the ditch, the stride stays short and the cost must stay close to the
    // fixed sampling's.
    use areo_terrain::synth::{Feature, Noise, TerrainSpec};
    let terrain = |noise_m: f64, wall_deg: f64| {
        TerrainSpec {
            cols: 300,
            rows: 200,
            cell_m: 0.02,
            base_m: 0.0,
            seed: 3,
            noise: Some(Noise { amplitude_m: noise_m, wavelength_m: 0.5, octaves: 3, persistence: 0.5 }),
            features: vec![
                Feature::Ditch { from_m: (2.0, 0.0), to_m: (2.0, 4.0), width_m: 0.5, depth_m: 0.2, wall_deg },
                Feature::Rock { x_m: 1.2, y_m: 1.7, height_m: 0.08, width_m: 0.2 },
            ],
        }
        .build()
        .unwrap()
    };
    let p = lsr1();
    let ev = Evaluator::new(&p);
    let mut stops = 0;
    // (x, y, heading, μ) of the start.
    let drives = [
        (0.9, 1.7, 90.0, 0.8),
        (0.9, 2.0, 90.0, 0.8),
        (0.9, 2.4, 90.0, 0.5),
        (0.9, 1.7, 90.0, 0.4),
        (0.9, 2.2, 90.0, 0.3),
    ];
    // Open ground west of the ditch and north of the rock: ten drives north.
    let open = [(0.5, 2.3, 0.0, 0.6), (0.8, 2.3, 0.0, 0.6)];
    for (dem, cases, modules, cost_bound) in [
        (terrain(0.005, 70.0), &drives[..], 25, 1.2),
        (terrain(0.02, 45.0), &drives[..], 25, 1.25),
        (terrain(0.005, 70.0), &open[..], 10, 0.5),
    ] {
        let mut queries = [0usize; 2];
        for &(x0, y, heading, mu) in cases {
            let mut runs = Vec::new();
            for (k, coarse) in [1usize, 4].into_iter().enumerate() {
                let (steps, stop, asked) = forward_drives(&ev, &dem, (x0, y, heading, mu), coarse, modules);
                queries[k] += asked;
                runs.push((steps, stop));
            }
            let ((fine, fine_stop), (coarse, coarse_stop)) = (&runs[0], &runs[1]);
            same_modules(fine, coarse, &format!("y {y} μ {mu}"));
            match (fine_stop, coarse_stop) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    stops += 1;
                    // The same limit at the same sample (the margin carried along may
                    // differ in its last digits: the poses were warm-started from
                    // different places).
                    let kind = |f: &areo_rover::motion::MotionFailure| match f {
                        areo_rover::motion::MotionFailure::Violation(Violation::Forces { side, failure, .. }) => {
                            format!("forces {side} {failure:?}")
                        }
                        other => format!("{other:?}"),
                    };
                    assert_eq!(kind(&a.failure), kind(&b.failure), "y {y} μ {mu}");
                    assert!((a.progress - b.progress).abs() < 1e-12, "y {y} μ {mu}: {} vs {}", a.progress, b.progress);
                }
                _ => panic!("y {y} μ {mu}: one sampling stopped, the other did not: {fine_stop:?} {coarse_stop:?}"),
            }
        }
        let ratio = queries[1] as f64 / queries[0] as f64;
        assert!(ratio < cost_bound, "terrain queries fine {} vs adaptive {} ({ratio:.2})", queries[0], queries[1]);
    }
    assert!(stops >= 2, "some drives stop at the ditch: {stops}");
}

#[test]
fn a_module_with_nothing_to_act_on_still_spends_its_time_and_hotel_energy() {
    let p = lsr1();
    let ev = Evaluator::new(&p);
    let flat = Plane { z0: 0.0, gx: 0.0, gy: 0.0 };
    let motion = Motion::new(&ev, 0.6);
    let start = RoverState::new(&ev, 0.0, 0.0, 0.0);
    let act = &p.activities;
    // (module, why it has nothing to do, its time, its load beyond hotel power)
    let cases = [
        (Module::Grasp, MotionFailure::NoSample, act.grasp_s, act.grasp_w),
        (Module::Release, MotionFailure::NotHolding, act.grasp_s, act.grasp_w),
        (Module::TurnToSample, MotionFailure::NothingToTurnTo, act.turn_to_sample_deg / p.turn_rate_deg_s, 0.0),
        (Module::TurnFromSample, MotionFailure::NothingToTurnTo, act.turn_to_sample_deg / p.turn_rate_deg_s, 0.0),
    ];
    for (m, why, seconds, load_w) in cases {
        assert_eq!(motion.run(&flat, &start, m, &[]).unwrap_err().failure, why, "{m:?}");
        let idle = motion.idle(&start, m).unwrap();
        assert!((idle.duration_s - seconds).abs() < 1e-12, "{m:?}");
        let wh = (p.hotel_power_w + load_w) * seconds / 3600.0;
        assert!((idle.energy.net_wh() - wh).abs() < 1e-12, "{m:?}: {} Wh", idle.energy.net_wh());
        assert!((start.battery_wh - idle.state.battery_wh - wh).abs() < 1e-12);
        assert_eq!((idle.state.x, idle.state.heading, idle.state.arm), (start.x, start.heading, start.arm));
    }
    // An arm move out of reach: 2 cm at the tool speed.
    let far = RoverState { arm: ArmState { tool_m: [0.84, 0.0, 0.42], payload_kg: 0.0 }, ..start };
    assert_eq!(motion.run(&flat, &far, Module::ArmForward, &[]).unwrap_err().failure, MotionFailure::ArmReach);
    let idle = motion.idle(&far, Module::ArmForward).unwrap();
    assert!((idle.duration_s - 0.02 / p.arm.tool_speed_m_s).abs() < 1e-12);
}

#[test]
fn a_grasp_reaches_down_by_inverse_kinematics_and_pays_for_lifting() {
    let p = lsr1();
    let ev = Evaluator::new(&p);
    let flat = Plane { z0: 0.0, gx: 0.0, gy: 0.0 };
    let motion = Motion::new(&ev, 0.6);
    let start = RoverState::new(&ev, 0.0, 0.0, 0.0);
    // Straight ahead on flat ground, 0.6 m from the reference point: the tool goes to
    // (0.6, 0, gripper) in the body frame and back to the stowed position.
    let site = SampleSite { id: 3, x: 0.0, y: 0.6, mass_kg: 0.15 };
    let step = motion.run(&flat, &start, Module::Grasp, &[site]).unwrap();
    assert_eq!(step.grasped, Some(3));
    assert_eq!(step.state.arm.tool_m, start.arm.tool_m, "back to the stowed position");
    assert_eq!(step.state.arm.payload_kg, 0.15);
    let t = start.arm.tool_m;
    let target = [0.6, 0.0, areo_rover::motion::GRIPPER_M];
    let travel = (target[0] - t[0]).hypot(target[1] - t[1]).hypot(target[2] - t[2]);
    let seconds = 2.0 * travel / p.arm.tool_speed_m_s + p.activities.grasp_s;
    assert!((step.duration_s - seconds).abs() < 1e-9, "{} s vs {seconds} s", step.duration_s);
    // Work: lifting the arm's links back up and the sample from the ground to the
    // stowed tool, over the joints' efficiency (lowering is not recovered).
    let reached = ArmState { tool_m: target, payload_kg: 0.0 };
    let lift_arm = p.arm.mass_kg * (start.arm.arm_cg(&p).unwrap().z - reached.arm_cg(&p).unwrap().z);
    let lift_sample = 0.15 * (t[2] - target[2]);
    let work_wh = (lift_arm + lift_sample) * p.gravity_m_s2 / p.arm.efficiency / 3600.0;
    assert!((step.energy.mechanical_wh - work_wh).abs() < 1e-9, "{} vs {work_wh}", step.energy.mechanical_wh);
    // The reach moves the CG forward: the margin is found at the poses on the way.
    assert!(step.min_stability.is_some());
    // Out of reach (1.2 m ahead) or behind the rover: nothing to grasp.
    for (x, y) in [(0.0, 1.2), (0.0, -0.6)] {
        let far = SampleSite { id: 4, x, y, mass_kg: 0.1 };
        assert_eq!(motion.run(&flat, &start, Module::Grasp, &[far]).unwrap_err().failure, MotionFailure::NoSample);
    }
    // body_point inverts tool_world on a tilted pose.
    let tilted = Plane { z0: 0.3, gx: 0.12, gy: -0.2 };
    let s = RoverState::new(&ev, 1.0, 2.0, 0.7);
    let tool = motion.tool_world(&tilted, &s).unwrap();
    let back = motion.body_point(&tilted, &s, tool).unwrap();
    for k in 0..3 {
        assert!((back[k] - s.arm.tool_m[k]).abs() < 1e-9, "{back:?} vs {:?}", s.arm.tool_m);
    }
}

/// The 3-D Newton chain and the planar decomposition agree at four places on `g`:
/// Newton from the planar pose and cold reach the same pose, pitch, roll and bogie
/// angles within 0.5°, every axle within 1 cm.
pub(crate) fn assert_newton_agrees(p: &RoverParams, g: &impl Ground) {
    let k = Kinematics::new(p);
    for (x, y, h) in [(0.0, 0.0, 0.0), (0.7, -0.4, 0.9), (-1.1, 0.5, 2.2), (2.0, 1.0, 4.0)] {
        let planar = k.solve(g, x, y, h, None).unwrap();
        let newton = newton_pose(g, p, x, y, h, Some(&planar)).expect("Newton converges");
        let cold = newton_pose(g, p, x, y, h, None).expect("Newton converges cold");
        assert!((newton.pitch - cold.pitch).abs() < 1e-6 && (newton.roll - cold.roll).abs() < 1e-6);
        let tol = 0.5f64.to_radians();
        assert!((newton.pitch - planar.pitch).abs() < tol, "pitch {} vs {}", newton.pitch, planar.pitch);
        assert!((newton.roll - planar.roll).abs() < tol, "roll {} vs {}", newton.roll, planar.roll);
        for (s, side) in [&planar.left, &planar.right].into_iter().enumerate() {
            assert!(
                (newton.bogie[s] - side.bogie_angle).abs() < tol,
                "bogie {s}: {} vs {}",
                newton.bogie[s],
                side.bogie_angle
            );
        }
        for i in 0..6 {
            let (a, b) = (newton.axles[i], planar.wheels[i].axle);
            let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
            assert!(d < 0.01, "axle {i}: {a:?} vs {b:?}");
        }
    }
}
