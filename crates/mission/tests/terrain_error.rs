//! Plans that hold on the terrain's height error: the envelope of error clones
//! (`World::envelope`) against the map, executed on the clones it was made for and on
//! fresh ones.

use areo_mission::uncertainty::{MonteCarlo, SampledRun, Uncertainty, dem_clone, open_loop_on, summarise};
use areo_mission::{ActionConfig, ActionModel, Mission, MissionPlan, PlannerConfig, Start, World};
use areo_terrain::Dem;

use crate::common::*;

/// A ridge across 24 × 16 cells of 20 m at Gale, with shadows: north–south along
/// x = 240 m, its flanks 14.5° steep except at a pass in the north, where they ease to
/// 6°; the Hyperion-class rover of the uncertainty tests may climb 15°.
fn ridge() -> (Dem, World, ActionModel) {
    let dem = Dem::from_fn(24, 16, 20.0, 20.0, |x, y| {
        let ease = ((y - 220.0) / 60.0).clamp(0.0, 1.0);
        let grade = (14.5 * (1.0 - ease) + 6.0 * ease).to_radians().tan();
        (60.0 - (x - 240.0).abs()).max(0.0) * grade
    })
    .unwrap();
    let world = World::new(dem.clone(), &config(30.0, Some(16)), &areo_ephemeris::Mars24).unwrap();
    (dem, world, model(600.0, ActionConfig { max_slope_deg: Some(15.0), ..ActionConfig::default() }))
}

/// `n` error clones of `map` (0.5 m RMS over 100 m: a LOLA-class DEM), from seeds
/// `first..first + n`.
fn clones(dem: &Dem, map: &World, first: u64, n: u64) -> Vec<World> {
    (first..first + n)
        .map(|seed| {
            let d = dem_clone(dem, 0.5, 100.0, seed).unwrap();
            World::truth(d, &config(30.0, Some(16)), &areo_ephemeris::Mars24, map).unwrap()
        })
        .collect()
}

fn problem(world: &World) -> (Start, [u32; 2]) {
    (
        Start { cell: world.cell(2, 8), t_min: 0.0, t_max: 0.0, energy_wh: 120.0 },
        [world.cell(21, 8), world.cell(20, 13)],
    )
}

/// A plan executed open-loop on each of `worlds` in turn, exactly as modelled (no
/// spread in the model's factors).
fn executed_on(plan: &MissionPlan, model: &ActionModel, worlds: &[World], start: Start) -> Vec<SampledRun> {
    let none = Uncertainty { confidence: 0.95, ..Uncertainty::default() };
    open_loop_on(plan, model, worlds, start, &none, &MonteCarlo { runs: worlds.len(), seed: 1 }).unwrap()
}

#[test]
fn a_plan_on_the_envelope_of_error_clones_holds_on_each_of_them() {
    let (dem, map, model) = ridge();
    let (start, goals) = problem(&map);
    let planning = clones(&dem, &map, 1, 10);
    let envelope = World::envelope(&map, &planning).unwrap();
    assert_eq!(envelope.terrain_members(), 11);
    // Lit on the envelope only where lit on the map and on every clone, through dawn
    // and dusk (the Sun every 4 min), and shadowed somewhere the map alone is lit. (Not
    // "if and only if": between two sectors whose highest horizons are different
    // members', the interpolated envelope may stand above each member's.)
    let (mut checked, mut darker, mut stricter) = (0, 0, 0);
    for t in (0..(30 * 15)).map(|k| f64::from(k) * 240.0) {
        let sun = map.sun(t);
        if !(0.0..20.0).contains(&sun.elevation_deg) {
            continue;
        }
        for c in 0..map.cells() as u32 {
            let all = map.lit(c, &sun) && planning.iter().all(|w| w.lit(c, &sun));
            assert!(!envelope.lit(c, &sun) || all, "cell {c} at {t} s");
            checked += 1;
            darker += usize::from(map.lit(c, &sun) && !all);
            stricter += usize::from(all && !envelope.lit(c, &sun));
        }
    }
    // (Measured: 23 808 checked, 691 dark on some clone where the map is lit, 6 dark
    // on the envelope though lit on every member.)
    assert!(checked > 10_000 && darker > 0 && stricter < darker, "{checked} checked, {darker} darker, {stricter}");
    let (_, on_map) = Mission::plan(&map, &model, PlannerConfig::default(), start, &goals).unwrap();
    let (_, held) = Mission::plan(&envelope, &model, PlannerConfig::default(), start, &goals).unwrap();
    // The map's plan climbs the 14.5° flank; on some clones it is steeper than 15°
    // there (measured: 2 of 10) and the rover refuses.
    let refused = executed_on(&on_map, &model, &planning, start)
        .iter()
        .filter(|e| matches!(&e.failure, Some((_, f)) if f.name() == "refused_slope"))
        .count();
    assert!((1..=4).contains(&refused), "{refused} of 10");
    // The envelope's plan holds on every clone it was made for, each step no later and
    // with no less battery than it predicts: a drive is planned at its worst member.
    let b = &model.rover().battery;
    let floor = b.capacity_wh * b.min_soc;
    for e in executed_on(&held, &model, &planning, start) {
        assert!(e.succeeded(), "{e:?}");
        for ((t, wh), w) in e.battery_wh.iter().zip(&held.waypoints[1..]) {
            assert!(*t <= w.t_s + 1e-6 && wh + floor >= w.battery_wh - 1e-6, "run {}: {t} s {wh} Wh vs {w:?}", e.run);
        }
    }
    // It avoids the crossing's steepest drives, at a price (measured: L + B 4062
    // against 3640).
    assert!(held.cost > on_map.cost * 1.05, "{} vs {}", held.cost, on_map.cost);
    // On 40 fresh clones (seeds the plan never saw): the map's plan is refused on the
    // slope in some (measured: 10), the envelope's never.
    let fresh = clones(&dem, &map, 1000, 40);
    let m = summarise(&executed_on(&on_map, &model, &fresh, start), 2);
    let h = summarise(&executed_on(&held, &model, &fresh, start), 2);
    assert!((4..=16).contains(&(40 - m.succeeded)), "{m:?}");
    assert_eq!(h.succeeded, 40, "{h:?}");
}

#[test]
fn an_envelope_of_clones_without_error_gives_the_maps_plan_exactly() {
    let (dem, map, model) = ridge();
    let (start, goals) = problem(&map);
    let same = World::truth(dem, &config(30.0, Some(16)), &areo_ephemeris::Mars24, &map).unwrap();
    let envelope = World::envelope(&map, &[same]).unwrap();
    let (_, on_map) = Mission::plan(&map, &model, PlannerConfig::default(), start, &goals).unwrap();
    let (_, held) = Mission::plan(&envelope, &model, PlannerConfig::default(), start, &goals).unwrap();
    assert_eq!(held.cost, on_map.cost);
    assert_eq!(
        held.waypoints.iter().map(|w| (w.cell, w.t_s, w.action, w.battery_wh)).collect::<Vec<_>>(),
        on_map.waypoints.iter().map(|w| (w.cell, w.t_s, w.action, w.battery_wh)).collect::<Vec<_>>()
    );
}

#[test]
fn re_plans_on_an_envelope_equal_fresh_searches_as_sensing_ends_the_error() {
    // The rover believes the envelope and drives on one clone: every cell it senses
    // takes the clone's values (the members' spread ends there) and the kept search
    // graphs must answer each re-plan as a fresh search on the updated belief does.
    use areo_mission::{SimConfig, Simulation, simulate};
    let (dem, map, model) = ridge();
    let (start, goals) = problem(&map);
    let planning = clones(&dem, &map, 1, 4);
    let envelope = World::envelope(&map, &planning).unwrap();
    let truth = clones(&dem, &map, 77, 1).pop().unwrap();
    let sim = Simulation {
        believed: &envelope,
        truth: &truth,
        model: &model,
        planner: PlannerConfig::default(),
        start,
        goals: &goals,
        config: SimConfig { compare_fresh: true, ..SimConfig::default() },
    };
    let report = simulate(&sim, &mut |_| {}).unwrap();
    assert_eq!(report.goals_reached.len(), 2, "{:?}", report.status);
    let compared: Vec<_> = report.plans.iter().filter_map(|p| p.fresh.map(|f| (p.step, p.plan.cost, f.1))).collect();
    assert!(compared.len() >= 10, "{} re-plans compared", compared.len());
    for (step, replan, fresh) in compared {
        assert!((replan - fresh).abs() < 1e-6, "step {step}: re-plan {replan} vs fresh {fresh}");
    }
    // Sensed cells left the envelope: what the rover saw is the clone's, and a drive
    // between two of them costs what it does on the clone.
    let seen = report.steps.iter().map(|s| s.cell).collect::<Vec<_>>();
    assert!(
        seen.iter()
            .all(|&c| envelope.elevation(c) == truth.elevation(c) && envelope.slope_deg(c) == truth.slope_deg(c))
    );
    let drives: Vec<_> = report.steps.iter().filter(|s| s.cell != s.to).collect();
    assert!(drives.len() > 10);
    for s in drives {
        let k = (0..8u8).find(|&k| model.drive_geometry(&truth, s.cell, k).is_ok_and(|g| g.to == s.to)).unwrap();
        assert_eq!(model.drive_geometry(&envelope, s.cell, k), model.drive_geometry(&truth, s.cell, k));
    }
}
