//! Motion primitives: every action module of Farritor et al.'s Table 1, executed as a
//! sequence of quasi-static poses, each evaluated in full ([`Evaluator`]), returning the
//! state after the module with its duration and energy, or the first violated
//! constraint and where it happened.
//!
//! Sampling: poses lie on a grid of [`Motion::spacing_m`] of the reference point's
//! travel on drives and arcs (1 cm by default, so a ditch edge or a rock is never
//! stepped over; the reference asks for ≥ 3 per 10 cm) and of the farthest wheel's
//! travel on point turns (a 5° turn rolls the corner wheels under 3 cm). The motion
//! strides up to [`Motion::coarse_steps`] grid steps where the pose changes smoothly —
//! every contact angle within 5°, pitch and roll within 1°, stability, friction and
//! torque margins within 0.05 ([`Signature`]) — and halves the stride back to one step
//! wherever it does not, or where a pose fails, so a failure is reported at the first
//! failing grid point, as sampling every step would. A module's first pose re-uses the
//! previous module's last one (only the forces change with the new motion). Poses are
//! checked in order against [`Motion::stability_floor`] too. Energy integrates the
//! electrical power over the samples (trapezoid rule):
//! P = Σ_i (max(τ_i ω_i, 0)/η_g + k τ_i²) + P₀, with ω_i = v_i/r from each wheel's
//! speed about the instantaneous centre of rotation (the paper's Table 1 misprints 106
//! as a right arc; it is the wide left one). Arm modules cost the rise in potential
//! energy of the arm and sample over the joint efficiency plus hotel power; the others
//! their listed load for their listed time.
//!
//! \[A\] Assumptions, all in the parameter file: point turns and arcs use steerable
//! corner wheels (as on Sojourner); "turn to sample" turns toward the nearest sample by
//! at most `activities.turn_to_sample_deg` and "turn from sample" undoes it — a stance
//! for the arm, not a steering command: a driving module after a turn to a sample
//! first turns back to the route heading (its time and energy counted), so the sample
//! modules never change the way the rover drives; while
//! recharging the Sun is overhead, so the array's output is flux × area × efficiency ×
//! cos(tilt).

use areo_terrain::Ground;

use crate::arm::ArmState;
use crate::evaluation::{Conditions, Evaluation, Evaluator, Place, Violation};
use crate::kinematics::Pose;

/// The action modules of Table 1 (numbers are the paper's).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
pub enum Module {
    /// 101: move forward 10 cm.
    Forward,
    /// 102: move back 10 cm.
    Backward,
    /// 103: turn left 5°.
    TurnLeft,
    /// 104: turn right 5°.
    TurnRight,
    /// 105: 10 cm forward on a 50 cm-radius circle to the left.
    ArcLeftTight,
    /// 106: 10 cm forward on a 200 cm-radius circle to the left.
    ArcLeftWide,
    /// 107: 10 cm forward on a 50 cm-radius circle to the right.
    ArcRightTight,
    /// 108: 10 cm forward on a 200 cm-radius circle to the right.
    ArcRightWide,
    /// 901: transmit video.
    VideoStart,
    /// 902: end video.
    VideoEnd,
    /// 910: sweep sensors.
    SweepSensors,
    /// 920: sleep.
    Sleep,
    /// 921: communicate with the ground station.
    Communicate,
    /// 1001: arm +x 2 cm.
    ArmForward,
    /// 1002: arm −x 2 cm.
    ArmBack,
    /// 1003: arm +y 2 cm.
    ArmLeft,
    /// 1004: arm −y 2 cm.
    ArmRight,
    /// 1005: arm −z 2 cm.
    ArmDown,
    /// 1006: arm +z 2 cm.
    ArmUp,
    /// 2010: deploy the science tray.
    TrayDeploy,
    /// 2020: retract the science tray.
    TrayRetract,
    /// 3000: turn to the sample.
    TurnToSample,
    /// 3001: turn from the sample.
    TurnFromSample,
    /// 3002: grasp the sample.
    Grasp,
    /// 3003: release the sample.
    Release,
    /// 4000: recharge the batteries with the solar array.
    Recharge,
}

impl Module {
    /// Every module, in Table 1 order.
    pub const ALL: [Module; 26] = [
        Module::Forward,
        Module::Backward,
        Module::TurnLeft,
        Module::TurnRight,
        Module::ArcLeftTight,
        Module::ArcLeftWide,
        Module::ArcRightTight,
        Module::ArcRightWide,
        Module::VideoStart,
        Module::VideoEnd,
        Module::SweepSensors,
        Module::Sleep,
        Module::Communicate,
        Module::ArmForward,
        Module::ArmBack,
        Module::ArmLeft,
        Module::ArmRight,
        Module::ArmDown,
        Module::ArmUp,
        Module::TrayDeploy,
        Module::TrayRetract,
        Module::TurnToSample,
        Module::TurnFromSample,
        Module::Grasp,
        Module::Release,
        Module::Recharge,
    ];

    /// The paper's module number.
    pub fn code(self) -> u16 {
        match self {
            Module::Forward => 101,
            Module::Backward => 102,
            Module::TurnLeft => 103,
            Module::TurnRight => 104,
            Module::ArcLeftTight => 105,
            Module::ArcLeftWide => 106,
            Module::ArcRightTight => 107,
            Module::ArcRightWide => 108,
            Module::VideoStart => 901,
            Module::VideoEnd => 902,
            Module::SweepSensors => 910,
            Module::Sleep => 920,
            Module::Communicate => 921,
            Module::ArmForward => 1001,
            Module::ArmBack => 1002,
            Module::ArmLeft => 1003,
            Module::ArmRight => 1004,
            Module::ArmDown => 1005,
            Module::ArmUp => 1006,
            Module::TrayDeploy => 2010,
            Module::TrayRetract => 2020,
            Module::TurnToSample => 3000,
            Module::TurnFromSample => 3001,
            Module::Grasp => 3002,
            Module::Release => 3003,
            Module::Recharge => 4000,
        }
    }

    /// The module with the paper's number `code`.
    pub fn from_code(code: u16) -> Option<Module> {
        Module::ALL.into_iter().find(|m| m.code() == code)
    }

    /// Direction of travel of the reference point: +1 forward, −1 backward, 0 for
    /// modules that do not drive it (turns in place, arm, instruments).
    pub fn direction(self) -> f64 {
        match self.path() {
            Some((d, _, _)) if d != 0.0 => d.signum(),
            _ => 0.0,
        }
    }

    /// A driving path: (distance of the reference point along the path, m; turn
    /// radius, m, positive left, infinite straight; in-place rotation, rad, positive
    /// left).
    pub fn path(self) -> Option<(f64, f64, f64)> {
        Some(match self {
            Module::Forward => (0.10, f64::INFINITY, 0.0),
            Module::Backward => (-0.10, f64::INFINITY, 0.0),
            Module::TurnLeft => (0.0, 0.0, 5f64.to_radians()),
            Module::TurnRight => (0.0, 0.0, -5f64.to_radians()),
            Module::ArcLeftTight => (0.10, 0.50, 0.0),
            Module::ArcLeftWide => (0.10, 2.00, 0.0),
            Module::ArcRightTight => (0.10, -0.50, 0.0),
            Module::ArcRightWide => (0.10, -2.00, 0.0),
            _ => return None,
        })
    }
}

/// The rover's state between modules.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoverState {
    /// Reference point (midpoint of the middle wheels), map frame, m.
    pub x: f64,
    /// Reference point, map frame, m.
    pub y: f64,
    /// Heading, rad clockwise from north.
    pub heading: f64,
    /// The arm.
    pub arm: ArmState,
    /// Battery charge, Wh.
    pub battery_wh: f64,
    /// Science tray deployed.
    pub tray_deployed: bool,
    /// Video on.
    pub video_on: bool,
    /// Heading change of the turns to a sample since the rover last drove, rad (undone
    /// by "turn from", or by the next driving module before it drives).
    pub sample_turn: f64,
    /// The last pose, to warm-start the next.
    pub pose: Option<Pose>,
}

impl RoverState {
    /// Parked at (x, y) with heading `heading` (rad), arm stowed, battery full.
    pub fn new(evaluator: &Evaluator, x: f64, y: f64, heading: f64) -> RoverState {
        let p = evaluator.params();
        RoverState {
            x,
            y,
            heading,
            arm: ArmState::stowed(p),
            battery_wh: p.battery.capacity_wh,
            tray_deployed: false,
            video_on: false,
            sample_turn: 0.0,
            pose: None,
        }
    }

    /// Where it stands.
    pub fn place(&self) -> Place {
        Place { x: self.x, y: self.y, heading: self.heading }
    }
}

/// Energy of a module by destination, Wh.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Energy {
    /// Mechanical work through the drives and arm joints over their efficiencies.
    pub mechanical_wh: f64,
    /// Motor copper losses Σ k τ².
    pub copper_wh: f64,
    /// Hotel (electronics) power, or the sleep draw.
    pub hotel_wh: f64,
    /// Instruments, radio, gripper, tray.
    pub payload_wh: f64,
    /// Collected by the solar array (recharging).
    pub solar_wh: f64,
}

impl Energy {
    /// Net drain on the battery, Wh (negative when charging).
    pub fn net_wh(&self) -> f64 {
        self.mechanical_wh + self.copper_wh + self.hotel_wh + self.payload_wh - self.solar_wh
    }
}

/// A module that ran to its end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModuleRun {
    /// The state after it.
    pub state: RoverState,
    /// Duration, s.
    pub duration_s: f64,
    /// Energy.
    pub energy: Energy,
    /// Smallest stability margin S over the poses it evaluated (`None` for modules that
    /// do not move anything).
    pub min_stability: Option<f64>,
    /// Largest friction used over its poses.
    pub max_friction: f64,
    /// Largest friction used over the friction available there, over its poses (1 = a
    /// wheel at its friction limit).
    pub max_friction_share: f64,
    /// Largest motor torque over the wheel torque limit, over its poses (1 = saturated).
    pub max_saturation: f64,
    /// The sample grasped by this module, if any (the id the sample lookup gave).
    pub grasped: Option<usize>,
}

impl ModuleRun {
    /// Takes in an evaluated pose's stability, friction and saturation (of a wheel
    /// torque limit of `torque_max_nm`).
    fn record(&mut self, eval: &Evaluation, torque_max_nm: f64) {
        self.min_stability = Some(self.min_stability.map_or(eval.stability, |m| m.min(eval.stability)));
        self.max_friction = self.max_friction.max(eval.friction_used);
        self.max_friction_share = self.max_friction_share.max(eval.friction_used / eval.friction_available);
        self.max_saturation = self.max_saturation.max(eval.saturation(torque_max_nm));
    }

    /// Adds `seconds` of the rover's hotel load and a payload of `load_w`, W.
    fn timed(&mut self, params: &crate::RoverParams, seconds: f64, load_w: f64) {
        self.duration_s += seconds;
        self.energy.hotel_wh += params.hotel_power_w * seconds / 3600.0;
        self.energy.payload_wh += load_w * seconds / 3600.0;
    }
}

/// A drive's motion: each wheel's speed (m/s), its duration (s) and direction (+1
/// forward, −1 backward; +1 for a turn in place).
struct Kinetics {
    wheel_speeds: [f64; 6],
    total_time: f64,
    direction: f64,
}

impl Kinetics {
    /// The fine grid of poses: for drives and arcs a step every `spacing_m` of the
    /// reference point's travel `dist` (at least 3); for point turns (`dist` 0) every
    /// `spacing_m` of the farthest wheel's travel — a 5° turn rolls the corner wheels
    /// under 3 cm.
    fn fine_steps(&self, dist: f64, spacing_m: f64) -> usize {
        if dist == 0.0 {
            let travel = self.wheel_speeds.iter().fold(0.0f64, |m, &v| m.max(v)) * self.total_time;
            ((travel / spacing_m - 1e-9).ceil() as usize).max(1)
        } else {
            ((dist.abs() / spacing_m).ceil() as usize).max(3)
        }
    }

    /// The drive's mechanical power (what the motors deliver over the gears'
    /// efficiency, never negative: no regeneration) and copper losses at a pose, W.
    fn power(&self, p: &crate::RoverParams, eval: &Evaluation) -> (f64, f64) {
        let (k_copper, eta) = (p.drive.copper_loss_w_per_nm2(), p.drive.gear_efficiency);
        let torques = eval.torques_nm();
        let (mut mech, mut copper) = (0.0, 0.0);
        for (torque, speed) in torques.iter().zip(&self.wheel_speeds) {
            let omega = speed / p.wheel_radius_m;
            mech += (torque * omega * self.direction).max(0.0) / eta;
            copper += k_copper * torque * torque;
        }
        (mech, copper)
    }
}

/// The motion of a drive of `dist` (m) along a circle of `radius` (m), or of a turn in
/// place by `turn` (rad) when `dist` is 0, at the rover's speed and turn rate.
fn kinetics(p: &crate::RoverParams, dist: f64, radius: f64, turn: f64) -> Kinetics {
    let in_place = dist == 0.0;
    // Yaw rate and reference speed.
    let (speed, yaw_rate) = if in_place {
        (0.0, p.turn_rate_deg_s.to_radians() * turn.signum())
    } else {
        let v = p.speed_m_s * dist.signum();
        (v, if radius.is_finite() { v / radius } else { 0.0 })
    };
    Kinetics {
        wheel_speeds: wheel_speeds(p, speed, yaw_rate),
        total_time: if in_place { turn.abs() / yaw_rate.abs() } else { dist.abs() / p.speed_m_s },
        direction: if in_place { 1.0 } else { dist.signum() },
    }
}

/// Each wheel's speed about the instantaneous centre for a reference `speed` (m/s) and
/// `yaw_rate` (rad/s): its body-frame velocity (speed − ω·y_w, ω·x_w) along its rolling
/// direction; left front, middle, rear, then right.
fn wheel_speeds(p: &crate::RoverParams, speed: f64, yaw_rate: f64) -> [f64; 6] {
    let (half, a) = (p.track_m / 2.0, p.axle_x_m);
    let mut w = [0.0; 6];
    for (k, y) in [half, -half].into_iter().enumerate() {
        for (i, x) in [a.front, a.middle, a.rear].into_iter().enumerate() {
            w[3 * k + i] = (speed - yaw_rate * y).hypot(yaw_rate * (x - a.middle));
        }
    }
    w
}

/// Where a drive of `dist` (m) along a circle of `radius` (m, infinite straight), or a
/// turn in place by `turn` (rad) when `dist` is 0, puts the reference point a fraction
/// `f` of the way from `start`.
fn place_along(start: &RoverState, dist: f64, radius: f64, turn: f64, f: f64) -> Place {
    if dist == 0.0 {
        Place { x: start.x, y: start.y, heading: start.heading - turn * f }
    } else if radius.is_finite() {
        // Along a circle: heading changes by s/R (left positive = azimuth down).
        let s = dist * f;
        let dpsi = s / radius;
        let (fx, fy) = (start.heading.sin(), start.heading.cos());
        let (lx, ly) = (-fy, fx);
        let (along, side) = (radius * dpsi.sin(), radius * (1.0 - dpsi.cos()));
        Place {
            x: start.x + fx * along + lx * side,
            y: start.y + fy * along + ly * side,
            heading: start.heading - dpsi,
        }
    } else {
        let s = dist * f;
        Place { x: start.x + start.heading.sin() * s, y: start.y + start.heading.cos() * s, heading: start.heading }
    }
}

/// A module stopped by `failure` after `progress` of it, in `state`.
fn stopped(failure: MotionFailure, progress: f64, state: RoverState) -> Stopped {
    Stopped { failure, progress, state: Box::new(state) }
}

/// A sample on the ground that a grasp can pick up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleSite {
    /// The caller's id for it.
    pub id: usize,
    /// Position on the map, m.
    pub x: f64,
    /// Position on the map, m.
    pub y: f64,
    /// Mass, kg.
    pub mass_kg: f64,
}

/// The gripper's length below the wrist, m \[A\]: a grasp puts the tool this far above
/// the ground at the sample.
pub const GRIPPER_M: f64 = 0.05;

/// How far a sample may be from the reference point for "turn to sample" to turn
/// toward it, m \[A\] (the arm reaches about 0.7 m ahead).
pub const SAMPLE_SEARCH_M: f64 = 1.0;

/// Why a module could not run.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum MotionFailure {
    /// A pose violated a physical limit.
    Violation(Violation),
    /// The arm cannot reach the new tool position.
    ArmReach,
    /// No sample within the arm's reach, or the gripper is already holding one.
    NoSample,
    /// "Turn to sample" with no sample near, or "turn from sample" with no turn to undo.
    NothingToTurnTo,
    /// Release with an empty gripper.
    NotHolding,
    /// The battery would drop below its usable window.
    Battery,
    /// A pose's stability margin S fell below [`Motion::stability_floor`].
    BelowFloor(f64),
}

impl std::fmt::Display for MotionFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MotionFailure::Violation(v) => v.fmt(f),
            MotionFailure::ArmReach => f.write_str("the arm cannot reach there"),
            MotionFailure::NoSample => f.write_str("no sample within the arm's reach, or already holding one"),
            MotionFailure::NothingToTurnTo => f.write_str("no sample to turn to, or no turn to undo"),
            MotionFailure::NotHolding => f.write_str("release with an empty gripper"),
            MotionFailure::Battery => f.write_str("the battery would drop below its usable window"),
            MotionFailure::BelowFloor(s) => write!(f, "stability margin {:.0} % below the floor", 100.0 * s),
        }
    }
}

/// A module that stopped: the failure, the fraction of the module done and the state
/// at the last admissible pose.
#[derive(Debug, Clone, PartialEq)]
pub struct Stopped {
    /// Why.
    pub failure: MotionFailure,
    /// Fraction of the module completed, 0..1.
    pub progress: f64,
    /// The state at the last admissible pose.
    pub state: Box<RoverState>,
}

/// Runs modules for one rover on one terrain.
#[derive(Debug, Clone)]
pub struct Motion<'e> {
    /// The evaluator.
    pub evaluator: &'e Evaluator,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Sample spacing, m: of the reference point's travel on drives and arcs, of the
    /// farthest wheel's on point turns. The finest the poses are ever sampled.
    pub spacing_m: f64,
    /// Widest stride between evaluated poses, in `spacing_m` steps, taken where the pose
    /// changes smoothly ([`Signature::change`] at most 1); 1 samples every step.
    pub coarse_steps: usize,
    /// Smallest admissible stability margin S (0..1): a pose below it stops the module,
    /// in the order its poses are reached. 0 stops only at tip-over.
    pub stability_floor: f64,
}

/// What must change little between two poses for the motion between them to be taken
/// as smooth: each wheel's contact angle (a wheel meeting an edge or a wall turns it),
/// body pitch and roll, the stability margin, the friction used and the torque load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Signature {
    /// Contact angles γ, rad, left front..right rear.
    pub gamma: [f64; 6],
    /// Body pitch and roll, rad.
    pub attitude: (f64, f64),
    /// Stability margin S, friction used, torque over its limit.
    pub margins: [f64; 3],
}

impl Signature {
    /// The signature of an evaluation (`torque_max_nm` the wheel torque limit).
    pub fn of(eval: &Evaluation, torque_max_nm: f64) -> Signature {
        let (l, r) = (eval.pose.left.gamma, eval.pose.right.gamma);
        Signature {
            gamma: [l[0], l[1], l[2], r[0], r[1], r[2]],
            attitude: (eval.pose.pitch, eval.pose.roll),
            margins: [eval.stability, eval.friction_used, eval.saturation(torque_max_nm)],
        }
    }

    /// How far apart two signatures are, as the largest of the changes over their
    /// allowances: 5° per contact angle, 1° of pitch or roll, 0.05 of each margin. At
    /// most 1 is smooth.
    pub fn change(&self, other: &Signature) -> f64 {
        let (deg5, deg1) = (5f64.to_radians(), 1f64.to_radians());
        let gamma = self.gamma.iter().zip(&other.gamma).map(|(a, b)| (a - b).abs() / deg5);
        let attitude = [self.attitude.0 - other.attitude.0, self.attitude.1 - other.attitude.1].map(|d| d.abs() / deg1);
        let margins = self.margins.iter().zip(&other.margins).map(|(a, b)| (a - b).abs() / 0.05);
        gamma.chain(attitude).chain(margins).fold(0.0, f64::max)
    }
}

impl<'e> Motion<'e> {
    /// Modules on `evaluator`'s rover with friction `mu`, sampled every centimetre where
    /// the pose changes and every 4 cm where it changes smoothly.
    pub fn new(evaluator: &'e Evaluator, mu: f64) -> Motion<'e> {
        Motion { evaluator, mu, spacing_m: 0.01, coarse_steps: 4, stability_floor: 0.0 }
    }

    /// One pose of a module: the forces and stability at `at` with `arm` under `cond`,
    /// re-using `known` if it was solved there (an arm move or a module's start does not
    /// move the wheels), and the stability floor applied.
    fn pose_at(
        &self,
        ground: &impl Ground,
        at: Place,
        arm: &ArmState,
        cond: &Conditions,
        known: Option<&Pose>,
    ) -> Result<Evaluation, MotionFailure> {
        let eval = match known {
            Some(pose) if pose.solved_at() == (at.x, at.y, at.heading) => {
                self.evaluator.evaluate_pose(ground, pose, arm, cond)
            }
            _ => self.evaluator.evaluate(ground, at, arm, cond, known),
        }
        .map_err(|v| match v {
            // Stability is found before the forces: a pose under the floor fails on it.
            Violation::Forces { stability, .. } if stability < self.stability_floor => {
                MotionFailure::BelowFloor(stability)
            }
            v => MotionFailure::Violation(v),
        })?;
        if eval.stability < self.stability_floor {
            return Err(MotionFailure::BelowFloor(eval.stability));
        }
        Ok(eval)
    }

    /// Evaluates the state where it stands (holding still).
    pub fn check(&self, ground: &impl Ground, state: &RoverState) -> Result<Evaluation, Violation> {
        let cond = Conditions { mu: self.mu, direction: 0.0 };
        self.evaluator.evaluate(ground, state.place(), &state.arm, &cond, state.pose.as_ref())
    }

    /// Runs `module` from `state`; `samples` are the samples still on the ground.
    ///
    /// A module with nothing to act on — a grasp with no sample in reach or a full
    /// gripper, a release with an empty one, an arm move out of reach, a turn to (or
    /// from) a sample with none to turn to — stops with that reason and changes
    /// nothing; what it costs all the same is [`Motion::idle`].
    pub fn run(
        &self,
        ground: &impl Ground,
        state: &RoverState,
        module: Module,
        samples: &[SampleSite],
    ) -> Result<ModuleRun, Stopped> {
        let p = self.evaluator.params();
        let act = &p.activities;
        let mut step = ModuleRun {
            state: *state,
            duration_s: 0.0,
            energy: Energy::default(),
            min_stability: None,
            max_friction: 0.0,
            max_friction_share: 0.0,
            max_saturation: 0.0,
            grasped: None,
        };
        if let Some((dist, radius, turn)) = module.path() {
            // A turn to a sample is a stance for the arm, not a change of route: the
            // rover turns back to its route heading before it drives on.
            let mut from = *state;
            if state.sample_turn != 0.0 {
                self.drive(ground, state, 0.0, 0.0, -state.sample_turn, &mut step)?;
                from = RoverState { sample_turn: 0.0, ..step.state };
                step.state = from;
            }
            self.drive(ground, &from, dist, radius, turn, &mut step)?;
        } else {
            self.stay(ground, state, module, samples, &mut step)?;
        }
        // Video and an open tray draw power for as long as the module lasts.
        if step.state.video_on && !matches!(module, Module::VideoStart | Module::VideoEnd) {
            step.energy.payload_wh += act.video_w * step.duration_s / 3600.0;
        }
        let battery = &p.battery;
        let floor = battery.capacity_wh * (1.0 - battery.usable_fraction);
        let after = (state.battery_wh - step.energy.net_wh()).min(battery.capacity_wh);
        if after < floor {
            return Err(stopped(MotionFailure::Battery, 1.0, *state));
        }
        step.state.battery_wh = after;
        Ok(step)
    }

    /// Runs a module that does not drive: arm moves, turns to and from a sample, grasps
    /// and releases, the tray, video, sensors, communication, sleep, recharge.
    fn stay(
        &self,
        ground: &impl Ground,
        state: &RoverState,
        module: Module,
        samples: &[SampleSite],
        step: &mut ModuleRun,
    ) -> Result<(), Stopped> {
        let p = self.evaluator.params();
        let act = &p.activities;
        match module {
            Module::ArmForward
            | Module::ArmBack
            | Module::ArmLeft
            | Module::ArmRight
            | Module::ArmDown
            | Module::ArmUp => {
                let d = 0.02;
                let delta = match module {
                    Module::ArmForward => [d, 0.0, 0.0],
                    Module::ArmBack => [-d, 0.0, 0.0],
                    Module::ArmLeft => [0.0, d, 0.0],
                    Module::ArmRight => [0.0, -d, 0.0],
                    Module::ArmDown => [0.0, 0.0, -d],
                    _ => [0.0, 0.0, d],
                };
                let from = state.arm;
                let path = |f: f64| from.moved([delta[0] * f, delta[1] * f, delta[2] * f], p);
                self.move_arm(ground, state, path, step)?;
                step.timed(p, d / p.arm.tool_speed_m_s, 0.0);
            }
            Module::TurnToSample | Module::TurnFromSample => {
                let turn = if module == Module::TurnFromSample {
                    -state.sample_turn
                } else {
                    self.turn_toward_sample(state, samples)
                };
                if turn == 0.0 {
                    return Err(stopped(MotionFailure::NothingToTurnTo, 0.0, *state));
                }
                self.drive(ground, state, 0.0, 0.0, turn, step)?;
                step.state.sample_turn = if module == Module::TurnFromSample { 0.0 } else { state.sample_turn + turn };
            }
            Module::Grasp => self.grasp(ground, state, samples, step)?,
            Module::Release => {
                if !(state.arm.payload_kg > 0.0) {
                    return Err(stopped(MotionFailure::NotHolding, 0.0, *state));
                }
                step.state.arm.payload_kg = 0.0;
                self.settle(ground, step, *state)?;
                step.timed(p, act.grasp_s, act.grasp_w);
            }
            Module::TrayDeploy | Module::TrayRetract => {
                step.state.tray_deployed = module == Module::TrayDeploy;
                step.timed(p, act.tray_s, act.tray_w);
            }
            Module::VideoStart | Module::VideoEnd => {
                step.state.video_on = module == Module::VideoStart;
                step.timed(p, act.video_s, act.video_w);
            }
            Module::SweepSensors => step.timed(p, act.sweep_s, act.sweep_w),
            Module::Communicate => step.timed(p, act.communicate_s, act.communicate_w),
            Module::Sleep => {
                step.duration_s += act.sleep_s;
                step.energy.hotel_wh += act.sleep_w * act.sleep_s / 3600.0;
            }
            Module::Recharge => {
                step.timed(p, act.recharge_s, 0.0);
                let tilt = state.pose.map_or(1.0, |q| q.pitch.cos() * q.roll.cos());
                let watts = act.recharge_flux_w_m2 * p.solar.area_m2 * p.solar.efficiency * tilt.max(0.0);
                step.energy.solar_wh += watts * act.recharge_s / 3600.0;
            }
            _ => {}
        }
        Ok(())
    }

    /// A grasp: reach down to the nearest sample in reach and back, by inverse
    /// kinematics through the arm's workspace — the arm's CG and then the sample's shift
    /// the rover's along the way, and lifting the sample costs its work.
    fn grasp(
        &self,
        ground: &impl Ground,
        state: &RoverState,
        samples: &[SampleSite],
        step: &mut ModuleRun,
    ) -> Result<(), Stopped> {
        let p = self.evaluator.params();
        let act = &p.activities;
        if state.arm.payload_kg > 0.0 {
            return Err(stopped(MotionFailure::NoSample, 0.0, *state));
        }
        let Some((site, target)) = self.reachable_sample(ground, state, samples) else {
            return Err(stopped(MotionFailure::NoSample, 0.0, *state));
        };
        let (from, to) = (state.arm, ArmState { tool_m: target, ..state.arm });
        self.move_arm(ground, state, |f| from.toward(&to, f, p), step)?;
        let reached = step.state;
        step.state.arm.payload_kg = site.mass_kg;
        if step.state.arm.check(p).is_err() {
            return Err(stopped(MotionFailure::ArmReach, 0.5, reached));
        }
        self.settle(ground, step, reached)?;
        let holding = step.state;
        let back = ArmState { payload_kg: site.mass_kg, ..from };
        self.move_arm(ground, &holding, |f| holding.arm.toward(&back, f, p), step)?;
        step.grasped = Some(site.id);
        // Timed by the tool's straight-line distance at the tool speed.
        let t = from.tool_m;
        let travel = (target[0] - t[0]).hypot(target[1] - t[1]).hypot(target[2] - t[2]);
        step.timed(p, 2.0 * travel / p.arm.tool_speed_m_s, 0.0);
        step.timed(p, act.grasp_s, act.grasp_w);
        Ok(())
    }

    /// Drives the reference point `dist` (m, negative backward) along a circle of
    /// `radius` (m, positive left; infinite straight) or turns in place by `turn` (rad,
    /// positive left), sampling poses.
    fn drive(
        &self,
        ground: &impl Ground,
        start: &RoverState,
        dist: f64,
        radius: f64,
        turn: f64,
        step: &mut ModuleRun,
    ) -> Result<(), Stopped> {
        let p = self.evaluator.params();
        let kin = kinetics(p, dist, radius, turn);
        let total_time = kin.total_time;
        let cond = Conditions { mu: self.mu, direction: kin.direction };
        let n = kin.fine_steps(dist, self.spacing_m);
        let place_at = |f: f64| place_along(start, dist, radius, turn, f);
        let power = |eval: &Evaluation| kin.power(p, eval);
        let mut state = *start;
        // The start: the previous module left its pose here, so only the forces under
        // this module's conditions are new.
        let first = self
            .pose_at(ground, start.place(), &start.arm, &cond, start.pose.as_ref())
            .map_err(|failure| Stopped { failure, progress: 0.0, state: Box::new(state) })?;
        let record = |step: &mut ModuleRun, eval: &Evaluation| step.record(eval, p.wheel_torque_max_nm);
        record(step, &first);
        let mut last = Signature::of(&first, p.wheel_torque_max_nm);
        let mut prev_power = power(&first);
        let mut warm = first.pose;
        state.pose = Some(first.pose);
        // Poses on a grid of n fine steps; a stride of up to `coarse_steps` of them where
        // the pose changes smoothly, halved back to one wherever it does not (or where a
        // pose fails, so the failure is reported at the first failing fine sample).
        let coarse = self.coarse_steps.max(1);
        let (mut j, mut stride) = (0usize, coarse);
        while j < n {
            let next = (j + stride).min(n);
            let f = next as f64 / n as f64;
            let at = place_at(f);
            let eval = match self.pose_at(ground, at, &start.arm, &cond, Some(&warm)) {
                Ok(eval) => eval,
                Err(_) if next - j > 1 => {
                    stride = (next - j) / 2;
                    continue;
                }
                Err(failure) => return Err(Stopped { failure, progress: f, state: Box::new(state) }),
            };
            let sig = Signature::of(&eval, p.wheel_torque_max_nm);
            let change = last.change(&sig);
            if next - j > 1 && change > 1.0 {
                stride = (next - j) / 2;
                continue;
            }
            record(step, &eval);
            let (mech, copper) = power(&eval);
            let dt = total_time * (next - j) as f64 / n as f64;
            step.energy.mechanical_wh += 0.5 * (prev_power.0 + mech) * dt / 3600.0;
            step.energy.copper_wh += 0.5 * (prev_power.1 + copper) * dt / 3600.0;
            prev_power = (mech, copper);
            warm = eval.pose;
            last = sig;
            state = RoverState { x: at.x, y: at.y, heading: at.heading, pose: Some(eval.pose), ..state };
            // Like an integrator's step control: widen only after a step well within the
            // allowance, so rough ground is not probed (and refused) at every step.
            if change < 0.5 {
                stride = (2 * (next - j)).min(coarse);
            }
            j = next;
        }
        step.duration_s += total_time;
        step.energy.hotel_wh += p.hotel_power_w * total_time / 3600.0;
        step.state = RoverState { arm: step.state.arm, ..state };
        Ok(())
    }

    /// Moves the arm along `path` (the arm a fraction 0..1 of the way), checking reach
    /// and stability at intermediate positions (every quarter of a 2 cm move, every
    /// twentieth of a reach to the ground); the energy is the rise in potential energy
    /// over the joints' efficiency.
    fn move_arm(
        &self,
        ground: &impl Ground,
        start: &RoverState,
        path: impl Fn(f64) -> Result<ArmState, String>,
        step: &mut ModuleRun,
    ) -> Result<(), Stopped> {
        let p = self.evaluator.params();
        let cond = Conditions { mu: self.mu, direction: 0.0 };
        let end = path(1.0).map_err(|_| Stopped {
            failure: MotionFailure::ArmReach,
            progress: 0.0,
            state: Box::new(*start),
        })?;
        let t = (end.tool_m[0] - start.arm.tool_m[0])
            .hypot(end.tool_m[1] - start.arm.tool_m[1])
            .hypot(end.tool_m[2] - start.arm.tool_m[2]);
        // About every 5 mm of the tool's straight-line travel, at least 4.
        let parts = ((t / 0.005).ceil() as usize).clamp(4, 200);
        let mut state = *start;
        for j in 1..=parts {
            let f = j as f64 / parts as f64;
            let arm = path(f).map_err(|_| Stopped {
                failure: MotionFailure::ArmReach,
                progress: f,
                state: Box::new(state),
            })?;
            let eval = self
                .pose_at(ground, state.place(), &arm, &cond, state.pose.as_ref())
                .map_err(|failure| Stopped { failure, progress: f, state: Box::new(state) })?;
            step.record(&eval, p.wheel_torque_max_nm);
            state = RoverState { arm, pose: Some(eval.pose), ..state };
        }
        let lift = |arm: &ArmState| -> f64 {
            let cg = arm.arm_cg(p).map_or(0.0, |c| c.z);
            (p.arm.mass_kg * cg + arm.payload_kg * arm.tool_m[2]) * p.gravity_m_s2
        };
        let rise = lift(&state.arm) - lift(&start.arm);
        step.energy.mechanical_wh += rise.max(0.0) / p.arm.efficiency / 3600.0;
        step.state = state;
        Ok(())
    }

    /// Re-evaluates the pose after a change of load (grasp, release).
    fn settle(&self, ground: &impl Ground, step: &mut ModuleRun, before: RoverState) -> Result<(), Stopped> {
        let s = &step.state;
        let cond = Conditions { mu: self.mu, direction: 0.0 };
        let eval = self.pose_at(ground, s.place(), &s.arm, &cond, s.pose.as_ref()).map_err(|failure| Stopped {
            failure,
            progress: 0.0,
            state: Box::new(before),
        })?;
        step.record(&eval, self.evaluator.params().wheel_torque_max_nm);
        step.state.pose = Some(eval.pose);
        Ok(())
    }

    /// The pose `state` stands in: its last one, or solved where it stands.
    fn pose_of(&self, ground: &impl Ground, state: &RoverState) -> Option<Pose> {
        match state.pose {
            Some(q) => Some(q),
            None => self.evaluator.kinematics().solve(ground, state.x, state.y, state.heading, None).ok(),
        }
    }

    /// The tool's position on the map, from the body pose.
    pub fn tool_world(&self, ground: &impl Ground, state: &RoverState) -> Option<[f64; 3]> {
        let p = self.evaluator.params();
        let pose = self.pose_of(ground, state)?;
        let t = state.arm.tool_m;
        Some(pose.body_to_map([t[0] - p.rocker_pivot_m.x, t[1], t[2] - p.rocker_pivot_m.z]))
    }

    /// What a module with nothing to act on costs (see [`Motion::run`]): its time —
    /// an arm move's 2 cm at the tool speed, a grasp's or release's cycle of the gripper
    /// (with its power), a turn to or from a sample the time to sweep the turn's
    /// largest angle looking for one — and the hotel power over it. The state changes
    /// only by the battery drawn; a draw below the battery's usable window stops it.
    pub fn idle(&self, state: &RoverState, module: Module) -> Result<ModuleRun, Stopped> {
        let p = self.evaluator.params();
        let act = &p.activities;
        let (seconds, load_w) = match module {
            Module::ArmForward
            | Module::ArmBack
            | Module::ArmLeft
            | Module::ArmRight
            | Module::ArmDown
            | Module::ArmUp => (0.02 / p.arm.tool_speed_m_s, 0.0),
            Module::Grasp | Module::Release => (act.grasp_s, act.grasp_w),
            Module::TurnToSample | Module::TurnFromSample => (act.turn_to_sample_deg / p.turn_rate_deg_s, 0.0),
            _ => (0.0, 0.0),
        };
        let energy = Energy {
            hotel_wh: p.hotel_power_w * seconds / 3600.0,
            payload_wh: load_w * seconds / 3600.0 + if state.video_on { act.video_w * seconds / 3600.0 } else { 0.0 },
            ..Energy::default()
        };
        let mut after = *state;
        after.battery_wh -= energy.net_wh();
        if after.battery_wh < p.battery.capacity_wh * (1.0 - p.battery.usable_fraction) {
            return Err(Stopped { failure: MotionFailure::Battery, progress: 1.0, state: Box::new(*state) });
        }
        Ok(ModuleRun {
            state: after,
            duration_s: seconds,
            energy,
            min_stability: None,
            max_friction: 0.0,
            max_friction_share: 0.0,
            max_saturation: 0.0,
            grasped: None,
        })
    }

    /// The heading change (rad, positive left) toward the sample within
    /// [`SAMPLE_SEARCH_M`] of the reference point that needs the least turn, limited
    /// to the module's angle; 0 if there is none.
    fn turn_toward_sample(&self, state: &RoverState, samples: &[SampleSite]) -> f64 {
        let limit = self.evaluator.params().activities.turn_to_sample_deg.to_radians();
        let mut best: Option<f64> = None;
        for s in samples {
            let (dx, dy) = (s.x - state.x, s.y - state.y);
            if dx.hypot(dy) > SAMPLE_SEARCH_M || dx.hypot(dy) < 1e-9 {
                continue;
            }
            // Bearing clockwise from north; a left turn lowers the heading.
            let bearing = dx.atan2(dy);
            let ang = (state.heading - bearing + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            if best.is_none_or(|b: f64| ang.abs() < b.abs()) {
                best = Some(ang);
            }
        }
        best.map_or(0.0, |a| a.clamp(-limit, limit))
    }

    /// The sample nearest the arm's shoulder that the tool can reach (gripper
    /// [`GRIPPER_M`] above the ground at the sample, within the arm's workspace), and
    /// the tool position (body frame, m) that reaches it.
    fn reachable_sample(
        &self,
        ground: &impl Ground,
        state: &RoverState,
        samples: &[SampleSite],
    ) -> Option<(SampleSite, [f64; 3])> {
        let p = self.evaluator.params();
        let sh = p.arm.shoulder_m;
        let mut best: Option<(f64, SampleSite, [f64; 3])> = None;
        for s in samples {
            // Far beyond any arm: skip the pose work.
            if (s.x - state.x).hypot(s.y - state.y) > 2.0 * (p.arm.upper_link_m + p.arm.lower_link_m) + 1.0 {
                continue;
            }
            let Some(z) = ground.height(s.x, s.y) else { continue };
            let Some(tool) = self.body_point(ground, state, [s.x, s.y, z + GRIPPER_M]) else { continue };
            let arm = ArmState { tool_m: tool, payload_kg: s.mass_kg };
            if arm.check(p).is_err() {
                continue;
            }
            let d = (tool[0] - sh.x).hypot(tool[1] - sh.y).hypot(tool[2] - sh.z);
            if best.is_none_or(|b| d < b.0) {
                best = Some((d, *s, tool));
            }
        }
        best.map(|(_, s, t)| (s, t))
    }

    /// A map point (m) in the body frame of `state`'s pose (x forward, y left, z up
    /// from the ground under the middle axles): the inverse of [`Motion::tool_world`].
    pub fn body_point(&self, ground: &impl Ground, state: &RoverState, world: [f64; 3]) -> Option<[f64; 3]> {
        let p = self.evaluator.params();
        let pose = self.pose_of(ground, state)?;
        let [bx, ry, rz] = pose.map_to_body(world);
        Some([bx + p.rocker_pivot_m.x, ry, rz + p.rocker_pivot_m.z])
    }
}
