//! The exact tick search against the Dijkstra with no dominance and no bound
//! ([`crate::exact::brute_force_by`]) where the goals ask more of a plan: a battery to
//! hold at the last goal, windows that open hours after the start (the rover must wait
//! for them or arrive late), and a last window that lies wholly between two ticks (only
//! a drive's own arrival, before its settle, can fall in it) — under L + B and Time; and
//! the planner's own entry point on a tick under EnergyUsed and Margin.

use areo_mission::exact::{ExactGoal, ExactQuery};
use areo_mission::{Mission, Objective, PlannerConfig, SearchMode};

use crate::common::model;
use crate::exact::{actions, brute_force_by, case};

const TICK_S: f64 = 900.0;

#[test]
fn goal_batteries_and_late_or_narrow_windows_keep_the_exact_search_equal_to_a_dijkstra() {
    let (mut planned, mut proven, mut late, mut narrow, mut covered) = (0, 0, 0, 0, 0);
    for seed in 0..16u64 {
        let c = case(300 + seed, 5.0);
        let model = model(150.0, actions(TICK_S));
        let t0 = c.start.t_min;
        // The windows open 1.5 h after the start; for odd seeds the last one is 100 s
        // wide, from 20 s past a tick.
        let mut goals: Vec<ExactGoal> =
            c.goals.iter().map(|g| ExactGoal { open_s: t0 + 5400.0, close_s: t0 + 5.0 * 3600.0, ..*g }).collect();
        if seed % 2 == 1 {
            let last = goals.last_mut().unwrap();
            let from = ((t0 + 2.0 * 3600.0) / TICK_S).ceil() * TICK_S + 20.0;
            (last.open_s, last.close_s) = (from, from + 100.0);
        }
        for objective in [Objective::Energy, Objective::Time] {
            let goal_wh = 20.0;
            let out = ExactQuery {
                world: &c.world,
                model: &model,
                start: c.start,
                goals: goals.clone(),
                goal_energy_wh: goal_wh,
                objective,
                max_labels: 5_000_000,
                settle: true,
            }
            .solve();
            assert!(!out.stopped);
            covered += out.covered;
            let brute = brute_force_by(objective, &c.world, &model, c.start, &goals, goal_wh);
            let case = format!("seed {seed}, {objective:?}");
            match (&out.plan, brute) {
                (Some((cost, steps)), Some(b)) => {
                    assert!((cost - b).abs() < 1e-6 * (1.0 + b), "{case}: exact {cost} vs Dijkstra {b}");
                    // The last goal is reached with the battery asked for, within its window.
                    let end = steps.last().unwrap();
                    assert!(end.battery_wh >= goal_wh - 1e-9, "{case}: {end:?}");
                    // It is there on the drive's arrival and at the end of its settle: one of
                    // the two lies in the window.
                    let (arrival, settled) = (end.t_s + end.duration_s - end.settle_s, end.t_s + end.duration_s);
                    let window = goals.last().unwrap();
                    let within = |t: f64| t >= window.open_s - 1e-6 && t <= window.close_s + 1e-6;
                    assert!(within(arrival) || within(settled), "{case}: {end:?}");
                    if settled > t0 + 5400.0 - 1e-6 {
                        late += 1;
                    }
                    planned += 1;
                    narrow += usize::from(seed % 2 == 1);
                }
                (None, None) => proven += 1,
                (p, b) => panic!("{case}: exact {:?} vs Dijkstra {b:?}", p.as_ref().map(|p| p.0)),
            }
        }
    }
    assert!(
        planned >= 8 && proven >= 2 && late >= 4 && narrow >= 2,
        "{planned} planned ({narrow} into a window between ticks), {proven} proven, {late} late"
    );
    // Waiting for the windows, the drives after a wait are weighed against driving
    // first (`exact::waiting`): pruning them on the battery alone, without their cost,
    // loses the optimum here (tried).
    assert!(covered > 0, "no drive after a wait was found beaten by driving first");
}

/// Through the planner's own entry point (`Mission::plan` on a tick, its goal windows
/// made from the start, Margin's capped by its longest acceptable plan), under
/// EnergyUsed and Margin: the plan's cost is the Dijkstra's over the mission's windows,
/// and the planner proves "no plan" where the Dijkstra finds none.
#[test]
fn the_planner_on_a_tick_by_energy_used_and_margin_equals_a_dijkstra() {
    let (mut planned, mut proven) = (0, 0);
    for seed in 0..12u64 {
        let c = case(400 + seed, 5.0);
        let model = model(150.0, actions(TICK_S));
        let cells: Vec<u32> = c.goals.iter().map(|g| g.cell).collect();
        for objective in [Objective::EnergyUsed, Objective::Margin { max_duration_s: 4.0 * 3600.0 }] {
            let config = PlannerConfig {
                actions: actions(TICK_S),
                objective,
                search: SearchMode::Exact { tick_s: TICK_S },
                ..Default::default()
            };
            let case = format!("seed {seed}, {objective:?}");
            let (cost, windows) = match Mission::plan(&c.world, &model, config, c.start, &cells) {
                Ok((mission, plan)) => (Some(plan.cost), mission.goal_windows()),
                Err(areo_mission::Error::Unreachable { proven: true, .. }) => (None, Vec::new()),
                Err(e) => panic!("{case}: {e}"),
            };
            let Some(cost) = cost else {
                // No plan: the Dijkstra finds none over windows as wide as any the
                // planner could have made (to the horizon, or Margin's deadline).
                let close = match objective {
                    Objective::Margin { max_duration_s } => c.start.t_min + max_duration_s,
                    _ => c.world.span_s(),
                };
                let goals: Vec<ExactGoal> =
                    cells.iter().map(|&cell| ExactGoal { cell, open_s: 0.0, close_s: close }).collect();
                assert_eq!(brute_force_by(objective, &c.world, &model, c.start, &goals, 0.0), None, "{case}");
                proven += 1;
                continue;
            };
            let goals: Vec<ExactGoal> = cells
                .iter()
                .zip(&windows)
                .map(|(&cell, &(open_s, close_s))| ExactGoal { cell, open_s, close_s })
                .collect();
            let brute = brute_force_by(objective, &c.world, &model, c.start, &goals, 0.0).expect(&case);
            assert!((cost - brute).abs() < 1e-6 * (1.0 + brute), "{case}: planner {cost} vs Dijkstra {brute}");
            planned += 1;
        }
    }
    assert!(planned >= 8, "{planned} planned, {proven} proven");
}
