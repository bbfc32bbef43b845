//! `areo grid`: solve Moving AI benchmark scenarios with the ISE, optionally
//! re-planning after seeded obstacles appear near the start.

use std::path::Path;

use areo_ise::grid::{Grid, Scenario, parse_scenarios};
use areo_ise::{Goal, Mode, Search};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::error::{Error, Result};
use crate::progress::Progress;

/// Options for [`solve_file`].
#[derive(Debug, Clone, Copy, Default)]
pub struct GridOptions {
    /// Block this many random free cells within 2 cells of each start, re-plan
    /// incrementally and check against a fresh search.
    pub replan: Option<u32>,
    /// Seed for the blocked cells.
    pub seed: u64,
}

/// The result of one scenario (`areo grid --format json` prints these as they are).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct GridRow {
    /// 0-based index of the scenario in the file.
    pub index: usize,
    /// The published optimal length.
    pub expected: f64,
    /// ISE's path cost (∞ if it found none).
    pub found: f64,
    /// Nodes expanded.
    pub expansions: u64,
    /// With `--replan`: the incremental search's cost after the cells were blocked.
    pub replanned: Option<f64>,
    /// With `--replan`: a fresh search's cost on the changed map.
    pub fresh: Option<f64>,
    /// With `--replan`: the expansions the repair needed.
    pub replan_expansions: Option<u64>,
    /// Whether the found length is off the published one by more than 1e-4 relative,
    /// or the re-plan disagrees with the fresh search.
    pub mismatched: bool,
}

impl GridRow {
    /// Sets `mismatched` from the costs.
    fn judged(mut self) -> GridRow {
        let off = |a: f64, b: f64| !((a - b).abs() <= 1e-4 * b.abs().max(1.0) || (a.is_infinite() && b.is_infinite()));
        let replan_off = self.replanned.zip(self.fresh).is_some_and(|(inc, fresh)| off(inc, fresh));
        self.mismatched = off(self.found, self.expected) || replan_off;
        self
    }
}

/// Reads a `.map` and its `.scen` and solves every scenario.
pub fn solve_file(
    map: &Path,
    scen: &Path,
    opts: GridOptions,
    progress: &dyn Progress,
    budget: crate::budget::Budget,
) -> Result<Vec<GridRow>> {
    let read = |p: &Path| crate::read_text(p).map_err(|source| Error::Read { path: p.to_path_buf(), source });
    let grid_err =
        |p: &Path, e: areo_ise::grid::GridError| Error::Grid { path: p.to_path_buf(), message: e.to_string() };
    let mut grid = Grid::parse_movingai(&read(map)?).map_err(|e| grid_err(map, e))?;
    let scenarios = parse_scenarios(&read(scen)?).map_err(|e| grid_err(scen, e))?;
    for (i, s) in scenarios.iter().enumerate() {
        for (what, x, y) in [("start", s.start_x, s.start_y), ("goal", s.goal_x, s.goal_y)] {
            if x >= grid.width() || y >= grid.height() || !grid.is_free(grid.cell(x, y)) {
                return Err(Error::Grid {
                    path: scen.to_path_buf(),
                    message: format!(
                        "scenario {i}: {what} ({x}, {y}) is off the {}x{} map or blocked",
                        grid.width(),
                        grid.height()
                    ),
                });
            }
        }
    }
    // Each search may expand every cell once (twice more with re-planning): refuse a
    // file set whose worst case is past the budget before searching.
    let cells = (grid.width() * grid.height()) as u64;
    let searches = scenarios.len() as u64 * if opts.replan.is_some() { 3 } else { 1 };
    budget.check(&crate::budget::Estimate {
        what: format!("{} searches on the {}x{} map", searches, grid.width(), grid.height()),
        memory_bytes: cells * 64,
        work_steps: searches.saturating_mul(cells),
        work_unit: "cell expansions",
    })?;
    progress.start(scenarios.len() as u64, "scenarios");
    let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
    let mut rows = Vec::with_capacity(scenarios.len());
    for (index, s) in scenarios.iter().enumerate() {
        rows.push(solve_one(&mut grid, index, s, opts.replan, &mut rng));
        progress.advance(1);
    }
    progress.finish();
    Ok(rows)
}

fn solve_one(grid: &mut Grid, index: usize, s: &Scenario, replan: Option<u32>, rng: &mut ChaCha8Rng) -> GridRow {
    let start = grid.cell(s.start_x, s.start_y);
    let goal_cell = grid.cell(s.goal_x, s.goal_y);
    grid.set_start(start);
    let goal = Goal { state: goal_cell, label: (), cost: 0.0 };
    let mut search = Search::new(&*grid, [goal.clone()], Mode::BestPathCost);
    let plan = search.plan(grid);
    let mut row = GridRow {
        index,
        expected: s.optimal,
        found: plan.cost,
        expansions: plan.stats.expansions,
        replanned: None,
        fresh: None,
        replan_expansions: None,
        mismatched: false,
    };
    let Some(k) = replan else { return row.judged() };
    // K random free cells within 2 cells of the start (never the start or the goal).
    let (sx, sy) = grid.xy(start);
    let mut candidates: Vec<u32> = (-2i64..=2)
        .flat_map(|dy| (-2i64..=2).map(move |dx| (i64::from(sx) + dx, i64::from(sy) + dy)))
        .filter(|&(x, y)| grid.contains(x, y))
        .map(|(x, y)| grid.cell(x as u32, y as u32))
        .filter(|&c| c != start && c != goal_cell && grid.is_free(c))
        .collect();
    let mut blocked = Vec::new();
    for _ in 0..k.min(candidates.len() as u32) {
        let c = candidates.swap_remove(rng.random_range(0..candidates.len()));
        grid.set_free(c, false);
        blocked.push(c);
    }
    let changed: Vec<u32> = blocked.iter().flat_map(|&c| grid.changed_states(c, true)).collect();
    search.update(grid, &changed);
    let repaired = search.plan(grid);
    let fresh = Search::new(&*grid, [goal], Mode::BestPathCost).plan(grid);
    (row.replanned, row.fresh, row.replan_expansions) =
        (Some(repaired.cost), Some(fresh.cost), Some(repaired.stats.expansions));
    for c in blocked {
        grid.set_free(c, true);
    }
    row.judged()
}
