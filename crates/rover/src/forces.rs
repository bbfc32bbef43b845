//! Quasi-static forces on one side of the rocker-bogie (the paper's eqs. 8–16 in the
//! planar form of the reference, §4.1): per wheel a normal force N_i and a tractive
//! force T_i, in equilibrium with the load the body puts on the side's rocker pivot (a
//! vertical force and a pitching couple, see [`crate::evaluation`] for the 3-D split),
//! with the wheel torques chosen to minimise Σ k τ² (copper losses, eq. 16) subject to
//! N_i ≥ N_min, |T_i| ≤ μ N_i and |τ_i| ≤ τ_max.
//!
//! Rolling resistance c_rr acts as a resisting moment at each wheel, so the motor torque
//! is τ_i = r (T_i + σ c_rr N_i) with σ the direction of travel (0 when holding still).
//!
//! Solved exactly and without allocation: fixing T_f and T_m, the four equilibrium
//! equations give the other four forces, so every equilibrium is x = x_p + Z s with
//! s ∈ ℝ². The 15 limits are half-planes in s and the objective a convex quadratic, so
//! the optimum is the unconstrained minimiser if feasible, else on the boundary: for
//! each constraint line, the feasible interval left by the others, and the 1-D
//! minimiser clamped to it.

use nalgebra::{Matrix2, Matrix4, SMatrix, SVector, Vector2, Vector4};

/// One side's contact geometry and load, in the side's (s forward, z up) plane, m, rad
/// and N.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SideContacts {
    /// Axle centres: front, middle, rear.
    pub axles: [(f64, f64); 3],
    /// (sin γ_i, cos γ_i) of the contact angles γ_i (positive when the terrain rises
    /// ahead): the contact normals in the side's plane.
    pub gamma_sin_cos: [(f64, f64); 3],
    /// Bogie pivot.
    pub bogie_pivot: (f64, f64),
    /// Rocker (body) pivot, where the load acts.
    pub rocker_pivot: (f64, f64),
    /// Downward force the body puts on the rocker pivot, N.
    pub load_n: f64,
    /// Pitching couple the body puts on the rocker, N·m (nose up positive).
    pub couple_nm: f64,
    /// Wheel radius, m.
    pub wheel_radius_m: f64,
}

impl SideContacts {
    /// The load of a weight `weight_n` (N) hanging at `cg`, carried by this side alone
    /// (the planar case): force at the pivot plus the couple of its lever.
    pub fn carry_weight_at(&mut self, weight_n: f64, cg: (f64, f64)) {
        self.load_n = weight_n;
        self.couple_nm = -weight_n * (cg.0 - self.rocker_pivot.0);
    }
}

/// Limits of the optimisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Friction coefficient μ.
    pub mu: f64,
    /// Wheel torque limit, N·m.
    pub torque_max_nm: f64,
    /// Smallest normal force that counts as contact, N.
    pub n_min: f64,
    /// Rolling-resistance coefficient c_rr.
    pub rolling_resistance: f64,
    /// Direction of travel σ: +1 forward, −1 backward, 0 holding still.
    pub direction: f64,
}

impl Limits {
    /// Holding still (no rolling resistance) with friction `mu` and no torque limit.
    pub fn static_friction(mu: f64) -> Limits {
        Limits { mu, torque_max_nm: f64::INFINITY, n_min: 0.0, rolling_resistance: 0.0, direction: 0.0 }
    }
}

/// The solved forces, front, middle, rear.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SideForces {
    /// Normal forces, N.
    pub normal_n: [f64; 3],
    /// Tractive forces, N.
    pub traction_n: [f64; 3],
    /// Motor torques at the wheels, N·m.
    pub torque_nm: [f64; 3],
    /// Σ τ² (multiply by k for watts of copper loss), N²·m².
    pub sum_torque_sq: f64,
    /// Largest |T_i|/N_i: the friction the configuration uses.
    pub friction_used: f64,
}

impl SideForces {
    /// The same forces described for the rover turned end for end: front and rear
    /// swap, tractive forces and torques (signed along the direction of travel) change
    /// sign.
    pub fn mirrored(&self) -> SideForces {
        let turn = |a: [f64; 3], k: f64| [k * a[2], k * a[1], k * a[0]];
        SideForces {
            normal_n: turn(self.normal_n, 1.0),
            traction_n: turn(self.traction_n, -1.0),
            torque_nm: turn(self.torque_nm, -1.0),
            ..*self
        }
    }
}

/// Why no admissible forces exist.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum ForceFailure {
    /// Equilibrium needs more friction than μ gives.
    Slip,
    /// Equilibrium needs a negative normal force (a wheel lifts off).
    LossOfContact,
    /// Equilibrium needs more torque than the motors give.
    Saturation,
}

impl std::fmt::Display for ForceFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ForceFailure::Slip => "slip: equilibrium needs more friction than μ",
            ForceFailure::LossOfContact => "loss of contact: a wheel would need a negative normal force",
            ForceFailure::Saturation => "saturation: a wheel needs more than the motor's torque",
        })
    }
}

type Mat46 = SMatrix<f64, 4, 6>;
type Vec6 = SVector<f64, 6>;

/// Constraints: 3 contact, 6 friction, 6 torque.
const ROWS: usize = 15;

fn cross(a: (f64, f64), b: (f64, f64)) -> f64 {
    a.0 * b.1 - a.1 * b.0
}

/// The equilibrium equations as A x = b with x = (N_f, N_m, N_r, T_f, T_m, T_r): E1
/// horizontal, E2 vertical, E3 moments about the rocker pivot, E4 moments about the
/// bogie pivot (front and middle wheels only).
fn equilibrium(c: &SideContacts) -> (Mat46, Vector4<f64>) {
    let mut a = Mat46::zeros();
    let r = c.wheel_radius_m;
    for i in 0..3 {
        let (s, co) = c.gamma_sin_cos[i];
        let n = (-s, co);
        let t = (co, s);
        let contact = (c.axles[i].0 - r * n.0, c.axles[i].1 - r * n.1);
        a[(0, i)] = n.0;
        a[(0, 3 + i)] = t.0;
        a[(1, i)] = n.1;
        a[(1, 3 + i)] = t.1;
        let arm = (contact.0 - c.rocker_pivot.0, contact.1 - c.rocker_pivot.1);
        a[(2, i)] = cross(arm, n);
        a[(2, 3 + i)] = cross(arm, t);
        if i < 2 {
            let arm = (contact.0 - c.bogie_pivot.0, contact.1 - c.bogie_pivot.1);
            a[(3, i)] = cross(arm, n);
            a[(3, 3 + i)] = cross(arm, t);
        }
    }
    (a, Vector4::new(0.0, c.load_n, -c.couple_nm, 0.0))
}

/// A constraint g·s ≥ h in the reduced coordinates.
#[derive(Debug, Clone, Copy)]
struct Half {
    g: Vector2<f64>,
    h: f64,
    kind: ForceFailure,
}

/// The reduced problem: x = x_p + Z s, objective |P x|², constraints.
struct Reduced {
    xp: Vec6,
    z: SMatrix<f64, 6, 2>,
    q: Matrix2<f64>,
    lin: Vector2<f64>,
    half: [Half; ROWS],
    tol: f64,
}

impl Reduced {
    fn build(c: &SideContacts, limits: &Limits) -> Option<Reduced> {
        let (a, b) = equilibrium(c);
        // Free pair: the first pair of tractions whose complement is well conditioned.
        let pairs = [(3usize, 4usize), (3, 5), (4, 5), (0, 3), (1, 4), (2, 5)];
        let mut best: Option<(f64, (usize, usize))> = None;
        for &(i, j) in &pairs {
            let rest: [usize; 4] = complement(i, j);
            let m = Matrix4::from_fn(|r, k| a[(r, rest[k])]);
            let det = det4(&m).abs();
            if best.is_none_or(|(d, _)| det > d) {
                best = Some((det, (i, j)));
            }
            if det > 1e-6 {
                break;
            }
        }
        let (det, (i, j)) = best?;
        if !(det > 1e-14) {
            return None;
        }
        let rest = complement(i, j);
        let inv = Matrix4::from_fn(|r, k| a[(r, rest[k])]).try_inverse()?;
        let mut xp = Vec6::zeros();
        let mut z = SMatrix::<f64, 6, 2>::zeros();
        let y = inv * b;
        for k in 0..4 {
            xp[rest[k]] = y[k];
        }
        for (col, free) in [i, j].into_iter().enumerate() {
            let y = inv * (-a.column(free));
            z[(free, col)] = 1.0;
            for k in 0..4 {
                z[(rest[k], col)] = y[k];
            }
        }
        // Torque per unit r: T_i + σ c_rr N_i.
        let roll = limits.direction * limits.rolling_resistance;
        // P x picks T_w + σ c_rr N_w per wheel.
        let pz = SMatrix::<f64, 3, 2>::from_fn(|w, k| z[(3 + w, k)] + roll * z[(w, k)]);
        let pxp = SVector::<f64, 3>::from_fn(|w, _| xp[3 + w] + roll * xp[w]);
        let q = pz.transpose() * pz;
        let lin = pz.transpose() * pxp;
        let t_max = limits.torque_max_nm / c.wheel_radius_m;
        let mut half = [Half { g: Vector2::zeros(), h: 0.0, kind: ForceFailure::Slip }; ROWS];
        // Every row is a·N_w + b·T_w ≥ h: in s, (a Z_w + b Z_{3+w})·s ≥ h − (a x_w + b x_{3+w}).
        let mut put = |k: usize, w: usize, (a, b): (f64, f64), h: f64, kind: ForceFailure| {
            let g = Vector2::new(a * z[(w, 0)] + b * z[(3 + w, 0)], a * z[(w, 1)] + b * z[(3 + w, 1)]);
            half[k] = Half { g, h: h - (a * xp[w] + b * xp[3 + w]), kind };
        };
        for w in 0..3 {
            put(5 * w, w, (1.0, 0.0), limits.n_min, ForceFailure::LossOfContact);
            put(5 * w + 1, w, (limits.mu, -1.0), 0.0, ForceFailure::Slip);
            put(5 * w + 2, w, (limits.mu, 1.0), 0.0, ForceFailure::Slip);
            // ±(T + σ c_rr N) ≥ −t_max.
            put(5 * w + 3, w, (roll, 1.0), -t_max, ForceFailure::Saturation);
            put(5 * w + 4, w, (-roll, -1.0), -t_max, ForceFailure::Saturation);
        }
        let tol = 1e-9 * c.load_n.abs().max(1.0);
        Some(Reduced { xp, z, q, lin, half, tol })
    }

    fn objective(&self, s: Vector2<f64>) -> f64 {
        s.dot(&(self.q * s)) + 2.0 * self.lin.dot(&s)
    }

    fn feasible(&self, s: Vector2<f64>, mask: u32) -> bool {
        self.half.iter().enumerate().all(|(k, c)| mask & (1 << k) == 0 || c.g.dot(&s) >= c.h - self.tol)
    }

    /// The best point on constraint line k's feasible interval (among rows in `mask`),
    /// or `None` if the interval is empty.
    fn on_line(&self, k: usize, mask: u32) -> Option<Vector2<f64>> {
        let c = self.half[k];
        let gn = c.g.norm_squared();
        if gn < 1e-24 {
            return None;
        }
        let s0 = c.g * (c.h / gn);
        let d = Vector2::new(-c.g.y, c.g.x) / gn.sqrt();
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for (j, o) in self.half.iter().enumerate() {
            if j == k || mask & (1 << j) == 0 {
                continue;
            }
            // o.g·(s0 + t d) ≥ o.h.
            let (gd, slack) = (o.g.dot(&d), o.g.dot(&s0) - o.h);
            if gd.abs() < 1e-15 {
                if slack < -self.tol {
                    return None;
                }
            } else if gd > 0.0 {
                lo = lo.max(-slack / gd);
            } else {
                hi = hi.min(-slack / gd);
            }
        }
        if lo > hi + 1e-12 {
            return None;
        }
        let dqd = d.dot(&(self.q * d));
        let t = if dqd > 1e-18 { -(d.dot(&(self.q * s0)) + d.dot(&self.lin)) / dqd } else { 0.0 };
        let t = t.clamp(lo.min(hi), hi.max(lo));
        let t = if t.is_finite() {
            t
        } else if lo.is_finite() {
            lo
        } else {
            hi.min(0.0).max(lo)
        };
        Some(s0 + d * t)
    }

    /// Whether the rows in `mask` admit any point.
    fn admits(&self, mask: u32) -> bool {
        (0..ROWS).any(|k| mask & (1 << k) != 0 && self.on_line(k, mask).is_some())
            || (self.half.iter().enumerate().all(|(k, c)| mask & (1 << k) == 0 || c.h <= self.tol))
    }
}

/// The determinant of a 4 × 4 matrix by 2 × 2 minors of its top and bottom row pairs
/// (Laplace along the first two rows): no pivoting, which the conditioning test here
/// does not need, and several times cheaper than an LU.
fn det4(m: &Matrix4<f64>) -> f64 {
    let lo = |a: usize, b: usize, i: usize, j: usize| m[(a, i)] * m[(b, j)] - m[(a, j)] * m[(b, i)];
    lo(0, 1, 0, 1) * lo(2, 3, 2, 3) - lo(0, 1, 0, 2) * lo(2, 3, 1, 3)
        + lo(0, 1, 0, 3) * lo(2, 3, 1, 2)
        + lo(0, 1, 1, 2) * lo(2, 3, 0, 3)
        - lo(0, 1, 1, 3) * lo(2, 3, 0, 2)
        + lo(0, 1, 2, 3) * lo(2, 3, 0, 1)
}

fn complement(i: usize, j: usize) -> [usize; 4] {
    let mut out = [0; 4];
    let mut n = 0;
    for k in 0..6 {
        if k != i && k != j {
            out[n] = k;
            n += 1;
        }
    }
    out
}

/// The power-optimal admissible forces, or why none exist.
pub fn solve(c: &SideContacts, limits: &Limits) -> Result<SideForces, ForceFailure> {
    let red = Reduced::build(c, limits).ok_or(ForceFailure::LossOfContact)?;
    let all = (1u32 << ROWS) - 1;
    let mut best: Option<(f64, Vector2<f64>)> = None;
    let mut consider = |s: Vector2<f64>| {
        if s.iter().all(|v| v.is_finite()) && red.feasible(s, all) {
            let f = red.objective(s);
            if best.is_none_or(|(bf, _)| f < bf) {
                best = Some((f, s));
            }
        }
    };
    let interior = red.q.try_inverse().map(|inv| -(inv * red.lin)).filter(|s| red.feasible(*s, all));
    match interior {
        Some(s) => consider(s),
        None => {
            for k in 0..ROWS {
                if let Some(s) = red.on_line(k, all) {
                    consider(s);
                }
            }
        }
    }
    let Some((_, s)) = best else { return Err(classify(&red)) };
    let x = red.xp + red.z * s;
    let r = c.wheel_radius_m;
    let roll = limits.direction * limits.rolling_resistance;
    let normal = [x[0], x[1], x[2]];
    let traction = [x[3], x[4], x[5]];
    let torque = [0, 1, 2].map(|w| r * (traction[w] + roll * normal[w]));
    let friction_used =
        (0..3).map(|w| if normal[w] > 1e-12 { traction[w].abs() / normal[w] } else { 0.0 }).fold(0.0, f64::max);
    Ok(SideForces {
        normal_n: normal,
        traction_n: traction,
        torque_nm: torque,
        sum_torque_sq: torque.iter().map(|t| t * t).sum(),
        friction_used,
    })
}

/// Which family of limits makes the problem infeasible: contact alone, then contact
/// with friction, else the torque limits.
fn classify(red: &Reduced) -> ForceFailure {
    let mut contact = 0u32;
    let mut friction = 0u32;
    for (k, c) in red.half.iter().enumerate() {
        match c.kind {
            ForceFailure::LossOfContact => contact |= 1 << k,
            ForceFailure::Slip => friction |= 1 << k,
            ForceFailure::Saturation => {}
        }
    }
    if !red.admits(contact) {
        ForceFailure::LossOfContact
    } else if !red.admits(contact | friction) {
        ForceFailure::Slip
    } else {
        ForceFailure::Saturation
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// LSR-1 side geometry on a uniform slope θ (rotated rigidly), W_s = 0.5.
    fn on_slope(theta_deg: f64) -> SideContacts {
        let th = theta_deg.to_radians();
        let (s, c) = th.sin_cos();
        let rot = |p: (f64, f64)| (p.0 * c - p.1 * s, p.0 * s + p.1 * c);
        SideContacts {
            axles: [rot((0.40, 0.10)), rot((0.0, 0.10)), rot((-0.40, 0.10))],
            gamma_sin_cos: [th.sin_cos(); 3],
            bogie_pivot: rot((0.20, 0.22)),
            rocker_pivot: rot((0.0, 0.32)),
            load_n: 0.0,
            couple_nm: 0.0,
            wheel_radius_m: 0.10,
        }
        .with_weight(0.5, rot((0.0, 0.25)))
    }

    impl SideContacts {
        fn with_weight(mut self, w: f64, cg: (f64, f64)) -> SideContacts {
            self.carry_weight_at(w, cg);
            self
        }
    }

    fn free(mu: f64) -> Limits {
        Limits::static_friction(mu)
    }

    #[test]
    fn the_minor_determinant_equals_nalgebras() {
        for seed in 0..20u32 {
            let m = Matrix4::from_fn(|r, c| ((seed * 31 + r as u32 * 7 + c as u32 * 13) % 17) as f64 / 3.0 - 2.5);
            let (a, b) = (det4(&m), m.determinant());
            assert!((a - b).abs() < 1e-9 * b.abs().max(1.0), "{seed}: {a} vs {b}");
        }
    }

    #[test]
    fn flat_ground_loads_are_equal_and_torque_free() {
        let f = solve(&on_slope(0.0), &free(0.5)).unwrap();
        for n in f.normal_n {
            assert!((n - 0.5 / 3.0).abs() < 1e-9, "{:?}", f.normal_n);
        }
        assert!(f.torque_nm.iter().all(|t| t.abs() < 1e-9));
    }

    #[test]
    fn holding_on_a_slope_needs_mu_equal_tan_theta() {
        for theta in [10.0f64, 20.0, 25.0, 30.0] {
            let mu_star = f64::to_radians(theta).tan();
            assert!(solve(&on_slope(theta), &free(mu_star + 1e-3)).is_ok(), "{theta}° at μ* + ε");
            assert_eq!(solve(&on_slope(theta), &free(mu_star - 1e-3)), Err(ForceFailure::Slip), "{theta}° at μ* − ε");
        }
    }

    #[test]
    fn unconstrained_optimum_gives_equal_torques_and_the_reference_loads() {
        // Reference §6 T4: at 20°, T_i = W_s sin θ / 3 and N = (0.0792, 0.2046, 0.1861).
        let f = solve(&on_slope(20.0), &free(10.0)).unwrap();
        let t = 0.5 * 20f64.to_radians().sin() / 3.0;
        for (got, want) in f.traction_n.iter().zip([t; 3]) {
            assert!((got - want).abs() < 1e-6, "{:?}", f.traction_n);
        }
        for (got, want) in f.normal_n.iter().zip([0.0792, 0.2046, 0.1861]) {
            assert!((got - want).abs() < 5e-4, "{:?}", f.normal_n);
        }
    }

    #[test]
    fn the_optimum_matches_a_brute_force_search() {
        // With friction binding (μ = 0.45 on 20°), compare with a grid over the two free
        // tractions, solving the remaining four unknowns from the equilibrium.
        let c = on_slope(20.0);
        let lim = free(0.45);
        let f = solve(&c, &lim).unwrap();
        let (a, b) = equilibrium(&c);
        let mut best = f64::INFINITY;
        let n = 400;
        for i in 0..=n {
            for j in 0..=n {
                let (tf, tm) = (-0.1 + 0.3 * i as f64 / n as f64, -0.1 + 0.3 * j as f64 / n as f64);
                // Unknowns N_f, N_m, N_r, T_r from A x = b with T_f, T_m fixed.
                let m = nalgebra::Matrix4::from_fn(|r, k| a[(r, [0, 1, 2, 5][k])]);
                let rhs = b - a.column(3) * tf - a.column(4) * tm;
                let Some(inv) = m.try_inverse() else { continue };
                let y = inv * rhs;
                let x = [y[0], y[1], y[2], tf, tm, y[3]];
                let ok = (0..3).all(|w| x[w] >= 0.0 && x[3 + w].abs() <= lim.mu * x[w] + 1e-12);
                if ok {
                    best = best.min((x[3] * x[3] + x[4] * x[4] + x[5] * x[5]) * 0.01);
                }
            }
        }
        assert!(best.is_finite());
        assert!(f.sum_torque_sq <= best + 1e-9, "solver {} vs grid {best}", f.sum_torque_sq);
        assert!(best - f.sum_torque_sq < 1e-4 * best.max(1e-9) + 1e-7, "solver {} vs grid {best}", f.sum_torque_sq);
    }

    #[test]
    fn a_weak_motor_saturates() {
        let lim = Limits { torque_max_nm: 1e-3, ..Limits::static_friction(1.0) };
        assert_eq!(solve(&on_slope(20.0), &lim), Err(ForceFailure::Saturation));
    }
}
