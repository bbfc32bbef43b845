//! Friction sweeps: the same task planned afresh at each wheel–ground friction
//! coefficient, to find the least friction that crosses an obstacle and the least that
//! completes the task (the paper's Figure 8 study).

use areo_rover::evaluation::Evaluator;
use areo_terrain::Ground;

use crate::error::Result;
use crate::executor::{ExecConfig, Executor, Failure, WheelLimit};
use crate::fitness::{Scale, Weights};
use crate::ga::{GaConfig, evolve};
use crate::inventory::Inventory;
use crate::task::Task;

/// One friction coefficient's best plan.
#[derive(Debug, Clone)]
pub struct SweepPoint {
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
    pub failure: Option<Failure>,
    /// The wheel that bound, when a force limit stopped it.
    pub binding: Option<WheelLimit>,
}

/// A sweep's points in the order given, and its two thresholds.
#[derive(Debug, Clone)]
pub struct FrictionSweep {
    /// One point per friction coefficient.
    pub points: Vec<SweepPoint>,
    /// The first μ whose best plan takes the rover north of the obstacle's far edge.
    pub min_mu_crossing: Option<f64>,
    /// The first μ whose best plan completes the task.
    pub min_mu_completing: Option<f64>,
}

/// Plans `task` once per μ in `mus` (in order) with the same inventory, weights and GA
/// settings; `far_edge_y_m` is the northing past which the obstacle counts as crossed.
/// `each` is called after every point (progress).
#[allow(clippy::too_many_arguments)]
pub fn friction_sweep<G: Ground + Sync>(
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
    mut each: impl FnMut(&SweepPoint),
) -> Result<FrictionSweep> {
    let mut sweep =
        FrictionSweep { points: Vec::with_capacity(mus.len()), min_mu_crossing: None, min_mu_completing: None };
    for &mu in mus {
        let executor = Executor::new(ground, evaluator, task, ExecConfig { mu, ..base });
        let report = evolve(&executor, inventory, weights, scale, ga)?;
        let best = executor.run(&report.best.plan, true);
        let max_y_m = best.trace.iter().map(|t| t.y_m).fold(task.start.1, f64::max);
        if far_edge_y_m.is_some_and(|y| max_y_m > y) && sweep.min_mu_crossing.is_none() {
            sweep.min_mu_crossing = Some(mu);
        }
        if best.complete && sweep.min_mu_completing.is_none() {
            sweep.min_mu_completing = Some(mu);
        }
        let point = SweepPoint {
            mu,
            complete: best.complete,
            best_fitness: report.best.fitness,
            prefix_len: best.prefix_len,
            max_y_m,
            failure: best.failure.map(|(_, f)| f),
            binding: best.binding,
        };
        each(&point);
        sweep.points.push(point);
    }
    Ok(sweep)
}
