//! ISE on Moving AI grids against the `pathfinding` crate's A* (same neighbour
//! function, same octile heuristic): fresh searches on a 512 and a 1024 map, and
//! re-planning after a change within 2 cells of the start (TEMPEST's sensing model).
//!
//! Maps come from ../shared/data/movingai when present (the 1024 map lives only
//! there), else from this crate's test data.

#![allow(clippy::print_stderr)] // the bench reports the graph's size once per map

use std::hint::black_box;
use std::ops::Add;
use std::path::PathBuf;

use areo_ise::grid::{Grid, Scenario, parse_scenarios};
use areo_ise::{Goal, Mode, Search};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use pathfinding::num_traits::Zero;

/// f64 with a total order, for the peer's `Ord` cost bound.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cost(f64);
impl Eq for Cost {}
impl PartialOrd for Cost {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Cost {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0)
    }
}
impl Add for Cost {
    type Output = Cost;
    fn add(self, o: Cost) -> Cost {
        Cost(self.0 + o.0)
    }
}
impl Zero for Cost {
    fn zero() -> Cost {
        Cost(0.0)
    }
    fn is_zero(&self) -> bool {
        self.0 == 0.0
    }
}

fn load(rel: &str) -> Option<(Grid, Vec<Scenario>)> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let name = rel.rsplit('/').next().unwrap();
    let candidates =
        [root.join("../../../shared/data/movingai").join(rel), root.join("tests/data/movingai").join(name)];
    let map_path = candidates.iter().find(|p| p.exists())?;
    let grid = Grid::parse_movingai(&std::fs::read_to_string(map_path).ok()?).ok()?;
    let scen = parse_scenarios(&std::fs::read_to_string(map_path.with_extension("map.scen")).ok()?).ok()?;
    Some((grid, scen))
}

/// The 10 longest scenarios: the searches that cover most of the map.
fn longest(scen: &[Scenario]) -> Vec<Scenario> {
    let mut v = scen.to_vec();
    v.sort_by(|a, b| b.optimal.total_cmp(&a.optimal));
    v.truncate(10);
    v
}

fn ise_cost(grid: &mut Grid, s: &Scenario) -> f64 {
    grid.set_start(grid.cell(s.start_x, s.start_y));
    let goal = Goal { state: grid.cell(s.goal_x, s.goal_y), label: (), cost: 0.0 };
    Search::new(&*grid, [goal], Mode::BestPathCost).plan(grid).cost
}

fn peer_cost(grid: &Grid, s: &Scenario) -> f64 {
    let start = grid.cell(s.start_x, s.start_y);
    let goal = grid.cell(s.goal_x, s.goal_y);
    pathfinding::prelude::astar(
        &start,
        |&c| grid.neighbours(c).map(|(n, k)| (n, Cost(k))).collect::<Vec<_>>(),
        |&c| Cost(grid.octile(c, goal)),
        |&c| c == goal,
    )
    .map_or(f64::INFINITY, |(_, c)| c.0)
}

fn fresh(c: &mut Criterion) {
    let mut g = c.benchmark_group("grid_fresh");
    g.sample_size(10);
    for rel in ["bg512/AR0011SR.map", "street/Berlin_1_1024.map"] {
        let Some((mut grid, scen)) = load(rel) else {
            eprintln!("skipping {rel}: not found");
            continue;
        };
        let name = rel.rsplit('/').next().unwrap();
        let picks = longest(&scen);
        for s in &picks {
            let (a, b) = (ise_cost(&mut grid, s), peer_cost(&grid, s));
            assert!(
                (a - b).abs() < 1e-6 && (a - s.optimal).abs() < 1e-3,
                "{name}: ise {a}, peer {b}, published {}",
                s.optimal
            );
        }
        g.bench_function(BenchmarkId::new("ise", name), |b| {
            b.iter(|| picks.iter().map(|s| ise_cost(&mut grid, s)).sum::<f64>())
        });
        g.bench_function(BenchmarkId::new("pathfinding_astar", name), |b| {
            b.iter(|| picks.iter().map(|s| peer_cost(&grid, s)).sum::<f64>())
        });
    }
    g.finish();
}

fn replan(c: &mut Criterion) {
    let mut g = c.benchmark_group("grid_replan");
    g.sample_size(20);
    for rel in ["bg512/AR0011SR.map", "street/Berlin_1_1024.map"] {
        let Some((mut grid, scen)) = load(rel) else { continue };
        let name = rel.rsplit('/').next().unwrap();
        let s = longest(&scen)[0];
        let start = grid.cell(s.start_x, s.start_y);
        grid.set_start(start);
        let goal = Goal { state: grid.cell(s.goal_x, s.goal_y), label: (), cost: 0.0 };
        let mut search = Search::new(&grid, [goal], Mode::BestPathCost);
        let first = search.plan(&grid);
        // A free cell within 2 cells of the start, not the start itself.
        let (sx, sy) = grid.xy(start);
        let near = (-2i64..=2)
            .flat_map(|dy| (-2i64..=2).map(move |dx| (dx, dy)))
            .map(|(dx, dy)| (i64::from(sx) + dx, i64::from(sy) + dy))
            .filter(|&(x, y)| grid.contains(x, y))
            .map(|(x, y)| grid.cell(x as u32, y as u32))
            .find(|&c| c != start && grid.is_free(c))
            .expect("a free cell near the start");
        eprintln!(
            "{name}: initial search {} expansions, {} states, {:.1} bytes per generated state",
            first.stats.expansions,
            first.stats.generated,
            first.stats.bytes as f64 / first.stats.generated as f64
        );
        // Each iteration: block the cell and re-plan, then clear it and re-plan.
        g.bench_function(BenchmarkId::new("ise_update_and_plan_x2", name), |b| {
            b.iter(|| {
                grid.set_free(near, false);
                search.update(&grid, &[near]);
                let a = search.plan(&grid).cost;
                grid.set_free(near, true);
                search.update(&grid, &[near]);
                black_box(a + search.plan(&grid).cost)
            })
        });
        g.bench_function(BenchmarkId::new("ise_fresh_x2", name), |b| {
            b.iter(|| black_box(ise_cost(&mut grid, &s) + ise_cost(&mut grid, &s)))
        });
        g.bench_function(BenchmarkId::new("pathfinding_astar_x2", name), |b| {
            b.iter(|| black_box(peer_cost(&grid, &s) + peer_cost(&grid, &s)))
        });
    }
    g.finish();
}

criterion_group!(benches, fresh, replan);
criterion_main!(benches);
