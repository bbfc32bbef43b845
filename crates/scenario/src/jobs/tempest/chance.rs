//! A TEMPEST job under uncertainty: the chance-constrained plan's margins, the
//! deterministic plan it is compared with, and the open-loop Monte Carlo of both —
//! figures, every execution's row and three plots (the last goal's arrival as a
//! cumulative distribution, the battery's spread against time, the lowest battery's
//! histogram).

use areo_mission::uncertainty::{MonteCarlo, SampledRun, Summary, Uncertainty, percentile, summarise};
use areo_mission::uncertainty::{closed_loop_on, dem_clone, open_loop_on, planning_clones};
use areo_mission::{Mission, MissionPlan, PlannerConfig, Simulation, Start, World, WorldConfig};

use super::{Context, nights, time_axis_name, time_ticks};
use crate::error::Result;
use crate::format::TempestJob;
use crate::report::plots::{HistogramPlot, Plot, Series, TimePlot};
use crate::report::tempest::{ChanceFigures, MonteCarloFigures, MonteCarloRow};

/// One plan's open-loop executions.
pub(super) struct Executed {
    pub executions: Vec<SampledRun>,
    pub summary: Summary,
}

/// What the job's `uncertainty` (and `monte_carlo`) gave.
pub(super) struct Chance {
    pub uncertainty: Uncertainty,
    /// The plan made on the nominal model, when the confidence adds a margin
    /// (`Err`: no deterministic plan either, with the reason).
    pub deterministic: Option<std::result::Result<MissionPlan, String>>,
    /// The chance-constrained plan's executions.
    pub chance_runs: Option<Executed>,
    /// The deterministic plan's executions.
    pub deterministic_runs: Option<Executed>,
    /// Closed-loop executions planning at the confidence, and deterministically.
    pub chance_closed: Option<Executed>,
    pub deterministic_closed: Option<Executed>,
}

/// The uncertainty the job states, if any (validated with the scenario).
pub(super) fn uncertainty(job: &TempestJob) -> Option<Uncertainty> {
    job.uncertainty.as_ref().map(Uncertainty::from)
}

/// The world a plan that must hold on the terrain's height error is made on: the
/// envelope of the map and `uncertainty.terrain_plan_clones` error clones of it
/// ([`World::envelope`]); `None` when the job plans on the map alone.
pub(super) fn planning_envelope(job: &TempestJob, world: &World, config: &WorldConfig) -> Result<Option<World>> {
    let Some(u) = uncertainty(job) else { return Ok(None) };
    let clones = planning_clones(&u, world, config, &job.body.model())?;
    if clones.is_empty() {
        return Ok(None);
    }
    Ok(Some(World::envelope(world, &clones)?))
}

/// Plans deterministically for comparison and runs the Monte Carlo the job asks for.
/// `plan` is the chance-constrained initial plan (made on `model`, which carries the
/// margins, and on `plan_world`: the map, or its envelope with error clones);
/// executions run on `truth` with the nominal model.
pub(super) fn evaluate(
    job: &TempestJob,
    (((world, plan_world), truth), config): (((&World, &World), &World), &WorldConfig),
    model: &areo_mission::ActionModel,
    planner: PlannerConfig,
    (start, goals): (Start, &[u32]),
    plan: &MissionPlan,
) -> Result<Option<Chance>> {
    let Some(u) = uncertainty(job) else { return Ok(None) };
    let margined = u.margins() != areo_mission::Perturbation::NONE || !std::ptr::eq(world, plan_world);
    let deterministic = margined.then(|| {
        Mission::plan(world, &model.nominal(), planner.clone(), start, goals).map(|(_, p)| p).map_err(|e| e.to_string())
    });
    let mut chance = Chance {
        uncertainty: u,
        deterministic,
        chance_runs: None,
        deterministic_runs: None,
        chance_closed: None,
        deterministic_closed: None,
    };
    let Some(spec) = &job.monte_carlo else { return Ok(Some(chance)) };
    let mc = MonteCarlo::from(spec);
    let executed = |executions: Vec<SampledRun>| {
        let summary = summarise(&executions, goals.len());
        Executed { executions, summary }
    };
    // The executions drive on error clones of the map, or on the truth.
    let clones = terrain_clones(job, &u, world, config, mc.seed)?;
    let worlds = if clones.is_empty() { std::slice::from_ref(truth) } else { &clones[..] };
    chance.chance_runs = Some(executed(open_loop_on(plan, model, worlds, start, &u, &mc)?));
    if let Some(Ok(d)) = &chance.deterministic {
        chance.deterministic_runs = Some(executed(open_loop_on(d, model, worlds, start, &u, &mc)?));
    }
    if spec.closed_loop_runs > 0 {
        let mc = MonteCarlo { runs: spec.closed_loop_runs, ..mc };
        // The closed-loop runs drive on error clones of the true terrain: the map's own
        // clones when the map is true, else clones of the truth.
        let truth_clones =
            if std::ptr::eq(truth, world) { Vec::new() } else { terrain_clones(job, &u, truth, config, mc.seed)? };
        let truths = if std::ptr::eq(truth, world) { &clones[..] } else { &truth_clones[..] };
        let nominal = model.nominal();
        let simulation = |model, believed| Simulation {
            believed,
            truth,
            model,
            planner: planner.clone(),
            start,
            goals,
            config: job.simulate.as_ref().map(Into::into).unwrap_or_default(),
        };
        chance.chance_closed = Some(executed(closed_loop_on(&simulation(model, plan_world), truths, &u, &mc)?));
        if margined {
            chance.deterministic_closed =
                Some(executed(closed_loop_on(&simulation(&nominal, world), truths, &u, &mc)?));
        }
    }
    Ok(Some(chance))
}

/// `uncertainty.terrain_clones` error clones of the believed map, each a world (clone i
/// from seed `seed + i`); none without a height error.
fn terrain_clones(
    job: &TempestJob,
    u: &Uncertainty,
    world: &World,
    config: &WorldConfig,
    seed: u64,
) -> Result<Vec<World>> {
    if u.terrain_clones == 0 || u.terrain_sigma_m == 0.0 {
        return Ok(Vec::new());
    }
    (0..u.terrain_clones as u64)
        .map(|i| {
            let dem = dem_clone(world.dem(), u.terrain_sigma_m, u.terrain_correlation_m, seed.wrapping_add(i))?;
            Ok(World::truth(dem, config, &job.body.model(), world)?)
        })
        .collect()
}

/// The report's figures of the plan under uncertainty.
pub(super) fn figures(ctx: &Context<'_>, plan: &MissionPlan, chance: &Chance) -> ChanceFigures {
    let u = &chance.uncertainty;
    let m = u.margins();
    let mut f = ChanceFigures {
        chance_confidence: u.confidence,
        chance_z: u.z(),
        chance_drive_time_factor: m.duration_factor,
        chance_draw_factor: m.draw_factor,
        chance_solar_factor: m.solar_factor,
        chance_action_delay_s: m.delay_s,
        chance_start_delay_s: u.start_delay_margin_s(),
        chance_correlation: format!("{:?}", u.correlation),
        ..ChanceFigures::default()
    };
    if u.terrain_sigma_m > 0.0 && (u.terrain_clones > 0 || u.terrain_plan_clones > 0) {
        f.mc_terrain_clones = (u.terrain_clones > 0).then_some(u.terrain_clones);
        f.chance_terrain_plan_clones = (u.terrain_plan_clones > 0).then_some(u.terrain_plan_clones);
        f.chance_terrain_sigma_m = Some(u.terrain_sigma_m);
        f.chance_terrain_correlation_m = Some(u.terrain_correlation_m);
    }
    deterministic_figures(&mut f, ctx, plan, chance);
    monte_carlo_figures(&mut f, ctx, chance);
    f
}

/// The deterministic plan beside the chance-constrained one: what the margins cost.
fn deterministic_figures(f: &mut ChanceFigures, ctx: &Context<'_>, plan: &MissionPlan, chance: &Chance) {
    match &chance.deterministic {
        Some(Ok(d)) => {
            let (extra_h, extra_wh) =
                ((plan.duration_s() - d.duration_s()) / 3600.0, energy_used_wh(plan) - energy_used_wh(d));
            f.deterministic_plan_duration_h = Some(d.duration_s() / 3600.0);
            f.deterministic_plan_min_battery_wh = Some(d.min_battery_wh() - super::floor_wh(ctx));
            f.chance_extra_duration_h = Some(extra_h);
            f.chance_extra_energy_used_wh = Some(extra_wh);
            f.chance_cost_ratio = Some(plan.cost / d.cost);
        }
        Some(Err(why)) => f.deterministic_plan = Some(format!("none: {why}")),
        None => {}
    }
}

/// The Monte Carlo executions of both plans, open and closed loop.
fn monte_carlo_figures(f: &mut ChanceFigures, ctx: &Context<'_>, chance: &Chance) {
    let figures = |runs: &Option<Executed>| runs.as_ref().map(|r| summary_figures(ctx, &r.summary));
    f.mc = figures(&chance.chance_runs);
    f.mc_deterministic = figures(&chance.deterministic_runs);
    f.mc_closed = figures(&chance.chance_closed);
    f.mc_closed_deterministic = figures(&chance.deterministic_closed);
}

/// Energy drawn along a plan (the sum of its battery's falls), Wh.
fn energy_used_wh(plan: &MissionPlan) -> f64 {
    plan.waypoints.windows(2).map(|w| (w[0].battery_wh - w[1].battery_wh).max(0.0)).sum()
}

fn summary_figures(ctx: &Context<'_>, s: &Summary) -> MonteCarloFigures {
    let arrival = |pick: fn((f64, f64, f64)) -> f64| s.last_arrival_s.map(|a| ctx.hours(pick(a)));
    MonteCarloFigures {
        runs: s.runs,
        success_probability: s.success_probability,
        success_ci_low: s.success_interval.0,
        success_ci_high: s.success_interval.1,
        battery_ok_probability: s.battery_ok_probability,
        goal_probability: (s.goal_probability.iter().enumerate())
            .map(|(i, p)| (ctx.goal_name(i).to_string(), *p))
            .collect(),
        last_arrival_h_p05: arrival(|a| a.0),
        last_arrival_h_p50: arrival(|a| a.1),
        last_arrival_h_p95: arrival(|a| a.2),
        lowest_battery_wh_p05: s.lowest_battery_wh.0,
        lowest_battery_wh_p50: s.lowest_battery_wh.1,
        failed: s.failures.iter().cloned().collect(),
    }
}

/// The plans whose open-loop executions are plotted: the chance-constrained plan's and
/// the deterministic one's.
fn open_loop(chance: &Chance) -> Vec<(&'static str, &Executed)> {
    let Some(c) = &chance.chance_runs else { return Vec::new() };
    std::iter::once(("chance_constrained", c))
        .chain(chance.deterministic_runs.as_ref().map(|d| ("deterministic", d)))
        .collect()
}

/// Every execution, open and closed loop (`monte_carlo.csv`), with a Monte Carlo.
pub(super) fn rows(ctx: &Context<'_>, chance: &Chance) -> Option<Vec<MonteCarloRow>> {
    chance.chance_runs.as_ref()?;
    let closed = [
        ("chance_constrained_closed_loop", &chance.chance_closed),
        ("deterministic_closed_loop", &chance.deterministic_closed),
    ]
    .into_iter()
    .filter_map(|(name, r)| r.as_ref().map(|r| (name, r)));
    let rows = open_loop(chance).into_iter().chain(closed).flat_map(|(plan, r)| {
        r.executions.iter().map(move |e| MonteCarloRow {
            plan: plan.to_string(),
            run: e.run,
            succeeded: e.succeeded(),
            failure: e.failure.map_or(String::new(), |(_, f)| f.name()),
            failed_at_action: e.failure.map_or(String::new(), |(k, _)| k.to_string()),
            goals_reached: e.arrivals_s.len(),
            last_arrival_h: (e.arrivals_s.len() == ctx.goals.len())
                .then(|| e.arrivals_s.last().map(|t| ctx.hours(*t)))
                .flatten(),
            lowest_battery_wh: e.lowest_battery_wh,
        })
    });
    Some(rows.collect())
}

/// The open-loop executions' plots: arrival, battery spread, lowest battery.
pub(super) fn plots(ctx: &Context<'_>, chance: &Chance) -> Vec<Plot> {
    let plans = open_loop(chance);
    if plans.is_empty() {
        return Vec::new();
    }
    let end_s = plans
        .iter()
        .flat_map(|(_, r)| r.executions.iter().filter_map(|e| e.battery_wh.last().map(|b| b.0)))
        .fold(0.0, f64::max);
    let night = nights(ctx.truth, end_s);
    let mut plots = vec![arrival_plot(ctx, &plans, (end_s, &night)), battery_fan(ctx, &plans, (end_s, &night))];
    plots.extend(lowest_battery_histogram(&plans));
    plots
}

/// The lowest battery of every execution, above its floor, binned: a histogram per
/// plan (the chance-constrained plan blue, the deterministic red), about 30 bins of a
/// round width over the range.
fn lowest_battery_histogram(plans: &[(&'static str, &Executed)]) -> Option<Plot> {
    let lowest = || plans.iter().flat_map(|(_, r)| r.executions.iter().map(|e| e.lowest_battery_wh));
    let (lo, hi) = lowest().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let width = round_width((hi - lo).max(1e-3) / 30.0);
    let series = plans
        .iter()
        .zip(COLOURS)
        .map(|((_, r), rgb)| (r.executions.iter().map(|e| (e.lowest_battery_wh / width).floor() as i64).collect(), rgb))
        .collect();
    let names: Vec<String> = plans
        .iter()
        .zip(["blue", "red"])
        .map(|((name, _), colour)| format!("{} {colour}", name.replace('_', "-")))
        .collect();
    Some(Plot::histogram(
        "mc_lowest_battery",
        HistogramPlot {
            title: format!("Open-loop executions: lowest battery ({})", names.join(", ")),
            x_label: format!("lowest battery above its floor, Wh (bins of {width} Wh; below 0: depleted)"),
            y_label: "executions".into(),
            bin_width: Some(width),
            series,
        },
    ))
}

/// The smallest of 1, 2 and 5 times a power of ten at or above `w`.
fn round_width(w: f64) -> f64 {
    let p = 10f64.powf(w.log10().floor());
    [1.0, 2.0, 5.0, 10.0].into_iter().map(|m| m * p).find(|&c| c >= w).unwrap_or(10.0 * p)
}

const COLOURS: [(u8, u8, u8); 2] = [(30, 90, 220), (220, 30, 40)];

/// The fraction of executions that have reached the last goal, against time.
fn arrival_plot(ctx: &Context<'_>, plans: &[(&'static str, &Executed)], (end_s, night): (f64, &[(f64, f64)])) -> Plot {
    let series = plans
        .iter()
        .zip(COLOURS)
        .map(|(&(name, r), rgb)| {
            let mut t: Vec<f64> = r
                .executions
                .iter()
                .filter(|e| e.arrivals_s.len() == ctx.goals.len())
                .filter_map(|e| e.arrivals_s.last().copied())
                .collect();
            t.sort_by(f64::total_cmp);
            let n = r.executions.len().max(1) as f64;
            let points = t.iter().enumerate().map(|(i, &s)| (ctx.hours(s), (i + 1) as f64 / n)).collect();
            Series { label: format!("{} plan", name.replace('_', "-")), points, rgb, width: 2 }
        })
        .collect();
    time_plot(
        ctx,
        ("mc_arrival", "Open-loop executions: share at the last goal by each time", "fraction of executions"),
        series,
        (end_s, night),
        false,
    )
}

/// The battery's 5th, 50th and 95th percentiles after each action of each plan (at the
/// action's median end time), over the executions still going.
fn battery_fan(ctx: &Context<'_>, plans: &[(&'static str, &Executed)], (end_s, night): (f64, &[(f64, f64)])) -> Plot {
    let mut series = Vec::new();
    for (&(name, r), rgb) in plans.iter().zip(COLOURS) {
        let steps = r.executions.iter().map(|e| e.battery_wh.len()).max().unwrap_or(0);
        let mut bands = [Vec::new(), Vec::new(), Vec::new()];
        for k in 0..steps {
            let (mut t, mut e): (Vec<f64>, Vec<f64>) =
                r.executions.iter().filter_map(|x| x.battery_wh.get(k).copied()).unzip();
            t.sort_by(f64::total_cmp);
            e.sort_by(f64::total_cmp);
            let at = ctx.hours(percentile(&t, 0.5));
            for (band, q) in bands.iter_mut().zip([0.05, 0.5, 0.95]) {
                band.push((at, percentile(&e, q)));
            }
        }
        let name = name.replace('_', "-");
        for (band, (q, width)) in bands.into_iter().zip([("5th", 1), ("median", 2), ("95th", 1)]) {
            series.push(Series { label: format!("{name} plan, {q}"), points: band, rgb, width });
        }
    }
    time_plot(
        ctx,
        ("mc_battery", "Open-loop executions: battery above its floor (percentiles)", "Wh above the battery floor"),
        series,
        (end_s, night),
        false,
    )
}

/// A time plot of `series` named `name`, with its title and y label, over the nights
/// until `end_s`: lines, or `dots` (one point per plan or run).
pub(super) fn time_plot(
    ctx: &Context<'_>,
    (name, title, y_label): (&str, &str, &str),
    series: Vec<Series>,
    (end_s, night): (f64, &[(f64, f64)]),
    dots: bool,
) -> Plot {
    Plot::time(
        name,
        TimePlot {
            title: title.into(),
            x_label: time_axis_name(ctx),
            y_label: y_label.into(),
            series,
            nights: night.to_vec(),
            windows: Vec::new(),
            windows_label: String::new(),
            x_range: (0.0, end_s / 3600.0),
            dots,
            x_ticks: time_ticks(ctx),
        },
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn histogram_bins_are_round_widths_at_or_above_the_asked() {
        for (asked, width) in [(0.37, 0.5), (3.1, 5.0), (1.0, 1.0), (0.0012, 0.002), (7.0, 10.0), (12.0, 20.0)] {
            let got = super::round_width(asked);
            assert!((got - width).abs() < 1e-12 * width, "{asked}: {got}");
        }
    }
}
