//! The ground under a drive: terrain classes (speed and power factors, their own slope
//! limits) and the rover's roll and pitch limits, against analytic durations and
//! energies, a Dijkstra on drive times, and tilted planes whose roll and pitch are known.

use std::sync::Arc;

use areo_mission::{
    Action, ActionConfig, ActionModel, Binding, ClassMap, Error, Mission, Objective, PlannerConfig, Start,
    TerrainClass, UNCLASSIFIED, World,
};
use areo_terrain::Dem;

use crate::common::*;

fn class(name: &str, speed: f64, power: f64) -> TerrainClass {
    TerrainClass { name: name.into(), speed_factor: speed, power_factor: power, max_slope_deg: None }
}

/// `world` with the class of cell (c, r) given by `f` (an index into `classes`, or
/// [`UNCLASSIFIED`]).
fn with_classes(mut world: World, classes: Vec<TerrainClass>, f: impl Fn(usize, usize) -> u8) -> World {
    let cells = (0..world.cells() as u32).map(|i| {
        let (c, r) = world.col_row(i);
        f(c, r)
    });
    world.set_ground(Arc::new(ClassMap::new(classes, cells.collect()).unwrap())).unwrap();
    world
}

/// Drives at any hour under a Sun fixed high in the sky, no camera rule.
fn any_hour() -> ActionConfig {
    let mut a = ActionConfig::default();
    a.drive.sun_in_camera = false;
    a
}

#[test]
fn a_class_at_half_speed_doubles_a_drive_and_its_power_factor_scales_locomotion() {
    let plain = fixed_sun_world(flat(6, 4, 20.0), 120.0, 60.0, 10.0);
    let sand =
        with_classes(fixed_sun_world(flat(6, 4, 20.0), 120.0, 60.0, 10.0), vec![class("sand", 0.5, 1.8)], |_, _| 0);
    let half =
        with_classes(fixed_sun_world(flat(6, 4, 20.0), 120.0, 60.0, 10.0), vec![class("sand", 0.5, 1.8)], |c, _| {
            if c >= 2 { 0 } else { UNCLASSIFIED }
        });
    let model = model(1e5, any_hour());
    let rover = model.rover();
    let (v, elec) = (rover.locomotor.speed_m_s, rover.electronics.high_w);
    let from = plain.cell(1, 1);
    for k in [2u8, 3] {
        let run = if k == 2 { 20.0 } else { 20.0 * std::f64::consts::SQRT_2 };
        let (a, b, m) = (
            model.drive_geometry(&plain, from, k).unwrap(),
            model.drive_geometry(&sand, from, k).unwrap(),
            model.drive_geometry(&half, from, k).unwrap(),
        );
        // Flat ground: run / v, twice that on sand, 1.5 times with one half on it.
        assert!((a.duration_s - run / v).abs() < 1e-9, "{a:?}");
        assert_eq!(b.duration_s, 2.0 * a.duration_s, "exactly twice as long");
        assert!((m.duration_s - 1.5 * a.duration_s).abs() < 1e-9 * a.duration_s, "{m:?}");
        assert!((m.from_time_share - 1.0 / 3.0).abs() < 1e-12, "{m:?}");
        // Locomotion energy per metre at any speed is m g c_rr / η: the same on sand at
        // half speed, times the power factor; the electronics run twice as long.
        let loco_wh =
            |g: &areo_mission::DriveGeometry, elec_s: f64| g.load_w * g.duration_s / 3600.0 - elec * elec_s / 3600.0;
        let flat_loco = loco_wh(&a, a.duration_s);
        let expected = rover.locomotor.mass_kg * rover.locomotor.gravity() * rover.locomotor.rolling_resistance * run
            / rover.locomotor.drive_efficiency
            / 3600.0;
        assert!((flat_loco - expected).abs() < 1e-9, "{flat_loco} vs {expected}");
        assert!((loco_wh(&b, b.duration_s) - 1.8 * flat_loco).abs() < 1e-9);
        assert!((loco_wh(&m, m.duration_s) - 1.4 * flat_loco).abs() < 1e-9);
    }
    // A whole plan on sand: the same cells, exactly twice the time.
    let start = Start { cell: plain.cell(0, 0), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let config = PlannerConfig { objective: Objective::Time, ..PlannerConfig::default() };
    let goal = [plain.cell(5, 3)];
    let (_m, p) = Mission::plan(&plain, &model, config.clone(), start, &goal).unwrap();
    let (_m, s) = Mission::plan(&sand, &model, config, start, &goal).unwrap();
    let cells = |p: &areo_mission::MissionPlan| p.waypoints.iter().map(|w| w.cell).collect::<Vec<_>>();
    assert_eq!(cells(&p), cells(&s));
    assert!((s.duration_s() - 2.0 * p.duration_s()).abs() < 1e-6, "{} vs {}", s.duration_s(), p.duration_s());
    assert!(s.waypoints.iter().all(|w| w.class == Some(0)));
    assert!(p.waypoints.iter().all(|w| w.class.is_none()));
}

/// The least total drive time from `from` to `to`, by a Dijkstra over the drives.
fn dijkstra_time(world: &World, model: &ActionModel, from: u32, to: u32) -> Option<f64> {
    let mut best = vec![f64::INFINITY; world.cells()];
    let mut open = std::collections::BinaryHeap::new();
    best[from as usize] = 0.0;
    open.push((std::cmp::Reverse(ordered_float::OrderedFloat(0.0)), from));
    while let Some((std::cmp::Reverse(ordered_float::OrderedFloat(t)), c)) = open.pop() {
        if c == to {
            return Some(t);
        }
        if t > best[c as usize] {
            continue;
        }
        for k in 0..8 {
            if let Ok(g) = model.drive_geometry(world, c, k) {
                let t1 = t + g.duration_s;
                if t1 < best[g.to as usize] {
                    best[g.to as usize] = t1;
                    open.push((std::cmp::Reverse(ordered_float::OrderedFloat(t1)), g.to));
                }
            }
        }
    }
    None
}

#[test]
fn the_fastest_plan_crosses_a_slow_band_where_a_dijkstra_on_drive_times_does() {
    // A band of sand (0.4 × speed) across a flat map, with a gap of hardpan faster than
    // the rover's own model (1.6 ×): the fastest plan takes the gap when it is worth
    // the detour, and its time is the Dijkstra's.
    let classes = vec![class("sand", 0.4, 1.8), class("hardpan", 1.6, 0.7)];
    for gap in [3usize, 9, 17] {
        let world =
            with_classes(fixed_sun_world(flat(20, 9, 20.0), 120.0, 60.0, 20.0), classes.clone(), |c, r| match (c, r) {
                (c, 3..=5) if c == gap => 1,
                (_, 3..=5) => 0,
                _ => UNCLASSIFIED,
            });
        let model = model(1e5, any_hour());
        let (from, to) = (world.cell(4, 0), world.cell(4, 8));
        let start = Start { cell: from, t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
        let config = PlannerConfig { objective: Objective::Time, ..PlannerConfig::default() };
        let (_m, plan) = Mission::plan(&world, &model, config, start, &[to]).unwrap();
        let reference = dijkstra_time(&world, &model, from, to).unwrap();
        assert!((plan.duration_s() - reference).abs() < 1e-6, "gap {gap}: {} vs {reference}", plan.duration_s());
        let through_gap = plan.waypoints.iter().any(|w| w.class == Some(1));
        // Straight across the sand: four drives off it, two on it and two half on it.
        let straight = (4.0 + 2.0 / 0.4 + 2.0 * (0.5 + 0.5 / 0.4)) * 20.0 / 0.3;
        assert!(plan.duration_s() <= straight + 1e-6);
        assert_eq!(through_gap, plan.duration_s() < straight - 1.0, "gap {gap}: {}", plan.duration_s());
        if gap == 3 {
            assert!(through_gap, "a gap next to the route is taken");
        }
        if gap == 17 {
            assert!(!through_gap, "a gap far off the route is not worth it");
        }
    }
}

#[test]
fn a_class_slope_limit_refuses_where_the_rovers_own_allows() {
    // A 12° ramp rising east: within Hyperion's 20°, above scree's 10°.
    let dem = Dem::from_fn(8, 5, 20.0, 20.0, |x, _| x * 12f64.to_radians().tan()).unwrap();
    let scree = TerrainClass { max_slope_deg: Some(10.0), ..class("scree", 1.0, 1.0) };
    let world =
        with_classes(
            fixed_sun_world(dem, 120.0, 60.0, 10.0),
            vec![scree],
            |c, _| if c >= 4 { 0 } else { UNCLASSIFIED },
        );
    let model = model(1e5, any_hour());
    assert!(model.drive_geometry(&world, world.cell(1, 2), 2).is_ok());
    assert_eq!(model.drive_geometry(&world, world.cell(3, 2), 2).unwrap_err(), Binding::Slope);
    let start = Start { cell: world.cell(1, 2), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    match Mission::plan(&world, &model, PlannerConfig::default(), start, &[world.cell(6, 2)]) {
        Err(Error::Unreachable { binding, proven, .. }) => assert_eq!((binding, proven), (Binding::Slope, true)),
        other => panic!("{other:?}"),
    }
}

/// A plane rising `deg` degrees toward the east.
fn east_ramp(deg: f64) -> World {
    let dem = Dem::from_fn(9, 9, 20.0, 20.0, move |x, _| x * deg.to_radians().tan()).unwrap();
    fixed_sun_world(dem, 120.0, 60.0, 10.0)
}

fn limited(roll: Option<f64>, up: Option<f64>, down: Option<f64>) -> ActionModel {
    let mut rover = rover(1e5);
    rover.locomotor.max_roll_deg = roll;
    rover.locomotor.max_pitch_up_deg = up;
    rover.locomotor.max_pitch_down_deg = down;
    ActionModel::new(rover, any_hour())
}

#[test]
fn a_drive_across_a_slope_steeper_than_max_roll_is_refused_while_straight_up_it_passes() {
    let world = east_ramp(15.0);
    let c = world.cell(4, 4);
    // Across the slope (north, south) the roll is the slope; up and down it, the pitch.
    let model = limited(Some(12.0), None, None);
    for (k, roll_sign) in [(0u8, 1.0), (4, -1.0)] {
        assert_eq!(model.drive_geometry(&world, c, k).unwrap_err(), Binding::Roll, "heading {k}");
        let (pitch, roll) = world.drive_attitude_deg(c, k).unwrap();
        assert!(pitch.abs() < 1e-9 && (roll - roll_sign * 15.0).abs() < 1e-4, "{pitch} {roll}");
    }
    let up = model.drive_geometry(&world, c, 2).unwrap();
    assert!((up.slope_deg - 15.0).abs() < 1e-5 && up.roll_deg.abs() < 1e-4, "{up:?}");
    // Diagonally the roll is asin(sin 15° · cos 45°) = 10.5°: under 12°.
    let diagonal = model.drive_geometry(&world, c, 1).unwrap();
    let expected = (15f64.to_radians().sin() * std::f64::consts::FRAC_1_SQRT_2).asin().to_degrees();
    assert!((diagonal.roll_deg.abs() - expected).abs() < 1e-4, "{diagonal:?} vs {expected}");
    // A goal straight north is reached by zig-zagging diagonals; with a 10° limit no
    // drive but east and west is allowed, and the roll is named.
    let start = Start { cell: world.cell(4, 8), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = [world.cell(4, 0)];
    let (_m, plan) = Mission::plan(&world, &model, PlannerConfig::default(), start, &goal).unwrap();
    assert!(plan.waypoints.iter().all(|w| !matches!(w.action, Some(Action::Drive(0 | 4)))));
    assert!(plan.waypoints.iter().filter_map(|w| w.drive_attitude_deg).all(|(_, roll)| roll.abs() <= 12.0));
    match Mission::plan(&world, &limited(Some(10.0), None, None), PlannerConfig::default(), start, &goal) {
        Err(Error::Unreachable { binding, proven, .. }) => assert_eq!((binding, proven), (Binding::Roll, true)),
        other => panic!("{other:?}"),
    }
    // Without a roll limit the plan drives straight north.
    let (_m, free) = Mission::plan(&world, &limited(None, None, None), PlannerConfig::default(), start, &goal).unwrap();
    assert_eq!(free.action_counts().0, 8);
}

#[test]
fn pitch_limits_refuse_up_and_down_the_slope_separately() {
    let world = east_ramp(15.0);
    let c = world.cell(4, 4);
    let climb_only = limited(None, Some(20.0), Some(10.0));
    assert!(climb_only.drive_geometry(&world, c, 2).is_ok(), "up 15° under 20°");
    assert_eq!(climb_only.drive_geometry(&world, c, 6).unwrap_err(), Binding::Pitch, "down 15° over 10°");
    let descend_only = limited(None, Some(10.0), Some(20.0));
    assert_eq!(descend_only.drive_geometry(&world, c, 2).unwrap_err(), Binding::Pitch);
    assert!(descend_only.drive_geometry(&world, c, 6).is_ok());
    // A goal up the ramp with a 10° climbing limit: diagonals pitch 10.7°, so no way up.
    let start = Start { cell: world.cell(0, 4), t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    match Mission::plan(&world, &descend_only, PlannerConfig::default(), start, &[world.cell(8, 4)]) {
        Err(Error::Unreachable { binding, proven, .. }) => assert_eq!((binding, proven), (Binding::Pitch, true)),
        other => panic!("{other:?}"),
    }
}
