//! The exact tick search against the Dijkstra with no dominance and no bound
//! ([`crate::exact::brute_force_by`]) where the goals ask more of a plan: a battery to
//! hold at the last goal, windows that open hours after the start (the rover must wait
//! for them or arrive late), and a last window that lies wholly between two ticks (only
//! a drive's own arrival, before its settle, can fall in it) — under L + B and Time.

use areo_mission::Objective;
use areo_mission::exact::{ExactGoal, ExactQuery};

use crate::common::model;
use crate::exact::{actions, brute_force_by, case};

const TICK_S: f64 = 900.0;

#[test]
fn goal_batteries_and_late_or_narrow_windows_keep_the_exact_search_equal_to_a_dijkstra() {
    let (mut planned, mut proven, mut late, mut narrow) = (0, 0, 0, 0);
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
}
