//! Rocker-bogie kinematics on terrain (Farritor et al. 1998, §3; reference §3).
//!
//! Two solvers of the same problem, given the heading and a reference point:
//!
//! - [`Kinematics::solve`], the paper's **planar decomposition**: each side is a planar
//!   three-wheel problem in its own wheel plane; the body pitch is the mean of the two
//!   rocker pitches (the differential) and the roll follows from the two rocker-pivot
//!   heights. The **footprint correction** then moves each side's wheel plane to
//!   ±(w/2)·cos ψ and projects in-plane heights by cos ψ (the paper's cos ψ factor),
//!   and the sides are solved again until the roll settles (2–3 passes; one when warm
//!   started from the previous pose of a motion).
//! - [`newton_pose`], a damped Newton solve of the full 3-D chain (body, differential,
//!   both rockers and bogies, 8 unknowns, 6 contacts + 2 anchor equations), the
//!   cross-check.
//!
//! Wheels touch the **dilated terrain**: the admissible axle height at s along the
//! wheel's line of travel is A(s) = max over |u| ≤ r of h(s + u) + √(r² − u²), so a
//! wheel against a wall rides up its face instead of sinking into it. A(s) has vertical
//! segments at walls taller than r; the loop closures are solved with a bracketing,
//! safeguarded Newton iteration that lands on such a segment when the closure circle
//! crosses it (the axle is then on the wall face, contact normal horizontal).
//!
//! A bogie-behind rover ([`Layout::BogieRear`], MER) is the same chain turned end for
//! end: [`Kinematics::solve`] solves it heading the other way with left and right
//! swapped and hands back the pose in the rover's own frame ([`SidePose::mirrored`]).
//!
//! Frames: map x east, y north, z up (m); heading is an azimuth clockwise from north.
//! In each side plane, s runs forward from the reference point and z up.

use areo_terrain::Ground;
use nalgebra::{Matrix3, Vector3};

use crate::math::Attitude;
use crate::params::{Axles, Layout, RoverParams};

/// Samples across a wheel's diameter for the dilated terrain: 25 samples, 8 mm apart
/// for a 20 cm wheel.
const WHEEL_SAMPLES: usize = 24;

/// Which point the (x, y) input names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Anchor {
    /// The midpoint between the two middle axles (what the planners move).
    #[default]
    MiddleMidpoint,
    /// The middle-right axle, as in the paper.
    MiddleRight,
    /// The middle-left axle.
    MiddleLeft,
}

impl Anchor {
    /// Each side's wheel plane's offset to the left of the anchor, m, for a rover of
    /// `track` rolled to cos ψ = `c`.
    fn offsets(self, track: f64, c: f64) -> (f64, f64) {
        match self {
            Anchor::MiddleMidpoint => (0.5 * track * c, -0.5 * track * c),
            Anchor::MiddleRight => (track * c, 0.0),
            Anchor::MiddleLeft => (0.0, -track * c),
        }
    }

    /// The sides' shifts along the heading that put both rocker pivots (at `pl`, `pr`
    /// along their lines) on the body's lateral axis with the anchor fixed.
    fn shifts(self, pl: f64, pr: f64) -> (f64, f64) {
        match self {
            Anchor::MiddleMidpoint => (0.5 * (pr - pl), 0.5 * (pl - pr)),
            Anchor::MiddleRight => (pr - pl, 0.0),
            Anchor::MiddleLeft => (0.0, pl - pr),
        }
    }

    /// The shifts moved by (`dl`, `dr`), the anchored side's staying at zero.
    fn stepped(self, shift: (f64, f64), (dl, dr): (f64, f64)) -> (f64, f64) {
        match self {
            Anchor::MiddleMidpoint => (shift.0 + dl, shift.1 + dr),
            Anchor::MiddleRight => (shift.0 + dl, 0.0),
            Anchor::MiddleLeft => (0.0, shift.1 + dr),
        }
    }

    /// The same point seen from the rover turned end for end (left and right swap).
    fn mirrored(self) -> Anchor {
        match self {
            Anchor::MiddleMidpoint => Anchor::MiddleMidpoint,
            Anchor::MiddleRight => Anchor::MiddleLeft,
            Anchor::MiddleLeft => Anchor::MiddleRight,
        }
    }
}

/// One side's planar solution in its wheel plane (s forward from the reference point,
/// z up, m; z is the true height).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SidePose {
    /// Front, middle and rear axle centres.
    pub axles: [(f64, f64); 3],
    /// Contact points under the front, middle and rear wheels.
    pub contacts: [(f64, f64); 3],
    /// Contact angles γ (terrain rising ahead positive; π/2 is a wall ahead), rad.
    pub gamma: [f64; 3],
    /// Bogie pivot.
    pub bogie_pivot: (f64, f64),
    /// Rocker (body) pivot.
    pub rocker_pivot: (f64, f64),
    /// Rocker pitch relative to its flat-ground orientation, rad (nose up positive).
    pub rocker_pitch: f64,
    /// Bogie pitch relative to the rocker's, rad (the bogie's forward end up positive:
    /// its front wheel on the paper's rover, its middle wheel on a bogie-behind one).
    pub bogie_angle: f64,
    /// Angle of bogie pivot → rocker pivot above the rearward horizontal, rad (the
    /// paper's α1 on the right side, α3 on the left).
    pub rocker_alpha: f64,
    /// Angle of front axle → bogie pivot above the rearward horizontal, rad (α2 right,
    /// α4 left).
    pub bogie_alpha: f64,
    /// Where s = 0 is on this side's contact line, map frame, m.
    pub origin: (f64, f64),
    /// How far this side's middle axle sits ahead of the anchor, m (the differential
    /// keeps both rocker pivots on one lateral axis).
    pub shift: f64,
    /// Height where the tilted wheel plane meets the contact line (the ground under
    /// s = 0), m.
    pub plane_z: f64,
    /// The rim sample touching the ground, per axle (seeds warm starts).
    pins: [usize; 3],
    /// (sin γ, cos γ) per wheel, found with γ (the pose's normals need them).
    gamma_sc: [(f64, f64); 3],
}

impl SidePose {
    /// (sin γ, cos γ) of the contact angles, front to rear.
    pub fn gamma_sin_cos(&self) -> [(f64, f64); 3] {
        self.gamma_sc
    }

    /// The same side seen from the rover turned end for end: s runs the other way, the
    /// front and rear wheels swap, angles measured from ahead change sign. Applying it
    /// twice gives the side back exactly.
    pub fn mirrored(&self) -> SidePose {
        let flip = |p: (f64, f64)| (-p.0, p.1);
        let turn3 = |a: [(f64, f64); 3]| [flip(a[2]), flip(a[1]), flip(a[0])];
        SidePose {
            axles: turn3(self.axles),
            contacts: turn3(self.contacts),
            gamma: [-self.gamma[2], -self.gamma[1], -self.gamma[0]],
            bogie_pivot: flip(self.bogie_pivot),
            rocker_pivot: flip(self.rocker_pivot),
            rocker_pitch: -self.rocker_pitch,
            bogie_angle: -self.bogie_angle,
            // The paper's angles belong to its bogie-in-front chain; they stay as the
            // mirror image measures them.
            rocker_alpha: self.rocker_alpha,
            bogie_alpha: self.bogie_alpha,
            origin: self.origin,
            shift: -self.shift,
            plane_z: self.plane_z,
            // Rim samples run from −r to +r along s: sample k becomes sample N − k.
            pins: [WHEEL_SAMPLES - self.pins[2], WHEEL_SAMPLES - self.pins[1], WHEEL_SAMPLES - self.pins[0]],
            gamma_sc: [2, 1, 0].map(|i| (-self.gamma_sc[i].0, self.gamma_sc[i].1)),
        }
    }
}

/// One wheel on the ground, map frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wheel {
    /// Axle centre, m.
    pub axle: [f64; 3],
    /// Contact point, m.
    pub contact: [f64; 3],
    /// Contact normal (unit, in the wheel plane), pointing from the ground to the axle.
    pub normal: [f64; 3],
}

/// The rover's pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Left side (body y = +w/2).
    pub left: SidePose,
    /// Right side (body y = −w/2).
    pub right: SidePose,
    /// Heading (azimuth clockwise from north), rad.
    pub heading: f64,
    /// Body pitch: the elevation of the body x axis, rad (nose up positive); the body
    /// axis is the mean of the rocker pitches (the differential) in the wheel planes.
    pub pitch: f64,
    /// Body roll, sin ψ = (z_B,left − z_B,right)/w, rad (left side up positive).
    pub roll: f64,
    /// Body reference: the midpoint of the two rocker pivots, map frame, m.
    pub body: [f64; 3],
    /// Left and right rocker pivots, map frame, m.
    pub pivots: [[f64; 3]; 2],
    /// The paper's α1, α2 (right rocker, right bogie), α3, α4 (left), rad.
    pub alpha: [f64; 4],
    /// Wheels in the order left front, middle, rear, right front, middle, rear.
    pub wheels: [Wheel; 6],
    /// The (x, y, heading) it was solved for.
    at: (f64, f64, f64),
    /// The settling iteration's inverse Jacobian (roll and side shifts), which seeds a
    /// warm start's first correction.
    inverse_jacobian: Matrix3<f64>,
}

impl Pose {
    /// The same pose described for the rover turned end for end: heading turned by π,
    /// pitch and roll negated, left and right and front and rear swapped (the map-frame
    /// geometry is unchanged). Applying it twice gives the pose back exactly, except the
    /// heading, which comes back turned by 2π.
    fn mirrored(&self) -> Pose {
        let w = self.wheels;
        Pose {
            left: self.right.mirrored(),
            right: self.left.mirrored(),
            heading: self.heading + std::f64::consts::PI,
            pitch: -self.pitch,
            roll: -self.roll,
            body: self.body,
            pivots: [self.pivots[1], self.pivots[0]],
            alpha: [self.alpha[2], self.alpha[3], self.alpha[0], self.alpha[1]],
            wheels: [w[5], w[4], w[3], w[2], w[1], w[0]],
            at: (self.at.0, self.at.1, self.at.2 + std::f64::consts::PI),
            // Only the bogie-in-front solver reads it, always in its own description.
            inverse_jacobian: self.inverse_jacobian,
        }
    }

    /// The anchor position (m, map frame) and heading (rad) this pose was solved for.
    pub fn solved_at(&self) -> (f64, f64, f64) {
        self.at
    }

    /// Horizontal unit vector along the heading (east, north).
    pub fn forward(&self) -> (f64, f64) {
        self.attitude().forward()
    }

    /// The body's heading, pitch and roll ([`crate::math::Attitude`]).
    pub fn attitude(&self) -> Attitude {
        Attitude { heading: self.heading, pitch: self.pitch, roll: self.roll }
    }

    /// A point given in the body frame about the body reference (x forward, y left, z
    /// up, m) on the map (east, north, up, m): rolled about x, pitched about y, turned
    /// to the heading and moved to [`Pose::body`]. [`Pose::map_to_body`] undoes it.
    pub fn body_to_map(&self, rel: [f64; 3]) -> [f64; 3] {
        self.attitude().body_to_map(self.body, rel)
    }

    /// A map point (m) in the body frame about the body reference: the inverse of
    /// [`Pose::body_to_map`].
    pub fn map_to_body(&self, world: [f64; 3]) -> [f64; 3] {
        self.attitude().map_to_body(self.body, world)
    }

    /// The largest wheel contact error, m: for each wheel, |distance from the axle to
    /// the terrain within the wheel's (roll-tilted) plane − r|, found by marching rays
    /// from the axle every 1° over the lower half and bisecting the first crossing —
    /// walls included, independent of the solver's sampling.
    pub fn contact_error_m(&self, ground: &impl Ground, wheel_radius_m: f64) -> f64 {
        let (fx, fy) = self.forward();
        let (lx, ly) = (-fy, fx);
        let (sr, cr) = self.roll.sin_cos();
        let b = [-sr * lx, -sr * ly, cr];
        let r = wheel_radius_m;
        let mut worst = 0.0f64;
        for w in &self.wheels {
            let mut nearest = f64::INFINITY;
            for k in 0..=180 {
                let (sa, ca) = (std::f64::consts::PI * (1.0 + k as f64 / 180.0)).sin_cos();
                let d = [ca * fx + sa * b[0], ca * fy + sa * b[1], sa * b[2]];
                let below = |t: f64| {
                    let p = [0, 1, 2].map(|i| w.axle[i] + t * d[i]);
                    ground.height(p[0], p[1]).map(|h| p[2] <= h)
                };
                let steps = 150;
                let mut prev = 0.0;
                for j in 1..=steps {
                    let t = 1.5 * r * j as f64 / steps as f64;
                    if below(t) == Some(true) {
                        let (mut lo, mut hi) = (prev, t);
                        for _ in 0..40 {
                            let mid = 0.5 * (lo + hi);
                            if below(mid) == Some(true) {
                                hi = mid;
                            } else {
                                lo = mid;
                            }
                        }
                        nearest = nearest.min(hi);
                        break;
                    }
                    prev = t;
                }
            }
            worst = worst.max((nearest - r).abs());
        }
        worst
    }
}

/// Why no pose exists.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum KinematicsFailure {
    /// A wheel footprint is off the terrain or on missing data.
    OffTerrain,
    /// No axle position satisfies a loop closure (terrain too rough for the links).
    NoClosure,
    /// A rocker or bogie joint would pass its limit.
    JointLimit,
}

impl std::fmt::Display for KinematicsFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            KinematicsFailure::OffTerrain => "a wheel is off the terrain or on missing data",
            KinematicsFailure::NoClosure => "no wheel placement closes the rocker-bogie loop",
            KinematicsFailure::JointLimit => "a rocker or bogie joint would pass its limit",
        })
    }
}

/// The kinematic model of one rover, precomputed from its parameters.
#[derive(Debug, Clone)]
pub struct Kinematics {
    r: f64,
    track: f64,
    /// Nominal side view relative to the middle axle: front axle, bogie pivot, rear
    /// axle, rocker pivot.
    front: (f64, f64),
    pivot: (f64, f64),
    rear: (f64, f64),
    rocker: (f64, f64),
    len_fm: f64,
    len_pr: f64,
    bogie_limit: f64,
    rocker_limit: f64,
    u: [f64; WHEEL_SAMPLES + 1],
    rise: [f64; WHEEL_SAMPLES + 1],
    /// Each sample's contact angle asin(u/r), and how far a tangent may sit from it
    /// and still be the sample's own contact (0.6 of the wider gap to a neighbour).
    angle: [f64; WHEEL_SAMPLES + 1],
    angle_tol: [f64; WHEEL_SAMPLES + 1],
    /// Nominal in-plane angles of the middle→front and bogie pivot→rear chords, rad.
    front_angle: f64,
    rear_chord_angle: f64,
    /// Which point the input names.
    pub anchor: Anchor,
    /// A bogie-behind rover ([`Layout::BogieRear`]), solved as the mirror image: the
    /// fields above describe the rover turned end for end.
    mirror: bool,
}

mod newton;
mod profile;

pub use newton::{NewtonPose, newton_pose};
use profile::{Dilated, Line};

/// A loop closure: the axle lies `len` from `centre`, in direction `dir` (±1) along s.
#[derive(Debug, Clone, Copy)]
struct Link {
    centre: (f64, f64),
    dir: f64,
    len: f64,
}

/// An axle placed by a loop closure.
#[derive(Debug, Clone, Copy)]
struct Placed {
    s: f64,
    /// Scaled height (true height / cos ψ).
    z: f64,
    /// The maximising sample at s.
    k: usize,
}

impl Kinematics {
    /// The model for `params` (which [`RoverParams::validate`] has accepted).
    pub fn new(params: &RoverParams) -> Kinematics {
        let r = params.wheel_radius_m;
        let a = params.axle_x_m;
        // A bogie-behind rover turned end for end (x → −x) has its bogie in front.
        let mirror = params.layout() == Layout::BogieRear;
        let (k, a) =
            if mirror { (-1.0, Axles { front: -a.rear, middle: -a.middle, rear: -a.front }) } else { (1.0, a) };
        let front = (a.front - a.middle, 0.0);
        let pivot = (k * params.bogie_pivot_m.x - a.middle, params.bogie_pivot_m.z - r);
        let rear = (a.rear - a.middle, 0.0);
        let rocker = (k * params.rocker_pivot_m.x - a.middle, params.rocker_pivot_m.z - r);
        let mut u = [0.0; WHEEL_SAMPLES + 1];
        let mut rise = [0.0; WHEEL_SAMPLES + 1];
        for k in 0..=WHEEL_SAMPLES {
            u[k] = -r + 2.0 * r * k as f64 / WHEEL_SAMPLES as f64;
            rise[k] = (r * r - u[k] * u[k]).max(0.0).sqrt();
        }
        let angle = u.map(|v| (v / r).clamp(-1.0, 1.0).asin());
        let mut angle_tol = [0.0; WHEEL_SAMPLES + 1];
        for k in 0..=WHEEL_SAMPLES {
            let below = if k > 0 { angle[k] - angle[k - 1] } else { 0.0 };
            let above = if k < WHEEL_SAMPLES { angle[k + 1] - angle[k] } else { 0.0 };
            angle_tol[k] = 0.6 * below.max(above);
        }
        Kinematics {
            r,
            track: params.track_m,
            front,
            pivot,
            rear,
            rocker,
            len_fm: front.0.hypot(front.1),
            len_pr: (rear.0 - pivot.0).hypot(rear.1 - pivot.1),
            bogie_limit: params.bogie_limit_deg.to_radians(),
            rocker_limit: params.rocker_limit_deg.to_radians(),
            u,
            rise,
            angle,
            angle_tol,
            front_angle: front.1.atan2(front.0),
            rear_chord_angle: (rear.1 - pivot.1).atan2(rear.0 - pivot.0),
            anchor: Anchor::default(),
            mirror,
        }
    }

    /// Whether this rover is solved as its mirror image (bogie behind, [`Layout::BogieRear`]).
    pub fn mirrored(&self) -> bool {
        self.mirror
    }

    /// The pose with the anchor at (x, y) (m, map frame) and heading `heading` (rad,
    /// azimuth clockwise from north). `warm`, the pose at a nearby point of the same
    /// motion, seeds the loop closures and the roll; the result is the same either way
    /// to the solver's tolerance (10 µm, 0.003°).
    pub fn solve(
        &self,
        ground: &impl Ground,
        x: f64,
        y: f64,
        heading: f64,
        warm: Option<&Pose>,
    ) -> Result<Pose, KinematicsFailure> {
        let solved = self.solve_either_layout(ground, x, y, heading, warm);
        // A warm start can lose what a cold solve finds (a wheel on the edge of a step
        // exactly one radius high loses its pinned rim sample); the answer must not
        // depend on the start, so a failed warm solve is tried again cold.
        match solved {
            Err(_) if warm.is_some() => self.solve_either_layout(ground, x, y, heading, None),
            _ => solved,
        }
    }

    fn solve_either_layout(
        &self,
        ground: &impl Ground,
        x: f64,
        y: f64,
        heading: f64,
        warm: Option<&Pose>,
    ) -> Result<Pose, KinematicsFailure> {
        if !self.mirror {
            return self.solve_bogie_front(ground, x, y, heading, warm, self.anchor);
        }
        // The rover turned end for end faces the other way; its left is our right.
        let warm = warm.map(Pose::mirrored);
        let turned = heading + std::f64::consts::PI;
        let mut pose = self.solve_bogie_front(ground, x, y, turned, warm.as_ref(), self.anchor.mirrored())?.mirrored();
        (pose.heading, pose.at) = (heading, (x, y, heading));
        Ok(pose)
    }

    /// [`Kinematics::solve`] for the bogie-in-front chain this model holds.
    ///
    /// Three coupled corrections settle together over a few passes: the roll ψ (secant
    /// steps on ψ = g(ψ)); the footprints (each side's wheel plane at ±(w/2)·cos ψ,
    /// tilted by ψ, so the terrain it cuts rises (1 + g_lat·tan ψ) times less than under
    /// the vertical line, g_lat the ground's sideways slope); and each side's shift
    /// along the heading that puts both rocker pivots on the body's lateral axis (the
    /// differential's pivot line) with the anchor fixed.
    fn solve_bogie_front(
        &self,
        ground: &impl Ground,
        x: f64,
        y: f64,
        heading: f64,
        warm: Option<&Pose>,
        anchor: Anchor,
    ) -> Result<Pose, KinematicsFailure> {
        let (fx, fy) = (heading.sin(), heading.cos());
        let mut roll = warm.map_or(0.0, |p| p.roll);
        let mut shift = warm.map_or((0.0, 0.0), |p| (p.left.shift, p.right.shift));
        // Where each side's axles were (s along the line), to seed the closures.
        let axle_s = |p: &SidePose| p.axles.map(|a| a.0);
        let mut guess = warm.map(|p| (axle_s(&p.left), axle_s(&p.right)));
        // Until the check at the end, each axle evaluates only the rim sample that
        // touched last time (1 height instead of 25).
        let mut pins = warm.map(|p| (p.left.pins, p.right.pins));
        let mut inverse_jacobian = warm.map_or(-Matrix3::identity(), |p| p.inverse_jacobian);
        let mut misses = 0;
        let mut sides = None;
        let mut last: Option<(Vector3<f64>, Vector3<f64>)> = None;
        // Lateral slopes where they were last taken: (x, y, slope) per axle and side.
        let mut lateral_cache = ([(f64::NAN, f64::NAN, 0.0); 3], [(f64::NAN, f64::NAN, 0.0); 3]);
        const PASSES: usize = 24;
        for pass in 0..PASSES {
            let (c, t) = (roll.cos(), roll.tan());
            let (ol, or) = anchor.offsets(self.track, c);
            let (origin_l, zl) = side_origin(ground, (x, y), (fx, fy), ol, shift.0)?;
            let (origin_r, zr) = side_origin(ground, (x, y), (fx, fy), or, shift.1)?;
            // The sideways slope under each wheel (where the last pass put it).
            let kl = self.squeeze(ground, (fx, fy), t, origin_l, guess.map(|g| g.0), &mut lateral_cache.0);
            let kr = self.squeeze(ground, (fx, fy), t, origin_r, guess.map(|g| g.1), &mut lateral_cache.1);
            let split = (0.5 * self.front.0, 0.5 * self.rear.0);
            let profile_l = Line { ground, origin: origin_l, dir: (fx, fy), zref: zl, squeeze: kl, split };
            let profile_r = Line { ground, origin: origin_r, dir: (fx, fy), zref: zr, squeeze: kr, split };
            let use_pins = if misses >= 2 { None } else { pins };
            let mut left = self.solve_side(&profile_l, origin_l, c, guess.map(|g| g.0), use_pins.map(|p| p.0))?;
            let mut right = self.solve_side(&profile_r, origin_r, c, guess.map(|g| g.1), use_pins.map(|p| p.1))?;
            pins = Some((left.pins, right.pins));
            (left.shift, left.plane_z, right.shift, right.plane_z) = (shift.0, zl, shift.1, zr);
            let sin_roll = ((left.rocker_pivot.1 - right.rocker_pivot.1) / self.track).clamp(-1.0, 1.0);
            let g = sin_roll.asin();
            let (pl, pr) = (left.rocker_pivot.0, right.rocker_pivot.0);
            let new_shift = anchor.shifts(pl, pr);
            // Settled: the shifts to 10 µm and the roll to 5e-5 rad (0.003°; the sides
            // then sit within ~3 µm of where the reported roll puts them), far below the
            // terrain's accuracy. The reported roll is the one the final sides give.
            let settled =
                (g - roll).abs() < 5e-5 && (new_shift.0 - shift.0).abs() < 1e-5 && (new_shift.1 - shift.1).abs() < 1e-5;
            if settled || pass + 1 == PASSES {
                let verify = use_pins.is_some();
                let ok_l = self.add_contacts(&profile_l, &mut left, c, verify)?;
                let ok_r = self.add_contacts(&profile_r, &mut right, c, verify)?;
                let ok = ok_l && ok_r;
                if ok || pass + 1 == PASSES {
                    self.add_angles(&mut left, c);
                    self.add_angles(&mut right, c);
                    sides = Some((left, right));
                    // The roll the final sides give.
                    roll = g;
                    break;
                }
                // A pinned sample was not the one touching: pin the ones that are (once),
                // then finish with full rims.
                misses += 1;
                pins = Some((left.pins, right.pins));
            }
            let x_now = Vector3::new(roll, shift.0, shift.1);
            let f_now = Vector3::new(g, new_shift.0, new_shift.1) - x_now;
            let step = broyden_step(&mut inverse_jacobian, &mut last, (x_now, f_now), pass >= PASSES / 2);
            guess = Some((axle_s(&left), axle_s(&right)));
            roll += step.x;
            shift = anchor.stepped(shift, (step.y, step.z));
        }
        let (left, right) = sides.ok_or(KinematicsFailure::NoClosure)?;
        self.assemble(left, right, roll, (x, y, heading), inverse_jacobian)
    }

    /// The pose from a side pair solved at `roll` for the rover at `at` (x, y, heading):
    /// pitch, joint limits, wheels on the map, pivots and body.
    fn assemble(
        &self,
        left: SidePose,
        right: SidePose,
        roll: f64,
        (x, y, heading): (f64, f64, f64),
        inverse_jacobian: Matrix3<f64>,
    ) -> Result<Pose, KinematicsFailure> {
        let (fx, fy) = (heading.sin(), heading.cos());
        let (lx, ly) = (-heading.cos(), heading.sin());
        // The mean rocker pitch is an angle in the tilted wheel planes; the body x axis'
        // elevation (the Euler pitch of yaw–pitch–roll) is asin(cos ψ · sin of it).
        let pitch = (roll.cos() * (0.5 * (left.rocker_pitch + right.rocker_pitch)).sin()).asin();
        let rho = 0.5 * (left.rocker_pitch - right.rocker_pitch);
        if rho.abs() > self.rocker_limit
            || left.bogie_angle.abs() > self.bogie_limit
            || right.bogie_angle.abs() > self.bogie_limit
        {
            return Err(KinematicsFailure::JointLimit);
        }
        // Each side's linkage lies in a plane tilted by the roll through its middle
        // contact: a point dz above that contact sits dz·tan ψ to the right of it.
        let tan_roll = roll.tan();
        let world = |side: &SidePose, p: (f64, f64)| {
            let aside = -(p.1 - side.plane_z) * tan_roll;
            [side.origin.0 + fx * p.0 + lx * aside, side.origin.1 + fy * p.0 + ly * aside, p.1]
        };
        let mut wheels = [Wheel { axle: [0.0; 3], contact: [0.0; 3], normal: [0.0; 3] }; 6];
        let (sr, cr) = roll.sin_cos();
        for (k, side) in [&left, &right].into_iter().enumerate() {
            for i in 0..3 {
                // In the wheel plane: −sin γ along the heading, cos γ along the tilted
                // vertical (−sin ψ left + cos ψ up).
                let (sg, cg) = side.gamma_sc[i];
                wheels[3 * k + i] = Wheel {
                    axle: world(side, side.axles[i]),
                    contact: world(side, side.contacts[i]),
                    normal: [-sg * fx - cg * sr * lx, -sg * fy - cg * sr * ly, cg * cr],
                };
            }
        }
        let (bl, br) = (world(&left, left.rocker_pivot), world(&right, right.rocker_pivot));
        Ok(Pose {
            left,
            right,
            heading,
            pitch,
            roll,
            body: [0.5 * (bl[0] + br[0]), 0.5 * (bl[1] + br[1]), 0.5 * (bl[2] + br[2])],
            pivots: [bl, br],
            alpha: [right.rocker_alpha, right.bogie_alpha, left.rocker_alpha, left.bogie_alpha],
            wheels,
            inverse_jacobian,
            at: (x, y, heading),
        })
    }

    /// The factors by which a side's three wheels see the terrain squeezed in the
    /// wheel plane tilted by a roll of tangent `t`: 1 / (1 + g_lat·t), g_lat the ground's
    /// sideways slope under each wheel (at `side`'s axles along `dir` from `o`, or their
    /// nominal places). Slopes are kept in `cache` while a wheel moves by under 0.1 mm.
    fn squeeze(
        &self,
        ground: &impl Ground,
        (fx, fy): (f64, f64),
        t: f64,
        o: (f64, f64),
        side: Option<[f64; 3]>,
        cache: &mut [(f64, f64, f64); 3],
    ) -> [f64; 3] {
        if t == 0.0 {
            return [1.0; 3];
        }
        let (lx, ly) = (-fy, fx);
        // Over the wheel's width scale, from heights (a Ground's normals may be coarser).
        let lateral_slope = |o: (f64, f64)| {
            let e = 0.5 * self.r;
            match (ground.height(o.0 + lx * e, o.1 + ly * e), ground.height(o.0 - lx * e, o.1 - ly * e)) {
                (Some(a), Some(b)) => (a - b) / (2.0 * e),
                _ => 0.0,
            }
        };
        let mut at = |i: usize, nominal: f64| {
            let s = side.map_or(nominal, |p| p[i]);
            let p = (o.0 + fx * s, o.1 + fy * s);
            // The slope over ±r/2 barely changes over 0.1 mm (the later passes move the
            // axles by less): on ground curved 3 /m it moves by 3e-4, which shifts the
            // squeezed heights by about a micron. It is kept.
            let (x, y, g) = cache[i];
            let g = if (p.0 - x).abs() < 1e-4 && (p.1 - y).abs() < 1e-4 {
                g
            } else {
                let g = lateral_slope(p);
                cache[i] = (p.0, p.1, g);
                g
            };
            1.0 / (1.0 + g * t).max(0.2)
        };
        [at(0, self.front.0), at(1, 0.0), at(2, self.rear.0)]
    }

    /// The dilated terrain at s in the side's tilted plane: in-plane heights are true
    /// heights over c = cos ψ, and the wheel is a disc of radius r in that plane.
    ///
    /// With `pin`, only that sample is evaluated: the caller asserts it is the maximiser
    /// (true near a solution already found) and checks it afterwards.
    fn dilated(&self, profile: &Line<'_, impl Ground>, s: f64, c: f64, pin: Option<usize>) -> Option<Dilated> {
        let inv = 1.0 / c;
        let k = match pin {
            Some(k) => k,
            None => profile.argmax_along(s + self.u[0], self.u[1] - self.u[0], inv, &self.rise)?,
        };
        let (h, slope) = profile.at_slope(s + self.u[k])?;
        Some(Dilated { z: h * inv + self.rise[k], u: self.u[k], slope: slope * inv, k })
    }

    /// The maximiser of h(s + u)/c + √(r² − u²) within one sample spacing of `u0`.
    fn refine_contact(&self, profile: &Line<'_, impl Ground>, s: f64, c: f64, u0: f64) -> Option<f64> {
        let step = 2.0 * self.r / WHEEL_SAMPLES as f64;
        let r2 = self.r * self.r;
        let f = |u: f64| -> Option<f64> { Some(profile.at(s + u)? / c + (r2 - u * u).max(0.0).sqrt()) };
        let (mut a, mut b) = ((u0 - step).max(-self.r), (u0 + step).min(self.r));
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut x1, mut x2) = (b - g * (b - a), a + g * (b - a));
        let (mut f1, mut f2) = (f(x1)?, f(x2)?);
        for _ in 0..24 {
            if f1 < f2 {
                a = x1;
                x1 = x2;
                f1 = f2;
                x2 = a + g * (b - a);
                f2 = f(x2)?;
            } else {
                b = x2;
                x2 = x1;
                f2 = f1;
                x1 = b - g * (b - a);
                f1 = f(x1)?;
            }
        }
        let u = 0.5 * (a + b);
        // Keep the sample if it is higher (a corner exactly on a sample).
        Some(if f(u)? >= f(u0)? { u } else { u0 })
    }

    /// The axle on the dilated terrain at distance `len` from `centre`, searching in
    /// direction `dir` (±1) from `centre.0`, starting at `guess` when given.
    fn closure(
        &self,
        profile: &Line<'_, impl Ground>,
        c: f64,
        link: Link,
        guess: Option<f64>,
        pin: Option<usize>,
    ) -> Result<Placed, KinematicsFailure> {
        let Link { centre, dir, len } = link;
        // In t = dir·(s − centre.0) the distance grows with t: φ(t) < 0 inside.
        let eval = |t: f64| -> Result<(f64, f64, Dilated), KinematicsFailure> {
            let s = centre.0 + dir * t;
            let d = self.dilated(profile, s, c, pin).ok_or(KinematicsFailure::OffTerrain)?;
            let (ds, dz) = (s - centre.0, d.z - centre.1);
            let dist = (ds * ds + dz * dz).sqrt();
            // dφ/dt = (ds·dir + dz·dz/dt)/dist with dz/dt = dir·slope.
            let deriv = if dist > 0.0 { (ds * dir + dz * dir * d.slope) / dist } else { 1.0 };
            Ok((dist - len, deriv, d))
        };
        let (mut lo, mut hi) = (f64::NAN, f64::NAN);
        let mut t = match guess {
            Some(s) => dir * (s - centre.0),
            None => {
                // Cold: scan outward for the sign change.
                let (a, b) = scan_for_closure(&eval, len)?;
                lo = a;
                hi = b;
                0.5 * (a + b)
            }
        };
        for _ in 0..100 {
            let (phi, deriv, d) = eval(t)?;
            if phi.abs() < 1e-8 {
                return Ok(Placed { s: centre.0 + dir * t, z: d.z, k: d.k });
            }
            if phi < 0.0 {
                lo = if lo.is_nan() { t } else { lo.max(t) };
            } else {
                hi = if hi.is_nan() { t } else { hi.min(t) };
            }
            if !lo.is_nan() && !hi.is_nan() && hi - lo < 1e-10 {
                break;
            }
            let newton = t - phi / deriv;
            let bracketed = !lo.is_nan() && !hi.is_nan();
            t = if deriv.is_finite() && deriv > 1e-3 && (newton - t).abs() < 0.05 * len {
                if bracketed && !(newton > lo && newton < hi) { 0.5 * (lo + hi) } else { newton }
            } else if bracketed {
                0.5 * (lo + hi)
            } else {
                // No bracket yet and no usable Newton step: walk toward the root.
                t + if phi < 0.0 { 0.01 * len } else { -0.01 * len }
            };
            if !bracketed && !(-0.5 * len..=1.5 * len).contains(&t) {
                return Err(KinematicsFailure::NoClosure);
            }
        }
        if lo.is_nan() || hi.is_nan() {
            return Err(KinematicsFailure::NoClosure);
        }
        // The bracket collapsed onto a vertical segment of A (a wall): the axle is where
        // the closure circle crosses it, between the heights on either side.
        let s = centre.0 + dir * hi;
        let (za, end) = (eval(lo)?.2.z, eval(hi)?.2);
        let zb = end.z;
        let ds = s - centre.0;
        let h = (len * len - ds * ds).max(0.0).sqrt();
        let (zl, zh) = (za.min(zb), za.max(zb));
        let z = [centre.1 + h, centre.1 - h]
            .into_iter()
            .min_by(|a, b| dist_to_range(*a, zl, zh).total_cmp(&dist_to_range(*b, zl, zh)))
            .unwrap_or(zh);
        Ok(Placed { s, z, k: end.k })
    }

    /// Contact points and angles of a solved side. On smooth ground the contact is the
    /// tangent point (γ = atan of the in-plane slope at the touching sample, when that
    /// agrees with the sample's own angle to within its spacing); at an edge the
    /// maximiser of the dilation is refined. With `verify`, returns `false` if a full
    /// dilation finds the ground above an axle (a pinned sample was not the maximiser).
    fn add_contacts(
        &self,
        profile: &Line<'_, impl Ground>,
        side: &mut SidePose,
        c: f64,
        verify: bool,
    ) -> Result<bool, KinematicsFailure> {
        let mut ok = true;
        for i in 0..3 {
            let (s, z_true) = side.axles[i];
            let z = z_true / c;
            let d = self.dilated(profile, s, c, None).ok_or(KinematicsFailure::OffTerrain)?;
            side.pins[i] = d.k;
            if verify && d.z > z + 1e-9 {
                ok = false;
                continue;
            }
            if z < d.z - 1e-9 && d.u.abs() > 1e-12 {
                // On a wall face: the contact is on the face, level with the axle.
                side.contacts[i] = (s + d.u, z_true);
                side.gamma[i] = d.u.signum() * std::f64::consts::FRAC_PI_2;
                side.gamma_sc[i] = (d.u.signum(), 0.0);
                continue;
            }
            let tangent = d.slope.atan();
            let u = if (tangent - self.angle[d.k]).abs() <= self.angle_tol[d.k] {
                side.gamma[i] = tangent;
                // sin and cos of atan(slope), without the trigonometry.
                let cos = 1.0 / (1.0 + d.slope * d.slope).sqrt();
                side.gamma_sc[i] = (d.slope * cos, cos);
                self.r * d.slope * cos
            } else {
                let u = self.refine_contact(profile, s, c, d.u).ok_or(KinematicsFailure::OffTerrain)?;
                let rise = (self.r * self.r - u * u).max(0.0).sqrt();
                side.gamma[i] = u.atan2(rise);
                side.gamma_sc[i] = (u / self.r, rise / self.r);
                u
            };
            side.contacts[i] = (s + u, profile.at(s + u).ok_or(KinematicsFailure::OffTerrain)?);
        }
        Ok(ok)
    }

    /// The link angles of a solved side, in its tilted plane (heights over c).
    fn add_angles(&self, side: &mut SidePose, c: f64) {
        let sc = |p: (f64, f64)| (p.0, p.1 / c);
        let (f, m, rear) = (sc(side.axles[0]), sc(side.axles[1]), sc(side.axles[2]));
        let (pivot, rocker) = (sc(side.bogie_pivot), sc(side.rocker_pivot));
        let chord = sub(rear, pivot);
        side.rocker_pitch = wrap_pi(chord.1.atan2(chord.0) - self.rear_chord_angle);
        let bogie_pitch = wrap_pi((f.1 - m.1).atan2(f.0 - m.0) - self.front_angle);
        side.bogie_angle = wrap_pi(bogie_pitch - side.rocker_pitch);
        side.rocker_alpha = (rocker.1 - pivot.1).atan2(pivot.0 - rocker.0);
        side.bogie_alpha = (pivot.1 - f.1).atan2(f.0 - pivot.0);
    }

    fn solve_side(
        &self,
        profile: &Line<'_, impl Ground>,
        origin: (f64, f64),
        c: f64,
        warm: Option<[f64; 3]>,
        pins: Option<[usize; 3]>,
    ) -> Result<SidePose, KinematicsFailure> {
        let pin = |i: usize| pins.map(|p| p[i]);
        let m0 = self.dilated(profile, 0.0, c, pin(1)).ok_or(KinematicsFailure::OffTerrain)?;
        let m = (0.0, m0.z);
        let front = Link { centre: m, dir: 1.0, len: self.len_fm };
        let fp = self.closure(profile, c, front, warm.map(|w| w[0]), pin(0))?;
        let f = (fp.s, fp.z);
        let pivot = place(m, f, self.front, self.pivot);
        let back = Link { centre: pivot, dir: -1.0, len: self.len_pr };
        let rp = self.closure(profile, c, back, warm.map(|w| w[2]).filter(|&s| s < pivot.0), pin(2))?;
        let rear = (rp.s, rp.z);
        let nominal_pr = sub(self.rear, self.pivot);
        let rocker = place(pivot, rear, nominal_pr, sub(self.rocker, self.pivot));
        let axles = [(f.0, f.1 * c), (m.0, m.1 * c), (rear.0, rear.1 * c)];
        // Contacts are found on the final pass only.
        let contacts = [(f.0, 0.0), (m0.u, 0.0), (rear.0, 0.0)];
        let gamma = [0.0; 3];
        let unscale = |p: (f64, f64)| (p.0, p.1 * c);
        Ok(SidePose {
            axles,
            contacts,
            gamma,
            bogie_pivot: unscale(pivot),
            rocker_pivot: unscale(rocker),
            // Angles are found on the final pass only.
            rocker_pitch: 0.0,
            bogie_angle: 0.0,
            rocker_alpha: 0.0,
            bogie_alpha: 0.0,
            origin,
            shift: 0.0,
            plane_z: 0.0,
            pins: [fp.k, m0.k, rp.k],
            gamma_sc: [(0.0, 1.0); 3],
        })
    }
}

fn dist_to_range(z: f64, lo: f64, hi: f64) -> f64 {
    if z < lo {
        lo - z
    } else if z > hi {
        z - hi
    } else {
        0.0
    }
}

fn sub(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 - b.0, a.1 - b.1)
}

/// Places `local` (given relative to `o` in the nominal layout, where o → `nominal_to`
/// is the reference chord) in the frame where o → `to` is that chord.
fn place(o: (f64, f64), to: (f64, f64), nominal_to: (f64, f64), local: (f64, f64)) -> (f64, f64) {
    // The rotation taking the nominal chord onto the actual one, without trigonometry.
    let (a, n) = ((to.0 - o.0, to.1 - o.1), nominal_to);
    let norm = ((a.0 * a.0 + a.1 * a.1) * (n.0 * n.0 + n.1 * n.1)).sqrt().max(1e-300);
    let (c, s) = ((a.0 * n.0 + a.1 * n.1) / norm, (n.0 * a.1 - n.1 * a.0) / norm);
    (o.0 + c * local.0 - s * local.1, o.1 + s * local.0 + c * local.1)
}

fn wrap_pi(a: f64) -> f64 {
    (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

/// The pose with the midpoint between the middle wheels at (x, y) (m, map frame) and
/// heading `heading_deg` (azimuth, degrees clockwise from north), by the planar
/// decomposition, cold.
pub fn pose(
    ground: &impl Ground,
    params: &RoverParams,
    x: f64,
    y: f64,
    heading_deg: f64,
) -> Result<Pose, KinematicsFailure> {
    Kinematics::new(params).solve(ground, x, y, heading_deg.to_radians(), None)
}

/// A side's line origin on the map for the rover at `at` heading along `fwd`: `offset`
/// to the left and `shift` along the heading; and the ground's height there, through
/// which the side's tilted wheel plane passes.
fn side_origin(
    ground: &impl Ground,
    at: (f64, f64),
    (fx, fy): (f64, f64),
    offset: f64,
    shift: f64,
) -> Result<((f64, f64), f64), KinematicsFailure> {
    let (lx, ly) = (-fy, fx);
    let o = (at.0 + lx * offset + fx * shift, at.1 + ly * offset + fy * shift);
    Ok((o, ground.height(o.0, o.1).ok_or(KinematicsFailure::OffTerrain)?))
}

/// A cold closure's bracket: scanning outward from t = 0 (where the link must be too
/// short) in 16 steps to 1.2 × its length, the first interval where φ changes sign.
fn scan_for_closure<T>(
    eval: &impl Fn(f64) -> Result<(f64, f64, T), KinematicsFailure>,
    len: f64,
) -> Result<(f64, f64), KinematicsFailure> {
    let steps = 16;
    if eval(0.0)?.0 >= 0.0 {
        return Err(KinematicsFailure::NoClosure);
    }
    let mut prev = 0.0;
    for k in 1..=steps {
        let t = 1.2 * len * k as f64 / steps as f64;
        if eval(t)?.0 >= 0.0 {
            return Ok((prev, t));
        }
        prev = t;
    }
    Err(KinematicsFailure::NoClosure)
}

/// One step of Broyden's method on x = (ψ, shift_l, shift_r) ↦ G(x) − x, from `x_now`
/// where G(x) − x is `f_now`, updating the inverse Jacobian's estimate and the last
/// point. With `plain` (late passes), or after a wild step, plain iteration.
fn broyden_step(
    inverse_jacobian: &mut Matrix3<f64>,
    last: &mut Option<(Vector3<f64>, Vector3<f64>)>,
    (x_now, f_now): (Vector3<f64>, Vector3<f64>),
    plain: bool,
) -> Vector3<f64> {
    // Broyden's method on x = (ψ, shift_l, shift_r) ↦ G(x) − x: roll and shifts
    // are coupled (moving a side along a sloping flank changes the roll), so a
    // step that knows the coupling settles in 2–3 passes where plain iteration
    // needs 4–5. H approximates the inverse Jacobian; −I is plain iteration.
    if let Some((x0, f0)) = *last {
        let (dx, df): (Vector3<f64>, Vector3<f64>) = (x_now - x0, f_now - f0);
        let dd = df.dot(&df);
        if dd > 1e-30 {
            *inverse_jacobian += (dx - *inverse_jacobian * df) * (df.transpose() / dd);
        }
    }
    *last = Some((x_now, f_now));
    let mut step = -(*inverse_jacobian * f_now);
    // A wild step (a changed pin, a wall) falls back to plain iteration.
    if !(step.iter().all(|v| v.is_finite()) && step.norm() <= 10.0 * f_now.norm()) || plain {
        *inverse_jacobian = -Matrix3::identity();
        step = f_now;
    }
    step
}

#[cfg(test)]
mod tests;
