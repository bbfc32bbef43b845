//! Plans a rover could take: the best plan as a sequence of commands a rover's
//! sequencing would read — what each wheel steers to, how far and on what arc the
//! rover drives, where the arm's joints go, and how long and how much energy each
//! takes as predicted by the quasi-static model.
//!
//! Steering follows from the arc (Ackermann): the corner wheels are turned so that
//! every wheel rolls on a circle about the turn centre, which lies on the middle axle's
//! line at the arc's radius from the reference point (a point turn: at the reference
//! point). The middle wheels do not steer.

use areo_rover::RoverParams;
use areo_rover::motion::Module;
use serde::Serialize;

use crate::executor::Execution;

/// One command of an exported plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Command {
    /// Position in the plan, from 1.
    pub step: usize,
    /// Table 1 code.
    pub code: u16,
    /// What it does, in words.
    pub action: &'static str,
    /// Distance the reference point drives along its path, m (negative backing up;
    /// 0 for modules that do not drive).
    pub distance_m: f64,
    /// Radius of the reference point's arc, m, positive turning left; `None` driving
    /// straight or not driving; 0 for a turn in place.
    pub arc_radius_m: Option<f64>,
    /// Heading change over the command, degrees, positive to the left.
    pub turn_deg: f64,
    /// Steering angles of the corner wheels, degrees, positive to the left: left front,
    /// right front, left rear, right rear. `None` when the wheels do not roll.
    pub steering_deg: Option<[f64; 4]>,
    /// Arm joint targets at the command's end, degrees: shoulder yaw (left positive),
    /// shoulder pitch above the horizontal, elbow (180 = straight). `None` if the
    /// arm's pose has no joint solution (it always has one for a validated rover).
    pub arm_joints_deg: Option<[f64; 3]>,
    /// The tool (wrist) at the command's end, body frame (forward, left, up), m.
    pub tool_m: [f64; 3],
    /// Duration, s.
    pub duration_s: f64,
    /// Battery energy, Wh (negative when charging).
    pub energy_wh: f64,
    /// Where the reference point ends: east, north (map, m) and heading (degrees
    /// clockwise from north).
    pub end: [f64; 3],
    /// Least stability margin during the command, when it moved anything.
    pub stability: Option<f64>,
}

/// What a module does, in words.
fn action(m: Module) -> &'static str {
    match m {
        Module::Forward => "drive forward",
        Module::Backward => "drive backward",
        Module::TurnLeft => "turn left in place",
        Module::TurnRight => "turn right in place",
        Module::ArcLeftTight | Module::ArcLeftWide => "drive forward on an arc to the left",
        Module::ArcRightTight | Module::ArcRightWide => "drive forward on an arc to the right",
        Module::VideoStart => "start video",
        Module::VideoEnd => "end video",
        Module::SweepSensors => "sweep sensors",
        Module::Sleep => "sleep",
        Module::Communicate => "communicate",
        Module::ArmForward => "arm forward",
        Module::ArmBack => "arm back",
        Module::ArmLeft => "arm left",
        Module::ArmRight => "arm right",
        Module::ArmDown => "arm down",
        Module::ArmUp => "arm up",
        Module::TrayDeploy => "deploy the science tray",
        Module::TrayRetract => "retract the science tray",
        Module::TurnToSample => "turn to the sample",
        Module::TurnFromSample => "turn from the sample",
        Module::Grasp => "grasp the sample",
        Module::Release => "release the sample",
        Module::Recharge => "recharge",
    }
}

/// Steering angles (rad, positive left) of the corner wheels — left front, right
/// front, left rear, right rear — for a turn centre `radius_m` to the left of the
/// reference point (negative: to the right; 0: a turn in place).
pub fn steering(params: &RoverParams, radius_m: f64) -> [f64; 4] {
    let half = params.track_m / 2.0;
    let (front, rear) = (params.axle_x_m.front, params.axle_x_m.rear);
    // A wheel at (x, y) rolls square to the line from the centre (0, R): it is turned
    // by atan(x / (R − y)). Straight ahead (R infinite) that is 0.
    let angle = |x: f64, y: f64| if radius_m.is_infinite() { 0.0 } else { (x / (radius_m - y)).atan() };
    [angle(front, half), angle(front, -half), angle(rear, half), angle(rear, -half)]
}

/// The executed part of `plan` as commands (`execution` run with a trace), the rover
/// starting at `start_heading_deg` (clockwise from north).
pub fn commands(plan: &[Module], execution: &Execution, params: &RoverParams, start_heading_deg: f64) -> Vec<Command> {
    let mut heading_before = start_heading_deg;
    plan.iter()
        .zip(&execution.trace)
        .enumerate()
        .map(|(i, (&m, t))| {
            // Heading is clockwise; a left turn is positive here.
            let turned = 180.0 - (t.heading_deg - heading_before + 540.0).rem_euclid(360.0);
            heading_before = t.heading_deg;
            // Turns to and from a sample are turns in place (by up to 15°, or none).
            let sample_turn = matches!(m, Module::TurnToSample | Module::TurnFromSample) && turned.abs() > 1e-9;
            let path = m.path().or(sample_turn.then_some((0.0, 0.0, turned.to_radians())));
            let arc = path.and_then(|(d, r, _)| if d == 0.0 { Some(0.0) } else { r.is_finite().then_some(r) });
            let arm = areo_rover::arm::ArmState { tool_m: t.tool_m, payload_kg: 0.0 };
            Command {
                step: i + 1,
                code: m.code(),
                action: action(m),
                distance_m: path.map_or(0.0, |(d, _, _)| d),
                arc_radius_m: arc,
                turn_deg: turned,
                steering_deg: path.map(|(_, r, _)| steering(params, r).map(f64::to_degrees)),
                arm_joints_deg: arm
                    .joints(params)
                    .ok()
                    .map(|j| [j.yaw.to_degrees(), j.shoulder.to_degrees(), j.elbow.to_degrees()]),
                tool_m: t.tool_m,
                duration_s: t.duration_s,
                energy_wh: t.energy_wh,
                end: [t.x_m, t.y_m, t.heading_deg],
                stability: t.stability,
            }
        })
        .collect()
}
