//! LSR-1 parameters: the RON format, loading and validation.

use std::path::Path;

use serde::Deserialize;

use crate::error::{Error, Result, parse_ron, read_text};

// Physical ranges: finite, positive where a zero would divide, and bounded so that no
// product overflows (masses to 10 t, lengths to 100 m, powers to 1 MW, durations to
// 10⁷ s).
const LEN: f64 = 100.0;
const POWER: f64 = 1e6;
const DURATION: f64 = 1e7;

/// A parameter out of its range: the field, its value and what is allowed.
type Invalid = (&'static str, f64, String);

/// The shipped LSR-1 parameter file (see its comments for sources and assumptions).
pub const LSR1_RON: &str = include_str!("../params/lsr1.ron");

/// A point in the rover's side view (x forward, z up), m.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SidePoint {
    /// Forward, m.
    pub x: f64,
    /// Up, m.
    pub z: f64,
}

/// A parameter of a rover file that no source gives, varied by a sensitivity study
/// ([`RoverParams::with_assumed`]). Scenario files name them as written here.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
pub enum Assumed {
    /// `bogie_limit_deg`: the bogie joint's range either way, degrees.
    BogieLimitDeg,
    /// `rocker_limit_deg`: the rocker's range relative to the body, degrees.
    RockerLimitDeg,
    /// `cg_m.z`: the centre of mass's height above the ground, arm stowed, m.
    CgHeightM,
    /// `cg_m.x`: the centre of mass ahead of the middle axles, arm stowed, m.
    CgForwardM,
    /// `arm.mass_kg`: the arm's mass (part of the rover's), kg.
    ArmMassKg,
    /// `bogie_pivot_m.z`: the bogie pivot's height above the ground, m.
    BogiePivotHeightM,
}

impl Assumed {
    /// The parameter file's name for it.
    pub fn field(self) -> &'static str {
        match self {
            Assumed::BogieLimitDeg => "bogie_limit_deg",
            Assumed::RockerLimitDeg => "rocker_limit_deg",
            Assumed::CgHeightM => "cg_m.z",
            Assumed::CgForwardM => "cg_m.x",
            Assumed::ArmMassKg => "arm.mass_kg",
            Assumed::BogiePivotHeightM => "bogie_pivot_m.z",
        }
    }
}

/// A point in the body frame, m.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyPoint {
    /// Forward, m.
    pub x: f64,
    /// Left, m.
    pub y: f64,
    /// Up, m.
    pub z: f64,
}

/// Axle positions along the body x axis, m.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axles {
    /// Front axle, m.
    pub front: f64,
    /// Middle axle, m.
    pub middle: f64,
    /// Rear axle, m.
    pub rear: f64,
}

/// Motor and gearbox of each wheel.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Drive {
    /// Gear ratio (motor turns per wheel turn).
    pub gear_ratio: f64,
    /// Gearbox efficiency, 0..=1.
    pub gear_efficiency: f64,
    /// Motor torque constant, N·m/A.
    pub torque_constant_nm_per_a: f64,
    /// Winding resistance, Ω.
    pub winding_resistance_ohm: f64,
    /// Bus voltage, V.
    pub bus_voltage_v: f64,
}

impl Drive {
    /// Wheel torque at stall, N·m: K_t·(V/R)·N·η.
    pub fn stall_torque_nm(&self) -> f64 {
        self.torque_constant_nm_per_a * self.bus_voltage_v / self.winding_resistance_ohm
            * self.gear_ratio
            * self.gear_efficiency
    }

    /// The copper-loss weight k of Σ k τ² (eq. 16): R/(K_t·N·η)², W/(N·m)².
    pub fn copper_loss_w_per_nm2(&self) -> f64 {
        self.winding_resistance_ohm / (self.torque_constant_nm_per_a * self.gear_ratio * self.gear_efficiency).powi(2)
    }
}

/// The manipulator arm.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Arm {
    /// Shoulder position, body frame, m.
    pub shoulder_m: BodyPoint,
    /// Shoulder-to-elbow length, m.
    pub upper_link_m: f64,
    /// Elbow-to-wrist length, m.
    pub lower_link_m: f64,
    /// Arm mass, kg.
    pub mass_kg: f64,
    /// Largest payload, kg.
    pub payload_max_kg: f64,
    /// Wrist (tool) position when stowed, body frame, m.
    pub stowed_tool_m: BodyPoint,
    /// Tool speed for arm moves, m/s.
    pub tool_speed_m_s: f64,
    /// Joint drive efficiency, 0..=1.
    pub efficiency: f64,
}

/// Durations (s) and electrical loads beyond hotel power (W) of the non-driving action
/// modules.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Activities {
    /// Grasp or release a sample, s.
    pub grasp_s: f64,
    /// Gripper load, W.
    pub grasp_w: f64,
    /// Deploy or retract the science tray, s.
    pub tray_s: f64,
    /// Tray actuator load, W.
    pub tray_w: f64,
    /// Start or end video, s.
    pub video_s: f64,
    /// Camera load, W.
    pub video_w: f64,
    /// Sweep the sensors, s.
    pub sweep_s: f64,
    /// Sensor load, W.
    pub sweep_w: f64,
    /// Communicate with the ground station, s.
    pub communicate_s: f64,
    /// Radio load, W.
    pub communicate_w: f64,
    /// Sleep, s.
    pub sleep_s: f64,
    /// Total draw while asleep (replaces hotel power), W.
    pub sleep_w: f64,
    /// Recharge from the solar array, s.
    pub recharge_s: f64,
    /// Turn to (or from) a sample: the heading change, degrees.
    pub turn_to_sample_deg: f64,
    /// Solar flux on the array while recharging, W/m².
    pub recharge_flux_w_m2: f64,
}

/// The solar array.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Solar {
    /// Active area, m².
    pub area_m2: f64,
    /// Cell efficiency, 0..=1.
    pub efficiency: f64,
}

/// LSR-1's battery pack: its size and the share of it a plan may use (the TEMPEST
/// rovers' state-of-charge model is [`crate::resources::Battery`]).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BatteryPack {
    /// Capacity, Wh.
    pub capacity_wh: f64,
    /// Usable fraction of the capacity, 0..=1.
    pub usable_fraction: f64,
}

/// Every LSR-1 parameter. Units are in the field names; angles are degrees only here,
/// at the file edge.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoverParams {
    /// A name for reports.
    pub name: String,
    /// Wheel radius, m.
    pub wheel_radius_m: f64,
    /// Wheel width, m.
    pub wheel_width_m: f64,
    /// Distance between the left and right wheel mid-planes, m.
    pub track_m: f64,
    /// Axle positions, m.
    pub axle_x_m: Axles,
    /// Bogie pivot, side view, m.
    pub bogie_pivot_m: SidePoint,
    /// Rocker (body/differential) pivot, side view, m.
    pub rocker_pivot_m: SidePoint,
    /// Bogie joint range, ± degrees.
    pub bogie_limit_deg: f64,
    /// Rocker joint range relative to the body, ± degrees.
    pub rocker_limit_deg: f64,
    /// Total mass, kg.
    pub mass_kg: f64,
    /// Centre of mass (arm stowed), body frame, m.
    pub cg_m: BodyPoint,
    /// Wheel torque limit, N·m (at the wheel).
    pub wheel_torque_max_nm: f64,
    /// Motor and gearbox.
    pub drive: Drive,
    /// Electronics (hotel) power, W.
    pub hotel_power_w: f64,
    /// The arm.
    pub arm: Arm,
    /// The solar array.
    pub solar: Solar,
    /// The battery.
    pub battery: BatteryPack,
    /// Gravity, m/s².
    pub gravity_m_s2: f64,
    /// Driving speed, m/s.
    pub speed_m_s: f64,
    /// Rolling-resistance coefficient c_rr.
    pub rolling_resistance: f64,
    /// Point-turn rate, degrees per second.
    pub turn_rate_deg_s: f64,
    /// The non-driving modules.
    pub activities: Activities,
}

impl RoverParams {
    /// The shipped LSR-1 parameters.
    pub fn lsr1() -> RoverParams {
        // The shipped file is checked by the tests; failing here is a build defect.
        RoverParams::parse(LSR1_RON, "params/lsr1.ron").expect("the shipped LSR-1 parameters are valid")
    }

    /// These parameters with `which` set to `value`, validated as a file would be (the
    /// error names the field and what is allowed).
    pub fn with_assumed(&self, which: Assumed, value: f64) -> Result<RoverParams> {
        let mut p = self.clone();
        match which {
            Assumed::BogieLimitDeg => p.bogie_limit_deg = value,
            Assumed::RockerLimitDeg => p.rocker_limit_deg = value,
            Assumed::CgHeightM => p.cg_m.z = value,
            Assumed::CgForwardM => p.cg_m.x = value,
            Assumed::ArmMassKg => p.arm.mass_kg = value,
            Assumed::BogiePivotHeightM => p.bogie_pivot_m.z = value,
        }
        p.validate(&format!("{} with {} = {value}", self.name, which.field()))?;
        Ok(p)
    }

    /// Reads and validates a parameter file.
    pub fn load(path: &Path) -> Result<RoverParams> {
        RoverParams::parse(&read_text(path)?, &path.display().to_string())
    }

    /// Parses and validates parameter text; `origin` labels errors.
    pub fn parse(text: &str, origin: &str) -> Result<RoverParams> {
        let params: RoverParams = parse_ron(text, origin)?;
        params.validate(origin)?;
        Ok(params)
    }

    /// Checks ranges and that the geometry can be built.
    pub fn validate(&self, origin: &str) -> Result<()> {
        self.check_magnitudes()
            .and_then(|()| self.check_bounds())
            .and_then(|()| self.check_geometry())
            .map_err(|(field, value, why)| Error::Invalid { origin: origin.into(), field, value, why })
    }

    /// The quantities that must be positive (a zero would divide) and bounded, and the
    /// efficiencies and fractions in (0, 1].
    fn check_magnitudes(&self) -> std::result::Result<(), Invalid> {
        let fail = |field: &'static str, value: f64, why: String| Err((field, value, why));
        let positive: [(&'static str, f64, f64); 18] = [
            ("arm.tool_speed_m_s", self.arm.tool_speed_m_s, 10.0),
            ("turn_rate_deg_s", self.turn_rate_deg_s, 360.0),
            ("activities.turn_to_sample_deg", self.activities.turn_to_sample_deg, 360.0),
            ("activities.sleep_s", self.activities.sleep_s, DURATION),
            ("wheel_radius_m", self.wheel_radius_m, 10.0),
            ("wheel_width_m", self.wheel_width_m, 10.0),
            ("track_m", self.track_m, LEN),
            ("mass_kg", self.mass_kg, 1e4),
            ("wheel_torque_max_nm", self.wheel_torque_max_nm, 1e6),
            ("drive.gear_ratio", self.drive.gear_ratio, 1e6),
            ("drive.torque_constant_nm_per_a", self.drive.torque_constant_nm_per_a, 1e3),
            ("drive.winding_resistance_ohm", self.drive.winding_resistance_ohm, 1e6),
            ("drive.bus_voltage_v", self.drive.bus_voltage_v, 1e5),
            ("arm.upper_link_m", self.arm.upper_link_m, LEN),
            ("arm.lower_link_m", self.arm.lower_link_m, LEN),
            ("battery.capacity_wh", self.battery.capacity_wh, 1e7),
            ("gravity_m_s2", self.gravity_m_s2, 100.0),
            ("speed_m_s", self.speed_m_s, 100.0),
        ];
        for (field, v, hi) in positive {
            if !(v > 0.0 && v <= hi) {
                return fail(field, v, format!("allowed 0 (exclusive)..={hi}"));
            }
        }
        if !(self.mass_kg >= 1e-3) {
            return fail("mass_kg", self.mass_kg, "allowed 0.001..=10000 kg".into());
        }
        let fractions: [(&'static str, f64); 4] = [
            ("arm.efficiency", self.arm.efficiency),
            ("drive.gear_efficiency", self.drive.gear_efficiency),
            ("solar.efficiency", self.solar.efficiency),
            ("battery.usable_fraction", self.battery.usable_fraction),
        ];
        for (field, v) in fractions {
            if !(v > 0.0 && v <= 1.0) {
                return fail(field, v, "allowed 0 (exclusive)..=1".into());
            }
        }
        Ok(())
    }

    /// The quantities that may be zero, every point of the geometry within 100 m of the
    /// body origin, and the joint limits.
    fn check_bounds(&self) -> std::result::Result<(), Invalid> {
        let fail = |field: &'static str, value: f64, why: String| Err((field, value, why));
        for (field, v, hi) in [
            ("hotel_power_w", self.hotel_power_w, POWER),
            ("arm.mass_kg", self.arm.mass_kg, 1e4),
            ("arm.payload_max_kg", self.arm.payload_max_kg, 1e4),
            ("solar.area_m2", self.solar.area_m2, 1e4),
            ("rolling_resistance", self.rolling_resistance, 1.0),
            ("activities.grasp_s", self.activities.grasp_s, DURATION),
            ("activities.grasp_w", self.activities.grasp_w, POWER),
            ("activities.tray_s", self.activities.tray_s, DURATION),
            ("activities.tray_w", self.activities.tray_w, POWER),
            ("activities.video_s", self.activities.video_s, DURATION),
            ("activities.video_w", self.activities.video_w, POWER),
            ("activities.sweep_s", self.activities.sweep_s, DURATION),
            ("activities.sweep_w", self.activities.sweep_w, POWER),
            ("activities.communicate_s", self.activities.communicate_s, DURATION),
            ("activities.communicate_w", self.activities.communicate_w, POWER),
            ("activities.sleep_w", self.activities.sleep_w, POWER),
            ("activities.recharge_s", self.activities.recharge_s, DURATION),
            ("activities.recharge_flux_w_m2", self.activities.recharge_flux_w_m2, 1e5),
        ] {
            if !(v >= 0.0 && v <= hi) {
                return fail(field, v, format!("allowed 0..={hi}"));
            }
        }
        // Every point of the geometry within 100 m of the body origin.
        for (field, v) in [
            ("axle_x_m.front", self.axle_x_m.front),
            ("axle_x_m.middle", self.axle_x_m.middle),
            ("axle_x_m.rear", self.axle_x_m.rear),
            ("bogie_pivot_m.x", self.bogie_pivot_m.x),
            ("bogie_pivot_m.z", self.bogie_pivot_m.z),
            ("rocker_pivot_m.x", self.rocker_pivot_m.x),
            ("rocker_pivot_m.z", self.rocker_pivot_m.z),
            ("cg_m.x", self.cg_m.x),
            ("cg_m.y", self.cg_m.y),
            ("cg_m.z", self.cg_m.z),
            ("arm.shoulder_m.x", self.arm.shoulder_m.x),
            ("arm.shoulder_m.y", self.arm.shoulder_m.y),
            ("arm.shoulder_m.z", self.arm.shoulder_m.z),
            ("arm.stowed_tool_m.x", self.arm.stowed_tool_m.x),
            ("arm.stowed_tool_m.y", self.arm.stowed_tool_m.y),
            ("arm.stowed_tool_m.z", self.arm.stowed_tool_m.z),
        ] {
            if !(v.abs() <= LEN) {
                return fail(field, v, format!("allowed -{LEN}..={LEN} m"));
            }
        }
        for (field, v) in [("bogie_limit_deg", self.bogie_limit_deg), ("rocker_limit_deg", self.rocker_limit_deg)] {
            if !(v > 0.0 && v < 90.0) {
                return fail(field, v, "allowed 0..90 degrees".into());
            }
        }
        Ok(())
    }

    /// The geometry: axles in order and apart, pivots where a rocker-bogie has them, the
    /// centre of mass over the footprint, a stowed arm, a drive that delivers its torque.
    fn check_geometry(&self) -> std::result::Result<(), Invalid> {
        let fail = |field: &'static str, value: f64, why: String| Err((field, value, why));
        // Geometry.
        let (a, r) = (self.axle_x_m, self.wheel_radius_m);
        if !(a.front > a.middle && a.middle > a.rear) {
            return fail("axle_x_m.middle", a.middle, "axles must run front > middle > rear".into());
        }
        if a.front - a.middle < 2.0 * r || a.middle - a.rear < 2.0 * r {
            return fail(
                "axle_x_m",
                a.front - a.rear,
                format!("wheels of radius {r} m overlap: axles must be ≥ 2r apart"),
            );
        }
        let (p, b) = (self.bogie_pivot_m, self.rocker_pivot_m);
        if !((p.x > a.middle && p.x < a.front) || (p.x > a.rear && p.x < a.middle)) {
            return fail(
                "bogie_pivot_m.x",
                p.x,
                "must lie between the middle and front axles (bogie in front, as on LSR-1 and Sojourner) \
                 or between the rear and middle axles (bogie behind, as on MER and MSL)"
                    .into(),
            );
        }
        if !(p.z > r) {
            return fail("bogie_pivot_m.z", p.z, format!("must be above the axles (z > r = {r})"));
        }
        match self.layout() {
            Layout::BogieFront if !(b.x > a.rear && b.x < p.x) => {
                return fail("rocker_pivot_m.x", b.x, "must lie between the rear axle and the bogie pivot".into());
            }
            Layout::BogieRear if !(b.x > p.x && b.x < a.front) => {
                return fail("rocker_pivot_m.x", b.x, "must lie between the bogie pivot and the front axle".into());
            }
            _ => {}
        }
        if !(b.z > p.z) {
            return fail("rocker_pivot_m.z", b.z, "must be above the bogie pivot".into());
        }
        if !(self.track_m > self.wheel_width_m) {
            return fail("track_m", self.track_m, "must exceed the wheel width".into());
        }
        if !(self.cg_m.x.abs() < (a.front - a.rear) / 2.0
            && self.cg_m.y.abs() < self.track_m / 2.0
            && self.cg_m.z > 0.0)
        {
            return fail("cg_m.x", self.cg_m.x, "the centre of mass must lie above the wheels' footprint".into());
        }
        if !(self.rolling_resistance < 1.0) {
            return fail("rolling_resistance", self.rolling_resistance, "allowed 0..1".into());
        }
        if let Err(why) = crate::arm::ArmState::stowed(self).check(self) {
            return fail("arm.stowed_tool_m.x", self.arm.stowed_tool_m.x, why);
        }
        if self.arm.payload_max_kg > self.mass_kg {
            return fail("arm.payload_max_kg", self.arm.payload_max_kg, "exceeds the rover's mass".into());
        }
        // The drive must deliver the torque limit it claims.
        let stall = self.drive.stall_torque_nm();
        if self.wheel_torque_max_nm > stall * 1.0001 {
            return fail(
                "wheel_torque_max_nm",
                self.wheel_torque_max_nm,
                format!("exceeds the drive's stall torque K_t·(V/R)·N·η = {stall:.3} N·m"),
            );
        }
        Ok(())
    }

    /// The rocker-bogie geometry in the paper's loop-closure form.
    pub fn geometry(&self) -> Geometry {
        Geometry::of(self)
    }

    /// Which pair of wheels rides the bogie: the front and middle ones (LSR-1, Sojourner)
    /// when the bogie pivot is ahead of the middle axles, else the middle and rear ones
    /// (MER, MSL).
    pub fn layout(&self) -> Layout {
        if self.bogie_pivot_m.x > self.axle_x_m.middle { Layout::BogieFront } else { Layout::BogieRear }
    }
}

/// Where a rocker-bogie's bogie sits. The two layouts are one mechanism turned end for
/// end: a bogie-behind rover driving forward is the mirror image of a bogie-in-front
/// rover driving backward, which is how [`crate::kinematics`] and
/// [`crate::evaluation`] solve it (the results come back in the rover's own frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// The bogie carries the front and middle wheels, the rocker the rear ones (the
    /// paper's LSR-1; Sojourner).
    BogieFront,
    /// The bogie carries the middle and rear wheels, the rocker the front ones (MER,
    /// MSL, Mars 2020).
    BogieRear,
}

/// The side-view rocker-bogie geometry in Farritor et al.'s form (their eqs. 2–7):
/// l3, l4 place the middle axle relative to the front one in the frame of the bogie
/// line (front axle → bogie pivot, angle α2 above the rearward horizontal); l1, l2 place
/// the rear axle relative to the bogie pivot in the frame of the rocker line (bogie
/// pivot → rocker pivot, angle α1). Lengths in m, angles in radians. On a bogie-behind rover (MER)
/// the same names describe the mirror image: "front" is the rear wheel, at the bogie's free
/// end, and "rear" the front wheel, on the rocker.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// Rocker loop-closure lengths, m.
    pub l1: f64,
    /// Rocker loop-closure lengths, m.
    pub l2: f64,
    /// Bogie loop-closure lengths, m.
    pub l3: f64,
    /// Bogie loop-closure lengths, m.
    pub l4: f64,
    /// Nominal rocker angle on flat ground, rad.
    pub alpha1_0: f64,
    /// Nominal bogie angle on flat ground, rad.
    pub alpha2_0: f64,
    /// Bogie arms |PF|, |PM|, m.
    pub bogie_arms_m: (f64, f64),
    /// Angle between the bogie arms at the pivot, rad.
    pub bogie_included: f64,
    /// Rocker arms |BP|, |BR|, m.
    pub rocker_arms_m: (f64, f64),
}

impl Geometry {
    fn of(p: &RoverParams) -> Geometry {
        let r = p.wheel_radius_m;
        // Side view with s running from the bogie's end to the rocker's end (s = −x on
        // the paper's rover; a bogie-behind rover is its mirror image, s = x): "front"
        // below is the wheel at the bogie's free end.
        let (k, a) = match p.layout() {
            Layout::BogieFront => (-1.0, p.axle_x_m),
            Layout::BogieRear => {
                (1.0, Axles { front: p.axle_x_m.rear, middle: p.axle_x_m.middle, rear: p.axle_x_m.front })
            }
        };
        let f = (k * a.front, r);
        let m = (k * a.middle, r);
        let rear = (k * a.rear, r);
        let piv = (k * p.bogie_pivot_m.x, p.bogie_pivot_m.z);
        let b = (k * p.rocker_pivot_m.x, p.rocker_pivot_m.z);
        let sub = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0, a.1 - b.1);
        let dot = |a: (f64, f64), b: (f64, f64)| a.0 * b.0 + a.1 * b.1;
        let norm = |a: (f64, f64)| a.0.hypot(a.1);
        let fp = sub(piv, f);
        let alpha2_0 = fp.1.atan2(fp.0);
        let (u2, v2) = ((alpha2_0.cos(), alpha2_0.sin()), (-alpha2_0.sin(), alpha2_0.cos()));
        let fm = sub(m, f);
        let pb = sub(b, piv);
        let alpha1_0 = pb.1.atan2(pb.0);
        let (u1, v1) = ((alpha1_0.cos(), alpha1_0.sin()), (-alpha1_0.sin(), alpha1_0.cos()));
        let pr = sub(rear, piv);
        let (pf, pm) = (sub(f, piv), sub(m, piv));
        Geometry {
            l1: dot(pr, u1),
            l2: -dot(pr, v1),
            l3: dot(fm, u2),
            l4: -dot(fm, v2),
            alpha1_0,
            alpha2_0,
            bogie_arms_m: (norm(pf), norm(pm)),
            bogie_included: (dot(pf, pm) / (norm(pf) * norm(pm))).clamp(-1.0, 1.0).acos(),
            rocker_arms_m: (norm(sub(piv, b)), norm(sub(rear, b))),
        }
    }
}
