//! The Pareto front of a one-goal mission in (arrival time, energy used, risk margin):
//! the plans an operator chooses between when no single objective says it all.
//!
//! Arrival time is the goal instant a plan meets; energy used is what its actions' loads
//! draw ([`crate::Effect::load_wh`]); the margin is the battery the rover has at the
//! start (less its idling until the plan departs) minus the battery the plan needs (its
//! label's E) — the most extra drain the plan absorbs at its worst moment, which is its
//! lowest predicted battery above the floor unless a charge meets a full battery.
//!
//! Per goal instant (so that plans arriving at different instants never prune one
//! another), the front in (energy used, margin) is walked by ε-constraints: the plan
//! drawing least among those with a margin of at least m, for m = 0, then just above
//! the margin of the plan found, and so on until no plan holds more. Each step is an
//! A*-guided search (the EnergyUsed objective, the start's battery lowered by m) that
//! goes on in the last step's graph (labels and costs do not depend on the start's
//! battery), so a goal instant's front costs about one search, not a flood of the map
//! or a search per point. With
//! `margin_step_wh` down to rounding (the tests use 1e-6 Wh) and label classes as fine
//! as the actions' quanta, every step is exact and the walk finds every non-dominated
//! plan of the planner's discretisation (goal instants, start window, actions) —
//! tested against an exhaustive enumeration on small worlds. A coarser step may skip a
//! plan whose margin lies within the step above one found (reported with the front).

use areo_ise::{Goal, Mode, Search};

use super::Mission;
use crate::domain::{Label, Objective, TempestDomain};
use crate::error::{Error, Result};
use crate::plan::MissionPlan;

/// One plan of the front.
#[derive(Debug, Clone)]
pub struct FrontPlan {
    /// When the plan leaves the start, s after the epoch.
    pub departure_s: f64,
    /// When it reaches the goal, s after the epoch.
    pub arrival_s: f64,
    /// Energy its actions' loads draw, Wh.
    pub energy_used_wh: f64,
    /// Battery at the start (less the idle before departure) minus the battery the plan
    /// needs, Wh.
    pub margin_wh: f64,
    /// The plan.
    pub plan: MissionPlan,
}

/// The non-dominated plans and what finding them took.
#[derive(Debug, Clone)]
pub struct ParetoFront {
    /// The plans, by arrival time, then energy used.
    pub plans: Vec<FrontPlan>,
    /// Searches run (one per goal instant, each walked along its front).
    pub searches: usize,
    /// Labels expanded, all searches.
    pub expansions: u64,
    /// Plans found before the non-dominated filter (one per search that found one).
    pub candidates: usize,
    /// The margin step the walk took, Wh: a plan within it above a found one's margin
    /// may be missing.
    pub margin_step_wh: f64,
}

/// Whether `a` is at least as good as `b` in arrival, energy used and margin, and better
/// in one (equal triples: the first stands).
fn dominates(a: (f64, f64, f64), b: (f64, f64, f64)) -> bool {
    const EPS: f64 = 1e-9;
    let no_worse = a.0 <= b.0 + EPS && a.1 <= b.1 + EPS && a.2 >= b.2 - EPS;
    let same = (a.0 - b.0).abs() <= EPS && (a.1 - b.1).abs() <= EPS && (a.2 - b.2).abs() <= EPS;
    no_worse && !same
}

/// The points of `points` that no other dominates, one of each equal triple, in the
/// order given.
pub fn non_dominated(points: &[(f64, f64, f64)]) -> Vec<usize> {
    let mut kept: Vec<usize> = Vec::new();
    for (i, &p) in points.iter().enumerate() {
        if points.iter().any(|&q| dominates(q, p)) {
            continue;
        }
        let duplicate = kept.iter().any(|&k| {
            let q = points[k];
            (q.0 - p.0).abs() <= 1e-9 && (q.1 - p.1).abs() <= 1e-9 && (q.2 - p.2).abs() <= 1e-9
        });
        if !duplicate {
            kept.push(i);
        }
    }
    kept
}

impl Mission<'_> {
    /// The front's settings refused, naming the field: one goal, a margin step in range.
    fn check_front(&self, margin_step_wh: f64) -> Result<()> {
        if self.goals.len() != 1 {
            return Err(Error::Config {
                field: "pareto_front",
                message: format!("the front is searched for a single goal; this mission has {}", self.goals.len()),
            });
        }
        if !(1e-9..=1e6).contains(&margin_step_wh) {
            return Err(Error::Config {
                field: "pareto_front.margin_step_wh",
                message: format!("{margin_step_wh}: allowed 1e-9..=1e6 Wh"),
            });
        }
        Ok(())
    }

    /// The Pareto front of this mission's plans in (arrival time, energy used, margin),
    /// margins walked `margin_step_wh` apart (see the module's notes). One goal only:
    /// chained segments pick one candidate per intermediate goal, which a front over the
    /// whole chain would have to keep apart.
    pub fn pareto_front(&self, margin_step_wh: f64) -> Result<ParetoFront> {
        self.check_front(margin_step_wh)?;
        if self.tick.is_some() {
            return self.tick_front();
        }
        let goal = self.goals[0];
        // One planning call: its searches share the call's expansion allowance.
        self.allowance.begin();
        let mut candidates: Vec<((f64, f64, f64), MissionPlan, f64)> = Vec::new();
        let (mut searches, mut expansions) = (0, 0);
        for t in self.final_goal_times() {
            let mut domain = TempestDomain::new(
                self.world,
                self.model,
                self.start,
                Objective::EnergyUsed,
                self.classes.resolution,
                self.config.path_length,
            )
            .sharing_geometry(&self.geometry)
            .metered(self.config.meter.clone())
            .allowing(self.allowance.clone());
            let seed = Goal { state: goal, label: Label { t, e: self.config.goal_energy_wh }, cost: 0.0 };
            let mut search = Search::new(&domain, [seed], Mode::BestPathCost);
            searches += 1;
            let mut least_margin = 0.0;
            while least_margin <= self.start.energy_wh {
                // A plan holds a margin of at least m when its start needs no more than
                // the battery less m (the idle before departure included). Labels and
                // costs do not depend on the start's battery: the graph goes on from
                // where the last step left it, as the planner's staircase does.
                domain.start.energy_wh = self.start.energy_wh - least_margin;
                search.start_moved(&domain);
                let found = search.plan(&domain);
                expansions += found.stats.expansions;
                // A stopped search's "no plan" is no answer: not the front's end.
                self.allowance.check()?;
                let Some(path) = found.path else { break };
                let first = path[0].label;
                let margin = self.start.energy_wh - self.model.idle_wh(first.t - self.start.t_min) - first.e;
                let steps: Vec<_> = super::own_path(path).into_iter().map(|s| (s, 0)).collect();
                let mut plan = self.waypoints(&steps, 0.0)?;
                let used = plan.energy_used_wh(self.world, self.model).map_err(|(step, a, b)| Error::Replay {
                    step,
                    action: format!("{a:?}"),
                    cell: plan.waypoints[step].cell,
                    binding: b.describe().to_string(),
                })?;
                plan.cost = used;
                // What this plan is: the least energy used at its margin and arrival.
                plan.objective = Objective::EnergyUsed;
                plan.expansions = found.stats.expansions;
                candidates.push(((t, used, margin), plan, first.t));
                least_margin = margin + margin_step_wh;
            }
        }
        let points: Vec<(f64, f64, f64)> = candidates.iter().map(|c| c.0).collect();
        let mut plans: Vec<FrontPlan> = non_dominated(&points)
            .into_iter()
            .map(|i| {
                let ((arrival_s, energy_used_wh, margin_wh), plan, departure_s) = candidates[i].clone();
                FrontPlan { departure_s, arrival_s, energy_used_wh, margin_wh, plan }
            })
            .collect();
        plans.sort_by(|a, b| a.arrival_s.total_cmp(&b.arrival_s).then(a.energy_used_wh.total_cmp(&b.energy_used_wh)));
        Ok(ParetoFront { plans, searches, expansions, candidates: candidates.len(), margin_step_wh })
    }
}

impl Mission<'_> {
    /// The front on a tick: the exact search's ([`crate::exact::ExactQuery::front`]) —
    /// every plan on the tick that no other beats in arrival, energy used and lowest
    /// battery, with no margin step (reported as 0). The margin is the plan's lowest
    /// battery above the floor, inside actions too.
    fn tick_front(&self) -> Result<ParetoFront> {
        self.allowance.begin();
        let query = self.tick_query(self.model, self.start);
        let (allowance, meter) = (&self.allowance, &self.config.meter);
        let front = query.front_with(&mut |held| {
            allowance.spend();
            meter.add(1);
            !allowance.exhausted() && !allowance.outgrown(held)
        });
        self.allowance.check()?;
        let candidates = front.points.len();
        let plans = (front.points.into_iter())
            .map(|p| {
                let departure_s = (p.steps.iter())
                    .find(|s| matches!(s.action, crate::action_model::Action::Drive(_)))
                    .map_or(p.arrival_s, |s| s.t_s);
                let mut plan = self.tick_waypoints(&p.steps, p.energy_used_wh, front.expanded);
                plan.objective = Objective::EnergyUsed;
                FrontPlan {
                    departure_s,
                    arrival_s: p.arrival_s,
                    energy_used_wh: p.energy_used_wh,
                    margin_wh: p.lowest_wh,
                    plan,
                }
            })
            .collect();
        Ok(ParetoFront { plans, searches: 1, expansions: front.expanded, candidates, margin_step_wh: 0.0 })
    }
}
