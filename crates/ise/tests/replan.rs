//! Re-planning equals planning from scratch: random grids, random sequences of cost
//! increases and decreases, new and cleared obstacles near and far from the start, and
//! start moves along the current path.

use areo_ise::grid::Grid;
use areo_ise::{Goal, Mode, Plan, Search};
use proptest::prelude::*;

#[derive(Debug, Clone)]
enum Op {
    Weight {
        cell: u32,
        weight: u8,
    },
    Block {
        cell: u32,
    },
    Clear {
        cell: u32,
    },
    /// Change within 2 cells of the start (TEMPEST's sensing radius).
    NearStart {
        dx: i8,
        dy: i8,
        kind: u8,
    },
    /// Move the start `steps` cells along the current plan.
    Advance {
        steps: u8,
    },
}

fn op(cells: u32) -> impl Strategy<Value = Op> {
    prop_oneof![
        (0..cells, 1u8..6).prop_map(|(cell, weight)| Op::Weight { cell, weight }),
        (0..cells).prop_map(|cell| Op::Block { cell }),
        (0..cells).prop_map(|cell| Op::Clear { cell }),
        (-2i8..=2, -2i8..=2, 0u8..4).prop_map(|(dx, dy, kind)| Op::NearStart { dx, dy, kind }),
        (1u8..4).prop_map(|steps| Op::Advance { steps }),
    ]
}

fn check_path(grid: &Grid, plan: &Plan<Grid>, goal: u32) {
    let path = plan.path.as_ref().unwrap();
    assert_eq!(path[0].state, grid.start());
    assert_eq!(path.last().unwrap().state, goal);
    let mut walked = 0.0;
    for w in path.windows(2) {
        let (_, c) = grid.neighbours(w[0].state).find(|(b, _)| *b == w[1].state).expect("path steps are legal moves");
        walked += c;
        assert!((w[1].cost_so_far - walked).abs() < 1e-9);
    }
    assert!((walked - plan.cost).abs() < 1e-9);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn replanning_equals_fresh_search(
        w in 4u32..14,
        h in 4u32..12,
        seed_cells in prop::collection::vec((any::<bool>(), 1u8..4), 16 * 12),
        start_goal in (any::<u32>(), any::<u32>()),
        ops in prop::collection::vec(op(14 * 12), 1..25),
    ) {
        let mut grid = Grid::new(w, h);
        let cells = w * h;
        let nth = |grid: &Grid, i: u32| grid.cell(i % cells % w, i % cells / w);
        for i in 0..cells {
            let c = nth(&grid, i);
            let (blocked, weight) = seed_cells[i as usize];
            grid.set_free(c, !(blocked && i % 3 == 0));
            grid.set_weight(c, f32::from(weight));
        }
        let start = nth(&grid, start_goal.0);
        let goal = nth(&grid, start_goal.1);
        grid.set_free(start, true);
        grid.set_free(goal, true);
        grid.set_start(start);
        let goal_label = Goal { state: goal, label: (), cost: 0.0 };
        let mut search = Search::new(&grid, [goal_label.clone()], Mode::BestPathCost);
        let mut plan = search.plan(&grid);
        for op in ops {
            let mut changed = Vec::new();
            match op {
                Op::Weight { cell, weight } => {
                    let cell = nth(&grid, cell);
                    grid.set_weight(cell, f32::from(weight));
                    changed = grid.changed_states(cell, false);
                }
                Op::Block { cell } => {
                    let cell = nth(&grid, cell);
                    if cell != goal && cell != grid.start() {
                        grid.set_free(cell, false);
                        changed = grid.changed_states(cell, true);
                    }
                }
                Op::Clear { cell } => {
                    let cell = nth(&grid, cell);
                    grid.set_free(cell, true);
                    changed = grid.changed_states(cell, true);
                }
                Op::NearStart { dx, dy, kind } => {
                    let (sx, sy) = grid.xy(grid.start());
                    let (x, y) = (i64::from(sx) + i64::from(dx), i64::from(sy) + i64::from(dy));
                    if grid.contains(x, y) {
                        let cell = grid.cell(x as u32, y as u32);
                        match kind {
                            0 if cell != goal && cell != grid.start() => grid.set_free(cell, false),
                            1 => grid.set_free(cell, true),
                            _ => grid.set_weight(cell, f32::from(kind) + 0.5),
                        }
                        changed = grid.changed_states(cell, kind <= 1);
                    }
                }
                Op::Advance { steps } => {
                    if let Some(path) = &plan.path {
                        let i = (steps as usize).min(path.len() - 1);
                        grid.set_start(path[i].state);
                        search.start_moved(&grid);
                    }
                }
            }
            if !changed.is_empty() {
                search.update(&grid, &changed);
            }
            plan = search.plan(&grid);
            let fresh = Search::new(&grid, [goal_label.clone()], Mode::BestPathCost).plan(&grid);
            match (&plan.path, &fresh.path) {
                (Some(_), Some(_)) => {
                    prop_assert!((plan.cost - fresh.cost).abs() < 1e-9, "incremental {} vs fresh {}", plan.cost, fresh.cost);
                    check_path(&grid, &plan, goal);
                }
                (None, None) => {}
                (a, b) => prop_assert!(false, "incremental found {}, fresh found {}", a.is_some(), b.is_some()),
            }
        }
    }
}

/// Hundreds of re-plans on one graph: weights change all over a 160 × 160 grid, so
/// repairs remove large subtrees. Nodes that no longer serve a purpose are reclaimed,
/// so the graph's memory stays flat, and every answer still equals a fresh search.
#[test]
fn memory_stays_flat_over_hundreds_of_replans() {
    let (w, h) = (160u32, 160u32);
    let mut grid = Grid::new(w, h);
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut next = move |n: u32| {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng % u64::from(n)) as u32
    };
    for c in 0..w * h {
        grid.set_weight(c, 1.0 + next(3) as f32);
    }
    grid.set_start(grid.cell(5, 5));
    let goal = Goal { state: grid.cell(150, 150), label: (), cost: 0.0 };
    let mut search = Search::new(&grid, [goal.clone()], Mode::BestPathCost);
    let mut plan = search.plan(&grid);
    let first_bytes = search.bytes();
    let (mut reclaimed, mut peak, mut invalidated) = (0, 0, 0);
    for round in 0..300 {
        // A cell on the current route: its subtree (everything planned through it) goes.
        let path = plan.path.as_ref().expect("the grid is open");
        let cell = path[next(path.len() as u32) as usize].state;
        grid.set_weight(cell, 1.0 + next(4) as f32);
        let repair = search.update(&grid, &grid.changed_states(cell, false));
        (reclaimed, invalidated) = (reclaimed + repair.reclaimed, invalidated + repair.invalidated);
        plan = search.plan(&grid);
        reclaimed += plan.stats.reclaimed;
        peak = peak.max(search.bytes());
        let fresh = Search::new(&grid, [goal.clone()], Mode::BestPathCost).plan(&grid);
        assert!((plan.cost - fresh.cost).abs() < 1e-9, "round {round}: {} vs {}", plan.cost, fresh.cost);
    }
    // Without reclaiming, the 600 k nodes the repairs removed stay: the graph grew to
    // 15 times its first size.
    assert!(invalidated > 300_000, "{invalidated} nodes removed: the repairs were too small to test this");
    assert!(reclaimed > invalidated / 2, "{reclaimed} of {invalidated} removed nodes reclaimed");
    assert!(peak <= 2 * first_bytes, "the graph grew from {first_bytes} to {peak} bytes");
}
