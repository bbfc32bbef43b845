use super::*;
use areo_terrain::analytic::{Plane, Wall};

fn lsr1() -> RoverParams {
    RoverParams::lsr1()
}

#[test]
fn the_body_frame_turns_with_heading_pitch_and_roll() {
    let g = Plane { z0: 0.0, gx: 0.0, gy: 0.0 };
    let mut p = pose(&g, &lsr1(), 10.0, 20.0, 0.0).unwrap();
    (p.body, p.heading) = ([10.0, 20.0, 5.0], std::f64::consts::FRAC_PI_2);
    let near = |a: [f64; 3], b: [f64; 3]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12);
    (p.pitch, p.roll) = (0.0, 0.0);
    // Facing east: forward is east, left is north.
    assert!(near(p.body_to_map([1.0, 0.0, 0.0]), [11.0, 20.0, 5.0]));
    assert!(near(p.body_to_map([0.0, 1.0, 0.0]), [10.0, 21.0, 5.0]));
    // Nose up 90°: forward points up; left side up 90°: left points up.
    p.pitch = std::f64::consts::FRAC_PI_2;
    assert!(near(p.body_to_map([1.0, 0.0, 0.0]), [10.0, 20.0, 6.0]));
    p.pitch = 0.0;
    p.roll = std::f64::consts::FRAC_PI_2;
    assert!(near(p.body_to_map([0.0, 1.0, 0.0]), [10.0, 20.0, 6.0]));
    // Any pose: map_to_body undoes body_to_map.
    (p.heading, p.pitch, p.roll) = (0.7, -0.3, 0.2);
    for rel in [[0.3, -0.2, 0.5], [-1.0, 0.4, -0.1]] {
        assert!(near(p.map_to_body(p.body_to_map(rel)), rel));
    }
}

#[test]
fn flat_ground_gives_the_nominal_pose() {
    let g = Plane { z0: 2.0, gx: 0.0, gy: 0.0 };
    let p = pose(&g, &lsr1(), 10.0, 5.0, 37.0).unwrap();
    assert!(p.pitch.abs() < 1e-9 && p.roll.abs() < 1e-9);
    for side in [&p.left, &p.right] {
        assert!((side.rocker_alpha.to_degrees() - 26.565).abs() < 0.01, "{}", side.rocker_alpha.to_degrees());
        assert!((side.bogie_alpha.to_degrees() - 30.964).abs() < 0.01);
        // The front axle 0.40 m ahead, the rear 0.40 m behind, contacts below.
        assert!((side.axles[0].0 - 0.40).abs() < 1e-6 && (side.axles[2].0 + 0.40).abs() < 1e-6);
        for (a, c) in side.axles.iter().zip(&side.contacts) {
            assert!((a.0 - c.0).abs() < 1e-9 && (a.1 - c.1 - 0.10).abs() < 1e-9);
        }
    }
    assert!((p.body[2] - 2.32).abs() < 1e-6, "rocker pivot 0.32 m above the ground");
    assert!(p.contact_error_m(&g, 0.1) < 1e-3);
    // Six contacts: the middle wheels at (x, y) ± (w/2) left of the heading.
    let h = 37f64.to_radians();
    let ml = p.wheels[1].contact;
    assert!((ml[0] - (10.0 - 0.3 * h.cos())).abs() < 1e-9 && (ml[1] - (5.0 + 0.3 * h.sin())).abs() < 1e-9);
}

#[test]
fn a_uniform_slope_pitches_the_body_by_the_slope() {
    // Heading north up a 10° slope: pitch = 10°, links unchanged relative to the body.
    let g = Plane { z0: 0.0, gx: 0.0, gy: 10f64.to_radians().tan() };
    let p = pose(&g, &lsr1(), 0.0, 0.0, 0.0).unwrap();
    assert!((p.pitch.to_degrees() - 10.0).abs() < 0.01, "{}", p.pitch.to_degrees());
    assert!(p.roll.abs() < 1e-9);
    assert!(((p.left.bogie_alpha + p.pitch).to_degrees() - 30.964).abs() < 0.02, "α relative to the body");
    assert!(p.left.bogie_angle.abs() < 1e-6);
    assert!(p.contact_error_m(&g, 0.1) < 0.004, "{}", p.contact_error_m(&g, 0.1));
    for gamma in p.left.gamma {
        assert!((gamma.to_degrees() - 10.0).abs() < 0.5, "contact angle = slope: {}", gamma.to_degrees());
    }
}

#[test]
fn a_side_slope_rolls_the_body_and_narrows_the_footprint() {
    // Heading north on ground rising to the west (left): roll = +φ, and the wheel
    // planes sit ±(w/2)·cos φ from the centre line.
    let g = Plane { z0: 0.0, gx: -15f64.to_radians().tan(), gy: 0.0 };
    let p = pose(&g, &lsr1(), 0.0, 0.0, 0.0).unwrap();
    assert!((p.roll.to_degrees() - 15.0).abs() < 1e-4, "{}", p.roll.to_degrees());
    assert!(p.pitch.abs() < 1e-9);
    assert!((p.left.origin.0 + 0.3 * 15f64.to_radians().cos()).abs() < 1e-6);
}

#[test]
fn the_front_wheel_climbs_a_step_and_the_differential_averages() {
    // A 0.15 m step 0.25 m ahead of the middle wheels, across both sides: the front
    // axles ride on top, 0.15 m higher; the bogies rotate by asin(0.15/0.40).
    let g = Wall { x_step: 0.0, low_m: 0.0, high_m: 0.15 };
    let p = pose(&g, &lsr1(), -0.25, 0.0, 90.0).unwrap();
    let f = p.left.axles[0];
    assert!((f.1 - (0.10 + 0.15)).abs() < 1e-3, "front axle on top: {f:?}");
    let m = p.left.axles[1];
    assert!(((f.1 - m.1) / 0.40 - (0.15f64 / 0.40)).abs() < 1e-3);
    assert!(p.pitch > 0.0, "nose up");
    assert!(p.contact_error_m(&g, 0.1) < 0.004, "{}", p.contact_error_m(&g, 0.1));
    // Only the left side on the step: the body pitches by half the left rocker pitch.
    struct LeftStep;
    impl Ground for LeftStep {
        fn height(&self, x: f64, y: f64) -> Option<f64> {
            Some(if x >= 0.0 && y > 0.0 { 0.15 } else { 0.0 })
        }
        fn normal(&self, _: f64, _: f64) -> Option<[f64; 3]> {
            Some([0.0, 0.0, 1.0])
        }
    }
    let q = pose(&LeftStep, &lsr1(), -0.25, 0.0, 90.0).unwrap();
    let body_axis = q.left.rocker_pitch / 2.0;
    assert!((q.pitch - (q.roll.cos() * body_axis.sin()).asin()).abs() < 1e-9, "{} {}", q.pitch, body_axis);
    assert!(q.right.rocker_pitch.abs() < 1e-9);
    assert!(q.roll > 0.0, "heading east, the left side is north: on the step, up");
}

#[test]
fn a_wheel_against_a_wall_sits_on_its_face() {
    // A 0.30 m wall (taller than r) just ahead: the front axle rests against the
    // face, r from it, with a horizontal contact normal (γ = 90°).
    let g = Wall { x_step: 0.0, low_m: 0.0, high_m: 0.30 };
    let p = pose(&g, &lsr1(), -0.45, 0.0, 90.0).unwrap();
    let f = p.left.axles[0];
    assert!((f.0 - 0.35).abs() < 1e-6, "axle r behind the wall: {f:?}");
    assert!((p.left.gamma[0].to_degrees() - 90.0).abs() < 1e-6);
    assert!(p.contact_error_m(&g, 0.1) < 0.004);
}

#[test]
fn warm_starts_give_the_cold_answer() {
    let g = areo_terrain::analytic::Paraboloid { a: 0.15, b: -0.08 };
    let k = Kinematics::new(&lsr1());
    let mut prev = k.solve(&g, 0.3, -0.2, 0.4, None).unwrap();
    for i in 1..20 {
        let x = 0.3 + 0.01 * i as f64;
        let warm = k.solve(&g, x, -0.2, 0.4, Some(&prev)).unwrap();
        let cold = k.solve(&g, x, -0.2, 0.4, None).unwrap();
        for (a, b) in warm.wheels.iter().zip(&cold.wheels) {
            for j in 0..3 {
                assert!((a.axle[j] - b.axle[j]).abs() < 2e-5, "{i}: {a:?} vs {b:?}");
            }
        }
        prev = warm;
    }
}

#[test]
fn a_warm_start_that_loses_a_step_edge_gives_the_cold_answer() {
    // A step exactly one wheel radius high, climbed 1 cm at a time: the warm start's
    // pinned rim sample loses the edge part way (the solver then retries cold), so
    // every pose must equal the cold one and none may be refused.
    let g = Wall { x_step: 0.0, low_m: 0.0, high_m: 0.10 };
    let k = Kinematics::new(&lsr1());
    let mut prev = None;
    for i in 0..120 {
        let x = -0.55 + 0.01 * i as f64;
        let warm = k.solve(&g, x, 0.0, std::f64::consts::FRAC_PI_2, prev.as_ref()).expect("a pose exists");
        let cold = k.solve(&g, x, 0.0, std::f64::consts::FRAC_PI_2, None).unwrap();
        for (a, b) in warm.wheels.iter().zip(&cold.wheels) {
            assert!((0..3).all(|j| (a.axle[j] - b.axle[j]).abs() < 2e-5), "{i}: {a:?} vs {b:?}");
        }
        prev = Some(warm);
    }
}

#[test]
fn the_middle_right_anchor_moves_the_rover_by_half_a_track() {
    let g = Plane { z0: 0.0, gx: 0.0, gy: 0.0 };
    let mut k = Kinematics::new(&lsr1());
    k.anchor = Anchor::MiddleRight;
    let p = k.solve(&g, 1.0, 2.0, 0.0, None).unwrap();
    let mr = p.wheels[4].contact;
    assert!((mr[0] - 1.0).abs() < 1e-9 && (mr[1] - 2.0).abs() < 1e-9);
    assert!((p.body[0] - 0.7).abs() < 1e-9, "body half a track to the left (west)");
}

#[test]
fn joint_limits_and_missing_ground_are_reported() {
    struct Island;
    impl Ground for Island {
        fn height(&self, x: f64, _: f64) -> Option<f64> {
            (x.abs() < 0.3).then_some(0.0)
        }
        fn normal(&self, _: f64, _: f64) -> Option<[f64; 3]> {
            Some([0.0, 0.0, 1.0])
        }
    }
    assert_eq!(pose(&Island, &lsr1(), 0.0, 0.0, 90.0), Err(KinematicsFailure::OffTerrain));
    // A 0.40 m step under the front wheels only needs the bogie past 45°.
    let g = Wall { x_step: 0.25, low_m: 0.0, high_m: 0.40 };
    assert_eq!(pose(&g, &lsr1(), 0.0, 0.0, 90.0), Err(KinematicsFailure::JointLimit));
}
