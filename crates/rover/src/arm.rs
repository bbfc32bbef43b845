//! The manipulator arm: where its tool is, what it holds, and how that moves the
//! rover's centre of mass (task 2 of Farritor et al. depends on it: reaching forward
//! keeps the rover from tipping backward on a steep hill).
//!
//! The arm is a shoulder yaw, shoulder pitch, elbow pitch and a wrist that keeps the
//! gripper pointing down, so the tool position (body frame) fixes the joints: yaw
//! toward the tool, then a two-link elbow-up solution in the vertical plane. Links are
//! uniform rods; the sample hangs at the tool.

use nalgebra::Vector3;

use crate::params::RoverParams;

/// The arm's configuration and load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmState {
    /// Tool (wrist) position, body frame (x forward, y left, z up from the ground under
    /// the middle axles), m.
    pub tool_m: [f64; 3],
    /// Mass of the sample held, kg (0 when empty).
    pub payload_kg: f64,
}

/// The arm's joint angles for a tool position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Joints {
    /// Shoulder yaw, rad (left positive).
    pub yaw: f64,
    /// Shoulder pitch above the horizontal, rad.
    pub shoulder: f64,
    /// Elbow angle between the links (π = straight), rad.
    pub elbow: f64,
}

impl ArmState {
    /// The stowed, empty arm of `params`.
    pub fn stowed(params: &RoverParams) -> ArmState {
        let t = params.arm.stowed_tool_m;
        ArmState { tool_m: t.into(), payload_kg: 0.0 }
    }

    /// The joint angles, or why the tool position is out of reach.
    pub fn joints(&self, params: &RoverParams) -> Result<Joints, String> {
        let a = &params.arm;
        let s = a.shoulder_m;
        let (dx, dy, dz) = (self.tool_m[0] - s.x, self.tool_m[1] - s.y, self.tool_m[2] - s.z);
        let rho = dx.hypot(dy);
        let d = rho.hypot(dz);
        let (l1, l2) = (a.upper_link_m, a.lower_link_m);
        // A margin keeps the elbow off its singular straight and folded positions.
        let (near, far) = ((l1 - l2).abs() + 0.01, l1 + l2 - 0.001);
        if !(near..=far).contains(&d) {
            return Err(format!("tool {d:.3} m from the shoulder: reachable {near:.3}..={far:.3} m"));
        }
        let yaw = if rho > 1e-9 { dy.atan2(dx) } else { 0.0 };
        let cos_inner = ((l1 * l1 + d * d - l2 * l2) / (2.0 * l1 * d)).clamp(-1.0, 1.0);
        let shoulder = dz.atan2(rho) + cos_inner.acos();
        let cos_elbow = ((l1 * l1 + l2 * l2 - d * d) / (2.0 * l1 * l2)).clamp(-1.0, 1.0);
        Ok(Joints { yaw, shoulder, elbow: cos_elbow.acos() })
    }

    /// Checks reach, payload and that the tool stays above the ground plane.
    pub fn check(&self, params: &RoverParams) -> Result<(), String> {
        self.joints(params)?;
        if self.tool_m[2] < 0.0 {
            return Err(format!("tool {:.3} m below the ground plane", -self.tool_m[2]));
        }
        if !(self.payload_kg >= 0.0 && self.payload_kg <= params.arm.payload_max_kg) {
            return Err(format!("payload {} kg: allowed 0..={} kg", self.payload_kg, params.arm.payload_max_kg));
        }
        Ok(())
    }

    /// The arm's own centre of mass (links only), body frame, m.
    pub fn arm_cg(&self, params: &RoverParams) -> Result<Vector3<f64>, String> {
        let j = self.joints(params)?;
        let a = &params.arm;
        let s = Vector3::from(a.shoulder_m);
        let (sy, cy) = j.yaw.sin_cos();
        let dir = |pitch: f64| Vector3::new(pitch.cos() * cy, pitch.cos() * sy, pitch.sin());
        let elbow = s + dir(j.shoulder) * a.upper_link_m;
        let tool = Vector3::from(self.tool_m);
        let (m1, m2) = (a.upper_link_m, a.lower_link_m);
        Ok(((s + elbow) * 0.5 * m1 + (elbow + tool) * 0.5 * m2) / (m1 + m2))
    }

    /// The whole rover's mass (kg) and centre of mass (body frame, m): the parameter
    /// file's CG is with the arm stowed and empty.
    pub fn system_mass_cg(&self, params: &RoverParams) -> Result<(f64, Vector3<f64>), String> {
        self.system_mass_cg_from(params, ArmState::stowed(params).arm_cg(params)?)
    }

    /// [`ArmState::system_mass_cg`] given the stowed arm's CG (body frame, m), which
    /// callers evaluating many poses compute once.
    pub fn system_mass_cg_from(
        &self,
        params: &RoverParams,
        stowed: Vector3<f64>,
    ) -> Result<(f64, Vector3<f64>), String> {
        // Most poses of a plan are driven with the arm stowed: no arm solve then.
        let t = params.arm.stowed_tool_m;
        let now = if self.tool_m == <[f64; 3]>::from(t) { stowed } else { self.arm_cg(params)? };
        let c = params.cg_m;
        let base = Vector3::from(c) + (now - stowed) * (params.arm.mass_kg / params.mass_kg);
        let total = params.mass_kg + self.payload_kg;
        Ok((total, (base * params.mass_kg + Vector3::from(self.tool_m) * self.payload_kg) / total))
    }

    /// The tool position (body frame, m) of joint angles `j`: forward kinematics, the
    /// inverse of [`ArmState::joints`].
    pub fn tool_of(joints: &Joints, params: &RoverParams) -> [f64; 3] {
        let a = &params.arm;
        let far = joints.shoulder - (std::f64::consts::PI - joints.elbow);
        let horizontal = a.upper_link_m * joints.shoulder.cos() + a.lower_link_m * far.cos();
        let (sy, cy) = joints.yaw.sin_cos();
        [
            a.shoulder_m.x + horizontal * cy,
            a.shoulder_m.y + horizontal * sy,
            a.shoulder_m.z + a.upper_link_m * joints.shoulder.sin() + a.lower_link_m * far.sin(),
        ]
    }

    /// The arm a fraction `f` (0..1) of the way to `target` in joint space (each joint
    /// turning at a steady rate, as an arm moves between poses; a straight line of
    /// the tool may pass through the shoulder), checked.
    pub fn toward(&self, target: &ArmState, f: f64, params: &RoverParams) -> Result<ArmState, String> {
        let (a, b) = (self.joints(params)?, target.joints(params)?);
        let mix = |x: f64, y: f64| x + (y - x) * f;
        let j = Joints { yaw: mix(a.yaw, b.yaw), shoulder: mix(a.shoulder, b.shoulder), elbow: mix(a.elbow, b.elbow) };
        let next = ArmState { tool_m: if f >= 1.0 { target.tool_m } else { ArmState::tool_of(&j, params) }, ..*self };
        next.check(params)?;
        Ok(next)
    }

    /// The tool moved by `delta` (m, body frame), checked.
    pub fn moved(&self, delta: [f64; 3], params: &RoverParams) -> Result<ArmState, String> {
        let next = ArmState {
            tool_m: [self.tool_m[0] + delta[0], self.tool_m[1] + delta[1], self.tool_m[2] + delta[2]],
            ..*self
        };
        next.check(params)?;
        Ok(next)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joints_reproduce_the_tool_position() {
        let p = RoverParams::lsr1();
        for tool in [[0.6, 0.1, 0.3], [0.15, 0.0, 0.55], [0.5, -0.2, 0.05], [0.84, 0.0, 0.42]] {
            let arm = ArmState { tool_m: tool, payload_kg: 0.0 };
            let j = arm.joints(&p).unwrap();
            let a = &p.arm;
            let (sy, cy) = j.yaw.sin_cos();
            let far = j.shoulder - (std::f64::consts::PI - j.elbow);
            let reach = |pitch: f64, l: f64| (l * pitch.cos(), l * pitch.sin());
            let (h1, v1) = reach(j.shoulder, a.upper_link_m);
            let (h2, v2) = reach(far, a.lower_link_m);
            let got = [a.shoulder_m.x + (h1 + h2) * cy, a.shoulder_m.y + (h1 + h2) * sy, a.shoulder_m.z + v1 + v2];
            let fk = ArmState::tool_of(&j, &p);
            for k in 0..3 {
                assert!((got[k] - tool[k]).abs() < 1e-9, "{tool:?} → {got:?}");
                assert!((fk[k] - tool[k]).abs() < 1e-9, "forward kinematics {fk:?}");
            }
        }
        assert!(ArmState { tool_m: [1.5, 0.0, 0.4], payload_kg: 0.0 }.check(&p).is_err());
        assert!(ArmState { tool_m: [0.6, 0.0, 0.3], payload_kg: 0.5 }.check(&p).is_err(), "over the payload limit");
    }

    #[test]
    fn reaching_forward_and_grasping_move_the_cg_forward() {
        let p = RoverParams::lsr1();
        let stowed = ArmState::stowed(&p);
        let (m0, g0) = stowed.system_mass_cg(&p).unwrap();
        assert!((m0 - 7.0).abs() < 1e-12 && (g0.x - p.cg_m.x).abs() < 1e-12 && (g0.z - p.cg_m.z).abs() < 1e-12);
        // Fully forward, horizontal: the links' CG is at shoulder + 0.5·(0.30² + 0.25²
        // + 2·0.30·0.25)/0.55 ... i.e. (0.30·0.15 + 0.25·(0.30 + 0.125))/0.55 ahead.
        let forward = ArmState { tool_m: [0.30 + 0.549, 0.0, 0.42], payload_kg: 0.0 };
        let arm = forward.arm_cg(&p).unwrap();
        let want = 0.30 + (0.30 * 0.15 + 0.25 * (0.30 + 0.1245)) / 0.55;
        assert!((arm.x - want).abs() < 2e-3, "{} vs {want}", arm.x);
        let (_, g1) = forward.system_mass_cg(&p).unwrap();
        let stowed_arm = stowed.arm_cg(&p).unwrap();
        assert!((g1.x - (arm.x - stowed_arm.x) / 7.0).abs() < 1e-12);
        // A 0.2 kg sample at the tool moves it further.
        let (m2, g2) = ArmState { payload_kg: 0.2, ..forward }.system_mass_cg(&p).unwrap();
        assert!((m2 - 7.2).abs() < 1e-12);
        assert!((g2.x - (g1.x * 7.0 + 0.849 * 0.2) / 7.2).abs() < 1e-12);
    }
}
