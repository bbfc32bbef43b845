//! The battery is checked inside every action, not only at its ends: the planner
//! refuses, and the executions report, a plan whose charge goes below the floor in the
//! middle of an action whose ends balance.

use areo_mission::uncertainty::{MonteCarlo, RunFailure, Uncertainty, open_loop};
use areo_mission::{
    Action, ActionConfig, ActionModel, Classes, Error, Mission, Perturbation, PlannerConfig, Resolution, SearchMode,
    Start, World,
};

use crate::common::{fixed_sun_world, flat, mars_world, model};

/// The actions of `actions` on whole minutes, so that the planner's verdicts are exact
/// at them (its last resort): an "unreachable" here is not an artefact of sampled goal
/// instants.
fn planner(actions: ActionConfig, goal_energy_wh: f64) -> PlannerConfig {
    assert_eq!(actions.time_quantum_s, 60.0);
    PlannerConfig {
        actions,
        goal_energy_wh,
        search: SearchMode::Approximate(Classes {
            resolution: Resolution { time_s: 60.0, energy_wh: None },
            ..Classes::default()
        }),
        ..PlannerConfig::default()
    }
}

/// Plans from `battery` Wh at the start cell, which is the goal, to end there with
/// `goal_wh`: the only way is to charge first.
fn plan_in_place(
    world: &World,
    model: &ActionModel,
    actions: &ActionConfig,
    t0: f64,
    battery: f64,
    goal_wh: f64,
) -> areo_mission::Result<areo_mission::MissionPlan> {
    let cell = world.cell(2, 2);
    let start = Start { cell, t_min: t0, t_max: t0, energy_wh: battery };
    Mission::plan(world, model, planner(actions.clone(), goal_wh), start, &[cell]).map(|(_, p)| p)
}

/// A Charge whose first quarter hour (the planning margin's delay) runs on the
/// generator alone — Hyperion has none, so on the battery — under a Sun that then
/// gives far more than the load: the ends balance in the rover's favour, the middle
/// does not.
#[test]
fn a_charge_that_warms_up_without_its_array_needs_charge_for_the_warm_up() {
    let world = fixed_sun_world(flat(5, 5, 10.0), 180.0, 60.0, 24.0);
    let mut actions = ActionConfig { charge_s: 1800.0, time_quantum_s: 60.0, ..Default::default() };
    // Nothing but the charge: hibernation needs the Sun too, and is a drain anyway.
    actions.hibernate.direct_sun = true;
    let warm_up = Perturbation { delay_s: 900.0, ..Perturbation::NONE };
    let model = model(400.0, actions.clone()).with_margins(warm_up);
    let cell = world.cell(2, 2);
    let effect = model.stay(&world, Action::Charge, cell, 3600.0).unwrap();
    assert!(effect.energy_wh < -5.0, "the charge gains overall: {}", effect.energy_wh);
    // At least what the medium load draws in the warm-up's part before the ramp to
    // the array (the trapezoid's first sample is the generator's).
    assert!(effect.peak_wh > 1.0, "the warm-up draws: {effect:?}");
    // The end-only rule would accept an empty battery: max(E + Δe, 0) = 0.
    assert!((effect.required_before(0.0) - effect.peak_wh).abs() < 1e-12);

    let below = 0.9 * effect.peak_wh;
    // More than the rover starts with, so it must charge.
    let goal_wh = below + 1.0;
    match plan_in_place(&world, &model, &actions, 3600.0, below, goal_wh) {
        Err(Error::Unreachable { .. }) => {}
        other => panic!("from {below:.2} Wh, below the warm-up's {:.2} Wh: {other:?}", effect.peak_wh),
    }
    let plan = plan_in_place(&world, &model, &actions, 3600.0, effect.peak_wh + 0.01, goal_wh).unwrap();
    assert_eq!(plan.waypoints[0].action, Some(Action::Charge));
}

/// The instant of the first sunrise after `after` s on `world`, to the Sun table's step.
fn sunrise(world: &World, after: f64) -> f64 {
    let mut t = after;
    while world.sun(t).elevation_deg > 0.0 || world.sun(t + 60.0).elevation_deg <= 0.0 {
        t += 60.0;
        assert!(t < world.span_s(), "no sunrise");
    }
    t + 60.0
}

/// A six-hour stay that starts two hours before sunrise: it drains in the dark, then
/// gains more than it drained. Judged at its ends it needs nothing; the battery runs
/// out before the Sun is up unless it holds the night's part.
#[test]
fn a_stay_across_sunrise_needs_the_night_s_drain_before_it() {
    let world = mars_world(flat(5, 5, 10.0), 36.0, None);
    // Hibernation only in the Sun, so the night offers nothing but the long stay; and
    // short, since the planner widens a start window to one Hibernate (the rover idles
    // at the start until it begins), which would let it sleep through part of the dark.
    let mut actions =
        ActionConfig { charge_s: 6.0 * 3600.0, hibernate_s: 120.0, time_quantum_s: 60.0, ..Default::default() };
    actions.charge.direct_sun = false;
    actions.hibernate.direct_sun = true;
    let model = model(2000.0, actions.clone());
    let t0 = sunrise(&world, 0.0) - 2.0 * 3600.0;
    let cell = world.cell(2, 2);
    let effect = model.stay(&world, Action::Charge, cell, t0).unwrap();
    assert!(effect.energy_wh < 0.0, "the stay gains overall: {effect:?}");
    // The dark hours at the medium load through the discharge efficiency, less the
    // one integration segment (20 min) that straddles sunrise and ramps to the array.
    let rover = model.rover();
    let dark_h = 2.0 - 1200.0 / 3600.0;
    let medium_w = rover.electronics.power_w(areo_rover::resources::Load::Medium);
    let dark_wh = medium_w * dark_h / rover.battery.discharge_efficiency;
    assert!(effect.peak_wh >= dark_wh - 1e-6, "{} against the dark hours' {dark_wh}", effect.peak_wh);
    assert!(effect.peak_wh <= medium_w * 2.0 / rover.battery.discharge_efficiency + 1e-6, "{effect:?}");

    // The planner: below the night's drain there is no plan, at it there is.
    let below = 0.9 * effect.peak_wh;
    // More than the rover starts with in either case, so it must charge.
    let goal_wh = effect.peak_wh + 5.0;
    match plan_in_place(&world, &model, &actions, t0, below, goal_wh) {
        Err(Error::Unreachable { .. }) => {}
        other => panic!("from {below:.1} Wh, below the night's {:.1} Wh: {other:?}", effect.peak_wh),
    }
    let plan = plan_in_place(&world, &model, &actions, t0, effect.peak_wh + 0.01, goal_wh).unwrap();
    assert_eq!(plan.waypoints[0].action, Some(Action::Charge));

    // The executions: the same plan, run from less charge, runs out inside the stay —
    // and its end alone would not have said so.
    let start = Start { cell, t_min: t0, t_max: t0, energy_wh: below };
    let runs =
        open_loop(&plan, &model, &world, start, &Uncertainty::default(), &MonteCarlo { runs: 1, seed: 1 }).unwrap();
    assert_eq!(runs[0].failure, Some((0, RunFailure::BatteryDepleted)), "{:?}", runs[0]);
    assert!((runs[0].lowest_battery_wh - (below - effect.peak_wh)).abs() < 1e-9, "{:?}", runs[0]);
    assert!(below - effect.energy_wh > goal_wh, "the stay's ends balance");
}

/// Sunset the other way round: a stay that charges a full battery in the evening (the
/// gain is lost at the capacity) and then drains through the night ends lower than
/// its net energy says.
#[test]
fn a_full_battery_cannot_bank_what_a_stay_across_sunset_gains() {
    let world = mars_world(flat(5, 5, 10.0), 36.0, None);
    let mut actions = ActionConfig { charge_s: 8.0 * 3600.0, ..Default::default() };
    actions.charge.direct_sun = false;
    let model = model(1000.0, actions);
    // Find a sunset: the first instant after a sunrise at which the Sun goes down.
    let rise = sunrise(&world, 0.0);
    let mut set = rise + 3600.0;
    while world.sun(set).elevation_deg > 0.0 {
        set += 60.0;
    }
    let t0 = set - 4.0 * 3600.0;
    let effect = model.stay(&world, Action::Charge, world.cell(2, 2), t0).unwrap();
    let capacity = model.capacity_wh();
    assert!(effect.trailing_wh > effect.energy_wh.max(0.0) + 1.0, "{effect:?}");
    let end = effect.after(capacity, capacity);
    assert!((end - (capacity - effect.trailing_wh)).abs() < 1e-9);
    assert!(end < capacity - effect.energy_wh.max(0.0) - 1.0, "the evening's gain is lost at the capacity");
}
