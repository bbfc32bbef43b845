//! The selectable objectives and the Pareto front against an exhaustive enumeration.
//!
//! On the small morning world of the Pareto tests (quantised actions, classes as fine as
//! the quanta) every plan the planner's discretisation allows is enumerated backward from
//! each goal instant: at each (cell, minute) the set of every distinct (energy used,
//! battery needed) of the ways on to the goal — no dominance, no bound. The start
//! window's minutes then give every plan's (arrival, energy used, margin, departure).
//! The front must equal the non-dominated set of these; the Time and EnergyUsed
//! objectives their least duration and least energy used.

use rustc_hash::FxHashSet;

use areo_mission::{ActionModel, Classes, Mission, Objective, SearchMode, Start, World, non_dominated};

use crate::common::*;
use crate::pareto::{config, morning, quantised, world};

/// One plan's measures: (arrival s, energy used Wh, margin Wh, departure s).
type Outcome = (f64, f64, f64, f64);

/// Every plan of `mission`'s discretisation to `goal`, by its measures (distinct ones).
fn every_plan(world: &World, model: &ActionModel, mission: &Mission<'_>, goal: u32) -> Vec<Outcome> {
    let start = mission.start();
    let capacity = model.capacity_wh();
    let first = (start.t_min / 60.0).ceil() as i64;
    let key = |x: f64| (x * 1e6).round() as i64;
    let mut out = Vec::new();
    let mut memo = MoveMemo::new(world, model);
    for g in mission.final_goal_times().iter().map(|t| (t / 60.0).round() as i64) {
        let span = (g - first + 1).max(0) as usize;
        if span == 0 {
            continue;
        }
        // ways[i][cell]: (used, need) of every way from (cell, first + i) to the goal at g.
        let mut ways: Vec<Vec<FxHashSet<(i64, i64)>>> = vec![vec![FxHashSet::default(); world.cells()]; span];
        ways[span - 1][goal as usize].insert((0, key(0.0)));
        for i in (0..span - 1).rev() {
            let t = (first + i as i64) as f64 * 60.0;
            for cell in 0..world.cells() as u32 {
                let mut here = FxHashSet::default();
                for &(_, to, e) in memo.at(cell, t) {
                    let j = i + (e.duration_s / 60.0).round() as usize;
                    if j >= span {
                        continue;
                    }
                    for &(used, need) in &ways[j][to as usize] {
                        let after = need as f64 / 1e6;
                        let need = e.required_before(after);
                        if need <= capacity + 1e-9 && e.fits(after, capacity) {
                            here.insert((used + key(e.load_wh), key(need)));
                        }
                    }
                }
                ways[i][cell as usize] = here;
            }
        }
        for (i, row) in ways.iter().enumerate() {
            let t = (first + i as i64) as f64 * 60.0;
            if t > start.t_max + 1e-9 {
                break;
            }
            let battery = start.energy_wh - model.idle_wh(t - start.t_min);
            for &(used, need) in &row[start.cell as usize] {
                let margin = battery - need as f64 / 1e6;
                if margin >= -1e-9 {
                    out.push((g as f64 * 60.0, used as f64 / 1e6, margin, t));
                }
            }
        }
    }
    out
}

fn triples(outcomes: &[Outcome]) -> Vec<(f64, f64, f64)> {
    outcomes.iter().map(|o| (o.0, o.1, o.2)).collect()
}

fn sorted(mut v: Vec<(f64, f64, f64)>) -> Vec<(f64, f64, f64)> {
    v.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.total_cmp(&b.2)));
    v
}

const ROUTES: [((usize, usize), (usize, usize)); 3] = [((0, 0), (4, 3)), ((4, 0), (0, 3)), ((0, 2), (5, 2))];
const ACROSS: [((usize, usize), (usize, usize)); 3] = [((0, 3), (6, 3)), ((0, 4), (6, 2)), ((1, 2), (6, 4))];

#[test]
fn the_pareto_front_equals_the_non_dominated_plans_of_an_exhaustive_enumeration() {
    let world = world();
    let t0 = morning(&world);
    let model = model(400.0, quantised());
    let (mut largest, mut compared) = (0, 0);
    for (from, to) in ROUTES {
        for start_wh in [8.0, 30.0] {
            let start = Start { cell: world.cell(from.0, from.1), t_min: t0, t_max: t0, energy_wh: start_wh };
            let goal = world.cell(to.0, to.1);
            let cfg = areo_mission::PlannerConfig {
                search: SearchMode::Approximate(Classes {
                    goal_times: 6,
                    ..*config(Objective::Energy).search.classes().expect("approximate")
                }),
                ..config(Objective::Energy)
            };
            let (mission, _) = Mission::plan(&world, &model, cfg, start, &[goal]).unwrap();
            let front = mission.pareto_front(1e-6).unwrap();
            let all = triples(&every_plan(&world, &model, &mission, goal));
            let brute = sorted(non_dominated(&all).into_iter().map(|i| all[i]).collect());
            let got = sorted(front.plans.iter().map(|p| (p.arrival_s, p.energy_used_wh, p.margin_wh)).collect());
            assert_eq!(got.len(), brute.len(), "{from:?}→{to:?} {start_wh} Wh: front {got:?}\nexhaustive {brute:?}");
            for (a, b) in got.iter().zip(&brute) {
                assert!(
                    (a.0 - b.0).abs() < 1e-6 && (a.1 - b.1).abs() < 1e-6 && (a.2 - b.2).abs() < 1e-6,
                    "{from:?}→{to:?} {start_wh} Wh: front {a:?} vs exhaustive {b:?}"
                );
            }
            // Each front plan replays to what it claims: its battery never below the
            // floor by more than its margin says, its arrival at the goal instant.
            for p in &front.plans {
                let last = p.plan.waypoints.last().unwrap();
                assert_eq!(last.cell, goal);
                assert!((last.t_s - p.arrival_s).abs() < 1e-6);
                let floor = model.rover().battery.capacity_wh * model.rover().battery.min_soc;
                assert!(p.plan.min_battery_wh() - floor >= p.margin_wh - 1e-6);
            }
            largest = largest.max(got.len());
            compared += 1;
        }
    }
    assert_eq!(compared, 6);
    // The measures trade: some front holds several plans, so the test compares fronts,
    // not single optima.
    assert!(largest >= 3, "the largest front has {largest} plans: the cases do not trade");
}

/// The front's searches spend the mission's expansion allowance: a front that would
/// need more stops with `WorkLimit` — never a shorter front passed off as whole.
#[test]
fn the_front_stops_at_the_expansion_limit_rather_than_end_short() {
    let world = world();
    let t0 = morning(&world);
    let model = model(400.0, quantised());
    let (from, to) = ROUTES[0];
    let start = Start { cell: world.cell(from.0, from.1), t_min: t0, t_max: t0, energy_wh: 30.0 };
    let goal = world.cell(to.0, to.1);
    let cfg = areo_mission::PlannerConfig {
        search: SearchMode::Approximate(Classes {
            goal_times: 6,
            ..*config(Objective::Energy).search.classes().expect("approximate")
        }),
        ..config(Objective::Energy)
    };
    let (mission, _) = Mission::plan(&world, &model, cfg.clone(), start, &[goal]).unwrap();
    let whole = mission.pareto_front(1e-6).unwrap();
    assert!(whole.expansions > 10 && whole.plans.len() >= 2, "{} expansions", whole.expansions);
    // Enough for the plan, not for the front: the limit stops the walk.
    let capped = areo_mission::PlannerConfig { max_expansions: Some(whole.expansions / 2), ..cfg };
    let (mission, _) = Mission::plan(&world, &model, capped, start, &[goal]).unwrap();
    match mission.pareto_front(1e-6) {
        // At the limit, or past it by the last expansion's comparisons.
        Err(areo_mission::Error::WorkLimit { expansions, limit }) => {
            assert!((limit..=limit + 1).contains(&expansions), "{expansions} of {limit}")
        }
        other => panic!("{other:?}"),
    }
}

/// A ridge across the middle columns with a pass at the bottom row: over it is shorter,
/// around it flatter.
fn ridge() -> World {
    let dem = areo_terrain::Dem::from_fn(7, 5, 20.0, 20.0, |x, y| {
        let across = (-((x - 70.0) / 25.0).powi(2)).exp();
        let pass = if y < 30.0 { 0.2 } else { 1.0 };
        RIDGE_M * across * pass
    })
    .unwrap();
    mars_world(dem, 30.0, None)
}

const RIDGE_M: f64 = 6.0;

#[test]
fn the_time_and_energy_used_objectives_equal_the_exhaustive_optima() {
    let world = ridge();
    let t0 = morning(&world);
    let model = model(400.0, quantised());
    let mut differ = 0;
    for (from, to) in ACROSS {
        let start = Start { cell: world.cell(from.0, from.1), t_min: t0, t_max: t0, energy_wh: 30.0 };
        let goal = world.cell(to.0, to.1);
        let plan_with = |objective| {
            let cfg = areo_mission::PlannerConfig {
                search: SearchMode::Approximate(Classes {
                    goal_times: 6,
                    ..*config(objective).search.classes().expect("approximate")
                }),
                ..config(objective)
            };
            Mission::plan(&world, &model, cfg, start, &[goal]).unwrap()
        };
        let (fast_mission, fast) = plan_with(Objective::Time);
        let every = every_plan(&world, &model, &fast_mission, goal);
        let least_time = every.iter().map(|o| o.0 - o.3).fold(f64::INFINITY, f64::min);
        assert!(
            (fast.duration_s() - least_time).abs() < 1e-6,
            "{from:?}→{to:?}: Time objective {} s, exhaustive {least_time} s",
            fast.duration_s()
        );
        let (frugal_mission, frugal) = plan_with(Objective::EnergyUsed);
        let every = every_plan(&world, &model, &frugal_mission, goal);
        let least_used = every.iter().map(|o| o.1).fold(f64::INFINITY, f64::min);
        // The plan's cost is the energy used plus the wait-late bias (a millionth of a
        // wait's load per wait).
        assert!(
            (frugal.cost - least_used).abs() < 1e-3,
            "{from:?}→{to:?}: EnergyUsed objective {} Wh, exhaustive {least_used} Wh",
            frugal.cost
        );
        // Whether the fastest plans draw more than the most frugal one.
        let fastest_used =
            every.iter().filter(|o| o.0 - o.3 <= least_time + 1e-6).map(|o| o.1).fold(f64::INFINITY, f64::min);
        if fastest_used > least_used + 1e-6 {
            differ += 1;
        }
    }
    // The two objectives disagree on two of the three routes (over the ridge is faster,
    // around it draws less): each is tested on its own.
    assert!(differ >= 2, "the fastest plans draw least on every route");
}

/// The Time and EnergyUsed heuristics obey the triangle inequality over every step the
/// search takes (what keeps re-plans on kept graphs exact) and vanish at the start: on
/// the ridge world, at every cell and minute of three hours, no step from a label costs
/// less than the fall of the heuristic across it.
#[test]
fn the_time_and_energy_used_heuristics_are_consistent() {
    use areo_ise::Domain;
    use areo_mission::{Label, PathLength, Resolution, TempestDomain};
    let world = ridge();
    let t0 = morning(&world);
    let model = model(400.0, quantised());
    let start = Start { cell: world.cell(1, 2), t_min: t0, t_max: t0 + 600.0, energy_wh: 30.0 };
    let resolution = Resolution { time_s: 60.0, energy_wh: None };
    for objective in [Objective::Time, Objective::EnergyUsed] {
        let domain = TempestDomain::new(&world, &model, start, objective, resolution, PathLength::Distance);
        assert_eq!(domain.heuristic(start.cell, &Label { t: t0 + 300.0, e: 0.0 }), 0.0);
        let (mut steps, mut tight) = (0, 0);
        for cell in 0..world.cells() as u32 {
            for m in 0..180 {
                let label = Label { t: t0 + 600.0 + 60.0 * f64::from(m), e: 5.0 };
                let h = domain.heuristic(cell, &label);
                domain.expand(
                    cell,
                    &label,
                    |_| true,
                    |a, step| {
                        let fall = h - domain.heuristic(step.state, &step.label);
                        assert!(
                            fall <= step.cost + 1e-9,
                            "{objective:?} {a:?} into cell {cell} at {} s: heuristic falls {fall}, step costs {}",
                            label.t,
                            step.cost
                        );
                        steps += 1;
                        if fall > 0.5 * step.cost {
                            tight += 1;
                        }
                    },
                );
            }
        }
        // How well each guides: Time's bound falls by more than half the cost across most
        // steps; EnergyUsed's across about 15 % (7 842 of 50 760) — the weak bound that
        // makes the Pareto front slow (docs/benchmarks.md).
        let share = tight as f64 / steps as f64;
        let least = if objective == Objective::Time { 0.5 } else { 0.1 };
        assert!(steps > 10_000 && share > least, "{objective:?}: {tight} of {steps} steps tight");
    }
}
