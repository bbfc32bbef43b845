//! Rocker-bogie kinematics on terrain by the paper's planar decomposition (Farritor et
//! al. 1998, §3; reference §3): each side is a planar three-wheel problem along the
//! heading; the body pitch is the mean of the two rocker pitches (the differential) and
//! the roll follows from the two rocker-pivot heights.
//!
//! Wheels touch the **dilated terrain**: the admissible axle height at s along the
//! profile is A(s) = max over |u| ≤ r of h(s + u) + √(r² − u²), so a wheel against a
//! wall rides up its face instead of sinking into it. Along each side: the middle axle
//! sits on A at the reference point; the front axle is where A meets the circle of
//! radius |FM| around it; the bogie pivot follows rigidly; the rear axle is where A
//! meets the circle of radius |PR| around the pivot.
//!
//! Not yet here: the footprint correction step (wheels shift sideways with roll) and a
//! Newton solve of the full system as a cross-check.

use areo_terrain::Ground;

use crate::params::RoverParams;

/// Samples across a wheel's diameter for the dilated terrain.
const WHEEL_SAMPLES: usize = 24;

/// One side's planar solution, in (s, z): s forward along the heading from the
/// reference point, z up (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SidePose {
    /// Front, middle and rear axle centres.
    pub axles: [(f64, f64); 3],
    /// Bogie pivot.
    pub bogie_pivot: (f64, f64),
    /// Rocker (body) pivot.
    pub rocker_pivot: (f64, f64),
    /// Rocker pitch relative to its flat-ground orientation, rad (nose up positive).
    pub rocker_pitch: f64,
    /// α1: angle of bogie pivot → rocker pivot above the rearward horizontal, rad.
    pub alpha1: f64,
    /// α2: angle of front axle → bogie pivot above the rearward horizontal, rad.
    pub alpha2: f64,
    /// Largest |distance from an axle to the terrain − r|, m.
    pub contact_error_m: f64,
}

/// The rover's pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Left side (y = +track/2).
    pub left: SidePose,
    /// Right side (y = −track/2).
    pub right: SidePose,
    /// Body pitch = mean of the rocker pitches, rad (nose up positive).
    pub pitch: f64,
    /// Body roll from the rocker-pivot heights, rad (left side up positive).
    pub roll: f64,
    /// Body height: mean of the rocker-pivot heights, m.
    pub pivot_height_m: f64,
}

impl Pose {
    /// The largest wheel contact error of both sides, m.
    pub fn contact_error_m(&self) -> f64 {
        self.left.contact_error_m.max(self.right.contact_error_m)
    }
}

/// Why no pose exists.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KinematicsFailure {
    /// A wheel footprint is off the terrain or on missing data.
    OffTerrain,
    /// No axle position satisfies a loop closure (terrain too rough for the links).
    NoClosure,
}

/// The pose with the midpoint between the middle wheels at (x, y) (m, map frame) and
/// the rover heading `heading_deg` (azimuth, clockwise from north).
pub fn pose(
    ground: &impl Ground,
    params: &RoverParams,
    x: f64,
    y: f64,
    heading_deg: f64,
) -> Result<Pose, KinematicsFailure> {
    let h = heading_deg.to_radians();
    let fwd = (h.sin(), h.cos());
    let left = (-h.cos(), h.sin());
    let half = params.track_m / 2.0;
    let side = |offset: f64| {
        let origin = (x + left.0 * offset, y + left.1 * offset);
        solve_side(&|s: f64| ground.height(origin.0 + fwd.0 * s, origin.1 + fwd.1 * s), params)
    };
    let (l, r) = (side(half)?, side(-half)?);
    Ok(Pose {
        left: l,
        right: r,
        pitch: 0.5 * (l.rocker_pitch + r.rocker_pitch),
        roll: ((l.rocker_pivot.1 - r.rocker_pivot.1) / params.track_m).atan(),
        pivot_height_m: 0.5 * (l.rocker_pivot.1 + r.rocker_pivot.1),
    })
}

/// Admissible axle height at s over a profile.
fn dilated(profile: &impl Fn(f64) -> Option<f64>, s: f64, r: f64) -> Option<f64> {
    let mut best = f64::NEG_INFINITY;
    for k in 0..=WHEEL_SAMPLES {
        let u = -r + 2.0 * r * k as f64 / WHEEL_SAMPLES as f64;
        best = best.max(profile(s + u)? + (r * r - u * u).max(0.0).sqrt());
    }
    Some(best)
}

/// The s in (from, from + dir·span] where the axle on the dilated terrain is at
/// distance `len` from `centre`, scanning outward then bisecting.
fn closure(
    profile: &impl Fn(f64) -> Option<f64>,
    r: f64,
    centre: (f64, f64),
    from: f64,
    dir: f64,
    len: f64,
) -> Result<(f64, f64), KinematicsFailure> {
    let dist = |s: f64| -> Result<f64, KinematicsFailure> {
        let z = dilated(profile, s, r).ok_or(KinematicsFailure::OffTerrain)?;
        Ok((s - centre.0).hypot(z - centre.1) - len)
    };
    let steps = 64;
    let mut a = from;
    let mut fa = dist(a)?;
    for k in 1..=steps {
        let b = from + dir * len * 1.2 * k as f64 / steps as f64;
        let fb = dist(b)?;
        if fa < 0.0 && fb >= 0.0 {
            let (mut lo, mut hi) = (a, b);
            for _ in 0..50 {
                let mid = 0.5 * (lo + hi);
                if dist(mid)? < 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let s = 0.5 * (lo + hi);
            return Ok((s, dilated(profile, s, r).ok_or(KinematicsFailure::OffTerrain)?));
        }
        a = b;
        fa = fb;
    }
    Err(KinematicsFailure::NoClosure)
}

fn solve_side(profile: &impl Fn(f64) -> Option<f64>, p: &RoverParams) -> Result<SidePose, KinematicsFailure> {
    let r = p.wheel_radius_m;
    let a = p.axle_x_m;
    // Nominal side view (s forward), relative to the middle axle.
    let nominal_f = (a.front - a.middle, 0.0);
    let nominal_p = (p.bogie_pivot_m.x - a.middle, p.bogie_pivot_m.z - r);
    let nominal_r = (a.rear - a.middle, 0.0);
    let nominal_b = (p.rocker_pivot_m.x - a.middle, p.rocker_pivot_m.z - r);
    let len_fm = nominal_f.0.hypot(nominal_f.1);
    let rel = |q: (f64, f64), o: (f64, f64)| (q.0 - o.0, q.1 - o.1);
    let len_pr = {
        let d = rel(nominal_r, nominal_p);
        d.0.hypot(d.1)
    };
    // Middle, front, bogie pivot.
    let m = (0.0, dilated(profile, 0.0, r).ok_or(KinematicsFailure::OffTerrain)?);
    let f = closure(profile, r, m, 0.0, 1.0, len_fm)?;
    let frame = |o: (f64, f64), to: (f64, f64), nominal_to: (f64, f64), local: (f64, f64)| {
        // Place `local` (given relative to o in the nominal layout, where o→nominal_to
        // is the reference chord) in the actual frame where o→to is that chord.
        let (cu, cv) = (to.0 - o.0, to.1 - o.1);
        let (nu, nv) = (nominal_to.0, nominal_to.1);
        let rot = cv.atan2(cu) - nv.atan2(nu);
        let (s, c) = rot.sin_cos();
        (o.0 + c * local.0 - s * local.1, o.1 + s * local.0 + c * local.1)
    };
    let pivot = frame(m, f, nominal_f, nominal_p);
    let rear = closure(profile, r, pivot, pivot.0, -1.0, len_pr)?;
    let rocker = frame(pivot, rear, rel(nominal_r, nominal_p), rel(nominal_b, nominal_p));
    let nominal_chord = rel(nominal_r, nominal_p);
    let chord = rel(rear, pivot);
    let rocker_pitch = chord.1.atan2(chord.0) - nominal_chord.1.atan2(nominal_chord.0);
    // Contact error: distance from each axle to the sampled terrain, less r.
    let error = |c: (f64, f64)| -> f64 {
        let mut d = f64::INFINITY;
        for k in 0..=4 * WHEEL_SAMPLES {
            let u = -1.5 * r + 3.0 * r * k as f64 / (4 * WHEEL_SAMPLES) as f64;
            if let Some(z) = profile(c.0 + u) {
                d = d.min(u.hypot(z - c.1));
            }
        }
        (d - r).abs()
    };
    Ok(SidePose {
        axles: [f, m, rear],
        bogie_pivot: pivot,
        rocker_pivot: rocker,
        rocker_pitch: wrap_pi(rocker_pitch),
        alpha1: (rocker.1 - pivot.1).atan2(pivot.0 - rocker.0),
        alpha2: (pivot.1 - f.1).atan2(f.0 - pivot.0),
        contact_error_m: error(f).max(error(m)).max(error(rear)),
    })
}

fn wrap_pi(a: f64) -> f64 {
    (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

#[cfg(test)]
mod tests {
    use super::*;
    use areo_terrain::analytic::{Plane, Step};

    fn lsr1() -> RoverParams {
        RoverParams::lsr1()
    }

    #[test]
    fn flat_ground_gives_the_nominal_pose() {
        let p = pose(&Plane { z0: 2.0, gx: 0.0, gy: 0.0 }, &lsr1(), 10.0, 5.0, 37.0).unwrap();
        assert!(p.pitch.abs() < 1e-9 && p.roll.abs() < 1e-9);
        assert!((p.left.alpha1.to_degrees() - 26.565).abs() < 0.01, "{}", p.left.alpha1.to_degrees());
        assert!((p.left.alpha2.to_degrees() - 30.964).abs() < 0.01);
        assert!((p.pivot_height_m - 2.32).abs() < 1e-6, "rocker pivot 0.32 m above the ground");
        assert!(p.contact_error_m() < 1e-3);
        // The front axle 0.40 m ahead, the rear 0.40 m behind.
        assert!((p.left.axles[0].0 - 0.40).abs() < 1e-6 && (p.left.axles[2].0 + 0.40).abs() < 1e-6);
    }

    #[test]
    fn a_uniform_slope_pitches_the_body_by_the_slope() {
        // Heading north up a 10° slope: pitch = 10°, links unchanged relative to the body.
        let g = Plane { z0: 0.0, gx: 0.0, gy: 10f64.to_radians().tan() };
        let p = pose(&g, &lsr1(), 0.0, 0.0, 0.0).unwrap();
        assert!((p.pitch.to_degrees() - 10.0).abs() < 0.01, "{}", p.pitch.to_degrees());
        assert!(p.roll.abs() < 1e-9);
        assert!(((p.left.alpha2 + p.pitch).to_degrees() - 30.964).abs() < 0.02, "α2 relative to the body");
        assert!(p.contact_error_m() < 0.004, "{}", p.contact_error_m());
    }

    #[test]
    fn a_side_slope_rolls_the_body() {
        // Heading north on ground rising to the west (left): roll = +φ.
        let g = Plane { z0: 0.0, gx: -10f64.to_radians().tan(), gy: 0.0 };
        let p = pose(&g, &lsr1(), 0.0, 0.0, 0.0).unwrap();
        assert!((p.roll.to_degrees() - 10.0).abs() < 0.01, "{}", p.roll.to_degrees());
        assert!(p.pitch.abs() < 1e-9);
    }

    #[test]
    fn the_front_wheel_climbs_a_step_and_the_differential_averages() {
        // A 0.15 m step 0.25 m ahead of the middle wheels, across both sides: the front
        // axles ride on top, 0.15 m higher; the bogies rotate by asin(0.15/0.40).
        let g = Step { x_step: 0.0, low_m: 0.0, high_m: 0.15 };
        // Heading east so the step (at x = 0) is ahead: reference at x = −0.25.
        let p = pose(&g, &lsr1(), -0.25, 0.0, 90.0).unwrap();
        let f = p.left.axles[0];
        assert!((f.1 - (0.10 + 0.15)).abs() < 1e-3, "front axle on top: {f:?}");
        let m = p.left.axles[1];
        assert!(((f.1 - m.1) / 0.40 - (0.15f64 / 0.40)).abs() < 1e-3);
        assert!(p.pitch > 0.0, "nose up");
        assert!(p.contact_error_m() < 0.004, "{}", p.contact_error_m());
        // Only the left side on the step: the body pitches by half the left rocker pitch.
        struct LeftStep;
        impl Ground for LeftStep {
            fn height(&self, x: f64, y: f64) -> Option<f64> {
                Some(if x >= 0.0 && y > 0.0 { 0.15 } else { 0.0 })
            }
            fn normal(&self, _: f64, _: f64) -> Option<[f64; 3]> {
                Some([0.0, 0.0, 1.0])
            }
        }
        let q = pose(&LeftStep, &lsr1(), -0.25, 0.0, 90.0).unwrap();
        assert!((q.pitch - q.left.rocker_pitch / 2.0).abs() < 1e-9 && q.right.rocker_pitch.abs() < 1e-9);
        assert!(q.roll > 0.0, "heading east, the left side is north: on the step, up");
    }

    #[test]
    fn off_the_terrain_is_reported() {
        struct Island;
        impl Ground for Island {
            fn height(&self, x: f64, _: f64) -> Option<f64> {
                (x.abs() < 0.3).then_some(0.0)
            }
            fn normal(&self, _: f64, _: f64) -> Option<[f64; 3]> {
                Some([0.0, 0.0, 1.0])
            }
        }
        assert_eq!(pose(&Island, &lsr1(), 0.0, 0.0, 90.0), Err(KinematicsFailure::OffTerrain));
    }
}
