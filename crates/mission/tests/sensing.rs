//! Re-planning after what the rover senses equals planning afresh on the updated map.
//!
//! The map and the true terrain differ by bumps and pits that change elevation, slope
//! and the horizon (so light and shadow too). Random patches of the truth are sensed
//! one after another (seeded); after each, the kept graphs are repaired
//! ([`Mission::replan`]) and a fresh mission is planned on the same, updated map. With
//! quantised actions and classes as fine as the quanta the search is exact, so the two
//! costs must be equal — and the repair must not expand more than the fresh search
//! (within 1 % where sensing made drives dearer: the kept 2-D bound is then a little
//! looser than the fresh search's).

use areo_mission::{
    ActionConfig, Classes, Mission, MissionPlan, PathLength, PlannerConfig, Resolution, SearchMode, Start, World,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common::*;

fn ground(cols: usize, rows: usize, bumps: &[(f64, f64, f64)]) -> areo_terrain::Dem {
    areo_terrain::Dem::from_fn(cols, rows, 20.0, 20.0, |x, y| {
        let base = 3.0 * (x / 37.0).sin() + 2.0 * (y / 23.0).cos() + 0.02 * x;
        base + bumps.iter().map(|&(bx, by, h)| h * (-((x - bx).powi(2) + (y - by).powi(2)) / 1600.0).exp()).sum::<f64>()
    })
    .unwrap()
}

fn quantised() -> ActionConfig {
    quantised_actions(1200.0)
}

fn planner_config() -> PlannerConfig {
    PlannerConfig {
        actions: quantised(),
        path_length: PathLength::Distance,
        max_wait_s: Some(3600.0),
        search: SearchMode::Approximate(Classes {
            resolution: Resolution { time_s: 60.0, energy_wh: None },
            goal_times: 8,
            segment_starts: 4,
            ..Classes::default()
        }),
        ..PlannerConfig::default()
    }
}

/// The map (no bumps) and the truth (bumps and a pit), both with 16-sector horizons.
fn worlds(cols: usize, rows: usize) -> (World, World) {
    let bumps = [(150.0, 110.0, 12.0), (300.0, 200.0, -8.0), (420.0, 90.0, 15.0), (230.0, 300.0, 10.0)];
    (mars_world(ground(cols, rows, &[]), 14.0, Some(16)), mars_world(ground(cols, rows, &bumps), 14.0, Some(16)))
}

/// Senses `patches` random discs of the truth one after another, re-planning after
/// each, and checks every re-plan against a fresh plan. Returns the number of patches
/// that changed the map.
fn check(seed: u64, goals: &[(usize, usize)], battery_wh: f64) -> (usize, MissionPlan) {
    let (cols, rows) = (26, 18);
    let (map, truth) = worlds(cols, rows);
    let model = model(2000.0, quantised());
    let start = Start { cell: map.cell(1, 1), t_min: 0.0, t_max: 600.0, energy_wh: battery_wh };
    let goals: Vec<u32> = goals.iter().map(|&(c, r)| map.cell(c, r)).collect();
    let (mut mission, first) = Mission::plan(&map, &model, planner_config(), start, &goals).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut effective = 0;
    for patch in 0..6 {
        let (c, r) = (rng.random_range(0..cols), rng.random_range(0..rows));
        let radius: usize = rng.random_range(1..=3);
        let mut cells = Vec::new();
        for rr in r.saturating_sub(radius)..(r + radius + 1).min(rows) {
            for cc in c.saturating_sub(radius)..(c + radius + 1).min(cols) {
                cells.push(map.cell(cc, rr));
            }
        }
        let changed = map.sense(&truth, &cells).unwrap();
        if changed.is_empty() {
            continue;
        }
        effective += 1;
        let replanned = mission.replan(&changed).unwrap();
        let (_, fresh) = Mission::plan(&map, &model, planner_config(), start, &goals).unwrap();
        assert!(
            (replanned.cost - fresh.cost).abs() < 1e-6,
            "seed {seed}, patch {patch} at ({c}, {r}): re-plan {} vs fresh {}",
            replanned.cost,
            fresh.cost
        );
        assert_eq!(replanned.waypoints.last().map(|w| w.cell), goals.last().copied());
        // Within 1 %: where sensing made drives dearer, the kept 2-D bound keeps the
        // old (lower) cost of those drives — still a bound, a little looser than the
        // fresh search's, which sees the new map (seed 21, patch 5: 52 228 against
        // 52 024).
        assert!(
            replanned.expansions * 100 <= fresh.expansions * 101,
            "seed {seed}, patch {patch}: the repair expanded {} nodes, a fresh plan {}",
            replanned.expansions,
            fresh.expansions
        );
    }
    (effective, first)
}

#[test]
fn single_goal_replans_after_sensed_terrain_equal_fresh_plans() {
    let mut effective = 0;
    for seed in 1..=4 {
        effective += check(seed, &[(23, 15)], 1500.0).0;
    }
    assert!(effective >= 12, "only {effective} patches changed the map");
}

#[test]
fn multi_goal_replans_after_sensed_terrain_equal_fresh_plans() {
    let mut effective = 0;
    for seed in 11..=13 {
        effective += check(seed, &[(12, 14), (23, 3)], 1500.0).0;
    }
    assert!(effective >= 8, "only {effective} patches changed the map");
}

#[test]
fn replans_with_a_binding_battery_equal_fresh_plans() {
    // A battery that barely suffices (the night allows no charging): the Pareto labels a
    // tight battery needs must survive repair too.
    let mut effective = 0;
    for seed in 21..=23 {
        let (n, first) = check(seed, &[(23, 15)], 160.0);
        effective += n;
        // It binds: the plan runs the battery to within 10 Wh of its floor (200 Wh), and
        // 30 Wh less at the start leaves no plan at all.
        assert!(first.min_battery_wh() < 210.0, "{}", first.min_battery_wh());
    }
    assert!(effective >= 8, "only {effective} patches changed the map");
    let (map, _) = worlds(26, 18);
    let start = Start { cell: map.cell(1, 1), t_min: 0.0, t_max: 600.0, energy_wh: 130.0 };
    let model = model(2000.0, quantised());
    let lean = Mission::plan(&map, &model, planner_config(), start, &[map.cell(23, 15)]);
    assert!(lean.is_err(), "30 Wh less should leave no plan");
}

#[test]
fn a_truth_sharing_the_maps_horizons_senses_and_lights_as_a_full_one() {
    let bumps = [(150.0, 110.0, 12.0), (300.0, 200.0, -8.0), (420.0, 90.0, 15.0), (230.0, 300.0, 10.0)];
    let map = mars_world(ground(26, 18, &[]), 14.0, Some(16));
    let full = mars_world(ground(26, 18, &bumps), 14.0, Some(16));
    let world_config = crate::common::config(14.0, Some(16));
    let shared = World::truth(ground(26, 18, &bumps), &world_config, &areo_ephemeris::Mars24, &map).unwrap();
    for t in (0..14).map(|h| f64::from(h) * 3600.0) {
        let sun = full.sun(t);
        for c in 0..full.cells() as u32 {
            assert_eq!(shared.lit(c, &sun), full.lit(c, &sun), "cell {c} at {t} s");
        }
    }
    // Sensing either truth changes a believed map the same way.
    let (a, b) = (mars_world(ground(26, 18, &[]), 14.0, Some(16)), mars_world(ground(26, 18, &[]), 14.0, Some(16)));
    let cells: Vec<u32> = (0..map.cells() as u32).collect();
    let (from_full, from_shared) = (a.sense(&full, &cells).unwrap(), b.sense(&shared, &cells).unwrap());
    assert_eq!(from_full, from_shared);
    assert!(from_full.len() > 50, "{} cells changed", from_full.len());
    for t in (0..14).map(|h| f64::from(h) * 3600.0) {
        let sun = a.sun(t);
        assert!((0..a.cells() as u32).all(|c| a.lit(c, &sun) == b.lit(c, &sun)));
    }
}

/// The cells within `radius` cells of `cell` (centre to centre).
fn disc(world: &World, cell: u32, radius: i64) -> Vec<u32> {
    let (c, r) = world.col_row(cell);
    let mut out = Vec::new();
    for dr in -radius..=radius {
        for dc in -radius..=radius {
            let (nc, nr) = (c as i64 + dc, r as i64 + dr);
            if dc * dc + dr * dr <= radius * radius
                && nc >= 0
                && nr >= 0
                && (nc as usize) < world.cols()
                && (nr as usize) < world.rows()
            {
                out.push(world.cell(nc as usize, nr as usize));
            }
        }
    }
    out
}

/// The map shows a gap in an east–west ridge; the truth closes it (the ridge leaves a
/// way round at its eastern end). Both over 14 h with 16-sector horizons.
fn ridge_worlds() -> (World, World) {
    let ridge = |gap: bool| {
        areo_terrain::Dem::from_fn(30, 24, 20.0, 20.0, move |x, y| {
            let base = 2.0 * (x / 37.0).sin() + 1.5 * (y / 23.0).cos();
            let on_ridge = (230.0..270.0).contains(&y) && x < 470.0 && !(gap && (250.0..330.0).contains(&x));
            base + if on_ridge { 60.0 } else { 0.0 }
        })
        .unwrap()
    };
    let map = mars_world(ridge(true), 14.0, Some(16));
    let truth =
        World::truth(ridge(false), &crate::common::config(14.0, Some(16)), &areo_ephemeris::Mars24, &map).unwrap();
    (map, truth)
}

#[test]
fn a_rover_that_finds_a_wall_replans_with_no_more_work_than_a_fresh_plan() {
    // The valley-detour situation at a small scale: the map shows a gap in a ridge, the
    // truth closes it; the rover drives, senses 2 cells around it after every action
    // and re-plans (plan extension + repair). Every re-plan — the wall's discovery
    // included — costs what the same problem searched from scratch on the updated map
    // costs, and expands at most 5 % more than that search.
    let (map, truth) = ridge_worlds();
    let model = model(2000.0, quantised());
    let start = Start { cell: map.cell(14, 21), t_min: 0.0, t_max: 600.0, energy_wh: 1500.0 };
    let goals = [map.cell(14, 2)];
    // What the rover sees before it sets off (the horizon there shows the closed gap).
    map.sense(&truth, &disc(&map, start.cell, 2)).unwrap();
    let (mut mission, mut plan) = Mission::plan(&map, &model, planner_config(), start, &goals).unwrap();
    assert!(
        plan.waypoints.iter().any(|w| (250.0..330.0).contains(&w.easting_m) && (230.0..270.0).contains(&w.northing_m))
    );
    let (mut cell, mut t, mut battery) = (start.cell, plan.waypoints[0].t_s, start.energy_wh);
    let (mut walls, mut steps, mut replanned, mut searched) = (0, 0, 0, 0);
    while let Some(action) = plan.waypoints.first().and_then(|w| w.action) {
        t = t.max(plan.waypoints[0].t_s);
        let exact = areo_mission::Perturbation::NONE;
        let (to, effect) = model.execute(&truth, action, cell, t, exact).unwrap();
        (cell, t, battery) = (to, t + effect.duration_s, effect.after(battery, model.capacity_wh()));
        let changed = map.sense(&truth, &disc(&map, cell, 2)).unwrap();
        let here = Start { cell, t_min: t, t_max: t, energy_wh: battery };
        plan = mission.advance(here, &changed).unwrap();
        // The same problem (goal instants, start) searched from scratch on the updated map.
        let fresh = mission.fresh().unwrap().expect("a fresh plan");
        assert!((plan.cost - fresh.cost).abs() < 1e-6, "step {steps}: re-plan {} vs fresh {}", plan.cost, fresh.cost);
        // A fresh search of a nearly finished trip is tiny, while a change beside the
        // goal (the backward search's root) costs a repair a few hundred expansions:
        // the comparison holds wherever the fresh search has real work to do.
        // (Within 5 %: a re-plan also drops the labels the rover's progress made
        // unreachable, and reopens what they had pruned.)
        if fresh.expansions >= 2000 {
            assert!(
                plan.expansions * 100 <= fresh.expansions * 105,
                "step {steps}: the re-plan expanded {}, a fresh plan {}",
                plan.expansions,
                fresh.expansions
            );
        }
        (replanned, searched) = (replanned + plan.expansions, searched + fresh.expansions);
        walls += usize::from(changed.iter().any(|&c| {
            let (x, y) = map.center(c);
            (250.0..330.0).contains(&x) && (230.0..270.0).contains(&y)
        }));
        steps += 1;
        assert!(steps < 400, "the rover never arrives");
    }
    assert_eq!(cell, goals[0]);
    assert!(walls > 0, "the rover never sensed the wall");
    // Over the whole trip re-planning did under a fifth of the fresh searches' work
    // (most of it at the wall's discovery).
    assert!(5 * replanned <= searched, "re-plans expanded {replanned}, fresh searches {searched}");
}

/// The ridge-and-gap walk of the test above at the shipped scenarios' settings: actions
/// not quantised (any duration, any energy), 20-minute time classes, energy exact or in
/// 25 Wh classes. Classes then merge different instants, which is where a kept graph
/// used to answer from its history: every re-plan must still cost exactly what a fresh
/// search of the same problem costs.
fn walk_with_coarse_classes(energy_wh: Option<f64>) -> usize {
    let (map, truth) = ridge_worlds();
    let mut actions = ActionConfig { charge_s: 900.0, hibernate_s: 1800.0, ..ActionConfig::default() };
    actions.drive.daylight = false;
    actions.charge.direct_sun = false;
    let model = model(2000.0, actions);
    let config = PlannerConfig {
        actions: model.config().clone(),
        max_wait_s: Some(3600.0),
        search: SearchMode::Approximate(Classes {
            resolution: Resolution { time_s: 1200.0, energy_wh },
            goal_times: 8,
            segment_starts: 4,
            ..Classes::default()
        }),
        ..PlannerConfig::default()
    };
    let start = Start { cell: map.cell(14, 21), t_min: 0.0, t_max: 600.0, energy_wh: 1500.0 };
    let goals = [map.cell(26, 15), map.cell(14, 2)];
    map.sense(&truth, &disc(&map, start.cell, 2)).unwrap();
    let (mut mission, mut plan) = Mission::plan(&map, &model, config, start, &goals).unwrap();
    let (mut cell, mut t, mut battery) = (start.cell, plan.waypoints[0].t_s, start.energy_wh);
    let (mut steps, mut next_goal) = (0, 0);
    while let Some(action) = plan.waypoints.first().and_then(|w| w.action) {
        t = t.max(plan.waypoints[0].t_s);
        let exact = areo_mission::Perturbation::NONE;
        let (to, effect) = model.execute(&truth, action, cell, t, exact).unwrap();
        (cell, t, battery) = (to, t + effect.duration_s, effect.after(battery, model.capacity_wh()));
        // As the simulation does: the first goal is reached when the rover stands on it.
        if next_goal == 0 && cell == goals[0] {
            next_goal = 1;
            mission.goal_reached();
        }
        let changed = map.sense(&truth, &disc(&map, cell, 2)).unwrap();
        let here = Start { cell, t_min: t, t_max: t, energy_wh: battery };
        plan = mission.advance(here, &changed).unwrap();
        let fresh = mission.fresh().unwrap().expect("a fresh plan");
        assert!(
            (plan.cost - fresh.cost).abs() <= 1e-9 * fresh.cost.abs().max(1.0),
            "step {steps} ({energy_wh:?} Wh classes): re-plan {} vs fresh {}",
            plan.cost,
            fresh.cost
        );
        steps += 1;
        assert!(steps < 600, "the rover never arrives");
    }
    assert_eq!((cell, next_goal), (goals[1], 1));
    steps
}

#[test]
fn replans_with_coarse_time_and_energy_classes_equal_fresh_plans() {
    let steps = walk_with_coarse_classes(Some(25.0));
    assert!(steps > 20, "{steps}");
}

#[test]
fn replans_with_coarse_time_classes_and_exact_energy_equal_fresh_plans() {
    let steps = walk_with_coarse_classes(None);
    assert!(steps > 20, "{steps}");
}

#[test]
fn a_horizon_change_neither_sun_nor_earth_can_see_is_not_reported_and_changes_no_light() {
    // One tall hill in the middle of the truth changes the horizon of most cells; for
    // many the change lies where the Sun never stands near the horizon. Those cells are
    // not reported (a repair there would reopen every time class for nothing) — and
    // then their light must be the same as on the truth at every instant, between the
    // Sun table's samples too.
    let cone = |height: f64| {
        areo_terrain::Dem::from_fn(26, 18, 20.0, 20.0, move |x, y| {
            let base = 3.0 * (x / 37.0).sin() + 2.0 * (y / 23.0).cos() + 0.02 * x;
            base + height * (1.0 - (x - 260.0).hypot(y - 180.0) / 70.0).max(0.0)
        })
        .unwrap()
    };
    let before = mars_world(cone(0.0), 14.0, Some(16));
    let sensed = mars_world(cone(0.0), 14.0, Some(16));
    let truth = mars_world(cone(45.0), 14.0, Some(16));
    let cells: Vec<u32> = (0..before.cells() as u32).collect();
    let changed = sensed.sense(&truth, &cells).unwrap();
    let mut unreported_but_different = 0;
    for &c in &cells {
        if changed.contains(&c) {
            continue;
        }
        let floors_differ = (0..64)
            .any(|k| before.horizon_floor_deg(c, k as f64 * 5.625) != truth.horizon_floor_deg(c, k as f64 * 5.625));
        unreported_but_different += usize::from(floors_differ);
        for t in (0..=14 * 3600 / 37).map(|k| f64::from(k) * 37.0) {
            let sun = truth.sun(t);
            assert_eq!(before.lit(c, &sun), truth.lit(c, &sun), "cell {c} at {t} s");
            assert_eq!(sensed.lit(c, &sun), truth.lit(c, &sun), "cell {c} at {t} s");
        }
    }
    // The filter had work to do, and left work for the search.
    assert!(unreported_but_different > 20, "{unreported_but_different} cells");
    assert!(changed.len() > 20, "{} cells reported", changed.len());
    // A reported cell whose terrain did not change was reported for its light.
    let lit_changed = changed.iter().any(|&c| {
        before.elevation(c) == truth.elevation(c)
            && (0..=14 * 3600 / 37).any(|k| {
                let sun = truth.sun(f64::from(k) * 37.0);
                before.lit(c, &sun) != truth.lit(c, &sun)
            })
    });
    assert!(lit_changed);
}
