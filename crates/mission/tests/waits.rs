//! The Wait action: a rover that stays where it is for any duration, charging where its
//! array sees the Sun and sleeping where it does not — against the rover's own power
//! budget worked by hand, against itself split anywhere, and in the planner and the
//! executions where the battery runs out inside a wait.

use areo_mission::uncertainty::{MonteCarlo, RunFailure, Uncertainty, open_loop};
use areo_mission::{
    Action, ActionConfig, Classes, Effect, Error, Mission, PlannerConfig, Resolution, SearchMode, Start, World,
};
use areo_rover::resources::Load;

use crate::common::{fixed_sun_world, flat, mars_world, model};

/// Rolling ground with 40 m of relief on 20 m cells, so that cells fall into each
/// other's shadows at low Sun.
fn relief(cols: usize, rows: usize) -> areo_terrain::Dem {
    areo_terrain::Dem::from_fn(cols, rows, 20.0, 20.0, |x, y| 20.0 * (x / 37.0).sin() + 20.0 * (y / 23.0).cos())
        .unwrap()
}

fn waits(step_s: f64) -> ActionConfig {
    ActionConfig { wait_step_s: Some(step_s), ..Default::default() }
}

/// Each field of two effects equal to rounding.
fn assert_same(a: &Effect, b: &Effect, what: &str) {
    let pairs = [
        (a.duration_s, b.duration_s),
        (a.energy_wh, b.energy_wh),
        (a.load_wh, b.load_wh),
        (a.peak_wh, b.peak_wh),
        (a.trailing_wh, b.trailing_wh),
        (a.deepest_wh, b.deepest_wh),
    ];
    for (x, y) in pairs {
        assert!((x - y).abs() <= 1e-9 * (1.0 + x.abs()), "{what}: {a:?} vs {b:?}");
    }
}

/// The first instant the Sun is below the horizon after being above it, from `after`,
/// to the minute.
fn sunset(world: &World, after: f64) -> f64 {
    let mut t = after;
    while world.sun(t).elevation_deg <= 0.0 {
        t += 60.0;
    }
    while world.sun(t).elevation_deg > 0.0 {
        t += 60.0;
    }
    t
}

/// The first instant the Sun is above the horizon after being below it, from `after`.
fn sunrise(world: &World, after: f64) -> f64 {
    let mut t = after;
    while world.sun(t).elevation_deg > 0.0 {
        t += 60.0;
    }
    while world.sun(t).elevation_deg <= 0.0 {
        t += 60.0;
    }
    t
}

/// Two waits back to back are one wait of their sum, to rounding: split at any
/// instant — across sunset and sunrise, in and out of cast shadows, across the edges of
/// a Communicate session — the pieces compose into the whole in duration, energy, load
/// and the battery's extremes inside. A wait integrated over samples of its own (as
/// the paper's fixed stays are) fails this wherever the net power bends between them.
#[test]
fn two_waits_back_to_back_are_one_wait() {
    let world = mars_world(relief(9, 9), 60.0, Some(32));
    let set = sunset(&world, 0.0);
    let model = model(600.0, waits(600.0)).with_sessions(vec![(set - 5000.0, set - 1234.5)]);
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut shaded = 0;
    for case in 0..300 {
        let cell = world.cell((next() * 9.0) as usize % 9, (next() * 9.0) as usize % 9);
        let t0 = set - 8.0 * 3600.0 + next() * 20.0 * 3600.0;
        let (d1, d2) = (next() * 5.0 * 3600.0, next() * 5.0 * 3600.0);
        let whole = model.wait(&world, cell, t0, d1 + d2).unwrap();
        let first = model.wait(&world, cell, t0, d1).unwrap();
        let second = model.wait(&world, cell, t0 + d1, d2).unwrap();
        assert_same(&first.then(&second), &whole, &format!("case {case}: {d1:.1} s + {d2:.1} s from {t0:.1} s"));
        // Three pieces too: the split is not special.
        let (a, b) = (d1 / 3.0, d2 / 2.0);
        let pieces = model
            .wait(&world, cell, t0, a)
            .unwrap()
            .then(&model.wait(&world, cell, t0 + a, d1 + b - a).unwrap())
            .then(&model.wait(&world, cell, t0 + d1 + b, d2 - b).unwrap());
        assert_same(&pieces, &whole, &format!("case {case}: three pieces"));
        let sun = world.sun(t0);
        if sun.elevation_deg > 5.0 && !world.lit(cell, &sun) {
            shaded += 1;
        }
    }
    // The cases reach cells in the terrain's shadow while the Sun is up: the relief
    // matters, not only the day and night.
    assert!(shaded >= 3, "only {shaded} cases in cast shadow");
}

/// Under a fixed Sun the net power is constant, so a wait's energy is the rover's
/// power budget worked by hand: in the Sun, the charge load against the array facing
/// the Sun, through the charge efficiency — or asleep, if that drains less; in the
/// dark, the low load through the discharge efficiency; in a session, at least the
/// high load (the radio).
#[test]
fn a_wait_charges_in_the_sun_and_sleeps_in_the_dark() {
    let hours = 2.0;
    for el in [60.0, 8.0, -10.0] {
        let world = fixed_sun_world(flat(5, 5, 10.0), 120.0, el, 24.0);
        let model = model(600.0, waits(300.0));
        let rover = model.rover();
        let cell = world.cell(2, 2);
        let t0 = 3.0 * 3600.0;
        let sun = world.sun(t0);
        let battery = |net_w: f64| {
            let wh = net_w * hours;
            if wh >= 0.0 { wh / rover.battery.discharge_efficiency } else { wh * rover.battery.charge_efficiency }
        };
        let source = model.source_w(&world, cell, &sun, None);
        let charging = rover.electronics.power_w(Load::Medium) - source;
        let sleeping = rover.electronics.power_w(Load::Low) - rover.nuclear_w;
        let expected = battery(if el > 0.0 { charging.min(sleeping) } else { sleeping });
        let effect = model.wait(&world, cell, t0, hours * 3600.0).unwrap();
        assert!((effect.energy_wh - expected).abs() < 1e-9, "elevation {el}°: {} vs {expected}", effect.energy_wh);
        if el == 60.0 {
            assert!(effect.energy_wh < -10.0, "a high Sun charges: {effect:?}");
        }
        if el < 0.0 {
            assert!(effect.energy_wh > 1.0 && (effect.peak_wh - effect.energy_wh).abs() < 1e-9, "{effect:?}");
        }
        // In a session the radio's high load replaces a lower one.
        let talking = model.clone().with_sessions(vec![(0.0, 24.0 * 3600.0)]);
        let high = rover.electronics.power_w(Load::High);
        let in_session = battery(if el > 0.0 { (high - source).min(high - rover.nuclear_w) } else { high });
        let effect = talking.wait(&world, cell, t0, hours * 3600.0).unwrap();
        assert!((effect.energy_wh - in_session).abs() < 1e-9, "elevation {el}° in a session: {effect:?}");
    }
}

/// The planner's verdict on a rover that must charge where it stands, from `battery`
/// Wh, to hold `goal_wh` at the end; its wait steps and actions are on whole minutes so
/// that the verdict is exact (the last resort at the quanta).
fn charge_in_place(
    world: &World,
    t0: f64,
    battery: f64,
    goal_wh: f64,
) -> areo_mission::Result<areo_mission::MissionPlan> {
    let actions = ActionConfig { time_quantum_s: 60.0, ..waits(600.0) };
    let model = model(2000.0, actions.clone());
    let cell = world.cell(2, 2);
    let config = PlannerConfig {
        actions,
        goal_energy_wh: goal_wh,
        max_wait_s: Some(10.0 * 3600.0),
        search: SearchMode::Approximate(Classes {
            resolution: Resolution { time_s: 60.0, energy_wh: None },
            ..Classes::default()
        }),
        ..PlannerConfig::default()
    };
    let start = Start { cell, t_min: t0, t_max: t0, energy_wh: battery };
    Mission::plan(world, &model, config, start, &[cell]).map(|(_, p)| p)
}

/// A wait that begins two hours before sunrise drains in the dark, then gains more
/// than it drained. Judged at its ends it needs nothing; the battery runs out before
/// the Sun is up unless it holds the night's part — in the planner (no plan below
/// that, one at it) and in the executions (the same plan from less charge runs out
/// inside a wait step before sunrise).
#[test]
fn a_wait_across_sunrise_needs_the_night_s_drain_before_it() {
    let world = mars_world(flat(5, 5, 10.0), 36.0, None);
    let model = model(2000.0, ActionConfig { time_quantum_s: 60.0, ..waits(600.0) });
    let rise = sunrise(&world, 0.0);
    let t0 = rise - 2.0 * 3600.0;
    let cell = world.cell(2, 2);
    let effect = model.wait(&world, cell, t0, 6.0 * 3600.0).unwrap();
    assert!(effect.energy_wh < 0.0, "the wait gains overall: {effect:?}");
    // The dark two hours at the low load through the discharge efficiency, less the
    // Sun-table step that ramps to the array at sunrise.
    let rover = model.rover();
    let low_w = rover.electronics.power_w(Load::Low);
    let step_h = world.sun_step_s() / 3600.0;
    let dark_wh = low_w * (2.0 - step_h) / rover.battery.discharge_efficiency;
    assert!(effect.peak_wh >= dark_wh - 1e-6, "{} against the dark hours' {dark_wh}", effect.peak_wh);
    assert!(effect.peak_wh <= low_w * (2.0 + step_h) / rover.battery.discharge_efficiency + 1e-6, "{effect:?}");

    let below = 0.9 * effect.peak_wh;
    let goal_wh = effect.peak_wh + 5.0;
    match charge_in_place(&world, t0, below, goal_wh) {
        Err(Error::Unreachable { .. }) => {}
        other => panic!("from {below:.1} Wh, below the night's {:.1} Wh: {other:?}", effect.peak_wh),
    }
    let plan = charge_in_place(&world, t0, effect.peak_wh + 0.01, goal_wh).unwrap();
    assert!(plan.wait_steps() >= 3, "the plan waits through sunrise: {:?}", plan.waypoints);
    assert!(plan.waypoints.iter().filter_map(|w| w.action).all(|a| a == Action::Wait), "{:?}", plan.waypoints);

    let start = Start { cell, t_min: t0, t_max: t0, energy_wh: below };
    let runs =
        open_loop(&plan, &model, &world, start, &Uncertainty::default(), &MonteCarlo { runs: 1, seed: 1 }).unwrap();
    let (step, failure) = runs[0].failure.expect("the run from less charge fails");
    assert_eq!(failure, RunFailure::BatteryDepleted, "{:?}", runs[0]);
    let failed_at = plan.waypoints[step].t_s;
    assert!(failed_at < rise, "it runs out in a wait step before sunrise, not at {failed_at} s (sunrise {rise} s)");
}

/// A wait across sunset from a full battery: the evening's gain is lost at the
/// capacity, and the night's drain then comes off a full battery — the wait ends lower
/// than its net energy says.
#[test]
fn a_full_battery_cannot_bank_what_a_wait_across_sunset_gains() {
    let world = mars_world(flat(5, 5, 10.0), 36.0, None);
    let model = model(1000.0, waits(600.0));
    let set = sunset(&world, 0.0);
    let effect = model.wait(&world, world.cell(2, 2), set - 4.0 * 3600.0, 8.0 * 3600.0).unwrap();
    let capacity = model.capacity_wh();
    assert!(effect.trailing_wh > effect.energy_wh.max(0.0) + 1.0, "{effect:?}");
    let end = effect.after(capacity, capacity);
    assert!((end - (capacity - effect.trailing_wh)).abs() < 1e-9);
    assert!(end < capacity - effect.energy_wh.max(0.0) - 1.0, "the evening's gain is lost at the capacity");
}

/// A wait step out of range is refused, naming the field and what is allowed.
#[test]
fn a_wait_step_out_of_range_names_the_field() {
    for bad in [0.0, -60.0, 1e9, f64::NAN] {
        let config = PlannerConfig { actions: waits(bad), ..PlannerConfig::default() };
        match config.validate() {
            Err(Error::Config { field, message }) => {
                assert_eq!(field, "actions.wait_step_s");
                assert!(message.contains("1..=86400"), "{message}");
            }
            other => panic!("wait_step_s {bad}: {other:?}"),
        }
    } // A wait step shorter than a time class would be merged with the instant it began
    // at: refused, naming both fields.
    let config = PlannerConfig {
        actions: waits(300.0),
        search: SearchMode::Approximate(Classes {
            resolution: Resolution { time_s: 1200.0, energy_wh: None },
            ..Classes::default()
        }),
        ..PlannerConfig::default()
    };
    match config.validate() {
        Err(Error::Config { field, message }) => {
            assert_eq!(field, "actions.wait_step_s");
            assert!(message.contains("resolution.time_s"), "{message}");
        }
        other => panic!("a wait step inside a time class: {other:?}"),
    }
}
