//! A TEMPEST job's Pareto front (`pareto_front: true`): the non-dominated plans to its
//! goal in (arrival time, energy used, battery margin) — figures, a row per plan, the
//! plans themselves (so an operator can take one) and two plots (energy used and margin
//! against arrival).

use areo_mission::{ActionModel, Mission, MissionPlan, ParetoFront, Start, World};

use crate::report::tempest::{FrontFigures, FrontRow};

use super::chance::time_plot;
use super::{Context, nights};
use crate::error::Result;
use crate::format::{ScenarioFile, TempestJob};
use crate::report::plots::{Plot, Series};

/// Plans the job again and searches its front, when the job asks for one.
pub(super) fn evaluate(
    job: &TempestJob,
    file: &ScenarioFile,
    (world, model): (&World, &ActionModel),
    (start, goals): (Start, &[u32]),
    planner: areo_mission::PlannerConfig,
) -> Result<Option<ParetoFront>> {
    let Some(spec) = &job.pareto_front else { return Ok(None) };
    let front = Mission::plan(world, model, planner, start, goals)
        .and_then(|(mission, _)| mission.pareto_front(spec.step_wh()));
    match front {
        Ok(front) => Ok(Some(front)),
        Err(areo_mission::Error::Config { field, message }) => {
            Err(super::scenario_error(file, super::planner_field(field), message))
        }
        Err(e) => Err(super::located(file, e)),
    }
}

/// The `front_…` figures; `plan` (the job's own plan, by its objective) is placed
/// against the front.
pub(super) fn figures(ctx: &Context<'_>, plan: &MissionPlan, front: &ParetoFront) -> FrontFigures {
    let plans = &front.plans;
    let mut f = FrontFigures {
        front_plans: plans.len(),
        front_searches: front.searches,
        front_candidates: front.candidates,
        // On a tick the front is exact; off it, margins are walked in steps.
        front_margin_step_wh: plan.tick_s.is_none().then_some(front.margin_step_wh),
        ..FrontFigures::default()
    };
    let range = |f: fn(&areo_mission::FrontPlan) -> f64| {
        plans.iter().map(f).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)))
    };
    let arrival = range(|p| p.arrival_s);
    let used = range(|p| p.energy_used_wh);
    let margin = range(|p| p.margin_wh);
    if plans.is_empty() {
        return f;
    }
    f.front_earliest_arrival_h = Some(ctx.hours(arrival.0));
    f.front_latest_arrival_h = Some(ctx.hours(arrival.1));
    f.front_least_energy_used_wh = Some(used.0);
    f.front_most_energy_used_wh = Some(used.1);
    f.front_least_margin_wh = Some(margin.0);
    f.front_largest_margin_wh = Some(margin.1);
    // The job's plan in the front's measures: dominated when a front plan arrives no
    // later, draws no more and holds no less, and is better in one.
    if let Some(own) = measures(ctx, plan) {
        let beaten = plans.iter().any(|p| {
            let q = (p.arrival_s, p.energy_used_wh, p.margin_wh);
            areo_mission::non_dominated(&[own, q]) == vec![1]
        });
        f.plan_energy_used_wh = Some(own.1);
        f.plan_margin_wh = Some(own.2);
        f.plan_dominated_by_front = Some(beaten);
    }
    f
}

/// A plan on a tick in the front's measures: (arrival s, energy used Wh, lowest battery
/// above the floor Wh), replayed on the job's model — each waypoint's action, then the
/// wait to the next waypoint (a drive's settle, a wait's length), from the start.
fn tick_measures(ctx: &Context<'_>, plan: &MissionPlan) -> Option<(f64, f64, f64)> {
    let (world, model, start) = (ctx.world, ctx.model, ctx.start);
    let capacity = model.capacity_wh();
    let (mut t, mut e, mut used, mut low) = (start.t_min, start.energy_wh, 0.0, start.energy_wh);
    let mut cell = start.cell;
    let mut take = |effect: &areo_mission::Effect, t: &mut f64, e: &mut f64| {
        low = f64::min(low, effect.lowest(*e, capacity));
        used += effect.load_wh;
        *e = effect.after(*e, capacity);
        *t += effect.duration_s;
    };
    for (i, w) in plan.waypoints.iter().enumerate() {
        if w.t_s > t + 1e-6 {
            let idle = model.wait(world, cell, t, w.t_s - t).ok()?;
            take(&idle, &mut t, &mut e);
        }
        cell = w.cell;
        match w.action {
            Some(areo_mission::Action::Drive(k)) => {
                let (to, drive) = model.drive(world, w.cell, k, w.t_s).ok()?;
                take(&drive, &mut t, &mut e);
                cell = to;
            }
            Some(areo_mission::Action::Wait) => {
                let until = plan.waypoints.get(i + 1)?.t_s;
                let wait = model.wait(world, w.cell, w.t_s, until - w.t_s).ok()?;
                take(&wait, &mut t, &mut e);
            }
            _ => {}
        }
    }
    Some((t, used, low))
}

/// A plan's (arrival s, energy used Wh, margin Wh), replayed on the job's model.
fn measures(ctx: &Context<'_>, plan: &MissionPlan) -> Option<(f64, f64, f64)> {
    if plan.tick_s.is_some() {
        return tick_measures(ctx, plan);
    }
    let (first, last) = (plan.waypoints.first()?, plan.waypoints.last()?);
    let used = plan.energy_used_wh(ctx.world, ctx.model).ok()?;
    let start = ctx.start;
    let margin = start.energy_wh - ctx.model.idle_wh(first.t_s - start.t_min) - first.required_wh;
    Some((last.t_s, used, margin))
}

/// A row per plan of the front (`pareto_front.csv`).
pub(super) fn rows(ctx: &Context<'_>, front: &ParetoFront) -> Vec<FrontRow> {
    let rows = front.plans.iter().enumerate().map(|(i, p)| {
        let (drives, charges, hibernations) = p.plan.action_counts();
        let utc = |k: usize| p.plan.waypoints.get(k).map_or(String::new(), |w| w.utc.clone());
        FrontRow {
            plan: i,
            departure_utc: utc(0),
            departure_h: ctx.hours(p.departure_s),
            arrival_utc: utc(p.plan.waypoints.len().saturating_sub(1)),
            arrival_h: ctx.hours(p.arrival_s),
            duration_h: p.plan.duration_s() / 3600.0,
            energy_used_wh: p.energy_used_wh,
            margin_wh: p.margin_wh,
            lowest_battery_wh: p.plan.min_battery_wh(),
            drives,
            charges,
            hibernations,
        }
    });
    rows.collect()
}

/// The front's two plots: energy used and margin against arrival, a dot per plan.
pub(super) fn plots(ctx: &Context<'_>, front: &ParetoFront) -> [Plot; 2] {
    let end_s = front.plans.iter().map(|p| p.arrival_s).fold(0.0, f64::max) * 1.05;
    let night = nights(ctx.truth, end_s);
    let dots = |f: fn(&areo_mission::FrontPlan) -> f64, label: &str| {
        vec![Series {
            label: label.into(),
            points: front.plans.iter().map(|p| (ctx.hours(p.arrival_s), f(p))).collect(),
            rgb: (30, 90, 220),
            width: 4,
        }]
    };
    [
        time_plot(
            ctx,
            ("front_energy", "Pareto front: energy used against arrival", "energy used, Wh"),
            dots(|p| p.energy_used_wh, "front plan"),
            (end_s, &night),
            true,
        ),
        time_plot(
            ctx,
            ("front_margin", "Pareto front: battery margin against arrival", "margin above the battery floor, Wh"),
            dots(|p| p.margin_wh, "front plan"),
            (end_s, &night),
            true,
        ),
    ]
}
