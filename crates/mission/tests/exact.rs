//! The exact tick search ([`areo_mission::exact`]) against a Dijkstra over every
//! (goal, cell, instant, battery) with no dominance and no bound, on seeded synthetic
//! worlds and on a crop of the MOLA Gale map; its nesting (halving the tick never
//! loses a plan nor makes it dearer) over 200 seeded worlds; and its "no plan" as a
//! proof.

use ordered_float::OrderedFloat;
use rustc_hash::FxHashMap;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

use areo_mission::exact::{ExactGoal, ExactQuery};
use areo_mission::{Action, ActionConfig, ActionModel, Effect, Objective, PathLength, Start, World};

use crate::common::{mars_world, model};

/// Rolling ground on 20 m cells, its relief and phase from `seed`.
pub(crate) fn hills(cols: usize, rows: usize, seed: u64) -> areo_terrain::Dem {
    let a = 2.0 + (seed % 7) as f64;
    let p = (seed % 13) as f64;
    areo_terrain::Dem::from_fn(cols, rows, 20.0, 20.0, move |x, y| {
        a * (x / 29.0 + p).sin() + 3.0 * (y / 17.0 + 0.5 * p).cos()
    })
    .unwrap()
}

/// Drives in daylight only and at any heading; waits in steps of `tick_s`.
pub(crate) fn actions(tick_s: f64) -> ActionConfig {
    let mut a = ActionConfig { wait_step_s: Some(tick_s), ..Default::default() };
    a.drive.sun_in_camera = false;
    a
}

/// A step's L + B cost: Δe plus E_max per unit of L (a drive its planar length in
/// cells, a wait its length over a Hibernate's), never below zero.
fn cost(world: &World, model: &ActionModel, e_max: f64, action: Action, e: &Effect) -> f64 {
    let units = match action {
        Action::Drive(_) => PathLength::Distance.units(action, world.dem().dx(), world.dem().dy()),
        _ => e.duration_s / model.config().hibernate_s,
    };
    (e.energy_wh + e_max * units).max(0.0)
}

/// The least L + B cost of a plan whose drives depart on ticks of `tick_s` (each drive
/// followed by a wait to the next tick, unless it reaches the last goal), by a Dijkstra
/// over (goals reached, cell, instant to the microsecond, battery) — every battery level
/// its own state, no dominance, no bound. A goal is reached at any instant of its
/// window the rover is there.
fn brute_force(world: &World, model: &ActionModel, start: Start, goals: &[ExactGoal], goal_wh: f64) -> Option<f64> {
    brute_force_by(Objective::Energy, world, model, start, goals, goal_wh)
}

/// [`brute_force`] under `objective`: L + B, Time or the loads' energy summed over the
/// steps, or Margin —
/// the most the battery falls below its start inside any step (a path's worst, which
/// only grows along it, so the Dijkstra holds).
pub(crate) fn brute_force_by(
    objective: Objective,
    world: &World,
    model: &ActionModel,
    start: Start,
    goals: &[ExactGoal],
    goal_wh: f64,
) -> Option<f64> {
    let (tick, e_max) = (model.wait_step_s().unwrap(), model.gain_bounds(world).0);
    let (e0, capacity) = (start.energy_wh, model.capacity_wh());
    let then = |d: f64, action: Action, effect: &Effect, before: f64| match objective {
        Objective::Margin { .. } => d.max(e0 - effect.lowest(before, capacity)),
        Objective::Time => d + effect.duration_s,
        Objective::EnergyUsed => d + effect.load_wh,
        _ => d + cost(world, model, e_max, action, effect),
    };
    let reached = |g: usize, cell: u32, t: f64, e: f64| -> usize {
        match goals.get(g) {
            Some(x) if x.cell == cell && t >= x.open_s - 1e-9 && t <= x.close_s + 1e-9 => {
                if g + 1 < goals.len() || e >= goal_wh - 1e-9 { g + 1 } else { g }
            }
            _ => g,
        }
    };
    let next_tick = |t: f64| ((t / tick + 1e-9).floor() + 1.0) * tick;
    type State = (usize, u32, i64, u64);
    let mut times: FxHashMap<i64, f64> = FxHashMap::default();
    let mut dist: FxHashMap<State, f64> = FxHashMap::default();
    let mut heap = BinaryHeap::new();
    let mut push = |s: State, t: f64, d: f64, dist: &mut FxHashMap<State, f64>, heap: &mut BinaryHeap<_>| {
        times.insert(s.2, t);
        if dist.get(&s).is_none_or(|&best| d < best - 1e-12) {
            dist.insert(s, d);
            heap.push(Reverse((OrderedFloat(d), s, OrderedFloat(t))));
        }
    };
    let (g0, key) = (reached(0, start.cell, start.t_min, start.energy_wh), |t: f64| (t * 1e6).round() as i64);
    push((g0, start.cell, key(start.t_min), start.energy_wh.to_bits()), start.t_min, 0.0, &mut dist, &mut heap);
    while let Some(Reverse((OrderedFloat(d), s, OrderedFloat(t)))) = heap.pop() {
        if dist.get(&s).is_some_and(|&best| best < d) {
            continue;
        }
        let (g, cell, _, b) = s;
        if g == goals.len() {
            return Some(d);
        }
        // Past its next goal's window a state reaches no goal: a feasibility cut, no bound.
        if t > goals[g].close_s + 1e-9 {
            continue;
        }
        let e = f64::from_bits(b);
        let mut moves: Vec<(usize, u32, f64, f64, f64)> = Vec::new();
        for k in 0..8u8 {
            let feasible = |(_, drive): &(u32, Effect)| drive.lowest(e, capacity) >= -1e-9;
            let Some((to, drive)) = model.drive(world, cell, k, t).ok().filter(feasible) else { continue };
            let (t1, e1) = (t + drive.duration_s, drive.after(e, capacity));
            let c1 = then(d, Action::Drive(k), &drive, e);
            let g1 = reached(g, to, t1, e1);
            let on_tick = ((t1 / tick) - (t1 / tick).round()).abs() < 1e-9;
            if g1 == goals.len() || on_tick {
                moves.push((g1, to, t1, e1, c1));
                continue;
            }
            let wait = model.wait(world, to, t1, next_tick(t1) - t1).ok();
            let Some(settle) = wait.filter(|settle| settle.lowest(e1, capacity) >= -1e-9) else { continue };
            let (t2, e2) = (t1 + settle.duration_s, settle.after(e1, capacity));
            moves.push((reached(g1, to, t2, e2), to, t2, e2, then(c1, Action::Wait, &settle, e1)));
        }
        if let Ok(wait) = model.wait(world, cell, t, next_tick(t) - t)
            && wait.lowest(e, capacity) >= -1e-9
        {
            let (t1, e1) = (t + wait.duration_s, wait.after(e, capacity));
            moves.push((reached(g, cell, t1, e1), cell, t1, e1, then(d, Action::Wait, &wait, e)));
        }
        for (g, to, t, e, c) in moves {
            push((g, to, key(t), e.to_bits()), t, c, &mut dist, &mut heap);
        }
    }
    None
}

/// A small deterministic generator for the seeded cases.
pub(crate) struct Seeds(pub(crate) u64);

impl Seeds {
    pub(crate) fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A seeded case on a 6 × 4 world: start and one or two goals, a morning or
/// afternoon start, a battery of 150 Wh with 2–40 Wh at the start, goal windows from
/// the start to `window_h` later.
pub(crate) struct Case {
    pub(crate) world: World,
    pub(crate) start: Start,
    pub(crate) goals: Vec<ExactGoal>,
}

pub(crate) fn case(seed: u64, window_h: f64) -> Case {
    let mut r = Seeds(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let world = mars_world(hills(6, 4, seed), 30.0, None);
    let cell = |r: &mut Seeds| world.cell((r.next() * 6.0) as usize % 6, (r.next() * 4.0) as usize % 4);
    let t0 = 4.0 * 3600.0 + r.next() * 12.0 * 3600.0;
    let start = Start { cell: cell(&mut r), t_min: t0, t_max: t0, energy_wh: 2.0 + 38.0 * r.next() };
    let n = 1 + (r.next() * 2.0) as usize;
    let goals = (0..n).map(|_| ExactGoal { cell: cell(&mut r), open_s: t0, close_s: t0 + window_h * 3600.0 }).collect();
    Case { world, start, goals }
}

/// Asserts that the exact search and the Dijkstra agree on `case`: the same cost, or
/// both no plan. Whether there was a plan.
pub(crate) fn agree(exact: Option<f64>, brute: Option<f64>, case: &str) -> bool {
    match (exact, brute) {
        (Some(cost), Some(b)) => {
            assert!((cost - b).abs() < 1e-6 * (1.0 + b), "{case}: exact {cost} vs Dijkstra {b}");
            true
        }
        (None, None) => false,
        (e, b) => panic!("{case}: exact {e:?} vs Dijkstra {b:?}"),
    }
}

fn exact(case: &Case, model: &ActionModel) -> areo_mission::exact::ExactOutcome {
    exact_on(&case.world, case.start, &case.goals, model)
}

fn exact_on(
    world: &World,
    start: Start,
    goals: &[ExactGoal],
    model: &ActionModel,
) -> areo_mission::exact::ExactOutcome {
    exact_by(Objective::Energy, world, start, goals, model)
}

fn exact_by(
    objective: Objective,
    world: &World,
    start: Start,
    goals: &[ExactGoal],
    model: &ActionModel,
) -> areo_mission::exact::ExactOutcome {
    query_by(objective, world, start, goals, model).solve()
}

/// The exact query from `start` to `goals` (no battery to hold at the last) under
/// `objective`, settling to ticks, with room for five million labels.
pub(crate) fn query_by<'a>(
    objective: Objective,
    world: &'a World,
    start: Start,
    goals: &[ExactGoal],
    model: &'a ActionModel,
) -> ExactQuery<'a> {
    ExactQuery {
        world,
        model,
        start,
        goals: goals.to_vec(),
        goal_energy_wh: 0.0,
        objective,
        max_labels: 5_000_000,
        settle: true,
    }
}

/// The exact search's plan costs what the Dijkstra with no dominance finds, and it
/// finds no plan exactly where the Dijkstra finds none — over seeded worlds with a
/// binding battery, morning and evening starts (the evening ones wait through the
/// dusk), one and two goals.
#[test]
fn the_exact_search_equals_a_dijkstra_without_dominance() {
    let (mut planned, mut proven, mut binding) = (0, 0, 0);
    for seed in 0..24 {
        let c = case(seed, 3.0);
        let model = model(150.0, actions(900.0));
        let out = exact(&c, &model);
        assert!(!out.stopped);
        let brute = brute_force(&c.world, &model, c.start, &c.goals, 0.0);
        let full = exact(&Case { start: Start { energy_wh: 135.0, ..c.start }, ..c }, &model);
        if full.plan.as_ref().map(|p| p.0) != out.plan.as_ref().map(|p| p.0) {
            binding += 1;
        }
        match (&out.plan, brute) {
            (Some((cost, steps)), Some(b)) => {
                assert!((cost - b).abs() < 1e-6 * (1.0 + b), "seed {seed}: exact {cost} vs Dijkstra {b}");
                // The plan's battery never goes below the floor, and drives depart on ticks
                // (or at the start).
                assert!(steps.iter().all(|s| s.battery_wh >= -1e-9), "seed {seed}: {steps:?}");
                for s in steps.iter().filter(|s| s.t_s > c.start.t_min) {
                    let phase = s.t_s / 900.0;
                    assert!((phase - phase.round()).abs() < 1e-9, "seed {seed}: a step off the ticks: {s:?}");
                }
                planned += 1;
            }
            (None, None) => proven += 1,
            (p, b) => panic!("seed {seed}: exact {:?} vs Dijkstra {b:?}", p.as_ref().map(|p| p.0)),
        }
    }
    assert!(planned >= 8 && proven >= 2, "{planned} planned, {proven} proven unreachable: the cases test too little");
    // In some cases the battery binds: a full one plans cheaper, or plans at all.
    assert!(binding >= 3, "the battery binds in only {binding} cases");
}

/// Halving the tick never loses a plan nor makes it dearer: a drive's wait to the next
/// tick is a wait to the next half tick and whole half ticks, which compose exactly.
/// Over 200 seeded worlds at 20 and 10 minutes: every plan found at 20 minutes is
/// found at 10 at no higher cost, and in many the finer tick is strictly cheaper (the
/// settle is a real cost, so the test can fail).
#[test]
fn halving_the_tick_never_loses_a_plan_over_200_seeded_worlds() {
    let (mut found, mut cheaper, mut only_finer) = (0, 0, 0);
    for seed in 0..200 {
        let c = case(1000 + seed, 4.0);
        let coarse = exact(&c, &model(150.0, actions(1200.0)));
        let fine = exact(&c, &model(150.0, actions(600.0)));
        assert!(!coarse.stopped && !fine.stopped);
        match (&coarse.plan, &fine.plan) {
            (Some((a, _)), Some((b, _))) => {
                assert!(*b <= a + 1e-6 * (1.0 + a), "seed {seed}: {b} at 10 min against {a} at 20 min");
                found += 1;
                if *b < a - 1e-6 {
                    cheaper += 1;
                }
            }
            (Some((a, _)), None) => panic!("seed {seed}: found at 20 min ({a}), lost at 10 min"),
            (None, Some(_)) => only_finer += 1,
            (None, None) => {}
        }
    }
    assert!(found >= 100, "only {found} of 200 seeded cases have a plan");
    assert!(cheaper >= 20, "the finer tick is cheaper in only {cheaper} cases");
    // Some plans exist only at the finer tick: the coarser one's "no plan" is a proof
    // at its own tick, not at every tick.
    assert!(only_finer >= 1, "no case plans only at the finer tick");
}

/// The 7 × 5 crop of the MOLA Gale map over 30 h, and the first minute the Sun stands
/// 8° above its horizon, s.
pub(crate) fn gale_morning() -> (World, f64) {
    let (crop, config) = crate::common::gale_crop(30.0);
    let world = World::new(crop, &config, &areo_ephemeris::Mars24).unwrap();
    let mut t0 = 0.0;
    while world.sun(t0).elevation_deg < 8.0 {
        t0 += 60.0;
    }
    (world, t0)
}

/// The Gale crop over 40 h from the Sun table's start (a night and the next morning
/// after the first afternoon), and its first sunset, s after the epoch.
pub(crate) fn gale_evening() -> (World, f64) {
    let (crop, config) = crate::common::gale_crop(40.0);
    let world = World::new(crop, &config, &areo_ephemeris::Mars24).unwrap();
    let mut t = 0.0;
    while world.sun(t).elevation_deg <= 0.0 {
        t += 60.0;
    }
    while world.sun(t).elevation_deg > 0.0 {
        t += 60.0;
    }
    (world, t)
}

/// On a crop of the real MOLA Gale map (7 × 5 cells of 463 m, real slopes and cast
/// shadows at a low morning Sun), two goals: the exact search equals the Dijkstra under
/// L + B and under Margin, with little battery and with plenty, and where the day is too short for both goals
/// both prove that no plan exists.
#[test]
fn on_a_crop_of_gale_crater_the_exact_search_equals_a_dijkstra_without_dominance() {
    let (world, t0) = gale_morning();
    // 5 Wh energy quanta keep the Dijkstra's battery levels few.
    let model = model(400.0, ActionConfig { energy_quantum_wh: 5.0, ..actions(1800.0) });
    let goals = [
        ExactGoal { cell: world.cell(1, 1), open_s: t0, close_s: t0 },
        ExactGoal { cell: world.cell(5, 4), open_s: t0, close_s: t0 },
    ];
    let (mut found, mut proven) = (0, 0);
    for hours in [7.0, 9.0, 11.0] {
        let goals: Vec<ExactGoal> = goals.iter().map(|g| ExactGoal { close_s: t0 + hours * 3600.0, ..*g }).collect();
        for battery in [5.0, 150.0] {
            let start = Start { cell: world.cell(6, 0), t_min: t0, t_max: t0, energy_wh: battery };
            for objective in [Objective::Energy, Objective::Margin { max_duration_s: hours * 3600.0 }] {
                let out = exact_by(objective, &world, start, &goals, &model);
                assert!(!out.stopped);
                let brute = brute_force_by(objective, &world, &model, start, &goals, 0.0);
                if agree(out.plan.map(|p| p.0), brute, &format!("{objective:?}, {hours} h, {battery} Wh")) {
                    found += 1;
                } else {
                    proven += 1;
                }
            }
        }
    }
    // The windows decide: too short a day has no plan, a long enough one has.
    assert!(proven >= 2 && found >= 2, "{found} found, {proven} proven unreachable");
}

/// Across a night: the exact search's waits run on to the first tick a drive may depart
/// (the night in one wait), the Dijkstra's wait one tick at a time; they cost the same,
/// and both prove "no plan" together. Seeded worlds, starts one to three hours before
/// sunset with goals whose windows run through the night into the next morning.
#[test]
fn across_a_night_the_exact_search_equals_a_dijkstra_waiting_tick_by_tick() {
    let (mut planned, mut overnight, mut proven) = (0, 0, 0);
    for seed in 0..24u64 {
        let mut r = Seeds(seed.wrapping_mul(0x2545_f491_4f6c_dd1d) | 1);
        let world = mars_world(hills(5, 4, 50 + seed), 30.0, None);
        let mut sunset = 0.0;
        while world.sun(sunset).elevation_deg <= 0.0 {
            sunset += 60.0;
        }
        while world.sun(sunset).elevation_deg > 0.0 {
            sunset += 60.0;
        }
        let t0 = sunset - 3600.0 * (1.0 + 2.0 * r.next());
        let cell = |r: &mut Seeds| world.cell((r.next() * 5.0) as usize % 5, (r.next() * 4.0) as usize % 4);
        let start = Start { cell: cell(&mut r), t_min: t0, t_max: t0, energy_wh: 60.0 + 300.0 * r.next() };
        let goals: Vec<ExactGoal> = (0..1 + (r.next() * 2.0) as usize)
            .map(|_| ExactGoal { cell: cell(&mut r), open_s: t0, close_s: t0 + 18.0 * 3600.0 })
            .collect();
        let model = model(400.0, actions(1800.0));
        let out = exact_on(&world, start, &goals, &model);
        assert!(!out.stopped);
        let brute = brute_force(&world, &model, start, &goals, 0.0);
        match (&out.plan, brute) {
            (Some((cost, steps)), Some(b)) => {
                assert!((cost - b).abs() < 1e-6 * (1.0 + b), "seed {seed}: exact {cost} vs Dijkstra {b}");
                planned += 1;
                let end = steps.last().map_or(t0, |s| s.t_s + s.duration_s);
                if end > sunset + 3600.0 {
                    overnight += 1;
                    // The night is one wait: no step starts in the deep night.
                    assert!(
                        steps.iter().filter(|s| s.t_s > sunset + 3600.0 && s.t_s < end - 3.0 * 3600.0).count() == 0
                            || steps.iter().any(|s| s.action == Action::Wait && s.duration_s > 4.0 * 3600.0),
                        "seed {seed}: the night waited tick by tick: {steps:?}"
                    );
                }
            }
            (None, None) => proven += 1,
            (p, b) => panic!("seed {seed}: exact {:?} vs Dijkstra {b:?}", p.as_ref().map(|p| p.0)),
        }
    }
    assert!(
        planned >= 8 && overnight >= 4 && proven >= 1,
        "{planned} planned ({overnight} through the night), {proven} proven unreachable: the cases test too little"
    );
}

/// Where nothing depends on time (drives by day or night, a battery far beyond the
/// route's needs), the tick search under the Time objective is a 2-D search: on a
/// crop of the MOLA Gale map its plan takes what a Dijkstra over the same drives at
/// whole ticks takes (less the last drive's settle, under one tick), with the same
/// expansions at a horizon of 40 h and of 300 h; where the route needs more than the
/// horizon, "no plan" is proven with no expansion beyond the start.
#[test]
fn a_static_route_on_a_tick_is_a_2d_search_whatever_the_horizon() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../terrain/tests/data/gale_mola_crop_64.tif");
    let dem = areo_terrain::read(&path).unwrap();
    let mut actions = actions(60.0);
    actions.drive.daylight = false;
    let model = model(1.0e7, actions);
    let tick = 60.0;
    let mut expansions = Vec::new();
    for span_h in [40.0, 300.0, 5.0] {
        let world = mars_world(dem.clone(), span_h, None);
        let (start, goal) = (world.cell(20, 20), world.cell(44, 40));
        let out = static_route(&world, &model, start, goal);
        assert!(!out.stopped);
        let reference = whole_tick_dijkstra(&world, &model, start, goal, tick);
        assert!(reference.is_finite() && reference > 20.0 * 3600.0, "{reference} s");
        match out.plan {
            Some((cost, _)) => {
                assert!(reference <= world.span_s(), "span {span_h} h");
                assert!(
                    (reference - tick..=reference + 1e-6).contains(&cost),
                    "{span_h} h: {cost} s against {reference} s"
                );
                expansions.push(out.expanded);
            }
            None => {
                assert!(reference > world.span_s(), "span {span_h} h: no plan, the Dijkstra takes {reference} s");
                assert!(out.expanded <= 1, "{} expansions to prove it", out.expanded);
            }
        }
    }
    assert_eq!(expansions.len(), 2);
    assert_eq!(expansions[0], expansions[1], "the horizon changed the work");
    assert!(expansions[0] < 2_000, "{} expansions", expansions[0]);
}

/// The fastest route from `start` to `goal` with a battery that never binds, any time
/// in the world's span.
fn static_route(world: &World, model: &ActionModel, start: u32, goal: u32) -> areo_mission::exact::ExactOutcome {
    ExactQuery {
        world,
        model,
        start: Start { cell: start, t_min: 0.0, t_max: 0.0, energy_wh: 5.0e6 },
        goals: vec![ExactGoal { cell: goal, open_s: 0.0, close_s: world.span_s() }],
        goal_energy_wh: 0.0,
        objective: Objective::Time,
        max_labels: 5_000_000,
        settle: true,
    }
    .solve()
}

/// The least time from `start` to `goal` over drives each lasting whole ticks, by a
/// Dijkstra over the cells (s; infinite: no way).
fn whole_tick_dijkstra(world: &World, model: &ActionModel, start: u32, goal: u32, tick: f64) -> f64 {
    let mut dist = vec![f64::INFINITY; world.cols() * world.rows()];
    let mut heap = BinaryHeap::new();
    dist[start as usize] = 0.0;
    heap.push(Reverse((OrderedFloat(0.0), start)));
    while let Some(Reverse((OrderedFloat(d), cell))) = heap.pop() {
        if cell == goal {
            return d;
        }
        if d > dist[cell as usize] {
            continue;
        }
        for k in 0..8u8 {
            let Ok(g) = model.drive_geometry(world, cell, k) else { continue };
            let nd = d + (g.duration_s / tick - 1e-9).ceil() * tick;
            if nd < dist[g.to as usize] {
                dist[g.to as usize] = nd;
                heap.push(Reverse((OrderedFloat(nd), g.to)));
            }
        }
    }
    f64::INFINITY
}

/// The bound's backward searches go only as far as the cells the search asks about: on
/// a map of 1.44 million cells a route of some 40 cells costs what the Dijkstra finds,
/// and the search holds under a tenth of what weighing every drive of the map would
/// take (four f32 weights per drive, 128 bytes a cell: 184 MB; it holds ~10 MB, mostly
/// pages of rows the backward searches crossed).
#[test]
fn on_a_large_map_the_bound_weighs_the_cells_around_the_route() {
    let mut actions = actions(60.0);
    actions.drive.daylight = false;
    let model = model(1.0e7, actions);
    let tick = 60.0;
    let world = mars_world(hills(1200, 1200, 3), 40.0, None);
    let (start, goal) = (world.cell(600, 600), world.cell(640, 615));
    let out = static_route(&world, &model, start, goal);
    let reference = whole_tick_dijkstra(&world, &model, start, goal, tick);
    let (cost, _) = out.plan.expect("a plan");
    assert!((reference - tick..=reference + 1e-6).contains(&cost), "{cost} s against {reference} s");
    let whole_map = (world.cols() * world.rows() * 8 * 4 * 4) as u64;
    assert!(out.bytes * 10 < whole_map, "{} bytes held against {whole_map} for the whole map", out.bytes);
}

/// Three goals in order, each reached at any instant of its window: the exact search
/// costs what the Dijkstra with no dominance finds, and proves "no plan" where it finds
/// none — the goal index a third dimension beside cell and instant.
#[test]
fn with_three_goals_the_exact_search_equals_a_dijkstra_without_dominance() {
    let (mut planned, mut proven) = (0, 0);
    for seed in 0..12u64 {
        let c = case(100 + seed, 4.0);
        let mut r = Seeds(seed.wrapping_mul(0x2545_f491_4f6c_dd1d) | 1);
        let cell = |r: &mut Seeds| c.world.cell((r.next() * 6.0) as usize % 6, (r.next() * 4.0) as usize % 4);
        let (open, close) = (c.start.t_min, c.start.t_min + 4.0 * 3600.0);
        let goals: Vec<ExactGoal> =
            (0..3).map(|_| ExactGoal { cell: cell(&mut r), open_s: open, close_s: close }).collect();
        let model = model(150.0, actions(900.0));
        let out = exact_on(&c.world, c.start, &goals, &model);
        assert!(!out.stopped);
        let brute = brute_force(&c.world, &model, c.start, &goals, 0.0);
        if agree(out.plan.map(|p| p.0), brute, &format!("seed {seed}")) {
            planned += 1;
        } else {
            proven += 1;
        }
    }
    assert!(planned >= 4 && proven >= 1, "{planned} planned, {proven} proven unreachable: the cases test too little");
}

/// Under Margin the exact search keeps the battery highest at the plan's lowest point:
/// its cost (the Wh drawn below the start there) equals the Dijkstra's over every
/// battery level, its plan never falls lower than that, and "no plan" agrees — over
/// seeded worlds with one and two goals, the last window the longest acceptable plan.
/// The margin is not the time: in some cases the fastest plan draws the battery lower.
#[test]
fn under_margin_the_exact_search_equals_a_dijkstra_without_dominance() {
    let margin = Objective::Margin { max_duration_s: 3.0 * 3600.0 };
    let (mut planned, mut proven, mut slower_but_safer) = (0, 0, 0);
    for seed in 0..24 {
        // A third of the cases allow only an hour: too short for some routes.
        let c = case(300 + seed, if seed % 3 == 0 { 1.0 } else { 3.0 });
        let model = model(150.0, actions(900.0));
        let out = exact_by(margin, &c.world, c.start, &c.goals, &model);
        assert!(!out.stopped);
        let brute = brute_force_by(margin, &c.world, &model, c.start, &c.goals, 0.0);
        if !agree(out.plan.as_ref().map(|p| p.0), brute, &format!("seed {seed}")) {
            proven += 1;
            continue;
        }
        planned += 1;
        let (used, steps) = out.plan.unwrap();
        let lowest = steps.iter().map(|s| s.battery_wh).fold(c.start.energy_wh, f64::min);
        assert!(lowest >= c.start.energy_wh - used - 1e-6, "seed {seed}: {lowest} Wh with {used} Wh used");
        let fastest = exact_by(Objective::Time, &c.world, c.start, &c.goals, &model).plan.expect("a plan");
        let fastest_low = fastest.1.iter().map(|s| s.battery_wh).fold(c.start.energy_wh, f64::min);
        if fastest_low < c.start.energy_wh - used - 1.0 {
            slower_but_safer += 1;
        }
    }
    assert!(planned >= 8 && proven >= 2, "{planned} planned, {proven} proven unreachable: the cases test too little");
    assert!(slower_but_safer >= 2, "the fastest plan is as safe as the margin's in all but {slower_but_safer} cases");
}

/// Every plan of `c` on the tick, enumerated state by state (no dominance: only exact
/// duplicates merge), ending at the last goal: its (arrival, energy used, lowest
/// battery); the non-dominated ones, sorted.
fn front_by_enumeration(world: &World, start: Start, goals: &[ExactGoal], model: &ActionModel) -> Vec<(f64, f64, f64)> {
    let tick = model.wait_step_s().unwrap();
    let capacity = model.capacity_wh();
    let close = goals.last().unwrap().close_s;
    let next_tick = |t: f64| ((t / tick + 1e-9).floor() + 1.0) * tick;
    let reached = |g: usize, cell: u32, t: f64| match goals.get(g) {
        Some(x) if x.cell == cell && t >= x.open_s - 1e-9 && t <= x.close_s + 1e-9 => g + 1,
        _ => g,
    };
    type S = (usize, u32, f64, f64, f64, f64);
    let key = |s: &S| (s.0, s.1, (s.2 * 1e6).round() as i64, s.3.to_bits(), s.4.to_bits(), s.5.to_bits());
    let mut seen = std::collections::HashSet::new();
    let mut layer: Vec<S> =
        vec![(reached(0, start.cell, start.t_min), start.cell, start.t_min, start.energy_wh, 0.0, start.energy_wh)];
    let mut ends = Vec::new();
    while !layer.is_empty() {
        let mut next_layer = Vec::new();
        for (g, cell, t, e, used, low) in layer {
            if g == goals.len() {
                ends.push((t, used, low));
                continue;
            }
            let step = |effect: &Effect, e: f64| {
                (effect.lowest(e, capacity) >= -1e-9).then(|| (effect.after(e, capacity), effect.lowest(e, capacity)))
            };
            let mut push = |s: S, next_layer: &mut Vec<S>| {
                if s.2 <= close + 1e-9 && seen.insert(key(&s)) {
                    next_layer.push(s);
                }
            };
            for k in 0..8u8 {
                let Ok((to, drive)) = model.drive(world, cell, k, t) else { continue };
                let Some((e1, l1)) = step(&drive, e) else { continue };
                let t1 = t + drive.duration_s;
                let (g1, used1, low1) = (reached(g, to, t1), used + drive.load_wh, low.min(l1));
                let on_tick = ((t1 / tick) - (t1 / tick).round()).abs() < 1e-9;
                if g1 == goals.len() || on_tick {
                    push((g1, to, t1, e1, used1, low1), &mut next_layer);
                    continue;
                }
                let Ok(settle) = model.wait(world, to, t1, next_tick(t1) - t1) else { continue };
                let Some((e2, l2)) = step(&settle, e1) else { continue };
                let t2 = t1 + settle.duration_s;
                push((reached(g1, to, t2), to, t2, e2, used1 + settle.load_wh, low1.min(l2)), &mut next_layer);
            }
            if let Ok(wait) = model.wait(world, cell, t, next_tick(t) - t)
                && let Some((e1, l1)) = step(&wait, e)
            {
                let t1 = t + wait.duration_s;
                push((reached(g, cell, t1), cell, t1, e1, used + wait.load_wh, low.min(l1)), &mut next_layer);
            }
        }
        layer = next_layer;
    }
    let no_worse = |a: (f64, f64, f64), b: (f64, f64, f64)| a.0 <= b.0 + 1e-9 && a.1 <= b.1 + 1e-9 && a.2 >= b.2 - 1e-9;
    let mut front: Vec<(f64, f64, f64)> = Vec::new();
    for &p in &ends {
        let beaten = ends.iter().any(|&q| no_worse(q, p) && !no_worse(p, q));
        if !beaten && !front.iter().any(|&q| no_worse(q, p) && no_worse(p, q)) {
            front.push(p);
        }
    }
    front.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    front
}

/// The exact search's Pareto front in (arrival, energy used, lowest battery) is the
/// front of every plan on the tick, enumerated one by one: the same points, over
/// seeded worlds with a binding battery; and in some the front holds more than one plan
/// (waiting to charge trades arrival for margin), so the test can tell a front from a
/// single optimum.
#[test]
fn the_exact_front_is_the_front_of_every_plan_enumerated() {
    let (mut compared, mut several) = (0, 0);
    for seed in 0..16 {
        let c = case(500 + seed, 1.5);
        let model = model(150.0, actions(900.0));
        let exact = ExactQuery {
            world: &c.world,
            model: &model,
            start: c.start,
            goals: c.goals.clone(),
            goal_energy_wh: 0.0,
            objective: Objective::Energy,
            max_labels: 5_000_000,
            settle: true,
        }
        .front();
        assert!(!exact.stopped);
        let got: Vec<(f64, f64, f64)> =
            exact.points.iter().map(|p| (p.arrival_s, p.energy_used_wh, p.lowest_wh)).collect();
        let want = front_by_enumeration(&c.world, c.start, &c.goals, &model);
        assert_eq!(got.len(), want.len(), "seed {seed}: {got:?} against {want:?}");
        for (g, w) in got.iter().zip(&want) {
            let close = (g.0 - w.0).abs() < 1e-6 && (g.1 - w.1).abs() < 1e-6 && (g.2 - w.2).abs() < 1e-6;
            assert!(close, "seed {seed}: {got:?} against {want:?}");
        }
        for p in &exact.points {
            let end = p.steps.last().map_or(c.start.t_min, |s| s.t_s + s.duration_s);
            assert!((end - p.arrival_s).abs() < 1e-6, "seed {seed}: the plan ends at {end}, not {}", p.arrival_s);
        }
        compared += usize::from(!want.is_empty());
        several += usize::from(want.len() > 1);
    }
    assert!(compared >= 6 && several >= 2, "{compared} fronts compared, {several} with more than one plan");
}

/// The same on a crop of the real MOLA Gale map (cells of 463 m, real slopes and cast
/// shadows at a low morning Sun; 5 Wh energy quanta keep the enumeration's states few):
/// the exact front is the front of every plan.
#[test]
fn on_a_crop_of_gale_crater_the_exact_front_is_the_front_of_every_plan() {
    let (world, t0) = gale_morning();
    let model = model(400.0, ActionConfig { energy_quantum_wh: 5.0, ..actions(1800.0) });
    let mut points = 0;
    for (battery, hours) in [(60.0, 5.0), (150.0, 4.0), (100.0, 7.0), (20.0, 7.0)] {
        let start = Start { cell: world.cell(6, 0), t_min: t0, t_max: t0, energy_wh: battery };
        let goals = vec![ExactGoal { cell: world.cell(3, 3), open_s: t0, close_s: t0 + hours * 3600.0 }];
        let exact = ExactQuery {
            world: &world,
            model: &model,
            start,
            goals: goals.clone(),
            goal_energy_wh: 0.0,
            objective: Objective::Energy,
            max_labels: 5_000_000,
            settle: true,
        }
        .front();
        let got: Vec<(f64, f64, f64)> =
            exact.points.iter().map(|p| (p.arrival_s, p.energy_used_wh, p.lowest_wh)).collect();
        let want = front_by_enumeration(&world, start, &goals, &model);
        assert_eq!(got.len(), want.len(), "{battery} Wh: {got:?} against {want:?}");
        for (g, w) in got.iter().zip(&want) {
            let close = (g.0 - w.0).abs() < 1e-6 && (g.1 - w.1).abs() < 1e-6 && (g.2 - w.2).abs() < 1e-6;
            assert!(close, "{battery} Wh: {got:?} against {want:?}");
        }
        points += want.len();
    }
    assert!(points >= 3, "{points} front plans in all: the cases test too little");
}

/// With Communicate sessions (no drive may overlap one) the exact search still equals
/// the Dijkstra: the bound counts the sessions' hours as time no drive can use (the
/// drives at their own durations, and the drives with their settles in whole ticks),
/// and a bound that overstated them would lose or overprice plans here. Sessions of 40
/// minutes every 90 minutes, off the tick grid, on a 12 × 4 world crossed end to end
/// (eleven drives or more: several sessions on the way), windows of 3.5 and 8 hours,
/// under Time and L + B; in many cases the sessions make the plan later than it is
/// without them.
#[test]
fn with_communicate_sessions_the_exact_search_equals_a_dijkstra_without_dominance() {
    let (mut planned, mut proven, mut delayed) = (0, 0, 0);
    for seed in 0..12u64 {
        let mut r = Seeds(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
        let world = mars_world(hills(12, 4, 500 + seed), 30.0, None);
        let t0 = 5.0 * 3600.0 + r.next() * 6.0 * 3600.0;
        let start =
            Start { cell: world.cell(0, seed as usize % 4), t_min: t0, t_max: t0, energy_wh: 40.0 + 60.0 * r.next() };
        let window_h = if seed % 3 == 0 { 3.5 } else { 8.0 };
        let goals =
            [ExactGoal { cell: world.cell(11, (seed as usize / 4) % 4), open_s: t0, close_s: t0 + window_h * 3600.0 }];
        let plain = model(150.0, actions(900.0));
        let first = t0 + 700.0;
        let sessions: Vec<(f64, f64)> =
            (0..8).map(|k| (first + k as f64 * 5400.0, first + k as f64 * 5400.0 + 2400.0)).collect();
        let model = model(150.0, actions(900.0)).with_sessions(sessions);
        for objective in [Objective::Time, Objective::Energy] {
            let out = exact_by(objective, &world, start, &goals, &model);
            assert!(!out.stopped);
            let brute = brute_force_by(objective, &world, &model, start, &goals, 0.0);
            if !agree(out.plan.as_ref().map(|p| p.0), brute, &format!("seed {seed}, {objective:?}")) {
                proven += 1;
                continue;
            }
            planned += 1;
            if objective == Objective::Time {
                let free = exact_by(objective, &world, start, &goals, &plain).plan.expect("a plan");
                if out.plan.as_ref().unwrap().0 > free.0 + 1.0 {
                    delayed += 1;
                }
            }
        }
    }
    assert!(planned >= 10 && proven >= 2, "{planned} planned, {proven} proven unreachable: the cases test too little");
    assert!(delayed >= 4, "the sessions delay only {delayed} plans");
}

/// Under Time with a full battery the sun keeps full, the search does not wait one tick
/// at a time where driving on first is never worse: its waits jump. It still equals
/// the Dijkstra that waits tick by tick — over seeded worlds with afternoon starts whose
/// windows run into the dusk (drives refused in shadow or darkness until a wait ends),
/// one and two goals, and on the crop of the Gale map under a low morning Sun — and the
/// jumps are many, while plans that must wait still wait.
#[test]
fn under_time_the_waits_that_jump_keep_the_optimum_of_a_dijkstra_waiting_tick_by_tick() {
    let (mut planned, mut proven, mut jumps, mut waited) = (0, 0, 0, 0);
    let mut check = |world: &World, model: &ActionModel, start: Start, goals: &[ExactGoal], case: &str| {
        let out = exact_by(Objective::Time, world, start, goals, model);
        assert!(!out.stopped, "{case}");
        jumps += out.jumps;
        let brute = brute_force_by(Objective::Time, world, model, start, goals, 0.0);
        if agree(out.plan.as_ref().map(|p| p.0), brute, case) {
            planned += 1;
            let steps = &out.plan.as_ref().unwrap().1;
            if steps.iter().any(|s| s.action == Action::Wait && s.duration_s > 900.0 + 1e-6 && s.t_s > start.t_min) {
                waited += 1;
            }
        } else {
            proven += 1;
        }
    };
    for seed in 0..24u64 {
        let mut r = Seeds(seed.wrapping_mul(0x6a09_e667_f3bc_c909) | 1);
        let world = mars_world(hills(7, 4, 300 + seed), 30.0, Some(32));
        // Drives in direct sun only: the hills' shadows refuse drives until they move.
        let mut lit = actions(900.0);
        lit.drive.direct_sun = true;
        let model = model(150.0, lit);
        let cell = |r: &mut Seeds| world.cell((r.next() * 7.0) as usize % 7, (r.next() * 4.0) as usize % 4);
        // Starts in the long shadows of the morning, or of the afternoon.
        let mut sunrise = 0.0;
        while world.sun(sunrise).elevation_deg > 0.0 || world.sun(sunrise + 60.0).elevation_deg <= 0.0 {
            sunrise += 60.0;
        }
        let t0 = sunrise + if seed % 2 == 0 { 3.0 * r.next() } else { 7.0 + 3.0 * r.next() } * 3600.0;
        let start = Start { cell: cell(&mut r), t_min: t0, t_max: t0, energy_wh: model.capacity_wh() };
        let n = 1 + (seed / 2 % 2) as usize;
        let close = (t0 + (3.0 + 12.0 * r.next()) * 3600.0).min(29.0 * 3600.0);
        // The first goal opens up to five hours after the start: the rover has time to
        // spare, to spend anywhere on the way.
        let open = t0 + 5.0 * 3600.0 * r.next();
        let goals: Vec<ExactGoal> =
            (0..n).map(|_| ExactGoal { cell: cell(&mut r), open_s: open, close_s: close }).collect();
        check(&world, &model, start, &goals, &format!("seed {seed}"));
    }
    // A cliff 40 m high east of a plain, whose morning shadow recedes east across it
    // while the Sun is already high enough to charge: the rover from the west waits at
    // the shadow's edge, cell by cell.
    let ridge = areo_terrain::Dem::from_fn(10, 3, 20.0, 20.0, |x, _| if x > 180.0 { 40.0 } else { 0.0 }).unwrap();
    let world = mars_world(ridge, 30.0, Some(32));
    let mut lit = actions(600.0);
    lit.drive.direct_sun = true;
    let ridge_model = model(150.0, lit);
    let mut sunrise = 0.0;
    while world.sun(sunrise).elevation_deg > 0.0 || world.sun(sunrise + 60.0).elevation_deg <= 0.0 {
        sunrise += 60.0;
    }
    for hours in [0.5, 1.0, 1.5, 2.5] {
        let t0 = sunrise + hours * 3600.0;
        let start = Start { cell: world.cell(0, 1), t_min: t0, t_max: t0, energy_wh: 135.0 };
        let goals = [ExactGoal { cell: world.cell(7, 1), open_s: t0, close_s: t0 + 10.0 * 3600.0 }];
        check(&world, &ridge_model, start, &goals, &format!("ridge, {hours} h after sunrise"));
    }
    let (world, t0) = gale_morning();
    let model = model(400.0, ActionConfig { energy_quantum_wh: 5.0, ..actions(1800.0) });
    for hours in [7.0, 9.0, 11.0] {
        let goals = [
            ExactGoal { cell: world.cell(1, 1), open_s: t0, close_s: t0 + hours * 3600.0 },
            ExactGoal { cell: world.cell(5, 4), open_s: t0, close_s: t0 + hours * 3600.0 },
        ];
        let start = Start { cell: world.cell(6, 0), t_min: t0, t_max: t0, energy_wh: 360.0 };
        check(&world, &model, start, &goals, &format!("Gale, {hours} h"));
    }
    assert!(planned >= 8 && proven >= 2, "{planned} planned, {proven} proven unreachable: the cases test too little");
    assert!(jumps >= 100, "only {jumps} waits jumped: the rule is not exercised");
    assert!(waited >= 2, "only {waited} plans wait: the cases never need a wait");
}

/// With terrain classes slower and faster than the rover's own model, hungrier and
/// thriftier (seeded per cell), the exact search still equals the Dijkstra: the bounds
/// its heuristic rests on take the classes' extremes.
#[test]
fn terrain_classes_keep_the_exact_search_equal_to_the_dijkstra() {
    let classes = vec![
        areo_mission::TerrainClass { name: "sand".into(), speed_factor: 0.5, power_factor: 1.8, max_slope_deg: None },
        areo_mission::TerrainClass {
            name: "hardpan".into(),
            speed_factor: 1.6,
            power_factor: 0.6,
            max_slope_deg: None,
        },
    ];
    let (mut planned, mut differs) = (0, 0);
    for seed in 0..16 {
        let mut c = case(seed, 3.0);
        let model = model(150.0, actions(900.0));
        let plain = exact(&c, &model).plan.map(|p| p.0);
        let mut r = Seeds(seed + 77);
        let cells = (0..c.world.cells()).map(|_| [0u8, 1, areo_mission::UNCLASSIFIED][(r.next() * 3.0) as usize % 3]);
        let ground = areo_mission::ClassMap::new(classes.clone(), cells.collect()).unwrap();
        c.world.set_ground(std::sync::Arc::new(ground)).unwrap();
        let out = exact(&c, &model);
        assert!(!out.stopped);
        let brute = brute_force(&c.world, &model, c.start, &c.goals, 0.0);
        let cost = out.plan.as_ref().map(|p| p.0);
        if agree(cost, brute, &format!("seed {seed} with classes")) {
            planned += 1;
        }
        let fastest = exact_by(Objective::Time, &c.world, c.start, &c.goals, &model);
        let brute = brute_force_by(Objective::Time, &c.world, &model, c.start, &c.goals, 0.0);
        agree(fastest.plan.map(|p| p.0), brute, &format!("seed {seed} with classes, fastest"));
        if cost.zip(plain).is_some_and(|(a, b)| (a - b).abs() > 1e-6) || cost.is_some() != plain.is_some() {
            differs += 1;
        }
    }
    assert!(planned >= 6, "only {planned} seeded cases plan");
    assert!(differs >= 4, "the classes change only {differs} plans: the test tests little");
}

/// On the Gale crop with the gale-ground scenario's class factors (rough 0.7 × speed and
/// 1.3 × power on the steeper half of the cells, the rover's own model on the rest) and a
/// hardpan faster and thriftier than the rover's model on the gentlest cells: the exact
/// search still equals the Dijkstra, and the classes change what the plans cost.
#[test]
fn on_the_gale_crop_with_terrain_classes_the_exact_search_equals_a_dijkstra() {
    let (mut world, t0) = gale_morning();
    let model = model(400.0, ActionConfig { energy_quantum_wh: 5.0, ..actions(1800.0) });
    let goals = [
        ExactGoal { cell: world.cell(1, 1), open_s: t0, close_s: t0 + 11.0 * 3600.0 },
        ExactGoal { cell: world.cell(5, 4), open_s: t0, close_s: t0 + 11.0 * 3600.0 },
    ];
    let start = Start { cell: world.cell(6, 0), t_min: t0, t_max: t0, energy_wh: 150.0 };
    let plain = exact_by(Objective::Energy, &world, start, &goals, &model).plan.map(|p| p.0);
    let mut slopes: Vec<f64> = (0..world.cells() as u32).map(|c| world.slope_deg(c)).collect();
    slopes.sort_by(f64::total_cmp);
    let (gentle, median) = (slopes[slopes.len() / 4], slopes[slopes.len() / 2]);
    let class = |name: &str, speed: f64, power: f64| areo_mission::TerrainClass {
        name: name.into(),
        speed_factor: speed,
        power_factor: power,
        max_slope_deg: None,
    };
    let cells = (0..world.cells() as u32)
        .map(|c| match world.slope_deg(c) {
            s if s >= median => 0,
            s if s <= gentle => 1,
            _ => areo_mission::UNCLASSIFIED,
        })
        .collect();
    let classes = vec![class("rough", 0.7, 1.3), class("hardpan", 1.4, 0.8)];
    world.set_ground(std::sync::Arc::new(areo_mission::ClassMap::new(classes, cells).unwrap())).unwrap();
    for objective in [Objective::Energy, Objective::Time] {
        let out = exact_by(objective, &world, start, &goals, &model);
        assert!(!out.stopped);
        let brute = brute_force_by(objective, &world, &model, start, &goals, 0.0);
        let cost = out.plan.as_ref().map(|p| p.0);
        assert!(agree(cost, brute, &format!("{objective:?} with classes")), "a plan exists");
        if objective == Objective::Energy {
            let (a, b) = (cost.unwrap(), plain.expect("a plan without classes"));
            assert!((a - b).abs() > 1e-3, "the classes change nothing: {a} vs {b}");
        }
    }
}
