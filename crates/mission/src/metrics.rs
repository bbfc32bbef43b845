//! Measures of a plan and of an executed run: [`PlanMetrics`], the same figures for
//! both (actions by kind, time in each, distance, drives at night and in the sun); and
//! measures taken on the world by sampling rather than from the planner's own
//! constraints, so that a report can check the planner: how far the Sun moved over a
//! plan and how low it went, how many drives kept a body-fixed array facing the Sun,
//! and how a run drove (zig-zags, night and shadowed drives).

use serde::Serialize;

use crate::action_model::Action;
use crate::plan::MissionPlan;
use crate::simulate::{ExecutedStep, SimReport};
use crate::world::World;

/// What a plan or an executed run does, measured alike for both.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct PlanMetrics {
    /// Drives.
    pub drives: usize,
    /// Charges.
    pub charges: usize,
    /// Hibernations.
    pub hibernations: usize,
    /// Wait steps (a plan's waits back to back count one each).
    pub wait_steps: usize,
    /// Time driving, h.
    pub drive_h: f64,
    /// Time charging, h.
    pub charge_h: f64,
    /// Time hibernating, h.
    pub hibernate_h: f64,
    /// Time waiting, h.
    pub wait_h: f64,
    /// Distance: a plan's waypoints joined on the map's plane, a run's drives as
    /// executed, m.
    pub distance_m: f64,
    /// Drives begun with the Sun at or below the horizon.
    pub night_drives: usize,
    /// The share of drives begun in sunlight — on the terrain's horizons (a plan's as
    /// the planner saw them, a run's on the true terrain); 1 without drives.
    pub sunlit_drive_fraction: f64,
}

impl PlanMetrics {
    /// A plan's figures, from its waypoints.
    pub fn of_plan(plan: &MissionPlan) -> PlanMetrics {
        let (drives, charges, hibernations) = plan.action_counts();
        let steps = plan.waypoints.windows(2).filter_map(|w| Some((w[0].action?, w[1].t_s - w[0].t_s)));
        let hours = |which: &dyn Fn(Action) -> bool| {
            // A fold from +0: `sum` of no f64 is -0, which prints as "-0.0 h".
            steps.clone().filter(|(a, _)| which(*a)).map(|(_, d)| d).fold(0.0, |a, d| a + d) / 3600.0
        };
        let drive_wps: Vec<_> = plan.waypoints.iter().filter(|w| matches!(w.action, Some(Action::Drive(_)))).collect();
        PlanMetrics {
            drives,
            charges,
            hibernations,
            wait_steps: plan.wait_steps(),
            drive_h: hours(&|a| matches!(a, Action::Drive(_))),
            charge_h: hours(&|a| a == Action::Charge),
            hibernate_h: hours(&|a| a == Action::Hibernate),
            wait_h: hours(&|a| a == Action::Wait),
            distance_m: (plan.waypoints.windows(2))
                .map(|w| (w[1].easting_m - w[0].easting_m).hypot(w[1].northing_m - w[0].northing_m))
                .sum(),
            night_drives: drive_wps.iter().filter(|w| w.sun_elevation_deg <= 0.0).count(),
            sunlit_drive_fraction: if drive_wps.is_empty() {
                1.0
            } else {
                drive_wps.iter().filter(|w| w.lit).count() as f64 / drive_wps.len() as f64
            },
        }
    }

    /// A run's figures, from its executed steps on `truth`.
    pub fn of_run(run: &SimReport, truth: &World) -> PlanMetrics {
        let count = |which: &dyn Fn(Action) -> bool| run.steps.iter().filter(|s| which(s.action)).count();
        let hours = |which: &dyn Fn(Action) -> bool| {
            run.steps.iter().filter(|s| which(s.action)).map(|s| s.duration_s).fold(0.0, |a, d| a + d) / 3600.0
        };
        PlanMetrics {
            drives: count(&|a| matches!(a, Action::Drive(_))),
            charges: count(&|a| a == Action::Charge),
            hibernations: count(&|a| a == Action::Hibernate),
            wait_steps: count(&|a| a == Action::Wait),
            drive_h: hours(&|a| matches!(a, Action::Drive(_))),
            charge_h: hours(&|a| a == Action::Charge),
            hibernate_h: hours(&|a| a == Action::Hibernate),
            wait_h: hours(&|a| a == Action::Wait),
            distance_m: run.distance_m(),
            night_drives: night_drives(&run.steps),
            sunlit_drive_fraction: sunlit_drive_fraction(truth, &run.steps),
        }
    }
}

/// The Sun over a plan, sampled every `step_s` from its first waypoint to its last.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SunAlong {
    /// How far the Sun's azimuth turns, degrees (each step's shortest turn, summed).
    pub azimuth_span_deg: f64,
    /// The lowest Sun elevation, degrees (at most 90).
    pub lowest_elevation_deg: f64,
}

/// The Sun's azimuth span and lowest elevation over `plan`, sampled every `step_s`.
pub fn sun_along(world: &World, plan: &MissionPlan, step_s: f64) -> SunAlong {
    let (t0, t1) = (plan.waypoints.first().map_or(0.0, |w| w.t_s), plan.waypoints.last().map_or(0.0, |w| w.t_s));
    let n = (((t1 - t0) / step_s).ceil() as usize).max(1);
    let azimuth_span_deg: f64 = (0..n)
        .map(|k| {
            let a = world.sun(t0 + (t1 - t0) * k as f64 / n as f64).azimuth_deg;
            let b = world.sun(t0 + (t1 - t0) * (k + 1) as f64 / n as f64).azimuth_deg;
            ((b - a + 180.0).rem_euclid(360.0) - 180.0).abs()
        })
        .sum();
    let lowest_elevation_deg =
        (0..=n).map(|k| world.sun(t0 + (t1 - t0) * k as f64 / n as f64).elevation_deg).fold(90.0, f64::min);
    SunAlong { azimuth_span_deg, lowest_elevation_deg }
}

/// The share of `plan`'s drives whose array — facing `facing_deg` clockwise from the
/// direction of travel — points within 90° of the Sun's azimuth at the drive's middle
/// (sun-synchronous driving); 0 without drives.
pub fn sunward_drive_fraction(world: &World, plan: &MissionPlan, facing_deg: f64) -> f64 {
    let drives: Vec<_> = plan.waypoints.windows(2).filter(|w| matches!(w[0].action, Some(Action::Drive(_)))).collect();
    let sunward = drives
        .iter()
        .filter(|w| {
            let heading = (w[1].easting_m - w[0].easting_m).atan2(w[1].northing_m - w[0].northing_m).to_degrees();
            let facing = heading + facing_deg;
            let sun = world.sun(0.5 * (w[0].t_s + w[1].t_s)).azimuth_deg;
            ((facing - sun + 180.0).rem_euclid(360.0) - 180.0).abs() < 90.0
        })
        .count();
    sunward as f64 / drives.len().max(1) as f64
}

/// Back-to-back diagonal drives at right angles (NE then NW, …) among executed steps:
/// a zig-zag that one straight drive of the same net advance would beat when the
/// objective counts length.
pub fn zigzag_pairs(steps: &[ExecutedStep]) -> usize {
    steps
        .windows(2)
        .filter(|w| match (w[0].action, w[1].action) {
            (Action::Drive(a), Action::Drive(b)) => a % 2 == 1 && b % 2 == 1 && (a + 8 - b) % 8 % 4 == 2,
            _ => false,
        })
        .count()
}

/// Executed drives begun with the Sun at or below the horizon.
pub fn night_drives(steps: &[ExecutedStep]) -> usize {
    steps.iter().filter(|s| matches!(s.action, Action::Drive(_)) && s.sun_elevation_deg <= 0.0).count()
}

/// The share of executed drives begun in sunlight on `truth` (1 without drives).
pub fn sunlit_drive_fraction(truth: &World, steps: &[ExecutedStep]) -> f64 {
    let drives = steps.iter().filter(|s| matches!(s.action, Action::Drive(_))).count();
    let shadowed =
        steps.iter().filter(|s| matches!(s.action, Action::Drive(_)) && !truth.lit(s.cell, &truth.sun(s.t_s))).count();
    if drives > 0 { 1.0 - shadowed as f64 / drives as f64 } else { 1.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(action: Action, sun_elevation_deg: f64) -> ExecutedStep {
        ExecutedStep {
            t_s: 0.0,
            cell: 0,
            to: 0,
            action,
            duration_s: 60.0,
            energy_wh: 0.0,
            load_wh: 0.0,
            battery_above_floor_wh: 0.0,
            distance_m: 0.0,
            sun_elevation_deg,
            refused: None,
        }
    }

    #[test]
    fn zigzags_are_diagonals_at_right_angles_back_to_back() {
        // NE then NW, and SE then SW, turn 90°; NW then NW, SW then NE (a reversal), an
        // orthogonal pair and a drive after a charge do not.
        let d = |k| step(Action::Drive(k), 10.0);
        let steps = [d(1), d(7), d(7), step(Action::Charge, 10.0), d(3), d(5), d(1), d(2), d(4)];
        assert_eq!(zigzag_pairs(&steps), 2);
        assert_eq!(zigzag_pairs(&steps[..2]), 1);
        assert_eq!(zigzag_pairs(&[]), 0);
    }

    #[test]
    fn night_drives_count_drives_begun_with_the_sun_down() {
        let steps = [
            step(Action::Drive(0), 0.0),
            step(Action::Drive(0), -5.0),
            step(Action::Drive(0), 0.1),
            step(Action::Hibernate, -20.0),
        ];
        assert_eq!(night_drives(&steps), 2);
    }
}
