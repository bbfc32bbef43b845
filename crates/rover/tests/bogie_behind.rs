//! The rocker-bogie with its bogie behind (MER, MSL): the planar solver and the force
//! balance handle it as the mirror image of the paper's layout. These tests check it
//! against statics and geometry worked by hand in the rover's own frame, against the
//! 3-D Newton chain (built directly, without a mirror image), and against the paper's
//! layout turned end for end and driven the other way.

use areo_rover::arm::ArmState;
use areo_rover::evaluation::{Conditions, Evaluator, Place};
use areo_rover::kinematics::Kinematics;
use areo_rover::{Layout, RoverParams};
use areo_terrain::Ground;
use areo_terrain::analytic::{Plane, Wall};

fn mer() -> RoverParams {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/params/mer.ron");
    RoverParams::load(std::path::Path::new(path)).expect("the shipped MER-class file is valid")
}

/// The LSR-1 turned end for end: every body-frame x negated (the arm too), so its bogie
/// is behind. Physically the same rover facing the other way.
fn lsr1_turned() -> RoverParams {
    let mut p = RoverParams::lsr1();
    let a = p.axle_x_m;
    (p.axle_x_m.front, p.axle_x_m.middle, p.axle_x_m.rear) = (-a.rear, -a.middle, -a.front);
    p.bogie_pivot_m.x = -p.bogie_pivot_m.x;
    p.rocker_pivot_m.x = -p.rocker_pivot_m.x;
    p.cg_m.x = -p.cg_m.x;
    p.arm.shoulder_m.x = -p.arm.shoulder_m.x;
    p.arm.stowed_tool_m.x = -p.arm.stowed_tool_m.x;
    p.validate("lsr1 turned").unwrap();
    p
}

struct F<G: Fn(f64, f64) -> f64>(G);
impl<G: Fn(f64, f64) -> f64> Ground for F<G> {
    fn height(&self, x: f64, y: f64) -> Option<f64> {
        Some((self.0)(x, y))
    }
    fn normal(&self, _: f64, _: f64) -> Option<[f64; 3]> {
        Some([0.0, 0.0, 1.0])
    }
}

#[test]
fn the_shipped_mer_file_has_its_bogie_behind() {
    let p = mer();
    assert_eq!(p.layout(), Layout::BogieRear);
    assert_eq!(RoverParams::lsr1().layout(), Layout::BogieFront);
    // A rocker pivot outside the bogie pivot–front axle span is refused by name.
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/params/mer.ron")).unwrap();
    let bad = text.replace("rocker_pivot_m: (x: 0.00, z: 0.45)", "rocker_pivot_m: (x: -0.30, z: 0.45)");
    let e = RoverParams::parse(&bad, "mer-bad.ron").unwrap_err().to_string();
    assert!(e.contains("rocker_pivot_m.x") && e.contains("bogie pivot and the front axle"), "{e}");
    let bad = text.replace("bogie_pivot_m: (x: -0.185, z: 0.30)", "bogie_pivot_m: (x: -0.45, z: 0.30)");
    let e = RoverParams::parse(&bad, "mer-bad.ron").unwrap_err().to_string();
    assert!(e.contains("bogie_pivot_m.x") && e.contains("bogie behind"), "{e}");
}

#[test]
fn flat_ground_loads_follow_the_lever_rule_of_the_turned_chain() {
    // Worked by hand in the rover's frame: each side carries W/2 at x_G. The rocker
    // holds the front wheel (x_f) and the bogie pivot (x_p): N_f = W/2·(x_G − x_p)/(x_f
    // − x_p). The bogie splits the rest between the middle (x_m) and rear (x_r) wheels
    // by the lever rule about x_p.
    for xg in [0.0, 0.06, -0.08] {
        let mut p = mer();
        p.cg_m.x = xg;
        let ev = Evaluator::new(&p);
        let e = ev
            .evaluate(
                &Plane { z0: 0.5, gx: 0.0, gy: 0.0 },
                Place { x: 1.0, y: 2.0, heading: 0.4 },
                &ArmState::stowed(&p),
                &Conditions { mu: 0.5, direction: 0.0 },
                None,
            )
            .unwrap();
        // The stowed arm moves the system CG forward of x_G.
        let (_, cg) = ArmState::stowed(&p).system_mass_cg(&p).unwrap();
        let (a, xp) = (p.axle_x_m, p.bogie_pivot_m.x);
        let half = e.weight_n / 2.0;
        let nf = half * (cg.x - xp) / (a.front - xp);
        let bogie = half - nf;
        let want = [nf, bogie * (xp - a.rear) / (a.middle - a.rear), bogie * (a.middle - xp) / (a.middle - a.rear)];
        for side in &e.sides {
            for (n, w) in side.normal_n.iter().zip(want) {
                assert!((n - w).abs() < 1e-6 * e.weight_n, "x_G {xg}: {:?} vs {want:?}", side.normal_n);
            }
            assert!(side.traction_n.iter().all(|t| t.abs() < 1e-9));
        }
        // Front wheels first in the pose too: the left front wheel is the one ahead.
        let (fx, fy) = e.pose.forward();
        let ahead = |w: [f64; 3]| (w[0] - 1.0) * fx + (w[1] - 2.0) * fy;
        assert!((ahead(e.pose.wheels[0].axle) - a.front).abs() < 1e-6);
        assert!((ahead(e.pose.wheels[5].axle) - a.rear).abs() < 1e-6);
    }
}

#[test]
fn a_step_under_the_front_wheels_turns_the_rocker_not_the_bogie() {
    // Heading east, the front wheels on a 0.10 m step, the middle and rear wheels on
    // the ground below: the bogie (middle, rear) stays level, so its pivot stays put and
    // the rocker turns about it until the front axle is 0.10 m higher. The body (the
    // mean of two equal rockers) pitches by that turn; each bogie sits at minus it
    // relative to its rocker.
    let p = mer();
    let (a, r) = (p.axle_x_m, p.wheel_radius_m);
    let h = 0.10;
    let g = Wall { x_step: 0.20, low_m: 0.0, high_m: h };
    let pose = Kinematics::new(&p).solve(&g, 0.0, 0.0, std::f64::consts::FRAC_PI_2, None).unwrap();
    let (dx, dz) = (a.front - p.bogie_pivot_m.x, r - p.bogie_pivot_m.z);
    let len = dx.hypot(dz);
    let turn = ((dz + h) / len).asin() - (dz / len).asin();
    assert!(turn > 0.15, "a real rotation: {turn}");
    assert!((pose.pitch - turn).abs() < 1e-5, "pitch {} vs {turn}", pose.pitch);
    for side in [&pose.left, &pose.right] {
        assert!((side.rocker_pitch - turn).abs() < 1e-5);
        assert!((side.bogie_angle + turn).abs() < 1e-5, "{} vs {}", side.bogie_angle, -turn);
        assert!((side.axles[0].1 - (h + r)).abs() < 1e-6, "front axle on top: {:?}", side.axles);
        assert!((side.axles[1].1 - r).abs() < 1e-6 && (side.axles[2].1 - r).abs() < 1e-6);
        // The front wheel is ahead (s > 0) and the rear behind, in the rover's own frame.
        assert!(side.axles[0].0 > 0.3 && side.axles[2].0 < -0.3, "{:?}", side.axles);
    }
    assert!(pose.roll.abs() < 1e-9);
    assert!(pose.contact_error_m(&g, r) < 0.005, "{}", pose.contact_error_m(&g, r));
    // The same step under the rear wheels only (heading west onto it backward) turns
    // the bogie instead: the rear axle 0.10 m up about the bogie pivot.
    // Heading west with the middle axles at x = 0.02: the rear axle is at 0.39, on top.
    let back = Kinematics::new(&p).solve(&g, 0.02, 0.0, -std::f64::consts::FRAC_PI_2, None).unwrap();
    let (dx, dz) = (a.middle - a.rear, 0.0);
    let bogie_turn = -(h / dx.hypot(dz)).asin();
    for side in [&back.left, &back.right] {
        assert!((side.axles[2].1 - (h + r)).abs() < 1e-6 && (side.axles[1].1 - r).abs() < 1e-6, "{:?}", side.axles);
        // The bogie turns (rear up: its forward end down) by asin(h / |middle − rear|)
        // relative to the ground; its pivot rises, so the rocker pitches nose down.
        assert!(
            (side.bogie_angle + side.rocker_pitch - bogie_turn).abs() < 1e-5,
            "{} {}",
            side.bogie_angle,
            side.rocker_pitch
        );
        assert!(side.rocker_pitch < -0.01, "{}", side.rocker_pitch);
    }
}

#[test]
fn newton_on_the_chain_built_as_it_is_agrees_with_the_mirrored_planar_solve() {
    let p = mer();
    let k = Kinematics::new(&p);
    assert!(k.mirrored());
    let g = F(|x: f64, y: f64| 0.09 * (1.1 * x).sin() * (0.9 * y).cos() + 0.12 * y);
    crate::physics::assert_newton_agrees(&p, &g);
}

#[test]
fn the_paper_rover_turned_end_for_end_and_driven_backward_is_the_same_physics() {
    // One body, two descriptions: the LSR-1 heading h driving forward, and the LSR-1
    // with every x negated (its bogie behind) heading h + π driving backward. The first
    // takes the direct path, the second the mirror-image path; they must agree wheel
    // for wheel on rough ground, warm-started along a drive.
    let (a, b) = (RoverParams::lsr1(), lsr1_turned());
    let (ea, eb) = (Evaluator::new(&a), Evaluator::new(&b));
    assert!(!ea.kinematics().mirrored() && eb.kinematics().mirrored());
    let g = F(|x: f64, y: f64| 0.05 * (2.3 * x).sin() * (1.7 * y).cos() + 0.15 * y + 0.04 * (3.1 * x * y).cos());
    let (arm_a, arm_b) = (ArmState::stowed(&a), ArmState::stowed(&b));
    let (mut warm_a, mut warm_b) = (None, None);
    for i in 0..25 {
        let h = 0.3 + 0.01 * i as f64;
        let (x, y) = (0.02 * i as f64 * h.sin(), 0.02 * i as f64 * h.cos());
        for (dir, mu) in [(1.0, 0.9), (-1.0, 0.9), (0.0, 0.6)] {
            let ra = ea.evaluate(
                &g,
                Place { x, y, heading: h },
                &arm_a,
                &Conditions { mu, direction: dir },
                warm_a.as_ref(),
            );
            let rb = eb.evaluate(
                &g,
                Place { x, y, heading: h + std::f64::consts::PI },
                &arm_b,
                &Conditions { mu, direction: -dir },
                warm_b.as_ref(),
            );
            let (ra, rb) = (ra.unwrap(), rb.unwrap());
            assert!((ra.pose.pitch + rb.pose.pitch).abs() < 1e-6, "{i}: pitch {} vs {}", ra.pose.pitch, rb.pose.pitch);
            assert!((ra.pose.roll + rb.pose.roll).abs() < 1e-6);
            assert!((ra.stability - rb.stability).abs() < 1e-6, "{i}: {} vs {}", ra.stability, rb.stability);
            assert!((ra.friction_used - rb.friction_used).abs() < 1e-6);
            let (na, nb) = (ra.normals_n(), rb.normals_n());
            let (ta, tb) = (ra.torques_nm(), rb.torques_nm());
            for w in 0..6 {
                // Wheel w of one is wheel 5 − w of the other (left front ↔ right rear).
                let d = ra.pose.wheels[w].axle.iter().zip(&rb.pose.wheels[5 - w].axle).map(|(p, q)| (p - q).abs());
                assert!(d.fold(0.0, f64::max) < 2e-5, "{i}: wheel {w}");
                assert!((na[w] - nb[5 - w]).abs() < 1e-3, "{i}, {dir}: normals {na:?} vs {nb:?}");
                assert!((ta[w] + tb[5 - w]).abs() < 1e-3, "{i}, {dir}: torques {ta:?} vs {tb:?}");
            }
            warm_a = Some(ra.pose);
            warm_b = Some(rb.pose);
        }
    }
}
