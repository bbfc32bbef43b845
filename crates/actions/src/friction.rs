//! Friction studies: how much wheel–ground friction a task needs.
//!
//! Two questions. [`friction_replay`] is the paper's study (section 4: "the robustness
//! of the plans obtained were studied with regard to the sensitivity to the coefficient
//! of friction"): one plan, found at one μ, executed unchanged at others — from which
//! μ up it still crosses the obstacle and completes the task, and what stops it below.
//! [`friction_scan`] plans afresh at each μ: the least friction *some* plan the GA
//! finds can do it with.

use areo_rover::evaluation::Evaluator;
use areo_rover::motion::Module;
use areo_terrain::Ground;

use crate::error::Result;
use crate::executor::{ExecConfig, ExecFailure, Executor, WheelLimit};
use crate::fitness::{Scale, Weights};
use crate::ga::{GaConfig, evolve};
use crate::inventory::Inventory;
use crate::task::Task;

/// One friction coefficient's best plan.
#[derive(Debug, Clone)]
pub struct ScanPoint {
    /// The friction coefficient.
    pub mu: f64,
    /// Whether the best plan completes the task.
    pub complete: bool,
    /// The best plan's fitness (eq. 17).
    pub best_fitness: f64,
    /// How many of its modules execute before the first failure (all if none).
    pub prefix_len: usize,
    /// The furthest north the rover got, m.
    pub max_y_m: f64,
    /// What stopped the best plan, if anything.
    pub failure: Option<ExecFailure>,
    /// The wheel that bound, when a force limit stopped it.
    pub binding: Option<WheelLimit>,
}

/// A scan's points in the order given, and its two thresholds.
#[derive(Debug, Clone)]
pub struct FrictionScan {
    /// One point per friction coefficient.
    pub points: Vec<ScanPoint>,
    /// The first μ whose best plan takes the rover north of the obstacle's far edge.
    pub min_mu_crossing: Option<f64>,
    /// The first μ whose best plan completes the task.
    pub min_mu_completing: Option<f64>,
}

/// Plans `task` once per μ in `mus` (in order) with the same inventory, weights and GA
/// settings; `far_edge_y_m` is the northing past which the obstacle counts as crossed.
/// `each` is called after every point (progress).
#[allow(clippy::too_many_arguments)]
pub fn friction_scan<G: Ground + Sync>(
    ground: &G,
    evaluator: &Evaluator,
    task: &Task,
    base: ExecConfig,
    inventory: &Inventory,
    weights: &Weights,
    scale: &Scale,
    ga: &GaConfig,
    mus: &[f64],
    far_edge_y_m: Option<f64>,
    mut each: impl FnMut(&ScanPoint),
) -> Result<FrictionScan> {
    let mut scan =
        FrictionScan { points: Vec::with_capacity(mus.len()), min_mu_crossing: None, min_mu_completing: None };
    // The first μ that does it: each μ has its own plan, so a higher μ's plan may
    // well do worse; the scan answers "the least friction a found plan needs".
    for &mu in mus {
        let executor = Executor::new(ground, evaluator, task, ExecConfig { mu, ..base });
        let report = evolve(&executor, inventory, weights, scale, ga)?;
        let best = executor.run(&report.best.plan, true);
        let max_y_m = best.trace.iter().map(|t| t.y_m).fold(task.start.1, f64::max);
        if far_edge_y_m.is_some_and(|y| max_y_m > y) && scan.min_mu_crossing.is_none() {
            scan.min_mu_crossing = Some(mu);
        }
        if best.complete && scan.min_mu_completing.is_none() {
            scan.min_mu_completing = Some(mu);
        }
        let point = ScanPoint {
            mu,
            complete: best.complete,
            best_fitness: report.best.fitness,
            prefix_len: best.prefix_len,
            max_y_m,
            failure: best.failure.map(|(_, f)| f),
            binding: best.binding,
        };
        each(&point);
        scan.points.push(point);
    }
    Ok(scan)
}

/// One friction coefficient's execution of a fixed plan.
#[derive(Debug, Clone)]
pub struct ReplayPoint {
    /// The friction coefficient.
    pub mu: f64,
    /// Whether the plan completes the task at this μ.
    pub complete: bool,
    /// How many of its modules execute before the first failure (all if none).
    pub prefix_len: usize,
    /// The furthest north the rover got, m.
    pub max_y_m: f64,
    /// The module (index into the plan) and the reason the plan stopped, if it did.
    pub failure: Option<(usize, ExecFailure)>,
    /// The wheel that bound, when a force limit stopped it.
    pub binding: Option<WheelLimit>,
}

/// A plan executed at each μ of a list (ascending), and the thresholds above which it
/// always succeeds.
#[derive(Debug, Clone)]
pub struct FrictionReplay {
    /// One point per friction coefficient, in the order given.
    pub points: Vec<ReplayPoint>,
    /// The least μ of the list from which the plan takes the rover past the obstacle's
    /// far edge at this and every larger μ listed ("any coefficient above … moved the
    /// rover across the ditch").
    pub min_mu_crossing: Option<f64>,
    /// The least μ from which it completes the task at this and every larger μ listed.
    pub min_mu_completing: Option<f64>,
}

impl FrictionReplay {
    /// The largest μ listed at which the plan does not complete: where it first fails
    /// as friction falls.
    pub fn highest_failing(&self) -> Option<&ReplayPoint> {
        self.points.iter().filter(|p| !p.complete).max_by(|a, b| a.mu.total_cmp(&b.mu))
    }
}

/// Executes `plan` unchanged at each μ in `mus` (the same modules, the same start,
/// `base`'s stability floor and body box); `far_edge_y_m` is the northing past which
/// the obstacle counts as crossed.
pub fn friction_replay<G: Ground + Sync>(
    ground: &G,
    evaluator: &Evaluator,
    task: &Task,
    base: ExecConfig,
    plan: &[Module],
    mus: &[f64],
    far_edge_y_m: Option<f64>,
) -> FrictionReplay {
    let points: Vec<ReplayPoint> = mus
        .iter()
        .map(|&mu| {
            let run = Executor::new(ground, evaluator, task, ExecConfig { mu, ..base }).run(plan, true);
            ReplayPoint {
                mu,
                complete: run.complete,
                prefix_len: run.prefix_len,
                max_y_m: run.trace.iter().map(|t| t.y_m).fold(task.start.1, f64::max),
                failure: run.failure,
                binding: run.binding,
            }
        })
        .collect();
    // The least μ from which every larger one listed passes.
    let from_up = |ok: &dyn Fn(&ReplayPoint) -> bool| {
        let mut sorted: Vec<&ReplayPoint> = points.iter().collect();
        sorted.sort_by(|a, b| a.mu.total_cmp(&b.mu));
        let mut least = None;
        for p in sorted.iter().rev() {
            if !ok(p) {
                break;
            }
            least = Some(p.mu);
        }
        least
    };
    let min_mu_crossing = far_edge_y_m.and_then(|y| from_up(&|p| p.max_y_m > y));
    let min_mu_completing = from_up(&|p| p.complete);
    FrictionReplay { points, min_mu_crossing, min_mu_completing }
}
