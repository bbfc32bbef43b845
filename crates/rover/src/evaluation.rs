//! One full quasi-static evaluation of the rover at a place: pose ([`crate::kinematics`]),
//! forces on both sides coupled through the body and differential
//! ([`crate::forces`]), and the force-angle stability margin
//! ([`crate::stability`]). This is what the action planner runs at every sampled pose
//! of every module; it does not allocate.
//!
//! Coupling the sides (reference §4.3): the body — everything but the wheels and links,
//! with the arm and any sample — hangs on the two rocker pivots. Its weight W splits
//! into vertical pivot loads by its roll balance (the lever rule of the CG's horizontal
//! projection on the pivot line), and the differential passes half the body's pitching
//! moment to each rocker. Each side's planar problem is then solved with its load and
//! couple at its rocker pivot. Lateral friction enters through the friction cone: a
//! wheel on ground sloping sideways by φ_i needs a lateral force N_i·tan φ_i, leaving
//! √(μ² − tan² φ_i)·N_i for traction.
//!
//! Stability is normalised per direction: each tip-over axis is classed front, rear,
//! left or right by its outward normal in the body frame and divided by the same
//! class's angle on flat ground with the arm stowed ([`Normalisation::PerAxis`]), or
//! the smallest angle by the smallest flat angle ([`Normalisation::Global`]).

use areo_terrain::Ground;
use nalgebra::Vector3;

use crate::arm::ArmState;
use crate::forces::{self, ForceFailure, Limits, SideContacts, SideForces};
use crate::kinematics::{Kinematics, KinematicsFailure, Pose, SidePose};
use crate::params::RoverParams;
use crate::stability::{ForceAngle, Normalisation, force_angle};

/// Where the rover stands: the anchor (midpoint of the middle wheels) at (x, y), m,
/// map frame, and the heading, rad clockwise from north.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Place {
    /// East, m.
    pub x: f64,
    /// North, m.
    pub y: f64,
    /// Heading, rad clockwise from north.
    pub heading: f64,
}

/// Conditions of one evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conditions {
    /// Wheel–ground friction coefficient μ.
    pub mu: f64,
    /// Direction of travel: +1 forward, −1 backward, 0 holding still (rolling
    /// resistance acts only when moving).
    pub direction: f64,
}

/// What stops the rover at a pose.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Violation {
    /// No pose: off the map, no loop closure, or a joint limit.
    Kinematics(KinematicsFailure),
    /// A side's forces are not admissible (0 = left, 1 = right).
    Forces {
        /// 0 left, 1 right.
        side: usize,
        /// Which limit.
        failure: ForceFailure,
        /// The pose's stability margin S, which is found before the forces (so a caller
        /// with a stability floor can tell which limit the pose passed first).
        stability: f64,
    },
    /// The centre of mass is outside the support polygon.
    TipOver,
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Violation::Kinematics(k) => write!(f, "kinematics: {k}"),
            Violation::Forces { side, failure, .. } => {
                write!(f, "{} side {failure}", if *side == 0 { "left" } else { "right" })
            }
            Violation::TipOver => f.write_str("tip-over: the centre of mass is outside the support polygon"),
        }
    }
}

/// The result of one evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluation {
    /// The pose.
    pub pose: Pose,
    /// Left and right side forces.
    pub sides: [SideForces; 2],
    /// Vertical loads on the left and right rocker pivots, N.
    pub pivot_loads_n: [f64; 2],
    /// Centre of mass, map frame, m.
    pub cg: [f64; 3],
    /// Total weight, N.
    pub weight_n: f64,
    /// Force-angle margins per tip-over axis.
    pub force_angle: ForceAngle,
    /// The normalised stability margin S (1 on flat ground with the arm stowed; 0 at
    /// tip-over).
    pub stability: f64,
    /// Largest friction coefficient any wheel uses (in-plane and lateral).
    pub friction_used: f64,
    /// The friction coefficient the forces were held to: the least of the motion's μ
    /// and the μ the ground sets under any wheel ([`Ground::friction`]).
    pub friction_available: f64,
}

impl Evaluation {
    /// The largest wheel torque over `torque_max_nm` (1 = a motor at its limit).
    pub fn saturation(&self, torque_max_nm: f64) -> f64 {
        self.sides.iter().flat_map(|s| s.torque_nm.iter()).map(|t| t.abs()).fold(0.0, f64::max)
            / torque_max_nm.max(1e-12)
    }

    /// Wheel torques, left front, middle, rear, right front, middle, rear, N·m.
    pub fn torques_nm(&self) -> [f64; 6] {
        let [l, r] = &self.sides;
        [l.torque_nm[0], l.torque_nm[1], l.torque_nm[2], r.torque_nm[0], r.torque_nm[1], r.torque_nm[2]]
    }

    /// Normal loads in the same order, N.
    pub fn normals_n(&self) -> [f64; 6] {
        let [l, r] = &self.sides;
        [l.normal_n[0], l.normal_n[1], l.normal_n[2], r.normal_n[0], r.normal_n[1], r.normal_n[2]]
    }
}

/// Flat-ground force angles per direction class (front, rear, left, right), rad.
#[derive(Debug, Clone, Copy, PartialEq)]
struct FlatReference {
    by_class: [f64; 4],
    smallest: f64,
}

/// Evaluates poses of one rover.
#[derive(Debug, Clone)]
pub struct Evaluator {
    params: RoverParams,
    kinematics: Kinematics,
    flat: FlatReference,
    /// The stowed arm's centre of mass, body frame, m.
    stowed_arm_cg: Vector3<f64>,
    /// How margins are normalised.
    pub normalisation: Normalisation,
}

/// The class of an axis from its outward normal (forward, left components).
fn class_of(forward: f64, left: f64) -> usize {
    if forward.abs() >= left.abs() {
        if forward > 0.0 { 0 } else { 1 }
    } else if left > 0.0 {
        2
    } else {
        3
    }
}

impl Evaluator {
    /// The evaluator for `params`.
    pub fn new(params: &RoverParams) -> Evaluator {
        let kinematics = Kinematics::new(params);
        let a = params.axle_x_m;
        let half = params.track_m / 2.0;
        let mut pts = [Vector3::zeros(); 6];
        for (k, y) in [half, -half].into_iter().enumerate() {
            for (i, x) in [a.front, a.middle, a.rear].into_iter().enumerate() {
                pts[3 * k + i] = Vector3::new(x, y, 0.0);
            }
        }
        let c = params.cg_m;
        let down = Vector3::new(0.0, 0.0, -1.0);
        let fa = force_angle(&pts, Vector3::from(c), down, Vector3::zeros());
        let mut by_class = [f64::INFINITY; 4];
        let mut smallest = f64::INFINITY;
        if let Some(fa) = fa {
            for (i, &ang) in fa.angles().iter().enumerate() {
                let o = fa.outward(i, down);
                let k = class_of(o.x, o.y);
                by_class[k] = by_class[k].min(ang);
                smallest = smallest.min(ang);
            }
        }
        // Validated parameters have a reachable stowed tool.
        let stowed_arm_cg = ArmState::stowed(params).arm_cg(params).unwrap_or_else(|_| Vector3::from(c));
        Evaluator {
            params: params.clone(),
            kinematics,
            flat: FlatReference { by_class, smallest },
            stowed_arm_cg,
            normalisation: Normalisation::PerAxis,
        }
    }

    /// The parameters.
    pub fn params(&self) -> &RoverParams {
        &self.params
    }

    /// The kinematic model.
    pub fn kinematics(&self) -> &Kinematics {
        &self.kinematics
    }

    /// Flat-ground force angles with the arm stowed: front, rear, left, right, rad.
    pub fn flat_angles(&self) -> [f64; 4] {
        self.flat.by_class
    }

    /// Evaluates the rover at `at`, arm state `arm`, under `cond`; `warm` is the
    /// previous pose of the same motion, if any.
    pub fn evaluate(
        &self,
        ground: &impl Ground,
        at: Place,
        arm: &ArmState,
        cond: &Conditions,
        warm: Option<&Pose>,
    ) -> Result<Evaluation, Violation> {
        let pose = self.kinematics.solve(ground, at.x, at.y, at.heading, warm).map_err(Violation::Kinematics)?;
        self.evaluate_pose(ground, &pose, arm, cond)
    }

    /// Forces and stability at a solved pose.
    pub fn evaluate_pose(
        &self,
        ground: &impl Ground,
        pose: &Pose,
        arm: &ArmState,
        cond: &Conditions,
    ) -> Result<Evaluation, Violation> {
        let p = &self.params;
        let (mass, cg_body) = arm
            .system_mass_cg_from(p, self.stowed_arm_cg)
            .map_err(|_| Violation::Kinematics(KinematicsFailure::JointLimit))?;
        let weight = mass * p.gravity_m_s2;
        // The CG on the map: the body frame turned by the pose's attitude about the body
        // reference (the rocker pivots' midpoint).
        let (fx, fy) = pose.forward();
        let rel = cg_body - Vector3::new(p.rocker_pivot_m.x, 0.0, p.rocker_pivot_m.z);
        let g = pose.body_to_map(rel.into());
        // Pivot loads by the lever rule along the (horizontal) pivot line.
        let [bl, br] = pose.pivots;
        let line = (bl[0] - br[0], bl[1] - br[1]);
        let len2 = line.0 * line.0 + line.1 * line.1;
        let lambda = ((g[0] - br[0]) * line.0 + (g[1] - br[1]) * line.1) / len2;
        let loads = [lambda * weight, (1.0 - lambda) * weight];
        // Pitching moment: W times the CG's horizontal lead over the pivot line.
        let len = len2.sqrt();
        let ahead = (line.1 / len, -line.0 / len);
        let lead = (g[0] - br[0]) * ahead.0 + (g[1] - br[1]) * ahead.1;
        let couple = -weight * lead / 2.0;
        // Stability over the six contacts.
        let mut pts = [Vector3::zeros(); 6];
        for (i, w) in pose.wheels.iter().enumerate() {
            pts[i] = Vector3::from(w.contact);
        }
        let down = Vector3::new(0.0, 0.0, -weight);
        let fa = force_angle(&pts, Vector3::from(g), down, Vector3::zeros()).ok_or(Violation::TipOver)?;
        let stability = self.normalised_stability(&fa, (fx, fy));
        if !(stability > 0.0) {
            return Err(Violation::TipOver);
        }
        let mut sides = [None; 2];
        let (mut friction_used, mut friction_available) = (0.0f64, f64::INFINITY);
        for (k, side) in [&pose.left, &pose.right].into_iter().enumerate() {
            let (f, worst_lateral, mu) =
                self.side_forces(ground, pose, k, side, (loads[k], couple), cond, stability)?;
            friction_used = friction_used.max(f.friction_used.hypot(worst_lateral));
            friction_available = friction_available.min(mu);
            sides[k] = Some(f);
        }
        let (Some(left), Some(right)) = (sides[0], sides[1]) else {
            return Err(Violation::Kinematics(KinematicsFailure::NoClosure));
        };
        Ok(Evaluation {
            pose: *pose,
            sides: [left, right],
            pivot_loads_n: loads,
            cg: g,
            weight_n: weight,
            force_angle: fa,
            stability,
            friction_used,
            friction_available,
        })
    }

    /// The force-angle stability margin `fa` normalised by flat ground's: per axis by
    /// the axis' class relative to the heading (`fx`, `fy`), or globally.
    fn normalised_stability(&self, fa: &ForceAngle, (fx, fy): (f64, f64)) -> f64 {
        let (lx, ly) = (-fy, fx);
        match self.normalisation {
            Normalisation::PerAxis => {
                let hull = fa.hull();
                fa.angles()
                    .iter()
                    .enumerate()
                    .map(|(i, &a)| {
                        // The axis' outward direction, up × (q − p) with gravity down the
                        // z axis; unnormalised, as the class only compares its components.
                        let (p, q) = (hull[i], hull[(i + 1) % hull.len()]);
                        let o = (p.y - q.y, q.x - p.x);
                        let class = class_of(o.0 * fx + o.1 * fy, o.0 * lx + o.1 * ly);
                        a / self.flat.by_class[class]
                    })
                    .fold(f64::INFINITY, f64::min)
            }
            Normalisation::Global => fa.critical().map_or(f64::NEG_INFINITY, |c| c.1) / self.flat.smallest,
        }
    }

    /// Side `k`'s force balance at `pose`, carrying `load` at its pivot and the body's
    /// pitching `couple`, within the friction cone the ground's lateral slope leaves:
    /// the forces, that worst lateral slope and the side's μ — the least the ground
    /// sets under its three wheels, the motion's where it sets none.
    #[allow(clippy::too_many_arguments)]
    fn side_forces(
        &self,
        ground: &impl Ground,
        pose: &Pose,
        k: usize,
        side: &SidePose,
        (load, couple): (f64, f64),
        cond: &Conditions,
        stability: f64,
    ) -> Result<(SideForces, f64, f64), Violation> {
        let p = &self.params;
        let (fx, fy) = pose.forward();
        let (lx, ly) = (-fy, fx);
        // Lateral ground slope at each contact, for the friction cone; the side's μ is
        // its slipperiest wheel's (one μ per side is what the force model holds to).
        let mut lateral = [0.0; 3];
        let mut mu = f64::INFINITY;
        for (i, l) in lateral.iter_mut().enumerate() {
            let c = pose.wheels[3 * k + i].contact;
            if let Some((_, slope)) = ground.height_slope(c[0], c[1], (lx, ly)) {
                *l = slope.abs();
            }
            mu = mu.min(ground.friction(c[0], c[1]).unwrap_or(cond.mu));
        }
        let worst_lateral = lateral.iter().copied().fold(0.0, f64::max);
        if worst_lateral >= mu {
            return Err(Violation::Forces { side: k, failure: ForceFailure::Slip, stability });
        }
        // The force balance knows the bogie-in-front chain: a bogie-behind rover's
        // side is solved as its mirror image (driving the other way, the couple's
        // nose at the other end) and its forces turned back.
        let mirror = self.kinematics.mirrored();
        let sign = if mirror { -1.0 } else { 1.0 };
        let chain = if mirror { side.mirrored() } else { *side };
        let contacts = SideContacts {
            axles: chain.axles,
            gamma_sin_cos: chain.gamma_sin_cos(),
            bogie_pivot: chain.bogie_pivot,
            rocker_pivot: chain.rocker_pivot,
            load_n: load,
            couple_nm: sign * couple,
            wheel_radius_m: p.wheel_radius_m,
        };
        let limits = Limits {
            mu: (mu * mu - worst_lateral * worst_lateral).sqrt(),
            torque_max_nm: p.wheel_torque_max_nm,
            n_min: 0.0,
            rolling_resistance: p.rolling_resistance,
            direction: sign * cond.direction,
        };
        let f =
            forces::solve(&contacts, &limits).map_err(|failure| Violation::Forces { side: k, failure, stability })?;
        let f = if mirror { f.mirrored() } else { f };
        Ok((f, worst_lateral, mu))
    }
}
