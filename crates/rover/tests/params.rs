//! The shipped LSR-1 parameters: the geometry reproduces the reference's computed
//! values (shared/reference/rover_physics.md §2.1, rows 7–10 and 19–21), and bad files
//! are rejected with the field named.

use areo_rover::{Error, LSR1_RON, RoverParams};

fn near(got: f64, want: f64, tol: f64, what: &str) {
    assert!((got - want).abs() <= tol, "{what}: {got} vs {want}");
}

#[test]
fn lsr1_geometry_matches_the_reference() {
    let p = RoverParams::lsr1();
    let g = p.geometry();
    near(g.l3, 0.3430, 1e-4, "l3");
    near(g.l4, 0.2058, 1e-4, "l4");
    near(g.alpha2_0.to_degrees(), 30.96, 0.01, "alpha2_0");
    near(g.l1, 0.4830, 1e-4, "l1");
    near(g.l2, 0.3757, 1e-4, "l2");
    near(g.alpha1_0.to_degrees(), 26.57, 0.01, "alpha1_0");
    // √(l3² + l4²) is the front–middle spacing; √(l1² + l2²) = |PR|.
    near(g.l3.hypot(g.l4), 0.40, 1e-12, "F–M spacing");
    near(g.l1.hypot(g.l2), 0.6119, 1e-4, "|PR|");
    near(g.bogie_arms_m.0, 0.2332, 1e-4, "|PF|");
    near(g.bogie_arms_m.1, 0.2332, 1e-4, "|PM|");
    near(g.bogie_included.to_degrees(), 118.1, 0.05, "bogie included angle");
    near(g.rocker_arms_m.0, 0.2236, 1e-4, "|BP|");
    // The reference's table gives |BR| = 0.4472 (= √(0.40² + 0.20²)), which does not
    // follow from its own side view (B at z 0.32, rear axle at z 0.10): √(0.40² + 0.22²).
    near(g.rocker_arms_m.1, (0.40f64 * 0.40 + 0.22 * 0.22).sqrt(), 1e-12, "|BR|");
    // On flat ground tan α2 = l4 / l3.
    near(g.alpha2_0.tan(), g.l4 / g.l3, 1e-12, "tan alpha2");
}

#[test]
fn lsr1_drive_train_is_consistent() {
    let p = RoverParams::lsr1();
    // Stall ≈ 3.6 N·m ≥ the 3.5 N·m limit (≈ 0.5 m g r); k ≈ 1.1 W/(N·m)².
    near(p.drive.stall_torque_nm(), 3.6, 1e-9, "stall torque");
    near(p.drive.copper_loss_w_per_nm2(), 10.0 / 9.0, 1e-9, "copper-loss weight");
    near(p.wheel_torque_max_nm, 0.5 * p.mass_kg * p.gravity_m_s2 * p.wheel_radius_m, 0.1, "τmax ≈ m g r / 2");
    // Overall size from the paper: 1.00 m long, 0.70 m wide.
    near(p.axle_x_m.front - p.axle_x_m.rear + 2.0 * p.wheel_radius_m, 1.0, 1e-12, "length");
    near(p.track_m + p.wheel_width_m, 0.70, 1e-12, "width");
}

fn with(replace: &str, by: &str) -> String {
    assert!(LSR1_RON.contains(replace), "{replace}");
    LSR1_RON.replacen(replace, by, 1)
}

#[test]
fn bad_parameters_are_rejected_naming_the_field() {
    let cases = [
        ("gear_efficiency: 0.5", "gear_efficiency: 1.5", "drive.gear_efficiency"),
        ("wheel_radius_m: 0.10", "wheel_radius_m: -0.10", "wheel_radius_m"),
        ("bogie_pivot_m: (x: 0.20, z: 0.22)", "bogie_pivot_m: (x: 0.50, z: 0.22)", "bogie_pivot_m.x"),
        ("rocker_pivot_m: (x: 0.00, z: 0.32)", "rocker_pivot_m: (x: 0.00, z: 0.15)", "rocker_pivot_m.z"),
        ("wheel_torque_max_nm: 3.5", "wheel_torque_max_nm: 9.0", "wheel_torque_max_nm"),
        (
            "axle_x_m: (front: 0.40, middle: 0.00, rear: -0.40)",
            "axle_x_m: (front: 0.40, middle: 0.30, rear: -0.40)",
            "axle_x_m",
        ),
    ];
    for (from, to, field) in cases {
        let err = RoverParams::parse(&with(from, to), "test.ron").unwrap_err();
        match &err {
            Error::Invalid { field: f, .. } => assert!(f.starts_with(field), "{to}: {err}"),
            other => panic!("{to}: {other}"),
        }
        assert!(err.to_string().contains("test.ron"));
    }
    // Unknown fields and syntax errors carry a position.
    let err = RoverParams::parse(&with("hotel_power_w", "hotel_powr_w"), "test.ron").unwrap_err();
    assert!(matches!(err, Error::Syntax { line, .. } if line > 1), "{err}");
    assert!(err.to_string().contains("hotel_powr_w"));
}

#[test]
fn an_assumed_parameter_is_set_and_validated_like_a_file() {
    use areo_rover::{Assumed, RoverParams};
    let lsr1 = RoverParams::lsr1();
    let higher = lsr1.with_assumed(Assumed::CgHeightM, 0.31).unwrap();
    assert_eq!(higher.cg_m.z, 0.31);
    assert_eq!(higher.bogie_limit_deg, lsr1.bogie_limit_deg);
    assert_eq!(lsr1.with_assumed(Assumed::BogieLimitDeg, 75.0).unwrap().bogie_limit_deg, 75.0);
    // Out of range: refused with the field's name, as in a file.
    let e = lsr1.with_assumed(Assumed::BogiePivotHeightM, 0.05).unwrap_err().to_string();
    assert!(e.contains("bogie_pivot_m.z") && e.contains("bogie_pivot_m.z = 0.05"), "{e}");
    let e = lsr1.with_assumed(Assumed::ArmMassKg, -1.0).unwrap_err().to_string();
    assert!(e.contains("arm.mass_kg"), "{e}");
}
