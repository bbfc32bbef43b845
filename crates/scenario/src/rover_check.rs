//! `areo rover check`: one quasi-static evaluation of a rover parameter file on a
//! standard test terrain — the pose, wheel loads and torques, which limits bind, the
//! stability margin and the smallest friction coefficient that holds — so an engineer
//! can sanity-check a parameter file against their own numbers.

use std::path::Path;
use std::str::FromStr;

use areo_rover::arm::ArmState;
use areo_rover::evaluation::{Conditions, Evaluation, Evaluator, Place, Violation};
use areo_rover::kinematics::Pose;
use areo_terrain::Ground;
use areo_terrain::analytic::{Plane, Wall};
use serde::Serialize;

use crate::error::{Error, Result};

/// A standard test terrain, as given to `--terrain`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TestTerrain {
    /// Level ground.
    Flat,
    /// A uniform slope rising ahead, degrees.
    Slope(f64),
    /// A uniform slope rising to the rover's left, degrees.
    SideSlope(f64),
    /// A vertical step of this height (m) with the front wheels pressed against it.
    Step(f64),
}

impl FromStr for TestTerrain {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<TestTerrain, String> {
        let allowed = "allowed: flat, slope:DEG or side-slope:DEG (0 ≤ DEG < 90), step:HEIGHT_M (0 < HEIGHT_M ≤ 2)";
        let number = |v: &str| v.parse::<f64>().map_err(|_| format!("`{s}`: `{v}` is not a number; {allowed}"));
        let (kind, value) = s.split_once(':').unwrap_or((s, ""));
        match kind {
            "flat" if value.is_empty() => Ok(TestTerrain::Flat),
            "slope" | "side-slope" => {
                let deg = number(value)?;
                if !(0.0..90.0).contains(&deg) {
                    return Err(format!("`{s}`: {deg}° is out of range; {allowed}"));
                }
                Ok(if kind == "slope" { TestTerrain::Slope(deg) } else { TestTerrain::SideSlope(deg) })
            }
            "step" => {
                let h = number(value)?;
                if !(h > 0.0 && h <= 2.0) {
                    return Err(format!("`{s}`: {h} m is out of range; {allowed}"));
                }
                Ok(TestTerrain::Step(h))
            }
            _ => Err(format!("`{s}`: unknown terrain; {allowed}")),
        }
    }
}

impl std::fmt::Display for TestTerrain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TestTerrain::Flat => f.write_str("flat"),
            TestTerrain::Slope(d) => write!(f, "slope:{d}"),
            TestTerrain::SideSlope(d) => write!(f, "side-slope:{d}"),
            TestTerrain::Step(h) => write!(f, "step:{h}"),
        }
    }
}

/// One wheel's share.
#[derive(Debug, Clone, Serialize)]
pub struct WheelReport {
    /// Which wheel, e.g. "left front".
    pub wheel: String,
    /// Normal load, N.
    pub normal_n: f64,
    /// Tractive force, N.
    pub traction_n: f64,
    /// Motor torque at the wheel, N·m.
    pub torque_nm: f64,
    /// Contact angle, degrees (terrain rising ahead positive).
    pub contact_deg: f64,
    /// Limits at their bound: "friction", "contact" (N = 0), "torque".
    pub binding: Vec<&'static str>,
}

/// The pose.
#[derive(Debug, Clone, Serialize)]
pub struct PoseReport {
    /// Body pitch, degrees (nose up positive).
    pub pitch_deg: f64,
    /// Body roll, degrees (left up positive).
    pub roll_deg: f64,
    /// Rocker-pivot midpoint height above the ground under the middle wheels, m.
    pub body_height_m: f64,
    /// The paper's α1..α4 (right rocker, right bogie, left rocker, left bogie), degrees.
    pub alpha_deg: [f64; 4],
}

/// What `areo rover check` reports.
#[derive(Debug, Clone, Serialize)]
pub struct RoverCheckReport {
    /// The rover's name.
    pub rover: String,
    /// The terrain.
    pub terrain: String,
    /// The friction coefficient checked.
    pub mu: f64,
    /// Driving (rolling resistance counted) or holding still.
    pub moving: bool,
    /// "ok", or the violated limit.
    pub verdict: String,
    /// The pose, if one exists.
    pub pose: Option<PoseReport>,
    /// The wheels, when the forces are admissible.
    pub wheels: Vec<WheelReport>,
    /// Force-angle stability margin, % of flat ground.
    pub stability_pct: Option<f64>,
    /// Total weight, N.
    pub weight_n: f64,
    /// The smallest μ (to 1e-4) at which the rover holds here, if any μ ≤ 5 does.
    pub mu_needed: Option<f64>,
    /// On a step: the climb over it, pose by pose.
    pub climb: Option<areo_actions::StepClimb>,
}

/// The wheels in report order.
const WHEELS: [&str; 6] = ["left front", "left middle", "left rear", "right front", "right middle", "right rear"];

/// Loads `params_path` and evaluates it on `terrain` with friction `mu`.
pub fn check(params_path: &Path, terrain: TestTerrain, mu: f64, moving: bool) -> Result<RoverCheckReport> {
    let params = crate::format::rover_files::load_params(params_path)?;
    if !(mu > 0.0 && mu.is_finite()) {
        return Err(Error::usage(format!("--mu {mu}"), "must be positive and finite"));
    }
    let ev = Evaluator::new(&params);
    let arm = ArmState::stowed(&params);
    let direction = if moving { 1.0 } else { 0.0 };
    let (result, ground_z, mu_needed) = match terrain {
        TestTerrain::Flat => at(&ev, &Plane { z0: 0.0, gx: 0.0, gy: 0.0 }, 0.0, &arm, mu, direction),
        TestTerrain::Slope(d) => {
            at(&ev, &Plane { z0: 0.0, gx: 0.0, gy: d.to_radians().tan() }, 0.0, &arm, mu, direction)
        }
        TestTerrain::SideSlope(d) => {
            // Heading north; rising to the west is rising to the left.
            at(&ev, &Plane { z0: 0.0, gx: -d.to_radians().tan(), gy: 0.0 }, 0.0, &arm, mu, direction)
        }
        TestTerrain::Step(h) => {
            // Heading east; the wall 1 µm inside the front wheels' reach.
            let a = params.axle_x_m;
            let x_step = (a.front - a.middle) + params.wheel_radius_m - 1e-6;
            at(&ev, &Wall { x_step, low_m: 0.0, high_m: h }, 90.0, &arm, mu, direction)
        }
    };
    let mut report = RoverCheckReport {
        rover: params.name.clone(),
        terrain: terrain.to_string(),
        mu,
        moving,
        verdict: "ok".into(),
        pose: None,
        wheels: Vec::new(),
        stability_pct: None,
        weight_n: params.mass_kg * params.gravity_m_s2,
        mu_needed,
        climb: None,
    };
    if let TestTerrain::Step(h) = terrain {
        report.climb = Some(areo_actions::step_climb(&ev, &arm, h, mu, direction));
    }
    match result {
        Ok(e) => {
            report.pose = Some(pose_report(&e.pose, ground_z));
            report.stability_pct = Some(100.0 * e.stability);
            report.weight_n = e.weight_n;
            report.wheels = wheels(&e, mu, params.wheel_torque_max_nm);
        }
        Err((violation, pose)) => {
            report.verdict = violation.to_string();
            report.pose = pose.map(|p| pose_report(&p, ground_z));
        }
    }
    Ok(report)
}

/// The evaluation (or the violation and the pose, if any), the ground height at the
/// anchor, and the smallest μ that holds.
type Outcome = (std::result::Result<Evaluation, (Violation, Option<Pose>)>, f64, Option<f64>);

/// Evaluates at the origin heading `heading_deg`, and finds the smallest μ that holds.
fn at(ev: &Evaluator, ground: &impl Ground, heading_deg: f64, arm: &ArmState, mu: f64, direction: f64) -> Outcome {
    let place = Place { x: 0.0, y: 0.0, heading: heading_deg.to_radians() };
    let eval = |mu: f64| ev.evaluate(ground, place, arm, &Conditions { mu, direction }, None);
    let result = eval(mu).map_err(|v| {
        let pose = ev.kinematics().solve(ground, place.x, place.y, place.heading, None).ok();
        (v, pose)
    });
    let mu_needed = areo_actions::least_mu(|mu| eval(mu).is_ok(), 1e-4);
    (result, ground.height(0.0, 0.0).unwrap_or(0.0), mu_needed)
}

fn pose_report(p: &Pose, ground_z: f64) -> PoseReport {
    PoseReport {
        pitch_deg: p.pitch.to_degrees(),
        roll_deg: p.roll.to_degrees(),
        body_height_m: p.body[2] - ground_z,
        alpha_deg: p.alpha.map(f64::to_degrees),
    }
}

fn wheels(e: &Evaluation, mu: f64, torque_max: f64) -> Vec<WheelReport> {
    let mut out = Vec::new();
    for (k, side) in e.sides.iter().enumerate() {
        let pose_side = if k == 0 { &e.pose.left } else { &e.pose.right };
        for i in 0..3 {
            let (n, t, tau) = (side.normal_n[i], side.traction_n[i], side.torque_nm[i]);
            let scale = e.weight_n * 1e-6;
            let mut binding = Vec::new();
            if n <= scale {
                binding.push("contact");
            } else if t.abs() >= mu * n - scale {
                binding.push("friction");
            }
            if tau.abs() >= torque_max * (1.0 - 1e-6) {
                binding.push("torque");
            }
            out.push(WheelReport {
                wheel: WHEELS[3 * k + i].into(),
                normal_n: n,
                traction_n: t,
                torque_nm: tau,
                contact_deg: pose_side.gamma[i].to_degrees(),
                binding,
            });
        }
    }
    out
}

/// What a rover file describes: the LSR-1-style geometry and mass properties the
/// quasi-static model reads ([`check`]), or a TEMPEST resource model — locomotor,
/// array, battery, loads ([`check_resources`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoverFile {
    /// `RoverParams(…)`.
    Physics,
    /// `ResourceModel(…)`.
    Resources,
}

/// The kind of rover file at `path`, from the struct name it opens with (after
/// comments and RON's `#![enable(…)]` lines); a file that opens with neither is read
/// as parameters, whose parser then names what it found.
pub fn file_kind(path: &Path) -> Result<RoverFile> {
    let text = crate::read_text(path).map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    let mut rest = text.as_str();
    loop {
        rest = rest.trim_start();
        if let Some(after) = rest.strip_prefix("//") {
            rest = after.split_once('\n').map_or("", |(_, r)| r);
        } else if let Some(after) = rest.strip_prefix("/*") {
            rest = after.split_once("*/").map_or("", |(_, r)| r);
        } else if rest.starts_with("#!") {
            rest = rest.split_once('\n').map_or("", |(_, r)| r);
        } else {
            break;
        }
    }
    let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
    Ok(if name == "ResourceModel" { RoverFile::Resources } else { RoverFile::Physics })
}

/// One driving condition of a resource model.
#[derive(Debug, Clone, Serialize)]
pub struct DriveFigures {
    /// What the row is: "flat", "up 10°", "down 10°", "up 20° (maximum)".
    pub ground: String,
    /// Slope, degrees (negative downhill).
    pub slope_deg: f64,
    /// Speed there (the model slows on slopes), m/s.
    pub speed_m_s: f64,
    /// Locomotion power m·g·v·(c_rr·cos θ + sin θ)/η, never below 0, W.
    pub locomotion_w: f64,
    /// Electronics while driving (the high level), W.
    pub electronics_w: f64,
    /// Drawn from the battery with no sunlight: load less the generator, W.
    pub battery_w: f64,
    /// Energy drawn from the battery per kilometre with no sunlight, Wh/km.
    pub wh_per_km: f64,
}

/// `areo rover check` on a TEMPEST resource model: what its numbers imply, to set
/// against an engineer's own.
#[derive(Debug, Clone, Serialize)]
pub struct ResourceReport {
    /// The model's name.
    pub rover: String,
    /// Gravity the locomotor works against, m/s².
    pub gravity_m_s2: f64,
    /// Whose gravity: "the file" or the body's name (the file gives none).
    pub gravity_from: String,
    /// Flat, the asked slope up and down, and the model's maximum slope up.
    pub drives: Vec<DriveFigures>,
    /// Array output per unit of beam irradiance at normal incidence (area ×
    /// efficiency), W per W/m²; 0 without an array.
    pub array_w_per_w_m2: f64,
    /// Generator output, W.
    pub nuclear_w: f64,
    /// Capacity, Wh.
    pub capacity_wh: f64,
    /// Stored energy between the state-of-charge limits, Wh.
    pub usable_wh: f64,
    /// What the usable energy delivers to the bus (× discharge efficiency), Wh.
    pub deliverable_wh: f64,
    /// Electronics at the low (hibernation), medium (idle, charging) and high levels, W.
    pub electronics_w: [f64; 3],
    /// Hours a full battery lasts hibernating / idle with no sunlight (∞ as `None`
    /// where the generator covers the load).
    pub hibernate_h: Option<f64>,
    /// Hours idle on a full battery with no sunlight.
    pub idle_h: Option<f64>,
    /// Kilometres on flat ground on a full battery with no sunlight.
    pub range_flat_km: Option<f64>,
}

/// Checks a resource model: drive power and energy per kilometre on flat ground, up
/// and down `terrain`'s slope and up the model's maximum, the array's output per unit
/// irradiance, and how long a full battery lasts. Only `flat` and `slope:DEG` apply.
/// A locomotor without `gravity_m_s2` gets `body`'s, as in a scenario on that body.
pub fn check_resources(path: &Path, terrain: TestTerrain, body: areo_ephemeris::Body) -> Result<ResourceReport> {
    let mut model = crate::format::rover_files::load_resources(path)?;
    let gravity_from = if model.locomotor.gravity_m_s2.is_some() { "the file" } else { body.iau_name() };
    model.locomotor.gravity_m_s2.get_or_insert(body.surface_gravity_m_s2());
    let slope = match terrain {
        TestTerrain::Flat => 0.0,
        TestTerrain::Slope(d) => d,
        other => {
            return Err(Error::usage(
                format!("--terrain {other}"),
                "a resource model is checked on flat or slope:DEG (its locomotor has no wheels to place on a side slope or a step)",
            ));
        }
    };
    let l = &model.locomotor;
    let high = model.electronics.power_w(areo_rover::resources::Load::High);
    let row = |ground: String, slope_deg: f64| {
        let speed = l.speed_on_slope_m_s(slope_deg);
        let locomotion = l.power_w(speed, slope_deg);
        let battery = (locomotion + high - model.nuclear_w).max(0.0);
        DriveFigures {
            ground,
            slope_deg,
            speed_m_s: speed,
            locomotion_w: locomotion,
            electronics_w: high,
            battery_w: battery,
            wh_per_km: battery / speed / 3.6,
        }
    };
    let mut drives = vec![row("flat".into(), 0.0)];
    if slope > 0.0 {
        if slope <= l.max_slope_deg {
            drives.push(row(format!("up {slope}°"), slope));
            drives.push(row(format!("down {slope}°"), -slope));
        } else {
            return Err(Error::usage(
                format!("--terrain slope:{slope}"),
                format!("steeper than the model's maximum slope ({}°): it does not drive there", l.max_slope_deg),
            ));
        }
    }
    drives.push(row(format!("up {}° (maximum)", l.max_slope_deg), l.max_slope_deg));
    let b = &model.battery;
    let usable_wh = b.usable_j() / 3600.0;
    let deliverable_wh = usable_wh * b.discharge_efficiency;
    let lasts = |load_w: f64| (load_w > model.nuclear_w).then(|| deliverable_wh / (load_w - model.nuclear_w));
    let e = &model.electronics;
    let flat = &drives[0];
    Ok(ResourceReport {
        rover: model.name.clone(),
        gravity_m_s2: l.gravity(),
        gravity_from: gravity_from.to_string(),
        array_w_per_w_m2: model.solar.map_or(0.0, |s| s.area_m2 * s.efficiency),
        nuclear_w: model.nuclear_w,
        capacity_wh: b.capacity_wh,
        usable_wh,
        deliverable_wh,
        electronics_w: [e.low_w, e.medium_w, e.high_w],
        hibernate_h: lasts(e.low_w),
        idle_h: lasts(e.medium_w),
        range_flat_km: (flat.battery_w > 0.0).then(|| deliverable_wh / flat.wh_per_km),
        drives,
    })
}

/// The report on either kind of rover file, as `areo rover check --format json` prints
/// it (untagged: the fields tell which).
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum Checked {
    /// An LSR-1-style parameter file on a test terrain.
    Physics(RoverCheckReport),
    /// A TEMPEST resource model.
    Resources(ResourceReport),
}

/// Checks the rover file at `path`, whichever kind it is ([`file_kind`]): parameters
/// with [`check`] (`terrain`, `mu`, `moving`), a resource model with
/// [`check_resources`] (`terrain`, `body`).
pub fn check_file(
    path: &Path,
    terrain: TestTerrain,
    mu: f64,
    moving: bool,
    body: areo_ephemeris::Body,
) -> Result<Checked> {
    match file_kind(path) {
        Ok(RoverFile::Resources) => check_resources(path, terrain, body).map(Checked::Resources),
        // An unreadable file too: `check` names it.
        _ => check(path, terrain, mu, moving).map(Checked::Physics),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn terrain_specs_parse_and_bad_ones_say_what_is_allowed() {
        assert_eq!("flat".parse::<TestTerrain>(), Ok(TestTerrain::Flat));
        assert_eq!("slope:20".parse::<TestTerrain>(), Ok(TestTerrain::Slope(20.0)));
        assert_eq!("side-slope:12.5".parse::<TestTerrain>(), Ok(TestTerrain::SideSlope(12.5)));
        assert_eq!("step:0.15".parse::<TestTerrain>(), Ok(TestTerrain::Step(0.15)));
        for bad in ["hill", "slope:95", "slope:x", "step:-1", "flat:3"] {
            let e = bad.parse::<TestTerrain>().unwrap_err();
            assert!(e.contains("allowed: flat"), "{bad}: {e}");
        }
    }

    fn lsr1() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../rover/params/lsr1.ron")
    }

    #[test]
    fn a_low_step_is_hardest_where_the_middle_wheel_meets_it_not_at_the_first_instant() {
        // An 8 cm step (below the 10 cm wheel radius): at the first instant the front
        // wheel can rest on the edge carrying nothing, so holding needs no friction;
        // lifting it onto the step loads the edge, and the middle wheel meets the step
        // when the reference point has come 0.4 m (the axle spacing) — that pose, with
        // the front wheel already up, is the one that needs the most.
        let report = check(&lsr1(), TestTerrain::Step(0.08), 0.8, false).unwrap();
        let climb = report.climb.expect("a step is climbed");
        assert!(climb.over, "{climb:?}");
        let first = report.mu_needed.expect("the first instant holds");
        let whole = climb.mu_needed.expect("the climb holds at some μ");
        assert!(first < 0.01 && whole > 0.3, "first instant {first}, climb {whole}");
        assert!((0.35..=0.45).contains(&climb.mu_needed_at_m), "{climb:?}");
        assert_eq!(climb.wheels_on_top_there, "front");
        // Below that μ the first instant still holds but the climb stops on slip.
        let short = check(&lsr1(), TestTerrain::Step(0.08), whole - 0.05, false).unwrap();
        assert_eq!(short.verdict, "ok");
        let c = short.climb.unwrap();
        assert!(!c.over && c.stop.as_deref() == Some("slip"), "{c:?}");
        // A vertical wall above the axle: the front wheel must be lifted by friction on
        // the wall at once, so the first instant is the hardest pose, and the climb
        // needs exactly what it needs.
        let wall = check(&lsr1(), TestTerrain::Step(0.2), 0.8, false).unwrap();
        let (first, c) = (wall.mu_needed.unwrap(), wall.climb.unwrap());
        assert!(c.over && (c.mu_needed.unwrap() - first).abs() < 2e-3, "{first} {c:?}");
        assert!(c.max_pitch_deg > 15.0 && c.min_stability_pct < 80.0, "{c:?}");
        // A step exactly one wheel radius high: the warm-started pose loses the edge at
        // 4 cm; the climb then solves cold and goes over.
        let edge = check(&lsr1(), TestTerrain::Step(0.1), 0.8, false).unwrap().climb.unwrap();
        assert!(edge.over && edge.poses == c.poses, "{edge:?}");
    }

    #[test]
    fn both_rocker_bogies_climb_a_step_one_and_a_half_wheels_high_and_not_two() {
        // The rocker-bogie's published reach: obstacles about 1.5 wheel diameters high
        // (Curiosity 75 cm on 50 cm wheels; shared/reference/rover_physics.md). With the
        // LSR-1's and the Sojourner-class file's geometry a step of 1.5 D is climbed
        // with μ ≤ 0.6 and one of 2 D is not (the bogie reaches its joint limit).
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../rover/params");
        for (file, d) in [("lsr1.ron", 0.20), ("sojourner.ron", 0.13)] {
            let path = dir.join(file);
            let up = check(&path, TestTerrain::Step(1.5 * d), 0.8, false).unwrap().climb.unwrap();
            assert!(up.over && up.mu_needed.is_some_and(|m| m < 0.6), "{file}: {up:?}");
            let not = check(&path, TestTerrain::Step(2.0 * d), 0.8, false).unwrap().climb.unwrap();
            assert!(!not.over && not.stop.as_deref() == Some("kinematics"), "{file}: {not:?}");
        }
    }

    #[test]
    fn a_bogie_behind_climbs_a_step_forward_worse_its_rear_wheel_meets_the_wall_on_the_bogie() {
        // The LSR-1 with its bogie turned behind (the MER/MSL layout) climbs a step of
        // 1.5 D forward only with μ ≈ 0.89, where the paper's layout needs < 0.6: the hard
        // pose is the rear wheel, on the bogie, against the wall with the front and
        // middle wheels on top; for any step taller than a wheel radius that first
        // contact is the same, so the μ it needs is too. A step under a radius is
        // climbed. The MER-class file (its wheels 1.42 D apart) needs μ ≈ 1.28 there at
        // 1 D; at 1.5 D its front wheel, on the rocker, finds no friction that holds.
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let turned = root.join("scenarios/rovers/lsr1-bogie-behind.ron");
        let mer = root.join("crates/rover/params/mer.ron");
        for (path, d, want, heights) in [(&turned, 0.20, 0.891, &[1.0, 1.5][..]), (&mer, 0.26, 1.279, &[1.0][..])] {
            for &k in heights {
                let c = check(path, TestTerrain::Step(k * d), 0.8, false).unwrap().climb.unwrap();
                assert!(!c.over && c.stop.as_deref() == Some("slip"), "{path:?} {k} D: {c:?}");
                assert!((c.mu_needed.unwrap() - want).abs() < 0.01, "{path:?} {k} D: {c:?}");
                assert_eq!(c.wheels_on_top_there, "front middle", "{path:?}");
            }
            let low = check(path, TestTerrain::Step(0.4 * d), 0.8, false).unwrap().climb.unwrap();
            assert!(low.over && low.mu_needed.is_some_and(|m| m < 0.6), "{path:?}: {low:?}");
        }
        let front = check(&root.join("crates/rover/params/lsr1.ron"), TestTerrain::Step(0.30), 0.8, false);
        assert!(front.unwrap().climb.unwrap().mu_needed.is_some_and(|m| m < 0.6));
    }
}
