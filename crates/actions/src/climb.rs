//! A straight climb examined pose by pose: the stability margin, pitch and front-wheel
//! load along a straight drive from the task's start, with the arm stowed and with the
//! arm reached as far forward as 1001 takes it. It answers "would moving the arm
//! forward keep this rover from tipping backward here, and what stops it first?"
//! without the GA: the climb stops at the first pose with no solution (a joint limit,
//! the map's edge) or where the stowed rover tips over.

use areo_rover::arm::ArmState;
use areo_rover::evaluation::{Conditions, Evaluation, Evaluator, Place, Violation};
use areo_rover::kinematics::Pose;
use areo_rover::motion::MotionFailure;
use areo_terrain::Ground;
use areo_terrain::analytic::Wall;
use serde::Serialize;

use crate::executor::ExecFailure;

/// One arm configuration at one pose of the climb.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ArmCase {
    /// Stability margin S (1 on flat ground with the arm stowed, 0 at tip-over).
    pub margin: f64,
    /// The front wheels' share of the rover's weight on the wheels (0: about to rotate
    /// back over the rear wheels).
    pub front_load_fraction: f64,
    /// The largest |T|/N any wheel needs to hold the pose (the least μ that holds it).
    pub friction_needed: f64,
    /// What the pose violates under the climb's μ, if anything (`slip`,
    /// `loss_of_contact`, `saturation`, `tip_over`).
    pub violation: Option<&'static str>,
}

/// One pose of the climb.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ClimbPose {
    /// Distance of the reference point from the start, m.
    pub distance_m: f64,
    /// Body pitch, degrees (nose up positive).
    pub pitch_deg: f64,
    /// The arm stowed.
    pub stowed: ArmCase,
    /// The arm reached forward.
    pub forward: ArmCase,
}

/// The margins along a straight climb, and what ended it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClimbProfile {
    /// The arm's tool position reached forward (body frame, m).
    pub forward_tool_m: [f64; 3],
    /// Every pose, in order.
    pub poses: Vec<ClimbPose>,
    /// Why the climb ended before its length, if it did: `kinematics` (a joint limit or
    /// the map's edge: no pose) or `tip_over` (the stowed rover's margin reached 0).
    pub stop: Option<&'static str>,
    /// The distance at which it ended, m.
    pub stop_distance_m: f64,
}

impl ClimbProfile {
    /// The least of `f` over the poses (those where it is a number; +∞ with none):
    /// the least margin, or with `f` negated the largest pitch.
    pub fn least(&self, f: impl Fn(&ClimbPose) -> f64) -> f64 {
        self.poses.iter().map(f).filter(|v| v.is_finite()).fold(f64::INFINITY, f64::min)
    }
}

/// The tool position that repeated 2 cm moves forward (module 1001) reach from the
/// stowed arm of `evaluator`'s rover.
pub fn arm_reached_forward(evaluator: &Evaluator) -> ArmState {
    let p = evaluator.params();
    let mut arm = ArmState::stowed(p);
    while let Ok(next) = arm.moved([0.02, 0.0, 0.0], p) {
        arm = next;
    }
    arm
}

fn case(eval: Result<Evaluation, Violation>) -> Option<ArmCase> {
    // The executor's names for the limits, so climb.csv and the plans agree.
    let kind = |v: &Violation| ExecFailure::Motion(MotionFailure::Violation(*v)).kind();
    match eval {
        Ok(e) => {
            let n = e.normals_n();
            let total: f64 = n.iter().sum();
            Some(ArmCase {
                margin: e.stability,
                front_load_fraction: if total > 0.0 { (n[0] + n[3]) / total } else { 0.0 },
                friction_needed: e.friction_used,
                violation: None,
            })
        }
        Err(v @ Violation::Forces { stability, .. }) => Some(ArmCase {
            margin: stability,
            front_load_fraction: f64::NAN,
            friction_needed: f64::NAN,
            violation: Some(kind(&v)),
        }),
        Err(Violation::TipOver) => Some(ArmCase {
            margin: 0.0,
            front_load_fraction: f64::NAN,
            friction_needed: f64::NAN,
            violation: Some("tip_over"),
        }),
        Err(Violation::Kinematics(_)) => None,
    }
}

/// Drives the reference point straight from `start` (x m, y m, heading ° clockwise
/// from north) for `length_m`, a pose every `step_m`, holding still at each under
/// friction `mu`, and evaluates it with the arm stowed and reached forward.
pub fn climb_margins(
    ground: &impl Ground,
    evaluator: &Evaluator,
    start: (f64, f64, f64),
    mu: f64,
    step_m: f64,
    length_m: f64,
) -> ClimbProfile {
    let stowed = ArmState::stowed(evaluator.params());
    let forward = arm_reached_forward(evaluator);
    let heading = start.2.to_radians();
    let cond = Conditions { mu, direction: 0.0 };
    let n = (length_m / step_m).round() as usize;
    let mut profile =
        ClimbProfile { forward_tool_m: forward.tool_m, poses: Vec::new(), stop: None, stop_distance_m: 0.0 };
    let mut warm = None;
    for k in 0..=n {
        let d = k as f64 * step_m;
        profile.stop_distance_m = d;
        let at = Place { x: start.0 + heading.sin() * d, y: start.1 + heading.cos() * d, heading };
        let Ok(pose) = evaluator.kinematics().solve(ground, at.x, at.y, at.heading, warm.as_ref()) else {
            profile.stop = Some("kinematics");
            return profile;
        };
        warm = Some(pose);
        let (Some(s), Some(f)) = (
            case(evaluator.evaluate_pose(ground, &pose, &stowed, &cond)),
            case(evaluator.evaluate_pose(ground, &pose, &forward, &cond)),
        ) else {
            profile.stop = Some("kinematics");
            return profile;
        };
        profile.poses.push(ClimbPose { distance_m: d, pitch_deg: pose.pitch.to_degrees(), stowed: s, forward: f });
        if s.violation == Some("tip_over") {
            profile.stop = Some("tip_over");
            return profile;
        }
    }
    profile
}

/// One value of an assumed parameter and the straight climb the rover makes with it
/// (or why the parameters are refused).
#[derive(Debug, Clone)]
pub struct SensitivityRow {
    /// The parameter varied.
    pub parameter: areo_rover::Assumed,
    /// Its value.
    pub value: f64,
    /// The climb with it, or the validation error.
    pub profile: Result<ClimbProfile, String>,
}

/// The straight climb of [`climb_margins`] repeated with `parameter` set to each of
/// `values` on `base`'s rover: how what stops the climb, and the margins with the arm
/// stowed and forward, move with a parameter no source gives.
#[allow(clippy::too_many_arguments)]
pub fn climb_sensitivity(
    ground: &impl Ground,
    base: &areo_rover::RoverParams,
    start: (f64, f64, f64),
    mu: f64,
    step_m: f64,
    length_m: f64,
    parameter: areo_rover::Assumed,
    values: &[f64],
) -> Vec<SensitivityRow> {
    values
        .iter()
        .map(|&value| {
            let profile = base
                .with_assumed(parameter, value)
                .map_err(|e| e.to_string())
                .map(|params| climb_margins(ground, &Evaluator::new(&params), start, mu, step_m, length_m));
            SensitivityRow { parameter, value, profile }
        })
        .collect()
}

/// A step climbed pose by pose: the rover driven forward from its front wheels
/// against the step until every wheel stands on top, holding still at each pose.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepClimb {
    /// Distance between poses, m.
    pub step_m: f64,
    /// Poses evaluated.
    pub poses: usize,
    /// How far the reference point gets at the checked μ (to the first pose that fails
    /// there), m.
    pub distance_m: f64,
    /// Every wheel on top of the step at the end.
    pub over: bool,
    /// Why the climb ended before every wheel was over: `kinematics` (no pose: a joint
    /// limit), or the first limit violated at the checked μ (`slip`, `loss_of_contact`,
    /// `saturation`, `tip_over`).
    pub stop: Option<String>,
    /// The smallest μ (to 1e-3) that holds every pose of the climb, if any μ ≤ 5 does.
    pub mu_needed: Option<f64>,
    /// Where that μ is needed: the reference point's distance from the start, m.
    pub mu_needed_at_m: f64,
    /// Which wheels touch the step's top there (e.g. "front", "front middle").
    pub wheels_on_top_there: String,
    /// The least stability margin over the poses that hold at the checked μ, % of flat
    /// ground.
    pub min_stability_pct: f64,
    /// The largest body pitch, degrees.
    pub max_pitch_deg: f64,
}

/// A step of height `h` (m) climbed pose by pose: from the front wheels against it,
/// heading east, a pose every centimetre until the rear wheels are a wheel radius past
/// the edge, each held still under friction `mu` (`direction` 1 counts rolling
/// resistance as when driving). `areo rover check --terrain step:H` reports it.
pub fn step_climb(ev: &Evaluator, arm: &ArmState, h: f64, mu: f64, direction: f64) -> StepClimb {
    let p = ev.params();
    let (a, r) = (p.axle_x_m, p.wheel_radius_m);
    let x_step = (a.front - a.middle) + r - 1e-6;
    let ground = Wall { x_step, low_m: 0.0, high_m: h };
    // The rear wheel's axle crosses the edge when the reference point is at
    // x_step − (rear − middle); a radius beyond, the wheel stands on top.
    let length = x_step - (a.rear - a.middle) + r;
    let step_m = 0.01;
    let n = (length / step_m).ceil() as usize;
    let mut climb = StepClimb {
        step_m,
        poses: 0,
        distance_m: 0.0,
        over: false,
        stop: None,
        mu_needed: Some(0.0),
        mu_needed_at_m: 0.0,
        wheels_on_top_there: String::new(),
        min_stability_pct: f64::INFINITY,
        max_pitch_deg: f64::NEG_INFINITY,
    };
    let mut warm: Option<Pose> = None;
    for k in 0..=n {
        let d = k as f64 * step_m;
        // Warm-started from the last pose (the solver falls back to cold by itself).
        let solved = ev.kinematics().solve(&ground, d, 0.0, std::f64::consts::FRAC_PI_2, warm.as_ref());
        let Ok(pose) = solved else {
            if climb.stop.is_none() {
                climb.distance_m = d;
            }
            climb.stop.get_or_insert_with(|| "kinematics".into());
            climb.mu_needed = None;
            return climb;
        };
        warm = Some(pose);
        climb.poses += 1;
        if climb.stop.is_none() {
            // How far it gets at the checked μ: up to the first pose that fails there
            // (the poses beyond still count toward the μ the whole climb needs).
            climb.distance_m = d;
        }
        climb.max_pitch_deg = climb.max_pitch_deg.max(pose.pitch.to_degrees());
        let hold = |mu: f64| ev.evaluate_pose(&ground, &pose, arm, &Conditions { mu, direction });
        match hold(mu) {
            Ok(e) => climb.min_stability_pct = climb.min_stability_pct.min(100.0 * e.stability),
            Err(v) => {
                let kind = match v {
                    Violation::TipOver => "tip_over".to_string(),
                    Violation::Kinematics(_) => "kinematics".to_string(),
                    Violation::Forces { .. } => ExecFailure::Motion(MotionFailure::Violation(v)).kind().to_string(),
                };
                climb.stop.get_or_insert(kind);
            }
        }
        let least = least_mu(|mu| hold(mu).is_ok(), 1e-3);
        match (least, climb.mu_needed) {
            (None, _) => {
                climb.mu_needed = None;
                climb.stop.get_or_insert_with(|| "no μ ≤ 5 holds".into());
                return climb;
            }
            (Some(m), Some(worst)) if m > worst || k == 0 => {
                climb.mu_needed = Some(m);
                climb.mu_needed_at_m = d;
                // A wheel is up once its axle has passed the edge.
                let top = |i: usize| pose.wheels[i].axle[0] >= x_step;
                let names = ["front", "middle", "rear"];
                climb.wheels_on_top_there = (0..3).filter(|&i| top(i)).map(|i| names[i]).collect::<Vec<_>>().join(" ");
            }
            _ => {}
        }
    }
    climb.over = climb.stop.is_none();
    climb
}

/// The least friction coefficient (to `tolerance`) at which `holds` is true: 0 if it
/// holds without friction, `None` if no μ ≤ 5 does. Holding is monotone in μ (a larger
/// μ only widens every friction cone), so a bisection finds it.
pub fn least_mu(holds: impl Fn(f64) -> bool, tolerance: f64) -> Option<f64> {
    if holds(0.0) {
        return Some(0.0);
    }
    if !holds(5.0) {
        return None;
    }
    let (mut lo, mut hi) = (0.0, 5.0);
    while hi - lo > tolerance {
        let mid = 0.5 * (lo + hi);
        if holds(mid) { hi = mid } else { lo = mid }
    }
    Some(hi)
}
