//! The genetic algorithm (Farritor et al., section 3): variable-length plans of action
//! modules, evolved by single-point crossover at the parent's failure point (Figure 2),
//! mutation, tournament selection and elitism; each plan is scored by executing it on
//! the physical model.
//!
//! Determinism: every random draw comes from one seeded ChaCha8 generator, in the same
//! order, on one thread; only the plan evaluations (pure functions of the plan) run in
//! parallel with rayon, and their results are collected in order — so a run depends on
//! its seed, never on the thread count.

use areo_rover::motion::Module;
use areo_terrain::Ground;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::executor::{Execution, Executor};
use crate::fitness::{Scale, Weights, fitness};
use crate::inventory::Inventory;

/// Where single-point crossover cuts the first parent.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum CrossoverPoint {
    /// A discrete normal centred on the parent's failure point with this standard
    /// deviation (modules), truncated to the plan; with probability `uniform`, uniform
    /// over the plan instead (diversity).
    Centred {
        /// Standard deviation, modules (> 0).
        sigma: f64,
        /// Probability of a uniform draw instead (0..1).
        uniform: f64,
    },
    /// Uniform over the plan (the paper's Figure 3 comparison).
    Uniform,
}

/// GA settings (scenario fields).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GaConfig {
    /// Plans per generation (≥ 2).
    pub population: usize,
    /// Generations (≥ 1).
    pub generations: usize,
    /// Length range of the random initial plans, modules.
    pub initial_length: (usize, usize),
    /// Longest plan, modules.
    pub max_length: usize,
    /// Crossover point distribution.
    pub crossover: CrossoverPoint,
    /// Per-module probability of replacement by a random module of the inventory.
    pub mutate_replace: f64,
    /// Per-plan probability of inserting a random module.
    pub mutate_insert: f64,
    /// Per-plan probability of deleting a module.
    pub mutate_delete: f64,
    /// Tournament size for selection (≥ 1).
    pub tournament: usize,
    /// Best plans copied unchanged into the next generation.
    pub elitism: usize,
    /// Seed of the ChaCha8 generator.
    pub seed: u64,
}

impl Default for GaConfig {
    fn default() -> GaConfig {
        GaConfig {
            population: 50,
            generations: 20,
            initial_length: (40, 80),
            max_length: 200,
            crossover: CrossoverPoint::Centred { sigma: 2.0, uniform: 0.1 },
            mutate_replace: 0.02,
            mutate_insert: 0.2,
            mutate_delete: 0.2,
            tournament: 2,
            elitism: 2,
            seed: 1,
        }
    }
}

impl GaConfig {
    /// Checks ranges, naming the first bad field.
    pub fn validate(&self) -> Result<()> {
        let bad = |field: &str, message: String| Err(Error::Config { field: field.into(), message });
        // Upper bounds keep a run's work (population × generations × plan length module
        // executions) within what a planner could ever need.
        if !(2..=10_000).contains(&self.population) {
            return bad("population", format!("{}: allowed 2..=10000", self.population));
        }
        if !(1..=10_000).contains(&self.generations) {
            return bad("generations", format!("{}: allowed 1..=10000", self.generations));
        }
        if !(1..=10_000).contains(&self.max_length) {
            return bad("max_length", format!("{}: allowed 1..=10000 modules", self.max_length));
        }
        let (lo, hi) = self.initial_length;
        if lo == 0 || hi < lo || hi > self.max_length {
            return bad("initial_length", format!("({lo}, {hi}): need 1 ≤ min ≤ max ≤ max_length"));
        }
        for (f, p) in [
            ("mutate_replace", self.mutate_replace),
            ("mutate_insert", self.mutate_insert),
            ("mutate_delete", self.mutate_delete),
        ] {
            if !(0.0..=1.0).contains(&p) {
                return bad(f, format!("{p}: a probability, 0..=1"));
            }
        }
        if let CrossoverPoint::Centred { sigma, uniform } = self.crossover
            && !(sigma > 0.0 && sigma <= 1e4 && (0.0..=1.0).contains(&uniform))
        {
            return bad("crossover", "sigma must be in 0 (exclusive)..=10000 and uniform a probability".into());
        }
        if self.tournament == 0 || self.tournament > self.population {
            return bad("tournament", format!("{}: allowed 1..=population ({})", self.tournament, self.population));
        }
        if self.elitism >= self.population {
            return bad("elitism", format!("{}: allowed 0..population ({})", self.elitism, self.population));
        }
        Ok(())
    }
}

/// A plan with its execution and fitness.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Individual {
    /// The modules.
    pub plan: Vec<Module>,
    /// What running it did.
    pub execution: Execution,
    /// Its fitness.
    pub fitness: f64,
}

impl Individual {
    /// The index of the module that failed, or the plan's length if none did.
    pub fn failure_point(&self) -> usize {
        self.execution.failure.as_ref().map_or(self.plan.len(), |(i, _)| *i)
    }
}

/// One generation's figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Generation {
    /// 0 = the random initial population.
    pub index: usize,
    /// Best fitness.
    pub best: f64,
    /// Mean fitness.
    pub mean: f64,
    /// The best plan's successful prefix, modules.
    pub best_prefix: usize,
    /// Whether some plan completes the task.
    pub solved: bool,
}

/// The result of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GaReport {
    /// The best plan found.
    pub best: Individual,
    /// Per generation.
    pub generations: Vec<Generation>,
    /// The first generation in which a plan completed the task.
    pub first_solved: Option<usize>,
    /// For every crossover whose child beat its first parent: the child's successful
    /// prefix minus the parent's (Figure 3's look-ahead).
    pub lookahead: Vec<i64>,
    /// Plans evaluated.
    pub evaluations: usize,
    /// Modules actually executed (successful prefixes plus each failing module, less
    /// the prefixes re-used from a parent).
    pub modules_executed: usize,
}

/// A plan to evaluate, with the execution of a plan sharing its first modules and how
/// many it shares.
type Job<'p> = (Vec<Module>, Option<(&'p Execution, usize)>);

/// Runs the GA.
pub fn evolve<G: Ground + Sync>(
    executor: &Executor<'_, G>,
    inventory: &Inventory,
    weights: &Weights,
    scale: &Scale,
    config: &GaConfig,
) -> Result<GaReport> {
    config.validate()?;
    if inventory.modules.is_empty() {
        return Err(Error::Config { field: "inventory".into(), message: "no modules left to plan with".into() });
    }
    let mut rng = ChaCha8Rng::seed_from_u64(config.seed);
    let pick = |rng: &mut ChaCha8Rng| inventory.modules[rng.random_range(0..inventory.modules.len())];
    let mut evaluations = 0usize;
    let mut modules_executed = 0usize;
    let evaluate = |plans: Vec<Job<'_>>, evaluations: &mut usize, modules: &mut usize| {
        evaluate_jobs(executor, (weights, scale), plans, evaluations, modules)
    };

    let initial: Vec<Vec<Module>> = (0..config.population)
        .map(|_| {
            let n = rng.random_range(config.initial_length.0..=config.initial_length.1);
            (0..n).map(|_| pick(&mut rng)).collect()
        })
        .collect();
    let mut population =
        evaluate(initial.into_iter().map(|p| (p, None)).collect(), &mut evaluations, &mut modules_executed);
    let mut generations = vec![summary(0, &population)];
    let mut first_solved = generations[0].solved.then_some(0);
    let mut lookahead = Vec::new();

    for g in 1..=config.generations {
        population.sort_by(|a, b| b.fitness.total_cmp(&a.fitness));
        let mut next_plans: Vec<Vec<Module>> = Vec::with_capacity(config.population);
        let mut parents: Vec<Option<usize>> = Vec::with_capacity(config.population);
        for elite in population.iter().take(config.elitism) {
            next_plans.push(elite.plan.clone());
            parents.push(None);
        }
        while next_plans.len() < config.population {
            let (child, a) = breed(&population, config, &mut rng, &pick);
            next_plans.push(child);
            parents.push(Some(a));
        }
        let jobs = jobs_of(&population, next_plans, &parents);
        let children = evaluate(jobs, &mut evaluations, &mut modules_executed);
        for (child, parent) in children.iter().zip(&parents) {
            if let Some(a) = parent {
                let pa = &population[*a];
                if child.fitness > pa.fitness {
                    lookahead.push(child.execution.prefix_len as i64 - pa.execution.prefix_len as i64);
                }
            }
        }
        population = children;
        let s = summary(g, &population);
        if s.solved && first_solved.is_none() {
            first_solved = Some(g);
        }
        generations.push(s);
    }
    population.sort_by(|a, b| b.fitness.total_cmp(&a.fitness));
    let best = population.swap_remove(0);
    Ok(GaReport { best, generations, first_solved, lookahead, evaluations, modules_executed })
}

/// Executes `plans` in parallel, each resuming from the execution of a plan sharing its
/// first modules where it has one (those are not executed again: a child keeps its
/// first parent's prefix), and scores them; counts the evaluations and the modules
/// executed.
fn evaluate_jobs<G: Ground + Sync>(
    executor: &Executor<'_, G>,
    (weights, scale): (&Weights, &Scale),
    plans: Vec<Job<'_>>,
    evaluations: &mut usize,
    modules: &mut usize,
) -> Vec<Individual> {
    let out: Vec<(Individual, usize)> = plans
        .into_par_iter()
        .map(|(plan, parent)| {
            let (execution, reused) = match parent {
                Some((e, shared)) => {
                    let ex = executor.resume(&plan, e, shared);
                    let reused = shared.min(e.checkpoints.len()).min(ex.prefix_len);
                    (ex, reused)
                }
                None => (executor.run(&plan, false), 0),
            };
            let fitness = fitness(&execution, weights, scale);
            (Individual { plan, execution, fitness }, reused)
        })
        .collect();
    *evaluations += out.len();
    *modules += out
        .iter()
        .map(|(i, reused)| i.execution.prefix_len + usize::from(i.execution.failure.is_some()) - reused)
        .sum::<usize>();
    out.into_iter().map(|(i, _)| i).collect()
}

/// A child of two tournament winners: one-point crossover, then replacements, at most
/// one insertion and one deletion, cut to the longest plan; with its first parent.
fn breed(
    population: &[Individual],
    config: &GaConfig,
    rng: &mut ChaCha8Rng,
    pick: &impl Fn(&mut ChaCha8Rng) -> Module,
) -> (Vec<Module>, usize) {
    let a = tournament(population, config.tournament, rng);
    let b = tournament(population, config.tournament, rng);
    let (pa, pb) = (&population[a], &population[b]);
    let c = crossover_point(pa, config.crossover, rng);
    let mut child: Vec<Module> = pa.plan[..c].to_vec();
    if c < pb.plan.len() {
        child.extend_from_slice(&pb.plan[c..]);
    }
    // Mutation: replacements, then at most one insertion and one deletion.
    for m in child.iter_mut() {
        if rng.random::<f64>() < config.mutate_replace {
            *m = pick(rng);
        }
    }
    if rng.random::<f64>() < config.mutate_insert {
        let at = rng.random_range(0..=child.len());
        let m = pick(rng);
        child.insert(at, m);
    }
    if child.len() > 1 && rng.random::<f64>() < config.mutate_delete {
        let at = rng.random_range(0..child.len());
        child.remove(at);
    }
    child.truncate(config.max_length);
    if child.is_empty() {
        child.push(pick(rng));
    }
    (child, a)
}

/// Each next plan with the execution it can resume from: its first parent's, or for an
/// elite (no parent) its own, and how many first modules they share.
fn jobs_of<'p>(population: &'p [Individual], next_plans: Vec<Vec<Module>>, parents: &[Option<usize>]) -> Vec<Job<'p>> {
    next_plans
        .into_iter()
        .zip(parents)
        .map(|(plan, parent)| {
            let a = parent.map_or(usize::MAX, |a| a);
            let source = if a == usize::MAX { None } else { Some(&population[a]) };
            // Elites are their own parents: everything is shared.
            let source = source.or_else(|| population.iter().find(|p| p.plan == plan));
            let shared = source.map_or(0, |s| s.plan.iter().zip(&plan).take_while(|(x, y)| x == y).count());
            (plan, source.map(|s| (&s.execution, shared)))
        })
        .collect()
}

fn summary(index: usize, population: &[Individual]) -> Generation {
    let best = population.iter().max_by(|a, b| a.fitness.total_cmp(&b.fitness)).map_or(0, |b| b.execution.prefix_len);
    Generation {
        index,
        best: population.iter().map(|i| i.fitness).fold(f64::NEG_INFINITY, f64::max),
        mean: population.iter().map(|i| i.fitness).sum::<f64>() / population.len() as f64,
        best_prefix: best,
        solved: population.iter().any(|i| i.execution.complete),
    }
}

fn tournament(population: &[Individual], k: usize, rng: &mut ChaCha8Rng) -> usize {
    let mut best = rng.random_range(0..population.len());
    for _ in 1..k {
        let c = rng.random_range(0..population.len());
        if population[c].fitness > population[best].fitness {
            best = c;
        }
    }
    best
}

/// Where to cut the first parent: keep its successful prefix, replace from about
/// where it failed.
fn crossover_point(parent: &Individual, how: CrossoverPoint, rng: &mut ChaCha8Rng) -> usize {
    let len = parent.plan.len();
    let uniform = |rng: &mut ChaCha8Rng| rng.random_range(1..=len.max(1));
    match how {
        CrossoverPoint::Uniform => uniform(rng),
        CrossoverPoint::Centred { sigma, uniform: p } => {
            if rng.random::<f64>() < p {
                return uniform(rng);
            }
            // Box–Muller from two uniform draws.
            let (u1, u2) = (rng.random::<f64>().max(1e-12), rng.random::<f64>());
            let z = (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
            let f = parent.failure_point() as f64;
            ((f + sigma * z).round() as i64).clamp(1, len.max(1) as i64) as usize
        }
    }
}
