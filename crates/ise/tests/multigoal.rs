//! Multi-goal seeding with initial costs equals a search from a super-source.

use areo_ise::grid::Grid;
use areo_ise::{Goal, Mode, Search};

use crate::brute::dijkstra;

#[test]
fn seeded_goals_equal_super_source_search() {
    let mut rng = 12345u64;
    let mut next = move |n: u64| {
        rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (rng >> 33) % n
    };
    for _ in 0..40 {
        let (w, h) = (12, 9);
        let mut grid = Grid::new(w, h);
        let nth = |grid: &Grid, i: u64| grid.cell(i as u32 % w, i as u32 / w);
        for i in 0..w * h {
            let c = nth(&grid, u64::from(i));
            if next(100) < 25 {
                grid.set_free(c, false);
            }
            grid.set_weight(c, 1.0 + next(3) as f32);
        }
        let start = nth(&grid, next(u64::from(w * h)));
        grid.set_free(start, true);
        grid.set_start(start);
        let goals: Vec<(u32, f64)> = (0..4)
            .map(|_| (nth(&grid, next(u64::from(w * h))), next(20) as f64 * 0.5))
            .filter(|(g, _)| grid.is_free(*g))
            .collect();
        let seeded = goals.iter().map(|&(g, c)| Goal { state: g, label: (), cost: c });
        let plan = Search::new(&grid, seeded, Mode::BestPathCost).plan(&grid);
        let brute = dijkstra(
            start,
            |c| grid.neighbours(c).collect(),
            |c| goals.iter().filter(|(g, _)| *g == c).map(|(_, k)| *k).reduce(f64::min),
        );
        match brute {
            Some(b) => {
                assert!((plan.cost - b).abs() < 1e-9, "super-source {b}, seeded {}", plan.cost);
                let path = plan.path.unwrap();
                let last = path.last().unwrap();
                let initial = goals.iter().filter(|(g, _)| *g == last.state).map(|(_, k)| *k).reduce(f64::min).unwrap();
                assert!((last.cost_so_far + initial - plan.cost).abs() < 1e-9);
            }
            None => assert!(plan.path.is_none()),
        }
    }
}
