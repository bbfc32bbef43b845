//! Quasi-static forces on one side of the rocker-bogie (the paper's eqs. 8–16 in the
//! planar form of the reference, §4.1): per wheel a normal force N_i and a tractive
//! force T_i (wheel torque τ_i = r·T_i), in equilibrium with the side's share of the
//! weight, with the torques chosen to minimise Σ k τ² (copper losses, eq. 16) subject to
//! N_i ≥ N_min, |T_i| ≤ μ N_i and |τ_i| ≤ τ_max.
//!
//! Solved exactly: the four equilibrium equations leave a 2-D family x = x_p + Z s of
//! force vectors; the limits are half-planes in s and the objective a convex quadratic,
//! so the optimum is the unconstrained minimiser if feasible, else the best of the
//! minimisers along each constraint line and the polygon's vertices.

use nalgebra::{SMatrix, SVector, Vector2};

/// One side's contact geometry, in the side's (s forward, z up) plane, m and rad.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SideContacts {
    /// Axle centres: front, middle, rear.
    pub axles: [(f64, f64); 3],
    /// Contact angles γ_i (positive when the terrain rises ahead), rad.
    pub gamma: [f64; 3],
    /// Bogie pivot.
    pub bogie_pivot: (f64, f64),
    /// The centre of mass the side carries.
    pub cg: (f64, f64),
    /// The side's share of the weight, N.
    pub weight_n: f64,
    /// Wheel radius, m.
    pub wheel_radius_m: f64,
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
}

/// The solved forces, front, middle, rear.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SideForces {
    /// Normal forces, N.
    pub normal_n: [f64; 3],
    /// Tractive forces, N.
    pub traction_n: [f64; 3],
    /// Wheel torques, N·m.
    pub torque_nm: [f64; 3],
    /// Σ τ² (multiply by k for watts of copper loss), N²·m².
    pub sum_torque_sq: f64,
}

/// Why no admissible forces exist.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ForceFailure {
    /// Equilibrium needs more friction than μ gives.
    Slip,
    /// Equilibrium needs a negative normal force (a wheel lifts off).
    LossOfContact,
    /// Equilibrium needs more torque than the motors give.
    Saturation,
}

type Mat46 = SMatrix<f64, 4, 6>;
type Vec6 = SVector<f64, 6>;

fn cross(a: (f64, f64), b: (f64, f64)) -> f64 {
    a.0 * b.1 - a.1 * b.0
}

/// The equilibrium equations E1..E4 as A x = b with x = (N_f, N_m, N_r, T_f, T_m, T_r).
fn equilibrium(c: &SideContacts) -> (Mat46, SVector<f64, 4>) {
    let mut a = Mat46::zeros();
    let r = c.wheel_radius_m;
    for i in 0..3 {
        let (s, co) = c.gamma[i].sin_cos();
        let n = (-s, co);
        let t = (co, s);
        let contact = (c.axles[i].0 - r * n.0, c.axles[i].1 - r * n.1);
        // E1 longitudinal, E2 vertical.
        a[(0, i)] = n.0;
        a[(0, 3 + i)] = t.0;
        a[(1, i)] = n.1;
        a[(1, 3 + i)] = t.1;
        // E3 moments about the CG.
        let arm = (contact.0 - c.cg.0, contact.1 - c.cg.1);
        a[(2, i)] = cross(arm, n);
        a[(2, 3 + i)] = cross(arm, t);
        // E4 moments about the bogie pivot (front and middle wheels only).
        if i < 2 {
            let arm = (contact.0 - c.bogie_pivot.0, contact.1 - c.bogie_pivot.1);
            a[(3, i)] = cross(arm, n);
            a[(3, 3 + i)] = cross(arm, t);
        }
    }
    (a, SVector::<f64, 4>::new(0.0, c.weight_n, 0.0, 0.0))
}

/// The power-optimal admissible forces, or why none exist.
pub fn solve(c: &SideContacts, limits: &Limits) -> Result<SideForces, ForceFailure> {
    let (a, b) = equilibrium(c);
    // Particular solution and null space from the SVD of Aᵀ (6×4): A has rank 4.
    let svd = a.transpose().svd(true, true);
    let (Some(u), Some(vt)) = (svd.u, svd.v_t) else { return Err(ForceFailure::LossOfContact) };
    // Aᵀ = U Σ Vᵀ, so A = V Σ Uᵀ and the least-norm solution is x_p = U Σ⁻¹ Vᵀ b.
    let sigma = svd.singular_values;
    let mut xp = Vec6::zeros();
    let vtb = vt * b;
    for k in 0..4 {
        if sigma[k] > 1e-12 {
            xp += u.column(k) * (vtb[k] / sigma[k]);
        }
    }
    // The null space of A: the orthogonal complement of span(U's 4 columns) in ℝ⁶.
    let full = nalgebra::SMatrix::<f64, 6, 6>::identity() - u * u.transpose();
    let null_svd = full.svd(true, false);
    let nu = null_svd.u.ok_or(ForceFailure::LossOfContact)?;
    let mut order: Vec<usize> = (0..6).collect();
    order.sort_by(|&i, &j| null_svd.singular_values[j].total_cmp(&null_svd.singular_values[i]));
    let z1 = nu.column(order[0]).into_owned();
    let z2 = nu.column(order[1]).into_owned();
    let x_of = |s: Vector2<f64>| xp + z1 * s.x + z2 * s.y;
    // Objective: Σ T_i² = |P x|² with P selecting the T components.
    let t_of = |x: &Vec6| SVector::<f64, 3>::new(x[3], x[4], x[5]);
    let (pz1, pz2, pxp) = (t_of(&z1), t_of(&z2), t_of(&xp));
    let q = nalgebra::Matrix2::new(pz1.dot(&pz1), pz1.dot(&pz2), pz1.dot(&pz2), pz2.dot(&pz2));
    let lin = Vector2::new(pz1.dot(&pxp), pz2.dot(&pxp));
    let objective = |s: Vector2<f64>| (pxp + pz1 * s.x + pz2 * s.y).norm_squared();
    // Constraints g·x ≥ h, as half-planes in s: (gᵀZ) s ≥ h − gᵀ x_p.
    let t_max = limits.torque_max_nm / c.wheel_radius_m;
    let mut rows: Vec<(Vec6, f64, ForceFailure)> = Vec::new();
    for i in 0..3 {
        let mut g = Vec6::zeros();
        g[i] = 1.0;
        rows.push((g, limits.n_min, ForceFailure::LossOfContact));
        let mut g = Vec6::zeros();
        g[i] = limits.mu;
        g[3 + i] = -1.0;
        rows.push((g, 0.0, ForceFailure::Slip));
        let mut g = Vec6::zeros();
        g[i] = limits.mu;
        g[3 + i] = 1.0;
        rows.push((g, 0.0, ForceFailure::Slip));
        let mut g = Vec6::zeros();
        g[3 + i] = -1.0;
        rows.push((g, -t_max, ForceFailure::Saturation));
        let mut g = Vec6::zeros();
        g[3 + i] = 1.0;
        rows.push((g, -t_max, ForceFailure::Saturation));
    }
    let half: Vec<(Vector2<f64>, f64, ForceFailure)> =
        rows.iter().map(|(g, h, kind)| (Vector2::new(g.dot(&z1), g.dot(&z2)), h - g.dot(&xp), *kind)).collect();
    let scale = c.weight_n.abs().max(1.0);
    let feasible = |s: Vector2<f64>| half.iter().all(|(g, h, _)| g.dot(&s) >= h - 1e-9 * scale);
    let mut best: Option<(f64, Vector2<f64>)> = None;
    let mut consider = |s: Vector2<f64>| {
        if s.iter().all(|v| v.is_finite()) && feasible(s) {
            let f = objective(s);
            if best.is_none_or(|(bf, _)| f < bf - 1e-15) {
                best = Some((f, s));
            }
        }
    };
    // Unconstrained minimiser (Q may be singular: fall back to least squares).
    if let Some(inv) = q.try_inverse() {
        consider(-(inv * lin));
    }
    // Along each constraint line g·s = h: s = s0 + t d.
    for (g, h, _) in &half {
        let gn = g.norm_squared();
        if gn < 1e-24 {
            continue;
        }
        let s0 = g * (h / gn);
        let d = Vector2::new(-g.y, g.x);
        let dqd = d.dot(&(q * d));
        let t = if dqd > 1e-18 { -(d.dot(&(q * s0)) + d.dot(&lin)) / dqd } else { 0.0 };
        consider(s0 + d * t);
    }
    // Vertices.
    for i in 0..half.len() {
        for j in i + 1..half.len() {
            let m = nalgebra::Matrix2::new(half[i].0.x, half[i].0.y, half[j].0.x, half[j].0.y);
            if let Some(inv) = m.try_inverse() {
                consider(inv * Vector2::new(half[i].1, half[j].1));
            }
        }
    }
    match best {
        Some((_, s)) => {
            let x = x_of(s);
            let r = c.wheel_radius_m;
            let traction = [x[3], x[4], x[5]];
            let torque = traction.map(|t| t * r);
            Ok(SideForces {
                normal_n: [x[0], x[1], x[2]],
                traction_n: traction,
                torque_nm: torque,
                sum_torque_sq: torque.iter().map(|t| t * t).sum(),
            })
        }
        None => Err(classify(&half, &q, &lin)),
    }
}

/// Which kind of limit the least-loss equilibrium violates most.
fn classify(
    half: &[(Vector2<f64>, f64, ForceFailure)],
    q: &nalgebra::Matrix2<f64>,
    lin: &Vector2<f64>,
) -> ForceFailure {
    let s = q.try_inverse().map_or(Vector2::zeros(), |inv| -(inv * lin));
    half.iter()
        .map(|(g, h, kind)| (h - g.dot(&s), *kind))
        .filter(|(violation, _)| *violation > 0.0)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(ForceFailure::Slip, |(_, kind)| kind)
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
            gamma: [th; 3],
            bogie_pivot: rot((0.20, 0.22)),
            cg: rot((0.0, 0.25)),
            weight_n: 0.5,
            wheel_radius_m: 0.10,
        }
    }

    fn free(mu: f64) -> Limits {
        Limits { mu, torque_max_nm: 1e6, n_min: 0.0 }
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
        let lim = Limits { mu: 1.0, torque_max_nm: 1e-3, n_min: 0.0 };
        assert_eq!(solve(&on_slope(20.0), &lim), Err(ForceFailure::Saturation));
    }
}
