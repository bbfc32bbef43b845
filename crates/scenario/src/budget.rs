//! What a job will cost, estimated before it starts: peak memory in bytes and work in
//! elementary steps (cell-sector rays, module executions, table rows). A job whose
//! estimate exceeds its [`Budget`] is refused ([`Error::Budget`], exit 2) with the
//! estimate, so a legal-looking but enormous input fails in a millisecond instead of
//! aborting on allocation or running for days.
//!
//! The per-cell figures are the libraries' own (`Dem::BYTES_PER_CELL`,
//! `HorizonMap::bytes_per_cell`, `World::estimate_bytes` — upper bounds read off the
//! data structures); they are meant to be within a factor of two of the measured peaks
//! (`docs/benchmarks.md`), and on the safe side. A TEMPEST job's searches are not
//! estimated but held to the budget as they run (a label expansion counts
//! [`EXPANSION_STEPS`] steps; [`search_allowance`]): what they expand depends on the
//! route and the battery, not on the map or the horizon, and a guess refused queries
//! that plan in a hundred expansions.

use crate::error::{Error, Result};
use crate::format::planner::SearchSpec;
use crate::format::{ActionsJob, Job, Scenario, TempestJob, TerrainSource, Truth};

/// The default work limit, steps.
pub const DEFAULT_WORK_STEPS: u64 = 20_000_000_000;

/// The limits a job must fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// Peak memory allowed, bytes.
    pub memory_bytes: u64,
    /// Elementary steps allowed.
    pub work_steps: u64,
}

impl Budget {
    /// Three quarters of this machine's memory (`/proc/meminfo`; 8 GiB where it cannot
    /// be read) and 2·10¹⁰ steps (the largest shipped up-front estimate, lita-scale's,
    /// is 2·10⁸; lunar-south-pole-10m's plan spends about 10⁹ as it runs). A step is
    /// about one horizon ray of a cell and sector (30–120 ns measured) and a label
    /// expansion counts [`EXPANSION_STEPS`], so the default is
    /// 10–40 minutes of work whichever kind spends it; the searches stop there
    /// ([`search_allowance`]).
    pub fn for_this_machine() -> Budget {
        let total = std::fs::read_to_string("/proc/meminfo")
            .ok()
            .and_then(|t| {
                let line = t.lines().find(|l| l.starts_with("MemTotal:"))?.to_string();
                line.split_whitespace().nth(1)?.parse::<u64>().ok()
            })
            .map_or(8 << 30, |kb| kb * 1024);
        Budget { memory_bytes: total / 4 * 3, work_steps: DEFAULT_WORK_STEPS }
    }

    /// Refuses `estimate` if it does not fit ([`Error::Budget`]).
    pub fn check(&self, estimate: &Estimate) -> Result<()> {
        if estimate.memory_bytes > self.memory_bytes || estimate.work_steps > self.work_steps {
            return Err(Error::Budget { estimate: estimate.clone(), limit: *self });
        }
        Ok(())
    }
}

/// The sentence refusing `estimate` under `limit`: memory first, then work.
pub(crate) fn refusal(estimate: &Estimate, limit: &Budget) -> String {
    if estimate.memory_bytes > limit.memory_bytes {
        format!(
            "{} needs about {} of memory, more than the {} allowed (raise it with --max-memory-gb)",
            estimate.what,
            gib(estimate.memory_bytes),
            gib(limit.memory_bytes)
        )
    } else {
        format!(
            "{} needs about {:.2e} steps of work ({}), more than the {:.2e} allowed (raise it with --max-work)",
            estimate.what, estimate.work_steps as f64, estimate.work_unit, limit.work_steps as f64
        )
    }
}

fn gib(bytes: u64) -> String {
    format!("{:.2} GiB", bytes as f64 / f64::from(1u32 << 30))
}

/// A job's estimated cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// What is being estimated, e.g. "the TEMPEST job on 2527 × 2356 cells".
    pub what: String,
    /// Peak memory, bytes.
    pub memory_bytes: u64,
    /// Elementary steps.
    pub work_steps: u64,
    /// What one step is.
    pub work_unit: &'static str,
}

/// Bytes per DEM cell held by a read or synthesised map (areo-terrain's figure).
const DEM_BYTES: u64 = areo_terrain::Dem::BYTES_PER_CELL;

/// The cost of `areo terrain shadow --tile`: one tile read with its halo at a time
/// (`window_cells`; its DEM, the own-ray method's views and bounds, the shadow map and
/// the Horn normals: about 60 bytes a cell), a band of results (`band_cells`, a byte
/// each) and the reader's chunk cache; every cell of the map computed once per tile
/// window it falls in.
pub fn tiled_shadow(map_cells: u64, tile: u64, window_cells: u64, band_cells: u64, cache_bytes: u64) -> Estimate {
    let tile_cells = tile.saturating_mul(tile).max(1);
    Estimate {
        what: format!(
            "`areo terrain shadow --tile {tile}` on {map_cells} cells (each tile read as {window_cells} cells with its halo)"
        ),
        memory_bytes: window_cells.saturating_mul(60).saturating_add(band_cells).saturating_add(cache_bytes),
        work_steps: map_cells.saturating_mul(window_cells.div_ceil(tile_cells).max(1)),
        work_unit: "cells computed",
    }
}

/// The cost of `areo terrain horizon --tile`: one tile read with its halo on every
/// side at a time (`window_cells`; its DEM and the horizon ray's codes and working
/// arrays: about 2 bytes a sector plus 24 bytes a cell), one tile of results (2 bytes
/// a cell and sector) and the reader's chunk cache; every window cell swept once per
/// sector.
pub fn tiled_horizon(map_cells: u64, sectors: u64, tile: u64, window_cells: u64, cache_bytes: u64) -> Estimate {
    let tile_cells = tile.saturating_mul(tile).max(1);
    let per_window_cell = DEM_BYTES + 24 + 2 * sectors;
    Estimate {
        what: format!(
            "`areo terrain horizon --tile {tile}` on {map_cells} cells, {sectors} sectors (each tile read as {window_cells} cells with its halo)"
        ),
        memory_bytes: window_cells
            .saturating_mul(per_window_cell)
            .saturating_add(tile_cells.saturating_mul(2 * sectors))
            .saturating_add(cache_bytes),
        work_steps: map_cells.saturating_mul(window_cells.div_ceil(tile_cells).max(1)).saturating_mul(sectors),
        work_unit: "cell-sector rays",
    }
}

/// A DEM command of `areo terrain`, as far as its cost goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DemCommand {
    /// `info`.
    Info,
    /// `slope`.
    Slope,
    /// `shadow` (whole map).
    Shadow,
    /// `viewshed`.
    Viewshed,
    /// `horizon` with this many sectors (whole map).
    Horizon {
        /// Horizon sectors.
        sectors: usize,
    },
}

impl DemCommand {
    /// The command's name after `areo terrain`.
    pub fn name(self) -> &'static str {
        match self {
            DemCommand::Info => "info",
            DemCommand::Slope => "slope",
            DemCommand::Shadow => "shadow",
            DemCommand::Viewshed => "viewshed",
            DemCommand::Horizon { .. } => "horizon",
        }
    }

    /// The command's cost on `cells` cells: the DEM and a few rasters (slope, aspect,
    /// map, preview RGB: 20 bytes a cell), and for `horizon` the map (2 bytes a sector)
    /// and its working codes; work is a ray per cell and sector.
    pub fn estimate(self, cells: u64) -> Estimate {
        let sectors = match self {
            DemCommand::Horizon { sectors } => sectors,
            _ => 0,
        };
        let horizon = if sectors > 0 { areo_terrain::horizon::HorizonMap::bytes_per_cell(sectors) + 4 } else { 0 };
        Estimate {
            what: format!("`areo terrain {}` on {cells} cells", self.name()),
            memory_bytes: cells.saturating_mul(DEM_BYTES + 20 + horizon),
            work_steps: cells.saturating_mul((sectors as u64).max(1)),
            work_unit: "cell-sector rays",
        }
    }
}

pub use areo_mission::search_cost::{CORRIDOR_CELLS, DETOUR, EXPANSION_STEPS, SearchMap};

/// The cost of a TEMPEST job on `map` that is certain before it starts: the worlds it
/// builds (the map's, the truth's, each terrain clone's: slopes, horizon maps, Sun
/// tables) and their horizon rays and open-loop executions. A job over the budget in
/// these would really exceed it, so it is refused before anything is computed.
///
/// The searches are not in it. What they expand depends on the route, the battery and
/// the Sun, not on the map's size or the horizon: a static route on a 256² crop of the
/// Gale map with 1000 goal instants over 300 h takes 143 expansions, where counting
/// cells × time classes estimated 10¹¹ steps and refused it. So the searches are held
/// to the budget while they run instead ([`search_allowance`] and the memory the
/// budget leaves beside the worlds): a search that would exceed it stops there with
/// the facts it has (exit 4), never refused on a guess. [`expected_expansions`] is
/// what a progress bar counts them against.
pub fn tempest(job: &TempestJob, map: SearchMap) -> Estimate {
    let cells = map.cells;
    let sectors = job.horizon_sectors as u64;
    let truth = !matches!(job.truth, Truth::Map);
    let (_, clones, executions) = chance_work(job);
    // A no-go mask sampled onto the map (16 bytes a cell), its codes (1) and its
    // inflation's distance transform (8), whatever `inflate_m`.
    let no_go = if job.no_go.is_some() { cells.saturating_mul(NO_GO_BYTES_PER_CELL) } else { 0 };
    let memory_bytes = areo_mission::World::estimate_bytes(cells, job.horizon_sectors, truth)
        .saturating_add(clones.saturating_mul(areo_mission::World::estimate_bytes(cells, job.horizon_sectors, false)))
        .saturating_add(no_go);
    Estimate {
        what: format!(
            "the TEMPEST job on {cells} cells ({sectors} horizon sectors, {clones} terrain clones, {executions} \
             open-loop executions; the searches are held to the budget as they run)"
        ),
        memory_bytes,
        work_steps: TempestWork::other(job, cells).min(u64::MAX as f64) as u64,
        work_unit: "cell-sector rays and execution steps",
    }
}

/// What a no-go mask holds per map cell while it is applied, bytes.
const NO_GO_BYTES_PER_CELL: u64 = 25;

/// The labels the searches of a TEMPEST job on `map` are expected to expand (see
/// [`tempest`]): what a progress bar counts them against.
pub fn expected_expansions(job: &TempestJob, map: SearchMap) -> u64 {
    TempestWork::labels(job, map).min(u64::MAX as f64) as u64
}

/// The label expansions one planning call of a TEMPEST job on `cells` cells may make
/// under `budget` (`areo_mission::PlannerConfig::max_expansions`): the work the budget
/// leaves after the job's horizon rays and executions, at [`EXPANSION_STEPS`] steps
/// an expansion — as if that one call were all the search the job does.
pub fn search_allowance(job: &TempestJob, cells: u64, budget: &Budget) -> u64 {
    let other = TempestWork::other(job, cells).min(u64::MAX as f64) as u64;
    (budget.work_steps.saturating_sub(other) / EXPANSION_STEPS).max(1)
}

/// A TEMPEST job's work, in the estimate's steps.
struct TempestWork;

impl TempestWork {
    /// The label expansions the searches are expected to make: for each leg (start to
    /// the first goal, then goal to goal), the cells within its detour ellipse
    /// ([`DETOUR`]; never more than the map) × time classes (horizon /
    /// `resolution.time_s`, or `tick_s` on a tick), per search. Each class holds a Pareto front in (cost,
    /// battery energy), a few labels in practice. An expectation, not a bound either
    /// way: a static route expands far fewer, a search whose battery is too low to move
    /// floods the map (fuzz seed 7 on devon-island expanded 4.8 M labels).
    fn labels(job: &TempestJob, map: SearchMap) -> f64 {
        let stops: Vec<(f64, f64)> =
            std::iter::once((job.start.x_m, job.start.y_m)).chain(job.goals.iter().map(|g| (g.x_m, g.y_m))).collect();
        let (searches, _, _) = chance_work(job);
        areo_mission::search_cost::expected_labels(&stops, map, job.horizon_h * 3600.0, step_s(job)) * searches as f64
    }

    /// The work besides the searches: horizon rays (the map's and the clones') and
    /// open-loop executions.
    fn other(job: &TempestJob, cells: u64) -> f64 {
        // Under uncertainty: a world per terrain clone (its slopes and horizon changes)
        // and a walk along the plan per open-loop execution.
        let (_, clones, executions) = chance_work(job);
        let sectors = job.horizon_sectors as u64;
        let time_classes = (job.horizon_h * 3600.0 / step_s(job)).ceil().max(1.0);
        let rays = cells.saturating_mul(sectors.max(1)).saturating_mul(clones.saturating_add(1)) as f64;
        rays + executions as f64 * time_classes
    }
}

/// The time step a TEMPEST job's labels are kept at, s: its tick, or its time classes.
fn step_s(job: &TempestJob) -> f64 {
    match &job.planner.search {
        SearchSpec::Exact { tick_s } => *tick_s,
        SearchSpec::Approximate(classes) => classes.resolution.time_s,
    }
}

/// A TEMPEST job's searches (the plan, the deterministic plan beside a
/// chance-constrained one, a mission per closed-loop run of each, the Pareto front's),
/// its terrain clones and its open-loop executions.
fn chance_work(job: &TempestJob) -> (u64, u64, u64) {
    // The Pareto front plans once more, then walks each goal instant's front: at most
    // one search per margin step of the starting battery (one per plan found, in
    // practice).
    let front = job.pareto_front.as_ref().map_or(0, |f| {
        let steps = (job.start_battery_above_floor_wh / f.step_wh()).floor().min(1e9) as u64 + 1;
        // On a tick the front is one search (its goal instants are every tick).
        let goal_times = job.planner.search.classes().copied().unwrap_or_default().goal_times;
        1u64.saturating_add((goal_times as u64).saturating_mul(steps))
    });
    let (searches, clones, executions) = uncertainty_work(job);
    (searches.saturating_add(front), clones, executions)
}

/// [`chance_work`] for `uncertainty` and `monte_carlo`.
fn uncertainty_work(job: &TempestJob) -> (u64, u64, u64) {
    let Some(u) = &job.uncertainty else { return (1, 0, 0) };
    let plans = 2u64;
    let (runs, closed) = job.monte_carlo.as_ref().map_or((0, 0), |m| (m.runs as u64, m.closed_loop_runs as u64));
    // Planning on error clones adds their envelope: a world of its own (a raised horizon
    // map, the members' heights), counted as one more clone.
    let planning = u.terrain_plan_clones + usize::from(u.terrain_plan_clones > 0);
    let clones = if u.terrain_sigma_m > 0.0 { (u.terrain_clones + planning) as u64 } else { 0 };
    (plans.saturating_add(closed.saturating_mul(plans)), clones, runs.saturating_mul(plans))
}

/// The cost of an actions job on a map of `cells` cells.
pub fn actions(job: &ActionsJob, cells: u64) -> Estimate {
    // Every run once per seed of its study, and the scan once per μ per seed.
    let seeds = |s: Option<(u64, u64)>| s.map_or(1, |(a, b)| b.saturating_sub(a).saturating_add(1));
    let run_evolutions =
        if job.runs.is_empty() { 1 } else { job.runs.iter().map(|r| seeds(r.seeds)).fold(0u64, u64::saturating_add) };
    let scan_points = job.mu_scan.map_or(0, |(a, b, step)| ((b - a) / step).floor().max(0.0) as u64 + 1);
    let runs = run_evolutions.saturating_add(scan_points.saturating_mul(seeds(job.mu_scan_seeds)));
    let ga = &job.ga;
    let evaluations = (ga.population as u64).saturating_mul(ga.generations as u64 + 1);
    let modules = evaluations.saturating_mul(ga.max_length as u64).saturating_mul(runs);
    // Every plan of a generation is kept with its execution (a few hundred bytes a
    // module), on top of the map.
    let plans = (ga.population as u64).saturating_mul(ga.max_length as u64).saturating_mul(400);
    Estimate {
        what: format!(
            "the actions job ({runs} GA runs of {} plans × {} generations, up to {} modules each)",
            ga.population, ga.generations, ga.max_length
        ),
        memory_bytes: cells.saturating_mul(DEM_BYTES + 20).saturating_add(plans),
        work_steps: modules,
        work_unit: "module executions",
    }
}

/// Cells of a terrain source known before reading it (a synthesised one), else `None`.
pub fn synth_cells(source: &TerrainSource) -> Option<u64> {
    match source {
        TerrainSource::Synth(spec) => Some(spec.cols as u64 * spec.rows as u64),
        TerrainSource::File(_) => None,
    }
}

/// What can be estimated from the scenario alone (before any file is read): the whole
/// job when its terrain is synthesised, `None` when the map's size comes from a file
/// (the job checks again once it has read it).
pub fn estimate(scenario: &Scenario) -> Option<Estimate> {
    match &scenario.job {
        Job::SunTable(job) => {
            let rows = (job.duration_h * 60.0 / job.step_min).ceil().max(1.0) as u64;
            Some(Estimate {
                what: format!("the Sun table of {rows} rows"),
                memory_bytes: rows * 200,
                work_steps: rows,
                work_unit: "table rows",
            })
        }
        Job::TerrainShadow(job) => synth_cells(&job.terrain).map(|c| DemCommand::Shadow.estimate(c)),
        Job::Tempest(job) => match &job.terrain {
            TerrainSource::Synth(spec) => {
                let cells = spec.cols as u64 * spec.rows as u64;
                let cell_m2 = spec.cell_m * spec.cell_m;
                Some(match &job.plan_region {
                    // A region of a synthesised map: the searches and horizons are the
                    // region's; the map itself is made whole.
                    Some(r) => {
                        let span = |(lo, hi): (f64, f64), n: usize| {
                            ((hi.min(n as f64 * spec.cell_m) - lo.max(0.0)) / spec.cell_m).ceil().max(1.0) as u64
                        };
                        let region = span(r.x_m, spec.cols) * span(r.y_m, spec.rows);
                        let mut e = tempest(job, SearchMap { cells: region.min(cells), cell_m2 });
                        e.memory_bytes = e.memory_bytes.saturating_add(cells.saturating_mul(DEM_BYTES));
                        e
                    }
                    None => tempest(job, SearchMap { cells, cell_m2 }),
                })
            }
            TerrainSource::File(_) => None,
        },
        Job::Actions(job) => synth_cells(&job.terrain).map(|c| actions(job, c)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_map_too_big_for_the_machine_is_refused_with_its_estimate() {
        // 20 000 × 20 000 cells with 360 sectors: 288 GB of horizon map alone, plus the
        // DEM and the rasters: 4e8 × (5 + 20 + 720 + 4) bytes = 279.02 GiB.
        let e = DemCommand::Horizon { sectors: 360 }.estimate(20_000 * 20_000);
        assert!(e.memory_bytes > 288_000_000_000, "{}", e.memory_bytes);
        let small = Budget { memory_bytes: 24 << 30, work_steps: 100_000_000_000 };
        let err = small.check(&e).unwrap_err().to_string();
        assert!(err.contains("GiB") && err.contains("--max-memory-gb") && err.contains("horizon"), "{err}");
        assert_eq!(err.split("needs about ").nth(1).map(|s| s.starts_with("279.02 GiB")), Some(true), "{err}");
        // The LITA-size map with 64 sectors fits in 24 GiB.
        assert!(small.check(&DemCommand::Horizon { sectors: 64 }.estimate(2527 * 2356)).is_ok());
        assert!(Budget::for_this_machine().memory_bytes > 0);
    }

    #[test]
    fn monte_carlo_work_counts_against_the_budget() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/uncertain-dawn.ron");
        let text = std::fs::read_to_string(&path).unwrap();
        let job = |t: &str| match crate::format::parse(&path, t).unwrap().job {
            Job::Tempest(j) => j,
            _ => unreachable!("a TEMPEST scenario"),
        };
        let shipped = job(&text);
        let cells = 24 * 16;
        let map = |cells| SearchMap { cells, cell_m2: 400.0 };
        let budget = Budget { memory_bytes: 1 << 40, work_steps: 100_000_000 };
        let base = tempest(&shipped, map(cells));
        assert!(budget.check(&base).is_ok(), "{base:?}");
        // The open-loop executions walk each plan once per run at the time classes: 100
        // times the runs are refused, naming what is counted and the flag.
        let many = job(&text.replace("runs: 1000,", "runs: 100000,"));
        let e = tempest(&many, map(cells));
        assert!(e.work_steps > 90 * base.work_steps, "{} against {}", e.work_steps, base.work_steps);
        let err = budget.check(&e).unwrap_err().to_string();
        assert!(err.contains("200000 open-loop executions") && err.contains("--max-work"), "{err}");
        // 10 000 closed-loop runs are 20 000 more missions: the progress bar expects
        // 476 × the searches, but their work is held to the budget as they run, not
        // refused on a guess.
        let closed = job(&text.replace("closed_loop_runs: 20", "closed_loop_runs: 10000"));
        let ratio = expected_expansions(&closed, map(cells)) as f64 / expected_expansions(&shipped, map(cells)) as f64;
        assert!((ratio - 20002.0 / 42.0).abs() < 0.01, "{ratio}");
        assert!(budget.check(&tempest(&closed, map(cells))).is_ok());
    }

    fn shipped(name: &str) -> TempestJob {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenarios/{name}.ron"));
        match crate::format::load(&path).unwrap().scenario.job {
            Job::Tempest(j) => *j,
            _ => unreachable!("a TEMPEST scenario"),
        }
    }

    /// The expected label work counts the cells around the route, not the map:
    /// lita-scale's one 6978 m leg on 100 m cells spreads over its detour ellipse
    /// (a = 2 · 3489 m + 10 cells, b = √(a² − 3489²)), 0.3 % of the 2527 × 2356 map.
    /// None of it is refused up front: sun-synchronous-traverse on a 1 s tick (4·10⁵
    /// ticks, 10¹² expected steps) is admitted with the horizon rays as its certain
    /// work, and its searches are held to the budget as they run.
    #[test]
    fn the_label_estimate_counts_the_route_and_is_never_a_refusal() {
        let lita = shipped("lita-scale");
        let map = SearchMap { cells: 2527 * 2356, cell_m2: 1e4 };
        let half = 6300f64.hypot(3000.0) / 2.0;
        let a = 2.0 * half + 1000.0;
        let ellipse = std::f64::consts::PI * a * (a * a - half * half).sqrt() / 1e4;
        let budget = Budget { memory_bytes: 1 << 40, work_steps: DEFAULT_WORK_STEPS };
        let mut fine = lita.clone();
        fine.planner.search = SearchSpec::Exact { tick_s: 60.0 };
        let expected = expected_expansions(&fine, map) as f64;
        assert!((expected - ellipse * 4320.0).abs() <= 1.0, "{expected}");
        let e = tempest(&fine, map);
        assert_eq!(e.work_steps, 2527 * 2356 * 32, "the rays alone");
        assert!(budget.check(&e).is_ok(), "{e:?}");
        let mut sun_sync = shipped("sun-synchronous-traverse");
        sun_sync.planner.search = SearchSpec::Exact { tick_s: 1.0 };
        let map = SearchMap { cells: 160 * 120, cell_m2: 2500.0 };
        assert!(expected_expansions(&sun_sync, map) as f64 * EXPANSION_STEPS as f64 > 1e12);
        assert!(budget.check(&tempest(&sun_sync, map)).is_ok());
        // The rays are certain: a map whose horizon rays exceed the budget is refused.
        let huge = SearchMap { cells: 1 << 30, cell_m2: 1.0 };
        let err = budget.check(&tempest(&sun_sync, huge)).unwrap_err().to_string();
        assert!(err.contains("--max-work") && err.contains("1073741824 cells"), "{err}");
    }

    /// A planning call may expand what the budget leaves after the rays, at
    /// [`EXPANSION_STEPS`] steps an expansion, and at least one.
    #[test]
    fn the_search_allowance_is_the_budget_left_in_expansions() {
        let devon = shipped("devon-island");
        let cells = 100 * 100;
        let budget = |work_steps| Budget { memory_bytes: 1 << 40, work_steps };
        let rays = cells * 64;
        assert_eq!(search_allowance(&devon, cells, &budget(rays + 7 * EXPANSION_STEPS + 3)), 7);
        assert_eq!(search_allowance(&devon, cells, &budget(rays / 2)), 1);
    }
}
